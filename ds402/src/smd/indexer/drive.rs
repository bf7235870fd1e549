//! The driver: Enable_Driver and Drive_Is_Enabled, the driver faults (over-temperature, STO), the
//! internal fault, and the motor current with idle current reduction (Reference 1).

use std::time::{Duration, Instant};

use super::{cmd1, Indexer};

/// Idle current reduction after this long without motion (SMD-R1-018).
pub const IDLE_DELAY: Duration = Duration::from_millis(1500);

/// Over-temperature fault above this (°C, SMD-R1-020).
pub const OVER_TEMPERATURE: f64 = 95.0;

/// The over-temperature fault clears at or below this (°C, the model's hysteresis).
pub const OVER_TEMPERATURE_CLEAR: f64 = 90.0;

/// Temperature_Above_90°C above this (°C, SMD-R6-074).
pub const TEMPERATURE_WARNING: f64 = 90.0;

impl Indexer {
    /// Drive_Is_Enabled: Enable_Driver with a valid configuration (SMD-R5-027, SMD-R6-030).
    pub(super) fn drive_enabled(&self) -> bool {
        // An STO fault clears Drive_Is_Enabled; an over-temperature fault does not (SMD-R6-062).
        self.prev.cmd1 & cmd1::ENABLE_DRIVER != 0 && !self.configuration_error() && !self.sto_fault
    }

    /// Moves may start: the driver is enabled and supplies current.
    pub(super) fn can_move(&self) -> bool {
        self.drive_enabled() && !self.driver_fault()
    }

    /// Driver_Fault: over-temperature, or an STO fault not yet reset.
    pub(super) fn driver_fault(&self) -> bool {
        self.over_temperature || self.sto_fault
    }

    /// The driver electronics' temperature in °C at `now` (over 95 °C: fault; over 90 °C:
    /// warning), sensed at the next exchange (SMD-R1-020).
    pub fn set_temperature(&mut self, _now: Instant, celsius: f64) {
        self.temperature = celsius;
    }

    /// Whether STO input 1 and 2 are powered (24 V present) from `now`, sensed at the next exchange
    /// ("within one cycle", SMD-R1-002).
    pub fn set_sto(&mut self, _now: Instant, input1: bool, input2: bool) {
        self.sto_powered = [input1, input2];
    }

    /// An internal fault of the unit from `now` (Module_OK = 0 while present), shown from the next
    /// exchange's inputs on.
    pub fn set_internal_fault(&mut self, _now: Instant, fault: bool) {
        self.internal_fault = fault;
    }

    /// The motor current the driver supplies now, in 0.1 A: 0 without Drive_Is_Enabled or with a
    /// Driver_Fault; the last move's current while moving and for 1.5 s after a stop; then the idle
    /// percentage of it (SMD-R1-018, SMD-R1-019, SMD-R2-101, SMD-R2-102, SMD-R6-061).
    pub fn actual_current(&self) -> f64 {
        // No current without Drive_Is_Enabled or with a Driver_Fault: what `can_move` says.
        if !self.can_move() {
            return 0.0;
        }
        let running = f64::from(self.in_current);
        if self.segment.is_none() && self.time >= self.stopped_since + IDLE_DELAY {
            running * f64::from(self.idle_pct) / 100.0
        } else {
            running
        }
    }

    /// Temperature and STO, once per cycle.
    pub(super) fn check_driver(&mut self) {
        // SMD-R1-020: the over-temperature fault.
        if self.temperature > OVER_TEMPERATURE {
            self.over_temperature = true;
        } else if self.temperature <= OVER_TEMPERATURE_CLEAR {
            self.over_temperature = false; // SMD-R6-071: clears itself.
        }
        if !(self.sto_powered[0] && self.sto_powered[1]) {
            self.sto_fault = true; // SMD-R1-002; cleared only by Reset Errors (SMD-R1-005).
        }
        // A driver fault ends a move like an Immediate Stop (SMD-R1-004 gap).
        if self.driver_fault() && self.segment.is_some() {
            self.stop_now();
        }
    }
}
