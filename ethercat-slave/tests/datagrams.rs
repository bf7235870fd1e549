//! Datagram commands through a chain of emulated ESCs, with the working counters and addresses a real
//! chain gives (ETG.1000.4 §5.4).

mod common;

use std::time::Instant;

use ethercat_slave::esc::{cmd, Chain, STATION_ADDRESS};
use ethercat_slave::frame::{emit, parse, Datagram, FrameError};

const SRC: [u8; 6] = [2, 0, 0, 0, 0, 1];

fn run(chain: &mut Chain, dgs: &[Datagram]) -> Vec<Datagram> {
    let mut f = emit(dgs, SRC);
    chain.handle_frame(Instant::now(), &mut f).unwrap();
    parse(&f).unwrap()
}

/// A master's start-up: count the slaves with BRD (WKC = slaves), give each a station address with
/// APWR by position, then read them back with FPRD.
#[test]
fn count_address_and_read_back() {
    let mut c = Chain::new(3);
    let r = run(&mut c, &[Datagram::new(cmd::BRD, 0, 0x0000, vec![0; 2])]);
    assert_eq!(r[0].wkc, 3, "one per slave");
    assert_eq!(r[0].address & 0xFFFF, 3, "ADP counted up by each slave");
    for k in 0..3u16 {
        let adp = 0u16.wrapping_sub(k);
        let addr = 0x1000 + k;
        let r = run(
            &mut c,
            &[Datagram::new(
                cmd::APWR,
                adp,
                STATION_ADDRESS,
                addr.to_le_bytes().to_vec(),
            )],
        );
        assert_eq!(r[0].wkc, 1, "exactly one slave at position {k}");
    }
    for k in 0..3u16 {
        assert_eq!(c.slaves[usize::from(k)].station_address(), 0x1000 + k);
        let r = run(
            &mut c,
            &[Datagram::new(
                cmd::FPRD,
                0x1000 + k,
                STATION_ADDRESS,
                vec![0; 2],
            )],
        );
        assert_eq!(
            (r[0].wkc, r[0].data.clone()),
            (1, (0x1000 + k).to_le_bytes().to_vec())
        );
    }
    // An address no slave has: WKC 0, data unchanged.
    let r = run(
        &mut c,
        &[Datagram::new(
            cmd::FPRD,
            0x7777,
            STATION_ADDRESS,
            vec![0xAA; 2],
        )],
    );
    assert_eq!((r[0].wkc, r[0].data.clone()), (0, vec![0xAA, 0xAA]));
}

/// Read-write counts 3 (1 read + 2 write); BWR writes every slave; BRD ORs what they hold; several
/// datagrams in one frame are each processed.
#[test]
fn read_write_broadcast_and_several_datagrams() {
    let mut c = Chain::new(2);
    c.slaves[0].store(0x0120, &[0x01]);
    c.slaves[1].store(0x0120, &[0x04]);
    let r = run(&mut c, &[Datagram::new(cmd::BRD, 0, 0x0120, vec![0])]);
    assert_eq!((r[0].wkc, r[0].data[0]), (2, 0x05), "ORed");
    let r = run(
        &mut c,
        &[
            Datagram::new(cmd::BWR, 0, 0x0120, vec![0x02]),
            Datagram::new(cmd::APRW, 0xFFFF, 0x0120, vec![0x08]),
        ],
    );
    assert_eq!(r[0].wkc, 2);
    assert_eq!(
        (r[1].wkc, r[1].data[0]),
        (3, 0x02),
        "read the old, wrote the new"
    );
    assert_eq!(c.slaves[1].load(0x0120, 1), [0x08]);
    assert_eq!(c.slaves[0].load(0x0120, 1), [0x02]);
}

/// ARMW: the addressed slave reads, every other slave writes what it read (here in the user RAM
/// 0x0F80; the DC system time is the usual case, see `dc.rs`).
#[test]
fn armw_distributes_one_slaves_value() {
    let mut c = Chain::new(3);
    c.slaves[0].store(0x0F80, &0x1122_3344u32.to_le_bytes());
    let r = run(&mut c, &[Datagram::new(cmd::ARMW, 0, 0x0F80, vec![0; 4])]);
    assert_eq!(r[0].wkc, 3);
    for s in &c.slaves {
        assert_eq!(s.load(0x0F80, 4), 0x1122_3344u32.to_le_bytes());
    }
}

/// The read-write commands by configured address and broadcast (ETG.1000.4 §5.4): three slaves at
/// 0x1000 … 0x1002 holding 0x01, 0x02, 0x03 at 0x0F80.
/// - FPRW to 0x1001 reads its 0x02 into the frame and writes 0x09 there: WKC 3, the others untouched;
/// - FRMW from 0x1001: the slave before it takes the frame's 0x00, 0x1001 reads its 0x09 into the
///   frame, the slave after takes 0x09: WKC 3;
/// - BRW: each slave ORs its byte into the frame and takes what reached it: 0x10 → slave 0 (then
///   0x10 | 0x00 = 0x10), → slave 1 (0x10 | 0x09 = 0x19), → slave 2 (0x19 | 0x09): WKC 3 × 3.
#[test]
fn configured_and_broadcast_read_write() {
    let mut c = Chain::new(3);
    for k in 0..3u16 {
        c.slaves[usize::from(k)].store(STATION_ADDRESS, &(0x1000 + k).to_le_bytes());
        c.slaves[usize::from(k)].store(0x0F80, &[k as u8 + 1]);
    }
    let mem = |c: &Chain| -> Vec<u8> { c.slaves.iter().map(|s| s.load(0x0F80, 1)[0]).collect() };
    let r = run(
        &mut c,
        &[Datagram::new(cmd::FPRW, 0x1001, 0x0F80, vec![0x09])],
    );
    assert_eq!((r[0].wkc, r[0].data.clone()), (3, vec![0x02]));
    assert_eq!(mem(&c), [0x01, 0x09, 0x03]);
    let r = run(
        &mut c,
        &[Datagram::new(cmd::FRMW, 0x1001, 0x0F80, vec![0x00])],
    );
    assert_eq!((r[0].wkc, r[0].data.clone()), (3, vec![0x09]));
    assert_eq!(mem(&c), [0x00, 0x09, 0x09]);
    let r = run(&mut c, &[Datagram::new(cmd::BRW, 0, 0x0F80, vec![0x10])]);
    assert_eq!((r[0].wkc, r[0].data.clone()), (9, vec![0x19]));
    assert_eq!(mem(&c), [0x10, 0x10, 0x19]);
}

/// What `emit` writes `parse` reads back, field by field: command, index, the 32-bit address (ADP and
/// ADO), data and working counter of each datagram; a short frame is padded to the 60-byte Ethernet
/// minimum.
#[test]
fn emit_and_parse_round_trip() {
    let dgs = vec![
        Datagram {
            cmd: cmd::FPRW,
            index: 0xA5,
            address: 0x1234_5678,
            data: vec![1, 2, 3],
            wkc: 0xBEEF,
        },
        Datagram {
            cmd: cmd::LRD,
            index: 7,
            address: 0x8000_0001,
            data: vec![9; 40],
            wkc: 2,
        },
    ];
    let f = emit(&dgs, SRC);
    assert_eq!(f.len(), 14 + 2 + (10 + 3 + 2) + (10 + 40 + 2));
    assert_eq!(parse(&f).unwrap(), dgs);
    let short = emit(&dgs[..1], SRC);
    assert_eq!(short.len(), 60);
    assert_eq!(short[14 + 2 + 15..], [0; 60 - 31]);
    assert_eq!(parse(&short).unwrap(), dgs[..1]);
}

