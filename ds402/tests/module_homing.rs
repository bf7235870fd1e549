//! Homing of the X67SM2436 module model ("Ramp", seed 002, 18.11.1.9, 18.11.1.11, 18.11.1.12, 18.11.1.13,
//! 18.11.3.3.10, 18.11.3.9): homing, stall homing, RefConfig and the reference registers, run through the
//! module's registers cycle by cycle. Each test names the rules of `rules/x67.md` it covers; the numbers are
//! worked out by hand from the rules and the ramp discretisation of X67-18.11.3.3.1-01 (speed first, then
//! position).
//!
//! Timing of the inputs, from the module documentation: a cam switches its input at the exact rotor position
//! within a cycle; an input the harness sets between two cycles is seen in the next cycle at the counter
//! values of that cycle's start, and a braking ramp it causes starts in the cycle after.

mod module_homing_helpers;
mod x67_rig;

use ds402::cia402::control::ENABLE_OPERATION;
use ds402::cia402::SW_WARNING;
use ds402::x67::axis::{modes, ref_config, CW_SWAP_COUNTERS, SW_TARGET_REACHED};
use ds402::x67::current::Level;
use ds402::x67::errors::CW_STALL_DETECTION;
use ds402::x67::module::{Cam, Module};
use ds402::x67::motor::Load;
use ds402::x67::registers::AxisReg;
use module_homing_helpers::*;
use x67_rig::{
    cat, cat_bools, get, increments as incs, set, set_ref_config, OPERATION_ENABLE, STATE_MASK,
};

// ----- homing: X67-18.11.3.3.10 -----

/// X67-18.11.3.3.10-01, X67-18.11.1.9-01: Mode −127 with the reference input inactive travels in the positive
/// direction and Mode −128 in the negative one, at RefSpeed0n.
#[test]
fn x67_18_11_3_3_10_01_positive_and_negative_homing() {
    let mut m = homing_axis(0, 40, 10, 10);
    m.set_mode(0, modes::HOMING_POSITIVE);
    assert_eq!(incs(&mut m, 0, 7), [10, 20, 30, 40, 40, 40, 40]);
    assert_eq!(m.act_val(0), 220);
    assert!(!bit(&m, 0, SW_TARGET_REACHED));
    assert_eq!(refs(&m, 0), (0, 0));

    // Axis 2 (R input DI6) homes negative; axis 1's registers are not touched by it.
    let mut m = homing_axis(1, 40, 10, 10);
    m.set_mode(1, modes::HOMING_NEGATIVE);
    assert_eq!(incs(&mut m, 1, 7), [-10, -20, -30, -40, -40, -40, -40]);
    assert_eq!(m.act_val(1), -220);
    assert_eq!(m.act_val(0), 0);
    assert_eq!(refs(&m, 1), (0, 0));
}

/// X67-18.11.3.3.10-01, X67-18.11.3.3.10-06: switched from −127 straight to −128 after the positive run has
/// ended, the axis starts a new run, in the negative direction: a run starts whenever a homing mode is
/// selected in Operation enable (the model's pick for the start of a run). Each run stores the counter of
/// its own DI3 edge (RefConfig01 default −125, rising): 220 going up, 180 going down.
#[test]
fn x67_18_11_3_3_10_01_switch_between_homing_modes_starts_a_new_run() {
    let mut m = homing_axis(0, 40, 10, 10);
    m.set_mode(0, modes::HOMING_POSITIVE);
    assert_eq!(incs(&mut m, 0, 7), [10, 20, 30, 40, 40, 40, 40]);
    assert_eq!(m.act_val(0), 220);
    // DI3 rises between two cycles: the reference is the counter at the next cycle's start, and the braking
    // with MaxDec01 = 10 starts in the cycle after.
    m.set_input(3, true);
    assert_eq!(
        incs_bits(&mut m, 0, 6, SW_TARGET_REACHED),
        [
            (40, false),
            (30, false),
            (20, false),
            (10, false),
            (0, true),
            (0, true)
        ]
    );
    assert_eq!(refs(&m, 0), (220, 0));
    assert_eq!(m.act_val(0), 320);
    m.set_input(3, false);
    assert_eq!(incs_bits(&mut m, 0, 1, SW_TARGET_REACHED), [(0, true)]);

    m.set_mode(0, modes::HOMING_NEGATIVE);
    assert_eq!(
        incs_bits(&mut m, 0, 5, SW_TARGET_REACHED),
        [
            (-10, false),
            (-20, false),
            (-30, false),
            (-40, false),
            (-40, false)
        ]
    );
    assert_eq!(m.act_val(0), 180);
    assert_eq!(refs(&m, 0), (220, 0), "not yet referenced again");
    m.set_input(3, true);
    assert_eq!(
        incs_bits(&mut m, 0, 5, SW_TARGET_REACHED),
        [
            (-40, false),
            (-30, false),
            (-20, false),
            (-10, false),
            (0, true)
        ]
    );
    assert_eq!(refs(&m, 0), (180, 0));
    assert_eq!(m.act_val(0), 80);
}

