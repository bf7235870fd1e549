//! The `canopen-node` command line: any CANopen description (EDS, DCF, XDD, XDC) as a live node, several
//! on one bus, with a CiA 402 drive behind each drive axis of a description. `main` only parses and calls
//! [`run`].
//!
//! Never silent: every value a node reports that its description does not give ([`Prepared`])
//! is one line on standard output at start, after the node's own line (`canopen-node: node 5: 0x6502
//! supported drive modes = 0x000000A5 (…)`), or one JSON object with `--json`; `--explain` prints
//! only these and opens no bus.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::{Parser, ValueEnum};
use ds402::drive::{DriveConfig, MotorKind};
use od::device::DeviceDescription;
use od::event::{Event, Origin};

use crate::cli_common::{capture, connect_hint, open_bus};
use crate::generic::{unique_serials, PrepareError, Prepared};
use crate::node::lss::UNCONFIGURED;
use crate::node::storage::{FileStorage, MemoryStorage, ParameterStorage};
use crate::node::{LssConfig, Node, NodeConfig, NodeError};
use crate::runtime::{self, RunStats, Station};
use crate::transport::{self, BusError, BusSpec};
use ds402::generic::GenericApp;

/// Virtual CANopen nodes from device descriptions: the dictionary of each description (EDS, DCF, XDD,
/// XDC) with its defaults, limits, access and PDO configuration, NMT, heartbeat, SYNC, PDOs, EMCY,
/// store/restore, SDO (expedited, segmented, block), TIME and LSS, and a CiA 402 drive behind every
/// axis whose 0x6040/0x6041 the description has.
///
/// Without --bus (or CANOPEN_BUS) it uses SocketCAN vcan0 where this machine has it, and otherwise
/// listens as a socketcand server on 127.0.0.1:29536.
#[derive(Debug, Clone, Parser)]
#[command(name = "canopen-node", version)]
pub struct Args {
    /// The bus: IFACE or socketcan:IFACE (e.g. vcan0, can0), socketcand://HOST:PORT/CHANNEL (a
    /// socketcand daemon to join), or socketcand-listen:ADDR:PORT (be a socketcand server; binds only
    /// the address given, 127.0.0.1 keeps it on this machine).
    #[arg(long, value_name = "BUS", env = transport::BUS_VARIABLE)]
    pub bus: Option<BusSpec>,

    /// A description to run as a node: FILE, or FILE@ID with ID 1 to 127, or FILE@lss for a node
    /// without a node-ID that waits for an LSS master (CiA 305). Give it once per node; nodes with the
    /// same identity get serial numbers counting up from the description's, so that LSS tells them
    /// apart.
    #[arg(long = "od", value_name = "FILE[@ID]", required_unless_present_any = ["completions", "man"])]
    pub ods: Vec<NodeSpec>,

    /// The node-ID of a single --od given without @ID (1 to 127, or lss). Without it a DCF's NodeID
    /// (0xFF: none, LSS) is used.
    #[arg(long, value_name = "ID")]
    pub node_id: Option<NodeIdArg>,

    /// A directory for what the nodes keep: node N's parameters (0x1010) in nodeN.params and its LSS
    /// configuration (store configuration) in nodeN.params.lss, N counting the --od options from 1.
    /// Without it both are kept in memory until the process ends.
    #[arg(long, value_name = "DIR")]
    pub storage: Option<PathBuf>,

    /// The heartbeat producer time (0x1017) at power-on, in ms; 0 sends no heartbeat. Without it,
    /// each description's default.
    #[arg(long, value_name = "MS")]
    pub heartbeat_ms: Option<u16>,

    /// How often a TIME producer (0x1012 bit 30) sends the time of day, in ms.
    #[arg(long, value_name = "MS", default_value_t = 1000, value_parser = clap::value_parser!(u64).range(1..=3_600_000))]
    pub time_period_ms: u64,

    /// The motor behind each drive: a servo (position controller, torque limit) or an open-loop
    /// stepper that loses steps beyond its pull-out torque.
    #[arg(long, value_enum, default_value_t = MotorArg::Servo)]
    pub motor: MotorArg,

    /// The simulated negative limit switch of each drive, in position counts (0x60FD bit 0 while
    /// the position is at or below it; homing methods 1, 17 and others search it).
    #[arg(long, value_name = "COUNTS", allow_hyphen_values = true)]
    pub negative_limit: Option<i64>,

    /// The simulated positive limit switch, in position counts (0x60FD bit 1 at or above it).
    #[arg(long, value_name = "COUNTS", allow_hyphen_values = true)]
    pub positive_limit: Option<i64>,

