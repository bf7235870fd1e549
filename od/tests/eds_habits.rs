//! Constructs of real EDS and DCF files that the established tools (python-canopen, Lely, CANopenNode)
//! load, each in a small file of its own: what the reader and the checks make of it, with the exact
//! findings and where in the file they are.

use od::validate::validate_mapped;
use od::{eds, DataType, Severity, Value};

/// Reads `text`, checks the description, and gives it back with every finding (the reader's, then the
/// checks') as `line:column: message`, warnings only.
fn read_and_check(text: &str) -> (od::DeviceDescription, Vec<String>) {
    let mut reading =
        eds::read_file(text.as_bytes(), "habit.eds").unwrap_or_else(|e| panic!("{e}"));
    let desc = reading.devices.pop().expect("one device");
    let source = reading.sources.pop().expect("one source map");
    let mut findings = reading.findings;
    findings.extend(validate_mapped(&desc, &source));
    let text = findings
        .iter()
        .map(|f| {
            assert_eq!(f.severity, Severity::Warning, "{f}");
            let p = f.position.expect("every finding has a position");
            format!("{}:{}: {f}", p.line, p.column)
        })
        .collect();
    (desc, text)
}

/// The mandatory objects, so that the checks have nothing to say about them.
const MANDATORY: &str = "\
[1000]
ParameterName=Device type
DataType=0x0007
AccessType=ro
DefaultValue=0x00000191
[1018]
ParameterName=Identity
ObjectType=0x9
[1018sub0]
ParameterName=Highest sub-index supported
DataType=0x0005
AccessType=ro
DefaultValue=0
";

/// CANopenNode maps a BOOLEAN into a whole byte (`0x20000108`), as CANopen maps every BOOLEAN: no
/// finding. An UNSIGNED16 mapped with 8 bits is a warning (the mapping loads, the value is cut); a
/// mapping of sub-index 0 = 0xFE (SAM-MPDO) or 0xFF (DAM-MPDO, whose entry addresses an object of the
/// consumer) lists no entries of this dictionary (CiA 301 §7.5.2.36).
#[test]
fn boolean_bytes_short_mappings_and_mpdos() {
    let text = format!(
        "{MANDATORY}\
[1600]
ParameterName=RPDO mapping parameter
ObjectType=0x9
[1600sub0]
ParameterName=Number of mapped objects
DataType=0x0005
AccessType=rw
DefaultValue=2
[1600sub1]
ParameterName=Mapped object 1
DataType=0x0007
AccessType=rw
DefaultValue=0x20000108
[1600sub2]
ParameterName=Mapped object 2
DataType=0x0007
AccessType=rw
DefaultValue=0x20000208
[1A00]
ParameterName=TPDO mapping parameter
ObjectType=0x9
[1A00sub0]
ParameterName=Number of mapped objects
DataType=0x0005
AccessType=rw
DefaultValue=0xFE
[1A01]
ParameterName=TPDO mapping parameter
ObjectType=0x9
[1A01sub0]
ParameterName=Number of mapped objects
DataType=0x0005
AccessType=rw
DefaultValue=0xFF
[1A01sub1]
ParameterName=Mapped object 1
DataType=0x0007
AccessType=rw
DefaultValue=0x30000020
[2000]
ParameterName=Outputs
ObjectType=0x9
[2000sub0]
ParameterName=Highest sub-index supported
DataType=0x0005
AccessType=ro
DefaultValue=2
[2000sub1]
ParameterName=Enable
DataType=0x0001
AccessType=rww
PDOMapping=1
[2000sub2]
ParameterName=Speed
DataType=0x0006
AccessType=rww
PDOMapping=1
"
    );
    let (desc, findings) = read_and_check(&text);
    assert_eq!(
        findings,
        ["27:2: warning: 0x1600:00: maps 0x2000:02 with 8 bits, its type UNSIGNED16 has 16"]
    );
    let d = &desc.dictionary;
    assert_eq!(d.read_value(0x1600, 1).unwrap(), Value::Uint(0x2000_0108));
    assert_eq!(d.entry(0x2000, 1).unwrap().data_type, DataType::Boolean);
    assert_eq!(d.read_value(0x1A00, 0).unwrap(), Value::Uint(0xFE));
    assert_eq!(d.read_value(0x1A01, 0).unwrap(), Value::Uint(0xFF));
    assert_eq!(d.read_value(0x1A01, 1).unwrap(), Value::Uint(0x3000_0020));
}

/// Reads `text` and gives back the description and the reader's warnings as `line:column: message`.
fn read_warnings(text: &str) -> (od::DeviceDescription, Vec<String>) {
    let mut reading =
        eds::read_file(text.as_bytes(), "habit.eds").unwrap_or_else(|e| panic!("{e}"));
    let text = reading
        .findings
        .iter()
        .map(|f| {
            assert_eq!(f.severity, Severity::Warning, "{f}");
            let p = f.position.expect("a reader warning has a position");
            format!("{}:{}: {}", p.line, p.column, f.message)
        })
        .collect();
    (reading.devices.pop().expect("one device"), text)
}

