//! The CiA 402 drive state machine as the X67SM2436 function model "Ramp" runs it (seed 002, 18.11.4).
//!
//! This is a sans-IO model: [`Command::decode`] turns a control word into a command, [`next`] is the pure
//! transition function and [`status_word`] builds the status word of a state. [`StateMachine`] wraps them with
//! the little memory the device needs between cycles (the previous control word for the Fault-reset edge and
//! whether the start-up motor identification has run). The axis model that owns the motor calls
//! [`StateMachine::step`] once per cycle with the control word it received and the [`Inputs`] it knows about
//! (pending error, standstill, identification finished), carries out the returned [`Action`]s and sends the
//! returned status word.
//!
//! ```
//! use ds402::cia402::{control, Action, Inputs, State, StateMachine};
//!
//! let mut sm = StateMachine::new();
//! let idle = Inputs { standstill: true, ..Inputs::default() };
//! assert_eq!(sm.step(control::DISABLE_VOLTAGE, &idle).status_word, 0x0240); // Switch on disabled
//! assert_eq!(sm.step(control::SHUTDOWN, &idle).status_word, 0x0221); // Ready to switch on
//! let out = sm.step(control::SWITCH_ON, &idle); // first Switch on: motor identification first
//! assert_eq!((out.state, out.actions), (State::ReadyToSwitchOn, vec![Action::StartIdentification]));
//! let done = Inputs { identification_done: true, ..idle };
//! assert_eq!(sm.step(control::SWITCH_ON, &done).status_word, 0x0233); // Switched on
//! assert_eq!(sm.step(control::ENABLE_OPERATION, &idle).status_word, 0x0237); // Operation enabled
//! ```
//!
//! Rule IDs (`X67-…`) refer to the rule catalogue of the X67SM2436 (`rules/x67.md`), sections 18.11.4.1 to
//! 18.11.4.3 and 18.11.3.5.

/// Control word bit 7: Fault reset, acting on its rising edge (X67-18.11.4.1-07).
pub const CW_FAULT_RESET: u16 = control::FAULT_RESET;

/// The control-word bits 0–3 and 7 and the commands of the state machine, as the command table of seed 002,
/// 18.11.4.1 gives them. Each command is a pattern and the mask of the bits the table fixes:
/// `(CW & mask) == pattern`.
pub mod control {
    /// Bit 0: Switch on.
    pub const SWITCH_ON_BIT: u16 = 1 << 0;
    /// Bit 1: Enable voltage.
    pub const ENABLE_VOLTAGE_BIT: u16 = 1 << 1;
    /// Bit 2: Quick stop (the command is bit 2 = 0).
    pub const QUICK_STOP_BIT: u16 = 1 << 2;
    /// Bit 3: Enable operation.
    pub const ENABLE_OPERATION_BIT: u16 = 1 << 3;
    /// Bits 0–3 and 7: the bits that select a command (X67-18.11.3.2-01, X67-18.11.4.1-12).
    pub const COMMAND_BITS: u16 = 0x008F;

    /// Shutdown: bit 0 = 0, bits 1 and 2 = 1, bit 7 = 0 (X67-18.11.4.1-01).
    pub const SHUTDOWN: u16 = ENABLE_VOLTAGE_BIT | QUICK_STOP_BIT;
    /// The bits Shutdown fixes: 0, 1, 2 and 7.
    pub const SHUTDOWN_MASK: u16 = 0x0087;
    /// Switch on: bits 3..0 = 0111, bit 7 = 0 (X67-18.11.4.1-02).
    pub const SWITCH_ON: u16 = SWITCH_ON_BIT | ENABLE_VOLTAGE_BIT | QUICK_STOP_BIT;
    /// The bits Switch on fixes: 0–3 and 7.
    pub const SWITCH_ON_MASK: u16 = COMMAND_BITS;
    /// Disable voltage: bit 1 = 0, bit 7 = 0 (X67-18.11.4.1-03).
    pub const DISABLE_VOLTAGE: u16 = 0x0000;
    /// The bits Disable voltage fixes: 1 and 7.
    pub const DISABLE_VOLTAGE_MASK: u16 = 0x0082;
    /// Quick stop: bit 1 = 1, bit 2 = 0, bit 7 = 0 (X67-18.11.4.1-04).
    pub const QUICK_STOP: u16 = ENABLE_VOLTAGE_BIT;
    /// The bits Quick stop fixes: 1, 2 and 7.
    pub const QUICK_STOP_MASK: u16 = 0x0086;
    /// Disable operation: the pattern of Switch on, given in Operation enable (X67-18.11.4.1-05).
    pub const DISABLE_OPERATION: u16 = SWITCH_ON;
    /// Enable operation: bits 3..0 = 1111, bit 7 = 0 (X67-18.11.4.1-06).
    pub const ENABLE_OPERATION: u16 = SWITCH_ON | ENABLE_OPERATION_BIT;
    /// The bits Enable operation fixes: 0–3 and 7.
    pub const ENABLE_OPERATION_MASK: u16 = COMMAND_BITS;
    /// Bit 7: Fault reset, on its rising edge whatever the other bits hold (X67-18.11.4.1-07).
    pub const FAULT_RESET: u16 = 1 << 7;
}

