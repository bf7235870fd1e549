//! One slave's ESC: its memory (registers 0x0000–0x0FFF and process RAM up to 64 KiB), its
//! configured station address (0x0010) and alias (0x0012), and the datagram commands of ETG.1000.4
//! §5.4 with their working-counter rules. A [`Chain`] passes a frame through its slaves in order.
//!
//! Working counter: a read that a slave serves adds 1, a write 1, a read-write 1 for the read and 2
//! for the write (3 when both); a broadcast adds per slave; ARMW/FRMW add 1 at the slave that reads and
//! 1 at each slave that writes. Auto-increment addressing: each slave takes the datagram when its ADP
//! is 0 and increments ADP as the frame passes.
//!
//! FMMUs and SyncManagers: an ESC has the ones its device has (ETG.2000: one per `Device/Fmmu` and
//! `Device/Sm` element of the ESI, [`Esc::for_device`]), at most 16 FMMUs and 8 SyncManagers, and
//! says how many in its ESC information (ETG.1000.4 DL information; ESC datasheet section II:
//! 0x0004 FMMUs supported, 0x0005 SyncManagers supported). The register blocks past them (0x0600 +
//! 16·n for FMMU n, up to 0x06FF; 0x0800 + 8·n for SyncManager n, up to 0x087F) are reserved (ESC
//! datasheet section II §1, table 1: not writable, their read data meaningless): a master's write
//! there is not taken and a read gives 0, and the datagram counts in the working counter as any
//! register access of the addressed ESC does (section I §2.4: the ESC is addressed and the register
//! area is not guarded by a SyncManager). An FMMU that does not exist maps nothing; a SyncManager
//! that does not exist guards nothing.

pub mod al;
pub mod dc;
pub mod registers;
pub mod sm;

pub use crate::frame::{cmd, Command, CommandCode};
use crate::frame::{datagrams_into, DatagramAt, FrameError};
use od::device::EthercatInfo;
use od::DeviceDescription;
use registers::{
    AlControl, AlStatus, DlControl, DlStatus, EepromCommand, EepromControl, FmmuRegisters,
};

/// ESC memory size.
pub const MEMORY: usize = 0x1_0000;
/// Configured station address register.
pub const STATION_ADDRESS: u16 = 0x0010;
/// Configured station alias register.
pub const STATION_ALIAS: u16 = 0x0012;

/// First FMMU register block (16 bytes each, ETG.1000.4 Table 57).
pub const FMMU_BASE: u16 = 0x0600;
/// FMMU register blocks the register map has (0x0600–0x06FF), all of them FMMUs this ESC offers: the
/// most a device's ESC has, and the FMMUs of an ESC made without a device ([`Esc::new`]).
pub const FMMUS: usize = 16;
/// EEPROM (SII) control/status register.
pub const EEPROM_CONTROL: u16 = 0x0502;
/// EEPROM word address register.
pub const EEPROM_ADDRESS: u16 = 0x0504;
/// EEPROM data register (8 bytes are read at once).
pub const EEPROM_DATA: u16 = 0x0508;
/// DL status register.
pub const DL_STATUS: u16 = 0x0110;
/// Watchdog divider register.
pub const WATCHDOG_DIVIDER: u16 = 0x0400;
/// Process-data watchdog time register.
pub const WATCHDOG_TIME_PD: u16 = 0x0420;
/// Process-data watchdog status register.
pub const WATCHDOG_STATUS_PD: u16 = 0x0440;
/// Process-data watchdog counter register.
pub const WATCHDOG_COUNTER_PD: u16 = 0x0442;
/// Registers the master cannot write: ESC information, the station alias (loaded from the SII), DL status, AL status and code, watchdog
/// status and counters, the EEPROM data register's read half.
const READ_ONLY: [(u16, usize); 5] = [
    (0x0000, 0x10),
    (STATION_ALIAS, 2),
    (DL_STATUS, 2),
    (0x0130, 6),
    (0x0440, 4),
];

/// Whether the access `[at, at+len)` overlaps the registers `[reg, reg+n)`.
pub(crate) fn touches(at: u16, len: usize, reg: u16, n: usize) -> bool {
    let (a, b) = (usize::from(at), usize::from(at) + len);
    let (r, e) = (usize::from(reg), usize::from(reg) + n);
    a < e && r < b
}

/// One FMMU as the master configured it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fmmu {
    /// Logical start address.
    pub logical: u32,
    /// Length in bytes.
    pub len: u16,
    /// Physical start address.
    pub physical: u16,
    /// Maps reads (LRD/LRW) from the slave.
    pub read: bool,
    /// Maps writes (LWR/LRW) to the slave.
    pub write: bool,
}

/// One slave controller.
#[derive(Clone)]
pub struct Esc {
    pub(crate) mem: Vec<u8>,
    /// The SII EEPROM image, read through the EEPROM interface registers.
    pub sii: Vec<u8>,
    /// What the AL state transitions check.
    pub al: al::AlConfig,
    /// The last mailbox put for the master, for a repeat request.
    pub(crate) last_mailbox: Option<Vec<u8>>,
    /// The chain time (ns) of the last output image, or of the last check while no SyncManager is
    /// watched (the SyncManager watchdog runs from it).
    watchdog_from: u64,
    watchdog_expired: bool,
    /// Output images the master completed since power-on (SM2 write events).
    outputs_received: u64,
    /// The Distributed Clock.
    pub(crate) clock: dc::Clock,
    /// The FMMUs the ESC has (0x0004): FMMU 0 up to this one, not included.
    fmmus: usize,
    /// The SyncManagers the ESC has (0x0005).
    sync_managers: usize,
    /// The FMMUs and SyncManagers as their registers configure them, decoded again whenever a
    /// write reaches those registers ([`Maps`]).
    maps: Maps,
}

