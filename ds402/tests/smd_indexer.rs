//! The SMD23K-B / SMD24K indexer in Command Mode, rule by rule (catalogue `rules/smd.md`, R2 and R6),
//! exchanging process data every millisecond as a master would.

mod smd_rig;

use std::time::Duration;

use ds402::smd::config::{Configuration, EncoderKind, CFG0_USE_ENCODER};
use ds402::smd::indexer::{cmd0, cmd1, stat0, stat1, Indexer, Outputs};
use proptest::prelude::*;
use smd_rig::Rig;

/// SMD-T2-002, SMD-R2-009: at power-up STATUS_word0 = 0x4408: Module_OK, Position_Invalid, Stopped.
#[test]
fn smd_r2_009_power_up_status() {
    let r = Rig::new();
    assert_eq!(r.s0(), 0x4408);
    assert_eq!(r.last.motor_position, 0);
    assert_eq!(
        r.last.motor_current, 10,
        "8010:07 before any move (SMD-R6-049 gap)"
    );
    assert_eq!(r.last.jerk, 0);
}

/// SMD-R2-052, SMD-R2-053, SMD-R2-048, SMD-R2-020 (Absolute, Relative): Relative and Absolute moves end exactly on target with
/// Move_Complete in the update where Stopped returns; accelerating, cruise and decelerating in order.
#[test]
fn smd_r2_052_053_relative_and_absolute_end_on_target() {
    let mut r = Rig::ready();
    r.out.position = 12_345;
    r.command(cmd0::RELATIVE_MOVE);
    let mut phases = Vec::new();
    loop {
        let i = r.cycle();
        let p = i.status0 & (stat0::ACCELERATING | stat0::DECELERATING);
        if phases.last() != Some(&p) {
            phases.push(p);
        }
        if i.status0 & stat0::STOPPED != 0 {
            assert_ne!(i.status0 & stat0::MOVE_COMPLETE, 0, "complete with Stopped");
            break;
        }
        assert_eq!(i.status0 & stat0::MOVE_COMPLETE, 0);
        assert_ne!(i.status0 & stat0::MOVING_CW, 0);
    }
    assert_eq!(r.pos(), 12_345);
    assert_eq!(
        phases,
        [stat0::ACCELERATING, 0, stat0::DECELERATING, 0],
        "accelerate, cruise, decelerate, stop"
    );
    r.command(0);
    r.move_to_end(cmd0::ABSOLUTE_MOVE, -2_000);
    assert_eq!(r.pos(), -2_000);
    assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
}

/// SMD-R2-008: an Absolute move runs CCW to a smaller target.
#[test]
fn smd_r2_008_absolute_direction() {
    let mut r = Rig::ready();
    r.out.position = -500;
    r.command(cmd0::ABSOLUTE_MOVE);
    assert_ne!(r.s0() & stat0::MOVING_CCW, 0);
    assert_eq!(r.s0() & stat0::MOVING_CW, 0);
}

/// SMD-R6-004: only a 0→1 edge runs a command; the bit held at 1 runs nothing more, 1 → 0 → 1 runs
/// the move again.
#[test]
fn smd_r6_004_commands_run_on_edges_only() {
    let mut r = Rig::ready();
    r.out.position = 100;
    r.command(cmd0::RELATIVE_MOVE);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    for _ in 0..200 {
        r.cycle();
    }
    assert_eq!(r.pos(), 100, "held bit: no second move");
    r.command(0);
    r.command(cmd0::RELATIVE_MOVE);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 200);
}

/// SMD-R6-005: clearing the bit of a running Relative move does not affect it.
#[test]
fn smd_r6_005_clearing_the_bit_mid_move() {
    let mut r = Rig::ready();
    r.out.position = 3_000;
    r.command(cmd0::RELATIVE_MOVE);
    r.command(0);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 3_000);
    assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
}

/// SMD-R1-024: two CMD_word0 command bits rising in one update: Command_Error, nothing runs (R6
/// "Command Bits Must Transition").
#[test]
fn two_command_bits_rising_together_are_a_command_error() {
    let mut r = Rig::ready();
    r.out.position = 100;
    r.command(cmd0::RELATIVE_MOVE | cmd0::PRESET_POSITION);
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0);
    assert_ne!(r.s0() & stat0::STOPPED, 0);
    assert_eq!(r.pos(), 0);
}

