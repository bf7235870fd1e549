//! Move-profile maths of the SMD23K-B / SMD24K (seed 000, Reference 3 "Calculating Move Profiles").
//!
//! Units as the unit takes them: speeds in steps/s, Acceleration and Deceleration in steps/s/ms (the
//! equations use ×1000, steps/s²), the Jerk word J = 0 … 5000 (0 = linear acceleration; otherwise the
//! physical jerk is j = J·a/100 steps/s³, R3 "S-Curve Acceleration Equations").
//!
//! - Linear phase (Table R3.1): T = Δv/a, D = T·(V₀ + V₁)/2.
//! - S-curve phase (R3 "Determining Waveforms by Values"): triangular when the acceleration reached at
//!   half the speed change, a_f = √(Δv·j), is at most a (time 2√(Δv/j)); otherwise trapezoidal, with
//!   t₁ = a/j of jerk, S₁ = j·t₁²/2, t₂ = (Δv/2 − S₁)/a, time 2(t₁ + t₂). Every phase is symmetric about
//!   its half-way point, so its distance is T·(V₀ + V₁)/2 as for a linear phase.
//! - Move (R3 "Constant Acceleration Equations", "Total Time Equations"): trapezoidal when D_A + D_D is
//!   less than the length (cruise D_P = length − D_A − D_D at V_P), triangular otherwise, peaking at
//!   V_M with D_A(V_M) + D_D(V_M) = length. For linear phases V_M² = V_S² + 2·L·a·d/(a + d) (the manual's
//!   formula solved); for S-curves the manual gives no formula (catalogue gap SMD-R3-025), and V_M is
//!   found by bisection on the same distance equation.
//!
//! The manual prints D_A = 250,002, D_D = 199,982 and 449,984 steps for its Table R3.2 example because
//! it multiplied the rounded times 4.993 s and 3.994 s; the formulas give 249,999.5, 199,999.6 and
//! 449,999.1 steps, which is what this module computes (SMD-R3-008 pick).

use std::fmt;

/// Highest Jerk word the unit takes (Reference 6 parameter ranges).
pub const MAX_JERK: u16 = 5000;
/// Highest Acceleration/Deceleration word (steps/s/ms).
pub const MAX_ACCEL: u16 = 5000;

/// Why a profile cannot be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ProfileError {
    /// Acceleration or Deceleration outside 1 … 5000 steps/s/ms.
    #[error("{which} {value} is outside 1 to 5000 steps/s/ms")]
    Accel {
        /// "acceleration" or "deceleration".
        which: &'static str,
        /// The value given.
        value: u16,
    },
    /// Jerk above 5000.
    #[error("jerk {0} is outside 0 to 5000")]
    Jerk(u16),
    /// The starting speed is not above 0 (Starting_Speed is 1 … 1,999,999 steps/s, SMD-R5-003).
    #[error("starting speed {0} steps/s is not above 0")]
    StartSpeed(f64),
    /// The programmed speed is below the starting speed.
    #[error("programmed speed {speed} steps/s is below the starting speed {start} steps/s")]
    Speed {
        /// The starting speed.
        start: f64,
        /// The programmed speed.
        speed: f64,
    },
    /// A value is not a finite number.
    #[error("{0} is not a finite number")]
    NotFinite(&'static str),
}

/// What a move is computed from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveParams {
    /// Configured Starting Speed V_S (steps/s).
    pub start_speed: f64,
    /// Programmed Speed V_P (steps/s).
    pub speed: f64,
    /// Acceleration word (steps/s/ms).
    pub accel: u16,
    /// Deceleration word (steps/s/ms).
    pub decel: u16,
    /// Jerk word (0 = linear).
    pub jerk: u16,
    /// Length of the move (steps, ≥ 0; the direction does not matter here).
    pub distance: f64,
}

