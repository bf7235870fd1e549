//! The SMD's two DC inputs (E-Stop, end limits, Start Indexed and Stop Jog captures, active levels) and
//! Jog moves, rule by rule (catalogue `rules/smd.md`, R1, R2, R5, R6).

mod smd_rig;

use ds402::smd::config::CFG0_USE_ENCODER;
use ds402::smd::indexer::{cmd0, cmd1, stat0, stat1};
use smd_rig::Rig;

const GP: u16 = 0;
const CW_LIMIT: u16 = 1;
const CCW_LIMIT: u16 = 2;
const START_INDEXED: u16 = 3;
const STOP_JOG: u16 = 4;
const E_STOP: u16 = 5;

/// A ready unit (driver on, position valid) with these input functions; both inputs active when
/// current flows (CFG_Word_1 = 3).
fn rig(in1: u16, in2: u16, encoder: bool) -> Rig {
    Rig::ready_with(
        in1 | (in2 << 3) | if encoder { CFG0_USE_ENCODER } else { 0 },
        10_000,
        10,
        10,
    )
}

fn input(r: &mut Rig, n: usize, current: bool) {
    r.ix.set_input(r.now(), n, current);
    r.cycle();
}

fn jog(r: &mut Rig, bit: u16, ms: u32) {
    r.command(bit);
    for _ in 0..ms {
        r.cycle();
    }
}

/// SMD-R1-001, SMD-R5-023, SMD-R5-024, SMD-R6-075, SMD-R1-034: two inputs, each with its own level; IN1_Active/IN2_Active after the level bits; an
/// unwired input with level 1 reads inactive; a General Purpose input changes no move.
#[test]
fn smd_r5_023_024_r6_075_active_levels() {
    let mut r = rig(GP, GP, false);
    assert_eq!(
        r.s1() & (stat1::IN1_ACTIVE | stat1::IN2_ACTIVE),
        0,
        "unwired, level 1"
    );
    input(&mut r, 1, true);
    assert_eq!(
        r.s1() & (stat1::IN1_ACTIVE | stat1::IN2_ACTIVE),
        stat1::IN1_ACTIVE
    );
    r.ix.write_config(r.now(), 2, 0x0002); // IN1 level 0: active without current.
    r.cycle();
    assert_eq!(
        r.s1() & (stat1::IN1_ACTIVE | stat1::IN2_ACTIVE),
        0,
        "current flows: inactive"
    );
    input(&mut r, 1, false);
    assert_eq!(
        r.s1() & (stat1::IN1_ACTIVE | stat1::IN2_ACTIVE),
        stat1::IN1_ACTIVE
    );
    // General Purpose: a move runs to its end whatever the input does.
    let mut r = rig(GP, GP, false);
    r.out.position = 3_000;
    r.command(cmd0::RELATIVE_MOVE);
    for k in 0..2_000 {
        r.ix.set_input(r.now(), 1, k % 7 == 0);
        r.cycle();
    }
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 3_000);
    assert_eq!(r.s0() & (stat0::INPUT_ERROR | stat0::COMMAND_ERROR), 0);
}

/// SMD-R1-027, SMD-R1-030, SMD-R1-028: an E-Stop edge stops a move at once (never Decelerating, no
/// Move_Complete), sets Input_Error and Position_Invalid; the driver stays enabled.
#[test]
fn smd_r1_027_028_030_e_stop_during_a_move() {
    let mut r = rig(E_STOP, GP, false);
    r.out.position = 100_000;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..500 {
        r.cycle();
    }
    let at = r.pos();
    input(&mut r, 1, true);
    assert_eq!(
        r.s0() & (stat0::STOPPED | stat0::DECELERATING | stat0::MOVE_COMPLETE),
        stat0::STOPPED
    );
    assert_eq!(r.pos(), at);
    assert_ne!(r.s0() & stat0::INPUT_ERROR, 0);
    assert_ne!(r.s0() & stat0::POSITION_INVALID, 0);
    assert_ne!(r.s1() & stat1::DRIVE_IS_ENABLED, 0);
}

