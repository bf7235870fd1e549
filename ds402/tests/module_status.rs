//! The X67SM2436 "Ramp" module seen as a whole through [`Module`]: the state machine of each axis, errors and
//! warnings, currents, motor identification, inputs and encoders, and the register table. The lower layers
//! (ramp, state machine, error register, current model) have their own tests; these prove the joined model.
//! Each test names the rules of `rules/x67.md` it checks.

mod x67_rig;

use ds402::cia402::control::{
    DISABLE_OPERATION, DISABLE_VOLTAGE, ENABLE_OPERATION, ENABLE_VOLTAGE_BIT, FAULT_RESET,
    QUICK_STOP, SHUTDOWN, SWITCH_ON,
};
use ds402::cia402::{self, State, SW_WARNING};
use ds402::x67::axis::{modes, CW_MOTOR_ID, CW_SWAP_COUNTERS, SW_TARGET_REACHED};
use ds402::x67::current::Level;
use ds402::x67::errors::{CW_CURRENT_ERROR_DETECTION, CW_STALL_DETECTION, CW_WARNING_RESET};
use ds402::x67::module::{Cam, Diagnostic, Module};
use ds402::x67::motor::{self, Load, MotorParams};
use ds402::x67::registers::{Access, AxisReg, ModuleReg, RegType, Register, RegisterError};
use x67_rig::{
    assert_state, increments, mask, operation_enable, set, set_currents, switch_on, FAULT,
    FAULT_REACTION_ACTIVE, NOT_READY, OPERATION_ENABLE, QUICK_STOP_ACTIVE, QUICK_STOP_FROM_ENABLED,
    READY, SWITCHED_ON, SWITCH_ON_DISABLED,
};
use Access::{Config as Wo, CyclicIn as Tx, CyclicOut as Rx, ReadAcyclic as Ro};
use RegType::{Dint, Int, Sint, Uint, Usint};

/// Status word bit 4: Voltage enabled (X67-18.11.4.2-09).
const SW_VOLTAGE_ENABLED: u16 = 1 << 4;

// ----- helpers -----

fn named(m: &Module, name: &str) -> i64 {
    m.read_named(name)
}

/// A module with axis 1 in Operation enable in speed mode 2 at `speed` microsteps/cycle, reached with
/// MaxAcc01 = MaxDec01 = `acc`; currents 20/50/80 %.
fn running(speed: i32, acc: u16) -> Module {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 50, 80);
    operation_enable(&mut m, 0, 0, i64::from(acc), i64::from(acc));
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, speed);
    for _ in 0..10_000 {
        if m.axis(0).observation().ramp.speed == speed {
            break;
        }
        m.step();
    }
    assert_eq!(m.axis(0).observation().ramp.speed, speed);
    m
}

/// One cycle; returns how far AbsPos0nActVal moved in it.
fn step_increment(m: &mut Module, axis: usize) -> i32 {
    x67_rig::cycle(m, axis).inc
}

/// The current level driven in the last cycle (`None` when the motor is not powered).
fn level(m: &Module, axis: usize) -> Option<Level> {
    m.axis(axis).observation().current.map(|c| c.level)
}

fn milliamps(m: &Module, axis: usize) -> u32 {
    m.axis(axis).phase_current_ma()
}

/// Stall threshold 3 (StallDetectConfig0n bits 4–6) and a motor whose load value is 2: a stall condition
/// whenever the axis moves with stall detection on (X67-18.6.1.1-02).
fn make_stall(m: &mut Module, axis: usize) {
    set(m, axis, AxisReg::StallDetectConfig, 0x30);
    m.axis_mut(axis).motor.load = Load::Value(2);
}

/// Drives the A/B inputs of ABR group `group` (0: DI1/DI2, 1: DI4/DI5) by hand through `counts` quadrature
/// edges: positive counts with A leading B, negative with B leading A.
fn quadrature(m: &mut Module, group: usize, counts: i32) {
    let (a, b) = if group == 0 { (1, 2) } else { (4, 5) };
    const PHASES: [(bool, bool); 4] = [(false, false), (true, false), (true, true), (false, true)];
    for _ in 0..counts.unsigned_abs() {
        let st = m.input_status();
        let now = ((st >> (a - 1)) & 1 == 1, (st >> (b - 1)) & 1 == 1);
        let p = PHASES.iter().position(|&x| x == now).unwrap();
        let next = PHASES[(p + if counts > 0 { 1 } else { 3 }) % 4];
        if next.0 != now.0 {
            m.set_input(a, next.0);
        } else {
            m.set_input(b, next.1);
        }
    }
}

/// The motor-identification value worked out from the winding: the current rises as
/// `i(t) = V/R · (1 − e^(−t·R/L))`; the time from I_nom/3 to I_nom, scaled to 1 A, in µs, rounded
/// (X67-18.11.3.7-01/-06). `None` when (2/3)·I_nom < 1 A, 65534 above 32 767 µs.
fn expected_identification(
    inductance_mh: f64,
    ohm: f64,
    volts: f64,
    nominal_percent: u8,
) -> Option<u16> {
    let i_nom = f64::from(nominal_percent) * 0.030;
    if i_nom * 2.0 / 3.0 < 1.0 {
        return None;
    }
    let tau = inductance_mh / 1000.0 / ohm;
    let t = |i: f64| -tau * (1.0 - i * ohm / volts).ln();
    let us = (t(i_nom) - t(i_nom / 3.0)) / (i_nom * 2.0 / 3.0) * 1e6;
    Some(if us > 32_767.0 {
        65_534
    } else {
        us.round() as u16
    })
}

/// Snapshots of one module with axis 1 in each state the commands reach, moving where it can: Not ready to
/// switch on, Switch on disabled, Ready to switch on, Ready to switch on during the start-up identification,
/// Switched on, Operation enable (moving in mode 1) and Quick stop active (braking). Currents 20/50/80 %,
/// MaxSpeed01pos 100, MaxAcc01 10, MaxDec01 5.
fn tour() -> Vec<(State, Module)> {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 50, 80);
    set(&mut m, 0, AxisReg::MaxSpeedPos, 100);
    set(&mut m, 0, AxisReg::MaxAcc, 10);
    set(&mut m, 0, AxisReg::MaxDec, 5);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 100_000);
    let mut out = vec![(State::NotReadyToSwitchOn, m.clone())];
    m.step();
    out.push((State::SwitchOnDisabled, m.clone()));
    m.set_control(0, SHUTDOWN);
    m.step();
    out.push((State::ReadyToSwitchOn, m.clone()));
    m.set_control(0, SWITCH_ON);
    m.run(5);
    assert!(m.axis(0).observation().identifying);
    out.push((State::ReadyToSwitchOn, m.clone()));
    m.run(40);
    assert_state(&m, 0, SWITCHED_ON);
    out.push((State::SwitchedOn, m.clone()));
    m.set_control(0, ENABLE_OPERATION);
    m.run(12);
    assert_state(&m, 0, OPERATION_ENABLE);
    assert_eq!(m.axis(0).observation().ramp.speed, 100);
    out.push((State::OperationEnabled, m.clone()));
    m.set_control(0, QUICK_STOP_FROM_ENABLED);
    m.run(2);
    assert_state(&m, 0, QUICK_STOP_ACTIVE);
    assert_eq!(m.axis(0).observation().ramp.speed, 90);
    out.push((State::QuickStopActive, m));
    out
}

/// A module with axis 1 cruising in mode 1 at 100 microsteps/cycle toward 100 000 (MaxAcc01 10, MaxDec01 5,
/// currents 20/50/80 %), after 10 cycles of acceleration and 5 of cruise.
fn cruising() -> Module {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 50, 80);
    operation_enable(&mut m, 0, 100, 10, 5);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 100_000);
    assert_eq!(
        increments(&mut m, 0, 15),
        [10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 100, 100, 100, 100, 100]
    );
    assert_eq!(m.act_val(0), 1050);
    m
}

/// The snapshot of [`tour`] in `state` (the first one when there are two).
fn snapshot(state: State) -> Module {
    tour()
        .into_iter()
        .find(|(s, _)| *s == state)
        .map(|(_, m)| m)
        .unwrap()
}

/// A module with axis 1 moving in mode 2 at 30 microsteps/cycle with stall detection on and stall
/// threshold 0.
fn stall_probe() -> Module {
    let mut m = running(30, 10);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.step();
    m
}

/// Runs axis 1 of `m` (mode 2) at `speed` until the speed holds and returns the load value in SW bits 13–15.
fn load_bits_at(m: &Module, speed: i32, torque: u8) -> u16 {
    let mut m = m.clone();
    m.axis_mut(0).motor.load = Load::Torque(torque);
    m.set_abs_pos(0, speed);
    m.run(200);
    assert_eq!(m.axis(0).observation().ramp.speed, speed);
    m.status_word(0) >> 13
}

/// The speeds (1…1000, mode 2 ramp with MaxAcc01 = 1) at which mixed decay is off with threshold `t`.
fn decay_off_speeds(t: i64) -> Vec<i32> {
    let mut m = running(0, 1);
    set(&mut m, 0, AxisReg::StallDetectConfig, t);
    m.set_abs_pos(0, 1000);
    let mut off = Vec::new();
    for _ in 0..1000 {
        m.step();
        let o = m.axis(0).observation();
        if !o.mixed_decay {
            off.push(o.ramp.speed);
        }
    }
    off
}

/// The Motoridentification01 value after the first Switch on of a fresh module whose axis-1 motor has been
/// changed by `motor`, at `volts`, with ConfigOutput04a = `nominal`.
fn first_identification(nominal: u8, volts: f64, motor: impl Fn(&mut MotorParams)) -> i64 {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, i64::from(nominal), 80);
    motor(&mut m.axis_mut(0).motor.params);
    m.set_supply(volts);
    switch_on(&mut m, 0);
    named(&m, "Motoridentification01")
}

/// Every status word of axis 1 (and of axis 2 in Switch on disabled) in every state: the snapshots of
/// [`tour`], each followed by an overtemperature (Fault) and a quick stop in Fault.
fn status_words_of_every_state() -> Vec<u16> {
    let mut words = Vec::new();
    for (_, mut m) in tour() {
        words.push(m.status_word(0));
        words.push(m.status_word(1));
        m.set_temperature(90.0);
        m.step();
        words.push(m.status_word(0));
        m.set_control(0, QUICK_STOP);
        m.step();
        words.push(m.status_word(0));
    }
    assert_eq!(words[0], 0x0200);
    words
}

// ----- the register table (18.5) -----

/// The 18.5 table as the data sheet gives it: name, register number, type, access.
const TABLE: [(&str, u16, RegType, Access); 71] = [
    // Configuration
    ("ConfigOutput03a", 48, Usint, Wo),
    ("ConfigOutput04a", 49, Usint, Wo),
    ("ConfigOutput05a", 50, Usint, Wo),
    ("ConfigOutput06a", 112, Usint, Wo),
    ("ConfigOutput07a", 113, Usint, Wo),
    ("ConfigOutput08a", 114, Usint, Wo),
    ("FullStepThreshold01", 72, Uint, Wo),
    ("FullStepThreshold02", 136, Uint, Wo),
    ("MaxSpeed01pos", 52, Uint, Wo),
    ("MaxSpeed02pos", 116, Uint, Wo),
    ("MaxAcc01", 54, Uint, Wo),
    ("MaxDec01", 56, Uint, Wo),
    ("MaxAcc02", 118, Uint, Wo),
    ("MaxDec02", 120, Uint, Wo),
    ("RevLoop01", 58, Int, Wo),
    ("RevLoop02", 122, Int, Wo),
    ("FixedPos01a", 60, Dint, Wo),
    ("FixedPos01b", 64, Dint, Wo),
    ("FixedPos02a", 124, Dint, Wo),
    ("FixedPos02b", 128, Dint, Wo),
    ("RefSpeed01", 68, Uint, Wo),
    ("RefSpeed02", 132, Uint, Wo),
    ("RefConfig01", 70, Sint, Wo),
    ("RefConfig02", 134, Sint, Wo),
    ("StallDetectConfig01", 51, Usint, Wo),
    ("StallDetectConfig02", 115, Usint, Wo),
    ("StallRecognitionDelay01", 74, Usint, Wo),
    ("StallRecognitionDelay02", 138, Usint, Wo),
    ("JoltTime01", 75, Usint, Wo),
    ("JoltTime02", 139, Usint, Wo),
    ("StallDetectMinSpeed01", 78, Uint, Wo),
    ("StallDetectMinSpeed02", 142, Uint, Wo),
    ("GeneralConfig01", 304, Usint, Wo),
    ("LimitSwitchConfig01", 306, Usint, Wo),
    ("LimitSwitchConfig02", 308, Usint, Wo),
    ("PositionLimitMin01", 380, Dint, Wo),
    ("PositionLimitMin02", 388, Dint, Wo),
    ("PositionLimitMax01", 384, Dint, Wo),
    ("PositionLimitMax02", 392, Dint, Wo),
    // Reading back the configuration
    ("ConfigOutput03aRead", 48, Usint, Ro),
    ("ConfigOutput04aRead", 49, Usint, Ro),
    ("ConfigOutput05aRead", 50, Usint, Ro),
    ("ConfigOutput06aRead", 112, Usint, Ro),
    ("ConfigOutput07aRead", 113, Usint, Ro),
    ("ConfigOutput08aRead", 114, Usint, Ro),
    // Communication
    ("AbsPos01", 0, Dint, Rx),
    ("MpGenControl01", 4, Uint, Rx),
    ("MpGenMode01", 6, Sint, Rx),
    ("AbsPos01ActVal", 0, Dint, Tx),
    ("MpGenStatus01", 4, Uint, Tx),
    ("AbsPos02", 8, Dint, Rx),
    ("MpGenControl02", 12, Uint, Rx),
    ("MpGenMode02", 14, Sint, Rx),
    ("AbsPos02ActVal", 8, Dint, Tx),
    ("MpGenStatus02", 12, Uint, Tx),
    ("InputStatus", 6, Usint, Tx),
    ("Motoridentification01", 84, Uint, Ro),
    ("Motoridentification02", 148, Uint, Ro),
    ("Temperature", 46, Sint, Ro),
    ("RefPos01CyclicCounter", 86, Dint, Ro),
    ("RefPos02CyclicCounter", 150, Dint, Ro),
    ("RefPos01AcyclicCounter", 94, Dint, Ro),
    ("RefPos02AcyclicCounter", 158, Dint, Ro),
    ("AbsPos01ActValAcyclic", 90, Dint, Ro),
    ("AbsPos02ActValAcyclic", 154, Dint, Ro),
    ("ControlReadback01", 80, Uint, Ro),
    ("ControlReadback02", 144, Uint, Ro),
    ("ModeReadback01", 82, Sint, Ro),
    ("ModeReadback02", 146, Sint, Ro),
    ("ErrorCode01", 98, Uint, Ro),
    ("ErrorCode02", 162, Uint, Ro),
];

