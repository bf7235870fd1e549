//! The configuration rules of R5 as a master sees them: values downloaded to `8010:01` … `8010:07`
//! through the unit, Configuration_Error (STATUS_word0 bit 13) and the motion that follows, rather than
//! the checks of `ds402::smd::config` alone (those are in `smd_config.rs`).

mod smd_rig;

use ds402::smd::config::{Configuration, EncoderKind};
use ds402::smd::indexer::{cmd0, cmd1, stat0, Indexer, Outputs};
use smd_rig::{Rig, MS};

/// A fresh unit of `kind` with the default configuration, one cycle run.
fn unit(kind: EncoderKind) -> Rig {
    let mut ix = Indexer::new(kind, Configuration::default());
    ix.start(std::time::Instant::now(), MS);
    let last = ix.cycle(Outputs::default(), MS);
    Rig {
        ix,
        out: Outputs::default(),
        last,
    }
}

/// STATUS_word0 bit 13 after the downloads `writes` (sub-index, value) to a fresh unit of `kind`.
fn configuration_error(kind: EncoderKind, writes: &[(u8, u32)]) -> bool {
    let mut r = unit(kind);
    assert_eq!(r.s0() & stat0::CONFIGURATION_ERROR, 0);
    for &(sub, value) in writes {
        assert!(r.ix.write_config(r.now(), sub, value));
    }
    r.cycle();
    r.s0() & stat0::CONFIGURATION_ERROR != 0
}

/// A case: its name, the encoder kind, the downloads (sub-index, value), Configuration_Error after them.
type Case = (&'static str, EncoderKind, &'static [(u8, u32)], bool);

/// SMD-R5-003, SMD-R5-004, SMD-R5-005, SMD-R5-006, SMD-R5-009, SMD-R5-010, SMD-R5-013, SMD-R5-015,
/// SMD-R5-021, SMD-R5-026:
/// each value at and beyond its bounds, downloaded to the unit, and Configuration_Error as the manual's
/// tables give it: Starting_Speed 1 … 1,999,999; Motor_Resolution 200 … 32,767; Encoder_Resolution
/// 1,024, 2,048 or 4,096 with the incremental encoder and 2,048 with the absolute one (checked with
/// Use_Encoder on); Idle_current_reduction 0 … 100; CFG_Word_0 bits 15 and 14 and 11 free, bits 9–6
/// reserved; and the derived words of Table R5.3.
#[test]
fn smd_r5_values_downloaded_to_the_unit() {
    use EncoderKind::{Absolute, Incremental};
    let cases: &[Case] = &[
        ("SMD-R5-003 Starting_Speed 1", Incremental, &[(3, 1)], false),
        (
            "SMD-R5-003 Starting_Speed 1,999,999",
            Incremental,
            &[(3, 1_999_999)],
            false,
        ),
        ("SMD-R5-003 Starting_Speed 0", Incremental, &[(3, 0)], true),
        (
            "SMD-R5-003 Starting_Speed 2,000,000",
            Incremental,
            &[(3, 2_000_000)],
            true,
        ),
        (
            "SMD-R5-004 Motor_Resolution 200",
            Incremental,
            &[(4, 200)],
            false,
        ),
        (
            "SMD-R5-004 Motor_Resolution 32,767",
            Incremental,
            &[(4, 32_767)],
            false,
        ),
        (
            "SMD-R5-004 Motor_Resolution 199",
            Incremental,
            &[(4, 199)],
            true,
        ),
        (
            "SMD-R5-004 Motor_Resolution 32,768",
            Incremental,
            &[(4, 32_768)],
            true,
        ),
        (
            "SMD-R5-005 1,024 incremental",
            Incremental,
            &[(1, 0x0400), (5, 1_024)],
            false,
        ),
        (
            "SMD-R5-005 4,096 incremental",
            Incremental,
            &[(1, 0x0400), (5, 4_096)],
            false,
        ),
        (
            "SMD-R5-005 1,000 incremental",
            Incremental,
            &[(1, 0x0400), (5, 1_000)],
            true,
        ),
        (
            "SMD-R5-005 2,048 absolute",
            Absolute,
            &[(1, 0x0400), (5, 2_048)],
            false,
        ),
        (
            "SMD-R5-005 1,024 absolute",
            Absolute,
            &[(1, 0x0400), (5, 1_024)],
            true,
        ),
        (
            "SMD-R5-005 4,096 absolute",
            Absolute,
            &[(1, 0x0400), (5, 4_096)],
            true,
        ),
        ("SMD-R5-006 idle 0 %", Incremental, &[(6, 0)], false),
        ("SMD-R5-006 idle 100 %", Incremental, &[(6, 100)], false),
        ("SMD-R5-006 idle 101 %", Incremental, &[(6, 101)], true),
        ("SMD-R5-009 CFG0 bit 15", Incremental, &[(1, 0x8000)], false),
        ("SMD-R5-010 CFG0 bit 14", Incremental, &[(1, 0x4000)], false),
        ("SMD-R5-015 CFG0 bit 11", Incremental, &[(1, 0x0800)], false),
        ("SMD-R5-013 CFG0 bit 6", Incremental, &[(1, 0x0040)], true),
        ("SMD-R5-013 CFG0 bit 7", Incremental, &[(1, 0x0080)], true),
        ("SMD-R5-013 CFG0 bit 8", Incremental, &[(1, 0x0100)], true),
        ("SMD-R5-013 CFG0 bit 9", Incremental, &[(1, 0x0200)], true),
        ("SMD-R5-021 0x240E", Incremental, &[(1, 0x240E)], false),
        ("SMD-R5-021 0x0C1E", Incremental, &[(1, 0x0C1E)], false),
        ("SMD-R5-021 0x2006", Incremental, &[(1, 0x2006)], true),
        ("SMD-R5-021 0x4000", Incremental, &[(1, 0x4000)], false),
    ];
    for &(case, kind, writes, error) in cases {
        assert_eq!(configuration_error(kind, writes), error, "{case}");
    }
}

