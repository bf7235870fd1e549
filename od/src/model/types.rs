//! CiA 301 basic data types (§7.1.4, table 44 "Object dictionary data types") and their names in the three
//! description formats: the 16-bit index used by EDS (CiA 306 §4.6.3) and XDD `dataType` attributes
//! (CiA 311), and the IEC 61131-3 style names of ESI (ETG.2000 §5.4.2) and of XDD parameter lists.

use std::fmt;

/// A basic data type of the object dictionary.
///
/// `Bit(n)` is the ESI `BITn` type (1 ≤ n ≤ 8): a field of `n` bits inside a PDO or a record. It has no
/// CiA 301 index of its own; EDS and XDD carry it as BOOLEAN (n = 1) or UNSIGNED8.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DataType {
    /// BOOLEAN (0x0001), ESI `BOOL`.
    Boolean,
    /// INTEGER8 (0x0002), ESI `SINT`.
    Integer8,
    /// INTEGER16 (0x0003), ESI `INT`.
    Integer16,
    /// INTEGER24 (0x0010), ESI `INT24`.
    Integer24,
    /// INTEGER32 (0x0004), ESI `DINT`.
    Integer32,
    /// INTEGER40 (0x0012).
    Integer40,
    /// INTEGER48 (0x0013).
    Integer48,
    /// INTEGER56 (0x0014).
    Integer56,
    /// INTEGER64 (0x0015), ESI `LINT`.
    Integer64,
    /// UNSIGNED8 (0x0005), ESI `USINT`.
    Unsigned8,
    /// UNSIGNED16 (0x0006), ESI `UINT`.
    Unsigned16,
    /// UNSIGNED24 (0x0016), ESI `UINT24`.
    Unsigned24,
    /// UNSIGNED32 (0x0007), ESI `UDINT`.
    Unsigned32,
    /// UNSIGNED40 (0x0018).
    Unsigned40,
    /// UNSIGNED48 (0x0019).
    Unsigned48,
    /// UNSIGNED56 (0x001A).
    Unsigned56,
    /// UNSIGNED64 (0x001B), ESI `ULINT`.
    Unsigned64,
    /// REAL32 (0x0008), ESI `REAL`.
    Real32,
    /// REAL64 (0x0011), ESI `LREAL`.
    Real64,
    /// VISIBLE_STRING (0x0009), ESI `STRING(n)`.
    VisibleString,
    /// OCTET_STRING (0x000A), ESI `OCTET_STRING(n)` / `ARRAY [0..n] OF BYTE`.
    OctetString,
    /// UNICODE_STRING (0x000B), ESI `UNICODE_STRING(n)`.
    UnicodeString,
    /// TIME_OF_DAY (0x000C): 28 bits of milliseconds after midnight, 4 reserved, 16 bits of days since
    /// 1 January 1984.
    TimeOfDay,
    /// TIME_DIFFERENCE (0x000D): the same layout as TIME_OF_DAY, counting a duration.
    TimeDifference,
    /// DOMAIN (0x000F): application-specific bytes of any length.
    Domain,
    /// ESI `BITn` (1 ≤ n ≤ 8).
    Bit(u8),
}

/// Every data type with a CiA 301 index, in index order (for property tests and tables).
pub const STANDARD_TYPES: &[DataType] = &[
    DataType::Boolean,
    DataType::Integer8,
    DataType::Integer16,
    DataType::Integer32,
    DataType::Unsigned8,
    DataType::Unsigned16,
    DataType::Unsigned32,
    DataType::Real32,
    DataType::VisibleString,
    DataType::OctetString,
    DataType::UnicodeString,
    DataType::TimeOfDay,
    DataType::TimeDifference,
    DataType::Domain,
    DataType::Integer24,
    DataType::Real64,
    DataType::Integer40,
    DataType::Integer48,
    DataType::Integer56,
    DataType::Integer64,
    DataType::Unsigned24,
    DataType::Unsigned40,
    DataType::Unsigned48,
    DataType::Unsigned56,
    DataType::Unsigned64,
];

