//! Typed, blocking SDO access on top of the sans-IO [`SdoClient`]: read and write each basic data type,
//! strings, byte strings and [`Value`]s, and stream DOMAIN contents from a reader or to a writer with a
//! progress callback.
//!
//! This is the edge where IO and the clock live: an [`SdoSession`] drives its client over an
//! [`SdoTransport`] (a CAN channel to one node's SDO server: it sends on COB-ID 0x600 + node and
//! receives what arrives on 0x580 + node) until the transfer ends. Everything protocol-related
//! (modes, fall-back, timeouts, aborts) is the client's.

use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use crate::abort::AbortCode;
use crate::sdo::client::{
    ClientConfig, ClientEvent, DownloadData, DownloadSource, SdoClient, SdoClientError, UploadSink,
    MAX_READ_PER_CALL,
};
use crate::sdo::frame::{Address, Frame};
use crate::types::DataType;
use crate::value::{Value, ValueError};

/// A channel to one SDO server: the frames a client sends and those the server answers with.
pub trait SdoTransport {
    /// Why the channel failed (kept as the source of [`SessionError::Transport`]).
    type Error: std::error::Error + Send + Sync + 'static;

    /// Sends one frame to the server.
    fn send(&mut self, frame: &Frame) -> Result<(), Self::Error>;

    /// Waits for the next frame from the server until `until`; `Ok(None)` when none came by then.
    fn recv(&mut self, until: Instant) -> Result<Option<Frame>, Self::Error>;

    /// The present time of the transport's clock.
    fn now(&self) -> Instant;
}

