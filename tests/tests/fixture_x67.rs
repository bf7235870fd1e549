//! The X67SM2436 description (`fixtures/src/x67sm2436.xdd`) against the B&R data sheet (seed 002): each
//! test names the rule of `shared/rules/x67.md` whose observable it checks.

use integration_tests::{fixture, load_one};
use od::device::DeviceDescription;
use od::{AbortCode, AccessType, DataType, Dictionary, PdoMapping, Value};

fn device() -> DeviceDescription {
    load_one(&fixture("src/x67sm2436.xdd"))
}

fn entry<'a>(d: &'a Dictionary, name: &str) -> &'a od::SubObject {
    let a = d.lookup(name).unwrap_or_else(|e| panic!("{e}"));
    d.entry(a.index, a.sub).unwrap()
}

use DataType::{
    Integer16 as INT, Integer32 as DINT, Integer8 as SINT, Unsigned16 as UINT, Unsigned8 as USINT,
};

/// Configuration registers of 18.5: (rule, name, type). All written acyclically only (X67-18.5-03).
const CONFIG: &[(&str, &str, DataType)] = &[
    ("X67-18.5-05", "ConfigOutput03a", USINT),
    ("X67-18.5-05", "ConfigOutput04a", USINT),
    ("X67-18.5-05", "ConfigOutput05a", USINT),
    ("X67-18.5-05", "ConfigOutput06a", USINT),
    ("X67-18.5-05", "ConfigOutput07a", USINT),
    ("X67-18.5-05", "ConfigOutput08a", USINT),
    ("X67-18.5-06", "FullStepThreshold01", UINT),
    ("X67-18.5-06", "FullStepThreshold02", UINT),
    ("X67-18.5-07", "MaxSpeed01pos", UINT),
    ("X67-18.5-07", "MaxSpeed02pos", UINT),
    ("X67-18.5-08", "MaxAcc01", UINT),
    ("X67-18.5-08", "MaxDec01", UINT),
    ("X67-18.5-08", "MaxAcc02", UINT),
    ("X67-18.5-08", "MaxDec02", UINT),
    ("X67-18.5-09", "RevLoop01", INT),
    ("X67-18.5-09", "RevLoop02", INT),
    ("X67-18.5-10", "FixedPos01a", DINT),
    ("X67-18.5-10", "FixedPos01b", DINT),
    ("X67-18.5-10", "FixedPos02a", DINT),
    ("X67-18.5-10", "FixedPos02b", DINT),
    ("X67-18.5-11", "RefSpeed01", UINT),
    ("X67-18.5-11", "RefSpeed02", UINT),
    ("X67-18.5-12", "RefConfig01", SINT),
    ("X67-18.5-12", "RefConfig02", SINT),
    ("X67-18.5-13", "StallDetectConfig01", USINT),
    ("X67-18.5-13", "StallDetectConfig02", USINT),
    ("X67-18.5-14", "StallRecognitionDelay01", USINT),
    ("X67-18.5-14", "StallRecognitionDelay02", USINT),
    ("X67-18.5-15", "JoltTime01", USINT),
    ("X67-18.5-15", "JoltTime02", USINT),
    ("X67-18.5-16", "StallDetectMinSpeed01", UINT),
    ("X67-18.5-16", "StallDetectMinSpeed02", UINT),
    ("X67-18.5-17", "GeneralConfig01", USINT),
    ("X67-18.5-18", "LimitSwitchConfig01", USINT),
    ("X67-18.5-18", "LimitSwitchConfig02", USINT),
    ("X67-18.5-19", "PositionLimitMin01", DINT),
    ("X67-18.5-19", "PositionLimitMax01", DINT),
    ("X67-18.5-19", "PositionLimitMin02", DINT),
    ("X67-18.5-19", "PositionLimitMax02", DINT),
];

