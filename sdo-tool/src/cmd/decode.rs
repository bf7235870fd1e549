//! `decode LOG [NODE]`: every frame of a candump log (or of a pcapng capture's SocketCAN
//! interfaces) named, read line by line (block by block) in bounded memory; at the end, the SDO
//! transfers left open.

use std::io::Write;
use std::path::PathBuf;

use super::{emit, file_error};
use crate::watch::{CobFilter, Kind, Watcher};
use crate::{ToolError, UsageError};

/// `decode`'s arguments.
#[derive(Debug, clap::Args)]
pub struct DecodeArgs {
    /// The log: candump's (`candump -L`), or a pcapng capture (told by its first bytes).
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

/// `decode`: every frame of a candump log or a pcapng capture (told by its first four bytes), named,
/// with its time since the log's first frame, read line by line (or block by block) in bounded
/// memory; at the end, the SDO transfers left open.
fn decode(
    path: &std::path::Path,
    w: crate::watch::Watcher,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    use crate::watch::{Decoded, LogDecoder, MAX_LOG_LINE, PCAPNG_MAGIC};
    use std::io::Read;
    let stdin = super::is_dash(path);
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
    let log_error = |error| UsageError::Log {
        name: name.clone(),
        error,
    };
    let mut input = std::io::BufReader::new(input);
    let mut head = Vec::with_capacity(4);
    (&mut input)
        .take(4)
        .read_to_end(&mut head)
        .map_err(log_error)?;
    let input = std::io::BufReader::new(std::io::Cursor::new(head.clone()).chain(input));
    let mut log = if head == PCAPNG_MAGIC {
        LogDecoder::pcapng(input, w)
    } else {
        LogDecoder::new(input, w)
    };
    while let Some(event) = log.next_event().map_err(log_error)? {
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
    match log.capture_summary() {
        Some(summary) => capture_notes(&name, summary),
        None => Ok(()),
    }
}

/// What a capture held besides the frames decoded, one line on standard error each; a capture with
/// no SocketCAN interface at all is refused.
fn capture_notes(name: &str, s: &crate::watch::CaptureSummary) -> Result<(), ToolError> {
    if let Some(at) = s.cut_at {
        eprintln!(
            "sdo-tool: {name}: the capture ends inside the block at byte {at} (cut short): \
             decoded up to there"
        );
    }
    if s.can_interfaces == 0 {
        return Err(UsageError::NoCanInCapture {
            name: name.to_string(),
            interfaces: s.interfaces.clone(),
        }
        .into());
    }
    if s.other_links > 0 {
        eprintln!(
            "sdo-tool: {name}: {} packet(s) of interfaces that are no SocketCAN bus: skipped",
            s.other_links
        );
    }
    if let Some((first, what)) = s.first_not_classic {
        eprintln!(
            "sdo-tool: {name}: {} SocketCAN packet(s) are no classic CAN frame (the first: \
             packet {first}, {what}): skipped",
            s.not_classic
        );
    }
    if s.unreadable > 0 {
        eprintln!(
            "sdo-tool: {name}: {} packet(s) of undescribed interfaces or too long to read: skipped",
            s.unreadable
        );
    }
    Ok(())
}
