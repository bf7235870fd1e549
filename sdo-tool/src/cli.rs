//! The `sdo-tool` command line: arguments and what each command does. `main` only parses and calls
//! [`run`].

use std::io::Write;
use std::path::PathBuf;
use std::time::Duration;

use clap::{Parser, Subcommand};

use crate::ethercat::{check_interface_name, EthercatSession};

/// `--ethercat IFACE`: a name the kernel could give an interface, checked before any socket.
fn interface_name(s: &str) -> Result<String, String> {
    check_interface_name(s)
        .map(|()| s.to_string())
        .map_err(|e| e.to_string())
}
use crate::link::{BusSpec, CanBus, SocketCanBus, SocketcandClient, SAVE_SIGNATURE};
use crate::{NmtCommand, SdoCommands, Tool, ToolError, UsageError};
use od::dict::Address;

/// The CANopen commissioning tool: SDO reads and writes, NMT, on SocketCAN or socketcand — and SDO
/// reads and writes of EtherCAT slaves (CoE) with --ethercat.
///
/// Without --bus (or CANOPEN_BUS) it uses SocketCAN vcan0 where this machine has it, and otherwise
/// the socketcand server that `x67-node` starts on 127.0.0.1:29536. With --ethercat IFACE the tool is an EtherCAT
/// master on that network interface instead (root or CAP_NET_RAW): it brings the chain's slaves to
/// Pre-Op and reaches their object dictionary through their CoE mailbox; NODE is then the slave's
/// position in the chain, 1 for the first; read, write, dump and apply work there, and slaves,
/// states and sdos are EtherCAT's own; the other commands are CANopen only. Types are CiA 309-3 mnemonics: b, i8–i64, u8–u64, x8–x64 (shown in
/// hex), r32, r64, vs, os, us, d, hex. Exit codes: 0 done, 1 SDO abort, 2 usage, 3 timeout or
/// transport failure, 4 verification difference (apply), 130 interrupted (Ctrl-C).
#[derive(Debug, Parser)]
#[command(name = "sdo-tool", version)]
pub struct Args {
    /// The bus: IFACE or socketcan:IFACE (e.g. can0, vcan0), or socketcand://HOST:PORT/CHANNEL.
    #[arg(long, global = true, value_name = "BUS", env = crate::link::BUS_VARIABLE)]
    pub bus: Option<BusSpec>,
    /// An EtherCAT network interface instead of a CAN bus: NODE is the slave's position in the chain
    /// (1 = first); read, write, dump, apply, slaves, states and sdos only.
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
    /// Use segmented transfers only (no block transfer).
    #[arg(long, global = true)]
    pub no_block: bool,
    /// What to do.
    #[command(subcommand)]
    pub command: Cmd,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Cmd {
    /// Read an object: `read NODE OBJECT [TYPE]` (OBJECT as 0x1018:01, 1018sub1 or a name with --od).
    Read {
        /// Node-ID, 1–127 (with --ethercat: the slave's position, 1 = first).
        node: u8,
        /// The object.
        object: String,
        /// The type (may be left out with --od).
        #[arg(value_name = "TYPE")]
        ty: Option<String>,
    },
    /// Write an object: `write NODE OBJECT TYPE VALUE` (TYPE may be left out with --od).
    Write {
        /// Node-ID, 1–127 (with --ethercat: the slave's position, 1 = first).
        node: u8,
        /// The object.
        object: String,
        /// TYPE VALUE, or VALUE alone with --od.
        #[arg(num_args = 1..=2, required = true, allow_hyphen_values = true, value_name = "[TYPE] VALUE")]
        rest: Vec<String>,
    },
    /// Upload an object's contents (a DOMAIN, typically) into FILE, with a progress bar.
    Upload {
        /// Node-ID, 1–127.
        node: u8,
        /// The object.
        object: String,
        /// Where the bytes go.
        file: PathBuf,
    },
    /// Download FILE into an object (a DOMAIN, typically), with a progress bar.
    Download {
        /// Node-ID, 1–127.
        node: u8,
        /// The object.
        object: String,
        /// The bytes to send.
        file: PathBuf,
    },
    /// Read the node's parameters (the writable entries of the --od description, without command
    /// objects, cyclic outputs and DOMAINs) into a DCF; the write-only ones, which cannot be read
    /// back, are named, and so are the entries the description flags "refuse read on scan"
    /// (ObjFlags bit 1), which are not read.
    Dump {
        /// Node-ID, 1–127 (with --ethercat: the slave's position, 1 = first).
        node: u8,
        /// The DCF to write.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Write the values a DCF sets (ParameterValue) to the node in CiA 301 order (each PDO made
    /// invalid, its mapping count 0, the entries, the count, the PDO as the file gives it), reading
    /// each back. An entry the DCF flags "refuse write on download" (ObjFlags bit 0) is not written,
    /// and said so. An entry the node refuses as such (read-only, missing) is skipped with a warning,
    /// another refusal is counted and the rest goes on. Exit 1 when a write was refused, 4 when a
    /// value reads back differently.
    Apply {
        /// Node-ID, 1–127 (with --ethercat: the slave's position, 1 = first).
        node: u8,
        /// The DCF.
        file: PathBuf,
        /// Only show what would be written.
        #[arg(long)]
        dry_run: bool,
        /// Stop at the first refused write, as a strict configuration manager does.
        #[arg(long)]
        stop_on_error: bool,
        /// When every value is written and reads back equal, "save all parameters" (0x1010:01), so
        /// that the node keeps them over a power cycle.
        #[arg(long)]
        save: bool,
    },
    /// Show heartbeats, NMT state changes, EMCY messages in words and (with --od and NODE) TPDOs
    /// decoded field by field, until Ctrl-C or --duration-ms.
    Watch {
        /// Only this node.
        node: Option<u8>,
        /// Stop after this many ms.
        #[arg(long)]
        duration_ms: Option<u64>,
        /// Also write every frame to FILE in candump's log format (`candump -L`), for `decode`,
        /// canplayer or python-can.
        #[arg(long, value_name = "FILE")]
        log: Option<PathBuf>,
        /// Also show the frames it cannot name, as ID#DATA.
        #[arg(long)]
        raw: bool,
        /// The frames to take, as candump's filters (hex identifiers): ID, ID:MASK, LOW-HIGH, ~ to
        /// invert; several with commas or again. The others are neither shown nor logged.
        #[arg(long, value_name = "FILTER", value_delimiter = ',')]
        filter: Vec<crate::watch::CobFilter>,
        /// Only these kinds of lines: nmt, heartbeat, sync, emcy, sdo, pdo, other (with commas).
        #[arg(long, value_name = "KINDS", value_delimiter = ',')]
        only: Vec<crate::watch::Kind>,
    },
    /// Names every frame of a candump log (`candump -L`, or `watch --log`; `-` reads standard
    /// input): NMT, boot-up and heartbeats, SYNC, EMCY, SDO transfers reassembled with their values,
    /// and with --od and NODE the node's PDOs field by field.
    ///
    /// The log is read line by line: a line of more than 4096 bytes is no frame and is skipped
    /// unread, with a warning naming its number. At the end, each SDO transfer still open gets a
    /// line "left open" (node, entry, kind, the bytes so far, the time of its last frame; with
    /// --json an event with "open"). The exit code stays 0 with transfers left open: a capture
    /// stopped at any moment may end in the middle of one, and the lines say so.
    Decode {
        /// The log.
        log: PathBuf,
        /// Only this node (its PDOs need --od).
        node: Option<u8>,
        /// Also show the frames it cannot name, as ID#DATA.
        #[arg(long)]
        raw: bool,
        /// The frames to take, as candump's filters (hex identifiers): ID, ID:MASK, LOW-HIGH, ~ to
        /// invert; several with commas or again.
        #[arg(long, value_name = "FILTER", value_delimiter = ',')]
        filter: Vec<crate::watch::CobFilter>,
        /// Only these kinds of lines: nmt, heartbeat, sync, emcy, sdo, pdo, other (with commas).
        #[arg(long, value_name = "KINDS", value_delimiter = ',')]
        only: Vec<crate::watch::Kind>,
    },
    /// Store the node's parameters: 0x1010:01 = "save".
    Save {
        /// Node-ID, 1–127.
        node: u8,
    },
    /// Restore the node's default parameters at its next reset: 0x1011:01 = "load".
    Restore {
        /// Node-ID, 1–127.
        node: u8,
    },
    /// With --ethercat: every slave of the chain, read only (any state, whoever runs the chain): its
    /// position (1 = first), AL state, and SII identity (vendor, product, revision, serial), with the
    /// device's name where the --od description has its product code.
    Slaves,
    /// With --ethercat: every slave's AL state and AL status code, read only.
    States,
    /// With --ethercat: the object dictionary of the slave at NODE (every slave without it) as the
    /// slave describes it by SDO Information, in the layout of IgH's `ethercat sdos`: each object,
    /// then each entry with its access in Pre-Op, Safe-Op and Op (`rwrwrw`), type, bit length and
    /// name. `read` and `write` take the type from the same source when neither TYPE nor --od is
    /// given.
    Sdos {
        /// The slave's position (1 = first).
        node: Option<u8>,
    },
    /// The entries of the --od description, one per line: address, name, type, access, default and
    /// limits (no bus needed); the names `read` and `write` take.
    List,
    /// Every node on the bus (asked for 0x1000, or seen by boot-up or heartbeat), with its identity.
    Scan {
        /// How long to listen for answers, in ms.
        #[arg(long, default_value_t = 300)]
        wait_ms: u64,
    },
    /// A CiA 309-3 ASCII gateway on standard input and output, or on a TCP socket with --listen
    /// (one client at a time; 127.0.0.1 unless another address is given). `help` lists the requests.
    Gateway {
        /// Listen on ADDR:PORT instead of standard input.
        #[arg(long, value_name = "ADDR:PORT")]
        listen: Option<std::net::SocketAddr>,
    },
    /// An NMT command: start, stop, preop, reset, reset-comm; NODE is 1–127 or all.
    Nmt {
        /// The command.
        command: String,
        /// The node, or `all`.
        node: String,
    },
}

/// The DCF `dump` writes: the description file it read (`path`, when an EDS or DCF) with the values
/// read and what a DCF adds, so that what the description holds beyond the model stays; the
/// writer's DCF of `dumped` otherwise.
fn dcf_bytes(
    path: Option<&std::path::Path>,
    as_read: od::DeviceDescription,
    dumped: od::DeviceDescription,
) -> Vec<u8> {
    let original = path.and_then(|p| {
        let bytes = od::load::read_limited(p, od::load::MAX_FILE_BYTES).ok()?;
        Some((od::load::Format::detect(p, &bytes)?, bytes))
    });
    match original {
        Some((format, bytes)) => {
            od::carry::write(&bytes, format, &[as_read], od::load::Format::Dcf, &[dumped]).bytes
        }
        None => od::eds::write_dcf(&dumped).into_bytes(),
    }
}

/// The first device of a description file.
fn load_description(
    path: &std::path::Path,
    what: &'static str,
) -> Result<od::DeviceDescription, ToolError> {
    let (_, mut devices) = od::load::load(path).map_err(|error| UsageError::Description {
        what,
        path: path.to_path_buf(),
        error,
    })?;
    if devices.is_empty() {
        return Err(UsageError::NoDevice {
            what,
            path: path.to_path_buf(),
        }
        .into());
    }
    Ok(devices.swap_remove(0))
}

/// Opens the bus `spec` names, or the default one.
pub fn open_bus(spec: Option<&BusSpec>) -> Result<Box<dyn CanBus>, ToolError> {
    match spec {
        Some(BusSpec::SocketcandListen { .. }) => Err(UsageError::ListeningBus.into()),
        Some(s) => Ok(crate::link::open_spec(s)?),
        None => match SocketCanBus::open("vcan0") {
            Ok(b) => Ok(Box::new(b)),
            Err(_) => Ok(Box::new(SocketcandClient::connect(
                "127.0.0.1",
                crate::link::SOCKETCAND_DEFAULT_PORT,
                "can0",
            )?)),
        },
    }
}

/// The commands that run over EtherCAT too (SDO transfers only).
fn is_sdo_command(command: &Cmd) -> bool {
    matches!(
        command,
        Cmd::Read { .. } | Cmd::Write { .. } | Cmd::Dump { .. } | Cmd::Apply { .. }
    )
}

/// The command's name on the command line.
fn command_name(command: &Cmd) -> &'static str {
    match command {
        Cmd::Read { .. } => "read",
        Cmd::Write { .. } => "write",
        Cmd::Upload { .. } => "upload",
        Cmd::Download { .. } => "download",
        Cmd::Dump { .. } => "dump",
        Cmd::Apply { .. } => "apply",
        Cmd::Watch { .. } => "watch",
        Cmd::Save { .. } => "save",
        Cmd::Restore { .. } => "restore",
        Cmd::Scan { .. } => "scan",
        Cmd::Gateway { .. } => "gateway",
        Cmd::Nmt { .. } => "nmt",
        Cmd::List => "list",
        Cmd::Decode { .. } => "decode",
        Cmd::Slaves => "slaves",
        Cmd::States => "states",
        Cmd::Sdos { .. } => "sdos",
    }
}

/// `slaves` and `states` on the chain of `interface`.
fn chain(
    interface: &str,
    identity: bool,
    desc: Option<&od::DeviceDescription>,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let io = ToolError::Output;
    let slaves = crate::ethercat::slaves(interface, identity)?;
    let name = |product: u32| {
        desc.filter(|d| d.identity.product_code == product)
            .map(|d| d.identity.order_code.clone())
            .filter(|n| !n.is_empty())
    };
    if json {
        let list: Vec<serde_json::Value> = slaves
            .iter()
            .map(|s| {
                let mut v = serde_json::json!({
                    "position": s.position,
                    "state": crate::ethercat::state_name(s.al_status),
                    "al_status": s.al_status,
                    "al_status_code": s.al_code,
                });
                if let Some([vendor, product, revision, serial]) = s.identity {
                    v["vendor"] = vendor.into();
                    v["product"] = product.into();
                    v["revision"] = revision.into();
                    v["serial"] = serial.into();
                    v["name"] = name(product).into();
                }
                v
            })
            .collect();
        writeln!(out, "{}", serde_json::json!({ "slaves": list })).map_err(io)?;
        return Ok(());
    }
    for s in &slaves {
        let state = crate::ethercat::state_name(s.al_status);
        let mut line = format!("{:>3}  {state:<10}", s.position);
        if identity {
            match s.identity {
                Some([vendor, product, revision, serial]) => line.push_str(&format!(
                    "  0x{vendor:08X}  0x{product:08X}  0x{revision:08X}  {serial:>10}  {}",
                    name(product).unwrap_or_default()
                )),
                None => line.push_str("  (no SII identity)"),
            }
        } else {
            line.push_str(&format!("  AL status code 0x{:04X}", s.al_code));
        }
        writeln!(out, "{}", line.trim_end()).map_err(io)?;
    }
    Ok(())
}

/// `sdos`: the dictionary of the slave at `node` (every slave when `None`) by SDO Information.
fn sdos(
    session: &mut EthercatSession,
    node: Option<u8>,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    use crate::SdoAccess;
    let io = ToolError::Output;
    let positions: Vec<u8> = match node {
        Some(n) => {
            session.check_node(n)?;
            vec![n]
        }
        None => (1..=session.slave_count())
            .map(|n| u8::try_from(n).unwrap_or(u8::MAX))
            .collect(),
    };
    let type_name = |code: u16| match od::coe::info::data_type(code) {
        Some(t) => t.to_string(),
        None => format!("type 0x{code:04X}"),
    };
    let object_code = |code: u8| match code {
        7 => "VAR".to_string(),
        8 => "ARRAY".to_string(),
        9 => "RECORD".to_string(),
        c => format!("object code {c}"),
    };
    for &position in &positions {
        let objects = session.sdos(position)?;
        if json {
            let list: Vec<serde_json::Value> = objects
                .iter()
                .map(|o| {
                    let entries: Vec<serde_json::Value> = o
                        .entries
                        .iter()
                        .map(|e| {
                            serde_json::json!({
                                "sub": e.sub, "name": e.name,
                                "type": type_name(e.data_type), "type_code": e.data_type,
                                "bits": e.bit_length, "access": e.access_text(),
                                "rxpdo": e.access & 0x40 != 0, "txpdo": e.access & 0x80 != 0,
                            })
                        })
                        .collect();
                    serde_json::json!({
                        "index": o.object.index, "object": format!("0x{:04X}", o.object.index),
                        "name": o.object.name, "object_code": object_code(o.object.object_code),
                        "max_sub": o.object.max_sub, "entries": entries,
                    })
                })
                .collect();
            writeln!(
                out,
                "{}",
                serde_json::json!({"position": position, "objects": list})
            )
            .map_err(io)?;
            continue;
        }
        if positions.len() > 1 {
            writeln!(out, "=== Slave {position} ===").map_err(io)?;
        }
        for o in &objects {
            writeln!(
                out,
                "SDO 0x{:04X}, {}, \"{}\"",
                o.object.index,
                object_code(o.object.object_code),
                o.object.name
            )
            .map_err(io)?;
            for e in &o.entries {
                writeln!(
                    out,
                    "  0x{:04X}:{:02X}, {}, {}, {} bit, \"{}\"",
                    e.index,
                    e.sub,
                    e.access_text(),
                    type_name(e.data_type),
                    e.bit_length,
                    e.name
                )
                .map_err(io)?;
            }
        }
    }
    Ok(())
}

/// `decode`: every frame of a candump log, named, with its time since the log's first frame, read
/// line by line in bounded memory; at the end, the SDO transfers left open.
fn decode(
    path: &std::path::Path,
    w: crate::watch::Watcher,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    use crate::watch::{Decoded, LogDecoder, MAX_LOG_LINE};
    use std::io::Read;
    let stdin = path.as_os_str() == "-";
    let input: Box<dyn Read> = if stdin {
        Box::new(std::io::stdin())
    } else {
        let kind = std::fs::metadata(path).map_err(|e| file_error(path, e))?;
        if kind.is_dir() {
            return Err(UsageError::Directory {
                path: path.to_path_buf(),
            }
            .into());
        }
        Box::new(std::fs::File::open(path).map_err(|e| file_error(path, e))?)
    };
    let name = if stdin {
        "standard input".to_string()
    } else {
        path.display().to_string()
    };
    let mut log = LogDecoder::new(std::io::BufReader::new(input), w);
    while let Some(event) = log.next_event().map_err(|error| UsageError::Log {
        name: name.clone(),
        error,
    })? {
        match event {
            Decoded::Line { t, text } => emit(
                out,
                json,
                format!("{t:>10.6}  {text}"),
                serde_json::json!({"t": t, "event": text}),
            )?,
            Decoded::Open { t, transfer: o } => emit(
                out,
                json,
                format!("{t:>10.6}  {o}"),
                serde_json::json!({"t": t, "event": o.to_string(), "open": {
                    "node": o.node, "object": o.address.to_string(), "kind": o.kind,
                    "bytes": o.bytes, "size": o.size, "last": o.last,
                }}),
            )?,
            Decoded::TooLong { line } => eprintln!(
                "sdo-tool: {name}: line {line} is longer than {MAX_LOG_LINE} bytes, no candump -L \
                 frame: skipped"
            ),
        }
    }
    if let (n @ 1.., Some(first)) = log.not_frames() {
        eprintln!(
            "sdo-tool: {name}: {n} line(s) are no candump -L frames (the first: line {first}): \
             skipped"
        );
    }
    Ok(())
}

/// A value as JSON: numbers as numbers, a string as its text, bytes as hex (`"01 02 0A"`), a time
/// as its milliseconds and days.
pub fn json_value(v: &od::value::Value) -> serde_json::Value {
    use od::value::Value;
    match v {
        Value::Bool(b) => (*b).into(),
        Value::Int(i) => (*i).into(),
        Value::Uint(u) => (*u).into(),
        Value::Real32(f) => {
            serde_json::Number::from_f64(f64::from(*f)).map_or(serde_json::Value::Null, Into::into)
        }
        Value::Real64(f) => {
            serde_json::Number::from_f64(*f).map_or(serde_json::Value::Null, Into::into)
        }
        Value::String(t) => t.clone().into(),
        Value::Unicode(u) => String::from_utf16_lossy(u).into(),
        Value::Bytes(b) => b
            .iter()
            .map(|x| format!("{x:02X}"))
            .collect::<Vec<_>>()
            .join(" ")
            .into(),
        Value::Time(t) => serde_json::json!({"ms": t.ms, "days": t.days}),
    }
}

/// What a read value means beyond its number: its unit (from the description) and the names of
/// the bits set in it (those the description lists, or CiA 402's for its controlword and
/// statusword).
#[derive(Debug, Default, PartialEq)]
pub struct Meaning {
    /// The unit's symbol.
    pub unit: Option<String>,
    /// The names of the set bits, lowest bit first; `None` when the entry has no named bits.
    pub bits: Option<Vec<String>>,
}

impl Meaning {
    /// The meaning of `value` read from `addr` as `read_as` (the type given, else the
    /// description's), with `dict` for its description.
    pub fn of(
        dict: Option<&od::Dictionary>,
        addr: Address,
        value: &od::value::Value,
        read_as: Option<od::DataType>,
    ) -> Meaning {
        use od::value::Value;
        let object = dict.and_then(|d| d.object(addr.index));
        let entry = object.and_then(|o| o.subs.get(&addr.sub));
        let unit = entry
            .and_then(|e| e.unit)
            .map(od::units::unit_text)
            .filter(|u| !u.is_empty());
        let number = match value {
            Value::Uint(u) => Some(*u),
            Value::Int(i) => Some(*i as u64),
            _ => None,
        };
        let bits = number.and_then(|n| {
            let size = read_as.or(entry.map(|e| e.data_type))?.bit_size()?;
            let description = entry.and_then(|e| {
                e.description.as_deref().or(object
                    .filter(|o| !o.kind.has_subs())
                    .and_then(|o| o.description.as_deref()))
            });
            let named = od::bits::bit_names(addr.index, addr.sub, description, size);
            (!named.is_empty()).then(|| od::bits::set_names(n, &named))
        });
        Meaning { unit, bits }
    }

