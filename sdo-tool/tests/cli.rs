//! `sdo-tool` against the virtual X67 node: in process (the library's runtime on an in-process bus)
//! and as a binary over socketcand on 127.0.0.1 — reads, writes, NMT, transfers, the gateway, watch
//! and JSON; the DCF commands are in `cli_dcf.rs`.

mod common;
mod x67;

use std::path::Path;
use std::process::{Command, Stdio};

use clap::Parser;
use sdo_tool::cli::{run, Args};
use socketcan_node::transport::CanBus;
use x67::{eds, hub, hub_with, Running};

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

/// A description of another device (`--od` of an X67SM2437, the X67 description with another
/// product code) is warned about on stderr before a write, naming both identities; the command still
/// runs. The node's own description: no warning. A read does not look at the identity: its only
/// SDO transfer is the read.
#[test]
fn a_description_of_another_device_is_warned_about() {
    let (mut node, port) = hub(3);
    let bus = format!("socketcand://127.0.0.1:{port}/can0");
    let dir = tempfile::tempdir().unwrap();
    let other = dir.path().join("X67SM2437.eds");
    let text = std::fs::read_to_string(eds()).unwrap();
    let text = text
        .replace("ProductNumber=0x00002436", "ProductNumber=0x00002437")
        .replace("ProductName=X67SM2436", "ProductName=X67SM2437");
    std::fs::write(&other, text).unwrap();
    let other = other.to_str().unwrap();
    let run = |od: &str, argv: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
            .args(["--bus", &bus, "--od", od])
            .args(argv)
            .output()
            .unwrap()
    };
    let write = ["write", "3", "ConfigOutput03a", "20"];
    let out = run(other, &write);
    assert!(out.status.success());
    assert_eq!(String::from_utf8_lossy(&out.stdout), "OK\n");
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "sdo-tool: warning: the description (--od) is of vendor 0x00000B2E, product 0x00002437 \
         (X67SM2437); node 3 reports vendor 0x00000B2E, product 0x00002436\n"
    );
    let out = run(&eds(), &write);
    assert!(out.status.success());
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
    let out = run(other, &["read", "3", "ConfigOutput03aRead"]);
    assert_eq!(String::from_utf8_lossy(&out.stdout), "20\n");
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
    // A description of several devices, none of them the node's: the first is used, and said so.
    let esi = |text: String| text[text.find("<EtherCATInfo").unwrap()..].to_string();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let smd = std::fs::read_to_string(root.join("fixtures/smd/SMD23K-B_SMD24K.esi.xml")).unwrap();
    let x67 = std::fs::read_to_string(root.join("fixtures/x67/X67SM2436.esi.xml")).unwrap();
    let x67 = x67.replace("ProductCode=\"#x00002436\"", "ProductCode=\"#x00002437\"");
    let list = dir.path().join("list.xml");
    std::fs::write(
        &list,
        format!(
            "<EtherCATInfoList>\n{}\n{}\n</EtherCATInfoList>\n",
            esi(x67),
            esi(smd)
        ),
    )
    .unwrap();
    let out = run(list.to_str().unwrap(), &write);
    assert!(out.status.success());
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "sdo-tool: warning: none of the 3 devices of the description (--od) is of vendor \
         0x00000B2E, product 0x00002436, which node 3 reports; the first, X67SM2436 (vendor \
         0x00000B2E, product 0x00002437), is used\n"
    );
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
    let port = testkit::free_port();
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
/// (`609#80 08 10 00 00 00 00 08`, after the block upload request `609#A4 08 10 00 7F 40 00 00`:
/// 127 segments a sub-block, a normal upload up to 64 bytes),
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
    assert_eq!(next_609(), [0xA4, 0x08, 0x10, 0x00, 0x7F, 0x40, 0, 0]);
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
        "0x00002436\n"
    );
    assert_eq!(n.tool(&["read", "5", "0x1017:00", "u16"]).unwrap(), before);
}

/// `--capture` on a bus given in process: the interface named as the bus describes itself, the
/// request sent and the answer received, each with its direction; `decode` names the transfer
/// from the capture.
#[test]
fn a_capture_of_a_bus_given_in_process() {
    use link_capture::pcapng::{Direction, Reader};
    let n = Running::start();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("inprocess.pcapng");
    let path = file.to_str().unwrap();
    assert_eq!(
        n.tool(&["--capture", path, "read", "5", "0x1018:01", "x32"])
            .unwrap(),
        "0x00000B2E\n"
    );
    let bytes = std::fs::read(&file).unwrap();
    let mut r = Reader::new(&bytes[..]);
    // The SDO channel's frames (the node's heartbeats aside, received too).
    let mut frames = Vec::new();
    while let Some(p) = r.next_packet().unwrap() {
        if p.data[2..4] != [0x07, 0x05] {
            frames.push((p.direction.unwrap(), p.data.to_vec()));
        }
    }
    #[rustfmt::skip]
    assert_eq!(
        frames,
        [
            (Direction::Outbound, vec![0, 0, 0x06, 0x05, 8, 0, 0, 0, 0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]),
            (Direction::Inbound, vec![0, 0, 0x05, 0x85, 8, 0, 0, 0, 0x43, 0x18, 0x10, 0x01, 0x2E, 0x0B, 0, 0]),
        ]
    );
    let name = r.interfaces_seen()[0].name.clone().unwrap();
    assert!(name.starts_with("in-process endpoint "), "{name}");
    // One SDO line, at the answer's time after the request's (the node's heartbeats aside).
    let decoded = n.tool(&["decode", path]).unwrap();
    let sdo: Vec<&str> = decoded.lines().filter(|l| l.contains("SDO")).collect();
    assert_eq!(sdo.len(), 1, "{decoded}");
    assert!(
        sdo[0].ends_with("  node 5: SDO read 0x1018:01 = 2E 0B 00 00"),
        "{decoded}"
    );
}
