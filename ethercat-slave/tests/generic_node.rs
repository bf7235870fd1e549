//! `ethercat-node`'s units in process, on a simulated clock, byte by byte: the example drive and
//! I/O device of `examples/` and the vendors' drives of the corpus beside the checkout, through a
//! master's start-up (SII, SyncManagers, FMMUs, AL states), their CoE dictionaries, their PDO
//! configuration and its refusals, and their process data with the drives behind it.

#[path = "common/node.rs"]
mod node;

use std::time::Duration;

use ethercat_slave::master::Layout;
use node::*;

/// The example drive's outputs (RxPDO 0x1600: controlword, target position, mode of operation).
fn drive_out(cw: u16, target: i32, mode: i8) -> Vec<u8> {
    let mut b = cw.to_le_bytes().to_vec();
    b.extend_from_slice(&target.to_le_bytes());
    b.push(mode as u8);
    b
}

/// The example drive's inputs (TxPDO 0x1A00): statusword, position, velocity, following error,
/// mode display.
fn drive_in(b: &[u8]) -> (u16, i32, i32, i32, i8) {
    let i32_at = |o: usize| i32::from_le_bytes(b[o..o + 4].try_into().unwrap());
    (
        u16::from_le_bytes([b[0], b[1]]),
        i32_at(2),
        i32_at(6),
        i32_at(10),
        b[14] as i8,
    )
}

/// Brings every unit to Op (SYNC0 every 1 ms on the units `sync0` names, from 500 µs on), running
/// the process data with `outputs` from Safe-Op on.
fn to_op(
    c: &mut ethercat_slave::master::SimChain<ethercat_slave::generic::GenericUnit>,
    layouts: &[Layout],
    sync0_on: &[usize],
    outputs: &[Vec<u8>],
) {
    configure(c, layouts);
    let n = layouts.len() as u16;
    assert_eq!(request(c, 0x02), n);
    for &k in sync0_on {
        node::sync0(c, k, 1_000_000, 500_000);
    }
    assert_eq!(request(c, 0x04), n);
    for k in 0..layouts.len() {
        assert_eq!(al(c, k), (0x04, 0), "unit {k} in Safe-Op");
    }
    lrw(c, layouts, outputs);
    assert_eq!(request(c, 0x08), n);
    for k in 0..layouts.len() {
        assert_eq!(al(c, k), (0x08, 0), "unit {k} in Op");
    }
}

/// The example drive from its ESI: identity in the SII and 0x1018 with serial numbers by position,
/// the process images of its power-on assignment (RxPDO 0x1600: 2 + 4 + 1 = 7 bytes; TxPDO 0x1A00:
/// 2 + 4 + 4 + 4 + 1 = 15 bytes), one drive axis.
#[test]
fn the_example_drive_from_its_esi() {
    let t = drive();
    let layout = Layout::of(&t);
    assert_eq!(layout.lengths(), (7, 15));
    assert_eq!(t.axes(), [0]);
    let mut c = chain(&[(&t, 2)]);
    let layouts = [layout.clone(), layout.clone()];
    configure(&mut c, &layouts);
    for k in 0..2 {
        // SII words 8–15: vendor 0xABC, product 0x402, revision 0x00010001, serial k + 1.
        let mut sii = Vec::new();
        for word in [8u32, 12] {
            fpwr(&mut c, k, 0x0504, word.to_le_bytes().to_vec());
            fpwr(&mut c, k, 0x0502, vec![0x00, 0x01]);
            sii.extend(fprd(&mut c, k, 0x0508, 8).0);
        }
        let words: Vec<u32> = sii
            .chunks(4)
            .map(|w| u32::from_le_bytes(w.try_into().unwrap()))
            .collect();
        assert_eq!(
            words,
            [0xABC, 0x402, 0x0001_0001, k as u32 + 1],
            "unit {k} SII"
        );
    }
    assert_eq!(request(&mut c, 0x02), 2);
    // The drives' initialisation (CiA 402 transition 1) takes their first control tick.
    c.cycle(Duration::from_millis(1));
    for k in 0..2 {
        assert_eq!(
            read(&mut c, &layout, k, 0x1018, 4),
            k as i64 + 1,
            "0x1018:04 of unit {k}"
        );
        assert_eq!(read(&mut c, &layout, k, 0x1018, 1), 0xABC);
        assert_eq!(upload(&mut c, &layout, k, 0x1008, 0), Ok(b"drive".to_vec()));
        assert_eq!(read(&mut c, &layout, k, 0x1C12, 0), 1);
        assert_eq!(read(&mut c, &layout, k, 0x1C12, 1), 0x1600);
        assert_eq!(read(&mut c, &layout, k, 0x1C13, 1), 0x1A00);
        assert_eq!(read(&mut c, &layout, k, 0x6502, 0), 0x3A5);
        // CiA 402 power-on: Switch on disabled (0x0040), remote and quick stop bits.
        assert_eq!(read(&mut c, &layout, k, 0x6041, 0) & 0x004F, 0x0040);
    }
}

