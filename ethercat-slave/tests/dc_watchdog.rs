//! Distributed Clocks, SYNC0 and the SyncManager watchdog of the emulated SMD units, as a master
//! configures and sees them.

mod common;

use std::time::Duration;

use common::master::*;
use ds402::smd::indexer::{cmd0, stat0, stat1, Outputs};
use ethercat_slave::esc::al::state;
use ethercat_slave::esc::cmd;
use ethercat_slave::esc::dc::HOP_NS;
use ethercat_slave::master::SimChain;
use ethercat_slave::smd::binding::Device;

fn u64_of(d: &[u8]) -> u64 {
    u64::from_le_bytes(d[..8].try_into().unwrap())
}

fn u32_of(d: &[u8]) -> u32 {
    u32::from_le_bytes(d[..4].try_into().unwrap())
}

/// SMD-R1-023: the ESC supports Distributed Clocks — feature bits, receive-time latch on every
/// port, system time with the master's offset, and the system-time difference after the master's
/// ARMW distribution of the reference clock; the ESI declares DC with a SYNC0 mode.
#[test]
fn smd_r1_023_dc_registers_latch_and_propagate_time() {
    let desc = ethercat_slave::smd::description(Device::Smd23kB).unwrap();
    let modes = &desc.ethercat.as_ref().unwrap().op_modes;
    assert!(modes
        .iter()
        .any(|m| m.name == "DC_Synchron" && m.assign_activate == 0x0300));
    let mut c = SimChain::new(Device::Smd23kB, 3).unwrap();
    configure(&mut c);
    // ESC features: DC (bit 2) with 64-bit system time (bit 3).
    for k in 0..3 {
        assert_eq!(fprd(&mut c, k, 0x0008, 2).0[0] & 0x0C, 0x0C);
    }
    c.advance(Duration::from_millis(10));
    assert_eq!(reg(&mut c, cmd::BWR, 0, 0x0900, vec![0; 4]).wkc, 3);
    let mut port0 = Vec::new();
    for k in 0..3 {
        let (r, _) = fprd(&mut c, k, 0x0900, 16);
        let (p0, p1) = (u32_of(&r[0..]), u32_of(&r[4..]));
        let pu = u64_of(&fprd(&mut c, k, 0x0918, 8).0);
        assert_eq!(pu as u32, p0, "0x0918 is the port-0 time in 64 bits");
        // The frame comes back through port 1 after the slaves behind it: 2 hops each.
        let back = if k < 2 {
            2 * (2 - k as u64) * HOP_NS
        } else {
            0
        };
        if k < 2 {
            assert_eq!(u64::from(p1.wrapping_sub(p0)), back, "unit {k} port 1");
        } else {
            assert_eq!(p1, 0, "the last unit's port 1 is closed");
        }
        port0.push(pu);
    }
    // Each local clock started at its own time: the master sets offsets so that every system time
    // reads the reference's (unit 0) time at the frame's passage.
    for (k, p) in port0.iter().enumerate() {
        let offset = port0[0].wrapping_sub(*p).wrapping_add(k as u64 * HOP_NS);
        fpwr(&mut c, k, 0x0920, offset.to_le_bytes().to_vec());
    }
    let reference = u64_of(&fprd(&mut c, 0, 0x0910, 8).0);
    for k in 0..3 {
        let st = u64_of(&fprd(&mut c, k, 0x0910, 8).0);
        // The frame reaches unit k k hops after unit 0.
        assert_eq!(st, reference + k as u64 * HOP_NS, "unit {k} system time");
    }
    // ARMW: unit 0 reads its system time, the others compare theirs with it.
    let r = reg(&mut c, cmd::ARMW, 0, 0x0910, vec![0; 8]);
    assert_eq!(r.wkc, 3);
    assert_eq!(u64_of(&r.data), reference);
    for k in 1..3 {
        let diff = u32_of(&fprd(&mut c, k, 0x092C, 4).0);
        assert_eq!(
            u64::from(diff),
            k as u64 * HOP_NS,
            "unit {k}: local copy ahead"
        );
        // The write did not set the clock.
        assert_eq!(
            u64_of(&fprd(&mut c, k, 0x0910, 8).0),
            reference + k as u64 * HOP_NS
        );
    }
}

