//! The `sdo-tool` command line: the global options, the commands, and [`run`], which hands each
//! command to its module under [`crate::cmd`]. `main` only parses and calls [`run`].

use std::io::Write;
use std::path::PathBuf;
use std::time::Duration;

use clap::{CommandFactory, Parser, Subcommand};

use crate::cmd::apply::ApplyArgs;
use crate::cmd::decode::DecodeArgs;
use crate::cmd::dump::DumpArgs;
use crate::cmd::ethercat::{SdosArgs, SlavesArgs};
use crate::cmd::foe::{FoeReadArgs, FoeWriteArgs};
use crate::cmd::gateway::GatewayArgs;
use crate::cmd::lss::LssArgs;
use crate::cmd::net::NetArgs;
use crate::cmd::nmt::NmtArgs;
use crate::cmd::pdos::{Layout, SlavesOf};
use crate::cmd::read::ReadArgs;
use crate::cmd::reg::{RegReadArgs, RegWriteArgs};
use crate::cmd::scan::ScanArgs;
use crate::cmd::sdo::SdoCommand;
use crate::cmd::sii::{AliasArgs, SiiReadArgs, SiiWriteArgs};
use crate::cmd::store::StoreArgs;
use crate::cmd::transfer::{DownloadArgs, UploadArgs};
use crate::cmd::watch::WatchArgs;
use crate::cmd::write::WriteArgs;
use crate::cmd::{load_devices, Context};
use crate::ethercat::{check_interface_name, EthercatSession};
use crate::link::{BusSpec, CanBus, Capture, Captured, SocketCanBus, SocketcandClient};
use crate::{BlockMode, Tool, ToolError, UsageError};

pub use crate::cmd::gateway::GATEWAY_CLIENTS;
pub use crate::cmd::read::{json_value, Meaning};

/// `--ethercat IFACE`: a name the kernel could give an interface, checked before any socket.
fn interface_name(s: &str) -> Result<String, String> {
    check_interface_name(s)
        .map(|()| s.to_string())
        .map_err(|e| e.to_string())
}

/// The CANopen commissioning tool: SDO reads and writes, NMT, on SocketCAN or socketcand — and SDO
/// reads and writes of EtherCAT slaves (CoE) with --ethercat.
///
/// Without --bus (or CANOPEN_BUS) it uses SocketCAN vcan0 where this machine has it, and otherwise
/// the socketcand server that `x67-node` starts on 127.0.0.1:29536. With --ethercat IFACE the tool is an EtherCAT
/// master on that network interface instead (root or CAP_NET_RAW): it brings the chain's slaves to
/// Pre-Op and reaches their object dictionary through their CoE mailbox; NODE is then the slave's
/// position in the chain, 1 for the first; read, write, dump and apply work there, and slaves,
/// states, sdos, pdos, sii-read, sii-write, reg-read, reg-write, alias, xml, cstruct, foe-write and foe-read (IgH's
/// `ethercat` tool's, in its layouts) are EtherCAT's own; the other commands are CANopen only. Types are CiA 309-3 mnemonics: b, i8–i64, u8–u64, x8–x64 (shown in
/// hex), r32, r64, vs, os, us, d, hex. Exit codes: 0 done, 1 SDO abort or FoE error, 2 usage, 3 timeout or
/// transport failure, 4 verification difference (apply), 130 interrupted (Ctrl-C).
#[derive(Debug, Parser)]
#[command(name = "sdo-tool", version)]
pub struct Args {
    /// The bus: IFACE or socketcan:IFACE (e.g. can0, vcan0), or socketcand://HOST:PORT/CHANNEL.
    #[arg(long, global = true, value_name = "BUS", env = crate::link::BUS_VARIABLE)]
    pub bus: Option<BusSpec>,
    /// An EtherCAT network interface instead of a CAN bus (it wins over a CANOPEN_BUS of the
    /// environment): NODE is the slave's position in the chain (1 = first); read, write, dump,
    /// apply, drive and EtherCAT's own commands only.
    #[arg(
        long,
        global = true,
        value_name = "IFACE",
        conflicts_with = "bus",
        value_parser = interface_name
    )]
    pub ethercat: Option<String>,
    /// A device description (EDS, DCF, XDD or ESI) for object names, types and limits.
    #[arg(long, global = true, value_name = "FILE")]
    pub od: Option<PathBuf>,
    /// SDO timeout per answer, in ms.
    #[arg(long, global = true, default_value_t = 1000, value_name = "MS")]
    pub timeout_ms: u64,
    /// Machine-readable output: one JSON object per result (errors too, on standard output).
    #[arg(long, global = true)]
    pub json: bool,
    /// Use block transfer for every transfer of more than 4 bytes (uploads of unknown size too);
    /// by default only a download of more than 64 bytes and an upload of a DOMAIN (--od) go by
    /// block, the rest expedited or segmented.
    #[arg(long, global = true, conflicts_with = "no_block")]
    pub block: bool,
    /// Use expedited and segmented transfers only (no block transfer).
    #[arg(long, global = true)]
    pub no_block: bool,
    /// Writes every frame the tool sends and receives to FILE, a pcapng capture Wireshark and
    /// tshark read: on a CAN bus its SocketCAN frames (LINKTYPE_CAN_SOCKETCAN, the bus's name as
    /// the interface's), with --ethercat the Ethernet frames of the interface (LINKTYPE_ETHERNET);
    /// nanosecond times, each frame's direction; written whenever the tool waits, whole when it ends.
    #[arg(long, global = true, value_name = "FILE")]
    pub capture: Option<PathBuf>,
    /// Standard output is a terminal (`main` says; `sii-read` lists the image there instead of
    /// writing its bytes).
    #[arg(skip)]
    pub stdout_terminal: bool,
    /// What to do.
    #[command(subcommand)]
    pub command: Cmd,
}

