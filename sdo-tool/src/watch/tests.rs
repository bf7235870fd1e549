//! The watcher's lines, frame by frame, and candump logs both ways.

use super::*;

fn f(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

/// Feeds `frames` (time, COB-ID, data) to a watcher of every node; every line with its time.
fn run(frames: &[(f64, u16, &[u8])]) -> Vec<(f64, String)> {
    let mut w = Watcher::new(None, None);
    frames
        .iter()
        .flat_map(|(t, id, d)| {
            w.at(*t, &f(*id, d))
                .into_iter()
                .map(move |l| (*t, l))
                .collect::<Vec<_>>()
        })
        .collect()
}

/// Node 3 beats every 0.1 s: a frame at exactly twice the period after the last beat is not
/// late yet, one 2 µs later is, and only once. A boot-up message starts the count again: after
/// it no period is known, so a silence is not reported until two heartbeats have shown one;
/// two beats at the same instant show none either.
#[test]
fn a_heartbeat_is_missing_after_more_than_twice_its_period() {
    let sync = (0x080u16, &[][..]);
    let lines = run(&[
        (10.0, 0x703, &[0x05]),
        (10.1, 0x703, &[0x05]),
        (10.3, sync.0, sync.1),
        (10.300002, sync.0, sync.1),
        (10.5, sync.0, sync.1),
        (10.6, 0x703, &[0x05]),
        (10.7, 0x703, &[0x00]),
        (12.0, sync.0, sync.1),
        (12.1, 0x703, &[0x7F]),
        (12.1, 0x703, &[0x7F]),
        (13.0, sync.0, sync.1),
    ]);
    let missed: Vec<&(f64, String)> = lines.iter().filter(|(_, l)| l.contains("missed")).collect();
    assert_eq!(
        missed,
        [&(
            10.300002,
            "node 3: heartbeat missed: none for 0.200 s (period 0.100 s)".to_string()
        )]
    );
}

/// NMT commands by their command byte, to one node or all; SYNC with and without its counter; a
/// frame of a wrong length on those identifiers is none of them. A segmented upload of 10 bytes
/// (toggles 0 and 1, the last with n = 4) in one line.
#[test]
fn nmt_sync_and_a_segmented_upload() {
    let lines: Vec<String> = run(&[
        (0.0, 0x000, &[0x01, 3]),
        (0.0, 0x000, &[0x02, 0]),
        (0.0, 0x000, &[0x80, 3]),
        (0.0, 0x000, &[0x81, 3]),
        (0.0, 0x000, &[0x82, 3]),
        (0.0, 0x000, &[0x42, 3]),
        (0.0, 0x000, &[0x01]),
        (0.0, 0x080, &[]),
        (0.0, 0x080, &[7]),
        (0.0, 0x080, &[7, 8]),
        (0.1, 0x603, &[0x40, 0x00, 0x20, 0x02, 0, 0, 0, 0]),
        (0.1, 0x583, &[0x41, 0x00, 0x20, 0x02, 10, 0, 0, 0]),
        (0.1, 0x603, &[0x60, 0, 0, 0, 0, 0, 0, 0]),
        (0.1, 0x583, &[0x00, 1, 2, 3, 4, 5, 6, 7]),
        (0.1, 0x603, &[0x70, 0, 0, 0, 0, 0, 0, 0]),
        (0.1, 0x583, &[0x19, 8, 9, 10, 0, 0, 0, 0]),
        // e without s, n bits set: all four bytes (the n bits count only with s).
        (0.2, 0x603, &[0x2E, 0x00, 0x20, 0x01, 1, 2, 3, 4]),
    ])
    .into_iter()
    .map(|(_, l)| l)
    .collect();
    assert_eq!(
        lines,
        [
            "NMT start: node 3",
            "NMT stop: all nodes",
            "NMT enter pre-operational: node 3",
            "NMT reset node: node 3",
            "NMT reset communication: node 3",
            "NMT command 0x42 to node 3",
            "SYNC",
            "SYNC 7",
            "node 3: SDO read 0x2000:02 = 01 02 03 04 05 06 07 08 09 0A (10 bytes, segmented)",
            "node 3: SDO write 0x2000:01 = 01 02 03 04",
        ]
    );
}

/// A watcher of node 3 shows NMT commands to it and to all, not to node 4; frames that do not
/// belong to the transfer going on (a client's segment during an upload, a server's segment and
/// initiate answer during a download) are not taken into it.
#[test]
fn one_node_and_stray_frames() {
    let mut w = Watcher::new(Some(3), None);
    let mut lines = Vec::new();
    for (id, d) in [
        (0x000u16, &[0x01u8, 3][..]),
        (0x000, &[0x01, 0]),
        (0x000, &[0x01, 4]),
        // An upload of 0x2000:02, 3 bytes in one segment, with a stray client segment before.
        (0x603, &[0x40, 0x00, 0x20, 0x02, 0, 0, 0, 0]),
        (0x583, &[0x41, 0x00, 0x20, 0x02, 3, 0, 0, 0]),
        (0x603, &[0x01, 0xEE, 0, 0, 0, 0, 0, 0]),
        (0x603, &[0x60, 0, 0, 0, 0, 0, 0, 0]),
        (0x583, &[0x09, 1, 2, 3, 0, 0, 0, 0]),
        // A download of 0x2000:03, 8 bytes, with a stray server segment and initiate answer.
        (0x603, &[0x21, 0x00, 0x20, 0x03, 8, 0, 0, 0]),
        (0x583, &[0x60, 0x00, 0x20, 0x03, 0, 0, 0, 0]),
        (0x583, &[0x01, 0xEE, 0, 0, 0, 0, 0, 0]),
        (0x603, &[0x00, 1, 2, 3, 4, 5, 6, 7]),
        (0x603, &[0x1D, 8, 0, 0, 0, 0, 0, 0]),
    ] {
        lines.extend(w.line(&f(id, d)));
    }
    assert_eq!(
        lines,
        [
            "NMT start: node 3",
            "NMT start: all nodes",
            "node 3: SDO read 0x2000:02 = 01 02 03 (3 bytes, segmented)",
            "node 3: SDO write 0x2000:03 = 01 02 03 04 05 06 07 08 (8 bytes, segmented)",
        ]
    );
}

/// `candump -L` lines: standard and extended identifiers, remote frames with and without a
/// length, empty data; what is not one (odd or too many data digits, CAN FD's `##`, no time)
/// is none.
#[test]
fn candump_lines_both_ways() {
    let (t, fr) = candump_line("(1700000000.250000) can0 601#4018100100000000").unwrap();
    assert_eq!(t, 1_700_000_000.25);
    assert_eq!(fr, f(0x601, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]));
    assert_eq!(
        candump_line("(1.0) vcan0 1ABCDEF0#0102").unwrap().1,
        CanFrame::new_extended(0x1ABC_DEF0, &[1, 2]).unwrap()
    );
    assert_eq!(
        candump_line("(1.0) can0 123#R").unwrap().1,
        CanFrame::new_remote_frame(0x123, false, 0).unwrap()
    );
    assert_eq!(
        candump_line("(1.0) can0 123#R5").unwrap().1,
        CanFrame::new_remote_frame(0x123, false, 5).unwrap()
    );
    assert_eq!(candump_line("(1.0) can0 080#").unwrap().1, f(0x080, &[]));
    for bad in [
        "(1.0) can0 123#012",
        "(1.0) can0 123#000102030405060708",
        "(1.0) can0 123##1020304",
        "can0 123#01",
        "(x) can0 123#01",
        "(1.0) can0 12G#01",
        "",
    ] {
        assert_eq!(candump_line(bad), None, "{bad:?}");
    }
    let at = std::time::UNIX_EPOCH + std::time::Duration::from_micros(1_700_000_000_250_001);
    assert_eq!(
        candump(at, "can0", &f(0x181, &[1, 2])),
        "(1700000000.250001) can0 181#0102"
    );
}

