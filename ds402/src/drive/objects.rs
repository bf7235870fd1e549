//! The CiA 402 objects a [`Drive`] owns, its copy of their values, and the drive as an
//! [`od::hook::DeviceHook`].
//!
//! Two kinds of owned objects (CiA 402-2, the object dictionary of each mode and of the device
//! control function):
//! - **process values** the drive computes ([`PROCESS`]): 0x603F error code, 0x6041 status word,
//!   0x6061 modes of operation display, 0x6062 position demand, 0x6063 position actual internal,
//!   0x6064 position actual, 0x606B velocity demand, 0x606C velocity actual, 0x6074 torque demand,
//!   0x6077 torque actual, 0x60F4 following error actual, 0x60FC position demand internal, 0x60FD
//!   digital inputs. `read` answers them; a write is refused (0x06010002).
//! - **parameters and targets** ([`DEFS`]): `read` answers `None` (the dictionary's stored value
//!   stands); `check`/`write` apply the drive's own rules on top of the dictionary's and keep a copy.
//!
//! Objects are per axis: axis `n` has them at `0x6000 + 0x800 · n + (index − 0x6000)` (CiA 402-2,
//! multi-axis devices). Values travel as little-endian bytes of the entry's data type, the type the
//! dictionary gives (the standard's type where the dictionary lacks the object).

use std::time::Instant;

use od::abort::AbortCode;
use od::dict::{Address, Dictionary};
use od::hook::DeviceHook;
use od::types::DataType;
use od::value::Value;

use super::{Drive, MotorConfig, MotorKind};

/// A parameter of the drive: its position in [`DEFS`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(usize)]
pub(crate) enum P {
    ControlWord,
    QuickStopOption,
    ShutdownOption,
    DisableOperationOption,
    HaltOption,
    FaultReactionOption,
    Mode,
    FollowingWindow,
    FollowingTimeout,
    PositionWindow,
    PositionWindowTime,
    VelocityWindow,
    VelocityWindowTime,
    VelocityThreshold,
    VelocityThresholdTime,
    TargetTorque,
    MaxTorque,
    RatedTorque,
    TargetPosition,
    HomeOffset,
    MinPositionLimit,
    MaxPositionLimit,
    MaxProfileVelocity,
    MaxMotorSpeed,
    ProfileVelocity,
    ProfileAcceleration,
    ProfileDeceleration,
    QuickStopDeceleration,
    MotionProfileType,
    EncoderIncrements,
    MotorRevolutions,
    HomingMethod,
    HomingSpeedSwitch,
    HomingSpeedZero,
    HomingAcceleration,
    PositionOffset,
    VelocityOffset,
    TorqueOffset,
    InterpolationUnits,
    InterpolationIndex,
    MaxAcceleration,
    MaxDeceleration,
    PositioningOption,
    TargetVelocity,
}

/// What the drive accepts for a parameter, beyond what the dictionary checks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Rule {
    /// Every value of the type.
    Any,
    /// `lo..=hi`: below is 0x06090032, above 0x06090031.
    Range(i64, i64),
    /// One of these values, else 0x06090030.
    OneOf(&'static [i64]),
    /// Greater than zero, else 0x06090032 (a ramp or speed of 0 would never end).
    Positive,
    /// Positive, and only while the power stage is off (0x08000022).
    PositiveWhileOff,
    /// A mode of operation the drive supports (0x6502), else 0x06090030.
    Mode,
}

/// One parameter: where it is, its standard type, its value where the dictionary lacks it, and its
/// rule.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Def {
    pub p: P,
    pub index: u16,
    pub sub: u8,
    pub ty: DataType,
    pub default: i64,
    pub rule: Rule,
}

/// The homing methods the drive runs (0 is accepted and ends a start with a homing error).
pub(crate) const HOMING_METHODS: &[i64] = &[
    0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27,
    28, 29, 30, 33, 34, 35, 37,
];

