//! A chain of emulated slaves, each an ESC ([`Esc`]) with a device behind it: a [`Model`] (a device
//! model behind its dictionary, through the one device hook `od::hook`), the CoE server
//! (`od::coe::server`) on that dictionary behind its mailbox, and its process data. What every kind
//! of unit shares is written here once: the SMD ([`crate::smd`]) and any ESI's device
//! ([`crate::generic`]) are both a [`UnitChain`] of their model.
//!
//! - [`UnitChain::handle_frame`] passes a frame through the chain at `now`, then tells each model
//!   the AL state its ESC is in, and serves the mailboxes the frame completed: a request the master
//!   completed in SM0 goes to the unit's CoE server at once and its answer into SM1 (answers wait
//!   while SM1 is still full; one request at a time, ETG.1000.6 §5.5). After a mailbox the unit's
//!   PDO configuration is read again: its process-image lengths are what Pre-Op → Safe-Op checks
//!   the SyncManagers against (ETG.1000.6 §6.4.1.4), and an invalid one refuses that transition
//!   with the model's AL status code.
//! - [`UnitChain::handle_timeout`] runs, when [`UnitChain::poll_timeout`] has passed, the SDO
//!   transfer timers and every unit's process-data cycle over the time since the last one: the
//!   SyncManager watchdog (its expiry in Op: Safe-Op with AL status code 0x001B, ETG.1000.4 §6.3),
//!   in Op a new output image of SM2 unpacked into the model's entries, the synchronisation event
//!   (the last SYNC0 since the last cycle at its own instant, ETG.1000.4 §9.3; without SYNC0, and
//!   with SYNC0 activated but before its first pulse at the start time the master set, the SM2
//!   event of a new output image), the model run up to now, and in Safe-Op and Op the input entries
//!   packed into SM3. Both images are laid out as the unit's PDO assignment (0x1C12, 0x1C13) and
//!   mapping say at the moment the unit entered Safe-Op (ETG.1000.6 §5.6.7.4: the assignment is
//!   changed in Pre-Op and takes effect at Safe-Op).
//! - Beside CoE the mailbox carries FoE where the unit has an FoE server ([`Unit::with_foe`];
//!   without one, FoE gets the mailbox error 0x0002, unsupported protocol), with the same mailbox
//!   counter and repeat; in Bootstrap only FoE (CoE gets 0x0002). The files a unit takes whole are
//!   handed to the edge ([`UnitChain::poll_written`]).
//! - In Init the unit's mailbox starts again: no transfer, no answer waiting, the mailbox counter
//!   from the start (an FoE transfer ends; the files stay). In Safe-Op and Op the entries mapped to the RxPDOs are the process data's: an
//!   SDO download to one is refused with 0x06010006.
//!
//! # Methods and polling order
//!
//! One clock, the host's: [`UnitChain::from_units`] at `now` (the chain's time zero: Distributed Clocks
//! count from it), then for every frame that arrives [`UnitChain::handle_frame`] with its time, and
//! [`UnitChain::handle_timeout`] whenever [`UnitChain::poll_timeout`] has passed (the next
//! process-data cycle, or an SDO transfer timer before it). The answer to a frame is the frame
//! itself, changed in place; nothing else leaves the chain. A host that stalled calls
//! [`UnitChain::handle_timeout`] once with the present time: one cycle runs over the whole gap and
//! the next is due a cycle later.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use std::sync::Arc;

use od::coe::mailbox::{MailboxHeader, MailboxType};
use od::coe::server::{CoeServer, MailboxService, ServiceAnswer};
use od::foe::{printable, FOE_HEADER_LEN};
use od::hook::{Device, Objects, ProcessImage};
use od::sdo::frame::Address;

use crate::esc::al::{AlState, AlStatusCode, SmRule};
use crate::esc::{Chain, Esc};
use crate::foe::{FoeEvent, FoeServer, Link};
use crate::frame::FrameError;

