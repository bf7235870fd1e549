//! `ds402::drive::fill`: what a drive reports where its description gives no value (0x1000, 0x6502),
//! the factory settings it takes where a value of 0 would stop it, the values its rules would refuse
//! replaced by those it runs with; every change said once, and a default that a reset keeps. Then,
//! on every CiA 402 EDS and DCF of the corpus beside the checkout: each value the drive reports is
//! accepted when written back.

use std::time::Instant;

use ds402::drive::{fill, Drive, DriveConfig, MotorKind};
use od::event::EventKind;
use od::hook::Bound;
use od::sdo::store::ObjectStore;
use od::{AccessType, Address, DataType, Dictionary, Object, SubObject, Value};

/// A VAR `index` of `ty`, read-write, with `default` where given.
fn var(dict: &mut Dictionary, index: u16, ty: DataType, default: Option<i64>) {
    let mut e = SubObject::new(format!("0x{index:04X}"), ty, AccessType::Rw);
    if let Some(v) = default {
        e = e.with_default(if ty.is_signed() {
            Value::Int(v)
        } else {
            Value::Uint(v as u64)
        });
    }
    dict.insert(Object::var(index, e));
}

/// A drive axis at `base` with 0x6040/0x6041 and `extra` objects.
fn axis(dict: &mut Dictionary, base: u16, extra: &[(u16, DataType, Option<i64>)]) {
    var(dict, base + 0x40, DataType::Unsigned16, Some(0));
    var(dict, base + 0x41, DataType::Unsigned16, Some(0));
    for &(index, ty, default) in extra {
        var(dict, base + index - 0x6000, ty, default);
    }
}

fn u32_at(dict: &Dictionary, index: u16, sub: u8) -> u64 {
    match dict.read_value(index, sub).unwrap() {
        Value::Uint(v) => v,
        Value::Int(v) => v as u64,
        other => panic!("{other:?}"),
    }
}

fn int_at(dict: &Dictionary, index: u16) -> i64 {
    dict.read_value(index, 0).unwrap().as_i128().unwrap() as i64
}

