//! What the pysoem tests share: the master's script and the check that it can run.

use std::process::Command;

/// The script, in the crate's tests.
pub fn script() -> String {
    format!(
        "{}/tests/python/pysoem_master.py",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// Root and an importable pysoem, or a failure that says which is missing.
pub fn preflight() {
    // SAFETY: geteuid(2) has no preconditions and cannot fail.
    let uid = unsafe { libc::geteuid() };
    assert_eq!(
        uid, 0,
        "the pysoem tests need root (network namespaces, veth pairs, raw sockets); running as uid {uid}"
    );
    let out = Command::new("python3")
        .args(["-c", "import pysoem; print(pysoem.__version__)"])
        .output()
        .unwrap_or_else(|e| panic!("cannot run python3 for the pysoem master: {e}"));
    assert!(
        out.status.success(),
        "pysoem is not importable by python3 (pip install pysoem): {}",
        String::from_utf8_lossy(&out.stderr).trim()
    );
}

/// The pysoem `script` with `args` on the master's end of the link `start` sets up (after the
/// check that root and pysoem are there), with its emulator (`emulator`, by name) on the far end,
/// for `limit` at most: the script's standard output, once it has
/// exited 0 with the emulator still running, every frame answered and none dropped as malformed (what
/// it and the emulator's log said otherwise in the failure); the number of frames answered beside it.
pub fn run_on(
    start: impl FnOnce() -> testkit::link::Link,
    emulator: &str,
    script: &str,
    args: &[&str],
    limit: std::time::Duration,
) -> (String, u64) {
    preflight();
    let mut link = start();
    assert!(
        link.running(),
        "{emulator} stopped at once: {}",
        link.stop()
    );
    let testkit::Finished {
        status,
        stdout,
        stderr,
    } = testkit::run_for_at_most(
        Command::new("python3")
            .arg(script)
            .arg(&link.master)
            .args(args),
        limit,
    );
    let alive = link.running();
    let log = link.stop();
    let name = std::path::Path::new(script)
        .file_name()
        .map_or_else(|| script.to_string(), |n| n.to_string_lossy().into_owned());
    let report = format!(
        "--- {name} {} stdout:\n{stdout}--- stderr:\n{stderr}--- emulator log:\n{log}",
        args.join(" ")
    );
    let status = status
        .unwrap_or_else(|| panic!("the pysoem master ran over {} s\n{report}", limit.as_secs()));
    assert!(
        status.success(),
        "the pysoem master failed ({status})\n{report}"
    );
    assert!(alive, "{emulator} had stopped by the end\n{report}");
    let (answered, dropped) = testkit::link::frame_counts(&log)
        .unwrap_or_else(|| panic!("no frame counts in the log\n{report}"));
    assert!(answered > 0, "no frames answered\n{report}");
    assert_eq!(dropped, 0, "SOEM's frames are all well-formed\n{report}");
    (stdout, answered)
}
