//! What the manager boots: the master's CiA 302 objects for each slave, with where each value
//! comes from, so that a failed step names the line to look at.

use std::collections::BTreeMap;

use od::DeviceDescription;

use crate::bus::NetError;
use crate::concise::{self, Entry};
use crate::file::{ini_keys, IniKeys};
use crate::gen::Generated;
use crate::slave::int_value;

/// Reads a file a master DCF names (relative to its folder): its bytes, `None` when there is none,
/// or why it cannot be read.
pub type LoadFile<'a> = dyn FnMut(&str) -> Result<Option<Vec<u8>>, String> + 'a;

/// An expected value (0: not checked, as CiA 302-2 says of 0x1F84–0x1F88) and where it comes from.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Expect {
    /// The value.
    pub value: u32,
    /// Where it comes from, as `FILE:LINE` with what is there (`bus.yml:31, drive.eds`).
    pub origin: String,
}

/// One entry of a slave's configuration (its concise DCF, 0x1F22) and where it comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ConfigEntry {
    /// The entry.
    pub entry: Entry,
    /// Where it comes from (`bus.yml:44 drive.tpdo`).
    pub origin: String,
}

/// One slave as the master boots it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SlavePlan {
    /// Node-ID, 1–127.
    pub node_id: u8,
    /// Its name in the bus description.
    pub name: String,
    /// Its entry of 0x1F81 (NMT slave assignment).
    pub assignment: u32,
    /// 0x1F84: the device type (0x1000) it must have.
    pub device_type: Expect,
    /// 0x1F85–0x1F88: the vendor-ID, product code, revision and serial number (0x1018:01–04).
    pub identity: [Expect; 4],
    /// 0x1F55: the software identification (0x1F56:01) it must have, checked when 0x1F81 bit 5
    /// is set.
    pub software: Expect,
    /// The master's heartbeat consumer time for it (0x1016), ms; 0 when none.
    pub heartbeat_ms: u16,
    /// Where the heartbeat consumer time comes from.
    pub heartbeat_origin: String,
    /// Its configuration, in the order it is written.
    pub configuration: Vec<ConfigEntry>,
    /// The configuration's date and time (CiA 301 0x1020:01 and :02), which its last two entries
    /// write: a node whose 0x1020 holds them already keeps this configuration, which is then not
    /// written again.
    pub stamp: Option<[u32; 2]>,
}

impl SlavePlan {
    /// 0x1F81 bit 2: the master configures and starts it (else it is only watched).
    pub fn boots(&self) -> bool {
        self.assignment & 0x04 != 0
    }

    /// 0x1F81 bit 3: the network does not come up without it.
    pub fn mandatory(&self) -> bool {
        self.assignment & 0x08 != 0
    }

    /// 0x1F81 bit 4: keep alive, no reset communication while it runs.
    pub fn keep_alive(&self) -> bool {
        self.assignment & 0x10 != 0
    }

    /// 0x1F81 bit 5: its software version is checked.
    pub fn checks_software(&self) -> bool {
        self.assignment & 0x20 != 0
    }
}

/// The master's boot configuration.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Plan {
    /// The master's node-ID.
    pub master_id: u8,
    /// 0x1F80 (NMT startup).
    pub startup: u32,
    /// 0x1F89: how long (ms) the master waits for its mandatory slaves; 0: no limit.
    pub boot_time_ms: u32,
    /// The master's heartbeat producer time (0x1017), ms; 0 when it sends none.
    pub heartbeat_ms: u16,
    /// The slaves, by node-ID.
    pub slaves: Vec<SlavePlan>,
}

impl Plan {
    /// 0x1F80 bit 1: every slave is started with one NMT command once the mandatory ones booted.
    pub fn start_all(&self) -> bool {
        self.startup & 0x02 != 0
    }

    /// 0x1F80 bit 2 clear: the master enters Operational itself when the network is up.
    pub fn master_operational(&self) -> bool {
        self.startup & 0x04 == 0
    }

    /// 0x1F80 bit 3 clear: the master starts its slaves.
    pub fn starts_slaves(&self) -> bool {
        self.startup & 0x08 == 0
    }

    /// 0x1F80 bit 4: a lost mandatory slave resets every node.
    pub fn reset_all_on_loss(&self) -> bool {
        self.startup & 0x10 != 0
    }

    /// 0x1F80 bit 6: a lost mandatory slave stops every node.
    pub fn stop_all_on_loss(&self) -> bool {
        self.startup & 0x40 != 0
    }

