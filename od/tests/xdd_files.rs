//! The XDD reader on real files: the public CiA 311 corpus in `../shared/corpus/xdd` (outside the
//! repository, see its SOURCES.md) and the project's X67SM2436 fixture. Every fact asserted here was checked
//! by reading the file.

use od::object::{AccessType, DefaultValue, ObjectKind, PdoMapping};
use od::{DataType, DeviceDescription, Value};

fn corpus(name: &str) -> Vec<u8> {
    let path = format!(
        "{}/../../shared/corpus/xdd/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn fixture() -> DeviceDescription {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures/src/x67sm2436.xdd");
    let bytes = std::fs::read(path).unwrap();
    od::xdd::read(&bytes, "x67sm2436.xdd").unwrap()
}

fn plain(v: Value) -> Option<DefaultValue> {
    Some(DefaultValue::plain(v))
}

fn node(v: u64) -> Option<DefaultValue> {
    Some(DefaultValue {
        value: Value::Uint(v),
        plus_node_id: true,
    })
}

/// How many sub-objects the arrays and records have.
fn structured_subs(d: &DeviceDescription) -> usize {
    d.dictionary
        .objects()
        .filter(|o| o.kind.has_subs())
        .map(|o| o.subs.len())
        .sum()
}

/// Writing a read description and reading it back gives the same description.
fn assert_round_trip(d: &DeviceDescription, name: &str) {
    let text = od::xdd::write(d);
    let back = od::xdd::read(text.as_bytes(), name).unwrap();
    assert_eq!(&back, d, "{name}");
    assert_eq!(od::xdd::write(&back), text, "{name}: byte-stable");
}

