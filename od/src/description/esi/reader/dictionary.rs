//! Resolution of one device's raw dictionary records: data types, objects, their entries, values and
//! flags, into a [`Dictionary`].

use std::collections::{BTreeMap, HashMap};

use super::pdo::apply_pdos;
use super::{clip, At, Ctx, RawDataType, RawDevice, RawFlags, RawInfo, RawObject, MAX_TYPE_DEPTH};
use crate::device::DeviceDescription;
use crate::dict::Dictionary;
use crate::error::ParseError;
use crate::object::{Access, AccessType, DefaultValue, Object, ObjectKind, SubObject};
use crate::report::SourceMap;
use crate::types::DataType;
use crate::value::{parse_hex_bytes, Value};

/// What a type name stands for.
enum Resolved<'t> {
    /// A basic type, with the bit size its name gives (strings).
    Basic(DataType, Option<u32>),
    /// A structure (`DataType` with `SubItem`s).
    Struct(&'t RawDataType),
    /// A `DataType` with `ArrayInfo`: element type, first sub-index, element count, total bits.
    Array {
        element: DataType,
        element_bits: Option<u32>,
        lbound: u32,
        elements: u32,
        bit_size: Option<u32>,
    },
}

struct Types<'t> {
    by_name: HashMap<&'t str, &'t RawDataType>,
}

impl<'t> Types<'t> {
    fn new(list: &'t [RawDataType]) -> Types<'t> {
        let mut by_name = HashMap::with_capacity(list.len());
        for dt in list {
            by_name.entry(dt.name.as_str()).or_insert(dt);
        }
        Types { by_name }
    }

    fn resolve(&self, name: &str, depth: usize) -> Option<Resolved<'t>> {
        let name = name.trim();
        if let Some((t, bits)) = DataType::from_esi_name(name) {
            return Some(Resolved::Basic(t, bits));
        }
        if depth > MAX_TYPE_DEPTH {
            return None;
        }
        let dt = *self.by_name.get(name)?;
        if !dt.subitems.is_empty() {
            return Some(Resolved::Struct(dt));
        }
        let base = dt.base_type.as_ref()?;
        let base = match self.resolve(&base.text, depth + 1)? {
            Resolved::Basic(t, bits) => (t, bits),
            _ => return None,
        };
        if dt.arrays.is_empty() {
            // An alias or enumeration of a basic type.
            let bits = if base.0.is_variable() {
                dt.bit_size.or(base.1)
            } else {
                None
            };
            return Some(Resolved::Basic(base.0, bits));
        }
        let mut elements: u32 = 1;
        let mut lbound = None;
        for (lb, n) in &dt.arrays {
            elements = elements.checked_mul(n.unwrap_or(0))?;
            lbound.get_or_insert(lb.unwrap_or(0));
        }
        let element_bits = match base.0.bit_size() {
            Some(b) => Some(b),
            None => base.1.or_else(|| dt.bit_size.map(|b| b / elements.max(1))),
        };
        Some(Resolved::Array {
            element: base.0,
            element_bits,
            lbound: lbound.unwrap_or(0),
            elements,
            bit_size: dt.bit_size,
        })
    }
}

/// One entry of a flattened structure.
struct Flat<'t> {
    sub: u8,
    name: String,
    data_type: DataType,
    bit_size: Option<u32>,
    flags: Option<RawFlags>,
    comment: Option<&'t str>,
    /// An array element: its name comes from the object's `Info/SubItem`.
    element: bool,
    /// Where its `SubItem` is.
    offset: usize,
}

