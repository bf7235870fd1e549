//! The simulated motor behind the drive: a rigid rotor (motor plus load inertia) with viscous
//! friction and a constant load torque, driven either by a servo controller or as a stepper.
//!
//! Positions are encoder counts (`f64`, the physical rotor), velocities counts/s; torques N·m. One
//! [`Motor::step`] advances the rotor by one control tick with the torque held constant over it
//! (exact integration of constant acceleration).
//!
//! - **Servo**: a cascade of a proportional position loop, a PI velocity loop and feed-forward of
//!   the demand's acceleration, of the friction and of the load torque, limited to the maximum
//!   torque (0x6072 per mille of 0x6076). The gains follow from the tick and the inertia: velocity
//!   loop bandwidth `0.25 / tick`, position loop a fifth of it, integral corner a tenth of it. On a
//!   1 ms tick a profile within the torque limit is followed to a fraction of a count.
//! - **Stepper**: the rotor is locked to the demand (less the steps it has lost) while the torque
//!   that needs (inertia × acceleration + friction + load) stays within the pull-out torque. Beyond
//!   it the rotor slips: it accelerates with the pull-out torque only, until it can catch the
//!   demand's velocity within one tick again; it then locks to the nearest full-step position, so
//!   it has fallen behind by whole full steps.
//! - **Power off**: no motor torque; the rotor coasts, slowed by the viscous friction, until its
//!   speed falls below 1 count/s, where it stands (the holding brake, or the detent torque, takes
//!   the load torque: the load does not move an unpowered motor).

use std::f64::consts::TAU;

use super::MotorKind;

/// What the drive asks of the motor for one tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Cmd {
    /// Power stage off.
    Off,
    /// Follow the demand: from `p0`/`v0` (demand at the previous tick) to `p1`/`v1` (at this one),
    /// with `v_extra` counts/s of velocity feed-forward and `t_extra` N·m of torque feed-forward
    /// (the offsets 0x60B1/0x60B2), within `t_max` N·m.
    Follow {
        p0: f64,
        v0: f64,
        p1: f64,
        v1: f64,
        v_extra: f64,
        t_extra: f64,
        t_max: f64,
    },
    /// Produce `tau` N·m, within `t_max` (cyclic synchronous torque).
    Torque { tau: f64, t_max: f64 },
}

/// The rotor and its controller.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Motor {
    pub kind: MotorKind,
    /// Counts per revolution.
    pub cpr: f64,
    /// Total inertia, kg·m².
    pub inertia: f64,
    /// Viscous friction, N·m·s/rad.
    pub friction: f64,
    /// Constant load torque, N·m, pulling towards negative positions.
    pub load: f64,
    /// Stepper pull-out torque, N·m.
    pub pull_out: f64,
    /// Full steps per revolution (stepper).
    pub full_steps: f64,
    /// Rotor position, counts.
    pub pos: f64,
    /// Rotor velocity, counts/s.
    pub vel: f64,
    /// Motor torque of the last tick, N·m.
    pub torque: f64,
    /// The torque the last tick asked for beyond what the motor gives (servo: its torque limit;
    /// stepper: its pull-out torque), and that limit, N·m; `None` when it was within.
    pub excess: Option<(f64, f64)>,
    integ: f64,
    locked: bool,
    lag: f64,
}

impl Motor {
    /// A motor standing at position 0.
    pub fn new(config: &super::MotorConfig, cpr: f64) -> Motor {
        Motor {
            kind: config.kind,
            cpr,
            inertia: config.rotor_inertia + config.load_inertia,
            friction: config.friction,
            load: config.load_torque,
            pull_out: config.pull_out_torque,
            full_steps: f64::from(config.full_steps_per_rev.max(1)),
            pos: 0.0,
            vel: 0.0,
            torque: 0.0,
            excess: None,
            integ: 0.0,
            locked: true,
            lag: 0.0,
        }
    }

    /// The encoder count of the rotor.
    pub fn count(&self) -> i64 {
        self.pos.round() as i64
    }

    /// Radians per count.
    fn k(&self) -> f64 {
        TAU / self.cpr
    }

    /// N·m per count/s² of acceleration.
    fn jc(&self) -> f64 {
        self.inertia * self.k()
    }

    /// N·m per count/s² of acceleration of the rotor and its load.
    pub fn accel_torque(&self) -> f64 {
        self.jc()
    }

    /// The viscous friction at `v` counts/s, N·m.
    pub fn friction_torque(&self, v: f64) -> f64 {
        self.friction * self.k() * v
    }

