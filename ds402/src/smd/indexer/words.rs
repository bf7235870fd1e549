//! The process data: the CMD_word0/1 and STATUS_word0/1 bits (Reference 6), the 20 output and
//! 20 input bytes, and the assembly of the status words from the unit's state.

use std::time::Duration;

use super::{Indexer, NetworkState, TEMPERATURE_WARNING};

/// STATUS_word0 bits (Reference 6, Figure R6.4).
pub mod stat0 {
    /// Bit 0.
    pub const MOVING_CW: u16 = 1 << 0;
    /// Bit 1.
    pub const MOVING_CCW: u16 = 1 << 1;
    /// Bit 2.
    pub const IN_HOLD_STATE: u16 = 1 << 2;
    /// Bit 3.
    pub const STOPPED: u16 = 1 << 3;
    /// Bit 4.
    pub const AT_HOME: u16 = 1 << 4;
    /// Bit 5.
    pub const ACCELERATING: u16 = 1 << 5;
    /// Bit 6.
    pub const DECELERATING: u16 = 1 << 6;
    /// Bit 7.
    pub const MOVE_COMPLETE: u16 = 1 << 7;
    /// Bit 8.
    pub const IN_ASSEMBLED_MODE: u16 = 1 << 8;
    /// Bit 9.
    pub const WAITING_FOR_SEGMENT: u16 = 1 << 9;
    /// Bit 10.
    pub const POSITION_INVALID: u16 = 1 << 10;
    /// Bit 11.
    pub const INPUT_ERROR: u16 = 1 << 11;
    /// Bit 12.
    pub const COMMAND_ERROR: u16 = 1 << 12;
    /// Bit 13.
    pub const CONFIGURATION_ERROR: u16 = 1 << 13;
    /// Bit 14.
    pub const MODULE_OK: u16 = 1 << 14;
    /// Bit 15.
    pub const MODE_FLAG: u16 = 1 << 15;
}

/// STATUS_word1 bits (Reference 6, Figure R6.5).
pub mod stat1 {
    /// Bit 0.
    pub const IN1_ACTIVE: u16 = 1 << 0;
    /// Bit 1.
    pub const IN2_ACTIVE: u16 = 1 << 1;
    /// Bit 4.
    pub const TEMPERATURE_ABOVE_90: u16 = 1 << 4;
    /// Bit 5.
    pub const PREOP_SAFEOP: u16 = 1 << 5;
    /// Bit 7.
    pub const DRIVER_FAULT: u16 = 1 << 7;
    /// Bit 9.
    pub const INVALID_JOG_CHANGE: u16 = 1 << 9;
    /// Bit 10.
    pub const LIMIT_CONDITION: u16 = 1 << 10;
    /// Bit 11.
    pub const HEARTBEAT: u16 = 1 << 11;
    /// Bit 12.
    pub const ABS_ENC_ERR: u16 = 1 << 12;
    /// Bit 13.
    pub const COMMAND_ACKNOWLEDGE: u16 = 1 << 13;
    /// Bit 14.
    pub const STALL_DETECTED: u16 = 1 << 14;
    /// Bit 15.
    pub const DRIVE_IS_ENABLED: u16 = 1 << 15;
}

/// CMD_word0 command bits (Reference 6, Figure R6.2).
pub mod cmd0 {
    /// Bit 0.
    pub const ABSOLUTE_MOVE: u16 = 1 << 0;
    /// Bit 1.
    pub const RELATIVE_MOVE: u16 = 1 << 1;
    /// Bit 2.
    pub const HOLD_MOVE: u16 = 1 << 2;
    /// Bit 3.
    pub const RESUME_MOVE: u16 = 1 << 3;
    /// Bit 4.
    pub const IMMEDIATE_STOP: u16 = 1 << 4;
    /// Bit 5.
    pub const FIND_HOME_CW: u16 = 1 << 5;
    /// Bit 6.
    pub const FIND_HOME_CCW: u16 = 1 << 6;
    /// Bit 7.
    pub const JOG_CW: u16 = 1 << 7;
    /// Bit 8.
    pub const JOG_CCW: u16 = 1 << 8;
    /// Bit 9.
    pub const PRESET_POSITION: u16 = 1 << 9;
    /// Bit 10.
    pub const RESET_ERRORS: u16 = 1 << 10;
    /// Bit 11.
    pub const PROGRAM_ASSEMBLED: u16 = 1 << 11;
    /// Bit 12.
    pub const READ_ASSEMBLED_DATA: u16 = 1 << 12;
    /// Bit 13.
    pub const RUN_ASSEMBLED_MOVE: u16 = 1 << 13;
    /// Bit 14.
    pub const PRESET_ENCODER: u16 = 1 << 14;
    /// Bit 15.
    pub const MODE_SELECT: u16 = 1 << 15;
}

