//! The typed, blocking SDO session over a scripted in-memory transport: a fake that checks each frame
//! the client sends against the next line of a script (bytes written from the CiA 301 §7.2.4.3
//! layouts) and answers with that line's prepared server frames. Its clock stands still until the
//! client waits with nothing to receive; then it jumps to the end of the wait.

use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use od::sdo::{
    Address, ClientConfig, Crc16, Frame, SdoClientError, SdoSession, SdoTransport, SessionError,
};
use od::{AbortCode, DataType, Value, ValueError};

fn frame(hex: &str) -> Frame {
    let bytes: Vec<u8> = hex
        .split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).unwrap())
        .collect();
    bytes.try_into().expect("eight bytes")
}

fn hex(f: &Frame) -> String {
    f.iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// A frame of byte 0 and up to seven data bytes, padded with zeros.
fn seg(byte0: u8, data: &[u8]) -> Frame {
    let mut f = [0u8; 8];
    f[0] = byte0;
    f[1..1 + data.len()].copy_from_slice(data);
    f
}

/// One line of a script: what the client must send, and what the server answers to it.
struct Line {
    expect: Frame,
    replies: Vec<Frame>,
}

/// The scripted transport.
struct Script {
    lines: VecDeque<Line>,
    inbox: VecDeque<Frame>,
    sent: Vec<String>,
    t0: Instant,
    now: Instant,
    /// Sends fail from this frame on (counting from 0).
    fail_send_at: Option<usize>,
    /// A flag this transport sets once its clock has run this long (a Ctrl-C during a wait).
    cancel_after: Option<(Duration, Arc<AtomicBool>)>,
}

impl Script {
    fn new() -> Script {
        let t0 = Instant::now();
        Script {
            lines: VecDeque::new(),
            inbox: VecDeque::new(),
            sent: Vec::new(),
            t0,
            now: t0,
            fail_send_at: None,
            cancel_after: None,
        }
    }

    /// The client sends `expect`; the server answers `replies`.
    fn line(mut self, expect: &str, replies: &[&str]) -> Script {
        self.lines.push_back(Line {
            expect: frame(expect),
            replies: replies.iter().map(|r| frame(r)).collect(),
        });
        self
    }

    fn line_frames(mut self, expect: Frame, replies: Vec<Frame>) -> Script {
        self.lines.push_back(Line { expect, replies });
        self
    }

    fn session(self) -> SdoSession<Script> {
        SdoSession::new(self, ClientConfig::default())
    }
}

impl SdoTransport for Script {
    type Error = io::Error;

    fn send(&mut self, f: &Frame) -> io::Result<()> {
        if self.fail_send_at == Some(self.sent.len()) {
            return Err(io::Error::new(io::ErrorKind::BrokenPipe, "bus off"));
        }
        self.sent.push(hex(f));
        let line = self
            .lines
            .pop_front()
            .unwrap_or_else(|| panic!("unscripted frame {}", hex(f)));
        assert_eq!(hex(f), hex(&line.expect), "frame {}", self.sent.len());
        self.inbox.extend(line.replies);
        Ok(())
    }

    fn recv(&mut self, until: Instant) -> io::Result<Option<Frame>> {
        match self.inbox.pop_front() {
            Some(f) => Ok(Some(f)),
            None => {
                self.now = self.now.max(until);
                if let Some((after, flag)) = &self.cancel_after {
                    if self.now - self.t0 >= *after {
                        flag.store(true, Ordering::Relaxed);
                    }
                }
                Ok(None)
            }
        }
    }

    fn now(&self) -> Instant {
        self.now
    }
}

/// Asserts the whole script was played.
fn played(s: &SdoSession<Script>) {
    assert!(
        s.transport.lines.is_empty(),
        "{} lines left",
        s.transport.lines.len()
    );
    assert!(s.transport.inbox.is_empty());
    assert!(!s.client.is_busy());
}

const HEARTBEAT: Address = Address::new(0x1017, 0);
const DEVICE_TYPE: Address = Address::new(0x1000, 0);
const DOMAIN: Address = Address::new(0x2000, 1);

#[test]
fn write_u16_is_one_expedited_exchange() {
    let mut s = Script::new()
        .line("2B 17 10 00 E8 03 00 00", &["60 17 10 00 00 00 00 00"])
        .session();
    s.write_u16(HEARTBEAT, 1000).unwrap();
    played(&s);
}

#[test]
fn typed_writes() {
    let mux = Address::new(0x2100, 2);
    let ok = "60 00 21 02 00 00 00 00";
    let mut s = Script::new()
        .line("2F 00 21 02 FF 00 00 00", &[ok]) // u8 255
        .line("2F 00 21 02 80 00 00 00", &[ok]) // i8 -128
        .line("2B 00 21 02 FE FF 00 00", &[ok]) // i16 -2
        .line("23 00 21 02 78 56 34 12", &[ok]) // u32
        .line("23 00 21 02 FF FF FF FF", &[ok]) // i32 -1
        .line("23 00 21 02 00 00 C0 3F", &[ok]) // f32 1.5
        .line("2F 00 21 02 01 00 00 00", &[ok]) // true
        .session();
    s.write_u8(mux, 255).unwrap();
    s.write_i8(mux, -128).unwrap();
    s.write_i16(mux, -2).unwrap();
    s.write_u32(mux, 0x1234_5678).unwrap();
    s.write_i32(mux, -1).unwrap();
    s.write_f32(mux, 1.5).unwrap();
    s.write_bool(mux, true).unwrap();
    played(&s);
}

#[test]
fn eight_byte_writes_go_by_block_download() {
    let v = 0x0102_0304_0506_0708u64;
    let data = v.to_le_bytes();
    let [lo, hi] = Crc16::of(&data).to_le_bytes();
    let mut s = Script::new()
        .line("C6 00 21 00 08 00 00 00", &["A4 00 21 00 7F 00 00 00"])
        .line_frames(seg(0x01, &data[..7]), vec![])
        .line_frames(
            seg(0x82, &data[7..]),
            vec![frame("A2 02 7F 00 00 00 00 00")],
        )
        // n 6: the last segment holds one byte.
        .line_frames(seg(0xD9, &[lo, hi]), vec![frame("A1 00 00 00 00 00 00 00")])
        .session();
    s.write_u64(Address::new(0x2100, 0), v).unwrap();
    played(&s);
}

#[test]
fn typed_reads() {
    let mut s = Script::new()
        .line("40 00 10 00 00 00 00 00", &["43 00 10 00 92 01 02 00"])
        .line("40 17 10 00 00 00 00 00", &["4B 17 10 00 E8 03 00 00"])
        .line("40 00 21 01 00 00 00 00", &["4F 00 21 01 FF 00 00 00"])
        .line("40 00 21 02 00 00 00 00", &["4B 00 21 02 FE FF 00 00"])
        .line("40 00 21 03 00 00 00 00", &["43 00 21 03 00 00 C0 BF"])
        .line("40 00 21 04 00 00 00 00", &["4F 00 21 04 01 00 00 00"])
        .line("40 00 21 05 00 00 00 00", &["4F 00 21 05 80 00 00 00"])
        .session();
    assert_eq!(s.read_u32(DEVICE_TYPE).unwrap(), 0x0002_0192);
    assert_eq!(s.read_u16(HEARTBEAT).unwrap(), 1000);
    assert_eq!(s.read_u8(Address::new(0x2100, 1)).unwrap(), 255);
    assert_eq!(s.read_i16(Address::new(0x2100, 2)).unwrap(), -2);
    assert_eq!(s.read_f32(Address::new(0x2100, 3)).unwrap(), -1.5);
    assert!(s.read_bool(Address::new(0x2100, 4)).unwrap());
    assert_eq!(s.read_i8(Address::new(0x2100, 5)).unwrap(), -128);
    played(&s);
}

#[test]
fn eight_byte_read_falls_back_when_the_server_refuses_block_upload() {
    let mut s = Script::new()
        .line("A4 00 21 00 7F 00 00 00", &["80 00 21 00 01 00 04 05"])
        .line("40 00 21 00 00 00 00 00", &["41 00 21 00 08 00 00 00"])
        // -1.5 as REAL64 is 0xBFF8_0000_0000_0000: seven bytes, then one (toggle 1, n 6, c 1).
        .line("60 00 00 00 00 00 00 00", &["00 00 00 00 00 00 00 F8"])
        .line("70 00 00 00 00 00 00 00", &["1D BF 00 00 00 00 00 00"])
        .session();
    assert_eq!(s.read_f64(Address::new(0x2100, 0)).unwrap(), -1.5);
    played(&s);
}

#[test]
fn a_wrong_length_is_a_value_error() {
    let mut s = Script::new()
        .line("40 17 10 00 00 00 00 00", &["43 17 10 00 E8 03 00 00"])
        .session();
    match s.read_u16(HEARTBEAT) {
        Err(SessionError::Value(ValueError::TooLong {
            data_type: DataType::Unsigned16,
            expected: 2,
            got: 4,
        })) => {}
        other => panic!("{other:?}"),
    }
    played(&s);
}

#[test]
fn a_short_answer_is_a_value_error() {
    let mut s = Script::new()
        .line("40 00 21 00 00 00 00 00", &["4B 00 21 00 E8 03 00 00"])
        .session();
    match s.read_u32(Address::new(0x2100, 0)) {
        Err(SessionError::Value(ValueError::TooShort {
            data_type: DataType::Unsigned32,
            expected: 4,
            got: 2,
        })) => {}
        other => panic!("{other:?}"),
    }
    played(&s);
}

#[test]
fn read_and_write_values() {
    let mux = Address::new(0x2100, 7);
    let mut s = Script::new()
        .line("40 00 21 07 00 00 00 00", &["4B 00 21 07 FE FF 00 00"])
        .line("2B 00 21 07 2C 01 00 00", &["60 00 21 07 00 00 00 00"])
        .session();
    assert_eq!(
        s.read_value(mux, DataType::Integer16).unwrap(),
        Value::Int(-2)
    );
    s.write_value(mux, &Value::Uint(300), DataType::Unsigned16)
        .unwrap();
    // A value that does not fit its type is refused before anything is sent.
    assert!(matches!(
        s.write_value(mux, &Value::Uint(300), DataType::Unsigned8),
        Err(SessionError::Value(ValueError::OutOfRange { .. }))
    ));
    played(&s);
}

#[test]
fn strings() {
    let name = Address::new(0x1008, 0);
    let data = b"hello world";
    let [lo, hi] = Crc16::of(data).to_le_bytes();
    let mut s = Script::new()
        // A segmented upload of "X67\0\0" (NUL padding is cut).
        .line("A4 08 10 00 7F 00 00 00", &["41 08 10 00 05 00 00 00"])
        .line("60 00 00 00 00 00 00 00", &["05 58 36 37 00 00 00 00"])
        // Eleven bytes by block download.
        .line("C6 08 10 00 0B 00 00 00", &["A4 08 10 00 7F 00 00 00"])
        .line_frames(seg(0x01, &data[..7]), vec![])
        .line_frames(
            seg(0x82, &data[7..]),
            vec![frame("A2 02 7F 00 00 00 00 00")],
        )
        .line_frames(seg(0xCD, &[lo, hi]), vec![frame("A1 00 00 00 00 00 00 00")])
        .session();
    assert_eq!(s.read_string(name).unwrap(), "X67");
    s.write_string(name, "hello world").unwrap();
    played(&s);

    // Bytes that are no UTF-8 are Latin-1: B0 is the degree sign.
    let mut s = Script::new()
        .line("A4 08 10 00 7F 00 00 00", &["4B 08 10 00 B0 43 00 00"])
        .session();
    assert_eq!(s.read_string(name).unwrap(), "\u{B0}C");
    played(&s);
}

#[test]
fn server_abort_is_an_sdo_error() {
    let mut s = Script::new()
        .line("2B 17 10 00 E8 03 00 00", &["80 17 10 00 02 00 01 06"])
        .session();
    match s.write_u16(HEARTBEAT, 1000) {
        Err(SessionError::Sdo(SdoClientError::Aborted {
            index: 0x1017,
            sub: 0,
            code: AbortCode::ReadOnly,
            by_server: true,
        })) => {}
        other => panic!("{other:?}"),
    }
    played(&s);
}

#[test]
fn silence_times_out_after_the_configured_time() {
    let mut s = Script::new()
        .line("40 00 10 00 00 00 00 00", &[])
        .line("80 00 10 00 00 00 04 05", &[])
        .session();
    match s.read_u32(DEVICE_TYPE) {
        Err(SessionError::Sdo(SdoClientError::Aborted {
            code: AbortCode::Timeout,
            by_server: false,
            ..
        })) => {}
        other => panic!("{other:?}"),
    }
    assert_eq!(s.transport.now, s.transport.t0 + Duration::from_secs(1));
    played(&s);
}

/// The script of a block upload of `data` (sub-blocks of 127 segments), with CRC.
fn block_upload_script(mux: &str, data: &[u8]) -> Script {
    let size = (data.len() as u32).to_le_bytes();
    let mut script = Script::new().line(
        &format!("A4 {mux} 7F 00 00 00"),
        &[&format!(
            "C6 {mux} {:02X} {:02X} {:02X} {:02X}",
            size[0], size[1], size[2], size[3]
        )],
    );
    let chunks: Vec<&[u8]> = data.chunks(7).collect();
    let mut start = frame("A3 00 00 00 00 00 00 00");
    for (b, block) in chunks.chunks(127).enumerate() {
        let last_block = b == chunks.len().div_ceil(127) - 1;
        let mut replies = Vec::new();
        for (i, chunk) in block.iter().enumerate() {
            let last = last_block && i == block.len() - 1;
            replies.push(seg((i as u8 + 1) | if last { 0x80 } else { 0 }, chunk));
        }
        script = script.line_frames(start, replies);
        start = seg(0xA2, &[block.len() as u8, 0x7F]);
    }
    let n = 7 - chunks.last().map_or(0, |c| c.len()) as u8;
    let [lo, hi] = Crc16::of(data).to_le_bytes();
    script
        .line_frames(start, vec![seg(0xC1 | n << 2, &[lo, hi])])
        .line("A1 00 00 00 00 00 00 00", &[])
}

/// A cancel flag already set: the upload's request (a block upload of 127 segments) goes out and is
/// aborted at once with 0x08000000 (`80 00 20 01 00 00 00 08`); it ends with `Cancelled` and leaves
/// the client idle.
#[test]
fn a_cancelled_upload_is_aborted_with_0x08000000() {
    let flag = Arc::new(AtomicBool::new(true));
    let mut s = Script::new()
        .line("A4 00 20 01 7F 00 00 00", &[])
        .line("80 00 20 01 00 00 00 08", &[])
        .session()
        .with_cancel(Arc::clone(&flag));
    let mut out = Vec::new();
    assert!(matches!(
        s.upload_to(DOMAIN, &mut out, |_, _| {}),
        Err(SessionError::Cancelled)
    ));
    assert!(out.is_empty());
    played(&s);
}

/// A flag set while the client waits for the server (here 200 ms into a wait of 1 s) ends the
/// transfer within the next look at the flag (50 ms): the abort is 0x08000000, not the timeout's
/// 0x05040000, and it leaves 200 to 250 ms after the request.
#[test]
fn a_cancel_during_a_wait_aborts_before_the_timeout() {
    let flag = Arc::new(AtomicBool::new(false));
    let mut script = Script::new()
        .line("A4 00 20 01 7F 00 00 00", &[])
        .line("80 00 20 01 00 00 00 08", &[]);
    script.cancel_after = Some((Duration::from_millis(200), Arc::clone(&flag)));
    let mut s = script.session().with_cancel(Arc::clone(&flag));
    assert!(matches!(
        s.upload_to(DOMAIN, &mut Vec::new(), |_, _| {}),
        Err(SessionError::Cancelled)
    ));
    let waited = s.transport.now - s.transport.t0;
    assert!(
        (Duration::from_millis(200)..=Duration::from_millis(250)).contains(&waited),
        "{waited:?}"
    );
    played(&s);
}

#[test]
fn upload_to_a_writer_with_progress() {
    let data: Vec<u8> = (0..1000u32).map(|i| (i * 31 % 256) as u8).collect();
    let mut s = block_upload_script("00 20 01", &data).session();
    let mut out = Vec::new();
    let mut reports = Vec::new();
    let n = s
        .upload_to(DOMAIN, &mut out, |done, total| reports.push((done, total)))
        .unwrap();
    assert_eq!(n, 1000);
    assert_eq!(out, data);
    // 1000 bytes = 142 full segments + 6: one report per sub-block and one at the end.
    assert_eq!(
        reports,
        [(889, Some(1000)), (994, Some(1000)), (1000, Some(1000))]
    );
    played(&s);
}

/// The script of a block download of `data` (the server takes 127 segments per sub-block), with CRC.
fn block_download_script(mux: &str, data: &[u8]) -> Script {
    let size = (data.len() as u32).to_le_bytes();
    let mut script = Script::new().line(
        &format!(
            "C6 {mux} {:02X} {:02X} {:02X} {:02X}",
            size[0], size[1], size[2], size[3]
        ),
        &[&format!("A4 {mux} 7F 00 00 00")],
    );
    let chunks: Vec<&[u8]> = data.chunks(7).collect();
    let blocks = chunks.len().div_ceil(127);
    for (b, block) in chunks.chunks(127).enumerate() {
        for (i, chunk) in block.iter().enumerate() {
            let end = i == block.len() - 1;
            let last = b == blocks - 1 && end;
            let replies = if end {
                vec![seg(0xA2, &[block.len() as u8, 0x7F])]
            } else {
                vec![]
            };
            script = script.line_frames(
                seg((i as u8 + 1) | if last { 0x80 } else { 0 }, chunk),
                replies,
            );
        }
    }
    let n = 7 - chunks.last().map_or(0, |c| c.len()) as u8;
    let [lo, hi] = Crc16::of(data).to_le_bytes();
    script.line_frames(
        seg(0xC1 | n << 2, &[lo, hi]),
        vec![frame("A1 00 00 00 00 00 00 00")],
    )
}

/// A reader that gives at most 5 bytes per read.
struct Slow<'a>(&'a [u8]);

