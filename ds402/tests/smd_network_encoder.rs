//! The EtherCAT state as the SMD sees it, Mode_Select, and the absolute against the incremental
//! encoder, rule by rule (catalogue `rules/smd.md`, R1 and R6).

mod smd_rig;

use ds402::smd::config::{Configuration, EncoderKind, CFG0_USE_ENCODER};
use ds402::smd::indexer::{cmd0, cmd1, stat0, stat1, Indexer, NetworkState, Outputs};
use smd_rig::{Rig, MS};

fn rig() -> Rig {
    Rig::ready_with(CFG0_USE_ENCODER, 5_000, 20, 20)
}

/// SMD-R6-072, SMD-R6-073: PreOp_SafeOp reads 1 outside Op; commands written in Safe-Op do nothing,
/// and a bit already 1 when Op is reached is no edge — a fresh 0→1 is needed.
#[test]
fn smd_r6_072_073_commands_only_in_op() {
    let mut r = rig();
    assert_eq!(r.s1() & stat1::PREOP_SAFEOP, 0);
    r.ix.set_network_state(r.now(), NetworkState::SafeOp);
    r.cycle();
    assert_ne!(r.s1() & stat1::PREOP_SAFEOP, 0);
    r.out.position = 1_000;
    r.command(cmd0::RELATIVE_MOVE);
    r.cycle();
    assert_eq!(r.pos(), 0);
    r.ix.set_network_state(r.now(), NetworkState::Op);
    for _ in 0..50 {
        r.cycle();
    }
    assert_eq!(r.pos(), 0, "the bit was already 1 at Op");
    assert_eq!(r.s1() & stat1::PREOP_SAFEOP, 0);
    r.command(0);
    r.command(cmd0::RELATIVE_MOVE);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 1_000);
}

/// SMD-R6-073 (gap pick: the first output data in Op is the edge reference): CMD_word0 0 in
/// Safe-Op, then the Relative bit already 1 in the first data after entering Op is no edge, nor
/// after exchanges without new output data (`cycle_held`) before it; 0 then 0x0002 moves exactly
/// 1,000 steps.
#[test]
fn smd_r6_073_the_first_op_data_is_the_edge_reference() {
    let mut r = rig();
    r.ix.set_network_state(r.now(), NetworkState::SafeOp);
    r.out.position = 1_000;
    r.command(0);
    r.ix.set_network_state(r.now(), NetworkState::Op);
    for _ in 0..3 {
        let i = r.ix.cycle_held(MS);
        // Position_Invalid since Op was left (SMD-R6-056).
        assert_eq!(i.status0, 0x4408, "Module_OK, Position_Invalid, Stopped");
    }
    r.out.cmd0 = 0x0002;
    for _ in 0..300 {
        r.cycle();
        assert_eq!(r.pos(), 0);
        assert_eq!(r.s0(), 0x4408);
    }
    // Exchanges without new data keep the last: no edge either.
    for _ in 0..3 {
        assert_eq!(r.ix.cycle_held(MS).motor_position, 0);
    }
    r.command(0);
    r.command(0x0002);
    // Velocity 5,000 with 20,000 steps/s² ramps: 1,000 steps peak at √(141² + 20,000,000) = 4,474
    // steps/s after 216.7 ms, and take 433 ms.
    for _ in 0..600 {
        r.cycle();
    }
    assert_eq!(r.pos(), 1_000);
    assert_eq!(
        r.s0(),
        0x4488,
        "Module_OK, Position_Invalid, Move_Complete, Stopped"
    );
}

/// SMD-R6-073: Op told again while in Op is no entry into Op: the next data's 0→1 edge is a command
/// as always (Relative 0x0002 of 1,000 steps runs).
#[test]
fn smd_r6_073_op_again_in_op_takes_no_new_reference() {
    let mut r = rig();
    r.out.position = 1_000;
    r.command(0);
    r.ix.set_network_state(r.now(), NetworkState::Op);
    let i = r.command(0x0002);
    assert_eq!(i.status0, 0x4021, "Accelerating, Moving_CW");
    for _ in 0..600 {
        r.cycle();
    }
    assert_eq!((r.pos(), r.s0()), (1_000, 0x4088));
}

