//! The CiA 402 state machine of the generic drive (`ds402::drive`): every transition 0–16 with the
//! status word a master reads after it, the option codes 0x605A–0x605E with the stops they make,
//! faults and the idle drive's timing.
//!
//! Status words: bits 0–6 of the standard's state table, bit 4 voltage enabled (Switched on,
//! Operation enabled, Quick stop active, a braking Fault reaction active), bit 5 = 1 outside Quick
//! stop active, bit 9 remote; mode 0 shows no mode bits, pp shows bit 10 target reached.

mod drive_rig;

use std::f64::consts::TAU;
use std::time::Duration;

use drive_rig::*;
use ds402::cia402::State;
use ds402::drive::{DriveConfig, MotorConfig};

const NOT_READY: u16 = 0x0220;
const SWITCH_ON_DISABLED: u16 = 0x0260;
const READY: u16 = 0x0221;
const SWITCHED_ON: u16 = 0x0233;
const ENABLED: u16 = 0x0237;
const QUICK_STOP_ACTIVE: u16 = 0x0217;
/// Fault reaction active while braking with the power on.
const FAULT_REACTION_BRAKING: u16 = 0x023F;
const FAULT: u16 = 0x0228;
/// Status word bit 10, target reached (standing still in Quick stop active, in pp).
const TR: u16 = 0x0400;

#[test]
fn power_on_and_transition_1() {
    let mut r = Rig::with(&[]);
    // 0: power on → Not ready to switch on, left at the first tick (1).
    assert_eq!(r.drive.state(), State::NotReadyToSwitchOn);
    assert_eq!(r.sw(), NOT_READY);
    assert_eq!(
        r.drive.poll_timeout(),
        Some(r.t0 + Duration::from_millis(1))
    );
    r.at(1);
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    // Idle with the power stage off: nothing to do until an input.
    assert_eq!(r.drive.poll_timeout(), None);
}

#[test]
fn a_command_sent_during_initialisation_acts_as_a_level_at_the_first_tick() {
    let mut r = Rig::with(&[]);
    r.cw(SHUTDOWN);
    assert_eq!(r.sw(), NOT_READY);
    r.at(1);
    assert_eq!(r.sw(), READY);
}

#[test]
fn transitions_2_to_10() {
    let mut r = Rig::with(&[(0x605B, 0, 0), (0x605C, 0, 0)]);
    r.at(1);
    r.cw(SHUTDOWN); // 2
    assert_eq!(r.sw(), READY);
    r.cw(SWITCH_ON); // 3
    assert_eq!(r.sw(), SWITCHED_ON);
    r.cw(ENABLE); // 4
    assert_eq!(r.sw(), ENABLED);
    r.cw(SWITCH_ON); // 5 (disable operation, option 0)
    assert_eq!(r.sw(), SWITCHED_ON);
    r.cw(SHUTDOWN); // 6
    assert_eq!(r.sw(), READY);
    r.cw(DISABLE_VOLTAGE); // 7
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    r.cw(SHUTDOWN);
    r.cw(0x0002); // 7 by quick stop
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    r.cw(SHUTDOWN);
    r.cw(SWITCH_ON);
    r.cw(ENABLE);
    r.cw(SHUTDOWN); // 8 (shutdown, option 0)
    assert_eq!(r.sw(), READY);
    r.cw(SWITCH_ON);
    r.cw(ENABLE);
    r.cw(DISABLE_VOLTAGE); // 9
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    r.cw(SHUTDOWN);
    r.cw(SWITCH_ON);
    r.cw(DISABLE_VOLTAGE); // 10 by disable voltage
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    r.cw(SHUTDOWN);
    r.cw(SWITCH_ON);
    r.cw(0x0002); // 10 by quick stop
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
}

#[test]
fn switch_on_and_enable_operation_at_once_is_3_then_4() {
    let mut r = Rig::with(&[]);
    r.at(1);
    r.cw(SHUTDOWN);
    r.cw(ENABLE);
    assert_eq!(r.sw(), ENABLED);
}