/// SMD-R1-024: the motion command bits (CMD_word0 bits 0–10, 13, 14) are mutually exclusive. 0x0003
/// written from 0 is a Command_Error and runs neither move; so is a command bit rising while another
/// is still 1 (Absolute rising under a held Relative bit, Immediate Stop rising under a running Jog
/// bit). Gap pick: a move already in progress carries on to its normal end. Bits 11/12 (0x1800) and
/// 15 are outside the set.
#[test]
fn smd_r1_024_motion_command_bits_are_exclusive() {
    let clean = |r: &Rig| {
        r.s0() & (stat0::COMMAND_ERROR | stat0::INPUT_ERROR | stat0::MOVE_COMPLETE | stat0::STOPPED)
    };
    // 0x0003 from 0: Command_Error, no motion, Move_Complete not set.
    let mut r = Rig::ready();
    r.out.position = 1_000;
    r.command(cmd0::ABSOLUTE_MOVE | cmd0::RELATIVE_MOVE);
    assert_eq!(clean(&r), stat0::COMMAND_ERROR | stat0::STOPPED);
    for _ in 0..100 {
        r.cycle();
    }
    assert_eq!((r.pos(), r.s0() & stat0::STOPPED), (0, stat0::STOPPED));

    // A bit rising while another stays 1: 0x0002 (run to its end, bit kept) → 0x0003.
    let mut r = Rig::ready();
    r.out.position = 1_000;
    r.command(cmd0::RELATIVE_MOVE);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 1_000);
    assert_eq!(clean(&r), stat0::MOVE_COMPLETE | stat0::STOPPED);
    r.out.position = 5_000;
    r.command(cmd0::ABSOLUTE_MOVE | cmd0::RELATIVE_MOVE);
    assert_eq!(
        clean(&r),
        stat0::COMMAND_ERROR | stat0::STOPPED,
        "rejected; a move command was written, so Move_Complete is reset (SMD-R6-057)"
    );
    for _ in 0..100 {
        r.cycle();
    }
    assert_eq!(r.pos(), 1_000, "the Absolute move to 5,000 did not run");

    // Two bits rising during a running Relative move: rejected, the move ends on its target.
    let mut r = Rig::ready();
    r.out.position = 5_000;
    r.command(cmd0::RELATIVE_MOVE);
    r.command(0);
    for _ in 0..200 {
        r.cycle();
    }
    r.command(cmd0::HOLD_MOVE | cmd0::IMMEDIATE_STOP);
    assert_eq!(clean(&r), stat0::COMMAND_ERROR);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 5_000);
    assert_eq!(
        r.s0()
            & (stat0::MOVE_COMPLETE
                | stat0::POSITION_INVALID
                | stat0::IN_HOLD_STATE
                | stat0::COMMAND_ERROR),
        stat0::MOVE_COMPLETE | stat0::COMMAND_ERROR,
        "neither Hold nor Immediate Stop ran"
    );

    // Immediate Stop rising while the Jog bit stays 1: rejected, the jog runs on at Velocity.
    let mut r = Rig::ready();
    r.command(cmd0::JOG_CW);
    for _ in 0..1_500 {
        r.cycle();
    }
    assert_eq!(r.ix.speed(), 10_000.0);
    r.command(cmd0::JOG_CW | cmd0::IMMEDIATE_STOP);
    assert_eq!(clean(&r), stat0::COMMAND_ERROR);
    let at = r.pos();
    for _ in 0..1_000 {
        r.cycle();
    }
    assert_eq!(r.ix.speed(), 10_000.0);
    assert_eq!(r.pos() - at, 10_000, "one more second at 10,000 steps/s");
    assert_eq!(r.s0() & stat0::POSITION_INVALID, 0);

    // Outside the set: Program_Assembled with Read_Assembled_Data (0x0800 → 0x1800) is no error.
    let mut r = Rig::ready();
    r.command(cmd0::PROGRAM_ASSEMBLED);
    r.out.position = 1_000;
    r.command(cmd0::PROGRAM_ASSEMBLED | cmd0::READ_ASSEMBLED_DATA);
    assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0);
    assert_eq!(r.ix.assembled_program(), None, "still programming");
}

/// Every move command the rules name (SMD-R2-034, SMD-R6-031): its name, the CMD_word1 bits it needs
/// and its CMD_word0 bit.
const MOVES: [(&str, u16, u16); 9] = [
    ("Absolute", 0, cmd0::ABSOLUTE_MOVE),
    ("Relative", 0, cmd0::RELATIVE_MOVE),
    ("Jog CW", 0, cmd0::JOG_CW),
    ("Jog CCW", 0, cmd0::JOG_CCW),
    ("Registration CW", cmd1::REGISTRATION_MOVE, cmd0::JOG_CW),
    ("Registration CCW", cmd1::REGISTRATION_MOVE, cmd0::JOG_CCW),
    ("Find Home CW", 0, cmd0::FIND_HOME_CW),
    ("Find Home CCW", 0, cmd0::FIND_HOME_CCW),
    ("Run Assembled", 0, cmd0::RUN_ASSEMBLED_MOVE),
];

/// SMD-R2-034: no move starts while another runs: during a Relative move of 5,000, an Absolute, a
/// Relative, a Jog and a Registration move each way, a Find Home each way and a Run Assembled are each
/// refused with Command_Error, and the running move ends where it would, cycle for cycle as without
/// the refused command.
#[test]
fn smd_r2_034_no_new_move_while_one_runs() {
    let start = || {
        // IN1 = Home, never active; a stored program.
        let mut r = Rig::ready_with(6, 10_000, 10, 10);
        r.program(&[(1_000, 4_000, 10, 10), (1_000, 4_000, 10, 10)], false);
        r.out.position = 5_000;
        r.command(cmd0::RELATIVE_MOVE);
        r.command(0);
        for _ in 0..100 {
            r.cycle();
        }
        r
    };
    let mut alone = start();
    let mut undisturbed = Vec::new();
    for _ in 0..3_000 {
        let i = alone.cycle();
        undisturbed.push((i.status0 & !stat0::COMMAND_ERROR, i.motor_position));
    }
    assert_eq!(alone.pos(), 5_000);
    for (case, extra, c) in MOVES {
        let mut r = start();
        r.out.cmd1 |= extra;
        r.out.position = 100;
        r.command(c);
        assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0, "{case}");
        let mut seen = vec![(r.s0() & !stat0::COMMAND_ERROR, r.pos())];
        r.command(0);
        seen.push((r.s0() & !stat0::COMMAND_ERROR, r.pos()));
        for _ in 2..3_000 {
            let i = r.cycle();
            seen.push((i.status0 & !stat0::COMMAND_ERROR, i.motor_position));
        }
        assert_eq!(seen, undisturbed, "{case}");
    }
}

/// SMD-R2-010: an Absolute move while Position_Invalid is refused: Command_Error, no motion, no
/// Move_Complete. SMD-R2-011: a Relative move runs.
#[test]
fn smd_r2_010_011_absolute_needs_a_valid_position() {
    let mut r = Rig::new();
    r.out = Outputs {
        cmd1: cmd1::ENABLE_DRIVER,
        velocity: 1_000,
        acceleration: 10,
        deceleration: 10,
        position: 50,
        ..Outputs::default()
    };
    r.command(cmd0::ABSOLUTE_MOVE);
    assert_eq!(
        r.s0() & (stat0::COMMAND_ERROR | stat0::STOPPED | stat0::MOVE_COMPLETE),
        stat0::COMMAND_ERROR | stat0::STOPPED
    );
    r.command(0);
    r.move_to_end(cmd0::RELATIVE_MOVE, 50);
    assert_eq!(r.pos(), 50);
    assert_ne!(r.s0() & stat0::POSITION_INVALID, 0);
}

