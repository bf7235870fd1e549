//! The X67SM2436 "Ramp" module seen as a whole through [`Module`]: two axes on two bridges, motor
//! identification and the currents. Each test names the rules of `rules/x67.md` it checks.

mod module_status_helpers;
mod x67_rig;

use ds402::cia402::control::{ENABLE_OPERATION, FAULT_RESET, SHUTDOWN, SWITCH_ON};
use ds402::cia402::State;
use ds402::x67::axis::{modes, CW_MOTOR_ID};
use ds402::x67::current::Level;
use ds402::x67::module::{Diagnostic, Module};
use ds402::x67::motor::{self, MotorParams};
use ds402::x67::registers::{AxisReg, Register, RegisterError};
use module_status_helpers::*;
use x67_rig::{
    assert_state, operation_enable, set, set_currents, switch_on, OPERATION_ENABLE,
    QUICK_STOP_ACTIVE, QUICK_STOP_FROM_ENABLED, READY, SWITCHED_ON, SWITCH_ON_DISABLED,
};

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
