//! The state machine of one axis and what feeds it (seed 002, 18.11.4 and 18.11.3.13): the error and warning
//! conditions sampled every cycle, the Warning reset, the start-up and triggered motor identification, and
//! the actions of the CiA 402 transitions ([`crate::cia402`]) carried out on the motor.

use super::{Axis, CycleContext, CW_MOTOR_ID};
use crate::cia402::{Action, Inputs};
use crate::x67::current::{self, CurrentModel};
use crate::x67::errors::{ErrorCode, CW_STALL_DETECTION, CW_WARNING_RESET};
use crate::x67::motor;

impl Axis {
    /// Samples the error and warning conditions of this cycle into the error register (X67-18.11.3.13) and
    /// carries out a Warning reset (↑ CW bit 12). `rising` holds the control-word bits that rose this cycle.
    pub(super) fn sample_errors(&mut self, ctx: &CycleContext, rising: u16) {
        // Detection bits 13/15 and Warning reset (X67-18.11.3.2-07, X67-18.11.3.2-09).
        self.errors.control_word(self.cw);
        // The Error-type conditions: supply voltage and overtemperature, module-wide or of the output stage
        // (X67-3-11, X67-15-01, X67-18.6.3.1-02, X67-18.11.3.13-02, X67-18.11.3.13-03, X67-18.11.3.13-12).
        self.errors
            .set_condition(ErrorCode::Voltage, ctx.supply_error);
        self.errors.set_condition(
            ErrorCode::Overtemperature,
            ctx.over_temperature || self.motor.faults.output_stage_overtemperature,
        );
        // The warnings of the powered motor: open circuit, current error, overcurrent
        // (X67-18.6.3.1-03, X67-18.6.3.1-04, X67-18.11.3.13-06, X67-18.11.3.13-07, X67-18.11.3.13-09).
        let powered = self.powered || self.ident_left.is_some();
        let speed_ps = self.speed_per_second(ctx.cycle);
        let faults = self.motor.faults;
        self.errors
            .set_condition(ErrorCode::OpenCircuit, powered && faults.open_winding);
        self.errors.set_condition(
            ErrorCode::CurrentError,
            powered && (faults.open_winding || self.motor.back_emf_exceeded(speed_ps)),
        );
        self.errors
            .set_condition(ErrorCode::Overcurrent, powered && faults.short);
        // Stall (X67-18.6.1.1-02, X67-18.11.3.13-08); StallRecognitionDelay0n plays no part outside homing on
        // stall (X67-18.11.1.12-02).
        self.load_value = self.motor.load_value(speed_ps);
        let stall = powered && self.stall_condition(self.load_value);
        self.errors.set_condition(ErrorCode::Stall, stall);
        // The Warning reset of this cycle acknowledges against the conditions of this cycle: the reset in
        // `control_word` above saw those of the last cycle and latched again a warning whose cause has gone
        // since (X67-18.11.3.2-06, X67-18.11.4.1-10).
        if rising & CW_WARNING_RESET != 0 {
            self.errors.warning_reset();
        }
    }

    /// Counts down the start-up identification (X67-18.11.4.3-07): 1.0 s of cycles. Returns whether it ended
    /// in this cycle.
    pub(super) fn count_identification(&mut self, ctx: &CycleContext) -> bool {
        let mut identification_done = false;
        if let Some(left) = self.ident_left {
            if left <= 1 {
                self.ident_left = None;
                identification_done = true;
                self.measure_identification(ctx.supply_volts);
            } else {
                self.ident_left = Some(left - 1);
            }
        }
        identification_done
    }

