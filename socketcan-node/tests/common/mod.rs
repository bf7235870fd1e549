//! What the node and `sdo-tool` tests share.
#![allow(dead_code)]

use std::process::{Command, Output};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Instant;

use socketcan_node::node::storage::MemoryStorage;
use socketcan_node::node::{Node, NodeConfig};
use socketcan_node::runtime::{self, RunStats};
use socketcan_node::transport::CanBus;
use socketcan_node::x67::{self, BusController};

/// `sdo-tool GLOBAL… ARGS…` as a user runs it; GLOBAL are the bus options (`--bus …`, `--ethercat …`).
pub fn sdo_tool(global: &[&str], argv: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(global)
        .args(argv)
        .output()
        .expect("run sdo-tool")
}

/// `sdo-tool GLOBAL… ARGS…`, expected to succeed: its standard output.
pub fn sdo_tool_ok(global: &[&str], argv: &[&str]) -> String {
    let o = sdo_tool(global, argv);
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "sdo-tool {argv:?}: {:?}\n{stdout}{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
    stdout
}

/// The X67 node (bus controller and one X67SM2436) of the library's runtime on `bus`, in a thread of
/// its own; stopped when dropped.
pub struct RunningNode {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<RunStats>>,
}

impl RunningNode {
    pub fn start(config: NodeConfig, mut bus: impl CanBus + 'static) -> RunningNode {
        let stop = Arc::new(AtomicBool::new(false));
        let s = Arc::clone(&stop);
        let thread = std::thread::spawn(move || {
            let dict = x67::dictionary(1).unwrap();
            let app = BusController::new(&dict, 1, x67::DEFAULT_X2X_CYCLE, Instant::now()).unwrap();
            let mut nodes =
                [Node::new(config, dict, app, Box::new(MemoryStorage::default())).unwrap()];
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
