//! `esi-gen`: turns any readable device description (ESI, XDD, EDS, DCF) into any other, checks a
//! description, compares two, and regenerates the project's fixtures.
//!
//! The command line is defined here ([`Cli`]) and run by [`run`]; the binary only parses arguments and
//! prints the outcome.
#![deny(missing_docs)]

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

use clap::{Args, Parser, Subcommand};
use od::device::{Commissioning, DeviceDescription};
use od::load::Format;

pub mod compare;
pub mod fixtures;
pub mod select;
pub mod summary;

/// Generate, check and compare CANopen / EtherCAT device descriptions.
#[derive(Debug, Parser)]
#[command(name = "esi-gen", version, about, long_about = None)]
pub struct Cli {
    /// Machine-readable output on standard output, nothing else there: a conversion's report, the
    /// SII image written and the fixtures written or stale as one JSON object; `check` as one JSON
    /// document; `diff` one object per difference; an error as one object (exit code 2). A
    /// conversion then needs `-o FILE`, since standard output carries the report.
    #[arg(long, global = true)]
    pub json: bool,
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Write an EtherCAT ESI (all devices of the input unless --device picks one).
    Esi(Convert),
    /// Write a CiA 311 XDD.
    Xdd(Convert),
    /// Write a CiA 306 EDS.
    Eds(Convert),
    /// Write a CiA 306 DCF with the current value of every configurable (writable) entry.
    Dcf(DcfArgs),
    /// Write a Markdown reference of the dictionary.
    Doc(Convert),
    /// Write the SII EEPROM image (binary, ETG.1000.6 layout) of an EtherCAT device.
    Sii(SiiArgs),
    /// Load and validate descriptions: errors first, then warnings, each at file:line:column; a
    /// summary of one file or a line per file of a folder; exit 1 when any has an error.
    Check(CheckArgs),
    /// Compare two descriptions, device by device; exit 0 when equal, 1 when they differ.
    ///
    /// Every part of the descriptions is compared: identity, file info, CAN info, commissioning, the
    /// EtherCAT parts, the dictionary and the comments. Two files of one device each compare those two;
    /// otherwise devices pair by product code and revision (and by name where several share both), and
    /// a device only one file has is one line. Each difference is one line: `- PLACE NAME` (only in the
    /// first), `+ PLACE NAME` (only in the second) or `~ PLACE FIELD: A -> B`, indented under a header
    /// per device when several are compared. Exit 2 when a file cannot be loaded.
    Diff(DiffArgs),
    /// Regenerate the generated descriptions under fixtures/ from fixtures/src and fixtures/identity.toml.
    Fixtures(FixturesArgs),
    /// The shell completion script for SHELL (bash, zsh, fish, elvish, powershell) on standard
    /// output: `source <(esi-gen completions bash)`.
    Completions {
        /// The shell.
        shell: cli_support::Shell,
    },
    /// The manual pages into DIR: esi-gen.1 and one per subcommand (esi-gen-check.1, …), each
    /// file named on standard output.
    Man {
        /// The folder (made if missing).
        dir: PathBuf,
    },
}

/// Input, device choice, identity overrides and output of a conversion. What is written is read back,
/// and what the target format did not keep (or added) is named on stderr, a line per kind.
#[derive(Debug, Args)]
pub struct Convert {
    /// The description to read (ESI, XDD, EDS or DCF; the format is told from the contents).
    pub input: PathBuf,
    /// The file to write; `-` or nothing writes to standard output.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Device options.
    #[command(flatten)]
    pub device: DeviceArgs,
    /// Ready the output as a new file: an EDS or DCF gets what CiA 306 asks of one (its format
    /// version, CAN capabilities, a description from the product name), a DCF the current value of
    /// every configurable entry. A conversion to another format does this anyway; a file written in
    /// its own format (or an EDS as a DCF, or back) otherwise keeps every part of the input as it
    /// was, including what the model does not hold, and gets only the changes asked for.
    #[arg(long)]
    pub normalise: bool,
}

