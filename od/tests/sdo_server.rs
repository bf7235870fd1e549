//! The SDO server against golden byte sequences written from the frame layouts of CiA 301 §7.2.4.3: each
//! transfer mode, every abort path, and the dictionary left as it was by every aborted download.

use std::time::{Duration, Instant};

use od::sdo::{Address, Frame, SdoServer, ServerConfig, ServerEvent};
use od::{AbortCode, AccessType, DataType, Dictionary, Object, ObjectKind, SubObject, Value};

/// A frame from its bytes written in hexadecimal, `"2B 17 10 00 E8 03 00 00"`.
fn h(text: &str) -> Frame {
    let bytes: Vec<u8> = text
        .split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).unwrap())
        .collect();
    bytes.try_into().unwrap()
}

fn hs(frames: &[&str]) -> Vec<Frame> {
    frames.iter().map(|f| h(f)).collect()
}

fn mux(index: u16, sub: u8) -> Address {
    Address::new(index, sub)
}

/// The dictionary the tests serve.
fn dictionary() -> Dictionary {
    let mut d = Dictionary::new();
    d.insert(Object::var(
        0x1000,
        SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro)
            .with_default(Value::Uint(0x0002_0192)),
    ));
    d.insert(Object::var(
        0x1008,
        SubObject::new(
            "Manufacturer device name",
            DataType::VisibleString,
            AccessType::Const,
        )
        .with_default(Value::String("firmware2".into())),
    ));
    d.insert(Object::var(
        0x1017,
        SubObject::new(
            "Producer heartbeat time",
            DataType::Unsigned16,
            AccessType::Rw,
        ),
    ));
    d.insert(
        Object::structured(0x1018, "Identity object", ObjectKind::Record)
            .with_sub(
                0,
                SubObject::new("Highest sub-index", DataType::Unsigned8, AccessType::Const)
                    .with_default(Value::Uint(1)),
            )
            .with_sub(
                1,
                SubObject::new("Vendor-ID", DataType::Unsigned32, AccessType::Ro)
                    .with_default(Value::Uint(0x0000_0123)),
            ),
    );
    d.insert(Object::var(
        0x2000,
        SubObject::new("Name", DataType::VisibleString, AccessType::Rw).with_bit_size(160),
    ));
    d.insert(Object::var(
        0x2001,
        SubObject::new("Password", DataType::Unsigned8, AccessType::Wo),
    ));
    d.insert(Object::var(
        0x2002,
        SubObject::new("Percent", DataType::Unsigned8, AccessType::Rw)
            .with_default(Value::Uint(50))
            .with_limits(Some(Value::Uint(10)), Some(Value::Uint(100))),
    ));
    d.insert(Object::var(
        0x2003,
        SubObject::new("Program", DataType::Domain, AccessType::Rw),
    ));
    d.insert(Object::var(
        0x2004,
        SubObject::new("Counter", DataType::Unsigned64, AccessType::Rw),
    ));
    d
}

/// A server, its dictionary and a simulated clock.
struct Bench {
    server: SdoServer,
    dict: Dictionary,
    now: Instant,
}

impl Bench {
    fn new() -> Bench {
        Bench::with(ServerConfig::default())
    }

    fn with(config: ServerConfig) -> Bench {
        Bench {
            server: SdoServer::new(config),
            dict: dictionary(),
            now: Instant::now(),
        }
    }

    /// Hands the server a frame 1 ms after the last and answers every frame it sends.
    fn rx(&mut self, frame: &str) -> Vec<Frame> {
        self.now += Duration::from_millis(1);
        self.server
            .handle_frame(self.now, &h(frame), &mut self.dict);
        self.drain()
    }

    /// Hands the server each frame and expects it to send nothing until the last.
    fn rx_all(&mut self, frames: &[&str]) -> Vec<Frame> {
        let (last, before) = frames.split_last().unwrap();
        for f in before {
            assert_eq!(self.rx(f), Vec::<Frame>::new(), "answer to {f}");
        }
        self.rx(last)
    }

    fn drain(&mut self) -> Vec<Frame> {
        std::iter::from_fn(|| self.server.poll_transmit()).collect()
    }

    fn events(&mut self) -> Vec<ServerEvent> {
        std::iter::from_fn(|| self.server.poll_event()).collect()
    }

    fn value(&self, index: u16, sub: u8) -> Vec<u8> {
        self.dict.entry(index, sub).unwrap().value.clone()
    }
}

/// Asserts that `frame` is answered with exactly `answer`.
macro_rules! exchange {
    ($bench:expr, $frame:expr => [$($answer:expr),* $(,)?]) => {
        assert_eq!($bench.rx($frame), hs(&[$($answer),*]), "answer to {}", $frame)
    };
}

// ---------------------------------------------------------------------------------------------------
// Expedited download (CiA 301 §7.2.4.3.3)

#[test]
fn expedited_download_with_size() {
    let mut b = Bench::new();
    // ccs 1, n 2, e 1, s 1: two bytes, 0x03E8 = 1000, to 0x1017:00.
    exchange!(b, "2B 17 10 00 E8 03 00 00" => ["60 17 10 00 00 00 00 00"]);
    assert_eq!(b.value(0x1017, 0), [0xE8, 0x03]);
    assert_eq!(
        b.events(),
        [ServerEvent::Downloaded {
            mux: mux(0x1017, 0)
        }]
    );
    assert!(!b.server.is_busy());
    assert_eq!(b.server.poll_timeout(), None);
}

#[test]
fn expedited_download_without_size_takes_the_fixed_size() {
    let mut b = Bench::new();
    // s = 0: a two-byte entry takes bytes 4 and 5, the rest is padding.
    exchange!(b, "22 17 10 00 E8 03 AA BB" => ["60 17 10 00 00 00 00 00"]);
    assert_eq!(b.value(0x1017, 0), [0xE8, 0x03]);
    // A string takes all four bytes.
    exchange!(b, "22 00 20 00 41 42 43 44" => ["60 00 20 00 00 00 00 00"]);
    assert_eq!(b.value(0x2000, 0), b"ABCD");
    // An eight-byte entry gets four bytes: too short.
    exchange!(b, "22 04 20 00 01 02 03 04" => ["80 04 20 00 13 00 07 06"]);
    assert_eq!(b.value(0x2004, 0), [0; 8]);
}

#[test]
fn expedited_download_of_one_and_four_bytes() {
    let mut b = Bench::new();
    // n = 3: one byte.
    exchange!(b, "2F 02 20 00 40 00 00 00" => ["60 02 20 00 00 00 00 00"]);
    assert_eq!(b.value(0x2002, 0), [0x40]);
    // n = 0: four bytes to a write-only entry of one byte: too long.
    exchange!(b, "23 01 20 00 01 02 03 04" => ["80 01 20 00 12 00 07 06"]);
    exchange!(b, "2F 01 20 00 07 00 00 00" => ["60 01 20 00 00 00 00 00"]);
    assert_eq!(b.value(0x2001, 0), [0x07]);
}

// ---------------------------------------------------------------------------------------------------
// Segmented download (CiA 301 §7.2.4.3.3–7.2.4.3.4)

