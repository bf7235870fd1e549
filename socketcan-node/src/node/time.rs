//! The TIME service (CiA 301 §7.2.6): a producer sends the time of day, consumers set their clock by
//! it. 0x1012 "COB-ID TIME" says which the node is: bit 31 consumer, bit 30 producer, bits 0–10 the
//! CAN-ID (default 0x100).
//!
//! The node's clock is the time of day at an instant ([`Clock`]); the edge sets it from its wall clock
//! ([`super::Node::set_clock`]), a TIME frame received sets it again. Choices where CiA 301 leaves room:
//! - a producer sends TIME in Pre-operational and Operational, once when it becomes a producer and
//!   then every [`super::NodeConfig::time_period`] (default 1 s); a node without a clock sends none;
//! - a consumer takes a TIME frame of exactly six bytes in Pre-operational and Operational; others
//!   are ignored;
//! - bits 28–31 of the milliseconds (reserved) are sent 0 and ignored on receipt; a millisecond count of
//!   a day or more is not a time of day and is ignored.

use std::time::{Duration, Instant};

use super::{Core, Device, NmtState, NodeEvent};

/// 0x1012 bit 31: the node consumes TIME.
pub const TIME_CONSUMER: u32 = 1 << 31;
/// 0x1012 bit 30: the node produces TIME.
pub const TIME_PRODUCER: u32 = 1 << 30;
/// Milliseconds in a day.
pub const DAY_MS: u64 = 86_400_000;
/// Milliseconds from 1970-01-01 (the Unix epoch) to 1984-01-01 (TIME_OF_DAY's day 0): 5,113 days.
pub const UNIX_TO_1984_MS: u64 = 5_113 * DAY_MS;

/// TIME_OF_DAY (CiA 301 §7.1.6.5): milliseconds after midnight and days since 1984-01-01.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TimeOfDay {
    /// Milliseconds after midnight, below 86,400,000.
    pub ms: u32,
    /// Days since 1984-01-01.
    pub days: u16,
}

impl TimeOfDay {
    /// The time of day `ms` milliseconds after 1984-01-01 00:00 (days wrap after 65,535).
    pub fn from_ms(ms: u64) -> TimeOfDay {
        TimeOfDay {
            ms: (ms % DAY_MS) as u32,
            days: (ms / DAY_MS) as u16,
        }
    }

    /// Milliseconds since 1984-01-01 00:00.
    pub fn to_ms(self) -> u64 {
        u64::from(self.days) * DAY_MS + u64::from(self.ms)
    }

    /// The six bytes of a TIME frame: the milliseconds in bits 0–27 (little-endian, bits 28–31 zero),
    /// then the days.
    pub fn encode(self) -> [u8; 6] {
        let m = (self.ms & 0x0FFF_FFFF).to_le_bytes();
        let d = self.days.to_le_bytes();
        [m[0], m[1], m[2], m[3], d[0], d[1]]
    }

    /// The time of day of a TIME frame's data; `None` unless it is six bytes with a millisecond count
    /// below a day.
    pub fn decode(data: &[u8]) -> Option<TimeOfDay> {
        let d: [u8; 6] = data.try_into().ok()?;
        let ms = u32::from_le_bytes([d[0], d[1], d[2], d[3]]) & 0x0FFF_FFFF;
        (u64::from(ms) < DAY_MS).then_some(TimeOfDay {
            ms,
            days: u16::from_le_bytes([d[4], d[5]]),
        })
    }
}

/// The node's clock: the time of day at an instant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Clock {
    /// The instant.
    pub at: Instant,
    /// Milliseconds since 1984-01-01 00:00 at that instant.
    pub ms: u64,
}

impl Clock {
    /// The time of day at `now` (an instant before the clock's counts as its instant).
    pub fn time_at(&self, now: Instant) -> TimeOfDay {
        let since = now.saturating_duration_since(self.at);
        TimeOfDay::from_ms(self.ms + since.as_millis() as u64)
    }
}

