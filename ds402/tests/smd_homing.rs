//! Find Home on the SMD (seed 000, Reference 4), rule by rule (catalogue `rules/smd.md`, R4), with the
//! Home sensor and the limit switches driven by the simulated motor position.

mod smd_rig;

use ds402::smd::config::{Configuration, CFG0_USE_BACKPLANE_PROXIMITY, CFG0_USE_ENCODER};
use ds402::smd::indexer::{cmd0, cmd1, stat0, stat1, Outputs};
use smd_rig::Rig;

const HOME: u16 = 6;
const CW_LIMIT: u16 = 1;
const CCW_LIMIT: u16 = 2;
const VS: f64 = 141.0;

/// Where the sensors are, as functions of the motor position: (current into IN1, into IN2).
type Sensors = fn(i64) -> (bool, bool);

fn rig(cfg0: u16) -> Rig {
    let mut r = Rig::with(Configuration {
        cfg0,
        ..Configuration::default()
    });
    r.out = Outputs {
        cmd1: cmd1::ENABLE_DRIVER,
        velocity: 5_000,
        acceleration: 20,
        deceleration: 20,
        position: 123_456, // SMD-R4-010: ignored.
        ..Outputs::default()
    };
    r.cycle();
    r
}

/// One cycle with the sensors set from the position the motor has now.
fn step(r: &mut Rig, sensors: Sensors) {
    let (a, b) = sensors(r.ix.position());
    r.ix.set_input(1, a);
    r.ix.set_input(2, b);
    r.cycle();
}

/// What a homing run did, cycle by cycle: (speed, status word 0).
fn home(r: &mut Rig, bit: u16, sensors: Sensors, max_ms: u32) -> Vec<(f64, u16)> {
    // Sensors as they are before the command.
    let (a, b) = sensors(r.ix.position());
    r.ix.set_input(1, a);
    r.ix.set_input(2, b);
    r.cycle();
    r.out.cmd0 = bit;
    let mut trace = Vec::new();
    for _ in 0..max_ms {
        step(r, sensors);
        trace.push((r.ix.speed(), r.s0()));
        if r.s0() & (stat0::AT_HOME | stat0::INPUT_ERROR) != 0 {
            break;
        }
    }
    r.out.cmd0 = 0;
    trace
}

/// The phases of a trace as runs of (direction, accelerating, decelerating, stopped) with lengths.
fn phases(trace: &[(f64, u16)]) -> Vec<(i8, bool, bool, usize)> {
    let mut out: Vec<(i8, bool, bool, usize)> = Vec::new();
    for &(v, s) in trace {
        let key = (
            if v > 0.0 {
                1
            } else if v < 0.0 {
                -1
            } else {
                0
            },
            s & stat0::ACCELERATING != 0,
            s & stat0::DECELERATING != 0,
        );
        match out.last_mut() {
            Some(last) if (last.0, last.1, last.2) == key => last.3 += 1,
            _ => out.push((key.0, key.1, key.2, 1)),
        }
    }
    out
}

/// IN1 = Home, active over steps 5,000 … 5,200.
fn home_at_5000(p: i64) -> (bool, bool) {
    ((5_000..=5_200).contains(&p), false)
}

/// SMD-R4-009, SMD-R4-011 … SMD-R4-015, SMD-R4-001 … SMD-R4-003, SMD-R4-010: the Home-input-only
/// profile of Figure R4.1 — search CW at Velocity, stop, 2 s, back off CCW past the sensor, stop,
/// 2 s, return CW at the starting speed and stop on the sensor's edge: Motor_Position and
/// Encoder_Position 0, At_Home, position valid, no Move_Complete.
#[test]
fn smd_r4_011_to_015_home_input_only_profile() {
    let mut r = rig(HOME | CFG0_USE_ENCODER);
    let trace = home(&mut r, cmd0::FIND_HOME_CW, home_at_5000, 60_000);
    let ph = phases(&trace);
    let kinds: Vec<(i8, bool, bool)> = ph.iter().map(|p| (p.0, p.1, p.2)).collect();
    assert_eq!(
        kinds,
        [
            (1, true, false),   // accelerate CW
            (1, false, false),  // search at Velocity
            (1, false, true),   // Home active: decelerate
            (0, false, false),  // 2 s pause
            (-1, true, false),  // accelerate CCW
            (-1, false, false), // run until Home inactive
            (-1, false, true),  // decelerate
            (0, false, false),  // 2 s pause
            (1, false, false),  // return at V_S
            (0, false, false),  // home
        ],
        "{ph:?}"
    );
    // The pauses: 2.0 s with Stopped and At_Home still 0.
    for k in [3, 7] {
        assert!((1_999..=2_001).contains(&ph[k].3), "pause {} ms", ph[k].3);
    }
    let search_speed = trace.iter().map(|t| t.0).fold(0.0, f64::max);
    assert_eq!(search_speed, 5_000.0);
    // The return runs at exactly V_S.
    let ret: Vec<f64> = trace.iter().filter(|t| t.0 > 0.0).map(|t| t.0).collect();
    assert_eq!(*ret.last().unwrap(), VS);
    assert_eq!(r.pos(), 0);
    assert_eq!(r.last.encoder_position, 0);
    assert_eq!(
        r.s0() & (stat0::AT_HOME | stat0::POSITION_INVALID | stat0::MOVE_COMPLETE | stat0::STOPPED),
        stat0::AT_HOME | stat0::STOPPED
    );
    // SMD-R2-022: the next command accepted clears At_Home.
    r.command(cmd0::RESET_ERRORS);
    assert_eq!(r.s0() & stat0::AT_HOME, 0);
}

