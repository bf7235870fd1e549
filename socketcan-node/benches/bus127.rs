//! 127 X67 nodes (one module each) in one process on one bus, SYNC every 1 ms, every TPDO synchronous
//! (transmission type 1): the CPU share the nodes' thread needs, from its own scheduler statistics,
//! and its CPU time per frame in and out. With `--capture FILE` the nodes' bus writes every frame to
//! FILE as `canopen-node --capture` does (`transport::Captured`): the cost of capturing, per frame.
//!
//! `cargo bench -p socketcan-node --bench bus127 [-- SECONDS] [--capture FILE]`

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use socketcan_node::node::{Node, NodeConfig};
use socketcan_node::runtime::{self, Station};
use socketcan_node::transport::{BusEvent, CanBus, InProcessBus};
use socketcan_node::x67::{self, BusController};
use socketcan_node::CanFrame;

const NODES: u8 = 127;

/// CPU time of the calling thread (ns), from /proc/thread-self/schedstat.
fn thread_cpu_ns() -> u64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let secs: u64 = args.iter().find_map(|a| a.parse().ok()).unwrap_or(5);
    let capture = args
        .iter()
        .position(|a| a == "--capture")
        .and_then(|k| args.get(k + 1))
        .map(|path| {
            link_capture::Capture::create(path.as_ref(), "bus127").expect("the capture file")
        });
    let bus = InProcessBus::new();
    let mut master = bus.endpoint();
    let nodes_end = bus.endpoint();
    let mut nodes_end: Box<dyn CanBus> = match &capture {
        Some(c) => Box::new(socketcan_node::transport::Captured::new(
            nodes_end,
            c,
            "inprocess",
        )),
        None => Box::new(nodes_end),
    };
    let stop = Arc::new(AtomicBool::new(false));
    let stop_nodes = Arc::clone(&stop);
    let nodes_thread = std::thread::spawn(move || {
        let now = Instant::now();
        let mut nodes: Vec<Station<BusController>> = (1..=NODES)
            .map(|id| {
                let mut dict = x67::dictionary(1).expect("fixture");
                for comm in [0x1800, 0x1801] {
                    dict.store(comm, 2, &[1]).expect("transmission type");
                }
                // The in-dictionary value becomes the node's default.
                for comm in [0x1800u16, 0x1801] {
                    if let Some(e) = dict.object_mut(comm).and_then(|o| o.subs.get_mut(&2)) {
                        e.default = Some(od::object::DefaultValue::plain(od::Value::Uint(1)));
                    }
                }
                let app = BusController::new(&dict, 1, x67::DEFAULT_X2X_CYCLE, now).expect("app");
                Station::in_memory(Node::new(NodeConfig::new(id), dict, app, now).expect("node"))
            })
            .collect();
        let cpu0 = thread_cpu_ns();
        let t0 = Instant::now();
        let stats = runtime::run(&mut nodes, nodes_end.as_mut(), &stop_nodes).expect("run");
        (thread_cpu_ns() - cpu0, t0.elapsed(), stats)
    });
    // Let them boot, then start all and send SYNC every 1 ms.
    std::thread::sleep(Duration::from_millis(200));
    master
        .send(&CanFrame::new(0, &[0x01, 0]).expect("nmt"))
        .expect("send");
    let sync = CanFrame::new(0x80, &[]).expect("sync");
    let start = Instant::now();
    let mut next = start;
    let mut syncs = 0u64;
    let mut tpdos = 0u64;
    while start.elapsed() < Duration::from_secs(secs) {
        next += Duration::from_millis(1);
        master.send(&sync).expect("send");
        syncs += 1;
        loop {
            let left = next.saturating_duration_since(Instant::now());
            if left.is_zero() {
                break;
            }
            if let Ok(Some(BusEvent::Frame { frame, .. })) = master.recv(left) {
                if let Some(c) = frame.cob_id() {
                    if (0x181..=0x2FF).contains(&c) {
                        tpdos += 1;
                    }
                }
            }
        }
    }
    stop.store(true, Ordering::Relaxed);
    let (cpu_ns, wall, stats) = nodes_thread.join().expect("nodes thread");
    while let Some(f) = master.try_recv() {
        if f.cob_id().is_some_and(|c| (0x181..=0x2FF).contains(&c)) {
            tpdos += 1;
        }
    }
    let share = cpu_ns as f64 / wall.as_nanos() as f64;
    println!(
        "127 nodes, SYNC 1 ms, {syncs} SYNCs in {:.1} s: {tpdos} TPDOs received ({:.1} per SYNC), \
         nodes thread CPU {:.1} % of one core ({} frames in, {} out, {:.2} µs a frame{})",
        wall.as_secs_f64(),
        tpdos as f64 / syncs as f64,
        share * 100.0,
        stats.received,
        stats.sent,
        cpu_ns as f64 / 1e3 / (stats.received + stats.sent).max(1) as f64,
        if capture.is_some() { ", captured" } else { "" }
    );
}
