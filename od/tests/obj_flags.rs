//! CiA 306 §4.6.3 `ObjFlags` (bit 0 refuse write on download, bit 1 refuse read on scan) and its XDD
//! form, CiA 311 `objFlags`: read where a file gives them (an object's section, a sub-index's), kept
//! apart from their absence, written back only there, and compared by `od::diff`.

use od::diff::diff_devices as diff;
use od::object::ObjFlags;
use od::report::Severity;
use od::DeviceDescription;

/// An EDS with a VAR 0x2000 (`var` ends its section), a RECORD 0x2001 (`record` ends the object's
/// section, `sub1` the section of its sub-index 1) and a VAR 0x2002 with no flags.
fn eds(var: &str, record: &str, sub1: &str) -> String {
    format!(
        "[FileInfo]\r
FileName=flags.eds\r
EDSVersion=4.0\r
[DeviceInfo]\r
VendorNumber=0x26C\r
[MandatoryObjects]\r
SupportedObjects=0\r
[ManufacturerObjects]\r
SupportedObjects=3\r
1=0x2000\r
2=0x2001\r
3=0x2002\r
[2000]\r
ParameterName=Setting\r
ObjectType=0x7\r
DataType=0x0007\r
AccessType=rw\r
DefaultValue=7\r
PDOMapping=0\r
{var}\r
[2001]\r
ParameterName=Record\r
ObjectType=0x9\r
SubNumber=2\r
{record}\r
[2001sub0]\r
ParameterName=Highest sub-index supported\r
ObjectType=0x7\r
DataType=0x0005\r
AccessType=ro\r
DefaultValue=1\r
PDOMapping=0\r
[2001sub1]\r
ParameterName=Value\r
ObjectType=0x7\r
DataType=0x0006\r
AccessType=rw\r
DefaultValue=9\r
PDOMapping=0\r
{sub1}\r
[2002]\r
ParameterName=Plain\r
ObjectType=0x7\r
DataType=0x0005\r
AccessType=rw\r
PDOMapping=0\r
"
    )
}

fn read(text: &str) -> DeviceDescription {
    od::eds::read(text.as_bytes(), "flags.eds").unwrap_or_else(|e| panic!("refused: {e}"))
}

/// The object's flags, and those of each of its entries.
fn flags(desc: &DeviceDescription, index: u16) -> (Option<u32>, Vec<(u8, Option<u32>)>) {
    let o = desc.dictionary.object(index).unwrap();
    (
        o.flags.map(ObjFlags::bits),
        o.subs
            .iter()
            .map(|(&s, e)| (s, e.flags.map(ObjFlags::bits)))
            .collect(),
    )
}

/// The `ObjFlags` lines of an EDS text, each with the section it is in.
fn flag_lines(text: &str) -> Vec<String> {
    let mut section = "";
    let mut lines = Vec::new();
    for line in text.lines() {
        if line.starts_with('[') {
            section = line;
        } else if line.starts_with("ObjFlags") {
            lines.push(format!("{section} {line}"));
        }
    }
    lines
}

/// An object's section holds the object's flags (a VAR's too: its one section is the object's); a
/// sub-index section holds the entry's own. Neither takes the other's: the record's entry 0 has none
/// of its object's 0x2, and a tool asks `flags_of`, which joins them.
#[test]
fn flags_are_read_where_the_file_gives_them() {
    let desc = read(&eds("ObjFlags=0x1", "ObjFlags=0x2", "ObjFlags=1"));
    assert_eq!(flags(&desc, 0x2000), (Some(1), vec![(0, None)]));
    assert_eq!(
        flags(&desc, 0x2001),
        (Some(2), vec![(0, None), (1, Some(1))])
    );
    assert_eq!(flags(&desc, 0x2002), (None, vec![(0, None)]));
    let record = desc.dictionary.object(0x2001).unwrap();
    assert_eq!(record.flags_of(0), ObjFlags::REFUSE_READ_ON_SCAN);
    assert_eq!(
        record.flags_of(1),
        ObjFlags::REFUSE_READ_ON_SCAN.union(ObjFlags::REFUSE_WRITE_ON_DOWNLOAD)
    );
    assert_eq!(
        record.flags_of(7),
        ObjFlags::REFUSE_READ_ON_SCAN,
        "no entry"
    );
    let var = desc.dictionary.object(0x2000).unwrap();
    assert_eq!(var.flags_of(0), ObjFlags::REFUSE_WRITE_ON_DOWNLOAD);
    assert!(desc
        .dictionary
        .object(0x2002)
        .unwrap()
        .flags_of(0)
        .is_empty());
}

