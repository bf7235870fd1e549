//! Reading a pcapng file block by block, in bounded memory: each block is held only while it is
//! looked at, a block longer than [`MAX_BLOCK`] is read past, and a section keeps at most
//! [`MAX_INTERFACES`] interfaces. Sections of either byte order, `if_tsresol` in powers of 10 or 2,
//! `if_tsoffset`; Enhanced, Simple and the obsolete Packet Blocks; other blocks are skipped.

use std::io::{self, Read};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use super::{
    Direction, BYTE_ORDER_MAGIC, EPB, EPB_FLAGS, IDB, IF_NAME, IF_TSOFFSET, IF_TSRESOL, PB, SHB,
    SPB,
};

/// The longest block held, in bytes: an Ethernet jumbo frame fits many times over. A longer packet
/// block is read past and counted ([`Reader::skipped`]); a longer header block is an error.
pub const MAX_BLOCK: u32 = 256 * 1024;
/// Interfaces a section keeps at most; the packets of further ones are skipped as of an unknown
/// interface.
pub const MAX_INTERFACES: usize = 1024;
/// The longest interface name kept, in bytes (a longer one is cut).
const MAX_NAME: usize = 256;

/// Why a file cannot be read on. Each names the byte offset of the block it is about.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReadError {
    /// Reading failed.
    #[error(transparent)]
    Io(#[from] io::Error),
    /// The file does not begin with a Section Header Block.
    #[error("not a pcapng file (no Section Header Block at its start)")]
    NotPcapng,
    /// A Section Header Block whose byte-order magic is neither order of 0x1A2B3C4D.
    #[error("byte {offset}: the section's byte-order magic is 0x{magic:08X}, not 0x1A2B3C4D")]
    ByteOrder {
        /// Where the block starts.
        offset: u64,
        /// The word read.
        magic: u32,
    },
    /// A section of another major version than 1.
    #[error("byte {offset}: pcapng version {major}.{minor} (this reader reads 1.x)")]
    Version {
        /// Where the block starts.
        offset: u64,
        /// Major version.
        major: u16,
        /// Minor version.
        minor: u16,
    },
    /// A block length shorter than a block of its type, or not a multiple of 4.
    #[error("byte {offset}: block length {length} is not a length of a block of type 0x{block_type:08X}")]
    Length {
        /// Where the block starts.
        offset: u64,
        /// The block's type.
        block_type: u32,
        /// The length given.
        length: u32,
    },
    /// A header block (section or interface) longer than [`MAX_BLOCK`].
    #[error("byte {offset}: a block of type 0x{block_type:08X} of {length} bytes (at most {MAX_BLOCK} are read)")]
    TooLong {
        /// Where the block starts.
        offset: u64,
        /// The block's type.
        block_type: u32,
        /// The length given.
        length: u32,
    },
    /// The two lengths of a block differ.
    #[error("byte {offset}: the block's lengths differ ({first} at its start, {last} at its end)")]
    Lengths {
        /// Where the block starts.
        offset: u64,
        /// The length at the start.
        first: u32,
        /// The length at the end.
        last: u32,
    },
    /// A block's contents do not fit its length.
    #[error("byte {offset}: {what}")]
    Block {
        /// Where the block starts.
        offset: u64,
        /// What does not fit.
        what: String,
    },
    /// The file ends inside a block (a capture cut short, or a file still being written).
    #[error("byte {offset}: the file ends inside a block")]
    Truncated {
        /// Where the block starts.
        offset: u64,
    },
}

/// An interface of a section, as its Interface Description Block describes it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InterfaceInfo {
    /// Its link type (`LINKTYPE_…`).
    pub link_type: u16,
    /// `if_name`, where given (cut at 256 bytes).
    pub name: Option<String>,
    /// `if_tsresol`: 10^-n s, or 2^-n s with the top bit set; 6 (microseconds) where not given.
    pub tsresol: u8,
    /// `if_tsoffset`: seconds added to every timestamp.
    pub tsoffset: i64,
}