    /// One step of the state machine with this cycle's control word (X67-18.11.4.1, X67-18.11.4.3), and the
    /// actions of its transitions carried out on the motor.
    pub(super) fn run_state_machine(&mut self, ctx: &CycleContext, identification_done: bool) {
        let inputs = Inputs {
            // Only Error-type conditions move the state machine (X67-18.11.4.3-16, X67-18.11.4.3-17).
            error_pending: self.errors.has_error(),
            standstill: self.ramp.standstill(),
            identification_done,
        };
        let out = self.sm.step(self.cw, &inputs);
        self.trace = out.trace;
        for action in out.actions {
            match action {
                // Ready to switch on → Switched on (X67-18.11.4.3-06).
                Action::VoltageOn => self.powered = true,
                // Switched on → Ready to switch on / Switch on disabled, Operation enable → Ready to switch on /
                // Switch on disabled, Quick stop active at standstill, Fault reaction active
                // (X67-18.11.4.3-05, X67-18.11.4.3-08, X67-18.11.4.3-11, X67-18.11.4.3-12, X67-18.11.4.3-14,
                // X67-18.11.4.3-18): the voltage goes off at once, without braking.
                Action::VoltageOff => {
                    // A turning motor gives its energy back into the DC bus (X67-18.11.4.3-12).
                    if self.powered {
                        let speed = self.speed_per_second(ctx.cycle);
                        self.regenerated_joules += self.motor.regenerated_joules(speed);
                    }
                    self.powered = false;
                    self.ident_left = None;
                    self.stop_now();
                    // No current flows any more, so there is no stronger level left to hold for 100 ms: the
                    // next Switch on starts with the holding current (X67-18.11.4.3-06).
                    self.current = CurrentModel::new(*self.current.config())
                        .unwrap_or_else(|_| unreachable!());
                }
                // The first Switch on after start-up identifies the motor first (X67-18.11.4.3-07,
                // X67-18.11.3.7-05).
                Action::StartIdentification => {
                    self.ident_left = Some(1000u32.div_ceil(ctx.cycle.millis()));
                }
                // Disable operation and Quick stop brake through the mode's Stop set-point outside Operation
                // enable (X67-18.11.4.3-10, X67-18.11.4.3-13); Enable operation resumes the mode (X67-18.11.4.3-09,
                // X67-18.11.4.3-15).
                Action::Decelerate { .. } | Action::EnableMotion => {}
                // Fault reset: errors and warnings are reset (X67-18.11.4.1-11, X67-18.11.4.3-19, X67-18.11.4.3-20).
                Action::ClearErrors => self.errors.fault_reset(),
            }
        }
    }

    /// Motor identification on ↑ control bit 11 (X67-18.11.3.2-05, X67-18.11.3.7-04): at standstill, motor
    /// powered, half-step position; otherwise nothing happens (the catalogue's pick).
    pub(super) fn motor_id_trigger(&mut self, ctx: &CycleContext, rising: u16) {
        if rising & CW_MOTOR_ID != 0
            && self.powered
            && self.ramp.standstill()
            && self.ramp.position().rem_euclid(1024) == 0
        {
            self.measure_identification(ctx.supply_volts);
        }
    }

    /// Motoridentification0n from the motor, the supply voltage and the nominal current (X67-18.11.3.7-01,
    /// X67-18.11.3.7-03, X67-18.11.3.7-06).
    fn measure_identification(&mut self, supply_volts: f64) {
        let nominal_ma =
            u32::from(self.config.nominal_current) * current::MODULE_NOMINAL_MILLIAMPS / 100;
        if let Some(v) = motor::identification_us(
            &self.motor.params,
            self.motor.faults.open_winding,
            supply_volts,
            nominal_ma,
        ) {
            self.motor_identification = v;
        }
    }

    /// The stall condition of this cycle (X67-18.6.1.1-02, X67-18.11.1.13-01): threshold on, control bit 15,
    /// speed above StallDetectMinSpeed0n and a load value below the threshold.
    pub(super) fn stall_condition(&self, load_value: u8) -> bool {
        let threshold = self.config.stall_threshold();
        threshold != 0
            && self.cw & CW_STALL_DETECTION != 0
            && self.last.ramp.speed.unsigned_abs() > u32::from(self.config.stall_detect_min_speed)
            && load_value < threshold
    }
}
