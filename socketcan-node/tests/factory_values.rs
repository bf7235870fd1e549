//! What `canopen-node` reports where a real drive description leaves values out, as a user sees it:
//! one startup line per value filled in or adjusted (`--explain` prints only those and opens no
//! bus, `--json` prints them as JSON objects), the values themselves over SDO on socketcand at
//! 127.0.0.1, kept through NMT reset node and restore defaults, and python-canopen's `BaseNode402`
//! switching the mode of a drive whose description gives 0x6502 no value.

use std::io::BufRead;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use testkit::free_port;

use socketcan_node::transport::{BusEvent, CanBus, SocketcandClient};
use socketcan_node::CanFrame;

const NODE: &str = env!("CARGO_BIN_EXE_canopen-node");

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A file of the shared corpus of real descriptions (beside the checkout).
fn corpus(name: &str) -> String {
    let p = root().join("../shared/corpus/eds").join(name);
    assert!(
        p.is_file(),
        "{} is missing: the corpus lies beside the checkout",
        p.display()
    );
    p.display().to_string()
}

/// What Schunk's EDS (no 0x1000 value, read-only 0x606B and 0x606C mapped into RPDO 2, no 0x6073,
/// 0x6075, 0x6081, 0x6083 values) is given as node 5.
const SCHUNK: [&str; 6] = [
    "canopen-node: node 5: 0x1000 device type = 0x00020192 (the description gives no value: a CiA \
     402 servo drive)",
    "canopen-node: node 5: 0x1601 number of mapped objects of RPDO 2 = 0 (the description maps \
     0x606B0020 (read-only), 0x606C0020 (read-only) into RPDO 2, which no RPDO takes: left out)",
    "canopen-node: node 5: 0x6073 max current = 3000 ‰ of the rated current (the description gives \
     no value (0), which would leave the motor no current: a factory default)",
    "canopen-node: node 5: 0x6075 motor rated current = 3000 mA (the description gives no value \
     (0), which makes every current given in ‰ of it 0: a factory default)",
    "canopen-node: node 5: 0x6081 profile velocity = 10000 counts/s (the description gives no value \
     (0), which would stop every profile position move: a factory default)",
    "canopen-node: node 5: 0x6083 profile acceleration = 100000 counts/s² (the description gives no \
     value (0), which would stop every move: a factory default)",
];

fn run(args: &[&str]) -> (String, bool) {
    let out = Command::new(NODE).args(args).output().unwrap();
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        out.status.success(),
    )
}

/// `--explain`: exactly the lines, node by node, and exit 0 without opening the bus (the one given
/// here has nobody listening); a description with nothing left out prints nothing. `--motor
/// stepper` says a stepper's device type.
#[test]
fn explain_prints_each_value_filled_in_and_opens_no_bus() {
    let schunk = corpus("rosc-Schunk.eds");
    let drive = root().join("examples/drive.eds").display().to_string();
    let closed = format!("socketcand://127.0.0.1:{}/can0", free_port());
    let (out, ok) = run(&[
        "--bus",
        &closed,
        "--explain",
        "--od",
        &format!("{schunk}@5"),
        "--od",
        &format!("{drive}@6"),
    ]);
    assert!(ok);
    let want: String = SCHUNK.iter().map(|l| format!("{l}\n")).collect();
    assert_eq!(out, want);

    let (out, ok) = run(&[
        "--explain",
        "--motor",
        "stepper",
        "--od",
        &format!("{schunk}@5"),
    ]);
    assert!(ok);
    assert_eq!(
        out.lines().next().unwrap(),
        "canopen-node: node 5: 0x1000 device type = 0x00040192 (the description gives no value: a \
         CiA 402 stepper motor drive)"
    );
}

