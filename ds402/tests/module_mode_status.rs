//! What the motion modes of the X67SM2436 "Ramp" module model show and when they act, tested through the
//! module's registers: status bits 10 and 12, motion only in Operation enable, the counter wrap-around, the
//! once-per-cycle take-over of the cyclic outputs, and properties of mode 1 over random ramp registers and
//! set-point sequences. Each test names the rules of `rules/x67.md` it covers.
//!
//! The expected trajectories follow the discretisation the catalogue picks in X67-18.11.3.3.1-01: each cycle
//! the speed changes first (by at most MaxAcc/MaxDec, up to MaxSpeed) and the position then advances by it;
//! braking starts as late as possible so that the target is met exactly. With MaxSpeed 100, MaxAcc 10 and
//! MaxDec 10 a move from standstill accelerates 10, 20, …, 100 (550 microsteps), brakes 90, 80, …, 10 (450
//! microsteps), and cruises at 100 for the rest; the axis arrives in the following cycle with increment 0.

mod module_modes_helpers;
mod x67_rig;

use ds402::cia402::control::{ENABLE_OPERATION, SWITCH_ON};
use ds402::x67::axis::{modes, CW_NEW_SETPOINT, CW_STOP, SW_SETPOINT_ACK};
use ds402::x67::module::Module;
use module_modes_helpers::*;
use proptest::prelude::*;
use x67_rig::{
    cat, cat_bools, cycle, enable_operation, set_ramp, state, switch_on, trace, write, Cyc,
    OPERATION_ENABLE, STATE_MASK, SWITCHED_ON,
};

// 18.11.3.5 / 18.11.4.2 Status word bits 10 and 12
// =====================================================================================================

/// X67-18.11.3.5-04: SW bit 12 follows the set-point handshake with the extended control word in mode 1, and is
/// 0 without it (CW bit 4 toggling) and in other modes (pick).
#[test]
fn x67_18_11_3_5_04_bit_12_mode_specific() {
    let mut m = standard_ext();
    let acks: Vec<bool> = [
        handshake(&mut m, 100, 0),
        cycle(&mut m, A1),
        release(&mut m, 0),
    ]
    .iter()
    .map(|c| c.ack())
    .collect();
    assert_eq!(acks, [true, true, false]);

    // Bit 4 toggling without the extended control word (mode 1, AbsPos01 = 100·k) and with it in speed
    // mode (AbsPos01 = 10): bit 12 stays 0.
    // (case, the module, mode, AbsPos01 in cycle k)
    type Setup = fn() -> Module;
    type AbsPos = fn(u16) -> i32;
    let cases: [(&str, Setup, i8, AbsPos); 2] = [
        ("mode 1 without ext CW", standard, modes::POSITION, |k| {
            i32::from(k) * 100
        }),
        ("mode 2 with ext CW", standard_ext, modes::SPEED, |_| 10),
    ];
    for (case, setup, mode, abs_pos) in cases {
        let mut m = setup();
        m.set_mode(A1, mode);
        for k in 0..20u16 {
            m.set_control(A1, ENABLE_OPERATION | (k % 2) << 4);
            m.set_abs_pos(A1, abs_pos(k));
            m.step();
            assert_eq!(m.status_word(A1) & SW_SETPOINT_ACK, 0, "{case}, cycle {k}");
        }
    }
}

/// X67-18.11.3.5-04, X67-18.11.3.3.2-11 (pick): bit 12 is Set-point acknowledge only in the modes with the
/// handshake, mode 1 and −121 before its trigger; in any other mode, and in −121 once triggered, it is 0,
/// even while bit 4 is still high and the value was taken.
#[test]
fn x67_18_11_3_5_04_bit_12_only_in_the_handshake_modes() {
    let mut m = standard_ext();
    assert!(handshake(&mut m, 1000, 0).ack());
    m.set_abs_pos(A1, 0);
    m.set_mode(A1, modes::SPEED);
    for k in 0..3 {
        let c = cycle(&mut m, A1);
        assert_eq!(c.sw & SW_SETPOINT_ACK, 0, "mode 2, cycle {k}");
    }

    let mut m = standard_ext();
    m.set_mode(A1, modes::REMAINING_DISTANCE);
    m.step();
    assert!(handshake(&mut m, 1000, 0).ack());
    let t = trace(&mut m, A1, 30);
    assert!(t.iter().all(|c| c.ack()), "−121 before its trigger");
    assert_eq!(m.act_val(A1), 1000);
    m.pulse_input(DI3);
    for k in 0..3 {
        let c = cycle(&mut m, A1);
        assert_eq!(c.sw & SW_SETPOINT_ACK, 0, "−121 triggered, cycle {k}");
    }
}

