//! Profile position mode of the generic drive: the trapezoid a master computes from 0x6081,
//! 0x6083 and 0x6084, the set-point handshake (controlword bit 4, status bit 12), change set
//! immediately (bit 5), relative moves (bit 6, 0x60F2), halt, target reached with and without a
//! position window, software position limits (0x607D, status bit 11) and the following error
//! (status bits 7 and 13).
//!
//! The rig's profile: 1000 counts/s, 10 000 counts/s² up and down, so a ramp takes 100 ms and 50
//! counts. Operation enabled is reached at 1 ms and the set-points written then start at 1 ms.

mod drive_rig;

use drive_rig::*;

const ENABLED: u16 = 0x0237;
const TR: u16 = 0x0400;
const ACK: u16 = 0x1000;
const FOLLOWING_ERROR: u16 = 0x2000;
const WARNING: u16 = 0x0080;
const LIMIT: u16 = 0x0800;

/// Operation enabled in pp at 1 ms; a new set-point `target` (absolute) at 1 ms, bit 4 back to 0.
fn moving_to(changes: &[(u16, u8, i64)], target: i64) -> Rig {
    let mut r = Rig::with(changes);
    r.enable(1);
    assert_eq!(r.sw(), ENABLED | TR, "standing, no set-point");
    r.set(0x607A, 0, target);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.sw(), ENABLED | ACK, "set-point acknowledged, moving");
    r.cw(ENABLE);
    assert_eq!(r.sw(), ENABLED, "bit 4 back to 0 clears the acknowledge");
    r
}

#[test]
fn trapezoid_at_named_instants() {
    // 0 → 2000: ramp 0.1 s to 50 counts, cruise 1.9 s, ramp 0.1 s; ends at 2.1 s after 1 ms.
    let mut r = moving_to(&[], 2000);
    r.at(51);
    // Half-way up the ramp: ½ · 10 000 · 0.05² = 12.5 counts, 500 counts/s.
    assert_eq!(r.read(0x606B, 0), 500);
    r.at(101);
    assert_eq!((r.demand(), r.pos()), (50, 50));
    assert_eq!(r.read(0x606C, 0), 1000);
    r.at(1001);
    assert_eq!((r.demand(), r.pos()), (950, 950));
    assert_eq!(r.read(0x60F4, 0), 0);
    r.at(2001);
    assert_eq!((r.demand(), r.pos()), (1950, 1950));
    r.at(2100);
    assert_eq!(r.sw(), ENABLED);
    r.at(2101);
    assert_eq!((r.demand(), r.pos()), (2000, 2000));
    assert_eq!(r.read(0x606C, 0), 0);
    assert_eq!(r.sw(), ENABLED | TR);
}

#[test]
fn triangle_when_the_distance_is_short() {
    // 0 → 40: the peak √(10 000 · 40) = 632.5 counts/s is below 1000: two ramps of 63.2 ms.
    let mut r = moving_to(&[], 40);
    r.at(64);
    assert_eq!(r.sw(), ENABLED);
    // 2 · 63.25 ms = 126.5 ms after 1 ms.
    r.at(127);
    assert_eq!(r.sw(), ENABLED);
    r.at(128);
    assert_eq!(r.sw(), ENABLED | TR);
    assert_eq!(r.pos(), 40);
}

#[test]
fn a_set_point_during_a_move_is_buffered_without_change_immediately() {
    let mut r = moving_to(&[], 2000);
    r.at(501);
    assert_eq!(r.pos(), 450);
    r.set(0x607A, 0, 3000);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.sw(), ENABLED | ACK);
    // The buffer is full: the acknowledge stays while bit 4 goes back to 0.
    r.cw(ENABLE);
    assert_eq!(r.sw(), ENABLED | ACK);
    // The first move is not changed.
    r.at(2100);
    assert_eq!(r.sw(), ENABLED | ACK);
    // At 2101 it ends at 2000 and the buffered set-point starts: 1000 counts, ends 1.1 s later.
    r.at(2101);
    assert_eq!(r.pos(), 2000);
    assert_eq!(r.sw(), ENABLED);
    r.at(2201);
    assert_eq!(r.pos(), 2050);
    r.at(3200);
    assert_eq!(r.sw(), ENABLED);
    r.at(3201);
    assert_eq!(r.pos(), 3000);
    assert_eq!(r.sw(), ENABLED | TR);
}

