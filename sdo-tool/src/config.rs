//! What a configuration file (a DCF) carries and in which order it is written back: the choices of
//! `dump` and `apply`, without any I/O.
//!
//! **Dump.** A DCF carries a node's *parameters*: entries a master writes once to configure it. Not
//! carried:
//! - command objects ([`COMMAND_OBJECTS`]): 0x1003 (writing 0 clears the error history), 0x1010 and
//!   0x1011 (store and restore), 0x1013 (a running time stamp), 0x1F51 (program control);
//! - entries that are not writable (`ro`, `const`): status, identity, measured values;
//! - cyclic outputs: entries written by process data, `rww` in an EDS (CiA 306: read/write on process
//!   output) or mapped into an RPDO (CANopen 0x1600–0x17FF) or RxPDO (EtherCAT, the same objects) as the
//!   node's mapping is read, or as the description gives it where the mapping is not writable;
//! - DOMAINs (a program, a file: `upload` moves them);
//! - write-only entries, which cannot be read back: they are named, so the user knows the DCF lacks
//!   them;
//! - entries the description flags "refuse read on scan" (CiA 306 §4.6.3 `ObjFlags` bit 1, XDD
//!   `objFlags`): not read at all, and named. The flags of an object's section cover each of its
//!   sub-indices ([`od::object::Object::flags_of`]).
//!
//! **Apply** ([`plan`]) writes what the DCF sets in index order, but each PDO with the CiA 301
//! §7.5.2.35–38 procedure: its COB-ID invalid (bit 31 set), its other communication parameters, the
//! mapping's count 0, the mapping entries, the count, then the COB-ID as the DCF gives it. A PDO
//! whose COB-ID the DCF gives read-only cannot be made invalid, so its mapping cannot change: its
//! entries and count go as they are (a node takes them when they are what it has). CoE PDO
//! assignments (0x1C10–0x1C2F, ETG.1020) go the same way: count 0, the entries, the count. Command
//! objects a DCF sets (one made elsewhere) are left out and said so, and so are the entries it flags
//! "refuse write on download" (`ObjFlags` bit 0; a PDO whose COB-ID is so flagged cannot be made
//! invalid either, and its mapping goes as it is).

use std::collections::{BTreeMap, BTreeSet};

use od::abort::AbortCode;
use od::dict::{Address, Dictionary};
use od::object::{AccessType, ObjFlags, SubObject};
use od::types::DataType;
use od::value::Value;

/// Objects that are commands, not parameters, with what writing them does.
pub const COMMAND_OBJECTS: &[(u16, &str)] = &[
    (0x1003, "pre-defined error field: writing 0 clears it"),
    (0x1010, "store parameters: a command"),
    (0x1011, "restore default parameters: a command"),
    (0x1013, "high-resolution time stamp: a running value"),
    (0x1F51, "program control: a command"),
];

/// The command object `index` is, with what writing it does.
pub fn command_object(index: u16) -> Option<&'static str> {
    COMMAND_OBJECTS
        .iter()
        .find(|(i, _)| *i == index)
        .map(|(_, what)| *what)
}

/// Why an entry is not in a DCF, or not written from one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Skip {
    /// A command object (see [`COMMAND_OBJECTS`]).
    Command(&'static str),
    /// Not writable (`ro`, `const`).
    NotWritable,
    /// Written by process data: `rww`, or mapped into the RPDO whose mapping object is given.
    CyclicOutput(Option<u16>),
    /// A DOMAIN.
    Domain,
    /// Write-only: cannot be read back, so a dump cannot capture it.
    WriteOnly,
    /// The description flags it "refuse read on scan" (CiA 306 §4.6.3 `ObjFlags` bit 1): a dump
    /// does not read it.
    RefuseReadOnScan,
    /// The description flags it "refuse write on download" (CiA 306 §4.6.3 `ObjFlags` bit 0):
    /// `apply` does not write it.
    RefuseWriteOnDownload,
}

impl std::fmt::Display for Skip {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Skip::Command(what) => write!(f, "{what}"),
            Skip::NotWritable => write!(f, "not writable"),
            Skip::CyclicOutput(None) => write!(f, "a cyclic output (rww)"),
            Skip::CyclicOutput(Some(m)) => write!(f, "a cyclic output (mapped by 0x{m:04X})"),
            Skip::Domain => write!(f, "a DOMAIN (upload moves it)"),
            Skip::WriteOnly => write!(f, "write-only: cannot be read back, not in the file"),
            Skip::RefuseReadOnScan => write!(f, "ObjFlags bit 1: refuse read on scan"),
            Skip::RefuseWriteOnDownload => write!(f, "ObjFlags bit 0: refuse write on download"),
        }
    }
}

