//! The master's side of the emulator's tests, benchmarks and examples: the start-up a master does
//! (station addresses, the SyncManagers and FMMUs of the ESI, the AL states), one LRW of all process
//! data per cycle, and CoE SDO transfers through the mailbox framed byte by byte as ETG.1000.6 lays
//! them out. It runs over any [`Wire`]: in process on a simulated clock ([`SimChain`]) or a raw socket
//! ([`SocketWire`]).
//!
//! Unit k (0-based) gets station address 0x1001 + k; its outputs are mapped at logical address
//! 20·k and its inputs at 20·n + 20·k, so one LRW of 40·n bytes carries every unit's process data.

use std::time::{Duration, Instant};

use ds402::smd::indexer::{Inputs, Outputs};

use crate::esc::al::AlStatusCode;
use crate::esc::registers::SmControl;
use crate::esc::{cmd, CommandCode};
use crate::frame::FrameError;
use crate::frame::{emit, parse, Datagram};
use crate::raw::RawSocket;
use crate::smd::binding::{Device, SmdUnit};
use crate::smd::{SmdChain, SmdSlaveError};
use crate::unit::{Model, UnitChain};

/// Output bytes (0x7000:01–08) and input bytes (0x6000:01–07) of one unit, as its manual's Reference 6
/// lays them out: the master's own layout, independent of the slave's image built from the ESI.
pub const PROCESS_DATA_LEN: usize = 20;

/// Decodes the 20 output bytes (0x7000:01–08, packed little-endian).
pub fn decode_outputs(b: &[u8; PROCESS_DATA_LEN]) -> Outputs {
    let u16_at = |o: usize| u16::from_le_bytes([b[o], b[o + 1]]);
    let u32_at = |o: usize| u32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
    Outputs {
        cmd0: u16_at(0),
        cmd1: u16_at(2),
        position: u32_at(4) as i32,
        velocity: u32_at(8),
        acceleration: u16_at(12),
        deceleration: u16_at(14),
        motor_current: u16_at(16),
        jerk: u16_at(18),
    }
}

/// Encodes the 20 output bytes (what a master puts into SM2).
pub fn encode_outputs(o: &Outputs) -> [u8; PROCESS_DATA_LEN] {
    let mut b = [0u8; PROCESS_DATA_LEN];
    b[0..2].copy_from_slice(&o.cmd0.to_le_bytes());
    b[2..4].copy_from_slice(&o.cmd1.to_le_bytes());
    b[4..8].copy_from_slice(&o.position.to_le_bytes());
    b[8..12].copy_from_slice(&o.velocity.to_le_bytes());
    b[12..14].copy_from_slice(&o.acceleration.to_le_bytes());
    b[14..16].copy_from_slice(&o.deceleration.to_le_bytes());
    b[16..18].copy_from_slice(&o.motor_current.to_le_bytes());
    b[18..20].copy_from_slice(&o.jerk.to_le_bytes());
    b
}

/// Encodes the 20 input bytes (0x6000:01–07).
pub fn encode_inputs(i: &Inputs) -> [u8; PROCESS_DATA_LEN] {
    let mut b = [0u8; PROCESS_DATA_LEN];
    b[0..2].copy_from_slice(&i.status0.to_le_bytes());
    b[2..4].copy_from_slice(&i.status1.to_le_bytes());
    b[4..8].copy_from_slice(&i.motor_position.to_le_bytes());
    b[8..12].copy_from_slice(&i.encoder_position.to_le_bytes());
    b[12..16].copy_from_slice(&i.trapped_encoder_position.to_le_bytes());
    b[16..18].copy_from_slice(&i.motor_current.to_le_bytes());
    b[18..20].copy_from_slice(&i.jerk.to_le_bytes());
    b
}