pub(super) fn build_device(
    ctx: Ctx,
    raw: RawDevice,
) -> Result<(DeviceDescription, SourceMap), ParseError> {
    let pos = |offset: usize| ctx.pos(offset);
    let mut source = SourceMap::default();
    source.set_device(pos(raw.offset));
    let mut desc = DeviceDescription::default();
    desc.identity.product_code = raw.product_code;
    desc.identity.revision = raw.revision;
    desc.identity.order_code = raw.order_code.clone();
    desc.identity.product_name = raw.name.get().unwrap_or_default().to_string();
    let types = Types::new(&raw.data_types);
    let mut dict = Dictionary::new();
    let mut first_at: BTreeMap<u16, usize> = BTreeMap::new();
    for o in &raw.objects {
        let Some(index) = o.index else {
            return Err(ctx.err(o.offset, "expected an <Index> in <Object>"));
        };
        if let Some(&prev) = first_at.get(&index) {
            let p = ctx.pos(prev);
            return Err(ctx.err(
                o.offset,
                format!(
                    "object #x{index:04X} is defined twice (first at line {})",
                    p.line
                ),
            ));
        }
        first_at.insert(index, o.offset);
        source.set_object(index, pos(o.offset));
        dict.insert(build_object(ctx, &types, o, index, &mut source)?);
    }
    for e in &raw.pdo_entry_offsets {
        let pdos = if e.tx {
            &raw.ecat.tx_pdos
        } else {
            &raw.ecat.rx_pdos
        };
        if let Some(pdo) = pdos.get(e.pdo) {
            source.set_pdo_entry(pdo.index, e.n, pos(e.offset));
        }
    }
    apply_pdos(ctx, &mut dict, &raw, &mut source);
    desc.dictionary = dict;
    let mut ecat = raw.ecat;
    ecat.group_type = raw.group_type;
    desc.ethercat = Some(ecat);
    Ok((desc, source))
}

fn build_object(
    ctx: Ctx,
    types: &Types,
    o: &RawObject,
    index: u16,
    source: &mut SourceMap,
) -> Result<Object, ParseError> {
    let name = o.name.get().unwrap_or_default().to_string();
    let comment = o.comment.get().map(str::to_string);
    let type_at = if o.type_name.text.is_empty() {
        o.offset
    } else {
        o.type_name.offset
    };
    let resolved = types.resolve(&o.type_name.text, 0).ok_or_else(|| {
        ctx.err(
            type_at,
            format!(
                "object #x{index:04X}: expected a basic type name or the name of a <DataType> in <Type>, found `{}`",
                clip(&o.type_name.text)
            ),
        )
    })?;
    let object_access = o.flags.and_then(|f| f.access);
    let var = |data_type: DataType, bit_size: Option<u32>| -> Result<Object, ParseError> {
        let mut sub = SubObject::new(
            name.clone(),
            data_type,
            object_access.unwrap_or(Access::new(AccessType::Ro)),
        );
        sub.bit_size = bit_size;
        sub.pdo = o.flags.and_then(|f| f.pdo).unwrap_or_default();
        sub.description = comment.clone();
        apply_info(ctx, &mut sub, &o.info, index);
        let mut object = Object::var(index, sub);
        object.description = comment.clone();
        Ok(object)
    };
    match resolved {
        Resolved::Basic(t, bits) => {
            let bit_size = if t.is_variable() {
                bits.or(o.bit_size)
            } else {
                t.bit_size()
            };
            var(t, bit_size)
        }
        Resolved::Array {
            element,
            element_bits,
            elements,
            bit_size,
            ..
        } => {
            // An array used as the type of one value: its bytes.
            let bits = bit_size
                .or(o.bit_size)
                .or_else(|| element_bits.and_then(|b| b.checked_mul(elements)));
            let _ = element;
            var(DataType::OctetString, bits)
        }
        Resolved::Struct(dt) => {
            let (flat, is_array) = flatten(ctx, types, dt, index)?;
            let kind = if is_array {
                ObjectKind::Array
            } else {
                ObjectKind::Record
            };
            let mut object = Object::structured(index, name.clone(), kind);
            object.type_name = Some(dt.name.clone());
            object.description = comment
                .clone()
                .or_else(|| dt.comment.get().map(str::to_string));
            // Match Info/SubItems to entries: by position when the Info lists every entry, else by name
            // and then by position.
            let mut assigned: Vec<Option<usize>> = vec![None; flat.len()];
            let complete = o.sub_infos.len() == flat.len();
            for (i, (info_name, _, _)) in o.sub_infos.iter().enumerate() {
                if complete {
                    assigned[i] = Some(i);
                    continue;
                }
                let pick =
                    if flat.get(i).is_some_and(|f| &f.name == info_name) && assigned[i].is_none() {
                        Some(i)
                    } else if let Some(j) = (0..flat.len())
                        .find(|&j| assigned[j].is_none() && &flat[j].name == info_name)
                    {
                        Some(j)
                    } else if i < flat.len() && assigned[i].is_none() {
                        Some(i)
                    } else {
                        None
                    };
                if let Some(j) = pick {
                    assigned[j] = Some(i);
                }
            }
            for (j, f) in flat.iter().enumerate() {
                let flags = f.flags.unwrap_or_default();
                let access = flags
                    .access
                    .or(object_access)
                    .unwrap_or(Access::new(AccessType::Ro));
                let pdo = flags
                    .pdo
                    .or(if f.sub == 0 {
                        None
                    } else {
                        o.flags.and_then(|g| g.pdo)
                    })
                    .unwrap_or_default();
                let info = assigned[j].and_then(|i| o.sub_infos.get(i));
                let name = match (f.element, info) {
                    (true, Some((n, _, _))) => n.clone(),
                    _ => f.name.clone(),
                };
                let mut sub = SubObject::new(name, f.data_type, access);
                sub.bit_size = f.bit_size;
                sub.pdo = pdo;
                sub.description = f.comment.map(str::to_string);
                if let Some((_, info, at)) = info {
                    apply_info(ctx, &mut sub, info, index);
                    source.set_entry(index, f.sub, ctx.pos(*at));
                }
                object.subs.insert(f.sub, sub);
            }
            if !object.subs.contains_key(&0) {
                let count = object.max_sub();
                let sub = SubObject::new("SubIndex 000", DataType::Unsigned8, AccessType::Ro)
                    .with_default(Value::Uint(count as u64));
                object.subs.insert(0, sub);
            }
            Ok(object)
        }
    }
}

