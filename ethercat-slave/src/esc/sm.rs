//! SyncManagers (ETG.1000.4 §6.7, ESC register block 0x0800 + 8·n): how the master's accesses to the
//! memory a SyncManager guards are gated and what they trigger.
//!
//! - **Mailbox mode** (control bits 0–1 = 10): one buffer. Written by the master (direction 01, SM0):
//!   writes are taken while the mailbox is empty, and the write that reaches its last byte fills it
//!   (status bit 3) for the application to take; reads are refused. Read by the master (direction 00,
//!   SM1): reads are served only while the application has put a mailbox in it, and the read that
//!   reaches its last byte empties it; writes are refused. A refused access changes nothing and does
//!   not count in the working counter. The repeat request (activate bit 1, toggled by the master) puts
//!   the last mailbox back and is acknowledged in PDI control bit 1.
//!   A process-data SyncManager in mailbox mode (an ESI's one-buffer `Inputs` with control byte
//!   0x22) works the same: the application's inputs fill it only while the master has read the last
//!   ones ([`Esc::put_inputs`]), a master's outputs count as a new output image and stay until the
//!   application has taken them ([`Esc::release_outputs`]).
//! - **Buffered mode** (control bits 0–1 = 00): the emulator processes each frame whole, so the master
//!   always sees one consistent buffer. A write that reaches the last byte of a master-written buffer
//!   (SM2) is a new output image: status bit 0, and the SyncManager watchdog restarts. The master
//!   cannot write a buffer it reads (SM3).
//! - A disabled SyncManager (activate bit 0 = 0) guards nothing; disabling or reconfiguring one
//!   empties its mailbox. The status byte and the PDI control byte are the slave's: a master's write
//!   to them is ignored.

use super::registers::{SmControl, SyncManagerRegisters};
use super::Esc;

/// SyncManagers this ESC offers: the most a device's ESC has, and the SyncManagers of an ESC made
/// without a device ([`Esc::new`]).
pub const SYNC_MANAGERS: usize = 8;
/// SyncManager register blocks the register map has (0x0800–0x087F); those past the ESC's
/// SyncManagers are reserved.
pub const MAX_SYNC_MANAGERS: usize = 16;
/// First SyncManager register block.
pub const SM_BASE: u16 = 0x0800;
/// Where process memory starts.
const PROCESS_RAM: usize = 0x1000;
/// Status bit 3: mailbox full.
pub const MAILBOX_FULL: u8 = 0x08;
/// Status bit 0: the last access was a (completed) write.
pub const WRITE_EVENT: u8 = 0x01;

/// Where the status byte of SyncManager `n` is in memory.
#[inline]
const fn status_at(n: usize) -> usize {
    SM_BASE as usize + SyncManagerRegisters::LEN * n + SyncManagerRegisters::STATUS as usize
}

/// A SyncManager as its registers configure it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SyncManager {
    /// Physical start address.
    pub start: u16,
    /// Length in bytes.
    pub len: u16,
    /// Control byte: mode (bits 0–1), direction (bits 2–3), watchdog enable (bit 6).
    pub control: u8,
    /// Activated (activate bit 0) and not deactivated by the PDI.
    pub enabled: bool,
}

impl SyncManager {
    /// Mailbox mode.
    pub fn is_mailbox(&self) -> bool {
        SmControl(self.control).is_mailbox()
    }

    /// Written by the master (direction 01).
    pub fn master_writes(&self) -> bool {
        SmControl(self.control).master_writes()
    }

    /// The SyncManager watchdog is enabled for it (control bit 6).
    pub fn watchdog(&self) -> bool {
        SmControl(self.control).watchdog()
    }

    fn end(&self) -> u32 {
        u32::from(self.start) + u32::from(self.len)
    }

    fn overlaps(&self, at: u16, len: usize) -> bool {
        self.enabled
            && self.len > 0
            && u32::from(at) < self.end()
            && u32::from(self.start) < u32::from(at) + len as u32
    }

