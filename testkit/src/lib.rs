//! What the tests and benchmarks of several crates share:
//!
//! - [`cargo_binary`]: a binary of another package, built once per test process with the profile the
//!   test runs with;
//! - [`sibling_binary`]: a binary already built beside the running test (in the VM of the vcan
//!   tests, where the runner builds first);
//! - [`start_until_first_line`]: a server started and given the time to say where it listens;
//! - [`favour`] and [`favour_this_thread`]: a simulated device's process or thread given a larger
//!   share of a busy machine, as a real device has its own processor;
//! - [`link`]: a veth pair with `smd-ethercat` running on its far end, in a network namespace of its
//!   own;
//! - [`sched`]: how long the machine held threads back (their run-queue wait), which a timing test
//!   takes off a late answer before it blames the node;
//! - [`tshark`]: Wireshark's dissectors on a capture (no malformed packet, no expert error; the
//!   protocol layers and fields of each frame).
#![deny(missing_docs)]

pub mod link;
pub mod sched;
pub mod tshark;

use std::collections::HashMap;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Mutex, OnceLock};

/// Gives process (or thread) `id` the nice value -10, so that on a machine busy with other jobs it
/// is scheduled first when it wakes: a real device answers from a processor of its own, and the
/// bounds the standards set on its timing (a heartbeat's period, a slave's answer within a master's
/// frame timeout) hold only when the simulated one is not queued behind a build. Without the
/// privilege to do so it stays as it is.
pub fn favour(id: u32) {
    // A nice value belongs to one thread on Linux: every thread the process has now, and those it
    // starts later from them, which inherit it.
    let mut ids: Vec<String> = std::fs::read_dir(format!("/proc/{id}/task"))
        .map(|d| {
            d.flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    if ids.is_empty() {
        ids.push(id.to_string());
    }
    let _ = Command::new("renice")
        .args(["-n", "-10", "-p"])
        .args(&ids)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
}

/// [`favour`] for the calling thread (Linux gives each thread a nice value of its own).
pub fn favour_this_thread() {
    let tid = std::fs::read_link("/proc/thread-self")
        .ok()
        .and_then(|p| p.file_name()?.to_str()?.parse::<u32>().ok());
    if let Some(tid) = tid {
        let _ = Command::new("renice")
            .args(["-n", "-10", "-p", &tid.to_string()])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status();
    }
}

/// A TCP port of 127.0.0.1 free a moment ago (the system's choice for port 0), for a server a test
/// starts next.
pub fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// The workspace root.
pub fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

/// Binary `bin` of workspace package `package` with `features`, built (or found up to date) once per
/// test process, in the target directory and with the profile of the running test or benchmark.
pub fn cargo_binary(package: &str, bin: &str, features: &[&str]) -> PathBuf {
    static BUILT: OnceLock<Mutex<HashMap<String, PathBuf>>> = OnceLock::new();
    let mut built = BUILT
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    let key = format!("{package}/{bin}/{}", features.join(","));
    if let Some(path) = built.get(&key) {
        return path.clone();
    }
    let dir = profile_dir();
    let profile = dir.file_name().and_then(|p| p.to_str()).unwrap_or("debug");
    let target = dir.parent().expect("target dir");
    let mut cargo = Command::new(env!("CARGO"));
    cargo
        .args(["build", "--quiet", "--locked", "-p", package, "--bin", bin])
        .arg("--target-dir")
        .arg(target)
        .current_dir(root());
    if !features.is_empty() {
        cargo.arg("--features").arg(features.join(","));
    }
    match profile {
        "debug" => {}
        "release" => {
            cargo.arg("--release");
        }
        other => {
            cargo.args(["--profile", other]);
        }
    }
    let status = cargo.status().expect("run cargo build");
    assert!(
        status.success(),
        "cargo build -p {package} --bin {bin} failed"
    );
    let path = dir.join(bin);
    assert!(path.exists(), "{} after cargo build", path.display());
    built.insert(key, path.clone());
    path
}

/// The binary `name` that cargo built beside the running test (`target/<profile>/<name>`), for the
/// tests of another package than the binary's, where [`cargo_binary`] cannot run (its build is
/// the caller's: `tests/vcan/run` builds `x67-node` before the tests).
pub fn sibling_binary(name: &str) -> PathBuf {
    let bin = profile_dir().join(name);
    assert!(bin.exists(), "{} is not built", bin.display());
    bin
}

/// The directory of the running test's profile: target/<profile>/deps/<this test> → target/<profile>.
fn profile_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("the test's path");
    exe.parent()
        .and_then(|deps| deps.parent())
        .expect("target/<profile>/deps")
        .to_path_buf()
}

/// `command` started with its standard output piped (standard error to nowhere), once it has printed
/// its first line (a server saying where it listens): the child and that line. The pipe stays with
/// the child, open while it runs, so later output does not meet a closed pipe.
pub fn start_until_first_line(command: &mut Command) -> (Child, String) {
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {command:?}: {e}"));
    let mut out = BufReader::new(child.stdout.take().expect("stdout piped"));
    let mut line = String::new();
    out.read_line(&mut line)
        .unwrap_or_else(|e| panic!("{command:?} printed nothing: {e}"));
    child.stdout = Some(out.into_inner());
    (child, line)
}

/// What [`run_for_at_most`] saw: the exit status (`None` when the process ran over its time and was
/// killed) and everything it wrote.
pub struct Finished {
    /// The exit status, or `None` when it was killed at its deadline.
    pub status: Option<std::process::ExitStatus>,
    /// Its standard output.
    pub stdout: String,
    /// Its standard error.
    pub stderr: String,
}

/// Runs `command` with its output captured (read as it comes, so it never waits on a full pipe),
/// for at most `limit`; killed then.
pub fn run_for_at_most(command: &mut Command, limit: std::time::Duration) -> Finished {
    use std::io::Read;
    let started = std::time::Instant::now();
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {command:?}: {e}"));
    let drain = |mut pipe: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut s = String::new();
            let _ = pipe.read_to_string(&mut s);
            s
        })
    };
    let stdout = drain(Box::new(child.stdout.take().expect("stdout")));
    let stderr = drain(Box::new(child.stderr.take().expect("stderr")));
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for the child") {
            break Some(status);
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    Finished {
        status,
        stdout: stdout.join().unwrap(),
        stderr: stderr.join().unwrap(),
    }
}

