//! Registration moves on the SMD (seed 000, R2 "Registration Moves", Tables R6.9/R6.11), rule by rule
//! (catalogue `rules/smd.md`).

mod smd_rig;

use ds402::smd::config::CFG0_USE_ENCODER;
use ds402::smd::indexer::{cmd0, cmd1, stat0};
use smd_rig::Rig;

const STOP_JOG: u16 = 4;

/// IN1 = Stop Jog/Registration; driver on, position valid; Velocity 10,000, Acceleration and
/// Deceleration 10 (braking from 10,000 to 141 takes 4,999 steps).
fn rig() -> Rig {
    let mut r = Rig::ready_with(STOP_JOG | CFG0_USE_ENCODER, 10_000, 10, 10);
    r.out.cmd1 |= cmd1::REGISTRATION_MOVE;
    r
}

/// Sets the Stopping Distance and the MRMD (split over Motor_Current and Jerk).
fn program(r: &mut Rig, stopping: i32, mrmd: u32) {
    r.out.position = stopping;
    r.out.motor_current = (mrmd & 0xFFFF) as u16;
    r.out.jerk = (mrmd >> 16) as u16;
}

fn cycles(r: &mut Rig, n: u32) {
    for _ in 0..n {
        r.cycle();
    }
}

/// A CW registration move with Stopping Distance 20,000 run at Velocity for 2 s, then the Stop input's
/// edge and the cycle that takes it.
fn triggered_run_out() -> Rig {
    let mut r = rig();
    program(&mut r, 20_000, 0);
    r.command(cmd0::JOG_CW);
    cycles(&mut r, 2_000);
    assert_eq!(r.ix.speed(), 10_000.0, "runs like a jog");
    r.ix.set_input(r.now(), 1, true);
    r.cycle();
    r
}

/// SMD-R2-061, SMD-R2-062, SMD-R2-065, SMD-R1-033: a CW registration move runs like a jog; the Stop
/// input's edge (after the MRMD) runs out exactly the Stopping Distance — here longer than the
/// braking distance, so it cruises, then brakes to V_S — and completes; the edge captured the encoder.
#[test]
fn smd_r2_061_062_065_run_out_after_the_stop_input() {
    let mut r = triggered_run_out();
    let trigger = r.pos();
    let enc = r.last.trapped_encoder_position;
    assert!(enc > 0, "captured at the edge");
    assert_eq!(r.s0() & stat0::DECELERATING, 0, "cruise first");
    let n = r.until(20_000, |i| i.status0 & stat0::STOPPED != 0);
    assert!(n > 1_000, "{n} ms run-out");
    let end = r.pos();
    assert!(
        (trigger + 20_000 - 10..=trigger + 20_000 + 10).contains(&end),
        "trigger {trigger}, end {end}"
    );
    assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
    assert_eq!(r.s0() & stat0::POSITION_INVALID, 0);
}

/// SMD-R2-062, SMD-R2-065: the run-out's path, cycle by cycle, from the status words and positions:
/// with a Stopping Distance of 20,000 at 10,000 steps/s and Deceleration 10, it cruises at 10
/// steps/ms for (20,000 − 4,999.0) / 10,000 = 1.5001 s, then brakes for (10,000 − 141) / 10,000 =
/// 0.9859 s; half-way through the braking (493 ms in) it has covered 10,000 × 0.493 − 10,000 ×
/// 0.493² / 2 = 3,714.8 steps of it.
#[test]
fn smd_r2_062_065_run_out_path() {
    let mut r = triggered_run_out();
    let mut path = vec![(r.s0(), r.pos())];
    let mut speeds = vec![r.ix.speed()];
    while r.s0() & stat0::STOPPED == 0 {
        let i = r.cycle();
        path.push((i.status0, i.motor_position));
        speeds.push(r.ix.speed());
        assert!(path.len() < 5_000);
    }
    let braking = path
        .iter()
        .position(|p| p.0 & stat0::DECELERATING != 0)
        .unwrap();
    assert!(
        (braking as f64 - 1_500.1).abs() <= 2.0,
        "cruise {braking} ms"
    );
    for w in path[..braking].windows(2) {
        assert_eq!(w[1].1 - w[0].1, 10, "cruise at 10 steps/ms");
    }
    let stop = path.len() - 1;
    assert!(
        ((stop - braking) as f64 - 985.9).abs() <= 2.0,
        "braking {} ms",
        stop - braking
    );
    let from = path[braking - 1].1;
    let half = path[braking - 1 + 493].1 - from;
    assert!(
        (f64::from(half) - 3_714.8).abs() <= 11.0,
        "{half} steps in 493 ms"
    );
    // The speed the simulator reports: 10,000 − 10,000 × 0.493 = 5,070 steps/s there.
    let mid = speeds[braking - 1 + 493];
    assert!((mid - 5_070.0).abs() <= 10.0, "{mid} steps/s half-way");
    // 20,000 from where the condition was taken, before the trigger cycle's 10 steps.
    assert_eq!(path[stop].1 - path[0].1, 19_990);
}