/// Mailbox error: the protocol is not supported (ETG.1000.4 §5.6).
const MBXERR_UNSUPPORTED_PROTOCOL: u16 = 0x0002;
/// Mailbox error: the mailbox is too short for its protocol's header.
const MBXERR_SIZE_TOO_SHORT: u16 = 0x0006;

/// What a unit serves beside CoE through its mailbox: FoE where it has it, and in Bootstrap
/// nothing else (a bootloader speaks FoE only: CoE is answered with the mailbox error 0x0002).
struct Protocols<'a> {
    foe: Option<&'a mut FoeServer>,
    link: Link,
}

impl MailboxService for Protocols<'_> {
    fn takes(&self, mailbox_type: MailboxType) -> bool {
        self.link.boot || (mailbox_type == MailboxType::Foe && self.foe.is_some())
    }

    fn serve(&mut self, now: Instant, header: &MailboxHeader, data: &[u8]) -> ServiceAnswer {
        match (self.foe.as_deref_mut(), header.mailbox_type) {
            (Some(_), MailboxType::Foe) if data.len() < FOE_HEADER_LEN => {
                ServiceAnswer::MailboxError(MBXERR_SIZE_TOO_SHORT)
            }
            (Some(foe), MailboxType::Foe) => {
                foe.handle_mailbox(now, data, self.link);
                match foe.poll_transmit() {
                    Some(frame) => ServiceAnswer::Mailbox(MailboxType::Foe, frame),
                    None => ServiceAnswer::Nothing,
                }
            }
            _ => ServiceAnswer::MailboxError(MBXERR_UNSUPPORTED_PROTOCOL),
        }
    }
}

/// One line of the log for what the FoE server of unit `k` (0 = first) did.
fn log_foe(k: usize, event: FoeEvent) {
    let unit = k + 1;
    match event {
        FoeEvent::Written { name, size } => {
            tracing::info!(unit, file = %printable(&name), size, "FoE: file written")
        }
        FoeEvent::Read { name, size } => {
            tracing::info!(unit, file = %printable(&name), size, "FoE: file read")
        }
        FoeEvent::Refused { name, code } => {
            tracing::info!(unit, file = %printable(&name), %code, "FoE: refused")
        }
        FoeEvent::Aborted { name, code } => {
            tracing::info!(unit, file = %printable(&name), %code, "FoE: the master ended the transfer")
        }
        FoeEvent::TimedOut { name } => {
            tracing::info!(unit, file = %printable(&name), "FoE: the transfer timed out")
        }
    }
}

/// What starts a process-data exchange of the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SyncEvent {
    /// The SYNC0 event of the Distributed Clock (ETG.1000.4 §9.3), at its own instant.
    Sync0,
    /// A new output image in SM2 while SYNC0 gives no pulses (off, or activated but before its start
    /// time): SyncManager-synchronous operation.
    Outputs,
}

/// A device behind its dictionary, as a unit of a [`UnitChain`] runs it: the project's one device
/// lifecycle ([`Device`], which the CANopen node runs too) with what EtherCAT adds (the process
/// images, the AL state, the SyncManager watchdog, the SYNC0 cycle). The dictionary and the device
/// hook come from [`Objects`]; the CoE server serves them as they are.
pub trait Model: Objects + Clone {
    /// The device: the unit runs it up to each cycle ([`Device::handle_timeout`]), up to the
    /// instant of an output image before it delivers the image, and synchronises it
    /// ([`Model::sync`]).
    fn device(&mut self) -> &mut dyn Device;

    /// The process images of the present PDO assignment and mapping, outputs (SM2) and inputs
    /// (SM3); or the AL status code with which Pre-Op → Safe-Op is refused while they are invalid
    /// (0x0025 invalid output mapping, 0x0024 invalid input mapping).
    fn process_images(&self) -> Result<(ProcessImage, ProcessImage), AlStatusCode>;

    /// The unit went from AL state `from` to `to` at `now`.
    fn set_al_state(&mut self, from: AlState, to: AlState, now: Instant);

    /// The master stopped reaching the unit in Op (the SyncManager watchdog expired, or the link was
    /// lost) at `now`; the unit drops to Safe-Op right after.
    fn outputs_lost(&mut self, now: Instant);

