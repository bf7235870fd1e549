//! Registration moves (Reference 2, "Registration Moves"; Tables R6.9 and R6.11): a jog that
//! runs out exactly the Stopping Distance after a stop condition past the Minimum Registration Move
//! Distance.

use std::time::Duration;

use super::{cmd0, cmd1, Curve, Indexer, Outcome, Outputs, Purpose, Segment};

impl Indexer {
    /// A Registration move (Jog bit with CMD_word1 bit 7, SMD-R6-029, SMD-R2-061): it runs like a
    /// jog (SMD-R2-023: linear, no Jerk); Position is the Stopping Distance, the Minimum
    /// Registration Move Distance is (Jerk << 16) | Motor_Current (SMD-R6-041, SMD-R6-042,
    /// SMD-R6-043).
    pub(super) fn start_registration(&mut self, out: Outputs, dir: i64) -> Outcome {
        let mrmd = (u32::from(out.jerk) << 16) | u32::from(out.motor_current);
        if !(0..=8_388_607).contains(&out.position) || mrmd > 8_388_607 {
            return Outcome::CommandErrorComplete; // SMD-R6-040
        }
        // Speed and ramps: the jog's own checks (Jerk 0, no Motor_Current) refuse them the same way.
        let params = Outputs {
            jerk: 0,
            cmd1: out.cmd1 & !cmd1::MOTOR_CURRENT,
            ..out
        };
        let bit = if dir > 0 { cmd0::JOG_CW } else { cmd0::JOG_CCW };
        let outcome = self.jog(params, dir, bit, true);
        if outcome == Outcome::Accepted {
            if let Some(seg) = self.segment.as_mut() {
                seg.purpose = Purpose::Registration {
                    bit,
                    stopping: i64::from(out.position),
                    mrmd: f64::from(mrmd),
                };
            }
        }
        outcome
    }

    /// The registration run-out: exactly `stopping` more steps from here (SMD-R2-062, SMD-R2-064,
    /// SMD-R2-065).
    pub(super) fn run_out(&mut self, stopping: i64) {
        let Some(seg) = self.segment else { return };
        // The run-out brakes linearly.
        let ramp = self.stop_ramp(&seg, 0);
        let (v, d) = (ramp.high, ramp.accel);
        let sd = stopping as f64;
        let (cruise, end) = if sd >= ramp.distance {
            let cruise = (sd - ramp.distance) / v;
            (cruise, cruise + ramp.time)
        } else {
            // Braking at Deceleration until the distance is out: v·τ − d·τ²/2 = SD.
            let tau = (v - (v * v - 2.0 * d * sd).max(0.0).sqrt()) / d;
            (0.0, tau)
        };
        // The run-out goes on from the jog's origin, past the whole steps the jog covered.
        let covered = seg.covered().round();
        let here = seg.origin + seg.dir * (covered as i64);
        self.segment = Some(Segment {
            base: covered,
            curve: Curve::RunOut {
                speed: v,
                cruise,
                ramp,
                end,
            },
            elapsed: Duration::ZERO,
            purpose: Purpose::Move,
            target: here + seg.dir * stopping,
            ..seg
        });
    }
}
