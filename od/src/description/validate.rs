//! Consistency checks of a device description beyond what a reader checks: structure of ARRAY/RECORD
//! objects (CiA 301 §7.4.3), defaults against types and limits, PDO mapping entries against the
//! dictionary (CiA 301 §7.5.2.36, ETG.1000.6 §5.6.7.4.7), and the mandatory objects (of a device: a
//! module of an ESI module catalogue has none of its own).
//!
//! Each finding is ranked as [`crate::report`] says: everything here describes a file that masters and
//! configuration tools still load (an entry mapped with fewer bits than its type, a default outside its
//! limits, a missing mandatory object), so it is a warning; only a default that is no value of its type,
//! which no reader produces, is an error.

use crate::device::DeviceDescription;
use crate::dict::{compare, Address, Dictionary};
use crate::object::ObjectKind;
use crate::report::SourceMap;
pub use crate::report::{Finding, Severity};
use crate::types::DataType;
use crate::value::Value;

/// Checks `desc`; findings in index order, errors and warnings mixed, without positions.
pub fn validate(desc: &DeviceDescription) -> Vec<Finding> {
    validate_mapped(desc, &SourceMap::default())
}

/// Checks `desc` as [`validate`] does, taking each finding's position in the file from `map` (what
/// the reader recorded).
pub fn validate_mapped(desc: &DeviceDescription, map: &SourceMap) -> Vec<Finding> {
    let mut c = Checker {
        map,
        out: Vec::new(),
    };
    c.run(desc);
    c.out
}

/// Sub-index 0 of a mapping object that makes it a source-address MPDO; 0xFF makes it a
/// destination-address one (CiA 301 §7.5.2.36).
const MPDO_SAM: u8 = 0xFE;

struct Checker<'m> {
    map: &'m SourceMap,
    out: Vec<Finding>,
}