/// Defaults, limits and parameter values that are no value of their type: SOMANET's `0xDEADBEEF` for an
/// INTEGER16, openPOWERLINK's `0` for an OCTET_STRING, python-canopen's `@ABCD` for a DOMAIN, `$NODEID`
/// where it cannot go. python-canopen catches the ValueError and skips such a value; so does the reader,
/// with a warning, and the entry loads without it.
#[test]
fn values_that_are_no_value_of_their_type_are_dropped() {
    let text = "\
[2000]
ParameterName=Position window
DataType=0x0003
AccessType=rw
DefaultValue=0xDEADBEEF
LowLimit=-40000
HighLimit=0x7FFF
[2001]
ParameterName=Address
DataType=0x000A
AccessType=rw
DefaultValue=0
[2002]
ParameterName=Offset
DataType=0x0008
AccessType=rw
DefaultValue=$NODEID+1.5
LowLimit=$NODEID
[2003]
ParameterName=Count
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID-1
ParameterValue=twelve
[2004]
ParameterName=Blob
DataType=0x000F
AccessType=rw
DefaultValue=@ABCD
";
    let (desc, warnings) = read_warnings(text);
    assert_eq!(
        warnings,
        [
            "5:14: DefaultValue= in [2000]: 0xDEADBEEF does not fit in INTEGER16, -32768 to 32767; the default is dropped",
            "6:10: LowLimit= in [2000]: -40000 does not fit in INTEGER16, -32768 to 32767; the limit is dropped",
            "12:14: DefaultValue= in [2001]: `0` is not a OCTET_STRING value: expected hexadecimal byte digits; the default is dropped",
            "17:14: DefaultValue= in [2002]: `$NODEID+1.5` adds the node-ID to a REAL32, and $NODEID is added to integers only; the default is dropped",
            "18:10: LowLimit= in [2002]: `$NODEID` adds the node-ID, which a limit cannot; the limit is dropped",
            "23:14: DefaultValue= in [2003]: `$NODEID-1` is not `$NODEID`, `$NODEID+offset` or `offset+$NODEID`; the default is dropped",
            "24:16: ParameterValue= in [2003]: `twelve` is not a UNSIGNED32 value: expected an integer; the value is dropped",
            "29:14: DefaultValue= in [2004]: `@ABCD` is not a DOMAIN value: expected hexadecimal byte digits; the default is dropped",
        ]
    );
    let d = &desc.dictionary;
    let window = d.entry(0x2000, 0).unwrap();
    assert_eq!(window.default, None);
    assert_eq!(window.low, None);
    assert_eq!(window.high, Some(Value::Int(0x7FFF)));
    assert_eq!(window.value, [0, 0]);
    let address = d.entry(0x2001, 0).unwrap();
    assert_eq!(
        (address.default.clone(), address.value.clone()),
        (None, vec![])
    );
    let offset = d.entry(0x2002, 0).unwrap();
    assert_eq!((offset.default.clone(), offset.low.clone()), (None, None));
    let count = d.entry(0x2003, 0).unwrap();
    assert_eq!(count.default, None);
    assert_eq!(count.value, [0; 4]);
    assert!(!count.value_set);
    assert_eq!(d.entry(0x2004, 0).unwrap().default, None);
    // What was kept writes and reads back without a warning.
    let again = eds::write_eds(&desc);
    let (back, warnings) = read_warnings(&again);
    assert_eq!(warnings, Vec::<String>::new());
    assert_eq!(od::diff::diff(&back.dictionary, &desc.dictionary), []);
}

/// CANopenNode's editor writes C integer literals: `0x1234567890ABCDEFLL` for an INTEGER64,
/// `$NODEID+0x100u`. Lely's C lexer reads the number and stops at the suffix; so does the reader, with a
/// warning.
#[test]
fn c_integer_suffixes_are_dropped() {
    let text = "\
[2120]
ParameterName=Demo record
ObjectType=0x9
[2120sub0]
ParameterName=Highest sub-index supported
DataType=0x0005
AccessType=ro
DefaultValue=2
[2120sub1]
ParameterName=I64
DataType=0x0015
AccessType=rw
DefaultValue=0x1234567890ABCDEFLL
[2120sub2]
ParameterName=U16
DataType=0x0006
AccessType=rw
DefaultValue=$NODEID+0x100u
LowLimit=10UL
[2120sub3]
ParameterName=Text
DataType=0x0009
AccessType=rw
DefaultValue=10UL
";
    let (desc, warnings) = read_warnings(text);
    assert_eq!(
        warnings,
        [
            "13:14: DefaultValue= in [2120sub1]: the C suffix `LL` of `0x1234567890ABCDEFLL` is dropped",
            "18:14: DefaultValue= in [2120sub2]: the C suffix `u` of `$NODEID+0x100u` is dropped",
            "19:10: LowLimit= in [2120sub2]: the C suffix `UL` of `10UL` is dropped",
        ]
    );
    let d = &desc.dictionary;
    assert_eq!(
        d.entry(0x2120, 1).unwrap().default,
        Some(od::DefaultValue::plain(Value::Int(0x1234_5678_90AB_CDEF)))
    );
    assert_eq!(
        d.entry(0x2120, 2).unwrap().default,
        Some(od::DefaultValue {
            value: Value::Uint(0x100),
            plus_node_id: true
        })
    );
    assert_eq!(d.entry(0x2120, 2).unwrap().low, Some(Value::Uint(10)));
    // In a string, the letters are text.
    assert_eq!(
        d.entry(0x2120, 3).unwrap().default,
        Some(od::DefaultValue::plain(Value::String("10UL".into())))
    );
    let (back, warnings) = read_warnings(&eds::write_eds(&desc));
    assert_eq!(warnings, Vec::<String>::new());
    assert_eq!(od::diff::diff(&back.dictionary, &desc.dictionary), []);
}