    fn reaches_last(&self, at: u16, len: usize) -> bool {
        let last = self.end() - 1;
        u32::from(at) <= last && last < u32::from(at) + len as u32
    }
}

/// What an access does to the SyncManagers it touches, worked out before the access.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Gate {
    /// SyncManagers whose last byte the access reaches.
    completes: u8,
    /// Those SyncManagers are all in buffered mode, and the access is to process memory only
    /// (it changes no SyncManager's configuration).
    buffered: bool,
}

/// How the SyncManagers take an access, worked out from their configuration ([`Esc::plan`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Plan {
    /// Taken, with this gate, whatever the SyncManagers' state.
    Open(Gate),
    /// Refused whatever their state.
    Refused,
    /// A mailbox's state decides: [`Esc::sm_gate`] at the access.
    AtAccess,
}

impl Esc {
    /// SyncManager `n` as configured; one the ESC does not have reads as zeros: disabled, guarding
    /// nothing.
    pub fn sync_manager(&self, n: usize) -> SyncManager {
        if n < self.sync_managers {
            self.maps.sync_managers[n]
        } else {
            self.decode_sync_manager(n)
        }
    }

    /// SyncManager `n` decoded from its registers, as [`Esc::sync_manager`] gives it.
    pub(super) fn decode_sync_manager(&self, n: usize) -> SyncManager {
        let r = SyncManagerRegisters::decode(self.bytes_at(SM_BASE + 8 * n as u16));
        SyncManager {
            start: r.start,
            len: r.len,
            control: r.control,
            enabled: r.enabled(),
        }
    }

    /// The status byte of SyncManager `n`.
    #[inline]
    pub fn sm_status(&self, n: usize) -> u8 {
        self.mem[status_at(n)]
    }

    /// Sets the status byte of SyncManager `n` (no part of its configuration: the decoded
    /// SyncManagers stay as they are).
    #[inline]
    fn set_sm_status(&mut self, n: usize, status: u8) {
        self.mem[status_at(n)] = status;
    }

    /// Whether the master may make this access; `None` refuses it (nothing changes, no working
    /// counter).
    pub(crate) fn sm_gate(&self, at: u16, len: usize, write: bool) -> Option<Gate> {
        let mut gate = Gate::default();
        if usize::from(at) + len <= PROCESS_RAM {
            // Registers: SyncManagers guard process memory only.
            return Some(gate);
        }
        for n in 0..self.sync_manager_count() {
            let sm = self.sync_manager(n);
            if !sm.overlaps(at, len) {
                continue;
            }
            let full = self.sm_status(n) & MAILBOX_FULL != 0;
            let allowed = match (sm.is_mailbox(), sm.master_writes(), write) {
                (true, true, true) => !full,
                (true, false, false) => full,
                (true, _, _) => false,
                (false, true, _) => true,
                (false, false, read_only) => !read_only,
            };
            if !allowed {
                return None;
            }
            if sm.reaches_last(at, len) {
                gate.completes |= 1 << n;
            }
        }
        Some(gate)
    }

    /// What [`Esc::sm_gate`] says of an access, as far as the SyncManagers' configuration decides
    /// it: SyncManagers in buffered mode decide by their configuration alone, one in mailbox mode
    /// may decide by whether its mailbox is full.
    pub(super) fn plan(&self, at: u16, len: u16, write: bool) -> Plan {
        let len = usize::from(len);
        let mailbox = (0..self.sync_manager_count()).any(|n| {
            let sm = self.sync_manager(n);
            sm.is_mailbox() && sm.overlaps(at, len)
        });
        if mailbox {
            return Plan::AtAccess;
        }
        match self.sm_gate(at, len, write) {
            // A read that reaches the last byte of a buffered SyncManager changes nothing
            // ([`Esc::sm_after`]).
            Some(_) if !write => Plan::Open(Gate::default()),
            Some(gate) => Plan::Open(Gate {
                buffered: usize::from(at) >= PROCESS_RAM,
                ..gate
            }),
            None => Plan::Refused,
        }
    }

