//! A SocketCAN interface (`can0`, `vcan0`, …) through the `socketcan` crate: classic CAN frames, error
//! frames reported as [`BusEvent::Error`] (the bus goes on).

use std::io::ErrorKind;
use std::time::{Duration, Instant, SystemTime};

use embedded_can::Frame as _;
use socketcan::{CanSocket, Socket, SocketOptions};

use super::{BusError, BusEvent, CanBus, DropCount};
use crate::frame::CanFrame;

/// An open SocketCAN interface.
pub struct SocketCanBus {
    socket: CanSocket,
    name: String,
    /// Frames dropped at a full transmit queue.
    dropped: DropCount,
}

impl SocketCanBus {
    /// Opens `iface` for classic CAN frames, with error frames of every class reported.
    pub fn open(iface: &str) -> Result<SocketCanBus, BusError> {
        let name = format!("socketcan:{iface}");
        let open_error = |source| BusError::Open {
            what: name.clone(),
            source,
        };
        let socket = CanSocket::open(iface).map_err(open_error)?;
        socket.set_error_filter_accept_all().map_err(open_error)?;
        // Frames this socket sends are not delivered back to it (CanBus contract); CAN_RAW's
        // default already is "no own messages", said here once more for clarity.
        socket.set_recv_own_msgs(false).map_err(open_error)?;
        Ok(SocketCanBus {
            socket,
            name,
            dropped: DropCount::default(),
        })
    }
}

fn to_socketcan(frame: &CanFrame) -> Option<socketcan::CanFrame> {
    let id: embedded_can::Id = embedded_can::Frame::id(frame);
    if frame.is_rtr() {
        socketcan::CanFrame::new_remote(id, frame.len())
    } else {
        socketcan::CanFrame::new(id, frame.data())
    }
}

fn from_socketcan(frame: &socketcan::CanFrame) -> Option<CanFrame> {
    let raw = match frame.id() {
        embedded_can::Id::Standard(s) => (u32::from(s.as_raw()), false),
        embedded_can::Id::Extended(e) => (e.as_raw(), true),
    };
    if frame.is_remote_frame() {
        CanFrame::new_remote_frame(raw.0, raw.1, frame.dlc().min(8) as u8)
    } else if raw.1 {
        CanFrame::new_extended(raw.0, frame.data())
    } else {
        CanFrame::new(raw.0 as u16, frame.data())
    }
}

impl CanBus for SocketCanBus {
    fn send(&mut self, frame: &CanFrame) -> Result<(), BusError> {
        let f = to_socketcan(frame).ok_or_else(|| BusError::Protocol {
            what: self.name.clone(),
            detail: format!("{frame} is not a classic CAN frame"),
        })?;
        loop {
            let Err(e) = self.socket.write_frame(&f) else {
                return Ok(());
            };
            match failed_send(&e) {
                FailedSend::Again => continue,
                FailedSend::Dropped => {
                    if let Some(n) = self.dropped.add() {
                        tracing::warn!(bus = %self.name, dropped = n, "transmit queue full, {frame} dropped");
                    }
                    return Ok(());
                }
                FailedSend::Fatal => {
                    return Err(BusError::Io {
                        what: self.name.clone(),
                        source: e,
                    })
                }
            }
        }
    }

    fn recv(&mut self, timeout: Duration) -> Result<Option<BusEvent>, BusError> {
        match self.socket.read_frame_timeout(poll_wait(timeout)) {
            Ok(socketcan::CanFrame::Error(e)) => {
                Ok(Some(BusEvent::Error(e.into_error().to_string())))
            }
            Ok(f) => Ok(from_socketcan(&f).map(|frame| BusEvent::Frame {
                frame,
                at: SystemTime::now(),
                received: Instant::now(),
            })),
            Err(e) if matches!(e.kind(), ErrorKind::TimedOut | ErrorKind::WouldBlock) => Ok(None),
            Err(e) if e.kind() == ErrorKind::Interrupted => Ok(None),
            Err(source) => Err(BusError::Io {
                what: self.name.clone(),
                source,
            }),
        }
    }

    fn describe(&self) -> String {
        self.name.clone()
    }
}

/// The wait to give poll(2), which counts whole milliseconds: `timeout` rounded up, so that a wait
/// shorter than a millisecond (a timer due soon) sleeps until it is due instead of polling at once,
/// over and over, until then.
fn poll_wait(timeout: Duration) -> Duration {
    let ms = timeout.as_nanos().div_ceil(1_000_000);
    Duration::from_millis(u64::try_from(ms).unwrap_or(u64::MAX))
}

/// What a failed write of a frame means.
#[derive(Debug, PartialEq, Eq)]
enum FailedSend {
    /// Interrupted by a signal: write again.
    Again,
    /// A full transmit queue (ENOBUFS): the frame is dropped, as a controller that never wins
    /// arbitration drops it; reported (at powers of two), not fatal.
    Dropped,
    /// The interface failed (down, gone): the bus ends.
    Fatal,
}

fn failed_send(e: &std::io::Error) -> FailedSend {
    if e.kind() == ErrorKind::Interrupted {
        FailedSend::Again
    } else if e.raw_os_error() == Some(libc_enobufs()) {
        FailedSend::Dropped
    } else {
        FailedSend::Fatal
    }
}

/// ENOBUFS on Linux.
const fn libc_enobufs() -> i32 {
    105
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A signal writes again, a full transmit queue drops the frame, anything else ends the bus.
    #[test]
    fn failed_sends_are_retried_dropped_or_fatal() {
        use std::io::Error;
        assert_eq!(
            failed_send(&Error::from(ErrorKind::Interrupted)),
            FailedSend::Again
        );
        assert_eq!(
            failed_send(&Error::from_raw_os_error(105)),
            FailedSend::Dropped
        );
        for errno in [100, 19, 6, 104] {
            // ENETDOWN, ENODEV, ENXIO, ECONNRESET
            assert_eq!(
                failed_send(&Error::from_raw_os_error(errno)),
                FailedSend::Fatal,
                "{errno}"
            );
        }
        assert_eq!(
            failed_send(&Error::from(ErrorKind::WouldBlock)),
            FailedSend::Fatal
        );
    }

    /// Waits round up to whole milliseconds; zero stays zero.
    #[test]
    fn poll_waits_round_up_to_whole_milliseconds() {
        let us = Duration::from_micros;
        for (wait, want) in [
            (us(0), 0),
            (Duration::from_nanos(1), 1),
            (us(999), 1),
            (us(1000), 1),
            (us(1001), 2),
            (us(49_999), 50),
            (Duration::MAX, u64::MAX),
        ] {
            assert_eq!(poll_wait(wait), Duration::from_millis(want), "{wait:?}");
        }
    }

    #[test]
    fn frames_convert_both_ways() {
        for f in [
            CanFrame::new(0x605, &[0x40, 0x18, 0x10, 1, 0, 0, 0, 0]).unwrap(),
            CanFrame::new(0x000, &[]).unwrap(),
            CanFrame::new_extended(0x1ABC_DEF0, &[1, 2]).unwrap(),
            CanFrame::new_remote_frame(0x705, false, 1).unwrap(),
        ] {
            let s = to_socketcan(&f).unwrap();
            assert_eq!(from_socketcan(&s), Some(f));
        }
    }

    #[test]
    fn opening_a_missing_interface_names_it() {
        let Err(e) = SocketCanBus::open("nosuchcan9") else {
            panic!("a missing interface opened")
        };
        assert!(
            e.to_string()
                .starts_with("cannot open socketcan:nosuchcan9: "),
            "{e}"
        );
    }
}
