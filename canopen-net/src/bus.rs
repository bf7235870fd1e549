//! The bus description: the master, the slaves and the options of a CANopen network, read from the
//! YAML Lely's `dcfgen` reads, or from a ros2_canopen `bus.yml`.
//!
//! **dcfgen's YAML.** The top level maps names to sections: `options`, `master`, and one section per
//! slave (any other name; names starting with `.` are skipped, so they can hold YAML anchors).
//!
//! `options`:
//! - `dcf_path`: the folder the master finds the slaves' concise DCFs in (default empty); written into
//!   the master's 0x1F22 `UploadFile` entries, `$VAR` and `${VAR}` expanded.
//! - `heartbeat_multiplier`: the factor from a producer's heartbeat time to its consumer's (default 3.0).
//! - `retry_factor`: the default of each slave's `retry_factor` (default 3).
//!
//! `master`:
//! - `node_id` (default 255), `baudrate` (kbit/s, default 1000), `vendor_id`, `product_code`,
//!   `revision_number`, `serial_number`: the master's own commissioning and identity (a serial number
//!   goes into `master.bin` as 0x1018:04).
//! - `sync_period` (0x1006, µs), `sync_window` (0x1007, µs), `sync_overflow` (0x1019), `time_cob_id`
//!   (0x1012, default 0x100), `emcy_inhibit_time` (0x1015, 100 µs), `nmt_inhibit_time` (0x102A, 100 µs),
//!   `boot_time` (0x1F89, ms).
//! - `heartbeat_multiplier` (default: the option's), `heartbeat_consumer` (default true: 0x1016 consumes
//!   each slave's heartbeat), `heartbeat_producer` (0x1017, ms; each slave with `heartbeat_consumer`
//!   is configured to consume it, times the multiplier).
//! - `error_behavior`: a map from 0x1029 sub-index to value (default `{1: 0}`).
//! - `start`, `start_nodes`, `start_all_nodes`, `reset_all_nodes`, `stop_all_nodes`: the bits of NMT
//!   start-up, 0x1F80.
//!
//! Each slave:
//! - `dcf` (required): its EDS or DCF, relative to the YAML's folder.
//! - `node_id`: its node-ID (default: the DCF's `NodeID`; a slave without one is left out).
//! - `dcf_path`: overrides the option for this slave; `configuration_file`: read and, as in dcfgen,
//!   without effect on what is written.
//! - `revision_number`, `serial_number`: expected identity (0x1F87, 0x1F88 in `master.bin`).
//! - `time_cob_id` (0x1012), `heartbeat_producer` (0x1017), `guard_time` (0x100C), `life_time_factor`
//!   (0x100D): written to the slave when they differ from its description (dcfgen compares
//!   `time_cob_id` with 0x100, whatever the description says).
//! - `heartbeat_multiplier` (default: the option's), `heartbeat_consumer` (default false: the slave
//!   consumes the master's heartbeat), `retry_factor` (default: the option's): the master's side.
//! - `error_behavior`: 0x1029 values by sub-index, written where they differ.
//! - `rpdo`, `tpdo`: maps from PDO number (1..512) to `enabled`, `cob_id` (a value or `auto`: the
//!   predefined set for PDOs 1–4, else the next free of 0x680..0x6DF), `transmission`,
//!   `inhibit_time`, `event_timer`, `event_deadline`, `sync_start` and `mapping` (a list of `index`,
//!   `sub_index`).
//! - `boot`, `mandatory`, `reset_communication`, `software_file`, `software_version`,
//!   `restore_configuration`: the slave's entries of 0x1F81, 0x1F58, 0x1F55 and 0x1F8A.
//! - `sdo`: a list of `index`, `sub_index`, `value` written after everything else (the value an
//!   integer, a float cut to one as dcfgen does, for REAL32 and REAL64 entries too).
//!
//! **ros2_canopen's `bus.yml`** has `options` and `master` as above, `defaults` (keys every slave
//! takes unless it gives its own) and `nodes` (the slaves by name); it is read as the dcfgen YAML it
//! flattens to, the slaves in `nodes` order, the keys only ros2_canopen reads (`driver`, `package`, …)
//! ignored.

use std::fmt;

use crate::yaml::{self, Kind, Node};

/// An error in a bus description: where it is, which key, what is wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NetError {
    /// The file.
    pub file: String,
    /// The line, from 1.
    pub line: usize,
    /// The key, as a path (`drive.rpdo.1.mapping`), empty for the file as a whole.
    pub key: String,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for NetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.key.is_empty() {
            write!(f, "{}:{}: {}", self.file, self.line, self.message)
        } else {
            write!(
                f,
                "{}:{}: {}: {}",
                self.file, self.line, self.key, self.message
            )
        }
    }
}

impl std::error::Error for NetError {}

/// A number as the description gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Number {
    /// An integer.
    Int(i128),
    /// A floating-point number (for REAL32 and REAL64 entries).
    Float(f64),
}

