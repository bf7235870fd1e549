//! The socketcand protocol as text: elements `< … >` cut from a byte stream, parsed into typed
//! commands (client → server) and messages (server → client), and emitted again.
//!
//! What is spoken (socketcand's `doc/protocol.md`, raw mode):
//! - server: `< hi >` on connect; `< ok >` or `< error TEXT >` after each mode command;
//!   `< frame ID SECONDS.MICROSECONDS DATA >` for each frame in raw mode, `DATA` one unbroken hex
//!   string (`< frame 585 1700000000.123456 4F171000 >`); `< echo >` back to `< echo >`.
//! - client: `< open CHANNEL >`, `< rawmode >`, `< bcmmode >`, `< echo >`,
//!   `< send ID DLC B0 B1 … >` with the data bytes as separate hex numbers, upper or lower case,
//!   with or without a leading zero (python-can writes `< send 605 8 2f 17 10 0 64 0 0 0 >`).
//!
//! An identifier written with 8 hex digits is a 29-bit one (socketcand's rule), shorter ones are
//! 11-bit. Remote frames (`R` after the identifier's digits is not part of the protocol) are not
//! carried: socketcand's raw mode has none.

use std::fmt::Write as _;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use crate::frame::CanFrame;

/// The longest element accepted (`< frame 1FFFFFFF 4294967295.999999 0011223344556677 >` is 52 bytes;
/// `< error … >` texts are short). Longer input is refused and skipped.
pub const MAX_ELEMENT: usize = 256;

/// Why an element did not parse.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum CodecError {
    /// Text outside `< … >`, or an element that never closes within [`MAX_ELEMENT`] bytes.
    #[error("bytes outside an element `< … >`: {0:?}")]
    Framing(String),
    /// A known command or message with wrong arguments.
    #[error("bad `{command}` element {element:?}: {reason}")]
    Arguments {
        /// The command word.
        command: String,
        /// The whole element.
        element: String,
        /// What was wrong.
        reason: String,
    },
}

/// Cuts complete `< … >` elements out of a byte stream.
#[derive(Debug, Default)]
pub struct Splitter {
    buf: Vec<u8>,
}

impl Splitter {
    /// An empty splitter.
    pub fn new() -> Splitter {
        Splitter::default()
    }

    /// Adds received bytes.
    pub fn push(&mut self, bytes: &[u8]) {
        self.buf.extend_from_slice(bytes);
    }

    /// The next complete element (the text between `<` and `>`, trimmed), or a framing error for
    /// stray bytes, which are dropped. `None` when more bytes are needed.
    ///
    /// An element is the bytes from a `<` to the first `>` with no `<` between: a `<` that is not
    /// closed before the next `<` is stray, so it cannot swallow the element after it. A run of
    /// stray bytes (however long, within [`MAX_ELEMENT`]) is one error, dropped at once.
    pub fn next_element(&mut self) -> Option<Result<String, CodecError>> {
        // Whitespace between elements is allowed.
        let skip = self
            .buf
            .iter()
            .take_while(|b| b.is_ascii_whitespace())
            .count();
        self.buf.drain(..skip);
        if self.buf.is_empty() {
            return None;
        }
        if self.buf[0] != b'<' {
            let end = self
                .buf
                .iter()
                .position(|&b| b == b'<')
                .unwrap_or(self.buf.len());
            let junk: Vec<u8> = self.buf.drain(..end).collect();
            return Some(Err(CodecError::Framing(truncated(&junk))));
        }
        let window = &self.buf[..self.buf.len().min(MAX_ELEMENT)];
        let close = window.iter().position(|&b| b == b'>');
        // The element's start: the last '<' before its '>' (or before the window's end).
        let open = window[..close.unwrap_or(window.len())]
            .iter()
            .rposition(|&b| b == b'<')
            .unwrap_or(0);
        if open > 0 {
            let junk: Vec<u8> = self.buf.drain(..open).collect();
            return Some(Err(CodecError::Framing(truncated(&junk))));
        }
        match close {
            Some(end) => {
                let inner = lossy(&self.buf[1..end]).trim().to_string();
                self.buf.drain(..=end);
                Some(Ok(inner))
            }
            None if self.buf.len() >= MAX_ELEMENT => {
                // Never closes within the bound: dropped whole.
                let junk: Vec<u8> = self.buf.drain(..MAX_ELEMENT).collect();
                Some(Err(CodecError::Framing(truncated(&junk))))
            }
            None => None,
        }
    }

