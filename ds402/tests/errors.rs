//! Tests of the error-code register and the over-temperature cut-off against the X67SM2436 rule catalogue,
//! sections 15, 18.11.3.8 and 18.11.3.13. Each test names the rules it covers; register values are asserted
//! in full, step by step.

use ds402::cia402::{Action, Inputs, StateMachine, CW_FAULT_RESET, SW_WARNING};
use ds402::x67::errors::{
    DcBus, ErrorCode, ErrorRegister, Kind, Temperature, CW_CURRENT_ERROR_DETECTION,
    CW_STALL_DETECTION, CW_WARNING_RESET,
};

/// A register with current-error and stall detection both on.
fn detecting() -> ErrorRegister {
    let mut r = ErrorRegister::new();
    r.control_word(CW_CURRENT_ERROR_DETECTION | CW_STALL_DETECTION);
    r
}

/// X67-18.11.3.13-01: nothing pending after power-up → 0x0000, no error, no warning.
#[test]
fn x67_18_11_3_13_01_zero_when_nothing_pending() {
    let r = ErrorRegister::new();
    assert_eq!(r.register(), 0x0000);
    assert!(!r.has_error());
    assert!(!r.has_warning());
    assert_eq!(r.highest(), None);
}

/// X67-18.11.3.13-02, X67-18.11.3.13-03, X67-18.11.3.13-04, X67-18.11.3.13-05, X67-18.11.3.13-06,
/// X67-18.11.3.13-07, X67-18.11.3.13-08, X67-18.11.3.13-09: every code, its value, type and rank as
/// in the seed's table.
#[test]
fn x67_18_11_3_13_02_to_09_table() {
    let table = [
        (ErrorCode::Voltage, 0x3000, Kind::Error),
        (ErrorCode::Overtemperature, 0x4200, Kind::Error),
        (ErrorCode::NegativeLimitSwitch, 0xFF20, Kind::Warning),
        (ErrorCode::PositiveLimitSwitch, 0xFF21, Kind::Warning),
        (ErrorCode::Overcurrent, 0x2300, Kind::Warning),
        (ErrorCode::CurrentError, 0xFF00, Kind::Warning),
        (ErrorCode::Stall, 0xFF01, Kind::Warning),
        (ErrorCode::OpenCircuit, 0xFF11, Kind::Warning),
    ];
    assert_eq!(ErrorCode::ALL.len(), table.len());
    for (rank, (code, value, kind)) in table.into_iter().enumerate() {
        assert_eq!(ErrorCode::ALL[rank], code);
        assert_eq!(code.code(), value);
        assert_eq!(code.kind(), kind);
        assert_eq!(code.priority(), rank);
        assert_eq!(ErrorCode::from_code(value), Some(code));
    }
    assert_eq!(ErrorCode::from_code(0x0000), None);
    assert_eq!(ErrorCode::from_code(0x3210), None);
    assert_eq!(ErrorCode::CurrentError.detection_bit(), Some(1 << 13));
    assert_eq!(ErrorCode::Stall.detection_bit(), Some(1 << 15));
    assert_eq!(ErrorCode::OpenCircuit.detection_bit(), None);
}

/// X67-18.11.3.13-02, X67-18.11.3.13-03, X67-18.11.3.13-04, X67-18.11.3.13-05, X67-18.11.3.13-06,
/// X67-18.11.3.13-07, X67-18.11.3.13-08, X67-18.11.3.13-09: each code alone is shown as it is, with
/// the right status flag.
#[test]
fn x67_18_11_3_13_02_to_09_each_code_alone() {
    for code in ErrorCode::ALL {
        let mut r = detecting();
        assert!(r.raise(code));
        assert_eq!(r.register(), code.code(), "{code:?}");
        assert_eq!(r.has_error(), code.kind() == Kind::Error, "{code:?}");
        assert_eq!(r.has_warning(), code.kind() == Kind::Warning, "{code:?}");
    }
}