/// A servo drive whose description leaves out most values: each one filled or adjusted, in this
/// order, with these words; the description's own values stand.
#[test]
fn a_servo_description_without_values() {
    use DataType::{Integer16 as I16, Integer8 as I8, Unsigned16 as U16, Unsigned32 as U32};
    let mut dict = Dictionary::new();
    var(&mut dict, 0x1000, U32, None);
    axis(
        &mut dict,
        0x6000,
        &[
            (0x605D, I16, None),
            (0x6060, I8, None),
            (0x6072, U16, None),
            (0x6076, U32, Some(0)),
            (0x607A, DataType::Integer32, Some(0)),
            (0x607F, U32, None),
            (0x6081, U32, None),
            (0x6083, U32, Some(0)),
            (0x6084, U32, Some(30_000)),
            (0x6098, I8, Some(0)),
            (0x6502, U32, None),
        ],
    );
    let events = fill(&mut dict, &DriveConfig::default());
    let lines: Vec<String> = events.iter().map(|e| e.line()).collect();
    assert_eq!(
        lines,
        [
            "0x1000 device type = 0x00020192 (the description gives no value: a CiA 402 servo drive)",
            "0x6502 supported drive modes = 0x00000021 (the description gives no value: the modes \
             this drive runs whose objects it has)",
            "0x607F max profile velocity = 500000 counts/s (the description gives no value (0), \
             which would allow no speed: a factory default)",
            "0x6072 max torque = 3000 ‰ of the rated torque (the description gives no value (0), \
             which would leave the motor no torque: a factory default)",
            "0x6076 motor rated torque = 1000 mN·m (the description gives 0, which makes every \
             torque given in ‰ of it 0: a factory default)",
            "0x6081 profile velocity = 10000 counts/s (the description gives no value (0), which \
             would stop every profile position move: a factory default)",
            "0x6083 profile acceleration = 100000 counts/s² (the description gives 0, which would \
             stop every move: a factory default)",
            "0x605D halt option code = 1 (the description gives no value (0), a code outside 1 to \
             4, which it refuses: its default)",
        ]
    );
    let kinds: Vec<EventKind> = events.iter().map(|e| e.kind).collect();
    use EventKind::{Adjusted, Filled};
    assert_eq!(
        kinds,
        [Filled, Filled, Filled, Filled, Adjusted, Filled, Adjusted, Filled]
    );
    // 0x1000 reads 92 01 02 00.
    assert_eq!(dict.read(0x1000, 0).unwrap(), [0x92, 0x01, 0x02, 0x00]);
    assert_eq!(u32_at(&dict, 0x6502, 0), 0x21);
    assert_eq!(u32_at(&dict, 0x6083, 0), 100_000);
    // The description's own values stand: 0x6084, 0x6098 = 0 (a method the drive takes: none).
    assert_eq!(u32_at(&dict, 0x6084, 0), 30_000);
    assert_eq!(int_at(&dict, 0x6098), 0);
    assert_eq!(int_at(&dict, 0x6060), 0);
    // Defaults: a reset keeps them, and once filled there is nothing more to fill.
    dict.reset(5);
    assert_eq!(u32_at(&dict, 0x607F, 0), 500_000);
    assert_eq!(u32_at(&dict, 0x6072, 0), 3000);
    assert_eq!(int_at(&dict, 0x605D), 1);
    assert!(fill(&mut dict, &DriveConfig::default()).is_empty());
    // The drive reports them and takes them back.
    let drive_config = DriveConfig::default();
    let mut drive = Drive::from_dictionary(&dict, 0, drive_config, Instant::now()).unwrap();
    assert_eq!(drive.supported_modes(), 0x21);
    let mut node = Bound::new(&mut dict, &mut drive, Instant::now());
    for index in [
        0x605Du16, 0x6072, 0x6076, 0x607F, 0x6081, 0x6083, 0x6084, 0x6098,
    ] {
        let at = Address::new(index, 0);
        let bytes = node.upload(at).unwrap();
        assert_eq!(node.download(at, &bytes), Ok(()), "0x{index:04X}");
    }
}

/// A stepper: type 0x04 in 0x1000, and no cyclic synchronous torque among its modes.
#[test]
fn a_stepper_reports_its_type_and_no_cst() {
    let mut dict = Dictionary::new();
    var(&mut dict, 0x1000, DataType::Unsigned32, None);
    axis(
        &mut dict,
        0x6000,
        &[
            (0x6071, DataType::Integer16, Some(0)),
            (0x607A, DataType::Integer32, Some(0)),
            (0x60C2, DataType::Unsigned8, Some(1)),
            (0x6502, DataType::Unsigned32, Some(0)),
        ],
    );
    let mut config = DriveConfig::default();
    config.motor.kind = MotorKind::Stepper;
    let events = fill(&mut dict, &config);
    assert_eq!(dict.read(0x1000, 0).unwrap(), [0x92, 0x01, 0x04, 0x00]);
    // csp (bit 7) only: cst (bit 9) is not run on a stepper.
    assert_eq!(u32_at(&dict, 0x6502, 0), 0x80);
    assert_eq!(
        events[1].line(),
        "0x6502 supported drive modes = 0x00000080 (the description gives 0, no mode at all: the \
         modes this drive runs whose objects it has)"
    );
    assert_eq!(events[1].kind, EventKind::Adjusted);
    assert_eq!(
        events[0].reason,
        "the description gives no value: a CiA 402 stepper motor drive"
    );
}

