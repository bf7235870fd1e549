//! The emulator's socket path as a master's frames reach it: a raw socket of the test's own on the
//! master's end of a veth pair (see `testkit::link`), `smd-ethercat --units N` on the other end.
//! Valid frames come back processed, with the locally-administered bit set in the source address;
//! malformed ones get no answer and leave the chain untouched; a flood of random frames leaves the
//! emulator running and answering, and its summary line counts what it dropped.
//!
//! Needs root (a network namespace, a veth pair, raw sockets): without it the tests fail and say so.

use std::time::{Duration, Instant};

use ethercat_slave::esc::cmd;
use ethercat_slave::frame::{emit, parse, Datagram, ETHERTYPE};
use ethercat_slave::raw::RawSocket;

use testkit::link;

/// The test master's source address: universally administered (bit 0x02 of its first byte clear),
/// so the emulator's answers are told apart by that bit.
const SRC: [u8; 6] = [0x00, 0x1B, 0x21, 0x5E, 0xCA, 0x7A];
/// How long a frame that must not be answered is waited on.
const SILENCE: Duration = Duration::from_millis(50);
/// How long an answer may take.
const ANSWER: Duration = Duration::from_millis(500);
/// ESC information 0x0000–0x0003 (type, revision, build) as the emulated ESC has it; read-only.
const ESC_INFO: [u8; 4] = [0x11, 0x00, 0x02, 0x00];

/// The test's side of the link.
struct Master {
    sock: RawSocket,
    index: u8,
    /// Frames sent that the emulator must answer, and EtherCAT frames that it must drop.
    valid: u64,
    malformed: u64,
}

impl Master {
    fn open(link: &link::Link) -> Master {
        let sock = RawSocket::open(&link.master)
            .unwrap_or_else(|e| panic!("a raw socket on {} (needs root): {e}", link.master));
        Master {
            sock,
            index: 0,
            valid: 0,
            malformed: 0,
        }
    }

    fn send(&self, frame: &[u8]) {
        self.sock
            .send(frame)
            .unwrap_or_else(|e| panic!("sending a frame of {} bytes: {e}", frame.len()));
    }

    /// The next frame from the emulator (source address ours with bit 0x02 set) within `timeout`.
    fn next_answer(&self, timeout: Duration) -> Option<Vec<u8>> {
        let deadline = Instant::now() + timeout;
        let mut buf = vec![0u8; 9_216];
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() || !self.sock.wait(left).expect("poll") {
                return None;
            }
            while let Some(n) = self.sock.recv(&mut buf).expect("recv") {
                let f = &buf[..n];
                if n >= 14 && f[7..12] == SRC[1..] && f[6] & !0x02 == SRC[0] {
                    return Some(f.to_vec());
                }
            }
        }
    }

    /// Reads frames until none arrives for `quiet`.
    fn drain(&self, quiet: Duration) -> usize {
        let mut n = 0;
        while self.next_answer(quiet).is_some() {
            n += 1;
        }
        n
    }

    /// Sends `d` alone in a frame and returns the answer's datagram, checking the frame came back
    /// from the emulator (locally-administered bit set in the source address).
    fn one(&mut self, mut d: Datagram) -> Datagram {
        self.index = self.index.wrapping_add(1);
        d.index = self.index;
        let (command, address) = (d.cmd, d.address);
        self.send(&emit(&[d], SRC));
        self.valid += 1;
        let deadline = Instant::now() + ANSWER;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            let f = self.next_answer(left).unwrap_or_else(|| {
                panic!("no answer to command {command} at 0x{address:08X} within {ANSWER:?}")
            });
            let Ok(dgs) = parse(&f) else { continue };
            let Some(first) = dgs.into_iter().next() else {
                continue;
            };
            if first.index != self.index || first.cmd != command {
                continue; // a late answer to an earlier frame
            }
            assert_eq!(
                f[6],
                SRC[0] | 0x02,
                "the answer's source address has bit 0x02 of byte 6 set"
            );
            assert_eq!(f[12..14], ETHERTYPE.to_be_bytes(), "the answer is EtherCAT");
            return first;
        }
    }

    /// Sends a frame that must get no answer; `ethercat` says whether the emulator's socket receives
    /// it at all (EtherType 0x88A4), and so counts it as dropped.
    fn silent(&mut self, frame: &[u8], ethercat: bool, what: &str) {
        self.drain(Duration::from_millis(1));
        self.send(frame);
        if ethercat {
            self.malformed += 1;
        }
        if let Some(f) = self.next_answer(SILENCE) {
            panic!(
                "{what}: answered ({} bytes back: {:02X?})",
                f.len(),
                &f[..f.len().min(40)]
            );
        }
    }

    /// A BRD of AL status: every unit answers (working counter `n`); its state byte.
    fn brd_al_status(&mut self, n: usize) -> u8 {
        let r = self.one(Datagram::new(cmd::BRD, 0, 0x0130, vec![0; 2]));
        assert_eq!(usize::from(r.wkc), n, "BRD 0x0130: working counter");
        r.data[0]
    }

    /// An APRD of the ESC information to each position, and one past the end of the chain.
    fn aprd_each(&mut self, n: usize) {
        for k in 0..=n {
            let adp = 0u16.wrapping_sub(k as u16);
            let r = self.one(Datagram::new(cmd::APRD, adp, 0x0000, vec![0; 4]));
            if k < n {
                assert_eq!(r.wkc, 1, "APRD to position {k}: working counter");
                assert_eq!(r.data, ESC_INFO, "APRD to position {k}: ESC information");
            } else {
                assert_eq!(r.wkc, 0, "APRD past the last unit (position {k})");
                assert_eq!(r.data, [0; 4], "APRD past the last unit: data unchanged");
            }
            assert_eq!(
                r.address & 0xFFFF,
                u32::from(adp.wrapping_add(n as u16)),
                "APRD to position {k}: ADP incremented once per unit"
            );
        }
    }
}

