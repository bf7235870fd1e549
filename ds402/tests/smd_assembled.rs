//! Assembled moves (programming handshake, Blend, Dwell, flash) and indexed moves on the SMD, rule by
//! rule (catalogue `rules/smd.md`, R2 and R6).

mod smd_rig;

use ds402::smd::indexer::{cmd0, cmd1, stat0, Outputs};
use smd_rig::Rig;

const START_INDEXED: u16 = 3;

fn rig(cfg0: u16) -> Rig {
    Rig::ready_with(cfg0, 5_000, 20, 20)
}

use smd_rig::Seg;

/// SMD-R2-083, SMD-R2-084, SMD-R2-085, SMD-R2-086, SMD-R2-087, SMD-R2-088, SMD-R6-016, SMD-R6-060:
/// Program_Assembled sets In_Assembled_Mode and
/// Waiting_For_Assembled_Segment; each Read_Assembled_Data edge takes a segment and clears Waiting,
/// which returns when the bit falls; Program_Assembled falling ends programming.
#[test]
fn smd_r2_083_to_088_programming_handshake() {
    let mut r = rig(0);
    assert_eq!(
        r.s0() & (stat0::IN_ASSEMBLED_MODE | stat0::WAITING_FOR_SEGMENT),
        0
    );
    let seen = r.program(&[(1_000, 2_000, 10, 10), (2_000, 4_000, 10, 10)], false);
    let bits = |s: u16| s & (stat0::IN_ASSEMBLED_MODE | stat0::WAITING_FOR_SEGMENT);
    let both = stat0::IN_ASSEMBLED_MODE | stat0::WAITING_FOR_SEGMENT;
    assert_eq!(
        seen.iter().map(|&s| bits(s)).collect::<Vec<_>>(),
        [
            both,
            stat0::IN_ASSEMBLED_MODE,
            both,
            stat0::IN_ASSEMBLED_MODE,
            both,
            0
        ]
    );
    assert!(seen.iter().all(|s| s & stat0::COMMAND_ERROR == 0));
    assert_eq!(r.ix.assembled_program().map(<[_]>::len), Some(2));
}

/// The positions of the stored program's segments.
fn stored(r: &Rig) -> Vec<i32> {
    r.ix.assembled_program()
        .unwrap()
        .iter()
        .map(|g| g.position)
        .collect()
}

/// SMD-R2-072, SMD-R2-085, SMD-R6-045, SMD-R2-087: a bad segment (Velocity below V_S, Position out of
/// range) is a Command_Error at its handshake and not stored; a 17th segment likewise. Each bad
/// segment is tried in a program of its own (Command_Error stays until Reset Errors, so a second
/// one would show nothing new), after a good one; and every handshake of 16 good segments is
/// checked free of Command_Error, so that the error is the 17th's and the first 16 are kept.
#[test]
fn smd_r2_072_085_087_bad_segments() {
    let mut r = rig(0);
    for bad in [(1_000, 100, 10, 10), (8_388_608, 2_000, 10, 10)] {
        let seen = r.program(&[(500, 2_000, 10, 10), bad], false);
        // [0] First Block, [1]/[2] the good segment's handshake, [3] the bad one's edge.
        assert_eq!(
            seen[1] & stat0::COMMAND_ERROR,
            0,
            "{bad:?}: the good segment"
        );
        assert_eq!(seen[2] & stat0::COMMAND_ERROR, 0, "{bad:?}");
        assert_eq!(
            seen[3] & (stat0::COMMAND_ERROR | stat0::WAITING_FOR_SEGMENT),
            stat0::COMMAND_ERROR,
            "{bad:?}: refused, not waiting"
        );
        assert_eq!(
            stored(&r),
            [500],
            "{bad:?}: only the good segment is stored"
        );
        r.command(cmd0::RESET_ERRORS);
        r.command(0);
        assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0);
    }
    let segs: Vec<Seg> = (0..17).map(|k| (100 + k, 2_000, 10, 10)).collect();
    let seen = r.program(&segs, false);
    assert_eq!(seen.len(), 36, "First Block, 2 per segment, the end");
    for (k, s) in seen[1..33].iter().enumerate() {
        assert_eq!(
            s & stat0::COMMAND_ERROR,
            0,
            "handshake step {k} of the first 16"
        );
    }
    assert_eq!(
        seen[33] & stat0::COMMAND_ERROR,
        stat0::COMMAND_ERROR,
        "the 17th"
    );
    assert_eq!(stored(&r), (100..116).collect::<Vec<i32>>(), "the first 16");
}

