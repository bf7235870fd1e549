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

/// The flags in the identifier word of Linux's `struct can_frame` (linux/can.h), as
/// `LINKTYPE_CAN_SOCKETCAN` captures carry them: extended frame format (29-bit identifier).
pub const CAN_EFF_FLAG: u32 = 0x8000_0000;
/// Remote transmission request.
pub const CAN_RTR_FLAG: u32 = 0x4000_0000;
/// Error frame.
pub const CAN_ERR_FLAG: u32 = 0x2000_0000;
/// `CANFD_FDF` in the byte after the length: a CAN FD frame.
const CANFD_FDF: u8 = 0x04;
/// `CANXL_XLF` in the length's place: a CAN XL frame.
const CANXL_XLF: u8 = 0x80;

/// Why captured SocketCAN bytes are no classic CAN frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum NotClassic {
    /// An error frame (`CAN_ERR_FLAG`): what the controller reported, not a frame on the bus.
    #[error("an error frame")]
    Error,
    /// A CAN FD frame (`CANFD_FDF`, or more than 16 bytes).
    #[error("a CAN FD frame")]
    Fd,
    /// A CAN XL frame (`CANXL_XLF`).
    #[error("a CAN XL frame")]
    Xl,
    /// Fewer bytes than the header and the length say, or a length above 8.
    #[error("not a whole SocketCAN frame")]
    Malformed,
}

impl CanFrame {
    /// The frame as Linux's `struct can_frame` has it and `LINKTYPE_CAN_SOCKETCAN` captures it:
    /// the identifier with [`CAN_EFF_FLAG`] and [`CAN_RTR_FLAG`] in network byte order, the data
    /// length (a remote frame's DLC), three zero bytes, and the data padded with zeros to 8.
    pub fn socketcan_bytes(&self) -> [u8; 16] {
        let mut id = self.id;
        if self.extended {
            id |= CAN_EFF_FLAG;
        }
        if self.rtr {
            id |= CAN_RTR_FLAG;
        }
        let mut out = [0u8; 16];
        out[..4].copy_from_slice(&id.to_be_bytes());
        out[4] = self.len;
        out[8..8 + self.data().len()].copy_from_slice(self.data());
        out
    }

    /// The classic frame captured SocketCAN `bytes` hold (`LINKTYPE_CAN_SOCKETCAN`): an 11-bit
    /// identifier without `CAN_EFF_FLAG` (the bits above it are not the frame's), a 29-bit one
    /// with it.
    pub fn from_socketcan_bytes(bytes: &[u8]) -> Result<CanFrame, NotClassic> {
        if bytes.len() < 8 {
            return Err(NotClassic::Malformed);
        }
        if bytes[4] & CANXL_XLF != 0 {
            return Err(NotClassic::Xl);
        }
        if bytes[5] & CANFD_FDF != 0 || bytes.len() > 16 {
            return Err(NotClassic::Fd);
        }
        let word = u32::from_be_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
        if word & CAN_ERR_FLAG != 0 {
            return Err(NotClassic::Error);
        }
        let len = bytes[4];
        let extended = word & CAN_EFF_FLAG != 0;
        let id = if extended {
            word & 0x1FFF_FFFF
        } else {
            word & 0x7FF
        };
        if word & CAN_RTR_FLAG != 0 {
            return CanFrame::new_remote_frame(id, extended, len).ok_or(NotClassic::Malformed);
        }
        let data = bytes
            .get(8..8 + usize::from(len))
            .ok_or(NotClassic::Malformed)?;
        Self::build(id, extended, false, data).ok_or(NotClassic::Malformed)
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

    /// The SocketCAN bytes of each kind of frame, worked out from linux/can.h: the identifier word
    /// big-endian with EFF (bit 31) and RTR (bit 30), the length, three zeros, the data padded.
    #[test]
    fn socketcan_bytes_golden() {
        let sdo = CanFrame::new(0x605, &[0x40, 0x18, 0x10, 0x01]).unwrap();
        assert_eq!(
            sdo.socketcan_bytes(),
            [0, 0, 0x06, 0x05, 4, 0, 0, 0, 0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]
        );
        let ext = CanFrame::new_extended(0x1234_5678, &[0xAB]).unwrap();
        assert_eq!(
            ext.socketcan_bytes(),
            [0x92, 0x34, 0x56, 0x78, 1, 0, 0, 0, 0xAB, 0, 0, 0, 0, 0, 0, 0]
        );
        let rtr = CanFrame::new_remote_frame(0x705, false, 1).unwrap();
        assert_eq!(
            rtr.socketcan_bytes(),
            [0x40, 0, 0x07, 0x05, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]
        );
        let ext_rtr = CanFrame::new_remote_frame(0x1FFF_FFFF, true, 8).unwrap();
        assert_eq!(&ext_rtr.socketcan_bytes()[..5], [0xDF, 0xFF, 0xFF, 0xFF, 8]);
        for f in [sdo, ext, rtr, ext_rtr, CanFrame::new(0x080, &[]).unwrap()] {
            assert_eq!(CanFrame::from_socketcan_bytes(&f.socketcan_bytes()), Ok(f));
        }
    }

    /// Captured bytes that are no classic frame say what they are; a standard identifier is its
    /// 11 bits; the data may be captured unpadded.
    #[test]
    fn socketcan_bytes_that_are_no_classic_frame() {
        let from = CanFrame::from_socketcan_bytes;
        let mut b = [0u8; 16];
        b[..5].copy_from_slice(&[0x20, 0, 0, 0x04, 8]);
        assert_eq!(from(&b), Err(NotClassic::Error));
        assert_eq!(from(&[0, 0, 1, 0x23, 8, 0x04, 0, 0]), Err(NotClassic::Fd));
        assert_eq!(from(&[0u8; 72]), Err(NotClassic::Fd));
        assert_eq!(from(&[0, 0, 1, 0x23, 0x80, 0, 0, 0]), Err(NotClassic::Xl));
        assert_eq!(from(&[0, 0, 1, 0x23, 2, 0, 0]), Err(NotClassic::Malformed));
        assert_eq!(
            from(&[0, 0, 1, 0x23, 9, 0, 0, 0]),
            Err(NotClassic::Malformed)
        );
        assert_eq!(
            from(&[0, 0, 1, 0x23, 2, 0, 0, 0, 1]),
            Err(NotClassic::Malformed)
        );
        assert_eq!(
            from(&[0x40, 0, 1, 0x23, 9, 0, 0, 0]),
            Err(NotClassic::Malformed)
        );
        assert_eq!(
            from(&[0x1F, 0xFF, 0xF9, 0x23, 2, 0, 0, 0, 1, 2]),
            Ok(CanFrame::new(0x123, &[1, 2]).unwrap())
        );
        assert_eq!(
            from(&[0x40, 0, 1, 0x23, 3, 0, 0, 0]),
            Ok(CanFrame::new_remote_frame(0x123, false, 3).unwrap())
        );
        assert_eq!(NotClassic::Fd.to_string(), "a CAN FD frame");
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
