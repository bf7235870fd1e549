//! `esi-gen diff` on two ESI files of several devices (`tests/data/revisions-{a,b}.xml`: EL1008 in two
//! revisions, and two devices with product code 0), and `--device` picking by name, product code and
//! revision in every subcommand.
//!
//! revisions-b.xml differs from revisions-a.xml in: EL1008 revision 0x00100000 has its Sm at #x1100 and
//! its input named `Input 1`; revision 0x00110000 is replaced by 0x00120000; DemoA is named `Demo A2`;
//! DemoB is replaced by DemoC.

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

const A: &str = "esi-gen/tests/data/revisions-a.xml";
const B: &str = "esi-gen/tests/data/revisions-b.xml";

#[test]
fn multi_device_files_are_compared_device_by_device() {
    let o = esi_gen(&["diff", A, B]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(
        stdout(&o),
        "device EL1008 (product code 0x03F03052, revision 0x00100000):\n\
         \x20 ~ Sm 0 start address: 0x1000 -> 0x1100\n\
         \x20 ~ TxPdo 0x1A00 entry 1 name: \"Input\" -> \"Input 1\"\n\
         \x20 ~ 0x6000:01 name: \"Input\" -> \"Input 1\"\n\
         - device EL1008 (product code 0x03F03052, revision 0x00110000)\n\
         device DemoA (product code 0x00000000, revision 0x00000000):\n\
         \x20 ~ identity product name: \"Demo A\" -> \"Demo A2\"\n\
         - device DemoB (product code 0x00000000, revision 0x00000000)\n\
         + device EL1008 (product code 0x03F03052, revision 0x00120000)\n\
         + device DemoC (product code 0x00000000, revision 0x00000000)\n"
    );
    assert_eq!(stderr(&o), "");
}

#[test]
fn json_is_one_object_per_difference() {
    let o = esi_gen(&["diff", A, B, "--json"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let el1008 = r#"{"name":"EL1008","product_code":"0x03F03052","revision":"0x00100000"}"#;
    let code0 = |name: &str| {
        format!(r#"{{"name":"{name}","product_code":"0x00000000","revision":"0x00000000"}}"#)
    };
    let expected = [
        format!(
            r#"{{"device":{el1008},"change":"changed","path":["Sm 0"],"field":"start address","a":"0x1000","b":"0x1100"}}"#
        ),
        format!(
            r#"{{"device":{el1008},"change":"changed","path":["TxPdo 0x1A00","entry 1"],"field":"name","a":"Input","b":"Input 1"}}"#
        ),
        format!(
            r#"{{"device":{el1008},"change":"changed","path":["0x6000:01"],"index":24576,"sub":1,"field":"name","a":"Input","b":"Input 1"}}"#
        ),
        r#"{"device":{"name":"EL1008","product_code":"0x03F03052","revision":"0x00110000"},"change":"only_in_a","path":[],"name":"EL1008"}"#.to_string(),
        format!(
            r#"{{"device":{},"change":"changed","path":["identity"],"field":"product name","a":"Demo A","b":"Demo A2"}}"#,
            code0("DemoA")
        ),
        format!(
            r#"{{"device":{},"change":"only_in_a","path":[],"name":"DemoB"}}"#,
            code0("DemoB")
        ),
        r#"{"device":{"name":"EL1008","product_code":"0x03F03052","revision":"0x00120000"},"change":"only_in_b","path":[],"name":"EL1008"}"#.to_string(),
        format!(
            r#"{{"device":{},"change":"only_in_b","path":[],"name":"DemoC"}}"#,
            code0("DemoC")
        ),
    ];
    assert_eq!(stdout(&o), expected.join("\n") + "\n");
}

#[test]
fn equal_files_print_nothing_and_exit_0() {
    for args in [vec!["diff", A, A], vec!["diff", A, A, "--json"]] {
        let o = esi_gen(&args);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        assert_eq!(stdout(&o), "");
    }
}

#[test]
fn a_file_that_cannot_be_loaded_exits_2() {
    let o = esi_gen(&["diff", A, "no/such/file.xml"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(stdout(&o), "");
    assert!(
        stderr(&o).starts_with("esi-gen: no/such/file.xml: "),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_device_of_several_revisions_is_its_newest_unless_the_revision_is_named() {
    // The newest of each file: 0x00110000 and 0x00120000.
    let o = esi_gen(&["diff", A, B, "--device", "EL1008"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(
        stdout(&o),
        "~ identity revision: 0x00110000 -> 0x00120000\n"
    );
    let first = "~ Sm 0 start address: 0x1000 -> 0x1100\n\
                 ~ TxPdo 0x1A00 entry 1 name: \"Input\" -> \"Input 1\"\n\
                 ~ 0x6000:01 name: \"Input\" -> \"Input 1\"\n";
    for wanted in [
        "el1008@0x00100000",
        "0x03F03052@#x00100000",
        "66072658@1048576",
        "EL1008 8Ch. Dig. Input@0x100000",
    ] {
        let o = esi_gen(&["diff", A, B, "--device", wanted]);
        assert_eq!(o.status.code(), Some(1), "{wanted}: {}", stderr(&o));
        assert_eq!(stdout(&o), first, "{wanted}");
    }
    let o = esi_gen(&["diff", A, B, "--device", "DemoA"]);
    assert_eq!(
        stdout(&o),
        "~ identity product name: \"Demo A\" -> \"Demo A2\"\n"
    );
}

#[test]
fn a_choice_of_different_devices_or_of_none_is_refused() {
    let o = esi_gen(&["diff", A, B, "--device", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(stdout(&o), "");
    assert_eq!(
        stderr(&o),
        format!(
            "esi-gen: {A}: `0` matches different devices: DemoA (product code 0x00000000, revision \
             0x00000000), DemoB (product code 0x00000000, revision 0x00000000); choose one by type \
             name, or add @REVISION\n"
        )
    );
    let o = esi_gen(&["diff", A, B, "--device", "EL1008@0x00120000"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        stderr(&o),
        format!(
            "esi-gen: {A}: no device matches `EL1008@0x00120000`; the file holds EL1008 (product \
             code 0x03F03052, revision 0x00100000), EL1008 (product code 0x03F03052, revision \
             0x00110000)\n"
        )
    );
    let o = esi_gen(&["diff", A, B, "--device", "DemoC"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).starts_with(&format!("esi-gen: {A}: no device matches `DemoC`; ")),
        "{}",
        stderr(&o)
    );
}

#[test]
fn every_subcommand_picks_the_same_way() {
    let o = esi_gen(&["check", A, "--device", "EL1008"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.starts_with(&format!("{A}: ESI, 1 device(s), read and checked in ")),
        "{text}"
    );
    assert!(
        text.contains("  product code 0x03F03052  revision 0x00110000\n"),
        "{text}"
    );
    let o = esi_gen(&["esi", A, "--device", "EL1008@0x00100000"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = stdout(&o);
    assert_eq!(text.matches("<Device>").count(), 1, "{text}");
    assert!(text.contains("RevisionNo=\"#x00100000\""), "{text}");
    for sub in ["xdd", "eds", "dcf", "doc"] {
        let o = esi_gen(&[sub, A, "--device", "EL1008@0x00130000"]);
        assert_eq!(o.status.code(), Some(2), "{sub}");
        assert!(
            stderr(&o).starts_with(&format!(
                "esi-gen: {A}: no device matches `EL1008@0x00130000`; "
            )),
            "{sub}: {}",
            stderr(&o)
        );
        let o = esi_gen(&[sub, A, "--device", "EL1008"]);
        assert_eq!(o.status.code(), Some(0), "{sub}: {}", stderr(&o));
    }
    let o = esi_gen(&["sii", A, "--device", "0", "-o", "/dev/null"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("`0` matches different devices"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn the_help_tells_the_device_syntax() {
    for sub in ["diff", "check", "esi", "xdd", "eds", "dcf", "doc", "sii"] {
        let o = esi_gen(&[sub, "--help"]);
        let text = stdout(&o);
        assert!(
            text.contains("--device <NAME|PRODUCT-CODE[@REVISION]>"),
            "{sub}: {text}"
        );
        assert!(
            text.contains("Without it, the newest revision of the device is taken"),
            "{sub}: {text}"
        );
    }
    let text = stdout(&esi_gen(&["diff", "--help"]));
    assert!(
        text.contains("--json\n          Machine-readable output on standard output")
            && text.contains("`diff` one object per difference"),
        "{text}"
    );
}

/// Writing a description in its own format and comparing the two is how a round trip is checked.
#[test]
fn a_file_and_its_own_format_rewrite_are_equal() {
    let dir = std::env::temp_dir().join(format!("esi-gen-compare-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("revisions-a.xml");
    let o = esi_gen(&["esi", A, "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let o = esi_gen(&["diff", A, out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stdout(&o));
    assert_eq!(stdout(&o), "");
}
