//! Drive channels of ETG.5001 Modular Device Profile 742 ("DRV", the servo and stepper terminals
//! EL72xx, ELM72xx, EL7062, EL7411, EJ7xxx, EP7211 and their kin): behind each channel the same CiA
//! 402 drive as behind a CiA 402 axis ([`ds402::drive::Drive`]), reached through a mapping from the
//! channel's objects to the drive's.
//!
//! # The layout
//!
//! Channel *n* (0 for the first) has its objects at the channel stride 0x100 (the documentation
//! writes them 0x6n00, 0x6n10, 0x7n10, 0x8n10): 0x6000 + 0x100·n "FB Inputs" (the feedback),
//! 0x6010 + 0x100·n "DRV Inputs", 0x7010 + 0x100·n "DRV Outputs", 0x8010 + 0x100·n "DRV Amplifier
//! settings". The entries this drive takes, with the CiA 402 object each stands for:
//!
//! | MDP 742 entry | name | type | CiA 402 |
//! |---|---|---|---|
//! | 0x7010:01 | Controlword | UINT16 | 0x6040 |
//! | 0x7010:03 | Modes of operation | UINT8 | 0x6060 |
//! | 0x7010:05 | Target position | UINT32 | 0x607A |
//! | 0x7010:06 | Target velocity | INT32 | 0x60FF |
//! | 0x7010:09 | Target torque | INT16 | 0x6071 |
//! | 0x7010:0A | Torque offset | INT16 | 0x60B2 |
//! | 0x6000:11 | Position | UINT32 | 0x6064 |
//! | 0x6010:01 | Statusword | UINT16 | 0x6041 |
//! | 0x6010:03 | Modes of operation display | UINT8 | 0x6061 |
//! | 0x6010:06 | Following error actual value | INT32 | 0x60F4 |
//! | 0x6010:07 | Velocity actual value | INT32 | 0x606C |
//! | 0x6010:08 | Torque actual value | INT16 | 0x6077 |
//! | 0x8010:50 | Following error window | UINT32 | 0x6065 |
//! | 0x8010:51 | Following error time out | UINT16 | 0x6066 |
//!
//! The controlword and statusword carry the CiA 402 state machine's bits (0–3 and 7 of the
//! controlword; 0–7, 11 and 12 of the statusword; the terminals use statusword bit 10 for a TxPDO
//! toggle, this drive for "target reached" after a halt, which the reserved controlword bit 8 never
//! asks for). The modes are 8 csp, 9 csv and 10 cst (11, cst with commutation angle, is not run).
//! Positions are the drive's counts (the terminals' "Position" counts encoder increments, scaled by
//! 0x9010:15; velocities there are scaled by 0x9010:14: this drive takes both scales as 1).
//!
//! Sources: Beckhoff's documentation of the object dictionaries of the EL72x1 ("Input data",
//! "Output data": 0x6000:11, 0x6010:01/03/07/08, 0x7010:01/03/05/06/09/0A), of the ELM72xx and
//! EL7062 ("CSP": 0x6n10:06 following error actual value, 0x8n10:50/51 following error window and
//! time out; channel 2 at 0x6100, 0x6110, 0x7110), of the EL7411 and EJ7411 ("Commissioning with
//! status word and control word": the state machine on 0x7010:01 and 0x6010:01); LinuxCNC's
//! `lcec_el7211.c` (EL7211 PDOs 0x1600 → 0x7010:01, 0x1601 → 0x7010:06, 0x1A00 → 0x6000:11, 0x1A01
//! → 0x6010:01, 0x1A02 → 0x6010:07); PSI's ecmccfg hardware scripts `ecmcEL7211-0010_CSP.cmd`
//! (0x1606 → 0x7010:05, mode 8 by SDO to 0x7010:03), `ecmcELM7222-0010.cmd` and
//! `ecmcEL7062_CSP.cmd` (channel 2: 0x7110:01, 0x7110:05, 0x6100:11, 0x6110:01).
//!
//! # Which devices
//!
//! A device whose dictionary has no CiA 402 axis (0x6040/0x6041 at 0x6000 + 0x800·axis) has an MDP
//! 742 channel *n* (0..8) where it has 0x7010 + 0x100·n:01 and 0x6010 + 0x100·n:01, both UNSIGNED16,
//! and at least one of the channel's targets (0x7010:05, :06, :09). (The ESI's `Profile` says
//! `ProfileNo` 5001 and `AddInfo` 742 for such a device; the objects are what the drive runs on,
//! and what this module goes by.)
//!
//! # The drive behind a channel
//!
//! [`Channels::dictionary`] makes a CiA 402 dictionary with an axis per channel (axis *n* for
//! channel *n*, at 0x6000 + 0x800·n): the CiA 402 objects of the table for the entries the channel
//! has, with the channel's values, and 0x6502 with the cyclic modes whose targets the channel has
//! (csp 0x7010:05, csv :06, cst :09). The drives are made on it; a read, check or write of a
//! channel's entry goes to its drive's object ([`Channels::to_drive`]), the value converted between
//! the two types (the same bytes where the sizes agree).

