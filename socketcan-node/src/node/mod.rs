//! A CiA 301 slave node as a sans-IO state machine: NMT, heartbeat producer and consumer, SYNC consumer
//! and optional producer, PDOs from the dictionary, EMCY, store/restore parameters and the SDO server.
//!
//! The node takes frames with the time they arrived ([`Node::handle_frame`]), is driven by
//! [`Node::handle_timeout`] at [`Node::poll_timeout`], and hands back the frames to send
//! ([`Node::poll_transmit`]). No sockets, threads, files or clocks inside: the runtime at the edge owns
//! those. "Save" (0x1010) and "restore" (0x1011) become requests the edge carries out on its storage
//! ([`Node::poll_storage`]); the edge hands the node the set it loaded ([`Node::set_stored`]) and
//! reports each request's outcome ([`Node::storage_done`]). Until it has, the answer that asked for
//! the request (the SDO download response to 0x1010/0x1011, the LSS store configuration response) and
//! the SDO and LSS answers after it wait, so that an answer says the set is kept; a failed request is
//! answered with SDO abort 0x08000020 or LSS error 2 (storage media access error) instead. The other
//! services (heartbeat, PDOs, EMCY, …) go on meanwhile: the edge may write on a thread of its own.
//!
//! # Methods and polling order
//!
//! 1. [`Node::new`] at `now`, [`Node::set_stored`] with what the edge's storage holds, then
//!    [`Node::start`] (boot-up message, Pre-operational).
//! 2. For every frame received: [`Node::handle_frame`] with the time it arrived.
//! 3. When [`Node::poll_timeout`] has passed: [`Node::handle_timeout`].
//! 4. After each of those calls, drain [`Node::poll_transmit`] (frames in the order to send),
//!    [`Node::poll_storage`] (parameter sets to write or forget; report each with
//!    [`Node::storage_done`] when carried out) and [`Node::poll_event`].
//! 5. Wait for a frame or for the next [`Node::poll_timeout`], whichever comes first.
//!
//! The device behind the node is a [`Device`] (`od::hook::Device`, the one device lifecycle the EtherCAT
//! unit runs too): it owns the manufacturer objects it declares, takes what the master writes to them (by
//! SDO or RPDO, each write with its instant, the device run up to it first), answers reads (SDO uploads
//! and TPDOs), advances its own time and reports its errors, which the node turns into EMCY messages.
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
//! - Event-driven TPDOs are checked for changed data at every application tick, the ticks the device
//!   runs up to a write or a SYNC included, and at every SYNC, and sent once on entering
//!   Operational; the event timer sends them when nothing changed for its time.
//! - Heartbeat consumer: monitoring starts with the first heartbeat of the producer; a missed heartbeat
//!   raises EMCY 0x8130 (error register bit 4) and takes an Operational node to Pre-operational (the
//!   CiA 301 default error behaviour); the next heartbeat clears the error.
//!
//! Inside, each service has its module: `nmt` (NMT states, resets, heartbeat producer and consumer),
//! `emcy` (error codes, error register 0x1001 and history 0x1003, EMCY COB-ID and inhibit time),
//! [`pdo`] (PDO configuration and the checks of the mapping procedure), `pdo_runtime` (RPDOs applied,
//! TPDOs triggered, inhibit and event timers), `comm` (the rules of writes to the communication
//! objects and their effects) and [`storage`] (the stored parameter set). This module keeps the node's
//! API, the dispatch of received frames and the order of the timers.

mod comm;
mod emcy;
pub mod lss;
mod nmt;
pub mod pdo;
mod pdo_runtime;
pub mod storage;
pub mod time;

use std::collections::VecDeque;
use std::time::{Duration, Instant};

pub use emcy::{
    error_register, DeviceError, EmcyCode, HEARTBEAT_ERROR, NO_ERROR, PDO_LENGTH_ERROR,
};
use lss::{LssAction, LssSlave, LSS_REQUEST, LSS_RESPONSE, UNCONFIGURED};
use nmt::Consumer;
use od::dict::Dictionary;
use od::sdo::server::{SdoServer, ServerConfig, ServerEvent};
use pdo::{PdoConfig, COB_NO_RTR};
use pdo_runtime::TxState;
use storage::StorageRequest;
use time::{Clock, TimeOfDay};

