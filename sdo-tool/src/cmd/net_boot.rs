//! `net boot` and `net watch`: the network manager of `canopen-net` on the bus, from a bus
//! description (dcfgen's YAML, ros2_canopen's `bus.yml`) or the folder `net gen` (or dcfgen) wrote.
//! Its events as lines (or JSON objects), a table of the nodes at the end, and on a terminal the
//! table live.

use std::io::{IsTerminal, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use can_link::BusEvent;
use canopen_net::boot::{BootEvent, Manager, ManagerConfig, NodeReport, NodeState, Plan, SlaveDcf};
use canopen_net::GenOptions;

use super::file_error;
use super::net::{env, loader, read_bus};
use crate::{Tool, ToolError, UsageError};

/// `net boot`'s and `net watch`'s arguments.
#[derive(Debug, clap::Args)]
pub struct BootArgs {
    /// Take a slave description that dcfgen's strict reading refuses as it is.
    #[arg(short = 'S', long = "no-strict")]
    pub no_strict: bool,
    /// How long to wait for the network (ms): `net boot` ends when every node booted or failed
    /// for good, or at this bound; `net watch` runs this long (default: until Ctrl-C). For `net
    /// boot` the default is the boot time 0x1F89, or 10 s when it is 0.
    #[arg(long = "wait-ms", value_name = "MS")]
    pub wait_ms: Option<u64>,
    /// How long a node is waited for after the reset before its boot starts without a boot-up
    /// message (ms).
    #[arg(long = "boot-up-wait-ms", value_name = "MS", default_value_t = 1000)]
    pub boot_up_wait_ms: u64,
    /// The bus description (a YAML file), a folder with master.dcf and the concise DCFs (as `net
    /// gen` writes them), or a folder of the slaves' DCFs, each at its NodeID.
    #[arg(value_name = "BUS.yml|DIR")]
    pub description: std::path::PathBuf,
}

/// The plan the description gives.
pub fn plan(args: &BootArgs) -> Result<Plan, ToolError> {
    let path = &args.description;
    if path.is_dir() {
        return folder_plan(path);
    }
    let bus = read_bus(path)?;
    let opts = GenOptions {
        remote_pdo: false,
        no_strict: args.no_strict,
    };
    let generated = canopen_net::generate(&bus, &mut loader(path), &env, opts)
        .map_err(|e| UsageError::Net(e.to_string()))?;
    for w in &generated.warnings {
        eprintln!("warning: {w}");
    }
    Ok(Plan::from_generated(
        &generated,
        &path.display().to_string(),
    ))
}

/// The plan of a folder: with `master.dcf`, as `net gen` or dcfgen wrote it, the concise DCFs its
/// 0x1F22 names found where it says or, by file name, in the folder; else the folder's DCFs, one per
/// slave ([`Plan::from_dcfs`]).
fn folder_plan(dir: &Path) -> Result<Plan, ToolError> {
    let master = dir.join("master.dcf");
    if !master.is_file() {
        return dcfs_plan(dir);
    }
    let text = std::fs::read_to_string(&master).map_err(|e| file_error(&master, e))?;
    let desc = super::load_description(&master, "net boot")?;
    let mut load = |name: &str| -> Result<Option<Vec<u8>>, String> {
        let given = Path::new(name);
        let candidates = [
            dir.join(given),
            dir.join(given.file_name().unwrap_or_default()),
        ];
        match candidates.iter().find(|p| p.is_file()) {
            Some(p) => std::fs::read(p)
                .map(Some)
                .map_err(|e| format!("{}: {e}", p.display())),
            None => Ok(None),
        }
    };
    let file = master.display().to_string();
    Plan::from_master_dcf(&desc, &text, &file, &mut load)
        .map_err(|e| UsageError::Net(e.to_string()).into())
}

/// The plan of a folder of DCFs (`*.dcf`, in name order), each a slave at its NodeID.
fn dcfs_plan(dir: &Path) -> Result<Plan, ToolError> {
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .map_err(|e| file_error(dir, e))?
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("dcf")))
        .collect();
    paths.sort();
    if paths.is_empty() {
        return Err(UsageError::Net(format!(
            "{}: neither master.dcf nor a slave's DCF (*.dcf)",
            dir.display()
        ))
        .into());
    }
    let mut dcfs = Vec::new();
    for p in paths {
        let text = std::fs::read_to_string(&p).map_err(|e| file_error(&p, e))?;
        dcfs.push(SlaveDcf {
            name: p
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default(),
            file: p.display().to_string(),
            desc: super::load_description(&p, "net boot")?,
            text,
        });
    }
    Plan::from_dcfs(&dcfs, 127).map_err(|e| UsageError::Net(e).into())
}