/// Checks the table rows of `names` against the model.
#[track_caller]
fn assert_rows(names: &[&str]) {
    for name in names {
        let row = TABLE.iter().find(|r| r.0 == *name).unwrap();
        let reg = Register::from_name(name).unwrap_or_else(|| panic!("no register {name}"));
        let info = reg.info();
        assert_eq!(info.name, *name);
        assert_eq!(
            (info.number, info.ty, info.access),
            (row.1, row.2, row.3),
            "{name}"
        );
    }
}

// ===== 18.11.4.3 State machine transitions =====

/// X67-18.11.4.3-01: after start-up both state machines are in Not ready to switch on.
#[test]
fn x67_18_11_4_3_01_starts_in_not_ready_to_switch_on() {
    let m = Module::new();
    for axis in 0..2 {
        assert_eq!(m.axis(axis).state(), State::NotReadyToSwitchOn);
        assert_eq!(m.status_word(axis), 0x0200);
        assert_state(&m, axis, NOT_READY);
    }
}

/// X67-18.11.4.3-02: the first cycle after start-up reaches Switch on disabled without any command.
#[test]
fn x67_18_11_4_3_02_switch_on_disabled_by_itself() {
    let mut m = Module::new();
    m.step();
    for axis in 0..2 {
        assert_state(&m, axis, SWITCH_ON_DISABLED);
        assert_eq!(m.axis(axis).state_trace(), [State::SwitchOnDisabled]);
    }
    m.run(10);
    for axis in 0..2 {
        assert_state(&m, axis, SWITCH_ON_DISABLED);
        assert!(m.axis(axis).state_trace().is_empty());
    }
}

/// X67-18.11.4.3-03: Shutdown takes Switch on disabled to Ready to switch on and does nothing else: no
/// phase current, AbsPos01ActVal unchanged.
#[test]
fn x67_18_11_4_3_03_shutdown_from_switch_on_disabled() {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 50, 80);
    operation_enable(&mut m, 0, 100, 10, 10);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 5000);
    m.run(70);
    assert_eq!(m.act_val(0), 5000);
    m.set_control(0, DISABLE_VOLTAGE);
    m.step();
    assert_state(&m, 0, SWITCH_ON_DISABLED);

    m.set_control(0, SHUTDOWN);
    m.step();
    assert_state(&m, 0, READY);
    assert_eq!(milliamps(&m, 0), 0);
    assert!(!m.axis(0).observation().powered);
    assert_eq!(m.act_val(0), 5000);
    m.run(5);
    assert_state(&m, 0, READY);
    assert_eq!(m.act_val(0), 5000);
    assert_eq!(milliamps(&m, 0), 0);
}

/// X67-18.11.4.3-04: Disable voltage or Quick stop (also with don't-care bits) takes Ready to switch on back
/// to Switch on disabled.
#[test]
fn x67_18_11_4_3_04_ready_to_switch_on_disabled() {
    // Disable voltage with bits 0, 2 and 3 set (0x000D) and Quick stop with bits 0 and 3 set (0x000B).
    let disable_voltage_with_x_bits = ENABLE_OPERATION & !ENABLE_VOLTAGE_BIT;
    for cw in [
        DISABLE_VOLTAGE,
        QUICK_STOP,
        disable_voltage_with_x_bits,
        QUICK_STOP_FROM_ENABLED,
    ] {
        let mut m = Module::new();
        m.step();
        m.set_control(0, SHUTDOWN);
        m.step();
        assert_state(&m, 0, READY);
        m.set_control(0, cw);
        m.step();
        assert_state(&m, 0, SWITCH_ON_DISABLED);
        assert_eq!(milliamps(&m, 0), 0);
        assert_eq!(m.act_val(0), 0);
    }
}

/// X67-18.11.4.3-05: Disable voltage or Quick stop takes Switched on to Switch on disabled, and the cycle
/// that takes the command already drives no phase current.
#[test]
fn x67_18_11_4_3_05_switched_on_to_switch_on_disabled() {
    for cw in [DISABLE_VOLTAGE, QUICK_STOP] {
        let mut m = Module::new();
        set_currents(&mut m, 0, 20, 50, 80);
        switch_on(&mut m, 0);
        m.step();
        assert_eq!(milliamps(&m, 0), 600);
        m.set_control(0, cw);
        m.step();
        assert_state(&m, 0, SWITCH_ON_DISABLED);
        assert_eq!(milliamps(&m, 0), 0);
        assert!(!m.axis(0).observation().powered);
    }
}

/// X67-18.11.4.3-06: Switch on takes Ready to switch on to Switched on with the voltage on: SW bit 4 = 1 and
/// the holding current ConfigOutput03a (20 % = 600 mA) flows at standstill. This also holds right after the
/// voltage was cut while the axis accelerated at maximum current.
#[test]
fn x67_18_11_4_3_06_switch_on_powers_with_holding_current() {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 50, 80);
    switch_on(&mut m, 0);
    m.set_control(0, SHUTDOWN);
    m.step();
    assert_state(&m, 0, READY);
    assert_eq!(milliamps(&m, 0), 0);

    m.set_control(0, SWITCH_ON);
    m.step();
    assert_state(&m, 0, SWITCHED_ON);
    assert_ne!(m.status_word(0) & SW_VOLTAGE_ENABLED, 0);
    assert_eq!(level(&m, 0), Some(Level::Holding));
    assert_eq!(milliamps(&m, 0), 600);

    // Voltage cut during an acceleration at maximum current, then Switch on again.
    m.set_control(0, ENABLE_OPERATION);
    set(&mut m, 0, AxisReg::MaxAcc, 5);
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, 100);
    m.run(3);
    assert_eq!(level(&m, 0), Some(Level::Maximum));
    m.set_control(0, SHUTDOWN);
    m.step();
    assert_state(&m, 0, READY);
    m.set_control(0, SWITCH_ON);
    m.step();
    assert_state(&m, 0, SWITCHED_ON);
    assert_eq!(level(&m, 0), Some(Level::Holding));
    assert_eq!(milliamps(&m, 0), 600);
}

/// X67-18.11.4.3-07, X67-18.11.3.7-05: the first Switch on keeps Ready to switch on for 1.0 s (40 cycles at
/// 25 ms) while the motor is identified, then Switched on with Motoridentification01 set; a later Switch on
/// takes one cycle.
#[test]
fn x67_18_11_4_3_07_first_switch_on_identifies_for_one_second() {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 50, 80);
    m.step();
    m.set_control(0, SHUTDOWN);
    m.step();
    m.set_control(0, SWITCH_ON);
    for _ in 0..40 {
        m.step();
        assert_state(&m, 0, READY);
        assert!(m.axis(0).observation().identifying);
        assert_eq!(named(&m, "Motoridentification01"), 0);
    }
    m.step();
    assert_state(&m, 0, SWITCHED_ON);
    assert_eq!(
        named(&m, "Motoridentification01"),
        i64::from(expected_identification(3.0, 1.5, 24.0, 50).unwrap())
    );
    assert_eq!(named(&m, "Motoridentification01"), 133);

    m.set_control(0, SHUTDOWN);
    m.step();
    assert_state(&m, 0, READY);
    m.set_control(0, SWITCH_ON);
    m.step();
    assert_state(&m, 0, SWITCHED_ON);
}

/// X67-18.11.4.3-07: at a 10 ms cycle (GeneralConfig01 bits 1–2 = 01) the 1.0 s are 100 cycles.
#[test]
fn x67_18_11_4_3_07_identification_at_10_ms() {
    let mut m = Module::new();
    m.write_named("GeneralConfig01", 0b010).unwrap();
    set_currents(&mut m, 0, 20, 100, 80);
    m.step();
    m.set_control(0, SHUTDOWN);
    m.step();
    m.set_control(0, SWITCH_ON);
    for _ in 0..100 {
        m.step();
        assert_state(&m, 0, READY);
    }
    m.step();
    assert_state(&m, 0, SWITCHED_ON);
    assert_eq!(named(&m, "Motoridentification01"), 143);
}

/// X67-18.11.4.3-08: Shutdown takes Switched on to Ready to switch on and the phase current stops at once.
#[test]
fn x67_18_11_4_3_08_shutdown_from_switched_on() {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 50, 80);
    switch_on(&mut m, 0);
    m.step();
    assert_eq!(milliamps(&m, 0), 600);
    m.set_control(0, SHUTDOWN);
    m.step();
    assert_state(&m, 0, READY);
    assert_eq!(milliamps(&m, 0), 0);
    assert_eq!(m.status_word(0) & SW_VOLTAGE_ENABLED, 0);
}

/// X67-18.11.4.3-09: Enable operation takes Switched on to Operation enable, and the selected mode moves the
/// axis at once: Mode 1 with AbsPos01 ≠ actual starts with MaxAcc01 in the same cycle.
#[test]
fn x67_18_11_4_3_09_enable_operation_starts_the_mode() {
    let mut m = Module::new();
    set(&mut m, 0, AxisReg::MaxSpeedPos, 100);
    set(&mut m, 0, AxisReg::MaxAcc, 10);
    set(&mut m, 0, AxisReg::MaxDec, 10);
    switch_on(&mut m, 0);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 10_000);
    assert_eq!(increments(&mut m, 0, 3), [0, 0, 0]);
    assert_state(&m, 0, SWITCHED_ON);
    m.set_control(0, ENABLE_OPERATION);
    assert_eq!(step_increment(&mut m, 0), 10);
    assert_state(&m, 0, OPERATION_ENABLE);
    assert_eq!(increments(&mut m, 0, 3), [20, 30, 40]);
}

/// X67-18.11.4.3-10: Disable operation during a move shows Switched on at once; the speed falls by MaxDec01
/// (5) per cycle to 0 with SW bit 4 = 1, then, after the 100 ms hold of the maximum current, the holding
/// current flows.
#[test]
fn x67_18_11_4_3_10_disable_operation_brakes_with_max_dec() {
    let mut m = cruising();
    m.set_control(0, DISABLE_OPERATION);
    for k in 1..=19 {
        assert_eq!(step_increment(&mut m, 0), 100 - 5 * k);
        assert_state(&m, 0, SWITCHED_ON);
        assert_ne!(m.status_word(0) & SW_VOLTAGE_ENABLED, 0);
        assert_eq!(m.status_word(0) & SW_TARGET_REACHED, 0);
        assert_eq!(level(&m, 0), Some(Level::Maximum));
    }
    assert_eq!(step_increment(&mut m, 0), 0);
    assert_state(&m, 0, SWITCHED_ON);
    assert_eq!(m.act_val(0), 1050 + 950);
    for _ in 0..4 {
        assert_eq!(step_increment(&mut m, 0), 0);
        assert_eq!(level(&m, 0), Some(Level::Maximum));
    }
    m.step();
    assert_state(&m, 0, SWITCHED_ON);
    assert_eq!(level(&m, 0), Some(Level::Holding));
    assert_eq!(milliamps(&m, 0), 600);
    assert_eq!(m.act_val(0), 2000);
}

/// X67-18.11.4.3-11: Shutdown during a move: Ready to switch on, no phase current in the next cycle, no
/// braking; the internal counter keeps its last value.
#[test]
fn x67_18_11_4_3_11_shutdown_during_motion_cuts_the_voltage() {
    let mut m = cruising();
    m.set_control(0, SHUTDOWN);
    assert_eq!(step_increment(&mut m, 0), 0);
    assert_state(&m, 0, READY);
    assert_eq!(milliamps(&m, 0), 0);
    assert_eq!(m.act_val(0), 1050);
    assert_eq!(increments(&mut m, 0, 5), [0; 5]);
}

/// The command of the seed's table (18.11.4.1) that control word `cw` gives after `prev`, written out
/// from the table: a rising bit 7 is a Fault reset; otherwise bit 7 = 1 is no command; then bit 1 = 0 is
/// Disable voltage, bit 2 = 0 Quick stop, bit 0 = 0 Shutdown, bit 3 = 0 Switch on (Disable operation)
/// and bit 3 = 1 Enable operation.
fn table_command(prev: u16, cw: u16) -> Option<&'static str> {
    if cw & 0x80 != 0 {
        return (prev & 0x80 == 0).then_some("fault reset");
    }
    Some(if cw & 0x02 == 0 {
        "disable voltage"
    } else if cw & 0x04 == 0 {
        "quick stop"
    } else if cw & 0x01 == 0 {
        "shutdown"
    } else if cw & 0x08 == 0 {
        "switch on"
    } else {
        "enable operation"
    })
}

/// The state pattern after `command` in the state shown by `from`, from the transitions of 18.11.4.3;
/// a command with no transition leaves the state as it is (X67-18.11.4.1-13).
fn table_next(from: u16, command: Option<&str>) -> u16 {
    match (from, command) {
        (SWITCH_ON_DISABLED, Some("shutdown")) => READY,
        (READY, Some("switch on")) => SWITCHED_ON,
        (READY | SWITCHED_ON, Some("disable voltage" | "quick stop")) => SWITCH_ON_DISABLED,
        (SWITCHED_ON, Some("enable operation")) => OPERATION_ENABLE,
        (SWITCHED_ON | OPERATION_ENABLE, Some("shutdown")) => READY,
        (OPERATION_ENABLE, Some("switch on")) => SWITCHED_ON,
        (OPERATION_ENABLE | QUICK_STOP_ACTIVE, Some("disable voltage")) => SWITCH_ON_DISABLED,
        (OPERATION_ENABLE, Some("quick stop")) => QUICK_STOP_ACTIVE,
        (QUICK_STOP_ACTIVE, Some("enable operation")) => OPERATION_ENABLE,
        (FAULT, Some("fault reset")) => SWITCH_ON_DISABLED,
        (state, _) => state,
    }
}