pub use od::sdo::{LOAD_SIGNATURE, SAVE_SIGNATURE};

/// The device behind the node: the project's one device lifecycle ([`od::hook::Device`]), which the
/// EtherCAT unit runs too. The node runs it up to the instant of every frame, SYNC and timeout
/// before it delivers a write to it. Its [`Device::sync`] comes at a SYNC in Operational, after the
/// synchronous RPDOs received before it were applied and before the synchronous TPDOs are sampled
/// (CiA 301 §7.2.2.2).
pub use od::hook::Device;

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

/// LSS (CiA 305) of a node: served when [`NodeConfig::lss`] is set.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LssConfig {
    /// The bit-timing table index the node starts with (CiA 301 table; 4 = 125 kbit/s).
    pub bit_timing: u8,
    /// The edge keeps a stored LSS configuration ([`StorageRequest::SaveLss`]); without it store
    /// configuration answers "not supported".
    pub can_store: bool,
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
    /// LSS slave services (CiA 305); with them the node-ID may be 0xFF, unconfigured: the node then
    /// waits in Initialising, silent but for LSS, until a master gives it a node-ID.
    pub lss: Option<LssConfig>,
    /// How often a TIME producer (0x1012 bit 30) sends the time of day.
    pub time_period: Duration,
}

impl NodeConfig {
    /// Node `node_id` with the defaults.
    pub fn new(node_id: u8) -> NodeConfig {
        NodeConfig {
            node_id,
            sdo: ServerConfig::default(),
            heartbeat_ms: None,
            lss: None,
            time_period: Duration::from_secs(1),
        }
    }
}

/// Why a node could not be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum NodeError {
    /// The node-ID is outside 1–127 (or 0xFF, unconfigured, with LSS).
    #[error("node-ID {0} is outside 1 to 127")]
    NodeId(u8),
}

/// What happened, for logs and tests.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
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
    /// LSS gave the node a node-ID it now uses (after NMT reset communication, or at once when it
    /// had none).
    NodeId(u8),
    /// LSS asked to switch the bit timing (table index) after a delay; the virtual bus keeps its rate.
    BitTiming(u8),
    /// A TIME frame set the node's clock.
    Time(TimeOfDay),
}

/// The node minus its SDO server, so the server can borrow it as its object store.
#[derive(Clone)]
struct Core<A: Device> {
    id: u8,
    state: NmtState,
    dict: Dictionary,
    /// The dictionary as built (defaults, `--heartbeat-ms` applied) for resets.
    pristine: Dictionary,
    app: A,
    /// The parameter set as the edge's storage holds it (loaded at each reset).
    stored: Option<Vec<u8>>,
    storage_out: VecDeque<StorageRequest>,
    /// The requests made whose outcome the edge has not reported yet, oldest first, each with the
    /// stored set as it was before it (put back when it fails).
    storage_waiting: VecDeque<Waiting>,
    /// SDO and LSS answers held while a storage request waits for its outcome.
    held: VecDeque<(u16, [u8; 8], u8)>,
    tx: VecDeque<(u16, [u8; 8], u8)>,
    events: VecDeque<NodeEvent>,
    // The PDO engine (`pdo_runtime`).
    rpdos: Vec<PdoConfig>,
    rpdo_pending: Vec<Option<([u8; 8], usize)>>,
    tpdos: Vec<PdoConfig>,
    tpdo_state: Vec<TxState>,
    // Heartbeat producer and consumer (`nmt`), SYNC producer.
    heartbeat_at: Option<Instant>,
    consumer: Consumer,
    sync_at: Option<Instant>,
    /// The `now` of the last boot whose boot-up message the edge has not reported sent.
    booted_at: Option<Instant>,
    // The EMCY producer (`emcy`).
    active: Vec<DeviceError>,
    history: Vec<u32>,
    emcy_queue: VecDeque<[u8; 8]>,
    emcy_after: Option<Instant>,
    scratch: Vec<DeviceError>,
    now: Instant,
    /// The device ran outside [`Core::poll`] (a due timeout before a write, [`Core::device_up_to`],
    /// or its ticks up to a SYNC and the SYNC itself): the next [`Core::poll`] checks its errors and
    /// event-driven TPDOs, as if it had run it, and [`Node::poll_timeout`] asks for that poll at once.
    device_ran: bool,
    /// The COB-IDs of data frames the node acts on, and of TPDOs a remote frame may ask for.
    listen: Vec<u16>,
    listen_rtr: Vec<u16>,
    sync_cob: u16,
    /// Changes whenever `listen` may have changed.
    generation: u64,
    /// The node answers LSS requests.
    serves_lss: bool,
    // TIME (`time`): the clock, the producer's next send and period.
    clock: Option<Clock>,
    time_at: Option<Instant>,
    time_period: Duration,
}

