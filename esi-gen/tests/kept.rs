//! A description written in its own format keeps the file: an unedited one comes back byte for byte,
//! an edited one changes where the edit is and nowhere else, whatever the model does not hold (vendor
//! elements, attributes and keys, comments, layout, encoding). Each file of tests/descriptions/kept
//! holds one family of such parts: an `EtherCATInfoList` as IgH's `ethercat xml` writes a bus; an ESI's
//! `Device@Physics`, `HideType`, `AlternativeType`,
//! `Type@CheckRevisionNo`, `Info` timeouts and electrical data, `ImageData16x14`, `Profile/ProfileNo`
//! and `AddInfo`, object `Flags/Category`, `Fmmu@OpOnly`, `ESC` registers, `ShiftTimeSync0@Input/@Factor`,
//! names in two languages, CDATA, ISO-8859-1; an EDS's `LastEDS`, `CompactPDO`, `[Comments]`,
//! `Denotation`, comment lines and a vendor section; a DCF without `ParameterValue`s; an XDD's
//! `uniqueIDRef`s, `dataTypeList`, `parameterList`, `ProfileHeader` and transport layers.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn kept(name: &str) -> PathBuf {
    root().join("tests/descriptions/kept").join(name)
}

fn esi_gen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_esi-gen"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("runs")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("esi-gen-kept-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap()
}

/// `original` with each `(from, to)` replaced once, where it must be.
fn edited(original: &[u8], changes: &[(&[u8], &[u8])]) -> Vec<u8> {
    let mut out = original.to_vec();
    for (from, to) in changes {
        let at = out
            .windows(from.len())
            .position(|w| w == *from)
            .unwrap_or_else(|| panic!("{} in the file", String::from_utf8_lossy(from)));
        out.splice(at..at + from.len(), to.iter().copied());
    }
    out
}

#[test]
fn an_unedited_file_comes_back_byte_for_byte() {
    for (sub, name) in [
        ("esi", "vendor-parts.xml"),
        ("esi", "igh-bus.xml"),
        ("eds", "vendor-parts.eds"),
        ("dcf", "configured.dcf"),
        ("xdd", "vendor-parts.xdd"),
    ] {
        let o = esi_gen(&[sub, kept(name).to_str().unwrap()]);
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert_eq!(o.stdout, read(&kept(name)), "{name}");
        assert_eq!(String::from_utf8_lossy(&o.stderr), "", "{name}");
    }
}

/// Rewrites `name` with `sub` and the edit `args` to the file `out`, which must be the input with each
/// of `changes` made (as text, so that a failure shows the lines).
fn assert_edit(sub: &str, name: &str, args: &[&str], out: &str, changes: &[(&[u8], &[u8])]) {
    let out = tmp(out);
    let input = kept(name);
    let mut all = vec![sub, input.to_str().unwrap()];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", out.to_str().unwrap()]);
    let o = esi_gen(&all);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        String::from_utf8_lossy(&read(&out)),
        String::from_utf8_lossy(&edited(&read(&input), changes)),
        "{name}"
    );
}

#[test]
fn an_esi_edit_changes_the_one_attribute() {
    assert_edit(
        "esi",
        "vendor-parts.xml",
        &["--revision", "0x00020000"],
        "kp100.xml",
        &[(
            b"RevisionNo=\"#x00010000\" CheckRevisionNo",
            b"RevisionNo=\"#x00020000\" CheckRevisionNo",
        )],
    );
}

