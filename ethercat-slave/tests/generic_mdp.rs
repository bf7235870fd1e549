//! `ethercat-node`'s units whose drives are ETG.5001 MDP 742 channels (the servo and stepper
//! terminals' "DRV" objects), in process on a simulated clock: the test ESIs beside this file (a
//! one-channel servo after the EL7211's layout, a two-channel stepper after the EL7062's), each
//! channel a drive axis; its entries read, written and carried in the process data as the drive's
//! CiA 402 objects; csp ramps to exact targets.

#[path = "common/node.rs"]
mod node;

use std::time::Duration;

use ethercat_slave::generic::mdp::Channels;
use ethercat_slave::generic::GenericUnit;
use ethercat_slave::master::{Layout, SimChain};
use node::*;

fn mdp(name: &str) -> ethercat_slave::generic::Template {
    template(&root().join("ethercat-slave/tests/esi").join(name), None)
}

fn u16_at(b: &[u8], at: usize) -> u16 {
    u16::from_le_bytes([b[at], b[at + 1]])
}

fn i32_at(b: &[u8], at: usize) -> i32 {
    i32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

/// From Init to Op with SYNC0 every 1 ms from `sync0_in` ns on, the process data running `outputs`
/// from Safe-Op on.
fn to_op(c: &mut SimChain<GenericUnit>, layouts: &[Layout], sync0_in: u64, outputs: &[Vec<u8>]) {
    configure(c, layouts);
    assert_eq!(request(c, 0x02), 1);
    c.cycle(Duration::from_millis(1));
    node::sync0(c, 0, 1_000_000, sync0_in);
    assert_eq!(request(c, 0x04), 1);
    assert_eq!(al(c, 0), (0x04, 0), "Safe-Op");
    lrw(c, layouts, outputs);
    assert_eq!(request(c, 0x08), 1);
    assert_eq!(al(c, 0), (0x08, 0), "Op");
}

/// The one-channel servo: channel 0 is drive axis 0 (`m0` in `ethercat-node --list`); its power-on
/// PDOs are csv's (outputs controlword, target velocity: 6 bytes; inputs position, statusword,
/// velocity: 10 bytes); its entries are the drive's objects: the statusword 0x6010:01 reads Switch
/// on disabled (0x0260: bits 6, 5 (no quick stop) and 9 (remote)), the mode 0x7010:03 is the ESI's 9 and 0x6010:03
/// shows it, a mode written to 0x7010:03 is the drive's (and one it does not run, 11 (cst with
/// commutation angle), is refused as 0x6060 refuses it).
#[test]
fn a_servo_terminal_s_channel_is_a_drive_axis() {
    let t = mdp("mdp742-servo-1ch.xml");
    assert_eq!(t.axes(), [0]);
    let channels = t.channels().expect("MDP 742 channels");
    assert_eq!(channels.channels(), [0]);
    assert_eq!(Channels::controlword(1), od::Address::new(0x7110, 1));
    let layout = Layout::of(&t);
    assert_eq!(layout.lengths(), (6, 10));
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    c.cycle(Duration::from_millis(1));
    assert_eq!(read(&mut c, &layout, 0, 0x6010, 1), 0x0260);
    assert_eq!(read(&mut c, &layout, 0, 0x7010, 3), 9);
    assert_eq!(read(&mut c, &layout, 0, 0x6010, 3), 9);
    assert_eq!(download(&mut c, &layout, 0, 0x7010, 3, &[8]), Ok(()));
    assert_eq!(read(&mut c, &layout, 0, 0x6010, 3), 8);
    assert_eq!(
        download(&mut c, &layout, 0, 0x7010, 3, &[11]),
        Err(0x0609_0030)
    );
    assert_eq!(read(&mut c, &layout, 0, 0x7010, 3), 8);
    // The drive's own objects are not the terminal's: no 0x6040 here.
    assert_eq!(
        upload(&mut c, &layout, 0, 0x6040, 0),
        Err(0x0602_0000),
        "0x6040 is no object of an MDP 742 device"
    );
}

/// csp on the servo terminal as a configuration tool sets it up from the ESI: the PDO assignment
/// 0x1C12 = 0x1600 (controlword), 0x1606 (target position) in Pre-Op, mode 8 in 0x7010:03; to Op
/// with SYNC0; enabled by the controlword 0x7010:01, the statusword 0x6010:01 checked at each
/// step; 100 set-points to +10,000, one per cycle, and one second standing: 0x6000:11 exactly
/// 10,000 in the process data and by SDO, 0x6010:06 (following error) 0.
#[test]
fn a_servo_terminal_moves_in_csp_to_its_exact_target() {
    let t = mdp("mdp742-servo-1ch.xml");
    let power_on = Layout::of(&t);
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&power_on));
    request(&mut c, 0x02);
    for (sub, value) in [(0u8, 0u16), (1, 0x1600), (2, 0x1606), (0, 2)] {
        let bytes = if sub == 0 {
            vec![value as u8]
        } else {
            value.to_le_bytes().to_vec()
        };
        assert_eq!(download(&mut c, &power_on, 0, 0x1C12, sub, &bytes), Ok(()));
    }
    assert_eq!(download(&mut c, &power_on, 0, 0x7010, 3, &[8]), Ok(()));
    let layout = Layout::with_lengths(&t, 6, 10);
    let layouts = [layout.clone()];
    let out = |cw: u16, target: i32| {
        let mut b = cw.to_le_bytes().to_vec();
        b.extend_from_slice(&target.to_le_bytes());
        b
    };
    to_op(&mut c, &layouts, 500_000, &[out(0, 0)]);
    for (cw, state) in [(0x0006u16, 0x0021u16), (0x0007, 0x0023), (0x000F, 0x0027)] {
        let mut sw = 0;
        for _ in 0..5 {
            let (_, inputs) = lrw(&mut c, &layouts, &[out(cw, 0)]);
            sw = u16_at(&inputs[0], 4);
        }
        assert_eq!(sw & 0x006F, state, "after {cw:#06x}: {sw:#06x}");
    }
    for n in 1..=100 {
        let (wkc, inputs) = lrw(&mut c, &layouts, &[out(0x000F, 100 * n)]);
        assert_eq!(wkc, 3);
        let sw = u16_at(&inputs[0], 4);
        assert_eq!(sw & 0x206F, 0x0027, "set-point {n}: statusword {sw:#06x}");
    }
    for _ in 0..1000 {
        lrw(&mut c, &layouts, &[out(0x000F, 10_000)]);
    }
    let (_, inputs) = lrw(&mut c, &layouts, &[out(0x000F, 10_000)]);
    assert_eq!(
        (i32_at(&inputs[0], 0), i32_at(&inputs[0], 6)),
        (10_000, 0),
        "position, velocity"
    );
    assert_eq!(read(&mut c, &layout, 0, 0x6000, 0x11), 10_000);
    assert_eq!(read(&mut c, &layout, 0, 0x6010, 6), 0);
    assert_eq!(read(&mut c, &layout, 0, 0x6010, 3), 8);
}