/// Runs the stored move (CMD_word0 = 0x2000) to its end; (speed, status) per cycle.
fn run(r: &mut Rig, cmd1_extra: u16, jerk: u16) -> Vec<(f64, u16)> {
    r.out.cmd1 = cmd1::ENABLE_DRIVER | cmd1_extra;
    r.out.jerk = jerk;
    r.command(cmd0::RUN_ASSEMBLED_MOVE);
    let mut trace = vec![(r.ix.speed(), r.s0())];
    for _ in 0..200_000 {
        let i = r.cycle();
        trace.push((r.ix.speed(), i.status0));
        if i.status0 & stat0::MOVE_COMPLETE != 0 || i.status0 & stat0::COMMAND_ERROR != 0 {
            break;
        }
    }
    r.command(0);
    trace
}

/// SMD-R2-070, SMD-R2-071, SMD-R2-074, SMD-R2-075, SMD-R2-068, SMD-R2-020 (Blend): a Blend runs every segment in the
/// CMD_word1 bit 4 direction (signs ignored) without stopping, changing speed at each boundary, and
/// ends at the sum of the magnitudes with Move_Complete.
#[test]
fn smd_r2_070_071_074_075_blend_move() {
    let mut r = rig(0);
    r.program(
        &[
            (10_000, 4_000, 10, 10),
            (-10_000, 8_000, 5, 20),
            (10_000, 2_000, 10, 4),
        ],
        false,
    );
    let trace = run(&mut r, 0, 0);
    assert_eq!(r.pos(), 30_000);
    assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
    let moving = &trace[..trace.len() - 1];
    assert!(
        moving.iter().all(|t| t.1 & stat0::STOPPED == 0),
        "never stops"
    );
    assert!(moving.iter().all(|t| t.0 > 0.0), "one direction");
    let peak = trace.iter().map(|t| t.0).fold(0.0, f64::max);
    assert_eq!(peak, 8_000.0, "segment 2's Velocity");
    // CCW with bit 4.
    let start = r.pos();
    let trace = run(&mut r, cmd1::REVERSE_BLEND, 0);
    assert_eq!(r.pos(), start - 30_000);
    assert!(trace[..trace.len() - 1].iter().all(|t| t.0 < 0.0));
}

/// SMD-R2-073: segments with the same Velocity pass the boundary with no speed change.
#[test]
fn smd_r2_073_same_speed_boundary() {
    let mut r = rig(0);
    r.program(&[(20_000, 4_000, 10, 10), (20_000, 4_000, 10, 10)], false);
    let trace = run(&mut r, 0, 0);
    // Between the end of the first ramp and the final braking: constant speed, no phase bits.
    let cruise: Vec<&(f64, u16)> = trace.iter().filter(|t| t.0 == 4_000.0).collect();
    assert!(cruise.len() > 8_000, "{} ms at 4,000", cruise.len());
    assert!(cruise
        .iter()
        .all(|t| t.1 & (stat0::ACCELERATING | stat0::DECELERATING) == 0));
    assert_eq!(r.pos(), 40_000);
}

