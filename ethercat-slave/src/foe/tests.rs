//! The FoE server against frames written byte by byte from ETG.1000.6 §5.9: OpCode, a reserved
//! 0, the 32-bit field little-endian, then name, data or text. Mailboxes of 32 bytes: 20 bytes of
//! file a packet.

use super::*;
use od::foe::data_per_packet;

/// Bytes from hexadecimal, then `tail`.
fn h(text: &str, tail: &[u8]) -> Vec<u8> {
    let mut v: Vec<u8> = text
        .split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).unwrap())
        .collect();
    v.extend_from_slice(tail);
    v
}

const PRE_OP: Link = Link {
    boot: false,
    write_len: 32,
    read_len: 32,
};
const BOOT: Link = Link {
    boot: true,
    write_len: 32,
    read_len: 32,
};
/// As [`PRE_OP`] and [`BOOT`] with a read mailbox of 128 bytes: room for the Error texts whole.
const WIDE: Link = Link {
    read_len: 128,
    ..PRE_OP
};
const BOOT_WIDE: Link = Link {
    read_len: 128,
    ..BOOT
};

/// `n` bytes 0, 1, 2, …
fn file(n: usize) -> Vec<u8> {
    (0..n).map(|k| k as u8).collect()
}

/// A server, its clock and a link.
struct Bench {
    server: FoeServer,
    now: Instant,
    link: Link,
}

impl Bench {
    fn new(config: FoeConfig) -> Bench {
        let store = FileStore::new(config.max_file, config.max_store);
        Bench {
            server: FoeServer::new(config, store),
            now: Instant::now(),
            link: PRE_OP,
        }
    }

    /// The answer to `frame` 1 ms after the last (none: `None`); at most one.
    fn rx(&mut self, frame: &[u8]) -> Option<Vec<u8>> {
        self.now += Duration::from_millis(1);
        self.server.handle_mailbox(self.now, frame, self.link);
        let answer = self.server.poll_transmit();
        assert_eq!(self.server.poll_transmit(), None, "one answer at most");
        answer
    }

    fn events(&mut self) -> Vec<FoeEvent> {
        std::iter::from_fn(|| self.server.poll_event()).collect()
    }

    fn written(&mut self) -> Vec<(Vec<u8>, Vec<u8>)> {
        std::iter::from_fn(|| self.server.poll_written())
            .map(|(n, d)| (n, d.to_vec()))
            .collect()
    }

    /// Writes `data` as `name` in packets of the write mailbox (20 bytes of 32), every answer the
    /// Ack of its packet.
    fn write(&mut self, name: &[u8], data: &[u8]) {
        assert_eq!(
            self.rx(&h("02 00 00 00 00 00", name)),
            Some(h("04 00 00 00 00 00", &[]))
        );
        // A file that is a multiple of a packet ends with an empty packet.
        let full = data_per_packet(self.link.write_len);
        let whole = data.len() / full * full == data.len();
        let chunks = data.chunks(full).chain(whole.then_some(&[][..]));
        for (k, chunk) in chunks.enumerate() {
            let p = (k as u32 + 1).to_le_bytes();
            let mut frame = vec![0x03, 0x00, p[0], p[1], p[2], p[3]];
            frame.extend_from_slice(chunk);
            let ack = vec![0x04, 0x00, p[0], p[1], p[2], p[3]];
            assert_eq!(self.rx(&frame), Some(ack), "packet {}", k + 1);
        }
    }

    /// Reads `name`: the packets' data joined, every packet numbered in turn.
    fn read(&mut self, name: &[u8]) -> Vec<u8> {
        let mut answer = self.rx(&h("01 00 00 00 00 00", name)).unwrap();
        let mut out = Vec::new();
        for packet in 1u32.. {
            let p = packet.to_le_bytes();
            assert_eq!(answer[..6], [0x03, 0x00, p[0], p[1], p[2], p[3]]);
            out.extend_from_slice(&answer[6..]);
            let last = answer.len() - 6 < data_per_packet(self.link.read_len);
            let next = self.rx(&[0x04, 0x00, p[0], p[1], p[2], p[3]]);
            if last {
                assert_eq!(next, None, "nothing after the last Ack");
                break;
            }
            answer = next.unwrap();
        }
        out
    }
}

