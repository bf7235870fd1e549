//! File access over EtherCAT (FoE, ETG.1000.5 and ETG.1000.6 §5.9): the six FoE frames a mailbox
//! of type 4 carries, the FoE error codes, and a sans-IO client ([`client`]).
//!
//! ```text
//! FoE header, 6 bytes: OpCode u8 | reserved u8 | Password, PacketNo or ErrorCode u32
//!                                             | (Busy: Done u16 | Entire u16)
//! then:                file name (Read, Write), data (Data), error text (Error), busy text (Busy)
//! ```
//!
//! | OpCode | frame | after the header |
//! |---|---|---|
//! | 1 | Read request | the file name |
//! | 2 | Write request | the file name |
//! | 3 | Data | up to the mailbox's size less 12 bytes of the file; a shorter one is the last |
//! | 4 | Ack | nothing: the packet number acknowledged (0 for a write request) |
//! | 5 | Error | the error text |
//! | 6 | Busy | the busy text; Done and Entire tell the progress |
//!
//! A write goes Write request → Ack 0, then Data 1 → Ack 1, Data 2 → Ack 2, … until a Data packet
//! shorter than the mailbox's data size (an empty one when the file is a multiple of it); a read
//! goes Read request → Data 1, Ack 1 → Data 2, … the same way round. Either side ends a transfer
//! with an Error; a slave that needs time answers a Data packet with Busy and the master sends that
//! packet again.

pub mod client;

use crate::coe::mailbox::{MailboxHeader, MailboxType, MAILBOX_HEADER_LEN};

/// The FoE header: OpCode, reserved byte, and the 32-bit field.
pub const FOE_HEADER_LEN: usize = 6;
/// Mailbox header and FoE header: the bytes of a mailbox that carry no file data.
pub const FOE_OVERHEAD: usize = MAILBOX_HEADER_LEN + FOE_HEADER_LEN;

/// The file data one Data packet carries in a mailbox of `mailbox_len` bytes (its SyncManager's
/// length): the mailbox less the mailbox and FoE headers, 12 bytes.
pub const fn data_per_packet(mailbox_len: usize) -> usize {
    mailbox_len.saturating_sub(FOE_OVERHEAD)
}

macro_rules! foe_error_codes {
    ($( $(#[$doc:meta])* $name:ident = $code:literal, $text:literal; )*) => {
        /// An FoE error code (ETG.1000.6 §5.9, the Error request's ErrorCode).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[non_exhaustive]
        pub enum FoeErrorCode {
            $( $(#[$doc])* $name, )*
            /// A code the table does not define (vendor-specific, or from a later edition).
            Other(u32),
        }

        impl FoeErrorCode {
            /// Every code of the table, in its order.
            pub const ALL: &'static [FoeErrorCode] = &[$(FoeErrorCode::$name,)*];

            /// The 32-bit code as it travels on the wire.
            pub const fn code(self) -> u32 {
                match self {
                    $(FoeErrorCode::$name => $code,)*
                    FoeErrorCode::Other(code) => code,
                }
            }

            /// The table's name of the code, as IgH's `ethercat foe_write` prints it (without its
            /// full stop).
            pub const fn description(self) -> &'static str {
                match self {
                    $(FoeErrorCode::$name => $text,)*
                    FoeErrorCode::Other(_) => "Unknown error code",
                }
            }
        }

        impl From<u32> for FoeErrorCode {
            fn from(code: u32) -> Self {
                match code {
                    $($code => FoeErrorCode::$name,)*
                    other => FoeErrorCode::Other(other),
                }
            }
        }
    };
}

foe_error_codes! {
    /// 0x8000: not defined (the text says what).
    NotDefined = 0x8000, "Not defined";
    /// 0x8001: the file is not there.
    NotFound = 0x8001, "Not found";
    /// 0x8002: access denied.
    AccessDenied = 0x8002, "Access denied";
    /// 0x8003: the file does not fit (disk full).
    DiskFull = 0x8003, "Disk full";
    /// 0x8004: a request that is not allowed now (illegal).
    Illegal = 0x8004, "Illegal";
    /// 0x8005: the packet number is not the one expected.
    PacketNumberWrong = 0x8005, "Packet number wrong";
    /// 0x8006: the file already exists.
    AlreadyExists = 0x8006, "Already exists";
    /// 0x8007: no user.
    NoUser = 0x8007, "No user";
    /// 0x8008: only in the Bootstrap state (and the slave is in it: only firmware goes).
    BootstrapOnly = 0x8008, "Bootstrap only";
    /// 0x8009: the slave is not in the Bootstrap state, which the request needs.
    NotBootstrap = 0x8009, "Not Bootstrap";
    /// 0x800A: no rights (a wrong password).
    NoRights = 0x800A, "No rights";
    /// 0x800B: program error.
    ProgramError = 0x800B, "Program Error";
}

impl std::fmt::Display for FoeErrorCode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "0x{:04X} ({})", self.code(), self.description())
    }
}