/// SMD-R6-073: an exchange on the host's clock without new output data (`exchange_held`) runs the
/// motion for the time since the last exchange with the last data in force: a Relative move of
/// 1,000 steps (Velocity 5,000, 20,000 steps/s² ramps: 141 t + 10,000 t² steps t s in) started
/// at 1 ms runs 100 ms more in one held exchange, to 141 · 0.101 + 10,000 · 0.101² = 116.251.
#[test]
fn smd_r6_073_an_exchange_without_new_data_runs_the_motion() {
    let t0 = std::time::Instant::now();
    let ms = std::time::Duration::from_millis;
    let mut r = rig();
    r.ix.start(t0, MS);
    r.out.position = 1_000;
    r.out.cmd0 = 0x0002;
    let i = r.ix.exchange(t0 + ms(1), r.out);
    assert_eq!((i.motor_position, i.status0), (0, 0x4021));
    let i = r.ix.exchange_held(t0 + ms(101));
    assert_eq!((i.motor_position, i.status0), (116, 0x4021));
    assert_eq!(
        r.ix.time(),
        ms(104),
        "the rig's three 1 ms updates, then 1 ms and 100 ms"
    );
}

/// SMD-R6-056: leaving Op and coming back makes the position invalid; a move running then stops at
/// once without Move_Complete.
#[test]
fn smd_r6_056_leaving_op() {
    let mut r = rig();
    r.out.position = 100_000;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..200 {
        r.cycle();
    }
    // Op again while in Op is no change of state: the move goes on, the position stays valid.
    let at = r.pos();
    r.ix.set_network_state(r.now(), NetworkState::Op);
    r.cycle();
    assert_eq!(
        r.s0() & (stat0::STOPPED | stat0::POSITION_INVALID),
        0,
        "Op to Op"
    );
    assert!(r.pos() > at);
    r.ix.set_network_state(r.now(), NetworkState::PreOp);
    r.cycle();
    assert_eq!(
        r.s0() & (stat0::STOPPED | stat0::MOVE_COMPLETE | stat0::POSITION_INVALID),
        stat0::STOPPED | stat0::POSITION_INVALID
    );
    r.ix.set_network_state(r.now(), NetworkState::Op);
    r.cycle();
    assert_ne!(r.s0() & stat0::POSITION_INVALID, 0);
}

/// SMD-R1-035, SMD-R6-054: a SyncManager watchdog expiry sets Input_Error and goes to Safe-Op.
#[test]
fn smd_r1_035_r6_054_sm_watchdog() {
    let mut r = rig();
    r.ix.sm_watchdog_expired(r.now());
    r.cycle();
    assert_ne!(r.s0() & stat0::INPUT_ERROR, 0);
    assert_ne!(r.s1() & stat1::PREOP_SAFEOP, 0);
    assert_eq!(r.ix.network_state(), NetworkState::SafeOp);
}

/// SMD-R6-010 (gap pick), SMD-R6-067: Mode_Select = 1 sets Mode_Flag, runs no command and stops the
/// heartbeat; Command Mode again clears it.
#[test]
fn smd_r6_010_mode_select() {
    let mut r = rig();
    assert_eq!(r.s0() & stat0::MODE_FLAG, 0);
    r.out.position = 500;
    r.command(cmd0::MODE_SELECT | cmd0::RELATIVE_MOVE);
    assert_ne!(r.s0() & stat0::MODE_FLAG, 0);
    let hb = r.s1() & stat1::HEARTBEAT;
    for _ in 0..1_500 {
        r.cycle();
        assert_eq!(
            r.s1() & stat1::HEARTBEAT,
            hb,
            "no heartbeat in configuration mode"
        );
    }
    assert_eq!(r.pos(), 0);
    r.command(0);
    assert_eq!(r.s0() & stat0::MODE_FLAG, 0);
    let mut toggled = false;
    for _ in 0..600 {
        toggled |= r.cycle().status1 & stat1::HEARTBEAT != hb;
    }
    assert!(toggled);
}

fn unit(kind: EncoderKind) -> Indexer {
    let mut ix = Indexer::new(
        kind,
        Configuration {
            cfg0: CFG0_USE_ENCODER,
            ..Configuration::default()
        },
    );
    ix.cycle(Outputs::default(), MS);
    ix
}

fn preset_encoder(ix: &mut Indexer, value: i32, save: bool) -> u16 {
    let out = Outputs {
        cmd0: cmd0::PRESET_ENCODER,
        cmd1: if save { cmd1::SAVE_TO_FLASH } else { 0 },
        position: value,
        ..Outputs::default()
    };
    let s1 = ix.cycle(out, MS).status1;
    ix.cycle(Outputs::default(), MS);
    s1
}