const fn def(p: P, index: u16, sub: u8, ty: DataType, default: i64, rule: Rule) -> Def {
    Def {
        p,
        index,
        sub,
        ty,
        default,
        rule,
    }
}

use DataType::{Integer16 as I16, Integer32 as I32, Integer8 as I8};
use DataType::{Unsigned16 as U16, Unsigned32 as U32, Unsigned8 as U8};

/// The parameters, in the order of [`P`]. Defaults are those this drive takes where the dictionary
/// lacks the object (CiA 402-2 gives most of them as manufacturer-specific): option codes as the
/// standard's preferred values, windows off, limits wide open, 1 rev/s profiles.
pub(crate) const DEFS: [Def; 44] = [
    def(P::ControlWord, 0x6040, 0, U16, 0, Rule::Any),
    def(P::QuickStopOption, 0x605A, 0, I16, 2, Rule::Range(0, 8)),
    def(P::ShutdownOption, 0x605B, 0, I16, 0, Rule::Range(0, 1)),
    def(
        P::DisableOperationOption,
        0x605C,
        0,
        I16,
        1,
        Rule::Range(0, 1),
    ),
    def(P::HaltOption, 0x605D, 0, I16, 1, Rule::Range(1, 4)),
    def(P::FaultReactionOption, 0x605E, 0, I16, 2, Rule::Range(0, 4)),
    def(P::Mode, 0x6060, 0, I8, 0, Rule::Mode),
    def(P::FollowingWindow, 0x6065, 0, U32, 0xFFFF_FFFF, Rule::Any),
    def(P::FollowingTimeout, 0x6066, 0, U16, 0, Rule::Any),
    def(P::PositionWindow, 0x6067, 0, U32, 0xFFFF_FFFF, Rule::Any),
    def(P::PositionWindowTime, 0x6068, 0, U16, 0, Rule::Any),
    def(P::VelocityWindow, 0x606D, 0, U16, 10, Rule::Any),
    def(P::VelocityWindowTime, 0x606E, 0, U16, 0, Rule::Any),
    def(P::VelocityThreshold, 0x606F, 0, U16, 10, Rule::Any),
    def(P::VelocityThresholdTime, 0x6070, 0, U16, 0, Rule::Any),
    def(P::TargetTorque, 0x6071, 0, I16, 0, Rule::Any),
    def(P::MaxTorque, 0x6072, 0, U16, 3000, Rule::Any),
    def(P::RatedTorque, 0x6076, 0, U32, 1000, Rule::Positive),
    def(P::TargetPosition, 0x607A, 0, I32, 0, Rule::Any),
    def(P::HomeOffset, 0x607C, 0, I32, 0, Rule::Any),
    def(
        P::MinPositionLimit,
        0x607D,
        1,
        I32,
        i32::MIN as i64,
        Rule::Any,
    ),
    def(
        P::MaxPositionLimit,
        0x607D,
        2,
        I32,
        i32::MAX as i64,
        Rule::Any,
    ),
    def(
        P::MaxProfileVelocity,
        0x607F,
        0,
        U32,
        0xFFFF_FFFF,
        Rule::Any,
    ),
    def(P::MaxMotorSpeed, 0x6080, 0, U32, 0xFFFF_FFFF, Rule::Any),
    def(P::ProfileVelocity, 0x6081, 0, U32, 10_000, Rule::Any),
    def(
        P::ProfileAcceleration,
        0x6083,
        0,
        U32,
        100_000,
        Rule::Positive,
    ),
    def(
        P::ProfileDeceleration,
        0x6084,
        0,
        U32,
        100_000,
        Rule::Positive,
    ),
    def(
        P::QuickStopDeceleration,
        0x6085,
        0,
        U32,
        1_000_000,
        Rule::Positive,
    ),
    def(P::MotionProfileType, 0x6086, 0, I16, 0, Rule::OneOf(&[0])),
    def(
        P::EncoderIncrements,
        0x608F,
        1,
        U32,
        10_000,
        Rule::PositiveWhileOff,
    ),
    def(
        P::MotorRevolutions,
        0x608F,
        2,
        U32,
        1,
        Rule::PositiveWhileOff,
    ),
    // A drive with homing mode but no 0x6098 has a fixed method: the current position is home
    // (method 35), which needs nothing of the machine.
    def(
        P::HomingMethod,
        0x6098,
        0,
        I8,
        35,
        Rule::OneOf(HOMING_METHODS),
    ),
    def(P::HomingSpeedSwitch, 0x6099, 1, U32, 5_000, Rule::Positive),
    def(P::HomingSpeedZero, 0x6099, 2, U32, 1_000, Rule::Positive),
    def(
        P::HomingAcceleration,
        0x609A,
        0,
        U32,
        100_000,
        Rule::Positive,
    ),
    def(P::PositionOffset, 0x60B0, 0, I32, 0, Rule::Any),
    def(P::VelocityOffset, 0x60B1, 0, I32, 0, Rule::Any),
    def(P::TorqueOffset, 0x60B2, 0, I16, 0, Rule::Any),
    def(P::InterpolationUnits, 0x60C2, 1, U8, 1, Rule::Any),
    def(P::InterpolationIndex, 0x60C2, 2, I8, -3, Rule::Any),
    def(
        P::MaxAcceleration,
        0x60C5,
        0,
        U32,
        0xFFFF_FFFF,
        Rule::Positive,
    ),
    def(
        P::MaxDeceleration,
        0x60C6,
        0,
        U32,
        0xFFFF_FFFF,
        Rule::Positive,
    ),
    def(P::PositioningOption, 0x60F2, 0, U16, 0, Rule::Any),
    def(P::TargetVelocity, 0x60FF, 0, I32, 0, Rule::Any),
];

