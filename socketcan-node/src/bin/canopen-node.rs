//! `canopen-node`: virtual CANopen nodes from device descriptions. See `canopen-node --help`.

use clap::Parser;
use tracing_subscriber::EnvFilter;

fn main() {
    let args = socketcan_node::canopen_cli::Args::parse();
    let filter = EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info"));
    let log = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr);
    // With --json the log is JSON too: one object per line, the drive's lines with their fields
    // (axis, index, value, limit, code) beside the message.
    if args.json {
        log.json().flatten_event(true).init();
    } else {
        log.init();
    }
    if let Err(e) = socketcan_node::canopen_cli::run(&args, None) {
        eprintln!("canopen-node: {e}");
        std::process::exit(2);
    }
}
