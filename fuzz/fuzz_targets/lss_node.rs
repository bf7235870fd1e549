#![no_main]
//! LSS requests (CiA 305) and other frames, with time passing between them, into a node serving
//! LSS over the X67 bus controller's dictionary, booted without a node-ID (0xFF) or as node 3, with
//! storage for the LSS configuration or without. The device behind it does nothing (the X67
//! modules' simulation would take most of the time and LSS does not reach it). No panic; an LSS
//! request gets at most one answer, on 0x7E4, and nothing else does; the node's node-ID is its LSS
//! slave's active one, 1–127 or 0xFF; a node without one sends nothing but LSS answers; the
//! node's output stays bounded. At the end LSS configures node-ID 5, which the node takes (at
//! once without a node-ID, at its reset communication with one) and answers an SDO read as node 5.

use std::cell::RefCell;
use std::time::{Duration, Instant};

use od::hook::NoHook;
use socketcan_node::node::lss::{LSS_REQUEST, LSS_RESPONSE, UNCONFIGURED};
use socketcan_node::node::storage::MemoryStorage;
use socketcan_node::node::LssConfig;
use socketcan_node::sim::SimNode;
use socketcan_node::{CanFrame, Node, NodeConfig};

/// A node as booted: without a node-ID or as node 3 (bit 0), with LSS storage or without (bit 1).
fn booted(variant: u8) -> SimNode<NoHook> {
    let config = NodeConfig {
        lss: Some(LssConfig {
            bit_timing: 4,
            can_store: variant & 2 != 0,
        }),
        ..NodeConfig::new(if variant & 1 == 0 { UNCONFIGURED } else { 3 })
    };
    let dict = socketcan_node::x67::dictionary(2).expect("dictionary");
    let t0 = Instant::now();
    let node = Node::new(config, dict, NoHook, t0).expect("node");
    SimNode::boot(node, t0, Box::new(MemoryStorage::default()))
}

thread_local! {
    /// The four nodes as booted, built once; each input runs on a fork of one.
    static BOOTED: RefCell<Vec<SimNode<NoHook>>> = RefCell::new((0..4).map(booted).collect());
}

/// The LSS address of `n` (its 0x1018:01–04).
fn address(n: &SimNode<NoHook>) -> [u32; 4] {
    n.node.lss().expect("serves LSS").address()
}

/// Checks what always holds of the node.
fn check_node_id(n: &SimNode<NoHook>) {
    let id = n.node.node_id();
    assert!(
        id == UNCONFIGURED || (1..=127).contains(&id),
        "node-ID {id}"
    );
    assert_eq!(id, n.node.lss().expect("serves LSS").active_node_id());
}

fn lss(n: &mut SimNode<NoHook>, data: [u8; 8]) -> Vec<CanFrame> {
    n.send(CanFrame::new(LSS_REQUEST, &data).expect("8 bytes"))
}

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Some((&variant, records)) = data.split_first() else {
        return;
    };
    let mut n = BOOTED.with(|b| b.borrow_mut()[usize::from(variant & 3)].fork());
    // Each record: a time step, a kind, and 8 bytes.
    for c in records.chunks_exact(10) {
        let (step, kind, d) = (c[0], c[1], &c[2..10]);
        // Mostly a few ms; with bit 7 of the kind in 100 ms steps, up to 25.5 s.
        let ms = if kind & 0x80 != 0 {
            u64::from(step) * 100
        } else {
            u64::from(step)
        };
        let before = n.node.node_id();
        let out = n.advance(Duration::from_millis(ms));
        assert!(
            before != UNCONFIGURED || out.is_empty(),
            "a node without a node-ID sent {out:?}"
        );
        assert!(
            out.iter().all(|f| f.cob_id() != Some(LSS_RESPONSE)),
            "an LSS answer unasked: {out:?}"
        );
        check_node_id(&n);
        let mut bytes = [0u8; 8];
        bytes.copy_from_slice(d);
        let frame = match kind & 0x0F {
            // An LSS request as it comes.
            0..=5 => CanFrame::new(LSS_REQUEST, &bytes),
            // An LSS request with a part of the node's address (selective switch, identify,
            // Fastscan compare these): bytes 1–4 the part d[1] & 3 names.
            6 | 7 => {
                let part = address(&n)[usize::from(d[1] & 3)].to_le_bytes();
                bytes[1..5].copy_from_slice(&part);
                CanFrame::new(LSS_REQUEST, &bytes)
            }
            // An LSS request of another length, or a remote frame on its identifier.
            8 => CanFrame::new(LSS_REQUEST, &bytes[..usize::from(d[7] % 8)]),
            9 => CanFrame::new_remote_frame(u32::from(LSS_REQUEST), false, d[7] % 9),
            // NMT: a command to all or to a node.
            10 | 11 => CanFrame::new(0x000, &bytes[..2]),
            // An SDO request to the node's identifier.
            12 => CanFrame::new(0x600 + u16::from(n.node.node_id() & 0x7F), &bytes),
            // Any frame.
            _ => {
                let id = u16::from_le_bytes([d[0], d[1]]) & 0x7FF;
                CanFrame::new(id, &bytes[2..2 + usize::from(kind >> 4) % 7])
            }
        }
        .expect("valid frame");
        let request = frame.cob_id() == Some(LSS_REQUEST) && !frame.is_rtr();
        let out = n.send(frame);
        assert!(out.len() <= 256, "{} frames for one frame", out.len());
        let answers = out
            .iter()
            .filter(|f| f.cob_id() == Some(LSS_RESPONSE))
            .count();
        assert!(
            answers <= usize::from(request),
            "{answers} LSS answers to {frame:?}: {out:?}"
        );
        check_node_id(&n);
        if n.node.node_id() == UNCONFIGURED {
            assert!(
                out.iter().all(|f| f.cob_id() == Some(LSS_RESPONSE)),
                "a node without a node-ID sent {out:?}"
            );
        }
        n.sent.clear();
    }

    // Node-ID 5 by LSS: configuration state, configure (answered "done"), back to waiting.
    lss(&mut n, [0x04, 0x01, 0, 0, 0, 0, 0, 0]);
    let answer = lss(&mut n, [0x11, 5, 0, 0, 0, 0, 0, 0]);
    assert_eq!(
        answer,
        [CanFrame::new(LSS_RESPONSE, &[0x11, 0, 0, 0, 0, 0, 0, 0]).unwrap()]
    );
    let unconfigured = n.node.node_id() == UNCONFIGURED;
    lss(&mut n, [0x04, 0x00, 0, 0, 0, 0, 0, 0]);
    if !unconfigured {
        n.nmt(0x82, 0);
    }
    check_node_id(&n);
    assert_eq!(n.node.node_id(), 5);
    assert_eq!(n.sdo_read(0x1018, 0), Ok(vec![4]));
});
