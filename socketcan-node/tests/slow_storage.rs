//! The runtime with a slow disk: "save" (0x1010) is written on the storage's own thread, so a write
//! that takes 60 ms (a write and its fsync on a slow disk) delays only the answer that confirms it,
//! never the heartbeat.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant, SystemTime};

use socketcan_node::node::storage::{MemoryStorage, ParameterStorage};
use socketcan_node::runtime::{self, Station};
use socketcan_node::transport::{BusEvent, CanBus, InProcessBus};
use socketcan_node::x67::{self, BusController};
use socketcan_node::{CanFrame, Node, NodeConfig};

/// A storage whose every write takes `delay`, counting the writes.
struct SlowDisk {
    inner: MemoryStorage,
    delay: Duration,
    writes: Arc<AtomicUsize>,
}

impl ParameterStorage for SlowDisk {
    fn load(&mut self) -> std::io::Result<Option<Vec<u8>>> {
        self.inner.load()
    }
    fn save(&mut self, data: &[u8]) -> std::io::Result<()> {
        std::thread::sleep(self.delay);
        self.writes.fetch_add(1, Ordering::SeqCst);
        self.inner.save(data)
    }
    fn clear(&mut self) -> std::io::Result<()> {
        std::thread::sleep(self.delay);
        self.inner.clear()
    }
}

#[test]
fn heartbeats_keep_their_period_while_a_slow_disk_saves() {
    const SAVES: usize = 40;
    let bus = InProcessBus::new();
    let mut master = bus.endpoint();
    let mut node_end = bus.endpoint();
    let writes = Arc::new(AtomicUsize::new(0));
    let now = Instant::now();
    let dict = x67::dictionary(1).unwrap();
    let app = BusController::new(&dict, 1, x67::DEFAULT_X2X_CYCLE, now).unwrap();
    let config = NodeConfig {
        heartbeat_ms: Some(100),
        ..NodeConfig::new(5)
    };
    let node = Node::new(config, dict, app, now).unwrap();
    let storage = SlowDisk {
        inner: MemoryStorage::default(),
        delay: Duration::from_millis(60),
        writes: Arc::clone(&writes),
    };
    let stop = Arc::new(AtomicBool::new(false));
    let stop_node = Arc::clone(&stop);
    let (tell, node_thread) = std::sync::mpsc::channel();
    let runner = std::thread::spawn(move || {
        // The node's thread scheduled first on a busy machine, as a node with a processor of its
        // own (the storage thread it starts inherits this).
        testkit::favour_this_thread();
        tell.send(testkit::sched::this_thread()).unwrap();
        let mut stations = vec![Station::new(node, Box::new(storage))];
        runtime::run(&mut stations, &mut node_end, &stop_node).unwrap();
    });
    // The time the machine keeps the node's thread from a processor: a beat late by that much is
    // the machine's, not the node's.
    let held_watch = testkit::sched::watch(vec![node_thread.recv().unwrap()], Arc::clone(&stop));
    let save = CanFrame::new(0x605, &[0x23, 0x10, 0x10, 0x01, b's', b'a', b'v', b'e']).unwrap();
    let saved = CanFrame::new(0x585, &[0x60, 0x10, 0x10, 0x01, 0, 0, 0, 0]).unwrap();
    let mut beats: Vec<SystemTime> = Vec::new();
    let mut answers = 0;
    let mut last_save = Instant::now();
    let deadline = Instant::now() + Duration::from_secs(60);
    // "save" again as soon as the last one is answered, SAVES times.
    master.send(&save).unwrap();
    while answers < SAVES {
        assert!(
            Instant::now() < deadline,
            "{answers} of {SAVES} saves answered in 60 s"
        );
        let Some(BusEvent::Frame { frame, at, .. }) =
            master.recv(Duration::from_millis(50)).unwrap()
        else {
            continue;
        };
        if frame == saved {
            // The answer confirms the write: it comes after the storage has it.
            answers += 1;
            assert_eq!(writes.load(Ordering::SeqCst), answers);
            assert!(last_save.elapsed() >= Duration::from_millis(60));
            last_save = Instant::now();
            if answers < SAVES {
                master.send(&save).unwrap();
            }
        } else if frame.cob_id() == Some(0x705) && frame.data() == [0x7F] {
            beats.push(at);
        }
    }
    stop.store(true, Ordering::SeqCst);
    runner.join().unwrap();
    let held = held_watch.join().unwrap();
    // 40 saves of 60 ms each take at least 2.4 s: at least 23 beats, none more than 10 ms later than
    // its instant on the 100 ms grid of the first (none leaves early: the grid is anchored on the
    // beat earliest against it), once the time the machine held the node's thread from a processor
    // between the instant and the beat is taken off.
    assert!(beats.len() >= 23, "{} heartbeats", beats.len());
    let offsets: Vec<f64> = beats
        .iter()
        .map(|t| t.duration_since(beats[0]).unwrap().as_secs_f64())
        .map(|t| t - (t / 0.1).round() * 0.1)
        .collect();
    let earliest = offsets.iter().copied().fold(f64::INFINITY, f64::min);
    for (k, o) in offsets.iter().enumerate() {
        let late = o - earliest;
        let at = beats[k];
        let held = held.held(at - Duration::from_secs_f64(late.max(0.0)), at);
        assert!(
            late - held.as_secs_f64() <= 0.010,
            "beat {k} {:.1} ms late on the 100 ms grid while saving ({:.1} ms of it the machine held the node's thread)",
            late * 1000.0,
            held.as_secs_f64() * 1000.0
        );
    }
}
