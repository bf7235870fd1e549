//! Expedited and segmented SDO download, client side (CiA 301 §7.2.4.3.3–7.2.4.3.5).
//!
//! Expedited: "initiate download" carries up to four bytes; the server's "initiate download response"
//! ends the transfer. Segmented: "initiate download" announces the size, then one "download segment"
//! of up to seven bytes per "download segment response", the toggle bit alternating from 0 and echoed
//! by the server, `c = 1` on the last segment.

use crate::abort::AbortCode;
use crate::sdo::frame::{Address, ClientFrame, ExpeditedData, SegmentData, ServerFrame};

use super::data::{Failure, Source};
use super::{ClientEvent, Out, Step};

/// Where a download stands.
enum Phase {
    /// The initiate request is out; waiting for the initiate response.
    Initiate,
    /// A segment is out; waiting for its response.
    Segment,
}

/// An expedited or segmented download.
pub(super) struct Download {
    source: Source,
    expedited: bool,
    phase: Phase,
    /// Toggle bit of the segment that is out.
    toggle: bool,
    /// Bytes in the segment that is out.
    seg_len: usize,
    /// True when the segment that is out is the last one.
    last: bool,
    /// Bytes the server confirmed.
    done: u64,
}

impl Download {
    /// Starts the transfer: expedited for 1–4 bytes (the value read at once), segmented otherwise
    /// (the size is always indicated). The source must hold at most `u32::MAX` bytes.
    pub fn start(mux: Address, mut source: Source, out: &mut Out) -> Result<Download, Failure> {
        let len = source.len();
        let expedited = (1..=4).contains(&len);
        if expedited {
            let mut value = Vec::with_capacity(4);
            source.read_into(&mut value, 4)?;
            out.send(ClientFrame::InitiateDownloadExpedited {
                mux,
                data: ExpeditedData::new(&value),
            });
        } else {
            out.send(ClientFrame::InitiateDownloadSegmented {
                mux,
                size: Some(len as u32),
            });
        }
        Ok(Download {
            source,
            expedited,
            phase: Phase::Initiate,
            toggle: false,
            seg_len: 0,
            last: false,
            done: 0,
        })
    }

    /// Takes a server frame (aborts are handled by the caller).
    pub fn handle(&mut self, mux: Address, frame: ServerFrame, out: &mut Out) -> Step {
        match (&self.phase, frame) {
            (Phase::Initiate, ServerFrame::InitiateDownload { mux: m }) if m == mux => {
                if self.expedited {
                    return Step::Done(ClientEvent::Downloaded);
                }
                self.phase = Phase::Segment;
                self.send_segment(out)
            }
            (Phase::Segment, ServerFrame::DownloadSegment { toggle }) => {
                if toggle != self.toggle {
                    return Step::Fail(Failure::abort(AbortCode::ToggleBit));
                }
                self.done += self.seg_len as u64;
                out.progress(self.done, Some(self.source.len()));
                if self.last {
                    return Step::Done(ClientEvent::Downloaded);
                }
                self.toggle = !self.toggle;
                self.send_segment(out)
            }
            _ => Step::Fail(Failure::abort(AbortCode::InvalidCommand)),
        }
    }

    /// Sends the next segment (an empty last one for an empty download).
    fn send_segment(&mut self, out: &mut Out) -> Step {
        let mut data = Vec::with_capacity(7);
        if let Err(f) = self.source.read_into(&mut data, 7) {
            return Step::Fail(f);
        }
        self.seg_len = data.len();
        self.last = self.source.remaining() == 0;
        out.send(ClientFrame::DownloadSegment {
            toggle: self.toggle,
            data: SegmentData::new(&data),
            last: self.last,
        });
        Step::Wait
    }
}