impl Args {
    /// The command line as `main` takes it, clap's errors printed and the process ended with their
    /// exit code (2).
    pub fn from_command_line() -> Args {
        Args::try_from_words(std::env::args_os()).unwrap_or_else(|e| e.exit())
    }

    /// `argv` parsed as clap's derive does, except that a bus from the environment
    /// ([`crate::link::BUS_VARIABLE`]) does not count against `--ethercat`: only a `--bus` given in
    /// the words excludes it, and with `--ethercat` the environment's bus is not looked at (nor
    /// checked).
    pub fn try_from_words<I, T>(argv: I) -> Result<Args, clap::Error>
    where
        I: IntoIterator<Item = T>,
        T: Into<std::ffi::OsString> + Clone,
    {
        use clap::error::ErrorKind;
        use clap::{CommandFactory, FromArgMatches};
        let argv: Vec<std::ffi::OsString> = argv.into_iter().map(Into::into).collect();
        // First without the environment: with --ethercat that is the answer.
        let words_only = Args::command().mut_arg("bus", |a| a.env(None));
        match words_only.try_get_matches_from(&argv) {
            Ok(m) if m.get_one::<String>("ethercat").is_some() => Args::from_arg_matches(&m),
            Err(e)
                if !matches!(
                    e.kind(),
                    ErrorKind::DisplayHelp
                        | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
                        | ErrorKind::DisplayVersion
                ) =>
            {
                Err(e)
            }
            // Without --ethercat (or for the help): with the environment.
            _ => Args::from_arg_matches(&Args::command().try_get_matches_from(&argv)?),
        }
    }
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Cmd {
    /// Read an object: `read NODE OBJECT [TYPE]` (OBJECT as 0x1018:01, 1018sub1 or a name with --od).
    Read(ReadArgs),
    /// Write an object: `write NODE OBJECT TYPE VALUE` (TYPE may be left out with --od).
    Write(WriteArgs),
    /// Upload an object's contents (a DOMAIN, typically) into FILE, with a progress bar.
    Upload(UploadArgs),
    /// Download FILE into an object (a DOMAIN, typically), with a progress bar.
    Download(DownloadArgs),
    /// Read the node's parameters (the writable entries of the --od description, without command
    /// objects, cyclic outputs and DOMAINs) into a DCF; the write-only ones, which cannot be read
    /// back, are named, and so are the entries the description flags "refuse read on scan"
    /// (ObjFlags bit 1), which are not read.
    Dump(DumpArgs),
    /// Write the values a DCF sets (ParameterValue) to the node in CiA 301 order (each PDO made
    /// invalid, its mapping count 0, the entries, the count, the PDO as the file gives it), reading
    /// each back. An entry the DCF flags "refuse write on download" (ObjFlags bit 0) is not written,
    /// and said so. An entry the node refuses as such (read-only, missing) is skipped with a warning,
    /// another refusal is counted and the rest goes on. Exit 1 when a write was refused, 4 when a
    /// value reads back differently.
    Apply(ApplyArgs),
    /// Show heartbeats, NMT state changes, EMCY messages in words and (with --od and NODE) TPDOs
    /// decoded field by field, until Ctrl-C or --duration-ms.
    Watch(WatchArgs),
    /// Names every frame of a candump log (`candump -L`, or `watch --log`; `-` reads standard
    /// input): NMT, boot-up and heartbeats, SYNC, EMCY, SDO transfers reassembled with their values,
    /// and with --od and NODE the node's PDOs field by field.
    ///
    /// The log is read line by line: a line of more than 4096 bytes is no frame and is skipped
    /// unread, with a warning naming its number. At the end, each SDO transfer still open gets a
    /// line "left open" (node, entry, kind, the bytes so far, the time of its last frame; with
    /// --json an event with "open"). The exit code stays 0 with transfers left open: a capture
    /// stopped at any moment may end in the middle of one, and the lines say so.
    Decode(DecodeArgs),
    /// A CiA 302 network: `net gen [-r] [-S] BUS.yml -d DIR` writes each slave's concise DCF,
    /// master.dcf and master.bin from a bus description (Lely dcfgen's YAML or ros2_canopen's
    /// bus.yml), as dcfgen does; `net check BUS.yml` says what is wrong with one, line by line.
    Net(NetArgs),
    /// Store the node's parameters: 0x1010:01 = "save".
    Save(StoreArgs),
    /// Restore the node's default parameters at its next reset: 0x1011:01 = "load".
    Restore(StoreArgs),
    /// With --ethercat: every slave of the chain, read only (any state, whoever runs the chain), in
    /// the layout of IgH's `ethercat slaves`: position (1 = first), the alias of the slave or of the
    /// last one before it with an alias and the position after that one, AL state, `+` (`E`: its
    /// SII could not be read), and the device name of its SII (else the --od description's for its
    /// product code, else vendor and product code). --verbose: each slave in detail.
    Slaves(SlavesArgs),
    /// With --ethercat: every slave's AL state and AL status code, read only.
    States,
    /// With --ethercat: the object dictionary of the slave at NODE (every slave without it) as the
    /// slave describes it by SDO Information, in the layout of IgH's `ethercat sdos`: each object,
    /// then each entry with its access in Pre-Op, Safe-Op and Op (`rwrwrw`), type, bit length and
    /// name. `read` and `write` take the type from the same source when neither TYPE nor --od is
    /// given.
    Sdos(SdosArgs),
    /// With --ethercat: send FILE to a slave by FoE (`-` reads standard input), as NAME (-o; FILE's
    /// name by default), with PASSWORD (0x… or decimal); -p POS selects the slave (1 = first),
    /// --boot takes it to Bootstrap first (where firmware goes). As IgH's `ethercat foe_write`.
    /// Exit 1 when the slave refuses it (its FoE error code and text are printed).
    #[command(name = "foe-write", alias = "foe_write")]
    FoeWrite(FoeWriteArgs),
    /// With --ethercat: fetch SOURCEFILE from a slave by FoE into -o FILE (standard output by
    /// default), with PASSWORD; -p POS and --boot as for foe-write. As IgH's `ethercat foe_read`.
    #[command(name = "foe-read", alias = "foe_read")]
    FoeRead(FoeReadArgs),
    /// With --ethercat: the slave's SII (EEPROM) image, read through its EEPROM interface up to the
    /// End category, as IgH's `ethercat sii_read`: raw bytes into -o FILE or onto standard output
    /// when it is no terminal; --verbose (and a terminal) lists the header words and each category.
    #[command(alias = "sii_read")]
    SiiRead(SiiReadArgs),
    /// With --ethercat: writes FILE into the slave's EEPROM word by word, as IgH's `ethercat
    /// sii_write`: refused unless it is whole words, at least 65 of them, with the checksum of words
    /// 0–6 in byte 14 and categories that end (--force writes it anyway), and refused when larger
    /// than the EEPROM the slave's SII gives (word 0x3E); nothing is written then.
    #[command(alias = "sii_write")]
    SiiWrite(SiiWriteArgs),
    /// With --ethercat: the slave's ESC registers (0x0000–0x0FFF) from ADDRESS, as IgH's `ethercat
    /// reg_read`: raw bytes in hex, or as --type int8…int64, uint8…uint64 (`0x0130 304`) or string.
    #[command(alias = "reg_read")]
    RegRead(RegReadArgs),
    /// With --ethercat: writes the slave's ESC registers from ADDRESS, as IgH's `ethercat
    /// reg_write`: DATA is a value of --type, or without it a file of bytes (`-`: standard input).
    #[command(alias = "reg_write")]
    RegWrite(RegWriteArgs),
    /// With --ethercat: the configured station alias (0 to 65535, 0 for none) into SII word 4 of the
    /// slave at POS (of every slave without it: --force on a chain of several) with the checksum
    /// made again, as IgH's `ethercat alias`; then the EEPROM reloaded, so that the alias register
    /// 0x0012 holds it at once.
    Alias(AliasArgs),
    /// With --ethercat: each slave's SyncManagers, PDOs and entries in the layout of IgH's `ethercat
    /// pdos`, from the SII and, for a slave with CoE, its PDO assignment (0x1C12, 0x1C13, …) and
    /// mapping objects read in Pre-Op (a chain another master runs: the SII's).
    Pdos(SlavesOf),
    /// With --ethercat: an ESI of what the slaves report (identity, names, SyncManagers, PDOs), in the
    /// layout of IgH's `ethercat xml`; several slaves as an EtherCATInfoList.
    Xml(SlavesOf),
    /// With --ethercat: each slave's PDOs as the C arrays of IgH's application interface
    /// (ec_pdo_entry_info_t, ec_pdo_info_t, ec_sync_info_t), as IgH's `ethercat cstruct`.
    Cstruct(SlavesOf),
    /// The entries of the --od description, one per line: address, name, type, access, default and
    /// limits (no bus needed); the names `read` and `write` take.
    List,
    /// Every node on the bus (asked for 0x1000, or seen by boot-up or heartbeat), with its identity.
    Scan(ScanArgs),
    /// A CiA 309-3 ASCII gateway on standard input and output, or on a TCP socket with --listen
    /// (one client at a time; 127.0.0.1 unless another address is given). `help` lists the requests.
    Gateway(GatewayArgs),
    /// An NMT command: start, stop, preop, reset, reset-comm; NODE is 1–127 or all.
    Nmt(NmtArgs),
    /// One frame in can-utils' cansend notation: `send 123#DEADBEEF`, `send 123#R` (remote frame),
    /// `send 12345678#00` (29-bit identifier).
    Send(crate::cmd::raw::SendArgs),
    /// SYNC messages (CiA 301): one by default, --count N of them --period-ms apart (0: until
    /// Ctrl-C), with the counter byte (--counter, up to --overflow), on 0x80 or --cob-id.
    Sync(crate::cmd::raw::SyncArgs),
    /// The LSS master (CiA 305): `lss scan` finds the nodes without a node-ID by Fastscan, `lss
    /// assign FIRST_ID` gives them node-IDs and stores them; `set-id`, `store`, `bitrate`,
    /// `inquire` and `switch` are the single services.
    Lss(LssArgs),
    /// A CiA 402 drive: `status` (state, mode, position, velocity, the statusword's bits by name;
    /// --watch), `enable`, `disable`, `fault-reset`, `quick-stop`, `home [METHOD]`, `move POS`,
    /// `jog V`, `stop`. Each waits for the drive to do it; a drive that does not says where it
    /// stayed and its error code. On CAN or, with --ethercat, on an EtherCAT chain.
    Drive(crate::cmd::drive::DriveArgs),
    /// The shell completion script for SHELL (bash, zsh, fish, elvish, powershell) on standard
    /// output: `source <(sdo-tool completions bash)`.
    Completions {
        /// The shell.
        shell: cli_support::Shell,
    },
    /// The manual pages into DIR: sdo-tool.1 and one per command (sdo-tool-read.1, …,
    /// sdo-tool-net-gen.1), each file named on standard output: `man -l DIR/sdo-tool-read.1`.
    Man {
        /// The folder (made if missing).
        dir: PathBuf,
    },
}

impl Cmd {
    /// The command's name on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Cmd::Read(_) => "read",
            Cmd::Write(_) => "write",
            Cmd::Upload(_) => "upload",
            Cmd::Download(_) => "download",
            Cmd::Dump(_) => "dump",
            Cmd::Apply(_) => "apply",
            Cmd::Watch(_) => "watch",
            Cmd::Save(_) => "save",
            Cmd::Restore(_) => "restore",
            Cmd::Scan(_) => "scan",
            Cmd::Gateway(_) => "gateway",
            Cmd::Nmt(_) => "nmt",
            Cmd::Send(_) => "send",
            Cmd::Sync(_) => "sync",
            Cmd::Lss(_) => "lss",
            Cmd::Drive(_) => "drive",
            Cmd::List => "list",
            Cmd::Decode(_) => "decode",
            Cmd::Net(_) => "net",
            Cmd::Slaves(_) => "slaves",
            Cmd::States => "states",
            Cmd::Sdos(_) => "sdos",
            Cmd::Completions { .. } => "completions",
            Cmd::Man { .. } => "man",
            Cmd::FoeWrite(_) => "foe-write",
            Cmd::FoeRead(_) => "foe-read",
            Cmd::SiiRead(_) => "sii-read",
            Cmd::SiiWrite(_) => "sii-write",
            Cmd::RegRead(_) => "reg-read",
            Cmd::RegWrite(_) => "reg-write",
            Cmd::Alias(_) => "alias",
            Cmd::Pdos(_) => "pdos",
            Cmd::Xml(_) => "xml",
            Cmd::Cstruct(_) => "cstruct",
        }
    }

    /// Whether the command is EtherCAT's own (it needs --ethercat).
    pub fn ethercat_only(&self) -> bool {
        matches!(
            self,
            Cmd::Slaves(_)
                | Cmd::States
                | Cmd::Sdos(_)
                | Cmd::SiiRead(_)
                | Cmd::SiiWrite(_)
                | Cmd::RegRead(_)
                | Cmd::RegWrite(_)
                | Cmd::Alias(_)
                | Cmd::Pdos(_)
                | Cmd::Xml(_)
                | Cmd::Cstruct(_)
                | Cmd::FoeWrite(_)
                | Cmd::FoeRead(_)
        )
    }

    /// The command as an SDO command, when it is one: those run over EtherCAT too.
    pub fn sdo(&self) -> Option<SdoCommand<'_>> {
        match self {
            Cmd::Read(a) => Some(SdoCommand::Read(a)),
            Cmd::Write(a) => Some(SdoCommand::Write(a)),
            Cmd::Dump(a) => Some(SdoCommand::Dump(a)),
            Cmd::Apply(a) => Some(SdoCommand::Apply(a)),
            _ => None,
        }
    }
}

