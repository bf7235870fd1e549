//! The generic drive behind its dictionary (`od::hook::DeviceHook`): which axes a dictionary has,
//! the objects a drive owns, process values read in the entry's type, parameters staying in the
//! dictionary, the modes 0x6060 accepts, and refusals with their CiA 301 abort codes that change
//! nothing, by SDO and by PDO.

mod drive_rig;

use std::time::Instant;

use drive_rig::*;
use ds402::drive::{Drive, DriveConfig};
use od::hook::{deliver, value, Bound, DeviceHook};
use od::sdo::store::ObjectStore;
use od::{AbortCode, Address, Dictionary};

const ENABLED: u16 = 0x0237;

#[test]
fn axes_of_a_dictionary() {
    let mut dict = dictionary(&[]);
    add_axis(&mut dict, 1, &[], &[]);
    assert_eq!(Drive::axes(&dict), vec![0, 1]);
    let now = Instant::now();
    let drive = Drive::from_dictionary(&dict, 0, DriveConfig::default(), now).unwrap();
    assert_eq!(drive.axis(), 0);
    assert!(Drive::from_dictionary(&dict, 1, DriveConfig::default(), now).is_some());
    assert!(Drive::from_dictionary(&dict, 2, DriveConfig::default(), now).is_none());
    assert!(Drive::from_dictionary(&dict, 9, DriveConfig::default(), now).is_none());
    // Without a status word there is no drive.
    let dict = dictionary_with(&[], &[0x6041]);
    assert_eq!(Drive::axes(&dict), Vec::<u8>::new());
    assert!(Drive::from_dictionary(&dict, 0, DriveConfig::default(), now).is_none());
    assert!(Drive::axes(&Dictionary::new()).is_empty());
}

#[test]
fn a_second_axis_owns_its_own_objects() {
    let mut dict = dictionary(&[]);
    add_axis(&mut dict, 1, &[(0x6081, 0, 2000)], &[]);
    let t0 = Instant::now();
    let mut drive = Drive::from_dictionary(&dict, 1, DriveConfig::default(), t0).unwrap();
    assert_eq!(drive.axis(), 1);
    assert!(drive.owns(0x6840));
    assert!(drive.owns(0x6841));
    assert!(drive.owns(0x687A));
    assert!(!drive.owns(0x6040));
    assert!(!drive.owns(0x6D02)); // 0x6502 of axis 1: the dictionary's
    assert!(!drive.owns(0x1000));
    drive.handle_timeout(t0 + std::time::Duration::from_millis(1));
    let mut bound = Bound::new(
        &mut dict,
        &mut drive,
        t0 + std::time::Duration::from_millis(1),
    );
    bound.download(Address::new(0x6860, 0), &[1]).unwrap();
    for cw in [SHUTDOWN, SWITCH_ON, ENABLE] {
        bound
            .download(Address::new(0x6840, 0), &cw.to_le_bytes())
            .unwrap();
    }
    assert_eq!(
        bound.upload(Address::new(0x6841, 0)),
        Ok(0x0637u16.to_le_bytes().to_vec())
    );
    // Axis 0's objects are untouched.
    assert_eq!(bound.upload(Address::new(0x6041, 0)), Ok(vec![0, 0]));
}

