//! The PDOs of a unit as its ESI gives them (ETG.2000 `RxPdo`/`TxPdo`, of the device and of the
//! modules in its slots): the dictionary completed with them at power-on, the rules of an SDO
//! download to the PDO assignment (0x1C12, 0x1C13) and mapping objects (0x1600+, 0x1A00+), and the
//! process images of the present configuration.
//!
//! - **Power-on configuration.** A mapping object the dictionary lacks is added (read-only, the
//!   PDO's entries as its values); one whose sub-index 0 has no default, or the default 0, takes the
//!   PDO's entries. The assignment objects the dictionary lacks are added (read-only); one with no
//!   PDO assigned by default (sub-index 0 without a default, or 0) takes the PDOs whose `Sm`
//!   attribute names SyncManager 2 (RxPDOs) or 3 (TxPDOs), in the ESI's order (ETG.2000: `Sm`, the
//!   SyncManager a PDO is assigned to by default). A default the dictionary gives otherwise stands.
//! - **Downloads** (ETG.1000.6 §5.6.7.4, the PDO configuration of a CoE slave): only in Pre-Op
//!   (0x08000022); the assignment only where `CoE@PdoAssign` allows it, a mapping only where
//!   `CoE@PdoConfig` allows it and the PDO is not `Fixed` (0x06010002); an assignment entry names a
//!   mapping object of its direction the unit has, or 0 (0x06090030); sub-index 0 of an assignment
//!   counts at most its entries (0x06090031), of a mapping at most its entries (0x06040042); a
//!   mapping entry names an existing entry (0x06020000) mappable in the PDO's direction with its
//!   type's bit length, a gap (index 0), or a CiA 301 dummy entry of its size (0x06040041). The
//!   rule that entries are written while sub-index 0 is 0 (0x06010003) is the CoE server's.
//! - **Images.** The process data of SM2 and SM3 are the assigned PDOs' entries one after the
//!   other ([`ProcessImage::from_assignment`]). An assignment that names a mapping the unit lacks or
//!   PDOs the ESI excludes from each other (`Exclude`), or an image longer than the SyncManager's
//!   `MaxSize`, refuses Pre-Op → Safe-Op with 0x0025 (outputs) or 0x0024 (inputs).

use od::abort::AbortCode;
use od::device::{EthercatInfo, Module, Pdo, Slots};
use od::dict::{Address, Dictionary};
use od::hook::ProcessImage;
use od::object::{AccessType, DefaultValue, Object, ObjectKind, SubObject};
use od::types::DataType;
use od::value::Value;

use crate::esc::al::AlStatusCode;

/// The RxPDO assignment (SyncManager 2, outputs).
pub const RX_ASSIGN: u16 = 0x1C12;
/// The TxPDO assignment (SyncManager 3, inputs).
pub const TX_ASSIGN: u16 = 0x1C13;

/// One PDO the unit has: where its mapping object is and what the ESI says of it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PdoDef {
    /// The mapping object (0x1600–0x17FF RxPDO, 0x1A00–0x1BFF TxPDO), moved with its slot.
    pub index: u16,
    /// A TxPDO (inputs).
    pub tx: bool,
    /// The ESI's name.
    pub name: String,
    /// `Fixed`: the mapping cannot be changed.
    pub fixed: bool,
    /// `Sm`: the SyncManager it is assigned to by default.
    pub sm: Option<u8>,
    /// `Exclude`: PDOs that cannot be assigned together with it.
    pub exclude: Vec<u16>,
    /// Its entries as mapping values (`index << 16 | sub << 8 | bits`).
    pub entries: Vec<u32>,
}

/// Whether `index` is a mapping object of the direction (`tx`: 0x1A00–0x1BFF, else 0x1600–0x17FF).
pub fn is_mapping(index: u16, tx: bool) -> bool {
    if tx {
        (0x1A00..=0x1BFF).contains(&index)
    } else {
        (0x1600..=0x17FF).contains(&index)
    }
}

/// The PDOs of a unit and what may change about them.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Pdos {
    /// Every PDO, the device's first, then each slot's module's, in the ESI's order.
    pub defs: Vec<PdoDef>,
    /// `CoE@PdoAssign`: the master may change the assignment.
    pub assign: bool,
    /// `CoE@PdoConfig`: the master may change the mapping of PDOs that are not `Fixed`.
    pub config: bool,
    /// `MaxSize` of the outputs and inputs SyncManagers, in bytes.
    pub max_len: (Option<u16>, Option<u16>),
    /// The numbers of the outputs and inputs SyncManagers (their places among the ESI's `Sm`
    /// elements; 2 and 3 on a device with a mailbox).
    pub sms: (u8, u8),
}