/// X67-18.11.4.2-11: in modes 1, −123, −124, −125 and −126 bit 10 is 0 from the start of a move and 1 once the
/// target is reached.
#[test]
fn x67_18_11_4_2_11_bit_10_in_positioning_modes() {
    for mode in [
        modes::POSITION,
        modes::MOVE_ON_INPUT,
        modes::TWO_POSITION,
        modes::FIXED_A,
        modes::FIXED_B,
    ] {
        let mut m = standard();
        assert!(cycle(&mut m, A1).reached());
        let late = start_move(&mut m, mode, 1000);
        let t = until_reached(&mut m, A1, 100);
        let expected = if late {
            after_edge(profile(0, 1))
        } else {
            profile(0, 1)
        };
        assert_eq!(incs(&t), expected, "mode {mode}");
        assert_eq!(bit10(&t), moving_then_reached(t.len()), "mode {mode}");
        assert!(trace(&mut m, A1, 5)
            .iter()
            .all(|c| c.reached() && c.pos == 1000));
    }
}

/// X67-18.11.4.2-12: in speed mode bit 10 is 0 while the speed changes and 1 once it equals the set-point:
/// 50 → 1 from the first cycle at 50; 80 → 0 until 80; 20 → 0 while braking.
#[test]
fn x67_18_11_4_2_12_bit_10_in_speed_mode() {
    let mut m = standard();
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 50);
    let t = trace(&mut m, A1, 7);
    assert_eq!(incs(&t), [10, 20, 30, 40, 50, 50, 50]);
    assert_eq!(bit10(&t), [false, false, false, false, true, true, true]);
    m.set_abs_pos(A1, 80);
    let t = trace(&mut m, A1, 4);
    assert_eq!(incs(&t), [60, 70, 80, 80]);
    assert_eq!(bit10(&t), [false, false, true, true]);
    m.set_abs_pos(A1, 20);
    let t = trace(&mut m, A1, 8);
    assert_eq!(incs(&t), [70, 60, 50, 40, 30, 20, 20, 20]);
    assert_eq!(
        bit10(&t),
        [false, false, false, false, false, true, true, true]
    );
}

/// X67-18.11.4.2-12 with X67-18.11.1.14-01: with the jerk filter, bit 10 in speed mode waits for the speed the
/// axis runs at, not for the ramp's unfiltered set-point (the model's pick). JoltTime01 = 4, set-point 40,
/// MaxAcc01 10: the set-point runs 10, 20, 30, 40, 40, …; the axis moves by the mean of the last four with the
/// remainder carried: 10/4 = 2 (2 left), 32/4 = 8, 60/4 = 15, 100/4 = 25, 130/4 = 32 (2 left), 152/4 = 38,
/// 160/4 = 40: bit 10 is 1 from that cycle, not from the fourth, where the set-point reached 40.
#[test]
fn x67_18_11_4_2_12_bit_10_follows_the_filtered_speed() {
    let mut m = standard();
    write(&mut m, "JoltTime0n", A1, 4);
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 40);
    let t = trace(&mut m, A1, 8);
    assert_eq!(incs(&t), [2, 8, 15, 25, 32, 38, 40, 40]);
    assert_eq!(bit10(&t), cat_bools(&[false; 6], &[true; 2]));
}

