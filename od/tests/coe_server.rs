//! The CoE SDO server against golden mailboxes written from the layouts of ETG.1000.6 §5.6 (mailbox
//! header, CoE header, SDO request and response frames) and ETG.1000.4 (mailbox error reply): each
//! transfer mode, complete access, every EtherCAT abort code, toggle, unknown and block commands, mailbox
//! repeat, the transfer timeout, and the dictionary as each transfer leaves it.
//!
//! Mailbox bytes are written as hexadecimal with `|` between the mailbox header (length, address,
//! channel/priority, type/counter), the CoE header (`00 20` SDO request, `00 30` SDO response) and the
//! SDO bytes.

use std::time::{Duration, Instant};

use od::coe::CoeServer;
use od::sdo::{Address, ServerConfig, ServerEvent};
use od::{AbortCode, AccessType, DataType, Dictionary, Object, ObjectKind, SubObject, Value};

/// Bytes from hexadecimal, `"0A 00 | 00 20 | 2B 10"`; `|` is only for the eye.
fn h(text: &str) -> Vec<u8> {
    text.split_whitespace()
        .filter(|t| *t != "|")
        .map(|b| u8::from_str_radix(b, 16).unwrap())
        .collect()
}

/// Bytes from hexadecimal followed by `data`.
fn hd(text: &str, data: &[u8]) -> Vec<u8> {
    let mut out = h(text);
    out.extend_from_slice(data);
    out
}

fn mux(index: u16, sub: u8) -> Address {
    Address::new(index, sub)
}

/// `n` bytes of visible text: A–Z over and over.
fn text(n: usize) -> Vec<u8> {
    (0..n).map(|i| b'A' + (i % 26) as u8).collect()
}

fn u8_entry(access: AccessType, value: u64) -> SubObject {
    SubObject::new("Number of entries", DataType::Unsigned8, access)
        .with_default(Value::Uint(value))
}

/// The dictionary the tests serve: a few objects shaped like the SMD's.
fn dictionary() -> Dictionary {
    let mut d = Dictionary::new();
    d.insert(Object::var(
        0x1000,
        SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro)
            .with_default(Value::Uint(0x0002_0192)),
    ));
    d.insert(Object::var(
        0x1008,
        SubObject::new("Device name", DataType::VisibleString, AccessType::Const)
            .with_default(Value::String("SMD23K-B".into())),
    ));
    let mut rx_map = Object::structured(0x1600, "RxPDO 1 mapping", ObjectKind::Record)
        .with_sub(0, u8_entry(AccessType::Rw, 2));
    for (sub, entry) in [(1u8, 0x7000_0110u64), (2, 0x7000_0210), (3, 0), (4, 0)] {
        rx_map = rx_map.with_sub(
            sub,
            SubObject::new("Entry", DataType::Unsigned32, AccessType::Rw)
                .with_default(Value::Uint(entry)),
        );
    }
    d.insert(rx_map);
    let mut assign = Object::structured(0x1C12, "RxPDO assign", ObjectKind::Array)
        .with_sub(0, u8_entry(AccessType::Rw, 2));
    for (sub, pdo) in [(1u8, 0x1600u64), (2, 0x1601), (3, 0)] {
        assign = assign.with_sub(
            sub,
            SubObject::new("PDO", DataType::Unsigned16, AccessType::Rw)
                .with_default(Value::Uint(pdo)),
        );
    }
    d.insert(assign);
    d.insert(Object::var(
        0x2000,
        SubObject::new("Text", DataType::VisibleString, AccessType::Rw).with_bit_size(8 * 256),
    ));
    d.insert(Object::var(
        0x2003,
        SubObject::new("Program", DataType::Domain, AccessType::Rw),
    ));
    d.insert(
        Object::structured(0x6000, "Inputs", ObjectKind::Record)
            .with_sub(0, u8_entry(AccessType::Ro, 1))
            .with_sub(
                1,
                SubObject::new("STATUS_word0", DataType::Unsigned16, AccessType::Ro),
            ),
    );
    d.insert(
        Object::structured(0x7000, "Outputs", ObjectKind::Record)
            .with_sub(0, u8_entry(AccessType::Ro, 2))
            .with_sub(
                1,
                SubObject::new("CMD_word0", DataType::Unsigned16, AccessType::Rw),
            )
            .with_sub(
                2,
                SubObject::new("CMD_word1", DataType::Unsigned16, AccessType::Rw),
            ),
    );
    d.insert(
        Object::structured(0x8010, "Configuration", ObjectKind::Record)
            .with_sub(0, u8_entry(AccessType::Ro, 4))
            .with_sub(
                1,
                SubObject::new("Control_Word", DataType::Unsigned16, AccessType::Rw),
            )
            .with_sub(
                2,
                SubObject::new("Config", DataType::Unsigned16, AccessType::Rw),
            )
            .with_sub(
                3,
                SubObject::new("Starting_Speed", DataType::Unsigned32, AccessType::Rw),
            )
            .with_sub(
                4,
                SubObject::new("Motor_Resolution", DataType::Unsigned16, AccessType::Rw)
                    .with_default(Value::Uint(200))
                    .with_limits(Some(Value::Uint(200)), Some(Value::Uint(32_767))),
            ),
    );
    d
}

/// A CoE server, its dictionary and a simulated clock.
struct Bench {
    server: CoeServer,
    dict: Dictionary,
    now: Instant,
}

impl Bench {
    fn new() -> Bench {
        Bench::with(CoeServer::new(ServerConfig::default(), 128))
    }

    fn with(server: CoeServer) -> Bench {
        Bench {
            server,
            dict: dictionary(),
            now: Instant::now(),
        }
    }

    /// Hands the server a mailbox 1 ms after the last and takes every mailbox it sends.
    fn rx(&mut self, mailbox: &[u8]) -> Vec<Vec<u8>> {
        self.now += Duration::from_millis(1);
        self.server
            .handle_mailbox(self.now, mailbox, &mut self.dict);
        self.drain()
    }

    fn drain(&mut self) -> Vec<Vec<u8>> {
        std::iter::from_fn(|| self.server.poll_transmit()).collect()
    }

    fn events(&mut self) -> Vec<ServerEvent> {
        std::iter::from_fn(|| self.server.poll_event()).collect()
    }

    fn value(&self, index: u16, sub: u8) -> Vec<u8> {
        self.dict.entry(index, sub).unwrap().value.clone()
    }
}

/// Asserts that the request mailbox is answered with exactly one mailbox, `answer`.
macro_rules! exchange {
    ($bench:expr, $request:expr => $answer:expr) => {
        assert_eq!(
            $bench.rx(&$request),
            vec![$answer],
            "answer to {:02X?}",
            $request
        )
    };
}