/// An `EtherCATInfoList` of two slaves as IgH's `ethercat xml` writes it (vendor IDs in decimal, names
/// in CDATA, no vendor names, PDO entries typed `UINT16`, a gap without a sub-index) stays a list: a
/// new revision changes each device's `RevisionNo` and nothing else.
#[test]
fn an_esi_list_edit_changes_each_device_in_place() {
    assert_edit(
        "esi",
        "igh-bus.xml",
        &["--revision", "0x00130000"],
        "igh-bus.xml",
        &[
            (
                b"\"#x0c1e3052\" RevisionNo=\"#x00120000\"",
                b"\"#x0c1e3052\" RevisionNo=\"#x00130000\"",
            ),
            (
                b"\"#x00030924\" RevisionNo=\"#x00010420\"",
                b"\"#x00030924\" RevisionNo=\"#x00130000\"",
            ),
        ],
    );
}

#[test]
fn an_eds_edit_changes_its_keys_in_place() {
    assert_edit(
        "eds",
        "vendor-parts.eds",
        &["--revision", "0x20000"],
        "kp200.eds",
        &[
            (b"FileName=vendor-parts.eds", b"FileName=kp200.eds"),
            (b"RevisionNumber=0x10000", b"RevisionNumber=0x00020000"),
        ],
    );
}

/// A DCF rewritten for another node gets that node-ID and nothing else: no `ParameterValue` for
/// the entries it did not configure, no new section.
#[test]
fn a_dcf_for_another_node_changes_only_its_node_id() {
    assert_edit(
        "dcf",
        "configured.dcf",
        &["--node-id", "5"],
        "axis2.dcf",
        &[
            (b"FileName=configured.dcf", b"FileName=axis2.dcf"),
            (b"NodeID=0x10", b"NodeID=5"),
        ],
    );
}

#[test]
fn an_xdd_edit_changes_its_attributes_and_elements_in_place() {
    assert_edit(
        "xdd",
        "vendor-parts.xdd",
        &["--product-code", "0x301"],
        "kp300.xdd",
        &[
            (b"fileName=\"vendor-parts.xdd\"", b"fileName=\"kp300.xdd\""),
            (
                b"<productID>0x00000300</productID>",
                b"<productID>0x00000301</productID>",
            ),
            (b"fileName=\"vendor-parts.xdd\"", b"fileName=\"kp300.xdd\""),
        ],
    );
}

