//! LSS (CiA 305) and TIME (CiA 301 §7.2.6) of a node, in process on a simulated clock: every request
//! and answer byte for byte as CiA 305 §8 lays them out (byte 0 the command specifier).

use std::path::Path;
use std::time::{Duration, Instant};

use od::abort::AbortCode;
use od::dict::Address;
use od::hook::DeviceHook;
use socketcan_node::node::lss::{LssSlave, LssState};
use socketcan_node::node::storage::{LssStored, MemoryStorage};
use socketcan_node::node::time::TimeOfDay;
use socketcan_node::node::{Device, DeviceError, LssConfig, NodeEvent};
use socketcan_node::sim::SimNode;
use socketcan_node::{CanFrame, NmtState, Node, NodeConfig};

/// A device whose dictionary is the whole device.
#[derive(Clone)]
struct Plain;

/// A device hook that owns no object: the dictionary is the whole device.
macro_rules! owns_no_object {
    ($device:ty) => {
        impl DeviceHook for $device {
            fn owns(&self, _: u16) -> bool {
                false
            }
            fn read(&self, _: Address, _: &mut [u8; 8]) -> Option<usize> {
                None
            }
            fn write(&mut self, _: Address, _: &[u8], _: Instant) -> Result<(), AbortCode> {
                Ok(())
            }
        }
    };
}

owns_no_object!(Plain);

impl Device for Plain {
    fn handle_timeout(&mut self, _: Instant) {}
    fn poll_timeout(&self) -> Option<Instant> {
        None
    }
    fn errors(&self, _: &mut Vec<DeviceError>) {}
    fn reset(&mut self, _: Instant) {}
}

/// The identity of examples/io-device.eds (0x1018:01–04).
const VENDOR: u32 = 0x0ABC;
const PRODUCT: u32 = 0x0401;
const REVISION: u32 = 0x0001_0001;
const SERIAL: u32 = 1;

fn io_device(node_id: u8, can_store: bool) -> SimNode<Plain> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/io-device.eds");
    let (_, mut devices) = od::load::load(&path).unwrap();
    let dict = devices.remove(0).dictionary;
    let config = NodeConfig {
        lss: Some(LssConfig {
            bit_timing: 4,
            can_store,
        }),
        ..NodeConfig::new(node_id)
    };
    let t0 = Instant::now();
    let node = Node::new(config, dict, Plain, t0).unwrap();
    SimNode::boot(node, t0, Box::new(MemoryStorage::default()))
}