    /// The simulated home switch, in position counts (0x60FD bit 2 at or above it).
    #[arg(long, value_name = "COUNTS", allow_hyphen_values = true)]
    pub home_switch: Option<i64>,

    /// Writes every frame the nodes send and receives to FILE, a pcapng capture Wireshark and
    /// tshark read (LINKTYPE_CAN_SOCKETCAN, the bus's name as the interface's, nanosecond times,
    /// each frame's direction); written whenever the node waits, whole when it stops.
    #[arg(long, value_name = "FILE")]
    pub capture: Option<PathBuf>,

    /// Writes the description of the first node as it runs (its dictionary with the drive
    /// simulation records at 0x5FF0 + axis) to FILE and exits: an EDS for FILE.eds, an XDD for
    /// FILE.xdd.
    #[arg(long, value_name = "FILE")]
    pub write_description: Option<PathBuf>,

    /// Prints what each node reports that its description does not give, one line per entry, and
    /// exits without opening a bus: a value the description leaves out (identity, names, device
    /// type, supported drive modes), or a factory setting in place of a value its drive could not
    /// run with (a limit or ramp of 0, a code it refuses). A node prints the same lines at start.
    #[arg(long, conflicts_with = "write_description")]
    pub explain: bool,

    /// Those lines (at start, and with --explain) as JSON objects, one per line: {"event":
    /// "filled" or "adjusted", "node", "index", "sub", "name", "value", "unit" (where it has one),
    /// "reason"}; and the log on standard error as JSON objects, one per line ("timestamp", "level",
    /// "message", "target", and the line's fields: a drive's refusals, limits and faults have
    /// "axis", "index", "value" and "limit" or "code").
    #[arg(long)]
    pub json: bool,

    /// `--completions SHELL`, `--man DIR`.
    #[command(flatten)]
    pub generate: cli_support::Generate,
}

/// The motor of the drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MotorArg {
    /// A servo motor with a position controller.
    Servo,
    /// An open-loop stepper motor.
    Stepper,
}

/// A node-ID on the command line: 1 to 127, or `lss` (255, none).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeIdArg(pub u8);

impl FromStr for NodeIdArg {
    type Err = String;

    fn from_str(s: &str) -> Result<NodeIdArg, String> {
        let t = s.trim();
        if t.eq_ignore_ascii_case("lss") {
            return Ok(NodeIdArg(UNCONFIGURED));
        }
        let n: u32 = if let Some(h) = t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
            u32::from_str_radix(h, 16).map_err(|_| format!("{s:?} is no node-ID"))?
        } else {
            t.parse().map_err(|_| format!("{s:?} is no node-ID"))?
        };
        match n {
            1..=127 => Ok(NodeIdArg(n as u8)),
            255 => Ok(NodeIdArg(UNCONFIGURED)),
            _ => Err(format!("node-ID {n} is outside 1 to 127 (or lss for none)")),
        }
    }
}

/// One --od: a description file and, after `@`, its node-ID.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NodeSpec {
    /// The file.
    pub path: PathBuf,
    /// The node-ID given with it.
    pub node_id: Option<NodeIdArg>,
}

impl FromStr for NodeSpec {
    type Err = String;

    fn from_str(s: &str) -> Result<NodeSpec, String> {
        if s.is_empty() {
            return Err("an empty file name".into());
        }
        // FILE@ID: the part after the last `@` when it is a node-ID; a file name may hold `@` too.
        if let Some((file, id)) = s.rsplit_once('@') {
            let looks_like_id = id.eq_ignore_ascii_case("lss")
                || (!id.is_empty() && id.chars().all(|c| c.is_ascii_hexdigit() || c == 'x'));
            if looks_like_id && !file.is_empty() {
                return Ok(NodeSpec {
                    path: PathBuf::from(file),
                    node_id: Some(id.parse()?),
                });
            }
        }
        Ok(NodeSpec {
            path: PathBuf::from(s),
            node_id: None,
        })
    }
}

