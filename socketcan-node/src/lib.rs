//! CANopen node runtime (NMT, heartbeat, SYNC, PDO, EMCY, SDO, storage) on the CAN links of
//! `can-link` (re-exported as [`frame`] and [`transport`]).
//!
//! - [`node`]: the CiA 301 node as a sans-IO state machine over a dictionary and a device
//!   (`od::hook::Device`);
//! - [`generic`]: any CANopen description made ready to run as a node, with a CiA 402 drive behind
//!   its drive axes (`ds402::generic`); [`x67`]: the X67 bus controller with its modules;
//! - with the feature `cli` (on by default), the command lines: `canopen_cli` runs descriptions as
//!   nodes (`canopen-node`), `cli` the X67 node (`x67-node`), `cli_common` what the two share.
//!   Without it the crate has no command-line parser, signal handler or log subscriber.
#![deny(missing_docs)]

#[cfg(feature = "cli")]
pub mod canopen_cli;
#[cfg(feature = "cli")]
pub mod cli;
#[cfg(feature = "cli")]
pub mod cli_common;
pub mod generic;
pub mod node;
pub mod runtime;
pub mod sim;
#[cfg(feature = "test-util")]
pub mod test_util;
pub mod x67;

pub use can_link::{frame, transport, BusEvent, BusSpec, CanBus, CanFrame};
pub use node::{Device, NmtState, Node, NodeConfig, NodeEvent};
pub use od;