impl Read for Slow<'_> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = buf.len().min(5).min(self.0.len());
        buf[..n].copy_from_slice(&self.0[..n]);
        self.0 = &self.0[n..];
        Ok(n)
    }
}

#[test]
fn download_from_a_reader_with_progress() {
    let data: Vec<u8> = (0..2000u32).map(|i| (i * 17 % 253) as u8).collect();
    let mut s = block_download_script("00 20 01", &data).session();
    let mut reports = Vec::new();
    s.download_from(DOMAIN, &mut Slow(&data), 2000, |done, total| {
        reports.push((done, total))
    })
    .unwrap();
    // 2000 bytes = 285 full segments + 5: sub-blocks of 889, 889 and 222 bytes.
    assert_eq!(
        reports,
        [(889, Some(2000)), (1778, Some(2000)), (2000, Some(2000))]
    );
    played(&s);
}

/// A reader that logs the size of every read asked of it and is interrupted at its second read.
struct Logged<'a> {
    data: &'a [u8],
    asked: Vec<usize>,
}

impl Read for Logged<'_> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.asked.push(buf.len());
        if self.asked.len() == 2 {
            return Err(io::ErrorKind::Interrupted.into());
        }
        let n = buf.len().min(self.data.len());
        buf[..n].copy_from_slice(&self.data[..n]);
        self.data = &self.data[n..];
        Ok(n)
    }
}