/// X67-18.11.3.3.10-02: switching to homing while the axis runs brakes it with MaxDec0n to standstill first;
/// the homing run starts from speed 0, even when it goes in the direction the axis was already running.
#[test]
fn x67_18_11_3_3_10_02_standstill_before_homing() {
    let mut m = homing_axis(0, 40, 10, 5);
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, 50);
    assert_eq!(incs(&mut m, 0, 6), [10, 20, 30, 40, 50, 50]);
    m.set_mode(0, modes::HOMING_POSITIVE);
    let run = incs_bits(&mut m, 0, 15, SW_TARGET_REACHED);
    let got: Vec<i32> = run.iter().map(|r| r.0).collect();
    assert_eq!(
        got,
        [45, 40, 35, 30, 25, 20, 15, 10, 5, 0, 10, 20, 30, 40, 40]
    );
    assert!(run.iter().all(|r| !r.1), "homing has not ended: bit 10 = 0");

    // The same from a negative speed into negative homing.
    let mut m = homing_axis(0, 20, 10, 10);
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, -30);
    assert_eq!(incs(&mut m, 0, 4), [-10, -20, -30, -30]);
    m.set_mode(0, modes::HOMING_NEGATIVE);
    assert_eq!(incs(&mut m, 0, 7), [-20, -10, 0, -10, -20, -20, -20]);
}

/// X67-18.11.3.3.10-03: the run rises by MaxAcc0n per cycle up to RefSpeed0n (MaxSpeed0npos plays no part)
/// and, after the referencing condition, brakes by MaxDec0n per cycle.
#[test]
fn x67_18_11_3_3_10_03_ref_speed_max_acc_max_dec() {
    let mut m = enabled(0, 10, 7, 4);
    set(&mut m, 0, AxisReg::RefSpeed, 30);
    m.set_mode(0, modes::HOMING_POSITIVE);
    assert_eq!(incs(&mut m, 0, 7), [7, 14, 21, 28, 30, 30, 30]);
    assert_eq!(m.act_val(0), 160);
    // DI3 rises between two cycles (RefConfig01 default −125).
    m.set_input(3, true);
    assert_eq!(incs(&mut m, 0, 1), [30]);
    assert_eq!(refs(&m, 0), (160, 0));
    assert_eq!(incs(&mut m, 0, 9), [26, 22, 18, 14, 10, 6, 2, 0, 0]);
    assert_eq!(m.act_val(0), 160 + 30 + 98);
    assert!(bit(&m, 0, SW_TARGET_REACHED));
}

/// X67-18.11.3.3.10-04, X67-18.11.4.2-13: the internal counter and the ABR counter at the instant of the
/// edge are stored, then the axis brakes with MaxDec0n; bit 10 is 0 during the run and 1 once stopped. The
/// reference switch is a cam on the rotor, so the edge lies at an exact rotor position between two cycle
/// ends, where the encoder already shows a count more than at the start of that cycle.
#[test]
fn x67_18_11_3_3_10_04_references_stored_at_the_edge() {
    let mut m = homing_axis(0, 40, 10, 10);
    m.axis_mut(0).motor.encoder_lines = ENCODER_LINES;
    m.attach_cam(
        3,
        Cam {
            axis: 0,
            from: 1000,
            to: 1_000_000,
        },
    );
    m.set_mode(0, modes::HOMING_POSITIVE);
    // 10, 30, 60, 100, then 40 per cycle: 980 after cycle 26, 1020 after cycle 27.
    let run = incs_bits(&mut m, 0, 26, SW_TARGET_REACHED);
    assert_eq!(m.act_val(0), 980);
    assert!(run.iter().all(|r| !r.1));
    assert_eq!(refs(&m, 0), (0, 0));
    assert_eq!(m.input_status() & 0x04, 0);

    assert_eq!(incs(&mut m, 0, 1), [40]);
    assert_eq!(m.act_val(0), 1020);
    assert_eq!(m.input_status() & 0x04, 0x04);
    assert_eq!(abr_at(1000), 39);
    assert_eq!(refs(&m, 0), (1000, 39));
    assert!(!bit(&m, 0, SW_TARGET_REACHED));

    let run = incs_bits(&mut m, 0, 5, SW_TARGET_REACHED);
    assert_eq!(
        run,
        [(30, false), (20, false), (10, false), (0, true), (0, true)]
    );
    assert_eq!(m.act_val(0), 1080);
    assert_eq!(
        get(&m, 0, AxisReg::ActValAcyclic),
        abr_at(1080),
        "the ABR counter follows the shaft"
    );
    assert_eq!(refs(&m, 0), (1000, 39));
    assert_eq!(m.error_code(0), 0);
}

