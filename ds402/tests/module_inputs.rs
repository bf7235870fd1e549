//! The X67SM2436 "Ramp" module seen as a whole through [`Module`]: inputs, encoders and counters. Each test
//! names the rules of `rules/x67.md` it checks.

mod module_status_helpers;
mod x67_rig;

use ds402::cia402::control::ENABLE_OPERATION;
use ds402::x67::axis::{modes, CW_SWAP_COUNTERS};
use ds402::x67::module::{Cam, Diagnostic, Module};
use ds402::x67::registers::{AxisReg, Register};
use module_status_helpers::*;
use x67_rig::{increments, operation_enable, set};

// ===== 3 / 8.2 / 18.11.3.6 Inputs, encoders, counters =====

/// X67-3-05: 256 microsteps of the internal counter turn the rotor by one full step, 1 microstep by 1/256.
#[test]
fn x67_3_05_256_microsteps_per_full_step() {
    let mut m = Module::new();
    operation_enable(&mut m, 0, 100, 10, 10);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 256);
    m.run(20);
    assert_eq!(m.act_val(0), 256);
    assert_eq!(m.axis(0).motor.rotor(), 256);
    assert_eq!(m.axis(0).motor.full_steps(), 1.0);
    m.set_abs_pos(0, 257);
    m.run(5);
    assert_eq!(m.axis(0).motor.full_steps(), 1.0 + 1.0 / 256.0);
    m.set_abs_pos(0, 51_200);
    m.run(600);
    assert_eq!(m.axis(0).motor.full_steps(), 200.0);
}

/// X67-3-06: six inputs; InputStatus bit k−1 shows DIk, driven with logical levels.
#[test]
fn x67_3_06_six_digital_inputs() {
    let mut m = Module::new();
    m.step();
    assert_eq!(m.input_status(), 0);
    for k in 1..=6 {
        m.set_input(k, true);
        m.step();
        assert_eq!(m.input_status(), 1 << (k - 1), "DI{k}");
        assert_eq!(named(&m, "InputStatus"), 1 << (k - 1));
        m.set_input(k, false);
        m.step();
        assert_eq!(m.input_status(), 0);
    }
}

/// X67-3-06: there are six inputs, DI1…DI6; the harness's calls for an input number outside 1…6 change
/// nothing (no input, no edge, no panic).
#[test]
fn x67_3_06_no_seventh_input() {
    let mut m = Module::new();
    m.step();
    for input in [0, 7, 8] {
        m.set_input(input, true);
        m.pulse_input(input);
        m.attach_cam(
            input,
            Cam {
                axis: 0,
                from: -10,
                to: 10,
            },
        );
        m.step();
        assert_eq!(m.input_status(), 0, "input {input}");
    }
}

/// X67-3-07 with the module's input harness: a cam attached to an input sets its level at once, and the
/// module sees that change as an edge at the next cycle. Mode −123 standing at 0 with AbsPos01 = 1000: a cam
/// over rotor positions −10…10 attached to DI3 shows in InputStatus before any cycle, and its rising edge
/// takes the target (that cycle), the move starts in the cycle after; a cam that does not cover the rotor
/// leaves the input low.
#[test]
fn x67_3_07_attached_cam_sets_the_level_at_once() {
    let mut m = Module::new();
    operation_enable(&mut m, 0, 100, 10, 10);
    m.set_mode(0, modes::MOVE_ON_INPUT);
    m.set_abs_pos(0, 1000);
    assert_eq!(increments(&mut m, 0, 3), [0, 0, 0]);
    m.attach_cam(
        4,
        Cam {
            axis: 0,
            from: 100,
            to: 200,
        },
    );
    assert_eq!(m.input_status(), 0);
    m.attach_cam(
        3,
        Cam {
            axis: 0,
            from: -10,
            to: 10,
        },
    );
    assert_eq!(m.input_status(), 0b0100);
    assert_eq!(increments(&mut m, 0, 4), [0, 10, 20, 30]);
}

