//! The SDO protocol of CiA 301 §7.2.4 as sans-IO state machines: frames in, frames out, time passed in.
//!
//! - [`frame`]: the wire formats ([`ClientFrame`], [`ServerFrame`], [`BlockSegment`]) and the block
//!   transfer CRC.
//! - [`store`]: what a server reads and writes ([`ObjectStore`], implemented for the
//!   [`Dictionary`](crate::Dictionary)).
//! - [`server`]: the SDO server ([`SdoServer`]).
pub mod frame;
pub mod server;
pub mod store;

pub use frame::{
    BlockSegment, ClientFrame, Crc16, ExpeditedData, Frame, Multiplexer, SegmentData, ServerFrame,
};
pub use server::{SdoServer, ServerConfig, ServerEvent};
pub use store::{DownloadCapacity, ObjectStore};