/// X67-18.11.3.3.10-05: homing stores the reference only; the internal counter goes on from where the axis
/// stopped and keeps its frame, so a later absolute target means the same point as before.
#[test]
fn x67_18_11_3_3_10_05_no_change_of_the_counter() {
    let mut m = enabled(0, 100, 10, 10);
    set(&mut m, 0, AxisReg::RefSpeed, 40);
    m.attach_cam(
        3,
        Cam {
            axis: 0,
            from: 1000,
            to: 1_000_000,
        },
    );
    m.set_mode(0, modes::HOMING_POSITIVE);
    m.run(40);
    assert_eq!(refs(&m, 0).0, 1000);
    assert_eq!(m.act_val(0), 1080);
    assert_eq!(get(&m, 0, AxisReg::ActVal), 1080);
    assert_eq!(incs(&mut m, 0, 5), [0; 5]);
    assert_eq!(m.act_val(0), 1080);

    // Mode 1 to 0 travels the whole 1080 back.
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 0);
    let path = incs(&mut m, 0, 40);
    assert_eq!(path.iter().sum::<i32>(), -1080);
    assert_eq!(m.act_val(0), 0);
    assert_eq!(refs(&m, 0).0, 1000, "the reference stays");
}

/// X67-18.11.3.3.10-06 (case 1), hand-set inputs: the reference level is absent at the start, so the axis
/// travels in the homing direction until the input rises; the counters at that moment are the references.
#[test]
fn x67_18_11_3_3_10_06_case_1_level_absent_at_start() {
    let mut m = homing_axis(0, 40, 10, 10);
    abr_plus_three(&mut m);
    m.step();
    assert_eq!(get(&m, 0, AxisReg::ActValAcyclic), 3);
    m.set_mode(0, modes::HOMING_POSITIVE);
    assert_eq!(incs(&mut m, 0, 6), [10, 20, 30, 40, 40, 40]);
    let p = m.act_val(0);
    assert_eq!(p, 180);
    m.set_input(3, true);
    assert_eq!(incs(&mut m, 0, 1), [40]);
    assert_eq!(refs(&m, 0), (180, 3));
    let run = incs_bits(&mut m, 0, 4, SW_TARGET_REACHED);
    assert_eq!(run, [(30, false), (20, false), (10, false), (0, true)]);
    assert_eq!(m.act_val(0), 280);
    // Further edges change nothing once homing has ended.
    m.set_input(3, false);
    m.set_input(3, true);
    m.run(3);
    assert_eq!(refs(&m, 0), (180, 3));
    assert_eq!(m.act_val(0), 280);

    // Axis 2, negative homing on DI6.
    let mut m = homing_axis(1, 25, 5, 5);
    m.set_mode(1, modes::HOMING_NEGATIVE);
    assert_eq!(incs(&mut m, 1, 6), [-5, -10, -15, -20, -25, -25]);
    m.set_input(3, true);
    m.set_input(4, true);
    assert_eq!(
        incs(&mut m, 1, 1),
        [-25],
        "DI3 and DI4 are not axis 2's R input"
    );
    assert_eq!(refs(&m, 1), (0, 0));
    let p = m.act_val(1);
    assert_eq!(p, -125);
    m.set_input(6, true);
    assert_eq!(incs(&mut m, 1, 1), [-25]);
    // DI4 is also encoder 2's A input: the hand edge counted one on axis 2's ABR counter.
    assert_eq!(refs(&m, 1), (-125, 1));
    assert_eq!(incs(&mut m, 1, 6), [-20, -15, -10, -5, 0, 0]);
    assert!(bit(&m, 1, SW_TARGET_REACHED));
}

/// X67-18.11.3.3.10-07 (case 2): the reference level is present at the start, so the axis first travels
/// against the homing direction until it goes, then in the homing direction until it comes back. With a cam
/// [−500, 500] around the start: the level goes at −501 and comes back at −500 exactly.
#[test]
fn x67_18_11_3_3_10_07_case_2_level_present_at_start() {
    let mut m = homing_axis(0, 40, 10, 10);
    m.attach_cam(
        3,
        Cam {
            axis: 0,
            from: -500,
            to: 500,
        },
    );
    m.step();
    assert_eq!(m.input_status() & 0x04, 0x04);
    m.set_mode(0, modes::HOMING_POSITIVE);
    let leave = incs(&mut m, 0, 15);
    assert_eq!(leave, cat(&[&[-10, -20, -30], &rep(-40, 12)]));
    assert_eq!(m.act_val(0), -540);
    assert_eq!(m.input_status() & 0x04, 0);
    assert_eq!(refs(&m, 0), (0, 0), "the level going is no reference");
    let back = incs_bits(&mut m, 0, 12, SW_TARGET_REACHED);
    let got: Vec<i32> = back.iter().map(|r| r.0).collect();
    assert_eq!(got, [-30, -20, -10, 0, 10, 20, 30, 40, 30, 20, 10, 0]);
    assert_eq!(refs(&m, 0), (-500, 0));
    assert_eq!(m.act_val(0), -440);
    assert!(back[..11].iter().all(|r| !r.1));
    assert!(back[11].1);

    // The same with the input set by hand.
    let mut m = homing_axis(0, 40, 10, 10);
    m.set_input(3, true);
    m.step();
    m.set_mode(0, modes::HOMING_POSITIVE);
    assert_eq!(incs(&mut m, 0, 3), [-10, -20, -30]);
    m.set_input(3, false);
    assert_eq!(incs(&mut m, 0, 1), [-40]);
    assert_eq!(incs(&mut m, 0, 6), [-30, -20, -10, 0, 10, 20]);
    assert_eq!(refs(&m, 0), (0, 0));
    let p = m.act_val(0);
    assert_eq!(p, -130);
    m.set_input(3, true);
    assert_eq!(incs(&mut m, 0, 1), [30]);
    assert_eq!(refs(&m, 0), (-130, 0));
    assert_eq!(incs(&mut m, 0, 4), [20, 10, 0, 0]);
    assert_eq!(m.act_val(0), -70);
    assert!(bit(&m, 0, SW_TARGET_REACHED));
}

