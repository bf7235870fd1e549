//! Units of values as ETG.1004 and CiA 303-2 encode them in 32 bits (ESI `Info/Unit`, SDO
//! Information's unit): bits 31–24 the prefix as a signed power of ten, bits 23–16 the unit, bits
//! 15–8 a unit the first is divided by (0 for none), bits 7–0 reserved. `0xFD260000` is millivolt,
//! `0x002D0000` degree Celsius, `0xFD262600` millivolt per volt.

/// The symbol of a unit index: the SI base and derived units of CiA 303-2, `None` for another
/// index.
fn symbol(index: u8) -> Option<&'static str> {
    Some(match index {
        0x01 => "m",
        0x02 => "kg",
        0x03 => "s",
        0x04 => "A",
        0x05 => "K",
        0x06 => "mol",
        0x07 => "cd",
        0x10 => "rad",
        0x11 => "sr",
        0x20 => "Hz",
        0x21 => "N",
        0x22 => "Pa",
        0x23 => "J",
        0x24 => "W",
        0x25 => "C",
        0x26 => "V",
        0x27 => "F",
        0x28 => "Ω",
        0x29 => "S",
        0x2A => "Wb",
        0x2B => "T",
        0x2C => "H",
        0x2D => "°C",
        0x2E => "lm",
        0x2F => "lx",
        0x30 => "Bq",
        0x31 => "Gy",
        0x32 => "Sv",
        _ => return None,
    })
}

/// The SI prefix of a power of ten, `None` for one without a symbol.
fn prefix(power: i8) -> Option<&'static str> {
    Some(match power {
        0 => "",
        1 => "da",
        2 => "h",
        3 => "k",
        6 => "M",
        9 => "G",
        12 => "T",
        -1 => "d",
        -2 => "c",
        -3 => "m",
        -6 => "µ",
        -9 => "n",
        -12 => "p",
        _ => return None,
    })
}

/// The unit `code` as text: `mV`, `°C`, `mV/V`, `ns`; a dimensionless unit with a prefix is the
/// factor (`×10^-3`); a code with a unit or prefix this table does not know is shown as the code
/// (`unit 0x00A00000`).
pub fn unit_text(code: u32) -> String {
    let [power, numerator, denominator, _] = code.to_be_bytes();
    let power = power as i8;
    let raw = || format!("unit 0x{code:08X}");
    let numerator_text = match numerator {
        0 => "",
        n => match symbol(n) {
            Some(s) => s,
            None => return raw(),
        },
    };
    let mut text = match (numerator, prefix(power)) {
        (0, _) if power != 0 => format!("×10^{power}"),
        (_, Some(p)) => format!("{p}{numerator_text}"),
        (_, None) => return raw(),
    };
    if denominator != 0 {
        match symbol(denominator) {
            Some(s) => {
                if text.is_empty() {
                    text.push('1');
                }
                text.push('/');
                text.push_str(s);
            }
            None => return raw(),
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use super::unit_text;

    /// Codes of real ESI files, worked out from the layout by hand.
    #[test]
    fn codes_read_as_their_units() {
        assert_eq!(unit_text(0xFD26_0000), "mV");
        assert_eq!(unit_text(0x002D_0000), "°C");
        assert_eq!(unit_text(0x0028_0000), "Ω");
        assert_eq!(unit_text(0x0003_0000), "s");
        assert_eq!(unit_text(0xF703_0000), "ns");
        assert_eq!(unit_text(0xFD26_2600), "mV/V");
        assert_eq!(unit_text(0xFD05_2400), "mK/W");
        assert_eq!(unit_text(0xFD20_0000), "mHz");
        assert_eq!(unit_text(0x0320_0000), "kHz");
        assert_eq!(unit_text(0xFA04_0000), "µA");
        assert_eq!(unit_text(0x0000_0300), "1/s");
        assert_eq!(unit_text(0xFD00_0000), "×10^-3");
        assert_eq!(unit_text(0x0000_0000), "");
    }

    /// CiA 303-2's SI units and prefixes, each on its own: the unit with no prefix, and metre with
    /// each prefix.
    #[test]
    fn every_unit_and_prefix_of_the_table() {
        let units: [(u32, &str); 28] = [
            (0x01, "m"),
            (0x02, "kg"),
            (0x03, "s"),
            (0x04, "A"),
            (0x05, "K"),
            (0x06, "mol"),
            (0x07, "cd"),
            (0x10, "rad"),
            (0x11, "sr"),
            (0x20, "Hz"),
            (0x21, "N"),
            (0x22, "Pa"),
            (0x23, "J"),
            (0x24, "W"),
            (0x25, "C"),
            (0x26, "V"),
            (0x27, "F"),
            (0x28, "Ω"),
            (0x29, "S"),
            (0x2A, "Wb"),
            (0x2B, "T"),
            (0x2C, "H"),
            (0x2D, "°C"),
            (0x2E, "lm"),
            (0x2F, "lx"),
            (0x30, "Bq"),
            (0x31, "Gy"),
            (0x32, "Sv"),
        ];
        for (index, symbol) in units {
            assert_eq!(unit_text(index << 16), symbol, "unit 0x{index:02X}");
            assert_eq!(
                unit_text(index << 8),
                format!("1/{symbol}"),
                "per 0x{index:02X}"
            );
        }
        let prefixes: [(i8, &str); 13] = [
            (12, "T"),
            (9, "G"),
            (6, "M"),
            (3, "k"),
            (2, "h"),
            (1, "da"),
            (0, ""),
            (-1, "d"),
            (-2, "c"),
            (-3, "m"),
            (-6, "µ"),
            (-9, "n"),
            (-12, "p"),
        ];
        for (power, symbol) in prefixes {
            let code = (u32::from(power as u8) << 24) | 0x0001_0000;
            assert_eq!(unit_text(code), format!("{symbol}m"), "10^{power}");
        }
    }

    #[test]
    fn an_unknown_unit_or_prefix_is_shown_as_its_code() {
        assert_eq!(unit_text(0x00A0_0000), "unit 0x00A00000");
        assert_eq!(unit_text(0x0026_A000), "unit 0x0026A000");
        assert_eq!(unit_text(0x0526_0000), "unit 0x05260000");
    }
}
