//! A slave of the network: what its description says, what the bus description asks of it, and the
//! concise DCF of the difference, entry by entry in the order dcfgen writes them.

use od::object::AccessType;
use od::{DataType, DeviceDescription, Object, Value};

use crate::bus::{Ctx, NetError, Number};
use crate::concise::Entry;
use crate::yaml::Node;

/// A sub-object mapped into a PDO.
#[derive(Debug, Clone, PartialEq)]
pub struct Mapped {
    /// Index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// The CiA 301 data type index.
    pub data_type: u16,
    /// Length in bits.
    pub bits: u32,
    /// The sub-object's name.
    pub name: String,
}

/// A PDO of the slave, as its description gives it and as the bus description configures it.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Pdo {
    /// COB-ID (bit 31: not valid).
    pub cob_id: u32,
    /// Transmission type.
    pub transmission_type: u32,
    /// Inhibit time (100 µs).
    pub inhibit_time: u32,
    /// Event timer (ms) of a TPDO.
    pub event_timer: u32,
    /// Event deadline (ms) of an RPDO.
    pub event_deadline: u32,
    /// SYNC start value.
    pub sync_start: u32,
    /// Number of mapped entries (sub-index 0 of the mapping).
    pub n: u32,
    /// The mapped entries by position.
    pub mapping: Vec<(u32, Mapped)>,
}

