//! The script: its statements, times and values, parsed into a [`Script`] with line-numbered
//! errors.

use std::fmt;
use std::time::Duration;

use super::{DEFAULT_CYCLE, MAX_CYCLE, MAX_RUN, MIN_CYCLE};
use crate::smd::config::{Configuration, EncoderKind};
use crate::smd::indexer::Outputs;

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
    pub(super) fn set(self, out: &mut Outputs, value: i64) {
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
#[non_exhaustive]
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
#[non_exhaustive]
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