    /// Bytes held waiting for the rest of an element.
    pub fn pending(&self) -> usize {
        self.buf.len()
    }
}

fn lossy(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn truncated(bytes: &[u8]) -> String {
    let mut s = lossy(&bytes[..bytes.len().min(40)]);
    if bytes.len() > 40 {
        s.push_str("...");
    }
    s
}

/// `text` as printable ASCII for an element: `<`, `>`, `\` and control bytes as `\xNN`, anything
/// beyond ASCII as `\u{…}`, at most 120 characters of it (then `...`), so that an answer never
/// carries a byte a client cannot decode or a bracket that ends the element early.
pub fn ascii_text(text: &str) -> String {
    let mut out = String::new();
    for (k, c) in text.chars().enumerate() {
        if k == 120 {
            out.push_str("...");
            break;
        }
        match c {
            '<' | '>' | '\\' => {
                let _ = write!(out, "\\x{:02x}", c as u32);
            }
            ' '..='~' => out.push(c),
            c if c.is_ascii() => {
                let _ = write!(out, "\\x{:02x}", c as u32);
            }
            c => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
        }
    }
    out
}

/// What a client says to the server.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Command {
    /// `< open CHANNEL >`.
    Open(String),
    /// `< rawmode >`: every frame of the bus is sent to this client.
    RawMode,
    /// `< bcmmode >`: back to the broadcast-manager mode (no frames sent unasked).
    BcmMode,
    /// `< controlmode >`, `< isotpmode >`: modes this server does not offer.
    OtherMode(String),
    /// `< echo >`.
    Echo,
    /// `< send ID DLC DATA… >`.
    Send(CanFrame),
    /// Any other command word (BCM jobs, statistics): answered with an error, the session goes on.
    Unsupported(String),
}

/// What the server says to a client.
#[derive(Debug, Clone, PartialEq)]
pub enum Message {
    /// `< hi >`.
    Hi,
    /// `< ok >`.
    Ok,
    /// `< echo >`.
    Echo,
    /// `< error TEXT >`.
    Error(String),
    /// `< frame ID TIME DATA >`.
    Frame {
        /// The frame.
        frame: CanFrame,
        /// When the server received it.
        at: SystemTime,
    },
    /// Anything else (`< stat … >` and the like): ignored by a raw-mode client.
    Other(String),
}

fn args_error(command: &str, element: &str, reason: impl Into<String>) -> CodecError {
    CodecError::Arguments {
        command: command.to_string(),
        element: element.to_string(),
        reason: reason.into(),
    }
}

/// Parses a hex CAN identifier: 8 digits = 29-bit, fewer = 11-bit.
fn parse_id(text: &str) -> Result<(u32, bool), String> {
    if text.is_empty() || text.len() > 8 || !text.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(format!("identifier {text:?} is not 1 to 8 hex digits"));
    }
    let id = u32::from_str_radix(text, 16).map_err(|e| e.to_string())?;
    let extended = text.len() == 8;
    let max = if extended { 0x1FFF_FFFF } else { 0x7FF };
    if id > max {
        return Err(format!(
            "identifier {text} is above {max:X} for a {}-bit identifier",
            if extended { 29 } else { 11 }
        ));
    }
    Ok((id, extended))
}

fn make_frame(id: u32, extended: bool, data: &[u8]) -> Option<CanFrame> {
    if extended {
        CanFrame::new_extended(id, data)
    } else {
        CanFrame::new(id as u16, data)
    }
}