/// The process values the drive computes, with their standard types.
pub(crate) const PROCESS: [(u16, DataType); 13] = [
    (0x603F, U16),
    (0x6041, U16),
    (0x6061, I8),
    (0x6062, I32),
    (0x6063, I32),
    (0x6064, I32),
    (0x606B, I32),
    (0x606C, I32),
    (0x6074, I16),
    (0x6077, I16),
    (0x60F4, I32),
    (0x60FC, I32),
    (0x60FD, U32),
];

/// The modes of operation this drive implements, as 0x6502 bits (bit `mode − 1`): profile
/// position (1), profile velocity (3), homing (6), cyclic synchronous position (8), velocity (9)
/// and torque (10).
pub const IMPLEMENTED_MODES: u32 = 1 << 0 | 1 << 2 | 1 << 5 | 1 << 7 | 1 << 8 | 1 << 9;

/// The drive's copy of its parameters: values, whether the dictionary has each, and its type there.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Params {
    values: [i64; DEFS.len()],
    present: [bool; DEFS.len()],
    types: [DataType; DEFS.len()],
    /// Counts per revolution (0x608F:01 / 0x608F:02, at least 1), which scales the defaults of the
    /// speeds and ramps ([`default_at`]).
    cpr: i64,
}

/// The counts per revolution the [`DEFS`] defaults of speeds and ramps are given at.
pub(crate) const DEFAULTS_CPR: i64 = 10_000;

/// The default of `p` for an encoder of `cpr` counts per revolution: a speed or ramp is given in
/// revolutions (1 rev/s profile velocity, 10 rev/s² profile ramps, 100 rev/s² quick stop, homing at
/// 0.5 and 0.1 rev/s with 10 rev/s²; [`DEFS`] has them at [`DEFAULTS_CPR`]), so that a motor of any
/// resolution moves as fast; at least 1. Every other default is [`DEFS`]'s.
pub(crate) fn default_at(p: P, cpr: i64) -> i64 {
    let d = DEFS[p as usize].default;
    match p {
        P::ProfileVelocity
        | P::ProfileAcceleration
        | P::ProfileDeceleration
        | P::QuickStopDeceleration
        | P::HomingSpeedSwitch
        | P::HomingSpeedZero
        | P::HomingAcceleration => (d.saturating_mul(cpr.max(1)) / DEFAULTS_CPR).max(1),
        _ => d,
    }
}

