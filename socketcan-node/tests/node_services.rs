//! The CiA 301 services of the X67 node, in process on a simulated clock: exact frames and times.

use std::time::Duration;

use socketcan_node::node::storage::{FileStorage, MemoryStorage, ParameterStorage, StorageRequest};
use socketcan_node::node::NodeEvent;
use socketcan_node::sim::SimNode;
use socketcan_node::x67::{self, BusController};
use socketcan_node::{CanFrame, NmtState, Node, NodeConfig};

const ID: u8 = 5;

fn node() -> SimNode {
    SimNode::new(ID, 1).unwrap()
}

fn f(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

fn u32le(v: &[u8]) -> u32 {
    let mut b = [0u8; 4];
    b[..v.len()].copy_from_slice(v);
    u32::from_le_bytes(b)
}

#[test]
fn boot_up_message_then_pre_operational() {
    let n = node();
    assert_eq!(n.sent, vec![(Duration::ZERO, f(0x705, &[0x00]))]);
    assert_eq!(n.node.state(), NmtState::PreOperational);
}

#[test]
fn nmt_states_and_heartbeat_bytes() {
    let mut n = node();
    n.sdo_write(0x1017, 0, &[100, 0]).unwrap();
    let hb = n.advance_ms(100);
    assert_eq!(hb, vec![f(0x705, &[0x7F])]);
    n.nmt(0x01, ID);
    assert_eq!(n.node.state(), NmtState::Operational);
    let hb: Vec<_> = n
        .advance_ms(100)
        .into_iter()
        .filter(|x| x.cob_id() == Some(0x705))
        .collect();
    assert_eq!(hb, vec![f(0x705, &[0x05])]);
    n.nmt(0x02, 0); // broadcast stop
    assert_eq!(n.node.state(), NmtState::Stopped);
    assert_eq!(n.advance_ms(100), vec![f(0x705, &[0x04])]);
    // No SDO in Stopped.
    assert_eq!(n.sdo_read(0x1000, 0), Err(0));
    n.nmt(0x80, ID);
    assert_eq!(n.node.state(), NmtState::PreOperational);
    // Commands for other nodes and malformed NMT frames change nothing.
    n.nmt(0x01, 6);
    n.send(f(0x000, &[0x01]));
    n.send(f(0x000, &[0x01, ID, 0]));
    assert_eq!(n.node.state(), NmtState::PreOperational);
}

/// The first heartbeat comes one producer time after the boot-up message: when the edge reports
/// that the boot-up left 40 ms after the reset began (the reset's own work on a slow machine), the
/// beats run from then, not from the reset.
#[test]
fn the_first_heartbeat_follows_the_boot_up_message_by_one_period() {
    let t0 = std::time::Instant::now();
    let config = NodeConfig {
        heartbeat_ms: Some(100),
        ..NodeConfig::new(ID)
    };
    let dict = x67::dictionary(1).unwrap();
    let app = BusController::new(&dict, 1, x67::DEFAULT_X2X_CYCLE, t0).unwrap();
    let mut node = Node::new(config, dict, app, t0).unwrap();
    // The frames on 0x705 (boot-up, heartbeats) the node sends when run up to `ms` after t0.
    let run_to = |node: &mut Node<BusController>, ms: u64| {
        let end = t0 + Duration::from_millis(ms);
        while let Some(t) = node.poll_timeout().filter(|t| *t <= end) {
            node.handle_timeout(t);
        }
        node.handle_timeout(end);
        std::iter::from_fn(|| node.poll_transmit())
            .filter(|f| f.cob_id() == Some(0x705))
            .collect::<Vec<_>>()
    };
    node.start(t0);
    assert_eq!(node.poll_transmit(), Some(f(0x705, &[0x00])));
    node.boot_up_sent(t0 + Duration::from_millis(40));
    assert_eq!(run_to(&mut node, 139), vec![]);
    assert_eq!(run_to(&mut node, 140), vec![f(0x705, &[0x7F])]);
    // Only the first report after a boot counts.
    node.boot_up_sent(t0 + Duration::from_millis(200));
    assert_eq!(run_to(&mut node, 239), vec![]);
    assert_eq!(run_to(&mut node, 240), vec![f(0x705, &[0x7F])]);
    // A reset starts again: reset communication at 300 ms, its boot-up reported at 310 ms.
    node.handle_frame(t0 + Duration::from_millis(300), &f(0x000, &[0x82, ID]));
    let boot: Vec<CanFrame> = std::iter::from_fn(|| node.poll_transmit())
        .filter(|f| f.cob_id() == Some(0x705))
        .collect();
    assert_eq!(boot, vec![f(0x705, &[0x00])]);
    node.boot_up_sent(t0 + Duration::from_millis(310));
    assert_eq!(run_to(&mut node, 409), vec![]);
    assert_eq!(run_to(&mut node, 410), vec![f(0x705, &[0x7F])]);
}

#[test]
fn heartbeat_period_is_exact() {
    let mut n = node();
    n.sdo_write(0x1017, 0, &[50, 0]).unwrap();
    let start = n.elapsed();
    n.advance_ms(1000);
    let times: Vec<Duration> = n
        .sent_on(0x705)
        .into_iter()
        .skip(1)
        .map(|(t, _)| t)
        .collect();
    assert_eq!(times.len(), 20);
    for (k, t) in times.iter().enumerate() {
        assert_eq!(*t - start, Duration::from_millis(50 * (k as u64 + 1)));
    }
}

/// A beat polled late keeps the period without drift while it is less than half a period late; later
/// than that, the period starts again from the late beat, so that two beats never leave within half a
/// period of each other (a busy machine once put two on the bus 1.3 ms apart).
#[test]
fn a_late_heartbeat_never_bursts() {
    let mut n = node();
    n.sdo_write(0x1017, 0, &[100, 0]).unwrap();
    let start = n.elapsed();
    let ms = Duration::from_millis;
    let beats = |n: &SimNode| -> Vec<Duration> {
        n.sent_on(0x705)
            .into_iter()
            .skip(1)
            .map(|(t, _)| t - start)
            .collect()
    };
    // Due at 100, sent at 140: the next is due at 200.
    assert_eq!(n.stall(ms(140)).len(), 1);
    n.advance(ms(60) - Duration::from_nanos(1));
    assert_eq!(beats(&n), [ms(140)]);
    n.advance(Duration::from_nanos(1));
    assert_eq!(beats(&n), [ms(140), ms(200)]);
    // Due at 300, sent at 370 (more than half a period late): the next is due at 470, not 400.
    assert_eq!(n.stall(ms(170)).len(), 1);
    n.advance(ms(100) - Duration::from_nanos(1));
    assert_eq!(beats(&n), [ms(140), ms(200), ms(370)]);
    n.advance(Duration::from_nanos(1));
    assert_eq!(beats(&n), [ms(140), ms(200), ms(370), ms(470)]);
    // Exactly half a period late (due 570, sent 620): still due at 670.
    n.stall(ms(150));
    n.advance(ms(50));
    assert_eq!(beats(&n)[4..], [ms(620), ms(670)]);
}

#[test]
fn heartbeat_default_from_the_configuration() {
    let mut cfg = NodeConfig::new(ID);
    cfg.heartbeat_ms = Some(200);
    let mut n = SimNode::with(cfg, 1, Box::new(MemoryStorage::default())).unwrap();
    assert_eq!(n.sdo_read(0x1017, 0), Ok(vec![200, 0]));
    assert_eq!(n.advance_ms(400), vec![f(0x705, &[0x7F]); 2]);
    // Boot-up at 0, then one heartbeat every 200 ms from the boot, none before.
    assert_eq!(
        n.sent_on(0x705),
        vec![
            (Duration::ZERO, f(0x705, &[0x00])),
            (Duration::from_millis(200), f(0x705, &[0x7F])),
            (Duration::from_millis(400), f(0x705, &[0x7F])),
        ]
    );
}

/// A SYNC producer (0x1005 bit 30, 0x1006 = 10 ms) stored with "save" runs from the next boot: the
/// first SYNC one period after the boot-up message, then every 10 ms.
#[test]
fn a_stored_sync_producer_starts_one_period_after_the_boot() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sync.params");
    let storage = || Box::new(FileStorage::new(&path)) as Box<dyn ParameterStorage>;
    let mut n = SimNode::with(NodeConfig::new(ID), 1, storage()).unwrap();
    n.sdo_write(0x1006, 0, &10_000u32.to_le_bytes()).unwrap();
    n.sdo_write(0x1005, 0, &0x4000_0080u32.to_le_bytes())
        .unwrap();
    n.sdo_write(0x1010, 1, b"save").unwrap();
    let mut m = SimNode::with(NodeConfig::new(ID), 1, storage()).unwrap();
    m.advance_ms(30);
    let ms = Duration::from_millis;
    assert_eq!(
        m.sent_on(0x080),
        vec![
            (ms(10), f(0x080, &[])),
            (ms(20), f(0x080, &[])),
            (ms(30), f(0x080, &[]))
        ]
    );
}

