//! The LSS master (CiA 305 "Layer setting services"), sans-IO: one service at a time, each request
//! sent on [`LSS_REQUEST`] (0x7E5) and its answer awaited on [`LSS_RESPONSE`] (0x7E4) for a bound
//! ([`DEFAULT_TIMEOUT`], 100 ms, unless [`LssMaster::with_timeout`] says otherwise).
//!
//! The runtime loop, as every core of the workspace: [`LssMaster::start`] a [`LssRequest`]; send
//! what [`LssMaster::poll_transmit`] gives; hand every frame received to
//! [`LssMaster::handle_frame`] and, when [`LssMaster::poll_timeout`] is reached,
//! call [`LssMaster::handle_timeout`]; [`LssMaster::poll_event`] gives the outcome of the service,
//! an [`LssAnswer`] or a typed [`LssError`].
//!
//! Choices where CiA 305 leaves room:
//! - Switch state global and activate bit timing have no answer: they finish as soon as their frame
//!   is polled.
//! - The identify services finish with the first answer; silence for the bound is the answer "no
//!   such slave" ([`LssAnswer::Identified`]`(false)`), not an error.
//! - Fastscan (§8.4.2.4) runs as python-canopen's `fast_scan`: a first request with `BitChecked`
//!   0x80 (silence: no unconfigured slave, [`LssAnswer::NotFound`]), then for each part of the
//!   address the bits 31 down to 0, each asked with the bit clear (silence: the bit is 1), then the
//!   part confirmed with `BitChecked` 0 and `LSSNext` the next part (0 after the serial number,
//!   which puts the slave found into the configuration state). Silence at a confirmation means an
//!   answer came too late for its step (a busy gateway or machine): after a quiet bound the scan
//!   starts again with twice the bound, up to [`FASTSCAN_RETRIES`] times, then
//!   [`LssError::FastscanLost`].
//! - Several slaves answer a Fastscan step alike; where their frames do not merge on the wire (a
//!   bus of software nodes, a gateway), the copies come one after the other. So after the first
//!   answer to a step the master waits a settling time (a tenth of the bound; 10 ms by default)
//!   and takes what comes in it as the same answer, before it sends the next step.
//! - Frames of another COB-ID or length than 8, and answers of another command specifier than the
//!   one awaited, are ignored.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use can_link::CanFrame;

/// COB-ID of the master's requests (CiA 305 §7.2).
pub const LSS_REQUEST: u16 = 0x7E5;
/// COB-ID of the slaves' answers (CiA 305 §7.2).
pub const LSS_RESPONSE: u16 = 0x7E4;
/// How long a request waits for its answer unless told otherwise.
pub const DEFAULT_TIMEOUT: Duration = Duration::from_millis(100);

/// How long store configuration waits for its answer at least: a node answers once its
/// non-volatile memory holds the configuration (a write and its sync, on a slow disk or flash
/// some hundreds of milliseconds), not within a scan step's bound.
pub const STORE_TIMEOUT: Duration = Duration::from_secs(1);

/// The longest bound a master takes; a longer one is cut to this.
pub const MAX_TIMEOUT: Duration = Duration::from_secs(3600);

/// The LSS address (CiA 305 §6.1): vendor-ID, product code, revision number and serial number
/// (0x1018 sub-indices 1 to 4).
pub type LssAddress = [u32; 4];

/// The parts of the LSS address, in the order of the services that name them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AddressPart {
    /// Vendor-ID (0x1018:01).
    Vendor,
    /// Product code (0x1018:02).
    Product,
    /// Revision number (0x1018:03).
    Revision,
    /// Serial number (0x1018:04).
    Serial,
}

impl AddressPart {
    /// The four parts in order.
    pub const ALL: [AddressPart; 4] = [
        AddressPart::Vendor,
        AddressPart::Product,
        AddressPart::Revision,
        AddressPart::Serial,
    ];

    /// 0 to 3.
    pub fn index(self) -> u8 {
        self as u8
    }

    /// The part's name in words.
    pub fn name(self) -> &'static str {
        match self {
            AddressPart::Vendor => "vendor-ID",
            AddressPart::Product => "product code",
            AddressPart::Revision => "revision number",
            AddressPart::Serial => "serial number",
        }
    }
}

