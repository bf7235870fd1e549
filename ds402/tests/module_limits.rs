//! Limit switches and software limits of the X67SM2436 module model ("Ramp", seed 002, 18.11.1.16,
//! 18.11.1.17), run through the module's registers cycle by cycle. Each test names the rules of
//! `rules/x67.md` it covers; the numbers are worked out by hand from the rules and the ramp discretisation
//! of X67-18.11.3.3.1-01 (speed first, then position).
//!
//! Timing of the inputs, from the module documentation: a cam switches its input at the exact rotor position
//! within a cycle; an input the harness sets between two cycles is seen in the next cycle at the counter
//! values of that cycle's start, and a braking ramp it causes starts in the cycle after.

mod module_homing_helpers;
mod x67_rig;

use ds402::cia402::control::ENABLE_OPERATION;
use ds402::cia402::SW_WARNING;
use ds402::x67::axis::{modes, SW_INTERNAL_LIMIT, SW_TARGET_REACHED};
use ds402::x67::current::Level;
use ds402::x67::errors::CW_WARNING_RESET;
use ds402::x67::module::Module;
use ds402::x67::registers::AxisReg;
use module_homing_helpers::*;
use proptest::prelude::*;
use x67_rig::{cat, increments as incs, set, OPERATION_ENABLE, STATE_MASK};

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

/// X67-18.11.1.17-06 with X67-18.11.1.17-02, X67-18.11.1.17-03: the counter that wrapped is the one
/// the limits hold. Past
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

/// X67-18.11.1.17-06 (pick: the move distance is the wrapping difference), X67-18.11.1.17-02,
/// X67-18.11.1.17-03: without
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