    /// The plan of a generated bus description (`file` is its name, for the origins).
    pub fn from_generated(generated: &Generated, file: &str) -> Plan {
        let m = &generated.master;
        let mut slaves: Vec<SlavePlan> = generated
            .slaves
            .iter()
            .filter(|s| (1..=127).contains(&s.node_id))
            .map(|s| {
                let (dcf, dcf_line) = &s.dcf;
                let described = format!("{file}:{dcf_line}, {dcf}");
                // A value the section gives comes from its line; the others from the description.
                let expect = |value: u32, shown: bool, key: &str| Expect {
                    value: if shown { value } else { 0 },
                    origin: if s.key_lines.iter().any(|(k, _)| *k == key) {
                        format!("{file}:{} {}.{key}", s.key_line(key), s.name)
                    } else {
                        described.clone()
                    },
                };
                let configuration = s
                    .sdo
                    .iter()
                    .zip(&s.sdo_origin)
                    .map(|(entry, (line, key))| ConfigEntry {
                        entry: entry.clone(),
                        origin: format!("{file}:{line} {key}"),
                    })
                    .collect();
                SlavePlan {
                    node_id: s.node_id as u8,
                    name: s.name.clone(),
                    assignment: s.assignment(),
                    device_type: expect(s.device_type, true, ""),
                    identity: [
                        expect(s.vendor_id, true, ""),
                        expect(s.product_code, s.has_identity(2), ""),
                        expect(s.revision_number, s.has_identity(3), "revision_number"),
                        expect(s.serial_number, s.has_identity(4), "serial_number"),
                    ],
                    software: expect(s.software_version, true, "software_version"),
                    heartbeat_ms: if m.heartbeat_consumer {
                        s.consumer_time()
                    } else {
                        0
                    },
                    heartbeat_origin: format!(
                        "{file}:{} {}.heartbeat_producer",
                        s.key_line("heartbeat_producer"),
                        s.name
                    ),
                    configuration,
                    stamp: None,
                }
            })
            .collect();
        slaves.sort_by_key(|s| s.node_id);
        Plan {
            master_id: m.node_id as u8,
            startup: m.startup_word(),
            boot_time_ms: m.boot_time,
            heartbeat_ms: m.heartbeat_producer.min(0xFFFF) as u16,
            slaves,
        }
    }