/// Starts SYNC0 on unit k with `cycle` ns, first event `start_in` ns after its present system time;
/// the first event's system time.
fn start_sync0(c: &mut SimChain, k: usize, cycle: u32, start_in: i64) -> u64 {
    fpwr(c, k, 0x0981, vec![0]);
    let now = u64_of(&fprd(c, k, 0x0910, 8).0);
    let start = now.wrapping_add_signed(start_in);
    fpwr(c, k, 0x0990, start.to_le_bytes().to_vec());
    fpwr(c, k, 0x09A0, cycle.to_le_bytes().to_vec());
    fpwr(c, k, 0x0981, vec![0x03]);
    start
}

/// SMD-T3-003: SYNC0 cycles of 2 ms and 50 ms are accepted; 1 ms and 51 ms are refused at
/// Pre-Op → Safe-Op with AL status code 0x0036 (the catalogue's pick); SMD-T3-002: SYNC0 only
/// (SYNC1 off) reaches Op.
#[test]
fn smd_t3_003_sync0_cycle_between_2_and_50_ms() {
    for (cycle, accepted) in [
        (2_000_000u32, true),
        (50_000_000, true),
        (1_000_000, false),
        (1_999_999, false),
        (51_000_000, false),
    ] {
        let mut c = SimChain::new(Device::Smd23kB, 1).unwrap();
        bring_up(&mut c, state::PREOP);
        start_sync0(&mut c, 0, cycle, 1_000_000);
        request(&mut c, state::SAFEOP);
        if accepted {
            assert_eq!(al(&mut c, 0), (0x0004, 0), "{cycle} ns");
            lrw(&mut c, &[Outputs::default()]);
            request(&mut c, state::OP);
            assert_eq!(al(&mut c, 0), (0x0008, 0), "SMD-T3-002: Op with SYNC0 only");
        } else {
            assert_eq!(al(&mut c, 0), (0x0012, 0x0036), "{cycle} ns refused");
        }
    }
}

/// Brings one unit to Op with SYNC0 running (2 ms, first event 3 ms ahead), the driver enabled and
/// the position preset; CFG_Word_1 = `cfg1` (by SDO in Pre-Op). The first SYNC0 event's system time.
fn op_with_sync0(c: &mut SimChain, cfg1: u16) -> (u64, Outputs) {
    bring_up(c, state::PREOP);
    download(c, 0, 0x8010, 2, &cfg1.to_le_bytes(), false).unwrap();
    request(c, state::SAFEOP);
    assert_eq!(al(c, 0), (0x0004, 0));
    lrw(c, &[Outputs::default()]);
    request(c, state::OP);
    let mut o = Outputs {
        cmd1: 0x8000,
        velocity: 10_000,
        acceleration: 100,
        deceleration: 100,
        cmd0: cmd0::PRESET_POSITION,
        ..Outputs::default()
    };
    for _ in 0..3 {
        lrw(c, &[o]);
    }
    o.cmd0 = 0;
    for _ in 0..3 {
        lrw(c, &[o]);
    }
    let first = start_sync0(c, 0, 2_000_000, 3_000_000);
    (first, o)
}

/// Sends a Relative move, then runs the chain in 20 µs steps: the system time at which the unit
/// reports motion (Moving_CW) first.
fn motion_starts_at(c: &mut SimChain, o: Outputs) -> u64 {
    send_move(c, o);
    for _ in 0..1_000 {
        c.cycle(Duration::from_micros(20));
        if c.unit(0).unwrap().inputs().status0 & stat0::MOVING_CW != 0 {
            return u64_of(&fprd(c, 0, 0x0910, 8).0);
        }
    }
    panic!("no motion");
}

/// Sends a Relative move of 1,000 steps with `o`'s other words in one LRW, without a cycle.
fn send_move(c: &mut SimChain, mut o: Outputs) {
    o.cmd0 = cmd0::RELATIVE_MOVE;
    o.position = 1_000;
    let mut data: Vec<u8> = ethercat_slave::master::encode_outputs(&o).to_vec();
    data.resize(40, 0);
    let r = one(
        c,
        ethercat_slave::frame::Datagram {
            cmd: cmd::LRW,
            index: 0,
            address: 0,
            data,
            wkc: 0,
        },
    );
    assert_eq!(r.wkc, 3);
}

