//! Stall detection, driver faults (over-temperature, STO), Module_OK and the motor current with idle
//! reduction on the SMD, rule by rule (catalogue `rules/smd.md`, R1, R2, R4, R5, R6).

mod smd_rig;

use ds402::smd::config::{CFG0_ENABLE_STALL_DETECTION, CFG0_USE_ENCODER};
use ds402::smd::indexer::{cmd0, stat0, stat1};
use smd_rig::Rig;

fn rig(cfg0: u16) -> Rig {
    Rig::ready_with(cfg0, 4_000, 10, 10)
}

const STALL: u16 = CFG0_USE_ENCODER | CFG0_ENABLE_STALL_DETECTION;

/// SMD-R1-007, SMD-R1-010, SMD-R1-011: a blocked shaft during a move: the stall trips once the motor
/// is more than 45° (250 steps of 2,000) ahead of the encoder — not at 45° — stopping the move at once
/// with Stall_Detected and Position_Invalid, no Move_Complete.
#[test]
fn smd_r1_007_010_011_stall_during_a_move() {
    let mut r = rig(STALL);
    r.out.position = 100_000;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..300 {
        r.cycle();
    }
    let from = r.pos();
    r.ix.set_shaft_blocked(r.now(), true);
    let n = r.until(10_000, |i| i.status1 & stat1::STALL_DETECTED != 0);
    assert!(n > 1);
    let ahead = r.pos() - from;
    assert!((251..=265).contains(&ahead), "tripped {ahead} steps ahead");
    assert_eq!(
        r.s0() & (stat0::STOPPED | stat0::POSITION_INVALID | stat0::MOVE_COMPLETE),
        stat0::STOPPED | stat0::POSITION_INVALID
    );
    let at = r.pos();
    r.cycle();
    assert_eq!(r.pos(), at);
}

/// SMD-R1-008, SMD-R6-063, SMD-R4-007: monitoring runs at rest: turning the idle shaft by more than
/// 45° (256 of 2,048 counts) trips it; it stays until Reset Errors, which takes a new reference so it
/// does not trip again at once.
#[test]
fn smd_r1_008_r6_063_stall_at_rest_and_reset() {
    let mut r = rig(STALL);
    r.ix.turn_shaft(r.now(), 256);
    r.cycle();
    assert_eq!(r.s1() & stat1::STALL_DETECTED, 0, "exactly 45°");
    r.ix.turn_shaft(r.now(), 1);
    r.cycle();
    assert_ne!(r.s1() & stat1::STALL_DETECTED, 0);
    assert_ne!(r.s0() & stat0::POSITION_INVALID, 0);
    r.ix.turn_shaft(r.now(), -257);
    for _ in 0..10 {
        r.cycle();
    }
    assert_ne!(r.s1() & stat1::STALL_DETECTED, 0, "kept until Reset Errors");
    r.ix.turn_shaft(r.now(), 400);
    r.command(cmd0::RESET_ERRORS);
    assert_eq!(r.s1() & stat1::STALL_DETECTED, 0);
    for _ in 0..100 {
        r.cycle();
    }
    assert_eq!(
        r.s1() & stat1::STALL_DETECTED,
        0,
        "new reference at the reset"
    );
}

/// SMD-R1-009: stall detection off: no difference trips it.
#[test]
fn smd_r1_009_no_stall_detection() {
    let mut r = rig(CFG0_USE_ENCODER);
    r.ix.turn_shaft(r.now(), 100_000);
    r.cycle();
    assert_eq!(r.s1() & stat1::STALL_DETECTED, 0);
}

