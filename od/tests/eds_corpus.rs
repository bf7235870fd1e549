//! The EDS reader on the real-world files of the shared corpus (`../shared/corpus/eds`, see its
//! SOURCES.md), each checked against facts read from the file by eye; and each written back and read
//! again unchanged.

use od::{
    eds, AccessType, DataType, DefaultValue, DeviceDescription, ObjectKind, PdoMapping, Value,
};

fn corpus(name: &str) -> Vec<u8> {
    let path = format!(
        "{}/../../shared/corpus/eds/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn read(name: &str) -> DeviceDescription {
    let desc = eds::read(&corpus(name), name).unwrap_or_else(|e| panic!("{e}"));
    round_trips(name, &desc);
    desc
}

/// Whatever the file held, the writer's EDS and DCF of it read back the same; configured as `esi-gen
/// dcf` configures it (every writable entry set), its DCF holds the same dictionary and reads back to the
/// same text.
fn round_trips(name: &str, desc: &DeviceDescription) {
    for dcf in [false, true] {
        let text = if dcf {
            eds::write_dcf(desc)
        } else {
            eds::write_eds(desc)
        };
        let mut back = eds::read(text.as_bytes(), "rewritten").unwrap();
        assert_eq!(
            od::diff::diff(&desc.dictionary, &back.dictionary),
            [],
            "{name}"
        );
        // What the module documentation says is written where the file has nothing: the CAN
        // information of `[DeviceInfo]`.
        if desc.can.is_none() {
            back.can = None;
        }
        assert_eq!(od::diff::diff_devices(desc, &back), [], "{name}");
        assert_eq!(&back, desc, "{name}");
    }
    let mut configured = desc.clone();
    configured.configure_writable();
    let text = eds::write_dcf(&configured);
    let back = eds::read(text.as_bytes(), "configured.dcf").unwrap();
    assert_eq!(
        od::diff::diff(&configured.dictionary, &back.dictionary),
        [],
        "{name}"
    );
    assert_eq!(back.dictionary, configured.dictionary, "{name}");
    assert_eq!(eds::write_dcf(&back), text, "{name}");
}

/// Every EDS and DCF of the corpus loads (what the established tools load, loads), and round-trips.
#[test]
fn every_file_loads_and_round_trips() {
    let dir = format!("{}/../../shared/corpus/eds", env!("CARGO_MANIFEST_DIR"));
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{dir}: {e}"))
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert!(names.len() >= 38, "{names:?}");
    for name in &names {
        let reading = eds::read_file(&corpus(name), name).unwrap_or_else(|e| panic!("{e}"));
        round_trips(name, &reading.devices[0]);
    }
}

fn plus_node_id(value: u64) -> Option<DefaultValue> {
    Some(DefaultValue {
        value: Value::Uint(value),
        plus_node_id: true,
    })
}

#[test]
fn canopennode_ds301_profile() {
    let desc = read("canopennode-DS301_profile.eds");
    let d = &desc.dictionary;
    assert_eq!(d.len(), 33);
    assert_eq!(desc.file_info.file_name, "DS301_profile.eds");
    assert_eq!(desc.file_info.modification_time, "2:07AM");
    // `VendorNumber=` is empty in this file.
    assert_eq!(desc.identity.vendor_id, 0);
    assert_eq!(desc.identity.product_name, "New Product");
    let can = desc.can.unwrap();
    assert_eq!(can.baud_rates, [10, 20, 50, 125, 250, 500, 800, 1000]);
    assert!(can.lss_supported);
    assert_eq!(can.dummy_usage, [2, 3, 4, 5, 6, 7]);
    assert_eq!(
        d.entry(0x1014, 0).unwrap().default,
        plus_node_id(0x80),
        "COB-ID EMCY"
    );
    let sdo_rx = d.entry(0x1200, 1).unwrap();
    assert_eq!(sdo_rx.name, "COB-ID client to server (rx)");
    assert_eq!(sdo_rx.default, plus_node_id(0x600));
    assert_eq!(sdo_rx.access.kind, AccessType::Ro);
    assert_eq!(sdo_rx.pdo, PdoMapping::Tpdo);
    assert_eq!(d.entry(0x1200, 2).unwrap().default, plus_node_id(0x580));
    assert_eq!(d.object(0x1018).unwrap().name, "Identity");
    assert_eq!(d.object(0x1018).unwrap().subs.len(), 5);
    assert_eq!(d.entry(0x1001, 0).unwrap().pdo, PdoMapping::Tpdo);
}

#[test]
fn canopendemo_demo_device() {
    let desc = read("canopendemo-demoDevice.eds");
    let d = &desc.dictionary;
    assert_eq!(d.len(), 47);
    assert_eq!(desc.identity.product_name, "Demo device");
    assert_eq!(desc.identity.product_code, 1);
    assert_eq!(desc.file_info.created_by, "Janez Paternoster");
    assert_eq!(
        d.entry(0x1400, 1).unwrap().default,
        plus_node_id(0x200),
        "$NODEID+0x00000200"
    );
    let record = d.object(0x2120).unwrap();
    assert_eq!(record.name, "Demo record");
    assert_eq!(record.kind, ObjectKind::Record);
    let i64_entry = &record.subs[&1];
    assert_eq!(i64_entry.data_type, DataType::Integer64);
    assert_eq!(
        i64_entry.default,
        Some(DefaultValue::plain(Value::Int(-1_234_567_890_123_456_789)))
    );
    assert_eq!(
        record.subs[&2].default,
        Some(DefaultValue::plain(Value::Uint(0x1234_5678_90AB_CDEF)))
    );
    assert_eq!(
        record.subs[&3].default,
        Some(DefaultValue::plain(Value::Real32(12.345)))
    );
    // `DefaultValue=` left empty on a REAL64: no default, value zero.
    assert_eq!(record.subs[&5].default, None);
    assert_eq!(record.subs[&5].value, [0; 8]);
    let long = d.entry(0x2121, 2).unwrap();
    assert_eq!(long.data_type, DataType::VisibleString);
    assert_eq!(
        long.default,
        Some(DefaultValue::plain(Value::String(
            "Example string with 1000 bytes capacity. It may contain UTF-8 characters, like '€', \
             tabs '\t', newlines, etc."
                .into()
        )))
    );
    assert_eq!(
        d.entry(0x2121, 3).unwrap().default,
        Some(DefaultValue::plain(Value::Bytes(vec![0xC8, 0x3D, 0xBB])))
    );
    let domain = d.entry(0x2122, 0).unwrap();
    assert_eq!(domain.data_type, DataType::Domain);
    assert_eq!(
        domain.default,
        Some(DefaultValue::plain(Value::Bytes(vec![])))
    );
}

#[test]
fn pycanopen_datatypes() {
    let desc = read("pycanopen-datatypes.eds");
    let d = &desc.dictionary;
    assert_eq!(d.len(), 24);
    assert_eq!(desc.file_info.created_by, "objdictgen");
    assert_eq!(desc.can.as_ref().unwrap().dummy_usage, [2, 3, 4, 5, 6, 7]);
    let default = |index| d.entry(index, 0).unwrap().default.clone().map(|v| v.value);
    assert_eq!(default(0x2001), Some(Value::Bool(false)));
    assert_eq!(default(0x2002), Some(Value::Int(12)));
    assert_eq!(default(0x2007), Some(Value::Uint(537_337_864)));
    assert_eq!(default(0x2008), Some(Value::Real32(1.2)));
    assert_eq!(default(0x2009), Some(Value::String("ABCD".into())));
    assert_eq!(default(0x200A), Some(Value::Bytes(vec![0xAB, 0xCD])));
    assert_eq!(
        default(0x200B),
        Some(Value::Unicode("abc✓".encode_utf16().collect()))
    );
    // `DefaultValue=@ABCD` on a DOMAIN is no hexadecimal: not kept.
    assert_eq!(d.entry(0x200F, 0).unwrap().data_type, DataType::Domain);
    assert_eq!(default(0x200F), None);
    assert_eq!(default(0x2010), Some(Value::Int(-1)));
    assert_eq!(d.entry(0x2010, 0).unwrap().value, [0xFF, 0xFF, 0xFF]);
    assert_eq!(default(0x2015), Some(Value::Int(-64)));
    assert_eq!(default(0x201B), Some(Value::Uint(64)));
    assert_eq!(d.entry(0x201B, 0).unwrap().data_type, DataType::Unsigned64);
}

#[test]
fn pycanopen_sample_is_a_dcf_with_compact_arrays() {
    let desc = read("pycanopen-sample.eds");
    let d = &desc.dictionary;
    assert_eq!(d.len(), 40);
    assert_eq!(
        desc.comments,
        ["|-------------|", "| Don't panic |", "|-------------|"]
    );
    let commissioning = desc.commissioning.as_ref().unwrap();
    assert_eq!(commissioning.node_id, Some(0x10));
    assert_eq!(commissioning.node_name, "Some name");
    assert_eq!(commissioning.baud_rate, 500);
    assert_eq!(desc.can.as_ref().unwrap().baud_rates, [125, 250, 500, 1000]);
    assert_eq!(desc.can.as_ref().unwrap().dummy_usage, [3]);

    // `$NODEID+512` and `1280+$NODEID`, resolved with NodeID=0x10 for the current value.
    let rpdo1 = d.entry(0x1400, 1).unwrap();
    assert_eq!(rpdo1.name, "COB-ID use by RPDO 1");
    assert_eq!(rpdo1.default, plus_node_id(512));
    assert_eq!(d.read_value(0x1400, 1).unwrap(), Value::Uint(512 + 0x10));
    assert_eq!(d.entry(0x1403, 1).unwrap().default, plus_node_id(1280));
    assert_eq!(d.read_value(0x1403, 1).unwrap(), Value::Uint(1280 + 0x10));

    // ParameterValue in a DCF.
    let vendor = d.entry(0x1018, 1).unwrap();
    assert!(vendor.value_set);
    assert_eq!(d.read_value(0x1018, 1).unwrap(), Value::Uint(1));
    assert!(d.entry(0x1018, 3).is_err(), "sub 3 is left out of the file");
    let rate = d.entry(0x3002, 0).unwrap();
    assert_eq!(rate.default, Some(DefaultValue::plain(Value::Real32(5.2))));
    assert_eq!(rate.low, Some(Value::Real32(4.5)));
    assert!(rate.value_set);

    // CompactSubObj=3 with names from [3004Name].
    let status = d.object(0x3004).unwrap();
    assert_eq!(status.kind, ObjectKind::Array);
    assert_eq!(status.subs.len(), 4);
    assert_eq!(status.subs[&0].name, "NrOfObjects");
    assert_eq!(
        status.subs[&0].default,
        Some(DefaultValue::plain(Value::Uint(3)))
    );
    assert_eq!(status.subs[&1].name, "Sensor Status 1");
    assert_eq!(status.subs[&3].name, "Sensor Status 3");
    assert_eq!(status.subs[&3].data_type, DataType::Unsigned16);
    assert_eq!(
        status.subs[&3].default,
        Some(DefaultValue::plain(Value::Uint(3)))
    );
    // CompactSubObj=24 without a name section: the object's name and the sub-index.
    let valves = d.object(0x3006).unwrap();
    assert_eq!(valves.subs.len(), 25);
    assert_eq!(valves.subs[&24].name, "Valve 1 % Open24");
    assert_eq!(valves.subs[&24].data_type, DataType::Real32);
    // An ARRAY with neither sub-index sections nor CompactSubObj has no entries.
    assert!(d.object(0x3003).unwrap().subs.is_empty());
    // `[3010Sub0]` with a capital S.
    assert_eq!(d.entry(0x3010, 0).unwrap().name, "Temperature");

    // Limits of signed types written as two's complement.
    assert_eq!(d.entry(0x3030, 0).unwrap().high, Some(Value::Int(-1)));
    assert_eq!(
        d.entry(0x3030, 0).unwrap().low,
        Some(Value::Int(i64::from(i32::MIN)))
    );
    assert_eq!(d.entry(0x3040, 0).unwrap().low, Some(Value::Int(-10)));
    assert_eq!(d.entry(0x3040, 0).unwrap().high, Some(Value::Int(10)));
    // DataType=0x40, a manufacturer structure: read as a domain.
    assert_eq!(d.entry(0x2020, 0).unwrap().data_type, DataType::Domain);
    // Objects 0x2001.. have sections but are not listed: read all the same.
    assert_eq!(d.entry(0x2001, 0).unwrap().data_type, DataType::Integer16);
    assert_eq!(d.entry(0x2001, 0).unwrap().pdo, PdoMapping::Both);
}

#[test]
fn pycanopen_e35_lists_an_object_it_does_not_describe() {
    let bytes = corpus("pycanopen-e35.eds");
    // 104=0x6505 in [OptionalObjects] has no [6505] section: the entry is skipped, the rest reads.
    let desc = eds::read(&bytes, "e35.eds").unwrap();
    assert!(desc.dictionary.object(0x6505).is_none());
    let d = &desc.dictionary;
    assert_eq!(d.len(), 211);
    assert_eq!(desc.file_info.format_version, "402");
    assert_eq!(desc.identity.vendor_id, 101);
    assert_eq!(desc.identity.revision, 295);
    assert_eq!(desc.identity.order_code, "25");
    assert_eq!(desc.can.as_ref().unwrap().dummy_usage, [5, 6, 7]);
    assert_eq!(
        d.entry(0x1000, 0).unwrap().default,
        Some(DefaultValue::plain(Value::Uint(0x20192)))
    );
    let controlword = d.entry(0x6040, 0).unwrap();
    assert_eq!(controlword.name, "Controlword");
    assert_eq!(controlword.data_type, DataType::Unsigned16);
    assert_eq!(controlword.access.kind, AccessType::Rww);
    assert_eq!(controlword.pdo, PdoMapping::Rpdo);
    let mode = d.entry(0x6060, 0).unwrap();
    assert_eq!(mode.data_type, DataType::Integer8);
    assert_eq!(mode.default, Some(DefaultValue::plain(Value::Int(1))));
    assert_eq!(mode.low, Some(Value::Int(-2)));
    assert_eq!(mode.high, Some(Value::Int(10)));
    assert_eq!(
        d.entry(0x607D, 1).unwrap().default,
        Some(DefaultValue::plain(Value::Int(-2_147_483_647)))
    );
    // ParameterValue without [DeviceComissioning]: current values all the same.
    let mapping = d.entry(0x1A00, 1).unwrap();
    assert!(mapping.value_set);
    assert_eq!(d.read_value(0x1A00, 1).unwrap(), Value::Uint(0x606C_0020));
    assert_eq!(desc.commissioning, None);
    let again = eds::read(eds::write_dcf(&desc).as_bytes(), "e35.dcf").unwrap();
    assert_eq!(od::diff::diff(&again.dictionary, &desc.dictionary), []);
}

/// The reader's warnings about `name`, as `line:column: message`.
fn warnings(name: &str) -> (DeviceDescription, Vec<String>) {
    let mut reading = eds::read_file(&corpus(name), name).unwrap_or_else(|e| panic!("{e}"));
    let text = reading
        .findings
        .iter()
        .map(|f| {
            let p = f.position.unwrap();
            format!("{}:{}: {}", p.line, p.column, f.message)
        })
        .collect();
    (reading.devices.pop().unwrap(), text)
}

/// The files the reader refused before it read what python-canopen, Lely and CANopenNode read, each
/// with the construct that stopped it, checked against the file by eye.
#[test]
fn files_once_refused_load_with_warnings() {
    // CANopenNode's C suffix.
    let (desc, w) = warnings("canopennode-IO.eds");
    assert!(w.contains(&"2105:14: DefaultValue= in [2120sub1]: the C suffix `LL` of `0x1234567890ABCDEFLL` is dropped".to_string()), "{w:#?}");
    assert_eq!(
        desc.dictionary.entry(0x2120, 1).unwrap().default,
        Some(DefaultValue::plain(Value::Int(0x1234_5678_90AB_CDEF)))
    );
    // CANopenEditor's Python port: object codes and data types by name.
    let (desc, w) = warnings("coeditorlb-demo_device.eds");
    assert_eq!(
        w[..2],
        [
            "21:12: ObjectType= in [1000]: `VAR` is the name of an object code, not a code; read as 0x7 (VAR)",
            "22:10: DataType= in [1000]: `UNSIGNED32` is the name of data type 0x0007, not its index; read as UNSIGNED32",
        ]
    );
    assert_eq!(
        desc.dictionary.object(0x1000).unwrap().kind,
        ObjectKind::Var
    );
    // Lely: an unconfigured node, and a time as `days ms`.
    let (desc, w) = warnings("lely-co-gw_txt-slave.dcf");
    assert_eq!(
        w,
        ["18:8: NodeID= in [DeviceComissioning]: `0xff` marks a node that LSS has yet to configure; the node is unconfigured, and `$NODEID` values stay relative to the node-ID"]
    );
    assert_eq!(desc.node_id(), None);
    let (desc, _) = warnings("lely-co-sdev.dcf");
    assert_eq!(
        desc.dictionary.read_value(0x200C, 0).unwrap(),
        Value::Time(od::value::TimeValue {
            ms: 43_200_000,
            days: 365
        })
    );
    // openPOWERLINK: `0` for an OCTET_STRING.
    let (desc, w) = warnings("oplk-sysmncn.eds");
    assert!(w.contains(&"337:14: DefaultValue= in [1030sub5]: `0` is not a OCTET_STRING value: expected hexadecimal byte digits; the default is dropped".to_string()), "{w:#?}");
    assert_eq!(desc.dictionary.entry(0x1030, 5).unwrap().default, None);
    // python-canopen's 255 compact entries.
    let (desc, w) = warnings("pycanopen-receiver.eds");
    assert!(w.contains(&"123:15: CompactSubObj= in [1003]: 255 entries reach sub-index 0xFF, which CiA 301 keeps for the object's structure; read as 255 entries, as Lely does".to_string()), "{w:#?}");
    assert_eq!(desc.dictionary.object(0x1003).unwrap().subs.len(), 256);
    // ros_canopen and ros2_canopen: parameter values relative to a node-ID the file does not give.
    for (name, index, offset) in [
        ("ros2c-prbt_0_1.dcf", 0x1400, 0x200),
        ("rosc-Schunk.eds", 0x1401, 0x300),
        ("rosc-Schunk_0_63.dcf", 0x1400, 0x200),
    ] {
        let (desc, _) = warnings(name);
        assert_eq!(desc.commissioning, None, "{name}");
        let cob = desc.dictionary.entry(index, 1).unwrap();
        assert!(cob.value_set && cob.value_plus_node_id, "{name}");
        assert_eq!(
            desc.dictionary.read_value(index, 1).unwrap(),
            Value::Uint(offset),
            "{name}"
        );
    }
    // SOMANET: 0xDEADBEEF for an INTEGER16.
    let (desc, w) = warnings("somanet-SOMANET_CIA402.eds");
    assert!(w.contains(&"1225:14: DefaultValue= in [6071sub1]: 0xDEADBEEF does not fit in INTEGER16, -32768 to 32767; the default is dropped".to_string()), "{w:#?}");
    assert_eq!(desc.dictionary.entry(0x6071, 1).unwrap().default, None);
}
