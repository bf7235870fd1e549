//! The CiA 301 values a device of a description reports where the description gives none: its
//! identity (0x1018:01–03) and its names (0x1008–0x100A). Vendor files often leave these objects
//! without a value, and a device running such a file as it stands would report 0 (or an empty
//! name) where the real device reports what the file says elsewhere: masters that check the
//! identity (python-canopen's readers, `sdo-tool`'s check of `--od`) then see another device.
//!
//! [`identity_and_names`] fills them in (sans-IO: a description in, the events of what it changed
//! out) and says what it did and why, one [`Event`] per entry; [`pdo_cob_ids`] makes not valid a PDO
//! the description puts on a CAN-ID no PDO may use, and [`pdo_mappings`] makes mappable what a
//! description maps by default into a PDO but marks not mappable: what a node reports (its PDOs),
//! it must take back written as read. The values become the entries'
//! defaults ([`SubObject::set_default`]), so that a reset keeps them. Picks:
//!
//! - **A description's own value always wins.** An entry gets a value only where it has none
//!   ([`SubObject::has_value`]); an object that is absent stays absent, except 0x1018, which CiA
//!   301 makes mandatory: it is added with sub-indices 0–4 (the serial number is a DCF's
//!   `LSS_SerialNumber`, else 0). An entry the description has without the sub-index stays
//!   without it.
//! - **Identity**: vendor-ID, product code and revision number of the description's identity
//!   (EDS `[DeviceInfo]` `VendorNumber`, `ProductNumber`, `RevisionNumber`; XDD `DeviceIdentity`;
//!   ESI `Vendor/Id`, `Type@ProductCode`, `Type@RevisionNo`); a number the identity gives as 0
//!   fills nothing (the entry holds 0 already).
//! - **EtherCAT**: the ESI's identity is also the SII's, and a master compares the two (ETG.1000.6:
//!   0x1018 holds the identity of the SII). Where an ESI's 0x1018 object gives another number than
//!   its own `Type` (Ingenia's EVE-XCR-E gives product code 0x32 there, 0x02C31001 in its `Type`),
//!   the identity replaces it, and says so ([`EventKind::Adjusted`]).
//! - **Names** (VISIBLE_STRING entries only; a name longer than the entry holds is left out):
//!   0x1008 manufacturer device name: the product name (EDS `ProductName`, XDD `productName`), for
//!   an ESI its `Type` text (the type name a master shows), else its `Name`; 0x1009 hardware
//!   version: XDD `version versionType="HW"`; 0x100A software version: XDD `"SW"` (else `"FW"`),
//!   for an ESI its revision number as `0x` and eight hex digits (the number EtherCAT devices
//!   carry their firmware revision in).

use crate::device::DeviceDescription;
use crate::dict::{Address, Dictionary};
use crate::event::{Event, EventKind};
use crate::object::{AccessType, Object, ObjectKind, PdoMapping, SubObject};
use crate::types::DataType;
use crate::value::Value;

/// CiA 301 §7.3.5: the CAN-IDs no configurable communication object (PDO, SYNC, TIME, EMCY) may
/// use: NMT (0x000), the ranges of the predefined connection set's node services and those kept
/// free (0x001–0x07F, 0x101–0x180, 0x581–0x5FF, 0x601–0x67F, 0x6E0–0x6FF, 0x701–0x77F,
/// 0x780–0x7FF).
pub const fn restricted_can_id(id: u16) -> bool {
    matches!(
        id,
        0x000
            | 0x001..=0x07F
            | 0x101..=0x180
            | 0x581..=0x5FF
            | 0x601..=0x67F
            | 0x6E0..=0x6FF
            | 0x701..=0x77F
            | 0x780..=0x7FF
    )
}

