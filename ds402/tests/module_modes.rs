//! The motion modes of the X67SM2436 "Ramp" module model and the status bits they drive, tested through the
//! module's registers: the Mode register and its values (18.11.3.3), mode 1 with and without the extended
//! control word, speed mode, modes −120…−126, the ramp registers as the modes use them (18.11.1.3–18.11.1.8,
//! 18.11.1.14, 18.11.1.15), the control-word bits 4–10, status bits 10 and 12, the counter wrap-around and the
//! once-per-cycle take-over of the cyclic outputs. Each test names the rules of `rules/x67.md` it covers.
//!
//! The expected trajectories follow the discretisation the catalogue picks in X67-18.11.3.3.1-01: each cycle
//! the speed changes first (by at most MaxAcc/MaxDec, up to MaxSpeed) and the position then advances by it;
//! braking starts as late as possible so that the target is met exactly. With MaxSpeed 100, MaxAcc 10 and
//! MaxDec 10 a move from standstill accelerates 10, 20, …, 100 (550 microsteps), brakes 90, 80, …, 10 (450
//! microsteps), and cruises at 100 for the rest; the axis arrives in the following cycle with increment 0.

mod x67_rig;

use ds402::cia402::control::{ENABLE_OPERATION, SHUTDOWN, SWITCH_ON};
use ds402::cia402::SW_WARNING;
use ds402::x67::axis::{
    modes, ref_config, CW_CHANGE_IMMEDIATELY, CW_NEW_SETPOINT, CW_RELATIVE, CW_STOP,
    CW_SWAP_COUNTERS, SW_SETPOINT_ACK, SW_TARGET_REACHED,
};
use ds402::x67::errors::CW_WARNING_RESET;
use ds402::x67::module::{Cam, Module};
use proptest::prelude::*;
use x67_rig::{
    cat, cat_bools, cycle, enable_operation, read, set_ramp, state, switch_on, trace, write, Cyc,
    DISABLED_MASK, OPERATION_ENABLE, QUICK_STOP_FROM_ENABLED, READY, STATE_MASK, SWITCHED_ON,
    SWITCH_ON_DISABLED,
};

/// Axis 1 (registers …01, R input DI3).
const A1: usize = 0;
/// DI3, the R input of axis 1.
const DI3: usize = 3;

// ----- bringing an axis up -----

/// A module whose axis 1 is in Operation enable with these ramp registers, in mode 1 at position 0 with
/// AbsPos01 = 0, so it stands still.
fn enabled(speed: i64, acc: i64, dec: i64) -> Module {
    let mut m = Module::new();
    set_ramp(&mut m, A1, speed, acc, dec);
    m.set_mode(A1, modes::POSITION);
    switch_on(&mut m, A1);
    enable_operation(&mut m, A1);
    assert_eq!(m.act_val(A1), 0);
    m
}

/// The default move parameters of these tests: MaxSpeed 100, MaxAcc 10, MaxDec 10.
fn standard() -> Module {
    enabled(100, 10, 10)
}

/// As [`standard`], with the extended control word (GeneralConfig01 bit 0 = 1).
fn standard_ext() -> Module {
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
fn until_reached(m: &mut Module, axis: usize, limit: usize) -> Vec<Cyc> {
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

fn incs(t: &[Cyc]) -> Vec<i32> {
    t.iter().map(|c| c.inc).collect()
}

fn bit10(t: &[Cyc]) -> Vec<bool> {
    t.iter().map(|c| c.reached()).collect()
}

fn positions(t: &[Cyc]) -> Vec<i32> {
    t.iter().map(|c| c.pos).collect()
}

// ----- expected profiles -----

/// `from`, `from + step`, … up to and including `to`.
fn seq(from: i32, to: i32, step: i32) -> Vec<i32> {
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
fn profile(cruise: usize, dir: i32) -> Vec<i32> {
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
fn moving_then_reached(len: usize) -> Vec<bool> {
    let mut v = vec![false; len - 1];
    v.push(true);
    v
}

/// Gives a set-point through the handshake: AbsPos01 and a rising edge on CW bit 4 (with `bits` 5/6), for one
/// cycle; returns that cycle.
fn handshake(m: &mut Module, value: i32, bits: u16) -> Cyc {
    m.set_abs_pos(A1, value);
    m.set_control(A1, ENABLE_OPERATION | CW_NEW_SETPOINT | bits);
    cycle(m, A1)
}

/// Clears CW bit 4 (keeping `bits`) and runs one cycle.
fn release(m: &mut Module, bits: u16) -> Cyc {
    m.set_control(A1, ENABLE_OPERATION | bits);
    cycle(m, A1)
}

/// Moves axis 1 in mode 1 to `target` and waits there.
fn move_to(m: &mut Module, target: i32) -> Vec<Cyc> {
    m.set_mode(A1, modes::POSITION);
    m.set_abs_pos(A1, target);
    let t = until_reached(m, A1, 2000);
    assert_eq!(m.act_val(A1), target);
    t
}

/// Starts a move to `target` in `mode` (1, −121, −123, −124, −125, −126) from standstill at 0; FixedPos01a/b
/// and DI3 are set as the mode needs. Returns whether the move starts one cycle late (input edge).
fn start_move(m: &mut Module, mode: i8, target: i32) -> bool {
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
fn move_with_control(ext: bool, cw: impl Fn(usize) -> u16) -> Vec<Cyc> {
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
fn approach(m: &mut Module, target: i32) -> (i32, i32, i32) {
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
fn after_edge(profile: Vec<i32>) -> Vec<i32> {
    cat(&[&[0], &profile])
}

// =====================================================================================================
// 18.11.3.3 Mode
// =====================================================================================================

/// X67-18.11.3.3-01: MpGenMode01 takes every listed mode value, and ModeReadback01 returns the value written.
#[test]
fn x67_18_11_3_3_01_mode_register_values_read_back() {
    let mut m = standard();
    for mode in [
        modes::NONE,
        modes::POSITION,
        modes::SPEED,
        modes::SET_HOME,
        modes::REMAINING_DISTANCE,
        modes::SET_POSITION,
        modes::MOVE_ON_INPUT,
        modes::TWO_POSITION,
        modes::FIXED_A,
        modes::FIXED_B,
        modes::HOMING_POSITIVE,
        modes::HOMING_NEGATIVE,
        modes::POSITION,
    ] {
        m.set_mode(A1, mode);
        m.step();
        assert_eq!(read(&m, "ModeReadback0n", A1), i64::from(mode));
        assert_eq!(read(&m, "MpGenMode0n", A1), i64::from(mode));
        assert_eq!(state(&m, A1), OPERATION_ENABLE, "mode {mode}");
    }
}

/// X67-18.11.3.3-01: the modes are the numbers of the seed's table, written as those numbers. The library's
/// names are these numbers, and each number starts its own function from standstill at 0 (MaxSpeed 100,
/// MaxAcc = MaxDec = 10): −120 sets home (500 becomes the actual position, reference 0 before) and −122 the
/// position (777), both without motion; −121 moves to AbsPos01 = 1000 without bit 10 (no trigger yet);
/// −123 waits for DI3 and then moves to 1000; −124 with DI3 low goes to FixedPos01b = −1000, and so does
/// −126; an unlisted number would do nothing (X67-18.11.3.3-05).
#[test]
fn x67_18_11_3_3_01_mode_numbers_of_the_table() {
    assert_eq!(
        [
            modes::NONE,
            modes::POSITION,
            modes::SPEED,
            modes::SET_HOME,
            modes::REMAINING_DISTANCE,
            modes::SET_POSITION,
            modes::MOVE_ON_INPUT,
            modes::TWO_POSITION,
            modes::FIXED_A,
            modes::FIXED_B,
            modes::HOMING_POSITIVE,
            modes::HOMING_NEGATIVE,
        ],
        [0, 1, 2, -120, -121, -122, -123, -124, -125, -126, -127, -128]
    );

    for (mode, abs_pos, expected) in [(-120i8, 500, 500), (-122, 777, 777)] {
        let mut m = standard();
        m.set_abs_pos(A1, abs_pos);
        m.set_mode(A1, mode);
        m.step();
        assert_eq!(m.act_val(A1), expected, "mode {mode}");
        assert_eq!(m.axis(A1).motor.rotor(), 0, "mode {mode}: no motion");
    }

    let mut m = standard();
    m.set_abs_pos(A1, 1000);
    m.set_mode(A1, -121);
    let t = trace(&mut m, A1, 25);
    assert_eq!(incs(&t), cat(&[&profile(0, 1), &[0; 5]]));
    assert!(t.iter().all(|c| !c.reached()));

    let mut m = standard();
    m.set_abs_pos(A1, 1000);
    m.set_mode(A1, -123);
    assert!(trace(&mut m, A1, 3).iter().all(|c| c.inc == 0));
    m.pulse_input(DI3);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), after_edge(profile(0, 1)));

    for mode in [-124i8, -126] {
        let mut m = standard();
        write(&mut m, "FixedPos0na", A1, 1000);
        write(&mut m, "FixedPos0nb", A1, -1000);
        m.set_mode(A1, mode);
        let t = until_reached(&mut m, A1, 100);
        assert_eq!(incs(&t), profile(0, -1), "mode {mode}");
        assert_eq!(m.act_val(A1), -1000, "mode {mode}");
    }
}

/// X67-18.11.3.3-02: mode 0 executes no motion function; switched to 0 during a move, the axis brakes with
/// MaxDec01 to standstill, bit 10 = 0 while it brakes and 1 at standstill (pick).
#[test]
fn x67_18_11_3_3_02_mode_0_no_motion_and_brakes() {
    let mut m = standard();
    m.set_mode(A1, modes::NONE);
    m.set_abs_pos(A1, 5000);
    let t = trace(&mut m, A1, 30);
    assert!(t.iter().all(|c| c.inc == 0 && c.pos == 0 && c.reached()));

    // A move in mode 1, switched to mode 0 at full speed.
    m.set_mode(A1, modes::POSITION);
    let t = trace(&mut m, A1, 15);
    assert_eq!(incs(&t), cat(&[&seq(10, 100, 10), &[100; 5]]));
    assert_eq!(t[14].pos, 1050);
    m.set_mode(A1, modes::NONE);
    let t = trace(&mut m, A1, 15);
    assert_eq!(incs(&t), cat(&[&seq(90, 10, -10), &[0; 6]]));
    assert_eq!(bit10(&t), cat_bools(&[false; 9], &[true; 6]));
    assert_eq!(m.act_val(A1), 1500);
}

/// X67-18.11.3.3-03: in every mode, bit 10 is set when the action has finished: mode 1 in the cycle the
/// axis arrives, mode 2 once the speed equals the set-point; at standstill outside Operation enable it is 1
/// (pick).
#[test]
fn x67_18_11_3_3_03_target_reached_for_all_modes() {
    let mut m = Module::new();
    set_ramp(&mut m, A1, 100, 10, 10);
    m.set_mode(A1, modes::POSITION);
    switch_on(&mut m, A1);
    assert_ne!(m.status_word(A1) & SW_TARGET_REACHED, 0);

    enable_operation(&mut m, A1);
    m.set_abs_pos(A1, 1000);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), profile(0, 1));
    assert_eq!(bit10(&t), moving_then_reached(20));
    assert_eq!(m.act_val(A1), 1000);

    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 30);
    let t = trace(&mut m, A1, 5);
    assert_eq!(incs(&t), [10, 20, 30, 30, 30]);
    assert_eq!(bit10(&t), [false, false, true, true, true]);
}

/// X67-18.11.3.3-04: a new set-point before the action has finished re-plans from the current speed without
/// a jump: speed set-point 100, then 20 while still accelerating (MaxAcc 10, MaxDec 5); and a change from
/// speed mode to mode 1 during motion continues from the current speed (pick).
#[test]
fn x67_18_11_3_3_04_new_setpoint_replans_without_jump() {
    let mut m = enabled(100, 10, 5);
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 100);
    let t = trace(&mut m, A1, 3);
    assert_eq!(incs(&t), [10, 20, 30]);
    m.set_abs_pos(A1, 20);
    let t = trace(&mut m, A1, 4);
    assert_eq!(incs(&t), [25, 20, 20, 20]);

    // Speed mode at 100, then mode 1 with a far target: the speed stays 100, no drop to 0.
    m.set_abs_pos(A1, 100);
    let t = trace(&mut m, A1, 8);
    assert_eq!(incs(&t), [30, 40, 50, 60, 70, 80, 90, 100]);
    let here = m.act_val(A1);
    m.set_mode(A1, modes::POSITION);
    m.set_abs_pos(A1, here + 10_000);
    let t = trace(&mut m, A1, 5);
    assert_eq!(incs(&t), [100; 5]);
}

/// X67-18.11.3.3-05: an unlisted mode value acts as mode 0 (pick): no motion at standstill, braking during a
/// move; ModeReadback01 returns the value written.
#[test]
fn x67_18_11_3_3_05_unlisted_mode_acts_as_mode_0() {
    for mode in [5i8, 3, -1, -119, 127] {
        let mut m = standard();
        m.set_mode(A1, mode);
        m.set_abs_pos(A1, 5000);
        let t = trace(&mut m, A1, 20);
        assert!(t.iter().all(|c| c.inc == 0 && c.reached()), "mode {mode}");
        assert_eq!(read(&m, "ModeReadback0n", A1), i64::from(mode));

        m.set_mode(A1, modes::POSITION);
        trace(&mut m, A1, 12);
        m.set_mode(A1, mode);
        let t = trace(&mut m, A1, 11);
        assert_eq!(incs(&t), cat(&[&seq(90, 10, -10), &[0, 0]]), "mode {mode}");
        assert_eq!(m.act_val(A1), 550 + 200 + 450);
    }
}

// =====================================================================================================
// 18.11.3.3.1 Mode 1: position mode
// =====================================================================================================

/// X67-18.11.3.3.1-01: MaxSpeed 100, MaxAcc = MaxDec = 10, AbsPos01 = 10 000: increments 10, 20, …, 100, a
/// cruise at 100, then 90, …, 10; the axis ends exactly at 10 000 with bit 10 = 1.
#[test]
fn x67_18_11_3_3_1_01_position_mode_trapezoid() {
    let mut m = standard();
    m.set_abs_pos(A1, 10_000);
    let t = until_reached(&mut m, A1, 200);
    assert_eq!(incs(&t), profile(90, 1));
    assert_eq!(bit10(&t), moving_then_reached(110));
    assert_eq!(m.act_val(A1), 10_000);
    assert_eq!(state(&m, A1), OPERATION_ENABLE);
    // It stays there.
    let t = trace(&mut m, A1, 10);
    assert!(t
        .iter()
        .all(|c| c.inc == 0 && c.pos == 10_000 && c.reached()));
}

/// X67-18.11.3.3.1-02: without the extended control word AbsPos01 is the target as soon as it differs: the
/// move starts in the next cycle, a new value in mid-move re-plans at once (brake, reverse, end at 1000), and
/// entering Operation enable with AbsPos01 ≠ actual starts a move at once.
#[test]
fn x67_18_11_3_3_1_02_abs_pos_taken_at_once() {
    let mut m = standard();
    m.set_abs_pos(A1, 10_000);
    let t = trace(&mut m, A1, 20);
    assert_eq!(incs(&t), cat(&[&seq(10, 100, 10), &[100; 10]]));
    assert_eq!(m.act_val(A1), 1550);
    m.set_abs_pos(A1, 1000);
    let t = until_reached(&mut m, A1, 100);
    // Brake to 2000, one cycle at rest, then back 1000.
    assert_eq!(incs(&t), cat(&[&seq(90, 10, -10), &[0], &profile(0, -1)]));
    assert_eq!(t[8].pos, 2000);
    assert_eq!(m.act_val(A1), 1000);
    assert!(bit10(&t)[..t.len() - 1].iter().all(|b| !b));

    let mut m = Module::new();
    set_ramp(&mut m, A1, 100, 10, 10);
    m.set_mode(A1, modes::POSITION);
    switch_on(&mut m, A1);
    m.set_abs_pos(A1, 1000);
    let before = m.act_val(A1);
    enable_operation(&mut m, A1);
    assert_eq!(m.act_val(A1) - before, 10);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), profile(0, 1)[1..]);
    assert_eq!(m.act_val(A1), 1000);
}

