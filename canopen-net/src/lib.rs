//! CiA 302 network commissioning, sans-IO: a bus description (the master, its slaves and what each
//! is to be configured with) read from YAML, and what a CANopen manager downloads from it: each
//! slave's concise DCF (CiA 302-3 0x1F22) and the master's own DCF, as Lely's `dcfgen` writes them.
//!
//! - [`concise`]: the concise DCF format, encoded and decoded.
//! - [`bus`]: the bus description and its readers (dcfgen's YAML, ros2_canopen's `bus.yml`); the
//!   module's documentation lists every key.
//! - [`generate`]: the files for a bus, given the slaves' descriptions (read by the caller with
//!   `od`), and [`check`]: what is wrong with a bus description, all at once.
//! - [`lint`]: the strict reading of a slave's EDS or DCF dcfgen makes (`-S` skips it).
//! - [`boot`]: the network manager (CiA 302-2): boots, starts and supervises the slaves of a bus
//!   description and explains each failure with its CiA 302-2 error status.
//! - [`lss`]: the LSS master (CiA 305): node-IDs and bit timing set by LSS address, and Fastscan
//!   to find the nodes that have no node-ID.
//! - [`yaml`]: the YAML tree with the line of every node, as PyYAML reads scalars.
#![deny(missing_docs)]
#![warn(unreachable_pub)]

pub mod boot;
pub mod bus;
mod check;
pub mod concise;
mod file;
mod gen;
pub mod lint;
mod lint_values;
pub mod lss;
mod master;
mod master_dcf;
mod pdo;
mod slave;
pub mod yaml;

pub use bus::{Bus, NetError, Number, Options};
pub use check::check;
pub use file::{IdentityKeys, SlaveFile};
pub use gen::{expand_vars, generate, GenOptions, Generated};
pub use master::Master;
pub use slave::{Mapped, Pdo, Slave};
