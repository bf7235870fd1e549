//! What the `sdo-tool` tests share.
#![allow(dead_code)]

use std::process::{Command, Output};

/// `sdo-tool GLOBAL… ARGS…` as a user runs it; GLOBAL are the bus options (`--bus …`, `--ethercat …`).
pub fn sdo_tool(global: &[&str], argv: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sdo-tool"))
        .args(global)
        .args(argv)
        .output()
        .expect("run sdo-tool")
}

/// `sdo-tool GLOBAL… ARGS…`, expected to succeed: its standard output.
pub fn sdo_tool_ok(global: &[&str], argv: &[&str]) -> String {
    let o = sdo_tool(global, argv);
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "sdo-tool {argv:?}: {:?}\n{stdout}{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
    stdout
}

/// A process of the test's (a node, a python-canopen script); killed when dropped.
pub struct Proc(pub std::process::Child);

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Starts `cmd` and waits for its first line of output (a node announces itself); the rest of its
/// output is drained so that it never blocks on a full pipe.
pub fn spawn(cmd: &mut Command) -> Proc {
    use std::io::{BufRead, BufReader};
    let mut child = cmd
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut out = BufReader::new(child.stdout.take().unwrap());
    let mut line = String::new();
    out.read_line(&mut line).unwrap();
    assert!(!line.is_empty(), "the process printed nothing and ended");
    std::thread::spawn(move || std::io::copy(&mut out, &mut std::io::sink()));
    Proc(child)
}

/// `canopen-node --bus BUS ARGS`, once it announced itself.
pub fn canopen_node(bus: &str, args: &[&str]) -> Proc {
    spawn(
        Command::new(testkit::cargo_binary("socketcan-node", "canopen-node", &[]))
            .args(["--bus", bus])
            .args(args),
    )
}

/// The bus a client of the socketcand server on `port` of 127.0.0.1 gives.
pub fn socketcand_bus(port: u16) -> String {
    format!("socketcand://127.0.0.1:{port}/can0")
}

/// `canopen-node ARGS` as a socketcand server on a free port of 127.0.0.1, taking connections: the
/// process and its port ([`socketcand_bus`] gives the bus of its clients).
pub fn node_server(args: &[&str]) -> (Proc, u16) {
    let port = testkit::free_port();
    let p = canopen_node(&format!("socketcand-listen:127.0.0.1:{port}"), args);
    for _ in 0..100 {
        if std::net::TcpStream::connect(("127.0.0.1", port)).is_ok() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    (p, port)
}