/// The LSS state to switch to (CiA 305 §6.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LssState {
    /// LSS waiting (mode 0).
    Waiting,
    /// LSS configuration (mode 1).
    Configuration,
}

/// A service of the LSS master (CiA 305 §8).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LssRequest {
    /// Switch state global (§8.2.1, cs 0x04): every slave; no answer.
    SwitchGlobal(LssState),
    /// Switch state selective (§8.2.2, cs 0x40–0x43, answer 0x44): the slave of this address to
    /// the configuration state.
    SwitchSelective(LssAddress),
    /// Configure node-ID (§8.3.1, cs 0x11): 1–127, or 0xFF for none.
    ConfigureNodeId(u8),
    /// Configure bit timing parameters (§8.3.2, cs 0x13): table selector and index.
    ConfigureBitTiming {
        /// Table selector (0: the CiA 301 table).
        table: u8,
        /// Index in the table.
        index: u8,
    },
    /// Activate bit timing parameters (§8.3.3, cs 0x15) after the delay in ms; no answer.
    ActivateBitTiming {
        /// The switch delay in ms.
        delay_ms: u16,
    },
    /// Store configuration (§8.3.4, cs 0x17).
    Store,
    /// Inquire identity vendor-ID, product code, revision or serial number (§8.3.5, cs 0x5A–0x5D).
    Inquire(AddressPart),
    /// Inquire node-ID (§8.3.6, cs 0x5E).
    InquireNodeId,
    /// Identify remote slave (§8.4.2, cs 0x46–0x4B, answer 0x4F): a slave of this vendor and
    /// product with a revision and a serial number in the ranges (both ends included).
    IdentifyRemote {
        /// Vendor-ID.
        vendor: u32,
        /// Product code.
        product: u32,
        /// Lowest and highest revision number.
        revision: (u32, u32),
        /// Lowest and highest serial number.
        serial: (u32, u32),
    },
    /// Identify non-configured remote slave (§8.4.3, cs 0x4C, answer 0x50).
    IdentifyNonConfigured,
    /// Fastscan (§8.4.2.4, cs 0x51, answer 0x4F): the address of one slave without a node-ID,
    /// which ends in the configuration state.
    Fastscan,
    /// Fastscan with each part of the address scanned, matched against a value (confirmed at once,
    /// no bit asked) or skipped (the confirmation before it names the part after it as `LSSNext`;
    /// the address found has 0 there). The vendor-ID cannot be skipped, a slave starting at it:
    /// skipping it scans it.
    FastscanWith([PartScan; 4]),
}

/// How Fastscan treats one part of the address ([`LssRequest::FastscanWith`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartScan {
    /// Found bit by bit.
    Scan,
    /// Not looked at.
    Skip,
    /// This value, confirmed at once.
    Match(u32),
}

impl LssRequest {
    /// The service's name in words.
    pub fn name(&self) -> &'static str {
        match self {
            LssRequest::SwitchGlobal(_) => "switch state global",
            LssRequest::SwitchSelective(_) => "switch state selective",
            LssRequest::ConfigureNodeId(_) => "configure node-ID",
            LssRequest::ConfigureBitTiming { .. } => "configure bit timing",
            LssRequest::ActivateBitTiming { .. } => "activate bit timing",
            LssRequest::Store => "store configuration",
            LssRequest::Inquire(_) => "inquire identity",
            LssRequest::InquireNodeId => "inquire node-ID",
            LssRequest::IdentifyRemote { .. } => "identify remote slave",
            LssRequest::IdentifyNonConfigured => "identify non-configured remote slave",
            LssRequest::Fastscan | LssRequest::FastscanWith(_) => "Fastscan",
        }
    }
}

/// What a service came to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LssAnswer {
    /// Switch state global or activate bit timing: sent (they have no answer).
    Sent,
    /// Switch state selective: the slave is in the configuration state.
    Selected,
    /// Configure node-ID, configure bit timing or store configuration: done (error code 0).
    Done,
    /// Inquire identity: the part asked for.
    Value(u32),
    /// Inquire node-ID: the active node-ID (0xFF: none).
    NodeId(u8),
    /// Identify: whether a slave answered within the bound.
    Identified(bool),
    /// Fastscan: the address of the slave found (now in the configuration state).
    Found(LssAddress),
    /// Fastscan: no slave without a node-ID answered.
    NotFound,
}

