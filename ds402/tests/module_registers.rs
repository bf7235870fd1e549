//! The X67SM2436 "Ramp" module seen as a whole through [`Module`]: the read registers, the CAN objects
//! (18.5.2) and the register table (18.5). Each test names the rules of `rules/x67.md` it checks.

mod module_status_helpers;
mod x67_rig;

use ds402::cia402::control::{SHUTDOWN, SWITCH_ON};
use ds402::x67::axis::{modes, CW_SWAP_COUNTERS};
use ds402::x67::current::Level;
use ds402::x67::module::Module;
use ds402::x67::motor::Load;
use ds402::x67::registers::{Access, AxisReg, ModuleReg, RegType, Register, RegisterError};
use module_status_helpers::*;
use x67_rig::{
    assert_state, operation_enable, set, set_currents, switch_on, READY, SWITCH_ON_DISABLED,
};
use RegType::{Dint, Int, Sint, Uint, Usint};

// ===== 18.11.3.5, 18.11.3.8, 18.11.3.11, 18.11.3.12 Read registers =====

/// X67-18.11.3.5-01: SW bit 8 is reserved and 0 in every state.
#[test]
fn x67_18_11_3_5_01_bit_8_always_0() {
    for sw in status_words_of_every_state() {
        assert_eq!(sw & 0x0100, 0, "{sw:#06x}");
    }
}

/// X67-18.11.3.5-02: SW bit 9 (Remote) is 1 in every state, from the first status on.
#[test]
fn x67_18_11_3_5_02_remote_always_1() {
    assert_eq!(Module::new().status_word(0) & 0x0200, 0x0200);
    for sw in status_words_of_every_state() {
        assert_eq!(sw & 0x0200, 0x0200, "{sw:#06x}");
    }
}

/// X67-18.11.3.5-05: SW bits 13–15 carry the load value with bit 13 as LSB when StallDetectConfig01 bit 7
/// = 1: load 6 → 110, load 1 → 001; with bit 7 = 0 → 000.
#[test]
fn x67_18_11_3_5_05_load_bits() {
    let base = running(50, 10);
    for (config, load, bits) in [(0x80, 6, 0b110), (0x80, 1, 0b001), (0x00, 6, 0)] {
        let mut m = base.clone();
        set(&mut m, 0, AxisReg::StallDetectConfig, config);
        m.axis_mut(0).motor.load = Load::Value(load);
        m.run(2);
        assert_eq!(
            m.status_word(0) & 0xE000,
            bits << 13,
            "{config:#04x} {load}"
        );
    }
}

/// X67-18.11.3.8-01: Temperature is the module temperature in °C, truncated toward zero, as a SINT.
#[test]
fn x67_18_11_3_8_01_temperature_register() {
    let mut m = Module::new();
    assert_eq!(named(&m, "Temperature"), 25);
    for (celsius, register) in [
        (47.6, 47),
        (47.0, 47),
        (-3.7, -3),
        (0.4, 0),
        (126.9, 126),
        (300.0, 127),
        (-300.0, -128),
    ] {
        m.set_temperature(celsius);
        m.step();
        assert_eq!(named(&m, "Temperature"), register, "{celsius} °C");
    }
}

/// X67-18.11.3.11-01: ControlReadback0n returns the last control word received, all 16 bits.
#[test]
fn x67_18_11_3_11_01_control_read_back() {
    let mut m = Module::new();
    m.step();
    assert_eq!(named(&m, "ControlReadback01"), 0);
    m.set_control(0, 0x820F);
    m.step();
    assert_eq!(named(&m, "ControlReadback01"), 0x820F);
    assert_eq!(named(&m, "ControlReadback02"), 0);
    m.set_control(1, 0xFFFF);
    m.step();
    assert_eq!(named(&m, "ControlReadback02"), 0xFFFF);
    assert_eq!(named(&m, "ControlReadback01"), 0x820F);
}

/// X67-18.11.3.12-01: ModeReadback0n returns the last mode received, as a SINT.
#[test]
fn x67_18_11_3_12_01_mode_read_back() {
    let mut m = Module::new();
    m.set_mode(0, modes::FIXED_A);
    m.set_mode(1, modes::SPEED);
    m.step();
    assert_eq!(named(&m, "ModeReadback01"), -125);
    assert_eq!((named(&m, "ModeReadback01") as i8) as u8, 0x83);
    assert_eq!(named(&m, "ModeReadback02"), 2);
    m.set_mode(0, 5);
    m.step();
    assert_eq!(named(&m, "ModeReadback01"), 5);
}

