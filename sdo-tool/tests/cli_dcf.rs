//! `sdo-tool`'s DCF commands and logs against the virtual X67 node: `dump`, `apply` (CiA 306
//! `ObjFlags`, refusals, the node's state), `list`, `decode` of a candump log and `read` of a whole
//! record.

mod common;
mod x67;

use std::path::Path;

use x67::{eds, Running, ID};

/// The DCF round trip on CANopen: `dump` reads the node's parameters (not its command objects, status
/// or cyclic outputs) and names the write-only ones it cannot read; the file, edited, goes back with
/// `apply` — each PDO by the CiA 301 procedure, every value read back — and `--save` stores it, so a
/// reset node keeps it.
#[test]
fn dump_edit_apply_save_round_trips_on_canopen() {
    let n = Running::start();
    let dir = tempfile::tempdir().unwrap();
    let dcf = dir.path().join("node5.dcf");
    n.tool(&["write", "5", "0x1017:00", "u16", "750"]).unwrap();
    n.tool(&["write", "5", "0x1800:02", "u8", "1"]).unwrap();
    let out = n
        .tool(&["--od", &eds(), "dump", "5", "-o", dcf.to_str().unwrap()])
        .unwrap();
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        lines[0].starts_with(
            "33 write-only parameters cannot be read back and are not in the file: \
             0x2010:00 (GeneralConfig01), 0x2113:00 (StallDetectConfig01), "
        ),
        "{out}"
    );
    assert_eq!(
        lines[1],
        format!(
            "43 entries written to {}; left out: 13 command objects, 6 cyclic outputs, \
             39 not writable, 33 write-only",
            dcf.display()
        )
    );
    let (_, devices) = od::load::load(&dcf).unwrap();
    let d = &devices[0].dictionary;
    assert_eq!(d.entry(0x1017, 0).unwrap().value, 750u16.to_le_bytes());
    for (index, sub, what) in [
        (0x1003u16, 0u8, "the error history (a command)"),
        (0x1010, 1, "store (a command)"),
        (0x1018, 1, "identity (read-only)"),
        (0x2100, 0, "AbsPos01 (a cyclic output)"),
        (
            0x2114,
            0,
            "MaxSpeed01pos (write-only, without a read-back register)",
        ),
    ] {
        assert!(
            !d.entry(index, sub).unwrap().value_set,
            "{what} not in the DCF"
        );
    }

    // Edited: the heartbeat 300 ms. Applied: RPDO 1 by the procedure, then the rest read back.
    let (_, mut devices) = od::load::load(&dcf).unwrap();
    devices[0]
        .dictionary
        .store_parameter(0x1017, 0, &300u16.to_le_bytes())
        .unwrap();
    std::fs::write(&dcf, od::eds::write_dcf(&devices[0])).unwrap();
    let out = n.tool(&["apply", "5", dcf.to_str().unwrap()]).unwrap();
    let lines: Vec<&str> = out.lines().collect();
    let rpdo1 = lines
        .iter()
        .position(|l| l.starts_with("wrote 0x1400:01"))
        .expect("RPDO 1 written");
    // COB-ID 0x205 (node 5), invalid 0x80000205 while its mapping changes; the mapping of the
    // description: AbsPos01 (0x2100, 32 bits), MpGenControl01 (0x2101, 16), MpGenMode01 (0x2102,
    // 8), a dummy byte (UNSIGNED8, 0x0005).
    assert_eq!(
        lines[rpdo1..rpdo1 + 9],
        [
            "wrote 0x1400:01 = 0x80000205 (the PDO made invalid while it changes)",
            "wrote 0x1400:02 = 255",
            "wrote 0x1600:00 = 0 (the count 0 while the entries change)",
            "wrote 0x1600:01 = 0x21000020 (0x2100:00, 32 bits)",
            "wrote 0x1600:02 = 0x21010010 (0x2101:00, 16 bits)",
            "wrote 0x1600:03 = 0x21020008 (0x2102:00, 8 bits)",
            "wrote 0x1600:04 = 0x00050008 (0x0005:00, 8 bits)",
            "wrote 0x1600:00 = 4",
            "wrote 0x1400:01 = 0x00000205",
        ]
    );
    assert!(lines.contains(&"wrote 0x1017:00 = 300"), "{out}");
    assert_eq!(
        *lines.last().unwrap(),
        "43 entries written, 0 skipped, 0 refused"
    );
    assert_eq!(n.tool(&["read", "5", "0x1017:00", "u16"]).unwrap(), "300\n");
    assert_eq!(n.tool(&["read", "5", "0x1800:02", "u8"]).unwrap(), "1\n");

    // With --save the set survives a reset node.
    let out = n
        .tool(&["apply", "5", dcf.to_str().unwrap(), "--save"])
        .unwrap();
    assert!(out.ends_with("saved: 0x1010:01 = \"save\"\n"), "{out}");
    n.tool(&["write", "5", "0x1017:00", "u16", "900"]).unwrap();
    n.tool(&["nmt", "reset", "5"]).unwrap();
    std::thread::sleep(std::time::Duration::from_millis(200));
    assert_eq!(n.tool(&["read", "5", "0x1017:00", "u16"]).unwrap(), "300\n");
}

