//! The X67SM2436 "Ramp" module seen as a whole through [`Module`]: overtemperature and the supply range,
//! the error code, error status and acknowledgment, control word bits 11–15, stall detection and mixed
//! decay. Each test names the rules of `rules/x67.md` it checks.

mod module_status_helpers;
mod x67_rig;

use ds402::cia402::control::{ENABLE_OPERATION, FAULT_RESET};
use ds402::cia402::SW_WARNING;
use ds402::x67::axis::{modes, CW_MOTOR_ID, CW_SWAP_COUNTERS};
use ds402::x67::errors::{CW_CURRENT_ERROR_DETECTION, CW_STALL_DETECTION, CW_WARNING_RESET};
use ds402::x67::module::Module;
use ds402::x67::motor::Load;
use ds402::x67::registers::{AxisReg, Register};
use module_status_helpers::*;
use x67_rig::{
    assert_state, increments, operation_enable, set, set_currents, switch_on, FAULT,
    OPERATION_ENABLE, SWITCHED_ON, SWITCH_ON_DISABLED,
};

// ===== 15 Overtemperature, 3 supply range =====

/// X67-15-01: 84 °C raises nothing; at 85 °C Temperature = 85, ErrorCode01 = ErrorCode02 = 0x4200, both
/// axes in Fault and no phase current.
#[test]
fn x67_15_01_overtemperature_cutoff_at_85() {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 50, 80);
    set_currents(&mut m, 1, 20, 50, 80);
    operation_enable(&mut m, 0, 100, 10, 10);
    switch_on(&mut m, 1);
    m.set_temperature(84.0);
    m.step();
    assert_eq!(named(&m, "Temperature"), 84);
    assert_eq!((named(&m, "ErrorCode01"), named(&m, "ErrorCode02")), (0, 0));
    assert_state(&m, 0, OPERATION_ENABLE);
    assert_state(&m, 1, SWITCHED_ON);
    assert_eq!((milliamps(&m, 0), milliamps(&m, 1)), (600, 600));

    m.set_temperature(85.0);
    m.step();
    assert_eq!(named(&m, "Temperature"), 85);
    for axis in 0..2 {
        assert_eq!(m.error_code(axis), 0x4200);
        assert_state(&m, axis, FAULT);
        assert_eq!(milliamps(&m, axis), 0);
    }
}

/// X67-15-02: the condition clears only at 83 °C: after 86 °C a Fault reset at 84 °C is refused; at 83 °C
/// it gives Switch on disabled and ErrorCode 0 (the code stays until the reset, pick).
#[test]
fn x67_15_02_hysteresis_down_to_83() {
    let mut m = Module::new();
    m.step();
    m.set_temperature(86.0);
    m.step();
    m.set_temperature(84.0);
    m.run(3);
    m.set_control(0, FAULT_RESET);
    m.set_control(1, FAULT_RESET);
    m.step();
    for axis in 0..2 {
        assert_state(&m, axis, FAULT);
        assert_eq!(m.error_code(axis), 0x4200);
    }
    m.set_control(0, 0);
    m.set_control(1, 0);
    m.set_temperature(83.0);
    m.step();
    for axis in 0..2 {
        assert_state(&m, axis, FAULT);
        assert_eq!(m.error_code(axis), 0x4200);
    }
    m.set_control(0, FAULT_RESET);
    m.set_control(1, FAULT_RESET);
    m.step();
    for axis in 0..2 {
        assert_state(&m, axis, SWITCH_ON_DISABLED);
        assert_eq!(m.error_code(axis), 0);
    }
}

/// X67-3-11: the supply band is 18.0 V … 48.125 V: 48.2 V or 17.9 V give 0x3000 on both axes; 24 V and
/// the band ends do not.
#[test]
fn x67_3_11_supply_range() {
    for volts in [48.2, 17.9, 60.0, 0.0] {
        let mut m = Module::new();
        m.step();
        m.set_supply(volts);
        m.step();
        for axis in 0..2 {
            assert_eq!(m.error_code(axis), 0x3000, "{volts} V");
            assert_state(&m, axis, FAULT);
        }
    }
    for volts in [24.0, 18.0, 48.125, 38.5] {
        let mut m = Module::new();
        m.step();
        m.set_supply(volts);
        m.run(3);
        for axis in 0..2 {
            assert_eq!(m.error_code(axis), 0, "{volts} V");
            assert_state(&m, axis, SWITCH_ON_DISABLED);
        }
    }
    // A reading that is not a number is no voltage: the supply stays at 24 V.
    for volts in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut m = Module::new();
        m.step();
        m.set_supply(volts);
        m.run(3);
        assert_eq!(m.dc_bus_volts(), 24.0, "{volts}");
        assert_eq!(m.error_code(0), 0, "{volts}");
    }
}