/// `--json`: the same events as JSON objects, one per line, with the node-ID, the entry, the value
/// as a number or a string, the unit where it has one, and the reason.
#[test]
fn json_gives_the_same_events_as_objects() {
    let cog = corpus("pycanopen-cog.eds");
    let (out, ok) = run(&["--explain", "--json", "--od", &format!("{cog}@6")]);
    assert!(ok);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 13, "{out}");
    assert_eq!(
        lines[0],
        r#"{"event":"filled","node":6,"index":"0x1008","sub":0,"name":"manufacturer device name","value":"cog","reason":"the description gives no value: its product name"}"#
    );
    assert_eq!(
        lines[1],
        r#"{"event":"filled","node":6,"index":"0x1018","sub":1,"name":"vendor-ID","value":1569,"reason":"the description gives no value: its identity's vendor-ID"}"#
    );
    assert_eq!(
        lines[2],
        r#"{"event":"adjusted","node":6,"index":"0x1806","sub":1,"name":"COB-ID of TPDO 7","value":2147483648,"reason":"the description gives 0x00000000, a valid PDO on CAN-ID 0x000, which CiA 301 keeps from PDOs: not valid"}"#
    );
    assert_eq!(
        lines[3],
        r#"{"event":"adjusted","node":6,"index":"0x6072","sub":0,"name":"max torque","value":3000,"unit":"‰ of the rated torque","reason":"the description gives 0, which would leave the motor no torque: a factory default"}"#
    );
    assert_eq!(
        lines[12],
        r#"{"event":"filled","node":6,"index":"0x6502","sub":0,"name":"supported drive modes","value":37,"reason":"the description gives no value: the modes this drive runs whose objects it has"}"#
    );
}

/// The node process; killed when dropped.
struct NodeProcess {
    child: Child,
    port: u16,
    /// What it printed at start, up to the line that says where it listens.
    startup: Vec<String>,
}

