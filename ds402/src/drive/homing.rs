//! Homing mode (CiA 402-2, homing mode: homing method 0x6098, homing speeds 0x6099:01 "during
//! search for switch" and :02 "during search for zero", homing acceleration 0x609A, home offset
//! 0x607C; controlword bit 4 homing operation start, bit 8 halt; statusword bit 10 target reached,
//! bit 12 homing attained, bit 13 homing error).
//!
//! Methods (the switches are 0x60FD bits 0–2, simulated by [`SimConfig`](super::SimConfig) or
//! forced with [`Drive::set_input`](super::Drive::set_input)):
//!
//! | method | signal | home position |
//! |---|---|---|
//! | 1 / 2 | negative / positive limit switch | first index pulse beyond the point where the switch becomes inactive (right / left of it) |
//! | 3 / 4 | positive home switch (active above its edge) | first index pulse left / right of the edge |
//! | 5 / 6 | negative home switch (active below its edge) | first index pulse right / left of the edge |
//! | 7–10 | home switch cam, positive limit switch to reverse | 7: left of the cam's left edge, 8: right of its left edge, 9: left of its right edge, 10: right of its right edge |
//! | 11–14 | home switch cam, negative limit switch to reverse | 11: right of the right edge, 12: left of the right edge, 13: right of the left edge, 14: left of the left edge |
//! | 17–30 | as 1–14 | the switch edge itself (no index pulse) |
//! | 33 / 34 | index pulse | first index pulse in negative / positive direction |
//! | 35, 37 | none | the present position |
//!
//! The search runs at 0x6099:01 until the first switch edge is found and at 0x6099:02 after it
//! (leaving a switch, approaching an edge again, the index pulse), ramped by 0x609A. An edge is
//! the first count at which the switch shows its new level, and the index pulse the first one at
//! or beyond that count (the drive latches both exactly, as encoder hardware does). Events count
//! only while the axis moves in the direction the step searches in, so overshoot while braking
//! and reversing finds nothing. Methods 7–14 and 23–30 reverse once on their limit switch.
//!
//! When the home position is found the position is redefined so that it reads the home offset
//! 0x607C there (status: homing attained); the axis then brakes and returns to it at 0x6099:02,
//! and stands there with 0x6064 = 0x607C (status: target reached too). Homing ends with a homing
//! error, braking at 0x609A, when the method needs a switch the machine does not have (neither
//! simulated nor forced), when a search runs into a limit switch it may not reverse on (or a second
//! time), or beyond the software position limits 0x607D, and at once for method 0.
//!
//! Status bits 13, 12, 10 (as python-canopen reads them under mask 0x3400): 0x0400 not started or
//! interrupted (at standstill), 0x0000 in progress, 0x1000 attained, 0x1400 completed, 0x2000 error
//! while braking, 0x2400 error at standstill. Halt (bit 8) and bit 4 going to 0 interrupt a homing
//! in progress (braking on the halt option code's ramp); a new rising edge of bit 4 starts over.
//! During the return to the home position they (and a quick stop) stop the axis short of it:
//! homing stays attained, 0x1000, and completes only where the axis stands at the home position.

use std::collections::VecDeque;

use super::objects::P;
use super::state::{SW_OMS12, SW_OMS13, SW_TARGET_REACHED};
use super::switches::{self, HOME_SWITCH, NEGATIVE_LIMIT, POSITIVE_LIMIT};
use super::{profile, Drive, Motion};

/// Where homing stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum HomingStatus {
    /// No homing since the mode was entered or the drive powered up.
    #[default]
    NotStarted,
    /// Searching.
    InProgress,
    /// Halted, bit 4 cleared, or left (quick stop, fault, power off, mode change) before the home
    /// position was found.
    Interrupted,
    /// The home position is found; the axis returns to it, or stands where halt, bit 4 going to
    /// 0 or a quick stop stopped the return short of it.
    Attained,
    /// The axis stands at the home position.
    Completed,
    /// Homing failed.
    Error,
}