/// X67-18.11.4.1-01 … X67-18.11.4.1-09, X67-18.11.4.1-13, through the module as a master drives it:
/// every control word of bits 0–7, alone and with bit 9 or 10 set, written in each state (Switch on
/// disabled, Ready to switch on and Switched on after the identification, Operation enable and Quick
/// stop active while moving, Fault with its cause gone) gives the state the seed's command table and
/// transitions give. And bit 7 already 1 before: 0x0086 is no command, 0x0006 then Shutdown.
#[test]
fn x67_18_11_4_1_command_table_through_the_module() {
    let tour = tour();
    let at = |state: State| {
        tour.iter()
            .rev()
            .find(|(s, _)| *s == state)
            .unwrap()
            .1
            .clone()
    };
    let mut ready = at(State::SwitchedOn);
    ready.set_control(0, SHUTDOWN);
    ready.step();
    assert_state(&ready, 0, READY);
    let mut fault = at(State::SwitchOnDisabled);
    fault.set_temperature(86.0);
    fault.step();
    fault.set_temperature(25.0);
    fault.set_control(0, DISABLE_VOLTAGE);
    fault.step();
    assert_state(&fault, 0, FAULT);
    let snapshots = [
        (SWITCH_ON_DISABLED, at(State::SwitchOnDisabled), 0),
        (READY, ready, SHUTDOWN),
        (SWITCHED_ON, at(State::SwitchedOn), SWITCH_ON),
        (
            OPERATION_ENABLE,
            at(State::OperationEnabled),
            ENABLE_OPERATION,
        ),
        (
            QUICK_STOP_ACTIVE,
            at(State::QuickStopActive),
            QUICK_STOP_FROM_ENABLED,
        ),
        (FAULT, fault, DISABLE_VOLTAGE),
    ];
    let mut tried = 0;
    for (from, base, prev) in &snapshots {
        assert_state(base, 0, *from);
        for low in 0u16..=0xFF {
            for reserved in [0, 0x0200, 0x0400] {
                let cw = low | reserved;
                let mut m = base.clone();
                m.set_control(0, cw);
                m.step();
                let expected = table_next(*from, table_command(*prev, cw));
                assert_eq!(
                    m.status_word(0) & mask(expected),
                    expected,
                    "from {from:#06x} with CW {cw:#06x}: SW {:#06x}",
                    m.status_word(0)
                );
                tried += 1;
            }
        }
    }
    assert_eq!(tried, 6 * 256 * 3);

    // X67-18.11.4.1-09: with bit 7 already 1, 0x0086 is no Shutdown; 0x0006 is.
    let mut m = at(State::SwitchOnDisabled);
    m.set_control(0, FAULT_RESET);
    m.step();
    m.set_control(0, SHUTDOWN | FAULT_RESET);
    m.step();
    assert_state(&m, 0, SWITCH_ON_DISABLED);
    m.set_control(0, SHUTDOWN);
    m.step();
    assert_state(&m, 0, READY);
}

/// X67-18.11.4.3-12: Disable voltage during a move: Switch on disabled, no phase current, no braking.
#[test]
fn x67_18_11_4_3_12_disable_voltage_during_motion() {
    let mut m = cruising();
    m.set_control(0, DISABLE_VOLTAGE);
    assert_eq!(step_increment(&mut m, 0), 0);
    assert_state(&m, 0, SWITCH_ON_DISABLED);
    assert_eq!(milliamps(&m, 0), 0);
    assert_eq!(m.act_val(0), 1050);
}

/// The DC bus voltage, worked out from the data sheet, after Disable voltage on a motor turning at `speed`
/// microsteps per 25 ms cycle with `share` of its kinetic energy coming back: the rotor's ½·J·ω² with the
/// harness motor's 0.3 kg·cm² and 200 × 256 microsteps per revolution, into the 200 µF bus capacitance
/// (section 3) charged to `supply` volts: √(V² + 2E/C).
fn bus_after_disable(supply: f64, speed: f64, share: f64) -> f64 {
    let omega = speed * 40.0 / 51_200.0 * 2.0 * std::f64::consts::PI;
    let joules = 0.5 * 0.3e-4 * omega * omega * share;
    (supply * supply + 2.0 * joules / 200e-6).sqrt()
}

/// X67-18.11.4.3-12 and its pick (X67-18.11.3.13-02): Disable voltage on a motor turning at 8000
/// microsteps/cycle (6.25 revolutions/s) sends its energy into the DC bus. From a 46 V supply the bus rises
/// to 48.45 V, above the 48.125 V of the supply band: the next cycle both axes go to Fault with 0x3000.
/// From 45 V (47.50 V), under a load that takes half of the energy (47.24 V), or with the motor at a
/// standstill, nothing happens. The rise falls away with τ = 1152 Ω × 200 µF = 0.2304 s: a Fault reset two
/// cycles later still finds the bus at 48.20 V and is refused; one cycle after that (47.97 V) it is taken.
#[test]
fn x67_18_11_4_3_12_disable_voltage_on_a_turning_motor_overvolts_the_dc_bus() {
    let v0 = bus_after_disable(46.0, 8000.0, 1.0);
    assert!((v0 - 48.4491).abs() < 1e-4, "{v0}");
    let decay = (-0.025f64 / (1152.0 * 200e-6)).exp();
    let after = |cycles: i32| 46.0 + (v0 - 46.0) * decay.powi(cycles);
    assert!(
        after(1) > 48.125 && after(2) < 48.125,
        "{} {}",
        after(1),
        after(2)
    );

    let turning = |supply: f64, torque: u8| {
        let mut m = running(8000, 1000);
        m.axis_mut(0).motor.load = Load::Torque(torque);
        m.set_supply(supply);
        m.step();
        assert_state(&m, 0, OPERATION_ENABLE);
        assert_eq!(m.dc_bus_volts(), supply);
        m.set_control(0, DISABLE_VOLTAGE);
        m.step();
        assert_state(&m, 0, SWITCH_ON_DISABLED);
        assert_eq!(milliamps(&m, 0), 0);
        m
    };

    // 46 V: the bus goes over; the next status shows Fault on both axes, voltage off.
    let mut m = turning(46.0, 0);
    assert!((m.dc_bus_volts() - v0).abs() < 1e-9, "{}", m.dc_bus_volts());
    assert_eq!(named(&m, "ErrorCode01"), 0);
    m.step();
    for axis in 0..2 {
        assert_state(&m, axis, FAULT);
        assert_eq!(
            m.axis(axis).state_trace(),
            [State::FaultReactionActive, State::Fault]
        );
    }
    assert_eq!(named(&m, "ErrorCode01"), 0x3000);
    assert_eq!(named(&m, "ErrorCode02"), 0x3000);
    assert!(
        (m.dc_bus_volts() - after(1)).abs() < 1e-9,
        "{}",
        m.dc_bus_volts()
    );
    // A Fault reset in the next cycle meets the bus at 48.20 V: refused.
    let mut early = m.clone();
    early.set_control(0, FAULT_RESET);
    early.step();
    assert_state(&early, 0, FAULT);
    assert_eq!(named(&early, "ErrorCode01"), 0x3000);
    // One cycle later the bus is at 47.97 V and the first Fault reset is taken.
    m.step();
    assert_state(&m, 0, FAULT);
    assert!(
        (m.dc_bus_volts() - after(2)).abs() < 1e-9,
        "{}",
        m.dc_bus_volts()
    );
    m.set_control(0, FAULT_RESET);
    m.step();
    assert_state(&m, 0, SWITCH_ON_DISABLED);
    assert_eq!(named(&m, "ErrorCode01"), 0);
    assert_state(&m, 1, FAULT);

    // 45 V, or half the energy taken by the load: below the band's top, no error.
    for (supply, torque, share) in [(45.0, 0, 1.0), (46.0, 50, 0.5)] {
        let expected = bus_after_disable(supply, 8000.0, share);
        assert!(expected < 48.125 && expected > supply + 1.0, "{expected}");
        let mut m = turning(supply, torque);
        assert!(
            (m.dc_bus_volts() - expected).abs() < 1e-9,
            "{supply} V: {}",
            m.dc_bus_volts()
        );
        m.run(3);
        assert_state(&m, 0, SWITCH_ON_DISABLED);
        assert_eq!(named(&m, "ErrorCode01"), 0, "{supply} V, {torque} %");
        assert_eq!(named(&m, "ErrorCode02"), 0);
    }

    // At a standstill there is nothing to give back.
    let mut m = Module::new();
    m.set_supply(48.0);
    operation_enable(&mut m, 0, 100, 10, 10);
    m.set_control(0, DISABLE_VOLTAGE);
    m.step();
    assert_state(&m, 0, SWITCH_ON_DISABLED);
    assert_eq!(m.dc_bus_volts(), 48.0);
    m.step();
    assert_state(&m, 0, SWITCH_ON_DISABLED);
    assert_eq!(named(&m, "ErrorCode01"), 0);
}

/// X67-18.11.4.3-13: Quick stop during a move shows Quick stop active while the speed falls by MaxDec01 (5)
/// per cycle, at maximum current.
#[test]
fn x67_18_11_4_3_13_quick_stop_brakes_with_max_dec() {
    let mut m = cruising();
    m.set_control(0, QUICK_STOP_FROM_ENABLED);
    for k in 1..=19 {
        assert_eq!(step_increment(&mut m, 0), 100 - 5 * k);
        assert_state(&m, 0, QUICK_STOP_ACTIVE);
        assert_ne!(m.status_word(0) & SW_VOLTAGE_ENABLED, 0);
        assert_eq!(level(&m, 0), Some(Level::Maximum));
    }
    assert_eq!(m.act_val(0), 1050 + 950);
}

/// X67-18.11.4.3-14: once the quick stop has braked the axis to standstill, it goes to Switch on disabled
/// by itself (the cycle after the one that reaches speed 0), with the voltage off.
#[test]
fn x67_18_11_4_3_14_quick_stop_ends_in_switch_on_disabled() {
    let mut m = cruising();
    m.set_control(0, QUICK_STOP_FROM_ENABLED);
    m.run(19);
    // The cycle that reaches speed 0 still shows Quick stop active.
    assert_eq!(step_increment(&mut m, 0), 0);
    assert_state(&m, 0, QUICK_STOP_ACTIVE);
    // The next one leaves it without a further command.
    assert_eq!(step_increment(&mut m, 0), 0);
    assert_state(&m, 0, SWITCH_ON_DISABLED);
    assert_eq!(m.axis(0).state_trace(), [State::SwitchOnDisabled]);
    assert_eq!(milliamps(&m, 0), 0);
    assert!(!m.axis(0).observation().powered);
    assert_eq!(m.act_val(0), 2000);
    m.run(5);
    assert_state(&m, 0, SWITCH_ON_DISABLED);
    assert_eq!(m.act_val(0), 2000);
}

/// X67-18.11.4.3-15: Enable operation during quick-stop braking returns to Operation enable, and the move
/// resumes from the current speed (85) with MaxAcc01 (10).
#[test]
fn x67_18_11_4_3_15_enable_operation_resumes_from_quick_stop() {
    let mut m = cruising();
    m.set_control(0, QUICK_STOP_FROM_ENABLED);
    assert_eq!(increments(&mut m, 0, 3), [95, 90, 85]);
    assert_state(&m, 0, QUICK_STOP_ACTIVE);
    m.set_control(0, ENABLE_OPERATION);
    assert_eq!(step_increment(&mut m, 0), 95);
    assert_state(&m, 0, OPERATION_ENABLE);
    assert_eq!(increments(&mut m, 0, 3), [100, 100, 100]);
}

/// X67-18.11.4.3-16, X67-18.11.4.2-07: an Error (overtemperature or supply) takes every state to Fault
/// reaction active and on to Fault; the trace shows both.
#[test]
fn x67_18_11_4_3_16_error_from_any_state() {
    for (state, base) in tour() {
        for error in ["temperature", "supply"] {
            let mut m = base.clone();
            if error == "temperature" {
                m.set_temperature(85.0);
            } else {
                m.set_supply(17.9);
            }
            m.step();
            assert_eq!(
                m.axis(0).state_trace(),
                [State::FaultReactionActive, State::Fault],
                "{state:?}, {error}"
            );
            assert_state(&m, 0, FAULT);
            assert_eq!(milliamps(&m, 0), 0, "{state:?}, {error}");
        }
    }
}

/// X67-18.11.4.3-16: no control word leads to Fault reaction active or Fault, in any state.
#[test]
fn x67_18_11_4_3_16_no_command_reaches_fault() {
    for (state, base) in tour() {
        for low in 0u16..=0xFF {
            for high in [0x0000, 0xFF00] {
                let mut m = base.clone();
                m.set_control(0, high | low);
                for _ in 0..2 {
                    m.step();
                    let s = m.axis(0).state();
                    assert!(
                        !matches!(s, State::Fault | State::FaultReactionActive),
                        "{state:?} with CW {:#06x} → {s:?}",
                        high | low
                    );
                    assert!(!m
                        .axis(0)
                        .state_trace()
                        .contains(&State::FaultReactionActive));
                }
            }
        }
    }
}

/// X67-18.11.4.3-17: a warning in Operation enable sets SW bit 7 and leaves the state and the motion
/// alone — the stall 0xFF01, an open winding (current error 0xFF00, which ranks above its open circuit
/// 0xFF11) and a shorted winding (overcurrent 0x2300) — through the module as a master sees it.
#[test]
fn x67_18_11_4_3_17_warning_does_not_change_the_state() {
    type Inject = fn(&mut Module);
    let cases: [(&str, Inject, u16, u16); 3] = [
        ("stall", |m| make_stall(m, 0), CW_STALL_DETECTION, 0xFF01),
        (
            "open winding",
            |m| m.axis_mut(0).motor.faults.open_winding = true,
            CW_CURRENT_ERROR_DETECTION,
            0xFF00,
        ),
        (
            "shorted winding",
            |m| m.axis_mut(0).motor.faults.short = true,
            0,
            0x2300,
        ),
    ];
    for (case, inject, detection, code) in cases {
        let mut m = running(20, 10);
        inject(&mut m);
        m.set_control(0, ENABLE_OPERATION | detection);
        assert_eq!(increments(&mut m, 0, 3), [20, 20, 20], "{case}");
        assert_eq!(named(&m, "ErrorCode01"), i64::from(code), "{case}");
        assert_eq!(
            m.status_word(0) & 0x03FF,
            OPERATION_ENABLE | SW_WARNING,
            "{case}"
        );
        assert!(m.axis(0).state_trace().is_empty(), "{case}");
        assert_eq!(increments(&mut m, 0, 3), [20, 20, 20], "{case}");
        assert_state(&m, 0, OPERATION_ENABLE);
    }
}

