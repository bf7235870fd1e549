//! Typed values of the basic data types, their little-endian encoding (CiA 301 §7.1.6 "Encoding of data
//! types": least significant byte first) and their text forms in description files (CiA 306 §4.6.2).

use std::fmt;

use crate::types::DataType;

/// A value of one of the basic data types.
///
/// Integers of every width are held as `i64`/`u64`; the data type that goes with a value says how many
/// bytes it takes on the wire.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// BOOLEAN or a one-bit field.
    Bool(bool),
    /// Any signed integer type.
    Int(i64),
    /// Any unsigned integer type or bit field.
    Uint(u64),
    /// REAL32.
    Real32(f32),
    /// REAL64.
    Real64(f64),
    /// VISIBLE_STRING.
    String(String),
    /// OCTET_STRING or DOMAIN.
    Bytes(Vec<u8>),
    /// UNICODE_STRING, as UTF-16 code units.
    Unicode(Vec<u16>),
    /// TIME_OF_DAY or TIME_DIFFERENCE.
    Time(TimeValue),
}

/// TIME_OF_DAY / TIME_DIFFERENCE (CiA 301 §7.1.6.5): milliseconds (28 bits) and days (16 bits).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct TimeValue {
    /// Milliseconds after midnight (TIME_OF_DAY) or of the duration's last day; at most 2^28 − 1.
    pub ms: u32,
    /// Days since 1 January 1984 (TIME_OF_DAY) or whole days of the duration.
    pub days: u16,
}

/// Why bytes or text could not be turned into a value of a type.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ValueError {
    /// Fewer bytes than the type takes.
    #[error("{data_type} takes {expected} bytes, got {got}")]
    TooShort {
        /// The type.
        data_type: DataType,
        /// Bytes the type takes.
        expected: usize,
        /// Bytes given.
        got: usize,
    },
    /// More bytes than the type takes.
    #[error("{data_type} takes {expected} bytes, got {got}")]
    TooLong {
        /// The type.
        data_type: DataType,
        /// Bytes the type takes.
        expected: usize,
        /// Bytes given.
        got: usize,
    },
    /// Bytes of the right length that are no valid value (a BOOLEAN other than 0 or 1, a string that is
    /// not text, a bit field with bits set beyond its width).
    #[error("not a valid {data_type}: {reason}")]
    Invalid {
        /// The type.
        data_type: DataType,
        /// What was wrong.
        reason: String,
    },
    /// A value of another kind than the type holds.
    #[error("a {got} value cannot be a {data_type}")]
    WrongKind {
        /// The type.
        data_type: DataType,
        /// The kind of value given.
        got: &'static str,
    },
    /// A number outside what the type can hold.
    #[error("{value} does not fit in {data_type}{}", data_type.integer_range().map(|(lo, hi)| format!(", {lo} to {hi}")).unwrap_or_default())]
    OutOfRange {
        /// The type.
        data_type: DataType,
        /// The number, as written.
        value: String,
    },
    /// Text that is no value of the type.
    #[error("`{text}` is not a {data_type} value: {reason}")]
    BadText {
        /// The type.
        data_type: DataType,
        /// The text.
        text: String,
        /// What was expected.
        reason: &'static str,
    },
}

