//! CANopen node runtime (NMT, heartbeat, SYNC, PDO, EMCY, SDO, storage) on the CAN links of
//! `can-link` (re-exported as [`frame`] and [`transport`]).
//!
//! - [`node`]: the CiA 301 node as a sans-IO state machine over a dictionary and a device
//!   (`od::hook::Device`);
//! - [`generic`]: any CANopen description made ready to run as a node, with a CiA 402 drive behind
//!   its drive axes (`ds402::generic`);
//! - [`canopen_cli`]: any CANopen description as a node (`canopen-node`); [`x67`] and [`cli`]: the
//!   X67 node (`x67-node`); [`cli_common`]: what the two command lines share.
#![deny(missing_docs)]

pub mod canopen_cli;
pub mod cli;
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
