//! `sdo-tool decode` on pcapng captures (told from candump logs by their first four bytes,
//! 0x0A0D0D0A): the same session as a candump log and as a capture says the same lines, its times
//! from the blocks; what is no classic CAN frame of a SocketCAN interface is counted on standard
//! error; a capture without a SocketCAN interface (EtherCAT's) is refused; a capture cut short is
//! decoded up to the cut; a block that breaks the format is refused naming its offset. And
//! `--capture` where the tool opens no link, or where the file cannot be created.

use std::io::Write;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use link_capture::pcapng::{
    enhanced_packet, interface_description, section_header, Direction, LINKTYPE_CAN_SOCKETCAN,
    LINKTYPE_ETHERNET,
};

/// A session of six nodes as a candump log: a finished SDO read, transfers of every kind left
/// open (the lines `transfers_left_open_are_named_at_the_end` of tests/decode.rs decodes).
const LOG: &str = "(20.000000) can0 602#210020010A000000\n\
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
                   (20.051000) can0 587#4300100092010200\n";

/// What `decode` says of [`LOG`].
const DECODED: &str = "  0.051000  node 7: SDO read 0x1000:00 = 92 01 02 00\n\
    \x20 0.051000  node 2: SDO segmented download of 0x2000:01 left open: 7 of 10 bytes so far, its last frame at 0.003000\n\
    \x20 0.051000  node 3: SDO segmented upload of 0x1008:00 left open: 7 of 24 bytes so far, its last frame at 0.013000\n\
    \x20 0.051000  node 4: SDO upload of 0x1018:01 left open: 0 bytes so far, its last frame at 0.020000\n\
    \x20 0.051000  node 5: SDO block download of 0x2000:02 left open: 14 of 20 bytes so far, its last frame at 0.034000\n\
    \x20 0.051000  node 6: SDO block upload of 0x2000:03 left open: 0 of 30 bytes so far, its last frame at 0.043000\n";

/// [`LOG`]'s frames: the time in µs since 20 s and the SocketCAN bytes (identifier big-endian,
/// length 8, three zeros, the data), read from the log's text here.
fn frames() -> Vec<(u64, [u8; 16])> {
    LOG.lines()
        .map(|l| {
            let (t, rest) = l
                .trim()
                .trim_start_matches('(')
                .split_once(") can0 ")
                .unwrap();
            let us = (t.parse::<f64>().unwrap() * 1e6).round() as u64 - 20_000_000;
            let (id, data) = rest.split_once('#').unwrap();
            let mut b = [0u8; 16];
            b[..4].copy_from_slice(&u32::from_str_radix(id, 16).unwrap().to_be_bytes());
            b[4] = 8;
            for k in 0..8 {
                b[8 + k] = u8::from_str_radix(&data[2 * k..2 * k + 2], 16).unwrap();
            }
            (us, b)
        })
        .collect()
}

/// 2023-11-14 22:13:20 UTC plus `us`.
fn at(us: u64) -> SystemTime {
    UNIX_EPOCH + Duration::from_secs(1_700_000_000) + Duration::from_micros(us)
}

fn sdo_tool(args: &[&str], stdin: Option<&[u8]>) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run sdo-tool");
    let mut input = child.stdin.take().unwrap();
    if let Some(bytes) = stdin {
        input.write_all(bytes).unwrap();
    }
    drop(input);
    child.wait_with_output().unwrap()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// [`LOG`] as a capture of two interfaces, vcan0 and an Ethernet one, with an Ethernet frame, an
/// error frame (CAN_ERR_FLAG) and a CAN FD frame (72 bytes) among the CAN frames: the same lines
/// as the log, from a file and from standard input; the three others counted on standard error.
#[test]
fn a_capture_decodes_as_its_candump_log() {
    let mut file = Vec::new();
    section_header(&mut file, "test");
    interface_description(&mut file, LINKTYPE_CAN_SOCKETCAN, "vcan0");
    interface_description(&mut file, LINKTYPE_ETHERNET, "eth0");
    for (k, (us, bytes)) in frames().into_iter().enumerate() {
        let direction = if k % 2 == 0 {
            Direction::Outbound
        } else {
            Direction::Inbound
        };
        enhanced_packet(&mut file, 0, at(us), direction, &bytes);
        match k {
            3 => enhanced_packet(&mut file, 1, at(us), Direction::Inbound, &[0xFF; 60]),
            5 => {
                let error = [0x20, 0, 0, 0x04, 8, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0];
                enhanced_packet(&mut file, 0, at(us), Direction::Inbound, &error)
            }
            7 => enhanced_packet(&mut file, 0, at(us), Direction::Inbound, &[0; 72]),
            _ => {}
        }
    }
    let dir = tempfile::tempdir().unwrap();
    let (log, cap) = (dir.path().join("s.log"), dir.path().join("s.pcapng"));
    std::fs::write(&log, LOG).unwrap();
    std::fs::write(&cap, &file).unwrap();
    let from_log = sdo_tool(&["decode", log.to_str().unwrap()], None);
    assert_eq!(text(&from_log.stdout), DECODED);
    let cap_name = cap.to_str().unwrap();
    let from_cap = sdo_tool(&["decode", cap_name], None);
    assert_eq!(
        from_cap.status.code(),
        Some(0),
        "{}",
        text(&from_cap.stderr)
    );
    assert_eq!(text(&from_cap.stdout), DECODED);
    assert_eq!(
        text(&from_cap.stderr),
        format!(
            "sdo-tool: {cap_name}: 1 packet(s) of interfaces that are no SocketCAN bus: skipped\n\
             sdo-tool: {cap_name}: 2 SocketCAN packet(s) are no classic CAN frame (the first: \
             packet 8, an error frame): skipped\n"
        )
    );
    let piped = sdo_tool(&["decode", "-", "3"], Some(&file));
    assert_eq!(
        text(&piped.stdout),
        "  0.051000  node 3: SDO segmented upload of 0x1008:00 left open: 7 of 24 bytes so far, \
         its last frame at 0.013000\n"
    );
    assert!(text(&piped.stderr).starts_with("sdo-tool: standard input: 1 packet(s) "));
}

