//! The AL state machine of the emulated slave with the SMD's SyncManager settings from its ESI.

mod common;

use std::time::Instant;

use ethercat_slave::esc::al::{AlConfig, AlState, AlStatusCode, AL_CONTROL};
use ethercat_slave::esc::{cmd, Chain};
use ethercat_slave::frame::{emit, parse, Datagram};

fn smd_chain() -> Chain {
    let mut c = Chain::new(1);
    c.slaves[0].al = AlConfig::from_description(&common::smd());
    c
}

fn write(c: &mut Chain, ado: u16, data: &[u8]) -> u16 {
    let mut f = emit(
        &[Datagram::new(cmd::APWR, 0, ado, data.to_vec())],
        [2, 0, 0, 0, 0, 1],
    );
    c.handle_frame(Instant::now(), &mut f).unwrap();
    parse(&f).unwrap()[0].wkc
}

fn request(c: &mut Chain, control: u16) -> (AlState, bool, AlStatusCode) {
    write(c, AL_CONTROL, &control.to_le_bytes());
    let (s, e) = c.slaves[0].al_state();
    (s, e, c.slaves[0].al_status_code())
}

/// SyncManager `n`: start, length, control byte, enabled.
fn sm(c: &mut Chain, n: u16, start: u16, len: u16, control: u8) {
    let mut r = start.to_le_bytes().to_vec();
    r.extend_from_slice(&len.to_le_bytes());
    r.extend_from_slice(&[control, 0, 1, 0]);
    assert_eq!(write(c, 0x0800 + 8 * n, &r), 1);
}

#[test]
fn init_to_op_with_the_checks_of_each_step() {
    let mut c = smd_chain();
    assert_eq!(c.slaves[0].al_state(), (AlState::Init, false));
    // Straight to Op: refused, error indicator set, code 0x0011; refused again until acknowledged.
    assert_eq!(
        request(&mut c, 0x08),
        (AlState::Init, true, AlStatusCode::InvalidStateChange)
    );
    assert_eq!(
        request(&mut c, 0x02).0,
        AlState::Init,
        "error not acknowledged"
    );
    assert_eq!(
        request(&mut c, 0x11),
        (AlState::Init, false, AlStatusCode::NoError)
    );
    // Pre-Op without the mailbox SyncManagers: 0x0016.
    assert_eq!(
        request(&mut c, 0x02),
        (AlState::Init, true, AlStatusCode::InvalidMailbox)
    );
    request(&mut c, 0x11);
    // Each mailbox SyncManager alone is not enough: the other one wrong is 0x0016 too.
    for (sm0, sm1) in [(0x26, 0x26), (0x22, 0x22)] {
        sm(&mut c, 0, 0x1000, 128, sm0);
        sm(&mut c, 1, 0x1080, 128, sm1);
        assert_eq!(
            request(&mut c, 0x02),
            (AlState::Init, true, AlStatusCode::InvalidMailbox),
            "SM0 {sm0:#04x}, SM1 {sm1:#04x}"
        );
        request(&mut c, 0x11);
    }
    sm(&mut c, 0, 0x1000, 128, 0x26);
    sm(&mut c, 1, 0x1080, 128, 0x22);
    assert_eq!(
        request(&mut c, 0x02),
        (AlState::PreOp, false, AlStatusCode::NoError)
    );
    // Safe-Op with a wrong output length: 0x001D; then right: Safe-Op, then Op.
    sm(&mut c, 2, 0x1100, 18, 0x64);
    sm(&mut c, 3, 0x1400, 20, 0x20);
    assert_eq!(
        request(&mut c, 0x04),
        (AlState::PreOp, true, AlStatusCode::InvalidOutputs)
    );
    request(&mut c, 0x12);
    sm(&mut c, 2, 0x1100, 20, 0x64);
    assert_eq!(
        request(&mut c, 0x04),
        (AlState::SafeOp, false, AlStatusCode::NoError)
    );
    assert_eq!(
        request(&mut c, 0x08),
        (AlState::Op, false, AlStatusCode::NoError)
    );
    // Back down is always allowed; bootstrap is not offered.
    assert_eq!(
        request(&mut c, 0x02),
        (AlState::PreOp, false, AlStatusCode::NoError)
    );
    assert_eq!(
        request(&mut c, 0x03),
        (AlState::PreOp, true, AlStatusCode::BootstrapNotSupported)
    );
    assert_eq!(
        request(&mut c, 0x11),
        (AlState::Init, false, AlStatusCode::NoError)
    );
}

/// The SMD's description with a bootstrap mailbox (ESI `Eeprom/BootStrap` `00180001 00190001`:
/// receive at 0x1800 and send at 0x1900, 256 bytes each).
fn boot_chain() -> Chain {
    let mut desc = common::smd();
    let ec = desc.ethercat.as_mut().unwrap();
    ec.eeprom.as_mut().unwrap().boot_strap = vec![0x00, 0x18, 0x00, 0x01, 0x00, 0x19, 0x00, 0x01];
    let mut c = Chain::new(1);
    c.slaves[0].al = AlConfig::from_description(&desc);
    c
}

