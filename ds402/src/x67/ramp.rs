//! The ramp generator of one X67SM2436 axis in the function model "Ramp" (seed 002, 18.11.1.3 to 18.11.1.6,
//! 18.11.1.14 and 18.11.1.15).
//!
//! A pure, deterministic model on a simulated clock: [`Ramp::step`] advances the axis by exactly one
//! ramp-generator cycle ([`Cycle`]) and returns the [`RampState`] after that cycle. Nothing here reads a clock
//! or does IO.
//!
//! Units are the device's own: positions in microsteps (1/256 full step), speeds in microsteps/cycle and
//! accelerations in microsteps/cycle² (X67-18.11.1.15-03).
//!
//! ```
//! use ds402::x67::ramp::{Config, Ramp, Target};
//!
//! let mut ramp = Ramp::new(Config { max_speed_pos: 20, max_acc: 10, max_dec: 10, ..Config::default() });
//! ramp.set_target(Target::Position(100));
//! let positions: Vec<i64> = (0..7).map(|_| ramp.step().position).collect();
//! assert_eq!(positions, [10, 30, 50, 70, 90, 100, 100]);
//! assert!(ramp.step().target_reached);
//! ```
//!
//! # How a move is planned
//!
//! The generator keeps an unfiltered *set-point* ramp (position and speed, all integers). In position mode it
//! chooses, every cycle, the largest set-point speed allowed by MaxSpeed0npos and MaxAcc0n from which the
//! remaining distance can still be braked to zero with MaxDec0n exactly on the target; the braking distance
//! from speed `w` is `Σ max(0, w − k·dec)` over k ≥ 1, so a final cycle shorter than `dec` absorbs the
//! remainder and the set-point stops exactly on the target with no overshoot. If no such speed exists (a new
//! target too close for the current speed) it brakes with MaxDec0n, passes the target and comes back.
//!
//! # Jerk limitation
//!
//! With JoltTime0n = N > 0 the position actually output each cycle advances by the mean of the last N
//! set-point speeds (a FIFO that starts filled with 0). The fractional remainder of each mean is carried into
//! the next cycle, so after the FIFO has drained the output has covered exactly the set-point distance and
//! stands exactly on the target (the catalogue's pick in X67-18.11.1.14-01). Planning is done on the
//! unfiltered set-point, so the filter never changes where the axis stops, only when.
//!
//! The output speed obeys MaxSpeed0npos exactly; since it is a whole number of microsteps, its change from
//! one cycle to the next may exceed MaxAcc0n/MaxDec0n by 1 microstep/cycle² of rounding while the filter is
//! on. The unfiltered set-point obeys both exactly.
//!
//! # Reversing loop
//!
//! Pick (a) of X67-18.11.1.6-03: a move in the direction of the sign of RevLoop0n first runs to
//! `target + RevLoop0n`, stops there and then approaches the target against that sign; a move against the sign
//! goes straight. Which case applies is decided from the set-point position when the target is given, and
//! again every cycle of the final approach: an axis that passes the target onto the wrong side (a new target
//! too close for its speed) runs the loop as well, so the final arrival always has the same direction.
//!
//! # Choices the seed leaves open
//!
//! - The set-point speed never changes sign within one cycle: reversing (speed mode, Stop followed by a new
//!   target, a target behind a moving axis, the loop point) passes through at least one cycle at speed 0.
//!   With the jerk FIFO on, the reversal also waits until the FIFO holds no speed of the old direction, so
//!   the output stands still before it turns and the loop point is a real stop of the axis.
//! - [`Target::Stop`] and [`Target::Speed`] never report `target_reached`.
//! - A JoltTime0n change is applied at the first standstill (set-point at rest and FIFO drained); reaching
//!   the target is such a standstill.
//!
//! Rule IDs (`X67-…`) refer to the rule catalogue of the X67SM2436 (`rules/x67.md`).

use std::collections::VecDeque;

/// Largest speed set-point accepted in speed mode, in microsteps/cycle.
pub const MAX_SPEED_SETPOINT: i32 = 65_535;

/// Largest effective JoltTime0n (FIFO length); larger values are limited to it (X67-18.11.1.14-02).
pub const MAX_JOLT_TIME: u8 = 80;

