//! `esi-gen check` as a user runs it on one file, on a folder of vendor files, as JSON, with
//! `--strict`, `--all` and `--round-trip`; on files that cannot be used and on what is not a file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn esi_gen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_esi-gen"))
        .args(args)
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join(".."))
        .output()
        .expect("runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// A fresh folder for one test.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("esi-gen-check-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The text with every time (`12.3 ms`, `; 45 ms`) replaced by `T ms`.
fn mask(text: &str) -> String {
    text.lines()
        .map(|line| {
            let words: Vec<&str> = line.split(' ').collect();
            let mut out: Vec<&str> = Vec::with_capacity(words.len());
            for (i, w) in words.iter().enumerate() {
                let before_ms = words.get(i + 1) == Some(&"ms");
                out.push(if before_ms && w.parse::<f64>().is_ok() {
                    "T"
                } else {
                    w
                });
            }
            out.join(" ") + "\n"
        })
        .collect()
}

/// An EDS with an unknown data type at line 8 and no 0x1018: two warnings, no error.
const ODD_EDS: &str = "[FileInfo]\nFileName=odd.eds\n[DeviceInfo]\nVendorName=V\nProductName=Odd\n\
    [1000]\nParameterName=Device type\nDataType=0x0017\nAccessType=ro\n";

/// An ESI whose vendor ID is no number (line 3, column 15): unusable.
const BAD_ESI: &str =
    "<?xml version=\"1.0\"?>\n<EtherCATInfo>\n  <Vendor><Id>#xZZ</Id></Vendor>\n</EtherCATInfo>\n";

#[test]
fn one_file_summary_with_warnings_at_their_positions() {
    let dir = folder("one");
    let eds = dir.join("odd.eds");
    std::fs::write(&eds, ODD_EDS).unwrap();
    let p = eds.display().to_string();
    let o = esi_gen(&["check", &p]);
    assert_eq!(o.status.code(), Some(0), "warnings only: {}", stdout(&o));
    assert_eq!(
        mask(&stdout(&o)),
        format!(
            "{p}: EDS, 1 device(s), read and checked in T ms\n\
             \n\
             Odd\n\
             \x20 vendor       0x00000000 V\n\
             \x20 product code 0x00000000  revision 0x00000000\n\
             \x20 dictionary   1 objects, 1 entries: 1 communication, 0 manufacturer, 0 profile\n\
             \x20 PDO mappings 0 receive, 0 transmit\n\
             \n\
             findings: 0 error(s), 2 warning(s)\n\
             \x20 {p}:1:1: warning: object 0x1018 (identity) is mandatory and missing\n\
             \x20 {p}:8:10: warning: DataType= in [1000]: 0x0017 is not a CiA 301 data type; the entry is read as DOMAIN\n"
        )
    );

    // --strict: the same findings, as errors, and exit 1.
    let o = esi_gen(&["check", "--strict", &p]);
    assert_eq!(o.status.code(), Some(1));
    let text = stdout(&o);
    assert!(
        text.contains("findings: 2 error(s), 0 warning(s)\n"),
        "{text}"
    );
    assert!(
        text.contains(&format!(
            "  {p}:1:1: error: object 0x1018 (identity) is mandatory and missing\n"
        )),
        "{text}"
    );

    // --round-trip: an EDS written and read back is equal.
    let o = esi_gen(&["check", "--round-trip", &p]);
    assert_eq!(o.status.code(), Some(0), "{}", stdout(&o));
    assert!(
        stdout(&o).ends_with("round trip: equal\n"),
        "{}",
        stdout(&o)
    );
}

#[test]
fn an_unusable_file_is_one_error_line_and_exit_1() {
    let dir = folder("bad");
    let esi = dir.join("bad.xml");
    std::fs::write(&esi, BAD_ESI).unwrap();
    let p = esi.display().to_string();
    let o = esi_gen(&["check", &p]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        mask(&stdout(&o)),
        format!(
            "{p}: ESI, 0 device(s), read and checked in T ms\n\
             \n\
             findings: 1 error(s), 0 warning(s)\n\
             \x20 {p}:3:15: error: expected a number like #x1A00 or 6656 in <Vendor>/<Id>, found `#xZZ`\n"
        )
    );
}

#[test]
fn twenty_findings_unless_all() {
    let dir = folder("all");
    let eds = dir.join("many.eds");
    let mut text = String::from("[1000]\nParameterName=D\nDataType=0x0007\nAccessType=ro\n");
    text.push_str("[1018]\nParameterName=I\nDataType=0x0007\nAccessType=ro\n");
    for n in 0..25 {
        text.push_str(&format!(
            "[{:04X}]\nParameterName=x\nDataType=0x0300\nAccessType=ro\n",
            0x2000 + n
        ));
    }
    std::fs::write(&eds, text).unwrap();
    let p = eds.display().to_string();
    let o = esi_gen(&["check", &p]);
    let out = stdout(&o);
    let listed = out.lines().filter(|l| l.contains(": warning: ")).count();
    assert_eq!(listed, 20, "{out}");
    assert!(
        out.ends_with("  … 5 more (--all lists every finding)\n"),
        "{out}"
    );
    // The first and the last listed: lines 11 and 87 (each object takes four lines from line 9).
    assert!(out.contains(&format!("  {p}:11:10: warning: DataType= in [2000]: 0x0300 is not a CiA 301 data type; the entry is read as DOMAIN\n")), "{out}");
    let o = esi_gen(&["check", "--all", &p]);
    let out = stdout(&o);
    assert_eq!(
        out.lines().filter(|l| l.contains(": warning: ")).count(),
        25
    );
    assert!(out.contains(&format!("  {p}:107:10: warning: DataType= in [2018]: 0x0300 is not a CiA 301 data type; the entry is read as DOMAIN\n")), "{out}");
    assert!(!out.contains("more (--all"), "{out}");
}

#[test]
fn a_folder_gets_a_line_per_file_and_a_summary() {
    let dir = folder("batch");
    std::fs::write(dir.join("odd.eds"), ODD_EDS).unwrap();
    std::fs::write(dir.join("bad.xml"), BAD_ESI).unwrap();
    std::fs::write(dir.join("notes.txt"), "not a description").unwrap();
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    std::fs::write(dir.join("sub").join("again.EDS"), ODD_EDS).unwrap();
    let d = dir.display().to_string();
    let o = esi_gen(&["check", &d]);
    assert_eq!(o.status.code(), Some(1), "one file has an error");
    assert_eq!(
        mask(&stdout(&o)),
        format!(
            "{d}/bad.xml  ESI  0 device(s)  0 objects  1 error(s)  0 warning(s)  T ms\n\
             \x20   {d}/bad.xml:3:15: error: expected a number like #x1A00 or 6656 in <Vendor>/<Id>, found `#xZZ`\n\
             {d}/odd.eds  EDS  1 device(s)  1 objects  0 error(s)  2 warning(s)  T ms\n\
             {d}/sub/again.EDS  EDS  1 device(s)  1 objects  0 error(s)  2 warning(s)  T ms\n\
             3 file(s): 2 passed, 1 with errors; 1 error(s), 4 warning(s); T ms\n"
        )
    );

    // Files named one by one, the same; with --round-trip each passing line says so.
    let odd = format!("{d}/odd.eds");
    let o = esi_gen(&["check", "--round-trip", &odd, &format!("{d}/sub/again.EDS")]);
    assert_eq!(o.status.code(), Some(0), "{}", stdout(&o));
    assert_eq!(
        mask(&stdout(&o)),
        format!(
            "{d}/odd.eds  EDS  1 device(s)  1 objects  0 error(s)  2 warning(s)  T ms  round trip equal\n\
             {d}/sub/again.EDS  EDS  1 device(s)  1 objects  0 error(s)  2 warning(s)  T ms  round trip equal\n\
             2 file(s): 2 passed, 0 with errors; 0 error(s), 4 warning(s); T ms\n"
        )
    );
}

#[test]
fn json_holds_every_file_device_and_finding() {
    let dir = folder("json");
    std::fs::write(dir.join("odd.eds"), ODD_EDS).unwrap();
    std::fs::write(dir.join("bad.xml"), BAD_ESI).unwrap();
    let d = dir.display().to_string();
    let o = esi_gen(&["check", "--json", &d]);
    assert_eq!(o.status.code(), Some(1));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON document");
    let files = doc["files"].as_array().unwrap();
    assert_eq!(files.len(), 2);
    let bad = &files[0];
    assert_eq!(bad["path"], format!("{d}/bad.xml"));
    assert_eq!(bad["format"], "ESI");
    assert_eq!(bad["readable"], false);
    assert_eq!(bad["errors"], 1);
    assert_eq!(
        bad["findings"][0],
        serde_json::json!({
            "severity": "error", "line": 3, "column": 15, "device": null, "index": null, "sub": null,
            "message": "expected a number like #x1A00 or 6656 in <Vendor>/<Id>, found `#xZZ`"
        })
    );
    let odd = &files[1];
    assert_eq!(odd["readable"], true);
    assert_eq!(
        odd["devices"],
        serde_json::json!([{
            "name": "Odd", "product_name": "Odd", "vendor_id": 0, "product_code": 0, "revision": 0,
            "objects": 1, "entries": 1, "flagged": []
        }])
    );
    assert_eq!(odd["warnings"], 2);
    assert_eq!(odd["findings"][1]["line"], 8);
    assert_eq!(odd["findings"][1]["column"], 10);
    assert_eq!(odd["round_trip"], serde_json::Value::Null);
    let summary = &doc["summary"];
    assert_eq!(summary["files"], 2);
    assert_eq!(summary["passed"], 1);
    assert_eq!(summary["with_errors"], 1);
    assert_eq!(summary["errors"], 1);
    assert_eq!(summary["warnings"], 2);
}

#[test]
fn what_is_not_a_regular_file_is_refused_at_once() {
    let dir = folder("fifo");
    let fifo = dir.join("pipe.eds");
    let made = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo");
    assert!(made.success());
    let p = fifo.display().to_string();
    // Nobody writes to the FIFO: opening it for reading would wait for ever. The check must end at
    // once; 30 s is room for a machine running at a fraction of its speed.
    let mut child = Command::new(env!("CARGO_BIN_EXE_esi-gen"))
        .args(["check", &p, "/dev/zero"])
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("runs");
    let started = std::time::Instant::now();
    while child.try_wait().expect("waits").is_none() {
        if started.elapsed() > std::time::Duration::from_secs(30) {
            let _ = child.kill();
            panic!("esi-gen check hangs on a FIFO");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let o = child.wait_with_output().expect("output");
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        mask(&stdout(&o)),
        format!(
            "{p}  ?  0 device(s)  0 objects  1 error(s)  0 warning(s)  T ms\n\
             \x20   {p}: error: not a regular file\n\
             /dev/zero  ?  0 device(s)  0 objects  1 error(s)  0 warning(s)  T ms\n\
             \x20   /dev/zero: error: not a regular file\n\
             2 file(s): 0 passed, 2 with errors; 2 error(s), 0 warning(s); T ms\n"
        )
    );
}

/// `CANOPEN_MAX_FILE_BYTES` replaces the size limit: at 100 bytes the fixture (105,773 bytes) is refused
/// before it is read, the line naming its size and the way to raise the limit; a value that is not a
/// number of bytes is named as such; at its exact size the file reads.
#[test]
fn canopen_max_file_bytes_replaces_the_size_limit() {
    let file = "fixtures/src/smd.esi.xml";
    let run = |limit: &str| {
        Command::new(env!("CARGO_BIN_EXE_esi-gen"))
            .args(["check", file])
            .env("CANOPEN_MAX_FILE_BYTES", limit)
            .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join(".."))
            .output()
            .expect("runs")
    };
    let o = run("100");
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stdout(&o).contains(&format!(
            "\n  {file}: error: 105773 bytes, more than the 100 such a file may have \
             (CANOPEN_MAX_FILE_BYTES=BYTES raises the limit)\n"
        )),
        "{}",
        stdout(&o)
    );
    let o = run("lots");
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stdout(&o).contains(&format!(
            "\n  {file}: error: CANOPEN_MAX_FILE_BYTES=\"lots\" is not a number of bytes\n"
        )),
        "{}",
        stdout(&o)
    );
    let o = run("105773");
    assert_eq!(o.status.code(), Some(0), "{}", stdout(&o));
    assert!(
        stdout(&o).starts_with(&format!("{file}: ESI, 2 device(s), ")),
        "{}",
        stdout(&o)
    );
}

