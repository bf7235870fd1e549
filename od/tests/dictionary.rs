//! Dictionary access: look-up, and writes checked for type, length, range and access, each refusal mapping
//! onto its CiA 301 abort code and leaving the old value in place.

use od::{
    AbortCode, Access, AccessType, Address, DataType, Dictionary, EcatStates, LookupError, Object,
    ObjectKind, OdError, PdoMapping, SubObject, Value,
};

fn sample() -> Dictionary {
    let mut d = Dictionary::new();
    d.insert(Object::var(
        0x1000,
        SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro)
            .with_default(Value::Uint(0x0002_0192)),
    ));
    d.insert(Object::var(
        0x1017,
        SubObject::new(
            "Producer heartbeat time",
            DataType::Unsigned16,
            AccessType::Rw,
        ),
    ));
    d.insert(Object::var(
        0x2001,
        SubObject::new("Secret", DataType::Unsigned8, AccessType::Wo),
    ));
    d.insert(Object::var(
        0x1008,
        SubObject::new(
            "Manufacturer device name",
            DataType::VisibleString,
            AccessType::Const,
        )
        .with_default(Value::String("X67SM2436".into())),
    ));
    d.insert(Object::var(
        0x2002,
        SubObject::new("Label", DataType::VisibleString, AccessType::Rw).with_bit_size(8 * 8),
    ));
    d.insert(Object::var(
        0x2003,
        SubObject::new("Enabled", DataType::Boolean, AccessType::Rw),
    ));
    d.insert(Object::var(
        0x2004,
        SubObject::new("Gain", DataType::Real32, AccessType::Rw),
    ));
    d.insert(
        Object::structured(0x8010, "Configuration Data", ObjectKind::Record)
            .with_sub(
                0,
                SubObject::new("SubIndex 000", DataType::Unsigned8, AccessType::Ro)
                    .with_default(Value::Uint(3)),
            )
            .with_sub(
                1,
                SubObject::new("CFG_Word_0", DataType::Unsigned16, AccessType::Rw),
            )
            .with_sub(
                2,
                SubObject::new("Speed", DataType::Integer32, AccessType::Rw)
                    .with_limits(Some(Value::Int(-1000)), Some(Value::Int(1000)))
                    .with_default(Value::Int(10))
                    .with_pdo(PdoMapping::Rpdo),
            )
            .with_sub(
                3,
                SubObject::new("Label", DataType::Unsigned8, AccessType::Rw),
            ),
    );
    d
}

fn refused(d: &mut Dictionary, index: u16, sub: u8, bytes: &[u8]) -> AbortCode {
    let before = d.clone();
    let err = d
        .write(index, sub, bytes)
        .expect_err("the write should be refused");
    assert_eq!(
        *d, before,
        "a refused write must leave the dictionary untouched"
    );
    err.abort_code()
}

#[test]
fn each_refusal_maps_onto_its_abort_code() {
    let mut d = sample();
    assert_eq!(
        refused(&mut d, 0x1000, 0, &[0, 0, 0, 0]).code(),
        0x0601_0002,
        "read-only"
    );
    assert_eq!(
        refused(&mut d, 0x1008, 0, b"x").code(),
        0x0601_0002,
        "const"
    );
    assert_eq!(
        d.read(0x2001, 0).unwrap_err().abort_code().code(),
        0x0601_0001,
        "write-only"
    );
    assert_eq!(
        refused(&mut d, 0x3000, 0, &[0]).code(),
        0x0602_0000,
        "no object"
    );
    assert_eq!(
        d.read(0x3000, 0).unwrap_err().abort_code().code(),
        0x0602_0000
    );
    assert_eq!(
        refused(&mut d, 0x8010, 9, &[0]).code(),
        0x0609_0011,
        "no sub-index"
    );
    assert_eq!(
        d.read(0x1017, 1).unwrap_err().abort_code().code(),
        0x0609_0011
    );
    assert_eq!(
        refused(&mut d, 0x1017, 0, &[1, 2, 3]).code(),
        0x0607_0012,
        "too long"
    );
    assert_eq!(
        refused(&mut d, 0x1017, 0, &[1]).code(),
        0x0607_0013,
        "too short"
    );
    assert_eq!(
        refused(&mut d, 0x2002, 0, b"123456789").code(),
        0x0607_0012,
        "string over capacity"
    );
    assert_eq!(
        refused(&mut d, 0x2003, 0, &[2]).code(),
        0x0609_0030,
        "BOOLEAN 2"
    );
    assert_eq!(
        refused(&mut d, 0x2004, 0, &f32::NAN.to_le_bytes()).code(),
        0x0609_0030,
        "NaN"
    );
    assert_eq!(
        refused(&mut d, 0x8010, 2, &1001i32.to_le_bytes()).code(),
        0x0609_0031,
        "above high"
    );
    assert_eq!(
        refused(&mut d, 0x8010, 2, &(-1001i32).to_le_bytes()).code(),
        0x0609_0032,
        "below low"
    );
    let before = d.clone();
    let e = d
        .write_value(0x1017, 0, &Value::String("x".into()))
        .unwrap_err();
    assert_eq!(e.abort_code().code(), 0x0607_0010, "type mismatch");
    assert_eq!(d, before);
}

