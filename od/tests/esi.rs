//! ESI reader and writer: error positions, and a property test of write → read (the hand-written file,
//! the writer's snapshots and the SMD fixture are in `esi_exact`).

use std::collections::BTreeMap;

use od::device::{
    CoeFlags, DeviceDescription, Eeprom, EthercatInfo, Identity, InitCmd, Mailbox, Module,
    ModulePdoGroup, OpMode, Pdo, PdoEntry, PdoRef, Slot, SlotDepend, SlotModuleClass,
    SlotModuleIdent, Slots, SyncManager,
};
use od::esi::{self};
use od::object::{Access, AccessType, EcatStates, Object, ObjectKind, PdoMapping, SubObject};
use od::types::DataType;
use od::value::{TimeValue, Value};
use od::Dictionary;

// ---------------------------------------------------------------------------------------------------------
// Errors name the place.

/// A file whose objects start on line 7.
fn with_objects(objects: &str) -> String {
    format!(
        "<?xml version=\"1.0\"?>\n<EtherCATInfo>\n<Vendor><Id>1</Id><Name>V</Name></Vendor>\n\
         <Descriptions><Devices><Device>\n<Type ProductCode=\"1\" RevisionNo=\"1\">T</Type><Name>N</Name>\n\
         <Profile><Dictionary><DataTypes/><Objects>\n{objects}\n</Objects></Dictionary></Profile>\n\
         </Device></Devices></Descriptions>\n</EtherCATInfo>\n"
    )
}

fn error_of(text: &str) -> (u32, u32, String) {
    let e = esi::read_all(text.as_bytes(), "bad.xml").unwrap_err();
    assert_eq!(e.source_name, "bad.xml");
    (e.position.line, e.position.column, e.message)
}

#[test]
fn errors_give_line_column_and_what_was_expected() {
    let (l, c, m) = error_of(&with_objects(
        "<Object><Index>zz</Index><Name>x</Name><Type>UINT</Type></Object>",
    ));
    assert_eq!((l, c), (7, 16));
    assert_eq!(
        m,
        "expected a number like #x1A00 or 6656 in <Object>/<Index>, found `zz`"
    );

    let (l, c, m) = error_of(&with_objects(
        "<Object><Index>#x10000</Index><Name>x</Name><Type>UINT</Type></Object>",
    ));
    assert_eq!((l, c), (7, 16));
    assert_eq!(
        m,
        "expected a number 0..65535 in <Object>/<Index>, found `#x10000`"
    );

    let (l, c, m) = error_of(&with_objects(
        "<Object><Index>#x2000</Index><Name>x</Name><Type>UINT</Type><Info><DefaultData>0G</DefaultData></Info></Object>",
    ));
    assert_eq!((l, c), (7, 80));
    assert!(
        m.contains("expected hexadecimal bytes like 0A1B in <DefaultData>, found `0G`"),
        "{m}"
    );

    let (l, c, m) = error_of(&with_objects(
        "<Object><Index>#x2000</Index><Name>x</Name>\n  <Type>DT9999</Type></Object>",
    ));
    assert_eq!((l, c), (8, 9));
    assert!(m.contains("object #x2000: expected a basic type name or the name of a <DataType> in <Type>, found `DT9999`"), "{m}");

    let (l, c, m) = error_of(&with_objects(
        "<Object><Index>#x2000</Index><Name>x</Name><Type>UINT</Type><Flags><Access>rx</Access></Flags></Object>",
    ));
    assert_eq!((l, c), (7, 76));
    assert_eq!(m, "expected ro, rw or wo in <Access>, found `rx`");

    let (l, c, m) = error_of(&with_objects(
        "<Object><Index>#x2000</Index><Name>x</Name><Type>UINT</Type><Flags><Access WriteRestrictions=\"Boot\">rw</Access></Flags></Object>",
    ));
    assert_eq!((l, c), (7, 76));
    assert!(
        m.contains("WriteRestrictions attribute, found `Boot`"),
        "{m}"
    );

    let (l, c, m) = error_of(&with_objects(
        "<Object><Index>#x2000</Index><Name>x</Name><Type>UINT</Type></Object>\n<Object><Index>#x2000</Index><Name>y</Name><Type>UINT</Type></Object>",
    ));
    assert_eq!((l, c), (8, 1));
    assert_eq!(m, "object #x2000 is defined twice (first at line 7)");

    // An attribute: the column of its name.
    let text = with_objects("").replace("ProductCode=\"1\"", "ProductCode=\"#xZZ\"");
    let (l, c, m) = error_of(&text);
    assert_eq!((l, c), (5, 7));
    assert_eq!(
        m,
        "expected a number like #x1A00 or 6656 in the ProductCode attribute, found `#xZZ`"
    );

    // Malformed XML.
    let text = with_objects("<Object><Index>#x2000</Index></Objekt>");
    let (l, _, m) = error_of(&text);
    assert_eq!(l, 7);
    assert!(m.starts_with("malformed XML"), "{m}");
    let (l, c, m) = error_of("<EtherCATInfo>\n<Vendor>");
    assert_eq!((l, c), (2, 9));
    assert_eq!(m, "unexpected end of file: <Vendor> is not closed");

    // Not an ESI.
    let (l, c, m) = error_of("<?xml version=\"1.0\"?>\n<ISO15745ProfileContainer/>");
    assert_eq!((l, c), (2, 1));
    assert!(m.contains("expected an <EtherCATInfo> root element"), "{m}");

    // Invalid UTF-8 where the file declares none.
    let e = esi::read_all(b"<EtherCATInfo>\n<Vendor><Name>\xB5</Name>", "bad.xml").unwrap_err();
    assert_eq!((e.position.line, e.position.column), (2, 15));
    let e = esi::read_all(
        b"\xEF\xBB\xBF<EtherCATInfo>\n<Vendor><Name>\xC3</Name>",
        "bad.xml",
    )
    .unwrap_err();
    assert_eq!(
        (e.position.line, e.position.column),
        (2, 15),
        "after a BOM too"
    );
}

