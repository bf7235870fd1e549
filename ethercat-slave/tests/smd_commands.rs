//! SMD-R6-006 through the EtherCAT path: every command of Reference 6 sent by the CMD_word0 value of
//! its command block (Tables R6.1–R6.17: 16#0001 … 16#4000, the programming blocks 16#0800 and
//! 16#1800), with the CMD_word1 bits of Figure R6.3 the tests use (0x8000 Enable_Driver, 0x2000
//! Preset_to_Encoder, 0x0200 Assembled_Move_Type, 0x0080 Registration_Move, 0x0010
//! Reverse_Blend_Direction, 0x0002 Motor Current), each seen in the input bytes a master reads:
//! exact positions and exact status words worked out by hand from the manual. Then one test per
//! named status bit (`stat0`, `stat1`): the constant is the bit of Figures R6.4 and R6.5, and a
//! master sees that bit, alone or with the bits worked out beside it.
//!
//! Unless a test says otherwise: Starting_Speed 141 steps/s (the fixture's 0x8010:03); STATUS_word0
//! 0x4008 is Module_OK (bit 14) with Stopped (bit 3); STATUS_word1 carries Drive_Is_Enabled (bit
//! 15, 0x8000) with the driver enabled and Heartbeat_Bit (bit 11) by the master's clock
//! ([`Master::heartbeat`]).

mod common;
#[path = "common/smd_master.rs"]
mod smd_master;

use common::master::{download, request};
use ds402::smd::config::EncoderKind;
use ds402::smd::indexer::{stat0, stat1, Indexer};
use ethercat_slave::smd::binding::{Device, SmdUnit};
use od::hook::ProcessImage;
use smd_master::{In, Master, Out};

/// Velocity 10,000 steps/s, Acceleration and Deceleration 100 (100,000 steps/s²): a ramp between
/// 141 and 10,000 steps/s lasts 98.59 ms and covers (10,000² − 141²) / 200,000 = 499.9006 steps.
const FAST: Out = Out {
    cmd0: 0,
    cmd1: 0x8000,
    position: 0,
    velocity: 10_000,
    acceleration: 100,
    deceleration: 100,
    motor_current: 0,
    jerk: 0,
};

/// Velocity 1,141 steps/s, Acceleration and Deceleration 1 (1,000 steps/s²): after t s of a jog,
/// 141 t + 500 t² steps (t ≤ 1 s); 400 ms in, 136.4 steps at 541 steps/s, from which a stop takes
/// 0.4 s and 136.4 steps more.
const SLOW: Out = Out {
    velocity: 1_141,
    acceleration: 1,
    deceleration: 1,
    ..FAST
};

/// The indexer of the unit, for what it senses (inputs, temperature, shaft) at `m.c.now`.
fn ix(m: &mut Master) -> &mut Indexer {
    m.c.unit_mut(0).unwrap().indexer_mut()
}

/// An SDO download of `value` (`len` bytes) to 0x8010:`sub` through the mailbox.
fn configure(m: &mut Master, sub: u8, value: u32, len: usize) {
    download(&mut m.c, 0, 0x8010, sub, &value.to_le_bytes()[..len], false).unwrap();
}

/// In Op with the driver enabled and `params`, CFG_Word_0 = `cfg0` (written first, by SDO), the
/// position preset to 0 (0x0200): Position_Invalid 0.
fn ready_with(cfg0: u16, params: Out) -> Master {
    let mut m = Master::op();
    if cfg0 != 0 {
        configure(&mut m, 1, u32::from(cfg0), 2);
    }
    m.out = params;
    let i = m.command(0x0200);
    assert_eq!(i.status0, 0x4008, "preset: Position_Invalid 0");
    assert_eq!(
        i.status1,
        0xA000 | m.heartbeat(),
        "Command_Acknowledge, Drive_Is_Enabled"
    );
    let i = m.command(0);
    assert_eq!((i.motor_position, i.status0), (0, 0x4008));
    assert_eq!(i.status1, 0x8000 | m.heartbeat());
    m
}

fn ready() -> Master {
    ready_with(0, FAST)
}

/// Cycles until `update` updates have passed since the command at update 1 (`now` counts them);
/// the position and STATUS_word0 then.
fn at(m: &mut Master, now: &mut u32, update: u32) -> (i32, u16) {
    assert!(update > *now, "update {update} after {now}");
    let i = m.run(update - *now);
    *now = update;
    (i.motor_position, i.status0)
}

// ---------------------------------------------------------------------------------------------------
// CMD_word0 commands

