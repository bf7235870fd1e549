//! The rig the X67SM2436 module tests share: register access by [`AxisReg`] or by name, the status-word state
//! patterns of 18.11.4.2, bringing an axis up to Switched on or Operation enable with the commands of
//! 18.11.4.1, and running cycles as the master sees them.
//!
//! The commands and control-word bits come from the library ([`ds402::cia402::control`], the `CW_…` constants
//! of [`ds402::x67::axis`] and [`ds402::x67::errors`]); the state patterns are the expected values of the seed's
//! table (X67-18.11.4.2-01, X67-18.11.4.2-02, X67-18.11.4.2-03, X67-18.11.4.2-04, X67-18.11.4.2-05,
//! X67-18.11.4.2-06, X67-18.11.4.2-07, X67-18.11.4.2-08) and stay spelled out here.
#![allow(dead_code)]

use ds402::cia402::control::{ENABLE_OPERATION, QUICK_STOP_BIT, SHUTDOWN, SWITCH_ON};
use ds402::x67::axis::{SW_SETPOINT_ACK, SW_TARGET_REACHED};
use ds402::x67::module::Module;
use ds402::x67::registers::{AxisReg, Register};

/// Quick stop with bits 0 and 3 still set, as a master sends it from Operation enable: Enable operation with
/// bit 2 cleared, `(CW & 0x0086) == 0x0002` (X67-18.11.4.1-04).
pub const QUICK_STOP_FROM_ENABLED: u16 = ENABLE_OPERATION & !QUICK_STOP_BIT;

// ----- status-word state patterns (18.11.4.2) -----

/// Not ready to switch on (X67-18.11.4.2-01).
pub const NOT_READY: u16 = 0x0200;
/// Switch on disabled (X67-18.11.4.2-02).
pub const SWITCH_ON_DISABLED: u16 = 0x0240;
/// Ready to switch on (X67-18.11.4.2-03).
pub const READY: u16 = 0x0221;
/// Switched on (X67-18.11.4.2-04).
pub const SWITCHED_ON: u16 = 0x0233;
/// Operation enable (X67-18.11.4.2-05).
pub const OPERATION_ENABLE: u16 = 0x0237;
/// Quick stop active (X67-18.11.4.2-06).
pub const QUICK_STOP_ACTIVE: u16 = 0x0217;
/// Fault reaction active (X67-18.11.4.2-07).
pub const FAULT_REACTION_ACTIVE: u16 = 0x020F;
/// Fault (X67-18.11.4.2-08).
pub const FAULT: u16 = 0x0208;

/// The status-word bits that fix the state where bit 5 is defined (X67-18.11.4.2-03,
/// X67-18.11.4.2-04, X67-18.11.4.2-05, X67-18.11.4.2-06).
pub const STATE_MASK: u16 = 0x037F;
/// The status-word bits that fix the state where bit 5 is `x`: Not ready to switch on, Switch on disabled,
/// Fault reaction active and Fault (X67-18.11.4.2-01, X67-18.11.4.2-02, X67-18.11.4.2-07,
/// X67-18.11.4.2-08).
pub const DISABLED_MASK: u16 = 0x035F;

/// The mask of a state pattern: bit 5 is `x` in Not ready to switch on, Switch on disabled, Fault reaction
/// active and Fault (0x035F), and fixed in the other four states (0x037F).
pub fn mask(pattern: u16) -> u16 {
    match pattern {
        READY | SWITCHED_ON | OPERATION_ENABLE | QUICK_STOP_ACTIVE => STATE_MASK,
        _ => DISABLED_MASK,
    }
}

/// The status word of `axis` under [`STATE_MASK`].
pub fn state(m: &Module, axis: usize) -> u16 {
    m.status_word(axis) & STATE_MASK
}

/// Asserts that the status word of `axis` shows the state `pattern` under its [`mask`].
#[track_caller]
pub fn assert_state(m: &Module, axis: usize, pattern: u16) {
    let sw = m.status_word(axis);
    assert_eq!(
        sw & mask(pattern),
        pattern,
        "axis {}: status word {sw:#06x}, expected the pattern {pattern:#06x}",
        axis + 1
    );
}

// ----- registers -----

/// Writes an axis register; panics with the register's error when the module refuses the value.
#[track_caller]
pub fn set(m: &mut Module, axis: usize, reg: AxisReg, value: i64) {
    m.write(Register::Axis(axis, reg), value)
        .unwrap_or_else(|e| panic!("{e}"));
}

/// Reads an axis register.
pub fn get(m: &Module, axis: usize, reg: AxisReg) -> i64 {
    m.read(Register::Axis(axis, reg))
}

/// A register name of `axis`: `"MaxAcc0n"` → `"MaxAcc01"` / `"MaxAcc02"`.
pub fn reg(name: &str, axis: usize) -> String {
    name.replace("0n", if axis == 0 { "01" } else { "02" })
}

/// Writes the register `name` of `axis` (`"…0n…"`, see [`reg`]).
#[track_caller]
pub fn write(m: &mut Module, name: &str, axis: usize, value: i64) {
    let name = reg(name, axis);
    m.write_named(&name, value)
        .unwrap_or_else(|e| panic!("{name} = {value}: {e}"));
}