/// Status word bit 7: Warning (seed 002, 18.11.3.5).
pub const SW_WARNING: u16 = 1 << 7;
/// Status word bit 9: Remote, always 1 because the module has no local mode (X67-18.11.3.5-02).
pub const SW_REMOTE: u16 = 1 << 9;
/// The status-word bits the state machine owns: bits 0–6 from the state table, bit 8 (reserved, always 0,
/// X67-18.11.3.5-01) and bit 9 (Remote, always 1). All other bits (7 Warning, 10–15) come from the axis model.
pub const SW_STATE_MASK: u16 = 0x037F;

/// A state of the CiA 402 state machine (seed 002, 18.11.4.2 table and 18.11.4.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum State {
    /// Initialisation after start-up; left by itself for Switch on disabled (X67-18.11.4.3-01, X67-18.11.4.3-02).
    NotReadyToSwitchOn,
    /// Motor voltage off, waiting for Shutdown.
    SwitchOnDisabled,
    /// Motor voltage off, ready for Switch on.
    ReadyToSwitchOn,
    /// Motor voltage on (holding current), no motion.
    SwitchedOn,
    /// Motor voltage on, motion according to the Mode register ("Operation enable" in the seed).
    OperationEnabled,
    /// Quick stop: braking; left for Switch on disabled at standstill.
    QuickStopActive,
    /// An Error occurred; the motor voltage goes off and the machine passes straight on to Fault.
    FaultReactionActive,
    /// An Error is latched; left only by Fault reset once no error remains.
    Fault,
}

impl State {
    /// The state bits 0–6 of the status word, exactly as the table of seed 002, 18.11.4.2 gives them
    /// (X67-18.11.4.2-01, X67-18.11.4.2-02, X67-18.11.4.2-03, X67-18.11.4.2-04, X67-18.11.4.2-05, X67-18.11.4.2-06,
    /// X67-18.11.4.2-07, X67-18.11.4.2-08). Bit 5 (Quick stop) is `x` in Not ready to switch on, Switch on disabled,
    /// Fault reaction active and Fault; it is 0 there (the catalogue's pick in X67-18.11.4.2-01). Bit 4 (Voltage
    /// enabled) follows the table, so it is 1 exactly in Switched on, Operation enabled and Quick stop active
    /// (X67-18.11.4.2-09), also while the start-up identification powers the motor in Ready to switch on (the
    /// catalogue's pick).
    pub const fn status_bits(self) -> u16 {
        match self {
            State::NotReadyToSwitchOn => 0x0000,
            State::SwitchOnDisabled => 0x0040,
            State::ReadyToSwitchOn => 0x0021,
            State::SwitchedOn => 0x0033,
            State::OperationEnabled => 0x0037,
            State::QuickStopActive => 0x0017,
            State::FaultReactionActive => 0x000F,
            State::Fault => 0x0008,
        }
    }

    /// Reads the state back from a status word, comparing bits 0–6 and ignoring all others. Returns `None` for
    /// a pattern that is no state (a master-side helper; the device never sends one).
    pub fn from_status_word(status_word: u16) -> Option<State> {
        let bits = status_word & 0x007F;
        // Bit 5 is x in four states: compare those without it.
        const ALL: [State; 8] = [
            State::NotReadyToSwitchOn,
            State::SwitchOnDisabled,
            State::ReadyToSwitchOn,
            State::SwitchedOn,
            State::OperationEnabled,
            State::QuickStopActive,
            State::FaultReactionActive,
            State::Fault,
        ];
        ALL.into_iter().find(|s| {
            let mask = if s.quick_stop_bit_defined() {
                0x007F
            } else {
                0x005F
            };
            bits & mask == s.status_bits()
        })
    }