/// Makes not valid (bit 31 set) every PDO of a CANopen description (RPDO 0x1400–0x15FF, TPDO
/// 0x1800–0x19FF, sub-index 1) whose COB-ID the description gives valid on a restricted CAN-ID
/// ([`restricted_can_id`]): python-canopen's cog.eds gives TPDO 7 the COB-ID 0x00000000, which a
/// node taking it would send on 0x000, as NMT commands. A COB-ID relative to the node-ID is left
/// (it depends on the node-ID), and so is an ESI's (EtherCAT has no CAN-IDs). What changed, one
/// event per entry.
pub fn pdo_cob_ids(desc: &mut DeviceDescription) -> Vec<Event> {
    let mut events = Vec::new();
    if desc.ethercat.is_some() {
        return events;
    }
    let indices: Vec<u16> = desc
        .dictionary
        .objects()
        .map(|o| o.index)
        .filter(|i| matches!(i, 0x1400..=0x15FF | 0x1800..=0x19FF))
        .collect();
    for index in indices {
        let Some(entry) = desc
            .dictionary
            .object_mut(index)
            .and_then(|o| o.subs.get_mut(&1))
            .filter(|e| e.data_type == DataType::Unsigned32)
        else {
            continue;
        };
        let relative =
            entry.default.as_ref().is_some_and(|d| d.plus_node_id) || entry.value_plus_node_id;
        let Some(cob) = entry
            .current()
            .and_then(|v| v.as_i128())
            .and_then(|v| u32::try_from(v).ok())
        else {
            continue;
        };
        if relative || cob & 0x8000_0000 != 0 || !restricted_can_id((cob & 0x7FF) as u16) {
            continue;
        }
        let invalid = cob | 0x8000_0000;
        let (kind, n) = if index < 0x1800 {
            ("RPDO", index - 0x1400 + 1)
        } else {
            ("TPDO", index - 0x1800 + 1)
        };
        if entry.set_default(Value::Uint(u64::from(invalid))) {
            events.push(Event::hex(
                EventKind::Adjusted,
                Address::new(index, 1),
                &format!("COB-ID of {kind} {n}"),
                invalid,
                format!(
                    "the description gives 0x{cob:08X}, a valid PDO on CAN-ID 0x{:03X}, which CiA \
                     301 keeps from PDOs: not valid",
                    cob & 0x7FF
                ),
            ));
        }
    }
    events
}

