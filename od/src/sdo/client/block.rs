//! Block download and block upload, client side (CiA 301 §7.2.4.3.9–7.2.4.3.16).
//!
//! Download: "initiate block download" (CRC support, size) → the server's response (its CRC support,
//! `blksize`) → sub-blocks of up to `blksize` segments numbered from 1, `c = 1` on the last segment of
//! the transfer → after each sub-block the server's acknowledgement with the last sequence number it
//! received in order (`ackseq`) and the next `blksize`; the client goes on with the byte after segment
//! `ackseq`, numbering from 1 again (so a short `ackseq` resends the rest) → "end block download" with
//! the unused bytes of the last segment (`n`) and the CRC → the server's end response.
//!
//! Upload: "initiate block upload" (CRC support, `blksize`, protocol switch threshold) → the server's
//! response (CRC support, size), or a normal initiate upload response when it switches protocol →
//! "start block upload" → sub-blocks from the server, each acknowledged with the last in-order sequence
//! number → "end block upload" from the server (`n`, CRC), checked, and answered with the client's end
//! response.
//!
//! The CRC is CRC-16/XMODEM over the data bytes only ([`Crc16`]); it is used when both sides support
//! it, and is 0 in the end frame otherwise.

use crate::abort::AbortCode;
use crate::sdo::frame::{Address, BlockSegment, ClientFrame, Crc16, Frame, ServerFrame};

use super::data::{check_size, crc_update, Failure, Sink, Source};
use super::{Out, Step};

/// The largest number of segments in a sub-block.
pub const MAX_BLKSIZE: u8 = 127;

fn valid_blksize(blksize: u8) -> Result<u8, Failure> {
    if (1..=MAX_BLKSIZE).contains(&blksize) {
        Ok(blksize)
    } else {
        Err(Failure::abort(AbortCode::InvalidBlockSize))
    }
}

/// Where a block download stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum DownloadPhase {
    /// "Initiate block download" is out.
    Initiate,
    /// A sub-block is out; waiting for its acknowledgement.
    SubBlock,
    /// "End block download" is out.
    End,
}

/// A block download.
pub(super) struct BlockDownload {
    source: Source,
    crc_wanted: bool,
    /// The running CRC, when both sides use one.
    crc: Option<Crc16>,
    phase: DownloadPhase,
    blksize: u8,
    /// The bytes of the sub-block that is out and not yet acknowledged (at most 127 · 7).
    buf: Vec<u8>,
    /// Segments in the sub-block that is out.
    sent: u8,
    /// Sequence number of the transfer's last segment when it is in the sub-block that is out.
    last_seq: Option<u8>,
    /// Data bytes in the transfer's last segment, once sent.
    last_len: usize,
    /// Bytes the server acknowledged.
    acked: u64,
}

impl BlockDownload {
    /// Sends "initiate block download" with the size.
    pub fn start(mux: Address, source: Source, crc: bool, out: &mut Out) -> BlockDownload {
        out.send(ClientFrame::InitiateBlockDownload {
            mux,
            crc,
            size: Some(source.len() as u32),
        });
        BlockDownload {
            source,
            crc_wanted: crc,
            crc: None,
            phase: DownloadPhase::Initiate,
            blksize: MAX_BLKSIZE,
            buf: Vec::new(),
            sent: 0,
            last_seq: None,
            last_len: 0,
            acked: 0,
        }
    }

    /// True while the initiate request waits for its answer (a refusal then falls back to segmented).
    pub fn is_initiating(&self) -> bool {
        self.phase == DownloadPhase::Initiate
    }

    /// The data, for a segmented retry; only called while initiating, before any byte was read.
    pub fn into_source(self) -> Source {
        self.source
    }

    /// Takes a server frame (aborts are handled by the caller).
    pub fn handle(&mut self, mux: Address, frame: ServerFrame, out: &mut Out) -> Step {
        match self.step(mux, frame, out) {
            Ok(step) => step,
            Err(f) => Step::Fail(f),
        }
    }