/// Why a service failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum LssError {
    /// No answer within the bound.
    #[error("{service}: no answer within {} ms", timeout.as_millis())]
    Timeout {
        /// The service.
        service: &'static str,
        /// The bound.
        timeout: Duration,
    },
    /// The slave refused: its error code (1 out of range or not supported, 0xFF
    /// manufacturer-specific, with the specific error).
    #[error("{service}: refused with error code {code}{}", refusal_text(*code, *specific))]
    Refused {
        /// The service.
        service: &'static str,
        /// The error code (byte 1 of the answer).
        code: u8,
        /// The manufacturer-specific error (byte 2), meaningful with code 0xFF.
        specific: u8,
    },
    /// Fastscan: the slave being scanned did not confirm a part of its address.
    #[error("Fastscan: no slave confirmed the {} 0x{value:08X}", part.name())]
    FastscanLost {
        /// The part of the address.
        part: AddressPart,
        /// Its value as scanned.
        value: u32,
    },
    /// A service was started while another was running.
    #[error("{service}: another LSS service is still running")]
    Busy {
        /// The service refused.
        service: &'static str,
    },
    /// A request out of range: a node-ID not 1–127 or 0xFF.
    #[error("{service}: node-ID {node_id} is not 1 to 127 or 0xFF")]
    NodeId {
        /// The service.
        service: &'static str,
        /// The node-ID.
        node_id: u8,
    },
}

fn refusal_text(code: u8, specific: u8) -> String {
    match code {
        1 => " (out of range or not supported)".into(),
        0xFF => format!(" (manufacturer-specific error 0x{specific:02X})"),
        _ => String::new(),
    }
}

/// Command specifiers (CiA 305 §8, table 2).
mod cs {
    pub(super) const SWITCH_GLOBAL: u8 = 0x04;
    pub(super) const CONFIGURE_NODE_ID: u8 = 0x11;
    pub(super) const CONFIGURE_BIT_TIMING: u8 = 0x13;
    pub(super) const ACTIVATE_BIT_TIMING: u8 = 0x15;
    pub(super) const STORE: u8 = 0x17;
    pub(super) const SELECTIVE_VENDOR: u8 = 0x40;
    pub(super) const SELECTIVE_RESPONSE: u8 = 0x44;
    pub(super) const IDENTIFY_VENDOR: u8 = 0x46;
    pub(super) const IDENTIFY_NON_CONFIGURED: u8 = 0x4C;
    pub(super) const IDENTIFY_SLAVE: u8 = 0x4F;
    pub(super) const IDENTIFY_NON_CONFIGURED_SLAVE: u8 = 0x50;
    pub(super) const FASTSCAN: u8 = 0x51;
    pub(super) const INQUIRE_VENDOR: u8 = 0x5A;
    pub(super) const INQUIRE_NODE_ID: u8 = 0x5E;
}

/// Where a Fastscan is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scan {
    /// The first request (`BitChecked` 0x80).
    Start,
    /// Asking bit `bit` of part `sub`.
    Bit { sub: u8, bit: u8 },
    /// Confirming part `sub`.
    Confirm { sub: u8 },
    /// After a part was not confirmed: answers still on their way are let pass before the scan
    /// starts again.
    Quiet,
}

/// How often a Fastscan starts again after a part was not confirmed, each time with twice the
/// bound of the last.
pub const FASTSCAN_RETRIES: u8 = 2;

/// The service running.
#[derive(Debug, Clone, Copy)]
struct Running {
    request: LssRequest,
    /// The command specifier of the answer awaited.
    answer: u8,
    deadline: Instant,
    /// Fastscan only: the address so far and the step.
    address: LssAddress,
    scan: Scan,
    /// Fastscan only: the step was answered; its copies are awaited until the deadline.
    settling: bool,
    /// Fastscan only: the bound of each step, doubled at each new start.
    step: Duration,
    /// Fastscan only: the starts again so far, and the part last not confirmed.
    retries: u8,
    lost: Option<(AddressPart, u32)>,
    /// Fastscan only: how each part is taken.
    parts: [PartScan; 4],
}