#[test]
fn a_set_point_while_the_buffer_is_full_is_ignored() {
    let mut r = moving_to(&[], 2000);
    r.at(501);
    r.set(0x607A, 0, 3000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.cw(ENABLE);
    r.set(0x607A, 0, 9000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.cw(ENABLE);
    r.at(4000);
    assert_eq!(r.pos(), 3000);
    assert_eq!(r.sw(), ENABLED | TR);
}

#[test]
fn change_set_immediately() {
    // At 501 (450 counts, 1000 counts/s) the target becomes 1000: cruise 500 counts (0.5 s), then
    // the 0.1 s ramp: at 1000 at 1101.
    let mut r = moving_to(&[], 2000);
    r.at(501);
    r.set(0x607A, 0, 1000);
    r.cw(ENABLE | NEW_SETPOINT | IMMEDIATE);
    assert_eq!(r.sw(), ENABLED | ACK);
    r.cw(ENABLE | IMMEDIATE);
    assert_eq!(r.sw(), ENABLED);
    r.at(1001);
    assert_eq!(r.pos(), 950);
    r.at(1101);
    assert_eq!(r.pos(), 1000);
    assert_eq!(r.sw(), ENABLED | TR);
}

#[test]
fn change_set_immediately_behind_the_axis_brakes_and_comes_back() {
    // At 501 (450, +1000 counts/s) the target becomes −1000: 100 ms to a stop at 500, then 1500
    // counts back (ramp 50, cruise 1400 in 1.4 s, ramp 50): at −1000 at 601 + 1600 = 2201.
    let mut r = moving_to(&[], 2000);
    r.at(501);
    r.set(0x607A, 0, -1000);
    r.cw(ENABLE | NEW_SETPOINT | IMMEDIATE);
    r.at(601);
    assert_eq!((r.pos(), r.read(0x606C, 0)), (500, 0));
    r.at(701);
    assert_eq!((r.pos(), r.read(0x606C, 0)), (450, -1000));
    r.at(2200);
    assert_eq!(r.sw(), ENABLED | ACK);
    r.at(2201);
    assert_eq!(r.pos(), -1000);
    assert_eq!(r.sw(), ENABLED | ACK | TR);
}

#[test]
fn relative_to_the_preceding_target() {
    // 0x60F2 bits 0–1 = 0: relative to the preceding target (0 before the first).
    let mut r = Rig::with(&[]);
    r.enable(1);
    r.set(0x607A, 0, 500);
    r.cw(ENABLE | NEW_SETPOINT | RELATIVE);
    r.cw(ENABLE | RELATIVE);
    // 500 counts: 0.6 s.
    r.at(601);
    assert_eq!(r.pos(), 500);
    r.at(700);
    r.cw(ENABLE | NEW_SETPOINT | RELATIVE);
    r.cw(ENABLE | RELATIVE);
    r.at(1300);
    assert_eq!(r.pos(), 1000);
    assert_eq!(r.sw(), ENABLED | TR);
}

#[test]
fn relative_to_the_position_demand() {
    // 0x60F2 = 1: at 301 the demand is 250; +100 immediately: the target 350 is reached after 50
    // counts of cruise and the 0.1 s ramp, at 451.
    let mut r = moving_to(&[(0x60F2, 0, 1)], 100_000);
    r.at(301);
    r.set(0x607A, 0, 100);
    r.cw(ENABLE | NEW_SETPOINT | IMMEDIATE | RELATIVE);
    r.at(450);
    assert_eq!(r.sw(), ENABLED | ACK);
    r.at(451);
    assert_eq!(r.pos(), 350);
    assert_eq!(r.sw(), ENABLED | ACK | TR);
}

#[test]
fn relative_to_the_position_actual_value() {
    // 0x60F2 = 2: relative to 0x6064.
    let mut r = Rig::with(&[(0x60F2, 0, 2)]);
    r.enable(1);
    r.set(0x607A, 0, 300);
    r.cw(ENABLE | NEW_SETPOINT);
    r.cw(ENABLE);
    r.at(1000);
    r.set(0x607A, 0, -100);
    r.cw(ENABLE | NEW_SETPOINT | RELATIVE);
    r.at(2000);
    assert_eq!(r.pos(), 200);
}

#[test]
fn halt_stops_and_resumes_the_positioning() {
    let mut r = moving_to(&[], 2000);
    r.at(501);
    r.cw(ENABLE | HALT);
    // 0x605D = 1: the slow-down ramp, 100 ms to 500.
    r.at(600);
    assert_eq!(r.sw(), ENABLED);
    r.at(601);
    assert_eq!(r.pos(), 500);
    assert_eq!(r.sw(), ENABLED | TR);
    r.at(1000);
    assert_eq!(r.pos(), 500);
    r.cw(ENABLE);
    assert_eq!(r.sw(), ENABLED);
    // 1500 counts left from rest: 1.6 s.
    r.at(2599);
    assert_eq!(r.sw(), ENABLED);
    r.at(2600);
    assert_eq!(r.pos(), 2000);
    assert_eq!(r.sw(), ENABLED | TR);
}

#[test]
fn target_reached_waits_for_the_position_window_time() {
    // 0x6067 = 5 counts for 0x6068 = 10 ms: the move ends at 2101, target reached at 2111.
    let mut r = moving_to(&[(0x6067, 0, 5), (0x6068, 0, 10)], 2000);
    r.at(2101);
    assert_eq!(r.pos(), 2000);
    assert_eq!(r.sw(), ENABLED);
    r.at(2110);
    assert_eq!(r.sw(), ENABLED);
    r.at(2111);
    assert_eq!(r.sw(), ENABLED | TR);
}

#[test]
fn software_limits_clamp_the_target_and_set_bit_11() {
    let mut r = Rig::with(&[(0x607D, 1, -1000), (0x607D, 2, 1500)]);
    r.enable(1);
    r.set(0x607A, 0, 2000);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.sw(), ENABLED | ACK | LIMIT);
    r.cw(ENABLE);
    // To 1500: ramp, 1.4 s, ramp: 1.6 s.
    r.at(1601);
    assert_eq!(r.pos(), 1500);
    assert_eq!(r.sw(), ENABLED | TR | LIMIT);
    r.set(0x607A, 0, 1000);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.sw(), ENABLED | ACK);
    r.cw(ENABLE);
    r.set(0x607A, 0, -5000);
    r.at(3000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(6000);
    assert_eq!(r.pos(), -1000);
    assert_eq!(r.sw(), ENABLED | ACK | TR | LIMIT);
}

#[test]
fn min_not_below_max_switches_the_software_limits_off() {
    let mut r = Rig::with(&[(0x607D, 1, 0), (0x607D, 2, 0)]);
    r.enable(1);
    r.set(0x607A, 0, 300);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.sw(), ENABLED | ACK);
    r.at(1000);
    assert_eq!(r.pos(), 300);
}