/// The local clocks a frame meets: each slave further on is 500 ns later (ETG.1000.4 §9.1), on top of
/// its own power-up start: a broadcast latch of the receive times gives slave 1 − slave 0 =
/// 1,000,000,007 (their starts apart) + 500 ns, and slave 2 − slave 1 the same.
#[test]
fn local_clocks_are_one_hop_apart() {
    let mut c = Chain::new(3);
    run(&mut c, &[Datagram::new(cmd::BWR, 0, 0x0900, vec![0; 4])]);
    let t: Vec<u64> = c
        .slaves
        .iter()
        .map(|s| u64::from_le_bytes(s.load(0x0918, 8).try_into().unwrap()))
        .collect();
    assert_eq!(t[1] - t[0], 1_000_000_007 + 500);
    assert_eq!(t[2] - t[1], 1_000_000_007 + 500);
}

/// A mailbox SyncManager is written only when the master's write reaches its last byte (ETG.1000.4
/// §8.2.1): SM0 at 0x1000, 128 bytes, master writes; 127 bytes leave it empty, the 128th fills it
/// (status bit 3), and while it is full even a one-byte write at its first address is refused.
#[test]
fn a_mailbox_fills_with_its_last_byte() {
    let mut c = Chain::new(1);
    run(
        &mut c,
        &[Datagram::new(
            cmd::APWR,
            0,
            0x0800,
            vec![0x00, 0x10, 128, 0, 0x26, 0, 0x01, 0],
        )],
    );
    let status = |c: &mut Chain| run(c, &[Datagram::new(cmd::APRD, 0, 0x0805, vec![0])])[0].data[0];
    let r = run(&mut c, &[Datagram::new(cmd::APWR, 0, 0x1000, vec![7; 127])]);
    assert_eq!(r[0].wkc, 1);
    assert_eq!(status(&mut c) & 0x08, 0, "127 bytes: not full");
    let r = run(&mut c, &[Datagram::new(cmd::APWR, 0, 0x107F, vec![7])]);
    assert_eq!(r[0].wkc, 1);
    assert_eq!(status(&mut c) & 0x08, 0x08, "the last byte: full");
    let r = run(&mut c, &[Datagram::new(cmd::APWR, 0, 0x1000, vec![9])]);
    assert_eq!(r[0].wkc, 0, "full: refused");
    assert_eq!(c.slaves[0].load(0x1000, 1), [7]);
    // A new length is a new configuration: the mailbox is empty again; so is a deactivation.
    run(&mut c, &[Datagram::new(cmd::APWR, 0, 0x0802, vec![64, 0])]);
    assert_eq!(status(&mut c) & 0x08, 0, "reconfigured: empty");
    run(&mut c, &[Datagram::new(cmd::APWR, 0, 0x1000, vec![7; 64])]);
    assert_eq!(status(&mut c) & 0x08, 0x08);
    run(&mut c, &[Datagram::new(cmd::APWR, 0, 0x0806, vec![0])]);
    assert_eq!(status(&mut c) & 0x08, 0, "deactivated: empty");
}

/// A buffered SyncManager the master writes (SM2, 0x64) shows the write event (status bit 0) after
/// every complete write of its buffer, the second as the first.
#[test]
fn an_output_buffer_write_sets_the_write_event() {
    let mut c = Chain::new(1);
    run(
        &mut c,
        &[Datagram::new(
            cmd::APWR,
            0,
            0x0810,
            vec![0x00, 0x11, 4, 0, 0x64, 0, 0x01, 0],
        )],
    );
    assert_eq!(c.slaves[0].outputs_received(), 0);
    for k in 0..2 {
        let r = run(&mut c, &[Datagram::new(cmd::APWR, 0, 0x1100, vec![k; 4])]);
        assert_eq!(r[0].wkc, 1);
        let s = run(&mut c, &[Datagram::new(cmd::APRD, 0, 0x0815, vec![0])]);
        assert_eq!(s[0].data[0] & 0x01, 0x01, "write {k}");
        // Each completed image counts once.
        assert_eq!(c.slaves[0].outputs_received(), u64::from(k) + 1);
    }
    // A write that stops short of the last byte is no new image.
    run(&mut c, &[Datagram::new(cmd::APWR, 0, 0x1100, vec![9; 3])]);
    assert_eq!(c.slaves[0].outputs_received(), 2);
}

/// The system time difference at a chain time that does not move (every frame at one instant): slave
/// 0's local clock is its power-up start, 1,000,000,007 ns. A 32-bit write of the system time compares
/// the low halves only; an 8-byte write compares all 64 bits.
#[test]
fn a_32_bit_system_time_write_compares_the_low_half() {
    let t0 = Instant::now();
    let mut c = Chain::new(1);
    let mut at = |dgs: &[Datagram]| {
        let mut f = emit(dgs, SRC);
        c.handle_frame(t0, &mut f).unwrap();
        parse(&f).unwrap()
    };
    let local: u64 = 1_000_000_007;
    // 1,000 ns ahead in the low half, with a high half that 32 bits do not carry.
    at(&[Datagram::new(
        cmd::APWR,
        0,
        0x0910,
        ((local + 1_000) as u32).to_le_bytes().to_vec(),
    )]);
    let d = at(&[Datagram::new(cmd::APRD, 0, 0x092C, vec![0; 4])]);
    assert_eq!(
        d[0].data,
        (0x8000_0000u32 | 1_000).to_le_bytes(),
        "local smaller by 1,000"
    );
    at(&[Datagram::new(
        cmd::APWR,
        0,
        0x0910,
        ((local - 300) as u32).to_le_bytes().to_vec(),
    )]);
    let d = at(&[Datagram::new(cmd::APRD, 0, 0x092C, vec![0; 4])]);
    assert_eq!(d[0].data, 300u32.to_le_bytes(), "local larger by 300");
    // All 64 bits: 2^32 + 1,000 ahead, held at 0x7FFF_FFFF.
    at(&[Datagram::new(
        cmd::APWR,
        0,
        0x0910,
        ((1u64 << 32) + local + 1_000).to_le_bytes().to_vec(),
    )]);
    let d = at(&[Datagram::new(cmd::APRD, 0, 0x092C, vec![0; 4])]);
    assert_eq!(d[0].data, 0xFFFF_FFFFu32.to_le_bytes());
}

/// A 32-bit system time write compares the low halves also when the local time has a high half
/// (ETG.1000.4 §9.2): 5 s after power-on slave 0's local clock is 5,000,000,000 + 1,000,000,007 =
/// 6,000,000,007 ns = 0x1_65A0_BC07, low half 1,705,032,711. The low half + 1,000 written gives
/// "local smaller by 1,000" (0x8000_03E8), the low half − 300 "larger by 300"; compared with the
/// high half they would differ by about 2^32 (held at 0x7FFF_FFFF).
#[test]
fn a_32_bit_system_time_write_ignores_the_local_high_half() {
    let t0 = Instant::now();
    let mut c = Chain::new(1);
    c.start(t0);
    let t = t0 + std::time::Duration::from_secs(5);
    let mut at = |dgs: &[Datagram]| {
        let mut f = emit(dgs, SRC);
        c.handle_frame(t, &mut f).unwrap();
        parse(&f).unwrap()
    };
    let low: u32 = 1_705_032_711;
    for (written, difference) in [(low + 1_000, 0x8000_03E8u32), (low - 300, 300)] {
        let r = at(&[Datagram::new(
            cmd::APWR,
            0,
            0x0910,
            written.to_le_bytes().to_vec(),
        )]);
        assert_eq!(r[0].wkc, 1);
        let d = at(&[Datagram::new(cmd::APRD, 0, 0x092C, vec![0; 4])]);
        assert_eq!(d[0].data, difference.to_le_bytes(), "{written} written");
    }
}