// ===== 18.11.3.13 Error code =====

/// X67-18.11.3.13-01: after power-up, with supply and temperature in range, both error codes are 0.
#[test]
fn x67_18_11_3_13_01_no_error_after_power_up() {
    let mut m = Module::new();
    assert_eq!((named(&m, "ErrorCode01"), named(&m, "ErrorCode02")), (0, 0));
    m.run(5);
    assert_eq!((named(&m, "ErrorCode01"), named(&m, "ErrorCode02")), (0, 0));
    for axis in 0..2 {
        assert_eq!(m.status_word(axis) & (SW_WARNING | 0x0008), 0);
    }
}

/// X67-18.11.3.13-02: 0x3000 Voltage is an Error with the highest priority: both axes go to Fault, and it
/// is shown over a simultaneous overtemperature.
#[test]
fn x67_18_11_3_13_02_voltage_error_highest() {
    let mut m = Module::new();
    m.step();
    m.set_supply(17.9);
    m.set_temperature(90.0);
    m.step();
    for axis in 0..2 {
        assert_eq!(m.error_code(axis), 0x3000);
        assert_state(&m, axis, FAULT);
    }
    // With the supply back, the latched 0x3000 stays until the Fault reset.
    m.set_supply(24.0);
    m.run(2);
    assert_eq!(m.error_code(0), 0x3000);
}

/// X67-18.11.3.13-03: 0x4200 Overtemperature is an Error (Fault) ranking below 0x3000 and above every
/// warning (here a latched 0xFF20).
#[test]
fn x67_18_11_3_13_03_overtemperature_error_second() {
    let mut m = running(-50, 10);
    set(&mut m, 0, AxisReg::LimitSwitchConfig, 0x03);
    m.set_input(1, true);
    m.step();
    assert_eq!(m.error_code(0), 0xFF20);
    m.set_temperature(85.0);
    m.step();
    assert_eq!(m.error_code(0), 0x4200);
    assert_state(&m, 0, FAULT);
    m.set_supply(10.0);
    m.step();
    assert_eq!(m.error_code(0), 0x3000);
}

/// X67-18.11.3.13-04: 0xFF20 Negative limit switch is a warning: SW bit 7, no state change; it ranks over
/// 0xFF21.
#[test]
fn x67_18_11_3_13_04_negative_limit_switch_warning() {
    let mut m = running(-50, 10);
    set(&mut m, 0, AxisReg::LimitSwitchConfig, 0x0F);
    m.set_input(1, true);
    m.step();
    assert_eq!(m.error_code(0), 0xFF20);
    assert_eq!(m.status_word(0) & 0x03FF, OPERATION_ENABLE | SW_WARNING);
    // The positive switch (active high on DI2) is hit as well: 0xFF20 still shows.
    m.set_input(2, true);
    m.step();
    assert!(m
        .axis(0)
        .errors()
        .is_latched(ds402::x67::errors::ErrorCode::PositiveLimitSwitch));
    assert_eq!(m.error_code(0), 0xFF20);
    assert_state(&m, 0, OPERATION_ENABLE);
}

/// X67-18.11.3.13-05: 0xFF21 Positive limit switch is a warning ranking over 0x2300.
#[test]
fn x67_18_11_3_13_05_positive_limit_switch_warning() {
    let mut m = running(50, 10);
    m.axis_mut(0).motor.faults.short = true;
    m.step();
    assert_eq!(m.error_code(0), 0x2300);
    set(&mut m, 0, AxisReg::LimitSwitchConfig, 0x0C);
    m.set_input(2, true);
    m.step();
    assert_eq!(m.error_code(0), 0xFF21);
    assert_eq!(m.status_word(0) & 0x03FF, OPERATION_ENABLE | SW_WARNING);
}

/// X67-18.11.3.13-06: 0x2300 Overcurrent is a warning (no state change, the motion goes on) ranking over
/// 0xFF00.
#[test]
fn x67_18_11_3_13_06_overcurrent_warning() {
    let mut m = running(50, 10);
    m.set_control(0, ENABLE_OPERATION | CW_CURRENT_ERROR_DETECTION);
    m.axis_mut(0).motor.faults.open_winding = true;
    m.step();
    assert_eq!(m.error_code(0), 0xFF00);
    m.axis_mut(0).motor.faults.short = true;
    assert_eq!(increments(&mut m, 0, 3), [50, 50, 50]);
    assert_eq!(m.error_code(0), 0x2300);
    assert_eq!(m.status_word(0) & 0x03FF, OPERATION_ENABLE | SW_WARNING);
}

