//! Every answer of two scripted master sessions pinned byte for byte: a chain of SMD units and a
//! chain of `ethercat-node`'s example drives, each from power-on through the start-up (station
//! addresses, SII by the EEPROM interface, SyncManagers, FMMUs, AL states, a refused request and
//! its acknowledgement), Distributed Clocks (receive times latched, system time read, FRMW and
//! ARMW of it, SYNC0), CoE SDO transfers through the mailbox, frames of several datagrams (NOP,
//! APRW, BRW, LRD, LWR beside an LRW) and process data in Op over many cycles, and frames that are
//! dropped. The whole transcript (each frame sent, its answer or why it was dropped, and each cycle
//! run) is pinned by its digest, and a few answers by their bytes, so that any change in what the
//! emulator answers shows here.

#[path = "common/coe.rs"]
#[allow(dead_code)]
mod coe;

use std::time::{Duration, Instant};

use coe::coe_request;
use ds402::smd::indexer::Outputs;
use ethercat_slave::esc::al::state;
use ethercat_slave::esc::cmd;
use ethercat_slave::frame::{emit, Datagram};
use ethercat_slave::generic::{self, GenericUnit};
use ethercat_slave::master::{self as m, Layout, SimChain, Wire, MBX_IN, MBX_LEN, MBX_OUT, SRC};
use ethercat_slave::smd::binding::Device;
use ethercat_slave::unit::Model;

/// A wire that writes down every frame it carries, the answer (or why there was none) and every
/// cycle it runs.
struct Recorder<M> {
    chain: SimChain<M>,
    transcript: Vec<u8>,
    frames: usize,
    /// The answers, in order.
    answers: Vec<Vec<u8>>,
}

impl<M: Model> Recorder<M> {
    fn new(chain: SimChain<M>) -> Recorder<M> {
        Recorder {
            chain,
            transcript: Vec::new(),
            frames: 0,
            answers: Vec::new(),
        }
    }

    fn note(&mut self, tag: u8, bytes: &[u8]) {
        self.transcript.push(tag);
        self.transcript
            .extend_from_slice(&(bytes.len() as u32).to_le_bytes());
        self.transcript.extend_from_slice(bytes);
    }

    /// A frame of `datagrams` through the chain: the answer.
    fn frame(&mut self, datagrams: &[Datagram]) -> Vec<u8> {
        let mut f = emit(datagrams, SRC);
        assert!(self.exchange(&mut f), "the frame is answered");
        f
    }

    /// Raw bytes through the chain: the answer, or `None` when the frame is dropped.
    fn raw(&mut self, bytes: &[u8]) -> Option<Vec<u8>> {
        let mut f = bytes.to_vec();
        self.exchange(&mut f).then_some(f)
    }

    /// FNV-1a (64 bits) of the transcript.
    fn digest(&self) -> u64 {
        self.transcript.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
            (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01B3)
        })
    }
}

impl<M: Model> Wire for Recorder<M> {
    fn exchange(&mut self, frame: &mut Vec<u8>) -> bool {
        self.note(b'>', frame);
        self.frames += 1;
        match self.chain.process(frame) {
            Ok(()) => {
                self.note(b'<', frame);
                self.answers.push(frame.clone());
                true
            }
            Err(e) => {
                self.note(b'!', e.to_string().as_bytes());
                false
            }
        }
    }

    fn pass(&mut self, dt: Duration) {
        self.note(b'~', &dt.as_nanos().to_le_bytes());
        self.chain.cycle(dt);
    }

