//! FoE on `ethercat-node`'s units in process, byte by byte: `examples/foe-device.esi.xml` (FoE and
//! a bootstrap mailbox of its own) beside `examples/io-device.esi.xml` (CoE only), their mailboxes
//! written and read through SM0/SM1 as a master does, every mailbox worked out from ETG.1000.4
//! §5.6 (header: length, address, channel/priority, type 4 = FoE with the counter in the high
//! nibble) and ETG.1000.6 §5.9 (the FoE frame).

#[path = "common/node.rs"]
mod node;

use std::time::Duration;

use ethercat_slave::generic::GenericUnit;
use ethercat_slave::master::{Layout, SimChain};
use node::*;

fn foe_device() -> ethercat_slave::generic::Template {
    template(&root().join("examples/foe-device.esi.xml"), None)
}

/// Bytes from hexadecimal, then `tail`.
fn h(text: &str, tail: &[u8]) -> Vec<u8> {
    let mut v: Vec<u8> = text
        .split_whitespace()
        .filter(|t| *t != "|")
        .map(|b| u8::from_str_radix(b, 16).unwrap())
        .collect();
    v.extend_from_slice(tail);
    v
}

/// An FoE mailbox of `frame` with `counter` (address 0, channel 0, priority 0).
fn foe(counter: u8, frame: &[u8]) -> Vec<u8> {
    let mut m = (frame.len() as u16).to_le_bytes().to_vec();
    m.extend_from_slice(&[0, 0, 0, 0x04 | (counter << 4)]);
    m.extend_from_slice(frame);
    m
}

/// The mailbox answer in SM1 as long as its header says (the rest of SM1 is zeros).
fn answer(m: &[u8]) -> Vec<u8> {
    let len = usize::from(u16::from_le_bytes([m[0], m[1]]));
    assert!(
        m[6 + len..].iter().all(|&b| b == 0),
        "zeros after the mailbox"
    );
    m[..6 + len].to_vec()
}

/// `request` into unit k's SM0 (padded to `layout`'s length), a few cycles, and no answer in SM1.
fn send_only(c: &mut SimChain<GenericUnit>, layout: &Layout, k: usize, request: &[u8]) {
    let (out, _) = layout.mailbox().unwrap();
    let mut bytes = request.to_vec();
    bytes.resize(usize::from(out.len), 0);
    fpwr(c, k, out.start, bytes);
    for _ in 0..5 {
        c.cycle(Duration::from_millis(1));
    }
    let (status, _) = fprd(c, k, 0x080D, 1);
    assert_eq!(status[0] & 0x08, 0, "SM1 stays empty");
}

/// `n` bytes 0, 1, 2, …
fn file(n: usize) -> Vec<u8> {
    (0..n).map(|k| (k % 251) as u8).collect()
}

/// The foe-device and the io-device in Pre-Op.
fn pre_op() -> (SimChain<GenericUnit>, Vec<Layout>) {
    let (f, io) = (foe_device(), io_device());
    let mut c = chain(&[(&f, 1), (&io, 1)]);
    let layouts = vec![Layout::of(&f), Layout::of(&io)];
    configure(&mut c, &layouts);
    assert_eq!(request(&mut c, 0x02), 2);
    (c, layouts)
}

/// A write of 126 bytes through 128-byte mailboxes: Write request `0B 00 00 00 00 14 | 02 00 00 00
/// 00 00 "a.txt"` → Ack 0 `06 00 00 00 00 14 | 04 00 00 00 00 00` (the slave's counter 1); Data 1
/// with 116 bytes (128 − 12: a full packet) → Ack 1; Data 2 with 10 bytes → Ack 2, and the chain
/// hands the file to the edge. Read back: Data 1 `7A 00 00 00 00 44 | 03 00 01 00 00 00` + 116
/// bytes, Ack 1 → Data 2 with 10 bytes, Ack 2 → nothing. A repeated request (same counter) gets
/// the same answer; an FoE mailbox shorter than the FoE header is mailbox error 0x0006.
#[test]
fn a_file_through_the_mailbox_byte_by_byte() {
    let (mut c, layouts) = pre_op();
    let l = &layouts[0];
    let data = file(126);
    let write = foe(1, &h("02 00 00 00 00 00", b"a.txt"));
    assert_eq!(write[..6], h("0B 00 00 00 00 14", &[]));
    let ack0 = h("06 00 00 00 00 14 | 04 00 00 00 00 00", &[]);
    assert_eq!(answer(&mailbox(&mut c, l, 0, &write)), ack0);
    assert_eq!(answer(&mailbox(&mut c, l, 0, &write)), ack0, "a repeat");
    let data1 = foe(2, &h("03 00 01 00 00 00", &data[..116]));
    assert_eq!(data1.len(), 128);
    assert_eq!(
        answer(&mailbox(&mut c, l, 0, &data1)),
        h("06 00 00 00 00 24 | 04 00 01 00 00 00", &[])
    );
    assert!(c.poll_written().is_none());
    assert_eq!(
        answer(&mailbox(
            &mut c,
            l,
            0,
            &foe(3, &h("03 00 02 00 00 00", &data[116..]))
        )),
        h("06 00 00 00 00 34 | 04 00 02 00 00 00", &[])
    );
    let (unit, name, contents) = c.poll_written().expect("the file for the edge");
    assert_eq!(
        (unit, name.as_slice(), &contents[..]),
        (0, &b"a.txt"[..], &data[..])
    );
    assert!(c.poll_written().is_none());
    assert_eq!(
        answer(&mailbox(
            &mut c,
            l,
            0,
            &foe(4, &h("01 00 00 00 00 00", b"a.txt"))
        )),
        h("7A 00 00 00 00 44 | 03 00 01 00 00 00", &data[..116])
    );
    assert_eq!(
        answer(&mailbox(
            &mut c,
            l,
            0,
            &foe(5, &h("04 00 01 00 00 00", &[]))
        )),
        h("10 00 00 00 00 54 | 03 00 02 00 00 00", &data[116..])
    );
    send_only(&mut c, l, 0, &foe(6, &h("04 00 02 00 00 00", &[])));
    assert_eq!(
        answer(&mailbox(&mut c, l, 0, &foe(7, &h("04 00 02", &[])))),
        h("04 00 00 00 00 60 | 01 00 06 00", &[])
    );
}

