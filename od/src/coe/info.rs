//! The SDO Information service of CoE (ETG.1000.6 §5.6.3): what a configuration tool asks to list
//! and describe a slave's dictionary without its description file.
//!
//! Every SDO Information mailbox has the CoE header (service 8) and a 4-byte header: OpCode (bits 0–6),
//! Incomplete (bit 7), a reserved byte, and the number of fragments still to come (u16). Served here:
//!
//! - **Get OD List** (1 → 2): ListType (u16) then, for type 0, the lengths of lists 1–5; for 1 all
//!   objects, 2 those mappable into an RxPDO, 3 into a TxPDO, 4 those for device replacement and
//!   5 the start-up parameters (none here: the dictionary does not mark them), each a list of u16
//!   indices.
//! - **Get Object Description** (3 → 4): Index, DataType (u16: the entries' type for VAR and ARRAY,
//!   the standard record type for the CiA 301 records, else 0), MaxSubindex (u8), ObjectCode (u8: 7
//!   VAR, 8 ARRAY, 9 RECORD), Name.
//! - **Get Entry Description** (5 → 6): Index, Subindex, ValueInfo (u8: of what the request asks
//!   for — 0x08 unit, 0x10 default, 0x20 minimum, 0x40 maximum — those the entry has; values only
//!   for fixed-size types), DataType (u16; BITn as 0x0030 + n − 1), BitLength (u16), ObjectAccess
//!   (u16: bits 0–2 readable in Pre-Op / Safe-Op / Op, 3–5 writable in them, 6 RxPDO and 7 TxPDO
//!   mappable), then the unit (u32) and values ValueInfo announces, each of the entry's size, and
//!   the Name.
//!
//! An answer longer than the mailbox is sent in fragments, Incomplete set on all but the last and
//! Fragments Left counting down; the master reads them one after the other without asking again. A
//! request for an object or entry that does not exist, or one that cannot be parsed, is answered with
//! SDO Info Error (7) and the abort code (0x06020000, 0x06090011, 0x06010000 for an unknown list type
//! or OpCode).
//!
//! The master's side is here too: [`request`] builds the three requests, [`Reassembly`] joins an
//! answer's fragments, and [`ObjectDescription`] and [`EntryDescription`] read the two descriptions.

use crate::abort::AbortCode;
use crate::coe::mailbox::{CoeHeader, CoeService, MAILBOX_HEADER_LEN};
use crate::dict::Dictionary;
use crate::object::{EcatStates, ObjectKind, PdoMapping, SubObject};
use crate::types::DataType;

/// Bytes of the SDO Information header.
pub const INFO_HEADER_LEN: usize = 4;

/// The OpCodes.
pub mod opcode {
    /// Get OD List request.
    pub const GET_OD_LIST: u8 = 1;
    /// Get OD List response.
    pub const OD_LIST: u8 = 2;
    /// Get Object Description request.
    pub const GET_OBJECT: u8 = 3;
    /// Get Object Description response.
    pub const OBJECT: u8 = 4;
    /// Get Entry Description request.
    pub const GET_ENTRY: u8 = 5;
    /// Get Entry Description response.
    pub const ENTRY: u8 = 6;
    /// SDO Info Error request.
    pub const ERROR: u8 = 7;
}

/// The CoE bodies (CoE header onwards) answering the SDO Information request `body` (CoE header
/// onwards), each fitting a mailbox of `mailbox_size` bytes.
pub fn answer(body: &[u8], d: &Dictionary, mailbox_size: usize) -> Vec<Vec<u8>> {
    let (op, data) = match serve(body, d) {
        Ok(answer) => answer,
        Err(code) => (opcode::ERROR, code.code().to_le_bytes().to_vec()),
    };
    fragments(op, &data, mailbox_size)
}