/// csp with SYNC0 every 1 ms (500 µs after each master cycle): the drive enabled by its
/// controlword in the process data (Shutdown 0x0006 → Ready to switch on 0x0021, Switch on 0x0007
/// → Switched on 0x0023, Enable operation 0x000F → Operation enabled 0x0027), then 2,000
/// set-points 1 count apart, one per cycle: the drive follows one SYNC0 period behind at the
/// ramp's speed and ends exactly at 2,000 (in the process data and by SDO), following error 0.
#[test]
fn csp_on_sync0_moves_to_the_last_set_point() {
    let t = drive();
    let layout = Layout::of(&t);
    let layouts = [layout.clone()];
    let mut c = chain(&[(&t, 1)]);
    to_op(&mut c, &layouts, &[0], &[drive_out(0, 0, 8)]);
    for (cw, state) in [(0x0006u16, 0x0021u16), (0x0007, 0x0023), (0x000F, 0x0027)] {
        let mut last = 0;
        for _ in 0..5 {
            let (_, inputs) = lrw(&mut c, &layouts, &[drive_out(cw, 0, 8)]);
            last = drive_in(&inputs[0]).0;
        }
        assert_eq!(
            last & 0x006F,
            state,
            "after controlword {cw:#06x}: statusword {last:#06x}"
        );
    }
    for p in 1..=2000 {
        let (wkc, inputs) = lrw(&mut c, &layouts, &[drive_out(0x000F, p, 8)]);
        assert_eq!(wkc, 3);
        let (_, pos, vel, ferr, mode) = drive_in(&inputs[0]);
        assert_eq!(mode, 8);
        // The inputs of the frame with set-point p were packed one cycle before, 500 µs after
        // the SYNC0 that took set-point p − 1: half-way from p − 2 to p − 1, p − 1.5, which
        // rounds (half away from zero) to p − 1; the ramp's 1,000 counts/s; no following error.
        if p >= 3 {
            assert_eq!((pos, vel, ferr), (p - 1, 1000, 0), "set-point {p}");
        }
    }
    for _ in 0..200 {
        lrw(&mut c, &layouts, &[drive_out(0x000F, 2000, 8)]);
    }
    let (_, inputs) = lrw(&mut c, &layouts, &[drive_out(0x000F, 2000, 8)]);
    let (sw, pos, vel, ferr, _) = drive_in(&inputs[0]);
    assert_eq!((sw & 0x006F, pos, vel, ferr), (0x0027, 2000, 0, 0));
    assert_eq!(read(&mut c, &layout, 0, 0x6064, 0), 2000);
    assert_eq!(read(&mut c, &layout, 0, 0x60F4, 0), 0);
}

/// Enables the example drive (unit `k` of `layouts`) by its controlword, `target` held.
fn enable(
    c: &mut ethercat_slave::master::SimChain<ethercat_slave::generic::GenericUnit>,
    layouts: &[Layout],
    outputs: &mut [Vec<u8>],
    k: usize,
    target: i32,
) {
    for cw in [0x0006u16, 0x0007, 0x000F] {
        outputs[k] = drive_out(cw, target, 8);
        for _ in 0..3 {
            lrw(c, layouts, outputs);
        }
    }
    let (_, inputs) = lrw(c, layouts, outputs);
    assert_eq!(
        drive_in(&inputs[k]).0 & 0x006F,
        0x0027,
        "unit {k} Operation enabled"
    );
}

/// SyncManager-synchronous csp (no SYNC0): each new output image is the drive's SYNC (taken on the
/// unit's cycle), so the set-points are followed all the same, two set-points behind, at the
/// ramp's 1,000 counts/s, ending exactly at the last.
#[test]
fn without_sync0_each_output_image_is_the_sync() {
    let t = drive();
    let layouts = [Layout::of(&t)];
    let mut c = chain(&[(&t, 1)]);
    let mut outputs = vec![drive_out(0, 0, 8)];
    to_op(&mut c, &layouts, &[], &outputs);
    enable(&mut c, &layouts, &mut outputs, 0, 0);
    let mut last = (0, 0);
    for p in 1..=500 {
        outputs[0] = drive_out(0x000F, p, 8);
        let (_, inputs) = lrw(&mut c, &layouts, &outputs);
        let (_, pos, vel, ferr, _) = drive_in(&inputs[0]);
        // The inputs of the frame with set-point p were packed at the cycle that took p − 1 as
        // its SYNC, where the demand starts from p − 2.
        if p >= 3 {
            assert_eq!((p - pos, ferr), (2, 0), "set-point {p}");
        }
        last = (pos, vel);
    }
    // The servo's velocity loop settles on the ramp's speed.
    assert_eq!(last, (498, 1000));
    for _ in 0..200 {
        lrw(&mut c, &layouts, &outputs);
    }
    let (_, inputs) = lrw(&mut c, &layouts, &outputs);
    let (_, pos, vel, ferr, _) = drive_in(&inputs[0]);
    assert_eq!((pos, vel, ferr), (500, 0, 0));
}

