//! The SMD23K-B / SMD24K description (`fixtures/src/smd.esi.xml`) against the AMCI manual (seed 000):
//! each test names the rule of `shared/rules/smd.md` whose observable it checks.

use integration_tests::{fixture, load_all};
use od::device::{DeviceDescription, Pdo};
use od::{AccessType, DataType, PdoMapping, Value};

fn devices() -> Vec<DeviceDescription> {
    load_all(&fixture("src/smd.esi.xml"))
}

/// A PDO's entries as (index, sub-index, bit length, name).
fn entries(pdo: &Pdo) -> Vec<(u16, u8, u16, &str)> {
    pdo.entries
        .iter()
        .map(|e| (e.index, e.sub, e.bit_len, e.name.as_str()))
        .collect()
}

#[test]
fn the_file_describes_both_units_with_one_dictionary() {
    let devs = devices();
    let names: Vec<&str> = devs
        .iter()
        .map(|d| d.identity.order_code.as_str())
        .collect();
    assert_eq!(names, ["SMD23K-B", "SMD24K"]);
    let diffs = od::diff::diff(&devs[0].dictionary, &devs[1].dictionary);
    assert!(!diffs.is_empty());
    for d in &diffs {
        assert!(d.index() == Some(0x1008), "only 0x1008 differs: {d}");
    }
    assert_eq!(
        devs[1].dictionary.read_value(0x1008, 0).unwrap(),
        Value::String("SMD24K".into())
    );
}

/// SMD-R5-001: 8010 has seven sub-indices with the manual's names and types; uploads are 2, 2, 4, 2, 2, 2, 2
/// bytes and 8010:00 reads 7.
#[test]
fn smd_r5_001_configuration_object() {
    for dev in devices() {
        let d = &dev.dictionary;
        assert_eq!(d.read_value(0x8010, 0).unwrap(), Value::Uint(7));
        let expected = [
            ("CFG_Word_0", DataType::Unsigned16),
            ("CFG_Word_1", DataType::Unsigned16),
            ("Starting_Speed", DataType::Unsigned32),
            ("Motor_Resolution", DataType::Unsigned16),
            ("Encoder_Resolution", DataType::Unsigned16),
            ("Idle_current_reduction", DataType::Unsigned16),
            ("Motor_Current", DataType::Unsigned16),
        ];
        for (i, (name, t)) in expected.iter().enumerate() {
            let sub = i as u8 + 1;
            let e = d.entry(0x8010, sub).unwrap();
            assert_eq!(
                (e.name.as_str(), e.data_type),
                (*name, *t),
                "8010:{sub:02X}"
            );
            assert_eq!(e.access.kind, AccessType::Rw);
            assert_eq!(d.read(0x8010, sub).unwrap().len(), [2, 2, 4, 2, 2, 2, 2][i]);
        }
        assert_eq!(d.lookup("cfg_word_1").unwrap(), od::Address::new(0x8010, 2));
    }
}

/// SMD-T2-005: an out-of-range configuration value is stored, the SDO write is not refused (the range is
/// documentation, the unit flags it in STATUS_word0 bit 13).
#[test]
fn smd_t2_005_out_of_range_configuration_is_stored() {
    let mut dev = devices().remove(0);
    let d = &mut dev.dictionary;
    d.write(0x8010, 4, &100u16.to_le_bytes())
        .expect("the write is confirmed");
    assert_eq!(d.read(0x8010, 4).unwrap(), &[100, 0]);
    d.write(0x8010, 3, &2_000_000u32.to_le_bytes())
        .expect("Starting_Speed above its range is stored too");
    let e = d.entry(0x8010, 4).unwrap();
    assert!(
        e.description
            .as_deref()
            .unwrap_or("")
            .contains("200 to 32,767"),
        "{:?}",
        e.description
    );
}

