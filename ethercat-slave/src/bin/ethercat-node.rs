//! `ethercat-node`: any ESI's devices as emulated EtherCAT slaves, with a CiA 402 drive behind the
//! drive axes. See `ethercat-node --help`.

use clap::CommandFactory;
use cli_support::LogFormat;

fn main() {
    let config = ethercat_slave::node_cli::parse(std::env::args_os()).unwrap_or_else(|e| e.exit());
    match config
        .args
        .generate
        .run(ethercat_slave::node_cli::Args::command())
    {
        Ok(true) => return,
        Ok(false) => {}
        Err(e) => {
            eprintln!("ethercat-node: {e}");
            std::process::exit(2);
        }
    }
    // With --json the log is JSON too: one object per line, a drive's lines with their fields
    // (axis, index, value, limit, code) beside the message and the unit's span.
    cli_support::init_logging(if config.args.json {
        LogFormat::Json
    } else {
        LogFormat::Text
    });
    match ethercat_slave::node_cli::run(&config, None) {
        Ok(_) if config.args.explain || config.args.list => {}
        Ok(stats) => eprintln!(
            "ethercat-node: {} frames answered, {} dropped",
            stats.answered, stats.dropped
        ),
        Err(e) => {
            eprintln!("ethercat-node: {e}");
            std::process::exit(2);
        }
    }
}