/// The LSS master; see the [module documentation](self).
#[derive(Debug)]
pub struct LssMaster {
    timeout: Duration,
    now: Option<Instant>,
    running: Option<Running>,
    transmit: VecDeque<CanFrame>,
    events: VecDeque<Result<LssAnswer, LssError>>,
}

impl Default for LssMaster {
    fn default() -> Self {
        LssMaster::new()
    }
}

fn frame(data: [u8; 8]) -> CanFrame {
    CanFrame::new(LSS_REQUEST, &data).expect("8 bytes on an 11-bit COB-ID")
}

fn request_frame(command: u8, bytes: &[u8]) -> CanFrame {
    let mut d = [0u8; 8];
    d[0] = command;
    d[1..1 + bytes.len()].copy_from_slice(bytes);
    frame(d)
}

fn fastscan(id: u32, bit: u8, sub: u8, next: u8) -> CanFrame {
    let v = id.to_le_bytes();
    frame([cs::FASTSCAN, v[0], v[1], v[2], v[3], bit, sub, next])
}

impl LssMaster {
    /// A master waiting [`DEFAULT_TIMEOUT`] for each answer.
    pub fn new() -> LssMaster {
        LssMaster::with_timeout(DEFAULT_TIMEOUT)
    }

    /// A master waiting `timeout` for each answer (and each Fastscan step; a tenth of it for the
    /// copies of a Fastscan answer); at most [`MAX_TIMEOUT`].
    pub fn with_timeout(timeout: Duration) -> LssMaster {
        LssMaster {
            timeout: timeout.min(MAX_TIMEOUT),
            now: None,
            running: None,
            transmit: VecDeque::new(),
            events: VecDeque::new(),
        }
    }

    /// The bound on each answer.
    pub fn timeout(&self) -> Duration {
        self.timeout
    }

    /// Whether a service is running.
    pub fn is_busy(&self) -> bool {
        self.running.is_some()
    }

    fn advance(&mut self, now: Instant) -> Instant {
        let now = self.now.map_or(now, |t| t.max(now));
        self.now = Some(now);
        now
    }

    /// Starts `request` at `now`: its frames go to [`poll_transmit`](Self::poll_transmit), its
    /// outcome comes from [`poll_event`](Self::poll_event). Refused while another service runs.
    pub fn start(&mut self, now: Instant, request: LssRequest) -> Result<(), LssError> {
        let service = request.name();
        if self.running.is_some() {
            return Err(LssError::Busy { service });
        }
        let now = self.advance(now);
        let answer = match request {
            LssRequest::SwitchGlobal(state) => {
                let mode = u8::from(state == LssState::Configuration);
                self.transmit
                    .push_back(request_frame(cs::SWITCH_GLOBAL, &[mode]));
                self.events.push_back(Ok(LssAnswer::Sent));
                return Ok(());
            }
            LssRequest::ActivateBitTiming { delay_ms } => {
                self.transmit.push_back(request_frame(
                    cs::ACTIVATE_BIT_TIMING,
                    &delay_ms.to_le_bytes(),
                ));
                self.events.push_back(Ok(LssAnswer::Sent));
                return Ok(());
            }
            LssRequest::SwitchSelective(address) => {
                for (i, part) in address.iter().enumerate() {
                    self.transmit.push_back(request_frame(
                        cs::SELECTIVE_VENDOR + i as u8,
                        &part.to_le_bytes(),
                    ));
                }
                cs::SELECTIVE_RESPONSE
            }
            LssRequest::ConfigureNodeId(id) => {
                if !((1..=127).contains(&id) || id == 0xFF) {
                    return Err(LssError::NodeId {
                        service,
                        node_id: id,
                    });
                }
                self.transmit
                    .push_back(request_frame(cs::CONFIGURE_NODE_ID, &[id]));
                cs::CONFIGURE_NODE_ID
            }
            LssRequest::ConfigureBitTiming { table, index } => {
                self.transmit
                    .push_back(request_frame(cs::CONFIGURE_BIT_TIMING, &[table, index]));
                cs::CONFIGURE_BIT_TIMING
            }
            LssRequest::Store => {
                self.transmit.push_back(request_frame(cs::STORE, &[]));
                cs::STORE
            }
            LssRequest::Inquire(part) => {
                let c = cs::INQUIRE_VENDOR + part.index();
                self.transmit.push_back(request_frame(c, &[]));
                c
            }
            LssRequest::InquireNodeId => {
                self.transmit
                    .push_back(request_frame(cs::INQUIRE_NODE_ID, &[]));
                cs::INQUIRE_NODE_ID
            }
            LssRequest::IdentifyRemote {
                vendor,
                product,
                revision,
                serial,
            } => {
                let parts = [vendor, product, revision.0, revision.1, serial.0, serial.1];
                for (i, part) in parts.iter().enumerate() {
                    self.transmit.push_back(request_frame(
                        cs::IDENTIFY_VENDOR + i as u8,
                        &part.to_le_bytes(),
                    ));
                }
                cs::IDENTIFY_SLAVE
            }
            LssRequest::IdentifyNonConfigured => {
                self.transmit
                    .push_back(request_frame(cs::IDENTIFY_NON_CONFIGURED, &[]));
                cs::IDENTIFY_NON_CONFIGURED_SLAVE
            }
            LssRequest::Fastscan | LssRequest::FastscanWith(_) => {
                self.transmit.push_back(fastscan(0, 0x80, 0, 0));
                cs::IDENTIFY_SLAVE
            }
        };
        let mut parts = match request {
            LssRequest::FastscanWith(parts) => parts,
            _ => [PartScan::Scan; 4],
        };
        if parts[0] == PartScan::Skip {
            parts[0] = PartScan::Scan;
        }
        self.running = Some(Running {
            request,
            answer,
            deadline: now + self.bound(&request),
            address: [0; 4],
            scan: Scan::Start,
            settling: false,
            step: self.timeout,
            retries: 0,
            lost: None,
            parts,
        });
        Ok(())
    }

