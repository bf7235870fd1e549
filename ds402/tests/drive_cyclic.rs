//! The cyclic synchronous modes of the generic drive at a 1 ms SYNC: the target of each SYNC
//! (0x607A + 0x60B0, 0x60FF + 0x60B1, 0x6071 + 0x60B2) is taken at `sync(now)` and reached one
//! interpolation period later (0x60C2 when present, else the time between the last two SYNCs);
//! status bit 12 shows the drive following; a following error beyond 0x6065 for 0x6066 ms faults
//! with 0x8611 in csp.

mod drive_rig;

use std::f64::consts::TAU;

use drive_rig::*;
use ds402::drive::{DriveConfig, MotorConfig, MotorKind};

const ENABLED: u16 = 0x0237;
const FOLLOWING: u16 = 0x1000;
const WARNING: u16 = 0x0080;

#[test]
fn csp_follows_a_ramp_one_sync_behind() {
    let mut r = Rig::with(&[]);
    r.enable(8);
    assert_eq!(r.read(0x6061, 0), 8);
    assert_eq!(r.sw(), ENABLED | FOLLOWING);
    // The master sends x(n) = 10 · (n − 1) before the SYNC at n ms (n ≥ 2): 10 000 counts/s. The
    // demand at the SYNC at n ms is the target of the one before, 10 · (n − 2).
    for n in 2..=201i64 {
        r.set(0x607A, 0, 10 * (n - 1));
        r.sync_at(n as u64);
        assert_eq!(r.demand(), 10 * (n - 2).max(0), "SYNC at {n} ms");
    }
    assert_eq!(r.pos(), 1990);
    assert_eq!(r.read(0x606C, 0), 10_000);
    assert_eq!(r.read(0x60F4, 0), 0);
    assert_eq!(r.sw(), ENABLED | FOLLOWING);
    // No more SYNCs: the last target (2000) is held. The demand stops within one tick, so the
    // rotor runs 5 counts past it ((10 000 + 0) / 2 counts/s for 1 ms) and the servo brings it back.
    r.at(203);
    assert_eq!((r.demand(), r.pos()), (2000, 2005));
    r.at(400);
    assert_eq!((r.demand(), r.pos(), r.read(0x606C, 0)), (2000, 2000, 0));
}

/// SYNCs half-way between two control ticks (an EtherCAT SYNC0 on its own time grid): each new
/// segment starts where the demand is at the SYNC itself. The master sends x(n) = 10 · (n − 1)
/// before the SYNC at n + 0.5 ms; that segment runs from x(n − 1) at n + 0.5 ms to x(n) at
/// n + 1.5 ms, so the demand at the tick n + 1 ms is half-way, 10n − 15, and its velocity is
/// 10 counts per 1 ms period, 10,000 counts/s, the ramp's own (not more: a segment that started
/// from the demand of the tick before the SYNC would run 15 counts in a period).
#[test]
fn csp_syncs_between_ticks_follow_the_ramp_at_its_speed() {
    let mut r = Rig::with(&[]);
    r.enable(8);
    for n in 2..=201i64 {
        r.set(0x607A, 0, 10 * (n - 1));
        r.sync_at_us(1000 * n as u64 + 500);
        if n >= 3 {
            r.at(n as u64 + 1);
            assert_eq!(r.demand(), 10 * n - 15, "tick at {} ms", n + 1);
        }
    }
    assert_eq!(r.read(0x606B, 0), 10_000, "velocity demand");
    assert_eq!(r.read(0x606C, 0), 10_000, "velocity actual");
    assert_eq!(r.read(0x60F4, 0), 0);
    // The last target, 2000, is reached one period after its SYNC (201.5 ms), and held.
    r.at(300);
    assert_eq!((r.demand(), r.pos(), r.read(0x606C, 0)), (2000, 2000, 0));
}

/// csv with SYNCs between ticks: the velocity ramps from where it is at the SYNC.
#[test]
fn csv_syncs_between_ticks_ramp_from_the_velocity_at_the_sync() {
    let mut r = Rig::with(&[]);
    r.enable(9);
    r.set(0x60FF, 0, 1000);
    r.sync_at_us(2500);
    r.sync_at_us(3500);
    r.set(0x60FF, 0, 2000);
    // At 4.5 ms the first ramp (0 → 1000 over 2.5…3.5 ms, then the same 1000 from 3.5 ms) is at 1000;
    // the second runs 1000 → 2000 over 4.5…5.5 ms: at the tick at 5 ms half-way.
    r.sync_at_us(4500);
    r.at(5);
    assert_eq!(r.read(0x606B, 0), 1500);
    r.at(6);
    assert_eq!(r.read(0x606B, 0), 2000);
}