/// The SDO requests to node 5 that `tap` saw since it was last asked, one `upload`/`download
/// INDEX:SUB` each (the initiating frame of each transfer; expedited and segmented alike).
fn sdo_requests(tap: &mut socketcan_node::transport::Endpoint) -> Vec<String> {
    let mut requests = Vec::new();
    while let Some(f) = tap.try_recv() {
        let d = f.data();
        if f.raw_id() != 0x600 + u32::from(ID) || d.len() < 4 {
            continue;
        }
        // CiA 301 §7.2.4.3: the client command specifier, bits 7–5 of the first byte; segments
        // (0, 3) carry no multiplexer.
        let what = match d[0] >> 5 {
            1 => "download",
            2 => "upload",
            5 if d[0] & 0x03 == 0 => "block upload",
            6 if d[0] & 0x01 == 0 => "block download",
            _ => continue,
        };
        requests.push(format!(
            "{what} 0x{:04X}:{:02X}",
            u16::from_le_bytes([d[1], d[2]]),
            d[3]
        ));
    }
    requests
}

/// CiA 306 `ObjFlags` honoured end to end, with `fixtures/objflags/ObjFlags.eds` (entries of the X67
/// node's dictionary): `dump` reads no entry flagged "refuse read on scan" (bit 1: 0x1006, 0x1015, and
/// 0x1016 flagged in its object's section alone) and names each; the DCF it writes keeps the flags;
/// `apply` of that DCF, every entry set, writes no entry flagged "refuse write on download" (bit 0:
/// 0x1005, 0x1015, 0x1016) and says so, in its dry run too. The bus shows exactly the SDO requests
/// that leaves.
#[test]
fn dump_and_apply_leave_out_what_obj_flags_refuse() {
    let n = Running::start();
    let mut tap = n.bus.endpoint();
    let eds = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures/objflags/ObjFlags.eds")
        .display()
        .to_string();
    let dir = tempfile::tempdir().unwrap();
    let dcf = dir.path().join("node5.dcf");

    let out = n.tool(&["--od", &eds, "list"]).unwrap();
    let flagged: Vec<&str> = out.lines().filter(|l| l.contains("ObjFlags")).collect();
    assert_eq!(
        flagged,
        [
            "0x1005:00  COB-ID SYNC  UNSIGNED32  rw  default 128  ObjFlags 0x1 (refuse write on download)",
            "0x1006:00  Communication cycle period  UNSIGNED32  rw  default 0  ObjFlags 0x2 (refuse read on scan)",
            "0x1015:00  Inhibit time EMCY  UNSIGNED16  rw  default 0  ObjFlags 0x3 (refuse write on download, refuse read on scan)",
            "0x1016:00  Consumer heartbeat time.Highest sub-index supported  UNSIGNED8  ro  default 1  ObjFlags 0x3 (refuse write on download, refuse read on scan)",
            "0x1016:01  Consumer heartbeat time.Consumer heartbeat time  UNSIGNED32  rw  default 0  ObjFlags 0x3 (refuse write on download, refuse read on scan)",
        ]
    );
    sdo_requests(&mut tap);

    let out = n
        .tool(&["--od", &eds, "dump", "5", "-o", dcf.to_str().unwrap()])
        .unwrap();
    assert_eq!(
        out.lines().collect::<Vec<_>>(),
        [
            "skipped 0x1006:00 (Communication cycle period): ObjFlags bit 1: refuse read on scan",
            "skipped 0x1015:00 (Inhibit time EMCY): ObjFlags bit 1: refuse read on scan",
            "skipped 0x1016:00 (Highest sub-index supported): ObjFlags bit 1: refuse read on scan",
            "skipped 0x1016:01 (Consumer heartbeat time): ObjFlags bit 1: refuse read on scan",
            &format!(
                "2 entries written to {}; left out: 5 not writable, 4 refused by ObjFlags",
                dcf.display()
            ),
        ]
    );
    // The identity check of --od (0x1018:01, :02), then the two entries read.
    assert_eq!(
        sdo_requests(&mut tap),
        [
            "upload 0x1018:01",
            "upload 0x1018:02",
            "upload 0x1005:00",
            "upload 0x1017:00",
        ]
    );
    let text = std::fs::read_to_string(&dcf).unwrap();
    let flags: Vec<&str> = text.lines().filter(|l| l.starts_with("ObjFlags")).collect();
    assert_eq!(
        flags,
        [
            "ObjFlags=0x1",
            "ObjFlags=0x2",
            "ObjFlags=0x3",
            "ObjFlags=0x3"
        ]
    );

    // Every entry set, then applied: only 0x1006 and 0x1017 go to the node.
    let (_, mut devices) = od::load::load(&dcf).unwrap();
    for (index, sub, bytes) in [
        (0x1005u16, 0u8, 0x81u32.to_le_bytes().to_vec()),
        (0x1006, 0, 250u32.to_le_bytes().to_vec()),
        (0x1015, 0, 10u16.to_le_bytes().to_vec()),
        (0x1016, 1, 0x0005_0064u32.to_le_bytes().to_vec()),
        (0x1017, 0, 500u16.to_le_bytes().to_vec()),
    ] {
        devices[0]
            .dictionary
            .store_parameter(index, sub, &bytes)
            .unwrap();
    }
    std::fs::write(&dcf, od::eds::write_dcf(&devices[0])).unwrap();
    let skipped = [
        "skipped 0x1005:00 = 0x00000081: ObjFlags bit 0: refuse write on download",
        "skipped 0x1015:00 = 10: ObjFlags bit 0: refuse write on download",
        "skipped 0x1016:01 = 0x00050064: ObjFlags bit 0: refuse write on download",
    ];
    let out = n
        .tool(&["apply", "5", dcf.to_str().unwrap(), "--dry-run"])
        .unwrap();
    let mut expected = skipped.to_vec();
    expected.extend([
        "would write 0x1006:00 = 250",
        "would write 0x1017:00 = 500",
        "2 entries to write, 3 skipped, 0 refused",
    ]);
    assert_eq!(out.lines().collect::<Vec<_>>(), expected);
    assert_eq!(sdo_requests(&mut tap), Vec::<String>::new(), "dry run");

    let out = n.tool(&["apply", "5", dcf.to_str().unwrap()]).unwrap();
    let mut expected = skipped.to_vec();
    expected.extend([
        "wrote 0x1006:00 = 250",
        "wrote 0x1017:00 = 500",
        "2 entries written, 3 skipped, 0 refused",
    ]);
    assert_eq!(out.lines().collect::<Vec<_>>(), expected);
    // Each write read back.
    assert_eq!(
        sdo_requests(&mut tap),
        [
            "download 0x1006:00",
            "upload 0x1006:00",
            "download 0x1017:00",
            "upload 0x1017:00",
        ]
    );
    assert_eq!(
        n.tool(&["read", "5", "0x1005:00", "x32"]).unwrap(),
        "0x00000080\n"
    );
    assert_eq!(n.tool(&["read", "5", "0x1015:00", "u16"]).unwrap(), "0\n");
    assert_eq!(n.tool(&["read", "5", "0x1016:01", "u32"]).unwrap(), "0\n");
}

