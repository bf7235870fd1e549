//! The object dictionary: an owned map from index to [`Object`], with look-up by `index:sub` and by name,
//! and reads and writes checked against type, length, range and access (CiA 301 §7.4).
//!
//! Every refusal is an [`OdError`], and each variant maps onto exactly one SDO abort code, so an SDO
//! server answers a refused access with `error.abort_code()`. A refused write changes nothing.

use std::collections::BTreeMap;
use std::fmt;

use crate::abort::AbortCode;
use crate::object::{Object, SubObject};
use crate::types::DataType;
use crate::value::{Value, ValueError};

/// Why a dictionary access was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum OdError {
    /// No object at the index (0x06020000).
    #[error("object 0x{index:04X} does not exist")]
    NoObject {
        /// The index asked for.
        index: u16,
    },
    /// The object has no such sub-index (0x06090011).
    #[error("object 0x{index:04X} has no sub-index {sub}")]
    NoSubIndex {
        /// The index.
        index: u16,
        /// The sub-index asked for.
        sub: u8,
    },
    /// Read of a write-only entry (0x06010001).
    #[error("0x{index:04X}:{sub:02X} is write-only")]
    WriteOnly {
        /// The index.
        index: u16,
        /// The sub-index.
        sub: u8,
    },
    /// Write of a read-only or constant entry (0x06010002).
    #[error("0x{index:04X}:{sub:02X} is read-only")]
    ReadOnly {
        /// The index.
        index: u16,
        /// The sub-index.
        sub: u8,
    },
    /// A value of another type than the entry's (0x06070010).
    #[error("0x{index:04X}:{sub:02X} is {expected}: {reason}")]
    TypeMismatch {
        /// The index.
        index: u16,
        /// The sub-index.
        sub: u8,
        /// The entry's type.
        expected: DataType,
        /// What was given.
        reason: String,
    },
    /// More bytes than the entry takes (0x06070012).
    #[error("0x{index:04X}:{sub:02X} takes at most {max} bytes, got {got}")]
    TooLong {
        /// The index.
        index: u16,
        /// The sub-index.
        sub: u8,
        /// Bytes the entry takes.
        max: usize,
        /// Bytes given.
        got: usize,
    },
    /// Fewer bytes than the entry takes (0x06070013).
    #[error("0x{index:04X}:{sub:02X} takes {min} bytes, got {got}")]
    TooShort {
        /// The index.
        index: u16,
        /// The sub-index.
        sub: u8,
        /// Bytes the entry takes.
        min: usize,
        /// Bytes given.
        got: usize,
    },
    /// A value the type cannot hold (0x06090030).
    #[error("0x{index:04X}:{sub:02X}: invalid value: {reason}")]
    InvalidValue {
        /// The index.
        index: u16,
        /// The sub-index.
        sub: u8,
        /// What was wrong.
        reason: String,
    },
    /// A value above the entry's high limit (0x06090031).
    #[error("0x{index:04X}:{sub:02X}: {value} is above the high limit {limit}")]
    TooHigh {
        /// The index.
        index: u16,
        /// The sub-index.
        sub: u8,
        /// The value written.
        value: Value,
        /// The high limit.
        limit: Value,
    },
    /// A value below the entry's low limit (0x06090032).
    #[error("0x{index:04X}:{sub:02X}: {value} is below the low limit {limit}")]
    TooLow {
        /// The index.
        index: u16,
        /// The sub-index.
        sub: u8,
        /// The value written.
        value: Value,
        /// The low limit.
        limit: Value,
    },
}