// =====================================================================================================
// 18.11.3.3.2 Mode 1 with the extended control word
// =====================================================================================================

/// X67-18.11.3.3.2-01: with the extended control word a change of AbsPos01 alone starts nothing, and SW bit 12
/// stays 0; the same change without it moves the axis.
#[test]
fn x67_18_11_3_3_2_01_abs_pos_alone_changes_nothing() {
    let mut m = standard_ext();
    for v in [5000, -3000, 12_345] {
        m.set_abs_pos(A1, v);
        let t = trace(&mut m, A1, 10);
        assert!(
            t.iter().all(|c| c.inc == 0 && c.pos == 0 && !c.ack()),
            "{v}"
        );
    }
    let mut m = standard();
    m.set_abs_pos(A1, 5000);
    assert_eq!(cycle(&mut m, A1).inc, 10);
}

/// X67-18.11.3.3.2-02: while SW bit 12 = 1 a new set-point is not accepted. Here bit 12 stays 1 because a
/// single set-point (bit 5 = 0) waits for the move to arrive (X67-18.11.3.3.2-04 pick); a further handshake
/// with AbsPos01 = 5000 in that time is ignored.
#[test]
fn x67_18_11_3_3_2_02_setpoint_ignored_while_acknowledged() {
    let mut m = standard_ext();
    let mut t = vec![handshake(&mut m, 10_000, 0)];
    t.push(release(&mut m, 0));
    t.extend(trace(&mut m, A1, 27));
    assert!(t[1..].iter().all(|c| !c.ack()));
    // Cycle 30: the second set-point is queued.
    t.push(handshake(&mut m, 20_000, 0));
    t.push(release(&mut m, 0));
    t.extend(trace(&mut m, A1, 8));
    // Cycle 40: a third handshake while bit 12 is still 1.
    assert!(t.last().unwrap().ack());
    t.push(handshake(&mut m, 5000, 0));
    t.push(release(&mut m, 0));
    t.extend(until_reached(&mut m, A1, 200));
    // The first move ends at 10 000 in cycle 110 (bit 10 = 1 there), the second starts in cycle 111.
    t.extend(until_reached(&mut m, A1, 200));
    assert_eq!(incs(&t), cat(&[&profile(90, 1), &profile(90, 1)]));
    assert_eq!(t[109].pos, 10_000);
    assert!(t[109].reached());
    assert_eq!(m.act_val(A1), 20_000);
    let ack: Vec<bool> = t.iter().map(|c| c.ack()).collect();
    let expected: Vec<bool> = (1..=t.len())
        .map(|k| k == 1 || (30..=110).contains(&k))
        .collect();
    assert_eq!(ack, expected);
    // 5000 never became a target.
    let t = trace(&mut m, A1, 20);
    assert!(t.iter().all(|c| c.pos == 20_000));
}

/// X67-18.11.3.3.2-03: a rising edge on CW bit 4 while bit 12 = 0 takes AbsPos01 as the target: bit 12 = 1
/// and the move begins in the same cycle.
#[test]
fn x67_18_11_3_3_2_03_new_setpoint_edge_takes_target() {
    let mut m = standard_ext();
    let c = handshake(&mut m, 4000, 0);
    assert!(c.ack());
    assert_eq!(c.inc, 10);
    release(&mut m, 0);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(m.act_val(A1), 4000);
    assert_eq!(incs(&t), profile(30, 1)[2..]);
}

/// X67-18.11.3.3.2-04: after the master clears CW bit 4 the module clears bit 12 in the next cycle when no
/// set-point is queued; bit 12 stays 1 as long as bit 4 stays 1.
#[test]
fn x67_18_11_3_3_2_04_ack_cleared_after_bit_4() {
    let mut m = standard_ext();
    assert!(handshake(&mut m, 4000, 0).ack());
    let held = trace(&mut m, A1, 5);
    assert!(held.iter().all(|c| c.ack()));
    let c = release(&mut m, 0);
    assert!(!c.ack());
    assert!(trace(&mut m, A1, 5).iter().all(|c| !c.ack()));
}

/// X67-18.11.3.3.2-05: with bit 5 = 0 the current move to 10 000 is finished first: the increment reaches 0
/// at 10 000 with bit 10 = 1 for that cycle, and the move to 20 000 starts in the next cycle.
#[test]
fn x67_18_11_3_3_2_05_single_setpoint_finishes_move_first() {
    let mut m = standard_ext();
    let mut t = vec![handshake(&mut m, 10_000, 0), release(&mut m, 0)];
    t.extend(trace(&mut m, A1, 27));
    t.push(handshake(&mut m, 20_000, 0));
    t.push(release(&mut m, 0));
    t.extend(until_reached(&mut m, A1, 200));
    assert_eq!(t.len(), 110);
    assert_eq!((t[109].inc, t[109].pos), (0, 10_000));
    assert_eq!(bit10(&t), moving_then_reached(110));
    let t = until_reached(&mut m, A1, 200);
    assert_eq!(incs(&t), profile(90, 1));
    assert_eq!(bit10(&t), moving_then_reached(110));
    assert_eq!(m.act_val(A1), 20_000);
}

/// X67-18.11.3.3.2-06: with bit 5 = 1 the move is broken off and the axis turns to the new target at once:
/// the speed stays 100 past 10 000 and the axis ends at 20 000.
#[test]
fn x67_18_11_3_3_2_06_set_of_setpoints_switches_at_once() {
    let mut m = standard_ext();
    let mut t = vec![handshake(&mut m, 10_000, 0), release(&mut m, 0)];
    t.extend(trace(&mut m, A1, 27));
    let c = handshake(&mut m, 20_000, CW_CHANGE_IMMEDIATELY);
    assert!(c.ack());
    t.push(c);
    let c = release(&mut m, CW_CHANGE_IMMEDIATELY);
    assert!(!c.ack());
    t.push(c);
    t.extend(until_reached(&mut m, A1, 300));
    assert_eq!(incs(&t), profile(190, 1));
    assert_eq!(m.act_val(A1), 20_000);
}

/// X67-18.11.3.3.2-07: with bit 6 = 0 the value is absolute: 3000 twice ends at 3000 both times.
#[test]
fn x67_18_11_3_3_2_07_absolute_setpoint() {
    let mut m = standard_ext();
    let mut t = vec![handshake(&mut m, 3000, 0), release(&mut m, 0)];
    t.extend(until_reached(&mut m, A1, 100));
    assert_eq!(incs(&t), profile(20, 1));
    assert_eq!(m.act_val(A1), 3000);
    let mut t = vec![handshake(&mut m, 3000, 0), release(&mut m, 0)];
    t.extend(trace(&mut m, A1, 30));
    assert!(t.iter().all(|c| c.inc == 0 && c.pos == 3000 && c.reached()));
}

/// X67-18.11.3.3.2-08: with bit 6 = 1 each handshake moves the target by AbsPos01: +1000, +1000, −500 give
/// 1000, 2000, 1500.
#[test]
fn x67_18_11_3_3_2_08_relative_setpoint() {
    let mut m = standard_ext();
    for (value, target) in [(1000, 1000), (1000, 2000), (-500, 1500)] {
        let mut t = vec![
            handshake(&mut m, value, CW_RELATIVE),
            release(&mut m, CW_RELATIVE),
        ];
        t.extend(until_reached(&mut m, A1, 100));
        assert_eq!(m.act_val(A1), target);
        if value == 1000 {
            assert_eq!(incs(&t), profile(0, 1));
        }
    }
}

/// X67-18.11.3.3.2-09: relative set-points build on the last specified target even across a mode change and
/// other motion: relative 1000 reached, mode 2 runs the axis to 5000, back to mode 1 with +100 → 1100.
#[test]
fn x67_18_11_3_3_2_09_relative_base_across_mode_change() {
    let mut m = standard_ext();
    handshake(&mut m, 1000, CW_RELATIVE);
    release(&mut m, CW_RELATIVE);
    until_reached(&mut m, A1, 100);
    assert_eq!(m.act_val(A1), 1000);

    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 100);
    let t = trace(&mut m, A1, 40);
    assert_eq!(incs(&t), cat(&[&seq(10, 100, 10), &[100; 30]]));
    m.set_abs_pos(A1, 0);
    let t = trace(&mut m, A1, 10);
    assert_eq!(incs(&t), cat(&[&seq(90, 10, -10), &[0]]));
    assert_eq!(m.act_val(A1), 5000);

    // Back in mode 1 nothing moves until a handshake; the old target 1000 is not resumed.
    m.set_mode(A1, modes::POSITION);
    let t = trace(&mut m, A1, 5);
    assert!(t.iter().all(|c| c.pos == 5000));
    let mut t = vec![
        handshake(&mut m, 100, CW_RELATIVE),
        release(&mut m, CW_RELATIVE),
    ];
    t.extend(until_reached(&mut m, A1, 200));
    assert_eq!(incs(&t), profile(29, -1));
    assert_eq!(m.act_val(A1), 1100);
}

/// X67-18.11.3.3.2-10: the base of relative set-points is 0 after start-up, not the actual position: after
/// speed mode has run the axis to 5000, the first relative +700 ends at 700.
#[test]
fn x67_18_11_3_3_2_10_relative_base_zero_after_start() {
    let mut m = standard_ext();
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 100);
    trace(&mut m, A1, 50);
    m.set_abs_pos(A1, 0);
    trace(&mut m, A1, 10);
    assert_eq!(m.act_val(A1), 5000);
    m.set_mode(A1, modes::POSITION);
    handshake(&mut m, 700, CW_RELATIVE);
    release(&mut m, CW_RELATIVE);
    until_reached(&mut m, A1, 200);
    assert_eq!(m.act_val(A1), 700);
}