/// SMD-R6-001: the RxPDO maps CMD_word0, CMD_word1, Position, Velocity, Acceleration, Deceleration,
/// Motor_Current and Jerk, 20 bytes, at 0x7000:01..08.
#[test]
fn smd_r6_001_output_process_data() {
    for dev in devices() {
        let ec = dev.ethercat.as_ref().unwrap();
        assert_eq!(ec.rx_pdos.len(), 1);
        let pdo = &ec.rx_pdos[0];
        assert_eq!((pdo.index, pdo.sm), (0x1600, Some(2)));
        assert_eq!(
            entries(pdo),
            [
                (0x7000, 1, 16, "CMD_word0"),
                (0x7000, 2, 16, "CMD_word1"),
                (0x7000, 3, 32, "Position"),
                (0x7000, 4, 32, "Velocity"),
                (0x7000, 5, 16, "Acceleration"),
                (0x7000, 6, 16, "Deceleration"),
                (0x7000, 7, 16, "Motor_Current"),
                (0x7000, 8, 16, "Jerk"),
            ]
        );
        let d = &dev.dictionary;
        let types: Vec<DataType> = (1..=8)
            .map(|s| d.entry(0x7000, s).unwrap().data_type)
            .collect();
        use DataType::*;
        assert_eq!(
            types,
            [
                Unsigned16, Unsigned16, Integer32, Unsigned32, Unsigned16, Unsigned16, Unsigned16,
                Unsigned16
            ]
        );
        assert!((1..=8).all(|s| d.entry(0x7000, s).unwrap().pdo == PdoMapping::Rpdo));
        let mapping: Vec<Value> = (1..=8).map(|s| d.read_value(0x1600, s).unwrap()).collect();
        assert_eq!(mapping[0], Value::Uint(0x7000_0110));
        assert_eq!(mapping[3], Value::Uint(0x7000_0420));
        assert_eq!(mapping[7], Value::Uint(0x7000_0810));
        let bits: u16 = pdo.entries.iter().map(|e| e.bit_len).sum();
        assert_eq!(bits, 160, "20 bytes");
        assert_eq!(ec.sync_managers[2].default_size, Some(20));
    }
}

/// SMD-R6-002, SMD-T2-001: the TxPDO maps STATUS_word0, STATUS_word1, Motor_Position, Encoder_Position,
/// Trapped_Encoder_Position, Motor_Current and Jerk, 20 bytes; 0x6000:01 is STATUS_word0.
#[test]
fn smd_r6_002_t2_001_input_process_data() {
    for dev in devices() {
        let ec = dev.ethercat.as_ref().unwrap();
        let pdo = &ec.tx_pdos[0];
        assert_eq!((pdo.index, pdo.sm), (0x1A00, Some(3)));
        assert_eq!(
            entries(pdo),
            [
                (0x6000, 1, 16, "STATUS_word0"),
                (0x6000, 2, 16, "STATUS_word1"),
                (0x6000, 3, 32, "Motor_Position"),
                (0x6000, 4, 32, "Encoder_Position"),
                (0x6000, 5, 32, "Trapped_Encoder_Position"),
                (0x6000, 6, 16, "Motor_Current"),
                (0x6000, 7, 16, "Jerk"),
            ]
        );
        let d = &dev.dictionary;
        assert_eq!(d.entry(0x6000, 1).unwrap().name, "STATUS_word0");
        assert!((1..=7).all(|s| d.entry(0x6000, s).unwrap().pdo == PdoMapping::Tpdo));
        assert_eq!(d.read_value(0x1C13, 1).unwrap(), Value::Uint(0x1A00));
        assert_eq!(d.read_value(0x1C12, 1).unwrap(), Value::Uint(0x1600));
        assert_eq!(ec.sync_managers[3].default_size, Some(20));
    }
}

/// SMD-T3-001, SMD-T3-002, SMD-T3-003: "SM-Synchron" is the default op mode; "DC_Synchron" uses SYNC0 only,
/// with a 2 ms minimum cycle.
#[test]
fn smd_t3_001_to_003_op_modes() {
    for dev in devices() {
        let ec = dev.ethercat.as_ref().unwrap();
        let names: Vec<&str> = ec.op_modes.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["SM-Synchron", "DC_Synchron"]);
        assert_eq!(ec.op_modes[0].assign_activate, 0x0000);
        assert_eq!(
            ec.op_modes[1].assign_activate, 0x0300,
            "cyclic unit + SYNC0, no SYNC1"
        );
        assert_eq!(ec.op_modes[1].cycle_time_sync0, Some((2_000_000, 1)));
        assert!(ec.op_modes[1].cycle_time_sync1.is_none());
        let mbox = ec.mailbox.as_ref().unwrap();
        assert!(mbox.coe.is_some());
        let kinds: Vec<&str> = ec.sync_managers.iter().map(|s| s.kind.as_str()).collect();
        assert_eq!(kinds, ["MBoxOut", "MBoxIn", "Outputs", "Inputs"]);
    }
}

#[test]
fn the_description_validates_without_errors() {
    for dev in devices() {
        let findings = od::validate::validate(&dev);
        let errors: Vec<String> = findings
            .iter()
            .filter(|f| f.severity == od::validate::Severity::Error)
            .map(|f| f.to_string())
            .collect();
        assert!(errors.is_empty(), "{errors:#?}");
    }
}