// ===== 18.5.2 CAN objects =====

/// X67-18.5.2-02, X67-18.5-21, X67-18.5-22, X67-18.5-23, X67-18.5-24, X67-18.5-25, X67-18.5-26:
/// object 1 carries axis 1 and the inputs: output bytes 0–3 AbsPos01,
/// 4–5 MpGenControl01, 6 MpGenMode01; input bytes 0–3 AbsPos01ActVal, 4–5 MpGenStatus01, 6 InputStatus.
#[test]
fn x67_18_5_2_02_object_1() {
    let mut m = Module::new();
    m.step();
    m.output_object(0, [0x78, 0x56, 0x34, 0x12, 0x06, 0x00, 0xFE, 0x00]);
    m.step();
    assert_eq!(named(&m, "AbsPos01"), 0x1234_5678);
    assert_eq!(named(&m, "ControlReadback01"), 0x0006);
    assert_eq!(named(&m, "ModeReadback01"), -2);
    assert_state(&m, 0, READY);
    assert_eq!(
        (named(&m, "AbsPos02"), named(&m, "ControlReadback02")),
        (0, 0)
    );

    m.set_input(2, true);
    m.set_input(5, true);
    m.step();
    let sw = m.status_word(0).to_le_bytes();
    let act = m.act_val(0).to_le_bytes();
    assert_eq!(
        m.input_object(0),
        [act[0], act[1], act[2], act[3], sw[0], sw[1], 0x12, 0x00]
    );
    assert_eq!(m.input_object(0)[4..6], [0x21, 0x06]);
}

/// X67-18.5.2-03: object 2 carries axis 2 at byte = offset − 8; input bytes 6–7 of object 2 are unused.
#[test]
fn x67_18_5_2_03_object_2() {
    let mut m = Module::new();
    set(&mut m, 1, AxisReg::MaxSpeedPos, 100);
    set(&mut m, 1, AxisReg::MaxAcc, 10);
    set(&mut m, 1, AxisReg::MaxDec, 10);
    m.step();
    m.output_object(1, [0x06, 0x00, 0x00, 0x00, 0x06, 0x00, 0x7F, 0x00]);
    m.step();
    assert_eq!(named(&m, "AbsPos02"), 6);
    assert_eq!(named(&m, "ControlReadback02"), 6);
    assert_eq!(named(&m, "ModeReadback02"), 127);
    assert_state(&m, 1, READY);
    assert_state(&m, 0, SWITCH_ON_DISABLED);

    switch_on(&mut m, 1);
    m.output_object(1, [0xE8, 0x03, 0x00, 0x00, 0x0F, 0x00, 0x01, 0x00]);
    m.set_input(6, true);
    m.run(30);
    assert_eq!(m.act_val(1), 1000);
    let sw = m.status_word(1).to_le_bytes();
    assert_eq!(
        m.input_object(1),
        [0xE8, 0x03, 0x00, 0x00, sw[0], sw[1], 0, 0]
    );
    assert_eq!(sw[0] & 0x7F, 0x37);
    assert_eq!(m.input_object(0)[6], 0x20);
}

/// X67-18.5.2-04: byte 7 of the output objects is ignored, and the unused input bytes are 0.
#[test]
fn x67_18_5_2_04_unused_bytes() {
    let mut a = Module::new();
    let mut b = Module::new();
    a.step();
    b.step();
    a.output_object(0, [0x10, 0x00, 0x00, 0x00, 0x06, 0x00, 0x01, 0x00]);
    b.output_object(0, [0x10, 0x00, 0x00, 0x00, 0x06, 0x00, 0x01, 0xFF]);
    a.output_object(1, [0x20, 0x00, 0x00, 0x00, 0x06, 0x00, 0x02, 0x00]);
    b.output_object(1, [0x20, 0x00, 0x00, 0x00, 0x06, 0x00, 0x02, 0xA5]);
    a.step();
    b.step();
    for reg in Register::all() {
        assert_eq!(a.read(reg), b.read(reg), "{reg}");
    }
    for k in 1..=6 {
        b.set_input(k, true);
    }
    b.step();
    assert_eq!(b.input_object(0)[7], 0);
    assert_eq!(b.input_object(1)[6..8], [0, 0]);
}

