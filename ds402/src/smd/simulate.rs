//! The offline simulator behind `smd simulate`: a text script of process-data writes, input changes
//! and configuration writes ([`Script::parse`]) runs cycle by cycle against the indexer model
//! ([`super::indexer::Indexer`]) and gives a [`Trace`] ([`run`]), which prints as a table
//! ([`write_table`]) and draws as an SVG chart ([`plot`]).
//!
//! # The script
//!
//! One statement per line; `#` starts a comment (to the end of the line); blank lines are ignored.
//! Times are absolute from power-up: a decimal number with the unit `us`, `ms` or `s` (`250us`,
//! `20ms`, `1.5s`), and a whole number of cycles.
//!
//! | statement | meaning |
//! |---|---|
//! | `unit incremental\|absolute` | the encoder kind (optional; the first statement; default incremental) |
//! | `cycle TIME` | the process-data period, 250 µs to 100 ms (optional, before the first `at`; default 1 ms) |
//! | `config NAME VALUE` | before the first `at`: a value of the power-up configuration |
//! | `at TIME out FIELD=VALUE ...` | output fields from that time on |
//! | `at TIME input N on\|off` | current flows into input N (1 or 2) from that time on, or not |
//! | `at TIME config NAME VALUE` | an SDO write to `8010` at that time ([`Indexer::write_config`]) |
//! | `until TIME` | the end of the run (required, the last statement, at most 1 hour) |
//!
//! - FIELD is one of `cmd0 cmd1 position velocity acceleration deceleration motor_current jerk` (the
//!   eight words of `0x7000`); VALUE is decimal (signed where the type is), `0x` hex or `0b` binary,
//!   `_` allowed between digits, and must fit the field's type (UNSIGNED16, INTEGER32 for `position`,
//!   UNSIGNED32 for `velocity`). Whether the unit accepts it is the model's business (Command_Error).
//! - NAME is one of `cfg_word_0 cfg_word_1 starting_speed motor_resolution encoder_resolution
//!   idle_current_reduction motor_current` (any case) or `8010:01` … `8010:07`; VALUE as above, in
//!   the entry's type (UNSIGNED32 for Starting_Speed, UNSIGNED16 for the others). An invalid
//!   configuration is not a script error: the model shows it in Configuration_Error.
//! - The power-up configuration starts from [`Configuration::default`] (CFG_Word_0 = 0, CFG_Word_1 = 3
//!   so both inputs are active while current flows, Starting_Speed 141, Motor_Resolution 2000, …);
//!   every output word starts at 0 and no current flows into either input.
//! - The simulator runs cycle by cycle. The statements of time t apply in file order before the cycle
//!   that starts at t; times must not go backwards, and `until` must lie after the last `at`. A
//!   command bit acts on its 0 → 1 edge, so set it at one time and clear it at a later one.
//! - A bare `config` after the first `at` is an error: write `at TIME config NAME VALUE`.
//!
//! ```text
//! # A Relative move of 5000 steps.
//! at 0ms  out cmd1=0x8000 velocity=10000 acceleration=100 deceleration=100  # Enable_Driver
//! at 10ms out cmd0=0x0200                  # Preset Position (to Position = 0)
//! at 20ms out cmd0=0
//! at 30ms out cmd0=0x0002 position=5000    # Relative Move
//! at 40ms out cmd0=0
//! until 1s
//! ```
//!
//! # The table
//!
//! A `#` header line, the column names, then one line
//! - at power-up (time 0, before the first cycle and before the statements of time 0);
//! - after each cycle in which STATUS_word0 changed, STATUS_word1 changed in a bit other than the
//!   Heartbeat_Bit, Trapped_Encoder_Position changed, or Motor_Position or Encoder_Position changed
//!   while the motor was at rest before and after the cycle (a preset);
//! - with `--every` ([`Options::every`]), after each cycle that ends on a multiple of that interval;
//! - after the last cycle.
//!
//! The positions changing during a move give no lines of their own: the motion bits do (the start,
//! the end of the acceleration, the start of the deceleration, the stop). The time is the end of the
//! cycle, when the unit's answer is read. The columns: `time [s]`, Motor_Position, Encoder_Position,
//! Trapped_Encoder_Position, speed [steps/s] (signed, clockwise positive), STATUS_word0 and
//! STATUS_word1 in hex (the Heartbeat_Bit included), then the names of the set STATUS_word0 bits
//! (Module_OK is not named, `!Module_OK` when it is clear) and, after ` | `, the names of the set
//! STATUS_word1 bits (the Heartbeat_Bit is not named).
//!
//! ```
//! use ds402::smd::simulate::{format_line, run, Options, Script};
//!
//! let script = Script::parse("at 0ms out cmd1=0x8000\nuntil 5ms\n", "enable.smd").unwrap();
//! let trace = run(&script, &Options::default());
//! assert_eq!(trace.lines.len(), 3); // power-up, Drive_Is_Enabled, the end
//! let line = format_line(&trace, &trace.lines[1]);
//! assert!(line.trim_start().starts_with("0.001 "));
//! assert!(line.ends_with("0x4408        0x8000  Stopped Position_Invalid | Drive_Is_Enabled"));
//! ```