/// SMD-R6-006: 0x0002 Relative Move goes 1,000 steps from where it is, 0x0001 Absolute Move to the
/// Position itself (−500). Relative 1,000: 197.2 ms (two ramps of 499.9006 steps and 0.1988 steps
/// at 10,000 steps/s), its first update accelerating CW (0x4021); Absolute from 1,000 to −500:
/// 1,500 steps CCW (first update 0x4022), two ramps and 500.2 steps at 10,000 steps/s, 247.2 ms.
#[test]
fn smd_r6_006_0x0002_relative_and_0x0001_absolute() {
    let mut m = ready();
    m.out.position = 1_000;
    let i = m.command(0x0002);
    assert_eq!(
        (i.motor_position, i.status0),
        (0, 0x4021),
        "Accelerating, Moving_CW"
    );
    let mut now = 1;
    assert_eq!(at(&mut m, &mut now, 197), (1_000, 0x4041), "Decelerating");
    assert_eq!(at(&mut m, &mut now, 198), (1_000, 0x4088), "Move_Complete");
    m.command(0);
    m.out.position = -500;
    let i = m.command(0x0001);
    assert_eq!(
        (i.motor_position, i.status0),
        (1_000, 0x4022),
        "Accelerating, Moving_CCW"
    );
    let mut now = 1;
    // 100 ms: 499.9006 + 10,000 · 1.41 ms = 514.0006 steps covered.
    assert_eq!(at(&mut m, &mut now, 100), (486, 0x4002), "Moving_CCW");
    assert_eq!(at(&mut m, &mut now, 247), (-500, 0x4042));
    assert_eq!(at(&mut m, &mut now, 248), (-500, 0x4088));
}

/// SMD-R6-006: 0x0004 Hold Move brings a Relative move of 5,000 steps to its hold state, 0x0008
/// Resume Move runs it on to the original target. 200 ms in, at 10,000 steps/s: 499.9006 +
/// 10,000 · 101.41 ms = 1,514.0006 steps. Hold in update 201: down to 141 steps/s in 98.59 ms and
/// 499.9006 steps, at rest from update 299 at 2,013.9012, In_Hold_State with Stopped (0x400C).
/// Resume in update 301: 2,986 steps, 2 · 98.59 ms + 1,986.1988 / 10,000 s = 395.8 ms, ending in
/// its 396th update.
#[test]
fn smd_r6_006_0x0004_hold_and_0x0008_resume() {
    let mut m = ready();
    m.out.position = 5_000;
    m.command(0x0002);
    let mut now = 1;
    assert_eq!(at(&mut m, &mut now, 200), (1_514, 0x4001));
    m.out.cmd0 = 0x0004;
    assert_eq!(at(&mut m, &mut now, 201), (1_524, 0x4041), "Decelerating");
    assert_eq!(at(&mut m, &mut now, 298), (2_014, 0x4041));
    assert_eq!(
        at(&mut m, &mut now, 299),
        (2_014, 0x400C),
        "In_Hold_State, Stopped"
    );
    m.out.cmd0 = 0;
    assert_eq!(at(&mut m, &mut now, 300), (2_014, 0x400C));
    // Resume's Position word is unused (Table R6.4): the target stays 5,000.
    m.out.position = -7;
    let i = m.command(0x0008);
    assert_eq!((i.motor_position, i.status0), (2_014, 0x4021));
    let mut now = 1;
    assert_eq!(at(&mut m, &mut now, 395), (5_000, 0x4041));
    assert_eq!(at(&mut m, &mut now, 396), (5_000, 0x4088), "Move_Complete");
}

/// SMD-R6-006: 0x0010 Immediate Stop ends a Relative move of 5,000 steps at once where it is
/// (100 ms in: 514.0006 steps), no deceleration, Position_Invalid set, no Move_Complete (0x4408).
#[test]
fn smd_r6_006_0x0010_immediate_stop() {
    let mut m = ready();
    m.out.position = 5_000;
    m.command(0x0002);
    let mut now = 1;
    assert_eq!(at(&mut m, &mut now, 100), (514, 0x4001));
    m.out.cmd0 = 0x0010;
    assert_eq!(at(&mut m, &mut now, 101), (514, 0x4408));
    assert_eq!(at(&mut m, &mut now, 200), (514, 0x4408));
}