/// SMD-R2-014, SMD-R1-029, SMD-R6-055: E-Stop at rest also makes the position invalid; while it is
/// active no move (Jog included) starts — Input_Error, not Command_Error; Input_Error stays after the
/// input goes inactive until Reset Errors.
#[test]
fn smd_r2_014_r1_029_e_stop_at_rest_blocks_moves() {
    let mut r = rig(GP, E_STOP, false);
    input(&mut r, 2, true);
    assert_ne!(r.s0() & stat0::POSITION_INVALID, 0);
    r.command(cmd0::RESET_ERRORS);
    r.command(0);
    r.out.position = 100;
    for bit in [cmd0::RELATIVE_MOVE, cmd0::JOG_CW, cmd0::JOG_CCW] {
        r.command(bit);
        assert_eq!(
            r.s0() & (stat0::INPUT_ERROR | stat0::COMMAND_ERROR | stat0::STOPPED),
            stat0::INPUT_ERROR | stat0::STOPPED,
            "{bit:#x}"
        );
        r.command(0);
    }
    assert_eq!(r.pos(), 0);
    input(&mut r, 2, false);
    assert_ne!(r.s0() & stat0::INPUT_ERROR, 0, "kept until Reset Errors");
    r.command(cmd0::RESET_ERRORS);
    assert_eq!(r.s0() & stat0::INPUT_ERROR, 0);
}

/// SMD-R2-039, SMD-R6-053, SMD-R6-068: an end limit during a Relative move stops it at once, whatever
/// the direction: Input_Error, Limit_Condition, Position_Invalid, no Move_Complete; Limit_Condition
/// clears when the limit goes inactive.
#[test]
fn smd_r2_039_limit_during_a_move() {
    let mut r = rig(CW_LIMIT, CCW_LIMIT, false);
    r.out.position = -100_000; // Moving CCW, the CW limit trips.
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..300 {
        r.cycle();
    }
    input(&mut r, 1, true);
    assert_eq!(
        r.s0()
            & (stat0::STOPPED
                | stat0::INPUT_ERROR
                | stat0::POSITION_INVALID
                | stat0::MOVE_COMPLETE
                | stat0::DECELERATING),
        stat0::STOPPED | stat0::INPUT_ERROR | stat0::POSITION_INVALID
    );
    assert_ne!(r.s1() & stat1::LIMIT_CONDITION, 0);
    input(&mut r, 1, false);
    assert_eq!(r.s1() & stat1::LIMIT_CONDITION, 0);
    assert_ne!(r.s0() & stat0::INPUT_ERROR, 0);
}

/// SMD-R2-015, SMD-R6-068 gap: a limit becoming active at rest changes only the input bit.
#[test]
fn smd_r2_015_limit_at_rest() {
    let mut r = rig(CW_LIMIT, GP, false);
    input(&mut r, 1, true);
    assert_ne!(r.s1() & stat1::IN1_ACTIVE, 0);
    assert_eq!(r.s1() & stat1::LIMIT_CONDITION, 0);
    assert_eq!(r.s0() & (stat0::POSITION_INVALID | stat0::INPUT_ERROR), 0);
}

/// SMD-R2-040: with an end limit active, Absolute and Relative moves are refused (Input_Error) in
/// either direction.
#[test]
fn smd_r2_040_no_move_from_an_active_limit() {
    let mut r = rig(CW_LIMIT, GP, false);
    input(&mut r, 1, true);
    r.out.position = -1_000;
    r.command(cmd0::RELATIVE_MOVE);
    assert_ne!(r.s0() & stat0::INPUT_ERROR, 0);
    assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0);
    r.command(0);
    r.command(cmd0::ABSOLUTE_MOVE);
    for _ in 0..100 {
        r.cycle();
    }
    assert_eq!(r.pos(), 0);
}