use std::fmt;
use std::io::{self, Write};
use std::path::Path;
use std::time::Duration;

use plotters::prelude::*;

use super::config::{Configuration, EncoderKind};
use super::indexer::{stat0, stat1, Indexer, Inputs, Outputs};
use super::plot::{format_tick, PlotError};

/// The long help of `smd simulate` (the format of the script and of the table).
pub const HELP: &str = "\
Runs a script of process-data writes and input changes against the indexer model offline (no unit,
no bus) and prints the resulting positions and status bits over time; with --plot it also draws
them as an SVG chart (Motor_Position, speed and the motion bits over time).

SCRIPT
  One statement per line; '#' starts a comment; blank lines are ignored. Times are absolute from
  power-up: a number with the unit us, ms or s (250us, 20ms, 1.5s), a whole number of cycles.

  unit incremental|absolute     the encoder kind (optional, the first statement; incremental)
  cycle TIME                    the process-data period, 250us to 100ms (optional, before the
                                first 'at'; default 1ms)
  config NAME VALUE             before the first 'at': a value of the power-up configuration
  at TIME out FIELD=VALUE ...   output fields from that time on
  at TIME input N on|off        current flows into input N (1 or 2) from then on, or not
  at TIME config NAME VALUE     an SDO write to 8010 at that time (the position becomes invalid)
  until TIME                    the end of the run (required, the last statement; at most 1 hour)

  FIELD: cmd0 cmd1 position velocity acceleration deceleration motor_current jerk (0x7000:01-08).
  NAME:  cfg_word_0 cfg_word_1 starting_speed motor_resolution encoder_resolution
         idle_current_reduction motor_current, or 8010:01 ... 8010:07.
  VALUE: decimal (signed where the type is), 0x hex or 0b binary; it must fit the entry's type
         (position INTEGER32, velocity and starting_speed UNSIGNED32, the others UNSIGNED16).
         Whether the unit accepts it is the model's business (Command_Error, Configuration_Error).

  The configuration starts as the fixture's default (CFG_Word_0 = 0, CFG_Word_1 = 3: inputs active
  while current flows; Starting_Speed 141, Motor_Resolution 2000, Encoder_Resolution 2048,
  Idle_current_reduction 50, Motor_Current 10); all outputs start at 0, no current flows into the
  inputs. The simulator runs cycle by cycle: the statements of time t apply in file order before
  the cycle that starts at t. Times must not go backwards and 'until' must lie after the last 'at'.
  A command bit acts on its 0 -> 1 edge: set it at one time and clear it at a later one.

OUTPUT
  A '#' header line, the column names, then one line
  - at power-up (time 0, before the first cycle and the statements of time 0);
  - after each cycle in which STATUS_word0 changed, STATUS_word1 changed in a bit other than the
    Heartbeat_Bit, Trapped_Encoder_Position changed, or Motor_Position or Encoder_Position changed
    while the motor was at rest (a preset);
  - with --every, after each cycle that ends on a multiple of that interval;
  - after the last cycle.
  A move's positions give no lines of their own: its motion bits do (start, end of acceleration,
  start of deceleration, stop). The time is the end of the cycle, when the answer is read.
  Columns: time [s], Motor_Position, Encoder_Position, Trapped_Encoder_Position, speed [steps/s]
  (signed, clockwise positive), STATUS_word0 and STATUS_word1 in hex, the names of the set
  STATUS_word0 bits (not Module_OK; '!Module_OK' when clear) and, after '|', of the set
  STATUS_word1 bits (not the Heartbeat_Bit).

EXAMPLE
  # A Relative move of 5000 steps.
  at 0ms  out cmd1=0x8000 velocity=10000 acceleration=100 deceleration=100  # Enable_Driver
  at 10ms out cmd0=0x0200                  # Preset Position (to Position = 0)
  at 20ms out cmd0=0
  at 30ms out cmd0=0x0002 position=5000    # Relative Move
  at 40ms out cmd0=0
  until 1s";

/// The shortest process-data cycle.
pub const MIN_CYCLE: Duration = Duration::from_micros(250);
/// The longest process-data cycle.
pub const MAX_CYCLE: Duration = Duration::from_millis(100);
/// The cycle when the script names none.
pub const DEFAULT_CYCLE: Duration = Duration::from_millis(1);
/// The longest run (`until`).
pub const MAX_RUN: Duration = Duration::from_secs(3600);
/// About how many evenly spaced samples [`Trace::curve`] keeps besides those at the changes.
pub const CURVE_POINTS: u64 = 2000;

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

/// One of the eight output words (`0x7000:01–08`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Field {
    /// CMD_word0.
    Cmd0,
    /// CMD_word1.
    Cmd1,
    /// Position.
    Position,
    /// Velocity.
    Velocity,
    /// Acceleration.
    Acceleration,
    /// Deceleration.
    Deceleration,
    /// Motor_Current.
    MotorCurrent,
    /// Jerk.
    Jerk,
}

