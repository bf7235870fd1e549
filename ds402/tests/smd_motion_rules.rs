//! More rules of the SMD's motion and status (catalogue `rules/smd.md`, R1, R2, R4, R6, T3), each
//! observed as a master sees it.

mod smd_rig;

use ds402::smd::config::{Configuration, CFG0_USE_ENCODER};
use ds402::smd::indexer::{cmd0, cmd1, stat0, stat1};
use smd_rig::Rig;

fn rig(cfg0: u16) -> Rig {
    Rig::ready_with(cfg0, 10_000, 20, 20)
}

/// Speed and status per cycle of a Relative move of `distance` from the present data.
fn trace(r: &mut Rig, distance: i32) -> Vec<(f64, u16, i32)> {
    r.out.position = distance;
    r.command(cmd0::RELATIVE_MOVE);
    let mut t = vec![(r.ix.speed(), r.s0(), r.pos())];
    while r.s0() & stat0::STOPPED == 0 {
        r.cycle();
        t.push((r.ix.speed(), r.s0(), r.pos()));
    }
    r.command(0);
    t
}

/// SMD-R2-002, SMD-R2-005: at cruise the position changes by Velocity steps per second, increasing
/// clockwise.
#[test]
fn smd_r2_002_005_cruise_speed_and_direction() {
    let mut r = rig(0);
    let t = trace(&mut r, 100_000);
    let cruise: Vec<&(f64, u16, i32)> = t
        .iter()
        .filter(|x| x.1 & (stat0::ACCELERATING | stat0::DECELERATING | stat0::STOPPED) == 0)
        .collect();
    assert!(cruise.len() > 1_000);
    let (a, b) = (cruise[0], cruise[1_000]);
    assert_eq!(b.2 - a.2, 10_000, "1,000 ms at 10,000 steps/s");
    assert!(t.iter().all(|x| x.1 & stat0::MOVING_CCW == 0));
    let t = trace(&mut r, -5_000);
    assert!(t[..t.len() - 1]
        .iter()
        .all(|x| x.1 & stat0::MOVING_CCW != 0));
    assert!(t.windows(2).all(|w| w[1].2 <= w[0].2), "CCW decreases");
}

/// SMD-R2-003, SMD-R2-024: with Jerk 0 and Acceleration 20 the speed rises 20 steps/s every
/// millisecond, a straight line.
#[test]
fn smd_r2_003_024_linear_acceleration() {
    let mut r = rig(0);
    let t = trace(&mut r, 100_000);
    let acc: Vec<f64> = t
        .iter()
        .filter(|x| x.1 & stat0::ACCELERATING != 0)
        .map(|x| x.0)
        .collect();
    // From V_S = 141 steps/s in steps of 20: 161 in the first accelerating cycle, and the last
    // below 10,000 is 141 + 20 × 492 = 9,981, so 492 cycles (the next one is at 10,000, cruise).
    assert_eq!(acc.len(), 492);
    assert!((acc[0] - 161.0).abs() < 1e-6, "{}", acc[0]);
    assert!((acc[491] - 9_981.0).abs() < 1e-6, "{}", acc[491]);
    for w in acc.windows(2) {
        assert!((w[1] - w[0] - 20.0).abs() < 1e-6, "{} → {}", w[0], w[1]);
    }
}

/// SMD-R2-006: a move starts at the starting speed and ends from it: the first cycle's speed and the
/// last moving cycle's are at V_S (within one cycle's acceleration).
#[test]
fn smd_r2_006_starting_speed_at_both_ends() {
    let mut r = rig(0);
    let t = trace(&mut r, 50_000);
    assert!((141.0..=161.0).contains(&t[0].0), "first {}", t[0].0);
    let last = t[t.len() - 2].0;
    assert!((141.0..=161.0).contains(&last), "last {last}");
}

