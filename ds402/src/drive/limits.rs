//! The drive's limits in the cyclic synchronous modes, and the line it logs when one of them (or a
//! fault it raises, or a refusal) holds it back.
//!
//! # The demand within the drive's limits
//!
//! In csp and csv the master's set-points make a reference: the straight lines between the targets
//! of consecutive SYNCs (csp), or the velocity ramps between them (csv) (see
//! [`Drive::sync`](super::Drive::sync)). The drive's demand (0x6062, 0x606B) *is* that reference
//! while each step of it is within the drive's limits:
//!
//! - velocity: 0x607F max profile velocity and 0x6080 max motor speed (rpm, at the encoder's
//!   counts per revolution), the lower of the two;
//! - acceleration: 0x60C5 max acceleration while the speed grows, 0x60C6 max deceleration while it
//!   falls; and what the motor can give at all: 90 % of the torque limit (servo: 0x6072 per mille
//!   of 0x6076; stepper: its pull-out torque) less the load torque and, while speeding up, the
//!   friction at the present speed, over the rotor and load inertia. A motor whose torque limit
//!   does not exceed its load takes no such limit (it cannot move the load at all; the following
//!   error shows it).
//!
//! A step beyond them is not followed: from there the demand runs after the reference within the
//! limits ([`track`]), a time-optimal approach (braking curve `v² = 2·a·d` to the reference,
//! discretised so that it lands on it exactly: the last two ticks are solved in closed form), and
//! follows the reference again from the tick it is back on it. The demand never asks the motor for
//! more than it can give, so a servo never runs into its torque limit (which would leave its
//! controller to recover from saturation) and a stepper never loses a step: once the set-points
//! stand, the drive stands exactly at the last one.
//!
//! cst takes 0x6071 + 0x60B2 within ±0x6072.
//!
//! # What the drive says
//!
//! Each limit that holds the drive back, each fault it raises itself, and each value it refuses
//! from the process data is a [`Limited`]: one line naming the axis, the object, the value asked for
//! and the limit, e.g. `axis 0: csp target step of 100 counts/cycle needs 100,000 counts/s, above
//! 0x607F = 8,000 counts/s`. The drive logs it through `tracing` (target `ds402::drive`, level
//! WARN, fields `axis`, `index`, `value`, `limit`) the moment it first happens, once per kind of
//! limit until the mode starts again (Operation enabled entered, a mode change, a halt released),
//! and keeps the last 32 for [`Drive::poll_limit`].

use std::fmt;

use crate::cia402::State;

use super::objects::P;
use super::{Demand, Drive, Motion, MotorKind};

/// How many [`Limited`] the drive keeps for [`Drive::poll_limit`].
const KEPT: usize = 32;

/// Share of the torque the demand may ask for acceleration; the rest is the controller's.
const MARGIN: f64 = 0.9;

/// A limit that held the drive back, a fault it raised, or a value it refused, as the drive logs it
/// (through `tracing`, target `ds402::drive`, level WARN, the moment it first happens: once per kind
/// until the mode starts again) and keeps it for [`Drive::poll_limit`]. In csp and csv a step of the
/// set-points beyond the drive's limits (0x607F, 0x6080, 0x60C5, 0x60C6, and the acceleration 90 %
/// of the motor's torque gives) is not followed: the demand runs after the set-points within them
/// and lands on them exactly.
#[derive(Clone, Debug, PartialEq)]
pub struct Limited {
    /// The axis (0..8).
    pub axis: u8,
    /// The object whose value is the limit (the axis's own index), or `None` for the motor's own
    /// (a stepper's pull-out torque).
    pub object: Option<(u16, u8)>,
    /// What was asked for, in the unit of the line.
    pub value: f64,
    /// What the limit allows, in the same unit.
    pub limit: f64,
    /// The line.
    pub message: String,
}

