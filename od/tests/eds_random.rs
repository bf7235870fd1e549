//! CiA 306 EDS and DCF: random descriptions restricted to what an EDS or a DCF carries, through write →
//! read.

mod support;

use od::device::{Commissioning, FileInfo, Identity};
use od::object::ObjFlags;
use od::types::STANDARD_TYPES;
use od::{
    eds, AccessType, DataType, DefaultValue, DeviceDescription, Object, ObjectKind, PdoMapping,
    SubObject, Value,
};
use proptest::prelude::*;
use proptest::sample::subsequence;

/// Text an INI value keeps: one line, no blanks at the ends.
/// A text an INI value holds: no blank at either end, and no `;` after a blank (a reader takes
/// the rest as an inline comment; the writer drops such blanks).
fn text() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(String::new()),
        "[A-Za-z0-9_µ€(\\[][A-Za-z0-9 _%=;#$().,µ€\\[\\]-]{0,16}[A-Za-z0-9_)]"
            .prop_filter("a `;` after a blank starts an inline comment", |t| {
                !t.contains(" ;")
            }),
    ]
}

fn name() -> impl Strategy<Value = String> {
    "[A-Za-z0-9_µ][A-Za-z0-9 _%().µ-]{0,12}[A-Za-z0-9_)]"
}

/// A value of type `t` with INI text.
fn value_of(t: DataType) -> BoxedStrategy<Value> {
    support::random::value(t, text())
}

fn default_of(t: DataType) -> BoxedStrategy<Option<DefaultValue>> {
    let integer = t.is_signed() || (t.is_unsigned() && t != DataType::Boolean);
    let wide = integer && t.bit_size().unwrap_or(0) >= 16;
    if wide {
        // `$NODEID+offset` with an offset that still fits once node 127 is added.
        prop_oneof![
            Just(None),
            value_of(t).prop_map(|v| Some(DefaultValue::plain(v))),
            (0u64..0x7000).prop_map(move |v| Some(DefaultValue {
                value: if t.is_signed() {
                    Value::Int(v as i64)
                } else {
                    Value::Uint(v)
                },
                plus_node_id: true,
            })),
        ]
        .boxed()
    } else {
        proptest::option::of(value_of(t).prop_map(DefaultValue::plain)).boxed()
    }
}

/// An entry as an EDS describes it; its current value is its default for node 0.
fn sub_object(name: BoxedStrategy<String>) -> impl Strategy<Value = SubObject> {
    (
        name,
        proptest::sample::select(STANDARD_TYPES.to_vec()),
        support::random::access(),
        any::<bool>(),
    )
        .prop_flat_map(|(name, t, access, mapped)| {
            let numeric = t.is_signed() || t.is_unsigned() || t.is_real();
            let limit = move || {
                if numeric {
                    proptest::option::of(value_of(t)).boxed()
                } else {
                    Just(None).boxed()
                }
            };
            (
                Just((name, t, access, mapped)),
                default_of(t),
                limit(),
                limit(),
            )
        })
        .prop_map(|((name, t, access, mapped), default, low, high)| {
            let mut sub = SubObject::new(name, t, access).with_limits(low, high);
            if mapped {
                sub.pdo = match access {
                    AccessType::Ro | AccessType::Const | AccessType::Rwr => PdoMapping::Tpdo,
                    AccessType::Wo | AccessType::Rww => PdoMapping::Rpdo,
                    AccessType::Rw => PdoMapping::Both,
                };
            }
            sub.default = default;
            sub.reset(0);
            sub
        })
}

fn object(index: u16) -> impl Strategy<Value = Object> {
    let kinds = proptest::sample::select(vec![
        ObjectKind::Var,
        ObjectKind::Domain,
        ObjectKind::DefType,
        ObjectKind::Null,
        ObjectKind::Array,
        ObjectKind::Record,
        ObjectKind::DefStruct,
    ]);
    // `ObjFlags` of the object's section, and of each sub-index section (a VAR has one section,
    // the object's).
    let flags = || proptest::option::of(any::<u32>().prop_map(ObjFlags::from_bits));
    (kinds, name(), flags()).prop_flat_map(move |(kind, object_name, object_flags)| {
        if kind.has_subs() {
            let entry = (sub_object(name().boxed()), flags()).prop_map(|(mut sub, f)| {
                sub.flags = f;
                sub
            });
            proptest::collection::btree_map(any::<u8>(), entry, 0..5)
                .prop_map(move |subs| {
                    let mut o = Object::structured(index, object_name.clone(), kind);
                    o.subs = subs;
                    o.flags = object_flags;
                    o
                })
                .boxed()
        } else if kind == ObjectKind::Null {
            let mut o = Object::structured(index, object_name, kind);
            o.flags = object_flags;
            Just(o).boxed()
        } else {
            sub_object(Just(object_name).boxed())
                .prop_map(move |sub| {
                    let mut o = Object::var(index, sub);
                    o.kind = kind;
                    o.flags = object_flags;
                    o
                })
                .boxed()
        }
    })
}

