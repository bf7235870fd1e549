//! The names of the bits of a bit-coded entry (a status or control word): from the entry's
//! description where it lists them, else the ones CiA 402 gives its controlword and statusword.
//!
//! A description lists them as `Bit 15 Mode_Flag; 14 Module_OK; …; 0 Moving_CW.` (the form of the
//! SMD and X67 descriptions, and a common one of vendors' comments): after `Bit` (or `Bits`), items
//! separated by `;`, each a bit number and the bit's name (its first word). An item of several bits
//! (`12 and 11 …`, `14 to 7 …`) and a reserved bit name nothing; the list ends at the first `.`
//! outside parentheses.

/// CiA 402-2 §8.4.1, the statusword (0x6041) bits that have names; bits 8, 12–15 are mode or
/// manufacturer specific.
const STATUSWORD: [(u8, &str); 11] = [
    (0, "Ready_to_switch_on"),
    (1, "Switched_on"),
    (2, "Operation_enabled"),
    (3, "Fault"),
    (4, "Voltage_enabled"),
    (5, "Quick_stop"),
    (6, "Switch_on_disabled"),
    (7, "Warning"),
    (9, "Remote"),
    (10, "Target_reached"),
    (11, "Internal_limit_active"),
];

/// CiA 402-2 §8.4.1, the controlword (0x6040) bits that have names; bits 4–6 and 9 are mode
/// specific, 10 reserved, 11–15 manufacturer specific.
const CONTROLWORD: [(u8, &str); 6] = [
    (0, "Switch_on"),
    (1, "Enable_voltage"),
    (2, "Quick_stop"),
    (3, "Enable_operation"),
    (7, "Fault_reset"),
    (8, "Halt"),
];

/// The named bits of the entry at `index`:`sub` with `description` and `bits` bits: the
/// description's list, or for CiA 402's controlword and statusword (0x6040 / 0x6041 of any of the
/// eight axes, 0x800 apart) the standard's names; empty when neither names any.
pub fn bit_names(index: u16, sub: u8, description: Option<&str>, bits: u32) -> Vec<(u8, String)> {
    let listed = description.map(listed_bits).unwrap_or_default();
    let listed: Vec<(u8, String)> = listed
        .into_iter()
        .filter(|(b, _)| u32::from(*b) < bits)
        .collect();
    if !listed.is_empty() {
        return listed;
    }
    let axis_base = index.wrapping_sub(0x6000) % 0x800;
    let standard: &[(u8, &str)] = match (index, axis_base, sub, bits) {
        (0x6000..=0x9FFF, 0x41, 0, 16) => &STATUSWORD,
        (0x6000..=0x9FFF, 0x40, 0, 16) => &CONTROLWORD,
        _ => &[],
    };
    standard.iter().map(|&(b, n)| (b, n.to_string())).collect()
}