impl Field {
    /// All eight in sub-index order.
    pub const ALL: [Field; 8] = [
        Field::Cmd0,
        Field::Cmd1,
        Field::Position,
        Field::Velocity,
        Field::Acceleration,
        Field::Deceleration,
        Field::MotorCurrent,
        Field::Jerk,
    ];

    /// The script's name.
    pub const fn name(self) -> &'static str {
        match self {
            Field::Cmd0 => "cmd0",
            Field::Cmd1 => "cmd1",
            Field::Position => "position",
            Field::Velocity => "velocity",
            Field::Acceleration => "acceleration",
            Field::Deceleration => "deceleration",
            Field::MotorCurrent => "motor_current",
            Field::Jerk => "jerk",
        }
    }

    const fn ty(self) -> Type {
        match self {
            Field::Position => Type::I32,
            Field::Velocity => Type::U32,
            _ => Type::U16,
        }
    }

    /// Writes `value` (already range-checked) into `out`.
    fn set(self, out: &mut Outputs, value: i64) {
        match self {
            Field::Cmd0 => out.cmd0 = value as u16,
            Field::Cmd1 => out.cmd1 = value as u16,
            Field::Position => out.position = value as i32,
            Field::Velocity => out.velocity = value as u32,
            Field::Acceleration => out.acceleration = value as u16,
            Field::Deceleration => out.deceleration = value as u16,
            Field::MotorCurrent => out.motor_current = value as u16,
            Field::Jerk => out.jerk = value as u16,
        }
    }
}

/// The names of the configuration entries `8010:01–07`, sub-index 1 first.
pub const CONFIG_NAMES: [&str; 7] = [
    "cfg_word_0",
    "cfg_word_1",
    "starting_speed",
    "motor_resolution",
    "encoder_resolution",
    "idle_current_reduction",
    "motor_current",
];

/// A CoE data type of a value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Type {
    /// UNSIGNED16.
    U16,
    /// UNSIGNED32.
    U32,
    /// INTEGER32.
    I32,
}

impl Type {
    const fn range(self) -> (i64, i64) {
        match self {
            Type::U16 => (0, u16::MAX as i64),
            Type::U32 => (0, u32::MAX as i64),
            Type::I32 => (i32::MIN as i64, i32::MAX as i64),
        }
    }

    /// The CoE name.
    pub const fn name(self) -> &'static str {
        match self {
            Type::U16 => "UNSIGNED16",
            Type::U32 => "UNSIGNED32",
            Type::I32 => "INTEGER32",
        }
    }
}

impl fmt::Display for Type {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (min, max) = self.range();
        write!(f, "{min} to {max}, {}", self.name())
    }
}

/// What a statement does at its time.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Action {
    /// Output words from now on, in the order written.
    Out(Vec<(Field, i64)>),
    /// Whether current flows into input `n` (1 or 2).
    Input {
        /// 1 or 2.
        n: usize,
        /// Current flows.
        current: bool,
    },
    /// An SDO write of `value` to `8010:sub`.
    Config {
        /// 1 … 7.
        sub: u8,
        /// The value (fits the entry's type).
        value: u32,
    },
}

/// A timed statement.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Event {
    /// When it applies (before the cycle that starts then).
    pub time: Duration,
    /// Its line in the script (1-based).
    pub line: usize,
    /// What it does.
    pub action: Action,
}

/// A parsed script.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Script {
    /// The file name used in messages and the header.
    pub file: String,
    /// The encoder kind (`unit`).
    pub kind: EncoderKind,
    /// The power-up configuration.
    pub config: Configuration,
    /// The process-data period.
    pub cycle: Duration,
    /// The timed statements in time (and file) order.
    pub events: Vec<Event>,
    /// The end of the run, a whole number of cycles after power-up.
    pub until: Duration,
}

