//! SyncManager mailboxes and the CoE SDO server behind them, byte by byte as a master sees them.

mod common;

use std::time::Duration;

use common::master::*;
use ds402::smd::indexer::stat0;
use ethercat_slave::esc::al::state;
use ethercat_slave::esc::cmd;
use ethercat_slave::master::SimChain;
use ethercat_slave::smd::binding::Device;

fn preop(n: usize) -> SimChain {
    let mut c = SimChain::new(Device::Smd23kB, n).unwrap();
    bring_up(&mut c, state::PREOP);
    c
}

/// The mailbox rules of a SyncManager in mailbox mode: SM0 takes a write only while empty, SM1 is
/// read only while full, the read of its last byte empties it, and a refused access changes nothing
/// and counts nothing in the working counter.
#[test]
fn mailbox_sync_managers_gate_the_masters_accesses() {
    let mut c = preop(1);
    // SM1 is empty: reading it is refused.
    let (_, wkc) = fprd(&mut c, 0, MBX_IN, MBX_LEN);
    assert_eq!(wkc, 0, "empty SM1");
    // Writing SM1 (the master's read mailbox) or reading SM0 is refused.
    assert_eq!(
        reg(&mut c, cmd::FPWR, station(0), MBX_IN, vec![1; 8]).wkc,
        0
    );
    assert_eq!(fprd(&mut c, 0, MBX_OUT, 8).1, 0);
    // A write that stops short of the last byte does not fill SM0: no answer.
    let request = coe_request(next_counter(), &[0x40, 0x18, 0x10, 0x04, 0, 0, 0, 0]);
    assert_eq!(
        reg(&mut c, cmd::FPWR, station(0), MBX_OUT, request.clone()).wkc,
        1
    );
    c.cycle(Duration::from_millis(1));
    assert_eq!(fprd(&mut c, 0, 0x080D, 1).0[0] & 0x08, 0, "SM1 still empty");
    // The whole mailbox: answered at once, SM1 full; the read of its last byte empties it.
    let mut m = request;
    m.resize(MBX_LEN, 0);
    assert_eq!(
        reg(&mut c, cmd::FPWR, station(0), MBX_OUT, m.clone()).wkc,
        1
    );
    assert_eq!(fprd(&mut c, 0, 0x080D, 1).0[0] & 0x08, 0x08, "SM1 full");
    let (first, _) = fprd(&mut c, 0, MBX_IN, 16);
    assert_eq!(fprd(&mut c, 0, 0x080D, 1).0[0] & 0x08, 0x08, "still full");
    let (answer, wkc) = fprd(&mut c, 0, MBX_IN, MBX_LEN);
    assert_eq!(wkc, 1);
    assert_eq!(first, answer[..16]);
    // 0x1018:04 serial number 1: expedited response 43 18 10 04 01 00 00 00.
    assert_eq!(
        answer[..16],
        [
            0x0A, 0x00, 0x00, 0x00, 0x00, 0x13, 0x00, 0x30, 0x43, 0x18, 0x10, 0x04, 0x01, 0x00,
            0x00, 0x00
        ]
    );
    assert_eq!(fprd(&mut c, 0, 0x080D, 1).0[0] & 0x08, 0, "emptied");
    // Repeat request: the master toggles SM1 activate bit 1, the slave puts the last answer back
    // and acknowledges in PDI control bit 1.
    assert_eq!(
        reg(&mut c, cmd::FPWR, station(0), 0x080E, vec![0x03]).wkc,
        1
    );
    assert_eq!(
        fprd(&mut c, 0, 0x080F, 1).0[0] & 0x02,
        0x02,
        "repeat acknowledged"
    );
    assert_eq!(
        fprd(&mut c, 0, MBX_IN, MBX_LEN).0,
        answer,
        "the same answer again"
    );
}

/// A mailbox written while SM0 is full (the slave has not taken it) is refused: wkc 0. Here the
/// answer to the first is still unread, so the second waits in SM0 and is answered after SM1 is
/// read.
#[test]
fn answers_wait_for_the_master_to_read_sm1() {
    let mut c = preop(1);
    let mut a = coe_request(next_counter(), &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]);
    a.resize(MBX_LEN, 0);
    let mut b = coe_request(next_counter(), &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]);
    b.resize(MBX_LEN, 0);
    fpwr(&mut c, 0, MBX_OUT, a);
    fpwr(&mut c, 0, MBX_OUT, b);
    let (first, _) = fprd(&mut c, 0, MBX_IN, MBX_LEN);
    assert_eq!(coe_answer(&first).unwrap()[..4], [0x43, 0x00, 0x10, 0x00]);
    c.cycle(Duration::from_millis(1));
    let (second, wkc) = fprd(&mut c, 0, MBX_IN, MBX_LEN);
    assert_eq!(wkc, 1);
    assert_eq!(
        coe_answer(&second).unwrap(),
        [0x43, 0x18, 0x10, 0x01, 0xC1, 0x0A, 0x00, 0x00],
        "vendor 0x0AC1"
    );
}

