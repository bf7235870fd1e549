//! SDO frames of CiA 301 §7.2.4.3 on CAN: eight bytes, the command specifier in the top three bits of
//! byte 0, the multiplexer (index little-endian, sub-index) in bytes 1–3.
//!
//! Two typed representations, one per direction: [`ClientFrame`] (what a client sends, COB-ID 0x600 +
//! node) and [`ServerFrame`] (what a server sends, 0x580 + node), each with `parse` and `emit`. Frames
//! inside a block (CiA 301 §7.2.4.3.9–16: sequence number and data, no command specifier) are told apart
//! only by the transfer state, so they are their own type, [`BlockSegment`], parsed by the side that
//! expects one.
//!
//! Parsing fails with the abort code the receiver answers: an unknown command specifier is
//! [`AbortCode::InvalidCommand`] (0x05040001).

use crate::abort::AbortCode;
/// The multiplexer of a transfer is the [`Address`] of its entry.
pub use crate::dict::Address;

/// The length of an SDO frame on CAN.
pub const FRAME_LEN: usize = 8;

/// An SDO frame's bytes.
pub type Frame = [u8; FRAME_LEN];

/// Index and sub-index of the entry a transfer is about (bytes 1–3 of initiate and abort frames).
fn read_address(f: &Frame) -> Address {
    Address {
        index: u16::from_le_bytes([f[1], f[2]]),
        sub: f[3],
    }
}

fn write_address(a: Address, f: &mut Frame) {
    f[1..3].copy_from_slice(&a.index.to_le_bytes());
    f[3] = a.sub;
}

/// Data carried in bytes 1–7 of a segment: 0 to 7 bytes.
#[derive(Clone, Copy, Eq, Default)]
pub struct SegmentData {
    bytes: [u8; 7],
    len: u8,
}

impl SegmentData {
    /// Up to seven bytes of `data` (the rest is not taken).
    pub fn new(data: &[u8]) -> SegmentData {
        let len = data.len().min(7);
        let mut bytes = [0u8; 7];
        bytes[..len].copy_from_slice(&data[..len]);
        SegmentData {
            bytes,
            len: len as u8,
        }
    }

    /// The bytes.
    pub fn as_slice(&self) -> &[u8] {
        &self.bytes[..self.len as usize]
    }

    /// Number of bytes.
    pub const fn len(&self) -> usize {
        self.len as usize
    }

    /// True when there is no byte.
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }
}

impl PartialEq for SegmentData {
    fn eq(&self, other: &SegmentData) -> bool {
        self.as_slice() == other.as_slice()
    }
}

impl std::fmt::Debug for SegmentData {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:02X?}", self.as_slice())
    }
}

/// Data of an expedited initiate frame: 0 to 4 bytes (bytes 4–7), or the size indicated by `n` unknown
/// (`size_known = false`: the receiver takes all four bytes, CiA 301 §7.2.4.3.3 with s = 0).
#[derive(Clone, Copy, Eq, Default)]
pub struct ExpeditedData {
    bytes: [u8; 4],
    len: u8,
    size_known: bool,
}

impl ExpeditedData {
    /// One to four bytes of `data`, size indicated. An empty value cannot travel expedited (`n` has two
    /// bits): send it segmented; an empty `data` here is sent as four zero bytes without size.
    pub fn new(data: &[u8]) -> ExpeditedData {
        if data.is_empty() {
            return ExpeditedData {
                bytes: [0; 4],
                len: 4,
                size_known: false,
            };
        }
        let len = data.len().min(4);
        let mut bytes = [0u8; 4];
        bytes[..len].copy_from_slice(&data[..len]);
        ExpeditedData {
            bytes,
            len: len as u8,
            size_known: true,
        }
    }

    /// The bytes (all four when the sender did not indicate the size).
    pub fn as_slice(&self) -> &[u8] {
        &self.bytes[..self.len as usize]
    }

    /// True when the sender indicated the size (s = 1).
    pub const fn size_known(&self) -> bool {
        self.size_known
    }

    fn decode(f: &Frame, n: u8, s: bool) -> ExpeditedData {
        let mut bytes = [0u8; 4];
        bytes.copy_from_slice(&f[4..8]);
        let len = if s { 4 - n } else { 4 };
        ExpeditedData {
            bytes,
            len,
            size_known: s,
        }
    }

