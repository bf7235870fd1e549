//! Command processing (Reference 6, "Command Bits Must Transition"): the edges of CMD_word0 and
//! CMD_word1, the mutually exclusive command bits, the parameter checks of a command block, the
//! dispatch of each CMD_word0 command, Reset Errors and the two presets.

use super::{cmd0, cmd1, EncoderKind, Indexer, NetworkState, Outputs};

/// Target / offset range of Absolute and Relative moves (SMD-R6-034).
pub const POSITION_RANGE: std::ops::RangeInclusive<i32> = -8_388_608..=8_388_607;

/// Highest Velocity (SMD-R6-035).
pub const MAX_VELOCITY: u32 = 2_999_999;

/// Highest Motor_Current word (×0.1 A, SMD-R6-039).
pub const MAX_MOTOR_CURRENT: u16 = 34;

/// How a command was taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Outcome {
    /// Run.
    Accepted,
    /// Refused with Command_Error.
    CommandError,
    /// Refused with Command_Error and Move_Complete (bad Jog parameters, SMD-R6-040).
    CommandErrorComplete,
    /// Refused with Input_Error (an active E-Stop or end limit).
    InputError,
}

/// The mutually exclusive CMD_word0 command bits (SMD-R1-024 pick: 0–10, 13, 14).
const EXCLUSIVE_BITS: u16 = 0x67FF;

/// The CMD_word0 commands that are moves (may be indexed, SMD-R2-090).
const MOVE_BITS: u16 = cmd0::ABSOLUTE_MOVE
    | cmd0::RELATIVE_MOVE
    | cmd0::JOG_CW
    | cmd0::JOG_CCW
    | cmd0::FIND_HOME_CW
    | cmd0::FIND_HOME_CCW
    | cmd0::RUN_ASSEMBLED_MOVE;

impl Indexer {
    /// Acts on new output data (the edges against the previous data).
    pub(super) fn take(&mut self, out: Outputs) {
        let prev = std::mem::replace(&mut self.prev, out);
        // Command_Acknowledge falls when the host clears the acknowledged bit (SMD-R6-064).
        if let Some(bit) = self.acknowledged {
            if out.cmd0 & bit == 0 {
                self.acknowledged = None;
            }
        }
        if self.network != NetworkState::Op {
            return; // SMD-R6-073: no commands outside Op.
        }
        // SMD-R6-010 gap pick: Mode_Select = 1 processes no commands and stops the heartbeat.
        self.mode_flag = out.cmd0 & cmd0::MODE_SELECT != 0;
        if self.flash_lockout || self.mode_flag {
            return;
        }
        if out.cmd1 & cmd1::BACKPLANE_PROXIMITY & !prev.cmd1 != 0 {
            self.proximity_edge();
        }
        self.program_handshake(prev, out);
        // SMD-R2-093: clearing an indexed command's bit cancels it.
        if let Some((bit, _)) = self.pending_index {
            if out.cmd0 & bit == 0 {
                self.pending_index = None;
            }
        }
        // The mutually exclusive command bits (SMD-R1-024 pick: bits 0–10, 13, 14).
        let rising = out.cmd0 & !prev.cmd0 & EXCLUSIVE_BITS;
        if rising == 0 {
            let current_edge = out.cmd1 & cmd1::MOTOR_CURRENT & !prev.cmd1;
            if current_edge != 0 {
                // SMD-R6-032 pick: the Motor_Current word applies at once.
                if out.motor_current <= MAX_MOTOR_CURRENT {
                    self.in_current = out.motor_current;
                } else {
                    self.command_error = true;
                }
            }
            return;
        }
        if (out.cmd0 & EXCLUSIVE_BITS).count_ones() > 1 || self.programming.is_some() {
            // Two command bits at 1 when one rises (SMD-R1-024: rising in the same update, R6
            // "Command Bits Must Transition", or rising while another is still 1), or a command
            // during assembled-move programming.
            self.command_error = true;
            return;
        }
        let had_motion = self.segment.is_some();
        let outcome = if out.cmd1 & cmd1::INDEXED != 0 && rising & MOVE_BITS != 0 {
            // SMD-R2-090: latched until the Start Indexed input's edge.
            self.pending_index = Some((rising, out));
            Outcome::Accepted
        } else {
            self.execute(rising, out)
        };
        // SMD-R1-021/-022, SMD-R5-022: with DC_Sync a new move waits for SYNC0.
        if !had_motion
            && self.segment.is_some()
            && rising & (MOVE_BITS | cmd0::RESUME_MOVE) != 0
            && self.config.cfg1 & crate::smd::config::CFG1_DC_SYNC != 0
        {
            self.sync_wait = Some(f64::INFINITY);
        }
        self.apply(outcome);
    }

