//! One slave's boot-slave process (CiA 302-2 §4.2, figures 6 to 11) and its supervision.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use can_link::CanFrame;
use od::abort::AbortCode;
use od::sdo::{Address, ClientConfig, ClientEvent, SdoClient, SdoClientError};

use super::plan::{Expect, SlavePlan};
use super::status::{BootError, BootEvent, ErrorStatus, NodeState};

/// What the manager knows of one node, for a table.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NodeReport {
    /// Node-ID.
    pub node: u8,
    /// Its name in the bus description.
    pub name: String,
    /// 0x1F81 bit 3.
    pub mandatory: bool,
    /// Where it is.
    pub state: NodeState,
    /// The state byte of its last heartbeat (0x00 boot-up, 0x04 stopped, 0x05 operational, 0x7F
    /// pre-operational), `None` before the first.
    pub nmt: Option<u8>,
    /// What it answered for 0x1000 and 0x1018:01–04 in its last boot (`None`: not read).
    pub identity: [Option<u32>; 5],
    /// Configuration entries written in its last boot, and how many there are.
    pub configured: (usize, usize),
    /// Its heartbeat consumer time, ms (0: not supervised).
    pub heartbeat_ms: u16,
    /// The last error, kept after a later boot succeeded.
    pub last_error: Option<BootError>,
    /// How often it booted.
    pub boots: u32,
    /// It was operational already and kept alive (CiA 302-2 status L): not booted again.
    pub kept: bool,
    /// Its configuration stamp (0x1020) was the plan's: the configuration was current and not
    /// written again in its last boot.
    pub current: bool,
}

/// What a node's step hands back to the manager.
pub(crate) struct Out<'a> {
    pub(crate) frames: &'a mut VecDeque<CanFrame>,
    pub(crate) events: &'a mut VecDeque<BootEvent>,
    /// The master starts a slave as soon as it booted (0x1F80 bit 3 clear, and bit 1 clear or the
    /// network up already).
    pub(crate) start_now: bool,
    /// How long a failed node waits before it is tried again, when it did not answer.
    pub(crate) retry: Duration,
    /// How long a node is waited for after the master's reset.
    pub(crate) boot_up_wait: Duration,
}

impl Out<'_> {
    pub(crate) fn nmt(&mut self, command: u8, node: u8) {
        if let Some(f) = CanFrame::new(0x000, &[command, node]) {
            self.frames.push_back(f);
        }
        self.events.push_back(BootEvent::Nmt { command, node });
    }
}

/// A value read in the identity check.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Check {
    /// 0x1000 against 0x1F84.
    DeviceType,
    /// 0x1018:01–04 against 0x1F85–0x1F88 (the sub-index).
    Identity(u8),
    /// 0x1F56:01 against 0x1F55.
    Software,
    /// 0x1020:01 and :02 (the configuration's date and time) against the stamp the plan writes
    /// with the configuration: equal, the configuration is current and is not written again.
    Stamp(u8),
}

impl Check {
    fn address(self) -> Address {
        match self {
            Check::DeviceType => Address {
                index: 0x1000,
                sub: 0,
            },
            Check::Identity(sub) => Address { index: 0x1018, sub },
            Check::Software => Address {
                index: 0x1F56,
                sub: 1,
            },
            Check::Stamp(sub) => Address { index: 0x1020, sub },
        }
    }

    fn status(self) -> ErrorStatus {
        match self {
            Check::DeviceType => ErrorStatus::B,
            Check::Identity(1) => ErrorStatus::D,
            Check::Identity(2) => ErrorStatus::M,
            Check::Identity(3) => ErrorStatus::N,
            Check::Identity(_) => ErrorStatus::O,
            Check::Software => ErrorStatus::H,
            Check::Stamp(_) => ErrorStatus::J,
        }
    }