/// SYNC0 activated with its start time 100 ms ahead (as SOEM sets it): until its first pulse each
/// new output image is the drive's SYNC, so a csp ramp started before it is followed from its
/// first set-point (two behind, as without SYNC0), not taken in one step when the first pulse
/// comes; after it the ramp goes on on SYNC0, and ends exactly at its last set-point.
#[test]
fn before_sync0_s_first_pulse_the_outputs_drive_the_set_points() {
    let t = drive();
    let layouts = [Layout::of(&t)];
    let mut c = chain(&[(&t, 1)]);
    let out = |cw: u16, target: i32| drive_out(cw, target, 8);
    configure(&mut c, &layouts);
    assert_eq!(request(&mut c, 0x02), 1);
    node::sync0(&mut c, 0, 1_000_000, 100_000_000);
    assert_eq!(request(&mut c, 0x04), 1);
    lrw(&mut c, &layouts, &[out(0, 0)]);
    assert_eq!(request(&mut c, 0x08), 1);
    assert_eq!(al(&mut c, 0), (0x08, 0), "Op");
    for cw in [0x0006u16, 0x0007, 0x000F] {
        for _ in 0..3 {
            lrw(&mut c, &layouts, &[out(cw, 0)]);
        }
    }
    for p in 1..=60 {
        let (_, inputs) = lrw(&mut c, &layouts, &[out(0x000F, p)]);
        let pos = drive_in(&inputs[0]).1;
        if p >= 3 {
            assert_eq!(p - pos, 2, "set-point {p} (before SYNC0's first pulse)");
        }
    }
    for p in 61..=200 {
        lrw(&mut c, &layouts, &[out(0x000F, p)]);
    }
    for _ in 0..200 {
        lrw(&mut c, &layouts, &[out(0x000F, 200)]);
    }
    let (_, inputs) = lrw(&mut c, &layouts, &[out(0x000F, 200)]);
    let (_, pos, vel, ferr, _) = drive_in(&inputs[0]);
    assert_eq!((pos, vel, ferr), (200, 0, 0));
}

/// ETG.1000.6 §5.6.7.4: the PDO assignment is changed in Pre-Op and takes effect at Safe-Op. The
/// example drive's 0x1C12 from 0x1600 (7 bytes) to 0x1602 (controlword, target torque, mode: 2 +
/// 2 + 1 = 5 bytes): SM2 set for the old 7 bytes is refused (0x001D), for 5 accepted; in Op the
/// torque of the process data is 0x6071's.
#[test]
fn a_new_assignment_takes_effect_at_safe_op() {
    let t = drive();
    let layout = Layout::of(&t);
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    assert_eq!(download(&mut c, &layout, 0, 0x1C12, 0, &[0]), Ok(()));
    assert_eq!(
        download(&mut c, &layout, 0, 0x1C12, 1, &0x1602u16.to_le_bytes()),
        Ok(())
    );
    assert_eq!(download(&mut c, &layout, 0, 0x1C12, 0, &[1]), Ok(()));
    assert_eq!(read(&mut c, &layout, 0, 0x1C12, 1), 0x1602);
    assert_eq!(request(&mut c, 0x04), 1);
    assert_eq!(
        al(&mut c, 0),
        (0x12, 0x001D),
        "SM2 of 7 bytes for a 5-byte image"
    );
    request(&mut c, 0x12);
    let five = Layout::with_lengths(&t, 5, 15);
    configure(&mut c, std::slice::from_ref(&five));
    assert_eq!(request(&mut c, 0x04), 1);
    assert_eq!(al(&mut c, 0), (0x04, 0));
    let mut out = 0x0006u16.to_le_bytes().to_vec();
    out.extend_from_slice(&(-250i16).to_le_bytes());
    out.push(10);
    lrw(
        &mut c,
        std::slice::from_ref(&five),
        std::slice::from_ref(&out),
    );
    request(&mut c, 0x08);
    assert_eq!(al(&mut c, 0), (0x08, 0));
    let (wkc, inputs) = lrw(&mut c, std::slice::from_ref(&five), &[out]);
    assert_eq!((wkc, inputs[0].len()), (3, 15));
    assert_eq!(read(&mut c, &five, 0, 0x6071, 0), -250);
    assert_eq!(read(&mut c, &five, 0, 0x6040, 0), 0x0006);
    assert_eq!(read(&mut c, &five, 0, 0x6060, 0), 10);
}

