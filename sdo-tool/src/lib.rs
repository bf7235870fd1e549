//! The commissioning tool's logic (`sdo-tool`): SDO reads and writes with the CiA 309-3 type notation,
//! object names from a device description, NMT commands — over any [`CanBus`], and the SDO commands
//! also over EtherCAT (CoE, [`ethercat`]).
//!
//! - [`TypeCode`]: the CiA 309-3 data-type mnemonics (`b`, `i8`…`i64`, `u8`…`u64`, `x8`…`x64`,
//!   `r32`, `r64`, `vs`, `os`, `us`, `d`, `hex`) as CANopenNode's `cocomm` writes them;
//! - [`BusTransport`]: one node's SDO channel (0x600 + node out, 0x580 + node in) on a bus;
//! - [`SdoAccess`]: the raw SDO transfers (the bytes of one entry of one node) the commands are made
//!   of, done by [`CanSdo`] on a CAN bus and by [`ethercat::EthercatSession`] through EtherCAT
//!   mailboxes; [`SdoCommands`]: `read`, `write`, `dump` and `apply` on either;
//! - [`Tool`]: the bus, an optional dictionary, the SDO client settings, and the commands.
//!
//! Values are written in decimal, `0x` hex or, for strings, as the text itself (CiA 309-3 allows
//! quotes: `"X67 node"`); `os`/`hex`/`d` take hex bytes (`01 02 0A` or `01020A`). With a dictionary the
//! type may be left out, and a value that the dictionary refuses (type, length, limits, access) is
//! refused before anything is sent.
//!
//! The command line is [`cli`] (the global options, the parser and the dispatch) and [`cmd`] (a
//! module per command family, each with its arguments and what it does); [`UsageError`] names what
//! is wrong in a command's words; [`watch`] puts the bus's frames into words for `watch` and
//! `decode`; [`link`] is where the tool takes what it needs from the CAN and EtherCAT crates.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

mod can;
pub mod cli;
pub mod cmd;
pub mod config;
pub mod ethercat;
pub mod gateway;
pub mod igh;
pub mod link;
pub mod raw;
pub mod show;
pub mod usage;

use can::Transfer;
pub use can::{BlockMode, BusTransport, CanSdo, BLOCK_FROM};
pub use usage::UsageError;
pub mod watch;

use od::abort::AbortCode;
use od::dict::{Address, Dictionary};
use od::sdo::client::ClientConfig;
use od::sdo::frame::ClientFrame;
use od::sdo::session::{SdoSession, SessionError};
use od::types::DataType;
use od::value::Value;

use crate::link::{BusError, BusEvent, CanBus, CanFrame};

/// A CiA 309-3 data-type mnemonic.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TypeCode {
    /// The CANopen type.
    pub data_type: DataType,
    /// Shown in hex (`x8`…`x64`, `hex`).
    pub hex: bool,
}

impl TypeCode {
    /// Parses `u16`, `x32`, `vs`, … (case-insensitive).
    pub fn parse(text: &str) -> Option<TypeCode> {
        use DataType::*;
        let t = text.trim().to_ascii_lowercase();
        let plain = |data_type| {
            Some(TypeCode {
                data_type,
                hex: false,
            })
        };
        let hex = |data_type| {
            Some(TypeCode {
                data_type,
                hex: true,
            })
        };
        match t.as_str() {
            "b" => plain(Boolean),
            "i8" => plain(Integer8),
            "i16" => plain(Integer16),
            "i24" => plain(Integer24),
            "i32" => plain(Integer32),
            "i40" => plain(Integer40),
            "i48" => plain(Integer48),
            "i56" => plain(Integer56),
            "i64" => plain(Integer64),
            "u8" => plain(Unsigned8),
            "u16" => plain(Unsigned16),
            "u24" => plain(Unsigned24),
            "u32" => plain(Unsigned32),
            "u40" => plain(Unsigned40),
            "u48" => plain(Unsigned48),
            "u56" => plain(Unsigned56),
            "u64" => plain(Unsigned64),
            "x8" => hex(Unsigned8),
            "x16" => hex(Unsigned16),
            "x24" => hex(Unsigned24),
            "x32" => hex(Unsigned32),
            "x40" => hex(Unsigned40),
            "x48" => hex(Unsigned48),
            "x56" => hex(Unsigned56),
            "x64" => hex(Unsigned64),
            "r32" => plain(Real32),
            "r64" => plain(Real64),
            "vs" => plain(VisibleString),
            "os" => plain(OctetString),
            "us" => plain(UnicodeString),
            "d" => plain(Domain),
            "hex" => hex(OctetString),
            _ => None,
        }
    }

    /// The type of a dictionary entry, as the tool shows it.
    pub fn of(data_type: DataType) -> TypeCode {
        TypeCode {
            data_type,
            hex: false,
        }
    }

