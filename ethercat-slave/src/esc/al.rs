//! The Application Layer state machine of a slave (ETG.1000.6 §6.4): AL control (0x0120), AL status
//! (0x0130) and AL status code (0x0134), with the checks each transition makes against the
//! SyncManager settings of the device description.
//!
//! Init → Pre-Op needs SM0/SM1 (the mailbox) configured as the ESI says (start address, a length
//! within MinSize…MaxSize, the control byte, enabled); Pre-Op → Safe-Op (ETG.1000.6 §6.4.1.4) needs a
//! valid PDO configuration (the application's verdict: 0x0025 or 0x0024 when its mapping is invalid),
//! SM2/SM3 (process data) at their start addresses with the process-data length, enabled (0x001D,
//! 0x001E), no SYNC0 on a device without it (0x0030) and — when the device limits it — an activated
//! SYNC0 at an accepted cycle time (0x0036). Op is reached from Safe-Op; any state may go back down. A refused request sets the error indicator (AL status bit 4) and the status
//! code, and the state stays; further requests are refused until the master acknowledges the error
//! (AL control bit 4).
//!
//! Bootstrap (ETG.1000.6 §6.4.1: reached from Init only, left to Init only) where the ESI gives
//! the bootstrap mailbox (`Eeprom/BootStrap`): Init → Bootstrap needs SM0/SM1 at its offsets and
//! sizes, with the standard mailbox's control bytes (0x0015); any other way into or out of it is
//! 0x0011; a device without it refuses Bootstrap with 0x0013.

use od::DeviceDescription;

use super::registers::AlControl;
use super::sm::SyncManager;
use super::Esc;

/// AL control register.
pub const AL_CONTROL: u16 = 0x0120;
/// AL status register.
pub const AL_STATUS: u16 = 0x0130;
/// AL status code register.
pub const AL_STATUS_CODE: u16 = 0x0134;

/// An AL state (ETG.1000.6 §6.4.1), as AL control and AL status bits 0–3 hold it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AlState {
    /// Init.
    Init = 1,
    /// Pre-Operational.
    PreOp = 2,
    /// Bootstrap.
    Boot = 3,
    /// Safe-Operational.
    SafeOp = 4,
    /// Operational.
    Op = 8,
}

impl AlState {
    /// The state bits 0–3 of `byte` (AL control or AL status), or `None` when they name no state.
    pub const fn from_bits(byte: u8) -> Option<AlState> {
        match byte & 0x0F {
            1 => Some(AlState::Init),
            2 => Some(AlState::PreOp),
            3 => Some(AlState::Boot),
            4 => Some(AlState::SafeOp),
            8 => Some(AlState::Op),
            _ => None,
        }
    }

    /// The state's bits as the registers hold them.
    pub const fn bits(self) -> u8 {
        self as u8
    }
}

impl std::fmt::Display for AlState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            AlState::Init => "Init",
            AlState::PreOp => "Pre-Op",
            AlState::Boot => "Bootstrap",
            AlState::SafeOp => "Safe-Op",
            AlState::Op => "Op",
        })
    }
}

/// The state bits as bytes, for a master that writes AL control (a state, with bit 4 to acknowledge
/// an error) and reads AL status register by register.
pub mod state {
    use super::AlState;

    /// Init.
    pub const INIT: u8 = AlState::Init.bits();
    /// Pre-Operational.
    pub const PREOP: u8 = AlState::PreOp.bits();
    /// Bootstrap.
    pub const BOOT: u8 = AlState::Boot.bits();
    /// Safe-Operational.
    pub const SAFEOP: u8 = AlState::SafeOp.bits();
    /// Operational.
    pub const OP: u8 = AlState::Op.bits();
}