/// SMD-R2-076 (pick): a Blend segment too short for its ramp ramps at its own rate for as long as it
/// lasts, and at its end the speed steps straight to the next segment's Velocity, with no ramp.
/// Segment 1 (1,000 steps, Velocity 20,000, Acceleration 10) rises 10 steps/s per ms from V_S and
/// reaches only 4,471 steps/s by its end (1,000 steps ≈ 434 ms), then the speed is 8,000 at once;
/// segment 3 (1,000 steps, 2,000 steps/s, Deceleration 1) slows 1 step/s per ms from 8,000, reaches
/// only 7,875 by its end, and the speed is segment 4's 3,000 at once. The move ends at 42,000.
#[test]
fn smd_r2_076_short_blend_segment_jumps() {
    let mut r = rig(0);
    r.program(
        &[
            (1_000, 20_000, 10, 10),
            (20_000, 8_000, 10, 10),
            (1_000, 2_000, 10, 1),
            (20_000, 3_000, 10, 10),
        ],
        false,
    );
    let trace = run(&mut r, 0, 0);
    assert_eq!(r.pos(), 42_000);
    assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
    // The steps of more than 1,000 steps/s from one cycle to the next.
    let jumps: Vec<(usize, f64, f64)> = trace
        .windows(2)
        .enumerate()
        .filter(|(_, w)| (w[1].0 - w[0].0).abs() > 1_000.0)
        .map(|(k, w)| (k + 1, w[0].0, w[1].0))
        .collect();
    assert_eq!(jumps.len(), 2, "{jumps:?}");
    let (k1, before1, after1) = jumps[0];
    assert!((before1 - 4_471.0).abs() < 1e-6, "{before1}");
    assert_eq!(after1, 8_000.0);
    // Up to the jump: Accelerating, 10 steps/s more every ms (the first cycle is 1 ms in: 151).
    assert!((trace[0].0 - 151.0).abs() < 1e-6);
    for w in trace[..k1].windows(2) {
        assert!((w[1].0 - w[0].0 - 10.0).abs() < 1e-6);
        assert_ne!(w[1].1 & stat0::ACCELERATING, 0);
    }
    assert_eq!(
        k1, 433,
        "1 ms per cycle, 4,471 − 141 = 4,330 steps/s in 433 ms"
    );
    // After it: 8,000 with neither Accelerating nor Decelerating.
    assert!(trace[k1..k1 + 100]
        .iter()
        .all(|t| t.0 == 8_000.0 && t.1 & (stat0::ACCELERATING | stat0::DECELERATING) == 0));
    let (k2, before2, after2) = jumps[1];
    // Segment 3 slowed at 1 step/s per ms until its end, then 3,000 at once.
    // 125 ms at −1,000 steps/s² cover 992 steps; in the 126th the segment ends.
    assert!((before2 - 7_875.0).abs() < 1e-6, "{before2}");
    assert_eq!(after2, 3_000.0);
    let slowing: Vec<&(f64, u16)> = trace[..k2]
        .iter()
        .filter(|t| t.1 & stat0::DECELERATING != 0)
        .collect();
    // Decelerating from the cycle that enters segment 3 (still 8,000) down to 7,875.
    assert_eq!(slowing.len(), 126, "cycles slowing in segment 3");
    assert_eq!(slowing[0].0, 8_000.0);
    for w in slowing.windows(2) {
        assert!(
            (w[0].0 - w[1].0 - 1.0).abs() < 1e-6,
            "{} → {}",
            w[0].0,
            w[1].0
        );
    }
    assert!((slowing[slowing.len() - 1].0 - before2).abs() < 1e-6);
    assert_eq!(
        trace[k2].1 & (stat0::ACCELERATING | stat0::DECELERATING),
        0,
        "no ramp to 3,000"
    );
}

/// SMD-R2-077, SMD-R2-078, SMD-R2-079, SMD-R2-080, SMD-R6-015, SMD-R6-003, SMD-R2-020 (Dwell): a Dwell Move runs each segment as its
/// own move, in the direction of its sign, stopped for the Dwell Time (the Jerk word, ms) between
/// segments and not after the last; bit 4 changes nothing.
#[test]
fn smd_r2_077_to_080_dwell_move() {
    let mut r = rig(0);
    r.program(
        &[
            (3_000, 4_000, 20, 20),
            (-1_000, 4_000, 20, 20),
            (500, 2_000, 20, 20),
        ],
        false,
    );
    let trace = run(&mut r, cmd1::DWELL | cmd1::REVERSE_BLEND, 750);
    assert_eq!(r.pos(), 2_500);
    let mut stops = Vec::new();
    let mut run_len = 0;
    let mut dirs = Vec::new();
    for &(v, s) in &trace {
        if s & stat0::STOPPED != 0 {
            run_len += 1;
        } else {
            if run_len > 0 {
                stops.push(run_len);
            }
            run_len = 0;
            let d = v.signum() as i32;
            if dirs.last() != Some(&d) {
                dirs.push(d);
            }
        }
    }
    assert_eq!(dirs, [1, -1, 1]);
    assert_eq!(stops.len(), 2, "{stops:?}");
    for s in stops {
        assert!((749..=752).contains(&s), "dwell {s} ms");
    }
    assert_eq!(run_len, 1, "complete in the update the last segment stops");
}

/// The lengths of the runs of Stopped = 1 between moving cycles, and the directions in order.
fn pauses_and_directions(trace: &[(f64, u16)]) -> (Vec<usize>, Vec<i32>) {
    let (mut pauses, mut dirs, mut run_len) = (Vec::new(), Vec::new(), 0);
    for &(v, s) in trace {
        if s & stat0::STOPPED != 0 {
            run_len += 1;
        } else {
            if run_len > 0 {
                pauses.push(run_len);
            }
            run_len = 0;
            let d = v.signum() as i32;
            if dirs.last() != Some(&d) {
                dirs.push(d);
            }
        }
    }
    (pauses, dirs)
}

