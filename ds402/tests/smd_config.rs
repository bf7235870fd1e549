//! Tests of the SMD23K-B / SMD24K configuration data (`ds402::smd::config`) against the rule catalogue
//! `rules/smd.md`, section R5 "Configuration data". Each test names the rule it covers; violations are
//! asserted in full (which invalid-configuration item, which rule, which detail).

use ds402::smd::config::{
    decode_words, Cfg0, Cfg1, Configuration, EncoderKind, InputFunction, InvalidItem, Parameter,
    ValidRange, Violation, Word, CFG1_VALID_VALUES,
};
use proptest::prelude::*;

use EncoderKind::{Absolute, Incremental};
use InputFunction::*;

/// The default (fixture) configuration with one numeric value changed.
fn with(f: impl FnOnce(&mut Configuration)) -> Configuration {
    let mut c = Configuration::default();
    f(&mut c);
    c
}

/// The violations of CFG_Word_0 alone.
fn cfg0_violations(word: u16) -> Vec<Violation> {
    Cfg0::decode(word).1
}

/// The rule IDs of a list of violations.
fn rules(v: &[Violation]) -> Vec<&'static str> {
    v.iter().map(Violation::rule).collect()
}

/// The manual's item numbers of a list of violations.
fn items(v: &[Violation]) -> Vec<u8> {
    v.iter().map(|x| x.item().number()).collect()
}

/// Asserts that `parameter` at `lo`/`hi` is valid and at each of `bad` gives exactly one item-2 violation
/// of `rule` with the range `valid`.
fn check_range(
    set: fn(&mut Configuration, u32),
    parameter: Parameter,
    good: &[u32],
    bad: &[u32],
    valid: ValidRange,
    rule: &str,
) {
    for &v in good {
        let c = with(|c| set(c, v));
        for kind in [Incremental, Absolute] {
            assert_eq!(
                c.violations(kind),
                vec![],
                "{parameter} = {v} should be valid"
            );
            assert!(c.is_valid(kind));
        }
    }
    for &v in bad {
        let c = with(|c| set(c, v));
        for kind in [Incremental, Absolute] {
            let got = c.violations(kind);
            assert_eq!(
                got,
                vec![Violation::OutOfRange {
                    parameter,
                    value: v,
                    valid,
                }],
                "{parameter} = {v}"
            );
            assert_eq!(got[0].item(), InvalidItem::OutOfRange);
            assert_eq!(got[0].item().number(), 2);
            assert_eq!(got[0].rule(), rule);
            assert!(!c.is_valid(kind));
        }
    }
}

/// The fixture defaults: 0, 3, 141, 2000, 2048, 50, 10, valid on both kinds of unit.
#[test]
fn defaults_are_the_fixture_values_and_valid() {
    let c = Configuration::default();
    assert_eq!(
        (
            c.cfg0,
            c.cfg1,
            c.starting_speed,
            c.motor_resolution,
            c.encoder_resolution,
            c.idle_current_reduction,
            c.motor_current
        ),
        (0, 3, 141, 2000, 2048, 50, 10)
    );
    assert!(c.is_valid(Incremental));
    assert!(c.is_valid(Absolute));
    assert_eq!(Cfg0::default().encode(), 0x0000);
    assert_eq!(Cfg1::default().encode(), 0x0003);
}

/// SMD-R5-003: Starting_Speed is valid from 1 to 1,999,999; 0 and 2,000,000 are item 2.
#[test]
fn smd_r5_003_starting_speed_range() {
    check_range(
        |c, v| c.starting_speed = v,
        Parameter::StartingSpeed,
        &[1, 1_999_999],
        &[0, 2_000_000, u32::MAX],
        ValidRange::Between {
            min: 1,
            max: 1_999_999,
        },
        "SMD-R5-003",
    );
    let v = with(|c| c.starting_speed = 0).violations(Incremental);
    assert_eq!(
        v[0].to_string(),
        "invalid configuration 2 (parameter out of range): Starting_Speed (8010:03) is 0 steps/s, \
         valid range 1 to 1,999,999"
    );
}

/// SMD-R5-004: Motor_Resolution is valid from 200 to 32,767; 199 and 32,768 are item 2.
#[test]
fn smd_r5_004_motor_resolution_range() {
    check_range(
        |c, v| c.motor_resolution = v as u16,
        Parameter::MotorResolution,
        &[200, 32_767],
        &[0, 199, 32_768, 65_535],
        ValidRange::Between {
            min: 200,
            max: 32_767,
        },
        "SMD-R5-004",
    );
}

