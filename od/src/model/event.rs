//! What a device says about its own entries: one [`Event`] per fact, shown as one line of text
//! ([`Event::line`]) or as one JSON object ([`Event::json`]).
//!
//! Today's kinds are those of a start: an entry the description gives no value got one
//! ([`EventKind::Filled`]), or a value the description gives was replaced because the device cannot
//! run with it ([`EventKind::Adjusted`]). Later kinds (a write refused, a fault raised) carry the
//! same fields, so that one reader takes them all.
//!
//! The JSON form, one object per line (no line breaks inside):
//!
//! ```text
//! {"event":"filled","node":5,"index":"0x6502","sub":0,"name":"supported drive modes","value":165,"reason":"…"}
//! {"event":"adjusted","device":"EVE-XCR-E","index":"0x6083","sub":0,"name":"profile acceleration","value":100000,"unit":"counts/s²","reason":"…"}
//! ```
//!
//! - `event`: the kind, lower case (`filled`, `adjusted`);
//! - who says it ([`Origin`]): `node` (a CANopen node-ID, `null` for a node still without one) or
//!   `device` (a kind of EtherCAT device, by name, for all its units);
//! - `index` as `0x` and four upper-case hex digits, `sub` as a number, `name` the entry's name as
//!   its profile gives it;
//! - `value`: a number for an integer, a string for text (and for any other type, its text form);
//! - `unit`: only where the value has one;
//! - `reason`: why, in words.

use std::fmt::Write as _;

use crate::dict::Address;
use crate::value::Value;

/// The kind of an [`Event`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum EventKind {
    /// An entry the description gives no value got one.
    Filled,
    /// A value the description gives was replaced: the device cannot run with it.
    Adjusted,
}

impl EventKind {
    /// The name JSON gives the kind (`filled`, `adjusted`).
    pub const fn as_str(self) -> &'static str {
        match self {
            EventKind::Filled => "filled",
            EventKind::Adjusted => "adjusted",
        }
    }
}

/// Who reports an [`Event`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin<'a> {
    /// A CANopen node, by its node-ID (`None`: a node without one, waiting for LSS).
    Node(Option<u8>),
    /// A kind of device (every unit of it), by name: an EtherCAT device of an ESI.
    Device(&'a str),
}

/// One fact about one entry. See the [module documentation](self).
#[derive(Debug, Clone, PartialEq)]
pub struct Event {
    /// What happened.
    pub kind: EventKind,
    /// The entry.
    pub address: Address,
    /// Its name as its profile gives it (`supported drive modes`).
    pub name: String,
    /// The value it holds now.
    pub value: Value,
    /// The value as the line shows it: `0x000000A5`, `100000`, `"PD4"`.
    pub shown: String,
    /// The unit of the value, if it has one (`counts/s²`).
    pub unit: Option<String>,
    /// Why, in words.
    pub reason: String,
}

impl Event {
    /// An event of a 32-bit number shown as hex (`0x000000A5`), without a unit: an identity entry,
    /// a device type, a COB-ID, supported modes.
    pub fn hex(kind: EventKind, address: Address, name: &str, value: u32, reason: String) -> Event {
        Event {
            kind,
            address,
            name: name.to_string(),
            value: Value::Uint(u64::from(value)),
            shown: format!("0x{value:08X}"),
            unit: None,
            reason,
        }
    }

    /// The entry's address as the line shows it: `0x6502`, or `0x1018:01` for a sub-index other
    /// than 0.
    pub fn at(&self) -> String {
        let Address { index, sub } = self.address;
        if sub == 0 {
            format!("0x{index:04X}")
        } else {
            format!("0x{index:04X}:{sub:02X}")
        }
    }

    /// One line of text: `0x6502 supported drive modes = 0x000000A5 (reason)`, the unit after the
    /// value where it has one.
    pub fn line(&self) -> String {
        let mut line = format!("{} {} = {}", self.at(), self.name, self.shown);
        if let Some(unit) = &self.unit {
            line.push(' ');
            line.push_str(unit);
        }
        let _ = write!(line, " ({})", self.reason);
        line
    }