#[test]
fn segmented_download_with_size() {
    let mut b = Bench::new();
    // "0123456789" to 0x2000:00; size 10 indicated.
    exchange!(b, "21 00 20 00 0A 00 00 00" => ["60 00 20 00 00 00 00 00"]);
    assert!(b.server.is_busy());
    assert_eq!(
        b.server.poll_timeout(),
        Some(b.now + Duration::from_secs(1))
    );
    // toggle 0, n 0, c 0.
    exchange!(b, "00 30 31 32 33 34 35 36" => ["20 00 00 00 00 00 00 00"]);
    // Nothing is written before the last segment.
    assert_eq!(b.value(0x2000, 0), b"");
    // toggle 1, n 4, c 1: three bytes.
    exchange!(b, "19 37 38 39 00 00 00 00" => ["30 00 00 00 00 00 00 00"]);
    assert_eq!(b.value(0x2000, 0), b"0123456789");
    assert_eq!(
        b.events(),
        [ServerEvent::Downloaded {
            mux: mux(0x2000, 0)
        }]
    );
    assert_eq!(b.server.poll_timeout(), None);
}

#[test]
fn segmented_download_without_size() {
    let mut b = Bench::new();
    exchange!(b, "20 03 20 00 00 00 00 00" => ["60 03 20 00 00 00 00 00"]);
    exchange!(b, "00 01 02 03 04 05 06 07" => ["20 00 00 00 00 00 00 00"]);
    exchange!(b, "10 08 09 0A 0B 0C 0D 0E" => ["30 00 00 00 00 00 00 00"]);
    // toggle 0, n 6, c 1: one byte.
    exchange!(b, "0D 0F 00 00 00 00 00 00" => ["20 00 00 00 00 00 00 00"]);
    assert_eq!(b.value(0x2003, 0), (1..=15).collect::<Vec<u8>>());
}

#[test]
fn segmented_download_of_a_fixed_size_entry() {
    let mut b = Bench::new();
    exchange!(b, "21 04 20 00 08 00 00 00" => ["60 04 20 00 00 00 00 00"]);
    exchange!(b, "00 01 02 03 04 05 06 07" => ["20 00 00 00 00 00 00 00"]);
    // toggle 1, n 6, c 1.
    exchange!(b, "1D 08 00 00 00 00 00 00" => ["30 00 00 00 00 00 00 00"]);
    assert_eq!(b.value(0x2004, 0), [1, 2, 3, 4, 5, 6, 7, 8]);
}

// ---------------------------------------------------------------------------------------------------
// Expedited and segmented upload (CiA 301 §7.2.4.3.6–7.2.4.3.7)

#[test]
fn expedited_upload() {
    let mut b = Bench::new();
    // scs 2, n 0, e 1, s 1: four bytes.
    exchange!(b, "40 00 10 00 00 00 00 00" => ["43 00 10 00 92 01 02 00"]);
    // n 2: two bytes.
    exchange!(b, "40 17 10 00 00 00 00 00" => ["4B 17 10 00 00 00 00 00"]);
    // n 3: one byte.
    exchange!(b, "40 18 10 00 00 00 00 00" => ["4F 18 10 00 01 00 00 00"]);
    exchange!(b, "40 18 10 01 00 00 00 00" => ["43 18 10 01 23 01 00 00"]);
    assert_eq!(
        b.events(),
        [0x1000, 0x1017, 0x1018, 0x1018]
            .iter()
            .zip([0, 0, 0, 1])
            .map(|(&i, s)| ServerEvent::Uploaded { mux: mux(i, s) })
            .collect::<Vec<_>>()
    );
    assert!(!b.server.is_busy());
}

#[test]
fn segmented_upload_of_a_nine_byte_string() {
    let mut b = Bench::new();
    // scs 2, e 0, s 1, size 9.
    exchange!(b, "40 08 10 00 00 00 00 00" => ["41 08 10 00 09 00 00 00"]);
    // toggle 0, n 0, c 0: "firmwar".
    exchange!(b, "60 00 00 00 00 00 00 00" => ["00 66 69 72 6D 77 61 72"]);
    // toggle 1, n 5, c 1: "e2".
    exchange!(b, "70 00 00 00 00 00 00 00" => ["1B 65 32 00 00 00 00 00"]);
    assert_eq!(
        b.events(),
        [ServerEvent::Uploaded {
            mux: mux(0x1008, 0)
        }]
    );
    assert!(!b.server.is_busy());
}

#[test]
fn segmented_upload_of_whole_segments_and_of_nothing() {
    let mut b = Bench::new();
    b.dict
        .write(0x2003, 0, &(1..=14).collect::<Vec<u8>>())
        .unwrap();
    exchange!(b, "40 03 20 00 00 00 00 00" => ["41 03 20 00 0E 00 00 00"]);
    exchange!(b, "60 00 00 00 00 00 00 00" => ["00 01 02 03 04 05 06 07"]);
    // toggle 1, n 0, c 1.
    exchange!(b, "70 00 00 00 00 00 00 00" => ["11 08 09 0A 0B 0C 0D 0E"]);

    // An empty value: size 0, then one segment with n 7, c 1.
    b.dict.write(0x2003, 0, &[]).unwrap();
    exchange!(b, "40 03 20 00 00 00 00 00" => ["41 03 20 00 00 00 00 00"]);
    exchange!(b, "60 00 00 00 00 00 00 00" => ["0F 00 00 00 00 00 00 00"]);
    assert!(!b.server.is_busy());
}

// ---------------------------------------------------------------------------------------------------
// Block download (CiA 301 §7.2.4.3.9–7.2.4.3.12)

/// "ABCDEFGHIJKLMNOPQRST" in three block segments; its CRC-16/XMODEM is 0x1034.
const SEG1: &str = "01 41 42 43 44 45 46 47";
const SEG2: &str = "02 48 49 4A 4B 4C 4D 4E";
const SEG3_LAST: &str = "83 4F 50 51 52 53 54 00";

#[test]
fn block_download_of_20_bytes_with_crc() {
    let mut b = Bench::new();
    // ccs 6, cc 1, s 1, cs 0; size 20.
    // Answer: scs 5, sc 1, ss 0; blksize 127.
    exchange!(b, "C6 00 20 00 14 00 00 00" => ["A4 00 20 00 7F 00 00 00"]);
    // Three segments, the last with c = 1; acknowledged with ackseq 3, blksize 127.
    assert_eq!(
        b.rx_all(&[SEG1, SEG2, SEG3_LAST]),
        hs(&["A2 03 7F 00 00 00 00 00"])
    );
    assert_eq!(b.value(0x2000, 0), b"");
    // End: ccs 6, n 1, cs 1; CRC 0x1034.
    exchange!(b, "C5 34 10 00 00 00 00 00" => ["A1 00 00 00 00 00 00 00"]);
    assert_eq!(b.value(0x2000, 0), b"ABCDEFGHIJKLMNOPQRST");
    assert_eq!(
        b.events(),
        [ServerEvent::Downloaded {
            mux: mux(0x2000, 0)
        }]
    );
    assert!(!b.server.is_busy());
}