/// SMD-R6-006: 0x0020 Find Home CW and 0x0040 Find Home CCW, with Input 1 the Home input
/// (CFG_Word_0 = 0x0006, Reference 4's Home-input-only profile): each searches in its own direction
/// (400 ms in: ±136.4 steps); the Home input becoming active stops it (136.4 steps more, to ±272.8)
/// for a 2 s pause; then it backs off the input, pauses again and returns at the starting speed; the
/// input's next activation is home: Motor_Position 0, At_Home with Stopped (0x4018), no
/// Move_Complete.
#[test]
fn smd_r6_006_0x0020_and_0x0040_find_home_cw_and_ccw() {
    // (command, direction, Accelerating + Moving that way, Decelerating + Moving that way,
    // Moving that way at constant speed, and the same three the other way.)
    for (cmd, sign, acc, dec, run, acc_back, dec_back) in [
        (
            0x0020u16, 1i32, 0x4021u16, 0x4041u16, 0x4001u16, 0x4022u16, 0x4042u16,
        ),
        (0x0040, -1, 0x4022, 0x4042, 0x4002, 0x4021, 0x4041),
    ] {
        let mut m = ready_with(0x0006, SLOW);
        let i = m.command(cmd);
        assert_eq!((i.motor_position, i.status0), (0, acc), "{cmd:#06x}");
        let mut now = 1;
        assert_eq!(at(&mut m, &mut now, 400), (136 * sign, acc));
        let sensed = m.c.now;
        ix(&mut m).set_input(sensed, 1, true);
        // 390 ms into the stop: 136.4 + 541 · 0.39 − 500 · 0.39² = 271.34 steps.
        assert_eq!(at(&mut m, &mut now, 790), (271 * sign, dec));
        // In the pause: Stopped, the search's stop done.
        assert_eq!(at(&mut m, &mut now, 1_500), (273 * sign, 0x4008));
        // Backing off, opposite to the search.
        assert_eq!(at(&mut m, &mut now, 3_000).1, acc_back);
        let sensed = m.c.now;
        ix(&mut m).set_input(sensed, 1, false);
        assert_eq!(at(&mut m, &mut now, 3_100).1, dec_back);
        // Second pause, then the return at 141 steps/s towards the input.
        assert_eq!(at(&mut m, &mut now, 5_000).1, 0x4008);
        assert_eq!(at(&mut m, &mut now, 6_500).1, run);
        let sensed = m.c.now;
        ix(&mut m).set_input(sensed, 1, true);
        assert_eq!(at(&mut m, &mut now, 6_501), (0, 0x4018), "{cmd:#06x}: home");
    }
}

/// SMD-R6-006, SMD-R6-029: 0x0080 Jog CW and 0x0100 Jog CCW run while the bit stays 1 (400 ms in:
/// ±136.4 steps); the bit back at 0 stops in 0.4 s (±272.8 steps), Move_Complete. With CMD_word1
/// 0x0080 (Registration_Move) the same 0x0080 is a Registration move: the bit falling is the stop
/// condition (Minimum Registration Move Distance 0) and it runs out exactly the Stopping Distance
/// (Position 100) from the 136 whole steps covered: 236.
#[test]
fn smd_r6_006_0x0080_and_0x0100_jogs_and_cmd1_0x0080_registration() {
    for (cmd, sign, acc, dec) in [
        (0x0080u16, 1i32, 0x4021u16, 0x4041u16),
        (0x0100, -1, 0x4022, 0x4042),
    ] {
        let mut m = ready_with(0, SLOW);
        let i = m.command(cmd);
        assert_eq!((i.motor_position, i.status0), (0, acc), "{cmd:#06x}");
        let mut now = 1;
        assert_eq!(at(&mut m, &mut now, 400), (136 * sign, acc));
        m.out.cmd0 = 0;
        // 390 ms into the stop: 136.4 + 541 · 0.39 − 500 · 0.39² = 271.34 steps.
        assert_eq!(at(&mut m, &mut now, 790), (271 * sign, dec));
        assert_eq!(at(&mut m, &mut now, 810), (273 * sign, 0x4088));
    }
    let mut m = ready_with(0, SLOW);
    m.out.cmd1 = 0x8080;
    m.out.position = 100;
    m.command(0x0080);
    let mut now = 1;
    assert_eq!(at(&mut m, &mut now, 400), (136, 0x4021));
    m.out.cmd0 = 0;
    // Braking at 1,000 steps/s² from 541 steps/s for the 100 steps: 236.6 ms.
    assert_eq!(at(&mut m, &mut now, 600).1, 0x4041);
    assert_eq!(at(&mut m, &mut now, 700), (236, 0x4088));
}

