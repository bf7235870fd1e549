//! pysoem holding two emulated units in Op while junk frames flood the link: a test binary of its
//! own, so that no other master and emulator share the machine with the flood. Needs root and pysoem
//! (`pip install pysoem`); without either it fails and says why.

use std::io::{BufRead, BufReader, Read};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use ethercat_slave::frame::datagrams;
use ethercat_slave::raw::RawSocket;
use testkit::link;

#[path = "common/pysoem.rs"]
#[allow(dead_code)]
mod pysoem_master;
use pysoem_master::{preflight, script};

/// Junk frames at `rate` a second on `iface` until `stop`: three kinds that do not parse (datagram
/// length beyond the frame, frame type 4, a datagram cut short) and one well-formed NOP, in turn.
/// Every one carries a frame index of 0xF0 or above, which SOEM (16 frame buffers) never waits for.
/// Returns `(malformed, nop)` frames sent.
fn junk(iface: &str, rate: u32, stop: &AtomicBool) -> (u64, u64) {
    let socket = RawSocket::open(iface).unwrap_or_else(|e| panic!("raw socket on {iface}: {e}"));
    let frame = |header: u16, index: u8| {
        let mut f = vec![0u8; 60];
        f[..6].fill(0xFF);
        f[6..12].copy_from_slice(&[0x02, 0, 0, 0, 0, 0xAA]);
        f[12..14].copy_from_slice(&[0x88, 0xA4]);
        f[14..16].copy_from_slice(&header.to_le_bytes());
        f[16] = 0x00; // NOP
        f[17] = index;
        f[22] = 2; // 2 data bytes
        f
    };
    let kinds = [
        (frame(0x1000 | 0x07FF, 0xF1), false), // 2047 bytes of datagrams in a 60-byte frame
        (frame(0x4000 | 14, 0xF2), false),     // type 4: not commands
        (frame(0x1000 | 8, 0xF3), false),      // 8 bytes: less than one datagram header
        (frame(0x1000 | 14, 0xF4), true),      // NOP, 2 data bytes: answered, changes nothing
    ];
    for (f, ok) in &kinds {
        assert_eq!(datagrams(f).is_ok(), *ok, "junk frame {:02X?}", &f[14..24]);
    }
    let (mut malformed, mut nop) = (0u64, 0u64);
    let start = Instant::now();
    let mut sent = 0u64;
    while !stop.load(Ordering::Relaxed) {
        // Frames due by now at `rate`, sent at once (bursts of a fortieth of a second, 500 at 20,000
        // a second: more than the kernel's default receive buffer holds); then a sleep.
        let due = start.elapsed().as_micros() as u64 * u64::from(rate) / 1_000_000;
        while sent < due {
            let (f, ok) = &kinds[(sent % 4) as usize];
            if socket.send(f).is_ok() {
                if *ok {
                    nop += 1;
                } else {
                    malformed += 1;
                }
            }
            sent += 1;
        }
        std::thread::sleep(Duration::from_millis(25));
    }
    (malformed, nop)
}

/// 20,000 junk frames a second (bursts of 500) on the link while pysoem holds both units in Op for 5 s: every cycle
/// at working counter 6, both units read (Op, AL status code 0) every 100 ms, so the SyncManager
/// watchdog (100 ms, SMD-R1-035) never ran out; the emulator counts every malformed junk frame as
/// dropped — none was lost in the kernel before it (its receive buffer is 16 MiB).
#[test]
fn pysoem_holds_op_under_20000_junk_frames_per_second_smd_r1_035() {
    preflight();
    let mut link = link::Link::up(&["--units", "2"]);
    let mut child = Command::new("python3")
        .arg(script())
        .arg(&link.master)
        .args(["2", "--hold-op", "5"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {}: {e}", script()));
    let (tx, rx) = std::sync::mpsc::channel::<String>();
    let mut stdout = BufReader::new(child.stdout.take().expect("stdout"));
    std::thread::spawn(move || {
        let mut line = String::new();
        while stdout.read_line(&mut line).is_ok_and(|n| n > 0) {
            let _ = tx.send(std::mem::take(&mut line));
        }
    });
    let mut stderr = child.stderr.take().expect("stderr");
    let stderr = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = stderr.read_to_string(&mut s);
        s
    });
    let in_op = rx.recv_timeout(Duration::from_secs(25));
    let fail = |link: &mut link::Link, child: &mut std::process::Child, why: String| -> ! {
        let _ = child.kill();
        let _ = child.wait();
        panic!("{why}\n--- emulator log:\n{}", link.stop());
    };
    if in_op.as_deref().map(str::trim) != Ok("in Op") {
        fail(
            &mut link,
            &mut child,
            format!("pysoem did not reach Op: {in_op:?}"),
        );
    }
    let stop = Arc::new(AtomicBool::new(false));
    let iface = link.master.clone();
    let s = Arc::clone(&stop);
    let started = Instant::now();
    let injector = std::thread::spawn(move || junk(&iface, 20_000, &s));
    let deadline = Instant::now() + Duration::from_secs(20);
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for the pysoem master") {
            break status;
        }
        if Instant::now() > deadline {
            stop.store(true, Ordering::Relaxed);
            fail(
                &mut link,
                &mut child,
                "the pysoem master ran over 20 s in Op".into(),
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    stop.store(true, Ordering::Relaxed);
    let injected_for = started.elapsed();
    let (malformed, nop) = injector.join().unwrap();
    let summary: String = rx.try_iter().collect();
    let alive = link.running();
    let log = link.stop();
    let report = format!(
        "--- stdout:\n{summary}--- stderr:\n{}--- emulator log:\n{log}",
        stderr.join().unwrap()
    );
    assert!(
        status.success(),
        "the pysoem master failed ({status})\n{report}"
    );
    assert!(alive, "smd-ethercat had stopped by the end\n{report}");
    assert!(summary.contains("held Op for 5 s"), "{report}");
    let rate = (malformed + nop) as f64 / injected_for.as_secs_f64();
    assert!(rate >= 19_000.0, "junk sent at {rate:.0} frames/s only");
    let (answered, dropped) =
        link::frame_counts(&log).unwrap_or_else(|| panic!("no frame counts in the log\n{report}"));
    assert_eq!(
        dropped, malformed,
        "every malformed junk frame dropped, none lost before\n{report}"
    );
    assert!(
        answered > nop,
        "the NOPs and the master's frames answered\n{report}"
    );
    println!(
        "{} [{malformed} malformed + {nop} NOP junk frames at {rate:.0}/s; {answered} answered, {dropped} dropped]",
        summary.trim()
    );
}
