//! The run: the script's statements applied before their cycles, the indexer cycled to the end,
//! and the samples kept for the table and the chart.

use std::time::{Duration, Instant};

use super::script::{Action, Script, Shown};
use super::CURVE_POINTS;
use crate::smd::config::EncoderKind;
use crate::smd::indexer::{stat1, Indexer, Inputs, Outputs};

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

/// Applies `action`, made at `now`, to the unit and the output words.
fn apply(ix: &mut Indexer, out: &mut Outputs, action: &Action, now: Instant) {
    match action {
        Action::Out(set) => {
            for &(field, value) in set {
                field.set(out, value);
            }
        }
        Action::Input { n, current } => ix.set_input(now, *n, *current),
        Action::Config { sub, value } => {
            ix.write_config(now, *sub, *value);
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

/// Runs `script` cycle by cycle, the unit powered on at `power_on`: no clock is read, the instant
/// of each cycle is `power_on` plus the cycles before it, and each statement is made at the start
/// of its cycle. The trace does not depend on `power_on`.
///
/// `options.every` should have passed [`check_every`]; an interval off the cycle grid only marks
/// the cycles that end on its multiples.
pub fn run(script: &Script, options: &Options, power_on: Instant) -> Trace {
    let mut ix = Indexer::new(script.kind, script.config);
    ix.start(power_on, script.cycle);
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
            let now = ix.last_exchange().unwrap_or(power_on);
            apply(&mut ix, &mut out, &e.action, now);
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