    /// A synchronisation event at `at` (the device has run up to `at`; a new output image is
    /// already in its entries): by default the device's [`Device::sync`], whatever the event.
    fn sync(&mut self, at: Instant, event: SyncEvent) {
        let _ = event;
        self.device().sync(at);
    }

    /// The SYNC0 cycle the unit runs with from Safe-Op on (the master set it in Pre-Op), or `None`
    /// without SYNC0; told when the unit enters Safe-Op from Pre-Op, and `None` when it goes back
    /// to Pre-Op or Init.
    fn set_sync0_cycle(&mut self, _cycle: Option<Duration>) {}
}

/// One unit behind its ESC: the model, its CoE server and its process data.
#[derive(Clone)]
pub struct Unit<M> {
    model: M,
    coe: CoeServer,
    /// The CoE server as it starts (again in Init).
    coe_at_start: CoeServer,
    /// Answers waiting for SM1 to be read.
    pending: VecDeque<Vec<u8>>,
    /// The AL state the model and the server were last told.
    state: AlState,
    /// SM2 / SM3 start addresses from the ESI (none for a device without that SyncManager).
    outputs_at: Option<u16>,
    inputs_at: Option<u16>,
    /// The layouts of SM2 and SM3 in force since the unit entered Safe-Op.
    output_image: ProcessImage,
    input_image: ProcessImage,
    /// The ESC's output-image count last taken into the model.
    outputs_taken: u64,
    /// The process-data SyncManager checks of the ESI (outputs, inputs), before the lengths of
    /// the unit's images are put in.
    sm_rules: (Option<SmRule>, Option<SmRule>),
    /// FoE, where the unit has it.
    foe: Option<FoeServer>,
}

impl<M: Model> Unit<M> {
    /// `model` with `coe` serving its dictionary, its process data at `outputs_at` (SM2) and
    /// `inputs_at` (SM3) where it has those SyncManagers, in Init.
    pub fn new(
        model: M,
        coe: CoeServer,
        outputs_at: Option<u16>,
        inputs_at: Option<u16>,
    ) -> Unit<M> {
        Unit {
            model,
            coe_at_start: coe.clone(),
            coe,
            pending: VecDeque::new(),
            state: AlState::Init,
            outputs_at,
            inputs_at,
            output_image: ProcessImage::default(),
            input_image: ProcessImage::default(),
            outputs_taken: 0,
            sm_rules: (None, None),
            foe: None,
        }
    }

    /// The unit with `foe` serving FoE through its mailbox (without it, an FoE mailbox is answered
    /// with the mailbox error 0x0002, unsupported protocol).
    pub fn with_foe(mut self, foe: FoeServer) -> Unit<M> {
        self.foe = Some(foe);
        self
    }

    /// The FoE server, where the unit has one.
    pub fn foe(&self) -> Option<&FoeServer> {
        self.foe.as_ref()
    }

    /// The model.
    pub fn model(&self) -> &M {
        &self.model
    }

    /// The process images in force (outputs, inputs).
    pub fn images(&self) -> (&ProcessImage, &ProcessImage) {
        (&self.output_image, &self.input_image)
    }

    /// Puts the waiting answers into SM1 while it takes them.
    fn send_pending(&mut self, esc: &mut Esc) {
        while let Some(next) = self.pending.front() {
            if !esc.put_mailbox(next) {
                break;
            }
            self.pending.pop_front();
        }
    }

    /// The master stopped reaching the unit in Op (watchdog, link): the model hears it, and the
    /// unit goes to Safe-Op with the error indication and code 0x001B.
    fn drop_to_safe_op(&mut self, esc: &mut Esc, now: Instant) {
        self.model.outputs_lost(now);
        esc.al_fault(AlState::SafeOp, AlStatusCode::SyncManagerWatchdog);
    }

