//! Homing, limit switches and software limits of the X67SM2436 module model ("Ramp", seed 002, 18.11.1.9,
//! 18.11.1.11 to 18.11.1.13, 18.11.1.16, 18.11.1.17, 18.11.3.3.10, 18.11.3.9), run through the module's
//! registers cycle by cycle. Each test names the rules of `rules/x67.md` it covers; the numbers are worked
//! out by hand from the rules and the ramp discretisation of X67-18.11.3.3.1-01 (speed first, then position).
//!
//! Timing of the inputs, from the module documentation: a cam switches its input at the exact rotor position
//! within a cycle; an input the harness sets between two cycles is seen in the next cycle at the counter
//! values of that cycle's start, and a braking ramp it causes starts in the cycle after.

mod x67_rig;

use ds402::cia402::control::ENABLE_OPERATION;
use ds402::cia402::SW_WARNING;
use ds402::x67::axis::{modes, ref_config, CW_SWAP_COUNTERS, SW_INTERNAL_LIMIT, SW_TARGET_REACHED};
use ds402::x67::current::Level;
use ds402::x67::errors::{CW_STALL_DETECTION, CW_WARNING_RESET};
use ds402::x67::module::{Cam, Module};
use ds402::x67::motor::Load;
use ds402::x67::registers::AxisReg;
use proptest::prelude::*;
use x67_rig::{
    cat, cat_bools, get, increments as incs, set, set_currents, set_ref_config, OPERATION_ENABLE,
    STATE_MASK,
};

// ----- helpers -----

/// Encoder lines for the tests with an ABR counter: 4 × 500 counts per 200 × 256 microsteps, i.e. 5 counts
/// per 128 microsteps.
const ENCODER_LINES: u32 = 500;

/// The ABR count of an encoder with [`ENCODER_LINES`] at a rotor position (4x evaluation, rounded down).
fn abr_at(rotor: i64) -> i64 {
    (rotor * 4 * i64::from(ENCODER_LINES)).div_euclid(200 * 256)
}

/// RefPos0nCyclicCounter and RefPos0nAcyclicCounter.
fn refs(m: &Module, axis: usize) -> (i64, i64) {
    (
        get(m, axis, AxisReg::RefPosCyclicCounter),
        get(m, axis, AxisReg::RefPosAcyclicCounter),
    )
}

/// A new module whose axis `axis` is in Operation enable at position 0 with mode 0, the given MaxSpeed0npos,
/// MaxAcc0n and MaxDec0n, and currents of 20 % (holding), 50 % (nominal) and 100 % (maximum).
fn enabled(axis: usize, max_speed: i64, acc: i64, dec: i64) -> Module {
    let mut m = Module::new();
    set_currents(&mut m, axis, 20, 50, 100);
    x67_rig::operation_enable(&mut m, axis, max_speed, acc, dec);
    assert_eq!(m.act_val(axis), 0);
    m
}

/// [`enabled`] with RefSpeed0n.
fn homing_axis(axis: usize, ref_speed: i64, acc: i64, dec: i64) -> Module {
    let mut m = enabled(axis, 0, acc, dec);
    set(&mut m, axis, AxisReg::RefSpeed, ref_speed);
    m
}

/// One cycle; returns the increment of AbsPos0nActVal (control bit 14 = 0) and the status word after it.
fn cycle(m: &mut Module, axis: usize) -> (i32, u16) {
    let c = x67_rig::cycle(m, axis);
    (c.inc, c.sw)
}

/// The increments of `n` cycles with SW bit `mask` after each.
fn incs_bits(m: &mut Module, axis: usize, n: usize, mask: u16) -> Vec<(i32, bool)> {
    (0..n)
        .map(|_| {
            let (inc, sw) = cycle(m, axis);
            (inc, sw & mask != 0)
        })
        .collect()
}

fn rep(value: i32, n: usize) -> Vec<i32> {
    vec![value; n]
}

fn bit(m: &Module, axis: usize, mask: u16) -> bool {
    m.status_word(axis) & mask != 0
}

/// Sets the ABR counter of axis 1 to +3 by hand quadrature on DI1/DI2 (A leading B counts up).
fn abr_plus_three(m: &mut Module) {
    m.set_input(1, true);
    m.set_input(2, true);
    m.set_input(1, false);
}

/// A cam on `input` carried by the rotor of `axis`.
fn cam(m: &mut Module, input: usize, axis: usize, from: i64, to: i64) {
    m.attach_cam(input, Cam { axis, from, to });
}

/// Stall homing set-up: threshold 3, stall detection on (control bit 15), RefConfig −127, encoder on the
/// shaft, a light load (load value 7: no stall).
fn stall_homing(ref_speed: i64) -> Module {
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
fn running(config: i64, speed: i32) -> Module {
    let mut m = enabled(0, 0, 10, 5);
    set(&mut m, 0, AxisReg::LimitSwitchConfig, config);
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, speed);
    let s = speed.signum();
    assert_eq!(incs(&mut m, 0, 5), [10 * s, 20 * s, 30 * s, 40 * s, 40 * s]);
    m
}