/// Choosing a device and overriding identity values.
#[derive(Debug, Args, Default)]
pub struct DeviceArgs {
    /// Pick one device: NAME, PRODUCT-CODE, or either @REVISION (BK1120@0x00100000).
    ///
    /// NAME is the type name or the product name (any case); PRODUCT-CODE is a number (0x04602C22,
    /// #x04602C22 or decimal); @REVISION picks one revision. Without it, the newest revision of the
    /// device is taken, as EtherCAT configuration tools do. A choice that matches different devices
    /// is refused with the list of them. (--revision does not pick: it overrides the revision written.)
    #[arg(long, value_name = "NAME|PRODUCT-CODE[@REVISION]")]
    pub device: Option<String>,
    /// A TOML file of identity values (`[type-name] vendor_id = …, product_code = …, revision = …`),
    /// applied to the device whose type or product name matches a section.
    #[arg(long)]
    pub identity: Option<PathBuf>,
    /// Override the vendor ID.
    #[arg(long, value_parser = parse_u32)]
    pub vendor_id: Option<u32>,
    /// Override the product code.
    #[arg(long, value_parser = parse_u32)]
    pub product_code: Option<u32>,
    /// Override the revision number.
    #[arg(long, value_parser = parse_u32)]
    pub revision: Option<u32>,
}

impl DeviceArgs {
    /// Applies the identity file (when given) and then the override values to each of `devices`.
    fn identify(&self, devices: &mut [DeviceDescription]) -> Result<(), Error> {
        let identities = match &self.identity {
            Some(p) => Some(IdentityFile::load(p)?),
            None => None,
        };
        for dev in devices {
            if let Some(ids) = &identities {
                ids.apply(dev);
            }
            dev.override_identity(self.vendor_id, self.product_code, self.revision);
        }
        Ok(())
    }
}

/// Arguments of `dcf`.
#[derive(Debug, Args)]
pub struct DcfArgs {
    /// Conversion arguments.
    #[command(flatten)]
    pub convert: Convert,
    /// The node-ID the DCF configures (1..127); `$NODEID` defaults resolve with it. Without it, the
    /// input's node-ID, or none (an unconfigured node, no `NodeID=`).
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=127))]
    pub node_id: Option<u8>,
    /// The bit rate in kbit/s.
    #[arg(long)]
    pub baud_rate: Option<u32>,
}

/// Arguments of `sii`.
#[derive(Debug, Args)]
pub struct SiiArgs {
    /// The ESI to read.
    pub input: PathBuf,
    /// The image file to write.
    #[arg(short, long)]
    pub output: PathBuf,
    /// The serial number in the image.
    #[arg(long, default_value_t = 0, value_parser = parse_u32)]
    pub serial: u32,
    /// Device options.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// Arguments of `check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// The descriptions to check: files, or folders whose description files (.xml, .esi, .eds, .dcf,
    /// .xdd, .xdc, .xpd) are checked one by one. One file gets a one-screen summary; several get a
    /// line each and a summary.
    #[arg(required = true, value_name = "FILE|DIR")]
    pub inputs: Vec<PathBuf>,
    /// Check only one device: NAME, PRODUCT-CODE, or either @REVISION (BK1120@0x00100000).
    ///
    /// NAME is the type name or the product name (any case); PRODUCT-CODE is a number (0x04602C22,
    /// #x04602C22 or decimal); @REVISION picks one revision. Without it, the newest revision of the
    /// device is taken, as EtherCAT configuration tools do. A choice that matches different devices
    /// is an error naming them.
    #[arg(long, value_name = "NAME|PRODUCT-CODE[@REVISION]")]
    pub device: Option<String>,
    /// List every finding (without it, a file's summary shows the first 20, a batch line its errors).
    #[arg(long)]
    pub all: bool,
    /// `--json` (a global flag): one JSON document, every file with its devices and findings, and a
    /// summary.
    #[arg(skip)]
    pub json: bool,
    /// Count warnings as errors.
    #[arg(long)]
    pub strict: bool,
    /// Also write each file in its own format and read it back (it must come back equal), and a
    /// CANopen description as an EDS (it must read back without errors).
    #[arg(long)]
    pub round_trip: bool,
}