/// A packet read, with what its interface says of it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Packet<'a> {
    /// Its interface's number in its section (0 for the first).
    pub interface: u32,
    /// Its interface's link type.
    pub link_type: u16,
    /// Its time, where the block has one (a Simple Packet Block has none); `None` too for a time
    /// that is no instant of this system's clock.
    pub time: Option<SystemTime>,
    /// The bytes captured.
    pub data: &'a [u8],
    /// Its direction, where `epb_flags` gives one.
    pub direction: Option<Direction>,
}

/// A pcapng file read block by block ([`Reader::next_packet`]).
pub struct Reader<R> {
    input: R,
    /// Where the next block starts.
    offset: u64,
    /// The present section's byte order: big-endian.
    big: bool,
    /// A Section Header Block was read.
    in_section: bool,
    /// The present section's interfaces.
    interfaces: Vec<InterfaceInfo>,
    /// Every interface of every section so far (at most [`MAX_INTERFACES`]), for a summary.
    seen: Vec<InterfaceInfo>,
    /// The block being looked at.
    block: Vec<u8>,
    skipped: u64,
    unknown_interface: u64,
}

/// Reads as much of `buf` as the input holds: the bytes read (fewer only at its end).
fn read_up_to(input: &mut impl Read, buf: &mut [u8]) -> io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match input.read(&mut buf[n..]) {
            Ok(0) => break,
            Ok(k) => n += k,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(n)
}

impl<R: Read> Reader<R> {
    /// A reader of `input`, from its first byte.
    pub fn new(input: R) -> Reader<R> {
        Reader {
            input,
            offset: 0,
            big: false,
            in_section: false,
            interfaces: Vec::new(),
            seen: Vec::new(),
            block: Vec::new(),
            skipped: 0,
            unknown_interface: 0,
        }
    }

    /// Packet blocks longer than [`MAX_BLOCK`] read past so far.
    pub fn skipped(&self) -> u64 {
        self.skipped
    }

    /// Packets of an interface no Interface Description Block of their section described (or one
    /// beyond [`MAX_INTERFACES`]), skipped so far.
    pub fn unknown_interface(&self) -> u64 {
        self.unknown_interface
    }

    /// Every interface described so far, in every section, in order (at most [`MAX_INTERFACES`]).
    pub fn interfaces_seen(&self) -> &[InterfaceInfo] {
        &self.seen
    }

    fn u16_at(&self, at: usize) -> u16 {
        let b = [self.block[at], self.block[at + 1]];
        if self.big {
            u16::from_be_bytes(b)
        } else {
            u16::from_le_bytes(b)
        }
    }

    fn u32_at(&self, at: usize) -> u32 {
        let b = [
            self.block[at],
            self.block[at + 1],
            self.block[at + 2],
            self.block[at + 3],
        ];
        if self.big {
            u32::from_be_bytes(b)
        } else {
            u32::from_le_bytes(b)
        }
    }

