//! Captures of this project's own sessions (`--capture`), read by Wireshark's dissectors (tshark,
//! `testkit::tshark`): no malformed packet, no expert error, every frame dissected as the protocol
//! it is, with the fields of each service present.
//!
//! - CANopen: `canopen-node` (the example I/O device at node 5, the example drive at node 6 and a
//!   drive without a node-ID) on a socketcand server of 127.0.0.1, captured by the node, and
//!   `sdo-tool` sessions against it, each captured by the tool: SDO of every kind (expedited,
//!   segmented and block, download and upload, an abort), SYNC with the TPDO it triggers and RPDOs,
//!   NMT commands, heartbeats, EMCY, LSS (identify, Fastscan, switch, configure node-ID). Every
//!   frame is `can:canopen` with `-d can.subdissector,canopen` (but a SYNC without a counter: tshark
//!   hands an empty payload to no dissector, and it stays `can`); a frame the tool sent is outbound
//!   in its capture and inbound in the node's. `decode` of the node's capture names the same session.
//! - EtherCAT: `sdo-tool --ethercat` (read, an abort, SDO Information) against `ethercat-node` on a
//!   veth pair, captured by both: every frame `eth:ethertype:ecatf:ecat`, the CoE mailboxes
//!   `ecat_mailbox` with their SDO and SDO Information fields.
//!
//! Needs tshark (`scripts/setup-test-deps`) and, for EtherCAT, root.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use testkit::tshark::{self, CANOPEN};

fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(name)
        .display()
        .to_string()
}

/// A number as tshark prints it: `0x…` hexadecimal, else decimal.
fn number(text: &str) -> u64 {
    match text.strip_prefix("0x") {
        Some(hex) => u64::from_str_radix(hex, 16).unwrap(),
        None => text.parse().unwrap(),
    }
}

/// The numbers of field column `k` (of [`tshark::fields`]' rows) in every frame that has it.
fn values(rows: &[Vec<String>], k: usize) -> Vec<u64> {
    rows.iter()
        .flat_map(|r| r[k].split(',').filter(|v| !v.is_empty()).map(number))
        .collect()
}

/// The sdo-tool runs of one session, each with a capture of its own in `dir`.
struct Tool {
    dir: PathBuf,
    bus: String,
    captures: Vec<PathBuf>,
}

impl Tool {
    /// `sdo-tool --bus BUS --capture DIR/N-NAME.pcapng ARGS…`.
    fn run(&mut self, args: &[&str]) -> Output {
        let name = format!(
            "{:02}-{}.pcapng",
            self.captures.len(),
            args.join("_").replace('/', "")
        );
        let file = self.dir.join(name.chars().take(60).collect::<String>());
        let file_arg = file.display().to_string();
        let o = common::sdo_tool(&["--bus", &self.bus, "--capture", &file_arg], args);
        self.captures.push(file);
        o
    }

    /// [`Tool::run`], expected to succeed: its standard output.
    fn ok(&mut self, args: &[&str]) -> String {
        let o = self.run(args);
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(
            o.status.success(),
            "sdo-tool {args:?}: {:?}\n{out}{}",
            o.status.code(),
            String::from_utf8_lossy(&o.stderr)
        );
        out
    }
}

/// Whether a COB-ID is one a master (the tool, or the test's client) sends here: NMT, RPDOs
/// (CiA 301's pre-defined connection set), SDO requests, LSS requests. SYNC is the node's: it is
/// made the producer.
fn from_master(cob: u64) -> bool {
    matches!(
        cob,
        0x000 | 0x200..=0x27F | 0x300..=0x37F | 0x400..=0x47F | 0x500..=0x57F | 0x600..=0x67F | 0x7E5
    )
}