/// X67-18.11.3.3.10-08, X67-18.11.3.3.10-09 (warning): homing on stall stores the counters at the stall and
/// stops abruptly: the increment drops from RefSpeed0n to 0 at once, without MaxDec0n's ramp; bit 10 = 1 in
/// that cycle, and the stall warning 0xFF01 is raised as well.
#[test]
fn x67_18_11_3_3_10_08_homing_on_stall_abrupt_stop() {
    let mut m = stall_homing(40);
    m.set_mode(0, modes::HOMING_POSITIVE);
    assert_eq!(incs(&mut m, 0, 7), [10, 20, 30, 40, 40, 40, 40]);
    assert_eq!(m.error_code(0), 0);
    assert_eq!(m.act_val(0), 220);
    // The load rises between two cycles: the stall is there from the next cycle's start.
    m.axis_mut(0).motor.load = Load::Value(2);
    let (inc, sw) = cycle(&mut m, 0);
    assert_eq!(inc, 0, "stopped within one cycle");
    assert_eq!(refs(&m, 0), (220, abr_at(220)));
    assert_eq!(abr_at(220), 8);
    assert!(sw & SW_TARGET_REACHED != 0);
    assert_eq!(m.error_code(0), 0xFF01);
    assert!(sw & SW_WARNING != 0);
    assert_eq!(sw & STATE_MASK, OPERATION_ENABLE);
    assert!(m.axis(0).observation().ramp.standstill);
    assert_eq!(incs(&mut m, 0, 3), [0, 0, 0]);
    assert_eq!(refs(&m, 0), (220, 8));
}

/// X67-18.11.3.3.10-08, X67-18.11.1.11-03: in homing on stall the stall is the only referencing condition,
/// and the R input plays no part: with DI3 high at the start the run does not first travel off it (that is
/// case 2 of the input conditions, X67-18.11.3.3.10-07) but goes straight in the homing direction, DI3
/// edges on the way change nothing, and the stall ends the run as without them.
#[test]
fn x67_18_11_3_3_10_08_stall_homing_ignores_the_r_input() {
    let mut m = stall_homing(40);
    m.set_input(3, true);
    m.step();
    m.set_mode(0, modes::HOMING_POSITIVE);
    assert_eq!(incs(&mut m, 0, 4), [10, 20, 30, 40]);
    m.set_input(3, false);
    assert_eq!(incs(&mut m, 0, 1), [40]);
    m.set_input(3, true);
    assert_eq!(incs(&mut m, 0, 2), [40, 40]);
    assert_eq!(m.act_val(0), 220);
    assert_eq!(refs(&m, 0), (0, 0));
    m.axis_mut(0).motor.load = Load::Value(2);
    let (inc, sw) = cycle(&mut m, 0);
    assert_eq!(inc, 0, "stopped within one cycle");
    assert_eq!(refs(&m, 0), (220, 8));
    assert!(sw & SW_TARGET_REACHED != 0);
}

/// X67-18.11.3.3.10-09: a stall ends the homing run only while it can be detected: control bit 15 = 0, a stall
/// threshold of 0 or a speed not above StallDetectMinSpeed0n leave the run going.
#[test]
fn x67_18_11_3_3_10_09_stall_only_when_detectable() {
    // One condition missing in each case: the run goes on at RefSpeed01 with no reference and no warning.
    // (case, what removes the condition, mode, direction)
    type Remove = fn(&mut Module);
    let cases: [(&str, Remove, i8, i32); 3] = [
        (
            "control bit 15 = 0",
            |m| m.set_control(0, ENABLE_OPERATION),
            modes::HOMING_POSITIVE,
            1,
        ),
        (
            "stall threshold 0",
            |m| set(m, 0, AxisReg::StallDetectConfig, 0x00),
            modes::HOMING_POSITIVE,
            1,
        ),
        (
            "speed not above StallDetectMinSpeed01",
            |m| set(m, 0, AxisReg::StallDetectMinSpeed, 40),
            modes::HOMING_NEGATIVE,
            -1,
        ),
    ];
    for (case, missing, mode, dir) in cases {
        let mut m = stall_homing(40);
        m.axis_mut(0).motor.load = Load::Value(0);
        missing(&mut m);
        m.set_mode(0, mode);
        let expected: Vec<i32> = cat(&[&[10, 20, 30], &rep(40, 17)])
            .into_iter()
            .map(|v| v * dir)
            .collect();
        assert_eq!(incs(&mut m, 0, 20), expected, "{case}");
        assert_eq!((refs(&m, 0), m.error_code(0)), ((0, 0), 0), "{case}");
        assert!(!bit(&m, 0, SW_TARGET_REACHED), "{case}");
    }

    // All conditions met: the first cycle after one at speed > 0 ends the run.
    let mut m = stall_homing(40);
    m.axis_mut(0).motor.load = Load::Value(0);
    m.set_mode(0, modes::HOMING_NEGATIVE);
    assert_eq!(incs(&mut m, 0, 3), [-10, 0, 0]);
    assert_eq!(refs(&m, 0), (-10, abr_at(-10)));
    assert_eq!(m.error_code(0), 0xFF01);
}