/// SMD-R6-023, SMD-R6-026, SMD-R6-064: Preset Position to either DINT extreme, clearing Move_Complete
/// and Position_Invalid; Command_Acknowledge while the bit stays 1, 0 once it is cleared.
#[test]
fn smd_r6_023_026_064_preset_position_and_acknowledge() {
    // Each of the two bits is cleared: Position_Invalid after an Immediate Stop during a move
    // (Move_Complete 0), Move_Complete after a move run to its end (Position_Invalid 0).
    let mut r = Rig::ready();
    r.out.position = 100_000;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..50 {
        r.cycle();
    }
    r.command(cmd0::IMMEDIATE_STOP);
    r.command(0);
    assert_eq!(
        r.s0() & (stat0::MOVE_COMPLETE | stat0::POSITION_INVALID),
        stat0::POSITION_INVALID
    );
    r.out.position = 7;
    r.command(cmd0::PRESET_POSITION);
    assert_eq!(
        (
            r.pos(),
            r.s0() & (stat0::MOVE_COMPLETE | stat0::POSITION_INVALID)
        ),
        (7, 0)
    );
    r.command(0);
    r.move_to_end(cmd0::RELATIVE_MOVE, 10);
    assert_eq!(
        r.s0() & (stat0::MOVE_COMPLETE | stat0::POSITION_INVALID),
        stat0::MOVE_COMPLETE
    );
    for p in [i32::MIN, i32::MAX] {
        r.out.position = p;
        r.command(cmd0::PRESET_POSITION);
        assert_eq!(r.pos(), p);
        assert_eq!(r.s0() & (stat0::MOVE_COMPLETE | stat0::POSITION_INVALID), 0);
        assert_ne!(r.s1() & stat1::COMMAND_ACKNOWLEDGE, 0);
        r.cycle();
        assert_ne!(
            r.s1() & stat1::COMMAND_ACKNOWLEDGE,
            0,
            "held while CMD0.9 = 1"
        );
        r.command(0);
        assert_eq!(r.s1() & stat1::COMMAND_ACKNOWLEDGE, 0);
    }
}

/// SMD-R6-004 wrap gap (SMD-R2-004): Motor_Position wraps in two's complement.
#[test]
fn smd_r2_004_motor_position_wraps() {
    let mut r = Rig::ready();
    r.out.position = i32::MAX - 5;
    r.command(cmd0::PRESET_POSITION);
    r.command(0);
    r.move_to_end(cmd0::RELATIVE_MOVE, 10);
    assert_eq!(r.pos(), i32::MIN + 4);
}

/// SMD-R6-027 pick: Preset Position during a move is refused; the move carries on.
#[test]
fn smd_r6_027_no_preset_while_moving() {
    let mut r = Rig::ready();
    r.out.position = 2_000;
    r.command(cmd0::RELATIVE_MOVE);
    r.out.position = 0;
    r.command(cmd0::PRESET_POSITION);
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0);
    assert_eq!(r.s1() & stat1::COMMAND_ACKNOWLEDGE, 0, "SMD-R6-065");
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 2_000);
}

/// SMD-R6-011, SMD-R6-024: Preset Encoder sets Encoder_Position; Preset Position with CMD_word1 bit 13
/// scales it: 2,048 counts at 1,024 counts and 400 steps per turn give 800 steps. With the encoder
/// off, Preset Encoder is refused.
#[test]
fn smd_r6_011_024_preset_encoder_and_preset_to_encoder() {
    let mut r = Rig::with(Configuration {
        cfg0: CFG0_USE_ENCODER,
        motor_resolution: 400,
        encoder_resolution: 1024,
        ..Configuration::default()
    });
    r.out.position = 2_048;
    r.command(cmd0::PRESET_ENCODER);
    assert_eq!(r.last.encoder_position, 2_048);
    assert_ne!(r.s1() & stat1::COMMAND_ACKNOWLEDGE, 0);
    r.command(0);
    r.out.cmd1 = cmd1::PRESET_TO_ENCODER;
    r.out.position = 7;
    r.command(cmd0::PRESET_POSITION);
    assert_eq!(r.pos(), 800);
    assert_eq!(r.s0() & stat0::POSITION_INVALID, 0);

    let mut off = Rig::new();
    off.out.position = 5;
    off.command(cmd0::PRESET_ENCODER);
    assert_ne!(off.s0() & stat0::COMMAND_ERROR, 0);
    assert_eq!(off.last.encoder_position, 0, "SMD-R6-047");
    assert_eq!(off.s1() & stat1::COMMAND_ACKNOWLEDGE, 0);
}

/// SMD-R2-001: with the encoder on, one turn of the motor is Encoder_Resolution counts.
#[test]
fn smd_r2_001_encoder_counts_with_the_motor() {
    let mut r = Rig::with(Configuration {
        cfg0: CFG0_USE_ENCODER,
        ..Configuration::default()
    });
    r.out = Outputs {
        cmd1: cmd1::ENABLE_DRIVER,
        velocity: 10_000,
        acceleration: 10,
        deceleration: 10,
        ..Outputs::default()
    };
    r.move_to_end(cmd0::RELATIVE_MOVE, 2_000);
    assert_eq!(r.pos(), 2_000);
    assert_eq!(r.last.encoder_position, 2_048);
}

/// SMD-R6-017, SMD-R6-018, SMD-R6-019, SMD-R6-052: Reset Errors clears Command_Error and
/// Move_Complete, not Position_Invalid or Configuration_Error; Command_Error survives a valid move.
#[test]
fn smd_r6_017_018_019_052_reset_errors() {
    let mut r = Rig::new();
    r.out.position = 1;
    r.command(cmd0::ABSOLUTE_MOVE); // Position invalid: Command_Error.
    r.command(0);
    r.ix.write_config(r.now(), 7, 35); // Motor_Current out of range.
    r.command(cmd0::RESET_ERRORS);
    assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0);
    assert_ne!(r.s0() & stat0::POSITION_INVALID, 0);
    assert_ne!(r.s0() & stat0::CONFIGURATION_ERROR, 0);
    assert_ne!(r.s1() & stat1::COMMAND_ACKNOWLEDGE, 0);

    let mut r = Rig::ready();
    r.out.acceleration = 0;
    r.command(cmd0::RELATIVE_MOVE);
    r.command(0);
    r.out.acceleration = 10;
    r.move_to_end(cmd0::RELATIVE_MOVE, 100);
    assert_eq!(
        r.pos(),
        100,
        "SMD-R6-009: a valid move runs with Command_Error set"
    );
    assert_eq!(
        r.s0() & (stat0::COMMAND_ERROR | stat0::MOVE_COMPLETE),
        stat0::COMMAND_ERROR | stat0::MOVE_COMPLETE
    );
    r.command(cmd0::RESET_ERRORS);
    assert_eq!(r.s0() & (stat0::COMMAND_ERROR | stat0::MOVE_COMPLETE), 0);
}