/// X67-18.11.3.3.2-11: SW bit 12 is 1 once the ramp generator has taken the value and 0 before: 0 while only
/// AbsPos01 changes, 1 from the cycle of the edge, 0 again after the release.
#[test]
fn x67_18_11_3_3_2_11_bit_12_shows_value_taken() {
    let mut m = standard_ext();
    m.set_abs_pos(A1, 2000);
    let before = cycle(&mut m, A1);
    assert!(!before.ack() && before.inc == 0);
    let mut t = vec![handshake(&mut m, 2000, 0)];
    t.extend(trace(&mut m, A1, 2));
    t.push(release(&mut m, 0));
    assert_eq!(
        t.iter().map(|c| c.ack()).collect::<Vec<_>>(),
        [true, true, true, false]
    );
    assert_eq!(incs(&t), [10, 20, 30, 40]);
}

/// The observable registers of one cycle: SW without bits 10 and 12, AbsPos01ActVal,
/// AbsPos01ActValAcyclic and ErrorCode01.
type Regs = (u16, i32, i64, i64);

fn regs(m: &Module) -> Regs {
    (
        m.status_word(A1) & !(SW_TARGET_REACHED | SW_SETPOINT_ACK),
        m.act_val(A1),
        read(m, "AbsPos0nActValAcyclic", A1),
        read(m, "ErrorCode0n", A1),
    )
}

/// The same command sequence with GeneralConfig01 bit 0 = `ext`: state-machine commands, mode −122, counter
/// swap (bit 14), a limit-switch warning and its reset (↑ bit 12), quick stop. One list of cycles per phase.
fn standard_bits_scenario(ext: bool) -> Vec<Vec<Regs>> {
    let mut m = Module::new();
    m.write_named("GeneralConfig01", i64::from(ext)).unwrap();
    write(&mut m, "LimitSwitchConfig0n", A1, 0x0C); // positive switch (DI2) active high
    let run = |m: &mut Module, cw: u16, n: usize| -> Vec<Regs> {
        m.set_control(A1, cw);
        (0..n)
            .map(|_| {
                m.step();
                regs(m)
            })
            .collect()
    };
    let mut phases = vec![
        run(&mut m, 0, 1),
        run(&mut m, SHUTDOWN, 1),
        run(&mut m, SWITCH_ON, 45),
    ];
    m.set_mode(A1, modes::SET_POSITION);
    m.set_abs_pos(A1, 777);
    phases.push(run(&mut m, ENABLE_OPERATION, 2));
    phases.push(run(&mut m, ENABLE_OPERATION | CW_SWAP_COUNTERS, 2));
    m.set_input(2, true);
    phases.push(run(&mut m, ENABLE_OPERATION | CW_SWAP_COUNTERS, 2));
    phases.push(run(
        &mut m,
        ENABLE_OPERATION | CW_SWAP_COUNTERS | CW_WARNING_RESET,
        2,
    ));
    phases.push(run(&mut m, QUICK_STOP_FROM_ENABLED | CW_SWAP_COUNTERS, 3));
    phases.push(run(&mut m, CW_SWAP_COUNTERS, 2));
    phases
}

/// X67-18.11.3.3.2-12: with the extended control word CW bits 0–3, 7 and 9–15 and SW bits 0–9, 11 and 13–15
/// keep their meaning: the same commands give the same status bits and registers with GeneralConfig01 bit 0
/// = 0 and 1.
#[test]
fn x67_18_11_3_3_2_12_other_bits_keep_meaning() {
    let plain = standard_bits_scenario(false);
    let ext = standard_bits_scenario(true);
    assert_eq!(plain, ext);
    let last = |k: usize| *ext[k].last().unwrap();
    let state_of = |r: Regs| r.0 & STATE_MASK;
    assert_eq!(last(0).0 & DISABLED_MASK, SWITCH_ON_DISABLED);
    assert_eq!(state_of(last(1)), READY);
    assert_eq!(state_of(last(2)), SWITCHED_ON);
    // Mode −122 sets the internal counter on Enable operation; bit 14 swaps it into the acyclic register.
    assert_eq!(state_of(last(3)), OPERATION_ENABLE);
    assert_eq!((last(3).1, last(3).2), (777, 0));
    assert_eq!((last(4).1, last(4).2), (0, 777));
    // The positive limit switch raises 0xFF21 and bit 7; ↑ bit 12 resets it. DI2 rising also counted the
    // ABR counter down by one (4x quadrature, X67-3-09), shown cyclically with bit 14.
    assert_eq!(
        (last(5).3, last(5).0 & SW_WARNING, last(5).1),
        (0xFF21, SW_WARNING, -1)
    );
    assert_eq!((last(6).3, last(6).0 & SW_WARNING), (0, 0));
    assert_eq!(state_of(last(6)), OPERATION_ENABLE);
    // Quick stop at standstill ends in Switch on disabled.
    assert_eq!(last(7).0 & DISABLED_MASK, SWITCH_ON_DISABLED);
    assert_eq!(last(8).0 & DISABLED_MASK, SWITCH_ON_DISABLED);
}

// =====================================================================================================
// 18.11.3.3.3 Mode 2: speed mode
// =====================================================================================================

/// X67-18.11.3.3.3-01: mode 2 ramps to the speed set-point with MaxAcc01 and holds it: MaxAcc01 = 5,
/// AbsPos01 = 50 → increments 5, 10, …, 50, 50, …; a lower set-point brakes with MaxDec01 (pick), through 0
/// to the other sign.
#[test]
fn x67_18_11_3_3_3_01_speed_mode_ramps_to_setpoint() {
    let mut m = enabled(0, 5, 20);
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 50);
    let t = trace(&mut m, A1, 15);
    assert_eq!(incs(&t), cat(&[&seq(5, 50, 5), &[50; 5]]));
    m.set_abs_pos(A1, -10);
    let t = trace(&mut m, A1, 6);
    assert_eq!(incs(&t), [30, 10, 0, -5, -10, -10]);
}

/// X67-18.11.3.3.3-02: speed set-points are clamped to ±65 535.
#[test]
fn x67_18_11_3_3_3_02_speed_setpoint_clamped() {
    let mut m = enabled(0, 60_000, 65_535);
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 100_000);
    let t = trace(&mut m, A1, 4);
    assert_eq!(incs(&t), [60_000, 65_535, 65_535, 65_535]);
    m.set_abs_pos(A1, -70_000);
    let t = trace(&mut m, A1, 4);
    assert_eq!(incs(&t), [0, -60_000, -65_535, -65_535]);
}

// =====================================================================================================
// 18.11.3.3.4 Mode −120: set home position
// =====================================================================================================

/// X67-18.11.3.3.4-01: homing recorded the reference at 12 345, the axis stands at 12 400; mode −120 with
/// AbsPos01 = 0 gives AbsPos01ActVal = 55 and RefPos01CyclicCounter = 0, without motion; bit 10 is 0 for
/// that cycle (as in −122).
#[test]
fn x67_18_11_3_3_4_01_set_home_shifts_counter() {
    let mut m = standard();
    move_to(&mut m, 12_345);
    // Immediate referencing stores the counters where the axis stands.
    write(&mut m, "RefConfig0n", A1, i64::from(ref_config::IMMEDIATE));
    m.set_mode(A1, modes::HOMING_POSITIVE);
    trace(&mut m, A1, 2);
    assert_eq!(read(&m, "RefPos0nCyclicCounter", A1), 12_345);
    move_to(&mut m, 12_400);
    let rotor = m.axis(A1).motor.rotor();

    m.set_mode(A1, modes::SET_HOME);
    m.set_abs_pos(A1, 0);
    let t = trace(&mut m, A1, 5);
    assert_eq!(positions(&t), [55; 5]);
    assert_eq!(bit10(&t), [false, true, true, true, true]);
    assert_eq!(read(&m, "RefPos0nCyclicCounter", A1), 0);
    assert_eq!(m.axis(A1).motor.rotor(), rotor);
    assert_eq!(state(&m, A1), OPERATION_ENABLE);

    // A new AbsPos01 in −120 shifts again: reference 0 → 1000 moves the counter by +1000.
    m.set_abs_pos(A1, 1000);
    let t = trace(&mut m, A1, 3);
    assert_eq!(positions(&t), [1055; 3]);
    assert_eq!(read(&m, "RefPos0nCyclicCounter", A1), 1000);
}

/// X67-18.11.3.3.4-02: mode −120 acts only in Operation enable: in Switched on nothing changes, on Enable
/// operation the shift happens, with reference 0 when the axis was never homed (pick).
#[test]
fn x67_18_11_3_3_4_02_set_home_only_in_operation_enable() {
    let mut m = standard();
    move_to(&mut m, 12_400);
    m.set_control(A1, SWITCH_ON);
    m.step();
    assert_eq!(state(&m, A1), SWITCHED_ON);
    m.set_mode(A1, modes::SET_HOME);
    m.set_abs_pos(A1, 100);
    let t = trace(&mut m, A1, 5);
    assert_eq!(positions(&t), [12_400; 5]);
    assert_eq!(read(&m, "RefPos0nCyclicCounter", A1), 0);
    enable_operation(&mut m, A1);
    assert_eq!(m.act_val(A1), 12_500);
    assert_eq!(read(&m, "RefPos0nCyclicCounter", A1), 100);
}

// =====================================================================================================
// 18.11.3.3.5 Mode −121: remaining distance
// =====================================================================================================

/// X67-18.11.3.3.5-01: before the trigger, mode −121 follows AbsPos01 as mode 1 does: 3000 is approached
/// on the mode-1 profile; bit 10 stays 0 (-04).
#[test]
fn x67_18_11_3_3_5_01_before_trigger_like_mode_1() {
    let mut m = standard();
    m.set_mode(A1, modes::REMAINING_DISTANCE);
    m.set_abs_pos(A1, 3000);
    let t = trace(&mut m, A1, 50);
    assert_eq!(incs(&t), cat(&[&profile(20, 1), &[0; 10]]));
    assert_eq!(m.act_val(A1), 3000);
    assert!(t.iter().all(|c| !c.reached()));
}

/// X67-18.11.3.3.5-02: at the trigger the target becomes the actual position at that instant plus
/// FixedPos01a: moving toward 10 000, DI3 rises at 4321 (a cam on the rotor) with FixedPos01a = −1000 → the
/// axis brakes, returns and ends at 3321.
#[test]
fn x67_18_11_3_3_5_02_trigger_target_is_actual_plus_offset() {
    let mut m = standard();
    write(&mut m, "FixedPos0na", A1, -1000);
    m.attach_cam(
        DI3,
        Cam {
            axis: A1,
            from: 4321,
            to: i64::from(i32::MAX),
        },
    );
    m.set_mode(A1, modes::REMAINING_DISTANCE);
    m.set_abs_pos(A1, 10_000);
    // 550 after 10 cycles, then 100 a cycle: the rotor passes 4321 in cycle 48 (4250 → 4350).
    let t = trace(&mut m, A1, 48);
    assert_eq!(m.act_val(A1), 4350);
    assert_eq!(m.input_status() & 0x04, 0x04);
    assert!(t.iter().all(|c| !c.reached()));
    let t = until_reached(&mut m, A1, 200);
    assert_eq!(incs(&t)[..10], cat(&[&seq(90, 10, -10), &[0]])[..]);
    assert_eq!(m.act_val(A1), 3321);
    assert_eq!(t.iter().map(|c| c.pos).max(), Some(4800));
}

/// X67-18.11.3.3.5-03: after the trigger AbsPos01 is ignored until the mode has been 0 and then −121 again.
#[test]
fn x67_18_11_3_3_5_03_abs_pos_ignored_after_trigger() {
    let mut m = standard();
    write(&mut m, "FixedPos0na", A1, 1000);
    m.set_mode(A1, modes::REMAINING_DISTANCE);
    m.set_abs_pos(A1, 3000);
    trace(&mut m, A1, 50);
    m.pulse_input(DI3);
    until_reached(&mut m, A1, 100);
    assert_eq!(m.act_val(A1), 4000);
    m.set_abs_pos(A1, 7000);
    let t = trace(&mut m, A1, 30);
    assert!(t.iter().all(|c| c.pos == 4000 && c.reached()));
    // Another edge does not re-trigger either.
    m.pulse_input(DI3);
    let t = trace(&mut m, A1, 30);
    assert!(t.iter().all(|c| c.pos == 4000));

    m.set_mode(A1, modes::NONE);
    m.step();
    m.set_mode(A1, modes::REMAINING_DISTANCE);
    let t = trace(&mut m, A1, 60);
    assert_eq!(incs(&t), cat(&[&profile(20, 1), &[0; 20]]));
    assert_eq!(m.act_val(A1), 7000);
    assert!(t.iter().all(|c| !c.reached()));
}