/// X67-18.11.4.3-18: after an Error the next status already shows Fault, the phase current is off and
/// ErrorCode01 shows the error (0x4200 or 0x3000).
#[test]
fn x67_18_11_4_3_18_fault_reaction_switches_off_and_shows_the_error() {
    for (error, code) in [("temperature", 0x4200), ("supply", 0x3000)] {
        let mut m = cruising();
        assert_eq!(milliamps(&m, 0), 1500);
        if error == "temperature" {
            m.set_temperature(90.0);
        } else {
            m.set_supply(50.0);
        }
        m.step();
        assert_state(&m, 0, FAULT);
        assert_eq!(m.status_word(0) & 0x035F, 0x0208);
        assert_eq!(milliamps(&m, 0), 0);
        assert_eq!(named(&m, "ErrorCode01"), code);
        let before = m.act_val(0);
        m.run(3);
        assert_eq!(m.act_val(0), before);
        assert_state(&m, 0, FAULT);
    }
}

/// X67-18.11.4.3-19: Fault reset leaves Fault only when no Error condition is present at that moment.
#[test]
fn x67_18_11_4_3_19_fault_reset_only_without_error_condition() {
    let mut m = Module::new();
    m.step();
    m.set_temperature(86.0);
    m.step();
    assert_state(&m, 0, FAULT);
    m.set_temperature(84.0);
    m.set_control(0, FAULT_RESET);
    m.step();
    assert_state(&m, 0, FAULT);
    assert_eq!(named(&m, "ErrorCode01"), 0x4200);
    m.set_control(0, 0);
    m.step();
    m.set_temperature(83.0);
    m.set_control(0, FAULT_RESET);
    m.step();
    assert_state(&m, 0, SWITCH_ON_DISABLED);
    assert_eq!(named(&m, "ErrorCode01"), 0);
}

/// X67-18.11.4.3-20: the Fault reset that leaves Fault resets every error and warning: a stall warning
/// latched before the overtemperature is gone too (ErrorCode01 = 0, SW bit 7 = 0). No warning condition of
/// the model can be present in Fault, where the motor is not powered.
#[test]
fn x67_18_11_4_3_20_fault_reset_clears_errors_and_warnings() {
    let mut m = running(20, 10);
    make_stall(&mut m, 0);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.run(2);
    assert_eq!(named(&m, "ErrorCode01"), 0xFF01);
    m.set_temperature(86.0);
    m.step();
    assert_state(&m, 0, FAULT);
    assert_eq!(named(&m, "ErrorCode01"), 0x4200);
    assert_ne!(m.status_word(0) & SW_WARNING, 0);
    m.set_temperature(60.0);
    m.set_control(0, FAULT_RESET | CW_STALL_DETECTION);
    m.step();
    assert_state(&m, 0, SWITCH_ON_DISABLED);
    assert_eq!(named(&m, "ErrorCode01"), 0);
    assert_eq!(m.status_word(0) & (SW_WARNING | 0x0008), 0);
}

// ===== 18.11.4.2 Status word states =====

/// X67-18.11.4.2-01: Not ready to switch on = (SW & 0x035F) == 0x0200, bit 5 = 0 (pick).
#[test]
fn x67_18_11_4_2_01_not_ready_to_switch_on_pattern() {
    let m = snapshot(State::NotReadyToSwitchOn);
    assert_eq!(m.status_word(0) & 0x035F, 0x0200);
    assert_eq!(m.status_word(0) & 0x0020, 0);
}

/// X67-18.11.4.2-02: Switch on disabled = (SW & 0x035F) == 0x0240, bit 5 = 0 (pick).
#[test]
fn x67_18_11_4_2_02_switch_on_disabled_pattern() {
    let m = snapshot(State::SwitchOnDisabled);
    assert_eq!(m.status_word(0) & 0x035F, 0x0240);
    assert_eq!(m.status_word(0) & 0x0020, 0);
}

/// X67-18.11.4.2-03: Ready to switch on = (SW & 0x037F) == 0x0221.
#[test]
fn x67_18_11_4_2_03_ready_to_switch_on_pattern() {
    let m = snapshot(State::ReadyToSwitchOn);
    assert_eq!(m.status_word(0) & 0x037F, 0x0221);
}

/// X67-18.11.4.2-04: Switched on = (SW & 0x037F) == 0x0233.
#[test]
fn x67_18_11_4_2_04_switched_on_pattern() {
    let m = snapshot(State::SwitchedOn);
    assert_eq!(m.status_word(0) & 0x037F, 0x0233);
}

/// X67-18.11.4.2-05: Operation enable = (SW & 0x037F) == 0x0237.
#[test]
fn x67_18_11_4_2_05_operation_enable_pattern() {
    let m = snapshot(State::OperationEnabled);
    assert_eq!(m.status_word(0) & 0x037F, 0x0237);
}

/// X67-18.11.4.2-06: Quick stop active = (SW & 0x037F) == 0x0217.
#[test]
fn x67_18_11_4_2_06_quick_stop_active_pattern() {
    let m = snapshot(State::QuickStopActive);
    assert_eq!(m.status_word(0) & 0x037F, 0x0217);
}

/// X67-18.11.4.2-07: Fault reaction active = (SW & 0x035F) == 0x020F; it is passed in the cycle of the
/// error, so it shows in the state trace.
#[test]
fn x67_18_11_4_2_07_fault_reaction_active_pattern() {
    let mut m = snapshot(State::OperationEnabled);
    m.set_supply(17.9);
    m.step();
    assert_eq!(m.axis(0).state_trace()[0], State::FaultReactionActive);
    assert_eq!(
        cia402::status_word(State::FaultReactionActive, 0) & 0x035F,
        FAULT_REACTION_ACTIVE
    );
}

/// X67-18.11.4.2-08: Fault = (SW & 0x035F) == 0x0208, bit 5 = 0 (pick).
#[test]
fn x67_18_11_4_2_08_fault_pattern() {
    let mut m = snapshot(State::SwitchedOn);
    m.set_temperature(85.0);
    m.step();
    assert_eq!(m.status_word(0) & 0x035F, 0x0208);
    assert_eq!(m.status_word(0) & 0x0020, 0);
}

/// X67-18.11.4.2-09: SW bit 4 (Voltage enabled) is 1 exactly in Switched on, Operation enable and Quick
/// stop active; during the start-up identification the motor is powered but SW keeps the Ready-to-switch-on
/// pattern with bit 4 = 0 (pick).
#[test]
fn x67_18_11_4_2_09_voltage_enabled_bit() {
    let mut identifications = 0;
    for (state, m) in tour() {
        let o = m.axis(0).observation();
        let expected = matches!(
            state,
            State::SwitchedOn | State::OperationEnabled | State::QuickStopActive
        );
        assert_eq!(
            m.status_word(0) & SW_VOLTAGE_ENABLED != 0,
            expected,
            "{state:?}"
        );
        if o.identifying {
            // Powered with the nominal current (50 %) while SW keeps the Ready-to-switch-on pattern.
            identifications += 1;
            assert!(o.powered);
            assert_eq!(milliamps(&m, 0), 1500);
            assert_eq!(m.status_word(0) & 0x037F, READY);
        } else {
            assert_eq!(o.powered, expected, "{state:?}");
        }
    }
    assert_eq!(identifications, 1);

    let mut m = snapshot(State::OperationEnabled);
    m.set_temperature(85.0);
    m.step();
    assert_state(&m, 0, FAULT);
    assert_eq!(m.status_word(0) & SW_VOLTAGE_ENABLED, 0);
}

/// X67-18.11.4.2-10: SW bit 7 is 1 while a warning is pending (overcurrent 0x2300) and a rising edge on
/// Warning reset clears it once no warning remains.
#[test]
fn x67_18_11_4_2_10_warning_bit() {
    let mut m = running(20, 10);
    m.axis_mut(0).motor.faults.short = true;
    m.step();
    assert_eq!(named(&m, "ErrorCode01"), 0x2300);
    assert_ne!(m.status_word(0) & SW_WARNING, 0);
    m.axis_mut(0).motor.faults.short = false;
    m.run(3);
    assert_ne!(m.status_word(0) & SW_WARNING, 0);
    m.set_control(0, ENABLE_OPERATION | CW_WARNING_RESET);
    m.step();
    assert_eq!(m.status_word(0) & SW_WARNING, 0);
    assert_eq!(named(&m, "ErrorCode01"), 0);
}

// ===== 18.11.4.1 Control word commands =====

/// X67-18.11.4.1-10: in Fault with 0x4200, a rising edge on bit 12 clears the latched stall warning (SW bit
/// 7) but leaves Fault and ErrorCode01 = 0x4200.
#[test]
fn x67_18_11_4_1_10_warning_reset_leaves_errors() {
    let mut m = running(20, 10);
    make_stall(&mut m, 0);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.run(2);
    assert_eq!(named(&m, "ErrorCode01"), 0xFF01);
    m.set_temperature(86.0);
    m.step();
    assert_state(&m, 0, FAULT);
    assert_ne!(m.status_word(0) & SW_WARNING, 0);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION | CW_WARNING_RESET);
    m.step();
    assert_state(&m, 0, FAULT);
    assert_eq!(named(&m, "ErrorCode01"), 0x4200);
    assert_eq!(m.status_word(0) & SW_WARNING, 0);
}

/// X67-18.11.4.1-11: a rising edge on bit 7 in Operation enable clears a pending stall warning without a
/// state change; with the stall condition still present the warning is latched again at once (pick).
#[test]
fn x67_18_11_4_1_11_fault_reset_clears_warnings_in_any_state() {
    let mut m = running(20, 10);
    make_stall(&mut m, 0);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.run(2);
    assert_eq!(named(&m, "ErrorCode01"), 0xFF01);

    let mut still = m.clone();
    still.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION | FAULT_RESET);
    still.step();
    assert_eq!(named(&still, "ErrorCode01"), 0xFF01);
    assert_state(&still, 0, OPERATION_ENABLE);

    m.axis_mut(0).motor.load = Load::Value(7);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION | FAULT_RESET);
    assert_eq!(step_increment(&mut m, 0), 20);
    assert_eq!(named(&m, "ErrorCode01"), 0);
    assert_eq!(m.status_word(0) & SW_WARNING, 0);
    assert_state(&m, 0, OPERATION_ENABLE);
    assert!(m.axis(0).state_trace().is_empty());
    // Bit 7 held at 1 is no command; back to Enable operation changes nothing either.
    m.step();
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    assert_eq!(increments(&mut m, 0, 2), [20, 20]);
    assert_state(&m, 0, OPERATION_ENABLE);
}

/// X67-18.11.4.1-12: bit 14 acts in Switch on disabled without a state transition: it swaps
/// AbsPos01ActVal (internal counter 5000) and AbsPos01ActValAcyclic (ABR counter 12).
#[test]
fn x67_18_11_4_1_12_other_bits_act_in_every_state() {
    let mut m = Module::new();
    operation_enable(&mut m, 0, 100, 10, 10);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 5000);
    m.run(70);
    m.set_control(0, DISABLE_VOLTAGE);
    m.step();
    assert_state(&m, 0, SWITCH_ON_DISABLED);
    quadrature(&mut m, 0, 12);
    m.step();
    assert_eq!(
        (
            named(&m, "AbsPos01ActVal"),
            named(&m, "AbsPos01ActValAcyclic")
        ),
        (5000, 12)
    );
    m.set_control(0, DISABLE_VOLTAGE | CW_SWAP_COUNTERS);
    m.step();
    assert_state(&m, 0, SWITCH_ON_DISABLED);
    assert!(m.axis(0).state_trace().is_empty());
    assert_eq!(
        (
            named(&m, "AbsPos01ActVal"),
            named(&m, "AbsPos01ActValAcyclic")
        ),
        (12, 5000)
    );
    m.set_control(0, DISABLE_VOLTAGE);
    m.step();
    assert_eq!(
        (
            named(&m, "AbsPos01ActVal"),
            named(&m, "AbsPos01ActValAcyclic")
        ),
        (5000, 12)
    );
}

// ===== 18.11.4 Two axes, 3 Technical data: two bridges =====

/// X67-18.11.4-01: each axis has its own state machine, control word and mode: axis 1 in Operation enable
/// leaves axis 2 in Switch on disabled; both run their own modes, and a quick stop of axis 1 leaves axis 2
/// running.
#[test]
fn x67_18_11_4_01_two_independent_state_machines() {
    let mut m = Module::new();
    operation_enable(&mut m, 0, 100, 10, 10);
    assert_state(&m, 1, SWITCH_ON_DISABLED);
    assert_eq!(named(&m, "MpGenStatus02") & 0x035F, 0x0240);

    operation_enable(&mut m, 1, 100, 20, 20);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 10_000);
    m.set_mode(1, modes::SPEED);
    m.set_abs_pos(1, -40);
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for _ in 0..3 {
        let (pa, pb) = (m.act_val(0), m.act_val(1));
        m.step();
        a.push(m.act_val(0) - pa);
        b.push(m.act_val(1) - pb);
    }
    assert_eq!(a, [10, 20, 30]);
    assert_eq!(b, [-20, -40, -40]);

    m.set_control(0, QUICK_STOP_FROM_ENABLED);
    m.step();
    assert_state(&m, 0, QUICK_STOP_ACTIVE);
    assert_state(&m, 1, OPERATION_ENABLE);
    assert_eq!(step_increment(&mut m, 1), -40);
}