/// Sets `input` to each level in turn, one cycle each; returns the increment and ErrorCode01 after each.
fn drive(m: &mut Module, input: usize, levels: &[bool]) -> Vec<(i32, u16)> {
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
fn drive_none(m: &mut Module, n: usize) -> Vec<(i32, u16)> {
    (0..n)
        .map(|_| {
            let (inc, _) = cycle(m, 0);
            (inc, m.error_code(0))
        })
        .collect()
}

/// Writes PositionLimitMin0n and PositionLimitMax0n.
fn limits(m: &mut Module, axis: usize, min: i64, max: i64) {
    set(m, axis, AxisReg::PositionLimitMin, min);
    set(m, axis, AxisReg::PositionLimitMax, max);
}

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

// ----- limit switches: X67-18.11.1.16 -----

/// A limit-switch case: axis 1 running in Mode 2 with LimitSwitchConfig01 = `config`, `input` driven through
/// `levels`, what [`drive`] returns for them, and the increments of the braking that follows.
struct SwitchCase {
    config: i64,
    input: usize,
    levels: &'static [bool],
    seen: &'static [(i32, u16)],
    braking: &'static [i32],
}

/// Runs `case` at `speed` and checks it, naming the case in each assertion.
#[track_caller]
fn check_switch(case: &SwitchCase, speed: i32) {
    let SwitchCase {
        config,
        input,
        levels,
        seen,
        braking,
    } = *case;
    let mut m = running(config, speed);
    assert_eq!(
        drive(&mut m, input, levels),
        seen,
        "config {config:#06b}, DI{input}"
    );
    assert_eq!(
        incs(&mut m, 0, braking.len()),
        braking,
        "config {config:#06b}, DI{input}"
    );
}

/// X67-18.11.1.16-01: bits 0–1 set the negative switch (DI1): 11 active high, 01 active low, 10 (reserved)
/// and 00 off. Only the edge into the active level triggers 0xFF20 and the braking.
#[test]
fn x67_18_11_1_16_01_negative_switch_polarity() {
    let cases = [
        SwitchCase {
            config: 0b11,
            input: 1,
            levels: &[true],
            seen: &[(-40, 0xFF20)],
            braking: &[-35, -30, -25, -20, -15, -10, -5, 0],
        },
        SwitchCase {
            config: 0b01,
            input: 1,
            levels: &[true, false],
            seen: &[(-40, 0), (-40, 0xFF20)],
            braking: &[-35, -30],
        },
    ];
    for case in &cases {
        check_switch(case, -40);
    }

    for config in [0b10, 0b00] {
        let mut m = running(config, -40);
        assert_eq!(
            drive(&mut m, 1, &[true, false, true, false]),
            [(-40, 0); 4],
            "config {config:#04b}"
        );
        assert!(!bit(&m, 0, SW_WARNING));
    }
}

/// X67-18.11.1.16-02: bits 2–3 set the positive switch (DI2) with the same encoding; 0xFF21.
#[test]
fn x67_18_11_1_16_02_positive_switch_polarity() {
    let cases = [
        SwitchCase {
            config: 0b0100,
            input: 2,
            levels: &[true, false],
            seen: &[(40, 0), (40, 0xFF21)],
            braking: &[35, 30, 25, 20, 15, 10, 5, 0],
        },
        SwitchCase {
            config: 0b1100,
            input: 2,
            levels: &[true],
            seen: &[(40, 0xFF21)],
            braking: &[],
        },
        // The negative switch's input is not the positive switch.
        SwitchCase {
            config: 0b1100,
            input: 1,
            levels: &[true],
            seen: &[(40, 0)],
            braking: &[],
        },
    ];
    for case in &cases {
        check_switch(case, 40);
    }

    for config in [0b1000, 0b0000] {
        let mut m = running(config, 40);
        assert_eq!(
            drive(&mut m, 2, &[true, false, true]),
            [(40, 0); 3],
            "config {config:#06b}"
        );
    }
}

/// X67-18.11.1.16-03: bit 7 is direction monitoring (off by default) and bits 4–6 are reserved: with bit 7 = 0
/// a negative switch stops a positive move; with bit 7 = 1 it does not, whatever bits 4–6 hold.
#[test]
fn x67_18_11_1_16_03_direction_monitoring_bit() {
    let m = Module::new();
    assert_eq!(m.read_named("LimitSwitchConfig01"), 0);
    for (config, expected) in [(0x03, 0xFF20), (0x73, 0xFF20), (0x83, 0), (0xF3, 0)] {
        let mut m = running(config, 40);
        let got = drive(&mut m, 1, &[true]);
        assert_eq!(got, [(40, expected)], "config {config:#04x}");
        let next = if expected == 0 { 40 } else { 35 };
        assert_eq!(incs(&mut m, 0, 1), [next], "config {config:#04x}");
    }
}

/// X67-18.11.1.16-04: reaching an active switch raises the warning and brakes with MaxDec01 to speed 0; the
/// state stays Operation enable and the holding current flows at standstill.
#[test]
fn x67_18_11_1_16_04_warning_and_braking_without_state_change() {
    let mut m = running(0b1100, 40);
    m.set_input(2, true);
    let (inc, sw) = cycle(&mut m, 0);
    assert_eq!(inc, 40);
    assert_eq!(m.error_code(0), 0xFF21);
    assert!(sw & SW_WARNING != 0);
    assert_eq!(sw & STATE_MASK, OPERATION_ENABLE);
    for expected in [35, 30, 25, 20, 15, 10, 5, 0] {
        let (inc, sw) = cycle(&mut m, 0);
        assert_eq!(inc, expected);
        assert_eq!(sw & STATE_MASK, OPERATION_ENABLE);
        assert!(sw & SW_WARNING != 0);
    }
    assert_eq!(m.act_val(0), 320);
    m.run(5);
    assert_eq!(m.act_val(0), 320, "the set-point 40 is not followed");
    let obs = m.axis(0).observation();
    assert!(obs.powered);
    assert_eq!(obs.current.unwrap().level, Level::Holding);
    assert_eq!(m.axis(0).phase_current_ma(), 600);
    assert_eq!(m.status_word(0) & STATE_MASK, OPERATION_ENABLE);
    assert_eq!(m.error_code(0), 0xFF21);
}

/// X67-18.11.1.16-04: a limit switch holding the axis in speed mode: bit 10 is 0 while the axis brakes
/// (40, 35, …, 5) and 1 once it stands, and stays 1 while the switch holds it, although the set-point speed
/// 40 is not reached (the model's pick: while a limit holds the axis bit 10 shows standstill).
#[test]
fn x67_18_11_1_16_04_bit_10_while_a_switch_holds_the_axis() {
    let mut m = running(0b1100, 40);
    m.set_input(2, true);
    let expected: Vec<(i32, bool)> = [40, 35, 30, 25, 20, 15, 10, 5]
        .into_iter()
        .map(|v| (v, false))
        .chain([(0, true); 5])
        .collect();
    assert_eq!(incs_bits(&mut m, 0, 13, SW_TARGET_REACHED), expected);
    assert_eq!(m.error_code(0), 0xFF21);
}

/// Which inputs are an axis's limit switches is the harness's choice (module documentation):
/// `set_limit_inputs(axis 1, DI5, DI6)` makes DI6 the positive switch of axis 1 (0xFF21 and braking) and
/// leaves DI2, its default, without effect; inputs outside 1…6 are held to DI1/DI6.
#[test]
fn x67_18_11_1_16_02_limit_switch_inputs_chosen_by_the_harness() {
    let mut m = running(0b1100, 40);
    m.set_limit_inputs(0, 5, 6);
    assert_eq!(drive(&mut m, 2, &[true]), [(40, 0)], "DI2 is no switch now");
    assert_eq!(drive(&mut m, 6, &[true]), [(40, 0xFF21)]);
    assert_eq!(incs(&mut m, 0, 8), [35, 30, 25, 20, 15, 10, 5, 0]);

    let mut m = running(0b1100, 40);
    m.set_limit_inputs(0, 0, 9);
    assert_eq!(drive(&mut m, 5, &[true]), [(40, 0)]);
    assert_eq!(drive(&mut m, 6, &[true]), [(40, 0xFF21)]);
}

/// X67-18.11.1.16-05: the acknowledgement (↑ bit 12) restores normal operation in both directions while the
/// switch stays active; the switch triggers again only on its next active edge.
#[test]
fn x67_18_11_1_16_05_acknowledge_and_next_edge() {
    let mut m = running(0b1100, 40);
    m.set_input(2, true);
    m.run(10);
    assert_eq!((m.act_val(0), m.error_code(0)), (320, 0xFF21));

    m.set_control(0, ENABLE_OPERATION | CW_WARNING_RESET);
    let (inc, sw) = cycle(&mut m, 0);
    assert_eq!((inc, m.error_code(0)), (10, 0));
    assert_eq!(sw & SW_WARNING, 0);
    assert_eq!(
        incs(&mut m, 0, 4),
        [20, 30, 40, 40],
        "toward the active switch"
    );
    assert_eq!(m.error_code(0), 0);
    m.set_abs_pos(0, -40);
    let back = incs(&mut m, 0, 20);
    assert_eq!(&back[..9], [35, 30, 25, 20, 15, 10, 5, 0, -10]);
    assert_eq!(back[19], -40);
    assert_eq!(m.error_code(0), 0);
    assert_eq!(m.input_status() & 0x02, 0x02, "DI2 still high");

    assert_eq!(drive(&mut m, 2, &[false, true]), [(-40, 0), (-40, 0xFF21)]);
    assert_eq!(incs(&mut m, 0, 2), [-35, -30]);
}

/// X67-18.11.1.16-06: without direction monitoring an axis that brakes past a switch (a cam [−1000, −900])
/// triggers it again when it reverses back over it after the acknowledgement.
#[test]
fn x67_18_11_1_16_06_overshoot_and_retrigger_when_reversing() {
    let mut m = running(0b11, -40);
    cam(&mut m, 1, 0, -1000, -900);
    // −100 after the first 4 cycles; 20 more at −40 reach −900, the switch's first position, exactly.
    assert_eq!(incs(&mut m, 0, 19), rep(-40, 19));
    assert_eq!((m.act_val(0), m.error_code(0)), (-900, 0xFF20));
    assert_eq!(incs(&mut m, 0, 8), [-35, -30, -25, -20, -15, -10, -5, 0]);
    assert_eq!(m.act_val(0), -1040);
    assert_eq!(m.input_status() & 0x01, 0, "braked past the switch");
    assert_eq!(m.error_code(0), 0xFF20);

    m.set_control(0, ENABLE_OPERATION | CW_WARNING_RESET);
    m.set_abs_pos(0, 40);
    assert_eq!(drive_none(&mut m, 2), [(10, 0), (20, 0)]);
    assert_eq!(m.act_val(0), -1010);
    assert_eq!(drive_none(&mut m, 1), [(30, 0xFF20)], "over −1000 again");
    assert_eq!(incs(&mut m, 0, 6), [25, 20, 15, 10, 5, 0]);
    assert_eq!(m.act_val(0), -905);
    assert_eq!(m.input_status() & 0x01, 0x01);
}

/// X67-18.11.1.16-07: with direction monitoring the negative switch triggers only in a commanded negative
/// movement; the commanded direction counts, so a motor wired in reverse never triggers the switch it runs
/// into, and the direction that would free it is the one denied (the data sheet's warning).
#[test]
fn x67_18_11_1_16_07_direction_monitoring() {
    // The negative switch is active; a positive move runs to its end.
    let mut m = enabled(0, 100, 10, 10);
    set(&mut m, 0, AxisReg::LimitSwitchConfig, 0x83);
    m.set_input(1, true);
    m.step();
    assert_eq!(m.error_code(0), 0);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 5000);
    m.run(20);
    m.set_input(1, false);
    m.step();
    m.set_input(1, true);
    m.run(60);
    assert_eq!(m.act_val(0), 5000);
    assert!(bit(&m, 0, SW_TARGET_REACHED));
    assert_eq!(m.error_code(0), 0);
    // Without direction monitoring the same active edge stops the positive move.
    let mut m = enabled(0, 100, 10, 10);
    set(&mut m, 0, AxisReg::LimitSwitchConfig, 0x03);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 5000);
    m.run(20);
    m.set_input(1, true);
    m.run(60);
    assert_eq!(m.error_code(0), 0xFF20);
    assert_eq!(m.act_val(0), 1550 + 100 + 450);

    // A motor wired in reverse: the rotor runs against the internal counter, into the switch of the other
    // direction. Switch cams: DI1 (negative) at rotor [−3000, −2000], DI2 (positive) at [2000, 3000].
    for (config, triggers) in [(0x8F, false), (0x0F, true)] {
        for (target, input) in [(10_000, 1), (-10_000, 2)] {
            let mut m = enabled(0, 100, 10, 10);
            m.axis_mut(0).motor.params.reversed = true;
            set(&mut m, 0, AxisReg::LimitSwitchConfig, config);
            cam(&mut m, 1, 0, -3000, -2000);
            cam(&mut m, 2, 0, 2000, 3000);
            m.set_mode(0, modes::POSITION);
            m.set_abs_pos(0, target);
            let mut crossed = false;
            for _ in 0..150 {
                m.step();
                crossed |= m.input_status() & (1 << (input - 1)) != 0;
            }
            assert!(crossed, "the rotor ran into DI{input}");
            if triggers {
                assert_eq!(m.error_code(0), [0xFF20, 0xFF21][input - 1]);
                assert!(m.act_val(0).abs() < 3000);
            } else {
                assert_eq!(m.error_code(0), 0, "DI{input}");
                assert_eq!(m.act_val(0), target);
                assert_eq!(m.axis(0).motor.rotor(), -i64::from(target));
            }
        }
    }

    // The same motor standing on its negative switch (rotor −2500): the commanded negative move, which would
    // turn the rotor off the switch, is the one refused.
    let mut m = enabled(0, 100, 10, 10);
    m.axis_mut(0).motor.params.reversed = true;
    set(&mut m, 0, AxisReg::LimitSwitchConfig, 0x83);
    cam(&mut m, 1, 0, -3000, -2000);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 2500);
    m.run(40);
    assert_eq!((m.act_val(0), m.axis(0).motor.rotor()), (2500, -2500));
    assert_eq!((m.input_status() & 0x01, m.error_code(0)), (0x01, 0));
    m.set_abs_pos(0, 0);
    assert_eq!(drive_none(&mut m, 3), [(0, 0xFF20); 3]);
}