/// What is wrong with a line of a script.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LineError {
    /// The first word is no statement.
    #[error("unknown statement {0:?} (expected unit, cycle, config, at or until)")]
    UnknownStatement(String),
    /// A statement with missing or extra words.
    #[error("{0}")]
    Usage(&'static str),
    /// An `at` whose third word is no action.
    #[error("unknown action {0:?} after the time (expected out, input or config)")]
    UnknownAction(String),
    /// Not an encoder kind.
    #[error("unknown encoder kind {0:?} (expected incremental or absolute)")]
    UnknownUnit(String),
    /// Not an output field.
    #[error(
        "unknown output field {0:?} (expected cmd0, cmd1, position, velocity, acceleration, \
         deceleration, motor_current or jerk)"
    )]
    UnknownField(String),
    /// A word of `out` without `=`.
    #[error("expected FIELD=VALUE, found {0:?}")]
    NotAssignment(String),
    /// Not a configuration entry.
    #[error(
        "unknown configuration entry {0:?} (expected cfg_word_0, cfg_word_1, starting_speed, \
         motor_resolution, encoder_resolution, idle_current_reduction, motor_current or \
         8010:01 to 8010:07)"
    )]
    UnknownConfig(String),
    /// Not a number.
    #[error("{0:?} is not a number (decimal, 0x hex or 0b binary)")]
    BadNumber(String),
    /// A number that does not fit its entry.
    #[error("{name} = {value} is out of range ({ty})")]
    OutOfRange {
        /// The field or entry.
        name: String,
        /// The value as written.
        value: String,
        /// Its type.
        ty: Type,
    },
    /// Not an input number.
    #[error("unknown input {0:?} (expected 1 or 2)")]
    UnknownInput(String),
    /// Neither on nor off.
    #[error("expected on or off, found {0:?}")]
    NotOnOff(String),
    /// Not a time.
    #[error("{0:?} is not a time (a number with us, ms or s, e.g. 250us, 20ms or 1.5s)")]
    BadTime(String),
    /// A time off the cycle grid.
    #[error("time {time} is not a whole number of cycles (the cycle is {cycle})")]
    OffCycle {
        /// The time as written.
        time: String,
        /// The cycle.
        cycle: Shown,
    },
    /// A time before the previous one.
    #[error("time {time} is before the previous statement's time {previous} (times must not go backwards)")]
    Backwards {
        /// The time as written.
        time: String,
        /// The previous time as written.
        previous: String,
    },
    /// A cycle out of range.
    #[error("cycle {0} is out of range (250us to 100ms)")]
    CycleRange(String),
    /// `until` beyond [`MAX_RUN`].
    #[error("until {0} is beyond the longest run of 1 hour")]
    TooLong(String),
    /// `until` not after the last `at`.
    #[error("until {until} is not after the last statement's time {last}")]
    UntilNotAfter {
        /// The time as written.
        until: String,
        /// The last `at` time as written.
        last: String,
    },
    /// `until 0s`.
    #[error("until {0} leaves no cycle to run")]
    EmptyRun(String),
    /// `unit` after another statement.
    #[error("unit must be the first statement")]
    UnitNotFirst,
    /// `cycle` after the first `at`.
    #[error("cycle must come before the first at")]
    CycleAfterAt,
    /// A second `unit` or `cycle`.
    #[error("a second {name} statement (the first is on line {first})")]
    Repeated {
        /// `unit` or `cycle`.
        name: &'static str,
        /// Its first line.
        first: usize,
    },
    /// `config` without a time after the first `at`.
    #[error("config after the first at needs a time: at TIME config NAME VALUE")]
    ConfigAfterAt,
    /// Anything after `until`.
    #[error("nothing may follow until (line {0})")]
    AfterUntil(usize),
}

/// Why a script was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ScriptError {
    /// A line is wrong.
    #[error("{file}:{line}: {error}")]
    Line {
        /// The file name.
        file: String,
        /// The line (1-based).
        line: usize,
        /// What is wrong.
        error: LineError,
    },
    /// No `until`.
    #[error("{file}: no until statement (the end of the run is required, as the last statement)")]
    NoUntil {
        /// The file name.
        file: String,
    },
}

/// A duration shown the way a script writes it (`250us`, `1ms`, `1.5s`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shown(pub Duration);

impl fmt::Display for Shown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let ns = self.0.as_nanos();
        let (div, unit) = if ns >= 1_000_000_000 {
            (1_000_000_000, "s")
        } else if ns >= 1_000_000 {
            (1_000_000, "ms")
        } else {
            (1_000, "us")
        };
        let whole = ns / div;
        let frac = ns % div;
        if frac == 0 {
            write!(f, "{whole}{unit}")
        } else {
            let digits = div.ilog10() as usize;
            let s = format!("{frac:0digits$}");
            write!(f, "{whole}.{}{unit}", s.trim_end_matches('0'))
        }
    }
}

/// Parses a time: a decimal number with `us` (or `µs`), `ms` or `s`; `None` when it is none or is
/// finer than 1 ns.
pub fn parse_time(text: &str) -> Option<Duration> {
    let (number, scale): (&str, u128) = if let Some(n) = text.strip_suffix("us") {
        (n, 1_000)
    } else if let Some(n) = text.strip_suffix("µs") {
        (n, 1_000)
    } else if let Some(n) = text.strip_suffix("ms") {
        (n, 1_000_000)
    } else if let Some(n) = text.strip_suffix('s') {
        (n, 1_000_000_000)
    } else {
        return None;
    };
    let (int, frac) = number.split_once('.').unwrap_or((number, ""));
    if int.is_empty()
        || int.len() > 12
        || number.ends_with('.')
        || !int.bytes().all(|b| b.is_ascii_digit())
        || !frac.bytes().all(|b| b.is_ascii_digit())
    {
        return None;
    }
    let mut ns: u128 = int.parse().ok()?;
    ns *= scale;
    let mut unit = scale;
    for d in frac.bytes() {
        let digit = u128::from(d - b'0');
        if unit % 10 != 0 {
            if digit != 0 {
                return None; // finer than 1 ns
            }
            continue;
        }
        unit /= 10;
        ns += digit * unit;
    }
    let ns = u64::try_from(ns).ok()?;
    Some(Duration::from_nanos(ns))
}

