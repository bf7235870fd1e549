//! Expedited and segmented SDO upload, client side (CiA 301 §7.2.4.3.6–7.2.4.3.8).
//!
//! "Initiate upload" names the entry; the server answers expedited (up to four bytes, the transfer
//! ends) or segmented (the size, when indicated). Then one "upload segment request" per segment, the
//! toggle bit alternating from 0; the server's segment carries the same toggle bit (a wrong one is
//! aborted with 0x05030000), up to seven bytes and `c = 1` on the last one.
//!
//! The same machine continues a block upload that the server switched to this protocol (CiA 301
//! §7.2.4.3.13, protocol switch threshold).

use crate::abort::AbortCode;
use crate::sdo::frame::{Address, ClientFrame, ServerFrame};

use super::data::{check_size, Failure, Sink};
use super::{Out, Step};

/// Where an upload stands.
enum Phase {
    /// The initiate request is out (plain or block with a possible protocol switch).
    Initiate,
    /// A segment request is out.
    Segment,
}

/// An expedited or segmented upload.
pub(super) struct Upload {
    sink: Option<Sink>,
    phase: Phase,
    /// Toggle bit of the request that is out.
    toggle: bool,
    /// The size the server announced.
    size: Option<u32>,
}

impl Upload {
    /// Sends "initiate upload".
    pub fn start(mux: Address, sink: Sink, out: &mut Out) -> Upload {
        out.send(ClientFrame::InitiateUpload { mux });
        Upload::waiting(sink)
    }

    /// An upload whose initiate request is already out: a block upload initiate that the server may
    /// answer with a normal initiate upload response.
    pub fn waiting(sink: Sink) -> Upload {
        Upload {
            sink: Some(sink),
            phase: Phase::Initiate,
            toggle: false,
            size: None,
        }
    }

    /// Takes a server frame (aborts are handled by the caller).
    pub fn handle(&mut self, mux: Address, frame: ServerFrame, out: &mut Out) -> Step {
        match self.step(mux, frame, out) {
            Ok(step) => step,
            Err(f) => Step::Fail(f),
        }
    }

    fn step(&mut self, mux: Address, frame: ServerFrame, out: &mut Out) -> Result<Step, Failure> {
        let sink = self
            .sink
            .as_mut()
            .ok_or(Failure::abort(AbortCode::General))?;
        match (&self.phase, frame) {
            (Phase::Initiate, ServerFrame::InitiateUploadExpedited { mux: m, data })
                if m == mux =>
            {
                sink.announce(Some(data.as_slice().len() as u32))?;
                sink.push(data.as_slice())?;
                self.finish()
            }
            (Phase::Initiate, ServerFrame::InitiateUploadSegmented { mux: m, size })
                if m == mux =>
            {
                sink.announce(size)?;
                self.size = size;
                self.phase = Phase::Segment;
                out.send(ClientFrame::UploadSegment { toggle: false });
                Ok(Step::Wait)
            }
            (Phase::Segment, ServerFrame::UploadSegment { toggle, data, last }) => {
                if toggle != self.toggle {
                    return Err(Failure::abort(AbortCode::ToggleBit));
                }
                sink.push(data.as_slice())?;
                let received = sink.received();
                check_size(received, self.size, last)?;
                out.progress(received, self.size.map(u64::from));
                if last {
                    return self.finish();
                }
                self.toggle = !self.toggle;
                out.send(ClientFrame::UploadSegment {
                    toggle: self.toggle,
                });
                Ok(Step::Wait)
            }
            _ => Err(Failure::abort(AbortCode::InvalidCommand)),
        }
    }

    fn finish(&mut self) -> Result<Step, Failure> {
        let sink = self.sink.take().ok_or(Failure::abort(AbortCode::General))?;
        Ok(Step::Done(sink.finish()?))
    }
}
