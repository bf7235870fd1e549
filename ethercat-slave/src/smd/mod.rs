//! The SMD23K-B / SMD24K as an EtherCAT slave: an [`Esc`] with the SII image and the AL checks of the
//! fixture's ESI, the CoE SDO server (`od::coe::server`) on the unit's dictionary behind its mailbox,
//! and the indexer model bound to its dictionary ([`binding::SmdUnit`]) behind its process data.
//!
//! - [`SmdChain::handle_frame`] passes a frame through the chain at `now`; a mailbox the master
//!   completed in SM0 is served at once and the answer put into SM1 (answers wait while SM1 is still
//!   full).
//! - [`SmdChain::handle_timeout`] runs, when [`SmdChain::poll_timeout`] has passed, the SDO transfer
//!   timers and the units' process-data cycle over the time since the last one: the SyncManager
//!   watchdog (its expiry in Op: Safe-Op with AL status code 0x001B, and the model's Input_Error,
//!   SMD-R1-035), SYNC0 events to the model, in Op the output bytes of SM2 to the model, in Safe-Op
//!   and Op the model's input bytes into SM3, both laid out as the description's PDO assignment
//!   (0x1C12, 0x1C13) and mapping objects (0x1600, 0x1A00) say (20 bytes each).
//! - The model sees the EtherCAT state (PreOp_SafeOp, commands only in Op); in Safe-Op and Op the
//!   output entries mapped to the RxPDO are the process data's (an SDO download is refused
//!   0x06010006).
//! - SYNC0 is accepted with a cycle time of 2 ms to 50 ms (SMD-T3-003); outside it Pre-Op → Safe-Op
//!   is refused with AL status code 0x0036.
//!
//! # Methods and polling order
//!
//! One clock, the host's: [`SmdChain::new`] at `now` (the chain's time zero: Distributed Clocks count
//! from it), then for every frame that arrives [`SmdChain::handle_frame`] with its time, and
//! [`SmdChain::handle_timeout`] whenever [`SmdChain::poll_timeout`] has passed (the next process-data
//! cycle, or an SDO transfer timer before it). The answer to a frame is the frame itself, changed in
//! place; nothing else leaves the chain. A host that stalled calls [`SmdChain::handle_timeout`] once
//! with the present time: one cycle runs over the whole gap and the next is due a cycle later.

pub mod binding;

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use binding::{Device, SmdUnit, FIXTURE_ESI, FIXTURE_NAME};
use ds402::smd::config::EncoderKind;
use ds402::smd::indexer::NetworkState;
use od::coe::server::CoeServer;
use od::hook::ProcessImage;
use od::sdo::frame::Address;
use od::sdo::server::ServerConfig;

use crate::esc::al::{AlConfig, AlState, AlStatusCode};
use crate::esc::{Chain, Esc};
use crate::frame::FrameError;

/// SYNC0 cycle times the unit accepts, in ns (SMD-T3-003: 2 ms to 50 ms).
pub const SYNC0_CYCLE_RANGE: (u32, u32) = (2_000_000, 50_000_000);

