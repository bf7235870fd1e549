//! The SDO server of CiA 301 §7.2.4 as a sans-IO state machine: it takes the frames a client sends (with
//! the time they arrived), reads and writes an [`ObjectStore`], and hands back the frames to send.
//!
//! - this module: [`SdoServer`], its configuration, events, frame dispatch and the transfer timer;
//! - `download`: expedited and segmented download (§7.2.4.3.3–7.2.4.3.5);
//! - `upload`: expedited and segmented upload (§7.2.4.3.6–7.2.4.3.8);
//! - `block_download`: block download (§7.2.4.3.9–7.2.4.3.12);
//! - `block_upload`: block upload (§7.2.4.3.13–7.2.4.3.16).

mod block_download;
mod block_upload;
mod download;
mod upload;

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use crate::abort::AbortCode;
use crate::sdo::frame::{Address, ClientFrame, Frame, ServerFrame};
use crate::sdo::store::ObjectStore;

/// How a server behaves: its transfer timeout, block size, CRC support and DOMAIN limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ServerConfig {
    /// The longest time without a frame from the client during a transfer; then the server aborts with
    /// 0x05040000. Default 1 s.
    pub timeout: Duration,
    /// Segments per block the server asks for in block download, 1–127 (a value outside is clamped into
    /// that range). Default 127.
    pub block_size: u8,
    /// True when the server supports the block transfer CRC (it is used when the client supports it
    /// too). Default true.
    pub crc: bool,
    /// The most bytes a download may bring to an entry that does not bound its length itself (a DOMAIN
    /// without a size), and the most the server ever buffers for one download. More is refused with
    /// 0x05040005 (out of memory). Default 1 MiB.
    pub domain_limit: usize,
}

impl Default for ServerConfig {
    fn default() -> ServerConfig {
        ServerConfig {
            timeout: Duration::from_secs(1),
            block_size: 127,
            crc: true,
            domain_limit: 1 << 20,
        }
    }
}

/// What happened to a transfer, for the application (a node acts on a finished download) and for logs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ServerEvent {
    /// A download finished and its value is in the store.
    Downloaded {
        /// The entry written.
        mux: Address,
    },
    /// An upload finished: the client has the whole value.
    Uploaded {
        /// The entry read.
        mux: Address,
    },
    /// A transfer ended with an abort: sent by the server (`by_client = false`, the abort frame is on its
    /// way) or received from the client (`by_client = true`, nothing is sent).
    Aborted {
        /// The entry of the transfer.
        mux: Address,
        /// Why.
        code: AbortCode,
        /// True when the client aborted.
        by_client: bool,
    },
    /// A transfer ended because the client started a new one before finishing it: nothing was written
    /// and no abort frame is sent for it.
    Superseded {
        /// The entry of the transfer that ended.
        mux: Address,
    },
}

/// Frames kept for [`SdoServer::poll_transmit`] at most; the oldest goes when more come.
const TRANSMIT_CAPACITY: usize = 4;
/// Events kept for [`SdoServer::poll_event`] at most; the oldest goes when more come.
const EVENT_CAPACITY: usize = 16;
/// Byte 0 of an abort frame (cs = 4). Inside a block download's sub-block it is the one frame that is not
/// a segment (a segment with sequence number 0 does not exist).
const ABORT_BYTE: u8 = 0x80;

/// A transfer in progress: the server is busy with at most one (CiA 301 §7.2.4.1).
#[derive(Debug, Clone)]
enum Transfer {
    /// Segmented download, waiting for the next segment.
    Download(download::Segmented),
    /// Segmented upload, waiting for the next segment request.
    Upload(upload::Segmented),
    /// Block download: receiving sub-blocks or waiting for the end frame.
    BlockDownload(block_download::BlockDownload),
    /// Block upload: waiting for the start, sending sub-blocks, or waiting for the end response.
    BlockUpload(block_upload::BlockUpload),
}

impl Transfer {
    fn mux(&self) -> Address {
        match self {
            Transfer::Download(t) => t.mux,
            Transfer::Upload(t) => t.mux,
            Transfer::BlockDownload(t) => t.mux,
            Transfer::BlockUpload(t) => t.mux,
        }
    }
}