impl Value {
    /// A short name of the kind of value, for messages.
    pub const fn kind(&self) -> &'static str {
        match self {
            Value::Bool(_) => "boolean",
            Value::Int(_) => "signed integer",
            Value::Uint(_) => "unsigned integer",
            Value::Real32(_) => "REAL32",
            Value::Real64(_) => "REAL64",
            Value::String(_) => "string",
            Value::Bytes(_) => "byte string",
            Value::Unicode(_) => "unicode string",
            Value::Time(_) => "time",
        }
    }

    /// The zero value of a type (empty for the variable-length types).
    pub fn zero(data_type: DataType) -> Value {
        match data_type {
            DataType::Boolean => Value::Bool(false),
            DataType::Real32 => Value::Real32(0.0),
            DataType::Real64 => Value::Real64(0.0),
            DataType::VisibleString => Value::String(String::new()),
            DataType::OctetString | DataType::Domain => Value::Bytes(Vec::new()),
            DataType::UnicodeString => Value::Unicode(Vec::new()),
            DataType::TimeOfDay | DataType::TimeDifference => Value::Time(TimeValue::default()),
            t if t.is_signed() => Value::Int(0),
            _ => Value::Uint(0),
        }
    }

    /// The value as an `i128`, for integer kinds and booleans.
    pub fn as_i128(&self) -> Option<i128> {
        match *self {
            Value::Bool(b) => Some(b as i128),
            Value::Int(v) => Some(v as i128),
            Value::Uint(v) => Some(v as i128),
            _ => None,
        }
    }

    /// The value as an `f64`, for numeric kinds.
    pub fn as_f64(&self) -> Option<f64> {
        match *self {
            Value::Real32(v) => Some(v as f64),
            Value::Real64(v) => Some(v),
            _ => self.as_i128().map(|v| v as f64),
        }
    }

    /// Decodes `bytes` as a value of `data_type`. Fixed-size types need exactly their size; a bit field
    /// may not have bits set beyond its width.
    pub fn decode(data_type: DataType, bytes: &[u8]) -> Result<Value, ValueError> {
        if let Some(size) = data_type.byte_size() {
            if bytes.len() < size {
                return Err(ValueError::TooShort {
                    data_type,
                    expected: size,
                    got: bytes.len(),
                });
            }
            if bytes.len() > size {
                return Err(ValueError::TooLong {
                    data_type,
                    expected: size,
                    got: bytes.len(),
                });
            }
        }
        let mut raw = [0u8; 8];
        let n = bytes.len().min(8);
        raw[..n].copy_from_slice(&bytes[..n]);
        let unsigned = u64::from_le_bytes(raw);
        Ok(match data_type {
            DataType::Boolean => match bytes[0] {
                0 => Value::Bool(false),
                1 => Value::Bool(true),
                other => {
                    return Err(ValueError::Invalid {
                        data_type,
                        reason: format!("0x{other:02X} is neither 0 nor 1"),
                    })
                }
            },
            DataType::Bit(width) => {
                if unsigned >> width != 0 {
                    return Err(ValueError::Invalid {
                        data_type,
                        reason: format!("0x{unsigned:02X} has bits set beyond bit {}", width - 1),
                    });
                }
                Value::Uint(unsigned)
            }
            DataType::Real32 => Value::Real32(f32::from_le_bytes([raw[0], raw[1], raw[2], raw[3]])),
            DataType::Real64 => Value::Real64(f64::from_le_bytes(raw)),
            DataType::VisibleString => match std::str::from_utf8(bytes) {
                Ok(s) => Value::String(s.to_string()),
                Err(_) => Value::String(bytes.iter().map(|&b| b as char).collect()),
            },
            DataType::OctetString | DataType::Domain => Value::Bytes(bytes.to_vec()),
            DataType::UnicodeString => {
                if bytes.len() % 2 == 1 {
                    return Err(ValueError::Invalid {
                        data_type,
                        reason: format!(
                            "{} bytes is not a whole number of UTF-16 units",
                            bytes.len()
                        ),
                    });
                }
                Value::Unicode(
                    bytes
                        .chunks_exact(2)
                        .map(|c| u16::from_le_bytes([c[0], c[1]]))
                        .collect(),
                )
            }
            DataType::TimeOfDay | DataType::TimeDifference => Value::Time(TimeValue {
                ms: u32::from_le_bytes([raw[0], raw[1], raw[2], raw[3]]) & 0x0FFF_FFFF,
                days: u16::from_le_bytes([raw[4], raw[5]]),
            }),
            t if t.is_signed() => {
                let bits = t.bit_size().unwrap_or(64);
                let shift = 64 - bits;
                Value::Int(((unsigned << shift) as i64) >> shift)
            }
            _ => Value::Uint(unsigned),
        })
    }

    /// Encodes the value as `data_type`, little-endian. Fails when the value is of another kind or does
    /// not fit in the type.
    pub fn encode(&self, data_type: DataType) -> Result<Vec<u8>, ValueError> {
        let wrong = || ValueError::WrongKind {
            data_type,
            got: self.kind(),
        };
        match data_type {
            DataType::Real32 => match *self {
                Value::Real32(v) => Ok(v.to_le_bytes().to_vec()),
                _ => Err(wrong()),
            },
            DataType::Real64 => match *self {
                Value::Real64(v) => Ok(v.to_le_bytes().to_vec()),
                Value::Real32(v) => Ok((v as f64).to_le_bytes().to_vec()),
                _ => Err(wrong()),
            },
            DataType::VisibleString => match self {
                Value::String(s) => Ok(s.as_bytes().to_vec()),
                _ => Err(wrong()),
            },
            DataType::OctetString | DataType::Domain => match self {
                Value::Bytes(b) => Ok(b.clone()),
                _ => Err(wrong()),
            },
            DataType::UnicodeString => match self {
                Value::Unicode(u) => Ok(u.iter().flat_map(|c| c.to_le_bytes()).collect()),
                Value::String(s) => Ok(s.encode_utf16().flat_map(|c| c.to_le_bytes()).collect()),
                _ => Err(wrong()),
            },
            DataType::TimeOfDay | DataType::TimeDifference => match *self {
                Value::Time(t) => {
                    if t.ms > 0x0FFF_FFFF {
                        return Err(ValueError::OutOfRange {
                            data_type,
                            value: t.ms.to_string(),
                        });
                    }
                    let mut out = t.ms.to_le_bytes().to_vec();
                    out.extend_from_slice(&t.days.to_le_bytes());
                    Ok(out)
                }
                _ => Err(wrong()),
            },
            t => {
                let v = self.as_i128().ok_or_else(wrong)?;
                let (lo, hi) = t.integer_range().ok_or_else(wrong)?;
                if v < lo || v > hi {
                    return Err(ValueError::OutOfRange {
                        data_type,
                        value: v.to_string(),
                    });
                }
                let size = t.byte_size().unwrap_or(8);
                Ok((v as i64 as u64).to_le_bytes()[..size].to_vec())
            }
        }
    }

    /// Parses the text form of a value as description files write it (CiA 306 §4.6.2): integers in
    /// decimal, `0x` hexadecimal or leading-zero octal with an optional sign; reals in decimal notation, or
    /// as their IEEE 754 bits in hexadecimal (Lely);
    /// strings as written; octet strings and domains as hexadecimal digits (spaces allowed); times as
    /// `days:ms`, `days ms` (Lely's form) or a plain millisecond count.
    pub fn parse_text(data_type: DataType, text: &str) -> Result<Value, ValueError> {
        let bad = |reason| ValueError::BadText {
            data_type,
            text: text.to_string(),
            reason,
        };
        let t = text.trim();
        match data_type {
            DataType::VisibleString => Ok(Value::String(text.to_string())),
            DataType::UnicodeString => Ok(Value::Unicode(text.encode_utf16().collect())),
            DataType::OctetString | DataType::Domain => parse_hex_bytes(t)
                .map(Value::Bytes)
                .ok_or_else(|| bad("expected hexadecimal byte digits")),
            // Hexadecimal text is the IEEE 754 bit pattern, as Lely writes reals (`0x40490FDB`, π).
            DataType::Real32 if is_hex(t) => parse_integer(t)
                .and_then(|v| u32::try_from(v).ok())
                .map(f32::from_bits)
                .filter(|v| v.is_finite())
                .map(Value::Real32)
                .ok_or_else(|| bad("expected the 32 bits of a finite REAL32")),
            DataType::Real64 if is_hex(t) => parse_integer(t)
                .and_then(|v| u64::try_from(v).ok())
                .map(f64::from_bits)
                .filter(|v| v.is_finite())
                .map(Value::Real64)
                .ok_or_else(|| bad("expected the 64 bits of a finite REAL64")),
            DataType::Real32 => parse_real(t)
                .map(|v| v as f32)
                .filter(|v| v.is_finite())
                .map(Value::Real32)
                .ok_or_else(|| bad("expected a decimal number within the REAL32 range")),
            DataType::Real64 => parse_real(t)
                .map(Value::Real64)
                .ok_or_else(|| bad("expected a decimal number")),
            DataType::TimeOfDay | DataType::TimeDifference => {
                // `days:ms`, or `days ms` as Lely writes and reads them.
                let split = t
                    .split_once(':')
                    .or_else(|| t.split_once(|c: char| c.is_ascii_whitespace()));
                let (days, ms) = match split {
                    Some((d, m)) => (
                        parse_integer(d.trim()).ok_or_else(|| bad("expected days:milliseconds"))?,
                        parse_integer(m.trim()).ok_or_else(|| bad("expected days:milliseconds"))?,
                    ),
                    None => (
                        0,
                        parse_integer(t).ok_or_else(|| bad("expected milliseconds"))?,
                    ),
                };
                let days = u16::try_from(days).map_err(|_| bad("days out of range 0..65535"))?;
                let ms = u32::try_from(ms)
                    .ok()
                    .filter(|&m| m <= 0x0FFF_FFFF)
                    .ok_or_else(|| bad("milliseconds out of range 0..268435455"))?;
                Ok(Value::Time(TimeValue { ms, days }))
            }
            DataType::Boolean => match t.to_ascii_lowercase().as_str() {
                "true" => Ok(Value::Bool(true)),
                "false" => Ok(Value::Bool(false)),
                _ => match parse_integer(t) {
                    Some(0) => Ok(Value::Bool(false)),
                    Some(1) => Ok(Value::Bool(true)),
                    _ => Err(bad("expected 0, 1, true or false")),
                },
            },
            dt => {
                let v = parse_integer(t).ok_or_else(|| bad("expected an integer"))?;
                let (lo, hi) = dt
                    .integer_range()
                    .ok_or_else(|| bad("not a numeric type"))?;
                // Hexadecimal text of a signed type may spell the two's complement bit pattern
                // (`0xFFFF` for INTEGER16 −1), as many description files do.
                let v = if dt.is_signed() && v > hi && is_hex(t) && v <= 2 * hi + 1 {
                    v - 2 * (hi + 1)
                } else {
                    v
                };
                if v < lo || v > hi {
                    return Err(ValueError::OutOfRange {
                        data_type: dt,
                        value: t.to_string(),
                    });
                }
                Ok(if dt.is_signed() {
                    Value::Int(v as i64)
                } else {
                    Value::Uint(v as u64)
                })
            }
        }
    }

    /// The text form [`Value::parse_text`] reads back: hexadecimal for unsigned integers (`0x` and at least
    /// the type's width in digits), decimal for signed ones and reals, hex digits for byte strings.
    pub fn to_text(&self, data_type: DataType) -> String {
        match self {
            Value::Bool(b) => (*b as u8).to_string(),
            Value::Uint(v) => {
                let digits = data_type.byte_size().unwrap_or(1) * 2;
                format!("0x{v:0digits$X}")
            }
            Value::Int(v) => v.to_string(),
            Value::Real32(v) => format_real(*v as f64, true),
            Value::Real64(v) => format_real(*v, false),
            Value::String(s) => s.clone(),
            Value::Bytes(b) => b.iter().map(|x| format!("{x:02X}")).collect(),
            Value::Unicode(u) => String::from_utf16_lossy(u),
            Value::Time(t) => format!("{}:{}", t.days, t.ms),
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Bool(b) => write!(f, "{b}"),
            Value::Int(v) => write!(f, "{v}"),
            Value::Uint(v) => write!(f, "{v}"),
            Value::Real32(v) => write!(f, "{v}"),
            Value::Real64(v) => write!(f, "{v}"),
            Value::String(s) => write!(f, "{s:?}"),
            Value::Bytes(b) => {
                for x in b {
                    write!(f, "{x:02X}")?;
                }
                Ok(())
            }
            Value::Unicode(u) => write!(f, "{:?}", String::from_utf16_lossy(u)),
            Value::Time(t) => write!(f, "{} d {} ms", t.days, t.ms),
        }
    }
}

