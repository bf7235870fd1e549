//! `drive NODE …`: a CiA 402 drive moved by SDO, on a CAN bus or an EtherCAT chain alike — its
//! state and values, the state machine's commands, homing, a move to a position, a jog. Each command
//! writes the controlword and waits, with a bound, for the statusword to say the drive did it; a
//! drive that does not says where it stayed and, in Fault, its error code 0x603F in words.
//!
//! On EtherCAT the chain runs in Op for the duration of the command (the controlword and the other
//! entries the drive maps in its RxPDOs go by process data) and is back in Init after it, as a
//! session of `sdo-tool --ethercat` leaves it; what a drive does when its master leaves Op is its
//! own (commonly a fault reaction, or disable).
//!
//! The objects (CiA 402-2, axis `a` at 0x800·a above each): 0x6040 controlword, 0x6041 statusword,
//! 0x603F error code, 0x6060/0x6061 modes of operation (display), 0x6064 position actual, 0x606C
//! velocity actual, 0x607A target position, 0x6081 profile velocity, 0x6083/0x6084 profile
//! acceleration and deceleration, 0x6098 homing method, 0x60FF target velocity.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use od::dict::Address;

use super::emit;
use crate::{SdoAccess, ToolError};

/// `drive`'s arguments.
#[derive(Debug, clap::Args)]
pub struct DriveArgs {
    /// The node: its node-ID on CAN, its position in the chain on EtherCAT.
    pub node: u8,
    /// The axis of a multi-axis device (its objects 0x800 above the first axis').
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u8).range(0..=7))]
    pub axis: u8,
    /// How long a command waits for the drive (ms); homing and moves wait this long for the
    /// target, the state machine's commands for each step.
    #[arg(long = "wait-ms", value_name = "MS", default_value_t = 10_000)]
    pub wait_ms: u64,
    /// What to do.
    #[command(subcommand)]
    pub command: DriveCmd,
}

/// The `drive` commands.
#[derive(Debug, clap::Subcommand)]
pub enum DriveCmd {
    /// The state, the mode, position and velocity, and the statusword's bits by name.
    Status {
        /// Again every 200 ms until Ctrl-C.
        #[arg(long)]
        watch: bool,
    },
    /// To OPERATION ENABLED, through the states before it (a fault reset first, in FAULT).
    Enable,
    /// To SWITCH ON DISABLED (disable voltage).
    Disable,
    /// Clears a fault (controlword bit 7 rising): to SWITCH ON DISABLED.
    FaultReset,
    /// Quick stop (controlword 0x0002): the drive brakes as its quick stop option code says.
    QuickStop,
    /// Homing (mode 6) with METHOD (0x6098), or the method the drive has; enables the drive first.
    Home {
        /// The homing method (CiA 402-2, e.g. 35 or 37: the current position).
        method: Option<i8>,
    },
    /// A profile position move (mode 1) to POS, or by POS with --relative; enables the drive first
    /// and waits for target reached.
    Move {
        /// The target position, in the drive's position units.
        #[arg(allow_hyphen_values = true)]
        position: i32,
        /// POS is relative to the present target.
        #[arg(long)]
        relative: bool,
        /// The profile velocity (0x6081).
        #[arg(long)]
        velocity: Option<u32>,
        /// The profile acceleration and deceleration (0x6083, 0x6084).
        #[arg(long)]
        acceleration: Option<u32>,
    },
    /// Profile velocity (mode 3) at V (0x60FF) until `stop`; enables the drive first.
    Jog {
        /// The target velocity, in the drive's velocity units.
        #[arg(allow_hyphen_values = true)]
        velocity: i32,
    },
    /// Halt (controlword bit 8): the drive stops in its mode and stays enabled.
    Stop,
}

/// The states of CiA 402-2 §8.1, as a master reads them from the statusword.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum State {
    /// xxxx xxxx x0xx 0000.
    NotReadyToSwitchOn,
    /// xxxx xxxx x1xx 0000.
    SwitchOnDisabled,
    /// xxxx xxxx x01x 0001.
    ReadyToSwitchOn,
    /// xxxx xxxx x01x 0011.
    SwitchedOn,
    /// xxxx xxxx x01x 0111.
    OperationEnabled,
    /// xxxx xxxx x00x 0111.
    QuickStopActive,
    /// xxxx xxxx x0xx 1111.
    FaultReactionActive,
    /// xxxx xxxx x0xx 1000.
    Fault,
}

