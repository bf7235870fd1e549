//! The emulator on an interface: a chain of units ([`UnitChain`]: virtual SMD units, or any ESI's
//! devices) answering every EtherCAT frame that arrives, as a real chain would, and running their
//! process-data cycle when the chain asks ([`UnitChain::poll_timeout`]). This is the edge: the socket, the clock and the carrier live here.
//!
//! A frame is processed by every unit in turn and sent back on the same interface with the source
//! address's locally-administered bit set (as the first ESC's port 0 does), so the master can tell its
//! frames from the answers. A frame that does not parse (not EtherCAT, truncated, bad lengths) is
//! dropped and counted; the chain is untouched. The link's carrier is watched: when it goes down the
//! units in Op drop to Safe-Op (SMD-R1-036). The frames waiting on the socket are taken in one
//! system call and their answers sent back in one (recvmmsg(2), sendmmsg(2): up to 32 frames), each
//! answered at its own time as before.
//!
//! [`run`] is `smd-ethercat`'s; [`serve`] runs any chain on an open socket.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::smd::binding::Device;

use crate::raw::{Batch, RawError, RawSocket};
use crate::smd::{SmdChain, SmdSlaveError};
use crate::unit::{Model, UnitChain};

/// Frames taken from the socket at once.
const BATCH: usize = 32;

/// What to run.
#[derive(Debug, Clone)]
pub struct Options {
    /// The interface.
    pub interface: String,
    /// Which unit.
    pub device: Device,
    /// How many units in the chain.
    pub units: usize,
    /// The process-data cycle of the units.
    pub cycle: Duration,
    /// After answering a frame, how long to keep polling the socket without sleeping before waiting
    /// in the kernel again: shortens the answer time to a master that sends its next frame at once,
    /// at the cost of CPU time. Zero sleeps at once.
    pub busy_poll: Duration,
    /// Where every frame received and sent is written too (a pcapng capture), if anywhere.
    pub capture: Option<link_capture::Capture>,
}

/// Why the emulator stopped.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RuntimeError {
    /// The socket.
    #[error(transparent)]
    Raw(#[from] RawError),
    /// The units.
    #[error(transparent)]
    Slave(#[from] SmdSlaveError),
    /// The socket failed while running.
    #[error("interface {iface}: {source}")]
    Io {
        /// The interface.
        iface: String,
        /// The error.
        source: std::io::Error,
    },
}

/// What the emulator did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Frames processed and sent back.
    pub answered: u64,
    /// Frames dropped (not EtherCAT, malformed).
    pub dropped: u64,
}

/// Reads the carrier of `iface` from sysfs (`None` when it cannot be read).
fn carrier(iface: &str) -> Option<bool> {
    let s = std::fs::read_to_string(format!("/sys/class/net/{iface}/carrier")).ok()?;
    Some(s.trim() == "1")
}

/// Runs until `stop` is set. `ready` is called once the socket is open.
pub fn run(
    options: &Options,
    stop: &Arc<AtomicBool>,
    ready: impl FnOnce(),
) -> Result<Stats, RuntimeError> {
    let mut socket = RawSocket::open(&options.interface)?;
    if let Some(capture) = &options.capture {
        socket.capture_to(capture);
    }
    let chain = SmdChain::new(options.device, options.units, options.cycle, Instant::now())?;
    ready();
    tracing::info!(
        interface = options.interface,
        units = options.units,
        device = options.device.order_code(),
        "virtual SMD units on line"
    );
    serve(
        &socket,
        &options.interface,
        options.busy_poll,
        chain,
        stop,
        &mut |_, _, _| {},
    )
}

/// What the edge does with a file a unit took whole by FoE: the unit (0 = first), the file's name,
/// its contents.
pub type KeepFile<'a> = dyn FnMut(usize, &[u8], &[u8]) + 'a;

/// Answers the frames arriving on `socket` (on `interface`) with `chain` until `stop` is set, running
/// the chain's timers in between; `busy_poll` as [`Options::busy_poll`]. Each file a unit takes
/// whole by FoE goes to `keep` (the unit, 0 = first; the file's name; its contents) right after the
/// frame that completed it ([`UnitChain::poll_written`]).
pub fn serve<M: Model>(
    socket: &RawSocket,
    interface: &str,
    busy_poll: Duration,
    mut chain: UnitChain<M>,
    stop: &Arc<AtomicBool>,
    keep: &mut KeepFile<'_>,
) -> Result<Stats, RuntimeError> {
    let io = |source| RuntimeError::Io {
        iface: interface.to_string(),
        source,
    };
    let mut stats = Stats::default();
    // The frames waiting on the socket are taken together and their answers sent together: two
    // system calls for a burst instead of two per frame.
    let mut batch = Batch::new(BATCH, 9_216);
    let mut next_carrier = Instant::now();
    let mut link = carrier(interface).unwrap_or(true);
    while !stop.load(Ordering::Relaxed) {
        let now = Instant::now();
        let wait = chain
            .poll_timeout()
            .map_or(Duration::from_millis(50), |t| {
                t.saturating_duration_since(now)
            })
            .min(Duration::from_millis(50));
        if socket.wait(wait).map_err(io)? {
            let mut spin_until = Instant::now() + busy_poll;
            loop {
                if socket.recv_batch(&mut batch).map_err(io)? == 0 {
                    if Instant::now() < spin_until && !stop.load(Ordering::Relaxed) {
                        std::hint::spin_loop();
                        continue;
                    }
                    break;
                }
                for k in 0..batch.len() {
                    let at = Instant::now();
                    spin_until = at + busy_poll;
                    let frame = batch.frame_mut(k);
                    match chain.handle_frame(at, frame) {
                        Ok(()) => {
                            frame[6] |= 0x02;
                            stats.answered += 1;
                        }
                        Err(e) => {
                            tracing::debug!(error = %e, "frame dropped");
                            stats.dropped += 1;
                            batch.skip(k);
                        }
                    }
                }
                if let Err(e) = socket.send_batch(&batch) {
                    tracing::warn!(error = %e, "a frame could not be sent back");
                }
                while let Some((unit, name, data)) = chain.poll_written() {
                    keep(unit, &name, &data);
                }
            }
        }
        let now = Instant::now();
        if chain.poll_timeout().is_some_and(|t| t <= now) {
            chain.handle_timeout(now);
        }
        if now >= next_carrier {
            next_carrier = now + Duration::from_millis(100);
            if let Some(up) = carrier(interface) {
                if link && !up {
                    tracing::warn!(interface, "link lost");
                    chain.link_lost(now);
                }
                link = up;
            }
        }
    }
    tracing::info!(
        answered = stats.answered,
        dropped = stats.dropped,
        "stopped"
    );
    Ok(stats)
}
