//! The X67SM2436 module in function model "Ramp" behind a CANopen bus controller: two [`Axis`] models, what
//! they share (GeneralConfig01, the six digital inputs, the supply voltage and the module temperature), the
//! register access of table 18.5 and the simulation harness (motors, encoders, cam switches, faults).
//!
//! A pure, deterministic model on a simulated clock: [`Module::step`] runs one ramp-generator cycle of both
//! axes. The master writes the cyclic outputs ([`Module::write`] or the `set_*` shortcuts) at any time; the
//! module takes them over once per cycle (X67-18.14-02 pick).
//!
//! # Methods and polling order
//!
//! On a real clock the host calls [`Module::start`] at power-on, then [`Module::handle_timeout`] whenever
//! [`Module::poll_timeout`] has passed: it runs every cycle due by then, each of the length GeneralConfig01
//! selects at that cycle (the model derives its time step itself). Register access ([`Module::read`],
//! [`Module::write`]) and the harness may come between any two calls; [`Module::take_diagnostics`] drains
//! what the cycles noted. [`Module::step`], [`Module::run`] and [`Module::run_ms`] run cycles without a
//! clock (tests, simulations that count cycles).
//!
//! ```
//! use ds402::x67::module::Module;
//! use ds402::x67::registers::{AxisReg, Register};
//!
//! let mut m = Module::new();
//! for (name, value) in [("MaxSpeed01pos", 100), ("MaxAcc01", 10), ("MaxDec01", 10), ("MpGenMode01", 1)] {
//!     m.write(Register::from_name(name).unwrap(), value).unwrap();
//! }
//! m.step(); // Not ready to switch on → Switch on disabled
//! m.set_control(0, 0x0006);
//! m.step();
//! m.set_control(0, 0x0007);
//! m.run_ms(1050); // the first Switch on runs the 1 s motor identification
//! m.set_control(0, 0x000F);
//! m.set_abs_pos(0, 5000);
//! m.run(200);
//! assert_eq!(m.read(Register::Axis(0, AxisReg::ActVal)), 5000);
//! assert_eq!(m.status_word(0) & 0x047F, 0x0437); // Operation enable, target reached
//! ```
//!
//! # Choices of this model beyond the catalogue
//!
//! - **Inputs.** Each input is either a level the harness sets ([`Module::set_input`], [`Module::pulse_input`])
//!   or a [`Cam`]: a switch fixed to the rotor of an axis that is active over a range of rotor positions. The
//!   module sees every edge, however short (X67-3-07): harness edges act at the next cycle at the counter
//!   values of the cycle start, cam edges at the exact rotor position where they happen within the cycle.
//! - **Limit-switch inputs.** The seed does not say which inputs are the limit switches. Default: DI1
//!   negative and DI2 positive for axis 1, DI4 negative and DI5 positive for axis 2
//!   ([`Module::set_limit_inputs`] changes it). These are also the A/B inputs of the encoders, so an axis with
//!   an encoder on its shaft should not use limit switches there.
//! - **Encoders.** An encoder on the shaft ([`crate::x67::motor::Motor::encoder_lines`]) drives the A/B inputs of
//!   its axis's group and the ABR counter (4x, A leading B counts up). Setting DI1/DI2 (DI4/DI5) by hand is
//!   decoded the same way, so a harness can also feed quadrature directly.
//! - **Holding a limit switch.** After a limit switch has stopped the axis, motion stays stopped until its
//!   warning is acknowledged (↑ control bit 12 or 7); the mode's set-point is then followed again.
//! - **Target reached** (bit 10) outside Operation enable, in mode 0 and while a limit holds the axis is 1 at
//!   standstill and 0 while the axis moves.
//! - **Leaving Operation enable** keeps the mode's set-point (a handshaken target, the target of mode −123),
//!   so that motion resumes on Enable operation, but ends a homing run; a homing run starts when a homing mode
//!   is selected in Operation enable or Operation enable is reached with one selected. A mode change drops
//!   a target taken by handshake or input edge (mode 1 with the extended control word, −121 before its
//!   trigger, −123): the new mode starts without one (the relative base of the extended control word stays).
//! - **Motor identification** on ↑ control bit 11 is taken at once; the start-up measurement takes 1.0 s
//!   (X67-18.11.4.3-07 pick), during which the nominal current flows.
//! - **Software limits and homing/speed mode.** The ramp brakes so that it stops at the limit; status bit 11 is
//!   1 in every cycle in which a limit holds the set-point back. The reversing-loop point is kept inside the
//!   limits. A counter already outside the limits (set by mode −122) may only move back toward them.
//! - **Current ratings** (X67-3-03, X67-3-04) are not enforced; breaking them writes a [`Diagnostic`].
//! - **Regeneration** (X67-18.11.4.3-12). When the voltage goes off on a turning motor, its kinetic energy
//!   ([`crate::x67::motor::Motor::regenerated_joules`]) charges the 200 µF DC bus that both bridges share
//!   ([`crate::x67::errors::DcBus`]); a bus above 48.125 V is the voltage error 0x3000 on both axes until
//!   the rise has discharged through the module's own consumption ([`Module::dc_bus_volts`]).