/// An explicit 0 is kept apart from no flags, and a number beyond the two bits CiA 306 defines is kept
/// as it is; `NV` in a sub-index section reads as none with a warning at the value, as in an object's.
#[test]
fn zero_reserved_bits_and_no_number() {
    let desc = read(&eds("ObjFlags=0", "ObjFlags=0x80000003", ""));
    assert_eq!(flags(&desc, 0x2000).0, Some(0));
    assert_eq!(flags(&desc, 0x2001).0, Some(0x8000_0003));

    let reading = od::eds::read_file(eds("", "", "ObjFlags=NV").as_bytes(), "flags.eds").unwrap();
    let warnings: Vec<String> = reading
        .findings
        .iter()
        .filter(|f| f.severity == Severity::Warning)
        .map(|f| {
            let p = f.position.unwrap();
            format!("{}:{}: {}", p.line, p.column, f.message)
        })
        .collect();
    assert_eq!(
        warnings,
        ["40:10: ObjFlags= in [2001sub1]: `NV` is no 32-bit number; read as no flags"]
    );
    assert_eq!(flags(&reading.devices[0], 0x2001).1[1], (1, None));
}

/// Written back as `ObjFlags=0x…` where the description has flags, an explicit 0 too, and nowhere
/// else; EDS and DCF read back the same.
#[test]
fn eds_and_dcf_write_them_back_where_they_were() {
    let desc = read(&eds("ObjFlags=0", "ObjFlags=0x3", "ObjFlags=2"));
    let text = od::eds::write_eds(&desc);
    assert_eq!(
        flag_lines(&text),
        [
            "[2000] ObjFlags=0x0",
            "[2001] ObjFlags=0x3",
            "[2001sub1] ObjFlags=0x2",
        ]
    );
    assert_eq!(read(&text), desc);
    let dcf = od::eds::write_dcf(&desc);
    assert_eq!(flag_lines(&dcf), flag_lines(&text));
    assert_eq!(read(&dcf), desc);
}

/// A file without `ObjFlags` gains none, in EDS, DCF and XDD.
#[test]
fn a_file_without_flags_gains_none() {
    let desc = read(&eds("", "", ""));
    assert!(!od::eds::write_eds(&desc).contains("ObjFlags"));
    assert!(!od::eds::write_dcf(&desc).contains("ObjFlags"));
    assert!(!od::xdd::write(&desc).contains("objFlags"));
    let fixture = format!(
        "{}/../fixtures/x67/X67SM2436.eds",
        env!("CARGO_MANIFEST_DIR")
    );
    let (_, devices) = od::load::load(std::path::Path::new(&fixture)).unwrap();
    assert!(!od::eds::write_eds(&devices[0]).contains("ObjFlags"));
}

/// A VAR's entry can have flags of its own only in an XDD (a `CANopenSubObject` under the VAR): an
/// EDS has one section for both, which gets the two together.
#[test]
fn a_var_entry_with_flags_of_its_own_shares_the_one_section() {
    let mut desc = read(&eds("ObjFlags=0x1", "", ""));
    let var = desc.dictionary.object_mut(0x2000).unwrap();
    var.subs.get_mut(&0).unwrap().flags = Some(ObjFlags::REFUSE_READ_ON_SCAN);
    assert_eq!(
        flag_lines(&od::eds::write_eds(&desc)),
        ["[2000] ObjFlags=0x3"]
    );
    let var = desc.dictionary.object_mut(0x2000).unwrap();
    var.flags = None;
    let back = read(&od::eds::write_eds(&desc));
    assert_eq!(flags(&back, 0x2000), (Some(2), vec![(0, None)]));
}

