//! The move-profile maths of Reference 3 (seed 000), rule by rule (catalogue `rules/smd.md`, R3), with
//! every worked number of the manual.

use ds402::smd::profile::{
    jerk_for_half_constant, jerk_for_third_constant, jerk_for_triangular, MoveParams, MoveShape,
    Phase, PhaseShape, Profile, ProfileError,
};
use proptest::prelude::*;

/// Table R3.2: Acceleration 20, Deceleration 25, Starting Speed 141, Programmed Speed 100,000.
fn r3_2(distance: f64) -> MoveParams {
    MoveParams {
        start_speed: 141.0,
        speed: 100_000.0,
        accel: 20,
        decel: 25,
        jerk: 0,
        distance,
    }
}

fn close(got: f64, want: f64, tol: f64) {
    assert!((got - want).abs() <= tol, "got {got}, want {want} ± {tol}");
}

/// SMD-R3-001, SMD-R3-002, SMD-R3-007: T_A = (V_P − V_S)/a = 4.99295 s, T_D = (V_P − V_S)/d = 3.99436 s.
#[test]
fn smd_r3_001_002_007_times_to_accelerate_and_decelerate() {
    let p = Profile::plan(r3_2(1_000_000.0)).unwrap();
    close(p.accel.time, 99_859.0 / 20_000.0, 1e-12);
    close(p.decel.time, 99_859.0 / 25_000.0, 1e-12);
    // The manual's rounding.
    assert_eq!(format!("{:.3}", p.accel.time), "4.993");
    assert_eq!(format!("{:.3}", p.decel.time), "3.994");
    assert_eq!(p.accel.shape, PhaseShape::Linear);
}

/// SMD-R3-003, SMD-R3-008: D_A = 249,999.5, D_D = 199,999.6, threshold 449,999.1 steps — the formulas'
/// values, not the manual's 250,002 / 199,982 / 449,984, which come from multiplying the rounded times.
#[test]
fn smd_r3_003_008_distances_and_the_threshold() {
    let p = Profile::plan(r3_2(1_000_000.0)).unwrap();
    let da = (100_000f64.powi(2) - 141f64.powi(2)) / (2.0 * 20_000.0);
    let dd = (100_000f64.powi(2) - 141f64.powi(2)) / (2.0 * 25_000.0);
    close(p.accel.distance, da, 1e-6);
    close(p.decel.distance, dd, 1e-6);
    assert_eq!(format!("{:.1}", p.accel.distance), "249999.5");
    assert_eq!(format!("{:.1}", p.decel.distance), "199999.6");
    assert_eq!(format!("{:.1}", p.threshold), "449999.1");
    // 450,000 steps reach the programmed speed; 449,999 peak just below it.
    let trap = Profile::plan(r3_2(450_000.0)).unwrap();
    assert_eq!(trap.shape, MoveShape::Trapezoidal);
    assert_eq!(trap.peak_speed, 100_000.0);
    let tri = Profile::plan(r3_2(449_999.0)).unwrap();
    assert_eq!(tri.shape, MoveShape::Triangular);
    assert!(
        tri.peak_speed < 100_000.0 && tri.peak_speed > 99_999.0,
        "{}",
        tri.peak_speed
    );
    // Between the manual's 449,984 and the formulas' 449,999.1: triangular.
    assert_eq!(
        Profile::plan(r3_2(449_990.0)).unwrap().shape,
        MoveShape::Triangular
    );
}

/// SMD-R3-004, SMD-R3-010: trapezoidal with a cruise of D_P = length − (D_A + D_D) at V_P; the
/// total time T_P = T_A + T_D + D_P/V_P (1,000,000 steps: ≈ 14.487 s).
#[test]
fn smd_r3_004_010_trapezoid_cruise_and_total_time() {
    let p = Profile::plan(r3_2(1_000_000.0)).unwrap();
    assert_eq!(p.shape, MoveShape::Trapezoidal);
    close(p.cruise_distance, 1_000_000.0 - p.threshold, 1e-6);
    close(p.cruise_time, p.cruise_distance / 100_000.0, 1e-12);
    close(
        p.total_time(),
        4.99295 + 3.99436 + 550_000.9 / 100_000.0,
        1e-5,
    );
    assert_eq!(format!("{:.3}", p.total_time()), "14.487");
    close(p.total_distance(), 1_000_000.0, 1e-6);
}

