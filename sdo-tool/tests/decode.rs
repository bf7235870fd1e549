//! `sdo-tool decode` as a user runs it on a candump log: a line far longer than any frame is
//! skipped in bounded memory, and the SDO transfers a log ends in the middle of are named.

use std::io::Write;
use std::process::{Command, Stdio};

/// The peak resident set of process `pid` (`VmHWM` of /proc/PID/status), in KiB.
fn peak_rss_kib(pid: u32) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).expect("status");
    let line = status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .expect("VmHWM");
    line.split_whitespace().nth(1).unwrap().parse().unwrap()
}

/// A log of node 1 with a 64 MiB line (a frame whose data never ends) in the middle, and a line
/// that is no frame after it, through a pipe: the frames before and after them are named, the long
/// line is one warning naming its number, the other line is counted by its number, and
/// the tool never holds it. It keeps at most 4096 bytes of a line and its 8 KiB read buffer, so the
/// whole process, code and libraries included, stays far under a quarter of the line, 16 MiB; the
/// peak is read while the tool still waits for the rest of its input, after it has read all of the
/// long line but what the pipe still holds (64 KiB).
#[test]
fn a_huge_line_is_skipped_in_bounded_memory() {
    const LINE: usize = 64 << 20;
    let mut child = Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(["decode", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run sdo-tool");
    let mut input = child.stdin.take().unwrap();
    input
        .write_all(
            b"(10.000000) can0 701#05\n\
              (10.100000) can0 601#2B17100064000000\n\
              (10.200000) can0 123#",
        )
        .unwrap();
    let chunk = vec![b'A'; 1 << 20];
    for _ in 0..LINE / chunk.len() {
        input.write_all(&chunk).unwrap();
    }
    input
        .write_all(
            b"\nnot a frame\n\
              (10.300000) can0 581#6017100000000000\n\
              (10.400000) can0 601#4008100000000000\n\
              (10.401000) can0 581#4108100018000000\n\
              (10.402000) can0 601#6000000000000000\n\
              (10.403000) can0 581#0058363742433433\n",
        )
        .unwrap();
    input.flush().unwrap();
    let peak = peak_rss_kib(child.id());
    drop(input);
    let out = child.wait_with_output().unwrap();
    assert!(
        peak < (LINE / 4 / 1024) as u64,
        "peak resident set {peak} KiB for a line of {} KiB",
        LINE / 1024
    );
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "  0.000000  node 1: heartbeat, operational\n\
         \x20 0.100000  node 1: SDO write 0x1017:00 = 64 00\n\
         \x20 0.300000  node 1: SDO written 0x1017:00\n\
         \x20 0.403000  node 1: SDO segmented upload of 0x1008:00 left open: 7 of 24 bytes so far, \
         its last frame at 0.403000\n"
    );
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "sdo-tool: standard input: line 3 is longer than 4096 bytes, no candump -L frame: skipped\n\
         sdo-tool: standard input: 1 line(s) are no candump -L frames (the first: line 4): skipped\n"
    );
}

