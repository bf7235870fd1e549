//! The master's side of one FoE transfer (ETG.1000.6 §5.9), sans-IO: [`FoeWrite`] sends a file,
//! [`FoeRead`] fetches one. Each hands out the FoE frames to put into the slave's write mailbox
//! and takes the frames the slave answers with; the caller moves them (mailbox header, counter,
//! SyncManagers) and keeps the time.
//!
//! # Methods and polling order
//!
//! [`request`](FoeWrite::request) gives the first frame (the Write or Read request); send it, and
//! give each answer (the bytes after its mailbox header) to `handle`, which says what comes next
//! ([`Next`]): another frame to send and answer, the same frame again after a pause (the slave is
//! busy), a last frame that gets no answer, or the end. An error ends the transfer; where the
//! slave still thinks it runs, [`FoeError::abort_frame`] is the Error request that ends it there.

use super::{printable, FoeErrorCode, FoeFrame, FoeFrameError};

/// What the master does after an answer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Next {
    /// Send this frame and give its answer to `handle`.
    Send(Vec<u8>),
    /// The slave is busy (`done` of `entire`, as it says): send this frame, the one before, again
    /// after a pause.
    Busy {
        /// The frame to send again.
        again: Vec<u8>,
        /// Progress: done …
        done: u16,
        /// … of entire.
        entire: u16,
    },
    /// Send this frame; no answer follows and the transfer is done (the Ack of a read's last
    /// packet).
    SendLast(Vec<u8>),
    /// The transfer is done.
    Done,
}

/// Why a transfer failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum FoeError {
    /// The slave ended it with an Error frame.
    #[error("error code 0x{:08x}: {}.{}", code.code(), code.description(), slave_text(text))]
    Refused {
        /// The code.
        code: FoeErrorCode,
        /// Its text, printable.
        text: String,
    },
    /// The answer is no FoE frame.
    #[error("the slave's answer is no FoE frame: {0}")]
    Frame(#[from] FoeFrameError),
    /// A Data packet with another number than the next.
    #[error("the slave sent packet {got}, not packet {expected}")]
    PacketNumber {
        /// The packet expected.
        expected: u32,
        /// The packet sent.
        got: u32,
    },
    /// An Ack of another packet than the one sent.
    #[error("the slave acknowledged packet {got}, not packet {expected}")]
    AckNumber {
        /// The packet sent.
        expected: u32,
        /// The packet acknowledged.
        got: u32,
    },
    /// A frame that has no place at this point (a Data frame answering a write, …).
    #[error("the slave answered with {what}, which has no place in a {transfer}")]
    Unexpected {
        /// The frame.
        what: &'static str,
        /// `write` or `read`.
        transfer: &'static str,
    },
    /// The file is longer than the reader takes.
    #[error("the file is longer than {max} bytes")]
    TooLarge {
        /// The most the reader takes.
        max: usize,
    },
}

/// ` ("text")` after a code, when the slave gave a text.
fn slave_text(text: &str) -> String {
    if text.is_empty() {
        String::new()
    } else {
        format!(" (\"{text}\")")
    }
}

impl FoeError {
    /// The Error request that ends the transfer on the slave's side, where the slave still runs it
    /// (none when the slave ended it itself).
    pub fn abort_frame(&self) -> Option<Vec<u8>> {
        let (code, text): (FoeErrorCode, &[u8]) = match self {
            FoeError::Refused { .. } => return None,
            FoeError::PacketNumber { .. } | FoeError::AckNumber { .. } => {
                (FoeErrorCode::PacketNumberWrong, b"")
            }
            FoeError::TooLarge { .. } => (FoeErrorCode::NotDefined, b"file too large"),
            FoeError::Frame(_) | FoeError::Unexpected { .. } => (FoeErrorCode::Illegal, b""),
        };
        Some(FoeFrame::Error { code, text }.to_vec())
    }
}

