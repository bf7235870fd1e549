//! The plan of a folder of DCFs, one per slave, as a configuration tool exports a network (or
//! `sdo-tool dump` writes a node): no bus description and no master DCF, each slave's DCF itself
//! being what the master checks and writes.

use od::object::AccessType;
use od::DeviceDescription;

use super::plan::{ConfigEntry, Expect, Plan, SlavePlan};
use crate::concise::Entry;
use crate::file::{ini_keys, IniKeys};
use crate::slave::int_value;

/// One slave's DCF: its name (the file's stem), the file's name for origins, what `od` read and
/// the file's text (for the lines of its values).
#[derive(Debug, Clone)]
pub struct SlaveDcf {
    /// The name shown for the slave.
    pub name: String,
    /// The file, as origins name it.
    pub file: String,
    /// The description `od` read.
    pub desc: DeviceDescription,
    /// The file's text.
    pub text: String,
}

/// The heartbeat multiplier dcfgen takes by default: the master waits three producer periods.
const HEARTBEAT_MULTIPLIER: u32 = 3;

impl Plan {
    /// The plan of `dcfs`, each a slave at the node-ID its `[DeviceComissioning] NodeID` gives
    /// (one without is refused, naming the file), booted and started one by one, none mandatory;
    /// the master (node-ID `master_id`) sends no heartbeat. Each slave's device type and identity
    /// are checked against its DCF's 0x1000 and 0x1018 (0 is not checked); its configuration is
    /// every entry the DCF gives a value (`ParameterValue`) that a master can write, in index
    /// order, each PDO as CiA 301 §7.3 asks: its COB-ID made invalid, its other parameters, the
    /// mapping emptied, its entries, its count, then its COB-ID as the DCF gives it; the
    /// configuration's date and time (0x1020), when the DCF gives both, last: a node that holds
    /// them already is not configured again. The master waits three of its heartbeat producer
    /// periods (0x1017) for it.
    pub fn from_dcfs(dcfs: &[SlaveDcf], master_id: u8) -> Result<Plan, String> {
        let mut slaves = Vec::new();
        for d in dcfs {
            let node_id = d
                .desc
                .node_id()
                .filter(|n| (1..=127).contains(n))
                .ok_or_else(|| format!("{}: no NodeID in [DeviceComissioning]", d.file))?;
            let keys = ini_keys(&d.text);
            let dict = &d.desc.dictionary;
            let value = |index: u16, sub: u8| {
                dict.object(index)
                    .and_then(|o| int_value(o, sub))
                    .map_or(0, |v| v as u32)
            };
            let expect = |index: u16, sub: u8| Expect {
                value: value(index, sub),
                origin: format!(
                    "{}:{} 0x{index:04X}:{sub:02X}",
                    d.file,
                    keys.line(index, sub)
                ),
            };
            let producer = value(0x1017, 0).min(0xFFFF);
            slaves.push(SlavePlan {
                node_id,
                name: d.name.clone(),
                assignment: 0x05,
                device_type: expect(0x1000, 0),
                identity: [
                    expect(0x1018, 1),
                    expect(0x1018, 2),
                    expect(0x1018, 3),
                    expect(0x1018, 4),
                ],
                software: Expect::default(),
                heartbeat_ms: (producer * HEARTBEAT_MULTIPLIER).min(0xFFFF) as u16,
                heartbeat_origin: format!("{}:{} 0x1017:00", d.file, keys.line(0x1017, 0)),
                stamp: stamp(d),
                configuration: configuration(d, &keys),
            });
        }
        slaves.sort_by_key(|s| s.node_id);
        if let Some(w) = slaves.windows(2).find(|w| w[0].node_id == w[1].node_id) {
            return Err(format!(
                "node-ID {} is given twice ({} and {})",
                w[0].node_id, w[0].name, w[1].name
            ));
        }
        Ok(Plan {
            master_id,
            startup: 0x01,
            boot_time_ms: 0,
            heartbeat_ms: 0,
            slaves,
        })
    }
}