use std::time::{Duration, Instant};

use crate::x67::axis::{Axis, CycleContext, Frac, InputEdge};
use crate::x67::current::MODULE_NOMINAL_MILLIAMPS;
use crate::x67::errors::{supply_in_range, DcBus, Temperature, SUPPLY_MAX_VOLTS};
use crate::x67::ramp::Cycle;
use crate::x67::registers::{AxisReg, ModuleReg, Register, RegisterError};

/// Largest count rate of the encoder inputs in counts per second (X67-3-10: 200 kHz).
pub const MAX_COUNT_RATE: i64 = 200_000;

/// The most cycles one [`Module::handle_timeout`] runs: 10 s of module time at the 5 ms cycle, so a host
/// that was stopped for long catches up in bounded time.
pub const MAX_CATCH_UP: u32 = 2000;

/// A switch fixed to the rotor of an axis: the input is high while the rotor position (microsteps) lies in
/// `from..=to`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cam {
    /// The axis whose rotor carries the cam (0 or 1).
    pub axis: usize,
    /// First rotor position at which the input is high.
    pub from: i64,
    /// Last rotor position at which the input is high.
    pub to: i64,
}

impl Cam {
    /// Whether the input is high at rotor position `x`.
    pub const fn active(&self, x: i64) -> bool {
        self.from <= x && x <= self.to
    }

    /// The edges while the rotor moves from `r0` to `r1` in one cycle, in order.
    fn edges(&self, input: usize, r0: i64, r1: i64) -> Vec<InputEdge> {
        let mut out = Vec::new();
        if r0 == r1 {
            return out;
        }
        let den = (r1 - r0).abs();
        let at = |x: i64| Frac {
            num: (x - r0).abs(),
            den,
        };
        let mut points: Vec<(i64, bool)> = if r1 > r0 {
            vec![(self.from, true), (self.to.saturating_add(1), false)]
        } else {
            vec![(self.to, true), (self.from.saturating_sub(1), false)]
        };
        points.retain(|&(x, _)| {
            if r1 > r0 {
                r0 < x && x <= r1
            } else {
                r1 <= x && x < r0
            }
        });
        for (x, level) in points {
            out.push(InputEdge {
                input,
                level,
                at: at(x),
            });
        }
        out
    }
}

/// What drives a digital input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputSource {
    /// A level set by the harness.
    Level,
    /// A cam on a rotor.
    Cam(Cam),
}

