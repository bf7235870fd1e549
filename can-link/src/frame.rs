//! Classic CAN frames as the node and the transports exchange them.

use std::fmt;

use embedded_can::{ExtendedId, Id, StandardId};

/// A classic CAN 2.0 data or remote frame: an 11- or 29-bit identifier and up to 8 data bytes.
///
/// Implements [`embedded_can::Frame`], so code written against that trait takes these frames too.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct CanFrame {
    id: u32,
    extended: bool,
    rtr: bool,
    len: u8,
    data: [u8; 8],
}

impl CanFrame {
    /// A data frame with an 11-bit identifier. `None` when `id` is above 0x7FF or `data` longer than 8.
    pub fn new(id: u16, data: &[u8]) -> Option<CanFrame> {
        if id > 0x7FF {
            return None;
        }
        Self::build(u32::from(id), false, false, data)
    }

    /// A data frame with a 29-bit identifier. `None` when `id` is above 0x1FFF_FFFF or `data` longer than 8.
    pub fn new_extended(id: u32, data: &[u8]) -> Option<CanFrame> {
        if id > 0x1FFF_FFFF {
            return None;
        }
        Self::build(id, true, false, data)
    }

    /// A remote frame (RTR) asking for `len` bytes. `None` when `id` or `len` is out of range.
    pub fn new_remote_frame(id: u32, extended: bool, len: u8) -> Option<CanFrame> {
        if len > 8 || id > if extended { 0x1FFF_FFFF } else { 0x7FF } {
            return None;
        }
        let mut f = Self::build(id, extended, true, &[])?;
        f.len = len;
        Some(f)
    }

    fn build(id: u32, extended: bool, rtr: bool, data: &[u8]) -> Option<CanFrame> {
        if data.len() > 8 {
            return None;
        }
        let mut bytes = [0u8; 8];
        bytes[..data.len()].copy_from_slice(data);
        Some(CanFrame {
            id,
            extended,
            rtr,
            len: data.len() as u8,
            data: bytes,
        })
    }

    /// The raw identifier (11 or 29 bits).
    pub const fn raw_id(&self) -> u32 {
        self.id
    }

    /// True for a 29-bit identifier.
    pub const fn is_extended(&self) -> bool {
        self.extended
    }

    /// True for a remote frame.
    pub const fn is_rtr(&self) -> bool {
        self.rtr
    }

    /// The data length code (0–8).
    pub const fn len(&self) -> usize {
        self.len as usize
    }

    /// True when the frame carries no data bytes.
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The data bytes (empty for a remote frame).
    pub fn data(&self) -> &[u8] {
        if self.rtr {
            &[]
        } else {
            &self.data[..self.len as usize]
        }
    }

    /// The data bytes padded with zeros to 8 (what a fixed 8-byte protocol such as SDO reads).
    pub const fn data8(&self) -> [u8; 8] {
        self.data
    }

    /// The 11-bit CANopen COB-ID when this is a standard data frame.
    pub fn cob_id(&self) -> Option<u16> {
        (!self.extended).then_some(self.id as u16)
    }
}

impl fmt::Debug for CanFrame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

/// `candump` notation: `181#0102030405060708`, `7FF#R2`, `12345678#00`.
impl fmt::Display for CanFrame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.extended {
            write!(f, "{:08X}#", self.id)?;
        } else {
            write!(f, "{:03X}#", self.id)?;
        }
        if self.rtr {
            return write!(f, "R{}", self.len);
        }
        for b in self.data() {
            write!(f, "{b:02X}")?;
        }
        Ok(())
    }
}

impl embedded_can::Frame for CanFrame {
    fn new(id: impl Into<Id>, data: &[u8]) -> Option<Self> {
        match id.into() {
            Id::Standard(s) => CanFrame::new(s.as_raw(), data),
            Id::Extended(e) => CanFrame::new_extended(e.as_raw(), data),
        }
    }

    fn new_remote(id: impl Into<Id>, dlc: usize) -> Option<Self> {
        let dlc = u8::try_from(dlc).ok()?;
        match id.into() {
            Id::Standard(s) => CanFrame::new_remote_frame(u32::from(s.as_raw()), false, dlc),
            Id::Extended(e) => CanFrame::new_remote_frame(e.as_raw(), true, dlc),
        }
    }

    fn is_extended(&self) -> bool {
        self.extended
    }

