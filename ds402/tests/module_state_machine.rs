//! The X67SM2436 "Ramp" module seen as a whole through [`Module`]: the state machine of each axis (18.11.4.3),
//! the status word states (18.11.4.2) and the control word commands (18.11.4.1). The lower layers have their
//! own tests; these prove the joined model. Each test names the rules of `rules/x67.md` it checks.

mod module_status_helpers;
mod x67_rig;

use ds402::cia402::control::{
    DISABLE_OPERATION, DISABLE_VOLTAGE, ENABLE_OPERATION, ENABLE_VOLTAGE_BIT, FAULT_RESET,
    QUICK_STOP, SHUTDOWN, SWITCH_ON,
};
use ds402::cia402::{self, State, SW_WARNING};
use ds402::x67::axis::{modes, CW_SWAP_COUNTERS, SW_TARGET_REACHED};
use ds402::x67::current::Level;
use ds402::x67::errors::{CW_CURRENT_ERROR_DETECTION, CW_STALL_DETECTION, CW_WARNING_RESET};
use ds402::x67::module::Module;
use ds402::x67::motor::Load;
use ds402::x67::registers::AxisReg;
use module_status_helpers::*;
use x67_rig::{
    assert_state, increments, mask, operation_enable, set, set_currents, switch_on, FAULT,
    FAULT_REACTION_ACTIVE, NOT_READY, OPERATION_ENABLE, QUICK_STOP_ACTIVE, QUICK_STOP_FROM_ENABLED,
    READY, SWITCHED_ON, SWITCH_ON_DISABLED,
};

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

/// X67-18.11.4.1-01, X67-18.11.4.1-02, X67-18.11.4.1-03, X67-18.11.4.1-04, X67-18.11.4.1-05,
/// X67-18.11.4.1-06, X67-18.11.4.1-07, X67-18.11.4.1-08, X67-18.11.4.1-09, X67-18.11.4.1-13,
/// through the module as a master drives it:
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