    /// Whether the seed's table fixes bit 5 for this state (it is `x` in the other four).
    const fn quick_stop_bit_defined(self) -> bool {
        matches!(
            self,
            State::ReadyToSwitchOn
                | State::SwitchedOn
                | State::OperationEnabled
                | State::QuickStopActive
        )
    }

    /// Whether the motor voltage is on in this state (status-word bit 4).
    pub const fn voltage_enabled(self) -> bool {
        self.status_bits() & 0x0010 != 0
    }

    /// Whether motion according to the Mode register is carried out: only in Operation enabled
    /// (seed 002, 18.11.4.3 Information; X67-18.11.4.3-21). Braking after Disable operation or Quick stop is
    /// not "motion according to the mode" and goes on outside this state.
    pub const fn motion_allowed(self) -> bool {
        matches!(self, State::OperationEnabled)
    }
}

/// The status word for `state`: the state bits of [`State::status_bits`], bit 8 = 0, bit 9 (Remote) = 1, and
/// the bits of `extra_bits` the state machine does not own (7 Warning, 10 Target reached, 11 Internal limit
/// active, 12 mode-specific, 13–15 motor load). Bits 0–6, 8 and 9 of `extra_bits` are ignored.
pub const fn status_word(state: State, extra_bits: u16) -> u16 {
    state.status_bits() | SW_REMOTE | (extra_bits & !SW_STATE_MASK)
}

/// A state-machine command decoded from the control word (seed 002, 18.11.4.1 command table).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Command {
    /// `(CW & 0x87) == 0x06` (X67-18.11.4.1-01).
    Shutdown,
    /// `(CW & 0x8F) == 0x07` outside Operation enabled (X67-18.11.4.1-02, X67-18.11.4.1-05).
    SwitchOn,
    /// `(CW & 0x82) == 0x00` (X67-18.11.4.1-03).
    DisableVoltage,
    /// `(CW & 0x86) == 0x02` (X67-18.11.4.1-04).
    QuickStop,
    /// `(CW & 0x8F) == 0x07` in Operation enabled: the same pattern as Switch on (X67-18.11.4.1-05).
    DisableOperation,
    /// `(CW & 0x8F) == 0x0F` (X67-18.11.4.1-06).
    EnableOperation,
    /// Rising edge of bit 7, whatever the other bits hold (X67-18.11.4.1-07).
    FaultReset,
}

impl Command {
    /// Decodes `control_word`, given the control word received in the previous cycle (for the Fault-reset
    /// edge) and the current state (to tell Disable operation from Switch on, which share a pattern).
    ///
    /// - A rising edge of bit 7 is Fault reset, whatever the other bits hold (X67-18.11.4.1-07).
    /// - Every other command needs bit 7 = 0, so a control word with bit 7 held at 1 is no command
    ///   (X67-18.11.4.1-09).
    /// - Only bits 0–3 and 7 take part. Bits 9 and 10, drawn as 0 in the table, are ignored: the catalogue's
    ///   pick in X67-18.11.4.1-08; bit 9 has no function and bit 10 is reserved (X67-18.11.3.2-03,
    ///   X67-18.11.3.2-04). Bits 4–6, 8 and 11–15 are `x` (X67-18.11.4.1-12).
    ///
    /// With bit 7 = 0 the masks cover all 16 combinations of bits 0–3 exactly once, so this returns `None`
    /// only when bit 7 is 1 without an edge.
    pub const fn decode(control_word: u16, previous: u16, state: State) -> Option<Command> {
        if control_word & CW_FAULT_RESET != 0 {
            return if previous & CW_FAULT_RESET == 0 {
                Some(Command::FaultReset)
            } else {
                None
            };
        }
        let cw = control_word & control::COMMAND_BITS;
        Some(
            if cw & control::DISABLE_VOLTAGE_MASK == control::DISABLE_VOLTAGE {
                Command::DisableVoltage
            } else if cw & control::QUICK_STOP_MASK == control::QUICK_STOP {
                Command::QuickStop
            } else if cw & control::SHUTDOWN_MASK == control::SHUTDOWN {
                Command::Shutdown
            } else if cw & control::ENABLE_OPERATION_MASK == control::ENABLE_OPERATION {
                Command::EnableOperation
            } else {
                // The only pattern left: bits 3..0 = 0111.
                if matches!(state, State::OperationEnabled) {
                    Command::DisableOperation
                } else {
                    Command::SwitchOn
                }
            },
        )
    }
}

