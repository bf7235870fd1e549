//! The `smd-ethercat` command line: its arguments and what it does with them. `main` only parses and
//! calls [`run`].

use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

use crate::smd::binding::Device;
use clap::Parser;

use crate::runtime::{self, Options, RuntimeError, Stats};

/// Virtual AMCI SMD23K-B / SMD24K units on an EtherCAT segment.
///
/// Answers every EtherCAT frame (EtherType 0x88A4) that arrives on INTERFACE as a chain of N units
/// would: register and logical datagrams with their working counters, the SII EEPROM generated from
/// the units' ESI (serial numbers 1…N), the AL states with their checks, CoE SDO access to the units'
/// dictionary, Distributed Clocks, and the process data of the indexer model. Any EtherCAT master
/// (TwinCAT, SOEM/pysoem, ethercrab, IgH) on the other end of the link finds, configures and drives
/// them.
///
/// Needs CAP_NET_RAW (root). A veth pair gives a master and the units a link on one machine:
///
///   ip link add ecat0 type veth peer name ecat1 && ip link set ecat0 up && ip link set ecat1 up
///
///   smd-ethercat ecat1 --units 2   (and the master on ecat0)
#[derive(Debug, Clone, Parser)]
#[command(name = "smd-ethercat", version, verbatim_doc_comment)]
pub struct Args {
    /// The network interface the master's frames arrive on.
    #[arg(value_name = "INTERFACE")]
    pub interface: String,

    /// How many units in the chain, 1 to 128.
    #[arg(long, short = 'n', value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..=128))]
    pub units: u16,

    /// Which unit.
    #[arg(long, value_enum, default_value_t = Device::Smd23kB)]
    pub device: Device,

    /// The units' process-data cycle in µs (how often the model runs and the inputs refresh), 250 to
    /// 10000.
    #[arg(long, value_name = "US", default_value_t = 1000, value_parser = clap::value_parser!(u64).range(250..=10_000))]
    pub cycle_us: u64,

    /// After answering a frame, keep polling the interface for this many µs before sleeping (0 to
    /// 1000): a faster answer to a master that sends its next frame at once, for CPU time.
    #[arg(long, value_name = "US", default_value_t = 0, value_parser = clap::value_parser!(u64).range(0..=1000))]
    pub busy_poll_us: u64,

    /// Writes every frame the units receive and answer to FILE, a pcapng capture Wireshark and
    /// tshark read (LINKTYPE_ETHERNET, the interface's name, nanosecond times, each frame's
    /// direction); written whenever the units wait, whole when they stop.
    #[arg(long, value_name = "FILE")]
    pub capture: Option<std::path::PathBuf>,
}

/// Why `smd-ethercat` stopped with an error.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CliError {
    /// The emulator.
    #[error(transparent)]
    Runtime(#[from] RuntimeError),
    /// Ctrl-C could not be hooked.
    #[error("cannot handle Ctrl-C: {0}")]
    Signal(#[from] cli_support::SignalError),
    /// The capture file cannot be created.
    #[error("--capture {0}")]
    Capture(#[from] link_capture::CaptureError),
}

/// Runs until Ctrl-C (or `stop`, when given, is set); prints `ready` lines on stdout when on line.
pub fn run(args: &Args, stop: Option<Arc<AtomicBool>>) -> Result<Stats, CliError> {
    let capture = args
        .capture
        .as_deref()
        .map(|path| {
            link_capture::Capture::create(path, concat!("smd-ethercat ", env!("CARGO_PKG_VERSION")))
        })
        .transpose()?;
    let stop = cli_support::stop_flag(stop)?;
    let options = Options {
        interface: args.interface.clone(),
        device: args.device,
        units: usize::from(args.units),
        cycle: Duration::from_micros(args.cycle_us),
        busy_poll: Duration::from_micros(args.busy_poll_us),
        capture,
    };
    let stats = runtime::run(&options, &stop, || {
        println!(
            "{} × {} on {} (serial numbers 1…{}); Ctrl-C stops",
            options.units,
            options.device.order_code(),
            options.interface,
            options.units
        );
    })?;
    Ok(stats)
}