#[test]
fn block_download_without_size_and_without_crc() {
    let mut b = Bench::new();
    // ccs 6, cc 0, s 0: the server still says it supports CRC, but the CRC is not used.
    exchange!(b, "C0 00 20 00 00 00 00 00" => ["A4 00 20 00 7F 00 00 00"]);
    assert_eq!(
        b.rx_all(&[SEG1, SEG2, SEG3_LAST]),
        hs(&["A2 03 7F 00 00 00 00 00"])
    );
    exchange!(b, "C5 00 00 00 00 00 00 00" => ["A1 00 00 00 00 00 00 00"]);
    assert_eq!(b.value(0x2000, 0), b"ABCDEFGHIJKLMNOPQRST");
}

#[test]
fn block_download_on_a_server_without_crc() {
    let mut b = Bench::with(ServerConfig {
        crc: false,
        block_size: 16,
        ..ServerConfig::default()
    });
    // sc 0, blksize 16; the client's CRC is not checked.
    exchange!(b, "C6 00 20 00 14 00 00 00" => ["A0 00 20 00 10 00 00 00"]);
    assert_eq!(
        b.rx_all(&[SEG1, SEG2, SEG3_LAST]),
        hs(&["A2 03 10 00 00 00 00 00"])
    );
    exchange!(b, "C5 FF FF 00 00 00 00 00" => ["A1 00 00 00 00 00 00 00"]);
    assert_eq!(b.value(0x2000, 0), b"ABCDEFGHIJKLMNOPQRST");
}

#[test]
fn block_download_with_a_lost_segment() {
    let mut b = Bench::new();
    exchange!(b, "C6 00 20 00 14 00 00 00" => ["A4 00 20 00 7F 00 00 00"]);
    // Segment 2 is lost: segment 3 (the last) is out of order, so the sub-block is acknowledged up to 1.
    assert_eq!(
        b.rx_all(&[SEG1, SEG3_LAST]),
        hs(&["A2 01 7F 00 00 00 00 00"])
    );
    // The client resumes after segment 1 with a new sub-block from sequence number 1.
    assert_eq!(
        b.rx_all(&["01 48 49 4A 4B 4C 4D 4E", "82 4F 50 51 52 53 54 00"]),
        hs(&["A2 02 7F 00 00 00 00 00"])
    );
    exchange!(b, "C5 34 10 00 00 00 00 00" => ["A1 00 00 00 00 00 00 00"]);
    assert_eq!(b.value(0x2000, 0), b"ABCDEFGHIJKLMNOPQRST");
}

#[test]
fn block_download_with_a_segment_lost_inside_a_sub_block() {
    // Block size 4, 35 bytes 0x00..0x22: five segments, two sub-blocks; segment 3 is lost.
    let mut b = Bench::with(ServerConfig {
        block_size: 4,
        ..ServerConfig::default()
    });
    exchange!(b, "C6 03 20 00 23 00 00 00" => ["A4 03 20 00 04 00 00 00"]);
    // Segment 4 ends the sub-block (sequence number = block size); acknowledged up to 2.
    assert_eq!(
        b.rx_all(&[
            "01 00 01 02 03 04 05 06",
            "02 07 08 09 0A 0B 0C 0D",
            "04 15 16 17 18 19 1A 1B"
        ]),
        hs(&["A2 02 04 00 00 00 00 00"])
    );
    // Resent from segment 3 on; the last segment closes the second sub-block early.
    assert_eq!(
        b.rx_all(&[
            "01 0E 0F 10 11 12 13 14",
            "02 15 16 17 18 19 1A 1B",
            "83 1C 1D 1E 1F 20 21 22",
        ]),
        hs(&["A2 03 04 00 00 00 00 00"])
    );
    // n 0; CRC 0xBF3A.
    exchange!(b, "C1 3A BF 00 00 00 00 00" => ["A1 00 00 00 00 00 00 00"]);
    assert_eq!(b.value(0x2003, 0), (0..35).collect::<Vec<u8>>());
}

#[test]
fn block_download_with_the_first_segment_lost_acknowledges_nothing() {
    let mut b = Bench::with(ServerConfig {
        block_size: 2,
        ..ServerConfig::default()
    });
    exchange!(b, "C6 00 20 00 14 00 00 00" => ["A4 00 20 00 02 00 00 00"]);
    exchange!(b, "02 48 49 4A 4B 4C 4D 4E" => ["A2 00 02 00 00 00 00 00"]);
    // Full sub-blocks of two.
    assert_eq!(b.rx_all(&[SEG1, SEG2]), hs(&["A2 02 02 00 00 00 00 00"]));
    exchange!(b, "81 4F 50 51 52 53 54 00" => ["A2 01 02 00 00 00 00 00"]);
    exchange!(b, "C5 34 10 00 00 00 00 00" => ["A1 00 00 00 00 00 00 00"]);
    assert_eq!(b.value(0x2000, 0), b"ABCDEFGHIJKLMNOPQRST");
}

#[test]
fn a_frame_inside_a_sub_block_is_a_segment() {
    let mut b = Bench::new();
    exchange!(b, "C6 00 20 00 14 00 00 00" => ["A4 00 20 00 7F 00 00 00"]);
    exchange!(b, SEG1 => []);
    // An initiate upload's byte 0 (0x40) reads as sequence number 64: out of order, ignored.
    exchange!(b, "40 17 10 00 00 00 00 00" => []);
    assert_eq!(
        b.rx_all(&[SEG2, SEG3_LAST]),
        hs(&["A2 03 7F 00 00 00 00 00"])
    );
    exchange!(b, "C5 34 10 00 00 00 00 00" => ["A1 00 00 00 00 00 00 00"]);
    assert_eq!(b.value(0x2000, 0), b"ABCDEFGHIJKLMNOPQRST");
}

// ---------------------------------------------------------------------------------------------------
// Block upload (CiA 301 §7.2.4.3.13–7.2.4.3.16)

fn bench_with_name() -> Bench {
    let mut b = Bench::new();
    b.dict.write(0x2000, 0, b"ABCDEFGHIJKLMNOPQRST").unwrap();
    b
}

#[test]
fn block_upload_of_20_bytes_with_crc() {
    let mut b = bench_with_name();
    // ccs 5, cc 1, cs 0; blksize 127, pst 0.
    // Answer: scs 6, sc 1, s 1, ss 0; size 20.
    exchange!(b, "A4 00 20 00 7F 00 00 00" => ["C6 00 20 00 14 00 00 00"]);
    // Start: ccs 5, cs 3. The whole value in one sub-block.
    exchange!(b, "A3 00 00 00 00 00 00 00" => [SEG1, SEG2, SEG3_LAST]);
    // Acknowledged up to 3: the end, scs 6, n 1, ss 1, CRC 0x1034.
    exchange!(b, "A2 03 7F 00 00 00 00 00" => ["C5 34 10 00 00 00 00 00"]);
    assert!(b.server.is_busy());
    assert_eq!(b.events(), Vec::<ServerEvent>::new());
    // End response: ccs 5, cs 1.
    exchange!(b, "A1 00 00 00 00 00 00 00" => []);
    assert_eq!(
        b.events(),
        [ServerEvent::Uploaded {
            mux: mux(0x2000, 0)
        }]
    );
    assert!(!b.server.is_busy());
}