fn aborted(index: u16, sub: u8, code: AbortCode) -> ServerEvent {
    ServerEvent::Aborted {
        mux: mux(index, sub),
        code,
        by_client: false,
    }
}

// ---------------------------------------------------------------------------------------------------
// Expedited transfer (ETG.1000.6 §5.6.2.1, §5.6.2.4)

#[test]
fn expedited_download_of_a_uint() {
    let mut b = Bench::new();
    // Length 10, address 0, channel 0, priority 0, type 3 (CoE), counter 1; SDO request; ccs 1, n 2,
    // e 1, s 1 (0x2B): 0x03E8 = 1000 to 0x8010:04.
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 2B 10 80 04 E8 03 00 00")
        => h("0A 00 00 00 00 13 | 00 30 | 60 10 80 04 00 00 00 00"));
    assert_eq!(b.value(0x8010, 4), [0xE8, 0x03]);
    assert_eq!(
        b.events(),
        [ServerEvent::Downloaded {
            mux: mux(0x8010, 4)
        }]
    );
    assert!(!b.server.is_busy());
    assert_eq!(b.server.poll_timeout(), None);
}

#[test]
fn expedited_upload() {
    let mut b = Bench::new();
    // ccs 2 (0x40) for 0x8010:04; answer scs 2, n 2, e 1, s 1 (0x4B) with 200 = 0x00C8.
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 40 10 80 04 00 00 00 00")
        => h("0A 00 00 00 00 13 | 00 30 | 4B 10 80 04 C8 00 00 00"));
    // Four bytes: n 0 (0x43).
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | 40 00 10 00 00 00 00 00")
        => h("0A 00 00 00 00 23 | 00 30 | 43 00 10 00 92 01 02 00"));
    assert_eq!(
        b.events(),
        [
            ServerEvent::Uploaded {
                mux: mux(0x8010, 4)
            },
            ServerEvent::Uploaded {
                mux: mux(0x1000, 0)
            }
        ]
    );
}

// ---------------------------------------------------------------------------------------------------
// Normal and segmented upload (ETG.1000.6 §5.6.2.5, §5.6.2.6)

#[test]
fn normal_upload_of_a_string_that_fits() {
    let mut b = Bench::new();
    // Answer: length 18 = CoE header + 8 + 8 data bytes; scs 2, s 1 (0x41), complete size 8, then the
    // data from byte 8 of the SDO part.
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 40 08 10 00 00 00 00 00")
        => hd("12 00 00 00 00 13 | 00 30 | 41 08 10 00 08 00 00 00", b"SMD23K-B"));
    assert_eq!(
        b.events(),
        [ServerEvent::Uploaded {
            mux: mux(0x1008, 0)
        }]
    );
    assert!(!b.server.is_busy());
}

#[test]
fn normal_upload_that_does_not_fit_goes_on_in_segments() {
    let mut b = Bench::new();
    let value = text(234);
    b.dict.write(0x2000, 0, &value).unwrap();
    // 234 = 0xEA bytes; a 128-byte mailbox takes 128 − 16 = 112 of them in the upload response
    // (length 2 + 8 + 112 = 122).
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 40 00 20 00 00 00 00 00")
        => hd("7A 00 00 00 00 13 | 00 30 | 41 00 20 00 EA 00 00 00", &value[..112]));
    assert!(b.server.is_busy());
    assert_eq!(b.events(), []);
    // Upload segment request, toggle 0 (0x60): 128 − 9 = 119 bytes, t 0, n 0, c 0 (0x00).
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | 60 00 00 00 00 00 00 00")
        => hd("7A 00 00 00 00 23 | 00 30 | 00", &value[112..231]));
    assert_eq!(b.events(), []);
    // Toggle 1 (0x70): the last 3 bytes, t 1, n 4, c 1 (0x19), padded to seven.
    exchange!(b, h("0A 00 00 00 00 33 | 00 20 | 70 00 00 00 00 00 00 00")
        => hd("0A 00 00 00 00 33 | 00 30 | 19", &[value[231], value[232], value[233], 0, 0, 0, 0]));
    assert_eq!(
        b.events(),
        [ServerEvent::Uploaded {
            mux: mux(0x2000, 0)
        }]
    );
    assert!(!b.server.is_busy());
    assert_eq!(b.server.poll_timeout(), None);
}

#[test]
fn segments_of_a_small_mailbox_take_part_of_a_can_segment() {
    // A 40-byte mailbox: 24 bytes in the upload response, 31 per segment; neither is a multiple of the
    // seven bytes of a CiA 301 segment, so part of one waits for the next response.
    let mut b = Bench::with(CoeServer::new(ServerConfig::default(), 40));
    let value = text(100);
    b.dict.write(0x2000, 0, &value).unwrap();
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 40 00 20 00 00 00 00 00")
        => hd("22 00 00 00 00 13 | 00 30 | 41 00 20 00 64 00 00 00", &value[..24]));
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | 60 00 00 00 00 00 00 00")
        => hd("22 00 00 00 00 23 | 00 30 | 00", &value[24..55]));
    exchange!(b, h("0A 00 00 00 00 33 | 00 20 | 70 00 00 00 00 00 00 00")
        => hd("22 00 00 00 00 33 | 00 30 | 10", &value[55..86]));
    // The last 14 bytes: seven or more, so n 0; c 1 (0x01); length 2 + 1 + 14.
    exchange!(b, h("0A 00 00 00 00 43 | 00 20 | 60 00 00 00 00 00 00 00")
        => hd("11 00 00 00 00 43 | 00 30 | 01", &value[86..]));
    assert_eq!(
        b.events(),
        [ServerEvent::Uploaded {
            mux: mux(0x2000, 0)
        }]
    );
}

#[test]
fn empty_value_is_a_normal_upload_of_size_0() {
    let mut b = Bench::new();
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 40 03 20 00 00 00 00 00")
        => h("0A 00 00 00 00 13 | 00 30 | 41 03 20 00 00 00 00 00"));
    assert!(!b.server.is_busy());
    assert_eq!(
        b.events(),
        [ServerEvent::Uploaded {
            mux: mux(0x2003, 0)
        }]
    );
}

// ---------------------------------------------------------------------------------------------------
// Normal and segmented download (ETG.1000.6 §5.6.2.2, §5.6.2.3)

#[test]
fn normal_download_that_fits() {
    let mut b = Bench::new();
    // ccs 1, s 1 (0x21), complete size 16, the data from byte 8; length 2 + 8 + 16 = 26.
    exchange!(b, hd("1A 00 00 00 00 13 | 00 20 | 21 00 20 00 10 00 00 00", b"Hello, EtherCAT!")
        => h("0A 00 00 00 00 13 | 00 30 | 60 00 20 00 00 00 00 00"));
    assert_eq!(b.value(0x2000, 0), b"Hello, EtherCAT!");
    assert_eq!(
        b.events(),
        [ServerEvent::Downloaded {
            mux: mux(0x2000, 0)
        }]
    );
    assert!(!b.server.is_busy());
}