#[test]
fn following_error_warning_then_bit_13() {
    // No torque (0x6072 = 0): the rotor stays at 0 and the following error is the demand,
    // round(½ · 10 000 · t²) with t from 1 ms: 10 at 46 ms (10.125), 11 at 47 ms (10.58), beyond
    // the window of 10 counts from 47 ms; for 0x6066 = 5 ms: bit 13 at 52 ms.
    let mut r = Rig::with(&[(0x6065, 0, 10), (0x6066, 0, 5)]);
    r.enable(1);
    r.set(0x6072, 0, 0);
    r.set(0x607A, 0, 2000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.cw(ENABLE);
    r.at(46);
    assert_eq!(r.read(0x60F4, 0), 10);
    assert_eq!(r.sw(), ENABLED);
    r.at(47);
    assert_eq!(r.read(0x60F4, 0), 11);
    assert_eq!(r.sw(), ENABLED | WARNING);
    r.at(51);
    assert_eq!(r.sw(), ENABLED | WARNING);
    r.at(52);
    assert_eq!(r.sw(), ENABLED | FOLLOWING_ERROR);
    assert_eq!(r.pos(), 0);
    // pp goes on (no fault): the demand ends at 2000, the rotor still at 0.
    r.at(2101);
    assert_eq!(r.sw(), ENABLED | TR | FOLLOWING_ERROR);
    assert_eq!(r.read(0x60F4, 0), 2000);
    assert_eq!(r.drive.error_code(), 0);
    // With torque again the rotor catches up and the bits clear.
    r.set(0x6072, 0, 3000);
    r.at(3000);
    assert_eq!(r.read(0x60F4, 0), 0);
    assert_eq!(r.sw(), ENABLED | TR);
}

/// 0x6065 = 0 (an EDS entry without a value) switches the following error monitor off, as
/// 0xFFFFFFFF does: the numbers of the test above give no warning and no bit 13.
#[test]
fn a_following_error_window_of_0_is_off() {
    let mut r = Rig::with(&[(0x6065, 0, 0), (0x6066, 0, 5)]);
    r.enable(1);
    r.set(0x6072, 0, 0);
    r.set(0x607A, 0, 2000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.cw(ENABLE);
    // ½ · 10 000 · 0.051² = 13.0.
    r.at(52);
    assert_eq!((r.sw(), r.read(0x60F4, 0)), (ENABLED, 13));
}

#[test]
fn profile_velocity_is_limited_by_0x607f_and_0x6080() {
    // 0x6081 = 5000 but 0x607F = 2000: 0 → 10 000 ramps 0.2 s (200 counts), cruise 4.8 s at 2000.
    let mut r = moving_to(&[(0x6081, 0, 5000), (0x607F, 0, 2000)], 10_000);
    r.at(1201);
    assert_eq!(r.read(0x606C, 0), 2000);
    assert_eq!(r.pos(), 2200);
    // 0x6080 = 6 rpm is 1000 counts/s at 10 000 counts/rev.
    let mut r = moving_to(&[(0x6081, 0, 5000), (0x6080, 0, 6)], 10_000);
    r.at(1201);
    assert_eq!(r.read(0x606C, 0), 1000);
}

#[test]
fn a_new_set_point_outside_operation_enabled_is_not_taken() {
    let mut r = Rig::with(&[]);
    r.at(1);
    r.set(0x6060, 0, 1);
    r.cw(SHUTDOWN);
    r.cw(SWITCH_ON);
    r.set(0x607A, 0, 500);
    r.cw(SWITCH_ON | NEW_SETPOINT);
    assert_eq!(r.sw(), 0x0233);
    // Enabling with bit 4 already set is no rising edge.
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(1000);
    assert_eq!(r.pos(), 0);
    assert_eq!(r.sw(), ENABLED | TR);
}

/// Bit 4 held at 1 over several writes (an RPDO repeats the control word every cycle) is one
/// set-point: the acknowledge (bit 12) stays until bit 4 falls (CiA 402-2, set-point handshake).
#[test]
fn bit_4_held_keeps_the_acknowledge() {
    let mut r = Rig::with(&[]);
    r.enable(1);
    r.set(0x607A, 0, 2000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(10);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.sw(), ENABLED | ACK);
    r.at(20);
    r.cw(ENABLE);
    assert_eq!(r.sw(), ENABLED);
    r.cw(ENABLE);
    assert_eq!(r.sw(), ENABLED);
}

/// A set-point waiting in the buffer is dropped when the mode's activity ends (here a quick stop,
/// 0x605A = 6); bit 4 being back at 0, the acknowledge (bit 12) goes with it, so the master can
/// hand over its next set-point (CiA 402-2, set-point handshake).
#[test]
fn a_dropped_set_point_releases_the_acknowledge() {
    let mut r = moving_to(&[(0x605A, 0, 6)], 2000);
    r.at(501);
    r.set(0x607A, 0, 3000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.cw(ENABLE);
    assert_eq!(r.sw(), ENABLED | ACK);
    // Quick stop at 0x6085 = 100 000 counts/s² from 1000 counts/s: 10 ms, 5 counts.
    r.cw(QUICK_STOP);
    assert_eq!(r.sw(), 0x0217);
    r.at(511);
    assert_eq!((r.sw(), r.pos()), (0x0217 | TR, 455));
    // 16: Operation enabled again, standing, no set-point and no acknowledge.
    r.cw(ENABLE);
    assert_eq!(r.sw(), ENABLED | TR);
    r.at(1000);
    assert_eq!((r.sw(), r.pos()), (ENABLED | TR, 455));
    // The next set-point is taken as the first.
    r.set(0x607A, 0, 555);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.sw(), ENABLED | ACK);
}

/// Bit 4 going back to 0 ends the set-point handshake in any state: dropped to 0 during a quick
/// stop (0x605A = 6), it leaves no acknowledge behind when operation is enabled again.
#[test]
fn bit_4_falling_in_quick_stop_active_releases_the_acknowledge() {
    let mut r = Rig::with(&[(0x605A, 0, 6)]);
    r.enable(1);
    r.set(0x607A, 0, 2000);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.sw(), ENABLED | ACK);
    // At 101 ms at the end of the ramp (50 counts, 1000 counts/s): a quick stop with bit 4 still
    // held, 10 ms and 5 counts at 0x6085.
    r.at(101);
    r.cw(QUICK_STOP | NEW_SETPOINT);
    r.at(111);
    assert_eq!((r.sw(), r.pos()), (0x0617, 55));
    r.cw(QUICK_STOP);
    r.cw(ENABLE);
    assert_eq!(r.sw(), ENABLED | TR);
}

/// The same when the power goes off with bit 4 held (Disable voltage 0x0010) and bit 4 falls
/// once before the master enables again with bit 4 set (0x0016, 0x001F, no rising edge): no
/// acknowledge and no new set-point.
#[test]
fn bit_4_falling_after_disable_voltage_releases_the_acknowledge() {
    let mut r = Rig::with(&[]);
    r.enable(1);
    r.set(0x607A, 0, 2000);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.sw(), ENABLED | ACK);
    r.cw(DISABLE_VOLTAGE | NEW_SETPOINT);
    assert_eq!(r.sw(), 0x0260);
    r.cw(DISABLE_VOLTAGE);
    r.cw(SHUTDOWN | NEW_SETPOINT);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.sw(), ENABLED | TR);
    r.at(100);
    assert_eq!((r.sw(), r.pos()), (ENABLED | TR, 0));
}