/// SYNC0 status (0x098E bit 0, ETG.1000.4 §9.3) is set by an event and cleared by the master's read
/// of it: SYNC0 every 1 ms from 1 ms after power-on (slave 0's local clock starts at
/// 1,000,000,007 ns); at 1.5 ms the event at 1 ms has passed. A read of the start time beside it
/// (0x0990, the next event: 1,002,000,007) leaves it: the status reads 0x01, and the next read of it
/// 0x00.
#[test]
fn sync0_status_is_cleared_by_reading_it() {
    let t0 = Instant::now();
    let mut c = Chain::new(1);
    c.start(t0);
    let base: u64 = 1_000_000_007;
    let t = t0 + std::time::Duration::from_micros(1_500);
    let at = |c: &mut Chain, d: Datagram| {
        let mut f = emit(&[d], SRC);
        c.handle_frame(t, &mut f).unwrap();
        parse(&f).unwrap().remove(0)
    };
    for (ado, data) in [
        (0x09A0, 1_000_000u32.to_le_bytes().to_vec()),
        (0x0990, (base + 1_000_000).to_le_bytes().to_vec()),
        (0x0981, vec![0x03]),
    ] {
        assert_eq!(at(&mut c, Datagram::new(cmd::APWR, 0, ado, data)).wkc, 1);
    }
    assert_eq!(c.slaves[0].sync0_passed(), Some(base + 1_000_000));
    let status = |c: &mut Chain| {
        let d = at(c, Datagram::new(cmd::APRD, 0, 0x098E, vec![0]));
        (d.wkc, d.data)
    };
    let next = at(&mut c, Datagram::new(cmd::APRD, 0, 0x0990, vec![0; 8]));
    assert_eq!(next.data, (base + 2_000_000).to_le_bytes());
    assert_eq!(status(&mut c), (1, vec![0x01]), "an event passed");
    assert_eq!(status(&mut c), (1, vec![0x00]), "cleared by the read");
}

/// A frame built by hand: the Ethernet header, an EtherCAT header announcing `body` bytes, then
/// `datagram` (as many bytes of it as given), no padding.
fn raw_frame(body: u16, datagram: &[u8]) -> Vec<u8> {
    let mut f = vec![0xFF; 6];
    f.extend_from_slice(&SRC);
    f.extend_from_slice(&[0x88, 0xA4]);
    f.extend_from_slice(&(0x1000 | body).to_le_bytes());
    f.extend_from_slice(datagram);
    f
}

/// Each datagram's lengths are checked against the body the EtherCAT header announces (ETG.1000.4
/// §5.3): a body that ends right after a datagram's 10-byte header lacks its data and working
/// counter; one 1 or 2 bytes short of the working counter likewise; one that is exact is taken.
#[test]
fn datagram_lengths_against_the_announced_body() {
    let mut c = Chain::new(1);
    // BRD, index 0, ADP 0, ADO 0x0130, 1 data byte, not followed.
    let header = [cmd::BRD.0, 0, 0, 0, 0x30, 0x01, 1, 0, 0, 0];
    let mut whole = header.to_vec();
    whole.extend_from_slice(&[0, 0, 0]);
    for body in [10u16, 11, 12] {
        let mut f = raw_frame(body, &whole[..usize::from(body)]);
        let len = f.len();
        assert_eq!(
            c.handle_frame(Instant::now(), &mut f),
            Err(FrameError::Truncated {
                len,
                what: "a datagram's data and working counter"
            }),
            "body {body}"
        );
    }
    let mut f = raw_frame(9, &header[..9]);
    let len = f.len();
    assert_eq!(
        c.handle_frame(Instant::now(), &mut f),
        Err(FrameError::Truncated {
            len,
            what: "a datagram header"
        })
    );
    let mut f = raw_frame(13, &whole);
    c.handle_frame(Instant::now(), &mut f).unwrap();
    let r = parse(&f).unwrap();
    assert_eq!(
        (r[0].wkc, r[0].data.clone()),
        (1, vec![0x01]),
        "AL status Init"
    );
}

/// A read-write whose write the SyncManager refuses counts the read alone: APRW over the buffer of a
/// SyncManager the master only reads (SM3, buffered, ECAT reads) gives WKC 1 and the buffer's bytes.
#[test]
fn a_read_write_with_the_write_refused_counts_one() {
    let mut c = Chain::new(1);
    run(
        &mut c,
        &[Datagram::new(
            cmd::APWR,
            0,
            0x0818,
            vec![0x00, 0x12, 4, 0, 0x00, 0, 0x01, 0],
        )],
    );
    c.slaves[0].store(0x1200, &[1, 2, 3, 4]);
    let r = run(&mut c, &[Datagram::new(cmd::APRW, 0, 0x1200, vec![9; 4])]);
    assert_eq!((r[0].wkc, r[0].data.clone()), (1, vec![1, 2, 3, 4]));
}

/// The chain's clock: `start` makes its instant time zero, and the time then counts from there; a
/// chain never started takes its first instant as zero.
#[test]
fn chain_time_counts_from_its_start() {
    let t0 = Instant::now();
    let mut c = Chain::new(1);
    c.start(t0);
    c.set_now(t0 + std::time::Duration::from_millis(5));
    assert_eq!(c.time_ns(), 5_000_000);
    let mut later = Chain::new(1);
    later.set_now(t0 + std::time::Duration::from_millis(5));
    assert_eq!(later.time_ns(), 0);
    later.set_now(t0 + std::time::Duration::from_millis(7));
    assert_eq!(later.time_ns(), 2_000_000);
}

/// A malformed or truncated frame is refused with the reason and changes nothing.
#[test]
fn broken_frames_are_dropped() {
    let mut c = Chain::new(1);
    let good = emit(&[Datagram::new(cmd::BWR, 0, 0x0120, vec![9])], SRC);
    // 14 bytes of Ethernet header and 2 of EtherCAT header, then one datagram of 10 + 1 + 2 bytes.
    for (cut, what) in [
        (0, "the Ethernet or EtherCAT header"),
        (10, "the Ethernet or EtherCAT header"),
        (15, "the Ethernet or EtherCAT header"),
        (16, "the datagrams the EtherCAT header announces"),
        (20, "the datagrams the EtherCAT header announces"),
        (28, "the datagrams the EtherCAT header announces"),
    ] {
        let mut f = good[..cut].to_vec();
        assert_eq!(
            c.handle_frame(Instant::now(), &mut f),
            Err(FrameError::Truncated { len: cut, what }),
            "{cut}"
        );
    }
    // A short frame of another EtherType is refused for its type, not its length.
    let mut f = good[..20].to_vec();
    f[12] = 0x08;
    f[13] = 0x06;
    assert_eq!(
        c.handle_frame(Instant::now(), &mut f),
        Err(FrameError::EtherType(0x0806))
    );
    let mut f = good.clone();
    f[12] = 0x08;
    f[13] = 0x00;
    assert_eq!(
        c.handle_frame(Instant::now(), &mut f),
        Err(FrameError::EtherType(0x0800))
    );
    let mut f = good.clone();
    f[15] = 0x20 | (f[15] & 0x0F);
    assert_eq!(
        c.handle_frame(Instant::now(), &mut f),
        Err(FrameError::Type(2))
    );
    assert_eq!(c.slaves[0].load(0x0120, 1), [0], "nothing written");
    // Any bytes: no panic.
    for n in 0..200usize {
        let mut junk: Vec<u8> = (0..n).map(|k| (k * 31 + n) as u8).collect();
        if junk.len() > 15 {
            junk[12] = 0x88;
            junk[13] = 0xA4;
        }
        let _ = c.handle_frame(Instant::now(), &mut junk);
    }
}