/// The configuration's date and time (0x1020:01 and :02) the DCF gives, both.
fn stamp(d: &SlaveDcf) -> Option<[u32; 2]> {
    let o = d.desc.dictionary.object(0x1020)?;
    let v = |sub: u8| {
        o.sub(sub)
            .filter(|s| s.value_set)
            .and_then(|_| int_value(o, sub))
            .map(|v| v as u32)
    };
    Some([v(1)?, v(2)?])
}

/// Whether a master writes an entry of this access.
fn writable(kind: AccessType) -> bool {
    matches!(
        kind,
        AccessType::Rw | AccessType::Wo | AccessType::Rww | AccessType::Rwr
    )
}

/// The entries a DCF sets, in the order a master writes them.
fn configuration(d: &SlaveDcf, keys: &IniKeys) -> Vec<ConfigEntry> {
    let dict = &d.desc.dictionary;
    let set = |index: u16, sub: u8| {
        dict.object(index)
            .and_then(|o| o.sub(sub))
            .filter(|s| s.value_set && writable(s.access.kind))
            .map(|s| s.value.clone())
    };
    let mut out = Vec::new();
    let mut push = |index: u16, sub: u8, data: Vec<u8>| {
        out.push(ConfigEntry {
            entry: Entry::new(index, sub, data),
            origin: format!(
                "{}:{} 0x{index:04X}:{sub:02X}",
                d.file,
                keys.line(index, sub)
            ),
        });
    };
    for o in dict.objects() {
        let index = o.index;
        // Store and restore are commands, not configuration; the program area is not written;
        // the configuration's stamp goes last.
        if matches!(index, 0x1010 | 0x1011 | 0x1020) || (0x1F50..=0x1F5F).contains(&index) {
            continue;
        }
        let pdo_comm = (0x1400..0x1600).contains(&index) || (0x1800..0x1A00).contains(&index);
        let pdo_map = (0x1600..0x1800).contains(&index) || (0x1A00..0x1C00).contains(&index);
        if pdo_map {
            continue;
        }
        if !pdo_comm {
            for (&sub, _) in o.subs.iter() {
                if let Some(v) = set(index, sub) {
                    push(index, sub, v);
                }
            }
            continue;
        }
        let map = index + 0x200;
        let count = set(map, 0);
        let entries: Vec<(u8, Vec<u8>)> = dict
            .object(map)
            .map(|m| {
                m.subs
                    .keys()
                    .filter(|&&s| s != 0)
                    .filter_map(|&s| set(map, s).map(|v| (s, v)))
                    .collect()
            })
            .unwrap_or_default();
        let cob = set(index, 1);
        let others: Vec<(u8, Vec<u8>)> = o
            .subs
            .keys()
            .filter(|&&s| s > 1)
            .filter_map(|&s| set(index, s).map(|v| (s, v)))
            .collect();
        if cob.is_none() && others.is_empty() && count.is_none() && entries.is_empty() {
            continue;
        }
        // The COB-ID the PDO has now, made invalid while it is changed (bit 31).
        let final_cob = cob.clone().unwrap_or_else(|| {
            dict.object(index)
                .and_then(|o| o.sub(1))
                .map(|s| s.value.clone())
                .unwrap_or_default()
        });
        let mut invalid = final_cob.clone();
        invalid.resize(4, 0);
        invalid[3] |= 0x80;
        push(index, 1, invalid.clone());
        for (s, v) in others {
            push(index, s, v);
        }
        if count.is_some() || !entries.is_empty() {
            push(map, 0, vec![0]);
            let n = entries.len() as u8;
            for (s, v) in entries {
                push(map, s, v);
            }
            push(map, 0, count.unwrap_or_else(|| vec![n]));
        }
        if final_cob != invalid {
            push(index, 1, final_cob);
        }
    }
    if stamp(d).is_some() {
        for sub in [1, 2] {
            if let Some(v) = set(0x1020, sub) {
                push(0x1020, sub, v);
            }
        }
    }
    out
}