/// X67-18.11.3.13-10: with two codes pending the higher one is shown, for every pair, in either order of
/// raising; clearing the higher one (here by acknowledging it) shows the lower one.
#[test]
fn x67_18_11_3_13_10_priority_of_every_pair() {
    for (i, hi) in ErrorCode::ALL.into_iter().enumerate() {
        for lo in ErrorCode::ALL.into_iter().skip(i + 1) {
            for hi_first in [true, false] {
                let mut r = detecting();
                if hi_first {
                    r.raise(hi);
                    r.raise(lo);
                } else {
                    r.raise(lo);
                    r.raise(hi);
                }
                assert_eq!(r.register(), hi.code(), "{hi:?} over {lo:?}");
                assert_eq!(r.pending().collect::<Vec<_>>(), vec![hi, lo]);
            }
        }
    }
}

/// X67-18.11.3.13-10 observe: stall and overcurrent pending → 0x2300; the overcurrent is reset with the
/// stall still present → 0xFF01.
#[test]
fn x67_18_11_3_13_10_overcurrent_over_stall() {
    let mut r = detecting();
    assert!(r.raise(ErrorCode::Stall));
    assert_eq!(r.register(), 0xFF01);
    assert!(r.raise(ErrorCode::Overcurrent));
    assert_eq!(r.register(), 0x2300);
    r.clear_condition(ErrorCode::Overcurrent);
    assert_eq!(r.register(), 0x2300); // latched until acknowledged
    r.warning_reset();
    assert_eq!(r.register(), 0xFF01);
    assert!(r.has_warning());
    r.clear_condition(ErrorCode::Stall);
    r.warning_reset();
    assert_eq!(r.register(), 0x0000);
    assert!(!r.has_warning());
}

/// X67-18.11.3.13-11: overtemperature plus a stall warning → Error and Warning flags together, 0x4200 shown.
#[test]
fn x67_18_11_3_13_11_error_and_warning_together() {
    let mut r = detecting();
    r.raise(ErrorCode::Stall);
    r.raise(ErrorCode::Overtemperature);
    assert_eq!(r.register(), 0x4200);
    assert!(r.has_error());
    assert!(r.has_warning());
}

/// X67-18.11.3.13-12: each axis has its own register; a module-wide condition is entered on both.
#[test]
fn x67_18_11_3_13_12_axes_are_independent() {
    let mut ax1 = detecting();
    let mut ax2 = detecting();
    ax2.raise(ErrorCode::Stall);
    assert_eq!((ax1.register(), ax2.register()), (0x0000, 0xFF01));
    ax1.raise(ErrorCode::Voltage);
    ax2.raise(ErrorCode::Voltage);
    assert_eq!((ax1.register(), ax2.register()), (0x3000, 0x3000));
}

/// X67-18.11.3.13-07, X67-18.11.3.2-07: 0xFF00 is detected only with CW bit 13 = 1.
#[test]
fn x67_18_11_3_13_07_current_error_only_with_bit_13() {
    let mut r = ErrorRegister::new();
    assert!(!r.detection_enabled(ErrorCode::CurrentError));
    assert!(!r.raise(ErrorCode::CurrentError));
    assert_eq!(r.register(), 0x0000);
    assert!(!r.has_warning());

    r.control_word(CW_STALL_DETECTION); // bit 15 alone does not enable it
    assert!(!r.raise(ErrorCode::CurrentError));
    assert_eq!(r.register(), 0x0000);

    r.control_word(CW_CURRENT_ERROR_DETECTION);
    assert!(r.raise(ErrorCode::CurrentError));
    assert_eq!(r.register(), 0xFF00);
    assert!(r.has_warning());
}

/// X67-18.11.3.13-08, X67-18.11.3.2-09: 0xFF01 is detected only with CW bit 15 = 1.
#[test]
fn x67_18_11_3_13_08_stall_only_with_bit_15() {
    let mut r = ErrorRegister::new();
    assert!(!r.raise(ErrorCode::Stall));
    r.control_word(CW_CURRENT_ERROR_DETECTION); // bit 13 alone does not enable it
    assert!(!r.raise(ErrorCode::Stall));
    assert_eq!(r.register(), 0x0000);
    r.control_word(CW_STALL_DETECTION);
    assert!(r.raise(ErrorCode::Stall));
    assert_eq!(r.register(), 0xFF01);
}

/// Switching a detection off drops the condition but keeps the latched code until it is acknowledged
/// (X67-18.6.3.1-05).
#[test]
fn x67_18_6_3_1_05_detection_off_keeps_latch() {
    let mut r = detecting();
    r.raise(ErrorCode::Stall);
    r.control_word(0);
    assert!(!r.is_present(ErrorCode::Stall));
    assert!(r.is_latched(ErrorCode::Stall));
    assert_eq!(r.register(), 0xFF01);
    r.warning_reset();
    assert_eq!(r.register(), 0x0000);
}

