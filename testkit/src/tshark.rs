//! Wireshark's reading of a capture, through `tshark` (Debian package `tshark`;
//! `scripts/setup-test-deps` installs it): its dissectors are the independent judge of the frames
//! a capture holds. [`clean`] asserts that tshark finds no malformed packet and no expert
//! information of severity error in a file; [`fields`] gives the protocol layers of every frame
//! with the fields asked for.
//!
//! tshark 4.0 dissects a SocketCAN frame's payload as CANopen only when told to ([`CANOPEN`]: the
//! "CAN next level dissector" decode-as table); EtherCAT (EtherType 0x88A4) it dissects by itself
//! (`ecat`, and `ecat_mailbox` for the mailboxes).

use std::path::Path;
use std::process::Command;

/// The decode-as that makes tshark dissect every SocketCAN payload as CANopen.
pub const CANOPEN: &[&str] = &["-d", "can.subdissector,canopen"];

/// The display filter of what tshark finds wrong: a malformed packet, or expert information of
/// severity error.
pub const PROBLEMS: &str = "_ws.malformed || _ws.expert.severity >= error";

/// `tshark -r FILE ARGS…`: its standard output, after it exited 0 (a failure says what tshark
/// said, and a missing tshark how to install it).
pub fn run(file: &Path, args: &[&str]) -> String {
    let out = Command::new("tshark")
        .arg("-r")
        .arg(file)
        .args(args)
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run tshark ({e}): `apt-get install tshark` (scripts/setup-test-deps)")
        });
    assert!(
        out.status.success(),
        "tshark -r {} {args:?}: {}",
        file.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Asserts that tshark, with `decode_as`, reads `file` without a malformed packet and without
/// expert information of severity error ([`PROBLEMS`] selects none), and that it holds frames.
pub fn clean(file: &Path, decode_as: &[&str]) {
    let all = run(file, decode_as);
    assert!(!all.trim().is_empty(), "{}: no frames", file.display());
    let args: Vec<&str> = decode_as.iter().copied().chain(["-Y", PROBLEMS]).collect();
    let problems = run(file, &args);
    assert!(
        problems.trim().is_empty(),
        "tshark finds problems in {}:\n{problems}\nall frames:\n{all}",
        file.display()
    );
}

/// Every frame of `file` as tshark dissects it with `decode_as`: its protocol layers
/// (`frame.protocols`, e.g. `can:canopen`), then the value of each of `names` (several
/// occurrences joined by commas; empty where the frame has none).
pub fn fields(file: &Path, decode_as: &[&str], names: &[&str]) -> Vec<Vec<String>> {
    let mut args: Vec<&str> = decode_as.to_vec();
    args.extend([
        "-T",
        "fields",
        "-E",
        "occurrence=a",
        "-e",
        "frame.protocols",
    ]);
    for name in names {
        args.extend(["-e", name]);
    }
    run(file, &args)
        .lines()
        .map(|l| l.split('\t').map(str::to_string).collect())
        .collect()
}