impl Params {
    /// The parameters of the axis whose objects start at `base` (0x6000 + 0x800 · axis): the
    /// dictionary's current values, the defaults (and the motor's configuration for 0x6072, 0x6076
    /// and 0x608F) where it lacks an object. A dictionary value of 0 for 0x6072, 0x6076 or 0x608F
    /// (an EDS entry without a default) also leaves the motor's configuration.
    pub fn load(dict: &Dictionary, base: u16, motor: &MotorConfig) -> Params {
        let mut values = [0i64; DEFS.len()];
        let mut present = [false; DEFS.len()];
        let mut types = [U8; DEFS.len()];
        for (i, d) in DEFS.iter().enumerate() {
            debug_assert_eq!(d.p as usize, i);
            values[i] = match d.p {
                P::MaxTorque => i64::from(motor.peak_torque_permille),
                P::RatedTorque => (motor.rated_torque * 1000.0).round() as i64,
                P::EncoderIncrements => i64::from(motor.counts_per_rev),
                _ => d.default,
            };
            types[i] = d.ty;
            let Ok(entry) = dict.entry(at(base, d.index), d.sub) else {
                continue;
            };
            present[i] = true;
            types[i] = entry.data_type;
            let value = entry
                .current()
                .and_then(|v| v.as_i128())
                .and_then(|v| i64::try_from(v).ok());
            if let Some(v) = value {
                let keep_config = matches!(
                    d.p,
                    P::MaxTorque | P::RatedTorque | P::EncoderIncrements | P::MotorRevolutions
                ) && v <= 0;
                if !keep_config {
                    values[i] = v;
                }
            }
        }
        let cpr = (values[P::EncoderIncrements as usize]
            / values[P::MotorRevolutions as usize].max(1))
        .max(1);
        for (i, d) in DEFS.iter().enumerate() {
            if !present[i] {
                values[i] = match d.p {
                    P::MaxTorque | P::RatedTorque | P::EncoderIncrements => values[i],
                    p => default_at(p, cpr),
                };
            }
        }
        Params {
            values,
            present,
            types,
            cpr,
        }
    }

    /// The value of `p`.
    pub fn get(&self, p: P) -> i64 {
        self.values[p as usize]
    }

    /// Whether the dictionary has `p`.
    pub fn present(&self, p: P) -> bool {
        self.present[p as usize]
    }

    pub fn set(&mut self, p: P, v: i64) {
        self.values[p as usize] = v;
    }

    /// A rate or speed (> 0): the value, or the default at the encoder's resolution where it is
    /// not positive.
    pub fn positive(&self, p: P) -> f64 {
        let v = self.get(p);
        if v > 0 {
            v as f64
        } else {
            default_at(p, self.cpr) as f64
        }
    }

    /// The value of `p` as an unsigned 32-bit quantity (a window, a limit).
    pub fn unsigned(&self, p: P) -> u64 {
        u64::try_from(self.get(p)).unwrap_or(0)
    }
}

/// The index of standard object `index` for the axis whose objects start at `base`.
pub(crate) const fn at(base: u16, index: u16) -> u16 {
    index - 0x6000 + base
}