#[test]
fn commands_without_a_transition_change_nothing() {
    let mut r = Rig::with(&[]);
    r.at(1);
    r.cw(ENABLE); // no transition from Switch on disabled
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    r.cw(SWITCH_ON);
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    r.cw(SHUTDOWN);
    r.cw(SWITCH_ON);
    r.cw(ENABLE);
    r.cw(SHUTDOWN | 0x0080); // bit 7 rising: Fault reset, no fault: nothing
    assert_eq!(r.sw(), ENABLED);
}

#[test]
fn transitions_11_12_16_at_standstill() {
    // 0x605A = 2: Quick stop active, at standstill at once, Switch on disabled at the next tick (12).
    let mut r = Rig::with(&[]);
    r.enable(0);
    r.cw(QUICK_STOP); // 11
    assert_eq!(r.sw(), QUICK_STOP_ACTIVE | TR);
    r.at(2);
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);

    // 0x605A = 6: stays in Quick stop active; 16 back to Operation enabled; 12 by Disable voltage.
    let mut r = Rig::with(&[(0x605A, 0, 6)]);
    r.enable(0);
    r.cw(QUICK_STOP);
    r.at(50);
    assert_eq!(r.sw(), QUICK_STOP_ACTIVE | TR);
    r.cw(ENABLE); // 16
    assert_eq!(r.sw(), ENABLED);
    r.cw(QUICK_STOP);
    r.cw(DISABLE_VOLTAGE); // 12
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
}

#[test]
fn transition_16_needs_option_5_to_8() {
    let mut r = Rig::with(&[(0x605A, 0, 1)]);
    r.enable(0);
    r.cw(QUICK_STOP);
    r.cw(ENABLE); // ignored with option 1
    assert_eq!(r.sw(), QUICK_STOP_ACTIVE | TR);
    r.at(2);
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
}

#[test]
fn transitions_13_14_15() {
    let mut r = Rig::with(&[]);
    r.enable(0);
    // 13: a fault; 0x605E = 2 brakes (at standstill: done at the next tick, 14).
    let now = r.now;
    r.drive.raise_fault(now, 0x4310);
    assert_eq!(r.sw(), FAULT_REACTION_BRAKING);
    assert_eq!(r.read(0x603F, 0), 0x4310);
    assert_eq!(r.drive.error_code(), 0x4310);
    r.at(2);
    assert_eq!(r.sw(), FAULT);
    assert_eq!(r.read(0x603F, 0), 0x4310);
    // Bit 7 held at 1 on entering is no edge; nothing happens until it rises.
    r.cw(ENABLE);
    assert_eq!(r.sw(), FAULT);
    r.cw(FAULT_RESET); // 15
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    assert_eq!(r.read(0x603F, 0), 0);
    assert_eq!(r.drive.error_code(), 0);
    // Bit 7 still set: no command.
    r.cw(FAULT_RESET | SHUTDOWN);
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    r.cw(SHUTDOWN);
    assert_eq!(r.sw(), READY);
}

#[test]
fn a_fault_with_the_power_off_goes_straight_to_fault() {
    let mut r = Rig::with(&[]);
    r.at(1);
    r.drive.raise_fault(r.now, 0x3210);
    assert_eq!(r.sw(), FAULT);
    assert_eq!(r.read(0x603F, 0), 0x3210);
}

// ----- option codes, with the axis cruising -----

