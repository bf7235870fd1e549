//! The data types, limits and values of the strict reading: each value a number of its type within
//! its limits, `$NODEID+N` allowing for node-IDs 1 to 127.

use crate::lint::{given, py_int, Linter};

/// The range of each basic data type.
fn range(data_type: i128) -> Option<(f64, f64)> {
    Some(match data_type {
        0x01 => (0.0, 1.0),
        0x02 => (-128.0, 127.0),
        0x03 => (-32768.0, 32767.0),
        0x04 => (-2147483648.0, 2147483647.0),
        0x05 => (0.0, 255.0),
        0x06 => (0.0, 65535.0),
        0x07 => (0.0, 4294967295.0),
        0x08 => (-f32::MAX as f64, f32::MAX as f64),
        0x10 => (-8388608.0, 8388607.0),
        0x11 => (-f64::MAX, f64::MAX),
        0x12 => (-549755813888.0, 549755813887.0),
        0x13 => (-140737488355328.0, 140737488355327.0),
        0x14 => (-36028797018963968.0, 36028797018963967.0),
        0x15 => (-9223372036854775808.0, 9223372036854775807.0),
        0x16 => (0.0, 16777215.0),
        0x18 => (0.0, 1099511627775.0),
        0x19 => (0.0, 281474976710655.0),
        0x1A => (0.0, 72057594037927935.0),
        0x1B => (0.0, 18446744073709551615.0),
        _ => return None,
    })
}

