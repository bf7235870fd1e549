//! `sdo-tool dump`, then `sdo-tool apply`, of an untouched drive round-trips: on every CiA 402 EDS
//! and DCF of the corpus beside the checkout (the files with object 0x6040), run by `canopen-node`
//! as node 5 on a socketcand server of its own on 127.0.0.1, every parameter the node reports is
//! written back as it was read, and none is refused (a drive reports only values it takes back:
//! `ds402::drive::fill`).

mod common;

use std::path::Path;
use std::process::{Child, Command};

/// `canopen-node` running `file` as node 5 on a socketcand server of its own; killed when dropped.
struct Node {
    child: Child,
    bus: String,
}

impl Node {
    fn start(file: &Path) -> Node {
        let port = testkit::free_port();
        let (child, line) = testkit::start_until_first_line(
            Command::new(testkit::cargo_binary("socketcan-node", "canopen-node", &[]))
                .args(["--bus", &format!("socketcand-listen:127.0.0.1:{port}")])
                .arg("--od")
                .arg(format!("{}@5", file.display())),
        );
        assert!(line.starts_with("canopen-node: node 5 from "), "{line}");
        Node {
            child,
            bus: format!("socketcand://127.0.0.1:{port}/can0"),
        }
    }
}

impl Drop for Node {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
fn dump_then_apply_of_every_corpus_drive_refuses_nothing() {
    let dir = tempfile::tempdir().unwrap();
    for eds in testkit::corpus_drive_descriptions() {
        let file = eds.file_name().unwrap().to_string_lossy().into_owned();
        let node = Node::start(&eds);
        let dcf = dir.path().join(format!("{file}.dcf"));
        let eds_arg = eds.display().to_string();
        let dcf_arg = dcf.display().to_string();
        let out = common::sdo_tool(
            &["--bus", &node.bus],
            &["--od", &eds_arg, "dump", "5", "-o", &dcf_arg],
        );
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{file}: dump: {text}{err}");
        // The node is the one of the description: no warning about another identity, but where
        // the description contradicts itself (e35's [DeviceInfo] says vendor 101, product 25; its
        // 0x1018, which the node reports, 0xFF and 1).
        assert_eq!(
            err.contains("warning"),
            file == "pycanopen-e35.eds",
            "{file}: {err}"
        );
        let out = common::sdo_tool(&["--bus", &node.bus], &["apply", "5", &dcf_arg]);
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(
            out.status.success(),
            "{file}: apply exits {:?}:\n{text}{err}",
            out.status.code()
        );
        let last = text.lines().last().unwrap_or_default();
        assert!(
            last.ends_with(" skipped, 0 refused") && last.contains(" entries written, "),
            "{file}: {last}\n{text}{err}"
        );
        let written: usize = last
            .split(' ')
            .next()
            .and_then(|n| n.parse().ok())
            .unwrap_or(0);
        assert!(written > 0, "{file}: {last}");
    }
}