    /// After an access the gate let through: mailboxes filled or emptied, write events.
    #[inline]
    pub(crate) fn sm_after(&mut self, gate: Gate, write: bool) {
        if gate.completes == 0 {
            return;
        }
        if !gate.buffered {
            self.sm_completed(gate, write);
        } else if write {
            // What `sm_completed` does for a buffered SyncManager the master wrote.
            for n in 0..self.sync_manager_count() {
                if gate.completes & (1 << n) != 0 {
                    let status = self.sm_status(n);
                    self.set_sm_status(n, status | WRITE_EVENT);
                    self.outputs_arrived();
                }
            }
        }
    }

    /// [`Esc::sm_after`] for the SyncManagers whose last byte the access reached.
    fn sm_completed(&mut self, gate: Gate, write: bool) {
        for n in 0..self.sync_manager_count() {
            if gate.completes & (1 << n) == 0 {
                continue;
            }
            let sm = self.sync_manager(n);
            let status = self.sm_status(n);
            if sm.is_mailbox() {
                if write {
                    self.set_sm_status(n, status | MAILBOX_FULL | WRITE_EVENT);
                    if self.mailbox_sms().0 != Some(n) {
                        self.outputs_arrived();
                    }
                } else {
                    self.set_sm_status(n, (status & !(MAILBOX_FULL | WRITE_EVENT)) | 0x02);
                }
            } else if write {
                self.set_sm_status(n, status | WRITE_EVENT);
                self.outputs_arrived();
            }
        }
    }

    /// A master's write to SyncManager registers: the slave's bytes (status, PDI control) are kept,
    /// a changed or disabled SyncManager's mailbox is emptied, a toggled repeat request repeats.
    pub(crate) fn sm_registers_written(&mut self, before: &[u8]) {
        const LEN: usize = SyncManagerRegisters::LEN;
        for n in 0..self.sync_manager_count() {
            let at = SM_BASE + (LEN * n) as u16;
            let now = SyncManagerRegisters::decode(self.bytes_at(at));
            let was = &before[LEN * n..LEN * (n + 1)];
            let was = SyncManagerRegisters::decode(was.try_into().expect("8 bytes"));
            // Status and PDI control are read-only for the master.
            let (status, pdi) = (was.status, was.pdi_control);
            self.store(at + SyncManagerRegisters::STATUS, &[status]);
            self.store(at + SyncManagerRegisters::PDI_CONTROL, &[pdi]);
            if now.configuration() != was.configuration() {
                self.set_sm_status(n, 0);
                continue;
            }
            let acked = was.repeat_ack();
            if now.repeat_request() != acked {
                let sm = self.sync_manager(n);
                if sm.is_mailbox() && !sm.master_writes() {
                    if let Some(last) = self.last_mailbox.clone() {
                        self.store(sm.start, &last);
                        self.set_sm_status(n, status | MAILBOX_FULL);
                    }
                }
                // The acknowledgement (bit 1) differs from the request: it toggles to match it.
                self.store(at + SyncManagerRegisters::PDI_CONTROL, &[pdi ^ 0x02]);
            }
        }
    }

    /// The first SyncManager in mailbox mode the master writes (SM0), and the one it reads (SM1).
    #[inline]
    fn mailbox_sms(&self) -> (Option<usize>, Option<usize>) {
        self.maps.mailboxes
    }

    /// [`Esc::mailbox_sms`] found among the SyncManagers.
    pub(super) fn find_mailbox_sms(&self) -> (Option<usize>, Option<usize>) {
        let mut out = (None, None);
        for n in 0..self.sync_manager_count() {
            let sm = self.sync_manager(n);
            if !sm.enabled || !sm.is_mailbox() {
                continue;
            }
            if sm.master_writes() {
                out.0 = out.0.or(Some(n));
            } else {
                out.1 = out.1.or(Some(n));
            }
        }
        out
    }