/// SMD-R2-042, SMD-R2-043, SMD-R2-045, SMD-R2-046: a Jog or a Registration move into an active limit
/// is refused with Input_Error — for 200 cycles Motor_Position stays 0, Stopped stays 1 and no Moving
/// bit comes — and one away from it runs, with no Input_Error, in its direction at 10 steps/ms once up
/// to speed. Both limits, both kinds of move.
#[test]
fn smd_r2_042_043_045_046_jogging_at_a_limit() {
    for (limit_input, into, away) in [
        (1usize, cmd0::JOG_CW, cmd0::JOG_CCW),
        (2, cmd0::JOG_CCW, cmd0::JOG_CW),
    ] {
        for registration in [0, cmd1::REGISTRATION_MOVE] {
            let case = format!("limit on IN{limit_input}, CMD_word1 {registration:#06x}");
            let mut r = rig(CW_LIMIT, CCW_LIMIT, false);
            r.out.cmd1 |= registration;
            r.out.position = 1_000; // the Registration move's stopping distance
            input(&mut r, limit_input, true);
            r.command(into);
            for _ in 0..200 {
                assert_eq!(
                    r.s0()
                        & (stat0::INPUT_ERROR
                            | stat0::STOPPED
                            | stat0::MOVING_CW
                            | stat0::MOVING_CCW),
                    stat0::INPUT_ERROR | stat0::STOPPED,
                    "{case}"
                );
                assert_eq!(r.pos(), 0, "{case}");
                r.cycle();
            }
            r.command(cmd0::RESET_ERRORS);
            r.command(0);
            let (dir, moving) = if away == cmd0::JOG_CW {
                (1, stat0::MOVING_CW)
            } else {
                (-1, stat0::MOVING_CCW)
            };
            r.command(away);
            let mut before = r.pos();
            for k in 0..1_200 {
                r.cycle();
                assert_eq!(
                    r.s0() & (stat0::INPUT_ERROR | stat0::STOPPED | moving),
                    moving,
                    "{case}, cycle {k}"
                );
                // 10,000 steps/s reached after (10,000 − 141) / 10 ≈ 986 ms.
                if k >= 1_000 {
                    assert_eq!((r.pos() - before) * dir, 10, "{case}, cycle {k}");
                }
                before = r.pos();
            }
        }
    }
}

/// SMD-R2-041, SMD-R2-044: either limit becoming active stops a jog at once.
#[test]
fn smd_r2_041_044_limit_stops_a_jog() {
    for (bit, limit_input) in [(cmd0::JOG_CW, 2usize), (cmd0::JOG_CCW, 1)] {
        let mut r = rig(CW_LIMIT, CCW_LIMIT, false);
        jog(&mut r, bit, 200);
        input(&mut r, limit_input, true);
        assert_eq!(
            r.s0() & (stat0::STOPPED | stat0::POSITION_INVALID | stat0::MOVE_COMPLETE),
            stat0::STOPPED | stat0::POSITION_INVALID
        );
        assert_ne!(r.s1() & stat1::LIMIT_CONDITION, 0);
        // SMD-R6-021: Reset Errors clears Limit_Condition even with the limit still active.
        r.command(cmd0::RESET_ERRORS);
        assert_eq!(r.s1() & stat1::LIMIT_CONDITION, 0);
    }
}

/// SMD-R2-055, SMD-R2-056, SMD-R2-057, SMD-R2-020 (Jog): a jog starts at the starting speed, accelerates to Velocity and
/// runs there while its bit stays 1; the bit going to 0 is a controlled stop with Move_Complete and the
/// position still valid.
#[test]
fn smd_r2_055_056_057_jog_runs_and_stops() {
    let mut r = rig(GP, GP, false);
    r.command(cmd0::JOG_CCW);
    // The first cycle of the jog: moving CCW and accelerating, both.
    assert_eq!(
        r.s0() & (stat0::ACCELERATING | stat0::MOVING_CCW | stat0::MOVING_CW | stat0::STOPPED),
        stat0::ACCELERATING | stat0::MOVING_CCW
    );
    let n = r.until(10_000, |i| i.status0 & stat0::ACCELERATING == 0);
    // (10,000 − 141) / 10,000 steps/s² ≈ 986 ms.
    assert!((984..=988).contains(&n), "{n} ms accelerating");
    let a = r.pos();
    for _ in 0..1_000 {
        r.cycle();
    }
    assert_eq!(a - r.pos(), 10_000, "one second at 10,000 steps/s");
    assert_eq!(r.ix.speed(), -10_000.0);
    r.command(0);
    assert_ne!(r.s0() & stat0::DECELERATING, 0);
    let n = r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert!((984..=988).contains(&n), "{n} ms decelerating");
    assert_eq!(
        r.s0() & (stat0::MOVE_COMPLETE | stat0::POSITION_INVALID),
        stat0::MOVE_COMPLETE
    );
}