/// Two axes: 0x1000 added (the description has none) with 0xFFFF, several logical devices; each
/// axis's own type at 0x67FF + 0x800 · axis; the second axis's objects named so.
#[test]
fn two_axes_report_several_devices() {
    let mut dict = Dictionary::new();
    axis(
        &mut dict,
        0x6000,
        &[
            (0x67FF, DataType::Unsigned32, None),
            (0x6502, DataType::Unsigned32, None),
        ],
    );
    // Standard indices, at 0x6800 + (index − 0x6000): 0x6FFF, 0x6D02, 0x6898, 0x6883.
    axis(
        &mut dict,
        0x6800,
        &[
            (0x67FF, DataType::Unsigned32, None),
            (0x6502, DataType::Unsigned32, None),
            (0x6098, DataType::Integer8, Some(35)),
            (0x6083, DataType::Unsigned32, None),
        ],
    );
    let events = fill(&mut dict, &DriveConfig::default());
    let lines: Vec<String> = events.iter().map(|e| e.line()).collect();
    assert_eq!(
        lines[..3],
        [
            "0x1000 device type = 0xFFFF0192 (the description has no 0x1000, which CiA 301 makes \
             mandatory: a CiA 402 servo drive of 2 axes (0xFFFF: several logical devices, each \
             describing itself at 0x67FF + 0x800 · axis))",
            "0x67FF device type of axis 1 = 0x00020192 (the description gives no value: a CiA 402 \
             servo drive)",
            "0x6FFF device type of axis 2 = 0x00020192 (the description gives no value: a CiA 402 \
             servo drive)",
        ]
    );
    assert_eq!(dict.read(0x1000, 0).unwrap(), [0x92, 0x01, 0xFF, 0xFF]);
    let o = dict.object(0x1000).unwrap();
    assert_eq!(o.subs[&0].access.kind, AccessType::Ro);
    // Axis 1 has no mode objects: no modes, 0x6502 stays without a value. Axis 2: homing (0x6E98).
    assert!(!lines.iter().any(|l| l.starts_with("0x6502")));
    assert_eq!(u32_at(&dict, 0x6D02, 0), 0x20);
    assert!(lines.contains(
        &"0x6D02 supported drive modes (axis 2) = 0x00000020 (the description gives no value: the \
          modes this drive runs whose objects it has)"
            .to_string()
    ));
    assert!(lines.contains(
        &"0x6883 profile acceleration (axis 2) = 100000 counts/s² (the description gives no value \
          (0), which would stop every move: a factory default)"
            .to_string()
    ));
}

/// The description's own values always win where the drive can run with them: no event, nothing
/// changed (a device type other than CiA 402's included).
#[test]
fn explicit_values_stand() {
    let mut dict = Dictionary::new();
    var(&mut dict, 0x1000, DataType::Unsigned32, Some(0x0042_0192));
    axis(
        &mut dict,
        0x6000,
        &[
            (0x6502, DataType::Unsigned32, Some(0x25)),
            (0x6083, DataType::Unsigned32, Some(30_000)),
            (0x607F, DataType::Unsigned32, Some(12_000)),
            (0x6060, DataType::Integer8, Some(1)),
            (0x605A, DataType::Integer16, Some(6)),
        ],
    );
    let before = dict.clone();
    assert!(fill(&mut dict, &DriveConfig::default()).is_empty());
    assert_eq!(dict, before);
    // A dictionary without drive axes is not touched at all.
    let mut io = Dictionary::new();
    var(&mut io, 0x1000, DataType::Unsigned32, None);
    var(&mut io, 0x6083, DataType::Unsigned32, None);
    let before = io.clone();
    assert!(fill(&mut io, &DriveConfig::default()).is_empty());
    assert_eq!(io, before);
}