#[test]
fn block_upload_without_crc() {
    let mut b = bench_with_name();
    // Client without CRC (cc 0): the server still says sc 1, and sends CRC 0.
    exchange!(b, "A0 00 20 00 7F 00 00 00" => ["C6 00 20 00 14 00 00 00"]);
    exchange!(b, "A3 00 00 00 00 00 00 00" => [SEG1, SEG2, SEG3_LAST]);
    exchange!(b, "A2 03 7F 00 00 00 00 00" => ["C5 00 00 00 00 00 00 00"]);
    exchange!(b, "A1 00 00 00 00 00 00 00" => []);

    let mut b = Bench::with(ServerConfig {
        crc: false,
        ..ServerConfig::default()
    });
    b.dict.write(0x2000, 0, b"ABCDEFGHIJKLMNOPQRST").unwrap();
    // A server without CRC: sc 0, CRC 0 although the client asked for it.
    exchange!(b, "A4 00 20 00 7F 00 00 00" => ["C2 00 20 00 14 00 00 00"]);
    exchange!(b, "A3 00 00 00 00 00 00 00" => [SEG1, SEG2, SEG3_LAST]);
    exchange!(b, "A2 03 7F 00 00 00 00 00" => ["C5 00 00 00 00 00 00 00"]);
    exchange!(b, "A1 00 00 00 00 00 00 00" => []);
}

#[test]
fn block_upload_resends_after_the_acknowledged_segment() {
    let mut b = bench_with_name();
    exchange!(b, "A4 00 20 00 7F 00 00 00" => ["C6 00 20 00 14 00 00 00"]);
    exchange!(b, "A3 00 00 00 00 00 00 00" => [SEG1, SEG2, SEG3_LAST]);
    // The client got segment 1 only: the server resends segments 2 and 3 as a new sub-block.
    exchange!(b, "A2 01 7F 00 00 00 00 00" => ["01 48 49 4A 4B 4C 4D 4E", "82 4F 50 51 52 53 54 00"]);
    // Nothing received: the same sub-block again.
    exchange!(b, "A2 00 7F 00 00 00 00 00" => ["01 48 49 4A 4B 4C 4D 4E", "82 4F 50 51 52 53 54 00"]);
    exchange!(b, "A2 02 7F 00 00 00 00 00" => ["C5 34 10 00 00 00 00 00"]);
    exchange!(b, "A1 00 00 00 00 00 00 00" => []);
    assert_eq!(
        b.events(),
        [ServerEvent::Uploaded {
            mux: mux(0x2000, 0)
        }]
    );
}

#[test]
fn block_upload_takes_the_block_size_of_each_acknowledgement() {
    let mut b = bench_with_name();
    // blksize 1.
    exchange!(b, "A4 00 20 00 01 00 00 00" => ["C6 00 20 00 14 00 00 00"]);
    exchange!(b, "A3 00 00 00 00 00 00 00" => [SEG1]);
    // Next sub-block of two.
    exchange!(b, "A2 01 02 00 00 00 00 00" => ["01 48 49 4A 4B 4C 4D 4E", "82 4F 50 51 52 53 54 00"]);
    exchange!(b, "A2 02 7F 00 00 00 00 00" => ["C5 34 10 00 00 00 00 00"]);
    exchange!(b, "A1 00 00 00 00 00 00 00" => []);
}

#[test]
fn block_upload_of_an_empty_value() {
    let mut b = Bench::new();
    exchange!(b, "A4 03 20 00 7F 00 00 00" => ["C6 03 20 00 00 00 00 00"]);
    // One last segment with no data.
    exchange!(b, "A3 00 00 00 00 00 00 00" => ["81 00 00 00 00 00 00 00"]);
    // n 7; the CRC of nothing is 0.
    exchange!(b, "A2 01 7F 00 00 00 00 00" => ["DD 00 00 00 00 00 00 00"]);
    exchange!(b, "A1 00 00 00 00 00 00 00" => []);
}

#[test]
fn block_upload_falls_back_below_the_protocol_switch_threshold() {
    let mut b = bench_with_name();
    // pst 4, two bytes: an expedited initiate upload response.
    exchange!(b, "A4 17 10 00 7F 04 00 00" => ["4B 17 10 00 00 00 00 00"]);
    assert!(!b.server.is_busy());
    // pst 21, 20 bytes: a segmented one, then upload segments.
    exchange!(b, "A4 00 20 00 7F 15 00 00" => ["41 00 20 00 14 00 00 00"]);
    exchange!(b, "60 00 00 00 00 00 00 00" => ["00 41 42 43 44 45 46 47"]);
    exchange!(b, "70 00 00 00 00 00 00 00" => ["10 48 49 4A 4B 4C 4D 4E"]);
    // toggle 0, n 1, c 1.
    exchange!(b, "60 00 00 00 00 00 00 00" => ["03 4F 50 51 52 53 54 00"]);
    assert!(!b.server.is_busy());
    // pst 20 is the size: still the fall-back; pst 19 is below it: block upload.
    exchange!(b, "A4 00 20 00 7F 14 00 00" => ["41 00 20 00 14 00 00 00"]);
    exchange!(b, "A4 00 20 00 7F 13 00 00" => ["C6 00 20 00 14 00 00 00"]);
}

// ---------------------------------------------------------------------------------------------------
// Abort paths (CiA 301 §7.2.4.3.17)

#[test]
fn toggle_bit_not_alternated() {
    let mut b = Bench::new();
    exchange!(b, "21 00 20 00 0A 00 00 00" => ["60 00 20 00 00 00 00 00"]);
    // The first segment carries toggle 1.
    exchange!(b, "10 30 31 32 33 34 35 36" => ["80 00 20 00 00 00 03 05"]);
    assert!(!b.server.is_busy());

    // The second segment repeats toggle 0.
    exchange!(b, "21 00 20 00 0A 00 00 00" => ["60 00 20 00 00 00 00 00"]);
    exchange!(b, "00 30 31 32 33 34 35 36" => ["20 00 00 00 00 00 00 00"]);
    exchange!(b, "09 37 38 39 00 00 00 00" => ["80 00 20 00 00 00 03 05"]);

    // Upload: the first request carries toggle 1.
    exchange!(b, "40 08 10 00 00 00 00 00" => ["41 08 10 00 09 00 00 00"]);
    exchange!(b, "70 00 00 00 00 00 00 00" => ["80 08 10 00 00 00 03 05"]);
    assert_eq!(b.value(0x2000, 0), b"");
    assert_eq!(
        b.events().last(),
        Some(&ServerEvent::Aborted {
            mux: mux(0x1008, 0),
            code: AbortCode::ToggleBit,
            by_client: false
        })
    );
}

