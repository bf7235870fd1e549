//! Find Home CW/CCW (Reference 4): the Home-input-only, Backplane_Proximity_Bit and overtravel
//! profiles, their 2 s pauses, and the home position.

use std::time::Duration;

use super::{limit_towards, Curve, Indexer, InputFunction, Outcome, Outputs, Purpose, Segment};

/// The phases of a Find Home run (Reference 4, Figures R4.1–R4.3).
#[derive(Debug, Clone, Copy, PartialEq)]
enum HomePhase {
    /// At Velocity in the requested direction, looking for the Home input (steps 1–2).
    Search,
    /// Decelerating after the Home input became active (step 3).
    Stopping1,
    /// The first 2 s pause (after step 3, or after the overtravel stop).
    Pause1 {
        /// End of the pause.
        until: Duration,
    },
    /// At Velocity opposite to the requested direction until the Home input goes inactive (4–5).
    Reverse,
    /// Decelerating after the Home input went inactive (step 6).
    Stopping2,
    /// The second 2 s pause.
    Pause2 {
        /// End of the pause.
        until: Duration,
    },
    /// Back at the starting speed until the Home input becomes active: home (step 7).
    Return,
    /// After the Backplane_Proximity_Bit edge: decelerating towards V_S, stop at the Home edge.
    Hunt,
}

/// A Find Home run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Homing {
    /// +1 for Find Home CW, −1 for CCW.
    dir: i64,
    phase: HomePhase,
    /// The command block's parameters.
    params: Outputs,
}

/// Length of each homing pause (R4 steps 3 and 6).
pub const HOMING_PAUSE: Duration = Duration::from_secs(2);

impl Indexer {
    /// Find Home CW (`dir` +1) or CCW (−1), Reference 4: the search at Velocity in the requested
    /// direction (SMD-R4-009, SMD-R4-011) with the block's parameters (SMD-R4-010); it may start
    /// with an end limit active (SMD-R2-040), not with E-Stop (SMD-R1-029).
    pub(super) fn find_home(&mut self, out: Outputs, dir: i64) -> Outcome {
        if !self.functions().contains(&Some(InputFunction::Home)) {
            return Outcome::CommandError; // SMD-R4-004 gap.
        }
        if !self.params_ok(&out) || self.busy() || !self.can_move() {
            return Outcome::CommandError;
        }
        if self.input_active(InputFunction::EStop) {
            return Outcome::InputError;
        }
        self.held = None;
        self.move_complete = false;
        self.take_current_and_jerk(&out);
        let travel_limit = limit_towards(dir);
        let proximity = self.proximity_mode();
        let phase = if self.input_active(travel_limit)
            || (!proximity && self.input_active(InputFunction::Home))
        {
            // SMD-R4-025, SMD-R4-016: start at step 4/5, backing off at once.
            HomePhase::Reverse
        } else {
            HomePhase::Search
        };
        self.homing = Some(Homing {
            dir,
            phase,
            params: out,
        });
        let run_dir = if phase == HomePhase::Reverse {
            -dir
        } else {
            dir
        };
        self.home_run(run_dir, f64::from(out.velocity), out);
        Outcome::Accepted
    }

    fn proximity_mode(&self) -> bool {
        self.config.cfg0 & crate::smd::config::CFG0_USE_BACKPLANE_PROXIMITY != 0
    }

    /// Starts a homing motion in `dir` from the starting speed towards `speed`.
    fn home_run(&mut self, dir: i64, speed: f64, params: Outputs) {
        self.start_jog_curve(dir, speed, params, Purpose::Home);
    }

    fn set_home_phase(&mut self, phase: HomePhase) {
        if let Some(h) = self.homing.as_mut() {
            h.phase = phase;
        }
    }

