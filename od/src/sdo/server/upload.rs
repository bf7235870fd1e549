//! Expedited and segmented SDO upload, server side (CiA 301 §7.2.4.3.6 "Initiate SDO upload",
//! §7.2.4.3.7 "Upload SDO segment").

use super::{Reply, ServerEvent, Step, Transfer};
use crate::abort::AbortCode;
use crate::sdo::frame::{Address, ClientFrame, ExpeditedData, SegmentData, ServerFrame};
use crate::sdo::store::ObjectStore;

/// Initiate SDO upload: reads the entry and answers.
pub(super) fn initiate(mux: Address, store: &mut impl ObjectStore) -> Step {
    let data = store.upload(mux)?;
    Ok(respond(mux, data))
}

/// The initiate upload response for `data`: expedited for one to four bytes (s = 1, n), segmented with the
/// size indicated otherwise (an empty value too: an expedited frame cannot say "no byte").
pub(super) fn respond(mux: Address, data: Vec<u8>) -> Reply {
    if (1..=4).contains(&data.len()) {
        return Reply::send(ServerFrame::InitiateUploadExpedited {
            mux,
            data: ExpeditedData::new(&data),
        })
        .finish(ServerEvent::Uploaded { mux });
    }
    let size = u32::try_from(data.len()).ok();
    Reply::send(ServerFrame::InitiateUploadSegmented { mux, size }).then(Transfer::Upload(
        Segmented {
            mux,
            toggle: false,
            data,
            sent: 0,
        },
    ))
}

/// A segmented upload waiting for the next segment request (CiA 301 §7.2.4.3.7).
#[derive(Debug, Clone)]
pub(super) struct Segmented {
    /// The entry.
    pub(super) mux: Address,
    /// The toggle bit the next request must carry (0 on the first).
    toggle: bool,
    /// The value.
    data: Vec<u8>,
    /// Bytes sent so far.
    sent: usize,
}

impl Segmented {
    /// The next frame of the transfer: an upload segment request, answered with up to seven bytes.
    pub(super) fn frame(mut self, frame: ClientFrame) -> Step {
        let ClientFrame::UploadSegment { toggle } = frame else {
            return Err(AbortCode::InvalidCommand);
        };
        if toggle != self.toggle {
            return Err(AbortCode::ToggleBit);
        }
        let rest = self.data.get(self.sent..).unwrap_or_default();
        let chunk = SegmentData::new(rest);
        let last = chunk.len() == rest.len();
        self.sent += chunk.len();
        self.toggle = !toggle;
        let reply = Reply::send(ServerFrame::UploadSegment {
            toggle,
            data: chunk,
            last,
        });
        Ok(if last {
            reply.finish(ServerEvent::Uploaded { mux: self.mux })
        } else {
            reply.then(Transfer::Upload(self))
        })
    }
}