/// SMD-R1-022, SMD-T3-004: with SYNC0 running and CFG1.6 DC_Sync = 1, a move commanded between two
/// SYNC0 events starts 520 µs after the next event; with DC_Sync = 0 it starts at once (SMD-R1-021).
#[test]
fn smd_r1_022_moves_start_520_us_after_sync0_with_dc_sync() {
    let mut c = SimChain::new(Device::Smd23kB, 1).unwrap();
    let (first, o) = op_with_sync0(&mut c, 0x0043);
    let sent = u64_of(&fprd(&mut c, 0, 0x0910, 8).0);
    assert!(sent < first, "the command comes before the first SYNC0");
    let started = motion_starts_at(&mut c, o);
    assert!(
        (first + 520_000..=first + 560_000).contains(&started),
        "started {} µs after SYNC0",
        (started as i64 - first as i64) / 1000
    );
    // DC_Sync = 0: at once, SYNC0 or not.
    let mut c = SimChain::new(Device::Smd23kB, 1).unwrap();
    let (first, o) = op_with_sync0(&mut c, 0x0003);
    let sent = u64_of(&fprd(&mut c, 0, 0x0910, 8).0);
    let started = motion_starts_at(&mut c, o);
    assert!(started < first, "before any SYNC0");
    assert!(started - sent <= 40_000, "within the first steps");
}

/// Runs `ms` 1 ms cycles without any frame.
fn silence(c: &mut SimChain, ms: u32) {
    for _ in 0..ms {
        c.cycle(Duration::from_millis(1));
    }
}

/// SMD-R1-035, SMD-R6-054: no output image for longer than the SyncManager watchdog (100 ms by
/// default) drops the unit from Op to Safe-Op with the error indication and status code 0x001B; the
/// still-exchanged inputs show PreOp_SafeOp and Input_Error; the master acknowledges and returns to
/// Op, Input_Error stays until Reset Errors (SMD-R6-055).
#[test]
fn smd_r1_035_sm_watchdog_drops_to_safe_op() {
    let mut c = SimChain::new(Device::Smd23kB, 1).unwrap();
    bring_up(&mut c, state::OP);
    let idle = Outputs::default();
    for _ in 0..5 {
        assert_eq!(lrw(&mut c, &[idle]).0, 3);
    }
    // The LRW's own cycle is the first millisecond without a new image.
    silence(&mut c, 98);
    assert_eq!(al(&mut c, 0), (0x0008, 0), "99 ms: still Op");
    assert_eq!(fprd(&mut c, 0, 0x0440, 2).0, [1, 0]);
    silence(&mut c, 2);
    assert_eq!(al(&mut c, 0), (0x0014, 0x001B));
    assert_eq!(fprd(&mut c, 0, 0x0440, 2).0, [0, 0], "expired");
    assert_eq!(fprd(&mut c, 0, 0x0442, 1).0, [1], "counted");
    lrw(&mut c, &[idle]);
    let (_, inputs) = lrw(&mut c, &[idle]);
    assert_ne!(inputs[0].status1 & stat1::PREOP_SAFEOP, 0);
    assert_ne!(inputs[0].status0 & stat0::INPUT_ERROR, 0);
    assert_eq!(fprd(&mut c, 0, 0x0440, 2).0, [1, 0], "outputs again");
    // A request without the acknowledge is refused; with it, back to Op.
    request(&mut c, state::OP);
    assert_eq!(al(&mut c, 0).0, 0x0014);
    request(&mut c, state::SAFEOP | 0x10);
    assert_eq!(al(&mut c, 0), (0x0004, 0));
    request(&mut c, state::OP);
    assert_eq!(al(&mut c, 0), (0x0008, 0));
    let (_, inputs) = lrw(&mut c, &[idle]);
    assert_ne!(
        inputs[0].status0 & stat0::INPUT_ERROR,
        0,
        "until Reset Errors"
    );
    let reset = Outputs {
        cmd0: cmd0::RESET_ERRORS,
        ..idle
    };
    lrw(&mut c, &[reset]);
    lrw(&mut c, &[reset]);
    let (_, inputs) = lrw(&mut c, &[reset]);
    assert_eq!(inputs[0].status0 & stat0::INPUT_ERROR, 0);
}

/// The watchdog time is the master's: 0x0420 = 200 with the default divider is 20 ms; 0 disables it.
#[test]
fn sm_watchdog_time_from_its_registers() {
    let mut c = SimChain::new(Device::Smd23kB, 1).unwrap();
    bring_up(&mut c, state::PREOP);
    fpwr(&mut c, 0, 0x0420, 200u16.to_le_bytes().to_vec());
    request(&mut c, state::SAFEOP);
    lrw(&mut c, &[Outputs::default()]);
    request(&mut c, state::OP);
    lrw(&mut c, &[Outputs::default()]);
    silence(&mut c, 18);
    assert_eq!(al(&mut c, 0).0, 0x0008);
    silence(&mut c, 2);
    assert_eq!(al(&mut c, 0), (0x0014, 0x001B));
    let mut c = SimChain::new(Device::Smd23kB, 1).unwrap();
    bring_up(&mut c, state::PREOP);
    fpwr(&mut c, 0, 0x0420, vec![0, 0]);
    request(&mut c, state::SAFEOP);
    lrw(&mut c, &[Outputs::default()]);
    request(&mut c, state::OP);
    silence(&mut c, 1_000);
    assert_eq!(al(&mut c, 0), (0x0008, 0), "disabled");
}

