//! A veth pair for a master and the EtherCAT emulator: the master's end stays in this namespace, the other end is
//! moved into a network namespace of its own where the emulator runs on it (`smd-ethercat`, or
//! `ethercat-node`). Created by [`Link::up`] or [`Link::node`], removed when the [`Link`] is
//! dropped. Needs root (CAP_NET_ADMIN, CAP_NET_RAW); without
//! it the test fails and says so.

use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

static NEXT: AtomicU32 = AtomicU32::new(0);

/// A link with the emulator running on its far end.
pub struct Link {
    /// The namespace the emulator runs in.
    pub ns: String,
    /// The master's interface (this namespace).
    pub master: String,
    /// The emulator's interface (in `ns`).
    pub slave: String,
    child: Option<Child>,
    /// What the emulator wrote on stderr, once stopped.
    log: PathBuf,
    /// The emulator's binary.
    emulator: PathBuf,
}

fn ip(args: &[&str]) {
    let out = Command::new("ip")
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run `ip` (iproute2): {e}"));
    assert!(
        out.status.success(),
        "`ip {}` failed (the tests create a veth pair in a network namespace and need root): {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr).trim()
    );
}

impl Link {
    /// A fresh veth pair and namespace, and `smd-ethercat` with `args` (e.g. `["--units", "2"]`) on the
    /// far end, on line.
    pub fn up(args: &[&str]) -> Link {
        Link::with(
            crate::cargo_binary("ethercat-slave", "smd-ethercat", &[]),
            args,
        )
    }

    /// A fresh veth pair and namespace, and `ethercat-node` with `args` (e.g. `["--esi",
    /// "examples/drive.esi.xml@2"]`, paths from the workspace root) on the far end, on line.
    pub fn node(args: &[&str]) -> Link {
        Link::with(
            crate::cargo_binary("ethercat-slave", "ethercat-node", &[]),
            args,
        )
    }

    /// A fresh veth pair and namespace, and the emulator `binary` with `args` on the far end, on line.
    pub fn with(binary: PathBuf, args: &[&str]) -> Link {
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        let id = format!("{}x{n}", std::process::id() % 1_000_000);
        let (ns, master, slave) = (format!("ecat-{id}"), format!("ecm{id}"), format!("ecs{id}"));
        ip(&["netns", "add", &ns]);
        let mut link = Link {
            ns: ns.clone(),
            master: master.clone(),
            slave: slave.clone(),
            child: None,
            log: std::env::temp_dir().join(format!("ecat-emulator-{id}.log")),
            emulator: binary,
        };
        ip(&[
            "link", "add", &master, "type", "veth", "peer", "name", &slave, "netns", &ns,
        ]);
        ip(&["link", "set", &master, "up"]);
        ip(&["-n", &ns, "link", "set", &slave, "up"]);
        link.start(args);
        link
    }

    /// Starts the emulator on the far end (after [`Link::stop`], a power cycle).
    pub fn start(&mut self, args: &[&str]) {
        let log = std::fs::File::create(&self.log).expect("emulator log file");
        let mut child = Command::new("ip")
            .args(["netns", "exec", &self.ns])
            .arg(&self.emulator)
            .arg(&self.slave)
            .args(args)
            .current_dir(crate::root())
            .stdout(Stdio::piped())
            .stderr(log)
            .spawn()
            .expect("start the emulator");
        let mut line = String::new();
        let mut out = BufReader::new(child.stdout.take().expect("stdout"));
        out.read_line(&mut line).expect("the emulator's first line");
        assert!(
            line.contains("Ctrl-C stops"),
            "{} did not come on line: {line:?}; {}",
            self.emulator.display(),
            std::fs::read_to_string(&self.log).unwrap_or_default()
        );
        // What the emulator prints after its first line goes to a thread that reads it, so that
        // it never waits on a full pipe.
        std::thread::spawn(move || {
            let mut sink = String::new();
            while out.read_line(&mut sink).is_ok_and(|n| n > 0) {
                sink.clear();
            }
        });
        // A real slave answers in hardware within microseconds; masters time a frame out after a
        // few milliseconds (SOEM: 2 ms). On a machine busy with other jobs the emulator gets a
        // larger share of the CPU, so that its answers keep within that.
        crate::favour(child.id());
        self.child = Some(child);
        // The carrier of a fresh veth takes a moment.
        let deadline = Instant::now() + Duration::from_secs(5);
        while Instant::now() < deadline {
            let c = std::fs::read_to_string(format!("/sys/class/net/{}/carrier", self.master));
            if c.is_ok_and(|c| c.trim() == "1") {
                break;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// `sdo-tool --ethercat MASTER ARGV…` on the master's end, run to its end.
    pub fn sdo_tool(&self, argv: &[&str]) -> std::process::Output {
        Command::new(crate::cargo_binary("sdo-tool", "sdo-tool", &[]))
            .args(["--ethercat", &self.master])
            .args(argv)
            .output()
            .expect("run sdo-tool")
    }

    /// Stops the emulator (SIGINT, as Ctrl-C) and returns what it wrote on stderr.
    pub fn stop(&mut self) -> String {
        if let Some(mut child) = self.child.take() {
            // `ip netns exec` execs the binary: the child is the emulator itself.
            let _ = Command::new("kill")
                .args(["-INT", &child.id().to_string()])
                .status();
            let deadline = Instant::now() + Duration::from_secs(5);
            while child.try_wait().ok().flatten().is_none() && Instant::now() < deadline {
                std::thread::sleep(Duration::from_millis(10));
            }
            let _ = child.kill();
            let _ = child.wait();
        }
        std::fs::read_to_string(&self.log).unwrap_or_default()
    }

    /// The emulator's process id (`ip netns exec` execs it: the child is the emulator itself), while
    /// it runs.
    pub fn pid(&self) -> Option<u32> {
        self.child.as_ref().map(Child::id)
    }

    /// Whether the emulator is still running.
    pub fn running(&mut self) -> bool {
        self.child
            .as_mut()
            .is_some_and(|c| c.try_wait().ok().flatten().is_none())
    }
}

/// `(answered, dropped)` from the emulator's last line in `log` (what [`Link::stop`] returns),
/// `smd-ethercat: N frames answered, M dropped` (or `ethercat-node: …`).
pub fn frame_counts(log: &str) -> Option<(u64, u64)> {
    let line = log.lines().rev().find(|l| l.contains("frames answered"))?;
    let rest = line.rsplit(": ").next()?;
    let mut words = rest.split_whitespace();
    let answered = words.next()?.parse().ok()?;
    let dropped = words.nth(2)?.parse().ok()?;
    Some((answered, dropped))
}

impl Drop for Link {
    fn drop(&mut self) {
        self.stop();
        let _ = Command::new("ip")
            .args(["link", "del", &self.master])
            .output();
        let _ = Command::new("ip").args(["netns", "del", &self.ns]).output();
        let _ = std::fs::remove_file(&self.log);
    }
}