/// SMD-R5-005: with Use_Encoder = 1, Encoder_Resolution must be 1,024, 2,048 or 4,096 (incremental) or
/// 2,048 (absolute). Pick: it is not checked while CFG_Word_0 bit 10 is 0.
#[test]
fn smd_r5_005_encoder_resolution_by_kind() {
    let enc = |r: u16| {
        with(|c| {
            c.cfg0 = 0x0400;
            c.encoder_resolution = r;
        })
    };
    for r in [1024, 2048, 4096] {
        assert_eq!(enc(r).violations(Incremental), vec![], "{r}");
    }
    for r in [0, 1000, 2047, 8192] {
        let v = enc(r).violations(Incremental);
        assert_eq!(
            v,
            vec![Violation::OutOfRange {
                parameter: Parameter::EncoderResolution,
                value: u32::from(r),
                valid: ValidRange::Encoder(Incremental),
            }]
        );
        assert_eq!((items(&v), rules(&v)), (vec![2], vec!["SMD-R5-005"]));
    }
    assert_eq!(enc(2048).violations(Absolute), vec![]);
    for r in [1024, 4096, 1000] {
        let v = enc(r).violations(Absolute);
        assert_eq!(
            v,
            vec![Violation::OutOfRange {
                parameter: Parameter::EncoderResolution,
                value: u32::from(r),
                valid: ValidRange::Encoder(Absolute),
            }]
        );
        assert_eq!(v[0].rule(), "SMD-R5-005");
    }
    assert_eq!(
        enc(1000).violations(Incremental)[0].to_string(),
        "invalid configuration 2 (parameter out of range): Encoder_Resolution (8010:05) is 1,000 \
         counts per turn, valid values for an incremental encoder 1,024, 2,048 or 4,096"
    );
    assert_eq!(
        enc(4096).violations(Absolute)[0].to_string(),
        "invalid configuration 2 (parameter out of range): Encoder_Resolution (8010:05) is 4,096 \
         counts per turn, valid value for an absolute encoder 2,048"
    );
    // Pick: encoder not used → Encoder_Resolution not checked.
    for r in [0, 1000, 4096] {
        let c = with(|c| c.encoder_resolution = r);
        assert_eq!(c.violations(Incremental), vec![]);
        assert_eq!(c.violations(Absolute), vec![]);
    }
    // Stall detection without encoder: only item 4, the resolution is still not checked.
    let c = with(|c| {
        c.cfg0 = 0x2000;
        c.encoder_resolution = 0;
    });
    assert_eq!(
        c.violations(Incremental),
        vec![Violation::StallWithoutEncoder]
    );
}

/// SMD-R5-006: Idle_current_reduction is valid from 0 to 100 %; 101 is item 2.
#[test]
fn smd_r5_006_idle_current_reduction_range() {
    check_range(
        |c, v| c.idle_current_reduction = v as u16,
        Parameter::IdleCurrentReduction,
        &[0, 100],
        &[101, 65_535],
        ValidRange::Between { min: 0, max: 100 },
        "SMD-R5-006",
    );
}

/// SMD-R5-007: Motor_Current is valid from 1 to 34 (0.1 to 3.4 Arms); 0 and 35 are item 2.
#[test]
fn smd_r5_007_motor_current_range() {
    check_range(
        |c, v| c.motor_current = v as u16,
        Parameter::MotorCurrent,
        &[1, 34],
        &[0, 35],
        ValidRange::Between { min: 1, max: 34 },
        "SMD-R5-007",
    );
}

/// SMD-R5-009: CFG_Word_0 bit 15 is ignored (pick: no error); 0x8000 behaves as 0x0000.
#[test]
fn smd_r5_009_cfg0_bit_15_ignored() {
    assert_eq!(cfg0_violations(0x8000), vec![]);
    assert_eq!(Cfg0::from_word(0x8000), Cfg0::from_word(0x0000));
    assert_eq!(Cfg0::from_word(0x8000).encode(), 0x0000);
    assert_eq!(Cfg0::from_word(0xA411), Cfg0::from_word(0x2411));
    assert!(with(|c| c.cfg0 = 0x8000).is_valid(Incremental));
}

/// SMD-R5-010: CFG_Word_0 bit 14 Disable_Antiresonance is valid either way.
#[test]
fn smd_r5_010_cfg0_bit_14_antiresonance_valid_either_way() {
    for (word, off) in [(0x0000, false), (0x4000, true)] {
        let (cfg, v) = Cfg0::decode(word);
        assert_eq!(v, vec![]);
        assert_eq!(cfg.disable_antiresonance, off);
        assert_eq!(
            Cfg0 {
                disable_antiresonance: off,
                ..Cfg0::default()
            }
            .encode(),
            word
        );
    }
}

/// SMD-R5-011: bit 13 Enable_Stall_Detection without bit 10 Use_Encoder is item 4; 0x2400 is valid.
#[test]
fn smd_r5_011_stall_detection_needs_encoder() {
    let v = cfg0_violations(0x2000);
    assert_eq!(v, vec![Violation::StallWithoutEncoder]);
    assert_eq!((items(&v), rules(&v)), (vec![4], vec!["SMD-R5-011"]));
    assert_eq!(
        v[0].to_string(),
        "invalid configuration 4 (stall detection without encoder): CFG_Word_0 bit 13 \
         Enable_Stall_Detection is 1 but bit 10 Use_Encoder is 0"
    );
    assert_eq!(cfg0_violations(0x2400), vec![]);
    assert!(with(|c| c.cfg0 = 0x2400).is_valid(Incremental));
    assert_eq!(
        with(|c| c.cfg0 = 0x2000).violations(Absolute),
        vec![Violation::StallWithoutEncoder]
    );
}

