//! Homing of one axis, modes −127 and −128 (seed 002, 18.11.3.3.10): the phases of a run (waiting for
//! standstill, leaving an active level, seeking the referencing condition, braking), the reference taken at an
//! input edge, at a stall or at once, and the reference registers (18.11.3.9).

use super::config::ref_config;
use super::modes;
use super::{Axis, CycleContext, Desired, InputEdge};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum HomingPhase {
    /// Braking a moving axis before homing starts (X67-18.11.3.3.10-02 pick).
    WaitStandstill,
    /// The active level is present at the start: travel against the homing direction until it goes
    /// (X67-18.11.3.3.10-07).
    Leave,
    /// Travel in the homing direction until the condition (X67-18.11.3.3.10-06, X67-18.11.3.3.10-08).
    Seek,
    /// The reference is taken; braking with MaxDec0n.
    Brake,
    /// Homing has ended.
    Done,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Homing {
    dir: i32,
    pub(super) phase: HomingPhase,
    /// Cycles since the run started (for StallRecognitionDelay0n).
    cycles: u32,
}

/// Whether `mode` is one of the homing modes −127/−128.
pub(super) const fn is_homing(mode: i8) -> bool {
    matches!(mode, modes::HOMING_POSITIVE | modes::HOMING_NEGATIVE)
}

impl Axis {
    /// The set-point of a homing mode in Operation enable.
    pub(super) fn homing_setpoint(&mut self, ctx: &CycleContext, entered: bool) -> Desired {
        // −127 homes in the positive direction, −128 in the negative (X67-18.11.3.3.10-01).
        let dir = if self.cur_mode == modes::HOMING_POSITIVE {
            1
        } else {
            -1
        };
        // A run starts when the homing mode is selected in Operation enable or Operation enable is reached
        // with it selected; a finished run is not repeated while the mode stays (a choice of this model).
        if entered || self.homing.is_none() {
            self.homing = Some(Homing {
                dir,
                phase: HomingPhase::WaitStandstill,
                cycles: 0,
            });
        }
        let Some(mut h) = self.homing else {
            return Desired::Stop;
        };
        // The run travels at RefSpeed0n within MaxAcc0n/MaxDec0n (X67-18.11.3.3.10-03, X67-18.11.1.9-01).
        let speed = i32::from(self.config.ref_speed);
        let rc = self.config.ref_config;
        // A moving axis is braked first; the run starts at standstill (X67-18.11.3.3.10-02 pick).
        if h.phase == HomingPhase::WaitStandstill && self.ramp.standstill() {
            h.cycles = 0;
            h.phase = match rc {
                ref_config::IMMEDIATE => {
                    // RefConfig0n −128 (X67-18.11.1.11-03).
                    // Immediate referencing: store both counters at once, no motion (X67-18.11.3.3.10-10).
                    self.store_reference(self.ramp.position(), self.abr_counter());
                    HomingPhase::Done
                }
                // Homing on stall travels until the stall (X67-18.11.1.11-03, X67-18.11.3.3.10-08).
                ref_config::STALL => HomingPhase::Seek,
                _ => {
                    // Case 1: the active level is absent, seek it; case 2: it is present, leave it first
                    // (X67-18.11.3.3.10-06, X67-18.11.3.3.10-07).
                    let (input, active_high) = self.ref_input(rc);
                    if ctx.levels[input] == active_high {
                        HomingPhase::Leave
                    } else {
                        HomingPhase::Seek
                    }
                }
            };
        }
        let desired = match h.phase {
            HomingPhase::WaitStandstill | HomingPhase::Brake | HomingPhase::Done => Desired::Stop,
            HomingPhase::Leave => Desired::Speed(-dir * speed),
            HomingPhase::Seek => {
                // Homing on stall: the reference is the counter at the stall and the motor stops abruptly,
                // once StallRecognitionDelay0n cycles have passed (X67-18.11.3.3.10-08, X67-18.11.3.3.10-09,
                // X67-18.11.1.12-01).
                if rc == ref_config::STALL
                    && h.cycles >= u32::from(self.config.stall_recognition_delay)
                    && self.powered
                    && self.stall_condition(self.load_value)
                {
                    self.store_reference(self.ramp.position(), self.abr_counter());
                    self.stop_now();
                    h.phase = HomingPhase::Done;
                    Desired::Stop
                } else {
                    Desired::Speed(dir * speed)
                }
            }
        };
        if matches!(h.phase, HomingPhase::Leave | HomingPhase::Seek) {
            h.cycles += 1;
        }
        self.homing = Some(h);
        desired
    }

    /// The input and the active level of an input referencing condition (X67-18.11.1.11-01, X67-18.11.1.11-02).
    pub(super) fn ref_input(&self, rc: i8) -> (usize, bool) {
        let r_input = self.r_input();
        match rc {
            ref_config::DI4_RISING => (3, true),
            ref_config::DI4_FALLING => (3, false),
            ref_config::R_FALLING => (r_input, false),
            _ => (r_input, true),
        }
    }

    /// Stores the reference point of both counters (RefPos0nCyclicCounter/AcyclicCounter, X67-18.11.3.9-01).
    /// Homing does not change the internal counter itself (X67-18.11.3.3.10-05).
    pub(super) fn store_reference(&mut self, internal: i64, abr: i32) {
        self.ref_internal = internal as i32;
        self.ref_abr = abr;
    }

    /// An input edge in Operation enable for a homing mode: leaving the active level, or the referencing
    /// condition itself. `at_internal` and `at_abr` are the counters at the edge.
    pub(super) fn homing_edge(&mut self, edge: &InputEdge, at_internal: i64, at_abr: i32) {
        let rc = self.config.ref_config;
        if let Some(mut h) = self.homing {
            if rc != ref_config::STALL && rc != ref_config::IMMEDIATE {
                let (input, active_high) = self.ref_input(rc);
                if edge.input == input {
                    if h.phase == HomingPhase::Leave && edge.level != active_high {
                        // Case 2: the level has gone, now seek it (X67-18.11.3.3.10-07).
                        h.phase = HomingPhase::Seek;
                    } else if h.phase == HomingPhase::Seek && edge.level == active_high {
                        // The counters at the edge are the referenced zero positions, and the motor stops
                        // (X67-18.11.3.3.10-04).
                        self.store_reference(at_internal, at_abr);
                        h.phase = HomingPhase::Brake;
                        self.apply(Desired::Stop);
                    }
                }
            }
            self.homing = Some(h);
        }
    }

    /// The end of a cycle: homing has ended once the axis has braked to standstill after the reference
    /// (X67-18.11.4.2-13).
    pub(super) fn homing_braked(&mut self) {
        if let Some(mut h) = self.homing {
            if h.phase == HomingPhase::Brake && self.ramp.standstill() {
                h.phase = HomingPhase::Done;
                self.homing = Some(h);
            }
        }
    }

    /// Whether the homing run has ended (for Target reached, X67-18.11.4.2-13).
    pub(super) fn homing_done(&self) -> bool {
        matches!(
            self.homing,
            Some(Homing {
                phase: HomingPhase::Done,
                ..
            })
        )
    }
}
