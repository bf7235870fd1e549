//! The cyclic synchronous modes reach every set-point exactly once the drive stands at it, servo
//! and stepper alike: a csp ramp of 100 or 1,000 set-points to +10,000 and one second standing at
//! the last ends with 0x6064 exactly 10,000; csv runs at exactly its target velocity (0x606C); cst
//! gives exactly its target torque (0x6077). Unless a limit holds the drive back, and then the drive
//! says which, once, in one line naming the axis, the object, the value and the limit
//! ([`ds402::drive::Drive::poll_limit`], logged through `tracing` the moment it happens).
//!
//! The rig's motor: 1e-4 kg·m², 10,000 counts/rev, 0x6072 = 3,000 ‰ of 0x6076 = 1,000 mN·m,
//! friction 1e-3 N·m·s/rad; a stepper's pull-out torque 0.5 N·m. The demand may ask 90 % of the
//! torque for acceleration: a servo 0.9 · 3 / (1e-4 · 2π / 10,000) = 42,971,835 counts/s² from rest,
//! a stepper 0.9 · 0.5 / (1e-4 · 2π / 10,000) = 7,161,972 counts/s².

mod drive_rig;

use drive_rig::*;
use ds402::drive::{DriveConfig, MotorConfig, MotorKind};

fn stepper() -> DriveConfig {
    DriveConfig {
        motor: MotorConfig {
            kind: MotorKind::Stepper,
            ..MotorConfig::default()
        },
        ..DriveConfig::default()
    }
}

/// The drive of `changes` on `config`, enabled in `mode` at 1 ms.
fn enabled(changes: &[(u16, u8, i64)], config: DriveConfig, mode: i8) -> Rig {
    let mut r = Rig::new(dictionary(changes), config);
    r.enable(mode);
    r
}

/// A ramp of `steps` set-points of `index` from 0 to `to`, one per SYNC every ms from 2 ms + `phase`
/// µs on, then the last one for 1,000 SYNCs more (one second standing).
fn ramp(r: &mut Rig, index: u16, steps: i64, to: i64, phase: u64) {
    for n in 1..=steps {
        r.set(index, 0, to * n / steps);
        r.sync_at_us(1000 * (1 + n as u64) + phase);
    }
    for k in 1..=1000u64 {
        r.sync_at_us(1000 * (1 + steps as u64 + k) + phase);
    }
}

/// The lines the drive logged, in order.
fn lines(r: &mut Rig) -> Vec<String> {
    std::iter::from_fn(|| r.drive.poll_limit())
        .map(|l| l.message)
        .collect()
}

const SERVO_ACCEL: &str = "the 42,971,835 counts/s² that 0x6072 = 3,000 ‰ of 0x6076 = 1,000 mN·m \
                           gives the motor";
const STEPPER_ACCEL: &str =
    "the 7,161,972 counts/s² that the stepper's pull-out torque of 0.500 N·m gives";

/// 100 set-points to +10,000 (100 counts per cycle: 100,000 counts/s from rest in one cycle, 1e8
/// counts/s², beyond either motor): the demand runs after them within the motor's torque, lands on
/// the last set-point, and the axis stands exactly there; 0x6062 shows the set-points all along,
/// 0x60F4 the distance the axis is behind them, 0 at the end. One line, though the limit holds the
/// drive back again when the set-points stop.
#[test]
fn csp_100_set_points_end_exactly_at_the_last_one() {
    for (config, limit) in [
        (DriveConfig::default(), SERVO_ACCEL),
        (stepper(), STEPPER_ACCEL),
    ] {
        for phase in [0, 370] {
            let mut r = enabled(&[], config.clone(), 8);
            ramp(&mut r, 0x607A, 100, 10_000, phase);
            let what = format!("{:?} SYNC at +{phase} µs", config.motor.kind);
            assert_eq!(r.pos(), 10_000, "{what}");
            assert_eq!(r.demand(), 10_000, "{what}");
            assert_eq!(r.read(0x60F4, 0), 0, "{what}");
            assert_eq!(r.read(0x606C, 0), 0, "{what}");
            assert_eq!(r.drive.rotor_position().round(), 10_000.0, "{what}");
            assert_eq!(r.sw(), 0x1237, "{what}");
            assert_eq!(
                lines(&mut r),
                vec![format!(
                    "axis 0: csp target step of 100 counts/cycle needs 100,000,000 counts/s² \
                     from 0 counts/s, above {limit}"
                )],
                "{what}"
            );
        }
    }
}