/// The FMMU and SyncManager registers of an ESC decoded: what every process-data and mailbox
/// access looks up, read from here instead of from the register bytes each time. Memory stays
/// the truth: every write to memory that reaches the registers of the ESC's FMMUs or
/// SyncManagers decodes them again ([`Esc::mem_written`]), except the SyncManager status bytes,
/// which are no part of a SyncManager's configuration. The reserved blocks past them are none of
/// these.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Maps {
    /// FMMU `n` when the ESC has it and it is active ([`Esc::fmmu`]).
    fmmus: [Option<Fmmu>; FMMUS],
    /// SyncManager `n` of those the ESC has ([`Esc::sync_manager`]); the rest unused.
    sync_managers: [sm::SyncManager; sm::SYNC_MANAGERS],
    /// The mailbox SyncManagers: the one the master writes (SM0) and the one it reads (SM1).
    mailboxes: (Option<usize>, Option<usize>),
    /// For FMMU `n`, how the SyncManagers take a read (`[n][0]`) and a write (`[n][1]`) of its
    /// whole physical range: what a logical datagram over all of the FMMU's logical range does.
    plans: [[sm::Plan; 2]; FMMUS],
}

impl Default for Maps {
    fn default() -> Self {
        Maps {
            fmmus: [None; FMMUS],
            sync_managers: [sm::SyncManager::default(); sm::SYNC_MANAGERS],
            mailboxes: (None, None),
            plans: [[sm::Plan::AtAccess; 2]; FMMUS],
        }
    }
}

impl Default for Esc {
    fn default() -> Self {
        Esc::new()
    }
}

impl std::fmt::Debug for Esc {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Esc")
            .field("station_address", &self.station_address())
            .finish()
    }
}

/// How one slave acts on a datagram.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Access {
    Read,
    Write,
    ReadWrite,
    /// ARMW/FRMW: read at the addressed slave, write at the others.
    ReadMultipleWrite,
}

/// The FMMUs and SyncManagers of a device's ESC, from its ESI (ETG.2000): one FMMU per `Fmmu`
/// element and one SyncManager per `Sm` element, at most what this ESC offers ([`FMMUS`] and
/// [`sm::SYNC_MANAGERS`]). An ESI without `Fmmu` elements gets the FMMUs its SyncManagers need: one
/// per `Sm` that is not the mailbox's `MBoxOut` or `MBoxIn` (a master maps each process-data
/// SyncManager with an FMMU of its own).
pub fn device_counts(ec: &EthercatInfo) -> (usize, usize) {
    let fmmus = if ec.fmmus.is_empty() {
        ec.sync_managers
            .iter()
            .filter(|s| s.kind != "MBoxOut" && s.kind != "MBoxIn")
            .count()
    } else {
        ec.fmmus.len()
    };
    (
        fmmus.min(FMMUS),
        ec.sync_managers.len().min(sm::SYNC_MANAGERS),
    )
}

impl Esc {
    /// An ESC with zeroed memory (station address 0) and all the FMMUs and SyncManagers it offers,
    /// [`FMMUS`] and [`sm::SYNC_MANAGERS`]: the ESC of no device in particular.
    pub fn new() -> Esc {
        Esc::with_counts(FMMUS, sm::SYNC_MANAGERS)
    }

    /// The ESC of `desc`'s device: the FMMUs and SyncManagers of its ESI ([`device_counts`]); an
    /// [`Esc::new`] for a description without an EtherCAT part.
    pub fn for_device(desc: &DeviceDescription) -> Esc {
        match &desc.ethercat {
            Some(ec) => {
                let (fmmus, sync_managers) = device_counts(ec);
                Esc::with_counts(fmmus, sync_managers)
            }
            None => Esc::new(),
        }
    }

    /// An ESC with zeroed memory (station address 0), `fmmus` FMMUs and `sync_managers`
    /// SyncManagers (at most [`FMMUS`] and [`sm::SYNC_MANAGERS`]), as its ESC information 0x0004
    /// and 0x0005 say.
    pub fn with_counts(fmmus: usize, sync_managers: usize) -> Esc {
        let fmmus = fmmus.min(FMMUS);
        let sync_managers = sync_managers.min(sm::SYNC_MANAGERS);
        let mut esc = Esc {
            mem: vec![0; MEMORY],
            sii: Vec::new(),
            al: al::AlConfig::default(),
            last_mailbox: None,
            watchdog_from: 0,
            watchdog_expired: false,
            outputs_received: 0,
            clock: dc::Clock::default(),
            fmmus,
            sync_managers,
            maps: Maps::default(),
        };
        esc.decode_maps();
        // ESC information (0x0000–0x0009, ETG.1000.4 DL information): type, revision, build, FMMUs,
        // SyncManagers, process RAM in KiB, ports 0 and 1 MII, features: byte-oriented FMMUs, DC
        // with 64-bit system time.
        esc.store(0x0000, &[0x11, 0x00, 0x02, 0x00]);
        esc.store(0x0004, &[fmmus as u8, sync_managers as u8, 60, 0x0F]);
        esc.store(0x0008, &0x000Du16.to_le_bytes());
        let init = AlStatus {
            state: al::AlState::Init,
            error: false,
        };
        esc.store(al::AL_STATUS, &init.encode());
        // Watchdog divider 2498 (100 µs units), PDI and process-data watchdog 1000 (100 ms), status:
        // not expired.
        esc.store(WATCHDOG_DIVIDER, &2498u16.to_le_bytes());
        esc.store(0x0410, &1000u16.to_le_bytes());
        esc.store(WATCHDOG_TIME_PD, &1000u16.to_le_bytes());
        esc.store(WATCHDOG_STATUS_PD, &[1, 0]);
        esc.set_position(0, 1);
        esc
    }

    /// The FMMUs the ESC has (ESC information 0x0004).
    pub fn fmmu_count(&self) -> usize {
        self.fmmus
    }

    /// The SyncManagers the ESC has (ESC information 0x0005).
    pub fn sync_manager_count(&self) -> usize {
        self.sync_managers
    }