/// Something the simulation noticed that no register shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Diagnostic {
    /// An axis carried more than 3 A for more than 2 s (X67-3-03).
    AxisOverCurrentTooLong {
        /// The axis.
        axis: usize,
        /// Simulated time in ms.
        at_ms: u64,
    },
    /// An axis went above 3 A less than 10 s after its last period above 3 A (X67-3-03).
    AxisRecoveryTooShort {
        /// The axis.
        axis: usize,
        /// Simulated time in ms.
        at_ms: u64,
    },
    /// Both axes together carried more than 8 A (X67-3-04).
    ModuleOverCurrent {
        /// The sum in mA.
        milliamps: u32,
        /// Simulated time in ms.
        at_ms: u64,
    },
    /// An encoder turned faster than the inputs allow (X67-3-10): a test-setup error.
    EncoderTooFast {
        /// The axis.
        axis: usize,
        /// Counts per second.
        rate: i64,
        /// Simulated time in ms.
        at_ms: u64,
    },
}

#[derive(Clone, Copy, Debug, Default)]
struct Rating {
    over_ms: u64,
    recovery_ms: u64,
    reported: bool,
}

/// The module.
#[derive(Clone, Debug)]
pub struct Module {
    axes: [Axis; 2],
    general_config: u8,
    levels: [bool; 6],
    sources: [InputSource; 6],
    /// Edges the harness made since the last cycle.
    pending: Vec<InputEdge>,
    limit_inputs: [[usize; 2]; 2],
    temperature: Temperature,
    supply_volts: f64,
    dc_bus: DcBus,
    time_ms: u64,
    ratings: [Rating; 2],
    module_over: bool,
    diagnostics: Vec<Diagnostic>,
    /// When the next cycle is due on the host's clock (`None` before [`Module::start`]).
    next_cycle: Option<Instant>,
}

impl Default for Module {
    fn default() -> Self {
        Self::new()
    }
}

impl Module {
    /// A module just after power-up: 24 V supply, 25 °C, all inputs low, every register at its bus-controller
    /// default, both axes in Not ready to switch on.
    pub fn new() -> Self {
        let mut temperature = Temperature::new();
        temperature.update(25.0);
        Module {
            axes: [Axis::new(0), Axis::new(1)],
            general_config: 0,
            levels: [false; 6],
            sources: [InputSource::Level; 6],
            pending: Vec::new(),
            limit_inputs: [[0, 1], [3, 4]],
            temperature,
            supply_volts: 24.0,
            dc_bus: DcBus::default(),
            time_ms: 0,
            ratings: [Rating {
                recovery_ms: 10_000,
                ..Rating::default()
            }; 2],
            module_over: false,
            diagnostics: Vec::new(),
            next_cycle: None,
        }
    }

    /// Starts the module's clock at `now` (power-on): the first cycle is due one cycle later.
    pub fn start(&mut self, now: Instant) {
        self.next_cycle = Some(now + self.cycle_length());
    }

    /// Runs every cycle due at `now` (at most [`MAX_CATCH_UP`] after a stall of the host; the clock then
    /// goes on from `now`). Nothing before [`Module::start`].
    pub fn handle_timeout(&mut self, now: Instant) {
        let Some(mut next) = self.next_cycle else {
            return;
        };
        let mut steps = 0;
        while next <= now && steps < MAX_CATCH_UP {
            self.step();
            next += self.cycle_length();
            steps += 1;
        }
        if next <= now {
            next = now + self.cycle_length();
        }
        self.next_cycle = Some(next);
    }

    /// When the next cycle is due (`None` before [`Module::start`]).
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Instant> {
        self.next_cycle
    }

    fn cycle_length(&self) -> Duration {
        Duration::from_millis(u64::from(self.cycle().millis()))
    }

    /// The ramp-generator cycle from GeneralConfig01 bits 1–2.
    pub const fn cycle(&self) -> Cycle {
        Cycle::from_general_config(self.general_config)
    }

    /// Simulated time since power-up in ms.
    pub const fn time_ms(&self) -> u64 {
        self.time_ms
    }

    /// An axis (0 = axis 1).
    pub fn axis(&self, axis: usize) -> &Axis {
        &self.axes[axis.min(1)]
    }

