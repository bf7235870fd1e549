//! What a drive of a description reports where the description gives no value, and the factory
//! settings it takes where the description's value would stop it: [`fill`] (its documentation has
//! the picks and the table of factory values).

use od::dict::{Address, Dictionary};
use od::event::{Event, EventKind};
use od::object::{AccessType, Object, SubObject};
use od::types::DataType;
use od::value::Value;

use super::objects::{self, Rule, DEFS, IMPLEMENTED_MODES};
use super::{Drive, DriveConfig, MotorConfig, MotorKind};

/// CiA 402's device profile number (bits 0–15 of 0x1000).
pub const PROFILE_402: u32 = 0x0192;
/// The type of a servo drive (bits 16–23 of 0x1000).
pub const TYPE_SERVO: u32 = 0x02;
/// The type of a stepper motor drive (bits 16–23 of 0x1000).
pub const TYPE_STEPPER: u32 = 0x04;
/// The additional information of a device of several logical devices, several axes (bits 16–31 of
/// 0x1000, CiA 301).
pub const SEVERAL_DEVICES: u32 = 0xFFFF;

/// The device type (0x1000) of a drive of `axes` axes with `motor`s behind them.
pub fn device_type(axes: usize, motor: MotorKind) -> u32 {
    if axes > 1 {
        SEVERAL_DEVICES << 16 | PROFILE_402
    } else {
        axis_type(motor)
    }
}

/// The device type of one axis (0x67FF + 0x800 · axis).
fn axis_type(motor: MotorKind) -> u32 {
    let kind = match motor {
        MotorKind::Servo => TYPE_SERVO,
        MotorKind::Stepper => TYPE_STEPPER,
    };
    kind << 16 | PROFILE_402
}

/// The 0x6502 bits the drive of the axis whose objects start at `base` runs: those the dictionary
/// declares (or whose objects it has), implemented, no cyclic synchronous torque on a stepper.
fn runs(dict: &Dictionary, base: u16, config: &DriveConfig) -> u32 {
    let mut bits = objects::declared_modes(dict, base, config.sync_clock) & IMPLEMENTED_MODES;
    if config.motor.kind == MotorKind::Stepper {
        bits &= !(1 << 9);
    }
    bits
}

/// A factory setting: the standard entry, its name, its unit, what a value of 0 would do, and the
/// value.
struct Factory {
    index: u16,
    sub: u8,
    name: &'static str,
    unit: &'static str,
    zero: &'static str,
    value: fn(&Context<'_>) -> i64,
}

/// What the factory values depend on.
struct Context<'a> {
    motor: &'a MotorConfig,
    /// Counts per revolution (0x608F, once filled).
    cpr: i64,
    /// 0x6080, once filled (rpm).
    max_speed: i64,
    /// 0x607F, once filled (counts/s), where the dictionary has it.
    max_profile: Option<i64>,
}

/// The max motor speed taken where the description gives none (rpm).
const MAX_MOTOR_SPEED: i64 = 3000;