#[test]
fn normal_download_with_segments() {
    let mut b = Bench::new();
    let data: Vec<u8> = (0..30).collect();
    // Complete size 30, the first 10 bytes in the request.
    exchange!(b, hd("14 00 00 00 00 13 | 00 20 | 21 03 20 00 1E 00 00 00", &data[..10])
        => h("0A 00 00 00 00 13 | 00 30 | 60 03 20 00 00 00 00 00"));
    assert!(b.server.is_busy());
    assert_eq!(b.value(0x2003, 0), []);
    // Download segment, t 0, n 0, c 0 (0x00), 15 bytes: seven in the segment and eight after it.
    exchange!(b, hd("12 00 00 00 00 23 | 00 20 | 00", &data[10..25])
        => h("0A 00 00 00 00 23 | 00 30 | 20 00 00 00 00 00 00 00"));
    assert_eq!(b.value(0x2003, 0), []);
    assert_eq!(b.events(), []);
    // t 1, n 2, c 1 (0x15): the last 5 bytes, padded to seven; answered with t 1 (0x30).
    exchange!(b, hd("0A 00 00 00 00 33 | 00 20 | 15", &[25, 26, 27, 28, 29, 0, 0])
        => h("0A 00 00 00 00 33 | 00 30 | 30 00 00 00 00 00 00 00"));
    assert_eq!(b.value(0x2003, 0), data);
    assert_eq!(
        b.events(),
        [ServerEvent::Downloaded {
            mux: mux(0x2003, 0)
        }]
    );
    assert!(!b.server.is_busy());
}

#[test]
fn a_download_announcing_more_than_the_entry_holds_is_refused_at_once() {
    let mut b = Bench::new();
    // 0x2000 holds 256 bytes; 1000 (0x3E8) are announced: 0x06070012, service 2 (abort request).
    exchange!(b, hd("12 00 00 00 00 13 | 00 20 | 21 00 20 00 E8 03 00 00", b"ABCDEFGH")
        => h("0A 00 00 00 00 13 | 00 20 | 80 00 20 00 12 00 07 06"));
    // Four bytes announced, eight given: the surplus is refused too, nothing written.
    exchange!(b, hd("12 00 00 00 00 23 | 00 20 | 21 00 20 00 04 00 00 00", b"ABCDEFGH")
        => h("0A 00 00 00 00 23 | 00 20 | 80 00 20 00 12 00 07 06"));
    assert_eq!(b.value(0x2000, 0), []);
    // A segment with c = 1 that leaves the value short: 0x06070013.
    exchange!(b, hd("12 00 00 00 00 33 | 00 20 | 21 03 20 00 0A 00 00 00", b"ABCDEFGH")
        => h("0A 00 00 00 00 33 | 00 30 | 60 03 20 00 00 00 00 00"));
    exchange!(b, h("0A 00 00 00 00 43 | 00 20 | 0D 49 00 00 00 00 00 00")
        => h("0A 00 00 00 00 43 | 00 20 | 80 03 20 00 13 00 07 06"));
    assert_eq!(b.value(0x2003, 0), []);
    assert!(!b.server.is_busy());
}

#[test]
fn a_value_refused_by_the_dictionary_is_not_written() {
    let mut b = Bench::new();
    // 100 is below the 200 minimum of 0x8010:04: 0x06090032.
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 2B 10 80 04 64 00 00 00")
        => h("0A 00 00 00 00 13 | 00 20 | 80 10 80 04 32 00 09 06"));
    assert_eq!(b.value(0x8010, 4), [0xC8, 0x00]);
    // A normal download of two bytes to it goes the same way.
    exchange!(b, h("0C 00 00 00 00 23 | 00 20 | 21 10 80 04 02 00 00 00 64 00")
        => h("0A 00 00 00 00 23 | 00 20 | 80 10 80 04 32 00 09 06"));
    exchange!(b, h("0C 00 00 00 00 33 | 00 20 | 21 10 80 04 02 00 00 00 D0 07")
        => h("0A 00 00 00 00 33 | 00 30 | 60 10 80 04 00 00 00 00"));
    assert_eq!(b.value(0x8010, 4), [0xD0, 0x07]);
    // Read-only, missing object, missing sub-index.
    exchange!(b, h("0A 00 00 00 00 43 | 00 20 | 23 00 10 00 00 00 00 00")
        => h("0A 00 00 00 00 43 | 00 20 | 80 00 10 00 02 00 01 06"));
    exchange!(b, h("0A 00 00 00 00 53 | 00 20 | 40 00 30 00 00 00 00 00")
        => h("0A 00 00 00 00 53 | 00 20 | 80 00 30 00 00 00 02 06"));
    exchange!(b, h("0A 00 00 00 00 63 | 00 20 | 40 10 80 09 00 00 00 00")
        => h("0A 00 00 00 00 63 | 00 20 | 80 10 80 09 11 00 09 06"));
}

// ---------------------------------------------------------------------------------------------------
// Complete access (ETG.1000.6 §5.6.2.1.2, §5.6.2.4.2)

#[test]
fn complete_access_upload_from_sub_index_0() {
    let mut b = Bench::new();
    // ccs 2 with the complete-access bit (0x50). Sub-index 0 (2) padded to 16 bits, then 0x1600 and
    // 0x1601: six bytes, a normal response with the bit (0x51).
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 50 12 1C 00 00 00 00 00")
        => h("10 00 00 00 00 13 | 00 30 | 51 12 1C 00 06 00 00 00 | 02 00 00 16 01 16"));
    assert_eq!(
        b.events(),
        [ServerEvent::Uploaded {
            mux: mux(0x1C12, 0)
        }]
    );
}

#[test]
fn complete_access_upload_from_sub_index_1() {
    let mut b = Bench::new();
    // The two entries only: four bytes, expedited (0x43) with the bit (0x53).
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 50 12 1C 01 00 00 00 00")
        => h("0A 00 00 00 00 13 | 00 30 | 53 12 1C 01 00 16 01 16"));
    // 0x1600 from sub-index 1: two UNSIGNED32, eight bytes, normal.
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | 50 00 16 01 00 00 00 00")
        => h("12 00 00 00 00 23 | 00 30 | 51 00 16 01 08 00 00 00 | 10 01 00 70 10 02 00 70"));
}