impl State {
    /// The state a statusword says (bits 0–3, 5 and 6).
    pub fn of(status: u16) -> State {
        match (status & 0x4F, status & 0x6F) {
            (_, 0x21) => State::ReadyToSwitchOn,
            (_, 0x23) => State::SwitchedOn,
            (_, 0x27) => State::OperationEnabled,
            (_, 0x07) => State::QuickStopActive,
            (0x40, _) => State::SwitchOnDisabled,
            (0x0F, _) => State::FaultReactionActive,
            (0x08, _) => State::Fault,
            _ => State::NotReadyToSwitchOn,
        }
    }

    /// Its name as CiA 402-2 writes it.
    pub fn name(self) -> &'static str {
        match self {
            State::NotReadyToSwitchOn => "NOT READY TO SWITCH ON",
            State::SwitchOnDisabled => "SWITCH ON DISABLED",
            State::ReadyToSwitchOn => "READY TO SWITCH ON",
            State::SwitchedOn => "SWITCHED ON",
            State::OperationEnabled => "OPERATION ENABLED",
            State::QuickStopActive => "QUICK STOP ACTIVE",
            State::FaultReactionActive => "FAULT REACTION ACTIVE",
            State::Fault => "FAULT",
        }
    }
}

/// The statusword's bits by name; bits 12 and 13 by the mode (`mode`, 0x6061).
pub fn bit_names(status: u16, mode: i8) -> Vec<&'static str> {
    let (b12, b13) = match mode {
        1 => ("set-point acknowledge", "following error"),
        3 => ("speed is zero", "max slippage error"),
        6 => ("homing attained", "homing error"),
        8..=10 => ("target value ignored", "following error"),
        _ => (
            "operation mode specific (12)",
            "operation mode specific (13)",
        ),
    };
    let names = [
        "ready to switch on",
        "switched on",
        "operation enabled",
        "fault",
        "voltage enabled",
        "quick stop",
        "switch on disabled",
        "warning",
        "manufacturer specific (8)",
        "remote",
        "target reached",
        "internal limit active",
        b12,
        b13,
        "manufacturer specific (14)",
        "manufacturer specific (15)",
    ];
    (0..16)
        .filter(|b| status & (1 << b) != 0)
        .map(|b| names[b])
        .collect()
}

/// The name of a mode of operation (CiA 402-2 0x6060).
pub fn mode_name(mode: i8) -> &'static str {
    match mode {
        0 => "no mode",
        1 => "profile position",
        2 => "velocity",
        3 => "profile velocity",
        4 => "profile torque",
        6 => "homing",
        7 => "interpolated position",
        8 => "cyclic synchronous position",
        9 => "cyclic synchronous velocity",
        10 => "cyclic synchronous torque",
        m if m < 0 => "manufacturer specific",
        _ => "reserved",
    }
}

/// What an error code 0x603F means: CiA 402-2's drive codes, else CiA 301's classes.
pub fn error_meaning(code: u16) -> &'static str {
    match code {
        0x2310 => "continuous over current",
        0x3210 => "DC link over-voltage",
        0x3220 => "DC link under-voltage",
        0x4210 => "excess temperature device",
        0x5441 => "drive disabled by input",
        0x7121 => "motor blocked",
        0x7305 => "incremental sensor 1 fault",
        0x8400 => "velocity speed controller",
        0x8500 => "position controller",
        0x8611 => "following error",
        0x8612 => "reference limit",
        0xFF00..=0xFFFF => "manufacturer specific",
        c => od::emcy::EmcyCode(c).meaning(),
    }
}

/// The drive of one node and axis, read and written by SDO.
struct Drive<'a> {
    sdo: &'a mut dyn SdoAccess,
    node: u8,
    base: u16,
    wait: Duration,
}

/// What `status` shows.
struct Snapshot {
    status: u16,
    mode: i8,
    position: Option<i32>,
    velocity: Option<i32>,
    error: Option<u16>,
}