impl OdError {
    /// The SDO abort code that answers this refusal.
    pub const fn abort_code(&self) -> AbortCode {
        match self {
            OdError::NoObject { .. } => AbortCode::NoObject,
            OdError::NoSubIndex { .. } => AbortCode::NoSubIndex,
            OdError::WriteOnly { .. } => AbortCode::WriteOnly,
            OdError::ReadOnly { .. } => AbortCode::ReadOnly,
            OdError::TypeMismatch { .. } => AbortCode::LengthMismatch,
            OdError::TooLong { .. } => AbortCode::LengthTooHigh,
            OdError::TooShort { .. } => AbortCode::LengthTooLow,
            OdError::InvalidValue { .. } => AbortCode::InvalidValue,
            OdError::TooHigh { .. } => AbortCode::ValueTooHigh,
            OdError::TooLow { .. } => AbortCode::ValueTooLow,
        }
    }
}

impl From<OdError> for AbortCode {
    fn from(e: OdError) -> AbortCode {
        e.abort_code()
    }
}

/// The address of one sub-object, `index:sub`: in the dictionary, in an SDO or CoE transfer (the
/// multiplexer, bytes 1–3 of its initiate and abort frames), in a PDO mapping.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct Address {
    /// Index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
}

impl Address {
    /// `index:sub`.
    pub const fn new(index: u16, sub: u8) -> Address {
        Address { index, sub }
    }

    /// Parses `0x8010:01`, `8010:1`, `0x8010sub1`, `0x1000` (sub-index 0) — hexadecimal index, sub-index
    /// hexadecimal with `0x` or as written after a colon (CiA 309-3 writes it in hex too).
    pub fn parse(text: &str) -> Option<Address> {
        let t = text.trim();
        let (idx, sub) = match t.split_once(':') {
            Some((i, s)) => (i, Some(s)),
            None => match t.to_ascii_lowercase().find("sub") {
                Some(p) => (&t[..p], Some(&t[p + 3..])),
                None => (t, None),
            },
        };
        let idx = idx.trim();
        let idx = idx
            .strip_prefix("0x")
            .or_else(|| idx.strip_prefix("0X"))
            .unwrap_or(idx);
        if idx.is_empty() || idx.len() > 4 {
            return None;
        }
        let index = u16::from_str_radix(idx, 16).ok()?;
        let sub = match sub {
            None => 0,
            Some(s) => {
                let s = s.trim();
                let s = s
                    .strip_prefix("0x")
                    .or_else(|| s.strip_prefix("0X"))
                    .unwrap_or(s);
                if s.is_empty() || s.len() > 2 {
                    return None;
                }
                u8::from_str_radix(s, 16).ok()?
            }
        };
        Some(Address { index, sub })
    }
}

impl fmt::Display for Address {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "0x{:04X}:{:02X}", self.index, self.sub)
    }
}

/// Why a name look-up found no single entry.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum LookupError {
    /// No object or sub-object has this name; the names closest to it, if any are close.
    #[error("no object or sub-object is named `{name}`{}", did_you_mean(similar))]
    NotFound {
        /// The name.
        name: String,
        /// Names of the dictionary that look like it, closest first (at most 3).
        similar: Vec<String>,
    },
    /// The object is there, but none of its sub-objects has this name.
    #[error("`{object}` has no sub-object named `{sub}`; its sub-objects: {}", subs.join(", "))]
    NoSub {
        /// The object's name.
        object: String,
        /// The sub-object's name asked for.
        sub: String,
        /// Its sub-objects' names.
        subs: Vec<String>,
    },
    /// `OBJECT.N` with a sub-index number the object does not have.
    #[error("`{object}` (0x{index:04X}) has no sub-index {sub}; its sub-indices: {}", subs.iter().map(|(s, n)| format!("{s} {n}")).collect::<Vec<_>>().join(", "))]
    NoSubIndex {
        /// The object's name.
        object: String,
        /// Its index.
        index: u16,
        /// The sub-index asked for.
        sub: u8,
        /// Its sub-indices with their names.
        subs: Vec<(u8, String)>,
    },
    /// `0xINDEX.SUB` with an index the dictionary does not have.
    #[error("there is no object 0x{0:04X}")]
    NoIndex(u16),
    /// Several entries have this name.
    #[error("`{name}` names several entries: {}", .candidates.iter().map(|a| a.to_string()).collect::<Vec<_>>().join(", "))]
    Ambiguous {
        /// The name.
        name: String,
        /// The entries it names.
        candidates: Vec<Address>,
    },
}