fn pdo_def(pdo: &Pdo, tx: bool, slot: usize, slots: Option<&Slots>, pdo_inc: u32) -> PdoDef {
    let index_inc = slots.and_then(|s| s.slot_index_increment).unwrap_or(0);
    let shift = |index: u16, depends: bool, inc: u32| -> u16 {
        if depends {
            (u32::from(index) + inc * slot as u32) as u16
        } else {
            index
        }
    };
    PdoDef {
        index: shift(pdo.index, pdo.index_depend.slot, pdo_inc),
        tx,
        name: pdo.name.clone(),
        fixed: pdo.fixed,
        sm: pdo.sm,
        exclude: pdo
            .exclude
            .iter()
            .map(|e| shift(e.index, e.depend.slot, pdo_inc))
            .collect(),
        entries: pdo
            .entries
            .iter()
            .map(|e| {
                let index = shift(e.index, e.index_depend.slot, index_inc);
                u32::from(index) << 16 | u32::from(e.sub) << 8 | u32::from(e.bit_len.min(255))
            })
            .collect(),
    }
}

impl Pdos {
    /// The PDOs of a device and of `modules` (slot number, module) in its slots.
    pub fn new(ec: &EthercatInfo, modules: &[(usize, &Module)]) -> Pdos {
        let mut defs = Vec::new();
        for (list, tx) in [(&ec.rx_pdos, false), (&ec.tx_pdos, true)] {
            defs.extend(list.iter().map(|p| pdo_def(p, tx, 0, None, 0)));
        }
        let slots = ec.slots.as_ref();
        for &(slot, module) in modules {
            let pdo_inc = slots
                .and_then(|s| s.slots.get(slot))
                .and_then(|s| s.slot_pdo_increment)
                .or(slots.and_then(|s| s.slot_pdo_increment))
                .unwrap_or(0);
            for (list, tx) in [(&module.rx_pdos, false), (&module.tx_pdos, true)] {
                defs.extend(list.iter().map(|p| pdo_def(p, tx, slot, slots, pdo_inc)));
            }
        }
        // A PDO index given twice (a slot's PDO on a device's own) keeps its first description.
        let mut seen = std::collections::HashSet::new();
        defs.retain(|d| is_mapping(d.index, d.tx) && seen.insert(d.index));
        let coe = ec.mailbox.as_ref().and_then(|m| m.coe);
        let max = |kind: &str| {
            ec.sync_managers
                .iter()
                .find(|s| s.kind == kind)
                .and_then(|s| s.max_size)
        };
        let sm = |kind: &str, or: u8| {
            ec.sync_managers
                .iter()
                .position(|s| s.kind == kind)
                .map_or(or, |n| n.min(255) as u8)
        };
        Pdos {
            defs,
            assign: coe.is_some_and(|c| c.pdo_assign),
            config: coe.is_some_and(|c| c.pdo_config),
            max_len: (max("Outputs"), max("Inputs")),
            sms: (sm("Outputs", 2), sm("Inputs", 3)),
        }
    }

    /// Gives the PDO configuration objects the types ETG.1000.6 §5.6.7.4 gives them where an ESI
    /// writes others (an Elmo ESI has UNSIGNED16 SyncManager types, INTEGER32 mapping entries):
    /// UNSIGNED8 counts, UNSIGNED8 SyncManager types (0x1C00), UNSIGNED16 assignment entries,
    /// UNSIGNED32 mapping entries, each keeping its value. Masters read them with those sizes.
    pub fn standard_types(dict: &mut Dictionary) {
        for object in dict.objects_mut() {
            let entry_type = match object.index {
                0x1C00 => DataType::Unsigned8,
                RX_ASSIGN | TX_ASSIGN => DataType::Unsigned16,
                i if is_mapping(i, false) || is_mapping(i, true) => DataType::Unsigned32,
                _ => continue,
            };
            for (&sub, entry) in object.subs.iter_mut() {
                let want = if sub == 0 {
                    DataType::Unsigned8
                } else {
                    entry_type
                };
                if entry.data_type == want {
                    continue;
                }
                let v = le(&entry.value);
                let default = entry.default.as_ref().and_then(|d| d.value.as_i128());
                entry.data_type = want;
                entry.bit_size = want.bit_size();
                entry.low = None;
                entry.high = None;
                let size = want.byte_size().unwrap_or(1);
                entry.value = v.to_le_bytes()[..size].to_vec();
                entry.default = default.map(|d| DefaultValue::plain(Value::Uint(d as u64)));
            }
        }
    }