/// What the axis model knows and the state machine needs, sampled once per cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Inputs {
    /// An Error-type condition (error code table type "Error": 0x3000 Voltage, 0x4200 Overtemperature) is
    /// present. Warnings do not belong here: they only set status-word bit 7 (X67-18.11.4.3-17).
    pub error_pending: bool,
    /// The axis is at standstill (speed 0).
    pub standstill: bool,
    /// The start-up motor-identification measurement has finished. [`StateMachine`] latches it, so the axis
    /// model may report it as a one-cycle pulse or as a level.
    pub identification_done: bool,
}

/// Something the axis must do because of a transition.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Action {
    /// Switch the motor voltage on (holding current at standstill).
    VoltageOn,
    /// Switch the motor voltage off at once, without braking.
    VoltageOff,
    /// Run the start-up motor-identification measurement (about 1 s, X67-18.11.4.3-07) and report its end
    /// through [`Inputs::identification_done`].
    StartIdentification,
    /// Brake a moving axis to standstill. The seed gives "the configured deceleration" for both Disable
    /// operation and Quick stop (18.11.4.3), so both use the configured maximum deceleration; `quick` tells
    /// which one it was.
    Decelerate {
        /// `true` for Quick stop, `false` for Disable operation.
        quick: bool,
    },
    /// Carry out motion according to the Mode register again (entering Operation enabled).
    EnableMotion,
    /// Reset all latched errors and warnings; conditions still present are latched again by the axis model
    /// (X67-18.11.4.1-11, X67-18.11.4.3-20).
    ClearErrors,
}

/// The result of one transition: the next state and what the axis must do.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Transition {
    /// The state after the transition (the same state when nothing happens).
    pub state: State,
    /// The actions, in the order to carry them out.
    pub actions: Vec<Action>,
}

impl Transition {
    fn to(state: State, actions: &[Action]) -> Transition {
        Transition {
            state,
            actions: actions.to_vec(),
        }
    }
}