/// SMD-R2-017, SMD-R2-050: in a triangular move Accelerating goes straight to Decelerating, with no
/// cruise cycle; Accelerating is 1 only while the speed rises.
#[test]
fn smd_r2_017_050_triangular_move_bits() {
    let mut r = rig(0);
    // D_A + D_D at 10,000 steps/s is 4,999.5 steps: 4,000 is triangular.
    let t = trace(&mut r, 4_000);
    let mut phases = Vec::new();
    for x in &t {
        let p = x.1 & (stat0::ACCELERATING | stat0::DECELERATING | stat0::STOPPED);
        if phases.last() != Some(&p) {
            phases.push(p);
        }
    }
    assert_eq!(
        phases,
        [stat0::ACCELERATING, stat0::DECELERATING, stat0::STOPPED]
    );
    for w in t.windows(2) {
        if w[1].1 & stat0::ACCELERATING != 0 {
            assert!(w[1].0 > w[0].0 || w[0].1 & stat0::STOPPED != 0);
        }
    }
    let peak = t.iter().map(|x| x.0).fold(0.0, f64::max);
    assert!(peak < 10_000.0, "{peak}");
}

/// SMD-R2-025: with an S-curve the acceleration rises from 0 and returns to 0 within the phase (no
/// step in acceleration at either end).
#[test]
fn smd_r2_025_s_curve_has_no_acceleration_step() {
    let mut r = rig(0);
    r.out.jerk = 100;
    let t = trace(&mut r, 200_000);
    let acc: Vec<f64> = t
        .iter()
        .filter(|x| x.1 & stat0::ACCELERATING != 0)
        .map(|x| x.0)
        .collect();
    let first = acc[1] - acc[0];
    let mid = acc[acc.len() / 2] - acc[acc.len() / 2 - 1];
    let end = acc[acc.len() - 1] - acc[acc.len() - 2];
    assert!(
        first < mid / 10.0 && end < mid / 10.0,
        "{first} {mid} {end}"
    );
}

/// SMD-R2-026, SMD-R2-027, SMD-R2-028: in motion, a triangular S-curve with J = 200/t takes twice the
/// linear time, a trapezoidal one with J = 400/t 4/3 of it, and a larger J a shorter phase.
#[test]
fn smd_r2_026_027_028_s_curve_phase_times() {
    let accel_ms = |jerk: u16| {
        let mut r = rig(0);
        r.out.acceleration = 10;
        r.out.velocity = 20_141;
        r.out.jerk = jerk;
        let t = trace(&mut r, 1_000_000);
        t.iter().filter(|x| x.1 & stat0::ACCELERATING != 0).count()
    };
    // Linear: 20,000 steps/s at 10,000 steps/s² = 2.0 s.
    let linear = accel_ms(0);
    assert!((1_999..=2_001).contains(&linear), "{linear}");
    let tri = accel_ms(50); // 200 / 4.0 s
    assert!((3_999..=4_001).contains(&tri), "{tri}");
    let trap = accel_ms(150); // 400 / 2.667 s
    assert!((2_665..=2_668).contains(&trap), "{trap}");
    assert!(accel_ms(1_000) < trap);
}

/// The first acceleration of the motion that starts with the command `c` (or, with `c` = 0, in the
/// next moving cycle): the speed 1 s into it and the number of 1 ms cycles with Accelerating = 1.
fn first_ramp(r: &mut Rig, c: u16) -> (f64, usize) {
    if c == 0 {
        r.until(200_000, |i| i.status0 & stat0::STOPPED == 0);
    } else {
        r.command(c);
    }
    let mut at_1s = f64::NAN;
    let mut n = 0;
    for k in 1..=20_000 {
        if k > 1 {
            r.cycle();
        }
        if k == 1_000 {
            at_1s = r.ix.speed().abs();
        }
        if r.s0() & stat0::ACCELERATING == 0 {
            break;
        }
        n += 1;
    }
    (at_1s, n)
}

/// Asserts a first acceleration from V_S = 141 to 20,141 steps/s at Acceleration 10 (10,000 steps/s²)
/// with the Jerk word `jerk` (0, 50 or 150): 1 s into it the speed is 141 + 10,000 = 10,141 (linear),
/// 141 + 5,000/2 = 2,641 (Jerk 50: j = 5,000 steps/s³, triangular, 4 s) or 141 + 3,333.3 + 3,333.3 =
/// 6,807.7 (Jerk 150: j = 15,000 steps/s³, trapezoidal with t₁ = 2/3 s, 2.667 s).
fn assert_ramp((at_1s, n): (f64, usize), jerk: u16, what: &str) {
    let (speed, ms) = match jerk {
        0 => (10_141.0, 1_999..=2_001),
        50 => (2_641.0, 3_999..=4_001),
        150 => (141.0 + 20_000.0 / 3.0, 2_666..=2_668),
        _ => unreachable!(),
    };
    assert!(
        (at_1s - speed).abs() < 1e-6,
        "{what}: {at_1s} steps/s after 1 s, Jerk {jerk}"
    );
    assert!(ms.contains(&n), "{what}: {n} ms accelerating, Jerk {jerk}");
}

