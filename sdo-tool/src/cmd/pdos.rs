//! `pdos`, `xml` and `cstruct`: each slave's SyncManagers, PDOs and entries as IgH's tool shows
//! them, from the SII and, for a slave with CoE, from its PDO assignment and mapping objects.
//!
//! As IgH's master does: the SyncManagers and their default PDOs come from the SII (its SyncM,
//! TxPDO and RxPDO categories); then, for a slave with CoE, each process-data SyncManager's
//! assignment is read from 0x1C10 + n and each assigned PDO's mapping from the PDO's object, and
//! replace the SII's for that SyncManager (where any of those reads fails, the SII's stay). The
//! CoE reads need the chain in Pre-Op: a chain in Init is brought there for them and back to Init;
//! a chain another master runs is left alone, and its slaves' PDOs are the SIIs' (said on standard
//! error). A PDO or entry read by CoE is named after the SII's PDO or entry of the same index.

use std::io::Write;
use std::time::Duration;

use od::dict::Address;

use crate::ethercat::{Chain, EthercatError, EthercatSession};
use crate::igh::{self, EntryConfig, PdoConfig, SlaveConfig, SyncConfig};
use crate::link::Capture;
use crate::{SdoAccess, ToolError};

/// The arguments of `pdos`, `xml` and `cstruct`.
#[derive(Debug, clap::Args)]
pub struct SlavesOf {
    /// The slave's position (1 = first); every slave without it.
    pub position: Option<u16>,
}

/// Which layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// `pdos`.
    Pdos,
    /// `xml`.
    Xml,
    /// `cstruct`.
    Cstruct,
}

/// PDOs as CoE gives them: each PDO's index and its entries (index, sub-index, bit length).
pub type Assignment = Vec<(u16, Vec<(u16, u8, u8)>)>;

/// The PDOs assigned to SyncManager `sync` of the slave at `node` by CoE: 0x1C10 + `sync` and each
/// PDO's mapping (entries as index, sub-index and bit length), or `None` when a read of them fails.
pub fn coe_assignment(sdo: &mut dyn SdoAccess, node: u8, sync: u8) -> Option<Assignment> {
    let assign = 0x1C10 + u16::from(sync);
    let count = *sdo
        .read_bytes(node, Address::new(assign, 0))
        .ok()?
        .first()?;
    let mut pdos = Vec::new();
    for k in 1..=count {
        let b = sdo.read_bytes(node, Address::new(assign, k)).ok()?;
        let pdo = u16::from_le_bytes([*b.first()?, *b.get(1)?]);
        let n = *sdo.read_bytes(node, Address::new(pdo, 0)).ok()?.first()?;
        let mut entries = Vec::new();
        for e in 1..=n {
            let b = sdo.read_bytes(node, Address::new(pdo, e)).ok()?;
            let v = u32::from_le_bytes(b.get(..4)?.try_into().ok()?);
            entries.push(((v >> 16) as u16, (v >> 8) as u8, v as u8));
        }
        pdos.push((pdo, entries));
    }
    Some(pdos)
}

/// The PDOs of `assignment` named after the SII's PDOs and entries of the same index in `sii`
/// (every PDO of its categories, assigned or not).
fn named(assignment: Assignment, sii: &[PdoConfig]) -> Vec<PdoConfig> {
    let pdo_name = |index: u16| {
        sii.iter()
            .find(|p| p.index == index)
            .map(|p| p.name.clone())
            .unwrap_or_default()
    };
    let entry_name = |index: u16, sub: u8| {
        sii.iter()
            .flat_map(|p| &p.entries)
            .find(|e| index != 0 && e.index == index && e.sub == sub)
            .map(|e| e.name.clone())
            .unwrap_or_default()
    };
    assignment
        .into_iter()
        .map(|(index, entries)| PdoConfig {
            index,
            name: pdo_name(index),
            entries: entries
                .into_iter()
                .map(|(index, sub, bit_len)| EntryConfig {
                    index,
                    sub,
                    bit_len,
                    name: entry_name(index, sub),
                })
                .collect(),
        })
        .collect()
}

/// The CoE assignments of the slave at `node` over its SII's (SyncManagers 2 on), named after
/// `sii`, every PDO of its SII.
pub fn apply_coe(sdo: &mut dyn SdoAccess, node: u8, syncs: &mut [SyncConfig], sii: &[PdoConfig]) {
    for sync in syncs.iter_mut().filter(|s| s.index >= 2) {
        if let Some(assignment) = coe_assignment(sdo, node, sync.index) {
            sync.pdos = named(assignment, sii);
        }
    }
}

/// A slave read for these commands: its configuration and whether it has CoE.
struct Read {
    config: SlaveConfig,
    coe: bool,
    /// Every PDO of its SII, for the names.
    sii_pdos: Vec<PdoConfig>,
}