/// Why `entry` at `addr` is no parameter a dump reads, before any mapping is known.
fn not_a_parameter(addr: Address, entry: &SubObject) -> Option<Skip> {
    if let Some(what) = command_object(addr.index) {
        return Some(Skip::Command(what));
    }
    if entry.data_type == DataType::Domain {
        return Some(Skip::Domain);
    }
    match entry.access.kind {
        AccessType::Ro | AccessType::Const => Some(Skip::NotWritable),
        AccessType::Rww => Some(Skip::CyclicOutput(None)),
        AccessType::Wo => Some(Skip::WriteOnly),
        AccessType::Rw | AccessType::Rwr => None,
    }
}

/// The entries of `dict` a dump reads, in index order, and the ones it leaves out with the reason
/// (mapped outputs are found only once the mapping is read: [`mapped_outputs`]). An entry flagged
/// "refuse read on scan" is left out for that, whatever else it is: the description says not to
/// read it.
pub fn dump_entries(dict: &Dictionary) -> (Vec<Address>, Vec<(Address, Skip)>) {
    let mut read = Vec::new();
    let mut skipped = Vec::new();
    for o in dict.objects() {
        for (&sub, e) in &o.subs {
            let addr = Address::new(o.index, sub);
            if o.flags_of(sub).contains(ObjFlags::REFUSE_READ_ON_SCAN) {
                skipped.push((addr, Skip::RefuseReadOnScan));
                continue;
            }
            match not_a_parameter(addr, e) {
                None => read.push(addr),
                Some(why) => skipped.push((addr, why)),
            }
        }
    }
    (read, skipped)
}

/// The write-only entries of `dict` that a read-back register shows, each with that register: a
/// read-only entry of the same type named as the write-only one with `Read` after it. That is how
/// the B&R X67SM2436 manual's 18.5 table ("Reading back the configuration") names them:
/// ConfigOutput03a…08a (the holding, nominal and maximum currents of each motor, write-only) are
/// read back through ConfigOutput03aRead…08aRead. The module's other configuration registers
/// (MaxSpeed01pos, FixedPos01a, GeneralConfig01, …) have no read-back register there, and none
/// here.
pub fn read_backs(dict: &Dictionary) -> BTreeMap<Address, Address> {
    let mut read_only = std::collections::HashMap::new();
    for o in dict.objects() {
        for (&sub, e) in &o.subs {
            if matches!(e.access.kind, AccessType::Ro) {
                read_only.insert(e.name.as_str(), (Address::new(o.index, sub), e.data_type));
            }
        }
    }
    let mut pairs = BTreeMap::new();
    for o in dict.objects() {
        for (&sub, e) in &o.subs {
            if e.access.kind != AccessType::Wo {
                continue;
            }
            if let Some(&(at, ty)) = read_only.get(format!("{}Read", e.name).as_str()) {
                if ty == e.data_type {
                    pairs.insert(Address::new(o.index, sub), at);
                }
            }
        }
    }
    pairs
}

/// The RPDO mapping objects' range (CiA 301; the RxPDO mapping of CoE is the same).
const RPDO_MAPPING: std::ops::RangeInclusive<u16> = 0x1600..=0x17FF;

/// The entries the RPDOs map, each with its mapping object: from `read` (what the node gave) where a
/// mapping entry was read, else from the description's default.
pub fn mapped_outputs(
    dict: &Dictionary,
    read: &BTreeMap<Address, Vec<u8>>,
) -> BTreeMap<Address, u16> {
    let value = |addr: Address| -> Option<u64> {
        match read.get(&addr) {
            Some(bytes) => {
                let mut b = [0u8; 8];
                let n = bytes.len().min(8);
                b[..n].copy_from_slice(&bytes[..n]);
                Some(u64::from_le_bytes(b))
            }
            None => match dict
                .entry(addr.index, addr.sub)
                .ok()?
                .default
                .as_ref()?
                .value
            {
                // Mapping entries are UNSIGNED32.
                Value::Uint(v) => Some(v),
                _ => None,
            },
        }
    };
    let mut mapped = BTreeMap::new();
    for o in dict.objects().filter(|o| RPDO_MAPPING.contains(&o.index)) {
        let count = value(Address::new(o.index, 0)).unwrap_or(0).min(64) as u8;
        for sub in 1..=count {
            if let Some(raw) = value(Address::new(o.index, sub)) {
                let raw = raw as u32;
                let target = Address::new((raw >> 16) as u16, (raw >> 8) as u8);
                // A dummy entry (an index below 0x1000, a data type) maps nothing.
                if target.index >= 0x1000 {
                    mapped.insert(target, o.index);
                }
            }
        }
    }
    mapped
}