fn serve(body: &[u8], d: &Dictionary) -> Result<(u8, Vec<u8>), AbortCode> {
    let request = body
        .get(2 + INFO_HEADER_LEN..)
        .ok_or(AbortCode::InvalidCommand)?;
    let u16_at = |k: usize| {
        request
            .get(k..k + 2)
            .map(|b| u16::from_le_bytes([b[0], b[1]]))
            .ok_or(AbortCode::InvalidCommand)
    };
    match body[2] & 0x7F {
        opcode::GET_OD_LIST => {
            let list = u16_at(0)?;
            let mut out = list.to_le_bytes().to_vec();
            if list == 0 {
                for l in 1..=5 {
                    out.extend_from_slice(&(od_list(d, l)?.len() as u16).to_le_bytes());
                }
            } else {
                for index in od_list(d, list)? {
                    out.extend_from_slice(&index.to_le_bytes());
                }
            }
            Ok((opcode::OD_LIST, out))
        }
        opcode::GET_OBJECT => {
            let index = u16_at(0)?;
            let object = d.object(index).ok_or(AbortCode::NoObject)?;
            let max_sub = object.subs.keys().next_back().copied().unwrap_or(0);
            let data_type = match object.kind {
                ObjectKind::Var | ObjectKind::Domain => {
                    object.subs.get(&0).map_or(0, |s| type_code(s.data_type))
                }
                ObjectKind::Array => object.subs.get(&1).map_or(0, |s| type_code(s.data_type)),
                _ => record_type(index),
            };
            let code = match object.kind {
                ObjectKind::Domain => ObjectKind::Var.code(),
                k => k.code(),
            };
            let mut out = index.to_le_bytes().to_vec();
            out.extend_from_slice(&data_type.to_le_bytes());
            out.push(max_sub);
            out.push(code);
            out.extend_from_slice(object.name.as_bytes());
            Ok((opcode::OBJECT, out))
        }
        opcode::GET_ENTRY => {
            let index = u16_at(0)?;
            let sub = *request.get(2).ok_or(AbortCode::InvalidCommand)?;
            let asked = request.get(3).copied().unwrap_or(0);
            let entry = d.entry(index, sub)?;
            let t = entry.data_type;
            // The values asked for that the entry has, at its size (fixed-size types only).
            let fixed = t.byte_size().filter(|_| !t.is_variable());
            let value =
                |v: Option<&crate::value::Value>| fixed.and(v).and_then(|v| v.encode(t).ok());
            let unit = (asked & 0x08 != 0).then_some(entry.unit).flatten();
            let values =
                [
                    (
                        0x10,
                        value(
                            entry.default.as_ref().map(|dv| &dv.value).filter(|_| {
                                !entry.default.as_ref().is_some_and(|dv| dv.plus_node_id)
                            }),
                        ),
                    ),
                    (0x20, value(entry.low.as_ref())),
                    (0x40, value(entry.high.as_ref())),
                ];
            let mut info = if unit.is_some() { 0x08 } else { 0 };
            for (bit, v) in &values {
                if asked & bit != 0 && v.is_some() {
                    info |= bit;
                }
            }
            let mut out = index.to_le_bytes().to_vec();
            out.push(sub);
            out.push(info);
            out.extend_from_slice(&type_code(t).to_le_bytes());
            let bits = t
                .bit_size()
                .or(entry.bit_size)
                .unwrap_or(8 * entry.value.len() as u32);
            out.extend_from_slice(&(bits.min(0xFFFF) as u16).to_le_bytes());
            out.extend_from_slice(&object_access(entry).to_le_bytes());
            if let Some(u) = unit {
                out.extend_from_slice(&u.to_le_bytes());
            }
            for (bit, v) in values {
                if let (true, Some(bytes)) = (info & bit != 0, v) {
                    out.extend_from_slice(&bytes);
                }
            }
            out.extend_from_slice(entry.name.as_bytes());
            Ok((opcode::ENTRY, out))
        }
        _ => Err(AbortCode::InvalidCommand),
    }
}

