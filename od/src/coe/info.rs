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
//! - **Get Entry Description** (5 → 6): Index, Subindex, ValueInfo (u8; none of unit, default,
//!   minimum or maximum is given, so 0 in the answer), DataType (u16; BITn as 0x0030 + n − 1),
//!   BitLength (u16), ObjectAccess (u16: bits 0–2 readable in Pre-Op / Safe-Op / Op, 3–5 writable
//!   in them, 6 RxPDO and 7 TxPDO mappable), Name.
//!
//! An answer longer than the mailbox is sent in fragments, Incomplete set on all but the last and
//! Fragments Left counting down; the master reads them one after the other without asking again. A
//! request for an object or entry that does not exist, or one that cannot be parsed, is answered with
//! SDO Info Error (7) and the abort code (0x06020000, 0x06090011, 0x06010000 for an unknown list type
//! or OpCode).

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
            let entry = d.entry(index, sub)?;
            let mut out = index.to_le_bytes().to_vec();
            out.push(sub);
            out.push(0);
            out.extend_from_slice(&type_code(entry.data_type).to_le_bytes());
            let bits = entry
                .data_type
                .bit_size()
                .or(entry.bit_size)
                .unwrap_or(8 * entry.value.len() as u32);
            out.extend_from_slice(&(bits.min(0xFFFF) as u16).to_le_bytes());
            out.extend_from_slice(&object_access(entry).to_le_bytes());
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

/// The ETG.1000.6 data-type code: CiA 301's, with BIT1–BIT8 at 0x0030–0x0037.
fn type_code(t: DataType) -> u16 {
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