/// SMD-R6-006: 0x0400 Reset Errors clears Command_Error (here from an Absolute Move to 8,388,608,
/// out of range: 0x5008) and sets Command_Acknowledge (STATUS_word1 0x2000) while the bit stays 1;
/// it also clears Move_Complete.
#[test]
fn smd_r6_006_0x0400_reset_errors() {
    let mut m = ready();
    m.out.position = 8_388_608;
    let i = m.command(0x0001);
    assert_eq!((i.motor_position, i.status0), (0, 0x5008), "Command_Error");
    assert_eq!(i.status1, 0x8000 | m.heartbeat());
    m.command(0);
    let i = m.command(0x0400);
    assert_eq!(i.status0, 0x4008);
    assert_eq!(i.status1, 0xA000 | m.heartbeat(), "Command_Acknowledge");
    let i = m.command(0);
    assert_eq!(i.status1, 0x8000 | m.heartbeat());
    m.out.position = 10;
    m.command(0x0002);
    let i = m.run(50);
    assert_eq!((i.motor_position, i.status0), (10, 0x4088));
    m.command(0);
    assert_eq!(m.command(0x0400).status0, 0x4008, "Move_Complete cleared");
}

/// SMD-R6-006, SMD-R6-016: 0x0800 First Block sets In_Assembled_Mode and
/// Waiting_For_Assembled_Segment (0x4308); each 0x1800 Segment Block is taken (Waiting 0: 0x4108)
/// and 0x0800 again asks for the next; CMD_word0 0 ends the programming (0x4008). 0x2000 Run
/// Assembled Move with CMD_word1 0x0200 (Dwell) runs the two segments of 1,000 and 2,000 steps
/// with the Jerk word's 100 ms between them: 1,000 steps end after 197.2 ms, the next 2,000 after
/// 297.2 ms more; with CMD_word1 0x0010 and bit 9 at 0 (a Blend, counter-clockwise) both run as one
/// move of 3,000 steps CCW, back to 0.
#[test]
fn smd_r6_006_0x0800_0x1800_program_and_0x2000_run_assembled() {
    let mut m = ready();
    assert_eq!(m.command(0x0800).status0, 0x4308);
    for position in [1_000, 2_000] {
        m.out.position = position;
        assert_eq!(m.command(0x1800).status0, 0x4108);
        assert_eq!(m.command(0x0800).status0, 0x4308);
    }
    assert_eq!(m.command(0).status0, 0x4008);
    m.out.cmd1 = 0x8200;
    m.out.jerk = 100;
    m.out.position = 0;
    let i = m.command(0x2000);
    assert_eq!((i.motor_position, i.status0), (0, 0x4021));
    let mut now = 1;
    assert_eq!(at(&mut m, &mut now, 250), (1_000, 0x4008), "the dwell");
    assert_eq!(at(&mut m, &mut now, 400).1, 0x4001);
    assert_eq!(at(&mut m, &mut now, 700), (3_000, 0x4088));
    m.out.cmd1 = 0x8010;
    m.out.jerk = 0;
    m.command(0);
    let i = m.command(0x2000);
    assert_eq!((i.motor_position, i.status0), (3_000, 0x4022));
    let mut now = 1;
    assert_eq!(at(&mut m, &mut now, 250).1, 0x4002, "no stop between them");
    assert_eq!(at(&mut m, &mut now, 500), (0, 0x4088));
}

/// SMD-R6-006, SMD-R6-011, SMD-R6-024: with Use_Encoder (CFG_Word_0 = 0x0400), 0x4000 Preset Encoder
/// sets Encoder_Position to the Position word (2,048) and leaves Motor_Position; 0x0200 Preset
/// Position with CMD_word1 0x2000 (Preset_to_Encoder) sets Motor_Position to 2,048 × 2,000 steps
/// per turn / 2,048 counts per turn = 2,000, the Position word (777) unused.
#[test]
fn smd_r6_006_0x4000_preset_encoder_and_cmd1_0x2000() {
    let mut m = ready_with(0x0400, FAST);
    m.out.position = 2_048;
    let i = m.command(0x4000);
    assert_eq!((i.motor_position, i.encoder_position), (0, 2_048));
    assert_eq!(i.status1, 0xA000 | m.heartbeat(), "Command_Acknowledge");
    m.command(0);
    m.out.cmd1 = 0xA000;
    m.out.position = 777;
    let i = m.command(0x0200);
    assert_eq!((i.motor_position, i.encoder_position), (2_000, 2_048));
    assert_eq!(i.status0, 0x4008);
}