/// X67-18.11.4.2-14: in mode −122 bit 10 drops to 0 for one cycle and returns to 1 once the position is set;
/// an unchanged AbsPos01 does not set it again.
#[test]
fn x67_18_11_4_2_14_bit_10_in_mode_122() {
    let mut m = standard();
    m.set_mode(A1, modes::SET_POSITION);
    m.set_abs_pos(A1, 777);
    let t = trace(&mut m, A1, 4);
    assert_eq!(bit10(&t), [false, true, true, true]);
    assert_eq!(positions(&t), [777; 4]);
    m.set_abs_pos(A1, 300);
    let t = trace(&mut m, A1, 3);
    assert_eq!(bit10(&t), [false, true, true]);
    assert_eq!(positions(&t), [300; 3]);
}

/// X67-18.11.4.2-15: with the extended control word and Stop = 1, bit 10 means "speed 0": mid-move toward
/// 10 000, Stop → 0 while braking, 1 at standstill at 2000; Stop released → the move resumes to 10 000.
#[test]
fn x67_18_11_4_2_15_bit_10_with_stop() {
    let mut m = standard_ext();
    let mut t = vec![handshake(&mut m, 10_000, 0), release(&mut m, 0)];
    t.extend(trace(&mut m, A1, 18));
    assert_eq!(m.act_val(A1), 1550);
    m.set_control(A1, ENABLE_OPERATION | CW_STOP);
    let t = trace(&mut m, A1, 14);
    assert_eq!(incs(&t), cat(&[&seq(90, 10, -10), &[0; 5]]));
    assert_eq!(bit10(&t), cat_bools(&[false; 9], &[true; 5]));
    assert_eq!(m.act_val(A1), 2000);
    m.set_control(A1, ENABLE_OPERATION);
    let t = until_reached(&mut m, A1, 200);
    assert_eq!(incs(&t), profile(70, 1));
    assert_eq!(m.act_val(A1), 10_000);
}

/// X67-18.11.4.2-16: without the extended control word CW bit 8 is no Stop: the move goes on unchanged and bit
/// 10 follows the mode.
#[test]
fn x67_18_11_4_2_16_bit_8_without_ext_cw() {
    let plain = move_with_control(false, |_| ENABLE_OPERATION);
    let stop = move_with_control(false, |k| {
        ENABLE_OPERATION | if k >= 5 { CW_STOP } else { 0 }
    });
    assert_eq!(stop, plain);
    assert_eq!(bit10(&stop), cat_bools(&[false; 39], &[true; 11]));
    assert_eq!(stop.last().unwrap().pos, 3000);
}

// =====================================================================================================
// 18.11.4.3 Motion only in Operation enable
// =====================================================================================================

/// X67-18.11.4.3-21: motion according to the mode happens only in Operation enable: in Switched on, mode 1 with
/// AbsPos01 = 1000 does not move; Enable operation starts the move in that cycle.
#[test]
fn x67_18_11_4_3_21_motion_only_in_operation_enable() {
    let mut m = Module::new();
    set_ramp(&mut m, A1, 100, 10, 10);
    m.set_mode(A1, modes::POSITION);
    switch_on(&mut m, A1);
    m.set_abs_pos(A1, 1000);
    let t = trace(&mut m, A1, 20);
    assert!(t
        .iter()
        .all(|c| c.pos == 0 && c.sw & STATE_MASK == SWITCHED_ON));
    m.set_control(A1, ENABLE_OPERATION);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(t[0].sw & STATE_MASK, OPERATION_ENABLE);
    assert_eq!(incs(&t), profile(0, 1));

    // Mode 2 in Switched on does not move either.
    let mut m = standard();
    m.set_control(A1, SWITCH_ON);
    m.step();
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 50);
    assert!(trace(&mut m, A1, 10).iter().all(|c| c.pos == 0));
}

// =====================================================================================================
// 18.11.1.17 Counter wrap-around without software limits
// =====================================================================================================