/// What is no `candump -L` frame, whatever its bytes, is none: hex digits cut in the middle of
/// a character, a sign before an identifier or a data byte, an identifier of neither 3 nor 8
/// digits (canplayer refuses it too), a time that is no finite number.
#[test]
fn odd_text_is_no_frame() {
    for bad in [
        "(1.0) can0 123#a\u{e9}1",
        "(1.0) can0 123#\u{e9}\u{e9}",
        "(1.0) can0 1\u{e9}#01",
        "(1.0) can0 \u{e9}#01",
        "(1.0) can0 +12#01",
        "(1.0) can0 123#+1",
        "(1.0) can0 #01",
        "(1.0) can0 123#R+1",
        "(1.0) can0 1234#01",
        "(nan) can0 123#01",
        "(inf) can0 123#01",
        "(-inf) can0 123#01",
    ] {
        assert_eq!(candump_line(bad), None, "{bad:?}");
    }
    assert_eq!(
        candump_line("(1.0) can0 123#aBcD").unwrap().1,
        f(0x123, &[0xAB, 0xCD])
    );
}

/// A remote frame of length 1 on a heartbeat's identifier is no heartbeat (it has no data
/// byte): nothing without --raw, itself with it, and no period is taken from it.
#[test]
fn a_remote_frame_on_a_heartbeat_identifier_is_no_heartbeat() {
    let rtr = CanFrame::new_remote_frame(0x703, false, 1).unwrap();
    let mut w = Watcher::new(None, None);
    assert!(w.at(0.0, &rtr).is_empty());
    assert!(w.at(0.1, &rtr).is_empty());
    assert!(w.missed(5.0).is_empty());
    let mut w = Watcher::new(None, None).with_raw(true);
    assert_eq!(w.at(0.0, &rtr), ["703#R1"]);
}