/// The entries of a structure type, in order, with array members expanded; and whether it is the ETG
/// array layout.
fn flatten<'t>(
    ctx: Ctx,
    types: &Types<'t>,
    dt: &'t RawDataType,
    index: u16,
) -> Result<(Vec<Flat<'t>>, bool), ParseError> {
    let mut out: Vec<Flat<'t>> = Vec::with_capacity(dt.subitems.len());
    let mut next: u32 = 0;
    let mut arrays = 0usize;
    let mut others = 0usize;
    for si in &dt.subitems {
        let at = if si.type_name.text.is_empty() {
            si.offset
        } else {
            si.type_name.offset
        };
        let resolved = types.resolve(&si.type_name.text, 0).ok_or_else(|| {
            ctx.err(
                at,
                format!(
                    "<DataType> {}: expected a basic type name or the name of an array <DataType> in <SubItem>/<Type>, found `{}`",
                    dt.name,
                    clip(&si.type_name.text)
                ),
            )
        })?;
        let comment = si.comment.get();
        match resolved {
            Resolved::Basic(t, bits) => {
                let sub = si.sub_idx.map_or(next, u32::from);
                let sub = u8::try_from(sub).map_err(|_| {
                    ctx.err(si.offset, format!("<DataType> {}: more than 256 entries", dt.name))
                })?;
                let bit_size = if t.is_variable() {
                    bits.or(si.bit_size)
                } else {
                    t.bit_size()
                };
                if sub != 0 {
                    others += 1;
                }
                out.push(Flat {
                    sub,
                    name: si.name.clone(),
                    data_type: t,
                    bit_size,
                    flags: si.flags,
                    comment,
                    element: false,
                    offset: si.offset,
                });
                next = u32::from(sub) + 1;
            }
            Resolved::Array {
                element,
                element_bits,
                lbound,
                elements,
                bit_size,
            } => {
                if let Some(sub) = si.sub_idx {
                    // An entry whose value is a whole array: its bytes.
                    out.push(Flat {
                        sub,
                        name: si.name.clone(),
                        data_type: DataType::OctetString,
                        bit_size: si.bit_size.or(bit_size),
                        flags: si.flags,
                        comment,
                        element: false,
                        offset: si.offset,
                    });
                    others += 1;
                    next = u32::from(sub) + 1;
                    continue;
                }
                let first = lbound.max(next);
                let last = first
                    .checked_add(elements)
                    .and_then(|e| e.checked_sub(1))
                    .filter(|&l| l <= 255 || elements == 0);
                let Some(last) = last else {
                    return Err(ctx.err(
                        at,
                        format!(
                            "object #x{index:04X}: the array type `{}` has {elements} elements from sub-index {first}; sub-indices end at 255",
                            clip(&si.type_name.text)
                        ),
                    ));
                };
                let element_bits = if element.is_variable() {
                    element_bits
                } else {
                    element.bit_size()
                };
                for s in first..first + elements {
                    let sub = u8::try_from(s).unwrap_or(u8::MAX);
                    out.push(Flat {
                        sub,
                        name: format!("SubIndex {sub:03}"),
                        data_type: element,
                        bit_size: element_bits,
                        flags: si.flags,
                        comment,
                        element: true,
                        offset: si.offset,
                    });
                }
                arrays += 1;
                next = last + 1;
            }
            Resolved::Struct(_) => {
                return Err(ctx.err(
                    at,
                    format!(
                        "<DataType> {}: the entry `{}` has the structure type `{}`; CoE entries are basic types or arrays of them",
                        dt.name,
                        si.name,
                        clip(&si.type_name.text)
                    ),
                ))
            }
        }
    }
    // Duplicate sub-indices: the later entry would silently replace the earlier.
    let mut seen = [false; 256];
    for f in &out {
        let s = usize::from(f.sub);
        if seen[s] {
            return Err(ctx.err(
                f.offset,
                format!(
                    "<DataType> {}: sub-index {} is defined twice",
                    dt.name, f.sub
                ),
            ));
        }
        seen[s] = true;
    }
    Ok((out, arrays == 1 && others == 0))
}

