//! `sdo-tool` on a real kernel's SocketCAN: vcan0 inside the VM that `tests/vcan/run` boots (built
//! with `--features vcan-tests`, run there with `--test-threads=1` after the node's vcan tests; the
//! runner builds the `x67-node` binary this test starts).

mod common;

use std::process::{Command, Stdio};
use std::time::Duration;

use socketcan_node::test_util::next_on;
use socketcan_node::transport::SocketCanBus;
use testkit::sibling_binary;

/// The `x67-node` binary on vcan0 as node `id`, returned once its boot-up message is on the bus (the
/// VM emulates its CPU, so the start takes a variable time).
fn spawn_node(id: u8) -> std::process::Child {
    let mut bus = SocketCanBus::open("vcan0").expect("vcan0 is up (tests/vcan/run brings it up)");
    let mut node = Command::new(sibling_binary("x67-node"))
        .args(["--bus", "socketcan:vcan0", "--node-id", &id.to_string()])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let boot = next_on(&mut bus, 0x700 + u16::from(id), Duration::from_secs(30));
    if boot.as_ref().map(|(frame, _)| frame.data()) != Some(&[0u8][..]) {
        node.kill().unwrap();
        panic!("x67-node {id} sent no boot-up message within 30 s: {boot:?}");
    }
    node
}

/// `sdo-tool` on vcan0 against the `x67-node` binary: a string read, a write read back, an abort.
#[test]
fn sdo_tool_on_vcan() {
    let mut node = spawn_node(7);
    let bus = ["--bus", "socketcan:vcan0", "--timeout-ms", "5000"];
    assert_eq!(
        common::sdo_tool_ok(&bus, &["read", "7", "0x1008:00", "vs"]),
        "\"X67BC4321-10 / X67SM2436\"\n"
    );
    common::sdo_tool_ok(&bus, &["write", "7", "0x1017:00", "u16", "321"]);
    assert_eq!(
        common::sdo_tool_ok(&bus, &["read", "7", "0x1017:00", "u16"]),
        "321\n"
    );
    let refused = common::sdo_tool(&bus, &["write", "7", "0x2110:00", "u8", "168"]);
    assert_eq!(refused.status.code(), Some(1));
    node.kill().unwrap();
    node.wait().unwrap();
}
