//! `apply NODE FILE`: the values a DCF sets written to the node in CiA 301 order and read back,
//! then, with `--save`, stored.

use std::io::Write;
use std::path::PathBuf;

use super::{load_description, Context};
use crate::link::SAVE_SIGNATURE;
use crate::{ApplyOutcome, ApplyStep, SdoCommands, ToolError};

/// `apply`'s arguments.
#[derive(Debug, clap::Args)]
pub struct ApplyArgs {
    /// Node-ID, 1–127 (with --ethercat: the slave's position, 1 = first).
    pub node: u8,
    /// The DCF.
    pub file: PathBuf,
    /// Only show what would be written.
    #[arg(long)]
    pub dry_run: bool,
    /// Stop at the first refused write, as a strict configuration manager does.
    #[arg(long)]
    pub stop_on_error: bool,
    /// When every value is written and reads back equal, "save all parameters" (0x1010:01), so
    /// that the node keeps them over a power cycle.
    #[arg(long)]
    pub save: bool,
}

/// `apply` on `commands` (any network), printing to `out`: exit 1 when a write was refused, 4 when
/// a value reads back differently.
pub fn run(
    args: &ApplyArgs,
    commands: &mut SdoCommands<'_>,
    ctx: Context<'_>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let io = ToolError::Output;
    let json = ctx.json;
    let dcf = load_description(&args.file, "apply")?;
    let mut lines = Vec::new();
    let result = commands.apply(args.node, &dcf, args.dry_run, args.stop_on_error, |step| {
        lines.push(step_line(step, args.stop_on_error));
    });
    let outcome = match result {
        Ok(o) => o,
        Err(e) => {
            // The steps up to the failure, then the failure.
            if json {
                writeln!(out, "{}", serde_json::json!({ "steps": lines })).map_err(io)?;
            } else {
                for l in &lines {
                    writeln!(out, "{l}").map_err(io)?;
                }
            }
            return Err(e);
        }
    };
    // Saved only when everything was written and reads back equal.
    let save_result =
        (args.save && !args.dry_run && outcome.refused == 0 && outcome.differences == 0).then(
            || {
                commands.write(
                    args.node,
                    "0x1010:01",
                    Some("u32"),
                    &SAVE_SIGNATURE.to_string(),
                )
            },
        );
    let saved = matches!(save_result, Some(Ok(())));
    if json {
        summary_json(args, &outcome, &lines, saved, out)?;
    } else {
        summary(args, &outcome, &lines, saved, out)?;
    }
    if let Some(Err(e)) = save_result {
        return Err(e);
    }
    if outcome.refused > 0 {
        return Err(ToolError::Refused(outcome.refused));
    }
    if outcome.differences > 0 {
        return Err(ToolError::Differences(outcome.differences));
    }
    Ok(())
}

/// A step as its line: `wrote 0x1017:00 = 1000`, `REFUSED …`, `skipped …`.
fn step_line(step: &ApplyStep, stop_on_error: bool) -> String {
    use ApplyStep::*;
    let with = |step: &Option<&str>| step.map(|s| format!(" ({s})")).unwrap_or_default();
    match step {
        WouldWrite { addr, value, step } => {
            format!("would write {addr} = {value}{}", with(step))
        }
        Written { addr, value, step } => {
            format!("wrote {addr} = {value}{}", with(step))
        }
        Differs {
            addr,
            value,
            read_back,
        } => format!("DIFFERS {addr} = {value}, reads back {read_back}"),
        Refused { addr, value, error } => format!(
            "REFUSED {addr} = {value}: {error}{}",
            if stop_on_error {
                "; nothing after it written"
            } else {
                ""
            }
        ),
        Skipped { addr, value, why } => format!("skipped {addr} = {value}: {why}"),
    }
}

/// With `--json`: the steps and the counts, one object.
fn summary_json(
    args: &ApplyArgs,
    outcome: &ApplyOutcome,
    lines: &[String],
    saved: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let dry_run = args.dry_run;
    writeln!(
        out,
        "{}",
        serde_json::json!({
            "steps": lines,
            "written": if dry_run { 0 } else { outcome.written },
            "to_write": if dry_run { outcome.written } else { 0 },
            "skipped": outcome.skipped,
            "refused": outcome.refused,
            "refused_in_state": outcome.refused_in_state,
            "differences": outcome.differences,
            "saved": saved,
        })
    )
    .map_err(ToolError::Output)
}

/// The steps, a line each, then the counts, what to do about writes refused for the node's state,
/// and whether the parameters were saved.
fn summary(
    args: &ApplyArgs,
    outcome: &ApplyOutcome,
    lines: &[String],
    saved: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let io = ToolError::Output;
    let node = args.node;
    for l in lines {
        writeln!(out, "{l}").map_err(io)?;
    }
    writeln!(
        out,
        "{} entries {}, {} skipped, {} refused",
        outcome.written,
        if args.dry_run { "to write" } else { "written" },
        outcome.skipped,
        outcome.refused
    )
    .map_err(io)?;
    if outcome.refused_in_state > 0 {
        writeln!(
            out,
            "{} refused for the node's present state (0x08000022): configure it in \
             Pre-Operational (sdo-tool nmt preop {node}) and apply again",
            outcome.refused_in_state
        )
        .map_err(io)?;
    }
    if saved {
        writeln!(out, "saved: 0x1010:01 = \"save\"").map_err(io)?;
    }
    Ok(())
}