#[test]
fn csp_position_offset_is_added() {
    let mut r = Rig::with(&[(0x60B0, 0, 100)]);
    r.enable(8);
    r.set(0x607A, 0, 50);
    r.sync_at(2);
    r.sync_at(3);
    assert_eq!(r.demand(), 150);
}

#[test]
fn csp_interpolates_over_the_measured_sync_period_without_0x60c2() {
    // SYNC every 2 ms: the target of the SYNC at 6 ms is half-way at 7 ms, there at 8 ms.
    let mut r = Rig::new(dictionary_with(&[], &[0x60C2]), DriveConfig::default());
    r.enable(8);
    r.sync_at(2);
    r.sync_at(4);
    r.set(0x607A, 0, 100);
    r.sync_at(6);
    r.at(7);
    assert_eq!(r.demand(), 50);
    r.at(8);
    assert_eq!(r.demand(), 100);
    // With 0x60C2 = 1 ms the same SYNCs reach the target at 7 ms.
    let mut r = Rig::with(&[]);
    r.enable(8);
    r.sync_at(2);
    r.sync_at(4);
    r.set(0x607A, 0, 100);
    r.sync_at(6);
    r.at(7);
    assert_eq!(r.demand(), 100);
    // 0x60C2 with a period of 0 (an EDS entry without a value) gives none: the measured period.
    let mut r = Rig::with(&[(0x60C2, 1, 0)]);
    r.enable(8);
    r.sync_at(2);
    r.sync_at(4);
    r.set(0x607A, 0, 100);
    r.sync_at(6);
    r.at(7);
    assert_eq!(r.demand(), 50);
    r.at(8);
    assert_eq!(r.demand(), 100);
}

/// 0x60C2 without its sub-index 2 (interpolation time index): the drive takes −3, milliseconds
/// (CiA 402-2, object 0x60C2). 0x60C2:01 = 2: the target of the SYNC at 3 ms is reached at 5 ms,
/// half-way at 4 ms, though the SYNC before came 1 ms earlier.
#[test]
fn csp_interpolation_time_index_defaults_to_milliseconds() {
    use od::{AccessType, DataType, Object, ObjectKind, SubObject, Value};
    let mut dict = dictionary_with(&[], &[0x60C2]);
    dict.insert(
        Object::structured(0x60C2, "Interpolation time period", ObjectKind::Record)
            .with_sub(
                0,
                SubObject::new(
                    "Highest sub-index supported",
                    DataType::Unsigned8,
                    AccessType::Const,
                )
                .with_default(Value::Uint(1)),
            )
            .with_sub(
                1,
                SubObject::new(
                    "Interpolation time period value",
                    DataType::Unsigned8,
                    AccessType::Rw,
                )
                .with_default(Value::Uint(2)),
            ),
    );
    let mut r = Rig::new(dict, DriveConfig::default());
    r.enable(8);
    r.sync_at(2);
    r.set(0x607A, 0, 100);
    r.sync_at(3);
    r.at(4);
    assert_eq!(r.demand(), 50);
    r.at(5);
    assert_eq!(r.demand(), 100);
}

/// The network's SYNC cycle wins over 0x60C2 (an ESI may give 1 s there, as Ingenia's does: 1 ×
/// 10⁰ s): with a 1 ms cycle set, the target of the SYNC at 2 ms is reached at 3 ms; without it,
/// 0x60C2's second.
#[test]
fn csp_interpolates_over_the_networks_sync_cycle_where_it_gives_one() {
    let mut r = Rig::with(&[(0x60C2, 1, 1), (0x60C2, 2, 0)]);
    r.enable(8);
    r.drive
        .set_sync_cycle(Some(std::time::Duration::from_millis(1)));
    r.set(0x607A, 0, 100);
    r.sync_at(2);
    r.at(3);
    assert_eq!(r.demand(), 100);
    r.drive.set_sync_cycle(None);
    r.set(0x607A, 0, 1100);
    r.sync_at(4);
    r.at(5);
    assert_eq!(r.demand(), 101, "1 count of 1,000 in the first ms of 1 s");
    // A cycle of 0 is none.
    r.drive.set_sync_cycle(Some(std::time::Duration::ZERO));
    r.sync_at(6);
    r.at(7);
    assert_eq!(r.demand(), 103);
}