/// Arguments of `diff`.
#[derive(Debug, Args)]
pub struct DiffArgs {
    /// The first description.
    pub a: PathBuf,
    /// The second description.
    pub b: PathBuf,
    /// Compare only one device of each file: NAME, PRODUCT-CODE, or either @REVISION (BK1120@0x00100000).
    ///
    /// NAME is the type name or the product name (any case); PRODUCT-CODE is a number (0x04602C22,
    /// #x04602C22 or decimal); @REVISION picks one revision. Without it, the newest revision of the
    /// device is taken, as EtherCAT configuration tools do. A choice that matches different devices
    /// is refused with the list of them.
    #[arg(long, value_name = "NAME|PRODUCT-CODE[@REVISION]")]
    pub device: Option<String>,
    /// Also compare the parts of the files the model does not hold (vendor elements, attributes and
    /// keys, comments), when both files are of one family (ESI, XDD, or EDS and DCF): each is a line
    /// `- file PATH` (only in the first), `+ file PATH` (only in the second) or `~ file PATH: A -> B`,
    /// after the model's differences. They are the files' whole, whatever --device picks.
    #[arg(long)]
    pub all: bool,
    /// `--json` (a global flag): one JSON object per line for each difference instead of text.
    #[arg(skip)]
    pub json: bool,
}

/// Arguments of `fixtures`.
#[derive(Debug, Args)]
pub struct FixturesArgs {
    /// The fixtures folder.
    #[arg(long, default_value = "fixtures")]
    pub root: PathBuf,
    /// Only compare: exit 1 and name the files that regeneration would change.
    #[arg(long)]
    pub check: bool,
}

/// Why a command failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A description could not be loaded.
    #[error(transparent)]
    Load(#[from] od::LoadError),
    /// A file could not be written or read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The identity file is not valid.
    #[error("{path}: {message}")]
    Identity {
        /// The file.
        path: PathBuf,
        /// What was wrong.
        message: String,
    },
    /// No device matches --device.
    #[error("{path}: no device matches `{wanted}`; the file holds {available}")]
    NoSuchDevice {
        /// The file.
        path: PathBuf,
        /// What was asked for.
        wanted: String,
        /// The devices there are.
        available: String,
    },
    /// --device matches different devices.
    #[error(
        "{path}: `{wanted}` matches different devices: {matches}; choose one by type name, or add @REVISION"
    )]
    AmbiguousDevice {
        /// The file.
        path: PathBuf,
        /// What was asked for.
        wanted: String,
        /// The devices it matches.
        matches: String,
    },
    /// The file holds several devices and the output format takes one.
    #[error("{path} holds several devices ({available}); choose one with --device")]
    SeveralDevices {
        /// The file.
        path: PathBuf,
        /// The devices there are.
        available: String,
    },
    /// The file holds no device.
    #[error("{0}: the file describes no device")]
    NoDevice(PathBuf),
    /// `--json` with a conversion to standard output.
    #[error("--json writes its report on standard output: give the file to write with -o FILE")]
    JsonNeedsOutput,
    /// No SII image could be made.
    #[error("{path}: {source}")]
    Sii {
        /// The description.
        path: PathBuf,
        /// Why.
        source: od::sii::SiiError,
    },
}

/// What a command ended with: exit code 0, or 1 for "check found errors" / "diff found differences".
pub type Outcome = Result<u8, Error>;

fn parse_u32(text: &str) -> Result<u32, String> {
    od::value::parse_integer(text)
        .and_then(|v| u32::try_from(v).ok())
        .ok_or_else(|| format!("`{text}` is not a 32-bit unsigned number (decimal or 0x…)"))
}