impl Drive<'_> {
    fn at(&self, index: u16, sub: u8) -> Address {
        Address::new(index + self.base, sub)
    }

    fn read<const N: usize>(&mut self, index: u16) -> Result<[u8; N], ToolError> {
        let addr = self.at(index, 0);
        let bytes = self.sdo.read_bytes(self.node, addr)?;
        bytes
            .get(..N)
            .and_then(|b| b.try_into().ok())
            .ok_or_else(|| {
                ToolError::Drive(format!(
                    "drive {}: 0x{:04X} gave {} bytes, not {N}",
                    self.node,
                    addr.index,
                    bytes.len()
                ))
            })
    }

    fn status(&mut self) -> Result<u16, ToolError> {
        Ok(u16::from_le_bytes(self.read(0x6041)?))
    }

    fn write(&mut self, index: u16, data: &[u8]) -> Result<(), ToolError> {
        let addr = self.at(index, 0);
        self.sdo.write_bytes(self.node, addr, data)
    }

    fn control(&mut self, word: u16) -> Result<(), ToolError> {
        self.write(0x6040, &word.to_le_bytes())
    }

    fn snapshot(&mut self) -> Result<Snapshot, ToolError> {
        let status = self.status()?;
        let mode = self.read::<1>(0x6061).map_or(0, |b| b[0] as i8);
        let position = self.read(0x6064).ok().map(i32::from_le_bytes);
        let velocity = self.read(0x606C).ok().map(i32::from_le_bytes);
        let error = self.read(0x603F).ok().map(u16::from_le_bytes);
        Ok(Snapshot {
            status,
            mode,
            position,
            velocity,
            error,
        })
    }

    /// Polls the statusword until `done` holds for it, for the bound; then why not, in words. A
    /// drive that falls into FAULT meanwhile ends the wait (once its fault reaction is over).
    fn wait_for(
        &mut self,
        what: &str,
        done: impl Fn(u16) -> bool,
        bound: Duration,
    ) -> Result<u16, ToolError> {
        let end = Instant::now() + bound;
        loop {
            let s = self.status()?;
            if done(s) {
                return Ok(s);
            }
            if State::of(s) == State::Fault {
                return Err(self.refusal(what, s, None));
            }
            if Instant::now() >= end {
                return Err(self.refusal(what, s, Some(bound)));
            }
            self.sdo.idle(Duration::from_millis(10))?;
        }
    }

    /// The drive did not do `what` (within `bound`, or it fell into FAULT): where it stayed, and
    /// its fault.
    fn refusal(&mut self, what: &str, status: u16, bound: Option<Duration>) -> ToolError {
        let state = State::of(status);
        let how = match bound {
            Some(b) => format!("not done within {} ms", b.as_millis()),
            None => "not done".to_string(),
        };
        let mut message = format!(
            "drive {}: {what} {how}: {} (statusword 0x{status:04X})",
            self.node,
            state.name()
        );
        if matches!(state, State::Fault | State::FaultReactionActive) {
            if let Ok(b) = self.read(0x603F) {
                let code = u16::from_le_bytes(b);
                message.push_str(&format!(
                    ", error code 0x603F = 0x{code:04X} ({})",
                    error_meaning(code)
                ));
            }
        } else if status & (1 << 9) == 0 {
            message.push_str(", remote (bit 9) clear: the drive takes no commands from the bus");
        }
        ToolError::Drive(message)
    }

    /// One command of the state machine, and the wait for the state it leads to.
    fn step(&mut self, word: u16, name: &str, to: State) -> Result<(), ToolError> {
        self.control(word)?;
        let what = format!("controlword 0x{word:04X} ({name}) to {}", to.name());
        self.wait_for(&what, |s| State::of(s) == to, self.wait)?;
        Ok(())
    }

    fn fault_reset(&mut self) -> Result<(), ToolError> {
        self.control(0x0000)?;
        self.control(0x0080)?;
        let end = Instant::now() + self.wait;
        loop {
            let s = self.status()?;
            if !matches!(State::of(s), State::Fault | State::FaultReactionActive) {
                break;
            }
            if Instant::now() >= end {
                let what = "fault reset (controlword bit 7 rising)";
                return Err(self.refusal(what, s, Some(self.wait)));
            }
            self.sdo.idle(Duration::from_millis(10))?;
        }
        self.control(0x0000)
    }

    /// To OPERATION ENABLED from wherever it is.
    fn enable(&mut self) -> Result<(), ToolError> {
        for _ in 0..6 {
            let state = State::of(self.status()?);
            match state {
                State::OperationEnabled => return Ok(()),
                State::Fault | State::FaultReactionActive => self.fault_reset()?,
                State::NotReadyToSwitchOn => {
                    let what = "leaving NOT READY TO SWITCH ON";
                    self.wait_for(
                        what,
                        |s| State::of(s) != State::NotReadyToSwitchOn,
                        self.wait,
                    )?;
                }
                State::SwitchOnDisabled | State::QuickStopActive => {
                    self.step(0x0006, "shutdown", State::ReadyToSwitchOn)?
                }
                State::ReadyToSwitchOn => self.step(0x0007, "switch on", State::SwitchedOn)?,
                State::SwitchedOn => {
                    self.step(0x000F, "enable operation", State::OperationEnabled)?
                }
            }
        }
        let s = self.status()?;
        Err(self.refusal("enable", s, Some(self.wait)))
    }

    /// Sets the mode of operation and waits for its display.
    fn mode(&mut self, mode: i8) -> Result<(), ToolError> {
        self.write(0x6060, &mode.to_le_bytes())?;
        let end = Instant::now() + self.wait;
        loop {
            let shown = self.read::<1>(0x6061)?[0] as i8;
            if shown == mode {
                return Ok(());
            }
            if Instant::now() >= end {
                return Err(ToolError::Drive(format!(
                    "drive {}: mode {mode} ({}) written to 0x6060, 0x6061 still shows {shown} \
                     ({}) after {} ms",
                    self.node,
                    mode_name(mode),
                    mode_name(shown),
                    self.wait.as_millis()
                )));
            }
            self.sdo.idle(Duration::from_millis(10))?;
        }
    }

    fn home(&mut self, method: Option<i8>) -> Result<(), ToolError> {
        self.enable()?;
        if let Some(m) = method {
            self.write(0x6098, &m.to_le_bytes())?;
        }
        self.mode(6)?;
        self.control(0x000F)?;
        self.control(0x001F)?;
        let s = self.wait_for(
            "homing (homing attained, bit 12, or homing error, bit 13)",
            |s| s & (1 << 13) != 0 || (s & (1 << 12) != 0 && s & (1 << 10) != 0),
            self.wait,
        )?;
        self.control(0x000F)?;
        if s & (1 << 13) != 0 {
            return Err(ToolError::Drive(format!(
                "drive {}: homing error (statusword 0x{s:04X} bit 13)",
                self.node
            )));
        }
        Ok(())
    }

    fn move_to(
        &mut self,
        position: i32,
        relative: bool,
        velocity: Option<u32>,
        acceleration: Option<u32>,
    ) -> Result<(), ToolError> {
        self.enable()?;
        self.mode(1)?;
        if let Some(v) = velocity {
            self.write(0x6081, &v.to_le_bytes())?;
        }
        if let Some(a) = acceleration {
            self.write(0x6083, &a.to_le_bytes())?;
            self.write(0x6084, &a.to_le_bytes())?;
        }
        self.write(0x607A, &position.to_le_bytes())?;
        // Bit 4 new set-point, bit 5 change set immediately, bit 6 relative.
        let base = 0x000F | if relative { 0x0040 } else { 0 };
        self.control(base)?;
        self.control(base | 0x0030)?;
        self.wait_for(
            "the new set-point (set-point acknowledge, bit 12)",
            |s| s & (1 << 12) != 0,
            self.wait,
        )?;
        self.control(base)?;
        self.wait_for(
            "the move (target reached, bit 10)",
            |s| s & (1 << 10) != 0 && s & (1 << 12) == 0,
            self.wait,
        )?;
        Ok(())
    }

    fn jog(&mut self, velocity: i32) -> Result<(), ToolError> {
        self.enable()?;
        self.mode(3)?;
        self.write(0x60FF, &velocity.to_le_bytes())?;
        self.control(0x000F)
    }

    fn stop(&mut self) -> Result<(), ToolError> {
        let status = self.status()?;
        if State::of(status) != State::OperationEnabled {
            return Ok(());
        }
        self.control(0x010F)?;
        self.wait_for(
            "halt (target reached, bit 10)",
            |s| s & (1 << 10) != 0,
            self.wait,
        )?;
        Ok(())
    }
}

