//! The AL state machine of the emulated slave with the SMD's SyncManager settings from its ESI.

mod common;

use std::time::Instant;

use ethercat_slave::esc::al::{code, state, AlConfig, AL_CONTROL, AL_STATUS_CODE};
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

fn request(c: &mut Chain, control: u16) -> (u8, bool, u16) {
    write(c, AL_CONTROL, &control.to_le_bytes());
    let (s, e) = c.slaves[0].al_state();
    let code = u16::from_le_bytes(c.slaves[0].load(AL_STATUS_CODE, 2).try_into().unwrap());
    (s, e, code)
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
    assert_eq!(c.slaves[0].al_state(), (state::INIT, false));
    // Straight to Op: refused, error indicator set, code 0x0011; refused again until acknowledged.
    assert_eq!(
        request(&mut c, 0x08),
        (state::INIT, true, code::INVALID_STATE_CHANGE)
    );
    assert_eq!(
        request(&mut c, 0x02).0,
        state::INIT,
        "error not acknowledged"
    );
    assert_eq!(request(&mut c, 0x11), (state::INIT, false, code::NONE));
    // Pre-Op without the mailbox SyncManagers: 0x0016.
    assert_eq!(
        request(&mut c, 0x02),
        (state::INIT, true, code::INVALID_MAILBOX)
    );
    request(&mut c, 0x11);
    sm(&mut c, 0, 0x1000, 128, 0x26);
    sm(&mut c, 1, 0x1080, 128, 0x22);
    assert_eq!(request(&mut c, 0x02), (state::PREOP, false, code::NONE));
    // Safe-Op with a wrong output length: 0x001D; then right: Safe-Op, then Op.
    sm(&mut c, 2, 0x1100, 18, 0x64);
    sm(&mut c, 3, 0x1400, 20, 0x20);
    assert_eq!(
        request(&mut c, 0x04),
        (state::PREOP, true, code::INVALID_OUTPUTS)
    );
    request(&mut c, 0x12);
    sm(&mut c, 2, 0x1100, 20, 0x64);
    assert_eq!(request(&mut c, 0x04), (state::SAFEOP, false, code::NONE));
    assert_eq!(request(&mut c, 0x08), (state::OP, false, code::NONE));
    // Back down is always allowed; bootstrap is not offered.
    assert_eq!(request(&mut c, 0x02), (state::PREOP, false, code::NONE));
    assert_eq!(
        request(&mut c, 0x03),
        (state::PREOP, true, code::BOOTSTRAP_NOT_SUPPORTED)
    );
    assert_eq!(request(&mut c, 0x11), (state::INIT, false, code::NONE));
}
