//! What the `sdo-tool` tests share.
#![allow(dead_code)]

use std::process::{Command, Output};

/// `sdo-tool GLOBAL… ARGS…` as a user runs it; GLOBAL are the bus options (`--bus …`, `--ethercat …`).
pub fn sdo_tool(global: &[&str], argv: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(global)
        .args(argv)
        .output()
        .expect("run sdo-tool")
}

/// `sdo-tool GLOBAL… ARGS…`, expected to succeed: its standard output.
pub fn sdo_tool_ok(global: &[&str], argv: &[&str]) -> String {
    let o = sdo_tool(global, argv);
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "sdo-tool {argv:?}: {:?}\n{stdout}{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
    stdout
}