#[test]
fn process_values_are_read_in_the_entrys_type() {
    let mut r = Rig::with(&[]);
    r.enable(1);
    r.set(0x607A, 0, -1000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(2000);
    let mut bound = Bound::new(&mut r.dict, &mut r.drive, r.now);
    assert_eq!(
        bound.upload(Address::new(0x6064, 0)),
        Ok((-1000i32).to_le_bytes().to_vec())
    );
    assert_eq!(
        bound.upload(Address::new(0x6063, 0)),
        Ok((-1000i32).to_le_bytes().to_vec())
    );
    assert_eq!(bound.upload(Address::new(0x6061, 0)), Ok(vec![1]));
    assert_eq!(
        bound.upload(Address::new(0x6041, 0)),
        Ok(0x1637u16.to_le_bytes().to_vec())
    );
    assert_eq!(bound.upload(Address::new(0x603F, 0)), Ok(vec![0, 0]));
    // A TPDO reads the same values.
    let mut buf = [0u8; 8];
    assert_eq!(
        value(&r.dict, &r.drive, Address::new(0x6062, 0), &mut buf),
        &(-1000i32).to_le_bytes()[..]
    );
}

#[test]
fn parameters_stay_in_the_dictionary() {
    let mut r = Rig::with(&[]);
    let mut buf = [0u8; 8];
    assert_eq!(r.drive.read(Address::new(0x6081, 0), &mut buf), None);
    assert_eq!(r.drive.read(Address::new(0x6040, 0), &mut buf), None);
    r.set(0x6081, 0, 2000);
    assert_eq!(r.read(0x6081, 0), 2000);
    // ... and the drive uses the value written: 0 → 2000 at 2000 counts/s ends after 1.2 s.
    r.enable(1);
    r.set(0x607A, 0, 2000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(1200);
    assert_eq!(r.sw() & 0x0400, 0);
    r.at(1201);
    assert_eq!(r.sw() & 0x0400, 0x0400);
}

#[test]
fn the_drive_starts_at_the_dictionarys_current_values() {
    // A DCF's ParameterValue is the current value: 0x6081 = 2000 where the default is 1000.
    let mut r = Rig::with(&[(0x6081, 0, 2000)]);
    r.enable(1);
    r.set(0x607A, 0, 2000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(1200);
    assert_eq!(r.sw() & 0x0400, 0);
    r.at(1201);
    assert_eq!((r.sw() & 0x0400, r.pos()), (0x0400, 2000));
}

#[test]
fn an_eds_file_becomes_a_drive() {
    let text = "\
[DeviceInfo]
VendorName=Test
ProductName=Drive
[MandatoryObjects]
SupportedObjects=1
1=0x1000
[1000]
ParameterName=Device type
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x00020192
[OptionalObjects]
SupportedObjects=9
1=0x6040
2=0x6041
3=0x6060
4=0x6061
5=0x6064
6=0x607A
7=0x6081
8=0x6083
9=0x6084
[6040]
ParameterName=Controlword
ObjectType=0x7
DataType=0x0006
AccessType=rww
PDOMapping=1
[6041]
ParameterName=Statusword
ObjectType=0x7
DataType=0x0006
AccessType=ro
PDOMapping=1
[6060]
ParameterName=Modes of operation
ObjectType=0x7
DataType=0x0002
AccessType=rww
DefaultValue=0
[6061]
ParameterName=Modes of operation display
ObjectType=0x7
DataType=0x0002
AccessType=ro
[6064]
ParameterName=Position actual value
ObjectType=0x7
DataType=0x0004
AccessType=ro
[607A]
ParameterName=Target position
ObjectType=0x7
DataType=0x0004
AccessType=rww
DefaultValue=0
[6081]
ParameterName=Profile velocity
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=2000
[6083]
ParameterName=Profile acceleration
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=10000
[6084]
ParameterName=Profile deceleration
ObjectType=0x7
DataType=0x0007
AccessType=rw
";
    let desc = od::eds::read(text.as_bytes(), "drive.eds").expect("EDS reads");
    let mut dict = desc.dictionary;
    assert_eq!(Drive::axes(&dict), vec![0]);
    let t0 = Instant::now();
    let mut drive = Drive::from_dictionary(&dict, 0, DriveConfig::default(), t0).unwrap();
    // Without 0x6502 the modes come from the objects: only pp (0x607A and 0x6081).
    assert_eq!(drive.supported_modes(), 0x0001);
    drive.handle_timeout(t0 + std::time::Duration::from_millis(1));
    {
        let mut bound = Bound::new(
            &mut dict,
            &mut drive,
            t0 + std::time::Duration::from_millis(1),
        );
        assert_eq!(
            bound.download(Address::new(0x6060, 0), &[3]),
            Err(AbortCode::InvalidValue)
        );
        bound.download(Address::new(0x6060, 0), &[1]).unwrap();
        bound
            .download(Address::new(0x607A, 0), &2000i32.to_le_bytes())
            .unwrap();
        for cw in [SHUTDOWN, SWITCH_ON, ENABLE, ENABLE | NEW_SETPOINT] {
            bound
                .download(Address::new(0x6040, 0), &cw.to_le_bytes())
                .unwrap();
        }
    }
    // 0x6084 has no default: 0, which the drive takes as its own default ramp (100 000 counts/s²).
    // 0x6081 = 2000, 0x6083 = 10 000: 0.2 s up (200 counts), 0.02 s down (20 counts), cruise 1780
    // counts in 0.89 s: 1.11 s.
    assert_eq!(
        drive.poll_timeout(),
        Some(t0 + std::time::Duration::from_millis(2))
    );
    drive.handle_timeout(t0 + std::time::Duration::from_millis(2));
    drive.handle_timeout(t0 + std::time::Duration::from_millis(1110));
    assert_eq!(drive.status_word() & 0x0400, 0);
    drive.handle_timeout(t0 + std::time::Duration::from_millis(1111));
    assert_eq!(drive.status_word(), 0x1637);
    assert_eq!(drive.position(), 2000);
}

#[test]
fn modes_of_operation() {
    // 0x6502 = 0x3A5: pp, pv, hm, csp, csv, cst.
    let mut r = Rig::with(&[]);
    assert_eq!(r.drive.supported_modes(), 0x3A5);
    for mode in [0, 1, 3, 6, 8, 9, 10] {
        assert_eq!(r.write(0x6060, 0, mode), Ok(()), "mode {mode}");
        assert_eq!(r.read(0x6061, 0), mode, "mode {mode}");
    }
    // Not implemented (vl 2, tq 4, ip 7) even where 0x6502 declares them; not defined.
    let mut r = Rig::with(&[(0x6502, 0, 0x3E7)]);
    assert_eq!(r.drive.supported_modes(), 0x3A5);
    r.set(0x6060, 0, 1);
    for mode in [2, 4, 7, 5, 11, -1, -128] {
        assert_eq!(
            r.write(0x6060, 0, mode),
            Err(AbortCode::InvalidValue),
            "mode {mode}"
        );
        assert_eq!(r.read(0x6060, 0), 1, "mode {mode}: the dictionary keeps 1");
        assert_eq!(r.read(0x6061, 0), 1, "mode {mode}: the drive keeps 1");
    }
    // 0x6502 narrower than what the drive can do.
    let mut r = Rig::with(&[(0x6502, 0, 0x0001)]);
    assert_eq!(r.write(0x6060, 0, 3), Err(AbortCode::InvalidValue));
    assert_eq!(r.write(0x6060, 0, 1), Ok(()));
    // Without 0x6502 and 0x60C2: pp, pv and hm from their objects.
    let r = Rig::new(
        dictionary_with(&[], &[0x6502, 0x60C2]),
        DriveConfig::default(),
    );
    assert_eq!(r.drive.supported_modes(), 0x0025);
    // Without 0x6502 but with 0x60C2: the cyclic modes too.
    let r = Rig::new(dictionary_with(&[], &[0x6502]), DriveConfig::default());
    assert_eq!(r.drive.supported_modes(), 0x03A5);
    // pp needs its profile velocity 0x6081 besides the target 0x607A (csp the target alone).
    let r = Rig::new(
        dictionary_with(&[], &[0x6502, 0x6081]),
        DriveConfig::default(),
    );
    assert_eq!(r.drive.supported_modes(), 0x03A4);
    // Without 0x6502 and 0x60C2, on a network whose SYNC has a clock of its own (EtherCAT's
    // SYNC0): the cyclic modes from their targets, pp, pv, hm as before: 0x03A5.
    let r = Rig::new(
        dictionary_with(&[], &[0x6502, 0x60C2]),
        DriveConfig {
            sync_clock: true,
            ..DriveConfig::default()
        },
    );
    assert_eq!(r.drive.supported_modes(), 0x03A5);
    // 0x6502 without a value (0: an ESI object without DefaultData, as Elmo's): as without it.
    let r = Rig::new(
        dictionary_with(&[(0x6502, 0, 0)], &[0x60C2]),
        DriveConfig::default(),
    );
    assert_eq!(r.drive.supported_modes(), 0x0025);
}

#[test]
fn refused_values_and_their_abort_codes() {
    // (index, sub, value, abort code)
    let cases: &[(u16, u8, i64, AbortCode)] = &[
        (0x605A, 0, 9, AbortCode::ValueTooHigh),
        (0x605A, 0, -1, AbortCode::ValueTooLow),
        (0x605B, 0, 2, AbortCode::ValueTooHigh),
        (0x605C, 0, 2, AbortCode::ValueTooHigh),
        (0x605D, 0, 0, AbortCode::ValueTooLow),
        (0x605D, 0, 5, AbortCode::ValueTooHigh),
        (0x605E, 0, 5, AbortCode::ValueTooHigh),
        (0x6086, 0, 1, AbortCode::InvalidValue),
        (0x6086, 0, 3, AbortCode::InvalidValue),
        (0x6098, 0, 15, AbortCode::InvalidValue),
        (0x6098, 0, 36, AbortCode::InvalidValue),
        (0x6098, 0, -1, AbortCode::InvalidValue),
        (0x6083, 0, 0, AbortCode::ValueTooLow),
        (0x6084, 0, 0, AbortCode::ValueTooLow),
        (0x6085, 0, 0, AbortCode::ValueTooLow),
        (0x609A, 0, 0, AbortCode::ValueTooLow),
        (0x6099, 1, 0, AbortCode::ValueTooLow),
        (0x6099, 2, 0, AbortCode::ValueTooLow),
        (0x6076, 0, 0, AbortCode::ValueTooLow),
        (0x608F, 1, 0, AbortCode::ValueTooLow),
    ];
    for &(index, sub, value, code) in cases {
        let mut r = Rig::with(&[]);
        r.at(1);
        let before = r.read(index, sub);
        assert_eq!(r.write(index, sub, value), Err(code), "0x{index:04X}:{sub}");
        assert_eq!(r.read(index, sub), before, "0x{index:04X}:{sub} unchanged");
    }
}

/// The values at the edges of what the drive accepts are taken (CiA 402-2: option codes
/// 0x605A 0…8, 0x605B and 0x605C 0…1, 0x605D 1…4, 0x605E 0…4; motion profile type 0; the homing
/// methods the drive runs; a ramp or speed of 1).
#[test]
fn values_at_the_edges_are_accepted() {
    let cases: &[(u16, u8, i64)] = &[
        (0x605A, 0, 0),
        (0x605A, 0, 8),
        (0x605B, 0, 0),
        (0x605B, 0, 1),
        (0x605C, 0, 0),
        (0x605C, 0, 1),
        (0x605D, 0, 1),
        (0x605D, 0, 4),
        (0x605E, 0, 0),
        (0x605E, 0, 4),
        (0x6086, 0, 0),
        (0x6098, 0, 0),
        (0x6098, 0, 14),
        (0x6098, 0, 17),
        (0x6098, 0, 37),
        (0x6083, 0, 1),
        (0x6084, 0, 1),
        (0x6085, 0, 1),
        (0x6099, 1, 1),
        (0x6099, 2, 1),
        (0x609A, 0, 1),
        (0x6076, 0, 1),
        (0x608F, 1, 1),
    ];
    for &(index, sub, value) in cases {
        let mut r = Rig::with(&[]);
        r.at(1);
        assert_eq!(
            r.write(index, sub, value),
            Ok(()),
            "0x{index:04X}:{sub} = {value}"
        );
        assert_eq!(r.read(index, sub), value, "0x{index:04X}:{sub}");
    }
}

#[test]
fn a_refused_option_code_leaves_the_drive_as_it_was() {
    let mut r = Rig::with(&[]);
    r.enable(0);
    assert_eq!(r.write(0x605A, 0, 9), Err(AbortCode::ValueTooHigh));
    // Still 2: a quick stop ends in Switch on disabled.
    r.cw(QUICK_STOP);
    r.at(2);
    assert_eq!(r.sw(), 0x0260);
}

#[test]
fn the_encoder_resolution_is_written_only_with_the_power_off() {
    let mut r = Rig::with(&[]);
    r.enable(1);
    assert_eq!(r.write(0x608F, 1, 4000), Err(AbortCode::DeviceState));
    assert_eq!(r.read(0x608F, 1), 10_000);
    r.cw(DISABLE_VOLTAGE);
    assert_eq!(r.write(0x608F, 1, 4000), Ok(()));
    // 0x6080 is in rpm: 6 rpm at 4000 counts/rev is 400 counts/s.
    r.set(0x6080, 0, 6);
    r.cw(SHUTDOWN);
    r.cw(ENABLE);
    r.set(0x607A, 0, 100_000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.wait(500);
    assert_eq!(r.read(0x606C, 0), 400);
}

#[test]
fn process_values_cannot_be_written() {
    let mut r = Rig::with(&[]);
    // The dictionary refuses first (read-only entries).
    assert_eq!(r.write(0x6064, 0, 5), Err(AbortCode::ReadOnly));
    assert_eq!(r.write(0x6041, 0, 5), Err(AbortCode::ReadOnly));
    // The hook refuses too, for a node that maps them into an RPDO regardless.
    assert_eq!(
        r.drive.check(Address::new(0x6064, 0), &5i32.to_le_bytes()),
        Err(AbortCode::ReadOnly)
    );
    assert_eq!(
        r.drive
            .write(Address::new(0x6041, 0), &5u16.to_le_bytes(), r.now),
        Err(AbortCode::ReadOnly)
    );
    // A wrong length is the dictionary's refusal.
    assert_eq!(
        r.write_bytes(0x6060, 0, &[1, 0]),
        Err(AbortCode::LengthTooHigh)
    );
}

#[test]
fn rpdo_delivery_goes_through_the_drive() {
    let mut r = Rig::with(&[(0x6060, 0, 1)]);
    r.at(1);
    for cw in [SHUTDOWN, SWITCH_ON, ENABLE] {
        deliver(
            &mut r.dict,
            &mut r.drive,
            Address::new(0x6040, 0),
            &cw.to_le_bytes(),
            r.now,
        );
    }
    assert_eq!(r.drive.status_word(), ENABLED | 0x0400);
    assert_eq!(r.read(0x6040, 0), 0x0F);
    assert_eq!(r.drive.control_word(), 0x0F);
    // A value the drive refuses is dropped: neither the drive nor the dictionary takes it.
    deliver(
        &mut r.dict,
        &mut r.drive,
        Address::new(0x6060, 0),
        &[7],
        r.now,
    );
    assert_eq!(r.read(0x6060, 0), 1);
    assert_eq!(r.drive.mode(), 1);
}

#[test]
fn an_idle_drive_asks_for_no_time() {
    let mut r = Rig::with(&[]);
    assert!(r.drive.poll_timeout().is_some());
    r.at(1);
    assert_eq!(r.drive.poll_timeout(), None);
    // A write asks for the next tick, where the node looks at its event-driven TPDOs; after it the
    // drive, switched on but not enabled, is idle again.
    r.cw(SHUTDOWN);
    r.cw(SWITCH_ON);
    assert_eq!(
        r.drive.poll_timeout(),
        Some(r.t0 + std::time::Duration::from_millis(2))
    );
    r.at(2);
    assert_eq!(r.drive.poll_timeout(), None);
    r.cw(ENABLE);
    assert_eq!(
        r.drive.poll_timeout(),
        Some(r.t0 + std::time::Duration::from_millis(3))
    );
    // A long idle time is skipped, not simulated tick by tick, and the clock is right afterwards.
    r.cw(DISABLE_VOLTAGE);
    r.at(3_600_000);
    assert_eq!(r.drive.now(), r.t0 + std::time::Duration::from_secs(3600));
}

#[test]
fn a_write_to_an_idle_drive_is_made_at_its_own_instant() {
    // A node that lets the idle drive's clock stand at 1 ms (it asks for no tick) and delivers an
    // enable and a set-point at 5 s: each write carries 5 s, the drive runs up to it first, and the
    // move starts at 5 s.
    let mut r = Rig::with(&[(0x6060, 0, 1)]);
    r.at(1);
    assert_eq!(r.drive.poll_timeout(), None);
    let t = r.t0 + std::time::Duration::from_millis(5000);
    r.now = t;
    for cw in [SHUTDOWN, SWITCH_ON, ENABLE] {
        r.cw(cw);
    }
    r.set(0x607A, 0, 2000);
    r.cw(ENABLE | NEW_SETPOINT);
    assert_eq!(r.drive.now(), t);
    // The next tick is the one after the writes.
    assert_eq!(
        r.drive.poll_timeout(),
        Some(r.t0 + std::time::Duration::from_millis(5001))
    );
    assert_eq!(r.drive.position(), 0);
    assert_eq!(r.drive.status_word(), 0x1237);
    // 2.1 s later the move has ended.
    r.at(7099);
    assert_eq!(r.drive.status_word() & 0x0400, 0);
    r.at(7100);
    assert_eq!((r.drive.status_word(), r.drive.position()), (0x1637, 2000));
}

/// The encoder resolution 0x608F is increments per motor revolutions (CiA 402-2, object 0x608F):
/// 8000 increments per 2 revolutions are 4000 counts/rev, so 0x6080 = 6 rpm limits the speed to
/// 400 counts/s.
#[test]
fn the_encoder_resolution_is_increments_per_motor_revolutions() {
    let mut r = Rig::with(&[(0x608F, 1, 8000), (0x608F, 2, 2), (0x6080, 0, 6)]);
    r.enable(1);
    r.set(0x607A, 0, 100_000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.wait(500);
    assert_eq!(r.read(0x606C, 0), 400);
}

/// A stepper drive offers no cyclic synchronous torque mode (10): 0x6502 declares 0x3A5, the drive
/// supports 0x1A5, and 0x6060 refuses 10 as it refuses the modes it does not implement (vl, 2).
#[test]
fn a_stepper_supports_the_declared_modes_but_cyclic_torque() {
    let config = DriveConfig {
        motor: ds402::drive::MotorConfig {
            kind: ds402::drive::MotorKind::Stepper,
            ..Default::default()
        },
        ..DriveConfig::default()
    };
    let mut r = Rig::new(dictionary(&[]), config);
    assert_eq!(r.drive.supported_modes(), 0x01A5);
    r.at(1);
    assert_eq!(r.write(0x6060, 0, 10), Err(AbortCode::InvalidValue));
    assert_eq!(r.write(0x6060, 0, 2), Err(AbortCode::InvalidValue));
    assert_eq!(r.write(0x6060, 0, 3), Ok(()));
    assert_eq!((r.read(0x6061, 0), r.drive.mode()), (3, 3));
}

/// The drive keeps the configuration it was made with, and the simulated machine can be changed
/// while it runs: a positive limit switch moved onto the axis shows in 0x60FD bit 1 (CiA 402-2,
/// object 0x60FD).
#[test]
fn the_configuration_and_the_machine_at_run_time() {
    let config = DriveConfig {
        tick: std::time::Duration::from_micros(500),
        sim: ds402::drive::SimConfig {
            home_switch: Some(5000),
            ..Default::default()
        },
        ..DriveConfig::default()
    };
    let mut r = Rig::new(dictionary(&[]), config.clone());
    assert_eq!(r.drive.config(), &config);
    r.at(1);
    assert_eq!(r.read(0x60FD, 0), 0);
    r.drive.sim_mut().positive_limit = Some(0);
    r.at(2);
    assert_eq!(r.read(0x60FD, 0), 0b010);
    assert_eq!(r.drive.config().sim.positive_limit, Some(0));
}

/// Objects the dictionary lacks take the motor's configuration: 0x6072 its peak torque, 0x6076 its
/// rated torque, 0x608F its counts per revolution (CiA 402-2, objects 0x6072, 0x6076, 0x608F).
#[test]
fn missing_motor_objects_take_the_motor_configuration() {
    use ds402::drive::MotorConfig;
    let motor = |m: MotorConfig| DriveConfig {
        motor: m,
        ..DriveConfig::default()
    };
    // Peak torque 8 ‰: a ramp of 1 000 000 counts/s² (62.8 ‰ of 1 N·m) gets 8 ‰.
    let config = motor(MotorConfig {
        peak_torque_permille: 8,
        ..MotorConfig::default()
    });
    let mut r = Rig::new(
        dictionary_with(&[(0x6083, 0, 1_000_000)], &[0x6072]),
        config,
    );
    r.enable(1);
    r.set(0x607A, 0, 100_000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.at(2);
    assert_eq!(r.read(0x6077, 0), 8);
    // Rated torque 2 N·m: holding against 0.5 N·m of load is 250 ‰.
    let config = motor(MotorConfig {
        rated_torque: 2.0,
        load_torque: 0.5,
        ..MotorConfig::default()
    });
    let mut r = Rig::new(dictionary_with(&[], &[0x6076]), config);
    r.enable(1);
    r.at(100);
    assert_eq!((r.pos(), r.read(0x6077, 0)), (0, 250));
    // 4000 counts/rev: 0x6080 = 6 rpm is 400 counts/s.
    let config = motor(MotorConfig {
        counts_per_rev: 4000,
        ..MotorConfig::default()
    });
    let mut r = Rig::new(dictionary_with(&[(0x6080, 0, 6)], &[0x608F]), config);
    r.enable(1);
    r.set(0x607A, 0, 100_000);
    r.cw(ENABLE | NEW_SETPOINT);
    r.wait(500);
    assert_eq!(r.read(0x606C, 0), 400);
}

/// An input that reaches an idle drive asks for the drive's next tick, and only that one: a second
/// look at the same instant keeps the request, the tick itself ends it. Forced 0x60FD bits read as
/// forced until the inputs are released.
#[test]
fn an_input_to_an_idle_drive_asks_for_its_next_tick_once() {
    let mut r = Rig::with(&[(0x6060, 0, 1)]);
    r.at(5);
    assert_eq!(r.drive.poll_timeout(), None);
    let t0 = r.t0;
    let ms = |n: u64| t0 + std::time::Duration::from_millis(n);
    r.drive.set_input(ms(5), 20, Some(true));
    assert_eq!(r.drive.poll_timeout(), Some(ms(6)));
    // The same instant again: no tick has passed, the request stands.
    r.drive.handle_timeout(ms(5));
    assert_eq!(r.drive.poll_timeout(), Some(ms(6)));
    assert_eq!(r.read(0x60FD, 0), 1 << 20);
    // The tick ends it.
    r.drive.handle_timeout(ms(6));
    assert_eq!(r.drive.poll_timeout(), None);
    // Released: the bit follows the simulated switches again (none at bit 20), and no tick is asked.
    r.drive.release_inputs();
    assert_eq!(r.read(0x60FD, 0), 0);
    assert_eq!(r.drive.poll_timeout(), None);
}