/// X67-18.5.2-05: multi-byte registers are little-endian: AbsPos01ActVal = 0x00012345 → 45 23 01 00.
#[test]
fn x67_18_5_2_05_little_endian() {
    let mut m = Module::new();
    operation_enable(&mut m, 0, 100, 10, 10);
    m.set_mode(0, modes::SET_POSITION);
    m.set_abs_pos(0, 0x0001_2345);
    m.run(2);
    assert_eq!(named(&m, "AbsPos01ActVal"), 0x0001_2345);
    assert_eq!(m.input_object(0)[0..4], [0x45, 0x23, 0x01, 0x00]);
    assert_eq!(m.input_object(0)[4..6], [0x37, 0x06]);
    m.output_object(0, [0x00, 0x00, 0x01, 0x00, 0x0F, 0x00, 0x01, 0x00]);
    m.step();
    assert_eq!(named(&m, "AbsPos01"), 0x0001_0000);
}

// ===== 18.5 Register table =====

/// X67-18.5-01: the model has exactly the 71 registers of the 18.5 table, and none of the registers that
/// exist only in function models 0 and 1.
#[test]
fn x67_18_5_01_exactly_the_ramp_registers() {
    let all: Vec<Register> = Register::all().collect();
    assert_eq!(all.len(), 71);
    let mut names: Vec<&str> = all.iter().map(|r| r.name()).collect();
    let mut expected: Vec<&str> = TABLE.iter().map(|r| r.0).collect();
    names.sort_unstable();
    expected.sort_unstable();
    assert_eq!(names, expected);
    assert_rows(&expected);
    for name in [
        "ConfigOutput01",
        "ConfigOutput02",
        "ConfigOutput09",
        "ConfigOutput16",
        "Motor1Step0",
        "Motor2Step3",
        "SetCounter01",
        "StatusInput",
        "MotorLoad",
        "MotorIdentTrigger",
        "Position1Sync",
        "GeneralConfig02",
        "MotorSettlingTime",
        "LifeCnt",
    ] {
        assert_eq!(Register::from_name(name), None, "{name}");
    }
}

/// X67-18.5-02: exactly the 11 registers with an offset are cyclic; all others are acyclic.
#[test]
fn x67_18_5_02_cyclic_registers() {
    let mut cyclic: Vec<&str> = Register::all()
        .filter(|r| matches!(r.info().access, Access::CyclicIn | Access::CyclicOut))
        .map(|r| r.name())
        .collect();
    cyclic.sort_unstable();
    assert_eq!(
        cyclic,
        [
            "AbsPos01",
            "AbsPos01ActVal",
            "AbsPos02",
            "AbsPos02ActVal",
            "InputStatus",
            "MpGenControl01",
            "MpGenControl02",
            "MpGenMode01",
            "MpGenMode02",
            "MpGenStatus01",
            "MpGenStatus02"
        ]
    );
}

/// X67-18.5-03: configuration registers and cyclic outputs are written by the master; read-back, acyclic
/// read and cyclic input registers refuse a write with `ReadOnly` (SDO abort 0x06010002) and keep their value.
#[test]
fn x67_18_5_03_access() {
    let mut m = Module::new();
    m.step();
    for reg in Register::all() {
        let info = reg.info();
        let before = m.read(reg);
        // A RefConfig value must be a listed one to be taken (X67-18.11.1.11-05).
        let value = if info.ty == RegType::Sint { -126 } else { 1 };
        let result = m.write(reg, value);
        match info.access {
            Access::Config | Access::CyclicOut => {
                assert_eq!(result, Ok(()), "{reg}");
                assert_eq!(m.read(reg), value, "{reg}");
            }
            Access::ReadAcyclic | Access::CyclicIn => {
                let err = result.unwrap_err();
                assert_eq!(err, RegisterError::ReadOnly(reg));
                assert_eq!(err.abort_code(), 0x0601_0002);
                assert_eq!(m.read(reg), before, "{reg}");
            }
        }
    }
    assert_eq!(
        Register::all()
            .filter(|r| r.info().access == Access::Config)
            .count(),
        39
    );
    assert_eq!(
        Register::all()
            .filter(|r| r.info().access == Access::ReadAcyclic)
            .count(),
        21
    );
}