    /// `text` with the unit after it and the set bits in brackets: `50000 mV`,
    /// `17416  [Stopped Position_Invalid Module_OK]`.
    pub fn show(&self, text: &str) -> String {
        let mut t = text.to_string();
        if let Some(u) = &self.unit {
            t.push(' ');
            t.push_str(u);
        }
        if let Some(bits) = &self.bits {
            t.push_str(&format!("  [{}]", bits.join(" ")));
        }
        t
    }

    /// Adds `unit` and `bits` to a JSON object where there are any.
    pub fn add_to(&self, v: &mut serde_json::Value) {
        if let Some(u) = &self.unit {
            v["unit"] = u.clone().into();
        }
        if let Some(bits) = &self.bits {
            v["bits"] = bits.clone().into();
        }
    }
}

/// The index of the RECORD or ARRAY `text` names as a whole (its name, or its index without a
/// sub-index, `0x1018`), for `read` to read every entry of it.
fn whole_object(dict: &od::Dictionary, text: &str) -> Option<u16> {
    let t = text.trim();
    if t.contains(':') || t.contains('.') {
        return None;
    }
    let index = match t
        .strip_prefix("0x")
        .or_else(|| t.strip_prefix("0X"))
        .map(|h| u16::from_str_radix(h, 16))
    {
        Some(Ok(i)) => i,
        Some(Err(_)) => return None,
        None => {
            dict.objects()
                .find(|o| o.kind.has_subs() && o.name.eq_ignore_ascii_case(t))?
                .index
        }
    };
    dict.object(index)
        .filter(|o| o.kind.has_subs())
        .map(|o| o.index)
}

/// `read` of a whole RECORD or ARRAY: each readable entry of it, in sub-index order, a line each;
/// an entry the node refuses is said so and the others go on (exit 1 at the end).
fn read_object(
    commands: &mut SdoCommands<'_>,
    node: u8,
    dict: &od::Dictionary,
    index: u16,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let io = ToolError::Output;
    let object = dict.object(index).expect("whole_object found it");
    let mut entries = Vec::new();
    let mut refused = 0;
    for (&sub, e) in &object.subs {
        if !e.access.kind.readable() {
            continue;
        }
        let addr = Address::new(index, sub);
        // The type from the description (the commands have it).
        match commands.read_typed(node, &addr.to_string(), None) {
            Ok((value, text)) => {
                let meaning = Meaning::of(Some(dict), addr, &value, None);
                if !json {
                    writeln!(out, "{addr}  {} = {}", e.name, meaning.show(&text)).map_err(io)?;
                }
                let mut v = serde_json::json!({
                    "object": addr.to_string(), "name": e.name,
                    "value": json_value(&value), "text": text,
                });
                meaning.add_to(&mut v);
                entries.push(v);
            }
            Err(err @ ToolError::Abort { .. }) => {
                refused += 1;
                if !json {
                    writeln!(out, "{addr}  {}: {err}", e.name).map_err(io)?;
                }
                entries.push(serde_json::json!({
                    "object": addr.to_string(), "name": e.name, "error": err.to_string(),
                }));
            }
            Err(err) => return Err(err),
        }
    }
    if json {
        writeln!(
            out,
            "{}",
            serde_json::json!({"node": node, "object": format!("0x{index:04X}"), "entries": entries})
        )
        .map_err(io)?;
    }
    if refused > 0 {
        return Err(ToolError::Refused(refused));
    }
    Ok(())
}

/// The node an SDO command addresses.
fn command_node(command: &Cmd) -> Option<u8> {
    match command {
        Cmd::Read { node, .. }
        | Cmd::Write { node, .. }
        | Cmd::Dump { node, .. }
        | Cmd::Apply { node, .. } => Some(*node),
        _ => None,
    }
}

/// When `node`'s 0x1018:01 and 0x1018:02 (vendor and product) are not the description's: the warning
/// that says so. Nothing when they match, or when the node does not give them (the command then
/// reports what it finds).
fn identity_mismatch(
    commands: &mut SdoCommands<'_>,
    node: u8,
    desc: &od::DeviceDescription,
) -> Option<String> {
    let id = &desc.identity;
    if id.vendor_id == 0 && id.product_code == 0 {
        return None;
    }
    let mut read = |sub: u8| {
        let b = commands.read_raw(node, Address::new(0x1018, sub)).ok()?;
        Some(u32::from_le_bytes(b.get(..4)?.try_into().ok()?))
    };
    let (vendor, product) = (read(1)?, read(2)?);
    (vendor != id.vendor_id || product != id.product_code).then(|| {
        format!(
            "the description (--od) is of vendor 0x{:08X}, product 0x{:08X} ({}); node {node} \
             reports vendor 0x{vendor:08X}, product 0x{product:08X}",
            id.vendor_id, id.product_code, id.product_name
        )
    })
}

/// `list`: every entry of `desc`, in index order.
fn list(desc: &od::DeviceDescription, json: bool, out: &mut dyn Write) -> Result<(), ToolError> {
    let io = ToolError::Output;
    let mut rows = Vec::new();
    for o in desc.dictionary.objects() {
        for (&sub, e) in &o.subs {
            let name = if o.kind.has_subs() {
                format!("{}.{}", o.name, e.name)
            } else {
                o.name.clone()
            };
            let default = e.default.as_ref().map(|d| {
                if d.plus_node_id {
                    format!("$NODEID+{}", d.value)
                } else {
                    d.value.to_string()
                }
            });
            let limits = crate::limits_text(e);
            let addr = Address::new(o.index, sub);
            let unit = e.unit.map(od::units::unit_text);
            // What dump and apply leave out for the description's ObjFlags (CiA 306 §4.6.3).
            let flags = Some(o.flags_of(sub)).filter(|f| !f.is_empty());
            if json {
                rows.push(serde_json::json!({
                    "address": addr.to_string(),
                    "name": name,
                    "type": e.data_type.to_string(),
                    "access": e.access.kind.as_str(),
                    "default": default,
                    "limits": limits,
                    "unit": unit,
                    "obj_flags": flags.map(|f| f.bits()),
                }));
            } else {
                let mut line = format!(
                    "{addr}  {name}  {}  {}",
                    e.data_type,
                    e.access.kind.as_str()
                );
                if let Some(d) = default {
                    line.push_str(&format!("  default {d}"));
                }
                if let Some(l) = limits {
                    line.push_str(&format!("  limits {l}"));
                }
                if let Some(u) = unit {
                    line.push_str(&format!("  unit {u}"));
                }
                if let Some(f) = flags {
                    line.push_str(&format!("  ObjFlags {f}"));
                }
                writeln!(out, "{line}").map_err(io)?;
            }
        }
    }
    if json {
        writeln!(out, "{}", serde_json::json!({ "entries": rows })).map_err(io)?;
    }
    Ok(())
}

/// Runs `args` on `bus` (opened from the arguments when `None`), printing to `out`. With
/// `--ethercat` the SDO commands run on the EtherCAT chain of that interface instead (and `bus` is
/// not used).
pub fn run(
    args: &Args,
    bus: Option<Box<dyn CanBus>>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let desc = match &args.od {
        Some(path) => Some(load_description(path, "--od")?),
        None => None,
    };
    let timeout = Duration::from_millis(args.timeout_ms.max(1));
    if let Cmd::Decode {
        log,
        node,
        raw,
        filter,
        only,
    } = &args.command
    {
        let w = crate::watch::Watcher::new(*node, desc.as_ref().map(|d| &d.dictionary))
            .with_raw(*raw)
            .with_filters(filter.clone())
            .with_only(only.clone());
        return decode(log, w, args.json, out);
    }
    if let Cmd::List = args.command {
        let desc = desc.as_ref().ok_or(UsageError::ListNeedsDescription)?;
        return list(desc, args.json, out);
    }
    if let Cmd::Slaves | Cmd::States | Cmd::Sdos { .. } = args.command {
        let Some(interface) = &args.ethercat else {
            return Err(UsageError::EthercatOnly {
                command: command_name(&args.command),
            }
            .into());
        };
        if let Cmd::Sdos { node } = args.command {
            let mut session = EthercatSession::open(interface, timeout)?;
            return sdos(&mut session, node, args.json, out);
        }
        return chain(
            interface,
            matches!(args.command, Cmd::Slaves),
            desc.as_ref(),
            args.json,
            out,
        );
    }
    // A name the description does not have is refused before any bus or chain is opened.
    if let Cmd::Read { object, .. } | Cmd::Write { object, .. } = &args.command {
        crate::object(desc.as_ref().map(|d| &d.dictionary), object)?;
    }
    if let Some(interface) = &args.ethercat {
        if !is_sdo_command(&args.command) {
            return Err(UsageError::CanopenOnly {
                command: command_name(&args.command),
            }
            .into());
        }
        let mut session = EthercatSession::open(interface, timeout)?;
        let mut commands = SdoCommands::new(&mut session, desc.as_ref().map(|d| &d.dictionary));
        return sdo_command(&mut commands, args, desc.as_ref(), out);
    }
    let bus = match bus {
        Some(b) => b,
        None => open_bus(args.bus.as_ref())?,
    };
    let mut tool = Tool::new(bus, desc.as_ref().map(|d| d.dictionary.clone()));
    tool.set_timeout(timeout);
    tool.sdo.block = !args.no_block;
    if matches!(args.command, Cmd::Upload { .. } | Cmd::Download { .. }) {
        // Ctrl-C aborts the transfer on the bus (0x08000000) instead of leaving the node in it.
        let flag = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let f = std::sync::Arc::clone(&flag);
        if ctrlc::set_handler(move || f.store(true, std::sync::atomic::Ordering::Relaxed)).is_ok() {
            tool.cancel = Some(flag);
        }
    }
    let io = ToolError::Output;
    let json = args.json;
    match &args.command {
        Cmd::Read { .. } | Cmd::Write { .. } | Cmd::Dump { .. } | Cmd::Apply { .. } => {
            return tool.with_commands(|commands| sdo_command(commands, args, desc.as_ref(), out));
        }
        // Answered above, before any bus is opened.
        Cmd::List | Cmd::Decode { .. } | Cmd::Slaves | Cmd::States | Cmd::Sdos { .. } => {}
        Cmd::Upload { node, object, file } => {
            let mut f = std::fs::File::create(file).map_err(|e| file_error(file, e))?;
            let bar = progress_bar(None);
            let started = std::time::Instant::now();
            let n = match tool.upload(*node, object, &mut f, |done, total| {
                if let Some(t) = total {
                    bar.set_length(t);
                }
                bar.set_position(done);
            }) {
                Ok(n) => n,
                Err(ToolError::Interrupted { .. }) => {
                    bar.finish_and_clear();
                    drop(f);
                    let _ = std::fs::remove_file(file);
                    return Err(ToolError::Interrupted {
                        removed: Some(file.clone()),
                    });
                }
                Err(e) => return Err(e),
            };
            bar.finish_and_clear();
            let took = started.elapsed();
            emit(
                out,
                json,
                rate(n, took),
                serde_json::json!({"bytes": n, "seconds": took.as_secs_f64()}),
            )?;
        }
        Cmd::Download { node, object, file } => {
            // Looked at before opening: opening a FIFO waits for a writer; a device has no length.
            let kind = std::fs::metadata(file).map_err(|e| file_error(file, e))?;
            if !kind.is_file() {
                return Err(UsageError::NotRegularFile { path: file.clone() }.into());
            }
            let mut f = std::fs::File::open(file).map_err(|e| file_error(file, e))?;
            let len = f.metadata().map_err(|e| file_error(file, e))?.len();
            let bar = progress_bar(Some(len));
            let started = std::time::Instant::now();
            tool.download(*node, object, &mut f, len, |done, _| bar.set_position(done))?;
            bar.finish_and_clear();
            let took = started.elapsed();
            emit(
                out,
                json,
                rate(len, took),
                serde_json::json!({"bytes": len, "seconds": took.as_secs_f64()}),
            )?;
        }
        Cmd::Watch {
            node,
            duration_ms,
            log,
            raw,
            filter,
            only,
        } => {
            let mut w = crate::watch::Watcher::new(*node, tool.od.as_ref())
                .with_raw(*raw)
                .with_filters(filter.clone())
                .with_only(only.clone());
            let iface = match &args.bus {
                Some(BusSpec::SocketCan { iface }) => iface.clone(),
                Some(BusSpec::Socketcand { channel, .. }) => channel.clone(),
                _ => "can0".to_string(),
            };
            let mut log = match log {
                Some(path) => Some(std::io::BufWriter::new(
                    std::fs::File::create(path).map_err(|e| file_error(path, e))?,
                )),
                None => None,
            };
            let start = std::time::Instant::now();
            let end = duration_ms.map(|ms| start + Duration::from_millis(ms));
            let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
            if end.is_none() {
                let s = std::sync::Arc::clone(&stop);
                let _ =
                    ctrlc::set_handler(move || s.store(true, std::sync::atomic::Ordering::Relaxed));
            }
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                let wait = match end {
                    Some(e) => {
                        let left = e.saturating_duration_since(std::time::Instant::now());
                        if left.is_zero() {
                            break;
                        }
                        left.min(Duration::from_millis(100))
                    }
                    None => Duration::from_millis(100),
                };
                let event = tool.bus.recv(wait)?;
                let t = start.elapsed().as_secs_f64();
                let lines = match event {
                    Some(crate::link::BusEvent::Frame { frame, at }) => {
                        let taken = w.takes(&frame);
                        if let Some(l) = log.as_mut().filter(|_| taken) {
                            writeln!(l, "{}", crate::watch::candump(at, &iface, &frame))
                                .map_err(io)?;
                        }
                        w.at(t, &frame)
                    }
                    _ => w.missed(t),
                };
                for line in lines {
                    emit(
                        out,
                        json,
                        format!("{t:>9.3}  {line}"),
                        serde_json::json!({"t": t, "event": line}),
                    )?;
                }
            }
        }
        Cmd::Save { node } => {
            tool.store(*node, false)?;
            emit(out, json, "OK", serde_json::json!({"ok": true}))?;
        }
        Cmd::Restore { node } => {
            tool.store(*node, true)?;
            emit(out, json, "OK", serde_json::json!({"ok": true}))?;
        }
        Cmd::Scan { wait_ms } => {
            let nodes = tool.scan(Duration::from_millis(*wait_ms))?;
            if json {
                // Numbers as numbers, the name as its text.
                let number = |v: &Option<String>| {
                    v.as_deref()
                        .and_then(|t| u64::from_str_radix(t.trim_start_matches("0x"), 16).ok())
                };
                let list: Vec<serde_json::Value> = nodes
                    .iter()
                    .map(|n| {
                        serde_json::json!({
                            "node": n.node, "device_type": number(&n.device_type),
                            "vendor": number(&n.vendor), "product": number(&n.product),
                            "revision": number(&n.revision), "serial": number(&n.serial),
                            "name": n.name.as_deref().map(|t| t.trim_matches('"')),
                        })
                    })
                    .collect();
                writeln!(out, "{}", serde_json::json!({ "nodes": list })).map_err(io)?;
                return Ok(());
            }
            writeln!(
                out,
                "node  device type  vendor      product     revision    serial      name"
            )
            .map_err(io)?;
            let show = |v: &Option<String>| v.clone().unwrap_or_else(|| "-".into());
            for n in &nodes {
                writeln!(
                    out,
                    "{:>4}  {:<11}  {:<10}  {:<10}  {:<10}  {:<10}  {}",
                    n.node,
                    show(&n.device_type),
                    show(&n.vendor),
                    show(&n.product),
                    show(&n.revision),
                    show(&n.serial),
                    show(&n.name)
                )
                .map_err(io)?;
            }
            writeln!(out, "{} node(s)", nodes.len()).map_err(io)?;
        }
        Cmd::Gateway { listen } => {
            let gw = std::sync::Arc::new(std::sync::Mutex::new(crate::gateway::Gateway::new(tool)));
            match listen {
                None => {
                    let stdin = std::io::stdin();
                    crate::gateway::serve(&gw, stdin.lock(), out).map_err(io)?;
                }
                Some(addr) => {
                    let listener =
                        std::net::TcpListener::bind(addr).map_err(|error| UsageError::Listen {
                            address: *addr,
                            error,
                        })?;
                    gateway_connections(&listener, &gw);
                }
            }
            return Ok(());
        }
        Cmd::Nmt { command, node } => {
            let c = NmtCommand::parse(command).ok_or_else(|| UsageError::NmtCommand {
                command: command.clone(),
            })?;
            let n = if node == "all" {
                0
            } else {
                node.parse::<u8>()
                    .ok()
                    .filter(|n| (1..=127).contains(n))
                    .ok_or_else(|| UsageError::NmtNodeText { text: node.clone() })?
            };
            tool.nmt(c, n)?;
            emit(out, json, "OK", serde_json::json!({"ok": true}))?;
        }
    }
    Ok(())
}

