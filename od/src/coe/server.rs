//! The CoE SDO server of an EtherCAT slave (ETG.1000.6 §5.6.2) as a sans-IO state machine: it takes
//! whole mailboxes the master writes (sync manager 0) with the time they arrived, reads and writes a
//! [`Dictionary`], and hands back whole mailboxes for the master to read (sync manager 1).
//!
//! It is the CiA 301 SDO server of [`crate::sdo::server`] and nothing else: every CoE request is turned
//! into the CAN SDO frames that server takes, and its answers are gathered into one CoE response.
//!
//! - this module: [`CoeServer`], the mailbox and CoE framing, the mailbox counter and repeat, dispatch
//!   of the SDO commands, the transfer timer;
//! - `transfer`: normal download and upload carried out as segmented CiA 301 transfers;
//! - `store`: the dictionary as the SDO server sees it over EtherCAT (complete access, the RxPDO and
//!   sub-index 0 rules).

mod store;
mod transfer;

use std::collections::{HashSet, VecDeque};
use std::time::Instant;

use self::store::CoeStore;
use self::transfer::{Download, Engine, Part, Upload};
use crate::abort::AbortCode;
use crate::coe::mailbox::{CoeHeader, CoeService, MailboxHeader, MailboxType, MAILBOX_HEADER_LEN};
use crate::coe::sdo::{CoeSdo, CoeSdoCommand, CoeSdoError};
use crate::dict::Dictionary;
use crate::hook::{Bound, Objects};
use crate::sdo::frame::{Address, ClientFrame, ExpeditedData, SegmentData, ServerFrame};
use crate::sdo::server::{ServerConfig, ServerEvent};

pub use self::store::is_pdo_configuration;

/// The CoE header and the first eight SDO bytes.
const SDO_HEADER_LEN: usize = 2 + 8;
/// Mailbox, CoE and SDO header of a normal upload response: data starts after these.
const NORMAL_OVERHEAD: usize = MAILBOX_HEADER_LEN + SDO_HEADER_LEN;
/// Mailbox and CoE header and the command byte of a segment: data starts after these.
const SEGMENT_OVERHEAD: usize = MAILBOX_HEADER_LEN + 2 + 1;
/// The smallest mailbox a CoE SDO response needs.
pub const MIN_MAILBOX_SIZE: usize = NORMAL_OVERHEAD;
/// The largest mailbox the 16-bit length field can describe.
pub const MAX_MAILBOX_SIZE: usize = MAILBOX_HEADER_LEN + u16::MAX as usize;
/// Mailboxes kept for [`CoeServer::poll_transmit`] at most; the oldest goes when more come.
const TRANSMIT_CAPACITY: usize = 4;

/// Mailbox error reply (ETG.1000.4 mailbox type 0): the service "mailbox command".
const MBX_ERROR_COMMAND: u16 = 0x0001;
/// Mailbox error: the mailbox protocol is not supported (not CoE).
const MBXERR_UNSUPPORTED_PROTOCOL: u16 = 0x0002;
/// Mailbox error: the CoE service is not supported (anything but an SDO request).
const MBXERR_SERVICE_NOT_SUPPORTED: u16 = 0x0004;
/// Mailbox error: the mailbox is too short for its protocol header.
const MBXERR_SIZE_TOO_SHORT: u16 = 0x0006;
/// Mailbox error: the length field says more than the mailbox holds.
const MBXERR_INVALID_SIZE: u16 = 0x0008;

/// The answers to an SDO Information mailbox (CoE service 8), or `None` for any other mailbox.
fn information(mailbox: &[u8], d: &Dictionary, mailbox_size: usize) -> Option<Vec<Vec<u8>>> {
    let (header, data) = MailboxHeader::split(mailbox).ok()?;
    if header.mailbox_type != MailboxType::Coe {
        return None;
    }
    let coe = CoeHeader::parse(data).ok()?;
    (coe.service == CoeService::SdoInformation)
        .then(|| crate::coe::info::answer(data, d, mailbox_size))
}

/// Another mailbox protocol served through the same mailbox as CoE (FoE, …): one mailbox per slave
/// with one counter and one repeat rule for every protocol (ETG.1000.4 §5.6), so a request of
/// another protocol goes through [`CoeServer::handle_mailbox_with`], which keeps the counters and
/// the last answer for a repeat, and hands the request to the service.
pub trait MailboxService {
    /// Whether the service takes mailboxes of `mailbox_type` instead of the CoE server (a type
    /// neither takes is answered with the mailbox error 0x0002, unsupported protocol).
    fn takes(&self, mailbox_type: MailboxType) -> bool;