#[test]
fn good_writes_store_little_endian_bytes() {
    let mut d = sample();
    d.write(0x1017, 0, &[0xE8, 0x03]).unwrap();
    assert_eq!(d.read(0x1017, 0).unwrap(), &[0xE8, 0x03]);
    assert_eq!(d.read_value(0x1017, 0).unwrap(), Value::Uint(1000));
    d.write_value(0x8010, 2, &Value::Int(-1000)).unwrap();
    assert_eq!(d.read(0x8010, 2).unwrap(), &(-1000i32).to_le_bytes());
    d.write(0x2002, 0, b"ABC").unwrap();
    assert_eq!(
        d.read_value(0x2002, 0).unwrap(),
        Value::String("ABC".into())
    );
    d.write(0x2001, 0, &[7]).unwrap();
    // The device itself may update a read-only entry.
    d.store_value(0x1000, 0, &Value::Uint(5)).unwrap();
    assert_eq!(d.read(0x1000, 0).unwrap(), &[5, 0, 0, 0]);
}

#[test]
fn typed_writes_out_of_the_type_range_are_value_range_errors() {
    let mut d = sample();
    let e = d.write_value(0x1017, 0, &Value::Uint(70_000)).unwrap_err();
    assert_eq!(e.abort_code(), AbortCode::ValueTooHigh);
    let e = d.write_value(0x1017, 0, &Value::Int(-1)).unwrap_err();
    assert_eq!(e.abort_code(), AbortCode::ValueTooLow);
}

#[test]
fn look_up_by_name_is_case_insensitive() {
    let d = sample();
    assert_eq!(d.lookup("CFG_Word_0").unwrap(), Address::new(0x8010, 1));
    assert_eq!(d.lookup("cfg_word_0").unwrap(), Address::new(0x8010, 1));
    assert_eq!(
        d.lookup("producer HEARTBEAT time").unwrap(),
        Address::new(0x1017, 0)
    );
    assert_eq!(
        d.lookup("Configuration Data").unwrap(),
        Address::new(0x8010, 0)
    );
    assert_eq!(d.lookup("0x8010:02").unwrap(), Address::new(0x8010, 2));
    assert_eq!(
        d.lookup("Configuration data.label").unwrap(),
        Address::new(0x8010, 3)
    );
    assert_eq!(
        d.lookup("nothing"),
        Err(LookupError::NotFound {
            name: "nothing".into(),
            similar: vec![]
        })
    );
    // An object's sub-object that is not there: the object named, and its sub-objects.
    let e = d.lookup("Configuration data.colour").unwrap_err();
    assert_eq!(
        e.to_string(),
        "`Configuration Data` has no sub-object named `colour`; its sub-objects: SubIndex 000, \
         CFG_Word_0, Speed, Label"
    );
    // A name close to one of the dictionary's: named in the refusal, once though two entries have it.
    let e = d.lookup("Labl").unwrap_err();
    assert_eq!(
        e,
        LookupError::NotFound {
            name: "Labl".into(),
            similar: vec!["Label".into()]
        }
    );
    assert_eq!(
        e.to_string(),
        "no object or sub-object is named `Labl`; did you mean `Label`?"
    );
    // A sub-index by its number after the object's name or index, decimal or hex.
    assert_eq!(
        d.lookup("Configuration data.2").unwrap(),
        Address::new(0x8010, 2)
    );
    assert_eq!(d.lookup("0x8010.3").unwrap(), Address::new(0x8010, 3));
    assert_eq!(d.lookup("0x8010.0x01").unwrap(), Address::new(0x8010, 1));
    assert_eq!(d.lookup("0x8010.Speed").unwrap(), Address::new(0x8010, 2));
    // A number the object has no sub-index for is said to be a sub-index, not a name.
    assert_eq!(
        d.lookup("Configuration data.9").unwrap_err().to_string(),
        "`Configuration Data` (0x8010) has no sub-index 9; its sub-indices: 0 SubIndex 000, \
         1 CFG_Word_0, 2 Speed, 3 Label"
    );
    assert_eq!(
        d.lookup("0x4321.1").unwrap_err(),
        LookupError::NoIndex(0x4321)
    );
    assert_eq!(
        LookupError::NoIndex(0x4321).to_string(),
        "there is no object 0x4321"
    );
    match d.lookup("Label") {
        Err(LookupError::Ambiguous { candidates, .. }) => {
            assert_eq!(
                candidates,
                vec![Address::new(0x2002, 0), Address::new(0x8010, 3)]
            )
        }
        other => panic!("expected an ambiguity, got {other:?}"),
    }
}