/// Decodes the 20 input bytes (what a master reads from SM3).
pub fn decode_inputs(b: &[u8; PROCESS_DATA_LEN]) -> Inputs {
    let u16_at = |o: usize| u16::from_le_bytes([b[o], b[o + 1]]);
    let u32_at = |o: usize| u32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
    Inputs {
        status0: u16_at(0),
        status1: u16_at(2),
        motor_position: u32_at(4) as i32,
        encoder_position: u32_at(8) as i32,
        trapped_encoder_position: u32_at(12) as i32,
        motor_current: u16_at(16),
        jerk: u16_at(18),
    }
}

/// The master's source address.
pub const SRC: [u8; 6] = [2, 0, 0, 0, 0, 1];
/// SM0 (mailbox out) and SM1 (mailbox in) start addresses, and their length.
pub const MBX_OUT: u16 = 0x1000;
/// SM1 start address.
pub const MBX_IN: u16 = 0x1080;
/// Mailbox length.
pub const MBX_LEN: usize = 128;

/// What went wrong on the master's side.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum MasterError {
    /// No answer to a frame.
    #[error("no answer to {0}")]
    NoAnswer(String),
    /// An answer that is not what the start-up needs.
    #[error("{what}: working counter {wkc}, expected {expected}")]
    WorkingCounter {
        /// The access.
        what: String,
        /// What came back.
        wkc: u16,
        /// What was expected.
        expected: u16,
    },
    /// A unit refused a state.
    #[error("unit {unit}: AL status 0x{status:04X}, code {code} after requesting state {state}")]
    State {
        /// The unit (0-based).
        unit: usize,
        /// The state requested.
        state: u8,
        /// AL status.
        status: u16,
        /// AL status code.
        code: AlStatusCode,
    },
}

/// Carries a frame to the slaves and back.
pub trait Wire {
    /// Sends `frame` and replaces it with the answer; false when none came.
    fn exchange(&mut self, frame: &mut Vec<u8>) -> bool;

    /// Runs the slaves' cycle for `dt` where the wire can (in process); a real link runs on its own.
    fn pass(&mut self, _dt: Duration) {}

    /// Units on the wire (for the logical layout).
    fn units(&self) -> usize;
}

/// A chain in process on a simulated clock, as its host would run it: a frame takes no time, and
/// [`SimChain::cycle`] moves the clock on and calls [`UnitChain::handle_timeout`] then. The units'
/// cycle is 1 µs, so every [`SimChain::cycle`] of 1 µs or more runs one process-data cycle over the
/// time since the last. Of SMD units unless told otherwise.
#[derive(Clone)]
pub struct SimChain<M = SmdUnit> {
    /// The chain.
    pub chain: UnitChain<M>,
    /// The simulated present.
    pub now: Instant,
}

impl SimChain<SmdUnit> {
    /// `n` units of `device`, powered on now.
    pub fn new(device: Device, n: usize) -> Result<SimChain, SmdSlaveError> {
        let now = Instant::now();
        let chain = SmdChain::new(device, n, Duration::from_micros(1), now)?;
        Ok(SimChain { chain, now })
    }
}

impl<M: Model> SimChain<M> {
    /// `chain`, made at `now` with a process-data cycle of 1 µs, on the simulated clock from `now`.
    pub fn with_chain(chain: UnitChain<M>, now: Instant) -> SimChain<M> {
        SimChain { chain, now }
    }

    /// A frame at the present time ([`UnitChain::handle_frame`]).
    pub fn process(&mut self, frame: &mut [u8]) -> Result<(), FrameError> {
        self.chain.handle_frame(self.now, frame)
    }

    /// Moves the clock on by `dt` without running anything (the next frame carries the later time).
    pub fn advance(&mut self, dt: Duration) {
        self.now += dt;
    }

    /// Moves the clock on by `dt` and runs what is due then ([`UnitChain::handle_timeout`]).
    pub fn cycle(&mut self, dt: Duration) {
        self.now += dt;
        self.chain.handle_timeout(self.now);
    }
}

impl<M> std::ops::Deref for SimChain<M> {
    type Target = UnitChain<M>;

