//! The modes of operation (CiA 402-2: modes of operation 0x6060/0x6061, profile position mode,
//! profile velocity mode, cyclic synchronous position/velocity/torque modes, position control
//! function), halt (controlword bit 8), target reached, the following error monitor, the software
//! position limits, and the status word they feed.
//!
//! - **Profile position (1).** A rising edge of controlword bit 4 (new set-point) takes 0x607A
//!   (bit 6: relative, to the preceding target, the position demand or the position actual as
//!   0x60F2 bits 0–1 say) clamped to the software limits 0x607D, and sets status bit 12 (set-point
//!   acknowledge); bit 4 back to 0 clears it. With bit 5 (change set immediately) the move changes
//!   at once; without it a set-point that arrives during a move waits in a one-deep buffer (bit 12
//!   stays 1 until it is taken) and starts when the move ends. The profile is the trapezoid of
//!   0x6081 (limited by 0x607F and 0x6080), 0x6083, 0x6084 (limited by 0x60C5/0x60C6).
//! - **Profile velocity (3).** 0x60FF (limited the same way), ramped with 0x6083 up and 0x6084
//!   down.
//! - **Cyclic synchronous (8, 9, 10).** See [`Drive::sync`](super::Drive::sync).
//! - **Halt (bit 8)** stops with 0x605D (1 slow-down ramp, 2 quick-stop ramp, 3 current limit, 4
//!   voltage limit) and stays in Operation enabled; releasing it resumes the positioning (pp), the
//!   target velocity (pv), or following the next SYNC (cyclic modes). In homing it interrupts.

use std::time::{Duration, Instant};

use crate::cia402::State;

use super::limits::{int, Kind};
use super::objects::P;
use super::state::{
    Ramp, ERROR_FOLLOWING, ERROR_REFERENCE_LIMIT, SW_INTERNAL_LIMIT, SW_OMS12, SW_OMS13, SW_REMOTE,
    SW_TARGET_REACHED, SW_WARNING,
};
use super::{profile, switches, Drive, Motion};

/// Profile position mode.
pub(crate) const PP: i8 = 1;
/// Profile velocity mode.
pub(crate) const PV: i8 = 3;
/// Homing mode.
pub(crate) const HM: i8 = 6;
/// Cyclic synchronous position mode.
pub(crate) const CSP: i8 = 8;
/// Cyclic synchronous velocity mode.
pub(crate) const CSV: i8 = 9;
/// Cyclic synchronous torque mode.
pub(crate) const CST: i8 = 10;

/// Controlword bit 4: new set-point (pp), homing operation start (hm).
pub(crate) const CW_NEW_SETPOINT: u16 = 1 << 4;
/// Controlword bit 5: change set immediately (pp).
pub(crate) const CW_IMMEDIATE: u16 = 1 << 5;
/// Controlword bit 6: relative (pp).
pub(crate) const CW_RELATIVE: u16 = 1 << 6;
/// Controlword bit 8: halt.
pub(crate) const CW_HALT: u16 = 1 << 8;

/// The state of profile position mode.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct ProfilePosition {
    /// The target in processing, raw counts.
    pub target: Option<f64>,
    /// The preceding target, user units (base of relative moves with 0x60F2 bits 0–1 = 0).
    pub last_user: i64,
    /// Status bit 12: set-point acknowledge.
    pub ack: bool,
    /// A set-point waiting for the move in processing to end: user units and whether clamped.
    pub buffer: Option<(i64, bool)>,
    /// The target in processing was clamped by the software limits.
    pub clamped: bool,
    /// Since when the actual position is within the position window of the target.
    pub window_since: Option<u64>,
}

/// The state of profile velocity mode.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct ProfileVelocity {
    /// Since when the velocity actual is within the velocity window of the target.
    pub window_since: Option<u64>,
    /// Since when the velocity actual is above the velocity threshold.
    pub over_since: Option<u64>,
}

/// The SYNC clock and the cyclic modes' state.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Cyclic {
    pub last_sync: Option<Instant>,
    pub period: Option<Duration>,
    /// The last csp target was clamped by the software limits.
    pub clamped: bool,
    /// The demand runs after the set-points within the drive's limits (it does not follow them).
    pub limited: bool,
    /// While it does, what the set-points ask for at the last tick (0x6062 and 0x606B read it).
    pub reference: Option<super::Demand>,
}

