//! A real EtherCAT master against the emulator: SOEM, through pysoem, runs
//! `tests/python/pysoem_master.py` on the master's end of a veth pair while `smd-ethercat --units 2`
//! answers on the other end (see `testkit::link`). The script checks every value it sees and exits
//! non-zero on the first mismatch; its output and the emulator's log are shown when it does.
//!
//! Needs root (a network namespace, a veth pair, raw sockets) and pysoem (`pip install pysoem`):
//! without either the tests fail and say why; they are never skipped.

use std::time::{Duration, Instant};

use testkit::link;

#[path = "common/pysoem.rs"]
#[allow(dead_code)]
mod pysoem_master;
use pysoem_master::script;

/// Runs the script with `extra` arguments against two units on a fresh link; its summary line.
fn run_master(extra: &[&str]) -> String {
    let units = 2.to_string();
    let started = Instant::now();
    let args: Vec<&str> = std::iter::once(units.as_str())
        .chain(extra.iter().copied())
        .collect();
    let (stdout, answered) = pysoem_master::run_on(
        || link::Link::up(&["--units", &units]),
        "smd-ethercat",
        &script(),
        &args,
        Duration::from_secs(25),
    );
    let summary = stdout
        .lines()
        .last()
        .unwrap_or_else(|| panic!("no summary line\n{stdout}"))
        .to_string();
    println!(
        "{summary} [{:.2} s, {answered} frames answered]",
        started.elapsed().as_secs_f64()
    );
    summary
}

/// Two units from Init to Op under SOEM, a Relative move on each, and the SyncManager watchdog.
///
/// - SMD-T2-007: the units start in Init — a raw BRD of AL status before SOEM sends anything reads
///   Init on both (working counter 2), and SOEM's enumeration reads Init too;
/// - SMD-T3-003: SYNC0 with a 2 ms cycle is accepted at Pre-Op → Safe-Op;
/// - SMD-R1-035: 300 ms without process data (watchdog 100 ms) drops both from Op to Safe-Op with the
///   error flag (pysoem state 0x14) and AL status code 0x001B; the inputs show PreOp_SafeOp and
///   Input_Error; after the acknowledgement (0x14) they go back to Op.
///
/// Besides: the SII and CoE identity (AMCI 0x0AC1, 0x2301, revision 1, serial numbers 1 and 2), SDO
/// uploads and downloads in Pre-Op with the abort codes of the refused ones, a 40-byte process image,
/// the working counter 6 in every Op cycle, Move_Complete exactly at +5000 and −2000.
#[test]
fn pysoem_drives_two_units_to_op_and_the_sm_watchdog_drops_them_smd_r1_035_t2_007_t3_003() {
    let summary = run_master(&[]);
    assert!(summary.contains("SM watchdog"), "{summary}");
}

/// SMD-T3-003 (the refusal): with SYNC0 activated at a 1 ms cycle (and 1.999999 ms, 50.000001 ms)
/// SOEM's Safe-Op request is refused — both units stay in Pre-Op with the error flag (0x12) and AL
/// status code 0x0036; acknowledged, they are in Pre-Op without error, and 50 ms and 2 ms are then
/// accepted.
#[test]
fn pysoem_sync0_of_1_ms_is_refused_with_0x0036_smd_t3_003() {
    let summary = run_master(&["--sync0-too-fast"]);
    assert!(summary.contains("1000000 ns"), "{summary}");
}
