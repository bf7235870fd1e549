//! Numbers and register values as IgH's tool reads and writes them: numbers in decimal, octal
//! (prefix `0`) or hexadecimal (prefix `0x`), and the `--type`s of `reg_read` and `reg_write`.

/// A number as IgH's tool takes one (its streams' base guessing): `0x…` hexadecimal, `0…`
/// octal, else decimal; a leading `-` for a negative one. `None` for anything else.
pub fn parse_number(text: &str) -> Option<i128> {
    let t = text.trim();
    let (negative, digits) = match t.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, t.strip_prefix('+').unwrap_or(t)),
    };
    let (radix, digits) = if let Some(hex) = digits
        .strip_prefix("0x")
        .or_else(|| digits.strip_prefix("0X"))
    {
        (16, hex)
    } else if digits.len() > 1 && digits.starts_with('0') {
        (8, &digits[1..])
    } else {
        (10, digits)
    };
    if digits.is_empty() || digits.starts_with(['+', '-']) {
        return None;
    }
    let value = i128::from_str_radix(digits, radix).ok()?;
    Some(if negative { -value } else { value })
}

/// A `--type` of `reg-read` and `reg-write`: IgH's `int8`…`uint64`, `string` and (for reads)
/// `raw`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RegType {
    /// A signed integer of this many bytes (1, 2, 4 or 8).
    Int(usize),
    /// An unsigned integer of this many bytes.
    Uint(usize),
    /// Text: the bytes as they are.
    String,
    /// The bytes in hex (reads only; also what a read without `--type` shows).
    Raw,
}

/// `data`'s first 8 bytes at most as an unsigned little-endian number.
fn unsigned_le(data: &[u8]) -> u128 {
    let mut le = [0u8; 16];
    let n = data.len().min(8);
    le[..n].copy_from_slice(&data[..n]);
    u128::from_le_bytes(le)
}

impl RegType {
    /// The type IgH names `name`.
    pub fn parse(name: &str) -> Option<RegType> {
        Some(match name {
            "int8" => RegType::Int(1),
            "int16" => RegType::Int(2),
            "int32" => RegType::Int(4),
            "int64" => RegType::Int(8),
            "uint8" => RegType::Uint(1),
            "uint16" => RegType::Uint(2),
            "uint32" => RegType::Uint(4),
            "uint64" => RegType::Uint(8),
            "string" => RegType::String,
            "raw" => RegType::Raw,
            _ => return None,
        })
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            RegType::Int(1) => "int8",
            RegType::Int(2) => "int16",
            RegType::Int(4) => "int32",
            RegType::Int(_) => "int64",
            RegType::Uint(1) => "uint8",
            RegType::Uint(2) => "uint16",
            RegType::Uint(4) => "uint32",
            RegType::Uint(_) => "uint64",
            RegType::String => "string",
            RegType::Raw => "raw",
        }
    }

    /// The bytes a value of the type has, when the type says (the integers).
    pub fn size(self) -> Option<usize> {
        match self {
            RegType::Int(n) | RegType::Uint(n) => Some(n),
            RegType::String | RegType::Raw => None,
        }
    }

    /// The integer `data` holds (little-endian, its first 8 bytes at most) for an integer type:
    /// its top bit the sign for a signed one. `None` for `string` and `raw`.
    pub fn value(self, data: &[u8]) -> Option<i128> {
        let unsigned = unsigned_le(data);
        match self {
            RegType::Uint(_) => Some(unsigned as i128),
            RegType::Int(_) => {
                let shift = 128 - 8 * (data.len().clamp(1, 8) as u32);
                Some(((unsigned << shift) as i128) >> shift)
            }
            RegType::String | RegType::Raw => None,
        }
    }

    /// `data` (little-endian, as long as the type says) as IgH's `reg_read` prints it: an integer
    /// as `0x` and its lower-case hex digits, two per byte, then its decimal value (`0x0130 304`);
    /// a string as its text; raw bytes as `0x11 0x00 0x02`. The line ends with a line break.
    pub fn format(self, data: &[u8]) -> String {
        if let Some(value) = self.value(data) {
            let unsigned = unsigned_le(data);
            return format!("0x{unsigned:0w$x} {value}\n", w = 2 * data.len().min(8));
        }
        if self == RegType::String {
            return format!("{}\n", String::from_utf8_lossy(data));
        }
        let hex: Vec<String> = data.iter().map(|b| format!("0x{b:02x}")).collect();
        format!("{}\n", hex.join(" "))
    }

    /// The bytes `reg-write` writes for `text` of this type: an integer in its width,
    /// little-endian (refused outside the type's range), a string's bytes. `None` for text that is
    /// no value of the type (and for `raw`, which is no type to write).
    pub fn encode(self, text: &str) -> Option<Vec<u8>> {
        match self {
            RegType::Int(n) => {
                let v = parse_number(text)?;
                let half = 1i128 << (8 * n - 1);
                (-half..half)
                    .contains(&v)
                    .then(|| v.to_le_bytes()[..n].to_vec())
            }
            RegType::Uint(n) => {
                let v = parse_number(text)?;
                (0..1i128 << (8 * n))
                    .contains(&v)
                    .then(|| v.to_le_bytes()[..n].to_vec())
            }
            RegType::String => Some(text.as_bytes().to_vec()),
            RegType::Raw => None,
        }
    }
}
