//! FoE through `ethercat-node` on a veth pair with two masters: SOEM (pysoem's `foe_write` and
//! `foe_read`, `tests/python/pysoem_foe.py`) and `sdo-tool --ethercat` (`foe-write`, `foe-read`).
//! The chain is `examples/foe-device.esi.xml` (FoE; a bootstrap mailbox of 256 bytes at 0x1200 and
//! 0x1300; firmware `*.efw` in Bootstrap only) and `examples/io-device.esi.xml` (no FoE), its files
//! kept in a folder (`--foe-dir`) and each file at most 20,000 bytes (`--foe-max-file`).
//!
//! Files of several sizes through 128-byte mailboxes (116 bytes of file a packet): 398 bytes (three
//! full packets and a short one), 464 (four full packets, then an empty one), 0 (one empty packet),
//! and 5,000 bytes of firmware in Bootstrap (244 bytes a packet); the emulator stopped and started
//! again with the same folder (a power cycle) and every file read back byte for byte; a file over
//! the limit refused with 0x8003 and kept nowhere; FoE to the unit without it refused with the
//! mailbox error 0x0002; each master reading the other's files; a slave that answers Busy waited
//! out by both.
//!
//! Needs root (a network namespace, a veth pair, raw sockets) and pysoem (`pip install pysoem`):
//! without either the test fails and says why; it is never skipped.

#[path = "common/pysoem.rs"]
#[allow(dead_code)]
mod pysoem_master;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Duration;

use testkit::link::Link;

/// The bytes of file `name` of `size` bytes, as the script makes them: byte k is (7k + k / 251 +
/// the sum of the name's bytes) mod 256.
fn pattern(name: &str, size: usize) -> Vec<u8> {
    let seed: usize = name.bytes().map(usize::from).sum();
    (0..size)
        .map(|k| ((7 * k + k / 251 + seed) % 256) as u8)
        .collect()
}