/// One step of a homing search.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Step {
    /// Move in `dir` until switch `sig` (0x60FD bit) shows `level`; reverse once on limit switch
    /// `reverse_on`.
    Seek {
        dir: i8,
        sig: u8,
        level: bool,
        reverse_on: Option<u8>,
    },
    /// Move in `dir` until the index pulse at `target` passes.
    Index { dir: i8, target: i64 },
}

/// The state of homing mode.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Homing {
    pub status: HomingStatus,
    steps: VecDeque<Step>,
    /// Still searching for the first switch (speed 0x6099:01).
    fast: bool,
    /// Reversed on a limit switch already.
    reversed: bool,
    /// The home position found, raw counts: homing completes when the axis stands there.
    home: f64,
}

/// The limit switch on side `dir`.
fn limit_on(dir: i8) -> u8 {
    if dir > 0 {
        POSITIVE_LIMIT
    } else {
        NEGATIVE_LIMIT
    }
}

/// The steps of `method` (1–14, 17–30) from the switch levels at the start, with the switches the
/// method needs. `None` for other methods.
fn plan(method: i64, levels: [bool; 3]) -> Option<(Vec<Step>, Vec<u8>)> {
    let index = method <= 14;
    let base = if index { method } else { method - 16 };
    let (canon, s): (i64, i8) = match base {
        1 => (1, 1),
        2 => (1, -1),
        3 => (3, 1),
        4 => (4, 1),
        5 => (3, -1),
        6 => (4, -1),
        7..=10 => (base, 1),
        11..=14 => (base - 4, -1),
        // Also every method outside 1–14 and 17–30: its base is below 1 or above 14.
        _ => return None,
    };
    let seek = |dir: i8, sig: u8, level: bool| Step::Seek {
        dir,
        sig,
        level,
        reverse_on: None,
    };
    let h = levels[usize::from(HOME_SWITCH)];
    let mut steps = Vec::new();
    let needs;
    let last_dir: i8;
    match canon {
        1 => {
            let l = limit_on(-s);
            if !levels[usize::from(l)] {
                steps.push(seek(-s, l, true));
            }
            steps.push(seek(s, l, false));
            last_dir = s;
            needs = vec![l];
        }
        3 => {
            if !h {
                steps.push(seek(s, HOME_SWITCH, true));
            }
            steps.push(seek(-s, HOME_SWITCH, false));
            last_dir = -s;
            needs = vec![HOME_SWITCH];
        }
        4 => {
            if h {
                steps.push(seek(-s, HOME_SWITCH, false));
            }
            steps.push(seek(s, HOME_SWITCH, true));
            last_dir = s;
            needs = vec![HOME_SWITCH];
        }
        _ => {
            let r = limit_on(s);
            if !h {
                steps.push(Step::Seek {
                    dir: s,
                    sig: HOME_SWITCH,
                    level: true,
                    reverse_on: Some(r),
                });
            }
            match canon {
                7 => {
                    steps.push(seek(-s, HOME_SWITCH, false));
                    last_dir = -s;
                }
                8 => {
                    steps.push(seek(-s, HOME_SWITCH, false));
                    steps.push(seek(s, HOME_SWITCH, true));
                    last_dir = s;
                }
                9 => {
                    steps.push(seek(s, HOME_SWITCH, false));
                    steps.push(seek(-s, HOME_SWITCH, true));
                    last_dir = -s;
                }
                _ => {
                    steps.push(seek(s, HOME_SWITCH, false));
                    last_dir = s;
                }
            }
            needs = vec![HOME_SWITCH, r];
        }
    }
    if index {
        // The target is set when the step before it ends.
        steps.push(Step::Index {
            dir: last_dir,
            target: 0,
        });
    }
    Some((steps, needs))
}

impl Drive {
    /// Whether 0x60FD bit `bit` is there at all: simulated or forced.
    fn has_input(&self, bit: u8) -> bool {
        self.forced[usize::from(bit)].is_some() || switches::switch(&self.config.sim, bit).is_some()
    }

