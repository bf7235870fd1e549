//! Constructs real tools write that the standards (CiA 306, CiA 311, ETG.2000) do not foresee, each
//! read with a warning at its position where the file can still be used, as python-canopen,
//! CANopenEditor or TwinCAT load it; each in a small file of its own.

use od::report::Severity;
use od::DeviceDescription;

/// An EDS of one object, 0x2000 UNSIGNED32 = 7, whose section ends with `extra`.
fn eds(extra: &str) -> String {
    format!(
        "[FileInfo]\r
FileName=constructs.eds\r
EDSVersion=4.0\r
[DeviceInfo]\r
VendorNumber=0x26C\r
[MandatoryObjects]\r
SupportedObjects=0\r
[ManufacturerObjects]\r
SupportedObjects=1\r
1=0x2000\r
[2000]\r
ParameterName=Setting\r
ObjectType=0x7\r
DataType=0x0007\r
AccessType=rw\r
DefaultValue=7\r
PDOMapping=0\r
{extra}"
    )
}

/// The warnings of a reading, each as `line:column: message`.
fn warnings(reading: &od::report::Reading) -> Vec<String> {
    reading
        .findings
        .iter()
        .filter(|f| f.severity == Severity::Warning)
        .map(|f| {
            let p = f.position.expect("a reader warning has a position");
            format!("{}:{}: {}", p.line, p.column, f.message)
        })
        .collect()
}

/// The description and the warnings, each as `line:column: message`.
fn read(text: &str) -> (DeviceDescription, Vec<String>) {
    let reading = od::eds::read_file(text.as_bytes(), "constructs.eds").unwrap_or_else(|e| {
        panic!("refused: {e}");
    });
    let warnings = warnings(&reading);
    (reading.devices.into_iter().next().unwrap(), warnings)
}

/// `ObjFlags=NV` (no number, as some vendor tools write it) and an empty `ObjFlags=` read as no
/// flags with a warning at the value (line 18, column 10); the object and its value stand. A number
/// reads without one.
#[test]
fn object_flags_that_are_no_number_read_as_none_with_a_warning() {
    let (desc, warnings) = read(&eds("ObjFlags=NV\r\n"));
    assert_eq!(
        warnings,
        ["18:10: ObjFlags= in [2000]: `NV` is no 32-bit number; read as no flags"]
    );
    assert_eq!(
        desc.dictionary.read_value(0x2000, 0).unwrap(),
        od::Value::Uint(7)
    );
    let (desc, warnings) = read(&eds("ObjFlags=\r\n"));
    assert_eq!(
        warnings,
        ["18:10: ObjFlags= in [2000] is empty; read as no flags"]
    );
    assert_eq!(desc.dictionary.object(0x2000).unwrap().flags, None);
    assert_eq!(
        desc.dictionary.read_value(0x2000, 0).unwrap(),
        od::Value::Uint(7)
    );
    for flags in ["ObjFlags=0x1\r\n", "ObjFlags=3\r\n"] {
        let (_, warnings) = read(&eds(flags));
        assert!(warnings.is_empty(), "{flags}: {warnings:?}");
    }
}

/// An XDD of one RECORD 0x2001 whose sub-indices are written `sub` (two of them).
fn xdd(sub0: &str, sub1: &str) -> String {
    format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<ISO15745ProfileContainer xmlns="http://www.canopen.org/xml/1.0" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
<ISO15745Profile>
<ProfileBody xsi:type="ProfileBody_Device_CANopen" fileName="t.xdd">
</ProfileBody>
</ISO15745Profile>
<ISO15745Profile>
<ProfileBody xsi:type="ProfileBody_CommunicationNetwork_CANopen" fileName="t.xdd">
<ApplicationLayers>
<CANopenObjectList>
<CANopenObject index="2001" name="Record" objectType="9" subNumber="2">
<CANopenSubObject subIndex="{sub0}" name="Highest sub-index supported" objectType="7" dataType="0005" accessType="ro" defaultValue="1"/>
<CANopenSubObject subIndex="{sub1}" name="Value" objectType="7" dataType="0007" accessType="rw" defaultValue="9"/>
</CANopenObject>
</CANopenObjectList>
</ApplicationLayers>
</ProfileBody>
</ISO15745Profile>
</ISO15745ProfileContainer>
"#
    )
}

