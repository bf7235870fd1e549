//! The registers the motion modes of the X67SM2436 "Ramp" module model use, tested through the module's
//! registers: set position and speed (18.11.3.1), the control-word bits 4–10 (18.11.3.2), the ramp registers
//! and fixed positions (18.11.1.3–18.11.1.8), the jerk time (18.11.1.14) and the general configuration
//! (18.11.1.15). Each test names the rules of `rules/x67.md` it covers.
//!
//! The expected trajectories follow the discretisation the catalogue picks in X67-18.11.3.3.1-01: each cycle
//! the speed changes first (by at most MaxAcc/MaxDec, up to MaxSpeed) and the position then advances by it;
//! braking starts as late as possible so that the target is met exactly. With MaxSpeed 100, MaxAcc 10 and
//! MaxDec 10 a move from standstill accelerates 10, 20, …, 100 (550 microsteps), brakes 90, 80, …, 10 (450
//! microsteps), and cruises at 100 for the rest; the axis arrives in the following cycle with increment 0.

mod module_modes_helpers;
mod x67_rig;

use ds402::cia402::control::{ENABLE_OPERATION, SHUTDOWN, SWITCH_ON};
use ds402::x67::axis::{modes, CW_NEW_SETPOINT, CW_STOP, SW_SETPOINT_ACK};
use ds402::x67::module::{Cam, Module};
use module_modes_helpers::*;
use x67_rig::{
    cat, cat_bools, cycle, enable_operation, read, set_ramp, state, switch_on, trace, write,
    OPERATION_ENABLE, READY, SWITCHED_ON,
};

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
