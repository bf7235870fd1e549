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
    start_with(method, sim, &[])
}

/// As [`start`], with `changes` to the dictionary besides.
fn start_with(method: i64, sim: SimConfig, changes: &[(u16, u8, i64)]) -> Rig {
    let config = DriveConfig {
        sim,
        ..DriveConfig::default()
    };
    let mut dict = vec![(0x6098, 0, method), (0x607C, 0, 100)];
    dict.extend_from_slice(changes);
    let mut r = Rig::new(dictionary(&dict), config);
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
    r.drive.set_input(r.now, 2, Some(false));
    r.enable(6);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(500);
    assert_eq!(r.read(0x60FD, 0), 0);
    r.drive.set_input(r.now, 2, Some(true));
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

/// Halt during the return to the home position (CiA 402-2, halt bit 8): the axis brakes on the
/// halt option code's ramp (0x605D = 1: 0x609A in homing) and stays where it stops. Homing is
/// attained (the position reads the home offset at the home point), not completed: the axis does
/// not stand there (status 0x1000, "homing attained, target not reached").
#[test]
fn halt_stops_the_return_to_the_home_position() {
    // Method 34: the index pulse at 2500 is found at 5.012 s after the start, the demand at
    // 2499.75 and 500 counts/s; the return brakes at 20 000 counts/s². 1 ms later the demand is at
    // 2499.75 + 0.5 − 0.01 = 2500.24 and 480 counts/s; halted there it stops 480² / 40 000 = 5.76
    // counts on, 24 ms later: at 2506, which reads 106.
    let mut r = start(34, step_switch());
    r.at(5013);
    assert_eq!(r.sw(), ENABLED | ATTAINED);
    r.at(5014);
    assert_eq!(r.sw(), ENABLED | ATTAINED);
    r.cw(ENABLE | NEW_SETPOINT | HALT);
    r.at(5037);
    assert_eq!(r.read(0x606B, 0), 20);
    r.at(5038);
    assert_eq!((r.read(0x606B, 0), r.demand()), (0, 106));
    r.at(5200);
    assert_eq!((r.demand(), r.pos()), (106, 106));
    assert_eq!(r.sw(), ENABLED | ATTAINED);
    assert_eq!(r.drive.homing_status(), HomingStatus::Attained);
    // Released, the axis stays; a new start homes again and completes at the home position.
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(5300);
    assert_eq!(r.sw(), ENABLED | ATTAINED);
    r.cw(ENABLE);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.sw(), ENABLED | IN_PROGRESS);
    r.at(30_000);
    assert_eq!((r.sw(), r.pos()), (ENABLED | COMPLETED, 100));
    assert_eq!(r.drive.rotor_position().round() as i64, 12_500);
}

/// A quick stop during the return to the home position (0x605A = 6: stay in Quick stop active):
/// enabled again (transition 16) the axis stands short of the home position, homing attained,
/// not completed (CiA 402-2, homing mode status). The numbers of the test above: at 5014 ms at
/// 2500.24 and 480 counts/s; 0x6085 = 100 000 counts/s² stops it 1.15 counts on, at 2501.4.
#[test]
fn a_quick_stop_during_the_return_leaves_homing_attained() {
    let mut r = start_with(34, step_switch(), &[(0x605A, 0, 6)]);
    r.at(5014);
    assert_eq!(r.sw(), ENABLED | ATTAINED);
    r.cw(QUICK_STOP | NEW_SETPOINT);
    r.at(5100);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!((r.sw(), r.pos()), (ENABLED | ATTAINED, 101));
    r.at(5200);
    assert_eq!((r.sw(), r.pos()), (ENABLED | ATTAINED, 101));
    assert_eq!(r.drive.homing_status(), HomingStatus::Attained);
}