/// Opens the bus `spec` names, or the default one: the bus and its spec.
pub fn open_bus(spec: Option<&BusSpec>) -> Result<(BusSpec, Box<dyn CanBus>), ToolError> {
    match spec {
        Some(BusSpec::SocketcandListen { .. }) => Err(UsageError::ListeningBus.into()),
        Some(s) => Ok((s.clone(), crate::link::open_spec(s)?)),
        None => match SocketCanBus::open("vcan0") {
            Ok(b) => Ok((
                BusSpec::SocketCan {
                    iface: "vcan0".into(),
                },
                Box::new(b),
            )),
            Err(_) => {
                let port = crate::link::SOCKETCAND_DEFAULT_PORT;
                let bus = SocketcandClient::connect("127.0.0.1", port, "can0")?;
                let spec = BusSpec::Socketcand {
                    host: "127.0.0.1".into(),
                    port,
                    channel: "can0".into(),
                };
                Ok((spec, Box::new(bus)))
            }
        },
    }
}

/// The capture of `--capture`, created right before a bus or an interface is opened.
fn capture(args: &Args) -> Result<Option<Capture>, ToolError> {
    let Some(path) = &args.capture else {
        return Ok(None);
    };
    let application = concat!("sdo-tool ", env!("CARGO_PKG_VERSION"));
    Capture::create(path, application)
        .map(Some)
        .map_err(|e| UsageError::Capture(e).into())
}

