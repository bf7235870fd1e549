//! How `sdo-tool` shows the values it reads with a description, against `canopen-node` running
//! `examples/drive.eds` at node 2 and `examples/io-device.eds` at node 3 on a socketcand server of
//! 127.0.0.1: status and control words, identities, COB-IDs and PDO mappings in hex with their
//! width (a mapping with what it maps), other numbers in decimal; a DOMAIN of 64 KiB as its first
//! 32 bytes and its length in `read`, `watch` and `decode`, whole with `--full`.

mod common;

use std::process::{Command, Stdio};

fn drive_od() -> String {
    testkit::root()
        .join("examples/drive.eds")
        .display()
        .to_string()
}

fn io_od() -> String {
    testkit::root()
        .join("examples/io-device.eds")
        .display()
        .to_string()
}

/// Both nodes, on a socketcand server of their own: the process and its clients' bus.
fn nodes() -> (common::Proc, String) {
    let (p, port) = common::node_server(&[
        "--od",
        &format!("{}@2", drive_od()),
        "--od",
        &format!("{}@3", io_od()),
    ]);
    (p, common::socketcand_bus(port))
}

/// With `--od examples/drive.eds`: the statusword after boot-up (0x0260: bits 5, 6 and 9, Switch on
/// disabled, CiA 402) and the controlword 0 in hex with their bits; the TPDO 1 mapping (the
/// statusword, 16 bits, and the mode display 0x6061, 8 bits) decoded; the TPDO 1 COB-ID 0x182
/// (0x180 + node 2), COB-ID SYNC 0x80, COB-ID EMCY 0x82, the identity, the error register and the
/// supported drive modes in hex; the transmission type, the event timer, the heartbeat time and
/// the mode of operation in decimal. A type given on the command line is shown as it says.
#[test]
fn bit_fields_identities_mappings_and_cob_ids_are_shown_in_hex() {
    let (_nodes, bus) = nodes();
    let od = drive_od();
    let read = |argv: &[&str]| {
        let mut all = vec!["read", "2"];
        all.extend_from_slice(argv);
        common::sdo_tool_ok(&["--bus", &bus, "--od", &od], &all)
    };
    assert_eq!(
        read(&["Statusword"]),
        "0x0260  [Quick_stop Switch_on_disabled Remote]\n"
    );
    assert_eq!(read(&["0x6040"]), "0x0000  []\n");
    assert_eq!(
        read(&["0x6041", "u16"]),
        "608  [Quick_stop Switch_on_disabled Remote]\n"
    );
    assert_eq!(
        read(&["0x1A00"]),
        "0x1A00:00  Number of mapped objects = 2\n\
         0x1A00:01  Mapped object 1 = 0x60410010 (0x6041:00, 16 bits)\n\
         0x1A00:02  Mapped object 2 = 0x60610008 (0x6061:00, 8 bits)\n\
         0x1A00:03  Mapped object 3 = 0x00000000\n\
         0x1A00:04  Mapped object 4 = 0x00000000\n\
         0x1A00:05  Mapped object 5 = 0x00000000\n\
         0x1A00:06  Mapped object 6 = 0x00000000\n\
         0x1A00:07  Mapped object 7 = 0x00000000\n\
         0x1A00:08  Mapped object 8 = 0x00000000\n"
    );
    assert_eq!(read(&["0x1A00:01", "u32"]), "1614872592\n");
    assert_eq!(
        read(&["0x1800"]),
        "0x1800:00  Highest sub-index supported = 5\n\
         0x1800:01  COB-ID used by TPDO = 0x00000182\n\
         0x1800:02  Transmission type = 255\n\
         0x1800:03  Inhibit time = 0\n\
         0x1800:04  Reserved = 0\n\
         0x1800:05  Event timer = 10\n"
    );
    assert_eq!(read(&["0x1005"]), "0x00000080\n");
    assert_eq!(read(&["0x1014"]), "0x00000082\n");
    assert_eq!(
        read(&["0x1018"]),
        "0x1018:00  Highest sub-index supported = 4\n\
         0x1018:01  Vendor-ID = 0x00000ABC\n\
         0x1018:02  Product code = 0x00000402\n\
         0x1018:03  Revision number = 0x00010001\n\
         0x1018:04  Serial number = 0x00000001\n"
    );
    assert_eq!(read(&["0x1000"]), "0x00020192\n");
    assert_eq!(read(&["0x1001"]), "0x00\n");
    assert_eq!(read(&["0x6502"]), "0x000003A5\n");
    assert_eq!(read(&["0x1017"]), "0\n");
    assert_eq!(read(&["0x6060"]), "0\n");
    // JSON keeps the number; its text is the line's.
    let v: serde_json::Value = serde_json::from_str(&common::sdo_tool_ok(
        &["--bus", &bus, "--od", &od, "--json"],
        &["read", "2", "0x1A00:01"],
    ))
    .unwrap();
    assert_eq!(v["value"], 0x6041_0010u32);
    assert_eq!(v["text"], "0x60410010 (0x6041:00, 16 bits)");
}

