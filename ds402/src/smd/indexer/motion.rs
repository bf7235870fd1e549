//! Motion: the running segment and its curve, Absolute and Relative moves, controlled and
//! immediate stops, Hold and Resume, and the advance of the motion each cycle.

use std::time::Duration;

use super::{
    cmd0, Indexer, InputFunction, Jog, MoveParams, Outcome, Outputs, Phase, Profile, SyncWait,
    POSITION_RANGE,
};

/// What a running motion segment is for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Purpose {
    /// An Absolute or Relative move (or its resumption) towards the segment's target.
    Move,
    /// The controlled stop of a Hold; what is held waits to be resumed.
    HoldStop(Held),
    /// A jog that runs while CMD_word0 `bit` stays 1 (the Jog bit, or Resume for a resumed jog).
    Jog {
        /// The controlling bit.
        bit: u16,
    },
    /// The controlled stop that ends a jog (Move_Complete at its end).
    JogStop,
    /// A phase of a Find Home run (what follows is in [`Homing`](super::homing::Homing)).
    Home,
    /// A Registration move that runs like a jog while CMD_word0 `bit` stays 1; a stop condition after
    /// `mrmd` steps starts the run-out of `stopping` steps.
    Registration {
        /// The controlling bit.
        bit: u16,
        /// Stopping Distance.
        stopping: i64,
        /// Minimum Registration Move Distance.
        mrmd: f64,
    },
    /// A controlled stop that ends a move without Move_Complete (Hold during homing).
    Abort,
    /// A Blend run (what follows is in [`AssembledRun`](super::assembled::AssembledRun)).
    Blend,
}

/// The curve of a segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Curve {
    /// A whole move profile.
    Profile(Profile),
    /// A deceleration from the present speed to the starting speed.
    Ramp(Phase),
    /// A jog.
    Jog(Jog),
    /// A registration run-out: `cruise` seconds at `speed`, then `ramp` (V_S … speed) run backwards,
    /// ending after `end` seconds (before the ramp's end when the Stopping Distance is shorter than
    /// the braking distance, SMD-R2-064).
    RunOut {
        /// Speed at the trigger.
        speed: f64,
        /// Time at that speed.
        cruise: f64,
        /// The braking phase.
        ramp: Phase,
        /// When the Stopping Distance is reached.
        end: f64,
    },
}

/// A running segment of motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Segment {
    /// Motor position where the segment started (whole steps).
    pub(super) origin: i64,
    /// +1 clockwise, −1 counter-clockwise.
    pub(super) dir: i64,
    /// Steps from `origin` already covered when the curve began (a stop or a registration run-out
    /// that starts mid-move).
    pub(super) base: f64,
    pub(super) curve: Curve,
    /// Time since the curve began, exact (whole nanoseconds), so a phase that ends on a cycle ends
    /// on that cycle.
    pub(super) elapsed: Duration,
    pub(super) purpose: Purpose,
    /// Where a move ends (for a held move: where the resumed move goes).
    pub(super) target: i64,
    /// The parameters in force (Deceleration and Jerk for a stop; a jog's present values).
    pub(super) params: Outputs,
}

impl Segment {
    fn duration(&self) -> f64 {
        match &self.curve {
            Curve::Profile(p) => p.total_time(),
            Curve::Ramp(r) => r.time,
            Curve::Jog(_) => f64::INFINITY,
            Curve::RunOut { end, .. } => *end,
        }
    }

    /// Seconds since the curve began.
    fn t(&self) -> f64 {
        self.elapsed.as_secs_f64()
    }

    fn finished(&self) -> bool {
        self.t() >= self.duration()
    }

    fn advance(&mut self, dt: Duration) {
        self.elapsed += dt;
        if let Curve::Jog(j) = &mut self.curve {
            j.advance(dt.as_secs_f64());
        }
    }