impl fmt::Display for Limited {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

/// The kinds of limit, each logged once until the mode starts again.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum Kind {
    CspVelocity,
    CspAcceleration,
    CsvVelocity,
    CsvAcceleration,
    CstTorque,
    PositionLimit,
    FollowingError,
    LimitSwitch,
    Mode,
    TorqueLimit,
    PullOut,
}

/// The bounds of the demand: velocity, acceleration while the speed grows, deceleration while it
/// falls (counts/s, counts/s²; infinite where there is none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Bounds {
    pub vmax: f64,
    pub acc: f64,
    pub dec: f64,
}

/// The velocity one tick of `dt` s after `v0`, as close to `v1` as `acc` (the speed growing) and
/// `dec` (the speed falling, down to 0) allow.
pub(crate) fn change(v0: f64, v1: f64, acc: f64, dec: f64, dt: f64) -> f64 {
    if v1 == v0 {
        return v1;
    }
    let falling = (v0 > 0.0 && v1 < v0) || (v0 < 0.0 && v1 > v0);
    if falling {
        // Towards 0 at `dec`; through 0 the speed grows again, at `acc` for the rest of the tick.
        let through = v1 != 0.0 && v1.signum() != v0.signum();
        let to_zero = v0.abs() / dec;
        if !through || to_zero >= dt {
            let step = dec * dt;
            if (v0 - v1).abs() <= step {
                return v1;
            }
            return v0 - step.copysign(v0);
        }
        let rest = acc * (dt - to_zero);
        return if v1.abs() <= rest {
            v1
        } else {
            rest.copysign(v1)
        };
    }
    let step = acc * dt;
    if (v1 - v0).abs() <= step {
        v1
    } else {
        v0 + step.copysign(v1 - v0)
    }
}

/// Whether the demand at velocity `v` can take the reference's velocity `rv` at the next tick.
pub(crate) fn follows(v: f64, rv: f64, b: &Bounds, dt: f64) -> bool {
    rv.abs() <= b.vmax && change(v, rv, b.acc, b.dec, dt) == rv
}

/// One tick of `dt` s of a demand at `p`, `v` running after a reference that is at `rp` with
/// velocity `rv` at the end of the tick (and goes on at `rv`), within `b`: the demand at the end of
/// the tick, and whether it is back on the reference (then exactly `rp`, `rv`).
pub(crate) fn track(p: f64, v: f64, rp: f64, rv: f64, b: &Bounds, dt: f64) -> (f64, f64, bool) {
    // Relative to the reference as it was at the start of the tick.
    let x = p - (rp - rv * dt);
    let y = v - rv;
    let tolerance = 1e-6 + 1e-12 * rp.abs();
    if (x + y * dt / 2.0).abs() <= tolerance && follows(v, rv, b, dt) {
        return (rp, rv, true);
    }
    let a = b.acc.min(b.dec);
    let feasible = |y1: f64| {
        let v1 = rv + y1;
        v1.abs() <= b.vmax
            && change(v, v1, b.acc, b.dec, dt) == v1
            && change(v1, rv, b.acc, b.dec, dt) == rv
    };
    // On the reference in two ticks: this one to relative velocity y1, the next back to 0.
    let y1 = -x / dt - y / 2.0;
    let wanted = if feasible(y1) {
        y1
    } else {
        // The braking curve: the relative velocity from which the rest of the way, after this
        // tick, is stopped at `a`: y*² = 2·a·(x + (y + y*)·dt/2) on the side that closes in.
        let s = if x > 0.0 || (x == 0.0 && y > 0.0) {
            1.0
        } else {
            -1.0
        };
        let (xs, ys) = (s * x, s * y);
        let disc = a * a * dt * dt + 4.0 * (2.0 * a * xs + a * dt * ys);
        let ystar = if disc < 0.0 {
            ys + a * dt
        } else {
            (a * dt - disc.sqrt()) / 2.0
        };
        s * ystar
    };
    let mut v1 = change(v, rv + wanted, b.acc, b.dec, dt);
    if v1.abs() > b.vmax {
        // Down to the velocity limit (at `dec` when above it already).
        v1 = if v.abs() <= b.vmax {
            b.vmax.copysign(v1)
        } else {
            change(v, b.vmax.copysign(v), b.acc, b.dec, dt)
        };
    }
    (p + (v + v1) / 2.0 * dt, v1, false)
}

