//! The SDO side of the [`Watcher`]: the transfers it follows (expedited, segmented and block ones,
//! each node's one at a time), reassembled into one line with the value, and those left open.

use od::abort::AbortCode;
use od::dict::Address;

use super::{Kind, Watcher};

/// An SDO transfer seen going on, for one node.
#[derive(Debug, Clone)]
pub(super) struct Transfer {
    mux: Address,
    upload: bool,
    block: bool,
    data: Vec<u8>,
    /// A block transfer's progress.
    sub_block: SubBlock,
    /// The size the initiate announced, when it did.
    size: Option<u32>,
    /// The server answered the initiate of an upload (segmented from then on).
    answered: bool,
    /// The time of the transfer's last frame.
    last: f64,
}

impl Transfer {
    /// A transfer begun by the client's initiate `d` at `now`; its size when the initiate's `s` bit
    /// (bit 0 for a download, bit 1 for a block download) says bytes 4–7 hold it.
    fn begun(mux: Address, upload: bool, block: bool, d: &[u8], now: f64) -> Transfer {
        let s_bit = if block { 0x02 } else { 0x01 };
        let size =
            (!upload && d[0] & s_bit != 0).then(|| u32::from_le_bytes([d[4], d[5], d[6], d[7]]));
        Transfer {
            mux,
            upload,
            block,
            data: Vec::new(),
            sub_block: SubBlock::default(),
            size,
            answered: false,
            last: now,
        }
    }

    /// What kind of transfer it is, in words.
    fn kind(&self) -> &'static str {
        match (self.block, self.upload, self.answered) {
            (true, true, _) => "block upload",
            (true, false, _) => "block download",
            (false, true, true) => "segmented upload",
            // The server has not said yet whether the value comes in the answer or in segments.
            (false, true, false) => "upload",
            (false, false, _) => "segmented download",
        }
    }

    /// Whether a frame with command specifier `cs` from the client (`request`) or the server is one
    /// of this segmented transfer's, beyond the initiates and segments taken elsewhere: the
    /// client's upload segment requests and the server's download segment answers.
    fn paces(&self, request: bool, cs: u8) -> bool {
        if self.upload {
            request && cs == 3
        } else {
            !request && cs == 1
        }
    }
}

/// An SDO transfer still going on: what [`Watcher::open_transfers`] reports at the end.
#[derive(Debug, Clone, PartialEq)]
pub struct OpenTransfer {
    /// The node.
    pub node: u8,
    /// The entry transferred.
    pub address: Address,
    /// `index:sub (name)`, with the description's name where it has one.
    pub named: String,
    /// `segmented upload`, `segmented download`, `block upload`, `block download`, or `upload` when
    /// the server has not answered the initiate.
    pub kind: &'static str,
    /// The data bytes taken so far (of a block transfer, those acknowledged).
    pub bytes: usize,
    /// The size the initiate announced, when it did.
    pub size: Option<u32>,
    /// The time of its last frame, in the watcher's seconds.
    pub last: f64,
}

impl std::fmt::Display for OpenTransfer {
    /// `node 3: SDO segmented upload of 0x1008:00 (Manufacturer device name) left open: 7 of 24
    /// bytes so far, its last frame at 0.313000`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "node {}: SDO {} of {} left open: {}",
            self.node, self.kind, self.named, self.bytes
        )?;
        if let Some(size) = self.size {
            write!(f, " of {size}")?;
        }
        write!(f, " bytes so far, its last frame at {:.6}", self.last)
    }
}

/// What an observer of a block transfer keeps (CiA 301 §7.2.4.3.9–16): the data side's segments of
/// the sub-block going on until the other side acknowledges them.
#[derive(Debug, Clone, Default)]
pub(super) struct SubBlock {
    /// The segments of the sub-block as they came: sequence number, last, the 7 bytes.
    pending: Vec<(u8, bool, [u8; 7])>,
    /// The last segment was acknowledged: the data side's next frame is the end, with the number
    /// of bytes of the last segment that carry no data.
    all_in: bool,
}

