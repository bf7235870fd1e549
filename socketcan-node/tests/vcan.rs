//! The node on a real kernel's SocketCAN: vcan0 inside the VM that `tests/vcan/run` boots (built
//! with `--features vcan-tests`, run there with `--test-threads=1`; every test shares vcan0).
//!
//! - the SocketCAN transport itself (frames both ways, 29-bit and remote frames, no echo to the
//!   sender; error frames reported, not fatal);
//! - the node's runtime on vcan0: SDO, NMT, heartbeat;
//! - `candump` of the `x67-node` binary's boot-up message and heartbeat;
//! - python-canopen as the master over vcan0 (the same script as over socketcand), of the X67 node
//!   and of `canopen-node`: BaseNode402 on the example drive, the LSS master's Fastscan;
//! - 100,000 random frames on vcan0 leave the node answering and its heartbeat on time.

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use socketcan_node::node::NodeConfig;
use socketcan_node::test_util::{next_on, spawn_args_on_vcan, spawn_on_vcan, RunningNode};
use socketcan_node::transport::{BusEvent, CanBus, SocketCanBus};
use socketcan_node::CanFrame;

const IFACE: &str = "vcan0";
const NODE: &str = env!("CARGO_BIN_EXE_x67-node");
const CANOPEN_NODE: &str = env!("CARGO_BIN_EXE_canopen-node");