/// SMD-R6-028, SMD-R2-013, SMD-R6-059, SMD-R2-030: Immediate Stop at rest makes the position invalid; during a
/// move it stops at once: Stopped, no Move_Complete, never Decelerating.
#[test]
fn smd_r6_028_immediate_stop() {
    let mut r = Rig::ready();
    r.command(cmd0::IMMEDIATE_STOP);
    assert_ne!(r.s0() & stat0::POSITION_INVALID, 0);
    assert_eq!(r.pos(), 0);
    r.command(0);
    r.out.position = 100_000;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..300 {
        r.cycle();
    }
    let at = r.pos();
    assert!(at > 0);
    r.command(cmd0::IMMEDIATE_STOP);
    assert_eq!(
        r.s0() & (stat0::STOPPED | stat0::MOVE_COMPLETE | stat0::DECELERATING),
        stat0::STOPPED
    );
    assert_eq!(r.pos(), at, "no further step");
    assert_ne!(r.s0() & stat0::POSITION_INVALID, 0);
}

/// SMD-R2-031, SMD-R2-032, SMD-R2-021: Hold decelerates to a stop and holds with the position still
/// valid; Resume runs on to the original target and completes.
#[test]
fn smd_r2_031_032_hold_and_resume() {
    let mut r = Rig::ready();
    r.out.position = 50_000;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..1_500 {
        r.cycle();
    }
    r.command(cmd0::HOLD_MOVE);
    assert_ne!(r.s0() & stat0::DECELERATING, 0);
    assert_eq!(r.s0() & stat0::IN_HOLD_STATE, 0, "not yet stopped");
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(
        r.s0() & (stat0::IN_HOLD_STATE | stat0::MOVE_COMPLETE | stat0::POSITION_INVALID),
        stat0::IN_HOLD_STATE
    );
    let held_at = r.pos();
    assert!(held_at > 0 && held_at < 50_000, "{held_at}");
    for _ in 0..100 {
        r.cycle();
    }
    assert_eq!(r.pos(), held_at);
    r.command(0);
    r.out.velocity = 20_000; // SMD-R6-044: the Resume block's speed, the original target.
    r.command(cmd0::RESUME_MOVE);
    assert_eq!(r.s0() & stat0::IN_HOLD_STATE, 0);
    r.until(20_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 50_000);
    assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
}

/// Cycles until Stopped; the speed of every cycle with Decelerating = 1 and whether
/// Position_Invalid was ever 1 meanwhile. Fails if a moving cycle is not Decelerating.
fn stop_trace(r: &mut Rig) -> (Vec<f64>, bool) {
    let mut speeds = Vec::new();
    let mut invalid = false;
    loop {
        invalid |= r.s0() & stat0::POSITION_INVALID != 0;
        if r.s0() & stat0::STOPPED != 0 {
            return (speeds, invalid);
        }
        assert_ne!(
            r.s0() & stat0::DECELERATING,
            0,
            "Decelerating until the stop"
        );
        speeds.push(r.ix.speed().abs());
        r.cycle();
    }
}

/// SMD-R2-029: a controlled stop (Hold during a Relative move, the Jog bit going to 0) decelerates at
/// the move's programmed Deceleration — 4 steps/s less every millisecond with Acceleration 10 and
/// Deceleration 4 — from Velocity down to V_S = 141 steps/s (9,859 / 4,000 s = 2,464.75 ms), with
/// Decelerating = 1 until Stopped, and leaves Position_Invalid as it was: 0 stays 0 and an Absolute
/// move then runs; 1 stays 1 and an Absolute move is still refused.
#[test]
fn smd_r2_029_controlled_stop() {
    let check = |speeds: &[f64], from: f64| {
        assert_eq!(speeds[0], from - 4.0, "first cycle of the stop");
        for w in speeds.windows(2) {
            assert!((w[0] - w[1] - 4.0).abs() < 1e-6, "{} → {}", w[0], w[1]);
        }
        let last = speeds[speeds.len() - 1];
        // 2,464 ms after the stop began: 10,000 − 4 × 2,464 = 144 steps/s, V_S 141 a cycle later.
        assert!((last - 144.0).abs() < 1e-6, "last moving speed {last}");
        // (10,000 − 141) / 4,000 s = 2,464.75 ms: moving in 2,464 cycles, Stopped in the 2,465th.
        assert_eq!(speeds.len(), 2_464, "ms moving while stopping");
    };
    // Hold during a Relative move, position valid.
    let mut r = Rig::ready_with(0, 10_000, 10, 4);
    r.out.position = 1_000_000;
    r.command(cmd0::RELATIVE_MOVE);
    r.command(0);
    for _ in 0..1_500 {
        r.cycle();
    }
    assert_eq!(r.ix.speed(), 10_000.0);
    r.command(cmd0::HOLD_MOVE);
    let (speeds, invalid) = stop_trace(&mut r);
    check(&speeds, 10_000.0);
    assert!(!invalid);
    assert_eq!(
        r.s0() & (stat0::POSITION_INVALID | stat0::IN_HOLD_STATE | stat0::COMMAND_ERROR),
        stat0::IN_HOLD_STATE
    );
    r.command(0);
    r.move_to_end(cmd0::ABSOLUTE_MOVE, -3_000);
    assert_eq!(r.pos(), -3_000, "Absolute moves still allowed");
    assert_eq!(
        r.s0() & (stat0::COMMAND_ERROR | stat0::MOVE_COMPLETE),
        stat0::MOVE_COMPLETE
    );

    // The Jog bit going to 0.
    r.command(cmd0::JOG_CCW);
    for _ in 0..1_500 {
        r.cycle();
    }
    assert_eq!(r.ix.speed(), -10_000.0);
    r.command(0);
    let (speeds, invalid) = stop_trace(&mut r);
    check(&speeds, 10_000.0);
    assert!(!invalid);
    let at = r.pos();
    r.move_to_end(cmd0::ABSOLUTE_MOVE, at + 500);
    assert_eq!(r.pos(), at + 500, "Absolute moves still allowed");
    assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0);

    // Position_Invalid already 1 (a configuration write): it stays 1.
    let mut r = Rig::ready_with(0, 10_000, 10, 4);
    assert!(r.ix.write_config(r.now(), 6, 50));
    r.out.position = 1_000_000;
    r.command(cmd0::RELATIVE_MOVE);
    r.command(0);
    for _ in 0..1_500 {
        r.cycle();
    }
    r.command(cmd0::HOLD_MOVE);
    let (speeds, _) = stop_trace(&mut r);
    check(&speeds, 10_000.0);
    assert_eq!(
        r.s0() & (stat0::POSITION_INVALID | stat0::IN_HOLD_STATE),
        stat0::POSITION_INVALID | stat0::IN_HOLD_STATE
    );
    r.command(0);
    r.out.position = 0;
    r.command(cmd0::ABSOLUTE_MOVE);
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0, "still invalid");
}

