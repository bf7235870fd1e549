#![no_main]
//! Any bytes as a candump log through `sdo-tool decode`'s reader and watcher, read in chunks of
//! any size, for every node or one, with the X67 node's dictionary (its PDOs and entry types) or
//! without, with --raw or not: no panic, and what comes out is in proportion to what went in (a
//! line or two per input line and the bytes of its frame, the transfers left open once each).

use std::cell::RefCell;
use std::io::BufReader;

use sdo_tool::watch::{Decoded, LogDecoder, Watcher};

thread_local! {
    /// The X67 bus controller's dictionary with two modules, built once.
    static DICT: RefCell<od::Dictionary> =
        RefCell::new(socketcan_node::x67::dictionary(2).expect("dictionary"));
}

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Some((&flags, rest)) = data.split_first() else {
        return;
    };
    let Some((&chunk, log)) = rest.split_first() else {
        return;
    };
    // Bits 0–1: every node, node 1, node 3 or node 0x7F; bit 2 the dictionary; bit 3 --raw.
    let node = match flags & 3 {
        0 => None,
        1 => Some(1),
        2 => Some(3),
        _ => Some(0x7F),
    };
    let events = DICT.with(|dict| {
        let dict = dict.borrow();
        let w = Watcher::new(node, (flags & 4 != 0).then_some(&*dict)).with_raw(flags & 8 != 0);
        let mut decoder = LogDecoder::new(BufReader::with_capacity(usize::from(chunk) + 1, log), w);
        let mut events = Vec::new();
        while let Some(e) = decoder.next_event().expect("reading from memory") {
            events.push(e);
        }
        events
    });
    let lines = log.split(|&b| b == b'\n').count();
    let mut out = 0usize;
    let mut open = 0usize;
    for e in &events {
        match e {
            Decoded::Line { text, .. } => out += text.len(),
            Decoded::Open { transfer, .. } => {
                open += 1;
                out += transfer.to_string().len();
            }
            Decoded::TooLong { line } => assert!(*line as usize <= lines, "line {line}"),
        }
    }
    // A node has at most one transfer going on.
    assert!(open <= 127, "{open} transfers open");
    // An input line is a frame, which gives a line about it, or a line too long; a node's
    // silence is told once after each of its heartbeats; a transfer's bytes come out as text of
    // a few characters each.
    assert!(
        events.len() <= 2 * lines + 127,
        "{} events for {lines} lines",
        events.len()
    );
    assert!(
        out <= 16 * log.len() + 256 * (lines + 127),
        "{out} bytes of text for {} bytes of log",
        log.len()
    );
});
