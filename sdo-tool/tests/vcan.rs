//! `sdo-tool` on a real kernel's SocketCAN: vcan0 inside the VM that `tests/vcan/run` boots (built
//! with `--features vcan-tests`, run there with `--test-threads=1` after the node's vcan tests; the
//! runner builds the `x67-node` binary this test starts).

mod common;

use socketcan_node::test_util::spawn_on_vcan;
use testkit::sibling_binary;

/// `sdo-tool` on vcan0 against the `x67-node` binary: a string read, a write read back, an abort,
/// and a read captured.
#[test]
fn sdo_tool_on_vcan() {
    let mut node = spawn_on_vcan(&sibling_binary("x67-node"), 7);
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
    // --capture on SocketCAN: the interface vcan0, the request sent, the answer received at the
    // time the kernel handed it over, in order (the heartbeat off, so that no other frame is on
    // the bus).
    common::sdo_tool_ok(&bus, &["write", "7", "0x1017:00", "u16", "0"]);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("vcan.pcapng");
    let captured = [&bus[..], &["--capture", file.to_str().unwrap()]].concat();
    let start = std::time::SystemTime::now();
    common::sdo_tool_ok(&captured, &["read", "7", "0x1017:00", "u16"]);
    let bytes = std::fs::read(&file).unwrap();
    let mut r = link_capture::pcapng::Reader::new(&bytes[..]);
    let mut seen = Vec::new();
    while let Some(p) = r.next_packet().unwrap() {
        assert!(p.time.unwrap() >= start);
        seen.push((p.direction, p.data.to_vec()));
    }
    use link_capture::pcapng::Direction::{Inbound, Outbound};
    #[rustfmt::skip]
    assert_eq!(
        seen,
        [
            (Some(Outbound), vec![0, 0, 0x06, 0x07, 8, 0, 0, 0, 0x40, 0x17, 0x10, 0, 0, 0, 0, 0]),
            (Some(Inbound), vec![0, 0, 0x05, 0x87, 8, 0, 0, 0, 0x4B, 0x17, 0x10, 0, 0, 0, 0, 0]),
        ]
    );
    assert_eq!(r.interfaces_seen()[0].name.as_deref(), Some("vcan0"));
    node.kill().unwrap();
    node.wait().unwrap();
}