/// X67-18.11.3.13-07: 0xFF00 Current error is a warning detected only with CW bit 13, ranking over 0xFF01.
#[test]
fn x67_18_11_3_13_07_current_error_warning() {
    let mut m = running(50, 10);
    make_stall(&mut m, 0);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.step();
    assert_eq!(m.error_code(0), 0xFF01);
    m.axis_mut(0).motor.faults.open_winding = true;
    m.step();
    assert_eq!(m.error_code(0), 0xFF01);
    m.set_control(
        0,
        ENABLE_OPERATION | CW_STALL_DETECTION | CW_CURRENT_ERROR_DETECTION,
    );
    assert_eq!(step_increment(&mut m, 0), 50);
    assert_eq!(m.error_code(0), 0xFF00);
    assert_state(&m, 0, OPERATION_ENABLE);
}

/// X67-18.11.3.13-08: 0xFF01 Stall is a warning detected only with CW bit 15, ranking over 0xFF11; the
/// ramp goes on.
#[test]
fn x67_18_11_3_13_08_stall_warning() {
    let mut m = running(50, 10);
    make_stall(&mut m, 0);
    m.axis_mut(0).motor.faults.open_winding = true;
    m.step();
    assert_eq!(m.error_code(0), 0xFF11);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    assert_eq!(increments(&mut m, 0, 2), [50, 50]);
    assert_eq!(m.error_code(0), 0xFF01);
    assert_state(&m, 0, OPERATION_ENABLE);
}

/// X67-18.11.3.13-09: 0xFF11 Open circuit is the lowest warning, raised on a powered axis whatever bit 13
/// holds; with bit 13 = 1 the higher 0xFF00 is shown.
#[test]
fn x67_18_11_3_13_09_open_circuit_lowest() {
    let mut m = running(50, 10);
    m.axis_mut(0).motor.faults.open_winding = true;
    m.step();
    assert_eq!(m.error_code(0), 0xFF11);
    assert_ne!(m.status_word(0) & SW_WARNING, 0);
    m.set_control(0, ENABLE_OPERATION | CW_CURRENT_ERROR_DETECTION);
    m.step();
    assert_eq!(m.error_code(0), 0xFF00);
    assert!(m
        .axis(0)
        .errors()
        .is_latched(ds402::x67::errors::ErrorCode::OpenCircuit));

    // Not powered: no open circuit.
    let mut m = Module::new();
    m.step();
    m.axis_mut(0).motor.faults.open_winding = true;
    m.run(3);
    assert_eq!(m.error_code(0), 0);
}

/// X67-18.11.3.13-10: with stall and overcurrent pending 0x2300 is shown; after the overcurrent is reset
/// with the stall still present, 0xFF01.
#[test]
fn x67_18_11_3_13_10_priority() {
    let mut m = running(50, 10);
    make_stall(&mut m, 0);
    m.axis_mut(0).motor.faults.short = true;
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.run(2);
    assert_eq!(m.error_code(0), 0x2300);
    m.axis_mut(0).motor.faults.short = false;
    m.step();
    assert_eq!(m.error_code(0), 0x2300);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION | CW_WARNING_RESET);
    m.step();
    assert_eq!(m.error_code(0), 0xFF01);
}

/// X67-18.11.3.13-11: overtemperature with a pending stall warning: SW bits 3 and 7 both 1, ErrorCode01 =
/// 0x4200.
#[test]
fn x67_18_11_3_13_11_fault_and_warning_bits_together() {
    let mut m = running(50, 10);
    make_stall(&mut m, 0);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.run(2);
    m.set_temperature(85.0);
    m.step();
    assert_eq!(m.error_code(0), 0x4200);
    assert_eq!(m.status_word(0) & 0x0088, 0x0088);
    assert_state(&m, 0, FAULT);
}

/// X67-18.11.3.13-12: each axis has its own list: a stall on axis 2 changes only ErrorCode02; an
/// undervoltage sets both.
#[test]
fn x67_18_11_3_13_12_per_axis_lists() {
    let mut m = Module::new();
    for axis in 0..2 {
        operation_enable(&mut m, axis, 0, 10, 10);
        m.set_mode(axis, modes::SPEED);
        m.set_abs_pos(axis, 30);
        m.set_control(axis, ENABLE_OPERATION | CW_STALL_DETECTION);
    }
    // Axis 1 has a stall threshold too, but its load value (7) stays above it.
    set(&mut m, 0, AxisReg::StallDetectConfig, 0x30);
    m.axis_mut(0).motor.load = Load::Value(7);
    make_stall(&mut m, 1);
    m.run(5);
    assert_eq!((m.error_code(0), m.error_code(1)), (0, 0xFF01));
    assert_eq!(m.status_word(0) & SW_WARNING, 0);
    m.set_supply(17.0);
    m.step();
    assert_eq!((m.error_code(0), m.error_code(1)), (0x3000, 0x3000));
}

// ===== 18.6.3.1 Error status, 18.6.3.2 Error acknowledgment =====

