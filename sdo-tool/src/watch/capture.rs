//! Captures in pcapng (Wireshark's, dumpcap's, `--capture`'s) as `decode` reads them: every
//! classic CAN frame of every SocketCAN interface in the file (`LINKTYPE_CAN_SOCKETCAN`), in file
//! order, with its time from its block; what is no such frame is counted ([`CaptureSummary`]),
//! not decoded.

use std::io::{self, Read};
use std::time::SystemTime;

use crate::link::pcapng::{ReadError, Reader, LINKTYPE_CAN_SOCKETCAN};
use crate::link::{CanFrame, NotClassic};

/// The first four bytes of a pcapng file (a Section Header Block's type).
pub const PCAPNG_MAGIC: [u8; 4] = [0x0A, 0x0D, 0x0D, 0x0A];

/// What a capture held besides the CAN frames decoded.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CaptureSummary {
    /// Interfaces of every section, as `NAME (link type N)`, in order.
    pub interfaces: Vec<String>,
    /// SocketCAN interfaces among them.
    pub can_interfaces: usize,
    /// Packets of other links (Ethernet, …): skipped.
    pub other_links: u64,
    /// SocketCAN packets that are no classic frame: how many, the first one's number (from 1,
    /// counting every packet) and what it is.
    pub not_classic: u64,
    /// The first of them.
    pub first_not_classic: Option<(u64, NotClassic)>,
    /// Packets of an interface the file does not describe, or blocks too long to read: skipped.
    pub unreadable: u64,
    /// Where the file ends inside a block (a capture cut short): the block's offset.
    pub cut_at: Option<u64>,
}

/// The CAN frames of a capture, one at a time, each with its time in seconds since the first
/// frame's.
pub struct CaptureFrames<R> {
    reader: Reader<R>,
    first: Option<SystemTime>,
    last: f64,
    packets: u64,
    summary: CaptureSummary,
    ended: bool,
}

impl<R: Read> CaptureFrames<R> {
    /// The frames of the capture `input` holds, from its first byte.
    pub fn new(input: R) -> CaptureFrames<R> {
        CaptureFrames {
            reader: Reader::new(input),
            first: None,
            last: 0.0,
            packets: 0,
            summary: CaptureSummary::default(),
            ended: false,
        }
    }

    /// The next frame; `None` at the end of the capture (or where it is cut short). A file that
    /// is no pcapng, or a block that does not fit the format, is an error of kind `InvalidData`
    /// naming the block's offset.
    pub fn next_frame(&mut self) -> io::Result<Option<(f64, CanFrame)>> {
        loop {
            if self.ended {
                return Ok(None);
            }
            let packet = match self.reader.next_packet() {
                Ok(Some(p)) => p,
                Ok(None) => {
                    self.end();
                    return Ok(None);
                }
                Err(ReadError::Truncated { offset }) => {
                    self.summary.cut_at = Some(offset);
                    self.end();
                    return Ok(None);
                }
                Err(ReadError::Io(e)) => return Err(e),
                Err(e) => return Err(io::Error::new(io::ErrorKind::InvalidData, e)),
            };
            self.packets += 1;
            if packet.link_type != LINKTYPE_CAN_SOCKETCAN {
                self.summary.other_links += 1;
                continue;
            }
            let frame = match CanFrame::from_socketcan_bytes(packet.data) {
                Ok(frame) => frame,
                Err(why) => {
                    self.summary.not_classic += 1;
                    let number = self.packets;
                    self.summary.first_not_classic.get_or_insert((number, why));
                    continue;
                }
            };
            // A packet without a time (a Simple Packet Block) is taken at the last one's.
            if let Some(at) = packet.time {
                let first = *self.first.get_or_insert(at);
                self.last = match at.duration_since(first) {
                    Ok(d) => d.as_secs_f64(),
                    Err(e) => -e.duration().as_secs_f64(),
                };
            }
            return Ok(Some((self.last, frame)));
        }
    }

    fn end(&mut self) {
        self.ended = true;
        let seen = self.reader.interfaces_seen();
        self.summary.interfaces = seen
            .iter()
            .map(|i| {
                format!(
                    "{} (link type {})",
                    i.name.as_deref().unwrap_or("no name"),
                    i.link_type
                )
            })
            .collect();
        self.summary.can_interfaces = seen
            .iter()
            .filter(|i| i.link_type == LINKTYPE_CAN_SOCKETCAN)
            .count();
        self.summary.unreadable = self.reader.unknown_interface() + self.reader.skipped();
    }

    /// What the capture held besides the frames, complete once [`CaptureFrames::next_frame`] gave
    /// `None`.
    pub fn summary(&self) -> &CaptureSummary {
        &self.summary
    }
}
