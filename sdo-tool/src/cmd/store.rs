//! `save` and `restore`: the node's parameters stored (0x1010:01 = "save"), or its defaults
//! restored at its next reset (0x1011:01 = "load").

use std::io::Write;

use super::emit;
use crate::{Tool, ToolError};

/// `save`'s and `restore`'s arguments.
#[derive(Debug, clap::Args)]
pub struct StoreArgs {
    /// Node-ID, 1–127.
    pub node: u8,
}

/// `save` (or, with `restore`, `restore`) on `tool`'s bus.
pub fn run(
    args: &StoreArgs,
    restore: bool,
    tool: &mut Tool,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    tool.store(args.node, restore)?;
    emit(out, json, "OK", serde_json::json!({"ok": true}))
}
