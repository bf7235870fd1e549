//! What the tests of this crate and of `sdo-tool` share (feature `test-util`): the X67 node of the
//! library's runtime in a thread of its own, waiting for one CAN-ID on a bus, and the `x67-node`
//! binary on vcan0.

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::node::{Node, NodeConfig};
use crate::runtime::{self, RunStats, Station};
use crate::transport::{BusEvent, CanBus, SocketCanBus};
use crate::x67::{self, BusController};
use crate::CanFrame;

/// The X67 node (bus controller and one X67SM2436) of the library's runtime on a bus, in a thread of
/// its own; stopped when dropped.
pub struct RunningNode {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<RunStats>>,
}

impl RunningNode {
    /// Starts the node with `config` on `bus`.
    pub fn start(config: NodeConfig, mut bus: impl CanBus + 'static) -> RunningNode {
        let stop = Arc::new(AtomicBool::new(false));
        let s = Arc::clone(&stop);
        let thread = std::thread::spawn(move || {
            let dict = x67::dictionary(1).unwrap();
            let now = Instant::now();
            let app = BusController::new(&dict, 1, x67::DEFAULT_X2X_CYCLE, now).unwrap();
            let mut nodes = [Station::in_memory(
                Node::new(config, dict, app, now).unwrap(),
            )];
            runtime::run(&mut nodes, &mut bus, &s).unwrap()
        });
        RunningNode {
            stop,
            thread: Some(thread),
        }
    }

    /// Stops the node: what its runtime counted (a panic if the runtime failed).
    pub fn stop(mut self) -> RunStats {
        self.stop.store(true, Ordering::Relaxed);
        let thread = self.thread.take().expect("started");
        thread
            .join()
            .expect("the node's runtime ran without an error")
    }
}

impl Drop for RunningNode {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The first frame with CAN-ID `cob` on `bus` within `within`, with the time it came.
pub fn next_on(bus: &mut dyn CanBus, cob: u16, within: Duration) -> Option<(CanFrame, Instant)> {
    let end = Instant::now() + within;
    while Instant::now() < end {
        if let Some(BusEvent::Frame { frame, .. }) = bus.recv(Duration::from_millis(20)).unwrap() {
            if frame.cob_id() == Some(cob) {
                return Some((frame, Instant::now()));
            }
        }
    }
    None
}

/// The `x67-node` binary `bin` on vcan0 as node `id`, returned once its boot-up message is on the bus
/// (the VM of the vcan tests emulates its CPU, so the start takes a variable time).
pub fn spawn_on_vcan(bin: &Path, id: u8) -> Child {
    spawn_args_on_vcan(bin, &["--node-id", &id.to_string()], id)
}

/// Starts `bin` on vcan0 with `args` and waits for the boot-up message of node `id` (30 s at most).
pub fn spawn_args_on_vcan(bin: &Path, args: &[&str], id: u8) -> Child {
    let mut bus = SocketCanBus::open("vcan0").expect("vcan0 is up (tests/vcan/run brings it up)");
    let mut node = Command::new(bin)
        .args(["--bus", "socketcan:vcan0"])
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let boot = next_on(&mut bus, 0x700 + u16::from(id), Duration::from_secs(30));
    if boot.as_ref().map(|(frame, _)| frame.data()) != Some(&[0u8][..]) {
        node.kill().unwrap();
        panic!(
            "{} {id} sent no boot-up message within 30 s: {boot:?}",
            bin.display()
        );
    }
    node
}
