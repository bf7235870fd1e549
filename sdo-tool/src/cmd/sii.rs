//! The EEPROM commands of IgH's tool: `sii-read` (a slave's SII image, raw or listed by category),
//! `sii-write` (an image into a slave's EEPROM, checked first) and `alias` (the configured station
//! alias in SII word 4, with its checksum, taken into 0x0012 by a reload).

use std::io::Write;
use std::path::PathBuf;
use std::time::Duration;

use crate::ethercat::Chain;
use crate::link::Capture;
use crate::{ToolError, UsageError};

/// The largest image `sii-write` takes: an EEPROM of 4 Mbit, the most an ESC addresses.
pub const MAX_IMAGE: usize = 512 * 1024;

/// `sii-read`'s arguments.
#[derive(Debug, clap::Args)]
pub struct SiiReadArgs {
    /// The slave's position (1 = first); may be left out on a chain of one slave.
    pub position: Option<u16>,
    /// Write the image into FILE (raw bytes).
    #[arg(long, short, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// List the image as IgH's `ethercat sii_read --verbose` does: the 64 header words, then each
    /// category with its type, name and length, in hex.
    #[arg(long, short)]
    pub verbose: bool,
}

/// `sii-write`'s arguments.
#[derive(Debug, clap::Args)]
pub struct SiiWriteArgs {
    /// `[POS] FILE`: the slave's position (left out on a chain of one slave) and the image (`-`:
    /// standard input).
    #[arg(value_name = "[POS] FILE", num_args = 1..=2, required = true)]
    pub words: Vec<String>,
    /// Write an image IgH's checks refuse (too short, bad checksum, categories that do not end).
    #[arg(long, short)]
    pub force: bool,
}

/// `alias`' arguments.
#[derive(Debug, clap::Args)]
pub struct AliasArgs {
    /// `[POS] ALIAS`: the slave's position (every slave without it) and the alias, 0 to 65535 (0:
    /// none).
    #[arg(value_name = "[POS] ALIAS", num_args = 1..=2, required = true)]
    pub words: Vec<String>,
    /// Write the alias of every slave of a chain of several.
    #[arg(long, short)]
    pub force: bool,
}

/// A slave position given in words: decimal.
fn position(text: &str) -> Result<u16, ToolError> {
    text.parse().map_err(|_| {
        UsageError::Number {
            what: "slave position",
            text: text.to_string(),
        }
        .into()
    })
}

/// `[POS] WORD` (clap takes one or two words): the position, where given, and the word.
fn position_and(words: &[String]) -> Result<(Option<u16>, &str), ToolError> {
    match words {
        [p, word] => Ok((Some(position(p)?), word)),
        [word] => Ok((None, word)),
        _ => unreachable!("clap takes one or two"),
    }
}

/// The slave a one-slave command works on: `given`, or the only slave of the chain.
pub fn one_slave(
    chain: &Chain,
    given: Option<u16>,
    command: &'static str,
) -> Result<u16, ToolError> {
    let position = match given {
        Some(p) => p,
        None if chain.count() == 1 => 1,
        None => {
            return Err(UsageError::OneSlave {
                command,
                how: "POS",
                interface: chain.interface().to_string(),
                count: chain.count(),
            }
            .into())
        }
    };
    chain.check_position(position)?;
    Ok(position)
}

/// `sii-read`: the slave's image as raw bytes into `-o FILE` or onto standard output when it is no
/// terminal; listed by category with `--verbose` (and on a terminal); with `--json` one object with
/// the image in hex.
pub fn sii_read(
    interface: &str,
    args: &SiiReadArgs,
    ctx: super::Context<'_>,
    timeout: Duration,
    capture: Option<&Capture>,
    terminal: bool,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let io = ToolError::Output;
    let mut chain = Chain::open(interface, timeout, capture)?;
    let p = one_slave(&chain, args.position, "sii-read")?;
    let read = chain.sii(p)?;
    if read.cut {
        eprintln!(
            "sdo-tool: warning: slave {p}: the SII's categories do not end within {} words: its \
             64 header words only, as IgH's master reads it",
            od::sii::MAX_WORDS
        );
    }
    if let Some(path) = &args.output {
        std::fs::write(path, &read.bytes).map_err(|e| super::file_error(path, e))?;
    }
    if ctx.json {
        let hex: String = read.bytes.iter().map(|b| format!("{b:02x}")).collect();
        let v = serde_json::json!({"position": p, "words": read.bytes.len() / 2, "sii": hex});
        return writeln!(out, "{v}").map_err(io);
    }
    if args.verbose || (terminal && args.output.is_none()) {
        return write!(out, "{}", crate::igh::sii_listing(&read.bytes)).map_err(io);
    }
    if args.output.is_none() {
        out.write_all(&read.bytes).map_err(io)?;
    }
    Ok(())
}