/// `list --od FILE`: every entry of the description, one line each, the names `read` and `write`
/// take; without --od a usage error; with --json one document. A name that is not there is refused
/// with the names close to it.
#[test]
fn list_shows_the_description_and_names_are_suggested() {
    let n = Running::start();
    let od = eds();
    let out = n.tool(&["--od", &od, "list"]).unwrap();
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 134);
    for want in [
        "0x1000:00  Device type  UNSIGNED32  ro  default 0",
        "0x1017:00  Producer heartbeat time  UNSIGNED16  rw  default 0",
        "0x1018:01  Identity.Vendor-ID  UNSIGNED32  ro  default 2862",
        "0x2110:00  ConfigOutput03a  UNSIGNED8  wo  default 0  limits 0 to 167",
    ] {
        assert!(lines.contains(&want), "{want}\n{out}");
    }
    assert_eq!(n.tool(&["list"]).unwrap_err().exit_code(), 2);
    let json: serde_json::Value =
        serde_json::from_str(&n.tool(&["--od", &od, "--json", "list"]).unwrap()).unwrap();
    assert_eq!(json["entries"].as_array().unwrap().len(), 134);
    assert_eq!(json["entries"][0]["name"], "Device type");
    let e = n
        .tool(&["--od", &od, "read", "5", "ConfigOutput3a"])
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "object \"ConfigOutput3a\": no object or sub-object is named `ConfigOutput3a`; did you \
         mean `ConfigOutput03a`, `ConfigOutput04a`, `ConfigOutput05a`?"
    );
    assert_eq!(e.exit_code(), 2);
}

