//! Motor current of one X67SM2436 axis; each test names the rule of `rules/x67.md` it checks.

use ds402::x67::current::{
    Config, ConfigError, CurrentModel, CurrentState, Level, Phase, ABORT_VALUE_TOO_HIGH,
    FULL_STEP_NEVER,
};
use ds402::x67::ramp::RampState;

fn config() -> Config {
    Config {
        holding: 20,
        nominal: 60,
        maximum: 100,
        ..Config::default()
    }
}

fn model(config: Config) -> CurrentModel {
    CurrentModel::new(config).unwrap()
}

/// Runs `n` cycles of `phase` and returns the levels.
fn levels(model: &mut CurrentModel, phase: Phase, n: usize, cycle_ms: u32) -> Vec<Level> {
    (0..n)
        .map(|_| model.step(phase, 100, cycle_ms).level)
        .collect()
}

fn rep(level: Level, n: usize) -> Vec<Level> {
    vec![level; n]
}

/// X67-18.11.1.1-01: 0…167 % accepted, the default is 0, above 167 is rejected with 0x06090031.
#[test]
fn x67_18_11_1_1_01_range_and_default() {
    assert_eq!(Config::default().holding, 0);
    assert_eq!(Config::default().nominal, 0);
    assert_eq!(Config::default().maximum, 0);
    let mut m = model(Config {
        holding: 0,
        nominal: 167,
        maximum: 167,
        ..Config::default()
    });
    let err = m
        .set_config(Config {
            maximum: 168,
            ..config()
        })
        .unwrap_err();
    assert_eq!(
        err,
        ConfigError::ValueTooHigh {
            level: Level::Maximum,
            value: 168
        }
    );
    assert_eq!(err.abort_code(), ABORT_VALUE_TOO_HIGH);
    assert_eq!(ABORT_VALUE_TOO_HIGH, 0x0609_0031);
    // The rejected configuration leaves the old one in place.
    assert_eq!(m.config().maximum, 167);
    assert_eq!(
        CurrentModel::new(Config {
            holding: 200,
            ..Config::default()
        })
        .unwrap_err(),
        ConfigError::ValueTooHigh {
            level: Level::Holding,
            value: 200
        }
    );
    assert_eq!(
        CurrentModel::new(Config {
            nominal: 255,
            ..Config::default()
        })
        .unwrap_err(),
        ConfigError::ValueTooHigh {
            level: Level::Nominal,
            value: 255
        }
    );
}

/// X67-18.11.1.1-01: percent of the 3 A module nominal current; 100 % = 3000 mA, 167 % = 5010 mA.
#[test]
fn x67_18_11_1_1_01_milliamps() {
    let mut m = model(Config {
        holding: 0,
        nominal: 100,
        maximum: 167,
        ..Config::default()
    });
    assert_eq!(
        m.step(Phase::Accelerating, 10, 10),
        CurrentState {
            level: Level::Maximum,
            percent: 167,
            amps_milli: 5010,
            full_step: false
        }
    );
    let mut m = model(Config {
        holding: 0,
        nominal: 100,
        maximum: 167,
        ..Config::default()
    });
    assert_eq!(
        m.step(Phase::Constant, 10, 10),
        CurrentState {
            level: Level::Nominal,
            percent: 100,
            amps_milli: 3000,
            full_step: false
        }
    );
    let mut m = model(Config {
        holding: 1,
        ..Config::default()
    });
    assert_eq!(
        m.step(Phase::Standstill, 0, 10),
        CurrentState {
            level: Level::Holding,
            percent: 1,
            amps_milli: 30,
            full_step: false
        }
    );
}

/// X67-18.11.1.1-02: holding at standstill, nominal at constant speed, maximum while accelerating and while
/// braking (the catalogue's pick).
#[test]
fn x67_18_11_1_1_02_level_by_phase() {
    let m = model(config());
    assert_eq!(m.wanted(Phase::Standstill), Level::Holding);
    assert_eq!(m.wanted(Phase::Constant), Level::Nominal);
    assert_eq!(m.wanted(Phase::Accelerating), Level::Maximum);
    assert_eq!(m.wanted(Phase::Decelerating), Level::Maximum);
    let mut m = model(config());
    let s = m.step(Phase::Standstill, 0, 10);
    assert_eq!(
        (s.level, s.percent, s.amps_milli),
        (Level::Holding, 20, 600)
    );
    let s = m.step(Phase::Accelerating, 5, 10);
    assert_eq!(
        (s.level, s.percent, s.amps_milli),
        (Level::Maximum, 100, 3000)
    );
    let s = m.step(Phase::Decelerating, 5, 10);
    assert_eq!(
        (s.level, s.percent, s.amps_milli),
        (Level::Maximum, 100, 3000)
    );
}

