//! `sdo-tool net gen` and `net check` as a user runs them: the files dcfgen writes, with the same
//! names and bytes, and every problem of a bus description on its own line with its file and line.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn net_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/net")
}

fn tool(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(args)
        .output()
        .unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// `net gen` writes what `dcfgen` writes for tests/net/basic.yml: the same files, each slave's
/// concise DCF and master.bin byte for byte (master.dcf is compared key by key in canopen-net's
/// tests). The description is read from another folder, its DCFs relative to it.
#[test]
fn gen_writes_dcfgens_files() {
    let ours = tempfile::tempdir().unwrap();
    let theirs = tempfile::tempdir().unwrap();
    let bus = net_dir().join("basic.yml");
    let out = tool(&[
        "net",
        "gen",
        bus.to_str().unwrap(),
        "-d",
        ours.path().to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("drive.bin (197 bytes)"),
        "{}",
        text(&out.stdout)
    );
    let status = Command::new("dcfgen")
        .args(["-d", theirs.path().to_str().unwrap(), "basic.yml"])
        .current_dir(net_dir())
        .env("PYTHONWARNINGS", "ignore")
        .status()
        .unwrap();
    assert!(status.success());
    for name in ["drive.bin", "io.bin", "master.bin"] {
        let a = std::fs::read(ours.path().join(name)).unwrap();
        let b = std::fs::read(theirs.path().join(name)).unwrap();
        assert_eq!(a, b, "{name}");
    }
    assert!(ours.path().join("master.dcf").exists());
}

/// `net check` names each problem on its own line, then exits 2 with their count.
#[test]
fn check_names_each_problem() {
    let dir = tempfile::tempdir().unwrap();
    let drive = net_dir().join("../../examples/drive.eds");
    let drive = drive.to_str().unwrap();
    let yaml = format!(
        "master: {{node_id: 1}}\na:\n  dcf: {drive}\n  node_id: 2\nb:\n  dcf: {drive}\n  node_id: 2\n\
         c:\n  dcf: nowhere.eds\n  node_id: 4\nd:\n  dcf: {drive}\n  node_id: 5\n  tpdo:\n    7: {{}}\n"
    );
    let bus = dir.path().join("bus.yml");
    std::fs::write(&bus, yaml).unwrap();
    let shown = bus.display().to_string();
    let out = tool(&["net", "check", &shown]);
    assert_eq!(out.status.code(), Some(2));
    let nowhere = dir.path().join("nowhere.eds");
    let stdout = text(&out.stdout);
    let lines: Vec<&str> = stdout
        .lines()
        .filter(|l| !l.starts_with("warning:"))
        .collect();
    assert_eq!(
        lines,
        [
            format!("{shown}:5: b: node-ID 2 is a's too"),
            format!(
                "{shown}:9: c.dcf: {}: No such file or directory (os error 2)",
                nowhere.display()
            ),
            format!("{shown}:15: d.tpdo: d: Transmit-PDO 7 not available"),
        ]
    );
    assert_eq!(
        text(&out.stderr).trim(),
        format!("sdo-tool: {shown}: 3 problems")
    );
}

/// A description that is no YAML is one line naming the file and the line.
#[test]
fn gen_refuses_a_broken_description() {
    let dir = tempfile::tempdir().unwrap();
    let bus = dir.path().join("bus.yml");
    std::fs::write(&bus, "master:\n  node_id: [1\n").unwrap();
    let shown = bus.display().to_string();
    let out = tool(&["net", "gen", &shown, "-d", dir.path().to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        text(&out.stderr).trim(),
        format!("sdo-tool: {shown}:3: while parsing a flow sequence, expected ',' or ']'")
    );
}
