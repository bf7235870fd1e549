//! CANopen node runtime (NMT, heartbeat, SYNC, PDO, EMCY, SDO, storage) and CAN transports.
//!
//! - [`frame`]: classic CAN frames ([`CanFrame`], an `embedded_can::Frame`);
//! - [`transport`]: the [`CanBus`] trait and its back ends (SocketCAN, socketcand, in-process);
//! - [`node`]: the CiA 301 node as a sans-IO state machine over a dictionary and an application;
//! - [`generic`]: any CANopen description as a node, with a CiA 402 drive behind its drive axes
//!   (`canopen-node`, [`canopen_cli`]); [`x67`] and [`cli`]: the X67 node (`x67-node`).
#![deny(missing_docs)]

pub mod canopen_cli;
pub mod cli;
pub mod frame;
pub mod node;
pub mod runtime;
pub mod sim;
#[cfg(feature = "test-util")]
pub mod test_util;
pub mod transport;
pub mod x67;

pub use frame::CanFrame;
pub use node::{Device, NmtState, Node, NodeConfig, NodeEvent};
pub use od;
pub use transport::{BusEvent, BusSpec, CanBus};
