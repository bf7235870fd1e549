//! Two virtual SMD23K-B on one chain, driven the way an EtherCAT master drives them: count, address,
//! read the SII identity, configure SyncManagers and FMMUs, bring them to Op, then exchange process
//! data with one LRW per cycle — a Relative move on each ends with Move_Complete at the target.

use std::time::Duration;

use ds402::smd::binding::Device;
use ds402::smd::indexer::{cmd0, stat0, stat1, Outputs};
use ethercat_slave::al::state;
use ethercat_slave::esc::cmd;
use ethercat_slave::frame::{emit, parse, Datagram};
use ethercat_slave::smd::{decode_outputs, encode_inputs, SmdChain};

const SRC: [u8; 6] = [2, 0, 0, 0, 0, 1];

fn one(c: &mut SmdChain, d: Datagram) -> Datagram {
    let mut f = emit(&[d], SRC);
    c.process(&mut f).unwrap();
    parse(&f).unwrap().remove(0)
}

fn fpwr(c: &mut SmdChain, station: u16, ado: u16, data: Vec<u8>) {
    assert_eq!(
        one(c, Datagram::new(cmd::FPWR, station, ado, data)).wkc,
        1,
        "0x{ado:04X}"
    );
}

fn outputs_bytes(o: &Outputs) -> Vec<u8> {
    let mut b = Vec::new();
    b.extend_from_slice(&o.cmd0.to_le_bytes());
    b.extend_from_slice(&o.cmd1.to_le_bytes());
    b.extend_from_slice(&o.position.to_le_bytes());
    b.extend_from_slice(&o.velocity.to_le_bytes());
    for w in [o.acceleration, o.deceleration, o.motor_current, o.jerk] {
        b.extend_from_slice(&w.to_le_bytes());
    }
    b
}