/// X67-18.5-03: a register the master cannot write answers `ReadOnly` (SDO abort 0x06010002) whatever the
/// value, also one outside its type's range, which a writable register would refuse as too high or too low;
/// the refusal names the register by its seed name.
#[test]
fn x67_18_5_03_read_only_before_the_range() {
    let mut m = Module::new();
    m.step();
    for (reg, value) in [
        (Register::Axis(0, AxisReg::ActVal), 1i64 << 40),
        (Register::Axis(1, AxisReg::Status), -1),
        (Register::Module(ModuleReg::InputStatus), 300),
        (Register::Axis(0, AxisReg::ErrorCode), 70_000),
    ] {
        let err = m.write(reg, value).unwrap_err();
        assert_eq!(err, RegisterError::ReadOnly(reg), "{reg} = {value}");
        assert_eq!(err.abort_code(), 0x0601_0002);
    }
    let act_val = Register::Axis(0, AxisReg::ActVal);
    assert_eq!(act_val.to_string(), "AbsPos01ActVal");
    assert_eq!(
        RegisterError::ReadOnly(act_val).to_string(),
        "AbsPos01ActVal is read-only"
    );
    let max_acc = Register::Axis(1, AxisReg::MaxAcc);
    assert_eq!(
        m.write(max_acc, 70_000).unwrap_err().to_string(),
        "70000 is above the range of MaxAcc02 (at most 65535)"
    );
}

/// X67-18.5-04: DINT, UINT, INT, SINT and USINT are 4, 2, 2, 1 and 1 bytes with their value ranges; a value
/// outside a register's type is refused (0x06090031 above, 0x06090032 below) and the register keeps its
/// value.
#[test]
fn x67_18_5_04_data_types() {
    assert_eq!(
        [Dint, Uint, Int, Sint, Usint].map(RegType::size),
        [4, 2, 2, 1, 1]
    );
    assert_eq!(Dint.range(), (-2_147_483_648, 2_147_483_647));
    assert_eq!(Uint.range(), (0, 65_535));
    assert_eq!(Int.range(), (-32_768, 32_767));
    assert_eq!(Sint.range(), (-128, 127));
    assert_eq!(Usint.range(), (0, 255));

    let mut m = Module::new();
    for (name, low, high, ok) in [
        ("MaxAcc01", -1, 65_536, 65_535),
        ("RevLoop02", -32_769, 32_768, -32_768),
        ("FixedPos01a", -2_147_483_649, 2_147_483_648, -2_147_483_648),
        ("StallDetectConfig02", -1, 256, 255),
        ("GeneralConfig01", -1, 256, 6),
        ("MpGenMode01", -129, 128, -128),
        ("MpGenControl02", -1, 65_536, 65_535),
    ] {
        m.write_named(name, ok).unwrap();
        let reg = Register::from_name(name).unwrap();
        let (min, max) = reg.info().ty.range();
        let high_err = m.write_named(name, high).unwrap_err();
        assert_eq!(
            high_err,
            RegisterError::TooHigh {
                register: reg,
                value: high,
                max
            }
        );
        assert_eq!(high_err.abort_code(), 0x0609_0031);
        let low_err = m.write_named(name, low).unwrap_err();
        assert_eq!(
            low_err,
            RegisterError::TooLow {
                register: reg,
                value: low,
                min
            }
        );
        assert_eq!(low_err.abort_code(), 0x0609_0032);
        assert_eq!(m.read_named(name), ok, "{name}");
    }
}

/// X67-18.5-05: the current registers are USINT configuration registers 48–50 (axis 1) and 112–114
/// (axis 2); above 167 they refuse the write with 0x06090031.
#[test]
fn x67_18_5_05_current_registers() {
    assert_rows(&[
        "ConfigOutput03a",
        "ConfigOutput04a",
        "ConfigOutput05a",
        "ConfigOutput06a",
        "ConfigOutput07a",
        "ConfigOutput08a",
    ]);
    assert_eq!(
        Register::from_name("ConfigOutput06a"),
        Some(Register::Axis(1, AxisReg::HoldingCurrent))
    );
    let mut m = Module::new();
    m.write_named("ConfigOutput08a", 100).unwrap();
    let err = m.write_named("ConfigOutput08a", 200).unwrap_err();
    assert_eq!(err.abort_code(), 0x0609_0031);
    assert_eq!(named(&m, "ConfigOutput08aRead"), 100);
}