    /// An axis, mutably (its motor, for the harness).
    pub fn axis_mut(&mut self, axis: usize) -> &mut Axis {
        &mut self.axes[axis.min(1)]
    }

    // ----- cyclic registers -----

    /// Writes AbsPos0n.
    pub fn set_abs_pos(&mut self, axis: usize, value: i32) {
        self.axis_mut(axis).set_abs_pos(value);
    }

    /// Writes MpGenControl0n.
    pub fn set_control(&mut self, axis: usize, value: u16) {
        self.axis_mut(axis).set_control(value);
    }

    /// Writes MpGenMode0n.
    pub fn set_mode(&mut self, axis: usize, value: i8) {
        self.axis_mut(axis).set_mode(value);
    }

    /// MpGenStatus0n.
    pub fn status_word(&self, axis: usize) -> u16 {
        self.axis(axis).status_word()
    }

    /// AbsPos0nActVal.
    pub fn act_val(&self, axis: usize) -> i32 {
        self.axis(axis).act_val()
    }

    /// ErrorCode0n.
    pub fn error_code(&self, axis: usize) -> u16 {
        self.axis(axis).error_code()
    }

    /// InputStatus: DI1…DI6 in bits 0–5, bits 6–7 = 0 (X67-18.11.3.6-01).
    pub fn input_status(&self) -> u8 {
        self.levels
            .iter()
            .enumerate()
            .fold(0, |acc, (k, &l)| acc | (u8::from(l) << k))
    }

    /// The 8-byte input CAN object `object` (0 or 1) as the bus controller sends it (X67-18.5.2-02, X67-18.5.2-03):
    /// AbsPos0nActVal, MpGenStatus0n and, in object 0, InputStatus; little-endian, unused bytes 0.
    pub fn input_object(&self, object: usize) -> [u8; 8] {
        let a = self.axis(object);
        let mut out = [0u8; 8];
        out[0..4].copy_from_slice(&a.act_val().to_le_bytes());
        out[4..6].copy_from_slice(&a.status_word().to_le_bytes());
        if object == 0 {
            out[6] = self.input_status();
        }
        out
    }

    /// Takes an 8-byte output CAN object `object` (0 or 1): AbsPos0n, MpGenControl0n and MpGenMode0n;
    /// byte 7 is ignored (X67-18.5.2-02, X67-18.5.2-04).
    pub fn output_object(&mut self, object: usize, data: [u8; 8]) {
        let a = self.axis_mut(object);
        a.set_abs_pos(i32::from_le_bytes([data[0], data[1], data[2], data[3]]));
        a.set_control(u16::from_le_bytes([data[4], data[5]]));
        a.set_mode(data[6] as i8);
    }

    // ----- every register -----

