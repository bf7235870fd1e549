//! XDD write → read gives back the description, for random descriptions restricted to what XDD carries
//! (see the `od::xdd` module documentation for what it cannot carry).

use od::device::{CanInfo, Commissioning, FileInfo, Identity};
use od::object::{Access, AccessType, DefaultValue, Object, ObjectKind, PdoMapping, SubObject};
use od::types::STANDARD_TYPES;
use od::value::TimeValue;
use od::{DataType, DeviceDescription, Dictionary, Value};
use proptest::collection::{btree_map, btree_set, vec};
use proptest::option;
use proptest::prelude::*;
use proptest::sample::select;

/// Text XML can carry: printable characters, tabs and line ends (written as references).
fn text() -> impl Strategy<Value = String> {
    "[ -~äöüµ€°\t\n\r]{0,10}"
}

fn value(t: DataType) -> BoxedStrategy<Value> {
    match t {
        DataType::Boolean => any::<bool>().prop_map(Value::Bool).boxed(),
        DataType::Real32 => prop_oneof![Just(0.0f32), proptest::num::f32::NORMAL]
            .prop_map(Value::Real32)
            .boxed(),
        DataType::Real64 => prop_oneof![Just(0.0f64), proptest::num::f64::NORMAL]
            .prop_map(Value::Real64)
            .boxed(),
        DataType::VisibleString => text().prop_map(Value::String).boxed(),
        DataType::UnicodeString => text()
            .prop_map(|s| Value::Unicode(s.encode_utf16().collect()))
            .boxed(),
        DataType::OctetString | DataType::Domain => {
            vec(any::<u8>(), 0..6).prop_map(Value::Bytes).boxed()
        }
        DataType::TimeOfDay | DataType::TimeDifference => (0..=0x0FFF_FFFFu32, any::<u16>())
            .prop_map(|(ms, days)| Value::Time(TimeValue { ms, days }))
            .boxed(),
        t => {
            let (lo, hi) = t.integer_range().unwrap();
            if t.is_signed() {
                (lo as i64..=hi as i64).prop_map(Value::Int).boxed()
            } else {
                (0..=hi as u64).prop_map(Value::Uint).boxed()
            }
        }
    }
}

fn access() -> impl Strategy<Value = AccessType> {
    select(vec![
        AccessType::Ro,
        AccessType::Wo,
        AccessType::Rw,
        AccessType::Rwr,
        AccessType::Rww,
        AccessType::Const,
    ])
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
        (text(), access(), pdo(), option::of(text())),
        (option::of(value(t)), any::<bool>()),
        (option::of(value(t)), option::of(value(t))),
        (option::of(0u32..40), option::of(value(t))),
    )
        .prop_map(
            move |(
                (name, access, pdo, description),
                (default, plus),
                (low, high),
                (cap, actual),
            )| {
                let mut s = SubObject::new(name, t, Access::new(access));
                s.pdo = pdo;
                s.description = description;
                s.default = default.map(|value| DefaultValue {
                    plus_node_id: plus && t.is_unsigned() && t != DataType::Boolean,
                    value,
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
    )
        .prop_map(|(sub, name, description)| {
            let entry_description = sub.description.clone();
            let mut o = Object::var(0, sub);
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
    )
        .prop_map(|(kind, name, type_name, description, subs)| {
            let mut o = Object::structured(0, name, kind);
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
    (
        (btree_set(select(BAUDS.to_vec()), 0..9), any::<[bool; 5]>()),
        (0u8..=64, any::<u8>(), any::<u16>(), any::<u16>()),
        // The schema knows Dummy0001 to Dummy0007 only.
        btree_set(1u16..=7, 0..7),
    )
        .prop_map(
            |((bauds, flags), (granularity, dynamic, rx, tx), dummies)| CanInfo {
                baud_rates: bauds.into_iter().collect(),
                simple_boot_up_master: flags[0],
                simple_boot_up_slave: flags[1],
                granularity,
                dynamic_channels: dynamic,
                group_messaging: flags[2],
                nr_of_rx_pdo: rx,
                nr_of_tx_pdo: tx,
                lss_supported: flags[3] && flags[4],
                dummy_usage: dummies.into_iter().collect(),
            },
        )
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
                    node_id,
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
                let node_id = commissioning.as_ref().map_or(0, |c| c.node_id);
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
fn a_description_without_can_parts_reads_back_with_the_defaults() {
    let d = DeviceDescription::default();
    let back = od::xdd::read(od::xdd::write(&d).as_bytes(), "empty.xdd").unwrap();
    assert_eq!(back.can, Some(CanInfo::default()));
    assert_eq!(back.file_info.creation_date, "1970-01-01");
    assert_eq!(back.dictionary.len(), 0);
}
