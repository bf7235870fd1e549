//! The move-profile equations of Reference 3 as a master sees them: Relative moves run on the unit and
//! measured from STATUS_word0 (Accelerating, Decelerating, Stopped) and Motor_Position alone, against
//! the manual's figures worked out here by hand. `smd_profile.rs` checks the calculator
//! (`ds402::smd::profile`) with the same equations; these check that the drive moves by them.

mod smd_rig;

use ds402::smd::indexer::{cmd0, stat0};
use smd_rig::Rig;

/// V_S, the default Starting_Speed (8010:03), steps/s.
const VS: f64 = 141.0;

/// What one Relative move looked like, in 1 ms cycles.
#[derive(Debug)]
struct Seen {
    /// Cycles with Accelerating, with neither bit while moving, with Decelerating.
    accel_ms: usize,
    cruise_ms: usize,
    decel_ms: usize,
    /// Cycles with Stopped = 0.
    moving_ms: usize,
    /// Motor_Position gained while Accelerating.
    accel_steps: i32,
    /// The largest gain in one cycle (the peak speed in steps/ms).
    peak: i32,
    /// The gain in the cycle at half the acceleration time.
    mid_accel: i32,
    /// The phases in order: 'A', 'C', 'D'.
    order: String,
}

/// Runs a Relative move of `length` with Velocity `v`, Acceleration `a`, Deceleration `d` (× 1000
/// steps/s²) and Jerk `j`, and measures it.
fn relative(length: i32, v: u32, a: u16, d: u16, j: u16) -> Seen {
    let cycles = trace(length, v, a, d, j);
    let mut before = 0;
    let mut seen = Seen {
        accel_ms: 0,
        cruise_ms: 0,
        decel_ms: 0,
        moving_ms: 0,
        accel_steps: 0,
        peak: 0,
        mid_accel: 0,
        order: String::new(),
    };
    let mut accel_gains = Vec::new();
    for &(s, p) in &cycles {
        let gain = p - before;
        before = p;
        if s & stat0::STOPPED != 0 {
            continue;
        }
        seen.moving_ms += 1;
        seen.peak = seen.peak.max(gain);
        let phase = if s & stat0::ACCELERATING != 0 {
            seen.accel_ms += 1;
            seen.accel_steps += gain;
            accel_gains.push(gain);
            'A'
        } else if s & stat0::DECELERATING != 0 {
            seen.decel_ms += 1;
            'D'
        } else {
            seen.cruise_ms += 1;
            'C'
        };
        if !seen.order.ends_with(phase) {
            seen.order.push(phase);
        }
    }
    seen.mid_accel = accel_gains[accel_gains.len() / 2];
    seen
}

/// The same move as (STATUS_word0, Motor_Position) of every update from the command's on, the last
/// one the first with Stopped.
fn trace(length: i32, v: u32, a: u16, d: u16, j: u16) -> Vec<(u16, i32)> {
    let mut r = Rig::ready_with(0, v, a, d);
    r.out.jerk = j;
    r.out.position = length;
    r.command(cmd0::RELATIVE_MOVE);
    let mut cycles = vec![(r.last.status0, r.pos())];
    for _ in 0..100_000 {
        let i = r.cycle();
        cycles.push((i.status0, i.motor_position));
        if i.status0 & stat0::STOPPED != 0 {
            break;
        }
    }
    assert_eq!(r.pos(), length, "the move ends on target");
    cycles
}

/// Asserts that a duration measured in 1 ms cycles is `expected` seconds, to within 2 ms.
#[track_caller]
fn assert_ms(measured: usize, expected: f64, what: &str) {
    assert!(
        (measured as f64 - expected * 1000.0).abs() <= 2.0,
        "{what}: {measured} ms, expected {:.1} ms",
        expected * 1000.0
    );
}