/// SMD-T2-008: the inputs 0x6000 read by SDO in Pre-Op; SMD-T2-007: the unit is in Init at
/// power-up, so STATUS_word0 shows the power-up bits (Position_Invalid, Stopped, Module_OK).
#[test]
fn smd_t2_008_inputs_by_sdo_in_preop() {
    let mut c = SimChain::new(Device::Smd23kB, 1).unwrap();
    let status = reg(&mut c, cmd::APRD, 0, 0x0130, vec![0; 2]);
    assert_eq!(
        (status.wkc, status.data),
        (1, vec![0x01, 0x00]),
        "SMD-T2-007: Init before any request"
    );
    bring_up(&mut c, state::PREOP);
    c.cycle(Duration::from_millis(1));
    let s = upload(&mut c, 0, 0x6000, 1, false).unwrap();
    let status0 = u16::from_le_bytes([s[0], s[1]]);
    assert_eq!(
        status0 & (stat0::POSITION_INVALID | stat0::STOPPED | stat0::MODULE_OK),
        stat0::POSITION_INVALID | stat0::STOPPED | stat0::MODULE_OK
    );
}

/// A normal (segmented-size) upload: the 0x1008 device name in one mailbox, with its size.
#[test]
fn normal_upload_of_the_device_name() {
    let mut c = preop(1);
    assert_eq!(upload(&mut c, 0, 0x1008, 0, false).unwrap(), b"SMD23K-B");
}

/// An SDO download of 0x8010 over EtherCAT reaches the model as the unit's configuration: an
/// invalid Motor_Current (35 = 3.5 A) shows as Configuration_Error (SMD-T2-005), a valid one clears
/// it; a refused download (value beyond the entry's limits, read-only entry) changes nothing and
/// answers the abort code.
#[test]
fn smd_t2_005_configuration_by_coe_reaches_the_model() {
    let mut c = SimChain::new(Device::Smd23kB, 1).unwrap();
    bring_up(&mut c, state::SAFEOP);
    // The inputs of an LRW are those of the cycle before it: the second shows the first's effect.
    let status = |c: &mut SimChain| {
        lrw(c, &[Default::default()]);
        lrw(c, &[Default::default()]).1[0].status0
    };
    assert_eq!(status(&mut c) & stat0::CONFIGURATION_ERROR, 0);
    download(&mut c, 0, 0x8010, 7, &35u16.to_le_bytes(), false).unwrap();
    assert_eq!(upload(&mut c, 0, 0x8010, 7, false).unwrap(), [35, 0]);
    assert_ne!(status(&mut c) & stat0::CONFIGURATION_ERROR, 0);
    download(&mut c, 0, 0x8010, 7, &10u16.to_le_bytes(), false).unwrap();
    assert_eq!(status(&mut c) & stat0::CONFIGURATION_ERROR, 0);
    // Read-only sub-index 0; a 4-byte value into a 2-byte entry.
    assert_eq!(
        download(&mut c, 0, 0x8010, 0, &[7], false),
        Err(0x0601_0002)
    );
    assert_eq!(
        download(&mut c, 0, 0x8010, 7, &10u32.to_le_bytes(), false),
        Err(0x0607_0012)
    );
    assert_eq!(upload(&mut c, 0, 0x8010, 7, false).unwrap(), [10, 0]);
    // The output image belongs to the process data.
    assert!(download(&mut c, 0, 0x7000, 1, &[1, 0], false).is_err());
}