/// What one step of a transfer asks the server to do; an `Err(code)` of a step is an abort.
#[derive(Debug, Default)]
struct Reply {
    /// The frame to send.
    frame: Option<Frame>,
    /// The transfer that goes on (`None`: the server is idle after this step).
    next: Option<Transfer>,
    /// The event of a finished transfer.
    event: Option<ServerEvent>,
    /// True when the frame moved the transfer on nothing (a block segment out of order): the
    /// transfer timer keeps running from the last frame that did.
    stalled: bool,
}

impl Reply {
    /// Sends `frame`.
    fn send(frame: ServerFrame) -> Reply {
        Reply {
            frame: Some(frame.emit()),
            ..Reply::default()
        }
    }

    /// The transfer goes on as `next`.
    fn then(mut self, next: Transfer) -> Reply {
        self.next = Some(next);
        self
    }

    /// The frame moved the transfer on nothing: the transfer timer is not restarted.
    fn stalled(mut self) -> Reply {
        self.stalled = true;
        self
    }

    /// The transfer is done.
    fn finish(mut self, event: ServerEvent) -> Reply {
        self.event = Some(event);
        self
    }
}

/// The result of one step of a transfer.
type Step = Result<Reply, AbortCode>;

/// An SDO server (CiA 301 §7.2.4): one per node, serving one client channel, busy with one transfer at a
/// time, reading and writing the [`ObjectStore`] passed to [`handle_frame`](SdoServer::handle_frame).
///
/// # Methods and polling order
///
/// Input carries the time; output is pulled:
///
/// - [`handle_frame`](SdoServer::handle_frame) takes a frame received from the client (COB-ID 0x600 +
///   node-ID) and the instant it arrived;
/// - [`handle_timeout`](SdoServer::handle_timeout) runs the transfer timer;
/// - [`poll_transmit`](SdoServer::poll_transmit) hands out the frames to send (0x580 + node-ID);
/// - [`poll_event`](SdoServer::poll_event) hands out what happened to transfers;
/// - [`poll_timeout`](SdoServer::poll_timeout) tells when `handle_timeout` is due.
///
/// After every `handle_frame` or `handle_timeout`, drain `poll_transmit` until it answers `None` (during
/// a block upload it answers a whole sub-block, up to 127 frames, one by one), then drain `poll_event`,
/// then wait for the next frame or until `poll_timeout`, whichever comes first, and call `handle_timeout`
/// with the time then. At most 4 frames and 16 events wait for the host; when it does not drain them the
/// oldest are dropped, so memory stays bounded whatever arrives.
///
/// # Behaviour the standard leaves open
///
/// - **A new initiate during a transfer** (any initiate frame while the server is busy, except inside a
///   block download's sub-block, where every frame is a segment) ends the old transfer without writing
///   anything and without an abort frame (the client evidently gave it up; an abort frame now would be
///   taken for an answer to the new request), reports [`ServerEvent::Superseded`], and serves the new
///   request.
/// - **Abort from the client** ends the transfer silently; byte 0 = 0x80 is an abort in every state,
///   inside a sub-block too. An abort while idle is ignored.
/// - **A frame that does not fit the state** (a segment while idle, an upload request during a download,
///   a command specifier 7) is answered with 0x05040001 and ends the transfer. The abort frame carries
///   the transfer's multiplexer, or bytes 1–3 of the received frame when the server was idle.
/// - **Sizes**: a download that announces more than the entry takes is refused at the initiate, before
///   anything is buffered: 0x06070012 for a fixed-size type or a bounded string or DOMAIN, 0x05040005
///   beyond [`ServerConfig::domain_limit`] (which caps every download, even an entry with a larger
///   capacity). An announcement smaller than a fixed-size type is 0x06070013 at once. The buffer grows
///   as data arrives; an announced size is never allocated. Data beyond the announced size is 0x06070012,
///   a transfer that ends short of it 0x06070013.
/// - **Expedited download without size** (s = 0) takes the entry's fixed size when it is at most 4 bytes
///   and all four bytes otherwise.
/// - **Uploads of 1–4 bytes are expedited**, others (also an empty value) segmented with the size
///   indicated; a value longer than 4 GiB would be sent with the size not indicated.
/// - **Block download**: a segment out of order (a lost or repeated one) makes the server ignore the rest
///   of the sub-block; at the sub-block's last segment (sequence number = block size, or c = 1) it
///   acknowledges the last segment received in order, and the client resumes after it with sequence
///   number 1. A segment out of order does not restart the transfer timer (nor does the
///   acknowledgement it may bring): only a segment taken in order does, so that a client that gave
///   the transfer up and polls with other requests is served again once the timeout has passed. Sequence number 0 (other than the abort byte 0x80) or above the block size is 0x05040003.
///   When the last segment of a sub-block is lost, no acknowledgement can be sent and the transfer ends
///   by timeout.
/// - **Block upload**: an acknowledgement of more segments than the sub-block had is 0x05040003; a block
///   size outside 1–127 in the initiate or an acknowledgement is 0x05040002. When the client's protocol
///   switch threshold is non-zero and the value is no longer, the answer is an expedited or segmented
///   initiate upload response and the transfer goes on as a segmented upload.
/// - **CRC**: used when both sides support it; a server without CRC support sends 0 in the CRC field.
/// - **Time**: a frame handled after the transfer's deadline first times the transfer out (as if
///   `handle_timeout` had run), then is handled by the idle server.
#[derive(Debug, Clone)]
pub struct SdoServer {
    config: ServerConfig,
    transfer: Option<Transfer>,
    /// The transfer timer: when the running transfer times out (`None` while idle).
    deadline: Option<Instant>,
    transmit: VecDeque<Frame>,
    events: VecDeque<ServerEvent>,
}