/// The cycle of the motion profile generator, from GeneralConfig01 bits 1–2 (X67-18.11.1.15-02).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Cycle {
    /// 25 ms, bits 1–2 = 00 (the default) and also the reserved 11.
    #[default]
    Ms25,
    /// 10 ms, bits 1–2 = 01.
    Ms10,
    /// 5 ms, bits 1–2 = 10.
    Ms5,
}

impl Cycle {
    /// Decodes GeneralConfig01: bits 1–2 select the cycle (00 = 25 ms, 01 = 10 ms, 10 = 5 ms). The reserved
    /// value 11 is treated like 00 (the catalogue's pick); bit 0 and bits 3–7 are ignored here
    /// (X67-18.11.1.15-02, X67-18.11.1.15-04).
    pub const fn from_general_config(general_config: u8) -> Self {
        match (general_config >> 1) & 0b11 {
            0b01 => Cycle::Ms10,
            0b10 => Cycle::Ms5,
            _ => Cycle::Ms25,
        }
    }

    /// The cycle length in milliseconds.
    pub const fn millis(self) -> u32 {
        match self {
            Cycle::Ms25 => 25,
            Cycle::Ms10 => 10,
            Cycle::Ms5 => 5,
        }
    }

    /// Converts a speed in microsteps/cycle into microsteps/second (X67-18.11.1.15-03).
    pub const fn per_second(self, speed: i64) -> i64 {
        speed * 1000 / self.millis() as i64
    }
}

/// The ramp-generator registers of one axis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Config {
    /// Ramp-generator cycle, decoded from GeneralConfig01 with [`Cycle::from_general_config`].
    pub cycle: Cycle,
    /// MaxSpeed0npos: speed limit of the absolute positioning moves in microsteps/cycle; not used in speed
    /// mode (X67-18.11.1.3-01, X67-18.11.1.3-02). 0 means no positioning move can start.
    pub max_speed_pos: u16,
    /// MaxAcc0n: largest rise of the speed magnitude per cycle, all modes (X67-18.11.1.4-01). 0 means the
    /// axis cannot start.
    pub max_acc: u16,
    /// MaxDec0n: largest fall of the speed magnitude per cycle, all modes (X67-18.11.1.5-01). 0 means a
    /// positioning move does not start, and any braking stops the ramp within one cycle (catalogue pick).
    pub max_dec: u16,
    /// JoltTime0n: FIFO length of the jerk limitation, 0 = off, values above 80 act as 80
    /// (X67-18.11.1.14-01, X67-18.11.1.14-02).
    pub jolt_time: u8,
    /// RevLoop0n: reversing loop in microsteps for the absolute positioning moves, 0 = off. A move in the
    /// direction of its sign overshoots the target by |RevLoop0n| and comes back (X67-18.11.1.6-02,
    /// X67-18.11.1.6-03).
    pub rev_loop: i16,
}

/// A set-point for the ramp generator.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Target {
    /// Brake with MaxDec0n to standstill and stay there.
    #[default]
    Stop,
    /// Absolute positioning to a position in microsteps, limited by MaxSpeed0npos, MaxAcc0n and MaxDec0n,
    /// with the reversing loop.
    Position(i64),
    /// Speed mode: ramp to this signed speed in microsteps/cycle with MaxAcc0n/MaxDec0n; clamped to
    /// ±[`MAX_SPEED_SETPOINT`]. MaxSpeed0npos and the reversing loop do not apply.
    Speed(i32),
}

/// The axis after one cycle, as [`Ramp::step`] returns it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct RampState {
    /// Output position in microsteps (the internal counter; see [`RampState::position_register`]).
    pub position: i64,
    /// Output speed: how far the position moved in this cycle, in microsteps/cycle (after jerk limitation).
    pub speed: i32,
    /// The magnitude of the output speed rose in this cycle.
    pub accelerating: bool,
    /// The magnitude of the output speed fell in this cycle.
    pub decelerating: bool,
    /// The axis stands: output speed 0 and nothing left in the set-point ramp or the jerk FIFO.
    pub standstill: bool,
    /// Position mode only: the axis stands exactly on the target after the final approach.
    pub target_reached: bool,
    /// The position bounds ([`Ramp::set_bounds`]) held the set-point back in this cycle: it was braked or
    /// kept from moving so that it does not leave them.
    pub limited: bool,
}

impl RampState {
    /// The position as the 32-bit register AbsPos0nActVal shows it: the internal counter is 32 bits wide
    /// (X67-18.6.3.3-03), so it wraps around at the DINT limits.
    pub const fn position_register(&self) -> i32 {
        self.position as i32
    }
}

