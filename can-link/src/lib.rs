//! CAN links, apart from any device: the classic CAN frame ([`CanFrame`], an `embedded_can::Frame`)
//! and the [`CanBus`] trait with its back ends: SocketCAN ([`transport::SocketCanBus`]), a
//! socketcand client and server ([`transport::SocketcandClient`], [`transport::socketcand`]) and an
//! in-process bus ([`transport::InProcessBus`]); [`BusSpec`] names one on a command line
//! (`vcan0`, `socketcand://host:port/can0`, `inprocess`). The CANopen nodes (`socketcan-node`)
//! and the commissioning tool (`sdo-tool`) run on them; [`transport::Captured`] writes a bus's
//! frames to a pcapng capture (`link-capture`).
//!
//! ```
//! use can_link::{BusSpec, CanFrame};
//!
//! let spec: BusSpec = "socketcand://127.0.0.1:29536/vcan0".parse().unwrap();
//! assert!(matches!(spec, BusSpec::Socketcand { .. }));
//! let frame = CanFrame::new(0x601, &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]).unwrap();
//! assert_eq!(frame.cob_id(), Some(0x601));
//! ```
#![deny(missing_docs)]

pub mod frame;
pub mod transport;

pub use frame::{CanFrame, NotClassic};
pub use transport::{BusEvent, BusSpec, CanBus};