fn did_you_mean(similar: &[String]) -> String {
    if similar.is_empty() {
        String::new()
    } else {
        format!(
            "; did you mean {}?",
            similar
                .iter()
                .map(|n| format!("`{n}`"))
                .collect::<Vec<_>>()
                .join(", ")
        )
    }
}

/// An object dictionary: objects by index.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Dictionary {
    objects: BTreeMap<u16, Object>,
}

impl Dictionary {
    /// An empty dictionary.
    pub fn new() -> Dictionary {
        Dictionary::default()
    }

    /// Adds an object, replacing any at the same index; answers the replaced one.
    pub fn insert(&mut self, object: Object) -> Option<Object> {
        self.objects.insert(object.index, object)
    }

    /// Removes the object at `index`.
    pub fn remove(&mut self, index: u16) -> Option<Object> {
        self.objects.remove(&index)
    }

    /// The object at `index`.
    pub fn object(&self, index: u16) -> Option<&Object> {
        self.objects.get(&index)
    }

    /// The object at `index`, mutable.
    pub fn object_mut(&mut self, index: u16) -> Option<&mut Object> {
        self.objects.get_mut(&index)
    }

    /// All objects in index order.
    pub fn objects(&self) -> impl Iterator<Item = &Object> {
        self.objects.values()
    }

    /// All objects in index order, mutable.
    pub fn objects_mut(&mut self) -> impl Iterator<Item = &mut Object> {
        self.objects.values_mut()
    }

    /// Number of objects.
    pub fn len(&self) -> usize {
        self.objects.len()
    }

    /// True when there is no object.
    pub fn is_empty(&self) -> bool {
        self.objects.is_empty()
    }

    /// The sub-object at `index:sub`, or the refusal that an SDO would answer.
    pub fn entry(&self, index: u16, sub: u8) -> Result<&SubObject, OdError> {
        let object = self
            .objects
            .get(&index)
            .ok_or(OdError::NoObject { index })?;
        object
            .subs
            .get(&sub)
            .ok_or(OdError::NoSubIndex { index, sub })
    }

    fn entry_mut(&mut self, index: u16, sub: u8) -> Result<&mut SubObject, OdError> {
        let object = self
            .objects
            .get_mut(&index)
            .ok_or(OdError::NoObject { index })?;
        object
            .subs
            .get_mut(&sub)
            .ok_or(OdError::NoSubIndex { index, sub })
    }

