//! The commands of IgH's `ethercat` tool in `sdo-tool --ethercat IFACE`, against `ethercat-node`
//! (crate `ethercat-slave`) on a veth pair: `slaves`, `sii-read`, `sii-write`, `alias`, `reg-read`,
//! `reg-write`, `pdos`, `xml` and `cstruct`. Every expected line is worked out by hand from the
//! example ESIs (`examples/io-device.esi.xml`, `examples/drive.esi.xml`), the SII layout of
//! ETG.1000.6 §5.4 that the emulator's EEPROM holds (its serial numbers are the positions), the
//! ESC registers the emulator documents (0x0000: type 0x11, build 0x0002; 0x0007: ports 0 and 1
//! MII; 0x0008 = 0x000D) and the output formats of IgH's tool.

mod common;

use std::io::Write;
use std::process::{Command, Output, Stdio};

use testkit::link::Link;

/// `sdo-tool --ethercat IFACE ARGS…`.
fn tool(link: &Link, argv: &[&str]) -> Output {
    common::sdo_tool(&["--ethercat", &link.master], argv)
}

/// Runs and expects success: standard output.
fn ok(link: &Link, argv: &[&str]) -> String {
    common::sdo_tool_ok(&["--ethercat", &link.master], argv)
}

/// Runs and expects exit `code` with one line on standard error: that line.
fn refused(link: &Link, argv: &[&str], code: i32) -> String {
    let o = tool(link, argv);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(code), "{argv:?}: {err}");
    assert_eq!(err.lines().count(), 1, "{argv:?}: {err}");
    err
}