/// SMD-R2-023: each Absolute, Relative, Resume, Find Home and Jog command takes its acceleration type
/// from its own Jerk word (0 linear, 50 triangular S-curve, 150 trapezoidal S-curve), whatever the
/// previous command used, and in.Jerk echoes it. In a Dwell or Blend move each segment ramps with its
/// own programmed Jerk (a Dwell's Jerk word is the dwell time, not a jerk). Gap pick: a Registration
/// move, whose Jerk word is the MRMD's high word, accelerates linearly and in.Jerk reads 0.
#[test]
fn smd_r2_023_each_move_its_own_acceleration_type() {
    let mut r = Rig::ready_with(6, 20_141, 10, 10); // IN1 = Home (never reached)
    r.out.position = 1_000_000;
    // Absolute with Jerk 0, held, resumed with Jerk 50.
    r.out.jerk = 0;
    assert_ramp(first_ramp(&mut r, cmd0::ABSOLUTE_MOVE), 0, "Absolute");
    assert_eq!(r.last.jerk, 0);
    r.command(cmd0::HOLD_MOVE);
    r.until(10_000, |i| i.status0 & stat0::IN_HOLD_STATE != 0);
    r.command(0);
    r.out.jerk = 50;
    assert_ramp(first_ramp(&mut r, cmd0::RESUME_MOVE), 50, "Resume");
    assert_eq!(r.last.jerk, 50);
    r.command(cmd0::IMMEDIATE_STOP);
    r.command(0);
    // Relative with Jerk 150, Jog with Jerk 50, Find Home with Jerk 150.
    for (command, jerk, what) in [
        (cmd0::RELATIVE_MOVE, 150, "Relative"),
        (cmd0::JOG_CW, 50, "Jog"),
        (cmd0::FIND_HOME_CW, 150, "Find Home"),
    ] {
        r.out.jerk = jerk;
        assert_ramp(first_ramp(&mut r, command), jerk, what);
        assert_eq!(r.last.jerk, jerk, "{what}");
        r.command(cmd0::IMMEDIATE_STOP);
        r.command(0);
    }
    // Registration: Jerk word 1 is the MRMD's high word (MRMD 65,536 steps), the ramp is linear.
    r.out.cmd1 |= cmd1::REGISTRATION_MOVE;
    r.out.jerk = 1;
    r.out.motor_current = 0;
    r.out.position = 1_000;
    assert_ramp(first_ramp(&mut r, cmd0::JOG_CW), 0, "Registration");
    assert_eq!(r.last.jerk, 0);
    assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0);
    r.command(cmd0::IMMEDIATE_STOP);
    r.command(0);
    r.out.cmd1 &= !cmd1::REGISTRATION_MOVE;

    // Assembled segments: (position, velocity, jerk), Acceleration and Deceleration 10.
    let program = |r: &mut Rig, segs: &[(i32, u32, u16)]| {
        r.command(cmd0::PROGRAM_ASSEMBLED);
        for &(position, velocity, jerk) in segs {
            r.out.position = position;
            r.out.velocity = velocity;
            r.out.jerk = jerk;
            r.command(cmd0::PROGRAM_ASSEMBLED | cmd0::READ_ASSEMBLED_DATA);
            r.command(cmd0::PROGRAM_ASSEMBLED);
        }
        r.command(0);
        assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0);
    };
    // Dwell (Jerk word 100 = 100 ms dwell): segment 1 linear, segment 2 with Jerk 50.
    program(&mut r, &[(100_000, 20_141, 0), (100_000, 20_141, 50)]);
    r.out.cmd1 |= cmd1::DWELL;
    r.out.jerk = 100;
    assert_ramp(first_ramp(&mut r, cmd0::RUN_ASSEMBLED_MOVE), 0, "Dwell 1");
    r.until(200_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_ramp(first_ramp(&mut r, 0), 50, "Dwell 2");
    r.until(200_000, |i| i.status0 & stat0::MOVE_COMPLETE != 0);
    r.command(0);
    r.out.cmd1 &= !cmd1::DWELL;
    // Blend: segment 1 linear to 20,141; segment 2 ramps on to 40,141 with Jerk 50 (4 s; 1 s in,
    // 20,141 + 2,500 = 22,641 steps/s).
    program(&mut r, &[(50_000, 20_141, 0), (300_000, 40_141, 50)]);
    r.out.jerk = 0;
    assert_ramp(first_ramp(&mut r, cmd0::RUN_ASSEMBLED_MOVE), 0, "Blend 1");
    // The ramp begins at the end of the cycle that reaches segment 2 (Accelerating from there on).
    r.until(200_000, |i| i.status0 & stat0::ACCELERATING != 0);
    let mut n = 0;
    for k in 1..=20_000 {
        r.cycle();
        if k == 1_000 {
            assert!((r.ix.speed() - 22_641.0).abs() < 1e-6, "{}", r.ix.speed());
        }
        if r.s0() & stat0::ACCELERATING == 0 {
            break;
        }
        n += 1;
    }
    assert!((3_999..=4_001).contains(&n), "Blend 2: {n} ms accelerating");
}