#[test]
fn identity_and_device_name() {
    let mut n = node();
    assert_eq!(n.sdo_read(0x1000, 0), Ok(vec![0, 0, 0, 0]));
    assert_eq!(n.sdo_read(0x1018, 0), Ok(vec![4]));
    // The device name is longer than 4 bytes: a segmented upload starts.
    let r = n.send(f(0x605, &[0x40, 0x08, 0x10, 0, 0, 0, 0, 0]));
    assert_eq!(r[0].data()[0], 0x41);
    let len = u32le(&r[0].data()[4..8]) as usize;
    assert_eq!(len, "X67BC4321-10 / X67SM2436".len());
    let mut name = Vec::new();
    let mut toggle = 0u8;
    loop {
        let r = n.send(f(0x605, &[0x60 | toggle, 0, 0, 0, 0, 0, 0, 0]));
        let d = r[0].data8();
        let unused = usize::from((d[0] >> 1) & 7);
        name.extend_from_slice(&d[1..8 - unused]);
        toggle ^= 0x10;
        if d[0] & 1 != 0 {
            break;
        }
    }
    assert_eq!(String::from_utf8(name).unwrap(), "X67BC4321-10 / X67SM2436");
}

#[test]
fn sdo_frames_with_a_short_dlc_or_for_other_nodes_are_ignored() {
    let mut n = node();
    assert!(n.send(f(0x605, &[0x40, 0x00, 0x10, 0])).is_empty());
    assert!(n
        .send(f(0x606, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]))
        .is_empty());
    assert_eq!(n.sdo_read(0x1000, 0), Ok(vec![0, 0, 0, 0]));
}