impl Checker<'_> {
    /// A finding about `address` (positioned at its entry) or about the whole device.
    fn push(&mut self, severity: Severity, address: Option<Address>, message: String) {
        let position = match address {
            Some(a) => self.map.entry(a),
            None => self.map.device(),
        };
        self.out.push(Finding {
            severity,
            position,
            address,
            message,
        });
    }

    fn warn(&mut self, address: Address, message: String) {
        self.push(Severity::Warning, Some(address), message);
    }

    fn run(&mut self, desc: &DeviceDescription) {
        let d = &desc.dictionary;
        // An EtherCAT device without CoE has no object dictionary to speak of; one whose ESI gives no
        // communication objects (no dictionary, or one of the application objects only) leaves the
        // dictionary to SDO Information, which masters read online.
        // A module of a module catalogue is a part of a device, whose dictionary has them.
        let coe = desc.ethercat.as_ref().is_none_or(|e| {
            e.mailbox.as_ref().is_some_and(|m| m.coe.is_some())
                && d.objects().any(|o| (0x1000..=0x1FFF).contains(&o.index))
                && !e.root.is_module()
        });
        for (index, what) in [(0x1000u16, "device type"), (0x1018, "identity")] {
            if coe && d.object(index).is_none() {
                self.push(
                    Severity::Warning,
                    None,
                    format!("object 0x{index:04X} ({what}) is mandatory and missing"),
                );
            }
        }
        for object in d.objects() {
            let zero = Address::new(object.index, 0);
            if object.name.trim().is_empty() {
                self.warn(zero, "object has no name".into());
            }
            if object.kind.has_subs() {
                match object.subs.get(&0) {
                    None => self.warn(
                        zero,
                        format!("{} has no sub-index 0 (number of entries)", object.kind),
                    ),
                    Some(s0) => {
                        // DS301 v4.0's 0x1004 (number of PDOs supported) has an UNSIGNED32 there.
                        let ds301_1004 =
                            object.index == 0x1004 && s0.data_type == DataType::Unsigned32;
                        if !matches!(s0.data_type, DataType::Unsigned8) && !ds301_1004 {
                            self.warn(
                                zero,
                                format!(
                                    "sub-index 0 of {} {} should be UNSIGNED8, is {}",
                                    if object.kind == ObjectKind::Array {
                                        "an"
                                    } else {
                                        "a"
                                    },
                                    object.kind,
                                    s0.data_type
                                ),
                            );
                        }
                        // Only a count the file gives. Some objects count what they hold at run time, not
                        // the entries they have room for: a PDO mapping the entries mapped, the error
                        // history (0x1003) the errors stored, a sync manager's PDO assignment (0x1C10–
                        // 0x1C2F) the PDOs assigned.
                        let given = s0.default.is_some() || s0.value_set;
                        let mapping = (0x1600..=0x17FF).contains(&object.index)
                            || (0x1A00..=0x1BFF).contains(&object.index);
                        let counts_use = mapping
                            || (0x1C10..=0x1C2F).contains(&object.index)
                            || object.index == 0x1003;
                        // A sub-index 0 of another type (DS301's 0x1004) holds no count.
                        let count = given && s0.data_type == DataType::Unsigned8;
                        if let Some(Value::Uint(n)) = s0.current().filter(|_| count) {
                            let highest = u64::from(object.max_sub());
                            if n > highest && !mapping {
                                // An SDO read of the sub-indices sub-index 0 promises is refused (the
                                // mapping check names a mapping's missing entries).
                                self.warn(
                                    zero,
                                    format!(
                                        "sub-index 0 says {n} but the highest sub-index is {highest}: \
                                         {} to {n} are missing",
                                        highest + 1
                                    ),
                                );
                            } else if n < highest
                                && object.kind == ObjectKind::Record
                                && !counts_use
                            {
                                self.warn(
                                    zero,
                                    format!(
                                        "sub-index 0 says {n} but the highest sub-index is {highest}"
                                    ),
                                );
                            }
                        }
                    }
                }
            }
            for (&sub, entry) in &object.subs {
                let at = Address::new(object.index, sub);
                if let (Some(lo), Some(hi)) = (&entry.low, &entry.high) {
                    if compare(lo, hi) == Some(std::cmp::Ordering::Greater) {
                        self.warn(at, format!("low limit {lo} is above high limit {hi}"));
                    }
                }
                if let Some(def) = &entry.default {
                    if def.value.encode(entry.data_type).is_err() {
                        self.push(
                            Severity::Error,
                            Some(at),
                            format!("default {} is not a {}", def.value, entry.data_type),
                        );
                    } else if !def.plus_node_id && !is_nan(&def.value) {
                        // A NaN default (Ingenia's "no value yet") is a value of a REAL; only a write of
                        // one is refused.
                        if let Err(e) = d.check(object.index, sub, &entry.value) {
                            self.warn(at, format!("default value outside the limits: {e}"));
                        }
                    }
                }
            }
            let (rpdo, tpdo) = (0x1600..=0x17FF, 0x1A00..=0x1BFF);
            if rpdo.contains(&object.index) || tpdo.contains(&object.index) {
                self.mapping(
                    d,
                    object.index,
                    rpdo.contains(&object.index),
                    desc.ethercat.is_none(),
                );
            }
        }
        if let Some(ec) = &desc.ethercat {
            for (pdos, receive) in [(&ec.rx_pdos, true), (&ec.tx_pdos, false)] {
                for pdo in pdos {
                    for (n, e) in pdo.entries.iter().enumerate() {
                        // A gap (index 0) or a CiA 301 dummy entry (0x0001–0x0007).
                        if e.index <= 0x0007 {
                            continue;
                        }
                        let position = self.map.pdo_entry(pdo.index, n);
                        // The master makes a virtual PDO's content (DC latch times, windows of ESC
                        // registers): any length of its entries is a reading that fits.
                        let bits = (!pdo.is_virtual).then_some(u32::from(e.bit_len));
                        self.entry(d, pdo.index, (e.index, e.sub), bits, receive, position);
                    }
                }
            }
        }
    }

    /// Checks the PDO mapping object `index` (an RPDO's when `receive`) entry by entry.
    ///
    /// A BOOLEAN mapped with 8 bits is no finding: CANopen maps a BOOLEAN into a byte (CANopenNode's
    /// mappings all do), where EtherCAT maps it into one bit.
    fn mapping(&mut self, d: &Dictionary, index: u16, receive: bool, can: bool) {
        let Some(object) = d.object(index) else {
            return;
        };
        let count = match object.subs.get(&0).and_then(|s| s.current()) {
            Some(Value::Uint(n)) => n as u8,
            _ => return,
        };
        if count >= MPDO_SAM {
            // A multiplexed PDO (CiA 301 §7.5.2.36): 0xFE is a source-address MPDO, whose objects the
            // object scanner list (0x1FA0–0x1FCF) names; 0xFF a destination-address MPDO, whose one entry
            // addresses an object of the consumer. Neither lists entries of this dictionary to check.
            return;
        }
        let mut bits = 0u32;
        for sub in 1..=count {
            let Some(entry) = object.subs.get(&sub) else {
                self.warn(
                    Address::new(index, 0),
                    format!("maps {count} entries but sub-index {sub} is missing"),
                );
                return;
            };
            // A CiA 301 mapping entry is an UNSIGNED32; POWERLINK's are UNSIGNED64 of another layout
            // (EPSG DS 301 §6.4.9.2: length, offset, sub-index, index), not checked here.
            if entry.data_type != DataType::Unsigned32 {
                continue;
            }
            // Only an entry the file gives a value (a profile template's have none).
            if entry.default.is_none() && !entry.value_set {
                continue;
            }
            let Some(Value::Uint(v)) = entry.current() else {
                continue;
            };
            let (mi, ms, len) = ((v >> 16) as u16, (v >> 8) as u8, (v & 0xFF) as u32);
            bits += len;
            if mi == 0 && !can {
                // A gap of `len` bits (ETG.1000.6 §5.6.7.4.7).
                continue;
            }
            if (0x0001..=0x0007).contains(&mi) {
                // A dummy entry (CiA 301 §7.4.7.1): the data type's index and its size.
                let size = DataType::from_index(mi).and_then(|t| t.bit_size());
                if size != Some(len) && !(mi == 0x0001 && len == 8) {
                    self.warn(
                        Address::new(index, sub),
                        format!("dummy entry of type 0x{mi:04X} with {len} bits"),
                    );
                }
                continue;
            }
            let position = self.map.entry(Address::new(index, sub));
            self.entry(d, index, (mi, ms), Some(len), receive, position);
        }
        if can && bits > 64 {
            // CANopen formats also describe CoE devices, whose PDOs are not CAN frames.
            self.warn(
                Address::new(index, 0),
                format!("maps {bits} bits, more than the 64 of a CAN frame (fine over EtherCAT)"),
            );
        }
    }

    /// One mapped entry `(index, sub)` of mapping `pdo` with `bits` bits (`None`: any length fits),
    /// found at `position`.
    fn entry(
        &mut self,
        d: &Dictionary,
        pdo: u16,
        (index, sub): (u16, u8),
        bits: Option<u32>,
        receive: bool,
        position: Option<crate::error::Position>,
    ) {
        let mut bad = |message: String| {
            self.out.push(Finding {
                severity: Severity::Warning,
                position,
                address: Some(Address::new(pdo, 0)),
                message,
            })
        };
        match d.entry(index, sub) {
            Err(_) => bad(format!(
                "maps 0x{index:04X}:{sub:02X}, which does not exist"
            )),
            Ok(e) => {
                if let (Some(size), Some(bits)) = (e.data_type.bit_size(), bits) {
                    if size != bits && !(e.data_type == DataType::Boolean && bits == 8) {
                        bad(format!(
                            "maps 0x{index:04X}:{sub:02X} with {bits} bits, its type {} has {size}",
                            e.data_type
                        ));
                    }
                }
                let ok = if receive { e.pdo.rpdo() } else { e.pdo.tpdo() };
                if !ok {
                    let dir = if receive { "an RPDO" } else { "a TPDO" };
                    bad(format!(
                        "maps 0x{index:04X}:{sub:02X} into {dir}, but it is not mappable that way"
                    ));
                }
            }
        }
    }
}