/// SMD-R6-014, SMD-R2-068 (one program run as a Blend, then as a Dwell): CMD_word0 = 0x2000 runs the stored program. With CMD_word1 bit 9 = 0 it is a Blend
/// (CW, or CCW with bit 4; segment signs ignored; the Jerk word unused: the same speed profile with
/// Jerk 0 and 500); with bit 9 = 1 a Dwell (signed segments, stopped for Jerk-word ms between
/// them: 300 and 40 ms). Pick: CMD_word1 bit 13 (Preset_to_Encoder) rising runs nothing.
#[test]
fn smd_r6_014_run_assembled_move() {
    let mut r = rig(0);
    r.program(&[(3_000, 4_000, 20, 20), (-1_000, 6_000, 20, 20)], false);
    // CMD_word1 bit 13 is not the run bit.
    r.out.cmd1 |= cmd1::PRESET_TO_ENCODER;
    for _ in 0..100 {
        r.cycle();
    }
    assert_eq!((r.pos(), r.s0() & stat0::STOPPED), (0, stat0::STOPPED));
    r.out.cmd1 &= !cmd1::PRESET_TO_ENCODER;
    r.cycle();

    // Blend, CW: 3,000 + 1,000 steps without stopping; the Jerk word changes nothing.
    let blend = run(&mut r, 0, 0);
    assert_eq!(r.pos(), 4_000);
    assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
    assert_eq!(pauses_and_directions(&blend), (vec![], vec![1]));
    assert_eq!(blend[blend.len() - 1].1 & stat0::STOPPED, stat0::STOPPED);
    let blend_jerk = run(&mut r, 0, 500);
    assert_eq!(r.pos(), 8_000);
    let speeds = |t: &[(f64, u16)]| t.iter().map(|x| x.0).collect::<Vec<_>>();
    assert_eq!(
        speeds(&blend_jerk),
        speeds(&blend),
        "Jerk unused by a Blend"
    );
    // Blend, CCW with CMD_word1 bit 4.
    let ccw = run(&mut r, cmd1::REVERSE_BLEND, 0);
    assert_eq!(r.pos(), 4_000);
    assert_eq!(pauses_and_directions(&ccw), (vec![], vec![-1]));

    // Dwell: +3,000 then −1,000, stopped Jerk-word ms between.
    for dwell in [300, 40] {
        let start = r.pos();
        let t = run(&mut r, cmd1::DWELL, dwell);
        assert_eq!(r.pos(), start + 2_000);
        assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
        assert_eq!(
            pauses_and_directions(&t),
            (vec![usize::from(dwell)], vec![1, -1]),
            "dwell {dwell} ms"
        );
    }
}

/// SMD-R2-069, SMD-R2-081: no program (or one segment) is a Command_Error; a program runs again; a
/// configuration write discards a RAM program.
#[test]
fn smd_r2_069_081_stored_program() {
    let mut r = rig(0);
    let trace = run(&mut r, 0, 0);
    assert_ne!(trace[0].1 & stat0::COMMAND_ERROR, 0);
    r.command(cmd0::RESET_ERRORS);
    r.command(0);
    r.program(&[(1_000, 4_000, 20, 20)], false);
    assert_ne!(
        run(&mut r, 0, 0)[0].1 & stat0::COMMAND_ERROR,
        0,
        "one segment"
    );
    r.command(cmd0::RESET_ERRORS);
    r.command(0);
    r.program(&[(1_000, 4_000, 20, 20), (1_000, 4_000, 20, 20)], false);
    let start = r.pos();
    run(&mut r, 0, 0);
    run(&mut r, 0, 0);
    assert_eq!(r.pos(), start + 4_000, "run twice");
    r.ix.write_config(r.now(), 6, 40);
    assert!(r.ix.assembled_program().is_none());
}

