//! `decode LOG [NODE]`: every frame of a candump log named, read line by line in bounded memory;
//! at the end, the SDO transfers left open.

use std::io::Write;
use std::path::PathBuf;

use super::{emit, file_error};
use crate::watch::{CobFilter, Kind, Watcher};
use crate::{ToolError, UsageError};

/// `decode`'s arguments.
#[derive(Debug, clap::Args)]
pub struct DecodeArgs {
    /// The log.
    pub log: PathBuf,
    /// Only this node (its PDOs need --od).
    pub node: Option<u8>,
    /// Also show the frames it cannot name, as ID#DATA.
    #[arg(long)]
    pub raw: bool,
    /// The frames to take, as candump's filters (hex identifiers): ID, ID:MASK, LOW-HIGH, ~ to
    /// invert; several with commas or again.
    #[arg(long, value_name = "FILTER", value_delimiter = ',')]
    pub filter: Vec<CobFilter>,
    /// Only these kinds of lines: nmt, heartbeat, sync, emcy, sdo, pdo, other (with commas).
    #[arg(long, value_name = "KINDS", value_delimiter = ',')]
    pub only: Vec<Kind>,
    /// Show a long value (a DOMAIN's, an OCTET_STRING's) whole, not its first 32 bytes and its
    /// length.
    #[arg(long)]
    pub full: bool,
}

/// `decode` with the `--od` description's dictionary, when given.
pub fn run(
    args: &DecodeArgs,
    od: Option<&od::Dictionary>,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let w = Watcher::new(args.node, od)
        .with_raw(args.raw)
        .with_filters(args.filter.clone())
        .with_only(args.only.clone())
        .with_full(args.full);
    decode(&args.log, w, json, out)
}

/// `decode`: every frame of a candump log, named, with its time since the log's first frame, read
/// line by line in bounded memory; at the end, the SDO transfers left open.
fn decode(
    path: &std::path::Path,
    w: crate::watch::Watcher,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    use crate::watch::{Decoded, LogDecoder, MAX_LOG_LINE};
    use std::io::Read;
    let stdin = path.as_os_str() == "-";
    let input: Box<dyn Read> = if stdin {
        Box::new(std::io::stdin())
    } else {
        let kind = std::fs::metadata(path).map_err(|e| file_error(path, e))?;
        if kind.is_dir() {
            return Err(UsageError::Directory {
                path: path.to_path_buf(),
            }
            .into());
        }
        Box::new(std::fs::File::open(path).map_err(|e| file_error(path, e))?)
    };
    let name = if stdin {
        "standard input".to_string()
    } else {
        path.display().to_string()
    };
    let mut log = LogDecoder::new(std::io::BufReader::new(input), w);
    while let Some(event) = log.next_event().map_err(|error| UsageError::Log {
        name: name.clone(),
        error,
    })? {
        match event {
            Decoded::Line { t, text } => emit(
                out,
                json,
                format!("{t:>10.6}  {text}"),
                serde_json::json!({"t": t, "event": text}),
            )?,
            Decoded::Open { t, transfer: o } => emit(
                out,
                json,
                format!("{t:>10.6}  {o}"),
                serde_json::json!({"t": t, "event": o.to_string(), "open": {
                    "node": o.node, "object": o.address.to_string(), "kind": o.kind,
                    "bytes": o.bytes, "size": o.size, "last": o.last,
                }}),
            )?,
            Decoded::TooLong { line } => eprintln!(
                "sdo-tool: {name}: line {line} is longer than {MAX_LOG_LINE} bytes, no candump -L \
                 frame: skipped"
            ),
        }
    }
    if let (n @ 1.., Some(first)) = log.not_frames() {
        eprintln!(
            "sdo-tool: {name}: {n} line(s) are no candump -L frames (the first: line {first}): \
             skipped"
        );
    }
    Ok(())
}