impl Command {
    /// Parses the inside of one element (what [`Splitter::next_element`] returns).
    pub fn parse(element: &str) -> Result<Command, CodecError> {
        let mut words = element.split_ascii_whitespace();
        let Some(word) = words.next() else {
            return Ok(Command::Unsupported(String::new()));
        };
        let rest: Vec<&str> = words.collect();
        let no_args = |c: Command| {
            if rest.is_empty() {
                Ok(c)
            } else {
                Err(args_error(word, element, "takes no arguments"))
            }
        };
        match word {
            "open" => match rest.as_slice() {
                [channel] if channel.len() <= 32 => Ok(Command::Open(channel.to_string())),
                [_] => Err(args_error(word, element, "channel name over 32 characters")),
                _ => Err(args_error(word, element, "expected one channel name")),
            },
            "rawmode" => no_args(Command::RawMode),
            "bcmmode" => no_args(Command::BcmMode),
            "controlmode" | "isotpmode" => no_args(Command::OtherMode(word.to_string())),
            "echo" => no_args(Command::Echo),
            "send" => {
                let [id, dlc, data @ ..] = rest.as_slice() else {
                    return Err(args_error(word, element, "expected ID DLC [DATA…]"));
                };
                let (id, extended) = parse_id(id).map_err(|r| args_error(word, element, r))?;
                let dlc: usize = dlc
                    .parse()
                    .ok()
                    .filter(|n| *n <= 8)
                    .ok_or_else(|| args_error(word, element, "DLC is not 0 to 8"))?;
                if data.len() != dlc {
                    return Err(args_error(
                        word,
                        element,
                        format!("DLC {dlc} but {} data bytes", data.len()),
                    ));
                }
                let mut bytes = [0u8; 8];
                for (b, t) in bytes.iter_mut().zip(data) {
                    *b = (t.len() <= 2)
                        .then(|| u8::from_str_radix(t, 16).ok())
                        .flatten()
                        .ok_or_else(|| {
                            args_error(word, element, format!("data byte {t:?} is not hex 00-FF"))
                        })?;
                }
                let frame = make_frame(id, extended, &bytes[..dlc])
                    .ok_or_else(|| args_error(word, element, "not a CAN frame"))?;
                Ok(Command::Send(frame))
            }
            other => Ok(Command::Unsupported(other.to_string())),
        }
    }

    /// The element as a client writes it (`< send 605 8 40 18 10 01 00 00 00 00 >`).
    pub fn emit(&self) -> String {
        match self {
            Command::Open(c) => format!("< open {c} >"),
            Command::RawMode => "< rawmode >".into(),
            Command::BcmMode => "< bcmmode >".into(),
            Command::OtherMode(m) => format!("< {m} >"),
            Command::Echo => "< echo >".into(),
            Command::Send(f) => {
                let mut s = String::with_capacity(48);
                s.push_str("< send ");
                push_id(&mut s, f);
                let _ = write!(s, " {}", f.len());
                for b in f.data() {
                    let _ = write!(s, " {b:02X}");
                }
                s.push_str(" >");
                s
            }
            Command::Unsupported(w) => format!("< {w} >"),
        }
    }
}

fn push_id(s: &mut String, f: &CanFrame) {
    if f.is_extended() {
        let _ = write!(s, "{:08X}", f.raw_id());
    } else {
        let _ = write!(s, "{:03X}", f.raw_id());
    }
}

/// Parses `SECONDS.MICROSECONDS` (the fraction may have 1–9 digits, or be absent).
fn parse_time(text: &str) -> Option<SystemTime> {
    let (secs, frac) = text.split_once('.').unwrap_or((text, ""));
    if secs.is_empty() || !secs.bytes().all(|b| b.is_ascii_digit()) || frac.len() > 9 {
        return None;
    }
    if !frac.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let secs: u64 = secs.parse().ok()?;
    let nanos: u32 = if frac.is_empty() {
        0
    } else {
        frac.parse::<u32>().ok()? * 10u32.pow(9 - frac.len() as u32)
    };
    UNIX_EPOCH.checked_add(Duration::new(secs, nanos))
}