#[test]
fn unknown_command_specifier() {
    let mut b = Bench::new();
    // ccs 7 while idle: the abort carries bytes 1–3 of the frame.
    exchange!(b, "E0 17 10 00 00 00 00 00" => ["80 17 10 00 01 00 04 05"]);
    // ccs 7 during a transfer: the abort carries the transfer's entry and ends it.
    exchange!(b, "21 00 20 00 0A 00 00 00" => ["60 00 20 00 00 00 00 00"]);
    exchange!(b, "FF FF FF FF FF FF FF FF" => ["80 00 20 00 01 00 04 05"]);
    assert!(!b.server.is_busy());
    exchange!(b, "00 30 31 32 33 34 35 36" => ["80 30 31 32 01 00 04 05"]);
}

#[test]
fn frames_that_do_not_fit_the_state() {
    let mut b = Bench::new();
    // Segment requests and block frames while idle.
    exchange!(b, "60 00 00 00 00 00 00 00" => ["80 00 00 00 01 00 04 05"]);
    exchange!(b, "A3 00 00 00 00 00 00 00" => ["80 00 00 00 01 00 04 05"]);
    exchange!(b, "C1 00 00 00 00 00 00 00" => ["80 00 00 00 01 00 04 05"]);
    // An upload segment request during a download.
    exchange!(b, "21 00 20 00 0A 00 00 00" => ["60 00 20 00 00 00 00 00"]);
    exchange!(b, "60 00 00 00 00 00 00 00" => ["80 00 20 00 01 00 04 05"]);
    // A download segment during an upload.
    exchange!(b, "40 08 10 00 00 00 00 00" => ["41 08 10 00 09 00 00 00"]);
    exchange!(b, "00 00 00 00 00 00 00 00" => ["80 08 10 00 01 00 04 05"]);
    // A second start during a block upload.
    b.dict.write(0x2000, 0, b"ABCDEFGHIJKLMNOPQRST").unwrap();
    exchange!(b, "A4 00 20 00 7F 00 00 00" => ["C6 00 20 00 14 00 00 00"]);
    exchange!(b, "A3 00 00 00 00 00 00 00" => [SEG1, SEG2, SEG3_LAST]);
    exchange!(b, "A3 00 00 00 00 00 00 00" => ["80 00 20 00 01 00 04 05"]);
    // An end response before the end during a block upload.
    exchange!(b, "A4 00 20 00 7F 00 00 00" => ["C6 00 20 00 14 00 00 00"]);
    exchange!(b, "A1 00 00 00 00 00 00 00" => ["80 00 20 00 01 00 04 05"]);
    // A download segment where the end of a block download is due.
    exchange!(b, "C6 00 20 00 14 00 00 00" => ["A4 00 20 00 7F 00 00 00"]);
    assert_eq!(
        b.rx_all(&[SEG1, SEG2, SEG3_LAST]),
        hs(&["A2 03 7F 00 00 00 00 00"])
    );
    exchange!(b, "00 00 00 00 00 00 00 00" => ["80 00 20 00 01 00 04 05"]);
    assert_eq!(b.value(0x2000, 0), b"ABCDEFGHIJKLMNOPQRST");
    assert!(!b.server.is_busy());
}

#[test]
fn timeout() {
    let mut b = Bench::new();
    exchange!(b, "21 00 20 00 0A 00 00 00" => ["60 00 20 00 00 00 00 00"]);
    let start = b.now;
    assert_eq!(
        b.server.poll_timeout(),
        Some(start + Duration::from_secs(1))
    );
    // Just before the deadline nothing happens.
    b.server.handle_timeout(start + Duration::from_millis(999));
    assert_eq!(b.drain(), Vec::<Frame>::new());
    // A frame restarts the timer.
    b.now = start + Duration::from_millis(900);
    exchange!(b, "00 30 31 32 33 34 35 36" => ["20 00 00 00 00 00 00 00"]);
    let last = b.now;
    assert_eq!(b.server.poll_timeout(), Some(last + Duration::from_secs(1)));
    b.server.handle_timeout(start + Duration::from_millis(1500));
    assert_eq!(b.drain(), Vec::<Frame>::new());
    // Past one second without a frame: abort 0x05040000 and idle.
    b.server.handle_timeout(last + Duration::from_millis(1001));
    assert_eq!(b.drain(), hs(&["80 00 20 00 00 00 04 05"]));
    assert_eq!(b.server.poll_timeout(), None);
    assert!(!b.server.is_busy());
    assert_eq!(
        b.events().last(),
        Some(&ServerEvent::Aborted {
            mux: mux(0x2000, 0),
            code: AbortCode::Timeout,
            by_client: false
        })
    );
    assert_eq!(b.value(0x2000, 0), b"");
}

#[test]
fn a_late_frame_times_the_transfer_out_first() {
    let mut b = Bench::new();
    b.dict.write(0x2000, 0, b"ABCDEFGHIJKLMNOPQRST").unwrap();
    exchange!(b, "A4 00 20 00 7F 00 00 00" => ["C6 00 20 00 14 00 00 00"]);
    exchange!(b, "A3 00 00 00 00 00 00 00" => [SEG1, SEG2, SEG3_LAST]);
    // The acknowledgement comes after the deadline, without handle_timeout in between.
    b.now += Duration::from_secs(2);
    exchange!(b, "A2 03 7F 00 00 00 00 00" => ["80 00 20 00 00 00 04 05", "80 03 7F 00 01 00 04 05"]);
}

#[test]
fn timeout_during_block_transfers() {
    let mut b = Bench::new();
    exchange!(b, "C6 00 20 00 14 00 00 00" => ["A4 00 20 00 7F 00 00 00"]);
    exchange!(b, SEG1 => []);
    b.server.handle_timeout(b.now + Duration::from_millis(1001));
    assert_eq!(b.drain(), hs(&["80 00 20 00 00 00 04 05"]));

    b.dict.write(0x2000, 0, b"ABCDEFGHIJKLMNOPQRST").unwrap();
    exchange!(b, "A4 00 20 00 7F 00 00 00" => ["C6 00 20 00 14 00 00 00"]);
    b.server.handle_timeout(b.now + Duration::from_millis(1001));
    assert_eq!(b.drain(), hs(&["80 00 20 00 00 00 04 05"]));
}

/// A block download whose client went away after the initiate: every later frame is read as a
/// segment (`40` as sequence number 64), out of order. Such frames take nothing, so they do not
/// restart the transfer timer: one second after the initiate the transfer ends with 0x05040000 and
/// the request that comes then is served. (Each one restarting the timer locked the server out for
/// as long as a master kept polling faster than the timeout.)
#[test]
fn out_of_order_segments_do_not_hold_a_block_download_open() {
    let mut b = Bench::new();
    let start = b.now + Duration::from_millis(1);
    exchange!(b, "C2 17 10 00 02 00 00 00" => ["A4 17 10 00 7F 00 00 00"]);
    assert_eq!(b.now, start);
    // An upload request of 0x1018:01 every 300 ms: ignored at 0.3, 0.6 and 0.9 s.
    for k in 1..=3u64 {
        b.now = start + Duration::from_millis(300 * k) - Duration::from_millis(1);
        exchange!(b, "40 18 10 01 00 00 00 00" => []);
        assert_eq!(
            b.server.poll_timeout(),
            Some(start + Duration::from_secs(1)),
            "after the request at {} ms",
            300 * k
        );
    }
    // At 1.2 s: the block download has timed out (abort 0x05040000 for 0x1017), and the request is
    // answered (vendor-ID 0x00000123).
    b.now = start + Duration::from_millis(1199);
    exchange!(b, "40 18 10 01 00 00 00 00" => ["80 17 10 00 00 00 04 05", "43 18 10 01 23 01 00 00"]);
    assert!(!b.server.is_busy());
    assert_eq!(b.value(0x1017, 0), [0, 0]);
}

