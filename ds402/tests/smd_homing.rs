//! Find Home on the SMD (seed 000, Reference 4), rule by rule (catalogue `rules/smd.md`, R4), with the
//! Home sensor and the limit switches driven by the simulated motor position.

mod smd_rig;

use ds402::smd::config::{Configuration, CFG0_USE_BACKPLANE_PROXIMITY, CFG0_USE_ENCODER};
use ds402::smd::indexer::{cmd0, cmd1, stat0, stat1, Inputs, Outputs};
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
    r.ix.set_input(r.now(), 1, a);
    r.ix.set_input(r.now(), 2, b);
    r.cycle();
}

/// A homing run as the master sees it: the sensors set as they are, one cycle, then CMD0 = `bit` for
/// exactly `ms` cycles, each cycle's input words recorded. It never stops early, so what a model does
/// after home or after an error is in the trace. Once At_Home is reported the position has been set
/// to 0, so from then on the sensors keep the levels they had (the shaft has not moved, or the trace
/// shows it has).
fn home(r: &mut Rig, bit: u16, sensors: Sensors, ms: u32) -> Vec<Inputs> {
    let (a, b) = sensors(r.ix.position());
    r.ix.set_input(r.now(), 1, a);
    r.ix.set_input(r.now(), 2, b);
    r.cycle();
    r.out.cmd0 = bit;
    let mut trace = Vec::new();
    for _ in 0..ms {
        if r.s0() & stat0::AT_HOME == 0 {
            step(r, sensors);
        } else {
            r.cycle();
        }
        trace.push(r.last);
    }
    r.out.cmd0 = 0;
    trace
}

/// The motion bits of STATUS_word0 that make a phase of a profile.
const PHASE_BITS: u16 = stat0::MOVING_CW
    | stat0::MOVING_CCW
    | stat0::ACCELERATING
    | stat0::DECELERATING
    | stat0::STOPPED
    | stat0::AT_HOME;

const CW_ACC: u16 = stat0::MOVING_CW | stat0::ACCELERATING;
const CW_RUN: u16 = stat0::MOVING_CW;
const CW_DEC: u16 = stat0::MOVING_CW | stat0::DECELERATING;
const CCW_ACC: u16 = stat0::MOVING_CCW | stat0::ACCELERATING;
const CCW_RUN: u16 = stat0::MOVING_CCW;
const CCW_DEC: u16 = stat0::MOVING_CCW | stat0::DECELERATING;
const PAUSE: u16 = stat0::STOPPED;
const HOMED: u16 = stat0::STOPPED | stat0::AT_HOME;

/// A run of cycles with the same motion bits: the bits, the index of its first cycle, its length.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Phase {
    bits: u16,
    first: usize,
    len: usize,
}

/// The phases of a trace, from STATUS_word0 alone.
fn phases(trace: &[Inputs]) -> Vec<Phase> {
    let mut out: Vec<Phase> = Vec::new();
    for (k, i) in trace.iter().enumerate() {
        let bits = i.status0 & PHASE_BITS;
        match out.last_mut() {
            Some(last) if last.bits == bits => last.len += 1,
            _ => out.push(Phase {
                bits,
                first: k,
                len: 1,
            }),
        }
    }
    out
}

/// The motion bits of each phase.
fn kinds(ph: &[Phase]) -> Vec<u16> {
    ph.iter().map(|p| p.bits).collect()
}

/// Motor_Position at the end of each cycle of a phase, with the position before its first cycle.
fn positions(trace: &[Inputs], p: Phase) -> Vec<i32> {
    let from = p
        .first
        .checked_sub(1)
        .map_or(trace[0].motor_position, |k| trace[k].motor_position);
    std::iter::once(from)
        .chain(
            trace[p.first..p.first + p.len]
                .iter()
                .map(|i| i.motor_position),
        )
        .collect()
}

/// Asserts that a phase runs at `per_ms` steps each cycle (a speed of `per_ms` × 1000 steps/s).
#[track_caller]
fn assert_cruise(trace: &[Inputs], p: Phase, per_ms: i32) {
    let pos = positions(trace, p);
    assert!(pos.len() >= 2, "{p:?}");
    for w in pos.windows(2) {
        assert_eq!(w[1] - w[0], per_ms, "{p:?}: {pos:?}");
    }
}

