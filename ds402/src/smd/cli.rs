//! The `smd` command line: arguments and what each command does. `main` only parses and calls [`run`].

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use clap::{Parser, Subcommand};

use super::config::{decode_words, Cfg0, Cfg1, InputFunction};
use super::plot::{self, Series};
use super::profile::{MoveParams, Profile};
use super::simulate::{self, Options, Script};

/// Tools for the AMCI SMD23K-B / SMD24K integrated stepper indexer.
#[derive(Debug, Parser)]
#[command(name = "smd", version)]
pub struct Args {
    /// Machine-readable output: one JSON object per result on standard output, nothing else (a
    /// simulation's table one object per line).
    #[arg(long, global = true)]
    pub json: bool,
    /// What to do.
    #[command(subcommand)]
    pub command: Cmd,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Cmd {
    /// Compute a move profile (manual Reference 3): phases, times, distances and the peak speed.
    Profile(ProfileArgs),
    /// The configuration-word calculator of table R5.3 (CFG_Word_0 / CFG_Word_1, 8010:01/02).
    #[command(subcommand)]
    Config(ConfigCmd),
    /// Run a script of process-data writes and input changes against the indexer model offline and
    /// print (with --plot also draw) the resulting positions and status bits over time.
    #[command(long_about = simulate::HELP)]
    Simulate(SimulateArgs),
}

/// `smd simulate`.
#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    /// The script (see the format above).
    #[arg(value_name = "SCRIPT")]
    pub script: PathBuf,
    /// Also print a line at every multiple of this interval: milliseconds, or a time with us, ms or s
    /// (a whole number of cycles).
    #[arg(long, value_name = "MS", value_parser = parse_every)]
    pub every: Option<std::time::Duration>,
    /// Also draw Motor_Position, speed and the motion bits over time into this SVG file.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
}

/// `--every`: a number of milliseconds (`100`, `0.5`) or a time with its unit (`250us`, `1s`).
fn parse_every(text: &str) -> Result<std::time::Duration, String> {
    let t = text.trim();
    let with_unit = if t.bytes().all(|b| b.is_ascii_digit() || b == b'.') {
        format!("{t}ms")
    } else {
        t.to_string()
    };
    match simulate::parse_time(&with_unit) {
        Some(d) if !d.is_zero() => Ok(d),
        _ => Err(format!(
            "{text:?} is not an interval (milliseconds, or a time with us, ms or s, above 0)"
        )),
    }
}

/// `smd config`.
#[derive(Debug, Subcommand)]
pub enum ConfigCmd {
    /// Build CFG_Word_0 (and CFG_Word_1 when one of its flags is given) from named settings; prints the
    /// word(s) in hex. Exit 1 when the result breaks an "Invalid Configurations" rule.
    Encode(EncodeArgs),
    /// Name the settings of CFG_Word_0 [and CFG_Word_1] and the rules they break; exit 1 when invalid.
    Decode(DecodeArgs),
}

/// `smd config encode`.
#[derive(Debug, clap::Args)]
pub struct EncodeArgs {
    /// Input 1's function: general-purpose, cw-limit, ccw-limit, start-indexed, stop-jog, e-stop, home.
    #[arg(long, default_value = "general-purpose")]
    pub input1: InputFunction,
    /// Input 2's function (same names).
    #[arg(long, default_value = "general-purpose")]
    pub input2: InputFunction,
    /// Use the built-in encoder (bit 10).
    #[arg(long)]
    pub encoder: bool,
    /// Use the Backplane_Proximity_Bit when homing (bit 11).
    #[arg(long)]
    pub backplane_proximity: bool,
    /// Enable stall detection (bit 13; needs --encoder).
    #[arg(long)]
    pub stall_detection: bool,
    /// Switch anti-resonance off (bit 14).
    #[arg(long)]
    pub disable_antiresonance: bool,
    /// CFG_Word_1 bit 0: Input 1 is active when current flows (normally-open sensor).
    #[arg(long)]
    pub in1_active_on_current: bool,
    /// CFG_Word_1 bit 1: Input 2 is active when current flows.
    #[arg(long)]
    pub in2_active_on_current: bool,
    /// CFG_Word_1 bit 6: start moves on the Distributed Clock's SYNC0.
    #[arg(long)]
    pub dc_sync: bool,
}