/// The end of a sub-block out of order is acknowledged (the last segment in order, here none), but
/// like any segment out of order it does not restart the timer; segments taken in order do.
#[test]
fn only_segments_in_order_restart_the_block_download_timer() {
    let mut b = Bench::with(ServerConfig {
        block_size: 2,
        ..ServerConfig::default()
    });
    let start = b.now + Duration::from_millis(1);
    exchange!(b, "C6 00 20 00 14 00 00 00" => ["A4 00 20 00 02 00 00 00"]);
    b.now = start + Duration::from_millis(499);
    exchange!(b, "02 48 49 4A 4B 4C 4D 4E" => ["A2 00 02 00 00 00 00 00"]);
    assert_eq!(
        b.server.poll_timeout(),
        Some(start + Duration::from_secs(1))
    );
    b.now = start + Duration::from_millis(899);
    exchange!(b, SEG1 => []);
    let taken = start + Duration::from_millis(900);
    assert_eq!(
        b.server.poll_timeout(),
        Some(taken + Duration::from_secs(1))
    );
    b.server.handle_timeout(taken + Duration::from_millis(999));
    assert_eq!(b.drain(), Vec::<Frame>::new());
    b.server.handle_timeout(taken + Duration::from_secs(1));
    assert_eq!(b.drain(), hs(&["80 00 20 00 00 00 04 05"]));
}

#[test]
fn invalid_block_size() {
    let mut b = bench_with_name();
    // blksize 0 and 128 in the initiate.
    exchange!(b, "A4 00 20 00 00 00 00 00" => ["80 00 20 00 02 00 04 05"]);
    exchange!(b, "A4 00 20 00 80 00 00 00" => ["80 00 20 00 02 00 04 05"]);
    // blksize 0 and 128 in an acknowledgement.
    exchange!(b, "A4 00 20 00 7F 00 00 00" => ["C6 00 20 00 14 00 00 00"]);
    exchange!(b, "A3 00 00 00 00 00 00 00" => [SEG1, SEG2, SEG3_LAST]);
    exchange!(b, "A2 01 00 00 00 00 00 00" => ["80 00 20 00 02 00 04 05"]);
    exchange!(b, "A4 00 20 00 7F 00 00 00" => ["C6 00 20 00 14 00 00 00"]);
    exchange!(b, "A3 00 00 00 00 00 00 00" => [SEG1, SEG2, SEG3_LAST]);
    exchange!(b, "A2 01 80 00 00 00 00 00" => ["80 00 20 00 02 00 04 05"]);
    assert!(!b.server.is_busy());
}

#[test]
fn invalid_sequence_number() {
    // Sequence number 0.
    let mut b = Bench::new();
    exchange!(b, "C6 00 20 00 14 00 00 00" => ["A4 00 20 00 7F 00 00 00"]);
    exchange!(b, "00 41 42 43 44 45 46 47" => ["80 00 20 00 03 00 04 05"]);
    assert!(!b.server.is_busy());

    // Above the block size.
    let mut b = Bench::with(ServerConfig {
        block_size: 4,
        ..ServerConfig::default()
    });
    exchange!(b, "C6 00 20 00 14 00 00 00" => ["A4 00 20 00 04 00 00 00"]);
    exchange!(b, SEG1 => []);
    exchange!(b, "05 41 42 43 44 45 46 47" => ["80 00 20 00 03 00 04 05"]);

    // A block upload acknowledgement of more segments than were sent.
    let mut b = bench_with_name();
    exchange!(b, "A4 00 20 00 7F 00 00 00" => ["C6 00 20 00 14 00 00 00"]);
    exchange!(b, "A3 00 00 00 00 00 00 00" => [SEG1, SEG2, SEG3_LAST]);
    exchange!(b, "A2 04 7F 00 00 00 00 00" => ["80 00 20 00 03 00 04 05"]);
}

#[test]
fn crc_mismatch() {
    let mut b = Bench::new();
    let before = b.dict.clone();
    exchange!(b, "C6 00 20 00 14 00 00 00" => ["A4 00 20 00 7F 00 00 00"]);
    assert_eq!(
        b.rx_all(&[SEG1, SEG2, SEG3_LAST]),
        hs(&["A2 03 7F 00 00 00 00 00"])
    );
    exchange!(b, "C5 35 10 00 00 00 00 00" => ["80 00 20 00 04 00 04 05"]);
    assert_eq!(b.dict, before);
    assert!(!b.server.is_busy());
}

#[test]
fn announced_sizes_beyond_the_entry_or_the_domain_limit() {
    let mut b = Bench::new();
    // 0xFFFFFFFF to an unbounded DOMAIN: out of memory, for segmented and block download.
    exchange!(b, "21 03 20 00 FF FF FF FF" => ["80 03 20 00 05 00 04 05"]);
    exchange!(b, "C6 03 20 00 FF FF FF FF" => ["80 03 20 00 05 00 04 05"]);
    // One byte more than the 1 MiB limit; the limit itself is accepted.
    exchange!(b, "21 03 20 00 01 00 10 00" => ["80 03 20 00 05 00 04 05"]);
    exchange!(b, "21 03 20 00 00 00 10 00" => ["60 03 20 00 00 00 00 00"]);
    // To a 20-byte string: length too high.
    exchange!(b, "21 00 20 00 15 00 00 00" => ["80 00 20 00 12 00 07 06"]);
    exchange!(b, "21 00 20 00 FF FF FF FF" => ["80 00 20 00 12 00 07 06"]);
    exchange!(b, "C6 00 20 00 15 00 00 00" => ["80 00 20 00 12 00 07 06"]);
    // To a two-byte entry: four bytes too high, one too low.
    exchange!(b, "21 17 10 00 04 00 00 00" => ["80 17 10 00 12 00 07 06"]);
    exchange!(b, "21 17 10 00 01 00 00 00" => ["80 17 10 00 13 00 07 06"]);
    exchange!(b, "23 17 10 00 01 02 03 04" => ["80 17 10 00 12 00 07 06"]);
    assert_eq!(b.dict, dictionary());
}

