//! EtherCAT frames (EtherType 0x88A4) and their datagrams (ETG.1000.4 §5.3, §5.4).
//!
//! Frame: Ethernet destination (6), source (6), EtherType 0x88A4 (2), the EtherCAT header (2 bytes,
//! little-endian: length of the datagrams in bits 0–10, type in bits 12–15, 1 = EtherCAT commands), then
//! the datagrams. Datagram: command (1), index (1), address (4: ADP and ADO, or a 32-bit logical
//! address), length/flags (2: length bits 0–10, circulating bit 14, more-follows bit 15), IRQ (2), data,
//! working counter (2).

/// A datagram command (ETG.1000.4 Table 14) as the byte it is on the wire; a byte no table defines is
/// kept as it is (the ESC passes such a datagram on unchanged, like NOP).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Command(pub u8);

macro_rules! commands {
    ($( $(#[$doc:meta])* $name:ident = $byte:literal; )*) => {
        impl Command {
            $( $(#[$doc])* pub const $name: Command = Command($byte); )*

            /// Every command ETG.1000.4 defines, in the table's order.
            pub const ALL: &'static [Command] = &[$(Command::$name,)*];

            /// The command's name (`"LRW"`), or `None` for a byte no table defines.
            pub const fn name(self) -> Option<&'static str> {
                match self.0 {
                    $($byte => Some(stringify!($name)),)*
                    _ => None,
                }
            }
        }

        /// The commands as constants of their own, for `use esc::cmd::*`-style call sites.
        pub mod cmd {
            use super::Command;
            $( $(#[$doc])* pub const $name: Command = Command::$name; )*
        }
    };
}

commands! {
    /// No operation.
    NOP = 0;
    /// Auto-increment read.
    APRD = 1;
    /// Auto-increment write.
    APWR = 2;
    /// Auto-increment read-write.
    APRW = 3;
    /// Configured-address read.
    FPRD = 4;
    /// Configured-address write.
    FPWR = 5;
    /// Configured-address read-write.
    FPRW = 6;
    /// Broadcast read.
    BRD = 7;
    /// Broadcast write.
    BWR = 8;
    /// Broadcast read-write.
    BRW = 9;
    /// Logical read.
    LRD = 10;
    /// Logical write.
    LWR = 11;
    /// Logical read-write.
    LRW = 12;
    /// Auto-increment read, multiple write.
    ARMW = 13;
    /// Configured-address read, multiple write.
    FRMW = 14;
}

impl std::fmt::Display for Command {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.name() {
            Some(name) => f.write_str(name),
            None => write!(f, "command 0x{:02X}", self.0),
        }
    }
}

/// The EtherType of EtherCAT.
pub use ecat_link::ETHERTYPE;
/// Ethernet header bytes.
pub const ETH_HEADER: usize = 14;
/// Datagram header bytes.
pub const DATAGRAM_HEADER: usize = 10;

/// Why a frame was not processed (it is dropped, as an ESC drops a frame it cannot parse).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum FrameError {
    /// Shorter than the headers say.
    #[error("frame of {len} bytes: {what}")]
    Truncated {
        /// Bytes in the frame.
        len: usize,
        /// Which part is cut off.
        what: &'static str,
    },
    /// Not EtherCAT.
    #[error("EtherType 0x{0:04X} is not EtherCAT (0x88A4)")]
    EtherType(u16),
    /// Not an EtherCAT command frame.
    #[error("EtherCAT frame type {0} is not 1 (commands)")]
    Type(u8),
}

/// Where one datagram lies in a frame buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DatagramAt {
    /// Offset of the datagram header.
    pub start: usize,
    /// Data length.
    pub len: usize,
}

impl DatagramAt {
    /// Offset of the data.
    pub const fn data(&self) -> usize {
        self.start + DATAGRAM_HEADER
    }

    /// Offset of the working counter.
    pub const fn wkc(&self) -> usize {
        self.start + DATAGRAM_HEADER + self.len
    }
}

/// The datagrams of an EtherCAT frame, checked for their lengths.
pub fn datagrams(frame: &[u8]) -> Result<Vec<DatagramAt>, FrameError> {
    let mut out = Vec::new();
    datagrams_into(frame, &mut out)?;
    Ok(out)
}

/// [`datagrams`] into `out` (emptied first), so that a caller that keeps `out` allocates nothing
/// per frame; on an error `out` holds no meaning.
pub fn datagrams_into(frame: &[u8], out: &mut Vec<DatagramAt>) -> Result<(), FrameError> {
    out.clear();
    let len = frame.len();
    if len < ETH_HEADER + 2 {
        return Err(FrameError::Truncated {
            len,
            what: "the Ethernet or EtherCAT header",
        });
    }
    let ethertype = u16::from_be_bytes([frame[12], frame[13]]);
    if ethertype != ETHERTYPE {
        return Err(FrameError::EtherType(ethertype));
    }
    let h = u16::from_le_bytes([frame[14], frame[15]]);
    let kind = (h >> 12) as u8;
    if kind != 1 {
        return Err(FrameError::Type(kind));
    }
    let body = usize::from(h & 0x07FF);
    if ETH_HEADER + 2 + body > len {
        return Err(FrameError::Truncated {
            len,
            what: "the datagrams the EtherCAT header announces",
        });
    }
    let end = ETH_HEADER + 2 + body;
    let mut at = ETH_HEADER + 2;
    loop {
        if at + DATAGRAM_HEADER > end {
            return Err(FrameError::Truncated {
                len,
                what: "a datagram header",
            });
        }
        let lf = u16::from_le_bytes([frame[at + 6], frame[at + 7]]);
        let dlen = usize::from(lf & 0x07FF);
        if at + DATAGRAM_HEADER + dlen + 2 > end {
            return Err(FrameError::Truncated {
                len,
                what: "a datagram's data and working counter",
            });
        }
        out.push(DatagramAt {
            start: at,
            len: dlen,
        });
        at += DATAGRAM_HEADER + dlen + 2;
        if lf & 0x8000 == 0 {
            break;
        }
    }
    Ok(())
}

/// One datagram to build a frame from (what a master sends).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Datagram {
    /// Command.
    pub cmd: Command,
    /// Index (the master's tag).
    pub index: u8,
    /// ADP (position or station address) and ADO (register), or a logical address.
    pub address: u32,
    /// Data.
    pub data: Vec<u8>,
    /// Working counter.
    pub wkc: u16,
}

impl Datagram {
    /// A datagram addressing slave/station `adp`, register `ado`.
    pub fn new(cmd: Command, adp: u16, ado: u16, data: Vec<u8>) -> Datagram {
        Datagram {
            cmd,
            index: 0,
            address: u32::from(adp) | (u32::from(ado) << 16),
            data,
            wkc: 0,
        }
    }
}

/// A frame of `datagrams` (each at most 2,047 data bytes, the 11-bit length), from `src` to broadcast.
pub fn emit(datagrams: &[Datagram], src: [u8; 6]) -> Vec<u8> {
    let mut f = vec![0xFF; 6];
    f.extend_from_slice(&src);
    f.extend_from_slice(&ETHERTYPE.to_be_bytes());
    let body: usize = datagrams
        .iter()
        .map(|d| DATAGRAM_HEADER + d.data.len() + 2)
        .sum();
    f.extend_from_slice(&((body as u16 & 0x07FF) | 0x1000).to_le_bytes());
    for (k, d) in datagrams.iter().enumerate() {
        f.push(d.cmd.0);
        f.push(d.index);
        f.extend_from_slice(&d.address.to_le_bytes());
        let more = if k + 1 < datagrams.len() { 0x8000 } else { 0 };
        f.extend_from_slice(&((d.data.len() as u16 & 0x07FF) | more).to_le_bytes());
        f.extend_from_slice(&0u16.to_le_bytes());
        f.extend_from_slice(&d.data);
        f.extend_from_slice(&d.wkc.to_le_bytes());
    }
    // Ethernet minimum payload.
    let padded = f.len().max(60);
    f.resize(padded, 0);
    f
}

/// The datagrams of a processed frame, read back (what a master receives).
pub fn parse(frame: &[u8]) -> Result<Vec<Datagram>, FrameError> {
    Ok(datagrams(frame)?
        .into_iter()
        .map(|d| Datagram {
            cmd: Command(frame[d.start]),
            index: frame[d.start + 1],
            address: u32::from_le_bytes([
                frame[d.start + 2],
                frame[d.start + 3],
                frame[d.start + 4],
                frame[d.start + 5],
            ]),
            data: frame[d.data()..d.data() + d.len].to_vec(),
            wkc: u16::from_le_bytes([frame[d.wkc()], frame[d.wkc() + 1]]),
        })
        .collect())
}