impl DataType {
    /// The CiA 301 data-type index (EDS `DataType=`, XDD `dataType=`). `Bit(1)` answers BOOLEAN's index and
    /// the wider bit fields UNSIGNED8's, the nearest types those formats have.
    pub const fn index(self) -> u16 {
        match self {
            DataType::Boolean | DataType::Bit(1) => 0x0001,
            DataType::Integer8 => 0x0002,
            DataType::Integer16 => 0x0003,
            DataType::Integer32 => 0x0004,
            DataType::Unsigned8 | DataType::Bit(_) => 0x0005,
            DataType::Unsigned16 => 0x0006,
            DataType::Unsigned32 => 0x0007,
            DataType::Real32 => 0x0008,
            DataType::VisibleString => 0x0009,
            DataType::OctetString => 0x000A,
            DataType::UnicodeString => 0x000B,
            DataType::TimeOfDay => 0x000C,
            DataType::TimeDifference => 0x000D,
            DataType::Domain => 0x000F,
            DataType::Integer24 => 0x0010,
            DataType::Real64 => 0x0011,
            DataType::Integer40 => 0x0012,
            DataType::Integer48 => 0x0013,
            DataType::Integer56 => 0x0014,
            DataType::Integer64 => 0x0015,
            DataType::Unsigned24 => 0x0016,
            DataType::Unsigned40 => 0x0018,
            DataType::Unsigned48 => 0x0019,
            DataType::Unsigned56 => 0x001A,
            DataType::Unsigned64 => 0x001B,
        }
    }

    /// The type with CiA 301 index `index`, if it is a basic type.
    pub fn from_index(index: u16) -> Option<DataType> {
        STANDARD_TYPES.iter().copied().find(|t| t.index() == index)
    }

    /// Size in bits of a value of this type; `None` for the variable-length types (strings, DOMAIN).
    pub const fn bit_size(self) -> Option<u32> {
        Some(match self {
            DataType::Boolean => 1,
            DataType::Bit(n) => n as u32,
            DataType::Integer8 | DataType::Unsigned8 => 8,
            DataType::Integer16 | DataType::Unsigned16 => 16,
            DataType::Integer24 | DataType::Unsigned24 => 24,
            DataType::Integer32 | DataType::Unsigned32 | DataType::Real32 => 32,
            DataType::Integer40 | DataType::Unsigned40 => 40,
            DataType::Integer48
            | DataType::Unsigned48
            | DataType::TimeOfDay
            | DataType::TimeDifference => 48,
            DataType::Integer56 | DataType::Unsigned56 => 56,
            DataType::Integer64 | DataType::Unsigned64 | DataType::Real64 => 64,
            DataType::VisibleString
            | DataType::OctetString
            | DataType::UnicodeString
            | DataType::Domain => return None,
        })
    }

    /// Size in bytes of an encoded value (a BOOLEAN or bit field takes one byte in an SDO); `None` for the
    /// variable-length types.
    pub const fn byte_size(self) -> Option<usize> {
        match self.bit_size() {
            Some(bits) => Some((bits as usize).div_ceil(8)),
            None => None,
        }
    }

    /// True for the types whose length is not fixed by the type (strings and DOMAIN).
    pub const fn is_variable(self) -> bool {
        self.bit_size().is_none()
    }

    /// True for the signed integer types.
    pub const fn is_signed(self) -> bool {
        matches!(
            self,
            DataType::Integer8
                | DataType::Integer16
                | DataType::Integer24
                | DataType::Integer32
                | DataType::Integer40
                | DataType::Integer48
                | DataType::Integer56
                | DataType::Integer64
        )
    }

    /// True for the unsigned integer types, BOOLEAN and bit fields.
    pub const fn is_unsigned(self) -> bool {
        matches!(
            self,
            DataType::Boolean
                | DataType::Bit(_)
                | DataType::Unsigned8
                | DataType::Unsigned16
                | DataType::Unsigned24
                | DataType::Unsigned32
                | DataType::Unsigned40
                | DataType::Unsigned48
                | DataType::Unsigned56
                | DataType::Unsigned64
        )
    }

    /// True for REAL32 and REAL64.
    pub const fn is_real(self) -> bool {
        matches!(self, DataType::Real32 | DataType::Real64)
    }

    /// The inclusive range of an integer type as `i128`, or `None` for other types.
    pub const fn integer_range(self) -> Option<(i128, i128)> {
        if self.is_signed() {
            let bits = match self.bit_size() {
                Some(b) => b,
                None => return None,
            };
            let half = 1i128 << (bits - 1);
            Some((-half, half - 1))
        } else if self.is_unsigned() {
            let bits = match self.bit_size() {
                Some(b) => b,
                None => return None,
            };
            Some((0, (1i128 << bits) - 1))
        } else {
            None
        }
    }

