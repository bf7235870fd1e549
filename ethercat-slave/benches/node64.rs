//! 64 example drives (`examples/drive.esi.xml`) of `ethercat-node` on one veth pair, driven by a
//! master with a 1 ms cycle and Distributed Clocks: SYNC0 every 1 ms on every unit (system times
//! aligned by their offsets 0x0920), and every cycle one frame with the reference clock's time
//! distributed (FRMW of 0x0910, as DC masters compensate drift) and one LRW of all process data
//! (64 × 7 output and 64 × 15 input bytes), the drives in csp following a ramp. Every answer is
//! checked: working counters 64 and 192, every drive Operation enabled without a following error;
//! at the end every position exactly at its target. The figure: the emulator's CPU time over the
//! run (its one thread, /proc/PID/schedstat) as a share of one core. First the same chain in
//! process (the master's frame, the chain's work, per cycle, from the thread's own statistics).
//!
//! `cargo bench -p ethercat-slave --bench node64 [-- SECONDS]` (default 10 s; without `--bench`,
//! as under `cargo test`, 1 s). Needs root.

use std::time::{Duration, Instant};

use ethercat_slave::esc::cmd;
use ethercat_slave::frame::{emit, parse, Datagram};
use ethercat_slave::master::{self, station, Layout, SocketWire, Wire, SRC};
use ethercat_slave::node_cli::{load, EsiSpec};
use ethercat_slave::raw::RawSocket;
use testkit::link::Link;

const UNITS: usize = 64;

/// CPU time of process `pid`'s (main) thread in ns, from /proc/PID/schedstat.
fn cpu_ns(pid: u32) -> u64 {
    std::fs::read_to_string(format!("/proc/{pid}/schedstat"))
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse().ok())
        .expect("the emulator's scheduler statistics")
}

fn out(cw: u16, target: i32) -> Vec<u8> {
    let mut b = cw.to_le_bytes().to_vec();
    b.extend_from_slice(&target.to_le_bytes());
    b.push(8);
    b
}

fn ok<T>(r: Result<T, master::MasterError>) -> T {
    r.unwrap_or_else(|e| panic!("{e}"))
}

fn u64_of(d: &[u8]) -> u64 {
    u64::from_le_bytes(d[..8].try_into().unwrap())
}

/// CPU time of the calling thread (ns), from /proc/thread-self/schedstat.
fn thread_cpu_ns() -> u64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

/// The same chain in process on a simulated clock (no sockets): the CPU time of one 1 ms cycle
/// (the master's LRW built and read, the frame through the chain, the units' cycle), averaged over
/// `cycles` cycles in csp, from the thread's scheduler statistics.
fn in_process(
    template: &ethercat_slave::generic::Template,
    layouts: &[Layout],
    cycles: i32,
) -> Duration {
    let now = Instant::now();
    let chain = ethercat_slave::generic::chain(
        &[(template, UNITS)],
        &ds402::drive::DriveConfig::default(),
        Duration::from_millis(1),
        now,
    )
    .expect("the chain");
    let mut c = master::SimChain::with_chain(chain, now);
    ok(master::configure_layouts(&mut c, layouts));
    ok(master::request(&mut c, 0x02));
    c.cycle(Duration::from_millis(1));
    ok(master::request(&mut c, 0x04));
    let mut outputs = vec![out(0, 0); UNITS];
    ok(master::lrw_layouts(&mut c, layouts, &outputs));
    ok(master::request(&mut c, 0x08));
    for cw in [0x0006u16, 0x0007, 0x000F] {
        outputs.iter_mut().for_each(|o| *o = out(cw, 0));
        for _ in 0..5 {
            ok(master::lrw_layouts(&mut c, layouts, &outputs));
        }
    }
    let cpu0 = thread_cpu_ns();
    for n in 1..=cycles {
        outputs.iter_mut().for_each(|o| *o = out(0x000F, n));
        let (wkc, inputs) = ok(master::lrw_layouts(&mut c, layouts, &outputs));
        assert_eq!(wkc, 3 * UNITS as u16);
        assert!(inputs.iter().all(|i| i[0] & 0x6F == 0x27));
    }
    Duration::from_nanos((thread_cpu_ns() - cpu0) / cycles as u64)
}

/// The master's one cycle on the link: the reference time distributed (FRMW of 0x0910) and all
/// process data (LRW), both answers checked; the slowest answer kept.
struct Cycle {
    /// Bytes of the LRW: every unit's outputs and inputs.
    total: usize,
    /// Each unit's logical addresses of its outputs and of its inputs.
    offsets: Vec<(u32, u32)>,
    /// The longest a frame took to come back.
    slowest: Duration,
}

