//! The `ethercat-node` command line: any ESI's devices as a chain of emulated EtherCAT slaves, with a
//! CiA 402 drive behind every drive axis ([`crate::generic`]). `main` only parses ([`parse`]) and
//! calls [`run`].
//!
//! Never silent: every value a kind of device reports that its ESI does not give
//! ([`Template::events`]) is one line on standard output at start, after the line of its units
//! (`ethercat-node: EVE-XCR-E: 0x1018:02 product code = 0x02C31001 (…)`), or one JSON object with
//! `--json`; `--explain` prints only these and opens no interface.

use std::ffi::OsString;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::{CommandFactory, FromArgMatches, Parser, ValueEnum};
use ds402::drive::{DriveConfig, MotorKind};
use od::event::Origin;
use od::load::Format;

use crate::foe::dir::DirError;
use crate::foe::FoeConfig;
use crate::generic::{self, parse_number, Template, TemplateError};
use crate::raw::RawSocket;
use crate::runtime::{self, RuntimeError, Stats};

/// The most units a chain may have.
pub const MAX_UNITS: usize = 128;

/// Emulated EtherCAT slaves from ESI files: each unit's SII, dictionary, CoE server (SDO, Complete
/// Access, SDO Information), SyncManagers, AL checks, Distributed Clocks and PDOs (fixed, or
/// assignable through 0x1C12/0x1C13 and 0x1600+/0x1A00+ as the ESI allows) come from its ESI, and
/// behind every CiA 402 axis (0x6040/0x6041 at 0x6000 + 0x800 per axis), and every drive channel of
/// ETG.5001 MDP 742 (servo and stepper terminals: controlword 0x7010:01, statusword 0x6010:01, each
/// channel 0x100 further), runs a drive: its state machine, pp, pv, homing, csp/csv/cst on SYNC0, the
/// following error and a motor model; it logs each limit that holds it back. A device without
/// drive axes is its dictionary: the process data writes and reads its entries. --list shows a
/// file's devices and their axes.
///
/// Where the ESI offers FoE (Mailbox/FoE) a unit keeps files by FoE (read and write, ETG.1000.6
/// error codes, the --foe-* limits), in memory or in --foe-dir; where it gives a bootstrap mailbox
/// (Eeprom/BootStrap) the unit has a Bootstrap state (from Init, back to Init only) in which it
/// takes firmware files (--foe-firmware) and speaks FoE only.
///
/// --esi FILE@N puts N units of FILE's device in the chain; give --esi once per device kind, in
/// chain order. A --device (type name, name or product code) and a --modules list belong to the
/// --esi before them. Serial numbers (SII and 0x1018:04) are the chain positions, 1 for the first.
///
/// Needs CAP_NET_RAW (root). A veth pair gives a master and the units a link on one machine:
///
///   ip link add ecat0 type veth peer name ecat1 && ip link set ecat0 up && ip link set ecat1 up
///
///   ethercat-node ecat1 --esi examples/drive.esi.xml --units 2   (and the master on ecat0)
#[derive(Debug, Clone, Parser)]
#[command(name = "ethercat-node", version, verbatim_doc_comment)]
pub struct Args {
    /// The network interface the master's frames arrive on (not with --explain).
    #[arg(value_name = "INTERFACE", required_unless_present_any = ["explain", "list", "completions", "man"])]
    pub interface: Option<String>,

    /// An ESI file, FILE or FILE@N for N units of its device (1 to 128). Give it once per kind of
    /// device; the chain is the units in that order.
    #[arg(long = "esi", value_name = "FILE[@N]", required_unless_present_any = ["completions", "man"])]
    pub esis: Vec<String>,

    /// The device of a file that holds several: its type name, name, or product code (0x…, #x… or
    /// decimal); the newest revision is taken. Belongs to the --esi before it.
    #[arg(long = "device", value_name = "NAME|CODE")]
    pub devices: Vec<String>,

    /// The modules in the slots of a modular device (ETG.2001), one for each slot from the first,
    /// separated by commas: a module ident (0x10b00100) or type name, or `none` for an empty slot.
    /// Without it each slot holds its default module. Belongs to the --esi before it.
    #[arg(long = "modules", value_name = "LIST")]
    pub modules: Vec<String>,