/// SMD-R6-006 with CMD_word1 bits 15 and 1: without Enable_Driver (CMD_word1 0) Drive_Is_Enabled
/// reads 0 and a Relative move is refused with Command_Error (SMD-R6-031 pick); with 0x8000 it runs.
/// With 0x8002 the move's current is the Motor_Current word (25: 2.5 A), with 0x8000 the configured
/// 0x8010:07 (10).
#[test]
fn smd_r6_006_cmd1_0x8000_enable_driver_and_0x0002_motor_current() {
    let mut m = ready();
    m.out.cmd1 = 0;
    m.out.position = 10;
    m.out.motor_current = 25;
    let i = m.command(0);
    assert_eq!(i.status1, m.heartbeat(), "Drive_Is_Enabled 0");
    let i = m.command(0x0002);
    assert_eq!((i.motor_position, i.status0), (0, 0x5008), "Command_Error");
    m.out.cmd1 = 0x8002;
    m.command(0);
    m.command(0x0002);
    let i = m.run(50);
    assert_eq!((i.motor_position, i.status0), (10, 0x5088));
    assert_eq!(i.motor_current, 25);
    m.out.cmd1 = 0x8000;
    m.command(0);
    m.command(0x0002);
    let i = m.run(50);
    assert_eq!((i.motor_position, i.motor_current), (20, 10));
}

// ---------------------------------------------------------------------------------------------------
// STATUS_word0 (Figure R6.4), bit by bit

/// STATUS_word0 bit 0, Moving_CW: a jog CW at its full 1,141 steps/s (1,200 ms in) reads 0x4001.
#[test]
fn stat0_bit_0_moving_cw() {
    assert_eq!(stat0::MOVING_CW, 0x0001);
    let mut m = ready_with(0, SLOW);
    m.command(0x0080);
    assert_eq!(m.run(1_200).status0, 0x4001);
}

/// STATUS_word0 bit 1, Moving_CCW: a jog CCW at its full speed reads 0x4002.
#[test]
fn stat0_bit_1_moving_ccw() {
    assert_eq!(stat0::MOVING_CCW, 0x0002);
    let mut m = ready_with(0, SLOW);
    m.command(0x0100);
    assert_eq!(m.run(1_200).status0, 0x4002);
}

/// STATUS_word0 bit 2, In_Hold_State: a held move reads 0x400C (with Stopped).
#[test]
fn stat0_bit_2_in_hold_state() {
    assert_eq!(stat0::IN_HOLD_STATE, 0x0004);
    let mut m = ready();
    m.out.position = 5_000;
    m.command(0x0002);
    m.run(199);
    m.command(0x0004);
    assert_eq!(m.run(150).status0, 0x400C);
}

/// STATUS_word0 bit 3, Stopped: 0x4008 at rest, 0x4000 while moving at constant speed.
#[test]
fn stat0_bit_3_stopped() {
    assert_eq!(stat0::STOPPED, 0x0008);
    let mut m = ready_with(0, SLOW);
    assert_eq!(m.lrw().status0, 0x4008);
    m.out.cmd0 = 0x0080;
    assert_eq!(m.run(1_200).status0, 0x4001, "Moving_CW at constant speed");
}

/// STATUS_word0 bit 4, At_Home: after Find Home CW with the Home input already active at the
/// start (it backs off at once, SMD-R4-016), 0x4018 with Motor_Position 0.
#[test]
fn stat0_bit_4_at_home() {
    assert_eq!(stat0::AT_HOME, 0x0010);
    let mut m = ready_with(0x0006, SLOW);
    let sensed = m.c.now;
    ix(&mut m).set_input(sensed, 1, true);
    m.command(0x0020);
    m.run(300);
    let sensed = m.c.now;
    ix(&mut m).set_input(sensed, 1, false);
    m.run(3_000);
    let sensed = m.c.now;
    ix(&mut m).set_input(sensed, 1, true);
    let i = m.lrw();
    assert_eq!((i.motor_position, i.status0), (0, 0x4018));
}

/// STATUS_word0 bit 5, Accelerating: a jog's first update reads 0x4021.
#[test]
fn stat0_bit_5_accelerating() {
    assert_eq!(stat0::ACCELERATING, 0x0020);
    let mut m = ready_with(0, SLOW);
    assert_eq!(m.command(0x0080).status0, 0x4021);
}