    /// The answer to `data`, a mailbox's data after its `header`, received at `now`.
    fn serve(&mut self, now: Instant, header: &MailboxHeader, data: &[u8]) -> ServiceAnswer;
}

/// What a [`MailboxService`] answers a mailbox with.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ServiceAnswer {
    /// A mailbox of this type with this data after its header.
    Mailbox(MailboxType, Vec<u8>),
    /// The mailbox error reply with this detail code (ETG.1000.4: 0x0002 unsupported protocol,
    /// 0x0006 size too short, …).
    MailboxError(u16),
    /// Nothing.
    Nothing,
}

/// No other protocol: every mailbox but CoE gets the mailbox error 0x0002.
struct CoeOnly;

impl MailboxService for CoeOnly {
    fn takes(&self, _: MailboxType) -> bool {
        false
    }

    fn serve(&mut self, _: Instant, _: &MailboxHeader, _: &[u8]) -> ServiceAnswer {
        ServiceAnswer::Nothing
    }
}

/// A transfer in progress over several mailboxes.
#[derive(Debug, Clone)]
enum Transfer {
    /// A normal download waiting for the master's next download segment.
    Download(Download),
    /// A normal upload waiting for the master's next upload segment request.
    Upload(Upload),
}

impl Transfer {
    fn mux(&self) -> Address {
        match self {
            Transfer::Download(t) => t.mux,
            Transfer::Upload(t) => t.mux,
        }
    }
}

/// What the slave answers a mailbox with.
#[derive(Debug)]
enum Answer {
    /// A CoE SDO frame: a response (service 3) or an abort (service 2).
    Sdo {
        command: CoeSdoCommand,
        complete_access: bool,
        extra: Vec<u8>,
    },
    /// A mailbox error reply with this detail code.
    MailboxError(u16),
    /// Another protocol's answer ([`MailboxService`]): its type and its data after the header.
    Other(MailboxType, Vec<u8>),
}

impl Answer {
    /// An SDO response.
    fn response(frame: ServerFrame, complete_access: bool) -> Answer {
        Answer::Sdo {
            command: CoeSdoCommand::Response(frame),
            complete_access,
            extra: Vec::new(),
        }
    }

    /// An SDO response with data after the eighth byte.
    fn response_with(frame: ServerFrame, complete_access: bool, extra: Vec<u8>) -> Answer {
        Answer::Sdo {
            command: CoeSdoCommand::Response(frame),
            complete_access,
            extra,
        }
    }

    /// Abort SDO Transfer (ETG.1000.6 §5.6.2.7): an SDO request (CoE service 2) in either direction.
    fn abort(mux: Address, code: AbortCode) -> Answer {
        Answer::Sdo {
            command: CoeSdoCommand::Request(ClientFrame::Abort { mux, code }),
            complete_access: false,
            extra: Vec::new(),
        }
    }

    /// An upload segment response carrying `data`: the first seven bytes in the CiA 301 segment (with
    /// `n` when fewer), the rest after it.
    fn upload_segment(toggle: bool, data: &[u8], last: bool) -> Answer {
        let head = data.len().min(7);
        Answer::response_with(
            ServerFrame::UploadSegment {
                toggle,
                data: SegmentData::new(&data[..head]),
                last,
            },
            false,
            data[head..].to_vec(),
        )
    }
}