#[test]
fn csp_software_limits_clamp_and_set_bit_11() {
    let mut r = Rig::with(&[(0x607D, 1, -100), (0x607D, 2, 100)]);
    r.enable(8);
    r.set(0x607A, 0, 500);
    r.sync_at(2);
    assert_eq!(r.sw(), ENABLED | FOLLOWING | 0x0800);
    r.sync_at(3);
    assert_eq!(r.demand(), 100);
    r.set(0x607A, 0, 50);
    r.sync_at(4);
    assert_eq!(r.sw(), ENABLED | FOLLOWING);
}

#[test]
fn csp_following_error_faults_with_8611() {
    // No torque: the rotor stays at 0, the following error is the demand 10 · (n − 2) at n ms.
    // Beyond 0x6065 = 100 from 13 ms (110); for 0x6066 = 3 ms: the fault at 16 ms.
    let mut r = Rig::with(&[(0x6065, 0, 100), (0x6066, 0, 3)]);
    r.enable(8);
    r.set(0x6072, 0, 0);
    for n in 2..=12i64 {
        r.set(0x607A, 0, 10 * (n - 1));
        r.sync_at(n as u64);
    }
    assert_eq!(r.read(0x60F4, 0), 100);
    assert_eq!(r.sw(), ENABLED | FOLLOWING);
    for n in 13..=15i64 {
        r.set(0x607A, 0, 10 * (n - 1));
        r.sync_at(n as u64);
        assert_eq!(r.sw(), ENABLED | FOLLOWING | WARNING, "{n} ms");
    }
    r.set(0x607A, 0, 150);
    r.sync_at(16);
    // Fault reaction active (0x605E = 2, braking) with bit 13 (following error), error code 0x8611.
    assert_eq!(r.sw(), 0x223F);
    assert_eq!(r.read(0x603F, 0), 0x8611);
    // The demand brakes from 10 000 counts/s at 0x6085 = 100 000: 100 ms.
    r.at(115);
    assert_eq!(r.sw(), 0x223F);
    r.at(116);
    assert_eq!(r.sw(), 0x2228);
    // Fault reset clears it.
    r.cw(FAULT_RESET);
    assert_eq!(r.sw(), 0x0260);
    assert_eq!(r.read(0x603F, 0), 0);
}

#[test]
fn csv_follows_the_target_velocity() {
    // 0x60FF = 4000 before the SYNC at 2 ms: the velocity demand rises to 4000 over 1 ms (2
    // counts), then 4 counts each ms.
    let mut r = Rig::with(&[]);
    r.enable(9);
    // Standing before the first SYNC: following (bit 12), not "target reached", which in the
    // cyclic modes is standing after a halt.
    assert_eq!(r.sw(), ENABLED | FOLLOWING);
    r.set(0x60FF, 0, 4000);
    for n in 2..=103u64 {
        r.sync_at(n);
    }
    assert_eq!(r.demand(), 2 + 4 * 100);
    assert_eq!(r.pos(), 402);
    assert_eq!(r.read(0x606C, 0), 4000);
    assert_eq!(r.sw(), ENABLED | FOLLOWING);
    // The velocity offset 0x60B1 adds to the target.
    r.set(0x60B1, 0, 1000);
    r.sync_at(104);
    r.sync_at(105);
    assert_eq!(r.read(0x606C, 0), 5000);
}

#[test]
fn cst_applies_the_target_torque() {
    // 0x6071 = 100 ‰ of 1 N·m on 1e-4 kg·m² without friction: 1000 rad/s², i.e. 1000 · 10 000 / 2π
    // counts/s². Taken at the SYNC at 2 ms, applied from then: after 10 ms, v = a · 0.01 and
    // x = a · 0.01² / 2.
    let config = DriveConfig {
        motor: MotorConfig {
            friction: 0.0,
            ..MotorConfig::default()
        },
        ..DriveConfig::default()
    };
    let mut r = Rig::new(dictionary(&[]), config);
    r.enable(10);
    r.set(0x6071, 0, 100);
    r.sync_at(2);
    r.at(12);
    let a = 1000.0 * 10_000.0 / TAU;
    assert_eq!(r.read(0x606C, 0), (a * 0.01).round() as i64); // 15 915
    assert_eq!(r.pos(), (a * 0.0001 / 2.0).round() as i64); // 80
    assert_eq!(r.read(0x6077, 0), 100);
    assert_eq!(r.sw(), ENABLED | FOLLOWING);
    // Beyond 0x6072 (3000 ‰) the torque is limited.
    r.set(0x6071, 0, 5000);
    r.sync_at(13);
    r.at(14);
    assert_eq!(r.read(0x6077, 0), 3000);
    // The torque offset 0x60B2 adds to the target.
    r.set(0x6071, 0, -300);
    r.set(0x60B2, 0, 100);
    r.sync_at(15);
    r.at(16);
    assert_eq!(r.read(0x6077, 0), -200);
}

