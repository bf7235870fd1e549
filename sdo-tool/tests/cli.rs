//! `sdo-tool` against the virtual X67 node: in process (the library's runtime on an in-process bus)
//! and as a binary over socketcand on 127.0.0.1.

mod common;

use std::path::Path;
use std::process::{Command, Stdio};

use clap::Parser;
use sdo_tool::cli::{run, Args};
use sdo_tool::{ToolError, UsageError};
use socketcan_node::node::NodeConfig;
use socketcan_node::test_util::RunningNode;
use socketcan_node::transport::{CanBus, InProcessBus};

const ID: u8 = 5;

fn eds() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures/x67/X67SM2436.eds")
        .display()
        .to_string()
}

/// Node 5 running on an in-process bus; stopped when dropped.
struct Running {
    _node: RunningNode,
    bus: InProcessBus,
}

impl Running {
    fn start() -> Running {
        let bus = InProcessBus::new();
        let node = RunningNode::start(NodeConfig::new(ID), bus.endpoint());
        std::thread::sleep(std::time::Duration::from_millis(50));
        Running { _node: node, bus }
    }

    /// Runs `sdo-tool ARGS…` in process: the output, or the error.
    fn tool(&self, argv: &[&str]) -> Result<String, ToolError> {
        let args = Args::try_parse_from(std::iter::once("sdo-tool").chain(argv.iter().copied()))
            .map_err(|e| ToolError::Usage(UsageError::CommandLine(e.to_string())))?;
        let bus: Box<dyn CanBus> = Box::new(self.bus.endpoint());
        let mut out = Vec::new();
        run(&args, Some(bus), &mut out)?;
        Ok(String::from_utf8(out).unwrap())
    }

    /// What the tool printed, and its error if it failed.
    fn tool_output(&self, argv: &[&str]) -> (String, Option<ToolError>) {
        let args =
            Args::try_parse_from(std::iter::once("sdo-tool").chain(argv.iter().copied())).unwrap();
        let bus: Box<dyn CanBus> = Box::new(self.bus.endpoint());
        let mut out = Vec::new();
        let e = run(&args, Some(bus), &mut out).err();
        (String::from_utf8(out).unwrap(), e)
    }
}

#[test]
fn read_with_cia_309_3_types() {
    let n = Running::start();
    assert_eq!(n.tool(&["read", "5", "0x1018:00", "u8"]).unwrap(), "4\n");
    assert_eq!(n.tool(&["read", "5", "1018sub0", "x8"]).unwrap(), "0x04\n");
    assert_eq!(
        n.tool(&["read", "5", "0x1000", "x32"]).unwrap(),
        "0x00000000\n"
    );
    // A segmented upload of a VISIBLE_STRING, in block mode and without.
    assert_eq!(
        n.tool(&["read", "5", "0x1008:00", "vs"]).unwrap(),
        "\"X67BC4321-10 / X67SM2436\"\n"
    );
    assert_eq!(
        n.tool(&["--no-block", "read", "5", "0x1008:00", "vs"])
            .unwrap(),
        "\"X67BC4321-10 / X67SM2436\"\n"
    );
}

#[test]
fn names_and_types_from_the_description() {
    let n = Running::start();
    let od = eds();
    assert_eq!(
        n.tool(&["--od", &od, "write", "5", "ConfigOutput03a", "20"])
            .unwrap(),
        "OK\n"
    );
    assert_eq!(
        n.tool(&["--od", &od, "read", "5", "ConfigOutput03aRead"])
            .unwrap(),
        "20\n"
    );
    // The description's limit refuses 168 before anything is sent.
    let e = n
        .tool(&["--od", &od, "write", "5", "ConfigOutput03a", "168"])
        .unwrap_err();
    assert_eq!(e.exit_code(), 2);
    assert!(e.to_string().contains("(not sent)"), "{e}");
    assert_eq!(
        n.tool(&["--od", &od, "read", "5", "ConfigOutput03aRead"])
            .unwrap(),
        "20\n"
    );
}

#[test]
fn aborts_are_named_with_code_and_meaning() {
    let n = Running::start();
    // Without --od the write reaches the node, which refuses it.
    let e = n
        .tool(&["write", "5", "0x2110:00", "u8", "168"])
        .unwrap_err();
    assert_eq!(e.exit_code(), 1);
    assert_eq!(
        e.to_string(),
        "0x2110:00: SDO abort 0x06090031 (Value of parameter written too high (download only))"
    );
    let e = n.tool(&["read", "5", "0x7777:00", "u8"]).unwrap_err();
    assert_eq!(e.exit_code(), 1);
    assert!(e.to_string().contains("0x06020000"), "{e}");
}