/// The network-wide options.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Where the master finds the concise DCFs.
    pub dcf_path: String,
    /// Producer to consumer heartbeat factor.
    pub heartbeat_multiplier: f64,
    /// Default retry factor.
    pub retry_factor: i128,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            dcf_path: String::new(),
            heartbeat_multiplier: 3.0,
            retry_factor: 3,
        }
    }
}

/// One section's keys as read, with their lines, for the typed accessors.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Section {
    /// The section's name (`master`, a slave's name).
    pub name: String,
    /// The line of the section's name.
    pub line: usize,
    /// The section's mapping.
    pub node: Option<Node>,
}

/// A bus description.
#[derive(Debug, Clone, PartialEq)]
pub struct Bus {
    /// The YAML file's name, for messages.
    pub file: String,
    /// The options.
    pub options: Options,
    /// The `master` section.
    pub master: Section,
    /// The slave sections, in file order.
    pub slaves: Vec<Section>,
}

impl Bus {
    /// Reads a bus description (dcfgen's YAML or ros2_canopen's `bus.yml`) from `text`; `file` names it
    /// in errors.
    pub fn parse(text: &str, file: &str) -> Result<Bus, NetError> {
        let err = |line, key: &str, message: String| NetError {
            file: file.to_string(),
            line,
            key: key.to_string(),
            message,
        };
        let root = yaml::parse(text).map_err(|(line, m)| err(line, "", m))?;
        if !matches!(root.kind, Kind::Map(_)) {
            return Err(err(
                root.line,
                "",
                "the bus description is no mapping".into(),
            ));
        }
        let mut bus = Bus {
            file: file.to_string(),
            options: Options::default(),
            master: Section::default(),
            slaves: Vec::new(),
        };
        let ctx = Ctx { file };
        if let Some((_, options)) = root.get("options") {
            if let Some(v) = ctx.get(options, "options", "dcf_path")? {
                bus.options.dcf_path = ctx.string(v, "options.dcf_path")?;
            }
            if let Some(v) = ctx.get(options, "options", "heartbeat_multiplier")? {
                bus.options.heartbeat_multiplier = ctx.float(v, "options.heartbeat_multiplier")?;
            }
            if let Some(v) = ctx.get(options, "options", "retry_factor")? {
                bus.options.retry_factor = ctx.int(v, "options.retry_factor")?;
            }
        }
        let Some((mkey, master)) = root.get("master") else {
            return Err(err(
                root.line,
                "master",
                "there is no master section".into(),
            ));
        };
        bus.master = Section {
            name: "master".into(),
            line: mkey.line,
            node: Some(master.clone()),
        };
        let ros = root.get("nodes");
        for (key, value) in root.entries() {
            let name = key.key_text().unwrap_or_default();
            if ros.is_some() || name == "master" || name == "options" || name.starts_with('.') {
                continue;
            }
            bus.slaves.push(Section {
                name,
                line: key.line,
                node: Some(value.clone()),
            });
        }
        if let Some((_, nodes)) = ros {
            let defaults = root.get("defaults").map(|(_, d)| d);
            for (key, value) in nodes.entries() {
                let mut merged = defaults.map(|d| d.entries().to_vec()).unwrap_or_default();
                for (k, v) in value.entries() {
                    match merged
                        .iter_mut()
                        .find(|(old, _)| old.key_text() == k.key_text())
                    {
                        Some(slot) => *slot = (k.clone(), v.clone()),
                        None => merged.push((k.clone(), v.clone())),
                    }
                }
                bus.slaves.push(Section {
                    name: key.key_text().unwrap_or_default(),
                    line: key.line,
                    node: Some(Node {
                        line: value.line,
                        kind: Kind::Map(merged),
                    }),
                });
            }
        }
        Ok(bus)
    }
}

/// Reads typed values out of nodes, with errors naming the file, line and key.
#[derive(Debug, Clone, Copy)]
pub struct Ctx<'a> {
    /// The file, for messages.
    pub file: &'a str,
}

impl<'a> Ctx<'a> {
    /// An error at `line` about `key`.
    pub fn error(&self, line: usize, key: &str, message: impl Into<String>) -> NetError {
        NetError {
            file: self.file.to_string(),
            line,
            key: key.to_string(),
            message: message.into(),
        }
    }