fn f(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

/// An LSS request; returns what the node sent.
fn lss<A: Device>(n: &mut SimNode<A>, data: [u8; 8]) -> Vec<CanFrame> {
    n.send(f(0x7E5, &data))
}

fn with_u32(cs: u8, value: u32) -> [u8; 8] {
    let v = value.to_le_bytes();
    [cs, v[0], v[1], v[2], v[3], 0, 0, 0]
}

/// The LSS answer `data` (COB-ID 0x7E4).
fn answer(data: [u8; 8]) -> Vec<CanFrame> {
    vec![f(0x7E4, &data)]
}

#[test]
fn an_unconfigured_node_is_silent_but_for_lss() {
    let mut n = io_device(0xFF, true);
    assert_eq!(n.node.node_id(), 0xFF);
    assert_eq!(n.node.state(), NmtState::Initialising);
    assert!(n.sent.is_empty(), "no boot-up: {:?}", n.sent);
    // NMT, SDO to any node, SYNC: nothing.
    assert!(n.nmt(0x81, 0).is_empty());
    assert!(n.nmt(0x01, 0).is_empty());
    for id in [0x600, 0x601, 0x67F, 0x6FF] {
        assert!(n.send(f(id, &[0x40, 0, 0x10, 0, 0, 0, 0, 0])).is_empty());
    }
    assert!(n.send(f(0x080, &[])).is_empty());
    assert!(n.advance_ms(5000).is_empty());
    assert_eq!(n.node.state(), NmtState::Initialising);
    // Identify non-configured remote slave: 0x4C, answered 0x50 (CiA 305 §8.4.3).
    assert_eq!(
        lss(&mut n, [0x4C, 0, 0, 0, 0, 0, 0, 0]),
        answer([0x50, 0, 0, 0, 0, 0, 0, 0])
    );
}

/// A device with a timer of its own every 10 ms (a drive's control cycle), counting its ticks.
#[derive(Clone)]
struct Ticking {
    next: Instant,
    ticks: u32,
}

owns_no_object!(Ticking);

impl Device for Ticking {
    fn handle_timeout(&mut self, now: Instant) {
        while self.next <= now {
            self.next += Duration::from_millis(10);
            self.ticks += 1;
        }
    }
    fn poll_timeout(&self) -> Option<Instant> {
        Some(self.next)
    }
    fn errors(&self, _: &mut Vec<DeviceError>) {}
    fn reset(&mut self, _: Instant) {}
}

/// A node without a node-ID waits for LSS and runs no timer, so it asks its edge for none: a
/// deadline it reported but never moved on (the device's own, here every 10 ms) kept a runtime
/// calling it in a busy loop, a whole core for an idle node.
#[test]
fn an_unconfigured_node_asks_for_no_timer() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/io-device.eds");
    let (_, mut devices) = od::load::load(&path).unwrap();
    let dict = devices.remove(0).dictionary;
    let config = NodeConfig {
        lss: Some(LssConfig {
            bit_timing: 4,
            can_store: false,
        }),
        ..NodeConfig::new(0xFF)
    };
    let t0 = Instant::now();
    let app = Ticking {
        next: t0 + Duration::from_millis(10),
        ticks: 0,
    };
    let node = Node::new(config, dict, app, t0).unwrap();
    let mut n = SimNode::boot(node, t0, Box::new(MemoryStorage::default()));
    assert_eq!(n.node.state(), NmtState::Initialising);
    assert_eq!(n.node.poll_timeout(), None);
    n.stall(Duration::from_millis(35));
    assert_eq!(n.node.poll_timeout(), None);
    assert!(n.sent.is_empty(), "{:?}", n.sent);
    // Given node-ID 9 (switch state global, configure node-ID, back to waiting): boot-up, and the
    // device's timer runs again from the next call on.
    assert!(lss(&mut n, [0x04, 1, 0, 0, 0, 0, 0, 0]).is_empty());
    assert_eq!(
        lss(&mut n, [0x11, 9, 0, 0, 0, 0, 0, 0]),
        answer([0x11, 0, 0, 0, 0, 0, 0, 0])
    );
    assert_eq!(
        lss(&mut n, [0x04, 0, 0, 0, 0, 0, 0, 0]),
        vec![f(0x709, &[0])]
    );
    assert_eq!(n.node.state(), NmtState::PreOperational);
    let due = n.node.poll_timeout().expect("the device's timer");
    assert!(due > n.now, "{due:?} is not after {:?}", n.now);
    n.advance_ms(100);
    assert!(n.node.app().ticks >= 10, "{} ticks", n.node.app().ticks);
}