#[test]
fn canopendemo_demo_device() {
    let d = od::xdd::read(&corpus("canopendemo-demoDevice.xdd"), "demoDevice.xdd").unwrap();
    assert_eq!(d.dictionary.len(), 48);
    assert_eq!(structured_subs(&d), 270, "every CANopenSubObject");

    assert_eq!(d.identity.vendor_name, "-");
    assert_eq!(d.identity.vendor_id, 0);
    assert_eq!(d.identity.product_name, "Demo device");
    assert_eq!(d.identity.product_code, 1);
    assert_eq!(d.file_info.file_name, "demoDevice.xdd");
    assert_eq!(d.file_info.created_by, "Janez Paternoster");
    assert_eq!(d.file_info.creation_date, "2020-11-28");
    assert_eq!(d.file_info.creation_time, "12:37:54.0000000+01:00");
    assert_eq!(d.file_info.modification_date, "2023-03-17");
    assert_eq!(d.file_info.modified_by, "Janez Paternoster");
    assert_eq!(d.file_info.file_version, "1");
    assert_eq!(
        d.file_info.description,
        "Demo CANopen device with example usage."
    );
    let can = d.can.as_ref().unwrap();
    assert_eq!(can.baud_rates, vec![10, 20, 50, 125, 250, 500, 800, 1000]);
    assert_eq!((can.nr_of_rx_pdo, can.nr_of_tx_pdo), (4, 4));
    assert_eq!(can.granularity, 8);
    assert!(can.lss_supported);
    assert!(
        !can.simple_boot_up_slave,
        "bootUpSlave absent: schema default false"
    );
    assert_eq!(can.dummy_usage, vec![2, 3, 4, 5, 6, 7]);
    assert!(d.commissioning.is_none());

    // Everything but the name and PDO mapping comes from the parameters by uniqueIDRef.
    let dev_type = d.dictionary.entry(0x1000, 0).unwrap();
    assert_eq!(dev_type.name, "Device type");
    assert_eq!(dev_type.data_type, DataType::Unsigned32);
    assert_eq!(dev_type.access.kind, AccessType::Ro, "no access: read");
    assert_eq!(dev_type.default, plain(Value::Uint(0x000F_0191)));
    assert!(d
        .dictionary
        .object(0x1000)
        .unwrap()
        .description
        .as_deref()
        .unwrap()
        .starts_with("* bit 16-31: Additional information\n* bit 0-15"));
    assert_eq!(d.dictionary.entry(0x1001, 0).unwrap().pdo, PdoMapping::Tpdo);
    assert_eq!(d.dictionary.entry(0x1014, 0).unwrap().default, node(0x80));
    assert_eq!(d.dictionary.entry(0x1400, 1).unwrap().default, node(0x200));

    let errors = d.dictionary.object(0x1003).unwrap();
    assert_eq!(errors.kind, ObjectKind::Array);
    assert_eq!(errors.subs.len(), 17);
    assert_eq!(errors.type_name.as_deref(), Some("Pre-defined error field"));
    assert_eq!(errors.subs[&0].name, "Number of errors");
    assert_eq!(errors.subs[&0].access.kind, AccessType::Rw);
    assert_eq!(errors.subs[&0x10].data_type, DataType::Unsigned32);

    let record = d.dictionary.object(0x2120).unwrap();
    assert_eq!(record.name, "Demo record");
    assert_eq!(
        record.subs[&1].default,
        plain(Value::Int(-1_234_567_890_123_456_789))
    );
    assert_eq!(
        record.subs[&2].default,
        plain(Value::Uint(0x1234_5678_90AB_CDEF))
    );
    assert_eq!(record.subs[&3].data_type, DataType::Real32);
    assert_eq!(record.subs[&3].default, plain(Value::Real32(12.345)));
    assert_eq!(record.subs[&4].default, plain(Value::Real64(456.789)));
    assert_eq!(record.subs[&1].pdo, PdoMapping::Both, "PDOmapping optional");

    let strings = d.dictionary.object(0x2121).unwrap();
    assert_eq!(strings.subs[&1].default, plain(Value::String("str".into())));
    assert_eq!(strings.subs[&1].bit_size, None);
    assert_eq!(
        strings.subs[&2].bit_size,
        Some(8000),
        "CO_stringLengthMin 1000"
    );
    assert!(
        matches!(&strings.subs[&2].default, Some(DefaultValue { value: Value::String(s), .. }) if s.contains("like '€', tabs '\t'"))
    );
    assert_eq!(strings.subs[&3].data_type, DataType::OctetString);
    assert_eq!(strings.subs[&3].value, vec![0xC8, 0x3D, 0xBB]);
    assert_eq!(strings.subs[&3].bit_size, Some(80));
    assert_eq!(
        d.dictionary.entry(0x2122, 0).unwrap().data_type,
        DataType::Domain,
        "BITSTRING without default, as the EDS of the same device says"
    );
    let outputs = d.dictionary.object(0x6411).unwrap();
    assert_eq!(outputs.subs[&1].data_type, DataType::Integer16);
    assert_eq!(outputs.subs[&1].access.kind, AccessType::Rw);
    assert_eq!(outputs.subs[&1].pdo, PdoMapping::Both);
    assert_eq!(d.dictionary.entry(0x6000, 1).unwrap().pdo, PdoMapping::Tpdo);

    assert_round_trip(&d, "demoDevice.xdd");
}

