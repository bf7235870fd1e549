//! `sdo-tool net boot` and `net watch` on a network of real nodes on a socketcand server of 127.0.0.1:
//! `canopen-node` running `examples/drive.eds` (node 2, the server) and `examples/io-device.eds`
//! (node 3, a second process joining it), `x67-node` (node 4) and a python-canopen `LocalNode`
//! (node 5). The network boots from a bus.yml of dcfgen's form; each fault injected (a wrong device
//! at a node-ID, a missing mandatory node, a refused configuration write, a lost heartbeat, a node
//! that restarts) ends with its CiA 302-2 letter and words, and the exit code of the worst node.

mod common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use common::{canopen_node, sdo_tool, sdo_tool_ok, spawn, Proc};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples")
}

/// The server (node 2, the drive) taking connections, and its port.
fn server() -> (Proc, u16) {
    let drive = format!("{}@2", examples().join("drive.eds").display());
    common::node_server(&["--od", &drive])
}

fn client(port: u16) -> String {
    common::socketcand_bus(port)
}

/// Node 3, the I/O device, joining the server.
fn io_node(port: u16) -> Proc {
    let io = format!("{}@3", examples().join("io-device.eds").display());
    canopen_node(&client(port), &["--od", &io])
}

/// A bus.yml in `dir`: the drive at 2 (mandatory; heartbeat 100 ms; TPDO 1 event timer 50 ms), the
/// I/O device at 3 (heartbeat 100 ms), with `extra` appended (more slaves). The master waits thirty
/// heartbeat periods (3 s) for each: a busy machine delays a heartbeat, not by seconds.
fn bus_yml(dir: &Path, extra: &str) -> PathBuf {
    let text = format!(
        "options:\n  heartbeat_multiplier: 30\n\n\
         master:\n  node_id: 1\n  heartbeat_producer: 200\n\n\
         drive:\n  dcf: {drive}\n  node_id: 2\n  mandatory: true\n  heartbeat_producer: 100\n\
         \x20 tpdo:\n    1:\n      enabled: true\n      cob_id: auto\n      transmission: 0xFE\n\
         \x20     event_timer: 50\n      mapping:\n        - {{index: 0x6041, sub_index: 0}}\n\n\
         io:\n  dcf: {io}\n  node_id: 3\n  heartbeat_producer: 100\n{extra}",
        drive = examples().join("drive.eds").display(),
        io = examples().join("io-device.eds").display(),
    );
    let path = dir.join("bus.yml");
    std::fs::write(&path, text).unwrap();
    path
}

fn lines_with<'a>(text: &'a str, what: &str) -> Vec<&'a str> {
    text.lines().filter(|l| l.contains(what)).collect()
}

/// The table row of `node` (its first column).
fn row(text: &str, node: u8) -> Vec<String> {
    let l = text
        .lines()
        .find(|l| l.split_whitespace().next() == Some(&node.to_string()))
        .unwrap_or_else(|| panic!("no row for node {node} in\n{text}"));
    l.split_whitespace().map(str::to_string).collect()
}

