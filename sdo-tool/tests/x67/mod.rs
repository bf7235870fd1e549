//! The X67 node the `sdo-tool` command line tests run against: in process on an in-process bus
//! ([`Running`]), or as `x67-node` behind a socketcand server on 127.0.0.1 ([`hub`]).
#![allow(dead_code)]

use std::path::Path;
use std::process::Command;

use clap::Parser;
use sdo_tool::cli::{run, Args};
use sdo_tool::{ToolError, UsageError};
use socketcan_node::node::NodeConfig;
use socketcan_node::test_util::RunningNode;
use socketcan_node::transport::{CanBus, InProcessBus};

/// The node-ID of the node the tests run.
pub const ID: u8 = 5;

/// The X67 node's description.
pub fn eds() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures/x67/X67SM2436.eds")
        .display()
        .to_string()
}

/// Node 5 running on an in-process bus; stopped when dropped.
pub struct Running {
    _node: RunningNode,
    /// The bus it is on.
    pub bus: InProcessBus,
}

impl Running {
    /// Node 5, started.
    pub fn start() -> Running {
        let bus = InProcessBus::new();
        let node = RunningNode::start(NodeConfig::new(ID), bus.endpoint());
        std::thread::sleep(std::time::Duration::from_millis(50));
        Running { _node: node, bus }
    }

    /// Runs `sdo-tool ARGS…` in process: the output, or the error.
    pub fn tool(&self, argv: &[&str]) -> Result<String, ToolError> {
        let args = Args::try_parse_from(std::iter::once("sdo-tool").chain(argv.iter().copied()))
            .map_err(|e| ToolError::from(UsageError::CommandLine(e.to_string())))?;
        let bus: Box<dyn CanBus> = Box::new(self.bus.endpoint());
        let mut out = Vec::new();
        run(&args, Some(bus), &mut out)?;
        Ok(String::from_utf8(out).unwrap())
    }

    /// What the tool printed, and its error if it failed.
    pub fn tool_output(&self, argv: &[&str]) -> (String, Option<ToolError>) {
        let args =
            Args::try_parse_from(std::iter::once("sdo-tool").chain(argv.iter().copied())).unwrap();
        let bus: Box<dyn CanBus> = Box::new(self.bus.endpoint());
        let mut out = Vec::new();
        let e = run(&args, Some(bus), &mut out).err();
        (String::from_utf8(out).unwrap(), e)
    }
}

/// `x67-node` as node `id` and socketcand server on a free port of 127.0.0.1, once it listens.
pub fn hub(id: u8) -> (std::process::Child, u16) {
    hub_with(id, &[])
}

/// [`hub`] with `extra` arguments for `x67-node`.
pub fn hub_with(id: u8, extra: &[&str]) -> (std::process::Child, u16) {
    let port = testkit::free_port();
    let (child, _) = testkit::start_until_first_line(
        Command::new(testkit::cargo_binary("socketcan-node", "x67-node", &[]))
            .args(["--bus", &format!("socketcand-listen:127.0.0.1:{port}")])
            .args(["--node-id", &id.to_string()])
            .args(extra),
    );
    (child, port)
}