fn f(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

fn open() -> SocketCanBus {
    SocketCanBus::open(IFACE).expect("vcan0 is up (tests/vcan/run brings it up)")
}

/// A node of the library's own runtime on vcan0 with a heartbeat, stopped when dropped.
fn start_node(id: u8, heartbeat_ms: u16) -> RunningNode {
    let mut config = NodeConfig::new(id);
    config.heartbeat_ms = Some(heartbeat_ms);
    RunningNode::start(config, open())
}

#[test]
fn socketcan_transport_frames_both_ways_without_echo() {
    let mut a = open();
    let mut b = open();
    let frames = [
        f(0x605, &[0x40, 0x18, 0x10, 1, 0, 0, 0, 0]),
        f(0x080, &[]),
        CanFrame::new_extended(0x1ABC_DEF0, &[1, 2, 3]).unwrap(),
        CanFrame::new_remote_frame(0x705, false, 1).unwrap(),
    ];
    for fr in frames {
        a.send(&fr).unwrap();
        match b.recv(Duration::from_secs(1)).unwrap() {
            Some(BusEvent::Frame { frame, .. }) => assert_eq!(frame, fr),
            other => panic!("{fr}: got {other:?}"),
        }
    }
    assert_eq!(
        a.recv(Duration::from_millis(100)).unwrap(),
        None,
        "no echo to the sender"
    );
    assert_eq!(a.describe(), "socketcan:vcan0");
}

/// An error frame on the bus is reported as an event and the bus goes on.
#[test]
fn error_frames_are_reported_not_fatal() {
    use socketcan::Socket as _;
    let raw = socketcan::CanSocket::open(IFACE).unwrap();
    let mut bus = open();
    // CAN_ERR_PROT (0x08) with a form error (byte 2 = 0x02).
    let err = socketcan::CanErrorFrame::new_error(0x08, &[0, 0, 0x02, 0, 0, 0, 0, 0]).unwrap();
    raw.write_frame(&err).unwrap();
    match bus.recv(Duration::from_secs(1)).unwrap() {
        Some(BusEvent::Error(text)) => assert!(!text.is_empty()),
        other => panic!("expected an error event, got {other:?}"),
    }
    open().send(&f(0x123, &[1])).unwrap();
    match bus.recv(Duration::from_secs(1)).unwrap() {
        Some(BusEvent::Frame { frame, .. }) => assert_eq!(frame, f(0x123, &[1])),
        other => panic!("expected the frame after the error, got {other:?}"),
    }
}

#[test]
fn runtime_node_on_vcan_boots_answers_sdo_and_beats() {
    let mut master = open();
    let _node = start_node(9, 50);
    let (boot, _) = next_on(&mut master, 0x709, Duration::from_secs(2)).expect("boot-up");
    assert_eq!(boot.data(), &[0x00]);
    master
        .send(&f(0x609, &[0x40, 0x18, 0x10, 0, 0, 0, 0, 0]))
        .unwrap();
    let (r, _) = next_on(&mut master, 0x589, Duration::from_secs(1)).expect("SDO answer");
    assert_eq!(r.data(), &[0x4F, 0x18, 0x10, 0, 4, 0, 0, 0]);
    master.send(&f(0x000, &[0x01, 9])).unwrap();
    let mut beats = Vec::new();
    while beats.len() < 10 {
        let (hb, at) = next_on(&mut master, 0x709, Duration::from_secs(1)).expect("heartbeat");
        beats.push((hb.data()[0], at));
    }
    // Operational after the first beat or two; on a 50 ms grid. Arrival times carry the VM's
    // scheduling jitter (a late beat and an on-time one arrive closer together), so single gaps are
    // only bounded above, and the grid allows each beat half a period.
    assert_eq!(beats.last().unwrap().0, 0x05);
    for w in beats.windows(2) {
        let gap = w[1].1 - w[0].1;
        assert!(gap < Duration::from_millis(150), "heartbeat gap {gap:?}");
    }
    let t0 = beats[0].1;
    let times: Vec<f64> = beats
        .iter()
        .map(|(_, at)| at.duration_since(t0).as_secs_f64())
        .collect();
    if let Err(e) = on_grid(&times, 0.05) {
        panic!("{e}: {times:?}");
    }
}

/// `candump -L` lines `(SECONDS.MICROS) vcan0 ID#DATA` with their times.
fn candump_lines(text: &str) -> Vec<(f64, String)> {
    text.lines()
        .filter_map(|l| {
            let (ts, rest) = l.strip_prefix('(')?.split_once(") ")?;
            let frame = rest.strip_prefix("vcan0 ")?;
            Some((ts.parse().ok()?, frame.trim().to_string()))
        })
        .collect()
}

#[test]
fn candump_sees_the_binary_boot_up_and_heartbeat() {
    let mut dump = Command::new("candump")
        .args(["-L", IFACE])
        .stdout(Stdio::piped())
        .spawn()
        .expect("candump (can-utils) runs");
    let dump_out = dump.stdout.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel::<String>();
    let reader = std::thread::spawn(move || {
        for line in BufReader::new(dump_out).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    // candump is listening once it prints a frame of ours (its start is slow under emulation).
    let mut marker = open();
    let ready = Instant::now() + Duration::from_secs(20);
    'listening: while Instant::now() < ready {
        marker.send(&f(0x123, &[0xC0, 0xDE])).unwrap();
        let wait = Instant::now() + Duration::from_millis(100);
        while let Ok(line) = rx.recv_timeout(wait.saturating_duration_since(Instant::now())) {
            if line.ends_with(" 123#C0DE") {
                break 'listening;
            }
        }
    }
    assert!(
        Instant::now() < ready,
        "candump printed nothing within 20 s"
    );
    let mut node = Command::new(NODE)
        .args([
            "--bus",
            "socketcan:vcan0",
            "--node-id",
            "5",
            "--heartbeat-ms",
            "100",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // From the boot-up message on, 1.25 s of the bus (the binary's start is slow under emulation).
    let mut text = String::new();
    let mut until = Instant::now() + Duration::from_secs(20);
    let mut booted = false;
    while Instant::now() < until {
        let Ok(line) = rx.recv_timeout(Duration::from_millis(10)) else {
            continue;
        };
        if !booted && line.ends_with(" 705#00") {
            booted = true;
            until = Instant::now() + Duration::from_millis(1250);
        }
        text.push_str(&line);
        text.push('\n');
    }
    node.kill().unwrap();
    node.wait().unwrap();
    dump.kill().unwrap();
    dump.wait().unwrap();
    reader.join().unwrap();
    assert!(booted, "no boot-up message of node 5 within 20 s:\n{text}");
    let lines = candump_lines(&text);
    let node5: Vec<&(f64, String)> = lines
        .iter()
        .filter(|(_, l)| l.starts_with("705#"))
        .collect();
    assert_eq!(
        node5.first().map(|(_, l)| l.as_str()),
        Some("705#00"),
        "{text}"
    );
    let beats: Vec<f64> = node5
        .iter()
        .skip(1)
        .inspect(|(_, l)| assert_eq!(l, "705#7F", "{text}"))
        .map(|(t, _)| *t)
        .collect();
    assert!(
        beats.len() >= 11,
        "{} heartbeats in 1.25 s:\n{text}",
        beats.len()
    );
    // The first beat one period after the boot-up message (the node times its beats from the
    // boot-up's departure, however long its start took), then every 100 ms.
    let first = beats[0] - node5[0].0;
    assert!(
        (0.099..0.2).contains(&first),
        "first heartbeat {first:.4} s after the boot-up:\n{text}"
    );
    let mut last = beats[0];
    for t in &beats[1..] {
        let gap = t - last;
        assert!(
            (0.02..0.2).contains(&gap),
            "heartbeat gap {gap:.4} s:\n{text}"
        );
        last = *t;
    }
    // The beats keep a 100 ms grid without drift; under emulation one may leave late, but less than
    // half a period (beyond that the node starts its period again, CiA 301 gives no other bound).
    if let Err(e) = on_grid(&beats, 0.1) {
        panic!("{e}:\n{text}");
    }
}

/// Whether `times` (s) sit on a grid of `period`: anchored on the time that is earliest against it
/// (no beat leaves before its instant), each within half a period after its instant. A schedule that
/// drifts by more than half a period over the run, or a missing beat, fails.
fn on_grid(times: &[f64], period: f64) -> Result<(), String> {
    let anchor = times
        .iter()
        .enumerate()
        .map(|(k, t)| t - k as f64 * period)
        .fold(f64::INFINITY, f64::min);
    for (k, t) in times.iter().enumerate() {
        let late = t - anchor - k as f64 * period;
        if late >= period / 2.0 {
            return Err(format!(
                "beat {k} {:.1} ms after its instant on the {:.0} ms grid",
                late * 1e3,
                period * 1e3
            ));
        }
    }
    Ok(())
}

#[test]
fn python_canopen_master_over_vcan() {
    let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let mut node = spawn_on_vcan(Path::new(NODE), 1);
    let out = Command::new(&python)
        .arg(format!("{root}/tests/python/x67_master.py"))
        .arg("--eds")
        .arg(format!("{root}/fixtures/x67/X67SM2436.eds"))
        .args(["--node-id", "1", "--socketcan", IFACE])
        .output()
        .expect("the host's python3 with python-canopen");
    node.kill().unwrap();
    node.wait().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    println!("{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "python-canopen master failed");
    assert!(text.lines().any(|l| l == "PASS"), "{text}");
}

/// `tests/python/canopen_master.py` over vcan0; asserts it passed.
fn canopen_master(args: &[&str]) {
    let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let out = Command::new(&python)
        .arg(format!("{root}/tests/python/canopen_master.py"))
        .args(args)
        .args(["--socketcan", IFACE])
        .output()
        .expect("the host's python3 with python-canopen");
    let text = String::from_utf8_lossy(&out.stdout);
    println!("{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "python-canopen master failed");
    assert_eq!(text.lines().last(), Some("PASS"), "{text}");
}

/// BaseNode402 on `canopen-node`'s example drive over vcan0: state machine, homing, profile
/// position, profile velocity, cyclic synchronous position.
#[test]
fn base_node_402_over_vcan() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let eds = format!("{root}/examples/drive.eds");
    let mut node = spawn_args_on_vcan(Path::new(CANOPEN_NODE), &["--od", &format!("{eds}@5")], 5);
    canopen_master(&["drive402", "--eds", &eds, "--node-id", "5"]);
    node.kill().unwrap();
    node.wait().unwrap();
}

/// A RemoteNode's block download and upload of 3,000 bytes over vcan0.
#[test]
fn block_transfers_over_vcan() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let io = format!("{root}/examples/io-device.eds");
    let mut node = spawn_args_on_vcan(Path::new(CANOPEN_NODE), &["--od", &format!("{io}@8")], 8);
    canopen_master(&["block", "--eds", &io, "--node-id", "8"]);
    node.kill().unwrap();
    node.wait().unwrap();
}

/// The LSS master over vcan0: Fastscan finds the node without node-ID, gives it 21, stores it; the
/// node boots as 21.
#[test]
fn lss_fastscan_over_vcan() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let io = format!("{root}/examples/io-device.eds");
    let dir = tempfile::tempdir().unwrap();
    // Node 4 is configured (its boot-up says the process runs); the second waits for LSS.
    let mut node = spawn_args_on_vcan(
        Path::new(CANOPEN_NODE),
        &[
            "--storage",
            dir.path().to_str().unwrap(),
            "--od",
            &format!("{io}@4"),
            "--od",
            &format!("{io}@lss"),
        ],
        4,
    );
    canopen_master(&["lss", "--eds", &io, "--assign", "21"]);
    node.kill().unwrap();
    node.wait().unwrap();
}

#[test]
fn a_flood_of_random_frames_on_vcan_leaves_the_node_answering() {
    let mut master = open();
    let mut flooder = open();
    let _node = start_node(3, 50);
    // Building the node (its dictionary from the fixture) is slow in a debug build under emulation.
    next_on(&mut master, 0x703, Duration::from_secs(30)).expect("boot-up");
    let flood = std::thread::spawn(move || {
        let mut seed = 0x1234_5678_9ABC_DEF1u64;
        let mut sent = 0u32;
        while sent < 100_000 {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let id = (seed & 0x7FF) as u16;
            // NMT and this node's SDO and heartbeat are the master's to check.
            if matches!(id, 0x000 | 0x603 | 0x583 | 0x703) {
                continue;
            }
            let len = ((seed >> 16) % 9) as usize;
            let data = (seed >> 24).to_le_bytes();
            flooder.send(&f(id, &data[..len])).unwrap();
            sent += 1;
            if sent.is_multiple_of(200) {
                std::thread::sleep(Duration::from_millis(1));
            }
        }
        sent
    });
    let mut answers = 0;
    let mut requests = 0;
    let mut beats = Vec::new();
    let start = Instant::now();
    let mut next_sdo = start;
    // The longest the master's own loop (a receive of at most 2 ms each turn) went unscheduled: a
    // heartbeat is timed when the master reads it, so a gap the machine put into the master's run
    // is no gap of the node's.
    let mut stalled = Duration::ZERO;
    let mut turn = Instant::now();
    while !flood.is_finished() || start.elapsed() < Duration::from_secs(2) {
        stalled = stalled.max(turn.elapsed().saturating_sub(Duration::from_millis(2)));
        turn = Instant::now();
        if Instant::now() >= next_sdo {
            master
                .send(&f(0x603, &[0x40, 0x18, 0x10, 0, 0, 0, 0, 0]))
                .unwrap();
            requests += 1;
            // Every 20 ms; a master thread that fell behind (a slow machine) does not catch up in
            // a burst.
            next_sdo = (next_sdo + Duration::from_millis(20)).max(Instant::now());
        }
        if let Some(BusEvent::Frame { frame, .. }) = master.recv(Duration::from_millis(2)).unwrap()
        {
            match frame.cob_id() {
                Some(0x703) => beats.push(Instant::now()),
                Some(0x583) => {
                    assert_eq!(frame.data(), &[0x4F, 0x18, 0x10, 0, 4, 0, 0, 0]);
                    answers += 1;
                }
                _ => {}
            }
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "flood took over 2 min"
        );
    }
    assert_eq!(flood.join().unwrap(), 100_000);
    let secs = start.elapsed().as_secs_f64();
    // Requests are answered during the flood (a frame the kernel's queue drops under it is lost as
    // on a real controller's full FIFO; how many depends on how fast the emulated machine drains it,
    // so the bound is half), and every one after it.
    assert!(
        answers * 2 >= requests,
        "{answers} SDO answers to {requests} requests in {secs:.1} s"
    );
    for k in 0..5 {
        master
            .send(&f(0x603, &[0x40, 0x18, 0x10, 0, 0, 0, 0, 0]))
            .unwrap();
        let (answer, _) = next_on(&mut master, 0x583, Duration::from_secs(2))
            .unwrap_or_else(|| panic!("request {k} after the flood not answered within 2 s"));
        assert_eq!(answer.data(), &[0x4F, 0x18, 0x10, 0, 4, 0, 0, 0]);
    }
    for w in beats.windows(2) {
        let gap = w[1] - w[0];
        assert!(
            gap < Duration::from_millis(250) + stalled,
            "heartbeat gap {gap:?} (the master itself stalled at most {stalled:?})"
        );
    }
    assert!(
        beats.len() as f64 >= secs * 20.0 * 0.8,
        "{} beats in {secs:.1} s",
        beats.len()
    );
}

/// `scripts/accept-402-canopen` over vcan0 on the drives of `tests/drives` (one for each PDO layout
/// family): every file passes, and here, where remote frames travel, every TPDO that allows them and
/// is not sent on SYNC anyway answers one with its data.
#[test]
fn every_pdo_layout_passes_base_node_402_over_vcan() {
    let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let out = Command::new(&python)
        .arg(format!("{root}/scripts/accept-402-canopen"))
        .arg(format!("{root}/tests/drives"))
        .args(["--bin", CANOPEN_NODE, "--socketcan", IFACE])
        .output()
        .expect("the host's python3 with python-canopen");
    let table = String::from_utf8_lossy(&out.stdout);
    println!("{table}{}", String::from_utf8_lossy(&out.stderr));
    let rows: Vec<&str> = table.lines().filter(|l| l.starts_with("| pdo-")).collect();
    let want: Vec<String> = [
        "pdo-event-only.eds",
        "pdo-event-timer.eds",
        "pdo-none.eds",
        "pdo-rtr.eds",
        "pdo-sync-every.eds",
        "pdo-sync-fourth.eds",
        "pdo-sync-on-change.eds",
    ]
    .iter()
    .map(|f| format!("| {f} | pass |  |"))
    .collect();
    assert_eq!(rows, want);
    assert!(out.status.success());
}
