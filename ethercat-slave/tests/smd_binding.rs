//! The SMD23K-B / SMD24K indexer bound to the object dictionary of `fixtures/`
//! (`ethercat_slave::smd::binding`). The first tests prove ARCHITECTURE principle 2 for every address the model
//! names; the others name the rule of `rules/smd.md` whose observable they check, seen through the
//! dictionary (`0x7000` in, `0x8010` by SDO, `0x6000` out).

use std::time::{Duration, Instant};

use ds402::od::{AbortCode, AccessType, DataType, Dictionary, OdError, PdoMapping, Value};
use ds402::smd::config::{Configuration, EncoderKind};
use ds402::smd::indexer::{cmd0, cmd1, stat0, Outputs};
use ethercat_slave::smd::binding::{
    self, check, dictionary, entries, BindingError, Block, Device, Entry, Mismatch, SmdUnit,
    CONFIGURATION_INDEX, FIXTURE_ESI, INPUTS_INDEX, OUTPUTS_INDEX, TABLE,
};
use proptest::prelude::*;

const MS: Duration = Duration::from_millis(1);
const KINDS: [EncoderKind; 2] = [EncoderKind::Incremental, EncoderKind::Absolute];

fn unit(device: Device) -> SmdUnit {
    SmdUnit::new(device, EncoderKind::Incremental).expect("the fixture binds")
}

/// Every unit to test: both devices, both encoder kinds.
fn units() -> Vec<SmdUnit> {
    Device::ALL
        .iter()
        .flat_map(|&d| KINDS.map(|k| SmdUnit::new(d, k).expect("the fixture binds")))
        .collect()
}

/// 6000:01 STATUS_word0 as the dictionary holds it.
fn status0(u: &SmdUnit) -> u16 {
    match u.value(INPUTS_INDEX, 1).unwrap() {
        Value::Uint(v) => u16::try_from(v).unwrap(),
        other => panic!("STATUS_word0 is {other:?}"),
    }
}

/// The source the shipped ESI is generated from (`fixtures/src/smd.esi.xml`), which od's CoE test and
/// the fixture tests load.
fn source_dictionaries() -> Vec<Dictionary> {
    let bytes = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../fixtures/src/smd.esi.xml"
    ))
    .unwrap();
    ds402::od::esi::read_all(&bytes, "smd.esi.xml")
        .unwrap()
        .into_iter()
        .map(|d| d.dictionary)
        .collect()
}

// ---------------------------------------------------------------------------------------------------
// Principle 2: the table against the fixture

/// Every address of the table exists in the fixture dictionary of both devices with the name, data type,
/// access and PDO mapping the model expects: outputs RPDO-mappable, inputs TPDO-mappable, configuration
/// rw with uploads of 2, 2, 4, 2, 2, 2, 2 bytes.
#[test]
fn principle_2_every_table_address_is_in_both_fixture_dictionaries() {
    for device in Device::ALL {
        let d = dictionary(device).unwrap();
        check(&d).unwrap();
        for e in &TABLE {
            let found = d
                .entry(e.index, e.sub)
                .unwrap_or_else(|err| panic!("{device} {e}: {err}"));
            assert_eq!(found.name, e.name, "{device} {e}");
            assert_eq!(found.data_type, e.data_type, "{device} {e}");
            assert_eq!(found.access.kind, e.access, "{device} {e}");
            assert_eq!(found.pdo, e.pdo, "{device} {e}");
            let size = e.data_type.byte_size().unwrap();
            assert_eq!(d.read(e.index, e.sub).unwrap().len(), size, "{device} {e}");
            match e.block {
                Block::Output => {
                    assert_eq!(e.index, 0x7000);
                    assert!(found.pdo.rpdo() && !found.pdo.tpdo(), "{device} {e}");
                    assert_eq!(found.access.kind, AccessType::Ro);
                }
                Block::Input => {
                    assert_eq!(e.index, 0x6000);
                    assert!(found.pdo.tpdo() && !found.pdo.rpdo(), "{device} {e}");
                    assert_eq!(found.access.kind, AccessType::Ro);
                }
                Block::Configuration => {
                    assert_eq!(e.index, 0x8010);
                    assert_eq!(found.access.kind, AccessType::Rw);
                    assert!(!found.pdo.any());
                }
            }
        }
        let sizes: Vec<usize> = entries(Block::Configuration)
            .map(|e| d.read(e.index, e.sub).unwrap().len())
            .collect();
        assert_eq!(sizes, [2, 2, 4, 2, 2, 2, 2], "{device}");
    }
}

