//! `x67-node`: the virtual X67BC4321-10 + X67SM2436 CANopen node. See `x67-node --help`.

use clap::Parser;
use tracing_subscriber::EnvFilter;

fn main() {
    tracing_subscriber::fmt()
        .with_env_filter(
            EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .init();
    let args = socketcan_node::cli::Args::parse();
    if let Err(e) = socketcan_node::cli::run(&args, None) {
        eprintln!("x67-node: {e}");
        std::process::exit(2);
    }
}