    fn units(&self) -> usize {
        self.chain.len()
    }
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

fn fprd(k: usize, ado: u16, len: usize) -> Datagram {
    Datagram::new(cmd::FPRD, m::station(k), ado, vec![0; len])
}

fn fpwr(k: usize, ado: u16, data: Vec<u8>) -> Datagram {
    Datagram::new(cmd::FPWR, m::station(k), ado, data)
}

/// What both sessions do once their units are configured and in Op: DC, the EEPROM interface,
/// an SDO upload and download of `(index, sub)` by unit 0's mailbox (SM0 at `mbx_out`, SM1 at
/// `mbx_in`, `mbx_len` bytes), frames of several datagrams beside `lrw`, and dropped frames. The
/// answers pinned by their bytes: the first SDO upload's, the last frame of several datagrams and
/// the last LRW.
fn common_part<M: Model>(
    r: &mut Recorder<M>,
    lrw: &Datagram,
    mailbox: (u16, u16, usize),
    (index, sub): (u16, u8),
) -> [Vec<u8>; 3] {
    let mut upload = None;
    let units = r.units();
    // Distributed Clocks: receive times latched by a broadcast write, read back with the system
    // time; the reference clock's time spread by FRMW and by ARMW; SYNC0 on unit 0.
    r.frame(&[Datagram::new(cmd::BWR, 0, 0x0900, vec![0; 4])]);
    for k in 0..units {
        r.frame(&[fprd(k, 0x0900, 16), fprd(k, 0x0910, 8), fprd(k, 0x0918, 8)]);
    }
    r.frame(&[Datagram::new(cmd::FRMW, m::station(0), 0x0910, vec![0; 8])]);
    r.frame(&[Datagram::new(cmd::ARMW, 0, 0x0910, vec![0; 8])]);
    r.frame(&[fprd(0, 0x092C, 4), fprd(units - 1, 0x092C, 4)]);
    let now = r.frame(&[fprd(0, 0x0910, 8)]);
    let t = u64::from_le_bytes(now[26..34].try_into().unwrap());
    r.frame(&[
        fpwr(0, 0x09A0, 2_000_000u32.to_le_bytes().to_vec()),
        fpwr(0, 0x0990, (t + 3_000_000).to_le_bytes().to_vec()),
        fpwr(0, 0x0981, vec![0x03]),
    ]);
    // The EEPROM interface: identity words and the serial number.
    for word in [0x0008u32, 0x000E] {
        r.frame(&[fpwr(0, 0x0504, word.to_le_bytes().to_vec())]);
        r.frame(&[fpwr(0, 0x0502, 0x0100u16.to_le_bytes().to_vec())]);
        r.frame(&[fprd(0, 0x0502, 2), fprd(0, 0x0508, 8)]);
    }
    // SDO upload and expedited download through unit 0's mailbox, with the master polling SM1's
    // status between cycles.
    let (out, inn, len) = mailbox;
    let i = index.to_le_bytes();
    for (counter, sdo) in [
        (1u8, vec![0x40, i[0], i[1], sub, 0, 0, 0, 0]),
        (2, vec![0x2B, i[0], i[1], sub, 0x34, 0x12, 0, 0]),
        (3, vec![0x40, i[0], i[1], sub, 0, 0, 0, 0]),
        (4, vec![0x40, 0x18, 0x10, 0x04, 0, 0, 0, 0]),
    ] {
        let mut mbx = coe_request(counter, &sdo);
        mbx.resize(len, 0);
        r.frame(&[fpwr(0, out, mbx)]);
        for _ in 0..3 {
            r.frame(&[fprd(0, 0x080D, 1), lrw.clone()]);
            r.pass(Duration::from_millis(1));
        }
        let answer = r.frame(&[fprd(0, inn, len)]);
        upload.get_or_insert(answer);
    }
    // Several datagrams in one frame: a NOP, AL status by broadcast, an APRW of user RAM, a BRW
    // of it, the process data by LRD, LWR and LRW, a read of an address no unit has.
    let n = lrw.data.len();
    let mut several = Vec::new();
    for step in 0..4u8 {
        several = r.frame(&[
            Datagram::new(cmd::NOP, 0, 0x0000, vec![0xA5; 3]),
            Datagram::new(cmd::BRD, 0, 0x0130, vec![0; 6]),
            Datagram::new(cmd::APRW, 0, 0x0F80, vec![step; 4]),
            Datagram::new(cmd::BRW, 0, 0x0F80, vec![step << 4; 4]),
            Datagram {
                cmd: cmd::LRD,
                index: 1,
                address: 0,
                data: vec![0; n],
                wkc: 0,
            },
            Datagram {
                cmd: cmd::LWR,
                index: 2,
                address: 0,
                data: lrw.data.clone(),
                wkc: 0,
            },
            lrw.clone(),
            Datagram::new(cmd::FPRD, 0x7777, 0x0000, vec![0; 2]),
        ]);
        r.pass(Duration::from_millis(1));
    }
    // A refused request (Bootstrap) and its acknowledgement back to Op.
    r.frame(&[Datagram::new(cmd::BWR, 0, 0x0120, vec![state::BOOT, 0])]);
    r.frame(&[Datagram::new(cmd::BRD, 0, 0x0130, vec![0; 6])]);
    r.frame(&[Datagram::new(
        cmd::BWR,
        0,
        0x0120,
        vec![state::OP | 0x10, 0],
    )]);
    r.frame(&[Datagram::new(cmd::BRD, 0, 0x0130, vec![0; 6])]);
    // Dropped: another EtherType, a truncated datagram, a frame type other than commands.
    let good = emit(&[fprd(0, 0x0130, 2)], SRC);
    let mut other = good.clone();
    other[12] = 0x08;
    assert_eq!(r.raw(&other), None);
    assert_eq!(r.raw(&good[..20]), None);
    let mut kind = good.clone();
    kind[15] = 0x40;
    assert_eq!(r.raw(&kind), None);
    // Mailbox answers in SM1 read once more, and the process data over many cycles.
    r.frame(&[fprd(0, inn, len.min(16)), fprd(0, 0x0808, 16)]);
    let mut last = Vec::new();
    for _ in 0..50 {
        last = r.frame(std::slice::from_ref(lrw));
        r.pass(Duration::from_micros(500));
    }
    [upload.unwrap(), several, last]
}

/// Two SMD units from power-on: the start-up, a relative move in Op, the common part.
fn smd_session() -> (
    Recorder<ethercat_slave::smd::binding::SmdUnit>,
    [Vec<u8>; 3],
) {
    let mut r = Recorder::new(SimChain::new(Device::Smd23kB, 2).unwrap());
    // Slaves counted, SII words read by position.
    r.frame(&[Datagram::new(cmd::BRD, 0, 0x0000, vec![0; 2])]);
    m::bring_up(&mut r, state::OP).unwrap();
    // A relative move on unit 1, then cycles.
    let mut outputs = vec![Outputs::default(); 2];
    for cycle in 0..30u16 {
        outputs[1].cmd0 = if cycle < 10 { 0x0000 } else { 0x0002 };
        outputs[1].position = 1000;
        outputs[1].velocity = 5000;
        outputs[1].acceleration = 100;
        outputs[1].deceleration = 100;
        outputs[1].motor_current = 10;
        m::lrw(&mut r, &outputs).unwrap();
    }
    let lrw = m::lrw_datagram(&outputs, 2);
    let pinned = common_part(&mut r, &lrw, (MBX_OUT, MBX_IN, MBX_LEN), (0x8010, 0x03));
    (r, pinned)
}

/// Two example drives of `ethercat-node` from power-on: the start-up with their layouts, the
/// drives enabled in Op, the common part.
fn node_session() -> (Recorder<GenericUnit>, [Vec<u8>; 3]) {
    let path = std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/drive.esi.xml"
    ));
    let spec = ethercat_slave::node_cli::EsiSpec {
        path: path.to_path_buf(),
        units: None,
        device: None,
        modules: None,
    };
    let template = ethercat_slave::node_cli::load(&spec).unwrap();
    let now = Instant::now();
    let chain = generic::chain(
        &[(&template, 2)],
        &ds402::drive::DriveConfig::default(),
        Duration::from_micros(1),
        now,
    )
    .unwrap();
    let mut r = Recorder::new(SimChain::with_chain(chain, now));
    let layouts = vec![Layout::of(&template); 2];
    m::configure_layouts(&mut r, &layouts).unwrap();
    for s in [state::PREOP, state::SAFEOP] {
        m::request(&mut r, s).unwrap();
    }
    let (out_len, _) = layouts[0].lengths();
    let out = |cw: u16| {
        let mut b = cw.to_le_bytes().to_vec();
        b.resize(out_len, 0);
        b[6] = 8; // csp
        b
    };
    m::lrw_layouts(&mut r, &layouts, &[out(0), out(0)]).unwrap();
    m::request(&mut r, state::OP).unwrap();
    for cw in [0x0006u16, 0x0007, 0x000F, 0x000F, 0x000F] {
        m::lrw_layouts(&mut r, &layouts, &[out(cw), out(cw)]).unwrap();
    }
    let total: usize = layouts.iter().map(|l| l.lengths().0 + l.lengths().1).sum();
    let mut data = vec![0u8; total];
    data[..out_len].copy_from_slice(&out(0x000F));
    let lrw = Datagram {
        cmd: cmd::LRW,
        index: 0,
        address: 0,
        data,
        wkc: 0,
    };
    let (mbx_out, mbx_in) = layouts[0].mailbox().expect("the drive has a mailbox");
    let pinned = common_part(
        &mut r,
        &lrw,
        (mbx_out.start, mbx_in.start, usize::from(mbx_in.len)),
        (0x6060, 0x00),
    );
    (r, pinned)
}