/// The table covers each of the three objects whole (its sub-index 0 gives the count), in sub-index
/// order, with the data types of the model's Rust fields.
#[test]
fn principle_2_the_table_covers_the_three_objects_whole() {
    let d = dictionary(Device::Smd23kB).unwrap();
    for (block, index, count) in [
        (Block::Output, OUTPUTS_INDEX, 8u8),
        (Block::Input, INPUTS_INDEX, 7),
        (Block::Configuration, CONFIGURATION_INDEX, 7),
    ] {
        assert_eq!(d.read_value(index, 0).unwrap(), Value::Uint(count.into()));
        assert_eq!(d.object(index).unwrap().max_sub(), count);
        let subs: Vec<(u16, u8)> = entries(block).map(|e| (e.index, e.sub)).collect();
        let expected: Vec<(u16, u8)> = (1..=count).map(|s| (index, s)).collect();
        assert_eq!(subs, expected, "{block:?}");
    }
    assert_eq!(TABLE.len(), 22);
    let types = |block| entries(block).map(|e| e.data_type).collect::<Vec<_>>();
    // Outputs: u16, u16, i32, u32, u16, u16, u16, u16.
    let (u16_, i32_, u32_) = (
        DataType::Unsigned16,
        DataType::Integer32,
        DataType::Unsigned32,
    );
    assert_eq!(
        types(Block::Output),
        [u16_, u16_, i32_, u32_, u16_, u16_, u16_, u16_]
    );
    // Inputs: u16, u16, i32, i32, i32, u16, u16.
    assert_eq!(
        types(Block::Input),
        [u16_, u16_, i32_, i32_, i32_, u16_, u16_]
    );
    // Configuration: u16, u16, u32, u16, u16, u16, u16.
    assert_eq!(
        types(Block::Configuration),
        [u16_, u16_, u32_, u16_, u16_, u16_, u16_]
    );
}

/// The process-data mapping of the fixture (RxPDO 0x1600, TxPDO 0x1A00) lists exactly the table's output
/// and input entries, in the table's order, with their bit lengths: the order the model packs `Outputs`
/// and `Inputs` in is the wire order.
#[test]
fn principle_2_the_pdo_mappings_are_the_tables_order() {
    for device in Device::ALL {
        let d = dictionary(device).unwrap();
        for (block, mapping) in [(Block::Output, 0x1600u16), (Block::Input, 0x1A00)] {
            let expected: Vec<Value> = entries(block)
                .map(|e| {
                    let bits = e.data_type.bit_size().unwrap();
                    Value::Uint(u64::from(e.index) << 16 | u64::from(e.sub) << 8 | u64::from(bits))
                })
                .collect();
            let n = d.read_value(mapping, 0).unwrap();
            assert_eq!(
                n,
                Value::Uint(expected.len() as u64),
                "{device} {mapping:04X}"
            );
            let found: Vec<Value> = (1..=expected.len() as u8)
                .map(|s| d.read_value(mapping, s).unwrap())
                .collect();
            assert_eq!(found, expected, "{device} {mapping:04X}");
        }
    }
}

/// The shipped ESI that the binding includes is generated from `fixtures/src/smd.esi.xml`: the table's
/// entries are the same in both, and the binding checks against the source's dictionaries too.
#[test]
fn principle_2_the_shipped_esi_and_its_source_agree_on_the_table() {
    assert!(FIXTURE_ESI.contains("<Type ProductCode="));
    let sources = source_dictionaries();
    assert_eq!(sources.len(), 2);
    for (device, source) in Device::ALL.iter().zip(&sources) {
        check(source).unwrap();
        let shipped = dictionary(*device).unwrap();
        for e in &TABLE {
            assert_eq!(
                shipped.entry(e.index, e.sub).unwrap(),
                source.entry(e.index, e.sub).unwrap(),
                "{device} {e}"
            );
        }
    }
}

/// Each device is selected by its order code; the two dictionaries differ in 0x1008.
#[test]
fn each_device_gets_its_own_dictionary() {
    for device in Device::ALL {
        let u = unit(device);
        assert_eq!(u.device(), device);
        assert_eq!(
            u.dict().read_value(0x1008, 0).unwrap(),
            Value::String(device.order_code().into())
        );
        assert_eq!(dictionary(device).unwrap(), dictionary(device).unwrap());
    }
    assert_ne!(
        dictionary(Device::Smd23kB).unwrap(),
        dictionary(Device::Smd24k).unwrap()
    );
}

