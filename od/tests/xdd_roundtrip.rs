//! XDD write → read gives back the description, for random descriptions restricted to what XDD carries
//! (see the `od::xdd` module documentation for what it cannot carry).

mod support;

use od::device::{CanInfo, Commissioning, FileInfo, Identity};
use od::object::{
    Access, AccessType, DefaultValue, ObjFlags, Object, ObjectKind, PdoMapping, SubObject,
};
use od::types::STANDARD_TYPES;
use od::{DataType, DeviceDescription, Dictionary, Value};
use proptest::collection::btree_map;
use proptest::option;
use proptest::prelude::*;
use proptest::sample::{select, subsequence};

/// Text XML can carry: printable characters, tabs and line ends (written as references).
fn text() -> impl Strategy<Value = String> {
    "[ -~äöüµ€°\t\n\r]{0,10}"
}

/// A value of type `t` with XML text.
fn value(t: DataType) -> BoxedStrategy<Value> {
    support::random::value(t, text())
}

fn pdo() -> impl Strategy<Value = PdoMapping> {
    select(vec![
        PdoMapping::None,
        PdoMapping::Rpdo,
        PdoMapping::Tpdo,
        PdoMapping::Both,
    ])
}

/// One entry; `value` holds an explicitly set value or, until `settle`, nothing in particular.
fn entry_of(t: DataType) -> impl Strategy<Value = SubObject> {
    (
        (text(), support::random::access(), pdo(), option::of(text())),
        (option::of(value(t)), any::<bool>()),
        (option::of(value(t)), option::of(value(t))),
        (option::of(0u32..40), option::of(value(t)), flags()),
    )
        .prop_map(
            move |(
                (name, access, pdo, description),
                (default, plus),
                (low, high),
                (cap, actual, flags),
            )| {
                let mut s = SubObject::new(name, t, Access::new(access));
                s.flags = flags;
                s.pdo = pdo;
                s.description = description;
                s.default = default.map(|value| {
                    // A $NODEID default must fit for every node-ID up to 127, as the reader demands.
                    let fits = DefaultValue {
                        value: value.clone(),
                        plus_node_id: true,
                    }
                    .resolve(127)
                    .encode(t)
                    .is_ok();
                    DefaultValue {
                        plus_node_id: plus && t.is_unsigned() && t != DataType::Boolean && fits,
                        value,
                    }
                });
                s.low = low;
                s.high = high;
                if matches!(t, DataType::VisibleString | DataType::OctetString) {
                    let default_len = s
                        .default
                        .as_ref()
                        .and_then(|d| d.value.encode(t).ok())
                        .map_or(0, |b| b.len()) as u32;
                    s.bit_size = cap.map(|c| c.max(default_len) * 8);
                }
                if let Some(a) = actual {
                    s.value = a.encode(t).unwrap();
                    s.value_set = true;
                }
                s
            },
        )
}

/// CiA 306 `ObjFlags` (`objFlags`), or none.
fn flags() -> impl Strategy<Value = Option<ObjFlags>> {
    option::of(any::<u32>().prop_map(ObjFlags::from_bits))
}

fn any_entry() -> impl Strategy<Value = SubObject> {
    select(STANDARD_TYPES.to_vec()).prop_flat_map(entry_of)
}

fn object() -> impl Strategy<Value = Object> {
    // Mostly the object's name and description are its entry's (written inline); sometimes not (written
    // with a CANopenSubObject).
    let var = (
        any_entry(),
        option::weighted(0.2, text()),
        option::weighted(0.2, option::of(text())),
        flags(),
    )
        .prop_map(|(sub, name, description, flags)| {
            let entry_description = sub.description.clone();
            let mut o = Object::var(0, sub);
            o.flags = flags;
            o.description = description.unwrap_or(entry_description);
            if let Some(name) = name {
                o.name = name;
            }
            o
        });
    let structured = (
        select(vec![ObjectKind::Array, ObjectKind::Record]),
        text(),
        option::of(text()),
        option::of(text()),
        btree_map(any::<u8>(), any_entry(), 0..5),
        flags(),
    )
        .prop_map(|(kind, name, type_name, description, subs, flags)| {
            let mut o = Object::structured(0, name, kind);
            o.flags = flags;
            o.type_name = type_name;
            o.description = description;
            o.subs = subs;
            o
        });
    prop_oneof![var, structured]
}

fn date() -> impl Strategy<Value = String> {
    (1000u32..=9999, 1u32..=12, 1u32..=28).prop_map(|(y, m, d)| format!("{y:04}-{m:02}-{d:02}"))
}

fn time() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(String::new()),
        (0u32..24, 0u32..60, 0u32..60).prop_map(|(h, m, s)| format!("{h:02}:{m:02}:{s:02}"))
    ]
}

fn file_info() -> impl Strategy<Value = FileInfo> {
    (
        (text(), text(), text(), text()),
        (date(), time(), text()),
        (prop_oneof![Just(String::new()), date()], time()),
    )
        .prop_map(
            |(
                (file_name, file_version, description, created_by),
                (creation_date, creation_time, modified_by),
                (modification_date, modification_time),
            )| FileInfo {
                file_name,
                file_version,
                description,
                creation_time,
                creation_date,
                created_by,
                modification_time,
                modification_date,
                modified_by,
                ..FileInfo::default()
            },
        )
}