/// Refusals that name the user's mistake, before anything is sent where the description tells: a
/// type that does not fit the bytes read (exit 2, not a transport failure), a write to a read-only
/// entry and a read of a write-only one (from the description's access).
#[test]
fn mistakes_are_named_before_sending() {
    let n = Running::start();
    let od = eds();
    for (argv, says) in [
        (
            &["read", "5", "0x1008:00", "u16"][..],
            "0x1008:00: UNSIGNED16 takes 2 bytes, got 24: the entry is of another type (read it \
             as its own type, or as hex)",
        ),
        (
            &["--od", &od, "write", "5", "0x1018:01", "5"],
            "0x1018:01 (Vendor-ID) is read-only (ro) in the description: not written",
        ),
        (
            &["--od", &od, "read", "5", "ConfigOutput03a"],
            "0x2110:00 (ConfigOutput03a) is write-only (wo) in the description: not read",
        ),
    ] {
        let e = n.tool(argv).unwrap_err();
        assert_eq!(e.to_string(), says);
        assert_eq!(e.exit_code(), 2, "{argv:?}");
    }
}

/// `decode` names every frame of a candump log written by hand from CiA 301's layouts: boot-up, the
/// state changes the heartbeat shows, an NMT command, an expedited write and its confirmation, a
/// segmented upload of 0x1008 reassembled (24 bytes in 4 segments, toggles 0 1 0 1, the last with
/// n = 4), a heartbeat found missing when the next frame comes 0.3 s after it (period 0.1 s), an
/// abort, SYNC, the node's TPDO 1 and RPDO 1 by the description's mapping; a frame of no kind only
/// with --raw; a line that is no frame is skipped and counted.
#[test]
fn decode_names_every_frame_of_a_candump_log() {
    let n = Running::start();
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("bus.log");
    std::fs::write(
        &log,
        "(100.000000) can0 701#00\n\
         (100.100000) can0 701#7F\n\
         (100.200000) can0 000#0101\n\
         (100.210000) can0 601#2B17100064000000\n\
         (100.211000) can0 581#6017100000000000\n\
         (100.300000) can0 701#05\n\
         (100.310000) can0 601#4008100000000000\n\
         (100.311000) can0 581#4108100018000000\n\
         (100.312000) can0 601#6000000000000000\n\
         (100.313000) can0 581#0058363742433433\n\
         (100.314000) can0 601#7000000000000000\n\
         (100.315000) can0 581#1032312D3130202F\n\
         (100.316000) can0 601#6000000000000000\n\
         (100.317000) can0 581#0020583637534D32\n\
         (100.318000) can0 601#7000000000000000\n\
         (100.319000) can0 581#1934333600000000\n\
         (100.400000) can0 701#05\n\
         (100.500000) can0 701#05\n\
         (100.800000) can0 601#4018100500000000\n\
         (100.801000) can0 581#8018100511000906\n\
         not a frame\n\
         (100.900000) can0 080#\n\
         (100.901000) can0 181#8813000040060100\n\
         (100.902000) can0 201#102700000F000100\n\
         (100.903000) can0 123#DEAD\n",
    )
    .unwrap();
    let log = log.to_str().unwrap();
    let out = n.tool(&["--od", &eds(), "decode", log, "1"]).unwrap();
    assert_eq!(
        out.lines().collect::<Vec<_>>(),
        [
            "  0.000000  node 1: boot-up",
            "  0.100000  node 1: NMT boot-up -> pre-operational",
            "  0.200000  NMT start: node 1",
            "  0.210000  node 1: SDO write 0x1017:00 (Producer heartbeat time) = 100",
            "  0.211000  node 1: SDO written 0x1017:00 (Producer heartbeat time)",
            "  0.300000  node 1: NMT pre-operational -> operational",
            "  0.319000  node 1: SDO read 0x1008:00 (Manufacturer device name) = \"X67BC4321-10 / X67SM2436\" (24 bytes, segmented)",
            "  0.400000  node 1: heartbeat, operational",
            "  0.500000  node 1: heartbeat, operational",
            "  0.800000  node 1: heartbeat missed: none for 0.300 s (period 0.100 s)",
            "  0.801000  node 1: SDO server aborts 0x1018:05: 0x06090011 (Sub-index does not exist)",
            "  0.900000  SYNC",
            "  0.901000  node 1: TPDO 1 AbsPos01ActVal=5000 MpGenStatus01=1600 InputStatus=1",
            "  0.902000  node 1: RPDO 1 AbsPos01=10000 MpGenControl01=15 MpGenMode01=1",
        ]
    );
    let out = n.tool(&["decode", log, "--raw"]).unwrap();
    assert_eq!(out.lines().last(), Some("  0.903000  123#DEAD"));
    assert!(
        out.contains("  0.902000  201#102700000F000100\n"),
        "without --od a PDO is raw: {out}"
    );
    // candump's filters: node 1's SDO identifiers only; then the kinds asked for. Times stay those
    // since the log's first frame.
    let out = n
        .tool(&["--od", &eds(), "decode", log, "--filter", "581,601"])
        .unwrap();
    assert_eq!(
        out.lines().collect::<Vec<_>>(),
        [
            "  0.210000  node 1: SDO write 0x1017:00 (Producer heartbeat time) = 100",
            "  0.211000  node 1: SDO written 0x1017:00 (Producer heartbeat time)",
            "  0.319000  node 1: SDO read 0x1008:00 (Manufacturer device name) = \"X67BC4321-10 / X67SM2436\" (24 bytes, segmented)",
            "  0.801000  node 1: SDO server aborts 0x1018:05: 0x06090011 (Sub-index does not exist)",
        ]
    );
    let out = n
        .tool(&[
            "--od",
            &eds(),
            "decode",
            log,
            "1",
            "--only",
            "heartbeat,pdo",
            "--filter",
            "181-201",
        ])
        .unwrap();
    // The heartbeats are filtered out, so no beat is missed either.
    assert_eq!(
        out.lines().collect::<Vec<_>>(),
        [
            "  0.901000  node 1: TPDO 1 AbsPos01ActVal=5000 MpGenStatus01=1600 InputStatus=1",
            "  0.902000  node 1: RPDO 1 AbsPos01=10000 MpGenControl01=15 MpGenMode01=1",
        ]
    );
    // Several filters: a frame any of them passes is taken. Not NMT (~0) or 181-201: everything
    // but the NMT command; of it the heartbeat lines.
    let out = n
        .tool(&["decode", log, "--only", "hb", "--filter", "~0,181-201"])
        .unwrap();
    assert_eq!(
        out.lines().collect::<Vec<_>>(),
        [
            "  0.000000  node 1: boot-up",
            "  0.100000  node 1: NMT boot-up -> pre-operational",
            "  0.300000  node 1: NMT pre-operational -> operational",
            "  0.400000  node 1: heartbeat, operational",
            "  0.500000  node 1: heartbeat, operational",
            "  0.800000  node 1: heartbeat missed: none for 0.300 s (period 0.100 s)",
        ]
    );
    // A filter that is none: a usage error (exit 2) naming it.
    use clap::Parser;
    let e = sdo_tool::cli::Args::try_parse_from(["sdo-tool", "decode", log, "--filter", "800"])
        .unwrap_err();
    assert_eq!(e.exit_code(), 2);
    assert!(
        e.to_string()
            .contains("filter \"800\" is not ID, ID:MASK or LOW-HIGH"),
        "{e}"
    );
}