/// The following error monitor.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Following {
    /// Since when the following error is beyond the window.
    pub since: Option<u64>,
    /// Beyond the window for the time-out: status bit 13.
    pub exceeded: bool,
}

impl Drive {
    /// Stores a parameter written through the hook and does what it means now.
    pub(crate) fn set_param(&mut self, p: P, value: i64) {
        let old = self.params.get(p);
        self.params.set(p, value);
        match p {
            P::ControlWord => {
                let previous = self.control;
                self.write_control(value as u16, previous);
            }
            P::Mode => self.set_mode(value as i8),
            // An RPDO delivers the same target every cycle: only a change replans.
            P::TargetVelocity if value != old && self.following_pv() => self.pv_plan(),
            P::EncoderIncrements | P::MotorRevolutions => {
                self.motor.cpr = Drive::cpr_of(&self.params);
            }
            _ => {}
        }
    }

    fn following_pv(&self) -> bool {
        self.mode == PV
            && self.state == State::OperationEnabled
            && self.braking.is_none()
            && !self.halted
    }

    /// A control word written at the present instant: the state machine command (with the
    /// Fault-reset edge against the previous word), then the mode's bits.
    fn write_control(&mut self, cw: u16, previous: u16) {
        self.control = cw;
        let cmd = crate::cia402::Command::decode(cw, previous, self.state);
        self.apply_command(cmd);
        self.update_halt();
        let rose = cw & CW_NEW_SETPOINT != 0 && previous & CW_NEW_SETPOINT == 0;
        let fell = cw & CW_NEW_SETPOINT == 0 && previous & CW_NEW_SETPOINT != 0;
        // Bit 4 back to 0 ends the set-point handshake in any state and mode, unless a set-point
        // still waits in the buffer.
        if fell && self.pp.buffer.is_none() {
            self.pp.ack = false;
        }
        if self.state != State::OperationEnabled || self.braking.is_some() {
            return;
        }
        match self.mode {
            PP if rose => self.pp_new_setpoint(cw),
            HM if rose => self.homing_start(),
            HM if fell => self.homing_interrupt(),
            _ => {}
        }
    }

    /// 0x6060 written: the mode in effect changes at once (0x6061 shows it).
    fn set_mode(&mut self, mode: i8) {
        if mode == self.mode {
            return;
        }
        if self.state == State::OperationEnabled && self.braking.is_none() {
            self.mode_interrupted();
            self.mode = mode;
            self.start_mode();
        } else {
            self.mode = mode;
        }
    }

    /// The mode in effect starts (Operation enabled entered, a mode change, a halt or slow-down
    /// released): from the present demand.
    pub(crate) fn start_mode(&mut self) {
        self.halted = self.control & CW_HALT != 0;
        self.pp.window_since = None;
        self.pv = ProfileVelocity::default();
        self.follow = Following::default();
        self.cyclic.clamped = false;
        self.cyclic.limited = false;
        self.reported = 0;
        match self.mode {
            PV => self.pv_plan(),
            CST => {
                self.motion = Motion::Torque {
                    permille: self.cst_target(),
                };
            }
            PP => {
                if let (Some(t), false) = (self.pp.target, self.halted) {
                    self.pp_plan(t);
                } else {
                    self.stop_or_hold(self.profile_decel());
                }
            }
            _ => {
                let dec = if self.mode == HM {
                    self.params.positive(P::HomingAcceleration)
                } else {
                    self.profile_decel()
                };
                self.stop_or_hold(dec);
            }
        }
        if self.halted {
            self.halt_stop();
        }
    }

    /// Leaving the mode's activity (quick stop, fault, power off, mode change): homing is
    /// interrupted, a pp set-point dropped. A buffered set-point held the acknowledge after bit 4
    /// went back to 0; dropped, it releases it.
    pub(crate) fn mode_interrupted(&mut self) {
        self.homing_interrupted();
        self.pp.target = None;
        self.pp.buffer = None;
        self.pp.clamped = false;
        if self.control & CW_NEW_SETPOINT == 0 {
            self.pp.ack = false;
        }
    }

    /// Brakes at `dec` if moving, else holds.
    fn stop_or_hold(&mut self, dec: f64) {
        if self.demand.v != 0.0 {
            self.plan(profile::stop(self.demand.p, self.demand.v, dec));
        } else {
            self.motion = Motion::Hold;
        }
    }

