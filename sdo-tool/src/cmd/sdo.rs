//! The commands that are SDO transfers — `read`, `write`, `dump`, `apply` — run alike on a CAN bus
//! and on an EtherCAT chain. With a description, the node's identity (0x1018:01 and 0x1018:02) is
//! read first where it matters: to pick the node's device from a file describing several (an ESI
//! of a device family), and before `write`, `dump` and `apply`, to warn of a description of another
//! device. A `read` with a description of one device reads nothing else.

use std::io::Write;

use od::dict::Address;

use super::apply::ApplyArgs;
use super::dump::DumpArgs;
use super::read::ReadArgs;
use super::write::WriteArgs;
use super::Context;
use crate::{SdoAccess, SdoCommands, ToolError};

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

    /// Runs the command on `sdo` (any network), printing to `out`, with the device of
    /// `ctx.devices` the node is ([`pick_device`]): a warning when the node's identity is not the
    /// description's.
    pub fn run(
        self,
        sdo: &mut dyn SdoAccess,
        ctx: Context<'_>,
        out: &mut dyn Write,
    ) -> Result<(), ToolError> {
        let check = !matches!(self, SdoCommand::Read(_));
        let desc = match pick_device(sdo, self.node(), ctx.devices, check) {
            Picked::Device(d) => Some(d),
            Picked::Other { first, warning } => {
                eprintln!("sdo-tool: warning: {warning}");
                Some(first)
            }
            Picked::None => None,
        };
        let ctx = Context { desc, ..ctx };
        let commands = &mut SdoCommands::new(sdo, desc.map(|d| &d.dictionary));
        match self {
            SdoCommand::Read(a) => super::read::run(a, commands, ctx, out),
            SdoCommand::Write(a) => super::write::run(a, commands, ctx, out),
            SdoCommand::Dump(a) => super::dump::run(a, commands, ctx, out),
            SdoCommand::Apply(a) => super::apply::run(a, commands, ctx, out),
        }
    }
}

/// The device of a description the command runs with.
#[derive(Debug)]
pub enum Picked<'a> {
    /// No description.
    None,
    /// The node's device (by its identity), or the description's only one when its identity was
    /// not read or not given.
    Device(&'a od::DeviceDescription),
    /// The node reports an identity none of the devices has: the first device, and the warning.
    Other {
        /// The description's first device.
        first: &'a od::DeviceDescription,
        /// The words of the warning.
        warning: String,
    },
}

/// The device of `devices` that `node` is. With one device, the node's identity is read only when
/// `check` (before a command that changes the node or writes a file), to warn of another device's
/// description; with several, it is read to find the node's (vendor and product, 0x1018:01 and
/// 0x1018:02). A node that does not give its identity gets the first device without a warning (the
/// command then reports what it finds).
pub fn pick_device<'a>(
    sdo: &mut dyn SdoAccess,
    node: u8,
    devices: &'a [od::DeviceDescription],
    check: bool,
) -> Picked<'a> {
    let Some(first) = devices.first() else {
        return Picked::None;
    };
    let known =
        |d: &od::DeviceDescription| d.identity.vendor_id != 0 || d.identity.product_code != 0;
    if (devices.len() == 1 && !check) || !devices.iter().any(known) {
        return Picked::Device(first);
    }
    let mut read = |sub: u8| {
        let b = sdo.read_bytes(node, Address::new(0x1018, sub)).ok()?;
        Some(u32::from_le_bytes(b.get(..4)?.try_into().ok()?))
    };
    let Some((vendor, product)) = read(1).zip(read(2)) else {
        return Picked::Device(first);
    };
    if let Some(d) = devices
        .iter()
        .find(|d| d.identity.vendor_id == vendor && d.identity.product_code == product)
    {
        return Picked::Device(d);
    }
    let id = &first.identity;
    let warning = if devices.len() == 1 {
        format!(
            "the description (--od) is of vendor 0x{:08X}, product 0x{:08X} ({}); node {node} \
             reports vendor 0x{vendor:08X}, product 0x{product:08X}",
            id.vendor_id, id.product_code, id.product_name
        )
    } else {
        format!(
            "none of the {} devices of the description (--od) is of vendor 0x{vendor:08X}, \
             product 0x{product:08X}, which node {node} reports; the first, {} (vendor \
             0x{:08X}, product 0x{:08X}), is used",
            devices.len(),
            id.product_name,
            id.vendor_id,
            id.product_code
        )
    };
    Picked::Other { first, warning }
}