#[test]
fn timeouts_and_usage_errors() {
    let n = Running::start();
    let e = n
        .tool(&["--timeout-ms", "50", "read", "9", "0x1000", "u32"])
        .unwrap_err();
    assert_eq!(e.exit_code(), 3);
    assert_eq!(
        e.to_string(),
        "0x1000:00: no answer from node 9 within 50 ms"
    );
    for (argv, says) in [
        (&["read", "5", "0x1000", "u33"][..], "not a CiA 309-3 type"),
        (&["read", "5", "ConfigOutput03a"], "names need --od"),
        (&["read", "5", "0x1000"], "give the type"),
        (&["write", "5", "0x1017:00", "u16", "70000"], "70000"),
        (&["nmt", "go", "5"], "is not start, stop"),
        (&["nmt", "start", "128"], "not 1 to 127 or all"),
    ] {
        let e = n.tool(argv).unwrap_err();
        assert_eq!(e.exit_code(), 2, "{argv:?}: {e}");
        assert!(e.to_string().contains(says), "{argv:?}: {e}");
    }
}

#[test]
fn nmt_commands_reach_the_node() {
    let n = Running::start();
    let mut watch = n.bus.endpoint();
    n.tool(&["write", "5", "0x1017:00", "u16", "20"]).unwrap();
    n.tool(&["nmt", "start", "5"]).unwrap();
    let heartbeat = |w: &mut dyn CanBus| loop {
        if let Some(socketcan_node::BusEvent::Frame { frame, .. }) =
            w.recv(std::time::Duration::from_secs(2)).unwrap()
        {
            if frame.cob_id() == Some(0x705) {
                return frame.data()[0];
            }
        } else {
            panic!("no heartbeat");
        }
    };
    let mut state = heartbeat(&mut watch);
    for _ in 0..5 {
        state = heartbeat(&mut watch);
    }
    assert_eq!(state, 0x05, "Operational");
    n.tool(&["nmt", "preop", "all"]).unwrap();
    for _ in 0..5 {
        state = heartbeat(&mut watch);
    }
    assert_eq!(state, 0x7F);
}

/// `x67-node` as node `id` and socketcand server on a free port of 127.0.0.1, once it listens.
fn hub(id: u8) -> (std::process::Child, u16) {
    hub_with(id, &[])
}

/// [`hub`] with `extra` arguments for `x67-node`.
fn hub_with(id: u8, extra: &[&str]) -> (std::process::Child, u16) {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let (child, _) = testkit::start_until_first_line(
        Command::new(testkit::cargo_binary("socketcan-node", "x67-node", &[]))
            .args(["--bus", &format!("socketcand-listen:127.0.0.1:{port}")])
            .args(["--node-id", &id.to_string()])
            .args(extra),
    );
    (child, port)
}

/// `x67-node --modules 2 --write-description FILE.eds` names module 2's registers (`AbsPos01_M2` at
/// 0x2400), and `sdo-tool --od FILE` reaches them by name on the node running with 2 modules; module
/// 1's register of the same kind is untouched.
#[test]
fn the_written_description_names_module_2_for_od() {
    let dir = tempfile::tempdir().unwrap();
    let eds = dir.path().join("node.eds");
    let eds = eds.to_str().unwrap();
    let out = Command::new(testkit::cargo_binary("socketcan-node", "x67-node", &[]))
        .args(["--modules", "2", "--write-description", eds])
        .output()
        .unwrap();
    assert!(out.status.success());
    // 93 objects of the bus controller and module 1; for module 2 its 71 registers, its simulation
    // inputs and the communication and mapping objects of its 2 RPDOs and 2 TPDOs (8).
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        format!(
            "x67-node: wrote {eds} (EDS: X67BC4321-10 with 2 X67SM2436 modules, 173 objects)\n"
        )
    );
    let (mut node, port) = hub_with(3, &["--modules", "2"]);
    let bus = format!("socketcand://127.0.0.1:{port}/can0");
    let named = ["--bus", bus.as_str(), "--od", eds];
    assert_eq!(
        common::sdo_tool_ok(&named, &["write", "3", "AbsPos01_M2", "-1234"]),
        "OK\n"
    );
    assert_eq!(
        common::sdo_tool_ok(&named, &["read", "3", "AbsPos01_M2"]),
        "-1234\n"
    );
    let plain = ["--bus", bus.as_str()];
    assert_eq!(
        common::sdo_tool_ok(&plain, &["read", "3", "0x2400:00", "i32"]),
        "-1234\n"
    );
    assert_eq!(
        common::sdo_tool_ok(&named, &["read", "3", "AbsPos01"]),
        "0\n"
    );
    node.kill().unwrap();
    node.wait().unwrap();
}