    /// The `n` field (bytes not holding data) and `s` bit as an initiate frame carries them.
    fn n_and_s(&self) -> (u8, bool) {
        if self.size_known {
            (4 - self.len, true)
        } else {
            (0, false)
        }
    }
}

impl PartialEq for ExpeditedData {
    /// Equal when the data bytes and the size indication are; bytes beyond the data do not count.
    fn eq(&self, other: &ExpeditedData) -> bool {
        self.as_slice() == other.as_slice() && self.size_known == other.size_known
    }
}

impl std::fmt::Debug for ExpeditedData {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:02X?}", self.as_slice())?;
        if !self.size_known {
            f.write_str(" (size not indicated)")?;
        }
        Ok(())
    }
}

/// A frame a client sends (CiA 301 §7.2.4.3.3–7.2.4.3.17, client side).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClientFrame {
    /// Initiate SDO download, expedited (ccs = 1, e = 1).
    InitiateDownloadExpedited {
        /// The entry.
        mux: Address,
        /// The value.
        data: ExpeditedData,
    },
    /// Initiate SDO download, segmented (ccs = 1, e = 0); `size` is `None` when not indicated (s = 0).
    InitiateDownloadSegmented {
        /// The entry.
        mux: Address,
        /// The number of bytes to come.
        size: Option<u32>,
    },
    /// Download SDO segment (ccs = 0).
    DownloadSegment {
        /// Toggle bit.
        toggle: bool,
        /// The data.
        data: SegmentData,
        /// True on the last segment (c = 1).
        last: bool,
    },
    /// Initiate SDO upload (ccs = 2).
    InitiateUpload {
        /// The entry.
        mux: Address,
    },
    /// Upload SDO segment request (ccs = 3).
    UploadSegment {
        /// Toggle bit.
        toggle: bool,
    },
    /// Abort SDO transfer (cs = 4).
    Abort {
        /// The entry of the aborted transfer.
        mux: Address,
        /// Why.
        code: AbortCode,
    },
    /// Initiate block download (ccs = 6, cs = 0).
    InitiateBlockDownload {
        /// The entry.
        mux: Address,
        /// True when the client supports CRC (cc).
        crc: bool,
        /// The size, when indicated (s = 1).
        size: Option<u32>,
    },
    /// End block download (ccs = 6, cs = 1): `unused` bytes of the last segment carry no data (n).
    EndBlockDownload {
        /// Bytes of the last segment that hold no data (0–7).
        unused: u8,
        /// CRC of the whole data (0 when CRC is not used).
        crc: u16,
    },
    /// Initiate block upload (ccs = 5, cs = 0).
    InitiateBlockUpload {
        /// The entry.
        mux: Address,
        /// True when the client supports CRC (cc).
        crc: bool,
        /// Number of segments per block, 1–127.
        blksize: u8,
        /// Protocol switch threshold: the server may answer with a normal upload when the data is no
        /// larger than this (0: no switch).
        pst: u8,
    },
    /// Start block upload (ccs = 5, cs = 3).
    StartBlockUpload,
    /// Block upload acknowledgement (ccs = 5, cs = 2).
    BlockUploadAck {
        /// Sequence number of the last segment received in order.
        ackseq: u8,
        /// Segments per block for the next block, 1–127.
        blksize: u8,
    },
    /// End block upload response (ccs = 5, cs = 1).
    EndBlockUpload,
}

