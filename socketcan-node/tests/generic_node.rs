//! A node from any description, in process on a simulated clock: a DCF's values as power-on values,
//! the drive behind a CiA 402 description over PDOs and SYNC, its simulation record, its faults as
//! EMCY, several axes, and what `canopen-node` makes of its arguments.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use clap::Parser;
use ds402::drive::DriveConfig;
use ds402::generic::{self, GenericApp, SIM_BASE};
use od::device::DeviceDescription;
use socketcan_node::canopen_cli::{self, Args};
use socketcan_node::node::storage::MemoryStorage;
use socketcan_node::sim::SimNode;
use socketcan_node::{CanFrame, NmtState, Node, NodeConfig};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(name)
}

fn load(path: &Path) -> DeviceDescription {
    let (_, mut d) = od::load::load(path).unwrap();
    d.remove(0)
}

fn f(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

/// A node of `desc` (simulation records added) with node-ID `id`, booted at time zero.
fn node(mut desc: DeviceDescription, id: u8) -> SimNode<GenericApp> {
    generic::add_sim_records(&mut desc.dictionary, &DriveConfig::default().sim);
    let t0 = Instant::now();
    let app = GenericApp::new(&desc.dictionary, &DriveConfig::default(), t0);
    let node = Node::new(NodeConfig::new(id), desc.dictionary, app, t0).unwrap();
    SimNode::boot(node, t0, Box::new(MemoryStorage::default()))
}

fn i32le(v: &[u8]) -> i32 {
    i32::from_le_bytes([v[0], v[1], v[2], v[3]])
}

/// A DCF's `ParameterValue`s are the node's power-on values, and what NMT reset node returns to:
/// heartbeat 250 ms (the EDS says 0), TPDO 1 on every SYNC (the EDS says 255), the analogue
/// outputs' RPDO with node-ID-relative COB-ID $NODEID+0x300 at node 12: 0x30C.
#[test]
fn dcf_values_are_power_on_values() {
    let mut desc = load(&example("io-device.eds"));
    desc.set_node_id(Some(12));
    for (index, sub, value) in [(0x1017u16, 0u8, 250u64), (0x1800, 2, 1)] {
        let e = desc
            .dictionary
            .object_mut(index)
            .unwrap()
            .subs
            .get_mut(&sub)
            .unwrap();
        e.value = od::Value::Uint(value).encode(e.data_type).unwrap();
        e.value_set = true;
    }
    desc.configure_writable();
    let dcf = od::eds::write_dcf(&desc);
    assert!(
        dcf.contains("[1017]") && dcf.contains("ParameterValue=0x00FA"),
        "{dcf}"
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("io.dcf");
    std::fs::write(&path, dcf).unwrap();
    // canopen-node takes the DCF's node-ID and makes its values the defaults.
    let args = Args::try_parse_from(["canopen-node", "--od", path.to_str().unwrap()]).unwrap();
    let mut loaded = canopen_cli::load(&args).unwrap();
    assert_eq!(loaded[0].node_id, 12);
    let mut n = node(loaded.remove(0).description, 12);
    assert_eq!(n.sdo_read(0x1017, 0), Ok(vec![250, 0]));
    assert_eq!(n.sdo_read(0x1800, 2), Ok(vec![1]));
    assert_eq!(n.sdo_read(0x1401, 1), Ok(vec![0x0C, 0x03, 0, 0]));
    // The heartbeat runs from boot-up: at 250 and 500 ms.
    n.advance_ms(500);
    let beats: Vec<Duration> = n.sent_on(0x70C).iter().map(|(t, _)| *t).collect();
    assert_eq!(
        beats,
        [
            Duration::ZERO,
            Duration::from_millis(250),
            Duration::from_millis(500)
        ]
    );
    // Changed, then reset node: back to the DCF's values, not the EDS's.
    n.sdo_write(0x1017, 0, &[0, 0]).unwrap();
    n.sdo_write(0x1800, 2, &[255]).unwrap();
    n.nmt(0x81, 12);
    assert_eq!(n.sdo_read(0x1017, 0), Ok(vec![250, 0]));
    assert_eq!(n.sdo_read(0x1800, 2), Ok(vec![1]));
}

/// The example drive in cyclic synchronous position at a 1 ms SYNC: RPDO 4 (0x505: 0x607A, 0x60FF,
/// on SYNC) carries a target that grows 10 counts a cycle; TPDO 4 (0x485: 0x6064, 0x606C, on SYNC)
/// answers each SYNC. The demand (0x6062) reaches each target one SYNC period after the SYNC that
/// brought it (interpolation over the period): at SYNC k it is exactly 10·(k − 1). The servo follows
/// a few counts behind the moving demand (0x60F4 = demand − actual, 0 to 5 counts: half a cycle at
/// 10,000 counts/s), the position in the TPDO is the demand minus that, and the speed settles at 10
/// counts per ms, 10,000 counts/s.
#[test]
fn csp_over_pdos_at_a_1_ms_sync() {
    let mut n = node(load(&example("drive.eds")), 5);
    n.sdo_write(0x6060, 0, &[8]).unwrap();
    n.nmt(0x01, 5);
    for cw in [0x06u8, 0x07, 0x0F] {
        n.send(f(0x205, &[cw, 0, 8]));
        n.advance_ms(1);
    }
    assert_eq!(n.sdo_read(0x6041, 0).unwrap()[0] & 0x6F, 0x27);
    let mut speeds = Vec::new();
    for k in 1..=40i32 {
        let target = (10 * k).to_le_bytes();
        n.send(f(
            0x505,
            &[target[0], target[1], target[2], target[3], 0, 0, 0, 0],
        ));
        let out = n.send(f(0x080, &[]));
        let tpdo = out
            .iter()
            .find(|x| x.cob_id() == Some(0x485))
            .unwrap_or_else(|| panic!("no TPDO 4 at SYNC {k}: {out:?}"));
        let position = i32le(&tpdo.data()[0..4]);
        speeds.push(i32le(&tpdo.data()[4..8]));
        let demand = i32le(&n.sdo_read(0x6062, 0).unwrap());
        let lag = i32le(&n.sdo_read(0x60F4, 0).unwrap());
        assert_eq!(demand, 10 * (k - 1), "SYNC {k}");
        assert!((0..=5).contains(&lag), "SYNC {k}: following error {lag}");
        assert_eq!(position, demand - lag, "SYNC {k}");
        n.advance_ms(1);
    }
    assert!(
        speeds[30..].iter().all(|v| (9_900..=10_100).contains(v)),
        "{speeds:?}"
    );
    // Status bit 12 (drive follows the command value) in csp.
    assert_ne!(n.sdo_read(0x6041, 0).unwrap()[1] & 0x10, 0);
}

/// tests/drives/pdo-rtr.eds in csp with SYNC running: the status word in TPDO 1, sent on a change
/// only (type 255, no event timer), the control word and the mode in RPDO 1 (type 255). A quick
/// stop (0x605A = 2) at standstill ends in Switch on disabled at the drive's next control tick, and
/// Shutdown from there is Ready to switch on at once. When a SYNC reaches the node at that tick,
/// before the node's own timer (the drive runs the tick inside the SYNC and is idle after it), TPDO
/// 1 carries the new state at that SYNC all the same: a master reading the state from TPDO 1 sees it.
#[test]
fn a_state_reached_at_a_sync_is_sent_by_the_status_tpdo() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/drives/pdo-rtr.eds");
    let od = format!("{}@5", path.display());
    let args = Args::try_parse_from(["canopen-node", "--od", &od]).unwrap();
    let mut n = node(canopen_cli::load(&args).unwrap().remove(0).description, 5);
    let status = |out: &[CanFrame]| {
        out.iter()
            .rev()
            .find(|x| x.cob_id() == Some(0x185))
            .map(|x| u16::from_le_bytes([x.data()[0], x.data()[1]]))
    };
    n.nmt(0x01, 5);
    for cw in [0x06u8, 0x07, 0x0F] {
        n.send(f(0x205, &[cw, 0, 8]));
        n.send(f(0x080, &[]));
        n.advance_ms(10);
    }
    let sent: Vec<CanFrame> = n.sent.iter().map(|(_, x)| *x).collect();
    assert_eq!(status(&sent).map(|s| s & 0x6F), Some(0x27));
    // Quick stop (0x0002), then Shutdown (0x0006): each time the SYNC comes at the drive's next tick.
    for (cw, mask, state) in [(0x02u8, 0x4F, 0x40), (0x06, 0x6F, 0x21)] {
        n.send(f(0x205, &[cw, 0, 8]));
        n.now = n.node.poll_timeout().expect("the drive's next tick");
        let out = n.send(f(0x080, &[]));
        assert_eq!(
            status(&out).map(|s| s & mask),
            Some(state),
            "control word {cw:#04x}: {out:?}"
        );
        n.advance_ms(10);
    }
}

/// The simulation record at 0x5FF0: forcing 0x60FD bits (sub 1 the mask, sub 2 the levels) shows in
/// 0x60FD at once; a limit switch forced active while the drive moves towards it is a fault: 0x603F
/// 0x8612 with an EMCY on 0x85 carrying it, the error register and the axis (1) in byte 3.
#[test]
fn simulation_inputs_and_a_fault_as_emcy() {
    let mut n = node(load(&example("drive.eds")), 5);
    assert_eq!(n.sdo_read(SIM_BASE, 0), Ok(vec![5]));
    n.sdo_write(SIM_BASE, 1, &[0x07, 0, 0, 0]).unwrap();
    n.sdo_write(SIM_BASE, 2, &[0x04, 0, 0, 0]).unwrap();
    assert_eq!(n.sdo_read(0x60FD, 0), Ok(vec![0x04, 0, 0, 0]));
    n.sdo_write(SIM_BASE, 2, &[0x00, 0, 0, 0]).unwrap();
    assert_eq!(n.sdo_read(0x60FD, 0), Ok(vec![0, 0, 0, 0]));
    // Profile velocity, positive, then the positive limit switch (bit 1) goes active.
    n.sdo_write(0x6060, 0, &[3]).unwrap();
    n.nmt(0x01, 5);
    for cw in [0x06u8, 0x07, 0x0F] {
        n.sdo_write(0x6040, 0, &[cw, 0]).unwrap();
        n.advance_ms(1);
    }
    n.sdo_write(0x60FF, 0, &1000i32.to_le_bytes()).unwrap();
    n.advance_ms(50);
    let before = n.sent.len();
    n.sdo_write(SIM_BASE, 2, &[0x02, 0, 0, 0]).unwrap();
    n.advance_ms(20);
    assert_eq!(n.sdo_read(0x603F, 0), Ok(vec![0x12, 0x86]));
    assert_eq!(n.sdo_read(0x6041, 0).unwrap()[0] & 0x4F, 0x08);
    let emcy: Vec<CanFrame> = n.sent[before..]
        .iter()
        .filter(|(_, x)| x.cob_id() == Some(0x85))
        .map(|(_, x)| *x)
        .collect();
    // Error register 0x21: generic (bit 0) and device profile (bit 5, a 0x86xx code).
    assert_eq!(emcy, vec![f(0x85, &[0x12, 0x86, 0x21, 0x01, 0, 0, 0, 0])]);
    // Fault reset with the switch released: EMCY 0x0000 with the error register back to 0, the
    // axis and the code cleared.
    n.sdo_write(SIM_BASE, 2, &[0, 0, 0, 0]).unwrap();
    n.sdo_write(0x6040, 0, &[0x80, 0]).unwrap();
    n.advance_ms(20);
    assert_eq!(n.sdo_read(0x603F, 0), Ok(vec![0, 0]));
    assert_eq!(
        n.sent_on(0x85).last().map(|(_, x)| *x),
        Some(f(0x85, &[0, 0, 0, 0x01, 0, 0x12, 0x86, 0]))
    );
}

/// CiA 402-2 multi-axis layout: the second axis's objects 0x800 above the first (0x6840, 0x6841, …)
/// give a second drive with its own simulation record at 0x5FF1; each answers its own state.
#[test]
fn two_axes_from_one_description() {
    let mut desc = load(&example("drive.eds"));
    let axis1: Vec<od::Object> = desc
        .dictionary
        .objects()
        .filter(|o| (0x6000..0x6800).contains(&o.index))
        .cloned()
        .collect();
    for mut o in axis1 {
        o.index += 0x800;
        desc.dictionary.insert(o);
    }
    let mut n = node(desc, 5);
    assert_eq!(n.node.app().drives().len(), 2);
    assert_eq!(n.sdo_read(SIM_BASE + 1, 0), Ok(vec![5]));
    n.advance_ms(2);
    n.sdo_write(0x6840, 0, &[0x06, 0]).unwrap();
    n.advance_ms(2);
    // Axis 2 Ready to switch on (0x0221 with bit 9 remote: 0x21, 0x02), axis 1 still Switch on
    // disabled (0x0260).
    assert_eq!(n.sdo_read(0x6841, 0), Ok(vec![0x21, 0x02]));
    assert_eq!(n.sdo_read(0x6041, 0), Ok(vec![0x60, 0x02]));
}

/// Nodes of one identity get serial numbers counting up; a DCF without NodeID runs without one
/// (LSS), an EDS needs one.
#[test]
fn arguments_to_nodes() {
    let io = example("io-device.eds");
    let io = io.to_str().unwrap();
    let args = Args::try_parse_from([
        "canopen-node",
        "--od",
        &format!("{io}@3"),
        "--od",
        &format!("{io}@lss"),
        "--od",
        &format!("{io}@0x7F"),
    ])
    .unwrap();
    let loaded = canopen_cli::load(&args).unwrap();
    let serial = |l: &canopen_cli::Loaded| {
        l.description
            .dictionary
            .entry(0x1018, 4)
            .unwrap()
            .value
            .clone()
    };
    assert_eq!(
        loaded.iter().map(|l| l.node_id).collect::<Vec<_>>(),
        [3, 0xFF, 127]
    );
    assert_eq!(
        loaded.iter().map(serial).collect::<Vec<_>>(),
        [vec![1, 0, 0, 0], vec![2, 0, 0, 0], vec![3, 0, 0, 0]]
    );
    // A DCF without NodeID: a node without node-ID.
    let mut desc = load(&example("io-device.eds"));
    desc.set_node_id(None);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("unconfigured.dcf");
    std::fs::write(&path, od::eds::write_dcf(&desc)).unwrap();
    let args = Args::try_parse_from(["canopen-node", "--od", path.to_str().unwrap()]).unwrap();
    assert_eq!(canopen_cli::load(&args).unwrap()[0].node_id, 0xFF);
    // `file@name` is a file name, and `--node-id` is for one --od only.
    for (argv, says) in [
        (
            vec!["canopen-node", "--od", "dir@home/x.eds"],
            "dir@home/x.eds: ",
        ),
        (
            vec!["canopen-node", "--od", io, "--od", io, "--node-id", "4"],
            "--node-id is for a single --od; give several as FILE@ID",
        ),
    ] {
        let args = Args::try_parse_from(&argv).unwrap();
        let e = canopen_cli::load(&args).err().unwrap().to_string();
        assert!(e.starts_with(says), "{argv:?}: {e}");
    }
    let stations = canopen_cli::build(
        &Args::try_parse_from(["canopen-node", "--od", &format!("{io}@lss")]).unwrap(),
    )
    .unwrap();
    assert_eq!(stations[0].node.node_id(), 0xFF);
    assert_eq!(stations[0].node.state(), NmtState::Initialising);
}
