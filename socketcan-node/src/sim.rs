//! A node on a simulated clock, for tests and benchmarks: frames go in, time advances exactly to each
//! timer the node asks for, and every frame the node sends is recorded with its time.

use std::time::{Duration, Instant};

use crate::node::storage::{MemoryStorage, ParameterStorage};
use crate::node::{Device, Node, NodeConfig, NodeError};
use crate::x67::{self, BusController, X67Error};
use crate::CanFrame;

/// Why a simulated node could not be built.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// The bus controller.
    #[error(transparent)]
    X67(#[from] X67Error),
    /// The node.
    #[error(transparent)]
    Node(#[from] NodeError),
}

/// A node on a simulated clock (by default the X67 bus controller).
pub struct SimNode<A: Device = BusController> {
    /// The node.
    pub node: Node<A>,
    /// Simulated now.
    pub now: Instant,
    /// Time zero.
    pub t0: Instant,
    /// Frames the node sent, with their time since `t0`.
    pub sent: Vec<(Duration, CanFrame)>,
    /// Where the node's parameter sets go (written as the node asks, at once).
    pub storage: Box<dyn ParameterStorage>,
}

impl SimNode<BusController> {
    /// Node `node_id` with `modules` modules and in-memory storage, booted at time zero.
    pub fn new(node_id: u8, modules: usize) -> Result<SimNode, SimError> {
        Self::with(
            NodeConfig::new(node_id),
            modules,
            Box::new(MemoryStorage::default()),
        )
    }

    /// A node with the given configuration and storage, booted at time zero.
    pub fn with(
        config: NodeConfig,
        modules: usize,
        storage: Box<dyn ParameterStorage>,
    ) -> Result<SimNode, SimError> {
        Self::build(config, modules, x67::DEFAULT_X2X_CYCLE, storage)
    }

    /// A node with the given configuration, X2X Link cycle and storage, booted at time zero.
    pub fn build(
        config: NodeConfig,
        modules: usize,
        x2x: Duration,
        storage: Box<dyn ParameterStorage>,
    ) -> Result<SimNode, SimError> {
        let t0 = Instant::now();
        let dict = x67::dictionary(modules)?;
        let app = BusController::new(&dict, modules, x2x, t0)?;
        let node = Node::new(config, dict, app, t0)?;
        Ok(SimNode::boot(node, t0, storage))
    }
}

impl<A: Device + Clone> SimNode<A> {
    /// A second node in this one's state, at the same simulated time, with its parameters in memory:
    /// a copy of the set this one's storage holds (a fuzz target or a test builds one node and forks
    /// it for each case).
    pub fn fork(&mut self) -> SimNode<A> {
        SimNode {
            node: self.node.clone(),
            now: self.now,
            t0: self.t0,
            sent: self.sent.clone(),
            storage: Box::new(MemoryStorage {
                data: self.storage.load().ok().flatten(),
                lss: self.storage.load_lss().ok().flatten(),
            }),
        }
    }
}

impl<A: Device> SimNode<A> {
    /// `node`, built at `t0`, booted at once with the set `storage` holds.
    pub fn boot(mut node: Node<A>, t0: Instant, storage: Box<dyn ParameterStorage>) -> SimNode<A> {
        let mut storage = storage;
        // A set that cannot be read is as none (the runtime logs it).
        node.set_stored(storage.load().ok().flatten());
        node.start(t0);
        let mut sim = SimNode {
            node,
            now: t0,
            t0,
            sent: Vec::new(),
            storage,
        };
        sim.collect();
        sim
    }

    /// Simulated time since zero.
    pub fn elapsed(&self) -> Duration {
        self.now - self.t0
    }

    fn collect(&mut self) {
        // The storage first: the answers that wait for it go out with the rest.
        while let Some(request) = self.node.poll_storage() {
            let result = request.apply(self.storage.as_mut());
            self.node.storage_done(result.is_ok());
        }
        while let Some(f) = self.node.poll_transmit() {
            self.sent.push((self.now - self.t0, f));
        }
    }

    /// Delivers `frame` now; returns the frames the node sent in answer.
    pub fn send(&mut self, frame: CanFrame) -> Vec<CanFrame> {
        let before = self.sent.len();
        self.node.handle_frame(self.now, &frame);
        self.node.handle_timeout(self.now);
        self.collect();
        self.sent[before..].iter().map(|(_, f)| *f).collect()
    }

    /// Runs the node's timers for `d`; returns the frames sent meanwhile.
    pub fn advance(&mut self, d: Duration) -> Vec<CanFrame> {
        let before = self.sent.len();
        let end = self.now + d;
        while let Some(t) = self.node.poll_timeout().filter(|t| *t <= end) {
            self.now = self.now.max(t);
            self.node.handle_timeout(self.now);
            self.collect();
        }
        self.now = end;
        self.node.handle_timeout(end);
        self.collect();
        self.sent[before..].iter().map(|(_, f)| *f).collect()
    }

    /// A stall of `d`: the node is polled once, `d` from now, as a thread that was not scheduled for
    /// that long polls it; returns the frames sent then.
    pub fn stall(&mut self, d: Duration) -> Vec<CanFrame> {
        let before = self.sent.len();
        self.now += d;
        self.node.handle_timeout(self.now);
        self.collect();
        self.sent[before..].iter().map(|(_, f)| *f).collect()
    }

    /// Runs for `ms` milliseconds.
    pub fn advance_ms(&mut self, ms: u64) -> Vec<CanFrame> {
        self.advance(Duration::from_millis(ms))
    }

    /// Frames sent so far whose COB-ID is `cob`, with their times.
    pub fn sent_on(&self, cob: u16) -> Vec<(Duration, CanFrame)> {
        self.sent
            .iter()
            .filter(|(_, f)| f.cob_id() == Some(cob))
            .copied()
            .collect()
    }

    /// An expedited SDO upload of `index:sub` answered at once: the value bytes or the abort code.
    pub fn sdo_read(&mut self, index: u16, sub: u8) -> Result<Vec<u8>, u32> {
        let id = u16::from(self.node.node_id());
        let i = index.to_le_bytes();
        let req = CanFrame::new(0x600 + id, &[0x40, i[0], i[1], sub, 0, 0, 0, 0]).expect("8 bytes");
        let replies = self.send(req);
        let r = replies
            .iter()
            .find(|f| f.cob_id() == Some(0x580 + id))
            .ok_or(0u32)?
            .data8();
        match r[0] {
            0x80 => Err(u32::from_le_bytes([r[4], r[5], r[6], r[7]])),
            c if c & 0xE3 == 0x43 => {
                let n = 4 - usize::from((c >> 2) & 3);
                Ok(r[4..4 + n].to_vec())
            }
            0x41 => Err(0xFFFF_FFFF),
            _ => Err(0),
        }
    }

    /// An expedited SDO download; `Ok` or the abort code.
    pub fn sdo_write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), u32> {
        assert!((1..=4).contains(&data.len()));
        let id = u16::from(self.node.node_id());
        let i = index.to_le_bytes();
        let cs = 0x23 | ((4 - data.len() as u8) << 2);
        let mut d = [cs, i[0], i[1], sub, 0, 0, 0, 0];
        d[4..4 + data.len()].copy_from_slice(data);
        let replies = self.send(CanFrame::new(0x600 + id, &d).expect("8 bytes"));
        let r = replies
            .iter()
            .find(|f| f.cob_id() == Some(0x580 + id))
            .ok_or(0u32)?
            .data8();
        match r[0] {
            0x60 => Ok(()),
            0x80 => Err(u32::from_le_bytes([r[4], r[5], r[6], r[7]])),
            _ => Err(0),
        }
    }

    /// Sends an NMT command (`cs`, node or 0 for all).
    pub fn nmt(&mut self, cs: u8, node: u8) -> Vec<CanFrame> {
        self.send(CanFrame::new(0, &[cs, node]).expect("2 bytes"))
    }
}
