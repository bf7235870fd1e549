//! `ethercat-node --explain` and `--json` as a user runs them: what each kind of device reports that
//! its ESI does not give, one line (or JSON object) per entry, printed without an interface or root.

use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn corpus(name: &str) -> String {
    let p = root().join("../shared/corpus/esi").join(name);
    assert!(
        p.is_file(),
        "{} is missing: the corpus beside the checkout",
        p.display()
    );
    p.display().to_string()
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

/// Ingenia's EVE-XCR-E: its identity as the SII carries it over its 0x1018 object's, then the
/// drive's values for those its ESI gives as 0; the example drive, complete, adds nothing; exit 0
/// with no interface named, and nothing on standard error.
#[test]
fn explain_names_each_value_per_kind_of_device() {
    let ingenia = corpus("ingenia-eve-xcr-e.xml");
    let (code, out, err) = run(&[
        "--explain",
        "--esi",
        &format!("{ingenia}@2"),
        "--esi",
        "examples/drive.esi.xml",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err, "");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 8, "{out}");
    assert_eq!(
        lines[0],
        "ethercat-node: EVE-XCR-E: 0x1018:02 product code = 0x02C31001 (the ESI's object gives \
         0x00000032, its Type 0x02C31001, which the SII carries and a master compares with 0x1018)"
    );
    assert_eq!(
        lines[2],
        "ethercat-node: EVE-XCR-E: 0x605D halt option code = 1 (the description gives 0, a code \
         outside 1 to 4, which it refuses: its default)"
    );
    assert_eq!(
        lines[4],
        "ethercat-node: EVE-XCR-E: 0x6083 profile acceleration = 100000 counts/s² (the description \
         gives 0, which would stop every move: a factory default)"
    );
}

/// `--json`: the same as JSON objects naming the device; `--motor stepper` changes the device type
/// a drive reports (Copley's two axes: several logical devices either way, said as a stepper's).
#[test]
fn json_objects_name_the_device() {
    let copley = corpus("copley-XE2_4.60.xml");
    let (code, out, err) = run(&["--explain", "--json", "--esi", &copley]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        out.lines().next().unwrap(),
        r#"{"event":"filled","device":"XE2","index":"0x1000","sub":0,"name":"device type","value":4294902162,"reason":"the description gives no value: a CiA 402 servo drive of 2 axes (0xFFFF: several logical devices, each describing itself at 0x67FF + 0x800 · axis)"}"#
    );
    let (code, out, _) = run(&["--explain", "--motor", "stepper", "--esi", &copley]);
    assert_eq!(code, 0);
    assert!(
        out.starts_with(
            "ethercat-node: XE2: 0x1000 device type = 0xFFFF0192 (the description gives no value: \
             a CiA 402 stepper motor drive of 2 axes"
        ),
        "{out}"
    );
}

/// Without --explain the interface is needed: refused in one line, exit 2.
#[test]
fn without_explain_an_interface_is_needed() {
    let (code, out, err) = run(&["--esi", "examples/drive.esi.xml"]);
    assert_eq!(code, 2);
    assert_eq!(out, "");
    assert!(err.contains("<INTERFACE>"), "{err}");
}
