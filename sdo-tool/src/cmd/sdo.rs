//! The commands that are SDO transfers — `read`, `write`, `dump`, `apply` — run alike on a CAN bus
//! and on an EtherCAT chain, after a look at the node's identity.

use std::io::Write;

use od::dict::Address;

use super::apply::ApplyArgs;
use super::dump::DumpArgs;
use super::read::ReadArgs;
use super::write::WriteArgs;
use super::Context;
use crate::{SdoCommands, ToolError};

/// One of the SDO commands, with its arguments.
#[derive(Debug, Clone, Copy)]
pub enum SdoCommand<'a> {
    /// `read`.
    Read(&'a ReadArgs),
    /// `write`.
    Write(&'a WriteArgs),
    /// `dump`.
    Dump(&'a DumpArgs),
    /// `apply`.
    Apply(&'a ApplyArgs),
}

impl SdoCommand<'_> {
    /// The node the command addresses.
    pub fn node(&self) -> u8 {
        match self {
            SdoCommand::Read(a) => a.node,
            SdoCommand::Write(a) => a.node,
            SdoCommand::Dump(a) => a.node,
            SdoCommand::Apply(a) => a.node,
        }
    }

    /// Runs the command on `commands` (any network), printing to `out`; first, with a
    /// description, a warning when the node's identity is not the description's.
    pub fn run(
        self,
        commands: &mut SdoCommands<'_>,
        ctx: Context<'_>,
        out: &mut dyn Write,
    ) -> Result<(), ToolError> {
        if let Some(d) = ctx.desc {
            if let Some(w) = identity_mismatch(commands, self.node(), d) {
                eprintln!("sdo-tool: warning: {w}");
            }
        }
        match self {
            SdoCommand::Read(a) => super::read::run(a, commands, ctx, out),
            SdoCommand::Write(a) => super::write::run(a, commands, ctx, out),
            SdoCommand::Dump(a) => super::dump::run(a, commands, ctx, out),
            SdoCommand::Apply(a) => super::apply::run(a, commands, ctx, out),
        }
    }
}

/// When `node`'s 0x1018:01 and 0x1018:02 (vendor and product) are not the description's: the warning
/// that says so. Nothing when they match, or when the node does not give them (the command then
/// reports what it finds).
fn identity_mismatch(
    commands: &mut SdoCommands<'_>,
    node: u8,
    desc: &od::DeviceDescription,
) -> Option<String> {
    let id = &desc.identity;
    if id.vendor_id == 0 && id.product_code == 0 {
        return None;
    }
    let mut read = |sub: u8| {
        let b = commands.read_raw(node, Address::new(0x1018, sub)).ok()?;
        Some(u32::from_le_bytes(b.get(..4)?.try_into().ok()?))
    };
    let (vendor, product) = (read(1)?, read(2)?);
    (vendor != id.vendor_id || product != id.product_code).then(|| {
        format!(
            "the description (--od) is of vendor 0x{:08X}, product 0x{:08X} ({}); node {node} \
             reports vendor 0x{vendor:08X}, product 0x{product:08X}",
            id.vendor_id, id.product_code, id.product_name
        )
    })
}
