//! SDO block download, server side (CiA 301 §7.2.4.3.9 "Initiate SDO block download", §7.2.4.3.10
//! "Download SDO block", §7.2.4.3.11 "End SDO block download"; protocol in §7.2.4.3.12).

use super::download::{check_against_announced, check_complete, Limit};
use super::{Reply, ServerConfig, ServerEvent, Step, Transfer};
use crate::abort::AbortCode;
use crate::sdo::frame::{Address, BlockSegment, ClientFrame, Crc16, Frame, ServerFrame};
use crate::sdo::store::ObjectStore;

/// Data bytes of one block segment.
const SEGMENT_DATA: usize = 7;

/// Initiate block download: checks the entry and the announced size, answers the server's block size
/// and CRC support, buffers nothing.
pub(super) fn initiate(
    mux: Address,
    crc: bool,
    size: Option<u32>,
    store: &mut impl ObjectStore,
    config: &ServerConfig,
) -> Step {
    let limit = Limit::new(store.download_capacity(mux)?, config.domain_limit);
    if let Some(size) = size {
        limit.check_announced(size)?;
    }
    let blksize = config.block_size;
    Ok(Reply::send(ServerFrame::InitiateBlockDownload {
        mux,
        crc: config.crc,
        blksize,
    })
    .then(Transfer::BlockDownload(BlockDownload {
        mux,
        crc: crc && config.crc,
        size,
        limit,
        data: Vec::new(),
        last: None,
        next_seq: 1,
        blksize,
    })))
}

/// A block download: receiving sub-blocks, then waiting for the end frame.
#[derive(Debug, Clone)]
pub(super) struct BlockDownload {
    /// The entry.
    pub(super) mux: Address,
    /// True when both sides use the CRC.
    crc: bool,
    /// The size the client announced.
    size: Option<u32>,
    /// The length limit.
    limit: Limit,
    /// The data of every segment received in order before the last one.
    data: Vec<u8>,
    /// The last segment's seven bytes (c = 1), once received in order: then the end frame is due, which
    /// tells how many of them are data.
    last: Option<[u8; SEGMENT_DATA]>,
    /// The sequence number expected next in this sub-block.
    next_seq: u8,
    /// Segments per sub-block.
    blksize: u8,
}

impl BlockDownload {
    /// True while sub-blocks arrive (every frame is then a segment); false once the last segment has been
    /// acknowledged and the end frame is due.
    pub(super) fn receiving(&self) -> bool {
        self.last.is_none()
    }

    /// A segment of a sub-block. In order, it is taken; out of order, it and the rest of the sub-block are
    /// ignored. At the sub-block's last segment the server acknowledges the last one received in order.
    pub(super) fn segment(mut self, frame: &Frame) -> Step {
        let seg = BlockSegment::parse(frame)?;
        if seg.seqno > self.blksize {
            return Err(AbortCode::InvalidSequence);
        }
        let ends_sub_block = seg.last || seg.seqno == self.blksize;
        // Out of order: nothing taken, so the transfer timer runs on (CiA 301 §7.2.4.3.12: the server
        // ignores it and the rest of the sub-block).
        if seg.seqno != self.next_seq {
            return Ok(if ends_sub_block {
                let ackseq = self.next_seq - 1;
                self.ack(ackseq)
            } else {
                Reply::default().then(Transfer::BlockDownload(self))
            }
            .stalled());
        }
        if seg.last {
            self.last = Some(seg.data);
        } else {
            let len = self.data.len() + SEGMENT_DATA;
            check_against_announced(len, self.size)?;
            self.limit.check_len(len)?;
            self.data.extend_from_slice(&seg.data);
        }
        Ok(if ends_sub_block {
            self.ack(seg.seqno)
        } else {
            self.next_seq += 1;
            Reply::default().then(Transfer::BlockDownload(self))
        })
    }

    /// Acknowledges the sub-block up to `ackseq`; the next sub-block starts at sequence number 1.
    fn ack(mut self, ackseq: u8) -> Reply {
        self.next_seq = 1;
        Reply::send(ServerFrame::BlockDownloadAck {
            ackseq,
            blksize: self.blksize,
        })
        .then(Transfer::BlockDownload(self))
    }

    /// The end frame: the last segment's unused bytes and the CRC. The entry is written when the length
    /// and the CRC are right.
    pub(super) fn frame(mut self, frame: ClientFrame, store: &mut impl ObjectStore) -> Step {
        let (ClientFrame::EndBlockDownload { unused, crc }, Some(last)) = (frame, self.last) else {
            return Err(AbortCode::InvalidCommand);
        };
        let used = SEGMENT_DATA.saturating_sub(unused as usize);
        let len = self.data.len() + used;
        check_complete(len, self.size)?;
        self.limit.check_len(len)?;
        self.data.extend_from_slice(&last[..used]);
        if self.crc && Crc16::of(&self.data) != crc {
            return Err(AbortCode::CrcError);
        }
        store.download(self.mux, &self.data)?;
        Ok(Reply::send(ServerFrame::EndBlockDownload)
            .finish(ServerEvent::Downloaded { mux: self.mux }))
    }
}
