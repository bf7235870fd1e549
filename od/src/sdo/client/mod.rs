//! The SDO client of CiA 301 §7.2.4 as a sans-IO state machine: one transfer at a time, frames in,
//! frames out, time passed in.
//!
//! - [`SdoClient`]: the machine and its [`ClientConfig`]; it reports through [`ClientEvent`]s.
//! - Transfer modes: expedited and segmented download (CiA 301 §7.2.4.3.3–5) and upload
//!   (§7.2.4.3.6–8), block download (§7.2.4.3.9–12) and block upload (§7.2.4.3.13–16).
//! - Data: a download takes [`DownloadData`] (bytes or a [`DownloadSource`]); an upload goes into
//!   memory (bounded by [`ClientConfig::upload_limit`]) or into an [`UploadSink`].
//!
//! The blocking, typed convenience on top is [`crate::sdo::session`].
//!
//! # Methods and polling order
//!
//! Input carries the time; output is pulled:
//!
//! 1. Start a transfer with its time: [`SdoClient::start_download`], [`SdoClient::start_upload`] (or
//!    `start_upload_expecting`, `start_upload_to`).
//! 2. For every frame from the server (0x580 + node-ID): [`SdoClient::handle_frame`] with the time it
//!    arrived; when [`SdoClient::poll_timeout`] has passed: [`SdoClient::handle_timeout`] (the answer
//!    timer, 0x05040000 on expiry).
//! 3. After each call, drain [`SdoClient::poll_transmit`] (frames for 0x600 + node-ID, in order; a block
//!    download hands out a whole sub-block), then [`SdoClient::poll_event`] (the transfer's end).
//! 4. Wait for the next frame or [`SdoClient::poll_timeout`], whichever comes first.

mod block;
mod data;
mod download;
mod upload;

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use crate::abort::AbortCode;
use crate::sdo::frame::{Address, BlockSegment, ClientFrame, Frame, ServerFrame};

use self::block::{BlockDownload, BlockUpload};
use self::data::{Failure, Sink, Source};
use self::download::Download;
use self::upload::Upload;

pub use self::block::MAX_BLKSIZE;
pub use self::data::{
    DownloadData, DownloadSource, ReadSource, UploadSink, WriteSink, MAX_READ_PER_CALL,
    UPLOAD_PREALLOC_CAP,
};

/// How a client transfers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ClientConfig {
    /// How long the client waits for each answer of the server before it aborts the transfer with
    /// 0x05040000 (SDO protocol timed out). Default 1 s.
    pub timeout: Duration,
    /// Use block transfer (CiA 301 §7.2.4.3.9–16) for data larger than
    /// [`block_threshold`](ClientConfig::block_threshold) and for uploads of unknown size; a server
    /// that refuses it gets the same transfer again, segmented. Default true.
    pub block: bool,
    /// Segments per sub-block the client asks for in block upload, 1–127 (0 counts as 1). Default 127.
    pub block_size: u8,
    /// Offer the block transfer CRC; it is used when the server supports it too. Default true.
    pub crc: bool,
    /// Protocol switch threshold of block upload: the server may answer with an expedited or segmented
    /// upload when the data is no larger than this many bytes (0: no switch). Default 0.
    pub pst: u8,
    /// Block download is used only for data larger than this many bytes (and larger than four: what
    /// fits an expedited transfer stays expedited). Default 4.
    pub block_threshold: usize,
    /// The most bytes an upload into memory may bring; a server that announces or sends more is
    /// aborted with 0x05040005 (out of memory). Uploads into an [`UploadSink`] have no limit.
    /// Default 16 MiB.
    pub upload_limit: usize,
}

impl Default for ClientConfig {
    fn default() -> ClientConfig {
        ClientConfig {
            timeout: Duration::from_secs(1),
            block: true,
            block_size: MAX_BLKSIZE,
            crc: true,
            pst: 0,
            block_threshold: 4,
            upload_limit: 16 << 20,
        }
    }
}