/// X67-3-01: two bridges, one per axis: every per-axis register is a …01/…02 pair, and taking axis 1 through
/// all its states (and an axis-1 fault) leaves MpGenStatus02, AbsPos02ActVal and ErrorCode02 unchanged.
#[test]
fn x67_3_01_two_independent_bridges() {
    for reg in AxisReg::ALL {
        let (one, two) = (Register::Axis(0, reg).name(), Register::Axis(1, reg).name());
        let paired = match reg {
            AxisReg::HoldingCurrent | AxisReg::HoldingCurrentRead => {
                one.replace("03a", "06a") == two
            }
            AxisReg::NominalCurrent | AxisReg::NominalCurrentRead => {
                one.replace("04a", "07a") == two
            }
            AxisReg::MaximumCurrent | AxisReg::MaximumCurrentRead => {
                one.replace("05a", "08a") == two
            }
            _ => one.replace("01", "02") == two,
        };
        assert!(paired, "{one} / {two}");
        assert_ne!(
            Register::Axis(0, reg).info().number,
            Register::Axis(1, reg).info().number
        );
    }

    let mut m = Module::new();
    operation_enable(&mut m, 1, 100, 10, 10);
    m.set_mode(1, modes::SET_POSITION);
    m.set_abs_pos(1, 777);
    m.run(2);
    let axis2 = |m: &Module| {
        (
            named(m, "MpGenStatus02"),
            named(m, "AbsPos02ActVal"),
            named(m, "ErrorCode02"),
        )
    };
    let before = axis2(&m);
    assert_eq!(before.1, 777);
    assert_eq!(before.0 & 0x037F, i64::from(OPERATION_ENABLE));

    let mut seen = Vec::new();
    let mut cycle = |m: &mut Module, cw: u16, n: usize| {
        m.set_control(0, cw);
        for _ in 0..n {
            m.step();
            seen.push(m.axis(0).state());
            assert_eq!(axis2(m), before);
        }
    };
    set(&mut m, 0, AxisReg::MaxSpeedPos, 100);
    set(&mut m, 0, AxisReg::MaxAcc, 10);
    set(&mut m, 0, AxisReg::MaxDec, 10);
    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 50_000);
    cycle(&mut m, SHUTDOWN, 1);
    cycle(&mut m, SWITCH_ON, 41);
    cycle(&mut m, ENABLE_OPERATION, 20);
    cycle(&mut m, QUICK_STOP_FROM_ENABLED, 15);
    m.axis_mut(0).motor.faults.output_stage_overtemperature = true;
    cycle(&mut m, SHUTDOWN, 2);
    m.axis_mut(0).motor.faults.output_stage_overtemperature = false;
    cycle(&mut m, FAULT_RESET, 2);
    for s in [
        State::ReadyToSwitchOn,
        State::SwitchedOn,
        State::OperationEnabled,
        State::QuickStopActive,
        State::SwitchOnDisabled,
        State::Fault,
    ] {
        assert!(seen.contains(&s), "{s:?}");
    }
    assert_state(&m, 0, SWITCH_ON_DISABLED);
}

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

// ===== 18.6.3.6 / 18.6.3.7 / 18.11.3.7 Motor identification =====

/// X67-18.6.3.6-01: no MotorIdentTrigger register; ↑ MpGenControl01 bit 11 at a half-step standstill
/// measures axis 1 again (and only axis 1).
#[test]
fn x67_18_6_3_6_01_motor_id_trigger_is_control_bit_11() {
    assert_eq!(Register::from_name("MotorIdentTrigger"), None);
    let mut m = Module::new();
    for axis in 0..2 {
        set_currents(&mut m, axis, 20, 100, 80);
        switch_on(&mut m, axis);
    }
    assert_eq!(
        (
            named(&m, "Motoridentification01"),
            named(&m, "Motoridentification02")
        ),
        (143, 143)
    );
    for axis in 0..2 {
        m.axis_mut(axis).motor.params.inductance_mh = 6.0;
    }
    m.set_control(0, SWITCH_ON | CW_MOTOR_ID);
    m.step();
    assert_eq!(
        (
            named(&m, "Motoridentification01"),
            named(&m, "Motoridentification02")
        ),
        (286, 143)
    );
}

/// X67-18.6.3.7-01: there is no module configuration (ConfigOutput02, bit 11 normal/enhanced);
/// Motoridentification0n always has the enhanced meaning, the µs for a 1 A current rise: 3 mH and 1.5 Ω at
/// 24 V from 1 A to 3 A take 286 µs, i.e. 143 µs per ampere, on both axes.
#[test]
fn x67_18_6_3_7_01_always_the_enhanced_meaning() {
    assert_eq!(Register::from_name("ConfigOutput02"), None);
    let mut m = Module::new();
    for axis in 0..2 {
        set_currents(&mut m, axis, 20, 100, 80);
        switch_on(&mut m, axis);
    }
    assert_eq!(named(&m, "Motoridentification01"), 143);
    assert_eq!(named(&m, "Motoridentification02"), 143);
}

/// X67-18.11.3.7-01: Motoridentification01 is the time in µs for a 1 A current rise, from the operating
/// voltage and the winding: 143 µs for 3 mH / 1.5 Ω at 24 V and 3 A nominal; twice the inductance gives about
/// twice the value, a higher supply voltage a smaller one.
#[test]
fn x67_18_11_3_7_01_microseconds_per_ampere() {
    let base = first_identification(100, 24.0, |_| {});
    assert_eq!(base, 143);
    assert_eq!(
        Some(base as u16),
        expected_identification(3.0, 1.5, 24.0, 100)
    );
    assert_eq!(
        motor::identification_us(&MotorParams::default(), false, 24.0, 3000),
        Some(143)
    );

    let double = first_identification(100, 24.0, |p| p.inductance_mh = 6.0);
    assert_eq!(
        Some(double as u16),
        expected_identification(6.0, 1.5, 24.0, 100)
    );
    assert!((double - 2 * base).abs() <= 1, "{double} vs 2 × {base}");

    let higher_voltage = first_identification(100, 36.0, |_| {});
    assert_eq!(
        Some(higher_voltage as u16),
        expected_identification(3.0, 1.5, 36.0, 100)
    );
    assert_eq!(higher_voltage, 91);
    assert!(higher_voltage < base);
}

/// X67-18.11.3.7-02: 0 after power-up and as long as the measurement conditions are not met (no Switch on
/// yet, ↑ bit 11 without the motor powered).
#[test]
fn x67_18_11_3_7_02_zero_until_measured() {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 100, 80);
    assert_eq!(named(&m, "Motoridentification01"), 0);
    m.run(3);
    m.set_control(0, CW_MOTOR_ID);
    m.run(3);
    assert_eq!(named(&m, "Motoridentification01"), 0);
    assert_eq!(named(&m, "Motoridentification02"), 0);
}

/// X67-18.11.3.7-03: a normal motor gives a value in 1…32 767; an open winding, or a rise slower than
/// 32 767 µs (1 H), gives 65534.
#[test]
fn x67_18_11_3_7_03_valid_range_and_overflow() {
    for (mh, ohm) in [(3.0, 1.5), (0.5, 0.8), (20.0, 4.0)] {
        let v = first_identification(100, 24.0, |p| {
            p.inductance_mh = mh;
            p.resistance_ohm = ohm;
        });
        assert!((1..=32_767).contains(&v), "{mh} mH {ohm} Ω → {v}");
        assert_eq!(Some(v as u16), expected_identification(mh, ohm, 24.0, 100));
    }
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 100, 80);
    m.axis_mut(0).motor.faults.open_winding = true;
    switch_on(&mut m, 0);
    assert_eq!(named(&m, "Motoridentification01"), 65_534);
    let slow = first_identification(100, 24.0, |p| p.inductance_mh = 1000.0);
    assert_eq!(slow, 65_534);
}

/// X67-18.11.3.7-03, X67-18.11.3.7-01: the simulated measurement overflows (65534) when the nominal current is
/// never reached: the winding's current rises toward V/R, which with 1.5 Ω at 4.5 V is exactly the nominal
/// 3 A and at 4.0 V below it; at 5.0 V it is reached, in (2 ms)·ln(1/(1 − 0.3·i)) for i A, so from 1 A to
/// 3 A in 2 ms·(ln 10 − ln(1/0.7)) = 3.8918 ms, 1946 µs per ampere. A winding without inductance or
/// resistance, an open one, and no or a negative supply give 65534 as well.
#[test]
fn x67_18_11_3_7_03_overflow_when_the_nominal_current_is_not_reached() {
    let p = MotorParams::default();
    assert_eq!(motor::identification_us(&p, false, 5.0, 3000), Some(1946));
    for volts in [4.5, 4.0, 0.0, -24.0] {
        assert_eq!(
            motor::identification_us(&p, false, volts, 3000),
            Some(motor::IDENT_OVERFLOW),
            "{volts} V"
        );
    }
    assert_eq!(
        motor::identification_us(&p, true, 24.0, 3000),
        Some(motor::IDENT_OVERFLOW)
    );
    for (mh, ohm) in [(0.0, 1.5), (3.0, 0.0), (3.0, -1.5), (-3.0, 1.5)] {
        let p = MotorParams {
            inductance_mh: mh,
            resistance_ohm: ohm,
            ..MotorParams::default()
        };
        assert_eq!(
            motor::identification_us(&p, false, 24.0, 3000),
            Some(motor::IDENT_OVERFLOW),
            "{mh} mH, {ohm} Ω"
        );
    }
}

/// X67-18.11.3.7-04: ↑ CW bit 11 measures only at standstill in a half-step position (internal counter ≡ 0
/// mod 1024): at 2048 and 1024 the register is updated, at 2050 or while moving (even at 1024) it is not.
#[test]
fn x67_18_11_3_7_04_only_at_standstill_in_half_step_position() {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 100, 80);
    operation_enable(&mut m, 0, 128, 128, 128);
    m.set_mode(0, modes::POSITION);
    let trigger = |m: &mut Module, inductance: f64| {
        m.axis_mut(0).motor.params.inductance_mh = inductance;
        m.set_control(0, ENABLE_OPERATION | CW_MOTOR_ID);
        m.step();
        m.set_control(0, ENABLE_OPERATION);
        m.step();
        named(m, "Motoridentification01")
    };
    for (target, inductance, expected) in [
        (2048, 6.0, 286),
        (2050, 9.0, 286),
        (1024, 9.0, 429),
        (1536, 3.0, 429),
    ] {
        m.set_abs_pos(0, target);
        m.run(40);
        assert_eq!(m.act_val(0), target);
        assert_eq!(trigger(&mut m, inductance), expected, "at {target}");
    }

    // Moving at 128 microsteps/cycle: the counter passes 1024 + 8 · 128 = 2048 at the start of a cycle.
    m.set_abs_pos(0, 100_000);
    while m.act_val(0) != 2048 {
        m.step();
    }
    assert_eq!(m.axis(0).observation().ramp.speed, 128);
    assert_eq!(trigger(&mut m, 3.0), 429);
}

/// X67-18.11.3.7-05: the measurement runs by itself at the first Switch on: about 1 s later Switched on
/// with Motoridentification01 ≠ 0.
#[test]
fn x67_18_11_3_7_05_measured_at_first_switch_on() {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 80, 80);
    m.step();
    m.set_control(0, SHUTDOWN);
    m.step();
    m.set_control(0, SWITCH_ON);
    m.run(40);
    assert_state(&m, 0, READY);
    assert_eq!(named(&m, "Motoridentification01"), 0);
    m.step();
    assert_state(&m, 0, SWITCHED_ON);
    assert_eq!(
        Some(named(&m, "Motoridentification01") as u16),
        expected_identification(3.0, 1.5, 24.0, 80)
    );
    assert_eq!(named(&m, "Motoridentification01"), 139);
}

/// X67-18.11.3.7-06: the measurement runs from a third of the configured nominal current up to it, with the
/// nominal current flowing; with ConfigOutput04a < 50 (the range spans less than 1 A) the register stays 0.
#[test]
fn x67_18_11_3_7_06_measured_over_the_nominal_current_range() {
    assert_eq!(first_identification(50, 24.0, |_| {}), 133);
    assert_eq!(first_identification(100, 24.0, |_| {}), 143);
    assert_eq!(first_identification(49, 24.0, |_| {}), 0);
    assert_eq!(first_identification(0, 24.0, |_| {}), 0);

    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 60, 80);
    m.step();
    m.set_control(0, SHUTDOWN);
    m.step();
    m.set_control(0, SWITCH_ON);
    for _ in 0..40 {
        m.step();
        assert_eq!(level(&m, 0), Some(Level::Nominal));
        assert_eq!(milliamps(&m, 0), 1800);
    }
}

// ===== 18.11.1.1 / 18.11.1.2 / 18.11.2.1 / 3 Currents =====

/// X67-18.11.1.1-01: ConfigOutput03a…08a default to 0, accept 0…167 and refuse 168 with the SDO abort
/// 0x06090031, keeping their value.
#[test]
fn x67_18_11_1_1_01_current_range() {
    let mut m = Module::new();
    let pairs = [
        ("ConfigOutput03a", "ConfigOutput03aRead"),
        ("ConfigOutput04a", "ConfigOutput04aRead"),
        ("ConfigOutput05a", "ConfigOutput05aRead"),
        ("ConfigOutput06a", "ConfigOutput06aRead"),
        ("ConfigOutput07a", "ConfigOutput07aRead"),
        ("ConfigOutput08a", "ConfigOutput08aRead"),
    ];
    for (write, read) in pairs {
        assert_eq!(named(&m, read), 0);
        m.write_named(write, 167).unwrap();
        assert_eq!(named(&m, read), 167);
        let err = m.write_named(write, 168).unwrap_err();
        assert_eq!(
            err,
            RegisterError::TooHigh {
                register: Register::from_name(write).unwrap(),
                value: 168,
                max: 167
            }
        );
        assert_eq!(err.abort_code(), 0x0609_0031);
        assert_eq!(named(&m, read), 167);
        m.write_named(write, 0).unwrap();
        assert_eq!(named(&m, read), 0);
    }
}

