//! The master's side of the in-process tests of `ethercat-node`'s units: a chain of templates on
//! the simulated clock, set up as their layouts say, CoE SDO transfers through each unit's own
//! mailbox (framed byte by byte as ETG.1000.6 lays them out), and the corpus beside the checkout.

#![allow(dead_code)]

#[path = "coe.rs"]
mod coe;
pub use coe::{coe_answer, coe_request};

use std::path::PathBuf;
use std::time::{Duration, Instant};

use ethercat_slave::esc::cmd;
use ethercat_slave::frame::Datagram;
use ethercat_slave::generic::{self, GenericUnit, Template};
use ethercat_slave::master::{self as m, Layout, SimChain};

/// The workspace root.
pub fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

/// A file of the shared corpus beside the checkout (`../shared/corpus/esi`); a missing corpus
/// fails the test and says where it was looked for.
pub fn corpus(name: &str) -> PathBuf {
    let path = root().join("../shared/corpus/esi").join(name);
    assert!(
        path.is_file(),
        "{} is missing: the tests read the vendors' ESIs from the corpus beside the checkout",
        path.display()
    );
    path
}

/// The device `device` (type name, name or product code) of the ESI at `path`, with `modules`.
pub fn template_with(
    path: &std::path::Path,
    device: Option<&str>,
    modules: Option<&[&str]>,
) -> Template {
    let spec = ethercat_slave::node_cli::EsiSpec {
        path: path.to_path_buf(),
        units: None,
        device: device.map(str::to_string),
        modules: modules.map(|m| m.iter().map(|s| s.to_string()).collect()),
    };
    ethercat_slave::node_cli::load(&spec).unwrap_or_else(|e| panic!("{e}"))
}

/// The device of the ESI at `path` (the file's only one, or `device`).
pub fn template(path: &std::path::Path, device: Option<&str>) -> Template {
    template_with(path, device, None)
}

/// `examples/drive.esi.xml`.
pub fn drive() -> Template {
    template(&root().join("examples/drive.esi.xml"), None)
}

/// `examples/io-device.esi.xml`.
pub fn io_device() -> Template {
    template(&root().join("examples/io-device.esi.xml"), None)
}

/// A chain of `units` on the simulated clock (process-data cycle 1 µs: every `cycle` runs one).
pub fn chain(units: &[(&Template, usize)]) -> SimChain<GenericUnit> {
    let now = Instant::now();
    let c = generic::chain(
        units,
        &ds402::drive::DriveConfig::default(),
        Duration::from_micros(1),
        now,
    )
    .unwrap();
    SimChain::with_chain(c, now)
}

fn ok<T>(r: Result<T, m::MasterError>) -> T {
    r.unwrap_or_else(|e| panic!("{e}"))
}

/// Station addresses, SyncManagers and FMMUs of every unit.
pub fn configure(c: &mut SimChain<GenericUnit>, layouts: &[Layout]) {
    ok(m::configure_layouts(c, layouts))
}

/// AL status and AL status code of unit `k`.
pub fn al(c: &mut SimChain<GenericUnit>, k: usize) -> (u16, u16) {
    ok(m::al(c, k))
}

/// Requests `state` from every unit (BWR of AL control); the working counter.
pub fn request(c: &mut SimChain<GenericUnit>, state: u8) -> u16 {
    ok(m::request(c, state))
}

/// Requests `state` from unit `k` (FPWR of AL control).
pub fn request_one(c: &mut SimChain<GenericUnit>, k: usize, state: u8) {
    ok(m::fpwr(c, k, 0x0120, vec![state, 0]))
}

/// One LRW of every unit's outputs and a 1 ms cycle: working counter and inputs.
pub fn lrw(
    c: &mut SimChain<GenericUnit>,
    layouts: &[Layout],
    outputs: &[Vec<u8>],
) -> (u16, Vec<Vec<u8>>) {
    ok(m::lrw_layouts(c, layouts, outputs))
}

/// FPRD of `len` bytes at `ado` of unit `k`: data and working counter.
pub fn fprd(c: &mut SimChain<GenericUnit>, k: usize, ado: u16, len: usize) -> (Vec<u8>, u16) {
    ok(m::fprd(c, k, ado, len))
}

/// FPWR that unit `k` must take.
pub fn fpwr(c: &mut SimChain<GenericUnit>, k: usize, ado: u16, data: Vec<u8>) {
    ok(m::fpwr(c, k, ado, data))
}