#[test]
fn unknown_elements_are_skipped() {
    let text = with_objects(
        "<Object><Index>#x2000</Index><Name>x</Name><Vendor:Extra a=\"b\"><Deep><Index>zz</Index></Deep></Vendor:Extra>\
         <Type>UINT</Type><Flags><Access>rw</Access><Category>o</Category><Backup>1</Backup></Flags></Object>",
    );
    let d = esi::read(text.as_bytes(), "x.xml", None).unwrap();
    assert_eq!(
        d.dictionary.entry(0x2000, 0).unwrap().access.kind,
        AccessType::Rw
    );
}

// ---------------------------------------------------------------------------------------------------------
// Property: write → read gives back every description the format can carry.

/// splitmix64: a small deterministic generator driven by one proptest seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n.max(1)
    }

    fn chance(&mut self, one_in: u64) -> bool {
        self.below(one_in) == 0
    }

    fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[self.below(items.len() as u64) as usize]
    }

    /// Trimmed text with XML specials and non-ASCII; `lines` allows inner line breaks.
    fn text(&mut self, max: u64, lines: bool) -> String {
        const CHARS: &[char] = &[
            'a', 'b', 'Z', '0', '7', ' ', '_', '-', '.', ':', '&', '<', '>', '"', '\'', 'µ', 'ä',
            '°', '€', '#', '[', ']',
        ];
        let n = self.below(max + 1);
        let mut s: String = (0..n)
            .map(|_| {
                if lines && self.chance(12) {
                    '\n'
                } else {
                    self.pick(CHARS)
                }
            })
            .collect();
        s = s.trim().to_string();
        s
    }

    fn bytes(&mut self, max: u64) -> Vec<u8> {
        let n = self.below(max + 1);
        (0..n).map(|_| self.next() as u8).collect()
    }
}

