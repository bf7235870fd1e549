//! `sdo-tool watch` and `sdo-tool decode`: what goes on on the bus, in words — NMT commands,
//! boot-up messages, heartbeats and the state changes they show, SYNC, EMCY messages with their error
//! code's meaning, SDO transfers (expedited, segmented and block ones reassembled into one line with
//! the value — a block transfer's sub-blocks as their acknowledgements take them, so a segment sent
//! again counts once — aborts with their code's meaning), and a node's PDOs (TPDOs and RPDOs)
//! decoded field by field from its mapping in a description. A frame that is none of these is shown
//! as it is when raw frames are asked for. candump's COB-ID filters and a choice of kinds narrow
//! what is looked at and shown.

use std::collections::{HashMap, VecDeque};
use std::io::BufRead;

use od::dict::Dictionary;
use od::types::DataType;
use od::value::Value;

use crate::link::{CanFrame, EmcyCode, PdoConfig, RPDO_COMM, TPDO_COMM};
use crate::TypeCode;
use od::abort::AbortCode;
use od::dict::Address;

/// A frame filter by COB-ID, as candump takes them (IDs in hex, with or without `0x`):
/// `ID:MASK` passes a frame whose ID matches ID in the bits of MASK, `LOW-HIGH` a range, `ID` one
/// identifier; a leading `~` inverts any of them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CobFilter {
    /// The lowest identifier that passes (with `mask`: the identifier to match).
    low: u16,
    /// The highest (with `mask`: unused).
    high: u16,
    /// `ID:MASK`'s mask.
    mask: Option<u16>,
    /// `~`: what does not match passes.
    invert: bool,
}

impl CobFilter {
    /// Whether `cob` passes this filter.
    pub fn passes(&self, cob: u16) -> bool {
        let hit = match self.mask {
            Some(m) => cob & m == self.low & m,
            None => (self.low..=self.high).contains(&cob),
        };
        hit != self.invert
    }
}

impl std::str::FromStr for CobFilter {
    type Err = String;

    fn from_str(text: &str) -> Result<CobFilter, String> {
        let bad = || {
            format!(
                "filter {text:?} is not ID, ID:MASK or LOW-HIGH (hex CAN identifiers up to 7FF, \
                 ~ before it to invert)"
            )
        };
        let t = text.trim();
        let (invert, t) = match t.strip_prefix('~') {
            Some(rest) => (true, rest),
            None => (false, t),
        };
        let id = |x: &str| {
            let x = x.trim();
            let h = x
                .strip_prefix("0x")
                .or_else(|| x.strip_prefix("0X"))
                .unwrap_or(x);
            u16::from_str_radix(h, 16).ok().filter(|v| *v <= 0x7FF)
        };
        let (low, high, mask) = if let Some((a, m)) = t.split_once(':') {
            let a = id(a).ok_or_else(bad)?;
            (a, a, Some(id(m).ok_or_else(bad)?))
        } else if let Some((a, b)) = t.split_once('-') {
            let (a, b) = (id(a).ok_or_else(bad)?, id(b).ok_or_else(bad)?);
            if a > b {
                return Err(bad());
            }
            (a, b, None)
        } else {
            let a = id(t).ok_or_else(bad)?;
            (a, a, None)
        };
        Ok(CobFilter {
            low,
            high,
            mask,
            invert,
        })
    }
}

/// What a frame (or a line about a node) is, for `--only`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    /// NMT commands (0x000).
    Nmt,
    /// Heartbeats and boot-up messages (0x701–0x77F), and a heartbeat missed.
    Heartbeat,
    /// SYNC (0x080).
    Sync,
    /// EMCY (0x081–0x0FF).
    Emcy,
    /// SDO (0x581–0x5FF, 0x601–0x67F).
    Sdo,
    /// A PDO of the node's mapping.
    Pdo,
    /// Anything else (shown with `--raw`).
    Other,
}

impl std::str::FromStr for Kind {
    type Err = String;

    fn from_str(text: &str) -> Result<Kind, String> {
        Ok(match text.trim().to_ascii_lowercase().as_str() {
            "nmt" => Kind::Nmt,
            "heartbeat" | "hb" => Kind::Heartbeat,
            "sync" => Kind::Sync,
            "emcy" => Kind::Emcy,
            "sdo" => Kind::Sdo,
            "pdo" => Kind::Pdo,
            "other" | "raw" => Kind::Other,
            _ => {
                return Err(format!(
                    "{text:?} is not nmt, heartbeat, sync, emcy, sdo, pdo or other"
                ))
            }
        })
    }
}

/// The NMT state a heartbeat byte names.
pub fn nmt_state_name(byte: u8) -> &'static str {
    match byte & 0x7F {
        0x00 => "boot-up",
        0x04 => "stopped",
        0x05 => "operational",
        0x7F => "pre-operational",
        _ => "unknown state",
    }
}

/// One decoded PDO: its kind and number, and the mapped entries with their names and types.
#[derive(Debug, Clone)]
struct PdoLayout {
    kind: &'static str,
    number: u16,
    fields: Vec<(String, DataType, usize)>,
}

/// An SDO transfer seen going on, for one node.
#[derive(Debug, Clone)]
struct Transfer {
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
struct SubBlock {
    /// The segments of the sub-block as they came: sequence number, last, the 7 bytes.
    pending: Vec<(u8, bool, [u8; 7])>,
    /// The last segment was acknowledged: the data side's next frame is the end, with the number
    /// of bytes of the last segment that carry no data.
    all_in: bool,
}

/// Decodes the bus's frames into lines.
pub struct Watcher {
    node: Option<u8>,
    last_state: HashMap<u8, u8>,
    pdos: HashMap<u16, PdoLayout>,
    od: Option<Dictionary>,
    transfers: HashMap<u8, Transfer>,
    raw: bool,
    /// Per node: its last heartbeat's time, the period seen between its last two, whether its
    /// silence was reported, and whether the last was a boot-up message.
    beats: HashMap<u8, (f64, Option<f64>, bool, bool)>,
    /// The frames taken (any filter passing; every frame when there is none).
    filters: Vec<CobFilter>,
    /// The kinds shown (every kind when empty).
    only: Vec<Kind>,
    /// The time of the frame being looked at ([`Watcher::at`]'s).
    now: f64,
}

impl Watcher {
    /// Watches `node` (or every node), decoding its TPDOs from `od` when given.
    pub fn new(node: Option<u8>, od: Option<&Dictionary>) -> Watcher {
        let mut pdos = HashMap::new();
        if let (Some(node), Some(od)) = (node, od) {
            let mut d = od.clone();
            d.reset(node);
            for (kind, comm, k) in (0..512u16)
                .map(|k| ("TPDO", TPDO_COMM, k))
                .chain((0..512u16).map(|k| ("RPDO", RPDO_COMM, k)))
            {
                let Some(pdo) = PdoConfig::read(&d, comm + k).filter(PdoConfig::valid) else {
                    continue;
                };
                let fields = pdo
                    .map
                    .iter()
                    .map(|e| {
                        // A dummy entry (a data type's index) fills bytes, nothing else.
                        if e.index < 0x1000 {
                            return ("Dummy".to_string(), DataType::Unsigned8, e.len());
                        }
                        let (name, ty) = match d.entry(e.index, e.sub) {
                            Ok(entry) => (entry.name.clone(), entry.data_type),
                            Err(_) => (
                                od::Address::new(e.index, e.sub).to_string(),
                                DataType::Unsigned8,
                            ),
                        };
                        (name, ty, e.len())
                    })
                    .collect();
                pdos.insert(
                    pdo.cob_id(),
                    PdoLayout {
                        kind,
                        number: k + 1,
                        fields,
                    },
                );
            }
        }
        Watcher {
            node,
            last_state: HashMap::new(),
            pdos,
            od: od.cloned(),
            transfers: HashMap::new(),
            raw: false,
            beats: HashMap::new(),
            filters: Vec::new(),
            only: Vec::new(),
            now: 0.0,
        }
    }