/// A frame a server sends (CiA 301 §7.2.4.3.3–7.2.4.3.17, server side).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ServerFrame {
    /// Initiate SDO download response (scs = 3).
    InitiateDownload {
        /// The entry.
        mux: Address,
    },
    /// Download SDO segment response (scs = 1).
    DownloadSegment {
        /// Toggle bit, as received.
        toggle: bool,
    },
    /// Initiate SDO upload response, expedited (scs = 2, e = 1).
    InitiateUploadExpedited {
        /// The entry.
        mux: Address,
        /// The value.
        data: ExpeditedData,
    },
    /// Initiate SDO upload response, segmented (scs = 2, e = 0).
    InitiateUploadSegmented {
        /// The entry.
        mux: Address,
        /// The size, when indicated.
        size: Option<u32>,
    },
    /// Upload SDO segment response (scs = 0).
    UploadSegment {
        /// Toggle bit.
        toggle: bool,
        /// The data.
        data: SegmentData,
        /// True on the last segment.
        last: bool,
    },
    /// Abort SDO transfer (cs = 4).
    Abort {
        /// The entry.
        mux: Address,
        /// Why.
        code: AbortCode,
    },
    /// Initiate block download response (scs = 5, ss = 0).
    InitiateBlockDownload {
        /// The entry.
        mux: Address,
        /// True when the server supports CRC (sc).
        crc: bool,
        /// Segments per block, 1–127.
        blksize: u8,
    },
    /// Block download acknowledgement (scs = 5, ss = 2).
    BlockDownloadAck {
        /// Sequence number of the last segment received in order.
        ackseq: u8,
        /// Segments per block for the next block.
        blksize: u8,
    },
    /// End block download response (scs = 5, ss = 1).
    EndBlockDownload,
    /// Initiate block upload response (scs = 6, ss = 0).
    InitiateBlockUpload {
        /// The entry.
        mux: Address,
        /// True when the server supports CRC (sc).
        crc: bool,
        /// The size, when indicated (s = 1).
        size: Option<u32>,
    },
    /// End block upload request (scs = 6, ss = 1).
    EndBlockUpload {
        /// Bytes of the last segment that hold no data (0–7).
        unused: u8,
        /// CRC of the whole data.
        crc: u16,
    },
}

/// One segment of a block (CiA 301 §7.2.4.3.11/15): byte 0 is `c` (bit 7, last segment) and the
/// sequence number 1–127; bytes 1–7 the data (always seven bytes on the wire; the last segment's unused
/// bytes are told by the end frame).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BlockSegment {
    /// Sequence number, 1–127.
    pub seqno: u8,
    /// True on the last segment of the transfer.
    pub last: bool,
    /// The seven data bytes.
    pub data: [u8; 7],
}

impl BlockSegment {
    /// Parses a segment; a sequence number of 0 is [`AbortCode::InvalidSequence`].
    pub fn parse(f: &Frame) -> Result<BlockSegment, AbortCode> {
        let seqno = f[0] & 0x7F;
        if seqno == 0 {
            return Err(AbortCode::InvalidSequence);
        }
        let mut data = [0u8; 7];
        data.copy_from_slice(&f[1..8]);
        Ok(BlockSegment {
            seqno,
            last: f[0] & 0x80 != 0,
            data,
        })
    }

    /// The frame's bytes.
    pub fn emit(&self) -> Frame {
        let mut f = [0u8; 8];
        f[0] = (self.seqno & 0x7F) | if self.last { 0x80 } else { 0 };
        f[1..8].copy_from_slice(&self.data);
        f
    }
}

fn abort_frame(mux: Address, code: AbortCode) -> Frame {
    let mut f = [0u8; 8];
    f[0] = 0x80;
    write_address(mux, &mut f);
    f[4..8].copy_from_slice(&code.code().to_le_bytes());
    f
}

fn abort_code(f: &Frame) -> AbortCode {
    AbortCode::from(u32::from_le_bytes([f[4], f[5], f[6], f[7]]))
}

fn size_field(f: &Frame) -> u32 {
    u32::from_le_bytes([f[4], f[5], f[6], f[7]])
}

fn segment(f: &Frame) -> (bool, SegmentData, bool) {
    let toggle = f[0] & 0x10 != 0;
    let n = ((f[0] >> 1) & 0x07) as usize;
    let last = f[0] & 0x01 != 0;
    (toggle, SegmentData::new(&f[1..8 - n]), last)
}

/// An initiate frame's data part (CiA 301 §7.2.4.3.3/6): expedited data (e = 1) or the size of a
/// segmented transfer (e = 0, size when s = 1).
enum Initiate {
    Expedited(ExpeditedData),
    Segmented(Option<u32>),
}

fn initiate(f: &Frame) -> Initiate {
    let b = f[0];
    let s = b & 0x01 != 0;
    if b & 0x02 != 0 {
        Initiate::Expedited(ExpeditedData::decode(f, (b >> 2) & 0x03, s))
    } else {
        Initiate::Segmented(s.then(|| size_field(f)))
    }
}

fn emit_expedited(cs: u8, mux: Address, data: &ExpeditedData) -> Frame {
    let mut f = [0u8; 8];
    let (n, s) = data.n_and_s();
    f[0] = (cs << 5) | (n << 2) | 0x02 | s as u8;
    write_address(mux, &mut f);
    f[4..4 + data.as_slice().len()].copy_from_slice(data.as_slice());
    f
}