/// X67-18.11.1.16-08: with direction monitoring and the switch active, a move toward it is refused (the
/// warning is raised again, no motion) and a move away from it runs.
#[test]
fn x67_18_11_1_16_08_move_toward_active_switch_refused() {
    let mut m = enabled(0, 100, 10, 10);
    set(&mut m, 0, AxisReg::LimitSwitchConfig, 0x83);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, -10_000);
    m.run(15);
    assert_eq!(m.act_val(0), -1050);
    // With direction monitoring the active level is checked against the commanded direction when the
    // cycle's set-point is chosen, so the braking starts in the cycle that sees the input.
    m.set_input(1, true);
    assert_eq!(drive_none(&mut m, 1), [(-90, 0xFF20)]);
    assert_eq!(
        incs(&mut m, 0, 9),
        [-80, -70, -60, -50, -40, -30, -20, -10, 0]
    );
    assert_eq!(m.act_val(0), -1500);

    // Acknowledged with the negative target still there: refused.
    m.set_control(0, ENABLE_OPERATION | CW_WARNING_RESET);
    assert_eq!(drive_none(&mut m, 5), [(0, 0xFF20); 5]);
    assert!(bit(&m, 0, SW_WARNING));
    // A positive target is held until the acknowledgement, then runs.
    m.set_control(0, ENABLE_OPERATION);
    m.set_abs_pos(0, 5000);
    assert_eq!(drive_none(&mut m, 1), [(0, 0xFF20)]);
    m.set_control(0, ENABLE_OPERATION | CW_WARNING_RESET);
    assert_eq!(drive_none(&mut m, 3), [(10, 0), (20, 0), (30, 0)]);
    m.run(100);
    assert_eq!((m.act_val(0), m.error_code(0)), (5000, 0));

    // Axis 2, positive switch DI5 active at standstill: a positive target is refused at once, a negative one
    // runs.
    let mut m = enabled(1, 100, 10, 10);
    set(&mut m, 1, AxisReg::LimitSwitchConfig, 0x8C);
    m.set_input(5, true);
    m.step();
    assert_eq!(m.error_code(1), 0);
    m.set_mode(1, modes::POSITION);
    m.set_abs_pos(1, 3000);
    m.run(5);
    assert_eq!((m.act_val(1), m.error_code(1)), (0, 0xFF21));
    m.set_abs_pos(1, -3000);
    m.set_control(1, ENABLE_OPERATION | CW_WARNING_RESET);
    m.run(60);
    assert_eq!((m.act_val(1), m.error_code(1)), (-3000, 0));
}