#[test]
fn download_from_reads_the_length_given_and_one_sub_block_ahead() {
    let data: Vec<u8> = (0..1500u32).map(|i| (i * 7 % 251) as u8).collect();
    let mut s = block_download_script("00 20 01", &data[..1000]).session();
    let mut reader = Logged {
        data: &data,
        asked: Vec::new(),
    };
    s.download_from(DOMAIN, &mut reader, 1000, |_, _| {})
        .unwrap();
    played(&s);
    // Exactly 1000 bytes were taken from the reader; the rest is left to its owner.
    assert_eq!(reader.data, &data[1000..]);
    // Before the transfer starts, one sub-block of 889 bytes is read ahead (reads of at most 256
    // bytes, the interrupted one asked again), no more; then the 111 left.
    assert_eq!(reader.asked[..5], [256, 256, 256, 256, 121]);
    assert_eq!(reader.asked[5..], [111]);
}

#[test]
fn a_reader_that_ends_early_aborts_the_download() {
    let data = [9u8; 10];
    let mut s = Script::new()
        .line("C6 00 20 01 14 00 00 00", &["A4 00 20 01 7F 00 00 00"])
        .session();
    match s.download_from(DOMAIN, &mut &data[..], 20, |_, _| {}) {
        Err(SessionError::Read(e)) => assert_eq!(e.kind(), io::ErrorKind::UnexpectedEof),
        other => panic!("{other:?}"),
    }
    // The early end is seen before the initiate goes out: nothing was sent.
    assert!(s.transport.sent.is_empty());
    assert!(!s.client.is_busy());
}