/// X67-18.11.3.3.10-10, X67-18.11.1.9-01 (gap): immediate referencing stores both counters at once without
/// moving, even with RefSpeed0n = 0, and homing has ended (bit 10 = 1) in the next status.
#[test]
fn x67_18_11_3_3_10_10_immediate_homing() {
    let mut m = enabled(0, 100, 10, 10);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 500);
    m.run(30);
    assert_eq!(m.act_val(0), 500);
    abr_plus_three(&mut m);
    set_ref_config(&mut m, 0, ref_config::IMMEDIATE);
    m.set_mode(0, modes::HOMING_POSITIVE);
    let (inc, sw) = cycle(&mut m, 0);
    assert_eq!(inc, 0);
    assert!(sw & SW_TARGET_REACHED != 0);
    assert_eq!(refs(&m, 0), (500, 3));
    assert_eq!(incs(&mut m, 0, 5), [0; 5]);
    assert_eq!(m.act_val(0), 500);

    // Negative homing, axis 2, somewhere else.
    let mut m = enabled(1, 100, 10, 10);
    m.set_mode(1, modes::POSITION);
    m.set_abs_pos(1, -777);
    m.run(40);
    set_ref_config(&mut m, 1, ref_config::IMMEDIATE);
    m.set_mode(1, modes::HOMING_NEGATIVE);
    assert_eq!(incs(&mut m, 1, 3), [0, 0, 0]);
    assert_eq!(refs(&m, 1), (-777, 0));
    assert!(bit(&m, 1, SW_TARGET_REACHED));
}

/// X67-18.11.4.2-13: in negative homing bit 10 is 0 in every cycle from the start of the run until the
/// axis stands after the reference, then 1; it was 1 at standstill before.
#[test]
fn x67_18_11_4_2_13_target_reached_in_homing() {
    let mut m = homing_axis(0, 40, 10, 10);
    m.attach_cam(
        3,
        Cam {
            axis: 0,
            from: -1_000_000,
            to: -300,
        },
    );
    assert!(bit(&m, 0, SW_TARGET_REACHED));
    m.set_mode(0, modes::HOMING_NEGATIVE);
    let run = incs_bits(&mut m, 0, 14, SW_TARGET_REACHED);
    let got: Vec<i32> = run.iter().map(|r| r.0).collect();
    // −10, −30, −60, −100, …, −300 (the edge at the end of cycle 9), then braking.
    assert_eq!(
        got,
        [-10, -20, -30, -40, -40, -40, -40, -40, -40, -30, -20, -10, 0, 0]
    );
    let reached: Vec<bool> = run.iter().map(|r| r.1).collect();
    assert_eq!(reached, cat_bools(&[false; 12], &[true; 2]));
    assert_eq!(refs(&m, 0).0, -300);
    assert_eq!(m.act_val(0), -360);
}

// ----- stall homing: currents, delay, minimum speed -----

/// X67-18.11.1.1-03: in homing on stall the nominal current replaces the maximum current while the axis
/// speeds up; homing on an input uses the maximum current there.
#[test]
fn x67_18_11_1_1_03_nominal_current_in_stall_homing() {
    let mut m = stall_homing(40);
    m.set_mode(0, modes::HOMING_POSITIVE);
    let mut levels = Vec::new();
    for _ in 0..8 {
        m.step();
        let c = m.axis(0).observation().current.unwrap();
        levels.push(c.level);
        assert_ne!(c.level, Level::Maximum);
    }
    // Four cycles speeding up, then cruising: nominal throughout, 50 % = 1.5 A.
    assert_eq!(levels, [Level::Nominal; 8]);
    assert_eq!(m.axis(0).phase_current_ma(), 1500);
    m.axis_mut(0).motor.load = Load::Value(0);
    for _ in 0..10 {
        m.step();
        assert_ne!(
            m.axis(0).observation().current.unwrap().level,
            Level::Maximum
        );
    }
    assert_eq!(refs(&m, 0).0, 260);
    assert_eq!(
        m.axis(0).observation().current.unwrap().level,
        Level::Holding
    );
    assert_eq!(m.axis(0).phase_current_ma(), 600);

    // Homing on the R input speeds up with the maximum current.
    let mut m = homing_axis(0, 40, 10, 10);
    m.set_mode(0, modes::HOMING_POSITIVE);
    m.step();
    let c = m.axis(0).observation().current.unwrap();
    assert_eq!(c.level, Level::Maximum);
    assert_eq!(m.axis(0).phase_current_ma(), 3000);
}