/// Lines read through a 3-byte buffer, at most 5 bytes kept: one of exactly 5, one of 6 (too
/// long, not kept), an empty one, one ending in CR LF (the CR is the line's), and a last line
/// without a line end, too long; then the end. A short last line without its end is a line.
#[test]
fn log_lines_are_kept_up_to_the_limit() {
    let input: &[u8] = b"abc\n12345\n123456\n\nxy\r\n0123456789abcdef";
    let mut lines = LogLines::new(std::io::BufReader::with_capacity(3, input), 5);
    let mut got = Vec::new();
    while let Some((n, line)) = lines.next_line().unwrap() {
        got.push((n, format!("{line:?}")));
    }
    let text = |b: &[u8]| format!("{:?}", LogLine::Text(b));
    let too_long = format!("{:?}", LogLine::TooLong);
    assert_eq!(
        got,
        [
            (1, text(b"abc")),
            (2, text(b"12345")),
            (3, too_long.clone()),
            (4, text(b"")),
            (5, text(b"xy\r")),
            (6, too_long),
        ]
    );
    let mut lines = LogLines::new(&b"a\nb"[..], 5);
    assert_eq!(lines.next_line().unwrap(), Some((1, LogLine::Text(b"a"))));
    assert_eq!(lines.next_line().unwrap(), Some((2, LogLine::Text(b"b"))));
    assert_eq!(lines.next_line().unwrap(), None);
    assert_eq!(LogLines::new(&b""[..], 5).next_line().unwrap(), None);
}

/// Expedited transfers by their `e`, `s` and `n` bits: 4 bytes without the size, 3 with n = 1, 2
/// with n = 2; a segmented download (the initiate announcing 10 bytes, segments of 7 and 3 with
/// toggles 0 and 1, the last with n = 4 and c) in one line, the server's initiate answer not
/// taken for its end; the client's block download and upload initiates, and a block frame with
/// no transfer going on, which is nothing.
#[test]
fn expedited_and_segmented_transfers_by_their_bits() {
    let lines: Vec<String> = run(&[
        (0.0, 0x603, &[0x22, 0x00, 0x20, 0x01, 1, 2, 3, 4]),
        (0.0, 0x603, &[0x27, 0x00, 0x20, 0x01, 1, 2, 3, 9]),
        (0.0, 0x583, &[0x4B, 0x00, 0x20, 0x01, 5, 6, 9, 9]),
        (0.0, 0x583, &[0x42, 0x00, 0x20, 0x01, 5, 6, 7, 8]),
        (0.1, 0x603, &[0x21, 0x00, 0x20, 0x02, 10, 0, 0, 0]),
        (0.1, 0x583, &[0x60, 0x00, 0x20, 0x02, 0, 0, 0, 0]),
        (0.1, 0x603, &[0x00, 1, 2, 3, 4, 5, 6, 7]),
        (0.1, 0x583, &[0x20, 0, 0, 0, 0, 0, 0, 0]),
        (0.1, 0x603, &[0x19, 8, 9, 10, 0, 0, 0, 0]),
        (0.1, 0x583, &[0x30, 0, 0, 0, 0, 0, 0, 0]),
        // Block frames with nothing going on: an end (0xC1) and a start (0xA3) are nothing.
        (0.2, 0x603, &[0xC1, 0, 0, 0, 0, 0, 0, 0]),
        (0.2, 0x603, &[0xA3, 0, 0, 0, 0, 0, 0, 0]),
        // A block download: begun by 0xC6, its segments (the client's) unnamed, ended by 0xA1.
        (0.3, 0x603, &[0xC6, 0x00, 0x20, 0x03, 3, 0, 0, 0]),
        (0.3, 0x583, &[0xA4, 0x00, 0x20, 0x03, 0x7F, 0, 0, 0]),
        (0.3, 0x603, &[0x81, 1, 2, 3, 0, 0, 0, 0]),
        (0.3, 0x583, &[0xA2, 0x01, 0x7F, 0, 0, 0, 0, 0]),
        (0.3, 0x603, &[0xD1, 0, 0, 0, 0, 0, 0, 0]),
        (0.3, 0x583, &[0xA1, 0, 0, 0, 0, 0, 0, 0]),
    ])
    .into_iter()
    .map(|(_, l)| l)
    .collect();
    assert_eq!(
        lines,
        [
            "node 3: SDO write 0x2000:01 = 01 02 03 04",
            "node 3: SDO write 0x2000:01 = 01 02 03",
            "node 3: SDO read 0x2000:01 = 05 06",
            "node 3: SDO read 0x2000:01 = 05 06 07 08",
            "node 3: SDO write 0x2000:02 = 01 02 03 04 05 06 07 08 09 0A (10 bytes, segmented)",
            "node 3: SDO written 0x2000:03 = 01 02 03 (3 bytes, block transfer)",
        ]
    );
}