    /// The Home input became active (`true`) or inactive (`false`) during a homing run.
    pub(super) fn home_edge(&mut self, active: bool) {
        let Some(h) = self.homing else { return };
        match (h.phase, active) {
            // SMD-R4-012 (and SMD-R4-017: ignored until the proximity edge).
            (HomePhase::Search, true) if !self.proximity_mode() => {
                self.set_home_phase(HomePhase::Stopping1);
                self.controlled_stop(Purpose::Home);
            }
            // SMD-R4-014.
            (HomePhase::Reverse, false) => {
                self.set_home_phase(HomePhase::Stopping2);
                self.controlled_stop(Purpose::Home);
            }
            // SMD-R4-015, SMD-R4-018: stop at once, this is home.
            (HomePhase::Return | HomePhase::Hunt, true) => self.home_done(),
            _ => {}
        }
    }

    /// CMD_word1 bit 11 rose (SMD-R4-017, SMD-R4-018, SMD-R4-019, SMD-R4-020, SMD-R4-021,
    /// SMD-R4-022).
    pub(super) fn proximity_edge(&mut self) {
        let Some(h) = self.homing else { return };
        if h.phase != HomePhase::Search || !self.proximity_mode() {
            return;
        }
        self.set_home_phase(HomePhase::Hunt);
        let vs = f64::from(self.config.starting_speed);
        if let Some(Segment {
            curve: Curve::Jog(j),
            ..
        }) = self.segment.as_mut()
        {
            j.change(
                vs,
                h.params.acceleration,
                h.params.deceleration,
                h.params.jerk,
            );
        }
    }

    /// An end limit became active during a homing run (SMD-R4-023, SMD-R4-024, SMD-R4-025,
    /// SMD-R4-026, SMD-R4-027).
    pub(super) fn homing_limit(&mut self, f: InputFunction, k: usize) {
        let Some(h) = self.homing else { return };
        let travel = limit_towards(h.dir);
        let moving_that_way = self.segment.is_some_and(|s| s.dir == h.dir);
        if f == travel {
            if moving_that_way {
                // Stop at once, 2 s, then back off (Limit_Condition and Position_Invalid: the
                // catalogue's gap pick; no Input_Error).
                self.segment = None;
                self.position_invalid = true;
                self.limit_condition = Some(k);
                self.set_home_phase(HomePhase::Pause1 {
                    until: self.time + HOMING_PAUSE,
                });
            }
        } else {
            // The opposite limit: abandon (SMD-R4-026).
            self.stop_now();
            self.input_error = true;
            self.limit_condition = Some(k);
        }
    }

    /// A homing stop reached the starting speed: the 2 s pause begins (SMD-R4-012, SMD-R4-014).
    pub(super) fn homing_stopped(&mut self) {
        let Some(h) = self.homing else { return };
        let until = self.time + HOMING_PAUSE;
        match h.phase {
            HomePhase::Stopping1 => self.set_home_phase(HomePhase::Pause1 { until }),
            HomePhase::Stopping2 => self.set_home_phase(HomePhase::Pause2 { until }),
            _ => {}
        }
    }

    /// The end of a homing pause starts the next motion.
    pub(super) fn homing_pause_over(&mut self) {
        let Some(h) = self.homing else { return };
        match h.phase {
            // SMD-R4-013, SMD-R4-024: at Velocity opposite to the requested direction.
            HomePhase::Pause1 { until } if self.time >= until => {
                self.set_home_phase(HomePhase::Reverse);
                self.home_run(-h.dir, f64::from(h.params.velocity), h.params);
            }
            HomePhase::Pause2 { until } if self.time >= until => {
                // SMD-R4-015: back at V_S, with no acceleration.
                self.set_home_phase(HomePhase::Return);
                let vs = f64::from(self.config.starting_speed);
                self.home_run(h.dir, vs, h.params);
            }
            _ => {}
        }
    }

    /// Home found (SMD-R6-058): the motion stops here, Motor_Position (and an enabled encoder) read
    /// 0, the position is valid, At_Home is set, Move_Complete is not (SMD-R4-001, SMD-R4-002,
    /// SMD-R4-003).
    fn home_done(&mut self) {
        self.segment = None;
        self.homing = None;
        self.position = 0;
        if self.encoder_enabled() {
            // Encoder_Position 0 here; the shaft's count stays (an absolute encoder keeps it).
            let raw = i64::from(self.encoder_position()) - self.encoder_base;
            self.encoder_base = -raw;
        }
        self.position_invalid = false;
        self.at_home = true;
        self.stall_reference();
    }
}
