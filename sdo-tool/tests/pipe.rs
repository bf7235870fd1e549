//! `sdo-tool … | head`: when the reader of its standard output is gone (EPIPE), the tool ends
//! quietly with 141 (128 + SIGPIPE, what a shell reports for IgH's `ethercat` and `cocomm`), with
//! nothing on standard error.

mod common;
mod x67;

use std::process::{Command, Stdio};

/// A pipe whose reader is gone: the write end of a shell's standard input, once the shell ended.
fn closed_pipe() -> Stdio {
    let mut reader = Command::new("sh")
        .args(["-c", "exit 0"])
        .stdin(Stdio::piped())
        .spawn()
        .unwrap();
    let write_end = reader.stdin.take().unwrap();
    assert!(reader.wait().unwrap().success());
    Stdio::from(write_end)
}

/// `sdo-tool ARGS` writing into a pipe nobody reads: its exit code and standard error.
fn into_closed_pipe(argv: &[&str]) -> (Option<i32>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(argv)
        .stdout(closed_pipe())
        .stderr(Stdio::piped())
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `list` (no bus), and `read`, `dump` and `--json read` against `x67-node` over socketcand: each
/// ends with 141 and says nothing; the DCF `dump` writes is written all the same.
#[test]
fn a_closed_pipe_ends_the_tool_quietly_with_141() {
    let od = x67::eds();
    assert_eq!(
        into_closed_pipe(&["--od", &od, "list"]),
        (Some(141), String::new())
    );
    // A description of some of the node's entries, none written only (the X67's own names on
    // stderr the registers it reads back).
    let flags = testkit::root().join("fixtures/objflags/ObjFlags.eds");
    let flags = flags.to_str().unwrap();
    let (mut node, port) = x67::hub(3);
    let bus = common::socketcand_bus(port);
    let dir = tempfile::tempdir().unwrap();
    let dcf = dir.path().join("node3.dcf");
    for argv in [
        &["--bus", &bus, "read", "3", "0x1008", "vs"][..],
        &["--bus", &bus, "--json", "read", "3", "0x1008", "vs"],
        &[
            "--bus",
            &bus,
            "--od",
            flags,
            "dump",
            "3",
            "-o",
            dcf.to_str().unwrap(),
        ],
    ] {
        assert_eq!(
            into_closed_pipe(argv),
            (Some(141), String::new()),
            "{argv:?}"
        );
    }
    assert!(std::fs::read_to_string(&dcf)
        .unwrap()
        .contains("[DeviceComissioning]"));
    // An error of another kind is still said (exit 1: the node has no 0x1018:05).
    let (code, stderr) = into_closed_pipe(&["--bus", &bus, "read", "3", "0x1018:05", "u32"]);
    assert_eq!(code, Some(1));
    assert!(
        stderr.starts_with("sdo-tool: 0x1018:05: SDO abort 0x06090011"),
        "{stderr}"
    );
    node.kill().unwrap();
    node.wait().unwrap();
}