    /// Units of each --esi given without @N.
    #[arg(long, short = 'n', value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..=128))]
    pub units: u16,

    /// The motor behind each drive: a servo (position controller, torque limit) or an open-loop
    /// stepper that loses steps beyond its pull-out torque.
    #[arg(long, value_enum, default_value_t = MotorArg::Servo)]
    pub motor: MotorArg,

    /// The units' process-data cycle in µs (how often the drives' inputs refresh and SYNC0 events
    /// are taken), 250 to 10000.
    #[arg(long, value_name = "US", default_value_t = 1000, value_parser = clap::value_parser!(u64).range(250..=10_000))]
    pub cycle_us: u64,

    /// After answering a frame, keep polling the interface for this many µs before sleeping (0 to
    /// 1000).
    #[arg(long, value_name = "US", default_value_t = 0, value_parser = clap::value_parser!(u64).range(0..=1000))]
    pub busy_poll_us: u64,

    /// Writes every frame the units receive and answer to FILE, a pcapng capture Wireshark and
    /// tshark read (LINKTYPE_ETHERNET, the interface's name, nanosecond times, each frame's
    /// direction); written whenever the units wait, whole when they stop.
    #[arg(long, value_name = "FILE")]
    pub capture: Option<std::path::PathBuf>,

    /// Prints what each kind of device reports that its ESI does not give, one line per entry, and
    /// exits without opening an interface: a value the ESI leaves out (0x1018 the identity of its
    /// SII, names, device type, supported drive modes), or a factory setting in place of a value its
    /// drive could not run with (a limit or ramp of 0, a code it refuses). The units print the same
    /// lines at start.
    #[arg(long)]
    pub explain: bool,

    /// Those lines (at start, and with --explain) as JSON objects, one per line: {"event": "filled"
    /// or "adjusted", "device", "index", "sub", "name", "value", "unit" (where it has one),
    /// "reason"}; and the log on standard error as JSON objects, one per line ("timestamp",
    /// "level", "message", "target", and the line's fields: a drive's limits, refusals and faults
    /// have "axis", "index", "value" and "limit" or "code").
    #[arg(long)]
    pub json: bool,

    /// A folder that keeps the units' FoE files: unit N's in DIR/unitN/, one file each under its
    /// FoE name (bytes other than A-Z a-z 0-9 _ - . written %XX). Read at start, written as each
    /// file arrives whole: a restart with the same folder is a power cycle that keeps them.
    /// Without it the files last as long as the run.
    #[arg(long, value_name = "DIR")]
    pub foe_dir: Option<PathBuf>,

    /// The largest FoE file a unit takes, in bytes; a larger one is refused with 0x8003 (disk
    /// full).
    #[arg(long, value_name = "BYTES", default_value_t = 4 << 20, value_parser = clap::value_parser!(u64).range(0..=1 << 30))]
    pub foe_max_file: u64,

    /// All FoE files of a unit together, in bytes; 0x8003 (disk full) beyond.
    #[arg(long, value_name = "BYTES", default_value_t = 16 << 20, value_parser = clap::value_parser!(u64).range(0..=1 << 30))]
    pub foe_max_store: u64,

    /// The password every FoE request must carry (0x…, #x… or decimal); another is refused with
    /// 0x800A (no rights). Without it any password goes.
    #[arg(long, value_name = "N", value_parser = password)]
    pub foe_password: Option<u32>,

    /// The firmware files (a name pattern, * for any characters, ASCII case ignored; give it
    /// again for more; *.efw without it): on a unit whose ESI gives a bootstrap mailbox
    /// (Eeprom/BootStrap) they are written by FoE in Bootstrap only (0x8009, not Bootstrap,
    /// otherwise), and in Bootstrap nothing else is (0x8008, Bootstrap only).
    #[arg(long = "foe-firmware", value_name = "PATTERN")]
    pub foe_firmware: Vec<String>,

    /// How many ms a unit takes to program an FoE Data packet: one that comes sooner is answered
    /// with Busy and sent again by the master (0 to 10000; 0, the default: never busy).
    #[arg(long, value_name = "MS", default_value_t = 0, value_parser = clap::value_parser!(u64).range(0..=10_000))]
    pub foe_busy_ms: u64,