const FIXED: &[DataType] = &[
    DataType::Boolean,
    DataType::Integer8,
    DataType::Integer16,
    DataType::Integer24,
    DataType::Integer32,
    DataType::Integer40,
    DataType::Integer48,
    DataType::Integer56,
    DataType::Integer64,
    DataType::Unsigned8,
    DataType::Unsigned16,
    DataType::Unsigned24,
    DataType::Unsigned32,
    DataType::Unsigned40,
    DataType::Unsigned48,
    DataType::Unsigned56,
    DataType::Unsigned64,
    DataType::Real32,
    DataType::Real64,
    DataType::TimeOfDay,
    DataType::TimeDifference,
    DataType::Bit(1),
    DataType::Bit(2),
    DataType::Bit(5),
    DataType::Bit(8),
];

const VARIABLE: &[DataType] = &[
    DataType::VisibleString,
    DataType::OctetString,
    DataType::UnicodeString,
    DataType::Domain,
];

/// A type and the bit size the ESI gives it.
fn random_type(r: &mut Rng) -> (DataType, Option<u32>) {
    if r.chance(4) {
        let t = r.pick(VARIABLE);
        let bits = match t {
            DataType::UnicodeString => 16 * r.below(9) as u32,
            DataType::Domain => r.below(300) as u32,
            _ => 8 * r.below(9) as u32,
        };
        (t, Some(bits))
    } else {
        let t = r.pick(FIXED);
        (t, t.bit_size())
    }
}

fn random_value(r: &mut Rng, t: DataType) -> Value {
    match t {
        DataType::Boolean => Value::Bool(r.chance(2)),
        DataType::Real32 => {
            let v = f32::from_bits(r.next() as u32);
            Value::Real32(if v.is_nan() { 0.5 } else { v })
        }
        DataType::Real64 => {
            let v = f64::from_bits(r.next());
            Value::Real64(if v.is_nan() { -0.25 } else { v })
        }
        DataType::VisibleString => Value::String(r.text(10, false)),
        DataType::UnicodeString => {
            Value::Unicode((0..r.below(5)).map(|_| r.next() as u16).collect())
        }
        DataType::OctetString | DataType::Domain => Value::Bytes(r.bytes(8)),
        DataType::TimeOfDay | DataType::TimeDifference => Value::Time(TimeValue {
            ms: (r.next() as u32) & 0x0FFF_FFFF,
            days: r.next() as u16,
        }),
        t => {
            let (lo, hi) = t.integer_range().unwrap();
            let span = (hi - lo + 1) as u128;
            let v = lo + (u128::from(r.next()) % span) as i128;
            if t.is_signed() {
                Value::Int(v as i64)
            } else {
                Value::Uint(v as u64)
            }
        }
    }
}

fn random_access(r: &mut Rng) -> Access {
    let set = |r: &mut Rng| {
        if r.chance(3) {
            let bits = 1 + r.below(7) as u8;
            let mut s = EcatStates::default();
            for (bit, st) in [
                (1, EcatStates::PREOP),
                (2, EcatStates::SAFEOP),
                (4, EcatStates::OP),
            ] {
                if bits & bit != 0 {
                    s = s.union(st);
                }
            }
            Some(s)
        } else {
            None
        }
    };
    Access {
        kind: r.pick(&[AccessType::Ro, AccessType::Rw, AccessType::Wo]),
        read_states: set(r),
        write_states: set(r),
    }
}