    /// The plan a master DCF gives (`master.dcf` as `net gen` or dcfgen writes it): `desc` is the
    /// file as `od` read it and `text` the file itself (`file` its name), whose `UploadFile` keys of
    /// 0x1F22 name each slave's concise DCF; `load` reads such a file (relative to the DCF's
    /// folder) and `master.bin` when there is one, whose entries the master's own objects take first.
    pub fn from_master_dcf(
        desc: &DeviceDescription,
        text: &str,
        file: &str,
        load: &mut LoadFile,
    ) -> Result<Plan, NetError> {
        let keys = ini_keys(text);
        let error = |line: usize, key: &str, message: String| NetError {
            file: file.to_string(),
            line,
            key: key.to_string(),
            message,
        };
        // The master's own concise DCF: 0x1F55, 0x1F87, 0x1F88 live there, not in master.dcf.
        let mut own: BTreeMap<(u16, u8), u32> = BTreeMap::new();
        if let Some(bytes) = load("master.bin").map_err(|m| error(0, "master.bin", m))? {
            let entries = concise::decode(&bytes)
                .map_err(|e| error(0, "master.bin", format!("master.bin: {e}")))?;
            for e in entries {
                let mut b = [0u8; 4];
                let n = e.data.len().min(4);
                b[..n].copy_from_slice(&e.data[..n]);
                own.insert((e.index, e.sub), u32::from_le_bytes(b));
            }
        }
        let dict = &desc.dictionary;
        let value = |index: u16, sub: u8| -> u32 {
            own.get(&(index, sub)).copied().unwrap_or_else(|| {
                dict.object(index)
                    .and_then(|o| int_value(o, sub))
                    .map_or(0, |v| v as u32)
            })
        };
        let origin = |index: u16, sub: u8| {
            let at = if own.contains_key(&(index, sub)) {
                return format!("{file}: master.bin 0x{index:04X}:{sub:02X}");
            } else {
                keys.line(index, sub)
            };
            format!("{file}:{at} 0x{index:04X}:{sub:02X}")
        };
        let mut consumers = BTreeMap::new();
        if let Some(o) = dict.object(0x1016) {
            for &sub in o.subs.keys().filter(|&&k| k != 0) {
                let v = int_value(o, sub).unwrap_or(0) as u32;
                consumers.insert(((v >> 16) & 0xFF) as u8, ((v & 0xFFFF) as u16, sub));
            }
        }
        let mut slaves = Vec::new();
        for id in 1..=127u8 {
            let assignment = value(0x1F81, id);
            if assignment & 0x01 == 0 {
                continue;
            }
            // dcfgen names each concise DCF after its slave.
            let name = keys
                .upload_file(id)
                .and_then(|(_, f)| {
                    let stem = std::path::Path::new(&f).file_stem()?.to_str()?.to_string();
                    Some(stem)
                })
                .unwrap_or_else(|| format!("node-{id}"));
            let configuration = match keys.upload_file(id) {
                Some((line, name)) => {
                    let bytes = load(&name)
                        .map_err(|m| error(line, "UploadFile", m))?
                        .ok_or_else(|| error(line, "UploadFile", format!("{name}: not found")))?;
                    let entries = concise::decode(&bytes)
                        .map_err(|e| error(line, "UploadFile", format!("{name}: {e}")))?;
                    entries
                        .into_iter()
                        .enumerate()
                        .map(|(i, entry)| ConfigEntry {
                            entry,
                            origin: format!("{name} entry {}", i + 1),
                        })
                        .collect()
                }
                None => Vec::new(),
            };
            let expect = |index: u16| Expect {
                value: value(index, id),
                origin: origin(index, id),
            };
            let (heartbeat_ms, heartbeat_origin) = match consumers.get(&id) {
                Some(&(ms, sub)) => (ms, origin(0x1016, sub)),
                None => (0, String::new()),
            };
            // 0x1F26 and 0x1F27: the configuration's date and time, written last with it.
            let stamp = [value(0x1F26, id), value(0x1F27, id)];
            let mut configuration: Vec<ConfigEntry> = configuration;
            let stamp = (stamp != [0, 0] && !configuration.is_empty()).then(|| {
                for (sub, (index, v)) in [(0x1F26, stamp[0]), (0x1F27, stamp[1])].iter().enumerate()
                {
                    configuration.push(ConfigEntry {
                        entry: Entry::new(0x1020, sub as u8 + 1, v.to_le_bytes().to_vec()),
                        origin: origin(*index, id),
                    });
                }
                stamp
            });
            slaves.push(SlavePlan {
                node_id: id,
                name,
                assignment,
                device_type: expect(0x1F84),
                identity: [
                    expect(0x1F85),
                    expect(0x1F86),
                    expect(0x1F87),
                    expect(0x1F88),
                ],
                software: expect(0x1F55),
                heartbeat_ms,
                heartbeat_origin,
                configuration,
                stamp,
            });
        }
        Ok(Plan {
            master_id: desc.node_id().unwrap_or(0),
            startup: value(0x1F80, 0),
            boot_time_ms: value(0x1F89, 0),
            heartbeat_ms: value(0x1017, 0).min(0xFFFF) as u16,
            slaves,
        })
    }
}

impl IniKeys {
    /// The line of the value of `index:sub`: its key in the `[XXXXValue]` section of a compact
    /// array, else its `[XXXXsubN]` section's (or, for sub-index 0, `[XXXX]`'s) `ParameterValue`,
    /// else `DefaultValue`, else 0.
    pub(crate) fn line(&self, index: u16, sub: u8) -> usize {
        let compact = (format!("{index:04X}VALUE"), sub.to_string());
        let hex = (format!("{index:04X}VALUE"), format!("0x{sub:x}"));
        let own = format!("{index:04X}SUB{sub:X}");
        let plain = format!("{index:04X}");
        let key = |section: &str, k: &str| (section.to_string(), k.to_string());
        [
            compact,
            hex,
            key(&own, "parametervalue"),
            key(&own, "defaultvalue"),
            key(&plain, "parametervalue"),
            key(&plain, "defaultvalue"),
        ]
        .iter()
        .find_map(|(section, key)| self.get(section, key))
        .map_or(0, |(line, _)| line)
    }

    /// The `UploadFile` of 0x1F22 for `node`, with its line.
    fn upload_file(&self, node: u8) -> Option<(usize, String)> {
        self.get(&format!("1F22SUB{node:X}"), "uploadfile")
            .filter(|(_, v)| !v.is_empty())
            .map(|(line, v)| (line, v.to_string()))
    }
}