    /// The reserved register blocks of the FMMUs and SyncManagers the ESC does not have, as
    /// (start, length).
    fn reserved(&self) -> [(u16, usize); 2] {
        [
            (
                FMMU_BASE + 16 * self.fmmus as u16,
                16 * (FMMUS - self.fmmus),
            ),
            (
                sm::SM_BASE + 8 * self.sync_managers as u16,
                8 * (sm::MAX_SYNC_MANAGERS - self.sync_managers),
            ),
        ]
    }

    /// Where the slave is in a chain of `n`: the DL status (ports 0 and 1 open with communication
    /// when a slave follows; ports 2 and 3 closed) and the DC propagation.
    pub fn set_position(&mut self, k: usize, n: usize) {
        // PDI operational, link and communication on port 0, ports 2 and 3 closed, and port 1
        // with link and communication where a slave follows, closed at the end of the chain.
        let follows = k + 1 < n;
        let dl = DlStatus {
            pdi_operational: true,
            link: [true, follows, false, false],
            closed: [false, !follows, true, true],
            communication: [true, follows, false, false],
            ..DlStatus::default()
        };
        self.store(DL_STATUS, &dl.encode());
        self.clock.position = k as u64;
        self.clock.return_hops = 2 * (n.saturating_sub(k + 1)) as u64;
        // Slaves power up at different instants: each local clock has its own start.
        self.clock.base = 1_000_000_007u64.wrapping_mul(k as u64 + 1);
    }

    /// The chain's time in nanoseconds since the chain's time zero ([`Chain::handle_frame`] and
    /// [`Chain::set_now`] set it from the host's `now`); it never goes back.
    pub(crate) fn set_time(&mut self, ns: u64) {
        self.clock.now = self.clock.now.max(ns);
    }

    /// A new output image: the SyncManager watchdog starts again.
    #[inline]
    pub(crate) fn outputs_arrived(&mut self) {
        self.outputs_received = self.outputs_received.wrapping_add(1);
        self.watchdog_from = self.clock.now;
        self.watchdog_expired = false;
        // (No FMMU or SyncManager register: a plain write.)
        let at = usize::from(WATCHDOG_STATUS_PD);
        self.mem[at..at + 2].copy_from_slice(&[1, 0]);
    }

    /// How many output images the master has completed (writes that reached the last byte of a
    /// buffered SyncManager it writes) since power-on: a new count is a new output image.
    pub fn outputs_received(&self) -> u64 {
        self.outputs_received
    }

    /// The process-data watchdog time: (divider + 2) × 40 ns × 0x0420; zero when disabled.
    pub fn watchdog_time(&self) -> std::time::Duration {
        let divider = u64::from(self.read_u16(WATCHDOG_DIVIDER));
        let n = u64::from(self.read_u16(WATCHDOG_TIME_PD));
        std::time::Duration::from_nanos((divider + 2) * 40 * n)
    }

    /// Checks the SyncManager watchdog at the chain's present time: true when it expired now (no
    /// output image for the watchdog time on a SyncManager with the watchdog enabled). Status 0x0440
    /// bit 0 is 0 while it stays expired; 0x0442 counts expiries.
    pub(crate) fn check_watchdog(&mut self) -> bool {
        let guarded = (0..self.sync_managers).any(|n| {
            let sm = self.sync_manager(n);
            sm.enabled && !sm.is_mailbox() && sm.master_writes() && sm.watchdog()
        });
        let time = self.watchdog_time();
        if !guarded || time.is_zero() {
            self.watchdog_from = self.clock.now;
            self.watchdog_expired = false;
            self.store(WATCHDOG_STATUS_PD, &[1, 0]);
            return false;
        }
        let elapsed =
            std::time::Duration::from_nanos(self.clock.now.saturating_sub(self.watchdog_from));
        if elapsed >= time && !self.watchdog_expired {
            self.watchdog_expired = true;
            self.store(WATCHDOG_STATUS_PD, &[0, 0]);
            let [count] = self.bytes_at(WATCHDOG_COUNTER_PD);
            let count = count.saturating_add(1);
            self.store(WATCHDOG_COUNTER_PD, &[count]);
            return true;
        }
        false
    }

    /// The application leaves for `state` with the error indication and `code` (e.g. a watchdog).
    pub fn al_fault(&mut self, state: al::AlState, code: al::AlStatusCode) {
        self.store(al::AL_STATUS, &AlStatus { state, error: true }.encode());
        self.store(al::AL_STATUS_CODE, &code.code().to_le_bytes());
    }

    /// The configured station address (register 0x0010).
    pub fn station_address(&self) -> u16 {
        self.read_u16(STATION_ADDRESS)
    }

    /// The AL state (AL status bits 0–3) and whether the error indicator is set.
    #[inline]
    pub fn al_state(&self) -> (al::AlState, bool) {
        // Only the ESC writes AL status (the master cannot), always with a state of the table.
        let status = AlStatus::decode(self.bytes_at(al::AL_STATUS));
        (status.state, status.error)
    }

    /// The AL status code (register 0x0134).
    pub fn al_status_code(&self) -> al::AlStatusCode {
        al::AlStatusCode::from(self.read_u16(al::AL_STATUS_CODE))
    }

    /// A 16-bit register.
    #[inline]
    pub fn read_u16(&self, at: u16) -> u16 {
        u16::from_le_bytes(self.bytes_at(at))
    }

    /// Sets memory from the slave's side (the application); bytes past the end are left out.
    pub fn store(&mut self, at: u16, bytes: &[u8]) {
        let start = usize::from(at);
        let n = bytes.len().min(MEMORY - start);
        self.mem[start..start + n].copy_from_slice(&bytes[..n]);
        self.mem_written(at, n);
    }