/// STATUS_word0 bit 6, Decelerating: a jog's stop reads 0x4041.
#[test]
fn stat0_bit_6_decelerating() {
    assert_eq!(stat0::DECELERATING, 0x0040);
    let mut m = ready_with(0, SLOW);
    m.command(0x0080);
    m.run(1_200);
    assert_eq!(m.command(0).status0, 0x4041);
}

/// STATUS_word0 bit 7, Move_Complete: after a Relative move, 0x4088.
#[test]
fn stat0_bit_7_move_complete() {
    assert_eq!(stat0::MOVE_COMPLETE, 0x0080);
    let mut m = ready();
    m.out.position = 10;
    m.command(0x0002);
    assert_eq!(m.run(50).status0, 0x4088);
}

/// STATUS_word0 bit 8, In_Assembled_Mode: a Segment Block just taken reads 0x4108.
#[test]
fn stat0_bit_8_in_assembled_mode() {
    assert_eq!(stat0::IN_ASSEMBLED_MODE, 0x0100);
    let mut m = ready();
    m.command(0x0800);
    m.out.position = 100;
    assert_eq!(m.command(0x1800).status0, 0x4108);
}

/// STATUS_word0 bit 9, Waiting_For_Assembled_Segment: the First Block reads 0x4308 (bits 8 and
/// 9, R6 "First Block").
#[test]
fn stat0_bit_9_waiting_for_assembled_segment() {
    assert_eq!(stat0::WAITING_FOR_SEGMENT, 0x0200);
    let mut m = ready();
    assert_eq!(m.command(0x0800).status0, 0x4308);
}

/// STATUS_word0 bit 10, Position_Invalid: at power-up, 0x4408 (SMD-T2-002).
#[test]
fn stat0_bit_10_position_invalid() {
    assert_eq!(stat0::POSITION_INVALID, 0x0400);
    let mut m = Master::op();
    assert_eq!(m.lrw().status0, 0x4408);
}

/// STATUS_word0 bit 11, Input_Error: Input 1 as the E-Stop input (CFG_Word_0 = 0x0005) activated
/// at rest: Input_Error, and Position_Invalid (R6 bit 10: "an … Emergency Stop has occurred"),
/// 0x4C08.
#[test]
fn stat0_bit_11_input_error() {
    assert_eq!(stat0::INPUT_ERROR, 0x0800);
    let mut m = ready_with(0x0005, FAST);
    let sensed = m.c.now;
    ix(&mut m).set_input(sensed, 1, true);
    assert_eq!(m.lrw().status0, 0x4C08);
}

/// STATUS_word0 bit 12, Command_Error: two command bits at once (0x0003), 0x5008.
#[test]
fn stat0_bit_12_command_error() {
    assert_eq!(stat0::COMMAND_ERROR, 0x1000);
    let mut m = ready();
    m.out.position = 10;
    let i = m.command(0x0003);
    assert_eq!((i.motor_position, i.status0), (0, 0x5008));
}

/// STATUS_word0 bit 13, Configuration_Error: Motor_Current 0x8010:07 = 35 (above 34) by SDO, 0x6408
/// (SMD-T2-003; the write also invalidates the position).
#[test]
fn stat0_bit_13_configuration_error() {
    assert_eq!(stat0::CONFIGURATION_ERROR, 0x2000);
    let mut m = ready();
    configure(&mut m, 7, 35, 2);
    assert_eq!(m.lrw().status0, 0x6408);
}

/// STATUS_word0 bit 14, Module_OK: 0x4008 without a fault, 0x0008 with an internal fault.
#[test]
fn stat0_bit_14_module_ok() {
    assert_eq!(stat0::MODULE_OK, 0x4000);
    let mut m = ready();
    assert_eq!(m.lrw().status0, 0x4008);
    let sensed = m.c.now;
    ix(&mut m).set_internal_fault(sensed, true);
    assert_eq!(m.lrw().status0, 0x0008);
}

/// STATUS_word0 bit 15, Mode_Flag: CMD_word0 bit 15 Mode_Select = 1 reads 0xC008 (SMD-R6-010).
#[test]
fn stat0_bit_15_mode_flag() {
    assert_eq!(stat0::MODE_FLAG, 0x8000);
    let mut m = ready();
    assert_eq!(m.command(0x8000).status0, 0xC008);
    assert_eq!(m.command(0).status0, 0x4008);
}

// ---------------------------------------------------------------------------------------------------
// STATUS_word1 (Figure R6.5), bit by bit