/// `read` of a whole RECORD with --od, by its name or its bare index: every readable entry, a line
/// each with its name, typed from the description; as JSON one object with the entries. Without
/// --od a bare index is sub-index 0, as before.
#[test]
fn read_of_a_whole_record() {
    let n = Running::start();
    let od = eds();
    let lines = "0x1018:00  Highest sub-index supported = 4\n\
                 0x1018:01  Vendor-ID = 0x00000B2E\n\
                 0x1018:02  Product code = 0x00002436\n\
                 0x1018:03  Revision number = 0x00000001\n\
                 0x1018:04  Serial number = 0x00000000\n";
    assert_eq!(
        n.tool(&["--od", &od, "read", "5", "Identity"]).unwrap(),
        lines
    );
    assert_eq!(
        n.tool(&["--od", &od, "read", "5", "0x1018"]).unwrap(),
        lines
    );
    let v: serde_json::Value = serde_json::from_str(
        &n.tool(&["--od", &od, "--json", "read", "5", "0x1018"])
            .unwrap(),
    )
    .unwrap();
    assert_eq!(v["object"], "0x1018");
    assert_eq!(v["entries"].as_array().unwrap().len(), 5);
    assert_eq!(
        v["entries"][1],
        serde_json::json!({"object": "0x1018:01", "name": "Vendor-ID", "value": 2862, "text": "0x00000B2E"})
    );
    assert_eq!(n.tool(&["read", "5", "0x1018", "u8"]).unwrap(), "4\n");
}

