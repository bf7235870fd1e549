//! Where a client's data comes from and goes to: the download source (owned bytes or a streaming
//! [`DownloadSource`]) and the upload target (memory, bounded by a limit, or a streaming
//! [`UploadSink`]).
//!
//! The state machines read the source strictly in order and at most [`MAX_READ_PER_CALL`] bytes per
//! call of the client, and hand the sink the received bytes strictly in order, so a caller can feed a
//! source or drain a sink between two calls with a bounded buffer.

use std::io;

use crate::abort::AbortCode;
use crate::sdo::frame::Crc16;

use super::{ClientEvent, SdoClientError};

/// The most bytes a client reads from a [`DownloadSource`] within one call (`start_download`,
/// `handle_frame`, `handle_timeout`): one full sub-block of block download, 127 segments of 7 bytes.
pub const MAX_READ_PER_CALL: usize = 127 * 7;

/// At most this many bytes are reserved ahead for an upload into memory, whatever size the server
/// announces; the buffer grows as data arrives.
pub const UPLOAD_PREALLOC_CAP: usize = 4096;

/// A streaming source of the bytes of a download (a file, a firmware image).
pub trait DownloadSource {
    /// The number of bytes the source will give; announced to the server before the first byte.
    fn len(&self) -> u64;

    /// True when the source gives no byte.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Reads the next bytes into `buf`, like [`std::io::Read::read`]: returns how many were read; 0
    /// before [`len`](DownloadSource::len) bytes were given is an early end and fails the transfer.
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize>;
}

/// A streaming destination of the bytes of an upload.
pub trait UploadSink {
    /// Takes the next received bytes (all of them, like [`std::io::Write::write_all`]).
    fn write_data(&mut self, data: &[u8]) -> io::Result<()>;

    /// Called once when the transfer completed and every byte was checked (size, CRC), before the
    /// client reports [`ClientEvent::UploadedToSink`]. A sink whose transfer fails gets no call: it has
    /// received some bytes that the caller should discard.
    fn finish(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// A [`DownloadSource`] over any [`std::io::Read`] whose length is known.
#[derive(Debug)]
pub struct ReadSource<R> {
    reader: R,
    len: u64,
}

impl<R: io::Read> ReadSource<R> {
    /// `len` bytes from `reader`.
    pub fn new(reader: R, len: u64) -> ReadSource<R> {
        ReadSource { reader, len }
    }
}

impl<R: io::Read> DownloadSource for ReadSource<R> {
    fn len(&self) -> u64 {
        self.len
    }

    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.reader.read(buf)
    }
}

/// An [`UploadSink`] over any [`std::io::Write`]; `finish` flushes it.
#[derive(Debug)]
pub struct WriteSink<W>(pub W);

impl<W: io::Write> UploadSink for WriteSink<W> {
    fn write_data(&mut self, data: &[u8]) -> io::Result<()> {
        self.0.write_all(data)
    }

    fn finish(&mut self) -> io::Result<()> {
        self.0.flush()
    }
}

/// The data of a download: owned bytes or a streaming source.
pub enum DownloadData {
    /// The bytes, in memory.
    Bytes(Vec<u8>),
    /// A source read as the transfer goes.
    Stream(Box<dyn DownloadSource + Send>),
}

impl DownloadData {
    /// The number of bytes.
    pub fn len(&self) -> u64 {
        match self {
            DownloadData::Bytes(b) => b.len() as u64,
            DownloadData::Stream(s) => s.len(),
        }
    }

    /// True when there is no byte.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl std::fmt::Debug for DownloadData {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DownloadData::Bytes(b) => f.debug_tuple("Bytes").field(b).finish(),
            DownloadData::Stream(s) => write!(f, "Stream({} bytes)", s.len()),
        }
    }
}

impl From<Vec<u8>> for DownloadData {
    fn from(bytes: Vec<u8>) -> DownloadData {
        DownloadData::Bytes(bytes)
    }
}

impl From<&[u8]> for DownloadData {
    fn from(bytes: &[u8]) -> DownloadData {
        DownloadData::Bytes(bytes.to_vec())
    }
}

impl<const N: usize> From<[u8; N]> for DownloadData {
    fn from(bytes: [u8; N]) -> DownloadData {
        DownloadData::Bytes(bytes.to_vec())
    }
}

impl<const N: usize> From<&[u8; N]> for DownloadData {
    fn from(bytes: &[u8; N]) -> DownloadData {
        DownloadData::Bytes(bytes.to_vec())
    }
}

impl From<Box<dyn DownloadSource + Send>> for DownloadData {
    fn from(source: Box<dyn DownloadSource + Send>) -> DownloadData {
        DownloadData::Stream(source)
    }
}

/// Why a transfer step failed on the client's side: the abort code sent on the wire and the error
/// reported to the caller.
pub(super) struct Failure {
    pub code: AbortCode,
    pub error: Option<SdoClientError>,
}

impl Failure {
    /// A protocol failure: reported as `Aborted { code, by_server: false }`.
    pub fn abort(code: AbortCode) -> Failure {
        Failure { code, error: None }
    }