    fn input(&self, bit: u8) -> bool {
        self.digital_inputs() & 1 << bit != 0
    }

    fn cpr_counts(&self) -> i64 {
        self.motor.cpr.round() as i64
    }

    /// A rising edge of bit 4 in homing mode, Operation enabled.
    pub(crate) fn homing_start(&mut self) {
        self.homing = Homing {
            status: HomingStatus::InProgress,
            steps: VecDeque::new(),
            fast: true,
            reversed: false,
            home: 0.0,
        };
        let method = self.params.get(P::HomingMethod);
        let count = self.motor.count();
        let steps = match method {
            35 | 37 => {
                self.homing_found(count);
                return;
            }
            33 | 34 => {
                let dir = if method == 33 { -1 } else { 1 };
                let target = switches::next_index(
                    count,
                    dir,
                    false,
                    self.config.sim.index_offset,
                    self.cpr_counts(),
                );
                vec![Step::Index { dir, target }]
            }
            _ => {
                let levels = [
                    self.input(NEGATIVE_LIMIT),
                    self.input(POSITIVE_LIMIT),
                    self.input(HOME_SWITCH),
                ];
                match plan(method, levels) {
                    Some((steps, needs)) if needs.iter().all(|&b| self.has_input(b)) => steps,
                    _ => {
                        self.homing_error();
                        return;
                    }
                }
            }
        };
        self.homing.steps = steps.into();
        self.homing_drive();
    }

    /// Sets the velocity of the present step.
    fn homing_drive(&mut self) {
        let (dir, speed) = match self.homing.steps.front() {
            Some(Step::Seek { dir, .. }) if self.homing.fast => {
                (*dir, self.params.positive(P::HomingSpeedSwitch))
            }
            Some(Step::Seek { dir, .. }) | Some(Step::Index { dir, .. }) => {
                (*dir, self.params.positive(P::HomingSpeedZero))
            }
            None => return,
        };
        let acc = self.params.positive(P::HomingAcceleration);
        let v = f64::from(dir) * speed.min(self.velocity_limit());
        self.plan(profile::velocity(self.demand.p, self.demand.v, v, acc, acc));
    }

    /// Homing failed: brake at 0x609A.
    fn homing_error(&mut self) {
        self.homing.status = HomingStatus::Error;
        self.homing.steps.clear();
        let acc = self.params.positive(P::HomingAcceleration);
        self.plan(profile::stop(self.demand.p, self.demand.v, acc));
    }

    /// The home position is at raw count `x`: redefine the position, return there.
    fn homing_found(&mut self, x: i64) {
        self.shift = self.params.get(P::HomeOffset) - x;
        self.homing.steps.clear();
        let target = x as f64;
        self.homing.home = target;
        if self.demand.v == 0.0 && (self.demand.p - target).abs() < 1.0 {
            self.demand.p = target;
            self.motion = Motion::Hold;
            self.homing.status = HomingStatus::Completed;
            return;
        }
        self.homing.status = HomingStatus::Attained;
        let acc = self.params.positive(P::HomingAcceleration);
        let speed = self
            .params
            .positive(P::HomingSpeedZero)
            .min(self.velocity_limit());
        self.plan(profile::move_to(
            self.demand.p,
            self.demand.v,
            target,
            speed,
            acc,
            acc,
        ));
    }

    /// Halt, or bit 4 back to 0: a homing in progress is interrupted; the axis brakes on the halt
    /// option code's ramp.
    pub(crate) fn homing_interrupt(&mut self) {
        match self.homing.status {
            HomingStatus::InProgress => {
                self.homing.status = HomingStatus::Interrupted;
                self.homing.steps.clear();
                self.halt_stop();
            }
            HomingStatus::Attained => self.halt_stop(),
            _ => {}
        }
    }

    /// The mode's activity ends (the caller stops the motion).
    pub(crate) fn homing_interrupted(&mut self) {
        if self.homing.status == HomingStatus::InProgress {
            self.homing.status = HomingStatus::Interrupted;
            self.homing.steps.clear();
        }
    }