/// A node in Operational refuses PDO mapping changes for its state (0x08000022): `apply` says to
/// configure it in Pre-Operational; there it goes through.
#[test]
fn apply_in_operational_says_to_configure_in_pre_operational() {
    let n = Running::start();
    let dir = tempfile::tempdir().unwrap();
    let dcf = dir.path().join("node5.dcf");
    n.tool(&["--od", &eds(), "dump", "5", "-o", dcf.to_str().unwrap()])
        .unwrap();
    n.tool(&["nmt", "start", "5"]).unwrap();
    std::thread::sleep(std::time::Duration::from_millis(100));
    let (out, e) = n.tool_output(&["apply", "5", dcf.to_str().unwrap()]);
    assert_eq!(e.map(|e| e.exit_code()), Some(1));
    let last = out.lines().last().unwrap();
    assert!(
        last.ends_with(
            " refused for the node's present state (0x08000022): configure it in Pre-Operational \
             (sdo-tool nmt preop 5) and apply again"
        ),
        "{out}"
    );
    n.tool(&["nmt", "preop", "5"]).unwrap();
    std::thread::sleep(std::time::Duration::from_millis(100));
    let out = n.tool(&["apply", "5", dcf.to_str().unwrap()]).unwrap();
    assert!(
        out.ends_with(" entries written, 0 skipped, 0 refused\n"),
        "{out}"
    );
}