/// Registers read acyclically: (rule, name, type).
const ACYCLIC_READ: &[(&str, &str, DataType)] = &[
    ("X67-18.5-20", "ConfigOutput03aRead", USINT),
    ("X67-18.5-20", "ConfigOutput04aRead", USINT),
    ("X67-18.5-20", "ConfigOutput05aRead", USINT),
    ("X67-18.5-20", "ConfigOutput06aRead", USINT),
    ("X67-18.5-20", "ConfigOutput07aRead", USINT),
    ("X67-18.5-20", "ConfigOutput08aRead", USINT),
    ("X67-18.5-27", "Motoridentification01", UINT),
    ("X67-18.5-27", "Motoridentification02", UINT),
    ("X67-18.5-28", "Temperature", SINT),
    ("X67-18.5-29", "RefPos01CyclicCounter", DINT),
    ("X67-18.5-29", "RefPos01AcyclicCounter", DINT),
    ("X67-18.5-29", "RefPos02CyclicCounter", DINT),
    ("X67-18.5-29", "RefPos02AcyclicCounter", DINT),
    ("X67-18.5-30", "AbsPos01ActValAcyclic", DINT),
    ("X67-18.5-30", "AbsPos02ActValAcyclic", DINT),
    ("X67-18.5-31", "ControlReadback01", UINT),
    ("X67-18.5-31", "ModeReadback01", SINT),
    ("X67-18.5-31", "ControlReadback02", UINT),
    ("X67-18.5-31", "ModeReadback02", SINT),
    ("X67-18.5-32", "ErrorCode01", UINT),
    ("X67-18.5-32", "ErrorCode02", UINT),
];

/// Cyclic registers: (rule, name, type, written by the master).
const CYCLIC: &[(&str, &str, DataType, bool)] = &[
    ("X67-18.5-21", "AbsPos01", DINT, true),
    ("X67-18.5-21", "AbsPos02", DINT, true),
    ("X67-18.5-22", "MpGenControl01", UINT, true),
    ("X67-18.5-22", "MpGenControl02", UINT, true),
    ("X67-18.5-23", "MpGenMode01", SINT, true),
    ("X67-18.5-23", "MpGenMode02", SINT, true),
    ("X67-18.5-24", "AbsPos01ActVal", DINT, false),
    ("X67-18.5-24", "AbsPos02ActVal", DINT, false),
    ("X67-18.5-25", "MpGenStatus01", UINT, false),
    ("X67-18.5-25", "MpGenStatus02", UINT, false),
    ("X67-18.5-26", "InputStatus", USINT, false),
];

/// X67-18.5-03, X67-18.5-04 and X67-18.5-05, X67-18.5-06, X67-18.5-07, X67-18.5-08, X67-18.5-09,
/// X67-18.5-10, X67-18.5-11, X67-18.5-12, X67-18.5-13, X67-18.5-14, X67-18.5-15, X67-18.5-16,
/// X67-18.5-17, X67-18.5-18, X67-18.5-19: every configuration register exists with its
/// type, is write-only, and an SDO read of it aborts with 0x06010001.
#[test]
fn x67_18_5_05_to_19_configuration_registers() {
    let d = device().dictionary;
    for &(rule, name, t) in CONFIG {
        let e = entry(&d, name);
        assert_eq!(e.data_type, t, "{rule} {name}");
        assert_eq!(e.access.kind, AccessType::Wo, "{rule} {name}");
        assert_eq!(e.pdo, PdoMapping::None, "{rule} {name}");
        let a = d.lookup(name).unwrap();
        assert_eq!(
            d.read(a.index, a.sub).unwrap_err().abort_code(),
            AbortCode::WriteOnly,
            "{rule} {name}"
        );
    }
    assert!(
        d.lookup("GeneralConfig02").is_err(),
        "X67-18.5-17: no GeneralConfig02"
    );
}