/// X67-18.5-06: FullStepThreshold01/02 are registers 72/136, UINT, written acyclically.
#[test]
fn x67_18_5_06_full_step_threshold_registers() {
    assert_rows(&["FullStepThreshold01", "FullStepThreshold02"]);
}

/// X67-18.5-07: MaxSpeed01pos/02pos are registers 52/116, UINT, written acyclically.
#[test]
fn x67_18_5_07_max_speed_registers() {
    assert_rows(&["MaxSpeed01pos", "MaxSpeed02pos"]);
}

/// X67-18.5-08: MaxAcc01/MaxDec01 are 54/56 and MaxAcc02/MaxDec02 118/120, UINT, written acyclically.
#[test]
fn x67_18_5_08_acceleration_registers() {
    assert_rows(&["MaxAcc01", "MaxDec01", "MaxAcc02", "MaxDec02"]);
}

/// X67-18.5-09: RevLoop01/02 are registers 58/122, INT, written acyclically.
#[test]
fn x67_18_5_09_reversing_loop_registers() {
    assert_rows(&["RevLoop01", "RevLoop02"]);
    let mut m = Module::new();
    m.write_named("RevLoop01", -500).unwrap();
    assert_eq!(named(&m, "RevLoop01"), -500);
}

/// X67-18.5-10: FixedPos01a/01b are 60/64 and FixedPos02a/02b 124/128, DINT, written acyclically.
#[test]
fn x67_18_5_10_fixed_position_registers() {
    assert_rows(&["FixedPos01a", "FixedPos01b", "FixedPos02a", "FixedPos02b"]);
}

/// X67-18.5-11: RefSpeed01/02 are registers 68/132, UINT, written acyclically.
#[test]
fn x67_18_5_11_homing_speed_registers() {
    assert_rows(&["RefSpeed01", "RefSpeed02"]);
}

/// X67-18.5-12: RefConfig01/02 are registers 70/134, SINT, written acyclically.
#[test]
fn x67_18_5_12_homing_configuration_registers() {
    assert_rows(&["RefConfig01", "RefConfig02"]);
    let mut m = Module::new();
    m.write_named("RefConfig02", -126).unwrap();
    assert_eq!(named(&m, "RefConfig02"), -126);
}

/// X67-18.5-13: StallDetectConfig01/02 are registers 51/115, USINT, written acyclically.
#[test]
fn x67_18_5_13_stall_detection_registers() {
    assert_rows(&["StallDetectConfig01", "StallDetectConfig02"]);
}

/// X67-18.5-14: StallRecognitionDelay01/02 are registers 74/138, USINT, written acyclically.
#[test]
fn x67_18_5_14_stall_recognition_delay_registers() {
    assert_rows(&["StallRecognitionDelay01", "StallRecognitionDelay02"]);
}

/// X67-18.5-15: JoltTime01/02 are registers 75/139, USINT, written acyclically.
#[test]
fn x67_18_5_15_jolt_time_registers() {
    assert_rows(&["JoltTime01", "JoltTime02"]);
}

/// X67-18.5-16: StallDetectMinSpeed01/02 are registers 78/142, UINT, written acyclically.
#[test]
fn x67_18_5_16_minimum_stall_speed_registers() {
    assert_rows(&["StallDetectMinSpeed01", "StallDetectMinSpeed02"]);
}

/// X67-18.5-17: GeneralConfig01 is register 304, USINT, written acyclically; there is no GeneralConfig02.
#[test]
fn x67_18_5_17_general_configuration_register() {
    assert_rows(&["GeneralConfig01"]);
    assert_eq!(
        Register::from_name("GeneralConfig01"),
        Some(Register::Module(ModuleReg::GeneralConfig))
    );
    assert_eq!(Register::from_name("GeneralConfig02"), None);
}

/// X67-18.5-18: LimitSwitchConfig01/02 are registers 306/308, USINT, written acyclically.
#[test]
fn x67_18_5_18_limit_switch_registers() {
    assert_rows(&["LimitSwitchConfig01", "LimitSwitchConfig02"]);
}

