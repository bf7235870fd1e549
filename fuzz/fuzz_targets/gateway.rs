#![no_main]
//! Arbitrary request lines into the CiA 309-3 gateway of sdo-tool, on a bus with no node (every SDO
//! request times out at once): no panic, one reply line at most per request, and a reply is one line.

use std::time::Duration;

use sdo_tool::gateway::Gateway;
use sdo_tool::Tool;
use socketcan_node::transport::InProcessBus;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let bus = InProcessBus::new();
    let mut tool = Tool::new(Box::new(bus.endpoint()), None);
    tool.set_timeout(Duration::from_millis(1));
    let mut gateway = Gateway::new(tool);
    for line in String::from_utf8_lossy(data).lines().take(64) {
        if let Some(reply) = gateway.handle(line) {
            assert!(!reply.contains('\n'), "{reply:?}");
        }
    }
});