/// SDO frames of node 3 in words: an expedited read; a block upload whose segments (any first
/// byte, here 0x01 and 0x82 that look like a download segment and an abort) are the server's
/// data, until the client's 0xA1 ends it; an abort during a block download from the server's
/// side.
#[test]
fn sdo_frames_in_words() {
    let lines: Vec<String> = run(&[
        (0.0, 0x603, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]),
        (0.0, 0x583, &[0x43, 0x18, 0x10, 0x01, 0x2E, 0x0B, 0, 0]),
        // Block upload of 0x1008: initiate, the server's answer, start, 2 segments, ack, end.
        (0.1, 0x603, &[0xA4, 0x08, 0x10, 0x00, 0x7F, 0, 0, 0]),
        (0.1, 0x583, &[0xC6, 0x08, 0x10, 0x00, 0x0A, 0, 0, 0]),
        (0.1, 0x603, &[0xA3, 0, 0, 0, 0, 0, 0, 0]),
        (
            0.1,
            0x583,
            &[0x01, 0x80, 0x81, 0x82, 0x83, 0x84, 0x85, 0x86],
        ),
        (0.1, 0x583, &[0x82, 0xC2, 0x08, 0x10, 0, 0, 0, 0]),
        (0.1, 0x603, &[0xA2, 0x02, 0x7F, 0, 0, 0, 0, 0]),
        // The end: n = 4 bytes of the last segment carry no data.
        (0.1, 0x583, &[0xD1, 0, 0, 0, 0, 0, 0, 0]),
        (0.1, 0x603, &[0xA1, 0, 0, 0, 0, 0, 0, 0]),
        // Block download of 0x2000:01 aborted by the server.
        (0.2, 0x603, &[0xC6, 0x00, 0x20, 0x01, 0x10, 0, 0, 0]),
        (
            0.2,
            0x583,
            &[0x80, 0x00, 0x20, 0x01, 0x00, 0x00, 0x00, 0x08],
        ),
    ])
    .into_iter()
    .map(|(_, l)| l)
    .collect();
    assert_eq!(
        lines,
        [
            "node 3: SDO read 0x1018:01 = 2E 0B 00 00",
            "node 3: SDO read 0x1008:00 = 80 81 82 83 84 85 86 C2 08 10 (10 bytes, block transfer)",
            "node 3: SDO server aborts 0x2000:01: 0x08000000 (General error)",
        ]
    );
}