#[test]
fn pdo_defaults_of_the_fixture() {
    let mut n = node();
    assert_eq!(n.sdo_read(0x1400, 1), Ok(0x205u32.to_le_bytes().to_vec()));
    assert_eq!(n.sdo_read(0x1401, 1), Ok(0x305u32.to_le_bytes().to_vec()));
    assert_eq!(n.sdo_read(0x1800, 1), Ok(0x185u32.to_le_bytes().to_vec()));
    assert_eq!(n.sdo_read(0x1801, 1), Ok(0x285u32.to_le_bytes().to_vec()));
    assert_eq!(
        n.sdo_read(0x1A00, 1),
        Ok(0x2108_0020u32.to_le_bytes().to_vec())
    );
}

#[test]
fn event_driven_tpdos_on_entering_operational_and_on_change() {
    let mut n = node();
    let out = n.nmt(0x01, ID);
    // Status word 0x0200 (bit 9 remote) at bytes 4-5; act. position 0; inputs 0.
    assert!(
        out.contains(&f(0x185, &[0, 0, 0, 0, 0x00, 0x02, 0, 0])),
        "{out:?}"
    );
    assert!(
        out.contains(&f(0x285, &[0, 0, 0, 0, 0x00, 0x02, 0, 0])),
        "{out:?}"
    );
    // The axes leave power-on (Switch on disabled, 0x0640); then nothing changes and nothing is sent.
    let out = n.advance_ms(1500);
    assert_eq!(out.last(), Some(&f(0x285, &[0, 0, 0, 0, 0x40, 0x06, 0, 0])));
    assert_eq!(n.advance_ms(100), vec![]);
    // X67-18.14-01: DI1 goes high: input object 1 byte 6 bit 0 within one X2X cycle.
    n.sdo_write(0x5F00, 1, &[0x01]).unwrap();
    let out = n.advance_ms(1);
    assert_eq!(out, vec![f(0x185, &[0, 0, 0, 0, 0x40, 0x06, 0x01, 0])]);
}

#[test]
fn synchronous_tpdos_every_nth_sync() {
    let mut n = node();
    n.sdo_write(0x1800, 2, &[1]).unwrap();
    n.sdo_write(0x1801, 2, &[3]).unwrap();
    n.nmt(0x01, ID);
    n.advance_ms(5);
    let mut tpdo1 = 0;
    let mut tpdo2 = 0;
    for _ in 0..6 {
        for x in n.send(f(0x080, &[])) {
            match x.cob_id() {
                Some(0x185) => tpdo1 += 1,
                Some(0x285) => tpdo2 += 1,
                _ => {}
            }
        }
        n.advance_ms(1);
    }
    assert_eq!((tpdo1, tpdo2), (6, 2));
}

#[test]
fn sync_producer_from_1005_bit_30_and_1006() {
    let mut n = node();
    n.sdo_write(0x1006, 0, &10_000u32.to_le_bytes()).unwrap();
    n.sdo_write(0x1005, 0, &0x4000_0080u32.to_le_bytes())
        .unwrap();
    let out = n.advance_ms(100);
    let syncs = out.iter().filter(|x| x.cob_id() == Some(0x080)).count();
    assert_eq!(syncs, 10);
    assert!(out
        .iter()
        .filter(|x| x.cob_id() == Some(0x080))
        .all(|x| x.is_empty()));
}

