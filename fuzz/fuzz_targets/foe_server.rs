#![no_main]
//! Arbitrary FoE frames, with time passing between them and the unit in and out of Bootstrap, into
//! the FoE server of a unit with small limits: no panic, every answer fits the read mailbox, and
//! the files never take more than the limits.

use std::time::{Duration, Instant};

use ethercat_slave::foe::{FileStore, FoeConfig, FoeServer, Link};

const MAX_FILE: usize = 300;
const MAX_STORE: usize = 500;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let config = FoeConfig {
        max_file: MAX_FILE,
        max_store: MAX_STORE,
        boot: true,
        packet_time: Duration::from_millis(3),
        ..FoeConfig::default()
    };
    let mut server = FoeServer::new(config, FileStore::new(MAX_FILE, MAX_STORE));
    let mut now = Instant::now();
    // Each record: a time step (ms), the link (bit 0 Bootstrap, bits 1-7 the mailboxes' length
    // beyond 13), a length, then that many bytes of frame.
    let mut rest = data;
    while let [step, link, len, tail @ ..] = rest {
        let n = usize::from(*len).min(tail.len());
        now += Duration::from_millis(u64::from(*step));
        let mailbox = 13 + usize::from(link >> 1);
        let link = Link {
            boot: link & 1 != 0,
            write_len: mailbox,
            read_len: mailbox,
        };
        server.handle_mailbox(now, &tail[..n], link);
        while let Some(answer) = server.poll_transmit() {
            assert!(
                answer.len() <= mailbox - 6,
                "{} bytes for a {mailbox}-byte mailbox",
                answer.len()
            );
        }
        while server.poll_event().is_some() {}
        while let Some((_, file)) = server.poll_written() {
            assert!(file.len() <= MAX_FILE);
        }
        assert!(server.store().used() <= MAX_STORE);
        rest = &tail[n..];
    }
});