/// CANopenEditor's Python port writes `ObjectType=VAR` and `DataType=UNSIGNED32`: the CiA 301 names
/// instead of the numbers. A name says which code or type as plainly as the number, so it is read, with a
/// warning; a word that names none stays an error.
#[test]
fn object_types_and_data_types_by_name() {
    let text = "\
[1000]
ParameterName=Device Type
ObjectType=VAR
DataType=UNSIGNED32
AccessType=ro
DefaultValue=0x00000000
[1018]
ParameterName=Identity
ObjectType=record
[1018sub0]
ParameterName=Highest sub-index supported
DataType=unsigned8
AccessType=ro
DefaultValue=1
[1018sub1]
ParameterName=Vendor-ID
DataType=0x0007
AccessType=ro
";
    let (desc, warnings) = read_warnings(text);
    assert_eq!(
        warnings,
        [
            "3:12: ObjectType= in [1000]: `VAR` is the name of an object code, not a code; read as 0x7 (VAR)",
            "4:10: DataType= in [1000]: `UNSIGNED32` is the name of data type 0x0007, not its index; read as UNSIGNED32",
            "9:12: ObjectType= in [1018]: `record` is the name of an object code, not a code; read as 0x9 (RECORD)",
            "12:10: DataType= in [1018sub0]: `unsigned8` is the name of data type 0x0005, not its index; read as UNSIGNED8",
        ]
    );
    let d = &desc.dictionary;
    assert_eq!(d.object(0x1000).unwrap().kind, od::ObjectKind::Var);
    assert_eq!(d.entry(0x1000, 0).unwrap().data_type, DataType::Unsigned32);
    assert_eq!(d.object(0x1018).unwrap().kind, od::ObjectKind::Record);
    assert_eq!(d.entry(0x1018, 0).unwrap().data_type, DataType::Unsigned8);
    assert_eq!(d.read_value(0x1018, 0).unwrap(), Value::Uint(1));

    let err = eds::read(
        b"[1000]\nParameterName=x\nObjectType=STRUCT\nDataType=7\nAccessType=ro\n",
        "bad.eds",
    )
    .unwrap_err();
    assert_eq!(
        err.to_string(),
        "bad.eds:3:12: ObjectType= in [1000]: expected an object code: 0x7 (VAR), 0x8 (ARRAY), 0x9 (RECORD), 0x2 (DOMAIN), 0x5 (DEFTYPE), 0x6 (DEFSTRUCT) or 0x0 (NULL), found `STRUCT`"
    );
    let err = eds::read(
        b"[1000]\nParameterName=x\nDataType=UINT32\nAccessType=ro\n",
        "bad.eds",
    )
    .unwrap_err();
    assert_eq!(
        err.to_string(),
        "bad.eds:3:10: DataType= in [1000]: expected a CiA 301 data type index like 0x0007, found `UINT32`"
    );
}

/// Lely writes TIME_OF_DAY and TIME_DIFFERENCE values as `days ms` (`365 43200000`, its test
/// co-sdev.dcf), separated by a blank; the reader takes that as well as `days:ms`.
#[test]
fn lely_time_values() {
    let text = "\
[200C]
ParameterName=TIME_OF_DAY value
DataType=0x000C
AccessType=rw
DefaultValue=0 0
ParameterValue=365 43200000
[200D]
ParameterName=TIME_DIFFERENCE value
DataType=0x000D
AccessType=rw
DefaultValue=1:2
";
    let (desc, warnings) = read_warnings(text);
    assert_eq!(warnings, Vec::<String>::new());
    let d = &desc.dictionary;
    let time = |days, ms| Value::Time(od::value::TimeValue { ms, days });
    assert_eq!(
        d.entry(0x200C, 0).unwrap().default,
        Some(od::DefaultValue::plain(time(0, 0)))
    );
    assert_eq!(d.read_value(0x200C, 0).unwrap(), time(365, 43_200_000));
    assert_eq!(
        d.entry(0x200C, 0).unwrap().value,
        [0x00, 0x2E, 0x93, 0x02, 0x6D, 0x01]
    );
    assert_eq!(d.read_value(0x200D, 0).unwrap(), time(1, 2));
    // Written in Lely's form, which Lely reads back.
    let text = eds::write_eds(&desc);
    assert!(text.contains("DefaultValue=0 0\r\nPDOMapping=0\r\nParameterValue=365 43200000\r\n"));
    assert!(text.ends_with("DefaultValue=1 2\r\nPDOMapping=0\r\n"));
    assert_eq!(
        eds::read(text.as_bytes(), "times.eds").unwrap().dictionary,
        desc.dictionary
    );
}

/// python-canopen's receiver.eds has `CompactSubObj=255` on 0x1003: entries up to sub-index 0xFF, which
/// CiA 301 keeps for the object's structure (an ARRAY has at most 254 entries). Lely builds all 255
/// (python-canopen builds entries on demand, with no bound); so does the reader, with a warning. Written
/// back one section per entry, the 256 sub-indices say `SubNumber=0xFF`, the largest the key holds.
#[test]
fn compact_sub_obj_255() {
    let text = "\
[1003]
ParameterName=Pre-defined error field
ObjectType=0x8
CompactSubObj=255
DataType=0x0007
AccessType=ro
PDOMapping=0
";
    let (desc, warnings) = read_warnings(text);
    assert_eq!(
        warnings,
        ["4:15: CompactSubObj= in [1003]: 255 entries reach sub-index 0xFF, which CiA 301 keeps for the object's structure; read as 255 entries, as Lely does"]
    );
    let errors = desc.dictionary.object(0x1003).unwrap();
    assert_eq!(errors.subs.len(), 256);
    assert_eq!(errors.subs[&0].name, "NrOfObjects");
    assert_eq!(
        errors.subs[&0].default,
        Some(od::DefaultValue::plain(Value::Uint(255)))
    );
    assert_eq!(errors.subs[&255].name, "Pre-defined error field255");
    assert_eq!(errors.subs[&255].data_type, DataType::Unsigned32);
    let written = eds::write_eds(&desc);
    assert!(written.contains(
        "[1003]\r\nParameterName=Pre-defined error field\r\nObjectType=0x8\r\nSubNumber=0xFF\r\n\r\n[1003sub0]\r\n"
    ));
    assert!(written.contains("[1003subFF]\r\nParameterName=Pre-defined error field255\r\n"));
    let (back, warnings) = read_warnings(&written);
    assert_eq!(warnings, Vec::<String>::new());
    assert_eq!(od::diff::diff(&back.dictionary, &desc.dictionary), []);
}