    /// One JSON object, on one line, of this event as `origin` reports it (see the [module
    /// documentation](self)).
    pub fn json(&self, origin: Origin<'_>) -> String {
        let mut out = String::from("{\"event\":");
        push_string(&mut out, self.kind.as_str());
        match origin {
            Origin::Node(Some(id)) => {
                let _ = write!(out, ",\"node\":{id}");
            }
            Origin::Node(None) => out.push_str(",\"node\":null"),
            Origin::Device(name) => {
                out.push_str(",\"device\":");
                push_string(&mut out, name);
            }
        }
        let _ = write!(
            out,
            ",\"index\":\"0x{:04X}\",\"sub\":{},\"name\":",
            self.address.index, self.address.sub
        );
        push_string(&mut out, &self.name);
        out.push_str(",\"value\":");
        match (&self.value, self.value.as_i128()) {
            (Value::Bool(b), _) => out.push_str(if *b { "true" } else { "false" }),
            (_, Some(n)) => {
                let _ = write!(out, "{n}");
            }
            (Value::String(s), None) => push_string(&mut out, s),
            (other, None) => push_string(&mut out, &other.to_string()),
        }
        if let Some(unit) = &self.unit {
            out.push_str(",\"unit\":");
            push_string(&mut out, unit);
        }
        out.push_str(",\"reason\":");
        push_string(&mut out, &self.reason);
        out.push('}');
        out
    }
}

/// `text` as a JSON string (RFC 8259 §7): quotes, backslashes and control characters escaped.
fn push_string(out: &mut String, text: &str) {
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if u32::from(c) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", u32::from(c));
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

#[cfg(test)]
mod tests {
    use super::*;

    fn modes() -> Event {
        Event {
            kind: EventKind::Filled,
            address: Address::new(0x6502, 0),
            name: "supported drive modes".into(),
            value: Value::Uint(0xA5),
            shown: "0x000000A5".into(),
            unit: None,
            reason:
                "the description gives no value: the modes this drive runs whose objects it has"
                    .into(),
        }
    }

    #[test]
    fn a_line_names_the_entry_its_value_and_why() {
        assert_eq!(
            modes().line(),
            "0x6502 supported drive modes = 0x000000A5 (the description gives no value: the modes \
             this drive runs whose objects it has)"
        );
        let e = Event {
            kind: EventKind::Adjusted,
            address: Address::new(0x6099, 1),
            name: "homing speed during search for switch".into(),
            value: Value::Uint(5000),
            shown: "5000".into(),
            unit: Some("counts/s".into()),
            reason: "r".into(),
        };
        assert_eq!(
            e.line(),
            "0x6099:01 homing speed during search for switch = 5000 counts/s (r)"
        );
    }

    #[test]
    fn json_objects_of_a_node_and_of_a_device() {
        assert_eq!(
            modes().json(Origin::Node(Some(5))),
            r#"{"event":"filled","node":5,"index":"0x6502","sub":0,"name":"supported drive modes","value":165,"reason":"the description gives no value: the modes this drive runs whose objects it has"}"#
        );
        let e = Event {
            kind: EventKind::Adjusted,
            address: Address::new(0x1008, 0),
            name: "manufacturer device name".into(),
            value: Value::String("A \"B\"\\\t\u{1}".into()),
            shown: "\"A\"".into(),
            unit: Some("µ".into()),
            reason: "x".into(),
        };
        assert_eq!(
            e.json(Origin::Device("EVE-XCR-E")),
            r#"{"event":"adjusted","device":"EVE-XCR-E","index":"0x1008","sub":0,"name":"manufacturer device name","value":"A \"B\"\\\t\u0001","unit":"µ","reason":"x"}"#
        );
        assert!(modes().json(Origin::Node(None)).contains(r#""node":null,"#));
    }
}