/// Asserts that a phase runs at V_S = 141 steps/s: `steps` in `p.len` ms, to within one step.
#[track_caller]
fn assert_at_vs(trace: &[Inputs], p: Phase, sign: i32) {
    let pos = positions(trace, p);
    let moved = (pos[pos.len() - 1] - pos[0]) * sign;
    let expected = p.len as f64 * VS / 1000.0;
    assert!(
        (f64::from(moved) - expected).abs() <= 1.0,
        "{p:?}: {moved} steps, {expected}"
    );
    for w in pos.windows(2) {
        assert!(
            (w[1] - w[0]) * sign >= 0 && (w[1] - w[0]) * sign <= 1,
            "{pos:?}"
        );
    }
}

/// Asserts that every cycle from `from` to the end of the trace reports the same input words: no
/// motion, no bit changing but the Heartbeat (SMD-R6-067), for at least `min` cycles.
#[track_caller]
fn assert_rest(trace: &[Inputs], from: usize, min: usize) {
    assert!(
        trace.len() >= from + min,
        "{} cycles after {from}",
        trace.len() - from.min(trace.len())
    );
    let quiet = |i: &Inputs| Inputs {
        status1: i.status1 & !stat1::HEARTBEAT,
        ..*i
    };
    for (k, i) in trace[from..].iter().enumerate() {
        assert_eq!(quiet(i), quiet(&trace[from]), "cycle {} after the end", k);
    }
}

/// IN1 = Home, active over steps 5,000 … 5,200.
fn home_at_5000(p: i64) -> (bool, bool) {
    ((5_000..=5_200).contains(&p), false)
}

/// SMD-R4-009, SMD-R4-011, SMD-R4-012, SMD-R4-013, SMD-R4-014, SMD-R4-015, SMD-R4-001, SMD-R4-002,
/// SMD-R4-003, SMD-R4-010: the Home-input-only
/// profile of Figure R4.1 with Velocity 5,000 steps/s, Acceleration 40 and Deceleration 20 (×1000
/// steps/s²), worked out by hand: accelerate CW from V_S = 141 to 5,000 (121.5 ms, 312 steps), run at 5
/// steps/ms until Home goes active at 5,000; decelerate over 243 ms and (5,000² − 141²) / 40,000 = 624.5
/// steps to about 5,624; 2.000 s stopped; accelerate CCW, run at 5 steps/ms until Home goes inactive below
/// 5,000, decelerate to about 4,375; 2.000 s; return CW at V_S and stop on the Home edge at 5,000: about
/// 625 steps in 4.4 s. Motor_Position and Encoder_Position are then 0 and the Trapped_Encoder_Position
/// of an earlier capture is kept; At_Home and Stopped, no Position_Invalid, no Move_Complete — and it
/// stays so for 3 s.
#[test]
fn smd_r4_011_to_015_home_input_only_profile() {
    // IN2 = Start Indexed, for a capture before the homing.
    let mut r = rig(HOME | (3 << 3) | CFG0_USE_ENCODER);
    r.out.acceleration = 40;
    r.out.position = 4_000;
    r.command(cmd0::PRESET_ENCODER);
    r.command(0);
    r.ix.set_input(r.now(), 2, true);
    r.cycle();
    r.ix.set_input(r.now(), 2, false);
    r.cycle();
    assert_eq!(r.last.trapped_encoder_position, 4_000);
    r.out.position = 123_456; // SMD-R4-010: ignored.

    let trace = home(&mut r, cmd0::FIND_HOME_CW, home_at_5000, 16_000);
    let ph = phases(&trace);
    assert_eq!(
        kinds(&ph),
        [CW_ACC, CW_RUN, CW_DEC, PAUSE, CCW_ACC, CCW_RUN, CCW_DEC, PAUSE, CW_RUN, HOMED],
        "{ph:?}"
    );
    // Accelerations and decelerations: (5,000 − 141) / 40 and / 20 ms.
    for (k, ms) in [(0, 121.5), (2, 243.0), (4, 121.5), (6, 243.0)] {
        assert!(
            (ph[k].len as f64 - ms).abs() <= 2.0,
            "phase {k}: {:?}",
            ph[k]
        );
    }
    // The search and the back-off at Velocity (SMD-R4-010, SMD-R4-011, SMD-R4-013).
    assert_cruise(&trace, ph[1], 5);
    assert_cruise(&trace, ph[5], -5);
    // The Home edges: the search brakes from the cycle after it reached 5,000, the back-off from the
    // cycle after it went below 5,000.
    let at = |k: usize| trace[k].motor_position;
    assert!(
        (5_000..5_005).contains(&at(ph[2].first - 1)),
        "{}",
        at(ph[2].first - 1)
    );
    assert!(
        (4_995..5_000).contains(&at(ph[6].first - 1)),
        "{}",
        at(ph[6].first - 1)
    );
    // Where each deceleration ends: 624.5 steps on.
    let stop1 = at(ph[3].first);
    let stop2 = at(ph[7].first);
    assert!((stop1 - (at(ph[2].first - 1) + 624)).abs() <= 3, "{stop1}");
    assert!((stop2 - (at(ph[6].first - 1) - 624)).abs() <= 3, "{stop2}");
    // The pauses: 2.0 s Stopped, At_Home 0, not moving (SMD-R4-012, SMD-R4-014).
    for k in [3, 7] {
        assert!((1_999..=2_001).contains(&ph[k].len), "pause {:?}", ph[k]);
        assert_eq!(
            positions(&trace, ph[k]).iter().max(),
            positions(&trace, ph[k]).iter().min()
        );
    }
    // The return at V_S, with no acceleration, up to the Home edge (SMD-R4-015, SMD-R4-009).
    assert_at_vs(&trace, ph[8], 1);
    let back = f64::from(5_000 - stop2) / VS * 1000.0;
    assert!(
        (ph[8].len as f64 - back).abs() <= 10.0,
        "{:?}, {back} ms",
        ph[8]
    );
    // Home: both positions 0, the capture kept (SMD-R4-001, SMD-R4-002, SMD-R4-003).
    let end = trace[ph[9].first];
    assert_eq!(end.motor_position, 0);
    assert_eq!(end.encoder_position, 0);
    assert_eq!(end.trapped_encoder_position, 4_000);
    assert_eq!(
        end.status0
            & (PHASE_BITS | stat0::POSITION_INVALID | stat0::MOVE_COMPLETE | stat0::INPUT_ERROR),
        HOMED
    );
    assert_rest(&trace, ph[9].first, 3_000);
    // SMD-R2-022: the next command accepted clears At_Home.
    r.command(cmd0::RESET_ERRORS);
    assert_eq!(r.s0() & stat0::AT_HOME, 0);
}