// ----- software limits: X67-18.11.1.17, X67-18.11.3.5-03 -----

/// X67-18.11.1.17-01: the limits are on as soon as one of Min/Max is non-zero, and then a 0 is a limit too;
/// with both 0 any target is accepted.
#[test]
fn x67_18_11_1_17_01_on_when_either_is_non_zero() {
    let mut m = enabled(0, 100, 10, 10);
    limits(&mut m, 0, 0, 10_000);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, -5);
    assert_eq!(
        incs_bits(&mut m, 0, 5, SW_INTERNAL_LIMIT),
        [(0, true); 5],
        "Min = 0 is a limit"
    );
    m.set_abs_pos(0, 10_000);
    assert_eq!(incs_bits(&mut m, 0, 1, SW_INTERNAL_LIMIT), [(10, false)]);
    m.run(150);
    assert_eq!(m.act_val(0), 10_000);
    assert!(bit(&m, 0, SW_TARGET_REACHED) && !bit(&m, 0, SW_INTERNAL_LIMIT));

    let mut m = enabled(0, 100, 10, 10);
    limits(&mut m, 0, -100, 0);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 5);
    assert_eq!(
        incs_bits(&mut m, 0, 5, SW_INTERNAL_LIMIT),
        [(0, true); 5],
        "Max = 0 is a limit"
    );
    m.set_abs_pos(0, -100);
    m.run(20);
    assert_eq!(m.act_val(0), -100);
    assert!(!bit(&m, 0, SW_INTERNAL_LIMIT));

    let mut m = enabled(0, 100, 10, 10);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, -5);
    assert_eq!(
        incs_bits(&mut m, 0, 2, SW_INTERNAL_LIMIT),
        [(-5, false), (0, false)]
    );
    m.set_abs_pos(0, 20_000);
    m.run(250);
    assert_eq!(m.act_val(0), 20_000);
    assert!(!bit(&m, 0, SW_INTERNAL_LIMIT));
}