#[test]
fn configuration_by_switch_state_global() {
    let mut n = io_device(0xFF, true);
    // In the waiting state the configuration services are not answered.
    assert!(lss(&mut n, [0x5E, 0, 0, 0, 0, 0, 0, 0]).is_empty());
    assert!(lss(&mut n, [0x11, 5, 0, 0, 0, 0, 0, 0]).is_empty());
    // Switch state global, configuration (0x04 01): no answer.
    assert!(lss(&mut n, [0x04, 1, 0, 0, 0, 0, 0, 0]).is_empty());
    assert_eq!(n.node.lss().unwrap().state(), LssState::Configuration);
    // Inquire node-ID: 0xFF; identity: 0x1018:01–04.
    assert_eq!(
        lss(&mut n, [0x5E, 0, 0, 0, 0, 0, 0, 0]),
        answer([0x5E, 0xFF, 0, 0, 0, 0, 0, 0])
    );
    for (cs, value) in [
        (0x5A, VENDOR),
        (0x5B, PRODUCT),
        (0x5C, REVISION),
        (0x5D, SERIAL),
    ] {
        assert_eq!(
            lss(&mut n, [cs, 0, 0, 0, 0, 0, 0, 0]),
            answer(with_u32(cs, value))
        );
    }
    // Configure node-ID: 0 and 128 are out of range (error 1), 5 is taken (error 0).
    for bad in [0u8, 128, 200] {
        assert_eq!(
            lss(&mut n, [0x11, bad, 0, 0, 0, 0, 0, 0]),
            answer([0x11, 1, 0, 0, 0, 0, 0, 0])
        );
    }
    assert_eq!(
        lss(&mut n, [0x11, 5, 0, 0, 0, 0, 0, 0]),
        answer([0x11, 0, 0, 0, 0, 0, 0, 0])
    );
    // Still the old node-ID until the slave leaves the configuration state.
    assert_eq!(
        lss(&mut n, [0x5E, 0, 0, 0, 0, 0, 0, 0]),
        answer([0x5E, 0xFF, 0, 0, 0, 0, 0, 0])
    );
    // Bit timing: table 0, index 2 (500 kbit/s) taken; index 5 (reserved), 9 (automatic) and
    // table 1 refused with error 1.
    assert_eq!(
        lss(&mut n, [0x13, 0, 2, 0, 0, 0, 0, 0]),
        answer([0x13, 0, 0, 0, 0, 0, 0, 0])
    );
    for (table, index) in [(0, 5), (0, 9), (1, 0)] {
        assert_eq!(
            lss(&mut n, [0x13, table, index, 0, 0, 0, 0, 0]),
            answer([0x13, 1, 0, 0, 0, 0, 0, 0])
        );
    }
    assert_eq!(n.node.lss().unwrap().bit_timing(), 2);
    // Activate bit timing (delay 100 ms): no answer, reported.
    assert!(lss(&mut n, [0x15, 100, 0, 0, 0, 0, 0, 0]).is_empty());
    assert!(std::iter::from_fn(|| n.node.poll_event()).any(|e| e == NodeEvent::BitTiming(2)));
    // Store configuration: stored (error 0), the edge keeps node-ID 5 and index 2.
    assert_eq!(
        lss(&mut n, [0x17, 0, 0, 0, 0, 0, 0, 0]),
        answer([0x17, 0, 0, 0, 0, 0, 0, 0])
    );
    assert_eq!(
        n.storage.load_lss().unwrap(),
        Some(LssStored {
            node_id: 5,
            bit_timing: 2
        })
    );
    // Back to waiting: the node had no node-ID, so it takes 5 at once and boots (CiA 305 §8.3.1).
    let before = n.elapsed();
    assert_eq!(
        lss(&mut n, [0x04, 0, 0, 0, 0, 0, 0, 0]),
        vec![f(0x705, &[0x00])]
    );
    assert_eq!(n.sent.last().unwrap().0, before);
    assert_eq!(n.node.node_id(), 5);
    assert_eq!(n.node.state(), NmtState::PreOperational);
    // SDO on 0x605, EMCY COB-ID $NODEID+0x80 = 0x85.
    assert_eq!(n.sdo_read(0x1014, 0), Ok(vec![0x85, 0, 0, 0]));
    assert_eq!(n.sdo_read(0x1000, 0), Ok(vec![0x91, 0x01, 0x0F, 0x00]));
    // A configured node answers no identify non-configured.
    assert!(lss(&mut n, [0x4C, 0, 0, 0, 0, 0, 0, 0]).is_empty());
}