#[test]
fn canopennode_ds301_profile_project_file() {
    let d = od::xdd::read(
        &corpus("canopennode-DS301_profile.xpd"),
        "DS301_profile.xpd",
    )
    .unwrap();
    assert_eq!(d.dictionary.len(), 55);
    assert_eq!(structured_subs(&d), 221);
    assert_eq!(d.identity.product_name, "New Product");
    assert_eq!(d.identity.vendor_name, "");
    assert_eq!(d.identity.vendor_id, 0, "empty vendorID: 0x1018:01");
    assert_eq!(d.file_info.file_name, "DS301_profile.xpd");
    assert_eq!(d.file_info.creation_date, "2020-11-23");
    assert_eq!(d.file_info.modification_date, "2023-09-05");

    let heartbeat = d.dictionary.object(0x1017).unwrap();
    assert_eq!(heartbeat.name, "Producer heartbeat time");
    assert_eq!(
        heartbeat.description.as_deref(),
        Some("Heartbeat producer time in ms (0 = disable transmission).")
    );
    assert_eq!(heartbeat.subs[&0].data_type, DataType::Unsigned16);
    assert_eq!(heartbeat.subs[&0].access.kind, AccessType::Rw);
    assert_eq!(heartbeat.subs[&0].default, plain(Value::Uint(0)));
    let os_mode = d.dictionary.entry(0x1024, 0).unwrap();
    assert_eq!(os_mode.name, "OS command mode");
    assert_eq!(os_mode.access.kind, AccessType::Wo, "access write");
    assert_eq!(d.dictionary.object(0x1003).unwrap().subs.len(), 17);
    assert_eq!(d.dictionary.object(0x1010).unwrap().subs.len(), 5);
    let sdo = d.dictionary.object(0x1200).unwrap();
    assert_eq!(sdo.subs[&1].default, node(0x600));
    assert_eq!(sdo.subs[&1].pdo, PdoMapping::Tpdo);
    assert_eq!(sdo.subs[&1].value, 0x600u32.to_le_bytes(), "node-ID 0");
    let can = d.can.as_ref().unwrap();
    assert_eq!((can.nr_of_rx_pdo, can.nr_of_tx_pdo), (4, 4));

    assert_round_trip(&d, "DS301_profile.xpd");
}

