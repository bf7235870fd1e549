//! Assembled moves (Reference 2, "Assembled Moves"; Tables R6.14–R6.17): the programming
//! handshake, Save_to_Flash, and the Blend and Dwell runs.

use std::time::Duration;

use super::{cmd0, cmd1, Curve, Indexer, Outcome, Outputs, Purpose, POSITION_RANGE};

/// One segment of an assembled move (Table R6.17).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AssembledSegment {
    /// Relative target (its sign counts only in a Dwell move).
    pub position: i32,
    /// Velocity.
    pub velocity: u32,
    /// Acceleration.
    pub acceleration: u16,
    /// Deceleration.
    pub deceleration: u16,
    /// Jerk.
    pub jerk: u16,
}

impl AssembledSegment {
    /// The segment's speed, ramps and Jerk. Its Position is not among them: a Dwell segment's
    /// target and a Blend's segment ends are worked out from it apart. The current of an assembled
    /// move is the configured one (SMD-R6-045: a segment's Motor_Current word is reserved), set when
    /// the run starts.
    fn params(&self) -> Outputs {
        Outputs {
            velocity: self.velocity,
            acceleration: self.acceleration,
            deceleration: self.deceleration,
            jerk: self.jerk,
            ..Outputs::default()
        }
    }
}

/// Most segments of an assembled move (SMD-R2-069, SMD-R2-087).
pub const MAX_SEGMENTS: usize = 16;

/// An assembled move being run.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct AssembledRun {
    segments: Vec<AssembledSegment>,
    /// The segment running now.
    idx: usize,
    /// Dwell Move: the pause between segments; `None` for a Blend.
    dwell: Option<Duration>,
    /// A Dwell pause that ends then.
    pause_until: Option<Duration>,
    /// Blend: the cumulative segment ends (steps from the start).
    ends: Vec<f64>,
}

impl Indexer {
    /// The assembled move stored now (RAM), if any.
    pub fn assembled_program(&self) -> Option<&[AssembledSegment]> {
        self.program.as_deref()
    }

    /// The assembled-move programming handshake: Program_Assembled (bit 11) and Read_Assembled_Data
    /// (bit 12), SMD-R2-083, SMD-R2-084, SMD-R2-085, SMD-R2-086, SMD-R2-087, SMD-R2-088,
    /// SMD-R2-089, SMD-R6-016 pick.
    pub(super) fn program_handshake(&mut self, prev: Outputs, out: Outputs) {
        let rose = |bit: u16| out.cmd0 & bit != 0 && prev.cmd0 & bit == 0;
        let fell = |bit: u16| out.cmd0 & bit == 0 && prev.cmd0 & bit != 0;
        // First Block: In_Assembled_Mode and Waiting_For_Assembled_Segment (SMD-R2-083).
        if rose(cmd0::PROGRAM_ASSEMBLED) {
            if self.busy() {
                self.command_error = true;
                return;
            }
            // The old RAM program is discarded when programming starts (SMD-R2-081 gap).
            self.program = None;
            self.programming = Some(Vec::new());
            self.waiting_for_segment = true;
        }
        // The segment's checks are a move block's, Motor_Current aside.
        let valid = POSITION_RANGE.contains(&out.position)
            && self.motion_params_ok(out.velocity, out.acceleration, out.deceleration, out.jerk);
        let Some(buf) = self.programming.as_mut() else {
            return;
        };
        // Segment Block: checked and stored (SMD-R2-084).
        if rose(cmd0::READ_ASSEMBLED_DATA) && self.waiting_for_segment {
            let seg = AssembledSegment {
                position: out.position,
                velocity: out.velocity,
                acceleration: out.acceleration,
                deceleration: out.deceleration,
                jerk: out.jerk,
            };
            if valid && buf.len() < MAX_SEGMENTS {
                buf.push(seg);
            } else {
                self.command_error = true; // SMD-R2-072, SMD-R2-085, SMD-R2-087, SMD-R6-045
            }
            self.waiting_for_segment = false;
        } else if fell(cmd0::READ_ASSEMBLED_DATA) && !self.waiting_for_segment {
            self.waiting_for_segment = true; // SMD-R2-086
        }
        if fell(cmd0::PROGRAM_ASSEMBLED) {
            let program = self.programming.take();
            self.waiting_for_segment = false;
            // SMD-R2-088; with CMD_word1 bit 5, Save_to_Flash, also to flash (SMD-R2-089).
            if out.cmd1 & cmd1::SAVE_TO_FLASH != 0 {
                self.flash_program = program.clone();
                self.flash_lockout = true;
            }
            self.program = program;
        }
    }

