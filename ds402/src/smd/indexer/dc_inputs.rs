//! The two discrete DC inputs (Reference 1, "Available Discrete DC Inputs"; Reference 5, CFG_Word_0
//! and CFG_Word_1): their active levels, their functions and what their edges do.

use std::time::Instant;

use super::{Cfg0, Indexer, InputFunction, Purpose};

impl Indexer {
    /// Whether current flows into input `n` (1 or 2) from `now`: the wiring, as a sensor drives it.
    /// Sensed at the next exchange, whose edges the inputs act on (Table R2.1).
    pub fn set_input(&mut self, _now: Instant, n: usize, current_flows: bool) {
        if let Some(c) = self.current.get_mut(n.wrapping_sub(1)) {
            *c = current_flows;
        }
    }

    /// Input `k` (0 or 1) active after the CFG_Word_1 level (SMD-R5-023): with its level bit 1 it
    /// is active when current flows, with 0 when none flows.
    pub(super) fn active(&self, k: usize) -> bool {
        let level = self.config.cfg1 & (1 << k) != 0;
        self.current[k] == level
    }

    pub(super) fn functions(&self) -> [Option<InputFunction>; 2] {
        let c = Cfg0::from_word(self.config.cfg0);
        [c.input1, c.input2]
    }

    /// An active input with function `f`.
    pub(super) fn input_active(&self, f: InputFunction) -> bool {
        let fs = self.functions();
        (0..2).any(|k| fs[k] == Some(f) && self.active(k))
    }

    /// E-Stop or an end limit is active: no Absolute, Relative or assembled move starts
    /// (SMD-R1-029, SMD-R2-040).
    pub(super) fn start_blocked(&self) -> bool {
        self.input_active(InputFunction::EStop)
            || self.input_active(InputFunction::CwLimit)
            || self.input_active(InputFunction::CcwLimit)
    }

    fn capture(&mut self) {
        if self.encoder_enabled() {
            self.trapped = self.encoder_position();
        }
    }

    /// The input edges since the last cycle (Table R2.1 and R1 "Available Discrete DC Inputs").
    pub(super) fn sense_inputs(&mut self) {
        let fs = self.functions();
        for (k, function) in fs.into_iter().enumerate() {
            let active = self.active(k);
            let was = std::mem::replace(&mut self.was_active[k], active);
            if active && !was {
                match function {
                    Some(InputFunction::EStop) => {
                        // SMD-R1-027, SMD-R1-030, SMD-R2-014: always, moving or not.
                        self.stop_now();
                        self.input_error = true;
                    }
                    Some(f @ (InputFunction::CwLimit | InputFunction::CcwLimit))
                        if self.homing.is_some() =>
                    {
                        self.homing_limit(f, k);
                    }
                    // Only a homing run acts on the Home input (SMD-R2-047).
                    Some(InputFunction::Home) => self.home_edge(true),
                    // SMD-R2-039, SMD-R2-041, SMD-R2-044, SMD-R6-053, SMD-R6-068: either limit
                    // stops any move; at rest nothing but the input bit (SMD-R2-015).
                    Some(InputFunction::CwLimit | InputFunction::CcwLimit) if self.busy() => {
                        self.stop_now();
                        self.input_error = true;
                        self.limit_condition = Some(k);
                    }
                    Some(InputFunction::StartIndexed) => {
                        // The capture (SMD-R1-025, SMD-R1-026, SMD-R5-019), then a pending indexed
                        // command starts, if nothing runs (SMD-R2-090, SMD-R2-094, SMD-R2-095).
                        self.capture();
                        if let Some((bit, out)) = self.pending_index {
                            if !self.busy() {
                                // Only a command's arrival reads Indexed_Command.
                                let outcome = self.execute(bit, out);
                                self.apply(outcome);
                            }
                        }
                    }
                    // SMD-R1-031, SMD-R1-033; other moves ignore the input (SMD-R1-032).
                    Some(InputFunction::StopJog) if self.jogging() => {
                        self.capture();
                        if matches!(self.segment, Some(s) if matches!(s.purpose, Purpose::Jog { .. }))
                        {
                            self.controlled_stop(Purpose::JogStop);
                        }
                        // A registration move acts on the input's level (follow_jog).
                    }
                    _ => {}
                }
            }
            if !active && was && function == Some(InputFunction::Home) {
                self.home_edge(false);
            }
            if !active && was && self.limit_condition == Some(k) {
                self.limit_condition = None; // SMD-R6-068
            }
        }
    }
}
