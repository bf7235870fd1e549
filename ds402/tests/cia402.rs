//! Tests of the CiA 402 state machine against the X67SM2436 rule catalogue, sections 18.11.3.5 and 18.11.4.1 to
//! 18.11.4.3. Each test names the rules it covers; status words are asserted in full, cycle by cycle.

use ds402::cia402::control::{
    DISABLE_OPERATION, DISABLE_VOLTAGE, ENABLE_OPERATION, FAULT_RESET, QUICK_STOP, QUICK_STOP_BIT,
    SHUTDOWN, SWITCH_ON,
};
use ds402::cia402::{next, status_word, Action, Command, Inputs, State, StateMachine};

/// Quick stop with bits 0 and 3 still set, as a master sends it from Operation enabled (0x000B).
const QUICK_STOP_FROM_ENABLED: u16 = ENABLE_OPERATION & !QUICK_STOP_BIT;

/// Status words of each state as the seed's table gives them (bit 5 = 0 where it is x) plus Remote (bit 9).
const NRTSO: u16 = 0x0200;
const SOD: u16 = 0x0240;
const RTSO: u16 = 0x0221;
const SO: u16 = 0x0233;
const OE: u16 = 0x0237;
const QSA: u16 = 0x0217;
const FRA: u16 = 0x020F;
const FAULT: u16 = 0x0208;

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

fn idle() -> Inputs {
    Inputs {
        standstill: true,
        ..Inputs::default()
    }
}

fn moving() -> Inputs {
    Inputs {
        standstill: false,
        identification_done: false,
        ..Inputs::default()
    }
}

fn error() -> Inputs {
    Inputs {
        error_pending: true,
        ..idle()
    }
}

/// Steps once and checks the status word and the actions of that cycle.
#[track_caller]
fn expect(sm: &mut StateMachine, cw: u16, ctx: Inputs, sw: u16, actions: &[Action]) {
    let out = sm.step(cw, &ctx);
    assert_eq!(
        (out.status_word, out.actions.as_slice()),
        (sw, actions),
        "CW {cw:#06x} from {:?}",
        out.state
    );
    assert_eq!(out.state, sm.state);
}

/// A machine that has run the first Switch on with its identification, back in Switch on disabled.
fn started() -> StateMachine {
    let mut sm = StateMachine::new();
    sm.step(DISABLE_VOLTAGE, &idle());
    sm.step(SHUTDOWN, &idle());
    sm.step(SWITCH_ON, &idle());
    sm.step(
        SWITCH_ON,
        &Inputs {
            identification_done: true,
            ..idle()
        },
    );
    assert_eq!(sm.state, State::SwitchedOn);
    sm.step(DISABLE_VOLTAGE, &idle());
    assert_eq!(sm.state, State::SwitchOnDisabled);
    sm
}

/// A new machine after Shutdown and its first Switch on: in Ready to switch on, the identification running.
fn identifying() -> StateMachine {
    let mut sm = StateMachine::new();
    sm.step(DISABLE_VOLTAGE, &idle());
    expect(&mut sm, SHUTDOWN, idle(), RTSO, &[]);
    expect(
        &mut sm,
        SWITCH_ON,
        idle(),
        RTSO,
        &[Action::StartIdentification],
    );
    sm
}

/// Brings an identified machine into `state` (not for the Fault states).
fn in_state(state: State) -> StateMachine {
    let mut sm = started();
    let path: &[u16] = match state {
        State::SwitchOnDisabled => &[],
        State::ReadyToSwitchOn => &[SHUTDOWN],
        State::SwitchedOn => &[SHUTDOWN, SWITCH_ON],
        State::OperationEnabled => &[SHUTDOWN, SWITCH_ON, ENABLE_OPERATION],
        State::QuickStopActive => &[SHUTDOWN, SWITCH_ON, ENABLE_OPERATION],
        _ => unreachable!(),
    };
    for &cw in path {
        sm.step(cw, &moving());
    }
    if state == State::QuickStopActive {
        sm.step(QUICK_STOP_FROM_ENABLED, &moving());
    }
    assert_eq!(sm.state, state);
    sm
}