/// 25 bytes: Write request `02 00 | 00 00 00 00 | "a.bin"` → Ack 0 `04 00 00 00 00 00`; Data 1
/// (20 bytes) → Ack 1; Data 2 (5 bytes, shorter: the last) → Ack 2, and the file is there. Read
/// request → Data 1 `03 00 01 00 00 00` + 20 bytes; Ack 1 → Data 2 + 5 bytes; Ack 2 → nothing.
#[test]
fn a_file_written_in_packets_is_read_back_in_packets() {
    let mut b = Bench::new(FoeConfig::default());
    let data = file(25);
    assert_eq!(
        b.rx(&h("02 00 00 00 00 00", b"a.bin")),
        Some(h("04 00 00 00 00 00", &[]))
    );
    assert!(b.server.is_busy());
    assert_eq!(
        b.rx(&h("03 00 01 00 00 00", &data[..20])),
        Some(h("04 00 01 00 00 00", &[]))
    );
    assert_eq!(b.written(), []);
    assert_eq!(
        b.rx(&h("03 00 02 00 00 00", &data[20..])),
        Some(h("04 00 02 00 00 00", &[]))
    );
    assert!(!b.server.is_busy());
    assert_eq!(b.written(), [(b"a.bin".to_vec(), data.clone())]);
    assert_eq!(
        b.events(),
        [FoeEvent::Written {
            name: b"a.bin".to_vec(),
            size: 25
        }]
    );
    assert_eq!(
        b.rx(&h("01 00 00 00 00 00", b"a.bin")),
        Some(h("03 00 01 00 00 00", &data[..20]))
    );
    assert_eq!(
        b.rx(&h("04 00 01 00 00 00", &[])),
        Some(h("03 00 02 00 00 00", &data[20..]))
    );
    assert_eq!(b.rx(&h("04 00 02 00 00 00", &[])), None);
    assert!(!b.server.is_busy());
    assert_eq!(
        b.events(),
        [FoeEvent::Read {
            name: b"a.bin".to_vec(),
            size: 25
        }]
    );
}

/// 40 bytes, two full packets: a third, empty packet ends the write and ends the read; an empty
/// file is one empty packet each way.
#[test]
fn a_multiple_of_the_packet_ends_with_an_empty_packet() {
    let mut b = Bench::new(FoeConfig::default());
    b.write(b"m", &file(40));
    assert_eq!(b.read(b"m"), file(40));
    assert_eq!(b.rx(&h("01 00 00 00 00 00", b"m")).unwrap().len(), 26);
    assert_eq!(b.rx(&h("04 00 01 00 00 00", &[])).unwrap().len(), 26);
    assert_eq!(
        b.rx(&h("04 00 02 00 00 00", &[])),
        Some(h("03 00 03 00 00 00", &[]))
    );
    assert_eq!(b.rx(&h("04 00 03 00 00 00", &[])), None);
    b.write(b"e", &[]);
    assert_eq!(
        b.rx(&h("01 00 00 00 00 00", b"e")),
        Some(h("03 00 01 00 00 00", &[]))
    );
    assert_eq!(b.rx(&h("04 00 01 00 00 00", &[])), None);
    assert_eq!(b.server.store().get(b"e").map(|f| f.len()), Some(0));
}

/// The packets are as long as the mailbox the master writes (a full one: its length less 12)
/// and the one it reads, each as the link says when the transfer starts.
#[test]
fn packets_follow_the_mailbox_lengths() {
    let mut b = Bench::new(FoeConfig::default());
    b.link = Link {
        boot: false,
        write_len: 16,
        read_len: 20,
    };
    b.rx(&h("02 00 00 00 00 00", b"x"));
    // 4 bytes fill a 16-byte mailbox: not the last.
    assert_eq!(
        b.rx(&h("03 00 01 00 00 00", &[1, 2, 3, 4])),
        Some(h("04 00 01 00 00 00", &[]))
    );
    assert!(b.server.is_busy());
    assert_eq!(
        b.rx(&h("03 00 02 00 00 00", &[5])),
        Some(h("04 00 02 00 00 00", &[]))
    );
    assert_eq!(
        b.rx(&h("01 00 00 00 00 00", b"x")),
        Some(h("03 00 01 00 00 00", &[1, 2, 3, 4, 5]))
    );
    assert_eq!(b.rx(&h("04 00 01 00 00 00", &[])), None);
}

