//! `net gen` and `net check`: a CiA 302 network's bus description (dcfgen's YAML or ros2_canopen's
//! `bus.yml`) made into the files a CANopen manager configures its slaves with, or checked before
//! anything is sent. The generation is `canopen-net`'s; this module reads and writes the files.

use std::io::Write;
use std::path::{Path, PathBuf};

use canopen_net::{Bus, GenOptions, SlaveFile};

use super::{emit, file_error};
use crate::{ToolError, UsageError};

/// `net`'s arguments.
#[derive(Debug, clap::Args)]
pub struct NetArgs {
    /// What to do with the bus description.
    #[command(subcommand)]
    pub command: NetCmd,
}

/// The `net` commands.
#[derive(Debug, clap::Subcommand)]
pub enum NetCmd {
    /// Write each slave's concise DCF (NAME.bin), master.dcf and master.bin into DIR, as Lely's
    /// dcfgen does.
    Gen(GenArgs),
    /// Say what is wrong with a bus description (a missing or unreadable DCF, a node-ID used twice, an
    /// entry or a mapping a slave's description cannot take), one line each with FILE:LINE; exit 2
    /// when anything is.
    Check(CheckArgs),
    /// Boot the network as a CiA 302-2 manager: reset, check each slave's device type and
    /// identity, write its configuration, wait for its heartbeat, start it; a table of the nodes at
    /// the end, each failure with its CiA 302-2 letter and in words. Exit 0 when every node booted,
    /// 6 when an optional one did not, 7 when a mandatory one did not (the network is not up).
    Boot(super::net_boot::BootArgs),
    /// Boot the network, then supervise it (heartbeats, boot-up messages, emergencies) until Ctrl-C
    /// or --wait-ms; a lost node is booted again when it comes back. On a terminal the table is live.
    Watch(super::net_boot::BootArgs),
}

impl NetCmd {
    /// True for the commands that run on a bus.
    pub fn needs_bus(&self) -> bool {
        matches!(self, NetCmd::Boot(_) | NetCmd::Watch(_))
    }
}

/// `net gen`'s arguments.
#[derive(Debug, clap::Args)]
pub struct GenArgs {
    /// Also write the remote PDO mappings (0x5800..0x5FFF) into master.dcf.
    #[arg(short = 'r', long = "remote-pdo")]
    pub remote_pdo: bool,
    /// Take a slave description that dcfgen's strict reading refuses (an unknown key, a value
    /// out of its type's range, an incomplete object list, …) as it is.
    #[arg(short = 'S', long = "no-strict")]
    pub no_strict: bool,
    /// The bus description.
    #[arg(value_name = "BUS.yml")]
    pub description: PathBuf,
    /// The folder to write into (made when missing).
    #[arg(
        short = 'd',
        long = "directory",
        value_name = "DIR",
        default_value = "."
    )]
    pub directory: PathBuf,
}

/// `net check`'s arguments.
#[derive(Debug, clap::Args)]
pub struct CheckArgs {
    /// Take a slave description that dcfgen's strict reading refuses (an unknown key, a value
    /// out of its type's range, an incomplete object list, …) as it is.
    #[arg(short = 'S', long = "no-strict")]
    pub no_strict: bool,
    /// The bus description.
    #[arg(value_name = "BUS.yml")]
    pub description: PathBuf,
}

/// Runs a `net` command.
pub fn run(args: &NetArgs, json: bool, out: &mut dyn Write) -> Result<(), ToolError> {
    match &args.command {
        NetCmd::Gen(a) => gen(a, json, out),
        NetCmd::Check(a) => check(a, json, out),
        // Run on the bus, by `run_on_bus`.
        NetCmd::Boot(_) | NetCmd::Watch(_) => Ok(()),
    }
}

/// Runs a `net` command that needs the bus.
pub fn run_on_bus(
    args: &NetArgs,
    tool: &mut crate::Tool,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    match &args.command {
        NetCmd::Boot(a) => super::net_boot::run(a, false, tool, json, out),
        NetCmd::Watch(a) => super::net_boot::run(a, true, tool, json, out),
        NetCmd::Gen(_) | NetCmd::Check(_) => run(args, json, out),
    }
}

pub(crate) fn read_bus(path: &Path) -> Result<Bus, ToolError> {
    let text = std::fs::read_to_string(path).map_err(|e| file_error(path, e))?;
    Bus::parse(&text, &path.display().to_string())
        .map_err(|e| UsageError::Net(e.to_string()).into())
}

/// The reader of slave descriptions, relative to the bus description's folder.
pub(crate) fn loader(bus: &Path) -> impl FnMut(&str) -> Result<SlaveFile, String> {
    let dir = bus.parent().map(Path::to_path_buf).unwrap_or_default();
    move |dcf: &str| {
        let path = dir.join(dcf);
        let (_, reading) = od::load::load_reading(&path).map_err(|e| e.to_string())?;
        let desc = reading
            .devices
            .into_iter()
            .next()
            .ok_or_else(|| format!("{}: no device", path.display()))?;
        let text = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(SlaveFile::new(desc, &text))
    }
}

pub(crate) fn env(name: &str) -> Option<String> {
    std::env::var(name).ok()
}

fn gen(args: &GenArgs, json: bool, out: &mut dyn Write) -> Result<(), ToolError> {
    let bus = read_bus(&args.description)?;
    let opts = GenOptions {
        remote_pdo: args.remote_pdo,
        no_strict: args.no_strict,
    };
    let generated = canopen_net::generate(&bus, &mut loader(&args.description), &env, opts)
        .map_err(|e| UsageError::Net(e.to_string()))?;
    for w in &generated.warnings {
        eprintln!("warning: {w}");
    }
    std::fs::create_dir_all(&args.directory).map_err(|e| file_error(&args.directory, e))?;
    for (name, bytes) in &generated.files {
        let path = args.directory.join(name);
        std::fs::write(&path, bytes).map_err(|e| file_error(&path, e))?;
        let shown = path.display().to_string();
        let text = format!("wrote {shown} ({} bytes)", bytes.len());
        emit(
            out,
            json,
            text,
            serde_json::json!({"file": shown, "bytes": bytes.len()}),
        )?;
    }
    Ok(())
}

fn check(args: &CheckArgs, json: bool, out: &mut dyn Write) -> Result<(), ToolError> {
    let bus = read_bus(&args.description)?;
    let opts = GenOptions {
        remote_pdo: false,
        no_strict: args.no_strict,
    };
    let (errors, warnings) = canopen_net::check(&bus, &mut loader(&args.description), &env, opts);
    for w in &warnings {
        emit(
            out,
            json,
            format!("warning: {w}"),
            serde_json::json!({"warning": w}),
        )?;
    }
    for e in &errors {
        emit(out, json, e, serde_json::json!({"error": e.to_string()}))?;
    }
    if errors.is_empty() {
        let text = format!(
            "{}: {} slaves, nothing wrong",
            args.description.display(),
            bus.slaves.len()
        );
        emit(
            out,
            json,
            text,
            serde_json::json!({"ok": true, "slaves": bus.slaves.len()}),
        )
    } else {
        Err(UsageError::NetProblems {
            file: args.description.clone(),
            count: errors.len(),
        }
        .into())
    }
}