/// The shape of one acceleration or deceleration phase.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PhaseShape {
    /// Constant acceleration (Jerk = 0).
    Linear,
    /// S-curve whose acceleration peaks at half the phase without reaching the programmed value.
    TriangularS,
    /// S-curve with a period at the programmed acceleration.
    TrapezoidalS,
}

/// One acceleration (or deceleration) phase between two speeds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Phase {
    /// Its shape.
    pub shape: PhaseShape,
    /// Speed at the slow end (V_S).
    pub low: f64,
    /// Speed at the fast end (V_P or V_M).
    pub high: f64,
    /// Programmed acceleration a (steps/s²).
    pub accel: f64,
    /// Physical jerk j (steps/s³; 0 for a linear phase).
    pub jerk: f64,
    /// Duration (s).
    pub time: f64,
    /// Steps covered.
    pub distance: f64,
    /// Highest acceleration reached (a for linear and trapezoidal phases, a_f for a triangular one).
    pub peak_accel: f64,
    /// Time of each jerk ramp: t₁ for a trapezoidal S-curve, half the phase for a triangular one, 0
    /// for linear.
    pub t1: f64,
    /// Half the time at constant acceleration: t₂ for a trapezoidal S-curve, 0 for a triangular one,
    /// half the phase for a linear one.
    pub t2: f64,
}

impl Phase {
    /// The phase from `low` to `high` steps/s with acceleration `accel` (steps/s²) and Jerk word
    /// `jerk_word` (Reference 3).
    pub fn new(low: f64, high: f64, accel: f64, jerk_word: u16) -> Phase {
        let dv = (high - low).max(0.0);
        let mut p = Phase {
            shape: PhaseShape::Linear,
            low,
            high,
            accel,
            jerk: 0.0,
            time: 0.0,
            distance: 0.0,
            peak_accel: accel,
            t1: 0.0,
            t2: 0.0,
        };
        if jerk_word == 0 {
            p.time = dv / accel;
            p.t2 = p.time / 2.0;
        } else {
            let j = physical_jerk(jerk_word, accel);
            p.jerk = j;
            if dv <= accel * accel / j {
                // a_f = j·t with t = √(Δv/j): no greater than a.
                let t = (dv / j).sqrt();
                p.shape = PhaseShape::TriangularS;
                p.t1 = t;
                p.peak_accel = j * t;
                p.time = 2.0 * t;
            } else {
                let t1 = accel / j;
                let s1 = j * t1 * t1 / 2.0;
                let t2 = (dv / 2.0 - s1) / accel;
                p.shape = PhaseShape::TrapezoidalS;
                p.t1 = t1;
                p.t2 = t2;
                p.time = 2.0 * (t1 + t2);
            }
        }
        p.distance = p.time * (low + high) / 2.0;
        p
    }

    /// Speed S₁ gained during the first jerk ramp (j·t₁²/2; the whole first half of a triangular
    /// S-curve, 0 for a linear phase).
    pub fn s1(&self) -> f64 {
        self.jerk * self.t1 * self.t1 / 2.0
    }

    /// The share of the phase spent at constant acceleration (0 … 1).
    pub fn constant_share(&self) -> f64 {
        if self.time == 0.0 {
            0.0
        } else {
            2.0 * self.t2 / self.time
        }
    }

    /// The speed `t` seconds into the phase, going from `low` to `high` (clamped to the phase).
    pub fn speed_rising(&self, t: f64) -> f64 {
        let t = t.clamp(0.0, self.time);
        match self.shape {
            PhaseShape::Linear => self.low + self.accel * t,
            PhaseShape::TriangularS => {
                if t <= self.t1 {
                    self.low + self.jerk * t * t / 2.0
                } else {
                    let r = self.time - t;
                    self.high - self.jerk * r * r / 2.0
                }
            }
            PhaseShape::TrapezoidalS => {
                let s1 = self.s1();
                if t <= self.t1 {
                    self.low + self.jerk * t * t / 2.0
                } else if t <= self.t1 + 2.0 * self.t2 {
                    self.low + s1 + self.accel * (t - self.t1)
                } else {
                    let r = self.time - t;
                    self.high - self.jerk * r * r / 2.0
                }
            }
        }
    }