/// SMD-R2-069: programs of 2 and of 16 segments (the bounds) run without error, as a Blend and as a
/// Dwell. Blend: segment k of (k + 1) × 50 steps at 2,000 or 4,000 steps/s, all CW whatever the sign
/// — 2 segments end 150 steps on, 16 end 50 × (1 + … + 16) = 6,800 on. Dwell: segments of ±300 steps
/// in turn, 10 ms apart — 2 or 16 runs in alternating directions with 1 or 15 pauses, ending where
/// they started. No cycle of any run shows Command_Error, and each ends with Move_Complete.
#[test]
fn smd_r2_069_two_and_sixteen_segments_run() {
    for n in [2usize, 16] {
        let blend: Vec<Seg> = (0..n)
            .map(|k| {
                let sign = if k % 3 == 1 { -1 } else { 1 };
                (sign * 50 * (k as i32 + 1), [2_000, 4_000][k % 2], 20, 20)
            })
            .collect();
        let mut r = rig(0);
        let seen = r.program(&blend, false);
        assert_eq!(seen.len(), 2 * n + 2);
        assert!(
            seen.iter().all(|s| s & stat0::COMMAND_ERROR == 0),
            "{seen:?}"
        );
        assert_eq!(r.ix.assembled_program().map(<[_]>::len), Some(n));
        let trace = run(&mut r, 0, 0);
        assert!(
            trace.iter().all(|t| t.1 & stat0::COMMAND_ERROR == 0),
            "{n} segments"
        );
        assert_ne!(
            trace[trace.len() - 1].1 & stat0::MOVE_COMPLETE,
            0,
            "{n} segments"
        );
        let expected = if n == 2 { 150 } else { 6_800 };
        assert_eq!(r.pos(), expected, "Blend of {n}");

        let dwell: Vec<Seg> = (0..n)
            .map(|k| (if k % 2 == 0 { 300 } else { -300 }, 4_000, 20, 20))
            .collect();
        let mut r = rig(0);
        r.program(&dwell, false);
        let trace = run(&mut r, cmd1::DWELL, 10);
        assert!(
            trace.iter().all(|t| t.1 & stat0::COMMAND_ERROR == 0),
            "{n} segments"
        );
        assert_ne!(trace[trace.len() - 1].1 & stat0::MOVE_COMPLETE, 0);
        let (pauses, dirs) = pauses_and_directions(&trace);
        assert_eq!(dirs, (0..n).map(|k| [1, -1][k % 2]).collect::<Vec<i32>>());
        assert_eq!(pauses.len(), n - 1, "{pauses:?}");
        for p in &pauses {
            assert!((9..=12).contains(p), "{pauses:?}");
        }
        assert_eq!(r.pos(), 0, "Dwell of {n}");
    }
}

/// SMD-R2-074, SMD-R2-075, SMD-R2-071: a Blend of 1,000 steps at 4,000 steps/s then 1,000 at 2,000
/// (both ramps 10 = 10,000 steps/s²), worked out by hand, from the status words and positions alone:
/// accelerate from V_S = 141 for (4,000 − 141) / 10 = 386 ms (799 steps), run at 4 steps/ms to the
/// boundary at 1,000; slow to 2,000 with the last segment's Deceleration for 200 ms (600 steps), run at
/// 2 steps/ms, then the final deceleration with the same slope, (2,000 − 141) / 10 = 186 ms (199 steps),
/// ending at 2,000 with Move_Complete, never stopped on the way.
#[test]
fn smd_r2_074_075_blend_speeds_and_both_slow_downs() {
    let mut r = rig(0);
    r.program(&[(1_000, 4_000, 10, 10), (1_000, 2_000, 10, 10)], false);
    r.out.cmd1 = cmd1::ENABLE_DRIVER;
    r.command(cmd0::RUN_ASSEMBLED_MOVE);
    let mut trace = vec![r.last];
    for _ in 0..3_000 {
        trace.push(r.cycle());
    }
    let bits = stat0::ACCELERATING | stat0::DECELERATING | stat0::STOPPED;
    // (bits, first cycle, length) of each run of equal motion bits.
    let mut ph: Vec<(u16, usize, usize)> = Vec::new();
    for (k, i) in trace.iter().enumerate() {
        match ph.last_mut() {
            Some(p) if p.0 == i.status0 & bits => p.2 += 1,
            _ => ph.push((i.status0 & bits, k, 1)),
        }
    }
    let kinds: Vec<u16> = ph.iter().map(|p| p.0).collect();
    assert_eq!(
        kinds,
        [
            stat0::ACCELERATING,
            0,
            stat0::DECELERATING,
            0,
            stat0::DECELERATING,
            stat0::STOPPED
        ],
        "{ph:?}"
    );
    for (k, ms) in [(0, 386.0), (2, 200.0), (4, 186.0)] {
        assert!((ph[k].2 as f64 - ms).abs() <= 2.0, "phase {k}: {ph:?}");
    }
    let cruise = |k: usize| {
        let (_, first, len) = ph[k];
        (first..first + len)
            .map(|c| trace[c].motor_position - trace[c - 1].motor_position)
            .collect::<Vec<i32>>()
    };
    assert_eq!(cruise(1), vec![4; ph[1].2]);
    assert_eq!(cruise(3), vec![2; ph[3].2]);
    // The boundary: the slow-down starts within a cycle of 1,000 steps.
    let at = trace[ph[2].1 - 1].motor_position;
    assert!((996..=1_004).contains(&at), "{at}");
    let end = trace[ph[5].1];
    assert_eq!(end.motor_position, 2_000);
    assert_ne!(end.status0 & stat0::MOVE_COMPLETE, 0);
    for i in &trace[..ph[5].1] {
        assert_eq!(i.status0 & (stat0::MOVE_COMPLETE | stat0::COMMAND_ERROR), 0);
    }
}