/// What a client reports, taken with [`SdoClient::poll_event`].
#[derive(Debug)]
#[non_exhaustive]
pub enum ClientEvent {
    /// Bytes confirmed so far: acknowledged by the server (download) or received (upload); `total` is
    /// the size when known. Consecutive progress reports that were not polled are merged into the last.
    Progress {
        /// Bytes so far.
        done: u64,
        /// All bytes, when known.
        total: Option<u64>,
    },
    /// The download completed.
    Downloaded,
    /// The upload into memory completed with these bytes.
    Uploaded(Vec<u8>),
    /// The upload into the sink completed; the sink took `len` bytes and was finished.
    UploadedToSink {
        /// Bytes the sink took.
        len: u64,
    },
    /// The transfer failed; the client sent an abort frame unless the server aborted.
    Failed(SdoClientError),
}

/// Why an SDO client transfer failed or could not start.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SdoClientError {
    /// The transfer was aborted (CiA 301 §7.2.4.3.17): by the server (`by_server`), or by the client,
    /// which then sent `code` on the wire (a timeout is 0x05040000, a toggle error 0x05030000, an
    /// unexpected frame 0x05040001, a CRC error 0x05040004, an upload over the limit 0x05040005 …).
    #[error("SDO transfer of 0x{index:04X}:{sub:02X} aborted by the {side}: {code}", side = if *by_server { "server" } else { "client" })]
    Aborted {
        /// Index of the entry.
        index: u16,
        /// Sub-index of the entry.
        sub: u8,
        /// The abort code.
        code: AbortCode,
        /// True when the server sent the abort.
        by_server: bool,
    },
    /// The download source or upload sink failed; the client aborted the transfer on the wire with
    /// 0x08000000 (source) or 0x08000020 (sink).
    #[error("SDO data source or sink failed: {0}")]
    Io(#[source] std::io::Error),
    /// A transfer was started while another one runs.
    #[error("the SDO client is busy with another transfer")]
    Busy,
    /// A download larger than an SDO can announce (4 GiB − 1 bytes).
    #[error("{len} bytes are more than an SDO download can announce")]
    TooLarge {
        /// The size asked for.
        len: u64,
    },
}

/// The outcome of one step of a transfer's state machine.
enum Step {
    /// Frames are queued; the next answer is awaited (the response timer restarts).
    Wait,
    /// The transfer completed.
    Done(ClientEvent),
    /// The client aborts the transfer.
    Fail(Failure),
}

/// Where a state machine puts its output.
struct Out<'a> {
    frames: &'a mut VecDeque<Frame>,
    block: &'a mut VecDeque<Frame>,
    events: &'a mut VecDeque<ClientEvent>,
}

impl Out<'_> {
    /// Queues a frame.
    fn send(&mut self, frame: ClientFrame) {
        self.frames.push_back(frame.emit());
    }

    /// Queues a segment of the sub-block being sent.
    fn send_block(&mut self, segment: BlockSegment) {
        self.block.push_back(segment.emit());
    }

    /// Drops the unsent segments of the previous sub-block.
    fn clear_block(&mut self) {
        self.block.clear();
    }

    /// Reports progress, replacing a report that was not polled yet.
    fn progress(&mut self, done: u64, total: Option<u64>) {
        if let Some(ClientEvent::Progress { .. }) = self.events.back() {
            self.events.pop_back();
        }
        self.events.push_back(ClientEvent::Progress { done, total });
    }
}

/// The state of the running transfer.
enum State {
    /// Expedited or segmented download (CiA 301 §7.2.4.3.3–5).
    Download(Download),
    /// Block download (CiA 301 §7.2.4.3.9–12).
    BlockDownload(BlockDownload),
    /// Expedited or segmented upload (CiA 301 §7.2.4.3.6–8), also after a protocol switch.
    Upload(Upload),
    /// Block upload (CiA 301 §7.2.4.3.13–16).
    BlockUpload(BlockUpload),
}

/// The running transfer.
struct Transfer {
    mux: Address,
    state: State,
}

