//! The motor current of one X67SM2436 axis (seed 002, 18.11.1.1 and 18.11.1.2).
//!
//! A pure, deterministic per-cycle model: [`CurrentModel::step`] takes the motion phase of one
//! ramp-generator cycle, the output speed and the cycle length, and returns the [`CurrentState`] the axis
//! drives in that cycle. Nothing here reads a clock or does IO.
//!
//! # Current levels
//!
//! The axis uses the holding current at standstill, the nominal current at constant speed and the maximum
//! current while the ramp changes the magnitude of the speed, braking included (X67-18.11.1.1-02). In homing
//! by referencing during stall the nominal current replaces the maximum current (X67-18.11.1.1-03).
//!
//! When the level changes to a weaker one, the stronger level is kept for another 100 ms
//! (X67-18.11.1.1-04). "Stronger" is decided by category — maximum before nominal before holding — and not by
//! the configured percentages (X67-18.11.1.1-05). The 100 ms are counted in whole ramp-generator cycles: the
//! stronger level stays for `ceil(100 / cycle_ms)` cycles after the last cycle that asked for it (10 cycles
//! at 10 ms, 4 at 25 ms, 20 at 5 ms); the cycle after that drives the weaker level.
//!
//! ```
//! use ds402::x67::current::{Config, CurrentModel, Level, Phase};
//!
//! let mut model = CurrentModel::new(Config { holding: 20, nominal: 60, maximum: 100, ..Config::default() })
//!     .unwrap();
//! assert_eq!(model.step(Phase::Accelerating, 50, 25).level, Level::Maximum);
//! let levels: Vec<Level> = (0..5).map(|_| model.step(Phase::Constant, 50, 25).level).collect();
//! assert_eq!(levels, [Level::Maximum, Level::Maximum, Level::Maximum, Level::Maximum, Level::Nominal]);
//! ```
//!
//! # Full step
//!
//! With FullStepThreshold0n = 1…65534 the axis runs in full steps at speeds (magnitude, microsteps/cycle) at
//! or above the threshold and in microsteps below it; 65535 and the default 0 keep it in microsteps at every
//! speed (X67-18.11.1.2-01, X67-18.11.1.2-02).
//!
//! Rule IDs (`X67-…`) refer to the rule catalogue of the X67SM2436 (`rules/x67.md`).

use crate::x67::ramp::RampState;

/// Largest value of ConfigOutput03a…08a, in percent of the module's nominal current (X67-18.11.1.1-01).
pub const MAX_PERCENT: u8 = 167;

/// The module's nominal current (100 %) in milliamperes (X67-18.11.1.1-01).
pub const MODULE_NOMINAL_MILLIAMPS: u32 = 3_000;

/// How long a stronger level is kept when the level changes to a weaker one, in milliseconds
/// (X67-18.11.1.1-04).
pub const HOLD_MS: u32 = 100;

/// FullStepThreshold0n value that keeps the motor in microstep mode at every speed (X67-18.11.1.2-01).
pub const FULL_STEP_NEVER: u16 = 65_535;

/// SDO abort code for a value above the register's range (CiA 301 0x06090031, value too high).
pub const ABORT_VALUE_TOO_HIGH: u32 = 0x0609_0031;

/// The configuration registers of one axis (axis 1: ConfigOutput03a/04a/05a and FullStepThreshold01).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Config {
    /// Holding current (ConfigOutput03a), 0…167 % of the module's nominal current; default 0.
    pub holding: u8,
    /// Nominal current (ConfigOutput04a), 0…167 %; default 0.
    pub nominal: u8,
    /// Maximum current (ConfigOutput05a), 0…167 %; default 0.
    pub maximum: u8,
    /// Full-step threshold (FullStepThreshold01) in microsteps/cycle; 0 and 65535 disable full step.
    pub full_step_threshold: u16,
    /// The axis is homing by referencing during stall: the nominal current replaces the maximum current.
    pub stall_homing: bool,
}

/// A configuration value outside its range.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ConfigError {
    /// A current register was given more than [`MAX_PERCENT`] (X67-18.11.1.1-01).
    ValueTooHigh {
        /// Which current register.
        level: Level,
        /// The rejected value.
        value: u8,
    },
}

impl ConfigError {
    /// The SDO abort code the download of the rejected value ends with (0x06090031).
    pub const fn abort_code(&self) -> u32 {
        match self {
            ConfigError::ValueTooHigh { .. } => ABORT_VALUE_TOO_HIGH,
        }
    }
}

