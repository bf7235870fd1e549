//! The `x67-node` command line: its arguments and what it does with them. `main` only parses and calls
//! [`run`].

use std::io::Write as _;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::Parser;

use crate::cli_common::{capture, connect_hint, open_bus};
use crate::node::storage::{FileStorage, MemoryStorage, ParameterStorage};
use crate::node::{Node, NodeConfig, NodeError};
use crate::runtime::{self, RunStats, Station};
use crate::transport::{self, BusError, BusSpec};
use crate::x67::{self, BusController, X67Error, BUS_CONTROLLER};

/// A virtual CANopen node: a B&R X67BC4321-10 bus controller with X67SM2436 stepper modules in
/// function model "Ramp".
///
/// Without --bus (or CANOPEN_BUS) it uses SocketCAN vcan0 where this machine has it, and otherwise
/// listens as a socketcand server on 127.0.0.1:29536, which python-can's "socketcand" interface and
/// this project's tools reach.
#[derive(Debug, Clone, Parser)]
#[command(name = "x67-node", version)]
pub struct Args {
    /// The bus: IFACE or socketcan:IFACE (e.g. vcan0, can0), socketcand://HOST:PORT/CHANNEL (a
    /// socketcand daemon to join), or socketcand-listen:ADDR:PORT (be a socketcand server; binds only
    /// the address given, 127.0.0.1 keeps it on this machine).
    #[arg(long, value_name = "BUS", env = transport::BUS_VARIABLE)]
    pub bus: Option<BusSpec>,

    /// The node-ID, 1 to 127 (the bus controller's node number switches).
    #[arg(long, value_name = "ID", default_value_t = 1, value_parser = clap::value_parser!(u8).range(1..=127))]
    pub node_id: u8,

    /// How many X67SM2436 modules sit behind the bus controller, 1 to 16. Module m (1-based) has its
    /// registers at 0x2000 + 0x300·(m−1) and its CAN objects on PDOs 2m−1 and 2m.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u8).range(1..=16))]
    pub modules: u8,

    /// Where "save all parameters" (0x1010) keeps the parameters and where a reset finds them.
    /// Without it they are kept in memory until the process ends.
    #[arg(long, value_name = "FILE")]
    pub storage: Option<PathBuf>,

    /// The heartbeat producer time (0x1017) at power-on, in ms; 0 sends no heartbeat. Without it,
    /// the description's default.
    #[arg(long, value_name = "MS")]
    pub heartbeat_ms: Option<u16>,

    /// The X2X Link cycle in µs, at which the bus controller refreshes the modules' inputs (at least
    /// 250).
    #[arg(long, value_name = "US", default_value_t = 1000, value_parser = clap::value_parser!(u64).range(250..=100_000))]
    pub x2x_us: u64,

    /// Writes every frame the node sends and receives to FILE, a pcapng capture Wireshark and
    /// tshark read (LINKTYPE_CAN_SOCKETCAN, the bus's name as the interface's, nanosecond times,
    /// each frame's direction); written whenever the node waits, whole when it stops.
    #[arg(long, value_name = "FILE")]
    pub capture: Option<PathBuf>,

    /// Writes the description of the node with --modules modules (every module's registers and PDOs,
    /// the simulation inputs at 0x5F00+) to FILE and exits: an EDS for FILE.eds, an XDD for FILE.xdd.
    /// Give it to a master's --od, python-canopen's add_node or any tool that reads descriptions.
    #[arg(long, value_name = "FILE")]
    pub write_description: Option<PathBuf>,

    /// `--completions SHELL`, `--man DIR`.
    #[command(flatten)]
    pub generate: cli_support::Generate,
}

