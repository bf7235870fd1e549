//! Tests of the X67SM2436 ramp generator against the rule catalogue, sections 18.11.1.3 to 18.11.1.6,
//! 18.11.1.14 and 18.11.1.15. Each test names the rules it covers; positions and speeds are asserted cycle by
//! cycle where the catalogue gives numbers.

use ds402::x67::ramp::{Config, Cycle, Ramp, RampState, Target, MAX_SPEED_SETPOINT};
use proptest::prelude::*;

fn cfg(max_speed_pos: u16, max_acc: u16, max_dec: u16) -> Config {
    Config {
        max_speed_pos,
        max_acc,
        max_dec,
        ..Config::default()
    }
}

fn run(ramp: &mut Ramp, cycles: usize) -> Vec<RampState> {
    (0..cycles).map(|_| ramp.step()).collect()
}

fn positions(states: &[RampState]) -> Vec<i64> {
    states.iter().map(|s| s.position).collect()
}

fn speeds(states: &[RampState]) -> Vec<i32> {
    states.iter().map(|s| s.speed).collect()
}

/// Runs until the target is reached (at most `limit` cycles) and returns every state on the way.
fn until_reached(ramp: &mut Ramp, limit: usize) -> Vec<RampState> {
    let mut out = Vec::new();
    for _ in 0..limit {
        let s = ramp.step();
        out.push(s);
        if s.target_reached {
            return out;
        }
    }
    panic!("target not reached in {limit} cycles: {:?}", out.last());
}

/// X67-18.11.1.3-01, X67-18.11.1.4-01, X67-18.11.1.5-01: a trapezoidal move accelerates by MaxAcc, cruises at
/// exactly MaxSpeed, brakes by MaxDec and stops exactly on the target.
#[test]
fn trapezoidal_move_cycle_by_cycle() {
    let mut ramp = Ramp::new(cfg(20, 10, 5));
    ramp.set_target(Target::Position(80));
    let states = run(&mut ramp, 8);
    assert_eq!(positions(&states), [10, 30, 50, 65, 75, 80, 80, 80]);
    assert_eq!(speeds(&states), [10, 20, 20, 15, 10, 5, 0, 0]);
    let flags: Vec<(bool, bool)> = states
        .iter()
        .map(|s| (s.accelerating, s.decelerating))
        .collect();
    assert_eq!(
        flags,
        [
            (true, false),
            (true, false),
            (false, false),
            (false, true),
            (false, true),
            (false, true),
            (false, true),
            (false, false)
        ]
    );
    assert!(!states[5].target_reached);
    assert!(states[6].target_reached && states[6].standstill);
}

/// X67-18.11.1.4-01, X67-18.11.1.5-01: a triangular move (MaxSpeed never reached) whose distance is no sum of
/// whole ramp steps still stops exactly on the target; the last braking steps are shortened.
#[test]
fn triangular_move_cycle_by_cycle() {
    let mut ramp = Ramp::new(cfg(100, 10, 10));
    ramp.set_target(Target::Position(90));
    assert_eq!(positions(&run(&mut ramp, 6)), [10, 30, 60, 80, 90, 90]);

    let mut ramp = Ramp::new(cfg(100, 10, 10));
    ramp.set_target(Target::Position(95));
    let states = run(&mut ramp, 7);
    assert_eq!(positions(&states), [10, 30, 60, 81, 93, 95, 95]);
    assert!(states[6].target_reached);
}

/// X67-18.11.1.4-01, X67-18.11.1.5-01: negative moves mirror positive ones.
#[test]
fn negative_move_mirrors() {
    let mut ramp = Ramp::at(cfg(20, 10, 5), 1000);
    ramp.set_target(Target::Position(920));
    assert_eq!(
        positions(&run(&mut ramp, 7)),
        [990, 970, 950, 935, 925, 920, 920]
    );
}