/// SMD-R2-035: Resume with nothing held is a Command_Error; a running move carries on.
/// SMD-R2-031, the model's pick where the manual is silent: a Hold written once the move's final
/// braking has begun (here in its first cycle, (10,000² − 141²) / 20,000 = 4,999 steps still to go)
/// would stop where the braking ends anyway, so the move ends on its own deceleration: Move_Complete
/// at the target, not held.
#[test]
fn smd_r2_031_hold_in_the_final_braking_completes_the_move() {
    // From 5,000, so that the move's start is not 0.
    let mut r = Rig::ready();
    r.out.position = 5_000;
    r.command(cmd0::PRESET_POSITION);
    r.command(0);
    r.out.position = 20_000;
    r.command(cmd0::RELATIVE_MOVE);
    r.command(0);
    r.until(10_000, |i| i.status0 & stat0::DECELERATING != 0);
    r.command(cmd0::HOLD_MOVE);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 25_000);
    assert_eq!(
        r.s0() & (stat0::IN_HOLD_STATE | stat0::MOVE_COMPLETE),
        stat0::MOVE_COMPLETE
    );
}

/// SMD-R2-037: Hold with nothing running changes nothing.
#[test]
fn smd_r2_035_037_resume_and_hold_without_a_move() {
    let mut r = Rig::ready();
    r.command(cmd0::HOLD_MOVE);
    assert_eq!(r.s0() & (stat0::COMMAND_ERROR | stat0::IN_HOLD_STATE), 0);
    r.command(0);
    r.out.position = 1_000;
    r.command(cmd0::RELATIVE_MOVE);
    r.command(0);
    r.command(cmd0::RESUME_MOVE);
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 1_000);
}

/// SMD-R2-033: a new move while one is held cancels it; a later Resume is a Command_Error.
#[test]
fn smd_r2_033_new_move_cancels_the_held_one() {
    let mut r = Rig::ready();
    r.out.position = 50_000;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..1_000 {
        r.cycle();
    }
    r.command(cmd0::HOLD_MOVE);
    r.until(10_000, |i| i.status0 & stat0::IN_HOLD_STATE != 0);
    let held_at = r.pos();
    r.command(0);
    r.move_to_end(cmd0::RELATIVE_MOVE, 10);
    assert_eq!(r.pos(), held_at + 10);
    assert_eq!(r.s0() & stat0::IN_HOLD_STATE, 0);
    r.command(cmd0::RESUME_MOVE);
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0);
    assert_eq!(r.s0() & stat0::STOPPED, stat0::STOPPED);
}

/// SMD-R6-034, SMD-R6-035, SMD-R6-036, SMD-R6-037, SMD-R6-038, SMD-R2-051: out-of-range parameters
/// are Command_Errors with no motion and
/// no Move_Complete; the limits themselves are accepted.
#[test]
fn smd_r6_034_to_038_parameter_ranges() {
    let base = Outputs {
        cmd1: cmd1::ENABLE_DRIVER,
        velocity: 10_000,
        acceleration: 10,
        deceleration: 10,
        position: 100,
        ..Outputs::default()
    };
    let bad = [
        Outputs {
            position: 8_388_608,
            ..base
        },
        Outputs {
            position: -8_388_609,
            ..base
        },
        Outputs {
            velocity: 140,
            ..base
        },
        Outputs {
            velocity: 3_000_000,
            ..base
        },
        Outputs {
            acceleration: 0,
            ..base
        },
        Outputs {
            acceleration: 5_001,
            ..base
        },
        Outputs {
            deceleration: 0,
            ..base
        },
        Outputs {
            deceleration: 5_001,
            ..base
        },
        Outputs {
            jerk: 5_001,
            ..base
        },
        Outputs {
            cmd1: cmd1::ENABLE_DRIVER | cmd1::MOTOR_CURRENT,
            motor_current: 35,
            ..base
        },
    ];
    for out in bad {
        let mut r = Rig::ready();
        r.out = out;
        r.command(cmd0::RELATIVE_MOVE);
        assert_eq!(
            r.s0() & (stat0::COMMAND_ERROR | stat0::STOPPED | stat0::MOVE_COMPLETE),
            stat0::COMMAND_ERROR | stat0::STOPPED,
            "{out:?}"
        );
        assert_eq!(r.pos(), 0, "{out:?}");
    }
    let good = [
        Outputs {
            position: 8_388_607,
            velocity: 2_999_999,
            acceleration: 5_000,
            deceleration: 5_000,
            ..base
        },
        Outputs {
            position: -8_388_608,
            velocity: 2_999_999,
            acceleration: 5_000,
            deceleration: 5_000,
            ..base
        },
        Outputs {
            velocity: 141,
            acceleration: 1,
            deceleration: 1,
            jerk: 5_000,
            ..base
        },
        Outputs {
            motor_current: 35,
            ..base
        }, // SMD-R6-039: unchecked without CMD_word1 bit 1.
    ];
    for out in good {
        let mut r = Rig::ready();
        r.out = out;
        r.command(cmd0::RELATIVE_MOVE);
        assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0, "{out:?}");
        r.until(100_000, |i| i.status0 & stat0::STOPPED != 0);
        assert_eq!(r.pos(), out.position, "{out:?}");
    }
}