/// The SMD session's transcript and some of its answers.
#[test]
fn smd_units_answer_as_pinned() {
    let (r, pinned) = smd_session();
    assert_eq!((r.frames, r.answers.len()), (151, 148));
    assert_eq!(format!("{:016x}", r.digest()), "8eec3032d0a71361");
    let pinned: Vec<String> = pinned.iter().map(|a| hex(a)).collect();
    assert_eq!(
        pinned,
        [
            "ffffffffffff02000000000188a48c10040001108010800000000a00000000130030431080038d000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000100",
            "ffffffffffff02000000000188a4631100000000000003800000a5a5a5000007000200300106800000080000000000020003000200800f0480000020202020030009000200800f048000003333333306000a01000000005080000000000000000000000000000000000000000000000000000000000000000000000000000000000000084400000000000000000000000000000a000000085400000000000000000000000000000a00000002000b020000000050800000000000000000000000000000000000000000000002000000e803000088130000640064000a0000000000000000000000000000000000000000000000000000000000000000000000000000000000000002000c000000000050800000000000000000000000000000000000000000000002000000e803000088130000640064000a000000084400000000000000000000000000000a000000085400000000000000000000000000000a00000006000400777700000200000000000000",
            "ffffffffffff02000000000188a45c100c000000000050000000000000000000000000000000000000000000000002000000e803000088130000640064000a000000084400000000000000000000000000000a000000085400000000000000000000000000000a0000000600",
        ]
    );
}

/// The node session's transcript and some of its answers.
#[test]
fn node_units_answer_as_pinned() {
    let (r, pinned) = node_session();
    assert_eq!((r.frames, r.answers.len()), (119, 116));
    assert_eq!(format!("{:016x}", r.digest()), "f87123ec23331a66");
    let pinned: Vec<String> = pinned.iter().map(|a| hex(a)).collect();
    assert_eq!(
        pinned,
        [
            "ffffffffffff02000000000188a48c10040001100011800000000a000000001300304f60600008000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000100",
            "ffffffffffff02000000000188a4f71000000000000003800000a5a5a5000007000200300106800000080000000000020003000200800f0480000020202020030009000200800f048000003333333306000a01000000002c800000000000000000000000000000000037120000000000000000000000000860020000000000000000000000000002000b02000000002c8000000f0000000000080000000000000000000000000000000000000000000000000000000000000000000000000002000c00000000002c8000000f0000000000080000000000000037120000000000000000000000000860020000000000000000000000000006000400777700000200000000000000",
            "ffffffffffff02000000000188a438100c00000000002c0000000f000000000008000000000000003712000000000000000000000000086002000000000000000000000000000600",
        ]
    );
}