/// Reads the SII of the slave at `position`.
fn read_slave(chain: &mut Chain, position: u16) -> Result<Read, ToolError> {
    let sii = chain.sii(position)?;
    let image = od::sii::Image::read(&sii.bytes).map_err(|e| EthercatError::Eeprom {
        interface: chain.interface().to_string(),
        position,
        detail: format!("its SII does not read: {e}"),
    })?;
    let general = image.general().unwrap_or_default();
    Ok(Read {
        config: SlaveConfig {
            position,
            identity: image.identity,
            order: image.string(general.order).to_string(),
            name: image.string(general.name).to_string(),
            syncs: igh::sii_syncs(&image),
        },
        coe: image.protocols & 0x04 != 0,
        sii_pdos: igh::sii_pdos(&image).into_iter().map(|(_, p)| p).collect(),
    })
}

/// The slaves' configurations: their SIIs, then for those with CoE their assignments in Pre-Op.
fn configurations(
    interface: &str,
    position: Option<u16>,
    timeout: Duration,
    capture: Option<&Capture>,
) -> Result<Vec<SlaveConfig>, ToolError> {
    let mut slaves = Vec::new();
    {
        let mut chain = Chain::open(interface, timeout, capture)?;
        let positions: Vec<u16> = match position {
            Some(p) => {
                chain.check_position(p)?;
                vec![p]
            }
            None => (1..=chain.count()).collect(),
        };
        for p in positions {
            slaves.push(read_slave(&mut chain, p)?);
        }
    }
    if slaves.iter().any(|s| s.coe) {
        match EthercatSession::open_captured(interface, timeout, capture) {
            Ok(mut session) => {
                for s in slaves.iter_mut().filter(|s| s.coe) {
                    let node = u8::try_from(s.config.position).unwrap_or(u8::MAX);
                    apply_coe(&mut session, node, &mut s.config.syncs, &s.sii_pdos);
                }
            }
            Err(ToolError::Ethercat(EthercatError::Running { state, .. })) => eprintln!(
                "sdo-tool: the chain is in {state}, another master's: the PDOs shown are the SIIs' \
                 (the CoE assignment is read in Pre-Op)"
            ),
            Err(e) => return Err(e),
        }
    }
    Ok(slaves.into_iter().map(|s| s.config).collect())
}

/// `pdos`, `xml` or `cstruct` of the slave at POS (every slave without it); with `--json` the
/// listing as one object, the ESI or the C text as the string of one.
pub fn run(
    interface: &str,
    args: &SlavesOf,
    layout: Layout,
    json: bool,
    timeout: Duration,
    capture: Option<&Capture>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let io = ToolError::Output;
    let slaves = configurations(interface, args.position, timeout, capture)?;
    let text = match layout {
        Layout::Pdos if json => {
            let list: Vec<serde_json::Value> = slaves.iter().map(slave_json).collect();
            format!("{}\n", serde_json::json!({ "slaves": list }))
        }
        Layout::Pdos => {
            let mut s = String::new();
            for slave in &slaves {
                if slaves.len() > 1 && !slave.syncs.is_empty() {
                    s.push_str(&format!("=== Slave {} ===\n", slave.position));
                }
                s.push_str(&igh::pdos(&slave.syncs));
            }
            s
        }
        Layout::Xml if json => format!("{}\n", serde_json::json!({ "xml": igh::xml(&slaves) })),
        Layout::Xml => igh::xml(&slaves),
        Layout::Cstruct => {
            let text: String = slaves.iter().map(igh::cstruct).collect();
            if json {
                format!("{}\n", serde_json::json!({ "cstruct": text }))
            } else {
                text
            }
        }
    };
    out.write_all(text.as_bytes()).map_err(io)
}

/// A slave's SyncManagers and PDOs as `pdos --json` gives them.
fn slave_json(s: &SlaveConfig) -> serde_json::Value {
    let syncs: Vec<serde_json::Value> = s
        .syncs
        .iter()
        .map(|sync| {
            let pdos: Vec<serde_json::Value> = sync
                .pdos
                .iter()
                .map(|p| {
                    let entries: Vec<serde_json::Value> = p
                        .entries
                        .iter()
                        .map(|e| {
                            serde_json::json!({"index": e.index, "sub": e.sub,
                                "bits": e.bit_len, "name": e.name})
                        })
                        .collect();
                    serde_json::json!({"index": p.index, "name": p.name, "entries": entries})
                })
                .collect();
            serde_json::json!({
                "sm": sync.index, "start_address": sync.start_address,
                "default_size": sync.default_size, "control": sync.control,
                "enable": sync.enable, "direction": if sync.output() { "rx" } else { "tx" },
                "pdos": pdos,
            })
        })
        .collect();
    serde_json::json!({"position": s.position, "syncs": syncs})
}