/// SMD-R3-001, SMD-R3-002, SMD-R3-003, SMD-R3-004, SMD-R3-007, SMD-R3-010: the manual's example
/// (Acceleration 20,
/// Deceleration 25, V_S 141, Velocity 100,000) as a 600,000-step Relative move: T_A = 99,859 / 20,000
/// = 4.99295 s, T_D = 99,859 / 25,000 = 3.99436 s, D_A = (100,000² − 141²) / 40,000 = 249,999.5 steps,
/// D_D = 199,999.6, a cruise of 600,000 − 449,999.1 = 150,000.9 steps at 100 steps/ms (1.50001 s),
/// T_P = 10.48732 s.
#[test]
fn smd_r3_001_to_004_007_010_trapezoid() {
    let s = relative(600_000, 100_000, 20, 25, 0);
    assert_eq!(s.order, "ACD", "{s:?}");
    assert_ms(s.accel_ms, 4.99295, "T_A");
    assert_ms(s.decel_ms, 3.99436, "T_D");
    assert_ms(s.cruise_ms, 1.50001, "cruise");
    assert_ms(s.moving_ms, 10.48732, "T_P");
    assert!(
        (s.accel_steps - 249_999).abs() <= 100,
        "D_A {}",
        s.accel_steps
    );
    assert_eq!(s.peak, 100, "V_P = 100 steps/ms");
}

/// SMD-R3-006, SMD-R3-009, SMD-R3-011: the same parameters over 300,000 steps, less than D_A + D_D:
/// a triangle peaking at V_M = √((300,000 · 2 · 20,000 · 25,000 / 45,000) + 141²) = 81,649.8 steps/s,
/// T_A = 81,508.8 / 20,000 = 4.07544 s, T_D = 81,508.8 / 25,000 = 3.26035 s, T_P = 7.33579 s, with no
/// cruise.
#[test]
fn smd_r3_006_009_011_triangle() {
    let s = relative(300_000, 100_000, 20, 25, 0);
    assert_eq!(s.order, "AD", "{s:?}");
    assert_ms(s.accel_ms, 4.07544, "T_A");
    assert_ms(s.decel_ms, 3.26035, "T_D");
    assert_ms(s.moving_ms, 7.33579, "T_P");
    assert!((81..=82).contains(&s.peak), "V_M {} steps/ms", s.peak);
}

/// SMD-R3-005, SMD-R3-024: a move exactly D_A + D_D long with Acceleration = Deceleration = 20 and
/// Velocity 20,141: (20,141² − 141²) / 40,000 = 10,141 steps each way, 20,282 in all. It just reaches
/// V_P, 1.000 s up and 1.000 s down, mirror images, with no time at V_P: T_P = 2.000 s.
///
/// Each status word tells the phase at the instant its cycle ends (the model's pick): the move starts
/// in the command's cycle, so the updates at 1 … 999 ms show Accelerating, the one at 1.000 s (full
/// speed, the deceleration's first instant) and those up to 1.999 s Decelerating, and the one at
/// 2.000 s Stopped: 999 + 1000 updates in motion, none at V_P alone.
#[test]
fn smd_r3_005_024_just_reaching_velocity() {
    let s = relative(20_282, 20_141, 20, 20, 0);
    assert_eq!(s.order, "AD", "{s:?}");
    assert_eq!(s.accel_ms, 999, "{s:?}");
    assert_eq!(s.decel_ms, 1000, "{s:?}");
    assert_eq!(s.cruise_ms, 0, "{s:?}");
    assert_eq!(s.moving_ms, 1999, "{s:?}");
    assert!((20..=21).contains(&s.peak), "{s:?}");
}

/// The time of one S-curve speed change of `dv` steps/s at `a` steps/s² with Jerk word `jerk`, by the
/// equations of R3 "Determining Waveforms by Values": j = J·a/100; triangular (2√(Δv/j)) when
/// Δv ≤ a²/j, else trapezoidal: t1 = a/j, S1 = j·t1²/2, t2 = (Δv/2 − S1)/a, T = 2(t1 + t2).
fn s_curve_seconds(dv: f64, a: f64, jerk: f64) -> f64 {
    let j = jerk * a / 100.0;
    if dv <= a * a / j {
        2.0 * (dv / j).sqrt()
    } else {
        let t1 = a / j;
        let s1 = j * t1 * t1 / 2.0;
        2.0 * (t1 + (dv / 2.0 - s1) / a)
    }
}