/// X67-18.6.3.1-01: no Error status register; a stall on axis 1 sets ErrorCode01 = 0xFF01 and MpGenStatus01
/// bit 7, and no other register differs from the same run without the stall.
#[test]
fn x67_18_6_3_1_01_errors_in_error_code_and_status_word() {
    assert_eq!(Register::from_name("ErrorStatus"), None);
    assert_eq!(Register::from_name("Error status"), None);
    let mut base = running(50, 10);
    make_stall(&mut base, 0);
    base.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    let mut stalled = base.clone();
    base.axis_mut(0).motor.load = Load::Value(7);
    base.run(5);
    stalled.run(5);
    for reg in Register::all() {
        let (a, b) = (base.read(reg), stalled.read(reg));
        match reg.name() {
            "ErrorCode01" => assert_eq!((a, b), (0, 0xFF01)),
            "MpGenStatus01" => assert_eq!(a ^ b, i64::from(SW_WARNING)),
            name => assert_eq!(a, b, "{name}"),
        }
    }
}

/// X67-18.6.3.1-02: an output-stage overtemperature on axis 2 gives ErrorCode02 = 0x4200 and leaves axis 1
/// alone; the module temperature at 85 °C hits both.
#[test]
fn x67_18_6_3_1_02_overtemperature_per_output_stage_and_module() {
    let mut m = Module::new();
    operation_enable(&mut m, 0, 100, 10, 10);
    switch_on(&mut m, 1);
    m.axis_mut(1).motor.faults.output_stage_overtemperature = true;
    m.step();
    assert_eq!((m.error_code(0), m.error_code(1)), (0, 0x4200));
    assert_state(&m, 0, OPERATION_ENABLE);
    assert_state(&m, 1, FAULT);
    m.set_temperature(85.0);
    m.step();
    assert_eq!((m.error_code(0), m.error_code(1)), (0x4200, 0x4200));
    assert_state(&m, 0, FAULT);
}

/// X67-18.6.3.1-03: a current error (0xFF00, bit 13 on) from an open winding, or from back-EMF above the
/// limit (400 000 microsteps/s under load, 5 % lower without load, in the simulated motor).
#[test]
fn x67_18_6_3_1_03_current_error_open_winding_and_back_emf() {
    let mut m = running(50, 10);
    m.set_control(0, ENABLE_OPERATION | CW_CURRENT_ERROR_DETECTION);
    m.axis_mut(0).motor.faults.open_winding = true;
    m.step();
    assert_eq!(m.error_code(0), 0xFF00);
    assert_ne!(m.status_word(0) & SW_WARNING, 0);

    // 9600 microsteps/cycle = 384 000 microsteps/s: too fast without load, fine under load.
    for (load, speed, code) in [
        (Load::Torque(0), 9600, 0xFF00),
        (Load::Torque(20), 9600, 0),
        (Load::Torque(20), 10_000, 0),
        (Load::Torque(20), 10_025, 0xFF00),
        (Load::Torque(0), 9_500, 0),
    ] {
        let mut m = running(speed, 10_025);
        m.axis_mut(0).motor.load = load;
        m.set_control(0, ENABLE_OPERATION | CW_CURRENT_ERROR_DETECTION);
        m.run(2);
        assert_eq!(m.error_code(0), code, "{load:?} at {speed}");
    }
}

/// X67-18.6.3.1-04: an injected winding short on axis 1 gives ErrorCode01 = 0x2300 and SW bit 7.
#[test]
fn x67_18_6_3_1_04_overcurrent_on_short() {
    let mut m = Module::new();
    switch_on(&mut m, 0);
    m.axis_mut(0).motor.faults.short = true;
    m.step();
    assert_eq!(m.error_code(0), 0x2300);
    assert_ne!(m.status_word(0) & SW_WARNING, 0);
    assert_eq!(m.error_code(1), 0);
}

/// X67-18.6.3.1-05: a warning stays latched after its cause has gone until it is acknowledged by ↑ bit 12
/// or ↑ bit 7.
#[test]
fn x67_18_6_3_1_05_latched_until_acknowledged() {
    let mut m = running(50, 10);
    make_stall(&mut m, 0);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.run(2);
    assert_eq!(m.error_code(0), 0xFF01);
    m.axis_mut(0).motor.load = Load::Value(7);
    m.run(10);
    assert_eq!(m.error_code(0), 0xFF01);
    assert_ne!(m.status_word(0) & SW_WARNING, 0);
    for ack in [CW_WARNING_RESET, FAULT_RESET] {
        let mut m = m.clone();
        m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION | ack);
        m.step();
        assert_eq!(m.error_code(0), 0, "{ack:#06x}");
        assert_eq!(m.status_word(0) & SW_WARNING, 0);
    }
}

