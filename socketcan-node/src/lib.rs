//! CANopen node runtime (NMT, heartbeat, SYNC, PDO, EMCY, SDO, storage) and CAN transports.
//!
//! - [`frame`]: classic CAN frames ([`CanFrame`], an `embedded_can::Frame`);
//! - [`transport`]: the [`CanBus`] trait and its back ends (SocketCAN, socketcand, in-process);
//! - [`node`]: the CiA 301 node as a sans-IO state machine over a dictionary and an application.
#![deny(missing_docs)]

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
pub use node::{Application, NmtState, Node, NodeConfig, NodeEvent};
pub use od;
pub use transport::{BusEvent, BusSpec, CanBus};
