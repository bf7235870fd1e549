//! `scan`: every node on the bus, with its identity.

use std::io::Write;
use std::time::Duration;

use crate::{Tool, ToolError};

/// `scan`'s arguments.
#[derive(Debug, clap::Args)]
pub struct ScanArgs {
    /// How long to listen for answers, in ms.
    #[arg(long, default_value_t = 300)]
    pub wait_ms: u64,
}

/// `scan` on `tool`'s bus: a table, or with `--json` one object.
pub fn run(
    args: &ScanArgs,
    tool: &mut Tool,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let io = ToolError::Output;
    let nodes = tool.scan(Duration::from_millis(args.wait_ms))?;
    if json {
        // Numbers as numbers, the name as its text.
        let number = |v: &Option<String>| {
            v.as_deref()
                .and_then(|t| u64::from_str_radix(t.trim_start_matches("0x"), 16).ok())
        };
        let list: Vec<serde_json::Value> = nodes
            .iter()
            .map(|n| {
                serde_json::json!({
                    "node": n.node, "device_type": number(&n.device_type),
                    "vendor": number(&n.vendor), "product": number(&n.product),
                    "revision": number(&n.revision), "serial": number(&n.serial),
                    "name": n.name.as_deref().map(|t| t.trim_matches('"')),
                })
            })
            .collect();
        writeln!(out, "{}", serde_json::json!({ "nodes": list })).map_err(io)?;
        return Ok(());
    }
    writeln!(
        out,
        "node  device type  vendor      product     revision    serial      name"
    )
    .map_err(io)?;
    let show = |v: &Option<String>| v.clone().unwrap_or_else(|| "-".into());
    for n in &nodes {
        writeln!(
            out,
            "{:>4}  {:<11}  {:<10}  {:<10}  {:<10}  {:<10}  {}",
            n.node,
            show(&n.device_type),
            show(&n.vendor),
            show(&n.product),
            show(&n.revision),
            show(&n.serial),
            show(&n.name)
        )
        .map_err(io)?;
    }
    writeln!(out, "{} node(s)", nodes.len()).map_err(io)?;
    Ok(())
}
