//! One axis of the X67SM2436 in function model "Ramp" (seed 002, 18.11): the CiA 402 state machine, the
//! ramp generator, the error-code register and the current model joined with the modes of the Mode
//! register, limit switches, software limits, homing and the read-back registers.
//!
//! An [`Axis`] is driven by its [`crate::x67::module::Module`], which owns what both axes share (the general
//! configuration, the digital inputs, supply and temperature) and calls, once per ramp-generator cycle,
//! `begin` (take over the cyclic outputs, run the state machine, choose the set-point), then steps the ramp,
//! moves the simulated motor and collects the input edges of the cycle, then `finish` (react to the edges,
//! currents, status word).
//!
//! Rule IDs (`X67-…`) refer to the rule catalogue of the X67SM2436 (`rules/x67.md`). Where the seed is silent
//! the code says which pick it follows; the choices of this model beyond the catalogue are listed in the
//! module documentation of [`crate::x67::module`].

use crate::cia402::{Action, Inputs, State, StateMachine};
use crate::x67::current::{self, CurrentModel, CurrentState, Phase};
use crate::x67::errors::{ErrorCode, ErrorRegister, CW_STALL_DETECTION, CW_WARNING_RESET};
use crate::x67::motor::{self, Motor};
use crate::x67::ramp::{self, Cycle, Ramp, RampState, Target};

/// Control word bit 4: New set-point (extended control word, X67-18.11.3.3.2-03).
pub const CW_NEW_SETPOINT: u16 = 1 << 4;
/// Control word bit 5: Change set immediately (X67-18.11.3.3.2-06).
pub const CW_CHANGE_IMMEDIATELY: u16 = 1 << 5;
/// Control word bit 6: relative set-point (X67-18.11.3.3.2-08).
pub const CW_RELATIVE: u16 = 1 << 6;
/// Control word bit 8: Stop, with the extended control word only (X67-18.11.3.2-02).
pub const CW_STOP: u16 = 1 << 8;
/// Control word bit 11: motor identification on its rising edge (X67-18.11.3.2-05).
pub const CW_MOTOR_ID: u16 = 1 << 11;
/// Control word bit 14: swap the internal and the ABR counter (X67-18.11.3.2-08).
pub const CW_SWAP_COUNTERS: u16 = 1 << 14;

/// Status word bit 10: Target reached (X67-18.11.4.2-11…16).
pub const SW_TARGET_REACHED: u16 = 1 << 10;
/// Status word bit 11: Internal limit active (X67-18.11.3.5-03).
pub const SW_INTERNAL_LIMIT: u16 = 1 << 11;
/// Status word bit 12: Set-point acknowledge with the extended control word (X67-18.11.3.5-04).
pub const SW_SETPOINT_ACK: u16 = 1 << 12;

/// The values of the Mode register (X67-18.11.3.3-01).
pub mod modes {
    /// 0: no mode selected.
    pub const NONE: i8 = 0;
    /// 1: position mode.
    pub const POSITION: i8 = 1;
    /// 2: speed mode.
    pub const SPEED: i8 = 2;
    /// −120: set home position.
    pub const SET_HOME: i8 = -120;
    /// −121: remaining distance mode.
    pub const REMAINING_DISTANCE: i8 = -121;
    /// −122: set actual position.
    pub const SET_POSITION: i8 = -122;
    /// −123: move to the target on a rising edge of the axis's input.
    pub const MOVE_ON_INPUT: i8 = -123;
    /// −124: two-position mode.
    pub const TWO_POSITION: i8 = -124;
    /// −125: move to fixed position A.
    pub const FIXED_A: i8 = -125;
    /// −126: move to fixed position B.
    pub const FIXED_B: i8 = -126;
    /// −127: positive homing.
    pub const HOMING_POSITIVE: i8 = -127;
    /// −128: negative homing.
    pub const HOMING_NEGATIVE: i8 = -128;
}

/// The referencing conditions of RefConfig0n (X67-18.11.1.11).
pub mod ref_config {
    /// Rising edge of DI4.
    pub const DI4_RISING: i8 = -121;
    /// Falling edge of DI4.
    pub const DI4_FALLING: i8 = -122;
    /// Rising edge of the axis's R input (DI3 / DI6); the default.
    pub const R_RISING: i8 = -125;
    /// Falling edge of the axis's R input.
    pub const R_FALLING: i8 = -126;
    /// Homing on stall.
    pub const STALL: i8 = -127;
    /// Immediate homing without motion.
    pub const IMMEDIATE: i8 = -128;
}

/// The configuration registers of one axis (seed 002, 18.11.1), with the bus-controller defaults.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AxisConfig {
    /// ConfigOutput03a/06a: holding current in % of 3 A, 0…167.
    pub holding_current: u8,
    /// ConfigOutput04a/07a: nominal current in %, 0…167.
    pub nominal_current: u8,
    /// ConfigOutput05a/08a: maximum current in %, 0…167.
    pub maximum_current: u8,
    /// StallDetectConfig0n: bits 0–3 mixed-decay threshold, 4–6 stall threshold, 7 motor load in the status
    /// word.
    pub stall_detect_config: u8,
    /// MaxSpeed0npos, microsteps/cycle.
    pub max_speed_pos: u16,
    /// MaxAcc0n, microsteps/cycle².
    pub max_acc: u16,
    /// MaxDec0n, microsteps/cycle².
    pub max_dec: u16,
    /// RevLoop0n, microsteps.
    pub rev_loop: i16,
    /// FixedPos0na, microsteps.
    pub fixed_pos_a: i32,
    /// FixedPos0nb, microsteps.
    pub fixed_pos_b: i32,
    /// RefSpeed0n, microsteps/cycle.
    pub ref_speed: u16,
    /// RefConfig0n: the referencing condition; default −125 (X67-18.11.1.11-06).
    pub ref_config: i8,
    /// FullStepThreshold0n, microsteps/cycle.
    pub full_step_threshold: u16,
    /// StallRecognitionDelay0n, cycles.
    pub stall_recognition_delay: u8,
    /// JoltTime0n, FIFO elements (values above 80 act as 80).
    pub jolt_time: u8,
    /// StallDetectMinSpeed0n, microsteps/cycle.
    pub stall_detect_min_speed: u16,
    /// LimitSwitchConfig0n: bits 0–1 negative switch, 2–3 positive switch, 7 direction monitoring.
    pub limit_switch_config: u8,
    /// PositionLimitMin0n, microsteps.
    pub position_limit_min: i32,
    /// PositionLimitMax0n, microsteps.
    pub position_limit_max: i32,
}