/// The indices of list `list` (1–5).
fn od_list(d: &Dictionary, list: u16) -> Result<Vec<u16>, AbortCode> {
    let mappable = |m: &dyn Fn(PdoMapping) -> bool| -> Vec<u16> {
        d.objects()
            .filter(|o| o.subs.values().any(|s| m(s.pdo)))
            .map(|o| o.index)
            .collect()
    };
    match list {
        1 => Ok(d.objects().map(|o| o.index).collect()),
        2 => Ok(mappable(&PdoMapping::rpdo)),
        3 => Ok(mappable(&PdoMapping::tpdo)),
        4 | 5 => Ok(Vec::new()),
        _ => Err(AbortCode::UnsupportedAccess),
    }
}

/// The ETG.1000.6 data-type code: CiA 301's, with BIT1–BIT8 at 0x0030–0x0037 (a 1-bit field is
/// BOOLEAN, 0x0001).
pub fn type_code(t: DataType) -> u16 {
    match t {
        DataType::Bit(n) if (2..=8).contains(&n) => 0x002F + u16::from(n),
        other => other.index(),
    }
}

/// The standard record types of the CiA 301 communication objects (0 for others).
fn record_type(index: u16) -> u16 {
    match index {
        0x1018 => 0x0023,
        0x1200..=0x12FF => 0x0022,
        0x1400..=0x15FF | 0x1800..=0x19FF => 0x0020,
        0x1600..=0x17FF | 0x1A00..=0x1BFF => 0x0021,
        _ => 0,
    }
}

/// ObjectAccess: readable and writable per state, PDO mapping.
fn object_access(e: &SubObject) -> u16 {
    let all = EcatStates::PREOP
        .union(EcatStates::SAFEOP)
        .union(EcatStates::OP);
    let bits = |states: EcatStates| -> u16 {
        [EcatStates::PREOP, EcatStates::SAFEOP, EcatStates::OP]
            .iter()
            .enumerate()
            .filter(|(_, s)| states.contains(**s))
            .map(|(k, _)| 1u16 << k)
            .sum()
    };
    let mut a = 0;
    if e.access.kind.readable() {
        a |= bits(e.access.read_states.unwrap_or(all));
    }
    if e.access.kind.writable() {
        a |= bits(e.access.write_states.unwrap_or(all)) << 3;
    }
    if e.pdo.rpdo() {
        a |= 1 << 6;
    }
    if e.pdo.tpdo() {
        a |= 1 << 7;
    }
    a
}

/// `data` split into CoE bodies of at most `mailbox_size` bytes with a mailbox header.
fn fragments(op: u8, data: &[u8], mailbox_size: usize) -> Vec<Vec<u8>> {
    let room = mailbox_size
        .saturating_sub(MAILBOX_HEADER_LEN + 2 + INFO_HEADER_LEN)
        .max(2);
    let chunks: Vec<&[u8]> = if data.is_empty() {
        vec![&[]]
    } else {
        data.chunks(room).collect()
    };
    let n = chunks.len();
    chunks
        .into_iter()
        .enumerate()
        .map(|(k, chunk)| {
            let left = (n - 1 - k).min(usize::from(u16::MAX)) as u16;
            let mut body = CoeHeader {
                number: 0,
                service: CoeService::SdoInformation,
            }
            .emit()
            .to_vec();
            body.push(op | if left > 0 { 0x80 } else { 0 });
            body.push(0);
            body.extend_from_slice(&left.to_le_bytes());
            body.extend_from_slice(chunk);
            body
        })
        .collect()
}

/// The ETG.1000.6 data-type code `code` as a basic type: BIT1–BIT8 (0x0030–0x0037) as `Bit`, the
/// CiA 301 codes as theirs; `None` for anything else (an ARRAY or vendor type).
pub fn data_type(code: u16) -> Option<DataType> {
    match code {
        0x0030 => Some(DataType::Bit(1)),
        0x0031..=0x0037 => Some(DataType::Bit((code - 0x002F) as u8)),
        other => DataType::from_index(other),
    }
}

/// A list of [`Request::OdList`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OdList {
    /// Type 0: the lengths of lists 1–5.
    Lengths,
    /// Type 1: every object.
    All,
    /// Type 2: the objects mappable into an RxPDO.
    RxPdo,
    /// Type 3: those mappable into a TxPDO.
    TxPdo,
    /// Type 4: those for device replacement.
    Replacement,
    /// Type 5: the start-up parameters.
    Startup,
}

