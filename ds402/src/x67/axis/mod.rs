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
//! The parts of the axis, each an `impl Axis` block of its own file:
//! - `state`: the error conditions, the motor identification and the actions of the state machine's
//!   transitions (18.11.4, 18.11.3.13);
//! - [`modes`]: the values of the Mode register and the set-point of each mode (18.11.3.3);
//! - `homing`: modes −127/−128 and the reference registers (18.11.3.3.10, 18.11.3.9);
//! - `limits`: the limit switches and the software limits (18.11.1.16, 18.11.1.17);
//! - `status`: the status word (18.11.3.5, 18.11.4.2);
//! - `cycle`: `begin` and `finish`, which call the others in order;
//! - `config`: [`AxisConfig`], [`SwitchPolarity`] and [`ref_config`] (18.11.1).
//!
//! Rule IDs (`X67-…`) refer to the rule catalogue of the X67SM2436 (`rules/x67.md`). Where the seed is silent
//! the code says which pick it follows; the choices of this model beyond the catalogue are listed in the
//! module documentation of [`crate::x67::module`].

use crate::cia402::{State, StateMachine};
use crate::x67::current::{self, CurrentModel, CurrentState};
use crate::x67::errors::ErrorRegister;
use crate::x67::motor::Motor;
use crate::x67::ramp::{self, Cycle, Ramp, RampState, Target};

mod config;
mod cycle;
mod homing;
mod limits;
pub mod modes;
mod state;
mod status;

pub use config::{ref_config, AxisConfig, SwitchPolarity};
use homing::Homing;

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

/// Status word bit 10: Target reached (X67-18.11.4.2-11, X67-18.11.4.2-12, X67-18.11.4.2-13, X67-18.11.4.2-14,
/// X67-18.11.4.2-15, X67-18.11.4.2-16).
pub const SW_TARGET_REACHED: u16 = 1 << 10;
/// Status word bit 11: Internal limit active (X67-18.11.3.5-03).
pub const SW_INTERNAL_LIMIT: u16 = 1 << 11;
/// Status word bit 12: Set-point acknowledge with the extended control word (X67-18.11.3.5-04).
pub const SW_SETPOINT_ACK: u16 = 1 << 12;

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
    /// Mixed decay is on in this cycle (X67-18.11.1.10-01, X67-18.11.1.10-02, X67-18.11.1.13-02).
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
    /// The axis's own state machine, commanded by its own control word (X67-18.11.4-01).
    sm: StateMachine,
    ramp: Ramp,
    errors: ErrorRegister,
    current: CurrentModel,
    powered: bool,
    /// Energy regenerated into the DC bus this cycle, in J, for the module to take (X67-18.11.4.3-12).
    regenerated_joules: f64,
    ident_left: Option<u32>,
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
            regenerated_joules: 0.0,
            ident_left: None,
            // 0 until a measurement succeeds (X67-18.11.3.7-02).
            motor_identification: 0,
            abr: 0,
            // Both reference registers read 0 before any homing (X67-18.11.3.9-02).
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
    /// (X67-18.11.4.3-16, X67-18.11.4.3-18). The simulation's state trace; no register shows Fault reaction active.
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

    // ----- the cycle -----

    /// A target register value in the ramp's frame. Without software limits the counter may wrap, so the
    /// move goes the wrapping difference target − actual (X67-18.11.1.17-06 pick). With the limits on the
    /// counter cannot overflow, so a target inside them is approached without crossing the wrap
    /// (X67-18.11.1.17-02, X67-18.11.1.17-03); the ramp's frame then holds the register values themselves.
    fn frame(&self, target: i32) -> i64 {
        if self.ramp.bounds().is_some() {
            return i64::from(target);
        }
        let pos = self.ramp.position();
        pos + i64::from(target.wrapping_sub(pos as i32))
    }

    /// Hands the ramp a new set-point when it differs from the one applied; the ramp re-plans from its present
    /// speed and position, so a new target or speed may come before the current action has finished
    /// (X67-18.11.3.3-04).
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

    /// Takes the energy regenerated into the DC bus since the last call, in J (X67-18.11.4.3-12).
    pub(crate) fn take_regenerated(&mut self) -> f64 {
        std::mem::take(&mut self.regenerated_joules)
    }

    /// Speed of the last cycle in microsteps/second.
    fn speed_per_second(&self, cycle: Cycle) -> i64 {
        cycle.per_second(i64::from(self.last.ramp.speed))
    }

    /// Advances the ramp by one cycle; the module moves the motor by the returned state's speed.
    pub(crate) fn step_ramp(&mut self) -> RampState {
        let state = self.ramp.step();
        // The internal counter is 32 bits wide and wraps around (X67-18.11.1.17-06); keep the ramp's frame
        // within the DINT range.
        let pos = self.ramp.position();
        let wrapped = i64::from(pos as i32);
        if wrapped != pos {
            self.ramp.shift(wrapped - pos);
        }
        state
    }
}