/// X67-18.11.3.3.5-04: bit 10 is 0 on reaching a target before the trigger and 1 once the end position after
/// the trigger is reached.
#[test]
fn x67_18_11_3_3_5_04_bit_10_only_after_trigger() {
    let mut m = standard();
    write(&mut m, "FixedPos0na", A1, 1000);
    m.set_mode(A1, modes::REMAINING_DISTANCE);
    m.set_abs_pos(A1, 3000);
    let t = trace(&mut m, A1, 60);
    assert_eq!(m.act_val(A1), 3000);
    assert!(t.iter().all(|c| !c.reached()));
    m.pulse_input(DI3);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), after_edge(profile(0, 1)));
    assert_eq!(bit10(&t), moving_then_reached(21));
    assert_eq!(m.act_val(A1), 4000);
}

/// Mode −121 standing at 3000 (pre-trigger) with RefConfig01 = `ref_config`, FixedPos01a = 1000 and DI3 at
/// `level` before the mode was selected.
fn remaining_at_3000(ref_config: i64, level: bool) -> Module {
    let mut m = standard();
    write(&mut m, "RefConfig0n", A1, ref_config);
    write(&mut m, "FixedPos0na", A1, 1000);
    m.set_input(DI3, level);
    m.step();
    m.set_mode(A1, modes::REMAINING_DISTANCE);
    m.set_abs_pos(A1, 3000);
    trace(&mut m, A1, 60);
    assert_eq!(m.act_val(A1), 3000);
    m
}

/// X67-18.11.3.3.5-05: the trigger is an edge on DI3; falling for RefConfig01 = −126 or −122, rising for every
/// other value, the default −125 included (pick).
#[test]
fn x67_18_11_3_3_5_05_trigger_edge_from_ref_config() {
    for (ref_config, falling) in [
        (-126, true),
        (-122, true),
        (-125, false),
        (-121, false),
        (-127, false),
        (-128, false),
    ] {
        // The wrong edge first: nothing happens.
        let mut m = remaining_at_3000(ref_config, !falling);
        m.set_input(DI3, falling);
        let t = trace(&mut m, A1, 20);
        assert!(
            t.iter().all(|c| c.pos == 3000 && !c.reached()),
            "{ref_config}"
        );
        // The right edge: the target becomes 3000 + 1000.
        m.set_input(DI3, !falling);
        let t = until_reached(&mut m, A1, 100);
        assert_eq!(incs(&t), after_edge(profile(0, 1)), "{ref_config}");
        assert_eq!(m.act_val(A1), 4000);
    }
    // The default is −125: rising.
    let mut m = standard();
    assert_eq!(read(&m, "RefConfig0n", A1), -125);
    write(&mut m, "FixedPos0na", A1, 1000);
    m.set_mode(A1, modes::REMAINING_DISTANCE);
    m.step();
    m.set_input(DI3, true);
    until_reached(&mut m, A1, 100);
    assert_eq!(m.act_val(A1), 1000);
}

/// X67-18.11.3.3.5-06: mode −121 ignores RevLoop01: with RevLoop01 = 500, no overshoot before or after the
/// trigger, whereas mode 1 overshoots on the same move.
#[test]
fn x67_18_11_3_3_5_06_no_reversing_loop() {
    let mut m = standard();
    write(&mut m, "RevLoop0n", A1, 500);
    write(&mut m, "FixedPos0na", A1, 1000);
    m.set_mode(A1, modes::REMAINING_DISTANCE);
    m.set_abs_pos(A1, 3000);
    let t = trace(&mut m, A1, 50);
    assert_eq!(incs(&t), cat(&[&profile(20, 1), &[0; 10]]));
    assert!(t.iter().all(|c| c.pos <= 3000));
    m.pulse_input(DI3);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), after_edge(profile(0, 1)));
    assert_eq!(m.act_val(A1), 4000);

    let mut m = standard();
    write(&mut m, "RevLoop0n", A1, 500);
    m.set_abs_pos(A1, 3000);
    let t = until_reached(&mut m, A1, 200);
    assert_eq!(t.iter().map(|c| c.pos).max(), Some(3500));
}

// =====================================================================================================
// 18.11.3.3.6 Mode −122: set actual position
// =====================================================================================================

/// X67-18.11.3.3.6-01: mode −122 writes AbsPos01 into the internal counter without moving the motor, and
/// again whenever AbsPos01 changes; the homing reference stays.
#[test]
fn x67_18_11_3_3_6_01_set_actual_position() {
    let mut m = standard();
    move_to(&mut m, 1000);
    m.set_mode(A1, modes::SET_POSITION);
    m.set_abs_pos(A1, 777);
    let t = trace(&mut m, A1, 5);
    assert_eq!(positions(&t), [777; 5]);
    assert_eq!(m.axis(A1).motor.rotor(), 1000);
    assert_eq!(read(&m, "RefPos0nCyclicCounter", A1), 0);
    m.set_abs_pos(A1, -5);
    let t = trace(&mut m, A1, 3);
    assert_eq!(positions(&t), [-5; 3]);
    assert_eq!(m.axis(A1).motor.rotor(), 1000);
    // Back in mode 1 the axis moves from the new value.
    m.set_mode(A1, modes::POSITION);
    m.set_abs_pos(A1, 995);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), profile(0, 1));
    assert_eq!(m.axis(A1).motor.rotor(), 2000);
}

/// X67-18.11.3.3.6-02: the position is set only in Operation enable: in Switched on nothing changes; on
/// Enable operation it is set. During motion it is set anyway and the ramp goes on from the new value
/// (pick): at speed 100 in mode 1, −122 with 0 → 90, 170, …, 450.
#[test]
fn x67_18_11_3_3_6_02_set_position_only_in_operation_enable() {
    let mut m = standard();
    move_to(&mut m, 1000);
    m.set_control(A1, SWITCH_ON);
    m.set_mode(A1, modes::SET_POSITION);
    m.set_abs_pos(A1, 777);
    let t = trace(&mut m, A1, 5);
    assert_eq!(state(&m, A1), SWITCHED_ON);
    assert_eq!(positions(&t), [1000; 5]);
    enable_operation(&mut m, A1);
    assert_eq!(m.act_val(A1), 777);

    let mut m = standard();
    m.set_abs_pos(A1, 10_000);
    trace(&mut m, A1, 20);
    assert_eq!(m.act_val(A1), 1550);
    m.set_mode(A1, modes::SET_POSITION);
    m.set_abs_pos(A1, 0);
    let t = trace(&mut m, A1, 11);
    assert_eq!(
        positions(&t),
        [90, 170, 240, 300, 350, 390, 420, 440, 450, 450, 450]
    );
    assert_eq!(m.axis(A1).motor.rotor(), 1550 + 450);
}

// =====================================================================================================
// 18.11.3.3.7 Mode −123: move to the target when the input rises
// =====================================================================================================

/// X67-18.11.3.3.7-01: in mode −123 AbsPos01 becomes the target only at a rising edge of DI3, and the axis
/// then moves there.
#[test]
fn x67_18_11_3_3_7_01_target_on_rising_edge() {
    let mut m = standard();
    m.set_mode(A1, modes::MOVE_ON_INPUT);
    m.set_abs_pos(A1, 8000);
    let t = trace(&mut m, A1, 20);
    assert!(t.iter().all(|c| c.pos == 0));
    m.set_input(DI3, true);
    let t = until_reached(&mut m, A1, 200);
    assert_eq!(incs(&t), after_edge(profile(70, 1)));
    assert_eq!(bit10(&t), moving_then_reached(t.len()));
    assert_eq!(m.act_val(A1), 8000);
}

/// X67-3-07 with X67-18.11.3.3.7-01: the inputs have no software filter, so a 50 µs pulse on DI3 that
/// falls between two cycles still triggers the set-point take-over of mode −123.
#[test]
fn x67_3_07_short_pulse_triggers_mode_123() {
    let mut m = standard();
    m.set_mode(A1, modes::MOVE_ON_INPUT);
    m.set_abs_pos(A1, 1000);
    m.step();
    m.pulse_input(DI3);
    assert_eq!(m.input_status() & 0x04, 0);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), after_edge(profile(0, 1)));
    assert_eq!(m.act_val(A1), 1000);
    assert_eq!(m.input_status() & 0x04, 0);
}

/// X67-18.11.3.3.7-02: a change of AbsPos01 without a new rising edge is not applied, with DI3 held high or
/// falling; the next rising edge applies it.
#[test]
fn x67_18_11_3_3_7_02_no_target_without_new_edge() {
    let mut m = standard();
    m.set_mode(A1, modes::MOVE_ON_INPUT);
    m.set_abs_pos(A1, 8000);
    m.set_input(DI3, true);
    until_reached(&mut m, A1, 200);
    assert_eq!(m.act_val(A1), 8000);
    m.set_abs_pos(A1, 9000);
    let t = trace(&mut m, A1, 20);
    assert!(t.iter().all(|c| c.pos == 8000 && c.reached()));
    m.set_input(DI3, false);
    let t = trace(&mut m, A1, 20);
    assert!(t.iter().all(|c| c.pos == 8000 && c.reached()));
    m.set_input(DI3, true);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), after_edge(profile(0, 1)));
    assert_eq!(m.act_val(A1), 9000);
}

/// X67-18.11.3.3.7-03: a rising edge during a move applies the current AbsPos01 at once: moving toward 8000 at
/// 2550, AbsPos01 = 2000 and a pulse on DI3 → the axis brakes, turns and ends at 2000 without going on to
/// 8000.
#[test]
fn x67_18_11_3_3_7_03_edge_during_move_applies_at_once() {
    let mut m = standard();
    m.set_mode(A1, modes::MOVE_ON_INPUT);
    m.set_abs_pos(A1, 8000);
    m.pulse_input(DI3);
    let t = trace(&mut m, A1, 31);
    assert_eq!(incs(&t), cat(&[&[0], &seq(10, 100, 10), &[100; 20]]));
    assert_eq!(m.act_val(A1), 2550);
    m.set_abs_pos(A1, 2000);
    m.pulse_input(DI3);
    let t = until_reached(&mut m, A1, 100);
    // The cycle that sees the edge still runs at 100 (2650); then brake to 3100, rest, back 1100.
    assert_eq!(
        incs(&t),
        cat(&[&[100], &seq(90, 10, -10), &[0], &profile(1, -1)])
    );
    assert_eq!(t.iter().map(|c| c.pos).max(), Some(3100));
    assert_eq!(m.act_val(A1), 2000);
}

// =====================================================================================================
// 18.11.3.3.8 Mode −124: two positions
// =====================================================================================================

/// X67-18.11.3.3.8-01: in mode −124 DI3 = 1 selects FixedPos01a and DI3 = 0 FixedPos01b.
#[test]
fn x67_18_11_3_3_8_01_input_level_selects_target() {
    let mut m = standard();
    write(&mut m, "FixedPos0na", A1, 1000);
    write(&mut m, "FixedPos0nb", A1, -1000);
    m.set_input(DI3, true);
    m.set_mode(A1, modes::TWO_POSITION);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), profile(0, 1));
    assert_eq!(m.act_val(A1), 1000);
    m.set_input(DI3, false);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), profile(10, -1));
    assert_eq!(m.act_val(A1), -1000);
}

/// X67-18.11.3.3.8-02: toggling DI3 during a move switches the target at once: heading for 5000 at 550 with
/// speed 100, DI3 falls → brake to 1000, turn, end at −1000.
#[test]
fn x67_18_11_3_3_8_02_toggle_during_move() {
    let mut m = standard();
    write(&mut m, "FixedPos0na", A1, 5000);
    write(&mut m, "FixedPos0nb", A1, -1000);
    m.set_input(DI3, true);
    m.set_mode(A1, modes::TWO_POSITION);
    let t = trace(&mut m, A1, 10);
    assert_eq!(incs(&t), seq(10, 100, 10));
    m.set_input(DI3, false);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), cat(&[&seq(90, 10, -10), &[0], &profile(10, -1)]));
    assert_eq!(t.iter().map(|c| c.pos).max(), Some(1000));
    assert_eq!(m.act_val(A1), -1000);
}

// =====================================================================================================
// 18.11.3.3.9 Mode −125/−126: fixed positions
// =====================================================================================================

/// X67-18.11.3.3.9-01: from speed mode at AbsPos01 = 80, mode −125 with FixedPos01a = 0 brakes, returns and
/// ends at 0; the 80 in AbsPos01 is never a target. Mode −126 goes to FixedPos01b the same way.
#[test]
fn x67_18_11_3_3_9_01_fixed_position_from_speed_mode() {
    for (mode, reg_name) in [
        (modes::FIXED_A, "FixedPos0na"),
        (modes::FIXED_B, "FixedPos0nb"),
    ] {
        let mut m = standard();
        write(&mut m, "FixedPos0na", A1, 0);
        write(&mut m, "FixedPos0nb", A1, 0);
        write(
            &mut m,
            if mode == modes::FIXED_A {
                "FixedPos0nb"
            } else {
                "FixedPos0na"
            },
            A1,
            3000,
        );
        m.set_mode(A1, modes::SPEED);
        m.set_abs_pos(A1, 80);
        let t = trace(&mut m, A1, 15);
        assert_eq!(incs(&t), cat(&[&seq(10, 80, 10), &[80; 7]]));
        assert_eq!(m.act_val(A1), 920);
        m.set_mode(A1, mode);
        let t = until_reached(&mut m, A1, 100);
        assert_eq!(
            incs(&t),
            cat(&[&seq(70, 10, -10), &[0], &profile(2, -1)]),
            "{reg_name}"
        );
        assert_eq!(m.act_val(A1), 0);
        let t = trace(&mut m, A1, 20);
        assert!(t.iter().all(|c| c.pos == 0 && c.reached()));
    }
}

