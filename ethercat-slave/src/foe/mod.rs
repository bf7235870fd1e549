//! File access over EtherCAT on a unit (ETG.1000.6 §5.9): [`FoeServer`], the slave's side of FoE
//! as a sans-IO state machine over the unit's [`FileStore`]; [`dir`] keeps stores in a folder (the
//! edge's files).
//!
//! The frames are [`od::foe`]'s. The unit hands the server each FoE mailbox through the CoE
//! server's mailbox ([`od::coe::MailboxService`]: one counter and one repeat rule for every
//! protocol), with the AL state and the mailbox lengths in force ([`Link`]).

pub mod dir;
pub mod store;

use std::collections::VecDeque;
use std::sync::Arc;
use std::time::{Duration, Instant};

use od::foe::{data_per_packet, FoeErrorCode, FoeFrame, FoeFrameError, FOE_HEADER_LEN};

pub use store::{FileStore, StoreError};

/// Answers kept for [`FoeServer::poll_transmit`] and events for [`FoeServer::poll_event`] at
/// most; the oldest goes when more come.
const QUEUE: usize = 16;

/// What the server takes, refuses and keeps (the rules of [`FoeServer`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FoeConfig {
    /// The largest file, in bytes.
    pub max_file: usize,
    /// All files of the unit together, in bytes.
    pub max_store: usize,
    /// The password every request must carry; `None` takes any.
    pub password: Option<u32>,
    /// The unit has a Bootstrap state: the files named by [`FoeConfig::firmware`] are written in
    /// it only, and in it nothing else is.
    pub boot: bool,
    /// The firmware files' names: patterns with `*` for any bytes, ASCII case ignored.
    pub firmware: Vec<String>,
    /// How long the unit takes to program a Data packet it took: one that comes sooner is
    /// answered with Busy and not taken (zero: never busy).
    pub packet_time: Duration,
    /// A transfer without a request for this long ends, and what it had written is dropped.
    pub timeout: Duration,
}

impl Default for FoeConfig {
    /// 4 MiB a file, 16 MiB a unit, any password, no Bootstrap, firmware `*.efw`, never busy, 10 s.
    fn default() -> FoeConfig {
        FoeConfig {
            max_file: 4 << 20,
            max_store: 16 << 20,
            password: None,
            boot: false,
            firmware: vec!["*.efw".to_string()],
            packet_time: Duration::ZERO,
            timeout: Duration::from_secs(10),
        }
    }
}

/// Whether `name` matches `pattern` (`*` any bytes, ASCII case ignored).
pub fn matches(pattern: &str, name: &[u8]) -> bool {
    let p = pattern.as_bytes();
    // The classic two-pointer match with one star to go back to.
    let (mut i, mut j) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while j < name.len() {
        if i < p.len() && p[i] == b'*' {
            star = Some((i, j));
            i += 1;
        } else if i < p.len() && p[i].eq_ignore_ascii_case(&name[j]) {
            i += 1;
            j += 1;
        } else if let Some((si, sj)) = star {
            i = si + 1;
            j = sj + 1;
            star = Some((si, sj + 1));
        } else {
            return false;
        }
    }
    p[i..].iter().all(|&c| c == b'*')
}

/// The unit's mailbox as the server answers a request: the AL state and the lengths of the
/// mailbox SyncManagers the master configured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Link {
    /// The unit is in Bootstrap.
    pub boot: bool,
    /// The length of the mailbox the master writes (SM0): a Data packet of its length less 12 is a
    /// full one.
    pub write_len: usize,
    /// The length of the mailbox the master reads (SM1): the server's Data packets carry its
    /// length less 12.
    pub read_len: usize,
}