/// X67-18.11.1.12-01: with StallRecognitionDelay01 = N a stall present from the start of the run is taken
/// N cycles after the run starts, not earlier; N = 0 takes it in the first cycle that follows a moving one.
#[test]
fn x67_18_11_1_12_01_stall_recognition_delay() {
    for (delay, run, reference) in [
        (0, vec![10, 0], 10),
        (2, vec![10, 20, 0], 30),
        (4, vec![10, 20, 30, 40, 0], 100),
    ] {
        let mut m = stall_homing(40);
        m.axis_mut(0).motor.load = Load::Value(2);
        set(&mut m, 0, AxisReg::StallRecognitionDelay, delay);
        m.set_mode(0, modes::HOMING_POSITIVE);
        let t0 = m.time_ms();
        let n = run.len();
        assert_eq!(incs(&mut m, 0, n), run, "delay {delay}");
        assert_eq!(refs(&m, 0).0, reference, "delay {delay}");
        // The reference is taken at the start of the last of these cycles: N × 25 ms after the start (and
        // one cycle later for N = 0, since a stall needs a moving axis).
        let taken_at = m.time_ms() - 25 - t0;
        assert_eq!(taken_at, 25 * (delay.max(1) as u64), "delay {delay}");
        assert!(bit(&m, 0, SW_TARGET_REACHED));
        assert_eq!(m.error_code(0), 0xFF01);
    }
}

/// X67-18.11.1.12-02: the delay is for homing on stall only: in mode 1 a stall raises 0xFF01 at once even
/// with StallRecognitionDelay01 = 255, and the move goes on.
#[test]
fn x67_18_11_1_12_02_delay_only_in_stall_homing() {
    let mut m = enabled(0, 100, 10, 10);
    m.axis_mut(0).motor.load = Load::Value(2);
    set(&mut m, 0, AxisReg::StallDetectConfig, 0x30);
    set(&mut m, 0, AxisReg::StallRecognitionDelay, 255);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 10_000);
    assert_eq!(incs(&mut m, 0, 1), [10]);
    assert_eq!(
        m.error_code(0),
        0,
        "standstill in the cycle before: no stall"
    );
    assert_eq!(incs(&mut m, 0, 1), [20]);
    assert_eq!(m.error_code(0), 0xFF01);
    assert!(bit(&m, 0, SW_WARNING));
    assert_eq!(incs(&mut m, 0, 3), [30, 40, 50]);
}

/// X67-18.11.1.13-01: a stall is reported only above StallDetectMinSpeed01 (= 50): in homing on stall a run
/// at RefSpeed 50 never ends on it and one at 51 does; in speed mode 50 raises nothing and 51 raises 0xFF01.
#[test]
fn x67_18_11_1_13_01_minimum_speed_for_stall_detection() {
    for (ref_speed, stops) in [(50, false), (51, true)] {
        let mut m = stall_homing(ref_speed);
        m.axis_mut(0).motor.load = Load::Value(0);
        set(&mut m, 0, AxisReg::StallDetectMinSpeed, 50);
        m.set_mode(0, modes::HOMING_POSITIVE);
        let run = incs(&mut m, 0, 10);
        if stops {
            assert_eq!(run, [10, 20, 30, 40, 50, 51, 0, 0, 0, 0]);
            assert_eq!(refs(&m, 0).0, 201);
            assert_eq!(m.error_code(0), 0xFF01);
        } else {
            assert_eq!(run, [10, 20, 30, 40, 50, 50, 50, 50, 50, 50]);
            assert_eq!(refs(&m, 0).0, 0);
            assert_eq!(m.error_code(0), 0);
        }
    }

    // Outside homing.
    let mut m = enabled(0, 0, 10, 10);
    m.axis_mut(0).motor.load = Load::Value(0);
    set(&mut m, 0, AxisReg::StallDetectConfig, 0x70);
    set(&mut m, 0, AxisReg::StallDetectMinSpeed, 50);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, 50);
    assert_eq!(incs(&mut m, 0, 20), cat(&[&[10, 20, 30, 40], &rep(50, 16)]));
    assert_eq!(m.error_code(0), 0);
    m.set_abs_pos(0, 51);
    assert_eq!(incs(&mut m, 0, 1), [51]);
    assert_eq!(m.error_code(0), 0, "the cycle before ran at 50");
    assert_eq!(incs(&mut m, 0, 1), [51]);
    assert_eq!(m.error_code(0), 0xFF01);
}

/// X67-18.11.1.9-01: RefSpeed0n is the travel speed of the run; with 0 the axis waits at standstill with
/// homing not ended, until a condition comes without motion (here the R input rising by itself).
#[test]
fn x67_18_11_1_9_01_homing_speed() {
    let mut m = homing_axis(0, 25, 100, 100);
    m.set_mode(0, modes::HOMING_POSITIVE);
    assert_eq!(incs(&mut m, 0, 5), [25; 5]);

    let mut m = enabled(0, 100, 10, 10);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 300);
    m.run(20);
    assert_eq!(m.act_val(0), 300);
    m.set_mode(0, modes::HOMING_POSITIVE);
    let run = incs_bits(&mut m, 0, 10, SW_TARGET_REACHED);
    assert_eq!(run, vec![(0, false); 10]);
    assert_eq!(refs(&m, 0), (0, 0));
    m.set_input(3, true);
    assert_eq!(incs_bits(&mut m, 0, 2, SW_TARGET_REACHED), [(0, true); 2]);
    assert_eq!(refs(&m, 0), (300, 0));
}