/// SMD-R2-058, SMD-R2-059: a new Velocity during a jog ramps to it without a new edge; a new
/// Deceleration rules the final stop.
#[test]
fn smd_r2_058_059_jog_speed_changes() {
    let mut r = rig(GP, GP, false);
    jog(&mut r, cmd0::JOG_CW, 1_500);
    assert_eq!(r.ix.speed(), 10_000.0);
    r.out.velocity = 20_000;
    r.cycle();
    assert_ne!(r.s0() & stat0::ACCELERATING, 0);
    let n = r.until(10_000, |i| i.status0 & stat0::ACCELERATING == 0);
    assert!(
        (998..=1_001).contains(&n),
        "{n} ms from 10,000 to 20,000 at 10,000 steps/s²"
    );
    assert_eq!(r.ix.speed(), 20_000.0);
    r.out.velocity = 5_000;
    r.cycle();
    assert_ne!(r.s0() & stat0::DECELERATING, 0);
    r.until(10_000, |i| i.status0 & stat0::DECELERATING == 0);
    assert_eq!(r.ix.speed(), 5_000.0);
    assert_eq!(r.s1() & stat1::INVALID_JOG_CHANGE, 0);
    r.out.deceleration = 20;
    r.cycle();
    r.command(0);
    let n = r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    // (5,000 − 141) / 20,000 s ≈ 243 ms.
    assert!((241..=245).contains(&n), "{n} ms stopping");
}

/// SMD-R2-059, SMD-R2-058: a new Velocity written in ONE update together with a new Acceleration and
/// Deceleration ramps with the new values, and the new Deceleration rules the final stop; the old
/// ramps would miss every position and status word below. Worked by hand (Jerk 0, linear ramps;
/// starting speed 141 steps/s; the rig's 1 ms updates; a change's own update runs its first
/// millisecond):
///
/// - Jog CW (0x0080) at Velocity 1,141 with Acceleration 1 (1,000 steps/s²): 1.000 s of ramp
///   (641 steps), then 1,141 steps/s; 1,499 ms in: 641 + 0.499 · 1,141 = 1,210.359 steps.
/// - Update 1,500: Velocity 5,141, Acceleration 4, Deceleration 5. Up at 4,000 steps/s²: 1.000 s,
///   x(t) = 1,141 t + 2,000 t². 500 ms in: 1,210.359 + 570.5 + 500 = 2,280.859 (the old 1,000
///   steps/s²: 1,905.859); 900 ms: 3,857.259; 1,100 ms, at 5,141 steps/s: 4,865.459; update 3,000:
///   4,351.359 + 0.501 · 5,141 = 6,927.000.
/// - Update 3,001: Velocity 2,141, Acceleration 3, Deceleration 8. Down at 8,000 steps/s²:
///   0.375 s (the old 5,000 steps/s²: 0.600 s), x(t) = 5,141 t − 4,000 t²: 100 ms in 7,401.1;
///   374 ms in 8,290.23, still decelerating; 376 ms in, at 2,141 steps/s; update 3,900: 8,292.375 +
///   0.525 · 2,141 = 9,416.4.
/// - Update 3,901: the Jog bit to 0. The stop from 2,141 to 141 steps/s at 8,000 steps/s² takes
///   0.250 s and 285.25 steps: 120 ms in 9,416.4 + 256.92 − 57.6 = 9,615.72; it ends in update
///   4,150 at 9,701.65, Move_Complete (0x4088).
#[test]
fn smd_r2_059_speed_and_ramps_changed_in_one_update() {
    let mut r = Rig::ready_with(0, 1_141, 1, 1);
    // Moving_CW 0x0001, Accelerating 0x0020, Decelerating 0x0040, Module_OK 0x4000.
    let at = |r: &mut Rig, update: u32, now: &mut u32| {
        assert!(update > *now);
        for _ in *now..update {
            r.cycle();
        }
        *now = update;
        (r.pos(), r.s0())
    };
    r.command(0x0080);
    let mut now = 1;
    assert_eq!(at(&mut r, 1_499, &mut now), (1_210, 0x4001));
    r.out.velocity = 5_141;
    r.out.acceleration = 4;
    r.out.deceleration = 5;
    assert_eq!(at(&mut r, 1_999, &mut now), (2_281, 0x4021));
    assert_eq!(at(&mut r, 2_399, &mut now), (3_857, 0x4021));
    assert_eq!(at(&mut r, 2_599, &mut now), (4_865, 0x4001));
    assert_eq!(at(&mut r, 3_000, &mut now), (6_927, 0x4001));
    r.out.velocity = 2_141;
    r.out.acceleration = 3;
    r.out.deceleration = 8;
    assert_eq!(at(&mut r, 3_100, &mut now), (7_401, 0x4041));
    assert_eq!(at(&mut r, 3_374, &mut now), (8_290, 0x4041));
    assert_eq!(at(&mut r, 3_376, &mut now), (8_295, 0x4001));
    assert_eq!(at(&mut r, 3_900, &mut now), (9_416, 0x4001));
    assert_eq!(r.ix.speed(), 2_141.0);
    r.out.cmd0 = 0;
    assert_eq!(at(&mut r, 4_020, &mut now), (9_616, 0x4041));
    assert_eq!(at(&mut r, 4_149, &mut now), (9_702, 0x4041));
    assert_eq!(at(&mut r, 4_150, &mut now), (9_702, 0x4088));
    assert_eq!(r.s1() & 0x0200, 0, "no Invalid_Jog_Change");
}