/// X67-18.11.1.3-01 gap, X67-18.11.1.4-01 gap, X67-18.11.1.5-01 gap: with MaxSpeed, MaxAcc or MaxDec at the
/// default 0 a positioning move does not start and the target is not reported as reached.
#[test]
fn zero_limits_do_not_start() {
    for c in [
        cfg(0, 10, 10),
        cfg(10, 0, 10),
        cfg(10, 10, 0),
        Config::default(),
    ] {
        let mut ramp = Ramp::new(c);
        ramp.set_target(Target::Position(500));
        for s in run(&mut ramp, 20) {
            assert_eq!(
                (s.position, s.speed, s.target_reached),
                (0, 0, false),
                "{c:?}"
            );
        }
    }
}

/// X67-18.11.1.15-02, X67-18.11.1.15-04: GeneralConfig01 bits 1–2 give 25/10/5 ms, 11 reads as 25 ms, bit 0
/// and bits 3–7 do not change the cycle.
#[test]
fn cycle_from_general_config() {
    assert_eq!(Cycle::from_general_config(0b000), Cycle::Ms25);
    assert_eq!(Cycle::from_general_config(0b010), Cycle::Ms10);
    assert_eq!(Cycle::from_general_config(0b100), Cycle::Ms5);
    assert_eq!(Cycle::from_general_config(0b110), Cycle::Ms25);
    assert_eq!(Cycle::from_general_config(0b001), Cycle::Ms25);
    assert_eq!(Cycle::from_general_config(0xF9), Cycle::Ms25);
    assert_eq!(Cycle::from_general_config(0xFB), Cycle::Ms10);
    assert_eq!(Cycle::from_general_config(0xFD), Cycle::Ms5);
    assert_eq!(
        [
            Cycle::Ms25.millis(),
            Cycle::Ms10.millis(),
            Cycle::Ms5.millis()
        ],
        [25, 10, 5]
    );
    assert_eq!(Cycle::default(), Cycle::Ms25);
}

/// X67-18.11.1.15-02, X67-18.11.1.15-03: speeds are per cycle, so speed 10 at 10 ms is 1000 microsteps per
/// second, and MaxSpeed 100 is 4000 microsteps/s at 25 ms and 20 000 at 5 ms.
#[test]
fn cycle_is_the_time_base() {
    let cycle = Cycle::from_general_config(0b010);
    let mut ramp = Ramp::new(Config {
        cycle,
        max_acc: 1000,
        max_dec: 1000,
        ..Config::default()
    });
    ramp.set_target(Target::Speed(10));
    let one_second = (1000 / cycle.millis()) as usize;
    assert_eq!(run(&mut ramp, one_second).last().unwrap().position, 1000);
    assert_eq!(Cycle::Ms25.per_second(100), 4000);
    assert_eq!(Cycle::Ms5.per_second(100), 20_000);
}

/// X67-18.11.1.6-02, X67-18.11.1.6-03 (pick a): RevLoop +500, a move from 0 to 10 000 overshoots to 10 500,
/// stops there and comes back; target reached only on the final arrival. A move from 20 000 to 10 000 goes
/// straight there.
#[test]
fn reversing_loop_positive() {
    let c = Config {
        rev_loop: 500,
        ..cfg(1000, 100, 100)
    };
    let mut ramp = Ramp::new(c);
    ramp.set_target(Target::Position(10_000));
    let states = until_reached(&mut ramp, 1000);
    let max = states.iter().map(|s| s.position).max().unwrap();
    assert_eq!(max, 10_500);
    let turn = states.iter().position(|s| s.position == 10_500).unwrap();
    assert_eq!(states[turn + 1].speed, 0, "stops at the loop point");
    assert!(states[..states.len() - 1].iter().all(|s| !s.target_reached));
    assert_eq!(states.last().unwrap().position, 10_000);
    assert!(
        states[turn + 2..].iter().all(|s| s.speed <= 0),
        "final approach runs negative"
    );

    let mut ramp = Ramp::at(c, 20_000);
    ramp.set_target(Target::Position(10_000));
    let states = until_reached(&mut ramp, 1000);
    assert!(
        states.iter().all(|s| s.position >= 10_000 && s.speed <= 0),
        "direct approach"
    );
}

