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