    /// Parses a value written on the command line.
    pub fn parse_value(&self, text: &str) -> Result<Value, String> {
        let t = text.trim();
        let t = if matches!(
            self.data_type,
            DataType::VisibleString | DataType::UnicodeString
        ) {
            t.strip_prefix('"')
                .and_then(|s| s.strip_suffix('"'))
                .unwrap_or(t)
        } else {
            t
        };
        if matches!(self.data_type, DataType::OctetString | DataType::Domain) {
            return od::value::parse_hex_bytes(t)
                .map(Value::Bytes)
                .ok_or_else(|| format!("{text:?} is not hex bytes (e.g. 01 02 0A)"));
        }
        // The error names the value and the type (and an integer type's range).
        Value::parse_text(self.data_type, t).map_err(|e| e.to_string())
    }

    /// Formats a value read from a node.
    pub fn format(&self, v: &Value) -> String {
        match v {
            Value::Uint(u) if self.hex => {
                let digits = self.data_type.byte_size().unwrap_or(8) * 2;
                format!("0x{u:0digits$X}")
            }
            Value::Bytes(b) => b
                .iter()
                .map(|x| format!("{x:02X}"))
                .collect::<Vec<_>>()
                .join(" "),
            Value::String(s) => format!("\"{s}\""),
            Value::Uint(u) => u.to_string(),
            Value::Int(i) => i.to_string(),
            Value::Bool(b) => u8::from(*b).to_string(),
            Value::Real32(r) => r.to_string(),
            Value::Real64(r) => r.to_string(),
            other => other.to_text(self.data_type),
        }
    }
}