/// X67-18.11.4.3-01, X67-18.11.4.3-02, X67-18.11.4.3-03, X67-18.11.4.3-06, X67-18.11.4.3-07,
/// X67-18.11.4.3-09; X67-18.11.4.2-01, X67-18.11.4.2-02, X67-18.11.4.2-03, X67-18.11.4.2-04,
/// X67-18.11.4.2-05, X67-18.11.4.2-09: the standard power-up sequence
/// 0x06 → 0x07 (with the identification) → 0x0F, status word cycle by cycle.
#[test]
fn power_up_sequence_with_identification() {
    let mut sm = StateMachine::new();
    assert_eq!(sm.state, State::NotReadyToSwitchOn);
    assert_eq!(sm.status_word(0), NRTSO);
    // Internal initialisation: Switch on disabled after one cycle, without a command.
    expect(&mut sm, DISABLE_VOLTAGE, idle(), SOD, &[]);
    expect(&mut sm, DISABLE_VOLTAGE, idle(), SOD, &[]);
    // Shutdown: no other action.
    expect(&mut sm, SHUTDOWN, idle(), RTSO, &[]);
    // First Switch on: the identification starts once; the state stays Ready to switch on (bit 4 = 0).
    expect(
        &mut sm,
        SWITCH_ON,
        idle(),
        RTSO,
        &[Action::StartIdentification],
    );
    for _ in 0..39 {
        expect(&mut sm, SWITCH_ON, idle(), RTSO, &[]);
    }
    let done = Inputs {
        identification_done: true,
        ..idle()
    };
    expect(&mut sm, SWITCH_ON, done, SO, &[Action::VoltageOn]);
    assert!(sm.identified);
    expect(&mut sm, SWITCH_ON, idle(), SO, &[]);
    expect(
        &mut sm,
        ENABLE_OPERATION,
        idle(),
        OE,
        &[Action::EnableMotion],
    );
    expect(&mut sm, ENABLE_OPERATION, idle(), OE, &[]);
}

/// X67-18.11.4.3-07: a later Switch on reaches Switched on within one cycle, without identification.
#[test]
fn later_switch_on_skips_identification() {
    let mut sm = started();
    expect(&mut sm, SHUTDOWN, idle(), RTSO, &[]);
    expect(&mut sm, SWITCH_ON, idle(), SO, &[Action::VoltageOn]);
}

/// X67-18.11.4.3-07 (model choice): an identification cut short by Disable voltage switches the voltage off and
/// runs again at the next Switch on.
#[test]
fn aborted_identification_runs_again() {
    let mut sm = identifying();
    expect(&mut sm, DISABLE_VOLTAGE, idle(), SOD, &[Action::VoltageOff]);
    expect(&mut sm, SHUTDOWN, idle(), RTSO, &[]);
    expect(
        &mut sm,
        SWITCH_ON,
        idle(),
        RTSO,
        &[Action::StartIdentification],
    );
    // Shutdown while it runs: no transition from Ready to switch on; the measurement finishes.
    expect(&mut sm, SHUTDOWN, idle(), RTSO, &[]);
    let done = Inputs {
        identification_done: true,
        ..idle()
    };
    expect(&mut sm, SHUTDOWN, done, RTSO, &[]);
    expect(&mut sm, SWITCH_ON, idle(), SO, &[Action::VoltageOn]);
}

/// X67-18.11.4.1-01: Shutdown is (CW & 0x87) == 0x06.
#[test]
fn decode_shutdown() {
    for cw in [0x0006, 0x000E, 0x0076, 0xFF7E] {
        assert_eq!(
            Command::decode(cw, 0, State::SwitchOnDisabled),
            Some(Command::Shutdown),
            "{cw:#06x}"
        );
    }
}

/// X67-18.11.4.1-02: Switch on is (CW & 0x8F) == 0x07.
#[test]
fn decode_switch_on() {
    for cw in [0x0007, 0x0077, 0xFF77] {
        assert_eq!(
            Command::decode(cw, 0, State::ReadyToSwitchOn),
            Some(Command::SwitchOn)
        );
    }
}

