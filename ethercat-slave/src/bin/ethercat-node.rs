//! `ethercat-node`: any ESI's devices as emulated EtherCAT slaves, with a CiA 402 drive behind the
//! drive axes. See `ethercat-node --help`.

use tracing_subscriber::EnvFilter;

fn main() {
    let config = ethercat_slave::node_cli::parse(std::env::args_os()).unwrap_or_else(|e| e.exit());
    let filter = EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info"));
    let log = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr);
    // With --json the log is JSON too: one object per line, a drive's lines with their fields
    // (axis, index, value, limit, code) beside the message and the unit's span.
    if config.args.json {
        log.json().flatten_event(true).init();
    } else {
        log.init();
    }
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