/// SMD-R2-060, SMD-R6-069, SMD-R6-020: a Velocity below the starting speed (or an Acceleration of 0)
/// written during a jog is refused: Invalid_Jog_Change, the jog keeps its speed, no Command_Error;
/// valid data clears the bit; Reset Errors does not.
#[test]
fn smd_r2_060_r6_069_invalid_jog_change() {
    let mut r = rig(GP, GP, false);
    jog(&mut r, cmd0::JOG_CW, 1_500);
    r.out.velocity = 100;
    r.cycle();
    assert_ne!(r.s1() & stat1::INVALID_JOG_CHANGE, 0);
    assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0);
    for _ in 0..100 {
        r.cycle();
    }
    assert_eq!(r.ix.speed(), 10_000.0);
    r.out.velocity = 10_000;
    r.out.acceleration = 0;
    r.cycle();
    assert_ne!(r.s1() & stat1::INVALID_JOG_CHANGE, 0);
    r.out.acceleration = 10;
    r.cycle();
    assert_eq!(r.s1() & stat1::INVALID_JOG_CHANGE, 0);
    // Reset Errors cannot rise while the Jog bit is 1 (SMD-R1-024): set the bit again, end the jog,
    // then Reset Errors at rest.
    r.out.velocity = 100;
    r.cycle();
    assert_ne!(r.s1() & stat1::INVALID_JOG_CHANGE, 0);
    r.command(0);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    r.command(cmd0::RESET_ERRORS);
    assert_ne!(
        r.s1() & stat1::COMMAND_ACKNOWLEDGE,
        0,
        "Reset Errors accepted"
    );
    assert_ne!(
        r.s1() & stat1::INVALID_JOG_CHANGE,
        0,
        "Reset Errors keeps it"
    );
}

/// SMD-R6-040: a Jog with a bad parameter sets Command_Error and Move_Complete and does not run.
#[test]
fn smd_r6_040_bad_jog_parameters_complete() {
    let mut r = rig(GP, GP, false);
    r.out.acceleration = 0;
    r.command(cmd0::JOG_CW);
    assert_eq!(
        r.s0() & (stat0::COMMAND_ERROR | stat0::MOVE_COMPLETE | stat0::STOPPED),
        stat0::COMMAND_ERROR | stat0::MOVE_COMPLETE | stat0::STOPPED
    );
}