/// SMD-R6-032, SMD-R6-049, SMD-R6-050: in.Motor_Current is 8010:07 or, with CMD_word1 bit 1, the
/// Motor_Current word; in.Jerk echoes the move's Jerk.
#[test]
fn smd_r6_032_050_current_and_jerk_echo() {
    let mut r = Rig::ready();
    r.out.jerk = 250;
    r.move_to_end(cmd0::RELATIVE_MOVE, 1_000);
    assert_eq!((r.last.motor_current, r.last.jerk), (10, 250));
    r.out.cmd1 |= cmd1::MOTOR_CURRENT;
    r.out.motor_current = 25;
    r.out.jerk = 0;
    r.move_to_end(cmd0::RELATIVE_MOVE, 1_000);
    assert_eq!((r.last.motor_current, r.last.jerk), (25, 0));
    // The pick for CMD_word1 bit 1 alone: the current applies at once.
    r.out.cmd1 &= !cmd1::MOTOR_CURRENT;
    r.cycle();
    r.out.motor_current = 12;
    r.out.cmd1 |= cmd1::MOTOR_CURRENT;
    r.cycle();
    assert_eq!(r.last.motor_current, 12);
}

/// SMD-R6-030, SMD-R6-031, SMD-R5-027: Drive_Is_Enabled follows Enable_Driver with a valid
/// configuration; moves are refused while it is 0.
#[test]
fn smd_r6_030_031_r5_027_enable_driver() {
    let mut r = Rig::ready();
    assert_ne!(r.s1() & stat1::DRIVE_IS_ENABLED, 0);
    r.out.cmd1 = 0;
    r.cycle();
    assert_eq!(r.s1() & stat1::DRIVE_IS_ENABLED, 0);
    r.out.position = 100;
    r.command(cmd0::RELATIVE_MOVE);
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0);
    assert_eq!(r.pos(), 0);
    r.command(0);
    r.out.cmd1 = cmd1::ENABLE_DRIVER;
    r.ix.write_config(r.now(), 6, 101);
    r.cycle();
    assert_ne!(r.s0() & stat0::CONFIGURATION_ERROR, 0);
    assert_eq!(r.s1() & stat1::DRIVE_IS_ENABLED, 0, "invalid configuration");
    r.ix.write_config(r.now(), 6, 100);
    r.cycle();
    assert_eq!(r.s0() & stat0::CONFIGURATION_ERROR, 0);
    assert_ne!(r.s1() & stat1::DRIVE_IS_ENABLED, 0);
    assert_ne!(
        r.s0() & stat0::POSITION_INVALID,
        0,
        "SMD-R2-012: every 8010 write"
    );
}

/// Runs `cycles` cycles with CMD_word0 held and asserts in each that the command was refused and nothing
/// moved: Command_Error and Stopped set, no Moving, Accelerating or Decelerating bit, Motor_Position at
/// `at` (SMD-R2-051).
#[track_caller]
fn assert_refused_without_motion(r: &mut Rig, case: &str, at: i32, cycles: usize) {
    let motion = stat0::MOVING_CW | stat0::MOVING_CCW | stat0::ACCELERATING | stat0::DECELERATING;
    for k in 0..cycles {
        assert_eq!(
            r.s0() & (stat0::COMMAND_ERROR | stat0::STOPPED | motion),
            stat0::COMMAND_ERROR | stat0::STOPPED,
            "{case}, cycle {k}"
        );
        assert_eq!(r.pos(), at, "{case}, cycle {k}");
        r.cycle();
    }
}

/// SMD-R2-051: the unit checks the whole command before any motion, so a refused command never moves:
/// for 300 cycles after each of these, Motor_Position stays where it was and Stopped stays 1 — bad
/// parameters for an Absolute, a Relative, a Jog each way, a Registration move and a Find Home; a
/// Find Home with no Home input; a Resume with nothing held; a Run Assembled with no program; two move
/// bits at once.
#[test]
fn smd_r2_051_a_refused_command_never_moves() {
    type Setup = fn(&mut Rig) -> u16;
    let cases: [(&str, Setup); 11] = [
        ("Absolute, Velocity 140", |r| {
            r.out.velocity = 140;
            cmd0::ABSOLUTE_MOVE
        }),
        ("Relative, Acceleration 0", |r| {
            r.out.acceleration = 0;
            cmd0::RELATIVE_MOVE
        }),
        ("Jog CW, Deceleration 5,001", |r| {
            r.out.deceleration = 5_001;
            cmd0::JOG_CW
        }),
        ("Jog CCW, Velocity 3,000,000", |r| {
            r.out.velocity = 3_000_000;
            cmd0::JOG_CCW
        }),
        ("Registration, Position out of range", |r| {
            r.out.cmd1 |= cmd1::REGISTRATION_MOVE;
            r.out.position = 8_388_608;
            cmd0::JOG_CW
        }),
        ("Find Home, Jerk 5,001", |r| {
            r.ix.write_config(r.now(), 1, 6);
            r.cycle();
            r.command(cmd0::PRESET_POSITION);
            r.command(0);
            r.out.jerk = 5_001;
            cmd0::FIND_HOME_CW
        }),
        ("Find Home, no Home input", |_| cmd0::FIND_HOME_CCW),
        ("Resume, nothing held", |_| cmd0::RESUME_MOVE),
        ("Resume of a held move, Acceleration 0", |r| {
            r.hold_a_move(100_000, 500);
            r.out.acceleration = 0;
            cmd0::RESUME_MOVE
        }),
        ("Run Assembled, no program", |_| cmd0::RUN_ASSEMBLED_MOVE),
        ("Absolute and Relative", |_| {
            cmd0::ABSOLUTE_MOVE | cmd0::RELATIVE_MOVE
        }),
    ];
    for (case, setup) in cases {
        let mut r = Rig::ready();
        r.out.position = 2_000;
        let c = setup(&mut r);
        let at = r.pos();
        r.command(c);
        assert_refused_without_motion(&mut r, case, at, 300);
    }
}

