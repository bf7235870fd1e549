//! The SDO protocol of CiA 301 §7.2.4 as sans-IO state machines: frames in, frames out, time passed in.
//!
//! - [`frame`]: the wire formats ([`ClientFrame`], [`ServerFrame`], [`BlockSegment`]) and the block
//!   transfer CRC.
pub mod frame;

pub use frame::{
    BlockSegment, ClientFrame, Crc16, ExpeditedData, Frame, Multiplexer, SegmentData, ServerFrame,
};