    /// Prints every device of each --esi file, one tab-separated row each, and exits without
    /// opening an interface: its name, how --device chooses it, its identity, its drive axes (0+1
    /// CiA 402 axes, m0+m1 MDP 742 channels), whether its ESI claims csp in 0x6502, the PDOs a
    /// master assigns to move them in csp, and what stands in the way.
    #[arg(long)]
    pub list: bool,

    /// `--completions SHELL`, `--man DIR`.
    #[command(flatten)]
    pub generate: cli_support::Generate,
}

/// A password as the command line gives it: `0x…`, `#x…` or decimal.
fn password(text: &str) -> Result<u32, String> {
    parse_number(text).ok_or_else(|| format!("{text:?} is no 32-bit number (0x…, #x… or decimal)"))
}

/// The FoE configuration `args` give.
pub fn foe_config(args: &Args) -> FoeConfig {
    let bytes = |n: u64| usize::try_from(n).unwrap_or(usize::MAX);
    let defaults = FoeConfig::default();
    FoeConfig {
        max_file: bytes(args.foe_max_file),
        max_store: bytes(args.foe_max_store),
        password: args.foe_password,
        firmware: if args.foe_firmware.is_empty() {
            defaults.firmware.clone()
        } else {
            args.foe_firmware.clone()
        },
        packet_time: Duration::from_millis(args.foe_busy_ms),
        ..defaults
    }
}

/// The motor of the drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MotorArg {
    /// A servo motor with a position controller.
    Servo,
    /// An open-loop stepper motor.
    Stepper,
}

/// One --esi with what belongs to it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EsiSpec {
    /// The file.
    pub path: PathBuf,
    /// Units of it, when given as FILE@N.
    pub units: Option<usize>,
    /// The --device after it.
    pub device: Option<String>,
    /// The --modules after it.
    pub modules: Option<Vec<String>>,
}

/// The command line, parsed: the arguments and each --esi with its --device and --modules.
#[derive(Debug, Clone)]
pub struct Config {
    /// The arguments.
    pub args: Args,
    /// The --esi options in order.
    pub specs: Vec<EsiSpec>,
}

/// Splits `FILE@N` (N a number of units); a path whose last `@` is not followed by a number is the
/// path.
pub fn split_count(text: &str) -> Result<(PathBuf, Option<usize>), String> {
    if let Some((path, n)) = text.rsplit_once('@') {
        if !n.is_empty() && n.chars().all(|c| c.is_ascii_digit()) {
            let count: usize = n
                .parse()
                .ok()
                .filter(|c| (1..=MAX_UNITS).contains(c))
                .ok_or_else(|| {
                    format!("{text}: @{n} is not a number of units from 1 to {MAX_UNITS}")
                })?;
            return Ok((PathBuf::from(path), Some(count)));
        }
    }
    Ok((PathBuf::from(text), None))
}

/// Parses the command line `argv` (the program's name first): the arguments, and each --device and
/// --modules given to the --esi before it (to the first one when they come before every --esi).
pub fn parse<I, T>(argv: I) -> Result<Config, clap::Error>
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let mut command = Args::command();
    let matches = command.try_get_matches_from_mut(argv)?;
    let args = Args::from_arg_matches(&matches)?;
    let invalid = |message: String| {
        command
            .clone()
            .error(clap::error::ErrorKind::ValueValidation, message)
    };
    let esi_at: Vec<usize> = matches
        .indices_of("esis")
        .map_or(Vec::new(), Iterator::collect);
    let owner = |at: usize| esi_at.iter().rposition(|&e| e < at).unwrap_or(0);
    let mut specs = Vec::with_capacity(args.esis.len());
    for text in &args.esis {
        let (path, units) = split_count(text).map_err(|m| invalid(format!("--esi {m}")))?;
        specs.push(EsiSpec {
            path,
            units,
            device: None,
            modules: None,
        });
    }
    let given =
        |id: &str| -> Vec<usize> { matches.indices_of(id).map_or(Vec::new(), Iterator::collect) };
    for (value, at) in args.devices.iter().zip(given("devices")) {
        let spec = &mut specs[owner(at)];
        if spec.device.is_some() {
            return Err(invalid(format!(
                "two --device for --esi {}: give each --esi its own",
                spec.path.display()
            )));
        }
        spec.device = Some(value.clone());
    }
    for (value, at) in args.modules.iter().zip(given("modules")) {
        let spec = &mut specs[owner(at)];
        if spec.modules.is_some() {
            return Err(invalid(format!(
                "two --modules for --esi {}: list every slot's module in one",
                spec.path.display()
            )));
        }
        spec.modules = Some(value.split(',').map(|m| m.trim().to_string()).collect());
    }
    let total: usize = specs
        .iter()
        .map(|s| s.units.unwrap_or(usize::from(args.units)))
        .sum();
    if total > MAX_UNITS {
        return Err(invalid(format!(
            "{total} units in all; a chain has at most {MAX_UNITS}"
        )));
    }
    Ok(Config { args, specs })
}