/// X67-18.11.1.1-02: powered, the axis drives the holding current at standstill (Switched on and Operation
/// enable), the maximum current while the speed changes (braking included) and the nominal current while
/// cruising (after the 100 ms hold of X67-18.11.1.1-04).
#[test]
fn x67_18_11_1_1_02_level_follows_the_motion_phase() {
    use Level::{Holding as H, Maximum as X, Nominal as N};
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 50, 80);
    switch_on(&mut m, 0);
    m.step();
    assert_eq!((level(&m, 0), milliamps(&m, 0)), (Some(H), 600));
    m.set_control(0, ENABLE_OPERATION);
    set(&mut m, 0, AxisReg::MaxSpeedPos, 100);
    set(&mut m, 0, AxisReg::MaxAcc, 10);
    set(&mut m, 0, AxisReg::MaxDec, 10);
    m.step();
    assert_state(&m, 0, OPERATION_ENABLE);
    assert_eq!((level(&m, 0), milliamps(&m, 0)), (Some(H), 600));

    m.set_mode(0, modes::POSITION);
    m.set_abs_pos(0, 10_000);
    let mut levels = Vec::new();
    let mut speeds = Vec::new();
    for _ in 0..116 {
        m.step();
        levels.push(level(&m, 0).unwrap());
        speeds.push(m.axis(0).observation().ramp.speed);
    }
    // 10 cycles of acceleration, 90 at 100, 10 of braking (90 … 0), then standstill.
    let mut want_speeds: Vec<i32> = (1..=10).map(|k| 10 * k).collect();
    want_speeds.extend([100; 90]);
    want_speeds.extend((0..10).rev().map(|k| 10 * k));
    want_speeds.extend([0; 6]);
    assert_eq!(speeds, want_speeds);
    let mut want: Vec<Level> = vec![X; 10];
    want.extend([X; 4]);
    want.extend([N; 86]);
    want.extend([X; 10]);
    want.extend([X; 4]);
    want.extend([H; 2]);
    assert_eq!(levels, want);
    assert_eq!(m.act_val(0), 10_000);
    assert_eq!(milliamps(&m, 0), 600);
}

/// X67-18.11.1.1-03: homing by referencing during stall (RefConfig01 = −127) never uses the maximum
/// current, also while it accelerates; homing on the R input does.
#[test]
fn x67_18_11_1_1_03_stall_homing_uses_nominal_current() {
    for (ref_config, maximum_seen) in [(-127, false), (-125, true)] {
        let mut m = Module::new();
        set_currents(&mut m, 0, 20, 50, 80);
        operation_enable(&mut m, 0, 0, 5, 5);
        set(&mut m, 0, AxisReg::RefConfig, ref_config);
        set(&mut m, 0, AxisReg::RefSpeed, 50);
        m.set_mode(0, modes::HOMING_POSITIVE);
        let mut levels = Vec::new();
        let mut speeds = Vec::new();
        for _ in 0..20 {
            m.step();
            levels.push(level(&m, 0).unwrap());
            speeds.push(m.axis(0).observation().ramp.speed);
        }
        assert_eq!(speeds[..11], [5, 10, 15, 20, 25, 30, 35, 40, 45, 50, 50]);
        assert_eq!(
            levels.contains(&Level::Maximum),
            maximum_seen,
            "{ref_config}"
        );
        if !maximum_seen {
            assert!(levels.iter().all(|l| *l == Level::Nominal));
        }
    }
}

/// X67-18.11.1.1-04: a weaker level follows a stronger one only after 100 ms: 4 cycles at 25 ms and 10
/// cycles at 10 ms of maximum current after the acceleration, and the same before holding after a stop.
#[test]
fn x67_18_11_1_1_04_stronger_level_kept_for_100_ms() {
    for (general_config, hold_cycles) in [(0, 4usize), (0b010, 10)] {
        let mut m = Module::new();
        m.write_named("GeneralConfig01", general_config).unwrap();
        set_currents(&mut m, 0, 20, 50, 80);
        operation_enable(&mut m, 0, 0, 50, 50);
        m.set_mode(0, modes::SPEED);
        m.set_abs_pos(0, 100);
        m.run(2);
        assert_eq!(m.axis(0).observation().ramp.speed, 100);
        assert_eq!(level(&m, 0), Some(Level::Maximum));
        for _ in 0..hold_cycles {
            m.step();
            assert_eq!(level(&m, 0), Some(Level::Maximum));
        }
        m.step();
        assert_eq!(
            (level(&m, 0), milliamps(&m, 0)),
            (Some(Level::Nominal), 1500)
        );

        m.set_abs_pos(0, 0);
        m.run(2);
        assert_eq!(m.axis(0).observation().ramp.speed, 0);
        for _ in 0..hold_cycles {
            m.step();
            assert_eq!(level(&m, 0), Some(Level::Maximum));
        }
        m.step();
        assert_eq!(
            (level(&m, 0), milliamps(&m, 0)),
            (Some(Level::Holding), 600)
        );
    }
}

/// X67-18.11.1.1-05: the stronger level is the category, not the percentage: holding 80 %, nominal 40 %,
/// maximum 30 % are accepted; after the acceleration the 30 % maximum is kept 100 ms before the 40 % nominal,
/// and after the stop before the 80 % holding.
#[test]
fn x67_18_11_1_1_05_priority_by_category() {
    let mut m = Module::new();
    set_currents(&mut m, 0, 80, 40, 30);
    assert_eq!(
        (
            named(&m, "ConfigOutput03aRead"),
            named(&m, "ConfigOutput04aRead"),
            named(&m, "ConfigOutput05aRead")
        ),
        (80, 40, 30)
    );
    operation_enable(&mut m, 0, 0, 50, 50);
    assert_eq!(milliamps(&m, 0), 2400);
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, 100);
    let mut ma = Vec::new();
    for _ in 0..7 {
        m.step();
        ma.push(milliamps(&m, 0));
    }
    assert_eq!(ma, [900, 900, 900, 900, 900, 900, 1200]);
    m.set_abs_pos(0, 0);
    let mut ma = Vec::new();
    for _ in 0..7 {
        m.step();
        ma.push(milliamps(&m, 0));
    }
    assert_eq!(ma, [900, 900, 900, 900, 900, 900, 2400]);
}

/// X67-18.11.1.2-01: with FullStepThreshold01 = 200 the axis runs in microsteps at 199 microsteps/cycle and
/// in full steps at 200 and above; 65535 keeps it in microsteps.
#[test]
fn x67_18_11_1_2_01_full_step_threshold() {
    for (threshold, speed, full) in [
        (200, 199, false),
        (200, 200, true),
        (200, 5000, true),
        (200, -200, true),
        (65_535, 60_000, false),
    ] {
        let mut m = running(speed, 65_535);
        set(&mut m, 0, AxisReg::FullStepThreshold, threshold);
        m.step();
        let c = m.axis(0).observation().current.unwrap();
        assert_eq!(c.full_step, full, "threshold {threshold} at {speed}");
    }
}

/// X67-18.11.1.2-02: FullStepThreshold01 defaults to 0, which keeps the axis in microsteps at every speed.
#[test]
fn x67_18_11_1_2_02_default_threshold_never_full_step() {
    assert_eq!(named(&Module::new(), "FullStepThreshold01"), 0);
    for speed in [1, 200, 60_000] {
        let m = running(speed, 65_535);
        assert!(
            !m.axis(0).observation().current.unwrap().full_step,
            "{speed}"
        );
    }
}

/// X67-18.11.2.1-01: ConfigOutput03aRead…08aRead return the value last accepted, 0 before any write.
#[test]
fn x67_18_11_2_1_01_current_read_back() {
    let mut m = Module::new();
    assert_eq!(named(&m, "ConfigOutput07aRead"), 0);
    m.write_named("ConfigOutput07a", 120).unwrap();
    assert_eq!(named(&m, "ConfigOutput07aRead"), 120);
    assert!(m.write_named("ConfigOutput07a", 200).is_err());
    assert_eq!(named(&m, "ConfigOutput07aRead"), 120);
    for name in [
        "ConfigOutput03aRead",
        "ConfigOutput04aRead",
        "ConfigOutput05aRead",
        "ConfigOutput06aRead",
        "ConfigOutput08aRead",
    ] {
        assert_eq!(named(&m, name), 0, "{name}");
    }
}

/// X67-3-02: 1 % = 30 mA: ConfigOutput04a = 50 at constant speed gives a phase current of 1.50 A; 100 %
/// gives 3 A and 167 % 5.01 A.
#[test]
fn x67_3_02_current_resolution() {
    for (nominal, ma) in [(50, 1500), (100, 3000), (167, 5010), (1, 30)] {
        let mut m = running(40, 10);
        set(&mut m, 0, AxisReg::NominalCurrent, nominal);
        m.run(5);
        assert_eq!(level(&m, 0), Some(Level::Nominal));
        assert_eq!(milliamps(&m, 0), ma, "{nominal} %");
    }
}

/// X67-3-03: more than 3 A for more than 2 s (an acceleration at 167 % of 81 cycles) writes a diagnostic,
/// 2.0 s does not; no register changes.
#[test]
fn x67_3_03_axis_current_rating_over_two_seconds() {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 50, 167);
    operation_enable(&mut m, 0, 0, 1, 1);
    assert!(m.take_diagnostics().is_empty());
    m.set_mode(0, modes::SPEED);
    m.set_abs_pos(0, 200);
    for _ in 0..80 {
        m.step();
        assert_eq!(milliamps(&m, 0), 5010);
    }
    assert!(m.take_diagnostics().is_empty());
    m.step();
    let diagnostics = m.take_diagnostics();
    assert_eq!(diagnostics.len(), 1);
    assert!(matches!(
        diagnostics[0],
        Diagnostic::AxisOverCurrentTooLong { axis: 0, .. }
    ));
    assert_eq!(m.error_code(0), 0);
    assert_eq!(m.status_word(0) & 0x03FF, OPERATION_ENABLE);
    m.run(50);
    assert!(m.take_diagnostics().is_empty());
}

/// X67-3-03: above 3 A again less than 10 s after the last time above 3 A writes a diagnostic; after 10 s
/// at no more than 3 A it does not.
#[test]
fn x67_3_03_axis_current_recovery_time() {
    for (rest_cycles, complaint) in [(399, true), (400, false)] {
        let mut m = Module::new();
        set_currents(&mut m, 0, 167, 0, 0);
        switch_on(&mut m, 0);
        m.run(10);
        assert_eq!(milliamps(&m, 0), 5010);
        m.set_control(0, SHUTDOWN);
        m.run(rest_cycles);
        assert_eq!(milliamps(&m, 0), 0);
        m.take_diagnostics();
        m.set_control(0, SWITCH_ON);
        m.step();
        assert_eq!(milliamps(&m, 0), 5010);
        let d = m.take_diagnostics();
        assert_eq!(
            d.iter()
                .any(|d| matches!(d, Diagnostic::AxisRecoveryTooShort { axis: 0, .. })),
            complaint,
            "{rest_cycles} cycles: {d:?}"
        );
    }
}

/// X67-3-04: both axes together above 8 A (3.00 A + 5.01 A) write a module diagnostic; 3.00 A + 4.98 A do
/// not. No register changes.
#[test]
fn x67_3_04_module_current_rating() {
    for (second, complaint) in [(167, true), (166, false)] {
        let mut m = Module::new();
        set_currents(&mut m, 0, 100, 0, 0);
        set_currents(&mut m, 1, second, 0, 0);
        switch_on(&mut m, 0);
        switch_on(&mut m, 1);
        m.step();
        assert_eq!(
            milliamps(&m, 0) + milliamps(&m, 1),
            3000 + 30 * second as u32
        );
        let d = m.take_diagnostics();
        let module: Vec<_> = d
            .iter()
            .filter(|d| matches!(d, Diagnostic::ModuleOverCurrent { .. }))
            .collect();
        if complaint {
            assert_eq!(module.len(), 1, "{d:?}");
            assert!(matches!(
                module[0],
                Diagnostic::ModuleOverCurrent {
                    milliamps: 8010,
                    ..
                }
            ));
        } else {
            assert!(module.is_empty(), "{d:?}");
        }
        for axis in 0..2 {
            assert_eq!(m.error_code(axis), 0);
            assert_state(&m, axis, SWITCHED_ON);
        }
    }
}

/// X67-3-03: exactly 3 A is not above the rating: holding current 100 % (3.00 A) for 3 s writes no
/// diagnostic.
#[test]
fn x67_3_03_three_amperes_are_within_the_rating() {
    let mut m = Module::new();
    set_currents(&mut m, 0, 100, 0, 0);
    switch_on(&mut m, 0);
    m.take_diagnostics();
    for _ in 0..120 {
        m.step();
        assert_eq!(milliamps(&m, 0), 3000);
    }
    assert_eq!(m.take_diagnostics(), []);
}

/// X67-3-04: the module diagnostic is written once, in the first cycle of a period above 8 A, and again
/// only for a new period: both axes holding at 3.00 A (6 A), then axis 2 at 5.01 A (8.01 A) for 10 cycles,
/// back to 3.00 A for one, and at 5.01 A again. That second period is also above 3 A again 25 ms after the
/// first (X67-3-03).
#[test]
fn x67_3_04_module_diagnostic_once_per_period() {
    let mut m = Module::new();
    for axis in 0..2 {
        set_currents(&mut m, axis, 100, 0, 0);
        switch_on(&mut m, axis);
    }
    m.step();
    assert_eq!(milliamps(&m, 0) + milliamps(&m, 1), 6000);
    assert_eq!(m.take_diagnostics(), []);

    set(&mut m, 1, AxisReg::HoldingCurrent, 167);
    m.step();
    let first = m.time_ms();
    assert_eq!(milliamps(&m, 0) + milliamps(&m, 1), 8010);
    assert_eq!(
        m.take_diagnostics(),
        [Diagnostic::ModuleOverCurrent {
            milliamps: 8010,
            at_ms: first
        }]
    );
    for _ in 0..10 {
        m.step();
        assert_eq!(m.take_diagnostics(), [], "the same period");
    }

    set(&mut m, 1, AxisReg::HoldingCurrent, 100);
    m.step();
    assert_eq!(m.take_diagnostics(), []);
    set(&mut m, 1, AxisReg::HoldingCurrent, 167);
    m.step();
    let again = m.time_ms();
    assert_eq!(
        m.take_diagnostics(),
        [
            Diagnostic::AxisRecoveryTooShort {
                axis: 1,
                at_ms: again
            },
            Diagnostic::ModuleOverCurrent {
                milliamps: 8010,
                at_ms: again
            }
        ]
    );
}

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

