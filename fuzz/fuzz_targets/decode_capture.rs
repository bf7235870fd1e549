#![no_main]
//! Any bytes as a pcapng capture through `sdo-tool decode`'s reader and watcher (after the
//! Section Header Block's type, so that the reader gets past its first check), for every node or
//! one: no panic, no error but one naming a block, and what comes out is in proportion to what
//! went in (a line or two per 16 bytes of input, the transfers left open once each).

use sdo_tool::watch::{Decoded, LogDecoder, Watcher};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Some((&flags, rest)) = data.split_first() else {
        return;
    };
    let node = (flags & 1 != 0).then_some(1);
    let mut file = vec![0x0A, 0x0D, 0x0D, 0x0A];
    file.extend_from_slice(rest);
    let w = Watcher::new(node, None).with_raw(flags & 2 != 0);
    let mut decoder = LogDecoder::pcapng(&file[..], w);
    let mut events = 0usize;
    let mut out = 0usize;
    loop {
        match decoder.next_event() {
            Ok(Some(Decoded::Line { text, .. })) => out += text.len(),
            Ok(Some(Decoded::Open { transfer, .. })) => out += transfer.to_string().len(),
            Ok(Some(Decoded::TooLong { .. })) => panic!("a capture has no lines"),
            Ok(None) => break,
            Err(e) => {
                assert!(e.to_string().starts_with("byte ") || e.to_string().starts_with("not a pcapng"), "{e}");
                break;
            }
        }
        events += 1;
    }
    // A frame is at least a 32-byte block; a node's silence is told once after each heartbeat.
    assert!(events <= 2 * (file.len() / 16) + 127, "{events} events for {} bytes", file.len());
    assert!(out <= 64 * file.len() + 256 * 127, "{out} bytes of text for {} bytes", file.len());
});