/// SMD-R5-012: CFG_Word_0 bit 12 is reserved and must be 0; 0x1000 is item 1.
#[test]
fn smd_r5_012_cfg0_bit_12_reserved() {
    let v = cfg0_violations(0x1000);
    assert_eq!(
        v,
        vec![Violation::ReservedBit {
            word: Word::Cfg0,
            bit: 12
        }]
    );
    assert_eq!((items(&v), rules(&v)), (vec![1], vec!["SMD-R5-012"]));
    assert_eq!(
        v[0].to_string(),
        "invalid configuration 1 (reserved bit): CFG_Word_0 bit 12 is reserved and must be 0"
    );
    assert_eq!(Cfg0::from_word(0x1000).reserved, 0x1000);
    assert_eq!(Cfg0::from_word(0x1000).encode(), 0x1000);
}

/// SMD-R5-013: CFG_Word_0 bits 9–6 are reserved and must be 0; each is its own item-1 violation.
#[test]
fn smd_r5_013_cfg0_bits_9_to_6_reserved() {
    for bit in 6..=9u8 {
        let v = cfg0_violations(1 << bit);
        assert_eq!(
            v,
            vec![Violation::ReservedBit {
                word: Word::Cfg0,
                bit
            }]
        );
        assert_eq!((items(&v), rules(&v)), (vec![1], vec!["SMD-R5-013"]));
    }
    let v = cfg0_violations(0x13C0);
    assert_eq!(
        v,
        [6, 7, 8, 9, 12]
            .map(|bit| Violation::ReservedBit {
                word: Word::Cfg0,
                bit
            })
            .to_vec()
    );
    assert_eq!(
        rules(&v),
        vec![
            "SMD-R5-013",
            "SMD-R5-013",
            "SMD-R5-013",
            "SMD-R5-013",
            "SMD-R5-012"
        ]
    );
}

/// SMD-R5-014: CFG_Word_0 bit 10 is Use_Encoder, valid either way; it switches the Encoder_Resolution
/// check on (see SMD-R5-005).
#[test]
fn smd_r5_014_cfg0_bit_10_use_encoder() {
    let (cfg, v) = Cfg0::decode(0x0400);
    assert_eq!(v, vec![]);
    assert!(cfg.use_encoder);
    assert!(!Cfg0::from_word(0x0000).use_encoder);
    assert_eq!(
        Cfg0 {
            use_encoder: true,
            ..Cfg0::default()
        }
        .encode(),
        0x0400
    );
    let bad_res = |cfg0| {
        with(|c| {
            c.cfg0 = cfg0;
            c.encoder_resolution = 1000;
        })
    };
    assert!(bad_res(0x0000).is_valid(Incremental));
    assert_eq!(
        rules(&bad_res(0x0400).violations(Incremental)),
        vec!["SMD-R5-005"]
    );
}

/// SMD-R5-015: CFG_Word_0 bit 11 Use_Backplane_Proximity is valid either way.
#[test]
fn smd_r5_015_cfg0_bit_11_backplane_proximity() {
    for (word, on) in [(0x0000, false), (0x0800, true), (0x0C00, true)] {
        let (cfg, v) = Cfg0::decode(word);
        assert_eq!(v, vec![]);
        assert_eq!(cfg.use_backplane_proximity, on);
    }
    assert_eq!(
        Cfg0 {
            use_backplane_proximity: true,
            ..Cfg0::default()
        }
        .encode(),
        0x0800
    );
}