/// 1,000 set-points to +10,000 (10 counts per cycle, 1e7 counts/s² at the start and the end): a
/// servo follows every one (nothing to say); a stepper's torque gives 7,161,972 counts/s² only, and
/// it runs after them. Both stand exactly at 10,000.
#[test]
fn csp_1000_set_points_end_exactly_at_the_last_one() {
    for (config, expected) in [
        (DriveConfig::default(), vec![]),
        (
            stepper(),
            vec![format!(
                "axis 0: csp target step of 10 counts/cycle needs 10,000,000 counts/s² from 0 \
                 counts/s, above {STEPPER_ACCEL}"
            )],
        ),
    ] {
        for phase in [0, 370] {
            let mut r = enabled(&[], config.clone(), 8);
            ramp(&mut r, 0x607A, 1000, 10_000, phase);
            let what = format!("{:?} SYNC at +{phase} µs", config.motor.kind);
            assert_eq!(r.pos(), 10_000, "{what}");
            assert_eq!(r.demand(), 10_000, "{what}");
            assert_eq!(r.read(0x60F4, 0), 0, "{what}");
            assert_eq!(r.read(0x606C, 0), 0, "{what}");
            assert_eq!(r.drive.rotor_position().round(), 10_000.0, "{what}");
            assert_eq!(lines(&mut r), expected, "{what}");
        }
    }
}

/// A servo whose torque is small for its ramp (0x6072 = 100 ‰ of 1 N·m, 1,000 counts/rev: it
/// accelerates at most at 0.9 · 0.1 / (1e-4 · 2π / 1,000) = 143,239 counts/s², and its friction,
/// 1e-3 · 2π / 1,000 N·m per count/s, takes those 0.09 N·m at 14,324 counts/s, far below the
/// set-points' 100,000 counts/s) approaches the last set-point without passing it and stands exactly there: 0x6064
/// never exceeds 10,000 during the second standing, and is 10,000 at its end.
#[test]
fn a_servo_short_of_torque_lands_on_the_last_set_point_without_overshoot() {
    let mut r = enabled(
        &[(0x6072, 0, 100), (0x608F, 1, 1000)],
        DriveConfig::default(),
        8,
    );
    for n in 1..=100i64 {
        r.set(0x607A, 0, 100 * n);
        r.sync_at(1 + n as u64);
    }
    for ms in 102..=1101u64 {
        r.sync_at(ms);
        let pos = r.pos();
        assert!(pos <= 10_000, "0x6064 = {pos} at {ms} ms");
    }
    assert_eq!(
        (r.pos(), r.read(0x606C, 0), r.read(0x60F4, 0)),
        (10_000, 0, 0)
    );
    assert_eq!(
        lines(&mut r),
        vec![
            "axis 0: csp target step of 100 counts/cycle needs 100,000,000 counts/s² from 0 \
              counts/s, above the 143,239 counts/s² that 0x6072 = 100 ‰ of 0x6076 = 1,000 mN·m \
              gives the motor"
                .to_string()
        ]
    );
}

/// csv: 100 and 1,000 set-points of the target velocity up to 10,000 counts/s, then standing: the
/// axis runs at exactly 10,000 counts/s (0x606C), servo and stepper.
#[test]
fn csv_runs_at_exactly_the_target_velocity() {
    for config in [DriveConfig::default(), stepper()] {
        for steps in [100, 1000] {
            let mut r = enabled(&[], config.clone(), 9);
            ramp(&mut r, 0x60FF, steps, 10_000, 370);
            let what = format!("{:?}, {steps} set-points", config.motor.kind);
            assert_eq!(r.read(0x606C, 0), 10_000, "{what}");
            assert_eq!(r.read(0x606B, 0), 10_000, "{what}");
            assert_eq!(lines(&mut r), Vec::<String>::new(), "{what}");
        }
    }
}

/// csv: a step of the target velocity beyond the stepper's torque (0 → 100,000 counts/s in one
/// cycle) is run up within it, and then held exactly; the line says so.
#[test]
fn csv_runs_up_to_a_target_beyond_its_torque_and_holds_it_exactly() {
    let mut r = enabled(&[], stepper(), 9);
    r.set(0x60FF, 0, 100_000);
    for ms in 2..=1001u64 {
        r.sync_at(ms);
    }
    assert_eq!(r.read(0x606C, 0), 100_000);
    assert_eq!(r.read(0x606B, 0), 100_000);
    assert_eq!(
        lines(&mut r),
        vec![format!(
            "axis 0: csv target change of 100,000 counts/s in a cycle needs 100,000,000 counts/s² \
             from 0 counts/s, above {STEPPER_ACCEL}"
        )]
    );
}

