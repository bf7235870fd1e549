//! A CiA 301 slave node as a sans-IO state machine: NMT, heartbeat producer and consumer, SYNC consumer
//! and optional producer, PDOs from the dictionary, EMCY, store/restore parameters and the SDO server.
//!
//! The node takes frames with the time they arrived ([`Node::handle_frame`]), is driven by
//! [`Node::handle_timeout`] at [`Node::poll_timeout`], and hands back the frames to send
//! ([`Node::poll_transmit`]). No sockets, threads, files or clocks inside: the runtime at the edge owns
//! those. "Save" (0x1010) and "restore" (0x1011) become requests the edge carries out on its storage
//! ([`Node::poll_storage`]); the edge hands the node the set it loaded ([`Node::set_stored`]).
//!
//! # Methods and polling order
//!
//! 1. [`Node::new`] at `now`, [`Node::set_stored`] with what the edge's storage holds, then
//!    [`Node::start`] (boot-up message, Pre-operational).
//! 2. For every frame received: [`Node::handle_frame`] with the time it arrived.
//! 3. When [`Node::poll_timeout`] has passed: [`Node::handle_timeout`].
//! 4. After each of those calls, drain [`Node::poll_transmit`] (frames in the order to send),
//!    [`Node::poll_storage`] (parameter sets to write or forget) and [`Node::poll_event`].
//! 5. Wait for a frame or for the next [`Node::poll_timeout`], whichever comes first.
//!
//! The device behind the node is an [`Application`]: it owns the manufacturer objects it declares, takes
//! what the master writes to them (by SDO or RPDO), answers reads (SDO uploads and TPDOs), advances its
//! own time and reports its errors, which the node turns into EMCY messages.
//!
//! Choices where CiA 301 leaves room (each is documented at its place):
//! - SDO frames with a DLC other than 8 are ignored; SDO is served in Pre-operational and Operational.
//! - A PDO mapping is changed only in Pre-operational (0x08000022 otherwise), only while the PDO is
//!   invalid (0x06040043), entries only while sub-index 0 is 0 (0x06040043); an entry that does not
//!   exist is 0x06020000, one that cannot be mapped 0x06040041, a count over the entries or 64 bits
//!   0x06040042, an empty or invalid entry among the counted ones 0x06040043.
//! - A COB-ID with bit 29 (29-bit identifiers) or a restricted CAN-ID (§7.3.5) is refused with 0x06090030,
//!   as is a new CAN-ID for a PDO that exists; an inhibit time is changed only while its TPDO is invalid.
//! - RPDO transmission types 0–240 are applied at the next SYNC, 254/255 on receipt; TPDO types 0,
//!   1–240, 254 and 255 are supported (252/253 are refused with 0x06090030). An RPDO shorter than its
//!   mapping is dropped with EMCY 0x8210; a longer one is applied from its first bytes.
//! - Event-driven TPDOs are checked for changed data at every application tick and sent once on
//!   entering Operational; the event timer sends them when nothing changed for its time.
//! - Heartbeat consumer: monitoring starts with the first heartbeat of the producer; a missed heartbeat
//!   raises EMCY 0x8130 (error register bit 4) and takes an Operational node to Pre-operational (the
//!   CiA 301 default error behaviour); the next heartbeat clears the error.

mod emcy;
pub mod pdo;
pub mod storage;

use std::collections::VecDeque;
use std::time::{Duration, Instant};

pub use emcy::{error_register, AppError, HEARTBEAT_ERROR, NO_ERROR, PDO_LENGTH_ERROR};
use od::abort::AbortCode;
use od::dict::{Address, Dictionary};
use od::hook::{self, DeviceHook};
use od::object::PdoMapping;
use od::sdo::{
    server::{SdoServer, ServerConfig, ServerEvent},
    store::{DownloadCapacity, ObjectStore},
};
use pdo::{
    Direction, PdoConfig, COB_EXTENDED, COB_INVALID, COB_NO_RTR, MAP_OFFSET, RPDO_COMM, TPDO_COMM,
};
use storage::StorageRequest;