/// `smd config decode`.
#[derive(Debug, clap::Args)]
pub struct DecodeArgs {
    /// CFG_Word_0 (0x2411, 9233, 0b0010010000010001).
    #[arg(value_parser = parse_word)]
    pub cfg_word0: u16,
    /// CFG_Word_1.
    #[arg(value_parser = parse_word)]
    pub cfg_word1: Option<u16>,
}

/// A 16-bit word in hex (0x…), binary (0b…) or decimal.
fn parse_word(text: &str) -> Result<u16, String> {
    let t = text.trim().replace('_', "");
    let parsed = if let Some(h) = t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        u16::from_str_radix(h, 16)
    } else if let Some(b) = t.strip_prefix("0b").or_else(|| t.strip_prefix("0B")) {
        u16::from_str_radix(b, 2)
    } else {
        t.parse::<u16>()
    };
    parsed.map_err(|_| format!("{text:?} is not a 16-bit word (0x0000 to 0xFFFF)"))
}

/// `smd profile`.
#[derive(Debug, clap::Args)]
pub struct ProfileArgs {
    /// Starting Speed (8010:03), steps/s (1 to 1,999,999).
    #[arg(long, default_value_t = 141, value_parser = clap::value_parser!(u32).range(1..=1_999_999))]
    pub start: u32,
    /// Programmed speed (the Velocity word), steps/s (the starting speed to 2,999,999).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=2_999_999))]
    pub speed: u32,
    /// Acceleration word, steps/s/ms (1 to 5000; ×1000 for steps/s²).
    #[arg(long)]
    pub accel: u16,
    /// Deceleration word, steps/s/ms (1 to 5000).
    #[arg(long)]
    pub decel: u16,
    /// Jerk word (0 = linear acceleration, 1 to 5000 = S-curve with jerk J·a/100 steps/s³).
    #[arg(long, default_value_t = 0)]
    pub jerk: u16,
    /// Length of the move in steps (the sign gives the direction and does not change the profile).
    #[arg(long, allow_hyphen_values = true)]
    pub distance: i64,
    /// Also draw speed over time into this SVG file.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
}