#[test]
fn data_beyond_the_domain_limit_without_announcement() {
    let mut b = Bench::with(ServerConfig {
        domain_limit: 10,
        ..ServerConfig::default()
    });
    exchange!(b, "20 03 20 00 00 00 00 00" => ["60 03 20 00 00 00 00 00"]);
    exchange!(b, "00 01 02 03 04 05 06 07" => ["20 00 00 00 00 00 00 00"]);
    exchange!(b, "10 08 09 0A 0B 0C 0D 0E" => ["80 03 20 00 05 00 04 05"]);
    // Block download without size: the second full segment passes the limit.
    exchange!(b, "C0 03 20 00 00 00 00 00" => ["A4 03 20 00 7F 00 00 00"]);
    exchange!(b, "01 01 02 03 04 05 06 07" => []);
    exchange!(b, "02 08 09 0A 0B 0C 0D 0E" => ["80 03 20 00 05 00 04 05"]);
    // Ten bytes exactly fit.
    exchange!(b, "C0 03 20 00 00 00 00 00" => ["A4 03 20 00 7F 00 00 00"]);
    assert_eq!(
        b.rx_all(&["01 01 02 03 04 05 06 07", "82 08 09 0A 00 00 00 00"]),
        hs(&["A2 02 7F 00 00 00 00 00"])
    );
    // n 4.
    exchange!(b, "D1 00 00 00 00 00 00 00" => ["A1 00 00 00 00 00 00 00"]);
    assert_eq!(b.value(0x2003, 0), (1..=10).collect::<Vec<u8>>());
}

#[test]
fn data_beyond_a_string_capacity_without_announcement() {
    let mut b = Bench::new();
    exchange!(b, "20 00 20 00 00 00 00 00" => ["60 00 20 00 00 00 00 00"]);
    exchange!(b, "00 41 42 43 44 45 46 47" => ["20 00 00 00 00 00 00 00"]);
    exchange!(b, "10 48 49 4A 4B 4C 4D 4E" => ["30 00 00 00 00 00 00 00"]);
    exchange!(b, "00 4F 50 51 52 53 54 55" => ["80 00 20 00 12 00 07 06"]);
    // Block download: the third full segment makes 21 bytes.
    exchange!(b, "C0 00 20 00 00 00 00 00" => ["A4 00 20 00 7F 00 00 00"]);
    assert_eq!(b.rx_all(&[SEG1, SEG2]), Vec::<Frame>::new());
    exchange!(b, "03 4F 50 51 52 53 54 55" => ["80 00 20 00 12 00 07 06"]);
    assert_eq!(b.value(0x2000, 0), b"");
}

#[test]
fn segmented_download_longer_or_shorter_than_announced() {
    let mut b = Bench::new();
    // Five bytes announced, seven sent.
    exchange!(b, "21 00 20 00 05 00 00 00" => ["60 00 20 00 00 00 00 00"]);
    exchange!(b, "01 30 31 32 33 34 35 36" => ["80 00 20 00 12 00 07 06"]);
    // Ten announced, seven sent and the last.
    exchange!(b, "21 00 20 00 0A 00 00 00" => ["60 00 20 00 00 00 00 00"]);
    exchange!(b, "01 30 31 32 33 34 35 36" => ["80 00 20 00 13 00 07 06"]);
    assert_eq!(b.value(0x2000, 0), b"");
}

#[test]
fn block_download_end_does_not_match_the_announced_size() {
    let mut b = Bench::new();
    exchange!(b, "C6 00 20 00 14 00 00 00" => ["A4 00 20 00 7F 00 00 00"]);
    assert_eq!(
        b.rx_all(&[SEG1, SEG2, SEG3_LAST]),
        hs(&["A2 03 7F 00 00 00 00 00"])
    );
    // n 0: 21 bytes where 20 were announced.
    exchange!(b, "C1 34 10 00 00 00 00 00" => ["80 00 20 00 12 00 07 06"]);
    exchange!(b, "C6 00 20 00 14 00 00 00" => ["A4 00 20 00 7F 00 00 00"]);
    assert_eq!(
        b.rx_all(&[SEG1, SEG2, SEG3_LAST]),
        hs(&["A2 03 7F 00 00 00 00 00"])
    );
    // n 2: 19 bytes.
    exchange!(b, "C9 34 10 00 00 00 00 00" => ["80 00 20 00 13 00 07 06"]);
    // Data beyond the announced size inside the sub-block.
    exchange!(b, "C6 00 20 00 0A 00 00 00" => ["A4 00 20 00 7F 00 00 00"]);
    exchange!(b, SEG1 => []);
    exchange!(b, SEG2 => ["80 00 20 00 12 00 07 06"]);
    assert_eq!(b.value(0x2000, 0), b"");
}

#[test]
fn dictionary_refusals() {
    let mut b = Bench::new();
    // Write to read-only and constant entries, in every download mode, refused at the initiate.
    exchange!(b, "23 00 10 00 00 00 00 00" => ["80 00 10 00 02 00 01 06"]);
    exchange!(b, "21 00 10 00 04 00 00 00" => ["80 00 10 00 02 00 01 06"]);
    exchange!(b, "C6 08 10 00 04 00 00 00" => ["80 08 10 00 02 00 01 06"]);
    exchange!(b, "2F 18 10 00 01 00 00 00" => ["80 18 10 00 02 00 01 06"]);
    // Read of a write-only entry, in both upload modes.
    exchange!(b, "40 01 20 00 00 00 00 00" => ["80 01 20 00 01 00 01 06"]);
    exchange!(b, "A4 01 20 00 7F 00 00 00" => ["80 01 20 00 01 00 01 06"]);
    // No object.
    exchange!(b, "40 00 30 00 00 00 00 00" => ["80 00 30 00 00 00 02 06"]);
    exchange!(b, "2F 00 30 00 01 00 00 00" => ["80 00 30 00 00 00 02 06"]);
    exchange!(b, "21 00 30 00 04 00 00 00" => ["80 00 30 00 00 00 02 06"]);
    // No sub-index.
    exchange!(b, "40 18 10 07 00 00 00 00" => ["80 18 10 07 11 00 09 06"]);
    exchange!(b, "2B 17 10 01 00 00 00 00" => ["80 17 10 01 11 00 09 06"]);
    // Above the high limit (100) and below the low limit (10).
    exchange!(b, "2F 02 20 00 C8 00 00 00" => ["80 02 20 00 31 00 09 06"]);
    exchange!(b, "2F 02 20 00 05 00 00 00" => ["80 02 20 00 32 00 09 06"]);
    // The same refusal at the end of a segmented download.
    exchange!(b, "21 02 20 00 01 00 00 00" => ["60 02 20 00 00 00 00 00"]);
    exchange!(b, "0D C8 00 00 00 00 00 00" => ["80 02 20 00 31 00 09 06"]);
    assert_eq!(b.dict, dictionary());
    assert!(!b.server.is_busy());
}