/// X67-18.11.3.13-09: an open winding with bit 13 = 0 → 0xFF11; with bit 13 = 1 the axis model also raises
/// 0xFF00, which is shown since it ranks higher.
#[test]
fn x67_18_11_3_13_09_open_circuit() {
    let mut r = ErrorRegister::new();
    assert!(r.raise(ErrorCode::OpenCircuit));
    assert!(!r.raise(ErrorCode::CurrentError));
    assert_eq!(r.register(), 0xFF11);

    let mut r = ErrorRegister::new();
    r.control_word(CW_CURRENT_ERROR_DETECTION);
    assert!(r.raise(ErrorCode::OpenCircuit));
    assert!(r.raise(ErrorCode::CurrentError));
    assert_eq!(r.register(), 0xFF00);
}

/// X67-18.6.3.1-05: a reported code stays latched after its cause has gone, until acknowledged.
#[test]
fn x67_18_6_3_1_05_latched_until_acknowledged() {
    let mut r = detecting();
    r.raise(ErrorCode::Stall);
    r.clear_condition(ErrorCode::Stall);
    assert_eq!(r.register(), 0xFF01);
    assert!(r.has_warning());
    assert!(!r.is_present(ErrorCode::Stall));
    r.control_word(CW_CURRENT_ERROR_DETECTION | CW_STALL_DETECTION | CW_WARNING_RESET);
    assert_eq!(r.register(), 0x0000);
    assert!(!r.has_warning());
}

/// X67-18.11.4.1-10: Warning reset clears warnings only; the latched error stays.
#[test]
fn x67_18_11_4_1_10_warning_reset_leaves_errors() {
    let mut r = detecting();
    r.raise(ErrorCode::Overtemperature);
    r.raise(ErrorCode::Overcurrent);
    r.clear_condition(ErrorCode::Overcurrent);
    r.clear_condition(ErrorCode::Overtemperature);
    assert_eq!(r.register(), 0x4200);
    assert!(r.has_warning());
    r.warning_reset();
    assert_eq!(r.register(), 0x4200);
    assert!(!r.has_warning());
    assert!(r.error_latched());
    assert!(r.is_latched(ErrorCode::Overtemperature));
}

/// X67-18.11.3.2-06: a warning whose condition is still present survives the Warning reset.
#[test]
fn x67_18_11_3_2_06_warning_reset_with_condition_present() {
    let mut r = detecting();
    r.raise(ErrorCode::PositiveLimitSwitch);
    r.raise(ErrorCode::Stall);
    r.clear_condition(ErrorCode::PositiveLimitSwitch);
    assert_eq!(r.register(), 0xFF21);
    r.warning_reset();
    assert_eq!(r.register(), 0xFF01);
    assert!(r.has_warning());
}

/// X67-18.11.3.2-06: the Warning reset acts on the rising edge of CW bit 12 only.
#[test]
fn x67_18_11_3_2_06_warning_reset_on_rising_edge() {
    let base = CW_CURRENT_ERROR_DETECTION | CW_STALL_DETECTION;
    let mut r = detecting();
    r.control_word(base | CW_WARNING_RESET); // edge with nothing pending
    r.raise(ErrorCode::Stall);
    r.clear_condition(ErrorCode::Stall);
    r.control_word(base | CW_WARNING_RESET); // bit held at 1: no edge
    assert_eq!(r.register(), 0xFF01);
    r.control_word(base);
    assert_eq!(r.register(), 0xFF01); // falling edge: nothing
    r.control_word(base | CW_WARNING_RESET);
    assert_eq!(r.register(), 0x0000);
}

/// X67-18.11.4.1-11: Fault reset clears errors and warnings.
#[test]
fn x67_18_11_4_1_11_fault_reset_clears_all() {
    let mut r = detecting();
    for code in ErrorCode::ALL {
        r.raise(code);
        r.clear_condition(code);
    }
    assert_eq!(r.register(), 0x3000);
    assert!(!r.has_error());
    assert!(r.error_latched());
    r.fault_reset();
    assert_eq!(r.register(), 0x0000);
    assert!(!r.has_warning());
    assert!(!r.error_latched());
    assert_eq!(r.pending().count(), 0);
}