/// SMD-R5-016: bits 2–0 are Input 1's function and bits 5–3 Input 2's, with the codes of table R5.2;
/// 0x000E is IN1 Home, IN2 CW Limit.
#[test]
fn smd_r5_016_input_function_codes() {
    let expected = [
        (0b000, GeneralPurpose, "general-purpose", "General Purpose"),
        (0b001, CwLimit, "cw-limit", "CW Limit"),
        (0b010, CcwLimit, "ccw-limit", "CCW Limit"),
        (
            0b011,
            StartIndexed,
            "start-indexed",
            "Start Indexed Move/Capture",
        ),
        (
            0b100,
            StopJog,
            "stop-jog",
            "Stop Jog or Registration/Capture",
        ),
        (0b101, EStop, "e-stop", "Emergency Stop"),
        (0b110, Home, "home", "Home"),
    ];
    assert_eq!(InputFunction::ALL.len(), 7);
    for (code, f, name, manual) in expected {
        assert_eq!(f.code(), code);
        assert_eq!(u8::from(f), code);
        assert_eq!(InputFunction::from_code(code), Some(f));
        assert_eq!(InputFunction::try_from(code), Ok(f));
        assert_eq!(f.name(), name);
        assert_eq!(name.parse::<InputFunction>(), Ok(f));
        assert_eq!(name.to_uppercase().parse::<InputFunction>(), Ok(f));
        assert_eq!(f.manual_name(), manual);
        assert_eq!(f.to_string(), manual);
        // Input 1 in bits 2–0, Input 2 in bits 5–3.
        let w1 = u16::from(code);
        let w2 = u16::from(code) << 3;
        assert_eq!(Cfg0::from_word(w1).input1, Some(f));
        assert_eq!(Cfg0::from_word(w1).input2, Some(GeneralPurpose));
        assert_eq!(Cfg0::from_word(w2).input2, Some(f));
        assert_eq!(Cfg0::from_word(w2).input1, Some(GeneralPurpose));
        assert_eq!(cfg0_violations(w1), vec![]);
        assert_eq!(cfg0_violations(w2), vec![]);
    }
    assert_eq!(InputFunction::from_code(0b111), None);
    assert_eq!(InputFunction::from_code(8), None);
    assert!(InputFunction::try_from(7).is_err());
    assert!("cw limit".parse::<InputFunction>().is_err());
    let cfg = Cfg0::from_word(0x000E);
    assert_eq!((cfg.input1, cfg.input2), (Some(Home), Some(CwLimit)));
    assert_eq!(Cfg0::with_inputs(Home, CwLimit).encode(), 0x000E);
}

/// SMD-R5-017: function code 111 on either input is item 5, one violation per input.
#[test]
fn smd_r5_017_input_code_111() {
    let v = cfg0_violations(0x0007);
    assert_eq!(v, vec![Violation::InputCode111 { input: 1 }]);
    assert_eq!((items(&v), rules(&v)), (vec![5], vec!["SMD-R5-017"]));
    assert_eq!(
        v[0].to_string(),
        "invalid configuration 5 (input code 111): Input 1 function (CFG_Word_0 bits 2–0) is 111, \
         a reserved combination"
    );
    let v = cfg0_violations(0x0038);
    assert_eq!(v, vec![Violation::InputCode111 { input: 2 }]);
    assert_eq!(rules(&v), vec!["SMD-R5-017"]);
    // Both 111: two item-5 violations and no item 3 (111 is no function).
    assert_eq!(
        cfg0_violations(0x003F),
        vec![
            Violation::InputCode111 { input: 1 },
            Violation::InputCode111 { input: 2 }
        ]
    );
    assert_eq!(Cfg0::from_word(0x0007).input1, None);
    assert_eq!(Cfg0::from_word(0x0007).encode(), 0x0007);
}

/// SMD-R5-018: both inputs with the same function is item 3, except both General Purpose.
#[test]
fn smd_r5_018_same_function_on_both_inputs() {
    let v = cfg0_violations(0x0009);
    assert_eq!(v, vec![Violation::SameFunction { function: CwLimit }]);
    assert_eq!((items(&v), rules(&v)), (vec![3], vec!["SMD-R5-018"]));
    assert_eq!(
        v[0].to_string(),
        "invalid configuration 3 (same function on both inputs): Input 1 and Input 2 are both CW \
         Limit; only General Purpose may be given to both"
    );
    assert_eq!(
        cfg0_violations(0x0036),
        vec![Violation::SameFunction { function: Home }]
    );
    assert_eq!(cfg0_violations(0x0000), vec![]);
    for f in InputFunction::ALL {
        let v = Cfg0::with_inputs(f, f).violations();
        if f == GeneralPurpose {
            assert_eq!(v, vec![]);
        } else {
            assert_eq!(v, vec![Violation::SameFunction { function: f }], "{f}");
        }
    }
}

/// SMD-R5-019: code 011 Start Indexed Move/Capture is a valid function on either input, with or
/// without the encoder.
#[test]
fn smd_r5_019_start_indexed_code_011() {
    for word in [0x0003, 0x0018, 0x0403, 0x0418] {
        let (cfg, v) = Cfg0::decode(word);
        assert_eq!(v, vec![]);
        assert!(cfg.input1 == Some(StartIndexed) || cfg.input2 == Some(StartIndexed));
    }
    assert_eq!(
        Cfg0::with_inputs(StartIndexed, GeneralPurpose).encode(),
        0x0003
    );
    assert_eq!(
        Cfg0::with_inputs(GeneralPurpose, StartIndexed).encode(),
        0x0018
    );
}

