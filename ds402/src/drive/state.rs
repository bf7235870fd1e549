//! The device control function of the drive: the CiA 402 finite state automaton with its option
//! codes, faults, and the status word (CiA 402-2, "Device control": state machine, controlword
//! 0x6040, statusword 0x6041, option codes 0x605A–0x605E, error code 0x603F).
//!
//! Transitions (numbers as in the standard's state diagram):
//! - 0 power on / NMT reset → Not ready to switch on; 1 → Switch on disabled by itself at the first
//!   control tick.
//! - 2 Shutdown; 3 Switch on; 4 Enable operation (also 3 + 4 at once: "Switch on + enable
//!   operation", 0x0F in Ready to switch on); 6 Shutdown; 7 and 10 Disable voltage or Quick stop.
//! - 5 Disable operation, by 0x605C: 0 power off at once; 1 slow-down ramp first (the state stays
//!   Operation enabled until standstill, then Switched on).
//! - 8 Shutdown from Operation enabled, by 0x605B: 0 power off at once; 1 slow-down ramp first.
//! - 9 Disable voltage: power off at once, the motor coasts.
//! - 11 Quick stop, by 0x605A: 0 disable at once (11 and 12 together); 1/5 slow-down ramp, 2/6
//!   quick-stop ramp (0x6085), 3/7 current limit, 4/8 voltage limit; 1–4 end in Switch on
//!   disabled at standstill (12), 5–8 stay in Quick stop active.
//! - 12 also on Disable voltage; 16 Enable operation from Quick stop active, with 0x605A 5–8 only.
//! - 13 a fault, 14 the fault reaction (0x605E: 0 power off at once, 1 slow-down ramp, 2 quick-stop
//!   ramp, 3 current limit, 4 voltage limit) completed, 15 Fault reset (rising edge of bit 7).
//!
//! "Slow-down ramp" is the profile deceleration 0x6084 (the homing acceleration 0x609A in homing);
//! "current limit" and "voltage limit" brake at the deceleration the torque limit allows.
//! Automatic transitions (1, 12 after a quick stop, 5/8 after the slow-down, 14) happen at the
//! control tick at which the condition is met, so a state entered at standstill shows for one tick.
//! The control word is also evaluated as a level at every tick (a command sent while the drive was
//! in Not ready to switch on takes effect at the first tick); only Fault reset needs an edge.

use crate::cia402::{Command, State};

use super::objects::P;
use super::{Drive, Motion};

/// What follows a stop ramp of the device control function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum After {
    /// Transition 12: quick stop option 1–4 completed.
    SwitchOnDisabled,
    /// Transition 8 with shutdown option 1.
    ReadyToSwitchOn,
    /// Transition 5 with disable operation option 1.
    SwitchedOn,
    /// Transition 14: the fault reaction completed.
    Fault,
    /// Quick stop option 5–8: stay in Quick stop active.
    Stay,
}

/// Which deceleration a stop uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Ramp {
    /// The slow-down ramp: 0x6084 (0x609A in homing).
    SlowDown,
    /// The quick-stop ramp: 0x6085.
    QuickStop,
    /// The current limit and the voltage limit (the latter taken as the current limit too): the
    /// deceleration the torque limit allows.
    TorqueLimit,
}

impl Ramp {
    /// The ramp of an option code value 1–4 (0x605A also 5–8, 0x605D, 0x605E).
    pub fn of(option: i64) -> Ramp {
        match (option - 1).rem_euclid(4) {
            0 => Ramp::SlowDown,
            1 => Ramp::QuickStop,
            _ => Ramp::TorqueLimit,
        }
    }
}

/// Status word bit 4: voltage enabled.
pub const SW_VOLTAGE_ENABLED: u16 = 1 << 4;
/// Status word bit 5: quick stop (0 = quick stop active).
pub const SW_QUICK_STOP: u16 = 1 << 5;
/// Status word bit 7: warning.
pub const SW_WARNING: u16 = 1 << 7;
/// Status word bit 9: remote.
pub const SW_REMOTE: u16 = 1 << 9;
/// Status word bit 10: target reached.
pub const SW_TARGET_REACHED: u16 = 1 << 10;
/// Status word bit 11: internal limit active.
pub const SW_INTERNAL_LIMIT: u16 = 1 << 11;
/// Status word bit 12: operation-mode specific.
pub const SW_OMS12: u16 = 1 << 12;
/// Status word bit 13: operation-mode specific.
pub const SW_OMS13: u16 = 1 << 13;

