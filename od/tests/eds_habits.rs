//! Constructs of real EDS and DCF files that the established tools (python-canopen, Lely, CANopenNode)
//! load, each in a small file of its own: what the reader and the checks make of it, with the exact
//! findings and where in the file they are.

use od::validate::validate_mapped;
use od::{eds, DataType, Severity, Value};

/// Reads `text`, checks the description, and gives it back with every finding (the reader's, then the
/// checks') as `line:column: message`, warnings only.
fn read_and_check(text: &str) -> (od::DeviceDescription, Vec<String>) {
    let mut reading = eds::read_file(text.as_bytes(), "habit.eds").unwrap_or_else(|e| panic!("{e}"));
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