/// SMD-R1-036, SMD-R6-056: a lost link drops a unit in Op to Safe-Op (PreOp_SafeOp in the inputs)
/// until the master requests Op again; the position is then invalid.
#[test]
fn smd_r1_036_link_loss_leaves_safe_op_until_requested() {
    let mut c = SimChain::new(Device::Smd23kB, 2).unwrap();
    bring_up(&mut c, state::OP);
    let preset = Outputs {
        cmd0: cmd0::PRESET_POSITION,
        cmd1: 0x8000,
        ..Outputs::default()
    };
    // The first image in Op is the edge reference (SMD-R6-073): 0 first, then the preset's edge.
    lrw(&mut c, &[Outputs::default(), Outputs::default()]);
    lrw(&mut c, &[preset, preset]);
    lrw(&mut c, &[Outputs::default(), Outputs::default()]);
    let (_, inputs) = lrw(&mut c, &[Outputs::default(), Outputs::default()]);
    assert_eq!(inputs[0].status0 & stat0::POSITION_INVALID, 0, "preset");
    c.chain.link_lost(c.now);
    for k in 0..2 {
        assert_eq!(al(&mut c, k), (0x0014, 0x001B), "unit {k}");
    }
    // The link is back: frames flow, the units stay in Safe-Op.
    lrw(&mut c, &[Outputs::default(), Outputs::default()]);
    let (_, inputs) = lrw(&mut c, &[Outputs::default(), Outputs::default()]);
    assert_ne!(inputs[1].status1 & stat1::PREOP_SAFEOP, 0);
    silence(&mut c, 50);
    assert_eq!(al(&mut c, 0).0, 0x0014, "not back to Op by itself");
    request(&mut c, state::OP | 0x10);
    assert_eq!(al(&mut c, 0), (0x0008, 0));
    lrw(&mut c, &[Outputs::default(), Outputs::default()]);
    let (_, inputs) = lrw(&mut c, &[Outputs::default(), Outputs::default()]);
    assert_ne!(inputs[0].status0 & stat0::POSITION_INVALID, 0, "SMD-R6-056");
    assert_eq!(inputs[0].status1 & stat1::PREOP_SAFEOP, 0);
}

/// SMD-R1-022 with a SYNC0 start time already past when SYNC0 is activated: its events count from
/// that time, so the first has passed before any move written after the activation; a move waits
/// for the next event (one 2 ms cycle after the start time) and starts 520 µs after it.
#[test]
fn smd_r1_022_a_past_start_time_puts_the_first_sync0_before_the_move() {
    let mut c = SimChain::new(Device::Smd23kB, 1).unwrap();
    let (_, o) = op_with_sync0(&mut c, 0x0043);
    let start = start_sync0(&mut c, 0, 2_000_000, -1_000_000);
    let started = motion_starts_at(&mut c, o);
    let next = start + 2_000_000;
    assert!(
        (next + 520_000..=next + 560_000).contains(&started),
        "started {} µs after the start time",
        (started - start) / 1000
    );
}

/// SMD-R1-022 inside one cycle of the unit: with 1 ms cycles and a SYNC0 event 100 µs into a
/// cycle, the unit runs up to the event, takes it, and runs on from it, so a move waiting for it
/// starts 520 µs after it — 620 µs into the cycle, before the cycle ends — and the first inputs
/// after the cycle report it moving.
#[test]
fn smd_r1_022_the_sync0_event_falls_inside_the_cycle() {
    let mut c = SimChain::new(Device::Smd23kB, 1).unwrap();
    let (_, o) = op_with_sync0(&mut c, 0x0043);
    start_sync0(&mut c, 0, 2_000_000, 100_000);
    send_move(&mut c, o);
    c.cycle(Duration::from_millis(1));
    let status0 = c.unit(0).unwrap().inputs().status0;
    assert_ne!(status0 & stat0::MOVING_CW, 0, "status {status0:#06x}");
}