    /// Steps from `origin` covered now.
    pub(super) fn covered(&self) -> f64 {
        let t = self.t().min(self.duration());
        self.base
            + match &self.curve {
                Curve::Profile(p) => p.position_at(t),
                Curve::Ramp(r) => r.distance - r.distance_rising(r.time - t),
                Curve::Jog(j) => j.covered,
                Curve::RunOut {
                    speed,
                    cruise,
                    ramp,
                    ..
                } => {
                    if t <= *cruise {
                        speed * t
                    } else {
                        let u = (t - cruise).min(ramp.time);
                        speed * cruise + ramp.distance - ramp.distance_rising(ramp.time - u)
                    }
                }
            }
    }

    /// The present speed (steps/s, ≥ 0).
    pub(super) fn speed(&self) -> f64 {
        let t = self.t();
        match &self.curve {
            Curve::Profile(p) => p.speed_at(t),
            Curve::Ramp(r) => r.speed_rising(r.time - t),
            Curve::Jog(j) => j.speed_now(),
            Curve::RunOut {
                speed,
                cruise,
                ramp,
                ..
            } => {
                if t <= *cruise {
                    *speed
                } else {
                    ramp.speed_rising(ramp.time - (t - cruise).min(ramp.time))
                }
            }
        }
    }

    /// (accelerating, decelerating) now: the phase at the instant the cycle ends, each phase holding
    /// from its start up to, not including, its end. A move whose acceleration takes exactly n
    /// cycles shows Accelerating in n − 1 updates (the n-th ends at full speed), its deceleration in
    /// all of its own, and Stopped in the update it ends (the model's pick: the manual does not say
    /// which side of a boundary a status bit takes). A segment is gone once its time is up, so none
    /// is asked past its end.
    pub(super) fn phase(&self) -> (bool, bool) {
        let t = self.t();
        match &self.curve {
            Curve::Profile(p) => {
                let ta = p.accel.time;
                (t < ta, t >= ta + p.cruise_time)
            }
            Curve::Ramp(_) => (false, true),
            Curve::Jog(j) => match j.ramp {
                Some((_, up, _)) => (up, !up),
                None => (false, false),
            },
            Curve::RunOut { cruise, .. } => (false, t >= *cruise),
        }
    }
}

/// What is in its hold state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Held {
    /// An Absolute or Relative move, to be resumed to `target`.
    Move {
        /// Where it goes.
        target: i64,
    },
    /// A jog in direction `dir`.
    Jog {
        /// +1 or −1.
        dir: i64,
    },
}

/// The limit input a move in direction `dir` (+1 CW, −1 CCW) runs into.
pub(super) fn limit_towards(dir: i64) -> InputFunction {
    if dir > 0 {
        InputFunction::CwLimit
    } else {
        InputFunction::CcwLimit
    }
}

impl Indexer {
    /// Stops all motion at once (Immediate Stop, E-Stop, end limit): no deceleration, the position
    /// becomes invalid, a held move is cancelled (SMD-R2-030, SMD-R6-028, SMD-R6-059).
    pub(super) fn stop_now(&mut self) {
        self.segment = None;
        self.sync_wait = None;
        self.held = None;
        self.homing = None;
        self.assembled = None;
        self.position_invalid = true;
    }

    /// A move, jog or homing run is in progress (a homing pause included): no other move starts
    /// (SMD-R2-034).
    pub(super) fn busy(&self) -> bool {
        self.segment.is_some() || self.homing.is_some() || self.assembled.is_some()
    }

    /// An Absolute (SMD-R2-052, SMD-R2-008) or Relative (SMD-R2-053) move: the Position in range
    /// (SMD-R6-034), Absolute refused while Position_Invalid (SMD-R2-010), none while another move
    /// runs (SMD-R2-034) or with the driver disabled (SMD-R6-031).
    pub(super) fn start_move(&mut self, out: Outputs, absolute: bool) -> Outcome {
        if !POSITION_RANGE.contains(&out.position)
            || !self.params_ok(&out)
            || (absolute && self.position_invalid)
            || self.busy()
            || !self.can_move()
        {
            return Outcome::CommandError;
        }
        // SMD-R1-029, SMD-R2-040: no move starts while E-Stop or an end limit is active.
        if self.start_blocked() {
            return Outcome::InputError;
        }
        let target = if absolute {
            i64::from(out.position)
        } else {
            self.position + i64::from(out.position)
        };
        // A new move cancels a held one (SMD-R2-033).
        self.held = None;
        self.take_current_and_jerk(&out);
        self.run_to(target, out)
    }