/// SMD-R3-005: D_A + D_D equal to the length: triangular, peaking exactly at V_P.
#[test]
fn smd_r3_005_triangle_that_just_reaches_the_speed() {
    let exact = Profile::plan(r3_2(449_999.1)).unwrap().threshold;
    let p = Profile::plan(r3_2(exact)).unwrap();
    assert_eq!(p.shape, MoveShape::Triangular);
    assert_eq!(p.peak_speed, 100_000.0);
    assert_eq!(p.cruise_distance, 0.0);
}

/// SMD-R3-006, SMD-R3-009, SMD-R3-011: a 300,000-step move is triangular with V_M = 81,649.8 (manual
/// 81,650) and takes T_A + T_D ≈ 7.336 s. With a = d the equation reduces to (V_M² − V_S²)/a = L.
#[test]
fn smd_r3_006_009_011_triangle_peak_and_time() {
    let p = Profile::plan(r3_2(300_000.0)).unwrap();
    assert_eq!(p.shape, MoveShape::Triangular);
    assert_eq!(format!("{:.1}", p.peak_speed), "81649.8");
    assert_eq!(p.peak_speed.round(), 81_650.0);
    let vm = p.peak_speed;
    close(
        (vm * vm - 141.0 * 141.0) / 40_000.0 + (vm * vm - 141.0 * 141.0) / 50_000.0,
        300_000.0,
        1e-6,
    );
    close(
        p.total_time(),
        (vm - 141.0) / 20_000.0 + (vm - 141.0) / 25_000.0,
        1e-12,
    );
    assert_eq!(format!("{:.3}", p.total_time()), "7.336");
    // a = d.
    let same = Profile::plan(MoveParams {
        decel: 20,
        ..r3_2(300_000.0)
    })
    .unwrap();
    let v = same.peak_speed;
    close((v * v - 141.0 * 141.0) / 20_000.0, 300_000.0, 1e-6);
}

/// SMD-R3-012, SMD-R3-013: j = J·a/100 in each phase with its own a (J = 100, a = 20,000, d = 40,000:
/// the deceleration jerk is twice the acceleration jerk); J = 1 … 5000 spans 200 … 1,000,000 steps/s³.
#[test]
fn smd_r3_012_013_physical_jerk() {
    let p = Profile::plan(MoveParams {
        start_speed: 100.0,
        speed: 50_000.0,
        accel: 20,
        decel: 40,
        jerk: 100,
        distance: 1_000_000.0,
    })
    .unwrap();
    assert_eq!(p.accel.jerk, 20_000.0);
    assert_eq!(p.decel.jerk, 40_000.0);
    assert_eq!(Phase::new(0.0, 1000.0, 20_000.0, 1).jerk, 200.0);
    assert_eq!(Phase::new(0.0, 1000.0, 20_000.0, 5000).jerk, 1_000_000.0);
}

/// SMD-R3-014: an S-curve phase is symmetric: half-way through, the speed is V_S + Δv/2, and its
/// distance is T·(V_S + V_P)/2.
#[test]
fn smd_r3_014_s_curve_phases_are_symmetric() {
    for jerk in [20, 400, 5000] {
        let ph = Phase::new(141.0, 30_141.0, 58_000.0, jerk);
        close(ph.speed_rising(ph.time / 2.0), 15_141.0, 1e-6);
        close(ph.distance, ph.time * (141.0 + 30_141.0) / 2.0, 1e-9);
        close(ph.distance_rising(ph.time), ph.distance, 1e-6);
        // Speed is symmetric about the midpoint: v(t) + v(T − t) = V_S + V_P.
        for k in 0..=10 {
            let t = ph.time * f64::from(k) / 20.0;
            close(
                ph.speed_rising(t) + ph.speed_rising(ph.time - t),
                141.0 + 30_141.0,
                1e-6,
            );
        }
    }
}

/// SMD-R3-015, SMD-R3-017 (Example 1, Jerk = 20): Δv = 30,000, a = 58,000: j = 11,600, t = 1.608 s,
/// a_f = 18,655 ≤ a, a triangular S-curve of 3.216 s.
#[test]
fn smd_r3_015_017_example_1_triangular_s_curve() {
    let ph = Phase::new(0.0, 30_000.0, 58_000.0, 20);
    assert_eq!(ph.shape, PhaseShape::TriangularS);
    assert_eq!(ph.jerk, 11_600.0);
    assert_eq!(format!("{:.3}", ph.t1), "1.608");
    assert_eq!(ph.peak_accel.round(), 18_655.0);
    assert_eq!(format!("{:.3}", ph.time), "3.216");
    close(ph.time, 2.0 * (30_000.0f64 / 11_600.0).sqrt(), 1e-12);
    assert_eq!(ph.constant_share(), 0.0);
}

