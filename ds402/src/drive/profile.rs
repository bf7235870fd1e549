//! The motion profiles of the drive: piecewise constant-acceleration trajectories planned once and
//! evaluated at each control tick (CiA 402-2, profile position mode, motion profile type 0 "linear
//! ramp (trapezoidal profile)", and profile velocity mode).
//!
//! A [`Profile`] is a list of [`Segment`]s, each of constant acceleration, from the instant it was
//! planned (t = 0). The last segment runs on for ever at constant velocity (0 for a move that ends
//! at rest). Planning is closed-form, so the position at any instant is the same whatever the
//! tick: a master can compute it by hand from the profile parameters. The segments start at whole
//! nanoseconds (each duration rounded to the nearest one, the state carried on from the rounded
//! duration) and are evaluated at whole nanoseconds, so a segment that ends on a tick ends there
//! exactly, whatever floating point makes of its duration.

/// A piece of a profile with constant acceleration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Segment {
    /// Start, nanoseconds after the profile's origin.
    pub start: u64,
    /// Position at the start (counts).
    pub p: f64,
    /// Velocity at the start (counts/s).
    pub v: f64,
    /// Acceleration during the segment (counts/s²).
    pub a: f64,
}

/// A planned trajectory: segments in order, the last one running on at constant velocity.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Profile {
    segments: Vec<Segment>,
    /// When the last segment starts (ns): the profile has reached its final state.
    end: u64,
}

impl Profile {
    /// Position and velocity `t` nanoseconds after the origin.
    pub fn eval(&self, t: u64) -> (f64, f64) {
        let seg = self
            .segments
            .iter()
            .rev()
            .find(|s| t >= s.start)
            .unwrap_or(&self.segments[0]);
        let tau = t.saturating_sub(seg.start) as f64 / 1e9;
        (
            seg.p + seg.v * tau + 0.5 * seg.a * tau * tau,
            seg.v + seg.a * tau,
        )
    }

    /// Whether the profile has reached its final state `t` nanoseconds after the origin.
    pub fn finished(&self, t: u64) -> bool {
        t >= self.end
    }

    /// The velocity it runs on with at the end.
    #[cfg(test)]
    pub fn final_velocity(&self) -> f64 {
        self.segments.last().map_or(0.0, |s| s.v)
    }
}

/// `d` seconds in whole nanoseconds (0 for what is not a positive duration; saturating).
fn seconds_to_ns(d: f64) -> u64 {
    if d > 0.0 {
        (d * 1e9).round().min(u64::MAX as f64) as u64
    } else {
        0
    }
}

/// Builds a profile segment by segment, keeping the state at the end of the last one.
struct Builder {
    t: u64,
    p: f64,
    v: f64,
    segments: Vec<Segment>,
}

impl Builder {
    fn new(p: f64, v: f64) -> Builder {
        Builder {
            t: 0,
            p,
            v,
            segments: Vec::new(),
        }
    }

    /// Changes the velocity to `to` at `rate` (counts/s², > 0).
    fn ramp(&mut self, to: f64, rate: f64) {
        let dv = to - self.v;
        if dv == 0.0 {
            return;
        }
        let ns = seconds_to_ns(dv.abs() / rate);
        let a = dv.signum() * rate;
        if ns == 0 {
            self.v = to;
            return;
        }
        let d = ns as f64 / 1e9;
        self.segments.push(Segment {
            start: self.t,
            p: self.p,
            v: self.v,
            a,
        });
        self.p += self.v * d + 0.5 * a * d * d;
        self.v = to;
        self.t += ns;
    }

    /// Runs at the present velocity for `d` seconds.
    fn cruise(&mut self, d: f64) {
        let ns = seconds_to_ns(d);
        if ns == 0 {
            return;
        }
        let d = ns as f64 / 1e9;
        self.segments.push(Segment {
            start: self.t,
            p: self.p,
            v: self.v,
            a: 0.0,
        });
        self.p += self.v * d;
        self.t += ns;
    }

    /// Ends the profile; `at` is the exact final position of a move that ends at rest.
    fn finish(mut self, at: Option<f64>) -> Profile {
        self.segments.push(Segment {
            start: self.t,
            p: at.unwrap_or(self.p),
            v: self.v,
            a: 0.0,
        });
        Profile {
            segments: self.segments,
            end: self.t,
        }
    }
}