/// Runs a parsed command line, writing normal output to `out`.
pub fn run(cli: Cli, out: &mut dyn Write, err: &mut dyn Write) -> Outcome {
    let json = cli.json;
    match cli.command {
        Command::Esi(c) => convert(&c, json, out, err, Target::Esi),
        Command::Xdd(c) => convert(&c, json, out, err, Target::Xdd),
        Command::Eds(c) => convert(&c, json, out, err, Target::Eds),
        Command::Doc(c) => convert(&c, json, out, err, Target::Doc),
        Command::Dcf(d) => convert(
            &d.convert,
            json,
            out,
            err,
            Target::Dcf {
                node_id: d.node_id,
                baud_rate: d.baud_rate,
            },
        ),
        Command::Sii(a) => {
            let (_, devices) = load_selected(&a.input, a.device.device.as_deref())?;
            let mut dev = one(&a.input, devices)?;
            a.device.identify(std::slice::from_mut(&mut dev))?;
            let image = od::sii::write(&dev, a.serial).map_err(|source| Error::Sii {
                path: a.input.clone(),
                source,
            })?;
            std::fs::write(&a.output, &image).map_err(|source| Error::Io {
                path: a.output.clone(),
                source,
            })?;
            let text = if json {
                json_line(&serde_json::json!({
                    "output": a.output.display().to_string(), "bytes": image.len(),
                }))
            } else {
                format!("wrote {} ({} bytes)\n", a.output.display(), image.len())
            };
            write_out(out, &text)?;
            Ok(0)
        }
        Command::Check(mut c) => {
            c.json = json;
            summary::run(&c, out)
        }
        Command::Diff(mut d) => {
            d.json = json;
            compare::run(&d, out)
        }
        Command::Completions { shell } => {
            use clap::CommandFactory;
            let mut script = Vec::new();
            cli_support::write_completions(Cli::command(), shell, &mut script).map_err(
                |source| Error::Io {
                    path: PathBuf::from("-"),
                    source,
                },
            )?;
            write_bytes(out, &script)?;
            Ok(0)
        }
        Command::Man { dir } => {
            use clap::CommandFactory;
            let pages =
                cli_support::write_man_pages(Cli::command(), &dir).map_err(|source| Error::Io {
                    path: dir.clone(),
                    source,
                })?;
            for page in pages {
                write_out(out, &format!("{}\n", page.display()))?;
            }
            Ok(0)
        }
        Command::Fixtures(f) => {
            let files = fixtures::generate(&f.root)?;
            if f.check {
                let stale = fixtures::stale(&files);
                if json {
                    let list: Vec<String> = stale.iter().map(|p| p.display().to_string()).collect();
                    write_out(out, &json_line(&serde_json::json!({ "stale": list })))?;
                } else {
                    for p in &stale {
                        write_out(out, &format!("stale: {}\n", p.display()))?;
                    }
                }
                return Ok(if stale.is_empty() { 0 } else { 1 });
            }
            for (path, text) in &files {
                if let Some(dir) = path.parent() {
                    std::fs::create_dir_all(dir).map_err(|source| Error::Io {
                        path: dir.to_path_buf(),
                        source,
                    })?;
                }
                std::fs::write(path, text).map_err(|source| Error::Io {
                    path: path.clone(),
                    source,
                })?;
                if !json {
                    write_out(out, &format!("wrote {}\n", path.display()))?;
                }
            }
            if json {
                let list: Vec<String> =
                    files.iter().map(|(p, _)| p.display().to_string()).collect();
                write_out(out, &json_line(&serde_json::json!({ "written": list })))?;
            }
            Ok(0)
        }
    }
}

/// `value` as one line of JSON.
fn json_line(value: &serde_json::Value) -> String {
    format!("{value}\n")
}

/// An error as `--json` prints it (on standard output; exit code 2).
pub fn error_json(e: &Error) -> serde_json::Value {
    serde_json::json!({"error": e.to_string(), "exit_code": 2})
}

fn write_out(out: &mut dyn Write, text: &str) -> Result<(), Error> {
    write_bytes(out, text.as_bytes())
}

fn write_bytes(out: &mut dyn Write, bytes: &[u8]) -> Result<(), Error> {
    out.write_all(bytes).map_err(|source| Error::Io {
        path: PathBuf::from("-"),
        source,
    })
}

/// What a conversion writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Target {
    Esi,
    Xdd,
    Eds,
    Dcf {
        node_id: Option<u8>,
        baud_rate: Option<u32>,
    },
    Doc,
}

impl Target {
    /// The description format written, read back to tell what was lost (none for the Markdown page).
    fn format(self) -> Option<Format> {
        match self {
            Target::Esi => Some(Format::Esi),
            Target::Xdd => Some(Format::Xdd),
            Target::Eds => Some(Format::Eds),
            Target::Dcf { .. } => Some(Format::Dcf),
            Target::Doc => None,
        }
    }

