//! A bus whose frames are also written to a pcapng capture, in the manner of smoltcp's `phy`
//! tracer: [`Captured`] wraps any [`CanBus`] and records each frame it sends (after the send) and
//! each frame it receives (at the time the link gives it), as `LINKTYPE_CAN_SOCKETCAN` frames
//! ([`CanFrame::socketcan_bytes`]) of one interface of the capture. What the bus reports as an
//! error ([`BusEvent::Error`]) is not a frame and is not recorded. The records reach the file
//! before each wait for the next event ([`CanBus::recv`]) and when the bus is dropped.

use std::time::{Duration, SystemTime};

use link_capture::pcapng::{Direction, LINKTYPE_CAN_SOCKETCAN};
use link_capture::{Capture, Interface};

use super::{BusError, BusEvent, CanBus};
use crate::frame::CanFrame;

/// `bus`, its frames written to a capture.
pub struct Captured<B> {
    bus: B,
    interface: Interface,
}

impl<B: CanBus> Captured<B> {
    /// `bus` with its frames written to `capture` as interface `name` (a bus's
    /// [`BusSpec::interface_name`](super::BusSpec::interface_name), e.g. `vcan0`).
    pub fn new(bus: B, capture: &Capture, name: &str) -> Captured<B> {
        Captured {
            bus,
            interface: capture.interface(name, LINKTYPE_CAN_SOCKETCAN),
        }
    }
}

impl<B> Drop for Captured<B> {
    fn drop(&mut self) {
        self.interface.flush();
    }
}

impl<B: CanBus> CanBus for Captured<B> {
    fn send(&mut self, frame: &CanFrame) -> Result<(), BusError> {
        self.bus.send(frame)?;
        self.interface.record(
            SystemTime::now(),
            Direction::Outbound,
            &frame.socketcan_bytes(),
        );
        Ok(())
    }

    fn recv(&mut self, timeout: Duration) -> Result<Option<BusEvent>, BusError> {
        // What was recorded since the last wait reaches the file before this one.
        self.interface.flush();
        let event = self.bus.recv(timeout)?;
        if let Some(BusEvent::Frame { frame, at, .. }) = &event {
            self.interface
                .record(*at, Direction::Inbound, &frame.socketcan_bytes());
        }
        Ok(event)
    }

    fn describe(&self) -> String {
        self.bus.describe()
    }

    fn listen_addr(&self) -> Option<std::net::SocketAddr> {
        self.bus.listen_addr()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transport::InProcessBus;
    use link_capture::pcapng::Reader;

    /// A frame sent and one received are in the capture, in order, each with its direction; the
    /// received one at the time the link gave it. What is recorded reaches the file at the next
    /// wait for an event, or when the bus is dropped.
    #[test]
    fn sent_and_received_frames_are_captured() {
        let (capture, file) = Capture::in_memory("test");
        let bus = InProcessBus::new();
        let mut ours = Captured::new(bus.endpoint(), &capture, "inprocess");
        let mut theirs = bus.endpoint();
        assert!(matches!(ours.recv(Duration::ZERO), Ok(None)));
        // The Section Header Block (40 bytes with "test") and the interface's (48 with
        // "inprocess").
        let header = file.lock().unwrap().len();
        assert_eq!(header, 88);
        let before = SystemTime::now();
        let request = CanFrame::new(0x605, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]).unwrap();
        ours.send(&request).unwrap();
        assert_eq!(file.lock().unwrap().len(), header, "held until the wait");
        let answer = CanFrame::new(0x585, &[0x43, 0x18, 0x10, 0x01, 0xC1, 0x0A, 0, 0]).unwrap();
        theirs.send(&answer).unwrap();
        let Some(BusEvent::Frame { frame, at, .. }) = ours.recv(Duration::from_secs(5)).unwrap()
        else {
            panic!("no frame")
        };
        assert_eq!(frame, answer);
        assert_eq!(file.lock().unwrap().len(), header + 60);
        assert_eq!(ours.describe(), "in-process endpoint 0");
        assert_eq!(ours.listen_addr(), None);
        drop(ours);
        assert_eq!(file.lock().unwrap().len(), header + 120);
        let bytes = file.lock().unwrap().clone();
        let mut r = Reader::new(&bytes[..]);
        let p = r.next_packet().unwrap().unwrap();
        assert_eq!(p.data, request.socketcan_bytes());
        assert_eq!(p.direction, Some(Direction::Outbound));
        assert!(p.time.unwrap() >= before);
        let p = r.next_packet().unwrap().unwrap();
        assert_eq!(p.data, answer.socketcan_bytes());
        assert_eq!((p.direction, p.time), (Some(Direction::Inbound), Some(at)));
        assert!(r.next_packet().unwrap().is_none());
        assert_eq!(r.interfaces_seen()[0].name.as_deref(), Some("inprocess"));
        assert_eq!(r.interfaces_seen()[0].link_type, 227);
        drop(theirs);
    }

    /// A listening bus keeps its address when captured.
    #[test]
    fn a_listening_bus_keeps_its_address() {
        let (capture, _) = Capture::in_memory("");
        let server =
            crate::transport::SocketcandServer::bind("127.0.0.1:0".parse().unwrap()).unwrap();
        let addr = server.local_addr();
        let captured = Captured::new(server, &capture, "socketcand-listen");
        assert_eq!(captured.listen_addr(), Some(addr));
        assert_eq!(captured.describe(), format!("socketcand-listen:{addr}"));
    }

    /// A bus that refuses a frame: the error is the bus's, and nothing is recorded.
    #[test]
    fn a_refused_send_is_not_recorded() {
        struct Refuses;
        impl CanBus for Refuses {
            fn send(&mut self, _: &CanFrame) -> Result<(), BusError> {
                Err(BusError::Closed("refuses".into()))
            }
            fn recv(&mut self, _: Duration) -> Result<Option<BusEvent>, BusError> {
                Ok(Some(BusEvent::Error("bus off".into())))
            }
            fn describe(&self) -> String {
                "refuses".into()
            }
        }
        let (capture, file) = Capture::in_memory("");
        let mut bus = Captured::new(Refuses, &capture, "x");
        let len = file.lock().unwrap().len();
        assert!(bus.send(&CanFrame::new(1, &[]).unwrap()).is_err());
        assert_eq!(
            bus.recv(Duration::ZERO).unwrap(),
            Some(BusEvent::Error("bus off".into()))
        );
        assert_eq!(file.lock().unwrap().len(), len);
    }
}