/// "save" as a little-endian UNSIGNED32 (0x1010).
pub const SAVE_SIGNATURE: u32 = 0x6576_6173;
/// "load" as a little-endian UNSIGNED32 (0x1011).
pub const LOAD_SIGNATURE: u32 = 0x6461_6F6C;

/// The device behind the node: the model that owns its manufacturer objects ([`DeviceHook`], the
/// project's one device hook), with its own time and its errors.
pub trait Application: DeviceHook {
    /// Runs the application up to `now`.
    fn handle_timeout(&mut self, now: Instant);
    /// When [`handle_timeout`](Application::handle_timeout) is next due.
    fn poll_timeout(&self) -> Option<Instant>;
    /// The errors active now.
    fn errors(&self, out: &mut Vec<AppError>);
    /// Back to power-on (NMT reset node), with time starting at `now`.
    fn reset(&mut self, now: Instant);
}

/// The NMT state (CiA 301 §7.3.2.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NmtState {
    /// Before the boot-up message.
    Initialising,
    /// SDO and EMCY, no PDOs.
    PreOperational,
    /// Everything.
    Operational,
    /// NMT and heartbeat only.
    Stopped,
}

impl NmtState {
    /// The state byte of the heartbeat (0x00 boot-up, 0x04, 0x05, 0x7F).
    pub const fn heartbeat_byte(self) -> u8 {
        match self {
            NmtState::Initialising => 0x00,
            NmtState::Stopped => 0x04,
            NmtState::Operational => 0x05,
            NmtState::PreOperational => 0x7F,
        }
    }
}

/// How a node starts.
#[derive(Debug, Clone, Copy)]
pub struct NodeConfig {
    /// Node-ID, 1–127.
    pub node_id: u8,
    /// The SDO server's configuration.
    pub sdo: ServerConfig,
    /// A default for 0x1017 other than the dictionary's (ms), e.g. from `--heartbeat-ms`.
    pub heartbeat_ms: Option<u16>,
}

impl NodeConfig {
    /// Node `node_id` with the defaults.
    pub fn new(node_id: u8) -> NodeConfig {
        NodeConfig {
            node_id,
            sdo: ServerConfig::default(),
            heartbeat_ms: None,
        }
    }
}

/// Why a node could not be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NodeError {
    /// The node-ID is outside 1–127.
    #[error("node-ID {0} is outside 1 to 127")]
    NodeId(u8),
}

/// What happened, for logs and tests.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NodeEvent {
    /// The NMT state changed.
    State(NmtState),
    /// A reset began (`true`: reset node, `false`: reset communication).
    Reset(bool),
    /// The parameters were saved (0x1010).
    Saved,
    /// The stored parameters were forgotten (0x1011); defaults apply at the next reset.
    Restored,
    /// The stored parameter set was refused as a whole at a reset (the defaults apply).
    Storage(storage::ParamFileError),
    /// The stored parameter set was loaded at a reset (number of entries).
    Loaded(usize),
    /// The monitored heartbeat producer was missed.
    HeartbeatLost(u8),
    /// The monitored heartbeat producer is back.
    HeartbeatResumed(u8),
    /// An SDO transfer ended.
    Sdo(ServerEvent),
}

/// Runtime state of one TPDO.
#[derive(Debug, Clone, Default)]
struct TxState {
    last: Option<[u8; 8]>,
    sync_count: u8,
    /// Data changed since the last transmission (type 0) or a transmission is owed (254/255).
    pending: bool,
    inhibit_until: Option<Instant>,
    event_at: Option<Instant>,
}

/// Heartbeat consumer of 0x1016:01.
#[derive(Debug, Clone, Copy, Default)]
struct Consumer {
    node: u8,
    time: Duration,
    deadline: Option<Instant>,
    lost: bool,
}