/// The bytes of the 64 KiB DOMAIN the test writes: 7k + 3.
fn domain() -> Vec<u8> {
    (0..65536u32).map(|k| (k * 7 + 3) as u8).collect()
}

/// Its first 32 bytes as the tool shows them.
fn head() -> String {
    domain()[..32]
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// A 64 KiB DOMAIN (0x2000:01 of the I/O device) read with `--od`: its first 32 bytes and
/// `… (65536 bytes)`, one short line; with `--full` the whole (65,536 bytes, 196,607 characters);
/// `--json` carries the whole value. `watch` shows the transfer the same way, its log decoded by
/// `decode` too, and `decode --full` shows it whole.
#[test]
fn a_long_domain_is_shown_as_its_first_bytes_and_its_length() {
    let (_nodes, bus) = nodes();
    let od = io_od();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("program.bin");
    std::fs::write(&file, domain()).unwrap();
    let global = ["--bus", bus.as_str(), "--od", od.as_str()];
    common::sdo_tool_ok(
        &global,
        &["download", "3", "0x2000:01", file.to_str().unwrap()],
    );
    let log = dir.path().join("bus.log");
    let watch = Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(global)
        .args(["watch", "3", "--log", log.to_str().unwrap()])
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    // The watcher is on the bus once its log exists.
    for _ in 0..100 {
        if log.exists() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    std::thread::sleep(std::time::Duration::from_millis(300));
    let short = format!("{} … (65536 bytes)\n", head());
    assert_eq!(
        common::sdo_tool_ok(&global, &["read", "3", "0x2000:01"]),
        short
    );
    let full = common::sdo_tool_ok(&global, &["read", "3", "0x2000:01", "--full"]);
    assert_eq!(full.len(), 65536 * 3);
    assert!(full.starts_with(&head()));
    // The last byte, 7 × 65535 + 3 = 458748 = 0xFC modulo 256.
    assert!(full.ends_with(" FC\n"));
    let json = common::sdo_tool_ok(&global, &["--json", "read", "3", "0x2000:01"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["value"].as_str().unwrap().len(), 65536 * 3 - 1);
    std::thread::sleep(std::time::Duration::from_millis(300));
    let kill = Command::new("kill")
        .args(["-INT", &watch.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let out = watch.wait_with_output().unwrap();
    let out = String::from_utf8_lossy(&out.stdout);
    let line = format!(
        "node 3: SDO read 0x2000:01 (Program 1) = {} … (65536 bytes, block transfer)",
        head()
    );
    let reads: Vec<&str> = out
        .lines()
        .filter(|l| l.contains("SDO read 0x2000:01"))
        .collect();
    assert_eq!(reads.len(), 3, "{out}");
    assert!(reads.iter().all(|l| l.ends_with(&line)), "{out}");
    let decoded = common::sdo_tool_ok(&global, &["decode", log.to_str().unwrap(), "3"]);
    let reads: Vec<&str> = decoded.lines().filter(|l| l.contains("SDO read")).collect();
    assert_eq!(reads.len(), 3, "{decoded}");
    assert!(reads.iter().all(|l| l.ends_with(&line)), "{decoded}");
    let decoded = common::sdo_tool_ok(&global, &["decode", log.to_str().unwrap(), "3", "--full"]);
    let whole = decoded.lines().find(|l| l.contains("SDO read")).unwrap();
    assert!(
        whole.ends_with(" FC (65536 bytes, block transfer)"),
        "{}",
        &whole[whole.len() - 100..]
    );
    assert!(whole.len() > 65536 * 3);
}