    /// The PDO whose mapping object is `index`.
    pub fn def(&self, index: u16) -> Option<&PdoDef> {
        self.defs.iter().find(|d| d.index == index)
    }

    /// Completes `dict` with the power-on PDO configuration (see the module documentation).
    pub fn complete(&self, dict: &mut Dictionary) {
        for d in &self.defs {
            let empty = match dict.object(d.index) {
                None => {
                    dict.insert(mapping_object(d));
                    false
                }
                Some(o) => o.sub(0).is_none_or(no_default),
            };
            if empty && !d.entries.is_empty() {
                set_values(dict, d.index, DataType::Unsigned32, &d.entries);
            }
        }
        for (assign, tx) in [(RX_ASSIGN, false), (TX_ASSIGN, true)] {
            let sm = if tx { self.sms.1 } else { self.sms.0 };
            let defaults: Vec<u32> = self
                .defs
                .iter()
                .filter(|d| d.tx == tx && d.sm == Some(sm))
                .map(|d| u32::from(d.index))
                .collect();
            let mappings = self.defs.iter().filter(|d| d.tx == tx).count();
            let empty = match dict.object(assign) {
                None if mappings > 0 => {
                    dict.insert(assignment_object(assign, mappings.max(defaults.len())));
                    true
                }
                None => false,
                Some(o) => o.sub(0).is_none_or(no_default),
            };
            if empty && !defaults.is_empty() {
                set_values(dict, assign, DataType::Unsigned16, &defaults);
            }
        }
    }

    /// The rules of a download of `data` to `at` beyond the dictionary's (see the module
    /// documentation); `dict` is the unit's dictionary (its structure and PDO flags), `preop` whether
    /// the unit is in Pre-Op.
    pub fn check(
        &self,
        dict: &Dictionary,
        at: Address,
        data: &[u8],
        preop: bool,
    ) -> Result<(), AbortCode> {
        let assignment = matches!(at.index, RX_ASSIGN | TX_ASSIGN);
        let tx_map = is_mapping(at.index, true);
        if !(assignment || tx_map || is_mapping(at.index, false)) {
            return Ok(());
        }
        // ETG.1000.6 §5.6.7.4: the PDO configuration is changed in Pre-Op.
        if !preop {
            return Err(AbortCode::DeviceState);
        }
        let value = le(data);
        let object = dict.object(at.index).ok_or(AbortCode::NoObject)?;
        let entries = object.max_sub();
        if assignment {
            if !self.assign {
                return Err(AbortCode::ReadOnly);
            }
            let tx = at.index == TX_ASSIGN;
            return match at.sub {
                0 if value > u64::from(entries) => Err(AbortCode::ValueTooHigh),
                0 => Ok(()),
                _ if value == 0 => Ok(()),
                _ => {
                    let index = value as u16;
                    let known =
                        value <= 0xFFFF && is_mapping(index, tx) && dict.object(index).is_some();
                    if known {
                        Ok(())
                    } else {
                        Err(AbortCode::InvalidValue)
                    }
                }
            };
        }
        if !self.config || self.def(at.index).is_some_and(|d| d.fixed) {
            return Err(AbortCode::ReadOnly);
        }
        match at.sub {
            0 if value > u64::from(entries) => Err(AbortCode::PdoTooLong),
            0 => Ok(()),
            _ => check_entry(dict, tx_map, value as u32),
        }
    }