    /// Finds an entry by name, case-insensitively: the name of a VAR or DOMAIN object (its sub-index 0) or
    /// of a sub-object of an ARRAY or RECORD (`CFG_Word_0` → 0x8010:01). Only when no entry has the name
    /// does the name of an ARRAY or RECORD answer its sub-index 0. `Object.Sub` picks a sub-object of a
    /// named object, and `0x8010:01` is taken as an address. A name that several entries share is refused
    /// with the list of them.
    pub fn lookup(&self, name: &str) -> Result<Address, LookupError> {
        let wanted = name.trim();
        if let Some(addr) = Address::parse(wanted).filter(|_| wanted.contains(':')) {
            return Ok(addr);
        }
        let mut subs = Vec::new();
        let mut objects = Vec::new();
        for object in self.objects.values() {
            if object.kind.has_subs() {
                if object.name.eq_ignore_ascii_case(wanted) {
                    objects.push(Address::new(object.index, 0));
                }
                for (&s, sub) in &object.subs {
                    if sub.name.eq_ignore_ascii_case(wanted) {
                        subs.push(Address::new(object.index, s));
                    }
                }
            } else if object.name.eq_ignore_ascii_case(wanted)
                || object
                    .subs
                    .get(&0)
                    .is_some_and(|s| s.name.eq_ignore_ascii_case(wanted))
            {
                subs.push(Address::new(object.index, 0));
            }
        }
        let found = if !subs.is_empty() { subs } else { objects };
        match found.len() {
            1 => Ok(found[0]),
            0 => {
                if let Some((obj_name, sub_name)) = wanted.split_once('.') {
                    // The object by its name, or by its index (`0x1018.2`).
                    let by_index = obj_name
                        .trim()
                        .strip_prefix("0x")
                        .or_else(|| obj_name.trim().strip_prefix("0X"))
                        .and_then(|h| u16::from_str_radix(h, 16).ok());
                    let obj = match by_index {
                        Some(i) if self.objects.contains_key(&i) => i,
                        Some(i) => return Err(LookupError::NoIndex(i)),
                        None => self.lookup_object(obj_name)?,
                    };
                    let object = &self.objects[&obj];
                    // A sub-index number (`Identity.2`, `0x1018.0x02`) rather than a name.
                    let sub_text = sub_name.trim();
                    let number = sub_text
                        .strip_prefix("0x")
                        .or_else(|| sub_text.strip_prefix("0X"))
                        .map_or_else(
                            || sub_text.parse::<u8>().ok(),
                            |h| u8::from_str_radix(h, 16).ok(),
                        );
                    if let Some(n) = number {
                        if object.subs.contains_key(&n) {
                            return Ok(Address::new(obj, n));
                        }
                        if !object
                            .subs
                            .values()
                            .any(|s| s.name.eq_ignore_ascii_case(sub_text))
                        {
                            return Err(LookupError::NoSubIndex {
                                object: object.name.clone(),
                                index: obj,
                                sub: n,
                                subs: object
                                    .subs
                                    .iter()
                                    .map(|(&k, s)| (k, s.name.clone()))
                                    .collect(),
                            });
                        }
                    }
                    let hits: Vec<Address> = object
                        .subs
                        .iter()
                        .filter(|(_, s)| s.name.eq_ignore_ascii_case(sub_name.trim()))
                        .map(|(&s, _)| Address::new(obj, s))
                        .collect();
                    return match hits.len() {
                        1 => Ok(hits[0]),
                        0 => Err(LookupError::NoSub {
                            object: object.name.clone(),
                            sub: sub_name.trim().to_string(),
                            subs: object.subs.values().map(|s| s.name.clone()).collect(),
                        }),
                        _ => Err(LookupError::Ambiguous {
                            name: wanted.to_string(),
                            candidates: hits,
                        }),
                    };
                }
                Err(self.not_found(wanted))
            }
            _ => Err(LookupError::Ambiguous {
                name: wanted.to_string(),
                candidates: found,
            }),
        }
    }

