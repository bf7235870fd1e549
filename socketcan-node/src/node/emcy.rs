//! The EMCY producer (CiA 301 §7.2.7): error codes, active errors, the error register 0x1001, the
//! pre-defined error field 0x1003 and the frames to send under COB-ID 0x1014 and inhibit time 0x1015.

use std::time::{Duration, Instant};

use super::pdo::COB_INVALID;
use super::{Core, Device, NmtState};
pub use od::emcy::{
    error_register, frame_data, DeviceError, EmcyCode, HEARTBEAT_ERROR, NO_ERROR, PDO_LENGTH_ERROR,
};
/// Most EMCYs waiting for the inhibit time; more are dropped.
const QUEUE_LIMIT: usize = 64;

impl<A: Device> Core<A> {
    /// Compares the application's errors with the active ones and raises / clears EMCYs. The errors
    /// the node raises itself (heartbeat, PDO length) are not the application's to clear.
    pub(super) fn check_errors(&mut self) {
        let mut now_errors = std::mem::take(&mut self.scratch);
        now_errors.clear();
        self.app.errors(&mut now_errors);
        let gone: Vec<DeviceError> = self
            .active
            .iter()
            .filter(|e| e.code != HEARTBEAT_ERROR && e.code != PDO_LENGTH_ERROR)
            .filter(|e| !now_errors.contains(e))
            .copied()
            .collect();
        for e in gone {
            self.clear_app_error(e);
        }
        for e in &now_errors {
            if !self.active.contains(e) {
                self.raise_error(*e);
            }
        }
        self.scratch = now_errors;
    }

    /// Makes `e` active: history 0x1003, register 0x1001 and its EMCY.
    pub(super) fn raise_error(&mut self, e: DeviceError) {
        if self.active.contains(&e) {
            return;
        }
        self.active.push(e);
        self.history.insert(0, u32::from(e.code.get()));
        self.history.truncate(
            self.dict
                .object(0x1003)
                .map_or(0, |o| usize::from(o.max_sub())),
        );
        self.sync_error_objects();
        let reg = error_register(&self.active);
        self.queue_emcy(frame_data(e.code, reg, e.info));
    }

    /// Clears every active error with `code`.
    pub(super) fn clear_error(&mut self, code: EmcyCode) {
        let gone: Vec<DeviceError> = self
            .active
            .iter()
            .filter(|e| e.code == code)
            .copied()
            .collect();
        for e in gone {
            self.clear_app_error(e);
        }
    }

    fn clear_app_error(&mut self, e: DeviceError) {
        self.active.retain(|a| *a != e);
        self.sync_error_objects();
        let reg = error_register(&self.active);
        let c = e.code.to_le_bytes();
        // "Error reset": code 0x0000, the remaining register, which module/axis and the cleared code.
        self.queue_emcy(frame_data(
            NO_ERROR,
            reg,
            [e.info[0], e.info[1], c[0], c[1], 0],
        ));
    }

    /// 0x1003:00 written with 0: the history is emptied (the active errors stay).
    pub(super) fn clear_history(&mut self) {
        self.history.clear();
        self.sync_error_objects();
    }

    /// Forgets the active errors, the history and the EMCYs not sent yet (a reset).
    pub(super) fn reset_emcy(&mut self) {
        self.active.clear();
        self.history.clear();
        self.emcy_queue.clear();
        self.emcy_after = None;
        self.sync_error_objects();
    }

    /// Writes the error register 0x1001 and the history 0x1003 into the dictionary.
    fn sync_error_objects(&mut self) {
        let reg = error_register(&self.active);
        let _ = self.dict.store(0x1001, 0, &[reg]);
        let _ = self.dict.store(0x1003, 0, &[self.history.len() as u8]);
        let max = self.dict.object(0x1003).map_or(0, |o| o.max_sub());
        for s in 1..=max {
            let v = self.history.get(usize::from(s) - 1).copied().unwrap_or(0);
            let _ = self.dict.store(0x1003, s, &v.to_le_bytes());
        }
    }

    /// Queues an EMCY frame's data and sends what the inhibit time allows.
    pub(super) fn queue_emcy(&mut self, data: [u8; 8]) {
        if self.emcy_queue.len() < QUEUE_LIMIT {
            self.emcy_queue.push_back(data);
        }
        self.flush_emcy(self.now);
    }

    /// Sends queued EMCYs as the inhibit time (0x1015, 100 µs) allows; in Pre-operational and
    /// Operational only, while the COB-ID is valid.
    pub(super) fn flush_emcy(&mut self, now: Instant) {
        if !matches!(self.state, NmtState::PreOperational | NmtState::Operational) {
            return;
        }
        let cob = self.u32_at(0x1014, 0).unwrap_or(0x80 + u32::from(self.id));
        if cob & COB_INVALID != 0 {
            self.emcy_queue.clear();
            return;
        }
        let inhibit = Duration::from_micros(100 * u64::from(self.u32_at(0x1015, 0).unwrap_or(0)));
        while self.emcy_after.is_none_or(|t| t <= now) {
            let Some(data) = self.emcy_queue.pop_front() else {
                break;
            };
            self.tx.push_back(((cob & 0x7FF) as u16, data, 8));
            self.emcy_after = (inhibit > Duration::ZERO).then(|| now + inhibit);
        }
    }

    /// When the inhibit time lets the next queued EMCY go.
    pub(super) fn emcy_timeout(&self) -> Option<Instant> {
        self.emcy_after.filter(|_| !self.emcy_queue.is_empty())
    }
}