/// A store configuration the edge's storage cannot keep (here a storage for parameter sets only) is
/// answered with error 2, "storage media access error" (CiA 305 §8.3.6), once the edge reports it.
#[test]
fn store_on_a_storage_that_fails_is_a_media_access_error() {
    struct SetsOnly;
    impl socketcan_node::node::storage::ParameterStorage for SetsOnly {
        fn load(&mut self) -> std::io::Result<Option<Vec<u8>>> {
            Ok(None)
        }
        fn save(&mut self, _: &[u8]) -> std::io::Result<()> {
            Ok(())
        }
        fn clear(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/io-device.eds");
    let (_, mut devices) = od::load::load(&path).unwrap();
    let config = NodeConfig {
        lss: Some(LssConfig {
            bit_timing: 4,
            can_store: true,
        }),
        ..NodeConfig::new(3)
    };
    let t0 = Instant::now();
    let node = Node::new(config, devices.remove(0).dictionary, Plain, t0).unwrap();
    let mut n = SimNode::boot(node, t0, Box::new(SetsOnly));
    assert!(lss(&mut n, [0x04, 1, 0, 0, 0, 0, 0, 0]).is_empty());
    assert_eq!(
        lss(&mut n, [0x17, 0, 0, 0, 0, 0, 0, 0]),
        answer([0x17, 2, 0, 0, 0, 0, 0, 0])
    );
}

#[test]
fn store_without_storage_is_not_supported() {
    let mut n = io_device(0xFF, false);
    lss(&mut n, [0x04, 1, 0, 0, 0, 0, 0, 0]);
    assert_eq!(
        lss(&mut n, [0x17, 0, 0, 0, 0, 0, 0, 0]),
        answer([0x17, 1, 0, 0, 0, 0, 0, 0])
    );
    assert_eq!(n.storage.load_lss().unwrap(), None);
}

#[test]
fn a_configured_node_takes_its_new_node_id_at_reset_communication() {
    let mut n = io_device(3, true);
    assert_eq!(n.sent, vec![(Duration::ZERO, f(0x703, &[0x00]))]);
    n.nmt(0x01, 3);
    // Switch state selective: vendor, product, revision, serial in turn; the fourth is answered
    // 0x44. A wrong part starts the sequence over.
    assert!(lss(&mut n, with_u32(0x40, VENDOR)).is_empty());
    assert!(lss(&mut n, with_u32(0x41, PRODUCT)).is_empty());
    assert!(lss(&mut n, with_u32(0x42, REVISION)).is_empty());
    assert!(lss(&mut n, with_u32(0x43, SERIAL + 1)).is_empty());
    assert_eq!(n.node.lss().unwrap().state(), LssState::Waiting);
    assert!(lss(&mut n, with_u32(0x41, PRODUCT)).is_empty());
    assert!(lss(&mut n, with_u32(0x40, VENDOR)).is_empty());
    assert!(lss(&mut n, with_u32(0x41, PRODUCT)).is_empty());
    assert!(lss(&mut n, with_u32(0x42, REVISION)).is_empty());
    assert_eq!(
        lss(&mut n, with_u32(0x43, SERIAL)),
        answer([0x44, 0, 0, 0, 0, 0, 0, 0])
    );
    assert_eq!(
        lss(&mut n, [0x5E, 0, 0, 0, 0, 0, 0, 0]),
        answer([0x5E, 3, 0, 0, 0, 0, 0, 0])
    );
    assert_eq!(
        lss(&mut n, [0x11, 9, 0, 0, 0, 0, 0, 0]),
        answer([0x11, 0, 0, 0, 0, 0, 0, 0])
    );
    // Back to waiting: a configured node keeps its node-ID and its NMT state.
    assert!(lss(&mut n, [0x04, 0, 0, 0, 0, 0, 0, 0]).is_empty());
    assert_eq!(n.node.node_id(), 3);
    assert_eq!(n.node.state(), NmtState::Operational);
    assert_eq!(n.sdo_read(0x1014, 0), Ok(vec![0x83, 0, 0, 0]));
    // NMT reset communication for node 3: it boots as node 9.
    assert_eq!(n.nmt(0x82, 3), vec![f(0x709, &[0x00])]);
    assert_eq!(n.node.node_id(), 9);
    assert_eq!(n.node.state(), NmtState::PreOperational);
    assert_eq!(n.sdo_read(0x1014, 0), Ok(vec![0x89, 0, 0, 0]));
    // Configure 0xFF: at the next reset the node has none and waits for LSS, silent.
    lss(&mut n, [0x04, 1, 0, 0, 0, 0, 0, 0]);
    assert_eq!(
        lss(&mut n, [0x11, 0xFF, 0, 0, 0, 0, 0, 0]),
        answer([0x11, 0, 0, 0, 0, 0, 0, 0])
    );
    lss(&mut n, [0x04, 0, 0, 0, 0, 0, 0, 0]);
    assert!(n.nmt(0x81, 0).is_empty());
    assert_eq!(n.node.node_id(), 0xFF);
    assert_eq!(n.node.state(), NmtState::Initialising);
    assert!(n.advance_ms(1000).is_empty());
    assert_eq!(
        lss(&mut n, [0x4C, 0, 0, 0, 0, 0, 0, 0]),
        answer([0x50, 0, 0, 0, 0, 0, 0, 0])
    );
}

#[test]
fn identify_remote_slave_by_ranges() {
    let mut n = io_device(3, true);
    // Vendor, product, revision low/high, serial low/high: answered 0x4F after the sixth when the
    // slave lies inside (CiA 305 §8.4.2), in either LSS state.
    let ask = |n: &mut SimNode<Plain>, rev: (u32, u32), serial: (u32, u32)| {
        for (cs, v) in [
            (0x46, VENDOR),
            (0x47, PRODUCT),
            (0x48, rev.0),
            (0x49, rev.1),
            (0x4A, serial.0),
        ] {
            assert!(lss(n, with_u32(cs, v)).is_empty());
        }
        lss(n, with_u32(0x4B, serial.1))
    };
    let hit = answer([0x4F, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(ask(&mut n, (REVISION, REVISION), (SERIAL, SERIAL)), hit);
    assert_eq!(ask(&mut n, (0, u32::MAX), (0, 10)), hit);
    assert!(ask(&mut n, (REVISION + 1, u32::MAX), (0, 10)).is_empty());
    assert!(ask(&mut n, (0, u32::MAX), (2, 10)).is_empty());
    // The last part alone is no request.
    assert!(lss(&mut n, with_u32(0x4B, 10)).is_empty());
}

/// The Fastscan master of CiA 305 §8.4.4 (as python-canopen runs it): returns the LSS address found,
/// or `None` when no slave answers the first request.
fn fastscan(slaves: &mut [LssSlave]) -> Option<[u32; 4]> {
    let mut ask = |id: u32, bit: u8, sub: u8, next: u8| {
        let v = id.to_le_bytes();
        let req = [0x51, v[0], v[1], v[2], v[3], bit, sub, next];
        // Every slave on the bus sees the request; any answer is "an answer".
        let answers: Vec<_> = slaves.iter_mut().filter_map(|s| s.handle(&req).0).collect();
        assert!(answers.iter().all(|a| *a == [0x4F, 0, 0, 0, 0, 0, 0, 0]));
        !answers.is_empty()
    };
    if !ask(0, 0x80, 0, 0) {
        return None;
    }
    let mut id = [0u32; 4];
    for sub in 0..4u8 {
        for bit in (0..32u8).rev() {
            if !ask(id[usize::from(sub)], bit, sub, sub) {
                id[usize::from(sub)] |= 1 << bit;
            }
        }
        let next = (sub + 1) & 3;
        assert!(
            ask(id[usize::from(sub)], 0, sub, next),
            "sub {sub} confirmed"
        );
    }
    Some(id)
}

#[test]
fn fastscan_finds_the_lowest_unconfigured_slave() {
    let a = [VENDOR, PRODUCT, REVISION, 0x1234_5678];
    let b = [VENDOR, PRODUCT, REVISION, 0x1234_5677];
    let configured = [VENDOR, PRODUCT, REVISION, 0x0000_0001];
    let mut slaves = [
        LssSlave::new(a, 0xFF, 4, true),
        LssSlave::new(b, 0xFF, 4, true),
        LssSlave::new(configured, 7, 4, true),
    ];
    // The lower serial number wins; it is in the configuration state, the others are waiting.
    assert_eq!(fastscan(&mut slaves), Some(b));
    assert_eq!(slaves[1].state(), LssState::Configuration);
    assert_eq!(slaves[0].state(), LssState::Waiting);
    assert_eq!(slaves[2].state(), LssState::Waiting);
    // Given a node-ID and back to waiting, b is configured; the next scan finds a.
    slaves[1].handle(&[0x11, 10, 0, 0, 0, 0, 0, 0]);
    slaves[1].handle(&[0x04, 0, 0, 0, 0, 0, 0, 0]);
    slaves[1].activate();
    assert_eq!(fastscan(&mut slaves), Some(a));
    assert_eq!(slaves[0].state(), LssState::Configuration);
    slaves[0].handle(&[0x11, 11, 0, 0, 0, 0, 0, 0]);
    slaves[0].handle(&[0x04, 0, 0, 0, 0, 0, 0, 0]);
    slaves[0].activate();
    // No unconfigured slave left: no answer at all.
    assert_eq!(fastscan(&mut slaves), None);
}

#[test]
fn fastscan_on_the_node() {
    let mut n = io_device(0xFF, true);
    let ask = |n: &mut SimNode<Plain>, id: u32, bit: u8, sub: u8, next: u8| {
        let v = id.to_le_bytes();
        let got = lss(n, [0x51, v[0], v[1], v[2], v[3], bit, sub, next]);
        match got.as_slice() {
            [] => false,
            [a] if a.cob_id() == Some(0x7E4) && a.data() == [0x4F, 0, 0, 0, 0, 0, 0, 0] => true,
            other => panic!("{other:?}"),
        }
    };
    assert!(ask(&mut n, 0, 0x80, 0, 0));
    // Wrong part (the slave is at part 0): no answer.
    assert!(!ask(&mut n, PRODUCT, 0, 1, 2));
    // The vendor-ID checked from bit 8 up: 0x0ABC & !0xFF = 0x0A00 matches, 0x0B00 does not.
    assert!(ask(&mut n, 0x0A00, 8, 0, 0));
    assert!(!ask(&mut n, 0x0B00, 8, 0, 0));
    for (sub, value) in [VENDOR, PRODUCT, REVISION, SERIAL].into_iter().enumerate() {
        let sub = sub as u8;
        assert!(!ask(&mut n, value ^ 1, 0, sub, (sub + 1) & 3));
        assert!(ask(&mut n, value, 0, sub, (sub + 1) & 3));
    }
    assert_eq!(n.node.lss().unwrap().state(), LssState::Configuration);
    assert_eq!(
        lss(&mut n, [0x11, 42, 0, 0, 0, 0, 0, 0]),
        answer([0x11, 0, 0, 0, 0, 0, 0, 0])
    );
    assert_eq!(
        lss(&mut n, [0x04, 0, 0, 0, 0, 0, 0, 0]),
        vec![f(0x700 + 42, &[0])]
    );
    // A configured slave takes no part in Fastscan.
    assert!(!ask(&mut n, 0, 0x80, 0, 0));
}

#[test]
fn time_consumer_sets_the_clock() {
    let mut n = io_device(3, true);
    // 0x1012 default 0x80000100: consumer on 0x100.
    assert_eq!(n.sdo_read(0x1012, 0), Ok(vec![0x00, 0x01, 0x00, 0x80]));
    assert_eq!(n.node.time_of_day(n.now), None);
    // 2026-12-04 12:00:00.250: day 15,678, 43,200,250 ms.
    let t = TimeOfDay {
        ms: 43_200_250,
        days: 15_678,
    };
    n.send(f(0x100, &t.encode()));
    assert_eq!(n.node.time_of_day(n.now), Some(t));
    assert!(std::iter::from_fn(|| n.node.poll_event()).any(|e| e == NodeEvent::Time(t)));
    n.advance_ms(1500);
    assert_eq!(
        n.node.time_of_day(n.now),
        Some(TimeOfDay {
            ms: 43_201_750,
            days: 15_678
        })
    );
    // Five or seven bytes: no time; in Stopped: not taken.
    n.send(f(0x100, &[0; 5]));
    n.send(f(0x100, &[0; 7]));
    n.nmt(0x02, 3);
    n.send(f(0x100, &[0; 6]));
    assert_eq!(n.node.time_of_day(n.now).unwrap().days, 15_678);
}

#[test]
fn time_producer_sends_each_second() {
    let mut n = io_device(3, true);
    // Not a producer yet: nothing on 0x100.
    n.node.set_clock(n.now, 15_678 * 86_400_000 + 1_000);
    assert!(n.advance_ms(2000).is_empty());
    // 0x1012 = 0x40000100: producer on 0x100. It sends at once, then every second.
    n.sdo_write(0x1012, 0, &[0x00, 0x01, 0x00, 0x40]).unwrap();
    let start = n.elapsed();
    n.advance_ms(3000);
    let sent = n.sent_on(0x100);
    assert_eq!(sent.len(), 4, "{sent:?}");
    for (k, (at, frame)) in sent.iter().enumerate() {
        let k = k as u64;
        assert_eq!(*at - start, Duration::from_secs(k));
        let ms = 1_000 + 2_000 + 1_000 * k;
        assert_eq!(
            TimeOfDay::decode(frame.data()),
            Some(TimeOfDay {
                ms: ms as u32,
                days: 15_678
            })
        );
        assert_eq!(frame.len(), 6);
    }
    // Stopped: no TIME.
    n.nmt(0x02, 3);
    let before = n.sent_on(0x100).len();
    n.advance_ms(3000);
    assert_eq!(n.sent_on(0x100).len(), before);
    // A 29-bit COB-ID is refused (0x06090030), the producer stays as it was.
    n.nmt(0x80, 3);
    assert_eq!(
        n.sdo_write(0x1012, 0, &[0x00, 0x01, 0x00, 0x60]),
        Err(0x0609_0030)
    );
    assert_eq!(n.sdo_read(0x1012, 0), Ok(vec![0x00, 0x01, 0x00, 0x40]));
}