    fn mismatch_status(self) -> ErrorStatus {
        match self {
            Check::DeviceType => ErrorStatus::C,
            other => other.status(),
        }
    }

    fn what(self) -> &'static str {
        match self {
            Check::DeviceType => "device type",
            Check::Identity(1) => "vendor-ID",
            Check::Identity(2) => "product code",
            Check::Identity(3) => "revision number",
            Check::Identity(_) => "serial number",
            Check::Software => "software identification",
            Check::Stamp(_) => "configuration stamp",
        }
    }

    /// What a different value means.
    fn meaning(self) -> &'static str {
        match self {
            Check::DeviceType => "a different kind of device answers at this node-ID",
            Check::Identity(1) => "a device of another vendor answers at this node-ID",
            Check::Identity(2) => "another product answers at this node-ID",
            Check::Identity(3) => "another revision of the device answers at this node-ID",
            Check::Identity(_) => "another unit of the device answers at this node-ID",
            Check::Software => "its software is to be updated, which this manager does not do",
            Check::Stamp(_) => "its configuration is written",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Step {
    /// Waiting for the boot-up message (or, kept alive, a heartbeat) until then.
    AwaitBootUp(Instant),
    /// A value of the identity check being read.
    Read(Check),
    /// Configuration entry `i` being written.
    Write(usize),
    /// Waiting for the first heartbeat until then.
    AwaitHeartbeat(Instant),
    /// Booted and supervised.
    Up,
    /// Only watched (0x1F81 bit 2 clear).
    Watched,
    /// Failed; tried again at the instant, if any, or at its next boot-up message.
    Failed(Option<Instant>),
    /// Its heartbeat was lost; booted again at its next boot-up message or heartbeat.
    Lost,
}

/// One slave's process.
pub(crate) struct Node {
    pub(crate) plan: SlavePlan,
    pub(crate) report: NodeReport,
    sdo: SdoClient,
    sdo_config: ClientConfig,
    step: Step,
    last_heartbeat: Option<Instant>,
}

impl Node {
    pub(crate) fn new(plan: SlavePlan, sdo_timeout: Duration) -> Node {
        let sdo_config = ClientConfig {
            timeout: sdo_timeout,
            block: false,
            ..ClientConfig::default()
        };
        let report = NodeReport {
            node: plan.node_id,
            name: plan.name.clone(),
            mandatory: plan.mandatory(),
            state: NodeState::Resetting,
            nmt: None,
            identity: [None; 5],
            configured: (0, plan.configuration.len()),
            heartbeat_ms: plan.heartbeat_ms,
            last_error: None,
            boots: 0,
            kept: false,
            current: false,
        };
        Node {
            sdo: SdoClient::new(sdo_config.clone()),
            sdo_config,
            plan,
            report,
            step: Step::Failed(None),
            last_heartbeat: None,
        }
    }

    pub(crate) fn is_up(&self) -> bool {
        self.step == Step::Up
    }

    /// True while its boot runs.
    pub(crate) fn busy(&self) -> bool {
        matches!(
            self.step,
            Step::AwaitBootUp(_) | Step::Read(_) | Step::Write(_) | Step::AwaitHeartbeat(_)
        )
    }

    /// True when nothing is pending: up, watched, or failed with no retry due.
    pub(crate) fn settled(&self) -> bool {
        matches!(
            self.step,
            Step::Up | Step::Watched | Step::Failed(None) | Step::Lost
        )
    }

    fn set_state(&mut self, state: NodeState, out: &mut Out) {
        if self.report.state != state {
            self.report.state = state.clone();
            out.events.push_back(BootEvent::Node {
                node: self.plan.node_id,
                state,
            });
        }
    }

    /// The master reset the network (or is about to boot without a reset, for a node kept alive):
    /// the node's boot starts at its boot-up message or when the wait is over.
    pub(crate) fn await_boot_up(&mut self, now: Instant, out: &mut Out) {
        self.sdo = SdoClient::new(self.sdo_config.clone());
        self.step = Step::AwaitBootUp(now + out.boot_up_wait);
        self.set_state(NodeState::Resetting, out);
    }

    /// Starts the boot-slave process from its first step.
    pub(crate) fn start_boot(&mut self, now: Instant, out: &mut Out) {
        self.sdo = SdoClient::new(self.sdo_config.clone());
        self.report.identity = [None; 5];
        self.report.configured.0 = 0;
        self.report.kept = false;
        self.report.current = false;
        if !self.plan.boots() {
            self.step = Step::Watched;
            self.set_state(NodeState::Watched, out);
            return;
        }
        self.set_state(NodeState::Checking, out);
        self.read(now, Check::DeviceType, out);
    }

    fn read(&mut self, now: Instant, check: Check, out: &mut Out) {
        self.step = Step::Read(check);
        if let Err(e) = self.sdo.start_upload_expecting(now, check.address(), 4) {
            self.fail_sdo(now, e, out);
        }
        self.drain(now, out);
    }

    /// The step after the check `done` passed: the next value to check, else the configuration.
    fn next(&mut self, now: Instant, done: Check, out: &mut Out) {
        let mut candidates = vec![];
        for sub in 1..=4u8 {
            if self.plan.identity[usize::from(sub) - 1].value != 0 {
                candidates.push(Check::Identity(sub));
            }
        }
        if self.plan.checks_software() && self.plan.software.value != 0 {
            candidates.push(Check::Software);
        }
        if self.plan.stamp.is_some() {
            candidates.extend([Check::Stamp(1), Check::Stamp(2)]);
        }
        let after = match done {
            Check::DeviceType => 0,
            c => candidates
                .iter()
                .position(|&x| x == c)
                .map_or(candidates.len(), |i| i + 1),
        };
        match candidates.get(after) {
            Some(&c) => self.read(now, c, out),
            None => self.write(now, 0, out),
        }
    }

    fn write(&mut self, now: Instant, i: usize, out: &mut Out) {
        let of = self.plan.configuration.len();
        self.report.configured = (i, of);
        let Some(c) = self.plan.configuration.get(i) else {
            return self.error_control(now, out);
        };
        let mux = Address {
            index: c.entry.index,
            sub: c.entry.sub,
        };
        let data = c.entry.data.clone();
        // One event when the configuration starts; the count goes on in the report.
        if i == 0 {
            self.set_state(NodeState::Configuring { done: 0, of }, out);
        } else {
            self.report.state = NodeState::Configuring { done: i, of };
        }
        self.step = Step::Write(i);
        if let Err(e) = self.sdo.start_download(now, mux, data) {
            self.fail_sdo(now, e, out);
        }
        self.drain(now, out);
    }

    fn error_control(&mut self, now: Instant, out: &mut Out) {
        if self.plan.heartbeat_ms == 0 {
            return self.booted(out);
        }
        self.step = Step::AwaitHeartbeat(now + ms(self.plan.heartbeat_ms));
        self.set_state(NodeState::ErrorControl, out);
    }

    fn booted(&mut self, out: &mut Out) {
        self.step = Step::Up;
        self.report.boots += 1;
        if out.start_now {
            out.nmt(0x01, self.plan.node_id);
        }
        self.set_state(NodeState::Up, out);
    }

    fn fail(&mut self, now: Instant, status: ErrorStatus, message: String, out: &mut Out) {
        let error = BootError {
            node: self.plan.node_id,
            status,
            message,
        };
        self.report.last_error = Some(error.clone());
        self.sdo = SdoClient::new(self.sdo_config.clone());
        self.step = match status {
            ErrorStatus::B => Step::Failed(Some(now + out.retry)),
            ErrorStatus::E => Step::Lost,
            _ => Step::Failed(None),
        };
        self.set_state(NodeState::Failed(error), out);
    }

    /// A transfer that failed, in the words of the step it was.
    fn fail_sdo(&mut self, now: Instant, e: SdoClientError, out: &mut Out) {
        let timeout = self.sdo_config.timeout.as_millis();
        let why = |code: Option<AbortCode>| match code {
            Some(AbortCode::Timeout) | None => format!("no answer within {timeout} ms"),
            Some(code) => format!("the node refused it with {code}"),
        };
        let code = match &e {
            SdoClientError::Aborted { code, .. } => Some(*code),
            _ => None,
        };
        match self.step {
            // No stamp to compare (no 0x1020, or refused): the configuration is written.
            Step::Read(Check::Stamp(_)) => self.write(now, 0, out),
            Step::Read(check) => {
                let a = check.address();
                let mut message = format!(
                    "{} 0x{:04X}:{:02X} could not be read: {}",
                    check.what(),
                    a.index,
                    a.sub,
                    why(code)
                );
                if check == Check::DeviceType && matches!(code, None | Some(AbortCode::Timeout)) {
                    message.push_str(" — no node answers at this node-ID");
                }
                self.fail(now, check.status(), message, out);
            }
            Step::Write(i) => {
                let c = &self.plan.configuration[i];
                let message = format!(
                    "writing 0x{:04X}:{:02X} = {} ({}) failed: {} — the node refuses its configuration",
                    c.entry.index,
                    c.entry.sub,
                    shown(&c.entry.data),
                    c.origin,
                    why(code)
                );
                self.fail(now, ErrorStatus::J, message, out);
            }
            _ => {}
        }
    }

    /// Hands the SDO client's frames and outcome on.
    fn drain(&mut self, now: Instant, out: &mut Out) {
        let id = u16::from(self.plan.node_id);
        while let Some(frame) = self.sdo.poll_transmit() {
            if let Some(f) = CanFrame::new(0x600 + id, &frame) {
                out.frames.push_back(f);
            }
        }
        while let Some(event) = self.sdo.poll_event() {
            match (event, self.step) {
                (ClientEvent::Uploaded(bytes), Step::Read(check)) => {
                    self.checked(now, check, &bytes, out);
                }
                (ClientEvent::Downloaded, Step::Write(i)) => self.write(now, i + 1, out),
                (ClientEvent::Failed(e), _) => self.fail_sdo(now, e, out),
                _ => {}
            }
        }
    }

    fn checked(&mut self, now: Instant, check: Check, bytes: &[u8], out: &mut Out) {
        let mut b = [0u8; 4];
        let n = bytes.len().min(4);
        b[..n].copy_from_slice(&bytes[..n]);
        let found = u32::from_le_bytes(b);
        let (slot, expect): (usize, &Expect) = match check {
            Check::DeviceType => (0, &self.plan.device_type),
            Check::Identity(sub) => (usize::from(sub), &self.plan.identity[usize::from(sub) - 1]),
            Check::Software => (5, &self.plan.software),
            Check::Stamp(sub) => {
                let stamp = self.plan.stamp.unwrap_or_default();
                return match (sub, found == stamp[usize::from(sub) - 1]) {
                    (_, false) => self.write(now, 0, out),
                    (1, true) => self.next(now, check, out),
                    (_, true) => {
                        // The node keeps the configuration this stamp closes: not written again.
                        self.report.current = true;
                        self.error_control(now, out)
                    }
                };
            }
        };
        if let Some(s) = self.report.identity.get_mut(slot) {
            *s = Some(found);
        }
        if expect.value != 0 && expect.value != found {
            let a = check.address();
            let message = format!(
                "{} 0x{:08X} expected ({}), 0x{found:08X} found in 0x{:04X}:{:02X} — {}",
                check.what(),
                expect.value,
                expect.origin,
                a.index,
                a.sub,
                check.meaning()
            );
            return self.fail(now, check.mismatch_status(), message, out);
        }
        self.next(now, check, out);
    }

    /// A frame from the node's SDO server.
    pub(crate) fn handle_sdo(&mut self, now: Instant, data: [u8; 8], out: &mut Out) {
        self.sdo.handle_frame(now, &data);
        self.drain(now, out);
    }

    /// Its heartbeat or boot-up message (state byte `state`).
    pub(crate) fn handle_heartbeat(&mut self, now: Instant, state: u8, out: &mut Out) {
        self.report.nmt = Some(state);
        if state != 0x00 {
            self.last_heartbeat = Some(now);
        }
        match (self.step, state) {
            (Step::AwaitBootUp(_), 0x05) if self.plan.keep_alive() => {
                // CiA 302-2 status L: operational already, kept alive; error control only.
                self.report.kept = true;
                self.report.boots += 1;
                self.step = Step::Up;
                self.set_state(NodeState::Up, out);
            }
            // Kept alive and not operational: booted now (no boot-up message will come).
            (Step::AwaitBootUp(_), _) if self.plan.keep_alive() => self.start_boot(now, out),
            (Step::AwaitHeartbeat(_), s) if s != 0x00 => self.booted(out),
            (Step::Lost, _) => self.start_boot(now, out),
            // A boot-up message at any other time: the node reset; its boot starts again.
            (_, 0x00) => self.start_boot(now, out),
            _ => {}
        }
    }

    /// The instant the node's step ends by itself: the wait for its boot-up message or its first
    /// heartbeat, its next try, or (up) the end of its heartbeat's consumer time.
    fn deadline(&self) -> Option<Instant> {
        match self.step {
            Step::AwaitBootUp(t) | Step::AwaitHeartbeat(t) | Step::Failed(Some(t)) => Some(t),
            Step::Up if self.plan.heartbeat_ms != 0 => {
                self.last_heartbeat.map(|t| t + ms(self.plan.heartbeat_ms))
            }
            _ => None,
        }
    }

    /// When the node needs its next call.
    pub(crate) fn poll_timeout(&self) -> Option<Instant> {
        [self.deadline(), self.sdo.poll_timeout()]
            .into_iter()
            .flatten()
            .min()
    }

    /// The time passed; returns true when the node's heartbeat was lost just now.
    pub(crate) fn handle_timeout(&mut self, now: Instant, out: &mut Out) -> bool {
        if self.sdo.poll_timeout().is_some_and(|t| t <= now) {
            self.sdo.handle_timeout(now);
            self.drain(now, out);
        }
        if self.deadline().is_none_or(|t| t > now) {
            return false;
        }
        match self.step {
            Step::AwaitBootUp(_) | Step::Failed(_) => self.start_boot(now, out),
            Step::AwaitHeartbeat(_) => {
                let message = format!(
                    "no heartbeat within {} ms of its configuration (consumer time, {}) — its \
                     heartbeat producer 0x1017 is 0 or slower than that",
                    self.plan.heartbeat_ms, self.plan.heartbeat_origin
                );
                self.fail(now, ErrorStatus::K, message, out);
            }
            Step::Up => {
                let message = format!(
                    "heartbeat lost: none for {} ms (consumer time, {}) — the node stopped, lost \
                     power or left the bus",
                    self.plan.heartbeat_ms, self.plan.heartbeat_origin
                );
                self.fail(now, ErrorStatus::E, message, out);
                return true;
            }
            _ => {}
        }
        false
    }
}

fn ms(v: u16) -> Duration {
    Duration::from_millis(u64::from(v))
}

/// A value written, for words: the number (little-endian) when it is 1 to 8 bytes.
fn shown(data: &[u8]) -> String {
    if (1..=8).contains(&data.len()) {
        let mut b = [0u8; 8];
        b[..data.len()].copy_from_slice(data);
        format!("0x{:X}", u64::from_le_bytes(b))
    } else {
        format!("{} bytes", data.len())
    }
}