/// SMD-R5-020: code 101 Emergency Stop is a valid function on either input.
#[test]
fn smd_r5_020_emergency_stop_code_101() {
    for (word, cfg) in [
        (0x0005, Cfg0::with_inputs(EStop, GeneralPurpose)),
        (0x0028, Cfg0::with_inputs(GeneralPurpose, EStop)),
        (0x002E, Cfg0::with_inputs(Home, EStop)),
    ] {
        assert_eq!(Cfg0::decode(word), (cfg, vec![]));
        assert_eq!(cfg.encode(), word);
    }
    assert_eq!(
        cfg0_violations(0x002D),
        vec![Violation::SameFunction { function: EStop }]
    );
}

/// SMD-R5-021: the derived Table R5.3 vectors: 0x240E, 0x0C1E and 0x4000 are valid, 0x2006 is not.
#[test]
fn smd_r5_021_table_r5_3_vectors() {
    // 0x240E: stall + encoder, IN2 CW Limit, IN1 Home.
    let c = Cfg0 {
        input1: Some(Home),
        input2: Some(CwLimit),
        use_encoder: true,
        enable_stall_detection: true,
        ..Cfg0::default()
    };
    assert_eq!(c.encode(), 0x240E);
    assert_eq!(Cfg0::decode(0x240E), (c, vec![]));
    // 0x0C1E: proximity + encoder, IN2 Start Indexed, IN1 Home.
    let c = Cfg0 {
        input1: Some(Home),
        input2: Some(StartIndexed),
        use_encoder: true,
        use_backplane_proximity: true,
        ..Cfg0::default()
    };
    assert_eq!(c.encode(), 0x0C1E);
    assert_eq!(Cfg0::decode(0x0C1E), (c, vec![]));
    // 0x2006: stall without encoder, IN1 Home, IN2 General Purpose.
    let c = Cfg0 {
        input1: Some(Home),
        enable_stall_detection: true,
        ..Cfg0::default()
    };
    assert_eq!(c.encode(), 0x2006);
    assert_eq!(
        Cfg0::decode(0x2006),
        (c, vec![Violation::StallWithoutEncoder])
    );
    // 0x4000: anti-resonance off, both inputs General Purpose.
    let c = Cfg0 {
        disable_antiresonance: true,
        ..Cfg0::default()
    };
    assert_eq!(c.encode(), 0x4000);
    assert_eq!(Cfg0::decode(0x4000), (c, vec![]));
    for (word, valid) in [
        (0x240E, true),
        (0x0C1E, true),
        (0x2006, false),
        (0x4000, true),
    ] {
        assert_eq!(
            with(|c| c.cfg0 = word).is_valid(Incremental),
            valid,
            "{word:#06X}"
        );
    }
}

/// The brief's example: IN1 CW Limit, IN2 CCW Limit, encoder and stall detection → 0x2411, valid.
#[test]
fn cfg0_example_0x2411() {
    let c = Cfg0 {
        input1: Some(CwLimit),
        input2: Some(CcwLimit),
        use_encoder: true,
        enable_stall_detection: true,
        ..Cfg0::default()
    };
    assert_eq!(c.encode(), 0x2411);
    assert_eq!(Cfg0::decode(0x2411), (c, vec![]));
    assert_eq!(
        c.to_string(),
        "Input 1: CW Limit\nInput 2: CCW Limit\nUse_Encoder: yes\nUse_Backplane_Proximity: no\n\
         Enable_Stall_Detection: yes\nDisable_Antiresonance: no\nReserved bits set: none"
    );
    let d = decode_words(0x2411, Some(0x0003));
    assert!(d.is_valid());
    assert_eq!(d.cfg0, c);
    assert_eq!(d.cfg1, Some(Cfg1::default()));
    assert_eq!(
        d.to_string(),
        "CFG_Word_0 = 0x2411\nInput 1: CW Limit\nInput 2: CCW Limit\nUse_Encoder: yes\n\
         Use_Backplane_Proximity: no\nEnable_Stall_Detection: yes\nDisable_Antiresonance: no\n\
         Reserved bits set: none\nCFG_Word_1 = 0x0003\n\
         IN1_Active_Level: 1 (active when current flows, normally open)\n\
         IN2_Active_Level: 1 (active when current flows, normally open)\n\
         DC_Sync: no (moves start when data is read from the ESC)\nReserved bits set: none\nValid: yes"
    );
}

/// SMD-R5-001: object `8010` holds CFG_Word_0 at sub-index 01, CFG_Word_1 at 02 and the five
/// parameters at 03 … 07 (Table R5.1: Starting_Speed, Motor_Resolution, Encoder_Resolution,
/// Idle_current_reduction, Motor_Current).
#[test]
fn smd_r5_001_sub_indices_of_8010() {
    assert_eq!(Word::Cfg0.sub_index(), 0x01);
    assert_eq!(Word::Cfg1.sub_index(), 0x02);
    assert_eq!(
        Parameter::ALL.map(|p| (p.name(), p.sub_index())),
        [
            ("Starting_Speed", 0x03),
            ("Motor_Resolution", 0x04),
            ("Encoder_Resolution", 0x05),
            ("Idle_current_reduction", 0x06),
            ("Motor_Current", 0x07),
        ]
    );
}