    /// Steps covered `t` seconds into the phase, going from `low` to `high`.
    pub fn distance_rising(&self, t: f64) -> f64 {
        let t = t.clamp(0.0, self.time);
        let j = self.jerk;
        // Distance of the falling-jerk tail that ends at the phase's end, r seconds long.
        let tail = |r: f64| self.high * r - j * r * r * r / 6.0;
        match self.shape {
            PhaseShape::Linear => self.low * t + self.accel * t * t / 2.0,
            PhaseShape::TriangularS => {
                if t <= self.t1 {
                    self.low * t + j * t * t * t / 6.0
                } else {
                    self.distance - tail(self.time - t)
                }
            }
            PhaseShape::TrapezoidalS => {
                let t1 = self.t1;
                let head = |t: f64| self.low * t + j * t * t * t / 6.0;
                if t <= t1 {
                    head(t)
                } else if t <= t1 + 2.0 * self.t2 {
                    let u = t - t1;
                    head(t1) + (self.low + self.s1()) * u + self.accel * u * u / 2.0
                } else {
                    self.distance - tail(self.time - t)
                }
            }
        }
    }
}

/// j = J·a/100 steps/s³ for the Jerk word J and acceleration a (steps/s²).
pub fn physical_jerk(jerk_word: u16, accel: f64) -> f64 {
    f64::from(jerk_word) * accel / 100.0
}

/// The ideal Jerk word for a triangular S-curve phase of `t` seconds: 200/t (R3 "Triangular S-Curve").
pub fn jerk_for_triangular(t: f64) -> f64 {
    200.0 / t
}

/// The Jerk word for a trapezoidal S-curve phase of `t` seconds at constant acceleration for half of
/// it: 400/t (R3 "Trapezoidal S-Curve").
pub fn jerk_for_half_constant(t: f64) -> f64 {
    400.0 / t
}

/// The Jerk word for a trapezoidal S-curve phase of `t` seconds at constant acceleration for a third
/// of it: 300/t.
pub fn jerk_for_third_constant(t: f64) -> f64 {
    300.0 / t
}

/// The peak V_M of an S-curve move from `vs` too short to reach `vp`: the speed whose acceleration
/// (`a`) and deceleration (`d`) phases with the Jerk word `jerk` add up to `length` steps. The manual
/// gives no formula (catalogue gap SMD-R3-025); the phase distances grow with the peak, so it is
/// found by bisection until the bracket's ends are neighbouring numbers, after which a halving
/// changes nothing. From a bracket of up to 3,000,000 steps/s above a starting speed of at least 1
/// that takes about 75 halvings; 200 leave room.
fn s_curve_peak(vs: f64, vp: f64, a: f64, d: f64, jerk: u16, length: f64) -> f64 {
    let dist = |v: f64| Phase::new(vs, v, a, jerk).distance + Phase::new(vs, v, d, jerk).distance;
    let (mut lo, mut hi) = (vs, vp);
    for _ in 0..200 {
        let mid = (lo + hi) / 2.0;
        if dist(mid) > length {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    (lo + hi) / 2.0
}

/// Trapezoidal or triangular.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MoveShape {
    /// Reaches the programmed speed and cruises there.
    Trapezoidal,
    /// Only accelerates and decelerates; the peak is V_M ≤ V_P (equal when D_A + D_D is the length).
    Triangular,
}

/// A whole move: acceleration phase, cruise, deceleration phase.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Profile {
    /// What it was computed from.
    pub params: MoveParams,
    /// Trapezoidal or triangular.
    pub shape: MoveShape,
    /// The highest speed reached (V_P, or V_M of a triangular move).
    pub peak_speed: f64,
    /// The acceleration phase, V_S → peak.
    pub accel: Phase,
    /// Steps at the peak speed (D_P; 0 for a triangular move).
    pub cruise_distance: f64,
    /// Time at the peak speed (D_P/V_P).
    pub cruise_time: f64,
    /// The deceleration phase, peak → V_S.
    pub decel: Phase,
    /// D_A + D_D with the full programmed speed (the trapezoid/triangle threshold).
    pub threshold: f64,
}