/// X67-18.6.3.2-01: no Error acknowledgment register; ↑ MpGenControl01 bit 12 clears axis 1's warning and
/// leaves axis 2's.
#[test]
fn x67_18_6_3_2_01_acknowledgment_per_axis() {
    for name in ["ClearError01", "ClearError02", "ErrorAcknowledgment"] {
        assert_eq!(Register::from_name(name), None);
    }
    let mut m = Module::new();
    for axis in 0..2 {
        operation_enable(&mut m, axis, 0, 10, 10);
        m.set_mode(axis, modes::SPEED);
        m.set_abs_pos(axis, 30);
        make_stall(&mut m, axis);
        m.set_control(axis, ENABLE_OPERATION | CW_STALL_DETECTION);
    }
    m.run(5);
    assert_eq!((m.error_code(0), m.error_code(1)), (0xFF01, 0xFF01));
    for axis in 0..2 {
        m.axis_mut(axis).motor.load = Load::Value(7);
    }
    m.step();
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION | CW_WARNING_RESET);
    m.step();
    assert_eq!((m.error_code(0), m.error_code(1)), (0, 0xFF01));
    assert_eq!(m.status_word(0) & SW_WARNING, 0);
    assert_ne!(m.status_word(1) & SW_WARNING, 0);
}

// ===== 18.11.3.2 Control word bits 11–15 =====

/// X67-18.11.3.2-05: a rising edge on CW bit 11 at standstill, powered, at internal counter 0 (≡ 0 mod 1024)
/// measures the motor again; holding the bit at 1 measures nothing more.
#[test]
fn x67_18_11_3_2_05_motor_id_on_rising_edge() {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 50, 80);
    operation_enable(&mut m, 0, 100, 10, 10);
    assert_eq!(named(&m, "Motoridentification01"), 133);

    m.axis_mut(0).motor.params.inductance_mh = 6.0;
    m.step();
    assert_eq!(named(&m, "Motoridentification01"), 133);
    m.set_control(0, ENABLE_OPERATION | CW_MOTOR_ID);
    m.step();
    let six = expected_identification(6.0, 1.5, 24.0, 50).unwrap();
    assert_eq!(six, 267);
    assert_eq!(named(&m, "Motoridentification01"), i64::from(six));

    m.axis_mut(0).motor.params.inductance_mh = 9.0;
    m.run(3);
    assert_eq!(named(&m, "Motoridentification01"), i64::from(six));
    m.set_control(0, ENABLE_OPERATION);
    m.step();
    assert_eq!(named(&m, "Motoridentification01"), i64::from(six));
    m.set_control(0, ENABLE_OPERATION | CW_MOTOR_ID);
    m.step();
    assert_eq!(named(&m, "Motoridentification01"), 400);
}

/// X67-18.11.3.2-06: ↑ CW bit 12 resets the stall warning once its cause is gone (the load removed before
/// the reset), but not while the condition is still present.
#[test]
fn x67_18_11_3_2_06_warning_reset() {
    let mut m = running(50, 10);
    make_stall(&mut m, 0);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.run(2);
    assert_eq!(m.error_code(0), 0xFF01);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION | CW_WARNING_RESET);
    m.step();
    assert_eq!(m.error_code(0), 0xFF01);
    assert_ne!(m.status_word(0) & SW_WARNING, 0);

    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.step();
    m.axis_mut(0).motor.load = Load::Value(7);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION | CW_WARNING_RESET);
    m.step();
    assert_eq!(m.error_code(0), 0);
    assert_eq!(m.status_word(0) & SW_WARNING, 0);
    m.run(3);
    assert_eq!(m.error_code(0), 0);
}

/// X67-18.11.3.2-07: CW bit 13 switches current-error detection: an open winding gives no 0xFF00 with bit
/// 13 = 0 (only the lower 0xFF11) and 0xFF00 with bit 13 = 1.
#[test]
fn x67_18_11_3_2_07_current_error_detection_bit() {
    let mut m = running(50, 10);
    m.axis_mut(0).motor.faults.open_winding = true;
    m.run(3);
    assert_eq!(m.error_code(0), 0xFF11);
    assert!(!m
        .axis(0)
        .errors()
        .is_latched(ds402::x67::errors::ErrorCode::CurrentError));
    m.set_control(0, ENABLE_OPERATION | CW_CURRENT_ERROR_DETECTION);
    m.step();
    assert_eq!(m.error_code(0), 0xFF00);
}

