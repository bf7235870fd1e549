//! Homing mode of the generic drive: every method it runs (1–14, 17–30, 33, 34, 35, 37) on a
//! simulated machine, with the home position the method defines, 0x6064 = home offset there, and
//! the status pair (bits 13, 12, 10 under mask 0x3400, as python-canopen reads it) at the end;
//! the status sequence, halt, forced inputs, and the homing errors.
//!
//! The machine: 10 000 counts/rev with an index pulse at 2500 + n · 10 000 (…, −17 500, −7500,
//! 2500, 12 500, 22 500, …). Homing speeds 2000 counts/s (search for switch) and 500 (search for
//! zero), 20 000 counts/s²; home offset 0x607C = 100. Every run starts at raw position 0.

mod drive_rig;

use drive_rig::*;
use ds402::drive::{DriveConfig, HomingStatus, SimConfig};

const ENABLED: u16 = 0x0237;
const STATUS_MASK: u16 = 0x3400;
const NOT_STARTED: u16 = 0x0400;
const IN_PROGRESS: u16 = 0x0000;
const ATTAINED: u16 = 0x1000;
const COMPLETED: u16 = 0x1400;
const ERROR_MOVING: u16 = 0x2000;
const ERROR_STANDING: u16 = 0x2400;
const LIMIT: u16 = 0x0800;

/// Limit switches at ±20 000, a positive home switch: active at and above 5000.
fn step_switch() -> SimConfig {
    SimConfig {
        negative_limit: Some(-20_000),
        positive_limit: Some(20_000),
        home_switch: Some(5000),
        home_switch_end: None,
        index_offset: 2500,
    }
}

/// As [`step_switch`] with the home switch active at and above −3000 (active at the start).
fn step_switch_behind() -> SimConfig {
    SimConfig {
        home_switch: Some(-3000),
        ..step_switch()
    }
}

/// A negative home switch: active below 5000 (active at the start).
fn negative_switch() -> SimConfig {
    SimConfig {
        home_switch: Some(i64::MIN),
        home_switch_end: Some(5000),
        ..step_switch()
    }
}

/// A negative home switch active below −3000 (inactive at the start).
fn negative_switch_ahead() -> SimConfig {
    SimConfig {
        home_switch: Some(i64::MIN),
        home_switch_end: Some(-3000),
        ..step_switch()
    }
}

/// Limit switches at ±30 000 and a home cam active over [5000, 15 000).
fn cam_right() -> SimConfig {
    SimConfig {
        negative_limit: Some(-30_000),
        positive_limit: Some(30_000),
        home_switch: Some(5000),
        home_switch_end: Some(15_000),
        index_offset: 2500,
    }
}

/// Limit switches at ±30 000 and a home cam active over [−15 000, −5000).
fn cam_left() -> SimConfig {
    SimConfig {
        home_switch: Some(-15_000),
        home_switch_end: Some(-5000),
        ..cam_right()
    }
}

/// A machine of the table below.
type Machine = fn() -> SimConfig;

/// Homing with `method` on `sim`, started at 1 ms in Operation enabled.
fn start(method: i64, sim: SimConfig) -> Rig {
    let config = DriveConfig {
        sim,
        ..DriveConfig::default()
    };
    let mut r = Rig::new(dictionary(&[(0x6098, 0, method), (0x607C, 0, 100)]), config);
    r.enable(6);
    assert_eq!(r.sw() & STATUS_MASK, NOT_STARTED);
    assert_eq!(r.drive.homing_status(), HomingStatus::NotStarted);
    r.cw(ENABLE | NEW_SETPOINT);
    r
}