impl<A: Device> Core<A> {
    /// 0x1012, or 0 when the dictionary has none.
    pub(super) fn time_cob(&self) -> u32 {
        self.u32_at(0x1012, 0).unwrap_or(0)
    }

    /// The COB-ID the node consumes TIME on, if it does.
    pub(super) fn time_consumed(&self) -> Option<u16> {
        let v = self.time_cob();
        (v & TIME_CONSUMER != 0).then_some((v & 0x7FF) as u16)
    }

    /// A TIME frame received at `now`.
    pub(super) fn time_received(&mut self, now: Instant, data: &[u8]) {
        if !matches!(self.state, NmtState::PreOperational | NmtState::Operational) {
            return;
        }
        if let Some(t) = TimeOfDay::decode(data) {
            self.clock = Some(Clock {
                at: now,
                ms: t.to_ms(),
            });
            self.events.push_back(NodeEvent::Time(t));
        }
    }

    /// After a change of 0x1012, a reset or a clock set: when the producer sends next.
    pub(super) fn reload_time(&mut self, now: Instant) {
        let producing = self.time_cob() & TIME_PRODUCER != 0 && self.clock.is_some();
        self.time_at = producing.then_some(now);
    }

    /// The producer's timer: sends the time of day when it is due.
    pub(super) fn time_timer(&mut self, now: Instant) {
        let Some(due) = self.time_at.filter(|t| *t <= now) else {
            return;
        };
        let period = self.time_period.max(Duration::from_millis(1));
        let next = due + period;
        self.time_at = Some(if next <= now { now + period } else { next });
        let Some(clock) = self.clock else {
            return;
        };
        if matches!(self.state, NmtState::PreOperational | NmtState::Operational) {
            let t = clock.time_at(now).encode();
            let mut data = [0u8; 8];
            data[..6].copy_from_slice(&t);
            let cob = (self.time_cob() & 0x7FF) as u16;
            self.tx.push_back((cob, data, 6));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_of_day_bytes() {
        // 2026-12-04 12:00:00.250: 15,678 days after 1984-01-01 (42 years with 11 leap days: 42·365 +
        // 11 = 15,341, then 337 days from January 1 to December 4 of a non-leap year), 43,200,250 ms
        // = 0x0293_2EFA after midnight.
        let t = TimeOfDay {
            ms: 43_200_250,
            days: 15_678,
        };
        assert_eq!(t.encode(), [0xFA, 0x2E, 0x93, 0x02, 0x3E, 0x3D]);
        assert_eq!(TimeOfDay::decode(&t.encode()), Some(t));
        assert_eq!(TimeOfDay::from_ms(t.to_ms()), t);
        // The reserved bits 28–31 are ignored on receipt.
        assert_eq!(
            TimeOfDay::decode(&[0xFA, 0x2E, 0x93, 0xF2, 0x3E, 0x3D]),
            Some(t)
        );
        // A day or more of milliseconds, or another length, is no time of day.
        let day = (DAY_MS as u32).to_le_bytes();
        assert_eq!(
            TimeOfDay::decode(&[day[0], day[1], day[2], day[3], 0, 0]),
            None
        );
        assert_eq!(TimeOfDay::decode(&[0; 5]), None);
        assert_eq!(TimeOfDay::decode(&[0; 7]), None);
        assert_eq!(UNIX_TO_1984_MS, 441_763_200_000);
    }

    #[test]
    fn clock_runs_on() {
        let t0 = Instant::now();
        let c = Clock {
            at: t0,
            ms: DAY_MS - 500,
        };
        assert_eq!(c.time_at(t0), TimeOfDay::from_ms(DAY_MS - 500));
        assert_eq!(
            c.time_at(t0 + Duration::from_millis(700)),
            TimeOfDay { ms: 200, days: 1 }
        );
    }
}