/// Error code 0x8611: following error (CiA 402-2 error codes).
pub const ERROR_FOLLOWING: u16 = 0x8611;
/// Error code 0x8612: reference limit (a limit switch run into).
pub const ERROR_REFERENCE_LIMIT: u16 = 0x8612;

impl Drive {
    /// Whether the power stage drives the motor: Operation enabled, Quick stop active, and Fault
    /// reaction active while braking.
    pub(crate) fn powered(&self) -> bool {
        match self.state {
            State::OperationEnabled | State::QuickStopActive => true,
            State::FaultReactionActive => self.braking.is_some(),
            _ => false,
        }
    }

    /// Status word bits 0–6 (CiA 402-2 statusword state table; bit 4 voltage enabled in Switched
    /// on, Operation enabled, Quick stop active and a braking Fault reaction active; bit 5 is 1
    /// outside Quick stop active).
    pub(crate) fn state_bits(&self) -> u16 {
        let bits = match self.state {
            State::NotReadyToSwitchOn => 0x0000,
            State::SwitchOnDisabled => 0x0040,
            State::ReadyToSwitchOn => 0x0001,
            State::SwitchedOn => 0x0003,
            State::OperationEnabled => 0x0007,
            State::QuickStopActive => 0x0007,
            State::FaultReactionActive => 0x000F,
            State::Fault => 0x0008,
        };
        let voltage = matches!(
            self.state,
            State::SwitchedOn | State::OperationEnabled | State::QuickStopActive
        ) || (self.state == State::FaultReactionActive && self.braking.is_some());
        let quick_stop = self.state != State::QuickStopActive;
        bits | if voltage { SW_VOLTAGE_ENABLED } else { 0 }
            | if quick_stop { SW_QUICK_STOP } else { 0 }
    }

    /// The control word as a level at a tick: the command without the Fault-reset edge.
    pub(crate) fn apply_level(&mut self) {
        let cmd = Command::decode(self.control, self.control, self.state);
        self.apply_command(cmd);
    }

    /// Whether the control word, evaluated as a level, would change anything.
    pub(crate) fn level_is_idle(&self) -> bool {
        let cmd = Command::decode(self.control, self.control, self.state);
        use Command::*;
        use State::*;
        !matches!(
            (self.state, cmd),
            (NotReadyToSwitchOn, _)
                | (SwitchOnDisabled, Some(Shutdown))
                | (
                    ReadyToSwitchOn,
                    Some(SwitchOn | EnableOperation | DisableVoltage | QuickStop)
                )
                | (
                    SwitchedOn,
                    Some(EnableOperation | Shutdown | DisableVoltage | QuickStop)
                )
        )
    }

    /// Carries out a state-machine command.
    pub(crate) fn apply_command(&mut self, cmd: Option<Command>) {
        use Command::*;
        use State::*;
        let Some(cmd) = cmd else {
            return;
        };
        // Each arm names its state and command: Not ready to switch on and Fault reaction active
        // take none, Fault reset acts in Fault only.
        match (self.state, cmd) {
            // 15: Fault reset clears the error.
            (Fault, FaultReset) => {
                self.error_code = 0;
                self.state = SwitchOnDisabled;
            }
            // 2
            (SwitchOnDisabled, Shutdown) => self.state = ReadyToSwitchOn,
            // 3
            (ReadyToSwitchOn, SwitchOn) => self.state = SwitchedOn,
            // 3 + 4
            (ReadyToSwitchOn, EnableOperation) => {
                self.state = SwitchedOn;
                self.enable_operation();
            }
            // 7
            (ReadyToSwitchOn, DisableVoltage | QuickStop) => self.state = SwitchOnDisabled,
            // 4
            (SwitchedOn, EnableOperation) => self.enable_operation(),
            // 6
            (SwitchedOn, Shutdown) => self.state = ReadyToSwitchOn,
            // 10
            (SwitchedOn, DisableVoltage | QuickStop) => self.state = SwitchOnDisabled,
            // 5
            (OperationEnabled, DisableOperation) => {
                if self.params.get(P::DisableOperationOption) == 1 {
                    self.brake(Ramp::SlowDown, After::SwitchedOn);
                } else {
                    self.power_off(SwitchedOn);
                }
            }
            // 8
            (OperationEnabled, Shutdown) => {
                if self.params.get(P::ShutdownOption) == 1 {
                    self.brake(Ramp::SlowDown, After::ReadyToSwitchOn);
                } else {
                    self.power_off(ReadyToSwitchOn);
                }
            }
            // 9, 12
            (OperationEnabled | QuickStopActive, DisableVoltage) => {
                self.power_off(SwitchOnDisabled)
            }
            // 11
            (OperationEnabled, QuickStop) => self.quick_stop(),
            // Enable operation again while a slow-down for 5 or 8 runs: carry on.
            (OperationEnabled, EnableOperation) if self.braking.is_some() => {
                self.braking = None;
                self.start_mode();
            }
            // 16
            (QuickStopActive, EnableOperation)
                if (5..=8).contains(&self.params.get(P::QuickStopOption)) =>
            {
                self.braking = None;
                self.state = OperationEnabled;
                self.start_mode();
            }
            _ => {}
        }
    }