/// `--normalise` readies a new file: the description from the product name where there is none,
/// and what else CiA 306 asks of a new EDS; the vendor's parts stay.
#[test]
fn normalise_adds_what_a_new_file_has() {
    let src = tmp("bare.eds");
    std::fs::write(
        &src,
        "; notes\n[DeviceInfo]\nProductName=Bare\nVendorNumber=0x1\n\n[1000]\nParameterName=Device type\nDataType=0x0007\nAccessType=ro\nDefaultValue=0x191\nDenotation=kept\n",
    )
    .unwrap();
    let out = tmp("new.eds");
    let o = esi_gen(&["eds", src.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(o.status.success());
    assert_eq!(read(&out), read(&src), "nothing added without --normalise");
    let o = esi_gen(&[
        "eds",
        src.to_str().unwrap(),
        "--normalise",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(read(&out)).unwrap();
    assert!(text.starts_with("; notes\n"), "{text}");
    assert!(text.contains("FileName=new.eds"), "{text}");
    assert!(text.contains("Description=Bare"), "{text}");
    assert!(text.contains("EDSVersion=4.0"), "{text}");
    assert!(
        text.contains("DefaultValue=0x191\nDenotation=kept\n"),
        "{text}"
    );
}

/// `diff` compares models; `diff --all` also the parts the models do not hold.
#[test]
fn diff_all_sees_what_the_model_does_not_hold() {
    let original = read(&kept("vendor-parts.eds"));
    let other = tmp("other.eds");
    let mut text = String::from_utf8(edited(
        &original,
        &[
            (b"CompactPDO=0x3", b"CompactPDO=0x1"),
            (b"LastEDS=vendor-parts-1.eds\n", b""),
        ],
    ))
    .unwrap();
    text.push_str("\n[VendorExtra]\nKey=1\n");
    std::fs::write(&other, text).unwrap();
    let a = kept("vendor-parts.eds");
    let o = esi_gen(&["diff", a.to_str().unwrap(), other.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "equal models");
    assert_eq!(String::from_utf8_lossy(&o.stdout), "");
    let o = esi_gen(&[
        "diff",
        "--all",
        a.to_str().unwrap(),
        other.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&o.stdout),
        "- file [FileInfo] LastEDS\n\
         ~ file [DeviceInfo] CompactPDO: 0x3 -> 0x1\n\
         + file [VendorExtra]\n"
    );
    let o = esi_gen(&[
        "--json",
        "diff",
        "--all",
        a.to_str().unwrap(),
        other.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let lines: Vec<serde_json::Value> = String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(
        lines,
        [
            serde_json::json!({"change": "only_in_a", "file_part": "[FileInfo] LastEDS", "a": "vendor-parts-1.eds"}),
            serde_json::json!({"change": "changed", "file_part": "[DeviceInfo] CompactPDO", "a": "0x3", "b": "0x1"}),
            serde_json::json!({"change": "only_in_b", "file_part": "[VendorExtra]", "b": "[VendorExtra]\nKey=1"}),
        ]
    );
    let o = esi_gen(&["diff", "--all", a.to_str().unwrap(), a.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0));

    let xml = kept("vendor-parts.xml");
    let other = tmp("other.xml");
    std::fs::write(
        &other,
        edited(
            &read(&xml),
            &[
                (b"<Fmmu OpOnly=\"1\">", b"<Fmmu>"),
                (b"Physics=\"YY\"", b"Physics=\"YYY\""),
            ],
        ),
    )
    .unwrap();
    let o = esi_gen(&[
        "diff",
        "--all",
        xml.to_str().unwrap(),
        other.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&o.stdout),
        "~ file EtherCATInfo/Descriptions/Devices/Device[KP100]/@Physics: YY -> YYY\n\
         - file EtherCATInfo/Descriptions/Devices/Device[KP100]/Fmmu[2]/@OpOnly\n"
    );
}

/// The file-level check of CI, on these files: every element, attribute, key and comment kept.
#[test]
fn the_file_level_check_finds_nothing_lost() {
    let o = Command::new("python3")
        .arg(root().join("scripts/file-level-check"))
        .arg(root().join("tests/descriptions/kept"))
        .arg("--esi-gen")
        .arg(env!("CARGO_BIN_EXE_esi-gen"))
        .output()
        .expect("python3 runs");
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{text}");
    assert!(
        text.starts_with("file-level-check: 5 files, 491 parts; unedited: 5 byte-identical, 0 parts lost, 0 added; edited (revision, file name): 5 files, 0 parts lost, 0 added by the edit"),
        "{text}"
    );
}

/// A conversion to another format cannot keep what the model does not hold, and says how much: the
/// EDS's comment lines (2), `LastEDS`, `CompactPDO`, `Denotation` and the vendor's section.
#[test]
fn another_format_names_the_file_parts_it_leaves_out() {
    let out = tmp("kp200.xdd");
    let o = esi_gen(&[
        "xdd",
        kept("vendor-parts.eds").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.ends_with("      6 × part of the file the model does not hold left out: #comment[1]\n"),
        "{err}"
    );
    let o = esi_gen(&[
        "--json",
        "xdd",
        kept("vendor-parts.eds").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["kept_as_written"], false);
    let last = v["not_kept"].as_array().unwrap().last().unwrap().clone();
    assert_eq!(
        last,
        serde_json::json!({"kind": "part of the file the model does not hold left out", "count": 6, "example": "#comment[1]"})
    );
    let o = esi_gen(&[
        "--json",
        "eds",
        kept("vendor-parts.eds").to_str().unwrap(),
        "-o",
        out.with_extension("eds").to_str().unwrap(),
    ]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["kept_as_written"], true);
    assert_eq!(v["not_kept"], serde_json::json!([]));
}