#[test]
fn every_method_finds_its_home_position() {
    // (method, machine, raw position of home)
    let cases: &[(i64, Machine, i64)] = &[
        // Limit switch and index pulse: beyond the point where the switch becomes inactive.
        (1, step_switch, -17_500),
        (2, step_switch, 12_500),
        // Positive home switch: index pulse left (3) or right (4) of the edge at 5000 / −3000.
        (3, step_switch, 2500),
        (3, step_switch_behind, -7500),
        (4, step_switch, 12_500),
        (4, step_switch_behind, 2500),
        // Negative home switch: index pulse right (5) or left (6) of the edge.
        (5, negative_switch, 12_500),
        (5, negative_switch_ahead, 2500),
        (6, negative_switch, 2500),
        (6, negative_switch_ahead, -7500),
        // Home cam and positive limit switch (7–10), negative limit switch (11–14).
        (7, cam_right, 2500),
        (7, cam_left, -17_500), // reverses on the positive limit switch
        (8, cam_right, 12_500),
        (9, cam_right, 12_500),
        (10, cam_right, 22_500),
        (11, cam_left, 2500),
        (11, cam_right, 22_500), // reverses on the negative limit switch
        (12, cam_left, -7500),
        (13, cam_left, -7500),
        (14, cam_left, -17_500),
        // 17–30: the switch edge itself, the first count with the new level.
        (17, step_switch, -19_999),
        (18, step_switch, 19_999),
        (19, step_switch, 4999),
        (20, step_switch, 5000),
        (21, negative_switch, 5000),
        (22, negative_switch, 4999),
        (23, cam_right, 4999),
        (24, cam_right, 5000),
        (25, cam_right, 14_999),
        (26, cam_right, 15_000),
        (27, cam_left, -5000),
        (28, cam_left, -5001),
        (29, cam_left, -15_000),
        (30, cam_left, -15_001),
        // Index pulse only.
        (33, step_switch, -7500),
        (34, step_switch, 2500),
        // The present position.
        (35, step_switch, 0),
        (37, step_switch, 0),
    ];
    for &(method, sim, home) in cases {
        let mut r = start(method, sim());
        r.at(120_000);
        assert_eq!(
            r.drive.homing_status(),
            HomingStatus::Completed,
            "method {method}"
        );
        assert_eq!(r.sw(), ENABLED | COMPLETED, "method {method}");
        assert_eq!(
            r.drive.rotor_position().round() as i64,
            home,
            "method {method}: home"
        );
        assert_eq!(r.pos(), 100, "method {method}: 0x6064 = home offset");
        assert_eq!(r.demand(), 100, "method {method}: 0x6062");
    }
}

#[test]
fn method_35_homes_at_once() {
    let mut r = start(35, SimConfig::default());
    assert_eq!(r.sw(), ENABLED | COMPLETED);
    assert_eq!(r.pos(), 100);
}

#[test]
fn status_sequence_of_method_34() {
    // The index pulse at 2500 at 500 counts/s: 25 ms of ramp (6.25 counts), then the rotor reads
    // 2500 at 5.012 s after the start (6.25 + 500 · 4.987 = 2499.75).
    let mut r = start(34, step_switch());
    assert_eq!(r.sw() & STATUS_MASK, IN_PROGRESS);
    r.at(5012);
    assert_eq!(r.sw(), ENABLED | IN_PROGRESS);
    assert_eq!(r.pos(), 2499);
    r.at(5013);
    // Attained: the position reads the home offset at the home point; braking and returning.
    assert_eq!(r.sw(), ENABLED | ATTAINED);
    assert_eq!(r.pos(), 100);
    r.at(5500);
    assert_eq!(r.sw(), ENABLED | COMPLETED);
    assert_eq!(r.pos(), 100);
    // Bit 4 back to 0 after completion changes nothing.
    r.cw(ENABLE);
    assert_eq!(r.sw(), ENABLED | COMPLETED);
}

#[test]
fn halt_interrupts_and_a_new_start_homes() {
    let mut r = start(34, step_switch());
    r.at(1001);
    r.cw(ENABLE | NEW_SETPOINT | HALT);
    // Braking at 0x609A (0x605D = 1 in homing): 25 ms from 500 counts/s.
    assert_eq!(r.sw(), ENABLED | IN_PROGRESS);
    assert_eq!(r.drive.homing_status(), HomingStatus::Interrupted);
    r.at(1026);
    assert_eq!(r.sw(), ENABLED | NOT_STARTED);
    r.at(2000);
    assert_eq!(r.sw(), ENABLED | NOT_STARTED);
    r.cw(ENABLE);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.sw(), ENABLED | IN_PROGRESS);
    r.at(12_000);
    assert_eq!(r.sw(), ENABLED | COMPLETED);
    assert_eq!(r.drive.rotor_position().round() as i64, 2500);
}

#[test]
fn bit_4_back_to_0_interrupts() {
    let mut r = start(34, step_switch());
    r.at(1001);
    r.cw(ENABLE);
    r.at(1100);
    assert_eq!(r.sw(), ENABLED | NOT_STARTED);
    assert_eq!(r.drive.homing_status(), HomingStatus::Interrupted);
}