/// X67-18.11.1.6-02, X67-18.11.1.6-03 (pick a): RevLoop −500 loops on negative moves: from 20 000 to 10 000
/// the axis goes to 9 500 and back; from 0 it goes straight to 10 000.
#[test]
fn reversing_loop_negative() {
    let c = Config {
        rev_loop: -500,
        ..cfg(1000, 100, 100)
    };
    let mut ramp = Ramp::at(c, 20_000);
    ramp.set_target(Target::Position(10_000));
    let states = until_reached(&mut ramp, 1000);
    assert_eq!(states.iter().map(|s| s.position).min(), Some(9_500));
    assert_eq!(states.last().unwrap().position, 10_000);

    let mut ramp = Ramp::new(c);
    ramp.set_target(Target::Position(10_000));
    let states = until_reached(&mut ramp, 1000);
    assert!(
        states.iter().all(|s| s.position <= 10_000 && s.speed >= 0),
        "direct approach"
    );
}

/// X67-18.11.1.6-02, X67-18.11.1.14-01: with the jerk FIFO on, the axis still stands (output speed 0) at the
/// loop point before it turns back, and ends exactly on the target.
#[test]
fn reversing_loop_with_jerk_fifo() {
    let c = Config {
        rev_loop: 300,
        jolt_time: 5,
        ..cfg(200, 20, 20)
    };
    let mut ramp = Ramp::new(c);
    ramp.set_target(Target::Position(3000));
    let states = until_reached(&mut ramp, 2000);
    let turn = states
        .iter()
        .position(|s| s.position == 3300)
        .expect("reaches the loop point");
    assert_eq!(states[turn + 1].speed, 0, "stands at the loop point");
    assert!(states[..=turn].iter().all(|s| s.speed >= 0));
    assert!(states[turn + 1..]
        .iter()
        .all(|s| s.speed <= 0 && s.position <= 3300));
    assert_eq!(states.last().unwrap().position, 3000);
    assert_eq!(states.iter().filter(|s| s.target_reached).count(), 1);
}

/// X67-18.11.1.6-01: with RevLoop 0 every target is approached directly, from both sides.
#[test]
fn no_reversing_loop_by_default() {
    for (start, target) in [(0, 5000), (5000, 0)] {
        let mut ramp = Ramp::at(cfg(100, 10, 10), start);
        ramp.set_target(Target::Position(target));
        let states = until_reached(&mut ramp, 500);
        let (lo, hi) = (start.min(target), start.max(target));
        assert!(states.iter().all(|s| (lo..=hi).contains(&s.position)));
    }
}

/// X67-18.11.1.6-01, X67-18.11.1.3-02: in speed mode neither the reversing loop nor MaxSpeed apply.
#[test]
fn speed_mode_ignores_rev_loop_and_max_speed() {
    let mut ramp = Ramp::new(Config {
        rev_loop: 1000,
        ..cfg(10, 100, 100)
    });
    ramp.set_target(Target::Speed(500));
    let states = run(&mut ramp, 6);
    assert_eq!(speeds(&states), [100, 200, 300, 400, 500, 500]);
}

/// X67-18.11.1.4-01, X67-18.11.1.5-01: speed mode ramps up by MaxAcc, down by MaxDec, and through zero into the
/// other direction; the set-point is clamped to ±65 535.
#[test]
fn speed_mode_ramps_and_clamps() {
    let mut ramp = Ramp::new(cfg(0, 30, 20));
    ramp.set_target(Target::Speed(70));
    assert_eq!(speeds(&run(&mut ramp, 4)), [30, 60, 70, 70]);
    ramp.set_target(Target::Speed(-50));
    assert_eq!(speeds(&run(&mut ramp, 7)), [50, 30, 10, 0, -30, -50, -50]);

    let mut ramp = Ramp::new(cfg(0, 65_535, 65_535));
    ramp.set_target(Target::Speed(100_000));
    assert_eq!(ramp.target(), Target::Speed(MAX_SPEED_SETPOINT));
    assert_eq!(speeds(&run(&mut ramp, 3)), [65_535, 65_535, 65_535]);
    ramp.set_target(Target::Speed(i32::MIN));
    assert_eq!(speeds(&run(&mut ramp, 3)), [0, -65_535, -65_535]);
}

