//! The CiA 302-2 network manager, sans-IO: boots every slave of a [`Plan`] as the boot-slave
//! process says, starts them, and supervises them after.
//!
//! The runtime loop, as every core of the workspace: [`Manager::start`]; send what
//! [`Manager::poll_transmit`] gives; hand every frame received to [`Manager::handle_frame`] and,
//! when [`Manager::poll_timeout`] is reached, call [`Manager::handle_timeout`];
//! [`Manager::poll_event`] gives what happened ([`BootEvent`]) and [`Manager::nodes`] where each
//! node is.
//!
//! What it does, from the master's objects:
//! - At [`Manager::start`] every slave is reset with NMT reset communication: all with one command,
//!   or one by one when a slave is kept alive (0x1F81 bit 4), which is not reset. A slave's boot
//!   starts at its boot-up message, or when [`ManagerConfig::boot_up_wait`] is over without one.
//!   A kept-alive slave whose heartbeat says Operational is not booted again (status L).
//! - The boot-slave process of a slave that 0x1F81 bit 2 says to boot: read 0x1000 and compare it
//!   with 0x1F84 (no answer: B, different: C), then each of 0x1018:01–04 whose expected value
//!   0x1F85–0x1F88 is not 0 (D, M, N, O), then 0x1F56:01 against 0x1F55 when 0x1F81 bit 5 says so
//!   (H: this manager downloads no program); write its configuration (the concise DCF of 0x1F22, in
//!   its order, which puts each PDO's COB-ID invalid before its mapping and valid after, as CiA 301
//!   requires; a refused write: J); when the master consumes its heartbeat (0x1016), wait for one
//!   (K); start it with NMT start remote node, unless 0x1F80 bit 3 says the master starts no slave
//!   or bit 1 says all start at once. A slave 0x1F81 bit 2 does not boot is only watched.
//! - When every mandatory slave (0x1F81 bit 3) is up and every other one's boot ended: NMT start all nodes when 0x1F80 bit 1 says
//!   so, and [`BootEvent::NetworkUp`]; the master's heartbeat (0x1017) says Operational from then
//!   on unless 0x1F80 bit 2 keeps it pre-operational. The boot time 0x1F89 passed before that:
//!   [`BootEvent::BootTimeout`] with the slaves missing.
//! - Supervision: a heartbeat not received within the consumer time is an error control event (E);
//!   a lost mandatory slave resets every node (0x1F80 bit 4) or stops every node (bit 6) when
//!   0x1F80 says so. A lost slave is booted again at its next heartbeat or boot-up message, and a
//!   boot-up message at any time starts the node's boot again.
//!
//! Choices where CiA 302-2 leaves room: a slave that did not answer (B) is tried again after
//! [`ManagerConfig::retry`] (1 s), mandatory or not, for as long as the manager runs; any other
//! failure is tried again at the slave's next boot-up message, since asking again cannot change a
//! wrong device or a refused value. Node guarding (0x1F81 bits 8–31 without a heartbeat) is not
//! run: such a slave is booted without error control.

mod dcfs;
mod node;
mod plan;
mod status;

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use can_link::CanFrame;

pub use dcfs::SlaveDcf;
pub use node::NodeReport;
pub use plan::{ConfigEntry, Expect, LoadFile, Plan, SlavePlan};
pub use status::{BootError, BootEvent, ErrorStatus, NodeState};

use node::{Node, Out};

/// How long a slave that did not answer waits before it is tried again.
pub const RETRY: Duration = Duration::from_secs(1);

/// The manager's timing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ManagerConfig {
    /// How long each SDO request waits for its answer. Default 1 s.
    pub sdo_timeout: Duration,
    /// How long a slave is waited for after the reset before its boot starts without a boot-up
    /// message. Default 1 s.
    pub boot_up_wait: Duration,
    /// How long a slave that did not answer waits before it is tried again. Default [`RETRY`].
    pub retry: Duration,
}

impl Default for ManagerConfig {
    fn default() -> ManagerConfig {
        ManagerConfig {
            sdo_timeout: Duration::from_secs(1),
            boot_up_wait: Duration::from_secs(1),
            retry: RETRY,
        }
    }
}

/// The network manager.
pub struct Manager {
    plan: Plan,
    config: ManagerConfig,
    nodes: Vec<Node>,
    frames: VecDeque<CanFrame>,
    events: VecDeque<BootEvent>,
    boot_deadline: Option<Instant>,
    timeout_reported: bool,
    network_up: bool,
    next_heartbeat: Option<Instant>,
}

impl Manager {
    /// A manager of `plan`, not started.
    pub fn new(plan: Plan, config: ManagerConfig) -> Manager {
        let nodes = plan
            .slaves
            .iter()
            .map(|s| Node::new(s.clone(), config.sdo_timeout))
            .collect();
        Manager {
            plan,
            config,
            nodes,
            frames: VecDeque::new(),
            events: VecDeque::new(),
            boot_deadline: None,
            timeout_reported: false,
            network_up: false,
            next_heartbeat: None,
        }
    }

    /// The plan.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// Every node, in node-ID order.
    pub fn nodes(&self) -> impl Iterator<Item = &NodeReport> {
        self.nodes.iter().map(|n| &n.report)
    }

    /// True once every mandatory slave booted.
    pub fn network_up(&self) -> bool {
        self.network_up
    }

    /// True when no node waits for anything: each is up, watched, lost, or failed with nothing
    /// that will try it again but its own boot-up message.
    pub fn settled(&self) -> bool {
        self.nodes.iter().all(Node::settled)
    }