/// X67-3-08: ABR counter 1 (DI1–DI3) belongs to axis 1 and counter 2 (DI4–DI6) to axis 2: hand quadrature
/// on DI1/DI2 changes only AbsPos01ActValAcyclic, on DI4/DI5 only AbsPos02ActValAcyclic; an encoder on
/// axis 1's shaft drives DI1/DI2 and counter 1 only.
#[test]
fn x67_3_08_one_abr_counter_per_axis() {
    let mut m = Module::new();
    m.step();
    quadrature(&mut m, 0, 10);
    m.step();
    assert_eq!(
        (
            named(&m, "AbsPos01ActValAcyclic"),
            named(&m, "AbsPos02ActValAcyclic")
        ),
        (10, 0)
    );
    quadrature(&mut m, 1, -7);
    m.step();
    assert_eq!(
        (
            named(&m, "AbsPos01ActValAcyclic"),
            named(&m, "AbsPos02ActValAcyclic")
        ),
        (10, -7)
    );

    let mut m = Module::new();
    m.axis_mut(0).motor.encoder_lines = 500;
    operation_enable(&mut m, 0, 100, 10, 10);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 51_200);
    m.run(600);
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 2000);
    assert_eq!(named(&m, "AbsPos02ActValAcyclic"), 0);
}

/// X67-3-09: 4x evaluation: one A/B period is ±4 counts, A leading B counts up; the 16-bit counter wraps
/// after 65 536 counts and is sign-extended into the DINT registers.
#[test]
fn x67_3_09_sixteen_bit_counter_4x() {
    let mut m = Module::new();
    m.step();
    quadrature(&mut m, 0, 4);
    m.step();
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 4);
    assert_eq!(m.input_status() & 0x03, 0);
    quadrature(&mut m, 0, -8);
    m.step();
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), -4);
    // A leading B: A rises first.
    let mut m = Module::new();
    m.step();
    m.set_input(1, true);
    m.step();
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 1);
    m.set_input(2, true);
    m.step();
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 2);
    // B leading A from 0: down.
    let mut m = Module::new();
    m.step();
    m.set_input(2, true);
    m.step();
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), -1);

    // Sign extension and wrap.
    let mut m = Module::new();
    m.step();
    quadrature(&mut m, 0, 32_767);
    m.step();
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 32_767);
    quadrature(&mut m, 0, 1);
    m.step();
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), -32_768);
    quadrature(&mut m, 0, 32_768);
    m.step();
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 0);

    // An encoder with 16 384 lines gives 65 536 counts per revolution: one revolution shows the start value.
    let mut m = Module::new();
    m.axis_mut(0).motor.encoder_lines = 16_384;
    operation_enable(&mut m, 0, 1000, 100, 100);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 25_600);
    m.run(200);
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), -32_768);
    m.set_abs_pos(0, 51_200);
    m.run(200);
    assert_eq!(m.act_val(0), 51_200);
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 0);
}

/// X67-3-10: an encoder faster than 200 000 counts/s (50 kHz per signal) is a test-setup error the harness
/// reports; exactly 200 000 counts/s is not.
#[test]
fn x67_3_10_encoder_frequency_limit() {
    // 5000 lines: 20 000 counts per 51 200 microsteps; 12 800 microsteps per 25 ms = 5000 counts per cycle.
    let mut m = Module::new();
    m.axis_mut(0).motor.encoder_lines = 5000;
    operation_enable(&mut m, 0, 0, 12_800, 12_800);
    m.take_diagnostics();
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, 12_800);
    m.run(10);
    assert!(m.take_diagnostics().is_empty());
    m.set_abs_pos(0, 12_832);
    m.run(2);
    let d = m.take_diagnostics();
    assert_eq!(d.len(), 2, "{d:?}");
    for diag in d {
        match diag {
            Diagnostic::EncoderTooFast { axis, rate, .. } => {
                assert_eq!(axis, 0);
                assert!((200_480..=200_520).contains(&rate), "{rate}");
            }
            other => panic!("{other:?}"),
        }
    }
}