/// SMD-R3-012, SMD-R3-013, SMD-R3-014, SMD-R3-015, SMD-R3-016, SMD-R3-017, SMD-R3-018, SMD-R3-019,
/// SMD-R3-020, SMD-R3-021, SMD-R3-022: S-curve phases on the unit, each against the manual's
/// figures:
/// - Example 1 (R3-017): Δv 30,000, Acceleration 58, J 20: triangular, 3.216 s;
/// - Example 2 (R3-018): J 400: trapezoidal, 0.7672 s;
/// - R3-013: Acceleration 20, Deceleration 40, J 100, Δv 10,000: 1.4142 s up, 1.000 s down;
/// - R3-019, R3-020: 20,000 steps/s² for 2.0 s (Δv 40,000) with J = 200/4 = 50: 4.0 s, no plateau;
/// - R3-021: 15,000 steps/s² for 2.0 s (Δv 30,000) with J = 400/2 = 150: 2.667 s;
/// - R3-022: the same with J = 300/3 = 100: 3.0 s, 50 % over the linear 2.0 s;
/// - R3-014: at half the acceleration time the speed is V_S + Δv/2.
#[test]
fn smd_r3_012_to_022_s_curves() {
    // (rule, Δv, Acceleration, Deceleration, J, up s, down s)
    let cases = [
        ("SMD-R3-017", 30_000.0, 58, 58, 20, 3.216, 3.216),
        ("SMD-R3-018", 30_000.0, 58, 58, 400, 0.7672, 0.7672),
        (
            "SMD-R3-013",
            10_000.0,
            20,
            40,
            100,
            std::f64::consts::SQRT_2,
            1.0,
        ),
        ("SMD-R3-020", 40_000.0, 20, 20, 50, 4.0, 4.0),
        ("SMD-R3-021", 30_000.0, 15, 15, 150, 2.66667, 2.66667),
        ("SMD-R3-022", 30_000.0, 15, 15, 100, 3.0, 3.0),
    ];
    for (rule, dv, a, d, jerk, up, down) in cases {
        // The manual's figure and the equations agree.
        let by_eq = s_curve_seconds(dv, f64::from(a) * 1000.0, f64::from(jerk));
        assert!((by_eq - up).abs() < 0.0006, "{rule}: {by_eq}");
        let v = (VS + dv) as u32;
        // Long enough to cruise: each phase covers (V_S + Δv/2)·T steps.
        let s = relative(200_000, v, a, d, jerk);
        assert_eq!(s.order, "ACD", "{rule}: {s:?}");
        assert_ms(s.accel_ms, up, rule);
        assert_ms(s.decel_ms, down, rule);
        let mid = (VS + dv / 2.0) / 1000.0;
        assert!(
            (f64::from(s.mid_accel) - mid).abs() <= 1.0,
            "{rule}: {} at mid-phase, {mid}",
            s.mid_accel
        );
    }
}