/// SMD-R1-020, SMD-R6-062, SMD-R6-071, SMD-R6-074, SMD-R6-061: above 90 °C a warning; above 95 °C a
/// Driver_Fault with no current while Drive_Is_Enabled stays 1; a move in progress stops; moves are
/// refused; the fault clears itself once cool.
#[test]
fn smd_r1_020_r6_071_074_over_temperature() {
    let mut r = rig(0);
    r.ix.set_temperature(r.now(), 91.0);
    r.cycle();
    assert_eq!(
        r.s1() & (stat1::TEMPERATURE_ABOVE_90 | stat1::DRIVER_FAULT),
        stat1::TEMPERATURE_ABOVE_90
    );
    r.ix.set_temperature(r.now(), 89.0);
    r.cycle();
    assert_eq!(r.s1() & stat1::TEMPERATURE_ABOVE_90, 0);
    // "Above": exactly 90 °C is no warning, exactly 95 °C no fault.
    r.ix.set_temperature(r.now(), 90.0);
    r.cycle();
    assert_eq!(r.s1() & stat1::TEMPERATURE_ABOVE_90, 0, "90 °C");
    r.ix.set_temperature(r.now(), 95.0);
    r.cycle();
    assert_eq!(
        r.s1() & (stat1::TEMPERATURE_ABOVE_90 | stat1::DRIVER_FAULT),
        stat1::TEMPERATURE_ABOVE_90,
        "95 °C"
    );
    r.ix.set_temperature(r.now(), 89.0);
    r.cycle();
    r.out.position = 50_000;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..200 {
        r.cycle();
    }
    r.ix.set_temperature(r.now(), 95.1);
    r.cycle();
    assert_eq!(
        r.s1() & (stat1::DRIVER_FAULT | stat1::DRIVE_IS_ENABLED),
        stat1::DRIVER_FAULT | stat1::DRIVE_IS_ENABLED
    );
    assert_eq!(r.ix.actual_current(), 0.0);
    assert_ne!(r.s0() & stat0::STOPPED, 0);
    r.command(0);
    r.command(cmd0::RELATIVE_MOVE);
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0);
    r.ix.set_temperature(r.now(), 92.0);
    r.cycle();
    assert_ne!(r.s1() & stat1::DRIVER_FAULT, 0, "hysteresis");
    r.ix.set_temperature(r.now(), 90.0);
    r.cycle();
    assert_eq!(r.s1() & stat1::DRIVER_FAULT, 0, "cleared with no command");
    assert!(r.ix.actual_current() > 0.0);
}

/// SMD-R1-002, SMD-R1-003, SMD-R1-004, SMD-R1-005, SMD-R1-006, SMD-R6-022: removing either STO
/// input faults the driver at once
/// (Drive_Is_Enabled 0, the move coasts to a stop with Position_Invalid); powering it again does not
/// clear the fault; Reset Errors does, only with both inputs powered, and with Enable_Driver still 1
/// current returns without a new edge.
#[test]
fn smd_r1_002_to_006_sto() {
    let mut r = rig(0);
    r.out.position = 50_000;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..200 {
        r.cycle();
    }
    r.ix.set_sto(r.now(), true, false);
    r.cycle();
    assert_eq!(
        r.s1() & (stat1::DRIVER_FAULT | stat1::DRIVE_IS_ENABLED),
        stat1::DRIVER_FAULT
    );
    assert_eq!(
        r.s0() & (stat0::STOPPED | stat0::DECELERATING | stat0::POSITION_INVALID),
        stat0::STOPPED | stat0::POSITION_INVALID
    );
    r.command(0);
    r.command(cmd0::RESET_ERRORS);
    assert_ne!(r.s1() & stat1::DRIVER_FAULT, 0, "one input still off");
    r.command(0);
    r.ix.set_sto(r.now(), true, true);
    r.cycle();
    assert_ne!(
        r.s1() & stat1::DRIVER_FAULT,
        0,
        "powered again: still faulted"
    );
    r.command(cmd0::RESET_ERRORS);
    assert_eq!(
        r.s1() & (stat1::DRIVER_FAULT | stat1::DRIVE_IS_ENABLED),
        stat1::DRIVE_IS_ENABLED
    );
}

/// SMD-R6-051: Module_OK falls only for an internal fault, not for command or configuration errors.
#[test]
fn smd_r6_051_module_ok() {
    let mut r = rig(0);
    r.ix.write_config(r.now(), 7, 0);
    r.command(cmd0::ABSOLUTE_MOVE);
    assert_ne!(r.s0() & stat0::MODULE_OK, 0);
    r.ix.set_internal_fault(r.now(), true);
    r.cycle();
    assert_eq!(r.s0() & stat0::MODULE_OK, 0);
}