/// `read`, `write`, `dump` and `apply` on `commands` (any network), printing to `out`.
fn sdo_command(
    commands: &mut SdoCommands<'_>,
    args: &Args,
    desc: Option<&od::DeviceDescription>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let io = ToolError::Output;
    let json = args.json;
    if let (Some(d), Some(node)) = (desc, command_node(&args.command)) {
        if let Some(w) = identity_mismatch(commands, node, d) {
            eprintln!("sdo-tool: warning: {w}");
        }
    }
    match &args.command {
        Cmd::Read { node, object, ty } => {
            if let (Some(d), None) = (desc, ty) {
                if let Some(index) = whole_object(&d.dictionary, object) {
                    return read_object(commands, *node, &d.dictionary, index, json, out);
                }
            }
            let (value, text) = commands.read_typed(*node, object, ty.as_deref())?;
            let addr = commands.object(object)?;
            let read_as = ty
                .as_deref()
                .and_then(crate::TypeCode::parse)
                .map(|c| c.data_type);
            let meaning = Meaning::of(commands.od, addr, &value, read_as);
            let mut v = serde_json::json!({
                "node": node,
                "object": addr.to_string(),
                "value": json_value(&value),
                "text": text,
            });
            meaning.add_to(&mut v);
            emit(out, json, meaning.show(&text), v)?;
        }
        Cmd::Write { node, object, rest } => {
            let (ty, value) = match rest.as_slice() {
                [v] => (None, v.as_str()),
                [t, v] => (Some(t.as_str()), v.as_str()),
                _ => return Err(UsageError::WriteArguments.into()),
            };
            // A type alone is a value left out, unless the entry is a string it could be.
            if let (None, Some(t)) = (ty, crate::TypeCode::parse(value)) {
                let addr = commands.object(object)?;
                let textual = commands
                    .od
                    .and_then(|d| d.entry(addr.index, addr.sub).ok())
                    .is_some_and(|e| {
                        matches!(
                            e.data_type,
                            od::DataType::VisibleString
                                | od::DataType::UnicodeString
                                | od::DataType::OctetString
                                | od::DataType::Domain
                        )
                    });
                if !textual {
                    return Err(UsageError::ValueMissing {
                        address: addr,
                        text: value.to_string(),
                        data_type: t.data_type,
                    }
                    .into());
                }
            }
            commands.write(*node, object, ty, value)?;
            emit(out, json, "OK", serde_json::json!({"ok": true}))?;
        }
        Cmd::Dump { node, output } => {
            let mut d = desc.cloned().ok_or(UsageError::DumpNeedsDescription)?;
            let as_read = d.clone();
            let outcome = commands.dump(*node, &mut d)?;
            od::eds::complete_new_file(&mut d);
            let bytes = dcf_bytes(args.od.as_deref(), as_read, d.clone());
            std::fs::write(output, bytes).map_err(|e| file_error(output, e))?;
            let name = |a: &Address| {
                d.dictionary
                    .entry(a.index, a.sub)
                    .map(|e| format!("{a} ({})", e.name))
                    .unwrap_or_else(|_| a.to_string())
            };
            let not_read: Vec<String> = outcome
                .refused
                .iter()
                .map(|(a, code)| format!("{}: not read, {code}", name(a)))
                .collect();
            let write_only: Vec<String> = outcome
                .skipped
                .iter()
                .filter(|(_, why)| *why == crate::config::Skip::WriteOnly)
                .map(|(a, _)| name(a))
                .collect();
            let not_scanned: Vec<String> = outcome
                .skipped
                .iter()
                .filter(|(_, why)| *why == crate::config::Skip::RefuseReadOnScan)
                .map(|(a, why)| format!("skipped {}: {why}", name(a)))
                .collect();
            let mut counts: std::collections::BTreeMap<&str, usize> = Default::default();
            for (_, why) in &outcome.skipped {
                let kind = match why {
                    crate::config::Skip::Command(_) => "command objects",
                    crate::config::Skip::NotWritable => "not writable",
                    crate::config::Skip::CyclicOutput(_) => "cyclic outputs",
                    crate::config::Skip::Domain => "DOMAINs",
                    crate::config::Skip::WriteOnly => "write-only",
                    crate::config::Skip::RefuseReadOnScan
                    | crate::config::Skip::RefuseWriteOnDownload => "refused by ObjFlags",
                };
                *counts.entry(kind).or_default() += 1;
            }
            let mut text = String::new();
            for l in &not_read {
                text.push_str(l);
                text.push('\n');
            }
            if !write_only.is_empty() {
                text.push_str(&format!(
                    "{} write-only parameters cannot be read back and are not in the file: {}\n",
                    write_only.len(),
                    write_only.join(", ")
                ));
            }
            for l in &not_scanned {
                text.push_str(l);
                text.push('\n');
            }
            let left_out: Vec<String> = counts.iter().map(|(k, n)| format!("{n} {k}")).collect();
            text.push_str(&format!(
                "{} entries written to {}{}",
                outcome.read,
                output.display(),
                if left_out.is_empty() {
                    String::new()
                } else {
                    format!("; left out: {}", left_out.join(", "))
                }
            ));
            emit(
                out,
                json,
                text,
                serde_json::json!({
                    "entries": outcome.read,
                    "file": output.display().to_string(),
                    "not_read": not_read,
                    "write_only": write_only,
                    "not_scanned": not_scanned,
                    "left_out": counts,
                }),
            )?;
        }
        Cmd::Apply {
            node,
            file,
            dry_run,
            stop_on_error,
            save,
        } => {
            let dcf = load_description(file, "apply")?;
            let mut lines = Vec::new();
            let result = commands.apply(*node, &dcf, *dry_run, *stop_on_error, |step| {
                use crate::ApplyStep::*;
                let with =
                    |step: &Option<&str>| step.map(|s| format!(" ({s})")).unwrap_or_default();
                lines.push(match step {
                    WouldWrite { addr, value, step } => {
                        format!("would write {addr} = {value}{}", with(step))
                    }
                    Written { addr, value, step } => {
                        format!("wrote {addr} = {value}{}", with(step))
                    }
                    Differs {
                        addr,
                        value,
                        read_back,
                    } => format!("DIFFERS {addr} = {value}, reads back {read_back}"),
                    Refused { addr, value, error } => format!(
                        "REFUSED {addr} = {value}: {error}{}",
                        if *stop_on_error {
                            "; nothing after it written"
                        } else {
                            ""
                        }
                    ),
                    Skipped { addr, value, why } => format!("skipped {addr} = {value}: {why}"),
                });
            });
            let outcome = match result {
                Ok(o) => o,
                Err(e) => {
                    // The steps up to the failure, then the failure.
                    if json {
                        writeln!(out, "{}", serde_json::json!({ "steps": lines })).map_err(io)?;
                    } else {
                        for l in &lines {
                            writeln!(out, "{l}").map_err(io)?;
                        }
                    }
                    return Err(e);
                }
            };
            // Saved only when everything was written and reads back equal.
            let save_result =
                (*save && !*dry_run && outcome.refused == 0 && outcome.differences == 0).then(
                    || commands.write(*node, "0x1010:01", Some("u32"), &SAVE_SIGNATURE.to_string()),
                );
            let saved = matches!(save_result, Some(Ok(())));
            if json {
                writeln!(
                    out,
                    "{}",
                    serde_json::json!({
                        "steps": lines,
                        "written": if *dry_run { 0 } else { outcome.written },
                        "to_write": if *dry_run { outcome.written } else { 0 },
                        "skipped": outcome.skipped,
                        "refused": outcome.refused,
                        "refused_in_state": outcome.refused_in_state,
                        "differences": outcome.differences,
                        "saved": saved,
                    })
                )
                .map_err(io)?;
            } else {
                for l in &lines {
                    writeln!(out, "{l}").map_err(io)?;
                }
                writeln!(
                    out,
                    "{} entries {}, {} skipped, {} refused",
                    outcome.written,
                    if *dry_run { "to write" } else { "written" },
                    outcome.skipped,
                    outcome.refused
                )
                .map_err(io)?;
                if outcome.refused_in_state > 0 {
                    writeln!(
                        out,
                        "{} refused for the node's present state (0x08000022): configure it in \
                         Pre-Operational (sdo-tool nmt preop {node}) and apply again",
                        outcome.refused_in_state
                    )
                    .map_err(io)?;
                }
                if saved {
                    writeln!(out, "saved: 0x1010:01 = \"save\"").map_err(io)?;
                }
            }
            if let Some(Err(e)) = save_result {
                return Err(e);
            }
            if outcome.refused > 0 {
                return Err(ToolError::Refused(outcome.refused));
            }
            if outcome.differences > 0 {
                return Err(ToolError::Differences(outcome.differences));
            }
        }
        other => {
            return Err(UsageError::NotSdoCommand {
                command: command_name(other),
            }
            .into())
        }
    }
    Ok(())
}