/// The node minus its SDO server, so the server can borrow it as its object store.
struct Core<A: Application> {
    id: u8,
    state: NmtState,
    dict: Dictionary,
    /// The dictionary as built (defaults, `--heartbeat-ms` applied) for resets.
    pristine: Dictionary,
    app: A,
    /// The parameter set as the edge's storage holds it (loaded at each reset).
    stored: Option<Vec<u8>>,
    storage_out: VecDeque<StorageRequest>,
    tx: VecDeque<(u16, [u8; 8], u8)>,
    events: VecDeque<NodeEvent>,
    rpdos: Vec<PdoConfig>,
    rpdo_pending: Vec<Option<([u8; 8], usize)>>,
    tpdos: Vec<PdoConfig>,
    tpdo_state: Vec<TxState>,
    heartbeat_at: Option<Instant>,
    consumer: Consumer,
    sync_at: Option<Instant>,
    active: Vec<AppError>,
    history: Vec<u32>,
    emcy_queue: VecDeque<[u8; 8]>,
    emcy_after: Option<Instant>,
    scratch: Vec<AppError>,
    now: Instant,
    /// The COB-IDs of data frames the node acts on, and of TPDOs a remote frame may ask for.
    listen: Vec<u16>,
    listen_rtr: Vec<u16>,
    sync_cob: u16,
    /// Changes whenever `listen` may have changed.
    generation: u64,
}

/// A CiA 301 node; see the [module documentation](self).
pub struct Node<A: Application> {
    sdo: SdoServer,
    core: Core<A>,
}

impl<A: Application> Node<A> {
    /// A node in Initialising at `now` over `dict` (the device's dictionary with its defaults) and
    /// `app`, with no stored parameters. [`start`](Node::start) boots it.
    pub fn new(
        config: NodeConfig,
        mut dict: Dictionary,
        app: A,
        now: Instant,
    ) -> Result<Node<A>, NodeError> {
        if !(1..=127).contains(&config.node_id) {
            return Err(NodeError::NodeId(config.node_id));
        }
        if let Some(ms) = config.heartbeat_ms {
            if let Some(e) = dict.object_mut(0x1017).and_then(|o| o.subs.get_mut(&0)) {
                e.default = Some(od::object::DefaultValue::plain(od::value::Value::Uint(
                    u64::from(ms),
                )));
            }
        }
        dict.reset(config.node_id);
        Ok(Node {
            sdo: SdoServer::new(config.sdo),
            core: Core {
                id: config.node_id,
                state: NmtState::Initialising,
                pristine: dict.clone(),
                dict,
                app,
                stored: None,
                storage_out: VecDeque::new(),
                tx: VecDeque::new(),
                events: VecDeque::new(),
                rpdos: Vec::new(),
                rpdo_pending: Vec::new(),
                tpdos: Vec::new(),
                tpdo_state: Vec::new(),
                heartbeat_at: None,
                consumer: Consumer::default(),
                sync_at: None,
                active: Vec::new(),
                history: Vec::new(),
                emcy_queue: VecDeque::new(),
                emcy_after: None,
                scratch: Vec::new(),
                now,
                listen: Vec::new(),
                listen_rtr: Vec::new(),
                sync_cob: 0x80,
                generation: 0,
            },
        })
    }

    /// The parameter set the edge's storage holds (`None`: none), as written by an earlier
    /// [`StorageRequest::Save`]; it is loaded at every reset, the first at [`start`](Node::start).
    pub fn set_stored(&mut self, set: Option<Vec<u8>>) {
        self.core.stored = set;
    }

    /// Boots the node at `now`: loads the stored parameters, sends the boot-up message and enters
    /// Pre-operational.
    pub fn start(&mut self, now: Instant) {
        self.core.reset(now, true);
    }

    /// The node-ID.
    pub fn node_id(&self) -> u8 {
        self.core.id
    }

    /// The NMT state.
    pub fn state(&self) -> NmtState {
        self.core.state
    }

    /// The dictionary (communication objects and every value written).
    pub fn dict(&self) -> &Dictionary {
        &self.core.dict
    }

    /// The application.
    pub fn app(&self) -> &A {
        &self.core.app
    }