/// STATUS_word1 bit 0, IN1_Active: current into Input 1 (active on current, CFG_Word_1 = 3),
/// 0x8001.
#[test]
fn stat1_bit_0_in1_active() {
    assert_eq!(stat1::IN1_ACTIVE, 0x0001);
    let mut m = ready();
    let sensed = m.c.now;
    ix(&mut m).set_input(sensed, 1, true);
    assert_eq!(m.lrw().status1, 0x8001 | m.heartbeat());
}

/// STATUS_word1 bit 1, IN2_Active: current into Input 2, 0x8002.
#[test]
fn stat1_bit_1_in2_active() {
    assert_eq!(stat1::IN2_ACTIVE, 0x0002);
    let mut m = ready();
    let sensed = m.c.now;
    ix(&mut m).set_input(sensed, 2, true);
    assert_eq!(m.lrw().status1, 0x8002 | m.heartbeat());
}

/// STATUS_word1 bit 4, Temperature_Above_90°C: 91 °C, 0x8010.
#[test]
fn stat1_bit_4_temperature_above_90() {
    assert_eq!(stat1::TEMPERATURE_ABOVE_90, 0x0010);
    let mut m = ready();
    let sensed = m.c.now;
    ix(&mut m).set_temperature(sensed, 91.0);
    assert_eq!(m.lrw().status1, 0x8010 | m.heartbeat());
}

/// STATUS_word1 bit 5, PreOp_SafeOp: in Safe-Op, 0x0020 (the outputs not taken: no
/// Drive_Is_Enabled).
#[test]
fn stat1_bit_5_preop_safeop() {
    assert_eq!(stat1::PREOP_SAFEOP, 0x0020);
    let mut m = Master::safe_op();
    assert_eq!(m.lrw().status1, 0x0020 | m.heartbeat());
    m.request_op();
    m.out.cmd1 = 0x8000;
    assert_eq!(m.lrw().status1, 0x8000 | m.heartbeat());
    request(&mut m.c, 0x04);
    assert_eq!(m.lrw().status1, 0x8020 | m.heartbeat());
}

/// STATUS_word1 bit 7, Driver_Fault: 96 °C, an over-temperature fault with the driver enabled:
/// Driver_Fault and Temperature_Above_90°C, and Drive_Is_Enabled stays 1 (SMD-R6-062 pick),
/// 0x8090.
#[test]
fn stat1_bit_7_driver_fault() {
    assert_eq!(stat1::DRIVER_FAULT, 0x0080);
    let mut m = ready();
    let sensed = m.c.now;
    ix(&mut m).set_temperature(sensed, 96.0);
    assert_eq!(m.lrw().status1, 0x8090 | m.heartbeat());
}

/// STATUS_word1 bit 9, Invalid_Jog_Change: Velocity 100 (below the starting speed) during a jog,
/// 0x8200.
#[test]
fn stat1_bit_9_invalid_jog_change() {
    assert_eq!(stat1::INVALID_JOG_CHANGE, 0x0200);
    let mut m = ready_with(0, SLOW);
    m.command(0x0080);
    m.run(100);
    m.out.velocity = 100;
    assert_eq!(m.lrw().status1, 0x8200 | m.heartbeat());
}

/// STATUS_word1 bit 10, Limit_Condition: Input 1 as the CW limit (CFG_Word_0 = 0x0001) reached
/// during a jog CW: Limit_Condition with IN1_Active, 0x8401.
#[test]
fn stat1_bit_10_limit_condition() {
    assert_eq!(stat1::LIMIT_CONDITION, 0x0400);
    let mut m = ready_with(0x0001, SLOW);
    m.command(0x0080);
    m.run(100);
    let sensed = m.c.now;
    ix(&mut m).set_input(sensed, 1, true);
    assert_eq!(m.lrw().status1, 0x8401 | m.heartbeat());
}

/// STATUS_word1 bit 11, Heartbeat_Bit: 0 until 500 ms after power-on, 1 from 500 to 1,000 ms, 0
/// again from 1,000 ms (SMD-R6-067), with the driver disabled: STATUS_word1 0x0000, 0x0800, 0x0000.
#[test]
fn stat1_bit_11_heartbeat() {
    assert_eq!(stat1::HEARTBEAT, 0x0800);
    let mut m = Master::safe_op();
    m.request_op();
    assert_eq!(m.ms(), 0, "no cycle yet");
    assert_eq!(m.run(499).status1, 0x0000, "499 ms");
    assert_eq!(m.lrw().status1, 0x0800, "500 ms");
    m.run(499);
    assert_eq!((m.ms(), m.last.status1), (999, 0x0800));
    assert_eq!(m.lrw().status1, 0x0000, "1,000 ms");
}