/// Configures FMMU 0 of `slave` to map `len` bytes at logical `logical` onto physical `physical`.
fn fmmu(c: &mut Chain, slave: usize, n: u16, logical: u32, len: u16, physical: u16, rw: u8) {
    let mut r = Vec::new();
    r.extend_from_slice(&logical.to_le_bytes());
    r.extend_from_slice(&len.to_le_bytes());
    r.extend_from_slice(&[0, 7]); // start bit 0, end bit 7
    r.extend_from_slice(&physical.to_le_bytes());
    r.extend_from_slice(&[0, rw, 1, 0, 0, 0]); // physical bit 0, type, active
    let adp = 0u16.wrapping_sub(slave as u16);
    let res = run(c, &[Datagram::new(cmd::APWR, adp, 0x0600 + 16 * n, r)]);
    assert_eq!(res[0].wkc, 1);
}

/// LRW over two slaves' process data: each slave's write FMMU takes its outputs, its read FMMU gives
/// its inputs; WKC = 3 per slave.
#[test]
fn logical_read_write_through_fmmus() {
    let mut c = Chain::new(2);
    for s in 0..2 {
        let base = 16 * s as u32;
        fmmu(&mut c, s, 0, base, 4, 0x1100, 0x02); // outputs: master → slave
        fmmu(&mut c, s, 1, base + 4, 4, 0x1200, 0x01); // inputs: slave → master
        c.slaves[s].store(0x1200, &[0xA0 + s as u8; 4]);
    }
    // One LRW over slave 0's image (8 bytes at logical 0).
    let r = run(
        &mut c,
        &[Datagram {
            cmd: cmd::LRW,
            index: 0,
            address: 0,
            data: vec![1, 2, 3, 4, 0, 0, 0, 0],
            wkc: 0,
        }],
    );
    assert_eq!(r[0].wkc, 3, "read 1 + write 2");
    assert_eq!(r[0].data, [1, 2, 3, 4, 0xA0, 0xA0, 0xA0, 0xA0]);
    assert_eq!(c.slaves[0].load(0x1100, 4), [1, 2, 3, 4]);
    assert_eq!(c.slaves[1].load(0x1100, 4), [0; 4], "not mapped there");
    // LRD over both slaves' input areas: WKC 1 each.
    let r = run(
        &mut c,
        &[Datagram {
            cmd: cmd::LRD,
            index: 0,
            address: 4,
            data: vec![0; 20],
            wkc: 0,
        }],
    );
    assert_eq!(r[0].wkc, 2);
    assert_eq!(r[0].data[..4], [0xA0; 4]);
    assert_eq!(r[0].data[16..20], [0xA1; 4]);
    // An area no FMMU maps: WKC 0.
    let r = run(
        &mut c,
        &[Datagram {
            cmd: cmd::LWR,
            index: 0,
            address: 0x9000,
            data: vec![5; 4],
            wkc: 0,
        }],
    );
    assert_eq!(r[0].wkc, 0);
}

/// A logical datagram of `command` at `address` over `data`: (WKC, the data after it).
fn logical(
    c: &mut Chain,
    command: ethercat_slave::frame::CommandCode,
    address: u32,
    data: Vec<u8>,
) -> (u16, Vec<u8>) {
    let r = run(
        c,
        &[Datagram {
            cmd: command,
            index: 0,
            address,
            data,
            wkc: 0,
        }],
    );
    (r[0].wkc, r[0].data.clone())
}

/// Each FMMU acts only in its direction, each logical command only in its own (ETG.1000.4 §5.4.4):
/// LRD through a write-only FMMU reads nothing, LWR through a read-only FMMU writes nothing, and an
/// LWR over both a write and a read FMMU writes (WKC 1) without reading into the frame. An FMMU whose
/// physical area runs past the end of the memory is left out (WKC 0).
#[test]
fn fmmus_and_logical_commands_keep_their_directions() {
    let mut c = Chain::new(1);
    fmmu(&mut c, 0, 0, 0x100, 4, 0x1100, 0x02); // write only
    fmmu(&mut c, 0, 1, 0x200, 4, 0x1200, 0x01); // read only
    c.slaves[0].store(0x1100, &[0x11; 4]);
    c.slaves[0].store(0x1200, &[0x22; 4]);
    assert_eq!(
        logical(&mut c, cmd::LRD, 0x100, vec![0; 4]),
        (0, vec![0; 4])
    );
    assert_eq!(
        c.slaves[0].load(0x1100, 4),
        [0x11; 4],
        "a read writes nothing"
    );
    assert_eq!(
        logical(&mut c, cmd::LWR, 0x200, vec![9; 4]),
        (0, vec![9; 4])
    );
    assert_eq!(c.slaves[0].load(0x1200, 4), [0x22; 4]);
    // 0x100 … 0x103 written, 0x200 … 0x203 not read, in one LWR over both.
    let mut data = vec![7; 0x104];
    data[0x100..].copy_from_slice(&[1, 2, 3, 4]);
    let (wkc, after) = logical(&mut c, cmd::LWR, 0, data.clone());
    assert_eq!((wkc, after.len()), (1, 0x104));
    assert_eq!(after, data, "a write leaves the frame's data");
    assert_eq!(c.slaves[0].load(0x1100, 4), [1, 2, 3, 4]);
    let mut both = vec![0; 0x204];
    both[0x100..0x104].copy_from_slice(&[5, 6, 7, 8]);
    let (wkc, after) = logical(&mut c, cmd::LWR, 0, both.clone());
    assert_eq!(wkc, 1);
    assert_eq!(after, both);
    // Physical 0xFFF0 … 0x1000F does not fit in the 64 KiB; 0xFFFC … 0xFFFF just does.
    fmmu(&mut c, 0, 2, 0x400, 32, 0xFFF0, 0x01);
    assert_eq!(
        logical(&mut c, cmd::LRD, 0x400, vec![0xEE; 32]),
        (0, vec![0xEE; 32])
    );
    fmmu(&mut c, 0, 3, 0x500, 4, 0xFFFC, 0x01);
    c.slaves[0].store(0xFFFC, &[1, 2, 3, 4]);
    assert_eq!(
        logical(&mut c, cmd::LRD, 0x500, vec![0; 4]),
        (1, vec![1, 2, 3, 4])
    );
}