impl OdList {
    /// The ListType code.
    pub const fn code(self) -> u16 {
        match self {
            OdList::Lengths => 0,
            OdList::All => 1,
            OdList::RxPdo => 2,
            OdList::TxPdo => 3,
            OdList::Replacement => 4,
            OdList::Startup => 5,
        }
    }
}

/// A request of the master.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Request {
    /// Get OD List.
    OdList(OdList),
    /// Get Object Description of an index.
    Object(u16),
    /// Get Entry Description of an index and sub-index, with the ValueInfo bits asked for (0x08
    /// unit, 0x10 default, 0x20 minimum, 0x40 maximum; 0 for none).
    Entry {
        /// The index.
        index: u16,
        /// The sub-index.
        sub: u8,
        /// The ValueInfo bits.
        value_info: u8,
    },
}

/// The CoE body (CoE header onwards) of `request`: a request fits one fragment.
pub fn request(request: Request) -> Vec<u8> {
    let (op, data) = match request {
        Request::OdList(list) => (opcode::GET_OD_LIST, list.code().to_le_bytes().to_vec()),
        Request::Object(index) => (opcode::GET_OBJECT, index.to_le_bytes().to_vec()),
        Request::Entry {
            index,
            sub,
            value_info,
        } => {
            let mut d = index.to_le_bytes().to_vec();
            d.extend_from_slice(&[sub, value_info]);
            (opcode::GET_ENTRY, d)
        }
    };
    let mut body = CoeHeader {
        number: 0,
        service: CoeService::SdoInformation,
    }
    .emit()
    .to_vec();
    body.extend_from_slice(&[op, 0, 0, 0]);
    body.extend_from_slice(&data);
    body
}

/// The most an answer's fragments may add up to: an OD list of every index (2 bytes each) and its
/// list type.
pub const MAX_ANSWER: usize = 2 + 2 * 65_536;

/// Why an answer is not one.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum InfoError {
    /// The slave answered SDO Info Error with this abort code.
    #[error("SDO Information error: {0}")]
    Refused(AbortCode),
    /// Not an SDO Information body, or not the answer asked for.
    #[error("not an SDO Information answer: {0}")]
    Malformed(String),
}

/// The fragments of one answer, joined: [`Reassembly::push`] each CoE body (CoE header onwards) as
/// it comes, until it gives the whole answer's OpCode and data.
///
/// The first fragment says how many follow (Fragments Left); each next one must count one down, and
/// the one with Incomplete clear is the last. An answer of more than [`MAX_ANSWER`] bytes is refused.
#[derive(Debug, Clone, Default)]
pub struct Reassembly {
    op: Option<u8>,
    left: u16,
    data: Vec<u8>,
}

impl Reassembly {
    /// Before the first fragment.
    pub fn new() -> Reassembly {
        Reassembly::default()
    }

    /// Takes the next fragment: `Ok(Some((opcode, data)))` when it was the last, `Ok(None)` when more
    /// follow.
    pub fn push(&mut self, body: &[u8]) -> Result<Option<(u8, Vec<u8>)>, InfoError> {
        let bad = |what: &str| Err(InfoError::Malformed(what.to_string()));
        let header = match CoeHeader::parse(body) {
            Ok(h) => h,
            Err(e) => return Err(InfoError::Malformed(e.to_string())),
        };
        if header.service != CoeService::SdoInformation {
            return bad("another CoE service");
        }
        let Some(info) = body.get(2..2 + INFO_HEADER_LEN) else {
            return bad("shorter than the SDO Information header");
        };
        let (op, incomplete) = (info[0] & 0x7F, info[0] & 0x80 != 0);
        let left = u16::from_le_bytes([info[2], info[3]]);
        let data = &body[2 + INFO_HEADER_LEN..];
        if op == opcode::ERROR {
            let Some(c) = data.get(..4) else {
                return bad("an SDO Info Error without its abort code");
            };
            return Err(InfoError::Refused(AbortCode::from(u32::from_le_bytes([
                c[0], c[1], c[2], c[3],
            ]))));
        }
        match self.op {
            None => self.op = Some(op),
            Some(first) if first != op => return bad("a fragment of another answer"),
            Some(_) if left.checked_add(1) != Some(self.left) => {
                return bad("a fragment out of order")
            }
            Some(_) => {}
        }
        if incomplete == (left == 0) {
            return bad("Incomplete and Fragments Left disagree");
        }
        if self.data.len() + data.len() > MAX_ANSWER {
            return bad("longer than any answer");
        }
        self.data.extend_from_slice(data);
        self.left = left;
        if incomplete {
            return Ok(None);
        }
        Ok(Some((op, std::mem::take(&mut self.data))))
    }
}