/// SMD-R4-016: the Home input already active: straight away opposite to the requested direction.
#[test]
fn smd_r4_016_home_already_active() {
    let mut r = rig(HOME);
    r.out.position = 5_100;
    r.command(cmd0::PRESET_POSITION);
    r.command(0);
    let trace = home(&mut r, cmd0::FIND_HOME_CW, home_at_5000, 60_000);
    assert!(trace[0].0 < 0.0, "first motion CCW, {:?}", &trace[..3]);
    assert_ne!(r.s0() & stat0::AT_HOME, 0);
    assert_eq!(r.pos(), 0);
}

/// SMD-R4-004 gap: no input configured as Home: Command_Error, no motion.
#[test]
fn smd_r4_004_find_home_needs_a_home_input() {
    let mut r = rig(CW_LIMIT);
    r.command(cmd0::FIND_HOME_CCW);
    assert_eq!(
        r.s0() & (stat0::COMMAND_ERROR | stat0::STOPPED),
        stat0::COMMAND_ERROR | stat0::STOPPED
    );
}

/// IN1 = Home at 5,000 … 5,200 and 17,000 … 17,200 (two sensor passes before the proximity edge).
fn two_flags(p: i64) -> (bool, bool) {
    (
        (5_000..=5_200).contains(&p) || (17_000..=17_200).contains(&p),
        false,
    )
}

/// SMD-R4-017 … SMD-R4-020: with Use_Backplane_Proximity, Home edges are ignored until
/// CMD_word1 bit 11 rises; then the motor decelerates towards V_S (and carries on at V_S) and stops
/// at once on the next Home edge — no reversal, no pauses; the bit need not stay 1.
#[test]
fn smd_r4_017_to_020_backplane_proximity_profile() {
    let mut r = rig(HOME | CFG0_USE_BACKPLANE_PROXIMITY);
    r.cycle();
    r.out.cmd0 = cmd0::FIND_HOME_CW;
    let mut decel_seen = false;
    let mut min_speed = f64::MAX;
    for _ in 0..30_000 {
        step(&mut r, two_flags);
        let p = r.ix.position();
        if p > 6_000 && r.out.cmd1 & cmd1::BACKPLANE_PROXIMITY == 0 && p < 15_000 {
            // Past the first flag at full speed: it was ignored.
            assert_eq!(r.ix.speed(), 5_000.0);
            assert_eq!(r.s0() & stat0::AT_HOME, 0);
        }
        if (15_000..15_100).contains(&p) {
            r.out.cmd1 |= cmd1::BACKPLANE_PROXIMITY; // the 0→1 edge ...
        } else if p >= 15_100 {
            r.out.cmd1 &= !cmd1::BACKPLANE_PROXIMITY; // ... and back to 0 (SMD-R4-020)
        }
        decel_seen |= r.s0() & stat0::DECELERATING != 0;
        if r.ix.is_moving() {
            assert!(r.ix.speed() > 0.0, "never reverses");
            min_speed = min_speed.min(r.ix.speed());
        }
        if r.s0() & stat0::AT_HOME != 0 {
            break;
        }
    }
    assert!(decel_seen);
    assert_eq!(
        min_speed, VS,
        "decelerated to V_S and carried on there (SMD-R4-019)"
    );
    assert_ne!(r.s0() & stat0::AT_HOME, 0);
    assert_eq!(r.pos(), 0);
}

/// SMD-R4-021: proximity mode without the bit: the search runs through every Home edge.
#[test]
fn smd_r4_021_proximity_bit_never_set() {
    let mut r = rig(HOME | CFG0_USE_BACKPLANE_PROXIMITY);
    let trace = home(&mut r, cmd0::FIND_HOME_CW, two_flags, 8_000);
    assert!(r.ix.position() > 17_200, "{}", r.ix.position());
    assert!(trace.iter().all(|t| t.1 & stat0::AT_HOME == 0));
    assert_eq!(r.ix.speed(), 5_000.0);
}