/// cst: the torque actual is exactly the target (0x6071 + 0x60B2); beyond 0x6072 it is 0x6072, and
/// the line says so, once.
#[test]
fn cst_gives_exactly_the_target_torque() {
    let mut r = enabled(&[], DriveConfig::default(), 10);
    ramp(&mut r, 0x6071, 100, 250, 370);
    assert_eq!(r.read(0x6077, 0), 250);
    assert_eq!(lines(&mut r), Vec::<String>::new());
    r.set(0x6071, 0, 5000);
    r.sync_at(1103);
    r.sync_at(1104);
    r.sync_at(1105);
    assert_eq!(r.read(0x6077, 0), 3000);
    assert_eq!(
        lines(&mut r),
        vec!["axis 0: cst target 5,000 ‰ (0x6071 + 0x60B2) above 0x6072 = 3,000 ‰: held there"]
    );
}

/// 0x607F = 8,000 counts/s: the ramp's 100 counts per cycle are 100,000 counts/s. The demand runs
/// at 8,000 counts/s (0x606C reads exactly that half a second in) and lands on 10,000 after about
/// 1.25 s; two seconds after the last set-point the axis stands there exactly.
#[test]
fn a_velocity_limit_holds_csp_back_and_the_line_says_so() {
    let mut r = enabled(&[(0x607F, 0, 8000)], DriveConfig::default(), 8);
    for n in 1..=100i64 {
        r.set(0x607A, 0, 100 * n);
        r.sync_at(1 + n as u64);
    }
    for ms in 102..=500u64 {
        r.sync_at(ms);
    }
    assert_eq!(r.read(0x606C, 0), 8000);
    assert_eq!(r.demand(), 10_000, "0x6062 shows the set-points");
    for ms in 501..=2101u64 {
        r.sync_at(ms);
    }
    assert_eq!(
        (r.pos(), r.read(0x606C, 0), r.read(0x60F4, 0)),
        (10_000, 0, 0)
    );
    assert_eq!(
        lines(&mut r),
        vec![
            "axis 0: csp target step of 100 counts/cycle needs 100,000 counts/s, above 0x607F = \
              8,000 counts/s"
        ]
    );
}

/// 0x6080 = 30 rpm is 5,000 counts/s at 10,000 counts/rev, below 0x607F: the line names 0x6080.
#[test]
fn a_max_motor_speed_holds_csp_back_and_the_line_names_it() {
    let mut r = enabled(&[(0x6080, 0, 30)], DriveConfig::default(), 8);
    r.set(0x607A, 0, 100);
    r.sync_at(2);
    r.sync_at(3);
    assert_eq!(
        lines(&mut r),
        vec![
            "axis 0: csp target step of 100 counts/cycle needs 100,000 counts/s, above 0x6080 = \
              30 rpm (5,000 counts/s)"
        ]
    );
}

/// 0x60C5 = 1,000,000 counts/s²: the ramp's first step asks 1e8 counts/s²; the axis still stands
/// exactly at the last set-point one second after it.
#[test]
fn an_acceleration_limit_holds_csp_back_and_the_line_says_so() {
    let mut dict = dictionary(&[]);
    dict.insert(od::Object::var(
        0x60C5,
        od::SubObject::new(
            "Max acceleration",
            od::DataType::Unsigned32,
            od::AccessType::Rw,
        )
        .with_default(od::Value::Uint(1_000_000)),
    ));
    let mut r = Rig::new(dict, DriveConfig::default());
    r.enable(8);
    ramp(&mut r, 0x607A, 100, 10_000, 0);
    assert_eq!(
        (r.pos(), r.read(0x606C, 0), r.read(0x60F4, 0)),
        (10_000, 0, 0)
    );
    assert_eq!(
        lines(&mut r),
        vec![
            "axis 0: csp target step of 100 counts/cycle needs 100,000,000 counts/s² from 0 \
              counts/s, above 0x60C5 = 1,000,000 counts/s²"
        ]
    );
}