    /// Run Assembled Move (CMD_word0 bit 13): a Blend (CMD_word1 bit 9 = 0, direction bit 4) or a
    /// Dwell Move (bit 9 = 1, the Jerk word is the dwell in ms), SMD-R2-068, SMD-R2-069,
    /// SMD-R2-070, SMD-R2-071, SMD-R2-072, SMD-R2-073, SMD-R2-074, SMD-R2-075, SMD-R2-076,
    /// SMD-R2-077, SMD-R2-078, SMD-R2-079, SMD-R2-080,
    /// SMD-R6-014.
    pub(super) fn run_assembled(&mut self, out: Outputs) -> Outcome {
        let Some(segments) = self.program.clone() else {
            return Outcome::CommandError; // SMD-R2-069 gap
        };
        // 2 to 16 segments (SMD-R2-069); not while a move runs (SMD-R2-034).
        if !(2..=MAX_SEGMENTS).contains(&segments.len()) || self.busy() || !self.can_move() {
            return Outcome::CommandError;
        }
        if self.start_blocked() {
            return Outcome::InputError;
        }
        self.held = None;
        self.move_complete = false;
        self.in_current = self.config.motor_current;
        self.in_jerk = segments[0].jerk;
        // CMD_word1 bit 9: a Dwell Move, the Jerk word the Dwell Time (SMD-R2-077, SMD-R6-003,
        // SMD-R6-015); each segment's sign its direction (SMD-R2-078, SMD-R2-080).
        if out.cmd1 & cmd1::DWELL != 0 {
            let first = segments[0];
            self.assembled = Some(AssembledRun {
                segments,
                idx: 0,
                dwell: Some(Duration::from_millis(u64::from(out.jerk))),
                pause_until: None,
                ends: Vec::new(),
            });
            let target = self.position + i64::from(first.position);
            self.run_to(target, first.params());
            if self.segment.is_none() {
                self.dwell_segment_done();
            }
            return Outcome::Accepted;
        }
        // A Blend: every segment in the direction of CMD_word1 bit 4 (SMD-R2-070), one after
        // another without stopping (SMD-R2-071).
        let dir = if out.cmd1 & cmd1::REVERSE_BLEND != 0 {
            -1
        } else {
            1
        };
        let mut sum = 0.0;
        let ends: Vec<f64> = segments
            .iter()
            .map(|g| {
                sum += f64::from(g.position.unsigned_abs());
                sum
            })
            .collect();
        let first = segments[0];
        let params = first.params();
        self.assembled = Some(AssembledRun {
            segments,
            idx: 0,
            dwell: None,
            pause_until: None,
            ends,
        });
        self.start_jog_curve(dir, f64::from(first.velocity), params, Purpose::Blend);
        Outcome::Accepted
    }

    /// A Blend after a cycle of motion: the next segment's speed at each segment end (a ramp not
    /// finished by then jumps to it, SMD-R2-076 pick), and the braking of the last segment timed to
    /// reach V_S exactly at the end (SMD-R2-075).
    pub(super) fn follow_blend(&mut self) {
        let Some(seg) = self.segment else { return };
        if seg.purpose != Purpose::Blend {
            return;
        }
        let Some(run) = self.assembled.as_mut() else {
            return;
        };
        let covered = seg.covered();
        let n = run.segments.len();
        let mut seg = seg;
        while run.idx < n - 1 && covered >= run.ends[run.idx] {
            run.idx += 1;
            let g = run.segments[run.idx];
            seg.params = g.params();
            if let Curve::Jog(j) = &mut seg.curve {
                if j.ramp.is_some() {
                    j.ramp = None;
                    j.speed = f64::from(g.velocity);
                } else {
                    j.change(
                        f64::from(g.velocity),
                        g.acceleration,
                        g.deceleration,
                        g.jerk,
                    );
                }
            }
        }
        let total = run.ends[n - 1];
        let last = run.idx == n - 1;
        self.segment = Some(seg);
        if last {
            let brake = self.stop_ramp(&seg, 0);
            let left = total - covered;
            if left <= brake.distance + brake.high * self.last_dt {
                let done = covered.round() as i64;
                self.assembled = None;
                self.run_out((total as i64 - done).max(0));
            }
        }
    }

    /// A Dwell segment ended: pause before the next, or complete (SMD-R2-077, SMD-R2-079).
    pub(super) fn dwell_segment_done(&mut self) {
        let Some(run) = self.assembled.as_mut() else {
            return;
        };
        if run.idx + 1 >= run.segments.len() {
            self.assembled = None;
            self.move_complete = true;
            return;
        }
        self.move_complete = false;
        run.pause_until = Some(self.time + run.dwell.unwrap_or_default());
    }

    /// The end of a Dwell pause starts the next segment.
    pub(super) fn dwell_pause_over(&mut self) {
        let Some(run) = self.assembled.as_mut() else {
            return;
        };
        if run.pause_until.is_none_or(|t| self.time < t) {
            return;
        }
        run.pause_until = None;
        run.idx += 1;
        let g = run.segments[run.idx];
        let target = self.position + i64::from(g.position);
        self.run_to(target, g.params());
        if self.segment.is_none() {
            self.dwell_segment_done();
        }
    }
}