// =====================================================================================================
// 18.11.3.1 Set position/speed
// =====================================================================================================

/// X67-18.11.3.1-01: in the position modes AbsPos01 is in microsteps of 1/256 full step: 51 200 turns a
/// 200-step motor by one revolution.
#[test]
fn x67_18_11_3_1_01_abs_pos_in_microsteps() {
    let mut m = standard();
    assert_eq!(m.axis(A1).motor.params.steps_per_rev, 200);
    m.set_abs_pos(A1, 51_200);
    let t = until_reached(&mut m, A1, 1000);
    assert_eq!(incs(&t), profile(502, 1));
    assert_eq!(m.axis(A1).motor.rotor(), 51_200);
    assert_eq!(m.axis(A1).motor.full_steps(), 200.0);
}

/// X67-18.11.3.1-02: in mode 2 AbsPos01 is a signed speed in microsteps/cycle: −40 → the counter falls by 40
/// a cycle once the ramp is done.
#[test]
fn x67_18_11_3_1_02_speed_setpoint_signed() {
    let mut m = standard();
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, -40);
    let t = trace(&mut m, A1, 8);
    assert_eq!(incs(&t), [-10, -20, -30, -40, -40, -40, -40, -40]);
    assert_eq!(m.act_val(A1), -260);
}

/// X67-18.11.3.1-03: modes −124, −125 and −126 take their targets from FixedPos01a/b and the homing modes their
/// speed from RefSpeed01; AbsPos01 changing every cycle has no effect.
#[test]
fn x67_18_11_3_1_03_abs_pos_unused_in_fixed_and_homing_modes() {
    for mode in [modes::TWO_POSITION, modes::FIXED_A, modes::FIXED_B] {
        let mut m = standard();
        write(&mut m, "FixedPos0na", A1, 5000);
        write(&mut m, "FixedPos0nb", A1, -5000);
        m.set_input(DI3, true);
        m.set_mode(A1, mode);
        let mut t = Vec::new();
        for k in 0..130 {
            m.set_abs_pos(A1, k * 977 - 40_000);
            t.push(cycle(&mut m, A1));
        }
        let dir = if mode == modes::FIXED_B { -1 } else { 1 };
        assert_eq!(incs(&t)[..60], profile(40, dir)[..], "mode {mode}");
        assert_eq!(m.act_val(A1), 5000 * dir);
    }
    let mut m = standard();
    write(&mut m, "RefSpeed0n", A1, 40);
    m.set_mode(A1, modes::HOMING_POSITIVE);
    let mut t = Vec::new();
    for k in 0..10 {
        m.set_abs_pos(A1, -k * 3000);
        t.push(cycle(&mut m, A1));
    }
    assert_eq!(incs(&t), [10, 20, 30, 40, 40, 40, 40, 40, 40, 40]);
}

// =====================================================================================================
// 18.11.3.2 Control word bits 4–6, 8, 9, 10
// =====================================================================================================

/// X67-18.11.3.2-01: without the extended control word bits 4–6 have no effect: toggled every cycle, they
/// change neither the state nor the motion nor the status word.
#[test]
fn x67_18_11_3_2_01_bits_4_to_6_without_ext_cw() {
    let plain = move_with_control(false, |_| ENABLE_OPERATION);
    let toggled = move_with_control(false, |k| ENABLE_OPERATION | ((k as u16 * 5) & 7) << 4);
    assert_eq!(incs(&plain), cat(&[&profile(20, 1), &[0; 10]]));
    assert_eq!(toggled, plain);
    assert!(toggled.iter().all(|c| !c.ack()));
}

/// X67-18.11.3.2-02: with the extended control word bit 8 (Stop) brakes in every mode: mode 2 at speed 100,
/// Stop → the speed falls by MaxDec01 = 20 to 0 and bit 10 = 1 at 0; Stop back to 0 resumes the set-point
/// (pick). Without the extended control word bit 8 has no effect.
#[test]
fn x67_18_11_3_2_02_stop_bit() {
    let mut m = Module::new();
    m.write_named("GeneralConfig01", 1).unwrap();
    set_ramp(&mut m, A1, 100, 10, 20);
    m.set_mode(A1, modes::SPEED);
    switch_on(&mut m, A1);
    enable_operation(&mut m, A1);
    m.set_abs_pos(A1, 100);
    let t = trace(&mut m, A1, 12);
    assert_eq!(incs(&t), cat(&[&seq(10, 100, 10), &[100; 2]]));
    m.set_control(A1, ENABLE_OPERATION | CW_STOP);
    let t = trace(&mut m, A1, 8);
    assert_eq!(incs(&t), [80, 60, 40, 20, 0, 0, 0, 0]);
    assert_eq!(
        bit10(&t),
        [false, false, false, false, true, true, true, true]
    );
    assert_eq!(state(&m, A1), OPERATION_ENABLE);
    m.set_control(A1, ENABLE_OPERATION);
    let t = trace(&mut m, A1, 11);
    assert_eq!(incs(&t), cat(&[&seq(10, 100, 10), &[100]]));
    assert_eq!(bit10(&t), cat_bools(&[false; 9], &[true; 2]));

    let mut m = enabled(100, 10, 20);
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 100);
    trace(&mut m, A1, 12);
    m.set_control(A1, ENABLE_OPERATION | CW_STOP);
    let t = trace(&mut m, A1, 8);
    assert!(t.iter().all(|c| c.inc == 100 && c.reached()));
}

/// X67-18.11.3.2-03: CW bit 9 (CurrentControlEnable) has no function: with it set through the whole start-up
/// and a move, states and motion are those without it; ControlReadback01 shows it.
#[test]
fn x67_18_11_3_2_03_bit_9_no_function() {
    const BIT_9: u16 = 1 << 9;
    let mut m = Module::new();
    set_ramp(&mut m, A1, 100, 10, 10);
    m.set_mode(A1, modes::POSITION);
    m.step();
    m.set_control(A1, SHUTDOWN | BIT_9);
    m.step();
    assert_eq!(state(&m, A1), READY);
    m.set_control(A1, SWITCH_ON | BIT_9);
    m.run(41);
    assert_eq!(state(&m, A1), SWITCHED_ON);
    m.set_control(A1, ENABLE_OPERATION | BIT_9);
    m.step();
    assert_eq!(state(&m, A1), OPERATION_ENABLE);
    assert_eq!(read(&m, "ControlReadback0n", A1), 0x020F);
    m.set_abs_pos(A1, 3000);
    let with = trace(&mut m, A1, 50);
    assert_eq!(with, move_with_control(false, |_| ENABLE_OPERATION));
}

/// X67-18.11.3.2-04: CW bit 10 is reserved: setting it changes nothing but ControlReadback01.
#[test]
fn x67_18_11_3_2_04_bit_10_reserved() {
    let plain = move_with_control(false, |_| ENABLE_OPERATION);
    let with = move_with_control(false, |k| {
        ENABLE_OPERATION | if k % 3 == 0 { 1 << 10 } else { 0 }
    });
    assert_eq!(with, plain);
    let mut m = standard();
    m.set_control(A1, ENABLE_OPERATION | 1 << 10);
    m.step();
    assert_eq!(read(&m, "ControlReadback0n", A1), 0x040F);
    assert_eq!(state(&m, A1), OPERATION_ENABLE);
}

// =====================================================================================================
// 18.11.1.3–18.11.1.8 Ramp registers and fixed positions as the modes use them
// =====================================================================================================

/// X67-18.11.1.3-01: in the positioning modes 1, −123, −124, −125 and −126 (and −121, pick) the speed never
/// exceeds MaxSpeed01pos and is exactly MaxSpeed01pos while cruising. With MaxSpeed01pos = 0 no move starts
/// and bit 10 stays 0 (pick).
#[test]
fn x67_18_11_1_3_01_max_speed_in_positioning_modes() {
    for mode in [
        modes::POSITION,
        modes::REMAINING_DISTANCE,
        modes::MOVE_ON_INPUT,
        modes::TWO_POSITION,
        modes::FIXED_A,
        modes::FIXED_B,
    ] {
        let mut m = standard();
        let late = start_move(&mut m, mode, 20_000);
        let t = trace(&mut m, A1, 220);
        let expected = if late {
            after_edge(profile(190, 1))
        } else {
            profile(190, 1)
        };
        assert_eq!(incs(&t)[..expected.len()], expected[..], "mode {mode}");
        assert_eq!(m.act_val(A1), 20_000, "mode {mode}");
    }
    let mut m = enabled(0, 10, 10);
    m.set_abs_pos(A1, 5000);
    let t = trace(&mut m, A1, 20);
    assert!(t.iter().all(|c| c.pos == 0 && !c.reached()));
}

/// X67-18.11.1.3-02: MaxSpeed01pos has no effect in speed mode and in homing: MaxSpeed01pos = 10 and a speed
/// set-point of 500 reach 500; RefSpeed01 = 200 is reached as well.
#[test]
fn x67_18_11_1_3_02_max_speed_not_in_speed_mode_or_homing() {
    let mut m = enabled(10, 100, 100);
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 500);
    let t = trace(&mut m, A1, 7);
    assert_eq!(incs(&t), [100, 200, 300, 400, 500, 500, 500]);

    let mut m = enabled(10, 50, 50);
    write(&mut m, "RefSpeed0n", A1, 200);
    m.set_mode(A1, modes::HOMING_POSITIVE);
    let t = trace(&mut m, A1, 6);
    assert_eq!(incs(&t), [50, 100, 150, 200, 200, 200]);
}

/// X67-18.11.1.4-01: in every motion mode the speed rises by at most MaxAcc01 a cycle (10, 20, 30, …); with
/// MaxAcc01 = 0 nothing starts, so with all registers at their defaults nothing moves.
#[test]
fn x67_18_11_1_4_01_max_acceleration() {
    // (mode, AbsPos01, RefSpeed01, the first four increments)
    let cases: [(i8, i32, i64, [i32; 4]); 3] = [
        (modes::POSITION, 100_000, 0, [10, 20, 30, 40]),
        (modes::SPEED, 1000, 0, [10, 20, 30, 40]),
        (modes::HOMING_NEGATIVE, 0, 1000, [-10, -20, -30, -40]),
    ];
    for (mode, abs_pos, ref_speed, expected) in cases {
        let mut m = standard();
        write(&mut m, "RefSpeed0n", A1, ref_speed);
        m.set_mode(A1, mode);
        m.set_abs_pos(A1, abs_pos);
        assert_eq!(
            incs(&trace(&mut m, A1, 4)),
            expected,
            "mode {mode}, AbsPos01 {abs_pos}, RefSpeed01 {ref_speed}"
        );
    }

    for (mode, speed, acc) in [
        (modes::POSITION, 100, 0),
        (modes::SPEED, 100, 0),
        (modes::HOMING_POSITIVE, 100, 0),
        (modes::POSITION, 0, 0),
    ] {
        let mut m = enabled(speed, acc, if speed == 0 { 0 } else { 10 });
        write(&mut m, "RefSpeed0n", A1, speed);
        m.set_mode(A1, mode);
        m.set_abs_pos(A1, 5000);
        let t = trace(&mut m, A1, 20);
        assert!(t.iter().all(|c| c.pos == 0), "mode {mode}");
    }
}

/// X67-18.11.1.5-01: braking lowers the speed by at most MaxDec01 a cycle: MaxDec01 = 5 → 100, 95, 90, … before
/// the target; the same in speed mode and when homing stops at its reference.
#[test]
fn x67_18_11_1_5_01_max_deceleration() {
    let mut m = enabled(100, 10, 5);
    m.set_abs_pos(A1, 10_000);
    let t = until_reached(&mut m, A1, 200);
    assert_eq!(
        incs(&t),
        cat(&[&seq(10, 100, 10), &[100; 85], &seq(95, 5, -5), &[0]])
    );
    assert_eq!(m.act_val(A1), 10_000);

    let mut m = enabled(100, 10, 5);
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 100);
    trace(&mut m, A1, 10);
    m.set_abs_pos(A1, 0);
    assert_eq!(incs(&trace(&mut m, A1, 21)), cat(&[&seq(95, 0, -5), &[0]]));

    // Homing on the rising edge of DI3 at 2000 (a cam), RefSpeed01 = 40: the stop brakes by 5 a cycle.
    let mut m = enabled(100, 10, 5);
    write(&mut m, "RefSpeed0n", A1, 40);
    m.attach_cam(
        DI3,
        Cam {
            axis: A1,
            from: 2000,
            to: 1 << 40,
        },
    );
    m.set_mode(A1, modes::HOMING_POSITIVE);
    let t = until_reached(&mut m, A1, 200);
    assert_eq!(
        incs(&t),
        cat(&[&[10, 20, 30], &[40; 49], &seq(35, 5, -5), &[0]])
    );
    assert_eq!(read(&m, "RefPos0nCyclicCounter", A1), 2000);
    assert_eq!(m.act_val(A1), 2020 + 140);
}