/// A logical datagram's address is its whole 32-bit address field (ETG.1000.4 §5.4), not the low
/// half: FMMU 0 maps logical 0x0001_0000 … 0x0001_0003 onto physical 0x1200 … 0x1203, which hold
/// 0x31 … 0x34.
/// - LRD at 0x0001_0000 reads the four (WKC 1); LRD at 0x0000_0000 finds no FMMU (WKC 0, the frame's
///   0xEE left as they were);
/// - LRD of 4 bytes at 0x0001_0002 starts inside the FMMU: its first two bytes are physical 0x1202 and
///   0x1203 (0x33, 0x34), the last two lie past the FMMU (0xEE);
/// - LRD of 4 bytes at 0x0000_FFFE (ADO 0x0000, ADP 0xFFFE) ends inside it: 0xEE, 0xEE, then physical
///   0x1200 and 0x1201 (0x31, 0x32).
///
/// An FMMU whose activate register (byte 12, ETG.1000.4 Table 57) is 0 maps nothing, though its other
/// registers are set: FMMU 1 for logical 0x300 onto 0x1300 (holding 0x77), read, not activated: LRD
/// at 0x300 gives WKC 0 and the frame's bytes.
#[test]
fn the_logical_address_is_32_bits_and_an_fmmu_maps_only_when_activated() {
    let mut c = Chain::new(1);
    fmmu(&mut c, 0, 0, 0x0001_0000, 4, 0x1200, 0x01);
    c.slaves[0].store(0x1200, &[0x31, 0x32, 0x33, 0x34]);
    assert_eq!(
        logical(&mut c, cmd::LRD, 0x0001_0000, vec![0xEE; 4]),
        (1, vec![0x31, 0x32, 0x33, 0x34])
    );
    assert_eq!(
        logical(&mut c, cmd::LRD, 0x0000_0000, vec![0xEE; 4]),
        (0, vec![0xEE; 4])
    );
    assert_eq!(
        logical(&mut c, cmd::LRD, 0x0001_0002, vec![0xEE; 4]),
        (1, vec![0x33, 0x34, 0xEE, 0xEE])
    );
    assert_eq!(
        logical(&mut c, cmd::LRD, 0x0000_FFFE, vec![0xEE; 4]),
        (1, vec![0xEE, 0xEE, 0x31, 0x32])
    );
    // FMMU 1: logical 0x300, 4 bytes, start bit 0, end bit 7, physical 0x1300 bit 0, read, not
    // activated.
    let inactive = vec![
        0x00, 0x03, 0, 0, 4, 0, 0, 7, 0x00, 0x13, 0, 0x01, 0, 0, 0, 0,
    ];
    let r = run(&mut c, &[Datagram::new(cmd::APWR, 0, 0x0610, inactive)]);
    assert_eq!(r[0].wkc, 1);
    c.slaves[0].store(0x1300, &[0x77; 4]);
    assert_eq!(
        logical(&mut c, cmd::LRD, 0x300, vec![0xEE; 4]),
        (0, vec![0xEE; 4])
    );
}

/// Reads 8 bytes of the SII at `word` as a master does: address, read command, data register.
fn eeprom_read(c: &mut Chain, word: u32) -> Vec<u8> {
    run(
        c,
        &[Datagram::new(
            cmd::APWR,
            0,
            0x0504,
            word.to_le_bytes().to_vec(),
        )],
    );
    run(
        c,
        &[Datagram::new(
            cmd::APWR,
            0,
            0x0502,
            0x0100u16.to_le_bytes().to_vec(),
        )],
    );
    run(c, &[Datagram::new(cmd::APRD, 0, 0x0508, vec![0; 8])])[0]
        .data
        .clone()
}

/// The EEPROM interface: a read command at a word address loads 8 bytes of the SII image; the
/// master reads the SMD's identity words this way.
#[test]
fn eeprom_interface_reads_the_sii_image() {
    let d = common::smd();
    let mut c = Chain::new(1);
    c.slaves[0].sii = od::sii::write(&d, 42).unwrap();
    // Word 0x0008: vendor ID, then product code.
    let data = eeprom_read(&mut c, 8);
    let vendor = u32::from_le_bytes(data[..4].try_into().unwrap());
    let product = u32::from_le_bytes(data[4..].try_into().unwrap());
    assert_eq!(
        (vendor, product),
        (d.identity.vendor_id, d.identity.product_code)
    );
    let status = run(&mut c, &[Datagram::new(cmd::APRD, 0, 0x0502, vec![0; 2])]);
    assert_eq!(
        u16::from_le_bytes([status[0].data[0], status[0].data[1]]) & 0x8000,
        0,
        "not busy"
    );
    // The serial at word 0x000E.
    let data = eeprom_read(&mut c, 0x0E);
    assert_eq!(u32::from_le_bytes(data[..4].try_into().unwrap()), 42);
}

/// Writes beside a DC register do not act on it (ETG.1000.4 §9): the 4 bytes just before the system
/// time (0x090C) and the 8 just after it (0x0918) leave the system time difference (0x092C) at 0, and
/// the 4 bytes after the port 0 receive time (0x0904) latch nothing into 0x0900; the register's own
/// writes then do both.
#[test]
fn writes_beside_a_dc_register_do_not_act_on_it() {
    let mut c = Chain::new(2);
    let read = |c: &mut Chain, at: u16, n: usize| {
        run(c, &[Datagram::new(cmd::APRD, 0, at, vec![0; n])])[0]
            .data
            .clone()
    };
    let write = |c: &mut Chain, at: u16, data: Vec<u8>| {
        let r = run(c, &[Datagram::new(cmd::APWR, 0, at, data)]);
        assert_eq!(r[0].wkc, 1);
    };
    assert_eq!(read(&mut c, 0x092C, 4), [0; 4]);
    write(&mut c, 0x090C, vec![0x55; 4]);
    write(&mut c, 0x0918, vec![0x55; 8]);
    assert_eq!(read(&mut c, 0x092C, 4), [0; 4], "no system-time write");
    let latched = read(&mut c, 0x0900, 4);
    write(&mut c, 0x0904, vec![0; 4]);
    assert_eq!(read(&mut c, 0x0900, 4), latched, "no receive-time latch");
    // The registers themselves: a system time 2^40 ns ahead, a latch of the local time.
    // The difference (ETG.1000.4 §9.2): bit 31 set when the local copy is smaller than the time
    // written, the magnitude held at 0x7FFF_FFFF: 2^40 ns ahead of a local time near 10^9 ns.
    write(&mut c, 0x0910, (1u64 << 40).to_le_bytes().to_vec());
    assert_eq!(read(&mut c, 0x092C, 4), 0xFFFF_FFFFu32.to_le_bytes());
    // 0 written: the local copy is larger by its time since power-up, 1,000,000,007 ns and the few
    // this test has taken: bit 31 clear.
    write(&mut c, 0x0910, 0u64.to_le_bytes().to_vec());
    let behind = u32::from_le_bytes(read(&mut c, 0x092C, 4).try_into().unwrap());
    assert!(
        (1_000_000_007..2_000_000_007).contains(&behind),
        "{behind:#x}"
    );
    write(&mut c, 0x0900, vec![0; 4]);
    assert_ne!(read(&mut c, 0x0900, 4), latched);
}

