//! CANopen node runtime (NMT, heartbeat, SYNC, PDO, EMCY, SDO, storage) and CAN transports.
//!
//! The runtime is built on the `od` dictionary; its services arrive with their own modules.
#![deny(missing_docs)]

pub use od;