    /// The PDOs (mapping object indices) a master assigns, as a configuration tool does from the
    /// ESI, so that the process data carries `entries` of the direction (`tx`: inputs): `Ok(None)`
    /// when the assignment in `dict` already does; else the fewest PDOs that map them, as `dict`
    /// maps them, none excluding another (ETG.2000 `Exclude`), each taking the most entries still
    /// missing (the lower index of equals), in index order. `Err` says why there are none: an entry
    /// no PDO maps, or an assignment the master may not change (`CoE@PdoAssign`).
    pub fn assignment_for(
        &self,
        dict: &Dictionary,
        tx: bool,
        entries: &[Address],
    ) -> Result<Option<Vec<u16>>, String> {
        let assign = if tx { TX_ASSIGN } else { RX_ASSIGN };
        let mapped = |pdo: u16| -> Vec<Address> {
            (1..=uint(dict, pdo, 0).unwrap_or(0).min(255))
                .filter_map(|sub| uint(dict, pdo, sub as u8))
                .map(|v| Address::new((v >> 16) as u16, (v >> 8) as u8))
                .collect()
        };
        let assigned: Vec<u16> = (1..=uint(dict, assign, 0).unwrap_or(0).min(255))
            .filter_map(|sub| uint(dict, assign, sub as u8).map(|v| v as u16))
            .filter(|&i| i != 0)
            .collect();
        let present: Vec<Address> = assigned.iter().flat_map(|&p| mapped(p)).collect();
        if entries.iter().all(|e| present.contains(e)) {
            return Ok(None);
        }
        let direction = if tx { "TxPDO" } else { "RxPDO" };
        if !self.assign {
            return Err(format!(
                "the {direction}s do not map {} and the ESI lets no master change their assignment",
                list(entries.iter().filter(|e| !present.contains(e)))
            ));
        }
        let candidates: Vec<(u16, Vec<Address>)> = self
            .defs
            .iter()
            .filter(|d| d.tx == tx)
            .map(|d| (d.index, mapped(d.index)))
            .collect();
        let mut chosen: Vec<u16> = Vec::new();
        let mut missing: Vec<Address> = entries.to_vec();
        while !missing.is_empty() {
            let excluded = |index: u16| {
                chosen.iter().any(|&c| {
                    self.def(c).is_some_and(|d| d.exclude.contains(&index))
                        || self.def(index).is_some_and(|d| d.exclude.contains(&c))
                })
            };
            let best = candidates
                .iter()
                .filter(|(i, _)| !chosen.contains(i) && !excluded(*i))
                .map(|(i, m)| (*i, missing.iter().filter(|e| m.contains(e)).count()))
                .filter(|(_, n)| *n > 0)
                .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)));
            let Some((index, _)) = best else {
                return Err(format!(
                    "no {direction} the ESI lets a master assign maps {}",
                    list(missing.iter())
                ));
            };
            chosen.push(index);
            let m = mapped(index);
            missing.retain(|e| !m.contains(e));
        }
        chosen.sort_unstable();
        Ok(Some(chosen))
    }

    /// The process images of the assignment in `dict`, or the AL status code Pre-Op → Safe-Op is
    /// refused with.
    pub fn images(&self, dict: &Dictionary) -> Result<(ProcessImage, ProcessImage), AlStatusCode> {
        let outputs = self
            .image(dict, false)
            .ok_or(AlStatusCode::InvalidOutputMapping)?;
        let inputs = self
            .image(dict, true)
            .ok_or(AlStatusCode::InvalidInputMapping)?;
        Ok((outputs, inputs))
    }

    fn image(&self, dict: &Dictionary, tx: bool) -> Option<ProcessImage> {
        let assign = if tx { TX_ASSIGN } else { RX_ASSIGN };
        if dict.object(assign).is_none() {
            return Some(ProcessImage::default());
        }
        let mut assigned: Vec<u16> = (1..=uint(dict, assign, 0)?)
            .map(|sub| uint(dict, assign, sub as u8).map(|v| v as u16))
            .collect::<Option<_>>()?;
        // An entry 0 assigns nothing (ProcessImage::from_assignment skips it).
        assigned.retain(|&i| i != 0);
        if assigned.iter().any(|&i| !is_mapping(i, tx)) {
            return None;
        }
        let excluded = assigned.iter().any(|&a| {
            self.def(a)
                .is_some_and(|d| d.exclude.iter().any(|x| *x != a && assigned.contains(x)))
        });
        if excluded {
            return None;
        }
        let image = ProcessImage::from_assignment(dict, assign).ok()?;
        let max = if tx { self.max_len.1 } else { self.max_len.0 };
        if max.is_some_and(|m| image.len() > usize::from(m)) {
            return None;
        }
        Some(image)
    }
}

