//! The master: its options, the heartbeat entries it adds to its slaves, its own concise DCF
//! (`master.bin`) and its DCF (`master.dcf`, CiA 306 with the CiA 302 objects).

use std::fmt::Write;

use crate::bus::{Bus, NetError, Number};
use crate::concise::Entry;
use crate::slave::{encode, int_value, Cx, Mapped, Pdo, Slave};
use od::DataType;

/// The master's settings (see the `bus` module for each key).
#[derive(Debug, Clone, PartialEq)]
pub struct Master {
    /// Node-ID.
    pub node_id: u32,
    /// Bit rate, kbit/s.
    pub baudrate: u32,
    /// Vendor-ID, product code, revision and serial number.
    pub identity: [u32; 4],
    /// 0x1006, 0x1007, 0x1019.
    pub sync: [u32; 3],
    /// 0x1012.
    pub time_cob_id: u32,
    /// 0x1015.
    pub emcy_inhibit_time: u32,
    /// 0x1016 present.
    pub heartbeat_consumer: bool,
    /// 0x1017.
    pub heartbeat_producer: u32,
    /// Producer to consumer factor.
    pub heartbeat_multiplier: f64,
    /// 0x1029 by sub-index.
    pub error_behavior: Vec<(u8, u32)>,
    /// 0x102A.
    pub nmt_inhibit_time: u32,
    /// start, start_nodes, start_all_nodes, reset_all_nodes, stop_all_nodes.
    pub startup: [bool; 5],
    /// 0x1F89.
    pub boot_time: u32,
    /// The master's own concise DCF.
    pub sdo: Vec<Entry>,
}

fn u32_entry(index: u16, sub: u32, value: u32) -> Entry {
    let v = Number::Int(value.into());
    encode(index, sub as u8, DataType::Unsigned32, v)
        .unwrap_or_else(|_| Entry::new(index, sub as u8, vec![]))
}

impl Master {
    /// Reads the `master` section and adds the heartbeat entries to `slaves`.
    pub fn from_config(cx: &mut Cx, bus: &Bus, slaves: &mut [Slave]) -> Result<Master, NetError> {
        let ctx = cx.ctx;
        let cfg = bus.master.node.clone().unwrap_or(crate::yaml::Node {
            line: bus.master.line,
            kind: crate::yaml::Kind::Null,
        });
        let get = |k: &str| ctx.get(&cfg, "master", k);
        let u32_of = |k: &str, default: u32| -> Result<u32, NetError> {
            match get(k)? {
                Some(v) => Ok(ctx.int_in(v, &format!("master.{k}"), 0, u32::MAX.into())? as u32),
                None => Ok(default),
            }
        };
        let mut m = Master {
            node_id: u32_of("node_id", 255)?,
            baudrate: u32_of("baudrate", 1000)?,
            identity: [
                u32_of("vendor_id", 0)?,
                u32_of("product_code", 0)?,
                u32_of("revision_number", 0)?,
                u32_of("serial_number", 0)?,
            ],
            sync: [
                u32_of("sync_period", 0)?,
                u32_of("sync_window", 0)?,
                u32_of("sync_overflow", 0)?,
            ],
            time_cob_id: u32_of("time_cob_id", 0x100)?,
            emcy_inhibit_time: u32_of("emcy_inhibit_time", 0)?,
            heartbeat_multiplier: match get("heartbeat_multiplier")? {
                Some(v) => ctx.float(v, "master.heartbeat_multiplier")?,
                None => bus.options.heartbeat_multiplier,
            },
            heartbeat_consumer: get("heartbeat_consumer")?.is_none_or(|v| ctx.truth(v)),
            heartbeat_producer: u32_of("heartbeat_producer", 0)?,
            error_behavior: vec![(1, 0)],
            nmt_inhibit_time: u32_of("nmt_inhibit_time", 0)?,
            startup: [true, true, false, false, false],
            boot_time: u32_of("boot_time", 0)?,
            sdo: Vec::new(),
        };
        if let Some(eb) = get("error_behavior")? {
            for (k, v) in eb.entries() {
                let sub = ctx.int_in(k, "master.error_behavior", 0, 255)? as u8;
                let value = ctx.int_in(v, "master.error_behavior", 0, 255)? as u32;
                match m.error_behavior.iter_mut().find(|(s, _)| *s == sub) {
                    Some(slot) => slot.1 = value,
                    None => m.error_behavior.push((sub, value)),
                }
            }
        }
        for (i, k) in [
            "start",
            "start_nodes",
            "start_all_nodes",
            "reset_all_nodes",
            "stop_all_nodes",
        ]
        .iter()
        .enumerate()
        {
            if let Some(v) = get(k)? {
                m.startup[i] = ctx.int(v, &format!("master.{k}"))? != 0;
            }
        }
        if m.identity[3] != 0 {
            m.sdo.push(u32_entry(0x1018, 4, m.identity[3]));
        }
        let line = get("heartbeat_producer")?.map_or(bus.master.line, |n| n.line);
        m.heartbeats(cx, slaves, line);
        for s in slaves.iter() {
            if s.software_version != 0 {
                m.sdo.push(u32_entry(0x1F55, s.node_id, s.software_version));
            }
            if s.revision_number != 0 && s.has_identity(3) {
                m.sdo.push(u32_entry(0x1F87, s.node_id, s.revision_number));
            }
            if s.serial_number != 0 && s.has_identity(4) {
                m.sdo.push(u32_entry(0x1F88, s.node_id, s.serial_number));
            }
        }
        Ok(m)
    }