    /// The next packet; `None` at the end of the file (after a whole block).
    pub fn next_packet(&mut self) -> Result<Option<Packet<'_>>, ReadError> {
        loop {
            let Some((block_type, offset)) = self.next_block()? else {
                return Ok(None);
            };
            let raw = match block_type {
                SHB => {
                    self.section(offset)?;
                    continue;
                }
                IDB => {
                    self.interface(offset)?;
                    continue;
                }
                EPB | PB | SPB => self.packet_at(block_type, offset)?,
                _ => continue,
            };
            let Some(info) = self.interfaces.get(raw.interface as usize) else {
                self.unknown_interface += 1;
                continue;
            };
            let (link_type, tsresol, tsoffset) = (info.link_type, info.tsresol, info.tsoffset);
            return Ok(Some(Packet {
                interface: raw.interface,
                link_type,
                time: raw.units.and_then(|ts| timestamp(ts, tsresol, tsoffset)),
                data: &self.block[raw.start..raw.start + raw.len],
                direction: raw.direction,
            }));
        }
    }

    /// Reads the next whole block into `self.block` (its type and lengths included): its type and
    /// offset, or `None` at the end of the file. A packet block longer than [`MAX_BLOCK`] is read
    /// past and the next one taken.
    fn next_block(&mut self) -> Result<Option<(u32, u64)>, ReadError> {
        loop {
            let offset = self.offset;
            let mut head = [0u8; 12];
            let n = read_up_to(&mut self.input, &mut head[..8])?;
            if n == 0 {
                return Ok(None);
            }
            if n < 8 {
                return Err(if self.in_section {
                    ReadError::Truncated { offset }
                } else {
                    ReadError::NotPcapng
                });
            }
            let raw_type = u32::from_le_bytes([head[0], head[1], head[2], head[3]]);
            if raw_type == SHB {
                // The byte order is the section's: the magic after the length says it.
                if read_up_to(&mut self.input, &mut head[8..12])? < 4 {
                    return Err(ReadError::Truncated { offset });
                }
                let magic = u32::from_le_bytes([head[8], head[9], head[10], head[11]]);
                self.big = match magic {
                    BYTE_ORDER_MAGIC => false,
                    m if m.swap_bytes() == BYTE_ORDER_MAGIC => true,
                    magic => return Err(ReadError::ByteOrder { offset, magic }),
                };
            } else if !self.in_section {
                return Err(ReadError::NotPcapng);
            }
            let word = |b: [u8; 4], big: bool| {
                if big {
                    u32::from_be_bytes(b)
                } else {
                    u32::from_le_bytes(b)
                }
            };
            let block_type = word([head[0], head[1], head[2], head[3]], self.big);
            let length = word([head[4], head[5], head[6], head[7]], self.big);
            let least = match block_type {
                SHB => 28,
                IDB => 20,
                EPB => 32,
                PB => 32,
                SPB => 16,
                _ => 12,
            };
            if length < least || length % 4 != 0 {
                return Err(ReadError::Length {
                    offset,
                    block_type,
                    length,
                });
            }
            let have = if block_type == SHB { 12 } else { 8 };
            if length > MAX_BLOCK {
                if matches!(block_type, SHB | IDB) {
                    return Err(ReadError::TooLong {
                        offset,
                        block_type,
                        length,
                    });
                }
                let rest = u64::from(length) - have as u64;
                let passed = io::copy(&mut (&mut self.input).take(rest), &mut io::sink())?;
                if passed < rest {
                    return Err(ReadError::Truncated { offset });
                }
                self.offset += u64::from(length);
                if matches!(block_type, EPB | PB | SPB) {
                    self.skipped += 1;
                }
                continue;
            }
            self.block.clear();
            self.block.extend_from_slice(&head[..have]);
            self.block.resize(length as usize, 0);
            if read_up_to(&mut self.input, &mut self.block[have..])? < length as usize - have {
                return Err(ReadError::Truncated { offset });
            }
            let last = self.u32_at(length as usize - 4);
            if last != length {
                return Err(ReadError::Lengths {
                    offset,
                    first: length,
                    last,
                });
            }
            self.offset += u64::from(length);
            return Ok(Some((block_type, offset)));
        }
    }

    /// A Section Header Block: a new section, its interfaces none yet.
    fn section(&mut self, offset: u64) -> Result<(), ReadError> {
        let (major, minor) = (self.u16_at(12), self.u16_at(14));
        if major != 1 {
            return Err(ReadError::Version {
                offset,
                major,
                minor,
            });
        }
        self.in_section = true;
        self.interfaces.clear();
        Ok(())
    }

    /// An Interface Description Block: the section's next interface.
    fn interface(&mut self, offset: u64) -> Result<(), ReadError> {
        let mut info = InterfaceInfo {
            link_type: self.u16_at(8),
            name: None,
            tsresol: 6,
            tsoffset: 0,
        };
        let end = self.block.len() - 4;
        self.options(offset, 16, end, |code, value, big| match code {
            IF_NAME => {
                let cut = &value[..value.len().min(MAX_NAME)];
                let text = String::from_utf8_lossy(cut);
                info.name = Some(text.trim_end_matches('\0').to_string());
            }
            IF_TSRESOL if value.len() == 1 => info.tsresol = value[0],
            IF_TSOFFSET if value.len() == 8 => {
                let mut b = [0u8; 8];
                b.copy_from_slice(value);
                info.tsoffset = if big {
                    i64::from_be_bytes(b)
                } else {
                    i64::from_le_bytes(b)
                };
            }
            _ => {}
        })?;
        if self.interfaces.len() < MAX_INTERFACES {
            self.interfaces.push(info.clone());
        }
        if self.seen.len() < MAX_INTERFACES {
            self.seen.push(info);
        }
        Ok(())
    }

    /// Calls `each(code, value, big_endian)` for every option between `start` and `end` of the
    /// block, up to `opt_endofopt`.
    fn options(
        &self,
        offset: u64,
        start: usize,
        end: usize,
        mut each: impl FnMut(u16, &[u8], bool),
    ) -> Result<(), ReadError> {
        let mut at = start;
        while at + 4 <= end {
            let (code, len) = (self.u16_at(at), usize::from(self.u16_at(at + 2)));
            if code == 0 {
                break;
            }
            let value = at + 4;
            if value + len > end {
                return Err(ReadError::Block {
                    offset,
                    what: format!("option {code} of {len} bytes runs past the block's end"),
                });
            }
            each(code, &self.block[value..value + len], self.big);
            at = value + len.div_ceil(4) * 4;
        }
        Ok(())
    }

    /// What a packet block holds: its interface, where its bytes are, its time, its direction.
    fn packet_at(&self, block_type: u32, offset: u64) -> Result<RawPacket, ReadError> {
        let end = self.block.len() - 4;
        if block_type == SPB {
            let original = self.u32_at(8) as usize;
            return Ok(RawPacket {
                interface: 0,
                start: 12,
                len: original.min(end - 12),
                units: None,
                direction: None,
            });
        }
        let interface = if block_type == EPB {
            self.u32_at(8)
        } else {
            u32::from(self.u16_at(8))
        };
        let units = (u64::from(self.u32_at(12)) << 32) | u64::from(self.u32_at(16));
        let captured = self.u32_at(20) as usize;
        if captured > end - 28 {
            return Err(ReadError::Block {
                offset,
                what: format!(
                    "a packet of {captured} bytes in a block of {} bytes",
                    self.block.len()
                ),
            });
        }
        let mut direction = None;
        if block_type == EPB {
            let options = 28 + captured.div_ceil(4) * 4;
            self.options(offset, options, end, |code, value, big| {
                if code == EPB_FLAGS && value.len() == 4 {
                    let b = [value[0], value[1], value[2], value[3]];
                    let flags = if big {
                        u32::from_be_bytes(b)
                    } else {
                        u32::from_le_bytes(b)
                    };
                    direction = Direction::from_flags(flags);
                }
            })?;
        }
        Ok(RawPacket {
            interface,
            start: 28,
            len: captured,
            units: Some(units),
            direction,
        })
    }
}

