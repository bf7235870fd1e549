//! `reg-read` and `reg-write`: a slave's ESC registers (0x0000–0x0FFF) as IgH's `ethercat
//! reg_read` and `reg_write` show and take them, by position, in any state, whoever runs the chain.
//! The process memory above 0x0FFF is left alone: its SyncManagers guard it, and a read there would
//! take a mailbox from its owner.

use std::io::Write;
use std::path::Path;
use std::time::Duration;

use crate::ethercat::Chain;
use crate::igh::{parse_number, RegType};
use crate::link::Capture;
use crate::{ToolError, UsageError};

/// The registers' end: an ESC's registers are 0x0000–0x0FFF.
pub const REGISTERS: usize = 0x1000;

/// `reg-read`'s arguments.
#[derive(Debug, clap::Args)]
pub struct RegReadArgs {
    /// The slave's position (1 = first).
    pub position: u16,
    /// The register's address, 0x0000 to 0x0FFF (decimal, 0x… hex or 0… octal).
    pub address: String,
    /// The bytes to read; a --type of a fixed size needs none (and overrides it).
    pub size: Option<String>,
    /// How to show the bytes: int8, int16, int32, int64, uint8, uint16, uint32, uint64 (hex and
    /// decimal), string, or raw (hex bytes, the default).
    #[arg(long, short, value_name = "TYPE")]
    pub r#type: Option<String>,
}

/// `reg-write`'s arguments.
#[derive(Debug, clap::Args)]
pub struct RegWriteArgs {
    /// The slave's position (1 = first).
    pub position: u16,
    /// The register's address, 0x0000 to 0x0FFF (decimal, 0x… hex or 0… octal).
    pub address: String,
    /// With --type, the value; without, a file of the bytes to write (`-`: standard input).
    pub data: String,
    /// The value's type: int8, int16, int32, int64, uint8, uint16, uint32, uint64 (written in its
    /// width, little-endian) or string.
    #[arg(long, short, value_name = "TYPE")]
    pub r#type: Option<String>,
}

/// A register address as given: a number within 0x0000–0x0FFF.
fn address(text: &str) -> Result<u16, UsageError> {
    let a = parse_number(text).ok_or_else(|| UsageError::Number {
        what: "address",
        text: text.to_string(),
    })?;
    if !(0..REGISTERS as i128).contains(&a) {
        return Err(UsageError::RegisterAddress { address: a });
    }
    Ok(a as u16)
}

/// `size` bytes from `address` are registers; a usage error says why not.
fn check_range(address: u16, size: usize, what: &'static str) -> Result<(), UsageError> {
    if size == 0 {
        return Err(UsageError::NoBytes { what });
    }
    if usize::from(address) + size > REGISTERS {
        return Err(UsageError::RegisterRange { address, size });
    }
    Ok(())
}

/// What `reg-read` reads: the address, the bytes and how to show them, all checked before the
/// chain is opened.
pub fn read_request(args: &RegReadArgs) -> Result<(u16, usize, RegType), UsageError> {
    let at = address(&args.address)?;
    let reg_type = match &args.r#type {
        Some(t) => RegType::parse(t).ok_or_else(|| UsageError::RegType {
            text: t.clone(),
            write: false,
        })?,
        None => RegType::Raw,
    };
    let size = match (reg_type.size(), &args.size) {
        (Some(n), _) => n,
        (None, Some(text)) => {
            let n = parse_number(text).ok_or_else(|| UsageError::Number {
                what: "size",
                text: text.clone(),
            })?;
            if n < 0 {
                return Err(UsageError::Number {
                    what: "size",
                    text: text.clone(),
                });
            }
            usize::try_from(n).unwrap_or(usize::MAX)
        }
        (None, None) => {
            return Err(UsageError::SizeNeeded {
                type_name: reg_type.name(),
            })
        }
    };
    check_range(at, size, "a read")?;
    Ok((at, size, reg_type))
}

/// `reg-read`: the registers, shown as the type says (IgH's layout), or with `--json` one object
/// with the bytes in hex and, for an integer type, the value.
pub fn reg_read(
    interface: &str,
    args: &RegReadArgs,
    json: bool,
    timeout: Duration,
    capture: Option<&Capture>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let (at, size, reg_type) = read_request(args)?;
    let mut chain = Chain::open(interface, timeout, capture)?;
    let data = chain.read(args.position, at, size)?;
    let r = if json {
        let hex: String = data.iter().map(|b| format!("{b:02x}")).collect();
        let mut v = serde_json::json!({
            "position": args.position,
            "address": at,
            "size": size,
            "data": hex,
        });
        if let Some(value) = reg_type.value(&data) {
            v["value"] = serde_json::Number::from_i128(value).into();
        } else if reg_type == RegType::String {
            v["text"] = String::from_utf8_lossy(&data).into_owned().into();
        }
        writeln!(out, "{v}")
    } else {
        write!(out, "{}", reg_type.format(&data))
    };
    r.map_err(ToolError::Output)
}

/// What `reg-write` writes: the address and the bytes, checked before the chain is opened.
pub fn write_request(args: &RegWriteArgs) -> Result<(u16, Vec<u8>), ToolError> {
    let at = address(&args.address)?;
    let data = match &args.r#type {
        Some(t) => {
            let reg_type = RegType::parse(t)
                .filter(|t| *t != RegType::Raw)
                .ok_or_else(|| UsageError::RegType {
                    text: t.clone(),
                    write: true,
                })?;
            reg_type
                .encode(&args.data)
                .ok_or_else(|| UsageError::RegValue {
                    text: args.data.clone(),
                    type_name: reg_type.name(),
                })?
        }
        None => super::read_input(Path::new(&args.data), REGISTERS)?,
    };
    check_range(at, data.len(), "a write")?;
    Ok((at, data))
}

/// `reg-write`: the bytes into the registers; nothing is printed (IgH's tool prints nothing), with
/// `--json` one object.
pub fn reg_write(
    interface: &str,
    args: &RegWriteArgs,
    json: bool,
    timeout: Duration,
    capture: Option<&Capture>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let (at, data) = write_request(args)?;
    let mut chain = Chain::open(interface, timeout, capture)?;
    chain.write(args.position, at, &data)?;
    if json {
        let v = serde_json::json!({"position": args.position, "address": at, "size": data.len()});
        writeln!(out, "{v}").map_err(ToolError::Output)?;
    }
    Ok(())
}