/// SMD-R1-031, SMD-R1-033: a Stop Jog edge during a jog is a controlled stop with
/// Move_Complete and captures the encoder; during a Relative move it changes nothing; at rest it
/// captures nothing.
#[test]
fn smd_r1_031_032_033_stop_jog_input() {
    let mut r = rig(STOP_JOG, GP, true);
    jog(&mut r, cmd0::JOG_CW, 1_200);
    let enc = r.last.encoder_position;
    input(&mut r, 1, true);
    assert_ne!(r.s0() & stat0::DECELERATING, 0);
    assert!((enc..=enc + 12).contains(&r.last.trapped_encoder_position));
    let trapped = r.last.trapped_encoder_position;
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(
        r.s0() & (stat0::MOVE_COMPLETE | stat0::POSITION_INVALID),
        stat0::MOVE_COMPLETE
    );
    // At rest: no capture.
    input(&mut r, 1, false);
    input(&mut r, 1, true);
    assert_eq!(r.last.trapped_encoder_position, trapped);
    input(&mut r, 1, false);
    r.command(0);
    // During a Relative move: ignored.
    r.out.position = 5_000;
    r.command(cmd0::RELATIVE_MOVE);
    let start = r.pos();
    input(&mut r, 1, true);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos() - start, 5_000);
    assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
    assert_eq!(r.last.trapped_encoder_position, trapped);
}

/// SMD-R1-032: the Stop Jog input only acts on Jog and Registration moves: during an Absolute move, a
/// Relative move, a Blend, a Dwell and a Find Home, three edges of it (on, off, on) change nothing —
/// every cycle's input words, bar IN1_Active, are those of the same move without them, and each move
/// ends where it would: 5,000; 5,000; 1,000 + 1,000; 1,000 − 400; home at 0.
#[test]
fn smd_r1_032_stop_jog_input_ignored_by_other_moves() {
    type Start = fn(&mut Rig);
    let cases: [(&str, Start, i32, u16); 5] = [
        (
            "Absolute",
            |r| {
                r.out.position = 5_000;
                r.command(cmd0::ABSOLUTE_MOVE);
            },
            5_000,
            stat0::MOVE_COMPLETE,
        ),
        (
            "Relative",
            |r| {
                r.out.position = 5_000;
                r.command(cmd0::RELATIVE_MOVE);
            },
            5_000,
            stat0::MOVE_COMPLETE,
        ),
        (
            "Blend",
            |r| {
                r.program(&[(1_000, 4_000, 10, 10), (1_000, 8_000, 10, 10)], false);
                r.command(cmd0::RUN_ASSEMBLED_MOVE);
            },
            2_000,
            stat0::MOVE_COMPLETE,
        ),
        (
            "Dwell",
            |r| {
                r.program(&[(1_000, 4_000, 10, 10), (-400, 8_000, 10, 10)], false);
                r.out.cmd1 |= cmd1::DWELL;
                r.out.jerk = 200;
                r.command(cmd0::RUN_ASSEMBLED_MOVE);
            },
            600,
            stat0::MOVE_COMPLETE,
        ),
        (
            "Find Home",
            |r| {
                r.out.velocity = 2_000;
                r.command(cmd0::FIND_HOME_CW);
            },
            0,
            stat0::AT_HOME,
        ),
    ];
    for (name, start, end, done) in cases {
        let run = |edges: bool| {
            // IN1 = Stop Jog, IN2 = Home over steps 1,500 … 1,700.
            let mut r = rig(STOP_JOG, 6, true);
            start(&mut r);
            let mut trace = Vec::new();
            for k in 0..12_000 {
                if edges && [100, 300, 500].contains(&k) {
                    r.ix.set_input(r.now(), 1, k != 300);
                }
                if r.s0() & stat0::AT_HOME == 0 {
                    r.ix.set_input(r.now(), 2, (1_500..=1_700).contains(&r.ix.position()));
                }
                let mut i = r.cycle();
                i.status1 &= !stat1::IN1_ACTIVE;
                trace.push(i);
            }
            trace
        };
        let with = run(true);
        assert_eq!(with, run(false), "{name}");
        let last = with[with.len() - 1];
        assert_eq!(last.motor_position, end, "{name}");
        assert_eq!(
            last.status0 & (done | stat0::STOPPED | stat0::COMMAND_ERROR | stat0::INPUT_ERROR),
            done | stat0::STOPPED,
            "{name}"
        );
        // The edges fell in the motion.
        for k in [100, 300, 500] {
            assert_eq!(with[k].status0 & stat0::STOPPED, 0, "{name}, cycle {k}");
        }
    }
}