/// X67-18.11.1.5-01 (and its gap): Stop brakes with MaxDec to standstill; with MaxDec 0 it stops within one
/// cycle.
#[test]
fn stop_brakes_with_max_dec() {
    let mut ramp = Ramp::new(cfg(0, 100, 30));
    ramp.set_target(Target::Speed(100));
    run(&mut ramp, 1);
    ramp.set_target(Target::Stop);
    let states = run(&mut ramp, 5);
    assert_eq!(speeds(&states), [70, 40, 10, 0, 0]);
    assert_eq!(positions(&states), [170, 210, 220, 220, 220]);
    assert!(states[3].standstill && !states[3].target_reached);

    let mut ramp = Ramp::new(cfg(0, 100, 0));
    ramp.set_target(Target::Speed(100));
    run(&mut ramp, 1);
    ramp.set_target(Target::Stop);
    assert_eq!(speeds(&run(&mut ramp, 2)), [0, 0]);
}

/// A new target during motion starts from the current position and speed; a target behind the axis is reached
/// after braking and reversing, exactly.
#[test]
fn retarget_during_motion() {
    let mut ramp = Ramp::new(cfg(50, 10, 10));
    ramp.set_target(Target::Position(10_000));
    let s = run(&mut ramp, 10);
    assert_eq!(s.last().unwrap().speed, 50);
    ramp.set_target(Target::Position(200));
    let states = until_reached(&mut ramp, 500);
    assert_eq!(states[0].speed, 40, "brakes from the current speed");
    assert_eq!(states.last().unwrap().position, 200);
}

/// X67-18.11.1.14-01: JoltTime 4 with MaxAcc 100 from standstill gives increments 25, 75, 150, 250, … (means of
/// the set-points 100, 200, 300, 400 with a FIFO that starts at 0).
#[test]
fn jerk_fifo_averages_four() {
    let mut ramp = Ramp::new(Config {
        jolt_time: 4,
        ..cfg(0, 100, 100)
    });
    ramp.set_target(Target::Speed(1000));
    let states = run(&mut ramp, 8);
    assert_eq!(speeds(&states), [25, 75, 150, 250, 350, 450, 550, 650]);
    assert_eq!(
        positions(&states),
        [25, 100, 250, 500, 850, 1300, 1850, 2500]
    );
}

/// X67-18.11.1.14-01 (gap pick: remainder carried): a position move with JoltTime 4 follows the averaged
/// set-points cycle by cycle and ends exactly on the target.
#[test]
fn jerk_fifo_position_move_exact() {
    let mut ramp = Ramp::new(Config {
        jolt_time: 4,
        ..cfg(100, 10, 10)
    });
    ramp.set_target(Target::Position(95));
    // Set-points 10, 20, 30, 21, 12, 2 (see triangular_move_cycle_by_cycle), then 0.
    let states = until_reached(&mut ramp, 50);
    // Windows: 10/4, 30/4, 60/4, 81/4, 83/4, 65/4, 35/4, 14/4, 2/4 with carried remainders.
    assert_eq!(speeds(&states), [2, 8, 15, 20, 21, 16, 9, 3, 1, 0]);
    assert_eq!(positions(&states), [2, 10, 25, 45, 66, 82, 91, 94, 95, 95]);
}

/// X67-18.11.1.14-02: JoltTime above 80 gives the same trajectory as 80.
#[test]
fn jolt_time_limited_to_80() {
    let run_with = |jolt_time| {
        let mut ramp = Ramp::new(Config {
            jolt_time,
            ..cfg(300, 7, 9)
        });
        ramp.set_target(Target::Position(20_000));
        run(&mut ramp, 300)
    };
    assert_eq!(run_with(200), run_with(80));
    assert_ne!(run_with(79), run_with(80));
    assert_eq!(run_with(200).last().unwrap().position, 20_000);
}