impl Profile {
    /// Computes the move `p` (Reference 3).
    pub fn plan(p: MoveParams) -> Result<Profile, ProfileError> {
        for (name, v) in [
            ("starting speed", p.start_speed),
            ("programmed speed", p.speed),
            ("distance", p.distance),
        ] {
            if !v.is_finite() {
                return Err(ProfileError::NotFinite(name));
            }
        }
        for (which, value) in [("acceleration", p.accel), ("deceleration", p.decel)] {
            if !(1..=MAX_ACCEL).contains(&value) {
                return Err(ProfileError::Accel { which, value });
            }
        }
        if p.jerk > MAX_JERK {
            return Err(ProfileError::Jerk(p.jerk));
        }
        if p.start_speed <= 0.0 {
            return Err(ProfileError::StartSpeed(p.start_speed));
        }
        if p.speed < p.start_speed {
            return Err(ProfileError::Speed {
                start: p.start_speed,
                speed: p.speed,
            });
        }
        let a = f64::from(p.accel) * 1000.0;
        let d = f64::from(p.decel) * 1000.0;
        let vs = p.start_speed;
        let length = p.distance.abs();
        let up = Phase::new(vs, p.speed, a, p.jerk);
        let down = Phase::new(vs, p.speed, d, p.jerk);
        let threshold = up.distance + down.distance;
        if threshold < length {
            let cruise = length - threshold;
            return Ok(Profile {
                params: p,
                shape: MoveShape::Trapezoidal,
                peak_speed: p.speed,
                accel: up,
                cruise_distance: cruise,
                // The programmed speed is at least the starting speed, which is above 0.
                cruise_time: cruise / p.speed,
                decel: down,
                threshold,
            });
        }
        let peak = if threshold == length {
            p.speed
        } else if p.jerk == 0 {
            // (V_M² − V_S²)/2a + (V_M² − V_S²)/2d = L.
            (vs * vs + 2.0 * length * a * d / (a + d))
                .sqrt()
                .min(p.speed)
        } else {
            s_curve_peak(vs, p.speed, a, d, p.jerk, length)
        };
        Ok(Profile {
            params: p,
            shape: MoveShape::Triangular,
            peak_speed: peak,
            accel: Phase::new(vs, peak, a, p.jerk),
            cruise_distance: 0.0,
            cruise_time: 0.0,
            decel: Phase::new(vs, peak, d, p.jerk),
            threshold,
        })
    }

    /// T_P: the whole move's time (T_A + T_D + D_P/V_P).
    pub fn total_time(&self) -> f64 {
        self.accel.time + self.cruise_time + self.decel.time
    }

    /// Steps covered by the phases and the cruise (the move's length, up to rounding).
    pub fn total_distance(&self) -> f64 {
        self.accel.distance + self.cruise_distance + self.decel.distance
    }

    /// The speed `t` seconds after the start (V_S before and after the move's phases).
    pub fn speed_at(&self, t: f64) -> f64 {
        let ta = self.accel.time;
        let tc = ta + self.cruise_time;
        if t <= ta {
            self.accel.speed_rising(t)
        } else if t <= tc {
            self.peak_speed
        } else {
            // The deceleration phase is the acceleration shape run backwards in time.
            self.decel.speed_rising(self.decel.time - (t - tc))
        }
    }