/// A broadcast read ORs what the slaves hold: two slaves in Init both give AL status 0x0001, which
/// ORed is 0x0001 (an exclusive or would give 0); a station address only one holds comes through.
#[test]
fn a_broadcast_read_ors_the_slaves_values() {
    let mut c = Chain::new(2);
    let r = run(&mut c, &[Datagram::new(cmd::BRD, 0, 0x0130, vec![0; 2])]);
    assert_eq!((r[0].wkc, r[0].data.clone()), (2, vec![0x01, 0x00]));
    run(
        &mut c,
        &[Datagram::new(
            cmd::APWR,
            0,
            STATION_ADDRESS,
            vec![0x34, 0x12],
        )],
    );
    let r = run(
        &mut c,
        &[Datagram::new(cmd::BRD, 0, STATION_ADDRESS, vec![0; 2])],
    );
    assert_eq!(r[0].data, [0x34, 0x12]);
}

/// A master's write over a whole SyncManager's registers, here SM2's at 0x0810, takes its start,
/// length, control and activate bytes, but not the ESC's own status (byte 5) or PDI control (byte 7).
#[test]
fn sync_manager_status_and_pdi_bytes_are_the_escs() {
    let mut c = Chain::new(1);
    let written = vec![0x00, 0x11, 0x04, 0x00, 0x64, 0xFF, 0x01, 0xFF];
    run(&mut c, &[Datagram::new(cmd::APWR, 0, 0x0810, written)]);
    let r = run(&mut c, &[Datagram::new(cmd::APRD, 0, 0x0810, vec![0; 8])]);
    assert_eq!(r[0].data, [0x00, 0x11, 0x04, 0x00, 0x64, 0x00, 0x01, 0x00]);
}

/// APWR of `data` at `ado` of the one slave: the working counter.
fn apwr(c: &mut Chain, ado: u16, data: Vec<u8>) -> u16 {
    run(c, &[Datagram::new(cmd::APWR, 0, ado, data)])[0].wkc
}

/// APRD of `len` bytes at `ado` of the one slave (zeros sent): the working counter and the data.
fn aprd(c: &mut Chain, ado: u16, len: usize) -> (u16, Vec<u8>) {
    let r = run(c, &[Datagram::new(cmd::APRD, 0, ado, vec![0; len])]);
    (r[0].wkc, r[0].data.clone())
}

/// One slave with the two mailboxes a master configures (ETG.1000.4 §6.7.2): SM0 at 0x1000 and SM1
/// at 0x1080, 16 bytes each, mailbox mode, written by the master (control 0x26) and read by it
/// (0x22), activated.
fn mailboxes() -> Chain {
    let mut c = Chain::new(1);
    assert_eq!(
        apwr(&mut c, 0x0800, vec![0x00, 0x10, 16, 0, 0x26, 0, 0x01, 0]),
        1
    );
    assert_eq!(
        apwr(&mut c, 0x0808, vec![0x80, 0x10, 16, 0, 0x22, 0, 0x01, 0]),
        1
    );
    c
}

/// The status byte of each mailbox SyncManager (ETG.1000.4 §6.7.2: bit 0 write event, bit 1 read
/// event, bit 3 mailbox full) after the master's accesses, in two exchanges one after the other: SM0
/// (0x0805) reads 0x09, written and full, after each request the master writes whole; SM1 (0x080D)
/// 0x02, read and empty, after each answer it reads whole. In between the application takes the
/// request and puts the answer.
#[test]
fn mailbox_status_bytes_through_two_exchanges() {
    let mut c = mailboxes();
    for k in 1..=2u8 {
        assert_eq!(apwr(&mut c, 0x1000, vec![k; 16]), 1);
        assert_eq!(aprd(&mut c, 0x0805, 1), (1, vec![0x09]), "request {k}");
        assert_eq!(c.slaves[0].take_mailbox(), Some(vec![k; 16]));
        assert!(c.slaves[0].put_mailbox(&[0xA0 + k; 16]));
        assert_eq!(aprd(&mut c, 0x1080, 16), (1, vec![0xA0 + k; 16]));
        assert_eq!(aprd(&mut c, 0x080D, 1), (1, vec![0x02]), "answer {k}");
    }
}

/// The application's mailbox fits SM1 or is refused (the master reads SM1's whole length, ETG.1000.4
/// §6.7): with SM1 of 16 bytes, 17 bytes are refused and SM1 stays empty (status 0x00, the master's
/// read refused: WKC 0); 16 bytes are taken whole; 5 bytes are padded with 11 zeros.
#[test]
fn a_mailbox_longer_than_sm1_is_refused() {
    let mut c = mailboxes();
    assert!(!c.slaves[0].put_mailbox(&[0x55; 17]));
    assert_eq!(aprd(&mut c, 0x080D, 1), (1, vec![0x00]));
    assert_eq!(aprd(&mut c, 0x1080, 16), (0, vec![0; 16]));
    let whole: Vec<u8> = (1..=16).collect();
    assert!(c.slaves[0].put_mailbox(&whole));
    assert_eq!(aprd(&mut c, 0x1080, 16), (1, whole));
    assert!(c.slaves[0].put_mailbox(&[7; 5]));
    assert_eq!(
        aprd(&mut c, 0x1080, 16),
        (1, vec![7, 7, 7, 7, 7, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0])
    );
}

/// The application's mailbox goes only into an activated SyncManager (activate bit 0, ETG.1000.4
/// §6.7.2): with SM1 configured but its activate byte 0x00, the put is refused and SM1's status and
/// memory stay as they were (0x00; the master reads the memory, which nothing guards now, as 16
/// zeros with WKC 1). Once the master activates SM1 the same put is taken and read.
#[test]
fn no_mailbox_goes_into_a_sync_manager_not_activated() {
    let mut c = mailboxes();
    assert_eq!(apwr(&mut c, 0x080E, vec![0x00]), 1);
    assert!(!c.slaves[0].put_mailbox(&[0x42; 16]));
    assert_eq!(aprd(&mut c, 0x080D, 1), (1, vec![0x00]));
    assert_eq!(aprd(&mut c, 0x1080, 16), (1, vec![0; 16]));
    assert_eq!(apwr(&mut c, 0x080E, vec![0x01]), 1);
    assert!(c.slaves[0].put_mailbox(&[0x42; 16]));
    assert_eq!(aprd(&mut c, 0x1080, 16), (1, vec![0x42; 16]));
}