/// Method 19 on a forced home switch (0x60FD bit 2): active at 501 ms (at 900, as in the test
/// above), then the search for its falling edge runs back at 500 counts/s (100 ms to a stop at
/// 1000, 25 ms to −500 counts/s at 993.75) until the input falls at 1001 ms: at 993.75 − 187.5 =
/// 806.25, count 806, the home position.
#[test]
fn a_forced_home_switch_gives_the_falling_edge_where_it_was_seen() {
    let mut r = Rig::new(
        dictionary(&[(0x6098, 0, 19), (0x607C, 0, 100)]),
        DriveConfig::default(),
    );
    r.drive.set_input(r.now, 2, Some(false));
    r.enable(6);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(500);
    r.drive.set_input(r.now, 2, Some(true));
    r.at(501);
    assert_eq!(r.sw(), ENABLED | IN_PROGRESS);
    r.at(1000);
    assert_eq!(r.read(0x606B, 0), -500);
    r.drive.set_input(r.now, 2, Some(false));
    r.at(1001);
    assert_eq!(r.read(0x60FD, 0), 0);
    assert_eq!(r.sw(), ENABLED | ATTAINED);
    assert_eq!(r.pos(), 100);
    r.at(3000);
    assert_eq!(r.sw(), ENABLED | COMPLETED);
    assert_eq!(r.drive.rotor_position().round() as i64, 806);
    assert_eq!(r.pos(), 100);
}

/// Method 37 where the axis stands away from 0: the present position is home at once, 0x6064
/// reads the home offset there (CiA 402-2, homing method 37).
#[test]
fn method_37_homes_at_once_where_the_axis_stands() {
    let mut r = Rig::new(
        dictionary(&[(0x6098, 0, 37), (0x607C, 0, 100)]),
        DriveConfig::default(),
    );
    r.enable(1);
    r.set(0x607A, 0, 2000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.cw(ENABLE);
    r.at(3000);
    assert_eq!(r.pos(), 2000);
    r.set(0x6060, 0, 6);
    assert_eq!(r.sw(), ENABLED | NOT_STARTED);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.sw(), ENABLED | COMPLETED);
    assert_eq!((r.pos(), r.demand()), (100, 100));
}

/// After the first switch edge the search runs at 0x6099:02 (CiA 402-2, homing speeds). Method 3:
/// the home switch at 5000 is met at 2000 counts/s at 2.55 s after the start; the axis reverses
/// (100 ms to a stop at 5100, 25 ms to −500 counts/s at 5093.75) and runs back at 500 counts/s:
/// 324 ms later, at 3000 ms, at 4931.75.
#[test]
fn the_search_for_zero_runs_at_the_second_homing_speed() {
    let mut r = start(3, step_switch());
    r.at(1000);
    assert_eq!(r.read(0x606B, 0), 2000);
    r.at(3000);
    assert_eq!(r.read(0x606B, 0), -500);
    assert_eq!(r.read(0x606C, 0), -500);
    assert_eq!(r.pos(), 4932);
    assert_eq!(r.sw(), ENABLED | IN_PROGRESS);
}

/// The search for the index pulse ends in a homing error when it runs into the limit switch of
/// its direction. Method 33 towards the pulse at −7500 meets the negative limit switch at −1000:
/// 6.25 counts of ramp, then 500 counts/s: −999.75 at 2.012 s after the start; 25 ms of braking
/// at 0x609A, 6.25 counts.
#[test]
fn the_index_search_into_a_limit_switch_is_a_homing_error() {
    let sim = SimConfig {
        negative_limit: Some(-1000),
        ..step_switch()
    };
    let mut r = start(33, sim);
    r.at(2012);
    assert_eq!((r.sw(), r.pos()), (ENABLED | IN_PROGRESS, -999));
    r.at(2013);
    assert_eq!((r.sw(), r.pos()), (ENABLED | LIMIT | ERROR_MOVING, -1000));
    r.at(2037);
    assert_eq!(r.sw(), ENABLED | LIMIT | ERROR_MOVING);
    r.at(2038);
    assert_eq!((r.sw(), r.pos()), (ENABLED | LIMIT | ERROR_STANDING, -1006));
}

