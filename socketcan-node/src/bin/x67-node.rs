//! `x67-node`: the virtual X67BC4321-10 + X67SM2436 CANopen node. See `x67-node --help`.

use clap::Parser;

fn main() {
    cli_support::init_logging(cli_support::LogFormat::Text);
    let args = socketcan_node::cli::Args::parse();
    if let Err(e) = socketcan_node::cli::run(&args, None) {
        eprintln!("x67-node: {e}");
        std::process::exit(2);
    }
}