/// Reads the register `name` of `axis` (`"…0n…"`, see [`reg`]).
pub fn read(m: &Module, name: &str, axis: usize) -> i64 {
    m.read_named(&reg(name, axis))
}

/// Writes RefConfig0n, the referencing condition (one of [`ds402::x67::axis::ref_config`]).
#[track_caller]
pub fn set_ref_config(m: &mut Module, axis: usize, value: i8) {
    set(m, axis, AxisReg::RefConfig, i64::from(value));
}

/// Writes MaxSpeed0npos, MaxAcc0n and MaxDec0n.
pub fn set_ramp(m: &mut Module, axis: usize, max_speed: i64, max_acc: i64, max_dec: i64) {
    set(m, axis, AxisReg::MaxSpeedPos, max_speed);
    set(m, axis, AxisReg::MaxAcc, max_acc);
    set(m, axis, AxisReg::MaxDec, max_dec);
}

/// ConfigOutput03a/04a/05a (axis 1) or 06a/07a/08a (axis 2) in percent of 3 A.
pub fn set_currents(m: &mut Module, axis: usize, holding: i64, nominal: i64, maximum: i64) {
    set(m, axis, AxisReg::HoldingCurrent, holding);
    set(m, axis, AxisReg::NominalCurrent, nominal);
    set(m, axis, AxisReg::MaximumCurrent, maximum);
}

// ----- bringing an axis up -----

/// Takes `axis` from power-up, Switch on disabled or Ready to switch on to Switched on: the first cycle after
/// power-up, Shutdown, then Switch on, which runs the 1.0 s start-up motor identification in Ready to switch
/// on the first time (X67-18.11.4.3-07) at whatever cycle GeneralConfig01 sets.
#[track_caller]
pub fn switch_on(m: &mut Module, axis: usize) {
    if m.status_word(axis) & DISABLED_MASK == NOT_READY {
        m.step();
    }
    let sw = m.status_word(axis);
    assert!(
        sw & DISABLED_MASK == SWITCH_ON_DISABLED || sw & STATE_MASK == READY,
        "axis {}: status word {sw:#06x}, expected Switch on disabled or Ready to switch on",
        axis + 1
    );
    m.set_control(axis, SHUTDOWN);
    m.step();
    assert_state(m, axis, READY);
    m.set_control(axis, SWITCH_ON);
    for _ in 0..=1000 / 5 {
        m.step();
        if state(m, axis) == SWITCHED_ON {
            return;
        }
        assert_state(m, axis, READY);
    }
    panic!("axis {} did not reach Switched on", axis + 1);
}

/// Enable operation from Switched on: one cycle, in which the selected mode already acts.
#[track_caller]
pub fn enable_operation(m: &mut Module, axis: usize) {
    m.set_control(axis, ENABLE_OPERATION);
    m.step();
    assert_state(m, axis, OPERATION_ENABLE);
}

/// Writes MaxSpeed0npos, MaxAcc0n and MaxDec0n and brings `axis` to Operation enable (Shutdown, Switch on
/// with the start-up identification, Enable operation).
#[track_caller]
pub fn operation_enable(m: &mut Module, axis: usize, max_speed: i64, max_acc: i64, max_dec: i64) {
    set_ramp(m, axis, max_speed, max_acc, max_dec);
    switch_on(m, axis);
    enable_operation(m, axis);
}

// ----- cycles -----

/// One cycle as the master sees it: the increment of AbsPos0nActVal, its value and the status word.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cyc {
    /// How far AbsPos0nActVal moved in the cycle.
    pub inc: i32,
    /// AbsPos0nActVal after the cycle.
    pub pos: i32,
    /// MpGenStatus0n after the cycle.
    pub sw: u16,
}

impl Cyc {
    /// SW bit 10, Target reached.
    pub fn reached(self) -> bool {
        self.sw & SW_TARGET_REACHED != 0
    }

    /// SW bit 12, Set-point acknowledge.
    pub fn ack(self) -> bool {
        self.sw & SW_SETPOINT_ACK != 0
    }
}

/// Runs one cycle and returns what the master sees of `axis`.
pub fn cycle(m: &mut Module, axis: usize) -> Cyc {
    let before = m.act_val(axis);
    m.step();
    let pos = m.act_val(axis);
    Cyc {
        inc: pos.wrapping_sub(before),
        pos,
        sw: m.status_word(axis),
    }
}

/// The cycles of `n` steps.
pub fn trace(m: &mut Module, axis: usize, n: usize) -> Vec<Cyc> {
    (0..n).map(|_| cycle(m, axis)).collect()
}

/// The per-cycle increments of AbsPos0nActVal over `n` cycles.
pub fn increments(m: &mut Module, axis: usize, n: usize) -> Vec<i32> {
    (0..n).map(|_| cycle(m, axis).inc).collect()
}

// ----- expected sequences -----

/// The concatenation of `parts`.
pub fn cat(parts: &[&[i32]]) -> Vec<i32> {
    parts.concat()
}

/// `a` followed by `b`.
pub fn cat_bools(a: &[bool], b: &[bool]) -> Vec<bool> {
    [a, b].concat()
}
