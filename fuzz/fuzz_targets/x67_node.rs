#![no_main]
//! Arbitrary frames, with time passing between them, into the virtual X67 node: no panic, the node's
//! output stays bounded, and after a reset communication it still answers an SDO read exactly.

use std::cell::RefCell;
use std::time::Duration;

use socketcan_node::sim::SimNode;
use socketcan_node::CanFrame;

thread_local! {
    /// The node as booted, built once from its dictionary; each input runs on a fork of it.
    static BOOTED: RefCell<SimNode> = RefCell::new(SimNode::new(3, 2).expect("node"));
}

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let mut n = BOOTED.with(|b| b.borrow_mut().fork());
    // Each record: a time step (ms), two bytes of id (11 bits + RTR flag), a length and 8 data bytes.
    for c in data.chunks_exact(12) {
        n.advance(Duration::from_millis(u64::from(c[0])));
        let raw = u16::from_le_bytes([c[1], c[2]]);
        let len = usize::from(c[3] % 9);
        let frame = if raw & 0x8000 != 0 {
            CanFrame::new_remote_frame(u32::from(raw & 0x7FF), false, len as u8)
        } else {
            CanFrame::new(raw & 0x7FF, &c[4..4 + len])
        }
        .expect("valid frame");
        let out = n.send(frame);
        assert!(out.len() <= 256, "{} frames for one frame", out.len());
        n.sent.clear();
    }
    n.nmt(0x82, 3);
    assert_eq!(n.sdo_read(0x1018, 0), Ok(vec![4]));
});