/// cst: 0x6071 is per mille of the rated torque 0x6076 (CiA 402-2, cyclic synchronous torque
/// mode): 50 ‰ of 2 N·m is the same 0.1 N·m as 100 ‰ of 1 N·m above. Nothing commands a position,
/// so the position demand 0x6062 reads the rotor's position and the following error is 0.
#[test]
fn cst_target_torque_is_per_mille_of_the_rated_torque() {
    let config = DriveConfig {
        motor: MotorConfig {
            friction: 0.0,
            ..MotorConfig::default()
        },
        ..DriveConfig::default()
    };
    let mut r = Rig::new(dictionary(&[(0x6076, 0, 2000)]), config);
    r.enable(10);
    r.set(0x6071, 0, 50);
    r.sync_at(2);
    r.at(12);
    let a = 1000.0 * 10_000.0 / TAU;
    assert_eq!(r.read(0x6077, 0), 50);
    assert_eq!(r.read(0x606C, 0), (a * 0.01).round() as i64); // 15 915
    assert_eq!(r.pos(), (a * 0.0001 / 2.0).round() as i64); // 80
    assert_eq!(r.demand(), 80);
    assert_eq!(r.read(0x606B, 0), 15_915);
    assert_eq!(r.read(0x60F4, 0), 0);
}

/// csv with a SYNC in the middle of a ramp: the new ramp starts from the velocity demand at the
/// SYNC itself. 0 → 1000 counts/s over 1.5…2.5 ms; the SYNC at 2.2 ms finds 700 and ramps to 2000
/// over 2.2…3.2 ms: at the tick at 3 ms 700 + 1300 · 0.8 = 1740.
#[test]
fn csv_a_sync_within_a_ramp_starts_from_the_velocity_there() {
    let mut r = Rig::with(&[]);
    r.enable(9);
    r.set(0x60FF, 0, 1000);
    r.sync_at_us(1500);
    r.at(2);
    assert_eq!(r.read(0x606B, 0), 500);
    r.set(0x60FF, 0, 2000);
    r.sync_at_us(2200);
    r.at(3);
    assert_eq!(r.read(0x606B, 0), 1740);
    r.at(4);
    assert_eq!(r.read(0x606B, 0), 2000);
}

/// cst from the enable: the target torque already set acts at once, without waiting for a SYNC;
/// halt brakes on 0x605D, and its release gives the target torque back at once (CiA 402-2, cyclic
/// synchronous torque mode). The numbers of the test above: after 10 ms v = a · 0.01.
#[test]
fn cst_acts_from_the_enable_and_again_at_the_release_of_halt() {
    let config = DriveConfig {
        motor: MotorConfig {
            friction: 0.0,
            ..MotorConfig::default()
        },
        ..DriveConfig::default()
    };
    let mut r = Rig::new(dictionary(&[(0x6071, 0, 100)]), config);
    r.enable(10);
    r.at(11);
    let a = 1000.0 * 10_000.0 / TAU;
    assert_eq!(r.read(0x6077, 0), 100);
    assert_eq!(r.read(0x606C, 0), (a * 0.01).round() as i64); // 15 915
    assert_eq!(r.pos(), (a * 0.0001 / 2.0).round() as i64); // 80
    r.cw(ENABLE | HALT);
    r.at(20);
    assert_eq!(r.sw(), ENABLED);
    r.cw(ENABLE);
    assert_eq!(r.sw(), ENABLED | FOLLOWING);
    r.at(21);
    assert_eq!(r.read(0x6077, 0), 100);
}

/// In Quick stop active (0x605A = 6: stay there) csp takes no targets at the SYNCs; after
/// transition 16 it follows again from the next SYNC (CiA 402-2, cyclic synchronous position mode).
#[test]
fn csp_takes_no_targets_in_quick_stop_active() {
    let mut r = Rig::with(&[(0x605A, 0, 6)]);
    r.enable(8);
    r.cw(QUICK_STOP);
    r.at(2);
    assert_eq!(r.sw(), 0x0617);
    r.set(0x607A, 0, 1000);
    r.sync_at(3);
    r.sync_at(4);
    r.at(10);
    assert_eq!((r.demand(), r.pos(), r.sw()), (0, 0, 0x0617));
    r.cw(ENABLE);
    r.sync_at(11);
    r.at(12);
    assert_eq!(r.demand(), 1000);
}