/// What happened, for the log.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FoeEvent {
    /// A file was written whole (and is in the store).
    Written {
        /// Its name.
        name: Vec<u8>,
        /// Its size.
        size: usize,
    },
    /// A file was read whole.
    Read {
        /// Its name.
        name: Vec<u8>,
        /// Its size.
        size: usize,
    },
    /// A request was refused, or a transfer ended, with an Error frame.
    Refused {
        /// The file.
        name: Vec<u8>,
        /// The code sent.
        code: FoeErrorCode,
    },
    /// The master ended the transfer with an Error frame.
    Aborted {
        /// The file.
        name: Vec<u8>,
        /// The code it sent.
        code: FoeErrorCode,
    },
    /// A transfer had no request for the timeout and ended.
    TimedOut {
        /// The file.
        name: Vec<u8>,
    },
}

/// A transfer in progress.
#[derive(Debug, Clone)]
enum Transfer {
    /// Taking a file: the bytes so far, the next packet expected, what a full packet carries, and
    /// until when the last packet is being programmed.
    Write {
        name: Vec<u8>,
        data: Vec<u8>,
        next: u32,
        full: usize,
        busy_until: Option<(Instant, Instant)>,
    },
    /// Sending a file: the last packet sent (its number, where it starts and its length).
    Read {
        name: Vec<u8>,
        file: Arc<[u8]>,
        packet: u32,
        at: usize,
        len: usize,
        full: usize,
    },
}

impl Transfer {
    fn name(&self) -> &[u8] {
        match self {
            Transfer::Write { name, .. } | Transfer::Read { name, .. } => name,
        }
    }
}

/// The slave's side of FoE on one unit (ETG.1000.6 §5.9), with the unit's files.
///
/// # Methods and polling order
///
/// [`handle_mailbox`](FoeServer::handle_mailbox) takes an FoE frame (a mailbox's data after its
/// header) at `now` with the [`Link`] in force; then drain [`poll_transmit`](FoeServer::poll_transmit)
/// (the answer: at most one frame, none after an Error from the master),
/// [`poll_event`](FoeServer::poll_event), and [`poll_written`](FoeServer::poll_written) (files to
/// keep). [`poll_timeout`](FoeServer::poll_timeout) says when [`handle_timeout`](FoeServer::handle_timeout)
/// ends a transfer the master left; [`reset`](FoeServer::reset) ends one at once (the unit went to
/// Init). The files stay through both.
///
/// # Rules
///
/// - **Read request**: a file of the store, its name 1 to 80 bytes (trailing NULs left out), the
///   password when one is set; Data 1 follows with the first `read_len − 12` bytes, and each Ack
///   of the last packet sent brings the next, until a packet shorter than that (an empty one after
///   a file that is a multiple of it) is acknowledged. A Busy from the master sends the last packet
///   again.
/// - **Write request**: Ack 0, then Data 1, 2, … each acknowledged; a packet shorter than
///   `write_len − 12` is the last, and the file replaces the one of its name only then. Nothing
///   is kept of a write that does not end so.
/// - **Refusals** (Error frames; the transfer ends and nothing changes): 0x8001 a file that is not
///   there; 0x800A a wrong password; 0x8004 a name of 0 or more than 80 bytes, a Data frame with no
///   write, an Ack with no read; 0x8005 a Data or Ack frame of another packet; 0x8003 a file over
///   the limit of a file, or beyond the store's limit with the other files (sent when the packet
///   that passes it comes, so a write takes no more memory than the limits); 0x8000 an OpCode
///   none of 1–6, and a Busy with no read. With Bootstrap ([`FoeConfig::boot`]): 0x8009 a
///   firmware file written outside Bootstrap, 0x8008 another file written in it (a bootloader
///   takes firmware only). A file of the store is read in any state.
/// - **Busy**: with a [`FoeConfig::packet_time`], a Data packet that comes before the last one is
///   programmed is answered with Busy (Done and Entire: the milliseconds of programming gone and
///   the whole) and not taken; the master sends it again.
/// - A new Read or Write request ends a transfer in progress (its written bytes dropped); an Error
///   from the master ends it without an answer.
/// - Every answer fits the read mailbox: Data packets of its length less 12 bytes, Error texts cut
///   to that; a read from a mailbox of 12 bytes or fewer, or one the master made shorter during the
///   read, ends with 0x8000.
#[derive(Debug, Clone)]
pub struct FoeServer {
    config: FoeConfig,
    store: FileStore,
    transfer: Option<Transfer>,
    deadline: Option<Instant>,
    transmit: VecDeque<Vec<u8>>,
    events: VecDeque<FoeEvent>,
    /// The read mailbox's length at the request being answered: an Error's text fits it.
    read_len: usize,
}