/// `(answered, dropped)` from the emulator's log (see [`link::frame_counts`]).
fn frame_counts(log: &str) -> (u64, u64) {
    link::frame_counts(log)
        .unwrap_or_else(|| panic!("no `N frames answered, M dropped` line in the log:\n{log}"))
}

fn root() {
    // SAFETY: geteuid(2) has no preconditions and cannot fail.
    let uid = unsafe { libc::geteuid() };
    assert_eq!(
        uid, 0,
        "the socket tests need root (network namespaces, veth pairs, raw sockets); uid {uid}"
    );
}

/// A BRD of 0x0130 as the emulator receives it: unpadded (30 bytes), so cuts and lengths are exact.
fn brd_frame() -> Vec<u8> {
    let mut f = emit(&[Datagram::new(cmd::BRD, 0, 0x0130, vec![0; 2])], SRC);
    f.truncate(14 + 2 + 10 + 2 + 2);
    f
}

/// Sets the EtherCAT header (length bits 0–10, type bits 12–15) of `f`.
fn header(f: &mut [u8], len: u16, kind: u16) {
    f[14..16].copy_from_slice(&((len & 0x07FF) | (kind << 12)).to_le_bytes());
}

/// SMD-T2-007 on the wire: the first frame the units ever see — a BRD of AL status, with no AL
/// control written before — reads Init on every unit (working counter 2, state 0x01), and the
/// answer comes back with the locally-administered bit set in its source address. Then malformed
/// frames: each is dropped without an answer and without touching the chain, and a valid frame after
/// each is still answered; the emulator's count of dropped frames is exactly the number sent.
#[test]
fn malformed_frames_get_no_answer_and_leave_the_chain_untouched() {
    root();
    const N: usize = 2;
    let mut link = link::Link::up(&["--units", "2"]);
    let mut m = Master::open(&link);
    assert_eq!(m.brd_al_status(N), 0x01, "both units in Init, no error");
    m.aprd_each(N);

    let good = brd_frame();
    let mut cases: Vec<(Vec<u8>, bool, String)> = Vec::new();
    // Cut anywhere before the working counter's last byte: 14 (Ethernet header only) to 29.
    for cut in 14..good.len() {
        cases.push((good[..cut].to_vec(), true, format!("cut at {cut} bytes")));
    }
    // Padded to the Ethernet minimum (as emit does), with the lengths wrong in other ways.
    let padded = emit(&[Datagram::new(cmd::BRD, 0, 0x0130, vec![0; 2])], SRC);
    for kind in [0u16, 2, 3, 4, 5, 0xF] {
        let mut f = padded.clone();
        header(&mut f, 14, kind);
        cases.push((f, true, format!("EtherCAT type {kind}")));
    }
    for (len, what) in [
        (0u16, "EtherCAT header length 0"),
        (
            9,
            "EtherCAT header length 9 (shorter than a datagram header)",
        ),
        (13, "EtherCAT header length 13 (cuts the working counter)"),
        (
            45,
            "EtherCAT header length 45, one more than the frame holds",
        ),
        (0x07FF, "EtherCAT header length 2047 in a 60-byte frame"),
    ] {
        let mut f = padded.clone();
        header(&mut f, len, 1);
        cases.push((f, true, what.to_string()));
    }
    for (header_len, dg_len, what) in [
        (14u16, 3u16, "datagram length 3 past the declared body"),
        (44, 33, "datagram length 33, one past the frame"),
        (44, 0x07FF, "datagram length 2047"),
    ] {
        let mut f = padded.clone();
        header(&mut f, header_len, 1);
        f[22..24].copy_from_slice(&dg_len.to_le_bytes());
        cases.push((f, true, what.to_string()));
    }
    {
        let mut f = padded.clone();
        f[23] |= 0x80; // more follows, but nothing does
        cases.push((f, true, "more-follows on the last datagram".to_string()));
    }
    {
        // A valid write first, then a datagram running past the frame: the whole frame is dropped,
        // the write is not done (checked below: station address still 0).
        let mut f = emit(
            &[
                Datagram::new(cmd::APWR, 0, 0x0010, vec![0x42, 0x42]),
                Datagram::new(cmd::BRD, 0, 0x0130, vec![0; 2]),
            ],
            SRC,
        );
        f.truncate(14 + 2 + 2 * (10 + 2 + 2));
        let len_at = 14 + 2 + 14 + 6; // the second datagram's length field
        f[len_at..len_at + 2].copy_from_slice(&40u16.to_le_bytes());
        cases.push((
            f,
            true,
            "a valid APWR followed by a datagram past the frame".to_string(),
        ));
    }
    for ethertype in [0x0800u16, 0x88A5, 0xA488] {
        let mut f = padded.clone();
        f[12..14].copy_from_slice(&ethertype.to_be_bytes());
        cases.push((f, false, format!("EtherType 0x{ethertype:04X}")));
    }

    let started = Instant::now();
    for (frame, ethercat, what) in &cases {
        m.silent(frame, *ethercat, what);
        assert_eq!(
            m.brd_al_status(N),
            0x01,
            "after {what}: still answered, still Init"
        );
    }
    let silent_s = started.elapsed().as_secs_f64();
    // Nothing of the dropped frames was done: the APWR's station address never arrived.
    for k in 0..N {
        let adp = 0u16.wrapping_sub(k as u16);
        let r = m.one(Datagram::new(cmd::APRD, adp, 0x0010, vec![0xEE; 2]));
        assert_eq!(r.wkc, 1);
        assert_eq!(r.data, [0, 0], "unit {k}: station address untouched");
    }
    m.aprd_each(N);
    assert!(link.running(), "smd-ethercat stopped");
    let log = link.stop();
    let (answered, dropped) = frame_counts(&log);
    assert_eq!(
        (answered, dropped),
        (m.valid, m.malformed),
        "the emulator's (answered, dropped) against the frames sent\n{log}"
    );
    println!(
        "{} malformed or foreign frames unanswered in {silent_s:.2} s; emulator: {answered} answered, \
         {dropped} dropped",
        cases.len()
    );
}