/// The CANopen session, captured by the node and by each sdo-tool run.
#[test]
fn canopen_sessions_read_clean_in_wireshark() {
    let dir = tempfile::tempdir().unwrap();
    let node_file = dir.path().join("node.pcapng");
    let (mut node, port) = common::node_server(&[
        "--od",
        &format!("{}@5", example("io-device.eds")),
        "--od",
        &format!("{}@6", example("drive.eds")),
        "--od",
        &format!("{}@lss", example("drive.eds")),
        "--heartbeat-ms",
        "200",
        "--capture",
        node_file.to_str().unwrap(),
    ]);
    let bus = common::socketcand_bus(port);
    let mut t = Tool {
        dir: dir.path().to_path_buf(),
        bus,
        captures: Vec::new(),
    };
    session(&mut t, port, dir.path());
    // Stopped as a service manager stops it: the capture is whole.
    let pid = node.0.id().to_string();
    assert!(Command::new("kill")
        .args(["-TERM", &pid])
        .status()
        .unwrap()
        .success());
    node.0.wait().unwrap();

    let names = [
        "can.id",
        "frame.packet_flags_direction",
        "canopen.sdo.cmd",
        "canopen.sdo.abort_code",
        "canopen.nmt_ctrl.cd",
        "canopen.nmt_guard.state",
        "canopen.em.err_code",
        "canopen.lss.cs",
        "canopen.pdo.data.bytes",
        "can.len",
        "_ws.col.Info",
    ];
    for (file, node_side) in t
        .captures
        .iter()
        .map(|f| (f.as_path(), false))
        .chain([(node_file.as_path(), true)])
    {
        tshark::clean(file, CANOPEN);
        let rows = tshark::fields(file, CANOPEN, &names);
        for r in &rows {
            // tshark hands no payload of 0 bytes to CANopen: a SYNC without a counter is `can`.
            let layers = if r[10] == "0" { "can" } else { "can:canopen" };
            assert_eq!(r[0], layers, "{}: {r:?}", file.display());
            let (cob, direction) = (number(&r[1]), number(&r[2]));
            // epb_flags: 2 outbound, 1 inbound. The tool sends what a master sends; the node
            // receives it and sends the rest.
            let outbound = from_master(cob) != node_side;
            assert_eq!(
                direction,
                if outbound { 2 } else { 1 },
                "{}: {r:?}",
                file.display()
            );
        }
    }
    services(&node_file, &names);
    // decode names the same session from the node's capture.
    let o = common::sdo_tool(&[], &["decode", node_file.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for says in [
        "node 5: SDO read 0x1018:01 = BC 0A 00 00",
        "block transfer",
        "0x06010002",
        "node 6: EMCY 0x8612",
        "NMT start: node 5",
    ] {
        assert!(text.contains(says), "{says:?} in\n{text}");
    }
}

/// The sdo-tool runs of the session against the nodes on `port`; files in `dir`.
fn session(t: &mut Tool, port: u16, dir: &Path) {
    // SDO: expedited upload and download, segmented download and upload, block download and
    // upload, an abort.
    assert_eq!(t.ok(&["read", "5", "0x1018:01", "x32"]), "0x00000ABC\n");
    t.ok(&["write", "5", "0x1017", "u16", "200"]);
    let label = "A label longer than four bytes";
    t.ok(&["--no-block", "write", "5", "0x2001", "vs", label]);
    assert_eq!(
        t.ok(&["--no-block", "read", "5", "0x2001", "vs"]),
        format!("\"{label}\"\n")
    );
    let program: Vec<u8> = (0..1000u32).map(|k| (k * 7 % 251) as u8).collect();
    let (src, back) = (dir.join("program.bin"), dir.join("back.bin"));
    std::fs::write(&src, &program).unwrap();
    t.ok(&["download", "5", "0x2000:01", src.to_str().unwrap()]);
    t.ok(&["upload", "5", "0x2000:01", back.to_str().unwrap()]);
    assert_eq!(std::fs::read(&back).unwrap(), program);
    let o = t.run(&["write", "5", "0x1018:01", "u32", "1"]);
    assert_eq!(o.status.code(), Some(1));
    // SYNC every 20 ms from node 5 (0x1006, then 0x1005 bit 30), node 5 operational: its TPDO 2
    // (0x285, transmission type 1) at each SYNC; its RPDOs 1 (0x205) and 2 (0x305) from here.
    t.ok(&["write", "5", "0x1006", "u32", "20000"]);
    t.ok(&["write", "5", "0x1005", "x32", "0x40000080"]);
    t.ok(&["nmt", "start", "5"]);
    {
        use socketcan_node::transport::{CanBus, SocketcandClient};
        use socketcan_node::CanFrame;
        let mut client = SocketcandClient::connect("127.0.0.1", port, "can0").unwrap();
        client
            .send(&CanFrame::new(0x205, &[0x0F, 0xF0]).unwrap())
            .unwrap();
        client
            .send(&CanFrame::new(0x305, &[0x34, 0x12, 0x78, 0x56]).unwrap())
            .unwrap();
    }
    t.ok(&["watch", "--duration-ms", "300"]);
    t.ok(&["write", "5", "0x1005", "x32", "0x00000080"]);
    // NMT commands; heartbeats show each state (stopped for two of node 5's periods).
    t.ok(&["nmt", "stop", "5"]);
    t.ok(&["watch", "5", "--duration-ms", "450"]);
    t.ok(&["nmt", "preop", "all"]);
    t.ok(&["nmt", "reset-comm", "5"]);
    // EMCY: the drive at node 6 runs into its positive limit switch (0x8612), then is enabled
    // again (the error cleared: EMCY 0x0000).
    t.ok(&["write", "6", "0x5FF0:4", "i32", "100"]);
    t.ok(&["drive", "6", "enable"]);
    assert_eq!(
        t.run(&["drive", "6", "move", "1000"]).status.code(),
        Some(1)
    );
    t.ok(&["drive", "6", "enable"]);
    // LSS: identify, Fastscan, configure node-ID 20 by address, back to waiting.
    assert_eq!(
        t.ok(&["lss", "identify"]),
        "yes: a node without a node-ID answered\n"
    );
    let address = t.ok(&["lss", "scan"]).trim().to_string();
    assert_eq!(
        t.ok(&["lss", "set-id", &address, "20"]),
        format!("{address} node-ID 20\n")
    );
    t.ok(&["lss", "switch", "waiting"]);
    t.ok(&["read", "20", "0x1018:04", "u32"]);
}

/// The services of the session in the node's capture `node_file`, as tshark dissects them with
/// the fields `names`.
fn services(node_file: &Path, names: &[&str]) {
    let rows = tshark::fields(node_file, CANOPEN, names);
    let cobs = values(&rows, 1);
    // The SDO commands of every kind (CiA 301 §7.2.4.3): initiate upload 0x40, expedited download
    // of 2 bytes 0x2B, initiate segmented download 0x21, upload segment 0x60, the abort 0x80 with
    // its code 0x06010002; and as tshark names them, the block transfers too (it gives their
    // initiate frames no command byte).
    let sdo = values(&rows, 3);
    for cmd in [0x40, 0x2B, 0x21, 0x60, 0x80] {
        assert!(sdo.contains(&cmd), "SDO command 0x{cmd:02X} in {sdo:02X?}");
    }
    assert!(values(&rows, 4).contains(&0x0601_0002));
    for service in [
        "Default-SDO (rx): Initiate upload request",
        "Default-SDO (tx): Initiate upload response",
        "Default-SDO (rx): Initiate download request",
        "Default-SDO (tx): Initiate download response",
        "Default-SDO (rx): Download segment request",
        "Default-SDO (rx): Upload segment request",
        "Default-SDO (rx): Block download",
        "Default-SDO (tx): Block download",
        "Default-SDO (rx): Block upload",
        "Default-SDO (tx): Block upload",
        "Default-SDO (tx): Abort transfer",
    ] {
        assert!(rows.iter().any(|r| r[11] == service), "{service:?}");
    }
    // NMT start 1, stop 2, pre-operational 0x80, reset communication 0x82; heartbeats in
    // operational 5, stopped 4, pre-operational 0x7F, and boot-ups 0.
    let nmt = values(&rows, 5);
    for cs in [0x01, 0x02, 0x80, 0x82] {
        assert!(nmt.contains(&cs), "NMT 0x{cs:02X} in {nmt:02X?}");
    }
    let states = values(&rows, 6);
    for state in [0x00, 0x04, 0x05, 0x7F] {
        assert!(
            states.contains(&state),
            "heartbeat 0x{state:02X} in {states:02X?}"
        );
    }
    // EMCY 0x8612 (reference limit) and its clearing 0x0000.
    let emcy = values(&rows, 7);
    assert!(emcy.contains(&0x8612) && emcy.contains(&0), "{emcy:04X?}");
    // LSS: switch global 4, selective 0x40–0x44, configure node-ID 0x11, identify remote 0x46–0x4B,
    // identify non-configured 0x4C, Fastscan 0x51.
    let lss = values(&rows, 8);
    for cs in [0x04, 0x40, 0x44, 0x11, 0x4C, 0x51] {
        assert!(lss.contains(&cs), "LSS 0x{cs:02X} in {lss:02X?}");
    }
    // SYNC, TPDO 2 and the two RPDOs, their data dissected.
    assert!(cobs.iter().filter(|&&c| c == 0x080).count() >= 5, "SYNCs");
    for cob in [0x205, 0x285, 0x305] {
        let pdo: Vec<_> = rows.iter().filter(|r| number(&r[1]) == cob).collect();
        assert!(
            !pdo.is_empty() && pdo.iter().all(|r| !r[9].is_empty()),
            "PDO 0x{cob:03X}"
        );
    }
}

/// `sdo-tool --ethercat` against the example drive on `ethercat-node`, both capturing: a read, an
/// abort and the dictionary by SDO Information. Every frame is EtherCAT to Wireshark, the CoE ones
/// with their SDO and SDO Information fields; nothing malformed, no expert error.
#[test]
fn ethercat_sessions_read_clean_in_wireshark() {
    let dir = tempfile::tempdir().unwrap();
    let node_file = dir.path().join("node.pcapng");
    let mut link = testkit::link::Link::node(&[
        "--esi",
        "examples/drive.esi.xml",
        "--capture",
        node_file.to_str().unwrap(),
    ]);
    let mut captures = Vec::new();
    let mut tool = |args: &[&str]| {
        let file = dir.path().join(format!("tool-{}.pcapng", captures.len()));
        let o = common::sdo_tool(
            &[
                "--ethercat",
                &link.master,
                "--capture",
                file.to_str().unwrap(),
            ],
            args,
        );
        captures.push(file);
        o
    };
    let o = tool(&["read", "1", "0x1008", "vs"]);
    assert_eq!(String::from_utf8_lossy(&o.stdout), "\"drive\"\n");
    assert_eq!(
        tool(&["write", "1", "0x1008", "vs", "x"]).status.code(),
        Some(1)
    );
    let o = tool(&["sdos", "1"]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("SDO 0x6040, VAR"));
    link.stop();
    let names = [
        "frame.packet_flags_direction",
        "ecat_mailbox.coe.sdoidx",
        "ecat_mailbox.coe.abortcode",
        "ecat_mailbox.coe.sdoinfoopcode",
        "ecat_mailbox.coe.sdoinfoindex",
    ];
    let mut all = Vec::new();
    for file in captures.iter().chain([&node_file]) {
        tshark::clean(file, &[]);
        let rows = tshark::fields(file, &[], &names);
        for r in &rows {
            assert!(
                r[0].starts_with("eth:ethertype:ecatf:ecat"),
                "{}: {r:?}",
                file.display()
            );
            assert!(matches!(number(&r[1]), 1 | 2), "{}: {r:?}", file.display());
        }
        all.push(rows);
    }
    let node_rows = all.pop().unwrap();
    // What the tool's captures hold in both directions, the node's capture holds the other way
    // round: as many frames.
    let tool_frames: usize = all.iter().map(Vec::len).sum();
    assert_eq!(node_rows.len(), tool_frames);
    let mailbox = |rows: &[Vec<String>]| rows.iter().any(|r| r[0].ends_with(":ecat_mailbox"));
    assert!(all.iter().all(|rows| mailbox(rows)));
    assert!(values(&all[0], 2).contains(&0x1008));
    assert!(values(&all[1], 3).contains(&0x0601_0002));
    // SDO Information: get OD list (1) and its response (2), get object description (3) and its
    // response (4), get entry description (5) and its response (6), of 0x6040 among others.
    let opcodes = values(&all[2], 4);
    for op in 1..=6 {
        assert!(
            opcodes.contains(&op),
            "SDO Information opcode {op} in {opcodes:?}"
        );
    }
    assert!(values(&node_rows, 5).contains(&0x6040));
}

/// IgH's commands and FoE with `--capture`, against the FoE example device on `ethercat-node`:
/// `slaves`, `reg-read` and `sii-read` look at the chain one datagram at a time with the probe's
/// frame indexes (0xE5 on); `foe-write` and `foe-read` of a file of 300 bytes go as FoE Write and
/// Read requests, three Data packets of 116, 116 and 68 bytes (a 128-byte mailbox less its 6-byte
/// header and FoE's 6) numbered 1 to 3, each acknowledged with its number. Wireshark finds nothing
/// malformed and no expert error in any of them.
#[test]
fn igh_commands_and_foe_read_clean_in_wireshark() {
    let dir = tempfile::tempdir().unwrap();
    let mut link = testkit::link::Link::node(&["--esi", &example("foe-device.esi.xml")]);
    let file = dir.path().join("notes.txt");
    let data: Vec<u8> = (0..300u32).map(|k| (k % 251) as u8).collect();
    std::fs::write(&file, &data).unwrap();
    let back = dir.path().join("back.txt");
    let sii = dir.path().join("unit.sii");
    let runs: [&[&str]; 5] = [
        &["slaves"],
        &["reg-read", "1", "0x0130", "2"],
        &["sii-read", "1", "-o", sii.to_str().unwrap()],
        &["foe-write", file.to_str().unwrap()],
        &["foe-read", "notes.txt", "-o", back.to_str().unwrap()],
    ];
    let mut captures = Vec::new();
    for (k, args) in runs.iter().enumerate() {
        let capture = dir.path().join(format!("{k}.pcapng"));
        let o = common::sdo_tool(
            &[
                "--ethercat",
                &link.master,
                "--capture",
                capture.to_str().unwrap(),
            ],
            args,
        );
        assert_eq!(
            o.status.code(),
            Some(0),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        captures.push(capture);
    }
    link.stop();
    assert_eq!(std::fs::read(&back).unwrap(), data);
    let names = [
        "frame.packet_flags_direction",
        "ecat.idx",
        "ecat.cmd",
        "ecat.ado",
        "ecat_mailbox.foe_opmode",
        "ecat_mailbox.foe_packetno",
        "ecat_mailbox.foe_filename",
    ];
    let mut rows = Vec::new();
    for file in &captures {
        tshark::clean(file, &[]);
        let r = tshark::fields(file, &[], &names);
        assert!(!r.is_empty(), "{}", file.display());
        for row in &r {
            assert!(
                row[0].starts_with("eth:ethertype:ecatf:ecat"),
                "{}: {row:?}",
                file.display()
            );
        }
        rows.push(r);
    }
    // The looks at the chain: the probe's indexes only, sent and answered.
    for r in &rows[..3] {
        let indexes = values(r, 2);
        assert!(
            indexes.iter().all(|i| (0xE5..=0xE7).contains(i)),
            "{indexes:?}"
        );
        let directions = values(r, 1);
        assert!(
            directions.contains(&1) && directions.contains(&2),
            "{directions:?}"
        );
    }
    // reg-read: an APRD (1) of 0x0130 among them, out and back.
    let aprd_0130 = rows[1]
        .iter()
        .filter(|r| number(&r[3]) == 1 && number(&r[4]) == 0x0130)
        .count();
    assert_eq!(aprd_0130, 2, "{:?}", rows[1]);
    // FoE: opmode and packet number of every FoE mailbox, in order, inbound to the slave (sent by
    // the tool) or outbound from it.
    let foe =
        |r: &[Vec<String>]| -> Vec<(u64, u64, u64)> {
            r.iter()
                .filter(|row| !row[5].is_empty())
                .map(|row| {
                    let packet = row[6].split(',').next().map_or(0, |p| {
                        if p.is_empty() {
                            0
                        } else {
                            number(p)
                        }
                    });
                    (number(&row[1]), number(&row[5]), packet)
                })
                .collect()
        };
    let write = foe(&rows[3]);
    let read = foe(&rows[4]);
    let opmodes = |f: &[(u64, u64, u64)], dir: u64| -> Vec<(u64, u64)> {
        let mut v: Vec<(u64, u64)> = f
            .iter()
            .filter(|(d, _, _)| *d == dir)
            .map(|&(_, op, p)| (op, p))
            .collect();
        v.dedup();
        v
    };
    // The tool's frames go out (2) and come back (1) through the chain: each FoE mailbox the tool
    // writes is seen going out; the slave's answers come back in reads of its mailbox.
    assert_eq!(
        opmodes(&write, 2)
            .into_iter()
            .filter(|(op, _)| *op != 4)
            .collect::<Vec<_>>(),
        vec![(2, 0), (3, 1), (3, 2), (3, 3)],
        "{write:?}"
    );
    assert!(opmodes(&write, 1).contains(&(4, 3)), "{write:?}");
    assert_eq!(opmodes(&read, 2)[0], (1, 0), "{read:?}");
    let data_in: Vec<u64> = opmodes(&read, 1)
        .into_iter()
        .filter(|(op, _)| *op == 3)
        .map(|(_, p)| p)
        .collect();
    assert_eq!(data_in, vec![1, 2, 3], "{read:?}");
    let file_names: Vec<&str> = rows[3]
        .iter()
        .chain(&rows[4])
        .map(|r| r[7].as_str())
        .filter(|n| !n.is_empty())
        .collect();
    assert!(
        file_names.iter().all(|n| *n == "notes.txt"),
        "{file_names:?}"
    );
    assert!(!file_names.is_empty());
}