    fn step(&mut self, mux: Address, frame: ServerFrame, out: &mut Out) -> Result<Step, Failure> {
        match (self.phase, frame) {
            (
                DownloadPhase::Initiate,
                ServerFrame::InitiateBlockDownload {
                    mux: m,
                    crc,
                    blksize,
                },
            ) if m == mux => {
                self.blksize = valid_blksize(blksize)?;
                self.crc = (self.crc_wanted && crc).then(Crc16::new);
                self.phase = DownloadPhase::SubBlock;
                self.send_sub_block(out)?;
                Ok(Step::Wait)
            }
            (DownloadPhase::SubBlock, ServerFrame::BlockDownloadAck { ackseq, blksize }) => {
                if ackseq > self.sent {
                    return Err(Failure::abort(AbortCode::InvalidSequence));
                }
                let blksize = valid_blksize(blksize)?;
                let confirmed = (ackseq as usize * 7).min(self.buf.len());
                self.buf.drain(..confirmed);
                self.acked += confirmed as u64;
                out.progress(self.acked, Some(self.source.len()));
                self.blksize = blksize;
                if matches!(self.last_seq, Some(last) if ackseq >= last) {
                    out.clear_block();
                    out.send(ClientFrame::EndBlockDownload {
                        unused: (7 - self.last_len) as u8,
                        crc: self.crc.map_or(0, |c| c.value()),
                    });
                    self.phase = DownloadPhase::End;
                } else {
                    self.send_sub_block(out)?;
                }
                Ok(Step::Wait)
            }
            (DownloadPhase::End, ServerFrame::EndBlockDownload) => {
                Ok(Step::Done(super::ClientEvent::Downloaded))
            }
            _ => Err(Failure::abort(AbortCode::InvalidCommand)),
        }
    }

    /// Queues the next sub-block: the unacknowledged bytes, topped up from the source to `blksize`
    /// segments, numbered from 1.
    fn send_sub_block(&mut self, out: &mut Out) -> Result<(), Failure> {
        out.clear_block();
        // Topped up to a whole sub-block; a buffer already that long (the block size shrank) reads
        // nothing.
        let want = self.blksize as usize * 7;
        let start = self.buf.len();
        self.source
            .read_into(&mut self.buf, want.saturating_sub(start))?;
        crc_update(&mut self.crc, &self.buf[start..]);
        let count = self.buf.len().div_ceil(7).clamp(1, self.blksize as usize);
        let exhausted = self.source.remaining() == 0;
        self.last_seq = None;
        for i in 0..count {
            let chunk = &self.buf[(i * 7).min(self.buf.len())..((i + 1) * 7).min(self.buf.len())];
            let last = exhausted && (i + 1) * 7 >= self.buf.len();
            let mut data = [0u8; 7];
            data[..chunk.len()].copy_from_slice(chunk);
            let seqno = i as u8 + 1;
            if last {
                self.last_seq = Some(seqno);
                self.last_len = chunk.len();
            }
            out.send_block(BlockSegment { seqno, last, data });
        }
        self.sent = count as u8;
        Ok(())
    }
}

/// Where a block upload stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum UploadPhase {
    /// "Initiate block upload" is out.
    Initiate,
    /// "Start block upload" or an acknowledgement is out; segments arrive.
    SubBlock,
    /// The last segment arrived and was acknowledged; waiting for "end block upload".
    End,
}

/// A block upload.
pub(super) struct BlockUpload {
    sink: Option<Sink>,
    crc_wanted: bool,
    crc: Option<Crc16>,
    /// Segments per sub-block the client asks for.
    blksize: u8,
    /// The size the server announced.
    size: Option<u32>,
    phase: UploadPhase,
    /// The sequence number expected next in order.
    expected: u8,
    /// The last segment's data, held until "end block upload" tells how much of it is data.
    held: [u8; 7],
}