/// SMD-R6-031 (pick): with Enable_Driver 0 every move command is refused — Absolute, Relative, Jog and
/// Registration each way, Find Home each way, Resume of a held move, Run Assembled — with Command_Error
/// and no motion; Preset Position, Reset Errors, Immediate Stop and programming still work.
#[test]
fn smd_r6_031_every_move_refused_with_the_driver_off() {
    let resume = ("Resume", 0, cmd0::RESUME_MOVE);
    for (case, extra, c) in MOVES.into_iter().chain([resume]) {
        // IN1 = Home; a stored program; a Relative move held at 1 s.
        let mut r = Rig::ready_with(6, 10_000, 10, 10);
        r.program(&[(1_000, 4_000, 10, 10), (1_000, 4_000, 10, 10)], false);
        r.hold_a_move(100_000, 1_000);
        assert_ne!(r.s0() & stat0::IN_HOLD_STATE, 0);
        let at = r.pos();
        r.out.cmd1 = extra;
        r.out.position = 2_000;
        r.cycle();
        assert_eq!(r.s1() & stat1::DRIVE_IS_ENABLED, 0);
        r.command(c);
        assert_refused_without_motion(&mut r, case, at, 300);
    }

    let mut r = Rig::ready();
    r.out.cmd1 = 0;
    r.cycle();
    r.out.position = 777;
    r.command(cmd0::PRESET_POSITION);
    assert_eq!(r.pos(), 777);
    r.command(0);
    r.command(cmd0::RELATIVE_MOVE);
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0);
    r.command(cmd0::RESET_ERRORS);
    assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0);
    r.command(cmd0::IMMEDIATE_STOP);
    assert_eq!(
        r.s0() & (stat0::COMMAND_ERROR | stat0::POSITION_INVALID),
        stat0::POSITION_INVALID
    );
    r.command(0);
    let seen = r.program(&[(1_000, 4_000, 10, 10), (500, 4_000, 10, 10)], false);
    assert!(
        seen.iter().all(|s| s & stat0::COMMAND_ERROR == 0),
        "{seen:?}"
    );
    assert_eq!(r.ix.assembled_program().map(<[_]>::len), Some(2));
}

/// SMD-R6-009: a set error bit does not stop a later valid command: with Command_Error, Input_Error or
/// Stall_Detected set, a Relative move of 1,000 runs to its end with Move_Complete, the error bit still
/// set until Reset Errors.
#[test]
fn smd_r6_009_error_bits_do_not_block_valid_commands() {
    type Raise = fn(&mut Rig);
    let cases: [(&str, u16, Raise, u16, u16); 3] = [
        (
            "Command_Error",
            0,
            |r| {
                r.out.acceleration = 0;
                r.command(cmd0::RELATIVE_MOVE);
                r.out.acceleration = 10;
            },
            stat0::COMMAND_ERROR,
            0,
        ),
        (
            "Input_Error",
            1, // IN1 = CW limit
            |r| {
                r.ix.set_input(r.now(), 1, true);
                r.command(cmd0::JOG_CW);
                r.ix.set_input(r.now(), 1, false);
            },
            stat0::INPUT_ERROR,
            0,
        ),
        (
            "Stall_Detected",
            CFG0_USE_ENCODER | ds402::smd::config::CFG0_ENABLE_STALL_DETECTION,
            |r| {
                r.ix.turn_shaft(r.now(), 300);
                r.cycle();
                r.ix.turn_shaft(r.now(), -300);
            },
            0,
            stat1::STALL_DETECTED,
        ),
    ];
    for (case, cfg0, raise, bit0, bit1) in cases {
        let mut r = Rig::ready_with(cfg0, 10_000, 10, 10);
        raise(&mut r);
        r.command(0);
        assert_eq!((r.s0() & bit0, r.s1() & bit1), (bit0, bit1), "{case}");
        let start = r.pos();
        r.out.position = 1_000;
        r.command(cmd0::RELATIVE_MOVE);
        assert_eq!(r.s0() & stat0::STOPPED, 0, "{case}: it runs");
        r.until(5_000, |i| i.status0 & stat0::STOPPED != 0);
        assert_eq!(r.pos(), start + 1_000, "{case}");
        assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0, "{case}");
        assert_eq!(
            (r.s0() & bit0, r.s1() & bit1),
            (bit0, bit1),
            "{case}: still set"
        );
        r.command(0);
        r.command(cmd0::RESET_ERRORS);
        assert_eq!((r.s0() & bit0, r.s1() & bit1), (0, 0), "{case}");
    }
}

/// The unit's encoder kind is the one it was built with; `is_moving` is true exactly in the cycles in
/// which STATUS_word0 shows Stopped = 0, over a whole Relative move and at rest before and after.
#[test]
fn encoder_kind_and_is_moving_as_reported() {
    for kind in [EncoderKind::Incremental, EncoderKind::Absolute] {
        assert_eq!(
            Indexer::new(kind, Configuration::default()).encoder_kind(),
            kind
        );
    }
    let mut r = Rig::ready();
    assert!(!r.ix.is_moving());
    r.out.position = 2_000;
    r.command(cmd0::RELATIVE_MOVE);
    let mut moving = 0;
    for _ in 0..2_000 {
        let i = r.cycle();
        assert_eq!(r.ix.is_moving(), i.status0 & stat0::STOPPED == 0);
        moving += usize::from(r.ix.is_moving());
    }
    assert!(moving > 300, "{moving}");
    assert!(!r.ix.is_moving());
    assert_eq!(r.pos(), 2_000);
}

/// SMD-R6-067: the Heartbeat_Bit changes state every 500 ms.
#[test]
fn smd_r6_067_heartbeat() {
    let mut r = Rig::new();
    let mut edges = Vec::new();
    let mut last = r.s1() & stat1::HEARTBEAT;
    for n in 2..=10_000u32 {
        let hb = r.cycle().status1 & stat1::HEARTBEAT;
        if hb != last {
            edges.push(n);
            last = hb;
        }
    }
    assert_eq!(edges.len(), 20, "{edges:?}");
    assert_eq!(edges[0], 500);
    for w in edges.windows(2) {
        assert_eq!(w[1] - w[0], 500);
    }
}