/// The mailbox repeat (ETG.1000.4 §6.7.2): the master toggles SM1's repeat request (activate bit 1,
/// 0x080E); the slave puts its last answer into SM1 again and sets the acknowledgement (PDI control
/// bit 1, 0x080F) to the request. Read as the two bytes 0x080E/0x080F:
/// - answer A read, SM1 empty (a second read refused); request 1: 0x03, 0x02 and A read once more;
/// - the activate byte written again as it is (0x03): no new request, still 0x03, 0x02, and SM1 stays
///   empty;
/// - request 0: 0x01, 0x00 and A read a third time;
/// - answer B put and not read, request 1 while SM1 is full: 0x03, 0x02 and SM1 still full with B;
/// - the repeat request of SM0, the mailbox the master writes, puts nothing into it: SM0 takes the
///   master's next request (WKC 1) and the application gets it.
#[test]
fn a_repeat_request_puts_the_last_answer_back_and_is_acknowledged() {
    let mut c = mailboxes();
    let a: Vec<u8> = (0xA0..0xB0).collect();
    assert!(c.slaves[0].put_mailbox(&a));
    assert_eq!(aprd(&mut c, 0x1080, 16), (1, a.clone()));
    assert_eq!(aprd(&mut c, 0x1080, 16).0, 0, "read: empty");
    let request = |c: &mut Chain, activate: u8| {
        assert_eq!(apwr(c, 0x080E, vec![activate]), 1);
        aprd(c, 0x080E, 2)
    };
    assert_eq!(request(&mut c, 0x03), (1, vec![0x03, 0x02]));
    assert_eq!(aprd(&mut c, 0x1080, 16), (1, a.clone()), "A again");
    assert_eq!(request(&mut c, 0x03), (1, vec![0x03, 0x02]), "unchanged");
    assert_eq!(aprd(&mut c, 0x1080, 16).0, 0, "nothing repeated");
    assert_eq!(request(&mut c, 0x01), (1, vec![0x01, 0x00]));
    assert_eq!(aprd(&mut c, 0x1080, 16), (1, a), "A a third time");
    assert!(c.slaves[0].put_mailbox(&[0xB5; 16]));
    assert_eq!(request(&mut c, 0x03), (1, vec![0x03, 0x02]));
    assert_eq!(aprd(&mut c, 0x1080, 16), (1, vec![0xB5; 16]), "B, full");
    assert_eq!(apwr(&mut c, 0x0806, vec![0x03]), 1);
    assert_eq!(apwr(&mut c, 0x1000, vec![1; 16]), 1, "SM0 empty");
    assert_eq!(c.slaves[0].take_mailbox(), Some(vec![1; 16]));
}

/// A master's write of a SyncManager's registers that leaves its configuration as it was (start,
/// length, control, activate bit 0) keeps the ESC's status byte, whatever byte 5 the master writes
/// (ETG.1000.4 §6.7.2: status is the ESC's), and the mailbox: SM0 full with a request (0x09) written
/// again with its configuration and status 0x00 reads back with status 0x09, refuses the next
/// request (WKC 0), and the application gets the first.
#[test]
fn writing_a_sync_manager_again_as_it_is_keeps_its_mailbox() {
    let mut c = mailboxes();
    assert_eq!(apwr(&mut c, 0x1000, vec![3; 16]), 1);
    let same = vec![0x00, 0x10, 16, 0, 0x26, 0x00, 0x01, 0x00];
    assert_eq!(apwr(&mut c, 0x0800, same), 1);
    assert_eq!(
        aprd(&mut c, 0x0800, 8),
        (1, vec![0x00, 0x10, 16, 0, 0x26, 0x09, 0x01, 0x00])
    );
    assert_eq!(apwr(&mut c, 0x1000, vec![4; 16]), 0, "still full");
    assert_eq!(c.slaves[0].take_mailbox(), Some(vec![3; 16]));
}

/// A SyncManager covers [start, start + length) (ETG.1000.4 §6.7); of length 0 it covers no byte and
/// guards nothing: SM2 activated at 0x1100 with length 0, buffered and read by the master (control
/// 0x00, which refuses the master's writes to what it covers), lets a 4-byte write across 0x1100
/// (0x10FE … 0x1101) through: WKC 1, the bytes in memory. With length 4 it guards 0x1100 … 0x1103
/// and the same write is refused: WKC 0, memory as it was.
#[test]
fn a_sync_manager_of_length_zero_guards_nothing() {
    let mut c = Chain::new(1);
    assert_eq!(
        apwr(&mut c, 0x0810, vec![0x00, 0x11, 0, 0, 0x00, 0, 0x01, 0]),
        1
    );
    assert_eq!(apwr(&mut c, 0x10FE, vec![1, 2, 3, 4]), 1);
    assert_eq!(c.slaves[0].load(0x10FE, 4), [1, 2, 3, 4]);
    assert_eq!(apwr(&mut c, 0x0812, vec![4, 0]), 1);
    assert_eq!(apwr(&mut c, 0x10FE, vec![5, 6, 7, 8]), 0);
    assert_eq!(c.slaves[0].load(0x10FE, 4), [1, 2, 3, 4]);
}

/// An EEPROM write (command 0x02 with write enable, ETG.1000.4 §6.4) of the image's last word takes
/// it; one word past the end is refused with the error bit 0x2000 and changes nothing.
#[test]
fn eeprom_writes_up_to_the_last_word() {
    let d = common::smd();
    let mut c = Chain::new(1);
    c.slaves[0].sii = od::sii::write(&d, 42).unwrap();
    let image = c.slaves[0].sii.clone();
    let words = (image.len() / 2) as u32;
    let write = |c: &mut Chain, word: u32| {
        run(
            c,
            &[Datagram::new(
                cmd::APWR,
                0,
                0x0504,
                word.to_le_bytes().to_vec(),
            )],
        );
        run(c, &[Datagram::new(cmd::APWR, 0, 0x0508, vec![0xAB, 0xCD])]);
        run(
            c,
            &[Datagram::new(
                cmd::APWR,
                0,
                0x0502,
                0x0201u16.to_le_bytes().to_vec(),
            )],
        );
        let status = run(c, &[Datagram::new(cmd::APRD, 0, 0x0502, vec![0; 2])]);
        u16::from_le_bytes([status[0].data[0], status[0].data[1]])
    };
    assert_eq!(write(&mut c, words) & 0x2000, 0x2000, "past the end");
    assert_eq!(c.slaves[0].sii, image);
    assert_eq!(write(&mut c, words - 1) & 0x2000, 0);
    let mut expected = image.clone();
    let n = expected.len();
    expected[n - 2..].copy_from_slice(&[0xAB, 0xCD]);
    assert_eq!(c.slaves[0].sii, expected);
    assert_eq!(&eeprom_read(&mut c, words - 1)[..2], [0xAB, 0xCD]);
}

/// The DL status (0x0110) of each slave of a chain of three: PDI operational, link and communication on
/// port 0, and on port 1 where a slave follows (0x5A31); the last one's port 1 is closed (0x5611).
#[test]
fn dl_status_shows_where_the_chain_ends() {
    let mut c = Chain::new(3);
    for (k, expected) in [(0u16, 0x5A31u16), (1, 0x5A31), (2, 0x5611)] {
        let r = run(
            &mut c,
            &[Datagram::new(
                cmd::APRD,
                0u16.wrapping_sub(k),
                0x0110,
                vec![0; 2],
            )],
        );
        assert_eq!(
            (r[0].wkc, r[0].data.clone()),
            (1, expected.to_le_bytes().to_vec()),
            "slave {k}"
        );
    }
    assert_eq!(format!("{:?}", c.slaves[2]), "Esc { station_address: 0 }");
}

/// A flood of 100,000 random frames (EtherCAT-typed, random datagrams, random lengths) leaves the
/// chain answering a valid frame exactly.
#[test]
fn a_flood_of_random_frames_leaves_the_chain_answering() {
    let mut c = Chain::new(3);
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    for _ in 0..100_000 {
        let len = (next() % 120) as usize;
        let mut f: Vec<u8> = (0..len).map(|_| next() as u8).collect();
        if f.len() >= 16 {
            f[12] = 0x88;
            f[13] = 0xA4;
            f[15] = (f[15] & 0x07) | 0x10;
        }
        let _ = c.handle_frame(Instant::now(), &mut f);
    }
    let r = run(&mut c, &[Datagram::new(cmd::BRD, 0, 0x0000, vec![0; 2])]);
    assert_eq!(r[0].wkc, 3);
}

