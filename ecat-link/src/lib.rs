//! The EtherCAT link, apart from any device: an AF_PACKET raw socket on one interface for EtherCAT
//! frames ([`raw::RawSocket`]), one frame at a time or several in one system call
//! ([`raw::Batch`]: recvmmsg(2), sendmmsg(2)). The emulator (`ethercat-slave`) answers on it;
//! the commissioning tool (`sdo-tool`) and the tests' masters send on it; with
//! [`raw::RawSocket::capture_to`] its frames go to a pcapng capture too (`link-capture`). Linux
//! only; root (or CAP_NET_RAW) to open.
//!
//! ```no_run
//! use ecat_link::raw::RawSocket;
//! use std::time::Duration;
//!
//! let socket = RawSocket::open("ecat0")?;
//! let mut buf = [0u8; 1514];
//! if socket.wait(Duration::from_millis(10))? {
//!     if let Some(n) = socket.recv(&mut buf)? {
//!         println!("{n} bytes of EtherCAT");
//!     }
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]

pub mod raw;

/// The EtherType of EtherCAT frames (ETG.1000.4 §5.1).
pub const ETHERTYPE: u16 = 0x88A4;