/// X67-8.2-01: InputStatus bits 0–5 are DI1–DI6; the R input of axis 1 is DI3 and that of axis 2 DI6
/// (mode −123 starts its move on the rising edge of the axis's own R input).
#[test]
fn x67_8_2_01_input_mapping() {
    let mut m = Module::new();
    for axis in 0..2 {
        operation_enable(&mut m, axis, 100, 10, 10);
        m.set_mode(axis, modes::MOVE_ON_INPUT);
        m.set_abs_pos(axis, 1000);
    }
    m.run(3);
    assert_eq!((m.act_val(0), m.act_val(1)), (0, 0));
    m.set_input(3, true);
    m.run(30);
    assert_eq!(m.input_status(), 0b00_0100);
    assert_eq!((m.act_val(0), m.act_val(1)), (1000, 0));
    m.set_input(6, true);
    m.run(30);
    assert_eq!(m.input_status(), 0b10_0100);
    assert_eq!((m.act_val(0), m.act_val(1)), (1000, 1000));
}

/// X67-18.11.3.6-01: InputStatus bits 0–5 hold DI1–DI6 and bits 6–7 are 0: DI3 and DI6 high gives 0x24 in
/// byte 6 of input object 1; the levels show also while the inputs serve an encoder or a limit switch.
#[test]
fn x67_18_11_3_6_01_input_status() {
    let mut m = Module::new();
    m.set_input(3, true);
    m.set_input(6, true);
    m.step();
    assert_eq!(named(&m, "InputStatus"), 0x24);
    assert_eq!(m.input_object(0)[6], 0x24);
    for k in 1..=6 {
        m.set_input(k, true);
    }
    m.step();
    assert_eq!(m.input_object(0)[6], 0x3F);

    // Encoder on axis 1 (500 lines = 2000 counts/rev): at 52 microsteps the count is 2, A and B high.
    let mut m = Module::new();
    m.axis_mut(0).motor.encoder_lines = 500;
    set(&mut m, 1, AxisReg::LimitSwitchConfig, 0x03);
    operation_enable(&mut m, 0, 10, 10, 10);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 52);
    m.run(20);
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 2);
    assert_eq!(m.input_status() & 0x03, 0x03);
    m.set_abs_pos(0, 77);
    m.run(20);
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 3);
    assert_eq!(m.input_status() & 0x03, 0x02);
    // The other two phases: count 4 (103 microsteps) has A and B low, count 1 (26 microsteps) A high only.
    m.set_abs_pos(0, 103);
    m.run(20);
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 4);
    assert_eq!(m.input_status() & 0x03, 0x00);
    m.set_abs_pos(0, 26);
    m.run(20);
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 1);
    assert_eq!(m.input_status() & 0x03, 0x01);
    // DI4 is axis 2's negative limit switch (active high).
    m.set_input(4, true);
    m.step();
    assert_eq!(m.input_status() & 0x08, 0x08);
}

/// X67-18.6.3.3-01: the internal counter is the ramp's set-point: with the rotor blocked AbsPos01ActVal
/// still follows the ramp while the ABR counter of the encoder on the shaft stays put.
#[test]
fn x67_18_6_3_3_01_blocked_rotor() {
    let mut m = Module::new();
    m.axis_mut(0).motor.encoder_lines = 500;
    m.axis_mut(0).motor.faults.blocked = true;
    operation_enable(&mut m, 0, 100, 10, 10);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 10_000);
    assert_eq!(increments(&mut m, 0, 5), [10, 20, 30, 40, 50]);
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 0);
    m.run(200);
    assert_eq!(m.act_val(0), 10_000);
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 0);
    assert_eq!(m.axis(0).motor.rotor(), 0);
}