/// A log that ends with five transfers going on, one of each kind, after a stray frame and an
/// expedited read that ended: each is named at the end, by node, at the log's last frame (0.051 s),
/// with its entry, kind, bytes so far (of the size its initiate announced) and last frame.
/// - node 2, a segmented download of 0x2000:01 (10 bytes announced): one segment of 7, its
///   answer at 0.003; the server's upload segment at 0.004 is none of the transfer's frames;
/// - node 3, the four frames of a segmented upload of 0x1008:00 (24 bytes), the first segment of 7;
/// - node 4, an upload of 0x1018:01 not answered: of no known kind yet, 0 bytes;
/// - node 5, a block download of 0x2000:02 (20 bytes): two segments acknowledged, 14 bytes;
/// - node 6, a block upload of 0x2000:03 (30 bytes, the server's answer says): a segment not yet
///   acknowledged, 0 bytes.
///
/// The exit code is 0. With --json each is an event with "open"; with --only not naming SDOs, and
/// for one node, only what is shown.
#[test]
fn transfers_left_open_are_named_at_the_end() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("cut.log");
    std::fs::write(
        &log,
        "(20.000000) can0 602#210020010A000000\n\
         (20.001000) can0 582#6000200100000000\n\
         (20.002000) can0 602#0001020304050607\n\
         (20.003000) can0 582#2000000000000000\n\
         (20.004000) can0 582#0011111111111111\n\
         (20.010000) can0 603#4008100000000000\n\
         (20.011000) can0 583#4108100018000000\n\
         (20.012000) can0 603#6000000000000000\n\
         (20.013000) can0 583#0058363742433433\n\
         (20.020000) can0 604#4018100100000000\n\
         (20.030000) can0 605#C600200214000000\n\
         (20.031000) can0 585#A400200204000000\n\
         (20.032000) can0 605#0111111111111111\n\
         (20.033000) can0 605#0222222222222222\n\
         (20.034000) can0 585#A202040000000000\n\
         (20.040000) can0 606#A400200304000000\n\
         (20.041000) can0 586#C60020031E000000\n\
         (20.042000) can0 606#A300000000000000\n\
         (20.043000) can0 586#0133333333333333\n\
         (20.050000) can0 607#4000100000000000\n\
         (20.051000) can0 587#4300100092010200\n",
    )
    .unwrap();
    let log = log.to_str().unwrap();
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
            .args(args)
            .output()
            .expect("run sdo-tool");
        assert_eq!(out.status.code(), Some(0), "{args:?}");
        assert_eq!(String::from_utf8_lossy(&out.stderr), "", "{args:?}");
        String::from_utf8(out.stdout).unwrap()
    };
    assert_eq!(
        run(&["decode", log]),
        "  0.051000  node 7: SDO read 0x1000:00 = 92 01 02 00\n\
         \x20 0.051000  node 2: SDO segmented download of 0x2000:01 left open: 7 of 10 bytes so far, its last frame at 0.003000\n\
         \x20 0.051000  node 3: SDO segmented upload of 0x1008:00 left open: 7 of 24 bytes so far, its last frame at 0.013000\n\
         \x20 0.051000  node 4: SDO upload of 0x1018:01 left open: 0 bytes so far, its last frame at 0.020000\n\
         \x20 0.051000  node 5: SDO block download of 0x2000:02 left open: 14 of 20 bytes so far, its last frame at 0.034000\n\
         \x20 0.051000  node 6: SDO block upload of 0x2000:03 left open: 0 of 30 bytes so far, its last frame at 0.043000\n"
    );
    assert_eq!(
        run(&["decode", log, "3"]),
        "  0.051000  node 3: SDO segmented upload of 0x1008:00 left open: 7 of 24 bytes so far, its last frame at 0.013000\n"
    );
    assert_eq!(run(&["decode", log, "--only", "heartbeat,nmt"]), "");

    let events: Vec<serde_json::Value> = run(&["--json", "decode", log])
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(events.len(), 6);
    let close = |v: &serde_json::Value, x: f64| (v.as_f64().unwrap() - x).abs() < 1e-9;
    for (e, (node, object, kind, bytes, size, last)) in events[1..].iter().zip([
        (2, "0x2000:01", "segmented download", 7, Some(10), 0.003),
        (3, "0x1008:00", "segmented upload", 7, Some(24), 0.013),
        (4, "0x1018:01", "upload", 0, None, 0.020),
        (5, "0x2000:02", "block download", 14, Some(20), 0.034),
        (6, "0x2000:03", "block upload", 0, Some(30), 0.043),
    ]) {
        let open = &e["open"];
        assert!(close(&e["t"], 0.051), "{e}");
        assert!(close(&open["last"], last), "{e}");
        assert_eq!(open["node"], node, "{e}");
        assert_eq!(open["object"], object, "{e}");
        assert_eq!(open["kind"], kind, "{e}");
        assert_eq!(open["bytes"], bytes, "{e}");
        assert_eq!(open["size"], serde_json::json!(size), "{e}");
        assert!(
            e["event"]
                .as_str()
                .unwrap()
                .starts_with(&format!("node {node}: SDO {kind} of {object} left open: ")),
            "{e}"
        );
    }
}