#[test]
fn rpdo_drives_the_axis_and_a_short_rpdo_raises_emcy_8210() {
    let mut n = node();
    n.nmt(0x01, ID);
    // Control word 0x0006 (shutdown), mode 1, position 0.
    n.send(f(0x205, &[0, 0, 0, 0, 0x06, 0x00, 0x01, 0]));
    assert_eq!(n.sdo_read(0x2101, 0).unwrap(), vec![0x06, 0x00]);
    assert_eq!(n.sdo_read(0x2102, 0).unwrap(), vec![0x01]);
    let out = n.send(f(0x205, &[0, 0, 0]));
    assert_eq!(
        out,
        vec![f(0x085, &[0x10, 0x82, 0x11, 0x05, 0x02, 3, 8, 0])]
    );
}

#[test]
fn pdo_mapping_procedure_and_its_aborts() {
    let mut n = node();
    // PDO valid: the mapping cannot change (0x06040043).
    assert_eq!(n.sdo_write(0x1A01, 0, &[0]), Err(0x0604_0043));
    // Step 1: destroy the PDO.
    n.sdo_write(0x1801, 1, &0x8000_0285u32.to_le_bytes())
        .unwrap();
    // Entries only while sub 0 is 0 (0x06040043).
    assert_eq!(
        n.sdo_write(0x1A01, 3, &0x2008_0008u32.to_le_bytes()),
        Err(0x0604_0043)
    );
    // Step 2.
    n.sdo_write(0x1A01, 0, &[0]).unwrap();
    // A configuration register cannot be mapped (X67-18.5-02): 0x06040041; a missing object 0x06020000.
    assert_eq!(
        n.sdo_write(0x1A01, 3, &0x2114_0010u32.to_le_bytes()),
        Err(0x0604_0041)
    );
    assert_eq!(
        n.sdo_write(0x1A01, 3, &0x2F00_0008u32.to_le_bytes()),
        Err(0x0602_0000)
    );
    // An RPDO-only object in a TPDO, and a wrong length: 0x06040041.
    assert_eq!(
        n.sdo_write(0x1A01, 3, &0x2100_0020u32.to_le_bytes()),
        Err(0x0604_0041)
    );
    assert_eq!(
        n.sdo_write(0x1A01, 3, &0x2008_0010u32.to_le_bytes()),
        Err(0x0604_0041)
    );
    // Step 3: InputStatus and the error register into bytes 6 and 7.
    n.sdo_write(0x1A01, 3, &0x2008_0008u32.to_le_bytes())
        .unwrap();
    assert_eq!(
        n.sdo_write(0x1A01, 4, &0x1001_0008u32.to_le_bytes()),
        Err(0x0609_0011)
    );
    // Step 4: more than 64 bits: 0x06040042 (4 + 2 + 1 = 7 bytes is fine).
    n.sdo_write(0x1A01, 0, &[3]).unwrap();
    n.sdo_write(0x1A01, 0, &[0]).unwrap();
    n.sdo_write(0x1A01, 1, &0x2208_0020u32.to_le_bytes())
        .unwrap();
    n.sdo_write(0x1A01, 2, &0x2108_0020u32.to_le_bytes())
        .unwrap();
    n.sdo_write(0x1A01, 3, &0x2008_0008u32.to_le_bytes())
        .unwrap();
    assert_eq!(n.sdo_write(0x1A01, 0, &[3]), Err(0x0604_0042));
    n.sdo_write(0x1A01, 2, &0x2209_0010u32.to_le_bytes())
        .unwrap();
    n.sdo_write(0x1A01, 0, &[3]).unwrap();
    // Step 5: create the PDO; a new CAN-ID is allowed while invalid.
    n.sdo_write(0x1801, 1, &0x0000_0385u32.to_le_bytes())
        .unwrap();
    // While valid, the CAN-ID cannot change (0x06090030); restricted IDs are refused.
    assert_eq!(
        n.sdo_write(0x1801, 1, &0x0000_0386u32.to_le_bytes()),
        Err(0x0609_0030)
    );
    assert_eq!(
        n.sdo_write(0x1800, 1, &0x8000_0605u32.to_le_bytes()),
        Err(0x0609_0030)
    );
    // The new map on the wire: act. pos 2 (4), status 2 (2), inputs (1) = 7 bytes on 0x385.
    n.sdo_write(0x5F00, 1, &[0x21]).unwrap();
    let out = n.nmt(0x01, ID);
    assert!(
        out.contains(&f(0x385, &[0, 0, 0, 0, 0x00, 0x02, 0x21])),
        "{out:?}"
    );
    // In Operational the mapping cannot change at all (0x08000022).
    n.sdo_write(0x1801, 1, &0x8000_0385u32.to_le_bytes())
        .unwrap();
    assert_eq!(n.sdo_write(0x1A01, 0, &[0]), Err(0x0800_0022));
}