/// A capture of an EtherCAT link only: refused in one line naming its interfaces, exit 2 (decode
/// names CAN frames; the CoE in EtherCAT frames is Wireshark's to dissect).
#[test]
fn an_ethercat_capture_is_refused_naming_its_interfaces() {
    let mut file = Vec::new();
    section_header(&mut file, "");
    interface_description(&mut file, LINKTYPE_ETHERNET, "ecm0");
    enhanced_packet(&mut file, 0, at(0), Direction::Outbound, &[0xFF; 60]);
    let o = sdo_tool(&["decode", "-"], Some(&file));
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(text(&o.stdout), "");
    assert_eq!(
        text(&o.stderr),
        "sdo-tool: standard input: no SocketCAN interface in the capture (its interfaces: ecm0 \
         (link type 1)): decode names CAN frames only\n"
    );
    let mut empty = Vec::new();
    section_header(&mut empty, "");
    let o = sdo_tool(&["decode", "-"], Some(&empty));
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("(it describes none)"),
        "{}",
        text(&o.stderr)
    );
}

/// A capture cut inside its last block (a file still being written) is decoded up to the cut, and
/// the cut is named; a block whose length breaks the format is refused naming its offset, after
/// the frames before it (exit 2).
#[test]
fn a_capture_cut_short_and_a_broken_block() {
    let mut file = Vec::new();
    section_header(&mut file, "");
    interface_description(&mut file, LINKTYPE_CAN_SOCKETCAN, "can0");
    let heartbeat = [0, 0, 0x07, 0x01, 1, 0, 0, 0, 0x05, 0, 0, 0, 0, 0, 0, 0];
    enhanced_packet(&mut file, 0, at(0), Direction::Inbound, &heartbeat);
    let whole = file.len();
    enhanced_packet(&mut file, 0, at(1000), Direction::Inbound, &heartbeat);
    let o = sdo_tool(&["decode", "-"], Some(&file[..file.len() - 10]));
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(
        text(&o.stdout),
        "  0.000000  node 1: heartbeat, operational\n"
    );
    assert_eq!(
        text(&o.stderr),
        format!(
            "sdo-tool: standard input: the capture ends inside the block at byte {whole} (cut \
             short): decoded up to there\n"
        )
    );
    let mut broken = file[..whole].to_vec();
    broken.extend_from_slice(&[6, 0, 0, 0, 33, 0, 0, 0]);
    let o = sdo_tool(&["decode", "-"], Some(&broken));
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        text(&o.stdout),
        "  0.000000  node 1: heartbeat, operational\n"
    );
    assert_eq!(
        text(&o.stderr),
        format!(
            "sdo-tool: standard input: byte {whole}: block length 33 is not a length of a block \
             of type 0x00000006\n"
        )
    );
}

/// `--capture` is refused where the tool opens no bus and no interface (before a capture file could
/// be written over, e.g. the one being decoded), and where the file cannot be created, before
/// anything is sent.
#[test]
fn capture_refusals() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("c.pcapng");
    let f = f.to_str().unwrap();
    for (args, command) in [
        (&["decode", "x.log"][..], "decode"),
        (&["list"], "list"),
        (&["net", "check", "bus.yml"], "net"),
    ] {
        let o = sdo_tool(&[&["--capture", f], args].concat(), None);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert_eq!(
            text(&o.stderr),
            format!(
                "sdo-tool: `{command}` uses no bus and no EtherCAT interface: --capture has \
                 nothing to record\n"
            ),
            "{args:?}"
        );
    }
    assert!(!std::path::Path::new(f).exists());
    let o = sdo_tool(
        &[
            "--capture",
            "/nonexistent/dir/c.pcapng",
            "--bus",
            "socketcand://127.0.0.1:1/can0",
            "read",
            "5",
            "0x1000",
            "u32",
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        text(&o.stderr),
        "sdo-tool: --capture /nonexistent/dir/c.pcapng: No such file or directory (os error 2)\n"
    );
}