/// A progress bar on standard error (hidden when it is not a terminal).
fn progress_bar(len: Option<u64>) -> indicatif::ProgressBar {
    let bar =
        indicatif::ProgressBar::with_draw_target(len, indicatif::ProgressDrawTarget::stderr());
    if let Ok(style) = indicatif::ProgressStyle::with_template(
        "{bar:40} {bytes}/{total_bytes} {binary_bytes_per_sec} {eta}",
    ) {
        bar.set_style(style);
    }
    bar
}

/// "1048576 bytes in 0.52 s (1969.2 KiB/s)".
fn rate(bytes: u64, took: Duration) -> String {
    let secs = took.as_secs_f64().max(1e-6);
    format!(
        "{bytes} bytes in {secs:.2} s ({:.1} KiB/s)",
        bytes as f64 / 1024.0 / secs
    )
}

/// The gateway's TCP clients, each on its own thread (a silent one holds only its own), sharing
/// the gateway one request at a time; at most [`GATEWAY_CLIENTS`] at once, the next refused with
/// `ERROR:102`.
fn gateway_connections(
    listener: &std::net::TcpListener,
    gw: &std::sync::Arc<std::sync::Mutex<crate::gateway::Gateway>>,
) {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let active = std::sync::Arc::new(AtomicUsize::new(0));
    for stream in listener.incoming() {
        let Ok(mut stream) = stream else { continue };
        if active.load(Ordering::Relaxed) >= GATEWAY_CLIENTS {
            let _ = writeln!(
                stream,
                "ERROR:102 #Request not processed due to internal state (too many clients)"
            );
            continue;
        }
        let Ok(reader) = stream.try_clone() else {
            continue;
        };
        let (gw, mine) = (std::sync::Arc::clone(gw), std::sync::Arc::clone(&active));
        active.fetch_add(1, Ordering::Relaxed);
        let spawned = std::thread::Builder::new()
            .name("gateway-client".into())
            .spawn(move || {
                let mut writer = stream;
                let _ = crate::gateway::serve(&gw, std::io::BufReader::new(reader), &mut writer);
                mine.fetch_sub(1, Ordering::Relaxed);
            });
        if spawned.is_err() {
            // No thread for it: the client's connection is dropped with the closure.
            active.fetch_sub(1, Ordering::Relaxed);
        }
    }
}