/// A Data packet of another number than the next: `05 00 05 80 00 00` with its text; the write
/// ends and leaves nothing; a Data frame then has no write (0x8004). An Ack of another packet
/// than the one sent ends a read the same way; an Ack with no read is 0x8004.
#[test]
fn a_wrong_packet_number_ends_the_transfer() {
    let mut b = Bench::new(FoeConfig::default());
    b.link = WIDE;
    b.rx(&h("02 00 00 00 00 00", b"w"));
    assert_eq!(
        b.rx(&h("03 00 02 00 00 00", &[1])),
        Some(h("05 00 05 80 00 00", b"packet 2, not 1"))
    );
    assert!(!b.server.is_busy());
    assert_eq!(b.written(), []);
    assert_eq!(
        b.rx(&h("03 00 01 00 00 00", &[1])),
        Some(h("05 00 04 80 00 00", b"no write in progress"))
    );
    b.write(b"r", &file(30));
    b.rx(&h("01 00 00 00 00 00", b"r"));
    assert_eq!(
        b.rx(&h("04 00 02 00 00 00", &[])),
        Some(h("05 00 05 80 00 00", b"Ack of packet 2, not 1"))
    );
    assert_eq!(
        b.rx(&h("04 00 01 00 00 00", &[])),
        Some(h("05 00 04 80 00 00", b"no read in progress"))
    );
    assert_eq!(
        b.events().last(),
        Some(&FoeEvent::Refused {
            name: Vec::new(),
            code: FoeErrorCode::Illegal
        })
    );
}

/// A file that is not there: `05 00 01 80 00 00 "no such file"`. With a password set, a request
/// with another is `05 00 0A 80 00 00 "wrong password"`, with it the request goes.
#[test]
fn not_found_and_a_wrong_password() {
    let mut b = Bench::new(FoeConfig {
        password: Some(0x1234_5678),
        ..FoeConfig::default()
    });
    assert_eq!(
        b.rx(&h("01 00 78 56 34 12", b"none")),
        Some(h("05 00 01 80 00 00", b"no such file"))
    );
    assert_eq!(
        b.rx(&h("02 00 00 00 00 00", b"p")),
        Some(h("05 00 0A 80 00 00", b"wrong password"))
    );
    assert_eq!(
        b.rx(&h("01 00 77 56 34 12", b"none")),
        Some(h("05 00 0A 80 00 00", b"wrong password"))
    );
    assert_eq!(
        b.rx(&h("02 00 78 56 34 12", b"p")),
        Some(h("04 00 00 00 00 00", &[]))
    );
}

/// A name of 0 or 81 bytes is 0x8004 with the rule; trailing NULs are no part of a name.
#[test]
fn names_of_1_to_80_bytes() {
    let mut b = Bench::new(FoeConfig::default());
    b.link = WIDE;
    assert_eq!(
        b.rx(&h("02 00 00 00 00 00", &[])),
        Some(h("05 00 04 80 00 00", b"a file name of 0 bytes (1 to 80)"))
    );
    assert_eq!(
        b.rx(&h("01 00 00 00 00 00", &[b'n'; 81])),
        Some(h("05 00 04 80 00 00", b"a file name of 81 bytes (1 to 80)"))
    );
    b.write(b"z\0\0", &[9]);
    assert_eq!(b.read(b"z"), [9]);
    b.write(&[b'n'; 80], &[1]);
    assert_eq!(b.read(&[b'n'; 80]), [1]);
}

/// Over the limit of a file (30 bytes): the packet that passes it is answered `05 00 03 80 00 00`
/// with the limit, the write ends, and the file of that name is as it was. Beside the others
/// (store 50 bytes, 30 taken): the same, naming what they take.
#[test]
fn a_file_over_the_limits_is_disk_full_and_changes_nothing() {
    let mut b = Bench::new(FoeConfig {
        max_file: 30,
        max_store: 50,
        ..FoeConfig::default()
    });
    b.link = WIDE;
    b.write(b"f", &file(30));
    b.rx(&h("02 00 00 00 00 00", b"f"));
    b.rx(&h("03 00 01 00 00 00", &[0xEE; 20]));
    assert_eq!(
        b.rx(&h("03 00 02 00 00 00", &[0xEE; 20])),
        Some(h(
            "05 00 03 80 00 00",
            b"40 bytes, over the 30-byte limit of a file"
        ))
    );
    assert_eq!(b.read(b"f"), file(30));
    b.rx(&h("02 00 00 00 00 00", b"g"));
    assert_eq!(
        b.rx(&h("03 00 01 00 00 00", &[1; 21])),
        Some(h(
            "05 00 03 80 00 00",
            b"21 bytes do not fit: 30 of the store's 50 bytes are taken by other files"
        ))
    );
    assert!(b.server.store().get(b"g").is_none());
    b.write(b"g", &file(20));
    assert_eq!(b.server.store().used(), 50);
}