use od::dict::{Address, Dictionary};
use od::object::{AccessType, Object, SubObject};
use od::types::DataType;
use od::value::Value;

/// The stride between two channels' objects.
pub const CHANNEL_STRIDE: u16 = 0x100;

/// The most channels a device has here (0x6000–0x67FF).
pub const MAX_CHANNELS: u8 = 8;

use DataType::{Integer16 as I16, Integer32 as I32, Integer8 as I8};
use DataType::{Unsigned16 as U16, Unsigned32 as U32};

/// The entries of a channel (channel 0's index, sub-index) with the CiA 402 object each stands for
/// (standard index, its type, its access).
const LAYOUT: [(u16, u8, u16, DataType, AccessType); 14] = [
    (0x7010, 0x01, 0x6040, U16, AccessType::Rww),
    (0x7010, 0x03, 0x6060, I8, AccessType::Rww),
    (0x7010, 0x05, 0x607A, I32, AccessType::Rww),
    (0x7010, 0x06, 0x60FF, I32, AccessType::Rww),
    (0x7010, 0x09, 0x6071, I16, AccessType::Rww),
    (0x7010, 0x0A, 0x60B2, I16, AccessType::Rww),
    (0x6000, 0x11, 0x6064, I32, AccessType::Ro),
    (0x6010, 0x01, 0x6041, U16, AccessType::Ro),
    (0x6010, 0x03, 0x6061, I8, AccessType::Ro),
    (0x6010, 0x06, 0x60F4, I32, AccessType::Ro),
    (0x6010, 0x07, 0x606C, I32, AccessType::Ro),
    (0x6010, 0x08, 0x6077, I16, AccessType::Ro),
    (0x8010, 0x50, 0x6065, U32, AccessType::Rw),
    (0x8010, 0x51, 0x6066, U16, AccessType::Rw),
];

/// The targets of a channel (0x7010 sub-index) and the mode each is the target of (csp, csv, cst).
const TARGETS: [(u8, u8); 3] = [(0x05, 8), (0x06, 9), (0x09, 10)];

/// One mapped entry: the channel's and its drive's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Entry {
    at: Address,
    ty: DataType,
    drive: Address,
    drive_ty: DataType,
}

/// The MDP 742 drive channels of a device. See the [module documentation](self).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Channels {
    channels: Vec<u8>,
    entries: Vec<Entry>,
}

/// Whether `dict` has `index:sub` as an UNSIGNED16.
fn u16_at(dict: &Dictionary, index: u16, sub: u8) -> bool {
    dict.entry(index, sub)
        .is_ok_and(|e| e.data_type == DataType::Unsigned16)
}

impl Channels {
    /// The MDP 742 channels of `dict`, when it has any and no CiA 402 axis.
    pub fn of(dict: &Dictionary) -> Option<Channels> {
        if !ds402::drive::Drive::axes(dict).is_empty() {
            return None;
        }
        let channels: Vec<u8> = (0..MAX_CHANNELS)
            .filter(|&n| {
                let off = CHANNEL_STRIDE * u16::from(n);
                u16_at(dict, 0x7010 + off, 1)
                    && u16_at(dict, 0x6010 + off, 1)
                    && TARGETS
                        .iter()
                        .any(|(sub, _)| dict.entry(0x7010 + off, *sub).is_ok())
            })
            .collect();
        if channels.is_empty() {
            return None;
        }
        let mut entries = Vec::new();
        for &n in &channels {
            let off = CHANNEL_STRIDE * u16::from(n);
            let axis = 0x800 * u16::from(n);
            for (index, sub, cia, drive_ty, _) in LAYOUT {
                let Ok(e) = dict.entry(index + off, sub) else {
                    continue;
                };
                if !(e.data_type.is_signed() || e.data_type.is_unsigned()) {
                    continue;
                }
                entries.push(Entry {
                    at: Address::new(index + off, sub),
                    ty: e.data_type,
                    drive: Address::new(cia + axis, 0),
                    drive_ty,
                });
            }
        }
        Some(Channels { channels, entries })
    }

    /// The channels (0 for the first), each the drive axis of the same number.
    pub fn channels(&self) -> &[u8] {
        &self.channels
    }