/// Which point a position move is heading for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Leg {
    /// First the reversing-loop point beyond the target.
    Loop,
    /// The target itself, approached from the reversing-loop side.
    Final,
}

/// The ramp generator of one axis.
#[derive(Clone, Debug)]
pub struct Ramp {
    config: Config,
    /// JoltTime written while moving, applied at the next standstill (X67-18.11.1.14-03).
    pending_jolt: Option<u8>,
    target: Target,
    leg: Leg,
    /// Set-point (unfiltered) position and speed.
    sp_pos: i64,
    sp_speed: i64,
    /// Jerk FIFO of set-point speeds, its sum and the carried remainder of the mean.
    fifo: VecDeque<i64>,
    fifo_sum: i64,
    carry: i64,
    /// Output position and speed.
    position: i64,
    speed: i64,
    /// Position bounds the set-point never leaves (software limits), inclusive.
    bounds: Option<(i64, i64)>,
}

impl Ramp {
    /// A ramp at standstill at position 0 with this configuration and target [`Target::Stop`].
    pub fn new(config: Config) -> Self {
        Self::at(config, 0)
    }

    /// A ramp at standstill at `position` with this configuration and target [`Target::Stop`].
    pub fn at(config: Config, position: i64) -> Self {
        let mut ramp = Ramp {
            config,
            pending_jolt: None,
            target: Target::Stop,
            leg: Leg::Final,
            sp_pos: position,
            sp_speed: 0,
            fifo: VecDeque::new(),
            fifo_sum: 0,
            carry: 0,
            position,
            speed: 0,
            bounds: None,
        };
        ramp.reset_fifo();
        ramp
    }

    /// The configuration in force (a JoltTime change still pending is not shown).
    pub const fn config(&self) -> &Config {
        &self.config
    }

    /// The current set-point.
    pub const fn target(&self) -> Target {
        self.target
    }

    /// The unfiltered set-point speed of the last cycle, before jerk limitation.
    pub const fn setpoint_speed(&self) -> i64 {
        self.sp_speed
    }

    /// Replaces the configuration. Every register takes effect with the next cycle, except JoltTime0n: a
    /// change while the axis moves waits until it stands (X67-18.11.1.14-03).
    pub fn set_config(&mut self, config: Config) {
        let jolt = config.jolt_time;
        let old = self.config.jolt_time;
        self.config = Config {
            jolt_time: old,
            ..config
        };
        if jolt != old {
            self.pending_jolt = Some(jolt);
            if self.is_standstill() {
                self.apply_pending_jolt();
            }
        } else {
            self.pending_jolt = None;
        }
    }

    /// Sets a new set-point; a move in progress continues from its current position and speed. A position
    /// target decides here whether it needs the reversing loop.
    pub fn set_target(&mut self, target: Target) {
        self.target = match target {
            Target::Speed(v) => Target::Speed(v.clamp(-MAX_SPEED_SETPOINT, MAX_SPEED_SETPOINT)),
            other => other,
        };
        if let Target::Position(t) = self.target {
            self.leg = if self.needs_loop(t) {
                Leg::Loop
            } else {
                Leg::Final
            };
        }
    }

    /// The output position (the internal counter before any 32-bit wrap-around).
    pub const fn position(&self) -> i64 {
        self.position
    }

    /// Whether the axis stands: set-point and output at rest and the jerk FIFO drained.
    pub fn standstill(&self) -> bool {
        self.is_standstill()
    }

    /// Moves the axis's positions by `delta` microsteps: the output and set-point positions and a position
    /// target shift together, so no motion results and a move in progress goes on unchanged (set actual
    /// position, set home position, 32-bit wrap-around of the counter). The bounds stay where they are:
    /// they are positions of the counter (the software limits), which setting the counter does not move.
    pub fn shift(&mut self, delta: i64) {
        self.position += delta;
        self.sp_pos += delta;
        if let Target::Position(t) = self.target {
            self.target = Target::Position(t + delta);
        }
    }

    /// Stops at once, without a braking ramp: set-point and output speed become 0 where they are, the jerk
    /// FIFO is emptied (its remainder is dropped) and the target becomes [`Target::Stop`]. For the motor
    /// voltage going off and the abrupt stop of homing on stall.
    pub fn stop_now(&mut self) {
        self.sp_pos = self.position;
        self.sp_speed = 0;
        self.speed = 0;
        self.target = Target::Stop;
        self.leg = Leg::Final;
        self.reset_fifo();
    }