/// The pure transition function: one step of the state machine from `state` with the decoded `command`
/// (`None` when the control word carries no command) and the axis `ctx`.
///
/// The transitions are those of seed 002, 18.11.4.3; a command for which the state has no transition leaves
/// it unchanged (X67-18.11.4.1-13). Where the seed is silent, CiA 402 fills in, as marked below.
///
/// In order:
/// 1. Not ready to switch on goes to Switch on disabled by itself (X67-18.11.4.3-02), unless an Error is
///    pending; commands are not evaluated during initialisation.
/// 2. Fault reaction active goes to Fault at once (X67-18.11.4.3-18); nothing else is evaluated there.
/// 3. An Error moves every other state except Fault to Fault reaction active and switches the voltage off
///    (X67-18.11.4.3-16). It takes precedence over the command of the same cycle.
/// 4. Fault reset clears errors and warnings in every state (X67-18.11.4.1-11, X67-18.11.4.1-13 pick); in Fault it
///    also leaves for Switch on disabled if no Error is pending (X67-18.11.4.3-19, X67-18.11.4.3-20).
/// 5. The command transitions of the seed's table.
/// 6. In Quick stop active without a command that leaves it, standstill leads to Switch on disabled with the
///    voltage off (X67-18.11.4.3-14).
pub fn next(state: State, command: Option<Command>, ctx: &Inputs) -> Transition {
    use Action::*;
    use Command::*;
    use State::*;

    match state {
        // Fault reaction active → Fault at once (X67-18.11.4.3-18).
        FaultReactionActive => return Transition::to(Fault, &[]),
        NotReadyToSwitchOn | SwitchOnDisabled | ReadyToSwitchOn | SwitchedOn | OperationEnabled
        | QuickStopActive
            if ctx.error_pending =>
        {
            // Any state → Fault reaction active on an Error-type condition (X67-18.11.4.3-16). The voltage
            // goes off in every state, also where it was already off, and also when a start-up
            // identification in Ready to switch on powers the motor (X67-18.11.4.3-18).
            return Transition::to(FaultReactionActive, &[VoltageOff]);
        }
        // Not ready to switch on → Switch on disabled by itself (X67-18.11.4.3-02).
        NotReadyToSwitchOn => return Transition::to(SwitchOnDisabled, &[]),
        _ => {}
    }

    let brake = |quick| {
        if ctx.standstill {
            Vec::new()
        } else {
            vec![Decelerate { quick }]
        }
    };

    match (state, command) {
        // Fault → Switch on disabled only without an Error condition; errors and warnings are reset
        // (X67-18.11.4.3-19, X67-18.11.4.3-20).
        (Fault, Some(FaultReset)) if !ctx.error_pending => {
            Transition::to(SwitchOnDisabled, &[ClearErrors])
        }
        // Fault reset in any other state (and in Fault with an Error still present) resets errors and
        // warnings without a state change (X67-18.11.4.1-11, X67-18.11.4.3-19).
        (_, Some(FaultReset)) => Transition::to(state, &[ClearErrors]),

        // Switch on disabled → Ready to switch on: "No others actions are performed." (X67-18.11.4.3-03)
        (SwitchOnDisabled, Some(Shutdown)) => Transition::to(ReadyToSwitchOn, &[]),

        // Ready to switch on → Switch on disabled: "No others actions are performed." (X67-18.11.4.3-04)
        (ReadyToSwitchOn, Some(DisableVoltage | QuickStop)) => {
            Transition::to(SwitchOnDisabled, &[])
        }
        // Ready to switch on → Switched on (X67-18.11.4.3-06); the first time after start-up only after the
        // identification (X67-18.11.4.3-07).
        (ReadyToSwitchOn, Some(SwitchOn)) if ctx.identification_done => {
            Transition::to(SwitchedOn, &[VoltageOn])
        }
        (ReadyToSwitchOn, Some(SwitchOn)) => {
            Transition::to(ReadyToSwitchOn, &[StartIdentification])
        }

        // Switched on → Switch on disabled / Ready to switch on: the voltage goes off at once
        // (X67-18.11.4.3-05, X67-18.11.4.3-08).
        (SwitchedOn, Some(DisableVoltage | QuickStop)) => {
            Transition::to(SwitchOnDisabled, &[VoltageOff])
        }
        (SwitchedOn, Some(Shutdown)) => Transition::to(ReadyToSwitchOn, &[VoltageOff]),
        // Switched on → Operation enable: motion follows the mode (X67-18.11.4.3-09).
        (SwitchedOn, Some(EnableOperation)) => Transition::to(OperationEnabled, &[EnableMotion]),

        // Operation enabled → Switched on: brake with the configured deceleration, voltage stays on. The state
        // shows Switched on at once and the braking goes on there (catalogue pick, X67-18.11.4.3-10).
        (OperationEnabled, Some(DisableOperation)) => Transition {
            state: SwitchedOn,
            actions: brake(false),
        },
        // Operation enabled → Ready to switch on / Switch on disabled: voltage off at once, no braking
        // (X67-18.11.4.3-11, X67-18.11.4.3-12).
        (OperationEnabled, Some(Shutdown)) => Transition::to(ReadyToSwitchOn, &[VoltageOff]),
        (OperationEnabled, Some(DisableVoltage)) => Transition::to(SwitchOnDisabled, &[VoltageOff]),
        // Operation enabled → Quick stop active: brake with the configured deceleration (X67-18.11.4.3-13).
        (OperationEnabled, Some(QuickStop)) => Transition {
            state: QuickStopActive,
            actions: brake(true),
        },

        // Quick stop active → Operation enabled (X67-18.11.4.3-15).
        (QuickStopActive, Some(EnableOperation)) => {
            Transition::to(OperationEnabled, &[EnableMotion])
        }
        // Not in the seed: CiA 402 transition 12, Disable voltage leaves Quick stop active for Switch on
        // disabled with the voltage off at once (catalogue pick, X67-18.11.4.1-13).
        (QuickStopActive, Some(DisableVoltage)) => Transition::to(SwitchOnDisabled, &[VoltageOff]),
        // At standstill Quick stop active ends by itself; the voltage goes off, as the Switch on disabled
        // pattern has bit 4 = 0 (catalogue pick, X67-18.11.4.3-14). This is checked from Quick stop active
        // only, so the state is shown for at least one cycle even when the axis was already standing.
        (QuickStopActive, _) if ctx.standstill => Transition::to(SwitchOnDisabled, &[VoltageOff]),

        // Every other command has no transition from this state (X67-18.11.4.1-13).
        _ => Transition::to(state, &[]),
    }
}