impl Message {
    /// Parses the inside of one element.
    pub fn parse(element: &str) -> Result<Message, CodecError> {
        let mut words = element.split_ascii_whitespace();
        let word = words.next().unwrap_or("");
        let rest: Vec<&str> = words.collect();
        match word {
            "hi" => Ok(Message::Hi),
            "ok" => Ok(Message::Ok),
            "echo" => Ok(Message::Echo),
            "error" => Ok(Message::Error(rest.join(" "))),
            "frame" => {
                let [id, time, data @ ..] = rest.as_slice() else {
                    return Err(args_error(word, element, "expected ID TIME [DATA]"));
                };
                let (id, extended) = parse_id(id).map_err(|r| args_error(word, element, r))?;
                let at = parse_time(time)
                    .ok_or_else(|| args_error(word, element, "time is not SECONDS.MICROSECONDS"))?;
                // One hex string; tolerate the bytes split by spaces too.
                let hex: String = data.concat();
                if !hex.len().is_multiple_of(2)
                    || hex.len() > 16
                    || !hex.bytes().all(|b| b.is_ascii_hexdigit())
                {
                    return Err(args_error(word, element, "data is not 0 to 8 bytes of hex"));
                }
                let bytes: Vec<u8> = (0..hex.len())
                    .step_by(2)
                    .map(|i| u8::from_str_radix(&hex[i..i + 2], 16).unwrap_or(0))
                    .collect();
                let frame = make_frame(id, extended, &bytes)
                    .ok_or_else(|| args_error(word, element, "not a CAN frame"))?;
                Ok(Message::Frame { frame, at })
            }
            _ => Ok(Message::Other(element.to_string())),
        }
    }

    /// The element as the server writes it (`< frame 585 1700000000.123456 4F171000 >`).
    pub fn emit(&self) -> String {
        match self {
            Message::Hi => "< hi >".into(),
            Message::Ok => "< ok >".into(),
            Message::Echo => "< echo >".into(),
            Message::Error(t) => format!("< error {} >", ascii_text(t)),
            Message::Frame { frame, at } => frame_element(frame, *at),
            Message::Other(t) => format!("< {t} >"),
        }
    }
}