/// Runs with `input` on standard input and expects success.
fn ok_with_input(link: &Link, argv: &[&str], input: &[u8]) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(["--ethercat", &link.master])
        .args(argv)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(input).unwrap();
    let o = child.wait_with_output().unwrap();
    assert!(
        o.status.success(),
        "{argv:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The example I/O device's name (its ESI's `Name`), which its SII's General category names.
const IO_NAME: &str = "io-device: 8 digital and 1 analog input, 8 digital and 1 analog output";

/// `slaves`: IgH's one-line layout with the name from the SII and no description given; the
/// alias column from SII word 4; `--verbose`: IgH's block, worked out from the ESI (mailboxes
/// 0x1000/128 and 0x1080/128, CoE with SDO Information and Complete Access, group `io`) and the
/// emulator's ESC (ports 0 and 1 MII, port 1 open where a slave follows, 64-bit DC).
#[test]
fn slaves_in_igh_layout_with_the_sii_name() {
    let link = Link::node(&["--esi", "examples/io-device.esi.xml@2"]);
    assert_eq!(
        ok(&link, &["slaves"]),
        format!("1  0:0  INIT  +  {IO_NAME}\n2  0:1  INIT  +  {IO_NAME}\n")
    );
    let block = |position: u32, port0: &str, port1: &str| {
        format!(
            "=== Slave {position} ===\n\
             State: INIT\n\
             Flag: +\n\
             Identity:\n  \
             Vendor Id:       0x00000abc\n  \
             Product code:    0x00000191\n  \
             Revision number: 0x00010001\n  \
             Serial number:   0x0000000{position}\n\
             DL information:\n  \
             FMMU bit operation: yes\n  \
             Distributed clocks: yes, 64 bit\n\
             Port  Type  Link  Loop    Signal  NextSlave\n\
             {port0}\n{port1}\n   \
             2  N/A   down  closed  no              -\n   \
             3  N/A   down  closed  no              -\n\
             Mailboxes:\n  \
             Bootstrap RX: 0x1000/128, TX: 0x1080/128\n  \
             Standard  RX: 0x1000/128, TX: 0x1080/128\n  \
             Supported protocols: CoE\n\
             General:\n  \
             Group: io\n  \
             Image name: \n  \
             Order number: io-device\n  \
             Device name: {IO_NAME}\n  \
             CoE details:\n    \
             Enable SDO: yes\n    \
             Enable SDO Info: yes\n    \
             Enable PDO Assign: no\n    \
             Enable PDO Configuration: no\n    \
             Enable Upload at startup: no\n    \
             Enable SDO complete access: yes\n  \
             Flags:\n    \
             Enable SafeOp: no\n    \
             Enable notLRW: no\n  \
             Current consumption: 0 mA\n"
        )
    };
    assert_eq!(
        ok(&link, &["slaves", "--verbose"]),
        block(
            1,
            "   0  MII   up    open    yes             -",
            "   1  MII   up    open    yes             2"
        ) + &block(
            2,
            "   0  MII   up    open    yes             1",
            "   1  MII   down  closed  no              -"
        )
    );
    let v: serde_json::Value = serde_json::from_str(&ok(&link, &["--json", "slaves"])).unwrap();
    assert_eq!(
        v["slaves"][1],
        serde_json::json!({"position": 2, "state": "INIT", "al_status": 1, "al_status_code": 0,
            "alias": 0, "name": IO_NAME, "sii_read": true, "vendor": 0xABC, "product": 0x191,
            "revision": 0x10001, "serial": 2, "order": "io-device", "group": "io"})
    );
}

/// The SII of the example I/O device as the emulator's EEPROM holds it (ETG.1000.6 §5.4): words
/// 0–6 its ConfigData (0x0008), the checksum 0x0D; the identity with serial number 1; then the
/// categories: Strings, 23 strings (the order code, the group, the 70-byte name, 18 entry and 2
/// PDO names: 263 bytes, 132 words), General (16 words), FMMU (3 bytes, 2 words), SyncM (4 × 8
/// bytes, 16 words), TxPDO and RxPDO (8 + 9 × 8 bytes, 40 words each), End: 646 bytes.
#[test]
fn sii_read_gives_the_eeprom_byte_for_byte() {
    let link = Link::node(&["--esi", "examples/io-device.esi.xml@2"]);
    let raw = tool(&link, &["sii-read", "1"]);
    assert!(raw.status.success());
    let b = raw.stdout;
    assert_eq!(b.len(), 646);
    assert_eq!(
        &b[..32],
        &[
            0x08, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x0D, 0, 0xBC, 0x0A, 0, 0, 0x91, 0x01, 0,
            0, 0x01, 0, 0x01, 0, 0x01, 0, 0, 0
        ]
    );
    assert_eq!(&b[644..], &[0xFF, 0xFF], "the End category");
    let listing = ok(&link, &["sii-read", "1", "--verbose"]);
    let categories: Vec<&str> = listing
        .lines()
        .filter(|l| l.starts_with("SII Category"))
        .collect();
    assert_eq!(
        categories,
        [
            "SII Category 0x000a (STRINGS), 132 words",
            "SII Category 0x001e (General), 16 words",
            "SII Category 0x0028 (FMMU), 2 words",
            "SII Category 0x0029 (SyncM), 16 words",
            "SII Category 0x0032 (TXPDO), 40 words",
            "SII Category 0x0033 (RXPDO), 40 words",
        ]
    );
    let lines: Vec<&str> = listing.lines().collect();
    assert_eq!(lines[0], "SII Area:");
    assert_eq!(
        lines[1],
        "  08 00 00 00 00 00 00 00 00 00 00 00 00 00 0d 00"
    );
    assert_eq!(
        lines[2],
        "  bc 0a 00 00 91 01 00 00 01 00 01 00 01 00 00 00"
    );
    // The FMMU category: Outputs, Inputs, MBoxState and a pad byte.
    let fmmu = lines.iter().position(|l| l.contains("(FMMU)")).unwrap();
    assert_eq!(lines[fmmu + 1], "  01 02 03 00");
    // The serial number is the position; -o writes the same bytes as standard output.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("two.sii");
    assert_eq!(
        ok(&link, &["sii-read", "2", "-o", file.to_str().unwrap()]),
        ""
    );
    let two = std::fs::read(&file).unwrap();
    assert_eq!(two.len(), 646);
    assert_eq!(&two[0x1C..0x20], &[2, 0, 0, 0]);
    assert_eq!(&two[..0x1C], &b[..0x1C]);
    assert_eq!(&two[0x20..], &b[0x20..]);
    let v: serde_json::Value =
        serde_json::from_str(&ok(&link, &["--json", "sii-read", "2"])).unwrap();
    assert_eq!(v["words"], 323);
    assert!(v["sii"].as_str().unwrap().starts_with("0800000000"));
    // One slave at a time; a position the chain has.
    assert_eq!(
        refused(&link, &["sii-read"], 2),
        format!(
            "sdo-tool: `sii-read` takes one slave: the chain on {} has 2: give POS (1 = first)\n",
            link.master
        )
    );
    assert_eq!(
        refused(&link, &["sii-read", "3"], 2),
        format!(
            "sdo-tool: slave position 3 is not 1 to 2 (the chain on {} has 2 slaves)\n",
            link.master
        )
    );
    // IgH's spelling.
    assert_eq!(tool(&link, &["sii_read", "1"]).stdout, b);
}

/// `reg-read` and `reg-write` by position: the ESC information, AL status, the station address
/// (written and read back, from a value, a file and standard input), an AL control write that the
/// slave refuses with an AL status code, and the refusals of addresses beyond the registers, sizes
/// of 0 and positions beyond the chain.
#[test]
fn registers_read_and_written_as_igh_does() {
    let link = Link::node(&["--esi", "examples/io-device.esi.xml@2"]);
    // ESC type 0x11, revision 0, build 0x0002.
    assert_eq!(
        ok(&link, &["reg-read", "1", "0x0000", "4"]),
        "0x11 0x00 0x02 0x00\n"
    );
    assert_eq!(
        ok(&link, &["reg-read", "1", "0", "1", "-t", "uint8"]),
        "0x11 17\n"
    );
    // AL status: Init.
    assert_eq!(
        ok(&link, &["reg-read", "2", "0x0130", "--type", "uint16"]),
        "0x0001 1\n"
    );
    // The station address: none yet; written as a value, from a file, from standard input.
    assert_eq!(
        ok(&link, &["reg-read", "2", "0x0010", "-t", "uint16"]),
        "0x0000 0\n"
    );
    assert_eq!(
        ok(
            &link,
            &["reg-write", "2", "0x0010", "-t", "uint16", "0x1234"]
        ),
        ""
    );
    assert_eq!(
        ok(&link, &["reg-read", "2", "0x0010", "-t", "uint16"]),
        "0x1234 4660\n"
    );
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("station.bin");
    std::fs::write(&file, [0x78, 0x56]).unwrap();
    ok(&link, &["reg-write", "1", "0x10", file.to_str().unwrap()]);
    assert_eq!(
        ok(&link, &["reg-read", "1", "0x0010", "-t", "int16"]),
        "0x5678 22136\n"
    );
    ok_with_input(&link, &["reg-write", "1", "020", "-"], &[0xFE, 0xFF]);
    assert_eq!(
        ok(&link, &["reg-read", "1", "0x0010", "-t", "int16"]),
        "0xfffe -2\n"
    );
    assert_eq!(ok(&link, &["reg-read", "2", "0x0010", "2"]), "0x34 0x12\n");
    let v: serde_json::Value = serde_json::from_str(&ok(
        &link,
        &["--json", "reg-read", "2", "0x0010", "-t", "uint16"],
    ))
    .unwrap();
    assert_eq!(
        v,
        serde_json::json!({"position": 2, "address": 16, "size": 2, "data": "3412", "value": 4660})
    );
    // Pre-Op asked of slave 1 with no mailbox configured: refused with the error flag and AL status
    // code 0x0016 (invalid mailbox configuration); the error acknowledged with Init: Init again.
    ok(&link, &["reg_write", "1", "0x0120", "-t", "uint16", "2"]);
    assert_eq!(
        ok(&link, &["reg-read", "1", "0x0130", "6"]),
        "0x11 0x00 0x00 0x00 0x16 0x00\n"
    );
    assert_eq!(
        ok(&link, &["states"]),
        "  1  INIT+ERROR  AL status code 0x0016\n  2  INIT        AL status code 0x0000\n"
    );
    ok(&link, &["reg-write", "1", "0x0120", "-t", "uint16", "0x11"]);
    assert_eq!(
        ok(&link, &["reg-read", "1", "0x0130", "-t", "uint16"]),
        "0x0001 1\n"
    );
    // Refused before anything is sent: exit 2, one line.
    for (argv, line) in [
        (
            &["reg-read", "1", "0x1000", "2"][..],
            "address 0x1000 is not a register (0x0000 to 0x0FFF; the process memory above \
             belongs to the SyncManagers)",
        ),
        (
            &["reg-read", "1", "0x0FFF", "2"],
            "0x0FFF + 2 bytes runs past the registers' end at 0x0FFF",
        ),
        (
            &["reg-read", "1", "0x0FFE", "-t", "uint32"],
            "0x0FFE + 4 bytes runs past the registers' end at 0x0FFF",
        ),
        (
            &["reg-read", "1", "0x0130", "0"],
            "a read of 0 bytes: give 1 or more",
        ),
        (
            &["reg-read", "1", "0x0130"],
            "give SIZE: raw has no size of its own",
        ),
        (
            &["reg-read", "1", "0x0130", "2", "-t", "float"],
            "type \"float\" is not int8, int16, int32, int64, uint8, uint16, uint32, uint64, \
             string or raw",
        ),
        (
            &["reg-read", "1", "0x13x", "2"],
            "address \"0x13x\" is not a number (decimal, 0x… hex or 0… octal)",
        ),
        (
            &["reg-write", "1", "0x0010", "-t", "uint8", "256"],
            "\"256\" is no uint8 value",
        ),
        (
            &["reg-write", "1", "0x0010", "-t", "raw", "1"],
            "type \"raw\" is not int8, int16, int32, int64, uint8, uint16, uint32, uint64, \
             string or raw (raw is for reads)",
        ),
        (
            &["reg-write", "1", "0x0FFF", "-t", "uint16", "1"],
            "0x0FFF + 2 bytes runs past the registers' end at 0x0FFF",
        ),
        (
            &["reg-write", "1", "0x0010", "-t", "string", ""],
            "a write of 0 bytes: give 1 or more",
        ),
    ] {
        assert_eq!(
            refused(&link, argv, 2),
            format!("sdo-tool: {line}\n"),
            "{argv:?}"
        );
    }
    assert_eq!(
        refused(&link, &["reg-read", "3", "0x0130", "2"], 2),
        format!(
            "sdo-tool: slave position 3 is not 1 to 2 (the chain on {} has 2 slaves)\n",
            link.master
        )
    );
    assert_eq!(
        ok(&link, &["reg-read", "2", "0x0010", "-t", "uint16"]),
        "0x1234 4660\n",
        "nothing refused was written"
    );
    // The words are checked before any interface is opened.
    let o = common::sdo_tool(
        &["--ethercat", "nosuchif0"],
        &["reg-read", "1", "0x0FFF", "2"],
    );
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        "sdo-tool: 0x0FFF + 2 bytes runs past the registers' end at 0x0FFF\n"
    );
}