/// SMD-R5-026, SMD-R6-019: Configuration_Error is 1 exactly while the stored configuration is invalid:
/// writing a valid value over the offending one clears it without any command; Reset Errors does not.
/// A move commanded meanwhile is refused with no motion, and runs once the configuration is valid.
#[test]
fn smd_r5_026_configuration_error_follows_the_stored_values() {
    let mut r = unit(EncoderKind::Incremental);
    r.out = Outputs {
        cmd1: cmd1::ENABLE_DRIVER,
        velocity: 5_000,
        acceleration: 20,
        deceleration: 20,
        position: 1_000,
        ..Outputs::default()
    };
    r.cycle();
    assert!(r.ix.write_config(r.now(), 4, 199));
    r.cycle();
    assert_ne!(r.s0() & stat0::CONFIGURATION_ERROR, 0);
    r.command(cmd0::RESET_ERRORS);
    r.command(0);
    assert_ne!(
        r.s0() & stat0::CONFIGURATION_ERROR,
        0,
        "Reset Errors leaves it"
    );
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..100 {
        assert_eq!(r.pos(), 0);
        assert_ne!(r.s0() & stat0::STOPPED, 0);
        r.cycle();
    }
    r.command(0);
    assert!(r.ix.write_config(r.now(), 4, 200));
    r.cycle();
    assert_eq!(
        r.s0() & stat0::CONFIGURATION_ERROR,
        0,
        "valid again, no command"
    );
    r.command(cmd0::RESET_ERRORS);
    r.command(0);
    r.move_to_end(cmd0::RELATIVE_MOVE, 1_000);
    assert_eq!(r.pos(), 1_000);
}

/// SMD-R5-014: with Use_Encoder (CFG_Word_0 bit 10) the encoder counts the shaft: a move of one turn
/// (2,000 steps) changes Encoder_Position by Encoder_Resolution, 2,048; without it Encoder_Position
/// stays 0 all through the same move.
#[test]
fn smd_r5_014_use_encoder() {
    for (cfg0, counts) in [(0x0400, 2_048), (0x0000, 0)] {
        let mut r = Rig::ready_with(cfg0, 5_000, 20, 20);
        r.out.position = 2_000;
        r.command(cmd0::RELATIVE_MOVE);
        let mut seen = Vec::new();
        for _ in 0..3_000 {
            seen.push(r.cycle().encoder_position);
        }
        assert_eq!(r.pos(), 2_000);
        assert_eq!(r.last.encoder_position, counts, "CFG_Word_0 {cfg0:#06x}");
        if counts == 0 {
            assert!(seen.iter().all(|&e| e == 0));
        } else {
            assert!(
                seen.windows(2).all(|w| w[1] >= w[0]),
                "counts up with the shaft"
            );
        }
    }
}