    /// The not-found error for `name`, with the names that look like it: a similarity (Jaro–Winkler,
    /// case-insensitive) of at least 0.85, closest first, at most three.
    fn not_found(&self, name: &str) -> LookupError {
        let wanted = name.to_lowercase();
        let mut scored: Vec<(f64, &str)> = Vec::new();
        for o in self.objects.values() {
            let names =
                std::iter::once(o.name.as_str()).chain(o.subs.values().map(|s| s.name.as_str()));
            for n in names {
                let score = strsim::jaro_winkler(&wanted, &n.to_lowercase());
                if score >= 0.85 && !scored.iter().any(|(_, m)| m.eq_ignore_ascii_case(n)) {
                    scored.push((score, n));
                }
            }
        }
        scored.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(b.1)));
        LookupError::NotFound {
            name: name.to_string(),
            similar: scored.iter().take(3).map(|(_, n)| n.to_string()).collect(),
        }
    }

    fn lookup_object(&self, name: &str) -> Result<u16, LookupError> {
        let hits: Vec<u16> = self
            .objects
            .values()
            .filter(|o| o.name.eq_ignore_ascii_case(name.trim()))
            .map(|o| o.index)
            .collect();
        match hits.len() {
            1 => Ok(hits[0]),
            0 => Err(self.not_found(name.trim())),
            _ => Err(LookupError::Ambiguous {
                name: name.trim().to_string(),
                candidates: hits.into_iter().map(|i| Address::new(i, 0)).collect(),
            }),
        }
    }

    /// Reads `index:sub` as an SDO upload does: refused for write-only entries.
    pub fn read(&self, index: u16, sub: u8) -> Result<&[u8], OdError> {
        Ok(&self.readable_entry(index, sub)?.value)
    }

    /// The sub-object at `index:sub` when an SDO may read it.
    fn readable_entry(&self, index: u16, sub: u8) -> Result<&SubObject, OdError> {
        let entry = self.entry(index, sub)?;
        if !entry.access.kind.readable() {
            return Err(OdError::WriteOnly { index, sub });
        }
        Ok(entry)
    }

    /// Reads `index:sub` as a typed value (access checked as by [`Dictionary::read`]).
    pub fn read_value(&self, index: u16, sub: u8) -> Result<Value, OdError> {
        let entry = self.readable_entry(index, sub)?;
        Value::decode(entry.data_type, &entry.value).map_err(|e| OdError::InvalidValue {
            index,
            sub,
            reason: e.to_string(),
        })
    }

    /// Writes `bytes` to `index:sub` as an SDO download does: the entry must exist and be writable, the
    /// length must fit the type, and the value must be valid and within the limits. A refused write
    /// changes nothing.
    pub fn write(&mut self, index: u16, sub: u8, bytes: &[u8]) -> Result<(), OdError> {
        let entry = self.entry(index, sub)?;
        if !entry.access.kind.writable() {
            return Err(OdError::ReadOnly { index, sub });
        }
        self.store(index, sub, bytes)
    }

    /// Writes a typed value to `index:sub` (access checked as by [`Dictionary::write`]).
    pub fn write_value(&mut self, index: u16, sub: u8, value: &Value) -> Result<(), OdError> {
        let bytes = self.encode_for(index, sub, value)?;
        self.write(index, sub, &bytes)
    }

    /// Sets `index:sub` from the device's side (the application, a PDO, a configuration file): the same
    /// checks as [`Dictionary::write`] except access, so read-only entries can be updated by their owner.
    /// The value stored is absolute: it no longer follows the node-ID
    /// ([`SubObject::value_plus_node_id`](crate::object::SubObject::value_plus_node_id)).
    pub fn store(&mut self, index: u16, sub: u8, bytes: &[u8]) -> Result<(), OdError> {
        let entry = self.entry_mut(index, sub)?;
        check_value(index, sub, entry, bytes)?;
        entry.value.clear();
        entry.value.extend_from_slice(bytes);
        entry.value_plus_node_id = false;
        Ok(())
    }

    /// Sets `index:sub` as a configuration value (a DCF `ParameterValue`): stored as by
    /// [`Dictionary::store`] and marked as set, so that a DCF writer writes it.
    pub fn store_parameter(&mut self, index: u16, sub: u8, bytes: &[u8]) -> Result<(), OdError> {
        self.store(index, sub, bytes)?;
        self.entry_mut(index, sub)?.value_set = true;
        Ok(())
    }

    /// Sets `index:sub` to a typed value from the device's side (see [`Dictionary::store`]).
    pub fn store_value(&mut self, index: u16, sub: u8, value: &Value) -> Result<(), OdError> {
        let bytes = self.encode_for(index, sub, value)?;
        self.store(index, sub, &bytes)
    }

    /// Checks `bytes` against `index:sub` without storing them (access not checked).
    pub fn check(&self, index: u16, sub: u8, bytes: &[u8]) -> Result<(), OdError> {
        check_value(index, sub, self.entry(index, sub)?, bytes)
    }

    fn encode_for(&self, index: u16, sub: u8, value: &Value) -> Result<Vec<u8>, OdError> {
        let entry = self.entry(index, sub)?;
        value.encode(entry.data_type).map_err(|e| match e {
            ValueError::OutOfRange { .. } => match value.as_i128() {
                Some(v) if v < 0 => OdError::TooLow {
                    index,
                    sub,
                    value: value.clone(),
                    limit: entry
                        .data_type
                        .integer_range()
                        .map_or(Value::Int(0), |(lo, _)| Value::Int(lo as i64)),
                },
                _ => OdError::TooHigh {
                    index,
                    sub,
                    value: value.clone(),
                    limit: entry
                        .data_type
                        .integer_range()
                        .map_or(Value::Uint(0), |(_, hi)| Value::Uint(hi as u64)),
                },
            },
            other => OdError::TypeMismatch {
                index,
                sub,
                expected: entry.data_type,
                reason: other.to_string(),
            },
        })
    }

    /// Sets every entry back to its default value for a node with `node_id` (CiA 301 reset: the
    /// application area) and forgets which values were set explicitly.
    pub fn reset(&mut self, node_id: u8) {
        for object in self.objects.values_mut() {
            for sub in object.subs.values_mut() {
                sub.reset(node_id);
            }
        }
    }

    /// Sets every entry of the indices in `range` back to its default (CiA 301 reset communication:
    /// 0x1000–0x1FFF).
    pub fn reset_range(&mut self, range: std::ops::RangeInclusive<u16>, node_id: u8) {
        for object in self.objects.range_mut(range) {
            for sub in object.1.subs.values_mut() {
                sub.reset(node_id);
            }
        }
    }
}

