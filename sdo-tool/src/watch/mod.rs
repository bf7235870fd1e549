//! `sdo-tool watch` and `sdo-tool decode`: what goes on on the bus, in words — NMT commands,
//! boot-up messages, heartbeats and the state changes they show, SYNC, EMCY messages with their error
//! code's meaning, SDO transfers (expedited, segmented and block ones reassembled into one line with
//! the value — a block transfer's sub-blocks as their acknowledgements take them, so a segment sent
//! again counts once — aborts with their code's meaning), and a node's PDOs (TPDOs and RPDOs)
//! decoded field by field from its mapping in a description. A frame that is none of these is shown
//! as it is when raw frames are asked for. candump's COB-ID filters and a choice of kinds narrow
//! what is looked at and shown.

use std::collections::HashMap;

use od::dict::Dictionary;
use od::types::DataType;
use od::value::Value;

use crate::link::{CanFrame, EmcyCode, PdoConfig, RPDO_COMM, TPDO_COMM};
use crate::TypeCode;
use od::dict::Address;

mod capture;
mod log;
mod sdo;
#[cfg(test)]
mod tests;

pub use capture::{CaptureFrames, CaptureSummary, PCAPNG_MAGIC};
pub use log::{candump, candump_line, Decoded, LogDecoder, LogLine, LogLines, MAX_LOG_LINE};
pub use sdo::OpenTransfer;
use sdo::Transfer;

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
    fields: Vec<(String, TypeCode, usize)>,
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
    /// Values shown whole, however long.
    full: bool,
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
                            return (
                                "Dummy".to_string(),
                                TypeCode::of(DataType::Unsigned8),
                                e.len(),
                            );
                        }
                        let at = od::Address::new(e.index, e.sub);
                        let (name, ty) = match d.entry(e.index, e.sub) {
                            Ok(entry) => (entry.name.clone(), entry.data_type),
                            Err(_) => (at.to_string(), DataType::Unsigned8),
                        };
                        (name, crate::show::code_for(Some(&d), at, ty), e.len())
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
            full: false,
        }
    }

    /// Shows every byte of a long value (a DOMAIN's, an unknown entry's) instead of its first
    /// [`crate::show::SHOWN_BYTES`] and its length.
    pub fn with_full(mut self, full: bool) -> Watcher {
        self.full = full;
        self
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

    /// `bytes` as a value of `mux`'s type in the description (in hex or decimal as
    /// [`crate::show`] says, a mapping with what it maps), else as hex bytes; more than
    /// [`crate::show::SHOWN_BYTES`] of them elided (`…`; the line gives the length) unless
    /// [`Watcher::with_full`].
    fn value(&self, mux: Address, bytes: &[u8]) -> String {
        let od = self.od.as_ref();
        let typed = od
            .and_then(|d| d.entry(mux.index, mux.sub).ok())
            .and_then(|e| {
                let v = Value::decode(e.data_type, bytes).ok()?;
                let text = crate::show::code_for(od, mux, e.data_type).format(&v);
                let text = crate::show::with_mapping(mux, &v, text);
                Some(match v {
                    Value::Bytes(b) => crate::show::bytes_head(&b, self.full),
                    _ => text,
                })
            });
        // A value longer than a frame's comes in a line that gives its length.
        typed.unwrap_or_else(|| crate::show::bytes_head(bytes, self.full))
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

    /// The line naming `frame` (whether its kind is shown or not): NMT, SYNC, heartbeat, EMCY,
    /// SDO or a PDO of the node's mapping; `None` for a frame it cannot name or of a node not
    /// watched.
    fn named_line(&mut self, frame: &CanFrame) -> Option<String> {
        let cob = frame.cob_id()?;
        let d = frame.data();
        match cob {
            0x000 if d.len() == 2 => self.nmt_line(d[0], d[1]),
            0x080 if d.len() <= 1 => Some(match d.first() {
                Some(c) => format!("SYNC {c}"),
                None => "SYNC".to_string(),
            }),
            0x701..=0x77F if d.len() == 1 => self.heartbeat_line((cob - 0x700) as u8, d[0]),
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
            _ => self.pdo_line(cob, d),
        }
    }

    /// An NMT command `cs` to node `id` (0: all nodes).
    fn nmt_line(&self, cs: u8, id: u8) -> Option<String> {
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

    /// Node `id`'s heartbeat with `state`: a boot-up, a state change, or the state.
    fn heartbeat_line(&mut self, id: u8, state: u8) -> Option<String> {
        if !self.wanted(id) {
            return None;
        }
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

    /// A PDO of the node's mapping, field by field (dummy entries left out); `None` for a frame of
    /// no mapped PDO, or too short for its mapping.
    fn pdo_line(&self, cob: u16, d: &[u8]) -> Option<String> {
        let layout = self.pdos.get(&cob)?;
        let mut at = 0;
        let mut parts = Vec::new();
        for (name, ty, len) in &layout.fields {
            let bytes = d.get(at..at + len)?;
            at += len;
            if name.starts_with("Dummy") {
                continue;
            }
            let v = Value::decode(ty.data_type, bytes).ok()?;
            parts.push(format!("{name}={}", ty.format(&v)));
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