/// SMD-R2-062, SMD-R2-020 (Registration): the run-out is exactly the Stopping Distance from where the condition was taken.
#[test]
fn smd_r2_062_exact_stopping_distance() {
    let mut r = rig();
    program(&mut r, 12_345, 0);
    r.command(cmd0::JOG_CW);
    cycles(&mut r, 1_500);
    let before = r.pos();
    r.command(0); // The Jog bit going to 0 is a stop condition too (SMD-R2-063).
    let at = r.pos();
    r.until(20_000, |i| i.status0 & stat0::STOPPED != 0);
    // The condition is taken in the cycle it arrives, at the position reached before that cycle's
    // motion.
    assert_eq!(r.pos(), before + 12_345, "from {before} (cycle end {at})");
    assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
}

/// SMD-R2-064: a Stopping Distance shorter than the braking distance brakes at Deceleration the whole
/// way and stops abruptly above V_S, exactly at the distance.
#[test]
fn smd_r2_064_short_run_out_stops_abruptly() {
    let mut r = rig();
    program(&mut r, 1_000, 0);
    r.out.cmd0 = cmd0::JOG_CCW;
    cycles(&mut r, 1_500);
    let before = r.pos();
    r.command(0);
    let mut last_speed = 0.0;
    let mut decel_all_the_way = true;
    loop {
        let i = r.cycle();
        if i.status0 & stat0::STOPPED != 0 {
            break;
        }
        decel_all_the_way &= i.status0 & stat0::DECELERATING != 0;
        last_speed = r.ix.speed();
    }
    assert!(decel_all_the_way);
    assert!(
        last_speed < -141.0 - 1_000.0,
        "stopped from {last_speed} steps/s"
    );
    assert_eq!(r.pos(), before - 1_000);
}

/// SMD-R2-066, SMD-R2-067: stop conditions wait for the MRMD; a Stop input pulse that ended before
/// it is ignored, one still active at the MRMD starts the run-out there.
#[test]
fn smd_r2_066_067_minimum_registration_move_distance() {
    // A pulse before the MRMD: ignored.
    let mut r = rig();
    program(&mut r, 100, 100_000);
    r.command(cmd0::JOG_CW);
    cycles(&mut r, 500);
    r.ix.set_input(r.now(), 1, true);
    cycles(&mut r, 5);
    r.ix.set_input(r.now(), 1, false);
    cycles(&mut r, 3_000);
    assert!(r.ix.is_moving(), "still jogging at {}", r.pos());
    assert!(r.pos() > 20_000);
    // Held active from early on: the run-out starts at the MRMD point.
    let mut r = rig();
    program(&mut r, 500, 50_000);
    r.command(cmd0::JOG_CW);
    cycles(&mut r, 100);
    r.ix.set_input(r.now(), 1, true);
    r.until(20_000, |i| i.status0 & stat0::STOPPED != 0);
    assert!(
        (50_500..=50_512).contains(&r.pos()),
        "MRMD + Stopping Distance, got {}",
        r.pos()
    );
    assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
}