/// SMD-R1-025, SMD-R1-026: with the encoder on, every Start Indexed edge copies Encoder_Position into
/// Trapped_Encoder_Position; with it off nothing is captured.
#[test]
fn smd_r1_025_026_start_indexed_capture() {
    let mut r = rig(GP, START_INDEXED, true);
    r.out.position = 4_000;
    r.command(cmd0::PRESET_ENCODER);
    r.command(0);
    input(&mut r, 2, true);
    assert_eq!(r.last.trapped_encoder_position, 4_000);
    input(&mut r, 2, false);
    r.out.position = 77;
    r.command(cmd0::PRESET_ENCODER);
    r.command(0);
    assert_eq!(
        r.last.trapped_encoder_position, 4_000,
        "SMD-R6-048: held until the next edge"
    );
    input(&mut r, 2, true);
    assert_eq!(r.last.trapped_encoder_position, 77);
    input(&mut r, 2, false);

    // The encoder switched off (CFG_Word_0 without Use_Encoder): Encoder_Position reads 0, and an
    // edge captures nothing — Trapped_Encoder_Position keeps 77, where a capture would give 0.
    r.ix.write_config(r.now(), 1, u32::from(START_INDEXED << 3));
    r.cycle();
    assert_eq!(
        (r.last.encoder_position, r.last.trapped_encoder_position),
        (0, 77)
    );
    input(&mut r, 2, true);
    assert_eq!(
        r.last.trapped_encoder_position, 77,
        "no capture with the encoder off"
    );
}

/// SMD-R2-038 picks: Hold during a jog (the Jog bit falling in the same update) holds it; Resume runs
/// it again while Resume_Move stays 1, at the Resume block's Velocity; Resume going to 0 is a
/// controlled stop with Move_Complete.
#[test]
fn smd_r2_038_jog_hold_and_resume() {
    let mut r = rig(GP, GP, false);
    jog(&mut r, cmd0::JOG_CW, 1_200);
    r.command(cmd0::HOLD_MOVE);
    assert_ne!(r.s0() & stat0::DECELERATING, 0);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(
        r.s0() & (stat0::IN_HOLD_STATE | stat0::MOVE_COMPLETE),
        stat0::IN_HOLD_STATE
    );
    r.command(0);
    r.out.velocity = 4_000;
    r.command(cmd0::RESUME_MOVE);
    assert_eq!(r.s0() & (stat0::IN_HOLD_STATE | stat0::STOPPED), 0);
    for _ in 0..1_000 {
        r.cycle();
    }
    assert_eq!(r.ix.speed(), 4_000.0);
    r.command(0);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
}

#[test]
fn e_stop_refuses_resume_of_nothing() {
    // An E-Stop while a move is held cancels it: a later Resume is a Command_Error.
    let mut r = rig(E_STOP, GP, false);
    r.out.position = 50_000;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..800 {
        r.cycle();
    }
    r.command(cmd0::HOLD_MOVE);
    r.until(10_000, |i| i.status0 & stat0::IN_HOLD_STATE != 0);
    input(&mut r, 1, true);
    assert_eq!(r.s0() & stat0::IN_HOLD_STATE, 0);
    input(&mut r, 1, false);
    r.command(0);
    r.command(cmd0::RESUME_MOVE);
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0);
}