/// With Bootstrap and firmware `*.efw`: a firmware file written outside Bootstrap is
/// `05 00 09 80 00 00` (Not Bootstrap), another file written in it `05 00 08 80 00 00`
/// (Bootstrap only); firmware goes in Bootstrap, other files outside it, and any file is read in
/// either. Without Bootstrap every name is written in any state.
#[test]
fn firmware_is_written_in_bootstrap_only() {
    let mut b = Bench::new(FoeConfig {
        boot: true,
        ..FoeConfig::default()
    });
    b.link = WIDE;
    assert_eq!(
        b.rx(&h("02 00 00 00 00 00", b"FW.EFW")),
        Some(h("05 00 09 80 00 00", b"firmware is written in Bootstrap"))
    );
    b.write(b"cfg.txt", b"x");
    b.link = BOOT_WIDE;
    assert_eq!(
        b.rx(&h("02 00 00 00 00 00", b"cfg.txt")),
        Some(h(
            "05 00 08 80 00 00",
            b"only firmware is written in Bootstrap"
        ))
    );
    b.write(b"FW.EFW", &file(21));
    assert_eq!(b.read(b"cfg.txt"), b"x");
    b.link = WIDE;
    assert_eq!(b.read(b"FW.EFW"), file(21));
    let mut plain = Bench::new(FoeConfig::default());
    plain.write(b"fw.efw", b"y");
    plain.link = BOOT;
    plain.write(b"fw.efw", b"z");
}

/// With 10 ms to program a packet: a Data packet 4 ms after the last is answered with Busy, Done 4
/// and Entire 10 (`06 00 04 00 0A 00`) and not taken; sent again 10 ms after, it is taken.
#[test]
fn a_packet_during_programming_is_answered_busy() {
    let mut b = Bench::new(FoeConfig {
        packet_time: Duration::from_millis(10),
        ..FoeConfig::default()
    });
    b.rx(&h("02 00 00 00 00 00", b"slow"));
    let t0 = b.now;
    b.rx(&h("03 00 01 00 00 00", &[1; 20]));
    b.now = t0 + Duration::from_millis(4);
    assert_eq!(
        b.rx(&h("03 00 02 00 00 00", &[2; 20])),
        Some(h("06 00 04 00 0A 00", &[]))
    );
    b.now = t0 + Duration::from_millis(10);
    assert_eq!(
        b.rx(&h("03 00 02 00 00 00", &[2; 20])),
        Some(h("04 00 02 00 00 00", &[]))
    );
    b.now += Duration::from_millis(20);
    assert_eq!(
        b.rx(&h("03 00 03 00 00 00", &[3])),
        Some(h("04 00 03 00 00 00", &[]))
    );
    assert_eq!(b.server.store().get(b"slow").map(|f| f.len()), Some(41));
}

/// OpCode 7 is `05 00 00 80 00 00 "OpCode 7"`; a Busy from the master with no read is 0x8000; a
/// Busy during a read brings the last packet again; a frame shorter than 6 bytes gets nothing.
#[test]
fn unknown_op_codes_and_the_masters_busy() {
    let mut b = Bench::new(FoeConfig::default());
    assert_eq!(
        b.rx(&h("07 00 00 00 00 00", &[])),
        Some(h("05 00 00 80 00 00", b"OpCode 7"))
    );
    assert_eq!(
        b.rx(&h("06 00 00 00 00 00", &[])),
        Some(h("05 00 00 80 00 00", b"Busy with no read"))
    );
    b.write(b"r", &file(30));
    let first = b.rx(&h("01 00 00 00 00 00", b"r"));
    assert_eq!(b.rx(&h("06 00 00 00 00 00", &[])), first);
    assert_eq!(
        b.rx(&h("04 00 01 00 00 00", &[])),
        Some(h("03 00 02 00 00 00", &file(30)[20..]))
    );
    assert_eq!(
        b.rx(&h("06 00 00 00 00 00", &[])),
        Some(h("03 00 02 00 00 00", &file(30)[20..]))
    );
    assert_eq!(b.rx(&[0x04, 0x00, 0x02]), None);
    assert!(b.server.is_busy());
}