/// X67-18.11.4.1-03: Disable voltage is (CW & 0x82) == 0x00.
#[test]
fn decode_disable_voltage() {
    for cw in [0x0000, 0x000D, 0x0001, 0x0004, 0x0008, 0xFF7D] {
        assert_eq!(
            Command::decode(cw, 0, State::OperationEnabled),
            Some(Command::DisableVoltage),
            "{cw:#06x}"
        );
    }
}

/// X67-18.11.4.1-04: Quick stop is (CW & 0x86) == 0x02.
#[test]
fn decode_quick_stop() {
    for cw in [0x0002, 0x000B, 0x0003, 0x000A, 0xFF7B] {
        assert_eq!(
            Command::decode(cw, 0, State::OperationEnabled),
            Some(Command::QuickStop),
            "{cw:#06x}"
        );
    }
}

/// X67-18.11.4.1-05: Disable operation has the Switch on pattern; the state decides. CW 0x07 in Operation
/// enabled → Switched on, in Ready to switch on → Switched on.
#[test]
fn decode_disable_operation_by_state() {
    assert_eq!(
        Command::decode(0x0007, 0, State::OperationEnabled),
        Some(Command::DisableOperation)
    );
    assert_eq!(
        Command::decode(0x0007, 0, State::ReadyToSwitchOn),
        Some(Command::SwitchOn)
    );
    let mut sm = in_state(State::OperationEnabled);
    expect(&mut sm, DISABLE_OPERATION, idle(), SO, &[]);
    let mut sm = in_state(State::ReadyToSwitchOn);
    expect(&mut sm, SWITCH_ON, idle(), SO, &[Action::VoltageOn]);
}

/// X67-18.11.4.1-06: Enable operation is (CW & 0x8F) == 0x0F.
#[test]
fn decode_enable_operation() {
    for cw in [0x000F, 0x007F, 0xFF7F] {
        assert_eq!(
            Command::decode(cw, 0, State::SwitchedOn),
            Some(Command::EnableOperation)
        );
    }
}

/// X67-18.11.4.1-07: Fault reset is the rising edge of bit 7 whatever the other bits hold; holding it is not a
/// second one.
#[test]
fn decode_fault_reset_edge() {
    assert_eq!(
        Command::decode(0x0080, 0x0000, State::Fault),
        Some(Command::FaultReset)
    );
    assert_eq!(
        Command::decode(0x008F, 0x000F, State::OperationEnabled),
        Some(Command::FaultReset)
    );
    assert_eq!(Command::decode(0x0080, 0x0080, State::Fault), None);
    let mut sm = in_state(State::OperationEnabled);
    expect(&mut sm, 0x008F, idle(), OE, &[Action::ClearErrors]);
    expect(&mut sm, 0x008F, idle(), OE, &[]);
}

/// X67-18.11.4.1-08: bits 9 and 10 are ignored when decoding: CW 0x020F in Switched on → Operation enabled.
#[test]
fn reserved_bits_9_10_ignored() {
    let mut sm = in_state(State::SwitchedOn);
    expect(&mut sm, 0x020F, idle(), OE, &[Action::EnableMotion]);
    assert_eq!(
        Command::decode(0x0606, 0, State::SwitchOnDisabled),
        Some(Command::Shutdown)
    );
}

/// X67-18.11.4.1-09: with bit 7 already 1, CW 0x0086 is no command; 0x0006 then is Shutdown.
#[test]
fn bit_7_must_be_cleared_before_next_command() {
    let mut sm = started();
    expect(&mut sm, FAULT_RESET, idle(), SOD, &[Action::ClearErrors]);
    expect(&mut sm, 0x0086, idle(), SOD, &[]);
    expect(&mut sm, SHUTDOWN, idle(), RTSO, &[]);
}

/// X67-18.11.4.1-10 (state-machine part): a rising edge on bit 12 (Warning reset) does not affect the state
/// machine, also in Fault.
#[test]
fn warning_reset_bit_does_not_affect_state() {
    let mut sm = in_state(State::OperationEnabled);
    expect(&mut sm, 0x100F, idle(), OE, &[]);
    let mut sm = started();
    expect(
        &mut sm,
        DISABLE_VOLTAGE,
        error(),
        FAULT,
        &[Action::VoltageOff],
    );
    expect(&mut sm, 0x1000, error(), FAULT, &[]);
    expect(&mut sm, DISABLE_VOLTAGE, idle(), FAULT, &[]);
    expect(&mut sm, 0x1000, idle(), FAULT, &[]);
}