/// ros_canopen's and ros2_canopen's DCFs are templates for a node whose ID is set at run time: they
/// give `ParameterValue=$NODEID+0x80000200` and no `[DeviceComissioning]`. The value stays relative to
/// the node-ID: resolved with 0 while there is none, written back as `$NODEID+…`, and moved with the
/// node-ID when one is set. A relative value that does not fit for node 127 is dropped with a warning,
/// as a relative default is.
#[test]
fn parameter_values_relative_to_an_unknown_node_id() {
    let text = "\
[DeviceInfo]
ProductName=Gripper
[1400]
ParameterName=RPDO 1 communication parameter
ObjectType=0x9
[1400sub0]
ParameterName=Highest sub-index supported
DataType=0x0005
AccessType=ro
DefaultValue=2
[1400sub1]
ParameterName=COB-ID used by RPDO 1
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x200
ParameterValue=$NODEID+0x80000200
[1400sub2]
ParameterName=Transmission type
DataType=0x0005
AccessType=rw
DefaultValue=255
ParameterValue=1
[2000]
ParameterName=Address
DataType=0x0006
AccessType=rw
ParameterValue=$NODEID+0xFFFF
";
    let (mut desc, warnings) = read_warnings(text);
    assert_eq!(
        warnings,
        ["27:16: ParameterValue= in [2000]: with node-ID 127 the value does not fit: 65662 does not fit in UNSIGNED16, 0 to 65535; the value is dropped"]
    );
    assert_eq!(desc.commissioning, None);
    let cob = desc.dictionary.entry(0x1400, 1).unwrap();
    assert_eq!(
        cob.default,
        Some(od::DefaultValue {
            value: Value::Uint(0x200),
            plus_node_id: true
        })
    );
    assert_eq!(cob.value, [0x00, 0x02, 0x00, 0x80]);
    assert!(cob.value_set && cob.value_plus_node_id);
    let address = desc.dictionary.entry(0x2000, 0).unwrap();
    assert!(!address.value_set && !address.value_plus_node_id);
    assert_eq!(address.value, [0, 0]);

    // Written as an EDS, the file's values stay as they are.
    let text = eds::write_eds(&desc);
    assert!(!text.contains("DeviceComissioning"));
    let back = eds::read(text.as_bytes(), "template.eds").unwrap();
    assert_eq!(back.dictionary, desc.dictionary);
    assert_eq!(back.commissioning, None);
    // Configured as `esi-gen dcf` does, every writable entry gets a value (0x2000, without one of its own,
    // its zero).
    let mut configured = desc.clone();
    configured.configure_writable();
    let dcf = eds::write_dcf(&configured);
    assert!(dcf.contains(
        "[1400sub1]\r\nParameterName=COB-ID used by RPDO 1\r\nObjectType=0x7\r\nDataType=0x0007\r\n\
         AccessType=rw\r\nDefaultValue=$NODEID+0x200\r\nPDOMapping=0\r\nParameterValue=$NODEID+0x80000200\r\n\r\n\
         [1400sub2]\r\nParameterName=Transmission type\r\nObjectType=0x7\r\nDataType=0x0005\r\nAccessType=rw\r\n\
         DefaultValue=0xFF\r\nPDOMapping=0\r\nParameterValue=0x01\r\n\r\n\
         [2000]\r\nParameterName=Address\r\nObjectType=0x7\r\nDataType=0x0006\r\nAccessType=rw\r\nPDOMapping=0\r\n\
         ParameterValue=0x0000\r\n"
    ));
    assert!(!dcf.contains("NodeID="));
    let back = eds::read(dcf.as_bytes(), "template.dcf").unwrap();
    assert_eq!(back.dictionary, configured.dictionary);
    assert!(back.dictionary.entry(0x2000, 0).unwrap().value_set);

    // Configured for node 5: the COB-ID follows, and is still written relative.
    desc.set_node_id(Some(5));
    assert_eq!(
        desc.dictionary.read_value(0x1400, 1).unwrap(),
        Value::Uint(0x8000_0205)
    );
    assert_eq!(
        desc.dictionary.read_value(0x1400, 2).unwrap(),
        Value::Uint(1)
    );
    let dcf = eds::write_dcf(&desc);
    assert!(dcf.contains(
        "[DeviceComissioning]\r\nNodeID=5\r\nNodeName=\r\nBaudrate=0\r\nNetNumber=0\r\nNetworkName=\r\n\
         CANopenManager=0\r\n\r\n"
    ));
    assert!(dcf.contains("PDOMapping=0\r\nParameterValue=$NODEID+0x80000200\r\n"));
    let back = eds::read(dcf.as_bytes(), "node5.dcf").unwrap();
    assert_eq!(od::diff::diff(&back.dictionary, &desc.dictionary), []);
    assert!(back.dictionary.entry(0x1400, 1).unwrap().value_plus_node_id);
    assert_eq!(back.node_id(), Some(5));
}