/// CMD_word1 bits (Reference 6, Figure R6.3).
pub mod cmd1 {
    /// Bit 11: Backplane_Proximity_Bit (homing with CFG_Word_0 bit 11).
    pub const BACKPLANE_PROXIMITY: u16 = 1 << 11;
    /// Bit 7: a Jog command runs as a Registration move.
    pub const REGISTRATION_MOVE: u16 = 1 << 7;
    /// Bit 4: Reverse_Blend_Direction (a Blend runs CCW).
    pub const REVERSE_BLEND: u16 = 1 << 4;
    /// Bit 5: Save_to_Flash.
    pub const SAVE_TO_FLASH: u16 = 1 << 5;
    /// Bit 8: Indexed_Command (the move waits for the Start Indexed input).
    pub const INDEXED: u16 = 1 << 8;
    /// Bit 9: Assembled_Move_Type (0 Blend, 1 Dwell).
    pub const DWELL: u16 = 1 << 9;
    /// Bit 1: take the move's current from the Motor_Current word.
    pub const MOTOR_CURRENT: u16 = 1 << 1;
    /// Bit 13: Preset Position presets to the scaled encoder position.
    pub const PRESET_TO_ENCODER: u16 = 1 << 13;
    /// Bit 15: Enable_Driver.
    pub const ENABLE_DRIVER: u16 = 1 << 15;
}

/// The Heartbeat_Bit's half period (SMD-R6-067).
pub const HEARTBEAT_HALF_PERIOD: Duration = Duration::from_millis(500);

/// The 20 output bytes (`0x7000:01–08`, SMD-R6-001).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Outputs {
    /// CMD_word0.
    pub cmd0: u16,
    /// CMD_word1.
    pub cmd1: u16,
    /// Position.
    pub position: i32,
    /// Velocity.
    pub velocity: u32,
    /// Acceleration.
    pub acceleration: u16,
    /// Deceleration.
    pub deceleration: u16,
    /// Motor_Current.
    pub motor_current: u16,
    /// Jerk.
    pub jerk: u16,
}

/// The 20 input bytes (`0x6000:01–07`, SMD-R6-002).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Inputs {
    /// STATUS_word0.
    pub status0: u16,
    /// STATUS_word1.
    pub status1: u16,
    /// Motor_Position.
    pub motor_position: i32,
    /// Encoder_Position.
    pub encoder_position: i32,
    /// Trapped_Encoder_Position.
    pub trapped_encoder_position: i32,
    /// Motor_Current (×0.1 A) of the last move command.
    pub motor_current: u16,
    /// Jerk of the last move command.
    pub jerk: u16,
}