/// SMD-R1-018, SMD-R1-019, SMD-R2-101, SMD-R5-008: 1.5 s after a stop the current drops to the idle
/// percentage of the move's current (2.0 A at 25 % → 0.5 A); it returns with motion; a new percentage
/// waits for the end of the next move.
#[test]
fn smd_r1_018_019_r2_101_r5_008_idle_current() {
    let mut r = rig(0);
    r.ix.write_config(r.now(), 6, 25);
    r.ix.write_config(r.now(), 7, 20);
    r.out.position = 1_000;
    r.command(cmd0::RELATIVE_MOVE);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    r.command(0);
    assert_eq!(r.ix.actual_current(), 20.0);
    for _ in 0..1_400 {
        r.cycle();
    }
    assert_eq!(r.ix.actual_current(), 20.0, "not before 1.5 s");
    for _ in 0..110 {
        r.cycle();
    }
    assert_eq!(r.ix.actual_current(), 5.0, "2.0 A × 25 %");
    r.ix.write_config(r.now(), 6, 50);
    r.cycle();
    assert_eq!(
        r.ix.actual_current(),
        5.0,
        "the old level until a move ends"
    );
    r.command(cmd0::RELATIVE_MOVE);
    assert_eq!(r.ix.actual_current(), 20.0, "full current with motion");
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    for _ in 0..1_600 {
        r.cycle();
    }
    assert_eq!(r.ix.actual_current(), 10.0, "the new 50 %");
}

/// SMD-R2-102: idle at 0 %: no current, but Drive_Is_Enabled stays 1.
#[test]
fn smd_r2_102_zero_idle_current() {
    let mut r = rig(0);
    r.ix.write_config(r.now(), 6, 0);
    r.out.position = 10;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..1_600 {
        r.cycle();
    }
    assert_eq!(r.ix.actual_current(), 0.0);
    assert_ne!(r.s1() & stat1::DRIVE_IS_ENABLED, 0);
}

/// SMD-R1-012: with the motor supply missing (shaft does not turn) and stall detection off, a move
/// completes in the data while the encoder stands still.
#[test]
fn smd_r1_012_aux_power_only() {
    let mut r = rig(CFG0_USE_ENCODER);
    r.ix.set_shaft_blocked(r.now(), true);
    r.out.position = 5_000;
    r.command(cmd0::RELATIVE_MOVE);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 5_000);
    assert_eq!(r.last.encoder_position, 0);
    assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
}

/// SMD-R4-007, SMD-R4-008: homing to a hard stop — jog into the stop with stall detection until
/// Stall_Detected; Reset Errors with the rotor still held; Preset Position clears Position_Invalid;
/// Preset Encoder then makes both positions equal.
#[test]
fn smd_r4_008_home_to_a_hard_stop() {
    let mut r = rig(STALL);
    r.out.velocity = 500;
    r.command(cmd0::JOG_CW);
    for _ in 0..200 {
        r.cycle();
    }
    r.ix.set_shaft_blocked(r.now(), true); // the hard stop
    r.until(10_000, |i| i.status1 & stat1::STALL_DETECTED != 0);
    // SMD-R4-007: the jog stopped with Position_Invalid (STAT0 = Module_OK | Position_Invalid |
    // Stopped, 0x4408) and Stall_Detected with the driver enabled (STAT1 less the Heartbeat_Bit:
    // 0xC000).
    assert_eq!(r.s0(), 0x4408);
    assert_eq!(r.s1() & !stat1::HEARTBEAT, 0xC000);
    r.command(cmd0::RESET_ERRORS);
    assert_eq!(r.s1() & stat1::STALL_DETECTED, 0);
    r.command(0);
    r.out.position = 1_000;
    r.command(cmd0::PRESET_POSITION);
    assert_eq!((r.pos(), r.s0() & stat0::POSITION_INVALID), (1_000, 0));
    r.command(0);
    r.command(cmd0::PRESET_ENCODER);
    assert_eq!(r.last.encoder_position, 1_000);
    for _ in 0..100 {
        r.cycle();
    }
    assert_eq!(r.s1() & stat1::STALL_DETECTED, 0);
}
