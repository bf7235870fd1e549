//! How a CoE SDO transfer (ETG.1000.6 §5.6.2) is carried out by the CiA 301 SDO server: the mailbox's
//! data is cut into the seven-byte download segments the server takes, and the seven-byte upload segments
//! it answers are gathered into as much as a mailbox holds.
//!
//! - [`Engine`]: the SDO server, one frame in and its answer out, and the events of the CoE server;
//! - [`Download`]: a normal download (§5.6.2.2, §5.6.2.3) fed to the server as segments;
//! - [`Upload`]: a normal upload (§5.6.2.5, §5.6.2.6) pulled from the server segment by segment.

use std::collections::VecDeque;
use std::time::Instant;

use super::store::Detached;
use crate::abort::AbortCode;
use crate::sdo::frame::{Address, ClientFrame, SegmentData, ServerFrame};
use crate::sdo::server::{SdoServer, ServerConfig, ServerEvent};
use crate::sdo::store::ObjectStore;

/// Events kept for the host at most; the oldest goes when more come.
const EVENT_CAPACITY: usize = 16;

/// Bytes of data in one download or upload segment of CiA 301.
const SEGMENT_DATA: usize = 7;

/// The SDO server that does the work, and the events of the CoE server.
#[derive(Debug, Clone)]
pub(super) struct Engine {
    server: SdoServer,
    events: VecDeque<ServerEvent>,
}

impl Engine {
    pub(super) fn new(config: ServerConfig) -> Engine {
        Engine {
            server: SdoServer::new(config),
            events: VecDeque::with_capacity(EVENT_CAPACITY),
        }
    }

    pub(super) fn config(&self) -> &ServerConfig {
        self.server.config()
    }

    /// The SDO server's transfer timer.
    pub(super) fn poll_timeout(&self) -> Option<Instant> {
        self.server.poll_timeout()
    }

    pub(super) fn poll_event(&mut self) -> Option<ServerEvent> {
        self.events.pop_front()
    }

    pub(super) fn push_event(&mut self, event: ServerEvent) {
        if self.events.len() == EVENT_CAPACITY {
            self.events.pop_front();
        }
        self.events.push_back(event);
    }

    /// Hands the SDO server `frame` (of the transfer about `mux`) and takes its answer.
    ///
    /// `Err(code)`: the transfer is over with an abort and its [`ServerEvent::Aborted`] is recorded
    /// (the server's own, or one for 0x08000000 when the server answered nothing, which does not
    /// happen). The server's [`ServerEvent::Uploaded`] is left out when `keep_uploaded` is false: a CoE
    /// upload is finished only when the master has the last byte, not when the server has handed it over.
    pub(super) fn exchange(
        &mut self,
        now: Instant,
        mux: Address,
        frame: ClientFrame,
        store: &mut impl ObjectStore,
        keep_uploaded: bool,
    ) -> Result<ServerFrame, AbortCode> {
        self.server.handle_frame(now, &frame.emit(), store);
        let mut answer = None;
        let mut abort = None;
        while let Some(bytes) = self.server.poll_transmit() {
            match ServerFrame::parse(&bytes) {
                Ok(ServerFrame::Abort { code, .. }) => {
                    abort.get_or_insert(code);
                }
                Ok(other) => answer = Some(other),
                Err(_) => {}
            }
        }
        while let Some(event) = self.server.poll_event() {
            if keep_uploaded || !matches!(event, ServerEvent::Uploaded { .. }) {
                self.push_event(event);
            }
        }
        if let Some(code) = abort {
            return Err(code);
        }
        answer.ok_or_else(|| self.unexpected(now, mux))
    }

    /// Ends the transfer about `mux` after an answer the CoE server cannot use (which does not happen):
    /// aborted with 0x08000000 (general error).
    pub(super) fn unexpected(&mut self, now: Instant, mux: Address) -> AbortCode {
        self.fail(now, mux, AbortCode::General);
        AbortCode::General
    }

    /// Ends the transfer about `mux` with an abort the CoE server decided on, and reports it.
    pub(super) fn fail(&mut self, now: Instant, mux: Address, code: AbortCode) {
        self.end_silently(now, mux);
        self.push_event(ServerEvent::Aborted {
            mux,
            code,
            by_client: false,
        });
    }

    /// Ends the SDO server's transfer, if any, without writing anything and without an event: the CoE
    /// server reports the end itself.
    pub(super) fn end_silently(&mut self, now: Instant, mux: Address) {
        if self.server.is_busy() {
            let abort = ClientFrame::Abort {
                mux,
                code: AbortCode::General,
            };
            self.server.handle_frame(now, &abort.emit(), &mut Detached);
        }
        while self.server.poll_transmit().is_some() {}
        while self.server.poll_event().is_some() {}
    }
}

/// Which part of a normal download the data comes in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Part {
    /// The download request (§5.6.2.2): the download is complete when the data reaches the size.
    Initiate,
    /// A download segment request (§5.6.2.3): the download is complete when the master says so.
    Segment {
        /// The master's "no more segments" bit.
        last: bool,
    },
}