#[test]
fn a_network_of_canopen_nodes_boots_configured_and_started() {
    let dir = tempfile::tempdir().unwrap();
    let (_server, port) = server();
    let _io = io_node(port);
    let bus = bus_yml(dir.path(), "");
    let out = sdo_tool(
        &["--bus", &client(port)],
        &["net", "boot", bus.to_str().unwrap()],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    // node, name, state, nmt, type, vendor, product, config, heartbeat, last error.
    let drive = row(&text, 2);
    assert_eq!(drive[1..3], ["drive", "up"], "{text}");
    assert_eq!(drive[4], "0x00020192", "{text}");
    let io = row(&text, 3);
    assert_eq!(io[1..3], ["io", "up"], "{text}");
    assert_eq!(io[4], "0x000F0191", "{text}");
    assert_eq!(
        lines_with(&text, "NMT reset communication all nodes").len(),
        1,
        "{text}"
    );
    assert_eq!(lines_with(&text, "NMT start node 2").len(), 1, "{text}");
    assert_eq!(lines_with(&text, "NMT start node 3").len(), 1, "{text}");
    assert_eq!(lines_with(&text, "network up").len(), 1, "{text}");
    // What the configuration wrote is in the node: its heartbeat time and the TPDO's event timer,
    // and the node is Operational (its heartbeat says 0x05).
    let bus_arg = ["--bus".to_string(), client(port)];
    let global: Vec<&str> = bus_arg.iter().map(String::as_str).collect();
    assert_eq!(
        sdo_tool_ok(&global, &["read", "2", "0x1017", "u16"]).trim(),
        "100"
    );
    assert_eq!(
        sdo_tool_ok(&global, &["read", "2", "0x1800:5", "u16"]).trim(),
        "50"
    );
    let watch = sdo_tool_ok(&global, &["watch", "--duration-ms", "400"]);
    assert!(
        watch
            .lines()
            .any(|l| l.ends_with("node 2: heartbeat, operational")),
        "{watch}"
    );
}

#[test]
fn a_wrong_device_at_a_node_id_ends_with_c_and_exit_7() {
    let dir = tempfile::tempdir().unwrap();
    let (_server, port) = server();
    let _io = io_node(port);
    // The bus.yml puts the drive at 3, where the I/O device answers.
    let bus = bus_yml(dir.path(), "");
    let text = std::fs::read_to_string(&bus).unwrap();
    let swapped = text
        .replace("node_id: 2", "node_id: 9")
        .replace("node_id: 3", "node_id: 2");
    let swapped = swapped.replace("node_id: 9", "node_id: 3");
    std::fs::write(&bus, swapped).unwrap();
    let out = sdo_tool(
        &["--bus", &client(port)],
        &["net", "boot", bus.to_str().unwrap()],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(7), "{text}");
    let line = format!(
        "node 3 [C] device type 0x00020192 expected ({}:9, {}), 0x000F0191 found in 0x1000:00 — a \
         different kind of device answers at this node-ID (device type 0x1000 differs from 0x1F84)",
        bus.display(),
        examples().join("drive.eds").display()
    );
    let found = lines_with(&text, "node 3 [C]");
    assert_eq!(found.len(), 1, "{text}");
    assert!(found[0].ends_with(&line), "{text}");
    assert_eq!(
        String::from_utf8_lossy(&out.stderr).trim(),
        "sdo-tool: mandatory node 3 and optional node 2 not booted: the network is not up"
    );
}

#[test]
fn a_missing_mandatory_node_ends_with_b_after_its_retries_and_exit_7() {
    let dir = tempfile::tempdir().unwrap();
    let (_server, port) = server();
    let _io = io_node(port);
    let ghost = format!(
        "\nghost:\n  dcf: {}\n  node_id: 6\n  mandatory: true\n",
        examples().join("drive.eds").display()
    );
    let bus = bus_yml(dir.path(), &ghost);
    let out = sdo_tool(
        &["--bus", &client(port)],
        &[
            "net",
            "boot",
            "--boot-up-wait-ms",
            "300",
            "--wait-ms",
            "6000",
            bus.to_str().unwrap(),
        ],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(7), "{text}");
    // Asked after the wait (0.3 s), failed at the SDO timeout (1 s) later, asked again a second
    // after that (2.3 s), and so on: at least twice in the 6 s of --wait-ms, each time with the
    // same words.
    let failures = lines_with(&text, "node 6 [B]");
    let line = "node 6 [B] device type 0x1000:00 could not be read: no answer within 1000 ms — no \
                node answers at this node-ID (no answer to the upload of 0x1000)";
    assert!(failures.len() >= 2, "{text}");
    assert!(failures.iter().all(|l| l.ends_with(line)), "{text}");
    let tries = lines_with(&text, "node 6 ghost: checking").len();
    assert!(
        tries == failures.len() || tries == failures.len() + 1,
        "{text}"
    );
    assert_eq!(row(&text, 2)[2], "up", "{text}");
    assert_eq!(row(&text, 3)[2], "up", "{text}");
    let ghost = row(&text, 6);
    // Failed, or asked again when the wait ended; its last error is B either way.
    assert!(
        ghost[2..4] == ["failed", "B"] || ghost[2] == "checking",
        "{text}"
    );
    assert!(
        text.lines()
            .last()
            .unwrap_or("")
            .contains("[B] device type 0x1000:00"),
        "{text}"
    );
    assert_eq!(lines_with(&text, "network up").len(), 0, "{text}");
    assert_eq!(
        String::from_utf8_lossy(&out.stderr).trim(),
        "sdo-tool: mandatory node 6 not booted: the network is not up"
    );
}

#[test]
fn a_refused_configuration_write_ends_with_j_naming_the_entry_and_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let (_server, port) = server();
    let _io = io_node(port);
    let bus = bus_yml(
        dir.path(),
        "  sdo:\n    - {index: 0x1001, sub_index: 0, value: 1}\n",
    );
    let out = sdo_tool(
        &["--bus", &client(port)],
        &["net", "boot", bus.to_str().unwrap()],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    // The I/O device is optional: the network is up without it.
    assert_eq!(out.status.code(), Some(6), "{text}");
    let line = format!(
        "node 3 [J] writing 0x1001:00 = 0x1 ({}:27 io.sdo) failed: the node refused it with \
         0x06010002 (Attempt to write a read only object) — the node refuses its configuration \
         (the configuration download failed)",
        bus.display()
    );
    let failures = lines_with(&text, "node 3 [J]");
    assert_eq!(failures.len(), 1, "{text}");
    assert!(failures[0].ends_with(&line), "{text}");
    assert_eq!(lines_with(&text, "network up").len(), 1, "{text}");
    assert_eq!(
        String::from_utf8_lossy(&out.stderr).trim(),
        "warning: io: no write access for sub-object 0x1001/0\nsdo-tool: optional node 3 not booted"
    );
}

/// `net watch --json` as it runs: its events line by line.
struct Watch {
    child: Child,
    lines: std::sync::mpsc::Receiver<serde_json::Value>,
}

impl Watch {
    fn start(port: u16, bus: &Path) -> Watch {
        let mut child = Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
            .args(["--bus", &client(port), "--json", "net", "watch"])
            .args(["--wait-ms", "60000"])
            .arg(bus)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let out = BufReader::new(child.stdout.take().unwrap());
        let (tx, lines) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            for l in out.lines().map_while(Result::ok) {
                let _ = tx.send(serde_json::from_str(&l).expect("one JSON object a line"));
            }
        });
        Watch { child, lines }
    }

    /// Every event up to the first `pred` holds for (which is the last); none within 20 s fails.
    fn until(&self, pred: impl Fn(&serde_json::Value) -> bool) -> Vec<serde_json::Value> {
        let mut seen = Vec::new();
        loop {
            let v = self
                .lines
                .recv_timeout(Duration::from_secs(20))
                .unwrap_or_else(|_| panic!("not seen in 20 s; so far {seen:#?}"));
            let done = pred(&v);
            seen.push(v);
            if done {
                return seen;
            }
        }
    }
}

