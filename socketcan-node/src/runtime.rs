//! The edge: runs nodes on a real bus with the real clock.
//!
//! [`run`] drives one or more [`Node`]s sharing one [`CanBus`]: frames from the bus go to every node,
//! frames a node sends go to the bus and to the other nodes of the same process (they are on the same
//! bus), each node's timers run when [`Node::poll_timeout`] says, and the parameter sets a node saves
//! go to its [`Station`]'s storage. It returns when `stop` is set or the bus fails.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::node::storage::{MemoryStorage, ParameterStorage};
use crate::node::{Application, Node, NodeEvent};
use crate::transport::{BusError, BusEvent, CanBus};
use crate::CanFrame;

/// Longest wait for a frame, so that `stop` is seen promptly.
const MAX_WAIT: Duration = Duration::from_millis(50);

/// Counters of a run, for logs and benchmarks.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct RunStats {
    /// Frames received from the bus.
    pub received: u64,
    /// Frames sent to the bus.
    pub sent: u64,
    /// Error frames / controller problems the bus reported.
    pub bus_errors: u64,
}

/// A node with the storage its parameter sets (0x1010, 0x1011) go to.
pub struct Station<A: Application> {
    /// The node.
    pub node: Node<A>,
    /// Where its parameters are kept.
    pub storage: Box<dyn ParameterStorage>,
}

impl<A: Application> Station<A> {
    /// `node` with `storage`; the node gets the set the storage holds (a set that cannot be read is
    /// logged and the node starts with its defaults).
    pub fn new(node: Node<A>, storage: Box<dyn ParameterStorage>) -> Station<A> {
        let id = node.node_id();
        let mut storage = storage;
        let set = storage.load().unwrap_or_else(|e| {
            tracing::warn!(node = id, "cannot read stored parameters: {e}");
            None
        });
        let mut node = node;
        node.set_stored(set);
        Station { node, storage }
    }

    /// `node` with `storage`, or why the storage cannot be read (not a regular file, too large, …).
    pub fn try_new(
        mut node: Node<A>,
        mut storage: Box<dyn ParameterStorage>,
    ) -> Result<Station<A>, std::io::Error> {
        node.set_stored(storage.load()?);
        Ok(Station { node, storage })
    }

    /// `node` with parameters kept in memory only.
    pub fn in_memory(node: Node<A>) -> Station<A> {
        Station::new(node, Box::new(MemoryStorage::default()))
    }

    /// Carries out what the node asked of its storage.
    fn persist(&mut self) {
        while let Some(request) = self.node.poll_storage() {
            if let Err(e) = request.apply(self.storage.as_mut()) {
                tracing::error!(node = self.node.node_id(), "parameter storage failed: {e}");
            }
        }
    }
}

/// Runs `stations` on `bus` until `stop` is set. Every node is started first (boot-up messages).
pub fn run<A: Application>(
    stations: &mut [Station<A>],
    bus: &mut dyn CanBus,
    stop: &AtomicBool,
) -> Result<RunStats, BusError> {
    let mut stats = RunStats::default();
    let now = Instant::now();
    // The nodes' clock for TIME: the wall clock, as milliseconds since 1984-01-01.
    let wall = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_millis() as u64);
    for s in stations.iter_mut() {
        s.node
            .set_clock(now, wall.saturating_sub(crate::node::time::UNIX_TO_1984_MS));
        s.node.start(now);
    }
    let nodes = stations;
    let mut outgoing: Vec<(usize, CanFrame)> = Vec::new();
    let mut interest = Interest::default();
    // Each node's next deadline, worked out again only for the nodes an input reached: a node's
    // state changes only through its inputs, so the others' deadlines stand. With 127 nodes this
    // keeps a frame's cost to the nodes it concerns.
    let mut touched = Touched::all(nodes.len());
    let mut due: Vec<Option<Instant>> = vec![None; nodes.len()];
    flush(
        nodes,
        bus,
        &mut outgoing,
        &mut interest,
        &mut touched,
        &mut stats,
    )?;
    touched.settle(nodes, &mut due);
    while !stop.load(Ordering::Relaxed) {
        let now = Instant::now();
        let next = due.iter().flatten().min();
        let wait = next.map_or(MAX_WAIT, |t| t.saturating_duration_since(now).min(MAX_WAIT));
        match bus.recv(wait)? {
            Some(BusEvent::Frame { frame, .. }) => {
                stats.received += 1;
                let at = Instant::now();
                interest.refresh(nodes);
                for &n in interest.takers(&frame) {
                    nodes[n].node.handle_frame(at, &frame);
                    touched.add(n);
                }
            }
            Some(BusEvent::Error(text)) => {
                stats.bus_errors += 1;
                tracing::warn!(bus = %bus.describe(), "bus error: {text}");
            }
            None => {}
        }
        let now = Instant::now();
        for (k, d) in due.iter().enumerate() {
            if d.is_some_and(|t| t <= now) {
                nodes[k].node.handle_timeout(now);
                touched.add(k);
            }
        }
        flush(
            nodes,
            bus,
            &mut outgoing,
            &mut interest,
            &mut touched,
            &mut stats,
        )?;
        touched.settle(nodes, &mut due);
    }
    Ok(stats)
}