/// A csp target beyond the software limits is held at the limit, and the line says so once; the
/// step to the limit itself, 100 counts in a cycle from rest, is beyond the servo's torque (that is
/// the second line).
#[test]
fn a_software_limit_holds_csp_back_and_the_line_says_so() {
    let mut r = enabled(
        &[(0x607D, 1, -100), (0x607D, 2, 100)],
        DriveConfig::default(),
        8,
    );
    r.set(0x607A, 0, 500);
    for ms in 2..=1001u64 {
        r.sync_at(ms);
    }
    assert_eq!((r.pos(), r.demand()), (100, 100));
    assert_eq!(
        lines(&mut r),
        vec![
            "axis 0: csp target 500 (0x607A + 0x60B0) beyond 0x607D:02 = 100: held there"
                .to_string(),
            format!(
                "axis 0: csp target step of 100 counts/cycle needs 100,000,000 counts/s² from 0 \
                 counts/s, above {SERVO_ACCEL}"
            )
        ]
    );
}

/// The following error fault of `csp_following_error_faults_with_8611` (drive_cyclic.rs): no
/// torque, the set-points 10 · (n − 2) at n ms, 0x6065 = 100, 0x6066 = 3 ms: at 16 ms the error is
/// 140 counts and the drive faults; the line says why. Before it, at 3 ms, the servo's first tick
/// after the first set-point asked 0 → 10,000 counts/s in 1 ms, 1e7 counts/s² · 1e-4 · 2π / 10,000
/// = 0.628 N·m, of a torque limit of 0.
#[test]
fn a_following_error_fault_says_why() {
    let mut r = enabled(
        &[(0x6065, 0, 100), (0x6066, 0, 3)],
        DriveConfig::default(),
        8,
    );
    r.set(0x6072, 0, 0);
    for n in 2..=16i64 {
        r.set(0x607A, 0, 10 * (n - 1));
        r.sync_at(n as u64);
    }
    assert_eq!(r.read(0x603F, 0), 0x8611);
    assert_eq!(
        lines(&mut r),
        vec![
            "axis 0: the servo needs 0.628 N·m, above its torque limit of 0.000 N·m (0x6072 = 0 ‰ \
             of 0x6076 = 1,000 mN·m)",
            "axis 0: following error 140 counts beyond 0x6065 = 100 counts for 0x6066 = 3 ms: \
             fault 0x8611"
        ]
    );
}

/// A mode of operation the drive does not run, written by the process data (no SDO to abort): the
/// write is dropped and the line says why (a stepper runs no cst: 0x6502 = 0x3A5 less bit 9).
#[test]
fn a_mode_refused_from_the_process_data_says_why() {
    let mut r = Rig::new(dictionary(&[]), stepper());
    r.at(1);
    for _ in 0..3 {
        od::hook::deliver(
            &mut r.dict,
            &mut r.drive,
            od::Address::new(0x6060, 0),
            &[10],
            r.now,
        );
    }
    assert_eq!(r.read(0x6061, 0), 0);
    assert_eq!(
        lines(&mut r),
        vec![
            "axis 0: 0x6060 = 10 refused: the modes the drive runs are 0x000001A5 (bit mode − 1, \
              as in 0x6502)"
        ]
    );
}

/// The lines name the axis's own objects: axis 1 of a two-axis drive (objects at 0x6800 on).
#[test]
fn the_lines_name_the_axis_and_its_own_objects() {
    let mut dict = dictionary(&[]);
    add_axis(&mut dict, 1, &[(0x607F, 0, 8000)], &[]);
    let t0 = std::time::Instant::now();
    let mut drive =
        ds402::drive::Drive::from_dictionary(&dict, 1, DriveConfig::default(), t0).unwrap();
    let ms = |n: u64| t0 + std::time::Duration::from_millis(n);
    drive.handle_timeout(ms(1));
    let mut bound = od::hook::Bound::new(&mut dict, &mut drive, ms(1));
    use od::sdo::store::ObjectStore;
    bound.download(od::Address::new(0x6860, 0), &[8]).unwrap();
    for cw in [0x06u16, 0x07, 0x0F] {
        bound
            .download(od::Address::new(0x6840, 0), &cw.to_le_bytes())
            .unwrap();
    }
    bound
        .download(od::Address::new(0x687A, 0), &100i32.to_le_bytes())
        .unwrap();
    drive.sync(ms(2));
    drive.sync(ms(3));
    let line = drive.poll_limit().expect("a line");
    assert_eq!(
        line.message,
        "axis 1: csp target step of 100 counts/cycle needs 100,000 counts/s, above 0x687F = 8,000 \
         counts/s"
    );
    assert_eq!(
        (line.axis, line.object, line.value, line.limit),
        (1, Some((0x687F, 0)), 100_000.0, 8000.0)
    );
    assert_eq!(drive.poll_limit(), None);
}