    /// Controlword bit 8 as a level.
    pub(crate) fn update_halt(&mut self) {
        let halt = self.control & CW_HALT != 0;
        if halt == self.halted {
            return;
        }
        self.halted = halt;
        if self.state != State::OperationEnabled || self.braking.is_some() {
            return;
        }
        if self.mode == HM {
            if halt {
                self.homing_interrupt();
            }
            return;
        }
        if halt {
            self.halt_stop();
            return;
        }
        match self.mode {
            PP => {
                if let Some(t) = self.pp.target {
                    self.pp_plan(t);
                }
            }
            PV => self.pv_plan(),
            CST => {
                self.motion = Motion::Torque {
                    permille: self.cst_target(),
                }
            }
            _ => {}
        }
    }

    /// Stops on the halt option code's ramp.
    pub(crate) fn halt_stop(&mut self) {
        self.pv.window_since = None;
        let dec = self.ramp_decel(Ramp::of(self.params.get(P::HaltOption)));
        self.plan(profile::stop(self.demand.p, self.demand.v, dec));
    }

    // ----- profile parameters -----

    /// The velocity limit, counts/s: 0x607F and 0x6080 (rpm).
    pub(crate) fn velocity_limit(&self) -> f64 {
        let profile_max = self.params.unsigned(P::MaxProfileVelocity) as f64;
        let motor_max = self.params.unsigned(P::MaxMotorSpeed) as f64 * self.motor.cpr / 60.0;
        profile_max.min(motor_max)
    }

    pub(crate) fn profile_accel(&self) -> f64 {
        self.params
            .positive(P::ProfileAcceleration)
            .min(self.params.positive(P::MaxAcceleration))
    }

    pub(crate) fn profile_decel(&self) -> f64 {
        self.params
            .positive(P::ProfileDeceleration)
            .min(self.params.positive(P::MaxDeceleration))
    }

    /// Clamps a user position to the software limits 0x607D (active when min < max): the value and
    /// whether it was clamped.
    pub(crate) fn clamp_to_limits(&self, user: i64) -> (i64, bool) {
        let min = self.params.get(P::MinPositionLimit);
        let max = self.params.get(P::MaxPositionLimit);
        if min >= max {
            return (user, false);
        }
        let clamped = user.clamp(min, max);
        (clamped, clamped != user)
    }

    // ----- profile position -----

    /// A rising edge of bit 4 in profile position mode.
    fn pp_new_setpoint(&mut self, cw: u16) {
        let target = self.params.get(P::TargetPosition);
        let wanted = if cw & CW_RELATIVE != 0 {
            let base = match self.params.get(P::PositioningOption) & 0x3 {
                1 => self.position_demand(),
                2 => self.position(),
                _ => self.pp.last_user,
            };
            base + target
        } else {
            target
        };
        let (user, clamped) = self.clamp_to_limits(wanted);
        let busy = self.pp.target.is_some() && (self.halted || !self.plan_done());
        if busy && cw & CW_IMMEDIATE == 0 {
            if self.pp.buffer.is_none() {
                self.pp.buffer = Some((user, clamped));
                self.pp.last_user = user;
                self.pp.ack = true;
            }
            return;
        }
        self.pp.last_user = user;
        self.pp.ack = true;
        self.pp_start(user, clamped);
    }

    /// Starts the move to `user` (user units).
    fn pp_start(&mut self, user: i64, clamped: bool) {
        let raw = (user - self.shift) as f64;
        self.pp.target = Some(raw);
        self.pp.clamped = clamped;
        self.pp.window_since = None;
        if !self.halted {
            self.pp_plan(raw);
        }
    }

    fn pp_plan(&mut self, raw: f64) {
        let vmax = self
            .params
            .unsigned(P::ProfileVelocity)
            .min(u64::from(u32::MAX)) as f64;
        let vmax = vmax.min(self.velocity_limit());
        let p = profile::move_to(
            self.demand.p,
            self.demand.v,
            raw,
            vmax,
            self.profile_accel(),
            self.profile_decel(),
        );
        self.plan(p);
    }

    /// pp status bit 10.
    fn pp_target_reached(&self) -> bool {
        if self.halted {
            return self.standstill();
        }
        match self.pp.target {
            None => self.standstill(),
            // A profile ends at its target, unless no move was possible (a profile velocity of 0).
            Some(t) if !self.plan_done() || self.demand.p != t => false,
            Some(_) => {
                self.params.unsigned(P::PositionWindow) == u64::from(u32::MAX)
                    || self.pp.window_since.is_some_and(|s| {
                        self.held_for(s, self.params.unsigned(P::PositionWindowTime))
                    })
            }
        }
    }