fn is_hex(text: &str) -> bool {
    let t = text.trim_start_matches(['+', '-']);
    t.starts_with("0x") || t.starts_with("0X")
}

/// Parses an integer as CiA 306 writes them: optional sign, then `0x…` hexadecimal, `0…` octal or decimal.
pub fn parse_integer(text: &str) -> Option<i128> {
    let t = text.trim();
    let (neg, body) = match t.as_bytes().first()? {
        b'-' => (true, &t[1..]),
        b'+' => (false, &t[1..]),
        _ => (false, t),
    };
    if body.is_empty() || body.starts_with(['+', '-']) {
        return None;
    }
    let magnitude = if let Some(hex) = body.strip_prefix("0x").or_else(|| body.strip_prefix("0X")) {
        if hex.is_empty() || hex.len() > 32 {
            return None;
        }
        u128::from_str_radix(hex, 16).ok()?
    } else if body.len() > 1 && body.starts_with('0') && body.bytes().all(|b| b.is_ascii_digit()) {
        u128::from_str_radix(&body[1..], 8).ok()?
    } else {
        if !body.bytes().all(|b| b.is_ascii_digit()) || body.len() > 39 {
            return None;
        }
        body.parse::<u128>().ok()?
    };
    let magnitude = i128::try_from(magnitude).ok()?;
    Some(if neg { -magnitude } else { magnitude })
}