    fn deref(&self) -> &UnitChain<M> {
        &self.chain
    }
}

impl<M> std::ops::DerefMut for SimChain<M> {
    fn deref_mut(&mut self) -> &mut UnitChain<M> {
        &mut self.chain
    }
}

impl<M: Model> Wire for SimChain<M> {
    fn exchange(&mut self, frame: &mut Vec<u8>) -> bool {
        self.process(frame).is_ok()
    }

    fn pass(&mut self, dt: Duration) {
        self.cycle(dt);
    }

    fn units(&self) -> usize {
        self.chain.len()
    }
}

/// A raw socket on the master's end of a link to `units` slaves.
#[derive(Debug)]
pub struct SocketWire {
    socket: RawSocket,
    units: usize,
    /// How long to wait for an answer.
    pub timeout: Duration,
    index: u8,
    buf: Vec<u8>,
}

impl SocketWire {
    /// A wire on `socket` to `units` slaves.
    pub fn new(socket: RawSocket, units: usize) -> SocketWire {
        SocketWire {
            socket,
            units,
            timeout: Duration::from_millis(100),
            index: 0,
            buf: vec![0; 2048],
        }
    }

    /// The socket, for frames the master sends outside [`Wire::exchange`].
    pub fn socket(&self) -> &RawSocket {
        &self.socket
    }
}

impl Wire for SocketWire {
    fn exchange(&mut self, frame: &mut Vec<u8>) -> bool {
        // The first datagram's index tells this frame's answer from a late one.
        self.index = self.index.wrapping_add(1);
        if frame.len() > 17 {
            frame[17] = self.index;
        }
        if self.socket.send(frame).is_err() {
            return false;
        }
        let deadline = Instant::now() + self.timeout;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.socket.recv(&mut self.buf) {
                Ok(Some(n)) => {
                    let answer = &self.buf[..n];
                    if n > 17 && answer[17] == self.index && answer[6] & 0x02 != 0 {
                        frame.clear();
                        frame.extend_from_slice(answer);
                        return true;
                    }
                }
                Ok(None) if !left.is_zero() => {
                    if self.socket.wait(left).is_err() {
                        return false;
                    }
                }
                _ => return false,
            }
        }
    }

    fn units(&self) -> usize {
        self.units
    }
}

/// The station address given to unit `k` (0-based).
pub fn station(k: usize) -> u16 {
    0x1001 + k as u16
}

/// One datagram over the wire, answered.
pub fn one(w: &mut impl Wire, d: Datagram) -> Result<Datagram, MasterError> {
    let what = format!("command {} at 0x{:08X}", d.cmd, d.address);
    let mut f = emit(&[d], SRC);
    if !w.exchange(&mut f) {
        return Err(MasterError::NoAnswer(what));
    }
    parse(&f)
        .ok()
        .and_then(|mut d| (!d.is_empty()).then(|| d.remove(0)))
        .ok_or(MasterError::NoAnswer(what))
}

/// A register datagram `command` to `adp`/`ado`.
pub fn reg(
    w: &mut impl Wire,
    command: CommandCode,
    adp: u16,
    ado: u16,
    data: Vec<u8>,
) -> Result<Datagram, MasterError> {
    one(w, Datagram::new(command, adp, ado, data))
}

/// A register datagram that must come back with working counter `expected`.
pub fn expect(w: &mut impl Wire, d: Datagram, expected: u16) -> Result<Datagram, MasterError> {
    let what = format!("command {} at 0x{:08X}", d.cmd, d.address);
    let r = one(w, d)?;
    if r.wkc != expected {
        return Err(MasterError::WorkingCounter {
            what,
            wkc: r.wkc,
            expected,
        });
    }
    Ok(r)
}

/// FPWR that unit `k` must take.
pub fn fpwr(w: &mut impl Wire, k: usize, ado: u16, data: Vec<u8>) -> Result<(), MasterError> {
    expect(w, Datagram::new(cmd::FPWR, station(k), ado, data), 1).map(|_| ())
}