    // ----- profile velocity -----

    /// The pv target, limited.
    fn pv_target(&self) -> f64 {
        let limit = self.velocity_limit();
        (self.params.get(P::TargetVelocity) as f64).clamp(-limit, limit)
    }

    /// Ramps to the pv target (or stops while halted).
    pub(crate) fn pv_plan(&mut self) {
        self.pv.window_since = None;
        if self.halted {
            self.halt_stop();
            return;
        }
        let p = profile::velocity(
            self.demand.p,
            self.demand.v,
            self.pv_target(),
            self.profile_accel(),
            self.profile_decel(),
        );
        self.plan(p);
    }

    fn pv_target_reached(&self) -> bool {
        self.pv
            .window_since
            .is_some_and(|s| self.held_for(s, self.params.unsigned(P::VelocityWindowTime)))
    }

    fn pv_speed_zero(&self) -> bool {
        !self
            .pv
            .over_since
            .is_some_and(|s| self.held_for(s, self.params.unsigned(P::VelocityThresholdTime)))
    }

    // ----- cyclic synchronous -----

    fn cst_target(&self) -> f64 {
        (self.params.get(P::TargetTorque) + self.params.get(P::TorqueOffset)) as f64
    }

    /// The interpolation time period 0x60C2 (units · 10^index s), when the dictionary has it and it
    /// is not zero.
    fn interpolation_period(&self) -> Option<Duration> {
        if !self.params.present(P::InterpolationUnits) {
            return None;
        }
        let units = u64::try_from(self.params.get(P::InterpolationUnits)).ok()?;
        let exp = 9 + self.params.get(P::InterpolationIndex);
        if units == 0 || !(0..=18).contains(&exp) {
            return None;
        }
        Some(Duration::from_nanos(
            units.checked_mul(10u64.pow(exp as u32))?,
        ))
    }

    /// The SYNC at `now`, after the ticks up to it.
    pub(crate) fn on_sync(&mut self, now: Instant) {
        let measured = self
            .cyclic
            .last_sync
            .map(|l| now.saturating_duration_since(l))
            .filter(|d| !d.is_zero());
        let period = self
            .sync_cycle
            .or_else(|| self.interpolation_period())
            .or(measured)
            .or(self.cyclic.period)
            .unwrap_or(Duration::from_nanos(self.tick_ns));
        self.cyclic.period = Some(period);
        self.cyclic.last_sync = Some(now);
        if self.state != State::OperationEnabled || self.braking.is_some() || self.halted {
            return;
        }
        match self.mode {
            CSP => {
                let wanted =
                    self.params.get(P::TargetPosition) + self.params.get(P::PositionOffset);
                let (user, clamped) = self.clamp_to_limits(wanted);
                self.cyclic.clamped = clamped;
                if clamped {
                    let sub = if user < wanted { 2 } else { 1 };
                    let side = if sub == 2 { "beyond" } else { "below" };
                    let text = format!(
                        "csp target {} ({} + {}) {side} {} = {}: held there",
                        int(wanted as f64),
                        self.name(0x607A, 0),
                        self.name(0x60B0, 0),
                        self.name(0x607D, sub),
                        int(user as f64)
                    );
                    let object = Some(self.own(0x607D, sub));
                    self.report(
                        Kind::PositionLimit,
                        object,
                        wanted as f64,
                        user as f64,
                        text,
                    );
                }
                // The new segment starts where the demand is at the SYNC itself, which need not
                // fall on a control tick (an EtherCAT SYNC0 keeps its own time grid).
                self.motion = Motion::Position {
                    from: self.demand_at(now).p,
                    to: (user - self.shift) as f64,
                    at: now,
                    period,
                };
            }
            CSV => {
                let v = (self.params.get(P::TargetVelocity) + self.params.get(P::VelocityOffset))
                    as f64;
                let (limit, name, object) = self.velocity_bound();
                if v.abs() > limit {
                    let text = format!(
                        "csv target {} counts/s ({} + {}) above {name}: held there",
                        int(v),
                        self.name(0x60FF, 0),
                        self.name(0x60B1, 0)
                    );
                    self.report(Kind::CsvVelocity, Some(object), v.abs(), limit, text);
                }
                self.motion = Motion::Velocity {
                    from: self.demand_at(now).v,
                    to: v.clamp(-limit, limit),
                    at: now,
                    period,
                };
            }
            CST => {
                let permille = self.cst_target();
                let max = self.params.get(P::MaxTorque).max(0) as f64;
                if permille.abs() > max {
                    let text = format!(
                        "cst target {} ‰ ({} + {}) above {} = {} ‰: held there",
                        int(permille),
                        self.name(0x6071, 0),
                        self.name(0x60B2, 0),
                        self.name(0x6072, 0),
                        int(max)
                    );
                    let object = Some(self.own(0x6072, 0));
                    self.report(Kind::CstTorque, object, permille.abs(), max, text);
                }
                self.motion = Motion::Torque { permille };
            }
            _ => {}
        }
    }