    /// Readies a description for this target. A new file (`fresh`): an EDS or DCF gets what CiA 306
    /// asks of one (its format version, CAN capabilities), a DCF every configurable value. Any DCF
    /// gets its node-ID and bit rate when given.
    fn prepare(self, dev: &mut DeviceDescription, fresh: bool) {
        if let (Target::Eds | Target::Dcf { .. }, true) = (self, fresh) {
            od::eds::complete_new_file(dev);
        }
        if let Target::Dcf { node_id, baud_rate } = self {
            // Without --node-id the node-ID is the description's, or none: a made-up one would change
            // what every `$NODEID` value means.
            if let Some(n) = node_id {
                dev.set_node_id(Some(n));
            }
            if fresh {
                // Every configurable value goes into the DCF, so that applying it writes them all.
                dev.configure_writable();
                dev.commissioning.get_or_insert_with(Commissioning::default);
            }
            if let Some(b) = baud_rate {
                dev.commissioning
                    .get_or_insert_with(Commissioning::default)
                    .baud_rate = b;
            }
        }
    }

    fn write(self, devices: &[DeviceDescription]) -> String {
        match self {
            Target::Esi => od::esi::write_all(devices),
            Target::Xdd => od::xdd::write(&devices[0]),
            Target::Eds => od::eds::write_eds(&devices[0]),
            Target::Dcf { .. } => od::eds::write_dcf(&devices[0]),
            Target::Doc => od::doc::write(&devices[0]),
        }
    }
}

fn convert(
    c: &Convert,
    json: bool,
    out: &mut dyn Write,
    err: &mut dyn Write,
    target: Target,
) -> Outcome {
    let to_stdout = c.output.as_deref().is_none_or(|p| p.as_os_str() == "-");
    if json && to_stdout {
        return Err(Error::JsonNeedsOutput);
    }
    let original = od::load::read_limited(&c.input, od::load::MAX_FILE_BYTES)?;
    let (input_format, as_read) = od::load::load(&c.input)?;
    let mut devices = match c.device.device.as_deref() {
        None => as_read.clone(),
        Some(wanted) => vec![select::select(&c.input, as_read.clone(), wanted)?],
    };
    if devices.is_empty() {
        return Err(Error::NoDevice(c.input.clone()));
    }
    if devices.len() > 1 && target != Target::Esi {
        return Err(Error::SeveralDevices {
            path: c.input.clone(),
            available: list(&devices),
        });
    }
    c.device.identify(&mut devices)?;
    // An ESI has no file information to stamp.
    let name = c
        .output
        .as_deref()
        .and_then(|p| p.file_name())
        .and_then(|n| n.to_str())
        .filter(|_| target != Target::Esi);
    // A file written in its own format is a new one only when asked; an EDS made a DCF is one.
    let carried = target
        .format()
        .filter(|f| od::carry::same_family(*f, input_format));
    let fresh = c.normalise || target.format() != Some(input_format);
    for dev in &mut devices {
        if let Some(name) = name {
            if fresh {
                stamp_file_info(dev, name);
            } else if !dev.file_info.file_name.is_empty() {
                // A rewrite names the file it is, where the input named itself.
                dev.file_info.file_name = name.to_string();
            }
        }
        target.prepare(dev, fresh);
    }
    let (text, fallback) = match carried {
        Some(format) => {
            let w = od::carry::write(&original, input_format, &as_read, format, &devices);
            (w.bytes, w.kept.err())
        }
        None => (target.write(&devices).into_bytes(), None),
    };

    if let Some(why) = &fallback {
        let note = format!(
            "esi-gen: {}: the parts the model does not hold could not be kept ({why}); written from the model\n",
            c.input.display()
        );
        err.write_all(note.as_bytes()).map_err(|source| Error::Io {
            path: PathBuf::from("-"),
            source,
        })?;
    }
    match &c.output {
        None => write_bytes(out, &text)?,
        Some(p) if p.as_os_str() == "-" => write_bytes(out, &text)?,
        Some(p) => std::fs::write(p, &text).map_err(|source| Error::Io {
            path: p.clone(),
            source,
        })?,
    }
    // What of the input file its model does not hold goes unless the output is the input kept.
    let unheld = if carried.is_some() && fallback.is_none() {
        Vec::new()
    } else {
        od::carry::unheld_in_file(&original, input_format, &as_read).unwrap_or_default()
    };
    if json {
        let (format, mut not_kept) = match target.format() {
            Some(format) => (
                format.to_string(),
                match loss_groups(format, &devices, &text) {
                    Ok(groups) => serde_json::json!(groups
                        .iter()
                        .map(|(kind, count, example)| serde_json::json!({
                            "kind": kind, "count": count, "example": example,
                        }))
                        .collect::<Vec<_>>()),
                    Err(e) => serde_json::json!({ "does_not_read_back": e }),
                },
            ),
            None => ("Markdown".to_string(), serde_json::Value::Null),
        };
        if let (Some(first), Some(list)) = (unheld.first(), not_kept.as_array_mut()) {
            list.push(serde_json::json!({
                "kind": UNHELD, "count": unheld.len(), "example": first.path,
            }));
        }
        let output = c.output.as_deref().map(|p| p.display().to_string());
        let value = serde_json::json!({
            "input": c.input.display().to_string(),
            "output": output,
            "format": format,
            "bytes": text.len(),
            "kept_as_written": carried.is_some() && fallback.is_none(),
            "devices": devices.iter().map(summary::label).collect::<Vec<_>>(),
            "not_kept": not_kept,
        });
        write_out(out, &json_line(&value))?;
        return Ok(0);
    }
    if let Some(format) = target.format() {
        let mut note = losses(&c.input, format, &devices, &text);
        if let Some(first) = unheld.first() {
            if note.is_empty() {
                note = format!("esi-gen: {}: written as {format}:\n", c.input.display());
            }
            let n = unheld.len();
            note.push_str(&format!(
                "  {n:>5} × {UNHELD}: {}\n",
                clip(&first.path, 100)
            ));
        }
        err.write_all(note.as_bytes()).map_err(|source| Error::Io {
            path: PathBuf::from("-"),
            source,
        })?;
    }
    Ok(0)
}