/// X67-18.11.1.17-02: the counter stays inside [Min, Max] in speed mode and in homing: the axis brakes with
/// MaxDec01 so that it stops exactly at the limit, with bit 11 = 1 from the first cycle the limit holds it
/// back.
#[test]
fn x67_18_11_1_17_02_containment_in_speed_mode_and_homing() {
    // From 820 the speed 40 still fits (40 + its braking distance 140 = 180 = room); from 860 it does not.
    let approach = cat(&[
        &[10, 20, 30],
        &rep(40, 20),
        &[35, 30, 25, 20, 15, 10, 5, 0, 0],
    ]);
    let held: Vec<bool> = (0..approach.len()).map(|k| k >= 23).collect();

    let mut m = enabled(0, 0, 10, 5);
    limits(&mut m, 0, -1000, 1000);
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, 40);
    let run = incs_bits(&mut m, 0, approach.len(), SW_INTERNAL_LIMIT);
    assert_eq!(run.iter().map(|r| r.0).collect::<Vec<_>>(), approach);
    assert_eq!(run.iter().map(|r| r.1).collect::<Vec<_>>(), held);
    assert_eq!(m.act_val(0), 1000);
    m.set_abs_pos(0, -40);
    assert_eq!(incs_bits(&mut m, 0, 1, SW_INTERNAL_LIMIT), [(-10, false)]);
    for _ in 0..120 {
        m.step();
        assert!(m.act_val(0) >= -1000);
    }
    assert_eq!(m.act_val(0), -1000);
    assert!(bit(&m, 0, SW_INTERNAL_LIMIT));

    let mut m = homing_axis(0, 40, 10, 5);
    limits(&mut m, 0, -1000, 1000);
    m.set_mode(0, modes::HOMING_POSITIVE);
    let run = incs_bits(&mut m, 0, approach.len(), SW_INTERNAL_LIMIT);
    assert_eq!(run.iter().map(|r| r.0).collect::<Vec<_>>(), approach);
    assert_eq!(run.iter().map(|r| r.1).collect::<Vec<_>>(), held);
    assert_eq!(m.act_val(0), 1000);
    assert!(!bit(&m, 0, SW_TARGET_REACHED), "homing has not ended");
    m.set_mode(0, modes::HOMING_NEGATIVE);
    for _ in 0..120 {
        m.step();
        assert!((-1000..=1000).contains(&m.act_val(0)));
    }
    assert_eq!(m.act_val(0), -1000);
    assert_eq!(refs(&m, 0), (0, 0));
}

/// X67-18.11.1.17-03, X67-18.11.3.5-03: a target outside the limits sets bit 11 and is not pursued: from
/// standstill nothing moves, in a move the axis brakes with MaxDec01 and stops before the limit. A target
/// inside clears bit 11 and is approached.
#[test]
fn x67_18_11_1_17_03_target_outside_sets_bit_11() {
    let mut m = enabled(0, 100, 10, 10);
    limits(&mut m, 0, 0, 10_000);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 20_000);
    assert_eq!(incs_bits(&mut m, 0, 5, SW_INTERNAL_LIMIT), [(0, true); 5]);

    m.set_abs_pos(0, 8000);
    let run = incs_bits(&mut m, 0, 20, SW_INTERNAL_LIMIT);
    let expected: Vec<(i32, bool)> = (1..=10)
        .map(|k| (10 * k, false))
        .chain((0..10).map(|_| (100, false)))
        .collect();
    assert_eq!(run, expected);
    assert_eq!(m.act_val(0), 1550);

    m.set_abs_pos(0, 20_000);
    let run = incs_bits(&mut m, 0, 12, SW_INTERNAL_LIMIT);
    let expected: Vec<(i32, bool)> = [90, 80, 70, 60, 50, 40, 30, 20, 10, 0, 0, 0]
        .into_iter()
        .map(|v| (v, true))
        .collect();
    assert_eq!(run, expected);
    assert_eq!(m.act_val(0), 2000);

    m.set_abs_pos(0, 5000);
    assert_eq!(incs_bits(&mut m, 0, 1, SW_INTERNAL_LIMIT), [(10, false)]);
    m.run(60);
    assert_eq!(m.act_val(0), 5000);
    assert!(bit(&m, 0, SW_TARGET_REACHED) && !bit(&m, 0, SW_INTERNAL_LIMIT));

    // The same for a fixed position (mode −125).
    set(&mut m, 0, AxisReg::FixedPosA, 10_001);
    m.set_mode(0, modes::FIXED_A);
    assert_eq!(incs_bits(&mut m, 0, 3, SW_INTERNAL_LIMIT), [(0, true); 3]);
    set(&mut m, 0, AxisReg::FixedPosA, 10_000);
    m.run(80);
    assert_eq!(m.act_val(0), 10_000);
    assert!(!bit(&m, 0, SW_INTERNAL_LIMIT));
}

/// X67-18.11.1.17-04: Min > Max sets bit 11 and no positioning move runs; valid limits clear it.
#[test]
fn x67_18_11_1_17_04_min_above_max() {
    let mut m = enabled(0, 100, 10, 10);
    limits(&mut m, 0, 100, 50);
    m.step();
    assert!(
        bit(&m, 0, SW_INTERNAL_LIMIT),
        "whatever the target and mode"
    );
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 75);
    assert_eq!(incs_bits(&mut m, 0, 10, SW_INTERNAL_LIMIT), [(0, true); 10]);
    m.set_abs_pos(0, 0);
    assert_eq!(incs_bits(&mut m, 0, 2, SW_INTERNAL_LIMIT), [(0, true); 2]);
    m.set_abs_pos(0, 75);
    limits(&mut m, 0, 0, 100);
    assert_eq!(incs_bits(&mut m, 0, 1, SW_INTERNAL_LIMIT), [(10, false)]);
    m.run(20);
    assert_eq!(m.act_val(0), 75);
}