impl Drop for Watch {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn is(v: &serde_json::Value, node: u8, event: &str, state: &str) -> bool {
    v["node"] == node && v["event"] == event && (state.is_empty() || v["state"] == state)
}

#[test]
fn net_watch_sees_a_lost_heartbeat_and_boots_the_node_again_when_it_restarts() {
    let dir = tempfile::tempdir().unwrap();
    let (_server, port) = server();
    let io = io_node(port);
    let bus = bus_yml(dir.path(), "");
    let watch = Watch::start(port, &bus);
    watch.until(|v| v["event"] == "network_up");
    // The I/O device's process ends: no heartbeat for 3000 ms (100 ms times 30) is event E.
    drop(io);
    let seen = watch.until(|v| is(v, 3, "failed", ""));
    let lost = seen.last().unwrap();
    assert_eq!(lost["status"], "E");
    assert_eq!(
        lost["message"],
        format!(
            "heartbeat lost: none for 3000 ms (consumer time, {}:25 io.heartbeat_producer) — the \
             node stopped, lost power or left the bus",
            bus.display()
        )
    );
    // The drive is not touched meanwhile.
    assert!(!seen.iter().any(|v| v["node"] == 2), "{seen:#?}");
    // It comes back: its boot-up message boots it again, to the end.
    let _io = io_node(port);
    let seen = watch.until(|v| is(v, 3, "state", "up"));
    let states: Vec<_> = seen
        .iter()
        .filter(|v| v["node"] == 3 && v["event"] == "state")
        .map(|v| v["state"].as_str().unwrap().to_string())
        .collect();
    assert_eq!(
        states.first().map(String::as_str),
        Some("checking"),
        "{seen:#?}"
    );
    assert_eq!(states.last().map(String::as_str), Some("up"), "{seen:#?}");
    let starts: Vec<_> = seen
        .iter()
        .filter(|v| v["event"] == "nmt" && v["command"] == "start")
        .collect();
    assert_eq!(starts.len(), 1, "{seen:#?}");
    assert_eq!(starts[0]["node"], 3);
}

/// python-canopen's `LocalNode` (tests/python/local_node.py) on the bus for `seconds`.
fn local_node(port: u16, eds: &Path, id: u8, seconds: u32) -> Proc {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/python/local_node.py");
    spawn(
        Command::new("python3")
            .arg(script)
            .arg("--eds")
            .arg(eds)
            .args(["--node-id", &id.to_string(), "--socketcand"])
            .arg(format!("127.0.0.1:{port}"))
            .args(["--seconds", &seconds.to_string()]),
    )
}

#[test]
fn a_mixed_network_boots_from_the_folder_net_gen_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let (_server, port) = server();
    let _io = io_node(port);
    // x67-node at 4, with the description it writes of itself.
    let x67 = dir.path().join("x67.eds");
    let o = Command::new(testkit::cargo_binary("socketcan-node", "x67-node", &[]))
        .arg("--write-description")
        .arg(&x67)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let _x67 = spawn(
        Command::new(testkit::cargo_binary("socketcan-node", "x67-node", &[])).args([
            "--bus",
            &client(port),
            "--node-id",
            "4",
        ]),
    );
    let _py = local_node(port, &examples().join("io-device.eds"), 5, 30);
    let extra = format!(
        "\nx67:\n  dcf: {}\n  node_id: 4\n  heartbeat_producer: 100\n\n\
         py:\n  dcf: {}\n  node_id: 5\n  sdo:\n    - {{index: 0x1800, sub_index: 5, value: 250}}\n",
        x67.display(),
        examples().join("io-device.eds").display()
    );
    let bus = bus_yml(dir.path(), &extra);
    let out_dir = dir.path().join("out");
    sdo_tool_ok(
        &[],
        &[
            "net",
            "gen",
            bus.to_str().unwrap(),
            "-d",
            out_dir.to_str().unwrap(),
        ],
    );
    let out = sdo_tool(
        &["--bus", &client(port)],
        &["net", "boot", out_dir.to_str().unwrap()],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    for (node, device_type) in [(2, "0x00020192"), (3, "0x000F0191"), (5, "0x000F0191")] {
        let r = row(&text, node);
        assert_eq!(
            (r[2].as_str(), r[4].as_str()),
            ("up", device_type),
            "{text}"
        );
    }
    assert_eq!(row(&text, 4)[2], "up", "{text}");
    // The folder's plan names its nodes after their concise DCFs, as dcfgen names those.
    let names: Vec<_> = [2, 3, 4, 5].map(|n| row(&text, n)[1].clone()).into();
    assert_eq!(names, ["drive", "io", "x67", "py"], "{text}");
    // python-canopen took the write of its configuration.
    let global = ["--bus".to_string(), client(port), "--no-block".to_string()];
    let global: Vec<&str> = global.iter().map(String::as_str).collect();
    assert_eq!(
        sdo_tool_ok(&global, &["read", "5", "0x1800:5", "u16"]).trim(),
        "250"
    );
}

#[test]
fn a_folder_of_the_nodes_dumped_dcfs_boots_with_an_edited_value_written() {
    let dir = tempfile::tempdir().unwrap();
    let (_server, port) = server();
    let _io = io_node(port);
    let bus = ["--bus".to_string(), client(port)];
    let global: Vec<&str> = bus.iter().map(String::as_str).collect();
    let dcfs = dir.path().join("dcfs");
    std::fs::create_dir(&dcfs).unwrap();
    for (node, eds, name) in [("2", "drive.eds", "drive"), ("3", "io-device.eds", "io")] {
        let od = examples().join(eds);
        let out = dcfs.join(format!("{name}.dcf"));
        let mut g = global.clone();
        g.extend(["--od", od.to_str().unwrap()]);
        sdo_tool_ok(&g, &["dump", node, "-o", out.to_str().unwrap()]);
    }
    // The drive's TPDO 1 event timer, edited in its DCF: 10 → 250 ms.
    let path = dcfs.join("drive.dcf");
    let text = std::fs::read_to_string(&path).unwrap();
    let at = text.find("[1800sub5]").unwrap();
    let value = at + text[at..].find("ParameterValue=").unwrap();
    let end = value + text[value..].find('\n').unwrap();
    let edited = format!("{}ParameterValue=250{}", &text[..value], &text[end..]);
    std::fs::write(&path, edited).unwrap();
    assert_eq!(
        sdo_tool_ok(&global, &["read", "2", "0x1800:5", "u16"]).trim(),
        "10"
    );
    let out = sdo_tool(&global, &["net", "boot", dcfs.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    assert_eq!(row(&text, 2)[1..3], ["drive", "up"], "{text}");
    assert_eq!(row(&text, 3)[1..3], ["io", "up"], "{text}");
    assert_eq!(
        sdo_tool_ok(&global, &["read", "2", "0x1800:5", "u16"]).trim(),
        "250"
    );
}

/// On a terminal the table is drawn live: each event draws it again over itself (cursor up by the
/// table's lines, each line cleared), with no event lines between.
#[test]
fn on_a_terminal_the_table_is_live() {
    let dir = tempfile::tempdir().unwrap();
    let (_server, port) = server();
    let _io = io_node(port);
    let bus = bus_yml(dir.path(), "");
    let command = format!(
        "{} --bus {} net boot {}",
        env!("CARGO_BIN_EXE_sdo-tool"),
        client(port),
        bus.display()
    );
    // `script` runs the command on a pseudo-terminal; -e: its exit code.
    let o = Command::new("script")
        .args(["-qec", &command, "/dev/null"])
        .output()
        .expect("script (util-linux)");
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{text}");
    let header = "\x1b[2Knode  name";
    let draws = text.matches(header).count();
    assert!(draws >= 2, "{text:?}");
    // Each draw after the first goes up over the header and the two nodes' rows.
    assert_eq!(text.matches("\x1b[3A").count(), draws - 1, "{text:?}");
    assert!(!text.contains("NMT reset communication"), "{text:?}");
    let last = text.rsplit(header).next().unwrap();
    assert!(last.contains("drive        up"), "{text:?}");
    assert!(last.contains("io           up"), "{text:?}");
}
