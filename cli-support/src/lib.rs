//! What the command-line binaries of the workspace share (`canopen-node`, `x67-node`,
//! `ethercat-node`, `smd-ethercat`): the log on standard error ([`init_logging`]) and the flag
//! Ctrl-C (or SIGTERM, SIGHUP) sets to stop a run ([`stop_flag`]), so that a run ends as it
//! returns, its capture written whole.
//!
//! Only binaries and the `cli` features of the libraries depend on this crate: a library used
//! without its `cli` feature has neither a log subscriber nor a signal handler.
#![deny(missing_docs)]

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

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

/// Installs the process's log: events on standard error in `format`, filtered by
/// [`FILTER_VARIABLE`], or by [`DEFAULT_FILTER`] where it is unset or does not parse.
///
/// # Panics
///
/// When a global subscriber is already installed (a second call).
pub fn init_logging(format: LogFormat) {
    let filter =
        EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new(DEFAULT_FILTER));
    let log = tracing_subscriber::fmt()
        .with_env_filter(filter)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_given_flag_is_the_flag() {
        let given = Arc::new(AtomicBool::new(false));
        let stop = stop_flag(Some(Arc::clone(&given))).unwrap();
        assert!(Arc::ptr_eq(&given, &stop));
    }
}
