//! Values followed by a comment on their line (`DefaultValue=0x3ED ; prevent homing`): read without
//! the comment, as python-canopen reads them (configparser's inline comments: a `;` after white
//! space), for every key whose value is read; a `;` right after the value is part of it. Each form in
//! a small file of its own, checked against python-canopen's reading of the same file.

use std::process::Command;

use od::report::Severity;
use od::value::Value;
use od::DeviceDescription;

/// An EDS with every form: a comment after a blank, after a tab, after `$NODEID+…`, a `;` without
/// a blank before it, and comments after limits, a parameter value and `[DeviceInfo]` keys.
const EDS: &str = "[FileInfo]\r
FileName=comments.eds ; the name\r
EDSVersion=4.0\r
[DeviceInfo]\r
VendorName=ACME ; who\r
VendorNumber=0x26C ; the vendor\r
ProductName=Drive\t; tab before\r
ProductNumber=70 ; product\r
RevisionNumber=3 ; rev\r
NrOfRXPDO=4 ; four\r
NrOfTXPDO=2\r
[MandatoryObjects]\r
SupportedObjects=1\r
1=0x1000 ; device type\r
[OptionalObjects]\r
SupportedObjects=5\r
1=0x1400\r
2=0x2000\r
3=0x2001\r
4=0x2002\r
5=0x2003\r
[1000]\r
ParameterName=Device type ; the name\r
ObjectType=0x7\r
DataType=0x0007\r
AccessType=ro\r
DefaultValue=0x00020192 ; servo\r
PDOMapping=0\r
[1400]\r
ParameterName=RPDO communication parameter\r
ObjectType=0x9\r
SubNumber=2\r
[1400sub0]\r
ParameterName=Highest sub-index supported\r
ObjectType=0x7\r
DataType=0x0005\r
AccessType=ro\r
DefaultValue=1\r
PDOMapping=0\r
[1400sub1]\r
ParameterName=COB-ID\r
ObjectType=0x7\r
DataType=0x0007\r
AccessType=rw\r
DefaultValue=$NODEID+0x200 ; RPDO 1\r
PDOMapping=0\r
[2000]\r
ParameterName=Homing\r
ObjectType=0x7\r
DataType=0x0006\r
AccessType=rw\r
DefaultValue=0x3ED ; prevent homing\r
LowLimit=0x10 ; low\r
HighLimit=2000\t; high\r
PDOMapping=0 ; not mapped\r
[2001]\r
ParameterName=No comment\r
ObjectType=0x7\r
DataType=0x0006\r
AccessType=rw\r
DefaultValue=1005;c\r
PDOMapping=0\r
[2002]\r
ParameterName=Set\r
ObjectType=0x7\r
DataType=0x0004\r
AccessType=rw\r
DefaultValue=-5\t; tab\r
ParameterValue=-7 ; set\r
PDOMapping=0\r
[2003]\r
ParameterName=Label\r
ObjectType=0x7\r
DataType=0x0009\r
AccessType=rw\r
DefaultValue=motor ; the text ends before the comment\r
PDOMapping=0\r
";

fn read(text: &str) -> (DeviceDescription, Vec<String>) {
    let reading = od::eds::read_file(text.as_bytes(), "comments.eds").unwrap();
    let warnings = reading
        .findings
        .iter()
        .filter(|f| f.severity == Severity::Warning)
        .map(|f| f.message.clone())
        .collect();
    (reading.devices.into_iter().next().unwrap(), warnings)
}

fn value(desc: &DeviceDescription, index: u16, sub: u8) -> Value {
    desc.dictionary.read_value(index, sub).unwrap()
}

