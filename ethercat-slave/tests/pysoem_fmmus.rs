//! A real EtherCAT master against a unit whose FMMUs 3…15 hold garbage: SOEM, through pysoem, runs
//! `tests/python/pysoem_fmmus.py` on the master's end of a veth pair while `ethercat-node` runs the
//! example I/O device (three ESI `Fmmu` elements, four `Sm`) on the other (see `testkit::link`).
//! The script reads ESC information 0x0004/0x0005 (03 04: FMMUs and SyncManagers supported, ESC
//! datasheet section II), writes FMMUs 3…15 by FPWR with a read-write mapping of the unit's inputs
//! onto its outputs SyncManager (ETG.1000.4 Table 57) and reads them back as zeros (reserved
//! registers: the ESC has three FMMUs), then starts again with a fresh master, which zeroes FMMUs
//! 0–2 only: the unit goes to Op, every working counter is 3, SM2's buffer and the unit's
//! 0x7000/0x7010 hold the master's outputs, and the FMMU registers read FMMU 0 and 1 as SOEM set
//! them and 224 zero bytes. The script checks every value it sees and exits non-zero on the first
//! mismatch; its output and the emulator's log are shown when it does.
//!
//! Needs root (a network namespace, a veth pair, raw sockets) and pysoem (`pip install pysoem`):
//! without either the test fails and says why; it is never skipped.

#[path = "common/pysoem.rs"]
#[allow(dead_code)]
mod pysoem_master;

#[test]
fn pysoem_restarts_a_unit_with_garbage_in_fmmus_3_to_15_to_op() {
    let script = format!(
        "{}/tests/python/pysoem_fmmus.py",
        env!("CARGO_MANIFEST_DIR")
    );
    let (stdout, _) = pysoem_master::run_on(
        || testkit::link::Link::node(&["--esi", "examples/io-device.esi.xml"]),
        "ethercat-node",
        &script,
        &[],
        std::time::Duration::from_secs(60),
    );
    let summary = stdout.lines().last().unwrap_or_default();
    assert!(
        summary.contains("to Op after a restart"),
        "{summary}\n{stdout}"
    );
    println!("{summary}");
}