/// SMD-R3-016, SMD-R3-018 (Example 2, Jerk = 400): j = 232,000, a_f would be 83,427 > a, so a
/// trapezoidal S-curve: t1 = 0.25 s, S1 = 7,250, S2 = 7,750, t2 = 0.1336 s, 0.7672 s, 34.8 %.
#[test]
fn smd_r3_016_018_example_2_trapezoidal_s_curve() {
    let ph = Phase::new(0.0, 30_000.0, 58_000.0, 400);
    assert_eq!(ph.shape, PhaseShape::TrapezoidalS);
    assert_eq!(ph.jerk, 232_000.0);
    assert_eq!(
        ((15_000.0f64 / 116_000.0).sqrt() * 232_000.0).round(),
        83_427.0
    );
    assert_eq!(ph.t1, 0.25);
    assert_eq!(ph.s1(), 7_250.0);
    assert_eq!(15_000.0 - ph.s1(), 7_750.0);
    assert_eq!(format!("{:.4}", ph.t2), "0.1336");
    assert_eq!(format!("{:.4}", ph.time), "0.7672");
    assert_eq!(format!("{:.1}", 100.0 * ph.constant_share()), "34.8");
    assert_eq!(ph.peak_accel, 58_000.0);
    // The plateau is at exactly a.
    let (t_a, t_b) = (ph.t1 + 0.01, ph.t1 + 2.0 * ph.t2 - 0.01);
    close(
        (ph.speed_rising(t_b) - ph.speed_rising(t_a)) / (t_b - t_a),
        58_000.0,
        1e-6,
    );
}

/// SMD-R3-019, SMD-R3-020: J = 200/t is the ideal triangular S-curve; with a = 20,000 kept, a 2.0 s
/// linear phase (Δv = 40,000) takes 4.0 s with J = 50 = 200/4.0, peaking exactly at a. A smaller J
/// lengthens the phase; a larger one turns it trapezoidal.
#[test]
fn smd_r3_019_020_jerk_200_over_t() {
    assert_eq!(jerk_for_triangular(4.0), 50.0);
    let ph = Phase::new(0.0, 40_000.0, 20_000.0, 50);
    assert_eq!(ph.shape, PhaseShape::TriangularS);
    close(ph.time, 4.0, 1e-12);
    close(ph.peak_accel, 20_000.0, 1e-9);
    let slower = Phase::new(0.0, 40_000.0, 20_000.0, 40);
    assert_eq!(slower.shape, PhaseShape::TriangularS);
    assert!(slower.time > 4.0);
    let plateau = Phase::new(0.0, 40_000.0, 20_000.0, 60);
    assert_eq!(plateau.shape, PhaseShape::TrapezoidalS);
    assert!(plateau.time < 4.0 && plateau.t2 > 0.0);
}

/// SMD-R3-021, SMD-R3-023: J = 400/t gives half the phase at constant acceleration; 15,000 steps/s²
/// for 2.0 s becomes 2.667 s with J = 150. A smaller J shortens the plateau, a larger one lengthens it.
#[test]
fn smd_r3_021_023_jerk_400_over_t() {
    assert_eq!(jerk_for_half_constant(400.0 / 150.0), 150.0);
    let ph = Phase::new(0.0, 30_000.0, 15_000.0, 150);
    assert_eq!(ph.shape, PhaseShape::TrapezoidalS);
    assert_eq!(format!("{:.3}", ph.time), "2.667");
    close(ph.constant_share(), 0.5, 1e-12);
    let shorter = Phase::new(0.0, 30_000.0, 15_000.0, 120).constant_share();
    let longer = Phase::new(0.0, 30_000.0, 15_000.0, 200).constant_share();
    assert!(shorter < 0.5 && longer > 0.5, "{shorter} {longer}");
}

/// SMD-R3-022: J = 300/t gives a third of the phase at constant acceleration and 50 % more time than
/// the linear phase.
#[test]
fn smd_r3_022_jerk_300_over_t() {
    let linear = 30_000.0 / 15_000.0;
    let j = jerk_for_third_constant(1.5 * linear);
    assert_eq!(j, 100.0);
    let ph = Phase::new(0.0, 30_000.0, 15_000.0, j as u16);
    close(ph.time, 1.5 * linear, 1e-12);
    close(ph.constant_share(), 1.0 / 3.0, 1e-12);
}