    /// Velocity and torque feed-forward of the offsets 0x60B1 (csp) and 0x60B2 (csp, csv), in
    /// counts/s and N·m.
    pub(crate) fn feed_forward(&self) -> (f64, f64) {
        let torque = self.params.get(P::TorqueOffset) as f64 / 1000.0 * self.rated_torque();
        match self.mode {
            CSP => (self.params.get(P::VelocityOffset) as f64, torque),
            CSV => (0.0, torque),
            _ => (0.0, 0.0),
        }
    }

    /// Whether a cyclic mode follows its command value (status bit 12).
    fn cyclic_following(&self) -> bool {
        self.state == State::OperationEnabled && self.braking.is_none() && !self.halted
    }

    // ----- per tick -----

    /// Supervision at a tick: limit switches and the following error.
    pub(crate) fn supervise(&mut self) {
        if self.state == State::OperationEnabled && self.mode != HM {
            let inputs = self.digital_inputs();
            let v = if matches!(self.motion, Motion::Torque { .. }) {
                let v = self.motor.vel;
                if v.abs() < 1.0 {
                    0.0
                } else {
                    v
                }
            } else {
                self.demand.v
            };
            let neg = inputs & 1 << switches::NEGATIVE_LIMIT != 0;
            let pos = inputs & 1 << switches::POSITIVE_LIMIT != 0;
            if (neg && v < 0.0) || (pos && v > 0.0) {
                let (side, bit) = if v < 0.0 {
                    ("negative", switches::NEGATIVE_LIMIT)
                } else {
                    ("positive", switches::POSITIVE_LIMIT)
                };
                let text = format!(
                    "moving at {} counts/s into the {side} limit switch ({} bit {bit}): fault \
                     {ERROR_REFERENCE_LIMIT:#06X}",
                    int(v),
                    self.name(0x60FD, 0)
                );
                let object = Some(self.own(0x60FD, 0));
                self.report(Kind::LimitSwitch, object, v, 0.0, text);
                self.fault(ERROR_REFERENCE_LIMIT);
                return;
            }
        }
        self.following_tick();
    }

    /// The following error window, when monitoring is on.
    fn following_window(&self) -> Option<u64> {
        let w = self.params.unsigned(P::FollowingWindow);
        (w != 0 && w != u64::from(u32::MAX)).then_some(w)
    }

    fn following_tick(&mut self) {
        let monitored = matches!(self.state, State::OperationEnabled | State::QuickStopActive)
            && matches!(self.mode, PP | CSP);
        let (true, Some(window)) = (monitored, self.following_window()) else {
            self.follow = Following::default();
            return;
        };
        if self.following_error().unsigned_abs() > window {
            let since = *self.follow.since.get_or_insert(self.ticks);
            if self.held_for(since, self.params.unsigned(P::FollowingTimeout)) {
                self.follow.exceeded = true;
                if self.mode == CSP {
                    let error = self.following_error();
                    let timeout = self.params.unsigned(P::FollowingTimeout);
                    let text = format!(
                        "following error {} counts beyond {} = {} counts for {} = {} ms: fault \
                         {ERROR_FOLLOWING:#06X}",
                        int(error as f64),
                        self.name(0x6065, 0),
                        int(window as f64),
                        self.name(0x6066, 0),
                        int(timeout as f64)
                    );
                    let object = Some(self.own(0x6065, 0));
                    self.report(
                        Kind::FollowingError,
                        object,
                        error as f64,
                        window as f64,
                        text,
                    );
                    self.fault(ERROR_FOLLOWING);
                }
            }
        } else {
            self.follow = Following::default();
        }
    }

