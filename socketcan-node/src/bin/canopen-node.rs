//! `canopen-node`: virtual CANopen nodes from device descriptions. See `canopen-node --help`.

use clap::Parser;
use tracing_subscriber::EnvFilter;

fn main() {
    tracing_subscriber::fmt()
        .with_env_filter(
            EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .init();
    let args = socketcan_node::canopen_cli::Args::parse();
    if let Err(e) = socketcan_node::canopen_cli::run(&args, None) {
        eprintln!("canopen-node: {e}");
        std::process::exit(2);
    }
}