/// X67-18.11.4.1-11: Fault reset outside Fault clears errors and warnings without a state change.
#[test]
fn fault_reset_outside_fault_clears_warnings() {
    for state in [
        State::SwitchOnDisabled,
        State::ReadyToSwitchOn,
        State::SwitchedOn,
        State::OperationEnabled,
    ] {
        let mut sm = in_state(state);
        let cw = sm.last_control | FAULT_RESET;
        let out = sm.step(cw, &idle());
        assert_eq!((out.state, out.actions), (state, vec![Action::ClearErrors]));
    }
}

/// X67-18.11.4.1-12: bits 4–6, 8 and 11–15 never select a transition.
#[test]
fn free_bits_do_not_select_transitions() {
    for state in ALL {
        for cw in 0u16..0x10 {
            let base = Command::decode(cw, 0, state);
            for free in [
                0x0010, 0x0020, 0x0040, 0x0100, 0x0800, 0x1000, 0x2000, 0x4000, 0x8000, 0xF970,
            ] {
                assert_eq!(
                    Command::decode(cw | free, 0, state),
                    base,
                    "{state:?} {cw:#x} {free:#x}"
                );
            }
        }
    }
    let mut sm = started();
    expect(&mut sm, 0x4000, idle(), SOD, &[]);
    expect(&mut sm, DISABLE_VOLTAGE, idle(), SOD, &[]);
}

/// X67-18.11.4.1-13: a command without a transition from the state leaves it unchanged: 0x0F or 0x07 in Switch
/// on disabled, Shutdown in Fault, 0x0F in Ready to switch on (the table's reading).
#[test]
fn command_without_transition_keeps_state() {
    let mut sm = started();
    expect(&mut sm, ENABLE_OPERATION, idle(), SOD, &[]);
    expect(&mut sm, SWITCH_ON, idle(), SOD, &[]);
    expect(&mut sm, QUICK_STOP, idle(), SOD, &[]);
    let mut sm = in_state(State::ReadyToSwitchOn);
    expect(&mut sm, ENABLE_OPERATION, idle(), RTSO, &[]);
    expect(&mut sm, SHUTDOWN, idle(), RTSO, &[]);
    let mut sm = in_state(State::SwitchedOn);
    expect(&mut sm, SWITCH_ON, idle(), SO, &[]);
    let mut sm = in_state(State::OperationEnabled);
    expect(&mut sm, ENABLE_OPERATION, idle(), OE, &[]);
    let mut sm = started();
    expect(
        &mut sm,
        DISABLE_VOLTAGE,
        error(),
        FAULT,
        &[Action::VoltageOff],
    );
    for cw in [
        SHUTDOWN,
        SWITCH_ON,
        ENABLE_OPERATION,
        QUICK_STOP,
        DISABLE_VOLTAGE,
    ] {
        expect(&mut sm, cw, idle(), FAULT, &[]);
    }
}

/// X67-18.11.4.1-13 (gap, CiA 402 transition 12): Disable voltage in Quick stop active → Switch on disabled,
/// voltage off at once, also while braking.
#[test]
fn disable_voltage_in_quick_stop_active() {
    let mut sm = in_state(State::QuickStopActive);
    expect(
        &mut sm,
        DISABLE_VOLTAGE,
        moving(),
        SOD,
        &[Action::VoltageOff],
    );
}

