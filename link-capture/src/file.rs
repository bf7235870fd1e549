//! One capture file that the links of a process share.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::SystemTime;

use crate::pcapng::{self, Direction};

/// The capture file could not be created, or its header not written.
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct CaptureError {
    /// The file.
    pub path: PathBuf,
    /// What the system said.
    #[source]
    pub source: std::io::Error,
}

/// The most bytes of blocks held before they are written, whatever the links do: a burst of
/// frames between two waits reaches the file in pieces of this size.
pub const PENDING: usize = 64 * 1024;

/// Where the blocks go, and the interfaces described so far.
struct Sink {
    out: Box<dyn Write + Send>,
    /// What the capture is, for the one warning when a write fails.
    name: String,
    /// Each interface's name and link type, in the order of their Interface Description Blocks.
    interfaces: Vec<(String, u16)>,
    /// A write failed: nothing more is written.
    failed: bool,
    /// Whole blocks not written yet.
    buf: Vec<u8>,
}

impl Sink {
    /// Writes the blocks held, in one write; the first failure is logged once and ends the
    /// capture.
    fn flush_buf(&mut self) {
        if !self.failed && !self.buf.is_empty() {
            if let Err(e) = self
                .out
                .write_all(&self.buf)
                .and_then(|()| self.out.flush())
            {
                self.failed = true;
                tracing::warn!(capture = %self.name, "the capture cannot be written ({e}): no more frames are captured");
            }
        }
        self.buf.clear();
    }
}

impl Drop for Sink {
    /// The blocks still held go to the file when the capture's last handle goes.
    fn drop(&mut self) {
        self.flush_buf();
    }
}

/// A pcapng capture that the links of a process write their frames to: a Section Header Block,
/// then an Interface Description Block per link ([`Capture::interface`]) and an Enhanced Packet
/// Block per frame ([`Interface::record`]). Clones are the same capture.
///
/// The header blocks are written at once. The frames' blocks are held until the link is about to
/// wait ([`Capture::flush`]: a link calls it before it blocks), [`PENDING`] bytes are held, or the
/// capture's last handle goes; then they reach the file in one write. So the file always ends
/// after a whole block, and whenever the process waits, every frame so far is in it: a process
/// killed at any moment loses at most the frames it handled since it last waited. A write that
/// fails is logged once, and the capture ends there; the links go on.
#[derive(Clone)]
pub struct Capture {
    sink: Arc<Mutex<Sink>>,
}

impl std::fmt::Debug for Capture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let sink = self.sink.lock().unwrap_or_else(PoisonError::into_inner);
        f.debug_struct("Capture")
            .field("name", &sink.name)
            .field("interfaces", &sink.interfaces)
            .finish()
    }
}

impl Capture {
    /// Creates (or empties) `path` and writes the Section Header Block, `application` as
    /// `shb_userappl` (e.g. `sdo-tool 0.1.0`).
    pub fn create(path: &Path, application: &str) -> Result<Capture, CaptureError> {
        let error = |source| CaptureError {
            path: path.to_path_buf(),
            source,
        };
        let file = std::fs::File::create(path).map_err(error)?;
        Capture::new(Box::new(file), &path.display().to_string(), application).map_err(error)
    }

    /// A capture into `out` (named `name` in the warning when a write fails), the Section Header
    /// Block written at once.
    pub fn new(
        out: Box<dyn Write + Send>,
        name: &str,
        application: &str,
    ) -> std::io::Result<Capture> {
        let mut sink = Sink {
            out,
            name: name.to_string(),
            interfaces: Vec::new(),
            failed: false,
            buf: Vec::new(),
        };
        pcapng::section_header(&mut sink.buf, application);
        let written = sink
            .out
            .write_all(&sink.buf)
            .and_then(|()| sink.out.flush());
        sink.buf.clear();
        written?;
        Ok(Capture {
            sink: Arc::new(Mutex::new(sink)),
        })
    }

    /// Writes the frames' blocks held so far: what a link calls before it waits.
    pub fn flush(&self) {
        self.sink
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .flush_buf();
    }

    /// A capture into memory, for tests and examples: the capture and the bytes written so far.
    pub fn in_memory(application: &str) -> (Capture, Arc<Mutex<Vec<u8>>>) {
        let bytes = Arc::new(Mutex::new(Vec::new()));
        let out = Shared(Arc::clone(&bytes));
        let capture = Capture::new(Box::new(out), "memory", application)
            .unwrap_or_else(|_| unreachable!("writing to memory does not fail"));
        (capture, bytes)
    }