/// An Error from the master ends the transfer without an answer and keeps nothing of a write; a
/// new request ends the one in progress the same way.
#[test]
fn the_master_ends_a_transfer() {
    let mut b = Bench::new(FoeConfig::default());
    b.rx(&h("02 00 00 00 00 00", b"w"));
    b.rx(&h("03 00 01 00 00 00", &[1; 20]));
    assert_eq!(b.rx(&h("05 00 00 80 00 00", b"stop")), None);
    assert!(!b.server.is_busy());
    assert_eq!(
        b.events(),
        [FoeEvent::Aborted {
            name: b"w".to_vec(),
            code: FoeErrorCode::NotDefined
        }]
    );
    b.rx(&h("02 00 00 00 00 00", b"w"));
    b.rx(&h("03 00 01 00 00 00", &[1; 20]));
    b.write(b"v", b"v");
    assert!(b.server.store().get(b"w").is_none());
    assert_eq!(b.written(), [(b"v".to_vec(), b"v".to_vec())]);
}

/// A transfer without a request for 10 s ends (not 1 ms before), and what it wrote is dropped;
/// `reset` ends one at once; the files stay.
#[test]
fn a_transfer_left_alone_times_out() {
    let mut b = Bench::new(FoeConfig::default());
    b.write(b"kept", b"k");
    assert_eq!(b.server.poll_timeout(), None);
    b.rx(&h("02 00 00 00 00 00", b"w"));
    b.rx(&h("03 00 01 00 00 00", &[1; 20]));
    let deadline = b.now + Duration::from_secs(10);
    assert_eq!(b.server.poll_timeout(), Some(deadline));
    b.server.handle_timeout(deadline - Duration::from_millis(1));
    assert!(b.server.is_busy());
    b.server.handle_timeout(deadline);
    assert!(!b.server.is_busy());
    assert_eq!(b.server.poll_timeout(), None);
    assert_eq!(
        b.events().last(),
        Some(&FoeEvent::TimedOut {
            name: b"w".to_vec()
        })
    );
    b.rx(&h("02 00 00 00 00 00", b"w"));
    b.server.reset();
    assert!(!b.server.is_busy());
    assert_eq!(b.read(b"kept"), b"k");
}

/// `*` stands for any bytes (none too), the rest matches ASCII case ignored.
#[test]
fn firmware_name_patterns() {
    for (pattern, name, yes) in [
        ("*.efw", &b"a.efw"[..], true),
        ("*.efw", b"A.EFW", true),
        ("*.efw", b".efw", true),
        ("*.efw", b"a.efw.bak", false),
        ("fw*", b"fw", true),
        ("fw*.bin", b"fw-1.2.bin", true),
        ("fw*.bin", b"fw-1.2.bix", false),
        ("*", b"", true),
        ("a*b*c", b"aXbYbc", true),
        ("a*b*c", b"acb", false),
        ("abc", b"ab", false),
    ] {
        assert_eq!(matches(pattern, name), yes, "{pattern} {name:?}");
    }
}

/// A host that does not drain the server gets the answers in order, the last 16 at most; the events
/// likewise: the oldest go.
#[test]
fn undrained_answers_and_events_keep_the_last_sixteen() {
    let mut b = Bench::new(FoeConfig::default());
    for k in 0..17u8 {
        b.now += Duration::from_millis(1);
        b.server
            .handle_mailbox(b.now, &h("01 00 00 00 00 00", &[b'a' + k]), PRE_OP);
    }
    let answers: Vec<Vec<u8>> = std::iter::from_fn(|| b.server.poll_transmit()).collect();
    assert_eq!(answers.len(), 16);
    assert_eq!(answers[0], h("05 00 01 80 00 00", b"no such file"));
    let events = b.events();
    assert_eq!(events.len(), 16);
    assert_eq!(
        events[0],
        FoeEvent::Refused {
            name: b"b".to_vec(),
            code: FoeErrorCode::NotFound
        }
    );
    assert_eq!(b.server.config(), &FoeConfig::default());
    assert_eq!(
        (b.server.store().max_file(), b.server.store().max_store()),
        (4 << 20, 16 << 20)
    );
}