/// IN1 = Home, active over steps −5,200 … −5,000.
fn home_at_minus_5000(p: i64) -> (bool, bool) {
    ((-5_200..=-5_000).contains(&p), false)
}

/// SMD-R4-009, SMD-R4-011, SMD-R4-012, SMD-R4-013, SMD-R4-014, SMD-R4-015: Find Home CCW is the
/// mirror image of Find Home CW: search CCW,
/// brake past the edge at −5,000, 2 s, back off CW past it, 2 s, return CCW at V_S, home at 0.
#[test]
fn smd_r4_009_find_home_ccw_is_the_mirror_image() {
    let mut r = rig(HOME);
    r.out.acceleration = 40;
    let trace = home(&mut r, cmd0::FIND_HOME_CCW, home_at_minus_5000, 16_000);
    let ph = phases(&trace);
    assert_eq!(
        kinds(&ph),
        [CCW_ACC, CCW_RUN, CCW_DEC, PAUSE, CW_ACC, CW_RUN, CW_DEC, PAUSE, CCW_RUN, HOMED],
        "{ph:?}"
    );
    assert_cruise(&trace, ph[1], -5);
    assert_cruise(&trace, ph[5], 5);
    let at = |k: usize| trace[k].motor_position;
    assert!(
        (-5_005..=-5_000).contains(&at(ph[2].first - 1)),
        "{}",
        at(ph[2].first - 1)
    );
    assert!(
        (-5_000..-4_995).contains(&at(ph[6].first - 1)),
        "{}",
        at(ph[6].first - 1)
    );
    for k in [3, 7] {
        assert!((1_999..=2_001).contains(&ph[k].len), "pause {:?}", ph[k]);
    }
    assert_at_vs(&trace, ph[8], -1);
    assert_eq!(trace[ph[9].first].motor_position, 0);
    assert_rest(&trace, ph[9].first, 3_000);
}