/// The kind of loss of a part of the input file its model does not hold (a vendor element, key or
/// comment), which only a rewrite in the input's own format keeps.
const UNHELD: &str = "part of the file the model does not hold left out";

/// What a conversion of `devices` (read from `input`) to `written`, a text in `format`, did not keep:
/// the differences of what reads back, grouped by the kind of part and field, each group with its count
/// and its first place; empty when everything came through.
pub fn losses(
    input: &Path,
    format: Format,
    devices: &[DeviceDescription],
    written: &[u8],
) -> String {
    let groups = match loss_groups(format, devices, written) {
        Ok(groups) => groups,
        Err(e) => {
            return format!(
                "esi-gen: {}: written as {format}, it does not read back: {e}\n",
                input.display()
            )
        }
    };
    if groups.is_empty() {
        return String::new();
    }
    let total: usize = groups.iter().map(|g| g.1).sum();
    let mut text = format!(
        "esi-gen: {}: written as {format}, {total} difference(s) read back (what {format} does not carry, or adds):\n",
        input.display()
    );
    for (kind, n, example) in &groups {
        let example = clip(example, 100);
        text.push_str(&format!("  {n:>5} × {kind}: {example}\n"));
    }
    text
}

/// The differences of what `written` (a text in `format`) reads back from `devices`, grouped by
/// kind: each kind with its count and its first place, in the order they come; or why it does not
/// read back.
fn loss_groups(
    format: Format,
    devices: &[DeviceDescription],
    written: &[u8],
) -> Result<Vec<(String, usize, String)>, String> {
    let back = od::load::read_bytes(written, "written", format).map_err(|e| e.to_string())?;
    let mut groups: Vec<(String, usize, String)> = Vec::new();
    let mut count = |kind: String, example: String| match groups.iter_mut().find(|g| g.0 == kind) {
        Some(g) => g.1 += 1,
        None => groups.push((kind, 1, example)),
    };
    let several = devices.len() > 1;
    for pairing in od::diff::pair_devices(devices, &back) {
        match pairing {
            od::diff::Pairing::Both(i, j) => {
                for d in od::diff::diff_devices(&devices[i], &back[j]) {
                    let example = if several {
                        format!("{}: {d}", summary::label(&devices[i]))
                    } else {
                        d.to_string()
                    };
                    count(loss_kind(&d), example);
                }
            }
            od::diff::Pairing::OnlyInA(i) => {
                count("device left out".into(), summary::label(&devices[i]));
            }
            od::diff::Pairing::OnlyInB(j) => {
                count("device added".into(), summary::label(&back[j]));
            }
        }
    }
    Ok(groups)
}