/// X67-18.11.4.3-20, X67-18.11.4.1-11 pick: after a Fault reset, codes whose conditions are still present
/// are latched again — an Error comes back, and so does a warning.
#[test]
fn x67_18_11_4_3_20_fault_reset_with_conditions_present() {
    let mut r = detecting();
    r.raise(ErrorCode::Voltage);
    r.raise(ErrorCode::Overtemperature);
    r.raise(ErrorCode::Stall);
    r.clear_condition(ErrorCode::Voltage);
    assert_eq!(r.register(), 0x3000);
    r.fault_reset();
    assert_eq!(r.register(), 0x4200);
    assert!(r.has_error());
    assert!(r.has_warning());
    r.clear_condition(ErrorCode::Overtemperature);
    r.fault_reset();
    assert_eq!(r.register(), 0xFF01);
    assert!(!r.has_error());
    r.clear_condition(ErrorCode::Stall);
    r.fault_reset();
    assert_eq!(r.register(), 0x0000);
}

/// X67-15-01: cut-off at 85 °C, not at 84 °C; the Temperature register shows the temperature.
#[test]
fn x67_15_01_cutoff_at_85_not_84() {
    let mut t = Temperature::new();
    let mut ax1 = ErrorRegister::new();
    let mut ax2 = ErrorRegister::new();
    for (celsius, over, reg) in [
        (24.0, false, 0x0000),
        (84.0, false, 0x0000),
        (84.99, false, 0x0000),
        (85.0, true, 0x4200),
    ] {
        assert_eq!(t.update(celsius), over, "{celsius}");
        t.apply_to(&mut ax1);
        t.apply_to(&mut ax2);
        assert_eq!((ax1.register(), ax2.register()), (reg, reg), "{celsius}");
        assert_eq!(
            (ax1.has_error(), ax2.has_error()),
            (over, over),
            "{celsius}"
        );
    }
    assert_eq!(t.register(), 85);
    assert!(t.over_temperature());
}

/// X67-15-02: after 86 °C, 84 °C keeps the condition; it goes at 83 °C, and only the Fault reset clears
/// 0x4200 from the register.
#[test]
fn x67_15_02_recovery_at_83_not_84() {
    let mut t = Temperature::new();
    let mut r = ErrorRegister::new();
    let mut step = |celsius: f64, r: &mut ErrorRegister| {
        let over = t.update(celsius);
        t.apply_to(r);
        over
    };
    assert!(step(86.0, &mut r));
    assert_eq!(r.register(), 0x4200);
    assert!(step(84.0, &mut r));
    assert!(r.has_error());
    r.fault_reset(); // refused by the state machine; the register latches again anyway
    assert_eq!(r.register(), 0x4200);
    assert!(step(83.5, &mut r));
    assert!(r.has_error());
    assert!(!step(83.0, &mut r));
    assert!(!r.has_error());
    assert_eq!(r.register(), 0x4200); // the code waits for the Fault reset
    assert!(!step(84.0, &mut r)); // rising again below 85 °C raises nothing
    assert_eq!(r.register(), 0x4200);
    r.fault_reset();
    assert_eq!(r.register(), 0x0000);
    assert!(!step(84.9, &mut r));
    assert_eq!(r.register(), 0x0000);
    assert!(step(85.0, &mut r));
    assert_eq!(r.register(), 0x4200);
}

/// X67-18.11.3.8-01: the Temperature register is whole °C as SINT, truncated toward zero, clamped.
#[test]
fn x67_18_11_3_8_01_temperature_register() {
    let mut t = Temperature::new();
    assert_eq!(t.register(), 0);
    for (celsius, reg) in [
        (47.6, 47i8),
        (85.0, 85),
        (84.99, 84),
        (-0.5, 0),
        (-10.7, -10),
        (127.9, 127),
        (200.0, 127),
        (-128.0, -128),
        (-300.0, -128),
    ] {
        t.update(celsius);
        assert_eq!(t.register(), reg, "{celsius}");
    }
    t.update(47.6);
    t.update(f64::NAN); // ignored
    assert_eq!(t.register(), 47);
    assert_eq!(t.celsius(), 47.6);
}