/// Parses an integer: optional sign, then decimal, `0x` hex or `0b` binary, `_` between digits.
fn parse_int(text: &str) -> Result<i128, LineError> {
    let bad = || LineError::BadNumber(text.to_string());
    let (neg, body) = match text.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, text.strip_prefix('+').unwrap_or(text)),
    };
    let (radix, digits) = if let Some(h) = body.strip_prefix("0x").or(body.strip_prefix("0X")) {
        (16, h)
    } else if let Some(b) = body.strip_prefix("0b").or(body.strip_prefix("0B")) {
        (2, b)
    } else {
        (10, body)
    };
    if digits.is_empty() || digits.starts_with('_') || digits.ends_with('_') {
        return Err(bad());
    }
    let clean: String = digits.chars().filter(|&c| c != '_').collect();
    if !clean.chars().all(|c| c.is_digit(radix)) {
        return Err(bad());
    }
    // Too many digits for i128 is simply out of range: saturate.
    let magnitude = i128::from_str_radix(&clean, radix).unwrap_or(i128::MAX);
    Ok(if neg { -magnitude } else { magnitude })
}

/// A value of `name` of type `ty`, written as `text`.
fn parse_value(name: &str, text: &str, ty: Type) -> Result<i64, LineError> {
    let v = parse_int(text)?;
    let (min, max) = ty.range();
    if v < i128::from(min) || v > i128::from(max) {
        return Err(LineError::OutOfRange {
            name: name.to_string(),
            value: text.to_string(),
            ty,
        });
    }
    Ok(v as i64)
}

/// The sub-index (1–7) of a configuration entry's name or `8010:NN`.
fn config_sub(name: &str) -> Option<u8> {
    if let Some(k) = CONFIG_NAMES
        .iter()
        .position(|n| n.eq_ignore_ascii_case(name))
    {
        return Some(k as u8 + 1);
    }
    let sub = name.strip_prefix("8010:")?;
    if sub.is_empty() || sub.len() > 2 {
        return None;
    }
    let sub = u8::from_str_radix(sub, 16).ok()?;
    (1..=7).contains(&sub).then_some(sub)
}

fn config_type(sub: u8) -> Type {
    if sub == 3 {
        Type::U32
    } else {
        Type::U16
    }
}

/// `config NAME VALUE` (the words after `config`).
fn parse_config(words: &[&str]) -> Result<(u8, u32), LineError> {
    let [name, value] = words else {
        return Err(LineError::Usage(
            "config needs a name and a value: config NAME VALUE",
        ));
    };
    let sub = config_sub(name).ok_or_else(|| LineError::UnknownConfig(name.to_string()))?;
    let shown = CONFIG_NAMES[usize::from(sub - 1)];
    let v = parse_value(shown, value, config_type(sub))?;
    Ok((sub, v as u32))
}

/// The parser's state between lines.
struct Parser {
    kind: EncoderKind,
    config: Configuration,
    cycle: Duration,
    events: Vec<Event>,
    until: Option<(Duration, usize)>,
    unit_line: Option<usize>,
    cycle_line: Option<usize>,
    /// Any statement seen yet (for `unit`).
    any: bool,
    /// The last `at` time and its text.
    last: Option<(Duration, String)>,
}

impl Parser {
    fn time(&self, text: &str) -> Result<Duration, LineError> {
        let t = parse_time(text).ok_or_else(|| LineError::BadTime(text.to_string()))?;
        if !t.as_nanos().is_multiple_of(self.cycle.as_nanos()) {
            return Err(LineError::OffCycle {
                time: text.to_string(),
                cycle: Shown(self.cycle),
            });
        }
        Ok(t)
    }

    fn statement(&mut self, line: usize, words: &[&str]) -> Result<(), LineError> {
        if let Some((_, at)) = self.until {
            return Err(LineError::AfterUntil(at));
        }
        let seen_before = std::mem::replace(&mut self.any, true);
        match words[0] {
            "unit" => {
                if let Some(l) = self.unit_line {
                    return Err(LineError::Repeated {
                        name: "unit",
                        first: l,
                    });
                }
                if seen_before {
                    return Err(LineError::UnitNotFirst);
                }
                let [_, kind] = words else {
                    return Err(LineError::Usage(
                        "unit needs a kind: unit incremental|absolute",
                    ));
                };
                self.kind = kind
                    .parse()
                    .map_err(|_| LineError::UnknownUnit(kind.to_string()))?;
                self.unit_line = Some(line);
            }
            "cycle" => {
                if let Some(l) = self.cycle_line {
                    return Err(LineError::Repeated {
                        name: "cycle",
                        first: l,
                    });
                }
                if self.last.is_some() {
                    return Err(LineError::CycleAfterAt);
                }
                let [_, t] = words else {
                    return Err(LineError::Usage("cycle needs a time: cycle TIME"));
                };
                let cycle = parse_time(t).ok_or_else(|| LineError::BadTime(t.to_string()))?;
                if !(MIN_CYCLE..=MAX_CYCLE).contains(&cycle) {
                    return Err(LineError::CycleRange(t.to_string()));
                }
                self.cycle = cycle;
                self.cycle_line = Some(line);
            }
            "config" => {
                if self.last.is_some() {
                    return Err(LineError::ConfigAfterAt);
                }
                let (sub, value) = parse_config(&words[1..])?;
                Configuration::set(&mut self.config, sub, value);
            }
            "at" => self.at(line, words)?,
            "until" => {
                let [_, t] = words else {
                    return Err(LineError::Usage("until needs a time: until TIME"));
                };
                let until = self.time(t)?;
                if until > MAX_RUN {
                    return Err(LineError::TooLong(t.to_string()));
                }
                if until.is_zero() {
                    return Err(LineError::EmptyRun(t.to_string()));
                }
                if let Some((last, last_text)) = &self.last {
                    if until <= *last {
                        return Err(LineError::UntilNotAfter {
                            until: t.to_string(),
                            last: last_text.clone(),
                        });
                    }
                }
                self.until = Some((until, line));
            }
            other => return Err(LineError::UnknownStatement(other.to_string())),
        }
        Ok(())
    }