    /// Reads a register. Write-only configuration registers read back the value in force, for the harness;
    /// the CANopen node refuses such reads by the access of its dictionary.
    pub fn read(&self, reg: Register) -> i64 {
        match reg {
            Register::Module(ModuleReg::InputStatus) => i64::from(self.input_status()),
            Register::Module(ModuleReg::GeneralConfig) => i64::from(self.general_config),
            Register::Module(ModuleReg::Temperature) => i64::from(self.temperature.register()),
            Register::Axis(axis, r) => {
                let a = self.axis(axis);
                let c = &a.config;
                match r {
                    AxisReg::AbsPos => i64::from(a.abs_pos()),
                    AxisReg::Control | AxisReg::ControlReadback => i64::from(a.control_readback()),
                    AxisReg::Mode | AxisReg::ModeReadback => i64::from(a.mode_readback()),
                    AxisReg::ActVal => i64::from(a.act_val()),
                    AxisReg::Status => i64::from(a.status_word()),
                    AxisReg::HoldingCurrent | AxisReg::HoldingCurrentRead => {
                        i64::from(c.holding_current)
                    }
                    AxisReg::NominalCurrent | AxisReg::NominalCurrentRead => {
                        i64::from(c.nominal_current)
                    }
                    AxisReg::MaximumCurrent | AxisReg::MaximumCurrentRead => {
                        i64::from(c.maximum_current)
                    }
                    AxisReg::StallDetectConfig => i64::from(c.stall_detect_config),
                    AxisReg::MaxSpeedPos => i64::from(c.max_speed_pos),
                    AxisReg::MaxAcc => i64::from(c.max_acc),
                    AxisReg::MaxDec => i64::from(c.max_dec),
                    AxisReg::RevLoop => i64::from(c.rev_loop),
                    AxisReg::FixedPosA => i64::from(c.fixed_pos_a),
                    AxisReg::FixedPosB => i64::from(c.fixed_pos_b),
                    AxisReg::RefSpeed => i64::from(c.ref_speed),
                    AxisReg::RefConfig => i64::from(c.ref_config),
                    AxisReg::FullStepThreshold => i64::from(c.full_step_threshold),
                    AxisReg::StallRecognitionDelay => i64::from(c.stall_recognition_delay),
                    AxisReg::JoltTime => i64::from(c.jolt_time),
                    AxisReg::StallDetectMinSpeed => i64::from(c.stall_detect_min_speed),
                    AxisReg::LimitSwitchConfig => i64::from(c.limit_switch_config),
                    AxisReg::PositionLimitMin => i64::from(c.position_limit_min),
                    AxisReg::PositionLimitMax => i64::from(c.position_limit_max),
                    AxisReg::MotorIdentification => i64::from(a.motor_identification()),
                    AxisReg::RefPosCyclicCounter => i64::from(a.ref_pos_cyclic()),
                    AxisReg::ActValAcyclic => i64::from(a.act_val_acyclic()),
                    AxisReg::RefPosAcyclicCounter => i64::from(a.ref_pos_acyclic()),
                    AxisReg::ErrorCode => i64::from(a.error_code()),
                }
            }
        }
    }

    /// Writes a register as the master does. Refused, changing nothing: a register the master cannot write
    /// (X67-18.5-03), a value outside the register's type, and a current above 167 % (X67-18.11.1.1-01).
    /// Accepted and without effect: a RefConfig0n value that is not listed (X67-18.11.1.11-05). A JoltTime0n
    /// above 80 is kept and acts as 80 (X67-18.11.1.14-02).
    pub fn write(&mut self, reg: Register, value: i64) -> Result<(), RegisterError> {
        let info = reg.info();
        if !info.access.writable() {
            return Err(RegisterError::ReadOnly(reg));
        }
        let (min, max) = info.ty.range();
        let max = match reg {
            Register::Axis(
                _,
                AxisReg::HoldingCurrent | AxisReg::NominalCurrent | AxisReg::MaximumCurrent,
            ) => i64::from(crate::x67::current::MAX_PERCENT),
            _ => max,
        };
        if value > max {
            return Err(RegisterError::TooHigh {
                register: reg,
                value,
                max,
            });
        }
        if value < min {
            return Err(RegisterError::TooLow {
                register: reg,
                value,
                min,
            });
        }
        match reg {
            Register::Module(ModuleReg::GeneralConfig) => self.general_config = value as u8,
            Register::Module(_) => return Err(RegisterError::ReadOnly(reg)),
            Register::Axis(axis, r) => {
                let a = self.axis_mut(axis);
                let c = &mut a.config;
                match r {
                    AxisReg::AbsPos => a.set_abs_pos(value as i32),
                    AxisReg::Control => a.set_control(value as u16),
                    AxisReg::Mode => a.set_mode(value as i8),
                    // Held to 0…167 % above (X67-18.11.1.1-01 pick: a higher value is refused and
                    // changes nothing).
                    AxisReg::HoldingCurrent => c.holding_current = value as u8,
                    AxisReg::NominalCurrent => c.nominal_current = value as u8,
                    AxisReg::MaximumCurrent => c.maximum_current = value as u8,
                    AxisReg::StallDetectConfig => c.stall_detect_config = value as u8,
                    AxisReg::MaxSpeedPos => c.max_speed_pos = value as u16,
                    AxisReg::MaxAcc => c.max_acc = value as u16,
                    AxisReg::MaxDec => c.max_dec = value as u16,
                    AxisReg::RevLoop => c.rev_loop = value as i16,
                    AxisReg::FixedPosA => c.fixed_pos_a = value as i32,
                    AxisReg::FixedPosB => c.fixed_pos_b = value as i32,
                    AxisReg::RefSpeed => c.ref_speed = value as u16,
                    AxisReg::RefConfig => {
                        if crate::x67::axis::AxisConfig::is_ref_condition(value as i8) {
                            c.ref_config = value as i8;
                        }
                    }
                    AxisReg::FullStepThreshold => c.full_step_threshold = value as u16,
                    AxisReg::StallRecognitionDelay => c.stall_recognition_delay = value as u8,
                    AxisReg::JoltTime => c.jolt_time = value as u8,
                    AxisReg::StallDetectMinSpeed => c.stall_detect_min_speed = value as u16,
                    AxisReg::LimitSwitchConfig => c.limit_switch_config = value as u8,
                    AxisReg::PositionLimitMin => c.position_limit_min = value as i32,
                    AxisReg::PositionLimitMax => c.position_limit_max = value as i32,
                    _ => return Err(RegisterError::ReadOnly(reg)),
                }
            }
        }
        Ok(())
    }