#[test]
fn complete_access_download() {
    let mut b = Bench::new();
    // ccs 1, s 1 with the bit (0x31): three entries, 0x1610..0x1612, from sub-index 0.
    exchange!(b, h("12 00 00 00 00 13 | 00 20 | 31 12 1C 00 08 00 00 00 | 03 00 10 16 11 16 12 16")
        => h("0A 00 00 00 00 13 | 00 30 | 70 12 1C 00 00 00 00 00"));
    assert_eq!(b.value(0x1C12, 0), [3]);
    assert_eq!(b.value(0x1C12, 1), [0x10, 0x16]);
    assert_eq!(b.value(0x1C12, 2), [0x11, 0x16]);
    assert_eq!(b.value(0x1C12, 3), [0x12, 0x16]);
    assert_eq!(
        b.events(),
        [ServerEvent::Downloaded {
            mux: mux(0x1C12, 0)
        }]
    );
    // Expedited, two bytes, with the bit (0x3B): 0x1600 from sub-index 0 with no entries: sets
    // sub-index 0 to 0 and leaves the entries as they were.
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | 3B 00 16 00 00 00 00 00")
        => h("0A 00 00 00 00 23 | 00 30 | 70 00 16 00 00 00 00 00"));
    assert_eq!(b.value(0x1600, 0), [0]);
    assert_eq!(b.value(0x1600, 1), [0x10, 0x01, 0x00, 0x70]);
}

#[test]
fn complete_access_download_with_segments() {
    // A download request with no data: every byte comes in a segment.
    let mut b = Bench::new();
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 31 00 16 00 0A 00 00 00")
        => h("0A 00 00 00 00 13 | 00 30 | 70 00 16 00 00 00 00 00"));
    // Two entries: 0x70000310, 0x70000410; sub-index 0 written last.
    exchange!(b, h("0D 00 00 00 00 23 | 00 20 | 01 02 00 10 03 00 70 10 04 00 70")
        => h("0A 00 00 00 00 23 | 00 30 | 20 00 00 00 00 00 00 00"));
    assert_eq!(b.value(0x1600, 0), [2]);
    assert_eq!(b.value(0x1600, 1), [0x10, 0x03, 0x00, 0x70]);
    assert_eq!(b.value(0x1600, 2), [0x10, 0x04, 0x00, 0x70]);
}

#[test]
fn complete_access_refusals() {
    let mut b = Bench::new();
    let before = b.dict.clone();
    // Start at sub-index 2: 0x06010000 (unsupported access).
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 50 12 1C 02 00 00 00 00")
        => h("0A 00 00 00 00 13 | 00 20 | 80 12 1C 02 00 00 01 06"));
    // A VAR object: 0x06010004.
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | 50 00 10 00 00 00 00 00")
        => h("0A 00 00 00 00 23 | 00 20 | 80 00 10 00 04 00 01 06"));
    exchange!(b, h("0A 00 00 00 00 33 | 00 20 | 33 00 20 00 41 42 43 44")
        => h("0A 00 00 00 00 33 | 00 20 | 80 00 20 00 04 00 01 06"));
    // A complete download announcing more than the object holds (8 bytes): 0x06070012.
    exchange!(b, h("0A 00 00 00 00 43 | 00 20 | 31 12 1C 00 09 00 00 00")
        => h("0A 00 00 00 00 43 | 00 20 | 80 12 1C 00 12 00 07 06"));
    // An object with no entry that may be written.
    exchange!(b, h("0A 00 00 00 00 53 | 00 20 | 33 00 60 00 01 00 00 00")
        => h("0A 00 00 00 00 53 | 00 20 | 80 00 60 00 02 00 01 06"));
    assert_eq!(b.dict, before);
}

// ---------------------------------------------------------------------------------------------------
// EtherCAT abort codes (ETG.1000.6 table "SDO abort codes")

#[test]
fn abort_0x06010003_sub_index_0_must_be_0_for_writing() {
    let mut b = Bench::new();
    // 0x1600:00 is 2: writing 0x1600:01 (0x70000120) is refused.
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 23 00 16 01 20 01 00 70")
        => h("0A 00 00 00 00 13 | 00 20 | 80 00 16 01 03 00 01 06"));
    // So is a complete download from sub-index 1 of 0x1C12, and a normal download to 0x1C12:03.
    exchange!(b, h("0E 00 00 00 00 23 | 00 20 | 31 12 1C 01 04 00 00 00 | 00 16 01 16")
        => h("0A 00 00 00 00 23 | 00 20 | 80 12 1C 01 03 00 01 06"));
    exchange!(b, h("0C 00 00 00 00 33 | 00 20 | 21 12 1C 03 02 00 00 00 | 02 16")
        => h("0A 00 00 00 00 33 | 00 20 | 80 12 1C 03 03 00 01 06"));
    assert_eq!(b.value(0x1600, 1), [0x10, 0x01, 0x00, 0x70]);
    // The PDO configuration procedure: sub-index 0 to 0, the entry, sub-index 0 back to 2.
    exchange!(b, h("0A 00 00 00 00 43 | 00 20 | 2F 00 16 00 00 00 00 00")
        => h("0A 00 00 00 00 43 | 00 30 | 60 00 16 00 00 00 00 00"));
    exchange!(b, h("0A 00 00 00 00 53 | 00 20 | 23 00 16 01 20 01 00 70")
        => h("0A 00 00 00 00 53 | 00 30 | 60 00 16 01 00 00 00 00"));
    exchange!(b, h("0A 00 00 00 00 63 | 00 20 | 2F 00 16 00 02 00 00 00")
        => h("0A 00 00 00 00 63 | 00 30 | 60 00 16 00 00 00 00 00"));
    assert_eq!(b.value(0x1600, 1), [0x20, 0x01, 0x00, 0x70]);
    assert_eq!(b.value(0x1600, 0), [2]);
}

#[test]
fn abort_0x06010004_complete_access_of_a_var() {
    let mut b = Bench::new();
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 50 08 10 00 00 00 00 00")
        => h("0A 00 00 00 00 13 | 00 20 | 80 08 10 00 04 00 01 06"));
    assert_eq!(
        b.events(),
        [aborted(0x1008, 0, AbortCode::CompleteAccessUnsupported)]
    );
}

#[test]
fn abort_0x06010005_without_segmented_transfer() {
    let mut b =
        Bench::with(CoeServer::new(ServerConfig::default(), 128).with_segmented_transfer(false));
    let value = text(113);
    b.dict.write(0x2000, 0, &value).unwrap();
    // 113 bytes do not fit the 112 a 128-byte mailbox holds.
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 40 00 20 00 00 00 00 00")
        => h("0A 00 00 00 00 13 | 00 20 | 80 00 20 00 05 00 01 06"));
    assert_eq!(b.events(), [aborted(0x2000, 0, AbortCode::ExceedsMailbox)]);
    assert!(!b.server.is_busy());
    // 112 do.
    b.dict.write(0x2000, 0, &value[..112]).unwrap();
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | 40 00 20 00 00 00 00 00")
        => hd("7A 00 00 00 00 23 | 00 30 | 41 00 20 00 70 00 00 00", &value[..112]));
    // A download whose request does not hold all its data.
    exchange!(b, hd("12 00 00 00 00 33 | 00 20 | 21 03 20 00 20 00 00 00", b"ABCDEFGH")
        => h("0A 00 00 00 00 33 | 00 20 | 80 03 20 00 05 00 01 06"));
    assert_eq!(b.value(0x2003, 0), []);
}