/// A CoE SDO server (ETG.1000.6 §5.6.2): one per EtherCAT slave, busy with one transfer at a time, made
/// of the CiA 301 [`SdoServer`](crate::sdo::SdoServer) working on the [`Dictionary`] passed to
/// [`handle_mailbox`](CoeServer::handle_mailbox).
///
/// # Methods and polling order
///
/// Input carries the time; output is pulled:
///
/// - [`handle_mailbox`](CoeServer::handle_mailbox) takes a mailbox the master wrote (the whole sync
///   manager 0 buffer or just the mailbox; padding after the length the header gives is ignored) and
///   the instant it arrived;
/// - [`handle_timeout`](CoeServer::handle_timeout) runs the transfer timer;
/// - [`poll_transmit`](CoeServer::poll_transmit) hands out the mailboxes for the master to read
///   (sync manager 1), each exactly as long as its header says;
/// - [`poll_event`](CoeServer::poll_event) hands out what happened to transfers (the events of the
///   SDO server: [`ServerEvent`]);
/// - [`poll_timeout`](CoeServer::poll_timeout) tells when `handle_timeout` is due.
///
/// After every `handle_mailbox` or `handle_timeout`, drain `poll_transmit` until it answers `None`
/// (at most one mailbox per mailbox handled, none after `handle_timeout`), then drain `poll_event`, then wait for the next mailbox or until `poll_timeout`,
/// whichever comes first, and call `handle_timeout` with the time then. At most 4 mailboxes and 16
/// events wait for the host; when it does not drain them the oldest are dropped.
///
/// # Transfers
///
/// - **Expedited download and upload** (§5.6.2.1, §5.6.2.4): the eight SDO bytes are the CiA 301 frame;
///   they go to the SDO server and its answer comes back unchanged.
/// - **Normal download** (§5.6.2.2): the SDO server gets the initiate with the complete size, then the
///   data of the mailbox as download segments of seven bytes (toggle from 0; c = 1 on the one that
///   completes the size). The master gets the download response (`60 index sub 00 00 00 00`) when the
///   initiate is accepted, whether the data is complete or download segments (§5.6.2.3) are to follow.
///   Each of those carries data from byte 1 (seven bytes and all bytes after the eighth, or 7 − n
///   bytes when n ≠ 0), is fed to the SDO server the same way (c = 1 on the last piece of a segment
///   with c = 1), and is answered with a download segment response carrying the master's toggle bit.
/// - **Normal upload** (§5.6.2.5): the SDO server's expedited answer passes through; a segmented one
///   with size N becomes the upload response `41 index sub N` with as many bytes as the mailbox holds
///   (mailbox size − 16), taken from the SDO server's upload segments; the rest goes in upload segment
///   responses (§5.6.2.6) of up to mailbox size − 9 bytes each, with n when fewer than seven and c = 1
///   on the last, each answering an upload segment request.
/// - **Complete access** (bit 4 of an initiate, §5.6.2.1.2 and §5.6.2.4.2): the same transfers, the SDO
///   server working on the whole object packed by [`crate::coe::complete`] (from sub-index 0, with
///   sub-index 0 padded to 16 bits, or from sub-index 1). The initiate response carries the bit too
///   (`70` for a download; `51` for a normal upload, `53`, `57`, `5B` or `5F` for an expedited one). A start at a sub-index above 1 is refused with
///   0x06010000 (unsupported access: ETG.1000.6 lets a complete access start at 0 or 1 only); a VAR
///   object, a DOMAIN or an object with an entry of variable length with 0x06010004.
/// - **EtherCAT rules**: 0x06010006 for a download to an entry marked with
///   [`set_rxpdo_mapped`](CoeServer::set_rxpdo_mapped); 0x06010003 for a download to an entry ≥ 1 of
///   a PDO mapping or assignment object ([`is_pdo_configuration`]), or a complete download of one from
///   sub-index 1, while its sub-index 0 is not 0;
///   0x06010005 for a value that does not fit one mailbox when segmented transfer is switched off
///   ([`with_segmented_transfer`](CoeServer::with_segmented_transfer)).
/// - **Refused commands**: block transfer commands (CiA 301 block download and upload have no place
///   in CoE) and the unknown command specifier 7 are answered with 0x05040001; so are a segment while
///   no transfer runs and a segment of the wrong direction (that one ends the transfer). A toggle bit
///   that did not alternate is 0x05030000 and ends the transfer.
/// - **Aborts** go out as Abort SDO Transfer requests (§5.6.2.7: CoE service 2 in both directions) with
///   the transfer's index and sub-index, or bytes 1–3 of the request when no transfer ran. Every abort
///   ends the transfer with nothing written; the SDO server's rules on sizes and values hold as on CAN
///   (a download announcing more than the entry holds is refused before any data is buffered).
///
/// # Mailboxes
///
/// - **Counter**: each response carries the slave's own counter, 1 to 7 and again 1 (a repeated
///   response keeps the counter it had).
/// - **Repeat**: a request with the same non-zero counter as the request before it is a repeat (the
///   master did not get the answer): the previous response is sent again, bytes unchanged, and the
///   request is not served twice.
/// - **Address, channel, priority**: the response carries the request's address; channel and priority 0.
/// - **Not an SDO request**: a mailbox shorter than its six-byte header is ignored. Otherwise the
///   answer is a mailbox error reply (ETG.1000.4, mailbox type 0, service 1): 0x0002 for another
///   mailbox protocol than CoE, 0x0004 for a CoE service other than SDO request and SDO Information
///   ([`crate::coe::info`]), 0x0006 for a CoE
///   mailbox shorter than its CoE header and eight SDO bytes, 0x0008 for a length field beyond the
///   bytes given. A running transfer goes on.
/// - **Other protocols** ([`handle_mailbox_with`](CoeServer::handle_mailbox_with)): a mailbox of a
///   type the [`MailboxService`] takes is its to answer, with the same counter and repeat rules; a
///   length field beyond the bytes given is 0x0008 before it sees the mailbox.
///
/// # Behaviour the standard leaves open
///
/// - **Timeout**: a transfer with no request from the master for [`ServerConfig::timeout`] ends; no
///   mailbox is sent then (the mailbox is the master's to ask: an unasked abort would be taken for the
///   answer to its next request), the event reports 0x05040000, and a segment request for it that
///   comes later is answered with an abort 0x05040000. A mailbox handled after the deadline first
///   times the transfer out.
/// - **A new initiate during a transfer** ends the old one without an abort and reports
///   [`ServerEvent::Superseded`]; an abort from the master ends it and reports
///   [`ServerEvent::Aborted`] with `by_client`.
/// - **Normal download without the size indicated** (s = 0): the data in the mailbox is the whole value.
/// - **Data beyond the announced size**, in the download request or a segment, is 0x06070012 and ends
///   the transfer with nothing written. A segment with c = 1 that leaves the value short is 0x06070013.
/// - [`ServerEvent::Uploaded`] is reported when the master has been sent the last byte.
#[derive(Debug, Clone)]
pub struct CoeServer {
    engine: Engine,
    /// Sync manager 1 size: the longest response.
    mailbox_size: usize,
    /// False: values that do not fit one mailbox are refused (0x06010005).
    segmented: bool,
    /// Entries whose download is blocked because they are mapped to an RxPDO (0x06010006).
    rxpdo: HashSet<Address>,
    transfer: Option<Transfer>,
    /// The transfer timer: when the running transfer times out (`None` while idle).
    deadline: Option<Instant>,
    /// The transfer that timed out since the last request.
    timed_out: Option<Address>,
    /// The counter of the last response sent (0 before the first).
    counter: u8,
    /// The counter of the last request, when not 0.
    last_request: Option<u8>,
    /// The answer to the last request, for a repeat.
    last_response: Option<Vec<u8>>,
    transmit: VecDeque<Vec<u8>>,
}

