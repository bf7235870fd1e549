//! Differences between two device descriptions: every part of the model — identity, file information,
//! CAN capabilities, commissioning, the EtherCAT parts (the file's root element, group type, FMMUs, sync
//! managers, PDOs, mailbox, DC op modes, EEPROM, slots, modules), the dictionary and the comments — and,
//! between two files of several devices, which devices pair with which.
//!
//! A [`Difference`] is a place in the description (a path of [`Step`]s) and a [`Change`] there: a part
//! only one side has, or a field whose values differ, each value shown as text ([`Shown`]). Everything is
//! compared on the values of the model, never on their text, so two descriptions are diff-equal exactly
//! when the model holds the same for both (reals compared bit for bit, so that NaN equals NaN).
//!
//! The comparison of each model struct destructures the struct whole: a field added to the model does not
//! compile until it is compared here. A list of parts is compared part by part, matched by a key (a PDO by
//! its index, an op mode by its name) or by position (sync managers, PDO entries, comment lines), with
//! the parts only one side has reported and, for keyed lists, a change of order.

mod context;
mod description;
mod dictionary;
mod ethercat;

use std::collections::HashMap;
use std::fmt;

use crate::device::DeviceDescription;
use crate::dict::Dictionary;
use context::Cx;

/// One step of the path to a difference.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Step {
    /// A part of the description that there is one of: `identity`, `file info`, `CAN`, `mailbox`…
    Part(&'static str),
    /// One of several parts of a kind, and its key: (`RxPdo`, `0x1600`), (`Sm`, `2`), (`entry`, `1`).
    Item {
        /// The kind of part.
        kind: &'static str,
        /// Which one: its index, name or position.
        key: String,
    },
    /// A dictionary object.
    Object(u16),
    /// A sub-object of the dictionary.
    Entry(u16, u8),
}

impl fmt::Display for Step {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Step::Part(name) => f.write_str(name),
            Step::Item { kind, key } => write!(f, "{kind} {key}"),
            Step::Object(index) => write!(f, "0x{index:04X}"),
            Step::Entry(index, sub) => write!(f, "0x{index:04X}:{sub:02X}"),
        }
    }
}

/// A value as a difference shows it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Shown {
    /// Text of the description (a name, a string value): shown quoted.
    Text(String),
    /// Anything else (a number, a flag, a list, `none`): shown as it is.
    Plain(String),
}

impl Shown {
    /// The text without quotes.
    pub fn as_str(&self) -> &str {
        match self {
            Shown::Text(t) | Shown::Plain(t) => t,
        }
    }
}

impl fmt::Display for Shown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Shown::Text(t) => write!(f, "{t:?}"),
            Shown::Plain(t) => f.write_str(t),
        }
    }
}

/// What differs at a place.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Change {
    /// Only `a` has the part; its name (empty for a part that has none).
    OnlyInA(String),
    /// Only `b` has the part; its name.
    OnlyInB(String),
    /// A field both have, with different values.
    Changed {
        /// The field: `name`, `type`, `access`, `value`, `start address`, `RxPdo order`…
        field: &'static str,
        /// The value in `a`.
        a: Shown,
        /// The value in `b`.
        b: Shown,
    },
}

/// One difference between description `a` and description `b`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Difference {
    /// Where: the steps from the description down to the part (empty for a field of the description's
    /// EtherCAT parts themselves, such as the group type).
    pub path: Vec<Step>,
    /// What differs there.
    pub change: Change,
}

impl Difference {
    /// The dictionary index of a difference in the dictionary.
    pub fn index(&self) -> Option<u16> {
        match self.path.first() {
            Some(Step::Object(index) | Step::Entry(index, _)) => Some(*index),
            _ => None,
        }
    }

    /// The sub-index of a difference in a sub-object of the dictionary.
    pub fn sub(&self) -> Option<u8> {
        match self.path.first() {
            Some(Step::Entry(_, sub)) => Some(*sub),
            _ => None,
        }
    }