/// A write that runs past the end of the 64 KiB ESC address space does not wrap onto the registers
/// at 0x0000: the read-only ESC information stays, and AL status cannot be written to Op that way
/// (the emulator's memory used to wrap, found by the flood below).
#[test]
fn writes_past_0xffff_do_not_wrap_onto_the_registers() {
    root();
    const N: usize = 2;
    let mut link = link::Link::up(&["--units", "2"]);
    let mut m = Master::open(&link);
    assert_eq!(m.brd_al_status(N), 0x01, "both units in Init");
    // 4 bytes at 0xFFFE: two would land on 0x0000–0x0001 (ESC type and revision).
    m.one(Datagram::new(
        cmd::APWR,
        0,
        0xFFFE,
        vec![0xA1, 0xA2, 0xA3, 0xA4],
    ));
    // 0x146 bytes at 0xFFF0 reach 0x0135 once wrapped: AL status 0x0130 = Op.
    let mut data = vec![0u8; 0x10 + 0x136];
    data[0x10 + 0x130] = 0x08;
    m.one(Datagram::new(cmd::BWR, 0, 0xFFF0, data));
    m.aprd_each(N);
    assert_eq!(m.brd_al_status(N), 0x01, "AL status still Init");
    let r = m.one(Datagram::new(cmd::BRD, 0, 0x0134, vec![0; 2]));
    assert_eq!(r.data, [0, 0], "AL status code untouched");
    assert!(link.running(), "smd-ethercat stopped");
}