/// XDD sub-indices of four digits (`subIndex="0001"`, as CANopenEditor wrote them) are read as the
/// two-digit ones with a warning at each value (lines 12 and 13, column 29); a sub-index whose extra
/// digits are not leading zeros stays an error.
#[test]
fn xdd_sub_indices_of_four_digits_read_with_a_warning() {
    let reading = od::xdd::read_file(xdd("0000", "0001").as_bytes(), "t.xdd").unwrap();
    let warnings = warnings(&reading);
    assert_eq!(
        warnings,
        [
            "12:29: subIndex `0000` has 4 digits where CiA 311 gives 2; read as 00",
            "13:29: subIndex `0001` has 4 digits where CiA 311 gives 2; read as 01",
        ]
    );
    let desc = reading.devices.into_iter().next().unwrap();
    assert_eq!(
        desc.dictionary.read_value(0x2001, 1).unwrap(),
        od::Value::Uint(9)
    );
    let e = od::xdd::read_file(xdd("00", "0101").as_bytes(), "t.xdd").unwrap_err();
    assert!(
        e.to_string()
            .contains("expected a sub-index of 2 hex digits like 01 in subIndex, found `0101`"),
        "{e}"
    );
}

/// An XDC's `nodeID="0"` (a node not yet configured) reads as no node-ID with a warning at the
/// value, as do 255 and an empty `nodeID=""` (python-canopen's XDD import reads it as none); 128
/// stays an error.
#[test]
fn an_xdc_node_id_of_0_is_none_with_a_warning() {
    let with = |id: &str| {
        xdd("00", "01").replace(
            "<ProfileBody xsi:type=\"ProfileBody_CommunicationNetwork_CANopen\" fileName=\"t.xdd\">",
            &format!(
                "<ProfileBody xsi:type=\"ProfileBody_CommunicationNetwork_CANopen\" fileName=\"t.xdd\">\n\
                 <NetworkManagement><deviceCommissioning nodeID=\"{id}\"/></NetworkManagement>"
            ),
        )
    };
    for id in ["0", "255", "", " "] {
        let reading = od::xdd::read_file(with(id).as_bytes(), "t.xdc").unwrap();
        let warnings: Vec<String> = reading
            .findings
            .iter()
            .filter(|f| f.severity == Severity::Warning)
            .map(|f| f.message.clone())
            .collect();
        let given = if id.trim().is_empty() {
            "nodeID is empty, which".to_string()
        } else {
            format!("nodeID `{id}`")
        };
        assert_eq!(
            warnings,
            [format!(
                "{given} is no node-ID (1 to 127); read as none, a node LSS configures"
            )]
        );
        let desc = reading.devices.into_iter().next().unwrap();
        assert_eq!(desc.node_id(), None, "nodeID {id}");
    }
    let e = od::xdd::read_file(with("128").as_bytes(), "t.xdc").unwrap_err();
    assert!(
        e.to_string()
            .contains("expected a nodeID of 1 to 127, found `128`"),
        "{e}"
    );
}

/// `examples/io-device.esi.xml` with `from` replaced by `to` (once): its warnings and its first
/// device.
fn esi_with(from: &str, to: &str) -> (Vec<String>, DeviceDescription) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/io-device.esi.xml");
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.contains(from), "{from}");
    let text = text.replacen(from, to, 1);
    let reading = od::esi::read_file(text.as_bytes(), "io.xml").unwrap_or_else(|e| {
        panic!("refused: {e}");
    });
    let warnings = warnings(&reading);
    (warnings, reading.devices.into_iter().next().unwrap())
}

/// A revision number with its hexadecimal prefix's x doubled (`#xx00010001`) reads as `#x00010001`
/// with a warning at the value.
#[test]
fn an_esi_number_with_a_doubled_x_reads_with_a_warning() {
    let (warnings, desc) = esi_with(
        r##"RevisionNo="#x00010001""##,
        r##"RevisionNo="#xx00010001""##,
    );
    assert_eq!(
        warnings,
        [
            "18:40: `#xx00010001` in the RevisionNo attribute has its hexadecimal prefix's x \
          doubled; read as #x00010001"
        ]
    );
    assert_eq!(desc.identity.revision, 0x0001_0001);
}

