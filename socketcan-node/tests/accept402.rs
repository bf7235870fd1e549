//! `scripts/accept-402-canopen` on the drives of `tests/drives`, one small description for each way a
//! vendor lays out the PDOs of a CiA 402 drive (status word on every SYNC, on every fourth, at the SYNC
//! after a change, on change only, on change with an inhibit time and an event timer, on a remote
//! frame, in no PDO; control word in a synchronous RPDO, in event-driven ones, in overlapping ones):
//! each run by `canopen-node` over socketcand on 127.0.0.1 and driven by python-canopen's
//! `BaseNode402` as a user who has only the file (tests/python/accept402_canopen.py): identity, the
//! state machine with quick stop, homing, a pp move to an exact position, a pv run, csp on SYNC to an
//! exact position. Every file passes; the table the runner prints is checked row by row.

use std::path::{Path, PathBuf};
use std::process::Command;

const NODE: &str = env!("CARGO_BIN_EXE_canopen-node");

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Runs the runner on `dir` with `extra` arguments; its table (stdout) and whether it passed.
pub fn runner(dir: &Path, extra: &[&str]) -> (String, bool) {
    let out = Command::new("python3")
        .arg(root().join("scripts/accept-402-canopen"))
        .arg(dir)
        .args(["--bin", NODE])
        .args(extra)
        .output()
        .expect("python3 runs (scripts/setup-test-deps installs python-canopen)");
    let table = String::from_utf8_lossy(&out.stdout).into_owned();
    println!("{table}{}", String::from_utf8_lossy(&out.stderr));
    (table, out.status.success())
}

/// The rows of the drives of tests/drives, each passing; over socketcand the remote frames are
/// skipped (the protocol carries none).
#[test]
fn every_pdo_layout_passes_base_node_402() {
    let (table, ok) = runner(&root().join("tests/drives"), &[]);
    let skip = "remote frames: socketcand carries no remote frames";
    let want: Vec<String> = [
        "pdo-event-only.eds",
        "pdo-event-timer.eds",
        "pdo-none.eds",
        "pdo-rtr.eds",
        "pdo-sync-every.eds",
        "pdo-sync-fourth.eds",
        "pdo-sync-on-change.eds",
    ]
    .iter()
    .map(|f| format!("| {f} | pass | {skip} |"))
    .collect();
    let rows: Vec<&str> = table.lines().filter(|l| l.starts_with("| pdo-")).collect();
    assert_eq!(rows, want);
    assert!(
        table.contains("7 of 7 descriptions with 0x6040/0x6041 pass on CANopen"),
        "{table}"
    );
    assert!(ok);
}

/// Every CiA 402 description of the corpus beside the checkout passes, or runs no drive because its
/// 0x6040/0x6041 are something else (a RECORD, an INTEGER16 "process data"): no row fails.
#[test]
fn every_corpus_drive_passes_base_node_402() {
    let corpus = root().join("../shared/corpus");
    assert!(
        corpus.is_dir(),
        "{} is missing: the corpus lies beside the checkout",
        corpus.display()
    );
    let (table, ok) = runner(&corpus, &[]);
    let rows: Vec<&str> = table.lines().filter(|l| l.starts_with("| eds/")).collect();
    assert!(rows.len() >= 16, "{table}");
    for row in &rows {
        let result = row.split(" | ").nth(1).unwrap_or("");
        assert!(
            result == "pass" || result == "no drive",
            "{row}\n(the whole table: {table})"
        );
    }
    assert!(ok, "{table}");
}