/// One write of [`plan`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Write {
    /// The entry.
    pub addr: Address,
    /// The bytes.
    pub bytes: Vec<u8>,
    /// A step of a procedure (a PDO made invalid, a count set to 0), not a value of the file: it is
    /// not read back.
    pub step: Option<&'static str>,
}

/// True when the description flags the entry at `addr` "refuse write on download".
fn refuses_write(dict: &Dictionary, addr: Address) -> bool {
    dict.object(addr.index).is_some_and(|o| {
        o.flags_of(addr.sub)
            .contains(ObjFlags::REFUSE_WRITE_ON_DOWNLOAD)
    })
}

/// The writes that apply `dict`'s set values, in order, and what it sets that is not written (an
/// entry flagged "refuse write on download" for that, whatever else it is).
pub fn plan(dict: &Dictionary) -> (Vec<Write>, Vec<(Address, Skip)>) {
    let mut values: BTreeMap<Address, Vec<u8>> = BTreeMap::new();
    let mut skipped = Vec::new();
    for o in dict.objects() {
        for (&sub, e) in &o.subs {
            if !e.value_set {
                continue;
            }
            let addr = Address::new(o.index, sub);
            if refuses_write(dict, addr) {
                skipped.push((addr, Skip::RefuseWriteOnDownload));
            } else if let Some(what) = command_object(o.index) {
                skipped.push((addr, Skip::Command(what)));
            } else if !e.access.kind.writable() {
                skipped.push((addr, Skip::NotWritable));
            } else {
                values.insert(addr, e.value.clone());
            }
        }
    }
    let mut writes = Vec::new();
    let mut done: BTreeSet<u16> = BTreeSet::new();
    let indices: Vec<u16> = values.keys().map(|a| a.index).collect();
    for index in indices {
        if done.contains(&index) {
            continue;
        }
        match index {
            0x1400..=0x15FF | 0x1800..=0x19FF => {
                // A COB-ID the file gives read-only, or flags "refuse write on download": the PDO
                // cannot be made invalid, so its mapping cannot change (CiA 301 §7.5.2.36): written
                // as it is, without the count 0.
                let fixed = dict
                    .entry(index, 1)
                    .is_ok_and(|e| !e.access.kind.writable())
                    || refuses_write(dict, Address::new(index, 1));
                pdo(&values, index, fixed, &mut writes);
                done.insert(index);
                done.insert(index + 0x200);
            }
            // A mapping whose PDO's communication object the file does not set (one whose object
            // it sets went with that PDO above).
            0x1600..=0x17FF | 0x1A00..=0x1BFF => {
                counted(&values, index, &mut writes);
                done.insert(index);
            }
            0x1C10..=0x1C2F => {
                counted(&values, index, &mut writes);
                done.insert(index);
            }
            _ => {
                writes.extend(
                    values
                        .range(Address::new(index, 0)..=Address::new(index, 0xFF))
                        .map(|(a, b)| Write {
                            addr: *a,
                            bytes: b.clone(),
                            step: None,
                        }),
                );
                done.insert(index);
            }
        }
    }
    (writes, skipped)
}

