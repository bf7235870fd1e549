//! `nmt COMMAND NODE|all`: an NMT command on the bus.

use std::io::Write;

use super::emit;
use crate::{NmtCommand, Tool, ToolError, UsageError};

/// `nmt`'s arguments.
#[derive(Debug, clap::Args)]
pub struct NmtArgs {
    /// The command.
    pub command: String,
    /// The node, or `all`.
    pub node: String,
}

/// `nmt` on `tool`'s bus.
pub fn run(
    args: &NmtArgs,
    tool: &mut Tool,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let NmtArgs { command, node } = args;
    let c = NmtCommand::parse(command).ok_or_else(|| UsageError::NmtCommand {
        command: command.clone(),
    })?;
    let n = if node == "all" {
        0
    } else {
        node.parse::<u8>()
            .ok()
            .filter(|n| (1..=127).contains(n))
            .ok_or_else(|| UsageError::NmtNodeText { text: node.clone() })?
    };
    tool.nmt(c, n)?;
    emit(out, json, "OK", serde_json::json!({"ok": true}))
}