/// SMD-R3-024: Acceleration = Deceleration gives mirror-image phases.
#[test]
fn smd_r3_024_equal_accel_and_decel_are_mirror_images() {
    let p = Profile::plan(MoveParams {
        start_speed: 141.0,
        speed: 30_000.0,
        accel: 58,
        decel: 58,
        jerk: 400,
        distance: 100_000.0,
    })
    .unwrap();
    assert_eq!(p.accel, p.decel);
    let total = p.total_time();
    for k in 0..=20 {
        let t = p.accel.time * f64::from(k) / 20.0;
        close(p.speed_at(t), p.speed_at(total - t), 1e-6);
    }
}

/// SMD-R3-025 (gap pick): an S-curve move too short for its phases peaks at the V_M whose phase
/// distances add up to the length.
#[test]
fn smd_r3_025_short_s_curve_move() {
    let p = Profile::plan(MoveParams {
        start_speed: 141.0,
        speed: 100_000.0,
        accel: 20,
        decel: 25,
        jerk: 50,
        distance: 100_000.0,
    })
    .unwrap();
    assert_eq!(p.shape, MoveShape::Triangular);
    assert!(p.peak_speed < 100_000.0);
    close(p.total_distance(), 100_000.0, 1e-3);
    close(p.position_at(p.total_time()), 100_000.0, 1e-3);
}

/// SMD-R3-025 (gap pick) with numbers worked by hand: V_S = 100, V_P = 2,100, Acceleration =
/// Deceleration = 1 (a = 1,000 steps/s²), Jerk 100 (j = 100·1,000/100 = 1,000 steps/s³), 2,400 steps.
/// At V_P each phase would be a trapezoidal S-curve of 3,300 steps (t₁ = a/j = 1 s, S₁ = 500,
/// t₂ = (1,000 − 500)/1,000 = 0.5 s, 3 s × 2,200/2), 6,600 for both: too long. At V_M = 1,100, Δv =
/// 1,000 = a²/j, so each phase is a triangular S-curve of 2√(Δv/j) = 2 s covering 2 s × (100 +
/// 1,100)/2 = 1,200 steps, 2,400 for both: the peak is exactly 1,100 steps/s and the move takes 4 s.
#[test]
fn smd_r3_025_short_s_curve_peak_worked_by_hand() {
    let p = Profile::plan(MoveParams {
        start_speed: 100.0,
        speed: 2_100.0,
        accel: 1,
        decel: 1,
        jerk: 100,
        distance: 2_400.0,
    })
    .unwrap();
    assert_eq!(p.threshold, 6_600.0);
    assert_eq!(p.shape, MoveShape::Triangular);
    close(p.peak_speed, 1_100.0, 1e-9);
    assert_eq!(p.accel.shape, PhaseShape::TriangularS);
    close(p.accel.time, 2.0, 1e-9);
    close(p.accel.distance, 1_200.0, 1e-6);
    close(p.decel.distance, 1_200.0, 1e-6);
    close(p.total_time(), 4.0, 1e-9);
}

/// SMD-R5-003: the starting speed is at least 1 step/s; a profile from a starting speed of 0 or
/// below is refused and says so (a programmed speed at or above it does not make it valid).
#[test]
fn smd_r5_003_profile_refuses_a_starting_speed_not_above_0() {
    for (start, text) in [
        (0.0, "starting speed 0 steps/s is not above 0"),
        (-1.0, "starting speed -1 steps/s is not above 0"),
    ] {
        let got = Profile::plan(MoveParams {
            start_speed: start,
            speed: 1_000.0,
            ..r3_2(10_000.0)
        });
        assert_eq!(got, Err(ProfileError::StartSpeed(start)));
        assert_eq!(got.unwrap_err().to_string(), text);
    }
    // The lowest valid starting speed plans.
    let p = Profile::plan(MoveParams {
        start_speed: 1.0,
        speed: 1_000.0,
        ..r3_2(10_000.0)
    })
    .unwrap();
    assert_eq!(p.shape, MoveShape::Trapezoidal);
}

