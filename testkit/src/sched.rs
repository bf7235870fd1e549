//! How long the machine held threads back: the time each spent ready to run but waiting for a
//! processor (the run-queue wait the kernel counts in `/proc/PID/task/TID/schedstat`, second field).
//! A timing test measures a node from outside; a late answer is the node's only when the machine did
//! not hold the node (or the master that stamped the request) back for that long. [`watch`] samples
//! the threads' waits every millisecond; [`WaitLog::held`] is what they waited between two instants.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, SystemTime};

/// The schedstat files of every thread of process `pid` as it is now.
pub fn process_threads(pid: u32) -> Vec<PathBuf> {
    std::fs::read_dir(format!("/proc/{pid}/task"))
        .map(|d| d.flatten().map(|e| e.path().join("schedstat")).collect())
        .unwrap_or_default()
}

/// The schedstat file of the calling thread.
pub fn this_thread() -> PathBuf {
    let tid = std::fs::read_link("/proc/thread-self")
        .ok()
        .and_then(|p| p.file_name()?.to_str().map(str::to_string))
        .unwrap_or_else(|| "self".into());
    PathBuf::from(format!("/proc/self/task/{tid}/schedstat"))
}

/// The run-queue wait so far of the thread whose schedstat file is `path` (0 when it cannot be read:
/// a thread that ended, a kernel without schedstats).
pub fn waited(path: &PathBuf) -> Duration {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|s| s.split_whitespace().nth(1)?.parse::<u64>().ok())
        .map_or(Duration::ZERO, Duration::from_nanos)
}

/// The summed run-queue wait of some threads, sampled in time.
#[derive(Debug, Clone, Default)]
pub struct WaitLog {
    samples: Vec<(SystemTime, Duration)>,
}

impl WaitLog {
    /// Adds a sample: the threads' summed wait `total` at `at` (samples come in time order).
    pub fn push(&mut self, at: SystemTime, total: Duration) {
        self.samples.push((at, total));
    }

    /// What the threads waited for a processor from `from` to `to`, as the samples around the two
    /// instants bound it (from the last sample at or before `from` to the first at or after `to`): at
    /// least what they waited in between.
    pub fn held(&self, from: SystemTime, to: SystemTime) -> Duration {
        let before = self
            .samples
            .iter()
            .rev()
            .find(|(t, _)| *t <= from)
            .or(self.samples.first());
        let after = self
            .samples
            .iter()
            .find(|(t, _)| *t >= to)
            .or(self.samples.last());
        match (before, after) {
            (Some((_, a)), Some((_, b))) => b.saturating_sub(*a),
            _ => Duration::ZERO,
        }
    }

    /// The number of samples.
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// True before the first sample.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }
}

/// Samples the summed run-queue wait of `threads` (schedstat files) every millisecond until `stop`.
pub fn watch(threads: Vec<PathBuf>, stop: Arc<AtomicBool>) -> JoinHandle<WaitLog> {
    std::thread::spawn(move || {
        let mut log = WaitLog::default();
        let total = || threads.iter().map(waited).sum::<Duration>();
        while !stop.load(Ordering::Relaxed) {
            log.push(SystemTime::now(), total());
            std::thread::sleep(Duration::from_millis(1));
        }
        log.push(SystemTime::now(), total());
        log
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The wait between two instants is bounded by the samples around them.
    #[test]
    fn held_is_the_wait_between_the_samples_around_the_span() {
        let t0 = SystemTime::UNIX_EPOCH + Duration::from_secs(100);
        let ms = |n: u64| t0 + Duration::from_millis(n);
        let mut log = WaitLog::default();
        for (t, w) in [(0, 0), (1, 0), (2, 3), (3, 7), (4, 7)] {
            log.push(ms(t), Duration::from_millis(w));
        }
        assert_eq!(log.held(ms(1), ms(3)), Duration::from_millis(7));
        assert_eq!(log.held(ms(3), ms(4)), Duration::ZERO);
        // Between samples: widened to the samples around.
        let mid = |a: u64| t0 + Duration::from_micros(a);
        assert_eq!(log.held(mid(1500), mid(2500)), Duration::from_millis(7));
        assert_eq!(log.len(), 5);
    }

    /// The calling thread's own file reads (this kernel keeps schedstats) and only grows.
    #[test]
    fn a_thread_s_wait_is_read_and_never_goes_back() {
        let me = this_thread();
        let a = waited(&me);
        std::thread::sleep(Duration::from_millis(2));
        assert!(waited(&me) >= a);
        assert!(std::fs::metadata(&me).is_ok(), "{}", me.display());
        assert!(!process_threads(std::process::id()).is_empty());
    }
}