/// SMD-R2-047: Home input edges during a Relative move change nothing.
#[test]
fn smd_r2_047_home_input_only_for_find_home() {
    let mut r = rig(6); // IN1 = Home
    r.out.position = 5_000;
    r.command(cmd0::RELATIVE_MOVE);
    for k in 0..3_000 {
        r.ix.set_input(r.now(), 1, k % 100 < 50);
        r.cycle();
    }
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 5_000);
    assert_eq!(r.s0() & stat0::AT_HOME, 0);
}

/// SMD-R2-097: an indexed Registration move: the Start Indexed input starts it, the Stop input ends it.
#[test]
fn smd_r2_097_indexed_registration() {
    let mut r = rig(3 | (4 << 3)); // IN1 Start Indexed, IN2 Stop Jog/Registration
    r.out.cmd1 |= cmd1::INDEXED | cmd1::REGISTRATION_MOVE;
    r.out.position = 2_000;
    r.command(cmd0::JOG_CW);
    for _ in 0..50 {
        r.cycle();
    }
    assert_eq!(r.pos(), 0);
    r.ix.set_input(r.now(), 1, true);
    r.cycle();
    for _ in 0..1_000 {
        r.cycle();
    }
    let before = r.pos();
    r.ix.set_input(r.now(), 2, true);
    r.cycle();
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), before + 2_000);
    assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
}

/// SMD-R4-006: 4,096 counts at 4,096 counts and 2,000 steps per turn preset Motor_Position to 2,000.
#[test]
fn smd_r4_006_preset_to_encoder_example() {
    let mut r = Rig::with(Configuration {
        cfg0: CFG0_USE_ENCODER,
        encoder_resolution: 4_096,
        ..Configuration::default()
    });
    r.out.position = 4_096;
    r.command(cmd0::PRESET_ENCODER);
    r.command(0);
    r.out.cmd1 = cmd1::PRESET_TO_ENCODER;
    r.command(cmd0::PRESET_POSITION);
    assert_eq!(r.pos(), 2_000);
}

/// SMD-R1-013, SMD-R6-046: with the motor supply off the shaft turned by hand still counts, and
/// Preset to Encoder gives the motor position back; Motor_Position is the commanded count.
#[test]
fn smd_r1_013_r6_046_encoder_without_motor_power() {
    let mut r = rig(CFG0_USE_ENCODER);
    r.ix.set_shaft_blocked(r.now(), true);
    r.out.position = 1_000;
    r.command(cmd0::RELATIVE_MOVE);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(
        (r.pos(), r.last.encoder_position),
        (1_000, 0),
        "commanded, not measured"
    );
    r.command(0);
    r.ix.turn_shaft(r.now(), 1_024);
    r.out.cmd1 |= cmd1::PRESET_TO_ENCODER;
    r.command(cmd0::PRESET_POSITION);
    assert_eq!(r.pos(), 1_000, "1,024 counts × 2,000 / 2,048");
}

/// SMD-R1-015: Encoder_Position wraps in two's complement.
#[test]
fn smd_r1_015_encoder_wraps() {
    let mut r = rig(CFG0_USE_ENCODER);
    r.out.position = i32::MAX;
    r.command(cmd0::PRESET_ENCODER);
    r.command(0);
    r.ix.turn_shaft(r.now(), 1);
    r.cycle();
    assert_eq!(r.last.encoder_position, i32::MIN);
}