/// One PDO: the communication object `comm` and its mapping `comm + 0x200`, by CiA 301's procedure;
/// with a `fixed` COB-ID (read-only), the mapping's entries and count as they are.
fn pdo(values: &BTreeMap<Address, Vec<u8>>, comm: u16, fixed: bool, writes: &mut Vec<Write>) {
    let cob = values.get(&Address::new(comm, 1));
    if let Some(cob) = cob.filter(|b| b.len() == 4) {
        let mut invalid = cob.clone();
        invalid[3] |= 0x80;
        writes.push(Write {
            addr: Address::new(comm, 1),
            bytes: invalid,
            step: Some("the PDO made invalid while it changes"),
        });
    }
    for (a, b) in values.range(Address::new(comm, 2)..=Address::new(comm, 0xFF)) {
        writes.push(Write {
            addr: *a,
            bytes: b.clone(),
            step: None,
        });
    }
    if fixed {
        let map = comm + 0x200;
        let count = values.get(&Address::new(map, 0));
        let n = count.and_then(|c| c.first().copied()).unwrap_or(0xFF);
        let entries = values.range(Address::new(map, 1)..=Address::new(map, n.max(1)));
        let count = values.range(Address::new(map, 0)..=Address::new(map, 0));
        writes.extend(entries.chain(count).map(|(a, b)| Write {
            addr: *a,
            bytes: b.clone(),
            step: None,
        }));
    } else {
        counted(values, comm + 0x200, writes);
    }
    if let Some(cob) = cob {
        writes.push(Write {
            addr: Address::new(comm, 1),
            bytes: cob.clone(),
            step: None,
        });
    }
}

/// An object whose sub-index 0 counts its entries (a PDO mapping, a PDO assignment): the count 0,
/// the entries up to the count, then the count. Without a count in the file, its entries as they are.
fn counted(values: &BTreeMap<Address, Vec<u8>>, index: u16, writes: &mut Vec<Write>) {
    let entries = values.range(Address::new(index, 1)..=Address::new(index, 0xFF));
    let Some(count) = values.get(&Address::new(index, 0)) else {
        writes.extend(entries.map(|(a, b)| Write {
            addr: *a,
            bytes: b.clone(),
            step: None,
        }));
        return;
    };
    let n = count.first().copied().unwrap_or(0);
    writes.push(Write {
        addr: Address::new(index, 0),
        bytes: vec![0; count.len().max(1)],
        step: Some("the count 0 while the entries change"),
    });
    writes.extend(entries.filter(|(a, _)| a.sub <= n).map(|(a, b)| Write {
        addr: *a,
        bytes: b.clone(),
        step: None,
    }));
    writes.push(Write {
        addr: Address::new(index, 0),
        bytes: count.clone(),
        step: None,
    });
}