/// Why a command failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CliError {
    /// The profile.
    #[error(transparent)]
    Profile(#[from] super::profile::ProfileError),
    /// The chart.
    #[error(transparent)]
    Plot(#[from] plot::PlotError),
    /// Writing the output.
    #[error("cannot write the output: {0}")]
    Output(#[from] std::io::Error),
    /// Reading a script.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// A script with an error.
    #[error(transparent)]
    Script(#[from] simulate::ScriptError),
    /// `--every` off the script's cycle.
    #[error(transparent)]
    Every(#[from] simulate::EveryError),
}

/// Runs `args` at `now` (the power-on instant of a simulation, which reads no clock), printing to
/// `out`; the process's exit code on success (0, or 1 where a command reports a finding such as an
/// invalid configuration).
pub fn run(args: &Args, now: Instant, out: &mut dyn Write) -> Result<i32, CliError> {
    let json = args.json;
    match &args.command {
        Cmd::Profile(p) => profile(p, json, out),
        Cmd::Config(ConfigCmd::Encode(e)) => encode(e, json, out),
        Cmd::Config(ConfigCmd::Decode(d)) => decode(d, json, out),
        Cmd::Simulate(s) => simulate(s, json, now, out),
    }
}

/// The largest script `simulate` reads.
pub const MAX_SCRIPT: u64 = 16 << 20;

/// A script's text: a regular file (a FIFO or a device is refused before it is opened) of at most
/// [`MAX_SCRIPT`] bytes, in UTF-8.
fn read_script(path: &std::path::Path) -> std::io::Result<String> {
    let bytes = crate::od::load::read_limited(path, MAX_SCRIPT)?;
    String::from_utf8(bytes)
        .map_err(|_| std::io::Error::new(std::io::ErrorKind::InvalidData, "not UTF-8 text"))
}

/// Writes `value` as one line of JSON.
fn json_line(out: &mut dyn Write, value: &serde_json::Value) -> Result<(), CliError> {
    writeln!(out, "{value}")?;
    Ok(())
}

/// Says where a chart went: `{"chart": PATH}`, or the text line after `prefix` (`# ` where it
/// follows a table).
fn chart_written(
    out: &mut dyn Write,
    json: bool,
    prefix: &str,
    path: &std::path::Path,
) -> Result<(), CliError> {
    if json {
        json_line(
            out,
            &serde_json::json!({"chart": path.display().to_string()}),
        )
    } else {
        writeln!(out, "{prefix}chart written to {}", path.display())?;
        Ok(())
    }
}

/// A configuration check's findings as JSON: the words, valid or not, and each violation with its
/// rule.
fn decoded_json(d: &super::config::Decoded) -> serde_json::Value {
    let input = |f: Option<InputFunction>| match f {
        Some(function) => serde_json::Value::from(function.manual_name()),
        None => serde_json::Value::Null,
    };
    let cfg1 = d.cfg1.map(|c| {
        serde_json::json!({
            "in1_active_level": u8::from(c.in1_active_level),
            "in2_active_level": u8::from(c.in2_active_level),
            "dc_sync": c.dc_sync,
            "reserved_bits": c.reserved,
        })
    });
    let c = &d.cfg0;
    serde_json::json!({
        "cfg_word0": d.word0,
        "cfg_word1": d.word1,
        "cfg0": {
            "input1": input(c.input1),
            "input2": input(c.input2),
            "use_encoder": c.use_encoder,
            "use_backplane_proximity": c.use_backplane_proximity,
            "enable_stall_detection": c.enable_stall_detection,
            "disable_antiresonance": c.disable_antiresonance,
            "reserved_bits": c.reserved,
        },
        "cfg1": cfg1,
        "valid": d.is_valid(),
        "violations": d.violations.iter().map(|v| serde_json::json!({
            "text": v.to_string(), "rule": v.rule(),
        })).collect::<Vec<_>>(),
    })
}

fn simulate(
    a: &SimulateArgs,
    json: bool,
    now: Instant,
    out: &mut dyn Write,
) -> Result<i32, CliError> {
    let file = a.script.display().to_string();
    let source = read_script(&a.script).map_err(|source| CliError::Read {
        path: file.clone(),
        source,
    })?;
    let script = Script::parse(&source, &file)?;
    if let Some(every) = a.every {
        simulate::check_every(&script, every)?;
    }
    let trace = simulate::run(&script, &Options { every: a.every }, now);
    if json {
        for s in &trace.lines {
            let i = &s.inputs;
            json_line(
                out,
                &serde_json::json!({
                    "t": s.time.as_secs_f64(),
                    "motor_position": i.motor_position,
                    "encoder_position": i.encoder_position,
                    "trapped_encoder_position": i.trapped_encoder_position,
                    // Negative zero is zero.
                    "speed": if s.speed == 0.0 { 0.0 } else { s.speed },
                    "status_word0": i.status0,
                    "status_word1": i.status1,
                    "status_word0_bits":
                        simulate::set_bit_names(i.status0, &simulate::STATUS0_NAMES),
                    "status_word1_bits":
                        simulate::set_bit_names(i.status1, &simulate::STATUS1_NAMES),
                }),
            )?;
        }
    } else {
        simulate::write_table(&trace, out)?;
    }
    if let Some(path) = &a.plot {
        simulate::plot(&trace, path)?;
        chart_written(out, json, "# ", path)?;
    }
    Ok(0)
}

fn encode(e: &EncodeArgs, json: bool, out: &mut dyn Write) -> Result<i32, CliError> {
    let cfg0 = Cfg0 {
        input1: Some(e.input1),
        input2: Some(e.input2),
        use_encoder: e.encoder,
        use_backplane_proximity: e.backplane_proximity,
        enable_stall_detection: e.stall_detection,
        disable_antiresonance: e.disable_antiresonance,
        ..Cfg0::default()
    };
    let word0 = cfg0.encode();
    let word1 = (e.in1_active_on_current || e.in2_active_on_current || e.dc_sync).then(|| {
        Cfg1 {
            in1_active_level: e.in1_active_on_current,
            in2_active_level: e.in2_active_on_current,
            dc_sync: e.dc_sync,
            ..Cfg1::from_word(0)
        }
        .encode()
    });
    let decoded = decode_words(word0, word1);
    if json {
        json_line(out, &decoded_json(&decoded))?;
        return Ok(if decoded.is_valid() { 0 } else { 1 });
    }
    writeln!(out, "{word0:#06x}")?;
    if let Some(w) = word1 {
        writeln!(out, "{w:#06x}")?;
    }
    for v in &decoded.violations {
        writeln!(out, "invalid: {v} [{}]", v.rule())?;
    }
    Ok(if decoded.is_valid() { 0 } else { 1 })
}

fn decode(d: &DecodeArgs, json: bool, out: &mut dyn Write) -> Result<i32, CliError> {
    let decoded = decode_words(d.cfg_word0, d.cfg_word1);
    if json {
        json_line(out, &decoded_json(&decoded))?;
    } else {
        writeln!(out, "{decoded}")?;
    }
    Ok(if decoded.is_valid() { 0 } else { 1 })
}

/// A phase of a move as JSON.
fn phase_json(p: &super::profile::Phase) -> serde_json::Value {
    use super::profile::PhaseShape;
    serde_json::json!({
        "shape": match p.shape {
            PhaseShape::Linear => "linear",
            PhaseShape::TriangularS => "triangular S-curve",
            PhaseShape::TrapezoidalS => "trapezoidal S-curve",
        },
        "low_speed": p.low, "high_speed": p.high, "accel": p.accel, "jerk": p.jerk,
        "time": p.time, "distance": p.distance, "peak_accel": p.peak_accel,
    })
}

fn profile(a: &ProfileArgs, json: bool, out: &mut dyn Write) -> Result<i32, CliError> {
    let profile = Profile::plan(MoveParams {
        start_speed: f64::from(a.start),
        speed: f64::from(a.speed),
        accel: a.accel,
        decel: a.decel,
        jerk: a.jerk,
        distance: a.distance.unsigned_abs() as f64,
    })?;
    if json {
        use super::profile::MoveShape;
        json_line(
            out,
            &serde_json::json!({
                "shape": match profile.shape {
                    MoveShape::Trapezoidal => "trapezoidal",
                    MoveShape::Triangular => "triangular",
                },
                "threshold": profile.threshold,
                "peak_speed": profile.peak_speed,
                "accel": phase_json(&profile.accel),
                "cruise": {"time": profile.cruise_time, "distance": profile.cruise_distance},
                "decel": phase_json(&profile.decel),
                "total_time": profile.total_time(),
                "total_distance": profile.total_distance(),
            }),
        )?;
    } else {
        write!(out, "{profile}")?;
    }
    if let Some(path) = &a.plot {
        let points = profile.speed_samples(1000);
        plot::line_chart(
            path,
            &format!(
                "SMD move of {} steps: accel {}, decel {}, jerk {}",
                a.distance.unsigned_abs(),
                a.accel,
                a.decel,
                a.jerk
            ),
            "time [s]",
            "speed [steps/s]",
            &[Series {
                label: "speed",
                points: &points,
            }],
        )?;
        chart_written(out, json, "", path)?;
    }
    Ok(0)
}

/// An error as `--json` prints it (on standard output, exit code 2).
pub fn error_json(e: &CliError) -> serde_json::Value {
    serde_json::json!({"error": e.to_string(), "exit_code": 2})
}