/// pp in Operation enabled at 1 ms, moving towards 100 000 at 1000 counts/s (0x6083/0x6084 10 000
/// counts/s²: 50 counts of ramp in 100 ms); at 301 ms the axis is at 250 counts, cruising.
fn cruising(changes: &[(u16, u8, i64)], config: DriveConfig) -> Rig {
    let mut r = Rig::new(dictionary(changes), config);
    r.enable(1);
    r.set(0x607A, 0, 100_000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.cw(ENABLE);
    r.at(301);
    assert_eq!(r.pos(), 250);
    assert_eq!(r.read(0x606C, 0), 1000);
    r
}

#[test]
fn quick_stop_option_1_slow_down_ramp_then_switch_on_disabled() {
    let mut r = cruising(&[(0x605A, 0, 1)], DriveConfig::default());
    r.cw(QUICK_STOP);
    assert_eq!(r.sw(), QUICK_STOP_ACTIVE);
    // 0x6084 = 10 000: 100 ms to a stop, 50 counts. 40 ms in: 250 + 40 − 8 = 282.
    r.at(341);
    assert_eq!(r.pos(), 282);
    r.at(400);
    assert_eq!(r.sw(), QUICK_STOP_ACTIVE);
    r.at(401);
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    assert_eq!(r.pos(), 300);
    assert_eq!(r.read(0x606C, 0), 0);
}

#[test]
fn quick_stop_option_2_quick_stop_ramp_then_switch_on_disabled() {
    // 0x6085 = 100 000: 10 ms to a stop, 5 counts.
    let mut r = cruising(&[(0x605A, 0, 2)], DriveConfig::default());
    r.cw(QUICK_STOP);
    r.at(310);
    assert_eq!(r.sw(), QUICK_STOP_ACTIVE);
    r.at(311);
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    assert_eq!(r.pos(), 255);
}

/// The torque limit's ramp with 0x6072 = 8 ‰ of 1 N·m: 0.008 N·m over the inertia 1e-4 kg·m² at
/// 10 000 counts/rev. Returns (milliseconds to a stop rounded up, counts braked).
fn torque_limit_stop() -> (u64, f64) {
    let decel = 0.008 / (1e-4 * (TAU / 10_000.0));
    let t = 1000.0 / decel;
    ((t * 1000.0).ceil() as u64, 1000.0 * 1000.0 / (2.0 * decel))
}

#[test]
fn quick_stop_options_3_and_4_brake_at_the_torque_limit() {
    let (ms, dist) = torque_limit_stop();
    assert_eq!(ms, 8); // 7.85 ms
    for option in [3, 4] {
        let mut r = cruising(
            &[(0x605A, 0, option), (0x6072, 0, 8)],
            DriveConfig::default(),
        );
        r.cw(QUICK_STOP);
        r.at(300 + ms);
        assert_eq!(r.sw(), QUICK_STOP_ACTIVE, "option {option}");
        r.at(301 + ms);
        assert_eq!(r.sw(), SWITCH_ON_DISABLED, "option {option}");
        assert_eq!(r.pos(), (250.0 + dist).round() as i64, "option {option}");
    }
}

/// The torque limit is 0x6072 per mille of the rated torque 0x6076 (CiA 402-2, objects 0x6072 and
/// 0x6076): 4 ‰ of 2 N·m is the same 0.008 N·m as 8 ‰ of 1 N·m, and quick stop option 3 brakes
/// alike.
#[test]
fn the_torque_limit_is_per_mille_of_the_rated_torque() {
    let (ms, dist) = torque_limit_stop();
    let mut r = cruising(
        &[(0x605A, 0, 3), (0x6072, 0, 4), (0x6076, 0, 2000)],
        DriveConfig::default(),
    );
    r.cw(QUICK_STOP);
    r.at(300 + ms);
    assert_eq!(r.sw(), QUICK_STOP_ACTIVE);
    r.at(301 + ms);
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    assert_eq!(r.pos(), (250.0 + dist).round() as i64); // 250 + 3.9
}

/// The current-limit ramp (0x605A = 3) brakes with the torque the load leaves (CiA 402-2, quick
/// stop option code): 10 ‰ of 1 N·m less a load of 0.002 N·m is the 0.008 N·m of the test above.
/// Where the load takes it all the ramp is the whole torque limit: moving at −1000 counts/s
/// against a load of 0.01 N·m with 0x6072 = 10 ‰, the stop is planned at 0.01 / (1e-4 · 2π /
/// 10 000) = 159 155 counts/s², 6.3 ms, and Switch on disabled follows at the tick after.
#[test]
fn the_current_limit_ramp_leaves_the_load_its_torque() {
    let (ms, dist) = torque_limit_stop();
    let load = |torque: f64| DriveConfig {
        motor: MotorConfig {
            load_torque: torque,
            ..MotorConfig::default()
        },
        ..DriveConfig::default()
    };
    let mut r = cruising(&[(0x605A, 0, 3), (0x6072, 0, 10)], load(0.002));
    r.cw(QUICK_STOP);
    r.at(300 + ms);
    assert_eq!(r.sw(), QUICK_STOP_ACTIVE);
    r.at(301 + ms);
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    assert_eq!(r.pos(), (250.0 + dist).round() as i64); // 250 + 3.9
    let mut r = Rig::new(dictionary(&[(0x605A, 0, 3), (0x6072, 0, 10)]), load(0.01));
    r.enable(1);
    r.set(0x607A, 0, -100_000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(301);
    assert_eq!((r.pos(), r.read(0x606C, 0)), (-250, -1000));
    r.cw(QUICK_STOP);
    r.at(307);
    assert_eq!(r.sw(), QUICK_STOP_ACTIVE);
    r.at(308);
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
}

#[test]
fn quick_stop_options_5_to_8_stay_in_quick_stop_active() {
    let (ms, dist) = torque_limit_stop();
    // (option, instant of standstill, position there)
    let cases = [
        (5, 401, 300),
        (6, 311, 255),
        (7, 301 + ms, (250.0 + dist).round() as i64),
        (8, 301 + ms, (250.0 + dist).round() as i64),
    ];
    for (option, stop, pos) in cases {
        let mut r = cruising(
            &[(0x605A, 0, option), (0x6072, 0, 8)],
            DriveConfig::default(),
        );
        r.cw(QUICK_STOP);
        r.at(stop - 1);
        assert_eq!(r.sw(), QUICK_STOP_ACTIVE, "option {option}");
        r.at(stop);
        assert_eq!(r.sw(), QUICK_STOP_ACTIVE | TR, "option {option}");
        assert_eq!(r.pos(), pos, "option {option}");
        r.at(stop + 500);
        assert_eq!(r.sw(), QUICK_STOP_ACTIVE | TR, "option {option}");
        assert_eq!(r.pos(), pos, "option {option}");
        // 16: back to Operation enabled; the set-point was dropped, pp stands at its target.
        r.cw(ENABLE);
        assert_eq!(r.sw(), ENABLED | TR, "option {option}");
    }
}

#[test]
fn quick_stop_option_0_disables_at_once_and_the_motor_coasts() {
    let mut r = cruising(&[(0x605A, 0, 0)], DriveConfig::default());
    r.cw(QUICK_STOP);
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    // Coasting on the viscous friction alone: 1e-3 N·m·s/rad over 1e-4 kg·m², a time constant of
    // 0.1 s: v = 1000·e^(−t/0.1), x = 250 + 100·(1 − e^(−t/0.1)).
    r.at(311);
    let decay = (-0.1f64).exp();
    assert_eq!(r.read(0x606C, 0), (1000.0 * decay).round() as i64); // 905
    assert_eq!(r.pos(), (250.0 + 100.0 * (1.0 - decay)).round() as i64); // 260
                                                                         // Below 1 count/s the rotor stands: 1000 · e^(−k/100) < 1 from the 691st tick after 301 ms
                                                                         // (ln 1000 · 0.1 s ≈ 0.69 s), at 992 ms; from then on the drive is idle.
    r.at(991);
    assert_eq!(r.read(0x606C, 0), 1);
    assert_eq!(
        r.drive.poll_timeout(),
        Some(r.t0 + Duration::from_millis(992))
    );
    r.at(992);
    assert_eq!(r.read(0x606C, 0), 0);
    assert_eq!(r.drive.poll_timeout(), None);
    r.at(1301);
    assert_eq!(r.read(0x606C, 0), 0);
    assert_eq!(r.pos(), 350);
    assert_eq!(r.drive.poll_timeout(), None);
}

/// Without friction the rotor coasts on at its speed (CiA 402-2, Disable voltage: the drive
/// function is off, the motor rotates freely): 1000 counts/s from 250 at 301 ms, 350 at 401 ms.
#[test]
fn without_friction_the_motor_coasts_on() {
    let config = DriveConfig {
        motor: MotorConfig {
            friction: 0.0,
            ..MotorConfig::default()
        },
        ..DriveConfig::default()
    };
    let mut r = cruising(&[(0x605A, 0, 0)], config);
    r.cw(QUICK_STOP);
    r.at(401);
    assert_eq!((r.read(0x606C, 0), r.pos()), (1000, 350));
}

#[test]
fn shutdown_option_codes() {
    // 0: Ready to switch on at once, coasting.
    let mut r = cruising(&[(0x605B, 0, 0)], DriveConfig::default());
    r.cw(SHUTDOWN);
    assert_eq!(r.sw(), READY);
    r.at(311);
    assert_eq!(r.pos(), 260);
    // 1: the slow-down ramp first, in Operation enabled, then Ready to switch on (8).
    let mut r = cruising(&[(0x605B, 0, 1)], DriveConfig::default());
    r.cw(SHUTDOWN);
    assert_eq!(r.sw(), ENABLED);
    r.at(400);
    assert_eq!(r.sw(), ENABLED);
    r.at(401);
    assert_eq!(r.sw(), READY);
    assert_eq!(r.pos(), 300);
}

#[test]
fn disable_operation_option_codes() {
    // 0: Switched on at once, coasting.
    let mut r = cruising(&[(0x605C, 0, 0)], DriveConfig::default());
    r.cw(SWITCH_ON);
    assert_eq!(r.sw(), SWITCHED_ON);
    r.at(311);
    assert_eq!(r.pos(), 260);
    // 1: slow-down ramp, then Switched on (5).
    let mut r = cruising(&[(0x605C, 0, 1)], DriveConfig::default());
    r.cw(SWITCH_ON);
    r.at(400);
    assert_eq!(r.sw(), ENABLED);
    r.at(401);
    assert_eq!(r.sw(), SWITCHED_ON);
    assert_eq!(r.pos(), 300);
    // Enable operation during the slow-down carries on with the move: at 351 at 500 counts/s, back
    // at 1000 counts/s 50 ms later.
    let mut r = cruising(&[(0x605C, 0, 1)], DriveConfig::default());
    r.cw(SWITCH_ON);
    r.at(351);
    assert_eq!(r.read(0x606C, 0), 500);
    r.cw(ENABLE);
    r.at(400);
    assert_eq!(r.read(0x606C, 0), 990);
    r.at(401);
    assert_eq!(r.sw(), ENABLED);
    assert_eq!(r.read(0x606C, 0), 1000);
}

#[test]
fn halt_option_codes() {
    let (ms, dist) = torque_limit_stop();
    let cases = [
        (1, 401, 300),
        (2, 311, 255),
        (3, 301 + ms, (250.0 + dist).round() as i64),
        (4, 301 + ms, (250.0 + dist).round() as i64),
    ];
    for (option, stop, pos) in cases {
        let mut r = cruising(
            &[(0x605D, 0, option), (0x6072, 0, 8)],
            DriveConfig::default(),
        );
        r.cw(ENABLE | HALT);
        r.at(stop - 1);
        assert_eq!(r.sw(), ENABLED, "option {option}");
        r.at(stop);
        // Halted at standstill: target reached, still Operation enabled.
        assert_eq!(r.sw(), ENABLED | TR, "option {option}");
        assert_eq!(r.pos(), pos, "option {option}");
        // Released: the positioning goes on.
        r.cw(ENABLE);
        assert_eq!(r.sw(), ENABLED, "option {option}");
        r.wait(200);
        assert_eq!(r.read(0x606C, 0), 1000, "option {option}");
    }
}

#[test]
fn fault_reaction_option_codes() {
    let (ms, dist) = torque_limit_stop();
    // 0: power off at once, Fault, coasting.
    let mut r = cruising(&[(0x605E, 0, 0)], DriveConfig::default());
    r.drive.raise_fault(r.now, 0x4310);
    assert_eq!(r.sw(), FAULT);
    r.at(311);
    assert_eq!(r.pos(), 260);
    // 1–4: Fault reaction active while braking, then Fault.
    let cases = [
        (1, 401, 300),
        (2, 311, 255),
        (3, 301 + ms, (250.0 + dist).round() as i64),
        (4, 301 + ms, (250.0 + dist).round() as i64),
    ];
    for (option, stop, pos) in cases {
        let mut r = cruising(
            &[(0x605E, 0, option), (0x6072, 0, 8)],
            DriveConfig::default(),
        );
        r.drive.raise_fault(r.now, 0x4310);
        assert_eq!(r.sw(), FAULT_REACTION_BRAKING, "option {option}");
        r.at(stop - 1);
        assert_eq!(r.sw(), FAULT_REACTION_BRAKING, "option {option}");
        r.at(stop);
        assert_eq!(r.sw(), FAULT, "option {option}");
        assert_eq!(r.pos(), pos, "option {option}");
        assert_eq!(r.read(0x603F, 0), 0x4310, "option {option}");
    }
}

#[test]
fn running_into_a_limit_switch_is_a_fault() {
    let config = DriveConfig {
        sim: ds402::drive::SimConfig {
            positive_limit: Some(1000),
            ..Default::default()
        },
        ..DriveConfig::default()
    };
    let mut r = cruising(&[], config);
    // The switch is active from 1000 counts: reached at 1001 + 50 = 1051 ms.
    r.at(1050);
    assert_eq!(r.sw(), ENABLED);
    assert_eq!(r.read(0x60FD, 0), 0);
    r.at(1051);
    assert_eq!(r.read(0x60FD, 0), 0b010);
    assert_eq!(r.sw(), FAULT_REACTION_BRAKING);
    assert_eq!(r.read(0x603F, 0), 0x8612);
    // Quick-stop ramp: 10 ms.
    r.at(1061);
    assert_eq!(r.sw(), FAULT);
    // Fault reset, enable, and a move away from the switch is fine.
    r.cw(FAULT_RESET);
    r.cw(SHUTDOWN);
    r.cw(SWITCH_ON);
    r.cw(ENABLE);
    assert_eq!(r.pos(), 1005);
    r.set(0x607A, 0, 0);
    r.cw(ENABLE | NEW_SETPOINT);
    // Still on the switch: bit 11 (internal limit) with Operation enabled and the acknowledge.
    assert_eq!(r.sw(), ENABLED | 0x1000 | 0x0800);
    r.wait(100);
    assert_eq!(r.read(0x606C, 0), -1000);
    assert_eq!(r.pos(), 955);
    assert_eq!(r.sw(), ENABLED | 0x1000);
}

/// Standing on active limit switches is no fault (bit 11 shows them), nor is moving out of one;
/// running into the negative limit switch is, as into the positive one above: at −1000 at 1051 ms
/// (CiA 402-2, 0x60FD; error code 0x8612).
#[test]
fn standing_on_a_limit_switch_is_no_fault_running_into_the_negative_one_is() {
    let on_both = DriveConfig {
        sim: ds402::drive::SimConfig {
            negative_limit: Some(0),
            positive_limit: Some(0),
            ..Default::default()
        },
        ..DriveConfig::default()
    };
    let mut r = Rig::new(dictionary(&[]), on_both);
    r.enable(1);
    r.at(100);
    assert_eq!(r.read(0x60FD, 0), 0b011);
    assert_eq!((r.sw(), r.read(0x603F, 0)), (ENABLED | TR | 0x0800, 0));
    // Bit 11 shows in Quick stop active too.
    r.cw(QUICK_STOP);
    assert_eq!(r.sw(), QUICK_STOP_ACTIVE | TR | 0x0800);
    let config = DriveConfig {
        sim: ds402::drive::SimConfig {
            negative_limit: Some(-1000),
            positive_limit: Some(0),
            ..Default::default()
        },
        ..DriveConfig::default()
    };
    let mut r = Rig::new(dictionary(&[]), config);
    r.enable(1);
    r.set(0x607A, 0, -100_000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.cw(ENABLE);
    r.at(1050);
    assert_eq!((r.sw(), r.read(0x60FD, 0), r.pos()), (ENABLED, 0, -999));
    r.at(1051);
    assert_eq!(r.read(0x60FD, 0), 0b001);
    assert_eq!(
        (r.sw(), r.read(0x603F, 0)),
        (FAULT_REACTION_BRAKING, 0x8612)
    );
}

/// A command the state does not take is kept as a level and acts at the first tick where it
/// applies (CiA 402-2, device control): Shutdown written while the quick stop (0x605A = 2) brakes
/// is Shutdown from Switch on disabled, taken at the tick after the stop ends, even on a stepper,
/// which stands exactly at that instant. Stepper from 250 at 1000 counts/s: 0x6085 = 100 000,
/// 10 ms.
#[test]
fn a_command_written_during_a_quick_stop_acts_when_it_ends() {
    let config = DriveConfig {
        motor: MotorConfig {
            kind: ds402::drive::MotorKind::Stepper,
            ..MotorConfig::default()
        },
        ..DriveConfig::default()
    };
    let mut r = cruising(&[], config);
    r.cw(QUICK_STOP);
    r.at(305);
    r.cw(SHUTDOWN);
    assert_eq!(r.sw(), QUICK_STOP_ACTIVE);
    r.at(311);
    assert_eq!((r.sw(), r.pos()), (SWITCH_ON_DISABLED, 255));
    r.at(312);
    assert_eq!(r.sw(), READY);
}

/// Disable voltage during a move drops the set-point (CiA 402-2, transition 9): enabled again
/// the axis stands where the coast left it and does not resume the old move; "target reached"
/// (bit 10, standing without a set-point).
#[test]
fn disable_voltage_drops_the_set_point() {
    let mut r = cruising(&[], DriveConfig::default());
    r.cw(DISABLE_VOLTAGE);
    r.at(2000);
    let here = r.pos();
    r.cw(SHUTDOWN);
    r.cw(ENABLE);
    assert_eq!(r.sw(), ENABLED | TR);
    r.at(3000);
    assert_eq!((r.sw(), r.pos(), r.demand()), (ENABLED | TR, here, here));
}

#[test]
fn nmt_reset_brings_back_the_power_on_values() {
    let mut r = Rig::with(&[]);
    r.enable(1);
    r.set(0x605A, 0, 5);
    r.set(0x607A, 0, 500);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(1000);
    assert_eq!(r.pos(), 500);
    let now = r.now;
    r.drive.reset(now);
    assert_eq!(r.sw(), NOT_READY);
    r.wait(1);
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
    // The rotor stays where it is.
    assert_eq!(r.pos(), 500);
    // 0x605A is 2 again in the drive (the node resets its dictionary itself): a quick stop ends in
    // Switch on disabled.
    r.cw(SHUTDOWN);
    r.cw(ENABLE);
    r.cw(QUICK_STOP);
    r.wait(1);
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
}

#[test]
fn a_config_with_a_finer_tick() {
    let config = DriveConfig {
        tick: Duration::from_micros(250),
        motor: MotorConfig::default(),
        ..DriveConfig::default()
    };
    let mut r = Rig::new(dictionary(&[]), config);
    assert_eq!(
        r.drive.poll_timeout(),
        Some(r.t0 + Duration::from_micros(250))
    );
    r.at(1);
    assert_eq!(r.sw(), SWITCH_ON_DISABLED);
}

/// In Quick stop active (0x605A = 6: stay there) the axis stands: neither a change of 0x6060 nor
/// halt and its release starts a motion; transition 16 (Enable operation) starts the mode in
/// effect, pv up to 0x60FF (CiA 402-2, state machine, transition 16).
#[test]
fn quick_stop_active_starts_no_motion_until_transition_16() {
    let mut r = Rig::with(&[(0x605A, 0, 6), (0x60FF, 0, 1000)]);
    r.enable(1);
    r.cw(QUICK_STOP);
    r.at(2);
    assert_eq!(r.sw(), QUICK_STOP_ACTIVE | TR);
    r.set(0x6060, 0, 3);
    assert_eq!(r.read(0x6061, 0), 3);
    r.cw(QUICK_STOP | HALT);
    r.cw(QUICK_STOP);
    r.at(102);
    assert_eq!((r.read(0x606C, 0), r.pos()), (0, 0));
    assert_eq!(r.sw(), QUICK_STOP_ACTIVE | TR);
    // 16 at 102 ms: 100 ms of ramp, 50 counts.
    r.cw(ENABLE);
    r.at(202);
    assert_eq!((r.read(0x606C, 0), r.pos()), (1000, 50));
}
