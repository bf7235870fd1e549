//! The values of the Mode register (X67-18.11.3.3-01) and the set-point each mode gives the ramp in Operation
//! enable: position mode with and without the extended control word (18.11.3.3.1/18.11.3.3.2), speed mode
//! (18.11.3.3.3), set home and set position (18.11.3.3.4/18.11.3.3.6), remaining distance (18.11.3.3.5),
//! the input-driven modes (18.11.3.3.7–18.11.3.3.9). The homing modes are in the axis's `homing` module.

/// 0: no mode selected.
pub const NONE: i8 = 0;
/// 1: position mode.
pub const POSITION: i8 = 1;
/// 2: speed mode.
pub const SPEED: i8 = 2;
/// −120: set home position.
pub const SET_HOME: i8 = -120;
/// −121: remaining distance mode.
pub const REMAINING_DISTANCE: i8 = -121;
/// −122: set actual position.
pub const SET_POSITION: i8 = -122;
/// −123: move to the target on a rising edge of the axis's input.
pub const MOVE_ON_INPUT: i8 = -123;
/// −124: two-position mode.
pub const TWO_POSITION: i8 = -124;
/// −125: move to fixed position A.
pub const FIXED_A: i8 = -125;
/// −126: move to fixed position B.
pub const FIXED_B: i8 = -126;
/// −127: positive homing.
pub const HOMING_POSITIVE: i8 = -127;
/// −128: negative homing.
pub const HOMING_NEGATIVE: i8 = -128;

use super::config::ref_config;
use super::{
    Axis, CycleContext, Desired, InputEdge, CW_CHANGE_IMMEDIATELY, CW_NEW_SETPOINT, CW_RELATIVE,
};
use crate::x67::ramp;

/// The modes that use the reversing loop (X67-18.11.1.6-01); mode −121 ignores it (X67-18.11.3.3.5-06).
pub(super) const fn uses_rev_loop(mode: i8) -> bool {
    matches!(
        mode,
        POSITION | MOVE_ON_INPUT | TWO_POSITION | FIXED_A | FIXED_B
    )
}

impl Axis {
    /// The set-point of the selected mode in Operation enable.
    pub(super) fn mode_setpoint(
        &mut self,
        ctx: &CycleContext,
        entered: bool,
        rising: u16,
    ) -> Desired {
        let r_input = self.r_input();
        let abs_changed = self.abs_pos != self.last_abs_pos;
        match self.cur_mode {
            // Mode 1: AbsPos0n is the target in microsteps (X67-18.11.3.3.1-01, X67-18.11.3.3.1-02,
            // X67-18.11.3.1-01); the extended control word's handshake is in `position_mode` (18.11.3.3.2).
            POSITION => self.position_mode(ctx.extended_cw, rising, true),
            // Mode 2: the signed speed set-point, clamped to ±65535 (X67-18.11.3.3.3-01, X67-18.11.3.3.3-02,
            // X67-18.11.3.1-02).
            SPEED => Desired::Speed(
                self.abs_pos
                    .clamp(-ramp::MAX_SPEED_SETPOINT, ramp::MAX_SPEED_SETPOINT),
            ),
            SET_HOME => {
                if entered || abs_changed {
                    // new actual = old actual + (AbsPos0n − reference); the reference becomes AbsPos0n
                    // (X67-18.11.3.3.4-01). Only reached in Operation enable (X67-18.11.3.3.4-02).
                    let delta = self.abs_pos.wrapping_sub(self.ref_internal);
                    self.ramp.shift(i64::from(delta));
                    self.ref_internal = self.abs_pos;
                    self.set_pulse = true;
                }
                Desired::Stop
            }
            SET_POSITION => {
                if entered || abs_changed {
                    // AbsPos0n becomes the internal counter without motion, in Operation enable only
                    // (X67-18.11.3.3.6-01, X67-18.11.3.3.6-02).
                    let delta = self.abs_pos.wrapping_sub(self.internal_counter());
                    self.ramp.shift(i64::from(delta));
                    self.set_pulse = true;
                }
                Desired::Stop
            }
            // Mode −121: like mode 1 before the trigger, then the end position of the trigger without the
            // reversing loop (X67-18.11.3.3.5-01, X67-18.11.3.3.5-03, X67-18.11.3.3.5-06).
            REMAINING_DISTANCE => match self.remaining {
                Some(target) => Desired::Position {
                    target,
                    rev_loop: false,
                },
                None => self.position_mode(ctx.extended_cw, rising, false),
            },
            // Mode −123: the target taken at the last rising edge (X67-18.11.3.3.7-01, X67-18.11.3.3.7-02).
            MOVE_ON_INPUT => match self.active_target {
                Some(target) => Desired::Position {
                    target,
                    rev_loop: true,
                },
                None => Desired::Stop,
            },
            // Mode −124: the input level selects FixedPos0na or FixedPos0nb, also during a move
            // (X67-18.11.3.3.8-01, X67-18.11.3.3.8-02). Modes −124…−126 do not read AbsPos0n (X67-18.11.3.1-03).
            TWO_POSITION => Desired::Position {
                target: if ctx.levels[r_input] {
                    self.config.fixed_pos_a
                } else {
                    self.config.fixed_pos_b
                },
                rev_loop: true,
            },
            // Modes −125/−126 (X67-18.11.3.3.9-01, X67-18.11.1.7-01, X67-18.11.1.8-01).
            FIXED_A => Desired::Position {
                target: self.config.fixed_pos_a,
                rev_loop: true,
            },
            FIXED_B => Desired::Position {
                target: self.config.fixed_pos_b,
                rev_loop: true,
            },
            HOMING_POSITIVE | HOMING_NEGATIVE => self.homing_setpoint(ctx, entered),
            // Mode 0 and the unlisted values: no motion (X67-18.11.3.3-02, X67-18.11.3.3-05).
            _ => Desired::Stop,
        }
    }