    /// Counts per full step (stepper).
    pub fn step_size(&self) -> f64 {
        self.cpr / self.full_steps
    }

    /// The deceleration (counts/s², > 0) the torque limit allows against the load: the ramp of the
    /// "current limit" and "voltage limit" option codes. A stepper's limit is its pull-out torque.
    pub fn limit_decel(&self, t_max: f64) -> f64 {
        let t = match self.kind {
            MotorKind::Servo => t_max,
            MotorKind::Stepper => self.pull_out,
        };
        let spare = t - self.load.abs();
        let spare = if spare > 0.0 { spare } else { t.abs() };
        (spare / self.jc()).max(1.0)
    }

    /// The power stage comes on with the demand at `demand`: the controller starts afresh; a
    /// stepper locks to the full-step position nearest its rotor.
    pub fn engage(&mut self, demand: f64) {
        self.integ = 0.0;
        self.locked = true;
        let step = self.step_size();
        self.lag = ((demand - self.pos) / step).round() * step;
    }

    /// Advances the rotor by `dt` seconds.
    pub fn step(&mut self, dt: f64, cmd: Cmd) {
        self.excess = None;
        match cmd {
            Cmd::Off => self.coast(dt),
            Cmd::Torque { tau, t_max } => {
                let tau = tau.clamp(-t_max, t_max);
                self.integ = 0.0;
                self.apply(tau, dt);
            }
            Cmd::Follow {
                p0,
                v0,
                p1,
                v1,
                v_extra,
                t_extra,
                t_max,
            } => match self.kind {
                MotorKind::Servo => self.servo(dt, p0, v0, v1, v_extra, t_extra, t_max),
                MotorKind::Stepper => self.stepper(dt, p1, v1),
            },
        }
    }

    /// Applies `tau` for `dt` (constant acceleration over the tick).
    fn apply(&mut self, tau: f64, dt: f64) {
        let net = tau - self.friction * self.k() * self.vel - self.load;
        let acc = net / self.jc();
        self.pos += self.vel * dt + 0.5 * acc * dt * dt;
        self.vel += acc * dt;
        self.torque = tau;
    }

    fn coast(&mut self, dt: f64) {
        self.torque = 0.0;
        self.integ = 0.0;
        if self.vel.abs() < 1.0 {
            self.vel = 0.0;
            return;
        }
        let lambda = self.friction / self.inertia;
        if lambda > 0.0 {
            let decay = (-lambda * dt).exp();
            self.pos += self.vel * (1.0 - decay) / lambda;
            self.vel *= decay;
        } else {
            self.pos += self.vel * dt;
        }
        if self.vel.abs() < 1.0 {
            self.vel = 0.0;
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn servo(
        &mut self,
        dt: f64,
        p0: f64,
        v0: f64,
        v1: f64,
        v_extra: f64,
        t_extra: f64,
        t_max: f64,
    ) {
        let jc = self.jc();
        let wv = 0.25 / dt;
        let kv = jc * wv;
        let kp = wv / 5.0;
        let ki = kv * wv / 10.0;
        let a_ff = (v1 - v0) / dt;
        let t_ff = jc * a_ff + self.friction * self.k() * self.vel + self.load + t_extra;
        let v_cmd = v0 + v_extra + kp * (p0 - self.pos);
        let e_v = v_cmd - self.vel;
        let tau = t_ff + kv * e_v + self.integ;
        let limited = tau.clamp(-t_max, t_max);
        if limited == tau {
            self.integ += ki * e_v * dt;
        } else {
            self.excess = Some((tau.abs(), t_max));
        }
        self.apply(limited, dt);
    }

    fn stepper(&mut self, dt: f64, p1: f64, v1: f64) {
        let jc = self.jc();
        let needed = jc * (v1 - self.vel) / dt + self.friction * self.k() * self.vel + self.load;
        if needed.abs() <= self.pull_out {
            if !self.locked {
                // Catching the demand's velocity within this tick: lock to the nearest full step.
                let at = self.pos + 0.5 * (self.vel + v1) * dt;
                let step = self.step_size();
                self.lag = ((p1 - at) / step).round() * step;
                self.locked = true;
            }
            self.pos = p1 - self.lag;
            self.vel = v1;
            self.torque = needed;
        } else {
            self.locked = false;
            self.excess = Some((needed.abs(), self.pull_out));
            self.apply(self.pull_out.copysign(needed), dt);
        }
    }
}