    /// Writes a register by its seed name; for the harness and examples. Panics on an unknown name.
    pub fn write_named(&mut self, name: &str, value: i64) -> Result<(), RegisterError> {
        let reg = Register::from_name(name).unwrap_or_else(|| panic!("no register named {name}"));
        self.write(reg, value)
    }

    /// Reads a register by its seed name; for the harness and examples. Panics on an unknown name.
    pub fn read_named(&self, name: &str) -> i64 {
        let reg = Register::from_name(name).unwrap_or_else(|| panic!("no register named {name}"));
        self.read(reg)
    }

    // ----- harness -----

    /// Sets the module temperature in °C (both axes; X67-15-01).
    pub fn set_temperature(&mut self, celsius: f64) {
        self.temperature.update(celsius);
    }

    /// The DC bus voltage in V: the supply's, raised for a while by the energy of a turning motor whose
    /// voltage went off (X67-18.11.4.3-12).
    pub fn dc_bus_volts(&self) -> f64 {
        self.dc_bus.volts(self.supply_volts)
    }

    /// Sets the supply voltage in V (X67-3-11); a value that is not a finite number is ignored.
    pub fn set_supply(&mut self, volts: f64) {
        if volts.is_finite() {
            self.supply_volts = volts;
        }
    }

    /// Sets digital input `input` (1 = DI1 … 6 = DI6) to a level and makes it a harness-driven input. A
    /// level change on an encoder input (DI1/DI2, DI4/DI5) is decoded by the ABR counter.
    pub fn set_input(&mut self, input: usize, level: bool) {
        let Some(k) = input.checked_sub(1).filter(|k| *k < 6) else {
            return;
        };
        self.sources[k] = InputSource::Level;
        if self.levels[k] != level {
            self.quadrature(k, level);
            self.levels[k] = level;
            self.pending.push(InputEdge {
                input: k,
                level,
                at: Frac::START,
            });
        }
    }

    /// A short pulse on input `input` (1…6) between two cycles: high and low again. The module sees both
    /// edges (X67-3-07).
    pub fn pulse_input(&mut self, input: usize) {
        let Some(k) = input.checked_sub(1).filter(|k| *k < 6) else {
            return;
        };
        let level = self.levels[k];
        self.set_input(input, !level);
        self.set_input(input, level);
    }