/// A dictionary that lacks an address, or has it with another type, access or mapping, is refused with
/// the table entry and what differs; nothing panics.
#[test]
fn a_dictionary_that_does_not_match_is_refused() {
    let kind = EncoderKind::Incremental;
    let base = dictionary(Device::Smd23kB).unwrap();

    let mut d = base.clone();
    d.remove(INPUTS_INDEX);
    let err = SmdUnit::with_dictionary(Device::Smd23kB, d, kind).unwrap_err();
    assert_eq!(
        err,
        BindingError::Entry {
            entry: binding::STATUS_WORD0,
            mismatch: Mismatch::Missing(OdError::NoObject { index: 0x6000 }),
        }
    );
    assert!(
        err.to_string().contains("STATUS_word0 (0x6000:01)"),
        "{err}"
    );

    let changed = |f: fn(&mut ds402::od::SubObject), e: &Entry| {
        let mut d = base.clone();
        let sub = d.object_mut(e.index).unwrap().subs.get_mut(&e.sub).unwrap();
        f(sub);
        match SmdUnit::with_dictionary(Device::Smd23kB, d, kind).unwrap_err() {
            BindingError::Entry { entry, mismatch } => {
                assert_eq!(entry, *e);
                mismatch
            }
            other => panic!("{other}"),
        }
    };
    assert_eq!(
        changed(|s| s.data_type = DataType::Unsigned32, &binding::POSITION),
        Mismatch::DataType {
            found: DataType::Unsigned32
        }
    );
    assert_eq!(
        changed(
            |s| s.access.kind = AccessType::Ro,
            &binding::CFG_MOTOR_CURRENT
        ),
        Mismatch::Access {
            found: AccessType::Ro
        }
    );
    assert_eq!(
        changed(|s| s.pdo = PdoMapping::Both, &binding::VELOCITY),
        Mismatch::Pdo {
            found: PdoMapping::Both
        }
    );
    assert_eq!(
        changed(|s| s.name = "Speed".into(), &binding::VELOCITY),
        Mismatch::Name {
            found: "Speed".into()
        }
    );
    assert_eq!(
        changed(
            |s| s.high = Some(Value::Uint(100)),
            &binding::MOTOR_POSITION
        ),
        Mismatch::Limited
    );
}

// ---------------------------------------------------------------------------------------------------
// Power-up

/// The configuration in memory at power-up is the fixture's 0x8010 defaults (which are also the model's
/// `Configuration::default()`), and it is valid for both encoder kinds.
#[test]
fn power_up_configuration_comes_from_the_8010_defaults() {
    for u in units() {
        let d = u.dict();
        let value = |sub| match d.read_value(CONFIGURATION_INDEX, sub).unwrap() {
            Value::Uint(v) => v,
            other => panic!("{other:?}"),
        };
        let c = u.indexer().config();
        assert_eq!(
            [
                u64::from(c.cfg0),
                u64::from(c.cfg1),
                u64::from(c.starting_speed),
                u64::from(c.motor_resolution),
                u64::from(c.encoder_resolution),
                u64::from(c.idle_current_reduction),
                u64::from(c.motor_current),
            ],
            [1, 2, 3, 4, 5, 6, 7].map(value)
        );
        assert_eq!(*c, Configuration::default());
        assert!(!u.indexer().configuration_error());
    }
}

/// SMD-T2-002: "After power-up with a valid configuration, before any command, 6000:01 reads 0x4408:
/// Module_OK = 1, Position_Invalid = 1, Stopped = 1, every other bit 0." The first cycle puts 0x4408 into
/// 0x6000:01 (and the unit's input image holds it from power-up on).
#[test]
fn smd_t2_002_power_up_status_word0_is_0x4408_in_6000_01() {
    for mut u in units() {
        assert_eq!(status0(&u), 0x4408, "input image at power-up");
        let inputs = u.cycle(MS);
        assert_eq!(inputs.status0, 0x4408);
        assert_eq!(u.sdo_read(0x6000, 1).unwrap(), &[0x08, 0x44]);
        assert_eq!(u.value(0x6000, 1).unwrap(), Value::Uint(0x4408));
        assert_eq!(
            u.inputs(),
            inputs,
            "0x6000:01–07 hold what the cycle answered"
        );
        assert_eq!(u.value(0x6000, 3).unwrap(), Value::Int(0), "Motor_Position");
    }
}