/// The 0x6502 bits a dictionary declares for the axis at `base`: its 0x6502, or where it has none,
/// the modes whose objects it has (pp: 0x607A and 0x6081; pv: 0x60FF and 0x6083; hm: 0x6098; csp:
/// 0x607A and 0x60C2; csv: 0x60FF and 0x60C2; cst: 0x6071 and 0x60C2; with `sync_clock` the
/// cyclic ones without 0x60C2).
pub(crate) fn declared_modes(dict: &Dictionary, base: u16, sync_clock: bool) -> u32 {
    let has = |index: u16| dict.object(at(base, index)).is_some();
    if let Ok(entry) = dict.entry(at(base, 0x6502), 0) {
        // An entry without a value (an ESI object without `DefaultData`, an EDS entry without a
        // default: 0) declares nothing: the objects the dictionary has tell the modes, as without
        // 0x6502.
        if let Some(v) = entry
            .current()
            .and_then(|v| v.as_i128())
            .filter(|v| *v != 0)
        {
            return v as u32;
        }
    }
    let mut bits = 0;
    let mut add = |mode: u32, ok: bool| {
        if ok {
            bits |= 1 << (mode - 1);
        }
    };
    add(1, has(0x607A) && has(0x6081));
    add(3, has(0x60FF) && has(0x6083));
    add(6, has(0x6098));
    // The cyclic modes take their period from 0x60C2, or from the network's SYNC clock.
    let period = has(0x60C2) || sync_clock;
    add(8, has(0x607A) && period);
    add(9, has(0x60FF) && period);
    add(10, has(0x6071) && period);
    bits
}

/// The little-endian bytes of `value` as a `ty` into `out`; `None` for a type that is no integer of
/// at most 8 bytes.
fn encode(value: i64, ty: DataType, out: &mut [u8; 8]) -> Option<usize> {
    if !(ty.is_signed() || ty.is_unsigned()) {
        return None;
    }
    let n = ty.byte_size()?.min(8);
    out[..n].copy_from_slice(&value.to_le_bytes()[..n]);
    Some(n)
}

impl Drive {
    /// The standard index (0x6000-based) of an index of this axis, if it is in the axis's range.
    pub(crate) fn standard_index(&self, index: u16) -> Option<u16> {
        let base = self.base();
        (index >= base && index - base < 0x800).then(|| index - base + 0x6000)
    }