/// A description of another device (`--od` of the SMD23K-B against the X67 node) is warned about on
/// stderr, naming both identities; the command still runs. The node's own description: no warning.
#[test]
fn a_description_of_another_device_is_warned_about() {
    let (mut node, port) = hub(3);
    let bus = format!("socketcand://127.0.0.1:{port}/can0");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let run = |od: &str| {
        Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
            .args(["--bus", &bus, "--od"])
            .arg(root.join(od))
            .args(["read", "3", "0x1017:00", "u16"])
            .output()
            .unwrap()
    };
    let out = run("fixtures/smd/SMD23K-B.eds");
    assert!(out.status.success());
    assert_eq!(String::from_utf8_lossy(&out.stdout), "0\n");
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "sdo-tool: warning: the description (--od) is of vendor 0x00000AC1, product 0x00002301 \
         (SMD23K-B Integrated Stepper Indexer/Driver/Motor (EtherCAT)); node 3 reports vendor \
         0x00000B2E, product 0x00002436\n"
    );
    let out = run("fixtures/x67/X67SM2436.eds");
    assert!(out.status.success());
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
    node.kill().unwrap();
    node.wait().unwrap();
}

/// A name the description does not have is refused (exit 2, with the names close to it) before the
/// bus is opened: here a bus nobody listens on, which would otherwise be the error (exit 3).
#[test]
fn names_are_resolved_before_the_bus_is_opened() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let out = Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(["--bus", "socketcand://127.0.0.1:1/can0", "--od"])
        .arg(root.join("fixtures/x67/X67SM2436.eds"))
        .args(["read", "1", "InputStatu"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "sdo-tool: object \"InputStatu\": no object or sub-object is named `InputStatu`; did you \
         mean `InputStatus`?\n"
    );
}

/// `CANOPEN_BUS` is the bus when `--bus` is not given; `--bus` wins over it.
#[test]
fn canopen_bus_is_the_default_bus() {
    let (mut node, port) = hub(3);
    let run = |extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
            .env("CANOPEN_BUS", format!("socketcand://127.0.0.1:{port}/can0"))
            .args(extra)
            .args(["read", "3", "0x1008:00", "vs"])
            .output()
            .unwrap()
    };
    let out = run(&[]);
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "\"X67BC4321-10 / X67SM2436\"\n"
    );
    let out = run(&["--bus", "socketcand://127.0.0.1:1/can0"]);
    assert_eq!(out.status.code(), Some(3), "the --bus given is used");
    node.kill().unwrap();
    node.wait().unwrap();
}