fn is_nan(v: &Value) -> bool {
    match v {
        Value::Real32(x) => x.is_nan(),
        Value::Real64(x) => x.is_nan(),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::{AccessType, Object, PdoMapping, SubObject};

    fn mapping(index: u16, entries: &[u32]) -> Object {
        let mut o = Object::structured(index, "mapping", ObjectKind::Record).with_sub(
            0,
            SubObject::new("n", DataType::Unsigned8, AccessType::Rw)
                .with_default(Value::Uint(entries.len() as u64)),
        );
        for (i, &e) in entries.iter().enumerate() {
            o = o.with_sub(
                i as u8 + 1,
                SubObject::new("e", DataType::Unsigned32, AccessType::Rw)
                    .with_default(Value::Uint(e as u64)),
            );
        }
        o
    }

    #[test]
    fn mapping_entries_are_checked_against_the_dictionary() {
        let mut desc = DeviceDescription::default();
        let d = &mut desc.dictionary;
        d.insert(Object::var(
            0x1000,
            SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro),
        ));
        d.insert(Object::var(
            0x1018,
            SubObject::new("Identity", DataType::Unsigned32, AccessType::Ro),
        ));
        d.insert(Object::var(
            0x2000,
            SubObject::new("Out", DataType::Unsigned16, AccessType::Rww).with_pdo(PdoMapping::Rpdo),
        ));
        d.insert(Object::var(
            0x2001,
            SubObject::new("In", DataType::Unsigned16, AccessType::Ro).with_pdo(PdoMapping::Tpdo),
        ));
        // A BOOLEAN dummy fills a byte as a mapped BOOLEAN does.
        d.insert(mapping(0x1600, &[0x2000_0010, 0x0005_0008, 0x0001_0008]));
        assert_eq!(validate(&desc), vec![]);
        desc.dictionary.insert(mapping(
            0x1601,
            &[0x2000_0008, 0x2001_0010, 0x3000_0008, 0x0001_0010],
        ));
        let text: Vec<String> = validate(&desc).iter().map(|f| f.to_string()).collect();
        assert_eq!(
            text,
            vec![
                "warning: 0x1601:00: maps 0x2000:00 with 8 bits, its type UNSIGNED16 has 16",
                "warning: 0x1601:00: maps 0x2001:00 into an RPDO, but it is not mappable that way",
                "warning: 0x1601:00: maps 0x3000:00, which does not exist",
                "warning: 0x1601:04: dummy entry of type 0x0001 with 16 bits",
            ]
        );
    }

    #[test]
    fn defaults_outside_limits_are_errors() {
        let mut desc = DeviceDescription::default();
        desc.dictionary.insert(Object::var(
            0x2000,
            SubObject::new("x", DataType::Integer8, AccessType::Rw)
                .with_default(Value::Int(50))
                .with_limits(Some(Value::Int(0)), Some(Value::Int(10))),
        ));
        let text: Vec<String> = validate(&desc).iter().map(|f| f.to_string()).collect();
        assert_eq!(
            text,
            vec![
                "warning: object 0x1000 (device type) is mandatory and missing",
                "warning: object 0x1018 (identity) is mandatory and missing",
                "warning: 0x2000:00: default value outside the limits: 0x2000:00: 50 is above the high limit 10",
            ]
        );
    }

    /// A module of a module catalogue (its mapping objects are in 0x1000–0x1FFF, its mailbox speaks
    /// CoE) lacks 0x1000 and 0x1018 without a finding: they are the device's; as a device it lacks them.
    #[test]
    fn a_module_of_a_catalogue_has_no_mandatory_objects() {
        use crate::device::{CatalogueModule, EsiRoot, EthercatInfo, Mailbox};
        let mut desc = DeviceDescription::default();
        desc.dictionary.insert(mapping(0x1A00, &[]));
        desc.ethercat = Some(EthercatInfo {
            mailbox: Some(Mailbox {
                coe: Some(Default::default()),
                ..Mailbox::default()
            }),
            root: EsiRoot::EtherCatModule(CatalogueModule::default()),
            ..EthercatInfo::default()
        });
        assert_eq!(validate(&desc), vec![]);
        // A device of an EtherCATInfoList lacks them as a device of an EtherCATInfo does.
        desc.ethercat.as_mut().unwrap().root = EsiRoot::EtherCatInfoList(1);
        assert_eq!(validate(&desc).len(), 2);
        desc.ethercat.as_mut().unwrap().root = EsiRoot::EtherCatInfo;
        let text: Vec<String> = validate(&desc).iter().map(|f| f.to_string()).collect();
        assert_eq!(
            text,
            vec![
                "warning: object 0x1000 (device type) is mandatory and missing",
                "warning: object 0x1018 (identity) is mandatory and missing",
            ]
        );
    }

    /// A description with 0x1000 and 0x1018, so that the checks have nothing to say about them.
    fn with_mandatory_objects() -> DeviceDescription {
        let mut desc = DeviceDescription::default();
        for (index, name) in [(0x1000, "Device type"), (0x1018, "Identity")] {
            desc.dictionary.insert(Object::var(
                index,
                SubObject::new(name, DataType::Unsigned32, AccessType::Ro),
            ));
        }
        desc
    }

    /// Entries of a mapping object this check does not read: POWERLINK's UNSIGNED64 ones (another
    /// layout), and one without a value in the file (a profile template's); and a NaN REAL default
    /// (Ingenia's), a value of its type, is no finding either.
    #[test]
    fn entries_without_a_cia_301_mapping_and_nan_defaults_are_no_findings() {
        let mut desc = with_mandatory_objects();
        let d = &mut desc.dictionary;
        d.insert(
            Object::structured(0x1600, "POWERLINK mapping", ObjectKind::Array)
                .with_sub(
                    0,
                    SubObject::new("n", DataType::Unsigned8, AccessType::Rw)
                        .with_default(Value::Uint(2)),
                )
                .with_sub(
                    1,
                    SubObject::new("e", DataType::Unsigned64, AccessType::Rw)
                        .with_default(Value::Uint(0x0010_0000_0060_0001)),
                )
                .with_sub(2, SubObject::new("e", DataType::Unsigned32, AccessType::Rw)),
        );
        d.insert(Object::var(
            0x2000,
            SubObject::new("Gain", DataType::Real32, AccessType::Rw)
                .with_default(Value::Real32(f32::NAN))
                .with_limits(Some(Value::Real32(0.0)), Some(Value::Real32(1.0))),
        ));
        d.insert(Object::var(
            0x2001,
            SubObject::new("Gain", DataType::Real64, AccessType::Rw)
                .with_default(Value::Real64(f64::NAN))
                .with_limits(Some(Value::Real64(0.0)), Some(Value::Real64(1.0))),
        ));
        assert_eq!(validate(&desc), vec![]);
        // The same entry given a value in the file is checked.
        desc.dictionary.insert(mapping(0x1601, &[0x3000_0008]));
        let text: Vec<String> = validate(&desc).iter().map(|f| f.to_string()).collect();
        assert_eq!(
            text,
            vec!["warning: 0x1601:00: maps 0x3000:00, which does not exist"]
        );
        // A number default outside the limits is.
        desc.dictionary
            .object_mut(0x2000)
            .unwrap()
            .subs
            .get_mut(&0)
            .unwrap()
            .default = Some(crate::object::DefaultValue::plain(Value::Real32(2.0)));
        desc.dictionary.insert(mapping(0x1601, &[]));
        let text: Vec<String> = validate(&desc).iter().map(|f| f.to_string()).collect();
        assert_eq!(text.len(), 1, "{text:?}");
        assert!(
            text[0].starts_with("warning: 0x2000:00: default value outside the limits"),
            "{text:?}"
        );
    }

    /// Sub-index 0 of an ARRAY or RECORD is its highest sub-index (CiA 301 §7.4.3): one that promises
    /// more than there is is a warning for both kinds; one that says less, for a RECORD, except where it
    /// counts what the object holds at run time (the error history 0x1003, a PDO mapping, a sync manager's
    /// PDO assignment); a sub-index 0 of another type than UNSIGNED8 holds no count.
    #[test]
    fn sub_index_0_counts_the_entries() {
        fn structured(index: u16, kind: ObjectKind, count: u64, subs: u8) -> Object {
            let mut o = Object::structured(index, "o", kind).with_sub(
                0,
                SubObject::new("n", DataType::Unsigned8, AccessType::Ro)
                    .with_default(Value::Uint(count)),
            );
            for s in 1..=subs {
                o = o.with_sub(s, SubObject::new("e", DataType::Unsigned32, AccessType::Ro));
            }
            o
        }
        let mut desc = with_mandatory_objects();
        let d = &mut desc.dictionary;
        d.insert(structured(0x1003, ObjectKind::Record, 0, 4));
        d.insert(structured(0x1C12, ObjectKind::Array, 1, 4));
        d.insert(structured(0x1C13, ObjectKind::Record, 1, 4));
        d.insert(structured(0x1A00, ObjectKind::Record, 0, 2));
        d.insert(structured(0x2000, ObjectKind::Array, 2, 3));
        d.insert(structured(0x2001, ObjectKind::Array, 3, 2));
        d.insert(structured(0x2002, ObjectKind::Record, 1, 2));
        d.insert(structured(0x2003, ObjectKind::Record, 4, 2));
        d.insert(structured(0x2004, ObjectKind::Record, 2, 2));
        d.insert(structured(0x2005, ObjectKind::Record, 9, 2).with_sub(
            0,
            SubObject::new("n", DataType::Unsigned16, AccessType::Ro).with_default(Value::Uint(9)),
        ));
        // UNSIGNED32 is DS301's type for 0x1004 only.
        d.insert(structured(0x2006, ObjectKind::Array, 9, 2).with_sub(
            0,
            SubObject::new("n", DataType::Unsigned32, AccessType::Ro).with_default(Value::Uint(9)),
        ));
        let text: Vec<String> = validate(&desc).iter().map(|f| f.to_string()).collect();
        assert_eq!(
            text,
            vec![
                "warning: 0x2001:00: sub-index 0 says 3 but the highest sub-index is 2: 3 to 3 are missing",
                "warning: 0x2002:00: sub-index 0 says 1 but the highest sub-index is 2",
                "warning: 0x2003:00: sub-index 0 says 4 but the highest sub-index is 2: 3 to 4 are missing",
                "warning: 0x2005:00: sub-index 0 of a RECORD should be UNSIGNED8, is UNSIGNED16",
                "warning: 0x2006:00: sub-index 0 of an ARRAY should be UNSIGNED8, is UNSIGNED32",
            ]
        );
    }

    /// A CAN mapping of more than 64 bits does not fit a frame (a warning, as CANopen formats describe
    /// CoE devices too); 64 bits do. In an EtherCAT description index 0 is a gap, any other entry is
    /// checked; in a CANopen one 0x0000 is no gap.
    #[test]
    fn mapping_lengths_and_gaps() {
        let mut desc = with_mandatory_objects();
        let d = &mut desc.dictionary;
        d.insert(Object::var(
            0x2000,
            SubObject::new("In", DataType::Unsigned32, AccessType::Ro).with_pdo(PdoMapping::Tpdo),
        ));
        d.insert(mapping(0x1A00, &[0x2000_0020, 0x2000_0020]));
        d.insert(mapping(0x1A01, &[0x2000_0020, 0x2000_0020, 0x0005_0008]));
        d.insert(mapping(0x1A02, &[0x0000_0008]));
        let text: Vec<String> = validate(&desc).iter().map(|f| f.to_string()).collect();
        assert_eq!(
            text,
            vec![
                "warning: 0x1A01:00: maps 72 bits, more than the 64 of a CAN frame (fine over EtherCAT)",
                "warning: 0x1A02:00: maps 0x0000:00, which does not exist",
            ]
        );
        desc.ethercat = Some(Default::default());
        desc.dictionary.insert(mapping(0x1A03, &[0x3000_0008]));
        let text: Vec<String> = validate(&desc).iter().map(|f| f.to_string()).collect();
        assert_eq!(
            text,
            vec!["warning: 0x1A03:00: maps 0x3000:00, which does not exist"]
        );
    }
}