impl CoeServer {
    /// An idle server for a slave whose input mailbox (sync manager 1) is `mailbox_size` bytes, e.g.
    /// 128; clamped into 16 ([`MIN_MAILBOX_SIZE`]) to 65541 ([`MAX_MAILBOX_SIZE`]). Segmented transfer is
    /// supported.
    pub fn new(config: ServerConfig, mailbox_size: usize) -> CoeServer {
        CoeServer {
            engine: Engine::new(config),
            mailbox_size: mailbox_size.clamp(MIN_MAILBOX_SIZE, MAX_MAILBOX_SIZE),
            segmented: true,
            rxpdo: HashSet::new(),
            transfer: None,
            deadline: None,
            timed_out: None,
            counter: 0,
            last_request: None,
            last_response: None,
            transmit: VecDeque::with_capacity(TRANSMIT_CAPACITY),
        }
    }

    /// Whether the slave supports segmented SDO transfer (ESI `CoE@SegmentedSdo`). Without it a value
    /// that does not fit one mailbox is refused with 0x06010005: an upload whose normal response would
    /// exceed the mailbox, a download whose request does not hold all its data.
    pub fn with_segmented_transfer(mut self, supported: bool) -> CoeServer {
        self.segmented = supported;
        self
    }

    /// Marks the entries mapped to an RxPDO while the slave is in SafeOp or Op (the process data owns
    /// them): an SDO download to one of them, or a complete download of its object, is refused with
    /// 0x06010006. Replaces the entries marked before; pass none when leaving SafeOp.
    pub fn set_rxpdo_mapped(&mut self, entries: impl IntoIterator<Item = Address>) {
        self.rxpdo = entries.into_iter().collect();
    }

    /// The entries marked with [`set_rxpdo_mapped`](CoeServer::set_rxpdo_mapped).
    pub fn rxpdo_mapped(&self) -> &HashSet<Address> {
        &self.rxpdo
    }

    /// The configuration of the SDO server.
    pub fn config(&self) -> &ServerConfig {
        self.engine.config()
    }

    /// The input mailbox size (clamped).
    pub fn mailbox_size(&self) -> usize {
        self.mailbox_size
    }