/// The binary over socketcand: `x67-node` on a free port, `sdo-tool --bus socketcand://…`.
#[test]
fn binary_over_socketcand() {
    let (mut node, port) = hub(3);
    let bus = format!("socketcand://127.0.0.1:{port}/can0");
    let tool = |argv: &[&str]| common::sdo_tool(&["--bus", &bus], argv);
    assert_eq!(
        common::sdo_tool_ok(&["--bus", &bus], &["read", "3", "0x1008:00", "vs"]),
        "\"X67BC4321-10 / X67SM2436\"\n"
    );
    let out = tool(&["write", "3", "0x2110:00", "u8", "168"]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "sdo-tool: 0x2110:00: SDO abort 0x06090031 (Value of parameter written too high (download only))\n"
    );
    let out = tool(&["read", "3", "0x1000"]);
    assert_eq!(out.status.code(), Some(2));
    // The gateway on standard input and output.
    let mut gw = Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(["--bus", &bus, "gateway"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    std::io::Write::write_all(
        gw.stdin.as_mut().unwrap(),
        b"[1] 3 r 0x1018 0 u8\n# nothing\n[2] 3 w 0x2110 0 u8 168\n",
    )
    .unwrap();
    drop(gw.stdin.take());
    let out = gw.wait_with_output().unwrap();
    assert!(out.status.success());
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "[1] 4\n[2] ERROR:0x06090031 #Value of parameter written too high (download only)\n"
    );
    node.kill().unwrap();
    node.wait().unwrap();
}

#[test]
fn save_restore_upload_download() {
    let n = Running::start();
    assert_eq!(n.tool(&["save", "5"]).unwrap(), "OK\n");
    assert_eq!(n.tool(&["read", "5", "0x1010:01", "u32"]).unwrap(), "1\n");
    assert_eq!(n.tool(&["restore", "5"]).unwrap(), "OK\n");
    let dir = tempfile::tempdir().unwrap();
    let name = dir.path().join("name.bin");
    let out = n
        .tool(&["upload", "5", "0x1008:00", name.to_str().unwrap()])
        .unwrap();
    assert!(out.starts_with("24 bytes in "), "{out}");
    assert_eq!(std::fs::read(&name).unwrap(), b"X67BC4321-10 / X67SM2436");
    let hb = dir.path().join("hb.bin");
    std::fs::write(&hb, 250u16.to_le_bytes()).unwrap();
    let out = n
        .tool(&["download", "5", "0x1017:00", hb.to_str().unwrap()])
        .unwrap();
    assert!(out.starts_with("2 bytes in "), "{out}");
    assert_eq!(n.tool(&["read", "5", "0x1017:00", "u16"]).unwrap(), "250\n");
    // A file of the wrong length for the object: the node's abort.
    std::fs::write(&hb, [1u8, 2, 3]).unwrap();
    let e = n
        .tool(&["download", "5", "0x1017:00", hb.to_str().unwrap()])
        .unwrap_err();
    assert_eq!(e.exit_code(), 1, "{e}");
    // A FIFO or a device is not a file to download: refused before it is opened.
    let fifo = dir.path().join("fifo");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    for file in [fifo.to_str().unwrap(), "/dev/zero"] {
        let e = n.tool(&["download", "5", "0x1017:00", file]).unwrap_err();
        assert_eq!(e.exit_code(), 2, "{e}");
        assert_eq!(e.to_string(), format!("{file}: not a regular file"));
    }
}

#[test]
fn scan_finds_the_node_and_its_identity() {
    let n = Running::start();
    let out = n.tool(&["scan", "--wait-ms", "200"]).unwrap();
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out}");
    assert!(lines[1].starts_with("   5  0x00000000"), "{out}");
    assert!(lines[1].ends_with("\"X67BC4321-10 / X67SM2436\""), "{out}");
    assert_eq!(lines[2], "1 node(s)");
}