impl FoeServer {
    /// A server with `store` as the unit's files, as `config` says.
    pub fn new(config: FoeConfig, store: FileStore) -> FoeServer {
        FoeServer {
            config,
            store,
            transfer: None,
            deadline: None,
            transmit: VecDeque::new(),
            events: VecDeque::new(),
            read_len: 0,
        }
    }

    /// The configuration.
    pub fn config(&self) -> &FoeConfig {
        &self.config
    }

    /// The unit's files.
    pub fn store(&self) -> &FileStore {
        &self.store
    }

    /// The unit's files, to put in those it had before it started ([`dir::load`]).
    pub fn store_mut(&mut self) -> &mut FileStore {
        &mut self.store
    }

    /// True while a transfer runs.
    pub fn is_busy(&self) -> bool {
        self.transfer.is_some()
    }

    /// Ends the transfer in progress, if any (the unit went to Init); the files stay.
    pub fn reset(&mut self) {
        self.transfer = None;
        self.deadline = None;
    }

    /// The answer to the last request.
    #[must_use]
    pub fn poll_transmit(&mut self) -> Option<Vec<u8>> {
        self.transmit.pop_front()
    }

    /// The next event.
    #[must_use]
    pub fn poll_event(&mut self) -> Option<FoeEvent> {
        self.events.pop_front()
    }

    /// A file written since the last call, to keep ([`FileStore::take_written`]).
    #[must_use]
    pub fn poll_written(&mut self) -> Option<(Vec<u8>, Arc<[u8]>)> {
        self.store.take_written()
    }

    /// When the transfer in progress ends unless a request comes.
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Instant> {
        self.deadline
    }

    /// Ends the transfer when its time has run out at `now`.
    pub fn handle_timeout(&mut self, now: Instant) {
        if self.deadline.is_some_and(|d| now >= d) {
            self.deadline = None;
            if let Some(t) = self.transfer.take() {
                let name = t.name().to_vec();
                self.event(FoeEvent::TimedOut { name });
            }
        }
    }

    /// Takes `frame`, an FoE mailbox's data after its header, received at `now` while `link` holds.
    /// A frame shorter than the FoE header is the caller's to refuse (mailbox error 0x0006).
    pub fn handle_mailbox(&mut self, now: Instant, frame: &[u8], link: Link) {
        self.handle_timeout(now);
        self.read_len = link.read_len;
        if frame.len() < FOE_HEADER_LEN {
            return;
        }
        let answer = match FoeFrame::parse(frame) {
            Ok(f) => self.serve(now, f, link),
            Err(FoeFrameError::UnknownOpCode(op)) => {
                let name = self.end();
                Some(self.refuse(name, FoeErrorCode::NotDefined, &format!("OpCode {op}")))
            }
            Err(_) => None,
        };
        self.deadline = match self.transfer {
            Some(_) => now.checked_add(self.config.timeout),
            None => None,
        };
        if let Some(a) = answer {
            if self.transmit.len() == QUEUE {
                self.transmit.pop_front();
            }
            self.transmit.push_back(a);
        }
    }

    fn event(&mut self, e: FoeEvent) {
        if self.events.len() == QUEUE {
            self.events.pop_front();
        }
        self.events.push_back(e);
    }

    /// Ends the transfer in progress: its file's name (empty without one).
    fn end(&mut self) -> Vec<u8> {
        self.transfer
            .take()
            .map(|t| t.name().to_vec())
            .unwrap_or_default()
    }