/// The CRC-8 (polynomial 0x07, initial 0xFF) of 08 00 00 00 00 00 00 00 34 12 00 00 00 00: words
/// 0–6 of the example I/O device with alias 0x1234 (worked out bit by bit).
const CRC_ALIAS_1234: u8 = 0xFA;
/// The same with alias 0x0777.
const CRC_ALIAS_0777: u8 = 0x28;

/// The SII round trip: the image read into a file, its alias changed in word 4 with the checksum
/// made again, written back, read back byte for byte; the ESC takes the alias into 0x0012 at a
/// reload (the EEPROM command 4 written into 0x0502 with `reg-write`). `alias` does the same in one
/// command. IgH's checks refuse a bad checksum, a short image and an odd length; nothing is written
/// then; an image larger than the EEPROM is refused even with `--force`.
#[test]
fn sii_round_trip_alias_and_refusals() {
    let link = Link::node(&["--esi", "examples/io-device.esi.xml@2"]);
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let original = path("one.sii");
    ok(&link, &["sii-read", "1", "-o", &original]);
    let before = std::fs::read(&original).unwrap();
    let mut changed = before.clone();
    changed[8..10].copy_from_slice(&[0x34, 0x12]);
    changed[14] = CRC_ALIAS_1234;
    let file = path("alias.sii");
    std::fs::write(&file, &changed).unwrap();
    assert_eq!(ok(&link, &["sii-write", "1", &file]), "");
    assert_eq!(tool(&link, &["sii-read", "1"]).stdout, changed);
    assert_eq!(
        ok(&link, &["reg-read", "1", "0x0012", "-t", "uint16"]),
        "0x0000 0\n",
        "the ESC takes the alias at a reload"
    );
    ok(
        &link,
        &["reg-write", "1", "0x0502", "-t", "uint16", "0x0400"],
    );
    assert_eq!(
        ok(&link, &["reg-read", "1", "0x0012", "-t", "uint16"]),
        "0x1234 4660\n"
    );
    assert_eq!(
        ok(&link, &["slaves"]),
        format!("1  4660:0  INIT  +  {IO_NAME}\n2  4660:1  INIT  +  {IO_NAME}\n")
    );

    // Refused by IgH's checks, and nothing written.
    let mut bad = changed.clone();
    bad[14] ^= 0x01;
    let bad_file = path("bad.sii");
    std::fs::write(&bad_file, &bad).unwrap();
    assert_eq!(
        refused(&link, &["sii-write", "1", &bad_file], 2),
        format!(
            "sdo-tool: {bad_file}: the checksum of words 0–6 is 0x{CRC_ALIAS_1234:02X}, byte 14 \
             holds 0x{:02X}; --force writes it anyway\n",
            CRC_ALIAS_1234 ^ 1
        )
    );
    let short = path("short.sii");
    std::fs::write(&short, &changed[..128]).unwrap();
    assert_eq!(
        refused(&link, &["sii-write", "1", &short], 2),
        format!(
            "sdo-tool: {short}: 64 words: an SII image has at least 65 (64 header words and the \
             End category); --force writes it anyway\n"
        )
    );
    let odd = path("odd.sii");
    std::fs::write(&odd, &changed[..201]).unwrap();
    assert_eq!(
        refused(&link, &["sii-write", "1", &odd, "--force"], 2),
        format!(
            "sdo-tool: {odd}: 201 bytes: an SII image is a positive whole number of 16-bit \
             words; --force writes it anyway\n"
        )
    );
    // The EEPROM holds 2048 bytes (SII word 0x3E = 15: 16 Kibit).
    let large = path("large.sii");
    let mut big = changed.clone();
    big.resize(2050, 0xFF);
    std::fs::write(&large, &big).unwrap();
    assert_eq!(
        refused(&link, &["sii-write", "1", &large, "--force"], 2),
        format!(
            "sdo-tool: {large}: 2050 bytes do not fit the EEPROM of slave 1, 2048 bytes (SII \
             word 0x3E)\n"
        )
    );
    // More than any EEPROM (4 Mbit): refused before a chain is looked at, not read on.
    let huge = path("huge.sii");
    std::fs::write(&huge, vec![0u8; 512 * 1024 + 2]).unwrap();
    assert_eq!(
        refused(&link, &["sii-write", "1", &huge, "--force"], 2),
        format!(
            "sdo-tool: {huge}: more than 524288 bytes: no SII image (an ESC's EEPROM holds 4 \
             Mbit at most)\n"
        )
    );
    assert_eq!(
        refused(&link, &["sii-write", &file], 2),
        format!(
            "sdo-tool: `sii-write` takes one slave: the chain on {} has 2: give POS (1 = first)\n",
            link.master
        )
    );
    assert_eq!(
        refused(&link, &["sii-write", "3", &file], 2),
        format!(
            "sdo-tool: slave position 3 is not 1 to 2 (the chain on {} has 2 slaves)\n",
            link.master
        )
    );
    assert_eq!(
        tool(&link, &["sii-read", "1"]).stdout,
        changed,
        "nothing refused was written"
    );
    // --force writes what the checks refuse; the original goes back in through standard input.
    ok(&link, &["sii_write", "1", &bad_file, "--force"]);
    assert_eq!(tool(&link, &["sii-read", "1"]).stdout, bad);
    ok_with_input(&link, &["sii-write", "1", "-"], &before);
    assert_eq!(tool(&link, &["sii-read", "1"]).stdout, before);

    // `alias`: word 4 and the checksum written, the reload done, 0x0012 holds it.
    assert_eq!(ok(&link, &["alias", "2", "0x0777"]), "");
    let two = tool(&link, &["sii-read", "2"]).stdout;
    assert_eq!(&two[8..10], &[0x77, 0x07]);
    assert_eq!(two[14], CRC_ALIAS_0777);
    assert_eq!(
        ok(&link, &["reg-read", "2", "0x0012", "-t", "uint16"]),
        "0x0777 1911\n"
    );
    // Slave 1 has its original image (alias 0) again.
    assert_eq!(
        ok(&link, &["slaves"]),
        format!("1     0:0  INIT  +  {IO_NAME}\n2  1911:0  INIT  +  {IO_NAME}\n")
    );
    assert_eq!(
        refused(&link, &["alias", "5"], 2),
        "sdo-tool: this writes alias 5 into the SII of all 2 slaves: give --force (or POS for \
         one)\n"
    );
    assert_eq!(
        refused(&link, &["alias", "1", "65536"], 2),
        "sdo-tool: alias \"65536\" is not 0 to 65535\n"
    );
    assert_eq!(ok(&link, &["alias", "0", "--force"]), "");
    for p in ["1", "2"] {
        assert_eq!(
            ok(&link, &["reg-read", p, "0x0012", "-t", "uint16"]),
            "0x0000 0\n"
        );
    }
    let v: serde_json::Value =
        serde_json::from_str(&ok(&link, &["--json", "alias", "1", "5"])).unwrap();
    assert_eq!(
        v,
        serde_json::json!({"position": 1, "alias": 5, "register": 5})
    );
}