/// A Get OD List answer's indices (the list type first is left out), checked to be of `list`.
pub fn od_list_indices(list: OdList, data: &[u8]) -> Result<Vec<u16>, InfoError> {
    let (code, rest) = match data {
        [a, b, rest @ ..] => (u16::from_le_bytes([*a, *b]), rest),
        _ => return Err(InfoError::Malformed("an OD list without its type".into())),
    };
    if code != list.code() || rest.len() % 2 != 0 {
        return Err(InfoError::Malformed(format!(
            "an OD list of type {code} and {} bytes",
            rest.len()
        )));
    }
    Ok(rest
        .chunks_exact(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]))
        .collect())
}

/// A Get Object Description answer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ObjectDescription {
    /// The index.
    pub index: u16,
    /// DataType (the entries' type for VAR and ARRAY, a record type or 0 for RECORD).
    pub data_type: u16,
    /// MaxSubindex.
    pub max_sub: u8,
    /// ObjectCode: 7 VAR, 8 ARRAY, 9 RECORD.
    pub object_code: u8,
    /// The name (bytes that are not UTF-8 replaced).
    pub name: String,
}

impl ObjectDescription {
    /// Reads the answer's data (after the SDO Information header).
    pub fn parse(data: &[u8]) -> Result<ObjectDescription, InfoError> {
        let [i0, i1, t0, t1, max_sub, object_code, name @ ..] = data else {
            return Err(InfoError::Malformed(format!(
                "an object description of {} bytes",
                data.len()
            )));
        };
        Ok(ObjectDescription {
            index: u16::from_le_bytes([*i0, *i1]),
            data_type: u16::from_le_bytes([*t0, *t1]),
            max_sub: *max_sub,
            object_code: *object_code,
            name: name_text(name),
        })
    }
}

/// A Get Entry Description answer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EntryDescription {
    /// The index.
    pub index: u16,
    /// The sub-index.
    pub sub: u8,
    /// ValueInfo: which of unit, default, minimum and maximum follow.
    pub value_info: u8,
    /// DataType (ETG.1000.6 code; see [`data_type`]).
    pub data_type: u16,
    /// BitLength.
    pub bit_length: u16,
    /// ObjectAccess: bits 0–2 readable in Pre-Op, Safe-Op, Op, 3–5 writable in them, 6 RxPDO and 7
    /// TxPDO mappable.
    pub access: u16,
    /// The unit (ValueInfo 0x08; see [`crate::units::unit_text`]).
    pub unit: Option<u32>,
    /// The default value's bytes (ValueInfo 0x10).
    pub default: Option<Vec<u8>>,
    /// The minimum's bytes (ValueInfo 0x20).
    pub min: Option<Vec<u8>>,
    /// The maximum's bytes (ValueInfo 0x40).
    pub max: Option<Vec<u8>>,
    /// The name, after the values (bytes that are not UTF-8 replaced).
    pub name: String,
}