    /// The lengths of the mailboxes as the master configured them: the one it writes and the one
    /// it reads (0 for one that is not there).
    pub fn mailbox_lengths(&self) -> (u16, u16) {
        let (write, read) = self.mailbox_sms();
        let len = |n: Option<usize>| n.map_or(0, |n| self.sync_manager(n).len);
        (len(write), len(read))
    }

    /// Whether the master has filled the mailbox it writes ([`Esc::take_mailbox`] takes it).
    #[inline]
    pub(crate) fn mailbox_written(&self) -> bool {
        self.mailbox_sms()
            .0
            .is_some_and(|n| self.sm_status(n) & MAILBOX_FULL != 0)
    }

    /// The application takes the mailbox the master wrote, when there is one; it is empty again.
    pub fn take_mailbox(&mut self) -> Option<Vec<u8>> {
        if !self.mailbox_written() {
            return None;
        }
        let n = self.mailbox_sms().0?;
        let status = self.sm_status(n);
        let sm = self.sync_manager(n);
        let bytes = self.load(sm.start, usize::from(sm.len));
        self.set_sm_status(n, status & !MAILBOX_FULL);
        Some(bytes)
    }

    /// The application puts a mailbox for the master to read (padded with zeros to the mailbox
    /// length); false while the last one has not been read, or when the master has no read mailbox
    /// configured or the mailbox is longer.
    pub fn put_mailbox(&mut self, bytes: &[u8]) -> bool {
        let Some(n) = self.mailbox_sms().1 else {
            return false;
        };
        let sm = self.sync_manager(n);
        let status = self.sm_status(n);
        if status & MAILBOX_FULL != 0 || bytes.len() > usize::from(sm.len) {
            return false;
        }
        let mut image = bytes.to_vec();
        image.resize(usize::from(sm.len), 0);
        self.store(sm.start, &image);
        self.last_mailbox = Some(image);
        self.set_sm_status(n, status | MAILBOX_FULL);
        true
    }

    /// The process-data SyncManager in mailbox mode starting at `at` in that direction: enabled,
    /// and not the mailbox of the mailbox protocols.
    fn one_buffer_at(&self, at: u16, master_writes: bool) -> Option<usize> {
        let (write_mailbox, read_mailbox) = self.mailbox_sms();
        let mailbox = if master_writes {
            write_mailbox
        } else {
            read_mailbox
        };
        (0..self.sync_manager_count()).find(|&n| {
            let sm = self.sync_manager(n);
            sm.enabled
                && sm.is_mailbox()
                && sm.master_writes() == master_writes
                && sm.start == at
                && Some(n) != mailbox
        })
    }

    /// The application writes its inputs at `at`. Through a SyncManager in mailbox mode (one
    /// buffer, ETG.1000.4 §6.7.2) only while the master has read the last ones, and the write fills
    /// it; false while it is still full (nothing changes). Elsewhere as [`store`](Esc::store).
    pub fn put_inputs(&mut self, at: u16, bytes: &[u8]) -> bool {
        if let Some(n) = self.one_buffer_at(at, false) {
            let status = self.sm_status(n);
            if status & MAILBOX_FULL != 0 {
                return false;
            }
            self.store(at, bytes);
            self.set_sm_status(n, status | MAILBOX_FULL);
        } else {
            self.store(at, bytes);
        }
        true
    }

    /// The application has taken the outputs at `at`: a SyncManager in mailbox mode there is empty
    /// again, for the master's next write.
    pub fn release_outputs(&mut self, at: u16) {
        if let Some(n) = self.one_buffer_at(at, true) {
            let status = self.sm_status(n);
            self.set_sm_status(n, status & !MAILBOX_FULL);
        }
    }
}