/// Why bytes are not an FoE frame.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum FoeFrameError {
    /// Fewer bytes than the FoE header.
    #[error("FoE frame too short: {got} bytes, the FoE header alone is 6")]
    Truncated {
        /// Bytes present.
        got: usize,
    },
    /// An OpCode the protocol does not define.
    #[error("FoE OpCode {0} is none of 1 (Read) to 6 (Busy)")]
    UnknownOpCode(u8),
}

/// One FoE frame (ETG.1000.6 §5.9), borrowing its name, data or text from the mailbox it was read
/// from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FoeFrame<'a> {
    /// OpCode 1: the master asks for a file.
    Read {
        /// The password (0 when the slave asks for none).
        password: u32,
        /// The file's name.
        name: &'a [u8],
    },
    /// OpCode 2: the master will send a file.
    Write {
        /// The password.
        password: u32,
        /// The file's name.
        name: &'a [u8],
    },
    /// OpCode 3: a piece of the file, packets counted from 1.
    Data {
        /// The packet number.
        packet: u32,
        /// The bytes.
        data: &'a [u8],
    },
    /// OpCode 4: a packet taken (0 answers a write request).
    Ack {
        /// The packet number.
        packet: u32,
    },
    /// OpCode 5: the transfer ends with an error.
    Error {
        /// The code.
        code: FoeErrorCode,
        /// The text after it (may be empty).
        text: &'a [u8],
    },
    /// OpCode 6: the slave is busy with the last packet; the master sends it again.
    Busy {
        /// Progress: done …
        done: u16,
        /// … of entire.
        entire: u16,
        /// The text after it (may be empty).
        text: &'a [u8],
    },
}

impl<'a> FoeFrame<'a> {
    /// The frame's OpCode.
    pub const fn op_code(&self) -> u8 {
        match self {
            FoeFrame::Read { .. } => 1,
            FoeFrame::Write { .. } => 2,
            FoeFrame::Data { .. } => 3,
            FoeFrame::Ack { .. } => 4,
            FoeFrame::Error { .. } => 5,
            FoeFrame::Busy { .. } => 6,
        }
    }

    /// The frame in `bytes`: the data of a mailbox after its header, exactly as long as the mailbox
    /// header's length says.
    pub fn parse(bytes: &'a [u8]) -> Result<FoeFrame<'a>, FoeFrameError> {
        let Some(head) = bytes.get(..FOE_HEADER_LEN) else {
            return Err(FoeFrameError::Truncated { got: bytes.len() });
        };
        let rest = &bytes[FOE_HEADER_LEN..];
        let word = u32::from_le_bytes([head[2], head[3], head[4], head[5]]);
        Ok(match head[0] {
            1 => FoeFrame::Read {
                password: word,
                name: rest,
            },
            2 => FoeFrame::Write {
                password: word,
                name: rest,
            },
            3 => FoeFrame::Data {
                packet: word,
                data: rest,
            },
            4 => FoeFrame::Ack { packet: word },
            5 => FoeFrame::Error {
                code: FoeErrorCode::from(word),
                text: rest,
            },
            6 => FoeFrame::Busy {
                done: u16::from_le_bytes([head[2], head[3]]),
                entire: u16::from_le_bytes([head[4], head[5]]),
                text: rest,
            },
            other => return Err(FoeFrameError::UnknownOpCode(other)),
        })
    }

    /// The bytes the frame takes after its mailbox header.
    pub fn len(&self) -> usize {
        FOE_HEADER_LEN + self.tail().len()
    }

    /// Never: a frame has its header at least.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// What follows the header: the name, data or text.
    fn tail(&self) -> &'a [u8] {
        match *self {
            FoeFrame::Read { name, .. } | FoeFrame::Write { name, .. } => name,
            FoeFrame::Data { data, .. } => data,
            FoeFrame::Ack { .. } => &[],
            FoeFrame::Error { text, .. } | FoeFrame::Busy { text, .. } => text,
        }
    }