    /// The application, to act on it from outside (simulation inputs).
    pub fn app_mut(&mut self) -> &mut A {
        &mut self.core.app
    }

    /// The errors active now (as last seen by [`handle_timeout`](Node::handle_timeout)).
    pub fn active_errors(&self) -> &[AppError] {
        &self.core.active
    }

    /// The COB-IDs of the frames this node acts on (NMT, SDO requests, SYNC, RPDOs, the monitored
    /// heartbeat) and, in the second list, the TPDOs a remote frame may ask for. A runtime that hosts
    /// many nodes uses this to hand each frame only to the nodes that take it.
    pub fn listens(&self) -> (&[u16], &[u16]) {
        (&self.core.listen, &self.core.listen_rtr)
    }

    /// A number that changes whenever [`listens`](Node::listens) may have changed.
    pub fn listen_generation(&self) -> u64 {
        self.core.generation
    }

    /// Handles a frame received at `now`.
    pub fn handle_frame(&mut self, now: Instant, frame: &crate::CanFrame) {
        self.core.now = now;
        let Some(cob) = frame.cob_id() else {
            return;
        };
        let core = &mut self.core;
        if cob == 0x000 {
            if frame.len() == 2 && !frame.is_rtr() {
                let d = frame.data();
                if d[1] == 0 || d[1] == core.id {
                    core.nmt(now, d[0]);
                }
            }
            return;
        }
        if core.state == NmtState::Initialising {
            return;
        }
        let id = u16::from(core.id);
        if cob == 0x600 + id {
            if frame.len() == 8 && !frame.is_rtr() && core.state != NmtState::Stopped {
                self.sdo.handle_frame(now, &frame.data8(), core);
                self.flush_sdo();
            }
            return;
        }
        if frame.is_rtr() {
            core.rtr(now, cob);
            return;
        }
        if core.consumer.time > Duration::ZERO && cob == 0x700 + u16::from(core.consumer.node) {
            if frame.len() == 1 {
                core.heartbeat_seen(now);
            }
            return;
        }
        if cob == core.sync_cob {
            if frame.len() <= 1 {
                core.sync(now);
            }
            return;
        }
        if core.state == NmtState::Operational {
            core.rpdo(now, cob, frame.data());
        }
    }

    fn flush_sdo(&mut self) {
        let id = u16::from(self.core.id);
        while let Some(f) = self.sdo.poll_transmit() {
            self.core.tx.push_back((0x580 + id, f, 8));
        }
        while let Some(e) = self.sdo.poll_event() {
            self.core.events.push_back(NodeEvent::Sdo(e));
        }
    }

    /// Runs every timer due at `now`: application time, event-driven TPDOs, heartbeat, SYNC producer,
    /// EMCY inhibit, the SDO transfer timeout.
    pub fn handle_timeout(&mut self, now: Instant) {
        self.core.now = now;
        self.sdo.handle_timeout(now);
        self.flush_sdo();
        self.core.poll(now);
        // A transfer may send its next block-upload segments as the client acknowledges them.
        self.flush_sdo();
    }

    /// When [`handle_timeout`](Node::handle_timeout) is next due.
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Instant> {
        let c = &self.core;
        let mut t: Option<Instant> = None;
        let mut take = |d: Option<Instant>| {
            if let Some(d) = d {
                t = Some(t.map_or(d, |t| t.min(d)));
            }
        };
        take(self.sdo.poll_timeout());
        take(c.app.poll_timeout());
        take(c.heartbeat_at);
        take(c.consumer.deadline);
        take(c.sync_at);
        take(c.emcy_after.filter(|_| !c.emcy_queue.is_empty()));
        if c.state == NmtState::Operational {
            for (cfg, st) in c.tpdos.iter().zip(&c.tpdo_state) {
                if cfg.valid() {
                    take(st.event_at);
                    take(st.inhibit_until.filter(|_| st.pending));
                }
            }
        }
        t
    }

