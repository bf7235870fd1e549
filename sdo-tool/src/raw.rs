//! Raw frames for `send` and `sync`: a frame in cansend's notation ([`cansend_frame`]) and the
//! SYNC producer's schedule ([`SyncSchedule`], sans-IO: the caller gives the time, sends what it
//! hands out and waits until [`SyncSchedule::poll_timeout`]).

use std::time::{Duration, Instant};

use crate::link::CanFrame;

/// A frame in can-utils' `cansend` notation: `ID#DATA` with ID three hex digits (11 bits, up to
/// 7FF) or eight (29 bits, up to 1FFFFFFF), DATA 0 to 8 bytes as hex digit pairs, a `.` allowed
/// between bytes (`123#DE.AD.BE.EF`); `ID#R` is a remote frame (RTR), `ID#R3` one asking for 3
/// bytes. Anything else: why not, in words.
pub fn cansend_frame(text: &str) -> Result<CanFrame, String> {
    let (id, data) = text
        .trim()
        .split_once('#')
        .ok_or("no '#' between the identifier and the data (ID#DATA, e.g. 123#DEADBEEF)")?;
    if data.starts_with('#') {
        return Err("CAN FD (##) is not sent: classic CAN frames only".into());
    }
    let hex = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_hexdigit());
    if !hex(id) {
        return Err(format!("identifier {id:?} is not hex digits"));
    }
    let (raw, extended) = match id.len() {
        3 => (
            u32::from_str_radix(id, 16).map_err(|e| e.to_string())?,
            false,
        ),
        8 => (
            u32::from_str_radix(id, 16).map_err(|e| e.to_string())?,
            true,
        ),
        n => {
            return Err(format!(
                "identifier {id:?} has {n} digits: 3 for 11 bits (000 to 7FF) or 8 for 29 bits \
                 (00000000 to 1FFFFFFF)"
            ))
        }
    };
    let limit = if extended { 0x1FFF_FFFF } else { 0x7FF };
    if raw > limit {
        return Err(format!("identifier {id} is above {limit:X}"));
    }
    if let Some(len) = data.strip_prefix('R').or_else(|| data.strip_prefix('r')) {
        let len: u8 = match len {
            "" => 0,
            _ => Some(len)
                .filter(|l| l.bytes().all(|b| b.is_ascii_digit()))
                .and_then(|l| l.parse().ok())
                .filter(|l| *l <= 8)
                .ok_or_else(|| format!("remote frame length {len:?} is not 0 to 8"))?,
        };
        return CanFrame::new_remote_frame(raw, extended, len).ok_or_else(|| "no frame".into());
    }
    let digits: String = data.chars().filter(|c| *c != '.').collect();
    if !digits.is_empty() && !hex(&digits) {
        return Err(format!("data {data:?} is not hex digits"));
    }
    if digits.len() & 1 == 1 {
        return Err(format!("data {data:?} has an odd number of hex digits"));
    }
    if digits.len() > 16 {
        return Err(format!(
            "data {data:?} is {} bytes: a classic CAN frame carries 0 to 8",
            digits.len() / 2
        ));
    }
    let bytes: Vec<u8> = (0..digits.len())
        .step_by(2)
        .map(|k| u8::from_str_radix(&digits[k..k + 2], 16).unwrap_or(0))
        .collect();
    let frame = if extended {
        CanFrame::new_extended(raw, &bytes)
    } else {
        CanFrame::new(raw as u16, &bytes)
    };
    frame.ok_or_else(|| "no frame".into())
}

/// The largest SYNC counter overflow value CiA 301 allows (0x1019: 2 to 240).
pub const MAX_SYNC_OVERFLOW: u8 = 240;

/// A SYNC producer's schedule (CiA 301 §7.2.5): `count` SYNC messages on `cob_id` (0 for no end),
/// the first at once, the next each `period` later (counted from the first, so they do not drift),
/// each with the counter byte when there is one: 1, 2, … up to its overflow value, then 1 again.
#[derive(Debug, Clone)]
pub struct SyncSchedule {
    cob_id: u16,
    period: Duration,
    left: Option<u64>,
    counter: Option<(u8, u8)>,
    first: Instant,
    sent: u64,
}

impl SyncSchedule {
    /// The schedule from `now`: `count` messages (0: until stopped), `period` apart, with a
    /// counter up to `overflow` (2 to 240) when given.
    pub fn new(
        cob_id: u16,
        count: u64,
        period: Duration,
        overflow: Option<u8>,
        now: Instant,
    ) -> SyncSchedule {
        SyncSchedule {
            cob_id,
            period,
            left: (count > 0).then_some(count),
            counter: overflow.map(|o| (1, o.clamp(2, MAX_SYNC_OVERFLOW))),
            first: now,
            sent: 0,
        }
    }

    /// When the next message is due; `None` when all were sent.
    pub fn poll_timeout(&self) -> Option<Instant> {
        if self.left == Some(0) {
            return None;
        }
        let k = u32::try_from(self.sent).unwrap_or(u32::MAX);
        self.first.checked_add(self.period.checked_mul(k)?)
    }

