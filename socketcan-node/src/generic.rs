//! Any CANopen description (EDS, DCF, XDD, XDC) made ready to run as a node with a CiA 402 drive
//! behind each drive axis ([`ds402::generic::GenericApp`]), as `ethercat_slave::generic::Template`
//! makes an ESI device ready for the EtherCAT emulator.
//!
//! - [`Prepared::load`] reads a file's first device and tells the node-ID it runs as: the one
//!   given, else the description's (a DCF's `NodeID`), else none (0xFF, a node an LSS master
//!   configures) for a DCF without one; an EDS or XDD without a node-ID given is refused.
//! - [`Prepared::new`] makes a description ready: a DCF's values become its power-on values
//!   ([`ds402::generic::power_on_values`]); the dictionary gets what a real device reports where the
//!   description gives no value ([`ds402::generic::complete`]: identity, names, device type,
//!   supported drive modes, factory settings in place of values a drive cannot run with), each
//!   change one event ([`Prepared::events`]); and each drive axis its simulation record at 0x5FF0 +
//!   axis ([`ds402::generic::add_sim_records`]).
//! - [`unique_serials`] gives nodes of the same identity serial numbers of their own, so that LSS
//!   tells them apart.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use ds402::drive::DriveConfig;
use ds402::generic;
use od::device::DeviceDescription;
use od::error::LoadError;
use od::event::Event;
use od::load::Format;

use crate::node::lss::UNCONFIGURED;

/// Why a description cannot run as a CANopen node.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PrepareError {
    /// The file does not load (it cannot be read, or its description does not parse).
    #[error("{}: {source}", path.display())]
    Load {
        /// The file.
        path: PathBuf,
        /// Why.
        source: LoadError,
    },
    /// The file is an ESI: an EtherCAT device.
    #[error("{}: an ESI describes an EtherCAT device; run it with ethercat-node", path.display())]
    Esi {
        /// The file.
        path: PathBuf,
    },
    /// The file describes no device.
    #[error("{}: describes no device", path.display())]
    NoDevice {
        /// The file.
        path: PathBuf,
    },
    /// No node-ID was given and the description has none either (an EDS or an XDD).
    #[error("{}: the {format} gives no node-ID", path.display())]
    NoNodeId {
        /// The file.
        path: PathBuf,
        /// Its format.
        format: Format,
    },
}

/// One description made ready to run as a node. See the [module documentation](self).
#[derive(Debug, Clone)]
pub struct Prepared {
    description: DeviceDescription,
    node_id: u8,
    events: Vec<Event>,
}

impl Prepared {
    /// The first device of the file at `path` (EDS, DCF, XDD or XDC), made ready ([`Prepared::new`])
    /// for drives made as `drive` says, with `node_id` (1 to 127, or 0xFF for none) or else the
    /// description's own.
    pub fn load(
        path: &Path,
        node_id: Option<u8>,
        drive: &DriveConfig,
    ) -> Result<Prepared, PrepareError> {
        let (format, mut devices) = od::load::load(path).map_err(|source| PrepareError::Load {
            path: path.to_path_buf(),
            source,
        })?;
        if format == Format::Esi {
            return Err(PrepareError::Esi {
                path: path.to_path_buf(),
            });
        }
        if devices.is_empty() {
            return Err(PrepareError::NoDevice {
                path: path.to_path_buf(),
            });
        }
        let description = devices.remove(0);
        let node_id = match node_id {
            Some(id) => id,
            None => match description.node_id() {
                Some(id) if (1..=127).contains(&id) => id,
                // A DCF without a node-ID is a node LSS configures.
                _ if description.commissioning.is_some() => UNCONFIGURED,
                _ => {
                    return Err(PrepareError::NoNodeId {
                        path: path.to_path_buf(),
                        format,
                    })
                }
            },
        };
        Ok(Prepared::new(description, node_id, drive))
    }

    /// `description` made ready to run as node `node_id` (0xFF: none, LSS) with drives made as
    /// `drive` says: a DCF's values its power-on values, the dictionary completed, the drives'
    /// simulation records added.
    pub fn new(mut description: DeviceDescription, node_id: u8, drive: &DriveConfig) -> Prepared {
        if description.commissioning.is_some() {
            generic::power_on_values(&mut description);
        }
        let events = generic::complete(&mut description, drive);
        generic::add_sim_records(&mut description.dictionary, &drive.sim);
        Prepared {
            description,
            node_id,
            events,
        }
    }

    /// The description as the node starts with it.
    pub fn description(&self) -> &DeviceDescription {
        &self.description
    }

    /// The description as the node starts with it, taken.
    pub fn into_description(self) -> DeviceDescription {
        self.description
    }

    /// The node-ID it runs as (0xFF: none, LSS).
    pub fn node_id(&self) -> u8 {
        self.node_id
    }

    /// What the description was given that it does not say itself
    /// ([`ds402::generic::complete`]), in index order.
    pub fn events(&self) -> &[Event] {
        &self.events
    }
}

/// Gives nodes of the same identity (0x1018:01–03) serial numbers (0x1018:04) counting up from
/// their description's: the first keeps its own, the second gets it + 1, and so on.
pub fn unique_serials(nodes: &mut [Prepared]) {
    let mut seen: HashMap<[u32; 3], u32> = HashMap::new();
    for node in nodes {
        unique_serial(&mut node.description, &mut seen);
    }
}

/// [`unique_serials`] for one node, `seen` counting the nodes of each identity before it.
fn unique_serial(desc: &mut DeviceDescription, seen: &mut HashMap<[u32; 3], u32>) {
    let read = |d: &DeviceDescription, sub| {
        d.dictionary
            .entry(0x1018, sub)
            .ok()
            .and_then(|e| e.current())
            .and_then(|v| v.as_i128())
            .map_or(0, |v| v as u32)
    };
    let key = [read(desc, 1), read(desc, 2), read(desc, 3)];
    let count = seen.entry(key).or_insert(0);
    let k = *count;
    *count += 1;
    if k == 0 {
        return;
    }
    if let Some(entry) = desc
        .dictionary
        .object_mut(0x1018)
        .and_then(|o| o.subs.get_mut(&4))
    {
        let serial = entry
            .current()
            .and_then(|v| v.as_i128())
            .map_or(0, |v| v as u32)
            .wrapping_add(k);
        let value = od::value::Value::Uint(u64::from(serial));
        if let Ok(bytes) = value.encode(entry.data_type) {
            entry.value = bytes;
            entry.default = Some(od::object::DefaultValue::plain(value));
        }
    }
}