/// Runs `args` on `bus` (opened from the arguments when `None`), printing to `out`. With
/// `--ethercat` the SDO commands run on the EtherCAT chain of that interface instead (and `bus` is
/// not used).
pub fn run(
    args: &Args,
    bus: Option<Box<dyn CanBus>>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    match &args.command {
        Cmd::Completions { shell } => {
            return cli_support::write_completions(Args::command(), *shell, out)
                .map_err(ToolError::Output);
        }
        Cmd::Man { dir } => {
            let pages = cli_support::write_man_pages(Args::command(), dir)
                .map_err(|e| crate::cmd::file_error(dir, e))?;
            for page in pages {
                writeln!(out, "{}", page.display()).map_err(ToolError::Output)?;
            }
            return Ok(());
        }
        _ => {}
    }
    let devices = match &args.od {
        Some(path) => load_devices(path, "--od")?,
        None => Vec::new(),
    };
    let desc = devices.first();
    let ctx = Context {
        json: args.json,
        desc,
        devices: &devices,
        od_path: args.od.as_deref(),
    };
    let timeout = Duration::from_millis(args.timeout_ms.max(1));
    let offline = match &args.command {
        Cmd::Decode(_) | Cmd::List => true,
        Cmd::Net(a) => !a.command.needs_bus(),
        _ => false,
    };
    if offline && args.capture.is_some() {
        return Err(UsageError::CaptureWithoutLink {
            command: args.command.name(),
        }
        .into());
    }
    match &args.command {
        Cmd::Decode(a) => {
            let od = desc.as_ref().map(|d| &d.dictionary);
            return crate::cmd::decode::run(a, od, args.json, out);
        }
        Cmd::Net(a) if !a.command.needs_bus() => return crate::cmd::net::run(a, args.json, out),
        Cmd::List => {
            let desc = desc.as_ref().ok_or(UsageError::ListNeedsDescription)?;
            return crate::cmd::list::run(desc, args.json, out);
        }
        c if c.ethercat_only() => return ethercat_command(args, ctx, timeout, out),
        _ => {}
    }
    // A name the description does not have is refused before any bus or chain is opened (a name
    // one of its devices has is taken: which one the node is, is known once it is asked).
    if let Cmd::Read(ReadArgs { object, .. }) | Cmd::Write(WriteArgs { object, .. }) = &args.command
    {
        let named = |d: &od::DeviceDescription| crate::object(Some(&d.dictionary), object).is_ok();
        if !devices.iter().any(named) {
            crate::object(desc.map(|d| &d.dictionary), object)?;
        }
    }
    if let Some(interface) = &args.ethercat {
        if let Cmd::Drive(a) = &args.command {
            let capture = capture(args)?;
            let session = EthercatSession::open_captured(interface, timeout, capture.as_ref())?;
            let mut op = session.into_op()?;
            return crate::cmd::drive::run(a, &mut op, args.json, out);
        }
        let command = args.command.sdo().ok_or(UsageError::CanopenOnly {
            command: args.command.name(),
        })?;
        let capture = capture(args)?;
        let mut session = EthercatSession::open_captured(interface, timeout, capture.as_ref())?;
        return command.run(&mut session, ctx, out);
    }
    let capture = capture(args)?;
    let (name, bus) = match bus {
        Some(b) => (b.describe(), b),
        None => {
            let (spec, bus) = open_bus(args.bus.as_ref())?;
            (spec.interface_name(), bus)
        }
    };
    let bus: Box<dyn CanBus> = match &capture {
        Some(c) => Box::new(Captured::new(bus, c, &name)),
        None => bus,
    };
    let mut tool = Tool::new(bus, desc.map(|d| d.dictionary.clone()));
    tool.set_timeout(timeout);
    tool.block = match (args.block, args.no_block) {
        (true, _) => BlockMode::Always,
        (_, true) => BlockMode::Never,
        _ => BlockMode::Auto,
    };
    can_command(args, tool, ctx, out)
}