/// SMD-R4-022: with CFG_Word_0 bit 11 = 0, CMD_word1 bit 11 changes nothing: the Home-input-only
/// profile runs.
#[test]
fn smd_r4_022_proximity_bit_ignored_without_the_configuration() {
    let mut r = rig(HOME);
    r.out.cmd1 |= cmd1::BACKPLANE_PROXIMITY;
    let trace = home(&mut r, cmd0::FIND_HOME_CW, home_at_5000, 60_000);
    assert!(trace.iter().any(|t| t.0 < 0.0), "it backed off");
    assert_ne!(r.s0() & stat0::AT_HOME, 0);
}

/// IN1 = Home at −3,000 … −2,800 (behind the start), IN2 = CW limit from 4,000 on.
fn overtravel(p: i64) -> (bool, bool) {
    ((-3_000..=-2_800).contains(&p), p >= 4_000)
}

/// SMD-R4-023, SMD-R4-024, SMD-R4-027: the overtravel profile: the CW limit stops the search at once
/// (no deceleration), 2 s, back off CCW past the Home sensor, stop, 2 s, return at V_S to home;
/// Input_Error never set.
#[test]
fn smd_r4_023_024_027_overtravel_profile() {
    let mut r = rig(HOME | (CW_LIMIT << 3));
    let trace = home(&mut r, cmd0::FIND_HOME_CW, overtravel, 80_000);
    let ph = phases(&trace);
    let kinds: Vec<(i8, bool, bool)> = ph.iter().map(|p| (p.0, p.1, p.2)).collect();
    assert_eq!(
        &kinds[..6],
        [
            (1, true, false),
            (1, false, false),
            (0, false, false), // the limit: stopped at once, 2 s
            (-1, true, false),
            (-1, false, false),
            (-1, false, true),
        ],
        "{ph:?}"
    );
    assert!((1_999..=2_001).contains(&ph[2].3), "pause {} ms", ph[2].3);
    assert!(trace.iter().all(|t| t.1 & stat0::INPUT_ERROR == 0));
    assert_ne!(r.s0() & stat0::AT_HOME, 0);
    assert_eq!(r.pos(), 0);
    assert_eq!(r.s0() & stat0::POSITION_INVALID, 0);
    assert_eq!(
        r.s1() & stat1::LIMIT_CONDITION,
        0,
        "cleared when the limit went inactive"
    );
}

/// SMD-R4-025: the travel limit already active: the first motion backs off at once.
#[test]
fn smd_r4_025_limit_already_active() {
    let mut r = rig(HOME | (CW_LIMIT << 3));
    r.out.position = 4_500;
    r.command(cmd0::PRESET_POSITION);
    r.command(0);
    let trace = home(&mut r, cmd0::FIND_HOME_CW, overtravel, 80_000);
    assert!(trace[0].0 < 0.0, "{:?}", &trace[..3]);
    assert_ne!(r.s0() & stat0::AT_HOME, 0);
}

/// IN1 = Home far away, IN2 = CCW limit from 2,000 on (wired the wrong way round).
fn wrong_limit(p: i64) -> (bool, bool) {
    (p >= 100_000, p >= 2_000)
}

/// SMD-R4-026: the limit of the other direction during a Find Home stops at once, Position_Invalid,
/// Input_Error, no home.
#[test]
fn smd_r4_026_opposite_limit_abandons_homing() {
    let mut r = rig(HOME | (CCW_LIMIT << 3));
    r.out.position = 0;
    r.command(cmd0::PRESET_POSITION);
    r.command(0);
    let trace = home(&mut r, cmd0::FIND_HOME_CW, wrong_limit, 10_000);
    assert!(trace.iter().all(|t| t.1 & stat0::DECELERATING == 0));
    assert_eq!(
        r.s0() & (stat0::STOPPED | stat0::POSITION_INVALID | stat0::INPUT_ERROR | stat0::AT_HOME),
        stat0::STOPPED | stat0::POSITION_INVALID | stat0::INPUT_ERROR
    );
    assert!(r.pos() >= 2_000 && r.pos() < 2_100, "{}", r.pos());
}

/// SMD-R2-036: Hold during a Find Home decelerates to a stop; not held, homing abandoned, a later
/// Resume is a Command_Error.
#[test]
fn smd_r2_036_hold_abandons_homing() {
    let mut r = rig(HOME);
    r.command(cmd0::FIND_HOME_CW);
    for _ in 0..500 {
        step(&mut r, home_at_5000);
    }
    r.out.cmd0 = cmd0::HOLD_MOVE;
    step(&mut r, home_at_5000);
    assert_ne!(r.s0() & stat0::DECELERATING, 0);
    while r.ix.is_moving() {
        step(&mut r, home_at_5000);
    }
    assert_eq!(
        r.s0() & (stat0::IN_HOLD_STATE | stat0::AT_HOME | stat0::MOVE_COMPLETE),
        0
    );
    let at = r.pos();
    for _ in 0..3_000 {
        step(&mut r, home_at_5000);
    }
    assert_eq!(r.pos(), at, "no more homing motion");
    r.command(0);
    r.command(cmd0::RESUME_MOVE);
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0);
}