/// X67-18.11.3.2-08, X67-18.11.3.4-01, X67-18.11.3.10-01: internal counter 5000 and ABR counter 120: with
/// CW bit 14 = 0 AbsPos01ActVal = 5000 (input object bytes 0–3) and AbsPos01ActValAcyclic = 120; with bit 14
/// = 1 the other way round.
#[test]
fn x67_18_11_3_2_08_counter_swap() {
    let mut m = Module::new();
    operation_enable(&mut m, 0, 100, 10, 10);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 5000);
    m.run(70);
    quadrature(&mut m, 0, 120);
    m.step();
    assert_eq!(named(&m, "AbsPos01ActVal"), 5000);
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 120);
    assert_eq!(m.input_object(0)[0..4], 5000i32.to_le_bytes());
    m.set_control(0, ENABLE_OPERATION | CW_SWAP_COUNTERS);
    m.step();
    assert_eq!(named(&m, "AbsPos01ActVal"), 120);
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 5000);
    assert_eq!(m.input_object(0)[0..4], 120i32.to_le_bytes());
    // The ABR count is sign-extended in the cyclic object: 120 − 123 = −3.
    quadrature(&mut m, 0, -123);
    m.step();
    assert_eq!(named(&m, "AbsPos01ActVal"), -3);
    assert_eq!(m.input_object(0)[0..4], [0xFD, 0xFF, 0xFF, 0xFF]);
    assert_eq!(named(&m, "AbsPos01ActValAcyclic"), 5000);
}

/// X67-18.11.3.2-09: CW bit 15 switches stall detection: the same stall condition gives no 0xFF01 with
/// bit 15 = 0 and 0xFF01 with bit 15 = 1.
#[test]
fn x67_18_11_3_2_09_stall_detection_bit() {
    let mut m = running(50, 10);
    make_stall(&mut m, 0);
    m.run(5);
    assert_eq!(m.error_code(0), 0);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.step();
    assert_eq!(m.error_code(0), 0xFF01);
}

// ===== 18.6.1 / 18.11.1.10 / 18.11.1.12 / 18.11.1.13 Stall detection and mixed decay =====

/// X67-18.6.1.1-01: the stall threshold is StallDetectConfig0n bits 4–6 per axis (no ConfigOutput01): axis
/// 1 with threshold 3 stalls at load value 2, axis 2 with the same load and threshold 0 does not, nor does
/// axis 1 with only bits 0–3 and 7 set.
#[test]
fn x67_18_6_1_1_01_threshold_per_axis() {
    assert_eq!(Register::from_name("ConfigOutput01"), None);
    let mut m = Module::new();
    for axis in 0..2 {
        operation_enable(&mut m, axis, 0, 10, 10);
        m.set_mode(axis, modes::SPEED);
        m.set_abs_pos(axis, 30);
        m.set_control(axis, ENABLE_OPERATION | CW_STALL_DETECTION);
        m.axis_mut(axis).motor.load = Load::Value(2);
    }
    set(&mut m, 0, AxisReg::StallDetectConfig, 0x8F);
    m.run(5);
    assert_eq!((m.error_code(0), m.error_code(1)), (0, 0));
    set(&mut m, 0, AxisReg::StallDetectConfig, 0x30);
    m.run(2);
    assert_eq!((m.error_code(0), m.error_code(1)), (0xFF01, 0));
}

/// X67-18.6.1.1-02, X67-18.11.1.10-03: a stall exists exactly when the load value is below the threshold
/// (bits 4–6): 0 never detects, 1 only at load 0, 7 up to load 6; threshold 3 with load 2 stalls, with
/// load 3 not.
#[test]
fn x67_18_6_1_1_02_stall_when_load_below_threshold() {
    let probe = stall_probe();
    for threshold in 0..=7u8 {
        for load in 0..=7u8 {
            let mut m = probe.clone();
            set(
                &mut m,
                0,
                AxisReg::StallDetectConfig,
                i64::from(threshold << 4),
            );
            m.axis_mut(0).motor.load = Load::Value(load);
            m.run(2);
            let expected = if load < threshold { 0xFF01 } else { 0 };
            assert_eq!(
                m.error_code(0),
                expected,
                "threshold {threshold}, load {load}"
            );
        }
    }
}

/// X67-18.11.1.10-03: bits 4–6 hold the stall threshold: the number of load values that stall rises with
/// the threshold from none (0) to seven (7).
#[test]
fn x67_18_11_1_10_03_stall_threshold_sensitivity() {
    let probe = stall_probe();
    let stalling: Vec<usize> = (0..=7u8)
        .map(|threshold| {
            (0..=7u8)
                .filter(|&load| {
                    let mut m = probe.clone();
                    set(
                        &mut m,
                        0,
                        AxisReg::StallDetectConfig,
                        i64::from(threshold << 4),
                    );
                    m.axis_mut(0).motor.load = Load::Value(load);
                    m.run(2);
                    m.error_code(0) == 0xFF01
                })
                .count()
        })
        .collect();
    assert_eq!(stalling, [0, 1, 2, 3, 4, 5, 6, 7]);
}