fn parse_real(text: &str) -> Option<f64> {
    let lower = text.to_ascii_lowercase();
    if lower.contains("inf") || lower.contains("nan") || text.is_empty() {
        // Description files hold finite limits and defaults only.
        return None;
    }
    text.parse::<f64>().ok().filter(|v| v.is_finite())
}

fn format_real(v: f64, single: bool) -> String {
    // The shortest text that parses back to the same value.
    let s = if single {
        format!("{:?}", v as f32)
    } else {
        format!("{v:?}")
    };
    s
}

/// Parses hexadecimal byte digits (`0102AB`, `01 02 ab`, optionally with a `0x` prefix).
pub fn parse_hex_bytes(text: &str) -> Option<Vec<u8>> {
    let t = text.trim();
    let t = t
        .strip_prefix("0x")
        .or_else(|| t.strip_prefix("0X"))
        .unwrap_or(t);
    let digits: Vec<u8> = t.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
    if digits.len() % 2 == 1 {
        return None;
    }
    digits
        .chunks_exact(2)
        .map(|pair| {
            let s = std::str::from_utf8(pair).ok()?;
            u8::from_str_radix(s, 16).ok()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::types::STANDARD_TYPES;

    #[test]
    fn little_endian_golden_bytes() {
        assert_eq!(
            Value::Uint(0x1234).encode(DataType::Unsigned16).unwrap(),
            [0x34, 0x12]
        );
        assert_eq!(
            Value::Int(-2).encode(DataType::Integer24).unwrap(),
            [0xFE, 0xFF, 0xFF]
        );
        assert_eq!(
            Value::Uint(0x0102_0304_0506)
                .encode(DataType::Unsigned48)
                .unwrap(),
            [6, 5, 4, 3, 2, 1]
        );
        assert_eq!(
            Value::Real32(1.0).encode(DataType::Real32).unwrap(),
            [0, 0, 0x80, 0x3F]
        );
        assert_eq!(
            Value::Time(TimeValue {
                ms: 0x0123_4567,
                days: 0xABCD
            })
            .encode(DataType::TimeOfDay)
            .unwrap(),
            [0x67, 0x45, 0x23, 0x01, 0xCD, 0xAB]
        );
        assert_eq!(
            Value::decode(DataType::Integer24, &[0xFE, 0xFF, 0xFF]).unwrap(),
            Value::Int(-2)
        );
        assert_eq!(
            Value::decode(DataType::Integer8, &[0x80]).unwrap(),
            Value::Int(-128),
            "sign extension"
        );
    }

    #[test]
    fn decode_refuses_wrong_lengths_and_invalid_bytes() {
        assert_eq!(
            Value::decode(DataType::Unsigned32, &[1, 2, 3]),
            Err(ValueError::TooShort {
                data_type: DataType::Unsigned32,
                expected: 4,
                got: 3
            })
        );
        assert_eq!(
            Value::decode(DataType::Unsigned8, &[1, 2]),
            Err(ValueError::TooLong {
                data_type: DataType::Unsigned8,
                expected: 1,
                got: 2
            })
        );
        assert!(matches!(
            Value::decode(DataType::Boolean, &[2]),
            Err(ValueError::Invalid { .. })
        ));
        assert!(matches!(
            Value::decode(DataType::Bit(3), &[8]),
            Err(ValueError::Invalid { .. })
        ));
        assert_eq!(
            Value::decode(DataType::Bit(3), &[7]).unwrap(),
            Value::Uint(7)
        );
        assert!(matches!(
            Value::decode(DataType::UnicodeString, &[1, 2, 3]),
            Err(ValueError::Invalid { .. })
        ));
    }

    #[test]
    fn encode_refuses_values_that_do_not_fit() {
        assert!(matches!(
            Value::Uint(256).encode(DataType::Unsigned8),
            Err(ValueError::OutOfRange { .. })
        ));
        assert!(matches!(
            Value::Int(-129).encode(DataType::Integer8),
            Err(ValueError::OutOfRange { .. })
        ));
        assert!(matches!(
            Value::String("x".into()).encode(DataType::Unsigned8),
            Err(ValueError::WrongKind { .. })
        ));
    }

    #[test]
    fn text_forms_of_cia_306() {
        assert_eq!(
            Value::parse_text(DataType::Unsigned16, "0x1A00").unwrap(),
            Value::Uint(0x1A00)
        );
        assert_eq!(
            Value::parse_text(DataType::Unsigned16, "010").unwrap(),
            Value::Uint(8)
        );
        assert_eq!(
            Value::parse_text(DataType::Integer16, "-5").unwrap(),
            Value::Int(-5)
        );
        assert_eq!(
            Value::parse_text(DataType::Integer16, "0xFFFF").unwrap(),
            Value::Int(-1)
        );
        assert_eq!(
            Value::parse_text(DataType::Integer16, "0x7FFF").unwrap(),
            Value::Int(0x7FFF)
        );
        assert!(Value::parse_text(DataType::Integer16, "40000").is_err());
        assert!(Value::parse_text(DataType::Unsigned8, "0x100").is_err());
        assert!(Value::parse_text(DataType::Unsigned8, "12ab").is_err());
        assert!(Value::parse_text(DataType::Unsigned8, "").is_err());
        assert!(Value::parse_text(DataType::Unsigned8, "--1").is_err());
        assert_eq!(
            Value::parse_text(DataType::Boolean, "TRUE").unwrap(),
            Value::Bool(true)
        );
        assert_eq!(
            Value::parse_text(DataType::OctetString, "01 02 ab").unwrap(),
            Value::Bytes(vec![1, 2, 0xAB])
        );
        assert_eq!(
            Value::parse_text(DataType::Real32, "1.5").unwrap(),
            Value::Real32(1.5)
        );
        assert!(Value::parse_text(DataType::Real64, "nan").is_err());
        assert!(Value::parse_text(DataType::Real32, "1e39").is_err());
        assert_eq!(
            Value::parse_text(DataType::Real64, "1e39").unwrap(),
            Value::Real64(1e39)
        );
        assert_eq!(
            Value::parse_text(DataType::TimeOfDay, "12:34").unwrap(),
            Value::Time(TimeValue { ms: 34, days: 12 })
        );
        // Lely's `days ms`.
        assert_eq!(
            Value::parse_text(DataType::TimeDifference, "365  43200000").unwrap(),
            Value::Time(TimeValue {
                ms: 43_200_000,
                days: 365
            })
        );
        assert_eq!(
            Value::parse_text(DataType::TimeOfDay, "7").unwrap(),
            Value::Time(TimeValue { ms: 7, days: 0 })
        );
        assert_eq!(
            Value::Uint(0x80).to_text(DataType::Unsigned32),
            "0x00000080"
        );
        assert_eq!(Value::Int(-3).to_text(DataType::Integer8), "-3");
    }

    #[test]
    fn every_type_round_trips_zero_and_text() {
        for &t in STANDARD_TYPES {
            let zero = Value::zero(t);
            let bytes = zero.encode(t).unwrap();
            assert_eq!(bytes.len(), t.byte_size().unwrap_or(0), "{t}");
            assert_eq!(Value::decode(t, &bytes).unwrap(), zero, "{t}");
            assert_eq!(Value::parse_text(t, &zero.to_text(t)).unwrap(), zero, "{t}");
        }
    }

    proptest::proptest! {
        #[test]
        fn integers_round_trip_through_bytes_and_text(v in proptest::prelude::any::<i64>(), which in 0usize..16) {
            let types = [
                DataType::Integer8, DataType::Integer16, DataType::Integer24, DataType::Integer32,
                DataType::Integer40, DataType::Integer48, DataType::Integer56, DataType::Integer64,
                DataType::Unsigned8, DataType::Unsigned16, DataType::Unsigned24, DataType::Unsigned32,
                DataType::Unsigned40, DataType::Unsigned48, DataType::Unsigned56, DataType::Unsigned64,
            ];
            let t = types[which];
            let (lo, hi) = t.integer_range().unwrap();
            let span = hi - lo + 1;
            let x = lo + (v as i128).rem_euclid(span);
            let value = if t.is_signed() { Value::Int(x as i64) } else { Value::Uint(x as u64) };
            let bytes = value.encode(t).unwrap();
            proptest::prop_assert_eq!(Value::decode(t, &bytes).unwrap(), value.clone());
            proptest::prop_assert_eq!(Value::parse_text(t, &value.to_text(t)).unwrap(), value);
        }

        #[test]
        fn reals_round_trip_through_text(v in proptest::num::f64::NORMAL) {
            let value = Value::Real64(v);
            proptest::prop_assert_eq!(Value::parse_text(DataType::Real64, &value.to_text(DataType::Real64)).unwrap(), value);
            let single = Value::Real32(v as f32);
            if (v as f32).is_finite() {
                proptest::prop_assert_eq!(Value::parse_text(DataType::Real32, &single.to_text(DataType::Real32)).unwrap(), single);
            }
        }
    }
}