#[test]
fn device_picks_one_device_of_a_file() {
    let o = esi_gen(&["check", "fixtures/src/smd.esi.xml", "--device", "SMD24K"]);
    assert_eq!(o.status.code(), Some(0), "{}", stdout(&o));
    let text = stdout(&o);
    assert!(
        text.starts_with("fixtures/src/smd.esi.xml: ESI, 1 device(s), "),
        "{text}"
    );
    assert!(text.contains("\nSMD24K\n"), "{text}");
    assert!(!text.contains("\nSMD23K-B\n"), "{text}");
    let o = esi_gen(&["check", "fixtures/src/smd.esi.xml", "--device", "SMD99"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stdout(&o).contains(": error: no device matches `SMD99`; the file holds SMD23K-B (product code 0x00000000, revision 0x00000000), SMD24K (product code 0x00000000, revision 0x00000000)\n"),
        "{}",
        stdout(&o)
    );
}

/// An ESI of `n` CoE devices (product codes 1…n, revision 0x10 each): each has 0x1000 but no 0x1018, which
/// is one warning at its `Device` element (line 3 + 3·k for device k from 0).
fn esi_of(n: usize) -> String {
    let mut text = String::from(
        "<?xml version=\"1.0\"?>\n<EtherCATInfo><Vendor><Id>7</Id><Name>V</Name></Vendor><Descriptions><Devices>\n",
    );
    for k in 1..=n {
        text.push_str(&format!(
            "<Device>\n<Type ProductCode=\"#x{k:X}\" RevisionNo=\"#x10\">T{k}</Type><Name>Terminal {k}</Name>\n\
             <Profile><Dictionary><Objects><Object><Index>#x1000</Index><Name>Device type</Name><Type>UDINT</Type></Object></Objects></Dictionary></Profile><Mailbox><CoE/></Mailbox></Device>\n"
        ));
    }
    text.push_str("</Devices></Descriptions></EtherCATInfo>\n");
    text
}

#[test]
fn devices_of_a_file_are_named_in_their_findings() {
    let dir = folder("devices");
    let two = dir.join("two.xml");
    std::fs::write(&two, esi_of(2)).unwrap();
    let p = two.display().to_string();
    let o = esi_gen(&["check", &p]);
    assert_eq!(o.status.code(), Some(0), "{}", stdout(&o));
    let text = mask(&stdout(&o));
    assert!(
        text.contains("\nT1\n  name         Terminal 1\n  vendor       0x00000007 V\n  product code 0x00000001  revision 0x00000010\n"),
        "{text}"
    );
    assert!(
        text.ends_with(&format!(
            "findings: 0 error(s), 2 warning(s)\n\
             \x20 {p}:3:1: warning: T1 rev 0x00000010: object 0x1018 (identity) is mandatory and missing\n\
             \x20 {p}:6:1: warning: T2 rev 0x00000010: object 0x1018 (identity) is mandatory and missing\n"
        )),
        "{text}"
    );
    // One device picked by its product code: no device label.
    let o = esi_gen(&["check", &p, "--device", "0x2"]);
    let text = mask(&stdout(&o));
    assert!(
        text.ends_with(&format!(
            "findings: 0 error(s), 1 warning(s)\n\
             \x20 {p}:6:1: warning: object 0x1018 (identity) is mandatory and missing\n"
        )),
        "{text}"
    );

    // Five devices: a line each instead of five summaries.
    let five = dir.join("five.xml");
    std::fs::write(&five, esi_of(5)).unwrap();
    let p = five.display().to_string();
    let o = esi_gen(&["check", &p]);
    let text = mask(&stdout(&o));
    assert!(
        text.starts_with(&format!(
            "{p}: ESI, 5 device(s), read and checked in T ms\n\
             \x20 T1                       product code 0x00000001  revision 0x00000010  1 objects\n\
             \x20 T2                       product code 0x00000002  revision 0x00000010  1 objects\n"
        )),
        "{text}"
    );
    assert!(!text.contains("  name "), "{text}");
    // Four devices: four summaries.
    std::fs::write(&five, esi_of(4)).unwrap();
    let text = stdout(&esi_gen(&["check", &p]));
    assert_eq!(text.matches("  name         Terminal").count(), 4, "{text}");
}

#[test]
fn a_batch_lists_three_errors_of_a_file_then_counts_the_rest() {
    let dir = folder("strict-batch");
    std::fs::write(dir.join("five.xml"), esi_of(5)).unwrap();
    let d = dir.display().to_string();
    let o = esi_gen(&["check", "--strict", &d]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        mask(&stdout(&o)),
        format!(
            "{d}/five.xml  ESI  5 device(s)  5 objects  5 error(s)  0 warning(s)  T ms\n\
             \x20   {d}/five.xml:3:1: error: T1 rev 0x00000010: object 0x1018 (identity) is mandatory and missing\n\
             \x20   {d}/five.xml:6:1: error: T2 rev 0x00000010: object 0x1018 (identity) is mandatory and missing\n\
             \x20   {d}/five.xml:9:1: error: T3 rev 0x00000010: object 0x1018 (identity) is mandatory and missing\n\
             \x20   … 2 more error(s)\n\
             1 file(s): 0 passed, 1 with errors; 5 error(s), 0 warning(s); T ms\n"
        )
    );
    // --all lists every finding, warnings too.
    let o = esi_gen(&["check", "--all", &d]);
    let text = stdout(&o);
    assert_eq!(text.matches(": warning: T").count(), 5, "{text}");
    assert!(!text.contains("more error"), "{text}");
}

/// The commissioning line of a DCF's summary: its node-ID and bit rate, or that there are none.
#[test]
fn a_dcf_summary_has_its_node_id_and_bit_rate() {
    let dir = folder("dcf");
    let dcf = dir.join("node.dcf");
    let base = "[DeviceInfo]\nProductName=N\n[1000]\nParameterName=Device type\nDataType=0x0007\nAccessType=ro\n";
    std::fs::write(
        &dcf,
        format!("{base}[DeviceComissioning]\nNodeID=5\nBaudrate=500\n"),
    )
    .unwrap();
    let text = stdout(&esi_gen(&["check", dcf.to_str().unwrap()]));
    assert!(
        text.contains("\n  node-ID      5  bit rate 500 kbit/s\n"),
        "{text}"
    );
    std::fs::write(&dcf, format!("{base}[DeviceComissioning]\nNodeName=n\n")).unwrap();
    let text = stdout(&esi_gen(&["check", dcf.to_str().unwrap()]));
    assert!(
        text.contains("\n  node-ID      unconfigured  bit rate not given\n"),
        "{text}"
    );
}

/// An EDS with `ObjFlags` (CiA 306 §4.6.3): a RECORD 0x2000 flagged 0x3 in its object's section
/// (its two entries inherit them), a VAR 0x2001 flagged 0x1, an entry 0x2002:01 flagged 0x2 in its
/// own section, a VAR 0x2003 with a reserved bit (0x4) and a VAR 0x2004 flagged 0x0; and `extra`
/// VARs 0x2100.. flagged 0x1 after them.
fn flagged_eds(extra: usize) -> String {
    let var = |index: u32, flags: &str| {
        format!(
            "[{index:X}]\nParameterName=Var {index:X}\nObjectType=0x7\nDataType=0x0007\n\
             AccessType=rw\nDefaultValue=0\n{flags}"
        )
    };
    let mut text = String::from(
        "[FileInfo]\nFileName=flags.eds\n[DeviceInfo]\nVendorName=V\nProductName=Flags\n\
         [2000]\nParameterName=Calibration\nObjectType=0x9\nSubNumber=2\nObjFlags=0x3\n\
         [2000sub0]\nParameterName=Count\nObjectType=0x7\nDataType=0x0005\nAccessType=ro\nDefaultValue=1\n\
         [2000sub1]\nParameterName=Gain\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=5\n\
         [2002]\nParameterName=Record\nObjectType=0x9\nSubNumber=2\n\
         [2002sub0]\nParameterName=Count\nObjectType=0x7\nDataType=0x0005\nAccessType=ro\nDefaultValue=1\n\
         [2002sub1]\nParameterName=Live\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=0\nObjFlags=2\n",
    );
    text += &var(0x2001, "ObjFlags=1\n");
    text += &var(0x2003, "ObjFlags=0x4\n");
    text += &var(0x2004, "ObjFlags=0x0\n");
    for i in 0..extra {
        text += &var(0x2100 + i as u32, "ObjFlags=1\n");
    }
    text
}

/// `check` names each entry a description flags with `ObjFlags` and what `sdo-tool` makes of it:
/// `apply` does not write an entry flagged "refuse write on download" (bit 0), `dump` does not read
/// one flagged "refuse read on scan" (bit 1); an object's flags reach its entries; reserved bits are
/// shown as read; 0x0 is no flag. In text, in JSON, the first 10 unless `--all`.
#[test]
fn object_flags_are_explained_entry_by_entry() {
    let dir = folder("flags");
    let eds = dir.join("flags.eds");
    std::fs::write(&eds, flagged_eds(0)).unwrap();
    let p = eds.display().to_string();
    let o = esi_gen(&["check", &p]);
    let text = stdout(&o);
    assert!(
        text.contains(
            "  PDO mappings 0 receive, 0 transmit\n\
             \x20 ObjFlags     5 entries flagged: 3 refuse write on download (sdo-tool apply does not \
             write them), 3 refuse read on scan (sdo-tool dump does not read them)\n\
             \x20   0x2000:00 Count: 0x3 (refuse write on download, refuse read on scan)\n\
             \x20   0x2000:01 Gain: 0x3 (refuse write on download, refuse read on scan)\n\
             \x20   0x2001:00 Var 2001: 0x1 (refuse write on download)\n\
             \x20   0x2002:01 Live: 0x2 (refuse read on scan)\n\
             \x20   0x2003:00 Var 2003: 0x4\n\
             \n\
             findings: 0 error(s), "
        ),
        "{text}"
    );

    let o = esi_gen(&["check", "--json", &p]);
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON document");
    let flagged = &doc["files"][0]["devices"][0]["flagged"];
    assert_eq!(flagged.as_array().unwrap().len(), 5, "{flagged}");
    assert_eq!(
        flagged[0],
        serde_json::json!({"index": 0x2000, "sub": 0, "name": "Count", "flags": 3,
            "meaning": "refuse write on download: sdo-tool apply does not write it; \
                        refuse read on scan: sdo-tool dump does not read it"})
    );
    assert_eq!(
        flagged[3]["meaning"],
        "refuse read on scan: sdo-tool dump does not read it"
    );
    assert_eq!(
        flagged[4]["meaning"],
        "reserved bits set: no tool acts on them"
    );

    // 5 + 7 flagged: the first 10 and a count of the rest; --all lists all 12.
    std::fs::write(&eds, flagged_eds(7)).unwrap();
    let text = stdout(&esi_gen(&["check", &p]));
    assert!(
        text.contains("  ObjFlags     12 entries flagged: 10 refuse"),
        "{text}"
    );
    assert!(text.contains("    0x2104:00 Var 2104: 0x1 (refuse write on download)\n    … 2 more (--all lists every one)\n"), "{text}");
    assert!(!text.contains("0x2105:00"), "{text}");
    let text = stdout(&esi_gen(&["check", "--all", &p]));
    assert!(
        text.contains("    0x2106:00 Var 2106: 0x1 (refuse write on download)\n\nfindings"),
        "{text}"
    );
    assert!(!text.contains("more (--all"), "{text}");

    // One entry flagged.
    std::fs::write(
        &eds,
        "[DeviceInfo]\nProductName=One\n[2001]\nParameterName=V\nObjectType=0x7\n\
         DataType=0x0007\nAccessType=rw\nObjFlags=0x2\n",
    )
    .unwrap();
    let text = stdout(&esi_gen(&["check", &p]));
    assert!(text.contains("  ObjFlags     1 entry flagged: 0 refuse write on download (sdo-tool apply does not write them), 1 refuse read on scan"), "{text}");
}