/// FoE to a unit whose ESI does not offer it: the mailbox error reply 0x0002 (unsupported
/// protocol, ETG.1000.4 §5.6), `04 00 00 00 00 10 | 01 00 02 00`.
#[test]
fn a_unit_without_foe_answers_unsupported_protocol() {
    let (mut c, layouts) = pre_op();
    let read = foe(1, &h("01 00 00 00 00 00", b"a.txt"));
    assert_eq!(
        answer(&mailbox(&mut c, &layouts[1], 1, &read)),
        h("04 00 00 00 00 10 | 01 00 02 00", &[])
    );
    assert!(c.slot(1).unwrap().foe().is_none());
    assert!(c.slot(0).unwrap().foe().is_some());
}

/// Firmware (`*.efw`) outside Bootstrap: `05 00 09 80 00 00` "firmware is written in Bootstrap".
/// Init, SM0/SM1 at the bootstrap mailbox of the SII (words 0x14–0x17: 0x1200, 256, 0x1300, 256;
/// the mailbox protocols word 0x1C says CoE and FoE, 0x000C) and Bootstrap: CoE is the mailbox
/// error 0x0002 there; the firmware goes in packets of 244 bytes (256 − 12); another file is
/// `05 00 08 80 00 00`. Back in Pre-Op the firmware reads back in packets of 116.
#[test]
fn firmware_goes_in_bootstrap_through_its_own_mailbox() {
    let (mut c, layouts) = pre_op();
    let l = &layouts[0];
    let mut refusal = h("26 00 00 00 00 14 | 05 00 09 80 00 00", &[]);
    refusal.extend_from_slice(b"firmware is written in Bootstrap");
    let write = foe(1, &h("02 00 00 00 00 00", b"fw.efw"));
    assert_eq!(answer(&mailbox(&mut c, l, 0, &write)), refusal);
    let sii = &c.chain.chain.slaves[0].sii;
    assert_eq!(
        sii[0x28..0x30],
        [0x00, 0x12, 0x00, 0x01, 0x00, 0x13, 0x00, 0x01]
    );
    assert_eq!(sii[0x38..0x3A], [0x0C, 0x00]);
    request_one(&mut c, 0, 0x01);
    fpwr(
        &mut c,
        0,
        0x0800,
        vec![0x00, 0x12, 0x00, 0x01, 0x26, 0, 1, 0],
    );
    fpwr(
        &mut c,
        0,
        0x0808,
        vec![0x00, 0x13, 0x00, 0x01, 0x22, 0, 1, 0],
    );
    request_one(&mut c, 0, 0x03);
    c.cycle(Duration::from_millis(1));
    assert_eq!(al(&mut c, 0), (0x03, 0), "Bootstrap");
    let mut boot = l.clone();
    boot.sms[0].as_mut().unwrap().start = 0x1200;
    boot.sms[0].as_mut().unwrap().len = 256;
    boot.sms[1].as_mut().unwrap().start = 0x1300;
    boot.sms[1].as_mut().unwrap().len = 256;
    let upload = coe_request(1, &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]);
    assert_eq!(
        answer(&mailbox(&mut c, &boot, 0, &upload)),
        h("04 00 00 00 00 10 | 01 00 02 00", &[])
    );
    let firmware = file(600);
    assert_eq!(
        answer(&mailbox(
            &mut c,
            &boot,
            0,
            &foe(2, &h("02 00 00 00 00 00", b"fw.efw"))
        )),
        h("06 00 00 00 00 24 | 04 00 00 00 00 00", &[])
    );
    for (k, chunk) in firmware.chunks(244).enumerate() {
        let p = k as u8 + 1;
        let counter = 3 + k as u8;
        let mut frame = vec![0x03, 0x00, p, 0, 0, 0];
        frame.extend_from_slice(chunk);
        assert_eq!(
            answer(&mailbox(&mut c, &boot, 0, &foe(counter, &frame))),
            [6, 0, 0, 0, 0, 0x04 | (counter << 4), 0x04, 0x00, p, 0, 0, 0],
            "packet {p}"
        );
    }
    let (_, name, contents) = c.poll_written().unwrap();
    assert_eq!((name.as_slice(), contents.len()), (&b"fw.efw"[..], 600));
    let mut other = h("2B 00 00 00 00 64 | 05 00 08 80 00 00", &[]);
    other.extend_from_slice(b"only firmware is written in Bootstrap");
    assert_eq!(
        answer(&mailbox(
            &mut c,
            &boot,
            0,
            &foe(6, &h("02 00 00 00 00 00", b"x.txt"))
        )),
        other
    );
    request_one(&mut c, 0, 0x01);
    configure(&mut c, &layouts);
    request_one(&mut c, 0, 0x02);
    c.cycle(Duration::from_millis(1));
    assert_eq!(al(&mut c, 0), (0x02, 0));
    let mut read = Vec::new();
    let mut m = answer(&mailbox(
        &mut c,
        l,
        0,
        &foe(1, &h("01 00 00 00 00 00", b"fw.efw")),
    ));
    for p in 1u8.. {
        assert_eq!(m[6..12], [0x03, 0x00, p, 0, 0, 0]);
        read.extend_from_slice(&m[12..]);
        let ack = foe(1 + p, &[0x04, 0x00, p, 0, 0, 0]);
        if m.len() - 12 < 116 {
            send_only(&mut c, l, 0, &ack);
            break;
        }
        m = answer(&mailbox(&mut c, l, 0, &ack));
    }
    assert_eq!(read, firmware);
}