/// The factory settings, in the order they are filled (what 0x607F depends on first).
const FACTORY: [Factory; 17] = [
    Factory {
        index: 0x608F,
        sub: 1,
        name: "encoder increments",
        unit: "counts",
        zero: "gives no position",
        value: |c| i64::from(c.motor.counts_per_rev),
    },
    Factory {
        index: 0x608F,
        sub: 2,
        name: "motor revolutions",
        unit: "rev",
        zero: "gives no position",
        value: |_| 1,
    },
    Factory {
        index: 0x6080,
        sub: 0,
        name: "max motor speed",
        unit: "rpm",
        zero: "would allow no speed",
        value: |_| MAX_MOTOR_SPEED,
    },
    Factory {
        index: 0x607F,
        sub: 0,
        name: "max profile velocity",
        unit: "counts/s",
        zero: "would allow no speed",
        value: |c| c.max_speed.saturating_mul(c.cpr) / 60,
    },
    Factory {
        index: 0x6072,
        sub: 0,
        name: "max torque",
        unit: "‰ of the rated torque",
        zero: "would leave the motor no torque",
        value: |c| i64::from(c.motor.peak_torque_permille),
    },
    Factory {
        index: 0x6073,
        sub: 0,
        name: "max current",
        unit: "‰ of the rated current",
        zero: "would leave the motor no current",
        value: |_| 3000,
    },
    Factory {
        index: 0x6075,
        sub: 0,
        name: "motor rated current",
        unit: "mA",
        zero: "makes every current given in ‰ of it 0",
        value: |_| 3000,
    },
    Factory {
        index: 0x6076,
        sub: 0,
        name: "motor rated torque",
        unit: "mN·m",
        zero: "makes every torque given in ‰ of it 0",
        value: |c| (c.motor.rated_torque * 1000.0).round() as i64,
    },
    Factory {
        index: 0x6081,
        sub: 0,
        name: "profile velocity",
        unit: "counts/s",
        zero: "would stop every profile position move",
        value: |c| {
            let own = objects::default_at(objects::P::ProfileVelocity, c.cpr);
            c.max_profile.map_or(own, |max| max.min(own))
        },
    },
    Factory {
        index: 0x6083,
        sub: 0,
        name: "profile acceleration",
        unit: "counts/s²",
        zero: "would stop every move",
        value: |c| objects::default_at(objects::P::ProfileAcceleration, c.cpr),
    },
    Factory {
        index: 0x6084,
        sub: 0,
        name: "profile deceleration",
        unit: "counts/s²",
        zero: "would stop every move",
        value: |c| objects::default_at(objects::P::ProfileDeceleration, c.cpr),
    },
    Factory {
        index: 0x6085,
        sub: 0,
        name: "quick stop deceleration",
        unit: "counts/s²",
        zero: "would never end a quick stop",
        value: |c| objects::default_at(objects::P::QuickStopDeceleration, c.cpr),
    },
    Factory {
        index: 0x6099,
        sub: 1,
        name: "homing speed during search for switch",
        unit: "counts/s",
        zero: "would never find home",
        value: |c| objects::default_at(objects::P::HomingSpeedSwitch, c.cpr),
    },
    Factory {
        index: 0x6099,
        sub: 2,
        name: "homing speed during search for zero",
        unit: "counts/s",
        zero: "would never find home",
        value: |c| objects::default_at(objects::P::HomingSpeedZero, c.cpr),
    },
    Factory {
        index: 0x609A,
        sub: 0,
        name: "homing acceleration",
        unit: "counts/s²",
        zero: "would never find home",
        value: |c| objects::default_at(objects::P::HomingAcceleration, c.cpr),
    },
    Factory {
        index: 0x60C5,
        sub: 0,
        name: "max acceleration",
        unit: "counts/s²",
        zero: "would stop every move",
        value: |_| i64::from(u32::MAX),
    },
    Factory {
        index: 0x60C6,
        sub: 0,
        name: "max deceleration",
        unit: "counts/s²",
        zero: "would stop every move",
        value: |_| i64::from(u32::MAX),
    },
];

/// The entries with a rule that refuses some values and no factory setting: name and what a refused
/// value is.
const RULED: [(u16, &str, &str); 8] = [
    (0x605A, "quick stop option code", "a code outside 0 to 8"),
    (0x605B, "shutdown option code", "a code outside 0 to 1"),
    (
        0x605C,
        "disable operation option code",
        "a code outside 0 to 1",
    ),
    (0x605D, "halt option code", "a code outside 1 to 4"),
    (
        0x605E,
        "fault reaction option code",
        "a code outside 0 to 4",
    ),
    (
        0x6060,
        "modes of operation",
        "a mode this drive does not run",
    ),
    (
        0x6086,
        "motion profile type",
        "a profile type other than 0, the only one this drive runs",
    ),
    (
        0x6098,
        "homing method",
        "a homing method this drive does not run",
    ),
];