impl Drop for NodeProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn start(args: &[&str]) -> NodeProcess {
    let port = free_port();
    let mut child = Command::new(NODE)
        .arg("--bus")
        .arg(format!("socketcand-listen:127.0.0.1:{port}"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut out = std::io::BufReader::new(child.stdout.take().unwrap());
    let mut startup = Vec::new();
    loop {
        let mut line = String::new();
        assert!(out.read_line(&mut line).unwrap() > 0, "{startup:?}");
        let line = line.trim_end().to_string();
        let last = line.starts_with("canopen-node: listening");
        startup.push(line);
        if last {
            break;
        }
    }
    // The rest of what it prints goes nowhere.
    std::thread::spawn(move || std::io::copy(&mut out, &mut std::io::sink()));
    NodeProcess {
        child,
        port,
        startup,
    }
}

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

/// The expedited SDO upload of `index:sub` from `node`: the answer's 8 bytes.
fn upload(bus: &mut dyn CanBus, node: u8, index: u16, sub: u8) -> [u8; 8] {
    let [lo, hi] = index.to_le_bytes();
    bus.send(&CanFrame::new(0x600 + u16::from(node), &[0x40, lo, hi, sub, 0, 0, 0, 0]).unwrap())
        .unwrap();
    wait_for(bus, 0x580 + u16::from(node)).data8()
}

/// Schunk's EDS (0x1000 without a value) as node 5 and python-canopen's cog.eds (0x6502 and
/// 0x1018:01 without values, 0x6072 = 0, TPDO 7 valid on CAN-ID 0x000) as node 6: the startup lines after each node's own line;
/// over SDO, the exact bytes: 0x1000 = 0x00020192, 0x6502 = 0x25 (pp, pv, hm), 0x1018:01 =
/// 0x0621, 0x6072 = 3000; the same after NMT reset node and after restore defaults (0x1011:01
/// "load") and a reset, the values being the entries' defaults.
#[test]
fn a_node_reports_the_values_over_sdo_and_keeps_them_through_resets() {
    let schunk = corpus("rosc-Schunk.eds");
    let cog = corpus("pycanopen-cog.eds");
    let node = start(&["--od", &format!("{schunk}@5"), "--od", &format!("{cog}@6")]);
    let s = &node.startup;
    assert_eq!(
        s[0],
        format!("canopen-node: node 5 from {schunk}, a CiA 402 drive")
    );
    assert_eq!(s[1..7], SCHUNK.map(String::from));
    assert_eq!(
        s[7],
        format!("canopen-node: node 6 from {cog}, a CiA 402 drive")
    );
    assert_eq!(s.len(), 7 + 1 + 13 + 1, "{s:#?}");
    assert_eq!(
        s[8],
        "canopen-node: node 6: 0x1008 manufacturer device name = \"cog\" (the description gives no \
         value: its product name)"
    );

    let mut bus = SocketcandClient::connect("127.0.0.1", node.port, "can0").unwrap();
    let check = |bus: &mut dyn CanBus| {
        assert_eq!(
            upload(bus, 5, 0x1000, 0),
            [0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]
        );
        assert_eq!(
            upload(bus, 6, 0x6502, 0),
            [0x43, 0x02, 0x65, 0x00, 0x25, 0x00, 0x00, 0x00]
        );
        assert_eq!(
            upload(bus, 6, 0x1018, 1),
            [0x43, 0x18, 0x10, 0x01, 0x21, 0x06, 0x00, 0x00]
        );
        // 0x6072 is UNSIGNED16 in cog.eds: 3000 = 0x0BB8.
        assert_eq!(
            upload(bus, 6, 0x6072, 0),
            [0x4B, 0x72, 0x60, 0x00, 0xB8, 0x0B, 0x00, 0x00]
        );
        // TPDO 7 not valid: nothing of it on 0x000.
        assert_eq!(
            upload(bus, 6, 0x1806, 1),
            [0x43, 0x06, 0x18, 0x01, 0x00, 0x00, 0x00, 0x80]
        );
    };
    check(&mut bus);
    // NMT reset node 6: its boot-up, then the same values.
    bus.send(&CanFrame::new(0x000, &[0x81, 6]).unwrap())
        .unwrap();
    assert_eq!(wait_for(&mut bus, 0x706).data8()[0], 0);
    check(&mut bus);
    // Restore defaults ("load" = 0x64616F6C), then a reset: still the same values.
    bus.send(&CanFrame::new(0x606, &[0x23, 0x11, 0x10, 0x01, b'l', b'o', b'a', b'd']).unwrap())
        .unwrap();
    assert_eq!(
        wait_for(&mut bus, 0x586).data8(),
        [0x60, 0x11, 0x10, 0x01, 0, 0, 0, 0]
    );
    bus.send(&CanFrame::new(0x000, &[0x81, 6]).unwrap())
        .unwrap();
    assert_eq!(wait_for(&mut bus, 0x706).data8()[0], 0);
    check(&mut bus);
}

/// python-canopen's `BaseNode402` on cog.eds, whose 0x6502 has no value: it reads the supported
/// modes the node reports (0x25) and switches to profile position, which it refused ("not
/// supported") while 0x6502 read 0; its identity reads the vendor of the EDS's [DeviceInfo].
#[test]
fn base_node_402_switches_the_mode_of_a_drive_whose_description_lists_none() {
    let cog = corpus("pycanopen-cog.eds");
    let node = start(&["--od", &format!("{cog}@6")]);
    let script = r#"
import sys, canopen
from canopen.profiles.p402 import BaseNode402
network = canopen.Network()
network.connect(interface="socketcand", host="127.0.0.1", port=int(sys.argv[1]), channel="can0")
node = BaseNode402(6, sys.argv[2])
network.add_node(node)
print(hex(node.sdo[0x6502].raw), hex(node.sdo[0x1018][1].raw), node.sdo[0x1008].raw)
node.op_mode = "PROFILED POSITION"
print(node.op_mode)
network.disconnect()
"#;
    let out = Command::new("python3")
        .arg("-c")
        .arg(script)
        .arg(node.port.to_string())
        .arg(&cog)
        .output()
        .expect("python3 runs (scripts/setup-test-deps installs python-canopen)");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(stdout, "0x25 0x621 cog\nPROFILED POSITION\n");
}