impl Indexer {
    /// STATUS_word0 as the unit reports it now (Reference 6, Figure R6.4; 0x4408 at power-up,
    /// SMD-T2-002).
    pub fn status0(&self) -> u16 {
        // Module_OK: 0 only for an internal fault (SMD-R6-051).
        let mut s = if self.internal_fault {
            0
        } else {
            stat0::MODULE_OK
        };
        let mut flag = |on: bool, bit: u16| {
            if on {
                s |= bit;
            }
        };
        // A move waiting for SYNC0 has not started yet (SMD-R1-022).
        match self.segment.filter(|_| self.sync_wait.is_none()) {
            Some(seg) => {
                flag(seg.dir > 0, stat0::MOVING_CW); // SMD-R2-016, SMD-R2-005
                flag(seg.dir < 0, stat0::MOVING_CCW); // SMD-R2-016, SMD-R2-005
                let (acc, dec) = seg.phase();
                flag(acc, stat0::ACCELERATING); // SMD-R2-017
                flag(dec, stat0::DECELERATING); // SMD-R2-018
            }
            None => flag(true, stat0::STOPPED), // SMD-R2-019
        }
        flag(self.held.is_some(), stat0::IN_HOLD_STATE); // SMD-R2-021
        flag(self.programming.is_some(), stat0::IN_ASSEMBLED_MODE); // SMD-R6-060, SMD-R2-083
        flag(
            self.programming.is_some() && self.waiting_for_segment,
            stat0::WAITING_FOR_SEGMENT, // SMD-R6-060, SMD-R2-083, SMD-R2-084, SMD-R2-086
        );
        flag(self.at_home, stat0::AT_HOME); // SMD-R2-022, SMD-R4-003
        flag(self.move_complete, stat0::MOVE_COMPLETE); // SMD-R2-020, SMD-R6-057
        flag(self.position_invalid, stat0::POSITION_INVALID); // SMD-R2-009, SMD-R2-012
        flag(self.input_error, stat0::INPUT_ERROR); // SMD-R1-030, SMD-R6-053, SMD-R6-054
        flag(self.command_error, stat0::COMMAND_ERROR); // SMD-R6-052
        flag(self.configuration_error(), stat0::CONFIGURATION_ERROR); // SMD-R5-026, SMD-T2-003
        flag(self.mode_flag, stat0::MODE_FLAG); // SMD-R6-010
        s
    }

    /// STATUS_word1 as the unit reports it now (Reference 6, Figure R6.5).
    pub fn status1(&self) -> u16 {
        // The reserved bits 2, 3, 6 and 8 read 0 (SMD-R6-070).
        let mut s = 0;
        let mut flag = |on: bool, bit: u16| {
            if on {
                s |= bit;
            }
        };
        flag(self.active(0), stat1::IN1_ACTIVE); // SMD-R6-075, SMD-R5-023
        flag(self.active(1), stat1::IN2_ACTIVE); // SMD-R6-075, SMD-R5-023
        flag(
            self.temperature > TEMPERATURE_WARNING,
            stat1::TEMPERATURE_ABOVE_90, // SMD-R6-074
        );
        // R6 STATUS_word1 bit 7 (p.81): "If the driver section … is enabled, this bit will be a 1
        // during a Overtemperature Fault"; an STO fault sets it whatever the driver (SMD-R1-002,
        // SMD-R1-020, SMD-R6-071). The current is removed either way (`driver_fault`).
        flag(
            self.sto_fault || (self.over_temperature && self.drive_enabled()),
            stat1::DRIVER_FAULT,
        );
        flag(self.invalid_jog_change, stat1::INVALID_JOG_CHANGE); // SMD-R6-069
        flag(self.stall, stat1::STALL_DETECTED); // SMD-R1-007, SMD-R6-063
        flag(self.network != NetworkState::Op, stat1::PREOP_SAFEOP); // SMD-R6-072
        flag(self.abs_encoder_error, stat1::ABS_ENC_ERR); // SMD-R1-017, SMD-R6-066
        flag(self.limit_condition.is_some(), stat1::LIMIT_CONDITION); // SMD-R6-068
        flag(
            (self.heartbeat_time.as_millis() / HEARTBEAT_HALF_PERIOD.as_millis()) % 2 == 1,
            stat1::HEARTBEAT, // SMD-R6-067: every 500 ms in Command Mode
        );
        flag(self.acknowledged.is_some(), stat1::COMMAND_ACKNOWLEDGE); // SMD-R6-064, SMD-R6-065
        flag(self.drive_enabled(), stat1::DRIVE_IS_ENABLED); // SMD-R6-030, SMD-R5-027
        s
    }

    /// The 20 input bytes as the unit reports them now (Table R6.18, SMD-R6-002).
    pub fn inputs(&self) -> Inputs {
        Inputs {
            status0: self.status0(),
            status1: self.status1(),
            // The commanded position, wrapping at 32 bits (SMD-R6-046, SMD-R2-004).
            motor_position: self.position as i32,
            encoder_position: self.encoder_position(), // SMD-R6-047, SMD-R1-015
            trapped_encoder_position: self.trapped,    // SMD-R6-048
            motor_current: self.in_current,            // SMD-R6-049
            jerk: self.in_jerk,                        // SMD-R6-050
        }
    }
}