/// The refusals of the PDO configuration, each with its abort code (ETG.1000.6 §5.6.7.4 and the
/// CiA 301 codes), and the AL status codes of an assignment that cannot run.
#[test]
fn the_pdo_configuration_refuses_what_the_esi_does_not_allow() {
    let t = drive();
    let layout = Layout::of(&t);
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    let dl =
        |c: &mut _, index: u16, sub: u8, data: &[u8]| download(c, &layout, 0, index, sub, data);
    // An entry while sub-index 0 is not 0.
    assert_eq!(dl(&mut c, 0x1C12, 1, &[0x01, 0x16]), Err(0x0601_0003));
    assert_eq!(dl(&mut c, 0x1C12, 0, &[0]), Ok(()));
    // A TxPDO in the RxPDO assignment, a PDO the drive does not have: invalid value.
    assert_eq!(dl(&mut c, 0x1C12, 1, &[0x00, 0x1A]), Err(0x0609_0030));
    assert_eq!(dl(&mut c, 0x1C12, 1, &[0x04, 0x16]), Err(0x0609_0030));
    // An entry 0 assigns nothing and is taken.
    assert_eq!(dl(&mut c, 0x1C12, 1, &[0x00, 0x00]), Ok(()));
    // More PDOs than the object has entries (2).
    assert_eq!(dl(&mut c, 0x1C12, 0, &[3]), Err(0x0609_0031));
    // A fixed PDO's mapping is read-only.
    assert_eq!(dl(&mut c, 0x1600, 0, &[0]), Err(0x0601_0002));
    // The configurable 0x1603: entries by the rules of a mapping.
    assert_eq!(dl(&mut c, 0x1603, 0, &[0]), Ok(()));
    // CiA 301 dummy entries of their types' sizes are taken (0x0001 BOOLEAN 1 bit, 0x0002
    // INTEGER8 and 0x0005 UNSIGNED8 8, 0x0003 INTEGER16 and 0x0006 UNSIGNED16 16, 0x0004 INTEGER32
    // and 0x0007 UNSIGNED32 32); another size, or a sub-index other than 0, is not mappable.
    for raw in [
        0x0001_0001u32,
        0x0002_0008,
        0x0005_0008,
        0x0003_0010,
        0x0006_0010,
        0x0004_0020,
        0x0007_0020,
    ] {
        assert_eq!(
            dl(&mut c, 0x1603, 1, &raw.to_le_bytes()),
            Ok(()),
            "{raw:#010x}"
        );
    }
    for raw in [0x0006_0008u32, 0x0001_0008, 0x0007_0120] {
        assert_eq!(
            dl(&mut c, 0x1603, 1, &raw.to_le_bytes()),
            Err(0x0604_0041),
            "{raw:#010x}"
        );
    }
    assert_eq!(
        dl(&mut c, 0x1603, 1, &0x6041_0010u32.to_le_bytes()),
        Err(0x0604_0041),
        "a TxPDO entry"
    );
    assert_eq!(
        dl(&mut c, 0x1603, 1, &0x2000_0010u32.to_le_bytes()),
        Err(0x0602_0000),
        "no such object"
    );
    assert_eq!(
        dl(&mut c, 0x1603, 1, &0x607A_0010u32.to_le_bytes()),
        Err(0x0604_0041),
        "16 bits of 32"
    );
    assert_eq!(
        dl(&mut c, 0x1603, 0, &[9]),
        Err(0x0604_0042),
        "9 entries of 8"
    );
    for (sub, raw) in [(1u8, 0x6040_0010u32), (2, 0x60FF_0020), (3, 0x0000_0008)] {
        assert_eq!(dl(&mut c, 0x1603, sub, &raw.to_le_bytes()), Ok(()));
    }
    assert_eq!(dl(&mut c, 0x1603, 0, &[3]), Ok(()));
    // 0x1600 and 0x1603 exclude each other: accepted by SDO, refused at Safe-Op (0x0025).
    assert_eq!(dl(&mut c, 0x1C12, 1, &[0x00, 0x16]), Ok(()));
    assert_eq!(dl(&mut c, 0x1C12, 2, &[0x03, 0x16]), Ok(()));
    assert_eq!(dl(&mut c, 0x1C12, 0, &[2]), Ok(()));
    configure(&mut c, &[Layout::with_lengths(&t, 14, 15)]);
    request(&mut c, 0x04);
    assert_eq!(al(&mut c, 0), (0x12, 0x0025));
    request(&mut c, 0x12);
    // 0x1603 alone: controlword, target velocity, an 8-bit gap: 7 bytes.
    assert_eq!(dl(&mut c, 0x1C12, 0, &[1]), Ok(()));
    assert_eq!(dl(&mut c, 0x1C12, 0, &[0]), Ok(()));
    assert_eq!(dl(&mut c, 0x1C12, 1, &[0x03, 0x16]), Ok(()));
    assert_eq!(dl(&mut c, 0x1C12, 0, &[1]), Ok(()));
    // TxPDOs beyond the inputs SyncManager's MaxSize (32 bytes): 0x1A00 (15) + 0x1A01 remapped to
    // 8 × 0x6064 (32): 0x0024.
    assert_eq!(dl(&mut c, 0x1A01, 0, &[0]), Ok(()));
    for sub in 1..=8 {
        assert_eq!(
            dl(&mut c, 0x1A01, sub, &0x6064_0020u32.to_le_bytes()),
            Ok(())
        );
    }
    assert_eq!(dl(&mut c, 0x1A01, 0, &[8]), Ok(()));
    assert_eq!(dl(&mut c, 0x1C13, 0, &[0]), Ok(()));
    assert_eq!(dl(&mut c, 0x1C13, 2, &[0x01, 0x1A]), Ok(()));
    assert_eq!(dl(&mut c, 0x1C13, 0, &[2]), Ok(()));
    configure(&mut c, &[Layout::with_lengths(&t, 7, 47)]);
    request(&mut c, 0x04);
    assert_eq!(al(&mut c, 0), (0x12, 0x0024));
    request(&mut c, 0x12);
    assert_eq!(dl(&mut c, 0x1C13, 0, &[1]), Ok(()));
    let layout7 = Layout::with_lengths(&t, 7, 15);
    configure(&mut c, std::slice::from_ref(&layout7));
    request(&mut c, 0x04);
    assert_eq!(al(&mut c, 0), (0x04, 0));
    // Safe-Op: the PDO configuration no longer changes (0x08000022), the RxPDO's entries are the
    // process data's (0x06010006); another entry is still written.
    let dl =
        |c: &mut _, index: u16, sub: u8, data: &[u8]| download(c, &layout7, 0, index, sub, data);
    assert_eq!(dl(&mut c, 0x1C12, 0, &[0]), Err(0x0800_0022));
    assert_eq!(dl(&mut c, 0x1603, 0, &[0]), Err(0x0800_0022));
    assert_eq!(
        dl(&mut c, 0x60FF, 0, &100i32.to_le_bytes()),
        Err(0x0601_0006)
    );
    assert_eq!(
        dl(&mut c, 0x607A, 0, &100i32.to_le_bytes()),
        Ok(()),
        "not mapped now"
    );
    assert_eq!(dl(&mut c, 0x6081, 0, &5000u32.to_le_bytes()), Ok(()));
}