/// Makes the default PDO mappings of a CANopen description ones its node takes back when a master
/// writes them as read (the CiA 301 procedure, `sdo-tool dump`, then `apply`), as the node's checks
/// of a mapping entry do (an existing entry of the mapped length, mappable in the PDO's direction; a
/// dummy of a basic type; not 0):
///
/// - an entry mapped by default but marked not mappable there (python-canopen's receiver.eds maps
///   0x6040, `PDOMapping=0`, into RPDO 1) becomes mappable in that direction, when its access allows
///   it (written by an RPDO, read by a TPDO): the node runs that mapping;
/// - an entry no PDO of that direction can take (absent, of another length, read-only in an RPDO,
///   write-only in a TPDO, an empty one among the mapped) is left out of the mapping: the others
///   move up and the count is theirs (Schunk's EDS maps the read-only 0x606B and 0x606C into its
///   RPDO 2, which it leaves not valid: 0 mapped).
///
/// An ESI is left alone (its PDOs are its own). What changed, one event per entry.
pub fn pdo_mappings(desc: &mut DeviceDescription) -> Vec<Event> {
    let mut events = Vec::new();
    if desc.ethercat.is_some() {
        return events;
    }
    let maps: Vec<u16> = desc
        .dictionary
        .objects()
        .map(|o| o.index)
        .filter(|i| matches!(i, 0x1600..=0x17FF | 0x1A00..=0x1BFF))
        .collect();
    for map in maps {
        let rpdo = map < 0x1A00;
        let (kind, n) = if rpdo {
            ("RPDO", map - 0x1600 + 1)
        } else {
            ("TPDO", map - 0x1A00 + 1)
        };
        let raw = |dict: &Dictionary, s: u8| {
            dict.entry(map, s)
                .ok()
                .and_then(SubObject::current)
                .and_then(|v| v.as_i128())
                .and_then(|v| u32::try_from(v).ok())
        };
        let count = raw(&desc.dictionary, 0).unwrap_or(0).min(0xFE) as u8;
        let mut kept = Vec::new();
        let mut left_out = Vec::new();
        for s in 1..=count {
            let Some(entry) = raw(&desc.dictionary, s) else {
                continue;
            };
            match mappable(&mut desc.dictionary, entry, rpdo) {
                Ok(made) => {
                    kept.push(entry);
                    if let Some((at, name, both)) = made {
                        let shown = if both {
                            "mappable into RPDOs and TPDOs".to_string()
                        } else {
                            format!("mappable into {kind}s")
                        };
                        events.push(Event {
                            kind: EventKind::Adjusted,
                            address: at,
                            name: format!("PDO mapping of {name}"),
                            value: Value::String(shown.clone()),
                            shown,
                            unit: None,
                            reason: format!(
                                "the description maps it into {kind} {n} by default but marks it \
                                 not mappable there: as the node runs it"
                            ),
                        });
                    }
                }
                Err(why) => left_out.push(format!("0x{entry:08X} ({why})")),
            }
        }
        if left_out.is_empty() {
            continue;
        }
        let why = format!(
            "the description maps {} into {kind} {n}, which no {kind} takes: left out",
            left_out.join(", ")
        );
        // The entries kept move up; those after the new count stay as they are (unmapped).
        for (k, &value) in kept.iter().enumerate() {
            let s = k as u8 + 1;
            if raw(&desc.dictionary, s) == Some(value) {
                continue;
            }
            if let Some(e) = desc
                .dictionary
                .object_mut(map)
                .and_then(|o| o.subs.get_mut(&s))
            {
                if e.set_default(Value::Uint(u64::from(value))) {
                    events.push(Event::hex(
                        EventKind::Adjusted,
                        Address::new(map, s),
                        &format!("mapped object {s} of {kind} {n}"),
                        value,
                        why.clone(),
                    ));
                }
            }
        }
        let number = kept.len() as u32;
        if let Some(e) = desc
            .dictionary
            .object_mut(map)
            .and_then(|o| o.subs.get_mut(&0))
        {
            if e.set_default(Value::Uint(u64::from(number))) {
                events.push(Event {
                    shown: number.to_string(),
                    ..Event::hex(
                        EventKind::Adjusted,
                        Address::new(map, 0),
                        &format!("number of mapped objects of {kind} {n}"),
                        number,
                        why,
                    )
                });
            }
        }
    }
    events
}

/// Whether mapping entry `raw` can go into an RPDO (`rpdo`) or a TPDO, as a node checks it; an entry
/// marked not mappable there whose access allows it is made mappable: `Some((entry, its name, now
/// both ways))`. The reason when it cannot.
#[allow(clippy::type_complexity)]
fn mappable(
    dict: &mut Dictionary,
    raw: u32,
    rpdo: bool,
) -> Result<Option<(Address, String, bool)>, &'static str> {
    let (index, sub, bits) = ((raw >> 16) as u16, (raw >> 8) as u8, raw as u8);
    if raw == 0 {
        return Err("empty");
    }
    if bits == 0 || bits % 8 != 0 {
        return Err("not whole bytes");
    }
    if index < 0x0020 {
        // A dummy: a basic type's index reserves room (CiA 301 §7.4.7.1).
        let size = match index {
            0x0002 | 0x0005 => 8,
            0x0003 | 0x0006 => 16,
            0x0004 | 0x0007 => 32,
            _ => 0,
        };
        return if sub == 0 && size == bits {
            Ok(None)
        } else {
            Err("no dummy")
        };
    }
    let Some(entry) = dict.object_mut(index).and_then(|o| o.subs.get_mut(&sub)) else {
        return Err("no such entry");
    };
    if entry.data_type.byte_size().map(|b| b * 8) != Some(usize::from(bits)) {
        return Err("of another length");
    }
    let (already, allowed, refused) = if rpdo {
        (entry.pdo.rpdo(), entry.access.kind.writable(), "read-only")
    } else {
        (entry.pdo.tpdo(), entry.access.kind.readable(), "write-only")
    };
    if already {
        return Ok(None);
    }
    if !allowed {
        return Err(refused);
    }
    entry.pdo = match (entry.pdo, rpdo) {
        (PdoMapping::None, true) => PdoMapping::Rpdo,
        (PdoMapping::None, false) => PdoMapping::Tpdo,
        _ => PdoMapping::Both,
    };
    Ok(Some((
        Address::new(index, sub),
        entry.name.clone(),
        entry.pdo == PdoMapping::Both,
    )))
}