/// Runs the manager of `args` on `tool`'s bus; `watch` keeps supervising after the boot.
pub fn run(
    args: &BootArgs,
    watch: bool,
    tool: &mut Tool,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let plan = plan(args)?;
    let config = ManagerConfig {
        sdo_timeout: tool.sdo.timeout,
        boot_up_wait: Duration::from_millis(args.boot_up_wait_ms),
        ..ManagerConfig::default()
    };
    let boot_time = plan.boot_time_ms;
    let mut m = Manager::new(plan, config);
    let start = Instant::now();
    let wait = match (args.wait_ms, watch) {
        (Some(ms), _) => Some(Duration::from_millis(ms)),
        (None, true) => None,
        (None, false) if boot_time != 0 => Some(Duration::from_millis(u64::from(boot_time))),
        (None, false) => Some(Duration::from_secs(10)),
    };
    let end = wait.map(|w| start + w);
    let stop = Arc::new(AtomicBool::new(false));
    {
        let s = Arc::clone(&stop);
        let _ = ctrlc::set_handler(move || s.store(true, Ordering::Relaxed));
    }
    let live = !json && std::io::stdout().is_terminal();
    let mut view = View {
        start,
        json,
        live,
        drawn: None,
    };
    m.start(start);
    let bus = tool.bus.as_mut();
    loop {
        while let Some(frame) = m.poll_transmit() {
            bus.send(&frame)?;
        }
        let mut changed = false;
        while let Some(event) = m.poll_event() {
            view.event(&m, &event, out)?;
            changed = true;
        }
        if live && changed {
            view.table(&m, out)?;
        }
        let now = Instant::now();
        let over = end.is_some_and(|e| now >= e) || stop.load(Ordering::Relaxed);
        if over || (!watch && m.settled()) {
            break;
        }
        let due = [
            m.poll_timeout(),
            end,
            Some(now + Duration::from_millis(100)),
        ]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(now);
        if let Some(BusEvent::Frame {
            frame, received, ..
        }) = bus.recv(due.saturating_duration_since(now))?
        {
            m.handle_frame(received, &frame);
        }
        m.handle_timeout(Instant::now());
    }
    if !live {
        view.table(&m, out)?;
    }
    verdict(&m)
}

/// The exit by the worst node: a mandatory one not up (7), an optional one not up (6).
fn verdict(m: &Manager) -> Result<(), ToolError> {
    let down = |mandatory: bool| -> Vec<u8> {
        m.nodes()
            .filter(|r| r.mandatory == mandatory)
            .filter(|r| !matches!(r.state, NodeState::Up | NodeState::Watched))
            .map(|r| r.node)
            .collect()
    };
    let (mandatory, optional) = (down(true), down(false));
    if mandatory.is_empty() && optional.is_empty() {
        return Ok(());
    }
    Err(ToolError::NotBooted {
        mandatory,
        optional,
    })
}

/// The output: event lines (or JSON objects) and the table.
struct View {
    start: Instant,
    json: bool,
    live: bool,
    /// Lines of the table last drawn on the terminal.
    drawn: Option<usize>,
}

impl View {
    fn event(&mut self, m: &Manager, e: &BootEvent, out: &mut dyn Write) -> Result<(), ToolError> {
        let t = self.start.elapsed().as_secs_f64();
        let name = |node: u8| {
            m.nodes()
                .find(|r| r.node == node)
                .map_or(String::new(), |r| r.name.clone())
        };
        let (text, value) = match e {
            BootEvent::Node { node, state } => {
                let (text, mut value) = match state {
                    NodeState::Failed(err) => (
                        format!("{err} ({})", err.status.meaning()),
                        serde_json::json!({"event": "failed", "status": err.status.letter().to_string(),
                            "meaning": err.status.meaning(), "message": err.message}),
                    ),
                    s => (
                        format!("node {node} {}: {}", name(*node), s.word()),
                        serde_json::json!({"event": "state", "state": s.word()}),
                    ),
                };
                value["node"] = (*node).into();
                value["name"] = name(*node).into();
                (text, value)
            }
            BootEvent::NetworkUp => (
                "network up".to_string(),
                serde_json::json!({"event": "network_up"}),
            ),
            BootEvent::BootTimeout { missing } => (
                format!(
                    "boot time over: mandatory node {} not booted, the network is not up",
                    ids(missing)
                ),
                serde_json::json!({"event": "boot_timeout", "missing": missing}),
            ),
            BootEvent::Emergency {
                node,
                code,
                register,
                data,
            } => (
                format!(
                    "node {node} {}: EMCY 0x{code:04X}, error register 0x{register:02X}, data {}",
                    name(*node),
                    hex(data)
                ),
                serde_json::json!({"event": "emergency", "node": node, "code": code,
                    "register": register, "data": hex(data)}),
            ),
            BootEvent::Nmt { command, node } => (
                format!("NMT {} {}", nmt_word(*command), node_words(*node)),
                serde_json::json!({"event": "nmt", "command": nmt_word(*command), "node": node}),
            ),
        };
        if self.live {
            return Ok(());
        }
        let r = if self.json {
            let mut value = value;
            value["t"] = ((t * 1000.0).round() / 1000.0).into();
            writeln!(out, "{value}")
        } else {
            writeln!(out, "{t:7.3} {text}")
        };
        r.map_err(ToolError::Output)
    }