impl Default for SdoServer {
    fn default() -> SdoServer {
        SdoServer::new(ServerConfig::default())
    }
}

impl SdoServer {
    /// An idle server.
    pub fn new(mut config: ServerConfig) -> SdoServer {
        config.block_size = config.block_size.clamp(1, 127);
        SdoServer {
            config,
            transfer: None,
            deadline: None,
            transmit: VecDeque::with_capacity(TRANSMIT_CAPACITY),
            events: VecDeque::with_capacity(EVENT_CAPACITY),
        }
    }

    /// The configuration (block size clamped into 1–127).
    pub fn config(&self) -> &ServerConfig {
        &self.config
    }

    /// True while a transfer is in progress.
    pub fn is_busy(&self) -> bool {
        self.transfer.is_some()
    }

    /// Handles a frame received from the client at `now`.
    pub fn handle_frame(&mut self, now: Instant, frame: &Frame, store: &mut impl ObjectStore) {
        self.handle_timeout(now);
        match self.transfer.take() {
            // CiA 301 §7.2.4.3.11: inside a sub-block every frame is a segment.
            Some(Transfer::BlockDownload(t)) if t.receiving() && frame[0] != ABORT_BYTE => {
                let mux = t.mux;
                let step = t.segment(frame);
                self.apply(now, mux, step);
            }
            transfer => self.command(now, transfer, frame, store),
        }
    }

    /// Runs the transfer timer: when a transfer has had no frame from the client for
    /// [`ServerConfig::timeout`], it is aborted with 0x05040000 and the server is idle.
    pub fn handle_timeout(&mut self, now: Instant) {
        if self.deadline.is_some_and(|d| now >= d) {
            self.deadline = None;
            if let Some(t) = self.transfer.take() {
                self.abort(t.mux(), AbortCode::Timeout);
            }
        }
    }

    /// When [`handle_timeout`](SdoServer::handle_timeout) is due; `None` while idle.
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Instant> {
        self.deadline
    }

    /// The next frame to send to the client.
    #[must_use]
    pub fn poll_transmit(&mut self) -> Option<Frame> {
        if let Some(f) = self.transmit.pop_front() {
            return Some(f);
        }
        match &mut self.transfer {
            Some(Transfer::BlockUpload(t)) => t.next_segment(),
            _ => None,
        }
    }

    /// The next event.
    #[must_use]
    pub fn poll_event(&mut self) -> Option<ServerEvent> {
        self.events.pop_front()
    }

