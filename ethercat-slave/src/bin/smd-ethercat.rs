//! `smd-ethercat`: virtual SMD23K-B / SMD24K units on an EtherCAT segment. See `smd-ethercat --help`.

use clap::Parser;

fn main() {
    cli_support::init_logging(cli_support::LogFormat::Text);
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
