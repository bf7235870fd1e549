//! Captures of a process's links in pcapng, the format Wireshark, tshark and dumpcap read and write
//! (draft-tuexen-opsawg-pcapng-05).
//!
//! - [`pcapng`]: the blocks, written and read with no I/O of their own: the Section Header Block,
//!   an Interface Description Block per link, an Enhanced Packet Block per frame with its time and
//!   direction; [`pcapng::Reader`] reads them back from any file of the format, in bounded memory.
//! - [`Capture`]: one capture file that the links of a process share ([`Capture::interface`] gives
//!   each link its interface in it): `can-link` wraps a CAN bus in one (SocketCAN frames,
//!   [`pcapng::LINKTYPE_CAN_SOCKETCAN`]), `ecat-link`'s raw socket writes its EtherCAT frames to one
//!   (whole Ethernet frames, [`pcapng::LINKTYPE_ETHERNET`]).
//!
//! The frames' blocks are held until the link waits ([`Capture::flush`]) and then written in one
//! write: the file always ends after a whole block, and holds every frame up to the last wait of
//! the process however it ends (a crash, a kill), every frame when it ends by returning.
//!
//! ```
//! use std::time::{Duration, SystemTime, UNIX_EPOCH};
//! use link_capture::pcapng::{Direction, Reader, LINKTYPE_ETHERNET};
//! use link_capture::Capture;
//!
//! let (capture, file) = Capture::in_memory("example");
//! let eth0 = capture.interface("eth0", LINKTYPE_ETHERNET);
//! let at = UNIX_EPOCH + Duration::from_secs(1_700_000_000);
//! eth0.record(at, Direction::Outbound, &[0xFF; 60]);
//! capture.flush();
//!
//! let bytes = file.lock().unwrap().clone();
//! let mut reader = Reader::new(&bytes[..]);
//! let packet = reader.next_packet().unwrap().unwrap();
//! assert_eq!((packet.link_type, packet.data.len()), (LINKTYPE_ETHERNET, 60));
//! assert_eq!((packet.time, packet.direction), (Some(at), Some(Direction::Outbound)));
//! ```
#![deny(missing_docs)]

mod file;
pub mod pcapng;

pub use file::{Capture, CaptureError, Interface, PENDING};