/// Sets default, limits and current value of `sub` from an `Info` element.
fn apply_info(ctx: Ctx, sub: &mut SubObject, info: &RawInfo, index: u16) {
    let t = sub.data_type;
    let read = if let Some((bytes, at)) = &info.default_data {
        Some((decode_data(ctx, t, bytes, *at, index, "DefaultData"), *at))
    } else if let Some(v) = &info.default_value {
        Some((value_text(ctx, t, v, index, "DefaultValue"), v.offset))
    } else {
        info.default_string.as_ref().map(|s| {
            let value = match t {
                DataType::VisibleString => Ok(Value::String(s.text.clone())),
                DataType::UnicodeString => Ok(Value::Unicode(s.text.encode_utf16().collect())),
                DataType::OctetString | DataType::Domain => {
                    Ok(Value::Bytes(s.text.as_bytes().to_vec()))
                }
                _ => value_text(ctx, t, s, index, "DefaultString"),
            };
            (value, s.offset)
        })
    };
    // A default that is no value of the type (a number beyond it, no bytes for a number) leaves the
    // entry without a default, as python-canopen and the EDS and XDD readers take theirs: dropped.
    let default = match read {
        Some((Ok(v), _)) => Some(v),
        Some((Err(e), at)) => {
            ctx.warn(at, format!("{}; the default is dropped", e.message));
            None
        }
        None => None,
    };
    // A limit that is no value of the type (vendors copy limits between objects of different types)
    // limits nothing a master could write: it is dropped.
    let limit = |data: &Option<(Vec<u8>, usize)>, value: &Option<At>, what: [&str; 2]| {
        let read = match (data, value) {
            (Some((bytes, at)), _) => decode_data(ctx, t, bytes, *at, index, what[0]),
            (None, Some(v)) => value_text(ctx, t, v, index, what[1]),
            (None, None) => return None,
        };
        match read {
            Ok(v) => Some(v),
            Err(e) => {
                let at = data
                    .as_ref()
                    .map_or_else(|| value.as_ref().map_or(0, |v| v.offset), |d| d.1);
                ctx.warn(at, format!("{}; the limit is dropped", e.message));
                None
            }
        }
    };
    sub.unit = info.unit;
    sub.low = limit(&info.min_data, &info.min_value, ["MinData", "MinValue"]);
    sub.high = limit(&info.max_data, &info.max_value, ["MaxData", "MaxValue"]);
    if let Some(v) = &default {
        // A string whose type is shorter than its default (`STRING(0)` with a default): the default
        // shows the size.
        if let (Some(bits), Ok(bytes)) = (sub.bit_size, v.encode(t)) {
            let unit = if t == DataType::UnicodeString { 16 } else { 8 };
            let needed = u32::try_from(bytes.len())
                .unwrap_or(u32::MAX / 8)
                .saturating_mul(8)
                .div_ceil(unit)
                * unit;
            if t.is_variable() && needed > bits {
                let at = info
                    .default_data
                    .as_ref()
                    .map(|d| d.1)
                    .or(info.default_value.as_ref().map(|v| v.offset))
                    .or(info.default_string.as_ref().map(|v| v.offset))
                    .unwrap_or(0);
                ctx.warn(
                    at,
                    format!(
                        "object #x{index:04X}: the default takes {needed} bits but the type gives {bits}; the size is the default's"
                    ),
                );
                sub.bit_size = Some(needed);
            }
        }
    }
    if let Some(v) = default {
        if let Ok(bytes) = v.encode(t) {
            sub.value = bytes;
        }
        sub.default = Some(DefaultValue::plain(v));
    }
}

