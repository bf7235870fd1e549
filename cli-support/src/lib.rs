//! What the command-line binaries of the workspace share (`sdo-tool`, `esi-gen`, `canopen-node`,
//! `x67-node`, `ethercat-node`, `smd-ethercat`): the log on standard error ([`init_logging`]), the
//! flag Ctrl-C (or SIGTERM, SIGHUP) sets to stop a run ([`stop_flag`]), so that a run ends as it
//! returns, its capture written whole, and the shell completion script and manual pages of a
//! command line ([`write_completions`], [`write_man_pages`], and [`Generate`], the
//! `--completions SHELL` and `--man DIR` options of the binaries without subcommands).
//!
//! Only binaries and the `cli` features of the libraries depend on this crate: a library used
//! without its `cli` feature has neither a log subscriber nor a signal handler.
#![deny(missing_docs)]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// The shells a completion script is written for: bash, zsh, fish, elvish, powershell.
pub use clap_complete::Shell;

use tracing_subscriber::EnvFilter;

/// Why Ctrl-C could not be hooked.
pub use ctrlc::Error as SignalError;

/// The variable whose filter directives choose what is logged (`RUST_LOG`, as
/// [`EnvFilter`] reads it).
pub const FILTER_VARIABLE: &str = EnvFilter::DEFAULT_ENV;

/// What is logged where [`FILTER_VARIABLE`] is unset or does not parse: every event of level info
/// and above.
pub const DEFAULT_FILTER: &str = "info";

/// How the log lines are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LogFormat {
    /// One human-readable line per event: the time, the level, the target, the message and the
    /// fields.
    #[default]
    Text,
    /// One JSON object per line: "timestamp", "level", "message", "target" and the event's fields
    /// beside them (flattened), with the spans it is in.
    Json,
}

/// The variable that turns colour off wherever it is set to anything but the empty string
/// (<https://no-color.org>).
pub const NO_COLOR_VARIABLE: &str = "NO_COLOR";

/// Whether the text log is coloured (ANSI escape codes): only on a terminal (`terminal`), and not
/// when [`NO_COLOR_VARIABLE`] is set to a value that is not empty (`no_color`), as no-color.org
/// asks. A log piped into a file or another program is plain text.
pub fn colour(terminal: bool, no_color: Option<&std::ffi::OsStr>) -> bool {
    terminal && !matches!(no_color, Some(v) if !v.is_empty())
}

/// Installs the process's log: events on standard error in `format`, filtered by
/// [`FILTER_VARIABLE`], or by [`DEFAULT_FILTER`] where it is unset or does not parse; coloured
/// only where [`colour`] says.
///
/// # Panics
///
/// When a global subscriber is already installed (a second call).
pub fn init_logging(format: LogFormat) {
    use std::io::IsTerminal;
    let filter =
        EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new(DEFAULT_FILTER));
    let no_color = std::env::var_os(NO_COLOR_VARIABLE);
    let log = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_ansi(colour(std::io::stderr().is_terminal(), no_color.as_deref()))
        .with_writer(std::io::stderr);
    match format {
        LogFormat::Text => log.init(),
        LogFormat::Json => log.json().flatten_event(true).init(),
    }
}

/// A new flag that Ctrl-C (SIGINT), SIGTERM (a service manager's stop) or SIGHUP sets.
///
/// A process hooks them once: a second call fails.
pub fn stop_on_ctrl_c() -> Result<Arc<AtomicBool>, SignalError> {
    let stop = Arc::new(AtomicBool::new(false));
    let hook = Arc::clone(&stop);
    ctrlc::set_handler(move || hook.store(true, Ordering::Relaxed))?;
    Ok(stop)
}

/// The flag that stops a run: `given` where there is one (a caller that stops the run itself, as a
/// test does), else a new one that Ctrl-C sets ([`stop_on_ctrl_c`]).
pub fn stop_flag(given: Option<Arc<AtomicBool>>) -> Result<Arc<AtomicBool>, SignalError> {
    match given {
        Some(stop) => Ok(stop),
        None => stop_on_ctrl_c(),
    }
}

/// Writes the completion script of `command` for `shell` to `out` (bash: `source <(TOOL
/// completions bash)`, or the file in `/etc/bash_completion.d/`). The script is made whole first,
/// so a failing `out` (a closed pipe) is an error, not a panic.
pub fn write_completions(
    mut command: clap::Command,
    shell: Shell,
    out: &mut dyn Write,
) -> std::io::Result<()> {
    let name = command.get_name().to_string();
    let mut script = Vec::new();
    clap_complete::generate(shell, &mut command, name, &mut script);
    out.write_all(&script)
}

/// Writes the manual pages of `command` into `dir` (made if missing): `NAME.1`, and for each
/// subcommand `NAME-SUB.1` (`sdo-tool-read.1`, `sdo-tool-net-gen.1`), as git's are named. Returns
/// the files written, in that order.
pub fn write_man_pages(command: clap::Command, dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut command = command;
    command.build();
    let mut written = Vec::new();
    let name = command.get_name().to_string();
    let version = command.get_version().map(str::to_string);
    man_pages(&command, &name, version.as_deref(), dir, &mut written)?;
    Ok(written)
}