/// What [`StateMachine::step`] returns for one cycle.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Output {
    /// The state at the end of the cycle.
    pub state: State,
    /// The state's part of the status word ([`status_word`] of `state` with no bits of the axis model; the
    /// axis adds its bits 7 and 10–15 with [`StateMachine::status_word`]).
    pub status_word: u16,
    /// The command decoded from the control word, if any.
    pub command: Option<Command>,
    /// Every state entered during this cycle, in order (empty when the state did not change). An Error shows
    /// `[FaultReactionActive, Fault]`: Fault reaction active is left in the same cycle (X67-18.11.4.3-18).
    pub trace: Vec<State>,
    /// The actions for the axis, in order.
    pub actions: Vec<Action>,
}

/// The state machine of one axis with its memory between cycles.
///
/// Call [`StateMachine::step`] once per cycle with the received control word. The state starts in Not ready to
/// switch on (X67-18.11.4.3-01) and reaches Switch on disabled in the first step (X67-18.11.4.3-02).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StateMachine {
    /// The current state.
    pub state: State,
    /// The control word received in the previous cycle (for the rising edge of bit 7).
    pub last_control: u16,
    /// Whether the start-up motor identification has been completed.
    pub identified: bool,
    /// Whether the start-up motor identification has been started and not yet completed.
    pub identifying: bool,
}

impl Default for StateMachine {
    fn default() -> Self {
        Self::new()
    }
}

impl StateMachine {
    /// A state machine just after start-up: Not ready to switch on, no control word received (taken as 0),
    /// motor not identified.
    pub const fn new() -> Self {
        StateMachine {
            state: State::NotReadyToSwitchOn,
            last_control: 0,
            identified: false,
            identifying: false,
        }
    }

    /// The status word of the current state with `extra_bits` (see [`status_word`]).
    pub const fn status_word(&self, extra_bits: u16) -> u16 {
        status_word(self.state, extra_bits)
    }

    /// One cycle: decode `control_word` against the previous one, run [`next`] (twice when an Error passes
    /// through Fault reaction active), and return the new state, its status word and the actions.
    ///
    /// The start-up identification: the first Switch on in Ready to switch on yields
    /// [`Action::StartIdentification`] once; the state stays Ready to switch on until
    /// [`Inputs::identification_done`] is reported while Switch on is still commanded. If the state leaves Ready
    /// to switch on before that (Disable voltage, Quick stop, an Error), the measurement counts as aborted: the
    /// step adds [`Action::VoltageOff`] if not already there and the next Switch on starts it again (not in the
    /// seed; a choice of this model).
    pub fn step(&mut self, control_word: u16, ctx: &Inputs) -> Output {
        if ctx.identification_done {
            self.identified = true;
            self.identifying = false;
        }
        let command = Command::decode(control_word, self.last_control, self.state);
        self.last_control = control_word;

        let inputs = Inputs {
            identification_done: self.identified,
            ..*ctx
        };
        let before = self.state;
        let mut trace = Vec::new();
        let mut actions = Vec::new();
        let mut t = next(self.state, command, &inputs);
        loop {
            actions.append(&mut t.actions);
            if t.state != self.state {
                trace.push(t.state);
            }
            self.state = t.state;
            if self.state != State::FaultReactionActive {
                break;
            }
            t = next(self.state, None, &inputs);
        }

        // Start the identification once, not every cycle Switch on is held.
        if actions.contains(&Action::StartIdentification) {
            if self.identifying {
                actions.retain(|a| *a != Action::StartIdentification);
            } else {
                self.identifying = true;
            }
        }
        if self.identifying
            && before == State::ReadyToSwitchOn
            && self.state != State::ReadyToSwitchOn
        {
            self.identifying = false;
            if !actions.contains(&Action::VoltageOff) {
                actions.push(Action::VoltageOff);
            }
        }

        Output {
            state: self.state,
            status_word: status_word(self.state, 0),
            command,
            trace,
            actions,
        }
    }
}
