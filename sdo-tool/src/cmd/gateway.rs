//! `gateway`: a CiA 309-3 ASCII gateway on standard input and output, or on a TCP socket.

use std::io::Write;

use crate::{Tool, ToolError, UsageError};

/// `gateway`'s arguments.
#[derive(Debug, clap::Args)]
pub struct GatewayArgs {
    /// Listen on ADDR:PORT instead of standard input.
    #[arg(long, value_name = "ADDR:PORT")]
    pub listen: Option<std::net::SocketAddr>,
}

/// The gateway on `tool`'s bus: on standard input and output, or for the clients of `--listen`.
pub fn run(args: &GatewayArgs, tool: Tool, out: &mut dyn Write) -> Result<(), ToolError> {
    let gw = std::sync::Arc::new(std::sync::Mutex::new(crate::gateway::Gateway::new(tool)));
    match &args.listen {
        None => {
            let stdin = std::io::stdin();
            crate::gateway::serve(&gw, stdin.lock(), out).map_err(ToolError::Output)?;
        }
        Some(addr) => {
            let listener =
                std::net::TcpListener::bind(addr).map_err(|error| UsageError::Listen {
                    address: *addr,
                    error,
                })?;
            gateway_connections(&listener, &gw);
        }
    }
    Ok(())
}

/// The gateway's TCP clients, each on its own thread (a silent one holds only its own), sharing
/// the gateway one request at a time; at most [`GATEWAY_CLIENTS`] at once, the next refused with
/// `ERROR:102`.
fn gateway_connections(
    listener: &std::net::TcpListener,
    gw: &std::sync::Arc<std::sync::Mutex<crate::gateway::Gateway>>,
) {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let active = std::sync::Arc::new(AtomicUsize::new(0));
    for stream in listener.incoming() {
        let Ok(mut stream) = stream else { continue };
        if active.load(Ordering::Relaxed) >= GATEWAY_CLIENTS {
            let _ = writeln!(
                stream,
                "ERROR:102 #Request not processed due to internal state (too many clients)"
            );
            continue;
        }
        let Ok(reader) = stream.try_clone() else {
            continue;
        };
        let (gw, mine) = (std::sync::Arc::clone(gw), std::sync::Arc::clone(&active));
        active.fetch_add(1, Ordering::Relaxed);
        let spawned = std::thread::Builder::new()
            .name("gateway-client".into())
            .spawn(move || {
                let mut writer = stream;
                let _ = crate::gateway::serve(&gw, std::io::BufReader::new(reader), &mut writer);
                mine.fetch_sub(1, Ordering::Relaxed);
            });
        if spawned.is_err() {
            // No thread for it: the client's connection is dropped with the closure.
            active.fetch_sub(1, Ordering::Relaxed);
        }
    }
}

/// Gateway clients served at once at most.
pub const GATEWAY_CLIENTS: usize = 16;