/// FPRD of `len` bytes at `ado` of unit `k`: data and working counter.
pub fn fprd(
    w: &mut impl Wire,
    k: usize,
    ado: u16,
    len: usize,
) -> Result<(Vec<u8>, u16), MasterError> {
    let r = reg(w, cmd::FPRD, station(k), ado, vec![0; len])?;
    Ok((r.data, r.wkc))
}

/// AL status and AL status code of unit `k`.
pub fn al(w: &mut impl Wire, k: usize) -> Result<(u16, u16), MasterError> {
    let (d, _) = fprd(w, k, 0x0130, 6)?;
    Ok((
        u16::from_le_bytes([d[0], d[1]]),
        u16::from_le_bytes([d[4], d[5]]),
    ))
}

/// Requests `state` (with the acknowledge bit 0x10 when given) from every unit by BWR of AL control;
/// the working counter.
pub fn request(w: &mut impl Wire, state: u8) -> Result<u16, MasterError> {
    Ok(reg(w, cmd::BWR, 0, 0x0120, vec![state, 0])?.wkc)
}

/// Station addresses, SyncManagers (the ESI's), FMMUs (see the module documentation).
pub fn configure(w: &mut impl Wire) -> Result<(), MasterError> {
    let n = w.units();
    for k in 0..n {
        let adp = 0u16.wrapping_sub(k as u16);
        let d = Datagram::new(cmd::APWR, adp, 0x0010, station(k).to_le_bytes().to_vec());
        expect(w, d, 1)?;
    }
    for k in 0..n {
        for (sm, start, len, control) in [
            (0u16, MBX_OUT, MBX_LEN as u16, 0x26u8),
            (1, MBX_IN, MBX_LEN as u16, 0x22),
            (2, 0x1100, 20, 0x64),
            (3, 0x1400, 20, 0x20),
        ] {
            let mut r = start.to_le_bytes().to_vec();
            r.extend_from_slice(&len.to_le_bytes());
            r.extend_from_slice(&[control, 0, 1, 0]);
            fpwr(w, k, 0x0800 + 8 * sm, r)?;
        }
        for (f, logical, phys, rw) in [
            (0u16, 20 * k as u32, 0x1100u16, 2u8),
            (1, 20 * (n + k) as u32, 0x1400, 1),
        ] {
            let mut r = logical.to_le_bytes().to_vec();
            r.extend_from_slice(&20u16.to_le_bytes());
            r.extend_from_slice(&[0, 7]);
            r.extend_from_slice(&phys.to_le_bytes());
            r.extend_from_slice(&[0, rw, 1, 0, 0, 0]);
            fpwr(w, k, 0x0600 + 16 * f, r)?;
        }
    }
    Ok(())
}

/// Configures the chain and brings every unit through Pre-Op to `to` (2, 4 or 8).
pub fn bring_up(w: &mut impl Wire, to: u8) -> Result<(), MasterError> {
    configure(w)?;
    for s in [2u8, 4, 8] {
        if s > to {
            break;
        }
        if s == 8 {
            // Outputs flow before Op is requested, as masters do.
            lrw(w, &vec![Outputs::default(); w.units()])?;
        }
        request(w, s)?;
        for k in 0..w.units() {
            let (status, code) = al(w, k)?;
            if (status, code) != (u16::from(s), 0) {
                return Err(MasterError::State {
                    unit: k,
                    state: s,
                    status,
                    code: AlStatusCode::from(code),
                });
            }
        }
    }
    Ok(())
}

/// The LRW datagram of every unit's outputs (and room for the inputs).
pub fn lrw_datagram(outputs: &[Outputs], units: usize) -> Datagram {
    let mut data: Vec<u8> = outputs.iter().flat_map(encode_outputs).collect();
    data.resize(2 * PROCESS_DATA_LEN * units, 0);
    Datagram {
        cmd: cmd::LRW,
        index: 0,
        address: 0,
        data,
        wkc: 0,
    }
}

