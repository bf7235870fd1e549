#![no_main]
//! Arbitrary EtherCAT frames, with time passing between them, through a chain of two emulated SMD
//! units: no panic, a frame keeps its length, a frame that does not parse leaves the chain as it
//! was, and the chain's timers keep running.

use std::sync::OnceLock;
use std::time::{Duration, Instant};

use ethercat_slave::smd::binding::Device;
use ethercat_slave::smd::SmdChain;

/// The chain as powered on, built once from the description; each input runs on a clone.
static CHAIN: OnceLock<(SmdChain, Instant)> = OnceLock::new();

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let (chain, t0) = CHAIN.get_or_init(|| {
        let t0 = Instant::now();
        let chain = SmdChain::new(Device::Smd23kB, 2, Duration::from_millis(1), t0).expect("chain");
        (chain, t0)
    });
    let (mut chain, t0) = (chain.clone(), *t0);
    let mut now = t0;
    // Each record: a time step (100 µs), a length (two bytes), then the frame.
    let mut rest = data;
    while let [step, lo, hi, tail @ ..] = rest {
        let n = usize::from(u16::from_le_bytes([*lo, *hi])).min(tail.len());
        now += Duration::from_micros(100 * u64::from(*step));
        let mut frame = tail[..n].to_vec();
        let before = frame.clone();
        match chain.handle_frame(now, &mut frame) {
            Ok(()) => assert_eq!(frame.len(), before.len()),
            Err(_) => assert_eq!(frame, before, "a refused frame is unchanged"),
        }
        if chain.poll_timeout().is_some_and(|t| t <= now) {
            chain.handle_timeout(now);
        }
        rest = &tail[n..];
    }
});