/// SMD-R1-014, SMD-R1-016: an incremental encoder reads 0 after a power cycle; an absolute one keeps
/// its count, turning while unpowered included; Position_Invalid is set at power-up either way, and a
/// Preset Position to the encoder restores Motor_Position without motion.
#[test]
fn smd_r1_014_016_encoders_through_a_power_cycle() {
    let mut inc = unit(EncoderKind::Incremental);
    inc.turn_shaft(std::time::Instant::now(), 5_000);
    inc.power_cycle();
    assert_eq!(inc.cycle(Outputs::default(), MS).encoder_position, 0);

    let mut abs = unit(EncoderKind::Absolute);
    abs.turn_shaft(std::time::Instant::now(), 4_096);
    abs.power_cycle_turned(2_048, 1_000.0);
    let i = abs.cycle(Outputs::default(), MS);
    assert_eq!(i.encoder_position, 6_144);
    assert_ne!(i.status0 & stat0::POSITION_INVALID, 0);
    let i = abs.cycle(
        Outputs {
            cmd0: cmd0::PRESET_POSITION,
            cmd1: cmd1::PRESET_TO_ENCODER,
            ..Outputs::default()
        },
        MS,
    );
    assert_eq!(i.motor_position, 6_000, "6,144 × 2,000 / 2,048");
    assert_eq!(i.status0 & stat0::POSITION_INVALID, 0);
}

/// SMD-R6-012, SMD-R6-013: on an absolute unit, a Preset Encoder saved to flash survives a power
/// cycle; one not saved reverts to the flash offset.
#[test]
fn smd_r6_012_013_encoder_offset_in_flash() {
    let mut abs = unit(EncoderKind::Absolute);
    let s1 = preset_encoder(&mut abs, 100_000, true);
    assert_ne!(s1 & stat1::COMMAND_ACKNOWLEDGE, 0);
    abs.turn_shaft(std::time::Instant::now(), 10);
    abs.power_cycle();
    assert_eq!(abs.cycle(Outputs::default(), MS).encoder_position, 100_010);
    preset_encoder(&mut abs, -5, false);
    assert_eq!(abs.cycle(Outputs::default(), MS).encoder_position, -5);
    abs.power_cycle();
    assert_eq!(
        abs.cycle(Outputs::default(), MS).encoder_position,
        100_010,
        "the unsaved preset is gone"
    );
}

/// SMD-R1-017, SMD-R6-066: Abs_Enc_Err (STATUS_word1 bit 12, 0x1000) after an unpowered rotation
/// above 160,000 °/s², or a battery fault; never on an incremental unit.
#[test]
fn smd_r1_017_r6_066_abs_encoder_error() {
    let mut abs = unit(EncoderKind::Absolute);
    abs.power_cycle_turned(100, 160_000.0);
    assert_eq!(abs.cycle(Outputs::default(), MS).status1 & 0x1000, 0);
    abs.power_cycle_turned(100, 160_001.0);
    assert_eq!(abs.cycle(Outputs::default(), MS).status1 & 0x1000, 0x1000);
    // The over-acceleration is gone at the next power-up.
    abs.power_cycle();
    assert_eq!(abs.cycle(Outputs::default(), MS).status1 & 0x1000, 0);
    abs.set_abs_encoder_fault(std::time::Instant::now(), true);
    assert_eq!(abs.cycle(Outputs::default(), MS).status1 & 0x1000, 0x1000);
    let mut inc = unit(EncoderKind::Incremental);
    inc.set_abs_encoder_fault(std::time::Instant::now(), true);
    assert_eq!(inc.cycle(Outputs::default(), MS).status1 & 0x1000, 0);
    inc.power_cycle_turned(0, 1e9);
    assert_eq!(inc.cycle(Outputs::default(), MS).status1 & 0x1000, 0);
}

/// SMD-R6-066 (R6 STATUS_word1 bit 12, p.80: "If this bit is set, cycle power to the unit. If the
/// bit remains set, contact AMCI"): Abs_Enc_Err stays set in every update after its battery fault
/// is gone, and through Reset Errors; a power cycle clears it once the fault is gone, and sets it
/// again at power-up while the fault is still there.
#[test]
fn smd_r6_066_abs_enc_err_stays_until_a_power_cycle() {
    let mut abs = unit(EncoderKind::Absolute);
    abs.set_abs_encoder_fault(std::time::Instant::now(), true);
    // STATUS_word1 = Abs_Enc_Err 0x1000 alone (the heartbeat's first 500 ms, driver disabled).
    assert_eq!(abs.cycle(Outputs::default(), MS).status1, 0x1000);
    abs.set_abs_encoder_fault(std::time::Instant::now(), false);
    for _ in 0..300 {
        assert_eq!(abs.cycle(Outputs::default(), MS).status1, 0x1000);
    }
    let reset = Outputs {
        cmd0: 0x0400,
        ..Outputs::default()
    };
    assert_eq!(
        abs.cycle(reset, MS).status1,
        0x3000,
        "Reset Errors: Command_Acknowledge, Abs_Enc_Err kept"
    );
    assert_eq!(abs.cycle(Outputs::default(), MS).status1, 0x1000);
    // The battery is faulty again, and still at the power cycle: set at power-up.
    abs.set_abs_encoder_fault(std::time::Instant::now(), true);
    abs.power_cycle();
    for _ in 0..300 {
        assert_eq!(abs.cycle(Outputs::default(), MS).status1, 0x1000);
    }
    // Mended while powered: the bit stays until the next power cycle, which clears it.
    abs.set_abs_encoder_fault(std::time::Instant::now(), false);
    assert_eq!(abs.cycle(Outputs::default(), MS).status1, 0x1000);
    abs.power_cycle();
    for _ in 0..300 {
        assert_eq!(abs.cycle(Outputs::default(), MS).status1, 0);
    }
}