/// Why a slave could not be built.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SmdSlaveError {
    /// The fixture's ESI does not read.
    #[error("the SMD description: {0}")]
    Description(#[from] od::ParseError),
    /// The fixture's ESI has no EtherCAT part.
    #[error("the SMD description: no EtherCAT part")]
    NoEthercat,
    /// The unit's dictionary does not bind to the model.
    #[error("the SMD description: {0}")]
    Binding(#[from] binding::BindingError),
    /// The PDO assignment or mapping does not give a process image.
    #[error("the SMD description: {0}")]
    Image(#[from] od::hook::ImageError),
    /// The SII image.
    #[error(transparent)]
    Sii(#[from] od::sii::SiiError),
}

/// The fixture's description of `device`.
pub fn description(device: Device) -> Result<od::DeviceDescription, SmdSlaveError> {
    let select = od::esi::Select::Name(device.order_code().to_string());
    Ok(od::esi::read(
        FIXTURE_ESI.as_bytes(),
        FIXTURE_NAME,
        Some(&select),
    )?)
}

/// One unit behind its ESC: the model and its CoE server.
#[derive(Clone)]
struct Unit {
    model: SmdUnit,
    coe: CoeServer,
    /// Answers waiting for SM1 to be read.
    pending: VecDeque<Vec<u8>>,
    /// The AL state the model and the server were last told.
    state: AlState,
}

/// A chain of virtual SMD units. A clone is a second chain in the same state (a fuzz target or a
/// test builds one chain from the description and clones it for each case).
#[derive(Clone)]
pub struct SmdChain {
    /// The ESCs in frame order.
    pub chain: Chain,
    units: Vec<Unit>,
    /// SM2 / SM3 start addresses from the ESI.
    outputs_at: u16,
    inputs_at: u16,
    /// The layouts of SM2 and SM3, from the PDO assignment (0x1C12, 0x1C13) and mapping objects of the
    /// description.
    output_image: ProcessImage,
    input_image: ProcessImage,
    /// One unit's process data on its way between the ESC and the model, kept for every cycle.
    image: Vec<u8>,
    /// The units' process-data cycle.
    cycle: Duration,
    /// The latest time the chain was given.
    now: Instant,
    /// When the last process-data cycle ran and when the next is due.
    last_cycle: Instant,
    next_cycle: Instant,
}

impl SmdChain {
    /// `n` units of `device`, serial numbers 1…n, all in Init (SMD-T2-007), powered on at `now`, running
    /// their process-data cycle every `cycle` (at least 1 µs).
    pub fn new(
        device: Device,
        n: usize,
        cycle: Duration,
        now: Instant,
    ) -> Result<SmdChain, SmdSlaveError> {
        let cycle = cycle.max(Duration::from_micros(1));
        let desc = description(device)?;
        let ec = desc.ethercat.as_ref().ok_or(SmdSlaveError::NoEthercat)?;
        let at = |kind: &str| {
            ec.sync_managers
                .iter()
                .find(|s| s.kind == kind)
                .map_or(0, |s| s.start_address)
        };
        let (outputs_at, inputs_at) = (at("Outputs"), at("Inputs"));
        let mailbox_in = ec
            .sync_managers
            .iter()
            .find(|s| s.kind == "MBoxIn")
            .and_then(|s| s.default_size)
            .unwrap_or(128);
        let mut chain = Chain::new(0);
        chain.start(now);
        let mut units = Vec::new();
        for k in 0..n {
            let mut esc = Esc::new();
            esc.sii = od::sii::write(&desc, k as u32 + 1)?;
            esc.load_sii_configuration();
            esc.al = AlConfig::from_description(&desc);
            esc.al.sync0_cycle = Some(SYNC0_CYCLE_RANGE);
            chain.push(esc);
            let mut model = SmdUnit::new(device, EncoderKind::Incremental)?;
            model.set_network_state(NetworkState::Init);
            model.set_serial_number(k as u32 + 1);
            model.indexer_mut().start(now);
            units.push(Unit {
                model,
                coe: CoeServer::new(ServerConfig::default(), usize::from(mailbox_in)),
                pending: VecDeque::new(),
                state: AlState::Init,
            });
        }
        let images = units.first().map(|u| {
            let d = u.model.dict();
            (
                ProcessImage::from_assignment(d, 0x1C12),
                ProcessImage::from_assignment(d, 0x1C13),
            )
        });
        let (output_image, input_image) = match images {
            Some((Ok(o), Ok(i))) => (o, i),
            Some((Err(e), _) | (_, Err(e))) => return Err(e.into()),
            None => Default::default(),
        };
        Ok(SmdChain {
            chain,
            units,
            outputs_at,
            inputs_at,
            image: vec![0; output_image.len().max(input_image.len())],
            output_image,
            input_image,
            cycle,
            now,
            last_cycle: now,
            next_cycle: now + cycle,
        })
    }

    /// Units in the chain.
    pub fn len(&self) -> usize {
        self.units.len()
    }

    /// True for a chain of none.
    pub fn is_empty(&self) -> bool {
        self.units.is_empty()
    }

    /// The model of unit `k` (0 = first in the chain).
    pub fn unit(&self, k: usize) -> Option<&SmdUnit> {
        self.units.get(k).map(|u| &u.model)
    }

    /// The model of unit `k`, to change what it senses (inputs, shaft, temperature).
    pub fn unit_mut(&mut self, k: usize) -> Option<&mut SmdUnit> {
        self.units.get_mut(k).map(|u| &mut u.model)
    }

    /// Processes a frame that arrived at `now` as it passes the chain, then serves the mailboxes it
    /// completed.
    pub fn handle_frame(&mut self, now: Instant, frame: &mut [u8]) -> Result<(), FrameError> {
        self.set_now(now);
        self.chain.handle_frame(self.now, frame)?;
        self.serve_mailboxes();
        Ok(())
    }

    /// Runs what is due at `now`: the SDO transfer timers and, once [`SmdChain::poll_timeout`]'s
    /// cycle time has come, one process-data cycle of every unit over the time since the last one.
    pub fn handle_timeout(&mut self, now: Instant) {
        self.set_now(now);
        for unit in &mut self.units {
            unit.coe.handle_timeout(self.now);
        }
        if self.now >= self.next_cycle {
            self.step();
            self.next_cycle += self.cycle;
            if self.next_cycle <= self.now {
                // Far behind (the host stalled): go on from now.
                self.next_cycle = self.now + self.cycle;
            }
        }
        self.serve_mailboxes();
    }

    /// When [`SmdChain::handle_timeout`] is next due: the next process-data cycle, or an SDO transfer
    /// timer that runs out before it.
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Instant> {
        let sdo = self.units.iter().filter_map(|u| u.coe.poll_timeout()).min();
        Some(sdo.map_or(self.next_cycle, |t| t.min(self.next_cycle)))
    }

    fn set_now(&mut self, now: Instant) {
        self.now = self.now.max(now);
        self.chain.set_now(self.now);
    }

    fn serve_mailboxes(&mut self) {
        let now = self.now;
        for (esc, unit) in self.chain.slaves.iter_mut().zip(self.units.iter_mut()) {
            if esc.al_state().0 == AlState::Init {
                // Told at once: the mailbox restarts before the master can use it again.
                unit.sync_state(AlState::Init);
            }
            unit.send_pending(esc);
            // One request at a time (ETG.1000.6 §5.5): the next is taken only once the answers
            // before it are in SM1 or read, so a master that never reads SM1 finds SM0 full.
            if unit.pending.is_empty() {
                if let Some(mailbox) = esc.take_mailbox() {
                    unit.sync_state(esc.al_state().0);
                    unit.model.handle_mailbox(&mut unit.coe, now, &mailbox);
                    unit.pending
                        .extend(std::iter::from_fn(|| unit.coe.poll_transmit()));
                    unit.send_pending(esc);
                }
            }
        }
    }

    /// The chain's clock in nanoseconds since its time zero.
    pub fn time_ns(&self) -> u64 {
        self.chain.time_ns()
    }

    /// The units' process-data cycle.
    pub fn cycle_time(&self) -> Duration {
        self.cycle
    }

    /// One process-data cycle of every unit over the time since the last one.
    fn step(&mut self) {
        let now = self.now;
        let dt = now.saturating_duration_since(self.last_cycle);
        self.last_cycle = now;
        for (esc, unit) in self.chain.slaves.iter_mut().zip(self.units.iter_mut()) {
            let expired = esc.check_watchdog();
            let (al, _) = esc.al_state();
            if expired && al == AlState::Op {
                // SMD-R1-035: the watchdog drops the unit to Safe-Op with the error indication.
                unit.drop_to_safe_op(esc);
            }
            let (al, _) = esc.al_state();
            unit.sync_state(al);
            let sync0 = esc.sync0_passed().map(|at| {
                let ago = Duration::from_nanos(esc.system_time().saturating_sub(at));
                ago.min(dt)
            });
            if al == AlState::Op {
                let outputs = &mut self.image[..self.output_image.len()];
                esc.load_into(self.outputs_at, outputs);
                unit.model.receive_process_data(&self.output_image, outputs);
            }
            match sync0 {
                // The model runs up to the SYNC0 event, takes it, and runs on from it.
                Some(ago) => {
                    if dt > ago {
                        unit.model.exchange(now - ago);
                    }
                    unit.model.indexer_mut().sync0_event();
                    unit.model.exchange(now);
                }
                None => {
                    unit.model.exchange(now);
                }
            }
            if matches!(al, AlState::Op | AlState::SafeOp) {
                let inputs = &mut self.image[..self.input_image.len()];
                unit.model.send_process_data(&self.input_image, inputs);
                esc.store(self.inputs_at, inputs);
            }
        }
    }

    /// The link to the master was lost (SMD-R1-036): a unit in Op drops to Safe-Op with the error
    /// indication, as on a watchdog expiry, and stays there until the master requests Op again.
    pub fn link_lost(&mut self, now: Instant) {
        self.set_now(now);
        for (esc, unit) in self.chain.slaves.iter_mut().zip(self.units.iter_mut()) {
            if esc.al_state().0 == AlState::Op {
                unit.drop_to_safe_op(esc);
                unit.sync_state(AlState::SafeOp);
            }
        }
    }
}

impl Unit {
    /// Puts the waiting answers into SM1 while it takes them.
    fn send_pending(&mut self, esc: &mut Esc) {
        while let Some(next) = self.pending.front() {
            if !esc.put_mailbox(next) {
                break;
            }
            self.pending.pop_front();
        }
    }

    /// The master stopped reaching the unit in Op (watchdog, link): Safe-Op with the error indication
    /// and code 0x001B, and the model's Input_Error.
    fn drop_to_safe_op(&mut self, esc: &mut Esc) {
        esc.al_fault(AlState::SafeOp, AlStatusCode::SyncManagerWatchdog);
        self.model.indexer_mut().sm_watchdog_expired();
    }

    /// Tells the model and the CoE server the AL state.
    fn sync_state(&mut self, al: AlState) {
        if al == self.state {
            return;
        }
        self.state = al;
        if al == AlState::Init {
            // The mailbox restarts in Init (as the ESC empties its SyncManagers): no transfer, no
            // answer waiting, and the mailbox counters from the start. A master that starts again
            // counts from 1 again, and a request with the counter of the request before Init would
            // otherwise be taken for a repeat and answered with that old response.
            self.coe = CoeServer::new(*self.coe.config(), self.coe.mailbox_size());
            self.pending.clear();
        }
        let network = match al {
            AlState::Op => NetworkState::Op,
            AlState::SafeOp => NetworkState::SafeOp,
            AlState::PreOp => NetworkState::PreOp,
            _ => NetworkState::Init,
        };
        self.model.set_network_state(network);
        let mapped: Vec<Address> = if matches!(al, AlState::Op | AlState::SafeOp) {
            (1..=8).map(|sub| Address { index: 0x7000, sub }).collect()
        } else {
            Vec::new()
        };
        self.coe.set_rxpdo_mapped(mapped);
    }
}