/// Why a command failed; [`ToolError::exit_code`] is the process's exit code.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ToolError {
    /// The node (or the tool) aborted the transfer.
    #[error("0x{index:04X}:{sub:02X}: SDO abort {code}")]
    Abort {
        /// Index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// The abort code with its meaning.
        code: AbortCode,
    },
    /// The node did not answer in time.
    #[error("0x{index:04X}:{sub:02X}: no answer from node {node} within {ms} ms")]
    Timeout {
        /// Index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// Node-ID.
        node: u8,
        /// The timeout.
        ms: u128,
    },
    /// An LSS service failed: a refusal or no answer.
    #[error("LSS {0}")]
    Lss(#[from] canopen_net::lss::LssError),
    /// `lss set-id --fastscan`: no node without a node-ID answered.
    #[error("LSS Fastscan: no node without a node-ID answered")]
    LssNotFound,
    /// The bus failed.
    #[error(transparent)]
    Bus(#[from] BusError),
    /// The command's words are wrong (object, type, value, node, a file, an option); boxed, as
    /// the largest of the errors.
    #[error(transparent)]
    Usage(Box<UsageError>),
    /// Anything else of the SDO layer (a client refusal, the data source or sink).
    #[error(transparent)]
    Session(SessionError<BusError>),
    /// The bytes read are no value of the type asked for.
    #[error(transparent)]
    Value(#[from] od::value::ValueError),
    /// The output (standard output or a file) could not be written.
    #[error("cannot write the output: {0}")]
    Output(#[source] std::io::Error),
    /// `apply`: entries read back differently from what was written.
    #[error("{0} entries read back differently from what was written")]
    Differences(usize),
    /// `apply`: writes the node refused (for their value or its state); the others were written.
    #[error("{0} writes refused")]
    Refused(usize),
    /// The EtherCAT network failed (the interface, the slaves' initialisation, a frame).
    #[error("EtherCAT: {0}")]
    Ethercat(#[from] ethercat::EthercatError),
    /// `drive`: the drive did not do what it was told within the bound; where it stayed, and why
    /// when it says.
    #[error("{0}")]
    Drive(String),
    /// `net boot`/`net watch`: nodes that did not boot (or were lost) by the end.
    #[error("{}", not_booted(mandatory, optional))]
    NotBooted {
        /// Mandatory nodes not up: the network is not up.
        mandatory: Vec<u8>,
        /// Optional nodes not up.
        optional: Vec<u8>,
    },
    /// An FoE transfer failed: the slave's Error frame (exit 1), or no answer, a mailbox error, a
    /// wrong answer (exit 3).
    #[error("slave {position}: FoE {op} of \"{file}\" {source}{hint}")]
    Foe {
        /// The slave's position.
        position: u8,
        /// `write` or `read`.
        op: &'static str,
        /// The file's name on the slave, printable.
        file: String,
        /// Why.
        source: ethercat::FoeFailure,
        /// What to do about it, where the tool knows (`; … --boot`).
        hint: &'static str,
    },
    /// Ctrl-C during a transfer: the abort 0x08000000 was sent to the node; an upload's partial file
    /// was removed.
    #[error("interrupted: the transfer was aborted with 0x08000000{}", removed.as_ref().map(|p| format!("; the partial {} was removed", p.display())).unwrap_or_default())]
    Interrupted {
        /// The partial file removed, for an upload.
        removed: Option<std::path::PathBuf>,
    },
}

/// The words of [`ToolError::NotBooted`].
fn not_booted(mandatory: &[u8], optional: &[u8]) -> String {
    let list = |v: &[u8]| v.iter().map(u8::to_string).collect::<Vec<_>>().join(", ");
    match (mandatory.is_empty(), optional.is_empty()) {
        (false, true) => format!(
            "mandatory node {} not booted: the network is not up",
            list(mandatory)
        ),
        (false, false) => format!(
            "mandatory node {} and optional node {} not booted: the network is not up",
            list(mandatory),
            list(optional)
        ),
        _ => format!("optional node {} not booted", list(optional)),
    }
}

/// The exit code when standard output is a pipe whose reader is gone (`sdo-tool … | head`): 141,
/// 128 + SIGPIPE, what a shell reports for IgH's `ethercat` and CANopenNode's `cocomm`, which
/// SIGPIPE ends there. The tool ends quietly, without a message.
pub const BROKEN_PIPE_EXIT: i32 = 141;

impl From<UsageError> for ToolError {
    fn from(e: UsageError) -> ToolError {
        ToolError::Usage(Box::new(e))
    }
}

impl ToolError {
    /// Whether the output could not be written because its reader is gone (EPIPE).
    pub fn broken_pipe(&self) -> bool {
        matches!(self, ToolError::Output(e) if e.kind() == std::io::ErrorKind::BrokenPipe)
    }

    /// 1 SDO abort or FoE error, 2 usage, 3 timeout or transport failure, 4 verification difference, 6 and 7 an
    /// optional or a mandatory node not booted, 130 interrupted (Ctrl-C, as a shell reports
    /// SIGINT), 141 the output's reader gone ([`BROKEN_PIPE_EXIT`]).
    pub fn exit_code(&self) -> i32 {
        if self.broken_pipe() {
            return BROKEN_PIPE_EXIT;
        }
        match self {
            ToolError::Abort { .. } | ToolError::Refused(_) | ToolError::Drive(_) => 1,
            ToolError::Lss(canopen_net::lss::LssError::Refused { .. }) => 1,
            ToolError::Lss(canopen_net::lss::LssError::NodeId { .. }) => 2,
            ToolError::Lss(_) | ToolError::LssNotFound => 3,
            ToolError::Usage(_) => 2,
            ToolError::Timeout { .. } | ToolError::Bus(_) | ToolError::Ethercat(_) => 3,
            ToolError::Session(_) | ToolError::Value(_) | ToolError::Output(_) => 3,
            ToolError::Foe { source, .. } if source.refused().is_some() => 1,
            ToolError::Foe { .. } => 3,
            ToolError::Differences(_) => 4,
            ToolError::Interrupted { .. } => 130,
            ToolError::NotBooted { mandatory, .. } if !mandatory.is_empty() => 7,
            ToolError::NotBooted { .. } => 6,
        }
    }
}

/// One node found by [`Tool::scan`]; each field as read, or `None` when the node did not give it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScanEntry {
    /// Node-ID.
    pub node: u8,
    /// 0x1000.
    pub device_type: Option<String>,
    /// 0x1018:01.
    pub vendor: Option<String>,
    /// 0x1018:02.
    pub product: Option<String>,
    /// 0x1018:03.
    pub revision: Option<String>,
    /// 0x1018:04.
    pub serial: Option<String>,
    /// 0x1008.
    pub name: Option<String>,
}

/// One step of [`SdoCommands::apply`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ApplyStep {
    /// `--dry-run`: would be written (`step`: a step of a procedure, not a value of the file).
    WouldWrite {
        /// The entry.
        addr: Address,
        /// The value.
        value: String,
        /// The procedure's step this write is, if it is one.
        step: Option<&'static str>,
    },
    /// Written and read back equal (or not readable; a procedure's step is not read back).
    Written {
        /// The entry.
        addr: Address,
        /// The value.
        value: String,
        /// The procedure's step this write is, if it is one.
        step: Option<&'static str>,
    },
    /// Written, but the node reads back something else.
    Differs {
        /// The entry.
        addr: Address,
        /// The value written.
        value: String,
        /// What the node reads back.
        read_back: String,
    },
    /// The node refused the write of this value (a range, a state): counted, the others go on
    /// unless `--stop-on-error`.
    Refused {
        /// The entry.
        addr: Address,
        /// The value.
        value: String,
        /// Why.
        error: String,
    },
    /// Not written: the file sets a command object, an entry the description makes read-only or one
    /// it flags "refuse write on download" (CiA 306 `ObjFlags` bit 0), or the node refuses the entry
    /// as such (its access, its existence), a warning.
    Skipped {
        /// The entry.
        addr: Address,
        /// The value.
        value: String,
        /// Why.
        why: String,
    },
}

/// What [`SdoCommands::apply`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ApplyOutcome {
    /// Entries written (or, with `--dry-run`, to be written), the procedures' steps not counted.
    pub written: usize,
    /// Entries that read back differently.
    pub differences: usize,
    /// Writes the node refused for their value or its state.
    pub refused: usize,
    /// Entries skipped with a warning.
    pub skipped: usize,
    /// Of the refused writes, those refused for the node's present state (0x08000022).
    pub refused_in_state: usize,
}

/// What [`SdoCommands::dump`] did.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct DumpOutcome {
    /// Entries read into the file.
    pub read: usize,
    /// Entries the node refused to give, with its abort.
    pub refused: Vec<(Address, AbortCode)>,
    /// Entries of the description left out, with the reason ([`config::Skip`]).
    pub skipped: Vec<(Address, config::Skip)>,
    /// Write-only entries read through their read-back register ([`config::read_backs`]), each
    /// with that register; their values are in the file as the entries'.
    pub read_back: Vec<(Address, Address)>,
}