    /// Takes only the frames one of `filters` passes (all when empty), as candump's filters do:
    /// the others are not looked at at all.
    pub fn with_filters(mut self, filters: Vec<CobFilter>) -> Watcher {
        self.filters = filters;
        self
    }

    /// Shows only lines of `kinds` (all when empty).
    pub fn with_only(mut self, kinds: Vec<Kind>) -> Watcher {
        self.only = kinds;
        self
    }

    /// Whether the filters take `frame` (one without an 11-bit identifier only when there are
    /// none).
    pub fn takes(&self, frame: &CanFrame) -> bool {
        match frame.cob_id() {
            Some(cob) => self.filters.is_empty() || self.filters.iter().any(|f| f.passes(cob)),
            None => self.filters.is_empty(),
        }
    }

    fn shows(&self, kind: Kind) -> bool {
        self.only.is_empty() || self.only.contains(&kind)
    }

    /// The kind of a frame of `cob`.
    fn kind(&self, cob: u16) -> Kind {
        match cob {
            _ if self.pdos.contains_key(&cob) => Kind::Pdo,
            0x000 => Kind::Nmt,
            0x080 => Kind::Sync,
            0x081..=0x0FF => Kind::Emcy,
            0x581..=0x5FF | 0x601..=0x67F => Kind::Sdo,
            0x700..=0x77F => Kind::Heartbeat,
            _ => Kind::Other,
        }
    }

    /// The lines for `frame` received at `t` (seconds): first the heartbeats found missing by then
    /// ([`Watcher::missed`]), then the frame's own.
    pub fn at(&mut self, t: f64, frame: &CanFrame) -> Vec<String> {
        self.now = t;
        let mut lines = self.missed(t);
        if !self.takes(frame) {
            return lines;
        }
        // A heartbeat has one data byte; a remote frame on its identifier has none, whatever its
        // length.
        if let (Some(c @ 0x701..=0x77F), [state]) = (frame.cob_id(), frame.data()) {
            let id = (c & 0x7F) as u8;
            let boot = *state == 0;
            // A period is between two heartbeats: not from a boot-up message to the first.
            let period = match self.beats.get(&id) {
                Some((last, _, _, false)) if !boot => Some(t - *last).filter(|p| *p > 0.0),
                _ => None,
            };
            self.beats.insert(id, (t, period, false, boot));
        }
        lines.extend(self.taken_line(frame));
        lines
    }

    /// A line for each watched node whose heartbeat has not come for more than twice the period seen
    /// between its last two beats (a consumer time of twice the producer's, as CiA 301 systems are
    /// commonly set up), once per silence.
    pub fn missed(&mut self, t: f64) -> Vec<String> {
        let mut lines = Vec::new();
        if !self.shows(Kind::Heartbeat) {
            return lines;
        }
        let mut ids: Vec<u8> = self.beats.keys().copied().collect();
        ids.sort_unstable();
        for id in ids {
            if !self.wanted(id) {
                continue;
            }
            let Some((last, Some(period), reported, _)) = self.beats.get_mut(&id) else {
                continue;
            };
            // More than twice the period (a microsecond of rounding aside).
            if !*reported && t - *last > 2.0 * *period + 1e-6 {
                *reported = true;
                lines.push(format!(
                    "node {id}: heartbeat missed: none for {:.3} s (period {:.3} s)",
                    t - *last,
                    period
                ));
            }
        }
        lines
    }

    /// Also shows the frames it cannot name, as `ID#DATA`.
    pub fn with_raw(mut self, raw: bool) -> Watcher {
        self.raw = raw;
        self
    }

    /// `index:sub (name)` with the description's name where it has one.
    fn named(&self, mux: Address) -> String {
        match self
            .od
            .as_ref()
            .and_then(|d| d.entry(mux.index, mux.sub).ok())
        {
            Some(e) => format!("{mux} ({})", e.name),
            None => mux.to_string(),
        }
    }

    /// `bytes` as a value of `mux`'s type in the description, else as hex bytes.
    fn value(&self, mux: Address, bytes: &[u8]) -> String {
        let typed = self
            .od
            .as_ref()
            .and_then(|d| d.entry(mux.index, mux.sub).ok())
            .and_then(|e| {
                Value::decode(e.data_type, bytes)
                    .ok()
                    .map(|v| TypeCode::of(e.data_type).format(&v))
            });
        typed.unwrap_or_else(|| hex(bytes))
    }

