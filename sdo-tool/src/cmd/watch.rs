//! `watch [NODE]`: the bus's frames in words as they come, until Ctrl-C or `--duration-ms`;
//! optionally logged in candump's format.

use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::{emit, file_error};
use crate::link::{BusEvent, BusSpec};
use crate::watch::{CobFilter, Kind, Watcher};
use crate::{Tool, ToolError};

/// `watch`'s arguments.
#[derive(Debug, clap::Args)]
pub struct WatchArgs {
    /// Only this node.
    pub node: Option<u8>,
    /// Stop after this many ms.
    #[arg(long)]
    pub duration_ms: Option<u64>,
    /// Also write every frame to FILE in candump's log format (`candump -L`), for `decode`,
    /// canplayer or python-can.
    #[arg(long, value_name = "FILE")]
    pub log: Option<PathBuf>,
    /// Also show the frames it cannot name, as ID#DATA.
    #[arg(long)]
    pub raw: bool,
    /// The frames to take, as candump's filters (hex identifiers): ID, ID:MASK, LOW-HIGH, ~ to
    /// invert; several with commas or again. The others are neither shown nor logged.
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

/// `watch` on `tool`'s bus; `bus` names the interface in the log's lines.
pub fn run(
    args: &WatchArgs,
    tool: &mut Tool,
    bus: Option<&BusSpec>,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let io = ToolError::Output;
    let mut w = Watcher::new(args.node, tool.od.as_ref())
        .with_raw(args.raw)
        .with_filters(args.filter.clone())
        .with_only(args.only.clone())
        .with_full(args.full);
    let iface = match bus {
        Some(BusSpec::SocketCan { iface }) => iface.clone(),
        Some(BusSpec::Socketcand { channel, .. }) => channel.clone(),
        _ => "can0".to_string(),
    };
    let mut log = match &args.log {
        Some(path) => Some(std::io::BufWriter::new(
            std::fs::File::create(path).map_err(|e| file_error(path, e))?,
        )),
        None => None,
    };
    let start = Instant::now();
    let end = args.duration_ms.map(|ms| start + Duration::from_millis(ms));
    let stop = Arc::new(AtomicBool::new(false));
    if end.is_none() {
        let s = Arc::clone(&stop);
        let _ = ctrlc::set_handler(move || s.store(true, Ordering::Relaxed));
    }
    while !stop.load(Ordering::Relaxed) {
        let wait = match end {
            Some(e) => {
                let left = e.saturating_duration_since(Instant::now());
                if left.is_zero() {
                    break;
                }
                left.min(Duration::from_millis(100))
            }
            None => Duration::from_millis(100),
        };
        let event = tool.bus.recv(wait)?;
        let t = start.elapsed().as_secs_f64();
        let lines = match event {
            Some(BusEvent::Frame { frame, at, .. }) => {
                let taken = w.takes(&frame);
                if let Some(l) = log.as_mut().filter(|_| taken) {
                    writeln!(l, "{}", crate::watch::candump(at, &iface, &frame)).map_err(io)?;
                }
                w.at(t, &frame)
            }
            _ => w.missed(t),
        };
        for line in lines {
            emit(
                out,
                json,
                format!("{t:>9.3}  {line}"),
                serde_json::json!({"t": t, "event": line}),
            )?;
        }
    }
    Ok(())
}