    /// A frame with a command specifier: an abort, an initiate, or the next step of the transfer.
    fn command(
        &mut self,
        now: Instant,
        transfer: Option<Transfer>,
        frame: &Frame,
        store: &mut impl ObjectStore,
    ) {
        let parsed = match ClientFrame::parse(frame) {
            Ok(f) => f,
            Err(code) => {
                let mux = transfer.map_or_else(|| frame_mux(frame), |t| t.mux());
                self.deadline = None;
                self.abort(mux, code);
                return;
            }
        };
        match parsed {
            ClientFrame::Abort { code, .. } => {
                self.deadline = None;
                if let Some(t) = transfer {
                    self.push_event(ServerEvent::Aborted {
                        mux: t.mux(),
                        code,
                        by_client: true,
                    });
                }
            }
            ClientFrame::InitiateDownloadExpedited { mux, data } => {
                self.supersede(transfer);
                let step = download::expedited(mux, data, store, &self.config);
                self.apply(now, mux, step);
            }
            ClientFrame::InitiateDownloadSegmented { mux, size } => {
                self.supersede(transfer);
                let step = download::initiate(mux, size, store, &self.config);
                self.apply(now, mux, step);
            }
            ClientFrame::InitiateUpload { mux } => {
                self.supersede(transfer);
                let step = upload::initiate(mux, store);
                self.apply(now, mux, step);
            }
            ClientFrame::InitiateBlockDownload { mux, crc, size } => {
                self.supersede(transfer);
                let step = block_download::initiate(mux, crc, size, store, &self.config);
                self.apply(now, mux, step);
            }
            ClientFrame::InitiateBlockUpload {
                mux,
                crc,
                blksize,
                pst,
            } => {
                self.supersede(transfer);
                let step = block_upload::initiate(mux, crc, blksize, pst, store, &self.config);
                self.apply(now, mux, step);
            }
            other => match transfer {
                None => {
                    self.deadline = None;
                    self.abort(frame_mux(frame), AbortCode::InvalidCommand);
                }
                Some(t) => {
                    let mux = t.mux();
                    let step = match t {
                        Transfer::Download(t) => t.frame(other, store),
                        Transfer::Upload(t) => t.frame(other),
                        Transfer::BlockDownload(t) => t.frame(other, store),
                        Transfer::BlockUpload(t) => t.frame(other),
                    };
                    self.apply(now, mux, step);
                }
            },
        }
    }

    /// Ends `transfer`, replaced by a new initiate.
    fn supersede(&mut self, transfer: Option<Transfer>) {
        if let Some(t) = transfer {
            self.push_event(ServerEvent::Superseded { mux: t.mux() });
        }
    }

    /// Carries out a step of the transfer about `mux`.
    fn apply(&mut self, now: Instant, mux: Address, step: Step) {
        match step {
            Ok(reply) => {
                if let Some(f) = reply.frame {
                    self.push_transmit(f);
                }
                if let Some(e) = reply.event {
                    self.push_event(e);
                }
                // An instant the clock cannot hold is a deadline never reached. Only a frame that
                // moves the transfer on restarts the timer: frames that a block download takes as
                // segments out of order (another client's requests, say) leave it running, so that
                // the transfer ends by timeout and the next request is served.
                if reply.next.is_none() {
                    self.deadline = None;
                } else if !(reply.stalled && self.deadline.is_some()) {
                    self.deadline = now.checked_add(self.config.timeout);
                }
                self.transfer = reply.next;
            }
            Err(code) => {
                self.transfer = None;
                self.deadline = None;
                self.abort(mux, code);
            }
        }
    }

    /// Sends an abort frame and reports it.
    fn abort(&mut self, mux: Address, code: AbortCode) {
        self.push_transmit(ServerFrame::Abort { mux, code }.emit());
        self.push_event(ServerEvent::Aborted {
            mux,
            code,
            by_client: false,
        });
    }

    fn push_transmit(&mut self, frame: Frame) {
        if self.transmit.len() == TRANSMIT_CAPACITY {
            self.transmit.pop_front();
        }
        self.transmit.push_back(frame);
    }

    fn push_event(&mut self, event: ServerEvent) {
        if self.events.len() == EVENT_CAPACITY {
            self.events.pop_front();
        }
        self.events.push_back(event);
    }
}

/// Bytes 1–3 of a frame read as a multiplexer (where initiate and abort frames carry it).
fn frame_mux(frame: &Frame) -> Address {
    Address::new(u16::from_le_bytes([frame[1], frame[2]]), frame[3])
}