// ===== 18.11.3.5, 18.11.3.8, 18.11.3.11, 18.11.3.12 Read registers =====

/// X67-18.11.3.5-01: SW bit 8 is reserved and 0 in every state.
#[test]
fn x67_18_11_3_5_01_bit_8_always_0() {
    for sw in status_words_of_every_state() {
        assert_eq!(sw & 0x0100, 0, "{sw:#06x}");
    }
}

/// X67-18.11.3.5-02: SW bit 9 (Remote) is 1 in every state, from the first status on.
#[test]
fn x67_18_11_3_5_02_remote_always_1() {
    assert_eq!(Module::new().status_word(0) & 0x0200, 0x0200);
    for sw in status_words_of_every_state() {
        assert_eq!(sw & 0x0200, 0x0200, "{sw:#06x}");
    }
}

/// X67-18.11.3.5-05: SW bits 13–15 carry the load value with bit 13 as LSB when StallDetectConfig01 bit 7
/// = 1: load 6 → 110, load 1 → 001; with bit 7 = 0 → 000.
#[test]
fn x67_18_11_3_5_05_load_bits() {
    let base = running(50, 10);
    for (config, load, bits) in [(0x80, 6, 0b110), (0x80, 1, 0b001), (0x00, 6, 0)] {
        let mut m = base.clone();
        set(&mut m, 0, AxisReg::StallDetectConfig, config);
        m.axis_mut(0).motor.load = Load::Value(load);
        m.run(2);
        assert_eq!(
            m.status_word(0) & 0xE000,
            bits << 13,
            "{config:#04x} {load}"
        );
    }
}

/// X67-18.11.3.8-01: Temperature is the module temperature in °C, truncated toward zero, as a SINT.
#[test]
fn x67_18_11_3_8_01_temperature_register() {
    let mut m = Module::new();
    assert_eq!(named(&m, "Temperature"), 25);
    for (celsius, register) in [
        (47.6, 47),
        (47.0, 47),
        (-3.7, -3),
        (0.4, 0),
        (126.9, 126),
        (300.0, 127),
        (-300.0, -128),
    ] {
        m.set_temperature(celsius);
        m.step();
        assert_eq!(named(&m, "Temperature"), register, "{celsius} °C");
    }
}

/// X67-18.11.3.11-01: ControlReadback0n returns the last control word received, all 16 bits.
#[test]
fn x67_18_11_3_11_01_control_read_back() {
    let mut m = Module::new();
    m.step();
    assert_eq!(named(&m, "ControlReadback01"), 0);
    m.set_control(0, 0x820F);
    m.step();
    assert_eq!(named(&m, "ControlReadback01"), 0x820F);
    assert_eq!(named(&m, "ControlReadback02"), 0);
    m.set_control(1, 0xFFFF);
    m.step();
    assert_eq!(named(&m, "ControlReadback02"), 0xFFFF);
    assert_eq!(named(&m, "ControlReadback01"), 0x820F);
}

/// X67-18.11.3.12-01: ModeReadback0n returns the last mode received, as a SINT.
#[test]
fn x67_18_11_3_12_01_mode_read_back() {
    let mut m = Module::new();
    m.set_mode(0, modes::FIXED_A);
    m.set_mode(1, modes::SPEED);
    m.step();
    assert_eq!(named(&m, "ModeReadback01"), -125);
    assert_eq!((named(&m, "ModeReadback01") as i8) as u8, 0x83);
    assert_eq!(named(&m, "ModeReadback02"), 2);
    m.set_mode(0, 5);
    m.step();
    assert_eq!(named(&m, "ModeReadback01"), 5);
}

// ===== 18.5.2 CAN objects =====

/// X67-18.5.2-02, X67-18.5-21…-26: object 1 carries axis 1 and the inputs: output bytes 0–3 AbsPos01,
/// 4–5 MpGenControl01, 6 MpGenMode01; input bytes 0–3 AbsPos01ActVal, 4–5 MpGenStatus01, 6 InputStatus.
#[test]
fn x67_18_5_2_02_object_1() {
    let mut m = Module::new();
    m.step();
    m.output_object(0, [0x78, 0x56, 0x34, 0x12, 0x06, 0x00, 0xFE, 0x00]);
    m.step();
    assert_eq!(named(&m, "AbsPos01"), 0x1234_5678);
    assert_eq!(named(&m, "ControlReadback01"), 0x0006);
    assert_eq!(named(&m, "ModeReadback01"), -2);
    assert_state(&m, 0, READY);
    assert_eq!(
        (named(&m, "AbsPos02"), named(&m, "ControlReadback02")),
        (0, 0)
    );

    m.set_input(2, true);
    m.set_input(5, true);
    m.step();
    let sw = m.status_word(0).to_le_bytes();
    let act = m.act_val(0).to_le_bytes();
    assert_eq!(
        m.input_object(0),
        [act[0], act[1], act[2], act[3], sw[0], sw[1], 0x12, 0x00]
    );
    assert_eq!(m.input_object(0)[4..6], [0x21, 0x06]);
}

/// X67-18.5.2-03: object 2 carries axis 2 at byte = offset − 8; input bytes 6–7 of object 2 are unused.
#[test]
fn x67_18_5_2_03_object_2() {
    let mut m = Module::new();
    set(&mut m, 1, AxisReg::MaxSpeedPos, 100);
    set(&mut m, 1, AxisReg::MaxAcc, 10);
    set(&mut m, 1, AxisReg::MaxDec, 10);
    m.step();
    m.output_object(1, [0x06, 0x00, 0x00, 0x00, 0x06, 0x00, 0x7F, 0x00]);
    m.step();
    assert_eq!(named(&m, "AbsPos02"), 6);
    assert_eq!(named(&m, "ControlReadback02"), 6);
    assert_eq!(named(&m, "ModeReadback02"), 127);
    assert_state(&m, 1, READY);
    assert_state(&m, 0, SWITCH_ON_DISABLED);

    switch_on(&mut m, 1);
    m.output_object(1, [0xE8, 0x03, 0x00, 0x00, 0x0F, 0x00, 0x01, 0x00]);
    m.set_input(6, true);
    m.run(30);
    assert_eq!(m.act_val(1), 1000);
    let sw = m.status_word(1).to_le_bytes();
    assert_eq!(
        m.input_object(1),
        [0xE8, 0x03, 0x00, 0x00, sw[0], sw[1], 0, 0]
    );
    assert_eq!(sw[0] & 0x7F, 0x37);
    assert_eq!(m.input_object(0)[6], 0x20);
}

/// X67-18.5.2-04: byte 7 of the output objects is ignored, and the unused input bytes are 0.
#[test]
fn x67_18_5_2_04_unused_bytes() {
    let mut a = Module::new();
    let mut b = Module::new();
    a.step();
    b.step();
    a.output_object(0, [0x10, 0x00, 0x00, 0x00, 0x06, 0x00, 0x01, 0x00]);
    b.output_object(0, [0x10, 0x00, 0x00, 0x00, 0x06, 0x00, 0x01, 0xFF]);
    a.output_object(1, [0x20, 0x00, 0x00, 0x00, 0x06, 0x00, 0x02, 0x00]);
    b.output_object(1, [0x20, 0x00, 0x00, 0x00, 0x06, 0x00, 0x02, 0xA5]);
    a.step();
    b.step();
    for reg in Register::all() {
        assert_eq!(a.read(reg), b.read(reg), "{reg}");
    }
    for k in 1..=6 {
        b.set_input(k, true);
    }
    b.step();
    assert_eq!(b.input_object(0)[7], 0);
    assert_eq!(b.input_object(1)[6..8], [0, 0]);
}

/// X67-18.5.2-05: multi-byte registers are little-endian: AbsPos01ActVal = 0x00012345 → 45 23 01 00.
#[test]
fn x67_18_5_2_05_little_endian() {
    let mut m = Module::new();
    operation_enable(&mut m, 0, 100, 10, 10);
    m.set_mode(0, modes::SET_POSITION);
    m.set_abs_pos(0, 0x0001_2345);
    m.run(2);
    assert_eq!(named(&m, "AbsPos01ActVal"), 0x0001_2345);
    assert_eq!(m.input_object(0)[0..4], [0x45, 0x23, 0x01, 0x00]);
    assert_eq!(m.input_object(0)[4..6], [0x37, 0x06]);
    m.output_object(0, [0x00, 0x00, 0x01, 0x00, 0x0F, 0x00, 0x01, 0x00]);
    m.step();
    assert_eq!(named(&m, "AbsPos01"), 0x0001_0000);
}

// ===== 18.5 Register table =====

/// X67-18.5-01: the model has exactly the 71 registers of the 18.5 table, and none of the registers that
/// exist only in function models 0 and 1.
#[test]
fn x67_18_5_01_exactly_the_ramp_registers() {
    let all: Vec<Register> = Register::all().collect();
    assert_eq!(all.len(), 71);
    let mut names: Vec<&str> = all.iter().map(|r| r.name()).collect();
    let mut expected: Vec<&str> = TABLE.iter().map(|r| r.0).collect();
    names.sort_unstable();
    expected.sort_unstable();
    assert_eq!(names, expected);
    assert_rows(&expected);
    for name in [
        "ConfigOutput01",
        "ConfigOutput02",
        "ConfigOutput09",
        "ConfigOutput16",
        "Motor1Step0",
        "Motor2Step3",
        "SetCounter01",
        "StatusInput",
        "MotorLoad",
        "MotorIdentTrigger",
        "Position1Sync",
        "GeneralConfig02",
        "MotorSettlingTime",
        "LifeCnt",
    ] {
        assert_eq!(Register::from_name(name), None, "{name}");
    }
}

/// X67-18.5-02: exactly the 11 registers with an offset are cyclic; all others are acyclic.
#[test]
fn x67_18_5_02_cyclic_registers() {
    let mut cyclic: Vec<&str> = Register::all()
        .filter(|r| matches!(r.info().access, Access::CyclicIn | Access::CyclicOut))
        .map(|r| r.name())
        .collect();
    cyclic.sort_unstable();
    assert_eq!(
        cyclic,
        [
            "AbsPos01",
            "AbsPos01ActVal",
            "AbsPos02",
            "AbsPos02ActVal",
            "InputStatus",
            "MpGenControl01",
            "MpGenControl02",
            "MpGenMode01",
            "MpGenMode02",
            "MpGenStatus01",
            "MpGenStatus02"
        ]
    );
}

/// X67-18.5-03: configuration registers and cyclic outputs are written by the master; read-back, acyclic
/// read and cyclic input registers refuse a write with `ReadOnly` (SDO abort 0x06010002) and keep their value.
#[test]
fn x67_18_5_03_access() {
    let mut m = Module::new();
    m.step();
    for reg in Register::all() {
        let info = reg.info();
        let before = m.read(reg);
        // A RefConfig value must be a listed one to be taken (X67-18.11.1.11-05).
        let value = if info.ty == RegType::Sint { -126 } else { 1 };
        let result = m.write(reg, value);
        match info.access {
            Access::Config | Access::CyclicOut => {
                assert_eq!(result, Ok(()), "{reg}");
                assert_eq!(m.read(reg), value, "{reg}");
            }
            Access::ReadAcyclic | Access::CyclicIn => {
                let err = result.unwrap_err();
                assert_eq!(err, RegisterError::ReadOnly(reg));
                assert_eq!(err.abort_code(), 0x0601_0002);
                assert_eq!(m.read(reg), before, "{reg}");
            }
        }
    }
    assert_eq!(
        Register::all()
            .filter(|r| r.info().access == Access::Config)
            .count(),
        39
    );
    assert_eq!(
        Register::all()
            .filter(|r| r.info().access == Access::ReadAcyclic)
            .count(),
        21
    );
}

/// X67-18.5-03: a register the master cannot write answers `ReadOnly` (SDO abort 0x06010002) whatever the
/// value, also one outside its type's range, which a writable register would refuse as too high or too low;
/// the refusal names the register by its seed name.
#[test]
fn x67_18_5_03_read_only_before_the_range() {
    let mut m = Module::new();
    m.step();
    for (reg, value) in [
        (Register::Axis(0, AxisReg::ActVal), 1i64 << 40),
        (Register::Axis(1, AxisReg::Status), -1),
        (Register::Module(ModuleReg::InputStatus), 300),
        (Register::Axis(0, AxisReg::ErrorCode), 70_000),
    ] {
        let err = m.write(reg, value).unwrap_err();
        assert_eq!(err, RegisterError::ReadOnly(reg), "{reg} = {value}");
        assert_eq!(err.abort_code(), 0x0601_0002);
    }
    let act_val = Register::Axis(0, AxisReg::ActVal);
    assert_eq!(act_val.to_string(), "AbsPos01ActVal");
    assert_eq!(
        RegisterError::ReadOnly(act_val).to_string(),
        "AbsPos01ActVal is read-only"
    );
    let max_acc = Register::Axis(1, AxisReg::MaxAcc);
    assert_eq!(
        m.write(max_acc, 70_000).unwrap_err().to_string(),
        "70000 is above the range of MaxAcc02 (at most 65535)"
    );
}

/// X67-18.5-04: DINT, UINT, INT, SINT and USINT are 4, 2, 2, 1 and 1 bytes with their value ranges; a value
/// outside a register's type is refused (0x06090031 above, 0x06090032 below) and the register keeps its
/// value.
#[test]
fn x67_18_5_04_data_types() {
    assert_eq!(
        [Dint, Uint, Int, Sint, Usint].map(RegType::size),
        [4, 2, 2, 1, 1]
    );
    assert_eq!(Dint.range(), (-2_147_483_648, 2_147_483_647));
    assert_eq!(Uint.range(), (0, 65_535));
    assert_eq!(Int.range(), (-32_768, 32_767));
    assert_eq!(Sint.range(), (-128, 127));
    assert_eq!(Usint.range(), (0, 255));

    let mut m = Module::new();
    for (name, low, high, ok) in [
        ("MaxAcc01", -1, 65_536, 65_535),
        ("RevLoop02", -32_769, 32_768, -32_768),
        ("FixedPos01a", -2_147_483_649, 2_147_483_648, -2_147_483_648),
        ("StallDetectConfig02", -1, 256, 255),
        ("GeneralConfig01", -1, 256, 6),
        ("MpGenMode01", -129, 128, -128),
        ("MpGenControl02", -1, 65_536, 65_535),
    ] {
        m.write_named(name, ok).unwrap();
        let reg = Register::from_name(name).unwrap();
        let (min, max) = reg.info().ty.range();
        let high_err = m.write_named(name, high).unwrap_err();
        assert_eq!(
            high_err,
            RegisterError::TooHigh {
                register: reg,
                value: high,
                max
            }
        );
        assert_eq!(high_err.abort_code(), 0x0609_0031);
        let low_err = m.write_named(name, low).unwrap_err();
        assert_eq!(
            low_err,
            RegisterError::TooLow {
                register: reg,
                value: low,
                min
            }
        );
        assert_eq!(low_err.abort_code(), 0x0609_0032);
        assert_eq!(m.read_named(name), ok, "{name}");
    }
}