impl Default for AxisConfig {
    fn default() -> Self {
        AxisConfig {
            holding_current: 0,
            nominal_current: 0,
            maximum_current: 0,
            stall_detect_config: 0,
            max_speed_pos: 0,
            max_acc: 0,
            max_dec: 0,
            rev_loop: 0,
            fixed_pos_a: 0,
            fixed_pos_b: 0,
            ref_speed: 0,
            ref_config: ref_config::R_RISING,
            full_step_threshold: 0,
            stall_recognition_delay: 0,
            jolt_time: 0,
            stall_detect_min_speed: 0,
            limit_switch_config: 0,
            position_limit_min: 0,
            position_limit_max: 0,
        }
    }
}

impl AxisConfig {
    /// The stall threshold 0…7 (StallDetectConfig0n bits 4–6, X67-18.11.1.10-03); 0 = off.
    pub const fn stall_threshold(&self) -> u8 {
        (self.stall_detect_config >> 4) & 0x07
    }

    /// The mixed-decay threshold 0…15 (bits 0–3, X67-18.11.1.10-01).
    pub const fn mixed_decay_threshold(&self) -> u8 {
        self.stall_detect_config & 0x0F
    }

    /// Whether the motor load is shown in status-word bits 13–15 (bit 7, X67-18.11.1.10-04).
    pub const fn load_in_status(&self) -> bool {
        self.stall_detect_config & 0x80 != 0
    }

    /// Whether a RefConfig0n value is one of the listed referencing conditions. −120 is listed as "Set home
    /// position" but is no referencing condition; it is handled like the unlisted values (X67-18.11.1.11-04).
    pub const fn is_ref_condition(value: i8) -> bool {
        matches!(value, -121 | -122 | -125 | -126 | -127 | -128)
    }

    /// The software limits when they are on (at least one of Min/Max non-zero, X67-18.11.1.17-01).
    pub const fn software_limits(&self) -> Option<(i32, i32)> {
        if self.position_limit_min != 0 || self.position_limit_max != 0 {
            Some((self.position_limit_min, self.position_limit_max))
        } else {
            None
        }
    }
}

/// A limit switch's configuration: off, active low or active high (X67-18.11.1.16-01/-02).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SwitchPolarity {
    /// 00, and the reserved 10 (the catalogue's pick).
    Off,
    /// 01: active when the input is low.
    ActiveLow,
    /// 11: active when the input is high.
    ActiveHigh,
}

impl SwitchPolarity {
    /// Decodes a two-bit field.
    pub const fn from_bits(bits: u8) -> Self {
        match bits & 0b11 {
            0b01 => SwitchPolarity::ActiveLow,
            0b11 => SwitchPolarity::ActiveHigh,
            _ => SwitchPolarity::Off,
        }
    }

    /// Whether an input level counts as the switch being active.
    pub const fn active(self, level: bool) -> bool {
        match self {
            SwitchPolarity::Off => false,
            SwitchPolarity::ActiveLow => !level,
            SwitchPolarity::ActiveHigh => level,
        }
    }
}

/// A point within a cycle: `num / den` of the way from its start (0) to its end (1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Frac {
    /// Numerator, 0 ≤ num ≤ den.
    pub num: i64,
    /// Denominator, > 0.
    pub den: i64,
}

impl Frac {
    /// The start of the cycle: edges the harness made between two cycles.
    pub const START: Frac = Frac { num: 0, den: 1 };

    /// Interpolates between `a` (at the start of the cycle) and `b` (at its end).
    pub fn lerp(self, a: i64, b: i64) -> i64 {
        let den = self.den.max(1);
        a + ((i128::from(b - a) * i128::from(self.num)) / i128::from(den)) as i64
    }

    /// Orders two points (`self < other`).
    pub fn before(self, other: Frac) -> bool {
        i128::from(self.num) * i128::from(other.den) < i128::from(other.num) * i128::from(self.den)
    }
}

/// A change of a digital input during a cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InputEdge {
    /// The input, 0 = DI1 … 5 = DI6.
    pub input: usize,
    /// The new level.
    pub level: bool,
    /// When in the cycle it changed.
    pub at: Frac,
}

/// What the module hands an axis for one cycle.
#[derive(Clone, Debug)]
pub struct CycleContext {
    /// The ramp-generator cycle.
    pub cycle: Cycle,
    /// GeneralConfig01 bit 0: extended control word (module-wide, X67-18.11.1.15-01 pick).
    pub extended_cw: bool,
    /// The supply voltage is out of its valid band (X67-3-11): condition 0x3000.
    pub supply_error: bool,
    /// The module temperature is over its cut-off (X67-15-01): condition 0x4200.
    pub over_temperature: bool,
    /// The supply voltage in volts (for the motor identification).
    pub supply_volts: f64,
    /// The input levels at the start of the cycle, DI1…DI6, with the harness's changes since the last cycle.
    pub levels: [bool; 6],
    /// The input levels before the harness's changes since the last cycle: where [`CycleContext::edges`]
    /// start from.
    pub levels_before: [bool; 6],
    /// The input changes of the cycle in time order: first those the harness made since the last cycle
    /// (at [`Frac::START`]), then those the motion of the cycle caused.
    pub edges: Vec<InputEdge>,
    /// The inputs of this axis's negative and positive limit switch (0-based).
    pub limit_inputs: [usize; 2],
}