/// An entry of `t`; `shape` fixes what must be uniform in an array.
fn random_sub(
    r: &mut Rng,
    name: String,
    t: DataType,
    bits: Option<u32>,
    shape: Option<(Access, PdoMapping, Option<String>)>,
) -> SubObject {
    let (access, pdo, description) = shape.unwrap_or_else(|| {
        (
            random_access(r),
            r.pick(&[
                PdoMapping::None,
                PdoMapping::Rpdo,
                PdoMapping::Tpdo,
                PdoMapping::Both,
            ]),
            if r.chance(2) {
                Some(r.text(30, true))
            } else {
                None
            },
        )
    });
    let mut s = SubObject::new(name, t, access).with_pdo(pdo);
    s.bit_size = bits;
    s.description = description;
    if r.chance(2) {
        let v = random_value(r, t);
        // A string's default fits its size (a longer one tells the reader the size).
        let fits = match (t.is_variable(), bits, v.encode(t)) {
            (true, Some(b), Ok(bytes)) => bytes.len() * 8 <= b as usize,
            _ => true,
        };
        if fits {
            s = s.with_default(v);
        }
    }
    let numeric = t.integer_range().is_some() || t.is_real();
    if numeric && r.chance(3) {
        s.low = Some(random_value(r, t));
    }
    if numeric && r.chance(3) {
        s.high = Some(random_value(r, t));
    }
    s
}

fn random_object(r: &mut Rng, index: u16) -> Object {
    let name = r.text(16, false);
    match r.below(4) {
        0 | 1 => {
            let (t, bits) = random_type(r);
            let mut sub = random_sub(r, name.clone(), t, bits, None);
            let mut o = Object::var(index, sub.clone());
            let description = sub.description.take();
            o.description = description.clone();
            o.subs.get_mut(&0).unwrap().description = description;
            o
        }
        k => {
            let kind = if k == 2 {
                ObjectKind::Record
            } else {
                ObjectKind::Array
            };
            let mut o = Object::structured(index, name, kind);
            o.type_name = Some(if r.chance(2) {
                format!("DT{index:04X}")
            } else {
                format!("T_{index}_x")
            });
            if r.chance(2) {
                o.description = Some(r.text(40, true));
            }
            let zero_name = r.text(12, false);
            let zero = random_sub(r, zero_name, DataType::Unsigned8, Some(8), None);
            o.subs.insert(0, zero);
            if kind == ObjectKind::Array {
                let (t, bits) = random_type(r);
                let shape = (
                    random_access(r),
                    r.pick(&[PdoMapping::None, PdoMapping::Tpdo]),
                    if r.chance(2) {
                        Some(r.text(20, false))
                    } else {
                        None
                    },
                );
                for s in 1..=r.below(6) as u8 {
                    let n = r.text(10, false);
                    let sub = random_sub(r, n, t, bits, Some(shape.clone()));
                    o.subs.insert(s, sub);
                }
            } else {
                let mut s = 0u8;
                for _ in 0..r.below(6) {
                    s = s.saturating_add(1 + r.below(4) as u8);
                    let (t, bits) = random_type(r);
                    let n = r.text(10, false);
                    let sub = random_sub(r, n, t, bits, None);
                    o.subs.insert(s, sub);
                }
            }
            o
        }
    }
}

fn random_pdo(r: &mut Rng) -> Pdo {
    let depend = |r: &mut Rng| SlotDepend {
        slot: r.chance(4),
        slot_group: r.chance(8),
    };
    let small = |r: &mut Rng| {
        if r.chance(2) {
            Some(r.below(100) as u32)
        } else {
            None
        }
    };
    Pdo {
        index: r.next() as u16,
        index_depend: depend(r),
        name: r.text(10, false),
        fixed: r.chance(2),
        mandatory: r.chance(2),
        is_virtual: r.chance(4),
        sm: if r.chance(2) {
            Some(r.next() as u8)
        } else {
            None
        },
        su: if r.chance(4) {
            Some(r.next() as u8)
        } else {
            None
        },
        os_factor: small(r),
        os_min: small(r),
        os_max: small(r),
        os_index_inc: small(r),
        exclude: (0..r.below(3))
            .map(|_| PdoRef {
                index: r.next() as u16,
                depend: depend(r),
            })
            .collect(),
        entries: (0..r.below(4))
            .map(|_| PdoEntry {
                index: if r.chance(3) { 0 } else { r.next() as u16 },
                index_depend: depend(r),
                sub: if r.chance(3) { 0 } else { r.next() as u8 },
                bit_len: r.next() as u16,
                name: r.text(8, false),
                comment: if r.chance(3) {
                    r.text(12, true)
                } else {
                    String::new()
                },
                data_type: r.text(8, false),
                data_scale: if r.chance(4) {
                    r.text(6, false)
                } else {
                    String::new()
                },
                fixed: r.chance(4),
            })
            .collect(),
    }
}

