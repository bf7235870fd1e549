//! Frames per second the emulator answers, for a chain of 1 and of 16 SMD units in Op with one LRW of
//! all process data per frame (40 bytes per unit):
//!
//! - **in process**: [`SmdChain::handle_frame`] alone, the ESC work per frame;
//! - **on a veth pair**: `smd-ethercat` in its own network namespace, a master on the other end
//!   sending the next frame when the answer is back (one frame in flight, as a master's cycle does),
//!   and with 8 frames in flight (what the emulator can take); and 16 units offered 148,809
//!   minimal frames a second (100 Mbit/s) by a master with up to 64 in flight that sends and
//!   receives in batches: the frames answered, and those the master could not send in time
//!   because its window was full. Needs root. `ECAT_EMULATOR=PATH` runs another build of
//!   `smd-ethercat` on the link. Each veth figure comes with the emulator's CPU time per frame
//!   (its thread's, /proc/PID/schedstat, the kernel's work on its behalf included): what it
//!   costs whatever else the machine is doing.
//!
//! `cargo bench -p ethercat-slave --bench frames [-- SECONDS] [in-process|veth]` (default 3 s per
//! figure; without `--bench`, as under `cargo test`, a short run; `in-process` or `veth` runs only
//! those figures).

use testkit::link;

use std::time::{Duration, Instant};

use ds402::smd::indexer::Outputs;
use ethercat_slave::esc::al::state;
use ethercat_slave::esc::cmd;
use ethercat_slave::frame::{emit, parse, Datagram};
use ethercat_slave::master::SimChain;
use ethercat_slave::master::{self, lrw_datagram, SocketWire, SRC};
use ethercat_slave::raw::{Batch, RawSocket};
use ethercat_slave::smd::binding::Device;

/// The LRW frame for `n` units and the working counter every answer must carry (3 per unit).
fn lrw_frame(n: usize) -> (Vec<u8>, u16) {
    let outputs = vec![Outputs::default(); n];
    (emit(&[lrw_datagram(&outputs, n)], SRC), 3 * n as u16)
}

fn check(answer: &[u8], wkc: u16) {
    let d = parse(answer).expect("the answer parses");
    assert_eq!(d[0].wkc, wkc, "every unit read and wrote");
}

fn in_process(n: usize, secs: f64) -> f64 {
    let mut c = SimChain::new(Device::Smd23kB, n).unwrap();
    master::bring_up(&mut c, state::OP).unwrap();
    let (frame, wkc) = lrw_frame(n);
    let mut f = frame.clone();
    let start = Instant::now();
    let mut frames = 0u64;
    let mut next_cycle = Duration::from_millis(1);
    while start.elapsed().as_secs_f64() < secs {
        for _ in 0..100 {
            f.copy_from_slice(&frame);
            c.process(&mut f).unwrap();
        }
        frames += 100;
        // The units' own 1 ms cycle, as the runtime runs it.
        let t = start.elapsed();
        if t >= next_cycle {
            c.cycle(Duration::from_millis(1));
            next_cycle = t + Duration::from_millis(1);
        }
    }
    check(&f, wkc);
    frames as f64 / start.elapsed().as_secs_f64()
}

/// `smd-ethercat` with `args` on a fresh veth pair: this workspace's, or the binary
/// `ECAT_EMULATOR` names (another build, to compare with).
fn emulator(args: &[&str]) -> link::Link {
    match std::env::var_os("ECAT_EMULATOR") {
        Some(path) => link::Link::with(path.into(), args),
        None => link::Link::up(args),
    }
}

/// CPU time of process `pid`'s (main) thread in ns, from /proc/PID/schedstat: the emulator's
/// own work and the kernel's on its behalf (its system calls, the frames it sends through the
/// veth pair).
fn cpu_ns(pid: u32) -> u64 {
    std::fs::read_to_string(format!("/proc/{pid}/schedstat"))
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse().ok())
        .expect("the emulator's scheduler statistics")
}

/// What the emulator took on a veth pair: frames/s answered, and its CPU time per frame (µs).
struct OnVeth {
    fps: f64,
    cpu_us: f64,
}

fn on_veth(n: usize, secs: f64, window: usize, busy_poll_us: u32) -> OnVeth {
    let units = n.to_string();
    let spin = busy_poll_us.to_string();
    let link = emulator(&["--units", &units, "--busy-poll-us", &spin]);
    let socket = RawSocket::open(&link.master).expect("raw socket on the master's end");
    let mut w = SocketWire::new(socket, n);
    master::bring_up(&mut w, state::OP).unwrap();
    let socket = w.socket();
    let (frame, wkc) = lrw_frame(n);
    let mut buf = vec![0u8; 2048];
    let pid = link.pid().expect("the emulator runs");
    let cpu = cpu_ns(pid);
    let start = Instant::now();
    let mut count = Count::default();
    while start.elapsed().as_secs_f64() < secs {
        while count.in_flight < window as u64 {
            socket.send(&frame).unwrap();
            count.sent();
        }
        // The master polls for the answer without sleeping, as a real-time master's cycle does.
        let deadline = Instant::now() + Duration::from_millis(100);
        let mut got = false;
        while !got && Instant::now() < deadline {
            while let Some(len) = socket.recv(&mut buf).unwrap() {
                check(&buf[..len], wkc);
                got |= count.answer();
            }
        }
        if !got {
            // Frames lost: reported, and the window starts again.
            count.timed_out();
        }
    }
    let fps = count.answered as f64 / start.elapsed().as_secs_f64();
    let cpu_us = (cpu_ns(pid) - cpu) as f64 / 1e3 / count.answered.max(1) as f64;
    if count.lost > 0 || count.late > 0 {
        println!(
            "   ({} frames lost, {} of them answered late)",
            count.lost, count.late
        );
    }
    OnVeth { fps, cpu_us }
}