/// Leaving Op ends the connection (CiA 402-2 0x6007, abort connection option code), drive by
/// drive: 2 (the example's default) disables the voltage (Switch on disabled), 3 quick-stops
/// (Quick stop active, where 0x605A = 6 keeps it), 1 faults with 0x8100 (Fault), 0 leaves the drive enabled. The master's
/// Safe-Op request and the SyncManager watchdog (100 ms without outputs: Safe-Op with 0x001B) alike.
#[test]
fn leaving_op_ends_the_connection_as_0x6007_says() {
    let t = drive();
    let layout = Layout::of(&t);
    let layouts = vec![layout.clone(); 4];
    let mut c = chain(&[(&t, 4)]);
    configure(&mut c, &layouts);
    request(&mut c, 0x02);
    for (k, option) in [(0usize, 2i16), (1, 3), (2, 1), (3, 0)] {
        assert_eq!(
            download(&mut c, &layout, k, 0x6007, 0, &option.to_le_bytes()),
            Ok(())
        );
    }
    // The quick stop stays in Quick stop active (0x605A = 6) so that it shows.
    assert_eq!(
        download(&mut c, &layout, 1, 0x605A, 0, &6i16.to_le_bytes()),
        Ok(())
    );
    let mut outputs = vec![drive_out(0, 0, 8); 4];
    to_op(&mut c, &layouts, &[0, 1, 2, 3], &outputs);
    for k in 0..4 {
        enable(&mut c, &layouts, &mut outputs, k, 0);
    }
    request(&mut c, 0x04);
    c.cycle(Duration::from_millis(50));
    let states: Vec<(i64, i64)> = (0..4)
        .map(|k| {
            (
                read(&mut c, &layout, k, 0x6041, 0),
                read(&mut c, &layout, k, 0x603F, 0),
            )
        })
        .collect();
    assert_eq!(states[0].0 & 0x4F, 0x40, "0x6007 = 2: Switch on disabled");
    assert_eq!(states[1].0 & 0x6F, 0x07, "0x6007 = 3: Quick stop active");
    assert_eq!(
        states[2].1 & 0xFFFF,
        0x8100,
        "0x6007 = 1: error code 0x8100"
    );
    assert_eq!(states[2].0 & 0x4F, 0x08, "0x6007 = 1: Fault");
    assert_eq!(
        states[3].0 & 0x6F,
        0x27,
        "0x6007 = 0: still Operation enabled"
    );
    // The watchdog: the last drive back in Op, then 100 ms without outputs.
    request(&mut c, 0x08);
    lrw(&mut c, &layouts, &outputs);
    assert_eq!(al(&mut c, 3), (0x08, 0));
    assert_eq!(
        download(&mut c, &layout, 3, 0x6007, 0, &2i16.to_le_bytes()),
        Ok(())
    );
    // The last outputs came 1 ms ago (the LRW's cycle); the watchdog (100 ms) runs out at 100 ms.
    c.cycle(Duration::from_millis(98));
    assert_eq!(al(&mut c, 3), (0x08, 0));
    c.cycle(Duration::from_millis(1));
    assert_eq!(al(&mut c, 3), (0x14, 0x001B));
    assert_eq!(read(&mut c, &layout, 3, 0x6041, 0) & 0x4F, 0x40);
}