/// SMD-R3-023: in a trapezoidal S-curve a Jerk below 400/t shortens the constant-acceleration part,
/// one above lengthens it. 15,000 steps/s² over Δv = 30,000 (t = 2.0 s linear, 400/t = 200): by the
/// R3 equations j = J·a/100, t1 = a/j = 100/J s, S1 = j·t1²/2, t2 = (Δv/2 − S1)/a, T = 2(t1 + t2),
/// plateau 2·t2:
/// - J 120: t1 0.8333 s, S1 6,250, t2 0.5833 s, T 2.8333 s, plateau 1.1667 s (41.2 %);
/// - J 150: t1 0.6667 s, S1 5,000, t2 0.6667 s, T 2.6667 s, plateau 1.3333 s (50.0 %);
/// - J 200: t1 0.5 s, S1 3,750, t2 0.75 s, T 2.5 s, plateau 1.5 s (60.0 %).
///
/// Measured on the unit from Motor_Position alone: the speed over ±20 ms at t1 is V_S + j·t1²/2 (the
/// jerk phase's gain), at T − t1 it is V_S + Δv − j·t1²/2, and between the two it rises at exactly
/// 15,000 steps/s², so the plateau is T − 2·t1 of the Accelerating time T counted from STATUS_word0.
#[test]
fn smd_r3_023_plateau_share_rises_with_jerk() {
    let mut shares = Vec::new();
    for (jerk, t1, t_a, share) in [
        (120, 0.83333, 2.83333, 0.41176),
        (150, 0.66667, 2.66667, 0.5),
        (200, 0.5, 2.5, 0.6),
    ] {
        let cycles = trace(200_000, 30_141, 15, 15, jerk);
        // Update n (from 1, the command's) is at n ms of motion.
        let accel_ms = cycles
            .iter()
            .filter(|(s, _)| s & stat0::ACCELERATING != 0)
            .count();
        assert_ms(accel_ms, t_a, "T_A");
        let pos = |ms: f64| f64::from(cycles[ms.round() as usize - 1].1);
        let speed = |t: f64| (pos(t * 1000.0 + 20.0) - pos(t * 1000.0 - 20.0)) / 0.040;
        let j = f64::from(jerk) * 15_000.0 / 100.0;
        let gained = j * t1 * t1 / 2.0;
        let (at_t1, at_end) = (speed(t1), speed(t_a - t1));
        // ±0.5 step at each end of a 40 ms window: ±25 steps/s; the window's own curvature at
        // the plateau's edges adds j·(0.02 s)²/6 ≈ 2 steps/s at most.
        assert!(
            (at_t1 - (VS + gained)).abs() < 30.0,
            "J {jerk}: {at_t1} at t1"
        );
        assert!(
            (at_end - (VS + 30_000.0 - gained)).abs() < 30.0,
            "J {jerk}: {at_end} at T - t1"
        );
        let plateau = t_a - 2.0 * t1;
        let rate = (at_end - at_t1) / plateau;
        assert!((rate - 15_000.0).abs() < 60.0, "J {jerk}: {rate} steps/s²");
        assert!((plateau / t_a - share).abs() < 1e-4, "J {jerk}");
        // The measured share: plateau over the Accelerating time the status word showed.
        shares.push(plateau / (accel_ms as f64 / 1000.0));
    }
    assert!(shares[0] < shares[1] && shares[1] < shares[2], "{shares:?}");
}

/// SMD-R3-025 (gap pick): an S-curve move too short to reach its Velocity peaks at the V_M whose two
/// phases cover the length. 100,000 steps, V_S 141, Velocity 100,000, Acceleration 20, Deceleration
/// 25, J 50: j = 10,000 and 12,500 steps/s³, both phases triangular (Δv below a²/j = 40,000 and
/// 50,000), each covering (V_S + Δv/2)·2√(Δv/j). Solved here by bisection: Δv = 30,129.0, V_M =
/// 30,270.0 steps/s, T_A = 3.4715 s, T_D = 3.1050 s, T_P = 6.5766 s.
#[test]
fn smd_r3_025_short_s_curve_move() {
    let (ja, jd) = (10_000.0_f64, 12_500.0_f64);
    let covered = |dv: f64| (VS + dv / 2.0) * 2.0 * ((dv / ja).sqrt() + (dv / jd).sqrt());
    let (mut lo, mut hi) = (0.0, 100_000.0);
    for _ in 0..100 {
        let mid = (lo + hi) / 2.0;
        if covered(mid) < 100_000.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    assert!((lo - 30_129.0).abs() < 0.1, "{lo}");
    let (t_a, t_d) = (2.0 * (lo / ja).sqrt(), 2.0 * (lo / jd).sqrt());
    let s = relative(100_000, 100_000, 20, 25, 50);
    assert_eq!(s.order, "AD", "{s:?}");
    assert_ms(s.accel_ms, t_a, "T_A");
    assert_ms(s.decel_ms, t_d, "T_D");
    assert_ms(s.moving_ms, t_a + t_d, "T_P");
    // V_M = 30.27 steps/ms: whole-step gains of 30 or 31 at the top.
    assert!((30..=31).contains(&s.peak), "{s:?}");
}