/// SMD-R4-028: with no limits, a Find Home that never meets the Home input runs on at Velocity.
#[test]
fn smd_r4_028_find_home_without_limits() {
    let mut r = rig(6);
    r.command(cmd0::FIND_HOME_CW);
    for _ in 0..5_000 {
        r.cycle();
    }
    assert_eq!(r.ix.speed(), 10_000.0);
    assert_eq!(r.s0() & stat0::AT_HOME, 0);
}

/// SMD-R6-007: unused words of a command (Hold, Reset Errors, Preset Position but Position) may hold
/// anything.
#[test]
fn smd_r6_007_unused_words_are_ignored() {
    let mut r = rig(0);
    r.out.velocity = 0;
    r.out.acceleration = 0;
    r.out.deceleration = 9_999;
    r.out.jerk = 65_535;
    r.out.motor_current = 999;
    for c in [cmd0::HOLD_MOVE, cmd0::RESET_ERRORS, cmd0::PRESET_POSITION] {
        r.command(c);
        r.command(0);
    }
    assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0);
}

/// SMD-R6-008: a rejected command during a jog leaves the jog running.
#[test]
fn smd_r6_008_rejected_command_leaves_the_move() {
    let mut r = rig(0);
    r.command(cmd0::JOG_CW);
    for _ in 0..1_000 {
        r.cycle();
    }
    r.out.position = 9_000_000;
    r.out.cmd0 = cmd0::JOG_CW | cmd0::ABSOLUTE_MOVE;
    r.cycle();
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0);
    r.cycle();
    assert_eq!(r.ix.speed(), 10_000.0);
}

/// SMD-R6-025: Preset_to_Encoder changes nothing but Preset Position.
#[test]
fn smd_r6_025_preset_to_encoder_only_for_presets() {
    let mut r = rig(CFG0_USE_ENCODER);
    r.out.cmd1 |= cmd1::PRESET_TO_ENCODER;
    trace(&mut r, 3_000);
    assert_eq!(r.pos(), 3_000);
}

/// SMD-R6-029: the same Jog bit runs a jog (CMD_word1 bit 7 = 0) or a registration move (1).
#[test]
fn smd_r6_029_jog_or_registration() {
    let mut r = rig(0);
    r.out.cmd1 |= cmd1::REGISTRATION_MOVE;
    r.out.position = 300;
    r.command(cmd0::JOG_CW);
    for _ in 0..500 {
        r.cycle();
    }
    let at = r.pos();
    r.command(0);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(
        r.pos(),
        at + 300,
        "registration: run-out of the Stopping Distance"
    );
}

/// SMD-R6-033 gap pick: reserved CMD_word1 bits are ignored.
#[test]
fn smd_r6_033_reserved_cmd1_bits() {
    let mut r = rig(0);
    r.out.cmd1 |= (1 << 14) | (1 << 12) | (1 << 10) | (1 << 6) | (1 << 3) | (1 << 2) | 1;
    trace(&mut r, 1_000);
    assert_eq!(r.pos(), 1_000);
    assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0);
}

/// SMD-R6-057, SMD-R6-058: Move_Complete stays set with CMD_word0 = 0 and clears when the next move
/// is accepted; homing does not set it.
#[test]
fn smd_r6_057_058_move_complete() {
    let mut r = rig(0);
    trace(&mut r, 500);
    for _ in 0..2_000 {
        r.cycle();
    }
    assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
    r.out.position = 500;
    r.command(cmd0::RELATIVE_MOVE);
    assert_eq!(r.s0() & stat0::MOVE_COMPLETE, 0);
}