    /// The controlword of channel `n`.
    pub fn controlword(n: u8) -> Address {
        Address::new(0x7010 + CHANNEL_STRIDE * u16::from(n), 1)
    }

    /// The drive's object a channel's entry stands for, and its value in the drive's type: `data`
    /// (the entry's bytes) converted (`None` for an entry that is none of the table's).
    pub fn to_drive(&self, at: Address, data: &[u8]) -> Option<(Address, Vec<u8>)> {
        let e = self.entries.iter().find(|e| e.at == at)?;
        Some((e.drive, convert(data, e.ty, e.drive_ty)))
    }

    /// The drive's object a channel's entry stands for.
    pub fn drive_address(&self, at: Address) -> Option<Address> {
        self.entries.iter().find(|e| e.at == at).map(|e| e.drive)
    }

    /// A value of the drive's object for `at`, in the entry's type (`None` for an entry that is
    /// none of the table's).
    pub fn from_drive(&self, at: Address, data: &[u8]) -> Option<Vec<u8>> {
        let e = self.entries.iter().find(|e| e.at == at)?;
        Some(convert(data, e.drive_ty, e.ty))
    }

    /// The CiA 402 dictionary of the drives behind the channels of `dict` (see the [module
    /// documentation](self)).
    pub fn dictionary(&self, dict: &Dictionary) -> Dictionary {
        let mut out = Dictionary::new();
        for &n in &self.channels {
            let axis = 0x800 * u16::from(n);
            let off = CHANNEL_STRIDE * u16::from(n);
            for (index, sub, cia, ty, access) in LAYOUT {
                let Some(e) = self
                    .entries
                    .iter()
                    .find(|e| e.at == Address::new(index + off, sub))
                else {
                    continue;
                };
                let bytes = dict
                    .entry(e.at.index, e.at.sub)
                    .map(|s| convert(&s.value, e.ty, ty))
                    .unwrap_or_default();
                let mut entry = SubObject::new(name_of(cia), ty, access);
                if let Ok(v) = Value::decode(ty, &bytes) {
                    entry = entry.with_default(v);
                }
                out.insert(Object::var(cia + axis, entry));
            }
            let modes = TARGETS
                .iter()
                .filter(|(sub, _)| dict.entry(0x7010 + off, *sub).is_ok())
                .fold(0u64, |bits, (_, mode)| bits | 1 << (mode - 1));
            out.insert(Object::var(
                0x6502 + axis,
                SubObject::new("Supported drive modes", U32, AccessType::Ro)
                    .with_default(Value::Uint(modes)),
            ));
        }
        out
    }
}

/// The CiA 402 name of a standard object of the table.
fn name_of(index: u16) -> &'static str {
    match index {
        0x6040 => "Controlword",
        0x6041 => "Statusword",
        0x6060 => "Modes of operation",
        0x6061 => "Modes of operation display",
        0x6064 => "Position actual value",
        0x6065 => "Following error window",
        0x6066 => "Following error time out",
        0x606C => "Velocity actual value",
        0x6071 => "Target torque",
        0x6077 => "Torque actual value",
        0x607A => "Target position",
        0x60B2 => "Torque offset",
        0x60F4 => "Following error actual value",
        _ => "Target velocity",
    }
}

/// `data`, an integer of type `from` (little-endian), as an integer of type `to`: sign-extended
/// from a signed type, then the low bytes of `to`'s size (the same bytes where the sizes agree).
fn convert(data: &[u8], from: DataType, to: DataType) -> Vec<u8> {
    let n = data.len().min(8);
    let mut raw = [0u8; 8];
    raw[..n].copy_from_slice(&data[..n]);
    if from.is_signed() && n > 0 && n < 8 && data[n - 1] & 0x80 != 0 {
        for b in &mut raw[n..] {
            *b = 0xFF;
        }
    }
    let size = to.byte_size().unwrap_or(n).min(8);
    raw[..size].to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_convert_between_the_types() {
        // UINT32 target position ↔ INT32: the same bytes.
        assert_eq!(
            convert(&[0x18, 0xFC, 0xFF, 0xFF], U32, I32),
            vec![0x18, 0xFC, 0xFF, 0xFF]
        );
        // INT8 mode display → UINT8: the same byte.
        assert_eq!(convert(&[0xFF], I8, DataType::Unsigned8), vec![0xFF]);
        // INT32 −1 → a 64-bit position: sign-extended.
        assert_eq!(
            convert(&[0xFF, 0xFF, 0xFF, 0xFF], I32, DataType::Integer64),
            vec![0xFF; 8]
        );
        // UINT16 0x8000 → INT32: not sign-extended.
        assert_eq!(convert(&[0x00, 0x80], U16, I32), vec![0x00, 0x80, 0, 0]);
    }
}