/// Why a session's read or write failed; `E` is the transport's error.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SessionError<E: std::error::Error + 'static = io::Error> {
    /// The transfer failed (aborted by either side, or the client was busy).
    #[error(transparent)]
    Sdo(#[from] SdoClientError),
    /// The transport failed; the transfer was given up.
    #[error("SDO transport failed: {0}")]
    Transport(#[source] E),
    /// Reading the data to download failed; the transfer was aborted with 0x08000000.
    #[error("reading the data to download failed: {0}")]
    Read(#[source] io::Error),
    /// Writing the uploaded data failed; the transfer was aborted with 0x08000020.
    #[error("writing the uploaded data failed: {0}")]
    Write(#[source] io::Error),
    /// The uploaded bytes are no value of the type asked for, or the value to write does not fit its
    /// type.
    #[error(transparent)]
    Value(#[from] ValueError),
    /// The caller cancelled the transfer ([`SdoSession::with_cancel`], a Ctrl-C); the abort
    /// 0x08000000 (general error: CiA 301 has no code of its own for a user's abort) was sent.
    #[error("cancelled; the transfer was aborted with 0x08000000")]
    Cancelled,
}

/// How often a session with a cancel flag looks at it while it waits for the server.
pub const CANCEL_CHECK: Duration = Duration::from_millis(50);

/// How a transfer driven by [`SdoSession`] ended well.
enum Finished {
    Downloaded,
    Uploaded(Vec<u8>),
    ToSink,
}

/// An [`SdoClient`] bound to an [`SdoTransport`]: each method runs one transfer to its end and
/// returns its result.
///
/// The loop of every transfer: send what the client queued; move data between the caller's reader or
/// writer and the client (at most one sub-block, 889 bytes, is buffered); hand the client's events to
/// the caller (progress) or return (end); then wait on the transport until the client's timeout and
/// hand the client the frame that came, or the timeout. A transport error, a reader or writer error
/// aborts the transfer (the abort is sent if the transport still works) and leaves the client idle.
#[derive(Debug)]
pub struct SdoSession<T: SdoTransport> {
    /// The client state machine.
    pub client: SdoClient,
    /// The channel to the server.
    pub transport: T,
    /// Set by the caller (a Ctrl-C handler) to end the running transfer with an abort.
    cancel: Option<Arc<AtomicBool>>,
}

macro_rules! typed_access {
    ($($read:ident, $write:ident, $ty:ty, $data_type:expr;)*) => {
        $(
            #[doc = concat!("Reads a `", stringify!($ty), "` (", stringify!($data_type), ", little-endian).")]
            pub fn $read(&mut self, mux: Address) -> Result<$ty, SessionError<T::Error>> {
                Ok(<$ty>::from_le_bytes(self.read_array(mux, $data_type)?))
            }

            #[doc = concat!("Writes a `", stringify!($ty), "` (", stringify!($data_type), ", little-endian).")]
            pub fn $write(&mut self, mux: Address, value: $ty) -> Result<(), SessionError<T::Error>> {
                self.write_bytes(mux, &value.to_le_bytes())
            }
        )*
    };
}

impl<T: SdoTransport> SdoSession<T> {
    /// A session with a new client configured by `config`.
    pub fn new(transport: T, config: ClientConfig) -> SdoSession<T> {
        SdoSession {
            client: SdoClient::new(config),
            transport,
            cancel: None,
        }
    }

    /// The session, with `flag` to cancel a transfer: once it is set, the running transfer is
    /// aborted (0x08000000 sent to the server) within [`CANCEL_CHECK`] and ends with
    /// [`SessionError::Cancelled`]; so does every transfer begun while it stays set.
    #[must_use]
    pub fn with_cancel(mut self, flag: Arc<AtomicBool>) -> SdoSession<T> {
        self.cancel = Some(flag);
        self
    }

    typed_access! {
        read_u8, write_u8, u8, DataType::Unsigned8;
        read_u16, write_u16, u16, DataType::Unsigned16;
        read_u32, write_u32, u32, DataType::Unsigned32;
        read_u64, write_u64, u64, DataType::Unsigned64;
        read_i8, write_i8, i8, DataType::Integer8;
        read_i16, write_i16, i16, DataType::Integer16;
        read_i32, write_i32, i32, DataType::Integer32;
        read_i64, write_i64, i64, DataType::Integer64;
        read_f32, write_f32, f32, DataType::Real32;
        read_f64, write_f64, f64, DataType::Real64;
    }

    /// Reads a BOOLEAN: one byte, 0 or 1.
    pub fn read_bool(&mut self, mux: Address) -> Result<bool, SessionError<T::Error>> {
        let [b] = self.read_array(mux, DataType::Boolean)?;
        Ok(matches!(
            Value::decode(DataType::Boolean, &[b])?,
            Value::Bool(true)
        ))
    }

    /// Writes a BOOLEAN: one byte, 0 or 1.
    pub fn write_bool(&mut self, mux: Address, value: bool) -> Result<(), SessionError<T::Error>> {
        self.write_bytes(mux, &[value as u8])
    }

    /// Reads a VISIBLE_STRING: UTF-8 when the bytes are, Latin-1 otherwise; trailing NUL bytes (a
    /// fixed-size buffer's padding) are cut.
    pub fn read_string(&mut self, mux: Address) -> Result<String, SessionError<T::Error>> {
        let mut bytes = self.read_bytes(mux)?;
        while bytes.last() == Some(&0) {
            bytes.pop();
        }
        match Value::decode(DataType::VisibleString, &bytes)? {
            Value::String(s) => Ok(s),
            _ => Ok(String::from_utf8_lossy(&bytes).into_owned()),
        }
    }

    /// Writes a VISIBLE_STRING (the string's UTF-8 bytes, no terminator).
    pub fn write_string(
        &mut self,
        mux: Address,
        value: &str,
    ) -> Result<(), SessionError<T::Error>> {
        self.write_bytes(mux, value.as_bytes())
    }

    /// Reads the entry's bytes into memory (at most the client's upload limit).
    pub fn read_bytes(&mut self, mux: Address) -> Result<Vec<u8>, SessionError<T::Error>> {
        self.upload(mux, None)
    }

    /// Writes `data` to the entry.
    pub fn write_bytes(&mut self, mux: Address, data: &[u8]) -> Result<(), SessionError<T::Error>> {
        let now = self.transport.now();
        self.client.start_download(now, mux, data.to_vec())?;
        self.drive(&mut || Ok(()), &mut |_, _| {}).map(|_| ())
    }

    /// Reads a value of `data_type`: the bytes must be a valid value of the type (exactly its size for
    /// the fixed-size types).
    pub fn read_value(
        &mut self,
        mux: Address,
        data_type: DataType,
    ) -> Result<Value, SessionError<T::Error>> {
        let bytes = self.upload(mux, data_type.byte_size())?;
        Ok(Value::decode(data_type, &bytes)?)
    }

    /// Writes `value` encoded as `data_type`.
    pub fn write_value(
        &mut self,
        mux: Address,
        value: &Value,
        data_type: DataType,
    ) -> Result<(), SessionError<T::Error>> {
        let bytes = value.encode(data_type)?;
        self.write_bytes(mux, &bytes)
    }

    /// Reads the entry (a DOMAIN, typically) into `writer` as the bytes arrive, calling `progress`
    /// with the bytes received so far and the size when the server announced it. Returns the number of
    /// bytes written; the writer is flushed at the end. No memory limit applies; on failure the writer
    /// has received part of the data.
    pub fn upload_to(
        &mut self,
        mux: Address,
        writer: &mut impl Write,
        mut progress: impl FnMut(u64, Option<u64>),
    ) -> Result<u64, SessionError<T::Error>> {
        let pipe = Arc::new(Mutex::new(Vec::new()));
        let now = self.transport.now();
        self.client.start_upload_to(
            now,
            mux,
            Box::new(PipeSink {
                shared: Arc::clone(&pipe),
            }),
        )?;
        let mut written = 0u64;
        let mut drain = || {
            let data = std::mem::take(&mut *lock(&pipe));
            writer.write_all(&data).map_err(SessionError::Write)?;
            written += data.len() as u64;
            Ok(())
        };
        self.drive(&mut drain, &mut progress)?;
        drain()?;
        writer.flush().map_err(SessionError::Write)?;
        Ok(written)
    }

    /// Writes `len` bytes from `reader` to the entry (a DOMAIN, typically), read as the transfer goes,
    /// calling `progress` with the bytes the server confirmed so far and `Some(len)`. A reader that
    /// fails or ends early aborts the transfer.
    pub fn download_from(
        &mut self,
        mux: Address,
        reader: &mut impl Read,
        len: u64,
        mut progress: impl FnMut(u64, Option<u64>),
    ) -> Result<(), SessionError<T::Error>> {
        let pipe = Arc::new(Mutex::new(VecDeque::with_capacity(MAX_READ_PER_CALL)));
        let mut supplied = 0u64;
        let mut fill = || {
            let mut queue = lock(&pipe);
            let mut chunk = [0u8; 256];
            while queue.len() < MAX_READ_PER_CALL && supplied < len {
                let want = (MAX_READ_PER_CALL - queue.len())
                    .min(chunk.len())
                    .min(usize::try_from(len - supplied).unwrap_or(usize::MAX));
                match reader.read(&mut chunk[..want]) {
                    Ok(0) => {
                        return Err(SessionError::Read(io::Error::new(
                            io::ErrorKind::UnexpectedEof,
                            format!("the reader ended after {supplied} of {len} bytes"),
                        )))
                    }
                    Ok(n) => {
                        let n = n.min(want);
                        queue.extend(&chunk[..n]);
                        supplied += n as u64;
                    }
                    Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                    Err(e) => return Err(SessionError::Read(e)),
                }
            }
            Ok(())
        };
        fill()?;
        let now = self.transport.now();
        let source: Box<dyn DownloadSource + Send> = Box::new(PipeSource {
            shared: Arc::clone(&pipe),
            len,
        });
        self.client
            .start_download(now, mux, DownloadData::Stream(source))?;
        self.drive(&mut fill, &mut progress).map(|_| ())
    }

    /// Reads exactly `N` bytes, the size of `data_type`.
    fn read_array<const N: usize>(
        &mut self,
        mux: Address,
        data_type: DataType,
    ) -> Result<[u8; N], SessionError<T::Error>> {
        let bytes = self.upload(mux, Some(N))?;
        let got = bytes.len();
        // Only a length other than N gets here.
        bytes.try_into().map_err(|_| {
            let e = match got.cmp(&N) {
                std::cmp::Ordering::Less => ValueError::TooShort {
                    data_type,
                    expected: N,
                    got,
                },
                _ => ValueError::TooLong {
                    data_type,
                    expected: N,
                    got,
                },
            };
            SessionError::Value(e)
        })
    }

    /// Uploads into memory; `expected` (a fixed size) keeps small values out of block mode.
    fn upload(
        &mut self,
        mux: Address,
        expected: Option<usize>,
    ) -> Result<Vec<u8>, SessionError<T::Error>> {
        let now = self.transport.now();
        match expected {
            Some(n) => self.client.start_upload_expecting(now, mux, n as u64)?,
            None => self.client.start_upload(now, mux)?,
        }
        match self.drive(&mut || Ok(()), &mut |_, _| {})? {
            Finished::Uploaded(bytes) => Ok(bytes),
            _ => Ok(Vec::new()),
        }
    }

    /// Runs the started transfer to its end. `pump` moves data between the caller and a streaming
    /// source or sink before every step; `progress` gets the progress events.
    fn drive(
        &mut self,
        pump: &mut dyn FnMut() -> Result<(), SessionError<T::Error>>,
        progress: &mut dyn FnMut(u64, Option<u64>),
    ) -> Result<Finished, SessionError<T::Error>> {
        loop {
            if self
                .cancel
                .as_ref()
                .is_some_and(|c| c.load(Ordering::Relaxed))
            {
                self.give_up(AbortCode::General);
                return Err(SessionError::Cancelled);
            }
            while let Some(frame) = self.client.poll_transmit() {
                if let Err(e) = self.transport.send(&frame) {
                    self.give_up(AbortCode::General);
                    return Err(SessionError::Transport(e));
                }
            }
            if let Err(e) = pump() {
                let code = match e {
                    SessionError::Write(_) => AbortCode::CannotStore,
                    _ => AbortCode::General,
                };
                self.give_up(code);
                return Err(e);
            }
            while let Some(event) = self.client.poll_event() {
                match event {
                    ClientEvent::Progress { done, total } => progress(done, total),
                    ClientEvent::Downloaded => return Ok(Finished::Downloaded),
                    ClientEvent::Uploaded(bytes) => return Ok(Finished::Uploaded(bytes)),
                    ClientEvent::UploadedToSink { .. } => return Ok(Finished::ToSink),
                    ClientEvent::Failed(e) => return Err(e.into()),
                }
            }
            let now = self.transport.now();
            let mut until = self
                .client
                .poll_timeout()
                .or_else(|| now.checked_add(Duration::from_secs(3600)))
                .unwrap_or(now);
            if self.cancel.is_some() {
                // Woken at least this often to see the flag.
                until = until.min(now + CANCEL_CHECK);
            }
            match self.transport.recv(until) {
                Ok(Some(frame)) => {
                    let now = self.transport.now();
                    self.client.handle_frame(now, &frame);
                }
                Ok(None) => {
                    let now = self.transport.now();
                    self.client.handle_timeout(now);
                }
                Err(e) => {
                    self.give_up(AbortCode::General);
                    return Err(SessionError::Transport(e));
                }
            }
        }
    }

    /// Aborts the transfer with `code`, sends the abort if the transport lets it, and forgets the
    /// transfer.
    fn give_up(&mut self, code: AbortCode) {
        self.client.abort(code);
        while let Some(frame) = self.client.poll_transmit() {
            if self.transport.send(&frame).is_err() {
                break;
            }
        }
        self.client.reset();
    }
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// The client's side of a download pipe: the session keeps it filled with at least one call's worth.
struct PipeSource {
    shared: Arc<Mutex<VecDeque<u8>>>,
    len: u64,
}

impl DownloadSource for PipeSource {
    fn len(&self) -> u64 {
        self.len
    }

    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        // The session keeps the pipe filled with what the client reads in one call, so it is never
        // empty here before the end.
        let mut queue = lock(&self.shared);
        let n = buf.len().min(queue.len());
        for (b, x) in buf.iter_mut().zip(queue.drain(..n)) {
            *b = x;
        }
        Ok(n)
    }
}

/// The client's side of an upload pipe: the session drains it after every step.
struct PipeSink {
    shared: Arc<Mutex<Vec<u8>>>,
}

impl UploadSink for PipeSink {
    fn write_data(&mut self, data: &[u8]) -> io::Result<()> {
        lock(&self.shared).extend_from_slice(data);
        Ok(())
    }
}