    /// How long `request` waits for its answer: the master's bound, and at least
    /// [`STORE_TIMEOUT`] for store configuration.
    fn bound(&self, request: &LssRequest) -> Duration {
        match request {
            LssRequest::Store => self.timeout.max(STORE_TIMEOUT),
            _ => self.timeout,
        }
    }

    /// The next frame to send, in order.
    pub fn poll_transmit(&mut self) -> Option<CanFrame> {
        self.transmit.pop_front()
    }

    /// The outcome of the last service, once it is there.
    pub fn poll_event(&mut self) -> Option<Result<LssAnswer, LssError>> {
        self.events.pop_front()
    }

    /// When [`handle_timeout`](Self::handle_timeout) is next due (`None`: no service waits).
    pub fn poll_timeout(&self) -> Option<Instant> {
        self.running.map(|r| r.deadline)
    }

    /// A frame from the bus at `now`: the answer awaited, or nothing to the master.
    pub fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        let now = self.advance(now);
        let Some(running) = self.running else {
            return;
        };
        if frame.cob_id() != Some(LSS_RESPONSE) || frame.data().len() != 8 {
            return;
        }
        let d = frame.data8();
        if d[0] != running.answer {
            return;
        }
        let service = running.request.name();
        let outcome = match running.request {
            LssRequest::Fastscan | LssRequest::FastscanWith(_) => {
                if !running.settling && running.scan != Scan::Quiet {
                    self.running = Some(Running {
                        settling: true,
                        deadline: now + running.step / 10,
                        ..running
                    });
                }
                return;
            }
            LssRequest::SwitchSelective(_) => Ok(LssAnswer::Selected),
            LssRequest::ConfigureNodeId(_)
            | LssRequest::ConfigureBitTiming { .. }
            | LssRequest::Store => match d[1] {
                0 => Ok(LssAnswer::Done),
                code => Err(LssError::Refused {
                    service,
                    code,
                    specific: d[2],
                }),
            },
            LssRequest::Inquire(_) => Ok(LssAnswer::Value(u32::from_le_bytes([
                d[1], d[2], d[3], d[4],
            ]))),
            LssRequest::InquireNodeId => Ok(LssAnswer::NodeId(d[1])),
            LssRequest::IdentifyRemote { .. } | LssRequest::IdentifyNonConfigured => {
                Ok(LssAnswer::Identified(true))
            }
            LssRequest::SwitchGlobal(_) | LssRequest::ActivateBitTiming { .. } => return,
        };
        self.finish(outcome);
    }

    /// The time is `now`: a service whose bound passed ends (a Fastscan takes the silence as "no"
    /// and goes on).
    pub fn handle_timeout(&mut self, now: Instant) {
        let now = self.advance(now);
        let Some(running) = self.running else {
            return;
        };
        if running.deadline > now {
            return;
        }
        let service = running.request.name();
        let outcome = match running.request {
            LssRequest::Fastscan | LssRequest::FastscanWith(_) => {
                return self.fastscan_step(now, running.settling)
            }
            LssRequest::IdentifyRemote { .. } | LssRequest::IdentifyNonConfigured => {
                Ok(LssAnswer::Identified(false))
            }
            _ => Err(LssError::Timeout {
                service,
                timeout: self.bound(&running.request),
            }),
        };
        self.finish(outcome);
    }

    fn finish(&mut self, outcome: Result<LssAnswer, LssError>) {
        self.running = None;
        self.events.push_back(outcome);
    }

    /// The next Fastscan request after an answer (`answered`) or silence.
    fn fastscan_step(&mut self, now: Instant, answered: bool) {
        let Some(mut r) = self.running else {
            return;
        };
        // While bits are asked, LSSNext is the part under scan: the slave stays at it.
        let bit_request = |address: &LssAddress, sub: u8, bit: u8| {
            (
                Scan::Bit { sub, bit },
                fastscan(address[usize::from(sub)], bit, sub, sub),
            )
        };
        let parts = r.parts;
        // The part after `sub` that is not skipped; 0 (back to the first) after the last.
        let next_part = |sub: u8| (sub + 1..4).find(|&k| parts[usize::from(k)] != PartScan::Skip);
        let confirm = |address: &LssAddress, sub: u8| {
            let next = next_part(sub).unwrap_or(0);
            (
                Scan::Confirm { sub },
                fastscan(address[usize::from(sub)], 0, sub, next),
            )
        };
        // A part begins: a value to match is confirmed at once, else its bits are asked.
        let begin = |address: &mut LssAddress, sub: u8| match parts[usize::from(sub)] {
            PartScan::Match(v) => {
                address[usize::from(sub)] = v;
                confirm(address, sub)
            }
            _ => bit_request(address, sub, 31),
        };
        let (next, request) = match r.scan {
            Scan::Start if !answered => {
                return match r.lost {
                    // The slave answered before: it is there, late.
                    Some(lost) => self.fastscan_again(now, r, lost),
                    None => self.finish(Ok(LssAnswer::NotFound)),
                };
            }
            Scan::Start => begin(&mut r.address, 0),
            Scan::Quiet => (Scan::Start, fastscan(0, 0x80, 0, 0)),
            Scan::Bit { sub, bit } => {
                if !answered {
                    r.address[usize::from(sub)] |= 1 << bit;
                }
                match bit {
                    0 => confirm(&r.address, sub),
                    _ => bit_request(&r.address, sub, bit - 1),
                }
            }
            Scan::Confirm { sub } if !answered => {
                let lost = (
                    AddressPart::ALL[usize::from(sub)],
                    r.address[usize::from(sub)],
                );
                return self.fastscan_again(now, r, lost);
            }
            Scan::Confirm { sub } => match next_part(sub) {
                Some(k) => begin(&mut r.address, k),
                None => return self.finish(Ok(LssAnswer::Found(r.address))),
            },
        };
        self.transmit.push_back(request);
        r.scan = next;
        r.settling = false;
        r.deadline = now + r.step;
        self.running = Some(r);
    }

    /// A part was not confirmed (`lost`): an answer came too late for its step and was taken for
    /// the next one's. The scan starts again from its first request (which sets every slave back
    /// to the first part), with twice the bound, after a quiet bound for late answers; after
    /// [`FASTSCAN_RETRIES`] starts again, [`LssError::FastscanLost`].
    fn fastscan_again(&mut self, now: Instant, mut r: Running, lost: (AddressPart, u32)) {
        if r.retries >= FASTSCAN_RETRIES {
            return self.finish(Err(LssError::FastscanLost {
                part: lost.0,
                value: lost.1,
            }));
        }
        r.retries += 1;
        r.lost = Some(lost);
        r.address = [0; 4];
        r.scan = Scan::Quiet;
        r.settling = false;
        r.deadline = now + r.step;
        r.step = (r.step * 2).min(MAX_TIMEOUT);
        self.running = Some(r);
    }
}