#[test]
fn x67sm2436_fixture() {
    let d = fixture();
    assert_eq!(d.dictionary.len(), 92);
    assert_eq!(
        d.dictionary.objects().filter(|o| o.index < 0x2000).count(),
        21,
        "CiA 301 communication objects"
    );
    assert_eq!(d.identity.vendor_name, "B&R");
    assert_eq!(d.identity.product_name, "X67SM2436");
    assert_eq!(d.identity.vendor_id, 0, "placeholder");
    assert_eq!(d.file_info.file_name, "x67sm2436.xdd");
    assert_eq!(d.file_info.created_by, "fixtures");
    assert!(d
        .file_info
        .description
        .starts_with("X67 stepper motor module"));

    let can = d.can.as_ref().unwrap();
    assert_eq!(can.granularity, 8, "dynamic mapping, byte granularity");
    assert_eq!((can.nr_of_rx_pdo, can.nr_of_tx_pdo), (2, 2));
    assert!(can.simple_boot_up_slave);
    assert_eq!(can.dummy_usage, vec![5, 6]);
    assert_eq!(can.baud_rates, vec![10, 20, 50, 125, 250, 500, 800, 1000]);

    // RPDO 1 mapping: AbsPos01, MpGenControl01, MpGenMode01, dummy UNSIGNED8.
    let map = d.dictionary.object(0x1600).unwrap();
    assert_eq!(map.kind, ObjectKind::Record);
    let entries: Vec<Option<DefaultValue>> =
        (0..=4u8).map(|s| map.subs[&s].default.clone()).collect();
    assert_eq!(
        entries,
        vec![
            plain(Value::Uint(4)),
            plain(Value::Uint(0x2100_0020)),
            plain(Value::Uint(0x2101_0010)),
            plain(Value::Uint(0x2102_0008)),
            plain(Value::Uint(0x0005_0008)),
        ]
    );
    assert!(
        map.subs.values().all(|s| s.access.kind == AccessType::Rw),
        "dynamic mapping: the master may change it"
    );
    assert_eq!(
        d.dictionary.entry(0x1A01, 3).unwrap().default,
        plain(Value::Uint(0x0006_0010)),
        "UNSIGNED16 dummy in TPDO 2"
    );

    // Every mapping fills 8 bytes, and every mapped object exists, mappable in that direction.
    for (map_index, rpdo) in [
        (0x1600, true),
        (0x1601, true),
        (0x1A00, false),
        (0x1A01, false),
    ] {
        let map = d.dictionary.object(map_index).unwrap();
        let mut bits = 0;
        for (&s, entry) in map.subs.iter().filter(|(&s, _)| s != 0) {
            let Some(Value::Uint(v)) = entry.default.as_ref().map(|d| d.value.clone()) else {
                panic!("{map_index:04X}:{s}");
            };
            let (index, sub, len) = ((v >> 16) as u16, (v >> 8) as u8, v as u8);
            bits += len as u32;
            if index < 0x20 {
                assert!(can.dummy_usage.contains(&index), "dummy {index:04X}");
                continue;
            }
            let target = d.dictionary.entry(index, sub).unwrap();
            assert_eq!(target.bit_size, Some(len as u32), "{index:04X}");
            if rpdo {
                assert_eq!(target.pdo, PdoMapping::Rpdo, "{index:04X}");
            } else {
                assert_eq!(target.pdo, PdoMapping::Tpdo, "{index:04X}");
            }
        }
        assert_eq!(bits, 64, "{map_index:04X}");
    }

    assert_eq!(d.dictionary.entry(0x1014, 0).unwrap().default, node(0x80));
    assert_eq!(d.dictionary.entry(0x1400, 1).unwrap().default, node(0x200));
    assert_eq!(d.dictionary.entry(0x1801, 1).unwrap().default, node(0x280));
    let tpdo = d.dictionary.object(0x1800).unwrap();
    assert_eq!(
        tpdo.subs.keys().copied().collect::<Vec<u8>>(),
        vec![0, 1, 2, 3, 5]
    );
    let name = d.dictionary.entry(0x1008, 0).unwrap();
    assert_eq!(name.data_type, DataType::VisibleString);
    assert_eq!(name.access.kind, AccessType::Const);
    assert_eq!(name.value, b"X67BC4321-10 / X67SM2436");

    // Manufacturer objects (X67SM2436-OBJECTS.md).
    let current = d.dictionary.object(0x2110).unwrap();
    assert_eq!(current.name, "ConfigOutput03a");
    assert_eq!(current.kind, ObjectKind::Var);
    let current = &current.subs[&0];
    assert_eq!(current.data_type, DataType::Unsigned8);
    assert_eq!(current.access.kind, AccessType::Wo);
    assert_eq!(current.pdo, PdoMapping::None);
    assert_eq!(current.low, Some(Value::Uint(0)));
    assert_eq!(current.high, Some(Value::Uint(167)));
    let pos = d.dictionary.entry(0x2100, 0).unwrap();
    assert_eq!(pos.name, "AbsPos01");
    assert_eq!(pos.data_type, DataType::Integer32);
    assert_eq!(pos.access.kind, AccessType::Rww);
    assert_eq!(pos.pdo, PdoMapping::Rpdo);
    let status = d.dictionary.entry(0x2209, 0).unwrap();
    assert_eq!(status.name, "MpGenStatus02");
    assert_eq!(status.default, plain(Value::Uint(0x0200)));
    assert_eq!(status.value, vec![0x00, 0x02]);
    let refconfig = d.dictionary.entry(0x211B, 0).unwrap();
    assert_eq!(refconfig.name, "RefConfig01");
    assert_eq!(refconfig.data_type, DataType::Integer8);
    assert_eq!(refconfig.default, plain(Value::Int(-125)));
    assert_eq!(refconfig.value, vec![0x83]);
    assert_eq!(d.dictionary.entry(0x2040, 0).unwrap().name, "Temperature");
    assert_eq!(
        d.dictionary.entry(0x2008, 0).unwrap().pdo,
        PdoMapping::Tpdo,
        "InputStatus"
    );
    assert_eq!(d.dictionary.object(0x2246).unwrap().name, "ErrorCode02");
}

#[test]
fn x67sm2436_fixture_round_trips() {
    let d = fixture();
    assert_round_trip(&d, "x67sm2436.xdd");
}
