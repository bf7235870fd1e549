//! The motor behind the generic drive: a stepper follows the demand exactly within its pull-out
//! torque and loses whole full steps beyond it (0x6064 shows them with an encoder, not without);
//! a servo with a load follows a profile without error and holds against the load.
//!
//! Stepper numbers: 1e-4 kg·m², no friction, 10 000 counts/rev, 200 full steps (50 counts each).
//! A pull-out torque of 2π · 1.001e-3 N·m accelerates the rotor at most at
//! a_r = 1.001e-3 · 2π / (1e-4 · 2π / 10 000) = 100 100 counts/s².

mod drive_rig;

use std::f64::consts::TAU;

use drive_rig::*;
use ds402::drive::{DriveConfig, MotorConfig, MotorKind};

const ENABLED: u16 = 0x0237;
const TR: u16 = 0x0400;

fn stepper(encoder: bool) -> DriveConfig {
    DriveConfig {
        motor: MotorConfig {
            kind: MotorKind::Stepper,
            pull_out_torque: TAU * 1.001e-3,
            friction: 0.0,
            encoder,
            ..MotorConfig::default()
        },
        ..DriveConfig::default()
    }
}

/// pp to 10 000 at 20 000 counts/s with `acc` up and 50 000 counts/s² down, from 1 ms.
fn stepper_move(acc: i64, encoder: bool) -> Rig {
    let dict = dictionary(&[(0x6081, 0, 20_000), (0x6083, 0, acc), (0x6084, 0, 50_000)]);
    let mut r = Rig::new(dict, stepper(encoder));
    r.enable(1);
    r.set(0x607A, 0, 10_000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.cw(ENABLE);
    r
}

#[test]
fn a_stepper_within_its_pull_out_torque_follows_exactly() {
    // 50 000 counts/s² needs half the pull-out torque. Ramp 0.4 s (4000 counts), cruise 2000
    // counts (0.1 s), ramp 0.4 s: at 10 000 at 901 ms.
    let mut r = stepper_move(50_000, true);
    r.at(201);
    assert_eq!((r.demand(), r.pos()), (1000, 1000));
    r.at(401);
    assert_eq!((r.demand(), r.pos()), (4000, 4000));
    assert_eq!(r.read(0x60F4, 0), 0);
    r.at(901);
    assert_eq!((r.demand(), r.pos()), (10_000, 10_000));
    assert_eq!(r.sw(), ENABLED | TR);
}

/// What the test works out for 200 000 counts/s² up: the rotor slips from the first tick, gaining
/// a_r · 1 ms of speed each tick, while the demand reaches 20 000 counts/s in 0.1 s and cruises.
/// It locks again at the first tick k (after the start) at which it can reach the demand's speed
/// within the tick, 20 000 − a_r · (k − 1) ms ≤ a_r · 1 ms, behind the demand by the whole full
/// steps nearest to the distance lost.
fn lost_counts() -> i64 {
    lost_counts_at(20_000.0)
}

/// As [`lost_counts`] for a cruise at `v` counts/s (reached at 200 000 counts/s²).
fn lost_counts_at(v: f64) -> i64 {
    let a_r = 1.001e-3 * TAU / (1e-4 * TAU / 10_000.0);
    let dt = 0.001;
    let k = (v / (a_r * dt)).ceil(); // 200 at 20 000 counts/s
    let before = (k - 1.0) * dt;
    let rotor = 0.5 * a_r * before * before + 0.5 * (a_r * before + v) * dt;
    // The demand: v / 200 000 s of ramp (1000 counts at 20 000 counts/s), then v.
    let ramp = v / 200_000.0;
    let demand = 0.5 * v * ramp + v * (k * dt - ramp);
    let step = 10_000.0 / 200.0;
    (((demand - rotor) / step).round() * step) as i64
}

#[test]
fn a_stepper_beyond_its_pull_out_torque_loses_whole_steps() {
    let lost = lost_counts();
    assert_eq!(lost, 1000); // 20 full steps
                            // 200 000 counts/s² up: ramp 0.1 s (1000 counts), ramp down 0.4 s (4000), cruise 5000 counts
                            // (0.25 s): the demand is at 10 000 at 751 ms.
    let mut r = stepper_move(200_000, true);
    // While it slips the motor gives its pull-out torque (6.29 ‰ of 1 N·m) and the rotor gains
    // a_r where the demand gains 200 000 counts/s²: 50 ms in, ½ · a_r · 0.05² = 125.1 counts
    // against 250.
    r.at(51);
    assert_eq!(r.read(0x6077, 0), 6);
    let a_r = 1.001e-3 * TAU / (1e-4 * TAU / 10_000.0);
    let rotor = (0.5 * a_r * 0.05 * 0.05).round() as i64;
    assert_eq!((r.demand(), r.pos()), (250, rotor));
    assert_eq!(r.read(0x60F4, 0), 250 - rotor);
    r.at(751);
    assert_eq!(r.demand(), 10_000);
    assert_eq!(r.pos(), 10_000 - lost);
    assert_eq!(r.read(0x60F4, 0), lost);
    assert_eq!(lost % 50, 0);
    r.at(2000);
    assert_eq!(r.pos(), 9000);
}

#[test]
fn an_open_loop_stepper_counts_commanded_steps() {
    let mut r = stepper_move(200_000, false);
    r.at(2000);
    assert_eq!(r.pos(), 10_000);
    assert_eq!(r.read(0x60F4, 0), 0);
    // The rotor itself has lost the steps.
    assert_eq!(
        r.drive.rotor_position().round() as i64,
        10_000 - lost_counts()
    );
}

#[test]
fn a_stepper_with_too_much_load_cannot_hold() {
    // 0.01 N·m of load against 6.29e-3 N·m of pull-out torque: the rotor slips backwards at
    // (6.29e-3 − 0.01) N·m over the inertia from the enable at 1 ms.
    let mut config = stepper(true);
    config.motor.load_torque = 0.01;
    let mut r = Rig::new(dictionary(&[]), config);
    r.enable(1);
    r.at(101);
    let a = (TAU * 1.001e-3 - 0.01) / (1e-4 * TAU / 10_000.0);
    assert_eq!(r.pos(), (0.5 * a * 0.1 * 0.1).round() as i64); // −2954
    assert_eq!(r.read(0x60F4, 0), -r.pos());
}

#[test]
fn a_servo_follows_and_holds_against_a_load() {
    let config = DriveConfig {
        motor: MotorConfig {
            load_torque: 0.5,
            ..MotorConfig::default()
        },
        ..DriveConfig::default()
    };
    let mut r = Rig::new(dictionary(&[]), config);
    r.enable(1);
    // Holding: 500 ‰ of the rated torque against the load from the first tick, no drift.
    r.at(2);
    assert_eq!((r.pos(), r.read(0x6077, 0)), (0, 500));
    r.at(500);
    assert_eq!(r.pos(), 0);
    assert_eq!(r.read(0x6077, 0), 500);
    r.set(0x607A, 0, 2000);
    r.cw(ENABLE | NEW_SETPOINT);
    // Started at 500 ms: 1 s in, 50 + 900 counts.
    r.at(1500);
    assert_eq!((r.demand(), r.pos(), r.read(0x60F4, 0)), (950, 950, 0));
    r.at(2600);
    assert_eq!(r.pos(), 2000);
    assert_eq!(r.sw(), ENABLED | 0x1000 | TR);
}

#[test]
fn the_torque_limit_makes_a_servo_fall_behind() {
    // 0x6072 = 1 ‰ of 1 N·m: at most 0.001 / (1e-4 · 2π / 10 000) = 15 915 counts/s² from rest,
    // so 20 ms into a ramp of 100 000 counts/s² (demand: 5 counts of ramp, then 10 at 1000
    // counts/s) the rotor is at most ½ · 15 915 · 0.02² = 3.2 counts along, at full torque. It
    // catches up on the cruise, which needs only the friction torque.
    let mut r = Rig::with(&[(0x6072, 0, 1), (0x6083, 0, 100_000)]);
    r.enable(1);
    r.set(0x607A, 0, 100_000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(21);
    assert_eq!(r.demand(), 15);
    assert_eq!(r.read(0x6077, 0), 1);
    let pos = r.pos();
    assert!(pos <= 3, "position {pos}");
    assert_eq!(r.read(0x60F4, 0), 15 - pos);
    r.at(1001);
    assert_eq!((r.demand(), r.pos(), r.read(0x60F4, 0)), (995, 995, 0));
}

/// 0x6077 torque actual is per mille of the rated torque 0x6076 (CiA 402-2, objects 0x6076 and
/// 0x6077): holding against a load of 0.25 N·m with 0x6076 = 500 mN·m reads 500 ‰.
#[test]
fn the_torque_actual_is_per_mille_of_the_rated_torque() {
    let config = DriveConfig {
        motor: MotorConfig {
            load_torque: 0.25,
            ..MotorConfig::default()
        },
        ..DriveConfig::default()
    };
    let mut r = Rig::new(dictionary(&[(0x6076, 0, 500)]), config);
    r.enable(1);
    r.at(500);
    assert_eq!(r.pos(), 0);
    assert_eq!(r.read(0x6077, 0), 500);
    assert_eq!(r.read(0x6074, 0), 500);
}

/// A relative move with 0x60F2 = 2 counts from the position actual value (CiA 402-2, positioning
/// option code): after the stepper lost 1000 counts, 0x6064 reads 9000 where the demand is 10 000,
/// so +500 is the target 9500, which the demand moves to.
#[test]
fn relative_to_the_actual_position_of_a_stepper_that_lost_steps() {
    let mut r = stepper_move(200_000, true);
    r.at(2000);
    assert_eq!((r.demand(), r.pos()), (10_000, 9000));
    r.set(0x6083, 0, 50_000);
    r.set(0x60F2, 0, 2);
    r.set(0x607A, 0, 500);
    r.cw(ENABLE | NEW_SETPOINT | RELATIVE);
    r.at(3000);
    assert_eq!((r.demand(), r.pos()), (9500, 8500));
    assert_eq!(r.sw(), ENABLED | 0x1000 | TR);
}

/// Target reached waits for 0x6064 within the position window 0x6067 of the target (CiA 402-2,
/// profile position mode): after its lost steps the stepper stands at 9000, 1000 counts short of
/// 10 000, outside a window of 100.
#[test]
fn a_stepper_that_lost_steps_is_outside_the_position_window() {
    let mut r = stepper_move(200_000, true);
    r.set(0x6067, 0, 100);
    r.at(2000);
    assert_eq!((r.demand(), r.pos()), (10_000, 9000));
    assert_eq!(r.sw(), ENABLED);
}

/// Enabled again after losing steps, a stepper locks where its rotor stands (CiA 402-2,
/// transition 4 takes the actual position as the demand): with an encoder 0x6064 and 0x6062 both
/// read 9000 and stay there; without one 0x6064 goes on counting the commanded 10 000, the rotor
/// stays 1000 counts behind, and a move of +1000 takes both 1000 counts on.
#[test]
fn a_stepper_enabled_again_locks_where_its_rotor_stands() {
    let mut r = stepper_move(200_000, true);
    r.at(2000);
    r.cw(DISABLE_VOLTAGE);
    r.cw(SHUTDOWN);
    r.cw(ENABLE);
    r.at(2100);
    assert_eq!((r.demand(), r.pos()), (9000, 9000));
    let mut r = stepper_move(200_000, false);
    r.at(2000);
    r.cw(DISABLE_VOLTAGE);
    r.cw(SHUTDOWN);
    r.cw(ENABLE);
    r.at(2100);
    assert_eq!((r.demand(), r.pos()), (10_000, 10_000));
    assert_eq!(r.drive.rotor_position().round() as i64, 9000);
    r.set(0x6083, 0, 50_000);
    r.set(0x607A, 0, 11_000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(3000);
    assert_eq!((r.demand(), r.pos()), (11_000, 11_000));
    assert_eq!(r.drive.rotor_position().round() as i64, 10_000);
}

/// A servo holds its position against a torque it does not expect: the torque offset 0x60B2 fed
/// forward in csp (100 ‰ of 1 N·m) with nothing to push against is taken back by the velocity
/// loop's integral action, and the axis stands at its demand with no torque left (CiA 402-2,
/// cyclic synchronous position mode, 0x60B2). Without it the position loop alone would leave
/// 0.1 N·m / (kv · kp) = 0.1 / (1e-4 · 2π / 10 000 · 250 · 50) ≈ 127 counts of error.
#[test]
fn a_servo_takes_back_an_unexpected_torque() {
    let mut r = Rig::with(&[]);
    r.enable(8);
    r.set(0x60B2, 0, 100);
    r.at(2001);
    assert_eq!((r.demand(), r.pos(), r.read(0x60F4, 0)), (0, 0, 0));
    assert_eq!(r.read(0x6077, 0), 0);
}

/// A stepper cruising gives the torque its friction takes: 1e-3 N·m·s/rad at 10 000 counts/s
/// (2π rad/s) is 2π · 1e-3 N·m, 6 ‰ of 1 N·m in 0x6077 (CiA 402-2, torque actual value).
#[test]
fn a_cruising_stepper_gives_its_friction_torque() {
    let config = DriveConfig {
        motor: MotorConfig {
            kind: MotorKind::Stepper,
            ..MotorConfig::default()
        },
        ..DriveConfig::default()
    };
    let dict = dictionary(&[(0x6081, 0, 10_000), (0x6083, 0, 100_000)]);
    let mut r = Rig::new(dict, config);
    r.enable(1);
    r.set(0x607A, 0, 100_000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(500);
    assert_eq!(r.read(0x606C, 0), 10_000);
    assert_eq!(r.read(0x6077, 0), 6);
}

/// The steps lost are the whole full steps nearest to the distance the rotor fell behind when it
/// catches the demand's speed again, its position then taken at the mean of its and the demand's
/// speed over that tick: at 24 000 counts/s 28.74 steps (29, 1450 counts), at 27 000 counts/s
/// 36.38 steps (36, 1800 counts).
#[test]
fn the_steps_lost_are_the_nearest_whole_steps() {
    for (v, lost) in [(24_000, 1450), (27_000, 1800)] {
        assert_eq!(lost_counts_at(v as f64), lost, "{v} counts/s");
        let dict = dictionary(&[(0x6081, 0, v), (0x6083, 0, 200_000), (0x6084, 0, 50_000)]);
        let mut r = Rig::new(dict, stepper(true));
        r.enable(1);
        r.set(0x607A, 0, 200_000);
        r.cw(ENABLE | NEW_SETPOINT);
        r.at(1001);
        assert_eq!(r.read(0x606C, 0), v, "{v} counts/s");
        assert_eq!(r.read(0x60F4, 0), lost, "{v} counts/s");
    }
}
