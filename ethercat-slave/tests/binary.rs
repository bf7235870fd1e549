//! The `smd-ethercat` binary's command line: help, refused arguments, an interface that is not there,
//! a capture file that cannot be created.

use std::process::Command;

fn run(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_smd-ethercat"))
        .args(args)
        .output()
        .expect("run smd-ethercat");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn help_explains_the_options_and_the_veth_recipe() {
    let (code, out, _) = run(&["--help"]);
    assert_eq!(code, 0);
    for needle in [
        "INTERFACE",
        "--units",
        "--device",
        "smd23k-b",
        "smd24k",
        "--cycle-us",
        "--busy-poll-us",
        "type veth",
        "CAP_NET_RAW",
    ] {
        assert!(out.contains(needle), "--help mentions {needle}:\n{out}");
    }
}

#[test]
fn refused_arguments_exit_2_naming_them() {
    for (args, needle) in [
        (&["ecat0", "--units", "0"][..], "--units"),
        (&["ecat0", "--units", "129"][..], "--units"),
        (&["ecat0", "--device", "smd42"][..], "--device"),
        (&["ecat0", "--cycle-us", "100"][..], "--cycle-us"),
        (&[][..], "INTERFACE"),
    ] {
        let (code, _, err) = run(args);
        assert_eq!(code, 2, "{args:?}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

/// A capture file that cannot be created is refused in one line before the interface is opened.
#[test]
fn a_capture_that_cannot_be_created_is_refused() {
    let (code, out, err) = run(&["lo", "--capture", "/nonexistent/dir/x.pcapng"]);
    assert_eq!(code, 2, "{err}");
    assert!(out.is_empty(), "not on line: {out}");
    assert_eq!(
        err,
        "smd-ethercat: --capture /nonexistent/dir/x.pcapng: No such file or directory (os error 2)\n"
    );
}

#[test]
fn an_interface_that_is_not_there_is_named() {
    let (code, out, err) = run(&["nosuchif0"]);
    assert_eq!(code, 2);
    assert!(out.is_empty(), "not on line: {out}");
    assert!(
        err.contains("smd-ethercat: interface \"nosuchif0\": no such interface"),
        "{err}"
    );
    let (code, _, err) = run(&["a-name-far-too-long-for-linux"]);
    assert_eq!(code, 2);
    assert!(err.contains("not a valid interface name"), "{err}");
}
