//! The SDO protocol of CiA 301 §7.2.4 as sans-IO state machines: frames in, frames out, time passed in.
//!
//! - [`frame`]: the wire formats ([`ClientFrame`], [`ServerFrame`], [`BlockSegment`]) and the block
//!   transfer CRC.
//! - [`client`]: the SDO client ([`SdoClient`]): expedited, segmented and block transfers with
//!   fall-back, timeouts and bounded memory.
pub mod client;
pub mod frame;

pub use client::{
    ClientConfig, ClientEvent, DownloadData, DownloadSource, ReadSource, SdoClient, SdoClientError,
    UploadSink, WriteSink,
};
pub use frame::{
    BlockSegment, ClientFrame, Crc16, ExpeditedData, Frame, Multiplexer, SegmentData, ServerFrame,
};