/// Bootstrap (ETG.1000.6 §6.4.1), for a device whose ESI gives the bootstrap mailbox: from Init
/// only, with SM0/SM1 at its offsets and sizes (the standard mailbox there is 0x0015; a length
/// from the standard mailbox's MinSize, 34, up to the bootstrap size is taken, 33 and 257 are
/// not); out of it to Init only (Pre-Op, Safe-Op and Op are 0x0011); from Pre-Op it is 0x0011,
/// not 0x0013.
#[test]
fn bootstrap_from_init_with_its_own_mailbox() {
    let mut c = boot_chain();
    sm(&mut c, 0, 0x1000, 128, 0x26);
    sm(&mut c, 1, 0x1080, 128, 0x22);
    assert_eq!(
        request(&mut c, 0x03),
        (AlState::Init, true, AlStatusCode::InvalidMailboxBoot)
    );
    assert_eq!(AlStatusCode::InvalidMailboxBoot.code(), 0x0015);
    request(&mut c, 0x11);
    for (len, taken) in [(33, false), (257, false), (34, true), (256, true)] {
        sm(&mut c, 0, 0x1800, len, 0x26);
        sm(&mut c, 1, 0x1900, 256, 0x22);
        let (state, error, _) = request(&mut c, 0x03);
        assert_eq!(
            (state == AlState::Boot, error),
            (taken, !taken),
            "SM0 of {len} bytes"
        );
        request(&mut c, 0x11);
    }
    sm(&mut c, 0, 0x1800, 256, 0x26);
    sm(&mut c, 1, 0x1900, 256, 0x22);
    assert_eq!(
        request(&mut c, 0x03),
        (AlState::Boot, false, AlStatusCode::NoError)
    );
    for next in [0x02, 0x04, 0x08] {
        assert_eq!(
            request(&mut c, next),
            (AlState::Boot, true, AlStatusCode::InvalidStateChange),
            "Bootstrap → {next:#04x}"
        );
        assert_eq!(
            request(&mut c, 0x13),
            (AlState::Boot, false, AlStatusCode::NoError)
        );
    }
    assert_eq!(
        request(&mut c, 0x01),
        (AlState::Init, false, AlStatusCode::NoError)
    );
    sm(&mut c, 0, 0x1000, 128, 0x26);
    sm(&mut c, 1, 0x1080, 128, 0x22);
    assert_eq!(
        request(&mut c, 0x02),
        (AlState::PreOp, false, AlStatusCode::NoError)
    );
    assert_eq!(
        request(&mut c, 0x03),
        (AlState::PreOp, true, AlStatusCode::InvalidStateChange)
    );
}

/// ETG.1000.6 Table 11 as the register holds it: the codes this slave sets, by number, and every code
/// of the table back to itself; a reserved or vendor-specific number stays that number.
#[test]
fn al_status_codes_are_the_tables_numbers() {
    for (code, number) in [
        (AlStatusCode::NoError, 0x0000),
        (AlStatusCode::InvalidStateChange, 0x0011),
        (AlStatusCode::UnknownState, 0x0012),
        (AlStatusCode::BootstrapNotSupported, 0x0013),
        (AlStatusCode::InvalidMailbox, 0x0016),
        (AlStatusCode::SyncManagerWatchdog, 0x001B),
        (AlStatusCode::InvalidOutputs, 0x001D),
        (AlStatusCode::InvalidInputs, 0x001E),
        (AlStatusCode::DcSync0CycleTime, 0x0036),
    ] {
        assert_eq!(code.code(), number, "{code:?}");
        assert_eq!(AlStatusCode::from(number), code);
    }
    for &code in AlStatusCode::ALL {
        assert_eq!(AlStatusCode::from(code.code()), code);
    }
    assert_eq!(AlStatusCode::ALL.len(), 53);
    assert_eq!(AlStatusCode::from(0x0004), AlStatusCode::Other(0x0004));
    assert_eq!(AlStatusCode::from(0x8001).code(), 0x8001);
    assert_eq!(
        AlStatusCode::SyncManagerWatchdog.to_string(),
        "0x001B (Sync manager watchdog)"
    );
    assert_eq!(
        AlStatusCode::Other(0x8001).to_string(),
        "0x8001 (vendor-specific)"
    );
    assert_eq!(AlStatusCode::Other(0x0004).to_string(), "0x0004 (reserved)");
    for (state, bits, name) in [
        (AlState::Init, 1, "Init"),
        (AlState::PreOp, 2, "Pre-Op"),
        (AlState::Boot, 3, "Bootstrap"),
        (AlState::SafeOp, 4, "Safe-Op"),
        (AlState::Op, 8, "Op"),
    ] {
        assert_eq!(state.bits(), bits);
        assert_eq!(
            AlState::from_bits(bits | 0x10),
            Some(state),
            "the error bit is not the state's"
        );
        assert_eq!(state.to_string(), name);
    }
    for bits in [0u8, 5, 6, 7, 9, 15] {
        assert_eq!(AlState::from_bits(bits), None, "{bits}");
    }
}