/// X67-18.11.1.6-01: RevLoop01 acts only in the positioning modes 1, −123…−126; its default 0 approaches every
/// target directly. RevLoop01 = 1000 in speed mode, in −121 and in homing gives no overshoot.
#[test]
fn x67_18_11_1_6_01_reversing_loop_only_in_positioning_modes() {
    let mut m = standard();
    assert_eq!(read(&m, "RevLoop0n", A1), 0);
    for target in [1000, 0] {
        m.set_abs_pos(A1, target);
        let t = until_reached(&mut m, A1, 100);
        assert_eq!(incs(&t), profile(0, if target == 0 { -1 } else { 1 }));
    }

    let mut m = standard();
    write(&mut m, "RevLoop0n", A1, 1000);
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 50);
    trace(&mut m, A1, 10);
    m.set_abs_pos(A1, 0);
    let t = trace(&mut m, A1, 10);
    assert_eq!(incs(&t), [40, 30, 20, 10, 0, 0, 0, 0, 0, 0]);

    let mut m = standard();
    write(&mut m, "RevLoop0n", A1, 1000);
    m.set_mode(A1, modes::REMAINING_DISTANCE);
    m.set_abs_pos(A1, 3000);
    let t = trace(&mut m, A1, 50);
    assert_eq!(incs(&t), cat(&[&profile(20, 1), &[0; 10]]));

    let mut m = standard();
    write(&mut m, "RevLoop0n", A1, 1000);
    write(&mut m, "RefSpeed0n", A1, 40);
    m.attach_cam(
        DI3,
        Cam {
            axis: A1,
            from: 2000,
            to: 1 << 40,
        },
    );
    m.set_mode(A1, modes::HOMING_POSITIVE);
    let t = until_reached(&mut m, A1, 200);
    assert_eq!(incs(&t), cat(&[&[10, 20, 30], &[40; 49], &[30, 20, 10, 0]]));
    assert_eq!(m.act_val(A1), 2080);
    let t = trace(&mut m, A1, 20);
    assert!(t.iter().all(|c| c.pos == 2080));
}

/// X67-18.11.1.6-02: with RevLoop01 ≠ 0 a target on the looping side is overshot by |RevLoop01|; the axis
/// stops there and comes back, and bit 10 = 1 only on the final arrival. RevLoop01 = 1000, 0 → 10 000.
#[test]
fn x67_18_11_1_6_02_reversing_loop_overshoots_and_returns() {
    let mut m = standard();
    write(&mut m, "RevLoop0n", A1, 1000);
    m.set_abs_pos(A1, 10_000);
    let t = until_reached(&mut m, A1, 300);
    let out = &profile(100, 1)[..119];
    assert_eq!(incs(&t[..119]), out);
    assert_eq!(t[118].pos, 11_000);
    // At rest at the loop point for at least one cycle, not reached.
    let rest = t[119..].iter().take_while(|c| c.inc == 0).count();
    assert!(rest >= 1);
    assert!(t[119..119 + rest]
        .iter()
        .all(|c| c.pos == 11_000 && !c.reached()));
    assert_eq!(incs(&t[119 + rest..]), profile(0, -1));
    assert_eq!(bit10(&t).iter().filter(|b| **b).count(), 1);
    assert_eq!(m.act_val(A1), 10_000);
}

/// X67-18.11.1.6-02, X67-18.11.1.6-03 (pick (a)): the final approach runs against the sign of RevLoop01 also
/// when the axis passes the target onto the wrong side. RevLoop01 = 500; running at −100 toward −100 000,
/// at −1050 the target becomes −1150, 100 ahead, where braking from 100 takes 450 (X67-18.11.3.3-04: re-planned
/// from the present speed): −90 to −1140, −80 past the target to −1220, on down to −1500; then the loop
/// up to −1150 + 500 = −650 (850: 10, …, 90, then 84, 74, 64, 54, 44, 35, 25, 15, 5, each the largest speed
/// that still stops on −650), two cycles at rest there (as in `x67_18_11_1_6_02_loop_point_inside_the_limits`)
/// and down 500 onto the target (10, …, 70, then 61, 51, 41, 31, 22, 12, 2); bit 10 only on the arrival.
#[test]
fn x67_18_11_1_6_02_target_passed_on_the_wrong_side_loops_again() {
    let mut m = standard();
    write(&mut m, "RevLoop0n", A1, 500);
    m.set_abs_pos(A1, -100_000);
    let t = trace(&mut m, A1, 15);
    assert_eq!(incs(&t), cat(&[&seq(-10, -100, -10), &[-100; 5]]));
    assert_eq!(m.act_val(A1), -1050);
    m.set_abs_pos(A1, -1150);
    let t = until_reached(&mut m, A1, 200);
    let expected = cat(&[
        &seq(-90, -10, 10),
        &[0],
        &seq(10, 90, 10),
        &[84, 74, 64, 54, 44, 35, 25, 15, 5],
        &[0, 0],
        &seq(-10, -70, -10),
        &[-61, -51, -41, -31, -22, -12, -2],
        &[0],
    ]);
    assert_eq!(incs(&t), expected);
    assert_eq!(positions(&t)[9], -1500);
    assert_eq!(positions(&t)[27], -650);
    assert_eq!(bit10(&t), moving_then_reached(expected.len()));
    assert_eq!(m.act_val(A1), -1150);
}

/// X67-18.11.1.6-03: the sign of RevLoop01 sets the direction in which the loop runs, pick (a): +500 overshoots
/// moves in the positive direction (0 → 10 000 reaches 10 500) and goes straight in the negative direction
/// (20 000 → 10 000); −500 the other way round. The final approach always runs against the sign.
#[test]
fn x67_18_11_1_6_03_loop_direction_from_sign() {
    let mut m = standard();
    write(&mut m, "RevLoop0n", A1, 500);
    let (_, hi, last) = approach(&mut m, 10_000);
    assert_eq!((hi, last.signum()), (10_500, -1));
    approach(&mut m, 20_000);
    let (lo, hi, last) = approach(&mut m, 10_000);
    assert_eq!((lo, hi, last.signum()), (10_000, 20_000, -1));

    let mut m = standard();
    write(&mut m, "RevLoop0n", A1, -500);
    let (lo, hi, last) = approach(&mut m, 10_000);
    assert_eq!((lo, hi, last.signum()), (0, 10_000, 1));
    approach(&mut m, 20_000);
    let (lo, _, last) = approach(&mut m, 10_000);
    assert_eq!((lo, last.signum()), (9500, 1));
}

/// X67-18.11.1.7-01: FixedPos01a (default 0) is the target of mode −125; a new value written during the move
/// is followed (pick).
#[test]
fn x67_18_11_1_7_01_fixed_position_a() {
    let mut m = standard();
    assert_eq!(read(&m, "FixedPos0na", A1), 0);
    write(&mut m, "FixedPos0na", A1, 5000);
    m.set_mode(A1, modes::FIXED_A);
    let t = until_reached(&mut m, A1, 200);
    assert_eq!(incs(&t), profile(40, 1));
    assert_eq!(m.act_val(A1), 5000);

    let mut m = standard();
    write(&mut m, "FixedPos0na", A1, 5000);
    m.set_mode(A1, modes::FIXED_A);
    let mut t = trace(&mut m, A1, 20);
    write(&mut m, "FixedPos0na", A1, 7000);
    t.extend(until_reached(&mut m, A1, 200));
    assert_eq!(incs(&t), profile(60, 1));
    assert_eq!(m.act_val(A1), 7000);
}

/// X67-18.11.1.8-01: FixedPos01b (default 0) is the target of mode −126.
#[test]
fn x67_18_11_1_8_01_fixed_position_b() {
    let mut m = standard();
    assert_eq!(read(&m, "FixedPos0nb", A1), 0);
    write(&mut m, "FixedPos0nb", A1, -3000);
    m.set_mode(A1, modes::FIXED_B);
    let t = until_reached(&mut m, A1, 200);
    assert_eq!(incs(&t), profile(20, -1));
    assert_eq!(m.act_val(A1), -3000);
}

// =====================================================================================================
// 18.11.1.14 Jerk time
// =====================================================================================================

/// X67-18.11.1.14-01: JoltTime01 = 4 with MaxAcc01 = 100 from standstill gives increments 25, 75, 150, 250, …
/// (means of the last four set-point speeds 100, 200, 300, 400 with a FIFO starting at 0); the move still
/// ends exactly on the target. JoltTime01 = 0 (default) gives the unfiltered ramp.
#[test]
fn x67_18_11_1_14_01_jerk_time_mean_of_fifo() {
    let mut m = enabled(1000, 100, 100);
    assert_eq!(read(&m, "JoltTime0n", A1), 0);
    m.set_abs_pos(A1, 100_000);
    let first = incs(&trace(&mut m, A1, 4));
    assert_eq!(first, [100, 200, 300, 400]);

    let mut m = enabled(1000, 100, 100);
    write(&mut m, "JoltTime0n", A1, 4);
    m.set_abs_pos(A1, 100_000);
    let t = until_reached(&mut m, A1, 400);
    assert_eq!(
        incs(&t)[..13],
        [25, 75, 150, 250, 350, 450, 550, 650, 750, 850, 925, 975, 1000]
    );
    assert_eq!(m.act_val(A1), 100_000);
    assert!(t.iter().all(|c| c.inc >= 0 && c.inc <= 1000));
}

/// Runs a move 0 → 20 000 with JoltTime01 = `jolt` and returns its increments.
fn jolt_move(jolt: i64) -> Vec<i32> {
    let mut m = enabled(200, 20, 20);
    write(&mut m, "JoltTime0n", A1, jolt);
    m.set_abs_pos(A1, 20_000);
    let t = until_reached(&mut m, A1, 1000);
    assert_eq!(m.act_val(A1), 20_000);
    incs(&t)
}

/// X67-18.11.1.14-02: values above 80 act as 80.
#[test]
fn x67_18_11_1_14_02_jerk_time_limited_to_80() {
    let j80 = jolt_move(80);
    assert_eq!(jolt_move(200), j80);
    assert_eq!(jolt_move(255), j80);
    assert_ne!(jolt_move(79), j80);
    // A FIFO of 80 with set-point speeds 20, 40, 60: 20/80 → 0 (20 carried), (60 + 20)/80 → 1 (0 carried),
    // 120/80 → 1 (40 carried).
    assert_eq!(j80[..3], [0, 1, 1]);
}

/// X67-18.11.1.14-03: a JoltTime01 change during a move takes effect only once the axis has reached its
/// position: 0 → 10 in mid-move, that move ends unfiltered, the next one is filtered (1, 3, 6, 10, …).
#[test]
fn x67_18_11_1_14_03_jerk_time_change_waits_for_standstill() {
    let mut m = standard();
    m.set_abs_pos(A1, 10_000);
    let mut t = trace(&mut m, A1, 30);
    write(&mut m, "JoltTime0n", A1, 10);
    t.extend(until_reached(&mut m, A1, 200));
    assert_eq!(incs(&t), profile(90, 1));
    m.set_abs_pos(A1, 20_000);
    let t = until_reached(&mut m, A1, 300);
    assert_eq!(incs(&t)[..10], [1, 3, 6, 10, 15, 21, 28, 36, 45, 55]);
    assert_eq!(m.act_val(A1), 20_000);

    // Speed mode: written while running, the change waits for the stop.
    let mut m = standard();
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 50);
    trace(&mut m, A1, 6);
    write(&mut m, "JoltTime0n", A1, 10);
    m.set_abs_pos(A1, 80);
    assert_eq!(incs(&trace(&mut m, A1, 3)), [60, 70, 80]);
    m.set_abs_pos(A1, 0);
    trace(&mut m, A1, 12);
    m.set_abs_pos(A1, 10);
    assert_eq!(incs(&trace(&mut m, A1, 3)), [1, 2, 3]);
}

// =====================================================================================================
// 18.11.1.15 General configuration
// =====================================================================================================

