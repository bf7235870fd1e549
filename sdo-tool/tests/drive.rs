//! `sdo-tool drive` against the generic CiA 402 drive of `canopen-node` (`examples/drive.eds` at
//! node 2) on a socketcand server of 127.0.0.1: each command's line, the statusword's bits worked out
//! from CiA 402-2's tables, the positions the moves reach, and a refusal explained.

mod common;

use std::path::Path;
use std::time::Duration;

use common::sdo_tool;

/// The drive at node 2 on a socketcand server of its own (stopped when dropped), and the bus its
/// clients give.
struct Node(#[allow(dead_code)] common::Proc, String);

fn node() -> Node {
    let eds = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/drive.eds");
    let (p, port) = common::node_server(&["--od", &format!("{}@2", eds.display())]);
    Node(p, common::socketcand_bus(port))
}

impl Node {
    /// `sdo-tool drive 2 ARGS`: exit code, standard output, standard error.
    fn drive(&self, args: &[&str]) -> (Option<i32>, String, String) {
        let bus = &self.1;
        let mut argv = vec!["drive", "2"];
        argv.extend_from_slice(args);
        let o = sdo_tool(&["--bus", bus], &argv);
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    }

    fn ok(&self, args: &[&str]) -> String {
        let (code, out, err) = self.drive(args);
        assert_eq!(code, Some(0), "drive {args:?}: {err}");
        out.trim_end().to_string()
    }

    fn write(&self, args: &[&str]) {
        common::sdo_tool_ok(&["--bus", &self.1], args);
    }
}

// CiA 402-2 statusword: bit 0 ready to switch on, 1 switched on, 2 operation enabled, 3 fault,
// 4 voltage enabled, 5 quick stop, 6 switch on disabled, 9 remote, 10 target reached, 12 the
// mode's own (set-point acknowledge, speed is zero, homing attained).
const DISABLED: &str = "SWITCH ON DISABLED";

#[test]
fn status_enable_move_home_jog_stop_disable() {
    let n = node();
    // Switch on disabled: bits 5, 6, 9 = 0x0260.
    assert_eq!(
        n.ok(&["status"]),
        format!(
            "node 2: {DISABLED}, no mode (0), position 0, velocity 0; statusword 0x0260: quick \
             stop, switch on disabled, remote"
        )
    );
    // Operation enabled: bits 0, 1, 2, 4, 5, 9 = 0x0237.
    assert_eq!(
        n.ok(&["enable"]),
        "node 2: OPERATION ENABLED, no mode (0), position 0, velocity 0; statusword 0x0237: ready \
         to switch on, switched on, operation enabled, voltage enabled, quick stop, remote"
    );
    // At the target: bit 10 too, 0x0637.
    assert_eq!(
        n.ok(&["move", "1000"]),
        "node 2: OPERATION ENABLED, profile position (1), position 1000, velocity 0; statusword \
         0x0637: ready to switch on, switched on, operation enabled, voltage enabled, quick stop, \
         remote, target reached"
    );
    let out = n.ok(&[
        "move",
        "--relative",
        "-1500",
        "--velocity",
        "2000",
        "--acceleration",
        "8000",
    ]);
    assert!(out.contains(", position -500, velocity 0;"), "{out}");
    // Homing on the current position (method 35): position 0, homing attained (bit 12), 0x1637.
    assert_eq!(
        n.ok(&["home", "35"]),
        "node 2: OPERATION ENABLED, homing (6), position 0, velocity 0; statusword 0x1637: ready \
         to switch on, switched on, operation enabled, voltage enabled, quick stop, remote, \
         target reached, homing attained"
    );
    n.ok(&["jog", "200"]);
    std::thread::sleep(Duration::from_millis(300));
    let out = n.ok(&["status"]);
    assert!(
        out.contains(": OPERATION ENABLED, profile velocity (3), position "),
        "{out}"
    );
    assert!(!out.contains(", velocity 0;"), "moving: {out}");
    let out = n.ok(&["stop"]);
    assert!(out.contains(", velocity 0;"), "{out}");
    assert!(out.contains(", target reached"), "{out}");
    assert_eq!(
        n.ok(&["disable"]).split(';').nth(1).unwrap().trim(),
        "statusword 0x0260: quick stop, switch on disabled, remote"
    );
}

#[test]
fn a_move_into_a_limit_switch_is_refused_with_the_drive_s_error_code() {
    let n = node();
    // The simulated positive limit switch at 100 (the generic drive's simulation record 0x5FF0).
    n.write(&["write", "2", "0x5FF0:4", "i32", "100"]);
    n.ok(&["enable"]);
    let (code, out, err) = n.drive(&["move", "1000"]);
    assert_eq!((code, out.as_str()), (Some(1), ""));
    // Fault: bit 3, with 5 and 9: 0x0228; 0x8612 is CiA 402-2's reference limit.
    assert_eq!(
        err.trim(),
        "sdo-tool: drive 2: the move (target reached, bit 10) not done: FAULT (statusword \
         0x0228), error code 0x603F = 0x8612 (reference limit)"
    );
    let out = n.ok(&["status"]);
    assert!(
        out.ends_with("; error code 0x8612 (reference limit)"),
        "{out}"
    );
    // enable clears the fault first.
    let out = n.ok(&["enable"]);
    assert!(out.starts_with("node 2: OPERATION ENABLED,"), "{out}");
    // A homing method the drive does not run: its SDO abort.
    let (code, _, err) = n.drive(&["home", "99"]);
    assert_eq!(code, Some(1));
    assert_eq!(
        err.trim(),
        "sdo-tool: 0x6098:00: SDO abort 0x06090030 (Invalid value for parameter (download only))"
    );
}

#[test]
fn status_as_json() {
    let n = node();
    let o = sdo_tool(&["--bus", &n.1, "--json"], &["drive", "2", "status"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(
        v,
        serde_json::json!({"node": 2, "state": DISABLED, "statusword": "0x0260",
            "bits": ["quick stop", "switch on disabled", "remote"], "mode": 0,
            "mode_name": "no mode", "position": 0, "velocity": 0, "error_code": "0x0000"})
    );
}

/// The same drive as an EtherCAT slave (`ethercat-node` with `examples/drive.esi.xml`) on a veth
/// pair. Each command runs the chain in Op; the controlword, target position and mode, which the
/// drive maps in its RxPDO 0x1600, go by process data (written by CoE they would be overwritten at
/// the next cycle, and the drive would never be enabled). After each command the chain is back in
/// Init, and this drive, left without its master, in SWITCH ON DISABLED.
#[test]
fn on_ethercat_the_chain_runs_in_op_for_each_command() {
    let esi = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/drive.esi.xml");
    let link = testkit::link::Link::node(&["--esi", esi.to_str().unwrap()]);
    let drive = |args: &[&str]| {
        let mut argv = vec!["drive", "1"];
        argv.extend_from_slice(args);
        let o = sdo_tool(&["--ethercat", &link.master], &argv);
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert_eq!(o.status.code(), Some(0), "drive {args:?}: {err}");
        String::from_utf8_lossy(&o.stdout).trim_end().to_string()
    };
    assert_eq!(
        drive(&["status"]),
        format!(
            "node 1: {DISABLED}, cyclic synchronous position (8), position 0, velocity 0; \
             statusword 0x0260: quick stop, switch on disabled, remote"
        )
    );
    assert_eq!(
        drive(&["move", "1000"]),
        "node 1: OPERATION ENABLED, profile position (1), position 1000, velocity 0; statusword \
         0x0637: ready to switch on, switched on, operation enabled, voltage enabled, quick stop, \
         remote, target reached"
    );
    assert_eq!(
        drive(&["status"]),
        format!(
            "node 1: {DISABLED}, profile position (1), position 1000, velocity 0; statusword \
             0x0260: quick stop, switch on disabled, remote"
        )
    );
    let out = drive(&["move", "--relative", "-250"]);
    assert!(out.contains(", position 750, velocity 0;"), "{out}");
    assert_eq!(
        drive(&["home", "35"]),
        "node 1: OPERATION ENABLED, homing (6), position 0, velocity 0; statusword 0x1637: ready \
         to switch on, switched on, operation enabled, voltage enabled, quick stop, remote, \
         target reached, homing attained"
    );
}

/// `status --watch`: a line every 200 ms until Ctrl-C (SIGINT), then exit 0.
#[test]
fn status_watch_repeats_until_interrupted() {
    use std::io::BufRead;
    let n = node();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(["--bus", &n.1, "drive", "2", "status", "--watch"])
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut out = std::io::BufReader::new(child.stdout.take().unwrap());
    let mut lines = Vec::new();
    // Two lines, then Ctrl-C.
    for _ in 0..2 {
        let mut l = String::new();
        out.read_line(&mut l).unwrap();
        lines.push(l);
    }
    let killed = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut out, &mut rest).unwrap();
    lines.extend(rest.lines().map(|l| format!("{l}\n")));
    assert_eq!(child.wait().unwrap().code(), Some(0));
    let prefix = format!("node 2: {DISABLED}, no mode (0)");
    assert!(lines.iter().all(|l| l.starts_with(&prefix)), "{lines:?}");
}