/// X67-18.11.1.17-02: at a limit the axis brakes as late as possible, at each cycle the largest speed from
/// which MaxDec0n still stops it on the limit. Mode 2 at 40 (MaxAcc01 10, MaxDec01 5) toward Max = 1010:
/// 10, 20, 30 and 40 up to 860, where 40 no longer fits (40 + 35 + 30 + … + 5 = 180 > 150 left) but 36 does
/// (36 + 31 + 26 + 21 + 16 + 11 + 6 + 1 = 148, 37 would need 156); then 31 (+ 81 = 112 of 114), 26 (+ 55 = 81
/// of 83), 21 (+ 34 = 55 of 57), 16 (+ 18 = 34 of 36), 11 (+ 7 = 18 of 20), 7 (+ 2 = 9 of 9) and 2 land on
/// 1010. Bit 11 is 1 from the first cycle the limit holds the set-point back.
#[test]
fn x67_18_11_1_17_02_braking_as_late_as_possible_at_a_limit() {
    let approach = cat(&[
        &[10, 20, 30],
        &rep(40, 20),
        &[36, 31, 26, 21, 16, 11, 7, 2, 0, 0],
    ]);
    let held: Vec<bool> = (0..approach.len()).map(|k| k >= 23).collect();
    let mut m = enabled(0, 0, 10, 5);
    limits(&mut m, 0, -1000, 1010);
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, 40);
    let run = incs_bits(&mut m, 0, approach.len(), SW_INTERNAL_LIMIT);
    assert_eq!(run.iter().map(|r| r.0).collect::<Vec<_>>(), approach);
    assert_eq!(run.iter().map(|r| r.1).collect::<Vec<_>>(), held);
    assert_eq!(m.act_val(0), 1010);
}

/// X67-18.11.1.17-02: limits written while the axis runs toward them too fast to stop in time still hold. The
/// axis brakes with MaxDec01 while that still stops it inside and, in the cycle it would cross the limit,
/// stops on it at once (the model's pick: the seed does not say how the module stops there). Mode 2 at 100
/// (MaxDec01 10) at 1050, then Max = 1250: 200 to go, where braking from 100 needs 450. The largest speed
/// that could still stop in 200 is 58, so the axis brakes as hard as it may: 90 (110 left), 80 (30 left),
/// then 30 instead of 70, and stands on 1250 with bit 11 = 1.
#[test]
fn x67_18_11_1_17_02_limits_written_too_late_still_hold() {
    let mut m = enabled(0, 0, 10, 10);
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, 100);
    assert_eq!(
        incs(&mut m, 0, 15),
        cat(&[&[10, 20, 30, 40, 50, 60, 70, 80, 90], &rep(100, 6)])
    );
    assert_eq!(m.act_val(0), 1050);
    limits(&mut m, 0, -10_000, 1250);
    assert_eq!(
        incs_bits(&mut m, 0, 5, SW_INTERNAL_LIMIT),
        [(90, true), (80, true), (30, true), (0, true), (0, true)]
    );
    assert_eq!(m.act_val(0), 1250);
}

/// X67-18.11.1.6-02 with X67-18.11.1.17-02: the reversing-loop point is kept inside the software limits (the
/// model's pick). RevLoop01 = 500 and Max = 10 200: a move 0 → 10 000 overshoots only to 10 200 (10, …, 100,
/// 92 cycles at 100, 90, …, 10), stands there two cycles (the cycle in which it stops and the one in which
/// the ramp sees it stopped, the model's pick for how long the loop stops) and comes back 200 (10, 20, 30,
/// 40, 40, 30, 20, 10); bit 11 stays 0 and bit 10 is 1 only on the arrival.
#[test]
fn x67_18_11_1_6_02_loop_point_inside_the_limits() {
    let mut m = enabled(0, 100, 10, 10);
    set(&mut m, 0, AxisReg::RevLoop, 500);
    limits(&mut m, 0, -1000, 10_200);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 10_000);
    let up: Vec<i32> = (1..=10).map(|k| 10 * k).collect();
    let down: Vec<i32> = (1..=9).rev().map(|k| 10 * k).collect();
    let expected = cat(&[
        &up,
        &rep(100, 92),
        &down,
        &[0, 0],
        &[-10, -20, -30, -40, -40, -30, -20, -10, 0],
    ]);
    let mut seen = Vec::new();
    for _ in 0..expected.len() {
        let (inc, sw) = cycle(&mut m, 0);
        assert_eq!(sw & SW_INTERNAL_LIMIT, 0, "cycle {}", seen.len());
        seen.push((inc, sw & SW_TARGET_REACHED != 0));
    }
    assert_eq!(seen.iter().map(|c| c.0).collect::<Vec<_>>(), expected);
    let mut reached = vec![false; expected.len() - 1];
    reached.push(true);
    assert_eq!(seen.iter().map(|c| c.1).collect::<Vec<_>>(), reached);
    assert_eq!(m.act_val(0), 10_000);
}

/// X67-18.11.1.17-01, X67-18.11.1.17-04: Min = Max (not 0) is a valid range of one position, not Min > Max:
/// the axis at 0 is sent to it (10, …, 100, 90, …, 10) and arrives with bit 11 = 0 in every cycle; a target
/// one microstep beside it is outside and sets bit 11 without motion.
#[test]
fn x67_18_11_1_17_04_min_equal_to_max_is_valid() {
    let mut m = enabled(0, 100, 10, 10);
    limits(&mut m, 0, 1000, 1000);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 1000);
    let expected: Vec<(i32, bool)> = (1..=10)
        .chain((1..=9).rev())
        .map(|k| (10 * k, false))
        .chain([(0, false)])
        .collect();
    assert_eq!(incs_bits(&mut m, 0, 20, SW_INTERNAL_LIMIT), expected);
    assert!(bit(&m, 0, SW_TARGET_REACHED));
    assert_eq!(m.act_val(0), 1000);
    for target in [1001, 999] {
        m.set_abs_pos(0, target);
        assert_eq!(
            incs_bits(&mut m, 0, 3, SW_INTERNAL_LIMIT),
            [(0, true); 3],
            "target {target}"
        );
    }
}

/// X67-18.11.1.17-04 in speed mode: Min > Max holds the axis at standstill with bit 11 = 1, and bit 10 shows
/// the standstill (the model's pick: while a limit holds the axis bit 10 is 1 at standstill), not the
/// set-point speed of 40 that is never reached.
#[test]
fn x67_18_11_1_17_04_min_above_max_in_speed_mode() {
    let mut m = enabled(0, 0, 10, 10);
    limits(&mut m, 0, 100, 50);
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, 40);
    for k in 0..5 {
        let (inc, sw) = cycle(&mut m, 0);
        assert_eq!(inc, 0, "cycle {k}");
        assert_eq!(
            sw & (SW_TARGET_REACHED | SW_INTERNAL_LIMIT),
            SW_TARGET_REACHED | SW_INTERNAL_LIMIT,
            "cycle {k}"
        );
    }
    assert_eq!(m.act_val(0), 0);
}