/// A factory value is held to the entry's type and limits: 0x6083 with HighLimit 50,000 gets
/// 50,000; 0x60C5 of INTEGER32 gets 2,147,483,647; 0x607F follows 0x6080 and 0x608F.
#[test]
fn factory_values_fit_their_entries() {
    let mut dict = Dictionary::new();
    var(&mut dict, 0x1000, DataType::Unsigned32, Some(0x0002_0192));
    axis(
        &mut dict,
        0x6000,
        &[
            (0x60C5, DataType::Integer32, Some(0)),
            (0x6080, DataType::Unsigned32, Some(1200)),
            (0x607F, DataType::Unsigned32, Some(0)),
        ],
    );
    let mut limited = SubObject::new("acc", DataType::Unsigned32, AccessType::Rw)
        .with_limits(Some(Value::Uint(1)), Some(Value::Uint(50_000)));
    limited.default = None;
    dict.insert(Object::var(0x6083, limited));
    dict.insert(
        Object::structured(
            0x608F,
            "Position encoder resolution",
            od::ObjectKind::Record,
        )
        .with_sub(
            0,
            SubObject::new("n", DataType::Unsigned8, AccessType::Ro).with_default(Value::Uint(2)),
        )
        .with_sub(
            1,
            SubObject::new("inc", DataType::Unsigned32, AccessType::Rw),
        )
        .with_sub(
            2,
            SubObject::new("rev", DataType::Unsigned32, AccessType::Rw)
                .with_default(Value::Uint(2)),
        ),
    );
    let events = fill(&mut dict, &DriveConfig::default());
    assert_eq!(u32_at(&dict, 0x6083, 0), 50_000);
    assert_eq!(int_at(&dict, 0x60C5), 2_147_483_647);
    // 10,000 counts per 2 revolutions: 5,000 counts/rev; 1,200 rpm = 20 rev/s = 100,000 counts/s.
    assert_eq!(u32_at(&dict, 0x608F, 1), 10_000);
    assert_eq!(u32_at(&dict, 0x607F, 0), 100_000);
    let lines: Vec<String> = events.iter().map(|e| e.line()).collect();
    assert_eq!(
        lines[0],
        "0x608F:01 encoder increments = 10000 counts (the description gives no value (0), which \
         gives no position: a factory default)"
    );
    assert!(lines.contains(
        &"0x60C5 max acceleration = 2147483647 counts/s² (the description gives 0, which would \
          stop every move: a factory default)"
            .to_string()
    ));
}

/// Values the drive's rules refuse are replaced by those it runs with: a mode it does not run
/// (Pilz's 7), a homing method it does not run, a motion profile type other than 0, an option code
/// out of range.
#[test]
fn refused_values_become_the_drive_s_defaults() {
    let mut dict = Dictionary::new();
    var(&mut dict, 0x1000, DataType::Unsigned32, Some(0x0002_0192));
    axis(
        &mut dict,
        0x6000,
        &[
            (0x6502, DataType::Unsigned32, Some(0x43)),
            (0x6060, DataType::Integer8, Some(7)),
            (0x6098, DataType::Integer8, Some(15)),
            (0x6086, DataType::Integer16, Some(1)),
            (0x605A, DataType::Integer16, Some(9)),
            (0x605E, DataType::Integer16, Some(-1)),
        ],
    );
    let events = fill(&mut dict, &DriveConfig::default());
    let lines: Vec<String> = events.iter().map(|e| e.line()).collect();
    assert_eq!(
        lines,
        [
            "0x605A quick stop option code = 2 (the description gives 9, a code outside 0 to 8, \
             which it refuses: its default)",
            "0x605E fault reaction option code = 2 (the description gives -1, a code outside 0 to \
             4, which it refuses: its default)",
            "0x6060 modes of operation = 0 (the description gives 7, a mode this drive does not \
             run, which it refuses: its default)",
            "0x6086 motion profile type = 0 (the description gives 1, a profile type other than 0, \
             the only one this drive runs, which it refuses: its default)",
            "0x6098 homing method = 35 (the description gives 15, a homing method this drive does \
             not run, which it refuses: its default)",
        ]
    );
    assert!(events.iter().all(|e| e.kind == EventKind::Adjusted));
    assert_eq!(int_at(&dict, 0x6060), 0);
    assert_eq!(int_at(&dict, 0x6098), 35);
}