    /// The mode's bookkeeping at a tick: a buffered set-point starts, windows are timed.
    pub(crate) fn mode_tick(&mut self) {
        if !matches!(self.state, State::OperationEnabled | State::QuickStopActive) {
            self.pp.window_since = None;
            self.pv = ProfileVelocity::default();
            return;
        }
        match self.mode {
            PP => {
                if self.state == State::OperationEnabled
                    && self.braking.is_none()
                    && !self.halted
                    && self.pp.target.is_some()
                    && self.plan_done()
                {
                    if let Some((user, clamped)) = self.pp.buffer.take() {
                        self.pp_start(user, clamped);
                        if self.control & CW_NEW_SETPOINT == 0 {
                            self.pp.ack = false;
                        }
                    }
                }
                let inside = match self.pp.target {
                    Some(t) if self.plan_done() => {
                        let window = self.params.unsigned(P::PositionWindow);
                        (self.actual_raw().round() - t).abs() <= window as f64
                    }
                    _ => false,
                };
                if inside {
                    self.pp.window_since.get_or_insert(self.ticks);
                } else {
                    self.pp.window_since = None;
                }
            }
            PV => {
                let target = if self.halted || self.braking.is_some() {
                    0.0
                } else {
                    self.pv_target()
                };
                let v = self.velocity();
                let window = self.params.unsigned(P::VelocityWindow) as f64;
                if (v as f64 - target).abs() <= window {
                    self.pv.window_since.get_or_insert(self.ticks);
                } else {
                    self.pv.window_since = None;
                }
                let threshold = self.params.unsigned(P::VelocityThreshold);
                if v.unsigned_abs() > threshold {
                    self.pv.over_since.get_or_insert(self.ticks);
                } else {
                    self.pv.over_since = None;
                }
            }
            _ => {}
        }
    }

    // ----- status word -----

    /// Bits 10, 12 and 13 of the mode in effect (Operation enabled).
    fn mode_bits(&self) -> u16 {
        let bit = |on: bool, mask: u16| if on { mask } else { 0 };
        match self.mode {
            PP => {
                bit(self.pp_target_reached(), SW_TARGET_REACHED)
                    | bit(self.pp.ack, SW_OMS12)
                    | bit(self.follow.exceeded, SW_OMS13)
            }
            PV => {
                bit(self.pv_target_reached(), SW_TARGET_REACHED)
                    | bit(self.pv_speed_zero(), SW_OMS12)
            }
            HM => self.homing_bits(),
            CSP => {
                bit(self.halted && self.standstill(), SW_TARGET_REACHED)
                    | bit(self.cyclic_following(), SW_OMS12)
                    | bit(self.follow.exceeded, SW_OMS13)
            }
            CSV | CST => {
                bit(self.halted && self.standstill(), SW_TARGET_REACHED)
                    | bit(self.cyclic_following(), SW_OMS12)
            }
            _ => 0,
        }
    }

    /// The status word 0x6041.
    pub(crate) fn compose_status_word(&self) -> u16 {
        let mut sw = self.state_bits() | SW_REMOTE;
        if self.follow.since.is_some() && !self.follow.exceeded {
            sw |= SW_WARNING;
        }
        match self.state {
            State::OperationEnabled => {
                sw |= self.mode_bits();
                if self.internal_limit() {
                    sw |= SW_INTERNAL_LIMIT;
                }
            }
            // A following-error fault keeps bit 13 until Fault reset.
            State::FaultReactionActive | State::Fault if self.error_code == ERROR_FOLLOWING => {
                sw |= SW_OMS13;
            }
            State::QuickStopActive => {
                sw |= self.mode_bits() & !(SW_TARGET_REACHED | SW_OMS12);
                if self.standstill() {
                    sw |= SW_TARGET_REACHED;
                }
                if self.internal_limit() {
                    sw |= SW_INTERNAL_LIMIT;
                }
            }
            _ => {}
        }
        sw
    }

    /// Status bit 11: a clamped target or an active limit switch.
    fn internal_limit(&self) -> bool {
        let clamped = match self.mode {
            PP => self.pp.clamped,
            CSP => self.cyclic.clamped,
            _ => false,
        };
        let switches = 1 << switches::NEGATIVE_LIMIT | 1 << switches::POSITIVE_LIMIT;
        clamped || self.digital_inputs() & switches != 0
    }
}