/// NMT commands (CiA 301 §7.2.8.3.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NmtCommand {
    /// 0x01 Start remote node.
    Start,
    /// 0x02 Stop remote node.
    Stop,
    /// 0x80 Enter Pre-operational.
    PreOp,
    /// 0x81 Reset node.
    Reset,
    /// 0x82 Reset communication.
    ResetComm,
}

impl NmtCommand {
    /// The command specifier.
    pub const fn cs(self) -> u8 {
        match self {
            NmtCommand::Start => 0x01,
            NmtCommand::Stop => 0x02,
            NmtCommand::PreOp => 0x80,
            NmtCommand::Reset => 0x81,
            NmtCommand::ResetComm => 0x82,
        }
    }

    /// `start`, `stop`, `preop`, `reset`, `reset-comm`.
    pub fn parse(text: &str) -> Option<NmtCommand> {
        Some(match text {
            "start" => NmtCommand::Start,
            "stop" => NmtCommand::Stop,
            "preop" | "pre-operational" => NmtCommand::PreOp,
            "reset" | "reset-node" => NmtCommand::Reset,
            "reset-comm" | "reset-communication" => NmtCommand::ResetComm,
            _ => return None,
        })
    }
}

/// The SDO transfers the commands are made of, on one network: the bytes of one entry of one node.
///
/// [`CanSdo`] does them with the SDO client on a CAN bus (NODE is the node-ID),
/// [`ethercat::EthercatSession`] with CoE through the slaves' mailboxes (NODE is the slave's position
/// in the chain). [`SdoCommands`] builds `read`, `write`, `dump` and `apply` on either.
pub trait SdoAccess {
    /// Whether `node` names a node of this network; a usage error says why not.
    fn check_node(&self, node: u8) -> Result<(), ToolError>;

    /// Reads the entry's bytes.
    fn read_bytes(&mut self, node: u8, addr: Address) -> Result<Vec<u8>, ToolError>;

    /// Writes `data` to the entry.
    fn write_bytes(&mut self, node: u8, addr: Address, data: &[u8]) -> Result<(), ToolError>;

    /// The entry's type as the node itself describes it (EtherCAT's SDO Information), for a command
    /// given neither a type nor a description; `None` where the network or node has no such
    /// service.
    fn entry_type(&mut self, _node: u8, _addr: Address) -> Result<Option<DataType>, ToolError> {
        Ok(None)
    }

    /// Lets `d` pass: a network whose devices need the master's cycles meanwhile (an EtherCAT
    /// chain in Op) keeps them going.
    fn idle(&mut self, d: Duration) -> Result<(), ToolError> {
        std::thread::sleep(d);
        Ok(())
    }

    /// Reads a value of `data_type`: the bytes must be a valid value of the type.
    fn read_value(
        &mut self,
        node: u8,
        addr: Address,
        data_type: DataType,
    ) -> Result<Value, ToolError> {
        let bytes = self.read_bytes(node, addr)?;
        Ok(Value::decode(data_type, &bytes)?)
    }
}

/// OBJECT as `0x1018:01`, `1018sub1`, `0x1000` or a name from `od`.
pub fn object(od: Option<&Dictionary>, text: &str) -> Result<Address, ToolError> {
    if let Some(a) = Address::parse(text.trim()) {
        return Ok(a);
    }
    match od {
        Some(od) => od.lookup(text).map_err(|error| {
            UsageError::UnknownName {
                text: text.to_string(),
                error,
            }
            .into()
        }),
        None => Err(UsageError::NameWithoutDescription {
            text: text.to_string(),
        }
        .into()),
    }
}

/// An entry's limits as text: `0 to 167`, `at least 1`, `at most 100`; `None` without limits.
pub fn limits_text(e: &od::SubObject) -> Option<String> {
    match (&e.low, &e.high) {
        (Some(lo), Some(hi)) => Some(format!("{lo} to {hi}")),
        (Some(lo), None) => Some(format!("at least {lo}")),
        (None, Some(hi)) => Some(format!("at most {hi}")),
        (None, None) => None,
    }
}