    /// The interface `name` of `link_type` (a `LINKTYPE_…` of [`pcapng`]): its Interface
    /// Description Block is written the first time it is asked for; the same name and link type
    /// again is the same interface.
    pub fn interface(&self, name: &str, link_type: u16) -> Interface {
        let mut sink = self.sink.lock().unwrap_or_else(PoisonError::into_inner);
        let known = sink
            .interfaces
            .iter()
            .position(|(n, t)| n == name && *t == link_type);
        let id = match known {
            Some(id) => id,
            None => {
                sink.interfaces.push((name.to_string(), link_type));
                pcapng::interface_description(&mut sink.buf, link_type, name);
                sink.flush_buf();
                sink.interfaces.len() - 1
            }
        };
        Interface {
            capture: self.clone(),
            id: id as u32,
        }
    }
}

/// One link's interface in a [`Capture`]: what it records is a frame of that link.
#[derive(Debug, Clone)]
pub struct Interface {
    capture: Capture,
    id: u32,
}

impl Interface {
    /// Its number in the capture's section (0 for the first).
    pub fn id(&self) -> u32 {
        self.id
    }

    /// Records `frame`, sent or received (`direction`) at `at` (held until the next
    /// [`Capture::flush`]).
    pub fn record(&self, at: SystemTime, direction: Direction, frame: &[u8]) {
        self.record_all(at, direction, [frame]);
    }

    /// Writes the blocks held so far ([`Capture::flush`]): what a link calls before it waits.
    pub fn flush(&self) {
        self.capture.flush();
    }

    /// Records `frames`, each sent or received (`direction`) at `at` (held until the next
    /// [`Capture::flush`]).
    pub fn record_all<'a>(
        &self,
        at: SystemTime,
        direction: Direction,
        frames: impl IntoIterator<Item = &'a [u8]>,
    ) {
        let mut sink = self
            .capture
            .sink
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        if sink.failed {
            return;
        }
        for frame in frames {
            pcapng::enhanced_packet(&mut sink.buf, self.id, at, direction, frame);
            if sink.buf.len() >= PENDING {
                sink.flush_buf();
            }
        }
    }
}

/// A writer into shared memory.
struct Shared(Arc<Mutex<Vec<u8>>>);

