//! The limits of one axis: the two limit switches with and without direction monitoring (seed 002,
//! 18.11.1.16) and the software limits PositionLimitMin0n/Max0n (18.11.1.17).

use super::config::SwitchPolarity;
use super::{Axis, CycleContext, Desired, InputEdge};
use crate::x67::errors::ErrorCode;

/// The two limit switches: index in [`CycleContext::limit_inputs`] and bit pair of LimitSwitchConfig0n, warning
/// code, and the direction of motion toward the switch.
const LIMIT_SWITCHES: [(usize, ErrorCode, i64); 2] = [
    (0, ErrorCode::NegativeLimitSwitch, -1),
    (1, ErrorCode::PositiveLimitSwitch, 1),
];

impl Axis {
    /// Whether direction monitoring is on (LimitSwitchConfig0n bit 7, X67-18.11.1.16-03).
    const fn direction_monitoring(&self) -> bool {
        self.config.limit_switch_config & 0x80 != 0
    }

    /// The polarity of limit switch `k` (0 = negative, 1 = positive; X67-18.11.1.16-01, X67-18.11.1.16-02).
    const fn switch_polarity(&self, k: usize) -> SwitchPolarity {
        SwitchPolarity::from_bits(self.config.limit_switch_config >> (2 * k))
    }

    /// A limit switch raises its warning and holds the axis at speed 0 until the warning is acknowledged
    /// (X67-18.11.1.16-04); the state does not change.
    fn trigger_limit(&mut self, code: ErrorCode) {
        self.errors.raise(code);
        self.errors.clear_condition(code);
        self.limit_hold = true;
    }

    /// The start of a cycle: the limit-switch hold ends with the acknowledgement of its warning (↑ CW bit 12
    /// or bit 7, X67-18.11.1.16-05).
    pub(super) fn release_limit_hold(&mut self) {
        if self.limit_hold
            && !self.errors.is_latched(ErrorCode::NegativeLimitSwitch)
            && !self.errors.is_latched(ErrorCode::PositiveLimitSwitch)
        {
            self.limit_hold = false;
        }
    }

    /// The software limits applied to the mode's set-point (X67-18.11.1.17): with the limits on the ramp is
    /// bounded to [Min, Max] (X67-18.11.1.17-01, X67-18.11.1.17-02); a target outside them or Min > Max stops the
    /// axis and sets SW bit 11 (X67-18.11.1.17-03, X67-18.11.1.17-04).
    pub(super) fn software_limits(&mut self, desired: Desired) -> Desired {
        self.target_out_of_limits = false;
        self.limits_misconfigured = false;
        match self.config.software_limits() {
            Some((min, max)) if min > max => {
                self.limits_misconfigured = true;
                self.ramp.set_bounds(None);
                Desired::Stop
            }
            Some((min, max)) => {
                self.ramp.set_bounds(Some((i64::from(min), i64::from(max))));
                if let Desired::Position { target, .. } = desired {
                    if target < min || target > max {
                        self.target_out_of_limits = true;
                        return Desired::Stop;
                    }
                }
                desired
            }
            // Limits off: the counter may overflow (X67-18.11.1.17-06).
            None => {
                self.ramp.set_bounds(None);
                desired
            }
        }
    }

    /// The limit switches applied to the mode's set-point: with direction monitoring a movement toward an
    /// active switch is refused (X67-18.11.1.16-07, X67-18.11.1.16-08), and while a switch holds the axis it stays at
    /// speed 0 (X67-18.11.1.16-04).
    pub(super) fn limit_switches(&mut self, ctx: &CycleContext, desired: Desired) -> Desired {
        if self.direction_monitoring() {
            let dir = self.commanded_direction(desired);
            for (k, code, sign) in LIMIT_SWITCHES {
                let pol = self.switch_polarity(k);
                if dir == sign && pol.active(ctx.levels[ctx.limit_inputs[k]]) {
                    self.trigger_limit(code);
                }
            }
        }
        if self.limit_hold {
            Desired::Stop
        } else {
            desired
        }
    }

    /// An input edge during the cycle on a limit-switch input: the active edge triggers the switch
    /// (X67-18.11.1.16-04), with direction monitoring only in the commanded direction (X67-18.11.1.16-07).
    /// Without direction monitoring a switch overshot while braking triggers again on its next active edge
    /// (X67-18.11.1.16-06).
    pub(super) fn limit_edge(&mut self, ctx: &CycleContext, edge: &InputEdge) {
        for (k, code, sign) in LIMIT_SWITCHES {
            if edge.input != ctx.limit_inputs[k] {
                continue;
            }
            let pol = self.switch_polarity(k);
            if !pol.active(edge.level) {
                continue;
            }
            let monitoring = self.direction_monitoring();
            let dir = self.ramp.setpoint_speed().signum();
            if !monitoring || dir == sign {
                self.trigger_limit(code);
                self.apply(Desired::Stop);
            }
        }
    }

    /// The commanded direction: the set-point's sign while it moves, else the direction of the desired
    /// set-point.
    fn commanded_direction(&self, desired: Desired) -> i64 {
        let sp = self.ramp.setpoint_speed();
        if sp != 0 {
            return sp.signum();
        }
        match desired {
            Desired::Stop => 0,
            Desired::Speed(s) => i64::from(s.signum()),
            Desired::Position { target, .. } => {
                i64::from(target.wrapping_sub(self.internal_counter()).signum())
            }
        }
    }
}