    /// The mandatory slaves not up.
    pub fn missing(&self) -> Vec<u8> {
        self.nodes
            .iter()
            .filter(|n| n.plan.mandatory() && n.plan.boots() && !n.is_up())
            .map(|n| n.plan.node_id)
            .collect()
    }

    fn out(&mut self) -> (Out<'_>, &mut Vec<Node>) {
        let start_now = self.plan.starts_slaves() && (!self.plan.start_all() || self.network_up);
        (
            Out {
                frames: &mut self.frames,
                events: &mut self.events,
                start_now,
                retry: self.config.retry,
                boot_up_wait: self.config.boot_up_wait,
            },
            &mut self.nodes,
        )
    }

    /// Starts the boot: resets the slaves and starts the master's heartbeat.
    pub fn start(&mut self, now: Instant) {
        self.network_up = false;
        self.timeout_reported = false;
        self.boot_deadline = (self.plan.boot_time_ms != 0)
            .then(|| now + Duration::from_millis(u64::from(self.plan.boot_time_ms)));
        if self.plan.heartbeat_ms != 0 {
            self.next_heartbeat = Some(now);
        }
        let keep_any = self.nodes.iter().any(|n| n.plan.keep_alive());
        let (mut out, nodes) = self.out();
        if !keep_any {
            out.nmt(0x82, 0);
        }
        for n in nodes.iter_mut() {
            if keep_any && !n.plan.keep_alive() {
                out.nmt(0x82, n.plan.node_id);
            }
            n.await_boot_up(now, &mut out);
        }
        self.after(now);
        self.handle_timeout(now);
    }

    /// A frame from the bus, received at `now`: SDO answers, heartbeats, boot-up and emergency
    /// messages of the slaves; any other is ignored.
    pub fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        let Some(cob) = frame.cob_id() else { return };
        if frame.is_rtr() {
            return;
        }
        let (function, id) = (cob & 0x780, (cob & 0x7F) as u8);
        let data = frame.data();
        match function {
            0x080 if id != 0 && data.len() == 8 => {
                let mut rest = [0u8; 5];
                rest.copy_from_slice(&data[3..8]);
                self.events.push_back(BootEvent::Emergency {
                    node: id,
                    code: u16::from_le_bytes([data[0], data[1]]),
                    register: data[2],
                    data: rest,
                });
            }
            0x580 | 0x700 => {
                let (mut out, nodes) = self.out();
                let Some(n) = nodes.iter_mut().find(|n| n.plan.node_id == id) else {
                    return;
                };
                if function == 0x580 && data.len() == 8 {
                    n.handle_sdo(now, frame.data8(), &mut out);
                } else if function == 0x700 && data.len() == 1 {
                    n.handle_heartbeat(now, data[0], &mut out);
                }
                self.after(now);
            }
            _ => {}
        }
    }

    /// The time passed to `now`.
    pub fn handle_timeout(&mut self, now: Instant) {
        if let Some(t) = self.next_heartbeat.filter(|&t| t <= now) {
            let state = if self.network_up && self.plan.master_operational() {
                0x05
            } else {
                0x7F
            };
            let id = u16::from(self.plan.master_id);
            if let Some(f) = CanFrame::new(0x700 + id, &[state]) {
                self.frames.push_back(f);
            }
            let period = Duration::from_millis(u64::from(self.plan.heartbeat_ms));
            // The next beat keeps the period; after a long pause it is a period from now.
            self.next_heartbeat = Some(if t + period > now {
                t + period
            } else {
                now + period
            });
        }
        let mut lost = Vec::new();
        {
            let (mut out, nodes) = self.out();
            for n in nodes.iter_mut() {
                if n.poll_timeout().is_some_and(|t| t <= now) && n.handle_timeout(now, &mut out) {
                    lost.push(n.plan.mandatory());
                }
            }
        }
        if lost.contains(&true) {
            self.mandatory_lost(now);
        }
        self.after(now);
    }

    /// A mandatory slave was lost: every node reset (and booted again) or stopped when 0x1F80
    /// says so.
    fn mandatory_lost(&mut self, now: Instant) {
        if self.plan.reset_all_on_loss() {
            self.start(now);
        } else if self.plan.stop_all_on_loss() {
            let (mut out, _) = self.out();
            out.nmt(0x02, 0);
        }
    }

    /// What follows from the nodes' states: the network up, or its boot time passed.
    fn after(&mut self, now: Instant) {
        let missing = self.missing();
        // The first boot of every slave is over (optional ones too, so that starting all at once
        // does not start a slave being configured), and every mandatory one is up.
        if !self.network_up && missing.is_empty() && !self.nodes.iter().any(Node::busy) {
            self.network_up = true;
            if self.plan.starts_slaves() && self.plan.start_all() {
                let (mut out, _) = self.out();
                out.nmt(0x01, 0);
            }
            self.events.push_back(BootEvent::NetworkUp);
        }
        if !self.network_up
            && !self.timeout_reported
            && self.boot_deadline.is_some_and(|t| t <= now)
        {
            self.timeout_reported = true;
            self.events.push_back(BootEvent::BootTimeout { missing });
        }
    }

    /// When to call [`Manager::handle_timeout`] next.
    pub fn poll_timeout(&self) -> Option<Instant> {
        let deadline = self
            .boot_deadline
            .filter(|_| !self.network_up && !self.timeout_reported);
        self.nodes
            .iter()
            .filter_map(Node::poll_timeout)
            .chain(self.next_heartbeat)
            .chain(deadline)
            .min()
    }

    /// The next frame to send.
    pub fn poll_transmit(&mut self) -> Option<CanFrame> {
        self.frames.pop_front()
    }

    /// The next event.
    pub fn poll_event(&mut self) -> Option<BootEvent> {
        self.events.pop_front()
    }
}