/// The page of `command` as `name` (with the program's `version`), then those of its
/// subcommands (but `help`).
fn man_pages(
    command: &clap::Command,
    name: &str,
    version: Option<&str>,
    dir: &Path,
    written: &mut Vec<PathBuf>,
) -> std::io::Result<()> {
    let path = dir.join(format!("{name}.1"));
    let mut page = Vec::new();
    let mut named = command.clone().name(name.to_string());
    if let Some(v) = version {
        named = named.version(v.to_string());
    }
    clap_mangen::Man::new(named).render(&mut page)?;
    std::fs::write(&path, page)?;
    written.push(path);
    for sub in command.get_subcommands() {
        if sub.get_name() == "help" || sub.is_hide_set() {
            continue;
        }
        let sub_name = format!("{name}-{}", sub.get_name());
        man_pages(sub, &sub_name, version, dir, written)?;
    }
    Ok(())
}

/// `--completions SHELL` and `--man DIR`, for a binary without subcommands to flatten into its
/// arguments (`#[command(flatten)]`); the binary's required arguments are required unless one of
/// them is given (`required_unless_present_any = ["completions", "man"]`), and the other options
/// (an environment variable's among them) are ignored then.
#[derive(Debug, Clone, Default, PartialEq, Eq, clap::Args)]
pub struct Generate {
    /// Write the shell completion script for SHELL (bash, zsh, fish, elvish, powershell) to
    /// standard output, and exit.
    #[arg(long, value_name = "SHELL", conflicts_with = "man")]
    pub completions: Option<Shell>,
    /// Write the manual page NAME.1 into DIR, and exit.
    #[arg(long, value_name = "DIR")]
    pub man: Option<PathBuf>,
}

impl Generate {
    /// Does what was asked, if anything, for `command`: the script to standard output, or the
    /// pages into the folder, naming each on standard output. Whether there was anything to do
    /// (the binary then exits).
    pub fn run(&self, command: clap::Command) -> std::io::Result<bool> {
        if let Some(shell) = self.completions {
            write_completions(command, shell, &mut std::io::stdout())?;
            return Ok(true);
        }
        if let Some(dir) = &self.man {
            for page in write_man_pages(command, dir)? {
                println!("{}", page.display());
            }
            return Ok(true);
        }
        Ok(false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Colour on a terminal only, and not there when NO_COLOR is set to anything but "".
    #[test]
    fn colour_only_on_a_terminal_without_no_color() {
        use std::ffi::OsStr;
        assert!(colour(true, None));
        assert!(colour(true, Some(OsStr::new(""))));
        assert!(!colour(true, Some(OsStr::new("1"))));
        assert!(!colour(false, None));
        assert!(!colour(false, Some(OsStr::new(""))));
    }

    /// A command of two levels: a page for it and each subcommand, none for `help`; the bash script
    /// completes the subcommands.
    #[test]
    fn pages_and_completions_of_a_command() {
        use clap::{Arg, Command};
        let command = || {
            Command::new("tool")
                .version("1.2.3")
                .about("Does things")
                .arg(Arg::new("verbose").long("verbose").num_args(0))
                .subcommand(
                    Command::new("net")
                        .about("Networks")
                        .subcommand(Command::new("gen").about("Generates")),
                )
                .subcommand(Command::new("read").about("Reads"))
        };
        let dir = std::env::temp_dir().join(format!("cli-support-man-{}", std::process::id()));
        let pages = write_man_pages(command(), &dir).unwrap();
        let names: Vec<String> = pages
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            names,
            ["tool.1", "tool-net.1", "tool-net-gen.1", "tool-read.1"]
        );
        let page = std::fs::read_to_string(dir.join("tool-net-gen.1")).unwrap();
        assert!(page.starts_with(".ie \\n(.g .ds Aq \\(aq"), "{page}");
        assert!(
            page.contains(".TH tool-net-gen 1  \"tool-net-gen 1.2.3\""),
            "{page}"
        );
        assert!(page.contains("Generates"), "{page}");
        std::fs::remove_dir_all(&dir).unwrap();
        let mut script = Vec::new();
        write_completions(command(), Shell::Bash, &mut script).unwrap();
        let script = String::from_utf8(script).unwrap();
        assert!(script.contains("complete -F _tool"), "{script}");
        assert!(script.contains("--verbose"), "{script}");
        assert!(script.contains("net read"), "{script}");
    }

    #[test]
    fn a_given_flag_is_the_flag() {
        let given = Arc::new(AtomicBool::new(false));
        let stop = stop_flag(Some(Arc::clone(&given))).unwrap();
        assert!(Arc::ptr_eq(&given, &stop));
    }
}