macro_rules! al_status_codes {
    ($( $(#[$doc:meta])* $name:ident = $code:literal, $text:literal; )*) => {
        /// An AL status code (register 0x0134, ETG.1000.6 Table 11).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[non_exhaustive]
        pub enum AlStatusCode {
            $( $(#[$doc])* $name, )*
            /// A code the table does not define (reserved, or vendor-specific from 0x8000).
            Other(u16),
        }

        impl AlStatusCode {
            /// Every code of the table, in its order.
            pub const ALL: &'static [AlStatusCode] = &[$(AlStatusCode::$name,)*];

            /// The 16-bit code as the register holds it.
            pub const fn code(self) -> u16 {
                match self {
                    $(AlStatusCode::$name => $code,)*
                    AlStatusCode::Other(code) => code,
                }
            }

            /// The table's description of the code.
            pub const fn description(self) -> &'static str {
                match self {
                    $(AlStatusCode::$name => $text,)*
                    AlStatusCode::Other(code) if code >= 0x8000 => "vendor-specific",
                    AlStatusCode::Other(_) => "reserved",
                }
            }
        }

        impl From<u16> for AlStatusCode {
            fn from(code: u16) -> Self {
                match code {
                    $($code => AlStatusCode::$name,)*
                    other => AlStatusCode::Other(other),
                }
            }
        }
    };
}

al_status_codes! {
    /// 0x0000.
    NoError = 0x0000, "No error";
    /// 0x0001.
    Unspecified = 0x0001, "Unspecified error";
    /// 0x0002.
    NoMemory = 0x0002, "No memory";
    /// 0x0003.
    InvalidDeviceSetup = 0x0003, "Invalid device setup";
    /// 0x0005.
    CompatibilityReserved = 0x0005, "Reserved due to compatibility reasons";
    /// 0x0011.
    InvalidStateChange = 0x0011, "Invalid requested state change";
    /// 0x0012.
    UnknownState = 0x0012, "Unknown requested state";
    /// 0x0013.
    BootstrapNotSupported = 0x0013, "Bootstrap not supported";
    /// 0x0014.
    NoValidFirmware = 0x0014, "No valid firmware";
    /// 0x0015.
    InvalidMailboxBoot = 0x0015, "Invalid mailbox configuration (Bootstrap)";
    /// 0x0016.
    InvalidMailbox = 0x0016, "Invalid mailbox configuration (Pre-Op)";
    /// 0x0017.
    InvalidSyncManager = 0x0017, "Invalid sync manager configuration";
    /// 0x0018.
    NoValidInputs = 0x0018, "No valid inputs available";
    /// 0x0019.
    NoValidOutputs = 0x0019, "No valid outputs";
    /// 0x001A.
    SynchronizationError = 0x001A, "Synchronization error";
    /// 0x001B.
    SyncManagerWatchdog = 0x001B, "Sync manager watchdog";
    /// 0x001C.
    InvalidSyncManagerTypes = 0x001C, "Invalid sync manager types";
    /// 0x001D.
    InvalidOutputs = 0x001D, "Invalid output configuration";
    /// 0x001E.
    InvalidInputs = 0x001E, "Invalid input configuration";
    /// 0x001F.
    InvalidWatchdog = 0x001F, "Invalid watchdog configuration";
    /// 0x0020.
    NeedsColdStart = 0x0020, "Slave needs cold start";
    /// 0x0021.
    NeedsInit = 0x0021, "Slave needs Init";
    /// 0x0022.
    NeedsPreOp = 0x0022, "Slave needs Pre-Op";
    /// 0x0023.
    NeedsSafeOp = 0x0023, "Slave needs Safe-Op";
    /// 0x0024.
    InvalidInputMapping = 0x0024, "Invalid input mapping";
    /// 0x0025.
    InvalidOutputMapping = 0x0025, "Invalid output mapping";
    /// 0x0026.
    InconsistentSettings = 0x0026, "Inconsistent settings";
    /// 0x0027.
    FreeRunNotSupported = 0x0027, "Free-run not supported";
    /// 0x0028.
    SyncModeNotSupported = 0x0028, "Synchronization not supported";
    /// 0x0029.
    FreeRunNeedsThreeBuffers = 0x0029, "Free-run needs 3-buffer mode";
    /// 0x002A.
    BackgroundWatchdog = 0x002A, "Background watchdog";
    /// 0x002B.
    NoValidInputsAndOutputs = 0x002B, "No valid inputs and outputs";
    /// 0x002C.
    FatalSyncError = 0x002C, "Fatal sync error";
    /// 0x002D.
    NoSyncError = 0x002D, "No sync error";
    /// 0x0030.
    InvalidDcSync = 0x0030, "Invalid DC SYNC configuration";
    /// 0x0031.
    InvalidDcLatch = 0x0031, "Invalid DC latch configuration";
    /// 0x0032.
    PllError = 0x0032, "PLL error";
    /// 0x0033.
    DcSyncIo = 0x0033, "DC sync IO error";
    /// 0x0034.
    DcSyncTimeout = 0x0034, "DC sync timeout error";
    /// 0x0035.
    DcInvalidSyncCycleTime = 0x0035, "DC invalid sync cycle time";
    /// 0x0036.
    DcSync0CycleTime = 0x0036, "DC SYNC0 cycle time";
    /// 0x0037.
    DcSync1CycleTime = 0x0037, "DC SYNC1 cycle time";
    /// 0x0041.
    MailboxAoe = 0x0041, "Mailbox AoE";
    /// 0x0042.
    MailboxEoe = 0x0042, "Mailbox EoE";
    /// 0x0043.
    MailboxCoe = 0x0043, "Mailbox CoE";
    /// 0x0044.
    MailboxFoe = 0x0044, "Mailbox FoE";
    /// 0x0045.
    MailboxSoe = 0x0045, "Mailbox SoE";
    /// 0x004F.
    MailboxVoe = 0x004F, "Mailbox VoE";
    /// 0x0050.
    EepromNoAccess = 0x0050, "EEPROM no access";
    /// 0x0051.
    EepromError = 0x0051, "EEPROM error";
    /// 0x0060.
    RestartedLocally = 0x0060, "Slave restarted locally";
    /// 0x0061.
    DeviceIdentificationUpdated = 0x0061, "Device identification value updated";
    /// 0x00F0.
    ApplicationControllerAvailable = 0x00F0, "Application controller available";
}

impl std::fmt::Display for AlStatusCode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "0x{:04X} ({})", self.code(), self.description())
    }
}

