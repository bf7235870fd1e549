//! How the tool shows a value whose type it takes from the description (or the node's SDO
//! Information) rather than from the command line.
//!
//! **Hex or decimal.** An UNSIGNED8–UNSIGNED64 value is shown in hex, zero-padded to its type's
//! width (`0x0637`, `0x00000B2E`), when its entry is of bit-field, identity, mapping or COB-ID
//! nature ([`hex_entry`]):
//!
//! - CiA 301: device type 0x1000, error register 0x1001, manufacturer status register 0x1002, the
//!   pre-defined error field 0x1003 (sub-indices 1–254), COB-ID SYNC 0x1005, the store and restore
//!   signatures 0x1010 and 0x1011 (1–254), COB-ID TIME 0x1012, COB-ID EMCY 0x1014, the consumer
//!   heartbeat times 0x1016 (node-ID and time in one word, 1–254), identity 0x1018 (1–4), the
//!   emergency consumers 0x1028 (1–254), the SDO COB-IDs 0x1200–0x12FF (1 and 2), the PDO COB-IDs
//!   0x1400–0x15FF and 0x1800–0x19FF (1), the PDO mappings 0x1600–0x17FF and 0x1A00–0x1BFF (1–254);
//! - CiA 302: NMT start-up 0x1F80, the slave assignment 0x1F81 and the expected device types and
//!   identities 0x1F84–0x1F88 (1–254);
//! - CiA 402, each axis 0x800 apart: error code 0x603F, controlword 0x6040, statusword 0x6041,
//!   digital inputs 0x60FD, digital outputs 0x60FE (1–254), supported drive modes 0x6502;
//! - and any entry whose description names its bits (`Bit 15 Mode_Flag; 14 Module_OK; …`).
//!
//! Every other number is shown in decimal. A type given on the command line is shown as it says
//! (`u16` decimal, `x16` hex).
//!
//! **A mapping decoded.** A PDO mapping entry is followed by what it maps: `0x60410010 (0x6041:00,
//! 16 bits)` (0 maps nothing and is shown alone).
//!
//! **Long byte strings elided.** A DOMAIN or OCTET_STRING of more than [`SHOWN_BYTES`] bytes is
//! shown as its first [`SHOWN_BYTES`] bytes and its length, `00 01 … 1F … (65536 bytes)`, unless
//! the whole is asked for (`--full`); JSON output always carries the whole value.

use od::dict::{Address, Dictionary};
use od::types::DataType;
use od::value::Value;

use crate::TypeCode;

/// The bytes of a DOMAIN or OCTET_STRING shown before the rest is elided.
pub const SHOWN_BYTES: usize = 32;

/// Whether `a` is an entry CiA 301, 302 or 402 gives a bit-field, identity, mapping or COB-ID
/// value (the list in the module documentation).
pub fn hex_entry(a: Address) -> bool {
    let (i, s) = (a.index, a.sub);
    match i {
        0x1000 | 0x1001 | 0x1002 | 0x1005 | 0x1012 | 0x1014 | 0x1F80 => s == 0,
        0x1003 | 0x1010 | 0x1011 | 0x1016 | 0x1028 | 0x1F81 | 0x1F84..=0x1F88 => s >= 1,
        0x1018 => (1..=4).contains(&s),
        0x1200..=0x12FF => s == 1 || s == 2,
        0x1400..=0x15FF | 0x1800..=0x19FF => s == 1,
        0x1600..=0x17FF | 0x1A00..=0x1BFF => s >= 1,
        0x6000..=0x9FFF => match 0x6000 + (i - 0x6000) % 0x800 {
            0x603F | 0x6040 | 0x6041 | 0x6502 | 0x60FD => s == 0,
            0x60FE => s >= 1,
            _ => false,
        },
        _ => false,
    }
}

/// Whether `a` is a PDO mapping entry (0x1600–0x17FF, 0x1A00–0x1BFF, sub-index 1 and above).
pub fn mapping_entry(a: Address) -> bool {
    matches!(a.index, 0x1600..=0x17FF | 0x1A00..=0x1BFF) && a.sub >= 1
}