/// A positioning move from position `p0` at velocity `v0` to rest at `x`, with at most `vmax`,
/// accelerating at `acc` and decelerating at `dec` (a trapezoid, or a triangle when the distance is
/// too short for `vmax`). A move started while running away from `x`, or too fast to stop before
/// it, first brakes to a stop at `dec` and then comes back. With `vmax`, `acc` or `dec` not
/// positive no move is possible: the axis brakes to a stop (at `dec`, or at once) and the profile
/// never reaches `x`.
pub(crate) fn move_to(p0: f64, v0: f64, x: f64, vmax: f64, acc: f64, dec: f64) -> Profile {
    let mut b = Builder::new(p0, v0);
    if !(vmax > 0.0 && acc > 0.0 && dec > 0.0) {
        if dec > 0.0 {
            b.ramp(0.0, dec);
        } else {
            b.v = 0.0;
        }
        return b.finish(None);
    }
    let d = x - b.p;
    if b.v != 0.0 && (b.v.signum() != d.signum() || b.v * b.v / (2.0 * dec) > d.abs()) {
        b.ramp(0.0, dec);
    }
    let d = x - b.p;
    if d == 0.0 && b.v == 0.0 {
        return b.finish(Some(x));
    }
    let s = d.signum();
    let dist = d.abs();
    let u = b.v * s;
    let vp = if u > vmax {
        vmax
    } else {
        ((2.0 * acc * dec * dist + dec * u * u) / (acc + dec))
            .sqrt()
            .min(vmax)
            .max(u)
    };
    b.ramp(s * vp, if vp >= u { acc } else { dec });
    let remaining = (x - b.p) * s - vp * vp / (2.0 * dec);
    if remaining > 0.0 {
        b.cruise(remaining / vp);
    }
    b.ramp(0.0, dec);
    b.finish(Some(x))
}

/// A velocity ramp from `v0` to `vt`: `acc` while the speed grows, `dec` while it falls (through
/// zero first when the sign changes); then on at `vt`. Both rates must be positive.
pub(crate) fn velocity(p0: f64, v0: f64, vt: f64, acc: f64, dec: f64) -> Profile {
    let mut b = Builder::new(p0, v0);
    if v0 != 0.0 && vt != 0.0 && v0.signum() != vt.signum() {
        b.ramp(0.0, dec);
    }
    if vt.abs() > b.v.abs() {
        b.ramp(vt, acc);
    } else {
        b.ramp(vt, dec);
    }
    b.finish(None)
}

/// A stop: the velocity falls to 0 at `dec` (> 0).
pub(crate) fn stop(p0: f64, v0: f64, dec: f64) -> Profile {
    velocity(p0, v0, 0.0, dec, dec)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trapezoid_positions_are_closed_form() {
        // 0 → 2000 counts, 1000 counts/s, 10 000 counts/s² both ways: 0.1 s ramp (50 counts), 1.9 s
        // cruise, 0.1 s ramp.
        let p = move_to(0.0, 0.0, 2000.0, 1000.0, 10_000.0, 10_000.0);
        const MS: u64 = 1_000_000;
        assert_eq!(p.eval(100 * MS).0.round(), 50.0);
        assert_eq!(p.eval(1000 * MS).0.round(), 950.0);
        assert_eq!(p.eval(2000 * MS).0.round(), 1950.0);
        assert!(!p.finished(2100 * MS - 1));
        assert!(p.finished(2100 * MS));
        assert_eq!(p.eval(5000 * MS), (2000.0, 0.0));
    }

    #[test]
    fn triangle_when_too_short() {
        // 100 counts at 10 000 counts/s²: peak 1000 counts/s would need 100 counts of ramps exactly.
        let p = move_to(0.0, 0.0, 100.0, 5000.0, 10_000.0, 10_000.0);
        let (x, v) = p.eval(100_000_000);
        assert!((x - 50.0).abs() < 1e-9 && (v - 1000.0).abs() < 1e-9);
        assert!(p.finished(200_000_000));
    }

    #[test]
    fn reversal_brakes_first() {
        // Moving at +1000 towards -100: brake 0.1 s (50 counts) then go back 150 counts.
        let p = move_to(0.0, 1000.0, -100.0, 1000.0, 10_000.0, 10_000.0);
        let (x, v) = p.eval(100_000_000);
        assert!((x - 50.0).abs() < 1e-9 && v.abs() < 1e-9);
        assert_eq!(p.eval(10_000_000_000), (-100.0, 0.0));
    }

    #[test]
    fn velocity_ramp_through_zero() {
        let p = velocity(0.0, 1000.0, -1000.0, 10_000.0, 5_000.0);
        // 0.2 s down to 0 at 5000, then 0.1 s up at 10 000.
        let (_, v) = p.eval(200_000_000);
        assert!(v.abs() < 1e-9);
        let (_, v) = p.eval(300_000_000);
        assert!((v + 1000.0).abs() < 1e-9);
        assert_eq!(p.final_velocity(), -1000.0);
    }
}
