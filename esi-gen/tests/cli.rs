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

/// An identity file that is not a regular file (a device, a FIFO) is refused before it is opened,
/// with one line, exit 2.
#[test]
fn an_identity_file_must_be_a_regular_file() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("ids.toml");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    for path in ["/dev/zero", fifo.to_str().unwrap()] {
        let o = esi_gen(&[
            "eds",
            "fixtures/src/smd.esi.xml",
            "--device",
            "SMD24K",
            "--identity",
            path,
        ]);
        assert_eq!(o.status.code(), Some(2), "{path}: {}", stderr(&o));
        assert_eq!(stderr(&o).lines().count(), 1, "{}", stderr(&o));
        assert!(
            stderr(&o).contains(&format!("{path}: not a regular file")),
            "{}",
            stderr(&o)
        );
    }
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

/// `esi-gen dcf` configures every writable entry (`ParameterValue`), so that `sdo-tool apply` writes
/// them: a `$NODEID` one relative to the node-ID; not the read-only ones, a DOMAIN, nor the command entry
/// 0x1010 (store parameters). Without `--node-id` there is no `NodeID=` (it once made up node 1, and
/// `$NODEID+0x80` came back as 0x81); the dictionary is the input's but for the configured values.
#[test]
fn dcf_configures_the_writable_entries() {
    let eds = tmp("configure.eds");
    std::fs::write(
        &eds,
        "[1000]\nParameterName=Device type\nDataType=0x0007\nAccessType=ro\nDefaultValue=0x191\n\
         [1010]\nParameterName=Store parameters\nObjectType=0x8\n\
         [1010sub0]\nParameterName=Highest sub-index supported\nDataType=0x0005\nAccessType=ro\nDefaultValue=1\n\
         [1010sub1]\nParameterName=Save all parameters\nDataType=0x0007\nAccessType=rw\nDefaultValue=1\n\
         [1014]\nParameterName=COB-ID EMCY\nDataType=0x0007\nAccessType=rw\nDefaultValue=$NODEID+0x80\n\
         [1017]\nParameterName=Producer heartbeat time\nDataType=0x0006\nAccessType=rw\n\
         [1F50]\nParameterName=Program data\nDataType=0x000F\nAccessType=wo\n",
    )
    .unwrap();
    let dcf = tmp("configure.dcf");
    let o = esi_gen(&["dcf", eds.to_str().unwrap(), "-o", dcf.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&dcf).unwrap();
    // The DCF is the EDS as it was written, with what a DCF adds in the writer's layout.
    assert!(text.contains(
        "[DeviceComissioning]\nNodeName=\nBaudrate=0\nNetNumber=0\nNetworkName=\nCANopenManager=0\n\n"
    ), "{text}");
    for section in [
        "[1000]\nParameterName=Device type\nDataType=0x0007\nAccessType=ro\nDefaultValue=0x191\n[1010]\n",
        "[1010sub1]\nParameterName=Save all parameters\nDataType=0x0007\nAccessType=rw\nDefaultValue=1\n[1014]\n",
        "[1014]\nParameterName=COB-ID EMCY\nDataType=0x0007\nAccessType=rw\nDefaultValue=$NODEID+0x80\n\
         ParameterValue=$NODEID+0x80\n[1017]\n",
        "[1017]\nParameterName=Producer heartbeat time\nDataType=0x0006\nAccessType=rw\n\
         ParameterValue=0x0000\n[1F50]\n",
        "[1F50]\nParameterName=Program data\nDataType=0x000F\nAccessType=wo\n",
    ] {
        assert!(text.contains(section), "{section}\n{text}");
    }
    assert!(!text.contains("NodeID"), "{text}");
    // What the DCF adds to the EDS: its name and format version, CAN and commissioning sections, and the
    // configured values; the dictionary is the same otherwise.
    let o = esi_gen(&["diff", eds.to_str().unwrap(), dcf.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", stdout(&o));
    assert_eq!(
        stdout(&o),
        "~ file info file name: \"\" -> \"configure.dcf\"\n\
         ~ file info format version: \"\" -> \"4.0\"\n\
         + CAN\n\
         + commissioning\n\
         ~ 0x1014:00 value set: no -> yes\n\
         ~ 0x1014:00 value relative to the node-ID: no -> yes\n\
         ~ 0x1017:00 value set: no -> yes\n"
    );

    // For node 5: the COB-ID follows the node-ID and stays relative.
    let o = esi_gen(&[
        "dcf",
        eds.to_str().unwrap(),
        "--node-id",
        "5",
        "-o",
        dcf.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&dcf).unwrap();
    assert!(text.contains("[DeviceComissioning]\nNodeID=5\n"), "{text}");
    assert!(text.contains("DefaultValue=$NODEID+0x80\nParameterValue=$NODEID+0x80\n"));
    let o = esi_gen(&["diff", eds.to_str().unwrap(), dcf.to_str().unwrap()]);
    assert_eq!(
        stdout(&o),
        "~ file info file name: \"\" -> \"configure.dcf\"\n\
         ~ file info format version: \"\" -> \"4.0\"\n\
         + CAN\n\
         + commissioning\n\
         ~ 0x1014:00 value: 0x00000080 -> 0x00000085\n\
         ~ 0x1014:00 value set: no -> yes\n\
         ~ 0x1014:00 value relative to the node-ID: no -> yes\n\
         ~ 0x1017:00 value set: no -> yes\n"
    );
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

/// A small CoE device: 0x1000 and one mappable input, with a mailbox.
const SMALL_ESI: &str = "<?xml version=\"1.0\"?>\n\
<EtherCATInfo><Vendor><Id>7</Id><Name>V</Name></Vendor><Descriptions><Devices>\n\
<Device><Type ProductCode=\"#x2\" RevisionNo=\"#x10\">T2</Type><Name>Terminal</Name>\n\
<Profile><Dictionary><DataTypes><DataType><Name>UDINT</Name><BitSize>32</BitSize></DataType></DataTypes><Objects>\n\
<Object><Index>#x1000</Index><Name>Device type</Name><Type>UDINT</Type><BitSize>32</BitSize><Info><DefaultData>91010000</DefaultData></Info><Flags><Access>ro</Access></Flags></Object>\n\
<Object><Index>#x6000</Index><Name>Input</Name><Type>UDINT</Type><BitSize>32</BitSize><Flags><Access>ro</Access><PdoMapping>T</PdoMapping></Flags></Object>\n\
</Objects></Dictionary></Profile><Mailbox><CoE/></Mailbox></Device>\n\
</Devices></Descriptions></EtherCATInfo>\n";

/// A conversion reads back what it wrote and names, on stderr, what the target format did not keep or
/// added, a line per kind with its count and first place; nothing when everything came through.
#[test]
fn conversions_name_what_they_do_not_keep() {
    let src = tmp("small.xml");
    std::fs::write(&src, SMALL_ESI).unwrap();
    let s = src.to_str().unwrap();
    let o = esi_gen(&["esi", s, "-o", tmp("small-again.xml").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(stderr(&o), "");
    let o = esi_gen(&["eds", s, "-o", tmp("small.eds").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(
        stderr(&o),
        format!(
            "esi-gen: {s}: written as EDS, 1 difference(s) read back (what EDS does not carry, or adds):\n\
             \x20     1 × EtherCAT left out: - EtherCAT\n"
        )
    );
    // XDD carries the revision in 0x1018:03 only, which this device lacks; it needs a creation date.
    let o = esi_gen(&["xdd", s]);
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(
        stderr(&o),
        format!(
            "esi-gen: {s}: written as XDD, 3 difference(s) read back (what XDD does not carry, or adds):\n\
             \x20     1 × identity revision changed: ~ identity revision: 0x00000010 -> 0x00000000\n\
             \x20     1 × file info creation date changed: ~ file info creation date: \"\" -> \"1970-01-01\"\n\
             \x20     1 × EtherCAT left out: - EtherCAT\n"
        )
    );
    // Several differences of one kind are one line, counted, with the first of them.
    let mut text = SMALL_ESI.replace(
        "<Name>Input</Name>",
        "<Name>Input</Name><Comment>first</Comment>",
    );
    text = text.replace(
        "<Name>Device type</Name>",
        "<Name>Device type</Name><Comment>kind</Comment>",
    );
    std::fs::write(&src, text).unwrap();
    let o = esi_gen(&["eds", s, "-o", tmp("small.eds").to_str().unwrap()]);
    let err = stderr(&o);
    assert!(
        err.contains(
            "\n      2 × object description changed: ~ 0x1000 description: \"kind\" -> none\n"
        ),
        "{err}"
    );
    // `-o -` is stdout, as no -o is.
    let o = esi_gen(&["esi", s, "-o", "-"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(stdout(&o).starts_with("<?xml"), "{}", stdout(&o));
    assert!(!root().join("-").exists());
    // The Markdown page is not read back.
    let o = esi_gen(&["doc", s]);
    assert_eq!((o.status.code(), stderr(&o)), (Some(0), String::new()));
}

/// `--json` on every command: one JSON object on standard output and nothing on standard error;
/// a conversion's report carries what the target format does not keep, as the text report does.
#[test]
fn json_output_of_every_command() {
    let one = |o: &Output| -> serde_json::Value {
        assert_eq!(stderr(o), "", "nothing on standard error");
        let out = stdout(o);
        assert_eq!(out.lines().count(), 1, "one line: {out}");
        serde_json::from_str(&out).unwrap_or_else(|e| panic!("{out}: {e}"))
    };
    let src = tmp("json.xml");
    std::fs::write(&src, SMALL_ESI).unwrap();
    let s = src.to_str().unwrap();
    let eds = tmp("json.eds");
    let o = esi_gen(&["--json", "eds", s, "-o", eds.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0));
    let v = one(&o);
    assert_eq!(v["format"], "EDS");
    assert_eq!(v["input"], s);
    assert_eq!(v["output"], eds.to_str().unwrap());
    assert_eq!(
        v["bytes"],
        std::fs::metadata(&eds).unwrap().len(),
        "the size of the file written"
    );
    assert_eq!(
        v["not_kept"],
        serde_json::json!([{"kind": "EtherCAT left out", "count": 1, "example": "- EtherCAT"}])
    );
    assert_eq!(v["devices"].as_array().unwrap().len(), 1);
    // ESI to ESI keeps everything: an empty list.
    let o = esi_gen(&[
        "esi",
        s,
        "--json",
        "-o",
        tmp("json-again.xml").to_str().unwrap(),
    ]);
    assert_eq!(one(&o)["not_kept"], serde_json::json!([]));
    // The report takes standard output: the file must be named.
    let o = esi_gen(&["--json", "eds", s]);
    assert_eq!(o.status.code(), Some(2));
    let v = one(&o);
    assert_eq!(v["exit_code"], 2);
    assert_eq!(
        v["error"],
        "--json writes its report on standard output: give the file to write with -o FILE"
    );
    // An error as one object: a missing file.
    let o = esi_gen(&["--json", "check", "no-such-file.xml"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        one(&o)["error"]
            .as_str()
            .unwrap()
            .starts_with("no-such-file.xml: "),
        "{}",
        stdout(&o)
    );
    // The SII image: its file and size.
    let bin = tmp("json.bin");
    let o = esi_gen(&["--json", "sii", s, "-o", bin.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v = one(&o);
    assert_eq!(v["output"], bin.to_str().unwrap());
    assert_eq!(v["bytes"], std::fs::metadata(&bin).unwrap().len());
    // The fixtures are up to date: nothing stale.
    let o = esi_gen(&["--json", "fixtures", "--check"]);
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(one(&o), serde_json::json!({"stale": []}));
    // Regenerating into a copy of the sources: the 11 files written, as one object.
    let copy = tmp("fixtures-copy");
    std::fs::create_dir_all(copy.join("src")).unwrap();
    for f in ["src/smd.esi.xml", "src/x67sm2436.xdd", "identity.toml"] {
        std::fs::copy(root().join("fixtures").join(f), copy.join(f)).unwrap();
    }
    let o = esi_gen(&["--json", "fixtures", "--root", copy.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v = one(&o);
    let written = v["written"].as_array().unwrap();
    assert_eq!(written.len(), 11, "{v}");
    for w in written {
        assert!(std::path::Path::new(w.as_str().unwrap()).is_file(), "{w}");
    }
    // `check` and `diff` as before, with the flag before or after the command.
    let o = esi_gen(&["--json", "check", s]);
    assert_eq!(o.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["files"][0]["path"], s);
    let o = esi_gen(&["diff", s, s, "--json"]);
    assert_eq!((o.status.code(), stdout(&o)), (Some(0), String::new()));
}

/// `esi-gen completions SHELL` and `esi-gen man DIR`: the script names the subcommands; a page for
/// the tool and each subcommand, each named on standard output.
#[test]
fn completions_and_manual_pages() {
    let o = esi_gen(&["completions", "bash"]);
    assert!(o.status.success());
    let script = stdout(&o);
    assert!(script.contains("complete -F _esi__gen -o nosort -o bashdefault -o default esi-gen"));
    assert!(script.contains("esi__gen,check)"));
    let dir = tmp("man");
    let o = esi_gen(&["man", dir.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let pages: Vec<String> = stdout(&o).lines().map(str::to_string).collect();
    assert_eq!(pages[0], dir.join("esi-gen.1").display().to_string());
    for page in [
        "esi-gen.1",
        "esi-gen-check.1",
        "esi-gen-diff.1",
        "esi-gen-man.1",
    ] {
        assert!(
            pages.contains(&dir.join(page).display().to_string()),
            "{page}"
        );
    }
    let check = std::fs::read_to_string(dir.join("esi-gen-check.1")).unwrap();
    assert!(check.contains(".TH esi-gen-check 1"));
}