    /// Reads the PDO configuration again: the SyncManager lengths Pre-Op → Safe-Op checks, or the
    /// code it refuses with (ETG.1000.6 §6.4.1.4). A process-data SyncManager of an empty image is
    /// not checked (a master leaves it disabled).
    fn configure_al(&self, esc: &mut Esc) {
        match self.model.process_images() {
            Ok((outputs, inputs)) => {
                esc.al.mapping_refused = None;
                let with_len = |rule: Option<SmRule>, image: &ProcessImage| {
                    let len = u16::try_from(image.len()).unwrap_or(u16::MAX);
                    rule.filter(|_| len > 0).map(|r| SmRule {
                        len: (len, len),
                        ..r
                    })
                };
                esc.al.outputs = with_len(self.sm_rules.0, &outputs);
                esc.al.inputs = with_len(self.sm_rules.1, &inputs);
            }
            Err(code) => esc.al.mapping_refused = Some(code),
        }
    }

    /// Tells the model and the CoE server the AL state (`sync0`: the SYNC0 cycle in ns, when on).
    fn sync_state(&mut self, al: AlState, now: Instant, sync0: Option<u32>) {
        let from = self.state;
        if al == from {
            return;
        }
        self.state = al;
        if al == AlState::Init {
            // The mailbox restarts in Init (as the ESC empties its SyncManagers): no transfer, no
            // answer waiting, and the mailbox counters from the start. A master that starts again
            // counts from 1 again, and a request with the counter of the request before Init would
            // otherwise be taken for a repeat and answered with that old response.
            self.coe = self.coe_at_start.clone();
            self.pending.clear();
            if let Some(foe) = &mut self.foe {
                foe.reset();
            }
        }
        if from == AlState::PreOp && al == AlState::SafeOp {
            // ETG.1000.6 §5.6.7.4: the PDO assignment of Pre-Op takes effect here.
            if let Ok((outputs, inputs)) = self.model.process_images() {
                self.output_image = outputs;
                self.input_image = inputs;
            }
            self.model
                .set_sync0_cycle(sync0.map(|ns| Duration::from_nanos(u64::from(ns))));
        }
        if matches!(al, AlState::PreOp | AlState::Init) {
            self.model.set_sync0_cycle(None);
        }
        self.model.set_al_state(from, al, now);
        let mapped: Vec<Address> = if matches!(al, AlState::Op | AlState::SafeOp) {
            self.output_image
                .entries()
                .iter()
                .filter(|e| !e.is_padding())
                .map(|e| e.at)
                .collect()
        } else {
            Vec::new()
        };
        self.coe.set_rxpdo_mapped(mapped);
    }
}

/// A chain of units of model `M`. A clone is a second chain in the same state (a fuzz target or a
/// test builds one chain and clones it for each case). See the [module documentation](self).
#[derive(Clone)]
pub struct UnitChain<M> {
    /// The ESCs in frame order.
    pub chain: Chain,
    units: Vec<Unit<M>>,
    /// One unit's process data on its way between the ESC and the model, kept for every cycle.
    image: Vec<u8>,
    /// The units' process-data cycle.
    cycle: Duration,
    /// The latest time the chain was given.
    now: Instant,
    /// When the last process-data cycle ran and when the next is due.
    last_cycle: Instant,
    next_cycle: Instant,
    /// Files the units' FoE servers took whole, for the edge to keep: unit, name, contents.
    written: VecDeque<(usize, Vec<u8>, Arc<[u8]>)>,
}

