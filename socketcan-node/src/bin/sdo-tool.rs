//! `sdo-tool`: the CANopen commissioning command line. See `sdo-tool --help`.

use clap::Parser;

fn main() {
    let args = socketcan_node::tool::cli::Args::parse();
    if let Err(e) = socketcan_node::tool::cli::run(&args, None, &mut std::io::stdout()) {
        if args.json {
            println!("{}", socketcan_node::tool::cli::error_json(&e));
        } else {
            eprintln!("sdo-tool: {e}");
        }
        std::process::exit(e.exit_code());
    }
}