/// CiA 301: transmission types 241–251 are reserved; 252 and 253 (remote request only) are TPDO
/// types, refused for an RPDO.
#[test]
fn reserved_transmission_types_are_refused() {
    let mut n = node();
    for t in [241u8, 245, 251] {
        assert_eq!(n.sdo_write(0x1800, 2, &[t]), Err(0x0609_0030), "type {t}");
        assert_eq!(n.sdo_write(0x1400, 2, &[t]), Err(0x0609_0030), "type {t}");
    }
    for t in [252u8, 253] {
        assert_eq!(n.sdo_write(0x1400, 2, &[t]), Err(0x0609_0030), "type {t}");
    }
    for t in [0u8, 1, 240, 252, 253, 254, 255] {
        assert_eq!(n.sdo_write(0x1800, 2, &[t]), Ok(()), "type {t}");
        assert_eq!(n.sdo_read(0x1800, 2), Ok(vec![t]), "type {t}");
    }
}

#[test]
fn emcy_on_over_temperature_and_its_reset() {
    let mut n = node();
    n.advance_ms(30);
    // 90 °C: error 0x4200 on both axes (module 1, axes 1 and 2), error register 0x09.
    n.sdo_write(0x5F00, 3, &[90]).unwrap();
    let out: Vec<_> = n
        .advance_ms(30)
        .into_iter()
        .filter(|x| x.cob_id() == Some(0x085))
        .collect();
    assert_eq!(
        out,
        vec![
            f(0x085, &[0x00, 0x42, 0x09, 1, 1, 0, 0, 0]),
            f(0x085, &[0x00, 0x42, 0x09, 1, 2, 0, 0, 0]),
        ]
    );
    assert_eq!(n.sdo_read(0x1001, 0), Ok(vec![0x09]));
    assert_eq!(n.sdo_read(0x1003, 0), Ok(vec![2]));
    assert_eq!(n.sdo_read(0x1003, 1), Ok(0x4200u32.to_le_bytes().to_vec()));
    // Only 0 may be written to 1003:00.
    assert_eq!(n.sdo_write(0x1003, 0, &[1]), Err(0x0609_0030));
    n.sdo_write(0x1003, 0, &[0]).unwrap();
    assert_eq!(n.sdo_read(0x1003, 0), Ok(vec![0]));
}

#[test]
fn emcy_on_supply_voltage_error() {
    let mut n = node();
    n.advance_ms(30);
    n.sdo_write(0x5F00, 2, &100u16.to_le_bytes()).unwrap(); // 10.0 V
    let out: Vec<_> = n
        .advance_ms(60)
        .into_iter()
        .filter(|x| x.cob_id() == Some(0x085))
        .collect();
    assert!(
        out.contains(&f(0x085, &[0x00, 0x30, 0x05, 1, 1, 0, 0, 0])),
        "{out:?}"
    );
}

#[test]
fn heartbeat_consumer_timeout_emcy_8130_and_back_to_pre_operational() {
    let mut n = node();
    // Monitor node 0x7F (the master) with 100 ms.
    n.sdo_write(0x1016, 1, &0x007F_0064u32.to_le_bytes())
        .unwrap();
    n.nmt(0x01, ID);
    n.send(f(0x77F, &[0x05]));
    n.advance_ms(90);
    n.send(f(0x77F, &[0x05]));
    let out = n.advance_ms(99);
    assert!(out.iter().all(|x| x.cob_id() != Some(0x085)));
    let out = n.advance_ms(2);
    assert!(
        out.contains(&f(0x085, &[0x30, 0x81, 0x11, 0x7F, 0, 0, 0, 0])),
        "{out:?}"
    );
    assert_eq!(n.node.state(), NmtState::PreOperational);
    let out = n.send(f(0x77F, &[0x05]));
    assert!(
        out.contains(&f(0x085, &[0x00, 0x00, 0x00, 0x7F, 0, 0x30, 0x81, 0])),
        "{out:?}"
    );
}