fn io_pdos() -> String {
    let mut s = String::from(concat!(
        "SM0: PhysAddr 0x1000, DefaultSize  128, ControlRegister 0x26, Enable 1\n",
        "SM1: PhysAddr 0x1080, DefaultSize  128, ControlRegister 0x22, Enable 1\n",
        "SM2: PhysAddr 0x1100, DefaultSize    3, ControlRegister 0x64, Enable 1\n",
        "  RxPDO 0x1600 \"Outputs\"\n",
    ));
    for k in 1..=8 {
        s.push_str(&format!(
            "    PDO entry 0x7000:0{k},  1 bit, \"Output {k}\"\n"
        ));
    }
    s.push_str(concat!(
        "    PDO entry 0x7010:01, 16 bit, \"Analog output\"\n",
        "SM3: PhysAddr 0x1180, DefaultSize    3, ControlRegister 0x20, Enable 1\n",
        "  TxPDO 0x1a00 \"Inputs\"\n",
    ));
    for k in 1..=8 {
        s.push_str(&format!(
            "    PDO entry 0x6000:0{k},  1 bit, \"Input {k}\"\n"
        ));
    }
    s.push_str("    PDO entry 0x6010:01, 16 bit, \"Analog input\"\n");
    s
}

/// The example I/O device and the example drive on one chain.
fn io_and_drive() -> Link {
    Link::node(&[
        "--esi",
        "examples/io-device.esi.xml",
        "--esi",
        "examples/drive.esi.xml",
    ])
}