    /// True while a transfer is in progress.
    pub fn is_busy(&self) -> bool {
        self.transfer.is_some()
    }

    /// Handles a mailbox the master wrote, received at `now`.
    pub fn handle_mailbox<O: Objects + ?Sized>(
        &mut self,
        now: Instant,
        mailbox: &[u8],
        objects: &mut O,
    ) {
        self.handle_mailbox_with(now, mailbox, objects, &mut CoeOnly);
    }

    /// Handles a mailbox the master wrote, received at `now`, with `service` serving the mailbox
    /// types it takes ([`MailboxService::takes`]) in place of the CoE server: the mailbox counter
    /// and the repeat of the last answer are the same for every protocol, and a CoE transfer in
    /// progress goes on (its timer runs on).
    pub fn handle_mailbox_with<O: Objects + ?Sized>(
        &mut self,
        now: Instant,
        mailbox: &[u8],
        objects: &mut O,
        service: &mut dyn MailboxService,
    ) {
        let (dict, hook) = objects.split();
        let d = &mut Bound::new(dict, hook, now);
        self.handle_timeout(now);
        let Ok(header) = MailboxHeader::parse(mailbox) else {
            return;
        };
        if header.counter != 0 && self.last_request == Some(header.counter) {
            if let Some(previous) = self.last_response.clone() {
                self.push_transmit(previous);
            }
            return;
        }
        self.last_request = (header.counter != 0).then_some(header.counter);
        if service.takes(header.mailbox_type) {
            let answer = match MailboxHeader::split(mailbox) {
                Err(_) => Some(Answer::MailboxError(MBXERR_INVALID_SIZE)),
                Ok((header, data)) => match service.serve(now, &header, data) {
                    ServiceAnswer::Mailbox(t, body) => Some(Answer::Other(t, body)),
                    ServiceAnswer::MailboxError(code) => Some(Answer::MailboxError(code)),
                    ServiceAnswer::Nothing => None,
                },
            };
            self.last_response = answer.map(|a| {
                let bytes = self.emit(header.address, a);
                self.push_transmit(bytes.clone());
                bytes
            });
            return;
        }
        if let Some(bodies) = information(mailbox, d.dict, self.mailbox_size) {
            // SDO Information: every fragment goes out, the master reads them one after the other.
            let mut last = None;
            for body in bodies {
                let m = self.coe_mailbox(header.address, &body);
                self.transmit.push_back(m.clone());
                last = Some(m);
            }
            self.last_response = last;
            return;
        }
        let timed_out = self.timed_out.take();
        let answer = self.serve(now, mailbox, timed_out, d);
        self.deadline = match self.transfer {
            // An instant the clock cannot hold is a deadline never reached.
            Some(_) => now.checked_add(self.engine.config().timeout),
            None => None,
        };
        self.last_response = answer.map(|a| {
            let bytes = self.emit(header.address, a);
            self.push_transmit(bytes.clone());
            bytes
        });
    }

    /// Runs the transfer timer: a transfer with no request from the master for
    /// [`ServerConfig::timeout`] ends, reported as aborted with 0x05040000; nothing is sent.
    pub fn handle_timeout(&mut self, now: Instant) {
        if self.poll_timeout().is_none_or(|t| now < t) {
            return;
        }
        self.deadline = None;
        if let Some(t) = self.transfer.take() {
            let mux = t.mux();
            self.engine.fail(now, mux, AbortCode::Timeout);
            self.timed_out = Some(mux);
        }
    }