fn random_ethercat(r: &mut Rng) -> EthercatInfo {
    let opt = |r: &mut Rng| {
        if r.chance(2) {
            Some(r.next() as u32)
        } else {
            None
        }
    };
    EthercatInfo {
        group_type: r.text(8, false),
        fmmus: (0..r.below(4)).map(|_| r.text(8, false)).collect(),
        sync_managers: (0..r.below(5))
            .map(|_| SyncManager {
                kind: r.text(8, false),
                start_address: r.next() as u16,
                default_size: opt(r).map(|v| v as u16),
                min_size: opt(r).map(|v| v as u16),
                max_size: opt(r).map(|v| v as u16),
                control_byte: r.next() as u8,
                enable: r.next() as u8,
                is_virtual: r.chance(4),
                op_only: r.chance(4),
                watchdog: r.chance(4),
            })
            .collect(),
        rx_pdos: (0..r.below(3)).map(|_| random_pdo(r)).collect(),
        tx_pdos: (0..r.below(3)).map(|_| random_pdo(r)).collect(),
        mailbox: random_mailbox(r),
        op_modes: (0..r.below(3))
            .map(|_| OpMode {
                name: r.text(8, false),
                desc: r.text(12, false),
                assign_activate: r.next() as u16,
                cycle_time_sync0: opt(r).map(|v| (v, r.next() as i32)),
                shift_time_sync0: opt(r).map(|v| v as i32),
                cycle_time_sync1: opt(r).map(|v| (v, r.next() as i32)),
                shift_time_sync1: opt(r).map(|v| v as i32),
            })
            .collect(),
        eeprom: if r.chance(2) {
            Some(Eeprom {
                byte_size: r.next() as u32,
                config_data: r.bytes(14),
                boot_strap: r.bytes(8),
            })
        } else {
            None
        },
        slots: random_slots(r),
        modules: Default::default(),
        root: Default::default(),
    }
}

fn random_mailbox(r: &mut Rng) -> Option<Mailbox> {
    if r.chance(3) {
        return None;
    }
    let coe = if r.chance(3) {
        None
    } else {
        Some(CoeFlags {
            sdo_info: r.chance(2),
            pdo_assign: r.chance(2),
            pdo_config: r.chance(2),
            pdo_upload: r.chance(2),
            complete_access: r.chance(2),
            segmented_sdo: r.chance(2),
        })
    };
    // Start-up commands are part of the CoE element.
    let init_cmds = if coe.is_some() {
        (0..r.below(3))
            .map(|_| InitCmd {
                transitions: (0..1 + r.below(2))
                    .map(|_| r.pick(&["PS", "SO", "SP", "OP", "OS", "IP"]).to_string())
                    .collect(),
                index: r.next() as u16,
                index_depend: SlotDepend {
                    slot: r.chance(3),
                    slot_group: r.chance(6),
                },
                sub: r.next() as u8,
                data: r.bytes(6),
                adapt_automatically: r.chance(3),
                comment: r.text(10, false),
                fixed: r.chance(3),
                complete_access: r.chance(3),
                overwritten_by_module: r.chance(5),
            })
            .collect()
    } else {
        Vec::new()
    };
    Some(Mailbox {
        data_link_layer: r.chance(2),
        coe,
        foe: r.chance(2),
        eoe: r.chance(2),
        init_cmds,
    })
}