    /// Drives input `input` (1…6) by a cam on a rotor; the level follows the rotor at once.
    pub fn attach_cam(&mut self, input: usize, cam: Cam) {
        let Some(k) = input.checked_sub(1).filter(|k| *k < 6) else {
            return;
        };
        self.sources[k] = InputSource::Cam(cam);
        let level = cam.active(self.axis(cam.axis).motor.rotor());
        if level != self.levels[k] {
            self.levels[k] = level;
            self.pending.push(InputEdge {
                input: k,
                level,
                at: Frac::START,
            });
        }
    }

    /// Chooses the inputs (1…6) of the negative and positive limit switch of an axis.
    pub fn set_limit_inputs(&mut self, axis: usize, negative: usize, positive: usize) {
        let clamp = |i: usize| i.clamp(1, 6) - 1;
        self.limit_inputs[axis.min(1)] = [clamp(negative), clamp(positive)];
    }

    /// The diagnostics written so far, oldest first; they are removed.
    pub fn take_diagnostics(&mut self) -> Vec<Diagnostic> {
        std::mem::take(&mut self.diagnostics)
    }

    /// 4x decoding of a hand-driven A/B input change on the ABR counter of its group (X67-3-08, X67-3-09).
    fn quadrature(&mut self, k: usize, level: bool) {
        let (group, a_in, b_in) = match k {
            0 | 1 => (0, 0, 1),
            3 | 4 => (1, 3, 4),
            _ => return,
        };
        let phase = |a: bool, b: bool| match (a, b) {
            (false, false) => 0,
            (true, false) => 1,
            (true, true) => 2,
            (false, true) => 3,
        };
        let old = phase(self.levels[a_in], self.levels[b_in]);
        let mut new_levels = self.levels;
        new_levels[k] = level;
        let new = phase(new_levels[a_in], new_levels[b_in]);
        let delta = match (new - old + 4) % 4 {
            1 => 1i16,
            3 => -1,
            _ => 0,
        };
        let axis = &mut self.axes[group];
        axis.abr = axis.abr.wrapping_add(delta);
    }

    /// Runs `cycles` ramp-generator cycles.
    pub fn run(&mut self, cycles: usize) {
        for _ in 0..cycles {
            self.step();
        }
    }

    /// Runs whole cycles for at least `ms` milliseconds of simulated time.
    pub fn run_ms(&mut self, ms: u64) {
        let t = u64::from(self.cycle().millis());
        self.run(ms.div_ceil(t) as usize);
    }