    /// Starts the motion to `target` with the parameters of `out`: the whole profile is planned
    /// before any motion (SMD-R2-051; Reference 3, SMD-R2-048, SMD-R2-050).
    pub(super) fn run_to(&mut self, target: i64, out: Outputs) -> Outcome {
        let distance = target - self.position;
        if distance == 0 {
            // SMD-R2-054: accepted, no motion, complete.
            self.move_complete = true;
            return Outcome::Accepted;
        }
        let Ok(profile) = Profile::plan(MoveParams {
            start_speed: f64::from(self.config.starting_speed),
            speed: f64::from(out.velocity),
            accel: out.acceleration,
            decel: out.deceleration,
            jerk: out.jerk,
            distance: distance.unsigned_abs() as f64,
        }) else {
            return Outcome::CommandError;
        };
        self.segment = Some(Segment {
            origin: self.position,
            dir: distance.signum(),
            base: 0.0,
            curve: Curve::Profile(profile),
            elapsed: Duration::ZERO,
            purpose: Purpose::Move,
            target,
            params: out,
        });
        Outcome::Accepted
    }

    /// The deceleration from `seg`'s present speed (at least the starting speed) to the starting
    /// speed at its Deceleration, with the Jerk word `jerk`.
    pub(super) fn stop_ramp(&self, seg: &Segment, jerk: u16) -> Phase {
        let vs = f64::from(self.config.starting_speed);
        Phase::new(
            vs,
            seg.speed().max(vs),
            f64::from(seg.params.deceleration) * 1000.0,
            jerk,
        )
    }

    /// Turns the running segment into a deceleration from its present speed to the starting speed
    /// at its Deceleration (SMD-R2-029), ending as `purpose` says.
    pub(super) fn controlled_stop(&mut self, purpose: Purpose) {
        let Some(seg) = self.segment else { return };
        let ramp = self.stop_ramp(&seg, seg.params.jerk);
        self.segment = Some(Segment {
            base: seg.covered(),
            curve: Curve::Ramp(ramp),
            elapsed: Duration::ZERO,
            purpose,
            ..seg
        });
    }

    /// Hold Move (CMD_word0 bit 2): a controlled stop into the hold state (SMD-R2-031, SMD-R2-021),
    /// or a stop without a hold (SMD-R2-036).
    pub(super) fn hold(&mut self) {
        let Some(seg) = self.segment else {
            // A homing run or a Dwell move in a pause is abandoned; otherwise nothing to hold
            // (SMD-R2-037).
            self.homing = None;
            self.assembled = None;
            return;
        };
        match seg.purpose {
            // SMD-R2-036: a Dwell segment or a registration run-out is stopped, not held.
            Purpose::Move
                if self.assembled.is_some() || matches!(seg.curve, Curve::RunOut { .. }) =>
            {
                self.assembled = None;
                self.controlled_stop(Purpose::Abort);
            }
            Purpose::Move => {
                let ramp = self.stop_ramp(&seg, seg.params.jerk);
                let left = (seg.target - seg.origin).unsigned_abs() as f64 - seg.covered();
                if ramp.distance >= left {
                    // Already braking into the target: a hold would stop there too, so the move
                    // completes on its own deceleration (SMD-R2-031, the model's pick).
                    return;
                }
                self.controlled_stop(Purpose::HoldStop(Held::Move { target: seg.target }));
            }
            // SMD-R2-038 pick (a): a jog is held (its bit falling in the same update is the hold).
            Purpose::Jog { .. } => {
                self.controlled_stop(Purpose::HoldStop(Held::Jog { dir: seg.dir }));
            }
            // SMD-R2-036: a registration move decelerates to a stop, not held.
            Purpose::Registration { .. } => self.controlled_stop(Purpose::Abort),
            // SMD-R2-036: a Blend or Dwell move decelerates to a stop; the rest is discarded.
            Purpose::Blend => {
                self.assembled = None;
                self.controlled_stop(Purpose::Abort);
            }
            // SMD-R2-036: a homing run decelerates to a stop and is abandoned.
            Purpose::Home => {
                self.homing = None;
                self.controlled_stop(Purpose::Abort);
            }
            Purpose::HoldStop(_) | Purpose::JogStop | Purpose::Abort => {}
        }
    }

