//! The `esi-gen` command line as a user runs it: exit codes, one-line errors, help, and conversions
//! between every pair of formats.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn esi_gen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_esi-gen"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("esi-gen-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn every_subcommand_has_help() {
    for sub in [
        "esi", "xdd", "eds", "dcf", "doc", "check", "diff", "fixtures",
    ] {
        let o = esi_gen(&[sub, "--help"]);
        assert!(o.status.success(), "{sub}");
        assert!(
            stdout(&o).contains("Usage: esi-gen"),
            "{sub}: {}",
            stdout(&o)
        );
    }
}

#[test]
fn check_summarises_both_smd_devices() {
    let o = esi_gen(&["check", "fixtures/src/smd.esi.xml"]);
    assert_eq!(o.status.code(), Some(0), "{}{}", stdout(&o), stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("fixtures/src/smd.esi.xml: ESI, 2 device(s)"),
        "{text}"
    );
    assert!(text.contains("\nSMD23K-B\n"), "{text}");
    assert!(text.contains("\nSMD24K\n"), "{text}");
    assert!(
        text.contains("op modes: SM-Synchron, DC_Synchron"),
        "{text}"
    );
    assert!(text.contains("0 error(s)"), "{text}");
}

#[test]
fn failures_exit_2_with_one_line() {
    let o = esi_gen(&["check", "no/such/file.xml"]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("esi-gen: no/such/file.xml: "), "{err}");

    let bad = tmp("bad.xml");
    std::fs::write(&bad, "<?xml version=\"1.0\"?>\n<EtherCATInfo>\n  <Vendor><Id>#xZZ</Id></Vendor>\n</EtherCATInfo>\n")
        .unwrap();
    let o = esi_gen(&["esi", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("bad.xml:3:"), "names file and line: {err}");

    let o = esi_gen(&["xdd", "fixtures/src/smd.esi.xml"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("choose one with --device"),
        "{}",
        stderr(&o)
    );

    let o = esi_gen(&["xdd", "fixtures/src/smd.esi.xml", "--device", "SMD99"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("no device matches `SMD99`"),
        "{}",
        stderr(&o)
    );

    let o = esi_gen(&["esi", "fixtures/src/smd.esi.xml", "--vendor-id", "banana"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn diff_exits_0_when_equal_and_1_when_different() {
    let eds = tmp("smd23k.eds");
    let o = esi_gen(&[
        "eds",
        "fixtures/src/smd.esi.xml",
        "--device",
        "SMD23K-B",
        "-o",
        eds.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = esi_gen(&["diff", eds.to_str().unwrap(), eds.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(stdout(&o), "");
    let o = esi_gen(&[
        "diff",
        "fixtures/src/smd.esi.xml",
        "fixtures/src/x67sm2436.xdd",
        "--device",
        "SMD23K-B",
    ]);
    assert_eq!(
        o.status.code(),
        Some(2),
        "--device must match in both files: {}",
        stderr(&o)
    );
    let x67 = tmp("x67.eds");
    let o = esi_gen(&[
        "eds",
        "fixtures/src/x67sm2436.xdd",
        "-o",
        x67.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = esi_gen(&["diff", eds.to_str().unwrap(), x67.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stdout(&o).contains("- 0x8010 Configuration Data"),
        "{}",
        stdout(&o)
    );
    assert!(stdout(&o).contains("+ 0x2100 AbsPos01"), "{}", stdout(&o));
}

#[test]
fn identity_overrides_reach_the_output() {
    let o = esi_gen(&[
        "eds",
        "fixtures/src/smd.esi.xml",
        "--device",
        "SMD24K",
        "--identity",
        "fixtures/identity.toml",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("ProductNumber=0x00002401"), "{text}");
    let o = esi_gen(&[
        "eds",
        "fixtures/src/smd.esi.xml",
        "--device",
        "SMD24K",
        "--product-code",
        "0x1234",
    ]);
    assert!(
        stdout(&o).contains("ProductNumber=0x00001234"),
        "{}",
        stdout(&o)
    );
}

#[test]
fn dcf_carries_the_node_id() {
    let o = esi_gen(&[
        "dcf",
        "fixtures/src/x67sm2436.xdd",
        "--node-id",
        "5",
        "--baud-rate",
        "500",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("NodeID=5") || text.contains("NodeID=0x05") || text.contains("NodeId=5"),
        "{text}"
    );
    let o = esi_gen(&["dcf", "fixtures/src/x67sm2436.xdd", "--node-id", "200"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn every_format_converts_to_every_other_and_back() {
    for (src, device) in [
        ("fixtures/src/smd.esi.xml", Some("SMD23K-B")),
        ("fixtures/src/x67sm2436.xdd", None),
    ] {
        for fmt in ["esi", "xdd", "eds", "dcf"] {
            let out = tmp(&format!(
                "conv-{}.{fmt}",
                Path::new(src).file_stem().unwrap().to_string_lossy()
            ));
            let mut args = vec![fmt, src, "-o", out.to_str().unwrap()];
            if let Some(d) = device {
                args.extend(["--device", d]);
            }
            let o = esi_gen(&args);
            assert!(o.status.success(), "{fmt} from {src}: {}", stderr(&o));
            let o = esi_gen(&["check", out.to_str().unwrap()]);
            assert_eq!(
                o.status.code(),
                Some(0),
                "{fmt} from {src}: {}{}",
                stdout(&o),
                stderr(&o)
            );
        }
    }
}

/// `esi-gen sii`: the image of one device of the SMD ESI, with its serial; a non-EtherCAT description
/// is refused with the reason.
#[test]
fn sii_image() {
    let img = tmp("smd24k.bin");
    let esi = format!(
        "{}/../fixtures/smd/SMD23K-B_SMD24K.esi.xml",
        env!("CARGO_MANIFEST_DIR")
    );
    let out = esi_gen(&[
        "sii",
        &esi,
        "--device",
        "SMD24K",
        "--serial",
        "0x77",
        "-o",
        img.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(&img).unwrap();
    let parsed = od::sii::parse(&bytes).unwrap();
    assert_eq!(parsed.identity[3], 0x77);
    let general = parsed.category(od::sii::category::GENERAL).unwrap();
    assert_eq!(parsed.string(general[2]), "SMD24K");
    let xdd = format!(
        "{}/../fixtures/x67/X67SM2436.xdd",
        env!("CARGO_MANIFEST_DIR")
    );
    let out = esi_gen(&["sii", &xdd, "-o", img.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no EtherCAT description"));
    let out = esi_gen(&["sii", &esi, "-o", img.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "two devices: --device needed");
}