    /// The CiA 301 name (`UNSIGNED16`, `VISIBLE_STRING`, …).
    pub const fn cia_name(self) -> &'static str {
        match self {
            DataType::Boolean => "BOOLEAN",
            DataType::Integer8 => "INTEGER8",
            DataType::Integer16 => "INTEGER16",
            DataType::Integer24 => "INTEGER24",
            DataType::Integer32 => "INTEGER32",
            DataType::Integer40 => "INTEGER40",
            DataType::Integer48 => "INTEGER48",
            DataType::Integer56 => "INTEGER56",
            DataType::Integer64 => "INTEGER64",
            DataType::Unsigned8 => "UNSIGNED8",
            DataType::Unsigned16 => "UNSIGNED16",
            DataType::Unsigned24 => "UNSIGNED24",
            DataType::Unsigned32 => "UNSIGNED32",
            DataType::Unsigned40 => "UNSIGNED40",
            DataType::Unsigned48 => "UNSIGNED48",
            DataType::Unsigned56 => "UNSIGNED56",
            DataType::Unsigned64 => "UNSIGNED64",
            DataType::Real32 => "REAL32",
            DataType::Real64 => "REAL64",
            DataType::VisibleString => "VISIBLE_STRING",
            DataType::OctetString => "OCTET_STRING",
            DataType::UnicodeString => "UNICODE_STRING",
            DataType::TimeOfDay => "TIME_OF_DAY",
            DataType::TimeDifference => "TIME_DIFFERENCE",
            DataType::Domain => "DOMAIN",
            DataType::Bit(1) => "BIT1",
            DataType::Bit(2) => "BIT2",
            DataType::Bit(3) => "BIT3",
            DataType::Bit(4) => "BIT4",
            DataType::Bit(5) => "BIT5",
            DataType::Bit(6) => "BIT6",
            DataType::Bit(7) => "BIT7",
            DataType::Bit(_) => "BIT8",
        }
    }

    /// The ESI (ETG.2000) base name: `UINT`, `DINT`, `BIT3`, `STRING`… For the variable-length types
    /// [`DataType::esi_name`] adds the length in brackets.
    pub const fn esi_base_name(self) -> &'static str {
        match self {
            DataType::Boolean => "BOOL",
            DataType::Integer8 => "SINT",
            DataType::Integer16 => "INT",
            DataType::Integer24 => "INT24",
            DataType::Integer32 => "DINT",
            DataType::Integer40 => "INT40",
            DataType::Integer48 => "INT48",
            DataType::Integer56 => "INT56",
            DataType::Integer64 => "LINT",
            DataType::Unsigned8 => "USINT",
            DataType::Unsigned16 => "UINT",
            DataType::Unsigned24 => "UINT24",
            DataType::Unsigned32 => "UDINT",
            DataType::Unsigned40 => "UINT40",
            DataType::Unsigned48 => "UINT48",
            DataType::Unsigned56 => "UINT56",
            DataType::Unsigned64 => "ULINT",
            DataType::Real32 => "REAL",
            DataType::Real64 => "LREAL",
            DataType::VisibleString => "STRING",
            DataType::OctetString => "OCTET_STRING",
            DataType::UnicodeString => "UNICODE_STRING",
            DataType::TimeOfDay => "TIME_OF_DAY",
            DataType::TimeDifference => "TIME_DIFFERENCE",
            DataType::Domain => "DOMAIN",
            DataType::Bit(_) => self.cia_name(),
        }
    }

    /// The ESI type name of a value of `bit_size` bits: `STRING(12)` for a 12-character string,
    /// `UINT` for UNSIGNED16.
    pub fn esi_name(self, bit_size: u32) -> String {
        match self {
            DataType::VisibleString | DataType::OctetString => {
                format!("{}({})", self.esi_base_name(), bit_size / 8)
            }
            DataType::UnicodeString => format!("{}({})", self.esi_base_name(), bit_size / 16),
            _ => self.esi_base_name().to_string(),
        }
    }

    /// Parses an ESI type name (`UINT`, `STRING(20)`, `BIT2`, `ARRAY [0..3] OF BYTE`, …), case-insensitively.
    /// Answers the type and, for sized strings, the length in bits that the name gives.
    pub fn from_esi_name(name: &str) -> Option<(DataType, Option<u32>)> {
        let name = name.trim();
        let upper = name.to_ascii_uppercase();
        if let Some(open) = upper.find('(') {
            let base = upper[..open].trim();
            let inner = upper[open + 1..].strip_suffix(')')?.trim();
            let n: u32 = inner.parse().ok()?;
            let (t, unit) = match base {
                "STRING" | "VISIBLE_STRING" => (DataType::VisibleString, 8),
                "OCTET_STRING" | "OCTETSTRING" => (DataType::OctetString, 8),
                "UNICODE_STRING" | "WSTRING" => (DataType::UnicodeString, 16),
                _ => return None,
            };
            return Some((t, Some(n.checked_mul(unit)?)));
        }
        // "ARRAY [0..n] OF BYTE" is how many ESIs spell an octet string.
        if let Some(rest) = upper.strip_prefix("ARRAY") {
            let rest = rest.trim();
            let (range, elem) = rest.split_once("OF")?;
            if elem.trim() != "BYTE" && elem.trim() != "USINT" {
                return None;
            }
            let range = range.trim().strip_prefix('[')?.strip_suffix(']')?;
            let (lo, hi) = range.split_once("..")?;
            let lo: u32 = lo.trim().parse().ok()?;
            let hi: u32 = hi.trim().parse().ok()?;
            let n = hi.checked_sub(lo)?.checked_add(1)?;
            return Some((DataType::OctetString, Some(n.checked_mul(8)?)));
        }
        let t = match upper.as_str() {
            "BOOL" | "BOOLEAN" => DataType::Boolean,
            // INTn and UINTn for the fixed sizes are how IgH and many generators spell them.
            "SINT" | "INT8" | "INTEGER8" => DataType::Integer8,
            "INT" | "INT16" | "INTEGER16" => DataType::Integer16,
            "INT24" | "INTEGER24" => DataType::Integer24,
            "DINT" | "INT32" | "INTEGER32" => DataType::Integer32,
            "INT40" | "INTEGER40" => DataType::Integer40,
            "INT48" | "INTEGER48" => DataType::Integer48,
            "INT56" | "INTEGER56" => DataType::Integer56,
            "LINT" | "INT64" | "INTEGER64" => DataType::Integer64,
            // ETG.1000.6's bit arrays BITARR8/16/32 are unsigned values of their size.
            "USINT" | "BYTE" | "UINT8" | "BITARR8" | "UNSIGNED8" => DataType::Unsigned8,
            "UINT" | "WORD" | "UINT16" | "BITARR16" | "UNSIGNED16" => DataType::Unsigned16,
            "UINT24" | "UNSIGNED24" => DataType::Unsigned24,
            "UDINT" | "DWORD" | "UINT32" | "BITARR32" | "UNSIGNED32" => DataType::Unsigned32,
            "UINT40" | "UNSIGNED40" => DataType::Unsigned40,
            "UINT48" | "UNSIGNED48" => DataType::Unsigned48,
            "UINT56" | "UNSIGNED56" => DataType::Unsigned56,
            "ULINT" | "LWORD" | "UINT64" | "UNSIGNED64" => DataType::Unsigned64,
            "REAL" | "REAL32" | "FLOAT" => DataType::Real32,
            "LREAL" | "REAL64" | "DOUBLE" => DataType::Real64,
            "STRING" | "VISIBLE_STRING" => DataType::VisibleString,
            "OCTET_STRING" => DataType::OctetString,
            "UNICODE_STRING" | "WSTRING" => DataType::UnicodeString,
            "TIME_OF_DAY" => DataType::TimeOfDay,
            "TIME_DIFFERENCE" => DataType::TimeDifference,
            "DOMAIN" => DataType::Domain,
            _ => {
                let n: u8 = upper.strip_prefix("BIT")?.parse().ok()?;
                if !(1..=8).contains(&n) {
                    return None;
                }
                if n == 1 {
                    // BIT1 and BOOL are the same single bit in process data.
                    return Some((DataType::Bit(1), None));
                }
                DataType::Bit(n)
            }
        };
        Some((t, None))
    }

    /// The XDD (CiA 311) parameter-list element name of this type: the ISO 15745 simple type (`UINT`,
    /// `BOOL`, `STRING`, …), or `BITSTRING` for the types that have none (the 24-, 40-, 48- and 56-bit
    /// integers, the time types, OCTET_STRING, DOMAIN, wider bit fields), as CANopenEditor writes them; the
    /// object's `dataType` attribute then says which type it is.
    pub const fn xdd_name(self) -> &'static str {
        match self {
            DataType::Boolean | DataType::Bit(1) => "BOOL",
            DataType::Integer8 => "SINT",
            DataType::Integer16 => "INT",
            DataType::Integer32 => "DINT",
            DataType::Integer64 => "LINT",
            DataType::Unsigned8 => "USINT",
            DataType::Unsigned16 => "UINT",
            DataType::Unsigned32 => "UDINT",
            DataType::Unsigned64 => "ULINT",
            DataType::Real32 => "REAL",
            DataType::Real64 => "LREAL",
            DataType::VisibleString => "STRING",
            DataType::UnicodeString => "WSTRING",
            _ => "BITSTRING",
        }
    }
}