    /// Its 0x1F80 (CiA 302-2 NMT startup): bit 0 the NMT master, 1 start all nodes at once, 2 do not
    /// enter Operational itself, 3 do not start the slaves, 4 reset all nodes and 6 stop all nodes
    /// when a mandatory slave is lost.
    pub fn startup_word(&self) -> u32 {
        let [start, start_nodes, start_all, reset_all, stop_all] = self.startup;
        let mut v = 1u32;
        v |= if start_all { 0x02 } else { 0 }
            | if start { 0 } else { 0x04 }
            | if start_nodes { 0 } else { 0x08 };
        v | if reset_all { 0x10 } else { 0 } | if stop_all { 0x40 } else { 0 }
    }

    /// Each slave consumes the master's heartbeat, or stops consuming it, in 0x1016.
    /// `line` is that of the master's `heartbeat_producer` (or of its section), where the entries
    /// come from.
    fn heartbeats(&self, cx: &mut Cx, slaves: &mut [Slave], line: usize) {
        let origin = (line, "master.heartbeat_producer".to_string());
        let heartbeat = (f64::from(self.heartbeat_producer) * self.heartbeat_multiplier) as i64;
        for s in slaves.iter_mut() {
            let consumers: Vec<(u8, u32)> = match s.desc.dictionary.object(0x1016) {
                Some(o) => o
                    .subs
                    .keys()
                    .filter(|&&k| k != 0)
                    .map(|&k| (k, int_value(o, k).unwrap_or(0) as u32))
                    .collect(),
                None => {
                    if s.heartbeat_consumer && heartbeat > 0 {
                        cx.warnings
                            .push(format!("{}: object 0x1016 does not exist", s.name));
                    }
                    continue;
                }
            };
            let node = |v: u32| (v >> 16) & 0xFF;
            if s.heartbeat_consumer && heartbeat > 0 {
                let sub = consumers
                    .iter()
                    .find(|(_, v)| node(*v) == self.node_id)
                    .or_else(|| {
                        consumers
                            .iter()
                            .find(|(_, v)| v & 0xFFFF == 0 || node(*v) == 0 || node(*v) > 127)
                    });
                match sub {
                    Some(&(sub, _)) => {
                        let value = ((self.node_id & 0xFF) << 16) | (heartbeat as u32 & 0xFFFF);
                        let mut warnings = Vec::new();
                        if let Ok(e) =
                            s.concise(0x1016, sub, Number::Int(value.into()), &mut warnings)
                        {
                            s.sdo.insert(0, e);
                            s.sdo_origin.insert(0, origin.clone());
                        }
                        cx.warnings.extend(warnings);
                    }
                    None => cx.warnings.push(format!(
                        "{}: no unused entry found in object 0x1016",
                        s.name
                    )),
                }
            } else {
                for &(sub, v) in &consumers {
                    if v & 0xFFFF != 0 && node(v) == self.node_id {
                        let mut warnings = Vec::new();
                        if let Ok(e) = s.concise(
                            0x1016,
                            sub,
                            Number::Int((node(v) << 16).into()),
                            &mut warnings,
                        ) {
                            s.sdo.insert(0, e);
                            s.sdo_origin.insert(0, origin.clone());
                        }
                        cx.warnings.extend(warnings);
                    }
                }
            }
        }
    }

    /// The text of `master.dcf`; `remote_pdo` adds the remote PDO objects.
    pub fn render(&self, slaves: &[Slave], remote_pdo: bool) -> String {
        crate::master_dcf::render(self, slaves, remote_pdo)
    }
}

/// The PDOs the master receives (the slaves' TPDOs) or sends (their RPDOs), with the slave of each.
pub(crate) fn pdos(slaves: &[Slave], tpdo: bool) -> Vec<(&Slave, u32, &Pdo)> {
    slaves
        .iter()
        .flat_map(|s| {
            let list = if tpdo { &s.tpdo } else { &s.rpdo };
            list.iter().map(move |(n, p)| (s, *n, p))
        })
        .collect()
}

/// Writes `args` then a newline.
pub(crate) fn line(out: &mut String, args: std::fmt::Arguments) {
    let _ = out.write_fmt(args);
    out.push('\n');
}

/// The entries of a PDO not mapped earlier in the same slave, by position.
pub(crate) fn first_mapped<'a>(pdo: &'a Pdo, mapped: &mut Vec<(u16, u8)>) -> Vec<&'a Mapped> {
    let mut out = Vec::new();
    for (_, m) in &pdo.mapping {
        if !mapped.contains(&(m.index, m.sub)) {
            mapped.push((m.index, m.sub));
            out.push(m);
        }
    }
    out
}