/// A packet block as read, before its interface is looked up.
struct RawPacket {
    interface: u32,
    start: usize,
    len: usize,
    units: Option<u64>,
    direction: Option<Direction>,
}

/// The instant `units` of `tsresol` (10^-n s, or 2^-n s with bit 7 set) since 1970 plus `offset`
/// seconds; `None` where the system's clock has no such instant.
pub fn timestamp(units: u64, tsresol: u8, offset: i64) -> Option<SystemTime> {
    let n = u32::from(tsresol & 0x7F);
    let (secs, nanos) = if tsresol & 0x80 == 0 {
        match 10u128.checked_pow(n) {
            Some(per_second) => {
                let units = u128::from(units);
                let frac = units % per_second;
                (units / per_second, frac * 1_000_000_000 / per_second)
            }
            None => (0, 0),
        }
    } else {
        let units = u128::from(units);
        let per_second = 1u128 << n.min(127);
        let frac = units % per_second;
        (units / per_second, frac * 1_000_000_000 / per_second)
    };
    let since = Duration::new(u64::try_from(secs).ok()?, nanos as u32);
    let at = UNIX_EPOCH.checked_add(since)?;
    if offset >= 0 {
        at.checked_add(Duration::from_secs(offset.unsigned_abs()))
    } else {
        at.checked_sub(Duration::from_secs(offset.unsigned_abs()))
    }
}
