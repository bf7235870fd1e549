use super::*;
use crate::device::*;
use crate::object::{
    AccessType, DefaultValue, EcatStates, Object, ObjectKind, PdoMapping, SubObject,
};
use crate::types::DataType;
use crate::value::Value;

fn base() -> Dictionary {
    let mut d = Dictionary::new();
    d.insert(Object::var(
        0x1000,
        SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro),
    ));
    d.insert(
        Object::structured(0x1018, "Identity", ObjectKind::Record)
            .with_sub(
                0,
                SubObject::new("n", DataType::Unsigned8, AccessType::Ro)
                    .with_default(Value::Uint(1)),
            )
            .with_sub(
                1,
                SubObject::new("Vendor-ID", DataType::Unsigned32, AccessType::Ro),
            ),
    );
    d
}

fn lines(diffs: &[Difference]) -> Vec<String> {
    diffs.iter().map(|d| d.to_string()).collect()
}

/// The differences of `base()` against a copy changed by `change`.
fn dict_diff(change: impl FnOnce(&mut Dictionary)) -> Vec<String> {
    let a = base();
    let mut b = base();
    change(&mut b);
    lines(&diff(&a, &b))
}

fn sub(d: &mut Dictionary, index: u16, sub: u8) -> &mut SubObject {
    d.object_mut(index).unwrap().subs.get_mut(&sub).unwrap()
}

#[test]
fn equal_dictionaries_have_no_difference() {
    assert!(diff(&base(), &base()).is_empty());
}

#[test]
fn every_kind_of_difference_is_reported_in_index_order() {
    let text = dict_diff(|b| {
        b.remove(0x1000);
        b.insert(Object::var(
            0x2000,
            SubObject::new("Extra", DataType::Integer8, AccessType::Rw),
        ));
        let o = b.object_mut(0x1018).unwrap();
        o.subs.get_mut(&1).unwrap().access = AccessType::Rw.into();
        o.subs.insert(
            2,
            SubObject::new("Product code", DataType::Unsigned32, AccessType::Ro),
        );
        o.subs.remove(&0);
    });
    assert_eq!(
        text,
        vec![
            "- 0x1000 Device type",
            "- 0x1018:00 n",
            "~ 0x1018:01 access: ro -> rw",
            "+ 0x1018:02 Product code",
            "+ 0x2000 Extra",
        ]
    );
    let text = dict_diff(|b| {
        b.insert(Object::var(
            0x0FFF,
            SubObject::new("Low", DataType::Integer8, AccessType::Rw),
        ));
    });
    assert_eq!(text, vec!["+ 0x0FFF Low"]);
    let a = base();
    let mut b = base();
    b.remove(0x1018);
    assert_eq!(lines(&diff(&a, &b)), vec!["- 0x1018 Identity"]);
    assert_eq!(lines(&diff(&b, &a)), vec!["+ 0x1018 Identity"]);
}

#[test]
fn object_fields_are_compared() {
    let text = dict_diff(|b| {
        let o = b.object_mut(0x1018).unwrap();
        o.name = "Identity object".into();
        o.description = Some("Who made it".into());
        o.kind = ObjectKind::Array;
        o.type_name = Some("DT1018".into());
    });
    assert_eq!(
        text,
        vec![
            "~ 0x1018 name: \"Identity\" -> \"Identity object\"",
            "~ 0x1018 description: none -> \"Who made it\"",
            "~ 0x1018 object code: RECORD -> ARRAY",
            "~ 0x1018 type name: none -> \"DT1018\"",
        ]
    );
}

#[test]
fn sub_object_fields_are_compared() {
    let text = dict_diff(|b| {
        let s = sub(b, 0x1018, 1);
        s.name = "Vendor ID".into();
        s.description = Some("\"quoted\"".into());
        s.access.read_states = Some(EcatStates::PREOP);
        s.access.write_states = Some(EcatStates::PREOP.union(EcatStates::SAFEOP));
        s.pdo = PdoMapping::Tpdo;
        s.low = Some(Value::Uint(1));
        s.high = Some(Value::Uint(0x10));
        s.value_set = true;
        let s = sub(b, 0x1018, 0);
        s.default = None;
    });
    assert_eq!(
        text,
        vec![
            "~ 0x1018:00 default: 0x01 -> none",
            "~ 0x1018:01 name: \"Vendor-ID\" -> \"Vendor ID\"",
            "~ 0x1018:01 description: none -> \"\\\"quoted\\\"\"",
            "~ 0x1018:01 access: ro -> ro read:PreOp write:PreOp_SafeOp",
            "~ 0x1018:01 PDO mapping: None -> Tpdo",
            "~ 0x1018:01 low limit: none -> 0x00000001",
            "~ 0x1018:01 high limit: none -> 0x00000010",
            "~ 0x1018:01 value set: no -> yes",
        ]
    );
}