/// Runs `drive` on `sdo` (a CAN bus or an EtherCAT chain).
pub fn run(
    args: &DriveArgs,
    sdo: &mut dyn SdoAccess,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    sdo.check_node(args.node)?;
    let mut d = Drive {
        sdo,
        node: args.node,
        base: 0x800 * u16::from(args.axis),
        wait: Duration::from_millis(args.wait_ms.max(1)),
    };
    match &args.command {
        DriveCmd::Status { watch } => return status(&mut d, *watch, json, out),
        DriveCmd::Enable => d.enable()?,
        DriveCmd::Disable => d.step(0x0000, "disable voltage", State::SwitchOnDisabled)?,
        DriveCmd::FaultReset => d.fault_reset()?,
        DriveCmd::QuickStop => {
            d.control(0x0002)?;
            d.wait_for(
                "quick stop",
                |s| {
                    matches!(
                        State::of(s),
                        State::QuickStopActive | State::SwitchOnDisabled
                    )
                },
                d.wait,
            )?;
        }
        DriveCmd::Home { method } => d.home(*method)?,
        DriveCmd::Move {
            position,
            relative,
            velocity,
            acceleration,
        } => d.move_to(*position, *relative, *velocity, *acceleration)?,
        DriveCmd::Jog { velocity } => d.jog(*velocity)?,
        DriveCmd::Stop => d.stop()?,
    }
    show(&mut d, json, out)
}