    /// After a write of `len` bytes of memory at `at`: the FMMUs and SyncManagers are decoded
    /// again when it reached their registers.
    fn mem_written(&mut self, at: u16, len: usize) {
        if touches(at, len, FMMU_BASE, 16 * self.fmmus)
            || touches(at, len, sm::SM_BASE, 8 * self.sync_managers)
        {
            self.decode_maps();
        }
    }

    /// Decodes the FMMU and SyncManager registers into [`Maps`].
    fn decode_maps(&mut self) {
        for n in 0..FMMUS {
            self.maps.fmmus[n] = self.decode_fmmu(n);
        }
        for n in 0..self.sync_managers {
            self.maps.sync_managers[n] = self.decode_sync_manager(n);
        }
        self.maps.mailboxes = self.find_mailbox_sms();
        for n in 0..FMMUS {
            self.maps.plans[n] = match self.maps.fmmus[n] {
                Some(f) => [false, true].map(|write| self.plan(f.physical, f.len, write)),
                None => [sm::Plan::AtAccess; 2],
            };
        }
    }

    /// Memory as the master sees it.
    pub fn load(&self, at: u16, len: usize) -> Vec<u8> {
        let mut out = vec![0; len];
        self.load_into(at, &mut out);
        out
    }

    /// As many bytes of memory from `at` as `out` holds, as [`load`](Esc::load) reads them.
    pub fn load_into(&self, at: u16, out: &mut [u8]) {
        let start = usize::from(at);
        match self.mem.get(start..start + out.len()) {
            Some(bytes) => out.copy_from_slice(bytes),
            // Past the end of memory the read wraps round to address 0.
            None => {
                for (k, b) in out.iter_mut().enumerate() {
                    *b = self.mem[(start + k) % MEMORY];
                }
            }
        }
    }

    /// `N` bytes of memory from `at`, as [`load`](Esc::load) reads them.
    #[inline]
    pub fn bytes_at<const N: usize>(&self, at: u16) -> [u8; N] {
        let start = usize::from(at);
        match self.mem.get(start..start + N) {
            Some(bytes) => bytes.try_into().expect("N bytes"),
            None => std::array::from_fn(|k| self.mem[(start + k) % MEMORY]),
        }
    }

    /// Reads into `data` (ORed for broadcasts, as an ESC ORs a broadcast read).
    fn read_into(&mut self, ado: u16, data: &mut [u8], or: bool) {
        self.dc_before_read(ado, data.len());
        if or {
            for (k, d) in data.iter_mut().enumerate() {
                *d |= self.mem[(usize::from(ado) + k) % MEMORY];
            }
        } else {
            self.load_into(ado, data);
        }
        self.dc_after_read(ado, data.len());
    }

    fn write_from(&mut self, ado: u16, data: &[u8]) {
        let len = data.len();
        let sm_bytes = 8 * self.sync_managers;
        let sm_before =
            touches(ado, len, sm::SM_BASE, sm_bytes).then(|| self.load(sm::SM_BASE, sm_bytes));
        let time_before: [u8; 8] = self.bytes_at(dc::SYSTEM_TIME);
        let kept: Vec<(u16, Vec<u8>)> = READ_ONLY
            .iter()
            .filter(|(r, n)| touches(ado, len, *r, *n))
            .map(|(r, n)| (*r, self.load(*r, *n)))
            .collect();
        self.store(ado, data);
        for (r, bytes) in kept {
            self.store(r, &bytes);
        }
        // The blocks of FMMUs and SyncManagers the ESC does not have take nothing: they stay 0.
        // (They are none of the FMMUs and SyncManagers [`Maps`] holds.)
        for (r, n) in self.reserved() {
            let r = usize::from(r);
            self.mem[r..r + n].fill(0);
        }
        if let Some(before) = sm_before {
            self.sm_registers_written(&before);
        }
        self.dc_after_write(ado, len, time_before);
        self.after_write(ado, len);
    }

    /// What a master's write triggers: an EEPROM read command loads 8 bytes of the SII image at the
    /// word address into the data register (ETG.1000.4 §6.4; command bits 8–10 of 0x0502 = 001).
    fn after_write(&mut self, ado: u16, len: usize) {
        let touches = |reg: u16, n: usize| touches(ado, len, reg, n);
        if touches(al::AL_CONTROL, 2) {
            let control = AlControl::decode(self.bytes_at(al::AL_CONTROL));
            let (current, _) = self.al_state();
            match al::transition(self, control) {
                al::Transition::Unchanged => {}
                al::Transition::To(next) => {
                    let status = AlStatus {
                        state: next,
                        error: false,
                    };
                    self.store(al::AL_STATUS, &status.encode());
                    self.store(al::AL_STATUS_CODE, &[0, 0]);
                }
                al::Transition::Refused(code) => self.al_fault(current, code),
            }
        }
        if touches(EEPROM_CONTROL, 2) {
            let control = EepromControl::decode(self.bytes_at(EEPROM_CONTROL));
            let word = u32::from_le_bytes(self.bytes_at(EEPROM_ADDRESS)) as usize;
            // 8 bytes are read at once; write enable clears itself.
            let mut status = EepromControl {
                write_enable: false,
                read_8_bytes: true,
                command: EepromCommand::Idle,
                command_error: false,
            };
            match control.command {
                EepromCommand::Read => {
                    let bytes: Vec<u8> = (0..8)
                        .map(|k| self.sii.get(word * 2 + k).copied().unwrap_or(0xFF))
                        .collect();
                    self.store(EEPROM_DATA, &bytes);
                }
                // Write: one word from the data register, with write enable in the same access.
                EepromCommand::Write if control.write_enable && word * 2 + 2 <= self.sii.len() => {
                    let d: [u8; 2] = self.bytes_at(EEPROM_DATA);
                    self.sii[word * 2..word * 2 + 2].copy_from_slice(&d);
                }
                // Write error: not enabled, or beyond the image.
                EepromCommand::Write => status.command_error = true,
                EepromCommand::Reload => self.load_sii_configuration(),
                EepromCommand::Idle | EepromCommand::Other(_) => {}
            }
            self.store(EEPROM_CONTROL, &status.encode());
        }
    }