/// Whether a refusal with `code` means the device does not take this entry at all (its access,
/// its existence), rather than this value now: such an entry is skipped with a warning.
pub fn refused_by_design(code: AbortCode) -> bool {
    matches!(
        code.code(),
        0x0601_0000 | 0x0601_0002 | 0x0602_0000 | 0x0609_0011
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use od::object::{Object, ObjectKind};

    fn entry(t: DataType, access: AccessType) -> SubObject {
        SubObject::new("e", t, access)
    }

    /// A dictionary of a TPDO (0x1800 / 0x1A00 with two entries), a CoE PDO assignment (0x1C13), a
    /// parameter, a command object and a read-only entry, each set to `value`.
    fn dcf() -> Dictionary {
        use AccessType::*;
        use DataType::*;
        let mut d = Dictionary::new();
        d.insert(Object::var(0x1017, entry(Unsigned16, Rw)));
        d.insert(Object::var(0x1001, entry(Unsigned8, Ro)));
        d.insert(
            Object::structured(0x1010, "store", ObjectKind::Array)
                .with_sub(0, entry(Unsigned8, Ro))
                .with_sub(1, entry(Unsigned32, Rw)),
        );
        d.insert(
            Object::structured(0x1800, "TPDO 1", ObjectKind::Record)
                .with_sub(0, entry(Unsigned8, Ro))
                .with_sub(1, entry(Unsigned32, Rw))
                .with_sub(2, entry(Unsigned8, Rw)),
        );
        let mut map = Object::structured(0x1A00, "TPDO 1 mapping", ObjectKind::Record)
            .with_sub(0, entry(Unsigned8, Rw));
        for s in 1..=3 {
            map = map.with_sub(s, entry(Unsigned32, Rw));
        }
        d.insert(map);
        d.insert(
            Object::structured(0x1C13, "TxPDO assign", ObjectKind::Array)
                .with_sub(0, entry(Unsigned8, Rw))
                .with_sub(1, entry(Unsigned16, Rw)),
        );
        for (index, sub, bytes) in [
            (0x1017u16, 0u8, vec![0xE8, 0x03]),
            (0x1001, 0, vec![0]),
            (0x1010, 1, b"save".to_vec()),
            (0x1800, 1, 0x185u32.to_le_bytes().to_vec()),
            (0x1800, 2, vec![1]),
            (0x1A00, 0, vec![2]),
            (0x1A00, 1, 0x6041_0010u32.to_le_bytes().to_vec()),
            (0x1A00, 2, 0x6064_0020u32.to_le_bytes().to_vec()),
            // Beyond the count: not written.
            (0x1A00, 3, 0x6077_0010u32.to_le_bytes().to_vec()),
            (0x1C13, 0, vec![1]),
            (0x1C13, 1, 0x1A00u16.to_le_bytes().to_vec()),
        ] {
            let e = d
                .object_mut(index)
                .and_then(|o| o.subs.get_mut(&sub))
                .unwrap();
            e.value = bytes;
            e.value_set = true;
        }
        d
    }

    /// CiA 301's order for a PDO (COB-ID invalid, the other parameters, count 0, the entries up to
    /// the count, the count, the COB-ID), ETG.1020's for an assignment; a command object and a
    /// read-only entry are not written.
    #[test]
    fn a_pdo_is_written_by_the_cia_301_procedure() {
        let (writes, skipped) = plan(&dcf());
        let got: Vec<(u16, u8, Vec<u8>, bool)> = writes
            .iter()
            .map(|w| (w.addr.index, w.addr.sub, w.bytes.clone(), w.step.is_some()))
            .collect();
        assert_eq!(
            got,
            [
                (0x1017, 0, vec![0xE8, 0x03], false),
                (0x1800, 1, vec![0x85, 0x01, 0x00, 0x80], true),
                (0x1800, 2, vec![1], false),
                (0x1A00, 0, vec![0], true),
                (0x1A00, 1, vec![0x10, 0x00, 0x41, 0x60], false),
                (0x1A00, 2, vec![0x20, 0x00, 0x64, 0x60], false),
                (0x1A00, 0, vec![2], false),
                (0x1800, 1, vec![0x85, 0x01, 0x00, 0x00], false),
                (0x1C13, 0, vec![0], true),
                (0x1C13, 1, vec![0x00, 0x1A], false),
                (0x1C13, 0, vec![1], false),
            ]
        );
        assert_eq!(
            skipped,
            [
                (Address::new(0x1001, 0), Skip::NotWritable),
                (
                    Address::new(0x1010, 1),
                    Skip::Command("store parameters: a command")
                )
            ]
        );
    }

    /// A PDO whose COB-ID the file gives read-only (SOMANET's EDS: `ro`, `$NODEID+0x40000180`)
    /// cannot be made invalid: its other parameters, then its mapping's entries up to the count and
    /// the count as they are, no count 0.
    #[test]
    fn a_pdo_with_a_read_only_cob_id_keeps_its_mapping_as_it_is() {
        let mut d = dcf();
        d.object_mut(0x1800)
            .and_then(|o| o.subs.get_mut(&1))
            .unwrap()
            .access = AccessType::Ro.into();
        let (writes, skipped) = plan(&d);
        let got: Vec<(u16, u8, Vec<u8>, bool)> = writes
            .iter()
            .filter(|w| (0x1800..=0x1BFF).contains(&w.addr.index))
            .map(|w| (w.addr.index, w.addr.sub, w.bytes.clone(), w.step.is_some()))
            .collect();
        assert_eq!(
            got,
            [
                (0x1800, 2, vec![1], false),
                (0x1A00, 1, vec![0x10, 0x00, 0x41, 0x60], false),
                (0x1A00, 2, vec![0x20, 0x00, 0x64, 0x60], false),
                (0x1A00, 0, vec![2], false),
            ]
        );
        assert!(skipped.contains(&(Address::new(0x1800, 1), Skip::NotWritable)));
    }

    /// A mapping whose communication object the file does not set goes alone, by its count.
    #[test]
    fn a_mapping_without_its_pdo_goes_by_its_count() {
        let mut d = dcf();
        for sub in 1..=2 {
            d.object_mut(0x1800)
                .and_then(|o| o.subs.get_mut(&sub))
                .unwrap()
                .value_set = false;
        }
        let (writes, _) = plan(&d);
        let pdo: Vec<(u16, u8)> = writes
            .iter()
            .filter(|w| (0x1800..0x1C00).contains(&w.addr.index))
            .map(|w| (w.addr.index, w.addr.sub))
            .collect();
        assert_eq!(pdo, [(0x1A00, 0), (0x1A00, 1), (0x1A00, 2), (0x1A00, 0)]);
    }

    /// Outputs are the entries the RPDO mappings hold: as read where read, else the description's
    /// defaults; a dummy entry (index 0x0005) maps nothing, entries beyond the count neither.
    #[test]
    fn mapped_outputs_follow_the_mapping_read_or_its_defaults() {
        use AccessType::*;
        use DataType::*;
        let mut d = Dictionary::new();
        for (index, entries) in [
            (0x1600u16, [0x2100_0020u32, 0x0005_0008]),
            (0x1601, [0x2200_0010, 0x2201_0010]),
        ] {
            let mut o = Object::structured(index, "map", ObjectKind::Record)
                .with_sub(0, entry(Unsigned8, Ro).with_default(Value::Uint(2)));
            for (k, raw) in entries.iter().enumerate() {
                o = o.with_sub(
                    k as u8 + 1,
                    entry(Unsigned32, Ro).with_default(Value::Uint(u64::from(*raw))),
                );
            }
            d.insert(o);
        }
        let mut read = BTreeMap::new();
        // 0x1601 read: one entry only, and another object than its default.
        read.insert(Address::new(0x1601, 0), vec![1]);
        read.insert(
            Address::new(0x1601, 1),
            0x2300_0108u32.to_le_bytes().to_vec(),
        );
        let got: Vec<(Address, u16)> = mapped_outputs(&d, &read).into_iter().collect();
        assert_eq!(
            got,
            [
                (Address::new(0x2100, 0), 0x1600),
                (Address::new(0x2300, 1), 0x1601)
            ]
        );
    }

    /// Flags `sub` of `index` (`None`: the object's section) of `d` with `bits`.
    fn flag(d: &mut Dictionary, index: u16, sub: Option<u8>, bits: u32) {
        let o = d.object_mut(index).unwrap();
        let flags = Some(ObjFlags::from_bits(bits));
        match sub {
            None => o.flags = flags,
            Some(s) => o.subs.get_mut(&s).unwrap().flags = flags,
        }
    }

    /// "Refuse read on scan" (bit 1) leaves an entry out of a dump, before any other reason (0x1001
    /// is read-only too); bit 0 alone does not. An object's flags cover its entries: 0x1A00 flagged
    /// in its own section, none of its entries is read.
    #[test]
    fn a_dump_reads_no_entry_flagged_refuse_read_on_scan() {
        let mut d = dcf();
        flag(&mut d, 0x1017, None, 0x1);
        flag(&mut d, 0x1001, None, 0x2);
        flag(&mut d, 0x1800, Some(2), 0x3);
        flag(&mut d, 0x1800, Some(1), 0x0);
        flag(&mut d, 0x1A00, None, 0x6);
        let (read, skipped) = dump_entries(&d);
        let a = Address::new;
        assert_eq!(
            read,
            [a(0x1017, 0), a(0x1800, 1), a(0x1C13, 0), a(0x1C13, 1)]
        );
        let refused: Vec<Address> = skipped
            .iter()
            .filter(|(_, why)| *why == Skip::RefuseReadOnScan)
            .map(|(addr, _)| *addr)
            .collect();
        assert_eq!(
            refused,
            [
                a(0x1001, 0),
                a(0x1800, 2),
                a(0x1A00, 0),
                a(0x1A00, 1),
                a(0x1A00, 2),
                a(0x1A00, 3)
            ]
        );
        assert_eq!(
            Skip::RefuseReadOnScan.to_string(),
            "ObjFlags bit 1: refuse read on scan"
        );
    }

    /// "Refuse write on download" (bit 0) leaves a set entry out of `apply`, before any other reason
    /// (0x1010:01 is a command too); bit 1 alone does not. 0x1C13 flagged in its own section: none of
    /// its entries is written.
    #[test]
    fn apply_writes_no_entry_flagged_refuse_write_on_download() {
        let mut d = dcf();
        flag(&mut d, 0x1017, None, 0x2);
        flag(&mut d, 0x1010, Some(1), 0x1);
        flag(&mut d, 0x1800, Some(2), 0x3);
        flag(&mut d, 0x1C13, None, 0x1);
        let (writes, skipped) = plan(&d);
        let got: Vec<(u16, u8)> = writes.iter().map(|w| (w.addr.index, w.addr.sub)).collect();
        assert_eq!(
            got,
            [
                (0x1017, 0),
                (0x1800, 1),
                (0x1A00, 0),
                (0x1A00, 1),
                (0x1A00, 2),
                (0x1A00, 0),
                (0x1800, 1),
            ]
        );
        let a = Address::new;
        assert_eq!(
            skipped,
            [
                (a(0x1001, 0), Skip::NotWritable),
                (a(0x1010, 1), Skip::RefuseWriteOnDownload),
                (a(0x1800, 2), Skip::RefuseWriteOnDownload),
                (a(0x1C13, 0), Skip::RefuseWriteOnDownload),
                (a(0x1C13, 1), Skip::RefuseWriteOnDownload),
            ]
        );
        assert_eq!(
            Skip::RefuseWriteOnDownload.to_string(),
            "ObjFlags bit 0: refuse write on download"
        );
    }

    /// A PDO whose COB-ID is flagged "refuse write on download" cannot be made invalid: its mapping
    /// goes as it is, as with a read-only COB-ID. A PDO whose whole communication object is flagged
    /// is not written at all, and its mapping goes alone, by its count, as that of a PDO the file
    /// does not set.
    #[test]
    fn a_pdo_whose_cob_id_refuses_writes_keeps_its_mapping_as_it_is() {
        for (sub, expected) in [
            (
                Some(1),
                vec![
                    (0x1800, 2, false),
                    (0x1A00, 1, false),
                    (0x1A00, 2, false),
                    (0x1A00, 0, false),
                ],
            ),
            (
                None,
                vec![
                    (0x1A00, 0, true),
                    (0x1A00, 1, false),
                    (0x1A00, 2, false),
                    (0x1A00, 0, false),
                ],
            ),
        ] {
            let mut d = dcf();
            flag(&mut d, 0x1800, sub, 0x1);
            let (writes, _) = plan(&d);
            let got: Vec<(u16, u8, bool)> = writes
                .iter()
                .filter(|w| (0x1800..=0x1BFF).contains(&w.addr.index))
                .map(|w| (w.addr.index, w.addr.sub, w.step.is_some()))
                .collect();
            assert_eq!(got, expected, "{sub:?}");
        }
    }

    /// Only a refusal of the entry as such is "by design".
    #[test]
    fn refusals_by_design() {
        for (code, design) in [
            (0x0601_0000, true),
            (0x0601_0002, true),
            (0x0602_0000, true),
            (0x0609_0011, true),
            (0x0609_0030, false),
            (0x0800_0020, false),
            (0x0604_0043, false),
            (0x0607_0010, false),
        ] {
            assert_eq!(
                refused_by_design(AbortCode::from(code)),
                design,
                "0x{code:08X}"
            );
        }
    }

    /// A write-only entry pairs with the read-only entry named as it with `Read` after it, of its
    /// type; not with one of another type, nor with a writable one, nor a read-only entry with one.
    #[test]
    fn read_back_registers_by_name() {
        use AccessType::*;
        use DataType::*;
        let mut d = Dictionary::new();
        let var = |name: &str, t, access| SubObject::new(name, t, access);
        d.insert(Object::var(0x2110, var("Current", Unsigned8, Wo)));
        d.insert(Object::var(0x2130, var("CurrentRead", Unsigned8, Ro)));
        d.insert(Object::var(0x2114, var("Speed", Unsigned16, Wo)));
        d.insert(Object::var(0x2134, var("SpeedRead", Unsigned8, Ro)));
        d.insert(Object::var(0x2115, var("Acc", Unsigned16, Wo)));
        d.insert(Object::var(0x2135, var("AccRead", Unsigned16, Rw)));
        d.insert(Object::var(0x2116, var("Status", Unsigned16, Ro)));
        d.insert(Object::var(0x2136, var("StatusRead", Unsigned16, Ro)));
        d.insert(Object::var(0x2117, var("Alone", Unsigned16, Wo)));
        let pairs: Vec<(Address, Address)> = read_backs(&d).into_iter().collect();
        assert_eq!(pairs, [(Address::new(0x2110, 0), Address::new(0x2130, 0))]);
    }
}