/// SMD-R6-057 (R6 STATUS_word0 bit 7, p.79: Move_Complete "is reset to 0 when the next move
/// command is written"): a move command that is written and refused clears it as an accepted one
/// does. After a Relative move STAT0 is Module_OK | Move_Complete | Stopped = 0x4088; then:
/// - a Relative move below the Starting Speed (SMD-R6-035): Command_Error, no Move_Complete,
///   0x5008;
/// - after Reset Errors and a second move, a Relative move written with Hold Move at 1
///   (SMD-R1-024): 0x5008 again;
/// - Hold Move alone, which is no move command, leaves Move_Complete: 0x4088;
/// - a Jog below the Starting Speed sets Move_Complete with Command_Error (SMD-R6-040): 0x5088.
#[test]
fn smd_r6_057_a_refused_move_clears_move_complete_too() {
    let mut r = rig(0);
    let settle = |r: &mut Rig| {
        for _ in 0..10 {
            r.cycle();
        }
    };
    let complete = |r: &mut Rig| {
        trace(r, 500);
        settle(r);
        assert_eq!(r.s0(), 0x4088, "after a completed move");
    };
    complete(&mut r);
    r.out.velocity = 100; // below the Starting Speed 141
    r.command(cmd0::RELATIVE_MOVE);
    assert_eq!(r.s0(), 0x5008, "refused for its speed");
    r.command(0);
    assert_eq!(r.s0(), 0x5008, "and it stays so with CMD_word0 = 0");
    r.out.velocity = 10_000;
    r.command(cmd0::RESET_ERRORS);
    r.command(0);
    complete(&mut r);
    // Hold Move at 1, then Relative Move rising beside it.
    r.command(cmd0::HOLD_MOVE);
    assert_eq!(r.s0(), 0x4088, "Hold Move is no move command");
    r.command(cmd0::HOLD_MOVE | cmd0::RELATIVE_MOVE);
    assert_eq!(r.s0(), 0x5008, "refused: two command bits");
    r.command(0);
    r.command(cmd0::RESET_ERRORS);
    r.command(0);
    complete(&mut r);
    r.out.velocity = 100;
    r.command(cmd0::JOG_CW);
    assert_eq!(
        r.s0(),
        0x5088,
        "a Jog with a bad speed sets it with Command_Error"
    );
    assert_eq!(r.pos(), 1_500, "no move was made");
}

/// R6 STATUS_word1 bit 7 (p.81): "If the driver section … is enabled, this bit will be a 1 during a
/// Overtemperature Fault". At 99 °C with Enable_Driver = 0, STATUS_word1 (the Heartbeat_Bit left
/// out) is Temperature_Above_90C alone, 0x0010; with the driver enabled it is Drive_Is_Enabled |
/// Driver_Fault | Temperature_Above_90C, 0x8090 (SMD-R6-062: the driver stays enabled); disabled
/// again, 0x0010. An STO fault sets the bit with the driver disabled too (SMD-R1-002): 0x0080.
#[test]
fn driver_fault_for_over_temperature_only_with_the_driver_enabled() {
    let mut r = rig(0);
    let s1 = |r: &mut Rig| {
        r.cycle();
        r.s1() & !stat1::HEARTBEAT
    };
    r.out.cmd1 &= !cmd1::ENABLE_DRIVER;
    assert_eq!(s1(&mut r), 0x0000);
    r.ix.set_temperature(r.now(), 99.0);
    assert_eq!(s1(&mut r), 0x0010, "disabled: no Driver_Fault");
    r.out.cmd1 |= cmd1::ENABLE_DRIVER;
    assert_eq!(s1(&mut r), 0x8090, "enabled: Driver_Fault");
    r.out.cmd1 &= !cmd1::ENABLE_DRIVER;
    assert_eq!(s1(&mut r), 0x0010, "disabled again");
    r.ix.set_temperature(r.now(), 25.0);
    assert_eq!(s1(&mut r), 0x0000);
    r.ix.set_sto(r.now(), false, true);
    assert_eq!(
        s1(&mut r),
        0x0080,
        "STO: Driver_Fault with the driver disabled"
    );
}

/// SMD-R6-069 (R6 STATUS_word1 bit 9, p.80: Invalid_Jog_Change "will reset when valid jog data is
/// sent from the host controller"): Acceleration 0 written during a Jog sets the bit; it stays set
/// in every cycle of the jog's stop and after it while Acceleration is still 0, since invalid jog
/// data is still being sent; Acceleration 20 written with no jog running clears it.
#[test]
fn smd_r6_069_invalid_jog_change_clears_when_valid_data_is_sent() {
    let mut r = rig(0);
    r.command(cmd0::JOG_CW);
    r.until(2_000, |i| {
        i.status0 & (stat0::ACCELERATING | stat0::MOVING_CW) == stat0::MOVING_CW
    });
    r.out.acceleration = 0;
    r.cycle();
    assert_eq!(
        r.s1() & stat1::INVALID_JOG_CHANGE,
        stat1::INVALID_JOG_CHANGE
    );
    r.out.cmd0 = 0;
    let mut cycles = 0;
    while r.cycle().status0 & stat0::STOPPED == 0 {
        assert_eq!(
            r.s1() & stat1::INVALID_JOG_CHANGE,
            stat1::INVALID_JOG_CHANGE,
            "stopping"
        );
        cycles += 1;
    }
    assert!(
        cycles > 100,
        "the jog's stop from 10,000 steps/s takes 0.5 s: {cycles} cycles"
    );
    for _ in 0..100 {
        assert_eq!(
            r.cycle().status1 & stat1::INVALID_JOG_CHANGE,
            stat1::INVALID_JOG_CHANGE,
            "stopped, Acceleration still 0"
        );
    }
    r.out.acceleration = 20;
    assert_eq!(
        r.cycle().status1 & stat1::INVALID_JOG_CHANGE,
        0,
        "valid data sent"
    );
}

