//! Logs in candump's format (`candump -L`): a frame as a line, a line as a frame, a log read line
//! by line in bounded memory, and [`LogDecoder`], which names each frame of one, or of a pcapng
//! capture ([`super::capture`]).

use std::collections::VecDeque;
use std::io::BufRead;

use super::capture::{CaptureFrames, CaptureSummary};
use super::{OpenTransfer, Watcher};
use crate::link::CanFrame;

/// A `candump -L` line: `(SECONDS.MICROS) IFACE ID#DATA`, with the time in seconds, the frame in
/// the notation can-utils writes and reads back ([`crate::raw::cansend_frame`]: 3 or 8 identifier
/// digits, as canplayer takes them). Anything else (a time that is no finite number, a frame that
/// is none, CAN FD) is none.
pub fn candump_line(line: &str) -> Option<(f64, CanFrame)> {
    let (ts, rest) = line.trim().strip_prefix('(')?.split_once(") ")?;
    let t: f64 = ts.parse().ok().filter(|t: &f64| t.is_finite())?;
    let (_, frame) = rest.trim().split_once(' ')?;
    Some((t, crate::raw::cansend_frame(frame).ok()?))
}

/// The longest line of a log [`LogLines`] hands on, in bytes (a `candump -L` line of a classic
/// frame is under 60); a longer one is skipped without being kept.
pub const MAX_LOG_LINE: usize = 4096;

/// A line of a log as [`LogLines`] reads it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogLine<'a> {
    /// The line's bytes, without its line end.
    Text(&'a [u8]),
    /// A line longer than the limit: its bytes were read past, not kept.
    TooLong,
}

/// The lines of a log read in bounded memory: a line is kept only up to a limit; the rest of a
/// longer one is read and dropped as it comes, whatever its length, so that no line is ever held
/// whole.
pub struct LogLines<R> {
    input: R,
    line: Vec<u8>,
    max: usize,
    number: u64,
}

impl<R: BufRead> LogLines<R> {
    /// The lines of `input`, each kept up to `max` bytes.
    pub fn new(input: R, max: usize) -> LogLines<R> {
        LogLines {
            input,
            line: Vec::new(),
            max,
            number: 0,
        }
    }

    /// The next line with its number (from 1); `None` at the end of the input. The last line may
    /// have no line end.
    pub fn next_line(&mut self) -> std::io::Result<Option<(u64, LogLine<'_>)>> {
        self.line.clear();
        let mut too_long = false;
        let mut any = false;
        loop {
            let buf = match self.input.fill_buf() {
                Ok(b) => b,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            if buf.is_empty() {
                if !any {
                    return Ok(None);
                }
                break;
            }
            any = true;
            let (part, used, end) = match buf.iter().position(|&b| b == b'\n') {
                Some(i) => (&buf[..i], i + 1, true),
                None => (buf, buf.len(), false),
            };
            if !too_long {
                if self.line.len() + part.len() <= self.max {
                    self.line.extend_from_slice(part);
                } else {
                    too_long = true;
                    self.line.clear();
                }
            }
            self.input.consume(used);
            if end {
                break;
            }
        }
        self.number += 1;
        let line = if too_long {
            LogLine::TooLong
        } else {
            LogLine::Text(&self.line)
        };
        Ok(Some((self.number, line)))
    }
}

/// What [`LogDecoder`] makes of a log, one at a time.
#[derive(Debug, Clone, PartialEq)]
pub enum Decoded {
    /// A line about the bus at `t`, in seconds since the log's first frame.
    Line {
        /// Seconds since the log's first frame.
        t: f64,
        /// What the watcher says.
        text: String,
    },
    /// At the end of the log: an SDO transfer still going on (`t`: the log's last frame).
    Open {
        /// The log's last frame, in seconds since its first.
        t: f64,
        /// The transfer.
        transfer: OpenTransfer,
    },
    /// Line `line` (from 1) is longer than [`MAX_LOG_LINE`]: no frame, skipped unread.
    TooLong {
        /// The line's number, from 1.
        line: u64,
    },
}

/// Where a decoder's frames come from.
enum Source<R> {
    /// A `candump -L` log, line by line.
    Candump(LogLines<R>),
    /// A pcapng capture, packet by packet.
    Pcapng(CaptureFrames<R>),
}

/// `sdo-tool decode`: a `candump -L` log read line by line in bounded memory (or a pcapng capture
/// packet by packet, [`LogDecoder::pcapng`]) through a [`Watcher`], pulled one [`Decoded`] at a
/// time; at the end, the transfers left open.
pub struct LogDecoder<R> {
    source: Source<R>,
    watcher: Watcher,
    /// The first frame's time, the last frame's (since the first).
    first: Option<f64>,
    last: f64,
    queue: VecDeque<Decoded>,
    ended: bool,
    not_frames: u64,
    first_not_frame: Option<u64>,
}

impl<R: BufRead> LogDecoder<R> {
    /// Decodes the candump log `input` with `watcher`.
    pub fn new(input: R, watcher: Watcher) -> LogDecoder<R> {
        LogDecoder::from_source(Source::Candump(LogLines::new(input, MAX_LOG_LINE)), watcher)
    }