impl Cycle {
    fn new(layouts: &[Layout]) -> Cycle {
        Cycle {
            total: layouts.iter().map(|l| l.lengths().0 + l.lengths().1).sum(),
            offsets: master::offsets(layouts),
            slowest: Duration::ZERO,
        }
    }

    /// One cycle with `outputs`: each unit's 15 input bytes.
    fn run(&mut self, w: &mut SocketWire, outputs: &[Vec<u8>]) -> Vec<Vec<u8>> {
        let mut data = vec![0u8; self.total];
        for (k, o) in outputs.iter().enumerate() {
            let at = self.offsets[k].0 as usize;
            data[at..at + o.len()].copy_from_slice(o);
        }
        let dgs = [
            Datagram::new(cmd::FRMW, station(0), 0x0910, vec![0; 8]),
            Datagram {
                cmd: cmd::LRW,
                index: 1,
                address: 0,
                data,
                wkc: 0,
            },
        ];
        let mut frame = emit(&dgs, SRC);
        let t = Instant::now();
        assert!(w.exchange(&mut frame), "an answer to every cycle's frame");
        self.slowest = self.slowest.max(t.elapsed());
        let answer = parse(&frame).expect("the answer parses");
        assert_eq!(
            answer[0].wkc, UNITS as u16,
            "FRMW: read at the reference, written at the others"
        );
        // LRW: inputs read (1) and outputs written (2) per unit, in Safe-Op as in Op (the ESC's
        // SyncManagers take the outputs; the unit acts on them in Op only).
        let want = 3 * UNITS as u16;
        assert_eq!(answer[1].wkc, want, "LRW working counter");
        (0..UNITS)
            .map(|k| {
                let at = self.offsets[k].1 as usize;
                answer[1].data[at..at + 15].to_vec()
            })
            .collect()
    }
}

/// The SyncManager watchdog at 1 s (0x0420 = 10,000 × 100 µs): a master that the machine's other
/// work holds up for more than 100 ms must not end the run.
fn slow_watchdog(w: &mut SocketWire) {
    for k in 0..UNITS {
        ok(master::fpwr(w, k, 0x0420, 10_000u16.to_le_bytes().to_vec()));
    }
}

/// Distributed Clocks: unit 1 is the reference; each unit's offset makes its system time the
/// reference's; SYNC0 every 1 ms from 20 ms on.
fn distributed_clocks(w: &mut SocketWire) {
    let time_of = |w: &mut SocketWire, k: usize| u64_of(&ok(master::fprd(w, k, 0x0910, 8)).0);
    let reference = time_of(w, 0);
    for k in 1..UNITS {
        let local = time_of(w, k);
        let offset = reference.wrapping_sub(local);
        ok(master::fpwr(w, k, 0x0920, offset.to_le_bytes().to_vec()));
    }
    let start = time_of(w, 0) + 20_000_000;
    for k in 0..UNITS {
        ok(master::fpwr(
            w,
            k,
            0x09A0,
            1_000_000u32.to_le_bytes().to_vec(),
        ));
        ok(master::fpwr(w, k, 0x0990, start.to_le_bytes().to_vec()));
        ok(master::fpwr(w, k, 0x0981, vec![0x03]));
    }
}

/// Safe-Op to Op with `outputs` in every cycle, then the drives through Shutdown, Switch on and
/// Enable operation (20 cycles each).
fn into_op(w: &mut SocketWire, cycle: &mut Cycle, outputs: &mut [Vec<u8>]) {
    for _ in 0..10 {
        cycle.run(w, outputs);
        std::thread::sleep(Duration::from_millis(1));
    }
    assert_eq!(ok(master::request(w, 0x08)), UNITS as u16);
    cycle.run(w, outputs);
    for k in 0..UNITS {
        assert_eq!(ok(master::al(w, k)), (0x08, 0), "unit {k} in Op");
    }
    for cw in [0x0006u16, 0x0007, 0x000F] {
        outputs.iter_mut().for_each(|o| *o = out(cw, 0));
        for _ in 0..20 {
            cycle.run(w, outputs);
            std::thread::sleep(Duration::from_millis(1));
        }
    }
}

/// What the measured run gives: its cycles, those started late, its length in seconds.
struct Run {
    cycles: i32,
    late: u64,
    elapsed: f64,
}