/// The example I/O device: no model, its process data writes and reads its dictionary's entries,
/// bit by bit (8 BOOL outputs 0x7000:01–08 and an INT 0x7010:01 in 3 bytes, the same for inputs
/// 0x6000 and 0x6010); an output entry mapped in Op refuses an SDO download (0x06010006); SYNC0 on
/// a device without Distributed Clocks refuses Safe-Op (0x0030).
#[test]
fn an_io_device_is_its_dictionary() {
    let t = io_device();
    let layout = Layout::of(&t);
    assert_eq!(layout.lengths(), (3, 3));
    assert!(t.axes().is_empty());
    let layouts = [layout.clone()];
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, &layouts);
    request(&mut c, 0x02);
    node::sync0(&mut c, 0, 1_000_000, 500_000);
    request(&mut c, 0x04);
    assert_eq!(al(&mut c, 0), (0x12, 0x0030));
    request(&mut c, 0x12);
    fpwr(&mut c, 0, 0x0981, vec![0]);
    let outputs = vec![vec![0b1010_0101, 0x34, 0x12]];
    request(&mut c, 0x04);
    assert_eq!(al(&mut c, 0), (0x04, 0));
    // Safe-Op: the outputs stay in their safe state (ETG.1000.6 §6.4.1: the outputs are taken in
    // Op only), 0x7000:01 and 0x7010:01 at their ESI defaults 0.
    lrw(&mut c, &layouts, &outputs);
    c.cycle(Duration::from_millis(1));
    assert_eq!(read(&mut c, &layout, 0, 0x7000, 1), 0);
    assert_eq!(read(&mut c, &layout, 0, 0x7010, 1), 0);
    request(&mut c, 0x08);
    assert_eq!(al(&mut c, 0), (0x08, 0));
    lrw(&mut c, &layouts, &outputs);
    let bits: Vec<i64> = (1..=8)
        .map(|s| read(&mut c, &layout, 0, 0x7000, s))
        .collect();
    assert_eq!(bits, [1, 0, 1, 0, 0, 1, 0, 1]);
    assert_eq!(read(&mut c, &layout, 0, 0x7010, 1), 0x1234);
    assert_eq!(
        download(&mut c, &layout, 0, 0x7010, 1, &[0, 0]),
        Err(0x0601_0006)
    );
    let now = c.now;
    let unit = c.chain.unit_mut(0).unwrap();
    unit.set(now, od::dict::Address::new(0x6000, 3), &[1])
        .unwrap();
    unit.set(now, od::dict::Address::new(0x6000, 8), &[1])
        .unwrap();
    unit.set(
        now,
        od::dict::Address::new(0x6010, 1),
        &(-5i16).to_le_bytes(),
    )
    .unwrap();
    assert!(unit
        .set(now, od::dict::Address::new(0x6010, 1), &[1, 2, 3])
        .is_err());
    lrw(&mut c, &layouts, &outputs);
    let (wkc, inputs) = lrw(&mut c, &layouts, &outputs);
    assert_eq!(wkc, 3);
    assert_eq!(inputs[0], [0b1000_0100, 0xFB, 0xFF]);
}