/// Every corpus drive, filled for a servo and for a stepper: every writable entry of its drive's
/// axis, read as the drive reports it, is accepted when written back; the drive accepts every mode
/// its 0x6502 reports that it runs.
#[test]
fn every_corpus_drive_takes_back_what_it_reports() {
    for path in testkit::corpus_drive_descriptions() {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let file = name.as_str();
        let (_, mut devices) = od::load::load(&path).unwrap_or_else(|e| {
            panic!(
                "{}: {e} (the corpus lies beside the checkout)",
                path.display()
            )
        });
        let desc = devices.remove(0);
        for kind in [MotorKind::Servo, MotorKind::Stepper] {
            let mut dict = desc.dictionary.clone();
            let mut config = DriveConfig::default();
            config.motor.kind = kind;
            fill(&mut dict, &config);
            dict.reset(5);
            // python-canopen's receiver.eds has 0x6040 and 0x6041 as INTEGER16 process data, the
            // SOMANET EDS as PDO records: no drive, their dictionaries alone.
            let drive = Drive::from_dictionary(&dict, 0, config, Instant::now());
            let no_drive = ["pycanopen-receiver.eds", "somanet-SOMANET_CIA402.eds"];
            assert_eq!(drive.is_none(), no_drive.contains(&file), "{file}");
            let writable: Vec<Address> = dict
                .objects()
                .filter(|o| (0x6000..0x6800).contains(&o.index))
                .flat_map(|o| {
                    o.subs
                        .iter()
                        .filter(|(_, s)| {
                            s.access.kind.readable()
                                && s.access.kind.writable()
                                && s.data_type != DataType::Domain
                        })
                        .map(|(&sub, _)| Address::new(o.index, sub))
                        .collect::<Vec<_>>()
                })
                .collect();
            match drive {
                Some(mut drive) => write_back(
                    &mut Bound::new(&mut dict, &mut drive, Instant::now()),
                    &writable,
                    file,
                    kind,
                ),
                None => write_back(&mut dict, &writable, file, kind),
            }
        }
    }
}

/// Each of `entries` read from `node` and written back as read: accepted.
fn write_back(node: &mut dyn ObjectStore, entries: &[Address], file: &str, kind: MotorKind) {
    for &at in entries {
        let bytes = node.upload(at).unwrap();
        assert_eq!(
            node.download(at, &bytes),
            Ok(()),
            "{file} ({kind:?}): {at} = {bytes:02X?} refused written back"
        );
    }
}