fn random_slots(r: &mut Rng) -> Option<Slots> {
    if r.chance(2) {
        return None;
    }
    let opt = |r: &mut Rng| {
        if r.chance(2) {
            Some(r.next() as u32)
        } else {
            None
        }
    };
    Some(Slots {
        max_slot_count: opt(r),
        max_slot_group_count: opt(r),
        slot_pdo_increment: opt(r),
        slot_group_pdo_increment: opt(r),
        slot_index_increment: opt(r),
        slot_group_index_increment: opt(r),
        download_module_ident_list: r.chance(2),
        identify_module_by: if r.chance(3) {
            "ModuleIdent".into()
        } else {
            String::new()
        },
        slots: (0..r.below(3))
            .map(|_| Slot {
                name: r.text(10, false),
                slot_group: opt(r),
                min_instances: r.next() as u32,
                max_instances: r.next() as u32,
                slot_pdo_increment: opt(r),
                slot_group_pdo_increment: opt(r),
                slot_index_increment: opt(r),
                slot_group_index_increment: opt(r),
                tree_view: if r.chance(3) {
                    "SLOT".into()
                } else {
                    String::new()
                },
                module_idents: (0..r.below(3))
                    .map(|_| SlotModuleIdent {
                        ident: r.next() as u32,
                        default: opt(r),
                    })
                    .collect(),
                module_classes: (0..r.below(3))
                    .map(|_| SlotModuleClass {
                        class: r.text(8, false),
                        vendor_id: opt(r),
                        name: r.text(8, false),
                    })
                    .collect(),
            })
            .collect(),
        module_pdo_groups: (0..r.below(2))
            .map(|_| ModulePdoGroup {
                name: r.text(8, false),
                alignment: opt(r),
                rx_pdo: opt(r).map(|v| v as u16),
                tx_pdo: opt(r).map(|v| v as u16),
            })
            .collect(),
    })
}

fn random_dictionary(r: &mut Rng, objects: usize) -> Dictionary {
    let mut objs = BTreeMap::new();
    for _ in 0..objects {
        let index = 0x1000 + r.below(0xF000) as u16;
        objs.insert(index, random_object(r, index));
    }
    let mut dictionary = Dictionary::new();
    for o in objs.into_values() {
        dictionary.insert(o);
    }
    dictionary
}

fn random_module(r: &mut Rng) -> Module {
    let mut m = Module {
        ident: r.next() as u32,
        class: r.text(8, false),
        pdo_group: if r.chance(2) {
            Some(r.below(10) as u32)
        } else {
            None
        },
        type_name: r.text(12, false),
        name: r.text(20, false),
        rx_pdos: (0..r.below(3)).map(|_| random_pdo(r)).collect(),
        tx_pdos: (0..r.below(3)).map(|_| random_pdo(r)).collect(),
        mailbox: random_mailbox(r),
        profile_no: if r.chance(2) { Some(402) } else { None },
        add_info: if r.chance(3) {
            Some(r.below(100) as u32)
        } else {
            None
        },
        dictionary: {
            let n = r.below(4) as usize;
            random_dictionary(r, n)
        },
        dc_op_mode_name: r.text(8, false),
    };
    map_entries(r, &mut m.dictionary, &mut m.rx_pdos, &mut m.tx_pdos);
    m
}

fn random_descriptions(seed: u64, count: usize, objects: usize) -> Vec<DeviceDescription> {
    let mut r = Rng(seed);
    let vendor_id = r.next() as u32;
    let vendor_name = r.text(20, false);
    let file_version = r.text(6, false);
    // The modules of a file belong to each of its devices.
    let modules: std::sync::Arc<[Module]> =
        (0..r.below(3)).map(|_| random_module(&mut r)).collect();
    (0..count)
        .map(|_| {
            let dictionary = random_dictionary(&mut r, objects);
            let mut d = DeviceDescription {
                identity: Identity {
                    vendor_id,
                    vendor_name: vendor_name.clone(),
                    product_code: r.next() as u32,
                    revision: r.next() as u32,
                    product_name: r.text(20, false),
                    order_code: r.text(12, false),
                    ..Default::default()
                },
                ethercat: Some(random_ethercat(&mut r)),
                dictionary,
                ..DeviceDescription::default()
            };
            d.file_info.file_version = file_version.clone();
            if let Some(ec) = d.ethercat.as_mut() {
                map_entries(&mut r, &mut d.dictionary, &mut ec.rx_pdos, &mut ec.tx_pdos);
                ec.modules = modules.clone();
            }
            d
        })
        .collect()
}

