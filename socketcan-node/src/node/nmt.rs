//! NMT slave (CiA 301 §7.3.2), resets with the stored parameters, and error control by heartbeat
//! (§7.2.8.3.2): the producer of 0x1017 and the consumer of 0x1016:01.

use std::time::{Duration, Instant};

use od::dict::Address;

use super::emcy::{DeviceError, HEARTBEAT_ERROR};
use super::{storage, Core, Device, NmtState, NodeEvent};

/// Heartbeat consumer of 0x1016:01.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Consumer {
    /// The monitored node (0: none).
    pub(super) node: u8,
    /// The heartbeat time; zero when nothing is monitored.
    pub(super) time: Duration,
    pub(super) deadline: Option<Instant>,
    lost: bool,
}

impl<A: Device> Core<A> {
    pub(super) fn set_state(&mut self, state: NmtState) {
        if self.state == state {
            return;
        }
        self.state = state;
        self.events.push_back(NodeEvent::State(state));
        if state == NmtState::Operational {
            self.start_pdos();
        }
    }

    /// NMT command `cs` for this node; true when it reset the node (node or communication).
    pub(super) fn nmt(&mut self, now: Instant, cs: u8) -> bool {
        if self.state == NmtState::Initialising {
            return false;
        }
        match cs {
            0x01 => self.set_state(NmtState::Operational),
            0x02 => self.set_state(NmtState::Stopped),
            0x80 => self.set_state(NmtState::PreOperational),
            0x81 => self.reset(now, true),
            0x82 => self.reset(now, false),
            _ => {}
        }
        matches!(cs, 0x81 | 0x82)
    }

    /// Reset node (`full`) or reset communication, then boot-up and Pre-operational.
    pub(super) fn reset(&mut self, now: Instant, full: bool) {
        self.events.push_back(NodeEvent::Reset(full));
        self.state = NmtState::Initialising;
        let range = if full {
            0x0000..=0xFFFF
        } else {
            0x1000..=0x1FFF
        };
        for object in self.pristine.objects() {
            if range.contains(&object.index) {
                self.dict.insert(object.clone());
            }
        }
        if full {
            self.app.reset(now);
        }
        let stored = match self.stored.as_deref().map(storage::decode) {
            Some(Ok(set)) => set,
            Some(Err(e)) => {
                self.events.push_back(NodeEvent::Storage(e));
                Vec::new()
            }
            None => Vec::new(),
        };
        let mut loaded = 0;
        for (index, sub, value) in stored {
            if !range.contains(&index) || !self.storable(index, sub) {
                continue;
            }
            if self.dict.check(index, sub, &value).is_err() {
                continue;
            }
            if self.app.owns(index)
                && self
                    .app
                    .write(Address::new(index, sub), &value, now)
                    .is_err()
            {
                continue;
            }
            if self.dict.store(index, sub, &value).is_ok() {
                loaded += 1;
            }
        }
        if loaded > 0 {
            self.events.push_back(NodeEvent::Loaded(loaded));
        }
        self.reset_emcy();
        self.tx.clear();
        self.reload_pdos();
        self.reload_consumer();
        // Boot-up, then Pre-operational (CiA 301 §7.3.2.2.1).
        self.tx.push_back((0x700 + u16::from(self.id), [0; 8], 1));
        self.set_state(NmtState::PreOperational);
        self.heartbeat_at = self.heartbeat_period().map(|p| now + p);
        self.sync_at = self.sync_period().map(|p| now + p);
        self.reload_time(now);
        self.reload_listen();
        self.now = now;
        self.booted_at = Some(now);
    }

    /// The boot-up message left at `at`: the timers the boot started (heartbeat producer, SYNC and
    /// TIME producers) run from then, so that the first heartbeat comes one producer time after the
    /// boot-up message (CiA 301, heartbeat protocol), however long the reset's own work kept the frame.
    pub(super) fn boot_up_sent(&mut self, at: Instant) {
        let Some(booted) = self.booted_at.take() else {
            return;
        };
        let Some(late) = at.checked_duration_since(booted).filter(|d| !d.is_zero()) else {
            return;
        };
        for timer in [&mut self.heartbeat_at, &mut self.sync_at, &mut self.time_at] {
            if let Some(t) = timer.as_mut() {
                *t += late;
            }
        }
    }

    /// The producer heartbeat time 0x1017; `None` when it is 0 (no heartbeat).
    pub(super) fn heartbeat_period(&self) -> Option<Duration> {
        let ms = self.u32_at(0x1017, 0).unwrap_or(0);
        (ms > 0).then(|| Duration::from_millis(u64::from(ms)))
    }

    /// Reads the consumer 0x1016:01 again; monitoring starts again with the producer's next heartbeat.
    pub(super) fn reload_consumer(&mut self) {
        let raw = self.u32_at(0x1016, 1).unwrap_or(0);
        let node = (raw >> 16) as u8;
        let ms = raw & 0xFFFF;
        let was_lost = self.consumer.lost;
        self.consumer = Consumer {
            node,
            time: if node == 0 || node > 127 {
                Duration::ZERO
            } else {
                Duration::from_millis(u64::from(ms))
            },
            deadline: None,
            lost: false,
        };
        if was_lost {
            self.clear_error(HEARTBEAT_ERROR);
        }
        self.reload_listen();
    }

    /// A heartbeat of the monitored producer: its deadline moves on, a lost producer is back.
    pub(super) fn heartbeat_seen(&mut self, now: Instant) {
        self.consumer.deadline = Some(now + self.consumer.time);
        if self.consumer.lost {
            self.consumer.lost = false;
            self.events
                .push_back(NodeEvent::HeartbeatResumed(self.consumer.node));
            self.clear_error(HEARTBEAT_ERROR);
        }
    }

    /// The heartbeat producer's beat and the consumer's deadline, when due at `now`.
    pub(super) fn heartbeat_timers(&mut self, now: Instant) {
        if let Some(t) = self.heartbeat_at.filter(|t| *t <= now) {
            self.tx.push_back((
                0x700 + u16::from(self.id),
                [self.state.heartbeat_byte(), 0, 0, 0, 0, 0, 0, 0],
                1,
            ));
            let p = self.heartbeat_period().unwrap_or(Duration::from_secs(1));
            // Keep the period without drift; a beat sent more than half a period late (a stalled
            // thread, a machine under load) starts the period again from now, so that two beats
            // never leave closer than half a period.
            let next = t + p;
            self.heartbeat_at = Some(if next < now + p / 2 { now + p } else { next });
        }
        if self.consumer.deadline.is_some_and(|d| d <= now) {
            self.consumer.deadline = None;
            if !self.consumer.lost {
                self.consumer.lost = true;
                self.events
                    .push_back(NodeEvent::HeartbeatLost(self.consumer.node));
                self.raise_error(DeviceError {
                    code: HEARTBEAT_ERROR,
                    info: [self.consumer.node, 0, 0, 0, 0],
                });
                if self.state == NmtState::Operational {
                    self.set_state(NmtState::PreOperational);
                }
            }
        }
    }
}