/// SMD-R4-016: the Home input already active when Find Home is issued: the profile starts at step 5,
/// CCW from the first cycle, with no first approach and no first pause; then the 2 s pause, the return
/// at V_S and home.
#[test]
fn smd_r4_016_home_already_active() {
    let mut r = rig(HOME);
    r.out.position = 5_100;
    r.command(cmd0::PRESET_POSITION);
    r.command(0);
    let trace = home(&mut r, cmd0::FIND_HOME_CW, home_at_5000, 12_000);
    let ph = phases(&trace);
    assert_eq!(
        kinds(&ph),
        [CCW_ACC, CCW_DEC, PAUSE, CW_RUN, HOMED],
        "{ph:?}"
    );
    assert_eq!(ph[0].first, 0);
    assert!((1_999..=2_001).contains(&ph[2].len), "{:?}", ph[2]);
    assert_at_vs(&trace, ph[3], 1);
    assert_eq!(trace[ph[4].first].motor_position, 0);
    assert_rest(&trace, ph[4].first, 3_000);
}

/// SMD-R4-004 gap: no input configured as Home: Command_Error, no motion.
#[test]
fn smd_r4_004_find_home_needs_a_home_input() {
    let mut r = rig(CW_LIMIT);
    let trace = home(&mut r, cmd0::FIND_HOME_CCW, |_| (false, false), 100);
    for i in &trace {
        assert_eq!(
            i.status0 & (PHASE_BITS | stat0::COMMAND_ERROR),
            stat0::COMMAND_ERROR | stat0::STOPPED
        );
        assert_eq!(i.motor_position, 0);
    }
}

/// IN1 = Home at 5,000 … 5,200 and 17,000 … 17,200 (two sensor passes before the proximity edge).
fn two_flags(p: i64) -> (bool, bool) {
    (
        (5_000..=5_200).contains(&p) || (17_000..=17_200).contains(&p),
        false,
    )
}

/// IN1 = Home at 5,000 … 5,200 and 15,300 … 15,500: the second flag comes while the motor still
/// brakes from the proximity edge at 15,000.
fn flag_while_braking(p: i64) -> (bool, bool) {
    (
        (5_000..=5_200).contains(&p) || (15_300..=15_500).contains(&p),
        false,
    )
}

/// A Find Home CW with Use_Backplane_Proximity, CMD1.11 at 1 for the one cycle after the motor passed
/// step 15,000, 0 before and after.
fn proximity_run(sensors: Sensors, ms: usize) -> Vec<Inputs> {
    let mut r = rig(HOME | CFG0_USE_BACKPLANE_PROXIMITY);
    r.cycle();
    r.out.cmd0 = cmd0::FIND_HOME_CW;
    let mut trace = Vec::new();
    let mut pulsed = false;
    for _ in 0..ms {
        if r.s0() & stat0::AT_HOME == 0 {
            step(&mut r, sensors);
        } else {
            r.cycle();
        }
        trace.push(r.last);
        // The 0→1 edge, and back to 0 in the next cycle (SMD-R4-020).
        r.out.cmd1 &= !cmd1::BACKPLANE_PROXIMITY;
        if !pulsed && r.ix.position() >= 15_000 {
            r.out.cmd1 |= cmd1::BACKPLANE_PROXIMITY;
            pulsed = true;
        }
    }
    trace
}