/// Entries as a message lists them: `0x607A:00, 0x6064:00`.
fn list<'a>(entries: impl Iterator<Item = &'a Address>) -> String {
    entries
        .map(|e| format!("{:#06X}:{:02X}", e.index, e.sub))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A value of up to 8 little-endian bytes.
fn le(data: &[u8]) -> u64 {
    let mut b = [0u8; 8];
    let n = data.len().min(8);
    b[..n].copy_from_slice(&data[..n]);
    u64::from_le_bytes(b)
}

fn uint(dict: &Dictionary, index: u16, sub: u8) -> Option<u64> {
    dict.read_value(index, sub)
        .ok()?
        .as_i128()
        .and_then(|v| u64::try_from(v).ok())
}

/// An entry whose sub-index 0 the ESI gives no value other than 0.
pub(crate) fn no_default(s: &SubObject) -> bool {
    match &s.default {
        None => true,
        Some(d) => d.value.as_i128() == Some(0),
    }
}

/// One mapping entry written by SDO: a gap, a dummy entry of its size, or an existing entry mappable
/// in this direction with its type's bit length.
fn check_entry(dict: &Dictionary, tx: bool, raw: u32) -> Result<(), AbortCode> {
    let (index, sub, bits) = ((raw >> 16) as u16, (raw >> 8) as u8, raw & 0xFF);
    match index {
        // A gap of any length (ETG.1000.6: index 0 in a mapping).
        0 => Ok(()),
        // CiA 301 dummy entries: the sizes of their types.
        1..=7 => {
            let size = match index {
                1 => 1,
                2 | 5 => 8,
                3 | 6 => 16,
                _ => 32,
            };
            if sub == 0 && bits == size {
                Ok(())
            } else {
                Err(AbortCode::NotMappable)
            }
        }
        _ => {
            let e = dict.entry(index, sub).map_err(|_| AbortCode::NoObject)?;
            let mappable = if tx { e.pdo.tpdo() } else { e.pdo.rpdo() };
            if mappable && e.data_type.bit_size() == Some(bits) {
                Ok(())
            } else {
                Err(AbortCode::NotMappable)
            }
        }
    }
}

/// Sets sub-index 0 of `index` to the number of `values` and sub-indices 1… to them, as defaults and
/// current values, adding the entries the object lacks (read-only, of `data_type`).
pub(crate) fn set_values(dict: &mut Dictionary, index: u16, data_type: DataType, values: &[u32]) {
    let Some(object) = dict.object_mut(index) else {
        return;
    };
    let count = values.len().min(254) as u8;
    let access = object.sub(0).map_or(AccessType::Ro.into(), |s| s.access);
    for (k, &v) in values.iter().take(254).enumerate() {
        let sub = k as u8 + 1;
        let entry = object
            .subs
            .entry(sub)
            .or_insert_with(|| SubObject::new(format!("SubIndex {sub:03}"), data_type, access));
        set_default(entry, u64::from(v));
    }
    let zero = object.subs.entry(0).or_insert_with(|| {
        SubObject::new("Number of entries", DataType::Unsigned8, AccessType::Ro)
    });
    set_default(zero, u64::from(count));
}

/// Makes `v` the entry's default and current value, in the entry's own type and size.
fn set_default(entry: &mut SubObject, v: u64) {
    let value = if entry.data_type.is_signed() {
        Value::Int(v as i64)
    } else {
        Value::Uint(v)
    };
    let size = entry.data_type.byte_size().unwrap_or(4).min(8);
    entry.value = v.to_le_bytes()[..size].to_vec();
    entry.default = Some(DefaultValue::plain(value));
}

/// The mapping object of a PDO the dictionary lacks: read-only, its entries as values.
fn mapping_object(d: &PdoDef) -> Object {
    let count = d.entries.len().min(254);
    let mut o = Object::structured(d.index, d.name.clone(), ObjectKind::Record).with_sub(
        0,
        SubObject::new("Number of entries", DataType::Unsigned8, AccessType::Ro)
            .with_default(Value::Uint(count as u64)),
    );
    for (k, &v) in d.entries.iter().take(count).enumerate() {
        let sub = k as u8 + 1;
        o = o.with_sub(
            sub,
            SubObject::new(
                format!("SubIndex {sub:03}"),
                DataType::Unsigned32,
                AccessType::Ro,
            )
            .with_default(Value::Uint(u64::from(v))),
        );
    }
    o
}

/// An assignment object the dictionary lacks: read-only, `n` entries, none assigned.
fn assignment_object(index: u16, n: usize) -> Object {
    let sm = if index == TX_ASSIGN { 3 } else { 2 };
    let n = n.min(254);
    let mut o = Object::structured(
        index,
        format!("Sync Manager {sm} PDO Assignment"),
        ObjectKind::Array,
    )
    .with_sub(
        0,
        SubObject::new(
            "Number of assigned PDOs",
            DataType::Unsigned8,
            AccessType::Ro,
        )
        .with_default(Value::Uint(0)),
    );
    for k in 1..=n as u8 {
        o = o.with_sub(
            k,
            SubObject::new(
                format!("SubIndex {k:03}"),
                DataType::Unsigned16,
                AccessType::Ro,
            )
            .with_default(Value::Uint(0)),
        );
    }
    o
}