/// `slaves`, `states` and `sdos`: EtherCAT's own commands, which need `--ethercat`.
fn ethercat_command(
    args: &Args,
    ctx: Context<'_>,
    timeout: Duration,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let Some(interface) = &args.ethercat else {
        return Err(UsageError::EthercatOnly {
            command: args.command.name(),
        }
        .into());
    };
    use crate::cmd::{ethercat, foe, pdos, reg, sii};
    let json = args.json;
    let capture = capture(args)?;
    let capture = capture.as_ref();
    match &args.command {
        Cmd::Sdos(a) => {
            let mut session = EthercatSession::open_captured(interface, timeout, capture)?;
            ethercat::sdos(&mut session, a, json, out)
        }
        Cmd::FoeWrite(a) => foe::write(a, interface, timeout, capture, json, out),
        Cmd::FoeRead(a) => foe::read(a, interface, timeout, capture, json, out),
        Cmd::Slaves(a) => ethercat::slaves(interface, a, ctx, timeout, capture, out),
        Cmd::SiiRead(a) => {
            let terminal = args.stdout_terminal;
            sii::sii_read(interface, a, ctx, timeout, capture, terminal, out)
        }
        Cmd::SiiWrite(a) => sii::sii_write(interface, a, ctx, timeout, capture, out),
        Cmd::Alias(a) => sii::alias(interface, a, ctx, timeout, capture, out),
        Cmd::RegRead(a) => reg::reg_read(interface, a, json, timeout, capture, out),
        Cmd::RegWrite(a) => reg::reg_write(interface, a, json, timeout, capture, out),
        Cmd::Pdos(a) => pdos::run(interface, a, Layout::Pdos, json, timeout, capture, out),
        Cmd::Xml(a) => pdos::run(interface, a, Layout::Xml, json, timeout, capture, out),
        Cmd::Cstruct(a) => pdos::run(interface, a, Layout::Cstruct, json, timeout, capture, out),
        _ => ethercat::states(interface, timeout, capture, json, out),
    }
}