/// SMD-R4-017, SMD-R4-018, SMD-R4-019, SMD-R4-020: with Use_Backplane_Proximity the first flag at
/// 5,000 is passed at 5
/// steps/ms; the proximity edge at 15,000 starts the deceleration towards V_S (624.5 steps), the motor
/// carries on at V_S and stops at once on the next Home edge at 17,000 — no reversal, no pauses, no
/// deceleration at the end — though the bit went back to 0.
#[test]
fn smd_r4_017_to_020_backplane_proximity_profile() {
    let trace = proximity_run(two_flags, 17_000);
    let ph = phases(&trace);
    assert_eq!(
        kinds(&ph),
        [CW_ACC, CW_RUN, CW_DEC, CW_RUN, HOMED],
        "{ph:?}"
    );
    // Through the first flag at Velocity, up to the proximity edge.
    assert_cruise(&trace, ph[1], 5);
    let edge = trace[ph[2].first - 1].motor_position;
    assert!((15_000..15_010).contains(&edge), "{edge}");
    assert!((ph[2].len as f64 - 243.0).abs() <= 2.0, "{:?}", ph[2]);
    // At V_S up to the flag (SMD-R4-019); home there (SMD-R4-018).
    assert_at_vs(&trace, ph[3], 1);
    let last = trace[ph[4].first - 1].motor_position;
    assert!((16_999..=17_000).contains(&last), "{last}");
    assert_eq!(trace[ph[4].first].motor_position, 0);
    assert_rest(&trace, ph[4].first, 3_000);
}

/// SMD-R4-018: a Home edge during the deceleration after the proximity edge stops the motor at once,
/// above V_S: no V_S run.
#[test]
fn smd_r4_018_home_edge_while_braking_stops_at_once() {
    let trace = proximity_run(flag_while_braking, 7_000);
    let ph = phases(&trace);
    assert_eq!(kinds(&ph), [CW_ACC, CW_RUN, CW_DEC, HOMED], "{ph:?}");
    let pos = positions(&trace, ph[2]);
    // 300 steps into a 624.5-step deceleration: still well above V_S (0.141 steps/ms).
    assert!(pos[pos.len() - 1] - pos[pos.len() - 2] >= 2, "{pos:?}");
    assert_eq!(trace[ph[3].first].motor_position, 0);
    assert_rest(&trace, ph[3].first, 3_000);
}

/// SMD-R4-021: proximity mode without the bit: the search runs at Velocity through every Home edge.
#[test]
fn smd_r4_021_proximity_bit_never_set() {
    let mut r = rig(HOME | CFG0_USE_BACKPLANE_PROXIMITY);
    let trace = home(&mut r, cmd0::FIND_HOME_CW, two_flags, 8_000);
    let ph = phases(&trace);
    assert_eq!(kinds(&ph), [CW_ACC, CW_RUN], "{ph:?}");
    assert_cruise(&trace, ph[1], 5);
    assert!(trace[trace.len() - 1].motor_position > 17_200);
}

/// SMD-R4-022: with CFG_Word_0 bit 11 = 0, CMD_word1 bit 11 changes nothing: the run with the bit
/// rising in the search (at step 2,000) is the run without it, cycle for cycle, and it is the
/// Home-input-only profile.
#[test]
fn smd_r4_022_proximity_bit_ignored_without_the_configuration() {
    let run = |proximity: bool| {
        let mut r = rig(HOME);
        r.out.acceleration = 40;
        r.cycle();
        r.out.cmd0 = cmd0::FIND_HOME_CW;
        let mut trace = Vec::new();
        for _ in 0..14_000 {
            if r.s0() & stat0::AT_HOME == 0 {
                step(&mut r, home_at_5000);
            } else {
                r.cycle();
            }
            trace.push(r.last);
            if proximity && r.ix.position() >= 2_000 {
                r.out.cmd1 |= cmd1::BACKPLANE_PROXIMITY;
            }
        }
        trace
    };
    let with = run(true);
    assert_eq!(with, run(false));
    assert_eq!(
        kinds(&phases(&with)),
        [CW_ACC, CW_RUN, CW_DEC, PAUSE, CCW_ACC, CCW_RUN, CCW_DEC, PAUSE, CW_RUN, HOMED]
    );
}

/// IN1 = Home at −3,000 … −2,800 (behind the start), IN2 = CW limit from 4,000 on.
fn overtravel(p: i64) -> (bool, bool) {
    ((-3_000..=-2_800).contains(&p), p >= 4_000)
}