/// RxPDO 0x1601 (csv) assigned to the drive's SM2 by CoE: 0x1C12 written in Pre-Op, where the
/// assignment is writable.
fn assign_csv(link: &Link) {
    for (sub, t, v) in [
        ("00", "u8", "0"),
        ("01", "u16", "0x1601"),
        ("00", "u8", "1"),
    ] {
        ok(link, &["write", "2", &format!("0x1C12:{sub}"), t, v]);
    }
}

/// `pdos` and `cstruct` of the example I/O device and the example drive, from their ESIs: the
/// drive's SII assigns RxPDO 0x1600 (csp) to SM2 and TxPDO 0x1A00 to SM3; once 0x1C12 assigns 0x1601
/// (csv) by CoE, `pdos` shows that.
#[test]
fn pdos_and_cstruct_from_sii_and_coe() {
    let link = io_and_drive();
    assert_eq!(ok(&link, &["pdos", "1"]), io_pdos());
    let drive = |rx: &str| {
        format!(
            "SM0: PhysAddr 0x1000, DefaultSize  128, ControlRegister 0x26, Enable 1\n\
             SM1: PhysAddr 0x1100, DefaultSize  128, ControlRegister 0x22, Enable 1\n\
             SM2: PhysAddr 0x1200, DefaultSize    0, ControlRegister 0x64, Enable 1\n\
             {rx}\
             SM3: PhysAddr 0x1300, DefaultSize    0, ControlRegister 0x20, Enable 1\n  \
             TxPDO 0x1a00 \"TxPDO\"\n    \
             PDO entry 0x6041:00, 16 bit, \"Statusword\"\n    \
             PDO entry 0x6064:00, 32 bit, \"Position actual value\"\n    \
             PDO entry 0x606c:00, 32 bit, \"Velocity actual value\"\n    \
             PDO entry 0x60f4:00, 32 bit, \"Following error actual value\"\n    \
             PDO entry 0x6061:00,  8 bit, \"Modes of operation display\"\n"
        )
    };
    let csp = "  RxPDO 0x1600 \"RxPDO csp\"\n    \
               PDO entry 0x6040:00, 16 bit, \"Controlword\"\n    \
               PDO entry 0x607a:00, 32 bit, \"Target position\"\n    \
               PDO entry 0x6060:00,  8 bit, \"Modes of operation\"\n";
    assert_eq!(ok(&link, &["pdos", "2"]), drive(csp));
    assert_eq!(
        ok(&link, &["pdos"]),
        format!(
            "=== Slave 1 ===\n{}=== Slave 2 ===\n{}",
            io_pdos(),
            drive(csp)
        )
    );
    assign_csv(&link);
    let csv = "  RxPDO 0x1601 \"RxPDO csv\"\n    \
               PDO entry 0x6040:00, 16 bit, \"Controlword\"\n    \
               PDO entry 0x60ff:00, 32 bit, \"Target velocity\"\n    \
               PDO entry 0x6060:00,  8 bit, \"Modes of operation\"\n";
    assert_eq!(ok(&link, &["pdos", "2"]), drive(csv));

    // cstruct of the I/O device.
    let mut entries = String::new();
    for k in 1..=8 {
        entries.push_str(&format!("    {{0x7000, 0x0{k}, 1}}, /* Output {k} */\n"));
    }
    entries.push_str("    {0x7010, 0x01, 16}, /* Analog output */\n");
    for k in 1..=8 {
        entries.push_str(&format!("    {{0x6000, 0x0{k}, 1}}, /* Input {k} */\n"));
    }
    entries.push_str("    {0x6010, 0x01, 16}, /* Analog input */\n");
    assert_eq!(
        ok(&link, &["cstruct", "1"]),
        format!(
            "/* Master 0, Slave 1, \"io-device\"\n \
             * Vendor ID:       0x00000abc\n \
             * Product code:    0x00000191\n \
             * Revision number: 0x00010001\n \
             */\n\n\
             ec_pdo_entry_info_t slave_1_pdo_entries[] = {{\n{entries}}};\n\n\
             ec_pdo_info_t slave_1_pdos[] = {{\n    \
             {{0x1600, 9, slave_1_pdo_entries + 0}}, /* Outputs */\n    \
             {{0x1a00, 9, slave_1_pdo_entries + 9}}, /* Inputs */\n\
             }};\n\n\
             ec_sync_info_t slave_1_syncs[] = {{\n    \
             {{0, EC_DIR_OUTPUT, 0, NULL, EC_WD_DISABLE}},\n    \
             {{1, EC_DIR_INPUT, 0, NULL, EC_WD_DISABLE}},\n    \
             {{2, EC_DIR_OUTPUT, 1, slave_1_pdos + 0, EC_WD_ENABLE}},\n    \
             {{3, EC_DIR_INPUT, 1, slave_1_pdos + 1, EC_WD_DISABLE}},\n    \
             {{0xff}}\n\
             }};\n\n"
        )
    );
}