/// SMD-R5-001: the seven values of `8010` printed one per line with their sub-index, the words in hex
/// and Motor_Current (×0.1 Arms, Table R5.1) also in amperes: the fixture defaults (10 = 1.0 Arms)
/// and the highest valid values (34 = 3.4 Arms), and 5 = 0.5 Arms.
#[test]
fn smd_r5_001_configuration_printed() {
    assert_eq!(
        Configuration::default().to_string(),
        "8010:01 CFG_Word_0 = 0x0000\n\
         8010:02 CFG_Word_1 = 0x0003\n\
         8010:03 Starting_Speed = 141 steps/s\n\
         8010:04 Motor_Resolution = 2000 steps per turn\n\
         8010:05 Encoder_Resolution = 2048 counts per turn\n\
         8010:06 Idle_current_reduction = 50 %\n\
         8010:07 Motor_Current = 10 (1.0 Arms)"
    );
    let high = Configuration {
        cfg0: 0x2411,
        cfg1: 0x0043,
        starting_speed: 1_999_999,
        motor_resolution: 32_767,
        encoder_resolution: 4096,
        idle_current_reduction: 100,
        motor_current: 34,
    };
    assert_eq!(
        high.to_string(),
        "8010:01 CFG_Word_0 = 0x2411\n\
         8010:02 CFG_Word_1 = 0x0043\n\
         8010:03 Starting_Speed = 1999999 steps/s\n\
         8010:04 Motor_Resolution = 32767 steps per turn\n\
         8010:05 Encoder_Resolution = 4096 counts per turn\n\
         8010:06 Idle_current_reduction = 100 %\n\
         8010:07 Motor_Current = 34 (3.4 Arms)"
    );
    assert!(with(|c| c.motor_current = 5)
        .to_string()
        .ends_with("\n8010:07 Motor_Current = 5 (0.5 Arms)"));
}

/// decode_words lists the violations of both words, CFG_Word_0's first, and prints them.
#[test]
fn decode_words_reports_both_words() {
    let d = decode_words(0x1007, Some(0x0044));
    assert_eq!(
        d.violations,
        vec![
            Violation::ReservedBit {
                word: Word::Cfg0,
                bit: 12
            },
            Violation::InputCode111 { input: 1 },
            Violation::ReservedBit {
                word: Word::Cfg1,
                bit: 2
            },
        ]
    );
    assert!(!d.is_valid());
    let text = d.to_string();
    assert!(
        text.contains("Input 1: Invalid Combination (111)\n"),
        "{text}"
    );
    assert!(text.contains("Reserved bits set: 12\n"), "{text}");
    assert!(
        text.contains("DC_Sync: yes (moves start on SYNC0)\n"),
        "{text}"
    );
    assert!(text.contains(
        "Valid: no\n  invalid configuration 1 (reserved bit): CFG_Word_0 bit 12 is reserved and must be 0 [SMD-R5-012]"
    ));
    assert!(text.ends_with(
        "invalid configuration 1 (reserved bit): CFG_Word_1 bit 2 is reserved and must be 0 [SMD-R5-025]"
    ));
    let d = decode_words(0x0000, None);
    assert_eq!(d.cfg1, None);
    assert!(!d.to_string().contains("CFG_Word_1"));
}

/// SMD-R5-025: the only valid CFG_Word_1 values are 0–3 and 64–67; every reserved bit among 14–7 and
/// 5–2 is an item-1 violation. Pick: bit 15 is masked off, so 0x8043 counts as 0x0043.
#[test]
fn smd_r5_025_cfg1_valid_values() {
    for w in CFG1_VALID_VALUES {
        assert_eq!(Cfg1::decode(w).1, vec![], "{w:#06X}");
        assert_eq!(Cfg1::decode(w | 0x8000).1, vec![], "{:#06X}", w | 0x8000);
    }
    for (w, bit) in [(0x0004, 2), (0x0020, 5), (0x0080, 7), (0x4000, 14)] {
        let v = Cfg1::decode(w).1;
        assert_eq!(
            v,
            vec![Violation::ReservedBit {
                word: Word::Cfg1,
                bit
            }]
        );
        assert_eq!((items(&v), rules(&v)), (vec![1], vec!["SMD-R5-025"]));
        assert!(!with(|c| c.cfg1 = w).is_valid(Incremental));
    }
    // Exhaustive: valid exactly when the value (bit 15 masked) is in the list.
    for w in 0..=u16::MAX {
        assert_eq!(
            Cfg1::from_word(w).is_valid(),
            CFG1_VALID_VALUES.contains(&(w & 0x7FFF)),
            "{w:#06X}"
        );
    }
    let c = Cfg1::from_word(0x8043);
    assert_eq!(c, Cfg1::from_word(0x0043));
    assert_eq!(
        (c.in1_active_level, c.in2_active_level, c.dc_sync),
        (true, true, true)
    );
    let c = Cfg1::from_word(0x0002);
    assert_eq!(
        (c.in1_active_level, c.in2_active_level, c.dc_sync),
        (false, true, false)
    );
    assert_eq!(
        Cfg1 {
            in1_active_level: true,
            in2_active_level: false,
            dc_sync: true,
            reserved: 0
        }
        .encode(),
        0x0041
    );
    assert_eq!(
        Cfg1::from_word(0x0041).to_string(),
        "IN1_Active_Level: 1 (active when current flows, normally open)\n\
         IN2_Active_Level: 0 (active when no current flows, normally closed)\n\
         DC_Sync: yes (moves start on SYNC0)\nReserved bits set: none"
    );
    assert!(with(|c| c.cfg1 = 0x8043).is_valid(Absolute));
}