/// Why `x67-node` stopped with an error.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CliError {
    /// The bus.
    #[error(transparent)]
    Bus(#[from] BusError),
    /// The bus controller.
    #[error(transparent)]
    X67(#[from] X67Error),
    /// The node.
    #[error(transparent)]
    Node(#[from] NodeError),
    /// Ctrl-C could not be hooked.
    #[error("cannot handle Ctrl-C: {0}")]
    Signal(#[from] cli_support::SignalError),
    /// The capture file cannot be created.
    #[error("--capture {0}")]
    Capture(#[from] crate::cli_common::CaptureError),
    /// The description file cannot be written, or its name says no format.
    #[error("--write-description {path}: {why}")]
    Description {
        /// The file given.
        path: String,
        /// What is wrong.
        why: String,
    },
    /// The storage file cannot be used (its directory, its kind, its size, its reading).
    #[error("--storage {path}: {source}")]
    Storage {
        /// The file given.
        path: String,
        /// What is wrong.
        source: std::io::Error,
    },
}

/// The node `args` describe with its storage, ready to start.
pub fn build_node(args: &Args) -> Result<Station<BusController>, CliError> {
    let modules = usize::from(args.modules);
    let storage: Box<dyn ParameterStorage> = match &args.storage {
        Some(path) => {
            let dir = match path.parent() {
                Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
                _ => PathBuf::from("."),
            };
            let refuse = |kind, why: String| CliError::Storage {
                path: path.display().to_string(),
                source: std::io::Error::new(kind, why),
            };
            if !dir.is_dir() {
                return Err(refuse(
                    std::io::ErrorKind::NotFound,
                    format!("directory {} does not exist", dir.display()),
                ));
            }
            if path.is_dir() {
                return Err(refuse(
                    std::io::ErrorKind::InvalidInput,
                    "is a directory".into(),
                ));
            }
            Box::new(FileStorage::new(path))
        }
        None => Box::new(MemoryStorage::default()),
    };
    let dict = x67::dictionary(modules)?;
    let now = Instant::now();
    let app = BusController::new(&dict, modules, Duration::from_micros(args.x2x_us), now)?;
    let mut config = NodeConfig::new(args.node_id);
    config.heartbeat_ms = args.heartbeat_ms;
    let node = Node::new(config, dict, app, now)?;
    Station::try_new(node, storage).map_err(|source| CliError::Storage {
        path: args
            .storage
            .as_ref()
            .map_or_else(String::new, |p| p.display().to_string()),
        source,
    })
}

/// Writes the description of the node `args` describe to `path` (EDS or XDD by the extension); what
/// it wrote, for the user.
pub fn write_description(args: &Args, path: &std::path::Path) -> Result<String, CliError> {
    let refuse = |why: String| CliError::Description {
        path: path.display().to_string(),
        why,
    };
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let desc = x67::description(usize::from(args.modules))?;
    let (format, text) = match ext.as_deref() {
        Some("eds") => ("EDS", od::eds::write_eds(&desc)),
        Some("xdd") => ("XDD", od::xdd::write(&desc)),
        _ => return Err(refuse("the name must end in .eds or .xdd".into())),
    };
    std::fs::write(path, text).map_err(|e| refuse(e.to_string()))?;
    Ok(format!(
        "x67-node: wrote {} ({format}: {BUS_CONTROLLER} with {} X67SM2436 module{}, {} objects)",
        path.display(),
        args.modules,
        if args.modules == 1 { "" } else { "s" },
        desc.dictionary.len()
    ))
}

/// Runs `x67-node` until Ctrl-C (or `stop`, when given) and returns the run's counters.
pub fn run(args: &Args, stop: Option<Arc<AtomicBool>>) -> Result<RunStats, CliError> {
    if let Some(path) = &args.write_description {
        let said = write_description(args, path)?;
        let _ = writeln!(std::io::stdout(), "{said}");
        return Ok(RunStats::default());
    }
    let mut station = build_node(args)?;
    let capture = capture(
        args.capture.as_deref(),
        concat!("x67-node ", env!("CARGO_PKG_VERSION")),
    )?;
    let (spec, mut bus) = open_bus(args.bus.as_ref(), capture.as_ref())?;
    let stop = cli_support::stop_flag(stop)?;
    // A closed standard output (a parent that stopped reading) does not stop the node.
    let _ = writeln!(
        std::io::stdout(),
        "x67-node: node {} ({BUS_CONTROLLER} with {} X67SM2436 module{}) {}",
        args.node_id,
        args.modules,
        if args.modules == 1 { "" } else { "s" },
        connect_hint(&spec)
    );
    tracing::info!(bus = %bus.describe(), node = args.node_id, "started");
    let stats = runtime::run(std::slice::from_mut(&mut station), bus.as_mut(), &stop)?;
    tracing::info!(
        received = stats.received,
        sent = stats.sent,
        bus_errors = stats.bus_errors,
        "stopped"
    );
    Ok(stats)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arguments_and_their_refusals() {
        let a = Args::try_parse_from(["x67-node"]).unwrap();
        assert_eq!((a.node_id, a.modules, a.x2x_us), (1, 1, 1000));
        assert!(a.bus.is_none());
        let a = Args::try_parse_from([
            "x67-node",
            "--bus",
            "socketcand-listen:127.0.0.1:4000",
            "--node-id",
            "127",
            "--modules",
            "16",
            "--heartbeat-ms",
            "100",
        ])
        .unwrap();
        assert_eq!(
            a.bus,
            Some(BusSpec::SocketcandListen {
                addr: "127.0.0.1:4000".parse().unwrap()
            })
        );
        assert_eq!((a.node_id, a.modules, a.heartbeat_ms), (127, 16, Some(100)));
        for (argv, says) in [
            (&["x67-node", "--node-id", "0"][..], "0 is not in 1..=127"),
            (&["x67-node", "--node-id", "128"], "128 is not in 1..=127"),
            (&["x67-node", "--modules", "17"], "17 is not in 1..=16"),
            (
                &["x67-node", "--x2x-us", "249"],
                "249 is not in 250..=100000",
            ),
            (&["x67-node", "--bus", "tcp://vcan0"], "unknown kind of bus"),
            (&["x67-node", "--heartbeat-ms", "70000"], "70000"),
        ] {
            let e = Args::try_parse_from(argv).unwrap_err().to_string();
            assert!(e.contains(says), "{argv:?}: {e}");
        }
    }

    #[test]
    fn a_storage_file_in_a_missing_directory_is_refused() {
        let a = Args::try_parse_from(["x67-node", "--storage", "/nonexistent/dir/params"]).unwrap();
        let Err(e) = build_node(&a) else {
            panic!("built")
        };
        assert_eq!(
            e.to_string(),
            "--storage /nonexistent/dir/params: directory /nonexistent/dir does not exist"
        );
    }
}