#[test]
fn a_change_of_type_is_one_line_unless_the_size_is_not_the_types() {
    // The value's bytes change with the type: 4 zero bytes are no UNSIGNED16.
    let text = dict_diff(|b| {
        sub(b, 0x1000, 0).data_type = DataType::Unsigned16;
        sub(b, 0x1000, 0).bit_size = Some(16);
        sub(b, 0x1000, 0).value = vec![0, 0];
    });
    assert_eq!(
        text,
        vec![
            "~ 0x1000:00 type: UNSIGNED32 -> UNSIGNED16",
            "~ 0x1000:00 value: 0x00000000 -> 0x0000",
        ]
    );
    let text = dict_diff(|b| sub(b, 0x1000, 0).bit_size = Some(24));
    assert_eq!(text, vec!["~ 0x1000:00 size: 32 bits -> 24 bits"]);
    let text = dict_diff(|b| sub(b, 0x1000, 0).bit_size = None);
    assert_eq!(text, vec!["~ 0x1000:00 size: 32 bits -> unbounded"]);
}

fn one_var(s: SubObject) -> Dictionary {
    let mut d = Dictionary::new();
    d.insert(Object::var(0x2000, s));
    d
}

/// The lines of two one-entry dictionaries whose entries are `a` and `b`.
fn var_diff(a: SubObject, b: SubObject) -> Vec<String> {
    lines(&diff(&one_var(a), &one_var(b)))
}

#[test]
fn values_are_shown_as_values_of_the_entrys_type() {
    let u32v = |v: u64| {
        SubObject::new("x", DataType::Unsigned32, AccessType::Rw).with_default(Value::Uint(v))
    };
    assert_eq!(
        var_diff(u32v(1), u32v(2)),
        vec![
            "~ 0x2000:00 default: 0x00000001 -> 0x00000002",
            "~ 0x2000:00 value: 0x00000001 -> 0x00000002",
        ]
    );
    let int = |v: i64| {
        SubObject::new("x", DataType::Integer16, AccessType::Rw).with_default(Value::Int(v))
    };
    assert_eq!(
        var_diff(int(-1), int(3)),
        vec!["~ 0x2000:00 default: -1 -> 3", "~ 0x2000:00 value: -1 -> 3",]
    );
    let real = |v: f32| {
        SubObject::new("x", DataType::Real32, AccessType::Rw).with_default(Value::Real32(v))
    };
    assert_eq!(
        var_diff(real(1.5), real(-0.25)),
        vec![
            "~ 0x2000:00 default: 1.5 -> -0.25",
            "~ 0x2000:00 value: 1.5 -> -0.25",
        ]
    );
    let text = |v: &str| {
        SubObject::new("x", DataType::VisibleString, AccessType::Rw)
            .with_default(Value::String(v.into()))
    };
    assert_eq!(
        var_diff(text("SMD23K"), text("SMD \"24\"")),
        vec![
            "~ 0x2000:00 default: \"SMD23K\" -> \"SMD \\\"24\\\"\"",
            "~ 0x2000:00 value: \"SMD23K\" -> \"SMD \\\"24\\\"\"",
        ]
    );
    let octets = |v: &[u8]| {
        SubObject::new("x", DataType::OctetString, AccessType::Rw)
            .with_default(Value::Bytes(v.to_vec()))
    };
    assert_eq!(
        var_diff(octets(&[1, 0xAB]), octets(&[])),
        vec![
            "~ 0x2000:00 default: 01 AB -> (empty)",
            "~ 0x2000:00 value: 01 AB -> (empty)",
        ]
    );
    let unicode = |v: &str| {
        SubObject::new("x", DataType::UnicodeString, AccessType::Rw)
            .with_default(Value::Unicode(v.encode_utf16().collect()))
    };
    assert_eq!(
        var_diff(unicode("ä"), unicode("ö")),
        vec![
            "~ 0x2000:00 default: \"ä\" -> \"ö\"",
            "~ 0x2000:00 value: \"ä\" -> \"ö\"",
        ]
    );
    let time = |ms: u32| {
        SubObject::new("x", DataType::TimeOfDay, AccessType::Rw)
            .with_default(Value::Time(crate::value::TimeValue { ms, days: 2 }))
    };
    assert_eq!(
        var_diff(time(5), time(6)),
        vec![
            "~ 0x2000:00 default: 2:5 -> 2:6",
            "~ 0x2000:00 value: 2:5 -> 2:6",
        ]
    );
    let flag = |v: bool| {
        SubObject::new("x", DataType::Boolean, AccessType::Rw).with_default(Value::Bool(v))
    };
    assert_eq!(
        var_diff(flag(false), flag(true)),
        vec!["~ 0x2000:00 default: 0 -> 1", "~ 0x2000:00 value: 0 -> 1"]
    );
}