/// An Error's text is cut to what the read mailbox holds beside the headers: 34 bytes (the
/// smallest a master may set: ESI `MinSize`) leave 22. A read mailbox of 12 bytes holds no file:
/// a Read is 0x8000 with no text; one made shorter during a read ends it with 0x8000 (text cut to
/// the new length), whether the master acknowledges or is busy.
#[test]
fn error_texts_fit_the_read_mailbox() {
    let mut b = Bench::new(FoeConfig::default());
    b.link = Link {
        boot: false,
        write_len: 34,
        read_len: 34,
    };
    assert_eq!(
        b.rx(&h("02 00 00 00 00 00", &[])),
        Some(h("05 00 04 80 00 00", b"a file name of 0 bytes"))
    );
    b.link = WIDE;
    b.write(b"f", &file(200));
    b.link.read_len = 12;
    assert_eq!(
        b.rx(&h("01 00 00 00 00 00", b"f")),
        Some(h("05 00 00 80 00 00", &[]))
    );
    for (shorter, frame) in [(20, "04 00 01 00 00 00"), (14, "06 00 00 00 00 00")] {
        b.link.read_len = 128;
        assert_eq!(b.rx(&h("01 00 00 00 00 00", b"f")).unwrap().len(), 122);
        b.link.read_len = shorter;
        let mut text = b"the read mailbox is shorter than at the start".to_vec();
        text.truncate(shorter - 12);
        assert_eq!(b.rx(&h(frame, &[])), Some(h("05 00 00 80 00 00", &text)));
        assert!(!b.server.is_busy());
    }
}

proptest::proptest! {
    /// Random frames (every OpCode and beyond, packet numbers around the right ones, data of any
    /// length up to beyond the mailbox, names from three letters, Bootstrap or not, mailboxes of
    /// 13 to 40 bytes, time passing) never panic; every answer fits the read mailbox (its length
    /// less the 6 bytes of its header); the files never take more than the store's 500 bytes, none
    /// more than 300.
    #[test]
    fn random_frames_stay_within_the_mailbox_and_the_limits(
        ops in proptest::collection::vec(
            (0u8..8, 0u32..4, 0usize..40, 0u64..20, proptest::bool::ANY, 13usize..40),
            0..300,
        )
    ) {
        let mut b = Bench::new(FoeConfig {
            max_file: 300,
            max_store: 500,
            boot: true,
            packet_time: Duration::from_millis(5),
            ..FoeConfig::default()
        });
        for (op, packet, len, step, boot, mailbox) in ops {
            let p = packet.to_le_bytes();
            let mut frame = vec![op, 0, p[0], p[1], p[2], p[3]];
            frame.extend((0..len).map(|k| b"ab."[k % 3]));
            b.now += Duration::from_millis(step);
            let link = Link { boot, write_len: mailbox, read_len: mailbox };
            b.server.handle_mailbox(b.now, &frame, link);
            while let Some(answer) = b.server.poll_transmit() {
                proptest::prop_assert!(answer.len() <= mailbox - 6, "{answer:02X?}");
            }
            while b.server.poll_event().is_some() {}
            while let Some((_, data)) = b.server.poll_written() {
                proptest::prop_assert!(data.len() <= 300);
            }
            proptest::prop_assert!(b.server.store().used() <= 500);
        }
    }
}

/// The server gives back the configuration it was made with, every field of it.
#[test]
fn the_server_keeps_its_configuration() {
    let config = FoeConfig {
        max_file: 100,
        max_store: 300,
        password: Some(0x1234_5678),
        boot: true,
        firmware: vec!["*.bin".to_string()],
        packet_time: Duration::from_millis(3),
        timeout: Duration::from_secs(2),
    };
    let b = Bench::new(config);
    assert_eq!(
        b.server.config(),
        &FoeConfig {
            max_file: 100,
            max_store: 300,
            password: Some(0x1234_5678),
            boot: true,
            firmware: vec!["*.bin".to_string()],
            packet_time: Duration::from_millis(3),
            timeout: Duration::from_secs(2),
        }
    );
    assert_eq!(
        (b.server.store().max_file(), b.server.store().max_store()),
        (100, 300)
    );
}