/// X67-18.11.1.17-06: without limits the 32-bit counter wraps from 2 147 483 647 to −2 147 483 648; with
/// limits [−2^31, 2^31 − 1] the axis stops exactly at 2 147 483 647.
#[test]
fn x67_18_11_1_17_06_overflow_only_without_limits() {
    for limited in [false, true] {
        let mut m = enabled(0, 0, 10, 10);
        if limited {
            limits(&mut m, 0, i64::from(i32::MIN), i64::from(i32::MAX));
        }
        m.set_mode(0, modes::SET_POSITION);
        m.set_abs_pos(0, i32::MAX - 1000);
        m.step();
        assert_eq!(m.act_val(0), i32::MAX - 1000);
        m.set_mode(0, modes::SPEED);
        m.set_abs_pos(0, 40);
        if limited {
            let run = incs_bits(&mut m, 0, 30, SW_INTERNAL_LIMIT);
            let got: Vec<i32> = run.iter().map(|r| r.0).collect();
            assert_eq!(
                got,
                cat(&[&[10, 20, 30], &rep(40, 22), &[30, 20, 10, 0, 0]])
            );
            let held: Vec<bool> = run.iter().map(|r| r.1).collect();
            assert_eq!(held, (0..30).map(|k| k >= 25).collect::<Vec<_>>());
            assert_eq!(m.act_val(0), i32::MAX);
        } else {
            let run = incs_bits(&mut m, 0, 28, SW_INTERNAL_LIMIT);
            assert_eq!(
                run,
                cat(&[&[10, 20, 30], &rep(40, 25)])
                    .into_iter()
                    .map(|v| (v, false))
                    .collect::<Vec<_>>()
            );
            assert_eq!(m.act_val(0), i32::MIN + 59);
        }
    }
}

/// X67-18.11.1.17-06 with X67-18.11.1.17-02/-03: the counter that wrapped is the one the limits hold. Past
/// 2 147 483 647 going positive (the run of the test above, then 60 more braking: −2 147 483 529), limits
/// [−2^31, −2^31 + 500] contain the axis, and a positive speed takes it to −2^31 + 500 and no further; the
/// mirror image going negative past −2^31 (to 2 147 483 528) with limits [2^31 − 1 − 500, 2^31 − 1] ends
/// at 2 147 483 147; and an axis that stops exactly on −2^31 stays there with limits [−2^31, −2^31 + 500]
/// until sent positive.
#[test]
fn x67_18_11_1_17_06_limits_hold_the_wrapped_counter() {
    // (start, speed of the run, where it stops, limits, speed then, where that ends)
    let (min, max) = (i64::from(i32::MIN), i64::from(i32::MAX));
    let cases = [
        (
            i32::MAX - 1000,
            40,
            i32::MIN + 119,
            (min, min + 500),
            40,
            min + 500,
        ),
        (
            i32::MIN + 1000,
            -40,
            i32::MAX - 119,
            (max - 500, max),
            -40,
            max - 500,
        ),
        (
            i32::MIN + 1120,
            -40,
            i32::MIN,
            (min, min + 500),
            40,
            min + 500,
        ),
    ];
    for (start, speed, stop, (low, high), then, end) in cases {
        let mut m = enabled(0, 0, 10, 10);
        m.set_mode(0, modes::SET_POSITION);
        m.set_abs_pos(0, start);
        m.step();
        m.set_mode(0, modes::SPEED);
        m.set_abs_pos(0, speed);
        m.run(28);
        m.set_abs_pos(0, 0);
        m.run(4);
        assert_eq!(m.act_val(0), stop, "from {start}");
        limits(&mut m, 0, low, high);
        // Inside the limits, or on the lower one: nothing moves.
        for _ in 0..5 {
            let (inc, _) = cycle(&mut m, 0);
            assert_eq!(inc, 0, "from {start}");
            assert_eq!(m.act_val(0), stop, "from {start}");
        }
        m.set_abs_pos(0, then);
        m.run(60);
        assert_eq!(i64::from(m.act_val(0)), end, "from {start}");
        assert!(bit(&m, 0, SW_INTERNAL_LIMIT), "from {start}");
    }
}

/// X67-18.11.1.17-06 (pick: the move distance is the wrapping difference), X67-18.11.1.17-02/-03: without
/// limits a target just past the wrap is reached forward through the overflow (1100 microsteps); with limits
/// [−2^31, 2^31 − 1] the same target lies inside them and is approached the long way, without overflow.
#[test]
fn x67_18_11_1_17_06_positioning_across_the_wrap() {
    for limited in [false, true] {
        let mut m = enabled(0, 100, 10, 10);
        if limited {
            limits(&mut m, 0, i64::from(i32::MIN), i64::from(i32::MAX));
        }
        m.set_mode(0, modes::SET_POSITION);
        m.set_abs_pos(0, i32::MAX - 1000);
        m.step();
        m.set_mode(0, modes::POSITION);
        m.set_abs_pos(0, i32::MIN + 99);
        let run = incs_bits(&mut m, 0, 30, SW_INTERNAL_LIMIT);
        assert!(run.iter().all(|r| !r.1), "limited = {limited}");
        if limited {
            let expected: Vec<(i32, bool)> = (1..=10)
                .map(|k| (-10 * k, false))
                .chain((0..20).map(|_| (-100, false)))
                .collect();
            assert_eq!(run, expected);
            assert_eq!(m.act_val(0), i32::MAX - 1000 - 550 - 2000);
        } else {
            assert_eq!(run.iter().map(|r| r.0).sum::<i32>(), 1100);
            assert_eq!(m.act_val(0), i32::MIN + 99);
            assert!(bit(&m, 0, SW_TARGET_REACHED));
        }
    }
}