impl Write for Shared {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .extend_from_slice(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pcapng::{Reader, LINKTYPE_CAN_SOCKETCAN, LINKTYPE_ETHERNET};
    use std::time::{Duration, UNIX_EPOCH};

    /// Two links in one capture: an interface each, the same name and type again the same one;
    /// their frames read back in the order recorded, each with its interface, time and direction.
    #[test]
    fn links_share_one_capture() {
        let (capture, bytes) = Capture::in_memory("test");
        let can = capture.interface("vcan0", LINKTYPE_CAN_SOCKETCAN);
        let eth = capture.interface("ecat0", LINKTYPE_ETHERNET);
        let again = capture.interface("vcan0", LINKTYPE_CAN_SOCKETCAN);
        assert_eq!((can.id(), eth.id(), again.id()), (0, 1, 0));
        let t = UNIX_EPOCH + Duration::new(1_700_000_000, 123_456_789);
        can.record(t, Direction::Inbound, &[1; 16]);
        eth.record_all(t, Direction::Outbound, [&[2u8; 60][..], &[3u8; 61][..]]);
        // The headers are written at once, the frames' blocks when flushed.
        assert_eq!(bytes.lock().unwrap().len(), 40 + 44 + 44);
        can.flush();
        let file = bytes.lock().unwrap().clone();
        let mut r = Reader::new(&file[..]);
        let mut got = Vec::new();
        while let Some(p) = r.next_packet().unwrap() {
            got.push((
                p.interface,
                p.link_type,
                p.data.to_vec(),
                p.time,
                p.direction,
            ));
        }
        assert_eq!(
            got,
            [
                (0, 227, vec![1; 16], Some(t), Some(Direction::Inbound)),
                (1, 1, vec![2; 60], Some(t), Some(Direction::Outbound)),
                (1, 1, vec![3; 61], Some(t), Some(Direction::Outbound)),
            ]
        );
        let names: Vec<_> = r
            .interfaces_seen()
            .iter()
            .map(|i| i.name.clone().unwrap())
            .collect();
        assert_eq!(names, ["vcan0", "ecat0"]);
        assert!(format!("{capture:?}").contains("vcan0"));
    }

    /// A write that fails ends the capture: nothing more is written, and recording goes on
    /// without error.
    #[test]
    fn a_failed_write_ends_the_capture() {
        struct Full(usize);
        impl Write for Full {
            fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
                if self.0 < buf.len() {
                    return Err(std::io::Error::other("no space left"));
                }
                self.0 -= buf.len();
                Ok(buf.len())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let capture = Capture::new(Box::new(Full(100)), "full", "").unwrap();
        let i = capture.interface("can0", LINKTYPE_CAN_SOCKETCAN);
        i.record(UNIX_EPOCH, Direction::Inbound, &[0; 16]);
        assert!(!capture.sink.lock().unwrap().failed);
        capture.flush();
        assert!(capture.sink.lock().unwrap().failed);
        i.record(UNIX_EPOCH, Direction::Inbound, &[0; 16]);
        assert!(capture.sink.lock().unwrap().buf.is_empty());
        assert!(Capture::new(Box::new(Full(4)), "full", "x").is_err());
    }

    /// An interface is its name and its link type: the same name on another link is another.
    #[test]
    fn an_interface_is_its_name_and_link_type() {
        let (capture, _) = Capture::in_memory("");
        let ids: Vec<u32> = [
            ("x", LINKTYPE_CAN_SOCKETCAN),
            ("x", LINKTYPE_ETHERNET),
            ("y", LINKTYPE_CAN_SOCKETCAN),
            ("x", LINKTYPE_ETHERNET),
        ]
        .iter()
        .map(|(n, t)| capture.interface(n, *t).id())
        .collect();
        assert_eq!(ids, [0, 1, 2, 1]);
    }

    /// After a failed write nothing is written, not even a new interface's block.
    #[test]
    fn nothing_is_written_after_a_failure() {
        struct FailsOnce(Arc<Mutex<(usize, usize)>>);
        impl Write for FailsOnce {
            fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
                let mut calls = self.0.lock().unwrap();
                calls.0 += 1;
                if calls.0 == 3 {
                    return Err(std::io::Error::other("no space left"));
                }
                calls.1 += buf.len();
                Ok(buf.len())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let seen = Arc::new(Mutex::new((0, 0)));
        let capture = Capture::new(Box::new(FailsOnce(Arc::clone(&seen))), "once", "").unwrap();
        let i = capture.interface("can0", LINKTYPE_CAN_SOCKETCAN);
        i.record(UNIX_EPOCH, Direction::Inbound, &[0; 16]);
        i.flush();
        assert_eq!(*seen.lock().unwrap(), (3, 28 + 40));
        capture.interface("can1", LINKTYPE_CAN_SOCKETCAN);
        i.flush();
        drop((i, capture));
        assert_eq!(*seen.lock().unwrap(), (3, 28 + 40));
    }

    /// The frames' blocks are held until a flush, until PENDING bytes are held, or until the last
    /// handle goes: each time written whole, in order.
    #[test]
    fn blocks_are_held_until_a_flush_the_bound_or_the_end() {
        let (capture, bytes) = Capture::in_memory("");
        let i = capture.interface("can0", LINKTYPE_CAN_SOCKETCAN);
        let header = bytes.lock().unwrap().len();
        assert_eq!(header, 28 + 40);
        // A 16-byte frame's block is 60 bytes: the 1,093rd reaches 65,580 ≥ 65,536 bytes held.
        for k in 0..1092u32 {
            i.record(UNIX_EPOCH, Direction::Inbound, &[k as u8; 16]);
        }
        assert_eq!(bytes.lock().unwrap().len(), header);
        i.record(UNIX_EPOCH, Direction::Inbound, &[0; 16]);
        assert_eq!(bytes.lock().unwrap().len(), header + 1093 * 60);
        i.record(UNIX_EPOCH, Direction::Outbound, &[1; 16]);
        i.flush();
        assert_eq!(bytes.lock().unwrap().len(), header + 1094 * 60);
        i.record(UNIX_EPOCH, Direction::Outbound, &[2; 16]);
        drop(capture);
        assert_eq!(
            bytes.lock().unwrap().len(),
            header + 1094 * 60,
            "a handle is left"
        );
        drop(i);
        let file = bytes.lock().unwrap().clone();
        assert_eq!(file.len(), header + 1095 * 60);
        let mut r = Reader::new(&file[..]);
        let mut n = 0;
        while let Some(p) = r.next_packet().unwrap() {
            n += 1;
            assert_eq!(p.data.len(), 16);
        }
        assert_eq!(n, 1095);
    }

    /// A file that cannot be created is refused with its name.
    #[test]
    fn a_file_that_cannot_be_created() {
        let e = Capture::create(Path::new("/nonexistent/dir/c.pcapng"), "t").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("/nonexistent/dir/c.pcapng: No such file or directory"),
            "{e}"
        );
    }
}
