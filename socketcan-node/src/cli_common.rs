//! What the `canopen-node` and `x67-node` command lines share: the capture file of `--capture`,
//! opening the bus they were given (or the default one), and the start-up hint how to reach the
//! nodes on it.

use std::path::Path;

pub use link_capture::{Capture, CaptureError};

use crate::transport::{self, BusError, BusSpec, CanBus, Captured};

/// The capture file of `--capture`, created (emptied) with its header, `application` (the
/// binary's name and version) in it; `None` without the option.
pub fn capture(path: Option<&Path>, application: &str) -> Result<Option<Capture>, CaptureError> {
    path.map(|p| Capture::create(p, application)).transpose()
}

/// Opens `spec`, or without one the default bus ([`transport::open_default`]: SocketCAN vcan0
/// where this machine has it, else a socketcand server on 127.0.0.1:29536), with every frame it
/// sends and receives written to `capture` where there is one (the interface named by
/// [`BusSpec::interface_name`]). The spec returned names the bus as opened: a socketcand server's
/// address with the port the system chose for port 0.
pub fn open_bus(
    spec: Option<&BusSpec>,
    capture: Option<&Capture>,
) -> Result<(BusSpec, Box<dyn CanBus>), BusError> {
    let (mut spec, bus): (BusSpec, Box<dyn CanBus>) = match spec {
        Some(spec) => (spec.clone(), transport::open(spec)?),
        None => transport::open_default()?,
    };
    // Port 0 asks the system for a free port: the hint names the one it chose.
    if let (BusSpec::SocketcandListen { addr }, Some(bound)) = (&mut spec, bus.listen_addr()) {
        *addr = bound;
    }
    let bus: Box<dyn CanBus> = match capture {
        Some(c) => Box::new(Captured::new(bus, c, &spec.interface_name())),
        None => bus,
    };
    Ok((spec, bus))
}

/// How to reach a node on `spec`, for the start-up message.
pub fn connect_hint(spec: &BusSpec) -> String {
    match spec {
        BusSpec::SocketcandListen { addr } => {
            let host = addr.ip();
            let port = addr.port();
            format!(
                "listening as a socketcand server on {addr} (any channel name is accepted); connect with\n  \
                 python-can:       can.Bus(interface=\"socketcand\", host=\"{host}\", port={port}, channel=\"can0\")\n  \
                 python-canopen:   network.connect(interface=\"socketcand\", host=\"{host}\", port={port}, channel=\"can0\")\n  \
                 this project:     --bus socketcand://{host}:{port}/can0"
            )
        }
        BusSpec::SocketCan { iface } => format!(
            "on SocketCAN {iface}; watch it with `candump {iface}`, reach it with --bus socketcan:{iface}"
        ),
        BusSpec::Socketcand { .. } => format!("joined the socketcand bus {spec}"),
        _ => format!("on {spec}"),
    }
}