/// X67-18.11.4.2-01, X67-18.11.4.2-02, X67-18.11.4.2-03, X67-18.11.4.2-04, X67-18.11.4.2-05,
/// X67-18.11.4.2-06, X67-18.11.4.2-07, X67-18.11.4.2-08, X67-18.11.3.5-01, X67-18.11.3.5-02: the
/// exact state bits, bit 8 = 0 and Remote = 1 in every
/// state, and the catalogue's masks.
#[test]
fn status_word_table() {
    let expected = [NRTSO, SOD, RTSO, SO, OE, QSA, FRA, FAULT];
    let masks = [
        0x035F, 0x035F, 0x037F, 0x037F, 0x037F, 0x037F, 0x035F, 0x035F,
    ];
    for ((state, sw), mask) in ALL.into_iter().zip(expected).zip(masks) {
        assert_eq!(status_word(state, 0), sw, "{state:?}");
        let full = status_word(state, 0xFFFF);
        assert_eq!(full & mask, sw & mask, "{state:?}");
        assert_eq!(full & 0x0100, 0, "bit 8 in {state:?}");
        assert_eq!(full & 0x0200, 0x0200, "Remote in {state:?}");
        assert_eq!(full & !0x037F, 0xFC80, "axis bits in {state:?}");
        assert_eq!(State::from_status_word(full), Some(state));
        if mask == 0x035F {
            // Bit 5 is x in this state.
            assert_eq!(State::from_status_word(sw | 0x0020), Some(state));
        }
    }
    assert_eq!(State::from_status_word(0x0203), None);
}

/// X67-18.11.4.2-09: Voltage enabled (bit 4) is 1 exactly in Switched on, Operation enabled and Quick stop
/// active; not during the identification in Ready to switch on (checked in the power-up test).
#[test]
fn voltage_enabled_bit() {
    for state in ALL {
        let on = matches!(
            state,
            State::SwitchedOn | State::OperationEnabled | State::QuickStopActive
        );
        assert_eq!(state.voltage_enabled(), on, "{state:?}");
        assert_eq!(status_word(state, 0) & 0x0010 != 0, on);
    }
}

/// X67-18.11.4.2-10, X67-18.11.3.5-05: the warning bit and bits 10–15 come from the axis model unchanged
/// through `StateMachine::status_word`, as the X67 axis builds its status word; the state bits cannot be
/// overridden, and the step's own status word carries the state alone.
#[test]
fn axis_bits_pass_through() {
    let mut sm = in_state(State::OperationEnabled);
    expect(&mut sm, ENABLE_OPERATION, idle(), OE, &[]);
    assert_eq!(sm.status_word(0xC480 | 0x007F), 0xC480 | OE);
    assert_eq!(sm.status_word(0xFFFF), 0xFC00 | 0x0080 | OE);
}

/// X67-18.11.4.3-04: Disable voltage or Quick stop in Ready to switch on → Switch on disabled, no other action.
#[test]
fn ready_to_switch_on_to_switch_on_disabled() {
    for cw in [DISABLE_VOLTAGE, QUICK_STOP] {
        let mut sm = in_state(State::ReadyToSwitchOn);
        expect(&mut sm, cw, idle(), SOD, &[]);
    }
}

/// X67-18.11.4.3-05: Disable voltage or Quick stop in Switched on → Switch on disabled, voltage off at once.
#[test]
fn switched_on_to_switch_on_disabled() {
    for cw in [DISABLE_VOLTAGE, QUICK_STOP] {
        let mut sm = in_state(State::SwitchedOn);
        expect(&mut sm, cw, idle(), SOD, &[Action::VoltageOff]);
    }
}

/// X67-18.11.4.3-08: Shutdown in Switched on → Ready to switch on, voltage off at once.
#[test]
fn switched_on_shutdown() {
    let mut sm = in_state(State::SwitchedOn);
    expect(&mut sm, SHUTDOWN, idle(), RTSO, &[Action::VoltageOff]);
}

/// X67-18.11.4.3-10: Disable operation brakes a moving axis with the configured deceleration, keeps the voltage
/// and shows Switched on at once; at standstill there is nothing to brake.
#[test]
fn disable_operation_decelerates() {
    let mut sm = in_state(State::OperationEnabled);
    expect(
        &mut sm,
        DISABLE_OPERATION,
        moving(),
        SO,
        &[Action::Decelerate { quick: false }],
    );
    expect(&mut sm, DISABLE_OPERATION, moving(), SO, &[]);
    expect(&mut sm, DISABLE_OPERATION, idle(), SO, &[]);
    let mut sm = in_state(State::OperationEnabled);
    expect(&mut sm, DISABLE_OPERATION, idle(), SO, &[]);
}