/// A search may not leave the software position limits 0x607D (CiA 402-2), which are on when min
/// < max. Method 34 with 0x607D = −1000…1000: 0x6064 reads 1001 at 2.014 s after the start
/// (1000.75), a homing error braking 6.25 counts.
#[test]
fn a_search_beyond_the_software_limits_is_a_homing_error() {
    let limits = [(0x607D, 1, -1000), (0x607D, 2, 1000)];
    let mut r = start_with(34, step_switch(), &limits);
    r.at(2014);
    assert_eq!((r.sw(), r.pos()), (ENABLED | IN_PROGRESS, 1000));
    r.at(2015);
    assert_eq!((r.sw(), r.pos()), (ENABLED | ERROR_MOVING, 1001));
    r.at(2039);
    assert_eq!(r.sw(), ENABLED | ERROR_MOVING);
    r.at(2040);
    assert_eq!((r.sw(), r.pos()), (ENABLED | ERROR_STANDING, 1007));
    // min = max: no limits, the search runs to the pulse at 2500.
    let off = [(0x607D, 1, 500), (0x607D, 2, 500)];
    let mut r = start_with(34, step_switch(), &off);
    r.at(5012);
    assert_eq!(r.sw(), ENABLED | IN_PROGRESS);
    r.at(5013);
    assert_eq!((r.sw(), r.pos()), (ENABLED | ATTAINED, 100));
}

/// An index pulse on the switch edge itself is the home position, taken once the axis moves past
/// it. Method 3 with the pulses at 4999 + n · 10 000: the edge at 4999 going back at 500 counts/s
/// (5093.75 at 2.675 s after the start, as above) is met at 2.864 s (4999.25); the axis reads 4999
/// there and 1 ms later (4998.75), and 4998 at 2.866 s.
#[test]
fn an_index_pulse_on_the_switch_edge_going_back() {
    let sim = SimConfig {
        index_offset: 4999,
        ..step_switch()
    };
    let mut r = start(3, sim);
    r.at(2865);
    assert_eq!((r.sw(), r.pos()), (ENABLED | IN_PROGRESS, 4999));
    r.at(2866);
    assert_eq!((r.sw(), r.pos()), (ENABLED | IN_PROGRESS, 4999));
    r.at(2867);
    assert_eq!((r.sw(), r.pos()), (ENABLED | ATTAINED, 99));
    r.at(4000);
    assert_eq!(r.sw(), ENABLED | COMPLETED);
    assert_eq!(r.drive.rotor_position().round() as i64, 4999);
}

/// As above going on: method 4 with the pulses at 5000 + n · 10 000 meets the edge at 5000 at
/// 2000 counts/s at 2.55 s after the start; 1 ms later the axis is at 5002 and past the pulse.
#[test]
fn an_index_pulse_on_the_switch_edge_going_on() {
    let sim = SimConfig {
        index_offset: 5000,
        ..step_switch()
    };
    let mut r = start(4, sim);
    r.at(2551);
    assert_eq!((r.sw(), r.pos()), (ENABLED | IN_PROGRESS, 5000));
    r.at(2552);
    assert_eq!((r.sw(), r.pos()), (ENABLED | ATTAINED, 102));
    r.at(4000);
    assert_eq!(r.sw(), ENABLED | COMPLETED);
    assert_eq!(r.drive.rotor_position().round() as i64, 5000);
}

/// The start command repeated (an RPDO carries the control word every cycle) is no new start and
/// no interruption: bit 4 stays 1 (CiA 402-2, homing operation start).
#[test]
fn bit_4_held_over_several_writes_keeps_homing() {
    let mut r = start(34, step_switch());
    r.at(1001);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.sw(), ENABLED | IN_PROGRESS);
    r.at(5012);
    assert_eq!((r.sw(), r.pos()), (ENABLED | IN_PROGRESS, 2499));
    r.at(5013);
    assert_eq!((r.sw(), r.pos()), (ENABLED | ATTAINED, 100));
}

/// After homing, profile positions are in the homed reference (CiA 402-2, home offset 0x607C):
/// method 35 at raw 0 with 0x607C = 100 makes the axis read 100 there, so the target 1100 lies
/// 1000 counts on (1.1 s at the rig's profile).
#[test]
fn profile_positions_after_homing_are_in_the_homed_reference() {
    let mut r = start(35, step_switch());
    assert_eq!(r.sw(), ENABLED | COMPLETED);
    r.set(0x6060, 0, 1);
    r.cw(ENABLE);
    r.set(0x607A, 0, 1100);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(1101);
    assert_eq!((r.pos(), r.demand()), (1100, 1100));
    assert_eq!(r.drive.rotor_position().round() as i64, 1000);
    assert_eq!(r.sw(), ENABLED | 0x1400);
}