    /// Resume Move (CMD_word0 bit 3): the held move on to its target (SMD-R2-032, SMD-R6-044), or
    /// the held jog (SMD-R2-038).
    pub(super) fn resume(&mut self, out: Outputs) -> Outcome {
        let Some(held) = self.held else {
            return Outcome::CommandError; // SMD-R2-035.
        };
        if !self.params_ok(&out) || !self.can_move() {
            return Outcome::CommandError;
        }
        match held {
            Held::Move { target } => {
                if self.start_blocked() {
                    return Outcome::InputError;
                }
                // The Resume block's parameters, the original target (SMD-R6-044).
                self.held = None;
                self.take_current_and_jerk(&out);
                self.run_to(target, out)
            }
            // SMD-R2-038 pick (c): a resumed jog runs while Resume_Move stays 1.
            Held::Jog { dir } => {
                let outcome = self.jog(out, dir, cmd0::RESUME_MOVE, false);
                if outcome == Outcome::Accepted {
                    self.held = None;
                }
                outcome
            }
        }
    }

    /// Runs the motion for `dt`.
    pub(super) fn advance(&mut self, dt: Duration) {
        self.time += dt;
        if !self.mode_flag {
            self.heartbeat_time += dt;
        }
        self.last_dt = dt.as_secs_f64();
        self.homing_pause_over();
        self.dwell_pause_over();
        let Some(mut seg) = self.segment else {
            return;
        };
        let mut dt = dt;
        // DC_Sync: the motion starts 520 µs after SYNC0 (SMD-R1-022); until SYNC0 it waits.
        match self.sync_wait {
            Some(SyncWait::ForSync0) => return,
            Some(SyncWait::Delay(wait)) => {
                if dt <= wait {
                    self.sync_wait = Some(SyncWait::Delay(wait - dt));
                    return;
                }
                dt -= wait;
                self.sync_wait = None;
            }
            None => {}
        }
        seg.advance(dt);
        let before = self.position;
        let end = seg.finished();
        // A move ends exactly on its target (SMD-R2-052, SMD-R2-053); on the way its curve never
        // covers more than its distance.
        self.position = match seg.purpose {
            Purpose::Move if end => seg.target,
            _ => seg.origin + seg.dir * (seg.covered().round() as i64),
        };
        // The encoder follows the shaft, not the command (SMD-R1-012, SMD-R6-046).
        if !self.shaft_blocked {
            self.encoder_steps += self.position - before;
        }
        if end {
            self.segment = None;
            match seg.purpose {
                Purpose::Move if self.assembled.is_some() => self.dwell_segment_done(),
                // SMD-R2-020: Move_Complete at the end of a move without error.
                Purpose::Move | Purpose::JogStop => self.move_complete = true,
                // In_Hold_State once the hold's deceleration has stopped (SMD-R2-021).
                Purpose::HoldStop(h) => self.held = Some(h),
                Purpose::Home => self.homing_stopped(),
                Purpose::Jog { .. }
                | Purpose::Registration { .. }
                | Purpose::Abort
                | Purpose::Blend => {}
            }
        } else {
            self.segment = Some(seg);
            self.follow_blend();
        }
    }
}