/// SMD-R4-023, SMD-R4-024, SMD-R4-027: the overtravel profile: the CW limit at 4,000 stops the search
/// at once (no deceleration), 2 s, back off CCW at Velocity past the Home sensor, decelerate once it
/// goes inactive below −3,000, 2 s, return at V_S to −3,000 and home. Input_Error is never set, and
/// Limit_Condition goes when the limit does.
#[test]
fn smd_r4_023_024_027_overtravel_profile() {
    let mut r = rig(HOME | (CW_LIMIT << 3));
    let trace = home(&mut r, cmd0::FIND_HOME_CW, overtravel, 16_000);
    let ph = phases(&trace);
    assert_eq!(
        kinds(&ph),
        [CW_ACC, CW_RUN, PAUSE, CCW_ACC, CCW_RUN, CCW_DEC, PAUSE, CW_RUN, HOMED],
        "{ph:?}"
    );
    let stop = trace[ph[2].first].motor_position;
    assert!((4_000..4_005).contains(&stop), "{stop}");
    assert_eq!(
        trace[ph[2].first - 1].motor_position,
        stop,
        "stopped in the cycle it saw the limit"
    );
    assert!((1_999..=2_001).contains(&ph[2].len), "{:?}", ph[2]);
    assert!((1_999..=2_001).contains(&ph[6].len), "{:?}", ph[6]);
    assert_cruise(&trace, ph[4], -5);
    let edge = trace[ph[5].first - 1].motor_position;
    assert!((-3_005..-3_000).contains(&edge), "{edge}");
    assert_at_vs(&trace, ph[7], 1);
    for i in &trace {
        assert_eq!(i.status0 & stat0::INPUT_ERROR, 0);
    }
    // Limit_Condition from the stop at the limit until the back-off leaves it.
    assert_ne!(trace[ph[2].first].status1 & stat1::LIMIT_CONDITION, 0);
    assert_eq!(trace[ph[5].first].status1 & stat1::LIMIT_CONDITION, 0);
    let home = trace[ph[8].first];
    assert_eq!(home.motor_position, 0);
    assert_eq!(home.status0 & (PHASE_BITS | stat0::POSITION_INVALID), HOMED);
    assert_rest(&trace, ph[8].first, 3_000);
}

/// SMD-R4-025: the travel limit already active: the first motion backs off at once, with no pause.
#[test]
fn smd_r4_025_limit_already_active() {
    let mut r = rig(HOME | (CW_LIMIT << 3));
    r.out.position = 4_500;
    r.command(cmd0::PRESET_POSITION);
    r.command(0);
    let trace = home(&mut r, cmd0::FIND_HOME_CW, overtravel, 16_000);
    let ph = phases(&trace);
    assert_eq!(
        kinds(&ph),
        [CCW_ACC, CCW_RUN, CCW_DEC, PAUSE, CW_RUN, HOMED],
        "{ph:?}"
    );
    assert_eq!(ph[0].first, 0);
    assert_eq!(trace[ph[5].first].motor_position, 0);
}

/// IN1 = Home far away, IN2 = CCW limit from 2,000 on (wired the wrong way round).
fn wrong_limit(p: i64) -> (bool, bool) {
    (p >= 100_000, p >= 2_000)
}

/// SMD-R4-026: the limit of the other direction during a Find Home stops the motor at once, with
/// Position_Invalid and Input_Error, and abandons the homing: for the 9 s after, nothing moves, nothing
/// is zeroed, no bit changes.
#[test]
fn smd_r4_026_opposite_limit_abandons_homing() {
    let mut r = rig(HOME | (CCW_LIMIT << 3));
    r.out.position = 0;
    r.command(cmd0::PRESET_POSITION);
    r.command(0);
    let trace = home(&mut r, cmd0::FIND_HOME_CW, wrong_limit, 10_000);
    let ph = phases(&trace);
    assert_eq!(kinds(&ph), [CW_ACC, CW_RUN, PAUSE], "{ph:?}");
    let stop = trace[ph[2].first];
    assert!((2_000..2_005).contains(&stop.motor_position), "{stop:?}");
    assert_eq!(trace[ph[2].first - 1].motor_position, stop.motor_position);
    assert_eq!(
        stop.status0 & (PHASE_BITS | stat0::POSITION_INVALID | stat0::INPUT_ERROR),
        stat0::STOPPED | stat0::POSITION_INVALID | stat0::INPUT_ERROR
    );
    for i in &trace[..ph[2].first] {
        assert_eq!(
            i.status0 & (stat0::INPUT_ERROR | stat0::POSITION_INVALID),
            0
        );
    }
    assert_rest(&trace, ph[2].first, 9_000);
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
    while r.s0() & stat0::STOPPED == 0 {
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