/// A normal download in progress: the SDO server has taken the initiate and the data so far.
#[derive(Debug, Clone)]
pub(super) struct Download {
    /// The entry, or the object and first sub-index of a complete access.
    pub(super) mux: Address,
    /// Complete access.
    pub(super) complete: bool,
    /// The toggle bit the master's next download segment must carry (0 on the first).
    pub(super) toggle: bool,
    /// The toggle bit of the next segment fed to the SDO server.
    inner_toggle: bool,
    /// Bytes the master announced and has not sent yet.
    remaining: u32,
}

impl Download {
    /// A download of `size` bytes whose initiate the SDO server has accepted.
    pub(super) fn new(mux: Address, complete: bool, size: u32) -> Download {
        Download {
            mux,
            complete,
            toggle: false,
            inner_toggle: false,
            remaining: size,
        }
    }

    /// Feeds `data` to the SDO server as download segments of up to seven bytes, the last of them with
    /// c = 1 when this part completes the download. `Ok(true)`: the download is complete and the value
    /// written. More data than announced is refused with 0x06070012 before any of it is fed.
    pub(super) fn feed(
        &mut self,
        engine: &mut Engine,
        now: Instant,
        store: &mut impl ObjectStore,
        data: &[u8],
        part: Part,
    ) -> Result<bool, AbortCode> {
        if data.len() as u64 > u64::from(self.remaining) {
            engine.fail(now, self.mux, AbortCode::LengthTooHigh);
            return Err(AbortCode::LengthTooHigh);
        }
        let finishing = match part {
            Part::Initiate => data.len() as u64 == u64::from(self.remaining),
            Part::Segment { last } => last,
        };
        let count = data.len().div_ceil(SEGMENT_DATA);
        if count == 0 {
            if finishing {
                self.segment(engine, now, store, &[], true)?;
            }
            return Ok(finishing);
        }
        for (i, chunk) in data.chunks(SEGMENT_DATA).enumerate() {
            self.segment(engine, now, store, chunk, finishing && i + 1 == count)?;
        }
        Ok(finishing)
    }

    fn segment(
        &mut self,
        engine: &mut Engine,
        now: Instant,
        store: &mut impl ObjectStore,
        chunk: &[u8],
        last: bool,
    ) -> Result<(), AbortCode> {
        let frame = ClientFrame::DownloadSegment {
            toggle: self.inner_toggle,
            data: SegmentData::new(chunk),
            last,
        };
        match engine.exchange(now, self.mux, frame, store, true)? {
            ServerFrame::DownloadSegment { .. } => {}
            _ => return Err(engine.unexpected(now, self.mux)),
        }
        self.inner_toggle = !self.inner_toggle;
        self.remaining -= chunk.len() as u32;
        Ok(())
    }
}

/// A normal upload in progress: the SDO server has answered the initiate with a segmented upload.
#[derive(Debug, Clone)]
pub(super) struct Upload {
    /// The entry, or the object and first sub-index of a complete access.
    pub(super) mux: Address,
    /// Complete access.
    pub(super) complete: bool,
    /// The toggle bit the master's next upload segment request must carry (0 on the first).
    pub(super) toggle: bool,
    /// The toggle bit of the next segment request to the SDO server.
    inner_toggle: bool,
    /// Bytes of the SDO server's last segment that did not fit the last response (at most six).
    pending: Vec<u8>,
    /// True when the SDO server has sent its last segment.
    inner_done: bool,
}

impl Upload {
    /// An upload whose initiate the SDO server has answered with a segmented upload.
    pub(super) fn new(mux: Address, complete: bool) -> Upload {
        Upload {
            mux,
            complete,
            toggle: false,
            inner_toggle: false,
            pending: Vec::new(),
            inner_done: false,
        }
    }

    /// Up to `capacity` bytes of the value: the bytes left over from the last response, then segments
    /// asked of the SDO server; a segment's bytes beyond `capacity` are kept for the next response. The
    /// flag is true when these are the last bytes of the value.
    pub(super) fn fill(
        &mut self,
        engine: &mut Engine,
        now: Instant,
        store: &mut impl ObjectStore,
        capacity: usize,
    ) -> Result<(Vec<u8>, bool), AbortCode> {
        let take = self.pending.len().min(capacity);
        let mut out: Vec<u8> = self.pending.drain(..take).collect();
        while out.len() < capacity && !self.inner_done {
            let frame = ClientFrame::UploadSegment {
                toggle: self.inner_toggle,
            };
            let ServerFrame::UploadSegment { data, last, .. } =
                engine.exchange(now, self.mux, frame, store, false)?
            else {
                return Err(engine.unexpected(now, self.mux));
            };
            self.inner_toggle = !self.inner_toggle;
            self.inner_done = last;
            let bytes = data.as_slice();
            let fit = bytes.len().min(capacity - out.len());
            out.extend_from_slice(&bytes[..fit]);
            self.pending.extend_from_slice(&bytes[fit..]);
        }
        Ok((out, self.inner_done && self.pending.is_empty()))
    }
}
