//! Command processing (Reference 6, "Command Bits Must Transition"): the edges of CMD_word0 and
//! CMD_word1, the mutually exclusive command bits, the parameter checks of a command block, the
//! dispatch of each CMD_word0 command, Reset Errors and the two presets.

use super::{cmd0, cmd1, EncoderKind, Indexer, NetworkState, Outputs, SyncWait};

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
        let mut prev = std::mem::replace(&mut self.prev, out);
        // Command_Acknowledge falls when the host clears the acknowledged bit (SMD-R6-064).
        if let Some(bit) = self.acknowledged {
            if out.cmd0 & bit == 0 {
                self.acknowledged = None;
            }
        }
        if self.network != NetworkState::Op {
            return; // SMD-R6-073: no commands outside Op.
        }
        if std::mem::take(&mut self.edge_reference_pending) {
            // SMD-R6-073 gap pick: the first output data in Op is the edge reference; a bit already
            // 1 in it is no edge, whatever was seen before Op.
            prev = out;
        }
        // CMD_word0 bit 15, SMD-R6-010 gap pick: Mode_Select = 1 processes no commands and stops
        // the heartbeat.
        self.mode_flag = out.cmd0 & cmd0::MODE_SELECT != 0;
        // After a save to flash nothing is processed until power is cycled (SMD-R2-089).
        if self.flash_lockout || self.mode_flag {
            return;
        }
        // CMD_word1 bit 11, Backplane_Proximity_Bit: its 0→1 edge during homing (SMD-R4-017).
        if out.cmd1 & cmd1::BACKPLANE_PROXIMITY & !prev.cmd1 != 0 {
            self.proximity_edge();
        }
        // CMD_word0 bits 11 and 12: assembled-move programming (SMD-R2-083, SMD-R2-084, SMD-R2-085,
        // SMD-R2-086, SMD-R2-087, SMD-R2-088, SMD-R2-089, SMD-R6-016).
        self.program_handshake(prev, out);
        // SMD-R2-093: clearing an indexed command's bit cancels it.
        if let Some((bit, _)) = self.pending_index {
            if out.cmd0 & bit == 0 {
                self.pending_index = None;
            }
        }
        // The mutually exclusive command bits (SMD-R1-024 pick: bits 0–10, 13, 14), each acting on
        // its 0→1 edge only (SMD-R6-004, SMD-R6-005).
        let rising = out.cmd0 & !prev.cmd0 & EXCLUSIVE_BITS;
        if rising == 0 {
            // CMD_word1 bit 1 without a command edge. The reserved CMD_word1 bits are ignored
            // (SMD-R6-033 gap pick).
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
        // SMD-R6-057 (R6 STATUS_word0 bit 7: "reset to 0 when the next move command is
        // written"): a move command clears Move_Complete when it is written, whether it is then
        // accepted or refused; a Jog or Registration with a bad parameter sets it again
        // (SMD-R6-040, in `apply`).
        if rising & MOVE_BITS != 0 {
            self.move_complete = false;
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
            // CMD_word1 bit 8, Indexed_Command (SMD-R2-090): latched until the Start Indexed
            // input's edge.
            self.pending_index = Some((rising, out));
            Outcome::Accepted
        } else {
            self.execute(rising, out)
        };
        // SMD-R1-021/SMD-R1-022, SMD-R5-022: with DC_Sync a new move waits for SYNC0. Only a move
        // command or a Resume starts motion from rest.
        if !had_motion
            && self.segment.is_some()
            && self.config.cfg1 & crate::smd::config::CFG1_DC_SYNC != 0
        {
            self.sync_wait = Some(SyncWait::ForSync0);
        }
        self.apply(outcome);
    }

    /// Runs the command of CMD_word0 bit `rising` with the data `out`.
    pub(super) fn execute(&mut self, rising: u16, out: Outputs) -> Outcome {
        // The single-bit CMD_word0 commands (SMD-R6-006).
        match rising {
            // Absolute Move, bit 0 (R2 "Absolute Move"): SMD-R2-052, SMD-R2-008, SMD-R2-010.
            cmd0::ABSOLUTE_MOVE => self.start_move(out, true),
            // Relative Move, bit 1 (R2 "Relative Move"): SMD-R2-053, SMD-R2-011.
            cmd0::RELATIVE_MOVE => self.start_move(out, false),
            // Hold Move, bit 2: SMD-R2-031, SMD-R2-036, SMD-R2-037; never indexed (SMD-R2-098).
            cmd0::HOLD_MOVE => {
                self.hold();
                Outcome::Accepted
            }
            // Resume Move, bit 3: SMD-R2-032, SMD-R2-035, SMD-R2-038, SMD-R6-044.
            cmd0::RESUME_MOVE => self.resume(out),
            // Immediate Stop, bit 4: SMD-R6-028, SMD-R2-013, SMD-R2-030; never indexed
            // (SMD-R2-099).
            cmd0::IMMEDIATE_STOP => {
                self.stop_now();
                Outcome::Accepted
            }
            // A Jog bit with CMD_word1 bit 7 is a Registration move (SMD-R6-029, SMD-R2-061).
            cmd0::JOG_CW | cmd0::JOG_CCW if out.cmd1 & cmd1::REGISTRATION_MOVE != 0 => {
                self.start_registration(out, if rising == cmd0::JOG_CW { 1 } else { -1 })
            }
            // Jog CW, bit 7, and Jog CCW, bit 8 (R2 "Jog Moves"): SMD-R2-055, SMD-R6-029.
            cmd0::JOG_CW => self.start_jog(out, 1),
            cmd0::JOG_CCW => self.start_jog(out, -1),
            // Find Home CW, bit 5, and CCW, bit 6 (Reference 4): SMD-R4-009, SMD-R4-010.
            cmd0::FIND_HOME_CW => self.find_home(out, 1),
            cmd0::FIND_HOME_CCW => self.find_home(out, -1),
            // Preset Position, bit 9: SMD-R6-023, SMD-R6-024, SMD-R6-026, SMD-R6-027.
            cmd0::PRESET_POSITION => self.preset_position(out),
            // Reset Errors, bit 10 (Table R6.13): SMD-R6-017, SMD-R6-018; Configuration_Error,
            // Position_Invalid and Invalid_Jog_Change stay (SMD-R6-019, SMD-R6-020); never indexed
            // (SMD-R2-100).
            cmd0::RESET_ERRORS => {
                self.command_error = false;
                self.input_error = false; // SMD-R6-055
                self.move_complete = false;
                self.limit_condition = None; // SMD-R6-021
                if self.stall {
                    self.stall = false; // SMD-R6-063
                    self.stall_reference(); // SMD-R4-007
                }
                if self.sto_powered[0] && self.sto_powered[1] {
                    self.sto_fault = false; // SMD-R1-006, SMD-R6-022
                }
                self.acknowledged = Some(cmd0::RESET_ERRORS); // SMD-R6-064
                Outcome::Accepted
            }
            // Run Assembled Move, bit 13 (Table R6.14): SMD-R6-014, SMD-R2-068.
            cmd0::RUN_ASSEMBLED_MOVE => self.run_assembled(out),
            // Preset Encoder, bit 14 (Table R6.15): SMD-R6-011, SMD-R6-012.
            cmd0::PRESET_ENCODER => self.preset_encoder(out),
            _ => Outcome::CommandError,
        }
    }

    pub(super) fn apply(&mut self, outcome: Outcome) {
        match outcome {
            // Any command accepted clears At_Home (SMD-R2-022).
            Outcome::Accepted => self.at_home = false,
            // Command_Error stays until Reset Errors (SMD-R6-052).
            Outcome::CommandError => self.command_error = true,
            // SMD-R6-040: a Jog or Registration command with a bad parameter.
            Outcome::CommandErrorComplete => {
                self.command_error = true;
                self.move_complete = true;
            }
            // An active E-Stop or end limit refuses the move (SMD-R1-029, SMD-R2-040, SMD-R2-042,
            // SMD-R2-045).
            Outcome::InputError => self.input_error = true,
        }
    }

    /// The speed, acceleration and jerk checks of a move block (SMD-R6-035, SMD-R6-036, SMD-R6-037,
    /// SMD-R6-038).
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

    /// Preset Position (CMD_word0 bit 9, Table R6.12): Motor_Position from the Position word
    /// (SMD-R6-023) or, with CMD_word1 bit 13, from the encoder (SMD-R6-024, SMD-R4-006);
    /// Move_Complete and Position_Invalid cleared (SMD-R6-026); the encoder untouched (SMD-R4-005).
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
        self.acknowledged = Some(cmd0::PRESET_POSITION); // SMD-R6-064
        Outcome::Accepted
    }

    /// Preset Encoder (CMD_word0 bit 14, Table R6.15): Encoder_Position becomes the Position word
    /// (SMD-R6-011), Motor_Position untouched (SMD-R4-005); with Save_to_Flash on an absolute unit
    /// the offset is kept through a power cycle (SMD-R6-012, SMD-R6-013).
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
        self.acknowledged = Some(cmd0::PRESET_ENCODER); // SMD-R6-064
        Outcome::Accepted
    }
}