/// X67-18.11.1.14-03: JoltTime changed from 0 to 10 during a move: that move finishes unfiltered and the next
/// move is filtered.
#[test]
fn jolt_change_waits_for_standstill() {
    let c = cfg(100, 10, 10);
    let mut ramp = Ramp::new(c);
    ramp.set_target(Target::Position(2000));
    assert_eq!(speeds(&run(&mut ramp, 2)), [10, 20]);
    ramp.set_config(Config { jolt_time: 10, ..c });
    assert_eq!(ramp.config().jolt_time, 0);
    let rest = until_reached(&mut ramp, 500);
    assert_eq!(rest[0].speed, 30, "still unfiltered");
    assert_eq!(rest.last().unwrap().position, 2000);
    ramp.set_target(Target::Position(4000));
    let next = run(&mut ramp, 2);
    assert_eq!(ramp.config().jolt_time, 10);
    assert_eq!(speeds(&next), [1, 3], "filtered: 10/10, 30/10");
}

/// X67-18.11.1.14-03: a JoltTime change written at standstill applies to the very next move.
#[test]
fn jolt_change_at_standstill_applies_at_once() {
    let c = cfg(100, 40, 40);
    let mut ramp = Ramp::new(c);
    ramp.set_config(Config { jolt_time: 4, ..c });
    assert_eq!(ramp.config().jolt_time, 4);
    ramp.set_target(Target::Position(1000));
    assert_eq!(
        speeds(&run(&mut ramp, 3)),
        [10, 30, 55],
        "means of 40, 80, 100"
    );
}

/// X67-18.11.1.5-01: Stop during a positioning move brakes with MaxDec and the target is not reported.
#[test]
fn stop_during_position_move() {
    let mut ramp = Ramp::new(cfg(50, 25, 10));
    ramp.set_target(Target::Position(10_000));
    run(&mut ramp, 3);
    ramp.set_target(Target::Stop);
    let states = run(&mut ramp, 7);
    assert_eq!(speeds(&states), [40, 30, 20, 10, 0, 0, 0]);
    assert!(states.iter().all(|s| !s.target_reached));
    assert!(states[4].standstill);
}

/// X67-18.6.3.3-03: the position register is the 32-bit counter and wraps at the DINT limits.
#[test]
fn position_register_wraps() {
    let mut ramp = Ramp::at(cfg(0, 100, 100), i64::from(i32::MAX) - 50);
    ramp.set_target(Target::Speed(100));
    let s = ramp.step();
    assert_eq!(s.position, i64::from(i32::MAX) + 50);
    assert_eq!(s.position_register(), i32::MIN + 49);
}

fn config_strategy() -> impl Strategy<Value = Config> {
    (1u16..200, 1u16..60, 1u16..60, 0u8..12, -300i16..300).prop_map(|(v, a, d, j, r)| Config {
        max_speed_pos: v,
        max_acc: a,
        max_dec: d,
        jolt_time: j,
        rev_loop: r,
        ..Config::default()
    })
}

/// Checks the limits on one cycle: set-point speed within MaxSpeed, its magnitude rising by at most MaxAcc and
/// falling by at most MaxDec without changing sign in one cycle. The output speed obeys the same limits; with
/// the jerk FIFO its rounding may add at most 1 microstep/cycle² (the carried remainder).
fn check_limits(c: &Config, prev: (i64, i64), now: (i64, i64), vmax: i64) {
    let tol = i64::from(c.jolt_time > 0);
    for (p, n, tol) in [(prev.0, now.0, 0), (prev.1, now.1, tol)] {
        assert!(n.abs() <= vmax, "speed {n} > {vmax}");
        assert!(p * n >= 0, "sign change in one cycle {p} → {n}");
        assert!(
            n.abs() - p.abs() <= i64::from(c.max_acc) + tol,
            "acc {p} → {n}"
        );
        assert!(
            p.abs() - n.abs() <= i64::from(c.max_dec) + tol,
            "dec {p} → {n}"
        );
    }
}