    /// The value of `key` in the mapping `node` (`path` names the mapping); an error when `node` is
    /// neither a mapping nor empty.
    pub fn get<'n>(
        &self,
        node: &'n Node,
        path: &str,
        key: &str,
    ) -> Result<Option<&'n Node>, NetError> {
        match node.kind {
            Kind::Map(_) => Ok(node.get(key).map(|(_, v)| v)),
            Kind::Null => Ok(None),
            _ => Err(self.error(node.line, path, "is no mapping")),
        }
    }

    /// Python's `int()` of the value: an integer, a boolean, a float cut to an integer or a string of
    /// decimal digits.
    pub fn int(&self, node: &Node, key: &str) -> Result<i128, NetError> {
        match &node.kind {
            Kind::Int(i) => Ok(*i),
            Kind::Bool(b) => Ok(i128::from(*b)),
            Kind::Float(f) if f.is_finite() && f.abs() < 1e30 => Ok(f.trunc() as i128),
            Kind::Str(s) => {
                let t = s.trim().replace('_', "");
                let digits = t.strip_prefix(['-', '+']).unwrap_or(&t);
                match t.parse::<i128>() {
                    Ok(v) if !digits.is_empty() && digits.chars().all(|c| c.is_ascii_digit()) => {
                        Ok(v)
                    }
                    _ => Err(self.error(node.line, key, format!("'{s}' is no integer"))),
                }
            }
            _ => Err(self.error(node.line, key, "is no integer")),
        }
    }

    /// `int()` of the value, within `low..=high`.
    pub fn int_in(&self, node: &Node, key: &str, low: i128, high: i128) -> Result<i128, NetError> {
        let v = self.int(node, key)?;
        if v < low || v > high {
            return Err(self.error(node.line, key, format!("{v} is out of range {low}..{high}")));
        }
        Ok(v)
    }

    /// Python's `float()` of the value.
    pub fn float(&self, node: &Node, key: &str) -> Result<f64, NetError> {
        match &node.kind {
            Kind::Int(i) => Ok(*i as f64),
            Kind::Float(f) => Ok(*f),
            Kind::Bool(b) => Ok(f64::from(u8::from(*b))),
            Kind::Str(s) => s
                .trim()
                .parse::<f64>()
                .map_err(|_| self.error(node.line, key, format!("'{s}' is no number"))),
            _ => Err(self.error(node.line, key, "is no number")),
        }
    }

    /// An integer, or a float kept as one.
    pub fn number(&self, node: &Node, key: &str) -> Result<Number, NetError> {
        match node.kind {
            Kind::Float(f) => Ok(Number::Float(f)),
            _ => self.int(node, key).map(Number::Int),
        }
    }

    /// Python's `bool()` of the value: a string is true when not empty, a number when not zero.
    pub fn truth(&self, node: &Node) -> bool {
        match &node.kind {
            Kind::Null => false,
            Kind::Bool(b) => *b,
            Kind::Int(i) => *i != 0,
            Kind::Float(f) => *f != 0.0,
            Kind::Str(s) => !s.is_empty(),
            Kind::Seq(v) => !v.is_empty(),
            Kind::Map(v) => !v.is_empty(),
        }
    }

    /// Python's `str()` of a scalar.
    pub fn string(&self, node: &Node, key: &str) -> Result<String, NetError> {
        node.key_text()
            .ok_or_else(|| self.error(node.line, key, "is no text"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dcfgen_sections_keep_their_order_and_skip_hidden_names() {
        let bus = Bus::parse(
            "options: {heartbeat_multiplier: 2}\nmaster: {node_id: 1}\n.x: &a {dcf: a.eds}\nb: *a\na:\n  dcf: a.eds\n",
            "bus.yml",
        )
        .unwrap();
        let names: Vec<_> = bus
            .slaves
            .iter()
            .map(|s| (s.name.as_str(), s.line))
            .collect();
        assert_eq!(names, [("b", 4), ("a", 5)]);
        assert_eq!(bus.options.heartbeat_multiplier, 2.0);
    }

    #[test]
    fn ros2_defaults_merge_into_each_node() {
        let bus = Bus::parse(
            "master: {node_id: 1}\ndefaults:\n  dcf: d.eds\n  heartbeat_producer: 100\nnodes:\n  a: {node_id: 2}\n  b: {node_id: 3, dcf: e.eds}\n",
            "bus.yml",
        )
        .unwrap();
        let b = bus.slaves[1].node.as_ref().unwrap();
        assert_eq!(b.get("dcf").unwrap().1.kind, Kind::Str("e.eds".into()));
        assert_eq!(b.get("heartbeat_producer").unwrap().1.kind, Kind::Int(100));
        assert_eq!(bus.slaves[0].name, "a");
    }

    proptest::proptest! {
        /// Any text is a bus description or an error, never a panic.
        #[test]
        fn any_text_parses_or_fails(text in "[ -~\n]{0,200}") {
            let _ = Bus::parse(&text, "bus.yml");
        }

        /// Any YAML of the right keys with any scalars is read or refused.
        #[test]
        fn any_scalars_are_read_or_refused(a in "[ -~]{0,12}", b in "[ -~]{0,12}") {
            let text = format!("options:\n  retry_factor: {a}\nmaster:\n  node_id: {b}\nx: {{dcf: {a}}}\n");
            let _ = Bus::parse(&text, "bus.yml");
        }
    }

    #[test]
    fn errors_name_file_line_and_key() {
        let e = Bus::parse(
            "options:\n  retry_factor: many\nmaster: {}\n",
            "net/bus.yml",
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "net/bus.yml:2: options.retry_factor: 'many' is no integer"
        );
        let e = Bus::parse("a: {dcf: x}\n", "bus.yml").unwrap_err();
        assert_eq!(
            e.to_string(),
            "bus.yml:1: master: there is no master section"
        );
    }
}
