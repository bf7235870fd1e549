//! Bad traffic leaves the node answering and its heartbeat on time: malformed frames, frames for other
//! nodes, SDO floods and 100,000 random frames.

use std::time::{Duration, Instant};

use proptest::prelude::*;
use socketcan_node::node::NodeConfig;
use socketcan_node::sim::SimNode;
use socketcan_node::test_util::RunningNode;
use socketcan_node::transport::{BusEvent, CanBus, InProcessBus};
use socketcan_node::{CanFrame, NmtState};

const ID: u8 = 3;

fn f(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

/// A node with a 100 ms heartbeat, Operational.
fn operational() -> SimNode {
    let mut n = SimNode::new(ID, 1).unwrap();
    n.sdo_write(0x1017, 0, &[100, 0]).unwrap();
    n.nmt(0x01, ID);
    n
}

/// The node still answers an SDO read with the exact value and sends heartbeats every 100 ms.
fn assert_healthy(n: &mut SimNode) {
    assert_eq!(n.sdo_read(0x1018, 0), Ok(vec![4]));
    let t0 = n.elapsed();
    n.advance_ms(300);
    let beats: Vec<Duration> = n
        .sent_on(0x703)
        .into_iter()
        .map(|(t, _)| t)
        .filter(|t| *t > t0)
        .collect();
    assert_eq!(beats.len(), 3, "{beats:?}");
    for w in beats.windows(2) {
        assert_eq!(w[1] - w[0], Duration::from_millis(100));
    }
}

/// A random frame: any id (standard or extended), RTR or not, any length.
fn random_frame(seed: &mut u64) -> CanFrame {
    let mut next = || {
        *seed ^= *seed << 13;
        *seed ^= *seed >> 7;
        *seed ^= *seed << 17;
        *seed
    };
    let r = next();
    let len = (r % 9) as usize;
    let data = next().to_le_bytes();
    match (r >> 8) % 8 {
        0 => CanFrame::new_extended((r >> 16) as u32 & 0x1FFF_FFFF, &data[..len]).unwrap(),
        1 => CanFrame::new_remote_frame((r >> 16) as u32 & 0x7FF, false, len as u8).unwrap(),
        // Bias towards the node's own COB-IDs so the services see plenty of garbage.
        2 => f(0x600 + u16::from(ID), &data[..len]),
        3 => f(0x000, &data[..len]),
        4 => f(
            0x200 + u16::from(ID) + 0x100 * ((r >> 20) % 4) as u16,
            &data[..len],
        ),
        _ => f(((r >> 16) & 0x7FF) as u16, &data[..len]),
    }
}

#[test]
fn malformed_frames_change_nothing() {
    let mut n = operational();
    let before = n.node.dict().clone();
    for frame in [
        f(0x000, &[]),
        f(0x000, &[0x01]),
        f(0x000, &[0x81, ID, 0]),
        f(0x000, &[0x99, ID]),
        f(0x603, &[]),
        f(0x603, &[0x23, 0x17, 0x10, 0, 0x10]),
        f(0x080, &[1, 2]),
        CanFrame::new_extended(0x603, &[0x40, 0x18, 0x10, 0, 0, 0, 0, 0]).unwrap(),
        CanFrame::new_remote_frame(0x603, false, 8).unwrap(),
        CanFrame::new_remote_frame(0x000, false, 2).unwrap(),
    ] {
        let out = n.send(frame);
        assert!(out.is_empty(), "{frame}: {out:?}");
    }
    assert_eq!(n.node.state(), NmtState::Operational);
    assert_eq!(n.node.dict().objects().count(), before.objects().count());
    assert_healthy(&mut n);
}

#[test]
fn frames_for_other_nodes_are_ignored() {
    let mut n = operational();
    for other in (1..=127u16).filter(|&i| i != u16::from(ID)) {
        let out = n.send(f(0x600 + other, &[0x40, 0x18, 0x10, 0, 0, 0, 0, 0]));
        assert!(out.is_empty());
        n.send(f(0x000, &[0x02, other as u8]));
        n.send(f(0x200 + other, &[0, 0, 0, 0, 0x0F, 0, 1, 0]));
    }
    assert_eq!(n.node.state(), NmtState::Operational);
    assert_eq!(n.sdo_read(0x2101, 0), Ok(vec![0, 0]));
    assert_healthy(&mut n);
}

#[test]
fn sdo_flood_answers_every_request() {
    let mut n = operational();
    for k in 0..10_000u32 {
        let i = [0x00u16, 0x1017, 0x1018, 0x2109][k as usize % 4].to_le_bytes();
        let out = n.send(f(0x603, &[0x40, i[0], i[1], 0, 0, 0, 0, 0]));
        assert_eq!(out.len(), 1, "request {k}");
        assert_eq!(out[0].cob_id(), Some(0x583));
        // Index 0x0000 does not exist: abort 0x06020000.
        if k % 4 == 0 {
            assert_eq!(out[0].data(), &[0x80, 0, 0, 0, 0x00, 0x00, 0x02, 0x06]);
        }
    }
    assert_healthy(&mut n);
}

#[test]
fn hundred_thousand_random_frames() {
    let mut n = operational();
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    for k in 0..100_000 {
        n.send(random_frame(&mut seed));
        if k % 1000 == 0 {
            n.advance_ms(1);
        }
    }
    // Random NMT frames may have stopped or reset it: bring it back and check.
    n.nmt(0x82, ID);
    n.sdo_write(0x1017, 0, &[100, 0]).unwrap();
    assert_healthy(&mut n);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// No sequence of frames makes the node panic or stop answering SDO.
    #[test]
    fn any_frames_keep_the_node_answering(frames in proptest::collection::vec(
        (0u16..0x800, proptest::collection::vec(any::<u8>(), 0..=8)), 1..200)) {
        let mut n = operational();
        for (id, data) in frames {
            n.send(f(id, &data));
        }
        n.nmt(0x82, ID);
        prop_assert_eq!(n.sdo_read(0x1018, 0), Ok(vec![4]));
    }
}

/// The real runtime on an in-process bus: under a flood of 100,000 random frames from another
/// participant the node keeps answering SDO and its heartbeat keeps its period (within the
/// scheduling slack of a loaded test machine).
#[test]
fn runtime_under_a_random_flood() {
    let bus = InProcessBus::new();
    let mut master = bus.endpoint();
    let mut flooder = bus.endpoint();
    let mut cfg = NodeConfig::new(ID);
    cfg.heartbeat_ms = Some(50);
    let runner = RunningNode::start(cfg, bus.endpoint());
    let flood = std::thread::spawn(move || {
        let mut seed = 0x1234_5678_9ABC_DEF1u64;
        let mut sent = 0;
        while sent < 100_000 {
            let fr = random_frame(&mut seed);
            // Keep NMT, SDO and heartbeat ids of this node out of the flood: the master checks those.
            if matches!(fr.cob_id(), Some(0x000 | 0x603 | 0x583 | 0x703)) {
                continue;
            }
            flooder.send(&fr).unwrap();
            sent += 1;
            if sent % 500 == 0 {
                std::thread::sleep(Duration::from_millis(1));
            }
        }
    });
    let mut beats = Vec::new();
    let mut answers = 0;
    let start = Instant::now();
    let mut next_sdo = start;
    while start.elapsed() < Duration::from_secs(3) {
        if Instant::now() >= next_sdo {
            master
                .send(&f(0x603, &[0x40, 0x18, 0x10, 0, 0, 0, 0, 0]))
                .unwrap();
            next_sdo += Duration::from_millis(20);
        }
        if let Ok(Some(BusEvent::Frame { frame, .. })) = master.recv(Duration::from_millis(2)) {
            match frame.cob_id() {
                Some(0x703) if frame.data() != [0x00] => beats.push(Instant::now()),
                Some(0x583) => {
                    assert_eq!(frame.data(), &[0x4F, 0x18, 0x10, 0, 4, 0, 0, 0]);
                    answers += 1;
                }
                _ => {}
            }
        }
    }
    flood.join().unwrap();
    runner.stop();
    assert!(answers >= 100, "only {answers} SDO answers in 3 s");
    assert!(beats.len() >= 50, "only {} heartbeats in 3 s", beats.len());
    for w in beats.windows(2) {
        let gap = w[1] - w[0];
        assert!(gap < Duration::from_millis(250), "heartbeat gap {gap:?}");
    }
}