/// The commands that are SDO transfers and nothing else — `read`, `write`, `dump`, `apply` — on any
/// [`SdoAccess`], with an optional dictionary for names, types and limits.
pub struct SdoCommands<'a> {
    /// The network's SDO access.
    pub sdo: &'a mut dyn SdoAccess,
    /// Names, types and limits.
    pub od: Option<&'a Dictionary>,
}

impl<'a> SdoCommands<'a> {
    /// The commands on `sdo`, with `od`.
    pub fn new(sdo: &'a mut dyn SdoAccess, od: Option<&'a Dictionary>) -> SdoCommands<'a> {
        SdoCommands { sdo, od }
    }

    /// OBJECT as `0x1018:01`, `1018sub1`, `0x1000` or a name from the dictionary.
    pub fn object(&self, text: &str) -> Result<Address, ToolError> {
        object(self.od, text)
    }

    /// The type to use: the one given, else the dictionary's, else the one the node describes
    /// (SDO Information).
    fn type_for(
        &mut self,
        node: u8,
        addr: Address,
        given: Option<&str>,
    ) -> Result<TypeCode, ToolError> {
        if let Some(t) = given {
            return TypeCode::parse(t).ok_or_else(|| {
                UsageError::UnknownType {
                    text: t.to_string(),
                }
                .into()
            });
        }
        let Some(od) = self.od else {
            return match self.sdo.entry_type(node, addr)? {
                Some(t) => Ok(show::code_for(None, addr, t)),
                None => Err(UsageError::TypeNeeded.into()),
            };
        };
        let e = od
            .entry(addr.index, addr.sub)
            .map_err(|error| UsageError::NotInDescription {
                address: addr,
                error,
            })?;
        Ok(show::code_for(Some(od), addr, e.data_type))
    }

    /// With a dictionary: `addr`'s access refuses `what` (`"read"` or `"written"`) — a write-only
    /// entry is not read, a read-only one not written — before anything is sent.
    fn check_access(&self, addr: Address, write: bool) -> Result<(), ToolError> {
        let Some(e) = self.od.and_then(|od| od.entry(addr.index, addr.sub).ok()) else {
            return Ok(());
        };
        let kind = e.access.kind;
        let refused = if write {
            !kind.writable()
        } else {
            !kind.readable()
        };
        if refused {
            return Err(UsageError::Access {
                address: addr,
                name: e.name.clone(),
                access: kind.as_str(),
                write,
            }
            .into());
        }
        Ok(())
    }

    /// `read NODE OBJECT [TYPE]`: the value as text.
    pub fn read(&mut self, node: u8, object: &str, ty: Option<&str>) -> Result<String, ToolError> {
        self.read_typed(node, object, ty).map(|(_, text)| text)
    }

    /// `read NODE OBJECT [TYPE]`: the value, and as text.
    pub fn read_typed(
        &mut self,
        node: u8,
        object: &str,
        ty: Option<&str>,
    ) -> Result<(Value, String), ToolError> {
        self.sdo.check_node(node)?;
        let addr = self.object(object)?;
        let code = self.type_for(node, addr, ty)?;
        self.check_access(addr, false)?;
        let v = match self.sdo.read_value(node, addr, code.data_type) {
            Ok(v) => v,
            // The bytes came; the type asked for does not fit them: the user's type is wrong.
            Err(ToolError::Value(error) | ToolError::Session(SessionError::Value(error))) => {
                return Err(UsageError::OtherType {
                    address: addr,
                    error,
                }
                .into())
            }
            Err(e) => return Err(e),
        };
        let text = code.format(&v);
        // A type from the description (or the node): a mapping says what it maps.
        let text = match ty {
            None => show::with_mapping(addr, &v, text),
            Some(_) => text,
        };
        Ok((v, text))
    }

    /// `write NODE OBJECT [TYPE] VALUE`.
    pub fn write(
        &mut self,
        node: u8,
        object: &str,
        ty: Option<&str>,
        value: &str,
    ) -> Result<(), ToolError> {
        self.sdo.check_node(node)?;
        let addr = self.object(object)?;
        let code = self.type_for(node, addr, ty)?;
        // Every refusal of the value is `ADDR: why (not sent)`.
        let refused = |why: String| UsageError::ValueRefused { address: addr, why };
        let v = code.parse_value(value).map_err(refused)?;
        let bytes = v
            .encode(code.data_type)
            .map_err(|e| refused(format!("{value:?}: {e}")))?;
        self.check_access(addr, true)?;
        if let Some(od) = self.od {
            // Refused before anything is sent: what the dictionary refuses, the node would too.
            if let Err(e) = od.check(addr.index, addr.sub, &bytes) {
                let why = match &e {
                    od::OdError::TooHigh { value, .. } | od::OdError::TooLow { value, .. } => {
                        let limits = od
                            .entry(addr.index, addr.sub)
                            .ok()
                            .and_then(limits_text)
                            .unwrap_or_default();
                        let which = if matches!(e, od::OdError::TooHigh { .. }) {
                            "above"
                        } else {
                            "below"
                        };
                        format!("{value} is {which} the description's limits, {limits}")
                    }
                    other => other.to_string(),
                };
                return Err(refused(why).into());
            }
        }
        self.sdo.write_bytes(node, addr, &bytes)
    }

    /// The raw bytes of `addr` on `node`.
    pub fn read_raw(&mut self, node: u8, addr: Address) -> Result<Vec<u8>, ToolError> {
        self.sdo.read_bytes(node, addr)
    }

    /// `dump`: the node's parameters (see [`config`]) read from `node` into `desc`'s dictionary,
    /// marked as set so that a DCF carries them; the entries left out, with the reason. An entry
    /// `desc` flags "refuse read on scan" (CiA 306 `ObjFlags` bit 1) is not read at all.
    pub fn dump(
        &mut self,
        node: u8,
        desc: &mut od::DeviceDescription,
    ) -> Result<DumpOutcome, ToolError> {
        self.sdo.check_node(node)?;
        let (addrs, skipped) = config::dump_entries(&desc.dictionary);
        let mut values = std::collections::BTreeMap::new();
        let mut refused = Vec::new();
        for a in addrs {
            match self.read_raw(node, a) {
                Ok(bytes) => {
                    values.insert(a, bytes);
                }
                Err(ToolError::Abort { code, .. }) => refused.push((a, code)),
                Err(e) => return Err(e),
            }
        }
        // A write-only entry with a read-back register: the register's value is the entry's.
        let mut read_back = Vec::new();
        let through = config::read_backs(&desc.dictionary);
        let mut left = Vec::with_capacity(skipped.len());
        for (a, why) in skipped {
            match through.get(&a) {
                Some(&r) if why == config::Skip::WriteOnly => match self.read_raw(node, r) {
                    Ok(bytes)
                        if desc
                            .dictionary
                            .store_parameter(a.index, a.sub, &bytes)
                            .is_ok() =>
                    {
                        read_back.push((a, r));
                    }
                    Ok(_) | Err(ToolError::Abort { .. }) => left.push((a, why)),
                    Err(e) => return Err(e),
                },
                _ => left.push((a, why)),
            }
        }
        let mut skipped = left;
        let outputs = config::mapped_outputs(&desc.dictionary, &values);
        let mut read = 0;
        for (a, bytes) in values {
            if let Some(&mapping) = outputs.get(&a) {
                skipped.push((a, config::Skip::CyclicOutput(Some(mapping))));
            } else if desc
                .dictionary
                .store_parameter(a.index, a.sub, &bytes)
                .is_ok()
            {
                read += 1;
            }
        }
        skipped.sort_by_key(|(a, _)| *a);
        // The entries the node did not give keep their defaults, `$NODEID` ones now for this node.
        desc.set_node_id(Some(node));
        Ok(DumpOutcome {
            read: read + read_back.len(),
            refused,
            skipped,
            read_back,
        })
    }

    /// `apply`: writes the values the DCF sets, in the order of [`config::plan`] (each PDO by the
    /// CiA 301 procedure; not the entries it flags "refuse write on download", CiA 306 `ObjFlags`
    /// bit 0), reading each value back. A refusal of the entry itself (read-only,
    /// missing) is skipped with a warning; another refusal is counted and the rest goes on, unless
    /// `stop_on_error`, which stops there with the abort. `dry_run` writes nothing.
    pub fn apply(
        &mut self,
        node: u8,
        dcf: &od::DeviceDescription,
        dry_run: bool,
        stop_on_error: bool,
        mut report: impl FnMut(&ApplyStep),
    ) -> Result<ApplyOutcome, ToolError> {
        self.sdo.check_node(node)?;
        let dict = &dcf.dictionary;
        let (writes, skipped) = config::plan(dict);
        let mut outcome = ApplyOutcome::default();
        for (addr, why) in skipped {
            let bytes = dict
                .entry(addr.index, addr.sub)
                .map(|e| e.value.clone())
                .unwrap_or_default();
            outcome.skipped += 1;
            report(&ApplyStep::Skipped {
                addr,
                value: shown(dict, addr, &bytes),
                why: why.to_string(),
            });
        }
        for w in writes {
            if dry_run {
                if w.step.is_none() {
                    outcome.written += 1;
                }
                report(&ApplyStep::WouldWrite {
                    addr: w.addr,
                    value: shown(dict, w.addr, &w.bytes),
                    step: w.step,
                });
                continue;
            }
            self.apply_write(node, dict, &w, stop_on_error, &mut outcome, &mut report)?;
        }
        Ok(outcome)
    }
}