// ---------------------------------------------------------------------------------------------------
// Configuration by SDO

/// SMD-T2-005, SMD-R5-007, SMD-T2-003, SMD-T2-004 (each single write re-checked at once),
/// SMD-R5-002 (read back as written): an SDO download of Motor_Current 8010:07 = 35 is confirmed and
/// stored, and the next cycle's 0x6000:01 reads 0x6408 (only Configuration_Error added); a valid value
/// (34) clears Configuration_Error again. The same with T2's own example, Motor_Resolution 8010:04 = 100.
#[test]
fn smd_t2_005_r5_007_invalid_configuration_shows_in_6000_01_and_clears() {
    let t0 = Instant::now();
    for mut u in units() {
        u.cycle(MS);
        u.sdo_write(t0, 0x8010, 7, &35u16.to_le_bytes())
            .expect("the download is confirmed");
        assert_eq!(u.sdo_read(0x8010, 7).unwrap(), &[35, 0]);
        assert_eq!(u.indexer().config().motor_current, 35);
        assert_eq!(u.cycle(MS).status0, 0x6408);
        assert_eq!(status0(&u), 0x6408);
        assert_ne!(status0(&u) & stat0::CONFIGURATION_ERROR, 0);

        u.sdo_write(t0, 0x8010, 7, &34u16.to_le_bytes()).unwrap();
        assert_eq!(u.cycle(MS).status0, 0x4408);
        assert_eq!(status0(&u) & stat0::CONFIGURATION_ERROR, 0);

        u.sdo_write(t0, 0x8010, 4, &100u16.to_le_bytes()).unwrap();
        assert_eq!(u.sdo_read(0x8010, 4).unwrap(), &[100, 0]);
        assert_eq!(u.cycle(MS).status0, 0x6408);
        u.sdo_write(t0, 0x8010, 4, &200u16.to_le_bytes()).unwrap();
        assert_eq!(u.cycle(MS).status0, 0x4408);
    }
}

/// Runs a motionless Preset Position to 0 through 0x7000 and returns the unit with Position_Invalid = 0.
fn preset(u: &mut SmdUnit) {
    let t0 = Instant::now();
    u.write_outputs(
        t0,
        &Outputs {
            cmd0: cmd0::PRESET_POSITION,
            ..Outputs::default()
        },
    );
    u.cycle(MS);
    u.write_outputs(t0, &Outputs::default());
    u.cycle(MS);
    assert_eq!(status0(u) & stat0::POSITION_INVALID, 0, "preset");
}

/// SMD-R2-012: every confirmed SDO download to 8010:01–07 sets Position_Invalid (STATUS_word0 bit 10),
/// even with the value the entry already holds; a refused download does not.
#[test]
fn smd_r2_012_each_8010_download_sets_position_invalid() {
    let t0 = Instant::now();
    let mut u = unit(Device::Smd24k);
    for e in entries(Block::Configuration) {
        preset(&mut u);
        let same = u.sdo_read(e.index, e.sub).unwrap().to_vec();
        u.sdo_write(t0, e.index, e.sub, &same[..same.len() - 1])
            .expect_err("one byte short");
        u.cycle(MS);
        assert_eq!(status0(&u) & stat0::POSITION_INVALID, 0, "{e}: refused");
        u.sdo_write(t0, e.index, e.sub, &same).unwrap();
        u.cycle(MS);
        assert_ne!(status0(&u) & stat0::POSITION_INVALID, 0, "{e}");
        assert_eq!(status0(&u), 0x4408, "{e}: nothing else changes");
    }
}

// ---------------------------------------------------------------------------------------------------
// Moves through 0x7000

