//! A bus inside one process: every [`Endpoint`] sees the frames of every other endpoint.

use std::sync::mpsc::{self, Receiver, SyncSender, TrySendError};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant, SystemTime};

use super::{BusError, BusEvent, CanBus};
use crate::frame::CanFrame;

/// Frames an endpoint holds unread at most; more are dropped, as a CAN controller's receive queue
/// overflows.
pub const QUEUE_CAPACITY: usize = 8192;

#[derive(Default)]
struct Shared {
    next_id: u64,
    members: Vec<(u64, SyncSender<super::Queued>)>,
}

/// The bus. Clone it to hand it around; every clone is the same bus.
#[derive(Clone, Default)]
pub struct InProcessBus {
    shared: Arc<Mutex<Shared>>,
}

impl InProcessBus {
    /// An empty bus.
    pub fn new() -> InProcessBus {
        InProcessBus::default()
    }

    /// A new participant.
    pub fn endpoint(&self) -> Endpoint {
        let (tx, rx) = mpsc::sync_channel(QUEUE_CAPACITY);
        let mut shared = self.shared.lock().unwrap_or_else(PoisonError::into_inner);
        let id = shared.next_id;
        shared.next_id += 1;
        shared.members.push((id, tx));
        Endpoint {
            id,
            rx,
            bus: self.clone(),
        }
    }

    /// Delivers `frame` to every endpoint but `from`.
    fn broadcast(&self, from: u64, frame: &CanFrame) {
        let (at, sent) = (SystemTime::now(), Instant::now());
        let mut shared = self.shared.lock().unwrap_or_else(PoisonError::into_inner);
        shared.members.retain(|(id, tx)| {
            if *id == from {
                return true;
            }
            !matches!(
                tx.try_send((*frame, at, sent)),
                Err(TrySendError::Disconnected(_))
            )
        });
    }
}

/// One participant of an [`InProcessBus`].
pub struct Endpoint {
    id: u64,
    rx: Receiver<super::Queued>,
    bus: InProcessBus,
}

impl Endpoint {
    /// The next frame already received, without waiting.
    pub fn try_recv(&mut self) -> Option<CanFrame> {
        self.rx.try_recv().ok().map(|(f, _, _)| f)
    }
}

impl CanBus for Endpoint {
    fn send(&mut self, frame: &CanFrame) -> Result<(), BusError> {
        self.bus.broadcast(self.id, frame);
        Ok(())
    }

    fn recv(&mut self, timeout: Duration) -> Result<Option<BusEvent>, BusError> {
        super::recv_queued(&self.rx, timeout, || self.describe())
    }

    fn describe(&self) -> String {
        format!("in-process endpoint {}", self.id)
    }
}

impl Drop for Endpoint {
    fn drop(&mut self) {
        let mut shared = self
            .bus
            .shared
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        shared.members.retain(|(id, _)| *id != self.id);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_reach_every_other_endpoint_but_not_the_sender() {
        let bus = InProcessBus::new();
        let mut a = bus.endpoint();
        let mut b = bus.endpoint();
        let mut c = bus.endpoint();
        let f = CanFrame::new(0x701, &[0x7F]).unwrap();
        a.send(&f).unwrap();
        assert_eq!(b.try_recv(), Some(f));
        assert_eq!(c.try_recv(), Some(f));
        assert_eq!(a.try_recv(), None);
        drop(c);
        b.send(&f).unwrap();
        assert_eq!(a.try_recv(), Some(f));
        assert!(matches!(a.recv(Duration::from_millis(1)), Ok(None)));
    }
}