/// SMD-R5-026: the configuration is invalid whenever any of the five items applies, and every broken
/// rule is reported; writing valid values over the offending ones makes it valid again.
#[test]
fn smd_r5_026_every_violation_reported() {
    let bad = Configuration {
        cfg0: 0x3049, // bit 12, bit 6, IN1 CW + IN2 CW, stall without encoder
        cfg1: 0x0083,
        starting_speed: 0,
        motor_resolution: 100,
        encoder_resolution: 1000, // not checked: encoder off
        idle_current_reduction: 101,
        motor_current: 35,
    };
    let v = bad.violations(Incremental);
    assert_eq!(
        v,
        vec![
            Violation::ReservedBit {
                word: Word::Cfg0,
                bit: 6
            },
            Violation::ReservedBit {
                word: Word::Cfg0,
                bit: 12
            },
            Violation::SameFunction { function: CwLimit },
            Violation::StallWithoutEncoder,
            Violation::ReservedBit {
                word: Word::Cfg1,
                bit: 7
            },
            Violation::OutOfRange {
                parameter: Parameter::StartingSpeed,
                value: 0,
                valid: ValidRange::Between {
                    min: 1,
                    max: 1_999_999
                }
            },
            Violation::OutOfRange {
                parameter: Parameter::MotorResolution,
                value: 100,
                valid: ValidRange::Between {
                    min: 200,
                    max: 32_767
                }
            },
            Violation::OutOfRange {
                parameter: Parameter::IdleCurrentReduction,
                value: 101,
                valid: ValidRange::Between { min: 0, max: 100 }
            },
            Violation::OutOfRange {
                parameter: Parameter::MotorCurrent,
                value: 35,
                valid: ValidRange::Between { min: 1, max: 34 }
            },
        ]
    );
    assert_eq!(items(&v), vec![1, 1, 3, 4, 1, 2, 2, 2, 2]);
    assert_eq!(
        rules(&v),
        vec![
            "SMD-R5-013",
            "SMD-R5-012",
            "SMD-R5-018",
            "SMD-R5-011",
            "SMD-R5-025",
            "SMD-R5-003",
            "SMD-R5-004",
            "SMD-R5-006",
            "SMD-R5-007"
        ]
    );
    assert!(!bad.is_valid(Incremental));
    // Item 5 too, and the encoder resolution once the encoder is on.
    let v = Configuration {
        cfg0: 0x043F,
        encoder_resolution: 1000,
        ..Configuration::default()
    }
    .violations(Absolute);
    assert_eq!(items(&v), vec![5, 5, 2]);
    assert_eq!(rules(&v), vec!["SMD-R5-017", "SMD-R5-017", "SMD-R5-005"]);
    // Overwrite the offending values one by one: valid at the end, with nothing else needed.
    let mut c = bad;
    c.cfg0 = 0x2411;
    c.cfg1 = 0x0003;
    c.starting_speed = 1;
    c.motor_resolution = 200;
    assert_eq!(items(&c.violations(Incremental)), vec![2, 2, 2]);
    c.encoder_resolution = 2048;
    c.idle_current_reduction = 100;
    c.motor_current = 34;
    assert_eq!(c.violations(Incremental), vec![]);
    assert!(c.is_valid(Incremental) && c.is_valid(Absolute));
}