impl fmt::Display for DataType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.cia_name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_ranges_are_the_types() {
        assert_eq!(DataType::Unsigned8.integer_range(), Some((0, 255)));
        assert_eq!(DataType::Integer8.integer_range(), Some((-128, 127)));
        assert_eq!(DataType::Unsigned16.integer_range(), Some((0, 65_535)));
        assert_eq!(
            DataType::Integer24.integer_range(),
            Some((-8_388_608, 8_388_607))
        );
        assert_eq!(
            DataType::Unsigned64.integer_range(),
            Some((0, i128::from(u64::MAX)))
        );
        assert_eq!(
            DataType::Integer64.integer_range(),
            Some((i128::from(i64::MIN), i128::from(i64::MAX)))
        );
        assert_eq!(DataType::Boolean.integer_range(), Some((0, 1)));
        assert_eq!(DataType::Bit(3).integer_range(), Some((0, 7)));
        assert_eq!(DataType::Real32.integer_range(), None);
        assert_eq!(DataType::VisibleString.integer_range(), None);
    }

    #[test]
    fn every_standard_type_round_trips_through_its_index() {
        for &t in STANDARD_TYPES {
            assert_eq!(DataType::from_index(t.index()), Some(t), "{t}");
        }
        assert_eq!(DataType::from_index(0x0017), None);
        assert_eq!(DataType::from_index(0x0000), None);
    }

    #[test]
    fn eds_indices_follow_cia_301_table_44() {
        assert_eq!(DataType::Boolean.index(), 0x0001);
        assert_eq!(DataType::Unsigned32.index(), 0x0007);
        assert_eq!(DataType::Domain.index(), 0x000F);
        assert_eq!(DataType::Integer24.index(), 0x0010);
        assert_eq!(DataType::Real64.index(), 0x0011);
        assert_eq!(DataType::Integer64.index(), 0x0015);
        assert_eq!(DataType::Unsigned24.index(), 0x0016);
        assert_eq!(DataType::Unsigned64.index(), 0x001B);
    }

    #[test]
    fn esi_names_parse_and_print() {
        assert_eq!(
            DataType::from_esi_name("UINT"),
            Some((DataType::Unsigned16, None))
        );
        assert_eq!(
            DataType::from_esi_name("dint"),
            Some((DataType::Integer32, None))
        );
        assert_eq!(
            DataType::from_esi_name("STRING(12)"),
            Some((DataType::VisibleString, Some(96)))
        );
        assert_eq!(
            DataType::from_esi_name("ARRAY [0..3] OF BYTE"),
            Some((DataType::OctetString, Some(32)))
        );
        assert_eq!(
            DataType::from_esi_name("BIT3"),
            Some((DataType::Bit(3), None))
        );
        assert_eq!(DataType::from_esi_name("BIT9"), None);
        assert_eq!(DataType::from_esi_name("DT1018"), None);
        assert_eq!(DataType::VisibleString.esi_name(96), "STRING(12)");
        assert_eq!(DataType::Unsigned32.esi_name(32), "UDINT");
        for &t in STANDARD_TYPES {
            let bits = t.bit_size().unwrap_or(64);
            let (back, _) = DataType::from_esi_name(&t.esi_name(bits)).unwrap();
            assert_eq!(back, t, "{t}");
        }
    }

    #[test]
    fn sizes_and_ranges() {
        assert_eq!(DataType::Unsigned24.byte_size(), Some(3));
        assert_eq!(DataType::TimeOfDay.byte_size(), Some(6));
        assert_eq!(DataType::Boolean.byte_size(), Some(1));
        assert_eq!(DataType::Domain.byte_size(), None);
        assert_eq!(
            DataType::Integer24.integer_range(),
            Some((-8_388_608, 8_388_607))
        );
        assert_eq!(
            DataType::Unsigned64.integer_range(),
            Some((0, u64::MAX as i128))
        );
        assert_eq!(DataType::Bit(3).integer_range(), Some((0, 7)));
        assert_eq!(DataType::Real32.integer_range(), None);
    }
}