/// The shared corpus of real vendor files beside the checkout (`../shared/corpus`); panics, saying
/// so, when it is missing (the tests that read it are never skipped).
pub fn corpus() -> PathBuf {
    let dir = root().join("../shared/corpus");
    assert!(
        dir.is_dir(),
        "{} is missing: the corpus lies beside the checkout",
        dir.display()
    );
    dir
}

/// Every CANopen description of the corpus (EDS, DCF, XDD, XDC, XPD, in any sub-folder) whose
/// text has object 0x6040 (an EDS `[6040]` section, an XDD `index="6040"`), sorted: the drive
/// descriptions a test runs, found rather than listed, so that a file added to the corpus is tried
/// too.
pub fn corpus_drive_descriptions() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                walk(&path, out);
                continue;
            }
            let ext = path
                .extension()
                .map(|e| e.to_string_lossy().to_ascii_lowercase())
                .unwrap_or_default();
            let Ok(bytes) = std::fs::read(&path) else {
                continue;
            };
            let text = String::from_utf8_lossy(&bytes).to_ascii_lowercase();
            let drive = match ext.as_str() {
                "eds" | "dcf" => text.contains("[6040]"),
                "xdd" | "xdc" | "xpd" => text.contains("index=\"6040\""),
                _ => false,
            };
            if drive {
                out.push(path);
            }
        }
    }
    let mut out = Vec::new();
    walk(&corpus(), &mut out);
    out.sort();
    assert!(!out.is_empty(), "no CiA 402 description in the corpus");
    out
}
