//! `smd-ethercat`: virtual SMD23K-B / SMD24K units on an EtherCAT segment. See `smd-ethercat --help`.

use clap::Parser;
use tracing_subscriber::EnvFilter;

fn main() {
    tracing_subscriber::fmt()
        .with_env_filter(
            EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .init();
    let args = ethercat_slave::cli::Args::parse();
    match ethercat_slave::cli::run(&args, None) {
        Ok(stats) => eprintln!(
            "smd-ethercat: {} frames answered, {} dropped",
            stats.answered, stats.dropped
        ),
        Err(e) => {
            eprintln!("smd-ethercat: {e}");
            std::process::exit(2);
        }
    }
}