/// ETG.1000.6 §6.4.1.4, the Pre-Op → Safe-Op checks in their order: the application's verdict on its
/// PDO mapping first (0x0025 even with the SyncManagers wrong too), then SM2 (0x001D), SM3
/// (0x001E), then SYNC0 activated on a device without it (0x0030); each refusal leaves Pre-Op with
/// the error flag.
#[test]
fn safe_op_checks_the_mapping_then_the_sync_managers_then_sync0() {
    let mut c = smd_chain();
    sm(&mut c, 0, 0x1000, 128, 0x26);
    sm(&mut c, 1, 0x1080, 128, 0x22);
    assert_eq!(request(&mut c, 0x02).0, AlState::PreOp);
    c.slaves[0].al.mapping_refused = Some(AlStatusCode::InvalidOutputMapping);
    c.slaves[0].al.no_sync0 = true;
    // SM2 and SM3 still unset, SYNC0 on: the mapping is named first.
    write(&mut c, 0x09A0, &1_000_000u32.to_le_bytes());
    write(&mut c, 0x0981, &[0x03]);
    assert_eq!(
        request(&mut c, 0x04),
        (AlState::PreOp, true, AlStatusCode::InvalidOutputMapping)
    );
    assert_eq!(AlStatusCode::InvalidOutputMapping.code(), 0x0025);
    assert_eq!(AlStatusCode::InvalidInputMapping.code(), 0x0024);
    assert_eq!(AlStatusCode::InvalidDcSync.code(), 0x0030);
    request(&mut c, 0x12);
    c.slaves[0].al.mapping_refused = None;
    assert_eq!(
        request(&mut c, 0x04),
        (AlState::PreOp, true, AlStatusCode::InvalidOutputs)
    );
    request(&mut c, 0x12);
    sm(&mut c, 2, 0x1100, 20, 0x64);
    assert_eq!(
        request(&mut c, 0x04),
        (AlState::PreOp, true, AlStatusCode::InvalidInputs)
    );
    request(&mut c, 0x12);
    sm(&mut c, 3, 0x1400, 20, 0x20);
    assert_eq!(
        request(&mut c, 0x04),
        (AlState::PreOp, true, AlStatusCode::InvalidDcSync)
    );
    request(&mut c, 0x12);
    write(&mut c, 0x0981, &[0x00]);
    assert_eq!(
        request(&mut c, 0x04),
        (AlState::SafeOp, false, AlStatusCode::NoError)
    );
}

/// A SyncManager is checked by its number among the ESI's `Sm` elements: a device whose process
/// data SyncManagers are SM0 and SM1 (no mailbox) reaches Safe-Op with those set, whatever SM2 and
/// SM3 hold.
#[test]
fn sync_managers_are_checked_by_their_esi_number() {
    let mut desc = common::smd();
    let ec = desc.ethercat.as_mut().unwrap();
    ec.sync_managers
        .retain(|s| s.kind == "Outputs" || s.kind == "Inputs");
    let mut c = Chain::new(1);
    c.slaves[0].al = AlConfig::from_description(&desc);
    let rules = c.slaves[0].al.clone();
    assert_eq!(rules.mailbox, None);
    assert_eq!(rules.outputs.map(|r| (r.sm, r.start)), Some((0, 0x1100)));
    assert_eq!(rules.inputs.map(|r| (r.sm, r.start)), Some((1, 0x1400)));
    assert_eq!(request(&mut c, 0x02).0, AlState::PreOp);
    assert_eq!(
        request(&mut c, 0x04),
        (AlState::PreOp, true, AlStatusCode::InvalidOutputs)
    );
    request(&mut c, 0x12);
    sm(&mut c, 0, 0x1100, 20, 0x64);
    sm(&mut c, 1, 0x1400, 20, 0x20);
    assert_eq!(
        request(&mut c, 0x04),
        (AlState::SafeOp, false, AlStatusCode::NoError)
    );
}

/// The ESC has 8 SyncManagers (0–7): an ESI `Sm` element beyond the eighth is none of them, so the
/// transitions check nothing for it. With the `Outputs` element the 8th (SM7) it is checked as SM7;
/// as the 9th there is no outputs rule.
#[test]
fn an_sm_element_beyond_the_eighth_is_not_checked() {
    use od::device::{DeviceDescription, EthercatInfo, SyncManager};
    let with_outputs_at = |n: usize| {
        let mut sms: Vec<SyncManager> = (0..n)
            .map(|k| SyncManager {
                kind: format!("Other{k}"),
                start_address: 0x1000 + 0x100 * k as u16,
                ..SyncManager::default()
            })
            .collect();
        sms.push(SyncManager {
            kind: "Outputs".into(),
            start_address: 0x1F00,
            control_byte: 0x64,
            ..SyncManager::default()
        });
        let desc = DeviceDescription {
            ethercat: Some(EthercatInfo {
                sync_managers: sms,
                ..EthercatInfo::default()
            }),
            ..DeviceDescription::default()
        };
        AlConfig::from_description(&desc).outputs
    };
    assert_eq!(
        with_outputs_at(7).map(|r| (r.sm, r.start, r.control)),
        Some((7, 0x1F00, 0x64))
    );
    assert_eq!(with_outputs_at(8), None);
}