    fn at(&mut self, line: usize, words: &[&str]) -> Result<(), LineError> {
        let usage = "at needs a time and an action: at TIME out|input|config ...";
        let (Some(t), Some(action)) = (words.get(1), words.get(2)) else {
            return Err(LineError::Usage(usage));
        };
        let time = self.time(t)?;
        if let Some((previous, text)) = &self.last {
            if time < *previous {
                return Err(LineError::Backwards {
                    time: t.to_string(),
                    previous: text.clone(),
                });
            }
        }
        let rest = &words[3..];
        let action = match *action {
            "out" => {
                if rest.is_empty() {
                    return Err(LineError::Usage(
                        "out needs at least one FIELD=VALUE: at TIME out FIELD=VALUE ...",
                    ));
                }
                let mut set = Vec::new();
                for w in rest {
                    let Some((name, value)) = w.split_once('=') else {
                        return Err(LineError::NotAssignment(w.to_string()));
                    };
                    let field = Field::ALL
                        .into_iter()
                        .find(|f| f.name().eq_ignore_ascii_case(name))
                        .ok_or_else(|| LineError::UnknownField(name.to_string()))?;
                    set.push((field, parse_value(field.name(), value, field.ty())?));
                }
                Action::Out(set)
            }
            "input" => {
                let [n, state] = rest else {
                    return Err(LineError::Usage(
                        "input needs a number and a state: at TIME input 1|2 on|off",
                    ));
                };
                let n = match *n {
                    "1" => 1,
                    "2" => 2,
                    other => return Err(LineError::UnknownInput(other.to_string())),
                };
                let current = match *state {
                    "on" => true,
                    "off" => false,
                    other => return Err(LineError::NotOnOff(other.to_string())),
                };
                Action::Input { n, current }
            }
            "config" => {
                let (sub, value) = parse_config(rest)?;
                Action::Config { sub, value }
            }
            other => return Err(LineError::UnknownAction(other.to_string())),
        };
        self.last = Some((time, t.to_string()));
        self.events.push(Event { time, line, action });
        Ok(())
    }
}

impl Script {
    /// Parses `source`; `file` names it in the messages (`file:line: what is wrong`).
    pub fn parse(source: &str, file: &str) -> Result<Script, ScriptError> {
        let mut p = Parser {
            kind: EncoderKind::Incremental,
            config: Configuration::default(),
            cycle: DEFAULT_CYCLE,
            events: Vec::new(),
            until: None,
            unit_line: None,
            cycle_line: None,
            any: false,
            last: None,
        };
        for (k, text) in source.lines().enumerate() {
            let code = text.split_once('#').map_or(text, |(c, _)| c);
            let words: Vec<&str> = code.split_whitespace().collect();
            if words.is_empty() {
                continue;
            }
            p.statement(k + 1, &words)
                .map_err(|error| ScriptError::Line {
                    file: file.to_string(),
                    line: k + 1,
                    error,
                })?;
        }
        let Some((until, _)) = p.until else {
            return Err(ScriptError::NoUntil {
                file: file.to_string(),
            });
        };
        Ok(Script {
            file: file.to_string(),
            kind: p.kind,
            config: p.config,
            cycle: p.cycle,
            events: p.events,
            until,
        })
    }
}

/// How to run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Options {
    /// Also keep a line after each cycle that ends on a multiple of this interval (a whole number of
    /// cycles, see [`check_every`]).
    pub every: Option<Duration>,
}

/// Why `--every` does not fit the script.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("--every {every} is not a whole number of cycles of {file} (the cycle is {cycle})")]
pub struct EveryError {
    /// The interval.
    pub every: Shown,
    /// The script.
    pub file: String,
    /// Its cycle.
    pub cycle: Shown,
}

/// Checks that `every` is a whole, non-zero number of the script's cycles.
pub fn check_every(script: &Script, every: Duration) -> Result<(), EveryError> {
    if every.is_zero() || !every.as_nanos().is_multiple_of(script.cycle.as_nanos()) {
        return Err(EveryError {
            every: Shown(every),
            file: script.file.clone(),
            cycle: Shown(script.cycle),
        });
    }
    Ok(())
}

