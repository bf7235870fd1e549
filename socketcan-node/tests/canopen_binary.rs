//! The `canopen-node` binary as a user runs it, over the socketcand protocol on 127.0.0.1, with
//! python-canopen as the master: `BaseNode402` drives the CiA 402 drive of this project's example
//! description and of real drive descriptions of five vendors, its LSS master finds an unconfigured
//! node by Fastscan and gives it a node-ID that a restart keeps, and a `RemoteNode` moves a DOMAIN by
//! block transfer.

use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::time::{Duration, Instant};
use testkit::free_port;

use socketcan_node::transport::{BusEvent, CanBus, SocketcandClient};
use socketcan_node::CanFrame;

const NODE: &str = env!("CARGO_BIN_EXE_canopen-node");

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A file of the shared corpus of real descriptions (beside the checkout).
fn corpus(name: &str) -> PathBuf {
    let p = root().join("../shared/corpus/eds").join(name);
    assert!(
        p.is_file(),
        "{} is missing: the corpus lies beside the checkout",
        p.display()
    );
    p
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

fn start(args: &[&str]) -> NodeProcess {
    let port = free_port();
    let (child, line) = testkit::start_until_first_line(
        Command::new(NODE)
            .arg("--bus")
            .arg(format!("socketcand-listen:127.0.0.1:{port}"))
            .args(args),
    );
    assert!(line.starts_with("canopen-node: node "), "{line}");
    NodeProcess { child, port }
}

/// Runs `tests/python/canopen_master.py` with `args` against `node`; asserts it passed and returns
/// what it printed.
fn master(node: &NodeProcess, args: &[&str]) -> String {
    let out = Command::new("python3")
        .arg(root().join("tests/python/canopen_master.py"))
        .args(args)
        .arg("--socketcand")
        .arg(format!("127.0.0.1:{}", node.port))
        .output()
        .expect("python3 runs (scripts/setup-test-deps installs python-canopen)");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    println!("{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "python-canopen master failed");
    assert_eq!(text.lines().last(), Some("PASS"), "{text}");
    text
}

/// BaseNode402 on the example drive: every step of the scenario, with the supported modes of its
/// 0x6502 (0x3A5: pp, pv, hm, csp, csv, cst).
#[test]
fn base_node_402_drives_the_example_drive() {
    let eds = root().join("examples/drive.eds");
    let eds = eds.to_str().unwrap();
    let node = start(&["--od", &format!("{eds}@5")]);
    let text = master(&node, &["drive402", "--eds", eds, "--node-id", "5"]);
    for step in [
        "ok   supported drive modes 0x000003A5",
        "ok   state: 'OPERATION ENABLED'",
        "ok   homing(): True",
        "ok   op_mode: 'PROFILED POSITION'",
        "ok   set-point acknowledged (status bit 12)",
        "ok   target reached (status bit 10)",
        "ok   op_mode: 'PROFILED VELOCITY'",
        "ok   velocity reached (status bit 10)",
        "ok   op_mode: 'CYCLIC SYNCHRONOUS POSITION'",
        "ok   csp: the position follows to the last target",
        "ok   state: 'SWITCH ON DISABLED'",
    ] {
        assert!(text.lines().any(|l| l == step), "{step}: {text}");
    }
}

/// The same scenario on five real drive descriptions of different vendors (Schunk, an integrated
/// stepper ISD860, Pilz PRBT as a DCF, the ros2_canopen CiA 402 slave, and python-canopen's e35):
/// each runs what its 0x6502 supports, with its own PDO layout.
#[test]
fn base_node_402_drives_real_descriptions_of_five_vendors() {
    // (file, 0x6502, homing mode among them)
    for (file, modes, homing) in [
        ("rosc-Schunk.eds", "0x00000063", true),
        ("rosc-ISD860.eds", "0x00000065", true),
        ("ros2c-prbt_0_1.dcf", "0x00000043", false),
        ("ros2c-cia402_slave.eds", "0x000000A5", true),
        ("pycanopen-e35.eds", "0x000303EF", true),
    ] {
        let eds = corpus(file);
        let eds = eds.to_str().unwrap();
        let node = start(&["--od", &format!("{eds}@7")]);
        let text = master(&node, &["drive402", "--eds", eds, "--node-id", "7"]);
        let want = format!("ok   supported drive modes {modes}");
        assert!(text.lines().any(|l| l == want), "{file}: {text}");
        assert_eq!(
            text.lines().any(|l| l == "ok   homing(): True"),
            homing,
            "{file}: {text}"
        );
        assert!(
            text.lines()
                .any(|l| l == "ok   target reached (status bit 10)"),
            "{file}: {text}"
        );
    }
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

/// python-canopen's LSS master: Fastscan among two unconfigured nodes finds the lower LSS address
/// (the second I/O device, whose serial number counts up to 2, before the drive with product code
/// 0x402), gives it node-ID 20 and stores it; the node boots as node 20 at once. Restarted with the
/// same storage, the process brings it up as node 20 again.
#[test]
fn lss_master_finds_configures_and_stores_a_node_id() {
    let dir = tempfile::tempdir().unwrap();
    let storage = dir.path().to_str().unwrap();
    let io = root().join("examples/io-device.eds");
    let io = io.to_str().unwrap();
    let drive = root().join("examples/drive.eds");
    let drive = drive.to_str().unwrap();
    let args = [
        "--storage",
        storage,
        "--od",
        &format!("{io}@6"),
        "--od",
        &format!("{io}@lss"),
        "--od",
        &format!("{drive}@lss"),
    ];
    let node = start(&args);
    let text = master(&node, &["lss", "--eds", io, "--assign", "20"]);
    assert!(
        text.lines().any(|l| l == "ok   serial number 0x00000002"),
        "{text}"
    );
    drop(node);
    // The second node's LSS configuration: node-ID 0x14, bit timing 4 (125 kbit/s).
    let kept = std::fs::read_to_string(dir.path().join("node2.params.lss")).unwrap();
    assert!(kept.contains("\n0000:01 14\n0000:02 04\n"), "{kept}");
    let port = free_port();
    let mut bus_spec = vec![format!("socketcand-listen:127.0.0.1:{port}")];
    bus_spec.extend(args.iter().map(|s| s.to_string()));
    let mut child = Command::new(NODE)
        .arg("--bus")
        .args(&bus_spec)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut out = std::io::BufReader::new(child.stdout.take().unwrap());
    let mut text = String::new();
    for _ in 0..3 {
        std::io::BufRead::read_line(&mut out, &mut text).unwrap();
    }
    let restarted = NodeProcess { child, port };
    assert!(
        text.contains("canopen-node: node 20 from "),
        "the stored node-ID at power-on: {text}"
    );
    let mut bus = SocketcandClient::connect("127.0.0.1", restarted.port, "can0").unwrap();
    bus.send(&CanFrame::new(0x614, &[0x40, 0x14, 0x10, 0, 0, 0, 0, 0]).unwrap())
        .unwrap();
    // EMCY COB-ID 0x80 + 20.
    assert_eq!(
        wait_for(&mut bus, 0x594).data8(),
        [0x43, 0x14, 0x10, 0, 0x94, 0, 0, 0]
    );
}

/// A RemoteNode moves 3000 bytes into the I/O device's DOMAIN by block download and reads them back
/// by block and by segmented upload.
#[test]
fn remote_node_block_transfers() {
    let io = root().join("examples/io-device.eds");
    let io = io.to_str().unwrap();
    let node = start(&["--od", &format!("{io}@9")]);
    master(&node, &["block", "--eds", io, "--node-id", "9"]);
}

#[test]
fn bad_arguments_exit_2_with_one_line() {
    let io = root().join("examples/io-device.eds");
    let io = io.to_str().unwrap();
    let esi = root().join("fixtures/smd/SMD23K-B_SMD24K.esi.xml");
    let cases: Vec<(Vec<String>, String)> = vec![
        (
            vec!["--od".into(), io.into()],
            format!(
                "canopen-node: {io}: the EDS gives no node-ID: add @ID (e.g. {io}@5) or --node-id"
            ),
        ),
        (
            vec![
                "--od".into(),
                format!("{io}@5"),
                "--od".into(),
                format!("{io}@5"),
            ],
            "canopen-node: node-ID 5 is given to two nodes".into(),
        ),
        (
            vec!["--od".into(), format!("{}@5", esi.display())],
            format!(
                "canopen-node: {}: an ESI describes an EtherCAT device; run it with ethercat-node",
                esi.display()
            ),
        ),
        (
            vec!["--od".into(), "/nonexistent/x.eds@5".into()],
            "canopen-node: /nonexistent/x.eds: ".into(),
        ),
        (
            vec![
                "--od".into(),
                format!("{io}@5"),
                "--capture".into(),
                "/nonexistent/dir/x.pcapng".into(),
            ],
            "canopen-node: --capture /nonexistent/dir/x.pcapng: No such file or directory (os error 2)"
                .into(),
        ),
    ];
    for (args, says) in cases {
        let out = Command::new(NODE)
            .args(["--bus", "socketcand-listen:127.0.0.1:0"])
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with(&says), "{args:?}: {err}");
    }
    // clap refuses a node-ID out of range.
    let out = Command::new(NODE)
        .args(["--od", &format!("{io}@128")])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("node-ID 128 is outside 1 to 127 (or lss for none)"));
}

/// CPU time (user + system) a process has used so far, from /proc/PID/stat (fields 14 and 15, in
/// clock ticks of 1/100 s on Linux).
fn cpu_seconds(pid: u32) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap();
    // The command name (field 2) is in parentheses and may hold spaces: count from after it.
    let rest = &stat[stat.rfind(')').unwrap() + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: u64 = fields[11].parse::<u64>().unwrap() + fields[12].parse::<u64>().unwrap();
    ticks as f64 / 100.0
}

/// A drive waiting for LSS to give it a node-ID (`FILE@lss`) sleeps until a frame comes: over two
/// idle seconds it uses a few milliseconds of CPU, as the same drive with a node-ID does (a deadline
/// it reported but never ran kept the process in a busy loop, a whole core).
#[test]
fn an_idle_node_without_a_node_id_uses_no_cpu() {
    let drive = root().join("examples/drive.eds");
    let drive = drive.to_str().unwrap();
    let node = start(&[
        "--od",
        &format!("{drive}@lss"),
        "--od",
        &format!("{drive}@5"),
    ]);
    // The start-up is behind us once the process has printed its first line; measure from here.
    let before = cpu_seconds(node.child.id());
    let wall = Instant::now();
    std::thread::sleep(Duration::from_secs(2));
    let used = cpu_seconds(node.child.id()) - before;
    let share = used / wall.elapsed().as_secs_f64();
    // Two idle nodes (one drive's 1 ms control cycle is all that runs) take well under a tenth of a
    // core; a busy loop takes all a core it is given, and even on a machine busy with other work,
    // more than that.
    assert!(
        share < 0.10,
        "{used:.2} s of CPU in 2 s idle ({:.0} %)",
        share * 100.0
    );
}

/// A write the drive refuses is answered with the abort code CiA 402 gives it and said on the node's
/// log in one line naming the axis, the object, the value and the rule: 0x6083 profile acceleration
/// = 0 is 0x06090032 (value too low), 0x6060 = 7 (interpolated position, which the example drive does
/// not run) 0x06090030, and neither changes the value.
#[test]
fn a_refused_write_is_explained_on_the_log() {
    let text = refuse_two_writes(&[]);
    let lines: Vec<&str> = text
        .lines()
        .filter(|l| l.contains("refused with"))
        .collect();
    assert_eq!(lines.len(), 2, "{text}");
    assert!(
        lines[0].contains(
            "axis 0: 0x6083 = 0 refused with 0x06090032 (Value of parameter written too low \
             (download only)): it must be above 0: a ramp or speed of 0 would never end"
        ),
        "{text}"
    );
    assert!(
        lines[1].contains(
            "axis 0: 0x6060 = 7 refused with 0x06090030 (Invalid value for parameter (download \
             only)): the modes this drive runs are 0x000003A5 (bit mode − 1, as in 0x6502)"
        ),
        "{text}"
    );
}

/// With --json the log is JSON lines: the refusal's line is an object with its fields.
#[test]
fn with_json_a_refusal_is_a_json_object_on_the_log() {
    let text = refuse_two_writes(&["--json"]);
    let lines: Vec<&str> = text
        .lines()
        .filter(|l| l.contains("refused with"))
        .collect();
    assert_eq!(lines.len(), 2, "{text}");
    let want = [
        r#""message":"axis 0: 0x6083 = 0 refused with 0x06090032 (Value of parameter written too low (download only)): it must be above 0: a ramp or speed of 0 would never end","axis":0,"index":"0x6083","value":0.0,"code":"0x06090032","target":"ds402::drive"}"#,
        r#""message":"axis 0: 0x6060 = 7 refused with 0x06090030 (Invalid value for parameter (download only)): the modes this drive runs are 0x000003A5 (bit mode − 1, as in 0x6502)","axis":0,"index":"0x6060","value":7.0,"code":"0x06090030","target":"ds402::drive"}"#,
    ];
    for (line, want) in lines.iter().zip(want) {
        assert!(line.starts_with(r#"{"timestamp":""#), "{line}");
        assert!(line.contains(r#","level":"WARN","#), "{line}");
        assert!(line.ends_with(want), "{line}");
    }
}

/// canopen-node with the example drive and `extra` arguments; two writes the drive refuses, each
/// answered with its abort code and changing nothing; what the node logged.
fn refuse_two_writes(extra: &[&str]) -> String {
    let port = free_port();
    let log = tempfile::NamedTempFile::new().unwrap();
    let mut child = Command::new(NODE)
        .args(extra)
        .arg("--bus")
        .arg(format!("socketcand-listen:127.0.0.1:{port}"))
        .arg("--od")
        .arg(format!("{}@5", root().join("examples/drive.eds").display()))
        .env("NO_COLOR", "1")
        .stdout(std::process::Stdio::null())
        .stderr(log.reopen().unwrap())
        .spawn()
        .unwrap();
    let end = Instant::now() + Duration::from_secs(20);
    let mut bus = loop {
        match SocketcandClient::connect("127.0.0.1", port, "can0") {
            Ok(bus) => break bus,
            Err(_) if Instant::now() < end => std::thread::sleep(Duration::from_millis(50)),
            Err(e) => panic!("canopen-node does not listen: {e}"),
        }
    };
    let sdo = |bus: &mut SocketcandClient, data: [u8; 8]| {
        bus.send(&CanFrame::new(0x605, &data).unwrap()).unwrap();
        wait_for(bus, 0x585).data8()
    };
    // Download 0x6083:00 = 0 (4 bytes): abort 0x06090032.
    assert_eq!(
        sdo(&mut bus, [0x23, 0x83, 0x60, 0, 0, 0, 0, 0]),
        [0x80, 0x83, 0x60, 0, 0x32, 0x00, 0x09, 0x06]
    );
    // Download 0x6060:00 = 7 (1 byte): abort 0x06090030.
    assert_eq!(
        sdo(&mut bus, [0x2F, 0x60, 0x60, 0, 7, 0, 0, 0]),
        [0x80, 0x60, 0x60, 0, 0x30, 0x00, 0x09, 0x06]
    );
    // Neither changed anything: 0x6083 is still the description's 100,000 (0x000186A0), 0x6060 0.
    assert_eq!(
        sdo(&mut bus, [0x40, 0x83, 0x60, 0, 0, 0, 0, 0]),
        [0x43, 0x83, 0x60, 0, 0xA0, 0x86, 0x01, 0x00]
    );
    assert_eq!(
        sdo(&mut bus, [0x40, 0x60, 0x60, 0, 0, 0, 0, 0]),
        [0x4F, 0x60, 0x60, 0, 0, 0, 0, 0]
    );
    let _ = child.kill();
    let _ = child.wait();
    std::fs::read_to_string(log.path()).unwrap()
}