/// The bit rates the schema lists.
const BAUDS: [u32; 9] = [10, 20, 50, 100, 125, 250, 500, 800, 1000];

fn can_info() -> impl Strategy<Value = CanInfo> {
    support::random::can_info(subsequence(BAUDS.to_vec(), 0..=9), 0u8..=64)
}

fn commissioning() -> impl Strategy<Value = Commissioning> {
    (
        1u8..=127,
        text(),
        prop_oneof![Just(0u32), select(BAUDS.to_vec())],
        any::<u32>(),
        text(),
        any::<bool>(),
    )
        .prop_map(
            |(node_id, node_name, baud_rate, net_number, network_name, canopen_manager)| {
                Commissioning {
                    node_id: Some(node_id),
                    node_name,
                    baud_rate,
                    net_number,
                    network_name,
                    canopen_manager,
                    lss_serial_number: 0,
                }
            },
        )
}

fn description() -> impl Strategy<Value = DeviceDescription> {
    (
        (text(), text(), text(), any::<[u32; 3]>(), any::<bool>()),
        file_info(),
        option::of(can_info()),
        option::of(commissioning()),
        btree_map(0x2000u16..=0xFFFF, object(), 0..6),
    )
        .prop_map(
            |(
                (vendor_name, product_name, order_code, ids, with_identity),
                file_info,
                can,
                commissioning,
                objects,
            )| {
                let mut dictionary = Dictionary::new();
                for (index, mut o) in objects {
                    o.index = index;
                    dictionary.insert(o);
                }
                // The revision travels as the default of 0x1018:03 only.
                let revision = if with_identity { ids[2] } else { 0 };
                if with_identity {
                    let mut id = Object::structured(0x1018, "Identity", ObjectKind::Record);
                    for (sub, v) in [(0u8, 3u32), (1, ids[0]), (2, ids[1]), (3, ids[2])] {
                        let t = if sub == 0 {
                            DataType::Unsigned8
                        } else {
                            DataType::Unsigned32
                        };
                        id.subs.insert(
                            sub,
                            SubObject::new(format!("sub {sub}"), t, AccessType::Ro)
                                .with_default(Value::Uint(v as u64)),
                        );
                    }
                    dictionary.insert(id);
                }
                let node_id = commissioning.as_ref().and_then(|c| c.node_id).unwrap_or(0);
                for o in dictionary.objects_mut() {
                    for s in o.subs.values_mut().filter(|s| !s.value_set) {
                        s.reset(node_id);
                    }
                }
                DeviceDescription {
                    identity: Identity {
                        vendor_id: ids[0],
                        vendor_name,
                        product_code: ids[1],
                        revision,
                        product_name,
                        order_code,
                        ..Default::default()
                    },
                    file_info,
                    // A description without CAN parts is written with the defaults.
                    can: Some(can.unwrap_or_default()),
                    commissioning,
                    ..DeviceDescription::default()
                }
                .with_dictionary(dictionary)
            },
        )
}

trait WithDictionary {
    fn with_dictionary(self, dictionary: Dictionary) -> Self;
}

impl WithDictionary for DeviceDescription {
    fn with_dictionary(mut self, dictionary: Dictionary) -> Self {
        self.dictionary = dictionary;
        self
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 200,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn write_then_read_gives_the_description(d in description()) {
        let text = od::xdd::write(&d);
        let back = od::xdd::read(text.as_bytes(), "random.xdd")
            .map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        prop_assert_eq!(&back, &d, "{}", text);
        prop_assert_eq!(od::xdd::write(&back), text);
    }
}

#[test]
fn a_description_without_can_parts_reads_back_without_them() {
    let d = DeviceDescription::default();
    let back = od::xdd::read(od::xdd::write(&d).as_bytes(), "empty.xdd").unwrap();
    assert_eq!(back.can, None);
    assert_eq!(back.file_info.creation_date, "1970-01-01");
    assert_eq!(back.dictionary.len(), 0);
}

/// A configured node without CAN parts is written with the CAN defaults its network management
/// needs (dummy usage too), so what is written reads back and writes again to the same text (found
/// by the `roundtrip` fuzz target: the dummy usage was missing the first time).
#[test]
fn a_configured_node_without_can_parts_writes_the_same_text_twice() {
    let mut desc = DeviceDescription {
        commissioning: Some(Commissioning {
            node_id: Some(5),
            ..Commissioning::default()
        }),
        ..DeviceDescription::default()
    };
    desc.dictionary.insert(Object::var(
        0x1000,
        SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro),
    ));
    assert_eq!(desc.can, None);
    let text = od::xdd::write(&desc);
    assert!(text.contains("<dummy entry=\"Dummy0001=0\"/>"), "{text}");
    let back = od::xdd::read(text.as_bytes(), "written").unwrap();
    assert_eq!(back.can, Some(CanInfo::default()));
    assert_eq!(od::xdd::write(&back), text);
}