/// X67-18.11.1.17-06: without software limits the 32-bit counter wraps around: in speed mode it passes
/// 2 147 483 647 and continues at −2 147 483 648 and beyond.
#[test]
fn x67_18_11_1_17_06_counter_wraps_in_speed_mode() {
    let mut m = enabled(100, 100, 100);
    m.set_mode(A1, modes::SET_POSITION);
    m.set_abs_pos(A1, 2_147_483_000);
    m.step();
    assert_eq!(m.act_val(A1), 2_147_483_000);
    m.set_mode(A1, modes::SPEED);
    m.set_abs_pos(A1, 100);
    let t = trace(&mut m, A1, 9);
    assert_eq!(incs(&t), [100; 9]);
    assert_eq!(
        positions(&t),
        [
            2_147_483_100,
            2_147_483_200,
            2_147_483_300,
            2_147_483_400,
            2_147_483_500,
            2_147_483_600,
            -2_147_483_596,
            -2_147_483_496,
            -2_147_483_396
        ]
    );
    assert_eq!(state(&m, A1), OPERATION_ENABLE);
}

/// X67-18.11.1.17-06: in mode 1 the move distance is the wrapping difference target − actual as a signed
/// 32-bit value: from 2 147 483 000 to −2 147 483 000 is +1296 through the wrap, not −4 294 966 000.
#[test]
fn x67_18_11_1_17_06_wrapping_distance_in_mode_1() {
    let mut m = standard();
    m.set_mode(A1, modes::SET_POSITION);
    m.set_abs_pos(A1, 2_147_483_000);
    m.step();
    m.set_mode(A1, modes::POSITION);
    m.set_abs_pos(A1, -2_147_483_000);
    let t = until_reached(&mut m, A1, 100);
    assert!(t.iter().all(|c| c.inc >= 0));
    assert_eq!(t.iter().map(|c| i64::from(c.inc)).sum::<i64>(), 1296);
    assert_eq!(incs(&t)[..10], seq(10, 100, 10)[..]);
    assert_eq!(m.act_val(A1), -2_147_483_000);
    assert_eq!(m.axis(A1).motor.rotor(), 1296);
}

// =====================================================================================================
// 18.14 Cyclic outputs are taken over once per cycle
// =====================================================================================================

/// X67-18.14-02: only the value present at the cycle boundary takes effect: AbsPos01 = 5000 then 1000 within one
/// cycle moves to 1000 on the 1000 profile; a CW bit 4 pulse within one cycle is no handshake; a mode written
/// and overwritten within one cycle never acts.
#[test]
fn x67_18_14_02_value_at_cycle_boundary() {
    let mut m = standard();
    m.set_abs_pos(A1, 5000);
    m.set_abs_pos(A1, 1000);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), profile(0, 1));

    let mut m = standard_ext();
    m.set_abs_pos(A1, 3000);
    m.set_control(A1, ENABLE_OPERATION | CW_NEW_SETPOINT);
    m.set_control(A1, ENABLE_OPERATION);
    let t = trace(&mut m, A1, 10);
    assert!(t.iter().all(|c| c.pos == 0 && !c.ack()));

    let mut m = standard();
    m.set_mode(A1, modes::SET_POSITION);
    m.set_abs_pos(A1, 777);
    m.set_mode(A1, modes::POSITION);
    m.set_abs_pos(A1, 0);
    let t = trace(&mut m, A1, 5);
    assert!(t.iter().all(|c| c.pos == 0 && c.reached()));

    // At a 5 ms cycle the same holds per 5 ms cycle.
    let mut m = Module::new();
    m.write_named("GeneralConfig01", 4).unwrap();
    set_ramp(&mut m, A1, 100, 10, 10);
    m.set_mode(A1, modes::POSITION);
    switch_on(&mut m, A1);
    enable_operation(&mut m, A1);
    m.set_abs_pos(A1, -7000);
    m.set_abs_pos(A1, -1000);
    let t = until_reached(&mut m, A1, 100);
    assert_eq!(incs(&t), profile(0, -1));
}

// =====================================================================================================
// Properties of mode 1 over random ramp registers and set-point sequences
// =====================================================================================================

