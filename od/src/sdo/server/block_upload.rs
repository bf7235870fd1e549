//! SDO block upload, server side (CiA 301 §7.2.4.3.13 "Initiate SDO block upload", §7.2.4.3.14 "Upload
//! SDO block", §7.2.4.3.15 "End SDO block upload"; protocol in §7.2.4.3.16).
//!
//! The segments of a sub-block are not queued: [`BlockUpload::next_segment`] makes each one when the host
//! polls, so a sub-block of 127 segments takes no more memory than the value itself.

use super::{upload, Reply, ServerConfig, ServerEvent, Step, Transfer};
use crate::abort::AbortCode;
use crate::sdo::frame::{Address, BlockSegment, ClientFrame, Crc16, Frame, ServerFrame};
use crate::sdo::store::ObjectStore;

/// Data bytes of one block segment.
const SEGMENT_DATA: usize = 7;

/// The block sizes CiA 301 allows.
const BLOCK_SIZES: std::ops::RangeInclusive<u8> = 1..=127;

/// Initiate block upload: checks the client's block size, reads the entry and answers with the size, or,
/// when the value is no longer than the client's protocol switch threshold, with a normal initiate upload
/// response (CiA 301 §7.2.4.3.13: pst).
pub(super) fn initiate(
    mux: Address,
    crc: bool,
    blksize: u8,
    pst: u8,
    store: &mut impl ObjectStore,
    config: &ServerConfig,
) -> Step {
    if !BLOCK_SIZES.contains(&blksize) {
        return Err(AbortCode::InvalidBlockSize);
    }
    let data = store.upload(mux)?;
    if pst > 0 && data.len() <= pst as usize {
        return Ok(upload::respond(mux, data));
    }
    let size = u32::try_from(data.len()).ok();
    Ok(Reply::send(ServerFrame::InitiateBlockUpload {
        mux,
        crc: config.crc,
        size,
    })
    .then(Transfer::BlockUpload(BlockUpload {
        mux,
        crc: crc && config.crc,
        data,
        blksize,
        phase: Phase::Initiated,
        first: 0,
        count: 0,
        next_seq: 1,
    })))
}

/// Where a block upload stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// Initiate answered; waiting for the client's start.
    Initiated,
    /// Sending a sub-block and waiting for its acknowledgement.
    Sending,
    /// End block upload request sent; waiting for the client's response.
    Ending,
}

/// A block upload.
#[derive(Debug, Clone)]
pub(super) struct BlockUpload {
    /// The entry.
    pub(super) mux: Address,
    /// True when both sides use the CRC.
    crc: bool,
    /// The value.
    data: Vec<u8>,
    /// Segments per sub-block, from the client (initiate, then each acknowledgement).
    blksize: u8,
    phase: Phase,
    /// Index (from 0, over the whole value) of the sub-block's first segment.
    first: usize,
    /// Segments in the sub-block.
    count: u8,
    /// The sequence number of the next segment to send (1 to `count`; `count + 1` when all are sent).
    next_seq: u8,
}

impl BlockUpload {
    /// Segments of the whole value: at least one, which is empty for an empty value.
    fn segments(&self) -> usize {
        self.data.len().div_ceil(SEGMENT_DATA).max(1)
    }

    /// Starts a sub-block at segment `first`.
    fn start_sub_block(&mut self) {
        let left = self.segments().saturating_sub(self.first);
        self.count = left.min(self.blksize as usize) as u8;
        self.next_seq = 1;
        self.phase = Phase::Sending;
    }

    /// The next frame of the transfer: the start, an acknowledgement of a sub-block, or the end response.
    pub(super) fn frame(mut self, frame: ClientFrame) -> Step {
        match (self.phase, frame) {
            (Phase::Initiated, ClientFrame::StartBlockUpload) => {
                self.start_sub_block();
                Ok(Reply::default().then(Transfer::BlockUpload(self)))
            }
            (Phase::Sending, ClientFrame::BlockUploadAck { ackseq, blksize }) => {
                if ackseq > self.count {
                    return Err(AbortCode::InvalidSequence);
                }
                if !BLOCK_SIZES.contains(&blksize) {
                    return Err(AbortCode::InvalidBlockSize);
                }
                // The client resumes after the last segment it received in order.
                self.first += ackseq as usize;
                self.blksize = blksize;
                if self.first < self.segments() {
                    self.start_sub_block();
                    return Ok(Reply::default().then(Transfer::BlockUpload(self)));
                }
                self.phase = Phase::Ending;
                let unused = (self.segments() * SEGMENT_DATA - self.data.len()) as u8;
                let crc = if self.crc { Crc16::of(&self.data) } else { 0 };
                Ok(Reply::send(ServerFrame::EndBlockUpload { unused, crc })
                    .then(Transfer::BlockUpload(self)))
            }
            (Phase::Ending, ClientFrame::EndBlockUpload) => {
                Ok(Reply::default().finish(ServerEvent::Uploaded { mux: self.mux }))
            }
            _ => Err(AbortCode::InvalidCommand),
        }
    }

    /// The next segment of the sub-block being sent, if any is left.
    pub(super) fn next_segment(&mut self) -> Option<Frame> {
        if self.phase != Phase::Sending || self.next_seq > self.count {
            return None;
        }
        let index = self.first + (self.next_seq - 1) as usize;
        let start = index * SEGMENT_DATA;
        let end = (start + SEGMENT_DATA).min(self.data.len());
        let mut data = [0u8; SEGMENT_DATA];
        if let Some(bytes) = self.data.get(start..end) {
            data[..bytes.len()].copy_from_slice(bytes);
        }
        let segment = BlockSegment {
            seqno: self.next_seq,
            last: index + 1 == self.segments(),
            data,
        };
        self.next_seq += 1;
        Some(segment.emit())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn upload(len: usize, blksize: u8) -> BlockUpload {
        BlockUpload {
            mux: Address::new(0x2000, 0),
            crc: true,
            data: (0..len).map(|i| i as u8).collect(),
            blksize,
            phase: Phase::Initiated,
            first: 0,
            count: 0,
            next_seq: 1,
        }
    }

    fn drain(t: &mut BlockUpload) -> Vec<Frame> {
        std::iter::from_fn(|| t.next_segment()).collect()
    }

    #[test]
    fn an_empty_value_is_one_empty_last_segment() {
        let mut t = upload(0, 127);
        t.start_sub_block();
        assert_eq!(drain(&mut t), vec![[0x81, 0, 0, 0, 0, 0, 0, 0]]);
    }

    #[test]
    fn sub_blocks_follow_the_block_size() {
        // 15 bytes: three segments; block size 2 gives a sub-block of two, then one.
        let mut t = upload(15, 2);
        t.start_sub_block();
        assert_eq!(
            drain(&mut t),
            vec![[0x01, 0, 1, 2, 3, 4, 5, 6], [0x02, 7, 8, 9, 10, 11, 12, 13]]
        );
        assert_eq!(t.next_segment(), None);
        t.first = 2;
        t.start_sub_block();
        assert_eq!(drain(&mut t), vec![[0x81, 14, 0, 0, 0, 0, 0, 0]]);
    }
}