#[test]
fn abort_0x06010006_entry_mapped_to_an_rxpdo() {
    let mut b = Bench::new();
    b.server.set_rxpdo_mapped([mux(0x7000, 1), mux(0x7000, 2)]);
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 2B 00 70 01 34 12 00 00")
        => h("0A 00 00 00 00 13 | 00 20 | 80 00 70 01 06 00 01 06"));
    assert_eq!(b.value(0x7000, 1), [0, 0]);
    // Reading is not blocked.
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | 40 00 70 01 00 00 00 00")
        => h("0A 00 00 00 00 23 | 00 30 | 4B 00 70 01 00 00 00 00"));
    // Back in PreOp nothing is blocked.
    b.server.set_rxpdo_mapped([]);
    exchange!(b, h("0A 00 00 00 00 33 | 00 20 | 2B 00 70 01 34 12 00 00")
        => h("0A 00 00 00 00 33 | 00 30 | 60 00 70 01 00 00 00 00"));
    assert_eq!(b.value(0x7000, 1), [0x34, 0x12]);
}

// ---------------------------------------------------------------------------------------------------
// Protocol errors

#[test]
fn toggle_bit_not_alternated() {
    let mut b = Bench::new();
    b.dict.write(0x2000, 0, &text(200)).unwrap();
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 40 00 20 00 00 00 00 00")
        => hd("7A 00 00 00 00 13 | 00 30 | 41 00 20 00 C8 00 00 00", &text(112)));
    // The first segment request must carry toggle 0: 0x05030000.
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | 70 00 00 00 00 00 00 00")
        => h("0A 00 00 00 00 23 | 00 20 | 80 00 20 00 00 00 03 05"));
    assert!(!b.server.is_busy());
    assert_eq!(b.events(), [aborted(0x2000, 0, AbortCode::ToggleBit)]);

    // In a download: nothing is written.
    exchange!(b, hd("12 00 00 00 00 33 | 00 20 | 21 03 20 00 10 00 00 00", b"ABCDEFGH")
        => h("0A 00 00 00 00 33 | 00 30 | 60 03 20 00 00 00 00 00"));
    exchange!(b, hd("0B 00 00 00 00 43 | 00 20 | 00", b"IJKLMNOP")
        => h("0A 00 00 00 00 43 | 00 30 | 20 00 00 00 00 00 00 00"));
    exchange!(b, hd("0A 00 00 00 00 53 | 00 20 | 00", b"QRSTUVW")
        => h("0A 00 00 00 00 53 | 00 20 | 80 03 20 00 00 00 03 05"));
    assert_eq!(b.value(0x2003, 0), []);
    assert!(!b.server.is_busy());
}

#[test]
fn unknown_command_specifier() {
    let mut b = Bench::new();
    // ccs 7 (0xE0): 0x05040001 about bytes 1–3.
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | E0 00 20 00 00 00 00 00")
        => h("0A 00 00 00 00 13 | 00 20 | 80 00 20 00 01 00 04 05"));
    // During a transfer: about the transfer, which ends.
    b.dict.write(0x2000, 0, &text(200)).unwrap();
    assert_eq!(
        b.rx(&h("0A 00 00 00 00 23 | 00 20 | 40 00 20 00 00 00 00 00"))
            .len(),
        1
    );
    exchange!(b, h("0A 00 00 00 00 33 | 00 20 | E1 12 34 56 00 00 00 00")
        => h("0A 00 00 00 00 33 | 00 20 | 80 00 20 00 01 00 04 05"));
    assert!(!b.server.is_busy());
    // A segment while no transfer runs, and a download segment during an upload.
    exchange!(b, h("0A 00 00 00 00 43 | 00 20 | 60 00 00 00 00 00 00 00")
        => h("0A 00 00 00 00 43 | 00 20 | 80 00 00 00 01 00 04 05"));
    assert_eq!(
        b.rx(&h("0A 00 00 00 00 53 | 00 20 | 40 00 20 00 00 00 00 00"))
            .len(),
        1
    );
    exchange!(b, h("0A 00 00 00 00 63 | 00 20 | 01 41 42 43 44 45 46 47")
        => h("0A 00 00 00 00 63 | 00 20 | 80 00 20 00 01 00 04 05"));
    assert!(!b.server.is_busy());
}

#[test]
fn block_commands_are_refused() {
    let mut b = Bench::new();
    // Initiate block download (0xC6: ccs 6, cc, s) and block upload (0xA4: ccs 5, cc; blksize 127).
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | C6 00 20 00 10 00 00 00")
        => h("0A 00 00 00 00 13 | 00 20 | 80 00 20 00 01 00 04 05"));
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | A4 08 10 00 7F 00 00 00")
        => h("0A 00 00 00 00 23 | 00 20 | 80 08 10 00 01 00 04 05"));
    // Start block upload (0xA3) with nothing running: about bytes 1–3.
    exchange!(b, h("0A 00 00 00 00 33 | 00 20 | A3 00 00 00 00 00 00 00")
        => h("0A 00 00 00 00 33 | 00 20 | 80 00 00 00 01 00 04 05"));
    assert_eq!(
        b.events(),
        [
            aborted(0x2000, 0, AbortCode::InvalidCommand),
            aborted(0x1008, 0, AbortCode::InvalidCommand),
            aborted(0x0000, 0, AbortCode::InvalidCommand),
        ]
    );
}

#[test]
fn abort_from_the_master_ends_the_transfer_silently() {
    let mut b = Bench::new();
    exchange!(b, hd("12 00 00 00 00 13 | 00 20 | 21 03 20 00 10 00 00 00", b"ABCDEFGH")
        => h("0A 00 00 00 00 13 | 00 30 | 60 03 20 00 00 00 00 00"));
    b.events();
    assert_eq!(
        b.rx(&h("0A 00 00 00 00 23 | 00 20 | 80 03 20 00 00 00 00 08")),
        Vec::<Vec<u8>>::new()
    );
    assert_eq!(
        b.events(),
        [ServerEvent::Aborted {
            mux: mux(0x2003, 0),
            code: AbortCode::General,
            by_client: true
        }]
    );
    assert!(!b.server.is_busy());
    assert_eq!(b.value(0x2003, 0), []);
}