    fn table(&mut self, m: &Manager, out: &mut dyn Write) -> Result<(), ToolError> {
        if self.json {
            for r in m.nodes() {
                writeln!(out, "{}", report_json(r)).map_err(ToolError::Output)?;
            }
            return Ok(());
        }
        let mut lines = vec![format!(
            "{:>4}  {:<12} {:<10} {:<6} {:<10} {:<10} {:<10} {:<7} {:<9} last error",
            "node", "name", "state", "nmt", "type", "vendor", "product", "config", "heartbeat"
        )];
        for r in m.nodes() {
            lines.push(row(r));
        }
        if let Some(n) = self.drawn {
            // Up over the table drawn last, each line cleared as it is drawn again.
            write!(out, "\x1b[{n}A").map_err(ToolError::Output)?;
        }
        let clear = if self.live { "\x1b[2K" } else { "" };
        for l in &lines {
            writeln!(out, "{clear}{l}").map_err(ToolError::Output)?;
        }
        if self.live {
            self.drawn = Some(lines.len());
        }
        out.flush().map_err(ToolError::Output)
    }
}

fn row(r: &NodeReport) -> String {
    let v = |x: Option<u32>| x.map_or("-".to_string(), |v| format!("0x{v:08X}"));
    let nmt = match r.nmt {
        None => "-",
        Some(0x00) => "boot",
        Some(0x04) => "stop",
        Some(0x05) => "op",
        Some(0x7F) => "preop",
        Some(_) => "?",
    };
    let heartbeat = if r.heartbeat_ms == 0 {
        "-".to_string()
    } else {
        format!("{} ms", r.heartbeat_ms)
    };
    let error = r.last_error.as_ref().map_or("-".to_string(), |e| {
        format!("[{}] {}", e.status.letter(), e.message)
    });
    format!(
        "{:>4}  {:<12} {:<10} {:<6} {:<10} {:<10} {:<10} {:<7} {:<9} {error}",
        r.node,
        r.name,
        r.state.word(),
        nmt,
        v(r.identity[0]),
        v(r.identity[1]),
        v(r.identity[2]),
        if r.current {
            "current".to_string()
        } else {
            format!("{}/{}", r.configured.0, r.configured.1)
        },
        heartbeat
    )
}

fn report_json(r: &NodeReport) -> serde_json::Value {
    let v = |x: Option<u32>| x.map(|v| format!("0x{v:08X}"));
    serde_json::json!({
        "event": "node",
        "node": r.node,
        "name": r.name,
        "mandatory": r.mandatory,
        "state": r.state.word(),
        "nmt": r.nmt,
        "device_type": v(r.identity[0]),
        "vendor_id": v(r.identity[1]),
        "product_code": v(r.identity[2]),
        "revision_number": v(r.identity[3]),
        "serial_number": v(r.identity[4]),
        "configured": r.configured.0,
        "entries": r.configured.1,
        "heartbeat_ms": r.heartbeat_ms,
        "boots": r.boots,
        "kept": r.kept,
        "current": r.current,
        "last_error": r.last_error.as_ref().map(|e| serde_json::json!({
            "status": e.status.letter().to_string(), "meaning": e.status.meaning(), "message": e.message})),
    })
}

fn nmt_word(command: u8) -> &'static str {
    match command {
        0x01 => "start",
        0x02 => "stop",
        0x80 => "enter pre-operational",
        0x81 => "reset node",
        0x82 => "reset communication",
        _ => "?",
    }
}

fn node_words(node: u8) -> String {
    if node == 0 {
        "all nodes".into()
    } else {
        format!("node {node}")
    }
}

fn ids(nodes: &[u8]) -> String {
    nodes
        .iter()
        .map(u8::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

fn hex(data: &[u8]) -> String {
    data.iter().map(|b| format!("{b:02X}")).collect()
}
