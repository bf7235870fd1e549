//! EtherCAT frames (EtherType 0x88A4) and their datagrams (ETG.1000.4 §5.3, §5.4).
//!
//! Frame: Ethernet destination (6), source (6), EtherType 0x88A4 (2), the EtherCAT header (2 bytes,
//! little-endian: length of the datagrams in bits 0–10, type in bits 12–15, 1 = EtherCAT commands), then
//! the datagrams. Datagram: command (1), index (1), address (4: ADP and ADO, or a 32-bit logical
//! address), length/flags (2: length bits 0–10, circulating bit 14, more-follows bit 15), IRQ (2), data,
//! working counter (2).

/// A datagram command code (ETG.1000.4 Table 14) as the byte it is on the wire; a byte no table
/// defines is kept as it is (the ESC passes such a datagram on unchanged, like NOP). [`Command`] is
/// the command with its address.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CommandCode(pub u8);

macro_rules! commands {
    ($( $(#[$doc:meta])* $name:ident = $byte:literal; )*) => {
        impl CommandCode {
            $( $(#[$doc])* pub const $name: CommandCode = CommandCode($byte); )*

            /// Every command ETG.1000.4 defines, in the table's order.
            pub const ALL: &'static [CommandCode] = &[$(CommandCode::$name,)*];

            /// The command's name (`"LRW"`), or `None` for a byte no table defines.
            pub const fn name(self) -> Option<&'static str> {
                match self.0 {
                    $($byte => Some(stringify!($name)),)*
                    _ => None,
                }
            }
        }

        /// The command codes as constants of their own, for `use esc::cmd::*`-style call sites.
        pub mod cmd {
            use super::CommandCode;
            $( $(#[$doc])* pub const $name: CommandCode = CommandCode::$name; )*
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

impl std::fmt::Display for CommandCode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.name() {
            Some(name) => f.write_str(name),
            None => write!(f, "command 0x{:02X}", self.0),
        }
    }
}

/// A datagram's command with its address (ETG.1000.4 §5.4): the command byte and the 32-bit
/// address field of the datagram header read together.
///
/// - Auto-increment commands (APRD, APWR, APRW, ARMW) address the slave at `position`: ADP, the
///   address field's low 16 bits, 0 at the slave addressed, each slave incrementing it as the
///   frame passes; `offset` (ADO, the high 16 bits) is the register.
/// - Configured-address commands (FPRD, FPWR, FPRW, FRMW) address the slave whose station address
///   (or alias) is `station`.
/// - Broadcasts (BRD, BWR, BRW) address every slave; they increment `position` as auto-increment
///   commands do.
/// - Logical commands (LRD, LWR, LRW) carry one 32-bit `logical` address the FMMUs map.
/// - NOP, and a command byte no table defines, address no slave: the datagram passes unchanged,
///   its address field kept as it is.
///
/// [`Command::parse`] and [`Command::header`] go from the header's bytes to the command and back,
/// unchanged for every byte and address.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Command {
    /// No operation.
    Nop {
        /// The address field, unused.
        address: u32,
    },
    /// Auto-increment read.
    Aprd {
        /// ADP: the slave's position relative to this one.
        position: u16,
        /// ADO: the register.
        offset: u16,
    },
    /// Auto-increment write.
    Apwr {
        /// ADP: the slave's position relative to this one.
        position: u16,
        /// ADO: the register.
        offset: u16,
    },
    /// Auto-increment read-write.
    Aprw {
        /// ADP: the slave's position relative to this one.
        position: u16,
        /// ADO: the register.
        offset: u16,
    },
    /// Configured-address read.
    Fprd {
        /// ADP: the station address or alias.
        station: u16,
        /// ADO: the register.
        offset: u16,
    },
    /// Configured-address write.
    Fpwr {
        /// ADP: the station address or alias.
        station: u16,
        /// ADO: the register.
        offset: u16,
    },
    /// Configured-address read-write.
    Fprw {
        /// ADP: the station address or alias.
        station: u16,
        /// ADO: the register.
        offset: u16,
    },
    /// Broadcast read.
    Brd {
        /// ADP: incremented by every slave.
        position: u16,
        /// ADO: the register.
        offset: u16,
    },
    /// Broadcast write.
    Bwr {
        /// ADP: incremented by every slave.
        position: u16,
        /// ADO: the register.
        offset: u16,
    },
    /// Broadcast read-write.
    Brw {
        /// ADP: incremented by every slave.
        position: u16,
        /// ADO: the register.
        offset: u16,
    },
    /// Logical read.
    Lrd {
        /// The logical address.
        logical: u32,
    },
    /// Logical write.
    Lwr {
        /// The logical address.
        logical: u32,
    },
    /// Logical read-write.
    Lrw {
        /// The logical address.
        logical: u32,
    },
    /// Auto-increment read, multiple write: read at the slave addressed, written at every other.
    Armw {
        /// ADP: the slave's position relative to this one.
        position: u16,
        /// ADO: the register.
        offset: u16,
    },
    /// Configured-address read, multiple write: read at the slave addressed, written at every
    /// other.
    Frmw {
        /// ADP: the station address or alias.
        station: u16,
        /// ADO: the register.
        offset: u16,
    },
    /// A command byte no table defines: passed on unchanged, like NOP.
    Unknown {
        /// The command byte.
        code: u8,
        /// The address field.
        address: u32,
    },
}

impl Command {
    /// The command of a datagram header's command byte `code` and 32-bit `address` field (its
    /// bytes 2–5, little-endian).
    #[inline]
    pub const fn parse(code: u8, address: u32) -> Command {
        let (adp, ado) = (address as u16, (address >> 16) as u16);
        match code {
            0 => Command::Nop { address },
            1 => Command::Aprd {
                position: adp,
                offset: ado,
            },
            2 => Command::Apwr {
                position: adp,
                offset: ado,
            },
            3 => Command::Aprw {
                position: adp,
                offset: ado,
            },
            4 => Command::Fprd {
                station: adp,
                offset: ado,
            },
            5 => Command::Fpwr {
                station: adp,
                offset: ado,
            },
            6 => Command::Fprw {
                station: adp,
                offset: ado,
            },
            7 => Command::Brd {
                position: adp,
                offset: ado,
            },
            8 => Command::Bwr {
                position: adp,
                offset: ado,
            },
            9 => Command::Brw {
                position: adp,
                offset: ado,
            },
            10 => Command::Lrd { logical: address },
            11 => Command::Lwr { logical: address },
            12 => Command::Lrw { logical: address },
            13 => Command::Armw {
                position: adp,
                offset: ado,
            },
            14 => Command::Frmw {
                station: adp,
                offset: ado,
            },
            code => Command::Unknown { code, address },
        }
    }

    /// The command of the datagram header at the start of `header` (at least its first 6 bytes).
    ///
    /// # Panics
    ///
    /// When `header` is shorter than 6 bytes.
    #[inline]
    pub fn from_header(header: &[u8]) -> Command {
        let address = u32::from_le_bytes([header[2], header[3], header[4], header[5]]);
        Command::parse(header[0], address)
    }

    /// The command byte and the 32-bit address field, as [`Command::parse`] takes them.
    pub const fn header(self) -> (CommandCode, u32) {
        let (code, address) = match self {
            Command::Nop { address } => (0, address),
            Command::Aprd { position, offset } => (1, adp_ado(position, offset)),
            Command::Apwr { position, offset } => (2, adp_ado(position, offset)),
            Command::Aprw { position, offset } => (3, adp_ado(position, offset)),
            Command::Fprd { station, offset } => (4, adp_ado(station, offset)),
            Command::Fpwr { station, offset } => (5, adp_ado(station, offset)),
            Command::Fprw { station, offset } => (6, adp_ado(station, offset)),
            Command::Brd { position, offset } => (7, adp_ado(position, offset)),
            Command::Bwr { position, offset } => (8, adp_ado(position, offset)),
            Command::Brw { position, offset } => (9, adp_ado(position, offset)),
            Command::Lrd { logical } => (10, logical),
            Command::Lwr { logical } => (11, logical),
            Command::Lrw { logical } => (12, logical),
            Command::Armw { position, offset } => (13, adp_ado(position, offset)),
            Command::Frmw { station, offset } => (14, adp_ado(station, offset)),
            Command::Unknown { code, address } => (code, address),
        };
        (CommandCode(code), address)
    }

    /// The command byte.
    pub const fn code(self) -> CommandCode {
        self.header().0
    }

    /// The 32-bit address field.
    pub const fn address(self) -> u32 {
        self.header().1
    }
}

/// The address field of ADP `adp` and ADO `ado`.
const fn adp_ado(adp: u16, ado: u16) -> u32 {
    adp as u32 | (ado as u32) << 16
}

impl std::fmt::Display for Command {
    /// The command's name and address: `FPRD 0x1001:0x0130`, `LRW 0x00010000`, `APWR -1:0x0120`
    /// (the position as a signed offset from the slave the frame is at).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (code, address) = self.header();
        match *self {
            Command::Nop { .. } | Command::Unknown { .. } => write!(f, "{code}"),
            Command::Lrd { logical } | Command::Lwr { logical } | Command::Lrw { logical } => {
                write!(f, "{code} 0x{logical:08X}")
            }
            Command::Fprd { station, offset }
            | Command::Fpwr { station, offset }
            | Command::Fprw { station, offset }
            | Command::Frmw { station, offset } => {
                write!(f, "{code} 0x{station:04X}:0x{offset:04X}")
            }
            _ => {
                let (position, offset) = (address as u16 as i16, (address >> 16) as u16);
                write!(f, "{code} {position}:0x{offset:04X}")
            }
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
    /// Command byte.
    pub cmd: CommandCode,
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
    pub fn new(cmd: CommandCode, adp: u16, ado: u16, data: Vec<u8>) -> Datagram {
        Datagram {
            cmd,
            index: 0,
            address: adp_ado(adp, ado),
            data,
            wkc: 0,
        }
    }

    /// A datagram of `command` (its code and address) over `data`.
    pub fn of(command: Command, data: Vec<u8>) -> Datagram {
        let (cmd, address) = command.header();
        Datagram {
            cmd,
            index: 0,
            address,
            data,
            wkc: 0,
        }
    }

    /// The datagram's command with its address.
    pub const fn command(&self) -> Command {
        Command::parse(self.cmd.0, self.address)
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
            cmd: CommandCode(frame[d.start]),
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The header bytes of ETG.1000.4 §5.4 to the command and back: FPRD of station 0x1001's AL
    /// status (0x0130) is `04 xx 01 10 30 01`; LRW at logical 0x00010000 is `0C xx 00 00 01 00`;
    /// APWR to the next slave (ADP 0xFFFF) of AL control is `02 xx FF FF 20 01`.
    #[test]
    fn commands_from_header_bytes() {
        for (header, command) in [
            (
                [0x04, 0x00, 0x01, 0x10, 0x30, 0x01],
                Command::Fprd {
                    station: 0x1001,
                    offset: 0x0130,
                },
            ),
            (
                [0x0C, 0x07, 0x00, 0x00, 0x01, 0x00],
                Command::Lrw {
                    logical: 0x0001_0000,
                },
            ),
            (
                [0x02, 0x00, 0xFF, 0xFF, 0x20, 0x01],
                Command::Apwr {
                    position: 0xFFFF,
                    offset: 0x0120,
                },
            ),
            (
                [0x07, 0x00, 0x00, 0x00, 0x00, 0x00],
                Command::Brd {
                    position: 0,
                    offset: 0,
                },
            ),
            (
                [0x0E, 0x00, 0x01, 0x10, 0x10, 0x09],
                Command::Frmw {
                    station: 0x1001,
                    offset: 0x0910,
                },
            ),
            (
                [0x00, 0x00, 0x78, 0x56, 0x34, 0x12],
                Command::Nop {
                    address: 0x1234_5678,
                },
            ),
            (
                [0x2A, 0x00, 0x78, 0x56, 0x34, 0x12],
                Command::Unknown {
                    code: 0x2A,
                    address: 0x1234_5678,
                },
            ),
        ] {
            assert_eq!(Command::from_header(&header), command, "{header:02X?}");
            let (code, address) = command.header();
            assert_eq!(code.0, header[0]);
            assert_eq!(address.to_le_bytes(), header[2..6]);
        }
    }

    /// Every command byte with addresses of every shape parses to a command whose header is the
    /// same byte and address; the defined bytes are the commands of [`CommandCode::ALL`].
    #[test]
    fn every_header_round_trips() {
        for code in 0..=255u8 {
            for address in [0, 1, 0xFFFF, 0x0001_0000, 0x0130_1001, 0xFFFF_FFFF] {
                let command = Command::parse(code, address);
                assert_eq!(command.header(), (CommandCode(code), address));
                assert_eq!(command.code(), CommandCode(code));
                assert_eq!(command.address(), address);
                let unknown = matches!(command, Command::Unknown { .. });
                assert_eq!(unknown, CommandCode(code).name().is_none(), "{code}");
            }
        }
        assert_eq!(CommandCode::ALL.len(), 15);
    }

    /// A datagram built from a command emits the same bytes as one built from its code, ADP and
    /// ADO, and reads back as that command.
    #[test]
    fn datagram_of_a_command() {
        let command = Command::Fpwr {
            station: 0x1002,
            offset: 0x0120,
        };
        let d = Datagram::of(command, vec![0x02, 0x00]);
        assert_eq!(
            d,
            Datagram::new(cmd::FPWR, 0x1002, 0x0120, vec![0x02, 0x00])
        );
        let f = emit(&[d], [2; 6]);
        assert_eq!(f[16..22], [0x05, 0x00, 0x02, 0x10, 0x20, 0x01]);
        assert_eq!(parse(&f).unwrap()[0].command(), command);
    }

    /// Commands shown with their addresses.
    #[test]
    fn commands_displayed() {
        for (command, text) in [
            (
                Command::Fprd {
                    station: 0x1001,
                    offset: 0x0130,
                },
                "FPRD 0x1001:0x0130",
            ),
            (Command::Lrw { logical: 0x10000 }, "LRW 0x00010000"),
            (
                Command::Apwr {
                    position: 0xFFFF,
                    offset: 0x0120,
                },
                "APWR -1:0x0120",
            ),
            (Command::Nop { address: 5 }, "NOP"),
            (
                Command::Unknown {
                    code: 0x2A,
                    address: 0,
                },
                "command 0x2A",
            ),
        ] {
            assert_eq!(command.to_string(), text);
        }
    }
}
