//! Jog moves (Reference 2, "Jog Moves"): the open-ended curve, its speed changes while it runs,
//! Invalid_Jog_Change and the stop when its bit falls.

use std::time::Duration;

use super::{
    cmd0, limit_towards, Curve, Indexer, InputFunction, Outcome, Outputs, Phase, Purpose, Segment,
};

/// An open-ended jog: runs at `speed`, ramping to a new speed when told.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Jog {
    /// The speed it runs at (or ramps to).
    pub(super) speed: f64,
    /// A speed change in progress: the phase (low → high), whether it rises, and its elapsed time.
    pub(super) ramp: Option<(Phase, bool, f64)>,
    /// Steps covered so far.
    pub(super) covered: f64,
}

impl Jog {
    /// A jog from the starting speed `vs` ramping to `to` with the Acceleration, Deceleration and
    /// Jerk words of `p`.
    fn starting(vs: f64, to: f64, p: &Outputs) -> Jog {
        let mut jog = Jog {
            speed: vs,
            ramp: None,
            covered: 0.0,
        };
        jog.change(to, p.acceleration, p.deceleration, p.jerk);
        jog
    }

    pub(super) fn speed_now(&self) -> f64 {
        match self.ramp {
            Some((p, true, t)) => p.speed_rising(t),
            Some((p, false, t)) => p.speed_rising(p.time - t),
            None => self.speed,
        }
    }

    /// Ramps from the present speed to `to` (steps/s) at `accel`/`decel` (steps/s²).
    /// A new target speed `to`, reached from the present speed with the Acceleration or Deceleration
    /// word (in 1,000 steps/s²) and the Jerk word.
    pub(super) fn change(&mut self, to: f64, accel: u16, decel: u16, jerk: u16) {
        let (accel, decel) = (f64::from(accel) * 1000.0, f64::from(decel) * 1000.0);
        let v = self.speed_now();
        self.ramp = if to > v {
            Some((Phase::new(v, to, accel, jerk), true, 0.0))
        } else if to < v {
            Some((Phase::new(to, v, decel, jerk), false, 0.0))
        } else {
            None
        };
        self.speed = to;
    }

    pub(super) fn advance(&mut self, mut dt: f64) {
        if let Some((p, up, t)) = &mut self.ramp {
            let step = dt.min(p.time - *t).max(0.0);
            let d = if *up {
                p.distance_rising(*t + step) - p.distance_rising(*t)
            } else {
                p.distance_rising(p.time - *t) - p.distance_rising(p.time - *t - step)
            };
            self.covered += d;
            *t += step;
            dt -= step;
            if *t >= p.time {
                self.ramp = None;
            }
        }
        self.covered += self.speed * dt;
    }
}

impl Indexer {
    /// A jog or a registration move runs (the Stop Jog/Registration input acts on these).
    pub(super) fn jogging(&self) -> bool {
        matches!(
            self.segment,
            Some(s) if matches!(s.purpose, Purpose::Jog { .. } | Purpose::Registration { .. })
        )
    }

    /// Jog_CW (`dir` +1) or Jog_CCW (−1), CMD_word0 bits 7 and 8 (SMD-R2-055, SMD-R2-056).
    pub(super) fn start_jog(&mut self, out: Outputs, dir: i64) -> Outcome {
        let bit = if dir > 0 { cmd0::JOG_CW } else { cmd0::JOG_CCW };
        self.jog(out, dir, bit, true)
    }