/// SMD-R6-001 / SMD-R6-002 through the dictionary: a Relative move (CMD_word0 = 0x0002, SMD-R6-006) of 500
/// steps with CMD_word1 = 0x8000 (Enable_Driver), Velocity 1000, Acceleration 10, Deceleration 10,
/// commanded as 0x7000 values and cycled at 1 ms until Move_Complete (STATUS_word0 bit 7): 0x6000:03
/// Motor_Position then reads exactly 500.
#[test]
fn smd_r6_relative_move_commanded_through_7000_ends_at_500_in_6000_03() {
    let t0 = Instant::now();
    for device in Device::ALL {
        let mut u = unit(device);
        let mut out = Outputs {
            cmd0: 0,
            cmd1: cmd1::ENABLE_DRIVER,
            position: 500,
            velocity: 1000,
            acceleration: 10,
            deceleration: 10,
            ..Outputs::default()
        };
        u.write_outputs(t0, &out);
        assert_eq!(u.outputs(), out);
        assert_eq!(u.value(0x7000, 2).unwrap(), Value::Uint(0x8000));
        assert_eq!(u.value(0x7000, 3).unwrap(), Value::Int(500));
        u.cycle(MS);
        out.cmd0 = cmd0::RELATIVE_MOVE;
        u.write_outputs(t0, &out);
        assert_eq!(u.sdo_read(0x7000, 1).unwrap(), &[0x02, 0x00]);

        let mut cycles = 0;
        let mut moved = false;
        while status0(&u) & stat0::MOVE_COMPLETE == 0 {
            assert!(cycles < 10_000, "{device}: no Move_Complete after 10 s");
            let inputs = u.cycle(MS);
            cycles += 1;
            moved |= inputs.status0 & stat0::MOVING_CW != 0;
            assert_eq!(inputs.status0 & stat0::COMMAND_ERROR, 0, "{device}");
        }
        assert!(moved, "{device}: the move ran over several cycles");
        assert!(cycles > 1, "{device}");
        assert_eq!(
            u.value(0x6000, 3).unwrap(),
            Value::Int(500),
            "{device}: Motor_Position"
        );
        assert_eq!(u.inputs().motor_position, 500);
        assert_ne!(status0(&u) & stat0::STOPPED, 0);
    }
}

// ---------------------------------------------------------------------------------------------------
// Refused downloads

/// A download to a read-only entry (0x6000:01 STATUS_word0, and the ro 0x7000 outputs and 0x8010:00) is
/// refused with the dictionary's error (abort 0x06010002) and changes nothing: neither the dictionary nor
/// the model.
#[test]
fn a_download_to_a_read_only_entry_is_refused_and_changes_nothing() {
    let t0 = Instant::now();
    for mut u in units() {
        u.cycle(MS);
        let dict = u.dict().clone();
        let status = u.indexer().status0();
        let config = *u.indexer().config();
        for (index, sub, bytes) in [
            (0x6000u16, 1u8, vec![0x00, 0x00]),
            (0x6000, 3, vec![1, 2, 3, 4]),
            (0x7000, 1, vec![0x02, 0x00]),
            (0x8010, 0, vec![7]),
        ] {
            let err = u.sdo_write(t0, index, sub, &bytes).unwrap_err();
            assert_eq!(err, OdError::ReadOnly { index, sub }.abort_code());
            assert_eq!(err, AbortCode::ReadOnly);
            assert_eq!(u32::from(err), 0x0601_0002);
        }
        assert_eq!(u.dict(), &dict);
        assert_eq!(u.indexer().status0(), status);
        assert_eq!(*u.indexer().config(), config);
        assert_eq!(status0(&u), 0x4408);
    }
}

/// Downloads that the dictionary refuses for a missing entry or a wrong length are answered with its
/// error and change nothing.
#[test]
fn missing_entries_and_wrong_lengths_are_refused() {
    let t0 = Instant::now();
    let mut u = unit(Device::Smd23kB);
    let dict = u.dict().clone();
    assert_eq!(
        u.sdo_write(t0, 0x8011, 1, &[0, 0]),
        Err(OdError::NoObject { index: 0x8011 }.abort_code())
    );
    assert_eq!(
        u.sdo_write(t0, 0x8010, 8, &[0, 0]),
        Err(OdError::NoSubIndex {
            index: 0x8010,
            sub: 8
        }
        .abort_code())
    );
    assert_eq!(
        u.sdo_write(t0, 0x8010, 7, &[35, 0, 0]),
        Err(OdError::TooLong {
            index: 0x8010,
            sub: 7,
            max: 2,
            got: 3
        }
        .abort_code())
    );
    assert_eq!(
        u.sdo_write(t0, 0x8010, 3, &[1, 0]),
        Err(OdError::TooShort {
            index: 0x8010,
            sub: 3,
            min: 4,
            got: 2
        }
        .abort_code())
    );
    assert_eq!(u.dict(), &dict);
    assert_eq!(u.cycle(MS).status0, 0x4408);
}