/// X67-18.11.1.15-01: GeneralConfig01 bit 0 selects mode 1 with the extended control word, for both axes
/// (pick): AbsPos01/AbsPos02 alone start nothing; a handshake on axis 2 moves axis 2 only.
#[test]
fn x67_18_11_1_15_01_extended_control_word_for_both_axes() {
    let mut m = Module::new();
    m.write_named("GeneralConfig01", 1).unwrap();
    for axis in [0, 1] {
        set_ramp(&mut m, axis, 100, 10, 10);
        m.set_mode(axis, modes::POSITION);
        switch_on(&mut m, axis);
        enable_operation(&mut m, axis);
        m.set_abs_pos(axis, 5000);
    }
    for _ in 0..20 {
        m.step();
        assert_eq!((m.act_val(0), m.act_val(1)), (0, 0));
    }
    m.set_abs_pos(1, 1000);
    m.set_control(1, ENABLE_OPERATION | CW_NEW_SETPOINT);
    let t = until_reached(&mut m, 1, 100);
    assert_eq!(incs(&t), profile(0, 1));
    assert_eq!((m.act_val(0), m.act_val(1)), (0, 1000));
    assert_eq!(t[0].sw & SW_SETPOINT_ACK, SW_SETPOINT_ACK);
}

/// X67-18.11.1.15-02: bits 1–2 set the cycle: 00 = 25 ms, 01 = 10 ms, 10 = 5 ms, 11 = 25 ms (pick). Mode 2
/// with AbsPos01 = 10 advances the counter by 10 a cycle: 400, 1000 and 2000 microsteps per second.
#[test]
fn x67_18_11_1_15_02_cycle_time() {
    for (config, ms, per_second) in [(0, 25, 400), (2, 10, 1000), (4, 5, 2000), (6, 25, 400)] {
        let mut m = Module::new();
        m.write_named("GeneralConfig01", config).unwrap();
        set_ramp(&mut m, A1, 100, 10, 10);
        m.set_mode(A1, modes::SPEED);
        switch_on(&mut m, A1);
        enable_operation(&mut m, A1);
        m.set_abs_pos(A1, 10);
        let t0 = m.time_ms();
        assert_eq!(cycle(&mut m, A1).inc, 10);
        assert_eq!(m.time_ms() - t0, ms);
        let (t0, p0) = (m.time_ms(), m.act_val(A1));
        m.run_ms(1000);
        assert_eq!(m.time_ms() - t0, 1000, "config {config}");
        assert_eq!(m.act_val(A1) - p0, per_second, "config {config}");
    }
}

/// X67-18.11.1.15-03: the cycle is the time base of every speed and acceleration register: MaxSpeed01pos = 100
/// is 4000 microsteps/s at 25 ms and 20 000 at 5 ms, and MaxAcc01 = 10 reaches it in 10 cycles, 250 ms or
/// 50 ms.
#[test]
fn x67_18_11_1_15_03_cycle_is_time_base() {
    for (config, per_second, ramp_ms) in [(0, 4000, 250), (2, 10_000, 100), (4, 20_000, 50)] {
        let mut m = Module::new();
        m.write_named("GeneralConfig01", config).unwrap();
        set_ramp(&mut m, A1, 100, 10, 10);
        m.set_mode(A1, modes::POSITION);
        switch_on(&mut m, A1);
        enable_operation(&mut m, A1);
        m.set_abs_pos(A1, 1_000_000);
        let t0 = m.time_ms();
        let t = trace(&mut m, A1, 10);
        assert_eq!(incs(&t), seq(10, 100, 10));
        assert_eq!(m.time_ms() - t0, ramp_ms);
        let p0 = m.act_val(A1);
        m.run_ms(1000);
        assert_eq!(m.act_val(A1) - p0, per_second, "config {config}");
    }
}

/// X67-18.11.1.15-04: bits 3–7 are reserved: setting them changes nothing (0xF8 acts as 0x00, 0xF9 as 0x01).
#[test]
fn x67_18_11_1_15_04_reserved_bits() {
    let run = |config: i64| {
        let mut m = Module::new();
        m.write_named("GeneralConfig01", config).unwrap();
        set_ramp(&mut m, A1, 100, 10, 10);
        m.set_mode(A1, modes::POSITION);
        switch_on(&mut m, A1);
        enable_operation(&mut m, A1);
        m.set_abs_pos(A1, 3000);
        let t = trace(&mut m, A1, 50);
        (t, m.time_ms())
    };
    assert_eq!(run(0xF8), run(0));
    assert_eq!(run(0xF9), run(1));
    let (moved, _) = run(0xF8);
    assert_eq!(moved.last().unwrap().pos, 3000);
    let (held, _) = run(0xF9);
    assert!(held.iter().all(|c| c.pos == 0));
}

// =====================================================================================================
// 18.11.3.5 / 18.11.4.2 Status word bits 10 and 12
// =====================================================================================================

/// X67-18.11.3.5-04: SW bit 12 follows the set-point handshake with the extended control word in mode 1, and is
/// 0 without it (CW bit 4 toggling) and in other modes (pick).
#[test]
fn x67_18_11_3_5_04_bit_12_mode_specific() {
    let mut m = standard_ext();
    let acks: Vec<bool> = [
        handshake(&mut m, 100, 0),
        cycle(&mut m, A1),
        release(&mut m, 0),
    ]
    .iter()
    .map(|c| c.ack())
    .collect();
    assert_eq!(acks, [true, true, false]);

    // Bit 4 toggling without the extended control word (mode 1, AbsPos01 = 100·k) and with it in speed
    // mode (AbsPos01 = 10): bit 12 stays 0.
    // (case, the module, mode, AbsPos01 in cycle k)
    type Setup = fn() -> Module;
    type AbsPos = fn(u16) -> i32;
    let cases: [(&str, Setup, i8, AbsPos); 2] = [
        ("mode 1 without ext CW", standard, modes::POSITION, |k| {
            i32::from(k) * 100
        }),
        ("mode 2 with ext CW", standard_ext, modes::SPEED, |_| 10),
    ];
    for (case, setup, mode, abs_pos) in cases {
        let mut m = setup();
        m.set_mode(A1, mode);
        for k in 0..20u16 {
            m.set_control(A1, ENABLE_OPERATION | (k % 2) << 4);
            m.set_abs_pos(A1, abs_pos(k));
            m.step();
            assert_eq!(m.status_word(A1) & SW_SETPOINT_ACK, 0, "{case}, cycle {k}");
        }
    }
}

/// X67-18.11.3.5-04, X67-18.11.3.3.2-11 (pick): bit 12 is Set-point acknowledge only in the modes with the
/// handshake, mode 1 and −121 before its trigger; in any other mode, and in −121 once triggered, it is 0,
/// even while bit 4 is still high and the value was taken.
#[test]
fn x67_18_11_3_5_04_bit_12_only_in_the_handshake_modes() {
    let mut m = standard_ext();
    assert!(handshake(&mut m, 1000, 0).ack());
    m.set_abs_pos(A1, 0);
    m.set_mode(A1, modes::SPEED);
    for k in 0..3 {
        let c = cycle(&mut m, A1);
        assert_eq!(c.sw & SW_SETPOINT_ACK, 0, "mode 2, cycle {k}");
    }

    let mut m = standard_ext();
    m.set_mode(A1, modes::REMAINING_DISTANCE);
    m.step();
    assert!(handshake(&mut m, 1000, 0).ack());
    let t = trace(&mut m, A1, 30);
    assert!(t.iter().all(|c| c.ack()), "−121 before its trigger");
    assert_eq!(m.act_val(A1), 1000);
    m.pulse_input(DI3);
    for k in 0..3 {
        let c = cycle(&mut m, A1);
        assert_eq!(c.sw & SW_SETPOINT_ACK, 0, "−121 triggered, cycle {k}");
    }
}

/// X67-18.11.4.2-11: in modes 1, −123, −124, −125 and −126 bit 10 is 0 from the start of a move and 1 once the
/// target is reached.
#[test]
fn x67_18_11_4_2_11_bit_10_in_positioning_modes() {
    for mode in [
        modes::POSITION,
        modes::MOVE_ON_INPUT,
        modes::TWO_POSITION,
        modes::FIXED_A,
        modes::FIXED_B,
    ] {
        let mut m = standard();
        assert!(cycle(&mut m, A1).reached());
        let late = start_move(&mut m, mode, 1000);
        let t = until_reached(&mut m, A1, 100);
        let expected = if late {
            after_edge(profile(0, 1))
        } else {
            profile(0, 1)
        };
        assert_eq!(incs(&t), expected, "mode {mode}");
        assert_eq!(bit10(&t), moving_then_reached(t.len()), "mode {mode}");
        assert!(trace(&mut m, A1, 5)
            .iter()
            .all(|c| c.reached() && c.pos == 1000));
    }
}

/// X67-18.11.4.2-12: in speed mode bit 10 is 0 while the speed changes and 1 once it equals the set-point:
/// 50 → 1 from the first cycle at 50; 80 → 0 until 80; 20 → 0 while braking.
#[test]
fn x67_18_11_4_2_12_bit_10_in_speed_mode() {
    let mut m = standard();
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 50);
    let t = trace(&mut m, A1, 7);
    assert_eq!(incs(&t), [10, 20, 30, 40, 50, 50, 50]);
    assert_eq!(bit10(&t), [false, false, false, false, true, true, true]);
    m.set_abs_pos(A1, 80);
    let t = trace(&mut m, A1, 4);
    assert_eq!(incs(&t), [60, 70, 80, 80]);
    assert_eq!(bit10(&t), [false, false, true, true]);
    m.set_abs_pos(A1, 20);
    let t = trace(&mut m, A1, 8);
    assert_eq!(incs(&t), [70, 60, 50, 40, 30, 20, 20, 20]);
    assert_eq!(
        bit10(&t),
        [false, false, false, false, false, true, true, true]
    );
}

/// X67-18.11.4.2-12 with X67-18.11.1.14-01: with the jerk filter, bit 10 in speed mode waits for the speed the
/// axis runs at, not for the ramp's unfiltered set-point (the model's pick). JoltTime01 = 4, set-point 40,
/// MaxAcc01 10: the set-point runs 10, 20, 30, 40, 40, …; the axis moves by the mean of the last four with the
/// remainder carried: 10/4 = 2 (2 left), 32/4 = 8, 60/4 = 15, 100/4 = 25, 130/4 = 32 (2 left), 152/4 = 38,
/// 160/4 = 40: bit 10 is 1 from that cycle, not from the fourth, where the set-point reached 40.
#[test]
fn x67_18_11_4_2_12_bit_10_follows_the_filtered_speed() {
    let mut m = standard();
    write(&mut m, "JoltTime0n", A1, 4);
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 40);
    let t = trace(&mut m, A1, 8);
    assert_eq!(incs(&t), [2, 8, 15, 25, 32, 38, 40, 40]);
    assert_eq!(bit10(&t), cat_bools(&[false; 6], &[true; 2]));
}

/// X67-18.11.4.2-14: in mode −122 bit 10 drops to 0 for one cycle and returns to 1 once the position is set;
/// an unchanged AbsPos01 does not set it again.
#[test]
fn x67_18_11_4_2_14_bit_10_in_mode_122() {
    let mut m = standard();
    m.set_mode(A1, modes::SET_POSITION);
    m.set_abs_pos(A1, 777);
    let t = trace(&mut m, A1, 4);
    assert_eq!(bit10(&t), [false, true, true, true]);
    assert_eq!(positions(&t), [777; 4]);
    m.set_abs_pos(A1, 300);
    let t = trace(&mut m, A1, 3);
    assert_eq!(bit10(&t), [false, true, true]);
    assert_eq!(positions(&t), [300; 3]);
}

/// X67-18.11.4.2-15: with the extended control word and Stop = 1, bit 10 means "speed 0": mid-move toward
/// 10 000, Stop → 0 while braking, 1 at standstill at 2000; Stop released → the move resumes to 10 000.
#[test]
fn x67_18_11_4_2_15_bit_10_with_stop() {
    let mut m = standard_ext();
    let mut t = vec![handshake(&mut m, 10_000, 0), release(&mut m, 0)];
    t.extend(trace(&mut m, A1, 18));
    assert_eq!(m.act_val(A1), 1550);
    m.set_control(A1, ENABLE_OPERATION | CW_STOP);
    let t = trace(&mut m, A1, 14);
    assert_eq!(incs(&t), cat(&[&seq(90, 10, -10), &[0; 5]]));
    assert_eq!(bit10(&t), cat_bools(&[false; 9], &[true; 5]));
    assert_eq!(m.act_val(A1), 2000);
    m.set_control(A1, ENABLE_OPERATION);
    let t = until_reached(&mut m, A1, 200);
    assert_eq!(incs(&t), profile(70, 1));
    assert_eq!(m.act_val(A1), 10_000);
}

/// X67-18.11.4.2-16: without the extended control word CW bit 8 is no Stop: the move goes on unchanged and bit
/// 10 follows the mode.
#[test]
fn x67_18_11_4_2_16_bit_8_without_ext_cw() {
    let plain = move_with_control(false, |_| ENABLE_OPERATION);
    let stop = move_with_control(false, |k| {
        ENABLE_OPERATION | if k >= 5 { CW_STOP } else { 0 }
    });
    assert_eq!(stop, plain);
    assert_eq!(bit10(&stop), cat_bools(&[false; 39], &[true; 11]));
    assert_eq!(stop.last().unwrap().pos, 3000);
}

