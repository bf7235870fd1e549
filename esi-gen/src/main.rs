use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = esi_gen::Cli::parse();
    let mut stdout = std::io::stdout().lock();
    match esi_gen::run(cli, &mut stdout) {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            eprintln!("esi-gen: {e}");
            ExitCode::from(2)
        }
    }
}