    /// Runs the command of CMD_word0 bit `rising` with the data `out`.
    pub(super) fn execute(&mut self, rising: u16, out: Outputs) -> Outcome {
        match rising {
            cmd0::ABSOLUTE_MOVE => self.start_move(out, true),
            cmd0::RELATIVE_MOVE => self.start_move(out, false),
            cmd0::HOLD_MOVE => {
                self.hold();
                Outcome::Accepted
            }
            cmd0::RESUME_MOVE => self.resume(out),
            cmd0::IMMEDIATE_STOP => {
                self.stop_now();
                Outcome::Accepted
            }
            cmd0::JOG_CW | cmd0::JOG_CCW if out.cmd1 & cmd1::REGISTRATION_MOVE != 0 => {
                self.start_registration(out, if rising == cmd0::JOG_CW { 1 } else { -1 })
            }
            cmd0::JOG_CW => self.start_jog(out, 1),
            cmd0::JOG_CCW => self.start_jog(out, -1),
            cmd0::FIND_HOME_CW => self.find_home(out, 1),
            cmd0::FIND_HOME_CCW => self.find_home(out, -1),
            cmd0::PRESET_POSITION => self.preset_position(out),
            cmd0::RESET_ERRORS => {
                self.command_error = false;
                self.input_error = false;
                self.move_complete = false;
                self.limit_condition = None; // SMD-R6-021
                if self.stall {
                    self.stall = false;
                    self.stall_reference(); // SMD-R4-007
                }
                if self.sto_powered[0] && self.sto_powered[1] {
                    self.sto_fault = false; // SMD-R1-006, SMD-R6-022
                }
                self.acknowledged = Some(cmd0::RESET_ERRORS);
                Outcome::Accepted
            }
            cmd0::RUN_ASSEMBLED_MOVE => self.run_assembled(out),
            cmd0::PRESET_ENCODER => self.preset_encoder(out),
            _ => Outcome::CommandError,
        }
    }

    pub(super) fn apply(&mut self, outcome: Outcome) {
        match outcome {
            // Any command accepted clears At_Home (SMD-R2-022).
            Outcome::Accepted => self.at_home = false,
            Outcome::CommandError => self.command_error = true,
            Outcome::CommandErrorComplete => {
                self.command_error = true;
                self.move_complete = true;
            }
            Outcome::InputError => self.input_error = true,
        }
    }

    /// The speed, acceleration and jerk checks of a move block (SMD-R6-035 … -038).
    pub(super) fn motion_params_ok(
        &self,
        velocity: u32,
        accel: u16,
        decel: u16,
        jerk: u16,
    ) -> bool {
        (self.config.starting_speed..=MAX_VELOCITY).contains(&velocity)
            && (1..=crate::smd::profile::MAX_ACCEL).contains(&accel)
            && (1..=crate::smd::profile::MAX_ACCEL).contains(&decel)
            && jerk <= crate::smd::profile::MAX_JERK
    }

    /// Every parameter check of a move block, the current included (SMD-R6-039).
    pub(super) fn params_ok(&self, out: &Outputs) -> bool {
        self.motion_params_ok(out.velocity, out.acceleration, out.deceleration, out.jerk)
            && (out.cmd1 & cmd1::MOTOR_CURRENT == 0 || out.motor_current <= MAX_MOTOR_CURRENT)
    }

    /// Takes the move's current and jerk for the input words (SMD-R6-032, SMD-R6-050).
    pub(super) fn take_current_and_jerk(&mut self, out: &Outputs) {
        self.in_current = if out.cmd1 & cmd1::MOTOR_CURRENT != 0 {
            out.motor_current
        } else {
            self.config.motor_current
        };
        self.in_jerk = out.jerk;
    }

    fn preset_position(&mut self, out: Outputs) -> Outcome {
        if self.busy() {
            return Outcome::CommandError; // SMD-R6-027 pick.
        }
        self.position = if out.cmd1 & cmd1::PRESET_TO_ENCODER != 0 {
            // Motor Position = Encoder Position × steps per turn / counts per turn (SMD-R6-024).
            let enc = i64::from(self.encoder_position());
            let res = i64::from(self.config.encoder_resolution.max(1));
            enc * i64::from(self.config.motor_resolution) / res
        } else {
            i64::from(out.position)
        };
        self.move_complete = false;
        self.position_invalid = false;
        self.stall_reference();
        self.acknowledged = Some(cmd0::PRESET_POSITION);
        Outcome::Accepted
    }

    fn preset_encoder(&mut self, out: Outputs) -> Outcome {
        if !self.encoder_enabled() {
            return Outcome::CommandError; // SMD-R6-011 gap pick.
        }
        // The shaft's count stays; the offset makes Encoder_Position the Position word.
        let raw = i64::from(self.encoder_position()) - self.encoder_base;
        self.encoder_base = i64::from(out.position) - raw;
        if out.cmd1 & cmd1::SAVE_TO_FLASH != 0 && self.kind == EncoderKind::Absolute {
            self.flash_encoder_offset = self.encoder_base; // SMD-R6-012
        }
        self.stall_reference();
        self.acknowledged = Some(cmd0::PRESET_ENCODER);
        Outcome::Accepted
    }
}