/// Gives the entries of `dict`'s drive axes what a drive of the description, made with `config`,
/// reports where the description gives no value, and the factory settings it runs with where the
/// description's value would stop it; one event per entry changed. Sans-IO: a node calls it on
/// the dictionary before it makes its drives, so that they, the SDO server and a reset all see the
/// same values: each becomes the entry's default ([`SubObject::set_default`]).
///
/// Only a dictionary with drive axes ([`Drive::axes`]) is touched. A description's own value always
/// wins, except where the drive could not run with it (a limit of 0, a code it refuses); of the
/// objects the description lacks, only 0x1000 (mandatory in CiA 301) is added.
///
/// **Reported values** (where the entry exists without a value):
///
/// - 0x1000 device type (CiA 301 §7.5.2.1, CiA 402-2 object 1000h): the profile number 402
///   (0x0192) in bits 0–15; bits 16–23 the type, 0x02 for a servo drive and 0x04 for a stepper motor
///   (as Nanotec's stepper and servo controllers, TI's EtherCAT stack and the UC42 of the corpus
///   report them: `0x00020192`, `0x00040192`); a device of several axes reports 0xFFFF in bits
///   16–31 (CiA 301: several logical devices, each describing itself at 0x67FF + 0x800 · axis,
///   which get the single axis's type where the description has them without a value).
/// - 0x6502 supported drive modes, per axis: the modes this drive runs that the description's
///   objects allow, the set 0x6060 accepts ([`Drive::supported_modes`]), also where the description
///   gives 0 (no mode at all; the drive reads 0 as no value).
///
/// **Factory settings**, where the value is 0 or below (or absent: 0), which would stop the drive
/// (positions in counts, velocities in counts/s, accelerations in counts/s², as the drive counts):
///
/// | object | value | why this one |
/// |---|---|---|
/// | 0x6072 max torque | [`MotorConfig::peak_torque_permille`], 3000 ‰ | the peak torque of the simulated motor |
/// | 0x6073 max current | 3000 ‰ | peak current follows peak torque |
/// | 0x6075 motor rated current | 3000 mA | a 1 N·m servo with a torque constant of ⅓ N·m/A |
/// | 0x6076 motor rated torque | [`MotorConfig::rated_torque`], 1000 mN·m | the simulated motor's |
/// | 0x6080 max motor speed | 3000 rpm | a common servo motor's maximum |
/// | 0x607F max profile velocity | 0x6080 × counts per revolution / 60 | the motor's maximum in counts/s (500,000 at 10,000 counts/rev) |
/// | 0x6081 profile velocity | 1 rev/s (10,000 counts/s at 10,000 counts/rev), at most 0x607F | the drive's default |
/// | 0x6083, 0x6084 profile acceleration, deceleration | 10 rev/s² (100,000 counts/s²) | the drive's default |
/// | 0x6085 quick stop deceleration | 100 rev/s² (1,000,000 counts/s²) | the drive's default: a stop from full speed in 0.5 s |
/// | 0x608F:01, :02 encoder increments, motor revolutions | [`MotorConfig::counts_per_rev`], 1 | the simulated encoder |
/// | 0x6099:01, :02 homing speeds | 0.5 and 0.1 rev/s (5,000 and 1,000 counts/s) | the drive's defaults |
/// | 0x609A homing acceleration | 10 rev/s² (100,000 counts/s²) | the drive's default |
/// | 0x60C5, 0x60C6 max acceleration, deceleration | 4,294,967,295 (the type's largest) | no limit beyond the profile's, as many drives ship |
///
/// Speeds and ramps are given in revolutions, at the encoder's counts per revolution (0x608F:01 /
/// 0x608F:02, once filled; the figures in brackets at 10,000 counts/rev), at least 1: a coarse
/// encoder (python-canopen's cog.eds gives 1 count per revolution) moves as fast as a fine one.
///
/// A value is held to the entry's type and limits; one that cannot be made positive so is left.
///
/// **Values the drive would refuse written back.** A value a device reports must be accepted when a
/// master writes it back (`sdo-tool dump`, then `apply`, of an untouched drive). The drive's own
/// rules refuse 0 for the ramps and speeds above (hence the factory settings), option codes outside
/// their ranges (0x605A 0–8, 0x605B and 0x605C 0–1, 0x605D 1–4, 0x605E 0–4; a 0x605D without a value
/// is 0), a mode it does not run in 0x6060 (Pilz's PRBT DCF gives 7, interpolated position), a
/// motion profile type other than 0 (0x6086) and a homing method it does not run (0x6098): such a
/// value is replaced by the drive's default (0 for 0x6060: the drive starts with no mode, as it did
/// with the refused one), and said.
pub fn fill(dict: &mut Dictionary, config: &DriveConfig) -> Vec<Event> {
    let axes = Drive::axes(dict);
    let mut events = Vec::new();
    if axes.is_empty() {
        return events;
    }
    device_types(dict, &axes, config.motor.kind, &mut events);
    for &axis in &axes {
        let base = 0x6000 + 0x800 * u16::from(axis);
        let named = |name: &str| {
            if axis == 0 {
                name.to_string()
            } else {
                format!("{name} (axis {})", axis + 1)
            }
        };
        supported_modes(dict, base, config, &named(""), &mut events);
        factory(dict, base, config, &named, &mut events);
        ruled(dict, base, config, &named, &mut events);
    }
    events
}