/// What a write to AL control does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Transition {
    /// Nothing: an error is indicated and the request does not acknowledge it.
    Unchanged,
    /// The requested state is entered (or kept), the error indication and code cleared.
    To(AlState),
    /// The request is refused: the state stays, with the error indication and this code.
    Refused(AlStatusCode),
}

/// One SyncManager setting a transition checks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SmRule {
    /// The SyncManager's number (its place among the ESI's `Sm` elements).
    pub sm: usize,
    /// Physical start address.
    pub start: u16,
    /// Smallest and largest length.
    pub len: (u16, u16),
    /// Control byte.
    pub control: u8,
}

/// What the transitions check, from the device description.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct AlConfig {
    /// SM0 (mailbox out) and SM1 (mailbox in).
    pub mailbox: Option<[SmRule; 2]>,
    /// SM0 and SM1 as the bootstrap mailbox (ESI `Eeprom/BootStrap`: receive offset and size, send
    /// offset and size), for a device with a Bootstrap state; `None`: Init → Bootstrap is refused
    /// with 0x0013.
    pub boot_mailbox: Option<[SmRule; 2]>,
    /// SM2 (outputs), when the device has outputs.
    pub outputs: Option<SmRule>,
    /// SM3 (inputs), when the device has inputs.
    pub inputs: Option<SmRule>,
    /// The SYNC0 cycle times (ns) the device accepts when SYNC0 is activated; checked at
    /// Pre-Op → Safe-Op (AL status code 0x0036).
    pub sync0_cycle: Option<(u32, u32)>,
    /// The device has no SYNC0 (no `Dc/OpMode` assigns it): an activated SYNC0 is refused at
    /// Pre-Op → Safe-Op with 0x0030 (invalid DC SYNC configuration).
    pub no_sync0: bool,
    /// The application's verdict on its present PDO configuration: when set, Pre-Op → Safe-Op is
    /// refused with this code (0x0025 invalid output mapping, 0x0024 invalid input mapping) before
    /// the SyncManagers are looked at.
    pub mapping_refused: Option<AlStatusCode>,
}