/// `x` rounded to a whole number, with thousands separators.
pub(crate) fn int(x: f64) -> String {
    let r = x.round();
    let digits = format!("{}", r.abs() as u128);
    let mut out = String::new();
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    if r < 0.0 {
        format!("-{out}")
    } else {
        out
    }
}

/// The limit the acceleration of the cyclic demand is bounded by, for the line that names it.
#[derive(Clone, Copy, Debug, PartialEq)]
enum AccelBy {
    Object(u16),
    Torque,
    PullOut,
}

impl Drive {
    /// The next [`Limited`] the drive has logged, oldest first (it keeps the last 32).
    pub fn poll_limit(&mut self) -> Option<Limited> {
        self.limits.pop_front()
    }

    /// Logs a limit of `kind` (once until the mode starts again) and keeps it.
    pub(crate) fn report(
        &mut self,
        kind: Kind,
        object: Option<(u16, u8)>,
        value: f64,
        limit: f64,
        text: String,
    ) {
        let bit = 1u32 << kind as u8;
        if self.reported & bit != 0 {
            return;
        }
        self.reported |= bit;
        let message = format!("axis {}: {text}", self.axis);
        let index = object.map_or_else(
            || "-".to_string(),
            |(i, s)| {
                if s == 0 {
                    format!("{i:#06X}")
                } else {
                    format!("{i:#06X}:{s:02X}")
                }
            },
        );
        tracing::warn!(
            target: "ds402::drive",
            axis = self.axis,
            index = %index,
            value,
            limit,
            "{message}"
        );
        if self.limits.len() == KEPT {
            self.limits.pop_front();
        }
        self.limits.push_back(Limited {
            axis: self.axis,
            object,
            value,
            limit,
            message,
        });
    }

    /// The object of this axis whose standard index is `index`, as the line names it.
    pub(crate) fn own(&self, index: u16, sub: u8) -> (u16, u8) {
        (self.base() + (index - 0x6000), sub)
    }

    /// The object (this axis's index) as the line writes it: `0x607F`, `0x607D:02`.
    pub(crate) fn name(&self, index: u16, sub: u8) -> String {
        let (i, s) = self.own(index, sub);
        if sub == 0 {
            format!("{i:#06X}")
        } else {
            format!("{i:#06X}:{s:02X}")
        }
    }

    /// The velocity limit of the demand and the line that names it: the lower of 0x607F and 0x6080.
    pub(crate) fn velocity_bound(&self) -> (f64, String, (u16, u8)) {
        let profile_max = self.params.unsigned(P::MaxProfileVelocity) as f64;
        let rpm = self.params.unsigned(P::MaxMotorSpeed) as f64;
        let motor_max = rpm * self.motor.cpr / 60.0;
        if motor_max < profile_max {
            (
                motor_max,
                format!(
                    "{} = {} rpm ({} counts/s)",
                    self.name(0x6080, 0),
                    int(rpm),
                    int(motor_max)
                ),
                self.own(0x6080, 0),
            )
        } else {
            (
                profile_max,
                format!("{} = {} counts/s", self.name(0x607F, 0), int(profile_max)),
                self.own(0x607F, 0),
            )
        }
    }