/// The ramp registers of one property case.
#[derive(Clone, Copy, Debug)]
struct Regs1 {
    speed: u16,
    acc: u16,
    dec: u16,
    rev_loop: i16,
    jolt: u8,
}

/// One cycle of a property run: what the master saw and the target in force.
#[derive(Clone, Copy, Debug)]
struct Step {
    c: Cyc,
    target: i32,
    /// Index of the order that gave the target.
    order: usize,
}

/// Runs mode-1 set-points (without the extended control word) on axis 1: each order gives its target and
/// then waits `Some(n)` cycles, or with `None` until bit 10 is 1. The last order always waits for bit 10.
fn drive(r: Regs1, orders: &[(i32, Option<usize>)]) -> Vec<Step> {
    let mut m = enabled(i64::from(r.speed), i64::from(r.acc), i64::from(r.dec));
    write(&mut m, "RevLoop0n", A1, i64::from(r.rev_loop));
    write(&mut m, "JoltTime0n", A1, i64::from(r.jolt));
    let mut out = Vec::new();
    for (k, &(target, wait)) in orders.iter().enumerate() {
        m.set_abs_pos(A1, target);
        let wait = if k + 1 == orders.len() { None } else { wait };
        match wait {
            Some(n) => {
                for _ in 0..n {
                    let c = cycle(&mut m, A1);
                    out.push(Step {
                        c,
                        target,
                        order: k,
                    });
                }
            }
            None => {
                let mut arrived = false;
                for _ in 0..20_000 {
                    let c = cycle(&mut m, A1);
                    out.push(Step {
                        c,
                        target,
                        order: k,
                    });
                    if c.reached() {
                        arrived = true;
                        break;
                    }
                }
                assert!(arrived, "order {k} ({target}) not reached; {r:?}");
            }
        }
    }
    out
}

/// Whether the increment may follow `prev` under MaxAcc/MaxDec: a rising magnitude by at most `acc`, a
/// falling one by at most `dec`; a change of sign brakes to 0 and accelerates from it.
fn accel_ok(prev: i32, cur: i32, acc: i32, dec: i32) -> bool {
    if prev == 0 || cur == 0 || prev.signum() == cur.signum() {
        let (p, c) = (prev.abs(), cur.abs());
        if c >= p {
            c - p <= acc
        } else {
            p - c <= dec
        }
    } else {
        prev.abs() <= dec && cur.abs() <= acc
    }
}