/// Lely's DCFs of a node that LSS is yet to configure say `NodeID=0xff` (co-gw_txt-slave.dcf) or have no
/// `[DeviceComissioning]` at all (cocatd.dcf, coctl.dcf); Lely reads both as unconfigured. So does the
/// reader, with a warning where a section says so, and `NodeID=0`, any other number that is no node-ID
/// and a section without `NodeID` alike. The node-ID is unknown: `$NODEID+0x80` reads as 0x80 and the
/// DCF written back has no `NodeID=` (it once got `NodeID=1`, and 0x1014 came back as 0x81).
#[test]
fn unconfigured_node_ids() {
    let body = "\
[1014]
ParameterName=COB-ID EMCY
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x80
";
    let with = |section: &str| format!("{section}{body}");
    for (section, warning) in [
        (
            "[DeviceComissioning]\nNodeID=0xff\nNodeName=slave\n",
            "2:8: NodeID= in [DeviceComissioning]: `0xff` marks a node that LSS has yet to configure; the node is unconfigured, and `$NODEID` values stay relative to the node-ID",
        ),
        (
            "[DeviceComissioning]\nNodeID=0\nNodeName=slave\n",
            "2:8: NodeID= in [DeviceComissioning]: `0` is no node-ID (1 to 127); the node is unconfigured, and `$NODEID` values stay relative to the node-ID",
        ),
        (
            "[DeviceComissioning]\nNodeID=300\nNodeName=slave\n",
            "2:8: NodeID= in [DeviceComissioning]: `300` is no node-ID (1 to 127); the node is unconfigured, and `$NODEID` values stay relative to the node-ID",
        ),
        (
            "[DeviceComissioning]\nNodeName=slave\n",
            "1:2: [DeviceComissioning] has no NodeID=; the node is unconfigured, and `$NODEID` values stay relative to the node-ID",
        ),
    ] {
        let (desc, warnings) = read_warnings(&with(section));
        assert_eq!(warnings, [warning]);
        let c = desc.commissioning.as_ref().unwrap();
        assert_eq!((c.node_id, c.node_name.as_str()), (None, "slave"));
        assert_eq!(desc.dictionary.entry(0x1014, 0).unwrap().value, [0x80, 0, 0, 0]);
        let mut configured = desc.clone();
        configured.configure_writable();
        let dcf = eds::write_dcf(&configured);
        assert!(dcf.contains(
            "[DeviceComissioning]\r\nNodeName=slave\r\nBaudrate=0\r\nNetNumber=0\r\nNetworkName=\r\n\
             CANopenManager=0\r\n\r\n"
        ));
        assert!(dcf.contains(
            "[1014]\r\nParameterName=COB-ID EMCY\r\nObjectType=0x7\r\nDataType=0x0007\r\nAccessType=rw\r\n\
             DefaultValue=$NODEID+0x80\r\nPDOMapping=0\r\nParameterValue=$NODEID+0x80\r\n"
        ));
        let back = eds::read(dcf.as_bytes(), "unconfigured.dcf").unwrap();
        assert_eq!(back.commissioning, desc.commissioning);
        assert_eq!(back.dictionary, configured.dictionary);
        assert_eq!(od::diff::diff(&back.dictionary, &configured.dictionary), []);
        // An EDS keeps the section, and so the node's being unconfigured.
        let back = eds::read(eds::write_eds(&desc).as_bytes(), "unconfigured.eds").unwrap();
        assert_eq!(back.commissioning, desc.commissioning);
        assert_eq!(back.dictionary, desc.dictionary);
    }
    // No section: no commissioning values, and none are made up.
    let (desc, warnings) = read_warnings(body);
    assert_eq!(warnings, Vec::<String>::new());
    assert_eq!(desc.commissioning, None);
    let dcf = eds::write_dcf(&desc);
    assert!(!dcf.contains("NodeID"));
    let back = eds::read(dcf.as_bytes(), "cocatd.dcf").unwrap();
    assert_eq!(od::diff::diff(&back.dictionary, &desc.dictionary), []);
    assert_eq!(
        back.dictionary.entry(0x1014, 0).unwrap().value,
        [0x80, 0, 0, 0]
    );
}

/// python-canopen's e35.eds gives `ParameterValue`s in an EDS (`0x1006` = 0x1, `0x1014` = 0xA0 beside
/// its `$NODEID+0x80` default), and its sample.eds the `[xxxxValue]` entries of a compact array. They
/// are current values like a DCF's, and an EDS written from the description keeps them, each in the
/// sub-index section of the array (the writer writes no compact arrays).
#[test]
fn parameter_values_in_an_eds() {
    let text = "\
[1006]
ParameterName=Cycle Period
DataType=0x0007
AccessType=rw
ParameterValue=0x1
[1014]
ParameterName=COB-ID Emergency message
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x80
ParameterValue=0xA0
[3004]
ParameterName=Sensor Status
ObjectType=0x8
DataType=0x0006
AccessType=ro
DefaultValue=3
CompactSubObj=2
[3004Value]
NrOfEntries=1
2=0x10
";
    let (desc, warnings) = read_warnings(text);
    assert_eq!(warnings, Vec::<String>::new());
    let d = &desc.dictionary;
    assert_eq!(d.read_value(0x1006, 0).unwrap(), Value::Uint(1));
    assert_eq!(d.read_value(0x1014, 0).unwrap(), Value::Uint(0xA0));
    assert!(d.entry(0x1014, 0).unwrap().value_set);
    assert!(!d.entry(0x1014, 0).unwrap().value_plus_node_id);
    assert_eq!(d.read_value(0x3004, 1).unwrap(), Value::Uint(3));
    assert_eq!(d.read_value(0x3004, 2).unwrap(), Value::Uint(0x10));
    let written = eds::write_eds(&desc);
    for section in [
        "[1006]\r\nParameterName=Cycle Period\r\nObjectType=0x7\r\nDataType=0x0007\r\nAccessType=rw\r\n\
         PDOMapping=0\r\nParameterValue=0x00000001\r\n\r\n",
        "[1014]\r\nParameterName=COB-ID Emergency message\r\nObjectType=0x7\r\nDataType=0x0007\r\n\
         AccessType=rw\r\nDefaultValue=$NODEID+0x80\r\nPDOMapping=0\r\nParameterValue=0x000000A0\r\n\r\n",
        "[3004sub1]\r\nParameterName=Sensor Status1\r\nObjectType=0x7\r\nDataType=0x0006\r\nAccessType=ro\r\n\
         DefaultValue=0x0003\r\nPDOMapping=0\r\n\r\n",
        "[3004sub2]\r\nParameterName=Sensor Status2\r\nObjectType=0x7\r\nDataType=0x0006\r\nAccessType=ro\r\n\
         DefaultValue=0x0003\r\nPDOMapping=0\r\nParameterValue=0x0010\r\n",
    ] {
        assert!(written.contains(section), "{section}\n{written}");
    }
    assert!(!written.contains("DeviceComissioning"));
    let back = eds::read(written.as_bytes(), "again.eds").unwrap();
    assert_eq!(back.dictionary, desc.dictionary);
}