/// The bits a description lists (see the module documentation), in the order it gives them.
pub fn listed_bits(text: &str) -> Vec<(u8, String)> {
    let Some(start) = list_start(text) else {
        return Vec::new();
    };
    let list = &text[start..];
    // The end: the first '.' outside parentheses.
    let mut depth = 0i32;
    let mut end = list.len();
    for (k, c) in list.char_indices() {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            '.' if depth <= 0 => {
                end = k;
                break;
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    for item in list[..end].split(';') {
        let item = item.trim();
        let digits = item.bytes().take_while(u8::is_ascii_digit).count();
        let Ok(bit) = item[..digits].parse::<u8>() else {
            continue;
        };
        if bit > 63 {
            continue;
        }
        let rest = item[digits..].trim_start();
        let name: String = rest
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        let several = ["and", "to", "-", "…"].iter().any(|w| {
            rest.strip_prefix(w)
                .is_some_and(|r| r.starts_with(|c: char| c == ' ' || c.is_ascii_digit()))
        });
        if name.is_empty()
            || several
            || name.eq_ignore_ascii_case("reserved")
            || !name.starts_with(|c: char| c.is_ascii_alphabetic())
        {
            continue;
        }
        out.push((bit, name));
    }
    out
}

/// Where the list starts: after `Bit ` or `Bits ` followed by a digit.
fn list_start(text: &str) -> Option<usize> {
    let mut from = 0;
    while let Some(k) = text[from..].find("Bit") {
        let at = from + k;
        let after = &text[at + 3..];
        let after = after.strip_prefix('s').unwrap_or(after);
        if let Some(rest) = after.strip_prefix(' ') {
            if rest.starts_with(|c: char| c.is_ascii_digit()) {
                return Some(text.len() - rest.len());
            }
        }
        from = at + 3;
    }
    None
}

/// The names of the bits set in `value` among `named`, in bit order.
pub fn set_names(value: u64, named: &[(u8, String)]) -> Vec<String> {
    let mut set: Vec<&(u8, String)> = named
        .iter()
        .filter(|(b, _)| value & (1u64 << b) != 0)
        .collect();
    set.sort_by_key(|(b, _)| *b);
    set.into_iter().map(|(_, n)| n.clone()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(v: &[(u8, String)]) -> Vec<(u8, &str)> {
        v.iter().map(|(b, n)| (*b, n.as_str())).collect()
    }

    /// The SMD's STATUS_word0 description (Reference 6, Figure R6.4): every bit named, and the list
    /// ends at the period before the rest of the comment.
    #[test]
    fn a_listed_word_names_every_bit() {
        let text = "Status Word 0 (Reference 6, STATUS_word0). Bit 15 Mode_Flag; 14 Module_OK; \
                    13 Configuration_Error; 12 Command_Error; 11 Input_Error; 10 Position_Invalid; \
                    9 Waiting_For_Assembled_Segment; 8 In_Assembled_Mode; 7 Move_Complete; \
                    6 Decelerating; 5 Accelerating; 4 At_Home; 3 Stopped; 2 In_Hold_State; \
                    1 Moving_CCW; 0 Moving_CW. Typically 16#4408 after power-up (Task 2).";
        let got = listed_bits(text);
        assert_eq!(got.len(), 16);
        assert_eq!(got[0], (15, "Mode_Flag".to_string()));
        assert_eq!(got[15], (0, "Moving_CW".to_string()));
        assert_eq!(
            set_names(0x4408, &got),
            ["Stopped", "Position_Invalid", "Module_OK"]
        );
    }

    /// Several bits in one item and reserved bits name nothing; a parenthesis with a `.` in it does
    /// not end the list.
    #[test]
    fn ranges_and_reserved_bits_are_left_out() {
        let text = "Bit 15 Mode_Select (0 = Command Mode, e.g. 1.5); 14 Preset_Encoder; 12 and 11 \
                    assembled-move programming; 10 to 8 reserved, must be 0; 7 reserved; \
                    6 DC_Sync (0 start moves when data is read); 5-4 both; 3 Halt.";
        assert_eq!(
            names(&listed_bits(text)),
            [
                (15, "Mode_Select"),
                (14, "Preset_Encoder"),
                (6, "DC_Sync"),
                (3, "Halt")
            ]
        );
        assert_eq!(
            listed_bits("Bits 1 A; 0 B"),
            [(1, "A".into()), (0, "B".into())]
        );
        assert!(listed_bits("Bitrate 500 kbit/s").is_empty());
        assert!(listed_bits("no list here").is_empty());
        assert!(listed_bits("Bit 99 Far; 64 Beyond").is_empty());
        assert_eq!(listed_bits("Bit 63 Top; 64 Over"), [(63, "Top".into())]);
        // The list ends at the first period after its parentheses close: what follows is prose.
        assert_eq!(
            names(&listed_bits("Bit 1 A (on, 1.5 s); 0 B. See also; 5 Extra")),
            [(1, "A"), (0, "B")]
        );
    }

    /// CiA 402's statusword and controlword, of the first and the third axis; not for another entry
    /// or a word of another size; a description's own list comes first.
    #[test]
    fn cia_402_words_have_the_standards_names() {
        let sw = bit_names(0x6041, 0, None, 16);
        assert_eq!(sw.len(), 11);
        assert_eq!(
            set_names(0x0237, &sw),
            [
                "Ready_to_switch_on",
                "Switched_on",
                "Operation_enabled",
                "Voltage_enabled",
                "Quick_stop",
                "Remote"
            ]
        );
        assert_eq!(bit_names(0x7041, 0, None, 16), sw, "axis 3");
        let cw = bit_names(0x6040, 0, None, 16);
        assert_eq!(
            set_names(0x008F, &cw),
            [
                "Switch_on",
                "Enable_voltage",
                "Quick_stop",
                "Enable_operation",
                "Fault_reset"
            ]
        );
        assert!(bit_names(0x6042, 0, None, 16).is_empty());
        assert!(bit_names(0x6041, 1, None, 16).is_empty());
        assert!(bit_names(0x6041, 0, None, 32).is_empty());
        assert!(bit_names(0x2041, 0, None, 16).is_empty());
        assert_eq!(
            names(&bit_names(0x6041, 0, Some("Bit 0 Mine"), 16)),
            [(0, "Mine")]
        );
        // A listed bit beyond the entry's size is not one of its bits: an 8-bit entry's are 0 to 7.
        assert_eq!(
            names(&bit_names(
                0x2000,
                0,
                Some("Bit 9 High; 8 Edge; 7 Top; 1 Low"),
                8
            )),
            [(7, "Top"), (1, "Low")]
        );
    }
}