    /// The next frame to send.
    #[must_use]
    pub fn poll_transmit(&mut self) -> Option<crate::CanFrame> {
        let (id, data, len) = self.core.tx.pop_front()?;
        crate::CanFrame::new(id, &data[..usize::from(len)])
    }

    /// The next event.
    #[must_use]
    pub fn poll_event(&mut self) -> Option<NodeEvent> {
        self.core.events.pop_front()
    }

    /// The next request to the edge's parameter storage (a set to write for 0x1010, forgetting it
    /// for 0x1011), in the order they were made.
    #[must_use]
    pub fn poll_storage(&mut self) -> Option<StorageRequest> {
        self.core.storage_out.pop_front()
    }
}

impl<A: Application> Core<A> {
    fn u32_at(&self, index: u16, sub: u8) -> Option<u32> {
        let v = &self.dict.entry(index, sub).ok()?.value;
        let mut b = [0u8; 4];
        let n = v.len().min(4);
        b[..n].copy_from_slice(&v[..n]);
        Some(u32::from_le_bytes(b))
    }

    fn set_state(&mut self, now: Instant, state: NmtState) {
        if self.state == state {
            return;
        }
        self.state = state;
        self.events.push_back(NodeEvent::State(state));
        if state == NmtState::Operational {
            for (cfg, st) in self.tpdos.iter().zip(self.tpdo_state.iter_mut()) {
                st.last = None;
                st.sync_count = 0;
                st.pending = matches!(cfg.transmission, 254 | 255);
                st.event_at = (cfg.event_timer > 0)
                    .then(|| now + Duration::from_millis(u64::from(cfg.event_timer)));
            }
            for p in &mut self.rpdo_pending {
                *p = None;
            }
        }
    }

    /// NMT command `cs` for this node.
    fn nmt(&mut self, now: Instant, cs: u8) {
        if self.state == NmtState::Initialising {
            return;
        }
        match cs {
            0x01 => self.set_state(now, NmtState::Operational),
            0x02 => self.set_state(now, NmtState::Stopped),
            0x80 => self.set_state(now, NmtState::PreOperational),
            0x81 => self.reset(now, true),
            0x82 => self.reset(now, false),
            _ => {}
        }
    }