/// The commands of ETG.1000.4 Table 14 by number and name; a byte the table does not define is
/// shown as its number.
#[test]
fn commands_by_number_and_name() {
    use ethercat_slave::esc::CommandCode;
    let names = [
        "NOP", "APRD", "APWR", "APRW", "FPRD", "FPWR", "FPRW", "BRD", "BWR", "BRW", "LRD", "LWR",
        "LRW", "ARMW", "FRMW",
    ];
    assert_eq!(CommandCode::ALL.len(), names.len());
    for (n, (c, name)) in CommandCode::ALL.iter().zip(names).enumerate() {
        assert_eq!(c.0 as usize, n);
        assert_eq!(c.name(), Some(name));
        assert_eq!(c.to_string(), name);
    }
    assert_eq!(CommandCode(15).name(), None);
    assert_eq!(CommandCode(0x2A).to_string(), "command 0x2A");
}

/// Process data through SyncManagers in mailbox mode (one buffer, ETG.1000.4 §6.7.2), as an ESI's
/// `Inputs` with control byte 0x22 asks, beside the two mailboxes: SM3 at 0x1100, 4 bytes, read by
/// the master (0x22); SM2 at 0x1180, 2 bytes, written by it (0x26).
/// - Inputs: the application's first put fills SM3 (status 0x08) and is read once (WKC 1, then
///   status 0x02 and a second read refused: WKC 0); a put while full changes nothing; the next put
///   after the read is read.
/// - Outputs: the master's write fills SM2 (status 0x09) and is a new output image; a second write
///   before the application took the first is refused (WKC 0, memory unchanged); once released, the
///   next write is taken and counts as the second image.
/// - Neither is the mailbox: a put_mailbox still goes to SM1 and take_mailbox reads SM0 only;
///   inputs put at SM1's address do not fill it, and releasing outputs at SM0's does not empty it.
#[test]
fn process_data_through_sync_managers_in_mailbox_mode() {
    let mut c = mailboxes();
    assert_eq!(
        apwr(&mut c, 0x0818, vec![0x00, 0x11, 4, 0, 0x22, 0, 0x01, 0]),
        1
    );
    assert_eq!(
        apwr(&mut c, 0x0810, vec![0x80, 0x11, 2, 0, 0x26, 0, 0x01, 0]),
        1
    );
    assert!(c.slaves[0].put_inputs(0x1100, &[1, 2, 3, 4]));
    assert_eq!(aprd(&mut c, 0x081D, 1), (1, vec![0x08]));
    assert!(!c.slaves[0].put_inputs(0x1100, &[9, 9, 9, 9]));
    assert_eq!(aprd(&mut c, 0x1100, 4), (1, vec![1, 2, 3, 4]));
    assert_eq!(aprd(&mut c, 0x081D, 1), (1, vec![0x02]));
    assert_eq!(aprd(&mut c, 0x1100, 4), (0, vec![0; 4]));
    assert!(c.slaves[0].put_inputs(0x1100, &[5, 6, 7, 8]));
    assert_eq!(aprd(&mut c, 0x1100, 4), (1, vec![5, 6, 7, 8]));

    let images = c.slaves[0].outputs_received();
    assert_eq!(apwr(&mut c, 0x1180, vec![0xA1, 0xA2]), 1);
    assert_eq!(aprd(&mut c, 0x0815, 1), (1, vec![0x09]));
    assert_eq!(c.slaves[0].outputs_received(), images + 1);
    assert_eq!(apwr(&mut c, 0x1180, vec![0xB1, 0xB2]), 0);
    assert_eq!(c.slaves[0].load(0x1180, 2), [0xA1, 0xA2]);
    assert_eq!(c.slaves[0].outputs_received(), images + 1);
    c.slaves[0].release_outputs(0x1180);
    assert_eq!(aprd(&mut c, 0x0815, 1), (1, vec![0x01]));
    assert_eq!(apwr(&mut c, 0x1180, vec![0xB1, 0xB2]), 1);
    assert_eq!(c.slaves[0].load(0x1180, 2), [0xB1, 0xB2]);
    assert_eq!(c.slaves[0].outputs_received(), images + 2);

    assert_eq!(c.slaves[0].take_mailbox(), None);
    assert!(c.slaves[0].put_mailbox(&[0x42; 16]));
    assert_eq!(aprd(&mut c, 0x1080, 16), (1, vec![0x42; 16]));
    assert!(c.slaves[0].put_inputs(0x1080, &[0x43; 16]));
    assert_eq!(aprd(&mut c, 0x080D, 1), (1, vec![0x02]));
    assert_eq!(apwr(&mut c, 0x1000, vec![0x44; 16]), 1);
    assert_eq!(c.slaves[0].outputs_received(), images + 2);
    c.slaves[0].release_outputs(0x1000);
    assert_eq!(c.slaves[0].take_mailbox(), Some(vec![0x44; 16]));
}

/// A logical write over part of an FMMU's range is gated as that part alone (ETG.1000.4 §6.7): one
/// that stops short of the last byte of the buffered output SyncManager under the FMMU is no new
/// output image, one that reaches it is, and so is a write of the whole range. Where an FMMU's
/// range runs on into a buffer the master only reads (SM3), a write of the whole range is refused
/// (working counter 0, nothing written) and a write of the part before that buffer is taken.
#[test]
fn a_logical_write_over_part_of_an_fmmu_is_gated_as_that_part() {
    let mut c = Chain::new(1);
    let sm = |c: &mut Chain, n: u16, start: u16, control: u8| {
        let mut r = start.to_le_bytes().to_vec();
        r.extend_from_slice(&[4, 0, control, 0, 0x01, 0]);
        run(c, &[Datagram::new(cmd::APWR, 0, 0x0800 + 8 * n, r)]);
    };
    sm(&mut c, 2, 0x1100, 0x64);
    sm(&mut c, 3, 0x1200, 0x20);
    fmmu(&mut c, 0, 0, 0x100, 4, 0x1100, 0x02);
    fmmu(&mut c, 0, 1, 0x200, 8, 0x11FC, 0x03);
    let images = |c: &Chain| c.slaves[0].outputs_received();
    assert_eq!(logical(&mut c, cmd::LWR, 0x100, vec![1; 3]).0, 1);
    assert_eq!(images(&c), 0, "short of SM2's last byte: no new image");
    assert_eq!(c.slaves[0].load(0x0815, 1), [0], "no write event");
    assert_eq!(logical(&mut c, cmd::LWR, 0x101, vec![2; 3]).0, 1);
    assert_eq!(images(&c), 1, "up to SM2's last byte: a new image");
    assert_eq!(logical(&mut c, cmd::LWR, 0x100, vec![3; 4]).0, 1);
    assert_eq!(images(&c), 2, "the whole range: a new image");
    assert_eq!(c.slaves[0].load(0x1100, 4), [3; 4]);

    assert_eq!(
        logical(&mut c, cmd::LWR, 0x200, vec![4; 8]).0,
        0,
        "into SM3: refused"
    );
    assert_eq!(c.slaves[0].load(0x11FC, 8), [0; 8]);
    assert_eq!(
        logical(&mut c, cmd::LWR, 0x200, vec![5; 4]).0,
        1,
        "before SM3: taken"
    );
    assert_eq!(c.slaves[0].load(0x11FC, 8), [5, 5, 5, 5, 0, 0, 0, 0]);
}