    /// The Error frame with `code` and `text` (an event says so).
    /// The Error frame with `code` and `text` (an event says so), the text cut to what the read
    /// mailbox holds beside the headers.
    fn refuse(&mut self, name: Vec<u8>, code: FoeErrorCode, text: &str) -> Vec<u8> {
        self.event(FoeEvent::Refused { name, code });
        let text = text.as_bytes();
        let room = data_per_packet(self.read_len).min(text.len());
        FoeFrame::Error {
            code,
            text: &text[..room],
        }
        .to_vec()
    }

    fn serve(&mut self, now: Instant, frame: FoeFrame<'_>, link: Link) -> Option<Vec<u8>> {
        match frame {
            FoeFrame::Read { password, name } => Some(self.read(password, name, link)),
            FoeFrame::Write { password, name } => Some(self.write(password, name, link)),
            FoeFrame::Data { packet, data } => Some(self.data(now, packet, data)),
            FoeFrame::Ack { packet } => self.ack(packet, link),
            FoeFrame::Busy { .. } => Some(self.busy(link)),
            FoeFrame::Error { code, .. } => {
                if let Some(t) = self.transfer.take() {
                    let name = t.name().to_vec();
                    self.event(FoeEvent::Aborted { name, code });
                }
                None
            }
        }
    }