    /// The path as text: its steps joined by spaces.
    pub fn place(&self) -> String {
        self.path
            .iter()
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
            .join(" ")
    }
}

impl fmt::Display for Difference {
    /// `- PLACE NAME`, `+ PLACE NAME` or `~ PLACE FIELD: A -> B`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let place = self.place();
        let join = |prefix: &str, tail: &str| {
            [prefix, place.as_str(), tail]
                .iter()
                .filter(|s| !s.is_empty())
                .copied()
                .collect::<Vec<_>>()
                .join(" ")
        };
        match &self.change {
            Change::OnlyInA(name) => f.write_str(&join("-", name)),
            Change::OnlyInB(name) => f.write_str(&join("+", name)),
            Change::Changed { field, a, b } => write!(f, "{}: {a} -> {b}", join("~", field)),
        }
    }
}

/// Every difference between dictionary `a` and dictionary `b`, in index order. Empty when the
/// dictionaries hold the same.
pub fn diff(a: &Dictionary, b: &Dictionary) -> Vec<Difference> {
    let mut out = Vec::new();
    dictionary::dictionary(&mut Cx::new(&mut out), a, b);
    out
}

/// Every difference between description `a` and description `b`: identity, file information, CAN
/// capabilities, commissioning, EtherCAT parts, dictionary (in index order) and comments, in that order.
/// Empty when the model holds the same for both.
pub fn diff_devices(a: &DeviceDescription, b: &DeviceDescription) -> Vec<Difference> {
    let mut out = Vec::new();
    description::device(&mut Cx::new(&mut out), a, b);
    out
}

/// How a device of file `a` pairs with one of file `b`, by position in each file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pairing {
    /// The devices to compare.
    Both(usize, usize),
    /// A device of `a` that `b` does not have.
    OnlyInA(usize),
    /// A device of `b` that `a` does not have.
    OnlyInB(usize),
}

/// Pairs the devices of two files. Two files of one device each pair those two, whatever they are.
/// Otherwise devices pair by product code and revision; where several devices of either file share a
/// product code and revision (several devices with product code 0), those pair by name (type name, else
/// product name). The pairs and the devices only `a` has come in `a`'s order, then the devices only `b`
/// has in `b`'s order.
pub fn pair_devices(a: &[DeviceDescription], b: &[DeviceDescription]) -> Vec<Pairing> {
    if a.len() == 1 && b.len() == 1 {
        return vec![Pairing::Both(0, 0)];
    }
    let key = |d: &DeviceDescription| (d.identity.product_code, d.identity.revision);
    let name = |d: &DeviceDescription| {
        if d.identity.order_code.is_empty() {
            d.identity.product_name.clone()
        } else {
            d.identity.order_code.clone()
        }
    };
    let mut in_b: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (j, y) in b.iter().enumerate() {
        in_b.entry(key(y)).or_default().push(j);
    }
    let mut in_a: HashMap<(u32, u32), usize> = HashMap::new();
    for x in a {
        *in_a.entry(key(x)).or_default() += 1;
    }
    let mut used = vec![false; b.len()];
    let mut out = Vec::new();
    for (i, x) in a.iter().enumerate() {
        let same_key = in_b.get(&key(x)).map_or(&[][..], Vec::as_slice);
        let hit = if same_key.len() == 1 && in_a.get(&key(x)) == Some(&1) {
            same_key.first().copied()
        } else {
            same_key
                .iter()
                .copied()
                .find(|&j| !used[j] && name(&b[j]) == name(x))
        };
        match hit {
            Some(j) => {
                used[j] = true;
                out.push(Pairing::Both(i, j));
            }
            None => out.push(Pairing::OnlyInA(i)),
        }
    }
    out.extend((0..b.len()).filter(|&j| !used[j]).map(Pairing::OnlyInB));
    out
}

#[cfg(test)]
mod tests;