/// What the axis did in the last cycle, for tests and the simulation's trace. No register shows these.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Observation {
    /// The state at the end of the cycle.
    pub state: State,
    /// The ramp output of the cycle (position before the 32-bit wrap; speed = increment of the cycle).
    pub ramp: RampState,
    /// The motor is powered (including the start-up identification in Ready to switch on).
    pub powered: bool,
    /// The current driven, when powered.
    pub current: Option<CurrentState>,
    /// Mixed decay is on in this cycle (X67-18.11.1.10-01/-02, X67-18.11.1.13-02).
    pub mixed_decay: bool,
    /// The load value 0…7 of the stall detection.
    pub load_value: u8,
    /// The start-up motor identification is running.
    pub identifying: bool,
}

/// The mode's choice of set-point for the ramp; compared with the one last applied so that the ramp is only
/// re-planned when it changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Desired {
    Stop,
    /// A target as register value, with or without the reversing loop.
    Position {
        target: i32,
        rev_loop: bool,
    },
    Speed(i32),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum HomingPhase {
    /// Braking a moving axis before homing starts (X67-18.11.3.3.10-02 pick).
    WaitStandstill,
    /// The active level is present at the start: travel against the homing direction until it goes
    /// (X67-18.11.3.3.10-07).
    Leave,
    /// Travel in the homing direction until the condition (X67-18.11.3.3.10-06/-08).
    Seek,
    /// The reference is taken; braking with MaxDec0n.
    Brake,
    /// Homing has ended.
    Done,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Homing {
    dir: i32,
    phase: HomingPhase,
    /// Cycles since the run started (for StallRecognitionDelay0n).
    cycles: u32,
}

/// One axis of the module.
#[derive(Clone, Debug)]
pub struct Axis {
    index: usize,
    /// The configuration registers.
    pub config: AxisConfig,
    /// The simulated motor behind the axis.
    pub motor: Motor,
    // Cyclic outputs as last written by the master.
    abs_pos: i32,
    control: u16,
    mode: i8,
    // Taken over at the cycle.
    cw: u16,
    prev_cw: u16,
    cur_mode: i8,
    last_abs_pos: i32,
    sm: StateMachine,
    ramp: Ramp,
    errors: ErrorRegister,
    current: CurrentModel,
    powered: bool,
    ident_left: Option<u32>,
    ident_done: bool,
    motor_identification: u16,
    /// The ABR counter (16 bit, X67-3-09).
    pub(crate) abr: i16,
    ref_internal: i32,
    ref_abr: i32,
    applied: Desired,
    was_enabled: bool,
    // Extended control word (mode 1 and −121 before the trigger).
    ack: bool,
    active_target: Option<i32>,
    queued: Option<i32>,
    last_setpoint: i32,
    // Mode −121.
    remaining: Option<i32>,
    // Homing.
    homing: Option<Homing>,
    // Mode −120/−122: bit 10 low for the cycle of the set.
    set_pulse: bool,
    // Limit switches.
    limit_hold: bool,
    // Software limits.
    target_out_of_limits: bool,
    limits_misconfigured: bool,
    last: Observation,
    status: u16,
    load_value: u8,
    /// The states entered in the last cycle, in order.
    trace: Vec<State>,
}

impl Axis {
    /// Axis `index` (0 or 1) just after power-up: every register at its default, Not ready to switch on.
    pub fn new(index: usize) -> Self {
        let config = AxisConfig::default();
        let ramp = Ramp::new(ramp::Config::default());
        let last = Observation {
            state: State::NotReadyToSwitchOn,
            ramp: RampState {
                standstill: true,
                ..RampState::default()
            },
            powered: false,
            current: None,
            mixed_decay: true,
            load_value: 0,
            identifying: false,
        };
        Axis {
            index,
            config,
            motor: Motor::default(),
            abs_pos: 0,
            control: 0,
            mode: 0,
            cw: 0,
            prev_cw: 0,
            cur_mode: 0,
            last_abs_pos: 0,
            sm: StateMachine::new(),
            ramp,
            errors: ErrorRegister::new(),
            current: CurrentModel::new(current::Config::default())
                .unwrap_or_else(|_| unreachable!()),
            powered: false,
            ident_left: None,
            ident_done: false,
            motor_identification: 0,
            abr: 0,
            ref_internal: 0,
            ref_abr: 0,
            applied: Desired::Stop,
            was_enabled: false,
            ack: false,
            active_target: None,
            queued: None,
            last_setpoint: 0,
            remaining: None,
            homing: None,
            set_pulse: false,
            limit_hold: false,
            target_out_of_limits: false,
            limits_misconfigured: false,
            last,
            status: crate::cia402::status_word(State::NotReadyToSwitchOn, 0),
            load_value: 0,
            trace: Vec::new(),
        }
    }

    /// The axis's R input, DI3 for axis 1 and DI6 for axis 2 (0-based: 2 and 5; X67-8.2-01).
    const fn r_input(&self) -> usize {
        if self.index == 0 {
            2
        } else {
            5
        }
    }

    /// The axis index (0 = axis 1).
    pub const fn index(&self) -> usize {
        self.index
    }

    // ----- cyclic outputs (written by the master, taken over at the next cycle) -----

    /// Writes AbsPos0n.
    pub fn set_abs_pos(&mut self, value: i32) {
        self.abs_pos = value;
    }

    /// Writes MpGenControl0n.
    pub fn set_control(&mut self, value: u16) {
        self.control = value;
    }

    /// Writes MpGenMode0n.
    pub fn set_mode(&mut self, value: i8) {
        self.mode = value;
    }

    /// AbsPos0n as last written.
    pub const fn abs_pos(&self) -> i32 {
        self.abs_pos
    }

    // ----- registers the axis shows -----

    /// The internal counter before the 32-bit wrap (the ramp's frame).
    pub(crate) fn ramp_position(&self) -> i64 {
        self.ramp.position()
    }

    /// The internal counter as a DINT (X67-18.6.3.3-03).
    pub fn internal_counter(&self) -> i32 {
        self.ramp.position() as i32
    }

    /// The ABR counter sign-extended to a DINT (X67-3-09).
    pub const fn abr_counter(&self) -> i32 {
        self.abr as i32
    }

    fn swapped(&self) -> bool {
        self.cw & CW_SWAP_COUNTERS != 0
    }

    /// AbsPos0nActVal: the internal counter, or the ABR counter with control bit 14 (X67-18.11.3.4-01).
    pub fn act_val(&self) -> i32 {
        if self.swapped() {
            self.abr_counter()
        } else {
            self.internal_counter()
        }
    }

    /// AbsPos0nActValAcyclic: the other counter (X67-18.11.3.10-01).
    pub fn act_val_acyclic(&self) -> i32 {
        if self.swapped() {
            self.internal_counter()
        } else {
            self.abr_counter()
        }
    }

    /// RefPos0nCyclicCounter: the reference of the counter shown cyclically (X67-18.11.3.9-01).
    pub const fn ref_pos_cyclic(&self) -> i32 {
        if self.cw & CW_SWAP_COUNTERS != 0 {
            self.ref_abr
        } else {
            self.ref_internal
        }
    }

    /// RefPos0nAcyclicCounter: the reference of the other counter (X67-18.11.3.9-01).
    pub const fn ref_pos_acyclic(&self) -> i32 {
        if self.cw & CW_SWAP_COUNTERS != 0 {
            self.ref_internal
        } else {
            self.ref_abr
        }
    }

    /// MpGenStatus0n as sent after the last cycle.
    pub const fn status_word(&self) -> u16 {
        self.status
    }

    /// ControlReadback0n: the last control word received (X67-18.11.3.11-01).
    pub const fn control_readback(&self) -> u16 {
        self.control
    }

    /// ModeReadback0n: the last mode received (X67-18.11.3.12-01).
    pub const fn mode_readback(&self) -> i8 {
        self.mode
    }

    /// ErrorCode0n (X67-18.11.3.13).
    pub fn error_code(&self) -> u16 {
        self.errors.register()
    }

    /// The error-code register with its conditions and latches.
    pub const fn errors(&self) -> &ErrorRegister {
        &self.errors
    }

    /// Motoridentification0n (X67-18.11.3.7).
    pub const fn motor_identification(&self) -> u16 {
        self.motor_identification
    }

    /// The state of the state machine.
    pub const fn state(&self) -> State {
        self.sm.state
    }

    /// Every state the state machine entered in the last cycle, in order; empty when the state did not change.
    /// An Error shows Fault reaction active and then Fault, as that state is left in the same cycle
    /// (X67-18.11.4.3-16/-18). The simulation's state trace; no register shows Fault reaction active.
    pub fn state_trace(&self) -> &[State] {
        &self.trace
    }

    /// What happened in the last cycle.
    pub const fn observation(&self) -> &Observation {
        &self.last
    }

    /// The phase current amplitude in mA driven in the last cycle (0 when the motor is not powered).
    pub fn phase_current_ma(&self) -> u32 {
        self.last.current.map_or(0, |c| c.amps_milli)
    }

    /// Writes the current registers through the current model; a value above 167 % is refused and changes
    /// nothing (X67-18.11.1.1-01 pick).
    pub(crate) fn set_currents(
        &mut self,
        holding: u8,
        nominal: u8,
        maximum: u8,
    ) -> Result<(), current::ConfigError> {
        let cfg = current::Config {
            holding,
            nominal,
            maximum,
            ..*self.current.config()
        };
        cfg.validate()?;
        self.config.holding_current = holding;
        self.config.nominal_current = nominal;
        self.config.maximum_current = maximum;
        Ok(())
    }

    // ----- the cycle -----

    /// A target register value in the ramp's frame. Without software limits the counter may wrap, so the
    /// move goes the wrapping difference target − actual (X67-18.11.1.17-06 pick). With the limits on the
    /// counter cannot overflow, so a target inside them is approached without crossing the wrap
    /// (X67-18.11.1.17-02/-03); the ramp's frame then holds the register values themselves.
    fn frame(&self, target: i32) -> i64 {
        if self.ramp.bounds().is_some() {
            return i64::from(target);
        }
        let pos = self.ramp.position();
        pos + i64::from(target.wrapping_sub(pos as i32))
    }

    fn apply(&mut self, desired: Desired) {
        if desired == self.applied {
            return;
        }
        let target = match desired {
            Desired::Stop => Target::Stop,
            Desired::Position { target, .. } => Target::Position(self.frame(target)),
            Desired::Speed(s) => Target::Speed(s),
        };
        self.ramp.set_target(target);
        self.applied = desired;
    }

    fn stop_now(&mut self) {
        self.ramp.stop_now();
        self.applied = Desired::Stop;
    }

    fn ramp_config(&self, cycle: Cycle, rev_loop: bool) -> ramp::Config {
        ramp::Config {
            cycle,
            max_speed_pos: self.config.max_speed_pos,
            max_acc: self.config.max_acc,
            max_dec: self.config.max_dec,
            jolt_time: self.config.jolt_time,
            rev_loop: if rev_loop { self.config.rev_loop } else { 0 },
        }
    }

    /// Speed of the last cycle in microsteps/second.
    fn speed_per_second(&self, cycle: Cycle) -> i64 {
        cycle.per_second(i64::from(self.last.ramp.speed))
    }

    /// The stall condition of this cycle (X67-18.6.1.1-02, X67-18.11.1.13-01): threshold on, control bit 15,
    /// speed above StallDetectMinSpeed0n and a load value below the threshold.
    fn stall_condition(&self, load_value: u8) -> bool {
        let threshold = self.config.stall_threshold();
        threshold != 0
            && self.cw & CW_STALL_DETECTION != 0
            && self.last.ramp.speed.unsigned_abs() > u32::from(self.config.stall_detect_min_speed)
            && load_value < threshold
    }

    fn store_reference(&mut self, internal: i64, abr: i32) {
        self.ref_internal = internal as i32;
        self.ref_abr = abr;
    }

    /// The commanded direction: the set-point's sign while it moves, else the direction of the desired
    /// set-point.
    fn commanded_direction(&self, desired: Desired) -> i64 {
        let sp = self.ramp.setpoint_speed();
        if sp != 0 {
            return sp.signum();
        }
        match desired {
            Desired::Stop => 0,
            Desired::Speed(s) => i64::from(s.signum()),
            Desired::Position { target, .. } => {
                i64::from(target.wrapping_sub(self.internal_counter()).signum())
            }
        }
    }

    /// The start of a cycle: take over the cyclic outputs, sample the error conditions, run the state machine
    /// and choose the ramp's set-point.
    pub(crate) fn begin(&mut self, ctx: &CycleContext) {
        // Cyclic outputs are taken over once per cycle (X67-18.14-02 pick).
        self.prev_cw = self.cw;
        self.cw = self.control;
        let prev_mode = self.cur_mode;
        self.cur_mode = self.mode;
        let rising = self.cw & !self.prev_cw;

        // Errors and warnings: detection bits and Warning reset (↑ bit 12).
        self.errors.control_word(self.cw);
        self.errors
            .set_condition(ErrorCode::Voltage, ctx.supply_error);
        self.errors.set_condition(
            ErrorCode::Overtemperature,
            ctx.over_temperature || self.motor.faults.output_stage_overtemperature,
        );
        let powered = self.powered || self.ident_left.is_some();
        let speed_ps = self.speed_per_second(ctx.cycle);
        let faults = self.motor.faults;
        self.errors
            .set_condition(ErrorCode::OpenCircuit, powered && faults.open_winding);
        self.errors.set_condition(
            ErrorCode::CurrentError,
            powered && (faults.open_winding || self.motor.back_emf_exceeded(speed_ps)),
        );
        self.errors
            .set_condition(ErrorCode::Overcurrent, powered && faults.short);
        self.load_value = self.motor.load_value(speed_ps);
        let stall = powered && self.stall_condition(self.load_value);
        self.errors.set_condition(ErrorCode::Stall, stall);
        // The Warning reset of this cycle acknowledges against the conditions of this cycle: the reset in
        // `control_word` above saw those of the last cycle and latched again a warning whose cause has gone
        // since (X67-18.11.3.2-06, X67-18.11.4.1-10).
        if rising & CW_WARNING_RESET != 0 {
            self.errors.warning_reset();
        }

        // The start-up identification (X67-18.11.4.3-07): 1.0 s of cycles.
        let mut identification_done = false;
        if let Some(left) = self.ident_left {
            if left <= 1 {
                self.ident_left = None;
                identification_done = true;
                self.measure_identification(ctx.supply_volts);
            } else {
                self.ident_left = Some(left - 1);
            }
        }

        // The state machine.
        let inputs = Inputs {
            error_pending: self.errors.has_error(),
            standstill: self.ramp.standstill(),
            identification_done,
            extra_status: 0,
        };
        let out = self.sm.step(self.cw, &inputs);
        self.trace = out.trace;
        for action in out.actions {
            match action {
                Action::VoltageOn => self.powered = true,
                Action::VoltageOff => {
                    self.powered = false;
                    self.ident_left = None;
                    self.stop_now();
                    // No current flows any more, so there is no stronger level left to hold for 100 ms: the
                    // next Switch on starts with the holding current (X67-18.11.4.3-06).
                    self.current = CurrentModel::new(*self.current.config())
                        .unwrap_or_else(|_| unreachable!());
                }
                Action::StartIdentification => {
                    self.ident_left = Some(1000u32.div_ceil(ctx.cycle.millis()));
                }
                Action::Decelerate { .. } | Action::EnableMotion => {}
                Action::ClearErrors => self.errors.fault_reset(),
            }
        }
        self.ident_done |= identification_done;

        // Motor identification on ↑ control bit 11 (X67-18.11.3.2-05, X67-18.11.3.7-04): at standstill, motor
        // powered, half-step position; otherwise nothing happens (the catalogue's pick).
        if rising & CW_MOTOR_ID != 0
            && self.powered
            && self.ramp.standstill()
            && self.ramp.position().rem_euclid(1024) == 0
        {
            self.measure_identification(ctx.supply_volts);
        }

        // Limit-switch hold ends with the acknowledgement of its warning (X67-18.11.1.16-05).
        if self.limit_hold
            && !self.errors.is_latched(ErrorCode::NegativeLimitSwitch)
            && !self.errors.is_latched(ErrorCode::PositiveLimitSwitch)
        {
            self.limit_hold = false;
        }

        // Mode 0 re-arms the remaining-distance mode (X67-18.11.3.3.5-03).
        if self.cur_mode == modes::NONE {
            self.remaining = None;
        }

        let enabled = self.sm.state == State::OperationEnabled;
        let entered = enabled && (!self.was_enabled || self.cur_mode != prev_mode);
        if !enabled && self.was_enabled {
            // Leaving Operation enable ends a homing run; the mode's set-point is kept, so that Enable operation
            // from Quick stop active resumes the motion (X67-18.11.4.3-15).
            self.homing = None;
        }
        if self.cur_mode != prev_mode {
            // A set-point of one mode is not carried into another: after a mode change the position modes
            // wait for their own set-point (the relative base of X67-18.11.3.3.2-09 is kept).
            self.active_target = None;
            self.queued = None;
            if !is_homing(self.cur_mode) {
                self.homing = None;
            }
        }
        self.was_enabled = enabled;
        self.set_pulse = false;

        let rev_loop_mode = matches!(self.cur_mode, 1 | -123 | -124 | -125 | -126);
        self.ramp
            .set_config(self.ramp_config(ctx.cycle, rev_loop_mode));

        let mut desired = if enabled {
            self.mode_setpoint(ctx, entered, rising)
        } else {
            Desired::Stop
        };
        self.last_abs_pos = self.abs_pos;

        // Software limits (X67-18.11.1.17).
        self.target_out_of_limits = false;
        self.limits_misconfigured = false;
        match self.config.software_limits() {
            Some((min, max)) if min > max => {
                self.limits_misconfigured = true;
                self.ramp.set_bounds(None);
                desired = Desired::Stop;
            }
            Some((min, max)) => {
                self.ramp.set_bounds(Some((i64::from(min), i64::from(max))));
                if let Desired::Position { target, .. } = desired {
                    if target < min || target > max {
                        self.target_out_of_limits = true;
                        desired = Desired::Stop;
                    }
                }
            }
            None => self.ramp.set_bounds(None),
        }

        // Limit switches with direction monitoring refuse a movement toward an active switch
        // (X67-18.11.1.16-07/-08).
        if self.config.limit_switch_config & 0x80 != 0 {
            let dir = self.commanded_direction(desired);
            for (k, code, sign) in LIMIT_SWITCHES {
                let pol = SwitchPolarity::from_bits(self.config.limit_switch_config >> (2 * k));
                if dir == sign && pol.active(ctx.levels[ctx.limit_inputs[k]]) {
                    self.trigger_limit(code);
                }
            }
        }
        if self.limit_hold {
            desired = Desired::Stop;
        }

        // The Stop bit of the extended control word brakes in every mode (X67-18.11.3.2-02).
        if ctx.extended_cw && self.cw & CW_STOP != 0 {
            desired = Desired::Stop;
        }
        self.apply(desired);
    }

    fn trigger_limit(&mut self, code: ErrorCode) {
        self.errors.raise(code);
        self.errors.clear_condition(code);
        self.limit_hold = true;
    }

    fn measure_identification(&mut self, supply_volts: f64) {
        let nominal_ma =
            u32::from(self.config.nominal_current) * current::MODULE_NOMINAL_MILLIAMPS / 100;
        if let Some(v) = motor::identification_us(
            &self.motor.params,
            self.motor.faults.open_winding,
            supply_volts,
            nominal_ma,
        ) {
            self.motor_identification = v;
        }
    }

    /// The set-point of the selected mode in Operation enable.
    fn mode_setpoint(&mut self, ctx: &CycleContext, entered: bool, rising: u16) -> Desired {
        let r_input = self.r_input();
        let abs_changed = self.abs_pos != self.last_abs_pos;
        match self.cur_mode {
            modes::POSITION => self.position_mode(ctx.extended_cw, rising, true),
            modes::SPEED => Desired::Speed(
                self.abs_pos
                    .clamp(-ramp::MAX_SPEED_SETPOINT, ramp::MAX_SPEED_SETPOINT),
            ),
            modes::SET_HOME => {
                if entered || abs_changed {
                    // new actual = old actual + (AbsPos0n − reference); the reference becomes AbsPos0n
                    // (X67-18.11.3.3.4-01).
                    let delta = self.abs_pos.wrapping_sub(self.ref_internal);
                    self.ramp.shift(i64::from(delta));
                    self.ref_internal = self.abs_pos;
                    self.set_pulse = true;
                }
                Desired::Stop
            }
            modes::SET_POSITION => {
                if entered || abs_changed {
                    let delta = self.abs_pos.wrapping_sub(self.internal_counter());
                    self.ramp.shift(i64::from(delta));
                    self.set_pulse = true;
                }
                Desired::Stop
            }
            modes::REMAINING_DISTANCE => match self.remaining {
                Some(target) => Desired::Position {
                    target,
                    rev_loop: false,
                },
                None => self.position_mode(ctx.extended_cw, rising, false),
            },
            modes::MOVE_ON_INPUT => match self.active_target {
                Some(target) => Desired::Position {
                    target,
                    rev_loop: true,
                },
                None => Desired::Stop,
            },
            modes::TWO_POSITION => Desired::Position {
                target: if ctx.levels[r_input] {
                    self.config.fixed_pos_a
                } else {
                    self.config.fixed_pos_b
                },
                rev_loop: true,
            },
            modes::FIXED_A => Desired::Position {
                target: self.config.fixed_pos_a,
                rev_loop: true,
            },
            modes::FIXED_B => Desired::Position {
                target: self.config.fixed_pos_b,
                rev_loop: true,
            },
            modes::HOMING_POSITIVE | modes::HOMING_NEGATIVE => self.homing_setpoint(ctx, entered),
            _ => Desired::Stop,
        }
    }

    /// Mode 1 (and mode −121 before its trigger): AbsPos0n directly, or through the New-set-point handshake
    /// with the extended control word (X67-18.11.3.3.1, X67-18.11.3.3.2).
    fn position_mode(&mut self, extended: bool, rising: u16, rev_loop: bool) -> Desired {
        if !extended {
            self.ack = false;
            return Desired::Position {
                target: self.abs_pos,
                rev_loop,
            };
        }
        if rising & CW_NEW_SETPOINT != 0 && !self.ack {
            // Bits 5 and 6 are sampled with the set-point (X67-18.11.3.3.2-03 pick).
            let target = if self.cw & CW_RELATIVE != 0 {
                self.last_setpoint.wrapping_add(self.abs_pos)
            } else {
                self.abs_pos
            };
            self.last_setpoint = target;
            self.ack = true;
            let idle = self.active_target.is_none() || self.last.ramp.target_reached;
            if self.cw & CW_CHANGE_IMMEDIATELY != 0 || idle {
                self.active_target = Some(target);
                self.queued = None;
            } else {
                self.queued = Some(target);
            }
        }
        if self.cw & CW_NEW_SETPOINT == 0 && self.queued.is_none() {
            self.ack = false;
        }
        match self.active_target {
            Some(target) => Desired::Position { target, rev_loop },
            None => Desired::Stop,
        }
    }

    fn homing_setpoint(&mut self, ctx: &CycleContext, entered: bool) -> Desired {
        let dir = if self.cur_mode == modes::HOMING_POSITIVE {
            1
        } else {
            -1
        };
        // A run starts when the homing mode is selected in Operation enable or Operation enable is reached
        // with it selected; a finished run is not repeated while the mode stays (a choice of this model).
        if entered || self.homing.is_none() {
            self.homing = Some(Homing {
                dir,
                phase: HomingPhase::WaitStandstill,
                cycles: 0,
            });
        }
        let Some(mut h) = self.homing else {
            return Desired::Stop;
        };
        let speed = i32::from(self.config.ref_speed);
        let rc = self.config.ref_config;
        if h.phase == HomingPhase::WaitStandstill && self.ramp.standstill() {
            h.cycles = 0;
            h.phase = match rc {
                ref_config::IMMEDIATE => {
                    // Immediate referencing: store both counters at once, no motion (X67-18.11.3.3.10-10).
                    self.store_reference(self.ramp.position(), self.abr_counter());
                    HomingPhase::Done
                }
                ref_config::STALL => HomingPhase::Seek,
                _ => {
                    let (input, active_high) = self.ref_input(rc);
                    if ctx.levels[input] == active_high {
                        HomingPhase::Leave
                    } else {
                        HomingPhase::Seek
                    }
                }
            };
        }
        let desired = match h.phase {
            HomingPhase::WaitStandstill | HomingPhase::Brake | HomingPhase::Done => Desired::Stop,
            HomingPhase::Leave => Desired::Speed(-dir * speed),
            HomingPhase::Seek => {
                // Homing on stall: the reference is the counter at the stall and the motor stops abruptly
                // (X67-18.11.3.3.10-08/-09).
                if rc == ref_config::STALL
                    && h.cycles >= u32::from(self.config.stall_recognition_delay)
                    && self.powered
                    && self.stall_condition(self.load_value)
                {
                    self.store_reference(self.ramp.position(), self.abr_counter());
                    self.stop_now();
                    h.phase = HomingPhase::Done;
                    Desired::Stop
                } else {
                    Desired::Speed(dir * speed)
                }
            }
        };
        if matches!(h.phase, HomingPhase::Leave | HomingPhase::Seek) {
            h.cycles += 1;
        }
        self.homing = Some(h);
        desired
    }

    /// The input and the active level of an input referencing condition (X67-18.11.1.11-01/-02).
    fn ref_input(&self, rc: i8) -> (usize, bool) {
        let r_input = self.r_input();
        match rc {
            ref_config::DI4_RISING => (3, true),
            ref_config::DI4_FALLING => (3, false),
            ref_config::R_FALLING => (r_input, false),
            _ => (r_input, true),
        }
    }

    /// The trigger edge of mode −121: falling for RefConfig0n −122/−126, rising otherwise, on DI3/DI6
    /// (X67-18.11.3.3.5-05 pick).
    fn remaining_trigger_rising(&self) -> bool {
        !matches!(
            self.config.ref_config,
            ref_config::DI4_FALLING | ref_config::R_FALLING
        )
    }

    /// Advances the ramp by one cycle; the module moves the motor by the returned state's speed.
    pub(crate) fn step_ramp(&mut self) -> RampState {
        let state = self.ramp.step();
        // The internal counter is 32 bits wide and wraps around (X67-18.11.1.17-06); keep the ramp's frame
        // within the DINT range.
        let pos = self.ramp.position();
        if pos > i64::from(i32::MAX) {
            self.ramp.shift(-(1i64 << 32));
        } else if pos < i64::from(i32::MIN) {
            self.ramp.shift(1i64 << 32);
        }
        state
    }

    /// The end of a cycle: react to the input edges of the cycle, drive the current and build the status
    /// word. `start` is the internal counter at the start of the cycle and `abr_start` the ABR counter.
    pub(crate) fn finish(
        &mut self,
        ctx: &CycleContext,
        ramp_state: RampState,
        start: i64,
        abr_start: i32,
    ) {
        let end = start + i64::from(ramp_state.speed);
        // The rotor path of the cycle: the ABR counter at an edge is the encoder's count at the rotor position
        // of that instant, not an interpolation between the counts at the cycle's ends.
        let rotor_end = self.motor.rotor();
        let rotor_start = rotor_end - self.motor.rotor_delta(i64::from(ramp_state.speed));
        let enabled = self.sm.state == State::OperationEnabled;
        let r_input = self.r_input();
        let mut levels = ctx.levels_before;
        let mut reached = ramp_state.target_reached;
        for edge in &ctx.edges {
            let was = levels[edge.input];
            levels[edge.input] = edge.level;
            if was == edge.level {
                continue;
            }
            let at_internal = edge.at.lerp(start, end);
            let counted = self
                .motor
                .encoder_phase(edge.at.lerp(rotor_start, rotor_end))
                - self.motor.encoder_phase(rotor_start);
            let at_abr = i32::from((abr_start as i16).wrapping_add(counted as i16));
            // Limit switches: the active edge triggers (X67-18.11.1.16-04); with direction monitoring only in
            // the commanded direction (X67-18.11.1.16-07).
            for (k, code, sign) in LIMIT_SWITCHES {
                if edge.input != ctx.limit_inputs[k] {
                    continue;
                }
                let pol = SwitchPolarity::from_bits(self.config.limit_switch_config >> (2 * k));
                if !pol.active(edge.level) {
                    continue;
                }
                let monitoring = self.config.limit_switch_config & 0x80 != 0;
                let dir = self.ramp.setpoint_speed().signum();
                if !monitoring || dir == sign {
                    self.trigger_limit(code);
                    self.apply(Desired::Stop);
                }
            }
            if !enabled {
                continue;
            }
            match self.cur_mode {
                modes::REMAINING_DISTANCE
                    if self.remaining.is_none()
                        && edge.input == r_input
                        && edge.level == self.remaining_trigger_rising() =>
                {
                    // The new target is the actual position at the edge plus FixedPos0na
                    // (X67-18.11.3.3.5-02).
                    let target = (at_internal as i32).wrapping_add(self.config.fixed_pos_a);
                    self.remaining = Some(target);
                    reached = false;
                }
                modes::MOVE_ON_INPUT if edge.input == r_input && edge.level => {
                    // The target is taken now: the ramp has it from here on, so bit 10 drops in this cycle
                    // (X67-18.11.3.3.7-01, X67-18.11.4.2-11).
                    self.active_target = Some(self.abs_pos);
                    self.apply(Desired::Position {
                        target: self.abs_pos,
                        rev_loop: true,
                    });
                    reached = false;
                }
                modes::HOMING_POSITIVE | modes::HOMING_NEGATIVE => {
                    let rc = self.config.ref_config;
                    if let Some(mut h) = self.homing {
                        if rc != ref_config::STALL && rc != ref_config::IMMEDIATE {
                            let (input, active_high) = self.ref_input(rc);
                            if edge.input == input {
                                if h.phase == HomingPhase::Leave && edge.level != active_high {
                                    h.phase = HomingPhase::Seek;
                                } else if h.phase == HomingPhase::Seek && edge.level == active_high
                                {
                                    // The counters at the edge are the referenced zero positions
                                    // (X67-18.11.3.3.10-04).
                                    self.store_reference(at_internal, at_abr);
                                    h.phase = HomingPhase::Brake;
                                    self.apply(Desired::Stop);
                                }
                            }
                        }
                        self.homing = Some(h);
                    }
                }
                _ => {}
            }
        }
        if let Some(mut h) = self.homing {
            if h.phase == HomingPhase::Brake && self.ramp.standstill() {
                h.phase = HomingPhase::Done;
                self.homing = Some(h);
            }
        }
        // A queued single set-point starts once the current move has arrived (X67-18.11.3.3.2-05).
        if ramp_state.target_reached {
            if let Some(q) = self.queued.take() {
                self.active_target = Some(q);
            }
        }

        // Currents (X67-18.11.1.1, X67-18.11.1.2).
        let identifying = self.ident_left.is_some();
        let stall_homing = is_homing(self.cur_mode)
            && self.config.ref_config == ref_config::STALL
            && self.homing.is_some();
        let cfg = current::Config {
            holding: self.config.holding_current,
            nominal: self.config.nominal_current,
            maximum: self.config.maximum_current,
            full_step_threshold: self.config.full_step_threshold,
            stall_homing,
        };
        let _ = self.current.set_config(cfg);
        let current = if self.powered {
            Some(self.current.step(
                Phase::from_ramp(&ramp_state),
                ramp_state.speed,
                ctx.cycle.millis(),
            ))
        } else if identifying {
            let percent = self.config.nominal_current;
            Some(CurrentState {
                level: current::Level::Nominal,
                percent,
                amps_milli: u32::from(percent) * current::MODULE_NOMINAL_MILLIAMPS / 100,
                full_step: false,
            })
        } else {
            None
        };

        // Mixed decay (X67-18.11.1.10-01/-02, X67-18.11.1.13-02): always on at or below the minimum stall
        // speed; above it 0 = off, 15 = on, 1…14 = on below 64·threshold microsteps/cycle.
        let speed = ramp_state.speed.unsigned_abs();
        let threshold = self.config.mixed_decay_threshold();
        let mixed_decay = if speed <= u32::from(self.config.stall_detect_min_speed) {
            true
        } else {
            match threshold {
                0 => false,
                15 => true,
                t => speed < 64 * u32::from(t),
            }
        };

        self.last = Observation {
            state: self.sm.state,
            ramp: ramp_state,
            powered: self.powered || identifying,
            current,
            mixed_decay,
            load_value: self.load_value,
            identifying,
        };
        self.status = self.build_status(ctx, ramp_state, reached);
    }

    /// The status word: the state bits from the state machine plus bits 7 and 10–15 (X67-18.11.3.5).
    fn build_status(&self, ctx: &CycleContext, rs: RampState, reached: bool) -> u16 {
        let mut extra = 0;
        if self.errors.has_warning() {
            extra |= crate::cia402::SW_WARNING;
        }
        if self.target_reached_bit(ctx, rs, reached) {
            extra |= SW_TARGET_REACHED;
        }
        if self.limits_misconfigured || self.target_out_of_limits || rs.limited {
            extra |= SW_INTERNAL_LIMIT;
        }
        let ext_position = ctx.extended_cw
            && (self.cur_mode == modes::POSITION
                || self.cur_mode == modes::REMAINING_DISTANCE && self.remaining.is_none());
        if ext_position && self.ack {
            extra |= SW_SETPOINT_ACK;
        }
        if self.config.load_in_status() {
            extra |= u16::from(self.load_value & 0x07) << 13;
        }
        self.sm.status_word(extra)
    }

    /// Status-word bit 10 (X67-18.11.4.2-11…16, X67-18.11.3.3-03).
    fn target_reached_bit(&self, ctx: &CycleContext, rs: RampState, reached: bool) -> bool {
        let standstill = rs.standstill;
        if self.sm.state != State::OperationEnabled {
            return standstill;
        }
        if ctx.extended_cw && self.cw & CW_STOP != 0 {
            return standstill;
        }
        if self.limit_hold || self.target_out_of_limits || self.limits_misconfigured {
            return standstill;
        }
        match self.cur_mode {
            modes::POSITION
            | modes::MOVE_ON_INPUT
            | modes::TWO_POSITION
            | modes::FIXED_A
            | modes::FIXED_B => match self.applied {
                Desired::Position { .. } => reached,
                _ => standstill,
            },
            modes::REMAINING_DISTANCE => self.remaining.is_some() && reached,
            modes::SPEED => {
                let s = self
                    .abs_pos
                    .clamp(-ramp::MAX_SPEED_SETPOINT, ramp::MAX_SPEED_SETPOINT);
                rs.speed == s && self.ramp.setpoint_speed() == i64::from(s)
            }
            modes::SET_HOME | modes::SET_POSITION => !self.set_pulse,
            modes::HOMING_POSITIVE | modes::HOMING_NEGATIVE => {
                matches!(
                    self.homing,
                    Some(Homing {
                        phase: HomingPhase::Done,
                        ..
                    })
                ) && standstill
            }
            _ => standstill,
        }
    }
}

/// The two limit switches: index in [`CycleContext::limit_inputs`] and bit pair of LimitSwitchConfig0n, warning
/// code, and the direction of motion toward the switch.
const LIMIT_SWITCHES: [(usize, ErrorCode, i64); 2] = [
    (0, ErrorCode::NegativeLimitSwitch, -1),
    (1, ErrorCode::PositiveLimitSwitch, 1),
];

const fn is_homing(mode: i8) -> bool {
    matches!(mode, modes::HOMING_POSITIVE | modes::HOMING_NEGATIVE)
}
