//! `canopen-node`: virtual CANopen nodes from device descriptions. See `canopen-node --help`.

use clap::{CommandFactory, Parser};
use cli_support::LogFormat;

fn main() {
    let args = socketcan_node::canopen_cli::Args::parse();
    match args
        .generate
        .run(socketcan_node::canopen_cli::Args::command())
    {
        Ok(true) => return,
        Ok(false) => {}
        Err(e) => {
            eprintln!("canopen-node: {e}");
            std::process::exit(2);
        }
    }
    // With --json the log is JSON too: one object per line, the drive's lines with their fields
    // (axis, index, value, limit, code) beside the message.
    cli_support::init_logging(if args.json {
        LogFormat::Json
    } else {
        LogFormat::Text
    });
    if let Err(e) = socketcan_node::canopen_cli::run(&args, None) {
        eprintln!("canopen-node: {e}");
        std::process::exit(2);
    }
}