/// SYNC0 of unit `k` every `cycle_ns` from a start `start_ns` after the unit's system time now
/// (ETG.1000.4 §9.3: cycle time 0x09A0, start time 0x0990, activation 0x0981 = 3).
pub fn sync0(c: &mut SimChain<GenericUnit>, k: usize, cycle_ns: u32, start_ns: u64) {
    let (t, _) = fprd(c, k, 0x0910, 8);
    let now = u64::from_le_bytes(t.try_into().unwrap());
    fpwr(c, k, 0x09A0, cycle_ns.to_le_bytes().to_vec());
    fpwr(c, k, 0x0990, (now + start_ns).to_le_bytes().to_vec());
    fpwr(c, k, 0x0981, vec![0x03]);
}

thread_local! {
    static COUNTERS: std::cell::RefCell<std::collections::HashMap<usize, u8>> = Default::default();
}

/// The next mailbox counter of unit `k`, 1…7 (as a master keeps one per slave: a slave takes a
/// request with its last request's counter for a repeat).
pub fn next_counter(k: usize) -> u8 {
    COUNTERS.with(|c| {
        let mut c = c.borrow_mut();
        let n = c.entry(k).or_insert(0);
        *n = *n % 7 + 1;
        *n
    })
}

/// Writes `request` into unit k's SM0 (padded to its length), waits (a few 1 ms cycles at most) for
/// SM1 to fill and reads it.
pub fn mailbox(
    c: &mut SimChain<GenericUnit>,
    layout: &Layout,
    k: usize,
    request: &[u8],
) -> Vec<u8> {
    let (out, inn) = layout.mailbox().expect("a unit with a mailbox");
    let mut bytes = request.to_vec();
    bytes.resize(usize::from(out.len), 0);
    fpwr(c, k, out.start, bytes);
    for _ in 0..10 {
        let (status, _) = fprd(c, k, 0x080D, 1);
        if status[0] & 0x08 != 0 {
            let (answer, wkc) = fprd(c, k, inn.start, usize::from(inn.len));
            assert_eq!(wkc, 1, "a full SM1 is read");
            return answer;
        }
        c.cycle(Duration::from_millis(1));
    }
    panic!("unit {k} did not answer the mailbox");
}

/// Expedited or normal SDO upload of `index:sub`: the value, or the abort code.
pub fn upload(
    c: &mut SimChain<GenericUnit>,
    layout: &Layout,
    k: usize,
    index: u16,
    sub: u8,
) -> Result<Vec<u8>, u32> {
    let i = index.to_le_bytes();
    let m = mailbox(
        c,
        layout,
        k,
        &coe_request(next_counter(k), &[0x40, i[0], i[1], sub, 0, 0, 0, 0]),
    );
    let sdo = coe_answer(&m)?;
    assert_eq!(&sdo[1..4], &[i[0], i[1], sub], "the answer names the entry");
    if sdo[0] & 0x02 != 0 {
        let n = 4 - usize::from((sdo[0] >> 2) & 0x03);
        Ok(sdo[4..4 + n].to_vec())
    } else {
        let size = u32::from_le_bytes([sdo[4], sdo[5], sdo[6], sdo[7]]) as usize;
        Ok(sdo[8..8 + size].to_vec())
    }
}

/// An upload as an integer (little-endian, sign-extended from its length when `signed`).
pub fn read(c: &mut SimChain<GenericUnit>, layout: &Layout, k: usize, index: u16, sub: u8) -> i64 {
    let b = upload(c, layout, k, index, sub)
        .unwrap_or_else(|code| panic!("upload of {index:04X}:{sub:02X}: abort {code:#010x}"));
    let mut v = [0u8; 8];
    v[..b.len()].copy_from_slice(&b);
    let raw = i64::from_le_bytes(v);
    let shift = 64 - 8 * b.len() as u32;
    (raw << shift) >> shift
}

/// Expedited SDO download of 1–4 bytes: the abort code when refused.
pub fn download(
    c: &mut SimChain<GenericUnit>,
    layout: &Layout,
    k: usize,
    index: u16,
    sub: u8,
    data: &[u8],
) -> Result<(), u32> {
    let i = index.to_le_bytes();
    let mut sdo = vec![0x23 | ((4 - data.len() as u8) << 2), i[0], i[1], sub];
    sdo.extend_from_slice(data);
    sdo.resize(8, 0);
    let m = mailbox(c, layout, k, &coe_request(next_counter(k), &sdo));
    let answer = coe_answer(&m)?;
    assert_eq!(answer[..4], [0x60, i[0], i[1], sub], "download response");
    Ok(())
}

/// A datagram through the chain, answered.
pub fn one(c: &mut SimChain<GenericUnit>, d: Datagram) -> Datagram {
    ok(m::one(c, d))
}

/// A BRD of `len` bytes at `ado`.
pub fn brd(c: &mut SimChain<GenericUnit>, ado: u16, len: usize) -> Datagram {
    one(c, Datagram::new(cmd::BRD, 0, ado, vec![0; len]))
}