/// xorshift64* (Vigna): enough randomness for a flood, and the same frames on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }

    fn byte(&mut self) -> u8 {
        self.next() as u8
    }

    fn fill(&mut self, n: usize) -> Vec<u8> {
        (0..n).map(|_| self.byte()).collect()
    }
}

/// Registers and memory a random datagram is aimed at half of the time: station address, AL
/// control/status, EEPROM, FMMUs, SyncManagers, DC, watchdog, mailboxes and process data.
const TARGETS: [u16; 14] = [
    0x0000, 0x0010, 0x0120, 0x0130, 0x0400, 0x0420, 0x0502, 0x0600, 0x0800, 0x0900, 0x0980, 0x1000,
    0x1080, 0x1100,
];

/// A random EtherCAT frame with a plausible structure: EtherType 0x88A4, a header of type 1 and the
/// right length most of the time, one to four datagrams of any command (and some unknown ones),
/// random data; now and then a wrong header, a wrong datagram length or a cut.
fn random_frame(rng: &mut Rng) -> Vec<u8> {
    let mut f = vec![0xFF; 6];
    f.extend_from_slice(&SRC);
    f.extend_from_slice(&ETHERTYPE.to_be_bytes());
    let datagrams = 1 + rng.below(4) as usize;
    let mut body = Vec::new();
    for k in 0..datagrams {
        let command = if rng.below(8) == 0 {
            rng.byte()
        } else {
            rng.below(15) as u8
        };
        let adp: u16 = match rng.below(4) {
            0 => 0,
            1 => 0u16.wrapping_sub(rng.below(3) as u16),
            2 => 0x1000 + rng.below(3) as u16,
            _ => rng.next() as u16,
        };
        let ado: u16 = if rng.below(2) == 0 {
            TARGETS[rng.below(TARGETS.len() as u64) as usize] + rng.below(0x40) as u16
        } else {
            rng.next() as u16
        };
        let len = if rng.below(16) == 0 {
            rng.below(2048)
        } else {
            rng.below(64)
        } as usize;
        let more = if k + 1 < datagrams { 0x8000u16 } else { 0 };
        let flags = if rng.below(8) == 0 {
            (rng.next() as u16) & 0x7800
        } else {
            0
        };
        body.push(command);
        body.push(rng.byte());
        body.extend_from_slice(&adp.to_le_bytes());
        body.extend_from_slice(&ado.to_le_bytes());
        body.extend_from_slice(&((len as u16 & 0x07FF) | more | flags).to_le_bytes());
        body.extend_from_slice(&rng.fill(2));
        body.extend(rng.fill(len.min(1_600)));
        let wkc = if rng.below(2) == 0 {
            [0, 0]
        } else {
            [rng.byte(), rng.byte()]
        };
        body.extend_from_slice(&wkc);
    }
    let (len, kind) = match rng.below(16) {
        0 => (rng.below(2048) as u16, 1),
        1 => (body.len() as u16, rng.below(16) as u16),
        _ => (body.len() as u16, 1),
    };
    f.extend_from_slice(&((len & 0x07FF) | (kind << 12)).to_le_bytes());
    f.extend(body);
    if rng.below(8) == 0 {
        let cut = 14 + rng.below(f.len() as u64 - 13) as usize;
        f.truncate(cut);
    }
    // The veth's MTU: 1500 bytes after the Ethernet header.
    f.truncate(1_514);
    f
}