/// The CiA 309-3 gateway: a script of requests with the exact replies.
#[test]
fn gateway_script_with_exact_replies() {
    use sdo_tool::gateway::Gateway;
    use sdo_tool::Tool;
    let n = Running::start();
    let mut tool = Tool::new(Box::new(n.bus.endpoint()), None);
    tool.set_timeout(std::time::Duration::from_millis(100));
    let mut gw = Gateway::new(tool);
    for (request, reply) in [
        ("# a comment", None),
        ("", None),
        ("[1] 5 read 0x1018 0 u8", Some("[1] 4")),
        (
            "[2] r 0x1018 0 u8",
            Some("[2] ERROR:105 #No default node set"),
        ),
        ("[3] set node 5", Some("[3] OK")),
        ("[4] r 0x1018 0 x8", Some("[4] 0x04")),
        (
            "[5] r 0x1008 0 vs",
            Some("[5] \"X67BC4321-10 / X67SM2436\""),
        ),
        ("[6] w 0x1017 0 u16 300", Some("[6] OK")),
        ("[7] 1 5 r 0x1017 0 u16", Some("[7] 300")),
        (
            "[8] w 0x2110 0 u8 168",
            Some("[8] ERROR:0x06090031 #Value of parameter written too high (download only)"),
        ),
        (
            "[9] r 0x7777 0 u8",
            Some("[9] ERROR:0x06020000 #Object does not exist in the object dictionary"),
        ),
        ("[10] 9 r 0x1000 0 u32", Some("[10] ERROR:103 #Time-out")),
        (
            "[11] 2 5 r 0x1000 0 u32",
            Some("[11] ERROR:106 #Unsupported net"),
        ),
        (
            "[12] 200 r 0x1000 0 u32",
            Some("[12] ERROR:107 #Unsupported node"),
        ),
        ("[13] fly", Some("[13] ERROR:100 #Request not supported")),
        ("[14] r 0x1000", Some("[14] ERROR:101 #Syntax error")),
        ("[x] r 0x1000 0 u32", Some("ERROR:101 #Syntax error")),
        ("[15] start", Some("[15] OK")),
        ("[16] reset comm", Some("[16] OK")),
        ("[17] set sdo_block 0", Some("[17] OK")),
        (
            "[18] r 0x1008 0 vs # segmented now",
            Some("[18] \"X67BC4321-10 / X67SM2436\""),
        ),
        ("r 0x1018 0 u8", Some("4")),
    ] {
        assert_eq!(gw.handle(request).as_deref(), reply, "{request}");
    }
}

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
            "39 write-only parameters cannot be read back and are not in the file: \
             0x2010:00 (GeneralConfig01), 0x2110:00 (ConfigOutput03a), "
        ),
        "{out}"
    );
    assert_eq!(
        lines[1],
        format!(
            "37 entries written to {}; left out: 13 command objects, 6 cyclic outputs, \
             39 not writable, 39 write-only",
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
        (0x2110, 0, "ConfigOutput03a (write-only)"),
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
            "wrote 0x1400:01 = 2147484165 (the PDO made invalid while it changes)",
            "wrote 0x1400:02 = 255",
            "wrote 0x1600:00 = 0 (the count 0 while the entries change)",
            "wrote 0x1600:01 = 553648160",
            "wrote 0x1600:02 = 553713680",
            "wrote 0x1600:03 = 553779208",
            "wrote 0x1600:04 = 327688",
            "wrote 0x1600:00 = 4",
            "wrote 0x1400:01 = 517",
        ]
    );
    assert!(lines.contains(&"wrote 0x1017:00 = 300"), "{out}");
    assert_eq!(
        *lines.last().unwrap(),
        "37 entries written, 0 skipped, 0 refused"
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
            "block upload 0x1018:01",
            "block upload 0x1018:02",
            "block upload 0x1005:00",
            "block upload 0x1017:00",
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
        "skipped 0x1005:00 = 129: ObjFlags bit 0: refuse write on download",
        "skipped 0x1015:00 = 10: ObjFlags bit 0: refuse write on download",
        "skipped 0x1016:01 = 327780: ObjFlags bit 0: refuse write on download",
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
            "block upload 0x1006:00",
            "download 0x1017:00",
            "block upload 0x1017:00",
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
                 0x1018:01  Vendor-ID = 2862\n\
                 0x1018:02  Product code = 9270\n\
                 0x1018:03  Revision number = 1\n\
                 0x1018:04  Serial number = 0\n";
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
        serde_json::json!({"object": "0x1018:01", "name": "Vendor-ID", "value": 2862, "text": "2862"})
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
            "REFUSED 0x1600:01 = 553713680: 0x1600:01: SDO abort 0x06040043 (General parameter incompatibility reason); nothing after it written"
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
            "skipped 0x1010:01 = 1702257011: store parameters: a command",
            "wrote 0x1017:00 = 1000",
            "REFUSED 0x1600:01 = 553713680: 0x1600:01: SDO abort 0x06040043 (General parameter incompatibility reason)",
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

/// `watch`: heartbeats, the NMT change, a TPDO decoded from the description, an EMCY in words.
#[test]
fn watch_decodes_the_bus() {
    let n = Running::start();
    n.tool(&["write", "5", "0x1017:00", "u16", "100"]).unwrap();
    let mut other = n.bus.endpoint();
    let poke = std::thread::spawn(move || {
        std::thread::sleep(std::time::Duration::from_millis(250));
        other
            .send(&socketcan_node::CanFrame::new(0, &[0x01, 5]).unwrap())
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(250));
        // Module temperature 90 °C through the simulation object: over-temperature, EMCY 0x4200.
        other
            .send(
                &socketcan_node::CanFrame::new(0x605, &[0x2F, 0x00, 0x5F, 3, 90, 0, 0, 0]).unwrap(),
            )
            .unwrap();
    });
    let out = n
        .tool(&["--od", &eds(), "watch", "5", "--duration-ms", "900"])
        .unwrap();
    poke.join().unwrap();
    assert!(out.contains("node 5: heartbeat, pre-operational"), "{out}");
    assert!(
        out.contains("node 5: NMT pre-operational -> operational"),
        "{out}"
    );
    assert!(
        out.contains("node 5: TPDO 1 AbsPos01ActVal=0 MpGenStatus01="),
        "{out}"
    );
    assert!(
        out.contains("node 5: EMCY 0x4200 (temperature, device), error register 0x"),
        "{out}"
    );
}