/// `DeviceDescription::set_node_id` (`esi-gen dcf --node-id`, `sdo-tool dump`) moves what follows the
/// node-ID and nothing else: a `$NODEID` default still the current value, and a value given as
/// `$NODEID+offset` (unsigned or signed); not a value set explicitly (even one equal to the default for the
/// old node), not another value stored since, not a plain default.
#[test]
fn set_node_id_moves_what_follows_the_node_id() {
    let text = "\
[DeviceComissioning]
NodeID=2
[1017]
ParameterName=Producer heartbeat time
DataType=0x0006
AccessType=rw
DefaultValue=100
[1200]
ParameterName=SDO server parameter
ObjectType=0x9
[1200sub1]
ParameterName=COB-ID client to server
DataType=0x0007
AccessType=ro
DefaultValue=$NODEID+0x600
[1200sub2]
ParameterName=COB-ID server to client
DataType=0x0007
AccessType=ro
DefaultValue=$NODEID+0x580
ParameterValue=0x582
[1400]
ParameterName=RPDO 1 communication parameter
ObjectType=0x9
[1400sub1]
ParameterName=COB-ID used by RPDO 1
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x200
[1800]
ParameterName=TPDO 1 communication parameter
ObjectType=0x9
[1800sub1]
ParameterName=COB-ID used by TPDO 1
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x180
ParameterValue=$NODEID+0x1C0
[2000]
ParameterName=Offset
DataType=0x0004
AccessType=rw
ParameterValue=$NODEID+5
";
    let (mut desc, warnings) = read_warnings(text);
    assert_eq!(warnings, Vec::<String>::new());
    let value =
        |desc: &od::DeviceDescription, index, sub| desc.dictionary.read_value(index, sub).unwrap();
    assert_eq!(value(&desc, 0x1200, 1), Value::Uint(0x602));
    assert_eq!(value(&desc, 0x2000, 0), Value::Int(7));
    // 0x1400:01 stored from the device's side, another value than its default: it stays.
    desc.dictionary
        .store_value(0x1400, 1, &Value::Uint(0x2FF))
        .unwrap();
    desc.set_node_id(Some(7));
    assert_eq!(desc.node_id(), Some(7));
    assert_eq!(value(&desc, 0x1017, 0), Value::Uint(100));
    assert_eq!(
        value(&desc, 0x1200, 1),
        Value::Uint(0x607),
        "the default follows"
    );
    assert_eq!(
        value(&desc, 0x1200, 2),
        Value::Uint(0x582),
        "set explicitly"
    );
    assert_eq!(value(&desc, 0x1400, 1), Value::Uint(0x2FF), "stored");
    assert_eq!(value(&desc, 0x1800, 1), Value::Uint(0x1C7), "relative");
    assert_eq!(value(&desc, 0x2000, 0), Value::Int(12), "relative, signed");
    let dcf = eds::write_dcf(&desc);
    assert!(dcf.contains("[DeviceComissioning]\r\nNodeID=7\r\n"));
    assert!(dcf.contains(
        "DefaultValue=$NODEID+0x180\r\nPDOMapping=0\r\nParameterValue=$NODEID+0x1C0\r\n"
    ));
    assert!(dcf.ends_with("AccessType=rw\r\nPDOMapping=0\r\nParameterValue=$NODEID+5\r\n"));
    // The stored value comes back set, as every value that differs from its default does.
    let back = eds::read(dcf.as_bytes(), "node7.dcf").unwrap();
    let said: Vec<String> = od::diff::diff(&desc.dictionary, &back.dictionary)
        .iter()
        .map(|d| d.to_string())
        .collect();
    assert_eq!(said, ["~ 0x1400:01 value set: no -> yes"]);
    assert!(back.dictionary.entry(0x1400, 1).unwrap().value_set);
    // Unconfigured again: resolved with 0.
    desc.set_node_id(None);
    assert_eq!(desc.commissioning.as_ref().unwrap().node_id, None);
    assert_eq!(value(&desc, 0x1200, 1), Value::Uint(0x600));
    assert_eq!(value(&desc, 0x2000, 0), Value::Int(5));
}

/// `DeviceDescription::configure_writable` (`esi-gen dcf`): every writable entry is set, so that a DCF
/// carries it, except a DOMAIN and the command entries of CiA 301 and CiA 302 (0x1003:00, 0x1010, 0x1011,
/// 0x1F25, 0x1F51), which a device refuses or acts on. An entry at its `$NODEID` default, also one
/// resolved with 0 (an EDS given a node-ID without `set_node_id`), gets the default for the node-ID,
/// relative to it.
#[test]
fn configure_writable_sets_the_settings_and_no_commands() {
    let entry = |index: &str, access: &str, default: &str| {
        format!(
            "[{index}]\nParameterName=x{index}\nDataType=0x0007\nAccessType={access}\nDefaultValue={default}\n"
        )
    };
    let mut text = String::new();
    for (index, access, default) in [
        ("1000", "ro", "0x191"),
        ("1014", "rw", "$NODEID+0x80"),
        ("1017", "rw", "0"),
        ("2000", "wo", "7"),
        ("2001", "rww", "8"),
        ("2002", "rwr", "9"),
        ("2003", "const", "10"),
    ] {
        text.push_str(&entry(index, access, default));
    }
    for index in ["1003", "1010", "1011", "1F25", "1F51"] {
        text.push_str(&format!(
            "[{index}]\nParameterName=x{index}\nObjectType=0x8\n[{index}sub0]\nParameterName=n\nDataType=0x0005\nAccessType=rw\nDefaultValue=1\n\
             [{index}sub1]\nParameterName=e\nDataType=0x0007\nAccessType=rw\nDefaultValue=1\n"
        ));
    }
    text.push_str("[1F50]\nParameterName=Program data\nDataType=0x000F\nAccessType=wo\n");
    let (mut desc, warnings) = read_warnings(&text);
    assert_eq!(warnings, Vec::<String>::new());
    // A node-ID given without moving the values: 0x1014 still holds 0x80, its default for node 0.
    desc.commissioning = Some(od::device::Commissioning {
        node_id: Some(3),
        ..Default::default()
    });
    desc.configure_writable();
    let set: Vec<String> = desc
        .dictionary
        .objects()
        .flat_map(|o| {
            o.subs
                .iter()
                .filter(|(_, s)| s.value_set)
                .map(move |(sub, _)| format!("{:04X}:{sub}", o.index))
        })
        .collect();
    assert_eq!(
        set,
        ["1003:1", "1014:0", "1017:0", "2000:0", "2001:0", "2002:0"]
    );
    let cob = desc.dictionary.entry(0x1014, 0).unwrap();
    assert!(cob.value_plus_node_id);
    assert_eq!(cob.value, [0x83, 0, 0, 0]);
    assert!(!desc.dictionary.entry(0x1017, 0).unwrap().value_plus_node_id);
}

