use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = esi_gen::Cli::parse();
    let json = cli.json;
    let mut stdout = std::io::stdout().lock();
    let mut stderr = std::io::stderr().lock();
    match esi_gen::run(cli, &mut stdout, &mut stderr) {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            if json {
                use std::io::Write;
                let _ = writeln!(stdout, "{}", esi_gen::error_json(&e));
            } else {
                eprintln!("esi-gen: {e}");
            }
            ExitCode::from(2)
        }
    }
}