/// Init ends an FoE transfer (the files stay): a Data packet after it has no write (0x8004); a
/// transfer left alone puts its deadline, 10 s on, into the chain's next timeout.
#[test]
fn init_ends_a_transfer_and_its_timer_is_the_chains() {
    let (mut c, layouts) = pre_op();
    let l = &layouts[0];
    mailbox(&mut c, l, 0, &foe(1, &h("02 00 00 00 00 00", b"kept")));
    mailbox(&mut c, l, 0, &foe(2, &h("03 00 01 00 00 00", b"k")));
    mailbox(&mut c, l, 0, &foe(3, &h("02 00 00 00 00 00", b"w")));
    let started = c.now;
    c.advance(Duration::from_millis(1));
    assert!(c.poll_timeout().is_some());
    let foe_server = c.slot(0).unwrap().foe().unwrap();
    assert!(foe_server.is_busy());
    assert!(foe_server.poll_timeout().unwrap() <= started + Duration::from_secs(10));
    request(&mut c, 0x01);
    configure(&mut c, &layouts);
    request(&mut c, 0x02);
    let mut illegal = h("1A 00 00 00 00 14 | 05 00 04 80 00 00", &[]);
    illegal.extend_from_slice(b"no write in progress");
    assert_eq!(
        answer(&mailbox(
            &mut c,
            l,
            0,
            &foe(1, &h("03 00 01 00 00 00", b"w"))
        )),
        illegal
    );
    let store = c.slot(0).unwrap().foe().unwrap().store();
    assert_eq!(store.get(b"kept").map(|f| f.to_vec()), Some(b"k".to_vec()));
    assert!(store.get(b"w").is_none());
}

/// The chain runs the FoE timer: a write left alone for the 10 s of the default configuration
/// ends (its bytes dropped) when the chain's time passes it, as any of its timers. The template
/// says which units have FoE and Bootstrap, and a configuration given to it keeps what the ESI says
/// of Bootstrap.
#[test]
fn the_chain_times_a_transfer_out() {
    let (mut c, layouts) = pre_op();
    mailbox(
        &mut c,
        &layouts[0],
        0,
        &foe(1, &h("02 00 00 00 00 00", b"w")),
    );
    mailbox(
        &mut c,
        &layouts[0],
        0,
        &foe(2, &h("03 00 01 00 00 00", &[7; 116])),
    );
    c.cycle(Duration::from_secs(9));
    assert!(c.slot(0).unwrap().foe().unwrap().is_busy());
    c.cycle(Duration::from_secs(1));
    assert!(!c.slot(0).unwrap().foe().unwrap().is_busy());
    assert!(c
        .slot(0)
        .unwrap()
        .foe()
        .unwrap()
        .store()
        .get(b"w")
        .is_none());
    let mut f = foe_device();
    assert!(f.foe().unwrap().boot);
    assert!(io_device().foe().is_none());
    f.set_foe(&ethercat_slave::foe::FoeConfig {
        max_file: 10,
        ..Default::default()
    });
    assert_eq!(
        (f.foe().unwrap().max_file, f.foe().unwrap().boot),
        (10, true)
    );
}
