//! Complete Access (ETG.1000.6 §5.6.2.1.2, §5.6.2.4.2): an ARRAY or RECORD read or written whole, from
//! sub-index 0 or from sub-index 1.
//!
//! The data is the entries in sub-index order, packed as the object's ESI data type lays them out: each
//! entry takes its bit size, bit fields (BOOL, BITn) share bytes, and sub-index 0 (UNSIGNED8) is followed
//! by eight bits of padding so that sub-index 1 starts at bit 16. Only the entries up to the number in
//! sub-index 0 take part. Objects with entries of variable length (strings, DOMAIN) and VAR objects
//! refuse complete access with 0x06010004.

use crate::abort::AbortCode;
use crate::dict::{Address, Dictionary};
use std::time::Instant;

use crate::hook::{get_bits, put_bits, DeviceHook, NoHook};
use crate::object::SubObject;

/// The sub-indices that take part, with each one's bit size, or the refusal.
fn layout(d: &Dictionary, index: u16, from_sub0: bool) -> Result<Vec<(u8, u32)>, AbortCode> {
    let object = d.object(index).ok_or(AbortCode::NoObject)?;
    if !object.kind.has_subs() {
        return Err(AbortCode::CompleteAccessUnsupported);
    }
    let count = d
        .read(index, 0)
        .map_err(|e| e.abort_code())?
        .first()
        .copied()
        .unwrap_or(0);
    let mut out = Vec::new();
    if from_sub0 {
        out.push((0, 16));
    }
    // `range(1..=0)` would panic: an object with no entries has none to take.
    if count > 0 {
        for (&sub, entry) in object.subs.range(1..=count) {
            out.push((sub, bits_of(entry)?));
        }
    }
    Ok(out)
}

fn bits_of(entry: &SubObject) -> Result<u32, AbortCode> {
    entry
        .data_type
        .bit_size()
        .ok_or(AbortCode::CompleteAccessUnsupported)
}

/// Reads object `index` whole, access checked per entry (a write-only entry refuses with 0x06010001).
pub fn upload(d: &Dictionary, index: u16, from_sub0: bool) -> Result<Vec<u8>, AbortCode> {
    upload_through(d, &NoHook, index, from_sub0)
}

/// [`upload`] with the current values of what `hook` owns ([`crate::hook::value`]).
pub fn upload_through(
    d: &Dictionary,
    hook: &dyn DeviceHook,
    index: u16,
    from_sub0: bool,
) -> Result<Vec<u8>, AbortCode> {
    let layout = layout(d, index, from_sub0)?;
    let total: u32 = layout.iter().map(|&(_, b)| b).sum();
    let mut out = vec![0u8; total.div_ceil(8) as usize];
    let mut bit = 0u32;
    let mut buf = [0u8; 8];
    for (sub, bits) in layout {
        d.read(index, sub).map_err(|e| e.abort_code())?;
        let bytes = crate::hook::value(d, hook, Address::new(index, sub), &mut buf);
        let width = if sub == 0 && from_sub0 { 8 } else { bits };
        put_bits(&mut out, bit, width, bytes);
        bit += bits;
    }
    Ok(out)
}

/// Writes object `index` whole. Every entry is checked first (access, type, range); only when all are
/// good is any written, so a refused complete download changes nothing. With `from_sub0` the first byte
/// is the new number of entries: the entries up to it are written, and sub-index 0 last.
pub fn download(
    d: &mut Dictionary,
    index: u16,
    from_sub0: bool,
    data: &[u8],
) -> Result<(), AbortCode> {
    download_planned(d, None, index, from_sub0, data)
}

/// [`download`] made at `now` with `hook` behind the dictionary: the entries it owns are checked by
/// it too ([`DeviceHook::check`]) before anything is written, then given to it in sub-index order.
pub fn download_through(
    d: &mut Dictionary,
    hook: &mut dyn DeviceHook,
    now: Instant,
    index: u16,
    from_sub0: bool,
    data: &[u8],
) -> Result<(), AbortCode> {
    download_planned(d, Some((hook, now)), index, from_sub0, data)
}