/// A `$NODEID` value must fit for node 127 only where the file gives no node-ID: in a DCF for node 5,
/// `$NODEID+0xFFFFFF90` is 0xFFFFFF95 and loads without a word.
#[test]
fn node_id_values_fit_the_node_the_file_names() {
    let text = "\
[DeviceComissioning]
NodeID=5
[1014]
ParameterName=COB-ID EMCY
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0xFFFFFF90
";
    let (desc, warnings) = read_warnings(text);
    assert_eq!(warnings, Vec::<String>::new());
    assert_eq!(
        desc.dictionary.read_value(0x1014, 0).unwrap(),
        Value::Uint(0xFFFF_FF95)
    );
}

/// The node-ID of a DCF resolves its `$NODEID` defaults in the other formats too: the ESI of a DCF for
/// node 5 gives 0x1800:01 `$NODEID+0x180` as 0x185.
#[test]
fn a_dcf_node_id_resolves_defaults_in_an_esi() {
    let text = "\
[DeviceComissioning]
NodeID=5
[1800]
ParameterName=TPDO 1 communication parameter
ObjectType=0x9
[1800sub1]
ParameterName=COB-ID used by TPDO 1
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x180
";
    let (desc, _) = read_warnings(text);
    let esi = od::esi::write(&desc);
    assert!(esi.contains("<DefaultData>85010000</DefaultData>"), "{esi}");
}

/// A file without `EDSVersion` (Lely writes none), a DCF without `[DeviceComissioning]` (ros_canopen's)
/// and a `[DeviceInfo]` without CAN keys are written as they were read; a new file gets the version of
/// CiA 306 it follows and the CAN keys.
#[test]
fn what_a_file_leaves_out_stays_out() {
    let text = "[FileInfo]\nFileName=plain.dcf\n[DeviceInfo]\nVendorName=V\n[1000]\nParameterName=Device type\nDataType=0x0007\n\
                AccessType=ro\nDefaultValue=0x191\n";
    let mut desc = eds::read(text.as_bytes(), "plain.dcf").unwrap();
    assert_eq!(desc.file_info.format_version, "");
    assert_eq!(desc.commissioning, None);
    assert_eq!(
        desc.can, None,
        "no CAN keys in [DeviceInfo] (Daxbot's sample.eds has no section)"
    );
    for written in [eds::write_eds(&desc), eds::write_dcf(&desc)] {
        assert!(
            written.starts_with("[FileInfo]\r\nFileName=plain.dcf\r\nFileVersion=\r\nFileRevision=\r\nDescription=\r\n"),
            "{written}"
        );
        assert!(!written.contains("[DeviceComissioning]"), "{written}");
        assert!(!written.contains("BaudRate_"), "{written}");
        assert!(!written.contains("[DummyUsage]"), "{written}");
        let back = eds::read(written.as_bytes(), "again.dcf").unwrap();
        assert_eq!(od::diff::diff_devices(&desc, &back), vec![]);
    }
    eds::complete_new_file(&mut desc);
    assert_eq!(desc.file_info.format_version, eds::EDS_VERSION);
    assert_eq!(desc.can, Some(od::device::CanInfo::default()));
    assert!(eds::write_eds(&desc).contains("\r\nOrderCode=\r\nBaudRate_10=0\r\n"));
    assert!(
        eds::write_eds(&desc).contains("\r\nFileRevision=\r\nEDSVersion=4.0\r\nDescription=\r\n")
    );
    desc.file_info.format_version = "3.0".into();
    eds::complete_new_file(&mut desc);
    assert_eq!(
        desc.file_info.format_version, "3.0",
        "a version given stays"
    );
}

/// Lely writes REAL32 and REAL64 values as their IEEE 754 bits in hexadecimal (its test `sdev.dcf` gives π
/// as `0x40490FDB` and `0x400921FB54442D18`): read as those bits, never as the integer they spell.
#[test]
fn lely_reals_in_hexadecimal_are_their_bits() {
    let text = "[2008]\nParameterName=REAL32\nDataType=0x0008\nAccessType=rw\nDefaultValue=1.5\n\
                ParameterValue=0x40490FDB\n\
                [2011]\nParameterName=REAL64\nDataType=0x0011\nAccessType=rw\nDefaultValue=-0.25\n\
                ParameterValue=0x400921FB54442D18\n\
                [2012]\nParameterName=too wide\nDataType=0x0008\nAccessType=rw\nDefaultValue=0x100000000\n";
    let (desc, warnings) = read_warnings(text);
    let d = &desc.dictionary;
    assert_eq!(
        d.read_value(0x2008, 0).unwrap(),
        Value::Real32(std::f32::consts::PI)
    );
    assert_eq!(
        d.read_value(0x2011, 0).unwrap(),
        Value::Real64(std::f64::consts::PI)
    );
    assert_eq!(
        d.entry(0x2011, 0).unwrap().default.as_ref().unwrap().value,
        Value::Real64(-0.25)
    );
    assert_eq!(d.entry(0x2012, 0).unwrap().default, None);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("0x100000000"), "{warnings:?}");
}