#[test]
fn values_are_read_without_their_comment() {
    let (desc, warnings) = read(EDS);
    // `[DeviceInfo]`: numbers and names alike.
    assert_eq!(desc.identity.vendor_id, 0x26C);
    assert_eq!(desc.identity.vendor_name, "ACME");
    assert_eq!(desc.identity.product_name, "Drive");
    assert_eq!(desc.identity.product_code, 70);
    assert_eq!(desc.identity.revision, 3);
    assert_eq!(desc.can.as_ref().unwrap().nr_of_rx_pdo, 4);
    assert_eq!(desc.file_info.file_name, "comments.eds");
    // A blank before the `;`.
    assert_eq!(value(&desc, 0x1000, 0), Value::Uint(0x0002_0192));
    assert_eq!(value(&desc, 0x2000, 0), Value::Uint(1005));
    let homing = desc.dictionary.entry(0x2000, 0).unwrap();
    assert_eq!(homing.low, Some(Value::Uint(16)));
    // A tab before the `;`.
    assert_eq!(homing.high, Some(Value::Uint(2000)));
    assert_eq!(desc.dictionary.object(0x2000).unwrap().name, "Homing");
    // `$NODEID+…` and a comment: relative to the node-ID still (an EDS: node-ID 0).
    let cob = desc.dictionary.entry(0x1400, 1).unwrap();
    assert_eq!(cob.default.as_ref().unwrap().value, Value::Uint(0x200));
    assert!(cob.default.as_ref().unwrap().plus_node_id);
    // ParameterValue, and a default after a tab.
    let set = desc.dictionary.entry(0x2002, 0).unwrap();
    assert_eq!(set.default.as_ref().unwrap().value, Value::Int(-5));
    assert_eq!(value(&desc, 0x2002, 0), Value::Int(-7));
    assert!(set.value_set);
    // Text ends before the comment.
    assert_eq!(value(&desc, 0x2003, 0), Value::String("motor".into()));
    // `1005;c`: no comment, so no number; dropped with a warning that says why, as python-canopen
    // drops it.
    assert!(!desc.dictionary.entry(0x2001, 0).unwrap().has_value());
    assert_eq!(value(&desc, 0x2001, 0), Value::Uint(0));
    assert!(
        warnings
            .iter()
            .any(|w| w.starts_with("DefaultValue= in [2001]:")
                && w.contains("(a `;` starts a comment only after a blank)")
                && w.ends_with("the default is dropped")),
        "{warnings:?}"
    );
}

/// `ProductNumber=70;x` in `[DeviceInfo]` is no number (no blank before the `;`): the file is
/// refused there with the line and the text, as python-canopen refuses it (its `int()` fails).
#[test]
fn a_device_info_number_with_a_semicolon_but_no_blank_is_no_number() {
    let text = EDS.replace("ProductNumber=70 ; product", "ProductNumber=70;x");
    let e = od::eds::read_file(text.as_bytes(), "comments.eds").unwrap_err();
    assert_eq!(e.position.line, 8, "{e}");
    assert!(e.message.contains("found `70;x`"), "{e}");
}

/// The writer keeps values a reader takes back whole: a text with `a ; b` in it is written `a; b`
/// (a reader would cut it after `a` otherwise), every number without a comment.
#[test]
fn written_back_nothing_is_cut() {
    let (mut desc, _) = read(EDS);
    let label = desc
        .dictionary
        .object_mut(0x2003)
        .unwrap()
        .subs
        .get_mut(&0)
        .unwrap();
    assert!(label.set_default(Value::String("left ; right\t;end".into())));
    desc.identity.product_name = "Drive ; X".into();
    let text = od::eds::write_eds(&desc);
    assert!(
        text.contains("\r\nDefaultValue=left; right;end\r\n"),
        "{text}"
    );
    assert!(text.contains("\r\nProductName=Drive; X\r\n"), "{text}");
    assert!(
        text.contains(
            "\r\nDefaultValue=0x03ED\r\nPDOMapping=0\r\nLowLimit=0x0010\r\nHighLimit=0x07D0\r\n"
        ),
        "{text}"
    );
    let (back, _) = read(&text);
    assert_eq!(
        value(&back, 0x2003, 0),
        Value::String("left; right;end".into())
    );
    assert_eq!(back.identity.product_name, "Drive; X");
    assert_eq!(value(&back, 0x2000, 0), Value::Uint(1005));
    assert_eq!(
        back.dictionary.entry(0x2000, 0).unwrap().high,
        Some(Value::Uint(2000))
    );
}

/// python-canopen reads the same file to the same values.
#[test]
fn python_canopen_reads_the_same_values() {
    let dir = tempfile_dir();
    let path = dir.join("comments.eds");
    std::fs::write(&path, EDS).unwrap();
    let script = r#"
import sys, canopen
od = canopen.import_od(sys.argv[1], node_id=5)
d = od.device_information
print(d.vendor_number, d.product_name, d.product_number, d.nr_of_RXPDO)
print(od[0x1000].default, od[0x2000].default, od[0x2000].min, od[0x2000].max)
print(od[0x1400][1].default, od[0x2001].default, od[0x2002].default, od[0x2002].value)
print(od[0x2003].default)
"#;
    let out = Command::new("python3")
        .arg("-c")
        .arg(script)
        .arg(&path)
        .output()
        .expect("python3 runs (scripts/setup-test-deps installs python-canopen)");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // python-canopen resolves $NODEID with the node-ID given (5): 0x205 = 517.
    assert_eq!(
        stdout,
        "620 Drive 70 4\n131474 1005 16 2000\n517 None -5 -7\nmotor\n"
    );
    let (desc, _) = read(EDS);
    assert_eq!(value(&desc, 0x2000, 0), Value::Uint(1005));
    let _ = std::fs::remove_dir_all(dir);
}

fn tempfile_dir() -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("od-eds-comments-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
