//! The pcapng blocks (draft-tuexen-opsawg-pcapng-05), written in little-endian order into a buffer
//! the caller owns, with no I/O: a Section Header Block ([`section_header`]), an Interface
//! Description Block per link ([`interface_description`]: its link type, `if_name` and `if_tsresol`
//! of nanoseconds) and an Enhanced Packet Block per frame ([`enhanced_packet`]: its time, its bytes
//! and `epb_flags` with its direction). [`Reader`] reads any file of the format back.
//!
//! Every block is `type`, `total length`, a body padded to 32 bits, and `total length` again
//! (§3.1); options are `code`, `length`, a value padded to 32 bits, and end with `opt_endofopt`
//! (§3.5).

mod read;

use std::time::{SystemTime, UNIX_EPOCH};

pub use read::{timestamp, InterfaceInfo, Packet, ReadError, Reader, MAX_BLOCK, MAX_INTERFACES};

/// `LINKTYPE_ETHERNET`: a whole Ethernet frame (destination, source, EtherType, payload), as
/// EtherCAT travels.
pub const LINKTYPE_ETHERNET: u16 = 1;
/// `LINKTYPE_CAN_SOCKETCAN`: a CAN frame as Linux's SocketCAN has it, the identifier in network
/// byte order with its flags, the length, three bytes and the data.
pub const LINKTYPE_CAN_SOCKETCAN: u16 = 227;

/// Block types (§4, §11.1).
pub(crate) const SHB: u32 = 0x0A0D_0D0A;
pub(crate) const IDB: u32 = 0x0000_0001;
pub(crate) const PB: u32 = 0x0000_0002;
pub(crate) const SPB: u32 = 0x0000_0003;
pub(crate) const EPB: u32 = 0x0000_0006;
/// The byte-order magic of a Section Header Block (§4.1).
pub(crate) const BYTE_ORDER_MAGIC: u32 = 0x1A2B_3C4D;

/// Option codes (§3.5, §4.1, §4.2, §4.3).
const OPT_ENDOFOPT: u16 = 0;
const SHB_USERAPPL: u16 = 4;
pub(crate) const IF_NAME: u16 = 2;
pub(crate) const IF_TSRESOL: u16 = 9;
pub(crate) const IF_TSOFFSET: u16 = 14;
pub(crate) const EPB_FLAGS: u16 = 2;

/// The timestamps' unit this crate writes: 10⁻⁹ s (`if_tsresol` = 9).
pub const TSRESOL_NANOSECONDS: u8 = 9;

/// Which way a frame went, as `epb_flags` bits 0–1 say (§4.3.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Received by the process (`01`).
    Inbound,
    /// Sent by the process (`10`).
    Outbound,
}

impl Direction {
    /// The `epb_flags` word with this direction and nothing else.
    pub const fn flags(self) -> u32 {
        match self {
            Direction::Inbound => 0b01,
            Direction::Outbound => 0b10,
        }
    }

    /// The direction `epb_flags` gives (`None`: not given, `00`, or the reserved `11`).
    pub const fn from_flags(flags: u32) -> Option<Direction> {
        match flags & 0b11 {
            0b01 => Some(Direction::Inbound),
            0b10 => Some(Direction::Outbound),
            _ => None,
        }
    }
}

/// Appends a block of `block_type` whose body `body` writes, with both total lengths.
fn block(out: &mut Vec<u8>, block_type: u32, body: impl FnOnce(&mut Vec<u8>)) {
    let start = out.len();
    out.extend_from_slice(&block_type.to_le_bytes());
    out.extend_from_slice(&[0; 4]);
    body(out);
    pad(out, start);
    let total = (out.len() - start + 4) as u32;
    out[start + 4..start + 8].copy_from_slice(&total.to_le_bytes());
    out.extend_from_slice(&total.to_le_bytes());
}

/// Zeros up to the next multiple of 4 bytes from `start`.
fn pad(out: &mut Vec<u8>, start: usize) {
    while !(out.len() - start).is_multiple_of(4) {
        out.push(0);
    }
}

/// Appends one option: its code, the value's length, the value padded to 32 bits. A value longer
/// than an option holds (65,535 bytes) is cut.
fn option(out: &mut Vec<u8>, code: u16, value: &[u8]) {
    let value = &value[..value.len().min(usize::from(u16::MAX))];
    out.extend_from_slice(&code.to_le_bytes());
    out.extend_from_slice(&(value.len() as u16).to_le_bytes());
    let start = out.len();
    out.extend_from_slice(value);
    pad(out, start);
}

/// Appends `opt_endofopt`.
fn end_of_options(out: &mut Vec<u8>) {
    out.extend_from_slice(&OPT_ENDOFOPT.to_le_bytes());
    out.extend_from_slice(&[0, 0]);
}

/// Appends a Section Header Block (§4.1): little-endian, version 1.0, section length unknown (−1:
/// the file is written as frames come), and `shb_userappl` = `application` when not empty.
pub fn section_header(out: &mut Vec<u8>, application: &str) {
    block(out, SHB, |b| {
        b.extend_from_slice(&BYTE_ORDER_MAGIC.to_le_bytes());
        b.extend_from_slice(&1u16.to_le_bytes());
        b.extend_from_slice(&0u16.to_le_bytes());
        b.extend_from_slice(&(-1i64).to_le_bytes());
        if !application.is_empty() {
            option(b, SHB_USERAPPL, application.as_bytes());
            end_of_options(b);
        }
    });
}

/// Appends an Interface Description Block (§4.2): `link_type`, no snapshot length limit (0),
/// `if_name` = `name` when not empty, and `if_tsresol` = 9 (timestamps in nanoseconds).
pub fn interface_description(out: &mut Vec<u8>, link_type: u16, name: &str) {
    block(out, IDB, |b| {
        b.extend_from_slice(&link_type.to_le_bytes());
        b.extend_from_slice(&[0, 0]);
        b.extend_from_slice(&0u32.to_le_bytes());
        if !name.is_empty() {
            option(b, IF_NAME, name.as_bytes());
        }
        option(b, IF_TSRESOL, &[TSRESOL_NANOSECONDS]);
        end_of_options(b);
    });
}

/// Nanoseconds since 1970-01-01 00:00:00 UTC (0 for an earlier time).
pub fn nanoseconds(at: SystemTime) -> u64 {
    at.duration_since(UNIX_EPOCH)
        .map_or(0, |d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX))
}

/// Appends an Enhanced Packet Block (§4.3) of interface `interface` (0 for the section's first
/// Interface Description Block): the time `at` in nanoseconds, `frame` whole (captured and original
/// length alike), and `epb_flags` with `direction`.
pub fn enhanced_packet(
    out: &mut Vec<u8>,
    interface: u32,
    at: SystemTime,
    direction: Direction,
    frame: &[u8],
) {
    let ts = nanoseconds(at);
    block(out, EPB, |b| {
        b.extend_from_slice(&interface.to_le_bytes());
        b.extend_from_slice(&((ts >> 32) as u32).to_le_bytes());
        b.extend_from_slice(&(ts as u32).to_le_bytes());
        b.extend_from_slice(&(frame.len() as u32).to_le_bytes());
        b.extend_from_slice(&(frame.len() as u32).to_le_bytes());
        let start = b.len();
        b.extend_from_slice(frame);
        pad(b, start);
        option(b, EPB_FLAGS, &direction.flags().to_le_bytes());
        end_of_options(b);
    });
}

#[cfg(test)]
mod tests;
