//! The `smd` binary as a user runs it, for the tests of its commands.

use std::process::Command;

/// `smd ARGS…`: exit code (-1 when killed by a signal), standard output, standard error.
pub fn smd(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_smd"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