    /// Sets the inclusive position bounds `(lo, hi)`, `lo ≤ hi`, the set-point never leaves (software
    /// limits), or removes them. With bounds the set-point brakes with MaxDec0n so that it stops no later
    /// than at a bound; when it could no longer stop in time (bounds set while moving fast toward them) it
    /// stops abruptly at the bound, so the bound is never crossed. A position already outside the bounds
    /// may only move back toward them.
    pub fn set_bounds(&mut self, bounds: Option<(i64, i64)>) {
        self.bounds = bounds;
    }

    /// The bounds in force.
    pub const fn bounds(&self) -> Option<(i64, i64)> {
        self.bounds
    }

    /// Holds a set-point speed `next` back so that the set-point can still stop inside the bounds. Returns
    /// the speed to use and whether it was reduced.
    fn bounded(&self, next: i64) -> (i64, bool) {
        let Some((lo, hi)) = self.bounds else {
            return (next, false);
        };
        let dir = next.signum();
        if dir == 0 {
            return (0, false);
        }
        let room = if dir > 0 {
            hi - self.sp_pos
        } else {
            self.sp_pos - lo
        };
        let u = next.abs();
        let fits = |w: i64| w + self.brake_distance(w) <= room;
        if room <= 0 {
            return (0, true);
        }
        if fits(u) {
            return (next, false);
        }
        let (mut a, mut b) = (0, u);
        while a < b {
            let mid = a + (b - a + 1) / 2;
            if fits(mid) {
                a = mid;
            } else {
                b = mid - 1;
            }
        }
        // Braking harder than MaxDec0n only happens when the bounds came too late; the bound still holds.
        let prev = if self.sp_speed.signum() == dir {
            self.sp_speed.abs()
        } else {
            0
        };
        let w = a.max((prev - self.dec_step()).max(0)).min(room);
        (dir * w, true)
    }

    /// The effective FIFO length.
    fn jolt_len(&self) -> usize {
        usize::from(self.config.jolt_time.min(MAX_JOLT_TIME))
    }

    fn reset_fifo(&mut self) {
        self.fifo = VecDeque::from(vec![0; self.jolt_len()]);
        self.fifo_sum = 0;
        self.carry = 0;
    }

    fn apply_pending_jolt(&mut self) {
        if let Some(j) = self.pending_jolt.take() {
            self.config.jolt_time = j;
            self.reset_fifo();
        }
    }

    /// Set-point at rest, FIFO drained and output at rest.
    fn is_standstill(&self) -> bool {
        self.sp_speed == 0 && self.fifo_sum == 0 && self.carry == 0 && self.speed == 0
    }

    /// The reversing-loop point for target `t`, or `None` without a loop; kept inside the bounds.
    fn loop_point(&self, t: i64) -> Option<i64> {
        (self.config.rev_loop != 0).then(|| {
            let p = t + i64::from(self.config.rev_loop);
            match self.bounds {
                Some((lo, hi)) => p.max(lo).min(hi),
                None => p,
            }
        })
    }

    /// True when the set-point is on the wrong side of `t` for the final approach: the final approach runs
    /// against the sign of RevLoop0n, so it starts from the side `t + RevLoop0n` lies on.
    fn needs_loop(&self, t: i64) -> bool {
        let r = i64::from(self.config.rev_loop);
        r != 0 && (self.sp_pos - t).signum() == -r.signum()
    }

    /// Braking step: MaxDec0n, or "within one cycle" when it is 0.
    fn dec_step(&self) -> i64 {
        match self.config.max_dec {
            0 => i64::MAX / 4,
            d => i64::from(d),
        }
    }

    /// Shortest distance covered after a cycle at speed `w ≥ 0` while braking to 0: Σ max(0, w − k·dec),
    /// the sum of the m = ⌊w / dec⌋ positive terms (when dec divides w, the m-th term is 0).
    fn brake_distance(&self, w: i64) -> i64 {
        let dec = self.dec_step();
        if w <= dec {
            return 0;
        }
        let m = w / dec;
        m * w - dec * m * (m + 1) / 2
    }