    /// Transition 4 (or 16): the power stage comes on and the mode of operation starts.
    fn enable_operation(&mut self) {
        self.state = State::OperationEnabled;
        self.braking = None;
        let actual = self.actual_raw();
        self.demand = super::Demand {
            p: actual,
            v: self.reported_velocity_f64(),
        };
        self.motor.engage(self.demand.p);
        self.start_mode();
    }

    /// Transition 11 with the quick stop option code.
    fn quick_stop(&mut self) {
        let option = self.params.get(P::QuickStopOption);
        self.state = State::QuickStopActive;
        self.mode_interrupted();
        if option == 0 {
            self.power_off(State::SwitchOnDisabled);
            return;
        }
        let after = if option <= 4 {
            After::SwitchOnDisabled
        } else {
            After::Stay
        };
        self.braking = None;
        self.brake(Ramp::of(option), after);
    }

    /// Brakes to standstill on `ramp`, then `after`. A stop already running keeps its ramp and
    /// takes the new `after`.
    pub(crate) fn brake(&mut self, ramp: Ramp, after: After) {
        if self.braking.replace(after).is_some() {
            return;
        }
        let dec = self.ramp_decel(ramp);
        self.plan(super::profile::stop(self.demand.p, self.demand.v, dec));
    }

    /// The deceleration of `ramp`, counts/s².
    pub(crate) fn ramp_decel(&self, ramp: Ramp) -> f64 {
        match ramp {
            Ramp::SlowDown if self.mode == super::modes::HM => {
                self.params.positive(P::HomingAcceleration)
            }
            Ramp::SlowDown => self.profile_decel(),
            Ramp::QuickStop => self.params.positive(P::QuickStopDeceleration),
            Ramp::TorqueLimit => self.motor.limit_decel(self.torque_limit()),
        }
    }

    /// The power stage goes off: the new `state`, no stop ramp, the motor coasts.
    pub(crate) fn power_off(&mut self, state: State) {
        if self.state == State::OperationEnabled || self.state == State::QuickStopActive {
            self.mode_interrupted();
        }
        self.state = state;
        self.braking = None;
        self.motion = Motion::Free;
    }

    /// Transition 13: a fault with `code` (0x603F) in any state but Fault reaction active and Fault;
    /// the fault reaction (0x605E) brakes with the power on, or switches it off at once (then 14 in
    /// the same instant).
    pub(crate) fn fault(&mut self, code: u16) {
        if matches!(self.state, State::FaultReactionActive | State::Fault) {
            return;
        }
        let was_powered = self.powered();
        if was_powered {
            self.mode_interrupted();
        }
        self.error_code = code;
        self.state = State::FaultReactionActive;
        self.braking = None;
        let option = self.params.get(P::FaultReactionOption);
        if was_powered && option != 0 {
            self.brake(Ramp::of(option), After::Fault);
        } else {
            self.power_off(State::Fault);
        }
    }

    /// At a tick: a stop ramp that has reached standstill completes its transition.
    pub(crate) fn finish_braking(&mut self) {
        let Some(after) = self.braking else {
            return;
        };
        if !self.plan_done() {
            return;
        }
        match after {
            After::Stay => {
                self.braking = None;
                self.motion = Motion::Hold;
            }
            After::SwitchOnDisabled => self.power_off(State::SwitchOnDisabled),
            After::ReadyToSwitchOn => self.power_off(State::ReadyToSwitchOn),
            After::SwitchedOn => self.power_off(State::SwitchedOn),
            After::Fault => self.power_off(State::Fault),
        }
    }
}