/// X67-18.5-03, X67-18.5-20, X67-18.5-27, X67-18.5-28, X67-18.5-29, X67-18.5-30, X67-18.5-31,
/// X67-18.5-32: read-acyclic registers are read-only; an SDO write
/// aborts with 0x06010002.
#[test]
fn x67_18_5_20_to_32_acyclic_read_registers() {
    let mut d = device().dictionary;
    for &(rule, name, t) in ACYCLIC_READ {
        let e = entry(&d, name);
        assert_eq!(e.data_type, t, "{rule} {name}");
        assert_eq!(e.access.kind, AccessType::Ro, "{rule} {name}");
        let a = d.lookup(name).unwrap();
        let bytes = vec![0u8; t.byte_size().unwrap()];
        assert_eq!(
            d.write(a.index, a.sub, &bytes).unwrap_err().abort_code(),
            AbortCode::ReadOnly,
            "{rule} {name}"
        );
    }
}

/// X67-18.5-02, X67-18.5-21, X67-18.5-22, X67-18.5-23, X67-18.5-24, X67-18.5-25, X67-18.5-26: the
/// cyclic registers, RPDO-mappable outputs and TPDO-mappable
/// inputs; no other register is mappable.
#[test]
fn x67_18_5_02_21_to_26_cyclic_registers() {
    let d = device().dictionary;
    for &(rule, name, t, output) in CYCLIC {
        let e = entry(&d, name);
        assert_eq!(e.data_type, t, "{rule} {name}");
        assert_eq!(
            e.pdo,
            if output {
                PdoMapping::Rpdo
            } else {
                PdoMapping::Tpdo
            },
            "{rule} {name}"
        );
    }
    let mappable: usize = d
        .objects()
        .filter(|o| (0x2000..=0x5FFF).contains(&o.index))
        .filter(|o| o.subs.values().any(|s| s.pdo.any()))
        .count();
    assert_eq!(
        mappable,
        CYCLIC.len(),
        "X67-18.5-02: only the 11 cyclic registers are mappable"
    );
}

/// X67-18.5-01: the manufacturer objects are exactly the registers of the 18.5 table.
#[test]
fn x67_18_5_01_exactly_the_register_table() {
    let d = device().dictionary;
    let manufacturer: Vec<&str> = d
        .objects()
        .filter(|o| (0x2000..=0x5FFF).contains(&o.index))
        .map(|o| o.name.as_str())
        .collect();
    assert_eq!(
        manufacturer.len(),
        CONFIG.len() + ACYCLIC_READ.len() + CYCLIC.len()
    );
    for absent in [
        "ConfigOutput01",
        "ConfigOutput02",
        "ConfigOutput09",
        "Motor1Step0",
        "MotorLoad",
        "MotorIdentTrigger",
    ] {
        assert!(d.lookup(absent).is_err(), "{absent}");
    }
}

fn mapping(d: &Dictionary, index: u16) -> Vec<u64> {
    let n = match d.read_value(index, 0).unwrap() {
        Value::Uint(n) => n as u8,
        v => panic!("{v:?}"),
    };
    (1..=n)
        .map(|s| match d.read_value(index, s).unwrap() {
            Value::Uint(v) => v,
            v => panic!("{v:?}"),
        })
        .collect()
}

fn layout(d: &Dictionary, index: u16) -> Vec<(String, u32, u32)> {
    let mut offset = 0;
    let mut out = Vec::new();
    for m in mapping(d, index) {
        let (mi, ms, bits) = ((m >> 16) as u16, (m >> 8) as u8, (m & 0xFF) as u32);
        let name = if mi < 0x0008 {
            "dummy".to_string()
        } else {
            d.entry(mi, ms).unwrap().name.clone()
        };
        out.push((name, offset / 8, bits));
        offset += bits;
    }
    out
}

fn owned(v: &[(&str, u32, u32)]) -> Vec<(String, u32, u32)> {
    v.iter().map(|(n, o, b)| (n.to_string(), *o, *b)).collect()
}

