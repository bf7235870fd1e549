//! The cycle of one axis: [`Axis::begin`] takes over the cyclic outputs, runs the state machine and chooses
//! the ramp's set-point from the mode, the software limits, the limit switches and the Stop bit;
//! [`Axis::finish`] reacts to the input edges of the cycle, drives the current and builds the status word.

use super::config::ref_config;
use super::homing::is_homing;
use super::modes;
use super::{Axis, CycleContext, Desired, Observation, CW_STOP};
use crate::cia402::State;
use crate::x67::current::{self, CurrentState, Phase};
use crate::x67::ramp::RampState;

impl Axis {
    /// The start of a cycle: take over the cyclic outputs, sample the error conditions, run the state machine
    /// and choose the ramp's set-point.
    pub(crate) fn begin(&mut self, ctx: &CycleContext) {
        // Cyclic outputs are taken over once per cycle (X67-18.14-02 pick).
        self.prev_cw = self.cw;
        self.cw = self.control;
        let prev_mode = self.cur_mode;
        self.cur_mode = self.mode;
        let rising = self.cw & !self.prev_cw;

        self.sample_errors(ctx, rising);
        let identification_done = self.count_identification(ctx);
        self.run_state_machine(ctx, identification_done);
        self.motor_id_trigger(ctx, rising);
        self.release_limit_hold();

        // Mode 0 re-arms the remaining-distance mode (X67-18.11.3.3.5-03).
        if self.cur_mode == modes::NONE {
            self.remaining = None;
        }

        let enabled = self.sm.state == State::OperationEnabled;
        let entered = enabled && (!self.was_enabled || self.cur_mode != prev_mode);
        if !enabled && self.was_enabled {
            // Leaving Operation enable ends a homing run; the mode's set-point is kept, so that Enable operation
            // from Quick stop active resumes the motion (X67-18.11.4.3-15).
            self.homing = None;
        }
        if self.cur_mode != prev_mode {
            // A set-point of one mode is not carried into another: after a mode change the position modes
            // wait for their own set-point (the relative base of X67-18.11.3.3.2-09 is kept). A homing run
            // needs nothing here: every mode change in Operation enable is `entered`, which starts a new run
            // when the new mode homes, and the run is read only while a homing mode is selected.
            self.active_target = None;
            self.queued = None;
        }
        self.was_enabled = enabled;
        self.set_pulse = false;

        self.ramp
            .set_config(self.ramp_config(ctx.cycle, modes::uses_rev_loop(self.cur_mode)));

        // Motion according to the Mode register only in Operation enable (X67-18.11.4.3-21).
        let desired = if enabled {
            self.mode_setpoint(ctx, entered, rising)
        } else {
            Desired::Stop
        };
        self.last_abs_pos = self.abs_pos;

        let desired = self.software_limits(desired);
        let mut desired = self.limit_switches(ctx, desired);

        // The Stop bit of the extended control word brakes in every mode (X67-18.11.3.2-02).
        if ctx.extended_cw && self.cw & CW_STOP != 0 {
            desired = Desired::Stop;
        }
        self.apply(desired);
    }

    /// The end of a cycle: react to the input edges of the cycle, drive the current and build the status
    /// word. `start` is the internal counter at the start of the cycle and `abr_start` the ABR counter.
    pub(crate) fn finish(
        &mut self,
        ctx: &CycleContext,
        ramp_state: RampState,
        start: i64,
        abr_start: i32,
    ) {
        let end = start + i64::from(ramp_state.speed);
        // The rotor path of the cycle: the ABR counter at an edge is the encoder's count at the rotor position
        // of that instant, not an interpolation between the counts at the cycle's ends.
        let rotor_end = self.motor.rotor();
        let rotor_start = rotor_end - self.motor.rotor_delta(i64::from(ramp_state.speed));
        let enabled = self.sm.state == State::OperationEnabled;
        let mut levels = ctx.levels_before;
        let mut reached = ramp_state.target_reached;
        for edge in &ctx.edges {
            let was = levels[edge.input];
            levels[edge.input] = edge.level;
            if was == edge.level {
                continue;
            }
            let at_internal = edge.at.lerp(start, end);
            let counted = self
                .motor
                .encoder_phase(edge.at.lerp(rotor_start, rotor_end))
                - self.motor.encoder_phase(rotor_start);
            let at_abr = i32::from((abr_start as i16).wrapping_add(counted as i16));
            self.limit_edge(ctx, edge);
            if !enabled {
                continue;
            }
            if is_homing(self.cur_mode) {
                self.homing_edge(edge, at_internal, at_abr);
            } else if self.mode_edge(edge, at_internal) {
                reached = false;
            }
        }
        self.homing_braked();
        // A queued single set-point starts once the current move has arrived (X67-18.11.3.3.2-05).
        if ramp_state.target_reached {
            if let Some(q) = self.queued.take() {
                self.active_target = Some(q);
            }
        }

        // Currents (X67-18.11.1.1, X67-18.11.1.2); the nominal current replaces the maximum in homing on
        // stall (X67-18.11.1.1-03).
        let identifying = self.ident_left.is_some();
        let stall_homing = is_homing(self.cur_mode)
            && self.config.ref_config == ref_config::STALL
            && self.homing.is_some();
        let cfg = current::Config {
            holding: self.config.holding_current,
            nominal: self.config.nominal_current,
            maximum: self.config.maximum_current,
            full_step_threshold: self.config.full_step_threshold,
            stall_homing,
        };
        let _ = self.current.set_config(cfg);
        let current = if self.powered {
            Some(self.current.step(
                Phase::from_ramp(&ramp_state),
                ramp_state.speed,
                ctx.cycle.millis(),
            ))
        } else if identifying {
            let percent = self.config.nominal_current;
            Some(CurrentState {
                level: current::Level::Nominal,
                percent,
                amps_milli: u32::from(percent) * current::MODULE_NOMINAL_MILLIAMPS / 100,
                full_step: false,
            })
        } else {
            None
        };

        // Mixed decay (X67-18.11.1.10-01, X67-18.11.1.10-02, X67-18.11.1.13-02): always on at or below the minimum
        // stall speed; above it 0 = off, 15 = on, 1…14 = on below 64·threshold microsteps/cycle.
        let speed = ramp_state.speed.unsigned_abs();
        let threshold = self.config.mixed_decay_threshold();
        let mixed_decay = if speed <= u32::from(self.config.stall_detect_min_speed) {
            true
        } else {
            match threshold {
                0 => false,
                15 => true,
                t => speed < 64 * u32::from(t),
            }
        };

        self.last = Observation {
            state: self.sm.state,
            ramp: ramp_state,
            powered: self.powered || identifying,
            current,
            mixed_decay,
            load_value: self.load_value,
            identifying,
        };
        self.status = self.build_status(ctx, ramp_state, reached);
    }
}