/// `xml` of the chain: the two slaves as an EtherCATInfoList in IgH's layout, with the PDO the drive
/// has by CoE; it reads back with `esi-gen check` (no finding) and the ESI reader: the identities,
/// names and PDOs as the slaves report them.
#[test]
fn xml_of_the_chain_reads_back_as_an_esi() {
    let link = io_and_drive();
    assign_csv(&link);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("bus.xml");
    let xml = ok(&link, &["xml"]);
    assert!(xml.starts_with("<?xml version=\"1.0\" ?>\n<EtherCATInfoList>\n  <EtherCATInfo>\n"));
    // In the list each EtherCATInfo is two spaces further in.
    assert!(xml.contains(concat!(
        "    <!-- Slave 2 -->\n",
        "    <Vendor>\n",
        "      <Id>2748</Id>\n",
        "    </Vendor>\n",
        "    <Descriptions>\n",
        "      <Devices>\n",
        "        <Device>\n",
        "          <Type ProductCode=\"#x00000402\" RevisionNo=\"#x00010001\">drive</Type>\n",
        "          <Name><![CDATA[drive: a CiA 402 servo drive (EtherCAT)]]></Name>\n",
        "          <Sm Enable=\"1\" StartAddress=\"#x1000\" ControlByte=\"#x26\" DefaultSize=\"128\" />\n",
    )));
    assert!(xml.contains(concat!(
        "          <RxPdo Sm=\"2\" Fixed=\"1\" Mandatory=\"1\">\n",
        "            <Index>#x1601</Index>\n",
        "            <Name>RxPDO csv</Name>\n",
        "            <Entry>\n",
        "              <Index>#x6040</Index>\n",
        "              <SubIndex>0</SubIndex>\n",
        "              <BitLen>16</BitLen>\n",
        "              <Name>Controlword</Name>\n",
        "              <DataType>UINT16</DataType>\n",
        "            </Entry>\n",
    )));
    std::fs::write(&file, &xml).unwrap();
    let check = Command::new(testkit::cargo_binary("esi-gen", "esi-gen", &[]))
        .arg("check")
        .arg(&file)
        .output()
        .unwrap();
    let report = String::from_utf8_lossy(&check.stdout);
    assert!(check.status.success(), "{report}");
    assert!(
        report.contains("findings: 0 error(s), 0 warning(s)"),
        "{report}"
    );
    let (_, devices) = od::load::load(&file).unwrap();
    let ids: Vec<(u32, u32, u32, &str)> = devices
        .iter()
        .map(|d| {
            let i = &d.identity;
            (
                i.vendor_id,
                i.product_code,
                i.revision,
                i.order_code.as_str(),
            )
        })
        .collect();
    assert_eq!(
        ids,
        [
            (0xABC, 0x191, 0x10001, "io-device"),
            (0xABC, 0x402, 0x10001, "drive")
        ]
    );
    let pdo = |d: &od::DeviceDescription, rx: bool| {
        let ec = d.ethercat.as_ref().unwrap();
        let p = if rx { &ec.rx_pdos } else { &ec.tx_pdos };
        assert_eq!(p.len(), 1);
        let entries: Vec<(u16, u8, u16, String)> = p[0]
            .entries
            .iter()
            .map(|e| (e.index, e.sub, e.bit_len, e.name.clone()))
            .collect();
        (p[0].index, p[0].name.clone(), p[0].sm, entries)
    };
    let (index, name, sm, entries) = pdo(&devices[1], true);
    assert_eq!((index, name.as_str(), sm), (0x1601, "RxPDO csv", Some(2)));
    assert_eq!(
        entries,
        [
            (0x6040, 0, 16, "Controlword".to_string()),
            (0x60FF, 0, 32, "Target velocity".to_string()),
            (0x6060, 0, 8, "Modes of operation".to_string())
        ]
    );
    let (index, name, sm, entries) = pdo(&devices[0], false);
    assert_eq!((index, name.as_str(), sm), (0x1A00, "Inputs", Some(3)));
    assert_eq!(entries.len(), 9);
    assert_eq!(entries[8], (0x6010, 1, 16, "Analog input".to_string()));
    assert_eq!(devices[0].identity.product_name, IO_NAME);
    // One slave: an EtherCATInfo; with --json the same text in one object.
    let one = ok(&link, &["xml", "1"]);
    assert!(one.starts_with("<?xml version=\"1.0\" ?>\n<EtherCATInfo>\n"));
    let v: serde_json::Value = serde_json::from_str(&ok(&link, &["--json", "xml", "1"])).unwrap();
    assert_eq!(v["xml"], one.as_str());
}