#[test]
fn bytes_that_are_no_value_of_the_type_are_shown_as_bytes() {
    let with = |bytes: &[u8]| {
        let mut s = SubObject::new("x", DataType::Unsigned32, AccessType::Rw);
        s.value = bytes.to_vec();
        s
    };
    assert_eq!(
        var_diff(with(&[1, 0]), with(&[1, 0, 0, 0])),
        vec!["~ 0x2000:00 value: 01 00 (not a UNSIGNED32) -> 0x00000001"]
    );
    assert_eq!(
        var_diff(with(&[]), with(&[1, 0, 0, 0, 0])),
        vec!["~ 0x2000:00 value: (empty) (not a UNSIGNED32) -> 01 00 00 00 00 (not a UNSIGNED32)"]
    );
    let mut flag = SubObject::new("x", DataType::Boolean, AccessType::Rw);
    flag.value = vec![2];
    assert_eq!(
        var_diff(
            flag.clone(),
            SubObject::new("x", DataType::Boolean, AccessType::Rw)
        ),
        vec!["~ 0x2000:00 value: 02 (not a BOOLEAN) -> 0"]
    );
}

#[test]
fn values_that_show_the_same_are_shown_as_held() {
    // 0xE9 is no UTF-8 and reads as Latin-1 `é`, which is also what C3 A9 is in UTF-8.
    let with = |bytes: &[u8]| {
        let mut s = SubObject::new("x", DataType::VisibleString, AccessType::Rw);
        s.value = bytes.to_vec();
        s
    };
    assert_eq!(
        var_diff(with(&[0xE9]), with(&[0xC3, 0xA9])),
        vec!["~ 0x2000:00 value: E9 -> C3 A9"]
    );
    // Two NaNs of different payloads show the same text.
    let nan = |bits: u32| {
        let mut s = SubObject::new("x", DataType::Real32, AccessType::Rw);
        s.default = Some(DefaultValue::plain(Value::Real32(f32::from_bits(bits))));
        s.low = Some(Value::Real32(f32::from_bits(bits)));
        s.high = Some(Value::Real64(f64::from_bits(
            bits as u64 | 0x7FF0_0000_0000_0000,
        )));
        s
    };
    assert_eq!(
        var_diff(nan(0x7FC0_0000), nan(0x7FC0_0001)),
        vec![
            "~ 0x2000:00 default: Real32(0x7FC00000) -> Real32(0x7FC00001)",
            "~ 0x2000:00 low limit: Real32(0x7FC00000) -> Real32(0x7FC00001)",
            "~ 0x2000:00 high limit: Real64(0x7FF000007FC00000) -> Real64(0x7FF000007FC00001)",
        ]
    );
    // …and equal NaNs are equal.
    assert_eq!(
        var_diff(nan(0x7FC0_0000), nan(0x7FC0_0000)),
        Vec::<String>::new()
    );
    // A default plus the node-ID and a plain default of the same number.
    let cob = |plus_node_id: bool| {
        let mut s = SubObject::new("x", DataType::Unsigned32, AccessType::Rw);
        s.default = Some(DefaultValue {
            value: Value::Uint(0x180),
            plus_node_id,
        });
        s
    };
    assert_eq!(
        var_diff(cob(true), cob(false)),
        vec!["~ 0x2000:00 default: $NODEID+0x00000180 -> 0x00000180"]
    );
    // The same number held as another kind of value.
    let held_as = |v: Value| {
        let mut s = SubObject::new("x", DataType::Unsigned8, AccessType::Rw);
        s.default = Some(DefaultValue {
            value: v,
            plus_node_id: true,
        });
        s
    };
    assert_eq!(
        var_diff(held_as(Value::Uint(1)), held_as(Value::Bool(true))),
        vec!["~ 0x2000:00 default: $NODEID+0x01 -> $NODEID+1"]
    );
    assert_eq!(
        var_diff(held_as(Value::Uint(1)), held_as(Value::Int(1))),
        vec!["~ 0x2000:00 default: $NODEID+0x01 -> $NODEID+1"]
    );
    let plain_as = |v: Value| {
        let mut s = SubObject::new("x", DataType::Unsigned8, AccessType::Rw);
        s.default = Some(DefaultValue::plain(v.clone()));
        s.low = Some(v);
        s
    };
    assert_eq!(
        var_diff(
            plain_as(Value::String("0x01".into())),
            plain_as(Value::Uint(1))
        ),
        vec![
            "~ 0x2000:00 default: \"0x01\" -> 0x01",
            "~ 0x2000:00 low limit: \"0x01\" -> 0x01",
        ]
    );
    assert_eq!(
        var_diff(plain_as(Value::Int(1)), plain_as(Value::Bool(true))),
        vec![
            "~ 0x2000:00 default: Int(1) -> Bool(true)",
            "~ 0x2000:00 low limit: Int(1) -> Bool(true)",
        ]
    );
}

/// Differences of whole descriptions: device parts, EtherCAT parts, devices of a file, modules.
mod descriptions;