/// A CiA 301 node; see the [module documentation](self).
#[derive(Clone)]
pub struct Node<A: Device> {
    sdo: SdoServer,
    lss: Option<LssSlave>,
    core: Core<A>,
}

impl<A: Device> Node<A> {
    /// A node in Initialising at `now` over `dict` (the device's dictionary with its defaults) and
    /// `app`, with no stored parameters. [`start`](Node::start) boots it.
    pub fn new(
        config: NodeConfig,
        mut dict: Dictionary,
        app: A,
        now: Instant,
    ) -> Result<Node<A>, NodeError> {
        let unconfigured = config.lss.is_some() && config.node_id == UNCONFIGURED;
        if !(1..=127).contains(&config.node_id) && !unconfigured {
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
        let lss = config.lss.map(|l| {
            let identity = |sub| {
                dict.entry(0x1018, sub)
                    .ok()
                    .and_then(|e| e.value.get(..4))
                    .map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            };
            let address = [identity(1), identity(2), identity(3), identity(4)];
            LssSlave::new(address, config.node_id, l.bit_timing, l.can_store)
        });
        Ok(Node {
            sdo: SdoServer::new(config.sdo),
            lss,
            core: Core {
                id: config.node_id,
                state: NmtState::Initialising,
                pristine: dict.clone(),
                dict,
                app,
                stored: None,
                storage_out: VecDeque::new(),
                storage_waiting: VecDeque::new(),
                held: VecDeque::new(),
                tx: VecDeque::new(),
                events: VecDeque::new(),
                rpdos: Vec::new(),
                rpdo_pending: Vec::new(),
                tpdos: Vec::new(),
                tpdo_state: Vec::new(),
                heartbeat_at: None,
                consumer: Consumer::default(),
                sync_at: None,
                booted_at: None,
                active: Vec::new(),
                history: Vec::new(),
                emcy_queue: VecDeque::new(),
                emcy_after: None,
                scratch: Vec::new(),
                now,
                device_ran: false,
                listen: Vec::new(),
                listen_rtr: Vec::new(),
                sync_cob: 0x80,
                generation: 0,
                serves_lss: config.lss.is_some(),
                clock: None,
                time_at: None,
                time_period: config.time_period,
            },
        })
    }

    /// The parameter set the edge's storage holds (`None`: none), as written by an earlier
    /// [`StorageRequest::Save`]; it is loaded at every reset, the first at [`start`](Node::start).
    pub fn set_stored(&mut self, set: Option<Vec<u8>>) {
        self.core.stored = set;
    }

    /// Boots the node at `now`: loads the stored parameters, sends the boot-up message and enters
    /// Pre-operational. A node without a node-ID (0xFF, with LSS) stays silent in Initialising until
    /// LSS gives it one.
    pub fn start(&mut self, now: Instant) {
        self.core.now = now;
        if self.core.id == UNCONFIGURED {
            self.core.reload_listen();
            return;
        }
        self.core.reset(now, true);
    }

    /// The node-ID (0xFF: none yet, with LSS).
    pub fn node_id(&self) -> u8 {
        self.core.id
    }

    /// The LSS slave, when the node serves LSS.
    pub fn lss(&self) -> Option<&LssSlave> {
        self.lss.as_ref()
    }

    /// Sets the node's clock: at `now` it is `ms_since_1984` milliseconds after 1984-01-01 00:00 (the
    /// edge's wall clock; [`time::UNIX_TO_1984_MS`] converts from Unix time). A TIME producer sends
    /// from now on.
    pub fn set_clock(&mut self, now: Instant, ms_since_1984: u64) {
        self.core.clock = Some(Clock {
            at: now,
            ms: ms_since_1984,
        });
        self.core.reload_time(now);
    }

    /// The node's time of day at `now`, once its clock was set (by the edge or a TIME frame).
    pub fn time_of_day(&self, now: Instant) -> Option<TimeOfDay> {
        self.core.clock.map(|c| c.time_at(now))
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
    pub fn active_errors(&self) -> &[DeviceError] {
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
        if cob == LSS_REQUEST {
            if !frame.is_rtr() {
                self.lss_request(now, frame.data());
            }
            return;
        }
        if cob == 0x000 {
            if frame.len() == 2 && !frame.is_rtr() {
                let d = frame.data();
                let core = &self.core;
                if (d[1] == 0 || d[1] == core.id) && core.state != NmtState::Initialising {
                    if matches!(d[0], 0x81 | 0x82) && !self.take_lss_node_id() {
                        return;
                    }
                    // A reset starts the SDO server again too (CiA 301 §7.3.2.2.1): a transfer in
                    // progress ends without an abort, its timer with it.
                    if self.core.nmt(now, d[0]) {
                        self.sdo = SdoServer::new(*self.sdo.config());
                    }
                }
            }
            return;
        }
        let core = &mut self.core;
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
        if core.time_consumed() == Some(cob) {
            core.time_received(now, frame.data());
            return;
        }
        if core.state == NmtState::Operational {
            core.rpdo(now, cob, frame.data());
        }
    }

    /// At an NMT reset: the node-ID LSS configured becomes the node's (CiA 305 §8.3.1). False when
    /// that leaves the node without one (0xFF): it then waits in Initialising for LSS, silent.
    fn take_lss_node_id(&mut self) -> bool {
        let Some(lss) = self.lss.as_mut() else {
            return true;
        };
        lss.activate();
        let id = lss.active_node_id();
        if id == self.core.id {
            return true;
        }
        self.set_node_id(id);
        if id == UNCONFIGURED {
            self.core.state = NmtState::Initialising;
            self.core
                .events
                .push_back(NodeEvent::State(NmtState::Initialising));
            self.core.tx.clear();
            self.core.heartbeat_at = None;
            self.core.sync_at = None;
            self.sdo = SdoServer::new(*self.sdo.config());
            return false;
        }
        true
    }

    /// The node's node-ID becomes `id`: the defaults that follow the node-ID follow it.
    fn set_node_id(&mut self, id: u8) {
        let core = &mut self.core;
        core.id = id;
        core.pristine.reset(id);
        core.events.push_back(NodeEvent::NodeId(id));
        core.reload_listen();
    }

    /// An LSS request: the answer, and a node-ID or a store to carry out.
    fn lss_request(&mut self, now: Instant, data: &[u8]) {
        let Some(lss) = self.lss.as_mut() else {
            return;
        };
        let (answer, action) = lss.handle(data);
        // The store goes to the edge first, so that its answer waits for the outcome.
        if let LssAction::Store {
            node_id,
            bit_timing,
        } = action
        {
            self.core.request_storage(StorageRequest::SaveLss {
                node_id,
                bit_timing,
            });
        }
        if let Some(a) = answer {
            self.core.answer(LSS_RESPONSE, a);
        }
        match action {
            LssAction::None => {}
            LssAction::ApplyNodeId(id) => {
                // The node had no node-ID: it takes this one with a reset communication now, boot-up
                // included (CiA 305 §8.3.1).
                lss.activate();
                self.set_node_id(id);
                self.core.reset(now, false);
                self.sdo = SdoServer::new(*self.sdo.config());
            }
            LssAction::Store { .. } => {}
            LssAction::ActivateBitTiming { bit_timing, .. } => {
                self.core.events.push_back(NodeEvent::BitTiming(bit_timing));
            }
        }
    }

    fn flush_sdo(&mut self) {
        let id = u16::from(self.core.id);
        while let Some(f) = self.sdo.poll_transmit() {
            self.core.answer(0x580 + id, f);
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
        // A node waiting in Initialising for LSS to give it a node-ID runs no timer (see `poll`):
        // it asks for none, so that an edge sleeps until the next frame.
        if c.state == NmtState::Initialising {
            return None;
        }
        let mut t: Option<Instant> = None;
        let mut take = |d: Option<Instant>| {
            if let Some(d) = d {
                t = Some(t.map_or(d, |t| t.min(d)));
            }
        };
        take(self.sdo.poll_timeout());
        // What the device did outside a poll is checked at the next one, now: the device itself
        // may ask for no timeout any more (it went idle in those ticks).
        take(c.device_ran.then_some(c.now));
        take(c.app.poll_timeout());
        take(c.heartbeat_at);
        take(c.consumer.deadline);
        take(c.sync_at);
        take(c.emcy_timeout());
        take(c.tpdo_timeout());
        take(c.time_at);
        t
    }

    /// The edge sent the node's boot-up message at `at` (an edge whose sends take no time, as a
    /// simulated one, need not call this). The timers the boot started run from `at`: a boot-up
    /// message that left after the reset's own work (loading the dictionary and the stored set takes
    /// a while on a slow machine) is still followed by the first heartbeat one producer time later.
    /// Only the first call after a boot counts.
    pub fn boot_up_sent(&mut self, at: Instant) {
        self.core.boot_up_sent(at);
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

    /// The edge carried out the oldest storage request it was handed: `ok` when the set is kept (or
    /// forgotten) as asked. The answers held for it go out ([`poll_transmit`](Node::poll_transmit));
    /// when it failed, its answer says so (SDO abort 0x08000020 "data cannot be stored", LSS store
    /// configuration error 2 "storage media access error", CiA 305 §8.3.6) and the node's idea of
    /// the stored set is as before the request. An outcome without a request waiting is ignored.
    pub fn storage_done(&mut self, ok: bool) {
        let core = &mut self.core;
        let Some(waiting) = core.storage_waiting.pop_front() else {
            return;
        };
        if !ok {
            if let Some(before) = waiting.stored_before {
                core.stored = before;
            }
            let sdo = 0x580 + u16::from(core.id);
            let failed = core.held.iter_mut().find(|(cob, d, _)| match waiting.kind {
                WaitingKind::Parameters => {
                    *cob == sdo && d[0] == 0x60 && d[2] == 0x10 && matches!(d[1], 0x10 | 0x11)
                }
                WaitingKind::Lss => *cob == LSS_RESPONSE && d[0] == 0x17,
            });
            if let Some((_, d, _)) = failed {
                match waiting.kind {
                    WaitingKind::Parameters => {
                        d[0] = 0x80;
                        d[4..].copy_from_slice(
                            &u32::from(od::abort::AbortCode::CannotStore).to_le_bytes(),
                        );
                    }
                    WaitingKind::Lss => d[1] = 2,
                }
            }
        }
        if core.storage_waiting.is_empty() {
            core.tx.extend(core.held.drain(..));
        }
    }
}

/// Answers held at most while storage requests wait; the oldest goes when more come (a client keeps
/// one SDO request open at a time, so only a misbehaving one gets there).
const HELD_CAPACITY: usize = 16;

/// A storage request whose outcome the edge has not reported yet.
#[derive(Debug, Clone)]
struct Waiting {
    kind: WaitingKind,
    /// The stored set before a save or a restore (`None` for an LSS store).
    stored_before: Option<Option<Vec<u8>>>,
}

/// Which answer a storage request holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum WaitingKind {
    /// 0x1010 or 0x1011 by SDO.
    Parameters,
    /// LSS store configuration.
    Lss,
}

impl<A: Device> Core<A> {
    /// Hands `request` to the edge; the answers from now on wait for its outcome.
    fn request_storage(&mut self, request: StorageRequest) {
        let (kind, stored_before) = match request {
            StorageRequest::SaveLss { .. } => (WaitingKind::Lss, None),
            _ => (WaitingKind::Parameters, Some(self.stored.clone())),
        };
        self.storage_waiting.push_back(Waiting {
            kind,
            stored_before,
        });
        self.storage_out.push_back(request);
    }

    /// Sends an SDO or LSS answer, or holds it while a storage request waits for its outcome.
    fn answer(&mut self, cob: u16, data: [u8; 8]) {
        if self.storage_waiting.is_empty() {
            self.tx.push_back((cob, data, 8));
        } else {
            if self.held.len() == HELD_CAPACITY {
                self.held.pop_front();
            }
            self.held.push_back((cob, data, 8));
        }
    }

    fn u32_at(&self, index: u16, sub: u8) -> Option<u32> {
        let v = &self.dict.entry(index, sub).ok()?.value;
        let mut b = [0u8; 4];
        let n = v.len().min(4);
        b[..n].copy_from_slice(&v[..n]);
        Some(u32::from_le_bytes(b))
    }

    /// The SYNC producer's period: 0x1006 while 0x1005 bit 30 says this node produces SYNC.
    fn sync_period(&self) -> Option<Duration> {
        let cob = self.u32_at(0x1005, 0).unwrap_or(0x80);
        let us = self.u32_at(0x1006, 0).unwrap_or(0);
        (cob & 0x4000_0000 != 0 && us > 0).then(|| Duration::from_micros(u64::from(us)))
    }

    /// The COB-IDs the node acts on, after a change of the SYNC COB-ID, the consumer or the PDOs.
    fn reload_listen(&mut self) {
        self.generation += 1;
        if self.id == UNCONFIGURED {
            self.listen = vec![LSS_REQUEST];
            self.listen_rtr.clear();
            return;
        }
        let mut l = vec![0x000, 0x600 + u16::from(self.id)];
        if self.serves_lss {
            l.push(LSS_REQUEST);
        }
        self.sync_cob = (self.u32_at(0x1005, 0).unwrap_or(0x80) & 0x7FF) as u16;
        l.push(self.sync_cob);
        if let Some(cob) = self.time_consumed() {
            l.push(cob);
        }
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
    }

    /// Runs the device up to `now` before a write made at `now` reaches it (an SDO download, an
    /// RPDO, a SYNC's synchronous RPDOs): the timeout it asked for before `now`, if any (what falls
    /// due at `now` itself runs after the write, as the node's own timers do). Its errors and
    /// event-driven TPDOs are checked at the next [`Core::poll`], where they were.
    fn device_up_to(&mut self, now: Instant) {
        if od::hook::run_before(&mut self.app, now) {
            self.device_ran = true;
        }
    }

    /// Every timer due at `now`, in this order: the application (then its errors and event-driven
    /// TPDOs), heartbeat producer and consumer, SYNC producer, TPDO inhibit and event timers, EMCY
    /// inhibit.
    fn poll(&mut self, now: Instant) {
        if self.state == NmtState::Initialising {
            return;
        }
        let due = self.app.poll_timeout().is_some_and(|t| t <= now);
        if due {
            self.app.handle_timeout(now);
        }
        if std::mem::take(&mut self.device_ran) || due {
            self.check_errors();
            if self.state == NmtState::Operational {
                self.event_tpdos(now);
            }
        }
        self.heartbeat_timers(now);
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
        self.time_timer(now);
        self.flush_emcy(now);
    }
}