/// SMD-R6-041, SMD-R6-042, SMD-R6-040: a negative Stopping Distance or an MRMD above 8,388,607 is a
/// Command_Error with Move_Complete; the MRMD is (Jerk << 16) | Motor_Current.
#[test]
fn smd_r6_041_042_registration_parameters() {
    let mut r = rig();
    program(&mut r, -1, 0);
    r.command(cmd0::JOG_CW);
    assert_eq!(
        r.s0() & (stat0::COMMAND_ERROR | stat0::MOVE_COMPLETE | stat0::STOPPED),
        stat0::COMMAND_ERROR | stat0::MOVE_COMPLETE | stat0::STOPPED
    );
    let mut r = rig();
    program(&mut r, 0, 0x0080_0000);
    r.command(cmd0::JOG_CW);
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0);
    // 0x0001_86A0 = 100,000 steps, accepted; the jerk and current words are not a current/jerk.
    let mut r = rig();
    program(&mut r, 0, 0x0001_86A0);
    r.command(cmd0::JOG_CW);
    assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0);
    assert_eq!(
        (r.last.motor_current, r.last.jerk),
        (10, 0),
        "SMD-R6-043 gap"
    );
}

/// SMD-R6-041, SMD-R6-042, SMD-R6-043, SMD-R6-040: the MRMD is (Jerk << 16) | Motor_Current and may
/// be up to
/// 8,388,607: 0x7F_FFFF starts the move, 0x80_0000 is a Command_Error with Move_Complete and no
/// motion. The MRMD's low half in the Motor_Current word is no current, even with CMD_word1 bit 1:
/// in.Motor_Current stays 8010:07's 10 while the move runs.
#[test]
fn smd_r6_041_043_mrmd_bounds_and_no_current_from_it() {
    let mut r = rig();
    program(&mut r, 1_000, 8_388_607);
    r.out.cmd1 |= cmd1::MOTOR_CURRENT;
    r.command(cmd0::JOG_CW);
    cycles(&mut r, 100);
    assert_eq!(r.s0() & (stat0::COMMAND_ERROR | stat0::STOPPED), 0);
    assert_eq!(r.last.motor_current, 10);
    assert!(r.pos() > 0);

    let mut r = rig();
    program(&mut r, 1_000, 8_388_608);
    r.command(cmd0::JOG_CW);
    assert_eq!(
        r.s0() & (stat0::COMMAND_ERROR | stat0::MOVE_COMPLETE | stat0::STOPPED),
        stat0::COMMAND_ERROR | stat0::MOVE_COMPLETE | stat0::STOPPED
    );
    cycles(&mut r, 100);
    assert_eq!(r.pos(), 0);
}

/// SMD-R2-036: Hold during a registration move's run-out (after the Stop input) stops it short, not
/// held: In_Hold_State 0, a Resume is a Command_Error and nothing moves.
#[test]
fn smd_r2_036_hold_during_the_run_out() {
    let mut r = triggered_run_out();
    let trigger = r.pos();
    cycles(&mut r, 200);
    r.command(cmd0::HOLD_MOVE);
    assert_ne!(r.s0() & stat0::DECELERATING, 0);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert!(
        r.pos() < trigger + 20_000 - 1_000,
        "stopped short: {}",
        r.pos() - trigger
    );
    assert_eq!(r.s0() & (stat0::IN_HOLD_STATE | stat0::MOVE_COMPLETE), 0);
    let at = r.pos();
    r.command(0);
    r.command(cmd0::RESUME_MOVE);
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0);
    cycles(&mut r, 1_000);
    assert_eq!(r.pos(), at);
}

/// SMD-R2-036: Hold during a registration move decelerates to a stop; not held.
#[test]
fn smd_r2_036_hold_during_registration() {
    let mut r = rig();
    program(&mut r, 10_000, 0);
    r.command(cmd0::JOG_CW);
    cycles(&mut r, 1_500);
    r.command(cmd0::HOLD_MOVE);
    assert_ne!(r.s0() & stat0::DECELERATING, 0);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.s0() & (stat0::IN_HOLD_STATE | stat0::MOVE_COMPLETE), 0);
}