/// `apply` of a DCF made elsewhere: a command object it sets is left out, an object the node does not
/// have is skipped with a warning (0x06020000), a mapping entry of a valid RPDO the node refuses
/// (0x06040043, the DCF sets no COB-ID to make it invalid; another entry than the one it holds,
/// which it would take back unchanged) is reported and the rest goes on (exit 1);
/// `--stop-on-error` stops at that refusal instead.
#[test]
fn apply_skips_and_reports_refusals_and_goes_on() {
    let n = Running::start();
    let dir = tempfile::tempdir().unwrap();
    let (_, mut devices) = od::load::load(Path::new(&eds())).unwrap();
    let d = &mut devices[0];
    d.dictionary.insert(od::object::Object::var(
        0x2FFF,
        od::object::SubObject::new(
            "Elsewhere",
            od::DataType::Unsigned8,
            od::object::AccessType::Rw,
        ),
    ));
    for (index, sub, bytes) in [
        (0x1010u16, 1u8, 0x6576_6173u32.to_le_bytes().to_vec()),
        (0x1017, 0, 1_000u16.to_le_bytes().to_vec()),
        (0x1600, 1, 0x2101_0010u32.to_le_bytes().to_vec()),
        (0x2110, 0, vec![20]),
        (0x2FFF, 0, vec![7]),
    ] {
        d.dictionary.store_parameter(index, sub, &bytes).unwrap();
    }
    let bad = dir.path().join("bad.dcf");
    std::fs::write(&bad, od::eds::write_dcf(d)).unwrap();
    let before = n.tool(&["read", "5", "0x1017:00", "u16"]).unwrap();
    let out = n
        .tool(&["apply", "5", bad.to_str().unwrap(), "--dry-run"])
        .unwrap();
    assert!(out.contains("would write 0x1017:00 = 1000"), "{out}");
    assert!(
        out.ends_with("4 entries to write, 1 skipped, 0 refused\n"),
        "{out}"
    );
    assert_eq!(
        n.tool(&["read", "5", "0x1017:00", "u16"]).unwrap(),
        before,
        "dry run"
    );

    let (out, e) = n.tool_output(&["apply", "5", bad.to_str().unwrap(), "--stop-on-error"]);
    assert_eq!(e.map(|e| e.exit_code()), Some(1));
    assert!(
        out.contains(
            "REFUSED 0x1600:01 = 0x21010010 (0x2101:00, 16 bits): 0x1600:01: SDO abort 0x06040043 (General parameter incompatibility reason); nothing after it written"
        ),
        "{out}"
    );
    assert_eq!(
        n.tool(&["read", "5", "0x2130:00", "u8"]).unwrap(),
        "0\n",
        "stopped"
    );

    let (out, e) = n.tool_output(&["apply", "5", bad.to_str().unwrap()]);
    assert_eq!(e.map(|e| e.to_string()), Some("1 writes refused".into()));
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        lines,
        [
            "skipped 0x1010:01 = 0x65766173: store parameters: a command",
            "wrote 0x1017:00 = 1000",
            "REFUSED 0x1600:01 = 0x21010010 (0x2101:00, 16 bits): 0x1600:01: SDO abort 0x06040043 (General parameter incompatibility reason)",
            "wrote 0x2110:00 = 20",
            "skipped 0x2FFF:00 = 7: the node refuses it: 0x06020000 (Object does not exist in the object dictionary)",
            "2 entries written, 2 skipped, 1 refused",
        ]
    );
    assert_eq!(
        n.tool(&["read", "5", "0x2130:00", "u8"]).unwrap(),
        "20\n",
        "written after the refusal (its read-back register)"
    );
    // --json: one object with the same steps and the counts, and nothing else on the output.
    let (out, e) = n.tool_output(&["--json", "apply", "5", bad.to_str().unwrap()]);
    assert_eq!(e.map(|e| e.exit_code()), Some(1));
    assert_eq!(out.lines().count(), 1, "{out}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        v,
        serde_json::json!({
            "steps": &lines[..5],
            "written": 2, "to_write": 0, "skipped": 2, "refused": 1,
            "refused_in_state": 0, "differences": 0, "saved": false,
        })
    );
}