// ----- RefConfig: X67-18.11.1.11 -----

/// X67-18.11.1.11-01: −121 is the rising and −122 the falling edge of DI4, for axis 1 and for axis 2.
#[test]
fn x67_18_11_1_11_01_di4_edges_for_both_axes() {
    // Axis 1, −121: DI4 rises at 600; DI3 (its R input) does nothing.
    let mut m = homing_axis(0, 40, 10, 10);
    set_ref_config(&mut m, 0, ref_config::DI4_RISING);
    cam(&mut m, 4, 0, 600, 1_000_000);
    m.set_mode(0, modes::HOMING_POSITIVE);
    m.run(5);
    m.set_input(3, true);
    m.run(5);
    assert_eq!(refs(&m, 0), (0, 0));
    m.run(10);
    assert_eq!(refs(&m, 0).0, 600);
    assert_eq!(m.input_status() & 0x08, 0x08);

    // Axis 2, −122: DI4 high up to 700, so its falling edge lies at 701.
    let mut m = homing_axis(1, 40, 10, 10);
    set_ref_config(&mut m, 1, ref_config::DI4_FALLING);
    cam(&mut m, 4, 1, -1_000_000, 700);
    m.step();
    assert_eq!(m.input_status() & 0x08, 0x08);
    m.set_mode(1, modes::HOMING_POSITIVE);
    // 10, 30, 60, 100, then 40 per cycle: 700 after cycle 19, 740 after cycle 20.
    m.run(19);
    assert_eq!((m.act_val(1), refs(&m, 1).0), (700, 0));
    m.step();
    assert_eq!(refs(&m, 1).0, 701);
    assert_eq!(m.input_status() & 0x08, 0);
    assert_eq!(get(&m, 1, AxisReg::RefConfig), -122);
}

/// X67-18.11.1.11-02: −125 is the rising and −126 the falling edge of the axis's R input: DI3 for axis 1,
/// DI6 for axis 2.
#[test]
fn x67_18_11_1_11_02_r_input_edges() {
    // Axis 2, Mode −128, −126: DI6 high from −800 on, so it falls at −801.
    let mut m = homing_axis(1, 40, 10, 10);
    set_ref_config(&mut m, 1, ref_config::R_FALLING);
    cam(&mut m, 6, 1, -800, 1_000_000);
    m.step();
    m.set_mode(1, modes::HOMING_NEGATIVE);
    m.run(4);
    m.set_input(3, false);
    m.set_input(3, true);
    m.set_input(3, false);
    m.run(17);
    assert_eq!((m.act_val(1), refs(&m, 1).0), (-780, 0));
    m.step();
    assert_eq!(refs(&m, 1).0, -801);
    assert_eq!(m.input_status() & 0x20, 0);

    // Axis 1, Mode −127, −126 by hand: DI3 high at the start is the inactive level.
    let mut m = homing_axis(0, 40, 10, 10);
    set_ref_config(&mut m, 0, ref_config::R_FALLING);
    m.set_input(3, true);
    m.set_mode(0, modes::HOMING_POSITIVE);
    assert_eq!(incs(&mut m, 0, 4), [10, 20, 30, 40]);
    m.set_input(6, false);
    m.set_input(6, true);
    m.set_input(6, false);
    m.step();
    assert_eq!(refs(&m, 0), (0, 0), "DI6 is axis 2's R input");
    m.set_input(3, false);
    m.step();
    assert_eq!(refs(&m, 0).0, 140);
}

/// X67-18.11.1.11-03: −127 makes a stall the condition (an R-input edge does not end the run) and −128 ends
/// homing at once without motion.
#[test]
fn x67_18_11_1_11_03_stall_and_immediate() {
    let mut m = stall_homing(40);
    assert_eq!(get(&m, 0, AxisReg::RefConfig), -127);
    m.set_mode(0, modes::HOMING_POSITIVE);
    m.run(5);
    m.set_input(3, true);
    m.run(3);
    assert_eq!(refs(&m, 0).0, 0);
    assert_eq!(m.act_val(0), 260);
    m.axis_mut(0).motor.load = Load::Value(1);
    assert_eq!(incs(&mut m, 0, 2), [0, 0]);
    assert_eq!(refs(&m, 0).0, 260);

    let mut m = homing_axis(0, 40, 10, 10);
    set_ref_config(&mut m, 0, ref_config::IMMEDIATE);
    assert_eq!(get(&m, 0, AxisReg::RefConfig), -128);
    m.set_mode(0, modes::HOMING_NEGATIVE);
    assert_eq!(incs(&mut m, 0, 3), [0, 0, 0]);
    assert!(bit(&m, 0, SW_TARGET_REACHED));
}