/// candump's filter forms: one ID, ID:MASK, a range, `~` inverting; hex with or without 0x.
#[test]
fn filters_take_what_candump_would() {
    let f = |t: &str| t.parse::<CobFilter>().unwrap();
    let takes = |t: &str, ids: &[u16]| -> Vec<u16> {
        let f = f(t);
        ids.iter().copied().filter(|&c| f.passes(c)).collect()
    };
    let ids = [
        0x000, 0x080, 0x185, 0x186, 0x1FF, 0x205, 0x585, 0x605, 0x705, 0x7FF,
    ];
    assert_eq!(takes("185", &ids), [0x185]);
    assert_eq!(takes("0x185", &ids), [0x185]);
    // Node 5's every COB-ID: the low 7 bits are 5.
    assert_eq!(takes("5:7F", &ids), [0x185, 0x205, 0x585, 0x605, 0x705]);
    assert_eq!(takes("180-1FF", &ids), [0x185, 0x186, 0x1FF]);
    assert_eq!(takes("0x580-0x67F", &ids), [0x585, 0x605]);
    // Not a heartbeat (0x700–0x77F): 0x7FF is not one.
    assert_eq!(
        takes("~700:780", &ids),
        [0x000, 0x080, 0x185, 0x186, 0x1FF, 0x205, 0x585, 0x605, 0x7FF]
    );
    assert_eq!(takes("~185", &ids).len(), ids.len() - 1);
    for bad in ["", "800", "1FF-180", "x", "185:", "-", "185:800", "~"] {
        let e = bad.parse::<CobFilter>().unwrap_err();
        assert!(
            e.starts_with(&format!("filter {bad:?} is not ID, ID:MASK or LOW-HIGH")),
            "{e}"
        );
    }
    assert_eq!(takes("185-185", &ids), [0x185]);
    for (name, kind) in [
        ("nmt", Kind::Nmt),
        ("heartbeat", Kind::Heartbeat),
        ("HB", Kind::Heartbeat),
        ("sync", Kind::Sync),
        ("EMCY", Kind::Emcy),
        ("sdo", Kind::Sdo),
        ("pdo", Kind::Pdo),
        ("other", Kind::Other),
        ("raw", Kind::Other),
    ] {
        assert_eq!(name.parse::<Kind>(), Ok(kind), "{name}");
    }
    assert!("pdos".parse::<Kind>().is_err());
}

/// With filters only the frames they pass are looked at: a heartbeat filtered out is neither
/// shown nor counted for a missed beat. With `--only`, the kinds not asked for are not shown,
/// but an SDO transfer is still followed.
#[test]
fn filters_and_kinds_choose_what_is_shown() {
    let frames: &[(f64, u16, &[u8])] = &[
        (0.00, 0x000, &[0x01, 0x05]),
        (0.01, 0x705, &[0x05]),
        (0.02, 0x080, &[]),
        (0.03, 0x605, &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]),
        (
            0.04,
            0x585,
            &[0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00],
        ),
        (0.05, 0x085, &[0x10, 0x81, 0x11, 0, 0, 0, 0, 0]),
        (0.06, 0x123, &[0xAA]),
    ];
    let run_with = |w: Watcher| -> Vec<String> {
        let mut w = w.with_raw(true);
        frames
            .iter()
            .flat_map(|(t, id, d)| w.at(*t, &f(*id, d)))
            .collect()
    };
    let all = run_with(Watcher::new(None, None));
    assert_eq!(all.len(), 7, "{all:?}");
    let sdo_only =
        run_with(Watcher::new(None, None).with_filters(vec!["580-67F".parse().unwrap()]));
    // The upload's request names nothing yet (raw), its answer the value.
    assert_eq!(
        sdo_only,
        [
            "605#4000100000000000",
            "node 5: SDO read 0x1000:00 = 92 01 02 00"
        ]
    );
    let only = |kinds: Vec<Kind>| run_with(Watcher::new(None, None).with_only(kinds));
    assert_eq!(only(vec![Kind::Sync]), ["SYNC"]);
    assert_eq!(
            only(vec![Kind::Emcy]),
            ["node 5: EMCY 0x8110 (CAN overrun (objects lost)), error register 0x11, data 00 00 00 00 00"]
        );
    assert_eq!(only(vec![Kind::Other]), ["123#AA"]);
    assert_eq!(
        only(vec![Kind::Heartbeat, Kind::Sync]),
        ["node 5: heartbeat, operational", "SYNC"]
    );
    // SDOs not asked for: nothing of the upload.
    let nmt = run_with(Watcher::new(None, None).with_only(vec![Kind::Nmt]));
    assert_eq!(nmt, ["NMT start: node 5"]);
    // A heartbeat filtered out does not count: no missed beat after it.
    let mut w = Watcher::new(None, None).with_filters(vec!["~700:780".parse().unwrap()]);
    for t in [0.0, 0.1, 0.2] {
        assert!(w.at(t, &f(0x703, &[0x05])).is_empty());
    }
    assert!(w.missed(5.0).is_empty());
    let mut w = Watcher::new(None, None).with_only(vec![Kind::Sdo]);
    for t in [0.0, 0.1] {
        assert!(w.at(t, &f(0x703, &[0x05])).is_empty());
    }
    assert!(
        w.missed(5.0).is_empty(),
        "a missed beat is a heartbeat line"
    );
    let mut w = Watcher::new(None, None).with_only(vec![Kind::Heartbeat]);
    for t in [0.0, 0.1] {
        w.at(t, &f(0x703, &[0x05]));
    }
    assert_eq!(
        w.missed(5.0),
        ["node 3: heartbeat missed: none for 4.900 s (period 0.100 s)"]
    );
}

