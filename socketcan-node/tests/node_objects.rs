//! The node's objects and services seen from outside, in process on a simulated clock: EMCY (CiA 301
//! §7.2.7) with its error register, history and inhibit time, the SYNC producer, the COB-IDs a node
//! listens to, LSS (CiA 305), the parameter storages, and the drives of a generic node (CiA 402).

use std::path::Path;
use std::time::{Duration, Instant};

use ds402::drive::DriveConfig;
use ds402::generic::{self, GenericApp, SIM_BASE};
use od::abort::AbortCode;
use od::device::DeviceDescription;
use od::dict::{Address, Dictionary};
use od::hook::DeviceHook;
use od::object::{AccessType, Object, ObjectKind, SubObject};
use od::types::DataType;
use socketcan_node::node::lss::{LssAction, LssSlave, LssState};
use socketcan_node::node::storage::{
    self, FileStorage, LssStored, MemoryStorage, ParameterStorage, StorageRequest,
};
use socketcan_node::node::{error_register, Device, DeviceError, EmcyCode, LssConfig};
use socketcan_node::sim::SimNode;
use socketcan_node::{CanFrame, Node, NodeConfig};

const ID: u8 = 5;

/// A device whose errors the test sets: the node sees a change at the device's next tick.
#[derive(Clone, Default)]
struct Faults {
    errors: Vec<DeviceError>,
    due: Option<Instant>,
}