/// `dump` of the X67SM2436: the six write-only current settings (ConfigOutput03a…08a, 0x2110–0x2112
/// and 0x2210–0x2212) are read through their read-back registers (ConfigOutput03aRead…08aRead,
/// 0x2130–0x2132 and 0x2230–0x2232, the manual's 18.5 "Reading back the configuration"), each named
/// on stderr, and the DCF holds the values configured under the write-only entries; MaxSpeed01pos,
/// which has no read-back register, is not in the file. The DCF applied to another node sets them
/// there.
#[test]
fn dump_reads_write_only_settings_through_their_read_back_registers() {
    let (mut node, port) = x67::hub(3);
    let bus = common::socketcand_bus(port);
    let od = eds();
    let named = ["--bus", bus.as_str(), "--od", od.as_str()];
    let settings = [
        ("ConfigOutput03a", "20"),
        ("ConfigOutput04a", "30"),
        ("ConfigOutput05a", "40"),
        ("ConfigOutput06a", "50"),
        ("ConfigOutput07a", "60"),
        ("ConfigOutput08a", "70"),
        ("MaxSpeed01pos", "1000"),
    ];
    for (name, value) in settings {
        common::sdo_tool_ok(&named, &["write", "3", name, value]);
    }
    let dir = tempfile::tempdir().unwrap();
    let dcf = dir.path().join("node3.dcf");
    let out = common::sdo_tool(&named, &["dump", "3", "-o", dcf.to_str().unwrap()]);
    assert!(out.status.success());
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "sdo-tool: 0x2110:00 (ConfigOutput03a) read through its read-back register 0x2130:00 (ConfigOutput03aRead)\n\
         sdo-tool: 0x2111:00 (ConfigOutput04a) read through its read-back register 0x2131:00 (ConfigOutput04aRead)\n\
         sdo-tool: 0x2112:00 (ConfigOutput05a) read through its read-back register 0x2132:00 (ConfigOutput05aRead)\n\
         sdo-tool: 0x2210:00 (ConfigOutput06a) read through its read-back register 0x2230:00 (ConfigOutput06aRead)\n\
         sdo-tool: 0x2211:00 (ConfigOutput07a) read through its read-back register 0x2231:00 (ConfigOutput07aRead)\n\
         sdo-tool: 0x2212:00 (ConfigOutput08a) read through its read-back register 0x2232:00 (ConfigOutput08aRead)\n"
    );
    let (_, devices) = od::load::load(&dcf).unwrap();
    let d = &devices[0].dictionary;
    for (index, value) in [
        (0x2110u16, 20u8),
        (0x2111, 30),
        (0x2112, 40),
        (0x2210, 50),
        (0x2211, 60),
        (0x2212, 70),
    ] {
        let e = d.entry(index, 0).unwrap();
        assert!(e.value_set, "0x{index:04X} in the DCF");
        assert_eq!(e.value, [value], "0x{index:04X}");
    }
    assert!(!d.entry(0x2114, 0).unwrap().value_set, "MaxSpeed01pos");
    // In the file as CiA 306 writes it: the section of 0x2110 with its ParameterValue, 20.
    let text = std::fs::read_to_string(&dcf).unwrap();
    let section: Vec<&str> = text
        .lines()
        .skip_while(|l| *l != "[2110]")
        .take_while(|l| !l.is_empty())
        .collect();
    assert!(section.contains(&"ParameterValue=0x14"), "{section:?}");
    // --json names them too.
    let json = common::sdo_tool_ok(
        &["--bus", &bus, "--od", &od, "--json"],
        &["dump", "3", "-o", dcf.to_str().unwrap()],
    );
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(
        v["read_back"][0],
        serde_json::json!({"entry": "0x2110:00 (ConfigOutput03a)", "through": "0x2130:00 (ConfigOutput03aRead)"})
    );
    // A write-only entry the description flags "refuse read on scan" (ObjFlags bit 1) is not read
    // through its read-back register either.
    let flagged = dir.path().join("flagged.eds");
    let text: String = std::fs::read_to_string(&od)
        .unwrap()
        .lines()
        .flat_map(|l| match l {
            "ParameterName=ConfigOutput03a" => vec![l, "ObjFlags=0x2"],
            _ => vec![l],
        })
        .map(|l| format!("{l}\r\n"))
        .collect();
    assert!(text.contains("ObjFlags=0x2"));
    std::fs::write(&flagged, text).unwrap();
    let out = common::sdo_tool(
        &["--bus", &bus, "--od", flagged.to_str().unwrap()],
        &[
            "dump",
            "3",
            "-o",
            dir.path().join("flagged.dcf").to_str().unwrap(),
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.lines().count(), 5, "{stderr}");
    assert!(!stderr.contains("0x2110"), "{stderr}");
    assert!(String::from_utf8_lossy(&out.stdout)
        .contains("skipped 0x2110:00 (ConfigOutput03a): ObjFlags bit 1: refuse read on scan"));
    node.kill().unwrap();
    node.wait().unwrap();

    // Applied to a node in its defaults: the currents read back as dumped.
    let (mut other, port) = x67::hub(4);
    let bus = common::socketcand_bus(port);
    let plain = ["--bus", bus.as_str()];
    common::sdo_tool_ok(&plain, &["apply", "4", dcf.to_str().unwrap()]);
    assert_eq!(
        common::sdo_tool_ok(&plain, &["read", "4", "0x2132:00", "u8"]),
        "40\n"
    );
    assert_eq!(
        common::sdo_tool_ok(&plain, &["read", "4", "0x2230:00", "u8"]),
        "50\n"
    );
    other.kill().unwrap();
    other.wait().unwrap();
}
