//! Findings about a description file, ranked as the field ranks them, and where in the file each
//! construct was read.
//!
//! An [`Severity::Error`] is kept for what cannot be used as written: a file that is not well-formed, a
//! value that no reading makes fit (an index beyond 16 bits, an object code that does not exist), a size
//! that cannot be known. Everything that the established tools (python-canopen, Lely, CANopenNode, SOEM,
//! TwinCAT) load loads here too, with a [`Severity::Warning`] that names the place and says what was
//! made of it ("the limit is dropped", "the PDOs win"). Readers stop at the first error (a
//! [`ParseError`](crate::error::ParseError)) and collect warnings in a [`Reading`]; [`validate`] adds the
//! findings about the model and takes their positions from the reader's [`SourceMap`].
//!
//! [`validate`]: crate::validate::validate_mapped

use std::collections::BTreeMap;
use std::fmt;

use crate::device::DeviceDescription;
use crate::dict::Address;
use crate::error::Position;

/// How serious a finding is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    /// The description loads and is usable; something in it is unusual, wrong by the letter of the
    /// standard, or was read in a way the finding says.
    Warning,
    /// The description cannot be used as written.
    Error,
}

impl Severity {
    /// `warning` or `error`.
    pub const fn as_str(self) -> &'static str {
        match self {
            Severity::Warning => "warning",
            Severity::Error => "error",
        }
    }
}

impl fmt::Display for Severity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One finding: how serious, where in the file, which entry, and what.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Finding {
    /// How serious.
    pub severity: Severity,
    /// Where in the source file, when the finding comes from one.
    pub position: Option<Position>,
    /// The dictionary entry concerned, if one.
    pub address: Option<Address>,
    /// What is wrong, and what was made of it.
    pub message: String,
}

impl Finding {
    /// A warning at `position`.
    pub fn warning(position: Position, message: impl Into<String>) -> Finding {
        Finding {
            severity: Severity::Warning,
            position: Some(position),
            address: None,
            message: message.into(),
        }
    }

    /// The same finding about `address` (builder style).
    pub fn at(mut self, address: Address) -> Finding {
        self.address = Some(address);
        self
    }
}

impl fmt::Display for Finding {
    /// `warning: 0x1A00:01: message` (the position is the caller's to print, before the file name).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.address {
            Some(a) => write!(f, "{}: {a}: {}", self.severity, self.message),
            None => write!(f, "{}: {}", self.severity, self.message),
        }
    }
}

/// Where a reader found the parts of one device: its element or section, each object and entry, and
/// each entry of an ESI PDO. A look-up falls back from an entry to its object and from there to the
/// device.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SourceMap {
    device: Option<Position>,
    objects: BTreeMap<u16, Position>,
    entries: BTreeMap<(u16, u8), Position>,
    pdo_entries: BTreeMap<(u16, usize), Position>,
}

impl SourceMap {
    /// Where the device is described (an ESI `Device` element; the start of an EDS or XDD).
    pub fn set_device(&mut self, at: Position) {
        self.device = Some(at);
    }

    /// Where object `index` is described; the first place given is kept.
    pub fn set_object(&mut self, index: u16, at: Position) {
        self.objects.entry(index).or_insert(at);
    }

    /// Where entry `index:sub` is described; the first place given is kept.
    pub fn set_entry(&mut self, index: u16, sub: u8, at: Position) {
        self.entries.entry((index, sub)).or_insert(at);
    }

    /// Where entry number `n` (from 0) of the ESI PDO `pdo` is.
    pub fn set_pdo_entry(&mut self, pdo: u16, n: usize, at: Position) {
        self.pdo_entries.entry((pdo, n)).or_insert(at);
    }

    /// Where the device is described.
    pub fn device(&self) -> Option<Position> {
        self.device
    }

    /// Where object `index` is described, else the device.
    pub fn object(&self, index: u16) -> Option<Position> {
        self.objects.get(&index).copied().or(self.device)
    }

    /// Where `address` is described, else its object, else the device.
    pub fn entry(&self, address: Address) -> Option<Position> {
        self.entries
            .get(&(address.index, address.sub))
            .copied()
            .or_else(|| self.object(address.index))
    }

    /// Where entry `n` of PDO `pdo` is, else the PDO's mapping object, else the device.
    pub fn pdo_entry(&self, pdo: u16, n: usize) -> Option<Position> {
        self.pdo_entries
            .get(&(pdo, n))
            .copied()
            .or_else(|| self.object(pdo))
    }
}

/// What a reader made of a file: the devices, where each was read, and the warnings.
#[derive(Debug, Clone, Default)]
pub struct Reading {
    /// The devices, in file order.
    pub devices: Vec<DeviceDescription>,
    /// Where each device's parts are, one map per device.
    pub sources: Vec<SourceMap>,
    /// The reader's warnings about the whole file, in file order.
    pub findings: Vec<Finding>,
}

impl Reading {
    /// A reading of one device.
    pub fn one(device: DeviceDescription, source: SourceMap, findings: Vec<Finding>) -> Reading {
        Reading {
            devices: vec![device],
            sources: vec![source],
            findings,
        }
    }
}

/// Orders findings for a person: errors before warnings, then by place in the file, then by entry.
pub fn sort(findings: &mut [Finding]) {
    findings.sort_by(|a, b| {
        b.severity
            .cmp(&a.severity)
            .then_with(|| {
                let key = |p: Option<Position>| p.map(|p| (p.line, p.column));
                key(a.position).cmp(&key(b.position))
            })
            .then_with(|| a.address.cmp(&b.address))
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(line: u32, column: u32) -> Position {
        Position { line, column }
    }

    #[test]
    fn look_ups_fall_back_from_entry_to_object_to_device() {
        let mut map = SourceMap::default();
        assert_eq!(map.entry(Address::new(0x1018, 1)), None);
        map.set_device(at(3, 5));
        map.set_object(0x1018, at(10, 7));
        map.set_entry(0x1018, 1, at(12, 9));
        map.set_entry(0x1018, 1, at(99, 1));
        map.set_pdo_entry(0x1A00, 2, at(40, 11));
        assert_eq!(map.entry(Address::new(0x1018, 1)), Some(at(12, 9)));
        assert_eq!(map.entry(Address::new(0x1018, 2)), Some(at(10, 7)));
        assert_eq!(map.entry(Address::new(0x2000, 0)), Some(at(3, 5)));
        assert_eq!(map.pdo_entry(0x1A00, 2), Some(at(40, 11)));
        assert_eq!(map.pdo_entry(0x1A00, 3), Some(at(3, 5)));
        assert_eq!(map.device(), Some(at(3, 5)));
    }

    #[test]
    fn errors_come_first_then_file_order() {
        let mut list = vec![
            Finding::warning(at(9, 1), "w9"),
            Finding {
                severity: Severity::Error,
                position: Some(at(20, 1)),
                address: None,
                message: "e20".into(),
            },
            Finding::warning(at(2, 4), "w2"),
            Finding {
                severity: Severity::Error,
                position: None,
                address: Some(Address::new(0x1000, 0)),
                message: "e-".into(),
            },
        ];
        sort(&mut list);
        let order: Vec<&str> = list.iter().map(|f| f.message.as_str()).collect();
        assert_eq!(order, ["e-", "e20", "w2", "w9"]);
        assert_eq!(
            list[0].to_string(),
            "error: 0x1000:00: e-",
            "the address follows the severity"
        );
        assert_eq!(list[2].to_string(), "warning: w2");
    }
}
