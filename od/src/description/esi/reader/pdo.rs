//! What a device's own PDOs say about its dictionary: the mapping direction of the entries they map,
//! and the entries only a PDO describes.

use std::collections::HashSet;

use super::dictionary::type_of_size;
use super::{clip, Ctx, RawDevice};
use crate::device::PdoEntry;
use crate::dict::{Address, Dictionary};
use crate::object::{AccessType, Object, ObjectKind, PdoMapping, SubObject};
use crate::report::SourceMap;
use crate::types::DataType;
use crate::value::Value;

/// `p` with the direction `dir` added.
fn with_direction(p: PdoMapping, dir: PdoMapping) -> PdoMapping {
    match (p, dir) {
        (PdoMapping::None, d) => d,
        (PdoMapping::Rpdo, PdoMapping::Tpdo) | (PdoMapping::Tpdo, PdoMapping::Rpdo) => {
            PdoMapping::Both
        }
        (p, _) => p,
    }
}

fn direction_text(p: PdoMapping) -> &'static str {
    match p {
        PdoMapping::None => "nothing",
        PdoMapping::Rpdo => "R",
        PdoMapping::Tpdo => "T",
        PdoMapping::Both => "RT",
    }
}

/// What the device's own PDOs say about its dictionary. An entry a PDO maps is mappable in the PDO's
/// direction: where the dictionary's `PdoMapping` is missing or says otherwise, the PDOs win (with a
/// warning). An entry the dictionary does not have (a device without a dictionary, or a partial one) is
/// made from the PDO entry that maps it: of the `DataType`'s type (else one of its `BitLen`), read-only,
/// mappable in the PDO's direction, without default; a VAR for sub-index 0, else an entry of a RECORD
/// (type name `DTxxxx`, as the writer names it) whose sub-index 0 counts up to the highest entry. The
/// object is named after the first PDO that maps it. Nothing else is made up.
pub(super) fn apply_pdos(ctx: Ctx, dict: &mut Dictionary, raw: &RawDevice, source: &mut SourceMap) {
    let partial = raw.has_dictionary;
    // Entries and objects made here (a second PDO that maps them only adds its direction).
    let mut made: HashSet<(u16, u8)> = HashSet::new();
    let mut made_objects: HashSet<u16> = HashSet::new();
    // The structure type names in use, once a RECORD is made.
    let mut type_names: Option<HashSet<String>> = None;
    for at in &raw.pdo_entry_offsets {
        let (pdos, dir, kind) = if at.tx {
            (&raw.ecat.tx_pdos, PdoMapping::Tpdo, "TxPdo")
        } else {
            (&raw.ecat.rx_pdos, PdoMapping::Rpdo, "RxPdo")
        };
        let Some(pdo) = pdos.get(at.pdo) else {
            continue;
        };
        let Some(e) = pdo.entries.get(at.n) else {
            continue;
        };
        // Index 0 is a gap (ETG.1000.6); 0x0001–0x0007 are CiA 301 dummy entries (KickCAT's examples map
        // 0x0006:01): padding of a data type's size, no entry of the dictionary.
        if e.index <= 0x0007 {
            continue;
        }
        let address = Address::new(e.index, e.sub);
        let which = || format!("{kind} #x{:04X}", pdo.index);
        if let Some(object) = dict
            .object_mut(e.index)
            .filter(|o| o.subs.contains_key(&e.sub))
        {
            let warn = !made.contains(&(e.index, e.sub));
            mark_mappable(ctx, object, e.sub, dir, warn.then(|| (at.offset, which())));
            continue;
        }
        let exists = dict.object(e.index).map(|o| o.kind.has_subs());
        if exists == Some(false) {
            // A VAR mapped with a sub-index it does not have: validate says so.
            continue;
        }
        let Some((t, bits)) = entry_type(ctx, e, at.offset, &which) else {
            continue;
        };
        let bit_size = if t.is_variable() {
            bits.or(Some(u32::from(e.bit_len)))
        } else {
            t.bit_size()
        };
        let mut sub = SubObject::new(e.name.clone(), t, AccessType::Ro).with_pdo(dir);
        sub.bit_size = bit_size;
        let exists = exists.is_some();
        if e.sub == 0 && !exists {
            dict.insert(Object::var(e.index, sub));
        } else {
            if !exists {
                let mut object = Object::structured(e.index, pdo.name.clone(), ObjectKind::Record);
                // The name the writer gives the structure type (unless the file uses it), so the
                // dictionary reads back the same.
                let used = type_names.get_or_insert_with(|| {
                    raw.data_types
                        .iter()
                        .map(|t| t.name.clone())
                        .chain(dict.objects().filter_map(|o| o.type_name.clone()))
                        .collect()
                });
                object.type_name = Some(structure_type_name(used, e.index));
                dict.insert(object);
                made_objects.insert(e.index);
            }
            let Some(object) = dict.object_mut(e.index) else {
                continue;
            };
            object.subs.insert(e.sub, sub);
            if made_objects.contains(&e.index) {
                let count = object.max_sub();
                let zero = SubObject::new("SubIndex 000", DataType::Unsigned8, AccessType::Ro)
                    .with_default(Value::Uint(u64::from(count)));
                object.subs.insert(0, zero);
            }
        }
        made.insert((e.index, e.sub));
        source.set_entry(e.index, e.sub, ctx.pos(at.offset));
        if partial {
            ctx.warn_about(
                at.offset,
                address,
                format!(
                    "{} maps it, but the dictionary does not have it: made from the PDO ({}, ro, mappable {})",
                    which(),
                    t.esi_name(bit_size.unwrap_or(0)),
                    direction_text(dir)
                ),
            );
        }
    }
}

