//! `sdo-tool --ethercat IFACE` against two virtual SMD23K-B (`smd-ethercat` of crate
//! `ethercat-slave`, built by the test) on a veth pair: NODE is the slave's position in the chain.
//! read, write (expedited, and a normal download), the aborts with their code and meaning, dump into
//! a DCF, apply of a DCF with read-back, and the usage errors of what EtherCAT does not do.

mod common;

use std::path::Path;
use std::process::Output;

use testkit::link::Link;

fn esi() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures/smd/SMD23K-B_SMD24K.esi.xml")
        .display()
        .to_string()
}

/// `sdo-tool --ethercat IFACE ARGS…`.
fn tool(link: &Link, argv: &[&str]) -> Output {
    common::sdo_tool(&["--ethercat", &link.master], argv)
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs and expects success: standard output.
fn ok(link: &Link, argv: &[&str]) -> String {
    common::sdo_tool_ok(&["--ethercat", &link.master], argv)
}

#[test]
fn read_and_write_by_position() {
    let link = Link::up(&["--units", "2"]);
    let t0 = std::time::Instant::now();
    // A VISIBLE_STRING of 8 bytes (a normal upload: more than an expedited one holds).
    assert_eq!(ok(&link, &["read", "1", "0x1008", "vs"]), "\"SMD23K-B\"\n");
    eprintln!(
        "one sdo-tool run (init to Pre-Op + one read): {:?}",
        t0.elapsed()
    );
    assert_eq!(ok(&link, &["read", "2", "0x1018:04", "u32"]), "2\n");
    assert_eq!(ok(&link, &["read", "1", "0x1018:04", "u32"]), "1\n");
    assert_eq!(
        ok(&link, &["read", "1", "0x1018:01", "x32"]),
        "0x00000AC1\n"
    );
    // Starting_Speed (0x8010:03, UDINT rw, 1 to 1,999,999 steps/s): written on unit 1 only.
    assert_eq!(ok(&link, &["read", "1", "0x8010:03", "u32"]), "141\n");
    assert_eq!(
        ok(&link, &["write", "1", "0x8010:03", "u32", "500"]),
        "OK\n"
    );
    assert_eq!(ok(&link, &["read", "1", "0x8010:03", "u32"]), "500\n");
    assert_eq!(ok(&link, &["read", "2", "0x8010:03", "u32"]), "141\n");
    // Names and types from the ESI.
    let od = esi();
    assert_eq!(
        ok(&link, &["--od", &od, "write", "2", "Starting_Speed", "750"]),
        "OK\n"
    );
    assert_eq!(ok(&link, &["--od", &od, "read", "2", "0x8010:03"]), "750\n");
    let o = tool(&link, &["--json", "read", "2", "0x1018:02", "x32"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["value"], 0x2301);
    assert_eq!(v["text"], "0x00002301");
    assert_eq!(v["object"], "0x1018:02");

    // Refused by the slave: exit 1 with the abort code and its meaning, as over CAN.
    let o = tool(&link, &["write", "1", "0x1018:04", "u32", "7"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(
        stderr(&o),
        "sdo-tool: 0x1018:04: SDO abort 0x06010002 (Attempt to write a read only object)\n"
    );
    let o = tool(&link, &["write", "1", "0x8010:03", "u16", "7"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(
        stderr(&o),
        "sdo-tool: 0x8010:03: SDO abort 0x06070013 (Data type does not match, length of service \
         parameter too low)\n"
    );
    // More than four bytes: a normal download, refused for its length, or as read-only.
    let o = tool(
        &link,
        &["write", "1", "0x8010:03", "os", "01 02 03 04 05 06"],
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("SDO abort 0x06070012"),
        "{}",
        stderr(&o)
    );
    // The largest normal download fits the 128-byte mailbox exactly (6 + 2 + 8 + 112 bytes): sent,
    // and refused by the slave as read-only; one byte more is not sent.
    let fill = |n: usize| vec!["41"; n].join(" ");
    let o = tool(&link, &["write", "1", "0x1008", "os", &fill(112)]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("SDO abort 0x06010002"),
        "{}",
        stderr(&o)
    );
    let o = tool(&link, &["write", "1", "0x1008", "os", &fill(113)]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert_eq!(
        stderr(&o),
        "sdo-tool: EtherCAT: 0x1008:00 of slave 1: 113 bytes do not fit the slave's 128-byte \
         mailbox (segmented download is not supported over EtherCAT)\n"
    );
    let o = tool(&link, &["write", "1", "0x1008", "vs", "A longer name"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("SDO abort 0x06010002"),
        "{}",
        stderr(&o)
    );
    let o = tool(&link, &["read", "1", "0x2345:00", "u8"]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stderr(&o),
        "sdo-tool: 0x2345:00: SDO abort 0x06020000 (Object does not exist in the object dictionary)\n"
    );
    let o = tool(&link, &["--json", "read", "1", "0x2345:00", "u8"]);
    assert_eq!(o.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["abort"], "0x06020000");
    assert_eq!(
        ok(&link, &["read", "1", "0x8010:03", "u32"]),
        "500\n",
        "nothing refused was stored"
    );
}

#[test]
fn usage_and_transport_errors() {
    let link = Link::up(&["--units", "2"]);
    // NODE is a position in the chain of 2.
    let o = tool(&link, &["read", "3", "0x1000", "u32"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("slave position 3 is not 1 to 2"),
        "{}",
        stderr(&o)
    );
    let o = tool(&link, &["read", "0", "0x1000", "u32"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    // CANopen-only commands.
    for argv in [
        &["nmt", "start", "1"][..],
        &["scan"],
        &["watch", "--duration-ms", "10"],
        &["save", "1"],
        &["upload", "1", "0x1008", "/dev/null"],
        &["gateway"],
    ] {
        let o = tool(&link, argv);
        assert_eq!(o.status.code(), Some(2), "{argv:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains(&format!(
                "`{}` is a CANopen command: over EtherCAT (--ethercat) only read, write, dump, \
                 apply, drive, slaves, states, sdos, pdos, sii-read, sii-write, reg-read, \
                 reg-write, alias, xml, cstruct, foe-read and foe-write are available\n",
                argv[0]
            )),
            "{}",
            stderr(&o)
        );
    }
    // --bus and --ethercat exclude each other when both are given; a bus of the environment
    // (CANOPEN_BUS, even one that names no bus) gives way to --ethercat.
    let o = tool(
        &link,
        &["--bus", "socketcan:vcan0", "read", "1", "0x1000", "u32"],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).starts_with(
            "error: the argument '--ethercat <IFACE>' cannot be used with '--bus <BUS>'\n"
        ),
        "{}",
        stderr(&o)
    );
    for bus in ["socketcand://127.0.0.1:1/can0", "vcan0", "no bus at all"] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
            .env("CANOPEN_BUS", bus)
            .args(["--ethercat", &link.master, "read", "1", "0x1018:04", "u32"])
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0), "{bus}: {}", stderr(&o));
        assert_eq!(stdout(&o), "1\n");
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
            .env("CANOPEN_BUS", bus)
            .args(["states", "--ethercat", &link.master])
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0), "{bus}: {}", stderr(&o));
        assert_eq!(
            stdout(&o),
            "  1  INIT        AL status code 0x0000\n  2  INIT        AL status code 0x0000\n"
        );
    }
    // No type and no description: the type is the slave's (SDO Information), UNSIGNED32; the
    // device type shown in hex.
    assert_eq!(ok(&link, &["read", "1", "0x1000"]), "0x00000000\n");
    // No such interface: said so (as root too), a transport failure.
    for argv in [
        &["read", "1", "0x1000", "u32"][..],
        &["slaves"],
        &["states"],
        &["sii-read", "1"],
        &["reg-read", "1", "0x0130", "2"],
        &["pdos"],
        &["foe-read", "f.bin"],
    ] {
        let o = common::sdo_tool(&["--ethercat", "nosuchif0"], argv);
        assert_eq!(o.status.code(), Some(3), "{argv:?}: {}", stderr(&o));
        assert_eq!(
            stderr(&o),
            "sdo-tool: EtherCAT: no such network interface: nosuchif0\n",
            "{argv:?}"
        );
    }
    // The help says what NODE is over EtherCAT.
    let o = common::sdo_tool(&[], &["read", "--help"]);
    assert!(
        stdout(&o).contains("with --ethercat: the slave's position, 1 = first"),
        "{}",
        stdout(&o)
    );
}

/// The DCF round trip over EtherCAT: unit 2's parameters (0x8010, the only writable entries of the
/// ESI) dumped, one edited, applied to unit 1 and read back; the identity, the inputs (0x6000) and the
/// cyclic outputs (0x7000, RxPDO-mapped) are not in the file, so nothing is refused. Then a DCF made
/// from the ESI with three values.
#[test]
fn dump_edit_apply_round_trips_on_ethercat() {
    let link = Link::up(&["--units", "2"]);
    let dir = tempfile::tempdir().unwrap();
    let od = esi();
    ok(&link, &["write", "2", "0x8010:06", "u16", "40"]);
    let dcf = dir.path().join("unit2.dcf");
    let out = ok(
        &link,
        &["--od", &od, "dump", "2", "-o", dcf.to_str().unwrap()],
    );
    assert_eq!(
        out,
        format!(
            "7 entries written to {}; left out: 53 not writable\n",
            dcf.display()
        )
    );
    let (_, mut devices) = od::load::load(&dcf).unwrap();
    let d = &mut devices[0].dictionary;
    assert_eq!(
        d.entry(0x8010, 6).unwrap().value,
        40u16.to_le_bytes(),
        "the unit's value, not the default"
    );
    assert_eq!(d.entry(0x8010, 3).unwrap().value, 141u32.to_le_bytes());
    for (index, sub) in [(0x1008u16, 0u8), (0x1018, 4), (0x6000, 1), (0x7000, 1)] {
        assert!(
            !d.entry(index, sub).unwrap().value_set,
            "0x{index:04X}:{sub:02X} not in the DCF"
        );
    }
    d.store_parameter(0x8010, 3, &2_000u32.to_le_bytes())
        .unwrap();
    std::fs::write(&dcf, od::eds::write_dcf(&devices[0])).unwrap();
    let out = ok(&link, &["apply", "1", dcf.to_str().unwrap()]);
    assert_eq!(
        out.lines().collect::<Vec<_>>(),
        [
            "wrote 0x8010:01 = 0",
            "wrote 0x8010:02 = 3",
            "wrote 0x8010:03 = 2000",
            "wrote 0x8010:04 = 2000",
            "wrote 0x8010:05 = 2048",
            "wrote 0x8010:06 = 40",
            "wrote 0x8010:07 = 10",
            "7 entries written, 0 skipped, 0 refused",
        ]
    );
    assert_eq!(ok(&link, &["read", "1", "0x8010:03", "u32"]), "2000\n");
    assert_eq!(ok(&link, &["read", "1", "0x8010:06", "u16"]), "40\n");
    assert_eq!(
        ok(&link, &["read", "2", "0x8010:03", "u32"]),
        "141\n",
        "unit 2 untouched"
    );

    // A DCF that sets three configuration values: applied to unit 2, each read back.
    let (_, mut devices) = od::load::load(Path::new(&od)).unwrap();
    let d = &mut devices[0];
    for (sub, bytes) in [
        (3u8, 3_000u32.to_le_bytes().to_vec()),
        (4, 400u16.to_le_bytes().to_vec()),
        (7, 20u16.to_le_bytes().to_vec()),
    ] {
        d.dictionary.store_parameter(0x8010, sub, &bytes).unwrap();
    }
    let file = dir.path().join("config.dcf");
    std::fs::write(&file, od::eds::write_dcf(d)).unwrap();
    let out = ok(&link, &["apply", "2", file.to_str().unwrap(), "--dry-run"]);
    assert!(
        out.ends_with("3 entries to write, 0 skipped, 0 refused\n"),
        "{out}"
    );
    assert_eq!(
        ok(&link, &["read", "2", "0x8010:03", "u32"]),
        "141\n",
        "dry run"
    );
    let out = ok(&link, &["apply", "2", file.to_str().unwrap()]);
    assert_eq!(
        out,
        "wrote 0x8010:03 = 3000\nwrote 0x8010:04 = 400\nwrote 0x8010:07 = 20\n\
         3 entries written, 0 skipped, 0 refused\n"
    );
    assert_eq!(ok(&link, &["read", "2", "0x8010:03", "u32"]), "3000\n");
    assert_eq!(ok(&link, &["read", "2", "0x8010:04", "u16"]), "400\n");
    assert_eq!(ok(&link, &["read", "2", "0x8010:07", "u16"]), "20\n");
}

/// `slaves`: in IgH's layout, positions from 1, alias 0, the AL state and the device name of the
/// SII (the ESI's `Name` of the SMD23K-B), with or without a description; read only, so the units
/// stay in Init; the SII identity (AMCI 0x0AC1, SMD23K-B 0x2301, revision 1, serial numbers 1 and
/// 2) in JSON. Without --ethercat a usage error.
#[test]
fn slaves_lists_the_chain_read_only() {
    let link = Link::up(&["--units", "2"]);
    let od = esi();
    let listing = concat!(
        "1  0:0  INIT  +  SMD23K-B Integrated Stepper Indexer/Driver/Motor (EtherCAT)\n",
        "2  0:1  INIT  +  SMD23K-B Integrated Stepper Indexer/Driver/Motor (EtherCAT)\n"
    );
    assert_eq!(ok(&link, &["--od", &od, "slaves"]), listing);
    assert_eq!(ok(&link, &["slaves"]), listing);
    let v: serde_json::Value = serde_json::from_str(&ok(&link, &["--json", "slaves"])).unwrap();
    assert_eq!(v["slaves"][1]["serial"], 2);
    assert_eq!(v["slaves"][1]["vendor"], 0x0AC1);
    assert_eq!(v["slaves"][1]["product"], 0x2301);
    assert_eq!(v["slaves"][1]["revision"], 1);
    assert_eq!(v["slaves"][1]["order"], "SMD23K-B");
    assert_eq!(v["slaves"][1]["state"], "INIT");
    let out = common::sdo_tool(&[], &["slaves"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        "sdo-tool: `slaves` is an EtherCAT command: give --ethercat IFACE\n"
    );
}

/// Next to a running master: while pysoem holds both units in Op (`pysoem_master.py --hold-op 3`,
/// the working counter checked in every cycle and (Op, 0) read every 100 ms), `sdo-tool --ethercat`
/// reads the AL status once, finds Op and refuses in one line (exit 3), sending nothing that changes
/// a state; `states`, `slaves` (the SII read through the EEPROM interface) and `pdos` (the SIIs',
/// said so) look at it meanwhile; pysoem's run ends without one bad cycle. Before and after, on the idle chain, a run
/// finds Init and leaves Init.
#[test]
fn a_chain_another_master_runs_is_left_alone() {
    use std::io::{BufRead, BufReader};
    use std::process::{Command, Stdio};
    let link = Link::up(&["--units", "2"]);
    assert_eq!(ok(&link, &["read", "1", "0x1008", "vs"]), "\"SMD23K-B\"\n");
    let script = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../ethercat-slave/tests/python/pysoem_master.py");
    let mut master = Command::new("python3")
        .arg(&script)
        .args([link.master.as_str(), "2", "--hold-op", "3"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("python3 with pysoem (scripts/setup-test-deps installs it)");
    let mut lines = BufReader::new(master.stdout.take().unwrap()).lines();
    let first = lines.next().and_then(Result::ok);
    assert_eq!(first.as_deref(), Some("in Op"), "pysoem reached Op");
    // A read-only look is fine next to a running master.
    assert_eq!(
        ok(&link, &["states"]),
        "  1  OP          AL status code 0x0000\n  2  OP          AL status code 0x0000\n"
    );
    // (Checked once pysoem's run is: a failed run would show here as states other than Op.)
    let slaves = ok(&link, &["slaves"]);
    // The PDOs: the SII's, said so; the CoE assignment needs Pre-Op, which is not asked for.
    let pdos = tool(&link, &["pdos", "2"]);
    let out = tool(&link, &["read", "1", "0x1008", "vs"]);
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(
        stderr(&out),
        format!(
            "sdo-tool: EtherCAT: interface {}: the chain is in Op (AL status 0x0008, every slave's \
             OR'd): another master runs it; sdo-tool --ethercat takes only a chain in Init and \
             leaves it there\n",
            link.master
        )
    );
    let rest: Vec<String> = lines.map_while(Result::ok).collect();
    let status = master.wait().unwrap();
    let mut err = String::new();
    std::io::Read::read_to_string(&mut master.stderr.take().unwrap(), &mut err).unwrap();
    assert!(status.success(), "pysoem: {rest:?}\n{err}");
    assert!(
        rest.last().is_some_and(|l| l.contains("held Op for 3 s")),
        "{rest:?}"
    );
    assert_eq!(
        slaves,
        concat!(
            "1  0:0  OP  +  SMD23K-B Integrated Stepper Indexer/Driver/Motor (EtherCAT)\n",
            "2  0:1  OP  +  SMD23K-B Integrated Stepper Indexer/Driver/Motor (EtherCAT)\n"
        )
    );
    assert!(pdos.status.success(), "{}", stderr(&pdos));
    assert_eq!(
        stderr(&pdos),
        "sdo-tool: the chain is in Op, another master's: the PDOs shown are the SIIs' (the CoE \
         assignment is read in Pre-Op)\n"
    );
    let pdos = stdout(&pdos);
    let syncs: Vec<&str> = pdos.lines().filter(|l| l.starts_with("SM")).collect();
    assert_eq!(
        syncs,
        [
            "SM0: PhysAddr 0x1000, DefaultSize  128, ControlRegister 0x26, Enable 1",
            "SM1: PhysAddr 0x1080, DefaultSize  128, ControlRegister 0x22, Enable 1",
            "SM2: PhysAddr 0x1100, DefaultSize   20, ControlRegister 0x64, Enable 1",
            "SM3: PhysAddr 0x1400, DefaultSize   20, ControlRegister 0x20, Enable 1",
        ]
    );
    assert!(
        pdos.contains(
            "  RxPDO 0x1600 \"Outputs\"\n    PDO entry 0x7000:01, 16 bit, \"CMD_word0\"\n"
        ),
        "{pdos}"
    );

    // pysoem's script asks for Init at its end: the chain is idle again, and served.
    assert_eq!(ok(&link, &["read", "2", "0x1018:04", "u32"]), "2\n");
}

/// `sdos` lists the slave's dictionary by SDO Information (ETG.1000.6 §5.6.3), in IgH's layout; and
/// `read`/`write` with neither TYPE nor --od take the entry's type from the same service.
#[test]
fn sdos_and_reads_without_a_description() {
    let link = Link::up(&["--units", "2"]);
    let listing = ok(&link, &["sdos", "1"]);
    // The ESI's 13 objects, in index order; 0x1018 and 0x8010 in full.
    let objects: Vec<&str> = listing.lines().filter(|l| l.starts_with("SDO ")).collect();
    assert_eq!(objects.len(), 13, "{listing}");
    assert_eq!(objects[0], "SDO 0x1000, VAR, \"Device type\"");
    assert_eq!(objects[12], "SDO 0x8010, RECORD, \"Configuration Data\"");
    assert!(
        listing.contains(concat!(
            "SDO 0x1018, RECORD, \"Identity\"\n",
            "  0x1018:00, r-r-r-, UNSIGNED8, 8 bit, \"SubIndex 000\"\n",
            "  0x1018:01, r-r-r-, UNSIGNED32, 32 bit, \"Vendor ID\"\n",
            "  0x1018:02, r-r-r-, UNSIGNED32, 32 bit, \"Product code\"\n",
            "  0x1018:03, r-r-r-, UNSIGNED32, 32 bit, \"Revision\"\n",
            "  0x1018:04, r-r-r-, UNSIGNED32, 32 bit, \"Serial number\"\n",
            "SDO 0x1600, RECORD, \"Outputs\"\n",
        )),
        "{listing}"
    );
    assert!(
        listing.ends_with(concat!(
            "SDO 0x8010, RECORD, \"Configuration Data\"\n",
            "  0x8010:00, r-r-r-, UNSIGNED8, 8 bit, \"SubIndex 000\"\n",
            "  0x8010:01, rwrwrw, UNSIGNED16, 16 bit, \"CFG_Word_0\"\n",
            "  0x8010:02, rwrwrw, UNSIGNED16, 16 bit, \"CFG_Word_1\"\n",
            "  0x8010:03, rwrwrw, UNSIGNED32, 32 bit, \"Starting_Speed\"\n",
            "  0x8010:04, rwrwrw, UNSIGNED16, 16 bit, \"Motor_Resolution\"\n",
            "  0x8010:05, rwrwrw, UNSIGNED16, 16 bit, \"Encoder_Resolution\"\n",
            "  0x8010:06, rwrwrw, UNSIGNED16, 16 bit, \"Idle_current_reduction\"\n",
            "  0x8010:07, rwrwrw, UNSIGNED16, 16 bit, \"Motor_Current\"\n",
        )),
        "{listing}"
    );
    // Every slave, each under its position.
    let both = ok(&link, &["sdos"]);
    let headers: Vec<&str> = both.lines().filter(|l| l.starts_with("===")).collect();
    assert_eq!(headers, ["=== Slave 1 ===", "=== Slave 2 ==="]);
    assert_eq!(both.lines().count(), 2 * (listing.lines().count() + 1));
    // One JSON object per slave; the inputs are TxPDO-mappable.
    let v: serde_json::Value = serde_json::from_str(&ok(&link, &["--json", "sdos", "2"])).unwrap();
    assert_eq!(v["position"], 2);
    let status = &v["objects"][10];
    assert_eq!(status["object"], "0x6000");
    assert_eq!(status["object_code"], "RECORD");
    assert_eq!(status["max_sub"], 7);
    assert_eq!(
        status["entries"][1],
        serde_json::json!({"sub": 1, "name": "STATUS_word0", "type": "UNSIGNED16",
            "type_code": 6, "bits": 16, "access": "r-r-r-", "rxpdo": false, "txpdo": true})
    );
    let o = tool(&link, &["sdos", "3"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        stderr(&o),
        format!(
            "sdo-tool: slave position 3 is not 1 to 2 (the chain on {} has 2 slaves)\n",
            link.master
        )
    );

    // No TYPE, no --od: the type is the slave's own description of the entry.
    assert_eq!(ok(&link, &["read", "1", "0x8010:03"]), "141\n");
    assert_eq!(ok(&link, &["read", "1", "0x1008"]), "\"SMD23K-B\"\n");
    assert_eq!(ok(&link, &["read", "2", "0x6000:03"]), "0\n");
    assert_eq!(ok(&link, &["write", "1", "0x8010:03", "600"]), "OK\n");
    assert_eq!(ok(&link, &["read", "1", "0x8010:03", "u32"]), "600\n");
    // An entry the slave does not have: its SDO Info Error, as the read would be refused.
    let o = tool(&link, &["read", "1", "0x2345:00"]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stderr(&o),
        "sdo-tool: 0x2345:00: SDO abort 0x06020000 (Object does not exist in the object dictionary)\n"
    );
    let o = tool(&link, &["read", "1", "0x1018:09"]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stderr(&o),
        "sdo-tool: 0x1018:09: SDO abort 0x06090011 (Sub-index does not exist)\n"
    );
}

/// With --od, a bit-coded entry is shown with the names of its set bits as its description lists
/// them (the ESI's STATUS_word0 and STATUS_word1 comments, Reference 6 Figures R6.4 and R6.5), in
/// text and in JSON: after power-up STATUS_word0 is 0x4408 (SMD-T2-002) and in Pre-Op STATUS_word1
/// has PreOp_SafeOp (SMD-R6-072), and Heartbeat_Bit (bit 11) in every other half second since the
/// unit started (SMD-R6-067): each read is checked with the heartbeat bit it shows.
#[test]
fn status_words_are_shown_with_their_bit_names() {
    let link = Link::up(&["--units", "1"]);
    let od = esi();
    assert_eq!(
        ok(&link, &["--od", &od, "read", "1", "STATUS_word0", "x16"]),
        "0x4408  [Stopped Position_Invalid Module_OK]\n"
    );
    let whole = ok(&link, &["--od", &od, "read", "1", "0x6000"]);
    let lines: Vec<&str> = whole.lines().collect();
    assert_eq!(
        lines[1],
        "0x6000:01  STATUS_word0 = 0x4408  [Stopped Position_Invalid Module_OK]"
    );
    // STATUS_word1: PreOp_SafeOp (0x0020), with the heartbeat (0x0800) half of the time.
    assert!(
        [
            "0x6000:02  STATUS_word1 = 0x0020  [PreOp_SafeOp]",
            "0x6000:02  STATUS_word1 = 0x0820  [PreOp_SafeOp Heartbeat_Bit]",
        ]
        .contains(&lines[2]),
        "{}",
        lines[2]
    );
    // A position has no named bits.
    assert_eq!(lines[3], "0x6000:03  Motor_Position = 0");
    let v: serde_json::Value = serde_json::from_str(&ok(
        &link,
        &["--json", "--od", &od, "read", "1", "STATUS_word1"],
    ))
    .unwrap();
    if v["value"] == 32 {
        assert_eq!(v["bits"], serde_json::json!(["PreOp_SafeOp"]));
    } else {
        assert_eq!(v["value"], 2080);
        assert_eq!(
            v["bits"],
            serde_json::json!(["PreOp_SafeOp", "Heartbeat_Bit"])
        );
    }
    assert!(v.get("unit").is_none(), "{v}");
    // Without --od the description's names are not known.
    assert_eq!(ok(&link, &["read", "1", "0x6000:01", "x16"]), "0x4408\n");
}