/// The description of `addr`'s bits: its entry's, or its object's for a VAR.
pub fn bit_description(dict: &Dictionary, addr: Address) -> Option<&str> {
    let object = dict.object(addr.index)?;
    let entry = object.subs.get(&addr.sub)?;
    entry.description.as_deref().or(object
        .description
        .as_deref()
        .filter(|_| !object.kind.has_subs()))
}

/// Whether `data_type` is one of the UNSIGNED types.
fn unsigned(data_type: DataType) -> bool {
    use DataType::*;
    matches!(
        data_type,
        Unsigned8
            | Unsigned16
            | Unsigned24
            | Unsigned32
            | Unsigned40
            | Unsigned48
            | Unsigned56
            | Unsigned64
    )
}

/// How a value of `data_type` at `addr` is shown when the type is not given on the command line:
/// in hex for an UNSIGNED entry of the natures of [`hex_entry`] or with named bits in `dict`.
pub fn code_for(dict: Option<&Dictionary>, addr: Address, data_type: DataType) -> TypeCode {
    let named = || {
        let Some(bits) = data_type.bit_size() else {
            return false;
        };
        let description = dict.and_then(|d| bit_description(d, addr));
        !od::bits::bit_names(addr.index, addr.sub, description, bits).is_empty()
    };
    TypeCode {
        data_type,
        hex: unsigned(data_type) && (hex_entry(addr) || named()),
    }
}

/// `text` (the value `v` of `addr`, shown) with what a PDO mapping entry maps after it:
/// `0x60410010 (0x6041:00, 16 bits)`.
pub fn with_mapping(addr: Address, v: &Value, text: String) -> String {
    match v {
        Value::Uint(m) if mapping_entry(addr) && *m != 0 => {
            let m = *m as u32;
            format!(
                "{text} ({}, {} bits)",
                Address::new((m >> 16) as u16, (m >> 8) as u8),
                m & 0xFF
            )
        }
        _ => text,
    }
}

/// `bytes` as hex, `01 02 0A`; with more than [`SHOWN_BYTES`] of them and not `full`, the first
/// ones and the length: `00 01 … 1F … (65536 bytes)`.
pub fn bytes_text(bytes: &[u8], full: bool) -> String {
    let shown = if full {
        bytes
    } else {
        &bytes[..bytes.len().min(SHOWN_BYTES)]
    };
    let mut t = shown
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ");
    if shown.len() < bytes.len() {
        t.push_str(&format!(" … ({} bytes)", bytes.len()));
    }
    t
}

/// `bytes` as hex; with more than [`SHOWN_BYTES`] of them and not `full`, the first ones and `…`,
/// for a line that gives the length itself: `00 01 … 1F …`.
pub fn bytes_head(bytes: &[u8], full: bool) -> String {
    let mut t = bytes_text(bytes, full);
    if let Some(at) = t.find(" … (") {
        t.truncate(at + " …".len());
    }
    t
}