/// `AccessType=R` and `AccessType=W` (can2mqtt's files) are read as python-canopen reads them, readable
/// and writable, with a warning; a sub-index 0 that is no UNSIGNED8 is named with its object's kind.
#[test]
fn one_letter_access_types() {
    let text = format!(
        "{MANDATORY}[2000]\nParameterName=Status\nDataType=0x0007\nAccessType=R\n\
         [2001]\nParameterName=Command\nDataType=0x0007\nAccessType=w\n\
         [2002]\nParameterName=Table\nObjectType=0x9\n\
         [2002sub0]\nParameterName=n\nDataType=0x0006\nAccessType=ro\nDefaultValue=1\n\
         [2002sub1]\nParameterName=a\nDataType=0x0007\nAccessType=rw\n"
    );
    let (desc, warnings) = read_and_check(&text);
    let d = &desc.dictionary;
    assert_eq!(d.entry(0x2000, 0).unwrap().access.kind, od::AccessType::Ro);
    assert_eq!(d.entry(0x2001, 0).unwrap().access.kind, od::AccessType::Wo);
    assert_eq!(
        warnings,
        [
            "17:12: warning: AccessType=R in [2000] is no CiA 306 access type; read as ro",
            "21:12: warning: AccessType=w in [2001] is no CiA 306 access type; read as wo",
            "25:2: warning: 0x2002:00: sub-index 0 of a RECORD should be UNSIGNED8, is UNSIGNED16",
        ]
    );
    let bad = text.replace("AccessType=R\n", "AccessType=X\n");
    let e = eds::read(bad.as_bytes(), "habit.eds").unwrap_err();
    assert_eq!(
        e.to_string(),
        "habit.eds:17:12: AccessType= in [2000]: expected ro, wo, rw, rwr, rww or const, found `X`"
    );
}

/// The object lists as Lely reads them (the objects they name, `SupportedObjects` of them) and as
/// python-canopen does (every section): where the two differ, a warning (gocanopen's zipped test file
/// counts 3 and lists 6, lists 0x1019 three times, and lists 0x2000 with no section for it).
#[test]
fn object_lists_that_lely_reads_otherwise() {
    let text = format!(
        "[MandatoryObjects]\nSupportedObjects=3\n1=0x1000\n2=0x1018\n3=0x1019\n4=0x1019\n\
         [ManufacturerObjects]\nSupportedObjects=1\n1=0x2000\n\
         {MANDATORY}\
         [1019]\nParameterName=Sync counter\nDataType=0x0005\nAccessType=rw\n\
         [2001]\nParameterName=Unlisted\nDataType=0x0005\nAccessType=rw\n\
         [2002]\nParameterName=Unlisted too\nDataType=0x0005\nAccessType=rw\n"
    );
    let (desc, warnings) = read_and_check(&text);
    assert_eq!(
        desc.dictionary
            .objects()
            .map(|o| o.index)
            .collect::<Vec<_>>(),
        [0x1000, 0x1018, 0x1019, 0x2001, 0x2002],
        "every section is read"
    );
    assert_eq!(
        warnings,
        [
            "2:18: warning: SupportedObjects=3 in [MandatoryObjects], but it lists 4 object(s)",
            "6:3: warning: [MandatoryObjects] lists 0x1019 again (first in [MandatoryObjects])",
            "9:3: warning: [ManufacturerObjects] lists 0x2000, which has no section [2000] (Lely refuses that)",
            "27:2: warning: 2 object(s) in none of the object lists, which Lely leaves out: [2001], [2002]",
        ]
    );
    // Eight are named, then an ellipsis for more.
    let mut eight = text.clone();
    for i in 3..=8 {
        eight.push_str(&format!(
            "[200{i}]\nParameterName=More\nDataType=0x0005\nAccessType=rw\n"
        ));
    }
    let (_, warnings) = read_and_check(&eight);
    assert_eq!(
        warnings[3],
        "27:2: warning: 8 object(s) in none of the object lists, which Lely leaves out: [2001], \
         [2002], [2003], [2004], [2005], [2006], [2007], [2008]"
    );
    let mut many = text.clone();
    for i in 3..=9 {
        many.push_str(&format!(
            "[200{i}]\nParameterName=More\nDataType=0x0005\nAccessType=rw\n"
        ));
    }
    let (_, warnings) = read_and_check(&many);
    assert_eq!(
        warnings[3],
        "27:2: warning: 9 object(s) in none of the object lists, which Lely leaves out: [2001], \
         [2002], [2003], [2004], [2005], [2006], [2007], [2008], …"
    );
    // Without lists, nothing is said of them.
    let (_, warnings) = read_and_check(&text[text.find("[1000]").unwrap()..]);
    assert_eq!(warnings, Vec::<String>::new());
}

/// Any one CAN key of `[DeviceInfo]`, a bit rate or another, gives the description its CAN capabilities.
#[test]
fn one_can_key_is_enough() {
    for (key, check) in [("BaudRate_250=1", 250u32), ("Granularity=0", 0)] {
        let text = format!("[DeviceInfo]\nVendorName=V\n{key}\n");
        let desc = eds::read(text.as_bytes(), "k.eds").unwrap();
        let can = desc.can.unwrap_or_else(|| panic!("{key}"));
        if check == 250 {
            assert_eq!(can.baud_rates, [250]);
        } else {
            assert_eq!((can.baud_rates.len(), can.granularity), (0, 0));
        }
    }
}