fn status(d: &mut Drive, watch: bool, json: bool, out: &mut dyn Write) -> Result<(), ToolError> {
    if !watch {
        return show(d, json, out);
    }
    let stop = Arc::new(AtomicBool::new(false));
    let s = Arc::clone(&stop);
    let _ = ctrlc::set_handler(move || s.store(true, Ordering::Relaxed));
    while !stop.load(Ordering::Relaxed) {
        show(d, json, out)?;
        d.sdo.idle(Duration::from_millis(200))?;
    }
    Ok(())
}

/// One line of the drive's state: `node 2: OPERATION ENABLED, profile position (1), position 1000,
/// velocity 0; statusword 0x1637: …`.
fn show(d: &mut Drive, json: bool, out: &mut dyn Write) -> Result<(), ToolError> {
    let s = d.snapshot()?;
    let state = State::of(s.status);
    let bits = bit_names(s.status, s.mode);
    let num = |v: Option<i32>| v.map_or("-".to_string(), |v| v.to_string());
    let mut text = format!(
        "node {}: {}, {} ({}), position {}, velocity {}; statusword 0x{:04X}: {}",
        d.node,
        state.name(),
        mode_name(s.mode),
        s.mode,
        num(s.position),
        num(s.velocity),
        s.status,
        bits.join(", ")
    );
    let fault = matches!(state, State::Fault | State::FaultReactionActive);
    if let Some(code) = s.error.filter(|&c| c != 0 || fault) {
        text.push_str(&format!(
            "; error code 0x{code:04X} ({})",
            error_meaning(code)
        ));
    }
    let value = serde_json::json!({
        "node": d.node,
        "state": state.name(),
        "statusword": format!("0x{:04X}", s.status),
        "bits": bits,
        "mode": s.mode,
        "mode_name": mode_name(s.mode),
        "position": s.position,
        "velocity": s.velocity,
        "error_code": s.error.map(|c| format!("0x{c:04X}")),
    });
    emit(out, json, text, value)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CiA 402-2 §8.1.1 table of the statusword's state bits.
    #[test]
    fn states_from_statuswords() {
        let cases = [
            (0x0000, State::NotReadyToSwitchOn),
            (0x0020, State::NotReadyToSwitchOn),
            (0x0040, State::SwitchOnDisabled),
            (0x0060, State::SwitchOnDisabled),
            (0x0021, State::ReadyToSwitchOn),
            (0x0031, State::ReadyToSwitchOn),
            (0x0023, State::SwitchedOn),
            (0x0233, State::SwitchedOn),
            (0x0027, State::OperationEnabled),
            (0x1637, State::OperationEnabled),
            (0x0007, State::QuickStopActive),
            (0x0017, State::QuickStopActive),
            (0x000F, State::FaultReactionActive),
            (0x002F, State::FaultReactionActive),
            (0x0008, State::Fault),
            (0x0218, State::Fault),
        ];
        for (word, state) in cases {
            assert_eq!(State::of(word), state, "0x{word:04X}");
        }
    }

    #[test]
    fn bits_by_name_with_the_mode_s_own() {
        assert_eq!(
            bit_names(0x1637, 1),
            [
                "ready to switch on",
                "switched on",
                "operation enabled",
                "voltage enabled",
                "quick stop",
                "remote",
                "target reached",
                "set-point acknowledge"
            ]
        );
        assert_eq!(bit_names(0x3000, 6), ["homing attained", "homing error"]);
        assert_eq!(error_meaning(0x8611), "following error");
        assert_eq!(error_meaning(0x8130), "life guard error or heartbeat error");
    }

    /// A drive as CiA 402-2 describes it, behind the SDO calls: the statusword follows the
    /// controlword's commands; the mode display follows 0x6060 after `lag` reads; homing (mode 6)
    /// ends `homing` (attained 0x1400, or 0x2000 an error) at the start; a profile position
    /// set-point is acknowledged (bit 12) while bit 4 is set and reached (bit 10) after.
    struct Fake {
        base: u16,
        status: u16,
        mode: i8,
        shown: i8,
        lag: u32,
        homing: u16,
        error: u16,
        /// Reads of 0x6041 in FAULT before a fault reset clears it.
        fault_reads: u32,
        /// Reads of 0x6041 that say NOT READY TO SWITCH ON first.
        not_ready_reads: u32,
        /// The statusword changes no more (after this many controlwords, when `frozen_after`).
        frozen: bool,
        frozen_after: Option<usize>,
        /// A fault reset was asked for (bit 7).
        reset: bool,
        /// The set-point acknowledge (bit 12) stays when bit 4 is cleared.
        ack_sticks: bool,
        writes: Vec<(u16, Vec<u8>)>,
    }

    impl Fake {
        fn new(status: u16) -> Fake {
            Fake {
                base: 0,
                status,
                mode: 0,
                shown: 0,
                lag: 0,
                homing: 0x1400,
                error: 0,
                fault_reads: 0,
                not_ready_reads: 0,
                frozen: false,
                frozen_after: None,
                reset: false,
                ack_sticks: false,
                writes: Vec::new(),
            }
        }

        fn controlwords(&self) -> Vec<u16> {
            self.writes
                .iter()
                .filter(|(i, _)| *i == 0x6040 + self.base)
                .map(|(_, d)| u16::from_le_bytes([d[0], d[1]]))
                .collect()
        }
    }

    impl SdoAccess for Fake {
        fn check_node(&self, _node: u8) -> Result<(), ToolError> {
            Ok(())
        }

        fn read_bytes(&mut self, _node: u8, addr: Address) -> Result<Vec<u8>, ToolError> {
            let index = addr.index.saturating_sub(self.base);
            Ok(match index {
                0x6041 => {
                    if self.not_ready_reads > 0 {
                        self.not_ready_reads -= 1;
                        return Ok(0x0200u16.to_le_bytes().to_vec());
                    }
                    if State::of(self.status) == State::Fault && self.reset {
                        match self.fault_reads {
                            0 => self.status = 0x0240 | (self.status & 0x0200),
                            _ => self.fault_reads -= 1,
                        }
                    }
                    self.status.to_le_bytes().to_vec()
                }
                0x6061 => {
                    if self.lag > 0 {
                        self.lag -= 1;
                    } else {
                        self.shown = self.mode;
                    }
                    vec![self.shown as u8]
                }
                0x603F => self.error.to_le_bytes().to_vec(),
                _ => vec![0; 4],
            })
        }

        fn write_bytes(&mut self, _node: u8, addr: Address, data: &[u8]) -> Result<(), ToolError> {
            self.writes.push((addr.index, data.to_vec()));
            let index = addr.index.saturating_sub(self.base);
            if index == 0x6060 {
                self.mode = data[0] as i8;
            }
            if index != 0x6040 {
                return Ok(());
            }
            let cw = u16::from_le_bytes([data[0], data[1]]);
            let count = self.controlwords().len();
            if self.frozen || self.frozen_after.is_some_and(|n| count > n) {
                return Ok(());
            }
            let state = State::of(self.status);
            let remote = self.status & 0x0200;
            self.status = match (state, cw) {
                (State::Fault, c) => {
                    self.reset |= c & 0x80 != 0;
                    self.status
                }
                (_, 0x0000) => 0x0240,
                (_, 0x0002) => 0x0217,
                (_, 0x0006) => 0x0221,
                (State::ReadyToSwitchOn, 0x0007) => 0x0233,
                (State::SwitchedOn | State::OperationEnabled, c) if c & 0x0F == 0x0F => {
                    let mut s = 0x0237;
                    if self.mode == 6 && c & 0x10 != 0 {
                        s |= self.homing;
                    }
                    if self.mode == 1 && c & 0x10 != 0 {
                        s |= 0x1000;
                    } else if self.mode == 1 {
                        s |= 0x0400 | (self.status & 0x1000 & if self.ack_sticks { !0 } else { 0 });
                    }
                    if c & 0x0100 != 0 {
                        s |= 0x0400;
                    }
                    s
                }
                _ => self.status,
            } & !0x0200
                | remote;
            Ok(())
        }

        fn idle(&mut self, _d: Duration) -> Result<(), ToolError> {
            Ok(())
        }
    }

    fn drive(fake: &mut Fake, axis: u8, wait_ms: u64) -> Drive<'_> {
        fake.base = 0x800 * u16::from(axis);
        Drive {
            sdo: fake,
            node: 5,
            base: 0x800 * u16::from(axis),
            wait: Duration::from_millis(wait_ms),
        }
    }

    #[test]
    fn enable_goes_through_each_state_of_cia_402_on_the_axis_asked() {
        // Not ready to switch on for two reads, then switch on disabled by itself.
        let mut fake = Fake::new(0x0240);
        fake.not_ready_reads = 2;
        drive(&mut fake, 1, 1000).enable().unwrap();
        assert_eq!(fake.controlwords(), [0x0006, 0x0007, 0x000F]);
        assert!(fake.writes.iter().all(|(i, _)| *i == 0x6840));
        assert_eq!(fake.status, 0x0237);
        // Never leaving it: refused with where it stayed.
        let mut fake = Fake::new(0x0240);
        fake.not_ready_reads = u32::MAX;
        let e = drive(&mut fake, 0, 30).enable().unwrap_err().to_string();
        assert_eq!(
            e,
            "drive 5: leaving NOT READY TO SWITCH ON not done within 30 ms: NOT READY TO SWITCH \
             ON (statusword 0x0200)"
        );
    }

    #[test]
    fn a_fault_is_reset_first_and_a_refusal_names_the_state_and_the_remote_bit() {
        // In FAULT for three more reads after the reset: waited for, then enabled.
        let mut fake = Fake::new(0x0208);
        fake.fault_reads = 3;
        drive(&mut fake, 0, 1000).enable().unwrap();
        assert_eq!(
            fake.controlwords(),
            [0x0000, 0x0080, 0x0000, 0x0006, 0x0007, 0x000F]
        );
        // A fault that stays: the reset is refused with the error code in words.
        let mut fake = Fake::new(0x0208);
        fake.fault_reads = u32::MAX;
        fake.error = 0x7121;
        let e = drive(&mut fake, 0, 30)
            .fault_reset()
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "drive 5: fault reset (controlword bit 7 rising) not done within 30 ms: FAULT \
             (statusword 0x0208), error code 0x603F = 0x7121 (motor blocked)"
        );
        // Remote clear: the drive takes nothing from the bus, and says so.
        let mut fake = Fake::new(0x0040);
        fake.frozen = true;
        let e = drive(&mut fake, 0, 30).enable().unwrap_err().to_string();
        assert_eq!(
            e,
            "drive 5: controlword 0x0006 (shutdown) to READY TO SWITCH ON not done within 30 ms: \
             SWITCH ON DISABLED (statusword 0x0040), remote (bit 9) clear: the drive takes no \
             commands from the bus"
        );
        // Remote set: no such words.
        let mut fake = Fake::new(0x0240);
        fake.frozen = true;
        let e = drive(&mut fake, 0, 30).enable().unwrap_err().to_string();
        assert!(e.ends_with("SWITCH ON DISABLED (statusword 0x0240)"), "{e}");
    }

    #[test]
    fn the_mode_is_waited_for_on_its_display() {
        let mut fake = Fake::new(0x0237);
        fake.lag = 3;
        drive(&mut fake, 0, 1000).mode(3).unwrap();
        assert_eq!(fake.shown, 3);
        let mut fake = Fake::new(0x0237);
        fake.lag = u32::MAX;
        let e = drive(&mut fake, 0, 30).mode(1).unwrap_err().to_string();
        assert_eq!(
            e,
            "drive 5: mode 1 (profile position) written to 0x6060, 0x6061 still shows 0 (no \
             mode) after 30 ms"
        );
    }

    #[test]
    fn homing_ends_at_attained_or_with_its_error() {
        let mut fake = Fake::new(0x0237);
        drive(&mut fake, 0, 1000).home(Some(35)).unwrap();
        assert_eq!(fake.controlwords(), [0x000F, 0x001F, 0x000F]);
        assert!(fake.writes.contains(&(0x6098, vec![35])));
        assert!(fake.writes.contains(&(0x6060, vec![6])));
        // Attained without target reached is not the end; an error (bit 13) is.
        let mut fake = Fake::new(0x0237);
        fake.homing = 0x1000;
        assert!(drive(&mut fake, 0, 30).home(None).is_err());
        // Target reached without attained is not the end either.
        let mut fake = Fake::new(0x0237);
        fake.homing = 0x0400;
        assert!(drive(&mut fake, 0, 30).home(None).is_err());
        let mut fake = Fake::new(0x0237);
        fake.homing = 0x2000;
        let e = drive(&mut fake, 0, 1000)
            .home(None)
            .unwrap_err()
            .to_string();
        assert_eq!(e, "drive 5: homing error (statusword 0x2237 bit 13)");
    }

    #[test]
    fn a_move_sends_its_set_point_and_waits_for_its_acknowledge_and_target() {
        let mut fake = Fake::new(0x0237);
        drive(&mut fake, 0, 1000)
            .move_to(-500, true, Some(2000), Some(8000))
            .unwrap();
        // Relative (bit 6): 0x004F, then new set-point and change at once (bits 4, 5): 0x007F.
        assert_eq!(fake.controlwords(), [0x004F, 0x007F, 0x004F]);
        let values: Vec<(u16, Vec<u8>)> = fake
            .writes
            .iter()
            .filter(|(i, _)| *i != 0x6040)
            .cloned()
            .collect();
        assert_eq!(
            values,
            [
                (0x6060, vec![1]),
                (0x6081, 2000u32.to_le_bytes().to_vec()),
                (0x6083, 8000u32.to_le_bytes().to_vec()),
                (0x6084, 8000u32.to_le_bytes().to_vec()),
                (0x607A, (-500i32).to_le_bytes().to_vec()),
            ]
        );
        // Target reached while the acknowledge of the set-point is still up is not the end.
        let mut fake = Fake::new(0x0237);
        fake.ack_sticks = true;
        let e = drive(&mut fake, 0, 30)
            .move_to(10, false, None, None)
            .unwrap_err();
        assert!(
            e.to_string()
                .starts_with("drive 5: the move (target reached, bit 10) not done"),
            "{e}"
        );
        // Never acknowledged: refused.
        let mut fake = Fake::new(0x0237);
        fake.frozen_after = Some(1);
        let e = drive(&mut fake, 0, 30)
            .move_to(10, false, None, None)
            .unwrap_err();
        assert!(
            e.to_string()
                .starts_with("drive 5: the new set-point (set-point acknowledge, bit 12) not done"),
            "{e}"
        );
    }

    #[test]
    fn stop_halts_and_waits_for_target_reached() {
        let mut fake = Fake::new(0x0237);
        drive(&mut fake, 0, 1000).stop().unwrap();
        assert_eq!(fake.controlwords(), [0x010F]);
        // Not enabled: nothing to stop.
        let mut fake = Fake::new(0x0240);
        drive(&mut fake, 0, 1000).stop().unwrap();
        assert_eq!(fake.controlwords(), Vec::<u16>::new());
    }

    #[test]
    fn status_shows_an_error_code_that_is_not_0_or_any_in_fault() {
        let line = |status: u16, error: u16| {
            let mut fake = Fake::new(status);
            fake.error = error;
            let mut out = Vec::new();
            show(&mut drive(&mut fake, 0, 30), false, &mut out).unwrap();
            String::from_utf8(out).unwrap()
        };
        // Enabled with a warning's code: shown.
        assert!(line(0x0237, 0x8611).ends_with("; error code 0x8611 (following error)\n"));
        // In FAULT with 0: shown too.
        assert!(line(0x0208, 0).ends_with("; error code 0x0000 (error reset or no error)\n"));
        // Enabled with 0: not.
        assert!(line(0x0237, 0).ends_with("remote\n"));
    }

    #[test]
    fn modes_by_name() {
        let names = [
            (0, "no mode"),
            (1, "profile position"),
            (2, "velocity"),
            (3, "profile velocity"),
            (4, "profile torque"),
            (5, "reserved"),
            (6, "homing"),
            (7, "interpolated position"),
            (8, "cyclic synchronous position"),
            (9, "cyclic synchronous velocity"),
            (10, "cyclic synchronous torque"),
            (11, "reserved"),
            (-1, "manufacturer specific"),
            (-128, "manufacturer specific"),
        ];
        for (mode, name) in names {
            assert_eq!(mode_name(mode), name, "{mode}");
        }
        assert_eq!(
            bit_names(0x3000, 3),
            ["speed is zero", "max slippage error"]
        );
        for mode in [8, 9, 10] {
            assert_eq!(
                bit_names(0x3000, mode),
                ["target value ignored", "following error"]
            );
        }
        assert_eq!(
            bit_names(0x3000, 0),
            [
                "operation mode specific (12)",
                "operation mode specific (13)"
            ]
        );
    }
}