/// The given value of an entry that has one: `Some(None)` without a value, `Some(Some(v))` with
/// one, `None` for no such entry (or one that is no integer).
fn given(dict: &Dictionary, at: Address) -> Option<Option<i64>> {
    let entry = dict.entry(at.index, at.sub).ok()?;
    if !(entry.data_type.is_signed() || entry.data_type.is_unsigned()) {
        return None;
    }
    if !entry.has_value() {
        return Some(None);
    }
    let v = entry.current()?.as_i128()?;
    Some(Some(i64::try_from(v).ok()?))
}

/// Makes `value` the default of the entry at `at`; false when the entry cannot hold it.
fn set(dict: &mut Dictionary, at: Address, value: i64) -> bool {
    let Some(entry) = dict
        .object_mut(at.index)
        .and_then(|o| o.subs.get_mut(&at.sub))
    else {
        return false;
    };
    let value = if entry.data_type.is_signed() {
        Value::Int(value)
    } else {
        match u64::try_from(value) {
            Ok(v) => Value::Uint(v),
            Err(_) => return false,
        }
    };
    entry.set_default(value)
}

/// 0x1000, and 0x67FF + 0x800 · axis.
fn device_types(dict: &mut Dictionary, axes: &[u8], motor: MotorKind, events: &mut Vec<Event>) {
    let what = match motor {
        MotorKind::Servo => "a CiA 402 servo drive",
        MotorKind::Stepper => "a CiA 402 stepper motor drive",
    };
    let value = device_type(axes.len(), motor);
    let about = if axes.len() > 1 {
        format!(
            "{what} of {} axes (0xFFFF: several logical devices, each describing itself at 0x67FF + 0x800 · axis)",
            axes.len()
        )
    } else {
        what.to_string()
    };
    let at = Address::new(0x1000, 0);
    let why = match given(dict, at) {
        None if dict.object(0x1000).is_none() => {
            let entry = SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro)
                .with_default(Value::Uint(u64::from(value)));
            dict.insert(Object::var(0x1000, entry));
            Some("the description has no 0x1000, which CiA 301 makes mandatory")
        }
        Some(None) => set(dict, at, i64::from(value)).then_some("the description gives no value"),
        _ => None,
    };
    if let Some(why) = why {
        events.push(Event::hex(
            EventKind::Filled,
            at,
            "device type",
            value,
            format!("{why}: {about}"),
        ));
    }
    if axes.len() < 2 {
        return;
    }
    for &axis in axes {
        let at = Address::new(0x67FF + 0x800 * u16::from(axis), 0);
        if given(dict, at) == Some(None) && set(dict, at, i64::from(axis_type(motor))) {
            events.push(Event::hex(
                EventKind::Filled,
                at,
                &format!("device type of axis {}", axis + 1),
                axis_type(motor),
                format!("the description gives no value: {what}"),
            ));
        }
    }
}

