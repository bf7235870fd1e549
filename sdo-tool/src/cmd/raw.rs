//! `send ID#DATA` (a frame as can-utils' cansend writes it) and `sync` (a SYNC producer): raw
//! frames on the bus, through the tool's bus like every other command.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::emit;
use crate::raw::{cansend_frame, SyncSchedule, MAX_SYNC_OVERFLOW};
use crate::{Tool, ToolError, UsageError};

/// `send`'s arguments.
#[derive(Debug, clap::Args)]
pub struct SendArgs {
    /// The frame, as cansend writes it: 123#DEADBEEF, 123#R (remote frame), 12345678#00 (29-bit),
    /// bytes optionally separated by dots (5A1#11.22.33).
    #[arg(value_name = "ID#DATA")]
    pub frame: String,
}

/// `send` on `tool`'s bus: the frame, or why it is none (nothing sent). Prints nothing, as cansend
/// does (`--json`: the frame sent).
pub fn send(
    args: &SendArgs,
    tool: &mut Tool,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let frame = cansend_frame(&args.frame).map_err(|why| UsageError::Frame {
        text: args.frame.clone(),
        why,
    })?;
    tool.bus.send(&frame)?;
    if json {
        emit(
            out,
            true,
            "",
            serde_json::json!({"sent": frame.to_string()}),
        )?;
    }
    Ok(())
}

/// A COB-ID: hex with `0x` (`0x80`) or decimal; 1 to 0x7FF.
fn cob_id(text: &str) -> Result<u16, String> {
    let t = text.trim();
    let v = match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(h) => u16::from_str_radix(h, 16).ok(),
        None => t.parse().ok(),
    };
    v.filter(|v| (1..=0x7FF).contains(v))
        .ok_or_else(|| format!("{text:?} is not a COB-ID of 0x001 to 0x7FF (0x80, or decimal)"))
}

/// `sync`'s arguments.
#[derive(Debug, clap::Args)]
pub struct SyncArgs {
    /// How many SYNC messages; 0 sends until Ctrl-C.
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub count: u64,
    /// The time between two, in ms (from the first, so that they do not drift).
    #[arg(long, default_value_t = 100, value_name = "MS")]
    pub period_ms: u64,
    /// With the SYNC counter byte (CiA 301): 1, 2, … up to --overflow, then 1 again.
    #[arg(long)]
    pub counter: bool,
    /// The counter's overflow value, as the nodes' 0x1019 has it: 2 to 240.
    #[arg(long, default_value_t = MAX_SYNC_OVERFLOW, value_name = "N",
          value_parser = clap::value_parser!(u8).range(2..=240), requires = "counter")]
    pub overflow: u8,
    /// The SYNC COB-ID (0x1005 of the nodes).
    #[arg(long, default_value = "0x80", value_name = "ID", value_parser = cob_id)]
    pub cob_id: u16,
}

/// `sync` on `tool`'s bus: the messages on their schedule, then one line saying how many.
pub fn sync(
    args: &SyncArgs,
    tool: &mut Tool,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let period = Duration::from_millis(args.period_ms);
    let overflow = args.counter.then_some(args.overflow);
    let mut schedule = SyncSchedule::new(args.cob_id, args.count, period, overflow, Instant::now());
    let stop = Arc::new(AtomicBool::new(false));
    if args.count == 0 {
        let s = Arc::clone(&stop);
        let _ = ctrlc::set_handler(move || s.store(true, Ordering::Relaxed));
    }
    while let Some(due) = schedule.poll_timeout() {
        if stop.load(Ordering::Relaxed) {
            break;
        }
        let now = Instant::now();
        if due > now {
            // Woken at least every 100 ms to see Ctrl-C.
            std::thread::sleep((due - now).min(Duration::from_millis(100)));
            continue;
        }
        if let Some(frame) = schedule.handle_timeout(now) {
            tool.bus.send(&frame)?;
        }
    }
    let sent = schedule.sent();
    emit(
        out,
        json,
        format!("{sent} SYNC sent on 0x{:03X}", args.cob_id),
        serde_json::json!({"sent": sent, "cob_id": args.cob_id}),
    )
}
