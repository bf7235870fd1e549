//! `foe-write` and `foe-read` (with `--ethercat`): a file to or from one slave by FoE, as IgH's
//! `ethercat foe_write` and `foe_read` (also accepted by those names) with this tool's 1-based
//! positions.
//!
//! - `foe-write [-p POS] [-o NAME] [--boot] FILE [PASSWORD]`: FILE (`-`: standard input, then `-o`
//!   is needed) sent as NAME, FILE's name without its folders by default; nothing printed.
//! - `foe-read [-p POS] [-o FILE] [--boot] SOURCEFILE [PASSWORD]`: the slave's SOURCEFILE into FILE,
//!   or to standard output (the default, or `-`); FILE is written only once the whole file came.
//! - POS: the slave's position, 1 = first (IgH counts from 0); needed on a chain of several.
//!   PASSWORD: 0x… or decimal, 0 without it. `--boot` first takes the slave to Bootstrap (where
//!   firmware goes), and the session takes it back to Init at the end.
//! - With `--json` one line `{"position", "file", "bytes", "output"}` (foe-read then needs `-o
//!   FILE`: the file's bytes are not mixed with it).

use std::io::Write;
use std::path::PathBuf;
use std::time::Duration;

use crate::cmd::{file_error, is_dash, read_input};
use crate::ethercat::EthercatSession;
use crate::link::Capture;
use crate::{ToolError, UsageError};

/// A 32-bit password: `0x…` or decimal.
fn password(text: &str) -> Result<u32, String> {
    let t = text.trim();
    let parsed = match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(hex) => u32::from_str_radix(hex, 16),
        None => t.parse(),
    };
    parsed.map_err(|_| format!("{text:?} is no 32-bit password (0x… or decimal)"))
}

/// What `foe-write` and `foe-read` both take after the file: the password, the slave, Bootstrap.
#[derive(Debug, clap::Args)]
pub struct FoeSlave {
    /// The password the slave asks for: 0x… or decimal (0 without it).
    #[arg(value_parser = password)]
    pub password: Option<u32>,
    /// The slave's position, 1 = first (IgH's tool counts from 0); needed on a chain of several.
    #[arg(short = 'p', long, value_name = "POS")]
    pub position: Option<u8>,
    /// Take the slave to Bootstrap first (where firmware goes): Init, SM0/SM1 at the bootstrap
    /// mailbox of its SII, Bootstrap; back to Init at the end.
    #[arg(long)]
    pub boot: bool,
}

/// `foe-write`'s arguments.
#[derive(Debug, clap::Args)]
pub struct FoeWriteArgs {
    /// The file to send; `-` reads standard input (then --output-file names it).
    pub file: PathBuf,
    /// The password, the slave and Bootstrap.
    #[command(flatten)]
    pub slave: FoeSlave,
    /// The file's name on the slave: FILE's name without its folders by default.
    #[arg(short = 'o', long = "output-file", value_name = "NAME")]
    pub output_file: Option<String>,
}

/// `foe-read`'s arguments.
#[derive(Debug, clap::Args)]
pub struct FoeReadArgs {
    /// The file's name on the slave.
    #[arg(value_name = "SOURCEFILE")]
    pub source_file: String,
    /// The password, the slave and Bootstrap.
    #[command(flatten)]
    pub slave: FoeSlave,
    /// Where the file goes: a file, or `-` (the default) for standard output.
    #[arg(short = 'o', long = "output-file", value_name = "FILE")]
    pub output_file: Option<PathBuf>,
}

/// `foe-write` on the chain of `interface`.
pub fn write(
    args: &FoeWriteArgs,
    interface: &str,
    timeout: Duration,
    capture: Option<&Capture>,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let name = match (&args.output_file, is_dash(&args.file)) {
        (Some(n), _) => n.clone(),
        (None, true) => return Err(UsageError::FoeStdinName.into()),
        (None, false) => args
            .file
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
    };
    let data = read_input(&args.file, usize::MAX)?;
    let bytes = data.len();
    let mut session = EthercatSession::open_captured(interface, timeout, capture)?;
    let position = session.single_slave(args.slave.position, "foe-write")?;
    let password = args.slave.password.unwrap_or(0);
    session.foe_write(position, name.as_bytes(), password, data, args.slave.boot)?;
    if json {
        let line = serde_json::json!({"position": position, "file": name, "bytes": bytes});
        writeln!(out, "{line}").map_err(ToolError::Output)?;
    }
    Ok(())
}

/// `foe-read` on the chain of `interface`.
pub fn read(
    args: &FoeReadArgs,
    interface: &str,
    timeout: Duration,
    capture: Option<&Capture>,
    json: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let to_file = args.output_file.as_deref().filter(|p| !is_dash(p));
    if json && to_file.is_none() {
        return Err(UsageError::FoeJsonOutput.into());
    }
    let mut session = EthercatSession::open_captured(interface, timeout, capture)?;
    let position = session.single_slave(args.slave.position, "foe-read")?;
    let password = args.slave.password.unwrap_or(0);
    let name = args.source_file.as_bytes();
    let data = session.foe_read(position, name, password, args.slave.boot)?;
    drop(session);
    match to_file {
        Some(path) => std::fs::write(path, &data).map_err(|e| file_error(path, e))?,
        None => out.write_all(&data).map_err(ToolError::Output)?,
    }
    if json {
        let output = to_file.map(|p| p.display().to_string());
        let line = serde_json::json!({
            "position": position, "file": args.source_file, "bytes": data.len(), "output": output,
        });
        writeln!(out, "{line}").map_err(ToolError::Output)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::password;

    /// Passwords as IgH's tool takes them: 0x… or decimal, 32 bits.
    #[test]
    fn passwords_in_hex_or_decimal() {
        assert_eq!(password("0x1234ABCD"), Ok(0x1234_ABCD));
        assert_eq!(password("0XFF"), Ok(255));
        assert_eq!(password("4294967295"), Ok(u32::MAX));
        assert_eq!(
            password("4294967296"),
            Err("\"4294967296\" is no 32-bit password (0x… or decimal)".to_string())
        );
        assert!(password("abc").is_err());
    }
}