#[test]
fn store_and_restore_parameters() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("node5.params");
    let storage = || Box::new(FileStorage::new(&path)) as Box<dyn ParameterStorage>;
    let mut n = SimNode::with(NodeConfig::new(ID), 1, storage()).unwrap();
    n.sdo_write(0x1017, 0, &[0xE8, 0x03]).unwrap();
    n.sdo_write(0x2114, 0, &[0x10, 0x27]).unwrap(); // MaxSpeed01pos 10000
                                                    // Wrong signature: 0x08000020, nothing stored.
    assert_eq!(n.sdo_write(0x1010, 1, b"savf"), Err(0x0800_0020));
    assert!(!path.exists());
    n.sdo_write(0x1010, 1, b"save").unwrap();
    assert_eq!(n.sdo_read(0x1010, 1), Ok(vec![1, 0, 0, 0]));
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("1017:00 E803\n"), "{text}");
    assert!(text.contains("2114:00 1027\n"), "{text}");
    // A new process with the same file starts with the stored values.
    let mut m = SimNode::with(NodeConfig::new(ID), 1, storage()).unwrap();
    assert_eq!(m.sdo_read(0x1017, 0), Ok(vec![0xE8, 0x03]));
    assert_eq!(m.node.app().modules()[0].read_named("MaxSpeed01pos"), 10000);
    // "load": the values stay until the next reset, then the defaults return.
    assert_eq!(m.sdo_write(0x1011, 1, b"lobd"), Err(0x0800_0020));
    m.sdo_write(0x1011, 1, b"load").unwrap();
    assert_eq!(m.sdo_read(0x1017, 0), Ok(vec![0xE8, 0x03]));
    m.nmt(0x81, ID);
    assert_eq!(m.sdo_read(0x1017, 0), Ok(vec![0, 0]));
    assert_eq!(m.node.app().modules()[0].read_named("MaxSpeed01pos"), 0);
}

/// A storage that fails every write (a full or read-only disk), holding `kept` as its set.
struct FailingStorage {
    kept: Option<Vec<u8>>,
}

impl ParameterStorage for FailingStorage {
    fn load(&mut self) -> std::io::Result<Option<Vec<u8>>> {
        Ok(self.kept.clone())
    }
    fn save(&mut self, _: &[u8]) -> std::io::Result<()> {
        Err(std::io::Error::other("no space left on device"))
    }
    fn clear(&mut self) -> std::io::Result<()> {
        Err(std::io::Error::other("read-only file system"))
    }
}

/// A save or restore the storage cannot carry out is answered with abort 0x08000020 (CiA 301: data
/// cannot be transferred or stored), and changes nothing: the next reset loads what the storage
/// holds, as before the request.
#[test]
fn a_save_the_storage_refuses_is_answered_with_an_abort() {
    // What the storage holds: heartbeat 1000 ms.
    let mut saved = SimNode::new(ID, 1).unwrap();
    saved.sdo_write(0x1017, 0, &[0xE8, 0x03]).unwrap();
    saved.sdo_write(0x1010, 1, b"save").unwrap();
    let kept = saved.storage.load().unwrap();
    assert!(kept.is_some());
    let storage = Box::new(FailingStorage { kept });
    let mut n = SimNode::with(NodeConfig::new(ID), 1, storage).unwrap();
    assert_eq!(n.sdo_read(0x1017, 0), Ok(vec![0xE8, 0x03]));
    n.sdo_write(0x1017, 0, &[0xD0, 0x07]).unwrap();
    assert_eq!(
        n.send(f(0x605, &[0x23, 0x10, 0x10, 0x01, b's', b'a', b'v', b'e'])),
        vec![f(0x585, &[0x80, 0x10, 0x10, 0x01, 0x20, 0x00, 0x00, 0x08])]
    );
    assert_eq!(
        n.send(f(0x605, &[0x23, 0x11, 0x10, 0x01, b'l', b'o', b'a', b'd'])),
        vec![f(0x585, &[0x80, 0x11, 0x10, 0x01, 0x20, 0x00, 0x00, 0x08])]
    );
    // Reset node: the stored 1000 ms, neither the 2000 ms of the failed save nor the defaults of the
    // failed restore.
    n.nmt(0x81, ID);
    assert_eq!(n.sdo_read(0x1017, 0), Ok(vec![0xE8, 0x03]));
}