fn emit_sized(cs: u8, mux: Address, size: Option<u32>) -> Frame {
    let mut f = [0u8; 8];
    f[0] = (cs << 5) | size.is_some() as u8;
    write_address(mux, &mut f);
    f[4..8].copy_from_slice(&size.unwrap_or(0).to_le_bytes());
    f
}

/// A block initiate with CRC flag and optional size (block download request, block upload response).
fn block_initiate(f: &Frame) -> (bool, Option<u32>) {
    (f[0] & 0x04 != 0, (f[0] & 0x02 != 0).then(|| size_field(f)))
}

fn emit_block_initiate(cs: u8, mux: Address, crc: bool, size: Option<u32>) -> Frame {
    let mut f = [0u8; 8];
    f[0] = (cs << 5) | ((crc as u8) << 2) | ((size.is_some() as u8) << 1);
    write_address(mux, &mut f);
    f[4..8].copy_from_slice(&size.unwrap_or(0).to_le_bytes());
    f
}

/// An end-of-block frame: unused bytes of the last segment and the CRC.
fn block_end(f: &Frame) -> (u8, u16) {
    ((f[0] >> 2) & 0x07, u16::from_le_bytes([f[1], f[2]]))
}

fn emit_block_end(cs: u8, unused: u8, crc: u16) -> Frame {
    let mut f = [0u8; 8];
    f[0] = (cs << 5) | ((unused & 0x07) << 2) | 0x01;
    f[1..3].copy_from_slice(&crc.to_le_bytes());
    f
}

/// A block acknowledgement (cs = 2 of the block command): last good sequence number, next block size.
fn emit_block_ack(cs: u8, ackseq: u8, blksize: u8) -> Frame {
    let mut f = [0u8; 8];
    f[0] = (cs << 5) | 0x02;
    f[1] = ackseq;
    f[2] = blksize;
    f
}

/// A download segment request or an upload segment response: both have command specifier 0.
fn emit_segment(toggle: bool, data: &SegmentData, last: bool) -> Frame {
    let mut f = [0u8; 8];
    f[0] = ((toggle as u8) << 4) | (((7 - data.len()) as u8) << 1) | last as u8;
    f[1..1 + data.len()].copy_from_slice(data.as_slice());
    f
}

impl ClientFrame {
    /// Parses a client frame (not a block segment: see [`BlockSegment`]).
    pub fn parse(f: &Frame) -> Result<ClientFrame, AbortCode> {
        let b = f[0];
        let mux = read_address(f);
        Ok(match b >> 5 {
            0 => {
                let (toggle, data, last) = segment(f);
                ClientFrame::DownloadSegment { toggle, data, last }
            }
            1 => match initiate(f) {
                Initiate::Expedited(data) => ClientFrame::InitiateDownloadExpedited { mux, data },
                Initiate::Segmented(size) => ClientFrame::InitiateDownloadSegmented { mux, size },
            },
            2 => ClientFrame::InitiateUpload { mux },
            3 => ClientFrame::UploadSegment {
                toggle: b & 0x10 != 0,
            },
            4 => ClientFrame::Abort {
                mux,
                code: abort_code(f),
            },
            5 => match b & 0x03 {
                0 => ClientFrame::InitiateBlockUpload {
                    mux,
                    crc: b & 0x04 != 0,
                    blksize: f[4],
                    pst: f[5],
                },
                1 => ClientFrame::EndBlockUpload,
                2 => ClientFrame::BlockUploadAck {
                    ackseq: f[1],
                    blksize: f[2],
                },
                _ => ClientFrame::StartBlockUpload,
            },
            6 => match b & 0x01 {
                0 => {
                    let (crc, size) = block_initiate(f);
                    ClientFrame::InitiateBlockDownload { mux, crc, size }
                }
                _ => {
                    let (unused, crc) = block_end(f);
                    ClientFrame::EndBlockDownload { unused, crc }
                }
            },
            _ => return Err(AbortCode::InvalidCommand),
        })
    }