impl SdoCommands<'_> {
    /// One write of [`SdoCommands::apply`], reported and counted in `outcome`: skipped when the
    /// node refuses the entry as such, refused (an error with `stop_on_error`), or written and read
    /// back.
    fn apply_write(
        &mut self,
        node: u8,
        dict: &Dictionary,
        w: &config::Write,
        stop_on_error: bool,
        outcome: &mut ApplyOutcome,
        report: &mut dyn FnMut(&ApplyStep),
    ) -> Result<(), ToolError> {
        let value = shown(dict, w.addr, &w.bytes);
        match self.sdo.write_bytes(node, w.addr, &w.bytes) {
            Ok(()) => {}
            Err(ToolError::Abort { code, .. })
                if config::refused_by_design(code) && !stop_on_error =>
            {
                outcome.skipped += 1;
                report(&ApplyStep::Skipped {
                    addr: w.addr,
                    value,
                    why: format!("the node refuses it: {code}"),
                });
                return Ok(());
            }
            Err(err @ ToolError::Abort { .. }) => {
                report(&ApplyStep::Refused {
                    addr: w.addr,
                    value,
                    error: err.to_string(),
                });
                if stop_on_error {
                    return Err(err);
                }
                outcome.refused += 1;
                if matches!(err, ToolError::Abort { code, .. } if code.code() == 0x0800_0022) {
                    outcome.refused_in_state += 1;
                }
                return Ok(());
            }
            Err(err) => return Err(err),
        }
        let step = self.read_back(node, dict, w, value, outcome)?;
        report(&step);
        Ok(())
    }

    /// The step of a write done: a procedure's step as it is; a value read back, equal or not (a
    /// write-only entry, which cannot be read back, is written, not verified).
    fn read_back(
        &mut self,
        node: u8,
        dict: &Dictionary,
        w: &config::Write,
        value: String,
        outcome: &mut ApplyOutcome,
    ) -> Result<ApplyStep, ToolError> {
        if w.step.is_none() {
            outcome.written += 1;
        }
        let written = |value| ApplyStep::Written {
            addr: w.addr,
            value,
            step: w.step,
        };
        if w.step.is_some() {
            return Ok(written(value));
        }
        match self.read_raw(node, w.addr) {
            Ok(b) if b == w.bytes => Ok(written(value)),
            Ok(b) => {
                outcome.differences += 1;
                Ok(ApplyStep::Differs {
                    addr: w.addr,
                    value,
                    read_back: shown(dict, w.addr, &b),
                })
            }
            Err(ToolError::Abort { .. }) => Ok(written(value)),
            Err(err) => Err(err),
        }
    }
}