fn number_event(
    kind: EventKind,
    at: Address,
    name: String,
    value: i64,
    unit: Option<&str>,
    reason: String,
) -> Event {
    Event {
        kind,
        address: at,
        name,
        value: Value::Int(value),
        shown: value.to_string(),
        unit: unit.map(str::to_string),
        reason,
    }
}

/// 0x6502 of the axis at `base` (`suffix`: the axis, for its name).
fn supported_modes(
    dict: &mut Dictionary,
    base: u16,
    config: &DriveConfig,
    suffix: &str,
    events: &mut Vec<Event>,
) {
    let at = Address::new(objects::at(base, 0x6502), 0);
    let (kind, reason) = match given(dict, at) {
        Some(None) => (EventKind::Filled, "the description gives no value"),
        Some(Some(0)) => (
            EventKind::Adjusted,
            "the description gives 0, no mode at all",
        ),
        _ => return,
    };
    // Without a value the drive takes the modes from the objects: the same bits.
    let bits = runs(dict, base, config);
    if bits == 0 || !set(dict, at, i64::from(bits)) {
        return;
    }
    events.push(Event::hex(
        kind,
        at,
        &format!("supported drive modes{suffix}"),
        bits,
        format!("{reason}: the modes this drive runs whose objects it has"),
    ));
}

/// The factory settings of the axis at `base`.
fn factory(
    dict: &mut Dictionary,
    base: u16,
    config: &DriveConfig,
    named: &dyn Fn(&str) -> String,
    events: &mut Vec<Event>,
) {
    for f in &FACTORY {
        let at = Address::new(objects::at(base, f.index), f.sub);
        let (kind, was) = match given(dict, at) {
            Some(None) => (EventKind::Filled, "no value (0)".to_string()),
            Some(Some(v)) if v <= 0 => (EventKind::Adjusted, v.to_string()),
            _ => continue,
        };
        let positive = |index: u16, sub: u8| {
            given(dict, Address::new(objects::at(base, index), sub))
                .flatten()
                .filter(|v| *v > 0)
        };
        let cpr = match (positive(0x608F, 1), positive(0x608F, 2)) {
            (Some(inc), Some(rev)) => (inc / rev).max(1),
            _ => i64::from(config.motor.counts_per_rev),
        };
        let context = Context {
            motor: &config.motor,
            cpr,
            max_speed: positive(0x6080, 0).unwrap_or(MAX_MOTOR_SPEED),
            max_profile: positive(0x607F, 0),
        };
        let Some(value) = fitting(dict, at, (f.value)(&context)) else {
            continue;
        };
        if set(dict, at, value) {
            events.push(number_event(
                kind,
                at,
                named(f.name),
                value,
                Some(f.unit),
                format!(
                    "the description gives {was}, which {}: a factory default",
                    f.zero
                ),
            ));
        }
    }
}

/// `value` held to the type and the limits of the entry at `at`, when that leaves it positive.
fn fitting(dict: &Dictionary, at: Address, value: i64) -> Option<i64> {
    let entry = dict.entry(at.index, at.sub).ok()?;
    let (_, type_max) = entry.data_type.integer_range()?;
    let mut v = i128::from(value).min(type_max);
    if let Some(high) = entry.high.as_ref().and_then(Value::as_i128) {
        v = v.min(high);
    }
    if let Some(low) = entry.low.as_ref().and_then(Value::as_i128) {
        if v < low {
            return None;
        }
    }
    (v > 0).then(|| i64::try_from(v).ok()).flatten()
}