/// A value from little-endian hexBinary bytes. Real files give fixed-size values in fewer bytes (`00` for
/// a UINT) or with zero bytes beyond the type's size; both are read as the number they spell (the missing
/// high bytes are zero). Nonzero bytes beyond the type are an error.
fn decode_data(
    ctx: Ctx,
    t: DataType,
    bytes: &[u8],
    at: usize,
    index: u16,
    what: &str,
) -> Result<Value, ParseError> {
    let mut fitted;
    let mut bytes = bytes;
    if let Some(size) = t.byte_size() {
        if bytes.len() < size && !bytes.is_empty() {
            fitted = bytes.to_vec();
            fitted.resize(size, 0);
            bytes = &fitted;
        } else if bytes.len() > size
            && (what == "DefaultData" || bytes.iter().skip(size).all(|&b| b == 0))
        {
            // Data longer than its type: zeros beyond are no value; a default with more (TwinCAT
            // loads it) is its first bytes, little-endian the value's own, and said. A limit with
            // more stays refused (and is dropped).
            if bytes.iter().skip(size).any(|&b| b != 0) {
                ctx.warn(
                    at,
                    format!(
                        "object #x{index:04X}: <{what}> has {} bytes for a {} of {size}; the first \
                         {size} read",
                        bytes.len(),
                        t.esi_base_name()
                    ),
                );
            }
            fitted = bytes.to_vec();
            fitted.truncate(size);
            bytes = &fitted;
        }
    }
    Value::decode(t, bytes).map_err(|e| {
        ctx.err(
            at,
            format!(
                "object #x{index:04X}: <{what}> is not a {}: {e}",
                t.esi_base_name()
            ),
        )
    })
}