/// Speeds and ramps are filled in revolutions at the encoder's resolution: with 1 count per
/// revolution (python-canopen's cog.eds) the profile velocity is 1 count/s, the ramps 10 counts/s²
/// and the quick stop 100 counts/s², not the 10,000-count figures that would ask such a motor for
/// 10,000 rev/s². Absent from the description, the drive takes the same: a pv stop from 5 counts/s
/// takes 0.5 s of its 10 counts/s² deceleration.
#[test]
fn speeds_and_ramps_follow_the_encoder_resolution() {
    use DataType::{Integer32 as I32, Integer8 as I8, Unsigned32 as U32, Unsigned8 as U8};
    let mut dict = Dictionary::new();
    axis(
        &mut dict,
        0x6000,
        &[
            (0x6060, I8, Some(3)),
            (0x6064, I32, None),
            (0x606C, I32, None),
            (0x6081, U32, None),
            (0x6083, U32, Some(0)),
            (0x6085, U32, None),
            (0x60FF, I32, Some(0)),
        ],
    );
    let encoder = Object::structured(0x608F, "Position encoder resolution", od::ObjectKind::Array)
        .with_sub(
            0,
            SubObject::new("n", U8, AccessType::Ro).with_default(Value::Uint(2)),
        )
        .with_sub(
            1,
            SubObject::new("inc", U32, AccessType::Rw).with_default(Value::Uint(1)),
        )
        .with_sub(
            2,
            SubObject::new("rev", U32, AccessType::Rw).with_default(Value::Uint(1)),
        );
    dict.insert(encoder);
    let events = fill(&mut dict, &DriveConfig::default());
    let filled: Vec<(u16, i64)> = events
        .iter()
        .filter(|e| matches!(e.address.index, 0x6081 | 0x6083 | 0x6085))
        .map(|e| (e.address.index, e.value.as_i128().unwrap() as i64))
        .collect();
    assert_eq!(filled, [(0x6081, 1), (0x6083, 10), (0x6085, 100)]);
    assert_eq!(u32_at(&dict, 0x6083, 0), 10);

    // Without 0x6084: the drive's own deceleration is 10 counts/s² too (0x6083 given as 10), the
    // resolution given as 2 counts per 2 revolutions.
    let mut dict = Dictionary::new();
    axis(
        &mut dict,
        0x6000,
        &[
            (0x6060, I8, Some(3)),
            (0x606C, I32, None),
            (0x6083, U32, Some(10)),
            (0x60FF, I32, Some(0)),
        ],
    );
    dict.insert(
        Object::structured(0x608F, "Position encoder resolution", od::ObjectKind::Array)
            .with_sub(
                0,
                SubObject::new("n", U8, AccessType::Ro).with_default(Value::Uint(2)),
            )
            .with_sub(
                1,
                SubObject::new("inc", U32, AccessType::Rw).with_default(Value::Uint(2)),
            )
            .with_sub(
                2,
                SubObject::new("rev", U32, AccessType::Rw).with_default(Value::Uint(2)),
            ),
    );
    let t0 = Instant::now();
    let ms = |n: u64| t0 + std::time::Duration::from_millis(n);
    let mut drive = Drive::from_dictionary(&dict, 0, DriveConfig::default(), t0).unwrap();
    drive.handle_timeout(ms(1));
    {
        let mut node = Bound::new(&mut dict, &mut drive, ms(1));
        node.download(Address::new(0x6060, 0), &[3]).unwrap();
        for cw in [0x06u16, 0x07, 0x0F] {
            node.download(Address::new(0x6040, 0), &cw.to_le_bytes())
                .unwrap();
        }
        node.download(Address::new(0x60FF, 0), &5i32.to_le_bytes())
            .unwrap();
    }
    // The drive's clock kept current, one call a tick (as a node does while it runs).
    let run_to = |drive: &mut Drive, from: u64, to: u64| {
        for t in from..=to {
            drive.handle_timeout(ms(t));
        }
    };
    run_to(&mut drive, 2, 1001);
    assert_eq!(drive.velocity_demand(), 5);
    Bound::new(&mut dict, &mut drive, ms(1001))
        .download(Address::new(0x60FF, 0), &0i32.to_le_bytes())
        .unwrap();
    run_to(&mut drive, 1002, 1201);
    assert_eq!(drive.velocity_demand(), 3, "5 − 10 counts/s² × 0.2 s");
    run_to(&mut drive, 1202, 1601);
    assert_eq!(drive.velocity_demand(), 0);
}