/// The commands on a CAN bus, with `tool` on it.
fn can_command(
    args: &Args,
    mut tool: Tool,
    ctx: Context<'_>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    use crate::cmd::{gateway, lss, nmt, scan, store, transfer, watch};
    let json = args.json;
    if let Some(command) = args.command.sdo() {
        return command.run(&mut tool.can_sdo(), ctx, out);
    }
    match &args.command {
        Cmd::Upload(a) => {
            transfer::cancel_on_interrupt(&mut tool);
            transfer::upload(a, &mut tool, json, out)
        }
        Cmd::Download(a) => {
            transfer::cancel_on_interrupt(&mut tool);
            transfer::download(a, &mut tool, json, out)
        }
        Cmd::Watch(a) => watch::run(a, &mut tool, args.bus.as_ref(), json, out),
        Cmd::Save(a) => store::run(a, false, &mut tool, json, out),
        Cmd::Restore(a) => store::run(a, true, &mut tool, json, out),
        Cmd::Scan(a) => scan::run(a, &mut tool, json, out),
        Cmd::Gateway(a) => gateway::run(a, tool, out),
        Cmd::Nmt(a) => nmt::run(a, &mut tool, json, out),
        Cmd::Send(a) => crate::cmd::raw::send(a, &mut tool, json, out),
        Cmd::Sync(a) => crate::cmd::raw::sync(a, &mut tool, json, out),
        Cmd::Lss(a) => lss::run(a, &mut tool, json, out),
        Cmd::Net(a) => crate::cmd::net::run_on_bus(a, &mut tool, json, out),
        Cmd::Drive(a) => crate::cmd::drive::run(a, &mut tool.can_sdo(), json, out),
        // Answered before any bus is opened: the SDO commands above, `list`, `decode`,
        // `completions`, `man` and EtherCAT's own commands.
        _ => Ok(()),
    }
}

/// An error as `--json` prints it.
pub fn error_json(e: &ToolError) -> serde_json::Value {
    let abort = match e {
        ToolError::Abort { code, .. } => Some(format!("0x{:08X}", code.code())),
        _ => None,
    };
    serde_json::json!({"error": e.to_string(), "exit_code": e.exit_code(), "abort": abort})
}