/// Why `ethercat-node` stopped with an error.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CliError {
    /// An ESI file that does not load or read (the reader's message names the file).
    #[error("{0}")]
    Load(String),
    /// An ESI device that cannot be emulated.
    #[error("{path}: {why}")]
    Esi {
        /// The file.
        path: String,
        /// Why.
        why: String,
    },
    /// The emulator.
    #[error(transparent)]
    Runtime(#[from] RuntimeError),
    /// Ctrl-C could not be hooked.
    #[error("cannot handle Ctrl-C: {0}")]
    Signal(#[from] cli_support::SignalError),
    /// No interface to run on.
    #[error("an INTERFACE is needed (only --explain runs without one)")]
    NoInterface,
    /// The capture file cannot be created.
    #[error("--capture {0}")]
    Capture(#[from] link_capture::CaptureError),
    /// The --foe-dir folder could not be read.
    #[error("--foe-dir {0}")]
    FoeDir(#[from] DirError),
}

/// Reads the device of `spec` and makes it ready with its modules, its drives servos.
pub fn load(spec: &EsiSpec) -> Result<Template, CliError> {
    load_for(spec, &DriveConfig::default())
}

/// [`load`] for drives made as `drive` says.
pub fn load_for(spec: &EsiSpec, drive: &DriveConfig) -> Result<Template, CliError> {
    let refuse = |why: String| CliError::Esi {
        path: spec.path.display().to_string(),
        why,
    };
    let limit = od::load::limit_from(
        od::load::MAX_FILE_BYTES,
        std::env::var_os(od::load::LIMIT_VARIABLE).as_deref(),
    )
    .map_err(|e| CliError::Load(e.to_string()))?;
    let bytes =
        od::load::read_limited(&spec.path, limit).map_err(|e| CliError::Load(e.to_string()))?;
    match Format::detect(&spec.path, &bytes) {
        Some(Format::Esi) => {}
        Some(other) => {
            return Err(refuse(format!(
                "an {other} describes a CANopen device; run it with canopen-node"
            )))
        }
        None => return Err(refuse("not an ESI (EtherCATInfo) file".into())),
    }
    let select = spec.device.as_deref().map(|d| match parse_number(d) {
        Some(code) => od::esi::Select::ProductCode(code),
        None => od::esi::Select::Name(d.to_string()),
    });
    let name = spec.path.display().to_string();
    let desc =
        od::esi::read(&bytes, &name, select.as_ref()).map_err(|e| CliError::Load(e.to_string()))?;
    Template::for_drives(desc, spec.modules.as_deref(), drive)
        .map_err(|e: TemplateError| refuse(e.to_string()))
}

/// The drives' configuration `args` give.
pub fn drive_config(args: &Args) -> DriveConfig {
    DriveConfig {
        motor: ds402::drive::MotorConfig {
            kind: match args.motor {
                MotorArg::Servo => MotorKind::Servo,
                MotorArg::Stepper => MotorKind::Stepper,
            },
            ..Default::default()
        },
        ..Default::default()
    }
}

/// The lines that say what `template`'s ESI was given ([`Template::events`]): `ethercat-node:
/// EVE-XCR-E: 0x6502 supported drive modes = 0x000003A5 (…)`, or with `json` one JSON object each
/// ([`od::event::Event::json`]).
pub fn event_lines(template: &Template, json: bool) -> Vec<String> {
    let name = template.name();
    template
        .events()
        .iter()
        .map(|e| {
            if json {
                e.json(Origin::Device(&name))
            } else {
                format!("ethercat-node: {name}: {}", e.line())
            }
        })
        .collect()
}

/// What a template's units carry: `2 × EVE-XCR-E (outputs 11 bytes, inputs 11 bytes, 1 drive axis)`.
pub fn describe(template: &Template, n: usize) -> String {
    let (o, i) = template.images();
    let axes = template.axes().len();
    let modules = if template.modules().is_empty() {
        String::new()
    } else {
        let list: Vec<String> = template
            .modules()
            .iter()
            .map(|(slot, ident)| format!("slot {}: {ident:#010x}", slot + 1))
            .collect();
        format!(", modules {}", list.join(", "))
    };
    format!(
        "{n} × {} (outputs {} bytes, inputs {} bytes, {axes} drive axis/axes{modules})",
        template.name(),
        o.len(),
        i.len()
    )
}

/// Runs until Ctrl-C (or `stop`, when given, is set); prints what runs on stdout once on line, its
/// first line ending in "Ctrl-C stops".
pub fn run(config: &Config, stop: Option<Arc<AtomicBool>>) -> Result<Stats, CliError> {
    let args = &config.args;
    if args.list {
        println!("{}", crate::node_list::HEADER);
        for spec in &config.specs {
            for device in crate::node_list::list(&spec.path)? {
                println!("{}", device.row());
            }
        }
        return Ok(Stats::default());
    }
    let drive = drive_config(args);
    let foe = foe_config(args);
    let templates: Vec<(Template, usize)> = config
        .specs
        .iter()
        .map(|s| {
            let mut t = load_for(s, &drive)?;
            t.set_foe(&foe);
            Ok((t, s.units.unwrap_or(usize::from(args.units))))
        })
        .collect::<Result<_, CliError>>()?;
    if args.explain {
        for (t, _) in &templates {
            for line in event_lines(t, args.json) {
                println!("{line}");
            }
        }
        return Ok(Stats::default());
    }
    let interface = args.interface.as_deref().ok_or(CliError::NoInterface)?;
    let capture = args
        .capture
        .as_deref()
        .map(|path| {
            link_capture::Capture::create(
                path,
                concat!("ethercat-node ", env!("CARGO_PKG_VERSION")),
            )
        })
        .transpose()?;
    let stop = cli_support::stop_flag(stop)?;
    let mut socket = RawSocket::open(interface).map_err(RuntimeError::from)?;
    if let Some(capture) = &capture {
        socket.capture_to(capture);
    }
    let list: Vec<(&Template, usize)> = templates.iter().map(|(t, n)| (t, *n)).collect();
    let mut chain = generic::chain(
        &list,
        &drive,
        Duration::from_micros(args.cycle_us),
        Instant::now(),
    )
    .map_err(|e| CliError::Esi {
        path: "chain".into(),
        why: e.to_string(),
    })?;
    let total = chain.len();
    let mut loaded = Vec::new();
    if let Some(root) = &args.foe_dir {
        for k in 0..total {
            if let Some(foe) = chain.foe_mut(k) {
                let n = crate::foe::dir::load(root, k + 1, foe.store_mut())?;
                loaded.push((k + 1, n));
            }
        }
    }
    println!(
        "ethercat-node: {total} unit(s) on {interface} (serial numbers 1…{total}); Ctrl-C stops"
    );
    for (t, n) in &templates {
        println!("  {}", describe(t, *n));
        for line in event_lines(t, args.json) {
            println!("{line}");
        }
    }
    if let Some(root) = &args.foe_dir {
        for (unit, n) in &loaded {
            let dir = crate::foe::dir::unit_dir(root, *unit);
            println!("  unit {unit}: {n} FoE file(s) in {}", dir.display());
        }
    }
    tracing::info!(interface, units = total, "emulated units on line");
    let root = args.foe_dir.clone();
    let mut keep = |k: usize, name: &[u8], data: &[u8]| {
        let Some(root) = &root else { return };
        match crate::foe::dir::save(root, k + 1, name, data) {
            Ok(path) => tracing::info!(unit = k + 1, path = %path.display(), "FoE file kept"),
            Err(e) => tracing::error!(unit = k + 1, error = %e, "FoE file not kept"),
        }
    };
    let stats = runtime::serve(
        &socket,
        interface,
        Duration::from_micros(args.busy_poll_us),
        chain,
        &stop,
        &mut keep,
    )?;
    Ok(stats)
}
