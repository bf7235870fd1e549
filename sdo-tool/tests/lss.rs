//! `sdo-tool lss` against real nodes: `canopen-node` running `examples/drive.eds` three times
//! without a node-ID (`FILE@lss`; serial numbers 1, 2, 3) on a socketcand server of its own on
//! 127.0.0.1. `lss assign 10` finds all three by Fastscan and gives them 10, 11, 12, stored; the
//! nodes restarted with the same storage come up with those node-IDs. `lss scan` lists the same
//! addresses python-canopen's `fast_scan` finds; the single services and the gateway's LSS
//! requests each with its exact reply.

mod common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

/// `canopen-node` with `args` on a socketcand server of its own; killed when dropped.
struct Nodes {
    child: Child,
    port: u16,
    /// What it printed at start.
    lines: Vec<String>,
}

impl Nodes {
    /// Starts the nodes and reads `count` lines of what they print at start (one per node).
    fn start(args: &[String], count: usize) -> Nodes {
        let port = testkit::free_port();
        let mut child = Command::new(testkit::cargo_binary("socketcan-node", "canopen-node", &[]))
            .args(["--bus", &format!("socketcand-listen:127.0.0.1:{port}")])
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut out = BufReader::new(child.stdout.take().unwrap());
        let mut lines = Vec::new();
        for _ in 0..count {
            let mut line = String::new();
            out.read_line(&mut line).unwrap();
            lines.push(line.trim_end().to_string());
        }
        // The server listens once the nodes are announced; wait until it takes connections.
        for _ in 0..100 {
            if std::net::TcpStream::connect(("127.0.0.1", port)).is_ok() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        Nodes { child, port, lines }
    }

    fn bus(&self) -> String {
        format!("socketcand://127.0.0.1:{}/can0", self.port)
    }
}

impl Drop for Nodes {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn drive() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/drive.eds")
}

/// `--od drive.eds@lss` `count` times, with `--storage dir` when given.
fn unconfigured(count: usize, storage: Option<&Path>) -> Vec<String> {
    let mut args = Vec::new();
    if let Some(dir) = storage {
        args.extend(["--storage".to_string(), dir.display().to_string()]);
    }
    for _ in 0..count {
        args.extend(["--od".to_string(), format!("{}@lss", drive().display())]);
    }
    args
}

fn lines(text: &str) -> Vec<&str> {
    text.lines().collect()
}

#[test]
fn lss_assign_gives_three_nodes_node_ids_that_a_restart_keeps() {
    let dir = tempfile::tempdir().unwrap();
    let args = unconfigured(3, Some(dir.path()));
    let nodes = Nodes::start(&args, 3);
    let bus = nodes.bus();
    let out = common::sdo_tool_ok(&["--bus", &bus], &["lss", "assign", "10"]);
    assert_eq!(
        lines(&out),
        [
            "0x00000ABC:0x00000402:0x00010001:0x00000001 node-ID 10 stored",
            "0x00000ABC:0x00000402:0x00010001:0x00000002 node-ID 11 stored",
            "0x00000ABC:0x00000402:0x00010001:0x00000003 node-ID 12 stored",
        ]
    );
    // The node-IDs are the nodes' at once: each answers SDO with its serial number.
    for (node, serial) in [("10", "1"), ("11", "2"), ("12", "3")] {
        let out = common::sdo_tool_ok(&["--bus", &bus], &["read", node, "0x1018:04", "u32"]);
        assert_eq!(lines(&out), [serial]);
    }
    // None is left without a node-ID.
    let out = common::sdo_tool_ok(&["--bus", &bus], &["lss", "scan"]);
    assert_eq!(lines(&out), ["no node without a node-ID answered"]);
    drop(nodes);

    // Restarted with the same storage, the nodes come up with the node-IDs stored.
    let restarted = Nodes::start(&args, 3);
    for (line, id) in restarted.lines.iter().zip([10, 11, 12]) {
        assert!(
            line.starts_with(&format!("canopen-node: node {id} from ")),
            "{line}"
        );
    }
    let out = common::sdo_tool_ok(
        &["--bus", &restarted.bus()],
        &["read", "12", "0x1018:04", "u32"],
    );
    assert_eq!(lines(&out), ["3"]);
}

/// python-canopen's `fast_scan`, on the nodes as they are: the address it finds, as `lss scan`
/// prints it.
fn python_fast_scan(port: u16) -> String {
    let script = format!(
        "import canopen\n\
         n = canopen.Network()\n\
         n.connect(interface='socketcand', host='127.0.0.1', port={port}, channel='can0')\n\
         n.lss.RESPONSE_TIMEOUT = 0.1\n\
         n.lss.send_switch_state_global(n.lss.WAITING_STATE)\n\
         ok, a = n.lss.fast_scan()\n\
         print(':'.join('0x%08X' % x for x in a) if ok else 'none')\n\
         n.lss.send_switch_state_global(n.lss.WAITING_STATE)\n\
         n.disconnect()\n"
    );
    let out = Command::new("python3")
        .args(["-c", &script])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

#[test]
fn lss_scan_and_the_single_services_against_two_nodes() {
    let nodes = Nodes::start(&unconfigured(2, None), 2);
    let bus = nodes.bus();
    let global = ["--bus", bus.as_str()];
    let first = "0x00000ABC:0x00000402:0x00010001:0x00000001";
    let second = "0x00000ABC:0x00000402:0x00010001:0x00000002";
    let out = common::sdo_tool_ok(&global, &["lss", "scan"]);
    assert_eq!(lines(&out), [first, second]);
    // python-canopen's Fastscan finds the same lowest address.
    assert_eq!(python_fast_scan(nodes.port), first);
    let out = common::sdo_tool_ok(&global, &["--json", "lss", "scan"]);
    assert_eq!(
        lines(&out),
        [
            r#"{"product":"0x00000402","revision":"0x00010001","serial":"0x00000001","vendor":"0x00000ABC"}"#,
            r#"{"product":"0x00000402","revision":"0x00010001","serial":"0x00000002","vendor":"0x00000ABC"}"#,
        ]
    );

    // Identify (CiA 305 §8.4.2, §8.4.3): a node without a node-ID answers; one of vendor 0xABC,
    // product 0x402, revision in 0x10000–0x1FFFF and serial 2 answers; none has a serial in 3–9.
    let out = common::sdo_tool_ok(&global, &["lss", "identify"]);
    assert_eq!(lines(&out), ["yes: a node without a node-ID answered"]);
    let range = "0xABC:0x402:0x10000-0x1FFFF:2";
    let out = common::sdo_tool_ok(&global, &["lss", "identify", range]);
    assert_eq!(lines(&out), [format!("yes: a node of {range} answered")]);
    let range = "0xABC:0x402:0x10001:3-9";
    let out = common::sdo_tool_ok(&global, &["--json", "lss", "identify", range]);
    assert_eq!(lines(&out), [r#"{"answered":false}"#]);
    let o = common::sdo_tool(&global, &["lss", "identify", "0xABC:0x402:1"]);
    assert_eq!(o.status.code(), Some(2));

    // The second node by its address: node-ID 20, pending until it is back in waiting.
    let out = common::sdo_tool_ok(&global, &["lss", "set-id", second, "20"]);
    assert_eq!(lines(&out), [format!("{second} node-ID 20")]);
    let out = common::sdo_tool_ok(&global, &["lss", "inquire"]);
    assert_eq!(lines(&out), [format!("{second} node-ID none")]);
    let out = common::sdo_tool_ok(&global, &["--json", "lss", "inquire"]);
    assert_eq!(
        lines(&out),
        [
            r#"{"node_id":null,"product":"0x00000402","revision":"0x00010001","serial":"0x00000002","vendor":"0x00000ABC"}"#
        ]
    );
    let out = common::sdo_tool_ok(&global, &["--json", "lss", "bitrate", "250"]);
    assert_eq!(lines(&out), [r#"{"ok":true}"#]);
    // Without --storage the node cannot keep its configuration: error code 1, exit 1.
    let o = common::sdo_tool(&global, &["lss", "store"]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        "sdo-tool: LSS store configuration: refused with error code 1 (out of range or not supported)\n"
    );
    let out = common::sdo_tool_ok(&global, &["lss", "switch", "waiting"]);
    assert_eq!(lines(&out), ["OK"]);
    let out = common::sdo_tool_ok(&global, &["read", "20", "0x1018:04", "u32"]);
    assert_eq!(lines(&out), ["2"]);

    // The first by Fastscan, with --json.
    let out = common::sdo_tool_ok(&global, &["--json", "lss", "set-id", "--fastscan", "21"]);
    assert_eq!(
        lines(&out),
        [
            r#"{"node_id":21,"product":"0x00000402","revision":"0x00010001","serial":"0x00000001","vendor":"0x00000ABC"}"#
        ]
    );
    // Nothing in the configuration state answers inquire once all are back in waiting.
    common::sdo_tool_ok(&global, &["lss", "switch", "waiting"]);
    let o = common::sdo_tool(&global, &["lss", "--lss-timeout-ms", "50", "inquire"]);
    assert_eq!(o.status.code(), Some(3));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        "sdo-tool: LSS inquire identity: no answer within 50 ms\n"
    );
    let out = common::sdo_tool_ok(&global, &["lss", "identify"]);
    assert_eq!(lines(&out), ["no: a node without a node-ID did not answer"]);
    let o = common::sdo_tool(&global, &["lss", "set-id", "--fastscan", "22"]);
    assert_eq!(o.status.code(), Some(3));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        "sdo-tool: LSS Fastscan: no node without a node-ID answered\n"
    );
}

#[test]
fn lss_usage_errors_are_one_line_each() {
    // The words are refused before anything is sent.
    let nodes = Nodes::start(&unconfigured(1, None), 1);
    for (argv, message) in [
        (
            &["lss", "set-id", "0xABC:0x402", "5"][..],
            "sdo-tool: LSS address \"0xABC:0x402\" is not VENDOR:PRODUCT:REVISION:SERIAL (e.g. 0x5A:0x402:1:2)\n",
        ),
        (
            &["lss", "set-id", "1:2:3:4", "128"],
            "sdo-tool: node-ID \"128\" is not 1 to 127\n",
        ),
        (
            &["lss", "set-id", "1:2:3:4"],
            "sdo-tool: lss set-id ADDRESS NEW_ID, or lss set-id --fastscan NEW_ID…\n",
        ),
        (
            &["lss", "bitrate", "300"],
            "sdo-tool: bit rate 300 kbit/s is not 1000, 800, 500, 250, 125, 100, 50, 20 or 10\n",
        ),
        (
            &["lss", "switch", "sleeping"],
            "sdo-tool: LSS state \"sleeping\" is not waiting or configuration\n",
        ),
        (&["lss", "assign", "0"], "sdo-tool: node-ID \"0\" is not 1 to 127\n"),
    ] {
        let o = common::sdo_tool(&["--bus", &nodes.bus()], argv);
        assert_eq!(String::from_utf8_lossy(&o.stderr), message, "{argv:?}");
        assert_eq!(o.status.code(), Some(2), "{argv:?}");
    }
}

#[test]
fn gateway_lss_requests_with_exact_replies() {
    let dir = tempfile::tempdir().unwrap();
    let nodes = Nodes::start(&unconfigured(2, Some(dir.path())), 2);
    // [13]: vendor and product matched, revision and serial scanned (CANopenNode's scan types
    // 2 and 0); [20]: a scan type that is none.
    let script = "\
[1] _lss_fastscan
[2] lss_inquire_addr
[3] lss_inquire_addr 3
[4] lss_inquire_addr 0x5B
[5] lss_get_node
[6] lss_set_node 30
[7] lss_set_node 128
[8] lss_conf_bitrate 0 4
[9] lss_conf_bitrate 0 5
[10] lss_store
[11] lss_switch_glob 0
[12] lss_get_node
[13] lss_allnodes 100 40 1 2 0xABC 2 0x402 0 0 0 0
[14] lss_allnodes
[15] lss_switch_sel 0xABC 0x402 0x10001 2
[16] lss_get_node
[17] lss_activate_bitrate 100
[18] lss_switch_glob 0
[19] lss_inquire_addr 4
[20] lss_allnodes 100 40 1 3 0xABC 0 0 0 0 0 0
[21] _lss_fastscan 4294967295
[22] lss_allnodes 100 128 1
";
    let mut child = Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(["--bus", &nodes.bus(), "gateway"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    std::io::Write::write_all(&mut child.stdin.take().unwrap(), script.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        lines(&text),
        [
            "[1] 0x00000ABC 0x00000402 0x00010001 0x00000001",
            "[2] 0x00000ABC 0x00000402 0x00010001 0x00000001",
            "[3] 0x00000001",
            "[4] 0x00000402",
            "[5] 255",
            "[6] OK",
            "[7] ERROR:101 #Syntax error",
            "[8] OK",
            "[9] ERROR:102 #Request not processed due to internal state",
            "[10] OK",
            "[11] OK",
            "[12] ERROR:103 #Time-out",
            "# Node-ID 40 assigned to: 0x00000ABC 0x00000402 0x00010001 0x00000002",
            "# Found 1 node, search finished.",
            "[13] OK",
            "# Found 0 nodes, search finished.",
            "[14] OK",
            "[15] OK",
            "[16] 40",
            "[17] OK",
            "[18] OK",
            "[19] ERROR:101 #Syntax error",
            "[20] ERROR:101 #Syntax error",
            "[21] ERROR:101 #Syntax error",
            "[22] ERROR:101 #Syntax error",
        ]
    );
}