    /// The acceleration the motor can give at velocity `v` (speeding up, slowing down), within its
    /// torque limit less the load (and the friction while speeding up), with a margin for the
    /// controller; `None` when the limit does not exceed the load.
    fn motor_accel(&self, v: f64) -> Option<(f64, f64)> {
        let torque = match self.config.motor.kind {
            MotorKind::Servo => self.torque_limit(),
            MotorKind::Stepper => self.motor.pull_out,
        };
        let spare = MARGIN * torque - self.motor.load.abs();
        if spare <= 0.0 {
            return None;
        }
        let jc = self.motor.accel_torque();
        let friction = self.motor.friction_torque(v.abs());
        Some((((spare - friction) / jc).max(0.0), spare / jc))
    }

    /// The bounds of the cyclic demand at its velocity `v`, with what bounds the acceleration and
    /// the deceleration.
    fn cyclic_bounds(&self, v: f64) -> (Bounds, AccelBy, AccelBy) {
        let (vmax, _, _) = self.velocity_bound();
        let max_acc = self.params.positive(P::MaxAcceleration);
        let max_dec = self.params.positive(P::MaxDeceleration);
        let motor_by = match self.config.motor.kind {
            MotorKind::Servo => AccelBy::Torque,
            MotorKind::Stepper => AccelBy::PullOut,
        };
        let (mut acc, mut acc_by) = (max_acc, AccelBy::Object(0x60C5));
        let (mut dec, mut dec_by) = (max_dec, AccelBy::Object(0x60C6));
        if let Some((a, d)) = self.motor_accel(v) {
            if a < acc {
                (acc, acc_by) = (a, motor_by);
            }
            if d < dec {
                (dec, dec_by) = (d, motor_by);
            }
        }
        (Bounds { vmax, acc, dec }, acc_by, dec_by)
    }

    /// The demand of a cyclic mode at the present tick: the `reference` (what the set-points ask
    /// for) while the drive can follow it from `before`, else one tick of running after it within
    /// the drive's limits.
    pub(super) fn limit_demand(&mut self, before: Demand, reference: Demand) -> Demand {
        let dt = self.dt();
        let (b, acc_by, dec_by) = self.cyclic_bounds(before.v);
        let position = match self.motion {
            Motion::Position { .. } => true,
            Motion::Velocity { .. } => false,
            _ => return reference,
        };
        if !self.cyclic.limited {
            if follows(before.v, reference.v, &b, dt) {
                return reference;
            }
            self.cyclic.limited = true;
            self.report_cyclic(position, before, reference, &b, acc_by, dec_by);
        }
        let demand = if position {
            let (p, v, back) = track(before.p, before.v, reference.p, reference.v, &b, dt);
            self.cyclic.limited = !back;
            Demand { p, v }
        } else {
            // csv: the velocity within the bounds (the target itself was clamped to the velocity
            // limit at its SYNC); the position runs on from it.
            let v = change(before.v, reference.v, b.acc, b.dec, dt);
            self.cyclic.limited = v != reference.v;
            Demand {
                p: before.p + 0.5 * (before.v + v) * dt,
                v,
            }
        };
        if self.cyclic.limited {
            self.cyclic.reference = Some(reference);
        }
        demand
    }

    /// What the set-points ask for at the last tick: the demand, or while the drive runs after
    /// the set-points within its limits, the set-points' own value (which 0x6062, 0x606B and the
    /// following error 0x60F4 show, as a drive whose motor falls behind shows them).
    pub(super) fn set_point(&self) -> Demand {
        self.cyclic.reference.unwrap_or(self.demand)
    }

    /// After a motor tick in Operation enabled: the torque the demand asked for beyond the motor's
    /// (a servo's torque limit, a stepper's pull-out torque).
    pub(crate) fn report_excess(&mut self) {
        let Some((needed, limit)) = self.motor.excess else {
            return;
        };
        if self.state != State::OperationEnabled {
            return;
        }
        match self.config.motor.kind {
            MotorKind::Servo => {
                let text = format!(
                    "the servo needs {needed:.3} N·m, above its torque limit of {limit:.3} N·m \
                     ({} = {} ‰ of {} = {} mN·m)",
                    self.name(0x6072, 0),
                    int(self.params.get(P::MaxTorque) as f64),
                    self.name(0x6076, 0),
                    int(self.rated_torque() * 1000.0)
                );
                let object = Some(self.own(0x6072, 0));
                self.report(Kind::TorqueLimit, object, needed, limit, text);
            }
            MotorKind::Stepper => {
                let text = format!(
                    "the stepper needs {needed:.3} N·m, above its pull-out torque of {limit:.3} \
                     N·m: it slips and loses steps"
                );
                self.report(Kind::PullOut, None, needed, limit, text);
            }
        }
    }

