//! SDO expedited round-trip time on a real kernel's vcan0: the node's runtime on one SocketCAN socket,
//! a master on another, one upload of 0x1018:01 after the other. Runs inside the VM of
//! `scripts/bench-vcan` (`--features vcan-tests`).
//!
//! `vcan_rtt [COUNT]` (default 5000) prints min, median, 99th percentile and mean; then a 1 MiB DOMAIN
//! downloaded and uploaded with `sdo-tool`'s library (block and segmented), a scan of an empty bus,
//! and the CPU time an idle `x67-node` binary (the path in `X67_NODE`) takes on vcan0 over 10 s.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use sdo_tool::Tool;
use socketcan_node::node::{Node, NodeConfig};
use socketcan_node::runtime::{self, Station};
use socketcan_node::transport::{BusEvent, CanBus, SocketCanBus};
use socketcan_node::x67::{self, BusController};
use socketcan_node::CanFrame;

fn main() {
    let count: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(5000);
    let mut master = SocketCanBus::open("vcan0").expect("vcan0");
    let mut node_bus = SocketCanBus::open("vcan0").expect("vcan0");
    let stop = Arc::new(AtomicBool::new(false));
    let s = Arc::clone(&stop);
    let node = std::thread::spawn(move || {
        let mut dict = x67::dictionary(1).expect("fixture");
        // A DOMAIN to move a megabyte through (benchmark only; not in the X67 description).
        dict.insert(od::object::Object::var(
            0x5FF0,
            od::object::SubObject::new("Blob", od::DataType::Domain, od::object::AccessType::Rw),
        ));
        let now = Instant::now();
        let app = BusController::new(&dict, 1, x67::DEFAULT_X2X_CYCLE, now).expect("app");
        let mut nodes = [Station::in_memory(
            Node::new(NodeConfig::new(1), dict, app, now).expect("node"),
        )];
        runtime::run(&mut nodes, &mut node_bus, &s).expect("run")
    });
    std::thread::sleep(Duration::from_millis(200));
    let req = CanFrame::new(0x601, &[0x40, 0x18, 0x10, 1, 0, 0, 0, 0]).expect("frame");
    let mut rtts = Vec::with_capacity(count);
    for _ in 0..count + 100 {
        let t0 = Instant::now();
        master.send(&req).expect("send");
        loop {
            match master.recv(Duration::from_secs(1)).expect("recv") {
                Some(BusEvent::Frame { frame, .. }) if frame.cob_id() == Some(0x581) => {
                    assert_eq!(frame.data()[0], 0x43, "{frame}");
                    break;
                }
                Some(_) => {}
                None => panic!("no SDO answer within 1 s"),
            }
        }
        rtts.push(t0.elapsed());
    }
    // 1 MiB DOMAIN, block and segmented, both ways.
    let data: Vec<u8> = (0..1u32 << 20).map(|k| (k * 7 + 3) as u8).collect();
    for block in [true, false] {
        let mut tool = Tool::new(Box::new(SocketCanBus::open("vcan0").expect("vcan0")), None);
        tool.block = if block {
            sdo_tool::BlockMode::Always
        } else {
            sdo_tool::BlockMode::Never
        };
        let t0 = Instant::now();
        tool.download(
            1,
            "0x5FF0:00",
            &mut data.as_slice(),
            data.len() as u64,
            |_, _| {},
        )
        .expect("download");
        let down = t0.elapsed();
        let mut back = Vec::new();
        let t0 = Instant::now();
        tool.upload(1, "0x5FF0:00", &mut back, |_, _| {})
            .expect("upload");
        let up = t0.elapsed();
        assert_eq!(back, data);
        let kib = |d: Duration| 1024.0 / d.as_secs_f64();
        println!(
            "1 MiB DOMAIN on vcan0, {}: download {:.2} s ({:.0} KiB/s), upload {:.2} s ({:.0} KiB/s)",
            if block { "block" } else { "segmented" },
            down.as_secs_f64(),
            kib(down),
            up.as_secs_f64(),
            kib(up)
        );
    }
    stop.store(true, Ordering::Relaxed);
    node.join().expect("node thread");
    // A scan of the now empty bus: 127 requests and the listening time.
    let mut tool = Tool::new(Box::new(SocketCanBus::open("vcan0").expect("vcan0")), None);
    let t0 = Instant::now();
    let found = tool.scan(Duration::from_millis(300)).expect("scan");
    println!(
        "scan of an empty vcan0 (300 ms listening): {} nodes in {:.3} s",
        found.len(),
        t0.elapsed().as_secs_f64()
    );
    idle_cpu();
    // The first 100 warm up.
    let mut rtts = rtts.split_off(100);
    rtts.sort();
    let us = |d: Duration| d.as_secs_f64() * 1e6;
    let mean = rtts.iter().map(|d| us(*d)).sum::<f64>() / rtts.len() as f64;
    println!(
        "SDO expedited upload round trip on vcan0, {} requests: min {:.0} µs, median {:.0} µs, \
         p99 {:.0} µs, mean {:.0} µs",
        rtts.len(),
        us(rtts[0]),
        us(rtts[rtts.len() / 2]),
        us(rtts[rtts.len() * 99 / 100]),
        mean
    );
}

/// User and system CPU time of process `pid` so far, from /proc (clock ticks of 10 ms).
fn cpu_ticks(pid: u32) -> u64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).expect("/proc/PID/stat");
    // The fields after the command name (which is in parentheses and may hold spaces).
    let rest = &stat[stat.rfind(')').expect("stat format") + 2..];
    let fields: Vec<&str> = rest.split(' ').collect();
    // utime and stime are fields 14 and 15 of stat(5), 12 and 13 after the name.
    fields[11].parse::<u64>().expect("utime") + fields[12].parse::<u64>().expect("stime")
}

/// An idle `x67-node` on vcan0 (one module, 100 ms heartbeat, the default 1 ms X2X cycle): its CPU
/// time over 10 s after a second to start, as a share of one core.
fn idle_cpu() {
    let Some(bin) = std::env::var_os("X67_NODE") else {
        println!("idle x67-node: X67_NODE not set (tests/vcan/run bench sets it)");
        return;
    };
    let mut child = std::process::Command::new(bin)
        .args([
            "--bus",
            "socketcan:vcan0",
            "--node-id",
            "2",
            "--heartbeat-ms",
            "100",
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("x67-node starts");
    std::thread::sleep(Duration::from_secs(1));
    let (t0, c0) = (Instant::now(), cpu_ticks(child.id()));
    std::thread::sleep(Duration::from_secs(10));
    let (wall, cpu) = (t0.elapsed(), cpu_ticks(child.id()) - c0);
    let _ = child.kill();
    let _ = child.wait();
    println!(
        "idle x67-node on vcan0 (1 module, heartbeat 100 ms, X2X 1 ms): {:.1} % of one core over {:.1} s",
        cpu as f64 / 100.0 / wall.as_secs_f64() * 100.0,
        wall.as_secs_f64()
    );
}