/// Why `canopen-node` stopped with an error.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CliError {
    /// The bus.
    #[error(transparent)]
    Bus(#[from] BusError),
    /// A description cannot run as a node.
    #[error(transparent)]
    Prepare(PrepareError),
    /// A description gives no node-ID, and none was given with it.
    #[error("{source}: add @ID (e.g. {}@5) or --node-id", path.display())]
    NoNodeId {
        /// The file given.
        path: PathBuf,
        /// What the description says.
        source: PrepareError,
    },
    /// The description cannot be written, or its name says no format.
    #[error("{path}: {why}")]
    Description {
        /// The file given.
        path: String,
        /// What is wrong.
        why: String,
    },
    /// The node-IDs given do not fit the descriptions.
    #[error("{0}")]
    NodeIds(String),
    /// A node.
    #[error(transparent)]
    Node(#[from] NodeError),
    /// Ctrl-C could not be hooked.
    #[error("cannot handle Ctrl-C: {0}")]
    Signal(#[from] cli_support::SignalError),
    /// The capture file cannot be created.
    #[error("--capture {0}")]
    Capture(#[from] crate::cli_common::CaptureError),
    /// The storage directory cannot be used.
    #[error("--storage {path}: {why}")]
    Storage {
        /// The directory given.
        path: String,
        /// What is wrong.
        why: String,
    },
}

/// A description loaded for a node, with the node-ID it runs as.
pub struct Loaded {
    /// The description, its DCF values made power-on values, completed
    /// ([`ds402::generic::complete`]) and the simulation records added ([`Prepared`]).
    pub description: DeviceDescription,
    /// The node-ID (0xFF: none, LSS).
    pub node_id: u8,
    /// The file.
    pub path: PathBuf,
    /// What the description was given that it does not say itself, in index order.
    pub events: Vec<Event>,
}

/// Loads every --od of `args`: the description, the node-ID each runs as, serial numbers made unique
/// among nodes of the same identity.
pub fn load(args: &Args) -> Result<Vec<Loaded>, CliError> {
    if args.node_id.is_some() && args.ods.len() > 1 {
        return Err(CliError::NodeIds(
            "--node-id is for a single --od; give several as FILE@ID".into(),
        ));
    }
    let drive = drive_config(args);
    let mut prepared = Vec::with_capacity(args.ods.len());
    for spec in &args.ods {
        let node_id = spec.node_id.or(args.node_id).map(|NodeIdArg(id)| id);
        prepared.push(
            Prepared::load(&spec.path, node_id, &drive).map_err(|e| match e {
                PrepareError::NoNodeId { .. } => CliError::NoNodeId {
                    path: spec.path.clone(),
                    source: e,
                },
                e => CliError::Prepare(e),
            })?,
        );
    }
    unique_serials(&mut prepared);
    let out: Vec<Loaded> = prepared
        .into_iter()
        .zip(&args.ods)
        .map(|(p, spec)| Loaded {
            node_id: p.node_id(),
            path: spec.path.clone(),
            events: p.events().to_vec(),
            description: p.into_description(),
        })
        .collect();
    let mut ids: Vec<u8> = out
        .iter()
        .map(|l| l.node_id)
        .filter(|id| *id != UNCONFIGURED)
        .collect();
    ids.sort_unstable();
    if let Some(w) = ids.windows(2).find(|w| w[0] == w[1]) {
        return Err(CliError::NodeIds(format!(
            "node-ID {} is given to two nodes",
            w[0]
        )));
    }
    Ok(out)
}

/// The drives' configuration `args` give.
pub fn drive_config(args: &Args) -> DriveConfig {
    let mut config = DriveConfig::default();
    config.motor.kind = match args.motor {
        MotorArg::Servo => MotorKind::Servo,
        MotorArg::Stepper => MotorKind::Stepper,
    };
    config.sim.negative_limit = args.negative_limit;
    config.sim.positive_limit = args.positive_limit;
    config.sim.home_switch = args.home_switch;
    config
}

/// The lines that say what node `node_id`'s description (`path`) was given ([`Loaded::events`]):
/// `canopen-node: node 5: 0x6502 supported drive modes = 0x000000A5 (…)`, or with `json` one JSON
/// object each ([`Event::json`]).
pub fn event_lines(node_id: u8, path: &Path, events: &[Event], json: bool) -> Vec<String> {
    let id = (node_id != UNCONFIGURED).then_some(node_id);
    let label = match id {
        Some(id) => format!("node {id}"),
        None => format!("node without node-ID ({})", path.display()),
    };
    events
        .iter()
        .map(|e| {
            if json {
                e.json(Origin::Node(id))
            } else {
                format!("canopen-node: {label}: {}", e.line())
            }
        })
        .collect()
}

/// The nodes `args` describe with their storage, ready to start.
pub fn build(args: &Args) -> Result<Vec<Station<GenericApp>>, CliError> {
    build_from(args, load(args)?)
}

/// The nodes of `loaded` (as [`load`] made them from `args`) with their storage, ready to start.
pub fn build_from(args: &Args, loaded: Vec<Loaded>) -> Result<Vec<Station<GenericApp>>, CliError> {
    if let Some(dir) = &args.storage {
        if !dir.is_dir() {
            return Err(CliError::Storage {
                path: dir.display().to_string(),
                why: "is not a directory".into(),
            });
        }
    }
    let now = Instant::now();
    let drive = drive_config(args);
    let mut stations = Vec::with_capacity(loaded.len());
    for (k, l) in loaded.into_iter().enumerate() {
        let mut storage: Box<dyn ParameterStorage> = match &args.storage {
            Some(dir) => Box::new(FileStorage::new(dir.join(format!("node{}.params", k + 1)))),
            None => Box::new(MemoryStorage::default()),
        };
        let storage_error = |e: std::io::Error| CliError::Storage {
            path: args
                .storage
                .as_ref()
                .map_or_else(String::new, |p| p.display().to_string()),
            why: e.to_string(),
        };
        // A stored LSS configuration is the node-ID at power-on (CiA 305 store configuration).
        let stored = storage.load_lss().map_err(storage_error)?;
        let node_id = stored.map_or(l.node_id, |s| s.node_id);
        let config = NodeConfig {
            heartbeat_ms: args.heartbeat_ms,
            lss: Some(LssConfig {
                bit_timing: stored.map_or(4, |s| s.bit_timing),
                can_store: args.storage.is_some(),
            }),
            time_period: Duration::from_millis(args.time_period_ms),
            ..NodeConfig::new(node_id)
        };
        let dict = l.description.dictionary;
        let app = GenericApp::new(&dict, &drive, now);
        let node = Node::new(config, dict, app, now)?;
        stations.push(Station::try_new(node, storage).map_err(storage_error)?);
    }
    Ok(stations)
}

/// Writes the description of the first node as it runs to `path` (EDS or XDD by the extension); what it
/// wrote, for the user.
pub fn write_description(args: &Args, path: &Path) -> Result<String, CliError> {
    let refuse = |why: String| CliError::Description {
        path: path.display().to_string(),
        why,
    };
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let mut loaded = load(args)?;
    let desc = loaded.remove(0).description;
    let (format, text) = match ext.as_deref() {
        Some("eds") => ("EDS", od::eds::write_eds(&desc)),
        Some("xdd") => ("XDD", od::xdd::write(&desc)),
        _ => return Err(refuse("the name must end in .eds or .xdd".into())),
    };
    std::fs::write(path, text).map_err(|e| refuse(e.to_string()))?;
    Ok(format!(
        "canopen-node: wrote {} ({format}, {} objects)",
        path.display(),
        desc.dictionary.len()
    ))
}

/// Runs `canopen-node` until Ctrl-C (or `stop`, when given) and returns the run's counters.
pub fn run(args: &Args, stop: Option<Arc<AtomicBool>>) -> Result<RunStats, CliError> {
    if let Some(path) = &args.write_description {
        let said = write_description(args, path)?;
        let _ = writeln!(std::io::stdout(), "{said}");
        return Ok(RunStats::default());
    }
    let loaded = load(args)?;
    if args.explain {
        let mut out = std::io::stdout();
        for l in &loaded {
            for line in event_lines(l.node_id, &l.path, &l.events, args.json) {
                let _ = writeln!(out, "{line}");
            }
        }
        return Ok(RunStats::default());
    }
    let said: Vec<Vec<String>> = loaded
        .iter()
        .map(|l| event_lines(l.node_id, &l.path, &l.events, args.json))
        .collect();
    let mut stations = build_from(args, loaded)?;
    let capture = capture(
        args.capture.as_deref(),
        concat!("canopen-node ", env!("CARGO_PKG_VERSION")),
    )?;
    let (spec, mut bus) = open_bus(args.bus.as_ref(), capture.as_ref())?;
    let stop = cli_support::stop_flag(stop)?;
    let mut out = std::io::stdout();
    for ((s, spec), lines) in stations.iter().zip(&args.ods).zip(&said) {
        let id = s.node.node_id();
        let drives = s.node.app().drives().len();
        let _ = writeln!(
            out,
            "canopen-node: node {} from {}{}",
            if id == UNCONFIGURED {
                "without node-ID (waiting for LSS)".to_string()
            } else {
                id.to_string()
            },
            spec.path.display(),
            match drives {
                0 => String::new(),
                1 => ", a CiA 402 drive".to_string(),
                n => format!(", {n} CiA 402 drive axes"),
            }
        );
        for line in lines {
            let _ = writeln!(out, "{line}");
        }
    }
    let _ = writeln!(out, "canopen-node: {}", connect_hint(&spec));
    tracing::info!(bus = %bus.describe(), nodes = stations.len(), "started");
    let stats = runtime::run(&mut stations, bus.as_mut(), &stop)?;
    tracing::info!(
        received = stats.received,
        sent = stats.sent,
        bus_errors = stats.bus_errors,
        "stopped"
    );
    Ok(stats)
}