/// The measured run: 1 ms cycles on absolute deadlines for `secs` seconds, each drive's target
/// rising 1 count a cycle from 0 (unit k: k + 1 counts).
fn measured_run(w: &mut SocketWire, cycle: &mut Cycle, outputs: &mut [Vec<u8>], secs: f64) -> Run {
    let t0 = Instant::now();
    let mut next = t0;
    let mut cycles = 0i32;
    let mut late = 0u64;
    while t0.elapsed().as_secs_f64() < secs {
        cycles += 1;
        for (k, o) in outputs.iter_mut().enumerate() {
            *o = out(0x000F, cycles * (k as i32 + 1));
        }
        let inputs = cycle.run(w, outputs);
        for (k, i) in inputs.iter().enumerate() {
            let sw = u16::from_le_bytes([i[0], i[1]]);
            assert_eq!(
                sw & 0x206F,
                0x0027,
                "cycle {cycles}: unit {k} statusword {sw:#06x}"
            );
        }
        next += Duration::from_millis(1);
        let now = Instant::now();
        if next > now {
            std::thread::sleep(next - now);
        } else {
            late += 1;
            next = now;
        }
    }
    Run {
        cycles,
        late,
        elapsed: t0.elapsed().as_secs_f64(),
    }
}

/// The targets held: after 300 more cycles every drive at its target of the last cycle exactly.
fn check_targets(w: &mut SocketWire, cycle: &mut Cycle, outputs: &[Vec<u8>], cycles: i32) {
    let mut inputs = Vec::new();
    for _ in 0..300 {
        inputs = cycle.run(w, outputs);
        std::thread::sleep(Duration::from_millis(1));
    }
    for (k, i) in inputs.iter().enumerate() {
        let pos = i32::from_le_bytes(i[2..6].try_into().unwrap());
        let sw = u16::from_le_bytes([i[0], i[1]]);
        let al = ok(master::al(w, k));
        assert_eq!(
            pos,
            cycles * (k as i32 + 1),
            "unit {k} at its target (statusword {sw:#06x}, AL status {al:04x?})"
        );
    }
}

fn main() {
    let bench = std::env::args().any(|a| a == "--bench");
    let secs: f64 = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(if bench { 10.0 } else { 1.0 });
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let template = load(&EsiSpec {
        path: root.join("examples/drive.esi.xml"),
        units: None,
        device: None,
        modules: None,
    })
    .expect("examples/drive.esi.xml");
    let layout = Layout::of(&template);
    assert_eq!(layout.lengths(), (7, 15));
    let layouts = vec![layout; UNITS];
    let per_cycle = in_process(&template, &layouts, if bench { 5000 } else { 500 });
    println!(
        "{UNITS} units in process: {per_cycle:?} of CPU per 1 ms cycle (master's frame, the chain's frame and cycle)"
    );
    let units = format!("examples/drive.esi.xml@{UNITS}");
    let link = Link::node(&["--esi", &units]);
    let pid = link.pid().expect("the emulator runs");
    let socket = RawSocket::open(&link.master).expect("raw socket on the master's end");
    let mut w = SocketWire::new(socket, UNITS);
    // A late answer (a machine shared with other work) is waited for, and its time reported.
    w.timeout = Duration::from_secs(1);
    ok(master::configure_layouts(&mut w, &layouts));
    slow_watchdog(&mut w);
    assert_eq!(ok(master::request(&mut w, 0x02)), UNITS as u16);
    distributed_clocks(&mut w);
    assert_eq!(ok(master::request(&mut w, 0x04)), UNITS as u16);
    for k in 0..UNITS {
        assert_eq!(ok(master::al(&mut w, k)), (0x04, 0), "unit {k} in Safe-Op");
    }
    let mut cycle = Cycle::new(&layouts);
    let mut outputs = vec![out(0, 0); UNITS];
    into_op(&mut w, &mut cycle, &mut outputs);
    cycle.slowest = Duration::ZERO;
    let cpu0 = cpu_ns(pid);
    let Run {
        cycles,
        late,
        elapsed,
    } = measured_run(&mut w, &mut cycle, &mut outputs, secs);
    let cpu = (cpu_ns(pid) - cpu0) as f64 / 1e9;
    let slowest = cycle.slowest;
    check_targets(&mut w, &mut cycle, &outputs, cycles);
    drop(link);
    println!(
        "{UNITS} units, DC (SYNC0 1 ms), 1 ms cycle: {cycles} cycles in {elapsed:.2} s ({late} started late), \
         every answer checked (slowest {slowest:?}); emulator CPU {cpu:.2} s = {:.1} % of one core",
        100.0 * cpu / elapsed
    );
}