/// An SDO client (CiA 301 §7.2.4): runs one transfer at a time against one server, as a sans-IO state
/// machine.
///
/// Method families, in the order a runtime uses them:
///
/// 1. Start a transfer: [`start_download`](SdoClient::start_download),
///    [`start_upload`](SdoClient::start_upload), [`start_upload_to`](SdoClient::start_upload_to),
///    [`start_upload_expecting`](SdoClient::start_upload_expecting). Starting while a transfer runs
///    fails with [`SdoClientError::Busy`].
/// 2. Input: [`handle_frame`](SdoClient::handle_frame) for each frame from the server (COB-ID
///    0x580 + node; the runtime filters), [`handle_timeout`](SdoClient::handle_timeout) when the
///    instant of [`poll_timeout`](SdoClient::poll_timeout) has come, [`abort`](SdoClient::abort) to
///    cancel.
/// 3. Output, drained after every input: [`poll_transmit`](SdoClient::poll_transmit) until `None`
///    (frames for COB-ID 0x600 + node, in order), then [`poll_event`](SdoClient::poll_event) until
///    `None`, then sleep until [`poll_timeout`](SdoClient::poll_timeout) or the next frame.
///
/// Modes: data of 1–4 bytes goes expedited; data larger than
/// [`ClientConfig::block_threshold`] goes by block download when [`ClientConfig::block`] is set,
/// segmented otherwise. Uploads ask for block upload when block transfer is on. A server that answers
/// a block initiate with an abort gets the same transfer once more in segmented (normal) mode, with no
/// report. Every request waits at most [`ClientConfig::timeout`] for its answer; then the client sends
/// abort 0x05040000 and reports [`ClientEvent::Failed`]. An unexpected frame (wrong command, wrong
/// multiplexer) is answered with abort 0x05040001; a server abort ends the transfer with
/// [`SdoClientError::Aborted`] `{ by_server: true }`. Frames that arrive while no transfer runs are
/// ignored. No received frame makes the client panic.
///
/// Memory is bounded: at most one sub-block (127 segments) is queued; an upload into memory reserves
/// at most [`UPLOAD_PREALLOC_CAP`] bytes ahead and grows as data arrives up to
/// [`ClientConfig::upload_limit`].
pub struct SdoClient {
    config: ClientConfig,
    transfer: Option<Transfer>,
    /// The response timer: when the answer to the last request is due.
    response_due: Option<Instant>,
    /// Frames to send, in order.
    frames: VecDeque<Frame>,
    /// The segments of the sub-block being sent (after `frames`).
    block: VecDeque<Frame>,
    events: VecDeque<ClientEvent>,
}

impl Default for SdoClient {
    fn default() -> SdoClient {
        SdoClient::new(ClientConfig::default())
    }
}

impl std::fmt::Debug for SdoClient {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SdoClient")
            .field("config", &self.config)
            .field("busy", &self.is_busy())
            .field("response_due", &self.response_due)
            .finish_non_exhaustive()
    }
}

impl SdoClient {
    /// A client with `config`, idle.
    pub fn new(config: ClientConfig) -> SdoClient {
        SdoClient {
            config,
            transfer: None,
            response_due: None,
            frames: VecDeque::new(),
            block: VecDeque::with_capacity(MAX_BLKSIZE as usize),
            events: VecDeque::new(),
        }
    }

    /// The configuration.
    pub fn config(&self) -> &ClientConfig {
        &self.config
    }

    /// The configuration, to change; a change applies from the next transfer (the timeout from the
    /// next request).
    pub fn config_mut(&mut self) -> &mut ClientConfig {
        &mut self.config
    }

    /// True while a transfer runs.
    pub fn is_busy(&self) -> bool {
        self.transfer.is_some()
    }

    /// Starts writing `data` to the server's entry `mux`: expedited for 1–4 bytes, block download for
    /// data larger than the block threshold when block transfer is on, segmented otherwise. A streaming
    /// source of 1–4 bytes is read at once (its error is returned); a larger one as the transfer goes.
    pub fn start_download(
        &mut self,
        now: Instant,
        mux: Address,
        data: impl Into<DownloadData>,
    ) -> Result<(), SdoClientError> {
        if self.is_busy() {
            return Err(SdoClientError::Busy);
        }
        let data = data.into();
        let len = data.len();
        if len > u32::MAX as u64 {
            return Err(SdoClientError::TooLarge { len });
        }
        let source = Source::new(data);
        let block = self.config.block && len > self.config.block_threshold.max(4) as u64;
        let crc = self.config.crc;
        let mut out = self.out();
        let state = if block {
            State::BlockDownload(BlockDownload::start(mux, source, crc, &mut out))
        } else {
            State::Download(
                Download::start(mux, source, &mut out).map_err(|f| f.into_error(mux, false))?,
            )
        };
        self.begin(now, mux, state);
        Ok(())
    }