/// `< frame ID SECONDS.MICROSECONDS DATA >` for `frame` received at `at`.
pub fn frame_element(frame: &CanFrame, at: SystemTime) -> String {
    let t = at.duration_since(UNIX_EPOCH).unwrap_or_default();
    let mut s = String::with_capacity(56);
    s.push_str("< frame ");
    push_id(&mut s, frame);
    let _ = write!(s, " {}.{:06} ", t.as_secs(), t.subsec_micros());
    for b in frame.data() {
        let _ = write!(s, "{b:02X}");
    }
    s.push_str(" >");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(id: u16, data: &[u8]) -> CanFrame {
        CanFrame::new(id, data).unwrap()
    }

    #[test]
    fn splits_elements_across_reads_and_reports_junk() {
        let mut s = Splitter::new();
        s.push(b"< hi >< op");
        assert_eq!(s.next_element(), Some(Ok("hi".into())));
        assert_eq!(s.next_element(), None);
        s.push(b"en can0 >\n  junk< echo >");
        assert_eq!(s.next_element(), Some(Ok("open can0".into())));
        assert_eq!(
            s.next_element(),
            Some(Err(CodecError::Framing("junk".into())))
        );
        assert_eq!(s.next_element(), Some(Ok("echo".into())));
        assert_eq!(s.next_element(), None);
        assert_eq!(s.pending(), 0);
    }

    /// A `<` not closed before the next `<` is stray: it cannot swallow the element after it.
    #[test]
    fn an_unclosed_element_does_not_swallow_the_next() {
        let mut s = Splitter::new();
        s.push(b"< junk < open can0 >");
        assert_eq!(
            s.next_element(),
            Some(Err(CodecError::Framing("< junk ".into())))
        );
        assert_eq!(s.next_element(), Some(Ok("open can0".into())));
        assert_eq!(s.next_element(), None);
    }

    /// A run of stray `<` is dropped a window at a time: 1,001 of them before `echo>` are four
    /// errors (255, 255, 255 and 235 bytes), then the element.
    #[test]
    fn a_run_of_stray_brackets_is_dropped_a_window_at_a_time() {
        let mut s = Splitter::new();
        s.push(&[b'<'; 1001]);
        s.push(b"echo>");
        let mut sizes = Vec::new();
        loop {
            match s.next_element() {
                Some(Err(CodecError::Framing(t))) => sizes.push(t),
                Some(Ok(e)) => {
                    assert_eq!(e, "echo");
                    break;
                }
                other => panic!("{other:?}"),
            }
        }
        let forty = format!("{}...", "<".repeat(40));
        assert_eq!(sizes, [forty.clone(), forty.clone(), forty.clone(), forty]);
        assert_eq!(s.pending(), 0);
    }

    /// Answers carry printable ASCII only: brackets, backslashes, control bytes and what is beyond
    /// ASCII are escaped, and a long text is cut.
    #[test]
    fn error_texts_are_printable_ascii() {
        assert_eq!(
            ascii_text("\u{e9}<x>\\\u{1}"),
            "\\u{e9}\\x3cx\\x3e\\x5c\\x01"
        );
        assert_eq!(
            ascii_text(&"a".repeat(130)),
            format!("{}...", "a".repeat(120))
        );
        let mut s = Splitter::new();
        s.push(&[0xFF, 0xFE, b'<', b'e', b'c', b'h', b'o', b'>']);
        let Some(Err(e)) = s.next_element() else {
            panic!("stray bytes");
        };
        let answer = Message::Error(e.to_string()).emit();
        assert!(answer.is_ascii(), "{answer}");
        assert_eq!(
            answer,
            "< error bytes outside an element `\\x3c \\u{2026} \\x3e`: \"\\u{fffd}\\u{fffd}\" >"
        );
    }

    #[test]
    fn an_element_that_never_closes_is_dropped_within_the_bound() {
        let mut s = Splitter::new();
        s.push(&[b'<'; 1000]);
        let mut errors = 0;
        while let Some(e) = s.next_element() {
            assert!(e.is_err());
            errors += 1;
        }
        assert!(errors > 0);
        assert!(s.pending() < MAX_ELEMENT);
        s.push(b">< ok >");
        // Whatever remains of the long element is junk; the next element parses.
        let mut last = None;
        while let Some(e) = s.next_element() {
            last = Some(e);
        }
        assert_eq!(last, Some(Ok("ok".into())));
    }

    #[test]
    fn send_as_python_can_writes_it() {
        assert_eq!(
            Command::parse("send 605 8 2f 17 10 0 64 0 0 0"),
            Ok(Command::Send(f(
                0x605,
                &[0x2F, 0x17, 0x10, 0, 0x64, 0, 0, 0]
            )))
        );
        assert_eq!(
            Command::parse("send 000 2 01 00"),
            Ok(Command::Send(f(0, &[1, 0])))
        );
        assert_eq!(Command::parse("send 80 0"), Ok(Command::Send(f(0x80, &[]))));
        assert_eq!(
            Command::parse("send 1234ABCD 1 ff"),
            Ok(Command::Send(
                CanFrame::new_extended(0x1234_ABCD, &[0xFF]).unwrap()
            ))
        );
    }

    #[test]
    fn send_refusals_name_the_fault() {
        for (text, reason) in [
            ("send", "expected ID DLC"),
            ("send 800 0", "above 7FF"),
            ("send 3FFFFFFFF 0", "1 to 8 hex digits"),
            ("send 2FFFFFFF 0", "above 1FFFFFFF"),
            ("send 605 9 0 0 0 0 0 0 0 0 0", "DLC is not 0 to 8"),
            ("send 605 2 00", "DLC 2 but 1 data bytes"),
            ("send 605 1 100", "not hex 00-FF"),
            ("send 60g 0", "hex digits"),
            ("open", "one channel name"),
            ("rawmode now", "takes no arguments"),
        ] {
            let e = Command::parse(text).unwrap_err();
            assert!(e.to_string().contains(reason), "{text}: {e}");
        }
    }

    #[test]
    fn commands_round_trip() {
        for c in [
            Command::Open("vcan0".into()),
            Command::RawMode,
            Command::BcmMode,
            Command::Echo,
            Command::Send(f(0x605, &[0x40, 0x18, 0x10, 1, 0, 0, 0, 0])),
            Command::Send(CanFrame::new_extended(0x18FF_0001, &[]).unwrap()),
        ] {
            let text = c.emit();
            let mut s = Splitter::new();
            s.push(text.as_bytes());
            let inner = s.next_element().unwrap().unwrap();
            assert_eq!(Command::parse(&inner), Ok(c), "{text}");
        }
        assert_eq!(
            Command::Send(f(0x605, &[0x40, 0x18, 0x10, 1])).emit(),
            "< send 605 4 40 18 10 01 >"
        );
    }

    #[test]
    fn frame_message_golden_text() {
        let at = UNIX_EPOCH + Duration::new(1_700_000_000, 123_456_789);
        let m = Message::Frame {
            frame: f(0x585, &[0x4F, 0x17, 0x10, 0]),
            at,
        };
        assert_eq!(m.emit(), "< frame 585 1700000000.123456 4F171000 >");
        assert_eq!(
            frame_element(&f(0x701, &[]), UNIX_EPOCH + Duration::from_micros(5)),
            "< frame 701 0.000005  >"
        );
        assert_eq!(
            Message::parse("frame 585 1700000000.123456 4F171000"),
            Ok(Message::Frame {
                frame: f(0x585, &[0x4F, 0x17, 0x10, 0]),
                at: UNIX_EPOCH + Duration::new(1_700_000_000, 123_456_000),
            })
        );
        assert_eq!(
            Message::parse("frame 701 12.5"),
            Ok(Message::Frame {
                frame: f(0x701, &[]),
                at: UNIX_EPOCH + Duration::new(12, 500_000_000),
            })
        );
        assert_eq!(
            Message::parse("frame 701 1.000000 05"),
            Ok(Message::Frame {
                frame: f(0x701, &[5]),
                at: UNIX_EPOCH + Duration::from_secs(1),
            })
        );
    }

    #[test]
    fn server_messages() {
        assert_eq!(Message::parse("hi"), Ok(Message::Hi));
        assert_eq!(Message::parse("ok"), Ok(Message::Ok));
        assert_eq!(
            Message::parse("error could not open bus"),
            Ok(Message::Error("could not open bus".into()))
        );
        assert_eq!(
            Message::parse("stat 1 2 3"),
            Ok(Message::Other("stat 1 2 3".into()))
        );
        for bad in [
            "frame",
            "frame 585 x 00",
            "frame 585 1.0 0",
            "frame 585 1.0 001122334455667788",
        ] {
            assert!(Message::parse(bad).is_err(), "{bad}");
        }
    }

    proptest::proptest! {
        /// Any bytes, cut anywhere: no panic, bounded memory, and a well-formed element after the
        /// junk still parses.
        #[test]
        fn any_bytes_are_split_and_parsed_without_panic(
            junk in proptest::collection::vec(proptest::num::u8::ANY, 0..2000),
            cut in 0usize..2000,
        ) {
            let mut s = Splitter::new();
            let cut = cut.min(junk.len());
            let mut last = None;
            for part in [&junk[..cut], &junk[cut..], b"> < send 123 1 AB >".as_slice()] {
                s.push(part);
                while let Some(e) = s.next_element() {
                    if let Ok(text) = &e {
                        let _ = Command::parse(text);
                        let _ = Message::parse(text);
                    }
                    last = Some(e);
                }
                proptest::prop_assert!(s.pending() < MAX_ELEMENT);
            }
            let last = last.expect("an element").expect("the last element parses");
            proptest::prop_assert_eq!(
                Command::parse(&last),
                Ok(Command::Send(CanFrame::new(0x123, &[0xAB]).unwrap()))
            );
        }
    }
}