/// X67-18.11.1.1-02, X67-18.11.1.1-04: a whole move with a 10 ms cycle, cycle by cycle.
#[test]
fn x67_18_11_1_1_04_move_10ms() {
    let mut m = model(config());
    assert_eq!(
        levels(&mut m, Phase::Standstill, 2, 10),
        rep(Level::Holding, 2)
    );
    assert_eq!(
        levels(&mut m, Phase::Accelerating, 3, 10),
        rep(Level::Maximum, 3)
    );
    // Acceleration ends: maximum for another 10 cycles (100 ms), then nominal.
    let mut want = rep(Level::Maximum, 10);
    want.extend(rep(Level::Nominal, 5));
    assert_eq!(levels(&mut m, Phase::Constant, 15, 10), want);
    // Braking: maximum at once.
    assert_eq!(
        levels(&mut m, Phase::Decelerating, 3, 10),
        rep(Level::Maximum, 3)
    );
    // Standstill straight after braking: maximum kept 10 cycles, then holding.
    let mut want = rep(Level::Maximum, 10);
    want.extend(rep(Level::Holding, 3));
    assert_eq!(levels(&mut m, Phase::Standstill, 13, 10), want);
}

/// X67-18.11.1.1-04: the percentages and milliamps follow the held level cycle by cycle.
#[test]
fn x67_18_11_1_1_04_percent_during_hold() {
    let mut m = model(config());
    m.step(Phase::Constant, 100, 10);
    let percents: Vec<u8> = (0..12)
        .map(|_| m.step(Phase::Standstill, 0, 10).percent)
        .collect();
    let mut want = vec![60; 10];
    want.extend([20, 20]);
    assert_eq!(percents, want);
}

/// X67-18.11.1.1-04: the 100 ms in cycles of 25 ms (4 cycles) and 5 ms (20 cycles).
#[test]
fn x67_18_11_1_1_04_hold_other_cycles() {
    for (cycle_ms, held) in [(25, 4), (5, 20), (10, 10)] {
        let mut m = model(config());
        m.step(Phase::Accelerating, 10, cycle_ms);
        let mut want = rep(Level::Maximum, held);
        want.extend(rep(Level::Nominal, 2));
        assert_eq!(
            levels(&mut m, Phase::Constant, held + 2, cycle_ms),
            want,
            "cycle {cycle_ms} ms"
        );
    }
}

/// X67-18.11.1.1-04: nominal → holding is held too, and a stronger request cuts the hold short.
#[test]
fn x67_18_11_1_1_04_nominal_hold_and_restart() {
    let mut m = model(config());
    m.step(Phase::Constant, 100, 25);
    let mut want = rep(Level::Nominal, 4);
    want.push(Level::Holding);
    assert_eq!(levels(&mut m, Phase::Standstill, 5, 25), want);
    // Stop during a hold: after 2 cycles of holding nominal the axis accelerates again → maximum at once.
    let mut m = model(config());
    m.step(Phase::Constant, 100, 25);
    assert_eq!(
        levels(&mut m, Phase::Standstill, 2, 25),
        rep(Level::Nominal, 2)
    );
    assert_eq!(m.step(Phase::Accelerating, 5, 25).level, Level::Maximum);
    // The hold restarts from the last cycle that asked for maximum.
    let mut want = rep(Level::Maximum, 4);
    want.push(Level::Nominal);
    assert_eq!(levels(&mut m, Phase::Constant, 5, 25), want);
}

/// X67-18.11.1.1-04: a short constant phase inside a maximum hold does not restart it; when the hold ends
/// the axis goes straight to the level now asked for.
#[test]
fn x67_18_11_1_1_04_hold_spans_phases() {
    let mut m = model(config());
    m.step(Phase::Accelerating, 10, 25);
    assert_eq!(
        levels(&mut m, Phase::Constant, 2, 25),
        rep(Level::Maximum, 2)
    );
    let mut want = rep(Level::Maximum, 2);
    want.extend(rep(Level::Holding, 2));
    assert_eq!(levels(&mut m, Phase::Standstill, 4, 25), want);
}