// =====================================================================================================
// 18.11.4.3 Motion only in Operation enable
// =====================================================================================================

/// X67-18.11.4.3-21: motion according to the mode happens only in Operation enable: in Switched on, mode 1 with
/// AbsPos01 = 1000 does not move; Enable operation starts the move in that cycle.
#[test]
fn x67_18_11_4_3_21_motion_only_in_operation_enable() {
    let mut m = Module::new();
    set_ramp(&mut m, A1, 100, 10, 10);
    m.set_mode(A1, modes::POSITION);
    switch_on(&mut m, A1);
    m.set_abs_pos(A1, 1000);
    let t = trace(&mut m, A1, 20);
    assert!(t
        .iter()
        .all(|c| c.pos == 0 && c.sw & STATE_MASK == SWITCHED_ON));
    m.set_control(A1, ENABLE_OPERATION);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(t[0].sw & STATE_MASK, OPERATION_ENABLE);
    assert_eq!(incs(&t), profile(0, 1));

    // Mode 2 in Switched on does not move either.
    let mut m = standard();
    m.set_control(A1, SWITCH_ON);
    m.step();
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 50);
    assert!(trace(&mut m, A1, 10).iter().all(|c| c.pos == 0));
}

// =====================================================================================================
// 18.11.1.17 Counter wrap-around without software limits
// =====================================================================================================

/// X67-18.11.1.17-06: without software limits the 32-bit counter wraps around: in speed mode it passes
/// 2 147 483 647 and continues at −2 147 483 648 and beyond.
#[test]
fn x67_18_11_1_17_06_counter_wraps_in_speed_mode() {
    let mut m = enabled(100, 100, 100);
    m.set_mode(A1, modes::SET_POSITION);
    m.set_abs_pos(A1, 2_147_483_000);
    m.step();
    assert_eq!(m.act_val(A1), 2_147_483_000);
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 100);
    let t = trace(&mut m, A1, 9);
    assert_eq!(incs(&t), [100; 9]);
    assert_eq!(
        positions(&t),
        [
            2_147_483_100,
            2_147_483_200,
            2_147_483_300,
            2_147_483_400,
            2_147_483_500,
            2_147_483_600,
            -2_147_483_596,
            -2_147_483_496,
            -2_147_483_396
        ]
    );
    assert_eq!(state(&m, A1), OPERATION_ENABLE);
}

/// X67-18.11.1.17-06: in mode 1 the move distance is the wrapping difference target − actual as a signed
/// 32-bit value: from 2 147 483 000 to −2 147 483 000 is +1296 through the wrap, not −4 294 966 000.
#[test]
fn x67_18_11_1_17_06_wrapping_distance_in_mode_1() {
    let mut m = standard();
    m.set_mode(A1, modes::SET_POSITION);
    m.set_abs_pos(A1, 2_147_483_000);
    m.step();
    m.set_mode(A1, modes::POSITION);
    m.set_abs_pos(A1, -2_147_483_000);
    let t = until_reached(&mut m, A1, 100);
    assert!(t.iter().all(|c| c.inc >= 0));
    assert_eq!(t.iter().map(|c| i64::from(c.inc)).sum::<i64>(), 1296);
    assert_eq!(incs(&t)[..10], seq(10, 100, 10)[..]);
    assert_eq!(m.act_val(A1), -2_147_483_000);
    assert_eq!(m.axis(A1).motor.rotor(), 1296);
}

// =====================================================================================================
// 18.14 Cyclic outputs are taken over once per cycle
// =====================================================================================================

/// X67-18.14-02: only the value present at the cycle boundary takes effect: AbsPos01 = 5000 then 1000 within one
/// cycle moves to 1000 on the 1000 profile; a CW bit 4 pulse within one cycle is no handshake; a mode written
/// and overwritten within one cycle never acts.
#[test]
fn x67_18_14_02_value_at_cycle_boundary() {
    let mut m = standard();
    m.set_abs_pos(A1, 5000);
    m.set_abs_pos(A1, 1000);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), profile(0, 1));

    let mut m = standard_ext();
    m.set_abs_pos(A1, 3000);
    m.set_control(A1, ENABLE_OPERATION | CW_NEW_SETPOINT);
    m.set_control(A1, ENABLE_OPERATION);
    let t = trace(&mut m, A1, 10);
    assert!(t.iter().all(|c| c.pos == 0 && !c.ack()));

    let mut m = standard();
    m.set_mode(A1, modes::SET_POSITION);
    m.set_abs_pos(A1, 777);
    m.set_mode(A1, modes::POSITION);
    m.set_abs_pos(A1, 0);
    let t = trace(&mut m, A1, 5);
    assert!(t.iter().all(|c| c.pos == 0 && c.reached()));

    // At a 5 ms cycle the same holds per 5 ms cycle.
    let mut m = Module::new();
    m.write_named("GeneralConfig01", 4).unwrap();
    set_ramp(&mut m, A1, 100, 10, 10);
    m.set_mode(A1, modes::POSITION);
    switch_on(&mut m, A1);
    enable_operation(&mut m, A1);
    m.set_abs_pos(A1, -7000);
    m.set_abs_pos(A1, -1000);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), profile(0, -1));
}

// =====================================================================================================
// Properties of mode 1 over random ramp registers and set-point sequences
// =====================================================================================================

/// The ramp registers of one property case.
#[derive(Clone, Copy, Debug)]
struct Regs1 {
    speed: u16,
    acc: u16,
    dec: u16,
    rev_loop: i16,
    jolt: u8,
}

/// One cycle of a property run: what the master saw and the target in force.
#[derive(Clone, Copy, Debug)]
struct Step {
    c: Cyc,
    target: i32,
    /// Index of the order that gave the target.
    order: usize,
}

/// Runs mode-1 set-points (without the extended control word) on axis 1: each order gives its target and
/// then waits `Some(n)` cycles, or with `None` until bit 10 is 1. The last order always waits for bit 10.
fn drive(r: Regs1, orders: &[(i32, Option<usize>)]) -> Vec<Step> {
    let mut m = enabled(i64::from(r.speed), i64::from(r.acc), i64::from(r.dec));
    write(&mut m, "RevLoop0n", A1, i64::from(r.rev_loop));
    write(&mut m, "JoltTime0n", A1, i64::from(r.jolt));
    let mut out = Vec::new();
    for (k, &(target, wait)) in orders.iter().enumerate() {
        m.set_abs_pos(A1, target);
        let wait = if k + 1 == orders.len() { None } else { wait };
        match wait {
            Some(n) => {
                for _ in 0..n {
                    let c = cycle(&mut m, A1);
                    out.push(Step {
                        c,
                        target,
                        order: k,
                    });
                }
            }
            None => {
                let mut arrived = false;
                for _ in 0..20_000 {
                    let c = cycle(&mut m, A1);
                    out.push(Step {
                        c,
                        target,
                        order: k,
                    });
                    if c.reached() {
                        arrived = true;
                        break;
                    }
                }
                assert!(arrived, "order {k} ({target}) not reached; {r:?}");
            }
        }
    }
    out
}

/// Whether the increment may follow `prev` under MaxAcc/MaxDec: a rising magnitude by at most `acc`, a
/// falling one by at most `dec`; a change of sign brakes to 0 and accelerates from it.
fn accel_ok(prev: i32, cur: i32, acc: i32, dec: i32) -> bool {
    if prev == 0 || cur == 0 || prev.signum() == cur.signum() {
        let (p, c) = (prev.abs(), cur.abs());
        if c >= p {
            c - p <= acc
        } else {
            p - c <= dec
        }
    } else {
        prev.abs() <= dec && cur.abs() <= acc
    }
}

fn orders() -> impl Strategy<Value = Vec<(i32, Option<usize>)>> {
    prop::collection::vec((-8000i32..=8000, prop::option::of(0usize..60)), 1..6)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// X67-18.11.1.3-01, X67-18.11.1.4-01, X67-18.11.1.5-01, X67-18.11.3.3-04 (JoltTime01 = 0): whatever the
    /// registers and however the targets arrive, the per-cycle increment of AbsPos01ActVal never exceeds
    /// MaxSpeed01pos and changes by no more than MaxAcc01 (rising) or MaxDec01 (falling).
    #[test]
    fn prop_mode_1_speed_and_acceleration_limits(
        speed in 20u16..=400,
        acc in 1u16..=60,
        dec in 1u16..=60,
        rev_loop in -1500i16..=1500,
        orders in orders(),
    ) {
        let r = Regs1 { speed, acc, dec, rev_loop, jolt: 0 };
        let steps = drive(r, &orders);
        let mut prev = 0;
        for (k, s) in steps.iter().enumerate() {
            prop_assert!(s.c.inc.abs() <= i32::from(speed), "cycle {k}: {s:?}");
            prop_assert!(
                accel_ok(prev, s.c.inc, i32::from(acc), i32::from(dec)),
                "cycle {k}: {prev} → {}", s.c.inc
            );
            prop_assert_eq!(s.c.sw & STATE_MASK, OPERATION_ENABLE);
            prev = s.c.inc;
        }
    }

    /// X67-18.11.3.3.1-01, X67-18.11.4.2-11, X67-18.11.1.6-02/-03, X67-18.11.1.14-01: every target waited for
    /// is reached exactly with bit 10 = 1; bit 10 = 1 only ever on the target in force; with RevLoop01 ≠ 0 the
    /// last movement before an arrival runs against the sign of RevLoop01 (pick (a)); JoltTime01 anywhere in
    /// 0…80 keeps the speed within MaxSpeed01pos.
    #[test]
    fn prop_mode_1_targets_reached_from_the_loop_side(
        speed in 20u16..=400,
        acc in 1u16..=60,
        dec in 1u16..=60,
        rev_loop in prop_oneof![Just(0i16), -1500i16..=1500],
        jolt in prop_oneof![Just(0u8), 1u8..=80],
        orders in orders(),
    ) {
        let r = Regs1 { speed, acc, dec, rev_loop, jolt };
        let steps = drive(r, &orders);
        let last = steps.last().unwrap();
        prop_assert!(last.c.reached());
        prop_assert_eq!(last.c.pos, last.target);
        for (k, s) in steps.iter().enumerate() {
            prop_assert!(s.c.inc.abs() <= i32::from(speed), "cycle {k}: {s:?}");
            if !s.c.reached() {
                continue;
            }
            prop_assert_eq!(s.c.pos, s.target, "cycle {}", k);
            prop_assert_eq!(s.c.inc, 0);
            // The last movement since this target was given.
            let since = steps[..=k].iter().rev().take_while(|p| p.order == s.order);
            let last_move = since.map(|p| p.c.inc).find(|&i| i != 0);
            if let (Some(inc), true) = (last_move, rev_loop != 0) {
                prop_assert_eq!(inc.signum(), -i32::from(rev_loop.signum()), "cycle {}", k);
            }
        }
        for (k, _) in orders.iter().enumerate().filter(|(k, o)| o.1.is_none() || *k + 1 == orders.len()) {
            let arrival = steps.iter().rfind(|s| s.order == k).unwrap();
            prop_assert!(arrival.c.reached(), "order {}", k);
            prop_assert_eq!(arrival.c.pos, orders[k].0);
        }
    }
}

/// The module's clock (X67-18.11.1.15-02: GeneralConfig01 bits 1–2 select the 25, 10 or 5 ms cycle): after
/// `start` a cycle is due every cycle length; `handle_timeout` runs exactly the cycles due, each of the
/// length selected when it runs, and a host stalled for an hour catches up 2000 cycles, then goes on
/// from its present time.
#[test]
fn x67_18_11_1_15_02_module_clock_runs_the_cycles_due() {
    let t0 = std::time::Instant::now();
    let ms = std::time::Duration::from_millis;
    let mut m = Module::new();
    m.handle_timeout(t0 + ms(1000));
    assert_eq!(
        (m.time_ms(), m.poll_timeout()),
        (0, None),
        "no clock before start"
    );
    m.start(t0);
    assert_eq!(m.poll_timeout(), Some(t0 + ms(25)));
    m.handle_timeout(t0 + ms(24));
    assert_eq!(m.time_ms(), 0);
    m.handle_timeout(t0 + ms(25));
    assert_eq!(m.time_ms(), 25);
    m.handle_timeout(t0 + ms(87));
    assert_eq!(m.time_ms(), 75, "cycles at 50 and 75 ms");
    assert_eq!(m.poll_timeout(), Some(t0 + ms(100)));
    // 5 ms from the next cycle on: the cycles due at 100, 105 and 110 ms are 5 ms cycles.
    write(&mut m, "GeneralConfig01", 0, 0b100);
    m.handle_timeout(t0 + ms(111));
    assert_eq!(m.time_ms(), 75 + 5 + 5 + 5);
    assert_eq!(m.poll_timeout(), Some(t0 + ms(115)));
    let late = t0 + ms(3_600_000);
    m.handle_timeout(late);
    assert_eq!(m.time_ms(), 90 + 2000 * 5);
    assert_eq!(m.poll_timeout(), Some(late + ms(5)));
}