proptest! {
    /// No panic on any download or output frame; a confirmed 0x8010 download is what the model holds, and
    /// 0x6000 always holds what the last cycle answered.
    #[test]
    fn no_panic_on_any_download_or_output(
        ops in proptest::collection::vec(
            (
                prop_oneof![
                    Just(0x6000u16), Just(0x7000), Just(0x8010), Just(0x1018), any::<u16>()
                ],
                0u8..10,
                proptest::collection::vec(any::<u8>(), 0..6),
                any::<[u16; 8]>(),
            ),
            1..40,
        )
    ) {
        let t0 = Instant::now();
        let mut u = unit(Device::Smd23kB);
        for (index, sub, bytes, w) in ops {
            if u.sdo_write(t0, index, sub, &bytes).is_ok() && index == 0x8010 {
                let c = *u.indexer().config();
                let held = [
                    c.cfg0.into(), c.cfg1.into(), c.starting_speed, c.motor_resolution.into(),
                    c.encoder_resolution.into(), c.idle_current_reduction.into(),
                    c.motor_current.into(),
                ];
                let mut le = [0u8; 4];
                le[..bytes.len()].copy_from_slice(&bytes);
                prop_assert_eq!(held[usize::from(sub) - 1], u32::from_le_bytes(le));
            }
            u.write_outputs(t0, &Outputs {
                cmd0: w[0],
                cmd1: w[1],
                position: i32::from(w[2] as i16),
                velocity: u32::from(w[3]),
                acceleration: w[4],
                deceleration: w[5],
                motor_current: w[6],
                jerk: w[7],
            });
            let inputs = u.cycle(MS);
            prop_assert_eq!(u.inputs(), inputs);
        }
    }
}

/// SMD-T2-008: 0x6000:01 reads by SDO as the present STATUS_word0, as the PDO carries it.
#[test]
fn smd_t2_008_inputs_readable_by_sdo() {
    let t0 = Instant::now();
    for mut u in units() {
        let i = u.cycle(MS);
        assert_eq!(u.sdo_read(0x6000, 1).unwrap(), &i.status0.to_le_bytes());
        u.sdo_write(t0, 0x8010, 7, &35u16.to_le_bytes()).unwrap();
        let i = u.cycle(MS);
        assert_eq!(i.status0, 0x6408);
        assert_eq!(u.sdo_read(0x6000, 1).unwrap(), &0x6408u16.to_le_bytes());
    }
}

/// Each output entry 0x7000:01–08 reads by SDO as the model holds it, in its type's size (SMD
/// Reference 6: words 2 bytes, Position and Velocity 4), little-endian; so do the inputs, the
/// encoder turned by hand to a count of its own.
#[test]
fn process_data_entries_read_by_sdo_in_their_sizes() {
    let t0 = Instant::now();
    let mut u = unit(Device::Smd23kB);
    u.write_outputs(
        t0,
        &Outputs {
            cmd0: 0x0102,
            cmd1: 0x0304,
            position: -5,
            velocity: 0x0A0B_0C0D,
            acceleration: 0x1112,
            deceleration: 0x1314,
            motor_current: 0x1516,
            jerk: 0x1718,
        },
    );
    let expected: [(u8, &[u8]); 8] = [
        (1, &[0x02, 0x01]),
        (2, &[0x04, 0x03]),
        (3, &[0xFB, 0xFF, 0xFF, 0xFF]),
        (4, &[0x0D, 0x0C, 0x0B, 0x0A]),
        (5, &[0x12, 0x11]),
        (6, &[0x14, 0x13]),
        (7, &[0x16, 0x15]),
        (8, &[0x18, 0x17]),
    ];
    for (sub, bytes) in expected {
        assert_eq!(u.sdo_read(0x7000, sub).unwrap(), bytes, "0x7000:{sub:02X}");
    }
    let mut u2 = unit(Device::Smd23kB);
    // Use_Encoder (CFG_Word_0 bit 10): Encoder_Position counts.
    u2.indexer_mut()
        .write_config(t0, 1, u32::from(ds402::smd::config::CFG0_USE_ENCODER));
    u2.indexer_mut().turn_shaft(t0, -300);
    // A move with Jerk 7 running: in.Jerk reports it (SMD-R6-050).
    let mut o = Outputs {
        cmd1: cmd1::ENABLE_DRIVER,
        velocity: 1_000,
        acceleration: 10,
        deceleration: 10,
        jerk: 7,
        ..Outputs::default()
    };
    for (cmd, position) in [
        (cmd0::PRESET_POSITION, 0),
        (0, 0),
        (cmd0::RELATIVE_MOVE, 100),
    ] {
        o.cmd0 = cmd;
        o.position = position;
        u2.write_outputs(t0, &o);
        u2.cycle(MS);
    }
    let i = u2.cycle(MS);
    assert_eq!(i.encoder_position, -300, "turned by hand");
    assert_eq!(i.jerk, 7);
    let expected: [(u8, Vec<u8>); 7] = [
        (1, i.status0.to_le_bytes().to_vec()),
        (2, i.status1.to_le_bytes().to_vec()),
        (3, i.motor_position.to_le_bytes().to_vec()),
        (4, vec![0xD4, 0xFE, 0xFF, 0xFF]),
        (5, i.trapped_encoder_position.to_le_bytes().to_vec()),
        (6, i.motor_current.to_le_bytes().to_vec()),
        (7, i.jerk.to_le_bytes().to_vec()),
    ];
    for (sub, bytes) in expected {
        assert_eq!(u2.sdo_read(0x6000, sub).unwrap(), bytes, "0x6000:{sub:02X}");
    }
}

