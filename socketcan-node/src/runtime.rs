//! The edge: runs nodes on a real bus with the real clock.
//!
//! [`run`] drives one or more [`Node`]s sharing one [`CanBus`]: frames from the bus go to every node,
//! frames a node sends go to the bus and to the other nodes of the same process (they are on the same
//! bus), each node's timers run when [`Node::poll_timeout`] says, and the parameter sets a node saves
//! go to its [`Station`]'s storage. It returns when `stop` is set or the bus fails.
//!
//! The storage is written on a thread of its own (`Writer`), in the order the nodes asked, so that
//! a slow disk (a write and its fsync may take a good part of a second) delays only the answer that
//! confirms the save, never a heartbeat, a PDO or another node's answer.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::node::storage::{MemoryStorage, ParameterStorage, StorageRequest};
use crate::node::{Device, Node, NodeEvent};
use crate::transport::{BusError, BusEvent, CanBus};
use crate::CanFrame;

/// Longest wait for a frame, so that `stop` is seen promptly.
const MAX_WAIT: Duration = Duration::from_millis(50);
/// Longest wait for a frame while the storage is being written, so that the answer a finished write
/// releases goes out promptly.
const STORAGE_WAIT: Duration = Duration::from_millis(1);

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
pub struct Station<A: Device> {
    /// The node.
    pub node: Node<A>,
    /// Where its parameters are kept.
    pub storage: Box<dyn ParameterStorage>,
}

impl<A: Device> Station<A> {
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
}

/// The thread that writes the stations' storage, one request after the other in the order they came.
struct Writer {
    requests: Option<mpsc::Sender<(usize, StorageRequest)>>,
    done: mpsc::Receiver<(usize, std::io::Result<()>)>,
    thread: Option<JoinHandle<Vec<Box<dyn ParameterStorage>>>>,
    /// Requests handed over whose outcome has not come back.
    waiting: usize,
}

impl Writer {
    /// Takes the stations' storage to a new thread (each station keeps an empty one meanwhile).
    fn start<A: Device>(stations: &mut [Station<A>]) -> Writer {
        let mut storages: Vec<Box<dyn ParameterStorage>> = stations
            .iter_mut()
            .map(|s| std::mem::replace(&mut s.storage, Box::new(MemoryStorage::default())))
            .collect();
        let (requests, inbox) = mpsc::channel::<(usize, StorageRequest)>();
        let (outbox, done) = mpsc::channel();
        let thread = std::thread::Builder::new()
            .name("storage".into())
            .spawn(move || {
                for (k, request) in inbox {
                    let result = request.apply(storages[k].as_mut());
                    if outbox.send((k, result)).is_err() {
                        break;
                    }
                }
                storages
            })
            .expect("a thread for the parameter storage");
        Writer {
            requests: Some(requests),
            done,
            thread: Some(thread),
            waiting: 0,
        }
    }

    /// Hands over what station `k`'s node asked of its storage.
    fn take<A: Device>(&mut self, k: usize, station: &mut Station<A>) {
        while let Some(request) = station.node.poll_storage() {
            if let Some(requests) = &self.requests {
                if requests.send((k, request)).is_ok() {
                    self.waiting += 1;
                    continue;
                }
            }
            // The thread is gone: the request fails, and the node answers so.
            station.node.storage_done(false);
        }
    }

    /// Reports the writes finished since the last call to their nodes.
    fn collect<A: Device>(&mut self, stations: &mut [Station<A>], touched: &mut Touched) {
        while let Ok((k, result)) = self.done.try_recv() {
            self.waiting -= 1;
            let station = &mut stations[k];
            if let Err(e) = &result {
                tracing::error!(
                    node = station.node.node_id(),
                    "parameter storage failed: {e}"
                );
            }
            station.node.storage_done(result.is_ok());
            touched.add(k);
        }
    }

    /// Waits for the writes still queued, then gives each station its storage back.
    fn finish<A: Device>(mut self, stations: &mut [Station<A>]) {
        drop(self.requests.take());
        let Some(storages) = self.thread.take().and_then(|t| t.join().ok()) else {
            tracing::error!("the parameter storage thread failed");
            return;
        };
        for (s, storage) in stations.iter_mut().zip(storages) {
            s.storage = storage;
        }
    }
}

/// Runs `stations` on `bus` until `stop` is set. Every node is started first (boot-up messages).
pub fn run<A: Device>(
    stations: &mut [Station<A>],
    bus: &mut dyn CanBus,
    stop: &AtomicBool,
) -> Result<RunStats, BusError> {
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
    let mut writer = Writer::start(stations);
    let result = serve(stations, bus, stop, &mut writer);
    writer.finish(stations);
    result
}

/// The loop of [`run`], with the storage on `writer`'s thread.
fn serve<A: Device>(
    nodes: &mut [Station<A>],
    bus: &mut dyn CanBus,
    stop: &AtomicBool,
    writer: &mut Writer,
) -> Result<RunStats, BusError> {
    let mut stats = RunStats::default();
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
        writer,
        &mut outgoing,
        &mut interest,
        &mut touched,
        &mut stats,
    )?;
    touched.settle(nodes, &mut due);
    while !stop.load(Ordering::Relaxed) {
        let now = Instant::now();
        let next = due.iter().flatten().min();
        let longest = if writer.waiting > 0 {
            STORAGE_WAIT
        } else {
            MAX_WAIT
        };
        let wait = next.map_or(longest, |t| t.saturating_duration_since(now).min(longest));
        match bus.recv(wait)? {
            Some(BusEvent::Frame {
                frame, received, ..
            }) => {
                stats.received += 1;
                // The instant the link took the frame, not when this thread woke up to it; never
                // before the start of this wait, so the nodes' time runs forwards (a frame queued
                // while the nodes were being served is taken as arriving then).
                let at = received.max(now);
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
            Some(_) | None => {}
        }
        writer.collect(nodes, &mut touched);
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
            writer,
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
    fn settle<A: Device>(&mut self, nodes: &[Station<A>], due: &mut [Option<Instant>]) {
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
    fn refresh<A: Device>(&mut self, nodes: &[Station<A>]) {
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
fn flush<A: Device>(
    nodes: &mut [Station<A>],
    bus: &mut dyn CanBus,
    writer: &mut Writer,
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
            writer.take(n, s);
            while let Some(f) = s.node.poll_transmit() {
                outgoing.push((n, f));
            }
        }
        // The frames first, then the log: a frame's time is part of the protocol (the first
        // heartbeat is due one period after the boot-up message the node timed it from), a log
        // line's is not, and writing one may take long.
        for (n, f) in outgoing.iter() {
            bus.send(f)?;
            stats.sent += 1;
            let node = &mut nodes[*n].node;
            if f.cob_id() == Some(0x700 + u16::from(node.node_id())) && f.data() == [0] {
                node.boot_up_sent(Instant::now());
            }
        }
        for &n in &poll {
            let s = &mut nodes[n];
            while let Some(e) = s.node.poll_event() {
                log_event(s.node.node_id(), &e);
            }
        }
        if outgoing.is_empty() || nodes.len() == 1 {
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