/// Checks that `bytes` are a value `entry` may hold: length, validity for the type, limits.
fn check_value(index: u16, sub: u8, entry: &SubObject, bytes: &[u8]) -> Result<(), OdError> {
    let t = entry.data_type;
    match t.byte_size() {
        Some(size) if bytes.len() > size => {
            return Err(OdError::TooLong {
                index,
                sub,
                max: size,
                got: bytes.len(),
            })
        }
        Some(size) if bytes.len() < size => {
            return Err(OdError::TooShort {
                index,
                sub,
                min: size,
                got: bytes.len(),
            })
        }
        Some(_) => {}
        None => {
            if let Some(cap) = entry.capacity() {
                if bytes.len() > cap {
                    return Err(OdError::TooLong {
                        index,
                        sub,
                        max: cap,
                        got: bytes.len(),
                    });
                }
            }
        }
    }
    let value = Value::decode(t, bytes).map_err(|e| OdError::InvalidValue {
        index,
        sub,
        reason: e.to_string(),
    })?;
    if let Value::Real32(v) = value {
        if v.is_nan() {
            return Err(OdError::InvalidValue {
                index,
                sub,
                reason: "NaN".into(),
            });
        }
    }
    if let Value::Real64(v) = value {
        if v.is_nan() {
            return Err(OdError::InvalidValue {
                index,
                sub,
                reason: "NaN".into(),
            });
        }
    }
    if let Some(high) = &entry.high {
        if compare(&value, high) == Some(std::cmp::Ordering::Greater) {
            return Err(OdError::TooHigh {
                index,
                sub,
                value,
                limit: high.clone(),
            });
        }
    }
    if let Some(low) = &entry.low {
        if compare(&value, low) == Some(std::cmp::Ordering::Less) {
            return Err(OdError::TooLow {
                index,
                sub,
                value,
                limit: low.clone(),
            });
        }
    }
    Ok(())
}

/// Orders two numeric values; `None` when either is not a number.
pub fn compare(a: &Value, b: &Value) -> Option<std::cmp::Ordering> {
    match (a.as_i128(), b.as_i128()) {
        (Some(x), Some(y)) => Some(x.cmp(&y)),
        _ => a.as_f64()?.partial_cmp(&b.as_f64()?),
    }
}