/// The nodes an input reached since their deadlines were last worked out.
struct Touched {
    list: Vec<usize>,
    marked: Vec<bool>,
}

impl Touched {
    /// Every one of `n` nodes.
    fn all(n: usize) -> Touched {
        Touched {
            list: (0..n).collect(),
            marked: vec![true; n],
        }
    }

    fn add(&mut self, k: usize) {
        if !self.marked[k] {
            self.marked[k] = true;
            self.list.push(k);
        }
    }

    /// Works out the deadlines of the nodes touched; none is touched any more.
    fn settle<A: Application>(&mut self, nodes: &[Station<A>], due: &mut [Option<Instant>]) {
        for k in self.list.drain(..) {
            due[k] = nodes[k].node.poll_timeout();
            self.marked[k] = false;
        }
    }
}

/// Which nodes take which COB-IDs, rebuilt when a node's configuration changes.
#[derive(Default)]
struct Interest {
    /// Each node's listen generation the tables were built from.
    generations: Vec<u64>,
    data: Vec<Vec<usize>>,
    rtr: Vec<Vec<usize>>,
    extended: Vec<usize>,
}

impl Interest {
    fn refresh<A: Application>(&mut self, nodes: &[Station<A>]) {
        let same = self.generations.len() == nodes.len()
            && nodes
                .iter()
                .zip(&self.generations)
                .all(|(s, g)| s.node.listen_generation() == *g);
        if same {
            return;
        }
        self.generations = nodes.iter().map(|s| s.node.listen_generation()).collect();
        self.data = vec![Vec::new(); 0x800];
        self.rtr = vec![Vec::new(); 0x800];
        for (k, s) in nodes.iter().enumerate() {
            let (data, rtr) = s.node.listens();
            for &c in data {
                self.data[usize::from(c & 0x7FF)].push(k);
            }
            for &c in rtr {
                self.rtr[usize::from(c & 0x7FF)].push(k);
            }
        }
    }

    fn takers(&self, frame: &CanFrame) -> &[usize] {
        match frame.cob_id() {
            Some(c) if frame.is_rtr() => &self.rtr[usize::from(c)],
            Some(c) => &self.data[usize::from(c)],
            None => &self.extended,
        }
    }
}

/// Sends what the nodes have to send; a frame of one node also reaches the others in this process.
fn flush<A: Application>(
    nodes: &mut [Station<A>],
    bus: &mut dyn CanBus,
    outgoing: &mut Vec<(usize, CanFrame)>,
    interest: &mut Interest,
    touched: &mut Touched,
    stats: &mut RunStats,
) -> Result<(), BusError> {
    // The nodes with outputs to take: those an input reached (a node's outputs come only from its
    // inputs), then those the frames of the last pass reached.
    let mut poll = touched.list.clone();
    loop {
        outgoing.clear();
        for &n in &poll {
            let s = &mut nodes[n];
            while let Some(e) = s.node.poll_event() {
                log_event(s.node.node_id(), &e);
            }
            s.persist();
            while let Some(f) = s.node.poll_transmit() {
                outgoing.push((n, f));
            }
        }
        if outgoing.is_empty() {
            return Ok(());
        }
        for (_, f) in outgoing.iter() {
            bus.send(f)?;
            stats.sent += 1;
        }
        if nodes.len() == 1 {
            return Ok(());
        }
        let at = Instant::now();
        interest.refresh(nodes);
        poll.clear();
        for (sender, f) in outgoing.iter() {
            for &n in interest.takers(f) {
                if n != *sender {
                    nodes[n].node.handle_frame(at, f);
                    touched.add(n);
                    poll.push(n);
                }
            }
        }
        poll.sort_unstable();
        poll.dedup();
    }
}

fn log_event(node: u8, e: &NodeEvent) {
    match e {
        NodeEvent::State(s) => tracing::info!(node, "NMT state {s:?}"),
        NodeEvent::Reset(full) => {
            tracing::info!(
                node,
                "{}",
                if *full {
                    "reset node"
                } else {
                    "reset communication"
                }
            )
        }
        NodeEvent::Saved => tracing::info!(node, "parameters saved"),
        NodeEvent::Restored => {
            tracing::info!(
                node,
                "stored parameters forgotten; defaults at the next reset"
            )
        }
        NodeEvent::Loaded(n) => tracing::info!(node, "{n} stored parameters loaded"),
        NodeEvent::Storage(e) => tracing::warn!(node, "stored parameters ignored: {e}"),
        NodeEvent::HeartbeatLost(p) => tracing::warn!(node, "heartbeat of node {p} missed"),
        NodeEvent::HeartbeatResumed(p) => tracing::info!(node, "heartbeat of node {p} back"),
        NodeEvent::Sdo(ev) => tracing::debug!(node, "SDO {ev:?}"),
        NodeEvent::NodeId(id) => tracing::info!(node, "LSS: node-ID {id} in use"),
        NodeEvent::Time(t) => tracing::debug!(node, "TIME: day {} ms {}", t.days, t.ms),
        NodeEvent::BitTiming(index) => {
            tracing::info!(
                node,
                "LSS: bit timing {index} activated (a virtual bus keeps its rate)"
            )
        }
    }
}