/// STATUS_word1 bit 12, Abs_Enc_Err: an absolute-encoder unit with a battery fault, as the input
/// bytes of its TxPDO (0x1C13) carry it: STATUS_word1 = 0x1000 (SMD-R6-066).
#[test]
fn stat1_bit_12_abs_enc_err() {
    assert_eq!(stat1::ABS_ENC_ERR, 0x1000);
    let mut u = SmdUnit::new(Device::Smd23kB, EncoderKind::Absolute).unwrap();
    let image = ProcessImage::from_assignment(u.dict(), 0x1C13).unwrap();
    let mut bytes = [0u8; 20];
    u.cycle(std::time::Duration::from_millis(1));
    u.send_process_data(&image, &mut bytes);
    assert_eq!(In::of(&bytes).status1, 0x0000);
    u.indexer_mut()
        .set_abs_encoder_fault(std::time::Instant::now(), true);
    u.cycle(std::time::Duration::from_millis(1));
    u.send_process_data(&image, &mut bytes);
    assert_eq!(In::of(&bytes).status1, 0x1000);
    assert_eq!(bytes[2..4], [0x00, 0x10]);
}

/// STATUS_word1 bit 13, Command_Acknowledge: Preset Position, 0xA000 while the bit stays 1.
#[test]
fn stat1_bit_13_command_acknowledge() {
    assert_eq!(stat1::COMMAND_ACKNOWLEDGE, 0x2000);
    let mut m = ready();
    assert_eq!(m.command(0x0200).status1, 0xA000 | m.heartbeat());
    assert_eq!(m.lrw().status1, 0xA000 | m.heartbeat());
    assert_eq!(m.command(0).status1, 0x8000 | m.heartbeat());
}

/// STATUS_word1 bit 14, Stall_Detected: with Use_Encoder and Enable_Stall_Detection (CFG_Word_0 =
/// 0x2400) and the shaft blocked, a Relative move of 1,000 steps stalls once the motor is more than
/// 45° (250 of 2,000 steps) ahead of the encoder: 70 ms in, 141 · 0.07 + 50,000 · 0.07² = 254.87
/// steps (69 ms: 247.78); it stops there at once, the position invalid: 0x4408, STATUS_word1
/// 0xC000.
#[test]
fn stat1_bit_14_stall_detected() {
    assert_eq!(stat1::STALL_DETECTED, 0x4000);
    let mut m = ready_with(0x2400, FAST);
    let sensed = m.c.now;
    ix(&mut m).set_shaft_blocked(sensed, true);
    m.out.position = 1_000;
    m.command(0x0002);
    let mut now = 1;
    assert_eq!(at(&mut m, &mut now, 69), (248, 0x4021));
    assert_eq!(m.last.status1, 0x8000 | m.heartbeat());
    assert_eq!(at(&mut m, &mut now, 70), (255, 0x4408));
    assert_eq!(m.last.status1, 0xC000 | m.heartbeat());
}

/// STATUS_word1 bit 15, Drive_Is_Enabled: follows CMD_word1 bit 15, 0x8000 and 0x0000.
#[test]
fn stat1_bit_15_drive_is_enabled() {
    assert_eq!(stat1::DRIVE_IS_ENABLED, 0x8000);
    let mut m = ready();
    assert_eq!(m.lrw().status1, 0x8000 | m.heartbeat());
    m.out.cmd1 = 0;
    assert_eq!(m.lrw().status1, m.heartbeat());
}

/// A host that runs the chain's cycle late (20 ms after the last, not 1 ms) with a new output image:
/// the unit first runs the indexer's exchange that fell due before the image came (its own cycle,
/// without new output data), then takes the image at the late cycle. A Relative move so taken starts
/// there: no step before it (taken 20 ms late it would be some 22 steps on: 141 steps/s starting
/// speed and 100,000 steps/s² for 20 ms), accelerating clockwise, and under way after.
#[test]
fn a_late_cycle_takes_the_new_image_after_the_overdue_exchange() {
    let mut m = ready();
    let start = m.last.motor_position;
    m.out.position = 1000;
    m.out.cmd0 = 0x0002;
    m.write();
    m.c.cycle(std::time::Duration::from_millis(20));
    let taken = m.read();
    assert_eq!(taken.motor_position, start);
    // Module_OK, Accelerating, Moving_CW: the move is taken.
    assert_eq!(taken.status0, 0x4021);
    let moving = m.run(20);
    assert!(moving.motor_position > start, "{moving:?}");
}