/// X67-18.5-19: PositionLimitMin01/Max01 are 380/384 and Min02/Max02 388/392, DINT, written acyclically.
#[test]
fn x67_18_5_19_software_limit_registers() {
    assert_rows(&[
        "PositionLimitMin01",
        "PositionLimitMax01",
        "PositionLimitMin02",
        "PositionLimitMax02",
    ]);
}

/// X67-18.5-20: ConfigOutput03aRead…08aRead are read acyclically, USINT, with the numbers of the registers
/// they read back (48–50, 112–114).
#[test]
fn x67_18_5_20_current_read_back_registers() {
    assert_rows(&[
        "ConfigOutput03aRead",
        "ConfigOutput04aRead",
        "ConfigOutput05aRead",
        "ConfigOutput06aRead",
        "ConfigOutput07aRead",
        "ConfigOutput08aRead",
    ]);
    for (write, read) in [
        ("ConfigOutput03a", "ConfigOutput03aRead"),
        ("ConfigOutput08a", "ConfigOutput08aRead"),
    ] {
        assert_eq!(
            Register::from_name(write).unwrap().info().number,
            Register::from_name(read).unwrap().info().number
        );
    }
}

/// X67-18.5-21: AbsPos01 (0) and AbsPos02 (8) are DINT cyclic outputs, at output bytes 0–3 of objects 1
/// and 2.
#[test]
fn x67_18_5_21_set_position_registers() {
    assert_rows(&["AbsPos01", "AbsPos02"]);
    let mut m = Module::new();
    m.output_object(0, [1, 2, 3, 4, 0, 0, 0, 0]);
    m.output_object(1, [0xFF, 0xFF, 0xFF, 0xFF, 0, 0, 0, 0]);
    assert_eq!(
        (named(&m, "AbsPos01"), named(&m, "AbsPos02")),
        (0x0403_0201, -1)
    );
}

/// X67-18.5-22: MpGenControl01 (4) and MpGenControl02 (12) are UINT cyclic outputs, at output bytes 4–5.
#[test]
fn x67_18_5_22_control_word_registers() {
    assert_rows(&["MpGenControl01", "MpGenControl02"]);
    let mut m = Module::new();
    m.output_object(0, [0, 0, 0, 0, 0x0F, 0x82, 0, 0]);
    m.output_object(1, [0, 0, 0, 0, 0x06, 0x40, 0, 0]);
    assert_eq!(
        (
            named(&m, "ControlReadback01"),
            named(&m, "ControlReadback02")
        ),
        (0x820F, 0x4006)
    );
}

/// X67-18.5-23: MpGenMode01 (6) and MpGenMode02 (14) are SINT cyclic outputs, at output byte 6.
#[test]
fn x67_18_5_23_mode_registers() {
    assert_rows(&["MpGenMode01", "MpGenMode02"]);
    let mut m = Module::new();
    m.output_object(0, [0, 0, 0, 0, 0, 0, 0x81, 0]);
    m.output_object(1, [0, 0, 0, 0, 0, 0, 0x02, 0]);
    assert_eq!(
        (named(&m, "ModeReadback01"), named(&m, "ModeReadback02")),
        (-127, 2)
    );
}

/// X67-18.5-24: AbsPos01ActVal (0) and AbsPos02ActVal (8) are DINT cyclic inputs, at input bytes 0–3.
#[test]
fn x67_18_5_24_actual_position_registers() {
    assert_rows(&["AbsPos01ActVal", "AbsPos02ActVal"]);
    let mut m = Module::new();
    m.step();
    quadrature(&mut m, 1, -5);
    m.set_control(1, CW_SWAP_COUNTERS);
    m.step();
    assert_eq!(named(&m, "AbsPos02ActVal"), -5);
    assert_eq!(m.input_object(1)[0..4], [0xFB, 0xFF, 0xFF, 0xFF]);
    assert_eq!(m.input_object(0)[0..4], [0, 0, 0, 0]);
}

/// X67-18.5-25: MpGenStatus01 (4) and MpGenStatus02 (12) are UINT cyclic inputs, at input bytes 4–5.
#[test]
fn x67_18_5_25_status_word_registers() {
    assert_rows(&["MpGenStatus01", "MpGenStatus02"]);
    let mut m = Module::new();
    m.step();
    m.set_control(1, SHUTDOWN);
    m.step();
    assert_eq!(named(&m, "MpGenStatus01"), i64::from(m.status_word(0)));
    assert_eq!(m.input_object(0)[4..6], m.status_word(0).to_le_bytes());
    assert_eq!(m.input_object(1)[4..6], m.status_word(1).to_le_bytes());
    assert_eq!(m.input_object(1)[4] & 0x7F, 0x21);
}