/// X67-18.6.1.1-03: the load value (SW bits 13–15 with StallDetectConfig01 bit 7) rises with the constant
/// speed under the same load and falls as the load rises at the same speed.
#[test]
fn x67_18_6_1_1_03_load_value_follows_speed_and_load() {
    let mut m = running(0, 10);
    set(&mut m, 0, AxisReg::StallDetectConfig, 0x80);
    let slow = load_bits_at(&m, 100, 20);
    let faster = load_bits_at(&m, 300, 20);
    let fast = load_bits_at(&m, 500, 20);
    assert!(slow < faster && faster < fast, "{slow} {faster} {fast}");
    let loaded = load_bits_at(&m, 500, 60);
    let heavy = load_bits_at(&m, 500, 100);
    assert!(fast > loaded && loaded > heavy, "{fast} {loaded} {heavy}");
}

/// X67-18.6.1.2-01, X67-18.11.1.10-01: the mixed-decay threshold is StallDetectConfig0n bits 0–3 (no
/// ConfigOutput16) with default 0 = off; 15 = always on; 1…14 thresholds (on at low, off at the highest
/// speed).
#[test]
fn x67_18_6_1_2_01_mixed_decay_threshold_default_off() {
    assert_eq!(Register::from_name("ConfigOutput16"), None);
    let m = Module::new();
    assert_eq!(named(&m, "StallDetectConfig01"), 0);
    assert_eq!(named(&m, "StallDetectConfig02"), 0);

    let decay = |threshold: i64, speed: i32| {
        let mut m = running(speed, 65_535);
        set(&mut m, 0, AxisReg::StallDetectConfig, threshold);
        m.step();
        m.axis(0).observation().mixed_decay
    };
    for speed in [1, 100, 5000, 65_535] {
        assert!(!decay(0, speed), "threshold 0 at {speed}");
        assert!(decay(15, speed), "threshold 15 at {speed}");
    }
    for threshold in 1..=14 {
        assert!(decay(threshold, 1), "threshold {threshold} at 1");
        assert!(!decay(threshold, 65_535), "threshold {threshold} at 65535");
    }
}

/// X67-18.11.1.10-01: the decay mode follows bits 0–3 only: bits 4–7 do not switch it.
#[test]
fn x67_18_11_1_10_01_decay_bits() {
    for (config, on) in [(0x00, false), (0xF0, false), (0x0F, true), (0xFF, true)] {
        let mut m = running(100, 100);
        set(&mut m, 0, AxisReg::StallDetectConfig, config);
        m.step();
        assert_eq!(m.axis(0).observation().mixed_decay, on, "{config:#04x}");
    }
}

/// X67-18.11.1.10-02: the smaller the mixed-decay threshold, the wider the speed range with mixed decay
/// off: threshold 1 switches it off at every speed threshold 14 does, and at more.
#[test]
fn x67_18_11_1_10_02_smaller_threshold_wider_off_range() {
    let one = decay_off_speeds(1);
    let fourteen = decay_off_speeds(14);
    assert!(!fourteen.is_empty());
    assert!(fourteen.iter().all(|s| one.contains(s)));
    assert!(one.len() > fourteen.len());
}

/// X67-18.11.1.10-01, X67-18.11.1.10-02 (the model's pick for the simulated decay mode, which no register
/// shows): above StallDetectMinSpeed01 (0 here) a threshold t of 1…14 keeps mixed decay on below 64·t
/// microsteps/cycle and off from there on: over the speeds 1…1000, threshold 1 has it off from 64, threshold
/// 14 from 896.
#[test]
fn x67_18_11_1_10_02_threshold_speeds() {
    assert_eq!(decay_off_speeds(1), (64..=1000).collect::<Vec<i32>>());
    assert_eq!(decay_off_speeds(14), (896..=1000).collect::<Vec<i32>>());
}

/// X67-18.11.1.10-04: with StallDetectConfig01 bit 7 the load value shows in SW bits 13–15 (bit 13 LSB),
/// without it those bits are 0.
#[test]
fn x67_18_11_1_10_04_load_value_in_status_word() {
    let base = running(50, 10);
    for (config, load, bits) in [
        (0x80, 5, 0b101),
        (0x80, 6, 0b110),
        (0x80, 3, 0b011),
        (0x00, 5, 0),
        (0x00, 6, 0),
    ] {
        let mut m = base.clone();
        set(&mut m, 0, AxisReg::StallDetectConfig, config);
        m.axis_mut(0).motor.load = Load::Value(load);
        m.run(2);
        assert_eq!(m.status_word(0) >> 13, bits, "{config:#04x}, load {load}");
        assert_eq!(m.status_word(0) & 0x037F, OPERATION_ENABLE);
    }
}