    /// Starts reading the server's entry `mux` into memory; block upload when block transfer is on.
    pub fn start_upload(&mut self, now: Instant, mux: Address) -> Result<(), SdoClientError> {
        let sink = self.memory_sink();
        self.begin_upload(now, mux, sink, self.config.block)
    }

    /// Starts reading the server's entry `mux` into memory when about `expected` bytes are expected
    /// (a value of a fixed-size type): block upload only when `expected` is larger than the block
    /// threshold, as for downloads. The server's answer decides the actual size.
    pub fn start_upload_expecting(
        &mut self,
        now: Instant,
        mux: Address,
        expected: u64,
    ) -> Result<(), SdoClientError> {
        let sink = self.memory_sink();
        let block = self.config.block && expected > self.config.block_threshold.max(4) as u64;
        self.begin_upload(now, mux, sink, block)
    }

    /// Starts reading the server's entry `mux` into `sink`, block upload when block transfer is on.
    /// The sink takes the bytes in order as they arrive; no memory limit applies.
    pub fn start_upload_to(
        &mut self,
        now: Instant,
        mux: Address,
        sink: Box<dyn UploadSink + Send>,
    ) -> Result<(), SdoClientError> {
        let sink = Sink::Stream { sink, written: 0 };
        self.begin_upload(now, mux, sink, self.config.block)
    }

    fn memory_sink(&self) -> Sink {
        Sink::Memory {
            buf: Vec::new(),
            limit: self.config.upload_limit,
        }
    }

    fn begin_upload(
        &mut self,
        now: Instant,
        mux: Address,
        sink: Sink,
        block: bool,
    ) -> Result<(), SdoClientError> {
        if self.is_busy() {
            return Err(SdoClientError::Busy);
        }
        let (crc, blksize, pst) = (
            self.config.crc,
            self.config.block_size.clamp(1, MAX_BLKSIZE),
            self.config.pst,
        );
        let mut out = self.out();
        let state = if block {
            State::BlockUpload(BlockUpload::start(mux, sink, crc, blksize, pst, &mut out))
        } else {
            State::Upload(Upload::start(mux, sink, &mut out))
        };
        self.begin(now, mux, state);
        Ok(())
    }

    fn begin(&mut self, now: Instant, mux: Address, state: State) {
        self.transfer = Some(Transfer { mux, state });
        self.response_due = now.checked_add(self.config.timeout);
    }