/// csp targets after homing are in the homed reference too: 105 is 5 counts from where method 35
/// made the axis read 100 (CiA 402-2, cyclic synchronous position mode).
#[test]
fn cyclic_positions_after_homing_are_in_the_homed_reference() {
    let mut r = start(35, step_switch());
    r.set(0x6060, 0, 8);
    r.set(0x607A, 0, 105);
    r.sync_at(2);
    r.at(3);
    assert_eq!(r.demand(), 105);
    r.at(200);
    assert_eq!((r.demand(), r.pos()), (105, 105));
    assert_eq!(r.drive.rotor_position().round() as i64, 5);
}

/// A home cam narrower than one tick's travel is still seen, entering and leaving within the same
/// tick (CiA 402-2, homing methods 7–14; the drive latches the edges exactly). Method 8 with the
/// cam at 5002 only, searching for switch at 5000 counts/s and for zero at 10 000 counts/s: the
/// search meets the cam at 1127 ms (5000 → 5005), brakes to a stop at 5630 (250 ms) and comes
/// back accelerating at 20 000 counts/s²: 5005 at 1627 ms, 4999.99 at 1628 ms, past the cam's both
/// edges; then forwards again through the cam (its left edge) to the index pulse at 12 500.
#[test]
fn a_cam_narrower_than_a_tick_is_seen() {
    let sim = SimConfig {
        home_switch: Some(5002),
        home_switch_end: Some(5003),
        ..cam_right()
    };
    let speeds = [(0x6099, 1, 5000), (0x6099, 2, 10_000)];
    let mut r = start_with(8, sim, &speeds);
    r.at(1627);
    assert_eq!((r.sw(), r.pos()), (ENABLED | IN_PROGRESS, 5005));
    r.at(1628);
    assert_eq!((r.sw(), r.pos()), (ENABLED | IN_PROGRESS, 5000));
    // The left edge found, the search turns forwards (the demand's speed falls towards it).
    r.at(1629);
    assert_eq!(r.read(0x606B, 0), -5000);
    r.at(60_000);
    assert_eq!(r.sw(), ENABLED | COMPLETED);
    assert_eq!(r.drive.rotor_position().round() as i64, 12_500);
    assert_eq!(r.pos(), 100);
}

/// A limit switch counts for a search once the axis moves towards it, not at the turning point
/// of a reversal. Method 3 on a machine whose negative limit switch is active up to 6000: the home
/// switch is met at 2551 ms (5000, at 2000 counts/s), the axis turns at 5100 at 2651 ms (speed 0
/// exactly) and moves towards the active switch from the next tick: a homing error then, braking
/// 1 ms from 20 counts/s.
#[test]
fn a_limit_switch_counts_once_the_search_moves_towards_it() {
    let sim = SimConfig {
        negative_limit: Some(6000),
        ..step_switch()
    };
    let mut r = start(3, sim);
    r.at(2651);
    assert_eq!(
        (r.sw(), r.read(0x606B, 0)),
        (ENABLED | LIMIT | IN_PROGRESS, 0)
    );
    r.at(2652);
    assert_eq!(r.sw(), ENABLED | LIMIT | ERROR_MOVING);
    r.at(2653);
    assert_eq!((r.sw(), r.pos()), (ENABLED | LIMIT | ERROR_STANDING, 5100));
}

