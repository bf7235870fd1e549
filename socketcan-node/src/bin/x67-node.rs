//! `x67-node`: the virtual X67BC4321-10 + X67SM2436 CANopen node. See `x67-node --help`.

use clap::{CommandFactory, Parser};

fn main() {
    cli_support::init_logging(cli_support::LogFormat::Text);
    let args = socketcan_node::cli::Args::parse();
    match args.generate.run(socketcan_node::cli::Args::command()) {
        Ok(true) => return,
        Ok(false) => {}
        Err(e) => {
            eprintln!("x67-node: {e}");
            std::process::exit(2);
        }
    }
    if let Err(e) = socketcan_node::cli::run(&args, None) {
        eprintln!("x67-node: {e}");
        std::process::exit(2);
    }
}