/// The identity entries: sub-index and name.
const IDENTITY: [(u8, &str); 4] = [
    (1, "vendor-ID"),
    (2, "product code"),
    (3, "revision number"),
    (4, "serial number"),
];

/// Fills 0x1018:01–03 and 0x1008–0x100A of `desc` from its identity where it gives them no value;
/// what it changed, one event per entry. See the [module documentation](self).
pub fn identity_and_names(desc: &mut DeviceDescription) -> Vec<Event> {
    let mut events = Vec::new();
    identity(desc, &mut events);
    names(desc, &mut events);
    events
}

/// 0x1018:01–03 (and the object itself where the description has none).
fn identity(desc: &mut DeviceDescription, events: &mut Vec<Event>) {
    let id = &desc.identity;
    let numbers = [id.vendor_id, id.product_code, id.revision];
    let esi = desc.ethercat.is_some();
    let serial = desc
        .commissioning
        .as_ref()
        .map_or(0, |c| c.lss_serial_number);
    let dict = &mut desc.dictionary;
    if dict.object(0x1018).is_none() {
        add_identity(dict, numbers, serial, events);
        return;
    }
    for ((sub, name), number) in IDENTITY.into_iter().zip(numbers) {
        let Some(entry) = dict
            .object_mut(0x1018)
            .and_then(|o| o.subs.get_mut(&sub))
            .filter(|e| e.data_type == DataType::Unsigned32)
        else {
            continue;
        };
        let (kind, reason) = if !entry.has_value() {
            if number == 0 {
                continue;
            }
            (
                EventKind::Filled,
                format!("the description gives no value: its identity's {name}"),
            )
        } else {
            let given = entry.current().and_then(|v| v.as_i128());
            if !esi || given == Some(i128::from(number)) {
                continue;
            }
            (
                EventKind::Adjusted,
                format!(
                    "the ESI's object gives 0x{:08X}, its Type 0x{number:08X}, which the SII carries \
                     and a master compares with 0x1018",
                    given.unwrap_or(0)
                ),
            )
        };
        if entry.set_default(Value::Uint(u64::from(number))) {
            events.push(Event::hex(
                kind,
                Address::new(0x1018, sub),
                name,
                number,
                reason,
            ));
        }
    }
}

/// Adds 0x1018 (CiA 301 §7.5.2.20: a RECORD of UNSIGNED32, read-only) with `numbers` and `serial`.
fn add_identity(dict: &mut Dictionary, numbers: [u32; 3], serial: u32, events: &mut Vec<Event>) {
    let count = SubObject::new(
        "Highest sub-index supported",
        DataType::Unsigned8,
        AccessType::Ro,
    )
    .with_default(Value::Uint(4));
    let mut object =
        Object::structured(0x1018, "Identity object", ObjectKind::Record).with_sub(0, count);
    let names = [
        "Vendor-ID",
        "Product code",
        "Revision number",
        "Serial number",
    ];
    for (((sub, name), title), number) in IDENTITY
        .into_iter()
        .zip(names)
        .zip(numbers.into_iter().chain([serial]))
    {
        let entry = SubObject::new(title, DataType::Unsigned32, AccessType::Ro)
            .with_default(Value::Uint(u64::from(number)));
        object = object.with_sub(sub, entry);
        let source = match (sub, number) {
            (4, 0) => "no serial number given".to_string(),
            (4, _) => "the DCF's LSS_SerialNumber".to_string(),
            (_, 0) => format!("its identity gives no {name} either"),
            _ => format!("its identity's {name}"),
        };
        events.push(Event::hex(
            EventKind::Filled,
            Address::new(0x1018, sub),
            name,
            number,
            format!("the description has no 0x1018, which CiA 301 makes mandatory: {source}"),
        ));
    }
    dict.insert(object);
}