/// SMD-R2-054 gap: a zero-length move completes at once without motion.
#[test]
fn smd_r2_054_zero_length_move() {
    let mut r = Rig::ready();
    r.out.position = 0;
    r.command(cmd0::RELATIVE_MOVE);
    assert_eq!(
        r.s0() & (stat0::MOVE_COMPLETE | stat0::STOPPED | stat0::COMMAND_ERROR),
        stat0::MOVE_COMPLETE | stat0::STOPPED
    );
}

/// SMD-R2-007: Motor_Position is not clamped to the command range.
#[test]
fn smd_r2_007_position_beyond_the_command_range() {
    let mut r = Rig::ready();
    r.out.velocity = 2_999_999;
    r.out.acceleration = 5_000;
    r.out.deceleration = 5_000;
    r.move_to_end(cmd0::RELATIVE_MOVE, 8_000_000);
    r.move_to_end(cmd0::RELATIVE_MOVE, 8_000_000);
    assert_eq!(r.pos(), 16_000_000);
    assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0);
}

/// SMD-R3-007, SMD-R2-049: in the Table R3.2 move, Accelerating lasts T_A = 4.993 s and Decelerating
/// T_D = 3.994 s (to the 1 ms cycle).
#[test]
fn smd_r3_007_phase_durations_in_motion() {
    let mut r = Rig::ready();
    r.out.velocity = 100_000;
    r.out.acceleration = 20;
    r.out.deceleration = 25;
    r.out.position = 1_000_000;
    r.command(cmd0::RELATIVE_MOVE);
    let (mut acc, mut dec) = (1u32, 0u32);
    loop {
        let i = r.cycle();
        acc += u32::from(i.status0 & stat0::ACCELERATING != 0);
        dec += u32::from(i.status0 & stat0::DECELERATING != 0);
        if i.status0 & stat0::STOPPED != 0 {
            break;
        }
    }
    assert!((4_992..=4_994).contains(&acc), "{acc} ms accelerating");
    assert!((3_993..=3_995).contains(&dec), "{dec} ms decelerating");
    assert_eq!(r.pos(), 1_000_000);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    /// Every Relative and Absolute move ends exactly on target, never faster than its Velocity (one cycle's steps
    /// at most Velocity × 1 ms, rounded), with the motion bits true to the direction of travel
    /// (SMD-R2-016, SMD-R2-019) and Accelerating never with Decelerating (SMD-R2-018).
    #[test]
    fn relative_moves_end_on_target(
        offset in -200_000i32..200_000,
        velocity in 141u32..200_000,
        accel in 1u16..200,
        decel in 1u16..200,
        jerk in prop_oneof![Just(0u16), 1u16..=5000],
        absolute in proptest::bool::ANY,
    ) {
        let mut r = Rig::ready();
        r.out.velocity = velocity;
        r.out.acceleration = accel;
        r.out.deceleration = decel;
        r.out.jerk = jerk;
        r.out.position = offset;
        // From 0, an Absolute move to `offset` and a Relative one by it end at the same place.
        r.command(if absolute { cmd0::ABSOLUTE_MOVE } else { cmd0::RELATIVE_MOVE });
        let mut prev = 0i64;
        let mut first = true;
        for _ in 0..2_000_000 {
            let i = if first { first = false; r.last } else { r.cycle() };
            let p = i64::from(i.motor_position);
            let step = p - prev;
            prop_assert!(step.unsigned_abs() as f64 <= f64::from(velocity) / 1000.0 + 1.0, "{} steps in 1 ms", step);
            let s = i.status0;
            prop_assert!(!(s & stat0::ACCELERATING != 0 && s & stat0::DECELERATING != 0));
            prop_assert!(!(s & stat0::MOVING_CW != 0 && s & stat0::MOVING_CCW != 0));
            if step > 0 { prop_assert!(s & stat0::MOVING_CW != 0); }
            if step < 0 { prop_assert!(s & stat0::MOVING_CCW != 0); }
            prop_assert_eq!(s & stat0::STOPPED != 0, s & (stat0::MOVING_CW | stat0::MOVING_CCW) == 0);
            prev = p;
            if s & stat0::STOPPED != 0 {
                break;
            }
        }
        prop_assert_eq!(r.pos(), offset);
        prop_assert!(r.s0() & stat0::MOVE_COMPLETE != 0);
    }
}

/// On the host's clock the model derives its time step: `exchange(now)` after `start` runs the same
/// motion as `cycle` with the time since the previous exchange (a move at 1 ms, 3 ms and 7 ms
/// steps, inputs equal at every step); before `start` the first exchange runs none, and a time
/// before the last runs none either.
#[test]
fn exchange_derives_the_time_step_from_now() {
    let t0 = std::time::Instant::now();
    let mut by_dt = Rig::ready();
    let mut by_now = by_dt.ix.clone();
    by_now.start(t0, Duration::from_millis(1));
    let mut now = t0;
    let mut out = by_dt.out;
    out.cmd0 = cmd0::RELATIVE_MOVE;
    out.position = 5_000;
    let steps = [1u64, 3, 7].repeat(200);
    for (k, ms) in steps.iter().enumerate() {
        let dt = Duration::from_millis(*ms);
        now += dt;
        let a = by_dt.ix.cycle(out, dt);
        let b = by_now.exchange(now, out);
        assert_eq!(a, b, "step {k}");
        assert_eq!(by_dt.ix.time(), by_now.time(), "step {k}");
    }
    assert_eq!(by_now.position(), 5_000, "the move ended at its target");
    let mut fresh = Indexer::new(EncoderKind::Incremental, Configuration::default());
    fresh.exchange(t0 + Duration::from_secs(9), Outputs::default());
    assert_eq!(
        fresh.time(),
        Duration::ZERO,
        "no start: the first exchange runs nothing"
    );
    fresh.exchange(t0 + Duration::from_secs(10), Outputs::default());
    assert_eq!(fresh.time(), Duration::from_secs(1));
    fresh.exchange(t0 + Duration::from_secs(2), Outputs::default());
    assert_eq!(
        fresh.time(),
        Duration::from_secs(1),
        "a time before the last: none"
    );
    fresh.exchange(t0 + Duration::from_secs(11), Outputs::default());
    assert_eq!(fresh.time(), Duration::from_secs(2));
}
