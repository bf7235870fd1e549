//! What the homing and limit tests of the X67SM2436 module share (`module_homing`, `module_limits`).
#![allow(dead_code)]

use crate::x67_rig::{get, increments as incs, set, set_currents, set_ref_config};
use ds402::cia402::control::ENABLE_OPERATION;
use ds402::x67::axis::{modes, ref_config};
use ds402::x67::errors::CW_STALL_DETECTION;
use ds402::x67::module::{Cam, Module};
use ds402::x67::motor::Load;
use ds402::x67::registers::AxisReg;

// ----- helpers -----

/// Encoder lines for the tests with an ABR counter: 4 × 500 counts per 200 × 256 microsteps, i.e. 5 counts
/// per 128 microsteps.
pub const ENCODER_LINES: u32 = 500;

/// The ABR count of an encoder with [`ENCODER_LINES`] at a rotor position (4x evaluation, rounded down).
pub fn abr_at(rotor: i64) -> i64 {
    (rotor * 4 * i64::from(ENCODER_LINES)).div_euclid(200 * 256)
}

/// RefPos0nCyclicCounter and RefPos0nAcyclicCounter.
pub fn refs(m: &Module, axis: usize) -> (i64, i64) {
    (
        get(m, axis, AxisReg::RefPosCyclicCounter),
        get(m, axis, AxisReg::RefPosAcyclicCounter),
    )
}

/// A new module whose axis `axis` is in Operation enable at position 0 with mode 0, the given MaxSpeed0npos,
/// MaxAcc0n and MaxDec0n, and currents of 20 % (holding), 50 % (nominal) and 100 % (maximum).
pub fn enabled(axis: usize, max_speed: i64, acc: i64, dec: i64) -> Module {
    let mut m = Module::new();
    set_currents(&mut m, axis, 20, 50, 100);
    crate::x67_rig::operation_enable(&mut m, axis, max_speed, acc, dec);
    assert_eq!(m.act_val(axis), 0);
    m
}

/// [`enabled`] with RefSpeed0n.
pub fn homing_axis(axis: usize, ref_speed: i64, acc: i64, dec: i64) -> Module {
    let mut m = enabled(axis, 0, acc, dec);
    set(&mut m, axis, AxisReg::RefSpeed, ref_speed);
    m
}

/// One cycle; returns the increment of AbsPos0nActVal (control bit 14 = 0) and the status word after it.
pub fn cycle(m: &mut Module, axis: usize) -> (i32, u16) {
    let c = crate::x67_rig::cycle(m, axis);
    (c.inc, c.sw)
}

/// The increments of `n` cycles with SW bit `mask` after each.
pub fn incs_bits(m: &mut Module, axis: usize, n: usize, mask: u16) -> Vec<(i32, bool)> {
    (0..n)
        .map(|_| {
            let (inc, sw) = cycle(m, axis);
            (inc, sw & mask != 0)
        })
        .collect()
}

pub fn rep(value: i32, n: usize) -> Vec<i32> {
    vec![value; n]
}

pub fn bit(m: &Module, axis: usize, mask: u16) -> bool {
    m.status_word(axis) & mask != 0
}

/// Sets the ABR counter of axis 1 to +3 by hand quadrature on DI1/DI2 (A leading B counts up).
pub fn abr_plus_three(m: &mut Module) {
    m.set_input(1, true);
    m.set_input(2, true);
    m.set_input(1, false);
}

/// A cam on `input` carried by the rotor of `axis`.
pub fn cam(m: &mut Module, input: usize, axis: usize, from: i64, to: i64) {
    m.attach_cam(input, Cam { axis, from, to });
}

/// Stall homing set-up: threshold 3, stall detection on (control bit 15), RefConfig −127, encoder on the
/// shaft, a light load (load value 7: no stall).
pub fn stall_homing(ref_speed: i64) -> Module {
    let mut m = homing_axis(0, ref_speed, 10, 5);
    m.axis_mut(0).motor.encoder_lines = ENCODER_LINES;
    m.axis_mut(0).motor.load = Load::Value(7);
    set(&mut m, 0, AxisReg::StallDetectConfig, 0x30);
    set_ref_config(&mut m, 0, ref_config::STALL);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.step();
    m
}

/// Axis 1 in Mode 2 at `speed` (MaxAcc01 = 10, MaxDec01 = 5) with LimitSwitchConfig01 = `config`, already at
/// speed (limit switches DI1 negative, DI2 positive).
pub fn running(config: i64, speed: i32) -> Module {
    let mut m = enabled(0, 0, 10, 5);
    set(&mut m, 0, AxisReg::LimitSwitchConfig, config);
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, speed);
    let s = speed.signum();
    assert_eq!(incs(&mut m, 0, 5), [10 * s, 20 * s, 30 * s, 40 * s, 40 * s]);
    m
}

/// Sets `input` to each level in turn, one cycle each; returns the increment and ErrorCode01 after each.
pub fn drive(m: &mut Module, input: usize, levels: &[bool]) -> Vec<(i32, u16)> {
    levels
        .iter()
        .map(|&level| {
            m.set_input(input, level);
            let (inc, _) = cycle(m, 0);
            (inc, m.error_code(0))
        })
        .collect()
}

/// `n` cycles without touching an input; the increment and ErrorCode01 after each.
pub fn drive_none(m: &mut Module, n: usize) -> Vec<(i32, u16)> {
    (0..n)
        .map(|_| {
            let (inc, _) = cycle(m, 0);
            (inc, m.error_code(0))
        })
        .collect()
}

/// Writes PositionLimitMin0n and PositionLimitMax0n.
pub fn limits(m: &mut Module, axis: usize, min: i64, max: i64) {
    set(m, axis, AxisReg::PositionLimitMin, min);
    set(m, axis, AxisReg::PositionLimitMax, max);
}