/// X67-18.6.3.5-01: there is no MotorLoad register; each axis's load value 0…7 is read from its own SW
/// bits 13–15 with StallDetectConfig0n bit 7.
#[test]
fn x67_18_6_3_5_01_load_value_per_axis_in_status_word() {
    for name in ["MotorLoad", "MotorLoad01", "MotorLoad02"] {
        assert_eq!(Register::from_name(name), None);
    }
    let mut m = Module::new();
    for (axis, load) in [(0, 3u8), (1, 5)] {
        operation_enable(&mut m, axis, 0, 10, 10);
        m.set_mode(axis, modes::SPEED);
        m.set_abs_pos(axis, 30);
        m.axis_mut(axis).motor.load = Load::Value(load);
    }
    set(&mut m, 0, AxisReg::StallDetectConfig, 0x80);
    set(&mut m, 1, AxisReg::StallDetectConfig, 0x80);
    m.run(5);
    assert_eq!((m.status_word(0) >> 13, m.status_word(1) >> 13), (3, 5));
    set(&mut m, 1, AxisReg::StallDetectConfig, 0x00);
    m.step();
    assert_eq!((m.status_word(0) >> 13, m.status_word(1) >> 13), (3, 0));
}

/// X67-18.6.1.3-01, X67-18.11.1.13-01: StallDetectMinSpeed01 = 50 is compared with the ramp speed in
/// microsteps/cycle: at 50 no stall, at 51 a stall, at 25 ms and at 10 ms alike.
#[test]
fn x67_18_11_1_13_01_minimum_speed_for_stall_detection() {
    for general_config in [0, 0b010] {
        let mut m = Module::new();
        m.write_named("GeneralConfig01", general_config).unwrap();
        operation_enable(&mut m, 0, 0, 10, 10);
        set(&mut m, 0, AxisReg::StallDetectMinSpeed, 50);
        make_stall(&mut m, 0);
        m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
        m.set_mode(0, modes::SPEED);
        m.set_abs_pos(0, 50);
        assert_eq!(increments(&mut m, 0, 8), [10, 20, 30, 40, 50, 50, 50, 50]);
        assert_eq!(m.error_code(0), 0, "GeneralConfig01 = {general_config}");
        m.set_abs_pos(0, 51);
        assert_eq!(increments(&mut m, 0, 2), [51, 51]);
        assert_eq!(
            m.error_code(0),
            0xFF01,
            "GeneralConfig01 = {general_config}"
        );
    }
}

/// X67-18.6.1.3-01: the unit is microsteps/cycle, not steps/second: 51 microsteps per 25 ms cycle
/// (2040 microsteps/s) is above StallDetectMinSpeed01 = 50.
#[test]
fn x67_18_6_1_3_01_minimum_speed_in_microsteps_per_cycle() {
    let mut m = running(51, 51);
    set(&mut m, 0, AxisReg::StallDetectMinSpeed, 50);
    make_stall(&mut m, 0);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.step();
    assert_eq!(m.error_code(0), 0xFF01);
}

/// X67-18.11.1.13-02: at or below StallDetectMinSpeed01 mixed decay is on (threshold 15) even with bits 0–3
/// = 0; above it the configured threshold (0 = off) applies.
#[test]
fn x67_18_11_1_13_02_mixed_decay_on_below_minimum_speed() {
    let mut m = Module::new();
    operation_enable(&mut m, 0, 0, 10, 10);
    set(&mut m, 0, AxisReg::StallDetectMinSpeed, 50);
    m.step();
    assert!(m.axis(0).observation().mixed_decay);
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, 60);
    let mut seen = Vec::new();
    for _ in 0..8 {
        m.step();
        let o = m.axis(0).observation();
        seen.push((o.ramp.speed, o.mixed_decay));
    }
    assert_eq!(
        seen,
        [
            (10, true),
            (20, true),
            (30, true),
            (40, true),
            (50, true),
            (60, false),
            (60, false),
            (60, false)
        ]
    );
}

/// X67-18.11.1.12-02: StallRecognitionDelay01 = 255 does not delay stall detection outside homing: in mode 1
/// the stall shows in the same cycle as with delay 0, the second cycle of motion (the load value is measured
/// on the motion of the cycle before).
#[test]
fn x67_18_11_1_12_02_recognition_delay_only_for_homing() {
    let mut cycles = Vec::new();
    for delay in [0, 255] {
        let mut m = Module::new();
        operation_enable(&mut m, 0, 100, 10, 10);
        set(&mut m, 0, AxisReg::StallRecognitionDelay, delay);
        make_stall(&mut m, 0);
        m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
        m.set_mode(0, modes::POSITION);
        m.set_abs_pos(0, 10_000);
        let first = (1..=20)
            .find(|_| {
                m.step();
                m.error_code(0) == 0xFF01
            })
            .unwrap();
        cycles.push(first);
    }
    assert_eq!(cycles, [2, 2]);
}