    /// The parameter at standard `index:sub`.
    fn param_at(index: u16, sub: u8) -> Option<&'static Def> {
        DEFS.iter().find(|d| d.index == index && d.sub == sub)
    }

    /// The current value of a process object (standard index).
    fn process_value(&self, index: u16) -> Option<i64> {
        Some(match index {
            0x603F => i64::from(self.error_code),
            0x6041 => i64::from(self.status_word()),
            0x6061 => i64::from(self.mode),
            0x6062 | 0x60FC => self.position_demand(),
            0x6063 | 0x6064 => self.position(),
            0x606B => self.velocity_demand(),
            0x606C => self.velocity(),
            0x6074 | 0x6077 => i64::from(self.torque()),
            0x60F4 => self.following_error(),
            0x60FD => i64::from(self.digital_inputs()),
            _ => return None,
        })
    }

    /// The drive's own checks of `value` for `def`.
    fn check_param(&self, def: &Def, value: i64) -> Result<(), AbortCode> {
        match def.rule {
            Rule::Any => Ok(()),
            Rule::Range(lo, _) if value < lo => Err(AbortCode::ValueTooLow),
            Rule::Range(_, hi) if value > hi => Err(AbortCode::ValueTooHigh),
            Rule::Range(..) => Ok(()),
            Rule::OneOf(values) if values.contains(&value) => Ok(()),
            Rule::OneOf(_) => Err(AbortCode::InvalidValue),
            Rule::Positive if value <= 0 => Err(AbortCode::ValueTooLow),
            Rule::Positive => Ok(()),
            Rule::PositiveWhileOff if self.powered() => Err(AbortCode::DeviceState),
            Rule::PositiveWhileOff if value <= 0 => Err(AbortCode::ValueTooLow),
            Rule::PositiveWhileOff => Ok(()),
            Rule::Mode if self.mode_supported(value) => Ok(()),
            Rule::Mode => Err(AbortCode::InvalidValue),
        }
    }

    /// Whether 0x6060 may take `mode`: 0 (no mode), or an implemented mode 0x6502 declares (not
    /// cyclic synchronous torque on a stepper).
    pub(crate) fn mode_supported(&self, mode: i64) -> bool {
        if mode == 0 {
            return true;
        }
        if !(1..=10).contains(&mode) {
            return false;
        }
        if mode == 10 && self.config.motor.kind == MotorKind::Stepper {
            return false;
        }
        self.supported & (1 << (mode - 1)) != 0
    }

    /// A mode of operation written without a check (the process data) and refused: the line that
    /// says why.
    fn report_refused_mode(&mut self, data: &[u8]) {
        let Some(&mode) = data.first() else {
            return;
        };
        let mode = i64::from(mode as i8);
        let text = format!(
            "{} = {mode} refused: the modes the drive runs are {:#010X} (bit mode − 1, as in {})",
            self.name(0x6060, 0),
            self.supported,
            self.name(0x6502, 0)
        );
        let object = Some(self.own(0x6502, 0));
        self.report(
            super::limits::Kind::Mode,
            object,
            mode as f64,
            f64::from(self.supported),
            text,
        );
    }

    /// Why a write of `data` to this axis's entry `at` is refused, as the drive's log says it: the
    /// abort code and the line (`axis 0: 0x6083 = 0 refused with 0x06090032 (…): it must be above
    /// 0: a ramp or speed of 0 would never end`); `None` where the drive's rules take it (the
    /// dictionary's own checks, its type and limits, come on top).
    pub fn refusal(&self, at: Address, data: &[u8]) -> Option<(AbortCode, String)> {
        let index = self.standard_index(at.index)?;
        let def = Drive::param_at(index, at.sub)?;
        let code = self.decode_param(def, data).err()?;
        self.refusal_line(def, data, code).map(|line| (code, line))
    }

    /// The line that says why a write of `data` to `def` was refused with `code`: the axis, the
    /// object, the value, the abort code and the rule.
    fn refusal_line(&self, def: &Def, data: &[u8], code: AbortCode) -> Option<String> {
        let ty = self.params.types[def.p as usize];
        let value = Value::decode(ty, data).ok().and_then(|v| v.as_i128())?;
        let object = self.name(def.index, def.sub);
        let rule = match def.rule {
            Rule::Range(lo, hi) => format!("this drive takes {lo} to {hi}"),
            Rule::OneOf(_) if def.p == P::HomingMethod => {
                "a homing method this drive does not run".to_string()
            }
            Rule::OneOf(values) => format!("this drive takes only {values:?}"),
            Rule::Positive => {
                "it must be above 0: a ramp or speed of 0 would never end".to_string()
            }
            Rule::PositiveWhileOff if self.powered() => {
                "it is written only while the power stage is off".to_string()
            }
            Rule::PositiveWhileOff => "it must be above 0".to_string(),
            Rule::Mode => format!(
                "the modes this drive runs are {:#010X} (bit mode − 1, as in {})",
                self.supported,
                self.name(0x6502, 0)
            ),
            Rule::Any => return None,
        };
        Some(format!(
            "axis {}: {object} = {value} refused with {:#010X} ({}): {rule}",
            self.axis,
            code.code(),
            code.description()
        ))
    }

    /// Says on the log why a write of `data` to `def` was refused with `code`, in one line
    /// ([`Drive::refusal`]; target `ds402::drive`, WARN, with the fields axis, index, value, code).
    fn log_refusal(&self, def: &Def, data: &[u8], code: AbortCode) {
        let Some(line) = self.refusal_line(def, data, code) else {
            return;
        };
        let value = Value::decode(self.params.types[def.p as usize], data)
            .ok()
            .and_then(|v| v.as_i128())
            .unwrap_or(0);
        tracing::warn!(
            target: "ds402::drive",
            axis = self.axis,
            index = %self.name(def.index, def.sub),
            value = value as f64,
            code = %format_args!("{:#010X}", code.code()),
            "{line}"
        );
    }

    /// Decodes `data` for parameter `def` (in the dictionary's type) and checks it.
    fn decode_param(&self, def: &Def, data: &[u8]) -> Result<i64, AbortCode> {
        let ty = self.params.types[def.p as usize];
        let value = Value::decode(ty, data)
            .ok()
            .and_then(|v| v.as_i128())
            .and_then(|v| i64::try_from(v).ok())
            .ok_or(AbortCode::LengthMismatch)?;
        self.check_param(def, value)?;
        Ok(value)
    }
}