    /// The name of a request, trailing NULs left out, or the refusal of a name (0x8004) or a
    /// password (0x800A).
    fn check_request<'a>(&mut self, password: u32, name: &'a [u8]) -> Result<&'a [u8], Vec<u8>> {
        let end = name.iter().rposition(|&b| b != 0).map_or(0, |k| k + 1);
        let name = &name[..end];
        if let Err(e) = FileStore::check_name(name) {
            return Err(self.refuse(name.to_vec(), FoeErrorCode::Illegal, &e.to_string()));
        }
        if self.config.password.is_some_and(|p| p != password) {
            return Err(self.refuse(name.to_vec(), FoeErrorCode::NoRights, "wrong password"));
        }
        Ok(name)
    }

    fn read(&mut self, password: u32, name: &[u8], link: Link) -> Vec<u8> {
        self.end();
        let name = match self.check_request(password, name) {
            Ok(n) => n,
            Err(refusal) => return refusal,
        };
        let Some(file) = self.store.get(name).cloned() else {
            return self.refuse(name.to_vec(), FoeErrorCode::NotFound, "no such file");
        };
        let full = data_per_packet(link.read_len);
        if full == 0 {
            let text = "the read mailbox holds no file data";
            return self.refuse(name.to_vec(), FoeErrorCode::NotDefined, text);
        }
        let len = full.min(file.len());
        let frame = FoeFrame::Data {
            packet: 1,
            data: &file[..len],
        }
        .to_vec();
        self.transfer = Some(Transfer::Read {
            name: name.to_vec(),
            file,
            packet: 1,
            at: 0,
            len,
            full,
        });
        frame
    }

    fn write(&mut self, password: u32, name: &[u8], link: Link) -> Vec<u8> {
        self.end();
        let name = match self.check_request(password, name) {
            Ok(n) => n,
            Err(refusal) => return refusal,
        };
        if self.config.boot {
            let firmware = self.config.firmware.iter().any(|p| matches(p, name));
            if firmware && !link.boot {
                let text = "firmware is written in Bootstrap";
                return self.refuse(name.to_vec(), FoeErrorCode::NotBootstrap, text);
            }
            if !firmware && link.boot {
                let text = "only firmware is written in Bootstrap";
                return self.refuse(name.to_vec(), FoeErrorCode::BootstrapOnly, text);
            }
        }
        self.transfer = Some(Transfer::Write {
            name: name.to_vec(),
            data: Vec::new(),
            next: 1,
            full: data_per_packet(link.write_len).max(1),
            busy_until: None,
        });
        FoeFrame::Ack { packet: 0 }.to_vec()
    }

    fn data(&mut self, now: Instant, packet: u32, bytes: &[u8]) -> Vec<u8> {
        let Some(Transfer::Write {
            name,
            data,
            next,
            full,
            busy_until,
        }) = &mut self.transfer
        else {
            let name = self.end();
            return self.refuse(name, FoeErrorCode::Illegal, "no write in progress");
        };
        if let Some((from, until)) = busy_until.filter(|(_, until)| now < *until) {
            let ms = |d: Duration| u16::try_from(d.as_millis()).unwrap_or(u16::MAX);
            return FoeFrame::Busy {
                done: ms(now.saturating_duration_since(from)),
                entire: ms(until.saturating_duration_since(from)),
                text: &[],
            }
            .to_vec();
        }
        if packet != *next {
            let text = format!("packet {packet}, not {next}");
            let name = self.end();
            return self.refuse(name, FoeErrorCode::PacketNumberWrong, &text);
        }
        let size = data.len().saturating_add(bytes.len());
        if let Err(e) = self.store.check(name, size) {
            let name = self.end();
            return self.refuse(name, FoeErrorCode::DiskFull, &e.to_string());
        }
        data.extend_from_slice(bytes);
        *next += 1;
        let last = bytes.len() < *full;
        if !self.config.packet_time.is_zero() {
            *busy_until = now
                .checked_add(self.config.packet_time)
                .map(|until| (now, until));
        }
        if last {
            if let Some(Transfer::Write { name, data, .. }) = self.transfer.take() {
                let size = data.len();
                // Checked with the packet above: the store takes it.
                let _ = self.store.put(&name, data.into());
                self.event(FoeEvent::Written { name, size });
            }
        }
        FoeFrame::Ack { packet }.to_vec()
    }

    /// Ends a read whose packets no longer fit the read mailbox (the master made it shorter
    /// during the transfer): the Error, or `None` while they fit.
    fn shrunk(&mut self, link: Link) -> Option<Vec<u8>> {
        let full = match &self.transfer {
            Some(Transfer::Read { full, .. }) => *full,
            _ => return None,
        };
        (data_per_packet(link.read_len) < full).then(|| {
            let name = self.end();
            let text = "the read mailbox is shorter than at the start";
            self.refuse(name, FoeErrorCode::NotDefined, text)
        })
    }

    /// The next packet of a read, or nothing after the last one's Ack.
    fn ack(&mut self, acked: u32, link: Link) -> Option<Vec<u8>> {
        if let Some(refusal) = self.shrunk(link) {
            return Some(refusal);
        }
        let Some(Transfer::Read {
            file,
            packet,
            at,
            len,
            full,
            ..
        }) = &mut self.transfer
        else {
            let name = self.end();
            return Some(self.refuse(name, FoeErrorCode::Illegal, "no read in progress"));
        };
        if acked != *packet {
            let text = format!("Ack of packet {acked}, not {packet}");
            let name = self.end();
            return Some(self.refuse(name, FoeErrorCode::PacketNumberWrong, &text));
        }
        if *len < *full {
            let size = file.len();
            let name = self.end();
            self.event(FoeEvent::Read { name, size });
            return None;
        }
        *at += *len;
        *len = (*full).min(file.len() - *at);
        *packet += 1;
        Some(
            FoeFrame::Data {
                packet: *packet,
                data: &file[*at..*at + *len],
            }
            .to_vec(),
        )
    }

    /// The master is busy: the last Data packet of a read again.
    fn busy(&mut self, link: Link) -> Vec<u8> {
        if let Some(refusal) = self.shrunk(link) {
            return refusal;
        }
        match &self.transfer {
            Some(Transfer::Read {
                file,
                packet,
                at,
                len,
                ..
            }) => FoeFrame::Data {
                packet: *packet,
                data: &file[*at..*at + *len],
            }
            .to_vec(),
            _ => {
                let name = self.end();
                self.refuse(name, FoeErrorCode::NotDefined, "Busy with no read")
            }
        }
    }
}

#[cfg(test)]
mod tests;
