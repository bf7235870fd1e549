//! The status word of one axis (seed 002, 18.11.3.5 and 18.11.4.2): the state bits from the state machine
//! plus Warning (bit 7), Target reached (bit 10) in each mode, Internal limit active (bit 11), Set-point
//! acknowledge (bit 12) and the motor load (bits 13–15).

use super::modes;
use super::{
    Axis, CycleContext, Desired, CW_STOP, SW_INTERNAL_LIMIT, SW_SETPOINT_ACK, SW_TARGET_REACHED,
};
use crate::cia402::State;
use crate::x67::ramp::{self, RampState};

impl Axis {
    /// The status word: the state bits from the state machine plus bits 7 and 10–15 (X67-18.11.3.5).
    pub(super) fn build_status(&self, ctx: &CycleContext, rs: RampState, reached: bool) -> u16 {
        let mut extra = 0;
        // Bit 7 while a warning is pending (X67-18.11.4.2-10, X67-18.11.3.13-11).
        if self.errors.has_warning() {
            extra |= crate::cia402::SW_WARNING;
        }
        if self.target_reached_bit(ctx, rs, reached) {
            extra |= SW_TARGET_REACHED;
        }
        // Bit 11: a target outside the software limits, Min > Max, or the ramp held at a limit
        // (X67-18.11.3.5-03, X67-18.11.1.17-03, X67-18.11.1.17-04).
        if self.limits_misconfigured || self.target_out_of_limits || rs.limited {
            extra |= SW_INTERNAL_LIMIT;
        }
        // Bit 12: Set-point acknowledge with the extended control word (X67-18.11.3.5-04,
        // X67-18.11.3.3.2-11).
        let ext_position = ctx.extended_cw
            && (self.cur_mode == modes::POSITION
                || self.cur_mode == modes::REMAINING_DISTANCE && self.remaining.is_none());
        if ext_position && self.ack {
            extra |= SW_SETPOINT_ACK;
        }
        // Bits 13–15: the load value with StallDetectConfig0n bit 7 (X67-18.11.1.10-04, X67-18.11.3.5-05).
        if self.config.load_in_status() {
            extra |= u16::from(self.load_value & 0x07) << 13;
        }
        self.sm.status_word(extra)
    }

    /// Status-word bit 10 (X67-18.11.4.2-11, X67-18.11.4.2-12, X67-18.11.4.2-13, X67-18.11.4.2-14, X67-18.11.4.2-15,
    /// X67-18.11.4.2-16, X67-18.11.3.3-03).
    fn target_reached_bit(&self, ctx: &CycleContext, rs: RampState, reached: bool) -> bool {
        let standstill = rs.standstill;
        if self.sm.state != State::OperationEnabled {
            return standstill;
        }
        // With the Stop bit: braking or speed 0, in every mode (X67-18.11.4.2-15, X67-18.11.4.2-16).
        if ctx.extended_cw && self.cw & CW_STOP != 0 {
            return standstill;
        }
        if self.limit_hold || self.target_out_of_limits || self.limits_misconfigured {
            return standstill;
        }
        match self.cur_mode {
            // The absolute positioning modes (X67-18.11.4.2-11).
            modes::POSITION
            | modes::MOVE_ON_INPUT
            | modes::TWO_POSITION
            | modes::FIXED_A
            | modes::FIXED_B => match self.applied {
                Desired::Position { .. } => reached,
                _ => standstill,
            },
            // Only the end position after the trigger counts (X67-18.11.3.3.5-04).
            modes::REMAINING_DISTANCE => self.remaining.is_some() && reached,
            // Speed mode: the set-point speed is reached (X67-18.11.4.2-12).
            modes::SPEED => {
                let s = self
                    .abs_pos
                    .clamp(-ramp::MAX_SPEED_SETPOINT, ramp::MAX_SPEED_SETPOINT);
                rs.speed == s && self.ramp.setpoint_speed() == i64::from(s)
            }
            // Low for the cycle of the set (X67-18.11.4.2-14).
            modes::SET_HOME | modes::SET_POSITION => !self.set_pulse,
            // Homing has ended (X67-18.11.4.2-13).
            modes::HOMING_POSITIVE | modes::HOMING_NEGATIVE => self.homing_done() && standstill,
            _ => standstill,
        }
    }
}