/// R2 Jog Moves (p.34: a Jog Move's speed and ramps "can be changed while the move is in
/// progress") and Registration Moves (p.36: the Programmed Speed and Deceleration "set with the
/// command"): a Registration move at 10,000 steps/s keeps that speed when Velocity 5,000 is
/// written — 1,000 steps in each 100 ms at cruise (SMD-R2-002) — and an invalid Acceleration
/// written during it sets no Invalid_Jog_Change; ended by CMD_word0 = 0 it runs out exactly its
/// Stopping Distance of 2,000 steps (SMD-R2-062).
#[test]
fn a_registration_move_keeps_the_values_of_its_command() {
    let mut r = rig(0);
    r.out.cmd1 |= cmd1::REGISTRATION_MOVE;
    r.out.position = 2_000;
    r.command(cmd0::JOG_CW);
    r.until(2_000, |i| {
        i.status0 & (stat0::ACCELERATING | stat0::MOVING_CW) == stat0::MOVING_CW
    });
    r.out.velocity = 5_000;
    r.out.acceleration = 0;
    for _ in 0..3 {
        let from = r.pos();
        for _ in 0..100 {
            assert_eq!(r.cycle().status1 & stat1::INVALID_JOG_CHANGE, 0);
            assert_eq!(
                r.s0() & (stat0::ACCELERATING | stat0::DECELERATING),
                0,
                "cruise"
            );
        }
        assert_eq!(r.pos() - from, 1_000, "10,000 steps/s for 100 ms");
    }
    // The condition is seen at the start of the cycle CMD_word0 = 0 arrives in: the run-out
    // counts from the position reported before it.
    let trigger = r.pos();
    r.out.cmd0 = 0;
    r.until(5_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), trigger + 2_000, "exactly the Stopping Distance");
}

/// SMD-R6-070: reserved STATUS_word1 bits 8, 6, 3, 2 always read 0.
#[test]
fn smd_r6_070_reserved_status_bits() {
    let mut r = rig(CFG0_USE_ENCODER);
    r.ix.set_temperature(r.now(), 99.0);
    r.ix.set_input(r.now(), 1, true);
    r.ix.set_input(r.now(), 2, true);
    for _ in 0..1_200 {
        assert_eq!(r.cycle().status1 & 0x014C, 0);
    }
    assert_ne!(r.s1() & stat1::DRIVER_FAULT, 0);
}

/// SMD-T3-004, SMD-T3-005, SMD-T3-006: DC_Sync is CFG_Word_1 bit 6; 64–67 are valid; with DC_Sync
/// and no SYNC0 a move never starts.
#[test]
fn smd_t3_004_005_006_dc_sync_values() {
    for cfg1 in [64u32, 65, 66, 67] {
        let mut r = rig(0);
        r.ix.write_config(r.now(), 2, cfg1);
        r.cycle();
        assert_eq!(r.s0() & stat0::CONFIGURATION_ERROR, 0, "{cfg1}");
    }
    let mut r = rig(0);
    r.ix.write_config(r.now(), 2, 0x0043);
    r.out.position = 100;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..3_000 {
        r.cycle();
    }
    assert_ne!(r.s0() & stat0::STOPPED, 0);
    assert_eq!(r.pos(), 0);
}

/// SMD-T2-006: online configuration writes are lost at power-off.
#[test]
fn smd_t2_006_online_configuration_is_temporary() {
    let mut r = rig(0);
    r.ix.write_config(r.now(), 3, 500);
    assert_eq!(r.ix.config().starting_speed, 500);
    r.ix.power_cycle();
    assert_eq!(r.ix.config().starting_speed, 141);
}