/// X67-18.11.3.5-03: bit 11 is 0 without limits, 1 at a lower or upper limit and while the limits are
/// misconfigured, and 0 again once nothing holds the axis.
#[test]
fn x67_18_11_3_5_03_internal_limit_bit() {
    let mut m = enabled(0, 0, 20, 20);
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, -200);
    for _ in 0..30 {
        m.step();
        assert!(!bit(&m, 0, SW_INTERNAL_LIMIT));
    }
    m.set_abs_pos(0, 0);
    m.run(15);
    let here = i64::from(m.act_val(0));
    // 1100 speeding up, 20 cycles at 200, 900 braking.
    assert_eq!(here, -6000);
    limits(&mut m, 0, here - 500, here + 500);
    m.set_abs_pos(0, -40);
    m.run(40);
    assert_eq!(i64::from(m.act_val(0)), here - 500);
    assert!(bit(&m, 0, SW_INTERNAL_LIMIT), "lower limit");
    m.set_abs_pos(0, 40);
    m.step();
    assert!(!bit(&m, 0, SW_INTERNAL_LIMIT));
    m.run(60);
    assert_eq!(i64::from(m.act_val(0)), here + 500);
    assert!(bit(&m, 0, SW_INTERNAL_LIMIT), "upper limit");
    m.set_mode(0, modes::NONE);
    m.step();
    assert!(!bit(&m, 0, SW_INTERNAL_LIMIT), "mode 0: nothing held back");
    limits(&mut m, 0, here + 600, here);
    m.step();
    assert!(bit(&m, 0, SW_INTERNAL_LIMIT), "misconfigured");
    limits(&mut m, 0, 0, 0);
    m.step();
    assert!(!bit(&m, 0, SW_INTERNAL_LIMIT));
}

// ----- property: the software limits hold in every mode -----

/// A command of the master in the property test.
#[derive(Clone, Debug)]
enum Command {
    /// Mode 1 with this AbsPos01.
    Target(i32),
    /// Mode −125 (`b` = false) or −126 with this FixedPos01a/b.
    Fixed { b: bool, pos: i32 },
    /// Mode 2 with this speed set-point.
    Speed(i32),
    /// Mode −127 or −128 (`negative`) with this RefConfig01.
    Homing { negative: bool, ref_config: i8 },
    /// Toggles DI3 or DI4 (the inputs of the referencing conditions).
    Toggle(usize),
}

/// The configuration of the property test.
#[derive(Clone, Debug)]
struct Setup {
    min: i32,
    max: i32,
    max_speed: i64,
    acc: i64,
    dec: i64,
    jolt: i64,
    rev_loop: i64,
    ref_speed: i64,
}

fn setup_strategy() -> impl Strategy<Value = Setup> {
    (
        (-20_000i32..5_000, 0i32..25_000),
        (1i64..400, 1i64..60, 0i64..60),
        (0i64..12, -500i64..500, 0i64..300),
    )
        .prop_map(
            |((min, width), (max_speed, acc, dec), (jolt, rev_loop, ref_speed))| {
                // Both 0 would switch the limits off.
                let max = if min == 0 && width == 0 {
                    1
                } else {
                    min + width
                };
                Setup {
                    min,
                    max,
                    max_speed,
                    acc,
                    dec,
                    jolt,
                    rev_loop,
                    ref_speed,
                }
            },
        )
}

fn command_strategy() -> impl Strategy<Value = Command> {
    prop_oneof![
        (-30_000i32..30_000).prop_map(Command::Target),
        (any::<bool>(), -30_000i32..30_000).prop_map(|(b, pos)| Command::Fixed { b, pos }),
        (-300i32..300).prop_map(Command::Speed),
        (
            any::<bool>(),
            prop::sample::select(vec![-121i8, -122, -125, -126, -128])
        )
            .prop_map(|(negative, ref_config)| Command::Homing {
                negative,
                ref_config
            }),
        prop::sample::select(vec![3usize, 4]).prop_map(Command::Toggle),
    ]
}

fn apply(m: &mut Module, command: &Command, levels: &mut [bool; 6]) {
    match *command {
        Command::Target(t) => {
            m.set_mode(0, modes::POSITION);
            m.set_abs_pos(0, t);
        }
        Command::Fixed { b, pos } => {
            let (reg, mode) = if b {
                (AxisReg::FixedPosB, -126)
            } else {
                (AxisReg::FixedPosA, -125)
            };
            set(m, 0, reg, i64::from(pos));
            m.set_mode(0, mode);
        }
        Command::Speed(v) => {
            m.set_mode(0, modes::SPEED);
            m.set_abs_pos(0, v);
        }
        Command::Homing {
            negative,
            ref_config,
        } => {
            set(m, 0, AxisReg::RefConfig, i64::from(ref_config));
            m.set_mode(0, if negative { -128 } else { -127 });
        }
        Command::Toggle(input) => {
            levels[input - 1] = !levels[input - 1];
            m.set_input(input, levels[input - 1]);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// X67-18.11.1.17-02: with random limits (Min ≤ Max), ramp registers, targets, fixed positions, speed
    /// set-points and homing runs given at random cycles, AbsPos01ActVal never leaves [Min, Max] once it is
    /// inside (a counter that starts outside may only come in).
    #[test]
    fn software_limits_contain_the_counter(
        s in setup_strategy(),
        commands in prop::collection::vec((command_strategy(), 1usize..60), 1..12),
    ) {
        let mut m = enabled(0, s.max_speed, s.acc, s.dec);
        set(&mut m, 0, AxisReg::JoltTime, s.jolt);
        set(&mut m, 0, AxisReg::RevLoop, s.rev_loop);
        set(&mut m, 0, AxisReg::RefSpeed, s.ref_speed);
        limits(&mut m, 0, i64::from(s.min), i64::from(s.max));
        let mut levels = [false; 6];
        let mut inside = false;
        let mut n = 0;
        for (command, cycles) in &commands {
            apply(&mut m, command, &mut levels);
            for _ in 0..*cycles {
                m.step();
                n += 1;
                let p = m.act_val(0);
                let within = s.min <= p && p <= s.max;
                prop_assert!(
                    within || !inside,
                    "cycle {n}: {p} left [{}, {}] after {command:?}", s.min, s.max
                );
                inside |= within;
            }
        }
    }
}