    /// One ramp-generator cycle of both axes.
    pub fn step(&mut self) {
        let cycle = self.cycle();
        let mut ctx = CycleContext {
            cycle,
            extended_cw: self.general_config & 1 != 0,
            // The supply out of its band, or the DC bus above it after regeneration (X67-3-11,
            // X67-18.11.4.3-12).
            supply_error: !supply_in_range(self.supply_volts)
                || self.dc_bus.volts(self.supply_volts) > SUPPLY_MAX_VOLTS,
            over_temperature: self.temperature.over_temperature(),
            supply_volts: self.supply_volts,
            levels: self.levels,
            levels_before: self.levels,
            edges: Vec::new(),
            limit_inputs: [0, 0],
        };
        // Levels at the start of the cycle: before the harness edges since the last cycle.
        for e in self.pending.iter().rev() {
            ctx.levels_before[e.input] = !e.level;
        }
        self.dc_bus.discharge(f64::from(cycle.millis()) / 1000.0);
        for (n, axis) in self.axes.iter_mut().enumerate() {
            ctx.limit_inputs = self.limit_inputs[n];
            axis.begin(&ctx);
            self.dc_bus
                .regenerate(self.supply_volts, axis.take_regenerated());
        }

        // Motion: ramps, rotors, encoders.
        let mut starts = [0i64; 2];
        let mut abr_starts = [0i32; 2];
        let mut rotor_paths = [(0i64, 0i64); 2];
        let mut states = Vec::with_capacity(2);
        for (n, axis) in self.axes.iter_mut().enumerate() {
            starts[n] = axis.ramp_position();
            abr_starts[n] = axis.abr_counter();
            let rs = axis.step_ramp();
            let r0 = axis.motor.rotor();
            let delta = axis.motor.rotor_delta(i64::from(rs.speed));
            axis.motor.turn(delta);
            rotor_paths[n] = (r0, r0 + delta);
            if axis.motor.encoder_lines > 0 {
                let p0 = axis.motor.encoder_phase(r0);
                let p1 = axis.motor.encoder_phase(r0 + delta);
                let counts = p1 - p0;
                axis.abr = axis.abr.wrapping_add(counts as i16);
                let rate = counts.abs() * 1000 / i64::from(cycle.millis());
                if rate > MAX_COUNT_RATE {
                    self.diagnostics.push(Diagnostic::EncoderTooFast {
                        axis: n,
                        rate,
                        at_ms: self.time_ms,
                    });
                }
                let (a, b) = match p1.rem_euclid(4) {
                    0 => (false, false),
                    1 => (true, false),
                    2 => (true, true),
                    _ => (false, true),
                };
                let base = 3 * n;
                self.levels[base] = a;
                self.levels[base + 1] = b;
            }
            states.push(rs);
        }

        // Edges of the cycle: the harness's first, then the cams'.
        // Each cam's edges are in the order of its rotor's path. Edges of different inputs act on
        // separate things (a limit switch, the reference, the R input's mode trigger), so their order
        // within the cycle changes nothing.
        let mut edges = std::mem::take(&mut self.pending);
        for (k, src) in self.sources.iter().enumerate() {
            if let InputSource::Cam(cam) = src {
                let (r0, r1) = rotor_paths[cam.axis.min(1)];
                edges.extend(cam.edges(k, r0, r1));
                self.levels[k] = cam.active(r1);
            }
        }
        ctx.edges = edges;
        for (n, axis) in self.axes.iter_mut().enumerate() {
            ctx.limit_inputs = self.limit_inputs[n];
            axis.finish(&ctx, states[n], starts[n], abr_starts[n]);
        }
        self.time_ms += u64::from(cycle.millis());
        self.check_ratings(cycle);
    }

    /// The current-rating monitors of each axis (X67-3-03) and of the module (X67-3-04).
    fn check_ratings(&mut self, cycle: Cycle) {
        let t = u64::from(cycle.millis());
        let mut sum = 0;
        for n in 0..2 {
            let ma = self.axes[n].phase_current_ma();
            sum += ma;
            let r = &mut self.ratings[n];
            if ma > MODULE_NOMINAL_MILLIAMPS {
                if r.over_ms == 0 && r.recovery_ms < 10_000 {
                    self.diagnostics.push(Diagnostic::AxisRecoveryTooShort {
                        axis: n,
                        at_ms: self.time_ms,
                    });
                }
                r.over_ms += t;
                r.recovery_ms = 0;
                if r.over_ms > 2_000 && !r.reported {
                    r.reported = true;
                    self.diagnostics.push(Diagnostic::AxisOverCurrentTooLong {
                        axis: n,
                        at_ms: self.time_ms,
                    });
                }
            } else {
                r.over_ms = 0;
                r.reported = false;
                r.recovery_ms = r.recovery_ms.saturating_add(t);
            }
        }
        self.check_module_rating(sum);
    }

    /// The module's rating of 8 A for both axes together (X67-3-04): one diagnostic at the start of each
    /// period above it. `sum` is the phase-current amplitudes of both axes in mA.
    fn check_module_rating(&mut self, sum: u32) {
        if sum > 8_000 {
            if !self.module_over {
                self.diagnostics.push(Diagnostic::ModuleOverCurrent {
                    milliamps: sum,
                    at_ms: self.time_ms,
                });
            }
            self.module_over = true;
        } else {
            self.module_over = false;
        }
    }
}