proptest! {
    /// X67-18.11.1.3-01, X67-18.11.1.4-01, X67-18.11.1.5-01, X67-18.11.1.6-02, X67-18.11.1.6-03,
    /// X67-18.11.1.14-01: every
    /// absolute target is reached exactly, within the speed, acceleration and deceleration limits, and with a
    /// reversing loop the final approach runs against the sign of RevLoop.
    #[test]
    fn every_target_reached_within_limits(c in config_strategy(), start in -5000i64..5000, target in -5000i64..5000) {
        let mut ramp = Ramp::at(c, start);
        ramp.set_target(Target::Position(target));
        let vmax = i64::from(c.max_speed_pos);
        let mut prev = (0, 0);
        let mut last_move = 0;
        let mut reached = false;
        for _ in 0..20_000 {
            let s = ramp.step();
            let now = (ramp.setpoint_speed(), i64::from(s.speed));
            check_limits(&c, prev, now, vmax);
            prev = now;
            if now.0 != 0 {
                last_move = now.0.signum();
            }
            if s.target_reached {
                prop_assert_eq!(s.position, target);
                reached = true;
                break;
            }
        }
        prop_assert!(reached);
        if c.rev_loop != 0 && start != target {
            prop_assert_eq!(last_move, -i64::from(c.rev_loop).signum());
        }
        let s = ramp.step();
        prop_assert!(s.target_reached && s.standstill && s.position == target);
    }

    /// X67-18.11.1.4-01, X67-18.11.1.5-01, X67-18.11.1.6-02: a second target given in the middle of a move is
    /// reached exactly from the current position and speed, within the limits.
    #[test]
    fn retarget_reached_within_limits(
        c in config_strategy(), first in -5000i64..5000, second in -5000i64..5000, after in 0usize..40,
    ) {
        let mut ramp = Ramp::new(c);
        ramp.set_target(Target::Position(first));
        let vmax = i64::from(c.max_speed_pos);
        let mut prev = (0, 0);
        for _ in 0..after {
            let s = ramp.step();
            prev = (ramp.setpoint_speed(), i64::from(s.speed));
        }
        ramp.set_target(Target::Position(second));
        let mut reached = false;
        for _ in 0..20_000 {
            let s = ramp.step();
            let now = (ramp.setpoint_speed(), i64::from(s.speed));
            check_limits(&c, prev, now, vmax);
            prev = now;
            if s.target_reached {
                prop_assert_eq!(s.position, second);
                reached = true;
                break;
            }
        }
        prop_assert!(reached);
    }

    /// X67-18.11.1.5-01: Stop at any point of a positioning move brakes to standstill within the limits and
    /// the axis then stays where it stopped.
    #[test]
    fn stop_within_limits(c in config_strategy(), target in -5000i64..5000, after in 0usize..60) {
        let mut ramp = Ramp::new(c);
        ramp.set_target(Target::Position(target));
        let mut prev = (0, 0);
        for _ in 0..after {
            let s = ramp.step();
            prev = (ramp.setpoint_speed(), i64::from(s.speed));
        }
        ramp.set_target(Target::Stop);
        let mut stopped = None;
        for _ in 0..1000 {
            let s = ramp.step();
            let now = (ramp.setpoint_speed(), i64::from(s.speed));
            check_limits(&c, prev, now, i64::from(c.max_speed_pos));
            prev = now;
            prop_assert!(!s.target_reached);
            match stopped {
                Some(p) => prop_assert!(s.standstill && s.position == p),
                None if s.standstill => stopped = Some(s.position),
                None => {}
            }
        }
        prop_assert!(stopped.is_some());
    }

    /// X67-18.11.1.4-01, X67-18.11.1.5-01, X67-18.11.1.3-02: speed mode follows any sequence of set-points
    /// within MaxAcc/MaxDec and reaches each clamped set-point.
    #[test]
    fn speed_mode_within_limits(c in config_strategy(), acc in 100u16..=65_535, dec in 100u16..=65_535, setpoints in prop::collection::vec(-70_000i32..70_000, 1..4)) {
        let c = Config { max_acc: acc, max_dec: dec, jolt_time: 0, ..c };
        let mut ramp = Ramp::new(c);
        let mut prev = (0, 0);
        for sp in setpoints {
            ramp.set_target(Target::Speed(sp));
            let want = i64::from(sp.clamp(-65_535, 65_535));
            let mut hit = false;
            for _ in 0..10_000 {
                let s = ramp.step();
                let now = (ramp.setpoint_speed(), i64::from(s.speed));
                check_limits(&c, prev, now, 65_535);
                prev = now;
                if now.0 == want {
                    hit = true;
                    break;
                }
            }
            prop_assert!(hit);
        }
    }
}