/// Every message starts with "invalid configuration N (title): ".
#[test]
fn violation_messages_name_the_item() {
    let all = [
        (InvalidItem::ReservedBit, 1, "reserved bit"),
        (InvalidItem::OutOfRange, 2, "parameter out of range"),
        (InvalidItem::SameFunction, 3, "same function on both inputs"),
        (
            InvalidItem::StallWithoutEncoder,
            4,
            "stall detection without encoder",
        ),
        (InvalidItem::InputCode111, 5, "input code 111"),
    ];
    for (item, n, title) in all {
        assert_eq!(item.number(), n);
        assert_eq!(item.title(), title);
        assert_eq!(
            item.to_string(),
            format!("invalid configuration {n} ({title})")
        );
    }
    let c = Configuration {
        cfg0: 0x3049,
        motor_current: 0,
        ..Configuration::default()
    };
    for v in c.violations(Incremental) {
        assert!(v.to_string().starts_with(&format!("{}: ", v.item())), "{v}");
    }
    assert_eq!(
        with(|c| c.motor_current = 35).violations(Incremental)[0].to_string(),
        "invalid configuration 2 (parameter out of range): Motor_Current (8010:07) is 35 (×0.1 Arms), \
         valid range 1 to 34"
    );
    assert_eq!("Absolute".parse::<EncoderKind>(), Ok(Absolute));
    assert_eq!("incremental".parse::<EncoderKind>(), Ok(Incremental));
    assert!("optical".parse::<EncoderKind>().is_err());
}

/// Round trip: every valid pair of input functions with every flag combination encodes to a valid word
/// that decodes back to the same settings.
#[test]
fn round_trip_all_valid_input_pairs() {
    let mut valid = 0;
    for a in InputFunction::ALL {
        for b in InputFunction::ALL {
            for flags in 0..16u8 {
                let c = Cfg0 {
                    input1: Some(a),
                    input2: Some(b),
                    use_encoder: flags & 1 != 0,
                    use_backplane_proximity: flags & 2 != 0,
                    enable_stall_detection: flags & 4 != 0,
                    disable_antiresonance: flags & 8 != 0,
                    reserved: 0,
                };
                let w = c.encode();
                assert_eq!(w & 0x7, u16::from(a.code()));
                assert_eq!((w >> 3) & 0x7, u16::from(b.code()));
                assert_eq!(w & 0x93C0, 0, "{w:#06X}");
                assert_eq!(Cfg0::from_word(w), c);
                let pair_ok = a != b || a == GeneralPurpose;
                let stall_ok = !c.enable_stall_detection || c.use_encoder;
                assert_eq!(c.is_valid(), pair_ok && stall_ok, "{w:#06X}");
                if c.is_valid() {
                    valid += 1;
                }
            }
        }
    }
    // 43 allowed pairs (49 minus 6 duplicates) × 12 allowed flag combinations.
    assert_eq!(valid, 43 * 12);
}

proptest! {
    /// Decoding keeps every bit but 15: from_word(w).encode() == w & 0x7FFF, in both words.
    #[test]
    fn decode_encode_is_lossless(w in any::<u16>()) {
        prop_assert_eq!(Cfg0::from_word(w).encode(), w & 0x7FFF);
        prop_assert_eq!(Cfg1::from_word(w).encode(), w & 0x7FFF);
    }

    /// Bit 15 is ignored in both words: same settings, same violations (SMD-R5-009, SMD-R5-025).
    #[test]
    fn bit_15_ignored_in_both_words(w0 in any::<u16>(), w1 in any::<u16>()) {
        prop_assert_eq!(Cfg0::decode(w0 ^ 0x8000), Cfg0::decode(w0));
        prop_assert_eq!(Cfg1::decode(w1 ^ 0x8000), Cfg1::decode(w1));
        let c = Configuration { cfg0: w0, cfg1: w1, ..Configuration::default() };
        let d = Configuration { cfg0: w0 ^ 0x8000, cfg1: w1 ^ 0x8000, ..c };
        prop_assert_eq!(c.violations(Incremental), d.violations(Incremental));
        prop_assert_eq!(c.violations(Absolute), d.violations(Absolute));
    }

    /// Any valid pair of functions with any flags round-trips through encode/decode.
    #[test]
    fn valid_pairs_round_trip(a in 0u8..7, b in 0u8..7, flags in 0u8..16) {
        let c = Cfg0 {
            input1: InputFunction::from_code(a),
            input2: InputFunction::from_code(b),
            use_encoder: flags & 1 != 0,
            use_backplane_proximity: flags & 2 != 0,
            enable_stall_detection: flags & 4 != 0,
            disable_antiresonance: flags & 8 != 0,
            reserved: 0,
        };
        let (back, v) = Cfg0::decode(c.encode());
        prop_assert_eq!(back, c);
        let only_pair_or_stall = v.iter().all(|x| {
            matches!(
                x,
                Violation::SameFunction { .. } | Violation::StallWithoutEncoder
            )
        });
        prop_assert!(only_pair_or_stall, "{:?}", v);
    }

    /// The word-level violations of a Configuration are exactly those of its two words when the
    /// numeric values are valid.
    #[test]
    fn configuration_word_violations_match(w0 in any::<u16>(), w1 in any::<u16>()) {
        let c = Configuration { cfg0: w0, cfg1: w1, ..Configuration::default() };
        let mut expected = Cfg0::decode(w0).1;
        expected.extend(Cfg1::decode(w1).1);
        prop_assert_eq!(c.violations(Incremental), expected.clone());
        prop_assert_eq!(decode_words(w0, Some(w1)).violations, expected);
    }
}