/// `--json`: one JSON object per result, values typed (numbers as numbers, a string as its text, the
/// text form beside); errors with their exit code and abort.
#[test]
fn json_output() {
    let n = Running::start();
    let json = |argv: &[&str]| -> serde_json::Value {
        serde_json::from_str(&n.tool(argv).unwrap()).unwrap()
    };
    assert_eq!(
        json(&["--json", "read", "5", "0x1018:00", "u8"]),
        serde_json::json!({"node": 5, "object": "0x1018:00", "value": 4, "text": "4"})
    );
    assert_eq!(
        json(&["--json", "read", "5", "0x1018:01", "x32"]),
        serde_json::json!({"node": 5, "object": "0x1018:01", "value": 2862, "text": "0x00000B2E"})
    );
    assert_eq!(
        json(&["--json", "read", "5", "0x1008:00", "vs"]),
        serde_json::json!({"node": 5, "object": "0x1008:00", "value": "X67BC4321-10 / X67SM2436",
            "text": "\"X67BC4321-10 / X67SM2436\""})
    );
    let v: serde_json::Value = serde_json::from_str(
        &n.tool(&["--json", "write", "5", "0x1017:00", "u16", "5"])
            .unwrap(),
    )
    .unwrap();
    assert_eq!(v, serde_json::json!({"ok": true}));
    let v: serde_json::Value =
        serde_json::from_str(&n.tool(&["--json", "scan", "--wait-ms", "150"]).unwrap()).unwrap();
    assert_eq!(
        v["nodes"][0],
        serde_json::json!({"node": 5, "device_type": 0, "vendor": 2862, "product": 0x2436,
            "revision": 1, "serial": 0, "name": "X67BC4321-10 / X67SM2436"})
    );
    let e = n
        .tool(&["--json", "write", "5", "0x2110:00", "u8", "168"])
        .unwrap_err();
    assert_eq!(
        sdo_tool::cli::error_json(&e),
        serde_json::json!({
            "error": "0x2110:00: SDO abort 0x06090031 (Value of parameter written too high (download only))",
            "exit_code": 1,
            "abort": "0x06090031",
        })
    );
}