#[test]
fn two_units_from_init_to_a_relative_move() {
    let mut c = SmdChain::new(Device::Smd23kB, 2).unwrap();
    assert_eq!(
        one(&mut c, Datagram::new(cmd::BRD, 0, 0, vec![0; 2])).wkc,
        2
    );
    for k in 0..2u16 {
        let r = one(
            &mut c,
            Datagram::new(
                cmd::APWR,
                0u16.wrapping_sub(k),
                0x0010,
                (0x1001 + k).to_le_bytes().to_vec(),
            ),
        );
        assert_eq!(r.wkc, 1);
    }
    // The SII identity through the EEPROM interface of unit 2: serial number 2.
    fpwr(&mut c, 0x1002, 0x0504, 0x0Eu32.to_le_bytes().to_vec());
    fpwr(&mut c, 0x1002, 0x0502, 0x0100u16.to_le_bytes().to_vec());
    let serial = one(&mut c, Datagram::new(cmd::FPRD, 0x1002, 0x0508, vec![0; 4]));
    assert_eq!(serial.data, 2u32.to_le_bytes());
    // SyncManagers as the ESI gives them, FMMUs: outputs at logical 20·k, inputs at 40 + 20·k.
    for k in 0..2u16 {
        let st = 0x1001 + k;
        for (n, start, len, control) in [
            (0u16, 0x1000u16, 128u16, 0x26u8),
            (1, 0x1080, 128, 0x22),
            (2, 0x1100, 20, 0x64),
            (3, 0x1400, 20, 0x20),
        ] {
            let mut r = start.to_le_bytes().to_vec();
            r.extend_from_slice(&len.to_le_bytes());
            r.extend_from_slice(&[control, 0, 1, 0]);
            fpwr(&mut c, st, 0x0800 + 8 * n, r);
        }
        for (n, logical, phys, rw) in [
            (0u16, 20 * u32::from(k), 0x1100u16, 2u8),
            (1, 40 + 20 * u32::from(k), 0x1400, 1),
        ] {
            let mut r = logical.to_le_bytes().to_vec();
            r.extend_from_slice(&20u16.to_le_bytes());
            r.extend_from_slice(&[0, 7]);
            r.extend_from_slice(&phys.to_le_bytes());
            r.extend_from_slice(&[0, rw, 1, 0, 0, 0]);
            fpwr(&mut c, st, 0x0600 + 16 * n, r);
        }
    }
    for s in [state::PREOP, state::SAFEOP] {
        assert_eq!(
            one(&mut c, Datagram::new(cmd::BWR, 0, 0x0120, vec![s, 0])).wkc,
            2
        );
        let r = one(&mut c, Datagram::new(cmd::BRD, 0, 0x0130, vec![0; 2]));
        assert_eq!(r.data[0], s, "both in state {s}");
    }
    // Safe-Op: inputs flow, PreOp_SafeOp is set; outputs are not acted on.
    c.cycle(Duration::from_millis(1));
    let lrw = |c: &mut SmdChain, o: [&Outputs; 2]| {
        let mut data = outputs_bytes(o[0]);
        data.extend(outputs_bytes(o[1]));
        data.extend([0u8; 40]);
        let r = one(
            c,
            Datagram {
                cmd: cmd::LRW,
                index: 0,
                address: 0,
                data,
                wkc: 0,
            },
        );
        c.cycle(Duration::from_millis(1));
        let at = |k: usize| -> [u8; 20] { r.data[40 + 20 * k..60 + 20 * k].try_into().unwrap() };
        (r.wkc, at(0), at(1))
    };
    let idle = Outputs::default();
    let (wkc, in0, _) = lrw(&mut c, [&idle, &idle]);
    assert_eq!(
        wkc, 6,
        "each unit: the input FMMU read (1) and the output FMMU write (2)"
    );
    let status1 = u16::from_le_bytes([in0[2], in0[3]]);
    assert_ne!(status1 & stat1::PREOP_SAFEOP, 0);
    assert_eq!(
        one(
            &mut c,
            Datagram::new(cmd::BWR, 0, 0x0120, vec![state::OP, 0])
        )
        .wkc,
        2
    );
    let mut o = [Outputs {
        cmd1: 0x8000,
        velocity: 10_000,
        acceleration: 100,
        deceleration: 100,
        ..Outputs::default()
    }; 2];
    o[0].cmd0 = cmd0::PRESET_POSITION;
    o[1].cmd0 = cmd0::PRESET_POSITION;
    lrw(&mut c, [&o[0], &o[1]]);
    o[0].cmd0 = 0;
    o[1].cmd0 = 0;
    lrw(&mut c, [&o[0], &o[1]]);
    o[0] = Outputs {
        cmd0: cmd0::RELATIVE_MOVE,
        position: 5_000,
        ..o[0]
    };
    o[1] = Outputs {
        cmd0: cmd0::RELATIVE_MOVE,
        position: -2_000,
        ..o[1]
    };
    let mut last = ([0u8; 20], [0u8; 20]);
    for _ in 0..5_000 {
        let (wkc, a, b) = lrw(&mut c, [&o[0], &o[1]]);
        assert_eq!(wkc, 6, "each unit: read 1 + write 2");
        last = (a, b);
        let done = |x: &[u8; 20]| u16::from_le_bytes([x[0], x[1]]) & stat0::MOVE_COMPLETE != 0;
        if done(&a) && done(&b) {
            break;
        }
    }
    let pos = |x: &[u8; 20]| i32::from_le_bytes([x[4], x[5], x[6], x[7]]);
    assert_eq!((pos(&last.0), pos(&last.1)), (5_000, -2_000));
    let s1 = u16::from_le_bytes([last.0[2], last.0[3]]);
    assert_eq!(s1 & stat1::PREOP_SAFEOP, 0, "in Op");
    // The codec round trip used above.
    let o2 = decode_outputs(&outputs_bytes(&o[1]).try_into().unwrap());
    assert_eq!(o2, o[1]);
    assert_eq!(
        encode_inputs(&c.unit(0).unwrap().inputs())[4..8],
        5_000i32.to_le_bytes()
    );
}
