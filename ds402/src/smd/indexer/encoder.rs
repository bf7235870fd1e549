//! The encoder (Reference 1, "Encoder Functionality"): its count, the shaft turned from outside,
//! the absolute encoder's error, and stall detection against it.

use std::time::Instant;

use super::{EncoderKind, Indexer, CFG0_USE_ENCODER};

/// Shaft acceleration while unpowered above which the absolute encoder loses count (°/s²,
/// SMD-R1-017).
pub const ABS_ENCODER_MAX_ACCEL: f64 = 160_000.0;

impl Indexer {
    pub(super) fn encoder_enabled(&self) -> bool {
        self.config.cfg0 & CFG0_USE_ENCODER != 0
    }

    /// The shaft is held (a hard stop) or free from `now`: while held, the encoder does not follow
    /// the motor. The motion of the exchanges from the next on sees it.
    pub fn set_shaft_blocked(&mut self, _now: Instant, blocked: bool) {
        self.shaft_blocked = blocked;
    }

    /// Turns the shaft from outside by `counts` encoder counts at `now` (a hand, a falling load):
    /// counted at once; the stall check compares it at the next exchange (SMD-R1-008).
    pub fn turn_shaft(&mut self, _now: Instant, counts: i64) {
        self.encoder_extra += counts;
    }

    /// Takes a new reference for the stall comparison (SMD-R1-007 pick).
    pub(super) fn stall_reference(&mut self) {
        self.stall_ref = (self.position, i64::from(self.encoder_position()));
    }

    /// Checks for a stall: with Use_Encoder and Enable_Stall_Detection, more than 45° between the
    /// motor's and the encoder's turning since the reference (SMD-R1-007, SMD-R1-008, SMD-R1-009,
    /// SMD-R1-010, SMD-R1-011).
    pub(super) fn check_stall(&mut self) {
        use crate::smd::config::CFG0_ENABLE_STALL_DETECTION;
        let on = CFG0_USE_ENCODER | CFG0_ENABLE_STALL_DETECTION;
        if self.config.cfg0 & on != on || self.stall {
            return;
        }
        let motor_res = f64::from(self.config.motor_resolution.max(1));
        let enc_res = f64::from(self.config.encoder_resolution.max(1));
        let motor_deg = (self.position - self.stall_ref.0) as f64 * 360.0 / motor_res;
        let enc_deg =
            (i64::from(self.encoder_position()) - self.stall_ref.1) as f64 * 360.0 / enc_res;
        if (motor_deg - enc_deg).abs() > 45.0 {
            self.stall = true;
            self.stop_now();
        }
    }

    pub(super) fn encoder_position(&self) -> i32 {
        if self.encoder_enabled() {
            let counts = (self.encoder_steps as i128 * i128::from(self.config.encoder_resolution))
                .div_euclid(i128::from(self.config.motor_resolution.max(1)));
            (i128::from(self.encoder_base) + counts + i128::from(self.encoder_extra)) as i64 as i32
        } else {
            0
        }
    }

    /// A battery or encoder fault of an absolute-encoder unit is present (`true`) or gone
    /// (`false`) from `now`. Present, it sets Abs_Enc_Err at once; the bit then stays set until power is
    /// cycled, and a fault still present at power-up sets it again (SMD-R6-066: R6 STATUS_word1
    /// bit 12, "cycle power to the unit. If the bit remains set, contact AMCI").
    pub fn set_abs_encoder_fault(&mut self, _now: Instant, fault: bool) {
        self.abs_encoder_fault = fault && self.kind == EncoderKind::Absolute;
        if self.abs_encoder_fault {
            self.abs_encoder_error = true;
        }
    }
}
