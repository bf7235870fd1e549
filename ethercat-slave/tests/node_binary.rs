//! The `ethercat-node` binary's command line: help, how --device and --modules belong to the --esi
//! before them, and every refusal in one line naming what and where, with exit code 2 (bad
//! arguments, ESIs that do not load or cannot be emulated, an interface that is not there).

use std::path::PathBuf;
use std::process::Command;

use ethercat_slave::node_cli::{parse, split_count};

fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn run(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_ethercat-node"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("run ethercat-node");
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
        "--esi",
        "FILE[@N]",
        "--device",
        "--modules",
        "--units",
        "--motor",
        "--cycle-us",
        "--busy-poll-us",
        "type veth",
        "CAP_NET_RAW",
        "CiA 402",
    ] {
        assert!(out.contains(needle), "--help mentions {needle}:\n{out}");
    }
}

/// `--esi FILE@N`: N units; a path whose last `@` has no number after it is the path. A --device or
/// --modules belongs to the --esi before it (before any, to the first); --units counts each --esi
/// without @N.
#[test]
fn device_and_modules_belong_to_the_esi_before_them() {
    assert_eq!(split_count("a.xml@3"), Ok(("a.xml".into(), Some(3))));
    assert_eq!(split_count("dir@x/a.xml"), Ok(("dir@x/a.xml".into(), None)));
    assert_eq!(split_count("a.xml"), Ok(("a.xml".into(), None)));
    assert!(split_count("a.xml@0").is_err());
    assert!(split_count("a.xml@129").is_err());
    let c = parse([
        "ethercat-node",
        "ecat1",
        "--device",
        "X",
        "--esi",
        "a.xml@2",
        "--esi",
        "b.xml",
        "--modules",
        "0x1,none",
        "--esi",
        "c.xml",
        "--device",
        "0x42",
        "--units",
        "3",
    ])
    .unwrap();
    let got: Vec<_> = c
        .specs
        .iter()
        .map(|s| {
            (
                s.path.display().to_string(),
                s.units,
                s.device.clone(),
                s.modules.clone(),
            )
        })
        .collect();
    assert_eq!(
        got,
        [
            ("a.xml".to_string(), Some(2), Some("X".to_string()), None),
            (
                "b.xml".into(),
                None,
                None,
                Some(vec!["0x1".to_string(), "none".into()])
            ),
            ("c.xml".into(), None, Some("0x42".into()), None),
        ]
    );
    assert_eq!(c.args.units, 3);
}

#[test]
fn refused_arguments_exit_2_naming_them() {
    for (args, needle) in [
        (&["ecat0"][..], "--esi"),
        (&["ecat0", "--esi", "a.xml", "--units", "0"][..], "--units"),
        (
            &["ecat0", "--esi", "a.xml@0"][..],
            "a.xml@0: @0 is not a number of units from 1 to 128",
        ),
        (
            &["ecat0", "--esi", "a.xml@100", "--esi", "b.xml@29"][..],
            "129 units in all; a chain has at most 128",
        ),
        (
            &["ecat0", "--esi", "a.xml", "--device", "A", "--device", "B"][..],
            "two --device for --esi a.xml",
        ),
        (
            &[
                "ecat0",
                "--esi",
                "a.xml",
                "--modules",
                "1",
                "--modules",
                "2",
            ][..],
            "two --modules for --esi a.xml",
        ),
        (
            &["ecat0", "--esi", "a.xml", "--cycle-us", "100"][..],
            "--cycle-us",
        ),
        (
            &["ecat0", "--esi", "a.xml", "--motor", "diesel"][..],
            "--motor",
        ),
    ] {
        let (code, out, err) = run(args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(out.is_empty(), "{args:?}: not on line: {out}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

/// A capture file that cannot be created is refused in one line before the interface is opened.
#[test]
fn a_capture_that_cannot_be_created_is_refused() {
    let (code, out, err) = run(&[
        "lo",
        "--esi",
        "examples/drive.esi.xml",
        "--capture",
        "/nonexistent/dir/x.pcapng",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(out.is_empty(), "not on line: {out}");
    assert_eq!(
        err,
        "ethercat-node: --capture /nonexistent/dir/x.pcapng: No such file or directory (os error 2)\n"
    );
}

/// An ESI that cannot run is refused before anything else, in one line naming the file and why.
#[test]
fn descriptions_that_cannot_run_are_named_in_one_line() {
    let corpus = root().join("../shared/corpus/esi/elmo-ECAT_00010420_V11.xml");
    assert!(
        corpus.is_file(),
        "{} is missing: the corpus beside the checkout",
        corpus.display()
    );
    let elmo = corpus.display().to_string();
    for (args, line) in [
        (
            vec!["nosuchif0", "--esi", "no/such.xml"],
            "ethercat-node: no/such.xml: No such file or directory (os error 2)\n".to_string(),
        ),
        (
            vec!["nosuchif0", "--esi", "examples/drive.eds"],
            "ethercat-node: examples/drive.eds: an EDS describes a CANopen device; run it with canopen-node\n".into(),
        ),
        (
            vec!["nosuchif0", "--esi", "/dev/null"],
            "ethercat-node: /dev/null: not a regular file\n".into(),
        ),
        (
            vec!["nosuchif0", "--esi", "examples/drive.esi.xml", "--modules", "0x1"],
            "ethercat-node: examples/drive.esi.xml: drive: 1 module(s) given, but the device has 0 slot(s)\n".into(),
        ),
        (
            vec!["nosuchif0", "--esi", "examples/drive.esi.xml", "--device", "0x999"],
            "ethercat-node: examples/drive.esi.xml:1:1: the file describes no device with product code #x00000999; it describes `drive` (product code #x00000402, revision #x00010001)\n".into(),
        ),
        (vec!["nosuchif0", "--esi", &elmo], format!("ethercat-node: {elmo}:1:1: the file describes 4 devices: ")),
    ] {
        let (code, out, err) = run(&args);
        assert_eq!(code, 2, "{args:?}");
        assert!(out.is_empty(), "{args:?}: {out}");
        assert_eq!(err.lines().count(), 1, "{args:?}: one line: {err}");
        if line.ends_with('\n') {
            assert_eq!(err, line, "{args:?}");
        } else {
            assert!(err.starts_with(&line), "{args:?}: {err}");
        }
    }
    // The ESI loads: then the interface is what is missing.
    let (code, out, err) = run(&["nosuchif0", "--esi", "examples/drive.esi.xml"]);
    assert_eq!(code, 2);
    assert!(out.is_empty(), "not on line: {out}");
    assert_eq!(
        err,
        "ethercat-node: interface \"nosuchif0\": no such interface\n"
    );
}

/// `--completions SHELL` and `--man DIR` alone on the command line, without an interface or an ESI.
#[test]
fn completions_and_manual_page() {
    let (code, script, _) = run(&["--completions", "bash"]);
    assert_eq!(code, 0);
    assert!(script
        .contains("complete -F _ethercat__node -o nosort -o bashdefault -o default ethercat-node"));
    assert!(script.contains("--esi"));
    let dir = std::env::temp_dir().join(format!("ethercat-node-man-{}", std::process::id()));
    let (code, out, _) = run(&["--man", dir.to_str().unwrap()]);
    assert_eq!(code, 0);
    let page = dir.join("ethercat-node.1");
    assert_eq!(out, format!("{}\n", page.display()));
    assert!(std::fs::read_to_string(&page)
        .unwrap()
        .contains(".TH ethercat-node 1"));
    std::fs::remove_dir_all(&dir).unwrap();
}