    /// When [`handle_timeout`](CoeServer::handle_timeout) is due; `None` while idle.
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Instant> {
        match (self.deadline, self.engine.poll_timeout()) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// The next mailbox for the master to read.
    #[must_use]
    pub fn poll_transmit(&mut self) -> Option<Vec<u8>> {
        self.transmit.pop_front()
    }

    /// The next event.
    #[must_use]
    pub fn poll_event(&mut self) -> Option<ServerEvent> {
        self.engine.poll_event()
    }

    /// The answer to a mailbox that is not a repeat.
    fn serve(
        &mut self,
        now: Instant,
        mailbox: &[u8],
        timed_out: Option<Address>,
        d: &mut Bound<'_>,
    ) -> Option<Answer> {
        let Ok((header, data)) = MailboxHeader::split(mailbox) else {
            return Some(Answer::MailboxError(MBXERR_INVALID_SIZE));
        };
        if header.mailbox_type != MailboxType::Coe {
            return Some(Answer::MailboxError(MBXERR_UNSUPPORTED_PROTOCOL));
        }
        let Ok(coe) = CoeHeader::parse(data) else {
            return Some(Answer::MailboxError(MBXERR_SIZE_TOO_SHORT));
        };
        if coe.service != CoeService::SdoRequest {
            return Some(Answer::MailboxError(MBXERR_SERVICE_NOT_SUPPORTED));
        }
        let sdo = &data[2..];
        let Some(raw) = sdo.get(..4) else {
            return Some(Answer::MailboxError(MBXERR_SIZE_TOO_SHORT));
        };
        // Bytes 1–3, where initiate and abort frames carry the multiplexer.
        let raw_mux = Address::new(u16::from_le_bytes([raw[1], raw[2]]), raw[3]);
        match CoeSdo::parse(CoeService::SdoRequest, sdo) {
            Ok(request) => self.request(now, request, raw_mux, timed_out, d),
            Err(CoeSdoError::Abort(code)) => Some(self.unexpected(now, raw_mux, code)),
            Err(CoeSdoError::Framing(_)) => Some(Answer::MailboxError(MBXERR_SIZE_TOO_SHORT)),
        }
    }

    /// An SDO request; `raw_mux` is bytes 1–3 of its SDO part.
    fn request(
        &mut self,
        now: Instant,
        request: CoeSdo<'_>,
        raw_mux: Address,
        timed_out: Option<Address>,
        d: &mut Bound<'_>,
    ) -> Option<Answer> {
        let CoeSdo {
            command: CoeSdoCommand::Request(frame),
            complete_access,
            extra,
        } = request
        else {
            return None;
        };
        Some(match frame {
            ClientFrame::Abort { code, .. } => {
                if let Some(t) = self.transfer.take() {
                    let mux = t.mux();
                    self.engine.end_silently(now, mux);
                    self.engine.push_event(ServerEvent::Aborted {
                        mux,
                        code,
                        by_client: true,
                    });
                }
                return None;
            }
            ClientFrame::InitiateDownloadExpedited { mux, data } => {
                self.supersede(now);
                self.download_expedited(now, mux, data, complete_access, d)
            }
            ClientFrame::InitiateDownloadSegmented { mux, size } => {
                self.supersede(now);
                self.download(now, mux, size, complete_access, extra, d)
            }
            ClientFrame::InitiateUpload { mux } => {
                self.supersede(now);
                self.upload(now, mux, complete_access, d)
            }
            ClientFrame::DownloadSegment { toggle, data, last } => {
                // Seven bytes in the segment: the data goes on after the eighth byte.
                let mut bytes = data.as_slice().to_vec();
                if data.len() == 7 {
                    bytes.extend_from_slice(extra);
                }
                match self.transfer.take() {
                    Some(Transfer::Download(t)) => {
                        self.download_segment(now, t, toggle, &bytes, last, d)
                    }
                    other => self.stray_segment(now, other, raw_mux, timed_out),
                }
            }
            ClientFrame::UploadSegment { toggle } => match self.transfer.take() {
                Some(Transfer::Upload(t)) => self.upload_segment(now, t, toggle, d),
                other => self.stray_segment(now, other, raw_mux, timed_out),
            },
            ClientFrame::InitiateBlockDownload { mux, .. }
            | ClientFrame::InitiateBlockUpload { mux, .. } => {
                self.supersede(now);
                self.refuse(mux, AbortCode::InvalidCommand)
            }
            ClientFrame::EndBlockDownload { .. }
            | ClientFrame::StartBlockUpload
            | ClientFrame::BlockUploadAck { .. }
            | ClientFrame::EndBlockUpload => {
                self.unexpected(now, raw_mux, AbortCode::InvalidCommand)
            }
        })
    }

    /// Expedited download (§5.6.2.1).
    fn download_expedited(
        &mut self,
        now: Instant,
        mux: Address,
        data: ExpeditedData,
        complete: bool,
        d: &mut Bound<'_>,
    ) -> Answer {
        if let Some(refused) = self.check_complete(mux, complete) {
            return refused;
        }
        let mut store = CoeStore::new(d, &self.rxpdo, complete);
        let frame = ClientFrame::InitiateDownloadExpedited { mux, data };
        match self.engine.exchange(now, mux, frame, &mut store, true) {
            Ok(ServerFrame::InitiateDownload { .. }) => {
                Answer::response(ServerFrame::InitiateDownload { mux }, complete)
            }
            Ok(_) => Answer::abort(mux, self.engine.unexpected(now, mux)),
            Err(code) => Answer::abort(mux, code),
        }
    }

    /// Normal download request (§5.6.2.2): the complete size and the first part of the data.
    fn download(
        &mut self,
        now: Instant,
        mux: Address,
        size: Option<u32>,
        complete: bool,
        data: &[u8],
        d: &mut Bound<'_>,
    ) -> Answer {
        if let Some(refused) = self.check_complete(mux, complete) {
            return refused;
        }
        // Without the size indicated, the data in the mailbox is the whole value (at most 65535 bytes).
        let size = size.unwrap_or(data.len() as u32);
        let mut store = CoeStore::new(d, &self.rxpdo, complete);
        let frame = ClientFrame::InitiateDownloadSegmented {
            mux,
            size: Some(size),
        };
        match self.engine.exchange(now, mux, frame, &mut store, true) {
            Ok(ServerFrame::InitiateDownload { .. }) => {}
            Ok(_) => return Answer::abort(mux, self.engine.unexpected(now, mux)),
            Err(code) => return Answer::abort(mux, code),
        }
        if !self.segmented && (data.len() as u64) < u64::from(size) {
            self.engine.fail(now, mux, AbortCode::ExceedsMailbox);
            return Answer::abort(mux, AbortCode::ExceedsMailbox);
        }
        let mut t = Download::new(mux, complete, size);
        match t.feed(&mut self.engine, now, &mut store, data, Part::Initiate) {
            Ok(done) => {
                if !done {
                    self.transfer = Some(Transfer::Download(t));
                }
                Answer::response(ServerFrame::InitiateDownload { mux }, complete)
            }
            Err(code) => Answer::abort(mux, code),
        }
    }

    /// Download segment request (§5.6.2.3) of a normal download.
    fn download_segment(
        &mut self,
        now: Instant,
        mut t: Download,
        toggle: bool,
        data: &[u8],
        last: bool,
        d: &mut Bound<'_>,
    ) -> Answer {
        if toggle != t.toggle {
            return self.fail(now, t.mux, AbortCode::ToggleBit);
        }
        let mut store = CoeStore::new(d, &self.rxpdo, t.complete);
        match t.feed(
            &mut self.engine,
            now,
            &mut store,
            data,
            Part::Segment { last },
        ) {
            Ok(done) => {
                if !done {
                    t.toggle = !toggle;
                    self.transfer = Some(Transfer::Download(t));
                }
                Answer::response(ServerFrame::DownloadSegment { toggle }, false)
            }
            Err(code) => Answer::abort(t.mux, code),
        }
    }

    /// Upload request (§5.6.2.4, §5.6.2.5).
    fn upload(&mut self, now: Instant, mux: Address, complete: bool, d: &mut Bound<'_>) -> Answer {
        if let Some(refused) = self.check_complete(mux, complete) {
            return refused;
        }
        let mut store = CoeStore::new(d, &self.rxpdo, complete);
        let frame = ClientFrame::InitiateUpload { mux };
        let size = match self.engine.exchange(now, mux, frame, &mut store, true) {
            Ok(expedited @ ServerFrame::InitiateUploadExpedited { .. }) => {
                return Answer::response(expedited, complete);
            }
            Ok(ServerFrame::InitiateUploadSegmented { size, .. }) => size,
            Ok(_) => return Answer::abort(mux, self.engine.unexpected(now, mux)),
            Err(code) => return Answer::abort(mux, code),
        };
        let capacity = self.mailbox_size - NORMAL_OVERHEAD;
        if !self.segmented && size.is_none_or(|n| n as usize > capacity) {
            self.engine.fail(now, mux, AbortCode::ExceedsMailbox);
            return Answer::abort(mux, AbortCode::ExceedsMailbox);
        }
        let mut t = Upload::new(mux, complete);
        match t.fill(&mut self.engine, now, &mut store, capacity) {
            Ok((data, done)) => {
                if done {
                    self.engine.push_event(ServerEvent::Uploaded { mux });
                } else {
                    self.transfer = Some(Transfer::Upload(t));
                }
                Answer::response_with(
                    ServerFrame::InitiateUploadSegmented { mux, size },
                    complete,
                    data,
                )
            }
            Err(code) => Answer::abort(mux, code),
        }
    }

    /// Upload segment request (§5.6.2.6) of a normal upload.
    fn upload_segment(
        &mut self,
        now: Instant,
        mut t: Upload,
        toggle: bool,
        d: &mut Bound<'_>,
    ) -> Answer {
        if toggle != t.toggle {
            return self.fail(now, t.mux, AbortCode::ToggleBit);
        }
        let mut store = CoeStore::new(d, &self.rxpdo, t.complete);
        let capacity = self.mailbox_size - SEGMENT_OVERHEAD;
        match t.fill(&mut self.engine, now, &mut store, capacity) {
            Ok((data, done)) => {
                if done {
                    self.engine.push_event(ServerEvent::Uploaded { mux: t.mux });
                } else {
                    t.toggle = !toggle;
                    self.transfer = Some(Transfer::Upload(t));
                }
                Answer::upload_segment(toggle, &data, done)
            }
            Err(code) => Answer::abort(t.mux, code),
        }
    }

    /// A segment that is not the next step of the running transfer (`transfer`, taken out).
    fn stray_segment(
        &mut self,
        now: Instant,
        transfer: Option<Transfer>,
        raw_mux: Address,
        timed_out: Option<Address>,
    ) -> Answer {
        match (transfer, timed_out) {
            (Some(t), _) => self.fail(now, t.mux(), AbortCode::InvalidCommand),
            // The transfer it belongs to has timed out (the event was reported then).
            (None, Some(mux)) => Answer::abort(mux, AbortCode::Timeout),
            (None, None) => self.refuse(raw_mux, AbortCode::InvalidCommand),
        }
    }

    /// A request that does not fit: it ends the running transfer, and is answered with `code` about
    /// that transfer, or about `raw_mux` (bytes 1–3 of the request) when none runs.
    fn unexpected(&mut self, now: Instant, raw_mux: Address, code: AbortCode) -> Answer {
        match self.transfer.take() {
            Some(t) => self.fail(now, t.mux(), code),
            None => self.refuse(raw_mux, code),
        }
    }

    /// The start of a complete access is sub-index 0 or 1 (ETG.1000.6 §5.6.2.1.2): a later one is
    /// refused with 0x06010000.
    fn check_complete(&mut self, mux: Address, complete: bool) -> Option<Answer> {
        (complete && mux.sub > 1).then(|| self.refuse(mux, AbortCode::UnsupportedAccess))
    }

    /// Ends the transfer about `mux` with `code` and answers with the abort.
    fn fail(&mut self, now: Instant, mux: Address, code: AbortCode) -> Answer {
        self.transfer = None;
        self.engine.fail(now, mux, code);
        Answer::abort(mux, code)
    }

    /// Answers a request with an abort while no transfer runs, and reports it.
    fn refuse(&mut self, mux: Address, code: AbortCode) -> Answer {
        self.engine.push_event(ServerEvent::Aborted {
            mux,
            code,
            by_client: false,
        });
        Answer::abort(mux, code)
    }

    /// Ends the running transfer for a new initiate.
    fn supersede(&mut self, now: Instant) {
        if let Some(t) = self.transfer.take() {
            let mux = t.mux();
            self.engine.end_silently(now, mux);
            self.engine.push_event(ServerEvent::Superseded { mux });
        }
    }

    /// The response mailbox for `answer`, with the next counter.
    fn emit(&mut self, address: u16, answer: Answer) -> Vec<u8> {
        self.counter = MailboxHeader::next_counter(self.counter);
        match answer {
            Answer::Sdo {
                command,
                complete_access,
                extra,
            } => CoeSdo {
                command,
                complete_access,
                extra: &extra,
            }
            .to_mailbox(address, self.counter),
            Answer::MailboxError(detail) => {
                let [c0, c1] = MBX_ERROR_COMMAND.to_le_bytes();
                let [d0, d1] = detail.to_le_bytes();
                MailboxHeader::wrap(MailboxType::Error, address, self.counter, &[c0, c1, d0, d1])
            }
            Answer::Other(mailbox_type, body) => {
                MailboxHeader::wrap(mailbox_type, address, self.counter, &body)
            }
        }
    }

    /// A CoE mailbox of `body` (CoE header onwards) with the next counter.
    fn coe_mailbox(&mut self, address: u16, body: &[u8]) -> Vec<u8> {
        self.counter = MailboxHeader::next_counter(self.counter);
        MailboxHeader::wrap(MailboxType::Coe, address, self.counter, body)
    }

    fn push_transmit(&mut self, mailbox: Vec<u8>) {
        if self.transmit.len() == TRANSMIT_CAPACITY {
            self.transmit.pop_front();
        }
        self.transmit.push_back(mailbox);
    }
}
