//! `smd`: tools for the AMCI SMD23K-B / SMD24K. See `smd --help`.

use clap::Parser;

fn main() {
    let args = ds402::smd::cli::Args::parse();
    match ds402::smd::cli::run(&args, std::time::Instant::now(), &mut std::io::stdout()) {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            if args.json {
                println!("{}", ds402::smd::cli::error_json(&e));
            } else {
                eprintln!("smd: {e}");
            }
            std::process::exit(2);
        }
    }
}
