//! The PDO engine of the node (CiA 301 §7.2.2): RPDOs applied on receipt or at the next SYNC, TPDOs sent
//! on SYNC, on a change of their data, on a remote frame and by their event timer, each within its
//! inhibit time. Types 252 and 253 are sent on a remote frame only: 252 with the data sampled at the
//! last SYNC, 253 with the data of the moment. The configurations come from the dictionary ([`PdoConfig::read`]).

use std::time::{Duration, Instant};

use od::dict::{Address, Dictionary};
use od::hook;

use super::emcy::{error_register, frame_data, PDO_LENGTH_ERROR};
use super::pdo::{PdoConfig, COB_NO_RTR, RPDO_COMM, TPDO_COMM};
use super::{Core, Device, NmtState};

/// Runtime state of one TPDO.
#[derive(Debug, Clone, Default)]
pub(super) struct TxState {
    last: Option<[u8; 8]>,
    sync_count: u8,
    /// Data changed since the last transmission (type 0) or a transmission is owed (254/255).
    pending: bool,
    inhibit_until: Option<Instant>,
    event_at: Option<Instant>,
    /// Type 252: the data sampled at the last SYNC, which a remote frame asks for.
    sampled: Option<([u8; 8], usize)>,
}

impl<A: Device> Core<A> {
    /// Reads every PDO's configuration from the dictionary again (RPDOs pending a SYNC are dropped).
    pub(super) fn reload_pdos(&mut self) {
        let read = |base: u16, dict: &Dictionary| -> Vec<PdoConfig> {
            (0..0x200)
                .map_while(|n| PdoConfig::read(dict, base + n))
                .collect()
        };
        self.rpdos = read(RPDO_COMM, &self.dict);
        self.tpdos = read(TPDO_COMM, &self.dict);
        self.rpdo_pending = vec![None; self.rpdos.len()];
        self.tpdo_state.resize(self.tpdos.len(), TxState::default());
        self.reload_listen();
    }

    /// A PDO parameter was written: the configurations are read again, and a TPDO that has just become
    /// valid starts afresh (254/255 send at once).
    pub(super) fn pdos_changed(&mut self) {
        let before: Vec<bool> = self.tpdos.iter().map(PdoConfig::valid).collect();
        self.reload_pdos();
        for (n, cfg) in self.tpdos.iter().enumerate() {
            if cfg.valid() && !before.get(n).copied().unwrap_or(false) {
                self.tpdo_state[n] = TxState {
                    pending: matches!(cfg.transmission, 254 | 255),
                    ..TxState::default()
                };
            }
        }
    }

    /// Entering Operational: every TPDO starts afresh (254/255 send once, and their event timers run
    /// from that transmission), RPDOs pending a SYNC are dropped.
    pub(super) fn start_pdos(&mut self) {
        for (cfg, st) in self.tpdos.iter().zip(self.tpdo_state.iter_mut()) {
            st.last = None;
            st.sync_count = 0;
            st.pending = matches!(cfg.transmission, 254 | 255);
            st.event_at = None;
            st.sampled = None;
        }
        for p in &mut self.rpdo_pending {
            *p = None;
        }
    }

    /// The earliest event timer, or transmission owed by an event-driven TPDO (at once, or when its
    /// inhibit time ends) (Operational only). Only event-driven TPDOs (254/255) have timers: the event
    /// timer of a synchronous one does nothing (CiA 301 §7.5.2.35).
    pub(super) fn tpdo_timeout(&self) -> Option<Instant> {
        if self.state != NmtState::Operational {
            return None;
        }
        self.tpdos
            .iter()
            .zip(&self.tpdo_state)
            .filter(|(cfg, _)| cfg.valid() && cfg.transmission >= 254)
            .flat_map(|(_, st)| {
                [
                    st.event_at,
                    st.pending.then(|| st.inhibit_until.unwrap_or(self.now)),
                ]
            })
            .flatten()
            .min()
    }

    /// The data of TPDO `n` from the application and the dictionary (dummies are zero).
    fn tpdo_data(&self, n: usize) -> ([u8; 8], usize) {
        let mut out = [0u8; 8];
        let mut at = 0usize;
        let mut buf = [0u8; 8];
        for e in &self.tpdos[n].map {
            let len = e.len();
            if at + len > 8 {
                break;
            }
            if !e.is_dummy() {
                let bytes = hook::value(
                    &self.dict,
                    &self.app,
                    Address::new(e.index, e.sub),
                    &mut buf,
                );
                let k = bytes.len().min(len);
                out[at..at + k].copy_from_slice(&bytes[..k]);
            }
            at += len;
        }
        (out, at)
    }

    fn send_tpdo(&mut self, now: Instant, n: usize, data: [u8; 8], len: usize) {
        let cfg = &self.tpdos[n];
        let st = &mut self.tpdo_state[n];
        self.tx.push_back((cfg.cob_id(), data, len as u8));
        st.last = Some(data);
        st.pending = false;
        st.inhibit_until =
            (cfg.inhibit > 0).then(|| now + Duration::from_micros(100 * u64::from(cfg.inhibit)));
        st.event_at =
            (cfg.event_timer > 0).then(|| now + Duration::from_millis(u64::from(cfg.event_timer)));
    }