    /// Mode 1 (and mode −121 before its trigger): AbsPos0n directly, or through the New-set-point handshake
    /// with the extended control word (X67-18.11.3.3.1, X67-18.11.3.3.2).
    fn position_mode(&mut self, extended: bool, rising: u16, rev_loop: bool) -> Desired {
        if !extended {
            // Without the extended control word AbsPos0n is the target at once (X67-18.11.3.3.1-02).
            self.ack = false;
            return Desired::Position {
                target: self.abs_pos,
                rev_loop,
            };
        }
        // With the extended control word AbsPos0n alone changes nothing (X67-18.11.3.3.2-01).
        // The handshake: ↑ New set-point while Set-point acknowledge is 0 (X67-18.11.3.3.2-02, X67-18.11.3.3.2-03).
        if rising & CW_NEW_SETPOINT != 0 && !self.ack {
            // Bits 5 and 6 are sampled with the set-point (X67-18.11.3.3.2-03 pick). A relative set-point
            // builds on the last target (X67-18.11.3.3.2-07, X67-18.11.3.3.2-08, X67-18.11.3.3.2-09,
            // X67-18.11.3.3.2-10).
            let target = if self.cw & CW_RELATIVE != 0 {
                self.last_setpoint.wrapping_add(self.abs_pos)
            } else {
                self.abs_pos
            };
            self.last_setpoint = target;
            self.ack = true;
            // Change set immediately, or a single set-point queued behind the current move
            // (X67-18.11.3.3.2-05, X67-18.11.3.3.2-06).
            let idle = self.active_target.is_none() || self.last.ramp.target_reached;
            if self.cw & CW_CHANGE_IMMEDIATELY != 0 || idle {
                self.active_target = Some(target);
                self.queued = None;
            } else {
                self.queued = Some(target);
            }
        }
        // Set-point acknowledge drops once New set-point is 0 again (X67-18.11.3.3.2-04, X67-18.11.3.3.2-11).
        if self.cw & CW_NEW_SETPOINT == 0 && self.queued.is_none() {
            self.ack = false;
        }
        match self.active_target {
            Some(target) => Desired::Position { target, rev_loop },
            None => Desired::Stop,
        }
    }

    /// The trigger edge of mode −121: falling for RefConfig0n −122/−126, rising otherwise, on DI3/DI6
    /// (X67-18.11.3.3.5-05 pick).
    fn remaining_trigger_rising(&self) -> bool {
        !matches!(
            self.config.ref_config,
            ref_config::DI4_FALLING | ref_config::R_FALLING
        )
    }

    /// An input edge in Operation enable for the input-driven modes −121 and −123. `at_internal` is the
    /// internal counter at the edge. Returns whether the edge gave the mode a new target, so that the cycle's
    /// Target reached drops.
    pub(super) fn mode_edge(&mut self, edge: &InputEdge, at_internal: i64) -> bool {
        let r_input = self.r_input();
        match self.cur_mode {
            REMAINING_DISTANCE
                if self.remaining.is_none()
                    && edge.input == r_input
                    && edge.level == self.remaining_trigger_rising() =>
            {
                // The new target is the actual position at the edge plus FixedPos0na
                // (X67-18.11.3.3.5-02); AbsPos0n is ignored from here on (X67-18.11.3.3.5-03).
                let target = (at_internal as i32).wrapping_add(self.config.fixed_pos_a);
                self.remaining = Some(target);
                true
            }
            MOVE_ON_INPUT if edge.input == r_input && edge.level => {
                // The target is taken now: the ramp has it from here on, so bit 10 drops in this cycle
                // (X67-18.11.3.3.7-01, X67-18.11.3.3.7-03, X67-18.11.4.2-11).
                self.active_target = Some(self.abs_pos);
                self.apply(Desired::Position {
                    target: self.abs_pos,
                    rev_loop: true,
                });
                true
            }
            _ => false,
        }
    }
}