/// X67-18.5.2-01, X67-18.5.2-02, X67-18.5.2-03, X67-18.5.2-04: two 8-byte CAN objects per
/// direction; object 1 carries axis 1 and
/// InputStatus, object 2 axis 2 at byte = offset − 8; unused bytes are padding.
#[test]
fn x67_18_5_2_01_to_04_can_object_layout() {
    let d = device().dictionary;
    assert_eq!(
        layout(&d, 0x1600),
        owned(&[
            ("AbsPos01", 0, 32),
            ("MpGenControl01", 4, 16),
            ("MpGenMode01", 6, 8),
            ("dummy", 7, 8)
        ])
    );
    assert_eq!(
        layout(&d, 0x1601),
        owned(&[
            ("AbsPos02", 0, 32),
            ("MpGenControl02", 4, 16),
            ("MpGenMode02", 6, 8),
            ("dummy", 7, 8)
        ])
    );
    assert_eq!(
        layout(&d, 0x1A00),
        owned(&[
            ("AbsPos01ActVal", 0, 32),
            ("MpGenStatus01", 4, 16),
            ("InputStatus", 6, 8),
            ("dummy", 7, 8)
        ])
    );
    assert_eq!(
        layout(&d, 0x1A01),
        owned(&[
            ("AbsPos02ActVal", 0, 32),
            ("MpGenStatus02", 4, 16),
            ("dummy", 6, 16)
        ])
    );
}

/// The CiA 301 communication objects the issue lists are all present, with node-ID relative COB-IDs.
#[test]
fn communication_objects() {
    let dev = device();
    let d = &dev.dictionary;
    for index in [
        0x1000u16, 0x1001, 0x1003, 0x1005, 0x1008, 0x1010, 0x1011, 0x1014, 0x1016, 0x1017, 0x1018,
        0x1400, 0x1401, 0x1600, 0x1601, 0x1800, 0x1801, 0x1A00, 0x1A01,
    ] {
        assert!(d.object(index).is_some(), "0x{index:04X}");
    }
    let emcy = d.entry(0x1014, 0).unwrap().default.clone().unwrap();
    assert!(emcy.plus_node_id);
    assert_eq!(emcy.resolve(5), Value::Uint(0x85));
    let tpdo1 = d.entry(0x1800, 1).unwrap().default.clone().unwrap();
    assert_eq!(tpdo1.resolve(5), Value::Uint(0x185));
    let findings = od::validate::validate(&dev);
    assert!(
        findings
            .iter()
            .all(|f| f.severity != od::validate::Severity::Error),
        "{findings:#?}"
    );
}

/// The register table of the `ds402` module model names every manufacturer object of the fixture, with the
/// same data type and access, and nothing else: the model and the description cannot drift apart
/// (X67-18.5-01, X67-18.5-03, X67-18.5-04).
#[test]
fn model_registers_match_the_fixture() {
    use ds402::x67::registers::{Access, RegType, Register};
    let d = device().dictionary;
    let mut names = Vec::new();
    for reg in Register::all() {
        let info = reg.info();
        let e = entry(&d, info.name);
        let t = match info.ty {
            RegType::Dint => DINT,
            RegType::Uint => UINT,
            RegType::Int => INT,
            RegType::Sint => SINT,
            RegType::Usint => USINT,
        };
        assert_eq!(e.data_type, t, "{}", info.name);
        let (access, pdo) = match info.access {
            Access::Config => (AccessType::Wo, PdoMapping::None),
            Access::ReadAcyclic => (AccessType::Ro, PdoMapping::None),
            Access::CyclicOut => (AccessType::Rww, PdoMapping::Rpdo),
            Access::CyclicIn => (AccessType::Ro, PdoMapping::Tpdo),
        };
        assert_eq!((e.access.kind, e.pdo), (access, pdo), "{}", info.name);
        names.push(info.name);
    }
    let manufacturer = d
        .objects()
        .filter(|o| (0x2000..=0x5FFF).contains(&o.index))
        .count();
    assert_eq!(names.len(), manufacturer);
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), manufacturer, "register names are unique");
}