/// SMD-R2-086: Waiting_For_Assembled_Segment comes back only when Read_Assembled_Data falls: held at 1
/// for 5 cycles after a segment was taken, it stays 0 all that time.
#[test]
fn smd_r2_086_waiting_returns_only_on_the_falling_edge() {
    let mut r = rig(0);
    r.command(cmd0::PROGRAM_ASSEMBLED);
    assert_ne!(r.s0() & stat0::WAITING_FOR_SEGMENT, 0);
    r.out.position = 1_000;
    r.out.velocity = 2_000;
    for _ in 0..5 {
        r.command(cmd0::PROGRAM_ASSEMBLED | cmd0::READ_ASSEMBLED_DATA);
        assert_eq!(r.s0() & stat0::WAITING_FOR_SEGMENT, 0);
    }
    r.command(cmd0::PROGRAM_ASSEMBLED);
    assert_ne!(r.s0() & stat0::WAITING_FOR_SEGMENT, 0);
    r.command(0);
    assert_eq!(stored(&r), [1_000], "one segment for one rising edge");
}

/// SMD-R6-032 with an assembled move: its segments carry no current, so with CMD_word1 bit 1 set and
/// out.Motor_Current = 25 the run uses the configured current: in.Motor_Current reads 8010:07's 10
/// throughout, with no Command_Error.
#[test]
fn smd_r6_032_an_assembled_move_runs_at_the_configured_current() {
    let mut r = rig(0);
    r.program(&[(500, 2_000, 10, 10), (500, 3_000, 10, 10)], false);
    let trace = {
        r.out.motor_current = 25;
        run(&mut r, cmd1::MOTOR_CURRENT, 0)
    };
    assert!(trace.len() > 100);
    assert_ne!(trace[trace.len() - 1].1 & stat0::MOVE_COMPLETE, 0);
    assert!(trace.iter().all(|t| t.1 & stat0::COMMAND_ERROR == 0));
    assert_eq!(r.last.motor_current, 10);
    assert_eq!(r.pos(), 1_000);
}

/// SMD-R2-036: Hold during a Blend, or during a Dwell segment, decelerates at once to a controlled
/// stop; the move is not held (In_Hold_State stays 0) and a later Resume is a Command_Error with no
/// motion. SMD-R2-034: in a Dwell move's pause nothing is moving, yet no other move starts.
#[test]
fn smd_r2_036_hold_stops_an_assembled_move_for_good() {
    for (case, extra) in [("Blend", 0), ("Dwell", cmd1::DWELL)] {
        let mut r = rig(0);
        r.program(&[(3_000, 4_000, 20, 20), (3_000, 4_000, 20, 20)], false);
        r.out.cmd1 = cmd1::ENABLE_DRIVER | extra;
        r.out.jerk = 500;
        r.command(cmd0::RUN_ASSEMBLED_MOVE);
        for _ in 0..400 {
            r.cycle();
        }
        r.command(cmd0::HOLD_MOVE);
        assert_eq!(
            r.s0() & (stat0::DECELERATING | stat0::STOPPED),
            stat0::DECELERATING,
            "{case}"
        );
        r.until(5_000, |i| i.status0 & stat0::STOPPED != 0);
        assert_eq!(
            r.s0() & (stat0::IN_HOLD_STATE | stat0::MOVE_COMPLETE),
            0,
            "{case}"
        );
        let at = r.pos();
        r.command(0);
        r.command(cmd0::RESUME_MOVE);
        assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0, "{case}");
        for _ in 0..1_000 {
            assert_eq!(r.pos(), at, "{case}");
            r.cycle();
        }
    }
    // The pause between two Dwell segments: Stopped, and a Relative move is refused.
    let mut r = rig(0);
    r.program(&[(500, 4_000, 20, 20), (500, 4_000, 20, 20)], false);
    r.out.cmd1 = cmd1::ENABLE_DRIVER | cmd1::DWELL;
    r.out.jerk = 1_000;
    r.command(cmd0::RUN_ASSEMBLED_MOVE);
    r.until(5_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 500);
    r.command(0);
    r.out.position = 100;
    r.command(cmd0::RELATIVE_MOVE);
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0, "in the pause");
    r.command(0);
    r.until(5_000, |i| i.status0 & stat0::MOVE_COMPLETE != 0);
    assert_eq!(r.pos(), 1_000, "the program goes on");
}

