//! `sdo-tool`: the CANopen commissioning command line. See `sdo-tool --help`.

fn main() {
    let args = sdo_tool::cli::Args::from_command_line();
    if let Err(e) = sdo_tool::cli::run(&args, None, &mut std::io::stdout()) {
        if args.json {
            println!("{}", sdo_tool::cli::error_json(&e));
        } else {
            eprintln!("sdo-tool: {e}");
        }
        std::process::exit(e.exit_code());
    }
}