/// With a profile velocity of 0 (0x6081: an EDS entry without a default) no move is possible:
/// the axis stands and the target is not reached (CiA 402-2, statusword bit 10). A set-point with
/// 0x6081 = 1000 at 500 ms then starts at once (the one before is no move in progress): 1000
/// counts in 1.1 s.
#[test]
fn a_profile_velocity_of_0_reaches_no_target() {
    let mut r = Rig::with(&[(0x6081, 0, 0)]);
    r.enable(1);
    r.set(0x607A, 0, 1000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.cw(ENABLE);
    r.at(500);
    assert_eq!((r.sw(), r.pos()), (ENABLED, 0));
    r.set(0x6081, 0, 1000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.cw(ENABLE);
    r.at(1599);
    assert_eq!(r.sw(), ENABLED);
    r.at(1600);
    assert_eq!((r.sw(), r.pos()), (ENABLED | TR, 1000));
}

/// A new target behind the axis (change set immediately): the axis brakes at 0x6084 and comes
/// back accelerating at 0x6083 (CiA 402-2, profile position mode). With 20 000 counts/s² up and
/// 10 000 down: at 501 the axis is at 25 + 450 = 475; the target becomes 100: it stops 50 counts
/// on, at 525 at 601, and is back at 525 − 25 − 50 = 450 at 701; at 100 after 25 + 350 + 50
/// counts (50 + 350 + 100 ms), at 1101.
#[test]
fn change_set_immediately_behind_the_axis_brakes_on_the_deceleration() {
    let mut r = moving_to(&[(0x6083, 0, 20_000)], 2000);
    r.at(501);
    assert_eq!(r.pos(), 475);
    r.set(0x607A, 0, 100);
    r.cw(ENABLE | NEW_SETPOINT | IMMEDIATE);
    r.cw(ENABLE | IMMEDIATE);
    r.at(601);
    assert_eq!((r.demand(), r.read(0x606B, 0)), (525, 0));
    r.at(701);
    assert_eq!((r.demand(), r.read(0x606B, 0)), (450, -1000));
    r.at(1100);
    assert_eq!(r.sw(), ENABLED);
    r.at(1101);
    assert_eq!((r.sw(), r.pos()), (ENABLED | TR, 100));
}

/// A new target ahead but closer than the stopping distance: the axis stops beyond it and comes
/// back (CiA 402-2, profile position mode). At 301 at 250 and 1000 counts/s, target 260: 50 counts
/// to a stop at 300 at 401, then 40 counts back in 2 · √(40 / 10 000) s = 126.5 ms.
#[test]
fn change_set_immediately_short_of_the_stopping_distance_overshoots_and_returns() {
    let mut r = moving_to(&[], 2000);
    r.at(301);
    assert_eq!(r.pos(), 250);
    r.set(0x607A, 0, 260);
    r.cw(ENABLE | NEW_SETPOINT | IMMEDIATE);
    r.cw(ENABLE | IMMEDIATE);
    r.at(401);
    assert_eq!((r.demand(), r.read(0x606B, 0)), (300, 0));
    r.at(527);
    assert_eq!(r.sw(), ENABLED);
    r.at(528);
    assert_eq!((r.sw(), r.demand(), r.pos()), (ENABLED | TR, 260, 260));
}

/// A set-point with a profile velocity of 0 while moving: no move is possible, the axis brakes at
/// 0x6084 and stands short of the target, which is not reached. At 301 at 250 and 1000 counts/s:
/// 50 counts, at 300 at 401.
#[test]
fn a_set_point_with_a_profile_velocity_of_0_brakes_the_axis() {
    let mut r = moving_to(&[], 2000);
    r.at(301);
    r.set(0x6081, 0, 0);
    r.set(0x607A, 0, 5000);
    r.cw(ENABLE | NEW_SETPOINT | IMMEDIATE);
    r.cw(ENABLE | IMMEDIATE);
    r.at(351);
    assert_eq!(r.read(0x606B, 0), 500);
    r.at(401);
    assert_eq!((r.demand(), r.read(0x606B, 0)), (300, 0));
    r.at(1000);
    assert_eq!((r.sw(), r.pos()), (ENABLED, 300));
}

/// A new target just beyond the stopping distance: the axis cruises on and ramps down to it (CiA
/// 402-2, profile position mode). At 301 at 250 and 1000 counts/s, target 310: 10 counts of
/// cruise (10 ms) and the 100 ms ramp of 50 counts, at 310 at 411.
#[test]
fn change_set_immediately_beyond_the_stopping_distance_cruises_into_the_ramp() {
    let mut r = moving_to(&[], 2000);
    r.at(301);
    r.set(0x607A, 0, 310);
    r.cw(ENABLE | NEW_SETPOINT | IMMEDIATE);
    r.cw(ENABLE | IMMEDIATE);
    r.at(311);
    assert_eq!((r.demand(), r.read(0x606B, 0)), (260, 1000));
    r.at(410);
    assert_eq!(r.sw(), ENABLED);
    r.at(411);
    assert_eq!((r.sw(), r.pos()), (ENABLED | TR, 310));
}

/// The profile velocity raised during a move (change set immediately): from 1000 counts/s with
/// 300 counts to go, the axis speeds up to √((2 · a · d · 300 + d · 1000²) / (a + d)) = √3.5e6 =
/// 1870.8 counts/s (125 counts in 87.1 ms) and ramps down from there (175 counts in 187.1 ms): at
/// 550 at 301 + 274.2 ms.
#[test]
fn a_profile_velocity_raised_during_a_move() {
    let mut r = moving_to(&[], 2000);
    r.at(301);
    r.set(0x6081, 0, 2000);
    r.set(0x607A, 0, 550);
    r.cw(ENABLE | NEW_SETPOINT | IMMEDIATE);
    r.cw(ENABLE | IMMEDIATE);
    r.at(351);
    assert_eq!(r.read(0x606B, 0), 1500);
    r.at(575);
    assert_eq!(r.sw(), ENABLED);
    r.at(576);
    assert_eq!((r.sw(), r.pos()), (ENABLED | TR, 550));
}

/// The profile velocity lowered during a move (change set immediately): the axis slows down to it
/// at 0x6084 (CiA 402-2, profile position mode): from 1000 to 500 counts/s in 50 ms.
#[test]
fn a_profile_velocity_lowered_during_a_move() {
    let mut r = moving_to(&[], 2000);
    r.at(301);
    r.set(0x6081, 0, 500);
    r.cw(ENABLE | NEW_SETPOINT | IMMEDIATE);
    r.cw(ENABLE | IMMEDIATE);
    r.at(326);
    assert_eq!(r.read(0x606B, 0), 750);
    r.at(351);
    assert_eq!(r.read(0x606B, 0), 500);
    r.at(1000);
    assert_eq!(r.read(0x606B, 0), 500);
}

/// A short move at a low acceleration is a triangle (CiA 402-2, profile position mode): 1 count
/// at 1 count/s² up and 1000 down peaks at √(2 · 1 · 1000 · 1 / 1001) = 1.4135 counts/s, after
/// 1.4135 s, and ends 1.4 ms later, at 1 + 1414.9 ms.
#[test]
fn a_short_move_at_a_low_acceleration() {
    let mut r = Rig::with(&[(0x6083, 0, 1), (0x6084, 0, 1000)]);
    r.enable(1);
    r.set(0x607A, 0, 1);
    r.cw(ENABLE | NEW_SETPOINT);
    r.cw(ENABLE);
    r.at(1415);
    assert_eq!(r.sw(), ENABLED);
    r.at(1416);
    assert_eq!((r.sw(), r.demand()), (ENABLED | TR, 1));
}