    /// Steps covered `t` seconds after the start.
    pub fn position_at(&self, t: f64) -> f64 {
        let ta = self.accel.time;
        let tc = ta + self.cruise_time;
        if t <= ta {
            self.accel.distance_rising(t)
        } else if t <= tc {
            self.accel.distance + self.peak_speed * (t - ta)
        } else {
            let r = (self.decel.time - (t - tc)).max(0.0);
            self.accel.distance + self.cruise_distance + self.decel.distance
                - self.decel.distance_rising(r)
        }
    }

    /// `n` + 1 evenly spaced samples (time, speed) over the whole move, for a chart.
    pub fn speed_samples(&self, n: usize) -> Vec<(f64, f64)> {
        let n = n.max(1);
        let total = self.total_time();
        (0..=n)
            .map(|k| {
                let t = total * k as f64 / n as f64;
                (t, self.speed_at(t))
            })
            .collect()
    }
}

fn shape_name(s: PhaseShape) -> &'static str {
    match s {
        PhaseShape::Linear => "linear",
        PhaseShape::TriangularS => "triangular S-curve",
        PhaseShape::TrapezoidalS => "trapezoidal S-curve",
    }
}

fn write_phase(f: &mut fmt::Formatter<'_>, name: &str, p: &Phase) -> fmt::Result {
    writeln!(
        f,
        "{name:<13} {:<20} {:>10.4} s {:>14.1} steps  {:.1} -> {:.1} steps/s",
        shape_name(p.shape),
        p.time,
        p.distance,
        if name == "deceleration" {
            p.high
        } else {
            p.low
        },
        if name == "deceleration" {
            p.low
        } else {
            p.high
        },
    )?;
    match p.shape {
        PhaseShape::Linear => writeln!(f, "{:14}a = {:.0} steps/s²", "", p.accel),
        PhaseShape::TriangularS => writeln!(
            f,
            "{:14}j = {:.1} steps/s³, t = {:.4} s, a_f = {:.0} steps/s² (≤ a = {:.0})",
            "", p.jerk, p.t1, p.peak_accel, p.accel
        ),
        PhaseShape::TrapezoidalS => writeln!(
            f,
            "{:14}j = {:.1} steps/s³, t1 = {:.4} s, S1 = {:.1} steps/s, t2 = {:.4} s, \
             {:.1} % at a = {:.0} steps/s²",
            "",
            p.jerk,
            p.t1,
            p.s1(),
            p.t2,
            100.0 * p.constant_share(),
            p.accel
        ),
    }
}

/// The table `smd profile` prints.
impl fmt::Display for Profile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = &self.params;
        writeln!(
            f,
            "move of {:.0} steps: starting speed {:.0} steps/s, programmed speed {:.0} steps/s, \
             acceleration {} ({} steps/s²), deceleration {} ({} steps/s²), jerk {}",
            p.distance.abs(),
            p.start_speed,
            p.speed,
            p.accel,
            u32::from(p.accel) * 1000,
            p.decel,
            u32::from(p.decel) * 1000,
            p.jerk
        )?;
        writeln!(
            f,
            "profile       {} (D_A + D_D at the programmed speed = {:.1} steps)",
            match self.shape {
                MoveShape::Trapezoidal => "trapezoidal",
                MoveShape::Triangular if self.peak_speed >= p.speed => {
                    "triangular, reaching the programmed speed"
                }
                MoveShape::Triangular => "triangular, below the programmed speed",
            },
            self.threshold
        )?;
        write_phase(f, "acceleration", &self.accel)?;
        writeln!(
            f,
            "{:<13} {:<20} {:>10.4} s {:>14.1} steps  at {:.1} steps/s",
            "cruise", "", self.cruise_time, self.cruise_distance, self.peak_speed
        )?;
        write_phase(f, "deceleration", &self.decel)?;
        writeln!(
            f,
            "{:<13} {:<20} {:>10.4} s {:>14.1} steps  peak {:.1} steps/s",
            "total",
            "",
            self.total_time(),
            self.total_distance(),
            self.peak_speed
        )
    }
}