    /// The message due by `now`, if one is; the caller sends it and asks again.
    pub fn handle_timeout(&mut self, now: Instant) -> Option<CanFrame> {
        if self.poll_timeout()? > now {
            return None;
        }
        self.sent += 1;
        if let Some(left) = &mut self.left {
            *left -= 1;
        }
        match &mut self.counter {
            Some((value, overflow)) => {
                let v = *value;
                *value = if v >= *overflow { 1 } else { v + 1 };
                CanFrame::new(self.cob_id, &[v])
            }
            None => CanFrame::new(self.cob_id, &[]),
        }
    }

    /// The messages sent so far.
    pub fn sent(&self) -> u64 {
        self.sent
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(f: &CanFrame) -> String {
        let data: String = f.data().iter().map(|b| format!("{b:02X}")).collect();
        let rtr = if f.is_rtr() { "R" } else { "" };
        format!("{:X}#{rtr}{data}/{}", f.raw_id(), f.len())
    }

    /// cansend's examples (can-utils' usage text) and the limits of each part.
    #[test]
    fn frames_in_cansend_notation() {
        let ok = |t: &str| text(&cansend_frame(t).unwrap());
        assert_eq!(ok("123#DEADBEEF"), "123#DEADBEEF/4");
        assert_eq!(ok("5A1#11.2233.44556677.88"), "5A1#1122334455667788/8");
        assert_eq!(ok("123#"), "123#/0");
        assert_eq!(ok("7FF#00"), "7FF#00/1");
        assert_eq!(ok("5AA#"), "5AA#/0");
        assert_eq!(ok("123#R"), "123#R/0");
        assert_eq!(ok("123#R3"), "123#R/3");
        assert_eq!(ok("12345678#0102"), "12345678#0102/2");
        assert_eq!(
            ok("1F334455#1122334455667788"),
            "1F334455#1122334455667788/8"
        );
        let f = cansend_frame("00000123#01").unwrap();
        assert!(f.is_extended());
        assert!(!cansend_frame("123#01").unwrap().is_extended());
        let err = |t: &str| cansend_frame(t).unwrap_err();
        assert_eq!(
            err("123DEADBEEF"),
            "no '#' between the identifier and the data (ID#DATA, e.g. 123#DEADBEEF)"
        );
        assert_eq!(err("800#00"), "identifier 800 is above 7FF");
        assert_eq!(err("20000000#00"), "identifier 20000000 is above 1FFFFFFF");
        assert!(err("1234#00").starts_with("identifier \"1234\" has 4 digits"));
        assert_eq!(err("12G#00"), "identifier \"12G\" is not hex digits");
        assert_eq!(err("123#1"), "data \"1\" has an odd number of hex digits");
        assert_eq!(err("123#XY"), "data \"XY\" is not hex digits");
        assert_eq!(
            err("123#001122334455667788"),
            "data \"001122334455667788\" is 9 bytes: a classic CAN frame carries 0 to 8"
        );
        assert_eq!(err("123#R9"), "remote frame length \"9\" is not 0 to 8");
        assert_eq!(err("123#R+1"), "remote frame length \"+1\" is not 0 to 8");
        assert_eq!(
            err("123##1"),
            "CAN FD (##) is not sent: classic CAN frames only"
        );
    }

    /// Three SYNC 10 ms apart from the first, the counter wrapping after its overflow value; the
    /// instants counted from the first, so a late call does not move the next.
    #[test]
    fn the_sync_schedule() {
        let t0 = Instant::now();
        let ms = Duration::from_millis;
        let mut s = SyncSchedule::new(0x80, 3, ms(10), Some(2), t0);
        assert_eq!(s.poll_timeout(), Some(t0));
        assert_eq!(text(&s.handle_timeout(t0).unwrap()), "80#01/1");
        assert!(s.handle_timeout(t0 + ms(9)).is_none());
        assert_eq!(s.poll_timeout(), Some(t0 + ms(10)));
        // Late: due at 10, handled at 15; the next is still due at 20.
        assert_eq!(text(&s.handle_timeout(t0 + ms(15)).unwrap()), "80#02/1");
        assert_eq!(s.poll_timeout(), Some(t0 + ms(20)));
        assert_eq!(text(&s.handle_timeout(t0 + ms(20)).unwrap()), "80#01/1");
        assert_eq!(s.poll_timeout(), None);
        assert!(s.handle_timeout(t0 + ms(100)).is_none());
        assert_eq!(s.sent(), 3);
        // No counter: no data; no end with a count of 0; another COB-ID.
        let mut s = SyncSchedule::new(0x90, 0, ms(1), None, t0);
        for k in 0..1000u64 {
            let f = s.handle_timeout(t0 + ms(k)).unwrap();
            assert_eq!(text(&f), "90#/0");
        }
        assert_eq!(s.poll_timeout(), Some(t0 + ms(1000)));
        // The counter runs up to 240 at most, and 2 at least.
        let mut s = SyncSchedule::new(0x80, 0, ms(0), Some(255), t0);
        let values: Vec<u8> = (0..241)
            .map(|_| s.handle_timeout(t0).unwrap().data()[0])
            .collect();
        assert_eq!(values[239], 240);
        assert_eq!(values[240], 1);
        let mut s = SyncSchedule::new(0x80, 0, ms(0), Some(1), t0);
        let values: Vec<u8> = (0..3)
            .map(|_| s.handle_timeout(t0).unwrap().data()[0])
            .collect();
        assert_eq!(values, [1, 2, 1]);
    }
}
