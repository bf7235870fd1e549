//! The SDO protocol of CiA 301 §7.2.4 as sans-IO state machines: frames in, frames out, time passed in.
//!
//! - [`frame`]: the wire formats ([`ClientFrame`], [`ServerFrame`], [`BlockSegment`]) and the block
//!   transfer CRC.
//! - [`store`]: what a server reads and writes ([`ObjectStore`], implemented for the
//!   [`Dictionary`](crate::Dictionary)).
//! - [`server`]: the SDO server ([`SdoServer`]).
//! - [`client`]: the SDO client ([`SdoClient`]): expedited, segmented and block transfers with
//!   fall-back, timeouts and bounded memory.
//! - [`session`]: typed, blocking reads and writes ([`SdoSession`]) on top of the client and a small
//!   [`SdoTransport`] trait.
pub mod client;
pub mod frame;
pub mod server;
pub mod session;
pub mod store;

pub use client::{
    ClientConfig, ClientEvent, DownloadData, DownloadSource, ReadSource, SdoClient, SdoClientError,
    UploadSink, WriteSink,
};
pub use frame::{
    Address, BlockSegment, ClientFrame, Crc16, ExpeditedData, Frame, SegmentData, ServerFrame,
};
pub use server::{SdoServer, ServerConfig, ServerEvent};
pub use session::{SdoSession, SdoTransport, SessionError};
pub use store::{DownloadCapacity, ObjectStore};

/// "save" as a little-endian UNSIGNED32: what a client writes to 0x1010 to store parameters
/// (CiA 301 §7.5.2.13).
pub const SAVE_SIGNATURE: u32 = 0x6576_6173;
/// "load" as a little-endian UNSIGNED32: what a client writes to 0x1011 to restore default
/// parameters (CiA 301 §7.5.2.14).
pub const LOAD_SIGNATURE: u32 = 0x6461_6F6C;