/// X67-18.6.3.3-02: L encoder lines on a 200-step motor give 4·L ABR counts per 51 200 microsteps.
#[test]
fn x67_18_6_3_3_02_abr_counts_per_revolution() {
    for lines in [100, 500, 1000, 2500] {
        let mut m = Module::new();
        m.axis_mut(0).motor.encoder_lines = lines;
        operation_enable(&mut m, 0, 500, 50, 50);
        m.set_mode(0, modes::POSITION);
        m.set_abs_pos(0, 51_200);
        m.run(200);
        assert_eq!(m.act_val(0), 51_200);
        assert_eq!(
            named(&m, "AbsPos01ActValAcyclic"),
            4 * i64::from(lines),
            "{lines} lines"
        );
    }
}

/// X67-18.6.3.3-03: positions are DINT: a move to 100 000 shows AbsPos01ActVal = 100 000, with no 16-bit
/// wrap; there are no 16-bit Position registers.
#[test]
fn x67_18_6_3_3_03_dint_positions() {
    for name in ["Position1Sync", "Position1Async", "Position2Sync"] {
        assert_eq!(Register::from_name(name), None);
    }
    let mut m = Module::new();
    operation_enable(&mut m, 0, 2000, 100, 100);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 100_000);
    let mut max = 0;
    for _ in 0..200 {
        m.step();
        assert!(m.act_val(0) >= max, "no wrap");
        max = m.act_val(0);
    }
    assert_eq!(named(&m, "AbsPos01ActVal"), 100_000);
    assert_eq!(m.input_object(0)[0..4], 100_000i32.to_le_bytes());
}

/// X67-18.6.1.5-01: no counter configuration (ConfigOutput09, SetCounter0n); CW bit 14 of each axis swaps
/// its own AbsPos0nActVal and AbsPos0nActValAcyclic.
#[test]
fn x67_18_6_1_5_01_counter_choice_per_axis() {
    for name in ["ConfigOutput09", "SetCounter01", "SetCounter02"] {
        assert_eq!(Register::from_name(name), None);
    }
    let mut m = Module::new();
    m.step();
    quadrature(&mut m, 0, 5);
    quadrature(&mut m, 1, 9);
    m.set_control(1, CW_SWAP_COUNTERS);
    m.step();
    assert_eq!(
        (
            named(&m, "AbsPos01ActVal"),
            named(&m, "AbsPos01ActValAcyclic")
        ),
        (0, 5)
    );
    assert_eq!(
        (
            named(&m, "AbsPos02ActVal"),
            named(&m, "AbsPos02ActValAcyclic")
        ),
        (9, 0)
    );
}

/// X67-18.11.3.4-01: AbsPos01ActVal (input object 1, bytes 0–3) follows the internal counter by default and
/// the ABR counter (sign-extended) with CW bit 14.
#[test]
fn x67_18_11_3_4_01_cyclic_position() {
    let mut m = Module::new();
    operation_enable(&mut m, 0, 100, 10, 10);
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, -30);
    quadrature(&mut m, 0, -2);
    for _ in 0..5 {
        m.step();
        assert_eq!(
            m.input_object(0)[0..4],
            m.axis(0).internal_counter().to_le_bytes()
        );
    }
    assert_eq!(m.act_val(0), -10 - 20 - 30 - 30 - 30);
    m.set_control(0, ENABLE_OPERATION | CW_SWAP_COUNTERS);
    m.step();
    assert_eq!(m.act_val(0), -2);
    assert_eq!(m.input_object(0)[0..4], [0xFE, 0xFF, 0xFF, 0xFF]);
}

/// X67-18.11.3.10-01: AbsPos01ActValAcyclic is the ABR count with bit 14 = 0 and AbsPos01ActVal's former
/// value (the internal counter) with bit 14 = 1.
#[test]
fn x67_18_11_3_10_01_acyclic_position() {
    let mut m = Module::new();
    operation_enable(&mut m, 0, 100, 10, 10);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 3000);
    m.run(60);
    quadrature(&mut m, 0, 33);
    m.step();
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 33);
    let cyclic = named(&m, "AbsPos01ActVal");
    assert_eq!(cyclic, 3000);
    m.set_control(0, ENABLE_OPERATION | CW_SWAP_COUNTERS);
    m.step();
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), cyclic);
}