/// X67-18.5-05: the current registers are USINT configuration registers 48–50 (axis 1) and 112–114
/// (axis 2); above 167 they refuse the write with 0x06090031.
#[test]
fn x67_18_5_05_current_registers() {
    assert_rows(&[
        "ConfigOutput03a",
        "ConfigOutput04a",
        "ConfigOutput05a",
        "ConfigOutput06a",
        "ConfigOutput07a",
        "ConfigOutput08a",
    ]);
    assert_eq!(
        Register::from_name("ConfigOutput06a"),
        Some(Register::Axis(1, AxisReg::HoldingCurrent))
    );
    let mut m = Module::new();
    m.write_named("ConfigOutput08a", 100).unwrap();
    let err = m.write_named("ConfigOutput08a", 200).unwrap_err();
    assert_eq!(err.abort_code(), 0x0609_0031);
    assert_eq!(named(&m, "ConfigOutput08aRead"), 100);
}

/// X67-18.5-06: FullStepThreshold01/02 are registers 72/136, UINT, written acyclically.
#[test]
fn x67_18_5_06_full_step_threshold_registers() {
    assert_rows(&["FullStepThreshold01", "FullStepThreshold02"]);
}

/// X67-18.5-07: MaxSpeed01pos/02pos are registers 52/116, UINT, written acyclically.
#[test]
fn x67_18_5_07_max_speed_registers() {
    assert_rows(&["MaxSpeed01pos", "MaxSpeed02pos"]);
}

/// X67-18.5-08: MaxAcc01/MaxDec01 are 54/56 and MaxAcc02/MaxDec02 118/120, UINT, written acyclically.
#[test]
fn x67_18_5_08_acceleration_registers() {
    assert_rows(&["MaxAcc01", "MaxDec01", "MaxAcc02", "MaxDec02"]);
}

/// X67-18.5-09: RevLoop01/02 are registers 58/122, INT, written acyclically.
#[test]
fn x67_18_5_09_reversing_loop_registers() {
    assert_rows(&["RevLoop01", "RevLoop02"]);
    let mut m = Module::new();
    m.write_named("RevLoop01", -500).unwrap();
    assert_eq!(named(&m, "RevLoop01"), -500);
}

/// X67-18.5-10: FixedPos01a/01b are 60/64 and FixedPos02a/02b 124/128, DINT, written acyclically.
#[test]
fn x67_18_5_10_fixed_position_registers() {
    assert_rows(&["FixedPos01a", "FixedPos01b", "FixedPos02a", "FixedPos02b"]);
}

/// X67-18.5-11: RefSpeed01/02 are registers 68/132, UINT, written acyclically.
#[test]
fn x67_18_5_11_homing_speed_registers() {
    assert_rows(&["RefSpeed01", "RefSpeed02"]);
}

/// X67-18.5-12: RefConfig01/02 are registers 70/134, SINT, written acyclically.
#[test]
fn x67_18_5_12_homing_configuration_registers() {
    assert_rows(&["RefConfig01", "RefConfig02"]);
    let mut m = Module::new();
    m.write_named("RefConfig02", -126).unwrap();
    assert_eq!(named(&m, "RefConfig02"), -126);
}

/// X67-18.5-13: StallDetectConfig01/02 are registers 51/115, USINT, written acyclically.
#[test]
fn x67_18_5_13_stall_detection_registers() {
    assert_rows(&["StallDetectConfig01", "StallDetectConfig02"]);
}

/// X67-18.5-14: StallRecognitionDelay01/02 are registers 74/138, USINT, written acyclically.
#[test]
fn x67_18_5_14_stall_recognition_delay_registers() {
    assert_rows(&["StallRecognitionDelay01", "StallRecognitionDelay02"]);
}

/// X67-18.5-15: JoltTime01/02 are registers 75/139, USINT, written acyclically.
#[test]
fn x67_18_5_15_jolt_time_registers() {
    assert_rows(&["JoltTime01", "JoltTime02"]);
}

/// X67-18.5-16: StallDetectMinSpeed01/02 are registers 78/142, UINT, written acyclically.
#[test]
fn x67_18_5_16_minimum_stall_speed_registers() {
    assert_rows(&["StallDetectMinSpeed01", "StallDetectMinSpeed02"]);
}

/// X67-18.5-17: GeneralConfig01 is register 304, USINT, written acyclically; there is no GeneralConfig02.
#[test]
fn x67_18_5_17_general_configuration_register() {
    assert_rows(&["GeneralConfig01"]);
    assert_eq!(
        Register::from_name("GeneralConfig01"),
        Some(Register::Module(ModuleReg::GeneralConfig))
    );
    assert_eq!(Register::from_name("GeneralConfig02"), None);
}

/// X67-18.5-18: LimitSwitchConfig01/02 are registers 306/308, USINT, written acyclically.
#[test]
fn x67_18_5_18_limit_switch_registers() {
    assert_rows(&["LimitSwitchConfig01", "LimitSwitchConfig02"]);
}

/// X67-18.5-19: PositionLimitMin01/Max01 are 380/384 and Min02/Max02 388/392, DINT, written acyclically.
#[test]
fn x67_18_5_19_software_limit_registers() {
    assert_rows(&[
        "PositionLimitMin01",
        "PositionLimitMax01",
        "PositionLimitMin02",
        "PositionLimitMax02",
    ]);
}

/// X67-18.5-20: ConfigOutput03aRead…08aRead are read acyclically, USINT, with the numbers of the registers
/// they read back (48–50, 112–114).
#[test]
fn x67_18_5_20_current_read_back_registers() {
    assert_rows(&[
        "ConfigOutput03aRead",
        "ConfigOutput04aRead",
        "ConfigOutput05aRead",
        "ConfigOutput06aRead",
        "ConfigOutput07aRead",
        "ConfigOutput08aRead",
    ]);
    for (write, read) in [
        ("ConfigOutput03a", "ConfigOutput03aRead"),
        ("ConfigOutput08a", "ConfigOutput08aRead"),
    ] {
        assert_eq!(
            Register::from_name(write).unwrap().info().number,
            Register::from_name(read).unwrap().info().number
        );
    }
}

/// X67-18.5-21: AbsPos01 (0) and AbsPos02 (8) are DINT cyclic outputs, at output bytes 0–3 of objects 1
/// and 2.
#[test]
fn x67_18_5_21_set_position_registers() {
    assert_rows(&["AbsPos01", "AbsPos02"]);
    let mut m = Module::new();
    m.output_object(0, [1, 2, 3, 4, 0, 0, 0, 0]);
    m.output_object(1, [0xFF, 0xFF, 0xFF, 0xFF, 0, 0, 0, 0]);
    assert_eq!(
        (named(&m, "AbsPos01"), named(&m, "AbsPos02")),
        (0x0403_0201, -1)
    );
}

/// X67-18.5-22: MpGenControl01 (4) and MpGenControl02 (12) are UINT cyclic outputs, at output bytes 4–5.
#[test]
fn x67_18_5_22_control_word_registers() {
    assert_rows(&["MpGenControl01", "MpGenControl02"]);
    let mut m = Module::new();
    m.output_object(0, [0, 0, 0, 0, 0x0F, 0x82, 0, 0]);
    m.output_object(1, [0, 0, 0, 0, 0x06, 0x40, 0, 0]);
    assert_eq!(
        (
            named(&m, "ControlReadback01"),
            named(&m, "ControlReadback02")
        ),
        (0x820F, 0x4006)
    );
}

/// X67-18.5-23: MpGenMode01 (6) and MpGenMode02 (14) are SINT cyclic outputs, at output byte 6.
#[test]
fn x67_18_5_23_mode_registers() {
    assert_rows(&["MpGenMode01", "MpGenMode02"]);
    let mut m = Module::new();
    m.output_object(0, [0, 0, 0, 0, 0, 0, 0x81, 0]);
    m.output_object(1, [0, 0, 0, 0, 0, 0, 0x02, 0]);
    assert_eq!(
        (named(&m, "ModeReadback01"), named(&m, "ModeReadback02")),
        (-127, 2)
    );
}

/// X67-18.5-24: AbsPos01ActVal (0) and AbsPos02ActVal (8) are DINT cyclic inputs, at input bytes 0–3.
#[test]
fn x67_18_5_24_actual_position_registers() {
    assert_rows(&["AbsPos01ActVal", "AbsPos02ActVal"]);
    let mut m = Module::new();
    m.step();
    quadrature(&mut m, 1, -5);
    m.set_control(1, CW_SWAP_COUNTERS);
    m.step();
    assert_eq!(named(&m, "AbsPos02ActVal"), -5);
    assert_eq!(m.input_object(1)[0..4], [0xFB, 0xFF, 0xFF, 0xFF]);
    assert_eq!(m.input_object(0)[0..4], [0, 0, 0, 0]);
}

/// X67-18.5-25: MpGenStatus01 (4) and MpGenStatus02 (12) are UINT cyclic inputs, at input bytes 4–5.
#[test]
fn x67_18_5_25_status_word_registers() {
    assert_rows(&["MpGenStatus01", "MpGenStatus02"]);
    let mut m = Module::new();
    m.step();
    m.set_control(1, SHUTDOWN);
    m.step();
    assert_eq!(named(&m, "MpGenStatus01"), i64::from(m.status_word(0)));
    assert_eq!(m.input_object(0)[4..6], m.status_word(0).to_le_bytes());
    assert_eq!(m.input_object(1)[4..6], m.status_word(1).to_le_bytes());
    assert_eq!(m.input_object(1)[4] & 0x7F, 0x21);
}

/// X67-18.5-26: InputStatus (6) is the one USINT cyclic input of the module, at byte 6 of input object 1.
#[test]
fn x67_18_5_26_input_status_register() {
    assert_rows(&["InputStatus"]);
    assert_eq!(
        Register::all()
            .filter(|r| r.name().starts_with("InputStatus"))
            .count(),
        1
    );
    let mut m = Module::new();
    m.set_input(1, true);
    m.set_input(4, true);
    m.step();
    assert_eq!(m.input_object(0)[6], 0x09);
    assert_eq!(m.input_object(1)[6], 0x00);
}

/// X67-18.5-27: Motoridentification01/02 are registers 84/148, UINT, read acyclically.
#[test]
fn x67_18_5_27_motor_identification_registers() {
    assert_rows(&["Motoridentification01", "Motoridentification02"]);
}

/// X67-18.5-28: Temperature is register 46, SINT, read acyclically, one for the module.
#[test]
fn x67_18_5_28_temperature_register() {
    assert_rows(&["Temperature"]);
    assert_eq!(
        Register::from_name("Temperature"),
        Some(Register::Module(ModuleReg::Temperature))
    );
    assert_eq!(Register::from_name("Temperature01"), None);
}

/// X67-18.5-29: RefPos01/02CyclicCounter are 86/150 and RefPos01/02AcyclicCounter 94/158, DINT, read
/// acyclically.
#[test]
fn x67_18_5_29_reference_position_registers() {
    assert_rows(&[
        "RefPos01CyclicCounter",
        "RefPos01AcyclicCounter",
        "RefPos02CyclicCounter",
        "RefPos02AcyclicCounter",
    ]);
}

/// X67-18.5-30: AbsPos01ActValAcyclic/02 are registers 90/154, DINT, read acyclically.
#[test]
fn x67_18_5_30_acyclic_position_registers() {
    assert_rows(&["AbsPos01ActValAcyclic", "AbsPos02ActValAcyclic"]);
}

/// X67-18.5-31: ControlReadback01/ModeReadback01 are 80/82 and …02 144/146; UINT and SINT, read acyclically.
#[test]
fn x67_18_5_31_read_back_registers() {
    assert_rows(&[
        "ControlReadback01",
        "ModeReadback01",
        "ControlReadback02",
        "ModeReadback02",
    ]);
}

/// X67-18.5-32: ErrorCode01/02 are registers 98/162, UINT, read acyclically.
#[test]
fn x67_18_5_32_error_code_registers() {
    assert_rows(&["ErrorCode01", "ErrorCode02"]);
}

/// X67-18.6.1.4-01: the Ramp model has no register that selects holding, nominal or maximum current at run
/// time (no MotorXStepX, no "Motor current"): no register name of the table mentions one, every writable
/// per-axis register is a configuration or cyclic output of 18.5, and writing every cyclic output of an axis
/// at standstill in Switched on leaves the holding current flowing.
#[test]
fn x67_18_6_1_4_01_no_run_time_current_selection() {
    use ds402::x67::registers::Register;
    for reg in Register::all() {
        let name = reg.name();
        assert!(
            !name.contains("Step") || name.starts_with("FullStep"),
            "{name}"
        );
        assert!(!name.eq_ignore_ascii_case("MotorCurrent"), "{name}");
    }
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 50, 80);
    switch_on(&mut m, 0);
    m.step();
    assert_eq!(
        (level(&m, 0), milliamps(&m, 0)),
        (Some(Level::Holding), 600)
    );
    // Current-selection bits of function model 0 (bits 14–15 of MotorXStepX) set in every cyclic output.
    m.set_abs_pos(0, i32::from_le_bytes([0, 0xC0, 0, 0xC0]));
    m.set_mode(0, modes::NONE);
    m.set_control(0, SWITCH_ON | 0x4000);
    m.run(10);
    assert_eq!(
        (level(&m, 0), milliamps(&m, 0)),
        (Some(Level::Holding), 600)
    );
}