/// X67-18.5-26: InputStatus (6) is the one USINT cyclic input of the module, at byte 6 of input object 1.
#[test]
fn x67_18_5_26_input_status_register() {
    assert_rows(&["InputStatus"]);
    assert_eq!(
        Register::all()
            .filter(|r| r.name().starts_with("InputStatus"))
            .count(),
        1
    );
    let mut m = Module::new();
    m.set_input(1, true);
    m.set_input(4, true);
    m.step();
    assert_eq!(m.input_object(0)[6], 0x09);
    assert_eq!(m.input_object(1)[6], 0x00);
}

/// X67-18.5-27: Motoridentification01/02 are registers 84/148, UINT, read acyclically.
#[test]
fn x67_18_5_27_motor_identification_registers() {
    assert_rows(&["Motoridentification01", "Motoridentification02"]);
}

/// X67-18.5-28: Temperature is register 46, SINT, read acyclically, one for the module.
#[test]
fn x67_18_5_28_temperature_register() {
    assert_rows(&["Temperature"]);
    assert_eq!(
        Register::from_name("Temperature"),
        Some(Register::Module(ModuleReg::Temperature))
    );
    assert_eq!(Register::from_name("Temperature01"), None);
}

/// X67-18.5-29: RefPos01/02CyclicCounter are 86/150 and RefPos01/02AcyclicCounter 94/158, DINT, read
/// acyclically.
#[test]
fn x67_18_5_29_reference_position_registers() {
    assert_rows(&[
        "RefPos01CyclicCounter",
        "RefPos01AcyclicCounter",
        "RefPos02CyclicCounter",
        "RefPos02AcyclicCounter",
    ]);
}

/// X67-18.5-30: AbsPos01ActValAcyclic/02 are registers 90/154, DINT, read acyclically.
#[test]
fn x67_18_5_30_acyclic_position_registers() {
    assert_rows(&["AbsPos01ActValAcyclic", "AbsPos02ActValAcyclic"]);
}

/// X67-18.5-31: ControlReadback01/ModeReadback01 are 80/82 and …02 144/146; UINT and SINT, read acyclically.
#[test]
fn x67_18_5_31_read_back_registers() {
    assert_rows(&[
        "ControlReadback01",
        "ModeReadback01",
        "ControlReadback02",
        "ModeReadback02",
    ]);
}

/// X67-18.5-32: ErrorCode01/02 are registers 98/162, UINT, read acyclically.
#[test]
fn x67_18_5_32_error_code_registers() {
    assert_rows(&["ErrorCode01", "ErrorCode02"]);
}

/// X67-18.6.1.4-01: the Ramp model has no register that selects holding, nominal or maximum current at run
/// time (no MotorXStepX, no "Motor current"): no register name of the table mentions one, every writable
/// per-axis register is a configuration or cyclic output of 18.5, and writing every cyclic output of an axis
/// at standstill in Switched on leaves the holding current flowing.
#[test]
fn x67_18_6_1_4_01_no_run_time_current_selection() {
    use ds402::x67::registers::Register;
    for reg in Register::all() {
        let name = reg.name();
        assert!(
            !name.contains("Step") || name.starts_with("FullStep"),
            "{name}"
        );
        assert!(!name.eq_ignore_ascii_case("MotorCurrent"), "{name}");
    }
    let mut m = Module::new();
    set_currents(&mut m, 0, 20, 50, 80);
    switch_on(&mut m, 0);
    m.step();
    assert_eq!(
        (level(&m, 0), milliamps(&m, 0)),
        (Some(Level::Holding), 600)
    );
    // Current-selection bits of function model 0 (bits 14–15 of MotorXStepX) set in every cyclic output.
    m.set_abs_pos(0, i32::from_le_bytes([0, 0xC0, 0, 0xC0]));
    m.set_mode(0, modes::NONE);
    m.set_control(0, SWITCH_ON | 0x4000);
    m.run(10);
    assert_eq!(
        (level(&m, 0), milliamps(&m, 0)),
        (Some(Level::Holding), 600)
    );
}
