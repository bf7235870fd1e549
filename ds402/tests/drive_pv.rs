//! Profile velocity mode of the generic drive: the ramps of 0x6083/0x6084 to 0x60FF, target
//! reached (|0x606C − target| ≤ 0x606D held for 0x606E ms), status bit 12 "speed" (0 once |0x606C|
//! > 0x606F has held for 0x6070 ms), halt and the velocity limit.

mod drive_rig;

use drive_rig::*;

const ENABLED: u16 = 0x0237;
const TR: u16 = 0x0400;
const SPEED_ZERO: u16 = 0x1000;

/// pv in Operation enabled at 1 ms with a velocity window of 0 held for 20 ms; 0x60FF = 1000 at
/// 1 ms: 10 000 counts/s² up, 100 ms to 1000 counts/s (50 counts).
fn running(changes: &[(u16, u8, i64)]) -> Rig {
    let mut all = vec![(0x606D, 0, 0), (0x606E, 0, 20)];
    all.extend_from_slice(changes);
    let mut r = Rig::with(&all);
    r.enable(3);
    r.set(0x60FF, 0, 1000);
    assert_eq!(r.sw(), ENABLED | SPEED_ZERO);
    r
}

#[test]
fn ramp_target_reached_and_speed_bit() {
    let mut r = running(&[]);
    // 10 counts/s at 2 ms is not above the threshold of 10; 20 at 3 ms is.
    r.at(2);
    assert_eq!(r.read(0x606C, 0), 10);
    assert_eq!(r.sw(), ENABLED | SPEED_ZERO);
    r.at(3);
    assert_eq!(r.sw(), ENABLED);
    r.at(101);
    assert_eq!((r.read(0x606C, 0), r.pos()), (1000, 50));
    assert_eq!(r.sw(), ENABLED);
    // On target from 101 ms, for 20 ms.
    r.at(120);
    assert_eq!(r.sw(), ENABLED);
    r.at(121);
    assert_eq!(r.sw(), ENABLED | TR);
    r.at(1101);
    assert_eq!(r.pos(), 1050);
    assert_eq!(r.read(0x606B, 0), 1000);
}

#[test]
fn a_new_target_through_zero() {
    let mut r = running(&[]);
    r.at(1101);
    assert_eq!(r.sw(), ENABLED | TR);
    // −500: 0x6084 down to 0 in 100 ms (50 counts), then 0x6083 up to −500 in 50 ms.
    r.set(0x60FF, 0, -500);
    assert_eq!(r.sw(), ENABLED);
    r.at(1201);
    assert_eq!((r.read(0x606C, 0), r.pos()), (0, 1100));
    assert_eq!(r.sw(), ENABLED | SPEED_ZERO);
    r.at(1251);
    assert_eq!(r.read(0x606C, 0), -500);
    r.at(1270);
    assert_eq!(r.sw(), ENABLED);
    r.at(1271);
    assert_eq!(r.sw(), ENABLED | TR);
}

#[test]
fn halt_brakes_to_zero_and_target_reached_means_standing() {
    let mut r = running(&[]);
    r.at(301);
    r.cw(ENABLE | HALT);
    assert_eq!(r.sw(), ENABLED);
    // 0x605D = 1: 0x6084, 100 ms.
    r.at(400);
    assert_eq!(r.read(0x606C, 0), 10);
    assert_eq!(r.sw(), ENABLED | SPEED_ZERO);
    r.at(401);
    assert_eq!(r.read(0x606C, 0), 0);
    r.at(420);
    assert_eq!(r.sw(), ENABLED | SPEED_ZERO);
    r.at(421);
    assert_eq!(r.sw(), ENABLED | SPEED_ZERO | TR);
    // Released: back to 1000.
    r.cw(ENABLE);
    r.at(521);
    assert_eq!(r.read(0x606C, 0), 1000);
}

#[test]
fn the_target_velocity_is_limited() {
    // 0x607F = 2000: a target of 5000 runs at 2000 (200 ms of ramp).
    let mut r = running(&[(0x607F, 0, 2000)]);
    r.set(0x60FF, 0, 5000);
    r.at(201);
    assert_eq!(r.read(0x606C, 0), 2000);
    r.at(1000);
    assert_eq!(r.read(0x606C, 0), 2000);
    assert_eq!(r.sw(), ENABLED | TR);
}

#[test]
fn the_speed_bit_waits_for_the_threshold_time() {
    // 0x6070 = 30 ms: above 10 counts/s from 3 ms, bit 12 drops at 33 ms.
    let mut r = running(&[(0x6070, 0, 30)]);
    r.at(32);
    assert_eq!(r.sw(), ENABLED | SPEED_ZERO);
    r.at(33);
    assert_eq!(r.sw(), ENABLED);
}