    /// Appends the frame (its header, then the name, data or text) to `out`.
    pub fn emit(&self, out: &mut Vec<u8>) {
        let word = match *self {
            FoeFrame::Read { password, .. } | FoeFrame::Write { password, .. } => {
                password.to_le_bytes()
            }
            FoeFrame::Data { packet, .. } | FoeFrame::Ack { packet } => packet.to_le_bytes(),
            FoeFrame::Error { code, .. } => code.code().to_le_bytes(),
            FoeFrame::Busy { done, entire, .. } => {
                let (d, e) = (done.to_le_bytes(), entire.to_le_bytes());
                [d[0], d[1], e[0], e[1]]
            }
        };
        out.push(self.op_code());
        out.push(0);
        out.extend_from_slice(&word);
        out.extend_from_slice(self.tail());
    }

    /// The frame's bytes after the mailbox header.
    pub fn to_vec(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.len());
        self.emit(&mut out);
        out
    }

    /// A whole mailbox of type FoE (4) to or from `address` with `counter`, carrying the frame.
    pub fn to_mailbox(&self, address: u16, counter: u8) -> Vec<u8> {
        MailboxHeader::wrap(MailboxType::Foe, address, counter, &self.to_vec())
    }
}

/// A name or text as the tool prints it: the bytes as text where they are UTF-8, with control
/// characters and others escaped (`"app\u{0}.bin"`), trailing NULs left out.
pub fn printable(bytes: &[u8]) -> String {
    let end = bytes.iter().rposition(|&b| b != 0).map_or(0, |k| k + 1);
    String::from_utf8_lossy(&bytes[..end])
        .escape_debug()
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each frame's bytes after the mailbox header, worked out from ETG.1000.6 §5.9: OpCode, a
    /// reserved 0, the 32-bit field little-endian (Busy: Done, then Entire, 16 bits each), then
    /// the name, data or text; emitted, and parsed back to the same frame.
    #[test]
    fn every_frame_has_its_bytes() {
        let cases: [(FoeFrame, &[u8]); 7] = [
            (
                FoeFrame::Read {
                    password: 0x1234_5678,
                    name: b"app.bin",
                },
                &[
                    0x01, 0x00, 0x78, 0x56, 0x34, 0x12, b'a', b'p', b'p', b'.', b'b', b'i', b'n',
                ],
            ),
            (
                FoeFrame::Write {
                    password: 0,
                    name: b"fw.efw",
                },
                &[
                    0x02, 0x00, 0x00, 0x00, 0x00, 0x00, b'f', b'w', b'.', b'e', b'f', b'w',
                ],
            ),
            (
                FoeFrame::Data {
                    packet: 0x0102,
                    data: &[0xA5, 0x5A],
                },
                &[0x03, 0x00, 0x02, 0x01, 0x00, 0x00, 0xA5, 0x5A],
            ),
            (
                FoeFrame::Data {
                    packet: 7,
                    data: &[],
                },
                &[0x03, 0x00, 0x07, 0x00, 0x00, 0x00],
            ),
            (
                FoeFrame::Ack { packet: 0 },
                &[0x04, 0x00, 0x00, 0x00, 0x00, 0x00],
            ),
            (
                FoeFrame::Error {
                    code: FoeErrorCode::NotBootstrap,
                    text: b"boot",
                },
                &[0x05, 0x00, 0x09, 0x80, 0x00, 0x00, b'b', b'o', b'o', b't'],
            ),
            (
                FoeFrame::Busy {
                    done: 3,
                    entire: 0x0140,
                    text: &[],
                },
                &[0x06, 0x00, 0x03, 0x00, 0x40, 0x01],
            ),
        ];
        for (frame, bytes) in cases {
            let mut out = vec![0xA5; 3];
            frame.emit(&mut out);
            assert_eq!(&out[3..], bytes, "{frame:?}");
            assert_eq!(frame.len(), bytes.len());
            assert!(!frame.is_empty());
            assert_eq!(FoeFrame::parse(bytes), Ok(frame));
        }
    }

    /// A whole mailbox: the six header bytes (length, address, channel/priority 0, type 4 and the
    /// counter in the high nibble), then the frame.
    #[test]
    fn a_frame_in_its_mailbox() {
        let m = FoeFrame::Ack { packet: 2 }.to_mailbox(0x1001, 3);
        assert_eq!(
            m,
            [0x06, 0x00, 0x01, 0x10, 0x00, 0x34, 0x04, 0x00, 0x02, 0x00, 0x00, 0x00]
        );
    }

    /// Fewer than six bytes, and OpCodes 0 and 7, are no frame.
    #[test]
    fn short_frames_and_unknown_op_codes_are_refused() {
        assert_eq!(
            FoeFrame::parse(&[0x04, 0x00, 0x01, 0x00, 0x00]),
            Err(FoeFrameError::Truncated { got: 5 })
        );
        assert_eq!(
            FoeFrame::parse(&[0x00; 6]),
            Err(FoeFrameError::UnknownOpCode(0))
        );
        assert_eq!(
            FoeFrame::parse(&[0x07, 0, 0, 0, 0, 0]),
            Err(FoeFrameError::UnknownOpCode(7))
        );
    }

    /// The codes 0x8000 to 0x800B with the names of ETG.1000.6 (as IgH's tool prints them);
    /// another code converts to `Other` and back to its number.
    #[test]
    fn error_codes_have_their_names() {
        let table = [
            (0x8000, "Not defined"),
            (0x8001, "Not found"),
            (0x8002, "Access denied"),
            (0x8003, "Disk full"),
            (0x8004, "Illegal"),
            (0x8005, "Packet number wrong"),
            (0x8006, "Already exists"),
            (0x8007, "No user"),
            (0x8008, "Bootstrap only"),
            (0x8009, "Not Bootstrap"),
            (0x800A, "No rights"),
            (0x800B, "Program Error"),
        ];
        assert_eq!(FoeErrorCode::ALL.len(), table.len());
        for (code, name) in table {
            let c = FoeErrorCode::from(code);
            assert_eq!((c.code(), c.description()), (code, name));
            assert!(!matches!(c, FoeErrorCode::Other(_)));
        }
        let other = FoeErrorCode::from(0x800C);
        assert_eq!(other, FoeErrorCode::Other(0x800C));
        assert_eq!(other.code(), 0x800C);
        assert_eq!(other.to_string(), "0x800C (Unknown error code)");
        assert_eq!(FoeErrorCode::DiskFull.to_string(), "0x8003 (Disk full)");
    }

    /// A mailbox of 128 bytes carries 116 bytes of file per packet; one of 12 or fewer none.
    #[test]
    fn data_per_packet_is_the_mailbox_less_twelve() {
        assert_eq!(data_per_packet(128), 116);
        assert_eq!(data_per_packet(13), 1);
        assert_eq!(data_per_packet(12), 0);
        assert_eq!(data_per_packet(3), 0);
    }

    /// Names are printed as text, escaped, without trailing NULs.
    #[test]
    fn names_are_printed_escaped() {
        assert_eq!(printable(b"fw.efw\0\0"), "fw.efw");
        assert_eq!(printable(b"a\nb"), "a\\nb");
        assert_eq!(printable(b""), "");
        assert_eq!(printable(&[0xFF, b'x']), "\u{FFFD}x");
    }
}