impl EntryDescription {
    /// Reads the answer's data (after the SDO Information header). The values ValueInfo announces
    /// are of the entry's size and are skipped before the name (a unit is 4 bytes).
    pub fn parse(data: &[u8]) -> Result<EntryDescription, InfoError> {
        let [i0, i1, sub, value_info, t0, t1, b0, b1, a0, a1, rest @ ..] = data else {
            return Err(InfoError::Malformed(format!(
                "an entry description of {} bytes",
                data.len()
            )));
        };
        let bit_length = u16::from_le_bytes([*b0, *b1]);
        let value_len = usize::from(bit_length).div_ceil(8);
        let missing = || {
            InfoError::Malformed(format!(
                "an entry description without the values ValueInfo 0x{value_info:02X} announces"
            ))
        };
        let mut at = 0;
        let mut take = |len: usize| -> Result<Vec<u8>, InfoError> {
            let bytes = rest.get(at..at + len).ok_or_else(missing)?.to_vec();
            at += len;
            Ok(bytes)
        };
        let unit = if value_info & 0x08 != 0 {
            let b = take(4)?;
            Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        } else {
            None
        };
        let mut values = [None, None, None];
        for (k, bit) in [0x10, 0x20, 0x40].into_iter().enumerate() {
            if value_info & bit != 0 {
                values[k] = Some(take(value_len)?);
            }
        }
        let [default, min, max] = values;
        Ok(EntryDescription {
            index: u16::from_le_bytes([*i0, *i1]),
            sub: *sub,
            value_info: *value_info,
            data_type: u16::from_le_bytes([*t0, *t1]),
            bit_length,
            access: u16::from_le_bytes([*a0, *a1]),
            unit,
            default,
            min,
            max,
            name: name_text(&rest[at..]),
        })
    }

    /// The access as IgH's `ethercat sdos` shows it: read and write for Pre-Op, Safe-Op and Op
    /// (`rwrwrw`, `r-r-r-`, …).
    pub fn access_text(&self) -> String {
        (0..3)
            .flat_map(|k| {
                [
                    if self.access & (1 << k) != 0 {
                        'r'
                    } else {
                        '-'
                    },
                    if self.access & (1 << (k + 3)) != 0 {
                        'w'
                    } else {
                        '-'
                    },
                ]
            })
            .collect()
    }
}

/// A name's bytes as text, a trailing NUL and what follows it left out.
fn name_text(bytes: &[u8]) -> String {
    let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    String::from_utf8_lossy(&bytes[..end]).into_owned()
}

#[cfg(test)]
mod client_tests {
    use super::*;

    /// ETG.1000.6 §5.6.3: CoE header 0x8000 (service 8, number 0), then OpCode, reserved, Fragments
    /// Left 0, then the request's data.
    #[test]
    fn requests_are_the_bytes_of_etg_1000_6() {
        assert_eq!(
            request(Request::OdList(OdList::All)),
            [0x00, 0x80, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00]
        );
        assert_eq!(
            request(Request::Object(0x1018)),
            [0x00, 0x80, 0x03, 0x00, 0x00, 0x00, 0x18, 0x10]
        );
        assert_eq!(
            request(Request::Entry {
                index: 0x6041,
                sub: 0,
                value_info: 0
            }),
            [0x00, 0x80, 0x05, 0x00, 0x00, 0x00, 0x41, 0x60, 0x00, 0x00]
        );
        assert_eq!(OdList::Lengths.code(), 0);
        assert_eq!(OdList::RxPdo.code(), 2);
        assert_eq!(OdList::TxPdo.code(), 3);
        assert_eq!(OdList::Replacement.code(), 4);
        assert_eq!(OdList::Startup.code(), 5);
    }

    /// A fragment as a slave sends it: OpCode with Incomplete, Fragments Left, data.
    fn fragment(op: u8, incomplete: bool, left: u16, data: &[u8]) -> Vec<u8> {
        let mut b = vec![0x00, 0x80, op | if incomplete { 0x80 } else { 0 }, 0];
        b.extend_from_slice(&left.to_le_bytes());
        b.extend_from_slice(data);
        b
    }