    /// What an ESC takes from its EEPROM at power-up and on a reload command: the configured station
    /// alias (SII word 4) into 0x0012.
    pub fn load_sii_configuration(&mut self) {
        if let Some(alias) = self.sii.get(8..10) {
            let alias = [alias[0], alias[1]];
            self.store(STATION_ALIAS, &alias);
        }
    }

    /// Whether configured-address datagrams to `adp` are this slave's: its station address, or its
    /// alias when the master enabled alias addressing (DL control 0x0100 bit 24).
    fn is_station(&self, adp: u16) -> bool {
        adp == self.station_address()
            || (DlControl::decode(self.bytes_at(DlControl::ADDRESS)).alias_enabled()
                && adp == self.read_u16(STATION_ALIAS))
    }

    /// FMMU `n` as configured in its registers, when the ESC has it and it is active.
    pub fn fmmu(&self, n: usize) -> Option<Fmmu> {
        if n >= self.fmmus {
            return None;
        }
        self.maps.fmmus[n]
    }

    /// FMMU `n` decoded from its registers, as [`Esc::fmmu`] gives it.
    fn decode_fmmu(&self, n: usize) -> Option<Fmmu> {
        if n >= self.fmmus {
            return None;
        }
        let r = FmmuRegisters::decode(self.bytes_at(FMMU_BASE + 16 * n as u16));
        if !r.active {
            return None;
        }
        Some(Fmmu {
            logical: r.logical_start,
            len: r.len,
            physical: r.physical_start,
            read: r.read,
            write: r.write,
        })
    }

    /// A logical datagram at `addr` over `data`: mapped reads copied in, mapped writes copied out,
    /// each through the SyncManager gate of its physical memory; the working-counter increment (1 for
    /// a read, 1 for LWR's write, 2 for LRW's write).
    fn logical(&mut self, command: Command, addr: u32, data: &mut [u8]) -> u16 {
        let (want_read, want_write) = match command {
            Command::Lrd { .. } => (true, false),
            Command::Lwr { .. } => (false, true),
            _ => (true, true),
        };
        let (mut read, mut wrote) = (false, false);
        let addr = u64::from(addr);
        let data_end = addr + data.len() as u64;
        // The active FMMUs in their order, each as its registers are when its turn comes (a
        // write through one may have reached the registers of the next).
        for n in 0..self.fmmus {
            let Some(f) = self.maps.fmmus[n] else {
                continue;
            };
            let logical = u64::from(f.logical);
            let start = logical.max(addr);
            let end = (logical + u64::from(f.len)).min(data_end);
            if start >= end {
                continue;
            }
            let k = (start - addr) as usize;
            let len = (end - start) as usize;
            let phys = usize::from(f.physical) + (start - logical) as usize;
            if phys + len > MEMORY {
                continue;
            }
            let at = phys as u16;
            // The SyncManagers' verdict on an access over the FMMU's whole range was worked out
            // with the registers; it stands while no mailbox's state decides it. (Read when used:
            // the write may have reached the registers.)
            let whole = len == usize::from(f.len);
            let gate = |esc: &Esc, write: bool| match esc.maps.plans[n][usize::from(write)] {
                sm::Plan::Open(gate) if whole => Some(gate),
                sm::Plan::Refused if whole => None,
                _ => esc.sm_gate(at, len, write),
            };
            // The frame's outputs are written before the slave's inputs are read into it.
            if want_write && f.write {
                if let Some(gate) = gate(self, true) {
                    self.mem[phys..phys + len].copy_from_slice(&data[k..k + len]);
                    self.mem_written(at, len);
                    self.sm_after(gate, true);
                    wrote = true;
                }
            }
            if want_read && f.read {
                if let Some(gate) = gate(self, false) {
                    data[k..k + len].copy_from_slice(&self.mem[phys..phys + len]);
                    self.sm_after(gate, false);
                    read = true;
                }
            }
        }
        let write_weight = if matches!(command, Command::Lrw { .. }) {
            2
        } else {
            1
        };
        u16::from(read) + if wrote { write_weight } else { 0 }
    }

    fn gated_read(&mut self, ado: u16, data: &mut [u8], or: bool) -> u16 {
        match self.sm_gate(ado, data.len(), false) {
            Some(gate) => {
                self.read_into(ado, data, or);
                self.sm_after(gate, false);
                1
            }
            None => 0,
        }
    }

    fn gated_write(&mut self, ado: u16, data: &[u8]) -> u16 {
        match self.sm_gate(ado, data.len(), true) {
            Some(gate) => {
                self.write_from(ado, data);
                self.sm_after(gate, true);
                1
            }
            None => 0,
        }
    }

    /// Applies one register datagram the slave is addressed by; the working-counter increment.
    fn access(
        &mut self,
        access: Access,
        ado: u16,
        data: &mut [u8],
        or: bool,
        addressed: bool,
    ) -> u16 {
        match access {
            Access::Read => self.gated_read(ado, data, or),
            Access::Write => self.gated_write(ado, data),
            Access::ReadWrite => {
                let incoming = data.to_vec();
                let read = self.gated_read(ado, data, or);
                read + 2 * self.gated_write(ado, &incoming)
            }
            Access::ReadMultipleWrite if addressed => self.gated_read(ado, data, false),
            Access::ReadMultipleWrite => self.gated_write(ado, data),
        }
    }
}

/// Slaves in the order a frame passes them.
///
/// # Methods and polling order
///
/// Every input carries the host's `now`: [`Chain::handle_frame`] processes a frame at that time (the
/// Distributed Clocks latch it, the SyncManager watchdog restarts from it); [`Chain::set_now`] moves
/// the chain's time on between frames. Time zero is the first `now` the chain is given (or
/// [`Chain::start`]).
#[derive(Debug, Clone, Default)]
pub struct Chain {
    /// The slaves.
    pub slaves: Vec<Esc>,
    /// The chain's time zero.
    epoch: Option<std::time::Instant>,
    /// Where the datagrams of the frame being processed lie, kept from frame to frame.
    datagrams: Vec<DatagramAt>,
}