/// 0x1008–0x100A where they exist as VISIBLE_STRINGs without a value.
fn names(desc: &mut DeviceDescription, events: &mut Vec<Event>) {
    let id = &desc.identity;
    let esi = desc.ethercat.is_some();
    let device_name = if esi && !id.order_code.trim().is_empty() {
        (id.order_code.trim().to_string(), "its Type")
    } else {
        (id.product_name.trim().to_string(), "its product name")
    };
    let software = if esi {
        (format!("0x{:08X}", id.revision), "its revision number")
    } else {
        match (id.software_version.trim(), id.firmware_version.trim()) {
            ("", firmware) => (firmware.to_string(), "its firmware version"),
            (software, _) => (software.to_string(), "its software version"),
        }
    };
    let hardware = (
        id.hardware_version.trim().to_string(),
        "its hardware version",
    );
    for (index, name, (text, source)) in [
        (0x1008u16, "manufacturer device name", device_name),
        (0x1009, "manufacturer hardware version", hardware),
        (0x100A, "manufacturer software version", software),
    ] {
        if text.is_empty() {
            continue;
        }
        let Some(entry) = desc
            .dictionary
            .object_mut(index)
            .and_then(|o| o.subs.get_mut(&0))
            .filter(|e| e.data_type == DataType::VisibleString && !e.has_value())
        else {
            continue;
        };
        if entry.set_default(Value::String(text.clone())) {
            events.push(Event {
                kind: EventKind::Filled,
                address: Address::new(index, 0),
                name: name.to_string(),
                value: Value::String(text.clone()),
                shown: format!("\"{text}\""),
                unit: None,
                reason: format!("the description gives no value: {source}"),
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::{Commissioning, EthercatInfo};
    use crate::object::DefaultValue;

    fn u32_entry(name: &str, default: Option<u32>) -> SubObject {
        let mut e = SubObject::new(name, DataType::Unsigned32, AccessType::Ro);
        if let Some(v) = default {
            e = e.with_default(Value::Uint(u64::from(v)));
        }
        e
    }

    fn with_identity(subs: [Option<u32>; 3]) -> DeviceDescription {
        let mut desc = DeviceDescription::default();
        desc.identity.vendor_id = 0x26C;
        desc.identity.product_code = 0x46;
        desc.identity.revision = 0x08A5_0000;
        let mut o = Object::structured(0x1018, "Identity", ObjectKind::Record).with_sub(
            0,
            SubObject::new("n", DataType::Unsigned8, AccessType::Ro).with_default(Value::Uint(3)),
        );
        for (k, v) in subs.into_iter().enumerate() {
            o = o.with_sub(k as u8 + 1, u32_entry("x", v));
        }
        desc.dictionary.insert(o);
        desc
    }

    fn value(desc: &DeviceDescription, index: u16, sub: u8) -> Value {
        desc.dictionary.read_value(index, sub).unwrap()
    }

    #[test]
    fn identity_entries_without_a_value_take_the_identity() {
        let mut desc = with_identity([None, Some(7), None]);
        let events = identity_and_names(&mut desc);
        let lines: Vec<String> = events.iter().map(Event::line).collect();
        assert_eq!(
            lines,
            [
                "0x1018:01 vendor-ID = 0x0000026C (the description gives no value: its identity's vendor-ID)",
                "0x1018:03 revision number = 0x08A50000 (the description gives no value: its identity's revision number)",
            ]
        );
        assert_eq!(value(&desc, 0x1018, 1), Value::Uint(0x26C));
        // The description's own value wins.
        assert_eq!(value(&desc, 0x1018, 2), Value::Uint(7));
        assert_eq!(value(&desc, 0x1018, 3), Value::Uint(0x08A5_0000));
        // A default: a reset keeps it.
        desc.dictionary.reset(5);
        assert_eq!(value(&desc, 0x1018, 1), Value::Uint(0x26C));
        // Once filled, nothing more to fill.
        assert!(identity_and_names(&mut desc).is_empty());
    }

    #[test]
    fn an_identity_number_of_0_fills_nothing() {
        let mut desc = with_identity([None, None, None]);
        desc.identity.product_code = 0;
        let events = identity_and_names(&mut desc);
        assert_eq!(events.len(), 2);
        assert!(!desc.dictionary.entry(0x1018, 2).unwrap().has_value());
    }

    #[test]
    fn an_absent_identity_object_is_added_with_its_five_entries() {
        let mut desc = DeviceDescription::default();
        desc.identity.vendor_id = 0x555;
        desc.commissioning = Some(Commissioning {
            lss_serial_number: 0x1234,
            ..Commissioning::default()
        });
        let events = identity_and_names(&mut desc);
        let lines: Vec<String> = events.iter().map(Event::line).collect();
        let why = "the description has no 0x1018, which CiA 301 makes mandatory";
        assert_eq!(
            lines,
            [
                format!("0x1018:01 vendor-ID = 0x00000555 ({why}: its identity's vendor-ID)"),
                format!("0x1018:02 product code = 0x00000000 ({why}: its identity gives no product code either)"),
                format!("0x1018:03 revision number = 0x00000000 ({why}: its identity gives no revision number either)"),
                format!("0x1018:04 serial number = 0x00001234 ({why}: the DCF's LSS_SerialNumber)"),
            ]
        );
        let o = desc.dictionary.object(0x1018).unwrap();
        assert_eq!(o.kind, ObjectKind::Record);
        assert_eq!(value(&desc, 0x1018, 0), Value::Uint(4));
        assert_eq!(value(&desc, 0x1018, 1), Value::Uint(0x555));
        assert_eq!(value(&desc, 0x1018, 4), Value::Uint(0x1234));
        assert_eq!(o.sub(1).unwrap().access.kind, AccessType::Ro);
    }

    #[test]
    fn an_esi_identity_replaces_an_object_value_that_differs_from_it() {
        let mut desc = with_identity([Some(0x26C), Some(0x32), None]);
        desc.ethercat = Some(EthercatInfo::default());
        let events = identity_and_names(&mut desc);
        assert_eq!(events[0].kind, EventKind::Adjusted);
        assert_eq!(
            events[0].line(),
            "0x1018:02 product code = 0x00000046 (the ESI's object gives 0x00000032, its Type \
             0x00000046, which the SII carries and a master compares with 0x1018)"
        );
        assert_eq!(events[1].kind, EventKind::Filled);
        assert_eq!(events.len(), 2);
        assert_eq!(value(&desc, 0x1018, 2), Value::Uint(0x46));
        // A CANopen description's own value stands.
        let mut desc = with_identity([Some(0x26C), Some(0x32), Some(1)]);
        assert!(identity_and_names(&mut desc).is_empty());
        assert_eq!(value(&desc, 0x1018, 2), Value::Uint(0x32));
    }

    fn string_var(index: u16, default: Option<&str>) -> Object {
        let mut e = SubObject::new("n", DataType::VisibleString, AccessType::Const);
        if let Some(d) = default {
            e = e.with_default(Value::String(d.into()));
        }
        Object::var(index, e)
    }

    #[test]
    fn names_where_the_objects_exist_without_a_value() {
        let mut desc = DeviceDescription::default();
        desc.identity.product_name = "PD4-EB59CD".into();
        desc.identity.hardware_version = "1.2".into();
        desc.identity.software_version = "FIR-v2213".into();
        desc.dictionary.insert(string_var(0x1008, None));
        desc.dictionary.insert(string_var(0x1009, Some("rev B")));
        desc.dictionary.insert(string_var(0x100A, None));
        let lines: Vec<String> = names_only(&mut desc);
        assert_eq!(
            lines,
            [
                "0x1008 manufacturer device name = \"PD4-EB59CD\" (the description gives no value: its product name)",
                "0x100A manufacturer software version = \"FIR-v2213\" (the description gives no value: its software version)",
            ]
        );
        assert_eq!(value(&desc, 0x1009, 0), Value::String("rev B".into()));
        assert_eq!(
            desc.dictionary.entry(0x1008, 0).unwrap().default,
            Some(DefaultValue::plain(Value::String("PD4-EB59CD".into())))
        );
        // An absent object stays absent; a name the entry cannot hold is left out.
        let mut desc = DeviceDescription::default();
        desc.identity.product_name = "long name".into();
        desc.identity.hardware_version = "1".into();
        let mut short = string_var(0x1008, None);
        short.subs.get_mut(&0).unwrap().bit_size = Some(16);
        desc.dictionary.insert(short);
        assert!(names_only(&mut desc).is_empty());
        assert!(desc.dictionary.object(0x1009).is_none());
    }

    #[test]
    fn a_valid_pdo_on_a_restricted_can_id_is_made_not_valid() {
        let mut desc = DeviceDescription::default();
        let pdo = |index: u16, cob: crate::object::DefaultValue| {
            let mut e = SubObject::new("COB-ID", DataType::Unsigned32, AccessType::Rw);
            e.value = cob.resolve(0).encode(DataType::Unsigned32).unwrap();
            e.default = Some(cob);
            Object::structured(index, "PDO", ObjectKind::Record).with_sub(1, e)
        };
        let plain = |v: u64| DefaultValue::plain(Value::Uint(v));
        desc.dictionary.insert(pdo(0x1806, plain(0)));
        desc.dictionary.insert(pdo(0x1400, plain(0x201)));
        desc.dictionary.insert(pdo(0x1401, plain(0x8000_0000)));
        desc.dictionary.insert(pdo(
            0x1800,
            DefaultValue {
                value: Value::Uint(0x180),
                plus_node_id: true,
            },
        ));
        desc.dictionary.insert(pdo(0x1A00, plain(0)));
        let events = pdo_cob_ids(&mut desc);
        let lines: Vec<String> = events.iter().map(Event::line).collect();
        assert_eq!(
            lines,
            ["0x1806:01 COB-ID of TPDO 7 = 0x80000000 (the description gives 0x00000000, a valid \
              PDO on CAN-ID 0x000, which CiA 301 keeps from PDOs: not valid)"]
        );
        assert_eq!(value(&desc, 0x1806, 1), Value::Uint(0x8000_0000));
        assert_eq!(value(&desc, 0x1400, 1), Value::Uint(0x201));
        assert_eq!(value(&desc, 0x1A00, 1), Value::Uint(0));
        assert!(restricted_can_id(0x180) && !restricted_can_id(0x181) && !restricted_can_id(0x080));
        // An ESI is left alone.
        let mut esi = DeviceDescription {
            ethercat: Some(EthercatInfo::default()),
            ..DeviceDescription::default()
        };
        esi.dictionary.insert(pdo(0x1806, plain(0)));
        assert!(pdo_cob_ids(&mut esi).is_empty());
    }

    #[test]
    fn entries_a_default_mapping_maps_become_mappable_there() {
        let mut desc = DeviceDescription::default();
        let var = |name: &str, ty, access, pdo| {
            let mut e = SubObject::new(name, ty, access);
            e.pdo = pdo;
            e
        };
        use AccessType::{Ro, Rw};
        use DataType::{Integer16 as I16, Unsigned32 as U32, Unsigned8 as U8};
        desc.dictionary.insert(Object::var(
            0x6040,
            var("Process Data 1", I16, Rw, PdoMapping::None),
        ));
        desc.dictionary.insert(Object::var(
            0x6041,
            var("Process Data 2", I16, Rw, PdoMapping::Rpdo),
        ));
        desc.dictionary.insert(Object::var(
            0x6042,
            var("Read only", I16, Ro, PdoMapping::None),
        ));
        desc.dictionary
            .insert(Object::var(0x6043, var("Byte", U8, Rw, PdoMapping::None)));
        let map = |entries: &[u32]| {
            let mut o = Object::structured(0, "map", ObjectKind::Record).with_sub(
                0,
                var("n", U8, Rw, PdoMapping::None).with_default(Value::Uint(entries.len() as u64)),
            );
            for (k, raw) in entries.iter().enumerate() {
                o = o.with_sub(
                    k as u8 + 1,
                    var("e", U32, Rw, PdoMapping::None).with_default(Value::Uint(u64::from(*raw))),
                );
            }
            o
        };
        // RPDO 1: 0x6040 (not mappable), 0x6042 (read-only), a dummy, 0x6043 at a wrong length.
        // TPDO 2: 0x6041 (RPDO only: both then).
        let mut rpdo = map(&[0x6040_0010, 0x6042_0010, 0x0005_0008, 0x6043_0010]);
        rpdo.index = 0x1600;
        desc.dictionary.insert(rpdo);
        let mut tpdo = map(&[0x6041_0010]);
        tpdo.index = 0x1A01;
        desc.dictionary.insert(tpdo);
        let lines: Vec<String> = pdo_mappings(&mut desc).iter().map(Event::line).collect();
        let left = "(the description maps 0x60420010 (read-only), 0x60430010 (of another length) \
                    into RPDO 1, which no RPDO takes: left out)";
        assert_eq!(
            lines,
            [
                "0x6040 PDO mapping of Process Data 1 = mappable into RPDOs (the description maps \
                 it into RPDO 1 by default but marks it not mappable there: as the node runs it)"
                    .to_string(),
                format!("0x1600:02 mapped object 2 of RPDO 1 = 0x00050008 {left}"),
                format!("0x1600 number of mapped objects of RPDO 1 = 2 {left}"),
                "0x6041 PDO mapping of Process Data 2 = mappable into RPDOs and TPDOs (the \
                 description maps it into TPDO 2 by default but marks it not mappable there: as \
                 the node runs it)"
                    .to_string(),
            ]
        );
        let pdo = |i: u16| desc.dictionary.entry(i, 0).unwrap().pdo;
        assert_eq!(pdo(0x6040), PdoMapping::Rpdo);
        assert_eq!(pdo(0x6041), PdoMapping::Both);
        assert_eq!(pdo(0x6042), PdoMapping::None);
        assert_eq!(pdo(0x6043), PdoMapping::None);
        assert_eq!(value(&desc, 0x1600, 0), Value::Uint(2));
        assert_eq!(value(&desc, 0x1600, 1), Value::Uint(0x6040_0010));
        assert_eq!(value(&desc, 0x1600, 2), Value::Uint(0x0005_0008));
        assert_eq!(value(&desc, 0x1600, 4), Value::Uint(0x6043_0010));
        assert!(pdo_mappings(&mut desc).is_empty());
    }

    fn names_only(desc: &mut DeviceDescription) -> Vec<String> {
        let mut events = Vec::new();
        names(desc, &mut events);
        events.iter().map(Event::line).collect()
    }

    #[test]
    fn a_firmware_version_names_the_software_where_there_is_none() {
        let mut desc = DeviceDescription::default();
        desc.identity.firmware_version = "1.3.1.1".into();
        desc.dictionary.insert(string_var(0x100A, None));
        assert_eq!(
            names_only(&mut desc),
            ["0x100A manufacturer software version = \"1.3.1.1\" (the description gives no value: \
              its firmware version)"]
        );
    }

    #[test]
    fn an_esi_names_its_type_and_its_revision() {
        let mut desc = DeviceDescription {
            ethercat: Some(EthercatInfo::default()),
            ..DeviceDescription::default()
        };
        desc.identity.product_name = "EVE-XCR-E CANopen drive".into();
        desc.identity.order_code = "EVE-XCR-E".into();
        desc.identity.revision = 327_700;
        desc.dictionary.insert(string_var(0x1008, None));
        desc.dictionary.insert(string_var(0x100A, None));
        assert_eq!(
            names_only(&mut desc),
            [
                "0x1008 manufacturer device name = \"EVE-XCR-E\" (the description gives no value: its Type)",
                "0x100A manufacturer software version = \"0x00050014\" (the description gives no value: its revision number)",
            ]
        );
    }
}