/// X67-18.11.4.3-11: Shutdown in Operation enabled → Ready to switch on, voltage off at once, no braking.
#[test]
fn operation_enabled_shutdown() {
    let mut sm = in_state(State::OperationEnabled);
    expect(&mut sm, SHUTDOWN, moving(), RTSO, &[Action::VoltageOff]);
}

/// X67-18.11.4.3-12: Disable voltage in Operation enabled → Switch on disabled, voltage off.
#[test]
fn operation_enabled_disable_voltage() {
    let mut sm = in_state(State::OperationEnabled);
    expect(
        &mut sm,
        DISABLE_VOLTAGE,
        moving(),
        SOD,
        &[Action::VoltageOff],
    );
}

/// X67-18.11.4.3-13, X67-18.11.4.3-14: Quick stop brakes, stays in Quick stop active while moving
/// and goes to Switch on
/// disabled by itself at standstill, with the voltage off.
#[test]
fn quick_stop_to_standstill() {
    let mut sm = in_state(State::OperationEnabled);
    expect(
        &mut sm,
        QUICK_STOP_FROM_ENABLED,
        moving(),
        QSA,
        &[Action::Decelerate { quick: true }],
    );
    for _ in 0..5 {
        expect(&mut sm, QUICK_STOP_FROM_ENABLED, moving(), QSA, &[]);
    }
    expect(
        &mut sm,
        QUICK_STOP_FROM_ENABLED,
        idle(),
        SOD,
        &[Action::VoltageOff],
    );
    expect(&mut sm, QUICK_STOP_FROM_ENABLED, idle(), SOD, &[]);
    // Already standing: Quick stop active is shown for one cycle.
    let mut sm = in_state(State::OperationEnabled);
    expect(&mut sm, QUICK_STOP, idle(), QSA, &[]);
    expect(&mut sm, QUICK_STOP, idle(), SOD, &[Action::VoltageOff]);
}

/// X67-18.11.4.3-15: Enable operation takes Quick stop active back to Operation enabled.
#[test]
fn quick_stop_back_to_operation_enabled() {
    let mut sm = in_state(State::QuickStopActive);
    expect(&mut sm, QUICK_STOP_FROM_ENABLED, moving(), QSA, &[]);
    expect(
        &mut sm,
        ENABLE_OPERATION,
        moving(),
        OE,
        &[Action::EnableMotion],
    );
    // Also at the standstill cycle: the command wins over the automatic transition.
    let mut sm = in_state(State::QuickStopActive);
    expect(
        &mut sm,
        ENABLE_OPERATION,
        idle(),
        OE,
        &[Action::EnableMotion],
    );
}

/// X67-18.11.4.3-16, X67-18.11.4.3-18, X67-18.11.4.2-07, X67-18.11.4.2-08: an Error moves every
/// state to Fault reaction active, switches
/// the voltage off and reaches Fault in the same cycle; no control word reaches Fault.
#[test]
fn error_passes_through_fault_reaction_active() {
    for state in [
        State::SwitchOnDisabled,
        State::ReadyToSwitchOn,
        State::SwitchedOn,
        State::OperationEnabled,
        State::QuickStopActive,
    ] {
        let mut sm = in_state(state);
        let cw = sm.last_control;
        let out = sm.step(cw, &error());
        assert_eq!(
            out.trace,
            vec![State::FaultReactionActive, State::Fault],
            "{state:?}"
        );
        assert_eq!(out.status_word, FAULT);
        assert_eq!(out.actions, vec![Action::VoltageOff]);
    }
    // From start-up, too.
    let mut sm = StateMachine::new();
    let out = sm.step(DISABLE_VOLTAGE, &error());
    assert_eq!(out.trace, vec![State::FaultReactionActive, State::Fault]);
    // The pure function shows the intermediate state.
    let t = next(
        State::OperationEnabled,
        Some(Command::EnableOperation),
        &error(),
    );
    assert_eq!(
        (t.state, t.actions),
        (State::FaultReactionActive, vec![Action::VoltageOff])
    );
    assert_eq!(status_word(t.state, 0), FRA);
    assert_eq!(next(t.state, None, &error()).state, State::Fault);
    // No control word reaches Fault without an error.
    for state in ALL {
        if matches!(state, State::FaultReactionActive | State::Fault) {
            continue;
        }
        for cw in 0u16..0x100 {
            let cmd = Command::decode(cw, 0, state);
            let t = next(state, cmd, &idle());
            assert!(
                !matches!(t.state, State::Fault | State::FaultReactionActive),
                "{state:?} {cw:#x}"
            );
        }
    }
}