/// CiA 301 §7.5.2.13/§7.5.2.14 on a sans-IO node: "save" and "load" become requests to the edge's
/// storage, answered once the edge reports them done (the answer confirms the save); the node
/// itself writes nothing, and a set handed to a new node before it starts is loaded at its boot.
#[test]
fn save_and_restore_are_requests_to_the_edge() {
    let t0 = std::time::Instant::now();
    let build = || {
        let dict = x67::dictionary(1).unwrap();
        let app = BusController::new(&dict, 1, x67::DEFAULT_X2X_CYCLE, t0).unwrap();
        Node::new(NodeConfig::new(ID), dict, app, t0).unwrap()
    };
    let exchange = |node: &mut Node<BusController>, request: [u8; 8]| {
        node.handle_frame(t0, &f(0x605, &request));
        let mut sent = Vec::new();
        while let Some(frame) = node.poll_transmit() {
            sent.push(frame);
        }
        sent
    };
    let mut node = build();
    node.start(t0);
    assert_eq!(node.poll_transmit(), Some(f(0x705, &[0x00])));
    // 0x1017:00 = 1000 ms, then "save" to 0x1010:01.
    let sent = exchange(&mut node, [0x2B, 0x17, 0x10, 0x00, 0xE8, 0x03, 0, 0]);
    assert_eq!(sent, vec![f(0x585, &[0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0])]);
    assert_eq!(
        node.poll_storage(),
        None,
        "a plain write asks nothing of the storage"
    );
    let sent = exchange(&mut node, [0x23, 0x10, 0x10, 0x01, b's', b'a', b'v', b'e']);
    assert_eq!(sent, vec![], "no answer before the edge has saved");
    let Some(StorageRequest::Save(set)) = node.poll_storage() else {
        panic!("a save request");
    };
    // Meanwhile the node's other services go on: a heartbeat of 1000 ms leaves at t0 + 1 s.
    node.handle_timeout(t0 + std::time::Duration::from_secs(1));
    assert_eq!(node.poll_transmit(), Some(f(0x705, &[0x7F])));
    assert_eq!(node.poll_transmit(), None);
    node.storage_done(true);
    assert_eq!(
        node.poll_transmit(),
        Some(f(0x585, &[0x60, 0x10, 0x10, 0x01, 0, 0, 0, 0]))
    );
    let text = String::from_utf8(set.clone()).unwrap();
    assert!(text.starts_with("x67-node parameters 1\n"), "{text}");
    assert!(text.contains("1017:00 E803\n"), "{text}");
    assert_eq!(node.poll_storage(), None, "one request per save");
    // "load" to 0x1011:01: forget the set.
    let sent = exchange(&mut node, [0x23, 0x11, 0x10, 0x01, b'l', b'o', b'a', b'd']);
    assert_eq!(sent, vec![]);
    assert_eq!(node.poll_storage(), Some(StorageRequest::Clear));
    node.storage_done(true);
    assert_eq!(
        node.poll_transmit(),
        Some(f(0x585, &[0x60, 0x11, 0x10, 0x01, 0, 0, 0, 0]))
    );
    // A new node given the saved set boots with its heartbeat of 1000 ms.
    let lines = text.lines().count();
    let mut next = build();
    next.set_stored(Some(set));
    next.start(t0);
    assert_eq!(next.poll_transmit(), Some(f(0x705, &[0x00])));
    let events: Vec<NodeEvent> = std::iter::from_fn(|| next.poll_event()).collect();
    // Every entry of the set (its lines but the first, naming the format, and the last, the CRC).
    assert!(events.contains(&NodeEvent::Loaded(lines - 2)), "{events:?}");
    let sent = exchange(&mut next, [0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0]);
    assert_eq!(
        sent,
        vec![f(0x585, &[0x4B, 0x17, 0x10, 0x00, 0xE8, 0x03, 0, 0])]
    );
    // Without a set: the default 0.
    let mut fresh = build();
    fresh.start(t0);
    let _ = fresh.poll_transmit();
    let events: Vec<NodeEvent> = std::iter::from_fn(|| fresh.poll_event()).collect();
    assert!(
        !events.iter().any(|e| matches!(e, NodeEvent::Loaded(_))),
        "nothing loaded: no Loaded event; {events:?}"
    );
    let sent = exchange(&mut fresh, [0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0]);
    assert_eq!(sent, vec![f(0x585, &[0x4B, 0x17, 0x10, 0x00, 0, 0, 0, 0])]);
}

#[test]
fn reset_communication_keeps_the_application() {
    let mut n = node();
    n.sdo_write(0x2114, 0, &[0x10, 0x27]).unwrap();
    n.sdo_write(0x1017, 0, &[100, 0]).unwrap();
    let out = n.nmt(0x82, ID);
    assert_eq!(out, vec![f(0x705, &[0x00])]);
    assert_eq!(n.sdo_read(0x1017, 0), Ok(vec![0, 0]));
    assert_eq!(n.node.app().modules()[0].read_named("MaxSpeed01pos"), 10000);
    let out = n.nmt(0x81, ID);
    assert_eq!(out, vec![f(0x705, &[0x00])]);
    assert_eq!(n.node.app().modules()[0].read_named("MaxSpeed01pos"), 0);
}

#[test]
fn register_refusals_keep_their_abort_codes() {
    let mut n = node();
    // ConfigOutput03a above 167 %: value too high.
    assert_eq!(n.sdo_write(0x2110, 0, &[168]), Err(0x0609_0031));
    // Read-only register.
    assert_eq!(n.sdo_write(0x2108, 0, &[0, 0, 0, 0]), Err(0x0601_0002));
    // Write-only register.
    assert_eq!(n.sdo_read(0x2114, 0), Err(0x0601_0001));
    // Read-back reflects the write at once.
    n.sdo_write(0x2110, 0, &[50]).unwrap();
    assert_eq!(n.sdo_read(0x2130, 0), Ok(vec![50]));
}