/// A value from a number (`#x…` or decimal) or, for strings, text.
fn value_text(ctx: Ctx, t: DataType, v: &At, index: u16, what: &str) -> Result<Value, ParseError> {
    let text = v.text.trim();
    let bad = |reason: &str| {
        ctx.err(
            v.offset,
            format!(
                "object #x{index:04X}: expected {reason} in <{what}>, found `{}`",
                clip(text)
            ),
        )
    };
    match t {
        DataType::VisibleString => Ok(Value::String(v.text.clone())),
        DataType::UnicodeString => Ok(Value::Unicode(v.text.encode_utf16().collect())),
        DataType::OctetString | DataType::Domain => parse_hex_bytes(text)
            .map(Value::Bytes)
            .ok_or_else(|| bad("hexadecimal bytes")),
        DataType::Real32 | DataType::Real64 => {
            if let Some(bits) = text.strip_prefix("#x").or_else(|| text.strip_prefix("#X")) {
                let n = u64::from_str_radix(bits, 16).map_err(|_| bad("a number"))?;
                return Ok(if t == DataType::Real32 {
                    Value::Real32(f32::from_bits(
                        u32::try_from(n).map_err(|_| bad("a 32-bit pattern"))?,
                    ))
                } else {
                    Value::Real64(f64::from_bits(n))
                });
            }
            Value::parse_text(t, text).map_err(|_| bad("a decimal number"))
        }
        DataType::TimeOfDay | DataType::TimeDifference => {
            let n = ctx
                .parse_number(text, v.offset, &format!("<{what}>"))
                .ok_or_else(|| bad("a number"))?;
            let bytes = u64::try_from(n)
                .ok()
                .filter(|&n| n < (1u64 << 48))
                .ok_or_else(|| bad("a 48-bit number"))?
                .to_le_bytes();
            Value::decode(t, &bytes[..6]).map_err(|_| bad("a time"))
        }
        DataType::Boolean => match text.to_ascii_lowercase().as_str() {
            "true" => Ok(Value::Bool(true)),
            "false" => Ok(Value::Bool(false)),
            _ => match ctx.parse_number(text, v.offset, &format!("<{what}>")) {
                Some(0) => Ok(Value::Bool(false)),
                Some(1) => Ok(Value::Bool(true)),
                _ => Err(bad("0, 1, true or false")),
            },
        },
        _ => {
            let n = ctx
                .parse_number(text, v.offset, &format!("<{what}>"))
                .ok_or_else(|| bad("a number like #x1A00 or 6656"))?;
            let (lo, hi) = t.integer_range().ok_or_else(|| bad("a number"))?;
            let hex = text.starts_with("#x") || text.starts_with("#X") || text.starts_with("0x");
            // Hexadecimal for a signed type may spell the two's complement (`#xFFFF` = -1 for INT).
            let n = if t.is_signed() && hex && n > hi && n <= 2 * hi + 1 {
                n - 2 * (hi + 1)
            } else {
                n
            };
            if n < lo || n > hi {
                return Err(bad(&format!("a {} value {lo}..{hi}", t.esi_base_name())));
            }
            Ok(if t.is_signed() {
                Value::Int(n as i64)
            } else {
                Value::Uint(n as u64)
            })
        }
    }
}

/// A type for an entry that only a PDO describes and whose `DataType` names none: an unsigned of its
/// `BitLen`, a bit field below 8 bits, else an octet string of the bytes it covers.
pub(super) fn type_of_size(bits: u16) -> Option<(DataType, Option<u32>)> {
    let t = match bits {
        0 => return None,
        1..=7 => DataType::Bit(bits as u8),
        8 => DataType::Unsigned8,
        16 => DataType::Unsigned16,
        24 => DataType::Unsigned24,
        32 => DataType::Unsigned32,
        40 => DataType::Unsigned40,
        48 => DataType::Unsigned48,
        56 => DataType::Unsigned56,
        64 => DataType::Unsigned64,
        _ => return Some((DataType::OctetString, Some(u32::from(bits).div_ceil(8) * 8))),
    };
    Some((t, None))
}