impl DeviceHook for Faults {
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

impl Device for Faults {
    fn handle_timeout(&mut self, _: Instant) {
        self.due = None;
    }
    fn poll_timeout(&self) -> Option<Instant> {
        self.due
    }
    fn errors(&self, out: &mut Vec<DeviceError>) {
        out.extend_from_slice(&self.errors);
    }
    fn reset(&mut self, _: Instant) {
        *self = Faults::default();
    }
}

fn example(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(name)
}

fn load(name: &str) -> DeviceDescription {
    let (_, mut d) = od::load::load(&example(name)).unwrap();
    d.remove(0)
}

/// The dictionary of examples/io-device.eds: RPDOs 0x205 (type 255) and 0x305 (type 1), TPDOs 0x185
/// (type 255) and 0x285 (type 1, 0x6401:01–02), TIME consumer on 0x100, EMCY $NODEID+0x80.
fn io_dict() -> Dictionary {
    load("io-device.eds").dictionary
}

fn boot(config: NodeConfig, dict: Dictionary) -> SimNode<Faults> {
    let t0 = Instant::now();
    let node = Node::new(config, dict, Faults::default(), t0).unwrap();
    SimNode::boot(node, t0, Box::new(MemoryStorage::default()))
}

/// Node 5 over examples/io-device.eds, booted at time zero (Pre-operational).
fn node() -> SimNode<Faults> {
    boot(NodeConfig::new(ID), io_dict())
}

fn f(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

fn fault(code: u16, info: u8) -> DeviceError {
    DeviceError {
        code: EmcyCode(code),
        info: [info, 0, 0, 0, 0],
    }
}

/// The device reports `errors` from now on; returns what the node sent at once.
fn report(n: &mut SimNode<Faults>, errors: &[DeviceError]) -> Vec<CanFrame> {
    let now = n.now;
    let app = n.node.app_mut();
    app.errors = errors.to_vec();
    app.due = Some(now);
    n.stall(Duration::ZERO)
}

/// The EMCY frames (COB-ID 0x85) sent so far, with their times.
fn emcys(n: &SimNode<Faults>) -> Vec<(Duration, CanFrame)> {
    n.sent_on(0x80 + u16::from(ID))
}

// ----- EMCY -----

/// CiA 301 Table 21: the class of a code by its high byte, else the generic class of its first
/// digit (0x1000 is the generic error itself).
#[test]
fn emcy_classes_of_table_21() {
    for (code, class) in [
        (0x1000, "generic error"),
        (0x1234, "generic error"),
        (0x2100, "current, device input side"),
        (0x2200, "current inside the device"),
        (0x2400, "current"),
        (0x3100, "mains voltage"),
        (0x3200, "voltage inside the device"),
        (0x3300, "output voltage"),
        (0x4100, "ambient temperature"),
        (0x4300, "temperature"),
        (0x6100, "internal software"),
        (0x6200, "user software"),
        (0x6400, "device software"),
        (0x7000, "additional modules"),
        (0x8300, "monitoring"),
    ] {
        assert_eq!(EmcyCode(code).class(), class, "{code:#06x}");
    }
}

/// A software error (0x6xxx) sets the error register's bit 5 besides bit 0 (generic): 0x21.
#[test]
fn a_software_error_sets_register_bit_5() {
    assert_eq!(error_register(&[fault(0x6100, 0)]), 0x21);
    assert_eq!(error_register(&[fault(0x6300, 0)]), 0x21);
}

/// Each new error is an EMCY (CiA 301 §7.2.7): code little-endian, the error register 0x1001 with
/// every active error, the five manufacturer bytes. The history 0x1003 lists the codes newest
/// first (§7.5.2.4), sub 0 their number.
#[test]
fn emcy_frames_register_and_history() {
    let mut n = node();
    let current = fault(0x2310, 1);
    let mains = fault(0x3110, 2);
    assert_eq!(
        report(&mut n, &[current]),
        [f(0x85, &[0x10, 0x23, 0x03, 1, 0, 0, 0, 0])]
    );
    assert_eq!(
        report(&mut n, &[current, mains]),
        [f(0x85, &[0x10, 0x31, 0x07, 2, 0, 0, 0, 0])]
    );
    assert_eq!(n.node.active_errors(), [current, mains]);
    assert_eq!(n.sdo_read(0x1001, 0), Ok(vec![0x07]));
    assert_eq!(n.sdo_read(0x1003, 0), Ok(vec![2]));
    assert_eq!(n.sdo_read(0x1003, 1), Ok(vec![0x10, 0x31, 0, 0]));
    assert_eq!(n.sdo_read(0x1003, 2), Ok(vec![0x10, 0x23, 0, 0]));
    assert_eq!(n.sdo_read(0x1003, 3), Ok(vec![0, 0, 0, 0]));
}

/// Without an object 0x1014 the EMCY goes on the pre-defined connection set's COB-ID, 0x80 +
/// node-ID (CiA 301 pre-defined connection set): 0x85.
#[test]
fn emcy_cob_id_of_the_predefined_connection_set() {
    let mut dict = io_dict();
    dict.remove(0x1014);
    let mut n = boot(NodeConfig::new(ID), dict);
    assert_eq!(
        report(&mut n, &[fault(0x1000, 0)]),
        [f(0x85, &[0x00, 0x10, 0x01, 0, 0, 0, 0, 0])]
    );
}

/// The inhibit time 0x1015 counts in 100 µs (CiA 301 §7.5.2.18): at 10, two EMCYs raised together
/// leave exactly 1 ms apart, the second when the node's timer says so.
#[test]
fn emcy_inhibit_time_in_100_us() {
    let mut n = node();
    n.sdo_write(0x1015, 0, &[10, 0]).unwrap();
    let start = n.elapsed();
    let frames = report(&mut n, &[fault(0x2310, 1), fault(0x3110, 2)]);
    assert_eq!(frames, [f(0x85, &[0x10, 0x23, 0x03, 1, 0, 0, 0, 0])]);
    assert_eq!(n.node.poll_timeout(), Some(n.now + ms(1)));
    n.advance(ms(5));
    assert_eq!(
        emcys(&n),
        [
            (start, f(0x85, &[0x10, 0x23, 0x03, 1, 0, 0, 0, 0])),
            (start + ms(1), f(0x85, &[0x10, 0x31, 0x07, 2, 0, 0, 0, 0])),
        ]
    );
}

/// At most 64 EMCYs wait for the inhibit time; more are dropped. 70 errors raised at once with an
/// inhibit time of 1 s: the first leaves at once, the next 64 one a second apart, the last 5 never.
#[test]
fn at_most_64_emcys_wait() {
    let mut n = node();
    n.sdo_write(0x1015, 0, &10_000u16.to_le_bytes()).unwrap();
    let start = n.elapsed();
    let errors: Vec<DeviceError> = (0..70).map(|k| fault(0x1000, k)).collect();
    report(&mut n, &errors);
    n.advance(Duration::from_secs(100));
    let sent = emcys(&n);
    assert_eq!(sent.len(), 65);
    for (k, (at, frame)) in sent.iter().enumerate() {
        assert_eq!(*at - start, Duration::from_secs(k as u64));
        assert_eq!(frame.data(), [0x00, 0x10, 0x01, k as u8, 0, 0, 0, 0]);
    }
}

/// EMCY is not sent in Stopped (CiA 301 NMT states: NMT and error control only); one raised there
/// waits without a timer of its own (no inhibit time) and leaves on the way back to
/// Pre-operational.
#[test]
fn an_emcy_raised_in_stopped_waits_for_pre_operational() {
    let mut n = node();
    let current = fault(0x2310, 1);
    let mains = fault(0x3110, 2);
    assert_eq!(report(&mut n, &[current]).len(), 1);
    n.nmt(0x02, ID);
    assert!(report(&mut n, &[current, mains]).is_empty());
    assert_eq!(n.node.poll_timeout(), None);
    assert_eq!(
        n.nmt(0x80, ID),
        [f(0x85, &[0x10, 0x31, 0x07, 2, 0, 0, 0, 0])]
    );
}

/// NMT reset node forgets the active errors, the history and the EMCYs still waiting for the
/// inhibit time: after the boot-up nothing more is sent, 0x1001 and 0x1003:00 read 0.
#[test]
fn reset_node_forgets_errors_and_waiting_emcys() {
    let mut n = node();
    n.sdo_write(0x1015, 0, &1000u16.to_le_bytes()).unwrap();
    assert_eq!(
        report(&mut n, &[fault(0x2310, 1), fault(0x3110, 2)]).len(),
        1
    );
    assert_eq!(n.nmt(0x81, ID), [f(0x705, &[0x00])]);
    assert!(n.advance(ms(500)).is_empty());
    assert_eq!(n.node.active_errors(), []);
    assert_eq!(n.sdo_read(0x1001, 0), Ok(vec![0]));
    assert_eq!(n.sdo_read(0x1003, 0), Ok(vec![0]));
    assert_eq!(emcys(&n).len(), 1);
}

// ----- The node's API: dictionary, listened COB-IDs -----

/// What the master wrote is in the node's dictionary.
#[test]
fn the_dictionary_holds_what_was_written() {
    let mut n = node();
    n.sdo_write(0x1017, 0, &[100, 0]).unwrap();
    assert_eq!(n.node.dict().read(0x1017, 0).unwrap(), [100, 0]);
}

/// The COB-IDs node 5 acts on: NMT 0x000, SYNC 0x080, TIME 0x100, the RPDOs 0x205 and 0x305, its SDO
/// requests 0x605, and the heartbeat of the producer 0x1016:01 monitors (0x700 + its node-ID);
/// remote frames may ask for the TPDOs that exist and allow them (COB-ID bit 30 clear, CiA 301
/// §7.5.2.35). Each change of the lists changes the generation.
#[test]
fn listened_cob_ids() {
    let mut n = node();
    let lists = |n: &SimNode<Faults>| {
        let (l, r) = n.node.listens();
        (l.to_vec(), r.to_vec())
    };
    let plain = vec![0x000, 0x080, 0x100, 0x205, 0x305, 0x605];
    assert_eq!(lists(&n), (plain.clone(), vec![0x185, 0x285]));
    let g0 = n.node.listen_generation();
    // Monitor node 0x20 every 1000 ms.
    n.sdo_write(0x1016, 1, &0x0020_03E8u32.to_le_bytes())
        .unwrap();
    let g1 = n.node.listen_generation();
    assert_ne!(g1, g0);
    let mut with_consumer = plain.clone();
    with_consumer.push(0x720);
    assert_eq!(lists(&n).0, with_consumer);
    // TPDO 1 refuses remote frames, TPDO 2 is made invalid.
    n.sdo_write(0x1800, 1, &0x4000_0185u32.to_le_bytes())
        .unwrap();
    assert_eq!(lists(&n).1, [0x285]);
    n.sdo_write(0x1801, 1, &0x8000_0285u32.to_le_bytes())
        .unwrap();
    assert_eq!(lists(&n).1, [] as [u16; 0]);
    assert_ne!(n.node.listen_generation(), g1);
}

/// A monitored heartbeat producer does not hide the other frames: a SYNC in Operational still makes
/// the synchronous TPDO 2 (0x285, analogue inputs 0).
#[test]
fn sync_is_served_beside_a_heartbeat_consumer() {
    let mut n = node();
    n.sdo_write(0x1016, 1, &0x0020_03E8u32.to_le_bytes())
        .unwrap();
    n.nmt(0x01, ID);
    assert_eq!(n.send(f(0x080, &[])), [f(0x285, &[0, 0, 0, 0])]);
}

/// Without a heartbeat consumer, 0x700 is a CAN-ID like others (CiA 301 §7.3.5 restricts 0x701 to
/// 0x77F only): as the SYNC COB-ID it brings the synchronous TPDO.
#[test]
fn cob_id_0x700_without_a_consumer() {
    let mut n = node();
    n.sdo_write(0x1005, 0, &0x700u32.to_le_bytes()).unwrap();
    n.nmt(0x01, ID);
    assert_eq!(n.send(f(0x700, &[])), [f(0x285, &[0, 0, 0, 0])]);
}

// ----- SYNC producer -----

/// The node produces SYNC only with 0x1005 bit 30 set and a period 0x1006 above 0 (CiA 301
/// §7.5.2.6: 0 disables the SYNC transmission).
#[test]
fn sync_producer_needs_bit_30_and_a_period() {
    let mut n = node();
    n.sdo_write(0x1006, 0, &10_000u32.to_le_bytes()).unwrap();
    assert!(n.advance(ms(100)).is_empty());
    let mut m = node();
    m.sdo_write(0x1005, 0, &0x4000_0080u32.to_le_bytes())
        .unwrap();
    assert!(m.sent_on(0x080).is_empty());
    assert_eq!(m.node.poll_timeout(), None);
    assert!(m.advance(ms(100)).is_empty());
    // Both: a SYNC (no data) every 10 ms.
    n.sdo_write(0x1005, 0, &0x4000_0080u32.to_le_bytes())
        .unwrap();
    assert_eq!(n.advance(ms(30)), vec![f(0x080, &[]); 3]);
}

/// A SYNC polled late keeps the period's grid while it is less than a period late; later than that
/// the period starts again from the late SYNC (no burst of SYNCs to catch up).
#[test]
fn a_late_sync_keeps_the_grid() {
    let mut n = node();
    n.sdo_write(0x1006, 0, &10_000u32.to_le_bytes()).unwrap();
    n.sdo_write(0x1005, 0, &0x4000_0080u32.to_le_bytes())
        .unwrap();
    let start = n.now;
    // Due at 10, polled at 13: the next is due at 20.
    assert_eq!(n.stall(ms(13)), [f(0x080, &[])]);
    assert_eq!(n.node.poll_timeout(), Some(start + ms(20)));
    n.advance(ms(7));
    // Due at 30, polled at 45: the next is due at 55.
    assert_eq!(n.stall(ms(25)), [f(0x080, &[])]);
    assert_eq!(n.node.poll_timeout(), Some(start + ms(55)));
    n.advance(ms(10));
    let times: Vec<Duration> = n
        .sent_on(0x080)
        .iter()
        .map(|(t, _)| n.t0 + *t - start)
        .collect();
    assert_eq!(times, [ms(13), ms(20), ms(45), ms(55)]);
}

// ----- LSS (CiA 305) -----

const ADDRESS: [u32; 4] = [0x0ABC, 0x0401, 0x0001_0001, 1];

fn request(cs: u8, byte1: u8) -> [u8; 8] {
    [cs, byte1, 0, 0, 0, 0, 0, 0]
}

fn with_u32(cs: u8, value: u32) -> [u8; 8] {
    let v = value.to_le_bytes();
    [cs, v[0], v[1], v[2], v[3], 0, 0, 0]
}

/// The LSS address of a node is its identity 0x1018:01–04 (CiA 305 §6.1).
#[test]
fn lss_address_is_the_identity_object() {
    let config = NodeConfig {
        lss: Some(LssConfig {
            bit_timing: 4,
            can_store: false,
        }),
        ..NodeConfig::new(ID)
    };
    let n = boot(config, io_dict());
    assert_eq!(n.node.lss().unwrap().address(), ADDRESS);
}

/// Configure node-ID (CiA 305 §8.3.1) makes the node-ID pending; it becomes active when the node
/// takes it.
#[test]
fn lss_configured_node_id_is_pending_until_activated() {
    let mut s = LssSlave::new(ADDRESS, 3, 4, true);
    s.handle(&request(0x04, 1));
    assert_eq!(
        s.handle(&request(0x11, 9)),
        (Some(request(0x11, 0)), LssAction::None)
    );
    assert_eq!((s.pending_node_id(), s.active_node_id()), (9, 3));
    s.activate();
    assert_eq!((s.pending_node_id(), s.active_node_id()), (9, 9));
}

/// In the waiting state configure bit timing, activate bit timing and store configuration are not
/// served (CiA 305 §8.3): no answer, nothing to do, the bit timing unchanged.
#[test]
fn lss_configuration_services_wait_for_the_configuration_state() {
    let mut s = LssSlave::new(ADDRESS, 3, 4, true);
    for req in [
        [0x13, 0, 2, 0, 0, 0, 0, 0],
        [0x15, 100, 0, 0, 0, 0, 0, 0],
        request(0x17, 0),
    ] {
        assert_eq!(s.handle(&req), (None, LssAction::None), "{req:02X?}");
    }
    assert_eq!(s.bit_timing(), 4);
    assert_eq!(s.state(), LssState::Waiting);
}

/// Switch state selective is four requests in a row (CiA 305 §8.2.2): another request between them
/// breaks the sequence, and its rest is not answered.
#[test]
fn lss_selective_switch_broken_by_another_request() {
    let mut s = LssSlave::new(ADDRESS, 3, 4, true);
    assert_eq!(s.handle(&with_u32(0x40, ADDRESS[0])).0, None);
    assert_eq!(s.handle(&with_u32(0x41, ADDRESS[1])).0, None);
    assert_eq!(s.handle(&request(0x5E, 0)).0, None);
    assert_eq!(s.handle(&with_u32(0x42, ADDRESS[2])).0, None);
    assert_eq!(s.handle(&with_u32(0x43, ADDRESS[3])).0, None);
    assert_eq!(s.state(), LssState::Waiting);
}

/// Fastscan checks bits 0–31 of a part (CiA 305 §8.4.4, BitChecked 0..31, or 0x80 to start): a
/// BitChecked of 32 is no request.
#[test]
fn lss_fastscan_bit_checked_above_31_is_ignored() {
    let mut s = LssSlave::new(ADDRESS, 0xFF, 4, true);
    let scan = |id: u32, bit: u8, sub: u8, next: u8| {
        let v = id.to_le_bytes();
        [0x51, v[0], v[1], v[2], v[3], bit, sub, next]
    };
    let hit = Some([0x4F, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(s.handle(&scan(0, 0x80, 0, 0)).0, hit);
    assert_eq!(s.handle(&scan(ADDRESS[0], 32, 0, 0)).0, None);
    assert_eq!(s.handle(&scan(ADDRESS[0], 0, 0, 1)).0, hit);
}

// ----- Parameter storages -----

/// Memory storage keeps the last set saved until it is cleared.
#[test]
fn memory_storage_keeps_the_last_set() {
    let mut s = MemoryStorage::default();
    assert_eq!(s.load().unwrap(), None);
    s.save(b"first").unwrap();
    s.save(b"second set").unwrap();
    assert_eq!(s.load().unwrap(), Some(b"second set".to_vec()));
    s.clear().unwrap();
    assert_eq!(s.load().unwrap(), None);
}

/// A storage that keeps only parameter sets has no LSS configuration and refuses to keep one.
#[test]
fn a_storage_without_lss_refuses_to_keep_one() {
    struct SetsOnly;
    impl ParameterStorage for SetsOnly {
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
    let request = StorageRequest::SaveLss {
        node_id: 5,
        bit_timing: 2,
    };
    let e = request.apply(&mut SetsOnly).unwrap_err();
    assert_eq!(e.kind(), std::io::ErrorKind::Unsupported);
    assert_eq!(SetsOnly.load_lss().unwrap(), None);
}

/// The LSS configuration goes to `PATH.lss` as a parameter set (0000:01 the node-ID, 0000:02 the
/// bit-timing index) and is read back from there; a set without both entries is refused.
#[test]
fn file_storage_keeps_the_lss_configuration_beside_the_parameters() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = FileStorage::new(dir.path().join("node5.params"));
    assert_eq!(s.lss_path(), dir.path().join("node5.params.lss"));
    assert_eq!(s.load_lss().unwrap(), None);
    let lss = LssStored {
        node_id: 5,
        bit_timing: 2,
    };
    s.save_lss(lss).unwrap();
    assert_eq!(
        std::fs::read(dir.path().join("node5.params.lss")).unwrap(),
        storage::encode(&[(0, 1, vec![5]), (0, 2, vec![2])])
    );
    let mut again = FileStorage::new(dir.path().join("node5.params"));
    assert_eq!(again.load_lss().unwrap(), Some(lss));
    // The parameter set itself is another file.
    assert_eq!(again.load().unwrap(), None);
    std::fs::write(s.lss_path(), storage::encode(&[(0, 1, vec![5])])).unwrap();
    let e = s.load_lss().unwrap_err();
    assert_eq!(e.kind(), std::io::ErrorKind::InvalidData);
    std::fs::write(
        s.lss_path(),
        storage::encode(&[(0, 1, vec![5, 0]), (0, 2, vec![2])]),
    )
    .unwrap();
    assert_eq!(
        s.load_lss().unwrap_err().kind(),
        std::io::ErrorKind::InvalidData
    );
}

/// Clearing a set that is not there is done; clearing what cannot be removed (a folder in its place)
/// is an error, and the folder stays.
#[test]
fn file_storage_clear_reports_what_it_cannot_remove() {
    let dir = tempfile::tempdir().unwrap();
    FileStorage::new(dir.path().join("absent")).clear().unwrap();
    let folder = dir.path().join("folder");
    std::fs::create_dir(&folder).unwrap();
    assert!(FileStorage::new(&folder).clear().is_err());
    assert!(folder.is_dir());
}

// ----- A generic node's drives (CiA 402) -----

/// A node of `desc` (simulation records added) with node-ID 5, booted at time zero.
fn drive_node(mut desc: DeviceDescription) -> SimNode<GenericApp> {
    generic::add_sim_records(&mut desc.dictionary, &DriveConfig::default().sim);
    let t0 = Instant::now();
    let app = GenericApp::new(&desc.dictionary, &DriveConfig::default(), t0);
    let node = Node::new(NodeConfig::new(ID), desc.dictionary, app, t0).unwrap();
    SimNode::boot(node, t0, Box::new(MemoryStorage::default()))
}

/// 0x60FD digital inputs as a u32.
fn inputs(n: &mut SimNode<GenericApp>) -> u32 {
    let v = n.sdo_read(0x60FD, 0).unwrap();
    u32::from_le_bytes([v[0], v[1], v[2], v[3]])
}

/// The switch positions of the simulation record (subs 3–5, raw counts; the rotor stands at 0) set
/// 0x60FD bits 0–2: negative limit active at and below its position, positive limit and home switch
/// at and above theirs.
#[test]
fn simulated_switch_positions() {
    let mut n = drive_node(load("drive.eds"));
    assert_eq!(inputs(&mut n), 0);
    n.sdo_write(SIM_BASE, 3, &100i32.to_le_bytes()).unwrap();
    assert_eq!(inputs(&mut n), 0b001);
    n.sdo_write(SIM_BASE, 4, &(-100i32).to_le_bytes()).unwrap();
    assert_eq!(inputs(&mut n), 0b011);
    n.sdo_write(SIM_BASE, 5, &(-50i32).to_le_bytes()).unwrap();
    assert_eq!(inputs(&mut n), 0b111);
}

/// Sub 1 of the simulation record is the mask of forced 0x60FD bits, sub 2 their levels: levels
/// alone force nothing, and a mask forces only its own bits.
#[test]
fn forced_inputs_mask_and_levels() {
    let mut n = drive_node(load("drive.eds"));
    n.sdo_write(SIM_BASE, 3, &100i32.to_le_bytes()).unwrap();
    assert_eq!(inputs(&mut n), 0x0000_0001);
    n.sdo_write(SIM_BASE, 2, &0x0001_0001u32.to_le_bytes())
        .unwrap();
    assert_eq!(inputs(&mut n), 0x0000_0001);
    n.sdo_write(SIM_BASE, 1, &0x0001_0000u32.to_le_bytes())
        .unwrap();
    assert_eq!(inputs(&mut n), 0x0001_0001);
    // Forcing the active limit switch low.
    n.sdo_write(SIM_BASE, 2, &0x0001_0000u32.to_le_bytes())
        .unwrap();
    n.sdo_write(SIM_BASE, 1, &0x0001_0001u32.to_le_bytes())
        .unwrap();
    assert_eq!(inputs(&mut n), 0x0001_0000);
}

/// NMT reset node takes the drive back to power-on (CiA 402: Not ready to switch on, then Switch on
/// disabled, statusword xxxx xxxx x1xx 0000) and forgets the forced inputs.
#[test]
fn reset_node_resets_the_drive() {
    let mut n = drive_node(load("drive.eds"));
    for cw in [0x06u8, 0x07, 0x0F] {
        n.sdo_write(0x6040, 0, &[cw, 0]).unwrap();
        n.advance_ms(1);
    }
    assert_eq!(n.sdo_read(0x6041, 0).unwrap()[0] & 0x6F, 0x27);
    n.sdo_write(SIM_BASE, 2, &[0x04, 0, 0, 0]).unwrap();
    n.sdo_write(SIM_BASE, 1, &[0x04, 0, 0, 0]).unwrap();
    assert_eq!(inputs(&mut n), 0x04);
    n.nmt(0x81, ID);
    n.advance_ms(10);
    assert_eq!(n.sdo_read(0x6041, 0).unwrap()[0] & 0x4F, 0x40);
    assert_eq!(inputs(&mut n), 0);
}

/// The switch positions the drives are made with (`--negative-limit` and the others) are the
/// simulation record's subs 3–5 from power-on, and NMT reset node returns both the record and the
/// drive to them: with the negative limit at 100 (active at the rotor's 0) and the home switch at
/// 500, the record reads 100, 0, 500 and 0x60FD bit 0; a master moves the negative limit to −100
/// (inactive) and the home switch to −50 (active: bit 2); after reset node the record reads 100, 0,
/// 500 again and 0x60FD is bit 0 alone again.
#[test]
fn switch_positions_of_the_configuration_are_the_records_and_survive_reset_node() {
    let mut config = DriveConfig::default();
    config.sim.negative_limit = Some(100);
    config.sim.home_switch = Some(500);
    let mut desc = load("drive.eds");
    generic::add_sim_records(&mut desc.dictionary, &config.sim);
    let t0 = Instant::now();
    let app = GenericApp::new(&desc.dictionary, &config, t0);
    let node = Node::new(NodeConfig::new(ID), desc.dictionary, app, t0).unwrap();
    let mut n = SimNode::boot(node, t0, Box::new(MemoryStorage::default()));
    let record = |n: &mut SimNode<GenericApp>| -> Vec<i32> {
        (3..=5)
            .map(|sub| {
                let v = n.sdo_read(SIM_BASE, sub).unwrap();
                i32::from_le_bytes([v[0], v[1], v[2], v[3]])
            })
            .collect()
    };
    assert_eq!(record(&mut n), [100, 0, 500]);
    assert_eq!(inputs(&mut n), 0b001);
    n.sdo_write(SIM_BASE, 3, &(-100i32).to_le_bytes()).unwrap();
    n.sdo_write(SIM_BASE, 5, &(-50i32).to_le_bytes()).unwrap();
    assert_eq!(record(&mut n), [-100, 0, -50]);
    assert_eq!(inputs(&mut n), 0b100);
    n.nmt(0x81, ID);
    n.advance_ms(10);
    assert_eq!(record(&mut n), [100, 0, 500]);
    assert_eq!(inputs(&mut n), 0b001);
}

/// A fault raised from outside on a drive in Operation enabled is an EMCY with its code, the error
/// register (0x4310 temperature: bits 0 and 3, 0x09) and the axis (1) in the first manufacturer
/// byte.
#[test]
fn a_drive_fault_from_outside_is_an_emcy() {
    let mut n = drive_node(load("drive.eds"));
    for cw in [0x06u8, 0x07, 0x0F] {
        n.sdo_write(0x6040, 0, &[cw, 0]).unwrap();
        n.advance_ms(1);
    }
    let now = n.now;
    n.node.app_mut().drives_mut()[0].raise_fault(now, 0x4310);
    let sent = n.advance_ms(1);
    assert_eq!(sent, [f(0x85, &[0x10, 0x43, 0x09, 1, 0, 0, 0, 0])]);
}

/// A fault raised from outside on an idle drive (Switch on disabled, power stage off) is an EMCY at
/// the next millisecond as well: 0x4310 with the error register 0x09 and the axis 1.
#[test]
fn a_drive_fault_on_an_idle_drive_is_an_emcy() {
    let mut n = drive_node(load("drive.eds"));
    n.advance_ms(10);
    assert_eq!(n.sdo_read(0x6041, 0).unwrap()[0] & 0x4F, 0x40);
    let now = n.now;
    n.node.app_mut().drives_mut()[0].raise_fault(now, 0x4310);
    let sent = n.advance_ms(1);
    assert_eq!(sent, [f(0x85, &[0x10, 0x43, 0x09, 1, 0, 0, 0, 0])]);
}

/// The application owns the drive's objects and its simulation record, and checks a write as the
/// drive does before any is made (CiA 402: 0x6060 takes only supported modes, 0x06090030; process
/// values are read-only, 0x06010002).
#[test]
fn the_application_owns_and_checks_the_drive_objects() {
    let n = drive_node(load("drive.eds"));
    let app = n.node.app();
    assert!(app.owns(0x6041));
    assert!(app.owns(SIM_BASE));
    assert!(!app.owns(0x1017));
    assert!(!app.owns(SIM_BASE + 1));
    assert_eq!(
        app.check(Address::new(0x6060, 0), &[99]),
        Err(AbortCode::InvalidValue)
    );
    assert_eq!(
        app.check(Address::new(0x6041, 0), &[0, 0]),
        Err(AbortCode::ReadOnly)
    );
    assert_eq!(app.check(Address::new(0x6060, 0), &[1]), Ok(()));
    assert_eq!(app.check(Address::new(SIM_BASE, 1), &[1, 0, 0, 0]), Ok(()));
}

/// A description that already has an object at 0x5FF0 keeps it: even with the record's types, under
/// other names it is not a simulation record, and what is written to it forces no input.
#[test]
fn an_object_of_the_description_at_0x5ff0_is_not_a_simulation_record() {
    let mut desc = load("drive.eds");
    let mut object = Object::structured(SIM_BASE, "Vendor record", ObjectKind::Record).with_sub(
        0,
        SubObject::new(
            "Highest sub-index supported",
            DataType::Unsigned8,
            AccessType::Ro,
        )
        .with_default(od::Value::Uint(5)),
    );
    for (sub, t) in [
        (1, DataType::Unsigned32),
        (2, DataType::Unsigned32),
        (3, DataType::Integer32),
        (4, DataType::Integer32),
        (5, DataType::Integer32),
    ] {
        object = object.with_sub(
            sub,
            SubObject::new(format!("Vendor value {sub}"), t, AccessType::Rw),
        );
    }
    desc.dictionary.insert(object);
    let mut n = drive_node(desc);
    assert!(!n.node.app().owns(SIM_BASE));
    n.sdo_write(SIM_BASE, 1, &[1, 0, 0, 0]).unwrap();
    n.sdo_write(SIM_BASE, 2, &[1, 0, 0, 0]).unwrap();
    assert_eq!(n.sdo_read(SIM_BASE, 2), Ok(vec![1, 0, 0, 0]));
    assert_eq!(inputs(&mut n), 0);
}