/// SMD-R2-089, SMD-R2-082: saved to flash when Program_Assembled falls with Save_to_Flash; then every
/// command is ignored until power is cycled; after the cycle (and a configuration write) the flash
/// program runs.
#[test]
fn smd_r2_082_089_flash() {
    let mut r = rig(0);
    let seen = r.program(&[(2_000, 4_000, 20, 20), (2_000, 4_000, 20, 20)], true);
    assert_eq!(
        seen.last().unwrap() & (stat0::IN_ASSEMBLED_MODE | stat0::WAITING_FOR_SEGMENT),
        0
    );
    r.out.position = 5;
    r.command(cmd0::RELATIVE_MOVE);
    assert_eq!(
        r.s0() & stat0::STOPPED,
        stat0::STOPPED,
        "ignored until a power cycle"
    );
    assert_eq!(r.pos(), 0);
    r.ix.power_cycle();
    r.ix.write_config(r.now(), 3, 141);
    r.out = Outputs {
        cmd1: cmd1::ENABLE_DRIVER,
        ..Outputs::default()
    };
    r.cycle();
    let trace = run(&mut r, 0, 0);
    assert_eq!(trace[0].1 & stat0::COMMAND_ERROR, 0);
    assert_eq!(r.pos(), 4_000);
}

/// SMD-R2-090, SMD-R2-092, SMD-R2-094, SMD-R2-095: an indexed Relative move waits for the Start
/// Indexed edge, runs on each later edge while the command stays, ignores edges while it runs, and
/// is not disturbed by the input going inactive.
#[test]
fn smd_r2_090_092_094_095_indexed_moves() {
    let mut r = rig(START_INDEXED);
    r.out.cmd1 |= cmd1::INDEXED;
    r.out.position = 1_000;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..100 {
        r.cycle();
    }
    assert_eq!(r.pos(), 0, "waits for the input");
    assert_ne!(r.s0() & stat0::STOPPED, 0);
    for k in 1..=3 {
        r.ix.set_input(r.now(), 1, true);
        r.cycle();
        assert_eq!(r.s0() & stat0::STOPPED, 0, "run {k} started");
        r.ix.set_input(r.now(), 1, false);
        r.cycle();
        r.ix.set_input(r.now(), 1, true); // mid-move edge: ignored
        r.cycle();
        r.ix.set_input(r.now(), 1, false);
        r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
        assert_eq!(r.pos(), 1_000 * k);
        assert_ne!(r.s0() & stat0::MOVE_COMPLETE, 0);
    }
}

/// SMD-R2-090: every move type waits, indexed, for the Start Indexed edge — Absolute, Relative, Jog and
/// Registration each way, Find Home each way, Blend, Dwell: for 200 cycles Stopped stays 1 and
/// Motor_Position 0; the IN1 edge starts it in that cycle, in its direction.
#[test]
fn smd_r2_090_every_move_type_waits_for_the_edge() {
    let cases: [(&str, u16, u16, u16); 10] = [
        ("Absolute", 0, cmd0::ABSOLUTE_MOVE, stat0::MOVING_CW),
        ("Relative", 0, cmd0::RELATIVE_MOVE, stat0::MOVING_CW),
        ("Jog CW", 0, cmd0::JOG_CW, stat0::MOVING_CW),
        ("Jog CCW", 0, cmd0::JOG_CCW, stat0::MOVING_CCW),
        (
            "Registration CW",
            cmd1::REGISTRATION_MOVE,
            cmd0::JOG_CW,
            stat0::MOVING_CW,
        ),
        (
            "Registration CCW",
            cmd1::REGISTRATION_MOVE,
            cmd0::JOG_CCW,
            stat0::MOVING_CCW,
        ),
        ("Find Home CW", 0, cmd0::FIND_HOME_CW, stat0::MOVING_CW),
        ("Find Home CCW", 0, cmd0::FIND_HOME_CCW, stat0::MOVING_CCW),
        ("Blend", 0, cmd0::RUN_ASSEMBLED_MOVE, stat0::MOVING_CW),
        (
            "Dwell",
            cmd1::DWELL,
            cmd0::RUN_ASSEMBLED_MOVE,
            stat0::MOVING_CW,
        ),
    ];
    for (case, extra, c, moving) in cases {
        // IN1 = Start Indexed, IN2 = Home.
        let mut r = rig(START_INDEXED | (6 << 3));
        r.program(&[(1_000, 4_000, 10, 10), (1_000, 2_000, 10, 10)], false);
        r.out.cmd1 = cmd1::ENABLE_DRIVER | cmd1::INDEXED | extra;
        r.out.position = 1_500;
        r.out.velocity = 5_000;
        r.out.jerk = 10;
        r.command(c);
        for k in 0..200 {
            assert_eq!(
                r.s0() & (stat0::STOPPED | stat0::COMMAND_ERROR | stat0::INPUT_ERROR),
                stat0::STOPPED,
                "{case}, cycle {k}"
            );
            assert_eq!(r.pos(), 0, "{case}");
            r.cycle();
        }
        r.ix.set_input(r.now(), 1, true);
        r.cycle();
        assert_eq!(
            r.s0() & (stat0::STOPPED | stat0::MOVING_CW | stat0::MOVING_CCW),
            moving,
            "{case}"
        );
        // From the edge on it is the move the same command gives at once without Indexed_Command:
        // STATUS_word0 and Motor_Position cycle for cycle.
        let mut plain = rig(START_INDEXED | (6 << 3));
        plain.program(&[(1_000, 4_000, 10, 10), (1_000, 2_000, 10, 10)], false);
        plain.out = Outputs {
            cmd1: cmd1::ENABLE_DRIVER | extra,
            ..r.out
        };
        plain.command(c);
        let seen = |r: &Rig| (r.s0(), r.pos());
        assert_eq!(seen(&r), seen(&plain), "{case}, first cycle");
        for k in 1..3_000 {
            r.cycle();
            plain.cycle();
            assert_eq!(seen(&r), seen(&plain), "{case}, cycle {k}");
        }
    }
}