/// SMD-R4-005: Preset Position leaves Encoder_Position alone and Preset Encoder Motor_Position.
#[test]
fn smd_r4_005_presets_are_separate() {
    let mut r = rig();
    r.out.position = 777;
    r.command(cmd0::PRESET_ENCODER);
    r.command(0);
    assert_eq!((r.pos(), r.last.encoder_position), (0, 777));
    r.out.position = -3;
    r.command(cmd0::PRESET_POSITION);
    assert_eq!((r.pos(), r.last.encoder_position), (-3, 777));
}

/// SMD-R1-021, SMD-R1-022, SMD-R5-022: with DC_Sync = 0 a move starts in the cycle its edge arrives;
/// with DC_Sync = 1 it waits for SYNC0 and starts 520 µs after it.
#[test]
fn smd_r1_021_022_r5_022_dc_sync() {
    let mut r = rig();
    r.out.position = 10_000;
    r.command(cmd0::RELATIVE_MOVE);
    assert_eq!(r.s0() & stat0::STOPPED, 0, "SM-synchronous: at once");
    r.command(0);

    let mut r = rig();
    r.ix.write_config(r.now(), 2, 0x0043); // DC_Sync, both inputs active on current
    r.command(cmd0::PRESET_POSITION);
    r.command(0);
    r.out.position = 10_000;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..20 {
        r.cycle();
        assert_ne!(r.s0() & stat0::STOPPED, 0, "waits for SYNC0");
        assert_eq!(r.pos(), 0);
    }
    r.ix.sync0_event(r.now());
    r.cycle();
    assert_ne!(r.s0() & stat0::MOVING_CW, 0);
    // 480 µs of motion at about the starting speed: 0 or 1 step so far; the profile runs from there.
    assert!(r.pos() <= 1, "{}", r.pos());
    r.until(20_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 10_000);

    // With updates every 200 µs the 520 µs are counted across them: stopped after 200 and 400 µs,
    // moving after 600.
    r.command(0);
    r.command(cmd0::RELATIVE_MOVE);
    r.ix.sync0_event(r.now());
    let step = std::time::Duration::from_micros(200);
    for k in 1..=3 {
        let s0 = r.ix.cycle(r.out, step).status0;
        let moving = s0 & stat0::STOPPED == 0;
        assert_eq!(moving, k == 3, "after {} µs", 200 * k);
    }

    // The 520 µs come off the motion's time: a move of exactly 2.000 s (20,282 steps at Velocity
    // 20,141 with Acceleration = Deceleration = 20, 1.000 s up and 1.000 s down) has run 1.99948 s
    // after 2,000 updates of 1 ms from SYNC0 and ends in update 2,001; started without DC_Sync it
    // ends in update 2,000.
    for dc_sync in [false, true] {
        let mut r = Rig::ready_with(0, 20_141, 20, 20);
        if dc_sync {
            r.ix.write_config(r.now(), 2, 0x0043);
        }
        r.out.position = 20_282;
        r.command(cmd0::RELATIVE_MOVE);
        if dc_sync {
            assert_eq!(r.pos(), 0);
            r.ix.sync0_event(r.now());
            r.cycle();
        }
        for update in 2..=1999 {
            r.cycle();
            assert_eq!(r.s0() & stat0::STOPPED, 0, "update {update}");
        }
        r.cycle();
        let stopped = r.s0() & stat0::STOPPED != 0;
        assert_eq!(stopped, !dc_sync, "update 2000, DC_Sync {dc_sync}");
        if dc_sync {
            r.cycle();
            assert_ne!(r.s0() & stat0::STOPPED, 0, "update 2001");
        }
        assert_eq!(r.pos(), 20_282);
    }
}