/// The name of an answer's frame, for [`FoeError::Unexpected`].
fn frame_name(frame: &FoeFrame<'_>) -> &'static str {
    match frame {
        FoeFrame::Read { .. } => "a Read request",
        FoeFrame::Write { .. } => "a Write request",
        FoeFrame::Data { .. } => "a Data frame",
        FoeFrame::Ack { .. } => "an Ack",
        FoeFrame::Error { .. } => "an Error",
        FoeFrame::Busy { .. } => "a Busy frame",
    }
}

/// What either transfer makes of an answer that is neither its next step nor a wrong number:
/// Busy sends `last` again, an Error is the slave's refusal, anything else is unexpected in
/// `transfer`.
fn other_answer(
    frame: FoeFrame<'_>,
    last: &[u8],
    transfer: &'static str,
) -> Result<Next, FoeError> {
    match frame {
        FoeFrame::Busy { done, entire, .. } => Ok(Next::Busy {
            again: last.to_vec(),
            done,
            entire,
        }),
        FoeFrame::Error { code, text } => Err(FoeError::Refused {
            code,
            text: printable(text),
        }),
        other => Err(FoeError::Unexpected {
            what: frame_name(&other),
            transfer,
        }),
    }
}

/// Sending one file: Write request, then Data packets of `per_packet` bytes, each acknowledged,
/// the last shorter (empty when the file is a multiple of `per_packet`).
#[derive(Debug, Clone)]
pub struct FoeWrite {
    name: Vec<u8>,
    password: u32,
    data: Vec<u8>,
    per_packet: usize,
    /// The last packet sent (0: the Write request).
    packet: u32,
    /// Where the last packet sent starts, and its length.
    at: usize,
    len: usize,
    /// The last frame sent, for a Busy answer.
    last: Vec<u8>,
}

impl FoeWrite {
    /// Sending `data` as `name` with `password`, `per_packet` bytes a packet (the slave's write
    /// mailbox less 12 bytes, [`super::data_per_packet`]; at least 1).
    pub fn new(name: &[u8], password: u32, data: Vec<u8>, per_packet: usize) -> FoeWrite {
        FoeWrite {
            name: name.to_vec(),
            password,
            data,
            per_packet: per_packet.max(1),
            packet: 0,
            at: 0,
            len: 0,
            last: Vec::new(),
        }
    }

    /// The Write request, the transfer's first frame (from the start again when called again).
    pub fn request(&mut self) -> Vec<u8> {
        (self.packet, self.at, self.len) = (0, 0, 0);
        self.last = FoeFrame::Write {
            password: self.password,
            name: &self.name,
        }
        .to_vec();
        self.last.clone()
    }

    /// The bytes the slave has acknowledged, and the file's.
    pub fn progress(&self) -> (usize, usize) {
        let acked = if self.packet == 0 { 0 } else { self.at };
        (acked, self.data.len())
    }

    /// Takes the slave's answer to the last frame sent.
    pub fn handle(&mut self, answer: &[u8]) -> Result<Next, FoeError> {
        match FoeFrame::parse(answer)? {
            FoeFrame::Ack { packet } if packet == self.packet => {
                if self.packet > 0 && self.len < self.per_packet {
                    return Ok(Next::Done);
                }
                self.at += self.len;
                self.len = self.per_packet.min(self.data.len() - self.at);
                self.packet += 1;
                self.last = FoeFrame::Data {
                    packet: self.packet,
                    data: &self.data[self.at..self.at + self.len],
                }
                .to_vec();
                Ok(Next::Send(self.last.clone()))
            }
            FoeFrame::Ack { packet } => Err(FoeError::AckNumber {
                expected: self.packet,
                got: packet,
            }),
            other => other_answer(other, &self.last, "write"),
        }
    }
}

/// Fetching one file: Read request, then the slave's Data packets, each acknowledged, until one
/// shorter than `per_packet`.
#[derive(Debug, Clone)]
pub struct FoeRead {
    name: Vec<u8>,
    password: u32,
    per_packet: usize,
    max: usize,
    data: Vec<u8>,
    /// The packet expected next.
    next: u32,
    last: Vec<u8>,
}

impl FoeRead {
    /// Fetching `name` with `password` from a slave whose read mailbox carries `per_packet` bytes
    /// a packet (its length less 12), taking `max` bytes at most.
    pub fn new(name: &[u8], password: u32, per_packet: usize, max: usize) -> FoeRead {
        FoeRead {
            name: name.to_vec(),
            password,
            per_packet: per_packet.max(1),
            max,
            data: Vec::new(),
            next: 1,
            last: Vec::new(),
        }
    }

    /// The Read request, the transfer's first frame (from the start again when called again).
    pub fn request(&mut self) -> Vec<u8> {
        self.data.clear();
        self.next = 1;
        self.last = FoeFrame::Read {
            password: self.password,
            name: &self.name,
        }
        .to_vec();
        self.last.clone()
    }

    /// The bytes received so far.
    pub fn received(&self) -> usize {
        self.data.len()
    }

    /// The file, once the transfer is done.
    pub fn into_data(self) -> Vec<u8> {
        self.data
    }

    /// Takes the slave's answer to the last frame sent.
    pub fn handle(&mut self, answer: &[u8]) -> Result<Next, FoeError> {
        match FoeFrame::parse(answer)? {
            FoeFrame::Data { packet, data } if packet == self.next => {
                if data.len() > self.max - self.data.len() {
                    return Err(FoeError::TooLarge { max: self.max });
                }
                self.data.extend_from_slice(data);
                self.next += 1;
                self.last = FoeFrame::Ack { packet }.to_vec();
                if data.len() < self.per_packet {
                    Ok(Next::SendLast(self.last.clone()))
                } else {
                    Ok(Next::Send(self.last.clone()))
                }
            }
            FoeFrame::Data { packet, .. } => Err(FoeError::PacketNumber {
                expected: self.next,
                got: packet,
            }),
            other => other_answer(other, &self.last, "read"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ack(packet: u32) -> Vec<u8> {
        let p = packet.to_le_bytes();
        vec![0x04, 0x00, p[0], p[1], p[2], p[3]]
    }

    fn data(packet: u32, bytes: &[u8]) -> Vec<u8> {
        let p = packet.to_le_bytes();
        let mut v = vec![0x03, 0x00, p[0], p[1], p[2], p[3]];
        v.extend_from_slice(bytes);
        v
    }

    /// Five bytes in packets of two: Write request `02 00 <password> name`, Ack 0, Data 1 (2
    /// bytes), Ack 1, Data 2 (2 bytes), Ack 2, Data 3 (1 byte, the last), Ack 3, done.
    #[test]
    fn a_write_in_packets_ends_with_the_short_one() {
        let mut w = FoeWrite::new(b"f", 0x0A0B_0C0D, vec![1, 2, 3, 4, 5], 2);
        assert_eq!(w.request(), [0x02, 0x00, 0x0D, 0x0C, 0x0B, 0x0A, b'f']);
        assert_eq!(w.progress(), (0, 5));
        assert_eq!(w.handle(&ack(0)), Ok(Next::Send(data(1, &[1, 2]))));
        assert_eq!(w.handle(&ack(1)), Ok(Next::Send(data(2, &[3, 4]))));
        assert_eq!(w.progress(), (2, 5));
        assert_eq!(w.handle(&ack(2)), Ok(Next::Send(data(3, &[5]))));
        assert_eq!(w.handle(&ack(3)), Ok(Next::Done));
    }

    /// A file of exactly two packets ends with an empty third; an empty file is one empty packet.
    #[test]
    fn a_multiple_ends_with_an_empty_packet() {
        let mut w = FoeWrite::new(b"f", 0, vec![1, 2, 3, 4], 2);
        w.request();
        assert_eq!(w.handle(&ack(0)), Ok(Next::Send(data(1, &[1, 2]))));
        assert_eq!(w.handle(&ack(1)), Ok(Next::Send(data(2, &[3, 4]))));
        assert_eq!(w.handle(&ack(2)), Ok(Next::Send(data(3, &[]))));
        assert_eq!(w.progress(), (4, 4));
        assert_eq!(w.handle(&ack(3)), Ok(Next::Done));
        let mut empty = FoeWrite::new(b"e", 0, Vec::new(), 2);
        empty.request();
        assert_eq!(empty.handle(&ack(0)), Ok(Next::Send(data(1, &[]))));
        assert_eq!(empty.handle(&ack(1)), Ok(Next::Done));
    }

    /// Busy answers the packet sent last: it is handed back to send again, and the Ack that comes
    /// then moves on.
    #[test]
    fn busy_sends_the_packet_again() {
        let mut w = FoeWrite::new(b"f", 0, vec![9; 3], 2);
        let request = w.request();
        let busy = [0x06, 0x00, 0x01, 0x00, 0x0A, 0x00];
        assert_eq!(
            w.handle(&busy),
            Ok(Next::Busy {
                again: request,
                done: 1,
                entire: 10
            })
        );
        assert_eq!(w.handle(&ack(0)), Ok(Next::Send(data(1, &[9, 9]))));
        assert_eq!(
            w.handle(&busy),
            Ok(Next::Busy {
                again: data(1, &[9, 9]),
                done: 1,
                entire: 10
            })
        );
        assert_eq!(w.handle(&ack(1)), Ok(Next::Send(data(2, &[9]))));
    }

    /// An Error answer ends the transfer with its code and text (no Error sent back); an Ack of
    /// another packet, a Data frame and bytes that are no frame end it with the Error request the
    /// slave is sent (0x8005, 0x8004).
    #[test]
    fn a_write_ends_on_an_error_or_a_wrong_answer() {
        let mut w = FoeWrite::new(b"f", 0, vec![1; 3], 2);
        w.request();
        let e = w
            .handle(&[0x05, 0x00, 0x09, 0x80, 0x00, 0x00, b'b'])
            .unwrap_err();
        assert_eq!(
            e,
            FoeError::Refused {
                code: FoeErrorCode::NotBootstrap,
                text: "b".into()
            }
        );
        assert_eq!(
            e.to_string(),
            "error code 0x00008009: Not Bootstrap. (\"b\")"
        );
        assert_eq!(e.abort_frame(), None);
        let e = w.handle(&ack(4)).unwrap_err();
        assert_eq!(
            e,
            FoeError::AckNumber {
                expected: 0,
                got: 4
            }
        );
        assert_eq!(
            e.abort_frame(),
            Some(vec![0x05, 0x00, 0x05, 0x80, 0x00, 0x00])
        );
        let e = w.handle(&data(1, &[])).unwrap_err();
        assert_eq!(
            e.to_string(),
            "the slave answered with a Data frame, which has no place in a write"
        );
        assert_eq!(
            e.abort_frame(),
            Some(vec![0x05, 0x00, 0x04, 0x80, 0x00, 0x00])
        );
        assert!(matches!(
            w.handle(&[0x04, 0x00]),
            Err(FoeError::Frame(FoeFrameError::Truncated { got: 2 }))
        ));
        let refused = FoeError::Refused {
            code: FoeErrorCode::NotFound,
            text: String::new(),
        };
        assert_eq!(refused.to_string(), "error code 0x00008001: Not found.");
    }

    /// A read of five bytes in packets of two: Read request, Data 1 → Ack 1, Data 2 → Ack 2, Data 3
    /// (1 byte) → Ack 3 sent last; the file is the five bytes.
    #[test]
    fn a_read_in_packets_acknowledges_each() {
        let mut r = FoeRead::new(b"ab", 7, 2, 100);
        assert_eq!(
            r.request(),
            [0x01, 0x00, 0x07, 0x00, 0x00, 0x00, b'a', b'b']
        );
        assert_eq!(r.handle(&data(1, &[1, 2])), Ok(Next::Send(ack(1))));
        assert_eq!(r.handle(&data(2, &[3, 4])), Ok(Next::Send(ack(2))));
        assert_eq!(r.received(), 4);
        assert_eq!(r.handle(&data(3, &[5])), Ok(Next::SendLast(ack(3))));
        assert_eq!(r.into_data(), [1, 2, 3, 4, 5]);
        let mut r = FoeRead::new(b"ab", 7, 2, 100);
        r.request();
        assert_eq!(r.handle(&data(1, &[])), Ok(Next::SendLast(ack(1))));
        assert_eq!(r.into_data(), Vec::<u8>::new());
    }

    /// A packet out of order, a file over the maximum, an Error and an Ack end a read; a Busy asks
    /// for the last frame again.
    #[test]
    fn a_read_ends_on_a_wrong_packet_or_too_much() {
        let mut r = FoeRead::new(b"x", 0, 2, 3);
        let request = r.request();
        assert_eq!(
            r.handle(&[0x06, 0x00, 0x00, 0x00, 0x00, 0x00]),
            Ok(Next::Busy {
                again: request,
                done: 0,
                entire: 0
            })
        );
        assert_eq!(
            r.handle(&data(2, &[1, 2])),
            Err(FoeError::PacketNumber {
                expected: 1,
                got: 2
            })
        );
        assert_eq!(r.handle(&data(1, &[1, 2])), Ok(Next::Send(ack(1))));
        let e = r.handle(&data(2, &[3, 4])).unwrap_err();
        assert_eq!(e, FoeError::TooLarge { max: 3 });
        let mut abort = vec![0x05, 0x00, 0x00, 0x80, 0x00, 0x00];
        abort.extend_from_slice(b"file too large");
        assert_eq!(e.abort_frame(), Some(abort));
        assert_eq!(r.handle(&data(2, &[3])), Ok(Next::SendLast(ack(2))));
        assert!(matches!(
            r.handle(&ack(1)),
            Err(FoeError::Unexpected {
                what: "an Ack",
                transfer: "read"
            })
        ));
        assert!(matches!(
            r.handle(&[0x05, 0x00, 0x01, 0x80, 0x00, 0x00]),
            Err(FoeError::Refused {
                code: FoeErrorCode::NotFound,
                ..
            })
        ));
    }
}