/// Gateway clients served at once at most.
pub const GATEWAY_CLIENTS: usize = 16;

/// Writes `text`, or with `--json` the JSON object `value`, as one line.
fn emit(
    out: &mut dyn Write,
    json: bool,
    text: impl std::fmt::Display,
    value: serde_json::Value,
) -> Result<(), ToolError> {
    let r = if json {
        writeln!(out, "{value}")
    } else {
        writeln!(out, "{text}")
    };
    r.map_err(ToolError::Output)
}

/// A file that cannot be looked at, opened, created or written: a usage error naming it.
fn file_error(path: &std::path::Path, error: std::io::Error) -> UsageError {
    UsageError::File {
        path: path.to_path_buf(),
        error,
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

#[cfg(test)]
mod tests {
    use super::Meaning;
    use od::dict::Address;
    use od::object::{AccessType, Object, SubObject};
    use od::{DataType, Dictionary, Value};

    fn dict() -> Dictionary {
        let mut d = Dictionary::new();
        let mut threshold = SubObject::new("Threshold", DataType::Unsigned32, AccessType::Rw);
        threshold.unit = Some(0xFD26_0000);
        d.insert(Object::var(0x8000, threshold));
        d.insert(Object::var(
            0x2000,
            SubObject::new("Flags", DataType::Unsigned8, AccessType::Ro)
                .with_description("Bit 7 Ready; 1 Busy; 0 Error."),
        ));
        d.insert(Object::var(
            0x2001,
            SubObject::new("Signed", DataType::Integer8, AccessType::Ro)
                .with_description("Bit 7 Negative; 0 Odd"),
        ));
        // A VAR whose bit list is the object's description; a RECORD whose object description
        // lists bits that are not its entries'.
        let mut var = Object::var(
            0x2002,
            SubObject::new("Word", DataType::Unsigned16, AccessType::Ro),
        );
        var.description = Some("Bit 9 Nine".into());
        d.insert(var);
        let mut record = Object::structured(0x2003, "Rec", od::ObjectKind::Record).with_sub(
            1,
            SubObject::new("Entry", DataType::Unsigned16, AccessType::Ro),
        );
        record.description = Some("Bit 9 Nine".into());
        d.insert(record);
        d
    }

    /// A unit follows the value; the set bits of a word whose description lists them come in
    /// brackets, lowest first; CiA 402's statusword is known without a description.
    #[test]
    fn values_are_shown_with_their_unit_and_bits() {
        let d = dict();
        let m = Meaning::of(
            Some(&d),
            Address::new(0x8000, 0),
            &Value::Uint(50_000),
            None,
        );
        assert_eq!(m.unit.as_deref(), Some("mV"));
        assert_eq!(m.bits, None);
        assert_eq!(m.show("50000"), "50000 mV");
        let m = Meaning::of(Some(&d), Address::new(0x2000, 0), &Value::Uint(0x83), None);
        assert_eq!(
            m.bits,
            Some(vec!["Error".to_string(), "Busy".into(), "Ready".into()])
        );
        assert_eq!(m.show("131"), "131  [Error Busy Ready]");
        // No bit set: the brackets are empty, so that the word is seen to have named bits.
        let m = Meaning::of(Some(&d), Address::new(0x2000, 0), &Value::Uint(0), None);
        assert_eq!(m.show("0"), "0  []");
        // CiA 402 statusword 0x0637 read as u16 without a description: Operation enabled, Remote,
        // Target reached.
        let m = Meaning::of(
            None,
            Address::new(0x6041, 0),
            &Value::Uint(0x0637),
            Some(DataType::Unsigned16),
        );
        assert_eq!(
            m.bits.unwrap(),
            [
                "Ready_to_switch_on",
                "Switched_on",
                "Operation_enabled",
                "Voltage_enabled",
                "Quick_stop",
                "Remote",
                "Target_reached"
            ]
        );
        // Read as another size, or with no size known, it is not the statusword.
        let m = Meaning::of(
            None,
            Address::new(0x6041, 0),
            &Value::Uint(0x0637),
            Some(DataType::Unsigned32),
        );
        assert_eq!(m, Meaning::default());
        let m = Meaning::of(None, Address::new(0x6041, 0), &Value::Uint(0x0637), None);
        assert_eq!(m, Meaning::default());
        // A signed word: its two's complement bits (-127 is 0x81).
        let m = Meaning::of(Some(&d), Address::new(0x2001, 0), &Value::Int(-127), None);
        assert_eq!(m.bits, Some(vec!["Odd".to_string(), "Negative".into()]));
        // A VAR's object description lists its bits; a RECORD's does not list its entries'.
        let m = Meaning::of(Some(&d), Address::new(0x2002, 0), &Value::Uint(0x200), None);
        assert_eq!(m.bits, Some(vec!["Nine".to_string()]));
        let m = Meaning::of(Some(&d), Address::new(0x2003, 1), &Value::Uint(0x200), None);
        assert_eq!(m.bits, None);
        // A string has no bits.
        let m = Meaning::of(
            Some(&d),
            Address::new(0x2000, 0),
            &Value::String("x".into()),
            None,
        );
        assert_eq!(m.bits, None);
        let mut v = serde_json::json!({});
        Meaning::of(Some(&d), Address::new(0x8000, 0), &Value::Uint(1), None).add_to(&mut v);
        assert_eq!(v, serde_json::json!({"unit": "mV"}));
    }
}

#[cfg(test)]
mod dump_file {
    use super::dcf_bytes;

    /// `dump` writes the description it read with the values read: its comments and the keys the
    /// model does not hold stay, the values come in at their entries, and a DCF's commissioning
    /// section comes in.
    #[test]
    fn a_dump_keeps_the_description_file() {
        let dir = tempfile::tempdir().unwrap();
        let eds = dir.path().join("node.eds");
        std::fs::write(
            &eds,
            "; vendor notes\n[FileInfo]\nFileName=node.eds\nLastEDS=old.eds\n\n[DeviceInfo]\nVendorNumber=0x1\n\n\
             [1017]\nParameterName=Producer heartbeat time\nDataType=0x0006\nAccessType=rw\nDefaultValue=0\nDenotation=beat\n",
        )
        .unwrap();
        let (_, devices) = od::load::load(&eds).unwrap();
        let as_read = devices[0].clone();
        let mut dumped = as_read.clone();
        dumped
            .dictionary
            .store_parameter(0x1017, 0, &750u16.to_le_bytes())
            .unwrap();
        dumped.set_node_id(Some(5));
        let text = String::from_utf8(dcf_bytes(Some(&eds), as_read, dumped)).unwrap();
        assert!(
            text.starts_with("; vendor notes\n[FileInfo]\nFileName=node.eds\nLastEDS=old.eds\n"),
            "{text}"
        );
        assert!(
            text.contains("[1017]\nParameterName=Producer heartbeat time\nDataType=0x0006\nAccessType=rw\nDefaultValue=0\nParameterValue=0x02EE\nDenotation=beat\n"),
            "{text}"
        );
        assert!(text.contains("[DeviceComissioning]\nNodeID=5\n"), "{text}");
    }
}