/// `text`, the value `v` shown in full, elided when `v` is bytes longer than [`SHOWN_BYTES`] and
/// not `full`.
pub fn elided(v: &Value, text: String, full: bool) -> String {
    match v {
        Value::Bytes(b) if !full && b.len() > SHOWN_BYTES => bytes_text(b, false),
        _ => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The entries shown in hex, at the edges of their ranges, and their neighbours shown in
    /// decimal.
    #[test]
    fn the_entries_of_hex_nature() {
        let hex = |i: u16, s: u8| hex_entry(Address::new(i, s));
        for (i, s) in [
            (0x1000, 0),
            (0x1001, 0),
            (0x1002, 0),
            (0x1003, 1),
            (0x1003, 254),
            (0x1005, 0),
            (0x1010, 1),
            (0x1011, 1),
            (0x1012, 0),
            (0x1014, 0),
            (0x1016, 1),
            (0x1018, 1),
            (0x1018, 4),
            (0x1028, 1),
            (0x1200, 1),
            (0x1200, 2),
            (0x12FF, 2),
            (0x1400, 1),
            (0x15FF, 1),
            (0x1600, 1),
            (0x17FF, 8),
            (0x1800, 1),
            (0x19FF, 1),
            (0x1A00, 1),
            (0x1BFF, 254),
            (0x1F80, 0),
            (0x1F81, 1),
            (0x1F84, 1),
            (0x1F88, 127),
            (0x603F, 0),
            (0x6040, 0),
            (0x6041, 0),
            (0x6841, 0),
            (0x9841, 0),
            (0x60FD, 0),
            (0x60FE, 1),
            (0x6502, 0),
        ] {
            assert!(hex(i, s), "0x{i:04X}:{s:02X} in hex");
        }
        for (i, s) in [
            (0x1000, 1),
            (0x1003, 0),
            (0x1006, 0),
            (0x1010, 0),
            (0x1016, 0),
            (0x1017, 0),
            (0x1018, 0),
            (0x1018, 5),
            (0x1200, 0),
            (0x1200, 3),
            (0x1400, 2),
            (0x1600, 0),
            (0x1800, 0),
            (0x1800, 2),
            (0x1800, 5),
            (0x1A00, 0),
            (0x1C00, 1),
            (0x1F80, 1),
            (0x1F83, 1),
            (0x1F89, 1),
            (0x5FFF, 0),
            (0x6040, 1),
            (0x6060, 0),
            (0x6064, 0),
            (0x60FE, 0),
            (0xA041, 0),
        ] {
            assert!(!hex(i, s), "0x{i:04X}:{s:02X} in decimal");
        }
        assert!(mapping_entry(Address::new(0x1600, 1)));
        assert!(mapping_entry(Address::new(0x1BFF, 1)));
        assert!(!mapping_entry(Address::new(0x1600, 0)));
        assert!(!mapping_entry(Address::new(0x1800, 1)));
        assert!(!mapping_entry(Address::new(0x1C00, 1)));
    }

    /// Hex only for UNSIGNED types, padded to the type's width; a mapping with what it maps.
    #[test]
    fn hex_texts_and_mappings() {
        let shown = |i: u16, s: u8, t: DataType, v: u64| {
            let a = Address::new(i, s);
            let v = Value::Uint(v);
            with_mapping(a, &v, code_for(None, a, t).format(&v))
        };
        assert_eq!(shown(0x6041, 0, DataType::Unsigned16, 0x0637), "0x0637");
        assert_eq!(shown(0x1001, 0, DataType::Unsigned8, 0x81), "0x81");
        assert_eq!(
            shown(0x1A00, 1, DataType::Unsigned32, 0x6041_0010),
            "0x60410010 (0x6041:00, 16 bits)"
        );
        assert_eq!(
            shown(0x1600, 4, DataType::Unsigned32, 0x0005_0008),
            "0x00050008 (0x0005:00, 8 bits)"
        );
        assert_eq!(shown(0x1600, 2, DataType::Unsigned32, 0), "0x00000000");
        assert_eq!(shown(0x1017, 0, DataType::Unsigned16, 1000), "1000");
        let a = Address::new(0x603F, 0);
        assert!(!code_for(None, a, DataType::Integer16).hex);
        assert!(code_for(None, a, DataType::Unsigned16).hex);
    }

    /// A byte string is elided after 32 bytes unless it is asked for in full.
    #[test]
    fn long_byte_strings_are_elided() {
        let b: Vec<u8> = (0..=32).collect();
        assert_eq!(
            bytes_text(&b, false),
            "00 01 02 03 04 05 06 07 08 09 0A 0B 0C 0D 0E 0F 10 11 12 13 14 15 16 17 18 19 1A 1B \
             1C 1D 1E 1F … (33 bytes)"
        );
        assert!(bytes_text(&b, true).ends_with("1F 20"));
        assert!(bytes_head(&b, false).ends_with("1D 1E 1F …"));
        assert_eq!(bytes_head(&b, true), bytes_text(&b, true));
        assert_eq!(bytes_text(&b[..32], false).len(), 32 * 3 - 1);
        let v = Value::Bytes(b.clone());
        assert!(elided(&v, "all".into(), false).ends_with("(33 bytes)"));
        assert_eq!(elided(&v, "all".into(), true), "all");
        let v = Value::Bytes(b[..32].to_vec());
        assert_eq!(elided(&v, "all".into(), false), "all");
    }
}