/// X67-3-11: the supply band 18.0 V … 48.125 V; outside it 0x3000 on both axes, inside no error.
#[test]
fn x67_3_11_supply_band() {
    use ds402::x67::errors::supply_in_range;
    for (volts, ok) in [
        (24.0, true),
        (18.0, true),
        (48.125, true),
        (17.9, false),
        (48.2, false),
        (f64::NAN, false),
    ] {
        assert_eq!(supply_in_range(volts), ok, "{volts}");
        let mut ax1 = ErrorRegister::new();
        let mut ax2 = ErrorRegister::new();
        ax1.set_condition(ErrorCode::Voltage, !supply_in_range(volts));
        ax2.set_condition(ErrorCode::Voltage, !supply_in_range(volts));
        let reg = if ok { 0x0000 } else { 0x3000 };
        assert_eq!((ax1.register(), ax2.register()), (reg, reg), "{volts}");
    }
}

/// One cycle of an axis, as the module runs it: the register takes the control word, the state machine
/// steps with `error_pending = has_error()`, its `ClearErrors` action is carried out, and the status
/// word is the state's with the Warning bit as the register has it after that.
fn cycle(sm: &mut StateMachine, r: &mut ErrorRegister, cw: u16) -> u16 {
    r.control_word(cw);
    let ctx = Inputs {
        error_pending: r.has_error(),
        standstill: true,
        identification_done: true,
    };
    let out = sm.step(cw, &ctx);
    if out.actions.contains(&Action::ClearErrors) {
        r.fault_reset();
    }
    sm.status_word(if r.has_warning() { SW_WARNING } else { 0 })
}

/// X67-15-02 observe, with the state machine: 86 °C then 84 °C → Fault reset refused, Fault and 0x4200
/// stay; at 83 °C the Fault reset gives Switch on disabled and 0x0000. X67-18.11.4.1-10: ↑ bit 12 in Fault
/// leaves Fault and 0x4200.
#[test]
fn x67_15_02_with_state_machine() {
    let mut sm = StateMachine::new();
    let mut r = ErrorRegister::new();
    let mut t = Temperature::new();
    assert_eq!(cycle(&mut sm, &mut r, 0x0000), 0x0240);

    t.update(86.0);
    t.apply_to(&mut r);
    // Through Fault reaction active to Fault in one cycle.
    assert_eq!(cycle(&mut sm, &mut r, 0x0000) & 0x035F, 0x0208);
    assert_eq!(r.register(), 0x4200);

    t.update(84.0);
    t.apply_to(&mut r);
    assert_eq!(cycle(&mut sm, &mut r, CW_FAULT_RESET) & 0x035F, 0x0208);
    assert_eq!(r.register(), 0x4200);
    assert_eq!(cycle(&mut sm, &mut r, 0x0000) & 0x035F, 0x0208);
    assert_eq!(cycle(&mut sm, &mut r, CW_WARNING_RESET) & 0x035F, 0x0208);
    assert_eq!(r.register(), 0x4200);

    t.update(83.0);
    t.apply_to(&mut r);
    assert_eq!(cycle(&mut sm, &mut r, 0x0000) & 0x035F, 0x0208); // no reset yet: still Fault
    assert_eq!(r.register(), 0x4200);
    assert_eq!(cycle(&mut sm, &mut r, CW_FAULT_RESET), 0x0240);
    assert_eq!(r.register(), 0x0000);
}

/// X67-18.11.4.3-20 observe: Fault reset with a stall condition still present → Switch on disabled,
/// ErrorCode 0xFF01 and SW bit 7 = 1. X67-18.11.3.13-11: Fault and Warning together before the reset.
#[test]
fn x67_18_11_4_3_20_with_state_machine() {
    let cw = CW_STALL_DETECTION;
    let mut sm = StateMachine::new();
    let mut r = ErrorRegister::new();
    cycle(&mut sm, &mut r, cw);
    r.raise(ErrorCode::Stall);
    r.raise(ErrorCode::Voltage);
    assert_eq!(cycle(&mut sm, &mut r, cw), 0x0288); // Fault + Warning + Remote
    assert_eq!(r.register(), 0x3000);
    r.clear_condition(ErrorCode::Voltage);
    assert_eq!(cycle(&mut sm, &mut r, cw | CW_FAULT_RESET), 0x02C0); // Switch on disabled + Warning
    assert_eq!(r.register(), 0xFF01);
    r.clear_condition(ErrorCode::Stall);
    assert_eq!(cycle(&mut sm, &mut r, cw | CW_WARNING_RESET), 0x0240);
    assert_eq!(r.register(), 0x0000);
}