/// What a master offering frames at a steady rate got: frames/s answered, frames it could not
/// send in time because its window was full (the emulator behind), frames lost.
struct Paced {
    answered: f64,
    behind: u64,
    lost: u64,
    /// The emulator's CPU time per frame answered (µs).
    cpu_us: f64,
}

/// A master offering `rate` minimal frames a second (a BRD of the AL status: 60 bytes, 64 on the
/// wire) to `n` units on a veth pair, at most `window` in flight, sending and receiving in batches
/// (sendmmsg, recvmmsg), so that the emulator is the limit; every answer checked for a working
/// counter of `n`.
fn paced_on_veth(n: usize, secs: f64, rate: f64, window: u64) -> Paced {
    let units = n.to_string();
    let link = emulator(&["--units", &units]);
    let socket = RawSocket::open(&link.master).expect("raw socket on the master's end");
    let mut w = SocketWire::new(socket, n);
    master::bring_up(&mut w, state::OP).unwrap();
    let socket = w.socket();
    let frame = emit(&[Datagram::new(cmd::BRD, 0, 0x0130, vec![0; 2])], SRC);
    let wkc = n as u16;
    let mut out = Batch::new(Batch::MAX, frame.len());
    let mut answers = Batch::new(Batch::MAX, 2048);
    let mut count = Count::default();
    let mut sent = 0u64;
    let mut due = 0u64;
    let pid = link.pid().expect("the emulator runs");
    let cpu = cpu_ns(pid);
    let start = Instant::now();
    let mut last_answer = start;
    loop {
        let elapsed = start.elapsed().as_secs_f64();
        if elapsed >= secs {
            break;
        }
        due = (elapsed * rate) as u64;
        out.clear();
        while sent < due && count.in_flight < window && out.push(&frame) {
            sent += 1;
            count.sent();
        }
        if !out.is_empty() {
            socket.send_batch(&out).unwrap();
        }
        let got = socket.recv_batch(&mut answers).unwrap();
        for k in 0..got {
            check(answers.frame(k), wkc);
            count.answer();
        }
        if got > 0 {
            last_answer = Instant::now();
        } else if count.in_flight > 0 && last_answer.elapsed() > Duration::from_millis(100) {
            count.timed_out();
            last_answer = Instant::now();
        }
    }
    Paced {
        answered: count.answered as f64 / start.elapsed().as_secs_f64(),
        behind: due - sent,
        lost: count.lost,
        cpu_us: (cpu_ns(pid) - cpu) as f64 / 1e3 / count.answered.max(1) as f64,
    }
}

/// The frames of a window-based master: in flight, answered in time, lost (no answer within the
/// timeout), and answers that came after their frame was counted lost.
#[derive(Debug, Default, PartialEq, Eq)]
struct Count {
    in_flight: u64,
    answered: u64,
    lost: u64,
    late: u64,
}

impl Count {
    fn sent(&mut self) {
        self.in_flight += 1;
    }

    /// An answer; false when it is a late one (its frame was counted lost already).
    fn answer(&mut self) -> bool {
        if self.in_flight == 0 {
            self.late += 1;
            return false;
        }
        self.in_flight -= 1;
        self.answered += 1;
        true
    }

    fn timed_out(&mut self) {
        self.lost += self.in_flight;
        self.in_flight = 0;
    }
}

/// The accounting of a late answer (a loaded machine): window of 3, one answered, the other two
/// counted lost at the timeout, then both answered late: no overflow, 1 answered, 2 lost, 2 late.
fn count_checks() {
    let mut c = Count::default();
    (0..3).for_each(|_| c.sent());
    assert!(c.answer());
    c.timed_out();
    assert!(!c.answer());
    assert!(!c.answer());
    assert_eq!(
        c,
        Count {
            in_flight: 0,
            answered: 1,
            lost: 2,
            late: 2
        }
    );
}

fn main() {
    count_checks();
    let bench = std::env::args().any(|a| a == "--bench");
    let secs: f64 = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(if bench { 3.0 } else { 0.3 });
    let only = |what: &str| {
        let filters = ["in-process", "veth"];
        let given: Vec<String> = std::env::args()
            .filter(|a| filters.contains(&a.as_str()))
            .collect();
        given.is_empty() || given.iter().any(|a| a == what)
    };
    for n in [1usize, 16].into_iter().filter(|_| only("in-process")) {
        println!(
            "{n:>2} units, in process:                {:>9.0} frames/s",
            in_process(n, secs)
        );
    }
    if only("veth") {
        // The master gets the emulator's priority (testkit::favour): on a machine busy with other
        // jobs a master at the default one would be the limit, not the emulator.
        testkit::favour_this_thread();
        // 100 Mbit/s of minimal frames: 84 bytes on the wire each with preamble and gap.
        let rate = 100e6 / (84.0 * 8.0);
        let window = 64;
        let p = paced_on_veth(16, secs, rate, window);
        println!(
            "16 units, veth, {rate:.0} minimal frames/s offered, up to {window} in flight: {:>9.0} frames/s ({} behind, {} lost), emulator {:.2} µs CPU a frame",
            p.answered, p.behind, p.lost, p.cpu_us
        );
    }
    for n in [1usize, 16].into_iter().filter(|_| only("veth")) {
        for (window, spin) in [(1usize, 0u32), (1, 200), (8, 0)] {
            let v = on_veth(n, secs, window, spin);
            println!(
                "{n:>2} units, veth, {window} frame(s) in flight, --busy-poll-us {spin:>3}: {:>9.0} frames/s, emulator {:.2} µs CPU a frame",
                v.fps, v.cpu_us
            );
        }
    }
}