    /// Event-driven TPDOs (254/255): data changed since the last transmission. Type 0: remember the
    /// change for the next SYNC.
    pub(super) fn event_tpdos(&mut self, now: Instant) {
        for n in 0..self.tpdos.len() {
            let cfg = &self.tpdos[n];
            if !cfg.valid() {
                continue;
            }
            let t = cfg.transmission;
            if !(t == 0 || t >= 254) {
                continue;
            }
            let (data, len) = self.tpdo_data(n);
            let st = &mut self.tpdo_state[n];
            if st.last != Some(data) {
                if t == 0 {
                    st.pending = true;
                    continue;
                }
                st.pending = true;
            }
            if t >= 254 && st.pending && st.inhibit_until.is_none_or(|i| i <= now) {
                self.send_tpdo(now, n, data, len);
            }
        }
    }

    /// Inhibit expiries with a transmission owed, and event timers.
    pub(super) fn timed_tpdos(&mut self, now: Instant) {
        for n in 0..self.tpdos.len() {
            let cfg = &self.tpdos[n];
            if !cfg.valid() || cfg.transmission < 254 {
                continue;
            }
            let st = &self.tpdo_state[n];
            let inhibit_ok = st.inhibit_until.is_none_or(|i| i <= now);
            let timer = st.event_at.is_some_and(|t| t <= now);
            if inhibit_ok && (st.pending || timer) {
                let (data, len) = self.tpdo_data(n);
                self.send_tpdo(now, n, data, len);
            }
        }
    }

    /// A SYNC: synchronous RPDOs take effect, synchronous TPDOs are sent. The device runs up to the
    /// SYNC and takes it; what that changed is checked for errors and event-driven TPDOs at the next
    /// [`Core::poll`], as after any other run of the device: a device that reaches an idle state in
    /// those ticks (a quick stop ending in Switch on disabled) asks for no tick after them at which
    /// the change would otherwise be seen.
    pub(super) fn sync(&mut self, now: Instant) {
        if self.state != NmtState::Operational {
            return;
        }
        self.device_up_to(now);
        for n in 0..self.rpdos.len() {
            if let Some((data, len)) = self.rpdo_pending[n].take() {
                self.apply_rpdo(n, &data[..len], now);
            }
        }
        self.app.sync(now);
        self.device_ran = true;
        for n in 0..self.tpdos.len() {
            let cfg = &self.tpdos[n];
            if !cfg.valid() {
                continue;
            }
            let t = cfg.transmission;
            let due = match t {
                0 => {
                    let (data, _) = self.tpdo_data(n);
                    let st = &self.tpdo_state[n];
                    st.pending || st.last != Some(data)
                }
                1..=240 => {
                    let st = &mut self.tpdo_state[n];
                    st.sync_count += 1;
                    if st.sync_count >= t {
                        st.sync_count = 0;
                        true
                    } else {
                        false
                    }
                }
                252 => {
                    self.tpdo_state[n].sampled = Some(self.tpdo_data(n));
                    false
                }
                _ => false,
            };
            if due {
                let (data, len) = self.tpdo_data(n);
                self.send_tpdo(now, n, data, len);
            }
        }
    }

    /// A remote frame for a TPDO (COB-ID bit 30 clear): its current data; for type 252 (synchronous,
    /// remote request only) the data sampled at the last SYNC (CiA 301 §7.2.2.2), the current data
    /// before the first.
    pub(super) fn rtr(&mut self, now: Instant, cob: u16) {
        if self.state != NmtState::Operational {
            return;
        }
        if let Some(n) = self
            .tpdos
            .iter()
            .position(|c| c.valid() && c.cob_raw & COB_NO_RTR == 0 && c.cob_id() == cob)
        {
            let (data, len) = match self.tpdo_state[n].sampled {
                Some(sampled) if self.tpdos[n].transmission == 252 => sampled,
                _ => self.tpdo_data(n),
            };
            self.send_tpdo(now, n, data, len);
        }
    }

    /// A data frame that may be an RPDO: applied now (254/255) or at the next SYNC (0–240); one shorter
    /// than its mapping raises EMCY 0x8210 and is dropped.
    pub(super) fn rpdo(&mut self, now: Instant, cob: u16, data: &[u8]) {
        let Some(n) = self
            .rpdos
            .iter()
            .position(|c| c.valid() && c.cob_id() == cob)
        else {
            return;
        };
        let need = self.rpdos[n].len();
        if data.len() < need {
            let c = cob.to_le_bytes();
            self.queue_emcy(frame_data(
                PDO_LENGTH_ERROR,
                error_register(&self.active) | 0x11,
                [c[0], c[1], data.len() as u8, need as u8, 0],
            ));
            return;
        }
        if self.rpdos[n].transmission <= 240 {
            let mut buf = [0u8; 8];
            buf[..data.len()].copy_from_slice(data);
            self.rpdo_pending[n] = Some((buf, data.len()));
        } else {
            self.apply_rpdo(n, data, now);
        }
    }

    /// Hands the mapped bytes of RPDO `n`, taking effect at `now`, to the device (run up to `now`
    /// first) and the dictionary (dummies skipped).
    fn apply_rpdo(&mut self, n: usize, data: &[u8], now: Instant) {
        self.device_up_to(now);
        let mut at = 0usize;
        for k in 0..self.rpdos[n].map.len() {
            let e = self.rpdos[n].map[k];
            let len = e.len();
            if at + len > data.len() {
                break;
            }
            let bytes = &data[at..at + len];
            at += len;
            if e.is_dummy() {
                continue;
            }
            hook::deliver(
                &mut self.dict,
                &mut self.app,
                Address::new(e.index, e.sub),
                bytes,
                now,
            );
        }
    }
}