impl Watcher {
    /// An SDO frame of node `id`, `request` from the client (0x600 + id) or not (0x580 + id).
    pub(super) fn sdo(&mut self, id: u8, request: bool, d: &[u8]) -> Option<String> {
        if d.len() != 8 {
            return None;
        }
        let mux = Address::new(u16::from_le_bytes([d[1], d[2]]), d[3]);
        let cs = d[0] >> 5;
        let mut aborted = cs == 4;
        if self.transfers.get(&id).is_some_and(|t| t.block) {
            match self.block_frame(id, request, d) {
                Some(line) => return line,
                None => aborted = true,
            }
        }
        // An abort, from either side, ends the transfer.
        if aborted {
            self.transfers.remove(&id);
            let code = AbortCode::from(u32::from_le_bytes([d[4], d[5], d[6], d[7]]));
            return Some(format!(
                "node {id}: SDO {} aborts {}: {code}",
                if request { "client" } else { "server" },
                self.named(mux)
            ));
        }
        // Taken out (not copied: a long segmented transfer would be copied at every segment) and
        // put back by whatever leaves it going on.
        let t = self.transfers.remove(&id);
        if request {
            self.client_frame(id, mux, d, t)
        } else {
            self.server_frame(id, mux, d, t)
        }
    }

    /// A frame of node `id`'s block transfer (CiA 301 §7.2.4.3.9–16): the frames of the side that
    /// sends the data are segments (sequence number and last bit; 0x80, sequence 0, is an abort),
    /// then the end with n; the other side acknowledges sub-blocks (0xA2 with the last segment in
    /// sequence) and ends it with 0xA1. `Some` with the frame's line, if it has one; `None` when the
    /// frame aborts the transfer, which is then gone.
    fn block_frame(&mut self, id: u8, request: bool, d: &[u8]) -> Option<Option<String>> {
        let mut t = self.transfers.remove(&id).expect("looked up");
        t.last = self.now;
        let b = &mut t.sub_block;
        if request != t.upload {
            if d[0] == 0x80 && !b.all_in {
                return None;
            }
            // The server's initiate answer of an upload (0xC0 with s and sc bits), before any
            // segment: the size when it gives one.
            if t.upload && !t.answered && b.pending.is_empty() && d[0] & 0xE1 == 0xC0 {
                t.answered = true;
                if d[0] & 0x02 != 0 {
                    t.size = Some(u32::from_le_bytes([d[4], d[5], d[6], d[7]]));
                }
            }
            if !b.all_in {
                // A segment. The server's initiate answer of an upload, before the client's start,
                // comes here too; its sequence number (0x40 to 0x46) is never the next one an
                // acknowledgement takes.
                let mut bytes = [0u8; 7];
                bytes.copy_from_slice(&d[1..8]);
                b.pending.push((d[0] & 0x7F, d[0] & 0x80 != 0, bytes));
            } else if d[0] & 0xE3 == 0xC1 {
                let n = usize::from((d[0] >> 2) & 0x07);
                t.data.truncate(t.data.len().saturating_sub(n));
            }
            self.transfers.insert(id, t);
            return Some(None);
        }
        match d[0] {
            0xA1 => {
                return Some(Some(format!(
                    "node {id}: SDO {} {} = {} ({} bytes, block transfer)",
                    if t.upload { "read" } else { "written" },
                    self.named(t.mux),
                    self.value(t.mux, &t.data),
                    t.data.len()
                )));
            }
            // The acknowledgement: the segments up to the last one in sequence are in.
            0xA2 => {
                let mut next = 1u8;
                for (seq, last, bytes) in std::mem::take(&mut b.pending) {
                    if seq == next && seq <= d[1] {
                        t.data.extend_from_slice(&bytes);
                        b.all_in |= last;
                        next = next.saturating_add(1);
                    }
                }
            }
            _ => {}
        }
        if d[0] >> 5 == 4 {
            return None;
        }
        self.transfers.insert(id, t);
        Some(None)
    }

    /// A client's frame (0x600 + `id`) that is no abort and no block transfer's going on; `t`, the
    /// transfer going on, taken out.
    fn client_frame(
        &mut self,
        id: u8,
        mux: Address,
        d: &[u8],
        t: Option<Transfer>,
    ) -> Option<String> {
        let cs = d[0] >> 5;
        match (cs, t) {
            // Initiate download: expedited (the value in the frame) or the size announced.
            (1, _) => match expedited(d) {
                Some(data) => Some(format!(
                    "node {id}: SDO write {} = {}",
                    self.named(mux),
                    self.value(mux, data)
                )),
                None => self.begin(id, mux, false, false, d),
            },
            (2, _) => self.begin(id, mux, true, false, d),
            // Block download (0xC0–0xC7 with bit 0 clear) or upload (0xA0, 0xA4) begun by the client.
            (6, _) if d[0] & 0x01 == 0 => self.begin(id, mux, false, true, d),
            (5, _) if d[0] & 0x03 == 0 => self.begin(id, mux, true, true, d),
            // Download segment: data after byte 0, 7 − n of them, c = last.
            (0, Some(t)) if !t.upload && !t.block => self.segment(id, t, d, "write"),
            (_, t) => self.keep(id, t, true, cs),
        }
    }

