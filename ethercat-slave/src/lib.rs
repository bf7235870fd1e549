//! An emulated EtherCAT slave controller (ESC), sans-IO: EtherCAT frames in, the same frames out with
//! every datagram processed as a chain of slaves processes it (ETG.1000.4).
//!
//! - [`frame`]: the EtherCAT frame and its datagrams (view + emit);
//! - [`esc`]: one slave's ESC memory (registers and process RAM), its addresses, and the datagram
//!   commands with their working-counter rules; [`esc::Chain`] passes a frame through several slaves.
//!
//! In it: the register commands, FMMU logical addressing (LRD/LWR/LRW, byte-granular), the EEPROM
//! interface reading an SII image (`od::sii`), the AL state machine with its SyncManager checks
//! ([`esc::al`]), SyncManager mailboxes and buffers and the watchdog ([`esc::sm`]), Distributed Clocks
//! ([`esc::dc`]); [`unit`](mod@unit) is a chain of ESCs with a device model and its CoE server behind each;
//! [`smd`] puts the SMD model behind each ESC; [`generic`] any ESI's device, with a CiA 402 drive
//! behind each drive axis; [`raw`] and [`runtime`]
//! answer real frames on a Linux interface; with the feature `cli` (on by default), `cli` is the
//! `smd-ethercat` command line, `node_cli` the `ethercat-node` one (`node_list` its `--list` of a
//! file's devices and their drive axes), and without it the crate has no command-line parser,
//! signal handler or log subscriber; `master` (with the feature `test-master`) is the master's side
//! the tests and benchmarks use.
#![deny(missing_docs)]

#[cfg(feature = "cli")]
pub mod cli;
pub mod esc;
pub mod foe;
pub mod frame;
pub mod generic;
#[cfg(feature = "test-master")]
pub mod master;
#[cfg(feature = "cli")]
pub mod node_cli;
#[cfg(feature = "cli")]
pub mod node_list;
pub use ecat_link::raw;
pub mod runtime;
pub mod smd;
pub mod unit;