/// `bytes` of `addr` as a value of its type in `dict` (in hex or decimal as [`show`] says, a
/// mapping with what it maps), else as bytes.
fn shown(dict: &Dictionary, addr: Address, bytes: &[u8]) -> String {
    match dict.entry(addr.index, addr.sub) {
        Ok(e) => Value::decode(e.data_type, bytes)
            .map(|v| {
                let text = show::code_for(Some(dict), addr, e.data_type).format(&v);
                show::with_mapping(addr, &v, text)
            })
            .unwrap_or_else(|_| format!("{bytes:02X?}")),
        Err(_) => format!("{bytes:02X?}"),
    }
}

/// The tool: a bus, an optional dictionary and the SDO client settings.
pub struct Tool {
    /// The bus.
    pub bus: Box<dyn CanBus>,
    /// Names, types and limits.
    pub od: Option<Dictionary>,
    /// The SDO client settings (timeout; block transfer as [`Tool::block`] says).
    pub sdo: ClientConfig,
    /// When block transfer is used.
    pub block: BlockMode,
    /// Set (by a Ctrl-C handler) to abort the running transfer with 0x08000000.
    pub cancel: Option<Arc<AtomicBool>>,
}

impl Tool {
    /// A tool on `bus`.
    pub fn new(bus: Box<dyn CanBus>, od: Option<Dictionary>) -> Tool {
        Tool {
            bus,
            od,
            sdo: ClientConfig::default(),
            block: BlockMode::Auto,
            cancel: None,
        }
    }