impl Chain {
    /// `n` slaves with zeroed memory.
    pub fn new(n: usize) -> Chain {
        let mut chain = Chain {
            slaves: (0..n).map(|_| Esc::new()).collect(),
            epoch: None,
            datagrams: Vec::new(),
        };
        chain.link();
        chain
    }

    /// Adds a slave at the end of the chain.
    pub fn push(&mut self, esc: Esc) {
        self.slaves.push(esc);
        self.link();
    }

    /// Sets every slave's position (DL status, DC propagation).
    fn link(&mut self) {
        let n = self.slaves.len();
        for (k, esc) in self.slaves.iter_mut().enumerate() {
            esc.set_position(k, n);
        }
    }

    /// Makes `now` the chain's time zero (power-on), if it has none yet.
    pub fn start(&mut self, now: std::time::Instant) {
        self.epoch.get_or_insert(now);
    }

    /// Moves the chain's time on to `now` (never back): the Distributed Clocks and the watchdogs.
    pub fn set_now(&mut self, now: std::time::Instant) {
        let epoch = *self.epoch.get_or_insert(now);
        let ns = u64::try_from(now.saturating_duration_since(epoch).as_nanos()).unwrap_or(u64::MAX);
        for esc in &mut self.slaves {
            esc.set_time(ns);
        }
    }

    /// The chain's time in nanoseconds since its time zero.
    pub fn time_ns(&self) -> u64 {
        self.slaves.first().map_or(0, |e| e.clock.now)
    }

    /// Processes every datagram of `frame` in place at `now`, as the frame passes each slave in turn.
    /// A frame that does not parse is left unchanged and the error returned (the caller drops it).
    pub fn handle_frame(
        &mut self,
        now: std::time::Instant,
        frame: &mut [u8],
    ) -> Result<(), FrameError> {
        self.set_now(now);
        self.process(frame)
    }

    fn process(&mut self, frame: &mut [u8]) -> Result<(), FrameError> {
        datagrams_into(frame, &mut self.datagrams)?;
        for esc in self.slaves.iter_mut() {
            for d in &self.datagrams {
                let command = Command::from_header(&frame[d.start..d.start + 6]);
                // A register datagram: how the slave acts, whether it is the one addressed, the
                // position the slaves increment (auto-increment and broadcast), whether a read ORs
                // (broadcast), the register.
                let (access, addressed, position, or, ado) = match command {
                    Command::Aprd { position, offset } => {
                        (Access::Read, position == 0, Some(position), false, offset)
                    }
                    Command::Apwr { position, offset } => {
                        (Access::Write, position == 0, Some(position), false, offset)
                    }
                    Command::Aprw { position, offset } => (
                        Access::ReadWrite,
                        position == 0,
                        Some(position),
                        false,
                        offset,
                    ),
                    Command::Armw { position, offset } => (
                        Access::ReadMultipleWrite,
                        position == 0,
                        Some(position),
                        false,
                        offset,
                    ),
                    Command::Fprd { station, offset } => {
                        (Access::Read, esc.is_station(station), None, false, offset)
                    }
                    Command::Fpwr { station, offset } => {
                        (Access::Write, esc.is_station(station), None, false, offset)
                    }
                    Command::Fprw { station, offset } => (
                        Access::ReadWrite,
                        esc.is_station(station),
                        None,
                        false,
                        offset,
                    ),
                    Command::Frmw { station, offset } => (
                        Access::ReadMultipleWrite,
                        esc.is_station(station),
                        None,
                        false,
                        offset,
                    ),
                    Command::Brd { position, offset } => {
                        (Access::Read, true, Some(position), true, offset)
                    }
                    Command::Bwr { position, offset } => {
                        (Access::Write, true, Some(position), false, offset)
                    }
                    Command::Brw { position, offset } => {
                        (Access::ReadWrite, true, Some(position), true, offset)
                    }
                    Command::Lrd { logical }
                    | Command::Lwr { logical }
                    | Command::Lrw { logical } => {
                        let inc = esc.logical(command, logical, &mut frame[d.data()..d.wkc()]);
                        add_wkc(frame, d, inc);
                        continue;
                    }
                    // NOP, and a command no table defines, pass unchanged.
                    Command::Nop { .. } | Command::Unknown { .. } => continue,
                };
                let multiple = access == Access::ReadMultipleWrite;
                if addressed || multiple {
                    let buf = &mut frame[d.data()..d.wkc()];
                    let inc = esc.access(access, ado, buf, or, addressed);
                    add_wkc(frame, d, inc);
                }
                if let Some(position) = position {
                    // Broadcasts increment ADP too (ETG.1000.4: "position" counts slaves).
                    let next = position.wrapping_add(1);
                    frame[d.start + 2..d.start + 4].copy_from_slice(&next.to_le_bytes());
                }
            }
        }
        Ok(())
    }
}