#[test]
fn a_new_request_supersedes_the_transfer() {
    let mut b = Bench::new();
    b.dict.write(0x2000, 0, &text(200)).unwrap();
    assert_eq!(
        b.rx(&h("0A 00 00 00 00 13 | 00 20 | 40 00 20 00 00 00 00 00"))
            .len(),
        1
    );
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | 40 00 10 00 00 00 00 00")
        => h("0A 00 00 00 00 23 | 00 30 | 43 00 10 00 92 01 02 00"));
    assert_eq!(
        b.events(),
        [
            ServerEvent::Superseded {
                mux: mux(0x2000, 0)
            },
            ServerEvent::Uploaded {
                mux: mux(0x1000, 0)
            }
        ]
    );
    assert!(!b.server.is_busy());
}

// ---------------------------------------------------------------------------------------------------
// Mailbox counter, repeat and errors (ETG.1000.4)

#[test]
fn mailbox_repeat_answers_again_without_serving_twice() {
    let mut b = Bench::new();
    let request = h("0A 00 00 00 00 13 | 00 20 | 2B 10 80 04 E8 03 00 00");
    let answer = h("0A 00 00 00 00 13 | 00 30 | 60 10 80 04 00 00 00 00");
    exchange!(b, request => answer.clone());
    // The application changes the value; the master, which lost the answer, sends the same mailbox
    // (counter 1 again): the same answer, and the value is not written again.
    b.dict.write(0x8010, 4, &[0xF4, 0x01]).unwrap();
    exchange!(b, request => answer);
    assert_eq!(b.value(0x8010, 4), [0xF4, 0x01]);
    assert_eq!(
        b.events(),
        [ServerEvent::Downloaded {
            mux: mux(0x8010, 4)
        }]
    );
    // The next request, counter 2, is served; the answer carries the slave's next counter, 2.
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | 40 10 80 04 00 00 00 00")
        => h("0A 00 00 00 00 23 | 00 30 | 4B 10 80 04 F4 01 00 00"));
    // A repeated segment request during an upload gets the same segment again.
    b.dict.write(0x2000, 0, &text(200)).unwrap();
    let value = text(200);
    exchange!(b, h("0A 00 00 00 00 33 | 00 20 | 40 00 20 00 00 00 00 00")
        => hd("7A 00 00 00 00 33 | 00 30 | 41 00 20 00 C8 00 00 00", &value[..112]));
    let segment = h("0A 00 00 00 00 43 | 00 20 | 60 00 00 00 00 00 00 00");
    let answer = hd("5B 00 00 00 00 43 | 00 30 | 01", &value[112..]);
    exchange!(b, segment => answer.clone());
    exchange!(b, segment => answer);
    assert!(!b.server.is_busy());
}

#[test]
fn counter_0_is_never_a_repeat_and_counters_cycle() {
    let mut b = Bench::new();
    let mut counters = Vec::new();
    for _ in 0..9 {
        let answers = b.rx(&h("0A 00 00 00 00 03 | 00 20 | 40 00 10 00 00 00 00 00"));
        assert_eq!(answers.len(), 1);
        counters.push(answers[0][5] >> 4);
    }
    assert_eq!(counters, [1, 2, 3, 4, 5, 6, 7, 1, 2]);
    assert_eq!(b.events().len(), 9);
}

#[test]
fn the_answer_carries_the_request_address() {
    let mut b = Bench::new();
    exchange!(b, h("0A 00 E9 03 00 13 | 00 20 | 40 00 10 00 00 00 00 00")
        => h("0A 00 E9 03 00 13 | 00 30 | 43 00 10 00 92 01 02 00"));
}

#[test]
fn padding_after_the_mailbox_is_ignored() {
    let mut b = Bench::new();
    let mut request = h("0A 00 00 00 00 13 | 00 20 | 40 00 10 00 00 00 00 00");
    request.resize(128, 0xA5);
    exchange!(b, request => h("0A 00 00 00 00 13 | 00 30 | 43 00 10 00 92 01 02 00"));
}

#[test]
fn mailboxes_that_are_not_sdo_requests_get_a_mailbox_error_reply() {
    let mut b = Bench::new();
    // Type 2 (EoE): mailbox error reply, type 0, service 1, detail 2 (unsupported protocol).
    exchange!(b, h("04 00 00 00 00 12 | 01 02 03 04") => h("04 00 00 00 00 10 | 01 00 02 00"));
    // CoE, service 5 (RxPDO): detail 4 (service not supported).
    exchange!(b, h("0A 00 00 00 00 23 | 00 50 | 01 00 00 00 00 00 00 00")
        => h("04 00 00 00 00 20 | 01 00 04 00"));
    // CoE SDO request of 4 bytes: detail 6 (size too short).
    exchange!(b, h("06 00 00 00 00 33 | 00 20 | 40 00 10 00") => h("04 00 00 00 00 30 | 01 00 06 00"));
    // A length beyond the bytes given: detail 8 (invalid size).
    exchange!(b, h("40 00 00 00 00 43 | 00 20 | 40 00 10 00 00 00 00 00")
        => h("04 00 00 00 00 40 | 01 00 08 00"));
    // Shorter than a mailbox header: nothing.
    assert_eq!(b.rx(&h("0A 00 00")), Vec::<Vec<u8>>::new());
    assert_eq!(b.events(), []);
}

/// A service of mailbox type 4 beside the CoE server: it answers `01 02` with `AA`, `EE` with the
/// mailbox error 0x0006, anything else with nothing; it counts what it serves.
struct Echo {
    served: usize,
}

impl od::coe::MailboxService for Echo {
    fn takes(&self, t: od::coe::MailboxType) -> bool {
        t == od::coe::MailboxType::Foe
    }

    fn serve(
        &mut self,
        _now: Instant,
        header: &od::coe::MailboxHeader,
        data: &[u8],
    ) -> od::coe::ServiceAnswer {
        self.served += 1;
        assert_eq!(usize::from(header.length), data.len());
        match data {
            [0x01, 0x02] => od::coe::ServiceAnswer::Mailbox(od::coe::MailboxType::Foe, vec![0xAA]),
            [0xEE] => od::coe::ServiceAnswer::MailboxError(0x0006),
            _ => od::coe::ServiceAnswer::Nothing,
        }
    }
}