/// A block download of 0x2000:04 (blksize 4) in which the third segment is lost: the server
/// acknowledges 2, the client sends the rest again as a new sub-block (sequence numbers from
/// 1); the data is what the acknowledgements took, less the end's n. Then a block download
/// the client aborts (0x80: sequence number 0 is no segment).
#[test]
fn a_block_transfer_with_a_lost_segment_is_reassembled() {
    let lines: Vec<String> = run(&[
        (0.0, 0x603, &[0xC6, 0x00, 0x20, 0x04, 25, 0, 0, 0]),
        (0.0, 0x583, &[0xA4, 0x00, 0x20, 0x04, 4, 0, 0, 0]),
        (
            0.0,
            0x603,
            &[0x01, 0x10, 0x11, 0x12, 0x13, 0x14, 0x15, 0x16],
        ),
        (
            0.0,
            0x603,
            &[0x02, 0x20, 0x21, 0x22, 0x23, 0x24, 0x25, 0x26],
        ),
        (
            0.0,
            0x603,
            &[0x04, 0x40, 0x41, 0x42, 0x43, 0x44, 0x45, 0x46],
        ),
        (0.0, 0x583, &[0xA2, 0x02, 0x04, 0, 0, 0, 0, 0]),
        (
            0.0,
            0x603,
            &[0x01, 0x30, 0x31, 0x32, 0x33, 0x34, 0x35, 0x36],
        ),
        (0.0, 0x603, &[0x82, 0x40, 0x41, 0x42, 0x43, 0, 0, 0]),
        (0.0, 0x583, &[0xA2, 0x02, 0x04, 0, 0, 0, 0, 0]),
        // 7 + 7 + 7 + 4 = 25 bytes: n = 3.
        (0.0, 0x603, &[0xCD, 0x12, 0x34, 0, 0, 0, 0, 0]),
        (0.0, 0x583, &[0xA1, 0, 0, 0, 0, 0, 0, 0]),
        (0.1, 0x603, &[0xC2, 0x00, 0x20, 0x05, 0, 0, 0, 0]),
        (0.1, 0x583, &[0xA0, 0x00, 0x20, 0x05, 4, 0, 0, 0]),
        (0.1, 0x603, &[0x01, 1, 2, 3, 4, 5, 6, 7]),
        (
            0.1,
            0x603,
            &[0x80, 0x00, 0x20, 0x05, 0x00, 0x00, 0x04, 0x05],
        ),
        // Nothing goes on now: the server's late acknowledgement is nothing.
        (0.1, 0x583, &[0xA2, 0x01, 0x04, 0, 0, 0, 0, 0]),
    ])
    .into_iter()
    .map(|(_, l)| l)
    .collect();
    assert_eq!(
        lines,
        [
            "node 3: SDO written 0x2000:04 = 10 11 12 13 14 15 16 20 21 22 23 24 25 26 30 31 32 \
                 33 34 35 36 40 41 42 43 (25 bytes, block transfer)",
            "node 3: SDO client aborts 0x2000:05: 0x05040000 (SDO protocol timed out)",
        ]
    );
}

