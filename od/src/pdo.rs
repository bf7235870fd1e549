//! PDO configuration as the dictionary holds it (CiA 301 §7.5.2.35–7.5.2.38): communication parameters
//! 0x1400+/0x1800+ and mappings 0x1600+/0x1A00+, and the checks of the mapping procedure: what a CANopen node serves and what a tool reading a
//! node's configuration decodes.

use crate::abort::AbortCode;
use crate::dict::Dictionary;

/// RPDO communication parameters start here; the mapping is at +0x200.
pub const RPDO_COMM: u16 = 0x1400;
/// TPDO communication parameters start here; the mapping is at +0x200.
pub const TPDO_COMM: u16 = 0x1800;
/// Offset from a communication parameter to its mapping.
pub const MAP_OFFSET: u16 = 0x200;
/// COB-ID bit 31: the PDO does not exist.
pub const COB_INVALID: u32 = 0x8000_0000;
/// COB-ID bit 30: no RTR allowed on this TPDO.
pub const COB_NO_RTR: u32 = 0x4000_0000;
/// COB-ID bit 29: 29-bit identifier (not supported: refused).
pub const COB_EXTENDED: u32 = 0x2000_0000;

/// Which way a PDO goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Received by the node (master outputs).
    Rx,
    /// Sent by the node (master inputs).
    Tx,
}

/// One mapped application object, or a dummy entry (index 0x0002–0x0007) that only takes room.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MapEntry {
    /// Mapped index (a data-type index for a dummy).
    pub index: u16,
    /// Mapped sub-index.
    pub sub: u8,
    /// Length in bits (a multiple of 8: granularity 8).
    pub bits: u8,
}

impl MapEntry {
    /// Decodes a mapping entry value `index << 16 | sub << 8 | bits`.
    pub const fn from_raw(raw: u32) -> MapEntry {
        MapEntry {
            index: (raw >> 16) as u16,
            sub: (raw >> 8) as u8,
            bits: raw as u8,
        }
    }

    /// The length in bytes.
    pub const fn len(&self) -> usize {
        self.bits as usize / 8
    }

    /// True for a zero-length entry.
    pub const fn is_empty(&self) -> bool {
        self.bits == 0
    }

    /// True for a dummy entry (CiA 301 §7.4.7.1: a data-type index reserves room).
    pub const fn is_dummy(&self) -> bool {
        self.index < 0x0020
    }
}

/// A PDO's configuration read from the dictionary.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PdoConfig {
    /// Direction.
    pub dir: Direction,
    /// Communication parameter index (0x1400+n or 0x1800+n).
    pub comm: u16,
    /// Sub 1, raw.
    pub cob_raw: u32,
    /// Sub 2.
    pub transmission: u8,
    /// Sub 3 in 100 µs (TPDO; 0 when absent).
    pub inhibit: u16,
    /// Sub 5 in ms (TPDO; 0 when absent).
    pub event_timer: u16,
    /// The mapped entries (sub 1 … sub 0).
    pub map: Vec<MapEntry>,
}

impl PdoConfig {
    /// True when the PDO exists (COB-ID bit 31 clear).
    pub const fn valid(&self) -> bool {
        self.cob_raw & COB_INVALID == 0
    }

    /// The 11-bit identifier.
    pub const fn cob_id(&self) -> u16 {
        (self.cob_raw & 0x7FF) as u16
    }

    /// Mapped length in bytes.
    pub fn len(&self) -> usize {
        self.map.iter().map(MapEntry::len).sum()
    }

    /// True when nothing is mapped.
    pub fn is_empty(&self) -> bool {
        self.map.is_empty()
    }

    /// Reads PDO `comm` from the dictionary; `None` when the object is absent.
    pub fn read(dict: &Dictionary, comm: u16) -> Option<PdoConfig> {
        let dir = if comm < TPDO_COMM {
            Direction::Rx
        } else {
            Direction::Tx
        };
        let u32_at = |i: u16, s: u8| -> Option<u32> {
            let v = dict.entry(i, s).ok()?.value.as_slice();
            let mut b = [0u8; 4];
            let n = v.len().min(4);
            b[..n].copy_from_slice(&v[..n]);
            Some(u32::from_le_bytes(b))
        };
        let cob_raw = u32_at(comm, 1)?;
        let count = u32_at(comm + MAP_OFFSET, 0).unwrap_or(0) as u8;
        let map = (1..=count)
            .filter_map(|s| u32_at(comm + MAP_OFFSET, s))
            .map(MapEntry::from_raw)
            .collect();
        Some(PdoConfig {
            dir,
            comm,
            cob_raw,
            transmission: u32_at(comm, 2).unwrap_or(255) as u8,
            inhibit: u32_at(comm, 3).unwrap_or(0) as u16,
            event_timer: u32_at(comm, 5).unwrap_or(0) as u16,
            map,
        })
    }
}

/// CiA 301 §7.3.5 restricted CAN-IDs: no PDO, SYNC or EMCY may use them
/// ([`crate::fill::restricted_can_id`]).
pub const fn restricted_id(id: u16) -> bool {
    crate::fill::restricted_can_id(id)
}

/// Checks one mapping entry written in step 3 of the procedure: the object exists (0x06020000), may be
/// mapped in this direction with its full length in whole bytes (0x06040041). Zero is accepted (empty).
pub fn check_entry(dict: &Dictionary, dir: Direction, raw: u32) -> Result<(), AbortCode> {
    if raw == 0 {
        return Ok(());
    }
    let e = MapEntry::from_raw(raw);
    if e.bits == 0 || !e.bits.is_multiple_of(8) {
        return Err(AbortCode::NotMappable);
    }
    if e.is_dummy() {
        let bits = match e.index {
            0x0002 | 0x0005 => 8,
            0x0003 | 0x0006 => 16,
            0x0004 | 0x0007 => 32,
            _ => return Err(AbortCode::NotMappable),
        };
        return if e.sub == 0 && e.bits == bits {
            Ok(())
        } else {
            Err(AbortCode::NotMappable)
        };
    }
    let entry = dict
        .entry(e.index, e.sub)
        .map_err(|_| AbortCode::NoObject)?;
    let mappable = match dir {
        Direction::Rx => entry.pdo.rpdo(),
        Direction::Tx => entry.pdo.tpdo(),
    };
    let size = entry.data_type.byte_size().unwrap_or(0);
    if !mappable || size * 8 != usize::from(e.bits) {
        return Err(AbortCode::NotMappable);
    }
    Ok(())
}

/// Checks the number of entries written in step 4: at most the entries the object has, each one
/// valid (0x06040043 for an empty or invalid one among them), 64 bits in all (0x06040042).
pub fn check_count(
    dict: &Dictionary,
    dir: Direction,
    map_index: u16,
    count: u8,
) -> Result<(), AbortCode> {
    let object = dict.object(map_index).ok_or(AbortCode::NoObject)?;
    if count > object.max_sub() {
        return Err(AbortCode::PdoTooLong);
    }
    let mut bits = 0u32;
    for s in 1..=count {
        let raw = dict
            .entry(map_index, s)
            .ok()
            .map(|e| {
                let mut b = [0u8; 4];
                let n = e.value.len().min(4);
                b[..n].copy_from_slice(&e.value[..n]);
                u32::from_le_bytes(b)
            })
            .ok_or(AbortCode::ParameterIncompatible)?;
        if raw == 0 || check_entry(dict, dir, raw).is_err() {
            return Err(AbortCode::ParameterIncompatible);
        }
        bits += raw & 0xFF;
    }
    if bits > 64 {
        return Err(AbortCode::PdoTooLong);
    }
    Ok(())
}