/// Another protocol through the CoE server's mailbox (ETG.1000.4 §5.6: one counter for every
/// protocol): its answer carries the slave's next counter as a CoE answer would; a repeat of its
/// request (same counter) gets the same answer without being served twice; after it, a CoE
/// request with the counter the last CoE request had is served, not taken for a repeat; a CoE
/// transfer in progress goes on across it; its mailbox error and its silence are the service's;
/// a length beyond the bytes given is 0x0008 without the service; EoE stays unsupported (0x0002).
#[test]
fn another_protocol_shares_the_mailbox_counter_and_repeat() {
    let mut b = Bench::new();
    let mut echo = Echo { served: 0 };
    let rx = |b: &mut Bench, echo: &mut Echo, m: &[u8]| {
        b.now += Duration::from_millis(1);
        b.server.handle_mailbox_with(b.now, m, &mut b.dict, echo);
        b.drain()
    };
    // A normal upload of 200 bytes starts a transfer (counter 1 → answer counter 1).
    b.dict.write(0x2000, 0, &text(200)).unwrap();
    let first = rx(
        &mut b,
        &mut echo,
        &h("0A 00 00 00 00 13 | 00 20 | 40 00 20 00 00 00 00 00"),
    );
    assert_eq!(first.len(), 1);
    assert!(b.server.is_busy());
    // Type 4, counter 2: the service's answer with the slave's counter 2, address kept.
    let request = h("02 00 34 12 00 24 | 01 02");
    assert_eq!(
        rx(&mut b, &mut echo, &request),
        vec![h("01 00 34 12 00 24 | AA")]
    );
    assert_eq!(echo.served, 1);
    // The same counter again: the same answer, not served again.
    assert_eq!(
        rx(&mut b, &mut echo, &request),
        vec![h("01 00 34 12 00 24 | AA")]
    );
    assert_eq!(echo.served, 1);
    // Counters 3 … 7, 1: six more requests of the service, the last with counter 1, the counter of
    // the CoE request above.
    for c in [3u8, 4, 5, 6, 7, 1] {
        let mut m = h("02 00 00 00 00 04 | 01 02");
        m[5] |= c << 4;
        let answer = rx(&mut b, &mut echo, &m);
        assert_eq!(answer.len(), 1);
        assert_eq!(answer[0][5], 0x04 | (c << 4), "the slave counts on");
    }
    assert_eq!(echo.served, 7);
    // A CoE upload segment request with counter 2: served (the transfer went on), not a repeat of
    // the CoE request with counter 2 before: toggle 0, the last 88 bytes of the value (c = 1).
    let segment = rx(
        &mut b,
        &mut echo,
        &h("0A 00 00 00 00 23 | 00 20 | 60 00 00 00 00 00 00 00"),
    );
    assert_eq!(segment.len(), 1);
    assert_eq!(
        &segment[0][..9],
        &h("5B 00 00 00 00 23 00 30 01"),
        "the last upload segment"
    );
    // The service's mailbox error (the slave's counter 3), and its silence (no counter used).
    assert_eq!(
        rx(&mut b, &mut echo, &h("01 00 00 00 00 34 | EE")),
        vec![h("04 00 00 00 00 30 | 01 00 06 00")]
    );
    assert_eq!(
        rx(&mut b, &mut echo, &h("01 00 00 00 00 44 | 55")),
        Vec::<Vec<u8>>::new()
    );
    // A length beyond the bytes given: 0x0008, the service not asked.
    let served = echo.served;
    assert_eq!(
        rx(&mut b, &mut echo, &h("09 00 00 00 00 54 | 01 02")),
        vec![h("04 00 00 00 00 40 | 01 00 08 00")]
    );
    assert_eq!(echo.served, served);
    // EoE: no one takes it.
    assert_eq!(
        rx(&mut b, &mut echo, &h("01 00 00 00 00 62 | 00")),
        vec![h("04 00 00 00 00 50 | 01 00 02 00")]
    );
}

// ---------------------------------------------------------------------------------------------------
// Timeout

#[test]
fn a_transfer_times_out_when_the_clock_passes_the_deadline() {
    let mut b = Bench::new();
    b.dict.write(0x2000, 0, &text(200)).unwrap();
    assert_eq!(
        b.rx(&h("0A 00 00 00 00 13 | 00 20 | 40 00 20 00 00 00 00 00"))
            .len(),
        1
    );
    b.events();
    let deadline = b.now + Duration::from_secs(1);
    assert_eq!(b.server.poll_timeout(), Some(deadline));
    b.server.handle_timeout(deadline - Duration::from_millis(1));
    assert!(b.server.is_busy());
    b.server.handle_timeout(deadline);
    // Nothing is sent unasked; the event tells.
    assert_eq!(b.drain(), Vec::<Vec<u8>>::new());
    assert_eq!(b.events(), [aborted(0x2000, 0, AbortCode::Timeout)]);
    assert!(!b.server.is_busy());
    assert_eq!(b.server.poll_timeout(), None);
    // The master's late segment request learns why.
    b.now = deadline + Duration::from_millis(500);
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | 60 00 00 00 00 00 00 00")
        => h("0A 00 00 00 00 23 | 00 20 | 80 00 20 00 00 00 04 05"));
    // Later ones are just out of place.
    exchange!(b, h("0A 00 00 00 00 33 | 00 20 | 60 00 00 00 00 00 00 00")
        => h("0A 00 00 00 00 33 | 00 20 | 80 00 00 00 01 00 04 05"));
}

#[test]
fn a_download_that_times_out_writes_nothing() {
    let mut b = Bench::new();
    exchange!(b, hd("12 00 00 00 00 13 | 00 20 | 21 03 20 00 10 00 00 00", b"ABCDEFGH")
        => h("0A 00 00 00 00 13 | 00 30 | 60 03 20 00 00 00 00 00"));
    // Each request restarts the timer.
    b.now += Duration::from_millis(900);
    exchange!(b, hd("0A 00 00 00 00 23 | 00 20 | 00", b"IJKLMNO")
        => h("0A 00 00 00 00 23 | 00 30 | 20 00 00 00 00 00 00 00"));
    assert_eq!(
        b.server.poll_timeout(),
        Some(b.now + Duration::from_secs(1))
    );
    // The last segment comes too late: the mailbox handled after the deadline first ends the transfer.
    b.now += Duration::from_secs(2);
    exchange!(b, h("0A 00 00 00 00 33 | 00 20 | 1D 50 00 00 00 00 00 00")
        => h("0A 00 00 00 00 33 | 00 20 | 80 03 20 00 00 00 04 05"));
    assert_eq!(b.value(0x2003, 0), []);
    assert_eq!(b.events(), [aborted(0x2003, 0, AbortCode::Timeout)]);
}

// ---------------------------------------------------------------------------------------------------
// The SMD's own dictionary