/// X67-18.11.1.11-04: −120 is no referencing condition; the write is ignored and the previous value stays.
#[test]
fn x67_18_11_1_11_04_minus_120_ignored() {
    let mut m = homing_axis(0, 40, 10, 10);
    set(&mut m, 0, AxisReg::RefConfig, -120);
    assert_eq!(get(&m, 0, AxisReg::RefConfig), -125);
    set_ref_config(&mut m, 0, ref_config::DI4_RISING);
    set(&mut m, 0, AxisReg::RefConfig, -120);
    assert_eq!(get(&m, 0, AxisReg::RefConfig), -121);
    cam(&mut m, 4, 0, 600, 1_000_000);
    m.set_mode(0, modes::HOMING_POSITIVE);
    m.run(4);
    m.set_input(3, true);
    m.run(16);
    assert_eq!(refs(&m, 0).0, 600, "homed on DI4 as −121 says");
}

/// X67-18.11.1.11-05: a value not listed is ignored: −125 stays after power-up, and any other value in force
/// stays as well.
#[test]
fn x67_18_11_1_11_05_unlisted_values_ignored() {
    let mut m = homing_axis(0, 40, 10, 10);
    for v in [0, 1, -1, -60, -119, -123, -124, 127] {
        set(&mut m, 0, AxisReg::RefConfig, v);
        assert_eq!(get(&m, 0, AxisReg::RefConfig), -125, "value {v}");
    }
    m.set_mode(0, modes::HOMING_POSITIVE);
    assert_eq!(incs(&mut m, 0, 4), [10, 20, 30, 40]);
    m.set_input(3, true);
    m.step();
    assert_eq!(refs(&m, 0).0, 100);

    let mut m = homing_axis(0, 40, 10, 10);
    set_ref_config(&mut m, 0, ref_config::R_FALLING);
    set(&mut m, 0, AxisReg::RefConfig, 0);
    assert_eq!(get(&m, 0, AxisReg::RefConfig), -126);
}

/// X67-18.11.1.11-06: RefConfig01 is −125 after power-up: homing ends on DI3 rising, not on DI4 or DI6.
#[test]
fn x67_18_11_1_11_06_default_minus_125() {
    let m = Module::new();
    assert_eq!(m.read_named("RefConfig01"), -125);
    assert_eq!(m.read_named("RefConfig02"), -125);
    let mut m = homing_axis(0, 40, 10, 10);
    m.set_mode(0, modes::HOMING_POSITIVE);
    m.run(4);
    m.set_input(4, true);
    m.set_input(6, true);
    m.step();
    assert_eq!(refs(&m, 0).0, 0);
    m.set_input(3, true);
    m.step();
    assert_eq!(refs(&m, 0).0, 140);
}

// ----- reference registers: X67-18.11.3.9 -----

/// X67-18.11.3.9-01: RefPos0nCyclicCounter holds the reference of the counter shown in AbsPos0nActVal and
/// RefPos0nAcyclicCounter the other one, following control bit 14 at read time.
#[test]
fn x67_18_11_3_9_01_cyclic_and_acyclic_references() {
    let mut m = homing_axis(0, 40, 10, 10);
    m.axis_mut(0).motor.encoder_lines = ENCODER_LINES;
    cam(&mut m, 3, 0, 12_345, 1_000_000);
    m.set_mode(0, modes::HOMING_POSITIVE);
    m.run(320);
    assert_eq!(abr_at(12_345), 482);
    assert_eq!(refs(&m, 0), (12_345, 482));
    // 12 340 → 12 380 is the cycle of the edge; braking 30, 20, 10.
    assert_eq!(m.act_val(0), 12_440);
    assert_eq!(get(&m, 0, AxisReg::ActValAcyclic), abr_at(12_440));

    m.set_control(0, ENABLE_OPERATION | CW_SWAP_COUNTERS);
    m.step();
    assert_eq!(refs(&m, 0), (482, 12_345));
    assert_eq!(m.act_val(0) as i64, abr_at(12_440));
    assert_eq!(get(&m, 0, AxisReg::ActValAcyclic), 12_440);
    assert_eq!(m.status_word(0) & STATE_MASK, OPERATION_ENABLE);

    m.set_control(0, ENABLE_OPERATION);
    m.step();
    assert_eq!(refs(&m, 0), (12_345, 482));
    assert_eq!(m.act_val(0), 12_440);
}

/// X67-18.11.3.9-02: before any homing both reference registers of both axes read 0, also after motion.
#[test]
fn x67_18_11_3_9_02_zero_before_homing() {
    let m = Module::new();
    for name in [
        "RefPos01CyclicCounter",
        "RefPos01AcyclicCounter",
        "RefPos02CyclicCounter",
        "RefPos02AcyclicCounter",
    ] {
        assert_eq!(m.read_named(name), 0, "{name}");
    }
    let mut m = enabled(0, 100, 10, 10);
    abr_plus_three(&mut m);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 3000);
    m.run(50);
    assert_eq!(m.act_val(0), 3000);
    assert_eq!(refs(&m, 0), (0, 0));
    m.set_control(0, ENABLE_OPERATION | CW_SWAP_COUNTERS);
    m.step();
    assert_eq!(refs(&m, 0), (0, 0));
    assert_eq!(refs(&m, 1), (0, 0));
}