fn orders() -> impl Strategy<Value = Vec<(i32, Option<usize>)>> {
    prop::collection::vec((-8000i32..=8000, prop::option::of(0usize..60)), 1..6)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// X67-18.11.1.3-01, X67-18.11.1.4-01, X67-18.11.1.5-01, X67-18.11.3.3-04 (JoltTime01 = 0): whatever the
    /// registers and however the targets arrive, the per-cycle increment of AbsPos01ActVal never exceeds
    /// MaxSpeed01pos and changes by no more than MaxAcc01 (rising) or MaxDec01 (falling).
    #[test]
    fn prop_mode_1_speed_and_acceleration_limits(
        speed in 20u16..=400,
        acc in 1u16..=60,
        dec in 1u16..=60,
        rev_loop in -1500i16..=1500,
        orders in orders(),
    ) {
        let r = Regs1 { speed, acc, dec, rev_loop, jolt: 0 };
        let steps = drive(r, &orders);
        let mut prev = 0;
        for (k, s) in steps.iter().enumerate() {
            prop_assert!(s.c.inc.abs() <= i32::from(speed), "cycle {k}: {s:?}");
            prop_assert!(
                accel_ok(prev, s.c.inc, i32::from(acc), i32::from(dec)),
                "cycle {k}: {prev} → {}", s.c.inc
            );
            prop_assert_eq!(s.c.sw & STATE_MASK, OPERATION_ENABLE);
            prev = s.c.inc;
        }
    }

    /// X67-18.11.3.3.1-01, X67-18.11.4.2-11, X67-18.11.1.6-02, X67-18.11.1.6-03, X67-18.11.1.14-01:
    /// every target waited for
    /// is reached exactly with bit 10 = 1; bit 10 = 1 only ever on the target in force; with RevLoop01 ≠ 0 the
    /// last movement before an arrival runs against the sign of RevLoop01 (pick (a)); JoltTime01 anywhere in
    /// 0…80 keeps the speed within MaxSpeed01pos.
    #[test]
    fn prop_mode_1_targets_reached_from_the_loop_side(
        speed in 20u16..=400,
        acc in 1u16..=60,
        dec in 1u16..=60,
        rev_loop in prop_oneof![Just(0i16), -1500i16..=1500],
        jolt in prop_oneof![Just(0u8), 1u8..=80],
        orders in orders(),
    ) {
        let r = Regs1 { speed, acc, dec, rev_loop, jolt };
        let steps = drive(r, &orders);
        let last = steps.last().unwrap();
        prop_assert!(last.c.reached());
        prop_assert_eq!(last.c.pos, last.target);
        for (k, s) in steps.iter().enumerate() {
            prop_assert!(s.c.inc.abs() <= i32::from(speed), "cycle {k}: {s:?}");
            if !s.c.reached() {
                continue;
            }
            prop_assert_eq!(s.c.pos, s.target, "cycle {}", k);
            prop_assert_eq!(s.c.inc, 0);
            // The last movement since this target was given.
            let since = steps[..=k].iter().rev().take_while(|p| p.order == s.order);
            let last_move = since.map(|p| p.c.inc).find(|&i| i != 0);
            if let (Some(inc), true) = (last_move, rev_loop != 0) {
                prop_assert_eq!(inc.signum(), -i32::from(rev_loop.signum()), "cycle {}", k);
            }
        }
        for (k, _) in orders.iter().enumerate().filter(|(k, o)| o.1.is_none() || *k + 1 == orders.len()) {
            let arrival = steps.iter().rfind(|s| s.order == k).unwrap();
            prop_assert!(arrival.c.reached(), "order {}", k);
            prop_assert_eq!(arrival.c.pos, orders[k].0);
        }
    }
}

/// The module's clock (X67-18.11.1.15-02: GeneralConfig01 bits 1–2 select the 25, 10 or 5 ms cycle): after
/// `start` a cycle is due every cycle length; `handle_timeout` runs exactly the cycles due, each of the
/// length selected when it runs, and a host stalled for an hour catches up 2000 cycles, then goes on
/// from its present time.
#[test]
fn x67_18_11_1_15_02_module_clock_runs_the_cycles_due() {
    let t0 = std::time::Instant::now();
    let ms = std::time::Duration::from_millis;
    let mut m = Module::new();
    m.handle_timeout(t0 + ms(1000));
    assert_eq!(
        (m.time_ms(), m.poll_timeout()),
        (0, None),
        "no clock before start"
    );
    m.start(t0);
    assert_eq!(m.poll_timeout(), Some(t0 + ms(25)));
    m.handle_timeout(t0 + ms(24));
    assert_eq!(m.time_ms(), 0);
    m.handle_timeout(t0 + ms(25));
    assert_eq!(m.time_ms(), 25);
    m.handle_timeout(t0 + ms(87));
    assert_eq!(m.time_ms(), 75, "cycles at 50 and 75 ms");
    assert_eq!(m.poll_timeout(), Some(t0 + ms(100)));
    // 5 ms from the next cycle on: the cycles due at 100, 105 and 110 ms are 5 ms cycles.
    write(&mut m, "GeneralConfig01", 0, 0b100);
    m.handle_timeout(t0 + ms(111));
    assert_eq!(m.time_ms(), 75 + 5 + 5 + 5);
    assert_eq!(m.poll_timeout(), Some(t0 + ms(115)));
    let late = t0 + ms(3_600_000);
    m.handle_timeout(late);
    assert_eq!(m.time_ms(), 90 + 2000 * 5);
    assert_eq!(m.poll_timeout(), Some(late + ms(5)));
}