/// The kind of a difference, for grouping: its place without keys (`TxPdo entry`, `entry`, `EtherCAT`)
/// and the field or whether the part is only on one side.
fn loss_kind(d: &od::diff::Difference) -> String {
    use od::diff::{Change, Step};
    let mut parts: Vec<&str> = d
        .path
        .iter()
        .map(|s| match s {
            Step::Part(name) => name,
            Step::Item { kind, .. } => kind,
            Step::Object(_) => "object",
            Step::Entry(..) => "entry",
        })
        .collect();
    let tail = match &d.change {
        Change::OnlyInA(_) => "left out".to_string(),
        Change::OnlyInB(_) => "added".to_string(),
        Change::Changed { field, .. } => {
            parts.push(field);
            "changed".to_string()
        }
    };
    if parts.is_empty() {
        return tail;
    }
    format!("{} {tail}", parts.join(" "))
}

pub(crate) fn clip(text: &str, max: usize) -> String {
    match text.char_indices().nth(max) {
        Some((i, _)) => format!("{}…", &text[..i]),
        None => text.to_string(),
    }
}

/// Fills the file information a written description gives about itself: its file name (always), and a
/// description (the product name) where the source had none.
pub fn stamp_file_info(dev: &mut DeviceDescription, file_name: &str) {
    dev.file_info.file_name = file_name.to_string();
    if dev.file_info.description.is_empty() {
        dev.file_info.description = dev.identity.product_name.clone();
    }
}

/// Loads `path` and keeps the device `wanted` picks (all devices when `None`), as [`select`] tells.
pub fn load_selected(
    path: &Path,
    wanted: Option<&str>,
) -> Result<(Format, Vec<DeviceDescription>), Error> {
    let (format, devices) = od::load::load(path)?;
    match wanted {
        None => Ok((format, devices)),
        Some(wanted) => Ok((format, vec![select::select(path, devices, wanted)?])),
    }
}

fn one(path: &Path, devices: Vec<DeviceDescription>) -> Result<DeviceDescription, Error> {
    match devices.len() {
        0 => Err(Error::NoDevice(path.to_path_buf())),
        1 => Ok(devices.into_iter().next().expect("one device")),
        _ => Err(Error::SeveralDevices {
            path: path.to_path_buf(),
            available: list(&devices),
        }),
    }
}