    /// A server's frame (0x580 + `id`) that is no abort and no block transfer's going on; `t`, the
    /// transfer going on, taken out.
    fn server_frame(
        &mut self,
        id: u8,
        mux: Address,
        d: &[u8],
        t: Option<Transfer>,
    ) -> Option<String> {
        let cs = d[0] >> 5;
        match (cs, t) {
            // Initiate upload response: expedited, or the size of what follows.
            (2, t) => match expedited(d) {
                Some(data) => Some(format!(
                    "node {id}: SDO read {} = {}",
                    self.named(mux),
                    self.value(mux, data)
                )),
                None => {
                    if let Some(mut t) = t {
                        // The answer to the upload going on: segments follow, the size when `s`
                        // says bytes 4–7 hold it.
                        if t.upload && !t.block {
                            t.answered = true;
                            t.last = self.now;
                            if d[0] & 0x01 != 0 {
                                t.size = Some(u32::from_le_bytes([d[4], d[5], d[6], d[7]]));
                            }
                        }
                        self.transfers.insert(id, t);
                    }
                    None
                }
            },
            // Initiate download response: the end of an expedited download; a segmented one goes on.
            (3, Some(mut t)) if !t.upload && !t.block => {
                t.last = self.now;
                self.transfers.insert(id, t);
                None
            }
            (3, _) => Some(format!("node {id}: SDO written {}", self.named(mux))),
            // Upload segment: data after byte 0, 7 − n of them, c = last.
            (0, Some(t)) if t.upload && !t.block => self.segment(id, t, d, "read"),
            (_, t) => self.keep(id, t, false, cs),
        }
    }

    /// A transfer begun by the client's initiate `d`: followed from now on.
    fn begin(
        &mut self,
        id: u8,
        mux: Address,
        upload: bool,
        block: bool,
        d: &[u8],
    ) -> Option<String> {
        let t = Transfer::begun(mux, upload, block, d, self.now);
        self.transfers.insert(id, t);
        None
    }

    /// A segment of `t` (data after byte 0, 7 − n of them, c = last): the line once the last is in.
    fn segment(&mut self, id: u8, mut t: Transfer, d: &[u8], what: &str) -> Option<String> {
        t.last = self.now;
        let (data, last) = segment(d);
        t.data.extend_from_slice(data);
        if !last {
            self.transfers.insert(id, t);
            return None;
        }
        Some(format!(
            "node {id}: SDO {what} {} = {} ({} bytes, segmented)",
            self.named(t.mux),
            self.value(t.mux, &t.data),
            t.data.len()
        ))
    }

    /// Any other frame: the transfer going on, if any, goes on, its time moved on by a frame that
    /// paces it.
    fn keep(&mut self, id: u8, t: Option<Transfer>, request: bool, cs: u8) -> Option<String> {
        if let Some(mut t) = t {
            if t.paces(request, cs) {
                t.last = self.now;
            }
            self.transfers.insert(id, t);
        }
        None
    }

    /// The SDO transfers still going on, by node (none when SDO lines are not shown): what a log
    /// that ends, or a watch that stops, leaves open.
    pub fn open_transfers(&self) -> Vec<OpenTransfer> {
        if !self.shows(Kind::Sdo) {
            return Vec::new();
        }
        let mut open: Vec<OpenTransfer> = self
            .transfers
            .iter()
            .map(|(&node, t)| OpenTransfer {
                node,
                address: t.mux,
                named: self.named(t.mux),
                kind: t.kind(),
                bytes: t.data.len(),
                size: t.size,
                last: t.last,
            })
            .collect();
        open.sort_by_key(|o| o.node);
        open
    }
}

/// The data bytes of an expedited initiate frame (byte 0 with `e`, `s` and `n`; CiA 301
/// §7.2.4.3.3/6): 4 − n with the size indicated, all 4 without; `None` when not expedited.
fn expedited(d: &[u8]) -> Option<&[u8]> {
    let (e, s) = (d[0] & 0x02 != 0, d[0] & 0x01 != 0);
    e.then(|| {
        let n = if s { usize::from((d[0] >> 2) & 3) } else { 0 };
        &d[4..8 - n]
    })
}

/// A segment's data (byte 0 with `n` of the 7 bytes unused) and whether it is the last (`c`).
fn segment(d: &[u8]) -> (&[u8], bool) {
    let n = usize::from((d[0] >> 1) & 7);
    (&d[1..8 - n], d[0] & 0x01 != 0)
}
