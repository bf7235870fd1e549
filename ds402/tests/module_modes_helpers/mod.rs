//! What the tests of the X67SM2436 module's motion modes share (`module_modes`, `module_mode_registers`,
//! `module_mode_status`): bringing an axis up, traces, and the expected profiles.
#![allow(dead_code)]

use crate::x67_rig::{cat, cycle, enable_operation, set_ramp, switch_on, write, Cyc};
use ds402::cia402::control::ENABLE_OPERATION;
use ds402::x67::axis::{modes, CW_NEW_SETPOINT};
use ds402::x67::module::Module;

/// Axis 1 (registers …01, R input DI3).
pub const A1: usize = 0;
/// DI3, the R input of axis 1.
pub const DI3: usize = 3;

// ----- bringing an axis up -----

/// A module whose axis 1 is in Operation enable with these ramp registers, in mode 1 at position 0 with
/// AbsPos01 = 0, so it stands still.
pub fn enabled(speed: i64, acc: i64, dec: i64) -> Module {
    let mut m = Module::new();
    set_ramp(&mut m, A1, speed, acc, dec);
    m.set_mode(A1, modes::POSITION);
    switch_on(&mut m, A1);
    enable_operation(&mut m, A1);
    assert_eq!(m.act_val(A1), 0);
    m
}

/// The default move parameters of these tests: MaxSpeed 100, MaxAcc 10, MaxDec 10.
pub fn standard() -> Module {
    enabled(100, 10, 10)
}

/// As [`standard`], with the extended control word (GeneralConfig01 bit 0 = 1).
pub fn standard_ext() -> Module {
    let mut m = Module::new();
    m.write_named("GeneralConfig01", 1).unwrap();
    set_ramp(&mut m, A1, 100, 10, 10);
    m.set_mode(A1, modes::POSITION);
    switch_on(&mut m, A1);
    enable_operation(&mut m, A1);
    m
}

// ----- traces -----

/// Runs until status bit 10 is 1 (at most `limit` cycles) and returns every cycle, the last included.
pub fn until_reached(m: &mut Module, axis: usize, limit: usize) -> Vec<Cyc> {
    let mut out = Vec::new();
    for _ in 0..limit {
        let c = cycle(m, axis);
        out.push(c);
        if c.reached() {
            return out;
        }
    }
    panic!(
        "bit 10 not set within {limit} cycles; last {:?}",
        out.last()
    );
}

pub fn incs(t: &[Cyc]) -> Vec<i32> {
    t.iter().map(|c| c.inc).collect()
}

pub fn bit10(t: &[Cyc]) -> Vec<bool> {
    t.iter().map(|c| c.reached()).collect()
}

pub fn positions(t: &[Cyc]) -> Vec<i32> {
    t.iter().map(|c| c.pos).collect()
}

// ----- expected profiles -----

/// `from`, `from + step`, … up to and including `to`.
pub fn seq(from: i32, to: i32, step: i32) -> Vec<i32> {
    let mut out = Vec::new();
    let mut v = from;
    while (step > 0 && v <= to) || (step < 0 && v >= to) {
        out.push(v);
        v += step;
    }
    out
}

/// The increments of a move from standstill over 1000 + 100·`cruise` microsteps with MaxSpeed 100 and
/// MaxAcc = MaxDec = 10, in direction `dir`, followed by the arrival cycle (increment 0).
pub fn profile(cruise: usize, dir: i32) -> Vec<i32> {
    cat(&[
        &seq(10, 100, 10),
        &vec![100; cruise],
        &seq(90, 10, -10),
        &[0],
    ])
    .into_iter()
    .map(|v| v * dir)
    .collect()
}

/// Bit 10 over [`profile`]: 0 while moving, 1 in the arrival cycle.
pub fn moving_then_reached(len: usize) -> Vec<bool> {
    let mut v = vec![false; len - 1];
    v.push(true);
    v
}

/// Gives a set-point through the handshake: AbsPos01 and a rising edge on CW bit 4 (with `bits` 5/6), for one
/// cycle; returns that cycle.
pub fn handshake(m: &mut Module, value: i32, bits: u16) -> Cyc {
    m.set_abs_pos(A1, value);
    m.set_control(A1, ENABLE_OPERATION | CW_NEW_SETPOINT | bits);
    cycle(m, A1)
}

/// Clears CW bit 4 (keeping `bits`) and runs one cycle.
pub fn release(m: &mut Module, bits: u16) -> Cyc {
    m.set_control(A1, ENABLE_OPERATION | bits);
    cycle(m, A1)
}

/// Moves axis 1 in mode 1 to `target` and waits there.
pub fn move_to(m: &mut Module, target: i32) -> Vec<Cyc> {
    m.set_mode(A1, modes::POSITION);
    m.set_abs_pos(A1, target);
    let t = until_reached(m, A1, 2000);
    assert_eq!(m.act_val(A1), target);
    t
}

/// Starts a move to `target` in `mode` (1, −121, −123, −124, −125, −126) from standstill at 0; FixedPos01a/b
/// and DI3 are set as the mode needs. Returns whether the move starts one cycle late (input edge).
pub fn start_move(m: &mut Module, mode: i8, target: i32) -> bool {
    write(m, "FixedPos0na", A1, i64::from(target));
    write(m, "FixedPos0nb", A1, i64::from(target));
    m.set_abs_pos(A1, target);
    match mode {
        modes::MOVE_ON_INPUT => m.pulse_input(DI3),
        modes::TWO_POSITION => m.set_input(DI3, true),
        _ => {}
    }
    m.set_mode(A1, mode);
    mode == modes::MOVE_ON_INPUT
}

/// Runs a move to 3000 in mode 1 with `cw(k)` as the control word of cycle k; returns the trace.
pub fn move_with_control(ext: bool, cw: impl Fn(usize) -> u16) -> Vec<Cyc> {
    let mut m = if ext { standard_ext() } else { standard() };
    m.set_abs_pos(A1, 3000);
    (0..50)
        .map(|k| {
            m.set_control(A1, cw(k));
            cycle(&mut m, A1)
        })
        .collect()
}

/// Moves to `target` and returns (lowest position, highest position, last non-zero increment), the start
/// included.
pub fn approach(m: &mut Module, target: i32) -> (i32, i32, i32) {
    let start = m.act_val(A1);
    let t = move_to(m, target);
    let lo = t.iter().map(|c| c.pos).min().unwrap().min(start);
    let hi = t.iter().map(|c| c.pos).max().unwrap().max(start);
    let last = t.iter().rev().find(|c| c.inc != 0).unwrap().inc;
    (lo, hi, last)
}

/// The increments after an input edge the harness makes between two cycles: the cycle that follows sees the
/// edge and takes the new target (bit 10 drops there), and the move starts in the cycle after it. The model
/// evaluates input edges at the end of a cycle, with the counters of the cycle start (X67-3-07 pick: acted on
/// at the next cycle).
pub fn after_edge(profile: Vec<i32>) -> Vec<i32> {
    cat(&[&[0], &profile])
}