/// What the host running the chain sees of a unit and does to it, as the master sees it: a chain
/// of none is empty; the example drive's unit has one drive (axis 0), process images of 7 and 15
/// bytes from Safe-Op on, its dictionary holds what an SDO download wrote (0x6067 = 1234), its
/// statusword as the process data carries it; a fault raised on its drive (over-temperature
/// 0x4310) the master reads as Fault (0x6041 & 0x4F = 0x08) with 0x603F = 0x4310.
#[test]
fn the_host_sees_and_acts_on_a_unit() {
    let t = drive();
    let empty = chain(&[(&t, 0)]);
    assert!(empty.chain.is_empty());
    assert_eq!(empty.chain.len(), 0);
    let layouts = [Layout::of(&t)];
    let layout = &layouts[0];
    let mut c = chain(&[(&t, 1)]);
    assert!(!c.chain.is_empty());
    let outputs = vec![drive_out(0, 0, 8)];
    to_op(&mut c, &layouts, &[], &outputs);
    let (o, i) = c.chain.slot(0).unwrap().images();
    assert_eq!((o.len(), i.len()), (7, 15));
    assert_eq!(
        download(&mut c, layout, 0, 0x6067, 0, &1234u32.to_le_bytes()),
        Ok(())
    );
    let (_, inputs) = lrw(&mut c, &layouts, &outputs);
    let unit = c.chain.unit(0).unwrap();
    assert_eq!(unit.dict().read(0x6067, 0).unwrap(), 1234u32.to_le_bytes());
    assert_eq!(unit.drives().len(), 1);
    assert_eq!(unit.drives()[0].axis(), 0);
    assert_eq!(
        unit.value(od::dict::Address::new(0x6041, 0)),
        inputs[0][0..2]
    );
    let now = c.now;
    c.chain.unit_mut(0).unwrap().drives_mut()[0].raise_fault(now, 0x4310);
    c.cycle(Duration::from_millis(10));
    assert_eq!(read(&mut c, layout, 0, 0x6041, 0) & 0x4F, 0x08);
    assert_eq!(read(&mut c, layout, 0, 0x603F, 0), 0x4310);
}

/// ETG.1000.6 §5.5: a request the master writes while SM1 still holds the answer before is taken,
/// and its answer waits for SM1: the example drive's uploads of 0x1018:01 (vendor 0xABC) and
/// 0x1018:02 (product 0x402) written one after the other are answered in order, each once SM1
/// is read (expedited, 4 bytes: command 0x43); so are 0x1018:01 and 0x1018:03 (revision
/// 0x00010001) with a Pre-Op → Safe-Op request between (only Init ends the mailbox's work).
#[test]
fn an_answer_waits_for_sm1() {
    let t = drive();
    let layouts = [Layout::of(&t)];
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, &layouts);
    request(&mut c, 0x02);
    let (out, inn) = layouts[0].mailbox().unwrap();
    let ask = |c: &mut ethercat_slave::master::SimChain<_>, sub: u8| {
        let mut m = coe_request(next_counter(0), &[0x40, 0x18, 0x10, sub, 0, 0, 0, 0]);
        m.resize(usize::from(out.len), 0);
        fpwr(c, 0, out.start, m);
        c.cycle(Duration::from_millis(1));
    };
    let answer = |c: &mut ethercat_slave::master::SimChain<_>| {
        assert_eq!(fprd(c, 0, 0x080D, 1).0[0] & 0x08, 0x08, "SM1 full");
        let (m, wkc) = fprd(c, 0, inn.start, usize::from(inn.len));
        assert_eq!(wkc, 1);
        c.cycle(Duration::from_millis(1));
        coe_answer(&m).unwrap()
    };
    let expect = |sub: u8, v: u32| {
        let mut b = vec![0x43, 0x18, 0x10, sub];
        b.extend_from_slice(&v.to_le_bytes());
        b
    };
    ask(&mut c, 1);
    ask(&mut c, 2);
    assert_eq!(answer(&mut c), expect(1, 0xABC));
    assert_eq!(answer(&mut c), expect(2, 0x402));
    ask(&mut c, 1);
    ask(&mut c, 3);
    request(&mut c, 0x04);
    assert_eq!(al(&mut c, 0), (0x04, 0));
    assert_eq!(answer(&mut c), expect(1, 0xABC));
    assert_eq!(answer(&mut c), expect(3, 0x0001_0001));
}