/// Why the drive refuses a write, in the words of its log line, for each kind of rule: a range, a
/// homing method, a profile type, a ramp of 0, the encoder resolution while powered and of 0, a mode
/// it does not run; a value it takes has no refusal.
#[test]
fn each_refusal_says_its_rule() {
    use DataType::{Integer16 as I16, Integer8 as I8, Unsigned32 as U32, Unsigned8 as U8};
    let mut dict = Dictionary::new();
    axis(
        &mut dict,
        0x6000,
        &[
            (0x605A, I16, Some(2)),
            (0x6060, I8, Some(1)),
            (0x607A, DataType::Integer32, Some(0)),
            (0x6081, U32, Some(1000)),
            (0x6083, U32, Some(1000)),
            (0x6086, I16, Some(0)),
            (0x6098, I8, Some(35)),
            (0x6502, U32, Some(0x21)),
        ],
    );
    dict.insert(
        Object::structured(0x608F, "Position encoder resolution", od::ObjectKind::Array)
            .with_sub(
                0,
                SubObject::new("n", U8, AccessType::Ro).with_default(Value::Uint(2)),
            )
            .with_sub(
                1,
                SubObject::new("inc", U32, AccessType::Rw).with_default(Value::Uint(4000)),
            )
            .with_sub(
                2,
                SubObject::new("rev", U32, AccessType::Rw).with_default(Value::Uint(1)),
            ),
    );
    let t0 = Instant::now();
    let mut drive = Drive::from_dictionary(&dict, 0, DriveConfig::default(), t0).unwrap();
    drive.handle_timeout(t0 + std::time::Duration::from_millis(1));
    let why = |drive: &Drive, index: u16, sub: u8, data: &[u8]| {
        drive
            .refusal(Address::new(index, sub), data)
            .map(|(code, line)| (code.code(), line))
    };
    assert_eq!(
        why(&drive, 0x605A, 0, &9i16.to_le_bytes()),
        Some((
            0x0609_0031,
            "axis 0: 0x605A = 9 refused with 0x06090031 (Value of parameter written too high \
             (download only)): this drive takes 0 to 8"
                .into()
        ))
    );
    assert_eq!(
        why(&drive, 0x6098, 0, &[15]),
        Some((
            0x0609_0030,
            "axis 0: 0x6098 = 15 refused with 0x06090030 (Invalid value for parameter (download \
             only)): a homing method this drive does not run"
                .into()
        ))
    );
    assert_eq!(
        why(&drive, 0x6086, 0, &1i16.to_le_bytes()),
        Some((
            0x0609_0030,
            "axis 0: 0x6086 = 1 refused with 0x06090030 (Invalid value for parameter (download \
             only)): this drive takes only [0]"
                .into()
        ))
    );
    assert_eq!(
        why(&drive, 0x6083, 0, &0u32.to_le_bytes()),
        Some((
            0x0609_0032,
            "axis 0: 0x6083 = 0 refused with 0x06090032 (Value of parameter written too low \
             (download only)): it must be above 0: a ramp or speed of 0 would never end"
                .into()
        ))
    );
    assert_eq!(
        why(&drive, 0x608F, 1, &0u32.to_le_bytes()),
        Some((
            0x0609_0032,
            "axis 0: 0x608F:01 = 0 refused with 0x06090032 (Value of parameter written too low \
             (download only)): it must be above 0"
                .into()
        ))
    );
    assert_eq!(
        why(&drive, 0x6060, 0, &[3]),
        Some((
            0x0609_0030,
            "axis 0: 0x6060 = 3 refused with 0x06090030 (Invalid value for parameter (download \
             only)): the modes this drive runs are 0x00000021 (bit mode − 1, as in 0x6502)"
                .into()
        ))
    );
    assert_eq!(why(&drive, 0x6083, 0, &500u32.to_le_bytes()), None);
    assert_eq!(why(&drive, 0x6098, 0, &[37]), None);
    assert_eq!(why(&drive, 0x607A, 0, &5i32.to_le_bytes()), None);
    // Powered, the encoder resolution takes no value at all.
    {
        let mut node = Bound::new(&mut dict, &mut drive, Instant::now());
        for cw in [0x06u16, 0x07, 0x0F] {
            node.download(Address::new(0x6040, 0), &cw.to_le_bytes())
                .unwrap();
        }
    }
    assert_eq!(
        why(&drive, 0x608F, 1, &8000u32.to_le_bytes()),
        Some((
            0x0800_0022,
            "axis 0: 0x608F:01 = 8000 refused with 0x08000022 (Data cannot be transferred or stored \
             to the application because of the present device state): it is written only while the \
             power stage is off"
                .into()
        ))
    );
}