/// The same for the search of the index pulse: with a forced home switch (method 3) the falling
/// edge may come while the axis still runs the other way. Active at 501 ms (at 900), inactive at
/// 551 ms (at 975, braking at 1000 counts/s): the search for the pulse at −7500 turns at 1000 at
/// 601 ms and moves into the negative limit switch (active up to 5000) from the next tick.
#[test]
fn a_limit_switch_counts_once_the_index_search_moves_towards_it() {
    let config = DriveConfig {
        sim: SimConfig {
            negative_limit: Some(5000),
            index_offset: 2500,
            ..SimConfig::default()
        },
        ..DriveConfig::default()
    };
    let mut r = Rig::new(dictionary(&[(0x6098, 0, 3), (0x607C, 0, 100)]), config);
    r.drive.set_input(r.now, 2, Some(false));
    r.enable(6);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(500);
    r.drive.set_input(r.now, 2, Some(true));
    r.at(550);
    r.drive.set_input(r.now, 2, Some(false));
    r.at(551);
    assert_eq!((r.read(0x606B, 0), r.pos()), (1000, 975));
    r.at(601);
    assert_eq!(
        (r.sw(), r.read(0x606B, 0)),
        (ENABLED | LIMIT | IN_PROGRESS, 0)
    );
    r.at(602);
    assert_eq!(r.sw(), ENABLED | LIMIT | ERROR_MOVING);
    r.at(603);
    assert_eq!((r.sw(), r.pos()), (ENABLED | LIMIT | ERROR_STANDING, 1000));
}

/// Method 37 with the demand a whole count from the actual position: the home is where the axis
/// is (0x6064 = 0x607C), and the demand, 1 count off, returns to it: attained, not yet completed.
/// A load of 0.01 N·m against a torque limit of 1 ‰ (0.001 N·m), without friction, pulls the
/// holding axis back at 0.009 / (1e-4 · 2π / 10 000) = 143 239 counts/s²: −0.645 (count −1) 3 ms
/// after the enable at 1 ms, where the demand is still 0.
#[test]
fn method_37_with_the_demand_a_count_away_returns_to_the_axis() {
    let config = DriveConfig {
        motor: ds402::drive::MotorConfig {
            load_torque: 0.01,
            friction: 0.0,
            ..Default::default()
        },
        ..DriveConfig::default()
    };
    let mut r = Rig::new(
        dictionary(&[(0x6098, 0, 37), (0x607C, 0, 100), (0x6072, 0, 1)]),
        config,
    );
    r.enable(6);
    r.at(4);
    assert_eq!((r.pos(), r.demand()), (-1, 0));
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(
        (r.sw(), r.pos(), r.demand()),
        (ENABLED | ATTAINED, 100, 101)
    );
}

/// Methods 33 and 34 starting on an index pulse: the home is the next pulse in the search
/// direction, a revolution away, not the one under the axis (CiA 402-2, homing methods 33 and 34:
/// the search moves to find a pulse). Pulses at n · 10 000.
#[test]
fn methods_33_and_34_on_a_pulse_home_on_the_next_one() {
    for (method, home) in [(33, -10_000), (34, 10_000)] {
        let sim = SimConfig {
            index_offset: 0,
            ..step_switch()
        };
        let mut r = start(method, sim);
        assert_eq!(r.sw(), ENABLED | IN_PROGRESS, "method {method}");
        r.at(30_000);
        assert_eq!(r.sw(), ENABLED | COMPLETED, "method {method}");
        assert_eq!(
            r.drive.rotor_position().round() as i64,
            home,
            "method {method}"
        );
        assert_eq!(r.pos(), 100, "method {method}");
    }
}

/// Homing's status moves on in homing mode only (CiA 402-2, modes of operation): left for pp
/// during the return, homing stays attained even where a pp move brings the axis to the home
/// position (0x6064 = 0x607C = 100); back in homing mode, standing there, it completes at the next
/// tick.
#[test]
fn homing_completes_in_homing_mode_only() {
    let mut r = start(34, step_switch());
    r.at(5014);
    assert_eq!(r.sw(), ENABLED | ATTAINED);
    r.set(0x6060, 0, 1);
    r.set(0x607A, 0, 100);
    r.cw(ENABLE);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(6000);
    assert_eq!((r.pos(), r.demand()), (100, 100));
    assert_eq!(r.drive.homing_status(), HomingStatus::Attained);
    r.set(0x6060, 0, 6);
    assert_eq!(r.sw(), ENABLED | ATTAINED);
    r.at(6001);
    assert_eq!(r.sw(), ENABLED | COMPLETED);
}
