//! `sdo-tool watch`: what goes on on the bus, in words — heartbeats and NMT state changes, EMCY
//! messages with their error code's meaning, and TPDOs of a node decoded field by field from its
//! mapping in a description.

use std::collections::HashMap;

use od::dict::Dictionary;
use od::types::DataType;
use od::value::Value;

use crate::TypeCode;
use socketcan_node::node::pdo::{PdoConfig, TPDO_COMM};
use socketcan_node::node::EmcyCode;
use socketcan_node::CanFrame;

/// The NMT state a heartbeat byte names.
pub fn nmt_state_name(byte: u8) -> &'static str {
    match byte & 0x7F {
        0x00 => "boot-up",
        0x04 => "stopped",
        0x05 => "operational",
        0x7F => "pre-operational",
        _ => "unknown state",
    }
}

/// One decoded TPDO: its COB-ID and the mapped entries with their names and types.
#[derive(Debug, Clone)]
struct PdoLayout {
    number: u16,
    fields: Vec<(String, DataType, usize)>,
}

/// Decodes the bus's frames into lines.
pub struct Watcher {
    node: Option<u8>,
    last_state: HashMap<u8, u8>,
    pdos: HashMap<u16, PdoLayout>,
}

impl Watcher {
    /// Watches `node` (or every node), decoding its TPDOs from `od` when given.
    pub fn new(node: Option<u8>, od: Option<&Dictionary>) -> Watcher {
        let mut pdos = HashMap::new();
        if let (Some(node), Some(od)) = (node, od) {
            let mut d = od.clone();
            d.reset(node);
            for k in 0..512u16 {
                let Some(pdo) = PdoConfig::read(&d, TPDO_COMM + k).filter(PdoConfig::valid) else {
                    continue;
                };
                let fields = pdo
                    .map
                    .iter()
                    .map(|e| {
                        let (name, ty) = match d.entry(e.index, e.sub) {
                            Ok(entry) => (entry.name.clone(), entry.data_type),
                            Err(_) => (
                                od::Address::new(e.index, e.sub).to_string(),
                                DataType::Unsigned8,
                            ),
                        };
                        (name, ty, e.len())
                    })
                    .collect();
                pdos.insert(
                    pdo.cob_id(),
                    PdoLayout {
                        number: k + 1,
                        fields,
                    },
                );
            }
        }
        Watcher {
            node,
            last_state: HashMap::new(),
            pdos,
        }
    }

    fn wanted(&self, id: u8) -> bool {
        self.node.is_none_or(|n| n == id)
    }

    /// The line for `frame`, if it is one the watcher reports.
    pub fn line(&mut self, frame: &CanFrame) -> Option<String> {
        let cob = frame.cob_id()?;
        let d = frame.data();
        match cob {
            0x701..=0x77F if d.len() == 1 => {
                let id = (cob - 0x700) as u8;
                if !self.wanted(id) {
                    return None;
                }
                let state = d[0];
                let before = self.last_state.insert(id, state & 0x7F);
                Some(match before {
                    Some(b) if b != state & 0x7F => format!(
                        "node {id}: NMT {} -> {}",
                        nmt_state_name(b),
                        nmt_state_name(state)
                    ),
                    _ if state == 0 => format!("node {id}: boot-up"),
                    _ => format!("node {id}: heartbeat, {}", nmt_state_name(state)),
                })
            }
            0x081..=0x0FF if d.len() == 8 => {
                let id = (cob - 0x80) as u8;
                if !self.wanted(id) {
                    return None;
                }
                let code = u16::from_le_bytes([d[0], d[1]]);
                Some(format!(
                    "node {id}: EMCY 0x{code:04X} ({}), error register 0x{:02X}, data {:02X} {:02X} {:02X} {:02X} {:02X}",
                    EmcyCode(code).meaning(),
                    d[2],
                    d[3],
                    d[4],
                    d[5],
                    d[6],
                    d[7]
                ))
            }
            _ => {
                let layout = self.pdos.get(&cob)?;
                let mut at = 0;
                let mut parts = Vec::new();
                for (name, ty, len) in &layout.fields {
                    let bytes = d.get(at..at + len)?;
                    at += len;
                    if name.starts_with("Dummy") {
                        continue;
                    }
                    let v = Value::decode(*ty, bytes).ok()?;
                    parts.push(format!("{name}={}", TypeCode::of(*ty).format(&v)));
                }
                Some(format!(
                    "node {}: TPDO {} {}",
                    self.node.unwrap_or(0),
                    layout.number,
                    parts.join(" ")
                ))
            }
        }
    }
}