impl DeviceHook for Drive {
    /// The objects of this axis the drive acts on (each 0x800 · axis further on): the process
    /// values 0x603F, 0x6041, 0x6061, 0x6062–0x6064, 0x606B, 0x606C, 0x6074, 0x6077, 0x60F4,
    /// 0x60FC, 0x60FD; the parameters and targets 0x6040, 0x605A–0x605E, 0x6060, 0x6065–0x6068,
    /// 0x606D–0x6072, 0x6076, 0x607A, 0x607C, 0x607D, 0x607F–0x6081, 0x6083–0x6086, 0x608F,
    /// 0x6098–0x609A, 0x60B0–0x60B2, 0x60C2, 0x60C5, 0x60C6, 0x60F2, 0x60FF.
    fn owns(&self, index: u16) -> bool {
        self.standard_index(index).is_some_and(|i| {
            PROCESS.iter().any(|(p, _)| *p == i) || DEFS.iter().any(|d| d.index == i)
        })
    }

    /// Process values as the dictionary's type encodes them; `None` for parameters.
    fn read(&self, at: Address, out: &mut [u8; 8]) -> Option<usize> {
        let index = self.standard_index(at.index)?;
        if at.sub != 0 {
            return None;
        }
        let value = self.process_value(index)?;
        let ty = self
            .process_types
            .iter()
            .find(|(i, _)| *i == index)
            .map(|(_, t)| *t)?;
        encode(value, ty, out)
    }

    /// The drive's own rules, after the dictionary's: process values are read-only (0x06010002);
    /// option codes out of their range (0x06090031 above, 0x06090032 below); a mode of operation
    /// not supported, a homing method not run, a motion profile type other than 0 (0x06090030);
    /// a ramp, speed, rated torque or encoder resolution of 0 (0x06090032); 0x608F with the power
    /// stage on (0x08000022).
    fn check(&self, at: Address, data: &[u8]) -> Result<(), AbortCode> {
        let Some(index) = self.standard_index(at.index) else {
            return Ok(());
        };
        if PROCESS.iter().any(|(p, _)| *p == index) {
            return Err(AbortCode::ReadOnly);
        }
        match Drive::param_at(index, at.sub) {
            Some(def) => self
                .decode_param(def, data)
                .map(|_| ())
                .inspect_err(|code| self.log_refusal(def, data, *code)),
            None => Ok(()),
        }
    }

    /// Takes a value [`check`](DeviceHook::check) accepts (and checks it again: an RPDO is
    /// delivered without a check) and acts on it at `now`, the drive run up to it first: a control
    /// word runs the state machine and the mode's bits, 0x6060 changes the mode, a new 0x60FF
    /// re-ramps pv.
    fn write(&mut self, at: Address, data: &[u8], now: Instant) -> Result<(), AbortCode> {
        let Some(index) = self.standard_index(at.index) else {
            return Ok(());
        };
        if PROCESS.iter().any(|(p, _)| *p == index) {
            return Err(AbortCode::ReadOnly);
        }
        let Some(def) = Drive::param_at(index, at.sub) else {
            return Ok(());
        };
        let value = match self.decode_param(def, data) {
            Ok(value) => value,
            Err(code) => {
                if def.p == P::Mode {
                    self.report_refused_mode(data);
                }
                return Err(code);
            }
        };
        self.input_at(now);
        self.set_param(def.p, value);
        Ok(())
    }
}