#[test]
fn abort_from_the_client_ends_the_transfer_silently() {
    let mut b = Bench::new();
    exchange!(b, "21 00 20 00 0A 00 00 00" => ["60 00 20 00 00 00 00 00"]);
    exchange!(b, "00 30 31 32 33 34 35 36" => ["20 00 00 00 00 00 00 00"]);
    // Abort 0x08000000.
    exchange!(b, "80 00 20 00 00 00 00 08" => []);
    assert!(!b.server.is_busy());
    assert_eq!(b.server.poll_timeout(), None);
    assert_eq!(
        b.events().last(),
        Some(&ServerEvent::Aborted {
            mux: mux(0x2000, 0),
            code: AbortCode::General,
            by_client: true
        })
    );
    // The transfer is gone: a further segment does not fit.
    exchange!(b, "10 37 38 39 00 00 00 00" => ["80 37 38 39 01 00 04 05"]);
    // Inside a block download's sub-block 0x80 is an abort too.
    exchange!(b, "C6 00 20 00 14 00 00 00" => ["A4 00 20 00 7F 00 00 00"]);
    exchange!(b, SEG1 => []);
    exchange!(b, "80 00 20 00 00 00 04 05" => []);
    assert!(!b.server.is_busy());
    assert_eq!(
        b.events().last(),
        Some(&ServerEvent::Aborted {
            mux: mux(0x2000, 0),
            code: AbortCode::Timeout,
            by_client: true
        })
    );
    // While idle an abort is ignored.
    exchange!(b, "80 00 20 00 00 00 04 05" => []);
    assert_eq!(b.events(), Vec::<ServerEvent>::new());
    assert_eq!(b.value(0x2000, 0), b"");
}

#[test]
fn a_new_initiate_ends_the_old_transfer() {
    let mut b = Bench::new();
    exchange!(b, "21 00 20 00 0A 00 00 00" => ["60 00 20 00 00 00 00 00"]);
    exchange!(b, "00 30 31 32 33 34 35 36" => ["20 00 00 00 00 00 00 00"]);
    // An upload request in the middle: served; the download is dropped without an abort frame.
    exchange!(b, "40 17 10 00 00 00 00 00" => ["4B 17 10 00 00 00 00 00"]);
    assert_eq!(
        b.events(),
        [
            ServerEvent::Superseded {
                mux: mux(0x2000, 0)
            },
            ServerEvent::Uploaded {
                mux: mux(0x1017, 0)
            }
        ]
    );
    assert_eq!(b.dict, dictionary());
    // A new download of the same entry starts over with toggle 0.
    exchange!(b, "21 00 20 00 0A 00 00 00" => ["60 00 20 00 00 00 00 00"]);
    exchange!(b, "21 00 20 00 03 00 00 00" => ["60 00 20 00 00 00 00 00"]);
    exchange!(b, "09 41 42 43 00 00 00 00" => ["20 00 00 00 00 00 00 00"]);
    assert_eq!(b.value(0x2000, 0), b"ABC");
}

#[test]
fn aborted_downloads_leave_the_dictionary_as_it_was() {
    let mut b = Bench::new();
    b.dict.write(0x2000, 0, b"old").unwrap();
    b.dict.write(0x2003, 0, &[9, 9, 9]).unwrap();
    let before = b.dict.clone();
    let cases: &[&[&str]] = &[
        // Toggle error after one good segment.
        &[
            "21 00 20 00 0A 00 00 00",
            "00 30 31 32 33 34 35 36",
            "00 37 38 39 00 00 00 00",
        ],
        // Client abort.
        &[
            "21 03 20 00 0A 00 00 00",
            "00 30 31 32 33 34 35 36",
            "80 03 20 00 00 00 00 08",
        ],
        // Superseded by an upload.
        &[
            "20 00 20 00 00 00 00 00",
            "00 30 31 32 33 34 35 36",
            "40 00 20 00 00 00 00 00",
        ],
        // Block download: CRC mismatch.
        &[
            "C6 00 20 00 14 00 00 00",
            SEG1,
            SEG2,
            SEG3_LAST,
            "C5 00 00 00 00 00 00 00",
        ],
        // Block download: client abort before the end.
        &[
            "C6 00 20 00 14 00 00 00",
            SEG1,
            SEG2,
            SEG3_LAST,
            "80 00 20 00 00 00 00 08",
        ],
        // Block download: bad sequence number.
        &["C6 03 20 00 14 00 00 00", SEG1, "00 00 00 00 00 00 00 00"],
        // Too long for the string.
        &[
            "20 00 20 00 00 00 00 00",
            "00 41 42 43 44 45 46 47",
            "10 41 42 43 44 45 46 47",
            "00 41 42 43 44 45 46 47",
        ],
        // Value too high at the end.
        &["21 02 20 00 01 00 00 00", "0D C8 00 00 00 00 00 00"],
    ];
    for case in cases {
        for f in *case {
            b.rx(f);
        }
        assert_eq!(b.dict, before, "after {case:?}");
    }
    // A transfer that times out.
    b.rx("21 00 20 00 0A 00 00 00");
    b.rx("00 30 31 32 33 34 35 36");
    b.server.handle_timeout(b.now + Duration::from_secs(5));
    b.rx("19 37 38 39 00 00 00 00");
    assert_eq!(b.dict, before);
}

#[test]
fn block_size_outside_the_range_is_clamped_in_the_configuration() {
    let b = Bench::with(ServerConfig {
        block_size: 200,
        ..ServerConfig::default()
    });
    assert_eq!(b.server.config().block_size, 127);
    let b = Bench::with(ServerConfig {
        block_size: 0,
        ..ServerConfig::default()
    });
    assert_eq!(b.server.config().block_size, 1);
}

#[test]
fn a_host_that_does_not_drain_keeps_bounded_queues() {
    let mut b = Bench::new();
    for _ in 0..1000 {
        b.now += Duration::from_millis(1);
        b.server
            .handle_frame(b.now, &h("40 17 10 00 00 00 00 00"), &mut b.dict);
    }
    assert_eq!(b.drain().len(), 4);
    assert_eq!(b.events().len(), 16);
}

/// Arbitrary frames in arbitrary states never panic, and every answer is one frame or a block's worth.
#[test]
fn random_frames_never_panic() {
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mut b = Bench::with(ServerConfig {
        block_size: 8,
        domain_limit: 64,
        ..ServerConfig::default()
    });
    b.dict.write(0x2000, 0, b"ABCDEFGHIJKLMNOPQRST").unwrap();
    // Byte 0 mostly from the command specifiers a server knows, bytes 1–3 mostly real entries.
    let starts = [0x00, 0x20, 0x40, 0x60, 0x80, 0xA0, 0xC0, 0xE0];
    let entries = [
        [0x00, 0x20, 0x00],
        [0x03, 0x20, 0x00],
        [0x17, 0x10, 0x00],
        [0x08, 0x10, 0x00],
    ];
    for _ in 0..200_000 {
        let r = next();
        let mut f: Frame = (next()).to_le_bytes();
        if r & 1 == 0 {
            f[0] = starts[(r >> 1) as usize % 8] | (f[0] & 0x1F);
        }
        if r & 2 == 0 {
            f[1..4].copy_from_slice(&entries[(r >> 4) as usize % 4]);
        }
        if r & 0x700 == 0 {
            f[4] = (r >> 16) as u8 % 40;
            f[5..8].fill(0);
        }
        b.now += Duration::from_millis((r >> 24) % 400);
        b.server.handle_frame(b.now, &f, &mut b.dict);
        if r & 0xF000 == 0 {
            b.server.handle_timeout(b.now + Duration::from_secs(2));
        }
        assert!(b.drain().len() <= 128);
        b.events();
    }
}