/// `<DefaultData>` longer than its type: the first bytes, with a warning at the value where the rest
/// is not zeros (0x1000 UDINT given 5 bytes: 0x000F0191); zeros beyond are read without one.
#[test]
fn esi_default_data_longer_than_its_type_reads_its_first_bytes() {
    let (warnings, desc) = esi_with(
        "<DefaultData>91010F00</DefaultData>",
        "<DefaultData>91010F0007</DefaultData>",
    );
    assert_eq!(
        warnings,
        ["703:32: object #x1000: <DefaultData> has 5 bytes for a UDINT of 4; the first 4 read"]
    );
    assert_eq!(
        desc.dictionary.read_value(0x1000, 0).unwrap(),
        od::Value::Uint(0x000F_0191)
    );
    let (warnings, _) = esi_with(
        "<DefaultData>91010F00</DefaultData>",
        "<DefaultData>91010F000000</DefaultData>",
    );
    assert!(warnings.is_empty(), "{warnings:?}");
}

/// An XDD value that is no value of its entry's type (`defaultValue="0x100000000"` for an
/// UNSIGNED32, `highLimit="none"`) is dropped with a warning at the value, as the EDS reader drops
/// `DefaultValue=300` of an UNSIGNED8 and python-canopen leaves out what it cannot read; the entry
/// and its other values stand.
#[test]
fn xdd_values_that_are_no_value_of_their_type_are_dropped_with_a_warning() {
    let text = xdd("00", "01").replace(
        r#"dataType="0007" accessType="rw" defaultValue="9"/>"#,
        r#"dataType="0007" accessType="rw" defaultValue="0x100000000" lowLimit="1" highLimit="none"/>"#,
    );
    let reading = od::xdd::read_file(text.as_bytes(), "t.xdd").unwrap_or_else(|e| {
        panic!("refused: {e}");
    });
    assert_eq!(
        warnings(&reading),
        [
            "13:107: expected a UNSIGNED32 value in defaultValue of 0x2001:01, found `0x100000000`: \
             0x100000000 does not fit in UNSIGNED32, 0 to 4294967295; the default is dropped",
            "13:144: expected a UNSIGNED32 value in highLimit of 0x2001:01, found `none`: `none` is \
             not a UNSIGNED32 value: expected an integer; the limit is dropped",
        ]
    );
    let desc = reading.devices.into_iter().next().unwrap();
    let entry = desc.dictionary.entry(0x2001, 1).unwrap();
    assert_eq!(entry.default, None);
    assert_eq!(
        (entry.low.clone(), entry.high.clone()),
        (Some(od::Value::Uint(1)), None)
    );
    assert_eq!(
        desc.dictionary.read_value(0x2001, 0).unwrap(),
        od::Value::Uint(1)
    );
}

/// An ESI default that is no value of its type, a number beyond it (`<DefaultValue>#x1000F0191`
/// for a UDINT) or no bytes at all (`<DefaultData></DefaultData>`), is dropped with a warning at
/// the value, as its limits are and as the EDS and XDD readers drop theirs.
#[test]
fn esi_defaults_that_are_no_value_of_their_type_are_dropped_with_a_warning() {
    for (given, warning) in [
        (
            "<DefaultValue>#x1000F0191</DefaultValue>",
            "703:33: object #x1000: expected a UDINT value 0..4294967295 in <DefaultValue>, found \
             `#x1000F0191`; the default is dropped",
        ),
        (
            "<DefaultData></DefaultData>",
            "703:32: object #x1000: <DefaultData> is not a UDINT: UNSIGNED32 takes 4 bytes, got 0; \
             the default is dropped",
        ),
    ] {
        let (warnings, desc) = esi_with("<DefaultData>91010F00</DefaultData>", given);
        assert_eq!(warnings, [warning], "{given}");
        let entry = desc.dictionary.entry(0x1000, 0).unwrap();
        assert_eq!(entry.default, None, "{given}");
        assert_eq!(desc.identity.product_code, 0x191);
    }
}
