//! The simulated machine around the motor: the limit switches and the home switch of
//! [`SimConfig`](super::SimConfig) as 0x60FD digital inputs (CiA 402-2, object 0x60FD: bit 0
//! negative limit switch, bit 1 positive limit switch, bit 2 home switch), and the encoder's index
//! pulse once per revolution.
//!
//! Switch positions are raw rotor counts (what 0x6064 reads before any homing moves the position
//! reference), so the switches stay where they are on the machine when homing redefines the
//! position.

use super::SimConfig;

/// 0x60FD bit 0: negative limit switch.
pub const NEGATIVE_LIMIT: u8 = 0;
/// 0x60FD bit 1: positive limit switch.
pub const POSITIVE_LIMIT: u8 = 1;
/// 0x60FD bit 2: home switch.
pub const HOME_SWITCH: u8 = 2;

/// A switch active over a closed interval of raw counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Switch {
    lo: i64,
    hi: i64,
}

impl Switch {
    /// Whether the switch is active at count `x`.
    pub fn active(&self, x: i64) -> bool {
        self.lo <= x && x <= self.hi
    }

    /// The first count after `from` on the way to `to` (inclusive) at which the switch shows the
    /// other level than at `from`.
    pub fn first_change(&self, from: i64, to: i64) -> Option<i64> {
        let on = self.active(from);
        if to > from {
            let c = if on {
                self.hi.checked_add(1)?
            } else if self.lo > from {
                self.lo
            } else {
                return None;
            };
            (c <= to).then_some(c)
        } else if to < from {
            let c = if on {
                self.lo.checked_sub(1)?
            } else if self.hi < from {
                self.hi
            } else {
                return None;
            };
            (c >= to).then_some(c)
        } else {
            None
        }
    }
}

/// The switch of 0x60FD bit `bit` (0, 1 or 2) as `sim` places it, if it has one.
pub(crate) fn switch(sim: &SimConfig, bit: u8) -> Option<Switch> {
    match bit {
        NEGATIVE_LIMIT => sim.negative_limit.map(|x| Switch {
            lo: i64::MIN,
            hi: x,
        }),
        POSITIVE_LIMIT => sim.positive_limit.map(|x| Switch {
            lo: x,
            hi: i64::MAX,
        }),
        HOME_SWITCH => sim.home_switch.map(|x| Switch {
            lo: x,
            hi: sim
                .home_switch_end
                .map_or(i64::MAX, |e| e.saturating_sub(1)),
        }),
        _ => None,
    }
}

/// The first index pulse from `x` in direction `dir` (±1): pulses sit at `offset + n · cpr`. With
/// `inclusive` a pulse at `x` itself counts.
pub(crate) fn next_index(x: i64, dir: i8, inclusive: bool, offset: i64, cpr: i64) -> i64 {
    let cpr = cpr.max(1);
    if dir >= 0 {
        let mut c = x + (offset - x).rem_euclid(cpr);
        if c == x && !inclusive {
            c += cpr;
        }
        c
    } else {
        let mut c = x - (x - offset).rem_euclid(cpr);
        if c == x && !inclusive {
            c -= cpr;
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn changes_along_a_path() {
        let s = Switch { lo: 100, hi: 199 };
        assert_eq!(s.first_change(0, 150), Some(100));
        assert_eq!(s.first_change(150, 300), Some(200));
        assert_eq!(s.first_change(300, 150), Some(199));
        assert_eq!(s.first_change(150, 0), Some(99));
        assert_eq!(s.first_change(0, 99), None);
        assert_eq!(s.first_change(300, 200), None);
    }

    #[test]
    fn index_pulses() {
        assert_eq!(next_index(0, 1, false, 2500, 10_000), 2500);
        assert_eq!(next_index(2500, 1, false, 2500, 10_000), 12_500);
        assert_eq!(next_index(2500, 1, true, 2500, 10_000), 2500);
        assert_eq!(next_index(0, -1, false, 2500, 10_000), -7500);
        assert_eq!(next_index(-7500, -1, true, 2500, 10_000), -7500);
    }
}