    /// Next set-point speed of a positioning move towards `goal`.
    fn position_speed(&self, goal: i64) -> i64 {
        let v = self.sp_speed;
        let dist = goal - self.sp_pos;
        let dir = if dist != 0 { dist.signum() } else { v.signum() };
        if dir == 0 {
            return 0;
        }
        // The distance to go and the speed along `dir` (±1).
        let (d, u) = (dist.abs(), v * dir);
        let dec = self.dec_step();
        if u < 0 {
            // Moving away from the goal: brake first.
            return dir * (u + dec).min(0);
        }
        let acc = i64::from(self.config.max_acc);
        let vmax = i64::from(self.config.max_speed_pos);
        let lo = (u - dec).max(0);
        let mut hi = vmax.min(u + acc);
        if u == 0 && self.config.max_dec == 0 {
            hi = 0; // a positioning move does not start while MaxDec0n = 0
        }
        let hi = hi.max(lo);
        let fits = |w: i64| w + self.brake_distance(w) <= d;
        if !fits(lo) {
            return dir * lo; // cannot stop in time: brake and come back
        }
        let (mut a, mut b) = (lo, hi);
        while a < b {
            let mid = a + (b - a + 1) / 2;
            if fits(mid) {
                a = mid;
            } else {
                b = mid - 1;
            }
        }
        dir * a
    }

    /// Next set-point speed towards a signed speed `s` (speed mode and Stop). The speed is braked to 0
    /// before it accelerates in the other direction.
    fn speed_speed(&self, s: i64) -> i64 {
        let v = self.sp_speed;
        let acc = i64::from(self.config.max_acc);
        let dec = self.dec_step();
        if v != 0 && (s.signum() != v.signum() || s.abs() < v.abs()) {
            let target_mag = if s.signum() == v.signum() { s.abs() } else { 0 };
            v.signum() * (v.abs() - dec).max(target_mag)
        } else {
            let dir = if v != 0 { v.signum() } else { s.signum() };
            dir * (v.abs() + acc).min(s.abs())
        }
    }

    /// Advances the axis by one ramp-generator cycle.
    pub fn step(&mut self) -> RampState {
        if self.is_standstill() {
            self.apply_pending_jolt();
        }
        // Set-point ramp.
        let next = match self.target {
            Target::Stop => self.speed_speed(0),
            Target::Speed(s) => self.speed_speed(i64::from(s)),
            Target::Position(t) => {
                if self.leg == Leg::Final && self.needs_loop(t) {
                    self.leg = Leg::Loop; // passed the target on the wrong side: loop again
                }
                let goal = match (self.leg, self.loop_point(t)) {
                    (Leg::Loop, Some(p)) => p,
                    _ => t,
                };
                self.position_speed(goal)
            }
        };
        // With the jerk FIFO a reversal waits until the FIFO holds no speed of the old direction, so the
        // output passes through standstill and its mean never mixes both directions.
        let next = if self.sp_speed == 0 && self.fifo.iter().any(|&f| f * next < 0) {
            0
        } else {
            next
        };
        let (next, limited) = self.bounded(next);
        self.sp_speed = next;
        self.sp_pos += next;
        if let (Target::Position(t), Leg::Loop) = (self.target, self.leg) {
            // The loop point counts as reached once the output stands there too (jerk FIFO drained), so the
            // axis really stops before it turns back.
            let drained = self.fifo_sum == 0 && self.carry == 0 && self.speed == 0;
            let at_loop_point = self.loop_point(t) == Some(self.sp_pos) && next == 0 && drained;
            if at_loop_point || self.config.rev_loop == 0 {
                self.leg = Leg::Final;
            }
        }
        // Jerk limitation: mean of the last N set-point speeds, remainder carried.
        let out = if self.fifo.is_empty() {
            next
        } else {
            let n = self.fifo.len() as i64;
            self.fifo_sum += next - self.fifo.pop_front().unwrap_or(0);
            self.fifo.push_back(next);
            let total = self.fifo_sum + self.carry;
            self.carry = total.rem_euclid(n);
            total.div_euclid(n)
        };
        let prev = self.speed;
        self.speed = out;
        self.position += out;
        let standstill = self.is_standstill();
        let target_reached = standstill
            && self.leg == Leg::Final
            && matches!(self.target, Target::Position(t) if t == self.position);
        if target_reached {
            self.apply_pending_jolt();
        }
        RampState {
            position: self.position,
            speed: out as i32,
            accelerating: out.abs() > prev.abs(),
            decelerating: out.abs() < prev.abs(),
            standstill,
            target_reached,
            limited,
        }
    }
}
