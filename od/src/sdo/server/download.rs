//! Expedited and segmented SDO download, server side (CiA 301 §7.2.4.3.3 "Initiate SDO download",
//! §7.2.4.3.4 "Download SDO segment"), and the length limit every download is held to.

use super::{Reply, ServerConfig, ServerEvent, Step, Transfer};
use crate::abort::AbortCode;
use crate::sdo::frame::{Address, ClientFrame, ExpeditedData, ServerFrame};
use crate::sdo::store::{DownloadCapacity, ObjectStore};

/// The most bytes a download may bring, and the abort code of more.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Limit {
    /// The most bytes.
    max: usize,
    /// The answer to more: 0x06070012 when the entry's own size is exceeded, 0x05040005 beyond the
    /// server's DOMAIN limit.
    over: AbortCode,
    /// True for a fixed-size type: `max` is also the least.
    fixed: bool,
}

impl Limit {
    /// The limit of an entry with `capacity` on a server that buffers at most `domain_limit` bytes.
    pub(super) fn new(capacity: DownloadCapacity, domain_limit: usize) -> Limit {
        let (max, fixed) = match capacity {
            DownloadCapacity::Fixed(n) => (n, true),
            DownloadCapacity::UpTo(n) => (n, false),
            DownloadCapacity::Unbounded => (usize::MAX, false),
        };
        if max > domain_limit {
            Limit {
                max: domain_limit,
                over: AbortCode::OutOfMemory,
                fixed: false,
            }
        } else {
            Limit {
                max,
                over: AbortCode::LengthTooHigh,
                fixed,
            }
        }
    }

    /// Checks the size a client announces (before any data).
    pub(super) fn check_announced(&self, size: u32) -> Result<(), AbortCode> {
        let size = u64::from(size);
        let max = self.max as u64;
        if size > max {
            Err(self.over)
        } else if self.fixed && size < max {
            Err(AbortCode::LengthTooLow)
        } else {
            Ok(())
        }
    }

    /// Checks the number of bytes received so far.
    pub(super) fn check_len(&self, len: usize) -> Result<(), AbortCode> {
        if len > self.max {
            Err(self.over)
        } else {
            Ok(())
        }
    }
}

/// Checks the bytes received so far against the size the client announced.
pub(super) fn check_against_announced(len: usize, size: Option<u32>) -> Result<(), AbortCode> {
    match size {
        Some(size) if len as u64 > u64::from(size) => Err(AbortCode::LengthTooHigh),
        _ => Ok(()),
    }
}

/// Checks the whole data against the size the client announced.
pub(super) fn check_complete(len: usize, size: Option<u32>) -> Result<(), AbortCode> {
    check_against_announced(len, size)?;
    match size {
        Some(size) if (len as u64) < u64::from(size) => Err(AbortCode::LengthTooLow),
        _ => Ok(()),
    }
}

/// Expedited download (e = 1): the value is in the initiate frame. Without the size indicated (s = 0)
/// the entry's fixed size is taken when it is at most four bytes, all four bytes otherwise.
pub(super) fn expedited(
    mux: Address,
    data: ExpeditedData,
    store: &mut impl ObjectStore,
    config: &ServerConfig,
) -> Step {
    let capacity = store.download_capacity(mux)?;
    let limit = Limit::new(capacity, config.domain_limit);
    let bytes = data.as_slice();
    let bytes = match capacity {
        DownloadCapacity::Fixed(n) if !data.size_known() => bytes.get(..n).unwrap_or(bytes),
        _ => bytes,
    };
    limit.check_len(bytes.len())?;
    store.download(mux, bytes)?;
    Ok(Reply::send(ServerFrame::InitiateDownload { mux }).finish(ServerEvent::Downloaded { mux }))
}

/// Initiate of a segmented download (e = 0): checks the entry and the announced size, buffers nothing.
pub(super) fn initiate(
    mux: Address,
    size: Option<u32>,
    store: &mut impl ObjectStore,
    config: &ServerConfig,
) -> Step {
    let limit = Limit::new(store.download_capacity(mux)?, config.domain_limit);
    if let Some(size) = size {
        limit.check_announced(size)?;
    }
    Ok(
        Reply::send(ServerFrame::InitiateDownload { mux }).then(Transfer::Download(Segmented {
            mux,
            toggle: false,
            size,
            limit,
            data: Vec::new(),
        })),
    )
}

/// A segmented download waiting for its next segment (CiA 301 §7.2.4.3.4).
#[derive(Debug, Clone)]
pub(super) struct Segmented {
    /// The entry.
    pub(super) mux: Address,
    /// The toggle bit the next segment must carry (0 on the first).
    toggle: bool,
    /// The size the client announced.
    size: Option<u32>,
    /// The length limit.
    limit: Limit,
    /// The data so far.
    data: Vec<u8>,
}

impl Segmented {
    /// The next frame of the transfer: a download segment. The entry is written when the last one has
    /// come and the whole data is good.
    pub(super) fn frame(mut self, frame: ClientFrame, store: &mut impl ObjectStore) -> Step {
        let ClientFrame::DownloadSegment { toggle, data, last } = frame else {
            return Err(AbortCode::InvalidCommand);
        };
        if toggle != self.toggle {
            return Err(AbortCode::ToggleBit);
        }
        let len = self.data.len() + data.len();
        check_against_announced(len, self.size)?;
        self.limit.check_len(len)?;
        self.data.extend_from_slice(data.as_slice());
        let reply = Reply::send(ServerFrame::DownloadSegment { toggle });
        if !last {
            self.toggle = !toggle;
            return Ok(reply.then(Transfer::Download(self)));
        }
        check_complete(len, self.size)?;
        store.download(self.mux, &self.data)?;
        Ok(reply.finish(ServerEvent::Downloaded { mux: self.mux }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_by_capacity() {
        let fixed = Limit::new(DownloadCapacity::Fixed(2), 1 << 20);
        assert_eq!(fixed.check_announced(2), Ok(()));
        assert_eq!(fixed.check_announced(3), Err(AbortCode::LengthTooHigh));
        assert_eq!(fixed.check_announced(1), Err(AbortCode::LengthTooLow));

        let string = Limit::new(DownloadCapacity::UpTo(10), 1 << 20);
        assert_eq!(string.check_announced(0), Ok(()));
        assert_eq!(string.check_announced(10), Ok(()));
        assert_eq!(string.check_announced(11), Err(AbortCode::LengthTooHigh));
        assert_eq!(string.check_len(11), Err(AbortCode::LengthTooHigh));

        let domain = Limit::new(DownloadCapacity::Unbounded, 100);
        assert_eq!(domain.check_announced(100), Ok(()));
        assert_eq!(domain.check_announced(101), Err(AbortCode::OutOfMemory));
        assert_eq!(
            domain.check_announced(u32::MAX),
            Err(AbortCode::OutOfMemory)
        );
        assert_eq!(domain.check_len(101), Err(AbortCode::OutOfMemory));

        // An entry larger than the server buffers is held to the server's limit.
        let big = Limit::new(DownloadCapacity::UpTo(1000), 100);
        assert_eq!(big.check_announced(101), Err(AbortCode::OutOfMemory));
    }

    #[test]
    fn announced_size_checks() {
        assert_eq!(check_against_announced(5, Some(5)), Ok(()));
        assert_eq!(
            check_against_announced(6, Some(5)),
            Err(AbortCode::LengthTooHigh)
        );
        assert_eq!(check_against_announced(6, None), Ok(()));
        assert_eq!(check_complete(4, Some(5)), Err(AbortCode::LengthTooLow));
        assert_eq!(check_complete(4, None), Ok(()));
    }
}
