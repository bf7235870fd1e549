#![no_main]
//! Arbitrary mailboxes, with time passing between them, into the CoE server of an SMD unit (its
//! dictionary and model): no panic, every answer fits the mailbox, and the answers of one mailbox are
//! bounded.

use std::time::{Duration, Instant};

use ds402::smd::config::EncoderKind;
use ethercat_slave::smd::binding::{Device, SmdUnit};
use od::coe::server::CoeServer;
use od::sdo::server::ServerConfig;

const MAILBOX: usize = 128;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let mut unit = SmdUnit::new(Device::Smd23kB, EncoderKind::Incremental).expect("unit");
    let mut coe = CoeServer::new(ServerConfig::default(), MAILBOX);
    let mut now = Instant::now();
    // Each record: a time step (ms), a length, then that many bytes of mailbox.
    let mut rest = data;
    while let [step, len, tail @ ..] = rest {
        let n = usize::from(*len).min(tail.len()).min(MAILBOX);
        now += Duration::from_millis(u64::from(*step));
        unit.handle_mailbox(&mut coe, now, &tail[..n]);
        let mut answers = 0;
        while let Some(answer) = coe.poll_transmit() {
            assert!(
                answer.len() <= MAILBOX,
                "{} bytes for a {MAILBOX}-byte mailbox",
                answer.len()
            );
            answers += 1;
            assert!(answers <= 4096, "answers without end");
        }
        rest = &tail[n..];
    }
});