/// The chart of `smd profile --plot`: n + 1 samples (time, speed) at k·T/n. Worked by hand: V_S =
/// 1,000, V_P = 3,000, Acceleration = Deceleration = 1 (1,000 steps/s²): each phase 2 s and
/// 2 × 4,000/2 = 4,000 steps; 14,000 steps leave 6,000 at 3,000 steps/s, 2 s; T = 6 s. Four
/// intervals: t = 0, 1.5, 3, 4.5, 6 s at 1,000, 2,500, 3,000, 2,500, 1,000 steps/s. A count of 0
/// gives one interval (start and end).
#[test]
fn speed_samples_of_a_worked_trapezoid() {
    let p = Profile::plan(MoveParams {
        start_speed: 1_000.0,
        speed: 3_000.0,
        accel: 1,
        decel: 1,
        jerk: 0,
        distance: 14_000.0,
    })
    .unwrap();
    assert_eq!(p.total_time(), 6.0);
    assert_eq!(
        p.speed_samples(4),
        vec![
            (0.0, 1_000.0),
            (1.5, 2_500.0),
            (3.0, 3_000.0),
            (4.5, 2_500.0),
            (6.0, 1_000.0),
        ]
    );
    assert_eq!(p.speed_samples(0), vec![(0.0, 1_000.0), (6.0, 1_000.0)]);
}

#[test]
fn refused_parameters_name_the_fault() {
    let bad = |m: MoveParams| Profile::plan(m).unwrap_err().to_string();
    assert_eq!(
        bad(MoveParams {
            accel: 0,
            ..r3_2(1.0)
        }),
        "acceleration 0 is outside 1 to 5000 steps/s/ms"
    );
    assert_eq!(
        bad(MoveParams {
            decel: 5001,
            ..r3_2(1.0)
        }),
        "deceleration 5001 is outside 1 to 5000 steps/s/ms"
    );
    assert_eq!(
        bad(MoveParams {
            jerk: 5001,
            ..r3_2(1.0)
        }),
        "jerk 5001 is outside 0 to 5000"
    );
    assert!(matches!(
        Profile::plan(MoveParams {
            speed: 100.0,
            ..r3_2(1.0)
        }),
        Err(ProfileError::Speed { .. })
    ));
    assert_eq!(
        bad(MoveParams {
            distance: f64::NAN,
            ..r3_2(1.0)
        }),
        "distance is not a finite number"
    );
}

#[test]
fn printed_table() {
    let text = Profile::plan(r3_2(300_000.0)).unwrap().to_string();
    assert!(
        text.contains("triangular, below the programmed speed"),
        "{text}"
    );
    assert!(text.contains("peak 81649.8 steps/s"), "{text}");
    assert!(text.contains("acceleration  linear"), "{text}");
}

proptest! {
    /// Any valid move: the phases and cruise add up to the length, the speed never exceeds the
    /// programmed speed nor falls below the starting speed, and position rises monotonically from 0 to
    /// the length.
    #[test]
    fn profiles_are_consistent(
        vs in 1.0f64..5_000.0,
        extra in 0.0f64..200_000.0,
        accel in 1u16..=5000,
        decel in 1u16..=5000,
        jerk in prop_oneof![Just(0u16), 1u16..=5000],
        distance in 0.0f64..2_000_000.0,
    ) {
        let p = Profile::plan(MoveParams { start_speed: vs, speed: vs + extra, accel, decel, jerk, distance }).unwrap();
        prop_assert!((p.total_distance() - distance).abs() <= 1e-6 * distance.max(1.0) + 1e-3);
        prop_assert!(p.peak_speed <= vs + extra + 1e-9);
        let total = p.total_time();
        let mut last = 0.0;
        for k in 0..=50 {
            let t = total * f64::from(k) / 50.0;
            let v = p.speed_at(t);
            prop_assert!(v >= vs - 1e-6 && v <= p.peak_speed + 1e-6, "v {} at {}", v, t);
            let x = p.position_at(t);
            // Position is the integral of the speed: the central difference over [t - h, t + h] is
            // the mean speed over that window, which differs from v(t) by at most A·h/2 where A is
            // the largest acceleration (steps/s/ms × 1000 in steps/s²), also across a phase corner.
            let h = 1e-4 * total.max(1e-3);
            if t > h && t < total - h {
                let dx = (p.position_at(t + h) - p.position_at(t - h)) / (2.0 * h);
                let a = f64::from(accel.max(decel)) * 1000.0;
                prop_assert!((dx - v).abs() <= a * h / 2.0 + 1e-6 * v + 1.0, "dx/dt {} vs v {} at {}", dx, v, t);
            }
            prop_assert!(x >= last - 1e-6, "position went back at {}", t);
            last = x;
        }
        prop_assert!((p.position_at(total) - distance).abs() <= 1e-6 * distance.max(1.0) + 1e-3);
    }
}
