//! CAN transports behind one trait, [`CanBus`]: SocketCAN interfaces (`can0`, `vcan0`), the socketcand
//! protocol over TCP (as a client of a daemon elsewhere, or as a server that is itself the bus), and an
//! in-process bus for tests.
//!
//! A bus is named by a [`BusSpec`] in the notation every tool of this project takes:
//! `socketcan:IFACE`, `socketcand://HOST:PORT/CHANNEL`, `socketcand-listen:ADDR:PORT`.

pub mod capture;
mod inprocess;
mod socketcan_bus;
pub mod socketcand;
mod spec;

use std::time::{Duration, Instant, SystemTime};

pub use capture::Captured;
pub use inprocess::{Endpoint, InProcessBus};
pub use socketcan_bus::SocketCanBus;
pub use socketcand::{SocketcandClient, SocketcandServer};
pub use spec::{BusSpec, SpecError, BUS_VARIABLE, SOCKETCAND_DEFAULT_PORT};

use crate::frame::CanFrame;

/// A count of dropped frames that says when to log: at the 1st, 2nd, 4th, 8th, … drop, so that a
/// flood of drops is a handful of lines with the running total, not one line per frame.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub(crate) struct DropCount(u64);

impl DropCount {
    /// Counts one drop; the total when it is a power of two (time to log it).
    pub(crate) fn add(&mut self) -> Option<u64> {
        self.0 += 1;
        self.0.is_power_of_two().then_some(self.0)
    }
}

/// What a bus delivers.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum BusEvent {
    /// A frame from another participant, with the time it was received.
    Frame {
        /// The frame.
        frame: CanFrame,
        /// Reception time (wall clock, as socketcand and candump report it; a socketcand
        /// daemon's own clock for a frame it relayed).
        at: SystemTime,
        /// When this host's link took the frame, on its monotonic clock: the `now` a sans-IO
        /// node handles it at.
        received: Instant,
    },
    /// An error frame or a controller problem the interface reported. Not fatal: the bus goes on.
    Error(String),
}

/// Why a bus operation failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BusError {
    /// The interface or connection could not be opened.
    #[error("cannot open {what}: {source}")]
    Open {
        /// The bus, as given.
        what: String,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The peer spoke the protocol wrongly.
    #[error("{what}: protocol error: {detail}")]
    Protocol {
        /// The bus, as given.
        what: String,
        /// What was wrong.
        detail: String,
    },
    /// Sending or receiving failed.
    #[error("{what}: {source}")]
    Io {
        /// The bus, as given.
        what: String,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The bus is gone (every other end closed, or the connection ended).
    #[error("{0}: the bus was closed")]
    Closed(String),
}

/// A CAN bus as one participant sees it: frames it sends reach every other participant, frames the
/// others send reach it. Frames a participant sends are not delivered back to it.
pub trait CanBus: Send {
    /// Sends one frame.
    fn send(&mut self, frame: &CanFrame) -> Result<(), BusError>;

    /// Waits at most `timeout` for the next event; `Ok(None)` when none came in time.
    fn recv(&mut self, timeout: Duration) -> Result<Option<BusEvent>, BusError>;

    /// A short description for logs (`socketcan:vcan0`, `socketcand://127.0.0.1:29536/can0`, …).
    fn describe(&self) -> String;

    /// The address a listening bus (a socketcand server) was bound to, with the port the system
    /// chose for port 0; `None` for a bus that does not listen.
    fn listen_addr(&self) -> Option<std::net::SocketAddr> {
        None
    }
}

impl<B: CanBus + ?Sized> CanBus for Box<B> {
    fn send(&mut self, frame: &CanFrame) -> Result<(), BusError> {
        (**self).send(frame)
    }

    fn recv(&mut self, timeout: Duration) -> Result<Option<BusEvent>, BusError> {
        (**self).recv(timeout)
    }

    fn describe(&self) -> String {
        (**self).describe()
    }

    fn listen_addr(&self) -> Option<std::net::SocketAddr> {
        (**self).listen_addr()
    }
}

/// Opens the bus `spec` names: a SocketCAN interface, a connection to a socketcand daemon, or a
/// socketcand server listening for clients.
pub fn open(spec: &BusSpec) -> Result<Box<dyn CanBus>, BusError> {
    Ok(match spec {
        BusSpec::SocketCan { iface } => Box::new(SocketCanBus::open(iface)?),
        BusSpec::Socketcand {
            host,
            port,
            channel,
        } => Box::new(SocketcandClient::connect(host, *port, channel)?),
        BusSpec::SocketcandListen { addr } => Box::new(SocketcandServer::bind(*addr)?),
    })
}

/// The bus a tool uses when none is named: `socketcan:vcan0` where this machine has that interface,
/// else a socketcand server on 127.0.0.1:29536 (machines without SocketCAN).
pub fn open_default() -> Result<(BusSpec, Box<dyn CanBus>), BusError> {
    match SocketCanBus::open("vcan0") {
        Ok(bus) => Ok((
            BusSpec::SocketCan {
                iface: "vcan0".into(),
            },
            Box::new(bus),
        )),
        Err(e) => {
            tracing::debug!("no SocketCAN vcan0 ({e}); serving socketcand instead");
            let spec = BusSpec::SocketcandListen {
                addr: std::net::SocketAddr::from(([127, 0, 0, 1], SOCKETCAND_DEFAULT_PORT)),
            };
            let bus = open(&spec)?;
            Ok((spec, bus))
        }
    }
}

/// A frame on a queue-backed bus, with the wall-clock and monotonic instants it was sent at.
type Queued = (CanFrame, SystemTime, Instant);

/// The next frame a queue-backed bus holds, waiting at most `timeout`; a queue whose senders are all
/// gone is a closed bus.
fn recv_queued(
    rx: &std::sync::mpsc::Receiver<Queued>,
    timeout: Duration,
    describe: impl FnOnce() -> String,
) -> Result<Option<BusEvent>, BusError> {
    use std::sync::mpsc::RecvTimeoutError;
    match rx.recv_timeout(timeout) {
        Ok((frame, at, received)) => Ok(Some(BusEvent::Frame {
            frame,
            at,
            received,
        })),
        Err(RecvTimeoutError::Timeout) => Ok(None),
        Err(RecvTimeoutError::Disconnected) => Err(BusError::Closed(describe())),
    }
}

#[cfg(test)]
mod tests {
    use super::DropCount;

    /// Logged at drops 1, 2, 4, 8, 16, …, 1024: 11 lines for 1,500 drops.
    #[test]
    fn drops_are_logged_at_powers_of_two() {
        let mut d = DropCount::default();
        let logged: Vec<u64> = (0..1500).filter_map(|_| d.add()).collect();
        assert_eq!(logged, [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024]);
    }
}