impl<M: Model> UnitChain<M> {
    /// The units, each behind its ESC (its SII and AL checks set), in frame order, powered on at
    /// `now` in Init, running their process-data cycle every `cycle` (at least 1 µs).
    pub fn from_units(units: Vec<(Esc, Unit<M>)>, cycle: Duration, now: Instant) -> UnitChain<M> {
        let cycle = cycle.max(Duration::from_micros(1));
        let mut chain = Chain::new(0);
        chain.start(now);
        let mut list = Vec::with_capacity(units.len());
        for (mut esc, mut unit) in units {
            unit.sm_rules = (esc.al.outputs, esc.al.inputs);
            unit.configure_al(&mut esc);
            chain.push(esc);
            list.push(unit);
        }
        UnitChain {
            chain,
            units: list,
            image: Vec::new(),
            cycle,
            now,
            last_cycle: now,
            next_cycle: now + cycle,
            written: VecDeque::new(),
        }
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
    pub fn unit(&self, k: usize) -> Option<&M> {
        self.units.get(k).map(|u| &u.model)
    }

    /// The model of unit `k`, to change what it senses.
    pub fn unit_mut(&mut self, k: usize) -> Option<&mut M> {
        self.units.get_mut(k).map(|u| &mut u.model)
    }

    /// Unit `k` with its CoE server and process images.
    pub fn slot(&self, k: usize) -> Option<&Unit<M>> {
        self.units.get(k)
    }

    /// The FoE server of unit `k`, where it has one: to put the files it had before it started
    /// into its store.
    pub fn foe_mut(&mut self, k: usize) -> Option<&mut FoeServer> {
        self.units.get_mut(k).and_then(|u| u.foe.as_mut())
    }

    /// A file a unit took whole by FoE since the last call: the unit (0 = first), the file's name
    /// and its contents, for the edge to keep (`ethercat-node --foe-dir`). Each file written is
    /// given once, with what it holds when it is given.
    #[must_use]
    pub fn poll_written(&mut self) -> Option<(usize, Vec<u8>, Arc<[u8]>)> {
        self.written.pop_front()
    }

    /// Processes a frame that arrived at `now` as it passes the chain, then tells the models their
    /// AL states and serves the mailboxes the frame completed.
    pub fn handle_frame(&mut self, now: Instant, frame: &mut [u8]) -> Result<(), FrameError> {
        // The chain's time moves on with the frame (Chain::handle_frame), as set_now moves it.
        self.now = self.now.max(now);
        self.chain.handle_frame(self.now, frame)?;
        self.serve_mailboxes();
        Ok(())
    }

    /// Runs what is due at `now`: the SDO transfer timers and, once [`UnitChain::poll_timeout`]'s
    /// cycle time has come, one process-data cycle of every unit over the time since the last one.
    pub fn handle_timeout(&mut self, now: Instant) {
        self.set_now(now);
        for unit in &mut self.units {
            unit.coe.handle_timeout(self.now);
            if let Some(foe) = &mut unit.foe {
                foe.handle_timeout(self.now);
            }
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

    /// When [`UnitChain::handle_timeout`] is next due: the next process-data cycle, or an SDO
    /// transfer timer that runs out before it.
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Instant> {
        let sdo = self.units.iter().filter_map(|u| u.coe.poll_timeout()).min();
        let foe = self
            .units
            .iter()
            .filter_map(|u| u.foe.as_ref().and_then(FoeServer::poll_timeout))
            .min();
        let first = match (sdo, foe) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        Some(first.map_or(self.next_cycle, |t| t.min(self.next_cycle)))
    }

    fn set_now(&mut self, now: Instant) {
        self.now = self.now.max(now);
        self.chain.set_now(self.now);
    }

    fn serve_mailboxes(&mut self) {
        let now = self.now;
        let units = self.chain.slaves.iter_mut().zip(self.units.iter_mut());
        for (k, (esc, unit)) in units.enumerate() {
            let (al, _) = esc.al_state();
            if al != unit.state {
                unit.sync_state(al, now, esc.sync0_cycle());
            }
            if !unit.pending.is_empty() {
                unit.send_pending(esc);
            }
            // One request at a time (ETG.1000.6 §5.5): the next is taken only once the answers
            // before it are in SM1 or read, so a master that never reads SM1 finds SM0 full.
            if unit.pending.is_empty() && esc.mailbox_written() {
                if let Some(mailbox) = esc.take_mailbox() {
                    let (write_len, read_len) = esc.mailbox_lengths();
                    let mut protocols = Protocols {
                        foe: unit.foe.as_mut(),
                        link: Link {
                            boot: al == AlState::Boot,
                            write_len: usize::from(write_len),
                            read_len: usize::from(read_len),
                        },
                    };
                    unit.coe
                        .handle_mailbox_with(now, &mailbox, &mut unit.model, &mut protocols);
                    while unit.coe.poll_event().is_some() {}
                    if let Some(foe) = &mut unit.foe {
                        while let Some(e) = foe.poll_event() {
                            log_foe(k, e);
                        }
                        while let Some((name, data)) = foe.poll_written() {
                            self.written.push_back((k, name, data));
                        }
                    }
                    unit.pending
                        .extend(std::iter::from_fn(|| unit.coe.poll_transmit()));
                    unit.send_pending(esc);
                    // A download may have changed the PDO assignment or mapping.
                    unit.configure_al(esc);
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
        let last = self.last_cycle;
        let dt = now.saturating_duration_since(last);
        self.last_cycle = now;
        for (esc, unit) in self.chain.slaves.iter_mut().zip(self.units.iter_mut()) {
            let expired = esc.check_watchdog();
            let (al, _) = esc.al_state();
            if expired && al == AlState::Op {
                unit.drop_to_safe_op(esc, now);
            }
            let (al, _) = esc.al_state();
            unit.sync_state(al, now, esc.sync0_cycle());
            let sync0_on = esc.sync0_cycle().is_some();
            // The last SYNC0 event since the last cycle, at its own instant (never before it).
            let sync0 = esc.sync0_passed().map(|at| {
                let ago = Duration::from_nanos(esc.system_time().saturating_sub(at));
                now - ago.min(dt)
            });
            // The output image is taken at the SYNC0 event, else at the cycle: the device runs up
            // to that instant first (what was due before it), takes the image there, is
            // synchronised, and runs on to `now`.
            let take_at = sync0.unwrap_or(now);
            let mut fresh = false;
            let new_image = esc.outputs_received() != unit.outputs_taken;
            if let Some(at) = unit.outputs_at.filter(|_| al == AlState::Op && new_image) {
                unit.outputs_taken = esc.outputs_received();
                let n = unit.output_image.len();
                self.image.resize(self.image.len().max(n), 0);
                let outputs = &mut self.image[..n];
                esc.load_into(at, outputs);
                esc.release_outputs(at);
                od::hook::run_before(unit.model.device(), take_at);
                let (dict, hook) = unit.model.split();
                unit.output_image.unpack(outputs, dict, hook, take_at);
                fresh = true;
            }
            match sync0 {
                // The device runs up to the SYNC0 event, takes it, and runs on from it.
                Some(at) => {
                    if at > last {
                        unit.model.device().handle_timeout(at);
                    }
                    unit.model.sync(at, SyncEvent::Sync0);
                }
                // SYNC0 activated but not started yet (a master sets its start time some way ahead:
                // SOEM 100 ms) drives nothing: until its first pulse the outputs do.
                None if fresh && !(sync0_on && esc.sync0_running()) => {
                    unit.model.sync(now, SyncEvent::Outputs)
                }
                None => {}
            }
            unit.model.device().handle_timeout(now);
            let inputs_at = unit
                .inputs_at
                .filter(|_| matches!(al, AlState::Op | AlState::SafeOp));
            if let Some(at) = inputs_at {
                let n = unit.input_image.len();
                self.image.resize(self.image.len().max(n), 0);
                let inputs = &mut self.image[..n];
                let (dict, hook) = unit.model.split();
                unit.input_image.pack(dict, hook, inputs);
                esc.put_inputs(at, inputs);
            }
        }
    }

    /// The link to the master was lost: a unit in Op drops to Safe-Op with the error indication,
    /// as on a watchdog expiry, and stays there until the master requests Op again.
    pub fn link_lost(&mut self, now: Instant) {
        self.set_now(now);
        let now = self.now;
        for (esc, unit) in self.chain.slaves.iter_mut().zip(self.units.iter_mut()) {
            if esc.al_state().0 == AlState::Op {
                unit.drop_to_safe_op(esc, now);
                unit.sync_state(AlState::SafeOp, now, esc.sync0_cycle());
            }
        }
    }
}