/// The offsets feed forward in csp (0x60B1 velocity, 0x60B2 torque) and csv (0x60B2) (CiA 402-2,
/// cyclic synchronous modes). 0x60B1 = 500 counts/s on an axis holding its position: the position
/// loop (gain a fifth of 0.25 / tick: 50 /s) stands 500 / 50 = 10 counts ahead. 0x60B2 = 100 ‰
/// of 0x6076 = 2 N·m: at the first tick after the write the drive gives exactly that torque.
#[test]
fn csp_and_csv_feed_the_offsets_forward() {
    let mut r = Rig::with(&[(0x6076, 0, 2000)]);
    r.enable(8);
    r.set(0x60B2, 0, 100);
    r.at(2);
    assert_eq!(r.read(0x6077, 0), 100);
    let mut r = Rig::with(&[(0x6076, 0, 2000)]);
    r.enable(9);
    r.set(0x60B2, 0, 100);
    r.at(2);
    assert_eq!(r.read(0x6077, 0), 100);
    let mut r = Rig::with(&[]);
    r.enable(8);
    r.set(0x60B1, 0, 500);
    r.at(2000);
    assert_eq!((r.demand(), r.pos(), r.read(0x60F4, 0)), (0, 10, -10));
}

/// cst and the limit switches (CiA 402-2, 0x60FD): 1 ‰ of 1 N·m without friction accelerates
/// at a = 0.001 / (1e-4 · 2π / 10 000) = 15 915 counts/s² from the enable at 1 ms, at ½ · a · t²:
/// 997.2 after 354 ms, 1002.9 after 355 ms, into the positive limit switch at 1000: fault 0x8612.
/// An axis creeping below 1 count/s counts as standing: on an active switch it is no fault.
#[test]
fn cst_into_a_limit_switch_is_a_fault_creeping_on_one_is_not() {
    let config = DriveConfig {
        motor: MotorConfig {
            friction: 0.0,
            ..MotorConfig::default()
        },
        sim: ds402::drive::SimConfig {
            positive_limit: Some(1000),
            ..Default::default()
        },
        ..DriveConfig::default()
    };
    let mut r = Rig::new(dictionary(&[(0x6071, 0, 1)]), config);
    r.enable(10);
    r.at(355);
    assert_eq!((r.sw(), r.pos()), (ENABLED | FOLLOWING, 997));
    r.at(356);
    assert_eq!((r.sw(), r.read(0x603F, 0)), (0x023F, 0x8612));
    // 10 ‰ for one tick (the SYNCs at 2 and 3 ms), then 0: the friction (1e-3 N·m·s/rad on 1e-4
    // kg·m²) takes 1 % of the speed each tick, from 159 counts/s to 0.007 in 1 s.
    let mut r = Rig::with(&[]);
    r.enable(10);
    r.set(0x6071, 0, 10);
    r.sync_at(2);
    r.set(0x6071, 0, 0);
    r.sync_at(3);
    r.at(1003);
    let here = r.pos();
    r.drive.sim_mut().positive_limit = Some(here);
    r.at(1010);
    assert_eq!(r.read(0x60FD, 0), 0b010);
    assert_eq!(
        (r.sw(), r.read(0x603F, 0)),
        (ENABLED | FOLLOWING | 0x0800, 0)
    );
}

#[test]
fn halt_in_csp_stops_and_the_drive_does_not_follow() {
    let mut r = Rig::with(&[]);
    r.enable(8);
    for n in 2..=101i64 {
        r.set(0x607A, 0, 10 * (n - 1));
        r.sync_at(n as u64);
    }
    r.cw(ENABLE | HALT);
    assert_eq!(r.sw(), ENABLED);
    // From 10 000 counts/s at 0x6084 = 10 000: 1 s.
    for n in 102..=1101i64 {
        r.set(0x607A, 0, 10 * (n - 1));
        r.sync_at(n as u64);
    }
    assert_eq!(r.read(0x606C, 0), 0);
    assert_eq!(r.sw(), ENABLED | 0x0400);
}

#[test]
fn cst_is_refused_on_a_stepper() {
    let config = DriveConfig {
        motor: MotorConfig {
            kind: MotorKind::Stepper,
            ..MotorConfig::default()
        },
        ..DriveConfig::default()
    };
    let mut r = Rig::new(dictionary(&[]), config);
    r.at(1);
    assert_eq!(r.write(0x6060, 0, 10), Err(od::AbortCode::InvalidValue));
    assert_eq!(r.read(0x6060, 0), 0);
    assert_eq!(r.read(0x6061, 0), 0);
    assert_eq!(r.write(0x6060, 0, 8), Ok(()));
    assert_eq!(r.read(0x6061, 0), 8);
}