impl AlConfig {
    /// The checks of the ESI's `Sm` elements.
    pub fn from_description(desc: &DeviceDescription) -> AlConfig {
        let Some(ec) = &desc.ethercat else {
            return AlConfig::default();
        };
        let rule = |kind: &str| {
            let at = ec
                .sync_managers
                .iter()
                .position(|s| s.kind == kind)
                .filter(|&at| at < super::sm::SYNC_MANAGERS)?;
            let s = &ec.sync_managers[at];
            let d = s.default_size.unwrap_or(0);
            Some(SmRule {
                sm: at,
                start: s.start_address,
                len: (s.min_size.unwrap_or(d), s.max_size.unwrap_or(d)),
                control: s.control_byte,
            })
        };
        let mailbox = rule("MBoxOut").zip(rule("MBoxIn")).map(|(a, b)| [a, b]);
        let boot = ec.eeprom.as_ref().map(|e| e.boot_strap.as_slice());
        let word = |b: &[u8], k: usize| u16::from_le_bytes([b[2 * k], b[2 * k + 1]]);
        let boot_mailbox = match (mailbox, boot) {
            (Some([out, inn]), Some(b)) if b.len() >= 8 => {
                // The bootstrap mailbox at its own place and size, as the standard one is set
                // otherwise; no shorter than the standard one's smallest.
                let at = |r: SmRule, start: u16, size: u16| SmRule {
                    start,
                    len: (r.len.0.min(size), size),
                    ..r
                };
                Some([
                    at(out, word(b, 0), word(b, 1)),
                    at(inn, word(b, 2), word(b, 3)),
                ])
            }
            _ => None,
        };
        AlConfig {
            mailbox,
            boot_mailbox,
            outputs: rule("Outputs"),
            inputs: rule("Inputs"),
            sync0_cycle: None,
            no_sync0: false,
            mapping_refused: None,
        }
    }
}

impl SmRule {
    /// Whether SyncManager `sm` is enabled and set as this rule says.
    fn accepts(&self, sm: SyncManager) -> bool {
        sm.enabled
            && sm.start == self.start
            && (self.len.0..=self.len.1).contains(&sm.len)
            && sm.control == self.control
    }
}

/// The outcome of writing `control` to the AL control register of `esc` (its configuration, state
/// and registers as they are).
pub fn transition(esc: &Esc, control: AlControl) -> Transition {
    use AlState::{Boot, Init, Op, PreOp, SafeOp};
    let config = &esc.al;
    let (current, error) = esc.al_state();
    if error && !control.acknowledge {
        return Transition::Unchanged;
    }
    let Some(requested) = control.requested() else {
        return Transition::Refused(AlStatusCode::UnknownState);
    };
    let refuse = Transition::Refused;
    match (requested, current) {
        // Any state may go back down to Init.
        (Init, _) => Transition::To(Init),
        (Boot, Init) => match &config.boot_mailbox {
            None => refuse(AlStatusCode::BootstrapNotSupported),
            Some([out, inn])
                if !(out.accepts(esc.sync_manager(out.sm))
                    && inn.accepts(esc.sync_manager(inn.sm))) =>
            {
                refuse(AlStatusCode::InvalidMailboxBoot)
            }
            Some(_) => Transition::To(Boot),
        },
        (Boot, Boot) => Transition::To(Boot),
        (Boot, _) if config.boot_mailbox.is_none() => refuse(AlStatusCode::BootstrapNotSupported),
        (Boot, _) => refuse(AlStatusCode::InvalidStateChange),
        (PreOp, Init) => match &config.mailbox {
            Some([out, inn])
                if !(out.accepts(esc.sync_manager(out.sm))
                    && inn.accepts(esc.sync_manager(inn.sm))) =>
            {
                refuse(AlStatusCode::InvalidMailbox)
            }
            _ => Transition::To(PreOp),
        },
        (PreOp, PreOp | SafeOp | Op) => Transition::To(PreOp),
        (SafeOp, PreOp) => {
            if let Some(code) = config.mapping_refused {
                refuse(code)
            } else if config
                .outputs
                .is_some_and(|r| !r.accepts(esc.sync_manager(r.sm)))
            {
                refuse(AlStatusCode::InvalidOutputs)
            } else if config
                .inputs
                .is_some_and(|r| !r.accepts(esc.sync_manager(r.sm)))
            {
                refuse(AlStatusCode::InvalidInputs)
            } else if config.no_sync0 && esc.sync0_cycle().is_some() {
                refuse(AlStatusCode::InvalidDcSync)
            } else if config.sync0_cycle.is_some_and(|(lo, hi)| {
                // SYNC0 off is accepted; on, its cycle time must be in the range (SMD-T3-003).
                esc.sync0_cycle().is_some_and(|c| !(lo..=hi).contains(&c))
            }) {
                refuse(AlStatusCode::DcSync0CycleTime)
            } else {
                Transition::To(SafeOp)
            }
        }
        (SafeOp, SafeOp | Op) => Transition::To(SafeOp),
        (Op, SafeOp | Op) => Transition::To(Op),
        (PreOp | SafeOp | Op, _) => refuse(AlStatusCode::InvalidStateChange),
    }
}