/// The entries of the axis at `base` whose value the drive's rules refuse.
fn ruled(
    dict: &mut Dictionary,
    base: u16,
    config: &DriveConfig,
    named: &dyn Fn(&str) -> String,
    events: &mut Vec<Event>,
) {
    let modes = runs(dict, base, config);
    for (index, name, refused) in RULED {
        let Some(def) = DEFS.iter().find(|d| d.index == index && d.sub == 0) else {
            continue;
        };
        let at = Address::new(objects::at(base, index), 0);
        let (kind, was, value) = match given(dict, at) {
            Some(None) => (EventKind::Filled, "no value (0)".to_string(), 0),
            Some(Some(v)) => (EventKind::Adjusted, v.to_string(), v),
            None => continue,
        };
        if accepts(def.rule, value, modes, config.motor.kind) {
            continue;
        }
        let default = if def.rule == Rule::Mode {
            0
        } else {
            def.default
        };
        if set(dict, at, default) {
            events.push(number_event(
                kind,
                at,
                named(name),
                default,
                None,
                format!("the description gives {was}, {refused}, which it refuses: its default"),
            ));
        }
    }
}

/// Whether the drive takes `value` under `rule` at power-on (power stage off) with `modes` supported
/// — the drive's own check of a write, as `objects` makes it.
fn accepts(rule: Rule, value: i64, modes: u32, motor: MotorKind) -> bool {
    match rule {
        Rule::Any => true,
        Rule::Range(lo, hi) => (lo..=hi).contains(&value),
        Rule::OneOf(values) => values.contains(&value),
        Rule::Positive | Rule::PositiveWhileOff => value > 0,
        Rule::Mode => {
            value == 0
                || ((1..=10).contains(&value)
                    && !(value == 10 && motor == MotorKind::Stepper)
                    && modes & (1 << (value - 1)) != 0)
        }
    }
}

#[cfg(test)]
mod tests {
    use std::time::Instant;

    use od::hook::DeviceHook;

    use super::*;

    /// The drive's own checks and [`accepts`] agree on every parameter with a rule, for values
    /// around each rule's edges.
    #[test]
    fn accepts_is_the_drive_s_own_check() {
        for motor in [MotorKind::Servo, MotorKind::Stepper] {
            let mut dict = Dictionary::new();
            for (index, ty) in [
                (0x6040u16, DataType::Unsigned16),
                (0x6041, DataType::Unsigned16),
            ] {
                dict.insert(Object::var(index, SubObject::new("x", ty, AccessType::Rw)));
            }
            let modes = 0b10_1010_0101u32; // pp, pv, hm, csp, cst
            dict.insert(Object::var(
                0x6502,
                SubObject::new("m", DataType::Unsigned32, AccessType::Ro)
                    .with_default(Value::Uint(u64::from(modes))),
            ));
            let mut config = DriveConfig::default();
            config.motor.kind = motor;
            let drive = Drive::from_dictionary(&dict, 0, config, Instant::now()).unwrap();
            for def in &DEFS {
                for v in [
                    -129i64, -2, -1, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 15, 35, 36, 127,
                ] {
                    if def
                        .ty
                        .integer_range()
                        .is_none_or(|(lo, hi)| i128::from(v) < lo || i128::from(v) > hi)
                    {
                        continue;
                    }
                    let bytes = &v.to_le_bytes()[..def.ty.byte_size().unwrap()];
                    let at = Address::new(def.index, def.sub);
                    assert_eq!(
                        accepts(def.rule, v, drive.supported_modes(), motor),
                        drive.check(at, bytes).is_ok(),
                        "0x{:04X}:{} = {v} ({motor:?})",
                        def.index,
                        def.sub
                    );
                }
            }
        }
    }
}
