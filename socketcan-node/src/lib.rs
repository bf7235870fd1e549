//! CANopen node runtime (NMT, heartbeat, SYNC, PDO, EMCY, SDO, storage) and CAN transports.
//!
//! - [`frame`]: classic CAN frames ([`CanFrame`], an `embedded_can::Frame`);
//! - [`transport`]: the [`CanBus`] trait and its back ends (SocketCAN, socketcand, in-process).
#![deny(missing_docs)]

pub mod frame;
pub mod transport;

pub use frame::CanFrame;
pub use od;
pub use transport::{BusEvent, BusSpec, CanBus};