/// Against python-canopen's `LocalNode`, an SDO server independent of this project, on a socketcand
/// bus that `x67-node` holds: reads (expedited and segmented) and writes arrive as they should.
#[test]
fn against_python_canopen_local_node() {
    let (mut hub, port) = hub(1);
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/python/local_node.py");
    let mut py = Command::new("python3")
        .arg(&script)
        .args(["--eds", &eds(), "--node-id", "10", "--socketcand"])
        .arg(format!("127.0.0.1:{port}"))
        .args(["--seconds", "4"])
        .stdout(Stdio::piped())
        .spawn()
        .expect("python3 with python-canopen");
    let mut py_out = std::io::BufReader::new(py.stdout.take().unwrap());
    let mut ready = String::new();
    std::io::BufRead::read_line(&mut py_out, &mut ready).unwrap();
    assert_eq!(ready.trim(), "READY");
    let bus = format!("socketcand://127.0.0.1:{port}/can0");
    let tool = |argv: &[&str]| {
        let o = common::sdo_tool(&["--bus", &bus, "--no-block"], argv);
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let (code, out, err) = tool(&["read", "10", "0x1018:00", "u8"]);
    assert_eq!((code, out.as_str()), (Some(0), "4\n"), "{err}");
    let (code, out, err) = tool(&["read", "10", "0x1008:00", "vs"]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(out, "\"X67BC4321-10 / X67SM2436\"\n");
    let (code, out, err) = tool(&["write", "10", "0x1017:00", "u16", "1234"]);
    assert_eq!((code, out.as_str()), (Some(0), "OK\n"), "{err}");
    let (code, out, _) = tool(&["read", "10", "0x1017:00", "u16"]);
    assert_eq!((code, out.as_str()), (Some(0), "1234\n"));
    let (code, _, err) = tool(&["read", "10", "0x7777:00", "u8"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("0x06020000"), "{err}");
    let mut written = String::new();
    std::io::Read::read_to_string(&mut py_out, &mut written).unwrap();
    assert!(py.wait().unwrap().success());
    assert!(written.contains("1017:00=D204"), "{written}");
    hub.kill().unwrap();
    hub.wait().unwrap();
}

/// `--ethercat` takes only a name the kernel could give an interface (1 to 15 bytes, no '/', space
/// or NUL): a longer one is a usage error of one line, exit 2, before any socket is opened.
#[test]
fn an_ethercat_interface_name_over_15_bytes_is_refused() {
    for name in ["a234567890123456", "veth/0", "has space", "", ".", ".."] {
        let o = common::sdo_tool(&["--ethercat", name], &["read", "1", "0x1000", "u32"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{name:?}: {err}");
        assert!(err.contains("not an interface name"), "{name:?}: {err}");
    }
    // A NUL cannot reach a command line; the library refuses it.
    assert!(sdo_tool::ethercat::check_interface_name("ve\0th").is_err());
    assert!(sdo_tool::ethercat::check_interface_name("veth0.1").is_ok());
    // 15 bytes is a name (no such interface here: a transport failure, exit 3).
    let o = common::sdo_tool(
        &["--ethercat", "a23456789012345"],
        &["read", "1", "0x1000", "u32"],
    );
    assert_eq!(
        o.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let e = sdo_tool::ethercat::EthercatSession::open(
        &"x".repeat(17),
        std::time::Duration::from_secs(1),
    );
    assert!(
        matches!(
            e,
            Err(sdo_tool::ToolError::Ethercat(
                sdo_tool::ethercat::EthercatError::InterfaceName { .. }
            ))
        ),
        "the library refuses it too"
    );
}

/// The gateway holds no line beyond `MAX_LINE`: a longer one is answered with a syntax error and
/// skipped, the next request is answered as usual (CR LF or LF), and a last line without its newline
/// is a request too.
#[test]
fn the_gateway_takes_lines_of_bounded_length() {
    use sdo_tool::gateway::{serve, Gateway, MAX_LINE};
    use sdo_tool::Tool;
    let n = Running::start();
    let mut tool = Tool::new(Box::new(n.bus.endpoint()), None);
    tool.set_timeout(std::time::Duration::from_millis(100));
    let gw = std::sync::Mutex::new(Gateway::new(tool));
    let mut input = vec![b'x'; 1_000_000];
    input.extend_from_slice(b"\n[1] 5 r 0x1018 0 u8\r\n");
    input.extend(std::iter::repeat_n(b'y', MAX_LINE));
    input.extend_from_slice(b"\n[2] 5 r 0x1018 0 u8");
    let mut out = Vec::new();
    serve(&gw, std::io::Cursor::new(input), &mut out).unwrap();
    assert_eq!(
        String::from_utf8(out).unwrap(),
        "ERROR:101 #Syntax error\n[1] 4\nERROR:100 #Request not supported\n[2] 4\n"
    );
}

/// Over TCP a silent client holds only its own connection: another one is answered at once.
#[test]
fn a_silent_gateway_client_does_not_block_the_others() {
    use std::io::{BufRead, Write};
    let n = Running::start();
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let listen = format!("127.0.0.1:{port}");
    let args = Args::try_parse_from(["sdo-tool", "gateway", "--listen", &listen]).unwrap();
    let bus: Box<dyn CanBus> = Box::new(n.bus.endpoint());
    std::thread::spawn(move || {
        let mut out = Vec::new();
        let _ = run(&args, Some(bus), &mut out);
    });
    let connect = || {
        for _ in 0..100 {
            if let Ok(s) = std::net::TcpStream::connect(("127.0.0.1", port)) {
                return s;
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        panic!("the gateway does not listen");
    };
    let _silent = connect();
    let mut talker = connect();
    talker
        .set_read_timeout(Some(std::time::Duration::from_secs(5)))
        .unwrap();
    talker.write_all(b"[1] 5 r 0x1018 0 u8\n").unwrap();
    let mut reply = String::new();
    std::io::BufReader::new(talker)
        .read_line(&mut reply)
        .unwrap();
    assert_eq!(reply, "[1] 4\n");
}

/// Ctrl-C during an upload: the waiting transfer is aborted on the bus with 0x08000000
/// (`609#80 08 10 00 00 00 00 08`, after the block upload request `609#A4 08 10 00 7F 00 00 00`),
/// long before the 10 s timeout; the partial file is removed and the exit code is 130.
#[test]
fn ctrl_c_in_an_upload_aborts_it_on_the_bus_and_removes_the_partial_file() {
    use socketcan_node::transport::{BusEvent, SocketcandClient};
    use std::time::Duration;
    let (mut node, port) = hub(3);
    let mut watch = SocketcandClient::connect("127.0.0.1", port, "can0").unwrap();
    std::thread::sleep(Duration::from_millis(100));
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("name.bin");
    let tool = Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(["--bus", &format!("socketcand://127.0.0.1:{port}/can0")])
        .args(["--timeout-ms", "10000", "upload", "9", "0x1008"])
        .arg(&file)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Node 9 does not exist: the request waits for an answer that never comes.
    let mut next_609 = || loop {
        match watch.recv(Duration::from_secs(5)).unwrap() {
            Some(BusEvent::Frame { frame, .. }) if frame.cob_id() == Some(0x609) => {
                return frame.data8()
            }
            Some(_) => {}
            None => panic!("no frame on 609 within 5 s"),
        }
    };
    assert_eq!(next_609(), [0xA4, 0x08, 0x10, 0x00, 0x7F, 0, 0, 0]);
    assert!(file.exists(), "the output file is open");
    let sent = std::time::Instant::now();
    let kill = Command::new("kill")
        .args(["-INT", &tool.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    assert_eq!(next_609(), [0x80, 0x08, 0x10, 0x00, 0x00, 0x00, 0x00, 0x08]);
    let out = tool.wait_with_output().unwrap();
    assert!(
        sent.elapsed() < Duration::from_secs(5),
        "ended {:?} after Ctrl-C",
        sent.elapsed()
    );
    assert_eq!(out.status.code(), Some(130));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!(
            "sdo-tool: interrupted: the transfer was aborted with 0x08000000; the partial {} was removed\n",
            file.display()
        )
    );
    assert!(!file.exists());
    node.kill().unwrap();
    node.wait().unwrap();
}

/// A refused value is named with its entry and why, in one form (`ADDR: why (not sent)`), with the
/// type's range or the description's limits; a type without a value is a value left out; nothing is
/// sent for any of them.
#[test]
fn refused_values_say_the_range_they_miss() {
    let n = Running::start();
    let od = eds();
    let before = n.tool(&["read", "5", "0x1017:00", "u16"]).unwrap();
    let refused = |argv: &[&str]| {
        let e = n.tool(argv).unwrap_err();
        assert_eq!(e.exit_code(), 2, "{argv:?}: {e}");
        e.to_string()
    };
    assert_eq!(
        refused(&["write", "5", "0x1017:00", "u16", "70000"]),
        "0x1017:00: 70000 does not fit in UNSIGNED16, 0 to 65535 (not sent)"
    );
    assert_eq!(
        refused(&["write", "5", "0x1017:00", "i8", "-200"]),
        "0x1017:00: -200 does not fit in INTEGER8, -128 to 127 (not sent)"
    );
    assert_eq!(
        refused(&["--od", &od, "write", "5", "0x1017:00", "70000"]),
        "0x1017:00: 70000 does not fit in UNSIGNED16, 0 to 65535 (not sent)"
    );
    assert_eq!(
        refused(&["write", "5", "0x1017:00", "u16", "ten"]),
        "0x1017:00: `ten` is not a UNSIGNED16 value: expected an integer (not sent)"
    );
    // The description's limits of ConfigOutput03a, as `list` shows them.
    assert_eq!(
        refused(&["--od", &od, "write", "5", "ConfigOutput03a", "168"]),
        "0x2110:00: 168 is above the description's limits, 0 to 167 (not sent)"
    );
    // A type where the value should be.
    assert_eq!(
        refused(&["write", "5", "0x1017:00", "u16"]),
        "0x1017:00: the value is missing after the type u16 (write NODE OBJECT [TYPE] VALUE; \
         UNSIGNED16 as TYPE)"
    );
    assert_eq!(
        refused(&["--od", &od, "write", "5", "Producer heartbeat time", "x16"]),
        "0x1017:00: the value is missing after the type x16 (write NODE OBJECT [TYPE] VALUE; \
         UNSIGNED16 as TYPE)"
    );
    // A sub-index by number that the object does not have: said as a sub-index.
    assert!(
        refused(&["--od", &od, "read", "5", "Identity.9"])
            .ends_with("`Identity` (0x1018) has no sub-index 9; its sub-indices: 0 Highest sub-index supported, 1 Vendor-ID, 2 Product code, 3 Revision number, 4 Serial number"),
    );
    assert_eq!(
        n.tool(&["--od", &od, "read", "5", "Identity.2"]).unwrap(),
        "9270\n"
    );
    assert_eq!(n.tool(&["read", "5", "0x1017:00", "u16"]).unwrap(), before);
}