/// A fresh folder for the files of one test.
fn folder(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("foe-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// The emulator's arguments with the files in `dir`, each at most 20,000 bytes (`small`).
fn node_args(dir: &Path, small: bool) -> Vec<String> {
    let mut args: Vec<String> = [
        "--esi",
        "examples/foe-device.esi.xml",
        "--esi",
        "examples/io-device.esi.xml",
        "--foe-dir",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([dir.display().to_string()])
    .collect();
    if small {
        args.extend(["--foe-max-file".to_string(), "20000".to_string()]);
    }
    args
}

fn start(dir: &Path, small: bool) -> Link {
    pysoem_master::preflight();
    let args = node_args(dir, small);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    Link::node(&args)
}

/// Stops the emulator and starts it again with the same arguments: a power cycle. What it logged.
fn power_cycle(link: &mut Link, dir: &Path) -> String {
    let log = link.stop();
    let args = node_args(dir, true);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    link.start(&args);
    log
}

/// The log without its colours.
fn plain(log: &str) -> String {
    let mut out = String::with_capacity(log.len());
    let mut chars = log.chars();
    while let Some(c) = chars.next() {
        if c == '\u{1b}' {
            for c in chars.by_ref() {
                if c == 'm' {
                    break;
                }
            }
        } else {
            out.push(c);
        }
    }
    out
}

/// The pysoem script with `ops` on the master's end; its standard output, once it exited 0.
fn pysoem(link: &Link, ops: &[&str]) -> String {
    let script = format!("{}/tests/python/pysoem_foe.py", env!("CARGO_MANIFEST_DIR"));
    let testkit::Finished {
        status,
        stdout,
        stderr,
    } = testkit::run_for_at_most(
        Command::new("python3")
            .arg(&script)
            .arg(&link.master)
            .args(ops),
        Duration::from_secs(120),
    );
    let status = status.unwrap_or_else(|| panic!("pysoem ran over 120 s: {stdout}{stderr}"));
    assert!(
        status.success(),
        "pysoem {ops:?}: {status}\n{stdout}{stderr}"
    );
    stdout
}

/// `sdo-tool --ethercat IFACE ARGS…`.
fn tool(link: &Link, argv: &[&str]) -> Output {
    link.sdo_tool(argv)
}

/// `sdo-tool` that must succeed: its standard output.
fn ok(link: &Link, argv: &[&str]) -> Vec<u8> {
    let o = tool(link, argv);
    assert!(
        o.status.success(),
        "sdo-tool {argv:?}: {}\n{}",
        o.status,
        String::from_utf8_lossy(&o.stderr)
    );
    o.stdout
}

/// `sdo-tool` that must fail with `code`, saying `line` on standard error.
fn refused(link: &Link, argv: &[&str], code: i32, line: &str) {
    let o = tool(link, argv);
    assert_eq!(o.status.code(), Some(code), "sdo-tool {argv:?}");
    assert_eq!(String::from_utf8_lossy(&o.stderr), format!("{line}\n"));
}

/// pysoem writes four files (one of them firmware, in Bootstrap), one over the limit (SOEM: -5,
/// the slave's Error; the emulator's log names 0x8003 and 0x8001 for a file that is not there)
/// and asks the unit without FoE for one (mailbox error 2); the files are in the folder as
/// written, the refused one nowhere; after a power cycle pysoem reads each back, the firmware in
/// Pre-Op and in Bootstrap.
#[test]
fn pysoem_keeps_files_across_a_power_cycle() {
    let dir = folder("pysoem");
    let mut link = start(&dir, true);
    let files = [
        ("a.bin", 398),
        ("multiple.bin", 464),
        ("empty.bin", 0),
        ("fw.efw", 5000),
    ];
    pysoem(
        &link,
        &[
            "w:1:a.bin:398",
            "w:1:multiple.bin:464",
            "w:1:empty.bin:0",
            "w:1:fw.efw:5000:boot",
            "big:1:big.bin:20001",
            "none:1:nope:0",
            "r:1:a.bin:398",
            "nofoe:2:a.bin:0",
        ],
    );
    let log = plain(&power_cycle(&mut link, &dir));
    assert!(
        log.contains("FoE: refused unit=1 file=big.bin code=0x8003 (Disk full)"),
        "{log}"
    );
    assert!(
        log.contains("FoE: refused unit=1 file=nope code=0x8001 (Not found)"),
        "{log}"
    );
    for (name, size) in files {
        let kept = std::fs::read(dir.join("unit1").join(name)).unwrap();
        assert_eq!(kept, pattern(name, size), "{name} in the folder");
    }
    assert!(!dir.join("unit1/big.bin").exists());
    assert!(!dir.join("unit2").exists());
    let out = pysoem(
        &link,
        &[
            "r:1:a.bin:398",
            "r:1:multiple.bin:464",
            "r:1:empty.bin:0",
            "r:1:fw.efw:5000",
            "r:1:fw.efw:5000:boot",
        ],
    );
    assert_eq!(out, "5 FoE operations done\n");
    drop(link);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// sdo-tool writes the files (firmware refused outside Bootstrap with 0x8009 and its hint, then
/// written with --boot), is refused a file over the limit (0x8003, exit 1) and one that is not
/// there (0x8001, exit 1), gets the mailbox error 2 from the unit without FoE (exit 3), which
/// refuses Bootstrap too (0x0013: its ESI gives no bootstrap mailbox; exit 3), and a usage error
/// without -p on a chain of two (exit 2); pysoem reads sdo-tool's files and writes one that
/// sdo-tool reads; after a power cycle sdo-tool reads every file back, byte for byte.
#[test]
fn sdo_tool_and_pysoem_read_each_others_files() {
    let dir = folder("sdo-tool");
    let mut link = start(&dir, true);
    let local = folder("sdo-tool-local");
    std::fs::create_dir_all(&local).unwrap();
    let files = [
        ("a.bin", 398),
        ("multiple.bin", 464),
        ("empty.bin", 0),
        ("fw.efw", 5000),
    ];
    for (name, size) in files {
        std::fs::write(local.join(name), pattern(name, size)).unwrap();
    }
    let path = |name: &str| local.join(name).display().to_string();
    for (name, _) in &files[..3] {
        ok(&link, &["foe-write", "-p", "1", &path(name)]);
    }
    refused(
        &link,
        &["foe-write", "-p", "1", &path("fw.efw")],
        1,
        "sdo-tool: slave 1: FoE write of \"fw.efw\" aborted with error code 0x00008009: Not \
         Bootstrap. (\"firmware is written in Bootstrap\"); the slave takes this file in \
         Bootstrap: --boot",
    );
    ok(&link, &["foe-write", "-p", "1", "--boot", &path("fw.efw")]);
    std::fs::write(local.join("big"), pattern("big.bin", 20001)).unwrap();
    refused(
        &link,
        &["foe-write", "-p", "1", &path("big"), "-o", "big.bin"],
        1,
        "sdo-tool: slave 1: FoE write of \"big.bin\" aborted with error code 0x00008003: Disk \
         full. (\"20001 bytes, over the 20000-byte limit of a file\")",
    );
    refused(
        &link,
        &["foe-read", "-p", "1", "nope"],
        1,
        "sdo-tool: slave 1: FoE read of \"nope\" aborted with error code 0x00008001: Not found. \
         (\"no such file\")",
    );
    refused(
        &link,
        &["foe-read", "-p", "2", "a.bin"],
        3,
        "sdo-tool: slave 2: FoE read of \"a.bin\" failed: the slave answered with mailbox error 2 \
         (mailbox protocol not supported)",
    );
    refused(
        &link,
        &["foe-write", "-p", "2", "--boot", &path("a.bin")],
        3,
        "sdo-tool: slave 2: FoE write of \"a.bin\" failed: the slave did not go to Bootstrap (AL \
         status 0x0011, AL status code 0x0013)",
    );
    refused(
        &link,
        &["foe_read", "a.bin"],
        2,
        &format!(
            "sdo-tool: `foe-read` takes one slave: the chain on {} has 2: give -p POS (1 = first)",
            link.master
        ),
    );
    pysoem(
        &link,
        &[
            "r:1:a.bin:398",
            "r:1:multiple.bin:464",
            "r:1:empty.bin:0",
            "r:1:fw.efw:5000",
            "w:1:from-pysoem.bin:1000",
        ],
    );
    assert_eq!(
        ok(&link, &["foe-read", "-p", "1", "from-pysoem.bin"]),
        pattern("from-pysoem.bin", 1000)
    );
    let json = ok(
        &link,
        &[
            "--json",
            "foe_write",
            "-p",
            "1",
            &path("a.bin"),
            "-o",
            "b.bin",
        ],
    );
    assert_eq!(
        String::from_utf8_lossy(&json),
        "{\"bytes\":398,\"file\":\"b.bin\",\"position\":1}\n"
    );
    power_cycle(&mut link, &dir);
    for (name, size) in files {
        let out = local.join(format!("{name}.read"));
        let out = out.display().to_string();
        ok(&link, &["foe-read", "-p", "1", name, "-o", &out]);
        assert_eq!(std::fs::read(&out).unwrap(), pattern(name, size), "{name}");
    }
    let firmware = ok(&link, &["foe-read", "-p", "1", "--boot", "fw.efw"]);
    assert_eq!(firmware, pattern("fw.efw", 5000));
    drop(link);
    std::fs::remove_dir_all(&dir).unwrap();
    std::fs::remove_dir_all(&local).unwrap();
}

/// A file of 1 MiB written by each master and read back by the other (the emulator's default
/// limits: 4 MiB a file); each write's throughput printed (not asserted: it is the machine's).
#[test]
fn one_mib_each_way() {
    let dir = folder("mib");
    let link = start(&dir, false);
    let size = 1 << 20;
    let local = folder("mib-local");
    std::fs::create_dir_all(&local).unwrap();
    let file = local.join("m.bin");
    std::fs::write(&file, pattern("m.bin", size)).unwrap();
    let started = std::time::Instant::now();
    ok(
        &link,
        &["foe-write", "-p", "1", &file.display().to_string()],
    );
    let s = started.elapsed().as_secs_f64();
    println!(
        "sdo-tool: write {size} bytes in {s:.3} s: {:.0} bytes/s (session start included)",
        size as f64 / s
    );
    let out = pysoem(&link, &["r:1:m.bin:1048576", "t:1:p.bin:1048576"]);
    print!("pysoem: {out}");
    assert_eq!(
        ok(&link, &["foe-read", "-p", "1", "p.bin"]),
        pattern("p.bin", size)
    );
    drop(link);
    std::fs::remove_dir_all(&dir).unwrap();
    std::fs::remove_dir_all(&local).unwrap();
}

/// A unit that takes 3 ms to program each packet (`--foe-busy-ms 3`) answers the packets that come
/// sooner with Busy, and sdo-tool sends them again: 4,000 bytes (35 packets, the first 34 of them
/// followed at once by the next) take at least 34 × 3 ms, and read back whole. SOEM sends them
/// again too: pysoem's 4,000 bytes read back whole.
#[test]
fn both_masters_wait_out_a_busy_slave() {
    pysoem_master::preflight();
    let link = Link::node(&["--esi", "examples/foe-device.esi.xml", "--foe-busy-ms", "3"]);
    let local = folder("busy-local");
    std::fs::create_dir_all(&local).unwrap();
    let file = local.join("slow.bin");
    std::fs::write(&file, pattern("slow.bin", 4000)).unwrap();
    let started = std::time::Instant::now();
    ok(&link, &["foe-write", &file.display().to_string()]);
    let took = started.elapsed();
    assert!(took >= Duration::from_millis(34 * 3), "{took:?}");
    assert_eq!(
        ok(&link, &["foe-read", "slow.bin"]),
        pattern("slow.bin", 4000)
    );
    pysoem(&link, &["w:1:busy.bin:4000", "r:1:busy.bin:4000"]);
    drop(link);
    std::fs::remove_dir_all(&local).unwrap();
}