impl BlockUpload {
    /// Sends "initiate block upload".
    pub fn start(
        mux: Address,
        sink: Sink,
        crc: bool,
        blksize: u8,
        pst: u8,
        out: &mut Out,
    ) -> BlockUpload {
        out.send(ClientFrame::InitiateBlockUpload {
            mux,
            crc,
            blksize,
            pst,
        });
        BlockUpload {
            sink: Some(sink),
            crc_wanted: crc,
            crc: None,
            blksize,
            size: None,
            phase: UploadPhase::Initiate,
            expected: 1,
            held: [0; 7],
        }
    }

    /// True while the initiate request waits for its answer (a refusal then falls back to a normal
    /// upload; a normal initiate upload response is a protocol switch).
    pub fn is_initiating(&self) -> bool {
        self.phase == UploadPhase::Initiate
    }

    /// True while segments arrive: then only `0x80` in byte 0 is an abort, other bytes are segments.
    pub fn receiving_segments(&self) -> bool {
        self.phase == UploadPhase::SubBlock
    }

    /// The upload target, for a normal upload after a refusal or a protocol switch.
    pub fn into_sink(self) -> Option<Sink> {
        self.sink
    }

    /// Takes a frame from the server (aborts are handled by the caller).
    pub fn handle(&mut self, mux: Address, frame: &Frame, out: &mut Out) -> Step {
        match self.step(mux, frame, out) {
            Ok(step) => step,
            Err(f) => Step::Fail(f),
        }
    }

    fn step(&mut self, mux: Address, frame: &Frame, out: &mut Out) -> Result<Step, Failure> {
        let sink = self
            .sink
            .as_mut()
            .ok_or(Failure::abort(AbortCode::General))?;
        if self.phase == UploadPhase::SubBlock {
            let seg = BlockSegment::parse(frame).map_err(Failure::abort)?;
            if seg.seqno > self.blksize {
                return Err(Failure::abort(AbortCode::InvalidSequence));
            }
            let ends_block = seg.last || seg.seqno == self.blksize;
            if seg.seqno == self.expected {
                if seg.last {
                    self.held = seg.data;
                    self.phase = UploadPhase::End;
                } else {
                    crc_update(&mut self.crc, &seg.data);
                    sink.push(&seg.data)?;
                    check_size(sink.received(), self.size, false)?;
                }
                self.expected += 1;
            }
            if ends_block {
                out.send(ClientFrame::BlockUploadAck {
                    ackseq: self.expected - 1,
                    blksize: self.blksize,
                });
                self.expected = 1;
                out.progress(sink.received(), self.size.map(u64::from));
            }
            return Ok(Step::Wait);
        }
        let frame = ServerFrame::parse(frame).map_err(Failure::abort)?;
        match (self.phase, frame) {
            (UploadPhase::Initiate, ServerFrame::InitiateBlockUpload { mux: m, crc, size })
                if m == mux =>
            {
                sink.announce(size)?;
                self.size = size;
                self.crc = (self.crc_wanted && crc).then(Crc16::new);
                self.phase = UploadPhase::SubBlock;
                self.expected = 1;
                out.send(ClientFrame::StartBlockUpload);
                Ok(Step::Wait)
            }
            (UploadPhase::End, ServerFrame::EndBlockUpload { unused, crc }) => {
                let data = &self.held[..7 - (unused as usize).min(7)];
                crc_update(&mut self.crc, data);
                sink.push(data)?;
                check_size(sink.received(), self.size, true)?;
                if self.crc.is_some_and(|c| c.value() != crc) {
                    return Err(Failure::abort(AbortCode::CrcError));
                }
                out.progress(sink.received(), self.size.map(u64::from));
                out.send(ClientFrame::EndBlockUpload);
                let sink = self.sink.take().ok_or(Failure::abort(AbortCode::General))?;
                Ok(Step::Done(sink.finish()?))
            }
            _ => Err(Failure::abort(AbortCode::InvalidCommand)),
        }
    }
}
