//! Distributed Clocks (ETG.1000.4 §6.8, registers 0x0900–0x09FF) of the emulated ESC.
//!
//! Each slave has a local clock in nanoseconds: the chain's time ([`super::Chain::set_now`])
//! plus a start offset of its own (slaves do not power up at the same instant) plus the time the frame
//! takes to reach it ([`HOP_NS`] per slave on the way out, the same back).
//!
//! - **Receive times** (0x0900–0x090F, 0x0918): a write to 0x0900 latches, as the frame passes, the
//!   local time on port 0 and — when a slave follows — on port 1 when the frame comes back; 0x0918 is
//!   the port-0 time in 64 bits.
//! - **System time** (0x0910, 64 bits) reads the local time plus the offset the master wrote
//!   (0x0920). A write to it (the master's drift compensation: ARMW/FRMW of the reference clock's
//!   time) does not set it; the difference goes to 0x092C (bits 0–30 magnitude, bit 31 set when the
//!   local copy is smaller). The emulated clocks do not drift, so nothing is adjusted.
//! - **SYNC0** (0x0981 activation: bit 0 cyclic operation, bit 1 SYNC0; 0x0990 start time, 0x09A0
//!   cycle time): events at start + k·cycle in system time (one event for cycle 0). While active,
//!   0x0990 reads the next event's time; 0x098E bit 0 is set after an event until read.

use super::registers::{SyncActivation, SystemTimeDifference};
use super::{touches, Esc};

/// Nanoseconds a frame takes from one slave to the next (ESC forwarding and a short cable).
pub const HOP_NS: u64 = 500;
/// Receive time port 0.
pub const RECEIVE_TIME: u16 = 0x0900;
/// System time.
pub const SYSTEM_TIME: u16 = 0x0910;
/// Receive time of the ECAT processing unit (port 0), 64 bits.
pub const RECEIVE_TIME_PU: u16 = 0x0918;
/// System time offset.
pub const SYSTEM_TIME_OFFSET: u16 = 0x0920;
/// System time delay.
pub const SYSTEM_TIME_DELAY: u16 = 0x0928;
/// System time difference.
pub const SYSTEM_TIME_DIFFERENCE: u16 = 0x092C;
/// Sync activation.
pub const SYNC_ACTIVATION: u16 = 0x0981;
/// SYNC0 status.
pub const SYNC0_STATUS: u16 = 0x098E;
/// Start time of cyclic operation.
pub const START_TIME: u16 = 0x0990;
/// SYNC0 cycle time.
pub const SYNC0_CYCLE: u16 = 0x09A0;

/// The DC state of one slave.
#[derive(Debug, Clone, Default)]
pub(crate) struct Clock {
    /// Local time at the chain's time 0.
    pub base: u64,
    /// Hops from the master to this slave.
    pub position: u64,
    /// Hops back from this slave to the end of the chain and back here (0 for the last slave).
    pub return_hops: u64,
    /// The chain's time.
    pub now: u64,
    /// The next SYNC0 event in system time, while SYNC0 runs.
    pub next_sync0: Option<u64>,
    /// SYNC0 has given its first pulse since it was activated.
    pub sync0_started: bool,
}

impl Esc {
    /// The local clock as the frame reaches the slave.
    pub fn local_time(&self) -> u64 {
        self.clock
            .now
            .wrapping_add(self.clock.base)
            .wrapping_add(self.clock.position * HOP_NS)
    }

    /// System time: local time plus the offset the master set.
    pub fn system_time(&self) -> u64 {
        self.local_time()
            .wrapping_add(self.u64_at(SYSTEM_TIME_OFFSET))
    }

    fn u64_at(&self, at: u16) -> u64 {
        u64::from_le_bytes(self.bytes_at(at))
    }

    /// Before the master reads DC registers: the system time and the next SYNC0 time are current.
    pub(crate) fn dc_before_read(&mut self, at: u16, len: usize) {
        if touches(at, len, SYSTEM_TIME, 8) {
            let t = self.system_time();
            self.store(SYSTEM_TIME, &t.to_le_bytes());
        }
        if let Some(next) = self
            .clock
            .next_sync0
            .filter(|_| touches(at, len, START_TIME, 8))
        {
            self.store(START_TIME, &next.to_le_bytes());
        }
    }

    /// After a read: reading SYNC0 status clears it.
    pub(crate) fn dc_after_read(&mut self, at: u16, len: usize) {
        if touches(at, len, SYNC0_STATUS, 1) {
            self.store(SYNC0_STATUS, &[0]);
        }
    }

    /// What a master's write to DC registers does; `before` is the system time register before it.
    pub(crate) fn dc_after_write(&mut self, at: u16, len: usize, before: [u8; 8]) {
        if touches(at, len, RECEIVE_TIME, 4) {
            let t0 = self.local_time();
            self.store(RECEIVE_TIME, &(t0 as u32).to_le_bytes());
            if self.clock.return_hops > 0 {
                let t1 = t0 + self.clock.return_hops * HOP_NS;
                self.store(RECEIVE_TIME + 4, &(t1 as u32).to_le_bytes());
            }
            self.store(RECEIVE_TIME_PU, &t0.to_le_bytes());
        }
        if touches(at, len, SYSTEM_TIME, 8) {
            let received = self.u64_at(SYSTEM_TIME);
            // A 32-bit write compares the low half.
            let local = self.system_time();
            let (received, local) = if len <= 4 && at == SYSTEM_TIME {
                (received & 0xFFFF_FFFF, local & 0xFFFF_FFFF)
            } else {
                (received, local)
            };
            let diff = SystemTimeDifference::between(local, received);
            self.store(SYSTEM_TIME_DIFFERENCE, &diff.encode());
            self.store(SYSTEM_TIME, &before);
        }
        if touches(at, len, SYNC_ACTIVATION, 1) {
            let [act] = self.bytes_at(SYNC_ACTIVATION);
            let running = SyncActivation::decode(act).sync0_running();
            self.clock.next_sync0 = running.then(|| self.u64_at(START_TIME));
            self.clock.sync0_started = false;
        }
    }

    /// SYNC0 cycle time while cyclic operation and SYNC0 are activated.
    pub fn sync0_cycle(&self) -> Option<u32> {
        let [act] = self.bytes_at(SYNC_ACTIVATION);
        SyncActivation::decode(act)
            .sync0_running()
            .then(|| u32::from_le_bytes(self.bytes_at(SYNC0_CYCLE)))
    }

    /// The SYNC0 events up to the present system time: the system time of the last one that passed
    /// since the last call, if any.
    pub fn sync0_passed(&mut self) -> Option<u64> {
        let Some(cycle) = self.sync0_cycle() else {
            self.clock.next_sync0 = None;
            return None;
        };
        let now = self.system_time();
        let next = self.clock.next_sync0.filter(|n| *n <= now)?;
        let last = if cycle == 0 {
            self.clock.next_sync0 = None;
            next
        } else {
            let c = u64::from(cycle);
            let last = next + (now - next) / c * c;
            self.clock.next_sync0 = Some(last + c);
            last
        };
        self.store(SYNC0_STATUS, &[1]);
        self.clock.sync0_started = true;
        Some(last)
    }

    /// Whether SYNC0 is activated and has given its first pulse ([`Esc::sync0_passed`] reported
    /// one): between the activation and the start time the master set (SOEM's some 100 ms later),
    /// it is activated but gives none.
    pub fn sync0_running(&self) -> bool {
        self.sync0_cycle().is_some() && self.clock.sync0_started
    }
}