    /// An SDO frame of node `id`, `request` from the client (0x600 + id) or not (0x580 + id).
    fn sdo(&mut self, id: u8, request: bool, d: &[u8]) -> Option<String> {
        if d.len() != 8 {
            return None;
        }
        let mux = Address::new(u16::from_le_bytes([d[1], d[2]]), d[3]);
        let cs = d[0] >> 5;
        let who = format!("node {id}: SDO");
        // A block transfer (CiA 301 §7.2.4.3.9–16): the frames of the side that sends the data are
        // segments (sequence number and last bit; 0x80, sequence 0, is an abort), then the end
        // with n; the other side acknowledges sub-blocks (0xA2 with the last segment in sequence)
        // and ends it with 0xA1.
        let mut aborted = cs == 4;
        if self.transfers.get(&id).is_some_and(|t| t.block) {
            let mut t = self.transfers.remove(&id).expect("looked up");
            t.last = self.now;
            let b = &mut t.sub_block;
            if request != t.upload {
                aborted = d[0] == 0x80 && !b.all_in;
                if !aborted {
                    // The server's initiate answer of an upload (0xC0 with s and sc bits), before
                    // any segment: the size when it gives one.
                    if t.upload && !t.answered && b.pending.is_empty() && d[0] & 0xE1 == 0xC0 {
                        t.answered = true;
                        if d[0] & 0x02 != 0 {
                            t.size = Some(u32::from_le_bytes([d[4], d[5], d[6], d[7]]));
                        }
                    }
                    if !b.all_in {
                        // A segment. The server's initiate answer of an upload, before the
                        // client's start, comes here too; its sequence number (0x40 to 0x46) is
                        // never the next one an acknowledgement takes.
                        let mut bytes = [0u8; 7];
                        bytes.copy_from_slice(&d[1..8]);
                        b.pending.push((d[0] & 0x7F, d[0] & 0x80 != 0, bytes));
                    } else if d[0] & 0xE3 == 0xC1 {
                        let n = usize::from((d[0] >> 2) & 0x07);
                        t.data.truncate(t.data.len().saturating_sub(n));
                    }
                    self.transfers.insert(id, t);
                    return None;
                }
            } else {
                match d[0] {
                    0xA1 => {
                        return Some(format!(
                            "{who} {} {} = {} ({} bytes, block transfer)",
                            if t.upload { "read" } else { "written" },
                            self.named(t.mux),
                            self.value(t.mux, &t.data),
                            t.data.len()
                        ));
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
                if !aborted {
                    self.transfers.insert(id, t);
                    return None;
                }
            }
        }
        // An abort, from either side, ends the transfer.
        if aborted {
            self.transfers.remove(&id);
            let code = AbortCode::from(u32::from_le_bytes([d[4], d[5], d[6], d[7]]));
            return Some(format!(
                "{who} {} aborts {}: {code}",
                if request { "client" } else { "server" },
                self.named(mux)
            ));
        }
        // Taken out (not copied: a long segmented transfer would be copied at every segment) and
        // put back by whatever leaves it going on.
        let t = self.transfers.remove(&id);
        match (request, cs, t) {
            // Initiate download: expedited (the value in the frame) or the size announced.
            (true, 1, _) => match expedited(d) {
                Some(data) => Some(format!(
                    "{who} write {} = {}",
                    self.named(mux),
                    self.value(mux, data)
                )),
                None => {
                    let t = Transfer::begun(mux, false, false, d, self.now);
                    self.transfers.insert(id, t);
                    None
                }
            },
            (true, 2, _) => {
                let t = Transfer::begun(mux, true, false, d, self.now);
                self.transfers.insert(id, t);
                None
            }
            // Block download (0xC0–0xC7 with bit 0 clear) or upload (0xA0, 0xA4) begun by the client.
            (true, 6, _) if d[0] & 0x01 == 0 => {
                let t = Transfer::begun(mux, false, true, d, self.now);
                self.transfers.insert(id, t);
                None
            }
            (true, 5, _) if d[0] & 0x03 == 0 => {
                let t = Transfer::begun(mux, true, true, d, self.now);
                self.transfers.insert(id, t);
                None
            }
            // Download segment: data after byte 0, 7 − n of them, c = last.
            (true, 0, Some(mut t)) if !t.upload && !t.block => {
                t.last = self.now;
                let (data, last) = segment(d);
                t.data.extend_from_slice(data);
                if !last {
                    self.transfers.insert(id, t);
                    return None;
                }
                let line = format!(
                    "{who} write {} = {} ({} bytes, segmented)",
                    self.named(t.mux),
                    self.value(t.mux, &t.data),
                    t.data.len()
                );
                Some(line)
            }
            // Initiate upload response: expedited, or the size of what follows.
            (false, 2, t) => match expedited(d) {
                Some(data) => Some(format!(
                    "{who} read {} = {}",
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
            (false, 3, Some(mut t)) if !t.upload && !t.block => {
                t.last = self.now;
                self.transfers.insert(id, t);
                None
            }
            (false, 3, _) => Some(format!("{who} written {}", self.named(mux))),
            // Upload segment: data after byte 0, 7 − n of them, c = last.
            (false, 0, Some(mut t)) if t.upload && !t.block => {
                t.last = self.now;
                let (data, last) = segment(d);
                t.data.extend_from_slice(data);
                if !last {
                    self.transfers.insert(id, t);
                    return None;
                }
                Some(format!(
                    "{who} read {} = {} ({} bytes, segmented)",
                    self.named(t.mux),
                    self.value(t.mux, &t.data),
                    t.data.len()
                ))
            }
            (_, _, t) => {
                if let Some(mut t) = t {
                    if t.paces(request, cs) {
                        t.last = self.now;
                    }
                    self.transfers.insert(id, t);
                }
                None
            }
        }
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

    fn wanted(&self, id: u8) -> bool {
        self.node.is_none_or(|n| n == id)
    }

    /// The line for `frame`, if it is one the watcher reports.
    pub fn line(&mut self, frame: &CanFrame) -> Option<String> {
        if !self.takes(frame) {
            return None;
        }
        self.taken_line(frame)
    }

    /// The line for `frame`, which the filters took.
    fn taken_line(&mut self, frame: &CanFrame) -> Option<String> {
        // An SDO transfer is followed even when its lines are not shown.
        let named = self.named_line(frame);
        let kind = frame.cob_id().map_or(Kind::Other, |c| self.kind(c));
        if !self.shows(kind) {
            return None;
        }
        if named.is_some() || !self.raw {
            return named;
        }
        Some(frame.to_string())
    }

    fn named_line(&mut self, frame: &CanFrame) -> Option<String> {
        let cob = frame.cob_id()?;
        let d = frame.data();
        match cob {
            0x000 if d.len() == 2 => {
                let (cs, id) = (d[0], d[1]);
                if id != 0 && !self.wanted(id) {
                    return None;
                }
                let what = match cs {
                    0x01 => "start",
                    0x02 => "stop",
                    0x80 => "enter pre-operational",
                    0x81 => "reset node",
                    0x82 => "reset communication",
                    _ => return Some(format!("NMT command 0x{cs:02X} to node {id}")),
                };
                Some(if id == 0 {
                    format!("NMT {what}: all nodes")
                } else {
                    format!("NMT {what}: node {id}")
                })
            }
            0x080 if d.len() <= 1 => Some(match d.first() {
                Some(c) => format!("SYNC {c}"),
                None => "SYNC".to_string(),
            }),
            0x701..=0x77F if d.len() == 1 => {
                let id = (cob - 0x700) as u8;
                if !self.wanted(id) {
                    return None;
                }
                let state = d[0];
                let before = self.last_state.insert(id, state & 0x7F);
                Some(match before {
                    Some(b) if b != state & 0x7F => format!(
                        "node {id}: NMT {} -> {}",
                        nmt_state_name(b),
                        nmt_state_name(state)
                    ),
                    _ if state == 0 => format!("node {id}: boot-up"),
                    _ => format!("node {id}: heartbeat, {}", nmt_state_name(state)),
                })
            }
            0x081..=0x0FF if d.len() == 8 => {
                let id = (cob - 0x80) as u8;
                if !self.wanted(id) {
                    return None;
                }
                let code = u16::from_le_bytes([d[0], d[1]]);
                Some(format!(
                    "node {id}: EMCY 0x{code:04X} ({}), error register 0x{:02X}, data {:02X} {:02X} {:02X} {:02X} {:02X}",
                    EmcyCode(code).meaning(),
                    d[2],
                    d[3],
                    d[4],
                    d[5],
                    d[6],
                    d[7]
                ))
            }
            0x581..=0x5FF | 0x601..=0x67F if !self.pdos.contains_key(&cob) => {
                let request = cob >= 0x600;
                let id = (cob & 0x7F) as u8;
                if !self.wanted(id) {
                    return None;
                }
                self.sdo(id, request, d)
            }
            _ => {
                let layout = self.pdos.get(&cob)?;
                let mut at = 0;
                let mut parts = Vec::new();
                for (name, ty, len) in &layout.fields {
                    let bytes = d.get(at..at + len)?;
                    at += len;
                    if name.starts_with("Dummy") {
                        continue;
                    }
                    let v = Value::decode(*ty, bytes).ok()?;
                    parts.push(format!("{name}={}", TypeCode::of(*ty).format(&v)));
                }
                Some(format!(
                    "node {}: {} {} {}",
                    self.node.unwrap_or(0),
                    layout.kind,
                    layout.number,
                    parts.join(" ")
                ))
            }
        }
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

/// Bytes as `01 02 0A`.
fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// A `candump -L` line: `(SECONDS.MICROS) IFACE ID#DATA`, with the time in seconds. Anything else
/// (a time that is no finite number, an identifier or data that is not hex digits, CAN FD) is none.
pub fn candump_line(line: &str) -> Option<(f64, CanFrame)> {
    let (ts, rest) = line.trim().strip_prefix('(')?.split_once(") ")?;
    let t: f64 = ts.parse().ok().filter(|t: &f64| t.is_finite())?;
    let (_, frame) = rest.trim().split_once(' ')?;
    let (id, data) = frame.split_once('#')?;
    let hex_digits = |x: &str| !x.is_empty() && x.bytes().all(|b| b.is_ascii_hexdigit());
    if !hex_digits(id) {
        return None;
    }
    let extended = id.len() > 3;
    let raw = u32::from_str_radix(id, 16).ok()?;
    if let Some(len) = data.strip_prefix('R') {
        let len = match len {
            "" => 0,
            _ if len.bytes().all(|b| b.is_ascii_digit()) => len.parse().ok()?,
            _ => return None,
        };
        return Some((t, CanFrame::new_remote_frame(raw, extended, len)?));
    }
    // Classic CAN only: CAN FD's `##` is no hex digit.
    if data.len() % 2 != 0 || data.len() > 16 || !data.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    let bytes: Vec<u8> = data
        .as_bytes()
        .chunks(2)
        .map(|pair| {
            let digit = |b: u8| (b as char).to_digit(16).map(|d| d as u8);
            Some((digit(pair[0])? << 4) | digit(pair[1])?)
        })
        .collect::<Option<_>>()?;
    let frame = if extended {
        CanFrame::new_extended(raw, &bytes)?
    } else {
        CanFrame::new(u16::try_from(raw).ok()?, &bytes)?
    };
    Some((t, frame))
}

/// The longest line of a log [`LogLines`] hands on, in bytes (a `candump -L` line of a classic
/// frame is under 60); a longer one is skipped without being kept.
pub const MAX_LOG_LINE: usize = 4096;

/// A line of a log as [`LogLines`] reads it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogLine<'a> {
    /// The line's bytes, without its line end.
    Text(&'a [u8]),
    /// A line longer than the limit: its bytes were read past, not kept.
    TooLong,
}

/// The lines of a log read in bounded memory: a line is kept only up to a limit; the rest of a
/// longer one is read and dropped as it comes, whatever its length, so that no line is ever held
/// whole.
pub struct LogLines<R> {
    input: R,
    line: Vec<u8>,
    max: usize,
    number: u64,
}

impl<R: BufRead> LogLines<R> {
    /// The lines of `input`, each kept up to `max` bytes.
    pub fn new(input: R, max: usize) -> LogLines<R> {
        LogLines {
            input,
            line: Vec::new(),
            max,
            number: 0,
        }
    }

    /// The next line with its number (from 1); `None` at the end of the input. The last line may
    /// have no line end.
    pub fn next_line(&mut self) -> std::io::Result<Option<(u64, LogLine<'_>)>> {
        self.line.clear();
        let mut too_long = false;
        let mut any = false;
        loop {
            let buf = match self.input.fill_buf() {
                Ok(b) => b,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            if buf.is_empty() {
                if !any {
                    return Ok(None);
                }
                break;
            }
            any = true;
            let (part, used, end) = match buf.iter().position(|&b| b == b'\n') {
                Some(i) => (&buf[..i], i + 1, true),
                None => (buf, buf.len(), false),
            };
            if !too_long {
                if self.line.len() + part.len() <= self.max {
                    self.line.extend_from_slice(part);
                } else {
                    too_long = true;
                    self.line.clear();
                }
            }
            self.input.consume(used);
            if end {
                break;
            }
        }
        self.number += 1;
        let line = if too_long {
            LogLine::TooLong
        } else {
            LogLine::Text(&self.line)
        };
        Ok(Some((self.number, line)))
    }
}

/// What [`LogDecoder`] makes of a log, one at a time.
#[derive(Debug, Clone, PartialEq)]
pub enum Decoded {
    /// A line about the bus at `t`, in seconds since the log's first frame.
    Line {
        /// Seconds since the log's first frame.
        t: f64,
        /// What the watcher says.
        text: String,
    },
    /// At the end of the log: an SDO transfer still going on (`t`: the log's last frame).
    Open {
        /// The log's last frame, in seconds since its first.
        t: f64,
        /// The transfer.
        transfer: OpenTransfer,
    },
    /// Line `line` (from 1) is longer than [`MAX_LOG_LINE`]: no frame, skipped unread.
    TooLong {
        /// The line's number, from 1.
        line: u64,
    },
}

/// `sdo-tool decode`: a `candump -L` log read line by line in bounded memory through a
/// [`Watcher`], pulled one [`Decoded`] at a time; at the end, the transfers left open.
pub struct LogDecoder<R> {
    lines: LogLines<R>,
    watcher: Watcher,
    /// The first frame's time, the last frame's (since the first).
    first: Option<f64>,
    last: f64,
    queue: VecDeque<Decoded>,
    ended: bool,
    not_frames: u64,
    first_not_frame: Option<u64>,
}

impl<R: BufRead> LogDecoder<R> {
    /// Decodes `input` with `watcher`.
    pub fn new(input: R, watcher: Watcher) -> LogDecoder<R> {
        LogDecoder {
            lines: LogLines::new(input, MAX_LOG_LINE),
            watcher,
            first: None,
            last: 0.0,
            queue: VecDeque::new(),
            ended: false,
            not_frames: 0,
            first_not_frame: None,
        }
    }

    /// The next thing decoded; `None` once the log and its open transfers are all told.
    pub fn next_event(&mut self) -> std::io::Result<Option<Decoded>> {
        loop {
            if let Some(d) = self.queue.pop_front() {
                return Ok(Some(d));
            }
            if self.ended {
                return Ok(None);
            }
            let Some((number, line)) = self.lines.next_line()? else {
                self.ended = true;
                let t = self.last;
                self.queue.extend(
                    self.watcher
                        .open_transfers()
                        .into_iter()
                        .map(|transfer| Decoded::Open { t, transfer }),
                );
                continue;
            };
            let bytes = match line {
                LogLine::Text(bytes) => bytes,
                LogLine::TooLong => {
                    self.queue.push_back(Decoded::TooLong { line: number });
                    continue;
                }
            };
            let text = String::from_utf8_lossy(bytes);
            let Some((t, frame)) = candump_line(&text) else {
                if !text.trim().is_empty() {
                    self.not_frames += 1;
                    self.first_not_frame.get_or_insert(number);
                }
                continue;
            };
            let t = t - *self.first.get_or_insert(t);
            self.last = t;
            let lines = self.watcher.at(t, &frame);
            self.queue
                .extend(lines.into_iter().map(|text| Decoded::Line { t, text }));
        }
    }

    /// The lines of at most [`MAX_LOG_LINE`] bytes that were no frame (blank lines aside): how
    /// many, and the first one's number.
    pub fn not_frames(&self) -> (u64, Option<u64>) {
        (self.not_frames, self.first_not_frame)
    }
}

/// `frame` as a `candump -L` line received at `at` on `iface`.
pub fn candump(at: std::time::SystemTime, iface: &str, frame: &CanFrame) -> String {
    let t = at.duration_since(std::time::UNIX_EPOCH).unwrap_or_default();
    format!("({}.{:06}) {iface} {frame}", t.as_secs(), t.subsec_micros())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(id: u16, data: &[u8]) -> CanFrame {
        CanFrame::new(id, data).unwrap()
    }

    /// Feeds `frames` (time, COB-ID, data) to a watcher of every node; every line with its time.
    fn run(frames: &[(f64, u16, &[u8])]) -> Vec<(f64, String)> {
        let mut w = Watcher::new(None, None);
        frames
            .iter()
            .flat_map(|(t, id, d)| {
                w.at(*t, &f(*id, d))
                    .into_iter()
                    .map(move |l| (*t, l))
                    .collect::<Vec<_>>()
            })
            .collect()
    }

    /// Node 3 beats every 0.1 s: a frame at exactly twice the period after the last beat is not
    /// late yet, one 2 µs later is, and only once. A boot-up message starts the count again: after
    /// it no period is known, so a silence is not reported until two heartbeats have shown one;
    /// two beats at the same instant show none either.
    #[test]
    fn a_heartbeat_is_missing_after_more_than_twice_its_period() {
        let sync = (0x080u16, &[][..]);
        let lines = run(&[
            (10.0, 0x703, &[0x05]),
            (10.1, 0x703, &[0x05]),
            (10.3, sync.0, sync.1),
            (10.300002, sync.0, sync.1),
            (10.5, sync.0, sync.1),
            (10.6, 0x703, &[0x05]),
            (10.7, 0x703, &[0x00]),
            (12.0, sync.0, sync.1),
            (12.1, 0x703, &[0x7F]),
            (12.1, 0x703, &[0x7F]),
            (13.0, sync.0, sync.1),
        ]);
        let missed: Vec<&(f64, String)> =
            lines.iter().filter(|(_, l)| l.contains("missed")).collect();
        assert_eq!(
            missed,
            [&(
                10.300002,
                "node 3: heartbeat missed: none for 0.200 s (period 0.100 s)".to_string()
            )]
        );
    }

    /// NMT commands by their command byte, to one node or all; SYNC with and without its counter; a
    /// frame of a wrong length on those identifiers is none of them. A segmented upload of 10 bytes
    /// (toggles 0 and 1, the last with n = 4) in one line.
    #[test]
    fn nmt_sync_and_a_segmented_upload() {
        let lines: Vec<String> = run(&[
            (0.0, 0x000, &[0x01, 3]),
            (0.0, 0x000, &[0x02, 0]),
            (0.0, 0x000, &[0x80, 3]),
            (0.0, 0x000, &[0x81, 3]),
            (0.0, 0x000, &[0x82, 3]),
            (0.0, 0x000, &[0x42, 3]),
            (0.0, 0x000, &[0x01]),
            (0.0, 0x080, &[]),
            (0.0, 0x080, &[7]),
            (0.0, 0x080, &[7, 8]),
            (0.1, 0x603, &[0x40, 0x00, 0x20, 0x02, 0, 0, 0, 0]),
            (0.1, 0x583, &[0x41, 0x00, 0x20, 0x02, 10, 0, 0, 0]),
            (0.1, 0x603, &[0x60, 0, 0, 0, 0, 0, 0, 0]),
            (0.1, 0x583, &[0x00, 1, 2, 3, 4, 5, 6, 7]),
            (0.1, 0x603, &[0x70, 0, 0, 0, 0, 0, 0, 0]),
            (0.1, 0x583, &[0x19, 8, 9, 10, 0, 0, 0, 0]),
            // e without s, n bits set: all four bytes (the n bits count only with s).
            (0.2, 0x603, &[0x2E, 0x00, 0x20, 0x01, 1, 2, 3, 4]),
        ])
        .into_iter()
        .map(|(_, l)| l)
        .collect();
        assert_eq!(
            lines,
            [
                "NMT start: node 3",
                "NMT stop: all nodes",
                "NMT enter pre-operational: node 3",
                "NMT reset node: node 3",
                "NMT reset communication: node 3",
                "NMT command 0x42 to node 3",
                "SYNC",
                "SYNC 7",
                "node 3: SDO read 0x2000:02 = 01 02 03 04 05 06 07 08 09 0A (10 bytes, segmented)",
                "node 3: SDO write 0x2000:01 = 01 02 03 04",
            ]
        );
    }

    /// A watcher of node 3 shows NMT commands to it and to all, not to node 4; frames that do not
    /// belong to the transfer going on (a client's segment during an upload, a server's segment and
    /// initiate answer during a download) are not taken into it.
    #[test]
    fn one_node_and_stray_frames() {
        let mut w = Watcher::new(Some(3), None);
        let mut lines = Vec::new();
        for (id, d) in [
            (0x000u16, &[0x01u8, 3][..]),
            (0x000, &[0x01, 0]),
            (0x000, &[0x01, 4]),
            // An upload of 0x2000:02, 3 bytes in one segment, with a stray client segment before.
            (0x603, &[0x40, 0x00, 0x20, 0x02, 0, 0, 0, 0]),
            (0x583, &[0x41, 0x00, 0x20, 0x02, 3, 0, 0, 0]),
            (0x603, &[0x01, 0xEE, 0, 0, 0, 0, 0, 0]),
            (0x603, &[0x60, 0, 0, 0, 0, 0, 0, 0]),
            (0x583, &[0x09, 1, 2, 3, 0, 0, 0, 0]),
            // A download of 0x2000:03, 8 bytes, with a stray server segment and initiate answer.
            (0x603, &[0x21, 0x00, 0x20, 0x03, 8, 0, 0, 0]),
            (0x583, &[0x60, 0x00, 0x20, 0x03, 0, 0, 0, 0]),
            (0x583, &[0x01, 0xEE, 0, 0, 0, 0, 0, 0]),
            (0x603, &[0x00, 1, 2, 3, 4, 5, 6, 7]),
            (0x603, &[0x1D, 8, 0, 0, 0, 0, 0, 0]),
        ] {
            lines.extend(w.line(&f(id, d)));
        }
        assert_eq!(
            lines,
            [
                "NMT start: node 3",
                "NMT start: all nodes",
                "node 3: SDO read 0x2000:02 = 01 02 03 (3 bytes, segmented)",
                "node 3: SDO write 0x2000:03 = 01 02 03 04 05 06 07 08 (8 bytes, segmented)",
            ]
        );
    }

    /// `candump -L` lines: standard and extended identifiers, remote frames with and without a
    /// length, empty data; what is not one (odd or too many data digits, CAN FD's `##`, no time)
    /// is none.
    #[test]
    fn candump_lines_both_ways() {
        let (t, fr) = candump_line("(1700000000.250000) can0 601#4018100100000000").unwrap();
        assert_eq!(t, 1_700_000_000.25);
        assert_eq!(fr, f(0x601, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]));
        assert_eq!(
            candump_line("(1.0) vcan0 1ABCDEF0#0102").unwrap().1,
            CanFrame::new_extended(0x1ABC_DEF0, &[1, 2]).unwrap()
        );
        assert_eq!(
            candump_line("(1.0) can0 123#R").unwrap().1,
            CanFrame::new_remote_frame(0x123, false, 0).unwrap()
        );
        assert_eq!(
            candump_line("(1.0) can0 123#R5").unwrap().1,
            CanFrame::new_remote_frame(0x123, false, 5).unwrap()
        );
        assert_eq!(candump_line("(1.0) can0 080#").unwrap().1, f(0x080, &[]));
        for bad in [
            "(1.0) can0 123#012",
            "(1.0) can0 123#000102030405060708",
            "(1.0) can0 123##1020304",
            "can0 123#01",
            "(x) can0 123#01",
            "(1.0) can0 12G#01",
            "",
        ] {
            assert_eq!(candump_line(bad), None, "{bad:?}");
        }
        let at = std::time::UNIX_EPOCH + std::time::Duration::from_micros(1_700_000_000_250_001);
        assert_eq!(
            candump(at, "can0", &f(0x181, &[1, 2])),
            "(1700000000.250001) can0 181#0102"
        );
    }

    /// What is no `candump -L` frame, whatever its bytes, is none: hex digits cut in the middle of
    /// a character, a sign before an identifier or a data byte, a time that is no finite number.
    #[test]
    fn odd_text_is_no_frame() {
        for bad in [
            "(1.0) can0 123#a\u{e9}1",
            "(1.0) can0 123#\u{e9}\u{e9}",
            "(1.0) can0 1\u{e9}#01",
            "(1.0) can0 \u{e9}#01",
            "(1.0) can0 +12#01",
            "(1.0) can0 123#+1",
            "(1.0) can0 #01",
            "(1.0) can0 123#R+1",
            "(nan) can0 123#01",
            "(inf) can0 123#01",
            "(-inf) can0 123#01",
        ] {
            assert_eq!(candump_line(bad), None, "{bad:?}");
        }
        assert_eq!(
            candump_line("(1.0) can0 123#aBcD").unwrap().1,
            f(0x123, &[0xAB, 0xCD])
        );
    }

    /// A remote frame of length 1 on a heartbeat's identifier is no heartbeat (it has no data
    /// byte): nothing without --raw, itself with it, and no period is taken from it.
    #[test]
    fn a_remote_frame_on_a_heartbeat_identifier_is_no_heartbeat() {
        let rtr = CanFrame::new_remote_frame(0x703, false, 1).unwrap();
        let mut w = Watcher::new(None, None);
        assert!(w.at(0.0, &rtr).is_empty());
        assert!(w.at(0.1, &rtr).is_empty());
        assert!(w.missed(5.0).is_empty());
        let mut w = Watcher::new(None, None).with_raw(true);
        assert_eq!(w.at(0.0, &rtr), ["703#R1"]);
    }

    /// Lines read through a 3-byte buffer, at most 5 bytes kept: one of exactly 5, one of 6 (too
    /// long, not kept), an empty one, one ending in CR LF (the CR is the line's), and a last line
    /// without a line end, too long; then the end. A short last line without its end is a line.
    #[test]
    fn log_lines_are_kept_up_to_the_limit() {
        let input: &[u8] = b"abc\n12345\n123456\n\nxy\r\n0123456789abcdef";
        let mut lines = LogLines::new(std::io::BufReader::with_capacity(3, input), 5);
        let mut got = Vec::new();
        while let Some((n, line)) = lines.next_line().unwrap() {
            got.push((n, format!("{line:?}")));
        }
        let text = |b: &[u8]| format!("{:?}", LogLine::Text(b));
        let too_long = format!("{:?}", LogLine::TooLong);
        assert_eq!(
            got,
            [
                (1, text(b"abc")),
                (2, text(b"12345")),
                (3, too_long.clone()),
                (4, text(b"")),
                (5, text(b"xy\r")),
                (6, too_long),
            ]
        );
        let mut lines = LogLines::new(&b"a\nb"[..], 5);
        assert_eq!(lines.next_line().unwrap(), Some((1, LogLine::Text(b"a"))));
        assert_eq!(lines.next_line().unwrap(), Some((2, LogLine::Text(b"b"))));
        assert_eq!(lines.next_line().unwrap(), None);
        assert_eq!(LogLines::new(&b""[..], 5).next_line().unwrap(), None);
    }

    /// Expedited transfers by their `e`, `s` and `n` bits: 4 bytes without the size, 3 with n = 1, 2
    /// with n = 2; a segmented download (the initiate announcing 10 bytes, segments of 7 and 3 with
    /// toggles 0 and 1, the last with n = 4 and c) in one line, the server's initiate answer not
    /// taken for its end; the client's block download and upload initiates, and a block frame with
    /// no transfer going on, which is nothing.
    #[test]
    fn expedited_and_segmented_transfers_by_their_bits() {
        let lines: Vec<String> = run(&[
            (0.0, 0x603, &[0x22, 0x00, 0x20, 0x01, 1, 2, 3, 4]),
            (0.0, 0x603, &[0x27, 0x00, 0x20, 0x01, 1, 2, 3, 9]),
            (0.0, 0x583, &[0x4B, 0x00, 0x20, 0x01, 5, 6, 9, 9]),
            (0.0, 0x583, &[0x42, 0x00, 0x20, 0x01, 5, 6, 7, 8]),
            (0.1, 0x603, &[0x21, 0x00, 0x20, 0x02, 10, 0, 0, 0]),
            (0.1, 0x583, &[0x60, 0x00, 0x20, 0x02, 0, 0, 0, 0]),
            (0.1, 0x603, &[0x00, 1, 2, 3, 4, 5, 6, 7]),
            (0.1, 0x583, &[0x20, 0, 0, 0, 0, 0, 0, 0]),
            (0.1, 0x603, &[0x19, 8, 9, 10, 0, 0, 0, 0]),
            (0.1, 0x583, &[0x30, 0, 0, 0, 0, 0, 0, 0]),
            // Block frames with nothing going on: an end (0xC1) and a start (0xA3) are nothing.
            (0.2, 0x603, &[0xC1, 0, 0, 0, 0, 0, 0, 0]),
            (0.2, 0x603, &[0xA3, 0, 0, 0, 0, 0, 0, 0]),
            // A block download: begun by 0xC6, its segments (the client's) unnamed, ended by 0xA1.
            (0.3, 0x603, &[0xC6, 0x00, 0x20, 0x03, 3, 0, 0, 0]),
            (0.3, 0x583, &[0xA4, 0x00, 0x20, 0x03, 0x7F, 0, 0, 0]),
            (0.3, 0x603, &[0x81, 1, 2, 3, 0, 0, 0, 0]),
            (0.3, 0x583, &[0xA2, 0x01, 0x7F, 0, 0, 0, 0, 0]),
            (0.3, 0x603, &[0xD1, 0, 0, 0, 0, 0, 0, 0]),
            (0.3, 0x583, &[0xA1, 0, 0, 0, 0, 0, 0, 0]),
        ])
        .into_iter()
        .map(|(_, l)| l)
        .collect();
        assert_eq!(
            lines,
            [
                "node 3: SDO write 0x2000:01 = 01 02 03 04",
                "node 3: SDO write 0x2000:01 = 01 02 03",
                "node 3: SDO read 0x2000:01 = 05 06",
                "node 3: SDO read 0x2000:01 = 05 06 07 08",
                "node 3: SDO write 0x2000:02 = 01 02 03 04 05 06 07 08 09 0A (10 bytes, segmented)",
                "node 3: SDO written 0x2000:03 = 01 02 03 (3 bytes, block transfer)",
            ]
        );
    }

    /// SDO frames of node 3 in words: an expedited read; a block upload whose segments (any first
    /// byte, here 0x01 and 0x82 that look like a download segment and an abort) are the server's
    /// data, until the client's 0xA1 ends it; an abort during a block download from the server's
    /// side.
    #[test]
    fn sdo_frames_in_words() {
        let lines: Vec<String> = run(&[
            (0.0, 0x603, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]),
            (0.0, 0x583, &[0x43, 0x18, 0x10, 0x01, 0x2E, 0x0B, 0, 0]),
            // Block upload of 0x1008: initiate, the server's answer, start, 2 segments, ack, end.
            (0.1, 0x603, &[0xA4, 0x08, 0x10, 0x00, 0x7F, 0, 0, 0]),
            (0.1, 0x583, &[0xC6, 0x08, 0x10, 0x00, 0x0A, 0, 0, 0]),
            (0.1, 0x603, &[0xA3, 0, 0, 0, 0, 0, 0, 0]),
            (
                0.1,
                0x583,
                &[0x01, 0x80, 0x81, 0x82, 0x83, 0x84, 0x85, 0x86],
            ),
            (0.1, 0x583, &[0x82, 0xC2, 0x08, 0x10, 0, 0, 0, 0]),
            (0.1, 0x603, &[0xA2, 0x02, 0x7F, 0, 0, 0, 0, 0]),
            // The end: n = 4 bytes of the last segment carry no data.
            (0.1, 0x583, &[0xD1, 0, 0, 0, 0, 0, 0, 0]),
            (0.1, 0x603, &[0xA1, 0, 0, 0, 0, 0, 0, 0]),
            // Block download of 0x2000:01 aborted by the server.
            (0.2, 0x603, &[0xC6, 0x00, 0x20, 0x01, 0x10, 0, 0, 0]),
            (
                0.2,
                0x583,
                &[0x80, 0x00, 0x20, 0x01, 0x00, 0x00, 0x00, 0x08],
            ),
        ])
        .into_iter()
        .map(|(_, l)| l)
        .collect();
        assert_eq!(
            lines,
            [
                "node 3: SDO read 0x1018:01 = 2E 0B 00 00",
                "node 3: SDO read 0x1008:00 = 80 81 82 83 84 85 86 C2 08 10 (10 bytes, block transfer)",
                "node 3: SDO server aborts 0x2000:01: 0x08000000 (General error)",
            ]
        );
    }

    /// candump's filter forms: one ID, ID:MASK, a range, `~` inverting; hex with or without 0x.
    #[test]
    fn filters_take_what_candump_would() {
        let f = |t: &str| t.parse::<CobFilter>().unwrap();
        let takes = |t: &str, ids: &[u16]| -> Vec<u16> {
            let f = f(t);
            ids.iter().copied().filter(|&c| f.passes(c)).collect()
        };
        let ids = [
            0x000, 0x080, 0x185, 0x186, 0x1FF, 0x205, 0x585, 0x605, 0x705, 0x7FF,
        ];
        assert_eq!(takes("185", &ids), [0x185]);
        assert_eq!(takes("0x185", &ids), [0x185]);
        // Node 5's every COB-ID: the low 7 bits are 5.
        assert_eq!(takes("5:7F", &ids), [0x185, 0x205, 0x585, 0x605, 0x705]);
        assert_eq!(takes("180-1FF", &ids), [0x185, 0x186, 0x1FF]);
        assert_eq!(takes("0x580-0x67F", &ids), [0x585, 0x605]);
        // Not a heartbeat (0x700–0x77F): 0x7FF is not one.
        assert_eq!(
            takes("~700:780", &ids),
            [0x000, 0x080, 0x185, 0x186, 0x1FF, 0x205, 0x585, 0x605, 0x7FF]
        );
        assert_eq!(takes("~185", &ids).len(), ids.len() - 1);
        for bad in ["", "800", "1FF-180", "x", "185:", "-", "185:800", "~"] {
            let e = bad.parse::<CobFilter>().unwrap_err();
            assert!(
                e.starts_with(&format!("filter {bad:?} is not ID, ID:MASK or LOW-HIGH")),
                "{e}"
            );
        }
        assert_eq!(takes("185-185", &ids), [0x185]);
        for (name, kind) in [
            ("nmt", Kind::Nmt),
            ("heartbeat", Kind::Heartbeat),
            ("HB", Kind::Heartbeat),
            ("sync", Kind::Sync),
            ("EMCY", Kind::Emcy),
            ("sdo", Kind::Sdo),
            ("pdo", Kind::Pdo),
            ("other", Kind::Other),
            ("raw", Kind::Other),
        ] {
            assert_eq!(name.parse::<Kind>(), Ok(kind), "{name}");
        }
        assert!("pdos".parse::<Kind>().is_err());
    }

    /// With filters only the frames they pass are looked at: a heartbeat filtered out is neither
    /// shown nor counted for a missed beat. With `--only`, the kinds not asked for are not shown,
    /// but an SDO transfer is still followed.
    #[test]
    fn filters_and_kinds_choose_what_is_shown() {
        let frames: &[(f64, u16, &[u8])] = &[
            (0.00, 0x000, &[0x01, 0x05]),
            (0.01, 0x705, &[0x05]),
            (0.02, 0x080, &[]),
            (0.03, 0x605, &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]),
            (
                0.04,
                0x585,
                &[0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00],
            ),
            (0.05, 0x085, &[0x10, 0x81, 0x11, 0, 0, 0, 0, 0]),
            (0.06, 0x123, &[0xAA]),
        ];
        let run_with = |w: Watcher| -> Vec<String> {
            let mut w = w.with_raw(true);
            frames
                .iter()
                .flat_map(|(t, id, d)| w.at(*t, &f(*id, d)))
                .collect()
        };
        let all = run_with(Watcher::new(None, None));
        assert_eq!(all.len(), 7, "{all:?}");
        let sdo_only =
            run_with(Watcher::new(None, None).with_filters(vec!["580-67F".parse().unwrap()]));
        // The upload's request names nothing yet (raw), its answer the value.
        assert_eq!(
            sdo_only,
            [
                "605#4000100000000000",
                "node 5: SDO read 0x1000:00 = 92 01 02 00"
            ]
        );
        let only = |kinds: Vec<Kind>| run_with(Watcher::new(None, None).with_only(kinds));
        assert_eq!(only(vec![Kind::Sync]), ["SYNC"]);
        assert_eq!(
            only(vec![Kind::Emcy]),
            ["node 5: EMCY 0x8110 (CAN overrun (objects lost)), error register 0x11, data 00 00 00 00 00"]
        );
        assert_eq!(only(vec![Kind::Other]), ["123#AA"]);
        assert_eq!(
            only(vec![Kind::Heartbeat, Kind::Sync]),
            ["node 5: heartbeat, operational", "SYNC"]
        );
        // SDOs not asked for: nothing of the upload.
        let nmt = run_with(Watcher::new(None, None).with_only(vec![Kind::Nmt]));
        assert_eq!(nmt, ["NMT start: node 5"]);
        // A heartbeat filtered out does not count: no missed beat after it.
        let mut w = Watcher::new(None, None).with_filters(vec!["~700:780".parse().unwrap()]);
        for t in [0.0, 0.1, 0.2] {
            assert!(w.at(t, &f(0x703, &[0x05])).is_empty());
        }
        assert!(w.missed(5.0).is_empty());
        let mut w = Watcher::new(None, None).with_only(vec![Kind::Sdo]);
        for t in [0.0, 0.1] {
            assert!(w.at(t, &f(0x703, &[0x05])).is_empty());
        }
        assert!(
            w.missed(5.0).is_empty(),
            "a missed beat is a heartbeat line"
        );
        let mut w = Watcher::new(None, None).with_only(vec![Kind::Heartbeat]);
        for t in [0.0, 0.1] {
            w.at(t, &f(0x703, &[0x05]));
        }
        assert_eq!(
            w.missed(5.0),
            ["node 3: heartbeat missed: none for 4.900 s (period 0.100 s)"]
        );
    }

    /// A block download of 0x2000:04 (blksize 4) in which the third segment is lost: the server
    /// acknowledges 2, the client sends the rest again as a new sub-block (sequence numbers from
    /// 1); the data is what the acknowledgements took, less the end's n. Then a block download
    /// the client aborts (0x80: sequence number 0 is no segment).
    #[test]
    fn a_block_transfer_with_a_lost_segment_is_reassembled() {
        let lines: Vec<String> = run(&[
            (0.0, 0x603, &[0xC6, 0x00, 0x20, 0x04, 25, 0, 0, 0]),
            (0.0, 0x583, &[0xA4, 0x00, 0x20, 0x04, 4, 0, 0, 0]),
            (
                0.0,
                0x603,
                &[0x01, 0x10, 0x11, 0x12, 0x13, 0x14, 0x15, 0x16],
            ),
            (
                0.0,
                0x603,
                &[0x02, 0x20, 0x21, 0x22, 0x23, 0x24, 0x25, 0x26],
            ),
            (
                0.0,
                0x603,
                &[0x04, 0x40, 0x41, 0x42, 0x43, 0x44, 0x45, 0x46],
            ),
            (0.0, 0x583, &[0xA2, 0x02, 0x04, 0, 0, 0, 0, 0]),
            (
                0.0,
                0x603,
                &[0x01, 0x30, 0x31, 0x32, 0x33, 0x34, 0x35, 0x36],
            ),
            (0.0, 0x603, &[0x82, 0x40, 0x41, 0x42, 0x43, 0, 0, 0]),
            (0.0, 0x583, &[0xA2, 0x02, 0x04, 0, 0, 0, 0, 0]),
            // 7 + 7 + 7 + 4 = 25 bytes: n = 3.
            (0.0, 0x603, &[0xCD, 0x12, 0x34, 0, 0, 0, 0, 0]),
            (0.0, 0x583, &[0xA1, 0, 0, 0, 0, 0, 0, 0]),
            (0.1, 0x603, &[0xC2, 0x00, 0x20, 0x05, 0, 0, 0, 0]),
            (0.1, 0x583, &[0xA0, 0x00, 0x20, 0x05, 4, 0, 0, 0]),
            (0.1, 0x603, &[0x01, 1, 2, 3, 4, 5, 6, 7]),
            (
                0.1,
                0x603,
                &[0x80, 0x00, 0x20, 0x05, 0x00, 0x00, 0x04, 0x05],
            ),
            // Nothing goes on now: the server's late acknowledgement is nothing.
            (0.1, 0x583, &[0xA2, 0x01, 0x04, 0, 0, 0, 0, 0]),
        ])
        .into_iter()
        .map(|(_, l)| l)
        .collect();
        assert_eq!(
            lines,
            [
                "node 3: SDO written 0x2000:04 = 10 11 12 13 14 15 16 20 21 22 23 24 25 26 30 31 32 \
                 33 34 35 36 40 41 42 43 (25 bytes, block transfer)",
                "node 3: SDO client aborts 0x2000:05: 0x05040000 (SDO protocol timed out)",
            ]
        );
    }

    /// A server that acknowledges fewer segments than came (2 of 3, the third sent again), a
    /// segment seen twice, and a sub-block of 65 segments whose last (0xC1: last, sequence 65)
    /// looks like an end; then a client abort before the server's initiate answer.
    #[test]
    fn block_segments_count_as_acknowledged() {
        let seg = |seq: u8, last: bool, fill: u8| {
            let mut d = [fill; 8];
            d[0] = seq | if last { 0x80 } else { 0 };
            d
        };
        let mut frames: Vec<(f64, u16, Vec<u8>)> = vec![
            (0.0, 0x603, vec![0xC6, 0x00, 0x20, 0x06, 28, 0, 0, 0]),
            (0.0, 0x583, vec![0xA4, 0x00, 0x20, 0x06, 3, 0, 0, 0]),
            (0.0, 0x603, seg(1, false, 0x11).to_vec()),
            (0.0, 0x603, seg(1, false, 0x11).to_vec()),
            (0.0, 0x603, seg(2, false, 0x22).to_vec()),
            (0.0, 0x603, seg(3, false, 0x33).to_vec()),
            (0.0, 0x583, vec![0xA2, 0x02, 0x03, 0, 0, 0, 0, 0]),
            (0.0, 0x603, seg(1, false, 0x33).to_vec()),
            (0.0, 0x603, seg(2, true, 0x44).to_vec()),
            (0.0, 0x583, vec![0xA2, 0x02, 0x03, 0, 0, 0, 0, 0]),
            // 4 × 7 = 28 bytes: n = 0.
            (0.0, 0x603, vec![0xC1, 0, 0, 0, 0, 0, 0, 0]),
            (0.0, 0x583, vec![0xA1, 0, 0, 0, 0, 0, 0, 0]),
            (0.1, 0x603, vec![0xC6, 0x00, 0x20, 0x07, 0xC7, 0x01, 0, 0]),
            (0.1, 0x583, vec![0xA4, 0x00, 0x20, 0x07, 127, 0, 0, 0]),
        ];
        for k in 1..=65u8 {
            frames.push((0.1, 0x603, seg(k, k == 65, k).to_vec()));
        }
        frames.extend([
            (0.1, 0x583, vec![0xA2, 65, 127, 0, 0, 0, 0, 0]),
            // 65 × 7 = 455 bytes for 455: n = 0.
            (0.1, 0x603, vec![0xC1, 0, 0, 0, 0, 0, 0, 0]),
            (0.1, 0x583, vec![0xA1, 0, 0, 0, 0, 0, 0, 0]),
            (0.2, 0x603, vec![0xC6, 0x00, 0x20, 0x08, 4, 0, 0, 0]),
            (
                0.2,
                0x603,
                vec![0x80, 0x00, 0x20, 0x08, 0x00, 0x00, 0x00, 0x08],
            ),
        ]);
        let mut w = Watcher::new(None, None);
        let lines: Vec<String> = frames
            .iter()
            .flat_map(|(t, id, d)| w.at(*t, &f(*id, d)))
            .collect();
        assert_eq!(lines.len(), 3, "{lines:#?}");
        let mut first = "node 3: SDO written 0x2000:06 = ".to_string();
        let bytes: Vec<String> = [0x11u8, 0x22, 0x33, 0x44]
            .iter()
            .flat_map(|b| std::iter::repeat_n(format!("{b:02X}"), 7))
            .collect();
        first.push_str(&bytes.join(" "));
        first.push_str(" (28 bytes, block transfer)");
        assert_eq!(lines[0], first);
        let long: Vec<String> = (1..=65u8)
            .flat_map(|k| std::iter::repeat_n(format!("{k:02X}"), 7))
            .collect();
        assert_eq!(
            lines[1],
            format!(
                "node 3: SDO written 0x2000:07 = {} (455 bytes, block transfer)",
                long.join(" ")
            )
        );
        assert_eq!(
            lines[2],
            "node 3: SDO client aborts 0x2000:08: 0x08000000 (General error)"
        );
    }
}