    /// The SDO client on this tool's bus, with its settings.
    pub fn can_sdo(&mut self) -> CanSdo<'_> {
        CanSdo {
            bus: self.bus.as_mut(),
            config: &self.sdo,
            block: self.block,
            cancel: self.cancel.clone(),
        }
    }

    /// Runs `f` on the SDO commands over this tool's bus.
    pub fn with_commands<R>(&mut self, f: impl FnOnce(&mut SdoCommands<'_>) -> R) -> R {
        let mut can = CanSdo {
            bus: self.bus.as_mut(),
            config: &self.sdo,
            block: self.block,
            cancel: self.cancel.clone(),
        };
        f(&mut SdoCommands::new(&mut can, self.od.as_ref()))
    }

    /// OBJECT as `0x1018:01`, `1018sub1`, `0x1000` or a name from the dictionary.
    pub fn object(&self, text: &str) -> Result<Address, ToolError> {
        object(self.od.as_ref(), text)
    }

    /// `read NODE OBJECT [TYPE]`: the value as text.
    pub fn read(&mut self, node: u8, object: &str, ty: Option<&str>) -> Result<String, ToolError> {
        self.with_commands(|c| c.read(node, object, ty))
    }

    /// `write NODE OBJECT [TYPE] VALUE`.
    pub fn write(
        &mut self,
        node: u8,
        object: &str,
        ty: Option<&str>,
        value: &str,
    ) -> Result<(), ToolError> {
        self.with_commands(|c| c.write(node, object, ty, value))
    }

    /// `nmt COMMAND NODE|all` (node 0 = all).
    pub fn nmt(&mut self, command: NmtCommand, node: u8) -> Result<(), ToolError> {
        if node > 127 {
            return Err(UsageError::NmtNode { node }.into());
        }
        let f = CanFrame::new(0x000, &[command.cs(), node]).expect("two bytes");
        self.bus.send(&f)?;
        Ok(())
    }

    /// `save NODE` (0x1010:01 = "save") or `restore NODE` (0x1011:01 = "load").
    pub fn store(&mut self, node: u8, restore: bool) -> Result<(), ToolError> {
        let (object, signature) = if restore {
            ("0x1011:01", crate::link::LOAD_SIGNATURE)
        } else {
            ("0x1010:01", crate::link::SAVE_SIGNATURE)
        };
        self.write(node, object, Some("u32"), &signature.to_string())
    }

    /// Runs `transfer` through a session on `node`, mapping its errors.
    fn transfer<R>(
        &mut self,
        node: u8,
        addr: Address,
        transfer: Transfer,
        f: impl FnOnce(&mut SdoSession<BusTransport<'_>>) -> Result<R, SessionError<BusError>>,
    ) -> Result<R, ToolError> {
        self.can_sdo().transfer(node, addr, transfer, f)
    }

    /// `upload NODE OBJECT`: the object's bytes into `sink`, reporting progress (bytes so far, size
    /// when announced). Returns the number of bytes. The entry is taken as large, a DOMAIN: in
    /// [`BlockMode::Auto`] a block upload, which the server may answer with a normal upload up to
    /// [`BLOCK_FROM`] bytes.
    pub fn upload(
        &mut self,
        node: u8,
        object: &str,
        sink: &mut impl std::io::Write,
        progress: impl FnMut(u64, Option<u64>),
    ) -> Result<u64, ToolError> {
        let addr = self.object(object)?;
        let mux = Address::new(addr.index, addr.sub);
        let upload = Transfer::Upload { domain: true };
        self.transfer(node, addr, upload, |s| s.upload_to(mux, sink, progress))
    }

    /// `download NODE OBJECT`: `len` bytes from `source` into the object, reporting progress.
    pub fn download(
        &mut self,
        node: u8,
        object: &str,
        source: &mut impl std::io::Read,
        len: u64,
        progress: impl FnMut(u64, Option<u64>),
    ) -> Result<(), ToolError> {
        let addr = self.object(object)?;
        let mux = Address::new(addr.index, addr.sub);
        self.transfer(node, addr, Transfer::Download, |s| {
            s.download_from(mux, source, len, progress)
        })
    }

    /// `scan`: every node that answers an SDO upload of 0x1000 (asked of ids 1–127 at once) or shows
    /// itself by boot-up or heartbeat within `wait`; then its identity and name.
    pub fn scan(&mut self, wait: Duration) -> Result<Vec<ScanEntry>, ToolError> {
        let mut found = std::collections::BTreeSet::new();
        let device_type = ClientFrame::InitiateUpload {
            mux: Address::new(0x1000, 0),
        }
        .emit();
        for id in 1..=127u16 {
            let f = CanFrame::new(0x600 + id, &device_type).expect("8 bytes");
            self.bus.send(&f)?;
        }
        let end = Instant::now() + wait;
        loop {
            let left = end.saturating_duration_since(Instant::now());
            if left.is_zero() {
                break;
            }
            if let Some(BusEvent::Frame { frame, .. }) = self.bus.recv(left)? {
                match frame.cob_id() {
                    Some(c @ 0x581..=0x5FF) if frame.len() == 8 => {
                        found.insert((c - 0x580) as u8);
                    }
                    Some(c @ 0x701..=0x77F) if frame.len() == 1 => {
                        found.insert((c - 0x700) as u8);
                    }
                    _ => {}
                }
            }
        }
        let mut out = Vec::new();
        for node in found {
            let mut read = |o: &str, t: &str| self.read(node, o, Some(t)).ok();
            out.push(ScanEntry {
                node,
                device_type: read("0x1000:00", "x32"),
                vendor: read("0x1018:01", "x32"),
                product: read("0x1018:02", "x32"),
                revision: read("0x1018:03", "x32"),
                serial: read("0x1018:04", "x32"),
                name: read("0x1008:00", "vs"),
            });
        }
        Ok(out)
    }

    /// Sets the SDO timeout.
    pub fn set_timeout(&mut self, t: Duration) {
        self.sdo.timeout = t;
    }
}