/// `sii-write`: `FILE` into the slave's EEPROM, word by word, after IgH's checks (`--force` passes
/// over them) and a check that it fits the EEPROM the slave's SII says it has (word 0x3E); nothing is
/// written when a check fails.
pub fn sii_write(
    interface: &str,
    args: &SiiWriteArgs,
    ctx: super::Context<'_>,
    timeout: Duration,
    capture: Option<&Capture>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let (given, file) = position_and(&args.words)?;
    let file = PathBuf::from(file);
    let bytes = super::read_input(&file, MAX_IMAGE)?;
    if bytes.len() > MAX_IMAGE {
        return Err(UsageError::SiiTooLong {
            path: file,
            limit: MAX_IMAGE,
        }
        .into());
    }
    if bytes.is_empty() || bytes.len() % 2 == 1 {
        // Not even --force writes half a word.
        let error = od::sii::ImageError::Size { bytes: bytes.len() };
        return Err(UsageError::SiiImage { path: file, error }.into());
    }
    if !args.force {
        od::sii::check_image(&bytes).map_err(|error| UsageError::SiiImage {
            path: file.clone(),
            error,
        })?;
    }
    let mut chain = Chain::open(interface, timeout, capture)?;
    let p = one_slave(&chain, given, "sii-write")?;
    if let Some(capacity) = chain.eeprom_size(p)? {
        if bytes.len() > capacity {
            return Err(UsageError::SiiTooLarge {
                path: file,
                bytes: bytes.len(),
                position: p,
                capacity,
            }
            .into());
        }
    }
    chain.write_sii(p, &bytes)?;
    if ctx.json {
        let v = serde_json::json!({"position": p, "words": bytes.len() / 2});
        writeln!(out, "{v}").map_err(ToolError::Output)?;
    }
    Ok(())
}

/// `alias`: the alias into SII word 4 of the slave at POS (every slave without it; `--force` on a
/// chain of several), the checksum of words 0–6 made again, words 0–7 written as IgH's tool writes
/// them; then the EEPROM reloaded, so that the ESC's alias register 0x0012 holds it at once, and
/// read back.
pub fn alias(
    interface: &str,
    args: &AliasArgs,
    ctx: super::Context<'_>,
    timeout: Duration,
    capture: Option<&Capture>,
    out: &mut dyn Write,
) -> Result<(), ToolError> {
    let (given, text) = position_and(&args.words)?;
    let alias = crate::igh::parse_number(text)
        .and_then(|a| u16::try_from(a).ok())
        .ok_or_else(|| UsageError::Alias {
            text: text.to_string(),
        })?;
    let mut chain = Chain::open(interface, timeout, capture)?;
    let positions: Vec<u16> = match given {
        Some(p) => {
            chain.check_position(p)?;
            vec![p]
        }
        None if chain.count() > 1 && !args.force => {
            return Err(UsageError::AliasForce {
                alias,
                count: chain.count(),
            }
            .into())
        }
        None => (1..=chain.count()).collect(),
    };
    for p in positions {
        let mut head = chain.sii_words(p, 0, 8)?;
        od::sii::set_alias(&mut head, alias);
        chain.write_sii(p, &head)?;
        chain.reload_sii(p)?;
        let now = chain.read(p, 0x0012, 2)?;
        let now = u16::from_le_bytes([now[0], now[1]]);
        if now != alias {
            eprintln!(
                "sdo-tool: warning: slave {p}: SII word 4 holds alias {alias}, the alias register \
                 0x0012 still {now} after the reload: the ESC takes it at its next power-up"
            );
        }
        if ctx.json {
            let v = serde_json::json!({"position": p, "alias": alias, "register": now});
            writeln!(out, "{v}").map_err(ToolError::Output)?;
        }
    }
    Ok(())
}