impl Config {
    /// Checks that every current register lies within 0…167 % (X67-18.11.1.1-01). No ordering of the three
    /// values is enforced (X67-18.11.1.1-05).
    pub fn validate(&self) -> Result<(), ConfigError> {
        for (level, value) in [
            (Level::Holding, self.holding),
            (Level::Nominal, self.nominal),
            (Level::Maximum, self.maximum),
        ] {
            if value > MAX_PERCENT {
                return Err(ConfigError::ValueTooHigh { level, value });
            }
        }
        Ok(())
    }

    /// The configured percentage of a level.
    pub const fn percent(&self, level: Level) -> u8 {
        match level {
            Level::Holding => self.holding,
            Level::Nominal => self.nominal,
            Level::Maximum => self.maximum,
        }
    }

    /// Whether the motor runs in full steps at `speed` (microsteps/cycle, either sign) (X67-18.11.1.2-01,
    /// X67-18.11.1.2-02).
    pub const fn full_step(&self, speed: i32) -> bool {
        let threshold = self.full_step_threshold;
        threshold != 0 && threshold != FULL_STEP_NEVER && speed.unsigned_abs() >= threshold as u32
    }
}

/// A current level; the order is the priority of X67-18.11.1.1-05 (holding < nominal < maximum).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Level {
    /// Holding current (standstill).
    Holding,
    /// Nominal current (constant speed).
    Nominal,
    /// Maximum current (the speed changes).
    Maximum,
}

/// The motion phase of one ramp-generator cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Phase {
    /// The magnitude of the speed rises.
    Accelerating,
    /// The magnitude of the speed falls (braking counts as an acceleration phase, X67-18.11.1.1-02).
    Decelerating,
    /// The axis moves without changing the magnitude of its speed.
    Constant,
    /// The axis stands.
    Standstill,
}

impl Phase {
    /// The phase of a ramp-generator cycle: accelerating or decelerating as flagged, standstill when the axis
    /// stands, otherwise constant (this includes a moving axis's cycle at speed 0 while it reverses).
    pub const fn from_ramp(state: &RampState) -> Self {
        if state.accelerating {
            Phase::Accelerating
        } else if state.decelerating {
            Phase::Decelerating
        } else if state.standstill {
            Phase::Standstill
        } else {
            Phase::Constant
        }
    }
}

/// What the axis drives in one cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CurrentState {
    /// The level in effect (after the 100 ms hold).
    pub level: Level,
    /// Its configured value in percent of the module's nominal current.
    pub percent: u8,
    /// The same in milliamperes: `percent × 30` (100 % = 3 A).
    pub amps_milli: u32,
    /// The motor runs in full-step mode in this cycle.
    pub full_step: bool,
}

/// The current model of one axis.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CurrentModel {
    config: Config,
    /// The level in effect; `None` before the first cycle.
    active: Option<Level>,
    /// Milliseconds the active level has been kept while a weaker one was asked for.
    held_ms: u32,
}

impl CurrentModel {
    /// A model with the given configuration, rejected if a current register is above 167 %.
    pub fn new(config: Config) -> Result<Self, ConfigError> {
        config.validate()?;
        Ok(Self {
            config,
            active: None,
            held_ms: 0,
        })
    }

    /// The configuration.
    pub const fn config(&self) -> &Config {
        &self.config
    }

    /// Replaces the configuration (a rejected one leaves the old one in place); the level in effect and the
    /// running hold are kept.
    pub fn set_config(&mut self, config: Config) -> Result<(), ConfigError> {
        config.validate()?;
        self.config = config;
        Ok(())
    }

    /// The level a phase asks for, before the 100 ms hold (X67-18.11.1.1-02, X67-18.11.1.1-03).
    pub const fn wanted(&self, phase: Phase) -> Level {
        match phase {
            Phase::Accelerating | Phase::Decelerating if self.config.stall_homing => Level::Nominal,
            Phase::Accelerating | Phase::Decelerating => Level::Maximum,
            Phase::Constant => Level::Nominal,
            Phase::Standstill => Level::Holding,
        }
    }

    /// Advances by one ramp-generator cycle of `cycle_ms` milliseconds (0 counts as 1) in which the axis is in
    /// `phase` at `speed` microsteps/cycle, and returns what it drives in that cycle.
    pub fn step(&mut self, phase: Phase, speed: i32, cycle_ms: u32) -> CurrentState {
        let wanted = self.wanted(phase);
        let level = match self.active {
            Some(active) if wanted < active && self.held_ms < HOLD_MS => {
                self.held_ms += cycle_ms.max(1);
                active
            }
            _ => {
                self.held_ms = 0;
                wanted
            }
        };
        self.active = Some(level);
        let percent = self.config.percent(level);
        CurrentState {
            level,
            percent,
            amps_milli: u32::from(percent) * MODULE_NOMINAL_MILLIAMPS / 100,
            full_step: self.config.full_step(speed),
        }
    }
}
