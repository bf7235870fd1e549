//! What the `sdo-tool` tests share.

use std::process::{Command, Output};

/// `sdo-tool GLOBAL… ARGS…` as a user runs it; GLOBAL are the bus options (`--bus …`, `--ethercat …`).
pub fn sdo_tool(global: &[&str], argv: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(global)
        .args(argv)
        .output()
        .expect("run sdo-tool")
}