/// Adds `inc` to the working counter of datagram `d` in `frame`.
fn add_wkc(frame: &mut [u8], d: &DatagramAt, inc: u16) {
    let at = d.wkc();
    let wkc = u16::from_le_bytes([frame[at], frame[at + 1]]).wrapping_add(inc);
    frame[at..at + 2].copy_from_slice(&wkc.to_le_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An ESC with SyncManager 2 at 0x1100, 4 bytes, with `control`, `activate` and PDI control `pdi`.
    fn with_sm2(control: u8, activate: u8, pdi: u8) -> Esc {
        let mut esc = Esc::new();
        esc.store(
            sm::SM_BASE + 16,
            &[0x00, 0x11, 4, 0, control, 0, activate, pdi],
        );
        esc
    }

    /// The process-data watchdog (ETG.1000.4 §6.3) guards only a SyncManager that is activated, not
    /// disabled by the PDI, buffered, written by the master and with its watchdog bit (control 0x64);
    /// with the default divider 2498 and time 1000 it expires after exactly (2498 + 2) × 40 ns × 1000 =
    /// 100 ms, not 1 ns before; 0x0440 bit 0 goes to 0 and 0x0442 counts 1.
    #[test]
    fn the_watchdog_guards_an_enabled_output_sync_manager_only() {
        for (case, control, activate, pdi, guarded) in [
            ("outputs with the watchdog", 0x64, 1, 0, true),
            ("not activated", 0x64, 0, 0, false),
            ("disabled by the PDI", 0x64, 1, 1, false),
            ("mailbox", 0x66, 1, 0, false),
            ("read by the master", 0x60, 1, 0, false),
            ("without the watchdog bit", 0x24, 1, 0, false),
        ] {
            let mut esc = with_sm2(control, activate, pdi);
            assert_eq!(esc.watchdog_time(), std::time::Duration::from_millis(100));
            esc.set_time(99_999_999);
            assert!(!esc.check_watchdog(), "{case}");
            assert_eq!(esc.load(WATCHDOG_STATUS_PD, 2), [1, 0], "{case}");
            esc.set_time(100_000_000);
            assert_eq!(esc.check_watchdog(), guarded, "{case}");
            let expired = if guarded { [0, 0] } else { [1, 0] };
            assert_eq!(esc.load(WATCHDOG_STATUS_PD, 2), expired, "{case}");
            assert_eq!(
                esc.load(WATCHDOG_COUNTER_PD, 1),
                [u8::from(guarded)],
                "{case}"
            );
        }
    }

    /// The watchdog time from its registers: (divider + 2) × 40 ns × time.
    #[test]
    fn watchdog_time_from_divider_and_time() {
        let mut esc = Esc::new();
        for (divider, time, ns) in [
            (0u16, 1u16, 80u64),
            (0, 0, 0),
            (1, 3, 360),
            (0xFFFF, 0xFFFF, 65_537 * 40 * 65_535),
        ] {
            esc.store(WATCHDOG_DIVIDER, &divider.to_le_bytes());
            esc.store(WATCHDOG_TIME_PD, &time.to_le_bytes());
            assert_eq!(esc.watchdog_time(), std::time::Duration::from_nanos(ns));
        }
    }

    /// SYNC0 events (ETG.1000.4 §9.3): with a 1 ms cycle from a start 1 ms after power-up, the events
    /// passed are reported as the last one of them, and the next is the one after it; none before
    /// the start or between two.
    #[test]
    fn sync0_events_passed_are_reported_by_the_last_one() {
        let mut esc = Esc::new();
        let base = 1_000_000_007u64; // slave 0's local clock at time 0
        esc.write_from(dc::SYNC0_CYCLE, &1_000_000u32.to_le_bytes());
        esc.write_from(dc::START_TIME, &(base + 1_000_000).to_le_bytes());
        esc.write_from(dc::SYNC_ACTIVATION, &[0x03]);
        for (ns, passed) in [
            (500_000, None),
            (4_500_000, Some(base + 4_000_000)),
            (4_900_000, None),
            (5_000_000, Some(base + 5_000_000)),
            (5_999_999, None),
            (9_200_000, Some(base + 9_000_000)),
        ] {
            esc.set_time(ns);
            assert_eq!(esc.sync0_passed(), passed, "at {ns} ns");
        }
    }

    /// The counts of ESI `Fmmu` and `Sm` elements (ETG.2000) as [`device_counts`] takes them: the
    /// `Fmmu` elements as they are (also fewer than the process-data SyncManagers: one `Outputs`
    /// FMMU over two `Outputs` SyncManagers gives 1); without any, one per SyncManager that is not
    /// a mailbox's (none for a mailbox-only device, 2 beside MBoxOut and MBoxIn); at most 16 FMMUs
    /// and 8 SyncManagers; and the ESC information 0x0004/0x0005 of [`Esc::with_counts`] says so.
    #[test]
    fn device_counts_follow_the_esi() {
        use od::device::SyncManager;
        let info = |fmmus: &[&str], sms: &[&str]| EthercatInfo {
            fmmus: fmmus.iter().map(|f| f.to_string()).collect(),
            sync_managers: sms
                .iter()
                .map(|k| SyncManager {
                    kind: k.to_string(),
                    ..SyncManager::default()
                })
                .collect(),
            ..EthercatInfo::default()
        };
        let mbx = ["MBoxOut", "MBoxIn", "Outputs", "Inputs"];
        assert_eq!(
            device_counts(&info(&["Outputs", "Inputs", "MBoxState"], &mbx)),
            (3, 4)
        );
        assert_eq!(
            device_counts(&info(&["Outputs"], &["Outputs", "Outputs"])),
            (1, 2)
        );
        assert_eq!(device_counts(&info(&[], &mbx)), (2, 4));
        assert_eq!(device_counts(&info(&[], &["MBoxOut", "MBoxIn"])), (0, 2));
        assert_eq!(device_counts(&info(&[], &[])), (0, 0));
        assert_eq!(
            device_counts(&info(&["Inputs"; 17], &["Inputs"; 9])),
            (16, 8)
        );
        let esc = Esc::with_counts(3, 4);
        assert_eq!(esc.load(0x0004, 2), [0x03, 0x04]);
        assert_eq!((esc.fmmu_count(), esc.sync_manager_count()), (3, 4));
        let esc = Esc::with_counts(17, 9);
        assert_eq!(esc.load(0x0004, 2), [0x10, 0x08]);
        assert_eq!((esc.fmmu_count(), esc.sync_manager_count()), (16, 8));
        assert_eq!(Esc::new().load(0x0004, 2), [0x10, 0x08]);
        // A description's ESC; one without an EtherCAT part is an ESC of no device.
        let mut desc = DeviceDescription {
            ethercat: Some(info(&["Inputs"], &["Inputs"])),
            ..DeviceDescription::default()
        };
        assert_eq!(Esc::for_device(&desc).load(0x0004, 2), [0x01, 0x01]);
        desc.ethercat = None;
        assert_eq!(Esc::for_device(&desc).load(0x0004, 2), [0x10, 0x08]);
    }

    /// The application's store at the end of the memory keeps what fits and leaves the rest out; the
    /// master's read wraps round to address 0, the ESC type 0x11, and so do register reads.
    #[test]
    fn a_store_past_the_end_of_memory_keeps_what_fits() {
        let mut esc = Esc::new();
        esc.store(0xFFFF, &[0xA5, 0x5A]);
        assert_eq!(esc.load(0xFFFF, 2), [0xA5, 0x11]);
        assert_eq!(esc.bytes_at(0xFFFE), [0x00, 0xA5, 0x11, 0x00]);
        assert_eq!(esc.read_u16(0xFFFF), 0x11A5);
    }

    /// The decoded FMMUs and SyncManagers ([`Maps`]) are what the registers say after every
    /// write, whichever way it comes: register datagrams of every kind over the FMMU and
    /// SyncManager blocks and beside them, logical writes through an FMMU that maps those
    /// registers, the application's stores, mailboxes filled and emptied. Random writes on a chain
    /// of an ESC with 3 FMMUs and 4 SyncManagers and one with all of them; after each, the maps
    /// equal those decoded afresh.
    #[test]
    fn decoded_fmmus_and_sync_managers_follow_every_write() {
        use crate::frame::{emit, Datagram};
        let mut chain = Chain::new(0);
        chain.push(Esc::with_counts(3, 4));
        chain.push(Esc::new());
        let mut seed = 0x2545_F491_4F6C_DD1Du64;
        let mut next = move |below: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % below
        };
        let check = |chain: &Chain, step: usize| {
            for (k, esc) in chain.slaves.iter().enumerate() {
                let mut fresh = esc.clone();
                fresh.decode_maps();
                assert_eq!(fresh.maps, esc.maps, "slave {k} after step {step}");
                // What the ESC tells of them: its own as decoded, the reserved blocks as their
                // bytes are (the application may have stored into them).
                for n in 0..=FMMUS {
                    assert_eq!(esc.fmmu(n), esc.decode_fmmu(n), "FMMU {n}");
                }
                for n in 0..sm::MAX_SYNC_MANAGERS {
                    let decoded = esc.decode_sync_manager(n);
                    assert_eq!(esc.sync_manager(n), decoded, "SyncManager {n}");
                }
            }
        };
        // FMMU 0 of each maps logical 0x100.. onto the SyncManager registers, FMMU 1 onto the FMMU
        // registers, FMMU 2 onto process memory under a mailbox SyncManager, all read and write;
        // set again every 100 steps.
        let arm = |chain: &mut Chain| {
            for k in 0..2u16 {
                let adp = 0u16.wrapping_sub(k);
                for (n, physical) in [(0u16, 0x0800u16), (1, 0x0600), (2, 0x1000)] {
                    let mut r = (0x100u32 + 0x100 * u32::from(n)).to_le_bytes().to_vec();
                    r.extend_from_slice(&0x80u16.to_le_bytes());
                    r.extend_from_slice(&[0, 7]);
                    r.extend_from_slice(&physical.to_le_bytes());
                    r.extend_from_slice(&[0, 3, 1, 0, 0, 0]);
                    let d = Datagram::new(cmd::APWR, adp, 0x0600 + 16 * n, r);
                    let mut f = emit(&[d], [2; 6]);
                    chain.process(&mut f).unwrap();
                }
            }
        };
        check(&chain, 0);
        let commands = [
            cmd::APWR,
            cmd::APRW,
            cmd::FPWR,
            cmd::BWR,
            cmd::BRW,
            cmd::ARMW,
            cmd::FRMW,
            cmd::LWR,
            cmd::LRW,
            cmd::LRD,
        ];
        for step in 1..3000 {
            if step % 100 == 1 {
                arm(&mut chain);
            }
            if next(10) == 0 {
                // The application's store, or a mailbox put or taken.
                let k = next(2) as usize;
                let esc = &mut chain.slaves[k];
                match next(3) {
                    0 => {
                        let at = 0x05F0 + next(0x2A0) as u16;
                        let bytes: Vec<u8> = (0..1 + next(12)).map(|_| next(256) as u8).collect();
                        esc.store(at, &bytes);
                    }
                    1 => {
                        esc.put_mailbox(&[next(256) as u8; 4]);
                    }
                    _ => {
                        esc.take_mailbox();
                    }
                }
                check(&chain, step);
                continue;
            }
            // Logical and register datagrams about as often.
            let command = match next(2) {
                0 => commands[7 + next(3) as usize],
                _ => commands[next(7) as usize],
            };
            let len = 1 + next(40) as usize;
            let data: Vec<u8> = (0..len).map(|_| next(256) as u8).collect();
            let d = if matches!(command, cmd::LWR | cmd::LRW | cmd::LRD) {
                Datagram {
                    cmd: command,
                    index: 0,
                    address: 0xF0 + 0x100 * next(3) as u32 + next(0x90) as u32,
                    data,
                    wkc: 0,
                }
            } else {
                let adp = match command {
                    cmd::FPWR | cmd::FRMW => 0,
                    _ => 0u16.wrapping_sub(next(2) as u16),
                };
                // Active, enabled and in mailbox mode more often than at random.
                let mut data = data;
                if next(2) == 0 && len > 6 {
                    data[6] |= 1;
                    data[4] = [0x26, 0x22, 0x64, 0x20][next(4) as usize];
                }
                Datagram::new(command, adp, 0x05F0 + next(0x2A0) as u16, data)
            };
            let mut f = emit(&[d], [2; 6]);
            chain.process(&mut f).unwrap();
            check(&chain, step);
        }
    }
}
