//! `sdo-tool`: the CANopen commissioning command line. See `sdo-tool --help`.

use std::io::IsTerminal;

fn main() {
    let mut args = sdo_tool::cli::Args::from_command_line();
    args.stdout_terminal = std::io::stdout().is_terminal();
    if let Err(e) = sdo_tool::cli::run(&args, None, &mut std::io::stdout()) {
        // The output's reader is gone (`| head`): nothing more to say, to anyone.
        if !e.broken_pipe() {
            if args.json {
                use std::io::Write;
                let _ = writeln!(std::io::stdout(), "{}", sdo_tool::cli::error_json(&e));
            } else {
                eprintln!("sdo-tool: {e}");
            }
        }
        std::process::exit(e.exit_code());
    }
}