    #[test]
    fn fragments_are_joined_in_order() {
        let mut r = Reassembly::new();
        assert_eq!(r.push(&fragment(2, true, 2, &[1, 0, 0x00])), Ok(None));
        assert_eq!(r.push(&fragment(2, true, 1, &[0x10, 0x18])), Ok(None));
        assert_eq!(
            r.push(&fragment(2, false, 0, &[0x10])),
            Ok(Some((2, vec![1, 0, 0x00, 0x10, 0x18, 0x10])))
        );
        // One fragment alone.
        let mut r = Reassembly::new();
        assert_eq!(r.push(&fragment(4, false, 0, &[7])), Ok(Some((4, vec![7]))));
    }

    #[test]
    fn a_fragment_out_of_order_or_of_another_answer_is_refused() {
        let mut r = Reassembly::new();
        r.push(&fragment(2, true, 2, &[1, 0])).unwrap();
        assert!(matches!(
            r.push(&fragment(2, false, 0, &[])),
            Err(InfoError::Malformed(m)) if m.contains("out of order")
        ));
        let mut r = Reassembly::new();
        r.push(&fragment(2, true, 1, &[1, 0])).unwrap();
        assert!(matches!(
            r.push(&fragment(4, false, 0, &[])),
            Err(InfoError::Malformed(m)) if m.contains("another answer")
        ));
        let mut r = Reassembly::new();
        assert!(matches!(
            r.push(&fragment(2, true, 0, &[])),
            Err(InfoError::Malformed(m)) if m.contains("disagree")
        ));
        assert!(matches!(
            Reassembly::new().push(&fragment(2, false, 3, &[])),
            Err(InfoError::Malformed(m)) if m.contains("disagree")
        ));
        // An SDO response (service 3) is not an SDO Information answer.
        assert!(matches!(
            Reassembly::new().push(&[0x00, 0x30, 0x43, 0x00, 0x10, 0x00]),
            Err(InfoError::Malformed(m)) if m.contains("another CoE service")
        ));
        assert!(matches!(
            Reassembly::new().push(&[0x00, 0x80, 0x02]),
            Err(InfoError::Malformed(_))
        ));
    }

    /// 131,074 bytes (every one of 65,536 indices and the list type) is the longest answer.
    #[test]
    fn the_longest_answer_is_an_od_list_of_every_index() {
        let whole = |last: usize| {
            let mut r = Reassembly::new();
            for k in 0..131u16 {
                r.push(&fragment(2, true, 131 - k, &[0u8; 1000]))?;
            }
            r.push(&fragment(2, false, 0, &vec![0u8; last]))
        };
        assert_eq!(whole(74).unwrap().unwrap().1.len(), 131_074);
        assert!(matches!(whole(75), Err(InfoError::Malformed(m)) if m.contains("longer")));
    }

    #[test]
    fn an_answer_longer_than_any_is_refused() {
        let mut r = Reassembly::new();
        let chunk = vec![0u8; 1000];
        let n = MAX_ANSWER / 1000;
        for k in 0..n {
            r.push(&fragment(2, true, (n + 5 - k) as u16, &chunk))
                .unwrap();
        }
        assert!(matches!(
            r.push(&fragment(2, true, 5, &chunk)),
            Err(InfoError::Malformed(m)) if m.contains("longer")
        ));
    }

    #[test]
    fn an_sdo_info_error_gives_its_abort_code() {
        let mut r = Reassembly::new();
        assert_eq!(
            r.push(&fragment(7, false, 0, &[0x00, 0x00, 0x02, 0x06])),
            Err(InfoError::Refused(AbortCode::NoObject))
        );
        assert!(matches!(
            Reassembly::new().push(&fragment(7, false, 0, &[0x00, 0x00])),
            Err(InfoError::Malformed(_))
        ));
    }