#[test]
fn addresses_parse_in_the_usual_spellings() {
    assert_eq!(Address::parse("0x8010:01"), Some(Address::new(0x8010, 1)));
    assert_eq!(Address::parse("8010:7"), Some(Address::new(0x8010, 7)));
    assert_eq!(Address::parse("0x1018sub2"), Some(Address::new(0x1018, 2)));
    assert_eq!(Address::parse("1000"), Some(Address::new(0x1000, 0)));
    assert_eq!(Address::parse("0x18010:1"), None);
    assert_eq!(Address::parse("0x1000:100"), None);
    assert_eq!(Address::parse("zz"), None);
    assert_eq!(Address::new(0x8010, 1).to_string(), "0x8010:01");
}

#[test]
fn reset_restores_defaults_and_node_id_relative_values() {
    let mut d = sample();
    d.insert(Object::var(0x1014, {
        let mut s = SubObject::new("COB-ID EMCY", DataType::Unsigned32, AccessType::Rw);
        s.default = Some(od::DefaultValue {
            value: Value::Uint(0x80),
            plus_node_id: true,
        });
        s
    }));
    d.write_value(0x8010, 2, &Value::Int(5)).unwrap();
    d.reset(0x21);
    assert_eq!(d.read_value(0x8010, 2).unwrap(), Value::Int(10));
    assert_eq!(d.read_value(0x1014, 0).unwrap(), Value::Uint(0xA1));
}

#[test]
fn access_types_and_state_sets() {
    assert!(AccessType::Rww.writable() && AccessType::Rww.readable());
    assert!(!AccessType::Const.writable());
    assert!(!AccessType::Wo.readable());
    assert_eq!(AccessType::parse("readWrite"), Some(AccessType::Rw));
    assert_eq!(AccessType::parse("CONST"), Some(AccessType::Const));
    let s = EcatStates::parse("PreOp_SafeOp").unwrap();
    assert!(
        s.contains(EcatStates::PREOP)
            && s.contains(EcatStates::SAFEOP)
            && !s.contains(EcatStates::OP)
    );
    assert_eq!(s.to_string(), "PreOp_SafeOp");
    assert_eq!(EcatStates::parse("Boot"), None);
    let a: Access = AccessType::Rw.into();
    assert_eq!(a.write_states, None);
}

#[test]
fn od_errors_name_the_entry() {
    let e = OdError::TooHigh {
        index: 0x8010,
        sub: 2,
        value: Value::Int(1001),
        limit: Value::Int(1000),
    };
    assert_eq!(
        e.to_string(),
        "0x8010:02: 1001 is above the high limit 1000"
    );
}
