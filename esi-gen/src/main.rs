use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = esi_gen::Cli::parse();
    let mut stdout = std::io::stdout().lock();
    let mut stderr = std::io::stderr().lock();
    match esi_gen::run(cli, &mut stdout, &mut stderr) {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            eprintln!("esi-gen: {e}");
            ExitCode::from(2)
        }
    }
}