/// The devices as `name (product code …, revision …)` for messages.
pub fn list<'a>(devices: impl IntoIterator<Item = &'a DeviceDescription>) -> String {
    devices
        .into_iter()
        .map(|d| {
            format!(
                "{} (product code 0x{:08X}, revision 0x{:08X})",
                device_name(d),
                d.identity.product_code,
                d.identity.revision
            )
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The shortest name of a device: its type name, else its product name.
pub fn device_name(d: &DeviceDescription) -> &str {
    if d.identity.order_code.is_empty() {
        &d.identity.product_name
    } else {
        &d.identity.order_code
    }
}

/// Identity values kept outside the descriptions (`fixtures/identity.toml`): one table per device,
/// keyed by type name, with `vendor_id`, `product_code` and `revision`.
#[derive(Debug, Clone, Default)]
pub struct IdentityFile {
    entries: BTreeMap<String, IdentityEntry>,
}

/// One device's identity values.
#[derive(Debug, Clone, Copy, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IdentityEntry {
    /// Vendor ID.
    pub vendor_id: Option<u32>,
    /// Product code.
    pub product_code: Option<u32>,
    /// Revision number.
    pub revision: Option<u32>,
}

/// The largest identity file read (a few lines per device; anything larger is not one).
pub const MAX_IDENTITY_FILE: u64 = 1 << 20;

impl IdentityFile {
    /// Reads an identity file: a regular file of at most [`MAX_IDENTITY_FILE`] bytes.
    pub fn load(path: &Path) -> Result<IdentityFile, Error> {
        let bytes = od::load::read_limited(path, MAX_IDENTITY_FILE)?;
        let text = String::from_utf8(bytes).map_err(|_| Error::Identity {
            path: path.to_path_buf(),
            message: "not UTF-8 text".into(),
        })?;
        IdentityFile::parse(&text).map_err(|message| Error::Identity {
            path: path.to_path_buf(),
            message,
        })
    }

    /// Parses the TOML text of an identity file.
    pub fn parse(text: &str) -> Result<IdentityFile, String> {
        let entries: BTreeMap<String, IdentityEntry> =
            toml::from_str(text).map_err(|e| e.to_string())?;
        let entries = entries
            .into_iter()
            .map(|(k, v)| (k.to_ascii_lowercase(), v))
            .collect();
        Ok(IdentityFile { entries })
    }

    /// The entry for a device, matched by type name or product name, case-insensitively.
    pub fn entry_for(&self, dev: &DeviceDescription) -> Option<&IdentityEntry> {
        self.entries
            .get(&dev.identity.order_code.to_ascii_lowercase())
            .or_else(|| {
                self.entries
                    .get(&dev.identity.product_name.to_ascii_lowercase())
            })
    }

    /// Applies the matching entry, if any, to `dev`.
    pub fn apply(&self, dev: &mut DeviceDescription) {
        if let Some(e) = self.entry_for(dev) {
            dev.override_identity(e.vendor_id, e.product_code, e.revision);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn device(name: &str, code: u32) -> DeviceDescription {
        let mut d = DeviceDescription::default();
        d.identity.order_code = name.into();
        d.identity.product_code = code;
        d.identity.revision = 1;
        d
    }

    /// What several devices lost is named by device; one device's differences are not.
    #[test]
    fn losses_name_the_device_when_there_are_several() {
        let two = [device("A", 1), device("B", 2)];
        let mut written = two.clone();
        written[1].identity.product_name = "Bee".into();
        let text = od::esi::write_all(&written);
        assert_eq!(
            losses(Path::new("in.xml"), Format::Esi, &two, text.as_bytes()),
            "esi-gen: in.xml: written as ESI, 3 difference(s) read back (what ESI does not carry, or adds):\n\
             \x20     2 × EtherCAT added: A rev 0x00000001: + EtherCAT\n\
             \x20     1 × identity product name changed: B rev 0x00000001: ~ identity product name: \"\" -> \"Bee\"\n"
        );
        let text = od::esi::write_all(&two[..1]);
        assert_eq!(
            losses(Path::new("in.xml"), Format::Esi, &two, text.as_bytes()),
            "esi-gen: in.xml: written as ESI, 2 difference(s) read back (what ESI does not carry, or adds):\n\
             \x20     1 × EtherCAT added: A rev 0x00000001: + EtherCAT\n\
             \x20     1 × device left out: B rev 0x00000001\n"
        );
        let text = od::esi::write_all(&two);
        let one = [device("A", 1), device("C", 3)];
        assert!(
            losses(Path::new("in.xml"), Format::Esi, &one, text.as_bytes()).ends_with(
                "\n      1 × device left out: C rev 0x00000001\n      1 × device added: B rev 0x00000001\n"
            )
        );
        // One device: no label.
        let text = od::esi::write_all(&two[..1]);
        assert_eq!(
            losses(Path::new("in.xml"), Format::Esi, &two[..1], text.as_bytes()),
            "esi-gen: in.xml: written as ESI, 1 difference(s) read back (what ESI does not carry, or adds):\n\
             \x20     1 × EtherCAT added: + EtherCAT\n"
        );
        assert_eq!(
            losses(Path::new("in.xml"), Format::Esi, &one, b"<EtherCATInfo"),
            "esi-gen: in.xml: written as ESI, it does not read back: written:1:1: malformed XML: syntax \
             error: tag not closed: `>` not found before end of input\n"
        );
    }
}