    /// Reset node (`full`) or reset communication, then boot-up and Pre-operational.
    fn reset(&mut self, now: Instant, full: bool) {
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
            if self.app.owns(index) && self.app.write(Address::new(index, sub), &value).is_err() {
                continue;
            }
            if self.dict.store(index, sub, &value).is_ok() {
                loaded += 1;
            }
        }
        if loaded > 0 {
            self.events.push_back(NodeEvent::Loaded(loaded));
        }
        self.active.clear();
        self.history.clear();
        self.emcy_queue.clear();
        self.emcy_after = None;
        self.tx.clear();
        self.reload_pdos();
        self.reload_consumer();
        // Boot-up, then Pre-operational (CiA 301 §7.3.2.2.1).
        self.tx.push_back((0x700 + u16::from(self.id), [0; 8], 1));
        self.set_state(now, NmtState::PreOperational);
        self.heartbeat_at = self.heartbeat_period().map(|p| now + p);
        self.sync_at = self.sync_period().map(|p| now + p);
        self.now = now;
    }

    /// True for the entries "save all parameters" keeps: writable, not mappable into PDOs (process
    /// data), and not the store/restore commands or the error history themselves.
    fn storable(&self, index: u16, sub: u8) -> bool {
        if matches!(index, 0x1003 | 0x1010 | 0x1011) {
            return false;
        }
        self.dict
            .entry(index, sub)
            .is_ok_and(|e| e.access.kind.writable() && e.pdo == PdoMapping::None)
    }

    fn parameter_set(&self) -> Vec<(u16, u8, Vec<u8>)> {
        let mut out = Vec::new();
        for object in self.dict.objects() {
            for (&sub, entry) in &object.subs {
                if self.storable(object.index, sub) {
                    out.push((object.index, sub, entry.value.clone()));
                }
            }
        }
        out
    }

    fn heartbeat_period(&self) -> Option<Duration> {
        let ms = self.u32_at(0x1017, 0).unwrap_or(0);
        (ms > 0).then(|| Duration::from_millis(u64::from(ms)))
    }

    fn sync_period(&self) -> Option<Duration> {
        let cob = self.u32_at(0x1005, 0).unwrap_or(0x80);
        let us = self.u32_at(0x1006, 0).unwrap_or(0);
        (cob & 0x4000_0000 != 0 && us > 0).then(|| Duration::from_micros(u64::from(us)))
    }

    fn reload_consumer(&mut self) {
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

    fn reload_pdos(&mut self) {
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

    fn reload_listen(&mut self) {
        let mut l = vec![0x000, 0x600 + u16::from(self.id)];
        self.sync_cob = (self.u32_at(0x1005, 0).unwrap_or(0x80) & 0x7FF) as u16;
        l.push(self.sync_cob);
        if self.consumer.time > Duration::ZERO {
            l.push(0x700 + u16::from(self.consumer.node));
        }
        l.extend(
            self.rpdos
                .iter()
                .filter(|c| c.valid())
                .map(PdoConfig::cob_id),
        );
        l.sort_unstable();
        l.dedup();
        self.listen = l;
        self.listen_rtr = self
            .tpdos
            .iter()
            .filter(|c| c.valid() && c.cob_raw & COB_NO_RTR == 0)
            .map(PdoConfig::cob_id)
            .collect();
        self.generation += 1;
    }

    fn heartbeat_seen(&mut self, now: Instant) {
        self.consumer.deadline = Some(now + self.consumer.time);
        if self.consumer.lost {
            self.consumer.lost = false;
            self.events
                .push_back(NodeEvent::HeartbeatResumed(self.consumer.node));
            self.clear_error(HEARTBEAT_ERROR);
        }
    }

    fn poll(&mut self, now: Instant) {
        if self.state == NmtState::Initialising {
            return;
        }
        if self.app.poll_timeout().is_some_and(|t| t <= now) {
            self.app.handle_timeout(now);
            self.check_errors();
            if self.state == NmtState::Operational {
                self.event_tpdos(now);
            }
        }
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
        if let Some(d) = self.consumer.deadline.filter(|d| *d <= now) {
            let _ = d;
            self.consumer.deadline = None;
            if !self.consumer.lost {
                self.consumer.lost = true;
                self.events
                    .push_back(NodeEvent::HeartbeatLost(self.consumer.node));
                self.raise_error(AppError {
                    code: HEARTBEAT_ERROR,
                    info: [self.consumer.node, 0, 0, 0, 0],
                });
                if self.state == NmtState::Operational {
                    self.set_state(now, NmtState::PreOperational);
                }
            }
        }
        if let Some(t) = self.sync_at.filter(|t| *t <= now) {
            let p = self.sync_period().unwrap_or(Duration::from_secs(1));
            let next = t + p;
            self.sync_at = Some(if next <= now { now + p } else { next });
            if self.state != NmtState::Stopped {
                let cob = (self.u32_at(0x1005, 0).unwrap_or(0x80) & 0x7FF) as u16;
                self.tx.push_back((cob, [0; 8], 0));
                self.sync(now);
            }
        }
        if self.state == NmtState::Operational {
            self.timed_tpdos(now);
        }
        self.flush_emcy(now);
    }

    /// Compares the application's errors with the active ones and raises / clears EMCYs.
    fn check_errors(&mut self) {
        let mut now_errors = std::mem::take(&mut self.scratch);
        now_errors.clear();
        self.app.errors(&mut now_errors);
        let gone: Vec<AppError> = self
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

    fn raise_error(&mut self, e: AppError) {
        if self.active.contains(&e) {
            return;
        }
        self.active.push(e);
        self.history.insert(0, u32::from(e.code));
        self.history.truncate(
            self.dict
                .object(0x1003)
                .map_or(0, |o| usize::from(o.max_sub())),
        );
        self.sync_error_objects();
        let reg = error_register(&self.active);
        self.queue_emcy(emcy::frame_data(e.code, reg, e.info));
    }

    fn clear_error(&mut self, code: u16) {
        let gone: Vec<AppError> = self
            .active
            .iter()
            .filter(|e| e.code == code)
            .copied()
            .collect();
        for e in gone {
            self.clear_app_error(e);
        }
    }

    fn clear_app_error(&mut self, e: AppError) {
        self.active.retain(|a| *a != e);
        self.sync_error_objects();
        let reg = error_register(&self.active);
        let c = e.code.to_le_bytes();
        // "Error reset": code 0x0000, the remaining register, which module/axis and the cleared code.
        self.queue_emcy(emcy::frame_data(
            NO_ERROR,
            reg,
            [e.info[0], e.info[1], c[0], c[1], 0],
        ));
    }

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

    fn queue_emcy(&mut self, data: [u8; 8]) {
        if self.emcy_queue.len() < 64 {
            self.emcy_queue.push_back(data);
        }
        self.flush_emcy(self.now);
    }

    /// Sends queued EMCYs as the inhibit time (0x1015, 100 µs) allows; in Pre-operational and
    /// Operational only, while the COB-ID is valid.
    fn flush_emcy(&mut self, now: Instant) {
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
    fn event_tpdos(&mut self, now: Instant) {
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
    fn timed_tpdos(&mut self, now: Instant) {
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

    /// A SYNC: synchronous RPDOs take effect, synchronous TPDOs are sent.
    fn sync(&mut self, now: Instant) {
        if self.state != NmtState::Operational {
            return;
        }
        for n in 0..self.rpdos.len() {
            if let Some((data, len)) = self.rpdo_pending[n].take() {
                self.apply_rpdo(n, &data[..len]);
            }
        }
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
                _ => false,
            };
            if due {
                let (data, len) = self.tpdo_data(n);
                self.send_tpdo(now, n, data, len);
            }
        }
    }

    /// A remote frame for a TPDO (COB-ID bit 30 clear): its current data.
    fn rtr(&mut self, now: Instant, cob: u16) {
        if self.state != NmtState::Operational {
            return;
        }
        if let Some(n) = self
            .tpdos
            .iter()
            .position(|c| c.valid() && c.cob_raw & COB_NO_RTR == 0 && c.cob_id() == cob)
        {
            let (data, len) = self.tpdo_data(n);
            self.send_tpdo(now, n, data, len);
        }
    }

    fn rpdo(&mut self, _now: Instant, cob: u16, data: &[u8]) {
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
            self.queue_emcy(emcy::frame_data(
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
            self.apply_rpdo(n, data);
        }
    }

    fn apply_rpdo(&mut self, n: usize, data: &[u8]) {
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
            );
        }
    }

    /// Special rules of the communication objects, checked before a download is stored. `Ok(true)`: the
    /// download is complete without storing the value (commands).
    fn check_download(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<bool, AbortCode> {
        let value = {
            let mut b = [0u8; 4];
            let n = data.len().min(4);
            b[..n].copy_from_slice(&data[..n]);
            u32::from_le_bytes(b)
        };
        match index {
            0x1003 if sub == 0 => {
                if value != 0 {
                    return Err(AbortCode::InvalidValue);
                }
                self.history.clear();
                self.sync_error_objects();
                return Ok(true);
            }
            0x1010 if sub >= 1 => {
                if value != SAVE_SIGNATURE {
                    return Err(AbortCode::CannotStore);
                }
                // Taken at once; the edge writes the set (CiA 301 §7.5.2.13 leaves when to it).
                let set = storage::encode(&self.parameter_set());
                self.stored = Some(set.clone());
                self.storage_out.push_back(StorageRequest::Save(set));
                self.events.push_back(NodeEvent::Saved);
                return Ok(true);
            }
            0x1011 if sub >= 1 => {
                if value != LOAD_SIGNATURE {
                    return Err(AbortCode::CannotStore);
                }
                self.stored = None;
                self.storage_out.push_back(StorageRequest::Clear);
                self.events.push_back(NodeEvent::Restored);
                return Ok(true);
            }
            0x1005 | 0x1014 => {
                let id = (value & 0x7FF) as u16;
                if value & COB_EXTENDED != 0 || (index == 0x1014 && pdo::restricted_id(id)) {
                    return Err(AbortCode::InvalidValue);
                }
            }
            RPDO_COMM..=0x15FF | TPDO_COMM..=0x19FF => {
                let n = usize::from(index & 0x1FF);
                let cfg = if index < TPDO_COMM {
                    self.rpdos.get(n)
                } else {
                    self.tpdos.get(n)
                };
                let valid = cfg.is_some_and(PdoConfig::valid);
                match sub {
                    1 => {
                        let id = (value & 0x7FF) as u16;
                        if value & COB_EXTENDED != 0
                            || value & 0x1FFF_F800 != 0
                            || pdo::restricted_id(id)
                        {
                            return Err(AbortCode::InvalidValue);
                        }
                        // The CAN-ID of a PDO that exists may not change (CiA 301 §7.5.2.35).
                        let old = cfg.map_or(0, PdoConfig::cob_id);
                        if valid && value & COB_INVALID == 0 && id != old {
                            return Err(AbortCode::InvalidValue);
                        }
                    }
                    2 => {
                        let t = value as u8;
                        if (241..=253).contains(&t) {
                            return Err(AbortCode::InvalidValue);
                        }
                    }
                    3 if index >= TPDO_COMM && valid => return Err(AbortCode::InvalidValue),
                    _ => {}
                }
            }
            0x1600..=0x17FF | 0x1A00..=0x1BFF => {
                let comm = index - MAP_OFFSET;
                let (dir, cfg) = if index < 0x1A00 {
                    (Direction::Rx, self.rpdos.get(usize::from(comm - RPDO_COMM)))
                } else {
                    (Direction::Tx, self.tpdos.get(usize::from(comm - TPDO_COMM)))
                };
                if self.state != NmtState::PreOperational {
                    return Err(AbortCode::DeviceState);
                }
                if cfg.is_some_and(PdoConfig::valid) {
                    return Err(AbortCode::ParameterIncompatible);
                }
                if sub == 0 {
                    if value != 0 {
                        pdo::check_count(&self.dict, dir, index, value as u8)?;
                    }
                } else {
                    if self.u32_at(index, 0).unwrap_or(0) != 0 {
                        return Err(AbortCode::ParameterIncompatible);
                    }
                    pdo::check_entry(&self.dict, dir, value)?;
                }
            }
            _ => {}
        }
        Ok(false)
    }

    /// Effects of a stored download on the node's services.
    fn after_download(&mut self, index: u16) {
        let now = self.now;
        match index {
            0x1005 | 0x1006 => {
                self.sync_at = self.sync_period().map(|p| now + p);
                self.reload_listen();
            }
            0x1016 => self.reload_consumer(),
            0x1017 => self.heartbeat_at = self.heartbeat_period().map(|p| now + p),
            0x1400..=0x1BFF => {
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
            _ => {}
        }
    }
}

impl<A: Application> ObjectStore for Core<A> {
    fn upload(&mut self, mux: Address) -> Result<Vec<u8>, AbortCode> {
        hook::upload(&self.dict, &self.app, mux)
    }

    fn download_capacity(&self, mux: Address) -> Result<DownloadCapacity, AbortCode> {
        self.dict.download_capacity(mux)
    }

    fn download(&mut self, mux: Address, data: &[u8]) -> Result<(), AbortCode> {
        let (index, sub) = (mux.index, mux.sub);
        hook::check_download(&self.dict, &self.app, mux, data)?;
        if self.check_download(index, sub, data)? {
            return Ok(());
        }
        hook::store_download(&mut self.dict, &mut self.app, mux, data)?;
        self.after_download(index);
        Ok(())
    }
}