/// X67-18.11.4.3-19, X67-18.11.4.3-20: Fault reset leaves Fault only when no error remains, and
/// clears errors and warnings.
#[test]
fn fault_reset() {
    let mut sm = in_state(State::OperationEnabled);
    expect(
        &mut sm,
        ENABLE_OPERATION,
        error(),
        FAULT,
        &[Action::VoltageOff],
    );
    // Error still present: stays in Fault (the latched warnings are still cleared).
    expect(&mut sm, FAULT_RESET, error(), FAULT, &[Action::ClearErrors]);
    expect(&mut sm, DISABLE_VOLTAGE, error(), FAULT, &[]);
    // Condition gone, but bit 7 held: no new edge.
    expect(&mut sm, DISABLE_VOLTAGE, idle(), FAULT, &[]);
    expect(&mut sm, FAULT_RESET, idle(), SOD, &[Action::ClearErrors]);
    expect(&mut sm, FAULT_RESET, idle(), SOD, &[]);
    // Back up again.
    expect(&mut sm, SHUTDOWN, idle(), RTSO, &[]);
    expect(&mut sm, SWITCH_ON, idle(), SO, &[Action::VoltageOn]);
    expect(
        &mut sm,
        ENABLE_OPERATION,
        idle(),
        OE,
        &[Action::EnableMotion],
    );
}

/// X67-18.11.4.3-21: motion only in Operation enabled.
#[test]
fn motion_only_in_operation_enabled() {
    for state in ALL {
        assert_eq!(state.motion_allowed(), state == State::OperationEnabled);
    }
}

/// Disable voltage (0x00) from every state (X67-18.11.4.1-03, X67-18.11.4.1-13; X67-18.11.4.3-04,
/// X67-18.11.4.3-05, X67-18.11.4.3-12, X67-18.11.4.3-02).
#[test]
fn disable_voltage_from_every_state() {
    let cases = [
        (State::SwitchOnDisabled, SOD, vec![]),
        (State::ReadyToSwitchOn, SOD, vec![]),
        (State::SwitchedOn, SOD, vec![Action::VoltageOff]),
        (State::OperationEnabled, SOD, vec![Action::VoltageOff]),
        (State::QuickStopActive, SOD, vec![Action::VoltageOff]),
    ];
    for (state, sw, actions) in cases {
        let mut sm = in_state(state);
        expect(&mut sm, DISABLE_VOLTAGE, moving(), sw, &actions);
    }
    // Not ready to switch on: initialisation goes on to Switch on disabled.
    let mut sm = StateMachine::new();
    expect(&mut sm, DISABLE_VOLTAGE, idle(), SOD, &[]);
    // Fault: no transition.
    let mut sm = started();
    sm.step(DISABLE_VOLTAGE, &error());
    expect(&mut sm, DISABLE_VOLTAGE, idle(), FAULT, &[]);
    // Fault reaction active (pure function): on to Fault.
    let t = next(
        State::FaultReactionActive,
        Some(Command::DisableVoltage),
        &idle(),
    );
    assert_eq!((t.state, t.actions), (State::Fault, vec![]));
}

/// X67-18.11.4.3-16 during X67-18.11.4.3-07: an Error while the identification runs ends it; the voltage goes
/// off once, and the next Switch on after the Fault reset measures again.
#[test]
fn error_during_identification() {
    let mut sm = identifying();
    expect(&mut sm, SWITCH_ON, error(), FAULT, &[Action::VoltageOff]);
    assert!(!sm.identifying && !sm.identified);
    expect(&mut sm, FAULT_RESET, idle(), SOD, &[Action::ClearErrors]);
    expect(&mut sm, SHUTDOWN, idle(), RTSO, &[]);
    expect(
        &mut sm,
        SWITCH_ON,
        idle(),
        RTSO,
        &[Action::StartIdentification],
    );
}