/// The unit's answer at the end of a cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Time since power-up (the end of the cycle).
    pub time: Duration,
    /// The 20 input bytes.
    pub inputs: Inputs,
    /// Speed in steps/s, positive clockwise.
    pub speed: f64,
    /// The motor turns.
    pub moving: bool,
}

/// The result of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    /// The script's file name.
    pub file: String,
    /// Its encoder kind.
    pub kind: EncoderKind,
    /// Its cycle.
    pub cycle: Duration,
    /// Its end.
    pub until: Duration,
    /// The `--every` interval of the run.
    pub every: Option<Duration>,
    /// The samples of the table's lines (see the module documentation), power-up first.
    pub lines: Vec<Sample>,
    /// The samples for a chart: about [`CURVE_POINTS`] evenly spaced ones, every line's sample and the
    /// one just before it (so that steps show as steps).
    pub curve: Vec<Sample>,
}

/// Applies `action` to the unit and the output words.
fn apply(ix: &mut Indexer, out: &mut Outputs, action: &Action) {
    match action {
        Action::Out(set) => {
            for &(field, value) in set {
                field.set(out, value);
            }
        }
        Action::Input { n, current } => ix.set_input(*n, *current),
        Action::Config { sub, value } => {
            ix.write_config(*sub, *value);
        }
    }
}

/// Whether `now` is a line after `before` by the change rules (not the interval or the end).
fn changed(before: &Sample, now: &Sample) -> bool {
    let (a, b) = (before.inputs, now.inputs);
    a.status0 != b.status0
        || (a.status1 ^ b.status1) & !stat1::HEARTBEAT != 0
        || a.trapped_encoder_position != b.trapped_encoder_position
        || (!before.moving
            && !now.moving
            && (a.motor_position != b.motor_position || a.encoder_position != b.encoder_position))
}

/// Runs `script` cycle by cycle.
///
/// `options.every` should have passed [`check_every`]; an interval off the cycle grid only marks
/// the cycles that end on its multiples.
pub fn run(script: &Script, options: &Options) -> Trace {
    let mut ix = Indexer::new(script.kind, script.config);
    let mut out = Outputs::default();
    let cycle_ns = script.cycle.as_nanos();
    let cycles = (script.until.as_nanos() / cycle_ns) as u64;
    let stride = (cycles / CURVE_POINTS).max(1);
    let every = options.every.filter(|e| !e.is_zero()).map(|e| e.as_nanos());
    let mut events = script.events.iter().peekable();
    let mut prev = Sample {
        time: Duration::ZERO,
        inputs: ix.inputs(),
        speed: 0.0,
        moving: false,
    };
    let mut lines = vec![prev];
    let mut curve = vec![prev];
    for k in 0..cycles {
        let start = script.cycle * k as u32;
        while let Some(e) = events.next_if(|e| e.time <= start) {
            apply(&mut ix, &mut out, &e.action);
        }
        let inputs = ix.cycle(out, script.cycle);
        let now = Sample {
            time: ix.time(),
            inputs,
            speed: ix.speed(),
            moving: ix.is_moving(),
        };
        let change = changed(&prev, &now) || k + 1 == cycles;
        let tick = every.is_some_and(|e| now.time.as_nanos().is_multiple_of(e));
        if change || tick {
            lines.push(now);
        }
        if change {
            if curve.last().map(|s| s.time) != Some(prev.time) {
                curve.push(prev);
            }
            curve.push(now);
        } else if (k + 1) % stride == 0 {
            curve.push(now);
        }
        prev = now;
    }
    Trace {
        file: script.file.clone(),
        kind: script.kind,
        cycle: script.cycle,
        until: script.until,
        every: options.every,
        lines,
        curve,
    }
}

