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
//! use std::time::Instant;
//!
//! let script = Script::parse("at 0ms out cmd1=0x8000\nuntil 5ms\n", "enable.smd").unwrap();
//! let trace = run(&script, &Options::default(), Instant::now());
//! assert_eq!(trace.lines.len(), 3); // power-up, Drive_Is_Enabled, the end
//! let line = format_line(&trace, &trace.lines[1]);
//! assert!(line.trim_start().starts_with("0.001 "));
//! assert!(line.ends_with("0x4408        0x8000  Stopped Position_Invalid | Drive_Is_Enabled"));
//! ```
//!
//! [`Indexer::write_config`]: super::indexer::Indexer::write_config
//! [`Configuration::default`]: super::config::Configuration::default

use std::time::Duration;

mod chart;
mod script;
mod table;
mod trace;

pub use chart::plot;
pub use script::{
    parse_time, Action, Event, Field, LineError, Script, ScriptError, Shown, Type, CONFIG_NAMES,
};
pub use table::{
    bit_names, format_line, header, set_bit_names, write_table, STATUS0_NAMES, STATUS1_NAMES,
};
pub use trace::{check_every, run, EveryError, Options, Sample, Trace};

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