#[test]
fn smd_fixture_over_coe() {
    let bytes = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../fixtures/src/smd.esi.xml"
    ))
    .unwrap();
    let devices = od::esi::read_all(&bytes, "smd.esi.xml").unwrap();
    let mut b = Bench::new();
    b.dict = devices[0].dictionary.clone();
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 2B 10 80 04 E8 03 00 00")
        => h("0A 00 00 00 00 13 | 00 30 | 60 10 80 04 00 00 00 00"));
    assert_eq!(b.value(0x8010, 4), [0xE8, 0x03]);
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | 40 08 10 00 00 00 00 00")
        => hd("12 00 00 00 00 23 | 00 30 | 41 08 10 00 08 00 00 00", b"SMD23K-B"));
    // 0x1C12: one RxPDO, 0x1600.
    exchange!(b, h("0A 00 00 00 00 33 | 00 20 | 50 12 1C 00 00 00 00 00")
        => h("0A 00 00 00 00 33 | 00 30 | 53 12 1C 00 01 00 00 16"));
    // The SMD's assignment is fixed (read-only).
    exchange!(b, h("0E 00 00 00 00 43 | 00 20 | 31 12 1C 00 04 00 00 00 | 01 00 00 16")
        => h("0A 00 00 00 00 43 | 00 20 | 80 12 1C 00 02 00 01 06"));
    // The configuration object whole, from sub-index 1: seven entries (UINT, UINT, UDINT, four UINT),
    // 16 bytes, in sub-index order.
    let entries: Vec<u8> = (1..=7).flat_map(|s| b.value(0x8010, s)).collect();
    assert_eq!(entries.len(), 16);
    assert_eq!(entries[..10], h("00 00 03 00 8D 00 00 00 E8 03"));
    exchange!(b, h("0A 00 00 00 00 53 | 00 20 | 50 10 80 01 00 00 00 00")
        => hd("1A 00 00 00 00 53 | 00 30 | 51 10 80 01 10 00 00 00", &entries));
}

// ---------------------------------------------------------------------------------------------------
// Robustness

#[test]
fn a_host_that_does_not_drain_keeps_bounded_queues() {
    let mut b = Bench::new();
    for _ in 0..1000 {
        b.now += Duration::from_millis(1);
        b.server.handle_mailbox(
            b.now,
            &h("0A 00 00 00 00 03 | 00 20 | 40 00 10 00 00 00 00 00"),
            &mut b.dict,
        );
    }
    assert_eq!(b.drain().len(), 4);
    assert_eq!(b.events().len(), 16);
}

#[test]
fn mailbox_size_is_clamped() {
    assert_eq!(
        CoeServer::new(ServerConfig::default(), 0).mailbox_size(),
        16
    );
    assert_eq!(
        CoeServer::new(ServerConfig::default(), 1 << 20).mailbox_size(),
        6 + 0xFFFF
    );
    // A 16-byte mailbox: the upload response carries no data, each segment seven bytes.
    let mut b = Bench::with(CoeServer::new(ServerConfig::default(), 16));
    exchange!(b, h("0A 00 00 00 00 13 | 00 20 | 40 08 10 00 00 00 00 00")
        => h("0A 00 00 00 00 13 | 00 30 | 41 08 10 00 08 00 00 00"));
    exchange!(b, h("0A 00 00 00 00 23 | 00 20 | 60 00 00 00 00 00 00 00")
        => hd("0A 00 00 00 00 23 | 00 30 | 00", b"SMD23K-"));
    exchange!(b, h("0A 00 00 00 00 33 | 00 20 | 70 00 00 00 00 00 00 00")
        => h("0A 00 00 00 00 33 | 00 30 | 1D 42 00 00 00 00 00 00"));
}

/// Arbitrary mailboxes in arbitrary states never panic, every answer fits the mailbox and has the
/// length its header gives, and an aborted download never leaves a partial value.
#[test]
fn random_mailboxes_never_panic() {
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mut b = Bench::with(CoeServer::new(
        ServerConfig {
            domain_limit: 300,
            ..ServerConfig::default()
        },
        48,
    ));
    b.dict.write(0x2000, 0, &text(100)).unwrap();
    let commands = [
        0x00, 0x20, 0x21, 0x2B, 0x31, 0x40, 0x50, 0x60, 0x80, 0xA0, 0xC0, 0xE0,
    ];
    let entries = [
        [0x00, 0x20, 0x00],
        [0x03, 0x20, 0x00],
        [0x12, 0x1C, 0x00],
        [0x12, 0x1C, 0x01],
        [0x00, 0x16, 0x01],
        [0x10, 0x80, 0x04],
        [0x08, 0x10, 0x00],
    ];
    let mut responses = 0;
    for i in 0..100_000u32 {
        let r = next();
        let len = (next() % 64) as usize;
        let mut mbx: Vec<u8> = (0..len).map(|_| next() as u8).collect();
        if r & 3 != 0 {
            // Mostly a well-formed CoE SDO request: a known command (while a transfer runs, mostly a
            // segment), a real entry, a small size.
            mbx.resize(mbx.len().max(16), 0);
            let body = (mbx.len() - 6) as u16;
            mbx[..2].copy_from_slice(&body.to_le_bytes());
            mbx[4] = 0;
            mbx[5] = 0x03 | (((i % 8) as u8) << 4);
            mbx[6..8].copy_from_slice(&[0x00, 0x20]);
            let low = if r & 4 == 0 { mbx[8] & 0x1F } else { 0 };
            mbx[8] = if b.server.is_busy() && r & 8 == 0 {
                [0x00, 0x10, 0x60, 0x70][(r >> 8) as usize % 4] | (low & 0x0F)
            } else {
                commands[(r >> 8) as usize % commands.len()] | low
            };
            if r & 0x70 != 0 {
                mbx[9..12].copy_from_slice(&entries[(r >> 16) as usize % entries.len()]);
            }
            if r & 0x80 == 0 {
                mbx[12] = (r >> 24) as u8 % 80;
                mbx[13..16].fill(0);
            }
        }
        b.now += Duration::from_millis((r >> 32) % 300);
        let before = b.dict.clone();
        b.server.handle_mailbox(b.now, &mbx, &mut b.dict);
        let answers = b.drain();
        let mut served = false;
        for answer in &answers {
            assert!(answer.len() <= 48 && answer.len() >= 6 + 4, "{answer:02X?}");
            assert_eq!(
                u16::from_le_bytes([answer[0], answer[1]]) as usize + 6,
                answer.len()
            );
            // CoE, SDO response (not an abort, not a mailbox error reply).
            if answer[5] & 0x0F == 3 && answer[7] >> 4 == 3 {
                served = true;
                responses += 1;
            }
        }
        if !served {
            assert_eq!(b.dict, before, "changed without a response: {mbx:02X?}");
        }
        if r & 0xF000 == 0 {
            b.server.handle_timeout(b.now + Duration::from_secs(2));
            assert_eq!(b.drain(), Vec::<Vec<u8>>::new());
            assert!(!b.server.is_busy());
        }
        b.events();
    }
    // The requests reach the transfers, not only the refusals.
    assert!(responses > 5_000, "{responses} responses");
}