#[test]
fn a_missing_switch_is_a_homing_error() {
    // (method, machine): the method needs a switch the machine lacks.
    let no_home = SimConfig {
        home_switch: None,
        ..step_switch()
    };
    let no_limits = SimConfig {
        negative_limit: None,
        positive_limit: None,
        ..cam_right()
    };
    let cases = [
        (3, no_home.clone()),
        (21, no_home.clone()),
        (8, no_home),
        (1, no_limits.clone()),
        (18, no_limits.clone()),
        (7, no_limits.clone()),
        (30, no_limits),
        (0, step_switch()),
    ];
    for (method, sim) in cases {
        let mut r = start(method, sim);
        assert_eq!(r.sw(), ENABLED | ERROR_STANDING, "method {method}");
        assert_eq!(r.drive.homing_status(), HomingStatus::Error);
        r.at(100);
        assert_eq!(r.pos(), 0, "method {method}: no motion");
    }
}

#[test]
fn a_search_into_a_limit_switch_is_a_homing_error() {
    // Method 5 expects a negative home switch; this machine's is positive (active above 5000), so
    // the search in negative direction runs into the negative limit switch at −20 000: 100 ms of
    // ramp (100 counts), then 19 900 counts at 2000 counts/s: at 10.051 s.
    let mut r = start(5, step_switch());
    r.at(10_050);
    assert_eq!(r.sw(), ENABLED | IN_PROGRESS);
    r.at(10_051);
    assert_eq!(r.pos(), -20_000);
    assert_eq!(r.sw(), ENABLED | LIMIT | ERROR_MOVING);
    // Braking at 0x609A: 100 ms, 100 counts.
    r.at(10_150);
    assert_eq!(r.sw(), ENABLED | LIMIT | ERROR_MOVING);
    r.at(10_151);
    assert_eq!(r.sw(), ENABLED | LIMIT | ERROR_STANDING);
    assert_eq!(r.pos(), -20_100);
    // No fault: homing errors are the mode's.
    assert_eq!(r.drive.error_code(), 0);
}

#[test]
fn a_second_limit_switch_after_the_reversal_is_a_homing_error() {
    // Method 7 with the cam beyond the positive limit switch: at +20 000 at 10.051 s (as below),
    // reverses there (0.2 s from +2000 to −2000 counts/s, back at +20 000), meets the negative
    // limit switch 40 000 counts later, at 30.251 s, and brakes 100 counts.
    let sim = SimConfig {
        home_switch: Some(50_000),
        home_switch_end: Some(60_000),
        ..step_switch()
    };
    let mut r = start(7, sim);
    r.at(10_251);
    assert_eq!((r.pos(), r.read(0x606C, 0)), (20_000, -2000));
    assert_eq!(r.sw() & STATUS_MASK, IN_PROGRESS);
    r.at(30_250);
    assert_eq!(r.sw(), ENABLED | IN_PROGRESS);
    r.at(30_251);
    assert_eq!(r.sw(), ENABLED | LIMIT | ERROR_MOVING);
    r.at(31_000);
    assert_eq!(r.sw(), ENABLED | LIMIT | ERROR_STANDING);
    assert_eq!(r.pos(), -20_100);
}

#[test]
fn a_forced_home_switch_gives_the_edge_where_it_was_seen() {
    // Method 20 (edge of a positive home switch, approached in positive direction) with the home
    // switch forced through 0x60FD: inactive at the start, active at 501 ms, when the axis is at
    // 100 + 2000 · 0.4 = 900.
    let mut r = start(20, SimConfig::default());
    // Not simulated and not forced: missing.
    assert_eq!(r.sw(), ENABLED | ERROR_STANDING);
    let mut r = Rig::new(
        dictionary(&[(0x6098, 0, 20), (0x607C, 0, 100)]),
        DriveConfig::default(),
    );
    r.drive.set_input(2, Some(false));
    r.enable(6);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(500);
    assert_eq!(r.read(0x60FD, 0), 0);
    r.drive.set_input(2, Some(true));
    r.at(501);
    assert_eq!(r.read(0x60FD, 0), 0b100);
    assert_eq!(r.sw(), ENABLED | ATTAINED);
    r.at(3000);
    assert_eq!(r.sw(), ENABLED | COMPLETED);
    assert_eq!(r.drive.rotor_position().round() as i64, 900);
    assert_eq!(r.pos(), 100);
}

#[test]
fn leaving_operation_enabled_interrupts_homing() {
    let mut r = start(34, step_switch());
    r.at(1001);
    r.cw(QUICK_STOP);
    assert_eq!(r.drive.homing_status(), HomingStatus::Interrupted);
}
