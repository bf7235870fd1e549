//! The table: the header, one line per kept sample, and the names of the set status bits.

use std::io::{self, Write};

use super::{Sample, Shown, Trace};
use crate::smd::indexer::{stat0, stat1};

/// The names of the STATUS_word0 bits, bit 0 first (Reference 6, Figure R6.4).
pub const STATUS0_NAMES: [&str; 16] = [
    "Moving_CW",
    "Moving_CCW",
    "In_Hold_State",
    "Stopped",
    "At_Home",
    "Accelerating",
    "Decelerating",
    "Move_Complete",
    "In_Assembled_Mode",
    "Waiting_For_Assembled_Segment",
    "Position_Invalid",
    "Input_Error",
    "Command_Error",
    "Configuration_Error",
    "Module_OK",
    "Mode_Flag",
];

/// The names of the STATUS_word1 bits, bit 0 first (Reference 6, Figure R6.5); `""` for the bits that
/// read 0.
pub const STATUS1_NAMES: [&str; 16] = [
    "IN1_Active",
    "IN2_Active",
    "",
    "",
    "Temperature_Above_90C",
    "PreOp_SafeOp",
    "",
    "Driver_Fault",
    "",
    "Invalid_Jog_Change",
    "Limit_Condition",
    "Heartbeat_Bit",
    "Abs_Enc_Err",
    "Command_Acknowledge",
    "Stall_Detected",
    "Drive_Is_Enabled",
];

/// The names of the bits set in `word`, bit 0 first, from `table` (`bit_N` where it has none).
pub fn set_bit_names(word: u16, table: &[&str; 16]) -> Vec<String> {
    (0..16)
        .filter(|&b| word & (1 << b) != 0)
        .map(|b| match table[b] {
            "" => format!("bit_{b}"),
            n => n.to_string(),
        })
        .collect()
}

/// The names of the set bits of STATUS_word0 (not Module_OK, `!Module_OK` when clear), then ` | ` and
/// those of STATUS_word1 (not the Heartbeat_Bit) when any is set.
pub fn bit_names(status0: u16, status1: u16) -> String {
    let names = |word: u16, table: &[&'static str; 16], skip: u16| -> Vec<String> {
        set_bit_names(word & !skip, table)
    };
    let mut w0 = names(status0, &STATUS0_NAMES, stat0::MODULE_OK);
    if status0 & stat0::MODULE_OK == 0 {
        w0.push("!Module_OK".to_string());
    }
    let w1 = names(status1, &STATUS1_NAMES, stat1::HEARTBEAT);
    let mut s = w0.join(" ");
    if !w1.is_empty() {
        if !s.is_empty() {
            s.push(' ');
        }
        s.push_str("| ");
        s.push_str(&w1.join(" "));
    }
    s
}

const TITLES: [&str; 8] = [
    "time [s]",
    "Motor_Position",
    "Encoder_Position",
    "Trapped_Encoder_Position",
    "speed [steps/s]",
    "STATUS_word0",
    "STATUS_word1",
    "bits",
];

/// Decimals of the time column: enough for the cycle, at least 3.
fn time_decimals(trace: &Trace) -> usize {
    let ns = trace.cycle.as_nanos();
    (3..9)
        .find(|&d| ns.is_multiple_of(10u128.pow(9 - d as u32)))
        .unwrap_or(9)
}

fn time_width(trace: &Trace) -> usize {
    let d = time_decimals(trace);
    let last = format!("{:.d$}", trace.until.as_secs_f64());
    last.len().max(TITLES[0].len()) + 2
}

/// The header: a `#` line naming the run, then the column names.
pub fn header(trace: &Trace) -> String {
    let every = trace
        .every
        .map_or(String::new(), |e| format!(", a line every {}", Shown(e)));
    let w = time_width(trace);
    format!(
        "# {}: {} encoder, cycle {}, 0 to {}{every}\n{:>w$}  {}  {}  {}  {}  {}  {}  {}",
        trace.file,
        trace.kind,
        Shown(trace.cycle),
        Shown(trace.until),
        TITLES[0],
        TITLES[1],
        TITLES[2],
        TITLES[3],
        TITLES[4],
        TITLES[5],
        TITLES[6],
        TITLES[7],
    )
}

/// One line of the table.
pub fn format_line(trace: &Trace, s: &Sample) -> String {
    let d = time_decimals(trace);
    let w = time_width(trace);
    let i = &s.inputs;
    let t = format!("{:.d$}", s.time.as_secs_f64());
    let speed = format!("{:.1}", s.speed);
    // Negative zero is zero.
    let speed = if speed == "-0.0" {
        "0.0".to_string()
    } else {
        speed
    };
    let line = format!(
        "{t:>w$}  {:>14}  {:>16}  {:>24}  {speed:>15}  {:>12}  {:>12}  {}",
        i.motor_position,
        i.encoder_position,
        i.trapped_encoder_position,
        format!("{:#06x}", i.status0),
        format!("{:#06x}", i.status1),
        bit_names(i.status0, i.status1),
    );
    line.trim_end().to_string()
}

/// Writes the header and every line of `trace`.
pub fn write_table(trace: &Trace, out: &mut dyn Write) -> io::Result<()> {
    writeln!(out, "{}", header(trace))?;
    for s in &trace.lines {
        writeln!(out, "{}", format_line(trace, s))?;
    }
    Ok(())
}