/// One operation on a register, for the property test.
#[derive(Clone, Debug)]
enum Op {
    Raise(usize),
    Clear(usize),
    Control(u16),
    WarningReset,
    FaultReset,
}

fn op() -> impl proptest::strategy::Strategy<Value = Op> {
    use proptest::prelude::*;
    prop_oneof![
        (0..8usize).prop_map(Op::Raise),
        (0..8usize).prop_map(Op::Clear),
        prop::sample::select(vec![0u16, 1 << 12, 1 << 13, 1 << 15, 0xB000, 0xA000])
            .prop_map(Op::Control),
        Just(Op::WarningReset),
        Just(Op::FaultReset),
    ]
}

proptest::proptest! {
    /// X67-18.11.3.13-10, X67-18.11.3.13-11, X67-18.6.3.1-05: after any sequence, the register
    /// shows the highest-priority
    /// latched code (0 when none), every present condition is latched, `has_error` is "an Error condition is
    /// present", `has_warning` is "a warning is latched", and 0xFF00/0xFF01 are present only with their bit.
    #[test]
    fn x67_18_11_3_13_10_invariants(ops in proptest::collection::vec(op(), 0..40)) {
        let mut r = ErrorRegister::new();
        let mut cw = 0u16;
        for op in ops {
            match op {
                Op::Raise(i) => { r.raise(ErrorCode::ALL[i]); }
                Op::Clear(i) => r.clear_condition(ErrorCode::ALL[i]),
                Op::Control(c) => { cw = c; r.control_word(c); }
                Op::WarningReset => r.warning_reset(),
                Op::FaultReset => r.fault_reset(),
            }
            let latched: Vec<ErrorCode> = ErrorCode::ALL.into_iter().filter(|c| r.is_latched(*c)).collect();
            proptest::prop_assert_eq!(r.register(), latched.first().map_or(0, |c| c.code()));
            for c in ErrorCode::ALL {
                proptest::prop_assert!(!r.is_present(c) || r.is_latched(c));
            }
            proptest::prop_assert_eq!(
                r.has_error(),
                ErrorCode::ALL.into_iter().any(|c| c.kind() == Kind::Error && r.is_present(c))
            );
            proptest::prop_assert_eq!(
                r.has_warning(),
                latched.iter().any(|c| c.kind() == Kind::Warning)
            );
            proptest::prop_assert!(!r.is_present(ErrorCode::CurrentError) || cw & (1 << 13) != 0);
            proptest::prop_assert!(!r.is_present(ErrorCode::Stall) || cw & (1 << 15) != 0);
        }
    }
}

/// X67-18.11.4.3-12: the DC bus on its own. 0.5 J into 200 µF on a 46 V supply: √(46² + 2·0.5/200e-6)
/// = √(2116 + 5000) = 84.356 V; a second 0.5 J on top: √(84.356² + 5000) = √12116 = 110.073 V. After
/// τ = 0.2304 s the rise above the supply is 1/e of what it was; the bus at the supply voltage stays.
#[test]
fn x67_18_11_4_3_12_dc_bus_rise_and_decay() {
    let mut bus = DcBus::default();
    assert_eq!(bus.volts(46.0), 46.0);
    bus.discharge(1.0);
    assert_eq!(bus.volts(46.0), 46.0);
    bus.regenerate(46.0, 0.5);
    assert!(
        (bus.volts(46.0) - 7116f64.sqrt()).abs() < 1e-9,
        "{}",
        bus.volts(46.0)
    );
    bus.regenerate(46.0, 0.5);
    assert!(
        (bus.volts(46.0) - 110.073).abs() < 1e-3,
        "{}",
        bus.volts(46.0)
    );
    assert!((bus.volts(46.0) - 12116f64.sqrt()).abs() < 1e-9);
    // The rise rides on the supply: 1 V less supply, 1 V less bus.
    assert!((bus.volts(45.0) - (12116f64.sqrt() - 1.0)).abs() < 1e-9);
    bus.discharge(0.2304);
    let rise = (12116f64.sqrt() - 46.0) / std::f64::consts::E;
    assert!(
        (bus.volts(46.0) - (46.0 + rise)).abs() < 1e-9,
        "{}",
        bus.volts(46.0)
    );
}
