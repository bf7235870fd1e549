//! SMD-R6-073 through the EtherCAT path: moves are commanded only in Op, and after the transition to
//! Op a fresh 0→1 edge of a command bit is needed. A master writes its output image with LRW in
//! Safe-Op (which the unit does not act on), requests Op and keeps the image; the first output data
//! in Op is the edge reference, so a bit already 1 in it is no edge (the catalogue's pick).

mod common;
#[path = "common/smd_master.rs"]
mod smd_master;

use smd_master::{Master, Out};

/// A Relative move (CMD_word0 = 0x0002) of 1,000 steps with the driver enabled (CMD_word1 =
/// 0x8000), Velocity 10,000 steps/s, Acceleration and Deceleration 100 (100,000 steps/s²), Jerk 0.
fn relative_1000() -> Out {
    Out {
        cmd0: 0x0002,
        cmd1: 0x8000,
        position: 1_000,
        velocity: 10_000,
        acceleration: 100,
        deceleration: 100,
        ..Out::default()
    }
}

/// The Relative move of [`relative_1000`] from Motor_Position 0 with the position never preset
/// (Position_Invalid, STATUS_word0 bit 10, stays 1): CMD_word0 0 for one cycle, then 0x0002.
/// By hand (Reference 3, linear ramps from the starting speed 141 steps/s): the acceleration to
/// 10,000 steps/s takes (10,000 − 141) / 100,000 = 98.59 ms and covers (10,000² − 141²) / 200,000
/// = 499.9006 steps, the deceleration the same, the 0.1988 steps between them 19.9 µs: the move
/// lasts 197.2 ms. The command's own cycle runs its first millisecond.
fn clear_then_move(m: &mut Master) {
    let i = m.command(0);
    assert_eq!(i.motor_position, 0);
    assert_eq!(i.status0, 0x4408, "Module_OK, Position_Invalid, Stopped");
    let i = m.command(0x0002);
    // 1 ms: 141 · 0.001 + 100,000 · 0.001² / 2 = 0.191 steps.
    assert_eq!(i.motor_position, 0);
    assert_eq!(
        i.status0, 0x4421,
        "Module_OK, Position_Invalid, Accelerating, Moving_CW"
    );
    // 50 ms: 141 · 0.05 + 100,000 · 0.05² / 2 = 132.05 steps.
    let i = m.run(49);
    assert_eq!(i.motor_position, 132);
    assert_eq!(i.status0, 0x4421);
    // 100 ms: 499.9006 + 0.1988 + 10,000 · 1.39 ms − 100,000 · (1.39 ms)² / 2 = 513.904 steps,
    // decelerating.
    let i = m.run(50);
    assert_eq!(i.motor_position, 514);
    assert_eq!(
        i.status0, 0x4441,
        "Module_OK, Position_Invalid, Decelerating, Moving_CW"
    );
    // 197 ms: 999.97 steps, still decelerating; 198 ms: ended on the target.
    let i = m.run(97);
    assert_eq!(i.motor_position, 1_000);
    assert_eq!(i.status0, 0x4441);
    let i = m.lrw();
    assert_eq!(i.motor_position, 1_000);
    assert_eq!(
        i.status0, 0x4488,
        "Module_OK, Position_Invalid, Move_Complete, Stopped"
    );
}

/// SMD-R6-073: the Relative bit written in Safe-Op and held while the unit goes to Op moves nothing
/// (Safe-Op: PreOp_SafeOp = 0x0020 in STATUS_word1, the outputs not acted on, so not even
/// Enable_Driver; Op: Drive_Is_Enabled 0x8000, the bit no edge) through 2,000 cycles; CMD_word0
/// back to 0 and 0x0002 again run the move to exactly 1,000 steps.
#[test]
fn smd_r6_073_a_command_bit_held_from_safe_op_into_op_is_no_edge() {
    let mut m = Master::safe_op();
    m.out = relative_1000();
    for _ in 0..20 {
        let i = m.lrw();
        assert_eq!(i.motor_position, 0);
        assert_eq!(i.status0, 0x4408, "Module_OK, Position_Invalid, Stopped");
        assert_eq!(i.status1, 0x0020 | m.heartbeat(), "PreOp_SafeOp");
    }
    m.request_op();
    for _ in 0..2_000 {
        let i = m.lrw();
        assert_eq!(i.motor_position, 0, "{} ms after power-on", m.ms());
        assert_eq!(i.status0, 0x4408);
        assert_eq!(i.status1, 0x8000 | m.heartbeat(), "Drive_Is_Enabled");
    }
    clear_then_move(&mut m);
}

/// SMD-R6-073: the first output data in Op is the edge reference, whatever Safe-Op's image held:
/// CMD_word0 0 written in Safe-Op, then the Relative bit already 1 in the first image after the
/// transition to Op, and held, is no edge either.
#[test]
fn smd_r6_073_the_first_image_in_op_is_the_edge_reference() {
    let mut m = Master::safe_op();
    m.out = Out {
        cmd0: 0,
        ..relative_1000()
    };
    m.run(5);
    m.request_op();
    m.out.cmd0 = 0x0002;
    for _ in 0..500 {
        let i = m.lrw();
        assert_eq!(i.motor_position, 0, "{} ms after power-on", m.ms());
        assert_eq!(i.status0, 0x4408);
    }
    clear_then_move(&mut m);
}

/// SMD-R6-073 without any output image before Op: the unit's cycles in Op before the master's first
/// image take nothing, and that first image (the Relative bit at 1) is the edge reference.
#[test]
fn smd_r6_073_cycles_before_the_first_image_in_op_take_no_reference() {
    let mut m = Master::safe_op();
    m.request_op();
    for _ in 0..5 {
        m.silence();
    }
    m.out = relative_1000();
    for _ in 0..500 {
        let i = m.lrw();
        assert_eq!(i.motor_position, 0, "{} ms after power-on", m.ms());
        assert_eq!(i.status0, 0x4408);
        assert_eq!(i.status1, 0x8000 | m.heartbeat());
    }
    clear_then_move(&mut m);
}

/// SMD-R6-073, SMD-R6-056: back from Op to Safe-Op and to Op again with the Relative bit still 1
/// after a completed move: no second move; the position is invalid (it was preset before); 0 and
/// 0x0002 again move 1,000 steps more.
#[test]
fn smd_r6_073_back_to_op_with_the_bit_held() {
    let mut m = Master::op();
    m.out = Out {
        cmd0: 0x0200,
        ..relative_1000()
    };
    m.out.position = 0;
    let i = m.lrw();
    assert_eq!(i.status0, 0x4008, "preset: Position_Invalid 0");
    m.out = relative_1000();
    m.command(0);
    m.command(0x0002);
    let i = m.run(300);
    assert_eq!(i.motor_position, 1_000);
    assert_eq!(i.status0, 0x4088, "Module_OK, Move_Complete, Stopped");
    common::master::request(&mut m.c, 0x04);
    assert_eq!(common::master::al(&mut m.c, 0), (0x0004, 0), "Safe-Op");
    let i = m.run(10);
    assert_eq!(i.status1 & 0x0020, 0x0020, "PreOp_SafeOp");
    m.request_op();
    for _ in 0..500 {
        let i = m.lrw();
        assert_eq!(i.motor_position, 1_000);
        // SMD-R6-056: Position_Invalid after leaving Op.
        assert_eq!(i.status0, 0x4488);
    }
    m.command(0);
    m.command(0x0002);
    let i = m.run(300);
    assert_eq!(i.motor_position, 2_000);
    assert_eq!(i.status0, 0x4488);
}