/// Each device is shown by its order code, the ESI's `Type` text: "SMD23K-B" and "SMD24K".
#[test]
fn each_device_shows_as_its_order_code() {
    assert_eq!(Device::Smd23kB.to_string(), "SMD23K-B");
    assert_eq!(Device::Smd24k.to_string(), "SMD24K");
}

/// A frame's output process data (laid out by the RxPDO assignment 0x1C12, SMD-R6-001: CMD_word0,
/// CMD_word1, Position, Velocity, Acceleration, Deceleration, Motor_Current, Jerk, little-endian at
/// bytes 0, 2, 4, 8, 12, 14, 16, 18) becomes the output image 0x7000:01–08, and its first cycle acts
/// on it: Preset Position (0x0200) to −2 with the driver enabled (0x8000).
#[test]
fn output_process_data_sets_the_output_image() {
    let mut u = unit(Device::Smd23kB);
    let image = ds402::od::hook::ProcessImage::from_assignment(u.dict(), 0x1C12).unwrap();
    assert_eq!(image.len(), 20);
    let bytes = [
        0x00, 0x02, 0x00, 0x80, 0xFE, 0xFF, 0xFF, 0xFF, 0x10, 0x27, 0x00, 0x00, 0x64, 0x00, 0x65,
        0x00, 0x07, 0x00, 0x08, 0x00,
    ];
    u.receive_process_data(std::time::Instant::now(), &image, &bytes);
    assert_eq!(
        u.outputs(),
        Outputs {
            cmd0: 0x0200,
            cmd1: 0x8000,
            position: -2,
            velocity: 10_000,
            acceleration: 100,
            deceleration: 101,
            motor_current: 7,
            jerk: 8,
        }
    );
    let i = u.cycle(MS);
    assert_eq!((i.motor_position, i.status0), (-2, 0x4008));
}

/// A CoE mailbox served on the unit answers with the server's events: a download of 12 to
/// Motor_Current 0x8010:07 (expedited, 2 bytes: command 0x2B) is one `Downloaded` of 0x8010:07, and
/// the value is in the dictionary and the model.
#[test]
fn a_mailbox_answers_with_the_servers_events() {
    use ds402::od::coe::server::CoeServer;
    use ds402::od::sdo::server::{ServerConfig, ServerEvent};
    let mut u = unit(Device::Smd23kB);
    let mut server = CoeServer::new(ServerConfig::default(), 128);
    let mut mailbox = vec![10, 0, 0, 0, 0, 0x13, 0x00, 0x20];
    mailbox.extend_from_slice(&[0x2B, 0x10, 0x80, 0x07, 12, 0, 0, 0]);
    let events = u.handle_mailbox(&mut server, std::time::Instant::now(), &mailbox);
    assert_eq!(
        events,
        [ServerEvent::Downloaded {
            mux: ds402::od::sdo::frame::Address::new(0x8010, 7)
        }]
    );
    assert_eq!(u.sdo_read(0x8010, 7).unwrap(), [12, 0]);
    assert_eq!(u.indexer().config().motor_current, 12);
}