    fn out(&mut self) -> Out<'_> {
        Out {
            frames: &mut self.frames,
            block: &mut self.block,
            events: &mut self.events,
        }
    }

    /// Takes a frame the server sent (its eight data bytes).
    pub fn handle_frame(&mut self, now: Instant, frame: &Frame) {
        let Some(Transfer { mux, mut state }) = self.transfer.take() else {
            return;
        };
        // In a block upload's sub-block every byte 0 but 0x80 is a segment (CiA 301 §7.2.4.3.15).
        let abort = match &state {
            State::BlockUpload(b) if b.receiving_segments() => frame[0] == 0x80,
            _ => frame[0] >> 5 == 4,
        };
        if abort {
            let code =
                AbortCode::from(u32::from_le_bytes([frame[4], frame[5], frame[6], frame[7]]));
            self.server_abort(now, mux, state, code);
            return;
        }
        let parsed = ServerFrame::parse(frame);
        // Protocol switch: a normal initiate upload response to a block upload initiate.
        if let State::BlockUpload(b) = state {
            state = if b.is_initiating()
                && matches!(
                    parsed,
                    Ok(ServerFrame::InitiateUploadExpedited { .. }
                        | ServerFrame::InitiateUploadSegmented { .. })
                ) {
                match b.into_sink() {
                    Some(sink) => State::Upload(Upload::waiting(sink)),
                    None => return self.fail(mux, Failure::abort(AbortCode::General)),
                }
            } else {
                State::BlockUpload(b)
            };
        }
        let mut out = self.out();
        let step = match (&mut state, parsed) {
            (State::BlockUpload(b), _) => b.handle(mux, frame, &mut out),
            (_, Err(code)) => Step::Fail(Failure::abort(code)),
            (State::Download(d), Ok(f)) => d.handle(mux, f, &mut out),
            (State::BlockDownload(b), Ok(f)) => b.handle(mux, f, &mut out),
            (State::Upload(u), Ok(f)) => u.handle(mux, f, &mut out),
        };
        match step {
            Step::Wait => self.begin(now, mux, state),
            Step::Done(event) => {
                self.response_due = None;
                self.events.push_back(event);
            }
            Step::Fail(f) => self.fail(mux, f),
        }
    }

    /// The server aborted: a refused block initiate falls back to a normal transfer, any other abort
    /// ends the transfer.
    fn server_abort(&mut self, now: Instant, mux: Address, state: State, code: AbortCode) {
        let mut out = self.out();
        let retry = match state {
            State::BlockDownload(b) if b.is_initiating() => {
                Some(Download::start(mux, b.into_source(), &mut out).map(State::Download))
            }
            State::BlockUpload(b) if b.is_initiating() => b
                .into_sink()
                .map(|sink| Ok(State::Upload(Upload::start(mux, sink, &mut out)))),
            _ => None,
        };
        match retry {
            Some(Ok(state)) => self.begin(now, mux, state),
            Some(Err(f)) => self.fail(mux, f),
            None => {
                self.block.clear();
                self.response_due = None;
                self.events
                    .push_back(ClientEvent::Failed(SdoClientError::Aborted {
                        index: mux.index,
                        sub: mux.sub,
                        code,
                        by_server: true,
                    }));
            }
        }
    }

    /// Ends the transfer from the client's side: abort frame on the wire, failure reported.
    fn fail(&mut self, mux: Address, failure: Failure) {
        self.transfer = None;
        self.response_due = None;
        self.block.clear();
        self.frames.push_back(
            ClientFrame::Abort {
                mux,
                code: failure.code,
            }
            .emit(),
        );
        self.events
            .push_back(ClientEvent::Failed(failure.into_error(mux, false)));
    }

    /// Runs the response timer: when the answer is overdue, the transfer is aborted with 0x05040000 on
    /// the wire and reported as failed.
    pub fn handle_timeout(&mut self, now: Instant) {
        if let (Some(due), Some(t)) = (self.response_due, &self.transfer) {
            if now >= due {
                let mux = t.mux;
                self.fail(mux, Failure::abort(AbortCode::Timeout));
            }
        }
    }

    /// When [`handle_timeout`](SdoClient::handle_timeout) is due next; `None` while idle.
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Instant> {
        self.transfer.as_ref().and(self.response_due)
    }

    /// The next frame to send to the server.
    #[must_use]
    pub fn poll_transmit(&mut self) -> Option<Frame> {
        self.frames.pop_front().or_else(|| self.block.pop_front())
    }

    /// The next event.
    #[must_use]
    pub fn poll_event(&mut self) -> Option<ClientEvent> {
        self.events.pop_front()
    }

    /// Aborts the running transfer with `code` (sent on the wire), reported as
    /// [`SdoClientError::Aborted`] `{ by_server: false }`. Returns false when no transfer runs.
    pub fn abort(&mut self, code: AbortCode) -> bool {
        match self.transfer.take() {
            Some(t) => {
                self.fail(t.mux, Failure::abort(code));
                true
            }
            None => false,
        }
    }

    /// Forgets the running transfer, the queued frames and the unpolled events, with nothing on the
    /// wire (for a runtime whose bus went away).
    pub fn reset(&mut self) {
        self.transfer = None;
        self.response_due = None;
        self.frames.clear();
        self.block.clear();
        self.events.clear();
    }
}

impl Failure {
    /// The error reported for this failure of the transfer of `mux`.
    fn into_error(self, mux: Address, by_server: bool) -> SdoClientError {
        self.error.unwrap_or(SdoClientError::Aborted {
            index: mux.index,
            sub: mux.sub,
            code: self.code,
            by_server,
        })
    }
}

#[cfg(test)]
mod tests;