/// The names of the set bits of STATUS_word0 (not Module_OK, `!Module_OK` when clear), then ` | ` and
/// those of STATUS_word1 (not the Heartbeat_Bit) when any is set.
pub fn bit_names(status0: u16, status1: u16) -> String {
    let names = |word: u16, table: &[&'static str; 16], skip: u16| -> Vec<String> {
        (0..16)
            .filter(|&b| word & (1 << b) != 0 && (1 << b) != skip)
            .map(|b| match table[b] {
                "" => format!("bit_{b}"),
                n => n.to_string(),
            })
            .collect()
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

/// The bits the chart's strip shows, top first: (name, STATUS word 0 or 1, mask).
const LANES: [(&str, u8, u16); 11] = [
    ("Moving_CW", 0, stat0::MOVING_CW),
    ("Moving_CCW", 0, stat0::MOVING_CCW),
    ("Accelerating", 0, stat0::ACCELERATING),
    ("Decelerating", 0, stat0::DECELERATING),
    ("In_Hold_State", 0, stat0::IN_HOLD_STATE),
    ("Move_Complete", 0, stat0::MOVE_COMPLETE),
    ("Position_Invalid", 0, stat0::POSITION_INVALID),
    ("Input_Error", 0, stat0::INPUT_ERROR),
    ("Command_Error", 0, stat0::COMMAND_ERROR),
    ("IN1_Active", 1, stat1::IN1_ACTIVE),
    ("IN2_Active", 1, stat1::IN2_ACTIVE),
];

/// A y range around `values` with 5 % room, never empty.
fn y_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (mut lo, mut hi) = (0.0f64, 0.0f64);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if hi <= lo {
        hi = lo + 1.0;
    }
    let pad = (hi - lo) * 0.05;
    (lo - pad)..(hi + pad)
}

/// Draws `trace` to `path` as SVG: three panels over time — Motor_Position, speed, and a strip of
/// status bits (Moving_CW … IN2_Active, a filled bar while the bit is 1).
pub fn plot(trace: &Trace, path: &Path) -> Result<(), PlotError> {
    let err = |e: &dyn fmt::Display| PlotError::at(path, e);
    let x = 0.0..trace.until.as_secs_f64();
    let pts = |f: &dyn Fn(&Sample) -> f64| -> Vec<(f64, f64)> {
        trace
            .curve
            .iter()
            .map(|s| (s.time.as_secs_f64(), f(s)))
            .collect()
    };
    let position = pts(&|s| f64::from(s.inputs.motor_position));
    let speed = pts(&|s| s.speed);

    let root = SVGBackend::new(path, (1000, 960)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let root = root
        .titled(
            &format!("smd simulate {} (cycle {})", trace.file, Shown(trace.cycle)),
            ("sans-serif", 22),
        )
        .map_err(|e| err(&e))?;
    let (top, rest) = root.split_vertically(320);
    let (middle, bottom) = rest.split_vertically(260);
    let label_area = 150;

    for (area, values, y_desc, colour) in [
        (&top, &position, "Motor_Position [steps]", BLUE),
        (&middle, &speed, "speed [steps/s]", RED),
    ] {
        let mut chart = ChartBuilder::on(area)
            .margin(10)
            .margin_right(24)
            .x_label_area_size(30)
            .y_label_area_size(label_area)
            .build_cartesian_2d(x.clone(), y_range(values.iter().map(|p| p.1)))
            .map_err(|e| err(&e))?;
        chart
            .configure_mesh()
            .y_desc(y_desc)
            .x_label_formatter(&|v| format_tick(*v))
            .y_label_formatter(&|v| format_tick(*v))
            .axis_desc_style(("sans-serif", 16))
            .draw()
            .map_err(|e| err(&e))?;
        chart
            .draw_series(LineSeries::new(
                values.iter().copied(),
                colour.stroke_width(2),
            ))
            .map_err(|e| err(&e))?;
    }

    let n = LANES.len();
    // Lane k (top first) spans 10 units of y: its baseline at 10·(n − 1 − k), its bar 7 high, its name
    // at the middle of the bar (integer coordinates, whose key points plotters can format).
    let lane_y = |k: usize| 10 * (n - 1 - k) as i32;
    let keys: Vec<i32> = (0..n).map(|k| lane_y(k) + 3).collect();
    let mut chart = ChartBuilder::on(&bottom)
        .margin(10)
        .margin_right(24)
        .x_label_area_size(44)
        .y_label_area_size(label_area)
        .build_cartesian_2d(x.clone(), (-2..10 * n as i32).with_key_points(keys))
        .map_err(|e| err(&e))?;
    let lane_name = |v: &i32| -> String {
        let k = (v - 3) / 10;
        if (0..n as i32).contains(&k) && (v - 3) % 10 == 0 {
            LANES[n - 1 - k as usize].0.to_string()
        } else {
            String::new()
        }
    };
    chart
        .configure_mesh()
        .disable_y_mesh()
        .x_desc("time [s]")
        .x_label_formatter(&|v| format_tick(*v))
        .y_label_formatter(&lane_name)
        .axis_desc_style(("sans-serif", 16))
        .draw()
        .map_err(|e| err(&e))?;
    let colours = [
        BLUE, BLUE, GREEN, RED, MAGENTA, BLACK, RED, RED, RED, CYAN, CYAN,
    ];
    let end = x.end;
    for (k, &(_, word, mask)) in LANES.iter().enumerate() {
        let y = lane_y(k);
        let colour = colours[k];
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(0.0, y), (end, y)],
                BLACK.mix(0.3),
            )))
            .map_err(|e| err(&e))?;
        let on = |s: &Sample| {
            let w = if word == 0 {
                s.inputs.status0
            } else {
                s.inputs.status1
            };
            w & mask != 0
        };
        let mut bars = Vec::new();
        let mut since: Option<f64> = None;
        for s in &trace.curve {
            let t = s.time.as_secs_f64();
            match (on(s), since) {
                (true, None) => since = Some(t),
                (false, Some(t0)) => {
                    bars.push((t0, t));
                    since = None;
                }
                _ => {}
            }
        }
        if let Some(t0) = since {
            bars.push((t0, end));
        }
        chart
            .draw_series(
                bars.into_iter().map(|(t0, t1)| {
                    Rectangle::new([(t0, y), (t1, y + 7)], colour.mix(0.6).filled())
                }),
            )
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
