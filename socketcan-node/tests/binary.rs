//! The `x67-node` binary as a user runs it: over the socketcand protocol on 127.0.0.1, with
//! python-canopen as the master, with its default bus, stopped by Ctrl-C, and killed while it saves
//! its parameters; its capture of a session.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use testkit::free_port;

use socketcan_node::transport::{BusEvent, CanBus, SocketcandClient};
use socketcan_node::CanFrame;

const NODE: &str = env!("CARGO_BIN_EXE_x67-node");

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The node process; killed when dropped.
struct NodeProcess {
    child: Child,
    port: u16,
}

impl Drop for NodeProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn start_node(extra: &[&str]) -> NodeProcess {
    let port = free_port();
    // The first line on stdout says the node is listening.
    let (child, line) = testkit::start_until_first_line(
        Command::new(NODE)
            .arg("--bus")
            .arg(format!("socketcand-listen:127.0.0.1:{port}"))
            .args(extra),
    );
    assert!(line.starts_with("x67-node: node "), "{line}");
    NodeProcess { child, port }
}

fn client(port: u16) -> SocketcandClient {
    SocketcandClient::connect("127.0.0.1", port, "can0").unwrap()
}

fn f(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

/// The first frame on `cob` within 5 s.
fn wait_for(bus: &mut dyn CanBus, cob: u16) -> CanFrame {
    let end = Instant::now() + Duration::from_secs(5);
    while Instant::now() < end {
        if let Some(BusEvent::Frame { frame, .. }) = bus.recv(Duration::from_millis(100)).unwrap() {
            if frame.cob_id() == Some(cob) {
                return frame;
            }
        }
    }
    panic!("no frame on {cob:03X} within 5 s");
}

/// An expedited SDO exchange with node 1: the response's 8 bytes.
fn sdo(bus: &mut dyn CanBus, req: [u8; 8]) -> [u8; 8] {
    bus.send(&f(0x601, &req)).unwrap();
    wait_for(bus, 0x581).data8()
}

#[test]
fn python_canopen_master_over_socketcand() {
    let node = start_node(&[]);
    let eds = root().join("fixtures/x67/X67SM2436.eds");
    let out = Command::new("python3")
        .arg(root().join("tests/python/x67_master.py"))
        .arg("--eds")
        .arg(&eds)
        .args(["--node-id", "1", "--socketcand"])
        .arg(format!("127.0.0.1:{}", node.port))
        .output()
        .expect("python3 runs (scripts/setup-test-deps installs python-canopen)");
    let text = String::from_utf8_lossy(&out.stdout);
    println!("{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "python-canopen master failed");
    assert!(text.lines().any(|l| l == "PASS"), "{text}");
    assert!(
        text.contains("ok   target 5000 reached (status bit 10)"),
        "{text}"
    );
}

#[test]
fn main_job_serves_socketcand_on_29536_and_stops_on_ctrl_c() {
    let mut child = Command::new(NODE)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut out = BufReader::new(child.stdout.take().unwrap());
    let mut text = String::new();
    for _ in 0..4 {
        out.read_line(&mut text).unwrap();
    }
    assert!(
        text.starts_with(
            "x67-node: node 1 (X67BC4321-10 with 1 X67SM2436 module) listening as a socketcand \
             server on 127.0.0.1:29536"
        ),
        "{text}"
    );
    assert!(
        text.contains(
            "network.connect(interface=\"socketcand\", host=\"127.0.0.1\", port=29536, channel=\"can0\")"
        ),
        "{text}"
    );
    assert!(
        text.contains("--bus socketcand://127.0.0.1:29536/can0"),
        "{text}"
    );
    let mut bus = client(29536);
    // 1018:00 = 4 entries.
    assert_eq!(
        sdo(&mut bus, [0x40, 0x18, 0x10, 0, 0, 0, 0, 0]),
        [0x4F, 0x18, 0x10, 0, 4, 0, 0, 0]
    );
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let end = Instant::now() + Duration::from_secs(5);
    let code = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        assert!(Instant::now() < end, "x67-node did not stop on SIGINT");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(code.success(), "{code:?}");
}

#[test]
fn bad_arguments_exit_2_with_the_reason() {
    let out = Command::new(NODE)
        .args([
            "--bus",
            "socketcand-listen:192.0.2.1:29536",
            "--node-id",
            "5",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("x67-node: cannot open socketcand-listen:192.0.2.1:29536: "),
        "{err}"
    );
    let out = Command::new(NODE)
        .args(["--node-id", "200"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("200 is not in 1..=127"));
    // A FIFO as the storage file: refused at once with one line (it is never opened).
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("params");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let out = Command::new(NODE)
        .args([
            "--storage",
            fifo.to_str().unwrap(),
            "--bus",
            "socketcand-listen:127.0.0.1:0",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("params: not a regular file"), "{err}");
    // A capture file that cannot be created: refused with one line before the bus is opened.
    let out = Command::new(NODE)
        .args([
            "--capture",
            "/nonexistent/dir/x.pcapng",
            "--bus",
            "socketcand-listen:127.0.0.1:0",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(
        err,
        "x67-node: --capture /nonexistent/dir/x.pcapng: No such file or directory (os error 2)\n"
    );
}

/// `--capture FILE`: what the node sent and received, in order and each with its direction, in a
/// pcapng file that is whole when the node is stopped by SIGTERM (a service manager's stop) or
/// Ctrl-C, each of which ends it with exit 0: its boot-up (0x701, 0x00) sent at start, the SDO
/// request for 0x1018:00 received, the answer (4 entries) sent; the times from the start to the
/// stop, in order.
#[test]
fn a_capture_is_whole_when_the_node_is_stopped_by_sigterm_or_ctrl_c() {
    use link_capture::pcapng::{Direction, Reader};
    for signal in ["-TERM", "-INT"] {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("node.pcapng");
        let start = std::time::SystemTime::now();
        let mut node = start_node(&["--heartbeat-ms", "0", "--capture", file.to_str().unwrap()]);
        let mut bus = client(node.port);
        assert_eq!(
            sdo(&mut bus, [0x40, 0x18, 0x10, 0, 0, 0, 0, 0]),
            [0x4F, 0x18, 0x10, 0, 4, 0, 0, 0]
        );
        let status = Command::new("kill")
            .args([signal, &node.child.id().to_string()])
            .status()
            .unwrap();
        assert!(status.success());
        let end = Instant::now() + Duration::from_secs(5);
        let status = loop {
            if let Some(status) = node.child.try_wait().unwrap() {
                break status;
            }
            assert!(Instant::now() < end, "x67-node did not stop on {signal}");
            std::thread::sleep(Duration::from_millis(20));
        };
        assert!(status.success(), "{signal}: {status:?}");
        let stop = std::time::SystemTime::now();
        let bytes = std::fs::read(&file).unwrap();
        let mut r = Reader::new(&bytes[..]);
        let mut frames = Vec::new();
        while let Some(p) = r.next_packet().unwrap() {
            let t = p.time.unwrap();
            assert!(start <= t && t <= stop, "{signal}: {t:?} outside the run");
            let frame = CanFrame::from_socketcan_bytes(p.data).unwrap();
            frames.push((p.direction.unwrap(), frame.to_string(), t));
        }
        use Direction::{Inbound as In, Outbound as Out};
        // The request may reach the link before the node's boot-up goes out (the client connects
        // once the node has said where it listens): the two come in either order, each at the
        // time its link took it; the answer comes after the request.
        let seen: Vec<(Direction, &str)> =
            frames.iter().map(|(d, f, _)| (*d, f.as_str())).collect();
        let boot = (Out, "701#00");
        let request = (In, "601#4018100000000000");
        let answer = (Out, "581#4F18100004000000");
        assert!(
            seen == [boot, request, answer] || seen == [request, boot, answer],
            "{signal}: {seen:?}"
        );
        assert!(frames[2].2 >= frames.iter().find(|f| f.1 == request.1).unwrap().2);
        let port = node.port;
        assert_eq!(
            r.interfaces_seen()[0].name,
            Some(format!("socketcand-listen:127.0.0.1:{port}"))
        );
    }
}

/// Store parameters (0x1010) into a file; a process killed at any moment leaves the old set or the
/// new one, which the next start loads. The answer to "save" comes once the set is in the file
/// (written, synced and renamed on the storage's own thread), so a kill after the answer keeps the
/// new set whatever the disk's speed; kills at other moments (right after the request, a few hundred
/// microseconds later: before, during or after the write, as the disk allows) keep one or the other.
#[test]
fn killed_while_saving_leaves_the_old_or_the_new_parameter_set() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("node1.params");
    let storage = file.to_str().unwrap().to_string();
    let mut saved: Option<u16> = None;
    for k in 0..12u16 {
        let value = 1000 + k;
        let mut node = start_node(&["--storage", &storage]);
        let mut bus = client(node.port);
        // What the last run left loads at start.
        let got = sdo(&mut bus, [0x40, 0x17, 0x10, 0, 0, 0, 0, 0]);
        let [lo, hi] = saved.unwrap_or(0).to_le_bytes();
        assert_eq!(got, [0x4B, 0x17, 0x10, 0, lo, hi, 0, 0], "run {k}");
        let [lo, hi] = value.to_le_bytes();
        assert_eq!(
            sdo(&mut bus, [0x2B, 0x17, 0x10, 0, lo, hi, 0, 0]),
            [0x60, 0x17, 0x10, 0, 0, 0, 0, 0]
        );
        // "save", then kill the process: every third run once the save is answered, the others
        // some microseconds after the request.
        let answered = k % 3 == 2;
        let save = [0x23, 0x10, 0x10, 1, b's', b'a', b'v', b'e'];
        if answered {
            assert_eq!(
                sdo(&mut bus, save),
                [0x60, 0x10, 0x10, 1, 0, 0, 0, 0],
                "run {k}"
            );
        } else {
            bus.send(&f(0x601, &save)).unwrap();
            std::thread::sleep(Duration::from_micros(u64::from(k) * 150));
        }
        node.child.kill().unwrap();
        node.child.wait().unwrap();
        // The file is the old set or the new one (the new one once the save was answered): a
        // fresh node says which.
        let mut check = start_node(&["--storage", &storage]);
        let mut bus = client(check.port);
        let got = sdo(&mut bus, [0x40, 0x17, 0x10, 0, 0, 0, 0, 0]);
        let now = u16::from_le_bytes([got[4], got[5]]);
        assert_eq!(got[..4], [0x4B, 0x17, 0x10, 0], "run {k}");
        if answered {
            assert_eq!(now, value, "run {k}: a save answered is kept");
        } else {
            assert!(
                now == value || Some(now) == saved || (saved.is_none() && now == 0),
                "run {k}: heartbeat {now} after a kill, neither the old {saved:?} nor the new {value}"
            );
        }
        if now == value {
            saved = Some(value);
        }
        // What the killed save left beside the file is gone once a node has loaded the set.
        let names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert!(
            names.iter().all(|n| n == "node1.params"),
            "run {k}: {names:?}"
        );
        check.child.kill().unwrap();
        check.child.wait().unwrap();
    }
}

/// `--bus socketcand://HOST:PORT/CHANNEL`: the node joins a bus that a socketcand server holds.
#[test]
fn joins_a_socketcand_bus_as_a_client() {
    use socketcan_node::transport::SocketcandServer;
    let mut server = SocketcandServer::bind("127.0.0.1:0".parse().unwrap()).unwrap();
    let port = server.local_addr().port();
    let mut child = Command::new(NODE)
        .args(["--bus", &format!("socketcand://127.0.0.1:{port}/can0")])
        .args(["--node-id", "7"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let boot = wait_for(&mut server, 0x707);
    assert_eq!(boot.data(), &[0x00], "boot-up message");
    server
        .send(&f(0x607, &[0x40, 0x18, 0x10, 0, 0, 0, 0, 0]))
        .unwrap();
    assert_eq!(
        wait_for(&mut server, 0x587).data(),
        &[0x4F, 0x18, 0x10, 0, 4, 0, 0, 0]
    );
    child.kill().unwrap();
    child.wait().unwrap();
}

/// `socketcand-listen:127.0.0.1:0` asks the system for a free port: the start-up line names the port
/// chosen, and a client reaches the node there.
#[test]
fn a_listener_on_port_0_prints_the_port_it_got() {
    let (mut child, line) = testkit::start_until_first_line(
        Command::new(NODE).args(["--bus", "socketcand-listen:127.0.0.1:0"]),
    );
    let at = line
        .find("server on 127.0.0.1:")
        .unwrap_or_else(|| panic!("{line}"));
    let port: u16 = line[at + "server on 127.0.0.1:".len()..]
        .split(|c: char| !c.is_ascii_digit())
        .next()
        .and_then(|p| p.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert_ne!(port, 0, "{line}");
    let mut bus = client(port);
    assert_eq!(
        sdo(&mut bus, [0x40, 0x18, 0x10, 0, 0, 0, 0, 0]),
        [0x4F, 0x18, 0x10, 0, 4, 0, 0, 0]
    );
    child.kill().unwrap();
    child.wait().unwrap();
}