    fn is_remote_frame(&self) -> bool {
        self.rtr
    }

    fn id(&self) -> Id {
        if self.extended {
            Id::Extended(ExtendedId::new(self.id).unwrap_or(ExtendedId::ZERO))
        } else {
            Id::Standard(StandardId::new(self.id as u16).unwrap_or(StandardId::ZERO))
        }
    }

    fn dlc(&self) -> usize {
        self.len as usize
    }

    fn data(&self) -> &[u8] {
        CanFrame::data(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn construction_bounds() {
        assert!(CanFrame::new(0x800, &[]).is_none());
        assert!(CanFrame::new(0x7FF, &[0; 9]).is_none());
        assert!(CanFrame::new_extended(0x2000_0000, &[]).is_none());
        assert!(CanFrame::new_remote_frame(0x700, false, 9).is_none());
        let f = CanFrame::new(0x181, &[1, 2, 3]).unwrap();
        assert_eq!(f.data(), &[1, 2, 3]);
        assert_eq!(f.data8(), [1, 2, 3, 0, 0, 0, 0, 0]);
        assert_eq!(f.cob_id(), Some(0x181));
        assert_eq!(f.to_string(), "181#010203");
        let r = CanFrame::new_remote_frame(0x705, false, 1).unwrap();
        assert_eq!(r.to_string(), "705#R1");
        assert!(r.data().is_empty());
        let e = CanFrame::new_extended(0x1234_5678, &[0xAB]).unwrap();
        assert_eq!(e.to_string(), "12345678#AB");
        assert_eq!(e.cob_id(), None);
    }

    #[test]
    fn embedded_can_round_trip() {
        use embedded_can::Frame as _;
        let id = StandardId::new(0x605).unwrap();
        let f = <CanFrame as embedded_can::Frame>::new(id, &[0x40, 0x18, 0x10, 1]).unwrap();
        assert_eq!(f.id(), Id::Standard(id));
        assert_eq!(f.dlc(), 4);
        assert!(!f.is_remote_frame());
    }

    /// The largest identifiers of each format are frames: 0x7FF (11 bits) and 0x1FFF_FFFF (29 bits,
    /// CAN 2.0B).
    #[test]
    fn largest_identifiers() {
        let s = CanFrame::new(0x7FF, &[]).unwrap();
        assert_eq!((s.raw_id(), s.is_extended()), (0x7FF, false));
        let e = CanFrame::new_extended(0x1FFF_FFFF, &[]).unwrap();
        assert_eq!((e.raw_id(), e.is_extended()), (0x1FFF_FFFF, true));
        assert_eq!(e.to_string(), "1FFFFFFF#");
    }

    /// The accessors read back what the frame was made of; `{:?}` shows `candump` notation too.
    #[test]
    fn accessors_and_debug() {
        let f = CanFrame::new(0x181, &[1, 2, 3]).unwrap();
        assert_eq!(f.raw_id(), 0x181);
        assert!(!f.is_extended());
        assert!(!f.is_rtr());
        assert_eq!(f.len(), 3);
        assert!(!f.is_empty());
        assert!(CanFrame::new(0x080, &[]).unwrap().is_empty());
        assert_eq!(format!("{f:?}"), "181#010203");
    }

    /// Through `embedded_can::Frame`: format, remote flag, DLC and data as made, for both formats.
    #[test]
    fn embedded_can_view() {
        use embedded_can::Frame as F;
        let data =
            <CanFrame as F>::new(StandardId::new(0x605).unwrap(), &[0x40, 0x18, 0x10, 1]).unwrap();
        assert!(!F::is_extended(&data));
        assert_eq!(F::data(&data), &[0x40, 0x18, 0x10, 1]);
        let ext = ExtendedId::new(0x1234_5678).unwrap();
        let e = <CanFrame as F>::new(ext, &[0xAB, 0xCD]).unwrap();
        assert!(F::is_extended(&e));
        assert_eq!(F::id(&e), Id::Extended(ext));
        assert_eq!(F::data(&e), &[0xAB, 0xCD]);
        let r = <CanFrame as F>::new_remote(StandardId::new(0x705).unwrap(), 1).unwrap();
        assert!(F::is_remote_frame(&r));
        assert!(!F::is_extended(&r));
        assert_eq!(F::dlc(&r), 1);
        assert_eq!(F::data(&r), &[] as &[u8]);
        assert_eq!(r.to_string(), "705#R1");
    }
}