    /// The frame's bytes; reserved bytes are 0.
    pub fn emit(&self) -> Frame {
        let mut f = [0u8; 8];
        match *self {
            ClientFrame::InitiateDownloadExpedited { mux, data } => {
                return emit_expedited(1, mux, &data)
            }
            ClientFrame::InitiateDownloadSegmented { mux, size } => {
                return emit_sized(1, mux, size)
            }
            ClientFrame::DownloadSegment { toggle, data, last } => {
                return emit_segment(toggle, &data, last)
            }
            ClientFrame::InitiateUpload { mux } => {
                f[0] = 0x40;
                write_address(mux, &mut f);
            }
            ClientFrame::UploadSegment { toggle } => f[0] = 0x60 | ((toggle as u8) << 4),
            ClientFrame::Abort { mux, code } => return abort_frame(mux, code),
            ClientFrame::InitiateBlockDownload { mux, crc, size } => {
                return emit_block_initiate(6, mux, crc, size)
            }
            ClientFrame::EndBlockDownload { unused, crc } => return emit_block_end(6, unused, crc),
            ClientFrame::InitiateBlockUpload {
                mux,
                crc,
                blksize,
                pst,
            } => {
                f[0] = 0xA0 | ((crc as u8) << 2);
                write_address(mux, &mut f);
                f[4] = blksize;
                f[5] = pst;
            }
            ClientFrame::StartBlockUpload => f[0] = 0xA3,
            ClientFrame::BlockUploadAck { ackseq, blksize } => {
                return emit_block_ack(5, ackseq, blksize)
            }
            ClientFrame::EndBlockUpload => f[0] = 0xA1,
        }
        f
    }
}

impl ServerFrame {
    /// Parses a server frame (not a block segment: see [`BlockSegment`]).
    pub fn parse(f: &Frame) -> Result<ServerFrame, AbortCode> {
        let b = f[0];
        let mux = read_address(f);
        Ok(match b >> 5 {
            0 => {
                let (toggle, data, last) = segment(f);
                ServerFrame::UploadSegment { toggle, data, last }
            }
            1 => ServerFrame::DownloadSegment {
                toggle: b & 0x10 != 0,
            },
            2 => match initiate(f) {
                Initiate::Expedited(data) => ServerFrame::InitiateUploadExpedited { mux, data },
                Initiate::Segmented(size) => ServerFrame::InitiateUploadSegmented { mux, size },
            },
            3 => ServerFrame::InitiateDownload { mux },
            4 => ServerFrame::Abort {
                mux,
                code: abort_code(f),
            },
            5 => match b & 0x03 {
                0 => ServerFrame::InitiateBlockDownload {
                    mux,
                    crc: b & 0x04 != 0,
                    blksize: f[4],
                },
                1 => ServerFrame::EndBlockDownload,
                2 => ServerFrame::BlockDownloadAck {
                    ackseq: f[1],
                    blksize: f[2],
                },
                _ => return Err(AbortCode::InvalidCommand),
            },
            6 => match b & 0x01 {
                0 => {
                    let (crc, size) = block_initiate(f);
                    ServerFrame::InitiateBlockUpload { mux, crc, size }
                }
                _ => {
                    let (unused, crc) = block_end(f);
                    ServerFrame::EndBlockUpload { unused, crc }
                }
            },
            _ => return Err(AbortCode::InvalidCommand),
        })
    }

    /// The frame's bytes; reserved bytes are 0.
    pub fn emit(&self) -> Frame {
        let mut f = [0u8; 8];
        match *self {
            ServerFrame::InitiateDownload { mux } => {
                f[0] = 0x60;
                write_address(mux, &mut f);
            }
            ServerFrame::DownloadSegment { toggle } => f[0] = 0x20 | ((toggle as u8) << 4),
            ServerFrame::InitiateUploadExpedited { mux, data } => {
                return emit_expedited(2, mux, &data)
            }
            ServerFrame::InitiateUploadSegmented { mux, size } => return emit_sized(2, mux, size),
            ServerFrame::UploadSegment { toggle, data, last } => {
                return emit_segment(toggle, &data, last)
            }
            ServerFrame::Abort { mux, code } => return abort_frame(mux, code),
            ServerFrame::InitiateBlockDownload { mux, crc, blksize } => {
                f[0] = 0xA0 | ((crc as u8) << 2);
                write_address(mux, &mut f);
                f[4] = blksize;
            }
            ServerFrame::BlockDownloadAck { ackseq, blksize } => {
                return emit_block_ack(5, ackseq, blksize)
            }
            ServerFrame::EndBlockDownload => f[0] = 0xA1,
            ServerFrame::InitiateBlockUpload { mux, crc, size } => {
                return emit_block_initiate(6, mux, crc, size)
            }
            ServerFrame::EndBlockUpload { unused, crc } => return emit_block_end(6, unused, crc),
        }
        f
    }
}