/// X67-18.11.1.1-03: homing by referencing during stall uses nominal instead of maximum, also while
/// accelerating and braking; the hold still applies from nominal to holding.
#[test]
fn x67_18_11_1_1_03_stall_homing() {
    let mut m = model(Config {
        stall_homing: true,
        ..config()
    });
    assert_eq!(m.wanted(Phase::Accelerating), Level::Nominal);
    assert_eq!(m.wanted(Phase::Decelerating), Level::Nominal);
    let s = m.step(Phase::Accelerating, 5, 10);
    assert_eq!((s.level, s.percent), (Level::Nominal, 60));
    assert_eq!(
        levels(&mut m, Phase::Constant, 3, 10),
        rep(Level::Nominal, 3)
    );
    assert_eq!(
        levels(&mut m, Phase::Decelerating, 3, 10),
        rep(Level::Nominal, 3)
    );
    let mut want = rep(Level::Nominal, 10);
    want.push(Level::Holding);
    assert_eq!(levels(&mut m, Phase::Standstill, 11, 10), want);
}

/// X67-18.11.1.1-05: the priority is by category, not by value; holding 80 % above nominal 40 % is accepted
/// and on stopping the 40 % nominal level is kept for 100 ms before 80 % holding.
#[test]
fn x67_18_11_1_1_05_priority_by_category() {
    let mut m = model(Config {
        holding: 80,
        nominal: 40,
        maximum: 10,
        ..Config::default()
    });
    assert_eq!(m.step(Phase::Constant, 50, 25).percent, 40);
    let percents: Vec<u8> = (0..6)
        .map(|_| m.step(Phase::Standstill, 0, 25).percent)
        .collect();
    assert_eq!(percents, [40, 40, 40, 40, 80, 80]);
    // Maximum 10 % still beats holding 80 %: accelerating switches to 10 % at once.
    assert_eq!(m.step(Phase::Accelerating, 5, 25).percent, 10);
}

/// X67-18.11.1.2-01: full step at or above the threshold (speed magnitude), microstep below; 65535 never.
#[test]
fn x67_18_11_1_2_01_threshold() {
    let mut m = model(Config {
        full_step_threshold: 200,
        ..config()
    });
    assert!(!m.step(Phase::Constant, 199, 10).full_step);
    assert!(m.step(Phase::Constant, 200, 10).full_step);
    assert!(m.step(Phase::Constant, -200, 10).full_step);
    assert!(!m.step(Phase::Constant, -199, 10).full_step);
    assert!(!m.step(Phase::Standstill, 0, 10).full_step);
    let c = Config {
        full_step_threshold: 1,
        ..config()
    };
    assert!(!c.full_step(0));
    assert!(c.full_step(1));
    assert!(c.full_step(i32::MIN));
    let c = Config {
        full_step_threshold: 65_534,
        ..config()
    };
    assert!(!c.full_step(65_533));
    assert!(c.full_step(65_534));
    let c = Config {
        full_step_threshold: FULL_STEP_NEVER,
        ..config()
    };
    assert!(!c.full_step(65_535));
    assert!(!c.full_step(i32::MAX));
}

/// X67-18.11.1.2-02: the default threshold 0 disables full step (the catalogue's pick).
#[test]
fn x67_18_11_1_2_02_default_zero_disables() {
    assert_eq!(Config::default().full_step_threshold, 0);
    let c = Config::default();
    for speed in [0, 1, 200, 65_535, i32::MAX, -1] {
        assert!(!c.full_step(speed), "speed {speed}");
    }
}

/// X67-18.11.1.1-02: the phase of a ramp-generator cycle from its flags.
#[test]
fn x67_18_11_1_1_02_phase_from_ramp() {
    let base = RampState {
        position: 0,
        speed: 0,
        accelerating: false,
        decelerating: false,
        standstill: false,
        target_reached: false,
        limited: false,
    };
    assert_eq!(
        Phase::from_ramp(&RampState {
            accelerating: true,
            speed: 3,
            ..base
        }),
        Phase::Accelerating
    );
    assert_eq!(
        Phase::from_ramp(&RampState {
            decelerating: true,
            speed: 3,
            ..base
        }),
        Phase::Decelerating
    );
    assert_eq!(
        Phase::from_ramp(&RampState {
            standstill: true,
            ..base
        }),
        Phase::Standstill
    );
    assert_eq!(
        Phase::from_ramp(&RampState { speed: 3, ..base }),
        Phase::Constant
    );
}