/// SMD-R2-093, SMD-R2-096: clearing the command cancels it; a new edge latches new parameters.
#[test]
fn smd_r2_093_096_indexed_cancel_and_new_parameters() {
    let mut r = rig(START_INDEXED);
    r.out.cmd1 |= cmd1::INDEXED;
    r.out.position = 1_000;
    r.command(cmd0::RELATIVE_MOVE);
    r.out.position = 7; // changed data without a new edge: the latched 1,000 stays
    r.cycle();
    r.ix.set_input(r.now(), 1, true);
    r.cycle();
    r.ix.set_input(r.now(), 1, false);
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 1_000);
    r.command(0);
    r.ix.set_input(r.now(), 1, true);
    r.cycle();
    r.ix.set_input(r.now(), 1, false);
    for _ in 0..100 {
        r.cycle();
    }
    assert_eq!(r.pos(), 1_000, "cancelled");
    r.out.position = 250;
    r.command(cmd0::RELATIVE_MOVE);
    r.ix.set_input(r.now(), 1, true);
    r.cycle();
    r.until(10_000, |i| i.status0 & stat0::STOPPED != 0);
    assert_eq!(r.pos(), 1_250);
}

/// SMD-R2-091: with no Start Indexed input an indexed command never starts (no error).
/// SMD-R2-098, SMD-R2-099, SMD-R2-100: Hold, Immediate Stop and Reset Errors act at once with
/// CMD_word1 bit 8.
#[test]
fn smd_r2_091_098_099_100_immediate_commands() {
    let mut r = rig(0);
    r.out.cmd1 |= cmd1::INDEXED;
    r.out.position = 1_000;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..100 {
        r.cycle();
    }
    assert_eq!(r.pos(), 0);
    assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0);
    r.command(0);
    r.out.cmd1 &= !cmd1::INDEXED;
    r.out.position = 50_000;
    r.command(cmd0::RELATIVE_MOVE);
    r.command(0);
    for _ in 0..500 {
        r.cycle();
    }
    r.out.cmd1 |= cmd1::INDEXED;
    r.command(cmd0::HOLD_MOVE);
    assert_ne!(r.s0() & stat0::DECELERATING, 0, "Hold at once");
    r.command(0);
    r.command(cmd0::IMMEDIATE_STOP);
    assert_ne!(
        r.s0() & stat0::POSITION_INVALID,
        0,
        "Immediate Stop at once"
    );
    r.command(0);
    r.command(cmd0::ABSOLUTE_MOVE); // indexed: latched, and with no Start Indexed input never run
    r.command(0);
    r.out.cmd1 &= !cmd1::INDEXED;
    r.out.position = 1;
    r.command(cmd0::ABSOLUTE_MOVE);
    assert_ne!(r.s0() & stat0::COMMAND_ERROR, 0);
    r.command(0);
    r.out.cmd1 |= cmd1::INDEXED;
    r.command(cmd0::RESET_ERRORS);
    assert_eq!(r.s0() & stat0::COMMAND_ERROR, 0, "Reset Errors at once");
}