    /// A jog in `dir` that runs while CMD_word0 `bit` stays 1 (a new one, or a held jog resumed
    /// under Resume_Move, SMD-R2-038): it starts at V_S and accelerates to Velocity (SMD-R2-056).
    pub(super) fn jog(&mut self, out: Outputs, dir: i64, bit: u16, fresh: bool) -> Outcome {
        if !self.params_ok(&out) {
            // SMD-R6-040: a Jog with bad parameters also sets Move_Complete.
            return Outcome::CommandErrorComplete;
        }
        if self.busy() || !self.can_move() {
            return Outcome::CommandError;
        }
        // SMD-R1-029; SMD-R2-042/SMD-R2-045: not into an active limit (away from one is allowed,
        // SMD-R2-043/SMD-R2-046).
        let into = limit_towards(dir);
        if self.input_active(InputFunction::EStop) || self.input_active(into) {
            return Outcome::InputError;
        }
        if fresh {
            self.held = None;
            self.move_complete = false;
        }
        self.take_current_and_jerk(&out);
        self.invalid_jog_change = false;
        self.start_jog_curve(dir, f64::from(out.velocity), out, Purpose::Jog { bit });
        Outcome::Accepted
    }

    /// Starts an open-ended motion in `dir` from the starting speed towards `to` steps/s with the
    /// ramps of `params` (a jog, a registration move, a homing phase, a Blend).
    pub(super) fn start_jog_curve(&mut self, dir: i64, to: f64, params: Outputs, purpose: Purpose) {
        let vs = f64::from(self.config.starting_speed);
        self.segment = Some(Segment {
            origin: self.position,
            dir,
            base: 0.0,
            curve: Curve::Jog(Jog::starting(vs, to, &params)),
            elapsed: Duration::ZERO,
            purpose,
            target: self.position,
            params,
        });
    }

    /// While a jog runs: its bit falling ends it with a controlled stop (SMD-R2-057); new Velocity,
    /// Acceleration and Deceleration values take effect, invalid ones set Invalid_Jog_Change and are
    /// ignored (SMD-R2-058, SMD-R2-059, SMD-R2-060, SMD-R6-069). A Registration move keeps the
    /// values "set with the command" (R2 Registration Moves NOTE): only a Jog Move's speed and
    /// ramps "can be changed while the move is in progress" (R2 Jog Moves).
    pub(super) fn follow_jog(&mut self, out: Outputs) {
        let jog = match self.segment {
            Some(
                seg @ Segment {
                    purpose: Purpose::Jog { bit },
                    ..
                },
            ) => {
                if out.cmd0 & bit == 0 {
                    self.controlled_stop(Purpose::JogStop);
                    return;
                }
                Some(seg)
            }
            Some(
                seg @ Segment {
                    purpose:
                        Purpose::Registration {
                            bit,
                            stopping,
                            mrmd,
                        },
                    ..
                },
            ) => {
                // SMD-R2-063, SMD-R2-066, SMD-R2-067: level-triggered stop conditions, from the
                // MRMD on.
                let stop_input = self.input_active(InputFunction::StopJog);
                if (out.cmd0 & bit == 0 || stop_input) && seg.covered() >= mrmd {
                    self.run_out(stopping);
                }
                None
            }
            _ => None,
        };
        let Some(seg) = jog else {
            // No jog runs: Invalid_Jog_Change "will reset when valid jog data is sent from the
            // host controller" (R6 STATUS_word1 bit 9), a jog running or not (SMD-R6-069).
            if self.motion_params_ok(out.velocity, out.acceleration, out.deceleration, out.jerk) {
                self.invalid_jog_change = false;
            }
            return;
        };
        let jerk = out.jerk;
        let p = seg.params;
        if (out.velocity, out.acceleration, out.deceleration, jerk)
            == (p.velocity, p.acceleration, p.deceleration, p.jerk)
        {
            self.invalid_jog_change = false;
            return;
        }
        if !self.motion_params_ok(out.velocity, out.acceleration, out.deceleration, jerk) {
            self.invalid_jog_change = true;
            return;
        }
        self.invalid_jog_change = false;
        let Some(seg) = self.segment.as_mut() else {
            return;
        };
        if let Curve::Jog(j) = &mut seg.curve {
            if out.velocity != p.velocity {
                j.change(
                    f64::from(out.velocity),
                    out.acceleration,
                    out.deceleration,
                    jerk,
                );
            }
        }
        seg.params.velocity = out.velocity;
        seg.params.acceleration = out.acceleration;
        seg.params.deceleration = out.deceleration;
        seg.params.jerk = jerk;
    }
}