    /// Whether switch `sig` shows `level` for the first time on the way from `from` to `to`, moving
    /// in `dir`: the count where it does.
    fn homing_event(&self, sig: u8, level: bool, dir: i8, from: i64, to: i64) -> Option<i64> {
        if let Some(forced) = self.forced[usize::from(sig)] {
            let before = self.inputs_prev & 1 << sig != 0;
            return (forced == level && before != level).then_some(to);
        }
        if (to - from).signum() != i64::from(dir) {
            return None;
        }
        let sw = switches::switch(&self.config.sim, sig)?;
        let first = sw.first_change(from, to)?;
        if sw.active(first) == level {
            return Some(first);
        }
        sw.first_change(first, to)
            .filter(|&c| sw.active(c) == level)
    }

    /// Homing at a tick, the rotor having moved from count `before` to `count`.
    pub(crate) fn homing_tick(&mut self, before: i64, count: i64) {
        match self.homing.status {
            HomingStatus::InProgress => self.homing_scan(before, count),
            // A return stopped short (halt, quick stop) leaves homing attained.
            HomingStatus::Attained if self.plan_done() && self.demand.p == self.homing.home => {
                self.homing.status = HomingStatus::Completed;
            }
            _ => {}
        }
    }

    fn homing_scan(&mut self, before: i64, count: i64) {
        let mut from = before;
        while let Some(&step) = self.homing.steps.front() {
            match step {
                Step::Seek {
                    dir,
                    sig,
                    level,
                    reverse_on,
                } => {
                    if let Some(c) = self.homing_event(sig, level, dir, from, count) {
                        self.homing.steps.pop_front();
                        self.homing.fast = false;
                        from = c;
                        match self.homing.steps.front_mut() {
                            Some(Step::Index { dir, target }) => {
                                *target = switches::next_index(
                                    c,
                                    *dir,
                                    true,
                                    self.config.sim.index_offset,
                                    self.motor.cpr.round() as i64,
                                );
                            }
                            None => {
                                self.homing_found(c);
                                return;
                            }
                            _ => {}
                        }
                        self.homing_drive();
                        continue;
                    }
                    let limit = limit_on(dir);
                    let moving = self.demand.v * f64::from(dir) > 0.0;
                    if moving && self.input(limit) && !(sig == limit && level) {
                        if reverse_on == Some(limit) && !self.homing.reversed {
                            self.homing.reversed = true;
                            if let Some(Step::Seek { dir, .. }) = self.homing.steps.front_mut() {
                                *dir = -*dir;
                            }
                            self.homing_drive();
                        } else {
                            self.homing_error();
                        }
                        return;
                    }
                }
                Step::Index { dir, target } => {
                    let passes = if dir > 0 {
                        count > from && (from..=count).contains(&target)
                    } else {
                        count < from && (count..=from).contains(&target)
                    };
                    if passes {
                        self.homing_found(target);
                        return;
                    }
                    let moving = self.demand.v * f64::from(dir) > 0.0;
                    if moving && self.input(limit_on(dir)) {
                        self.homing_error();
                        return;
                    }
                }
            }
            break;
        }
        // A search may not leave the software position limits.
        let min = self.params.get(P::MinPositionLimit);
        let max = self.params.get(P::MaxPositionLimit);
        let user = self.position();
        if min < max && !(min..=max).contains(&user) {
            self.homing_error();
        }
    }

    /// Status bits 10, 12, 13 in homing mode.
    pub(crate) fn homing_bits(&self) -> u16 {
        let still = if self.standstill() {
            SW_TARGET_REACHED
        } else {
            0
        };
        match self.homing.status {
            HomingStatus::NotStarted => SW_TARGET_REACHED,
            HomingStatus::InProgress => 0,
            HomingStatus::Interrupted => still,
            HomingStatus::Attained => SW_OMS12,
            HomingStatus::Completed => SW_OMS12 | SW_TARGET_REACHED,
            HomingStatus::Error => SW_OMS13 | still,
        }
    }
}