/// The two-channel stepper terminal: channels 0 and 1 (0x7010/0x7110, 0x6010/0x6110) are two
/// independent drive axes, in csp from power-on (its PDOs and 0x7n10:03 say so): channel 0 ramps
/// to +10,000 and channel 1 to −20,000 over 100 set-points, and after one second both stand
/// exactly there (0x6000:11, 0x6100:11).
#[test]
fn a_two_channel_stepper_terminal_moves_both_channels() {
    let t = mdp("mdp742-stepper-2ch.xml");
    assert_eq!(t.axes(), [0, 1]);
    let layout = Layout::of(&t);
    // Outputs: controlword and target position of each channel; inputs: position, statusword,
    // velocity of each.
    assert_eq!(layout.lengths(), (12, 20));
    let layouts = [layout.clone()];
    let mut c = SimChain::with_chain(
        ethercat_slave::generic::chain(
            &[(&t, 1)],
            &ds402::drive::DriveConfig {
                motor: ds402::drive::MotorConfig {
                    kind: ds402::drive::MotorKind::Stepper,
                    ..Default::default()
                },
                ..Default::default()
            },
            Duration::from_micros(1),
            std::time::Instant::now(),
        )
        .unwrap(),
        std::time::Instant::now(),
    );
    let out = |cw: u16, a: i32, b: i32| {
        let mut o = cw.to_le_bytes().to_vec();
        o.extend_from_slice(&a.to_le_bytes());
        o.extend_from_slice(&cw.to_le_bytes());
        o.extend_from_slice(&b.to_le_bytes());
        o
    };
    to_op(&mut c, &layouts, 500_000, &[out(0, 0, 0)]);
    for cw in [0x0006u16, 0x0007, 0x000F] {
        for _ in 0..5 {
            lrw(&mut c, &layouts, &[out(cw, 0, 0)]);
        }
    }
    for n in 1..=100 {
        let (_, inputs) = lrw(&mut c, &layouts, &[out(0x000F, 100 * n, -200 * n)]);
        assert_eq!(
            (
                u16_at(&inputs[0], 4) & 0x206F,
                u16_at(&inputs[0], 14) & 0x206F
            ),
            (0x0027, 0x0027),
            "set-point {n}"
        );
    }
    for _ in 0..1000 {
        lrw(&mut c, &layouts, &[out(0x000F, 10_000, -20_000)]);
    }
    let (_, inputs) = lrw(&mut c, &layouts, &[out(0x000F, 10_000, -20_000)]);
    assert_eq!(
        (i32_at(&inputs[0], 0), i32_at(&inputs[0], 10)),
        (10_000, -20_000)
    );
    assert_eq!(read(&mut c, &layout, 0, 0x6000, 0x11), 10_000);
    assert_eq!(read(&mut c, &layout, 0, 0x6100, 0x11) as i32, -20_000);
}