/// Complete Access: 0x8010 read whole from sub-index 1 (16 bytes: CFG_Word_0, CFG_Word_1,
/// Starting_Speed, Motor_Resolution, Encoder_Resolution, Idle_Current_Reduction, Motor_Current),
/// written back whole with a new Starting_Speed; the model takes it (Position_Invalid set again after
/// a preset cleared it, SMD-R2-012).
#[test]
fn complete_access_of_the_configuration() {
    let mut c = preop(1);
    let mut cfg = upload(&mut c, 0, 0x8010, 1, true).unwrap();
    assert_eq!(cfg.len(), 16);
    assert_eq!(cfg[..8], [0x00, 0x00, 0x03, 0x00, 0x8D, 0x00, 0x00, 0x00]);
    cfg[4..8].copy_from_slice(&300u32.to_le_bytes());
    download(&mut c, 0, 0x8010, 1, &cfg, true).unwrap();
    assert_eq!(
        upload(&mut c, 0, 0x8010, 3, false).unwrap(),
        300u32.to_le_bytes()
    );
    let unit = c.unit(0).unwrap();
    assert_eq!(unit.indexer().config().starting_speed, 300);
}

/// A mailbox of another protocol than CoE is answered with a mailbox error (type 0, service 1,
/// detail 0x0002 unsupported protocol); the server goes on.
#[test]
fn other_mailbox_protocols_get_a_mailbox_error() {
    let mut c = preop(1);
    // Type 5 = FoE, counter 0.
    let m = mailbox(&mut c, 0, &[4, 0, 0, 0, 0, 0x05, 1, 0, 0, 0]);
    assert_eq!(m[5] & 0x0F, 0x00, "mailbox error reply");
    assert_eq!(m[6..10], [0x01, 0x00, 0x02, 0x00]);
    assert_eq!(
        upload(&mut c, 0, 0x1018, 2, false).unwrap(),
        0x2301u32.to_le_bytes()
    );
}

/// The mailbox restarts in Init only: a request with the counter of the last one is a repeat in
/// Safe-Op too (answered with the last answer again, not executed), while after Init the same
/// counter starts a new exchange.
#[test]
fn the_mailbox_restarts_in_init_only() {
    let mut c = preop(1);
    let k = next_counter();
    let vendor = [0x43, 0x18, 0x10, 0x01, 0xC1, 0x0A, 0x00, 0x00];
    let a = mailbox(
        &mut c,
        0,
        &coe_request(k, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]),
    );
    assert_eq!(coe_answer(&a).unwrap(), vendor);
    request(&mut c, state::SAFEOP);
    assert_eq!(al(&mut c, 0), (0x0004, 0));
    let device_type = [0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0];
    let b = mailbox(&mut c, 0, &coe_request(k, &device_type));
    assert_eq!(
        coe_answer(&b).unwrap(),
        vendor,
        "a repeat: the last answer again"
    );
    request(&mut c, state::INIT);
    request(&mut c, state::PREOP);
    assert_eq!(al(&mut c, 0), (0x0002, 0));
    let d = mailbox(&mut c, 0, &coe_request(k, &device_type));
    assert_eq!(
        coe_answer(&d).unwrap()[..4],
        [0x43, 0x00, 0x10, 0x00],
        "after Init: a new request"
    );
}

/// A master that writes SM0 and never reads SM1 cannot make the unit queue answers without bound
/// (ETG.1000.6 §5.5: the mailbox is a one-request, one-answer exchange): the unit takes a request
/// only once the answers before it are on their way, so SM0 stays full and refuses the master's
/// writes (working counter 0); read back in order, the answers are those of the requests taken,
/// none stale.
#[test]
fn a_master_that_never_reads_sm1_gets_backpressure_not_a_queue() {
    let mut c = preop(1);
    let request = |counter: u8, sub: u8| {
        let mut m = coe_request(counter, &[0x40, 0x18, 0x10, sub, 0, 0, 0, 0]);
        m.resize(MBX_LEN, 0);
        m
    };
    let mut written = Vec::new();
    for k in 0..200u8 {
        let counter = k % 7 + 1;
        let sub = k % 4 + 1;
        let wkc = reg(
            &mut c,
            cmd::FPWR,
            station(0),
            MBX_OUT,
            request(counter, sub),
        )
        .wkc;
        if wkc == 1 {
            written.push(sub);
        }
        c.cycle(Duration::from_millis(1));
    }
    // One answer in SM1, one waiting for it, one request in SM0: three taken, the rest refused.
    assert_eq!(written, [1, 2, 3]);
    for sub in [1u8, 2, 3] {
        let answer = answer(&mut c, 0);
        assert_eq!(coe_answer(&answer).unwrap()[..4], [0x43, 0x18, 0x10, sub]);
    }
    let (status, _) = fprd(&mut c, 0, 0x080D, 1);
    assert_eq!(status[0] & 0x08, 0, "nothing more to read");
}