/// 20,000 random frames (EtherType 0x88A4, plausible headers, a fixed xorshift seed or
/// `SMD_FLOOD_SEED`), paced so the
/// emulator's socket keeps up: the emulator is still running afterwards, a BRD and an APRD to each
/// position are answered with the right working counters, and its summary line reports frames
/// dropped.
#[test]
fn a_flood_of_random_frames_leaves_the_emulator_answering() {
    root();
    const N: usize = 2;
    const FRAMES: usize = 20_000;
    let mut link = link::Link::up(&["--units", "2"]);
    let mut m = Master::open(&link);
    assert_eq!(m.brd_al_status(N), 0x01, "both units in Init");
    // Another seed for a wider search: SMD_FLOOD_SEED=<u64>.
    let seed = std::env::var("SMD_FLOOD_SEED")
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
        .filter(|&s| s != 0)
        .unwrap_or(0x9E37_79B9_7F4A_7C15);
    let mut rng = Rng(seed);
    let started = Instant::now();
    let mut answers = 0;
    for k in 0..FRAMES {
        m.send(&random_frame(&mut rng));
        if k % 100 == 99 {
            // Pace: let the emulator's socket drain, and ours.
            answers += m.drain(Duration::from_millis(1));
            std::thread::sleep(Duration::from_millis(1));
        }
    }
    answers += m.drain(Duration::from_millis(100));
    let flood_s = started.elapsed().as_secs_f64();
    assert!(
        link.running(),
        "smd-ethercat stopped during the flood:\n{}",
        link.stop()
    );
    // The random writes may have changed states and addresses: only what no write changes is
    // checked — working counters and the read-only ESC information.
    let _ = m.brd_al_status(N);
    m.aprd_each(N);
    assert!(link.running(), "smd-ethercat stopped");
    let log = link.stop();
    let (answered, dropped) = frame_counts(&log);
    assert!(dropped > 0, "no random frame was dropped\n{log}");
    assert!(
        answered >= m.valid,
        "the emulator answered {answered}, fewer than the {} valid frames sent\n{log}",
        m.valid
    );
    assert!(
        answered + dropped <= (FRAMES as u64) + m.valid,
        "the emulator counted more frames than were sent\n{log}"
    );
    println!(
        "{FRAMES} random frames (seed {seed}) in {flood_s:.2} s: {answers} answers seen; emulator: \
         {answered} answered, {dropped} dropped"
    );
}

/// The emulator's raw socket asks for a 16 MiB receive buffer and gets it (as root, past
/// rmem_max): the kernel reports twice the size asked, its bookkeeping included. Opened on the
/// loopback interface only; nothing is sent.
#[test]
fn the_raw_socket_has_a_large_receive_buffer() {
    use ethercat_slave::raw::RECEIVE_BUFFER;
    let socket = RawSocket::open("lo").expect("a raw socket on lo (root)");
    assert_eq!(socket.receive_buffer().unwrap(), 2 * RECEIVE_BUFFER);
}

/// A burst as a master with many frames in flight sends it: 300 frames handed to the kernel 64
/// at a time (`RawSocket::send_batch`, sendmmsg), every third one malformed (cut inside its
/// working counter), the answers taken as they come (`RawSocket::recv_batch`, recvmmsg). The
/// emulator takes such a burst in batches: every valid frame is answered, once, in the order sent
/// — each APRW of unit 0's user RAM (0x0F80) writes its own number and reads the one before it —
/// and every malformed one is dropped and counted, wherever it fell in a batch.
#[test]
fn a_burst_of_frames_is_answered_in_order_and_the_malformed_dropped() {
    use ethercat_slave::raw::Batch;
    root();
    const N: usize = 2;
    const FRAMES: u32 = 300;
    let mut link = link::Link::up(&["--units", "2"]);
    let mut m = Master::open(&link);
    assert_eq!(m.brd_al_status(N), 0x01, "both units in Init");
    let frame = |k: u32| {
        emit(
            &[Datagram::new(
                cmd::APRW,
                0,
                0x0F80,
                k.to_le_bytes().to_vec(),
            )],
            SRC,
        )
    };
    // Unit 0's user RAM starts from 0: the first valid frame reads 0.
    m.one(Datagram::new(cmd::APWR, 0, 0x0F80, vec![0; 4]));
    let mut out = Batch::new(64, 64);
    let mut valid = Vec::new();
    for k in 1..=FRAMES {
        let mut f = frame(k);
        if k % 3 == 0 {
            f.truncate(14 + 2 + 10 + 4 + 1);
            m.malformed += 1;
        } else {
            valid.push(k);
            m.valid += 1;
        }
        assert!(out.push(&f));
        if out.is_full() || k == FRAMES {
            m.sock.send_batch(&out).expect("sendmmsg");
            out.clear();
        }
    }
    let mut answers = Batch::new(Batch::MAX, 2048);
    let mut seen = Vec::new();
    let deadline = Instant::now() + Duration::from_secs(5);
    while seen.len() < valid.len() && Instant::now() < deadline {
        if !m.sock.wait(Duration::from_millis(50)).expect("poll") {
            continue;
        }
        for j in 0..m.sock.recv_batch(&mut answers).expect("recvmmsg") {
            let f = answers.frame(j);
            if f[7..12] != SRC[1..] || f[6] != SRC[0] | 0x02 {
                continue;
            }
            let d = parse(f).expect("an answer parses");
            assert_eq!(d[0].wkc, 3, "APRW at position 0: read and written");
            let wrote = u32::from_le_bytes(d[0].data[..4].try_into().unwrap());
            seen.push(wrote);
        }
    }
    // Each valid frame read the number the valid frame before it wrote (0 for the first).
    let expected: Vec<u32> = std::iter::once(0)
        .chain(valid.iter().copied())
        .take(valid.len())
        .collect();
    assert_eq!(
        seen, expected,
        "the answers, in order, each reading the write before it"
    );
    assert_eq!(m.drain(Duration::from_millis(50)), 0, "no answer more");
    assert!(link.running(), "smd-ethercat stopped");
    let log = link.stop();
    assert_eq!(
        frame_counts(&log),
        (m.valid, m.malformed),
        "the emulator's (answered, dropped) against the frames sent\n{log}"
    );
    assert!(
        !log.contains("could not be sent"),
        "every answer sent, nothing for a dropped frame\n{log}"
    );
}