/// One slave, generated.
#[derive(Debug, Clone, PartialEq)]
pub struct Slave {
    /// Its name in the bus description.
    pub name: String,
    /// Node-ID (255: unconfigured).
    pub node_id: u32,
    /// The line of its section.
    pub line: usize,
    /// Its `dcf` key as written, and the key's line: where the values the description gives come
    /// from, named in a boot error.
    pub dcf: (String, usize),
    /// The description, resolved for the node-ID.
    pub desc: DeviceDescription,
    /// Where the master finds the concise DCF.
    pub dcf_path: String,
    /// 0x1000.
    pub device_type: u32,
    /// Vendor-ID.
    pub vendor_id: u32,
    /// Product code.
    pub product_code: u32,
    /// Revision number.
    pub revision_number: u32,
    /// Serial number.
    pub serial_number: u32,
    /// 0x1014.
    pub emcy_cob_id: u32,
    /// Heartbeat factor.
    pub heartbeat_multiplier: f64,
    /// Whether it consumes the master's heartbeat.
    pub heartbeat_consumer: bool,
    /// Its heartbeat producer time (ms).
    pub heartbeat_producer: u32,
    /// Retry factor.
    pub retry_factor: i128,
    /// Guard time (ms).
    pub guard_time: u32,
    /// Life time factor.
    pub life_time_factor: u32,
    /// Boot it.
    pub boot: bool,
    /// Mandatory.
    pub mandatory: bool,
    /// Reset communication on boot.
    pub reset_communication: bool,
    /// Program download file.
    pub software_file: String,
    /// Expected software version.
    pub software_version: u32,
    /// The concise DCF file the master downloads, empty when none.
    pub configuration_file: String,
    /// Restore configuration sub-index.
    pub restore_configuration: u32,
    /// Its RPDOs by number, enabled and mapped ones only after generation.
    pub rpdo: Vec<(u32, Pdo)>,
    /// Its TPDOs by number.
    pub tpdo: Vec<(u32, Pdo)>,
    /// 0x1029 values by sub-index.
    pub error_behavior: Vec<(u8, i128)>,
    /// The concise DCF entries.
    pub sdo: Vec<Entry>,
    /// Where each entry of `sdo` comes from: the line of the key that made it, and the key.
    pub sdo_origin: Vec<(usize, String)>,
    /// The lines of the keys a boot error names (`heartbeat_producer`, `software_version`,
    /// `revision_number`, `serial_number`) where the section gives them.
    pub key_lines: Vec<(&'static str, usize)>,
}

/// The integer a sub-object holds.
pub(crate) fn int_value(obj: &Object, sub: u8) -> Option<i128> {
    match obj.sub(sub)?.current()? {
        Value::Uint(v) => Some(v.into()),
        Value::Int(v) => Some(v.into()),
        Value::Bool(b) => Some(b.into()),
        _ => None,
    }
}

/// The concise encoding dcfgen gives a data type: the size field, the bytes it writes, signed.
fn layout(dt: DataType) -> Option<(u32, usize, bool)> {
    use DataType::*;
    Some(match dt {
        Boolean | Unsigned8 => (1, 1, false),
        Integer8 => (1, 1, true),
        Integer16 => (2, 2, true),
        Unsigned16 => (2, 2, false),
        Integer32 => (4, 4, true),
        Unsigned32 => (4, 4, false),
        Integer24 => (3, 4, true),
        Unsigned24 => (3, 4, false),
        Integer40 => (5, 8, true),
        Integer48 => (6, 8, true),
        Integer56 => (7, 8, true),
        Integer64 => (8, 8, true),
        Unsigned40 => (5, 8, false),
        Unsigned48 => (6, 8, false),
        Unsigned56 => (7, 8, false),
        Unsigned64 => (8, 8, false),
        _ => return None,
    })
}

/// The length in bits dcfgen maps a data type with, `None` for types it cannot map.
pub(crate) fn bits(dt: DataType) -> Option<u32> {
    match dt {
        DataType::Boolean => Some(1),
        DataType::Real32 => Some(32),
        DataType::Real64 => Some(64),
        _ => layout(dt).map(|(n, _, _)| n * 8),
    }
}

/// The entry writing `value` as `dt` to `index:sub`, as dcfgen packs it.
pub(crate) fn encode(index: u16, sub: u8, dt: DataType, value: Number) -> Result<Entry, String> {
    let as_int = |v: Number| match v {
        Number::Int(i) => i,
        Number::Float(f) => f.trunc() as i128,
    };
    let as_float = |v: Number| match v {
        Number::Int(i) => i as f64,
        Number::Float(f) => f,
    };
    let data = match dt {
        DataType::Real32 => (as_float(value) as f32).to_le_bytes().to_vec(),
        DataType::Real64 => as_float(value).to_le_bytes().to_vec(),
        _ => {
            let (size, width, signed) =
                layout(dt).ok_or_else(|| format!("cannot write a {dt:?} value"))?;
            let v = as_int(value);
            let bits = 8 * width as u32;
            let (low, high) = if signed {
                (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
            } else {
                (0, (1i128 << bits) - 1)
            };
            if v < low || v > high {
                return Err(format!("{v} is out of range for 0x{index:04X}/{sub}"));
            }
            let mut data = (v as u128).to_le_bytes()[..width].to_vec();
            data.truncate(width);
            return Ok(Entry {
                index,
                sub,
                size,
                data,
            });
        }
    };
    Ok(Entry::new(index, sub, data))
}

impl Slave {
    /// Its entry of 0x1F81 (CiA 302-2 NMT slave assignment): bit 0 a slave, 2 boot it, 3
    /// mandatory, 4 keep alive (no reset communication), 5 check the software version, 6 update
    /// the software, 7 restore the configuration; retry factor in bits 8–15, guard time in 16–31.
    pub fn assignment(&self) -> u32 {
        let mut v = 1u32;
        v |= if self.boot { 0x04 } else { 0 } | if self.mandatory { 0x08 } else { 0 };
        v |= if self.reset_communication { 0 } else { 0x10 }
            | if self.software_version != 0 { 0x20 } else { 0 };
        v |= if self.software_file.is_empty() {
            0
        } else {
            0x40
        } | if self.restore_configuration != 0 {
            0x80
        } else {
            0
        };
        if self.retry_factor != 0 {
            v |= (self.retry_factor as u32) << 8;
        }
        if self.guard_time != 0 {
            v |= self.guard_time << 16;
        }
        v
    }

    /// Whether its description has sub-index `sub` of the identity object 0x1018: the master checks
    /// (and dcfgen writes 0x1F86–0x1F88 for) only the parts the slave has.
    pub fn has_identity(&self, sub: u8) -> bool {
        self.desc
            .dictionary
            .object(0x1018)
            .and_then(|o| o.sub(sub))
            .is_some()
    }

    /// The line of its key `key`, else of its section.
    pub fn key_line(&self, key: &str) -> usize {
        self.key_lines
            .iter()
            .find(|(k, _)| *k == key)
            .map_or(self.line, |&(_, l)| l)
    }

    /// The time (ms) the master waits for its heartbeat: its producer time times the heartbeat
    /// multiplier, as the master's 0x1016 entry for it holds (0: none).
    pub fn consumer_time(&self) -> u16 {
        ((f64::from(self.heartbeat_producer) * self.heartbeat_multiplier) as i64 as u32 & 0xFFFF)
            as u16
    }

    /// The entry writing `value` to `index:sub` of this slave, with dcfgen's checks: the object must
    /// exist, the sub-object too (or be sub-index 0 of an object with sub-objects); writing an entry
    /// that is not writable is a warning.
    pub fn concise(
        &self,
        index: u16,
        sub: u8,
        value: Number,
        warn: &mut Vec<String>,
    ) -> Result<Entry, String> {
        let name = &self.name;
        let Some(obj) = self.desc.dictionary.object(index) else {
            return Err(format!("{name}: object 0x{index:04X} does not exist"));
        };
        match obj.sub(sub) {
            Some(s) => {
                if matches!(s.access.kind, AccessType::Ro | AccessType::Const) {
                    warn.push(format!(
                        "{name}: no write access for sub-object 0x{index:04X}/{sub}"
                    ));
                }
                encode(index, sub, s.data_type, value).map_err(|e| format!("{name}: {e}"))
            }
            None if sub == 0 && !obj.subs.is_empty() => {
                encode(index, 0, DataType::Unsigned8, value).map_err(|e| format!("{name}: {e}"))
            }
            None => Err(format!(
                "{name}: sub-object 0x{index:04X}/{sub} does not exist"
            )),
        }
    }

    /// The entry at `node`'s line: an error from [`Slave::concise`] becomes one naming it.
    pub fn push(
        &mut self,
        cx: &mut Cx,
        node: &Node,
        key: &str,
        at: (u16, u8),
        value: Number,
    ) -> Result<(), NetError> {
        let entry = self
            .concise(at.0, at.1, value, &mut cx.warnings)
            .map_err(|m| cx.ctx.error(node.line, key, m))?;
        self.sdo.push(entry);
        self.sdo_origin.push((node.line, key.to_string()));
        Ok(())
    }
}

/// What generation carries from slave to slave.
#[derive(Debug)]
pub struct Cx<'a> {
    /// The reader of values.
    pub ctx: Ctx<'a>,
    /// The next free COB-ID of `cob_id: auto`.
    pub next_cob_id: u32,
    /// Warnings, in order.
    pub warnings: Vec<String>,
    /// Descriptions the strict reading refuses are taken as they are.
    pub no_strict: bool,
}

/// The mapped sub-object `value` (a mapping entry) stands for in `desc`.
fn mapped(desc: &DeviceDescription, value: i128) -> Option<Mapped> {
    let index = ((value >> 16) & 0xFFFF) as u16;
    let sub = ((value >> 8) & 0xFF) as u8;
    if index < 0x1000 {
        let dt = DataType::from_index(index)?;
        return (sub == 0).then(|| Mapped {
            index,
            sub,
            data_type: index,
            bits: bits(dt).unwrap_or(0),
            name: format!("{dt:?}"),
        });
    }
    let s = desc.dictionary.object(index)?.sub(sub)?;
    Some(Mapped {
        index,
        sub,
        data_type: s.data_type.index(),
        bits: bits(s.data_type).unwrap_or(0),
        name: s.name.clone(),
    })
}

/// The PDO whose communication parameter is `comm` in `desc`, as dcfgen reads it.
pub(crate) fn read_pdo(desc: &DeviceDescription, comm: u16) -> Result<Pdo, String> {
    let tpdo = comm & 0xFE00 == 0x1800;
    let mut pdo = Pdo {
        cob_id: 0x8000_0000,
        ..Pdo::default()
    };
    let Some(c) = desc.dictionary.object(comm) else {
        return Ok(pdo);
    };
    let v = |sub| int_value(c, sub).map(|v| v as u32);
    let n = v(0).unwrap_or(0);
    let set = |min: u32, sub: u8, field: &mut u32| {
        if n >= min {
            if let Some(x) = v(sub) {
                *field = x;
            }
        }
    };
    set(1, 1, &mut pdo.cob_id);
    set(2, 2, &mut pdo.transmission_type);
    if tpdo {
        set(3, 3, &mut pdo.inhibit_time);
        set(5, 5, &mut pdo.event_timer);
        set(6, 6, &mut pdo.sync_start);
    } else {
        set(5, 5, &mut pdo.event_deadline);
    }
    let Some(m) = desc.dictionary.object(comm + 0x200) else {
        return Err(format!("object 0x{:04X} does not exist", comm + 0x200));
    };
    pdo.n = int_value(m, 0).unwrap_or(0) as u32;
    for i in 1..=pdo.n.min(255) {
        let Some(value) = int_value(m, i as u8) else {
            continue;
        };
        if value == 0 {
            continue;
        }
        let entry = mapped(desc, value).ok_or_else(|| {
            format!(
                "0x{:04X}/{i} maps 0x{value:08X}, which does not exist",
                comm + 0x200
            )
        })?;
        pdo.mapping.push((i, entry));
    }
    Ok(pdo)
}