/// A server that acknowledges fewer segments than came (2 of 3, the third sent again), a
/// segment seen twice, and a sub-block of 65 segments whose last (0xC1: last, sequence 65)
/// looks like an end; then a client abort before the server's initiate answer.
#[test]
fn block_segments_count_as_acknowledged() {
    let seg = |seq: u8, last: bool, fill: u8| {
        let mut d = [fill; 8];
        d[0] = seq | if last { 0x80 } else { 0 };
        d
    };
    let mut frames: Vec<(f64, u16, Vec<u8>)> = vec![
        (0.0, 0x603, vec![0xC6, 0x00, 0x20, 0x06, 28, 0, 0, 0]),
        (0.0, 0x583, vec![0xA4, 0x00, 0x20, 0x06, 3, 0, 0, 0]),
        (0.0, 0x603, seg(1, false, 0x11).to_vec()),
        (0.0, 0x603, seg(1, false, 0x11).to_vec()),
        (0.0, 0x603, seg(2, false, 0x22).to_vec()),
        (0.0, 0x603, seg(3, false, 0x33).to_vec()),
        (0.0, 0x583, vec![0xA2, 0x02, 0x03, 0, 0, 0, 0, 0]),
        (0.0, 0x603, seg(1, false, 0x33).to_vec()),
        (0.0, 0x603, seg(2, true, 0x44).to_vec()),
        (0.0, 0x583, vec![0xA2, 0x02, 0x03, 0, 0, 0, 0, 0]),
        // 4 × 7 = 28 bytes: n = 0.
        (0.0, 0x603, vec![0xC1, 0, 0, 0, 0, 0, 0, 0]),
        (0.0, 0x583, vec![0xA1, 0, 0, 0, 0, 0, 0, 0]),
        (0.1, 0x603, vec![0xC6, 0x00, 0x20, 0x07, 0xC7, 0x01, 0, 0]),
        (0.1, 0x583, vec![0xA4, 0x00, 0x20, 0x07, 127, 0, 0, 0]),
    ];
    for k in 1..=65u8 {
        frames.push((0.1, 0x603, seg(k, k == 65, k).to_vec()));
    }
    frames.extend([
        (0.1, 0x583, vec![0xA2, 65, 127, 0, 0, 0, 0, 0]),
        // 65 × 7 = 455 bytes for 455: n = 0.
        (0.1, 0x603, vec![0xC1, 0, 0, 0, 0, 0, 0, 0]),
        (0.1, 0x583, vec![0xA1, 0, 0, 0, 0, 0, 0, 0]),
        (0.2, 0x603, vec![0xC6, 0x00, 0x20, 0x08, 4, 0, 0, 0]),
        (
            0.2,
            0x603,
            vec![0x80, 0x00, 0x20, 0x08, 0x00, 0x00, 0x00, 0x08],
        ),
    ]);
    let mut w = Watcher::new(None, None);
    let lines: Vec<String> = frames
        .iter()
        .flat_map(|(t, id, d)| w.at(*t, &f(*id, d)))
        .collect();
    assert_eq!(lines.len(), 3, "{lines:#?}");
    let mut first = "node 3: SDO written 0x2000:06 = ".to_string();
    let bytes: Vec<String> = [0x11u8, 0x22, 0x33, 0x44]
        .iter()
        .flat_map(|b| std::iter::repeat_n(format!("{b:02X}"), 7))
        .collect();
    first.push_str(&bytes.join(" "));
    first.push_str(" (28 bytes, block transfer)");
    assert_eq!(lines[0], first);
    // 455 bytes: the first 32 shown, the line gives the length.
    let long: Vec<String> = (1..=65u8)
        .flat_map(|k| std::iter::repeat_n(format!("{k:02X}"), 7))
        .collect();
    assert_eq!(
        lines[1],
        format!(
            "node 3: SDO written 0x2000:07 = {} … (455 bytes, block transfer)",
            long[..32].join(" ")
        )
    );
    assert_eq!(
        lines[2],
        "node 3: SDO client aborts 0x2000:08: 0x08000000 (General error)"
    );
    // With every byte asked for (`--full`).
    let mut w = Watcher::new(None, None).with_full(true);
    let lines: Vec<String> = frames
        .iter()
        .flat_map(|(t, id, d)| w.at(*t, &f(*id, d)))
        .collect();
    assert_eq!(
        lines[1],
        format!(
            "node 3: SDO written 0x2000:07 = {} (455 bytes, block transfer)",
            long.join(" ")
        )
    );
}
