//! The node runs its device up to the instant of a write before it delivers the write: a timeout the
//! device asked for before that instant runs first; one due at that very instant runs after it, with
//! the node's own timers.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use od::abort::AbortCode;
use od::dict::{Address, Dictionary};
use od::hook::{Device, DeviceHook};
use od::object::{AccessType, Object, SubObject};
use od::types::DataType;
use od::value::Value;
use socketcan_node::{CanFrame, Node, NodeConfig};

/// A device owning 0x2000 that notes, in order, each timeout it ran and each write it took (in ms
/// from `t0`), with its next timeout at `due`.
#[derive(Clone)]
struct Noting {
    t0: Instant,
    due: Option<Instant>,
    log: Arc<Mutex<Vec<String>>>,
}

impl Noting {
    fn note(&self, what: &str, now: Instant) {
        let ms = (now - self.t0).as_millis();
        self.log.lock().unwrap().push(format!("{what} {ms}"));
    }
}

impl DeviceHook for Noting {
    fn owns(&self, index: u16) -> bool {
        index == 0x2000
    }
    fn read(&self, _: Address, _: &mut [u8; 8]) -> Option<usize> {
        None
    }
    fn write(&mut self, _: Address, _: &[u8], now: Instant) -> Result<(), AbortCode> {
        self.note("write", now);
        Ok(())
    }
}

impl Device for Noting {
    fn handle_timeout(&mut self, now: Instant) {
        if self.due.is_some_and(|t| t <= now) {
            self.note("timeout", now);
            self.due = None;
        }
    }
    fn poll_timeout(&self) -> Option<Instant> {
        self.due
    }
    fn reset(&mut self, _: Instant) {}
}

fn dictionary() -> Dictionary {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/io-device.eds");
    let (_, mut devices) = od::load::load(std::path::Path::new(path)).unwrap();
    let mut dict = devices.remove(0).dictionary;
    dict.insert(Object::var(
        0x2000,
        SubObject::new("Set-point", DataType::Unsigned8, AccessType::Rw)
            .with_default(Value::Uint(0)),
    ));
    dict
}

/// The log after an SDO download to 0x2000 at `write_ms` of a device due at `due_ms`, the node's
/// own timers run at `write_ms` right after the frame (as a runtime does).
fn run(due_ms: u64, write_ms: u64) -> Vec<String> {
    let t0 = Instant::now();
    let ms = |n: u64| t0 + Duration::from_millis(n);
    let log = Arc::new(Mutex::new(Vec::new()));
    let device = Noting {
        t0,
        due: None,
        log: Arc::clone(&log),
    };
    let mut node = Node::new(NodeConfig::new(5), dictionary(), device, t0).unwrap();
    node.start(t0);
    while node.poll_transmit().is_some() {}
    // The device asks for a timeout at `due_ms` (nothing was due before).
    node.app_mut().due = Some(ms(due_ms));
    let download = CanFrame::new(0x605, &[0x2F, 0x00, 0x20, 0x00, 7, 0, 0, 0]).unwrap();
    node.handle_frame(ms(write_ms), &download);
    node.handle_timeout(ms(write_ms));
    let answers: Vec<CanFrame> = std::iter::from_fn(|| node.poll_transmit()).collect();
    assert!(
        answers
            .iter()
            .any(|f| f.cob_id() == Some(0x585) && f.data() == [0x60, 0x00, 0x20, 0x00, 0, 0, 0, 0]),
        "{answers:?}"
    );
    let log = log.lock().unwrap().clone();
    log
}

#[test]
fn a_timeout_due_before_a_write_runs_before_it() {
    assert_eq!(run(10, 15), ["timeout 15", "write 15"]);
}

#[test]
fn a_timeout_due_at_the_write_s_instant_runs_after_it() {
    assert_eq!(run(15, 15), ["write 15", "timeout 15"]);
}

#[test]
fn a_timeout_due_after_a_write_waits_for_its_time() {
    assert_eq!(run(20, 15), ["write 15"]);
}