    /// The line of the limit that keeps the cyclic demand off its reference from `before`.
    fn report_cyclic(
        &mut self,
        position: bool,
        before: Demand,
        reference: Demand,
        b: &Bounds,
        acc_by: AccelBy,
        dec_by: AccelBy,
    ) {
        let dt = self.dt();
        let (mode, step) = match self.motion {
            Motion::Position { from, to, .. } => (
                "csp",
                format!("target step of {} counts/cycle", int(to - from)),
            ),
            Motion::Velocity { from, to, .. } => (
                "csv",
                format!("target change of {} counts/s in a cycle", int(to - from)),
            ),
            _ => return,
        };
        if reference.v.abs() > b.vmax {
            let (limit, name, object) = self.velocity_bound();
            let kind = if position {
                Kind::CspVelocity
            } else {
                Kind::CsvVelocity
            };
            self.report(
                kind,
                Some(object),
                reference.v.abs(),
                limit,
                format!(
                    "{mode} {step} needs {} counts/s, above {name}",
                    int(reference.v.abs())
                ),
            );
            return;
        }
        let needed = ((reference.v - before.v) / dt).abs();
        let falling = (before.v > 0.0 && reference.v < before.v)
            || (before.v < 0.0 && reference.v > before.v);
        let (limit, by) = if falling {
            (b.dec, dec_by)
        } else {
            (b.acc, acc_by)
        };
        let (object, name) = match by {
            AccelBy::Object(index) => (
                Some(self.own(index, 0)),
                format!("{} = {} counts/s²", self.name(index, 0), int(limit)),
            ),
            AccelBy::Torque => (
                Some(self.own(0x6072, 0)),
                format!(
                    "the {} counts/s² that {} = {} ‰ of {} = {} mN·m gives the motor",
                    int(limit),
                    self.name(0x6072, 0),
                    int(self.params.get(P::MaxTorque) as f64),
                    self.name(0x6076, 0),
                    int(self.rated_torque() * 1000.0)
                ),
            ),
            AccelBy::PullOut => (
                None,
                format!(
                    "the {} counts/s² that the stepper's pull-out torque of {:.3} N·m gives",
                    int(limit),
                    self.motor.pull_out
                ),
            ),
        };
        let kind = if position {
            Kind::CspAcceleration
        } else {
            Kind::CsvAcceleration
        };
        self.report(
            kind,
            object,
            needed,
            limit,
            format!(
                "{mode} {step} needs {} counts/s² from {} counts/s, above {name}",
                int(needed),
                int(before.v)
            ),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f64 = 0.001;

    /// Runs `track` from `p`, `v` after a reference at 0 moving at `rv` until it is back on it:
    /// the ticks it took, every change within the bounds on the way.
    fn land(mut p: f64, mut v: f64, rv: f64, b: &Bounds, most: usize) -> usize {
        let mut rp = 0.0;
        for k in 1..=most {
            rp += rv * DT;
            let (p1, v1, back) = track(p, v, rp, rv, b, DT);
            assert_eq!(change(v, v1, b.acc, b.dec, DT), v1, "tick {k}: {v} → {v1}");
            assert!(v1.abs() <= b.vmax || v1.abs() < v.abs(), "tick {k}: {v1}");
            if back {
                assert_eq!((p1, v1), (rp, rv));
                return k;
            }
            (p, v) = (p1, v1);
        }
        panic!("not back on the reference after {most} ticks: {p} − {rp}, {v} − {rv}");
    }

    #[test]
    fn a_step_within_the_bounds_is_followed() {
        let b = Bounds {
            vmax: 10_000.0,
            acc: 1e6,
            dec: 2e6,
        };
        assert!(follows(0.0, 1000.0, &b, DT));
        assert!(!follows(0.0, 1001.0, &b, DT));
        assert!(follows(2000.0, 0.0, &b, DT));
        assert!(!follows(2001.0, 0.0, &b, DT));
        assert!(!follows(9500.0, 10_001.0, &b, DT));
        // Through zero: 1000 down at `dec` (0.5 ms), then up to −1000 at `acc` (1 ms): beyond.
        assert!(!follows(1000.0, -1000.0, &b, DT));
    }

    /// From rest 10,000 counts behind a standing reference at 1e6 counts/s²: the time-optimal
    /// move, accelerating half-way and braking the other half, takes 2 · √(10,000 / 1e6) = 0.2 s:
    /// 200 ticks, on the reference exactly at the last.
    #[test]
    fn a_standing_reference_is_reached_exactly() {
        let b = Bounds {
            vmax: f64::INFINITY,
            acc: 1e6,
            dec: 1e6,
        };
        let ticks = land(-10_000.0, 0.0, 0.0, &b, 1000);
        assert_eq!(ticks, 200);
        let ticks = land(10_000.0, 0.0, 0.0, &b, 1000);
        assert_eq!(ticks, 200);
    }

    /// 1,000 counts behind a reference that moves at 100,000 counts/s, from rest, with at most
    /// 150,000 counts/s and 5e6 counts/s²: 30 ms up to 150,000 counts/s (the gap grows to 1,750
    /// counts), 30 ms at 50,000 counts/s more than the reference (1,500 counts), 10 ms down to its
    /// velocity (250 counts): on it after 70 ticks.
    #[test]
    fn a_moving_reference_is_caught_within_the_velocity_limit() {
        let b = Bounds {
            vmax: 150_000.0,
            acc: 5e6,
            dec: 5e6,
        };
        let ticks = land(-1000.0, 0.0, 100_000.0, &b, 10_000);
        assert_eq!(ticks, 70);
    }

    /// States all over the plane, bounds of every size: every run lands exactly, within the
    /// bounds at every tick.
    #[test]
    fn every_start_lands_exactly() {
        let mut seed = 0x2545_F491_4F6C_DD1Du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..2000 {
            let a = 10f64.powf(4.0 + 4.0 * next());
            let acc = a * [1.0, 2.0, 5.0][(next() * 3.0) as usize];
            let dec = a * [1.0, 2.0, 5.0][(next() * 3.0) as usize];
            let vmax = if next() < 0.5 {
                f64::INFINITY
            } else {
                10f64.powf(4.0 + 2.0 * next())
            };
            let rv = if next() < 0.3 {
                0.0
            } else {
                (2.0 * next() - 1.0) * vmax.min(1e6) * 0.8
            };
            let p = (2.0 * next() - 1.0) * 10f64.powf(6.0 * next());
            let v = (2.0 * next() - 1.0) * vmax.min(1e6);
            let b = Bounds { vmax, acc, dec };
            let am = acc.min(dec);
            let y = v - rv;
            let far = p.abs() + y * y / (2.0 * am);
            let spare = vmax - rv.abs();
            let most = 3.0 * (2.0 * y.abs() / am + 2.0 * (far / am).sqrt() + far / spare) / DT;
            land(p, v, rv, &b, most as usize + 20);
        }
    }

    #[test]
    fn numbers_have_thousands_separators() {
        assert_eq!(int(100_000.0), "100,000");
        assert_eq!(int(-1_234_567.4), "-1,234,567");
        assert_eq!(int(999.5), "1,000");
        assert_eq!(int(12.0), "12");
    }
}