#[test]
fn second_module_objects_and_pdos() {
    let mut n = SimNode::new(9, 2).unwrap();
    assert_eq!(n.sdo_read(0x1802, 1), Ok(0x389u32.to_le_bytes().to_vec()));
    assert_eq!(n.sdo_read(0x1803, 1), Ok(0x489u32.to_le_bytes().to_vec()));
    assert_eq!(n.sdo_read(0x1402, 1), Ok(0x409u32.to_le_bytes().to_vec()));
    assert_eq!(n.sdo_read(0x1403, 1), Ok(0x509u32.to_le_bytes().to_vec()));
    assert_eq!(
        n.sdo_read(0x1A02, 1),
        Ok(0x2408_0020u32.to_le_bytes().to_vec())
    );
    assert_eq!(
        n.sdo_read(0x1A03, 3),
        Ok(0x0006_0010u32.to_le_bytes().to_vec())
    );
    n.sdo_write(0x2414, 0, &[0x20, 0x00]).unwrap();
    assert_eq!(n.node.app().modules()[1].read_named("MaxSpeed01pos"), 0x20);
    assert_eq!(n.node.app().modules()[0].read_named("MaxSpeed01pos"), 0);
    n.sdo_write(0x5F01, 1, &[0x04]).unwrap();
    assert_eq!(n.sdo_read(0x2308, 0), Ok(vec![0x04]));
    assert_eq!(n.sdo_read(0x2008, 0), Ok(vec![0x00]));
}

/// An NMT reset ends any SDO transfer (CiA 301 §7.3.2.2.1: the communication parameters and the
/// SDO server start again): a block download begun before "reset communication" or "reset node"
/// does not swallow the next request as its segment; the next upload is answered at once.
#[test]
fn an_nmt_reset_ends_an_sdo_block_download() {
    for reset in [0x82u8, 0x81] {
        let mut n = node();
        // Block download of 2 bytes to 0x1017:00, CRC supported: the server takes it, 127 per block.
        assert_eq!(
            n.send(f(0x605, &[0xC6, 0x17, 0x10, 0x00, 0x02, 0, 0, 0])),
            vec![f(0x585, &[0xA4, 0x17, 0x10, 0x00, 0x7F, 0, 0, 0])],
            "reset {reset:#04x}"
        );
        assert_eq!(
            n.nmt(reset, ID),
            vec![f(0x705, &[0x00])],
            "reset {reset:#04x}"
        );
        // Upload of 0x1018:00: four entries.
        assert_eq!(
            n.send(f(0x605, &[0x40, 0x18, 0x10, 0x00, 0, 0, 0, 0])),
            vec![f(0x585, &[0x4F, 0x18, 0x10, 0x00, 0x04, 0, 0, 0])],
            "reset {reset:#04x}"
        );
        // Nothing of the old transfer comes later (its timer is gone with it).
        assert_eq!(
            n.advance_ms(2_000),
            Vec::<CanFrame>::new(),
            "reset {reset:#04x}"
        );
    }
}

/// The other NMT commands leave an SDO transfer alone: a segmented upload goes on across a start.
#[test]
fn an_nmt_start_does_not_end_an_sdo_transfer() {
    let mut n = node();
    assert_eq!(
        n.send(f(0x605, &[0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0])),
        vec![f(0x585, &[0x41, 0x08, 0x10, 0x00, 24, 0, 0, 0])]
    );
    n.nmt(0x01, ID);
    assert_eq!(n.node.state(), NmtState::Operational);
    let out = n.send(f(0x605, &[0x60, 0, 0, 0, 0, 0, 0, 0]));
    assert_eq!(out, vec![f(0x585, b"\x00X67BC43")]);
}

/// A fork is a second node in the same state that runs on its own: a write to the fork leaves the
/// original as it was, and the set the original had saved (0x1010:01 "save") is the fork's stored
/// set, loaded at its reset node.
#[test]
fn a_forked_node_runs_on_its_own_with_a_copy_of_the_stored_set() {
    let mut a = node();
    let ms = |v: u16| Ok(v.to_le_bytes().to_vec());
    a.sdo_write(0x1017, 0, &200u16.to_le_bytes()).unwrap();
    a.sdo_write(0x1010, 1, b"save").unwrap();
    a.sdo_write(0x1017, 0, &300u16.to_le_bytes()).unwrap();
    let mut b = a.fork();
    assert_eq!(b.sdo_read(0x1017, 0), ms(300));
    b.sdo_write(0x1017, 0, &400u16.to_le_bytes()).unwrap();
    assert_eq!(a.sdo_read(0x1017, 0), ms(300));
    assert_eq!(b.sdo_read(0x1017, 0), ms(400));
    b.nmt(0x81, ID);
    assert_eq!(
        b.sdo_read(0x1017, 0),
        ms(200),
        "the saved set, at the fork's reset"
    );
    assert_eq!(a.sdo_read(0x1017, 0), ms(300), "the original not reset");
}