fn description() -> impl Strategy<Value = DeviceDescription> {
    let identity = (
        any::<u32>(),
        text(),
        any::<u32>(),
        any::<u32>(),
        text(),
        text(),
    )
        .prop_map(
            |(vendor_id, vendor_name, product_code, revision, product_name, order_code)| Identity {
                vendor_id,
                vendor_name,
                product_code,
                revision,
                product_name,
                order_code,
                ..Default::default()
            },
        );
    let file_info = proptest::collection::vec(text(), 10).prop_map(|t| FileInfo {
        file_name: t[0].clone(),
        file_version: t[1].clone(),
        file_revision: t[2].clone(),
        format_version: "4.0".into(),
        description: t[3].clone(),
        creation_time: t[4].clone(),
        creation_date: t[5].clone(),
        created_by: t[6].clone(),
        modification_time: t[7].clone(),
        modification_date: t[8].clone(),
        modified_by: t[9].clone(),
    });
    let can = support::random::can_info(
        subsequence(vec![10u32, 20, 50, 125, 250, 500, 800, 1000], 0..=8),
        any::<u8>(),
    );
    let objects = proptest::collection::btree_set(any::<u16>(), 0..12)
        .prop_flat_map(|indices| indices.into_iter().map(object).collect::<Vec<_>>());
    (
        identity,
        file_info,
        can,
        proptest::collection::vec(text(), 0..4),
        objects,
    )
        .prop_map(|(identity, file_info, can, comments, objects)| {
            let mut desc = DeviceDescription {
                identity,
                file_info,
                can: Some(can),
                comments,
                ..DeviceDescription::default()
            };
            for o in objects {
                desc.dictionary.insert(o);
            }
            desc
        })
}

/// A DCF: commissioning values, and some entries set to other values.
fn configured() -> impl Strategy<Value = DeviceDescription> {
    (
        description(),
        1u8..=127,
        (
            text(),
            any::<u32>(),
            any::<u32>(),
            text(),
            any::<bool>(),
            any::<u32>(),
        ),
        any::<u64>(),
    )
        .prop_flat_map(|(mut desc, node_id, c, seed)| {
            desc.commissioning = Some(Commissioning {
                node_id: Some(node_id),
                node_name: c.0,
                baud_rate: c.1,
                net_number: c.2,
                network_name: c.3,
                canopen_manager: c.4,
                lss_serial_number: c.5,
            });
            desc.dictionary.reset(node_id);
            // Every third entry (by a seed) gets a value of its own.
            let mut picks = Vec::new();
            let mut n = seed;
            for o in desc.dictionary.objects() {
                for (&s, sub) in &o.subs {
                    if n % 3 == 0 {
                        picks.push((o.index, s, sub.data_type));
                    }
                    n = n.rotate_left(7) ^ 0x9E37_79B9;
                }
            }
            let values: Vec<_> = picks
                .iter()
                .map(|&(i, s, t)| value_of(t).prop_map(move |v| (i, s, t, v)))
                .collect();
            (Just(desc), values)
        })
        .prop_map(|(mut desc, values)| {
            for (index, sub, t, v) in values {
                let entry = desc
                    .dictionary
                    .object_mut(index)
                    .and_then(|o| o.subs.get_mut(&sub))
                    .unwrap();
                entry.value = v.encode(t).unwrap();
                entry.value_set = true;
            }
            desc
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn eds_write_read_round_trips(desc in description()) {
        let text = eds::write_eds(&desc);
        let back = eds::read(text.as_bytes(), "random.eds").map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        prop_assert_eq!(&back, &desc);
        prop_assert_eq!(eds::write_eds(&back), text);
    }

    #[test]
    fn dcf_write_read_round_trips(desc in configured()) {
        let text = eds::write_dcf(&desc);
        let back = eds::read(text.as_bytes(), "random.dcf").map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        prop_assert_eq!(&back, &desc);
        prop_assert_eq!(eds::write_dcf(&back), text);
    }
}