/// The link lost: a unit in Op drops to Safe-Op with the error indication and AL status code
/// 0x001B (as on a SyncManager watchdog expiry) and its drive ends the connection (0x6007 = 2:
/// Switch on disabled, 0x6041 & 0x4F = 0x40); a unit in Safe-Op stays there without an error.
#[test]
fn a_lost_link_drops_the_units_in_op() {
    let t = drive();
    let layouts = [Layout::of(&t), Layout::of(&t)];
    let layout = &layouts[0];
    let mut c = chain(&[(&t, 2)]);
    let mut outputs = vec![drive_out(0, 0, 8); 2];
    to_op(&mut c, &layouts, &[], &outputs);
    enable(&mut c, &layouts, &mut outputs, 0, 0);
    request_one(&mut c, 1, 0x04);
    assert_eq!(al(&mut c, 1), (0x04, 0));
    let now = c.now;
    c.chain.link_lost(now);
    assert_eq!(al(&mut c, 0), (0x14, 0x001B));
    assert_eq!(al(&mut c, 1), (0x04, 0));
    c.cycle(Duration::from_millis(10));
    assert_eq!(read(&mut c, layout, 0, 0x6041, 0) & 0x4F, 0x40);
}

/// ETG.1020 0x1C32:02 (cycle time, ns) shows the SYNC0 cycle from Safe-Op on: one set in Pre-Op
/// (2 ms) with which the unit goes back to Init, never having run with it, leaves the ESI's
/// 1,000,000 ns.
#[test]
fn a_sync0_cycle_never_run_leaves_the_cycle_time() {
    let t = drive();
    let layouts = [Layout::of(&t)];
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, &layouts);
    request(&mut c, 0x02);
    node::sync0(&mut c, 0, 2_000_000, 500_000);
    request(&mut c, 0x01);
    assert_eq!(al(&mut c, 0), (0x01, 0));
    request(&mut c, 0x02);
    assert_eq!(al(&mut c, 0), (0x02, 0));
    assert_eq!(read(&mut c, &layouts[0], 0, 0x1C32, 2), 1_000_000);
}

/// Without SYNC0 the drive's SYNC is a new output image (SyncManager-synchronous operation, the SM2
/// event), and a process-data cycle without one is none: the example drive in csp with the RxPDO
/// 0x1602 (controlword, target torque, mode: 5 bytes), so that 0x607A is written by SDO in Op,
/// stands at 0 through 20 cycles without a frame after 0x607A = 1,000, and is at 1,000 once output
/// images come again.
#[test]
fn without_sync0_a_cycle_without_new_outputs_is_no_sync() {
    let t = drive();
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, &[Layout::of(&t)]);
    request(&mut c, 0x02);
    let layout = Layout::of(&t);
    for (sub, v) in [(0u8, vec![0]), (1, vec![0x02, 0x16]), (0, vec![1])] {
        assert_eq!(download(&mut c, &layout, 0, 0x1C12, sub, &v), Ok(()));
    }
    let layouts = [Layout::with_lengths(&t, 5, 15)];
    let layout = &layouts[0];
    configure(&mut c, &layouts);
    let out = |cw: u16| {
        let mut b = cw.to_le_bytes().to_vec();
        b.extend_from_slice(&[0, 0, 8]);
        vec![b]
    };
    request(&mut c, 0x04);
    lrw(&mut c, &layouts, &out(0));
    request(&mut c, 0x08);
    assert_eq!(al(&mut c, 0), (0x08, 0));
    let mut inputs = Vec::new();
    for cw in [0x0006u16, 0x0007, 0x000F] {
        for _ in 0..3 {
            inputs = lrw(&mut c, &layouts, &out(cw)).1;
        }
    }
    assert_eq!(drive_in(&inputs[0]).0 & 0x6F, 0x27, "Operation enabled");
    assert_eq!(read(&mut c, layout, 0, 0x6064, 0), 0);
    assert_eq!(
        download(&mut c, layout, 0, 0x607A, 0, &1000i32.to_le_bytes()),
        Ok(())
    );
    for _ in 0..20 {
        c.cycle(Duration::from_millis(1));
    }
    assert_eq!(read(&mut c, layout, 0, 0x6064, 0), 0);
    for _ in 0..3000 {
        lrw(&mut c, &layouts, &out(0x000F));
    }
    assert_eq!(read(&mut c, layout, 0, 0x6064, 0), 1000);
}