/// A frame the kernel refuses in the middle of a batch (longer than the link's 1,500-byte MTU):
/// `RawSocket::send_batch` leaves it out, sends the frames before and after it — both answered,
/// once — and reports the refusal (EMSGSIZE).
#[test]
fn a_frame_the_kernel_refuses_leaves_the_rest_of_its_batch_sent() {
    use ethercat_slave::raw::Batch;
    root();
    let mut link = link::Link::up(&["--units", "2"]);
    let mut m = Master::open(&link);
    assert_eq!(m.brd_al_status(2), 0x01, "both units in Init");
    let brd = |index: u8, len: usize| {
        let mut d = Datagram::new(cmd::BRD, 0, 0x0130, vec![0; len]);
        d.index = index;
        emit(&[d], SRC)
    };
    let mut out = Batch::new(3, 2048);
    for f in [brd(0x31, 2), brd(0x32, 1900), brd(0x33, 2)] {
        assert!(out.push(&f));
    }
    let e = m
        .sock
        .send_batch(&out)
        .expect_err("a frame longer than the MTU");
    assert_eq!(e.raw_os_error(), Some(libc::EMSGSIZE), "{e}");
    let mut indices = Vec::new();
    while let Some(f) = m.next_answer(Duration::from_millis(200)) {
        indices.push(parse(&f).expect("an answer parses")[0].index);
    }
    assert_eq!(
        indices,
        [0x31, 0x33],
        "the frames before and after it, once each"
    );
    m.valid += 2;
    let log = link.stop();
    assert_eq!(frame_counts(&log), (m.valid, 0), "{log}");
}

/// `--busy-poll-us`: after answering a frame the emulator keeps polling its socket for that long
/// before it sleeps in the kernel again. 50 frames 5 ms apart with 1 ms of busy polling cost it
/// about 50 ms of CPU time more (its thread's, /proc/PID/schedstat) than without, where it sleeps
/// as soon as the socket is empty.
#[test]
fn busy_polling_goes_on_after_a_frame_is_answered() {
    root();
    let cpu_ms = |link: &link::Link| {
        let pid = link.pid().expect("the emulator runs");
        let stat = std::fs::read_to_string(format!("/proc/{pid}/schedstat")).expect("schedstat");
        let ns: u64 = stat.split_whitespace().next().unwrap().parse().unwrap();
        ns as f64 / 1e6
    };
    let mut spent = Vec::new();
    for spin_us in ["1000", "0"] {
        let link = link::Link::up(&["--units", "1", "--busy-poll-us", spin_us]);
        let mut m = Master::open(&link);
        assert_eq!(m.brd_al_status(1), 0x01);
        std::thread::sleep(Duration::from_millis(50));
        let before = cpu_ms(&link);
        for _ in 0..50 {
            assert_eq!(m.brd_al_status(1), 0x01);
            std::thread::sleep(Duration::from_millis(5));
        }
        spent.push(cpu_ms(&link) - before);
    }
    println!(
        "CPU time for 50 frames: {:.1} ms with busy polling, {:.1} ms without",
        spent[0], spent[1]
    );
    assert!(
        spent[0] > spent[1] + 20.0,
        "CPU time for 50 frames: {:.1} ms with 1 ms of busy polling, {:.1} ms without",
        spent[0],
        spent[1]
    );
}