/// A reader that fails after its first bytes.
struct Failing {
    given: usize,
}

impl Read for Failing {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.given >= 889 {
            return Err(io::Error::other("disk gone"));
        }
        let n = buf.len().min(889 - self.given);
        buf[..n].fill(1);
        self.given += n;
        Ok(n)
    }
}

#[test]
fn a_failing_reader_aborts_the_download_on_the_wire() {
    let mut script = Script::new().line("C6 00 20 01 E8 03 00 00", &["A4 00 20 01 7F 00 00 00"]);
    for i in 1..=127u8 {
        script = script.line_frames(seg(i, &[1; 7]), vec![]);
    }
    // The reader fails when the session refills after the first sub-block: 0x08000000 (general
    // error).
    let mut s = script.line("80 00 20 01 00 00 00 08", &[]).session();
    match s.download_from(DOMAIN, &mut Failing { given: 0 }, 1000, |_, _| {}) {
        Err(SessionError::Read(e)) => assert_eq!(e.to_string(), "disk gone"),
        other => panic!("{other:?}"),
    }
    played(&s);
}

struct FullDisk;

impl Write for FullDisk {
    fn write(&mut self, _: &[u8]) -> io::Result<usize> {
        Err(io::Error::other("disk full"))
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

#[test]
fn a_failing_writer_aborts_the_upload_on_the_wire() {
    let mut s = Script::new()
        .line("A4 00 20 01 7F 00 00 00", &["C6 00 20 01 14 00 00 00"])
        .line(
            "A3 00 00 00 00 00 00 00",
            &["01 01 02 03 04 05 06 07", "02 01 02 03 04 05 06 07"],
        )
        // 0x08000020: data cannot be stored.
        .line("80 00 20 01 20 00 00 08", &[])
        .session();
    match s.upload_to(DOMAIN, &mut FullDisk, |_, _| {}) {
        Err(SessionError::Write(e)) => assert_eq!(e.to_string(), "disk full"),
        other => panic!("{other:?}"),
    }
    assert!(!s.client.is_busy());
    // The second segment is still in the transport; the script is otherwise played.
    assert!(s.transport.lines.is_empty());
}

#[test]
fn a_transport_failure_gives_the_transfer_up() {
    let mut script = Script::new();
    script.fail_send_at = Some(0);
    let mut s = script.session();
    assert!(matches!(
        s.read_u32(DEVICE_TYPE),
        Err(SessionError::Transport(_))
    ));
    assert!(!s.client.is_busy());
    assert_eq!(s.client.poll_transmit(), None);
    assert_eq!(s.client.poll_event().map(|_| ()), None);
}

#[test]
fn a_busy_client_refuses() {
    let mut s = Script::new().session();
    s.client.start_upload(s.transport.now, DEVICE_TYPE).unwrap();
    assert!(matches!(
        s.read_u32(DEVICE_TYPE),
        Err(SessionError::Sdo(SdoClientError::Busy))
    ));
}