/// CRC-16 of SDO block transfer (CiA 301 §7.2.4.3.16): polynomial x^16 + x^12 + x^5 + 1 (0x1021),
/// initial value 0, no reflection, no final XOR (the "XMODEM" variant).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Crc16(u16);

impl Crc16 {
    /// A CRC over no data (0).
    pub const fn new() -> Crc16 {
        Crc16(0)
    }

    /// Adds `data`.
    pub fn update(&mut self, data: &[u8]) {
        let mut crc = self.0;
        for &b in data {
            crc ^= (b as u16) << 8;
            for _ in 0..8 {
                crc = if crc & 0x8000 != 0 {
                    (crc << 1) ^ 0x1021
                } else {
                    crc << 1
                };
            }
        }
        self.0 = crc;
    }

    /// The CRC so far.
    pub const fn value(&self) -> u16 {
        self.0
    }

    /// The CRC of `data`.
    pub fn of(data: &[u8]) -> u16 {
        let mut c = Crc16::new();
        c.update(data);
        c.value()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mux() -> Address {
        Address::new(0x1017, 0x00)
    }

    /// Each layout: parse the golden bytes, compare with the typed value, emit it back.
    fn client(bytes: Frame, frame: ClientFrame) {
        assert_eq!(ClientFrame::parse(&bytes), Ok(frame), "{bytes:02X?}");
        assert_eq!(frame.emit(), bytes, "{frame:?}");
    }

    fn server(bytes: Frame, frame: ServerFrame) {
        assert_eq!(ServerFrame::parse(&bytes), Ok(frame), "{bytes:02X?}");
        assert_eq!(frame.emit(), bytes, "{frame:?}");
    }

    #[test]
    fn segment_data_compares_and_shows_its_bytes_only() {
        let three = SegmentData::new(&[1, 2, 3]);
        assert_eq!(three.len(), 3);
        assert!(!three.is_empty());
        assert!(SegmentData::new(&[]).is_empty());
        assert_eq!(SegmentData::new(&[]).len(), 0);
        // Eight bytes given: seven taken.
        assert_eq!(SegmentData::new(&[9; 8]).as_slice(), [9; 7]);
        assert_eq!(three, SegmentData::new(&[1, 2, 3]));
        assert_ne!(three, SegmentData::new(&[1, 2, 4]));
        assert_ne!(three, SegmentData::new(&[1, 2]));
        assert_eq!(format!("{three:?}"), "[01, 02, 03]");
        assert_eq!(format!("{:?}", SegmentData::new(&[0xAB])), "[AB]");
    }

    #[test]
    fn expedited_data_compares_bytes_and_size_indication() {
        let two = ExpeditedData::new(&[0xE8, 0x03]);
        assert_eq!(two, ExpeditedData::new(&[0xE8, 0x03]));
        assert_ne!(two, ExpeditedData::new(&[0xE8, 0x04]));
        // The same four bytes, with and without the size indicated.
        let parsed = ServerFrame::parse(&[0x42, 0x17, 0x10, 0x00, 0, 0, 0, 0]).unwrap();
        let ServerFrame::InitiateUploadExpedited { data: no_size, .. } = parsed else {
            panic!("{parsed:?}");
        };
        assert!(!no_size.size_known());
        assert_eq!(no_size.as_slice(), [0, 0, 0, 0]);
        assert_ne!(no_size, ExpeditedData::new(&[0, 0, 0, 0]));
        assert_eq!(format!("{two:?}"), "[E8, 03]");
        assert_eq!(
            format!("{no_size:?}"),
            "[00, 00, 00, 00] (size not indicated)"
        );
    }

    #[test]
    fn client_frames_golden_bytes() {
        // CiA 301 §7.2.4.3.3: 0x2B = ccs 1, n 2, e 1, s 1: two bytes 0x03E8 to 0x1017:00.
        client(
            [0x2B, 0x17, 0x10, 0x00, 0xE8, 0x03, 0x00, 0x00],
            ClientFrame::InitiateDownloadExpedited {
                mux: mux(),
                data: ExpeditedData::new(&[0xE8, 0x03]),
            },
        );
        client(
            [0x23, 0x00, 0x10, 0x00, 1, 2, 3, 4],
            ClientFrame::InitiateDownloadExpedited {
                mux: Address::new(0x1000, 0),
                data: ExpeditedData::new(&[1, 2, 3, 4]),
            },
        );
        client(
            [0x21, 0x08, 0x10, 0x00, 0x20, 0x00, 0x00, 0x00],
            ClientFrame::InitiateDownloadSegmented {
                mux: Address::new(0x1008, 0),
                size: Some(32),
            },
        );
        client(
            [0x00, b'A', b'B', b'C', b'D', b'E', b'F', b'G'],
            ClientFrame::DownloadSegment {
                toggle: false,
                data: SegmentData::new(b"ABCDEFG"),
                last: false,
            },
        );
        // 0x1B = toggle 1, n = 5 (two bytes of data), c = 1.
        client(
            [0x1B, b'H', b'I', 0, 0, 0, 0, 0],
            ClientFrame::DownloadSegment {
                toggle: true,
                data: SegmentData::new(b"HI"),
                last: true,
            },
        );
        client(
            [0x40, 0x18, 0x10, 0x02, 0, 0, 0, 0],
            ClientFrame::InitiateUpload {
                mux: Address::new(0x1018, 2),
            },
        );
        client(
            [0x60, 0, 0, 0, 0, 0, 0, 0],
            ClientFrame::UploadSegment { toggle: false },
        );
        client(
            [0x70, 0, 0, 0, 0, 0, 0, 0],
            ClientFrame::UploadSegment { toggle: true },
        );
        client(
            [0x80, 0x17, 0x10, 0x00, 0x00, 0x00, 0x04, 0x05],
            ClientFrame::Abort {
                mux: mux(),
                code: AbortCode::Timeout,
            },
        );
        // CiA 301 §7.2.4.3.9: 0xC6 = ccs 6, cc 1, s 1, cs 0.
        client(
            [0xC6, 0x00, 0x20, 0x01, 0x00, 0x00, 0x10, 0x00],
            ClientFrame::InitiateBlockDownload {
                mux: Address::new(0x2000, 1),
                crc: true,
                size: Some(0x0010_0000),
            },
        );
        // 0xD5 = ccs 6, n = 5, cs 1.
        client(
            [0xD5, 0x34, 0x12, 0, 0, 0, 0, 0],
            ClientFrame::EndBlockDownload {
                unused: 5,
                crc: 0x1234,
            },
        );
        // CiA 301 §7.2.4.3.13: 0xA4 = ccs 5, cc 1, cs 0; blksize 127, pst 4.
        client(
            [0xA4, 0x00, 0x20, 0x01, 0x7F, 0x04, 0, 0],
            ClientFrame::InitiateBlockUpload {
                mux: Address::new(0x2000, 1),
                crc: true,
                blksize: 127,
                pst: 4,
            },
        );
        client([0xA3, 0, 0, 0, 0, 0, 0, 0], ClientFrame::StartBlockUpload);
        client(
            [0xA2, 0x7F, 0x40, 0, 0, 0, 0, 0],
            ClientFrame::BlockUploadAck {
                ackseq: 127,
                blksize: 64,
            },
        );
        client([0xA1, 0, 0, 0, 0, 0, 0, 0], ClientFrame::EndBlockUpload);
    }

    #[test]
    fn server_frames_golden_bytes() {
        server(
            [0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0],
            ServerFrame::InitiateDownload { mux: mux() },
        );
        server(
            [0x20, 0, 0, 0, 0, 0, 0, 0],
            ServerFrame::DownloadSegment { toggle: false },
        );
        server(
            [0x30, 0, 0, 0, 0, 0, 0, 0],
            ServerFrame::DownloadSegment { toggle: true },
        );
        // 0x4F = scs 2, n 3, e 1, s 1: one byte.
        server(
            [0x4F, 0x01, 0x10, 0x00, 0x05, 0, 0, 0],
            ServerFrame::InitiateUploadExpedited {
                mux: Address::new(0x1001, 0),
                data: ExpeditedData::new(&[5]),
            },
        );
        server(
            [0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00],
            ServerFrame::InitiateUploadExpedited {
                mux: Address::new(0x1000, 0),
                data: ExpeditedData::new(&[0x92, 0x01, 0x02, 0x00]),
            },
        );
        server(
            [0x41, 0x08, 0x10, 0x00, 0x09, 0, 0, 0],
            ServerFrame::InitiateUploadSegmented {
                mux: Address::new(0x1008, 0),
                size: Some(9),
            },
        );
        // 0x0B: toggle 0, n 5, c 1.
        server(
            [0x0B, b'x', b'y', 0, 0, 0, 0, 0],
            ServerFrame::UploadSegment {
                toggle: false,
                data: SegmentData::new(b"xy"),
                last: true,
            },
        );
        server(
            [0x80, 0x00, 0x30, 0x00, 0x00, 0x00, 0x02, 0x06],
            ServerFrame::Abort {
                mux: Address::new(0x3000, 0),
                code: AbortCode::NoObject,
            },
        );
        server(
            [0xA4, 0x00, 0x20, 0x01, 0x7F, 0, 0, 0],
            ServerFrame::InitiateBlockDownload {
                mux: Address::new(0x2000, 1),
                crc: true,
                blksize: 127,
            },
        );
        server(
            [0xA2, 0x05, 0x7F, 0, 0, 0, 0, 0],
            ServerFrame::BlockDownloadAck {
                ackseq: 5,
                blksize: 127,
            },
        );
        server([0xA1, 0, 0, 0, 0, 0, 0, 0], ServerFrame::EndBlockDownload);
        server(
            [0xC6, 0x00, 0x20, 0x01, 0x00, 0x04, 0x00, 0x00],
            ServerFrame::InitiateBlockUpload {
                mux: Address::new(0x2000, 1),
                crc: true,
                size: Some(1024),
            },
        );
        server(
            [0xC9, 0xCD, 0xAB, 0, 0, 0, 0, 0],
            ServerFrame::EndBlockUpload {
                unused: 2,
                crc: 0xABCD,
            },
        );
    }

    #[test]
    fn block_segments_golden_bytes() {
        let s = BlockSegment {
            seqno: 127,
            last: true,
            data: [1, 2, 3, 4, 5, 6, 7],
        };
        assert_eq!(s.emit(), [0xFF, 1, 2, 3, 4, 5, 6, 7]);
        assert_eq!(BlockSegment::parse(&[0xFF, 1, 2, 3, 4, 5, 6, 7]), Ok(s));
        assert_eq!(
            BlockSegment::parse(&[0x80, 0, 0, 0, 0, 0, 0, 0]),
            Err(AbortCode::InvalidSequence)
        );
    }

    #[test]
    fn expedited_without_size_takes_four_bytes() {
        let f = [0x22, 0x00, 0x20, 0x00, 9, 8, 7, 6];
        match ClientFrame::parse(&f).unwrap() {
            ClientFrame::InitiateDownloadExpedited { data, .. } => {
                assert!(!data.size_known());
                assert_eq!(data.as_slice(), &[9, 8, 7, 6]);
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn unknown_command_specifiers() {
        assert_eq!(
            ClientFrame::parse(&[0xE0, 0, 0, 0, 0, 0, 0, 0]),
            Err(AbortCode::InvalidCommand)
        );
        assert_eq!(
            ServerFrame::parse(&[0xE0, 0, 0, 0, 0, 0, 0, 0]),
            Err(AbortCode::InvalidCommand)
        );
        assert_eq!(
            ServerFrame::parse(&[0xA3, 0, 0, 0, 0, 0, 0, 0]),
            Err(AbortCode::InvalidCommand)
        );
    }

    #[test]
    fn every_byte_0_parses_or_is_an_invalid_command() {
        for b in 0..=255u8 {
            let f = [b, 0x17, 0x10, 0, 1, 2, 3, 4];
            if let Ok(c) = ClientFrame::parse(&f) {
                // Emitting the parsed frame and parsing again gives the same frame.
                assert_eq!(ClientFrame::parse(&c.emit()), Ok(c), "{b:02X}");
            }
            if let Ok(s) = ServerFrame::parse(&f) {
                assert_eq!(ServerFrame::parse(&s.emit()), Ok(s), "{b:02X}");
            }
        }
    }

    #[test]
    fn crc16_is_the_xmodem_variant() {
        // The standard check value of CRC-16/XMODEM.
        assert_eq!(Crc16::of(b"123456789"), 0x31C3);
        assert_eq!(Crc16::of(b""), 0x0000);
        let mut c = Crc16::new();
        c.update(b"1234");
        c.update(b"56789");
        assert_eq!(c.value(), 0x31C3);
    }
}