/// [`download_through`], or [`download`] without a model.
fn download_planned(
    d: &mut Dictionary,
    mut hook: Option<(&mut dyn DeviceHook, Instant)>,
    index: u16,
    from_sub0: bool,
    data: &[u8],
) -> Result<(), AbortCode> {
    let object = d.object(index).ok_or(AbortCode::NoObject)?;
    if !object.kind.has_subs() {
        return Err(AbortCode::CompleteAccessUnsupported);
    }
    let count = if from_sub0 {
        *data.first().ok_or(AbortCode::LengthTooLow)?
    } else {
        d.entry(index, 0)
            .map_err(|e| e.abort_code())?
            .value
            .first()
            .copied()
            .unwrap_or(0)
    };
    let mut writes: Vec<(u8, Vec<u8>)> = Vec::new();
    let mut bit = if from_sub0 { 16 } else { 0 };
    for sub in 1..=count {
        let entry = d.entry(index, sub).map_err(|e| e.abort_code())?;
        let bits = bits_of(entry)?;
        if (bit + bits).div_ceil(8) as usize > data.len() {
            return Err(AbortCode::LengthTooLow);
        }
        let bytes = get_bits(data, bit, bits);
        writes.push((sub, bytes));
        bit += bits;
    }
    if (data.len() as u32) * 8 >= bit + 8 {
        return Err(AbortCode::LengthTooHigh);
    }
    if from_sub0 {
        if d.object(index).is_some_and(|o| o.max_sub() < count) {
            return Err(AbortCode::ValueTooHigh);
        }
        writes.push((0, vec![count]));
    }
    // Every entry is checked (dictionary, then model) before anything is written: a refusal
    // changes nothing.
    let owned = hook.as_ref().is_some_and(|(h, _)| h.owns(index));
    let mut plan = Vec::with_capacity(writes.len());
    for (sub, bytes) in writes {
        let entry = d.entry(index, sub).map_err(|e| e.abort_code())?;
        if !entry.access.kind.writable() {
            // Sub-index 0 of a fixed structure may be "written" with its own value.
            if sub == 0 && entry.value.as_slice() == bytes.as_slice() {
                continue;
            }
            return Err(AbortCode::ReadOnly);
        }
        d.check(index, sub, &bytes).map_err(|e| e.abort_code())?;
        if let Some((h, _)) = hook.as_ref().filter(|_| owned) {
            h.check(Address::new(index, sub), &bytes)?;
        }
        plan.push((sub, bytes));
    }
    for (sub, bytes) in plan {
        if let Some((h, now)) = hook.as_mut().filter(|_| owned) {
            h.write(Address::new(index, sub), &bytes, *now)?;
        }
        d.write(index, sub, &bytes).map_err(|e| e.abort_code())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::{AccessType, Object, ObjectKind};
    use crate::types::DataType;
    use crate::value::Value;

    fn dict() -> Dictionary {
        let mut d = Dictionary::new();
        d.insert(
            Object::structured(0x1C12, "RxPDO assign", ObjectKind::Array)
                .with_sub(
                    0,
                    SubObject::new("n", DataType::Unsigned8, AccessType::Rw)
                        .with_default(Value::Uint(2)),
                )
                .with_sub(
                    1,
                    SubObject::new("1", DataType::Unsigned16, AccessType::Rw)
                        .with_default(Value::Uint(0x1600)),
                )
                .with_sub(
                    2,
                    SubObject::new("2", DataType::Unsigned16, AccessType::Rw)
                        .with_default(Value::Uint(0x1601)),
                )
                .with_sub(3, SubObject::new("3", DataType::Unsigned16, AccessType::Rw)),
        );
        d.insert(
            Object::structured(0x6000, "Inputs", ObjectKind::Record)
                .with_sub(
                    0,
                    SubObject::new("n", DataType::Unsigned8, AccessType::Ro)
                        .with_default(Value::Uint(3)),
                )
                .with_sub(
                    1,
                    SubObject::new("a", DataType::Bit(1), AccessType::Ro)
                        .with_default(Value::Uint(1)),
                )
                .with_sub(
                    2,
                    SubObject::new("b", DataType::Bit(3), AccessType::Ro)
                        .with_default(Value::Uint(5)),
                )
                .with_sub(
                    3,
                    SubObject::new("c", DataType::Integer16, AccessType::Ro)
                        .with_default(Value::Int(-2)),
                ),
        );
        d.insert(Object::var(
            0x1000,
            SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro),
        ));
        d
    }

    #[test]
    fn upload_from_sub0_pads_sub0_to_16_bits() {
        let d = dict();
        assert_eq!(
            upload(&d, 0x1C12, true).unwrap(),
            [0x02, 0x00, 0x00, 0x16, 0x01, 0x16]
        );
        assert_eq!(upload(&d, 0x1C12, false).unwrap(), [0x00, 0x16, 0x01, 0x16]);
    }

    #[test]
    fn an_object_with_no_entries_uploads_sub0_only() {
        let mut d = dict();
        d.write(0x1C12, 0, &[0]).unwrap();
        assert_eq!(upload(&d, 0x1C12, true).unwrap(), [0x00, 0x00]);
        assert_eq!(upload(&d, 0x1C12, false).unwrap(), [0u8; 0]);
    }

    #[test]
    fn bit_fields_share_bytes() {
        // a = 1 (bit 0), b = 5 (bits 1–3), c = -2 at bits 4–19.
        let d = dict();
        let bytes = upload(&d, 0x6000, false).unwrap();
        assert_eq!(bytes, [0b1110_1011, 0xFF, 0x0F]);
    }

    #[test]
    fn download_writes_all_or_nothing() {
        let mut d = dict();
        download(
            &mut d,
            0x1C12,
            true,
            &[0x03, 0x00, 0x10, 0x16, 0x11, 0x16, 0x12, 0x16],
        )
        .unwrap();
        assert_eq!(d.read(0x1C12, 0).unwrap(), &[3]);
        assert_eq!(d.read(0x1C12, 3).unwrap(), &[0x12, 0x16]);
        let before = d.clone();
        assert_eq!(
            download(&mut d, 0x1C12, true, &[0x03, 0x00, 0x10, 0x16]),
            Err(AbortCode::LengthTooLow)
        );
        assert_eq!(
            download(&mut d, 0x1C12, true, &[0x04, 0x00, 0, 0, 0, 0, 0, 0, 0, 0]),
            Err(AbortCode::NoSubIndex)
        );
        assert_eq!(
            download(
                &mut d,
                0x1C12,
                false,
                &[0x10, 0x16, 0x11, 0x16, 0x12, 0x16, 0x13, 0x16]
            ),
            Err(AbortCode::LengthTooHigh)
        );
        assert_eq!(
            download(&mut d, 0x6000, false, &[0, 0, 0]),
            Err(AbortCode::ReadOnly)
        );
        assert_eq!(d, before);
    }

    /// ETG.1000.6 complete access to a fixed structure: a read-only sub-index 0 may be "written" with
    /// its own value (the subs are written), any other value is refused with 0x06010002 and nothing
    /// changes.
    #[test]
    fn a_read_only_sub0_takes_only_its_own_value() {
        let mut d = dict();
        d.insert(
            Object::structured(0x7000, "Outputs", ObjectKind::Record)
                .with_sub(
                    0,
                    SubObject::new("n", DataType::Unsigned8, AccessType::Ro)
                        .with_default(Value::Uint(2)),
                )
                .with_sub(1, SubObject::new("x", DataType::Unsigned16, AccessType::Rw))
                .with_sub(2, SubObject::new("y", DataType::Unsigned16, AccessType::Rw)),
        );
        download(&mut d, 0x7000, true, &[0x02, 0x00, 0x34, 0x12, 0x78, 0x56]).unwrap();
        assert_eq!(d.read(0x7000, 1).unwrap(), &[0x34, 0x12]);
        assert_eq!(d.read(0x7000, 2).unwrap(), &[0x78, 0x56]);
        let before = d.clone();
        assert_eq!(
            download(&mut d, 0x7000, true, &[0x01, 0x00, 0x11, 0x11]),
            Err(AbortCode::ReadOnly)
        );
        assert_eq!(d, before);
    }

    #[test]
    fn var_objects_refuse_complete_access() {
        let mut d = dict();
        assert_eq!(
            upload(&d, 0x1000, true),
            Err(AbortCode::CompleteAccessUnsupported)
        );
        assert_eq!(
            download(&mut d, 0x1000, true, &[0; 4]),
            Err(AbortCode::CompleteAccessUnsupported)
        );
        assert_eq!(upload(&d, 0x2000, true), Err(AbortCode::NoObject));
    }
}
