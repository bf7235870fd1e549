//! The master's side of the in-process tests: [`ethercat_slave::master`] with its errors turned into
//! test failures, and CoE SDO transfers through the mailbox, framed byte by byte as ETG.1000.6 lays
//! them out.

#![allow(dead_code)]

#[path = "coe.rs"]
mod coe;
pub use coe::{coe_answer, coe_request};

use std::time::Duration;

use ds402::smd::indexer::{Inputs, Outputs};
use ethercat_slave::esc::CommandCode;
use ethercat_slave::frame::Datagram;
use ethercat_slave::master as m;
use ethercat_slave::master::SimChain;
#[allow(unused_imports)]
pub use ethercat_slave::master::{station, MBX_IN, MBX_LEN, MBX_OUT, SRC};

fn ok<T>(r: Result<T, m::MasterError>) -> T {
    r.unwrap_or_else(|e| panic!("{e}"))
}

/// One datagram through the chain, answered.
pub fn one(c: &mut SimChain, d: Datagram) -> Datagram {
    ok(m::one(c, d))
}

/// A register datagram `command` to `adp`/`ado`.
pub fn reg(c: &mut SimChain, command: CommandCode, adp: u16, ado: u16, data: Vec<u8>) -> Datagram {
    ok(m::reg(c, command, adp, ado, data))
}

/// FPWR that unit `k` must take (working counter 1).
pub fn fpwr(c: &mut SimChain, k: usize, ado: u16, data: Vec<u8>) {
    ok(m::fpwr(c, k, ado, data))
}

/// FPRD of `len` bytes at `ado` of unit `k` (data and working counter).
pub fn fprd(c: &mut SimChain, k: usize, ado: u16, len: usize) -> (Vec<u8>, u16) {
    ok(m::fprd(c, k, ado, len))
}

/// AL status and AL status code of unit `k`.
pub fn al(c: &mut SimChain, k: usize) -> (u16, u16) {
    ok(m::al(c, k))
}

/// Requests `state` from every unit; the working counter.
pub fn request(c: &mut SimChain, state: u8) -> u16 {
    ok(m::request(c, state))
}

/// Station addresses, SyncManagers, FMMUs.
pub fn configure(c: &mut SimChain) {
    ok(m::configure(c))
}

/// Configures the chain and brings every unit to `to`.
pub fn bring_up(c: &mut SimChain, to: u8) {
    ok(m::bring_up(c, to))
}

/// One LRW and a 1 ms cycle: the working counter and the inputs.
pub fn lrw(c: &mut SimChain, outputs: &[Outputs]) -> (u16, Vec<Inputs>) {
    ok(m::lrw(c, outputs))
}

/// Writes `request` into unit k's SM0 (padded to its length), waits for SM1 to fill and reads it.
pub fn mailbox(c: &mut SimChain, k: usize, request: &[u8]) -> Vec<u8> {
    let mut m = request.to_vec();
    m.resize(MBX_LEN, 0);
    fpwr(c, k, MBX_OUT, m);
    answer(c, k)
}

/// Waits (a few 1 ms cycles at most) for unit k's SM1 to fill and reads it.
pub fn answer(c: &mut SimChain, k: usize) -> Vec<u8> {
    for _ in 0..10 {
        let (status, _) = fprd(c, k, 0x080D, 1);
        if status[0] & 0x08 != 0 {
            let (answer, wkc) = fprd(c, k, MBX_IN, MBX_LEN);
            assert_eq!(wkc, 1, "a full SM1 is read");
            return answer;
        }
        c.cycle(Duration::from_millis(1));
    }
    panic!("unit {k} did not answer the mailbox");
}

thread_local! {
    static COUNTER: std::cell::Cell<u8> = const { std::cell::Cell::new(0) };
}

/// The next mailbox counter, 1…7, per test thread (0 is not used: a slave takes a repeated counter for
/// a repeat).
pub fn next_counter() -> u8 {
    COUNTER.with(|c| {
        c.set(c.get() % 7 + 1);
        c.get()
    })
}

/// Expedited or normal SDO upload of `index:sub` (complete access with `ca`): the value.
pub fn upload(c: &mut SimChain, k: usize, index: u16, sub: u8, ca: bool) -> Result<Vec<u8>, u32> {
    let i = index.to_le_bytes();
    let cmd = if ca { 0x50 } else { 0x40 };
    let m = mailbox(
        c,
        k,
        &coe_request(next_counter(), &[cmd, i[0], i[1], sub, 0, 0, 0, 0]),
    );
    let sdo = coe_answer(&m)?;
    assert_eq!(&sdo[1..4], &[i[0], i[1], sub], "the answer names the entry");
    if sdo[0] & 0x02 != 0 {
        // Expedited: size in bits 2–3.
        let n = 4 - usize::from((sdo[0] >> 2) & 0x03);
        Ok(sdo[4..4 + n].to_vec())
    } else {
        let size = u32::from_le_bytes([sdo[4], sdo[5], sdo[6], sdo[7]]) as usize;
        Ok(sdo[8..8 + size].to_vec())
    }
}

/// Expedited SDO download (1–4 bytes) or, with `ca` or more bytes, a normal download in one mailbox.
pub fn download(
    c: &mut SimChain,
    k: usize,
    index: u16,
    sub: u8,
    data: &[u8],
    ca: bool,
) -> Result<(), u32> {
    let i = index.to_le_bytes();
    let sdo = if data.len() <= 4 && !ca {
        let mut s = vec![0x23 | ((4 - data.len() as u8) << 2), i[0], i[1], sub];
        s.extend_from_slice(data);
        s.resize(8, 0);
        s
    } else {
        let mut s = vec![if ca { 0x31 } else { 0x21 }, i[0], i[1], sub];
        s.extend_from_slice(&(data.len() as u32).to_le_bytes());
        s.extend_from_slice(data);
        s
    };
    let m = mailbox(c, k, &coe_request(next_counter(), &sdo));
    let answer = coe_answer(&m)?;
    // The response echoes the complete-access bit of the request.
    let response = if ca { 0x70 } else { 0x60 };
    assert_eq!(
        answer[..4],
        [response, i[0], i[1], sub],
        "download response"
    );
    Ok(())
}