/// An XDD of a VAR 0x2000 (`var` its attributes) and a RECORD 0x2001 (`record` on the object, `sub1`
/// on its entry 1).
fn xdd(var: &str, record: &str, sub1: &str) -> String {
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
<CANopenObject index="2000" name="Setting" objectType="7" dataType="0007" accessType="rw" defaultValue="7" PDOmapping="no" {var}/>
<CANopenObject index="2001" name="Record" objectType="9" subNumber="2" {record}>
<CANopenSubObject subIndex="00" name="Highest sub-index supported" objectType="7" dataType="0005" accessType="ro" defaultValue="1"/>
<CANopenSubObject subIndex="01" name="Value" objectType="7" dataType="0006" accessType="rw" defaultValue="9" {sub1}/>
</CANopenObject>
</CANopenObjectList>
</ApplicationLayers>
</ProfileBody>
</ISO15745Profile>
</ISO15745ProfileContainer>
"#
    )
}

fn read_xdd(text: &str) -> od::report::Reading {
    od::xdd::read_file(text.as_bytes(), "t.xdd").unwrap_or_else(|e| panic!("refused: {e}"))
}

/// `objFlags` (hexBinary) on `CANopenObject` and `CANopenSubObject`, as in an EDS; 8 digits and a
/// `0x` are read too; what is no hexadecimal number of 32 bits reads as none with a warning.
#[test]
fn xdd_reads_obj_flags_of_objects_and_sub_objects() {
    let reading = read_xdd(&xdd(
        r#"objFlags="0001""#,
        r#"objFlags="00000002""#,
        r#"objFlags="0x3""#,
    ));
    assert!(reading.findings.is_empty(), "{:?}", reading.findings);
    let desc = &reading.devices[0];
    assert_eq!(flags(desc, 0x2000), (Some(1), vec![(0, None)]));
    assert_eq!(
        flags(desc, 0x2001),
        (Some(2), vec![(0, None), (1, Some(3))])
    );

    for bad in ["", "zz", "123456789", "000000001", "-1", "+1"] {
        let reading = read_xdd(&xdd(&format!(r#"objFlags="{bad}""#), "", ""));
        let messages: Vec<&str> = reading
            .findings
            .iter()
            .map(|f| f.message.as_str())
            .collect();
        assert_eq!(
            messages,
            [format!(
                "objFlags `{bad}` is no hexBinary number of 32 bits; read as no flags"
            )],
            "{bad}"
        );
        assert_eq!(flags(&reading.devices[0], 0x2000).0, None, "{bad}");
    }
}

/// Written back on the element they belong to, as 4 hexadecimal digits (8 beyond 16 bits), and read
/// back the same; a VAR whose entry has flags of its own is written with a `CANopenSubObject` to
/// keep them apart. EDS → XDD → EDS keeps them.
#[test]
fn xdd_writes_them_back_on_their_element() {
    // 4 digits up to 0xFFFF, 8 beyond.
    for (bits, text) in [(0xFFFF, "FFFF"), (0x1_0000, "00010000")] {
        let desc = read(&eds(&format!("ObjFlags=0x{bits:X}"), "", ""));
        assert!(
            od::xdd::write(&desc).contains(&format!(r#"objFlags="{text}""#)),
            "{text}"
        );
    }
    let mut desc = read(&eds("ObjFlags=0x1", "ObjFlags=0x10002", "ObjFlags=0"));
    desc.file_info.creation_date = "2024-05-31".into();
    let text = od::xdd::write(&desc);
    let lines: Vec<&str> = text.lines().filter(|l| l.contains("objFlags")).collect();
    assert_eq!(lines.len(), 3, "{text}");
    assert!(lines[0].contains(r#"index="2000""#) && lines[0].contains(r#"objFlags="0001""#));
    assert!(lines[1].contains(r#"index="2001""#) && lines[1].contains(r#"objFlags="00010002""#));
    assert!(lines[2].contains(r#"subIndex="01""#) && lines[2].contains(r#"objFlags="0000""#));
    let back = read_xdd(&text).devices.remove(0);
    for index in [0x2000, 0x2001, 0x2002] {
        assert_eq!(flags(&back, index), flags(&desc, index), "0x{index:04X}");
    }
    let again = read(&od::eds::write_eds(&back));
    for index in [0x2000, 0x2001, 0x2002] {
        assert_eq!(flags(&again, index), flags(&desc, index), "0x{index:04X}");
    }

    let var = desc.dictionary.object_mut(0x2000).unwrap();
    var.subs.get_mut(&0).unwrap().flags = Some(ObjFlags::REFUSE_READ_ON_SCAN);
    let text = od::xdd::write(&desc);
    assert!(
        text.contains(r#"<CANopenObject index="2000" name="Setting" objectType="7" subNumber="1" objFlags="0001">"#),
        "{text}"
    );
    assert!(
        text.contains(r#"<CANopenSubObject subIndex="00" name="Setting" objectType="7" dataType="0007" accessType="rw" defaultValue="0x00000007" PDOmapping="no" objFlags="0002"/>"#),
        "{text}"
    );
    let back = read_xdd(&text).devices.remove(0);
    assert_eq!(flags(&back, 0x2000), (Some(1), vec![(0, Some(2))]));
}

/// Two files that differ only in their flags are not equal: the object's, the entry's, and an
/// explicit 0 against none each make a difference, shown with the flags' meaning.
#[test]
fn diff_tells_files_apart_by_their_flags() {
    let base = read(&eds("ObjFlags=0x1", "ObjFlags=0x2", "ObjFlags=0x1"));
    assert!(diff(&base, &base).is_empty());
    let changed = |var: &str, record: &str, sub1: &str| -> Vec<String> {
        diff(&base, &read(&eds(var, record, sub1)))
            .iter()
            .map(ToString::to_string)
            .collect()
    };
    assert_eq!(
        changed("ObjFlags=0x3", "ObjFlags=0x2", "ObjFlags=0x1"),
        ["~ 0x2000 ObjFlags: 0x1 (refuse write on download) -> 0x3 (refuse write on download, refuse read on scan)"]
    );
    assert_eq!(
        changed("ObjFlags=0x1", "", "ObjFlags=0x1"),
        ["~ 0x2001 ObjFlags: 0x2 (refuse read on scan) -> none"]
    );
    assert_eq!(
        changed("ObjFlags=0x1", "ObjFlags=0x2", "ObjFlags=0"),
        ["~ 0x2001:01 ObjFlags: 0x1 (refuse write on download) -> 0x0"]
    );
}

/// The flags as text: the number, then the meaning of the bits CiA 306 defines.
#[test]
fn flags_show_their_meaning() {
    assert_eq!(ObjFlags::NONE.to_string(), "0x0");
    assert_eq!(
        ObjFlags::from_bits(3).to_string(),
        "0x3 (refuse write on download, refuse read on scan)"
    );
    assert_eq!(
        ObjFlags::from_bits(0x6).to_string(),
        "0x6 (refuse read on scan)"
    );
    assert!(ObjFlags::from_bits(3).contains(ObjFlags::REFUSE_WRITE_ON_DOWNLOAD));
    assert!(!ObjFlags::from_bits(2).contains(ObjFlags::REFUSE_WRITE_ON_DOWNLOAD));
    assert!(!ObjFlags::from_bits(2).is_empty());
    assert_eq!(
        ObjFlags::from_bits(3).union(ObjFlags::REFUSE_WRITE_ON_DOWNLOAD),
        ObjFlags::from_bits(3),
        "a set and one of its flags"
    );
    assert_eq!(ObjFlags::from_bits(0x80).bits(), 0x80);
}

/// Real files: Faulhaber flags its calibration data 0x240A as a whole (`ObjFlags=0x3` in the object's
/// section, none in its sub-indices), its 0x2405 in the object and its sub-index 2 on its own.
#[test]
fn a_vendor_file_flags_objects_and_entries() {
    let path = format!(
        "{}/../../shared/corpus/eds/kac-faulhaber-3150.67-B-EK-2.eds",
        env!("CARGO_MANIFEST_DIR")
    );
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let desc = od::eds::read(&bytes, "faulhaber.eds").unwrap();
    let (object, subs) = flags(&desc, 0x240A);
    assert_eq!(object, Some(3));
    assert!(subs.iter().all(|(_, f)| f.is_none()), "{subs:?}");
    let o = desc.dictionary.object(0x240A).unwrap();
    assert!(o.subs.keys().all(|&s| o.flags_of(s).bits() == 3));
    assert_eq!(flags(&desc, 0x2405).1[2], (2, Some(1)));
    assert_eq!(
        desc.dictionary.object(0x2405).unwrap().flags_of(2).bits(),
        3
    );
    let back = od::eds::read(od::eds::write_eds(&desc).as_bytes(), "back.eds").unwrap();
    assert!(diff(&desc, &back).is_empty());
}
