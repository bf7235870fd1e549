//! The motion modes of the X67SM2436 "Ramp" module model, tested through the module's registers: the Mode
//! register and its values (18.11.3.3), mode 1 with and without the extended control word, speed mode and
//! modes −120, −121, −122, −123, −124, −125 and −126. Each test names the rules of `rules/x67.md` it covers.
//!
//! The expected trajectories follow the discretisation the catalogue picks in X67-18.11.3.3.1-01: each cycle
//! the speed changes first (by at most MaxAcc/MaxDec, up to MaxSpeed) and the position then advances by it;
//! braking starts as late as possible so that the target is met exactly. With MaxSpeed 100, MaxAcc 10 and
//! MaxDec 10 a move from standstill accelerates 10, 20, …, 100 (550 microsteps), brakes 90, 80, …, 10 (450
//! microsteps), and cruises at 100 for the rest; the axis arrives in the following cycle with increment 0.

mod module_modes_helpers;
mod x67_rig;

use ds402::cia402::control::{ENABLE_OPERATION, SHUTDOWN, SWITCH_ON};
use ds402::cia402::SW_WARNING;
use ds402::x67::axis::{
    modes, ref_config, CW_CHANGE_IMMEDIATELY, CW_RELATIVE, CW_SWAP_COUNTERS, SW_SETPOINT_ACK,
    SW_TARGET_REACHED,
};
use ds402::x67::errors::CW_WARNING_RESET;
use ds402::x67::module::{Cam, Module};
use module_modes_helpers::*;
use x67_rig::{
    cat, cat_bools, cycle, enable_operation, read, set_ramp, state, switch_on, trace, write,
    DISABLED_MASK, OPERATION_ENABLE, QUICK_STOP_FROM_ENABLED, READY, STATE_MASK, SWITCHED_ON,
    SWITCH_ON_DISABLED,
};

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