/// One LRW of every unit's outputs and inputs, then a 1 ms cycle where the wire runs one: the
/// working counter and the inputs the frame brought back.
pub fn lrw(w: &mut impl Wire, outputs: &[Outputs]) -> Result<(u16, Vec<Inputs>), MasterError> {
    let n = w.units();
    let r = one(w, lrw_datagram(outputs, n))?;
    w.pass(Duration::from_millis(1));
    let inputs = (0..n)
        .map(|k| {
            let at = PROCESS_DATA_LEN * (n + k);
            let mut b = [0u8; PROCESS_DATA_LEN];
            b.copy_from_slice(&r.data[at..at + PROCESS_DATA_LEN]);
            decode_inputs(&b)
        })
        .collect();
    Ok((r.wkc, inputs))
}

/// One SyncManager as a master sets it: start address, length, control byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SmSetting {
    /// Physical start address.
    pub start: u16,
    /// Length in bytes.
    pub len: u16,
    /// Control byte.
    pub control: u8,
}

/// How a master sets up one unit of any device: its SyncManagers by number (the ESI's `Sm` elements,
/// the process-data ones with the lengths of the unit's process images), with the outputs FMMU on
/// the outputs SyncManager and the inputs FMMU on the inputs one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Layout {
    /// The SyncManagers by number; `None` for one left disabled.
    pub sms: Vec<Option<SmSetting>>,
    /// The numbers of the outputs and inputs SyncManagers.
    pub outputs: Option<usize>,
    /// The inputs SyncManager.
    pub inputs: Option<usize>,
}

impl Layout {
    /// The layout of `template`'s units with their power-on process images.
    pub fn of(template: &crate::generic::Template) -> Layout {
        let (o, i) = template.images();
        Layout::with_lengths(template, o.len() as u16, i.len() as u16)
    }

    /// The layout of `template`'s units with process images of `outputs` and `inputs` bytes.
    pub fn with_lengths(template: &crate::generic::Template, outputs: u16, inputs: u16) -> Layout {
        let ec = template.description().ethercat.clone().unwrap_or_default();
        let mut layout = Layout {
            sms: Vec::new(),
            outputs: None,
            inputs: None,
        };
        for (n, sm) in ec.sync_managers.iter().enumerate() {
            let len = match sm.kind.as_str() {
                "Outputs" => {
                    layout.outputs = Some(n);
                    outputs
                }
                "Inputs" => {
                    layout.inputs = Some(n);
                    inputs
                }
                _ => sm.default_size.unwrap_or(128),
            };
            layout.sms.push((len > 0).then_some(SmSetting {
                start: sm.start_address,
                len,
                control: sm.control_byte,
            }));
        }
        layout
    }

    /// The output and input lengths.
    pub fn lengths(&self) -> (usize, usize) {
        let len = |n: Option<usize>| {
            n.and_then(|n| self.sms.get(n).copied().flatten())
                .map_or(0, |s| usize::from(s.len))
        };
        (len(self.outputs), len(self.inputs))
    }

    /// The mailbox SyncManagers (SM0, SM1), when the unit has them.
    pub fn mailbox(&self) -> Option<(SmSetting, SmSetting)> {
        match (self.sms.first(), self.sms.get(1)) {
            (Some(Some(a)), Some(Some(b))) if SmControl(a.control).is_mailbox() => Some((*a, *b)),
            _ => None,
        }
    }
}

/// Where unit `k`'s outputs and inputs are in the logical image of `layouts`: every unit's outputs
/// one after the other from 0, then every unit's inputs.
pub fn logical(layouts: &[Layout], k: usize) -> (u32, u32) {
    offsets(layouts)[k]
}

/// Where every unit's outputs and inputs are in the logical image of `layouts` (see [`logical`]).
pub fn offsets(layouts: &[Layout]) -> Vec<(u32, u32)> {
    let outputs: usize = layouts.iter().map(|l| l.lengths().0).sum();
    let (mut o, mut i) = (0usize, outputs);
    layouts
        .iter()
        .map(|l| {
            let at = (o as u32, i as u32);
            let (lo, li) = l.lengths();
            o += lo;
            i += li;
            at
        })
        .collect()
}

