//! 127 generic CiA 402 drive nodes (examples/drive.eds) in one process on one bus, in cyclic
//! synchronous position: every 1 ms the master sends each node its target in RPDO 4 (on SYNC) and
//! then a SYNC, and every node answers with TPDO 4 (position and velocity, on SYNC). The CPU share
//! the nodes' thread needs, from its own scheduler statistics.
//!
//! `cargo bench -p socketcan-node --bench drives127 [-- SECONDS]`

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use ds402::drive::DriveConfig;
use ds402::generic::{self, GenericApp};
use socketcan_node::node::{Node, NodeConfig};
use socketcan_node::runtime::{self, Station};
use socketcan_node::transport::{BusEvent, CanBus, InProcessBus};
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
    let secs: u64 = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(5);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/drive.eds");
    let (_, mut devices) = od::load::load(&path).expect("examples/drive.eds");
    let mut dict = devices.remove(0).dictionary;
    generic::add_sim_records(&mut dict, &DriveConfig::default().sim);
    // Cyclic synchronous position from power-on.
    if let Some(e) = dict.object_mut(0x6060).and_then(|o| o.subs.get_mut(&0)) {
        e.default = Some(od::object::DefaultValue::plain(od::Value::Int(8)));
    }
    let bus = InProcessBus::new();
    let mut master = bus.endpoint();
    let mut nodes_end = bus.endpoint();
    let stop = Arc::new(AtomicBool::new(false));
    let stop_nodes = Arc::clone(&stop);
    let nodes_thread = std::thread::spawn(move || {
        let now = Instant::now();
        let mut nodes: Vec<Station<GenericApp>> = (1..=NODES)
            .map(|id| {
                let app = GenericApp::new(&dict, &DriveConfig::default(), now);
                let node = Node::new(NodeConfig::new(id), dict.clone(), app, now).expect("node");
                Station::in_memory(node)
            })
            .collect();
        let cpu0 = thread_cpu_ns();
        let t0 = Instant::now();
        let stats = runtime::run(&mut nodes, &mut nodes_end, &stop_nodes).expect("run");
        (thread_cpu_ns() - cpu0, t0.elapsed(), stats)
    });
    std::thread::sleep(Duration::from_millis(300));
    let send = |m: &mut dyn CanBus, id: u16, data: &[u8]| {
        m.send(&CanFrame::new(id, data).expect("frame"))
            .expect("send");
    };
    send(&mut master, 0, &[0x01, 0]);
    // Shutdown, switch on, enable operation: RPDO 1 (control word, mode 8).
    for cw in [0x06u8, 0x07, 0x0F] {
        for id in 1..=u16::from(NODES) {
            send(&mut master, 0x200 + id, &[cw, 0, 8]);
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    while master.try_recv().is_some() {}
    let start = Instant::now();
    let mut next = start;
    let mut syncs = 0u64;
    let mut tpdos = 0u64;
    let mut last_position = 0i32;
    while start.elapsed() < Duration::from_secs(secs) {
        next += Duration::from_millis(1);
        syncs += 1;
        let target = (10 * syncs as i32).to_le_bytes();
        for id in 1..=u16::from(NODES) {
            send(
                &mut master,
                0x500 + id,
                &[target[0], target[1], target[2], target[3], 0, 0, 0, 0],
            );
        }
        send(&mut master, 0x80, &[]);
        loop {
            let left = next.saturating_duration_since(Instant::now());
            if left.is_zero() {
                break;
            }
            if let Ok(Some(BusEvent::Frame { frame, .. })) = master.recv(left) {
                if frame.cob_id() == Some(0x480 + u16::from(NODES)) {
                    let d = frame.data();
                    last_position = i32::from_le_bytes([d[0], d[1], d[2], d[3]]);
                }
                if frame.cob_id().is_some_and(|c| (0x481..=0x4FF).contains(&c)) {
                    tpdos += 1;
                }
            }
        }
    }
    stop.store(true, Ordering::Relaxed);
    let (cpu_ns, wall, stats) = nodes_thread.join().expect("nodes thread");
    while let Some(f) = master.try_recv() {
        if f.cob_id().is_some_and(|c| (0x481..=0x4FF).contains(&c)) {
            tpdos += 1;
        }
    }
    let share = cpu_ns as f64 / wall.as_nanos() as f64;
    println!(
        "127 CiA 402 drives in csp, SYNC 1 ms, {syncs} SYNCs in {:.1} s: {tpdos} position TPDOs \
         received ({:.1} per SYNC), node 127 at {last_position} counts (target {}), nodes thread \
         CPU {:.1} % of one core ({} frames in, {} out)",
        wall.as_secs_f64(),
        tpdos as f64 / syncs as f64,
        10 * syncs,
        share * 100.0,
        stats.received,
        stats.sent
    );
}
