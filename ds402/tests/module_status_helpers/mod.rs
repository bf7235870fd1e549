//! What the tests of the X67SM2436 module seen as a whole share (`module_state_machine`, `module_errors`,
//! `module_currents`, `module_inputs`, `module_registers`): modules brought to a state, probes of the
//! currents and the stall detection, and the 18.5 register table as the data sheet gives it.
#![allow(dead_code)]

use crate::x67_rig::{
    assert_state, increments, operation_enable, set, set_currents, switch_on, OPERATION_ENABLE,
    QUICK_STOP_ACTIVE, QUICK_STOP_FROM_ENABLED, SWITCHED_ON,
};
use ds402::cia402::control::{ENABLE_OPERATION, QUICK_STOP, SHUTDOWN, SWITCH_ON};
use ds402::cia402::State;
use ds402::x67::axis::modes;
use ds402::x67::current::Level;
use ds402::x67::errors::CW_STALL_DETECTION;
use ds402::x67::module::Module;
use ds402::x67::motor::{Load, MotorParams};
use ds402::x67::registers::{Access, AxisReg, RegType, Register};
use Access::{Config as Wo, CyclicIn as Tx, CyclicOut as Rx, ReadAcyclic as Ro};
use RegType::{Dint, Int, Sint, Uint, Usint};

/// Status word bit 4: Voltage enabled (X67-18.11.4.2-09).
pub const SW_VOLTAGE_ENABLED: u16 = 1 << 4;

// ----- helpers -----

pub fn named(m: &Module, name: &str) -> i64 {
    m.read_named(name)
}

/// A module with axis 1 in Operation enable in speed mode 2 at `speed` microsteps/cycle, reached with
/// MaxAcc01 = MaxDec01 = `acc`; currents 20/50/80 %.
pub fn running(speed: i32, acc: u16) -> Module {
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
pub fn step_increment(m: &mut Module, axis: usize) -> i32 {
    crate::x67_rig::cycle(m, axis).inc
}

/// The current level driven in the last cycle (`None` when the motor is not powered).
pub fn level(m: &Module, axis: usize) -> Option<Level> {
    m.axis(axis).observation().current.map(|c| c.level)
}

pub fn milliamps(m: &Module, axis: usize) -> u32 {
    m.axis(axis).phase_current_ma()
}

/// Stall threshold 3 (StallDetectConfig0n bits 4–6) and a motor whose load value is 2: a stall condition
/// whenever the axis moves with stall detection on (X67-18.6.1.1-02).
pub fn make_stall(m: &mut Module, axis: usize) {
    set(m, axis, AxisReg::StallDetectConfig, 0x30);
    m.axis_mut(axis).motor.load = Load::Value(2);
}

/// Drives the A/B inputs of ABR group `group` (0: DI1/DI2, 1: DI4/DI5) by hand through `counts` quadrature
/// edges: positive counts with A leading B, negative with B leading A.
pub fn quadrature(m: &mut Module, group: usize, counts: i32) {
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
/// (X67-18.11.3.7-01, X67-18.11.3.7-06). `None` when (2/3)·I_nom < 1 A, 65534 above 32 767 µs.
pub fn expected_identification(
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
pub fn tour() -> Vec<(State, Module)> {
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
pub fn cruising() -> Module {
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
pub fn snapshot(state: State) -> Module {
    tour()
        .into_iter()
        .find(|(s, _)| *s == state)
        .map(|(_, m)| m)
        .unwrap()
}

/// A module with axis 1 moving in mode 2 at 30 microsteps/cycle with stall detection on and stall
/// threshold 0.
pub fn stall_probe() -> Module {
    let mut m = running(30, 10);
    m.set_control(0, ENABLE_OPERATION | CW_STALL_DETECTION);
    m.step();
    m
}

/// Runs axis 1 of `m` (mode 2) at `speed` until the speed holds and returns the load value in SW bits 13–15.
pub fn load_bits_at(m: &Module, speed: i32, torque: u8) -> u16 {
    let mut m = m.clone();
    m.axis_mut(0).motor.load = Load::Torque(torque);
    m.set_abs_pos(0, speed);
    m.run(200);
    assert_eq!(m.axis(0).observation().ramp.speed, speed);
    m.status_word(0) >> 13
}

/// The speeds (1…1000, mode 2 ramp with MaxAcc01 = 1) at which mixed decay is off with threshold `t`.
pub fn decay_off_speeds(t: i64) -> Vec<i32> {
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
pub fn first_identification(nominal: u8, volts: f64, motor: impl Fn(&mut MotorParams)) -> i64 {
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, i64::from(nominal), 80);
    motor(&mut m.axis_mut(0).motor.params);
    m.set_supply(volts);
    switch_on(&mut m, 0);
    named(&m, "Motoridentification01")
}

/// Every status word of axis 1 (and of axis 2 in Switch on disabled) in every state: the snapshots of
/// [`tour`], each followed by an overtemperature (Fault) and a quick stop in Fault.
pub fn status_words_of_every_state() -> Vec<u16> {
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
pub const TABLE: [(&str, u16, RegType, Access); 71] = [
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
pub fn assert_rows(names: &[&str]) {
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
