//! The Application Layer state machine of a slave (ETG.1000.6 §6.4): AL control (0x0120), AL status
//! (0x0130) and AL status code (0x0134), with the checks each transition makes against the
//! SyncManager settings of the device description.
//!
//! Init → Pre-Op needs SM0/SM1 (the mailbox) configured as the ESI says (start address, a length
//! within MinSize…MaxSize, the control byte, enabled); Pre-Op → Safe-Op needs SM2/SM3 (process data)
//! at their start addresses with the process-data length, enabled, and — when the device limits it —
//! an activated SYNC0 to run at an accepted cycle time (0x0036). Op is reached from Safe-Op; any
//! state may go back down. A refused request sets the error indicator (AL status bit 4) and the status
//! code, and the state stays; further requests are refused until the master acknowledges the error
//! (AL control bit 4).

use od::DeviceDescription;

use super::sm::SyncManager;
use super::Esc;

/// AL control register.
pub const AL_CONTROL: u16 = 0x0120;
/// AL status register.
pub const AL_STATUS: u16 = 0x0130;
/// AL status code register.
pub const AL_STATUS_CODE: u16 = 0x0134;

/// The states (AL status bits 0–3).
pub mod state {
    /// Init.
    pub const INIT: u8 = 1;
    /// Pre-Operational.
    pub const PREOP: u8 = 2;
    /// Bootstrap.
    pub const BOOT: u8 = 3;
    /// Safe-Operational.
    pub const SAFEOP: u8 = 4;
    /// Operational.
    pub const OP: u8 = 8;
}

/// AL status codes (ETG.1000.6 Table 11).
pub mod code {
    /// No error.
    pub const NONE: u16 = 0x0000;
    /// Invalid requested state change.
    pub const INVALID_STATE_CHANGE: u16 = 0x0011;
    /// Unknown requested state.
    pub const UNKNOWN_STATE: u16 = 0x0012;
    /// Bootstrap not supported.
    pub const BOOTSTRAP_NOT_SUPPORTED: u16 = 0x0013;
    /// Invalid mailbox configuration (Pre-Op).
    pub const INVALID_MAILBOX: u16 = 0x0016;
    /// Invalid output configuration.
    pub const INVALID_OUTPUTS: u16 = 0x001D;
    /// Invalid input configuration.
    pub const INVALID_INPUTS: u16 = 0x001E;
    /// SyncManager watchdog.
    pub const SM_WATCHDOG: u16 = 0x001B;
    /// DC SYNC0 cycle time.
    pub const SYNC0_CYCLE_TIME: u16 = 0x0036;
}

/// One SyncManager setting a transition checks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SmRule {
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
    /// SM2 (outputs), when the device has outputs.
    pub outputs: Option<SmRule>,
    /// SM3 (inputs), when the device has inputs.
    pub inputs: Option<SmRule>,
    /// The SYNC0 cycle times (ns) the device accepts when SYNC0 is activated; checked at
    /// Pre-Op → Safe-Op (AL status code 0x0036).
    pub sync0_cycle: Option<(u32, u32)>,
}

impl AlConfig {
    /// The checks of the ESI's `Sm` elements.
    pub fn from_description(desc: &DeviceDescription) -> AlConfig {
        let Some(ec) = &desc.ethercat else {
            return AlConfig::default();
        };
        let rule = |kind: &str| {
            ec.sync_managers.iter().find(|s| s.kind == kind).map(|s| {
                let d = s.default_size.unwrap_or(0);
                SmRule {
                    start: s.start_address,
                    len: (s.min_size.unwrap_or(d), s.max_size.unwrap_or(d)),
                    control: s.control_byte,
                }
            })
        };
        AlConfig {
            mailbox: rule("MBoxOut").zip(rule("MBoxIn")).map(|(a, b)| [a, b]),
            outputs: rule("Outputs"),
            inputs: rule("Inputs"),
            sync0_cycle: None,
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
/// and registers as they are): the new state and status code (0 when accepted).
pub fn transition(esc: &Esc, control: u16) -> (u8, u16) {
    let config = &esc.al;
    let (current, error) = esc.al_state();
    let requested = (control & 0x0F) as u8;
    let acknowledge = control & 0x10 != 0;
    if error && !acknowledge {
        return (current, u16::MAX); // no change while the error is not acknowledged
    }
    let ok = (requested, code::NONE);
    match requested {
        state::INIT => ok,
        state::BOOT => (current, code::BOOTSTRAP_NOT_SUPPORTED),
        state::PREOP => match current {
            state::INIT => match &config.mailbox {
                Some([out, inn])
                    if !(out.accepts(esc.sync_manager(0)) && inn.accepts(esc.sync_manager(1))) =>
                {
                    (current, code::INVALID_MAILBOX)
                }
                _ => ok,
            },
            state::PREOP | state::SAFEOP | state::OP => ok,
            _ => (current, code::INVALID_STATE_CHANGE),
        },
        state::SAFEOP => match current {
            state::PREOP => {
                if config
                    .outputs
                    .is_some_and(|r| !r.accepts(esc.sync_manager(2)))
                {
                    (current, code::INVALID_OUTPUTS)
                } else if config
                    .inputs
                    .is_some_and(|r| !r.accepts(esc.sync_manager(3)))
                {
                    (current, code::INVALID_INPUTS)
                } else if config.sync0_cycle.is_some_and(|(lo, hi)| {
                    // SYNC0 off is accepted; on, its cycle time must be in the range.
                    esc.sync0_cycle().is_some_and(|c| !(lo..=hi).contains(&c))
                }) {
                    (current, code::SYNC0_CYCLE_TIME)
                } else {
                    ok
                }
            }
            state::SAFEOP | state::OP => ok,
            _ => (current, code::INVALID_STATE_CHANGE),
        },
        state::OP => match current {
            state::SAFEOP | state::OP => ok,
            _ => (current, code::INVALID_STATE_CHANGE),
        },
        _ => (current, code::UNKNOWN_STATE),
    }
}
