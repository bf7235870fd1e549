//! The commands of `sdo-tool`, one module per family: each has its arguments (a clap struct) and
//! what it does. [`crate::cli`] parses the command line and hands each command to its module.
//!
//! - [`read`], [`mod@write`], [`dump`], [`apply`]: SDO transfers, on CAN or on EtherCAT ([`sdo`]);
//! - [`transfer`]: `upload` and `download` of a file, with a progress bar;
//! - [`store`]: `save` and `restore`; [`nmt`]; [`scan`]; [`gateway`]: the CiA 309-3 gateway;
//! - [`raw`]: `send` (a frame in cansend's notation) and `sync` (a SYNC producer);
//! - [`drive`]: a CiA 402 drive's state, enabled, homed, moved and jogged, on either network;
//! - [`lss`]: the LSS master (CiA 305): Fastscan, node-IDs, bit timing, store;
//! - [`watch`] and [`decode`]: the bus's frames in words, live or from a candump log;
//! - [`list`]: the entries of a description; [`net`]: a network's bus description made into the
//!   master's and the slaves' configuration files (`net gen`), or checked (`net check`), and the
//!   network booted and supervised ([`net_boot`]); [`ethercat`]: `slaves`, `states` and `sdos`;
//! - the other commands of IgH's `ethercat` tool: [`sii`] (`sii-read`, `sii-write`, `alias`),
//!   [`reg`] (`reg-read`, `reg-write`), [`pdos`] (`pdos`, `xml`, `cstruct`), [`foe`]
//!   (`foe-write`, `foe-read`).

use std::io::Write;
use std::path::Path;

use crate::{ToolError, UsageError};

pub mod apply;
pub mod decode;
pub mod drive;
pub mod dump;
pub mod ethercat;
pub mod foe;
pub mod gateway;
pub mod list;
pub mod lss;
pub mod net;
pub mod net_boot;
pub mod nmt;
pub mod pdos;
pub mod raw;
pub mod read;
pub mod reg;
pub mod scan;
pub mod sdo;
pub mod sii;
pub mod store;
pub mod transfer;
pub mod watch;
pub mod write;

/// What every command is run with beyond its own arguments: the output's form and the description.
#[derive(Clone, Copy)]
pub struct Context<'a> {
    /// `--json`: one JSON object per result.
    pub json: bool,
    /// The `--od` description's device the command runs with (the first, or the node's:
    /// [`sdo::pick_device`]).
    pub desc: Option<&'a od::DeviceDescription>,
    /// Every device of the `--od` description (most files describe one).
    pub devices: &'a [od::DeviceDescription],
    /// The `--od` file.
    pub od_path: Option<&'a Path>,
}

/// Writes `text`, or with `--json` the JSON object `value`, as one line.
pub fn emit(
    out: &mut dyn Write,
    json: bool,
    text: impl std::fmt::Display,
    value: serde_json::Value,
) -> Result<(), ToolError> {
    let r = if json {
        writeln!(out, "{value}")
    } else {
        writeln!(out, "{text}")
    };
    r.map_err(ToolError::Output)
}

/// A file that cannot be looked at, opened, created or written: a usage error naming it.
pub fn file_error(path: &Path, error: std::io::Error) -> UsageError {
    UsageError::File {
        path: path.to_path_buf(),
        error,
    }
}

/// Whether `path` is `-`: standard input or output.
pub fn is_dash(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// The bytes of `path`, or of standard input for `-`; at most `limit` bytes and one more are taken,
/// so that a caller refuses a larger input without reading it whole (`usize::MAX`: all of it).
pub fn read_input(path: &Path, limit: usize) -> Result<Vec<u8>, ToolError> {
    use std::io::Read;
    let take = u64::try_from(limit.saturating_add(1)).unwrap_or(u64::MAX);
    let mut bytes = Vec::new();
    if is_dash(path) {
        std::io::stdin()
            .lock()
            .take(take)
            .read_to_end(&mut bytes)
            .map_err(|e| file_error(Path::new("standard input"), e))?;
    } else {
        std::fs::File::open(path)
            .and_then(|f| f.take(take).read_to_end(&mut bytes))
            .map_err(|e| file_error(path, e))?;
    }
    Ok(bytes)
}

/// The first device of a description file; `what` says where it was given (`--od`, `apply`).
pub fn load_description(
    path: &Path,
    what: &'static str,
) -> Result<od::DeviceDescription, ToolError> {
    Ok(load_devices(path, what)?.swap_remove(0))
}

/// Every device of a description file, at least one; `what` says where it was given.
pub fn load_devices(
    path: &Path,
    what: &'static str,
) -> Result<Vec<od::DeviceDescription>, ToolError> {
    let (_, devices) = od::load::load(path).map_err(|error| UsageError::Description {
        what,
        path: path.to_path_buf(),
        error,
    })?;
    if devices.is_empty() {
        return Err(UsageError::NoDevice {
            what,
            path: path.to_path_buf(),
        }
        .into());
    }
    Ok(devices)
}