/// The sub-index `sub` of `object`, mapped by a PDO, made mappable in the direction `dir` (every element,
/// for an ARRAY). With `warn` (where the PDO entry is and which PDO it is in), a changed mapping is warned
/// about.
fn mark_mappable(
    ctx: Ctx,
    object: &mut Object,
    sub: u8,
    dir: PdoMapping,
    warn: Option<(usize, String)>,
) {
    // The elements of an ARRAY share one `SubItem`, and so one `PdoMapping`.
    let array = object.kind == ObjectKind::Array && sub != 0;
    let was = object.subs.get(&sub).map_or(PdoMapping::None, |s| s.pdo);
    let now = with_direction(was, dir);
    for (&s, entry) in object.subs.iter_mut() {
        if s == sub || (array && s != 0) {
            entry.pdo = with_direction(entry.pdo, dir);
        }
    }
    let Some((offset, which)) = warn else {
        return;
    };
    if now != was {
        let flag = if was == PdoMapping::None {
            "is missing".to_string()
        } else {
            format!("says {}", direction_text(was))
        };
        ctx.warn_about(
            offset,
            Address::new(object.index, sub),
            format!(
                "{which} maps it, but its <PdoMapping> {flag}: read as {}",
                direction_text(now)
            ),
        );
    }
}

/// The type of an entry made from the PDO entry `e` (at `offset`, in the PDO `which`): its `DataType`,
/// else a type of its `BitLen` (with a warning); `None` (with a warning) when neither gives one.
fn entry_type(
    ctx: Ctx,
    e: &PdoEntry,
    offset: usize,
    which: &dyn Fn() -> String,
) -> Option<(DataType, Option<u32>)> {
    if let Some(found) = DataType::from_esi_name(&e.data_type) {
        return Some(found);
    }
    let address = Address::new(e.index, e.sub);
    let named = if e.data_type.trim().is_empty() {
        "no <DataType>".to_string()
    } else {
        format!(
            "the <DataType> `{}`, which names no type",
            clip(&e.data_type)
        )
    };
    let Some((t, bits)) = type_of_size(e.bit_len) else {
        ctx.warn_about(
            offset,
            address,
            format!(
                "{} gives it {named} and BitLen 0: no entry is made",
                which()
            ),
        );
        return None;
    };
    let size = bits.or(t.bit_size()).unwrap_or(0);
    ctx.warn_about(
        offset,
        address,
        format!(
            "{} gives it {named}: made {} from its BitLen {}",
            which(),
            t.esi_name(size),
            e.bit_len
        ),
    );
    Some((t, bits))
}

/// The name the writer gives the structure type of the object `index` (`DTxxxx`, else `DTxxxx_n`), one
/// not among `used`; it is added to them.
fn structure_type_name(used: &mut HashSet<String>, index: u16) -> String {
    let base = format!("DT{index:04X}");
    let name = std::iter::once(base.clone())
        .chain((1..=256).map(|n| format!("{base}_{n}")))
        .find(|n| !used.contains(n))
        .unwrap_or(base);
    used.insert(name.clone());
    name
}