    #[test]
    fn descriptions_read_as_etg_1000_6_lays_them_out() {
        // 0x1018, type 0x0023 (IDENTITY), max sub 4, RECORD, "Identity".
        let mut d = vec![0x18, 0x10, 0x23, 0x00, 0x04, 0x09];
        d.extend_from_slice(b"Identity");
        assert_eq!(
            ObjectDescription::parse(&d).unwrap(),
            ObjectDescription {
                index: 0x1018,
                data_type: 0x0023,
                max_sub: 4,
                object_code: 9,
                name: "Identity".into()
            }
        );
        assert!(ObjectDescription::parse(&d[..5]).is_err());
        // 0x6041:00, UNSIGNED16, 16 bits, readable in all three states and TxPDO mappable.
        let mut e = vec![0x41, 0x60, 0x00, 0x00, 0x06, 0x00, 0x10, 0x00, 0x87, 0x00];
        e.extend_from_slice(b"Statusword\0");
        let e = EntryDescription::parse(&e).unwrap();
        assert_eq!(
            e,
            EntryDescription {
                index: 0x6041,
                sub: 0,
                value_info: 0,
                data_type: 0x0006,
                bit_length: 16,
                access: 0x0087,
                unit: None,
                default: None,
                min: None,
                max: None,
                name: "Statusword".into()
            }
        );
        assert_eq!(e.access_text(), "r-r-r-");
        assert!(EntryDescription::parse(&[0x41, 0x60, 0x00]).is_err());
    }

    #[test]
    fn value_info_values_come_before_the_name() {
        // ValueInfo 0x38: unit (4 bytes), default and minimum of a 16-bit entry (2 bytes each).
        let mut e = vec![0x00, 0x20, 0x01, 0x38, 0x06, 0x00, 0x10, 0x00, 0x3F, 0x00];
        e.extend_from_slice(&[0xAA, 0xBB, 0xCC, 0xDD, 0x01, 0x00, 0x00, 0x00]);
        e.extend_from_slice(b"Speed");
        let e = EntryDescription::parse(&e).unwrap();
        assert_eq!(e.name, "Speed");
        assert_eq!(e.unit, Some(0xDDCC_BBAA));
        assert_eq!(e.default, Some(vec![0x01, 0x00]));
        assert_eq!(e.min, Some(vec![0x00, 0x00]));
        assert_eq!(e.max, None);
        assert_eq!(e.access_text(), "rwrwrw");
        // Announced but missing.
        let short = [
            0x00, 0x20, 0x01, 0x40, 0x07, 0x00, 0x20, 0x00, 0x01, 0x00, 1, 2,
        ];
        assert!(EntryDescription::parse(&short).is_err());
    }

    #[test]
    fn access_text_has_each_state_in_its_place() {
        let e = |access| EntryDescription {
            index: 0,
            sub: 0,
            value_info: 0,
            data_type: 7,
            bit_length: 32,
            access,
            unit: None,
            default: None,
            min: None,
            max: None,
            name: String::new(),
        };
        assert_eq!(e(0x0001).access_text(), "r-----");
        assert_eq!(e(0x0002).access_text(), "--r---");
        assert_eq!(e(0x0004).access_text(), "----r-");
        assert_eq!(e(0x0008).access_text(), "-w----");
        assert_eq!(e(0x0010).access_text(), "---w--");
        assert_eq!(e(0x0020).access_text(), "-----w");
    }

    #[test]
    fn od_lists_are_checked_for_their_type() {
        assert_eq!(
            od_list_indices(OdList::All, &[1, 0, 0x00, 0x10, 0x18, 0x10]),
            Ok(vec![0x1000, 0x1018])
        );
        assert!(od_list_indices(OdList::RxPdo, &[1, 0, 0x00, 0x10]).is_err());
        assert!(od_list_indices(OdList::All, &[1, 0, 0x00]).is_err());
        assert!(od_list_indices(OdList::All, &[1]).is_err());
    }

    #[test]
    fn bit_types_have_the_etg_codes() {
        assert_eq!(data_type(0x0030), Some(DataType::Bit(1)));
        assert_eq!(data_type(0x0031), Some(DataType::Bit(2)));
        assert_eq!(data_type(0x0037), Some(DataType::Bit(8)));
        assert_eq!(data_type(0x0038), None);
        assert_eq!(data_type(0x0007), Some(DataType::Unsigned32));
        assert_eq!(data_type(0x0800), None);
        for n in 2..=8 {
            assert_eq!(
                data_type(type_code(DataType::Bit(n))),
                Some(DataType::Bit(n))
            );
        }
    }
}