#[test]
fn enabling_in_pv_runs_to_the_target_already_set() {
    let mut r = Rig::with(&[(0x60FF, 0, -1000)]);
    r.enable(3);
    r.at(101);
    assert_eq!((r.read(0x606C, 0), r.pos()), (-1000, -50));
}

#[test]
fn the_same_target_written_every_cycle_changes_nothing() {
    // An RPDO with 0x60FF every millisecond: target reached as when it is written once.
    let mut r = running(&[]);
    for ms in 2..=121u64 {
        r.set(0x60FF, 0, 1000);
        r.at(ms);
    }
    assert_eq!(r.sw(), ENABLED | TR);
}

/// A change of 0x6060 in Operation enabled starts the new mode at once (CiA 402-2, modes of
/// operation): pv ramps from the write to 0x60FF; a mode without motion of its own (csp without
/// SYNCs) stops on the slow-down ramp 0x6084, homing on 0x609A.
#[test]
fn a_mode_change_starts_the_mode_at_once() {
    let mut r = Rig::with(&[(0x60FF, 0, 1000)]);
    r.enable(1);
    r.at(10);
    r.set(0x6060, 0, 3);
    // 10 000 counts/s² from 10 ms: 500 counts/s at 60 ms, 1000 (50 counts) at 110 ms.
    r.at(60);
    assert_eq!(r.read(0x606B, 0), 500);
    r.at(110);
    assert_eq!((r.read(0x606B, 0), r.demand()), (1000, 50));
    // csp at 200 ms (at 140): 0x6084 = 10 000 counts/s², 100 ms, 50 counts.
    r.at(200);
    r.set(0x6060, 0, 8);
    r.at(250);
    assert_eq!(r.read(0x606B, 0), 500);
    r.at(300);
    assert_eq!((r.read(0x606B, 0), r.demand()), (0, 190));
    // pv again from 300 ms (50 counts of ramp, 240 at 400 ms, 340 at 500 ms), then homing:
    // 0x609A = 20 000 counts/s², 50 ms, 25 counts.
    r.set(0x6060, 0, 3);
    r.at(500);
    assert_eq!((r.read(0x606B, 0), r.demand()), (1000, 340));
    r.set(0x6060, 0, 6);
    r.at(525);
    assert_eq!(r.read(0x606B, 0), 500);
    r.at(550);
    assert_eq!((r.read(0x606B, 0), r.demand()), (0, 365));
    r.at(600);
    assert_eq!((r.read(0x606C, 0), r.pos()), (0, 365));
}

/// The following error is monitored in pp and csp only (CiA 402-2, position control function): in
/// pv an axis that cannot follow (no torque, 0x6072 = 0) shows no warning. The demand ramps at
/// 10 000 counts/s² from 1 ms: 13 counts at 52 ms, beyond the window of 10.
#[test]
fn the_following_error_is_not_monitored_in_pv() {
    let mut r = running(&[(0x6065, 0, 10), (0x6066, 0, 100)]);
    r.set(0x6072, 0, 0);
    r.at(52);
    assert_eq!((r.sw(), r.read(0x60F4, 0)), (ENABLED | SPEED_ZERO, 13));
}

/// pv ramps speed up at 0x6083 and slow down at 0x6084, and a change of direction slows down to 0
/// first (CiA 402-2, profile velocity mode). With 20 000 counts/s² up and 10 000 down: 0 → 1000
/// counts/s in 50 ms, 1000 → 2000 in 50 ms, 2000 → 1000 in 100 ms, 1000 → −1000 in 100 ms to 0
/// and 50 ms on.
#[test]
fn speeding_up_at_the_acceleration_slowing_down_at_the_deceleration() {
    let mut r = running(&[(0x6083, 0, 20_000)]);
    r.at(26);
    assert_eq!(r.read(0x606B, 0), 500);
    r.at(51);
    assert_eq!(r.read(0x606B, 0), 1000);
    r.set(0x60FF, 0, 2000);
    r.at(76);
    assert_eq!(r.read(0x606B, 0), 1500);
    r.at(101);
    assert_eq!(r.read(0x606B, 0), 2000);
    r.set(0x60FF, 0, 1000);
    r.at(151);
    assert_eq!(r.read(0x606B, 0), 1500);
    r.at(201);
    assert_eq!(r.read(0x606B, 0), 1000);
    r.set(0x60FF, 0, -1000);
    r.at(251);
    assert_eq!(r.read(0x606B, 0), 500);
    r.at(301);
    assert_eq!(r.read(0x606B, 0), 0);
    r.at(326);
    assert_eq!(r.read(0x606B, 0), -500);
    r.at(351);
    assert_eq!(r.read(0x606B, 0), -1000);
}