    /// A failure of the caller's source or sink, answered on the wire with `code`.
    fn io(code: AbortCode, error: io::Error) -> Failure {
        Failure {
            code,
            error: Some(SdoClientError::Io(error)),
        }
    }
}

/// The bytes of a download, read in order; `pos` counts the bytes read so far.
pub(super) struct Source {
    data: DownloadData,
    pos: u64,
    len: u64,
}

impl Source {
    pub fn new(data: DownloadData) -> Source {
        let len = data.len();
        Source { data, pos: 0, len }
    }

    pub fn len(&self) -> u64 {
        self.len
    }

    pub fn remaining(&self) -> u64 {
        self.len - self.pos
    }

    /// Appends the next `n` bytes (at most the remaining ones) to `out`; a source error or early end is
    /// a failure answered with 0x08000000 (general error) on the wire.
    pub fn read_into(&mut self, out: &mut Vec<u8>, n: usize) -> Result<(), Failure> {
        let n = n.min(usize::try_from(self.remaining()).unwrap_or(usize::MAX));
        let start = out.len();
        match &mut self.data {
            DownloadData::Bytes(bytes) => {
                let from = self.pos as usize;
                out.extend_from_slice(&bytes[from..from + n]);
            }
            DownloadData::Stream(source) => {
                out.resize(start + n, 0);
                let mut filled = start;
                while filled < start + n {
                    match source.read(&mut out[filled..start + n]) {
                        Ok(0) => {
                            out.truncate(start);
                            return Err(Failure::io(
                                AbortCode::General,
                                io::Error::new(
                                    io::ErrorKind::UnexpectedEof,
                                    format!(
                                        "the download source ended after {} of {} bytes",
                                        self.pos + (filled - start) as u64,
                                        self.len
                                    ),
                                ),
                            ));
                        }
                        // A source that claims more than it was given room for is taken at its room.
                        Ok(k) => filled = (filled + k).min(start + n),
                        Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                        Err(e) => {
                            out.truncate(start);
                            return Err(Failure::io(AbortCode::General, e));
                        }
                    }
                }
            }
        }
        self.pos += n as u64;
        Ok(())
    }
}

/// Where an upload goes.
pub(super) enum Sink {
    /// Into memory, at most `limit` bytes.
    Memory { buf: Vec<u8>, limit: usize },
    /// Into a caller's sink; `written` counts the bytes handed over.
    Stream {
        sink: Box<dyn UploadSink + Send>,
        written: u64,
    },
}

impl Sink {
    /// Bytes received so far.
    pub fn received(&self) -> u64 {
        match self {
            Sink::Memory { buf, .. } => buf.len() as u64,
            Sink::Stream { written, .. } => *written,
        }
    }

    /// Learns the size the server announced: refused with 0x05040005 (out of memory) when it exceeds
    /// the memory limit; otherwise reserves room for it, at most [`UPLOAD_PREALLOC_CAP`] bytes.
    pub fn announce(&mut self, size: Option<u32>) -> Result<(), Failure> {
        if let (Sink::Memory { buf, limit }, Some(size)) = (self, size) {
            let size = size as usize;
            if size > *limit {
                return Err(Failure::abort(AbortCode::OutOfMemory));
            }
            buf.reserve(size.min(UPLOAD_PREALLOC_CAP).saturating_sub(buf.len()));
        }
        Ok(())
    }

    /// Takes received bytes: beyond the memory limit is 0x05040005 (out of memory); a sink error is
    /// answered with 0x08000020 (data cannot be stored).
    pub fn push(&mut self, data: &[u8]) -> Result<(), Failure> {
        match self {
            Sink::Memory { buf, limit } => {
                if buf.len() + data.len() > *limit {
                    return Err(Failure::abort(AbortCode::OutOfMemory));
                }
                buf.extend_from_slice(data);
            }
            Sink::Stream { sink, written } => {
                sink.write_data(data)
                    .map_err(|e| Failure::io(AbortCode::CannotStore, e))?;
                *written += data.len() as u64;
            }
        }
        Ok(())
    }

    /// Ends a good transfer: the event that reports it.
    pub fn finish(self) -> Result<ClientEvent, Failure> {
        match self {
            Sink::Memory { buf, .. } => Ok(ClientEvent::Uploaded(buf)),
            Sink::Stream {
                mut sink, written, ..
            } => {
                sink.finish()
                    .map_err(|e| Failure::io(AbortCode::CannotStore, e))?;
                Ok(ClientEvent::UploadedToSink { len: written })
            }
        }
    }
}

/// Checks the bytes received so far against the size the server announced: more is 0x06070012
/// (length too high); at the end (`complete`), less is 0x06070013 (length too low).
pub(super) fn check_size(received: u64, size: Option<u32>, complete: bool) -> Result<(), Failure> {
    match size {
        Some(size) if received > size as u64 => Err(Failure::abort(AbortCode::LengthTooHigh)),
        Some(size) if complete && received < size as u64 => {
            Err(Failure::abort(AbortCode::LengthTooLow))
        }
        _ => Ok(()),
    }
}

/// Feeds `data` to the CRC when the transfer uses one.
pub(super) fn crc_update(crc: &mut Option<Crc16>, data: &[u8]) {
    if let Some(c) = crc {
        c.update(data);
    }
}
