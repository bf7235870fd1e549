//! `dump NODE -o FILE`: the node's parameters read into a DCF, with what was left out and why.

use std::io::Write;
use std::path::{Path, PathBuf};

use od::dict::Address;

use super::{emit, file_error, Context};
use crate::config::Skip;
use crate::{DumpOutcome, SdoCommands, ToolError, UsageError};

/// `dump`'s arguments.
#[derive(Debug, clap::Args)]
pub struct DumpArgs {
    /// Node-ID, 1–127 (with --ethercat: the slave's position, 1 = first).
    pub node: u8,
    /// The DCF to write.
    #[arg(short, long)]
    pub output: PathBuf,
}

/// `dump` on `commands` (any network), printing to `out`.
pub fn run(
    args: &DumpArgs,
    commands: &mut SdoCommands<'_>,
    ctx: Context<'_>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let DumpArgs { node, output } = args;
    let mut d = ctx.desc.cloned().ok_or(UsageError::DumpNeedsDescription)?;
    let as_read = d.clone();
    let outcome = commands.dump(*node, &mut d)?;
    for (entry, register) in &outcome.read_back {
        eprintln!(
            "sdo-tool: {} read through its read-back register {}",
            named(&d, entry),
            named(&d, register)
        );
    }
    od::eds::complete_new_file(&mut d);
    let bytes = dcf_bytes(ctx.od_path, as_read, d.clone());
    std::fs::write(output, bytes).map_err(|e| file_error(output, e))?;
    let (text, value) = report(&outcome, &d, output);
    emit(out, ctx.json, text, value)
}

/// `a` with its name in `d`: `0x2110:00 (ConfigOutput03a)`.
fn named(d: &od::DeviceDescription, a: &Address) -> String {
    d.dictionary
        .entry(a.index, a.sub)
        .map(|e| format!("{a} ({})", e.name))
        .unwrap_or_else(|_| a.to_string())
}

/// What `dump` says of `outcome`, as text and as JSON: the entries not read, the write-only ones,
/// those the description keeps from a scan, and how many of each kind were left out (the JSON also
/// the write-only entries read through a read-back register, which the text says on stderr).
fn report(
    outcome: &DumpOutcome,
    d: &od::DeviceDescription,
    output: &Path,
) -> (String, serde_json::Value) {
    let name = |a: &Address| named(d, a);
    let not_read: Vec<String> = outcome
        .refused
        .iter()
        .map(|(a, code)| format!("{}: not read, {code}", name(a)))
        .collect();
    let write_only: Vec<String> = outcome
        .skipped
        .iter()
        .filter(|(_, why)| *why == Skip::WriteOnly)
        .map(|(a, _)| name(a))
        .collect();
    let not_scanned: Vec<String> = outcome
        .skipped
        .iter()
        .filter(|(_, why)| *why == Skip::RefuseReadOnScan)
        .map(|(a, why)| format!("skipped {}: {why}", name(a)))
        .collect();
    let counts = left_out(outcome);
    let mut text = String::new();
    for l in &not_read {
        text.push_str(l);
        text.push('\n');
    }
    if !write_only.is_empty() {
        text.push_str(&format!(
            "{} write-only parameters cannot be read back and are not in the file: {}\n",
            write_only.len(),
            write_only.join(", ")
        ));
    }
    for l in &not_scanned {
        text.push_str(l);
        text.push('\n');
    }
    let kinds: Vec<String> = counts.iter().map(|(k, n)| format!("{n} {k}")).collect();
    text.push_str(&format!(
        "{} entries written to {}{}",
        outcome.read,
        output.display(),
        if kinds.is_empty() {
            String::new()
        } else {
            format!("; left out: {}", kinds.join(", "))
        }
    ));
    let value = serde_json::json!({
        "entries": outcome.read,
        "file": output.display().to_string(),
        "not_read": not_read,
        "write_only": write_only,
        "not_scanned": not_scanned,
        "left_out": counts,
        "read_back": outcome
            .read_back
            .iter()
            .map(|(entry, register)| serde_json::json!({"entry": name(entry), "through": name(register)}))
            .collect::<Vec<_>>(),
    });
    (text, value)
}

/// The entries left out, counted by kind.
fn left_out(outcome: &DumpOutcome) -> std::collections::BTreeMap<&'static str, usize> {
    let mut counts: std::collections::BTreeMap<&str, usize> = Default::default();
    for (_, why) in &outcome.skipped {
        let kind = match why {
            Skip::Command(_) => "command objects",
            Skip::NotWritable => "not writable",
            Skip::CyclicOutput(_) => "cyclic outputs",
            Skip::Domain => "DOMAINs",
            Skip::WriteOnly => "write-only",
            Skip::RefuseReadOnScan | Skip::RefuseWriteOnDownload => "refused by ObjFlags",
        };
        *counts.entry(kind).or_default() += 1;
    }
    counts
}

/// The DCF `dump` writes: the description file it read (`path`, when an EDS or DCF) with the values
/// read and what a DCF adds, so that what the description holds beyond the model stays; the
/// writer's DCF of `dumped` otherwise.
fn dcf_bytes(
    path: Option<&std::path::Path>,
    as_read: od::DeviceDescription,
    dumped: od::DeviceDescription,
) -> Vec<u8> {
    let original = path.and_then(|p| {
        let bytes = od::load::read_limited(p, od::load::MAX_FILE_BYTES).ok()?;
        Some((od::load::Format::detect(p, &bytes)?, bytes))
    });
    match original {
        Some((format, bytes)) => {
            od::carry::write(&bytes, format, &[as_read], od::load::Format::Dcf, &[dumped]).bytes
        }
        None => od::eds::write_dcf(&dumped).into_bytes(),
    }
}

#[cfg(test)]
mod dump_file {
    use super::dcf_bytes;

    /// `dump` writes the description it read with the values read: its comments and the keys the
    /// model does not hold stay, the values come in at their entries, and a DCF's commissioning
    /// section comes in.
    #[test]
    fn a_dump_keeps_the_description_file() {
        let dir = tempfile::tempdir().unwrap();
        let eds = dir.path().join("node.eds");
        std::fs::write(
            &eds,
            "; vendor notes\n[FileInfo]\nFileName=node.eds\nLastEDS=old.eds\n\n[DeviceInfo]\nVendorNumber=0x1\n\n\
             [1017]\nParameterName=Producer heartbeat time\nDataType=0x0006\nAccessType=rw\nDefaultValue=0\nDenotation=beat\n",
        )
        .unwrap();
        let (_, devices) = od::load::load(&eds).unwrap();
        let as_read = devices[0].clone();
        let mut dumped = as_read.clone();
        dumped
            .dictionary
            .store_parameter(0x1017, 0, &750u16.to_le_bytes())
            .unwrap();
        dumped.set_node_id(Some(5));
        let text = String::from_utf8(dcf_bytes(Some(&eds), as_read, dumped)).unwrap();
        assert!(
            text.starts_with("; vendor notes\n[FileInfo]\nFileName=node.eds\nLastEDS=old.eds\n"),
            "{text}"
        );
        assert!(
            text.contains("[1017]\nParameterName=Producer heartbeat time\nDataType=0x0006\nAccessType=rw\nDefaultValue=0\nParameterValue=0x02EE\nDenotation=beat\n"),
            "{text}"
        );
        assert!(text.contains("[DeviceComissioning]\nNodeID=5\n"), "{text}");
    }
}