/// The exact range of an integer type.
fn int_range(data_type: i128) -> Option<(i128, i128)> {
    let bits = match data_type {
        0x01 => return Some((0, 1)),
        0x02 | 0x05 => 8,
        0x03 | 0x06 => 16,
        0x10 | 0x16 => 24,
        0x04 | 0x07 => 32,
        0x12 | 0x18 => 40,
        0x13 | 0x19 => 48,
        0x14 | 0x1A => 56,
        0x15 | 0x1B => 64,
        _ => return None,
    };
    let signed = matches!(
        data_type,
        0x02 | 0x03 | 0x04 | 0x10 | 0x12 | 0x13 | 0x14 | 0x15
    );
    Some(if signed {
        (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
    } else {
        (0, (1i128 << bits) - 1)
    })
}

fn is_real(data_type: i128) -> bool {
    matches!(data_type, 0x08 | 0x11)
}

/// A REAL32 or REAL64 value as dcf-tools reads one: an integer giving the bits.
fn real(text: &str, data_type: i128) -> Option<f64> {
    let bits = py_int(text, 0)?;
    if bits < 0 {
        return None;
    }
    if data_type == 0x08 {
        Some(f32::from_bits(u32::try_from(bits).ok()?) as f64)
    } else {
        Some(f64::from_bits(u64::try_from(bits).ok()?))
    }
}

/// `$NODEID`, `$NODEID+N` or `N` (hex or decimal): the number and whether the node-ID is added.
fn node_value(text: &str) -> Option<(i128, bool)> {
    if text.eq_ignore_ascii_case("$NODEID") {
        return Some((0, true));
    }
    let (rest, node) = match text.get(..7) {
        Some(head) if head.eq_ignore_ascii_case("$NODEID") => {
            let r = text[7..].trim_start().strip_prefix('+')?.trim_start();
            (r, true)
        }
        _ => (text, false),
    };
    let digits = rest.strip_prefix('-').unwrap_or(rest);
    let hex = digits.len() > 2
        && digits[..2].eq_ignore_ascii_case("0x")
        && digits[2..].chars().all(|c| c.is_ascii_hexdigit());
    let dec = !digits.is_empty() && digits.chars().all(|c| c.is_ascii_digit());
    if !(hex || dec) {
        return None;
    }
    py_int(rest, 0).map(|v| (v, node))
}

impl Linter<'_> {
    /// The data type of a section and its limits.
    pub(crate) fn data_type(&mut self, section: &str, keys: &[(String, String)]) -> bool {
        let Some(text) = given(keys, "DataType") else {
            return true;
        };
        let Some(data_type) = py_int(text, 0) else {
            return self.warn(format!("invalid DataType in [{section}]: {text}"));
        };
        if range(data_type).is_some() {
            return self.limit(section, keys, "LowLimit", data_type)
                && self.limit(section, keys, "HighLimit", data_type);
        }
        let mut ok = true;
        for k in ["LowLimit", "HighLimit"] {
            if given(keys, k).is_some() {
                ok = self.warn(format!("{k} not supported in [{section}]"));
            }
        }
        ok
    }

    fn limit(
        &mut self,
        section: &str,
        keys: &[(String, String)],
        key: &str,
        data_type: i128,
    ) -> bool {
        let Some(text) = given(keys, key) else {
            return true;
        };
        let (value, node) = if is_real(data_type) {
            match real(text, data_type) {
                Some(v) => (v, false),
                None => return self.warn(format!("invalid {key} in [{section}]: {text}")),
            }
        } else {
            match node_value(text) {
                Some((v, node)) => (v as f64, node),
                None => {
                    // dcf-tools warns and goes on with 0.
                    self.warnings
                        .push(format!("invalid {key} in [{section}]: {text}"));
                    (0.0, false)
                }
            }
        };
        let (low, high) = range(data_type).unwrap_or((f64::MIN, f64::MAX));
        if value < low - f64::from(u8::from(node)) {
            return self.warn(format!("{key} underflow in [{section}]"));
        }
        if value > high - if node { 127.0 } else { 0.0 } {
            return self.warn(format!("{key} overflow in [{section}]"));
        }
        true
    }

    /// A value of the type `keys` give, within their limits.
    pub(crate) fn value(
        &mut self,
        keys: &[(String, String)],
        section: &str,
        entry: &str,
        text: &str,
    ) -> bool {
        let Some(data_type) = given(keys, "DataType").and_then(|t| py_int(t, 0)) else {
            return self.warn(format!("invalid DataType in [{section}]"));
        };
        if is_real(data_type) {
            let limit = |k: &str, default: f64| {
                given(keys, k).map_or(Some(default), |t| real(t, data_type))
            };
            let (low, high) = range(data_type).unwrap_or_default();
            let (Some(low), Some(high)) = (limit("LowLimit", low), limit("HighLimit", high)) else {
                return self.warn(format!("invalid limit in [{section}]"));
            };
            let Some(v) = real(text, data_type) else {
                return self.warn(format!("invalid {entry} in [{section}]: {text}"));
            };
            return self.within(section, entry, v < low, v > high);
        }
        let Some((low, high)) = int_range(data_type) else {
            return true;
        };
        let mut bound = |k: &str, default: i128| -> Option<(i128, bool)> {
            match given(keys, k) {
                None => Some((default, false)),
                Some(t) => match node_value(t) {
                    Some(v) => Some(v),
                    None => {
                        self.warnings
                            .push(format!("invalid {k} in [{section}]: {t}"));
                        None
                    }
                },
            }
        };
        let (Some((mut low, low_node)), Some((mut high, high_node))) =
            (bound("LowLimit", low), bound("HighLimit", high))
        else {
            return false;
        };
        let Some((v, node)) = node_value(text) else {
            return self.warn(format!("invalid {entry} in [{section}]: {text}"));
        };
        match (node, low_node) {
            (false, true) => low += 1,
            (true, false) => low -= 1,
            _ => {}
        }
        match (node, high_node) {
            (false, true) => high += 127,
            (true, false) => high -= 127,
            _ => {}
        }
        self.within(section, entry, v < low, v > high)
    }

    fn within(&mut self, section: &str, entry: &str, under: bool, over: bool) -> bool {
        if under {
            return self.warn(format!("{entry} underflow in [{section}]"));
        }
        if over {
            return self.warn(format!("{entry} overflow in [{section}]"));
        }
        true
    }
}