/// Points every PDO entry at an entry of the dictionary (or makes it a gap) and makes that entry
/// mappable in the PDO's direction: the descriptions an ESI can carry, since the reader makes the entries
/// PDOs map and takes their direction from the PDOs.
fn map_entries(r: &mut Rng, dictionary: &mut Dictionary, rx: &mut [Pdo], tx: &mut [Pdo]) {
    let existing: Vec<(u16, u8)> = dictionary
        .objects()
        .flat_map(|o| o.subs.keys().map(move |&s| (o.index, s)))
        .collect();
    for (pdos, dir) in [(rx, PdoMapping::Rpdo), (tx, PdoMapping::Tpdo)] {
        for e in pdos.iter_mut().flat_map(|p| p.entries.iter_mut()) {
            if e.index == 0 {
                continue;
            }
            if existing.is_empty() {
                e.index = 0;
                continue;
            }
            let (index, sub) = existing[r.below(existing.len() as u64) as usize];
            (e.index, e.sub) = (index, sub);
            let Some(object) = dictionary.object_mut(index) else {
                continue;
            };
            // The elements of an ARRAY stay uniform.
            let array = object.kind == ObjectKind::Array && sub != 0;
            for (&s, entry) in object.subs.iter_mut() {
                if s == sub || (array && s != 0) {
                    entry.pdo = match (entry.pdo, dir) {
                        (PdoMapping::None, d) => d,
                        (p, d) if p == d || p == PdoMapping::Both => p,
                        _ => PdoMapping::Both,
                    };
                }
            }
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(200))]

    #[test]
    fn written_descriptions_read_back_equal(seed in proptest::prelude::any::<u64>(), count in 1usize..3, objects in 0usize..12) {
        let descs = random_descriptions(seed, count, objects);
        let text = esi::write_all(&descs);
        let back = esi::read_all(text.as_bytes(), "prop.xml").map_err(|e| {
            proptest::test_runner::TestCaseError::fail(format!("{e}\n{text}"))
        })?;
        proptest::prop_assert_eq!(&back, &descs, "{}", text);
        proptest::prop_assert_eq!(esi::write_all(&back), text);
    }
}

#[test]
fn negative_shift_times_read_and_write_back() {
    let text = r##"<?xml version="1.0"?>
<EtherCATInfo><Vendor><Id>1</Id></Vendor><Descriptions><Devices><Device>
<Type ProductCode="#x1" RevisionNo="#x1">D</Type><Name>D</Name>
<Dc><OpMode><Name>DC</Name><Desc>DC</Desc><AssignActivate>#x0300</AssignActivate>
<CycleTimeSync0 Factor="1">0</CycleTimeSync0><ShiftTimeSync0>-250000</ShiftTimeSync0></OpMode></Dc>
</Device></Devices></Descriptions></EtherCATInfo>"##;
    let dev = od::esi::read(text.as_bytes(), "shift.xml", None).unwrap();
    let mode = &dev.ethercat.as_ref().unwrap().op_modes[0];
    assert_eq!(mode.shift_time_sync0, Some(-250_000));
    let back = od::esi::read(od::esi::write(&dev).as_bytes(), "back.xml", None).unwrap();
    assert_eq!(
        back.ethercat.unwrap().op_modes[0].shift_time_sync0,
        Some(-250_000)
    );
}
