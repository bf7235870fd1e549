//! `sdo-tool` on a real kernel's SocketCAN: vcan0 inside the VM that `tests/vcan/run` boots (built
//! with `--features vcan-tests`, run there with `--test-threads=1` after the node's vcan tests; the
//! runner builds the `x67-node` binary this test starts).

mod common;

use socketcan_node::test_util::spawn_on_vcan;
use testkit::sibling_binary;

/// `sdo-tool` on vcan0 against the `x67-node` binary: a string read, a write read back, an abort.
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
    node.kill().unwrap();
    node.wait().unwrap();
}