/// Station addresses, every unit's SyncManagers as its layout says, and its FMMUs (see
/// [`logical`]).
pub fn configure_layouts(w: &mut impl Wire, layouts: &[Layout]) -> Result<(), MasterError> {
    for k in 0..layouts.len() {
        let adp = 0u16.wrapping_sub(k as u16);
        let d = Datagram::new(cmd::APWR, adp, 0x0010, station(k).to_le_bytes().to_vec());
        expect(w, d, 1)?;
    }
    let at = offsets(layouts);
    for (k, layout) in layouts.iter().enumerate() {
        for (n, sm) in layout.sms.iter().enumerate() {
            let Some(sm) = sm else { continue };
            let mut r = sm.start.to_le_bytes().to_vec();
            r.extend_from_slice(&sm.len.to_le_bytes());
            r.extend_from_slice(&[sm.control, 0, 1, 0]);
            fpwr(w, k, 0x0800 + 8 * n as u16, r)?;
        }
        let (out_at, in_at) = at[k];
        let (out_len, in_len) = layout.lengths();
        let fmmus = [
            (layout.outputs, out_at, out_len, 2u8),
            (layout.inputs, in_at, in_len, 1),
        ];
        // FMMUs from 0 in the order they are used, as SOEM takes them: a unit with inputs only
        // (and one FMMU) maps them with FMMU 0.
        let mut f = 0;
        for (sm, at, len, rw) in fmmus {
            let Some(sm) = sm.and_then(|n| layout.sms[n]).filter(|_| len > 0) else {
                continue;
            };
            let mut r = at.to_le_bytes().to_vec();
            r.extend_from_slice(&(len as u16).to_le_bytes());
            r.extend_from_slice(&[0, 7]);
            r.extend_from_slice(&sm.start.to_le_bytes());
            r.extend_from_slice(&[0, rw, 1, 0, 0, 0]);
            fpwr(w, k, 0x0600 + 16 * f, r)?;
            f += 1;
        }
    }
    Ok(())
}

/// The working counter an LRW of `layouts` comes back with when every unit is in Op: per unit 1
/// for its inputs read and 2 for its outputs written (ETG.1000.4 §5.4.3).
pub fn lrw_wkc(layouts: &[Layout]) -> u16 {
    layouts
        .iter()
        .map(|l| {
            let (o, i) = l.lengths();
            2 * u16::from(o > 0) + u16::from(i > 0)
        })
        .sum()
}

/// One LRW of every unit's outputs (each as long as its layout says) and inputs, then a 1 ms
/// cycle where the wire runs one: the working counter and each unit's inputs.
pub fn lrw_layouts(
    w: &mut impl Wire,
    layouts: &[Layout],
    outputs: &[Vec<u8>],
) -> Result<(u16, Vec<Vec<u8>>), MasterError> {
    let total: usize = layouts.iter().map(|l| l.lengths().0 + l.lengths().1).sum();
    let mut data = vec![0u8; total];
    let offsets = offsets(layouts);
    for (k, (layout, out)) in layouts.iter().zip(outputs).enumerate() {
        let (at, _) = offsets[k];
        let n = layout.lengths().0.min(out.len());
        data[at as usize..at as usize + n].copy_from_slice(&out[..n]);
    }
    let r = one(
        w,
        Datagram {
            cmd: cmd::LRW,
            index: 0,
            address: 0,
            data,
            wkc: 0,
        },
    )?;
    w.pass(Duration::from_millis(1));
    let inputs = (0..layouts.len())
        .map(|k| {
            let (_, at) = offsets[k];
            let n = layouts[k].lengths().1;
            r.data[at as usize..at as usize + n].to_vec()
        })
        .collect();
    Ok((r.wkc, inputs))
}