    /// Decodes the pcapng capture `input` with `watcher`: every classic CAN frame of its SocketCAN
    /// interfaces, its time from its block.
    pub fn pcapng(input: R, watcher: Watcher) -> LogDecoder<R> {
        LogDecoder::from_source(Source::Pcapng(CaptureFrames::new(input)), watcher)
    }

    fn from_source(source: Source<R>, watcher: Watcher) -> LogDecoder<R> {
        LogDecoder {
            source,
            watcher,
            first: None,
            last: 0.0,
            queue: VecDeque::new(),
            ended: false,
            not_frames: 0,
            first_not_frame: None,
        }
    }

    /// The next thing decoded; `None` once the log and its open transfers are all told.
    pub fn next_event(&mut self) -> std::io::Result<Option<Decoded>> {
        loop {
            if let Some(d) = self.queue.pop_front() {
                return Ok(Some(d));
            }
            if self.ended {
                return Ok(None);
            }
            let next = match &mut self.source {
                Source::Candump(lines) => match lines.next_line()? {
                    None => None,
                    Some((number, LogLine::TooLong)) => {
                        self.queue.push_back(Decoded::TooLong { line: number });
                        continue;
                    }
                    Some((number, LogLine::Text(bytes))) => {
                        let text = String::from_utf8_lossy(bytes);
                        let Some((t, frame)) = candump_line(&text) else {
                            if !text.trim().is_empty() {
                                self.not_frames += 1;
                                self.first_not_frame.get_or_insert(number);
                            }
                            continue;
                        };
                        Some((t - *self.first.get_or_insert(t), frame))
                    }
                },
                Source::Pcapng(frames) => frames.next_frame()?,
            };
            let Some((t, frame)) = next else {
                self.ended = true;
                let t = self.last;
                self.queue.extend(
                    self.watcher
                        .open_transfers()
                        .into_iter()
                        .map(|transfer| Decoded::Open { t, transfer }),
                );
                continue;
            };
            self.last = t;
            let lines = self.watcher.at(t, &frame);
            self.queue
                .extend(lines.into_iter().map(|text| Decoded::Line { t, text }));
        }
    }

    /// The lines of at most [`MAX_LOG_LINE`] bytes that were no frame (blank lines aside): how
    /// many, and the first one's number.
    pub fn not_frames(&self) -> (u64, Option<u64>) {
        (self.not_frames, self.first_not_frame)
    }

    /// For a pcapng capture, what it held besides the frames decoded (complete at its end).
    pub fn capture_summary(&self) -> Option<&CaptureSummary> {
        match &self.source {
            Source::Pcapng(frames) => Some(frames.summary()),
            Source::Candump(_) => None,
        }
    }
}

/// `frame` as a `candump -L` line received at `at` on `iface`.
pub fn candump(at: std::time::SystemTime, iface: &str, frame: &CanFrame) -> String {
    let t = at.duration_since(std::time::UNIX_EPOCH).unwrap_or_default();
    format!("({}.{:06}) {iface} {frame}", t.as_secs(), t.subsec_micros())
}
