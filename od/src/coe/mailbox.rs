//! The EtherCAT mailbox header (ETG.1000.4 §5.6 / ETG.1000.6 §5.6.1, table 29) and the CoE header
//! (ETG.1000.6 §5.6.2, table 30).
//!
//! ```text
//! mailbox header, 6 bytes:  Length u16 | Address u16 | Channel:6 Priority:2 | Type:4 Cnt:3 reserved:1
//! CoE header, 2 bytes:      Number:9 reserved:3 Service:4
//! ```

/// Length of the mailbox header.
pub const MAILBOX_HEADER_LEN: usize = 6;

/// Why bytes are not a mailbox or CoE frame.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum FramingError {
    /// Fewer bytes than the header or the length field says.
    #[error("frame too short: {need} bytes needed, {got} present")]
    Truncated {
        /// Bytes needed.
        need: usize,
        /// Bytes present.
        got: usize,
    },
    /// The mailbox type is not CoE.
    #[error("mailbox type {0} is not CoE (3)")]
    NotCoe(u8),
    /// A CoE service that is not SDO request, SDO response or SDO information.
    #[error("CoE service {0} is not an SDO service")]
    NotSdo(u8),
}

/// The mailbox protocol in the header's type field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MailboxType {
    /// 0: error reply.
    Error,
    /// 1: ADS over EtherCAT.
    Aoe,
    /// 2: Ethernet over EtherCAT.
    Eoe,
    /// 3: CANopen over EtherCAT.
    Coe,
    /// 4: File access over EtherCAT.
    Foe,
    /// 5: Servo profile over EtherCAT.
    Soe,
    /// 15: vendor specific.
    Voe,
    /// Another value.
    Other(u8),
}

impl MailboxType {
    /// The 4-bit code.
    pub const fn code(self) -> u8 {
        match self {
            MailboxType::Error => 0,
            MailboxType::Aoe => 1,
            MailboxType::Eoe => 2,
            MailboxType::Coe => 3,
            MailboxType::Foe => 4,
            MailboxType::Soe => 5,
            MailboxType::Voe => 15,
            MailboxType::Other(c) => c & 0x0F,
        }
    }

    /// The type of a 4-bit code.
    pub const fn from_code(code: u8) -> MailboxType {
        match code & 0x0F {
            0 => MailboxType::Error,
            1 => MailboxType::Aoe,
            2 => MailboxType::Eoe,
            3 => MailboxType::Coe,
            4 => MailboxType::Foe,
            5 => MailboxType::Soe,
            15 => MailboxType::Voe,
            c => MailboxType::Other(c),
        }
    }
}

/// The mailbox header.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MailboxHeader {
    /// Length of the data after the header.
    pub length: u16,
    /// Station address of the sender (master → slave: the master's, usually 0) or receiver.
    pub address: u16,
    /// Channel, 0–63 (0 for CoE).
    pub channel: u8,
    /// Priority, 0–3.
    pub priority: u8,
    /// The protocol.
    pub mailbox_type: MailboxType,
    /// Counter, 1–7 (0 only for the first mailbox after start-up); a repeated counter marks a repeated
    /// mailbox.
    pub counter: u8,
}

impl MailboxHeader {
    /// Parses the first six bytes.
    pub fn parse(bytes: &[u8]) -> Result<MailboxHeader, FramingError> {
        let b: &[u8; MAILBOX_HEADER_LEN] = bytes
            .get(..MAILBOX_HEADER_LEN)
            .and_then(|s| s.try_into().ok())
            .ok_or(FramingError::Truncated {
                need: MAILBOX_HEADER_LEN,
                got: bytes.len(),
            })?;
        Ok(MailboxHeader {
            length: u16::from_le_bytes([b[0], b[1]]),
            address: u16::from_le_bytes([b[2], b[3]]),
            channel: b[4] & 0x3F,
            priority: b[4] >> 6,
            mailbox_type: MailboxType::from_code(b[5] & 0x0F),
            counter: (b[5] >> 4) & 0x07,
        })
    }

    /// The six header bytes.
    pub fn emit(&self) -> [u8; MAILBOX_HEADER_LEN] {
        let l = self.length.to_le_bytes();
        let a = self.address.to_le_bytes();
        [
            l[0],
            l[1],
            a[0],
            a[1],
            (self.channel & 0x3F) | ((self.priority & 0x03) << 6),
            self.mailbox_type.code() | ((self.counter & 0x07) << 4),
        ]
    }

    /// The header and the data it announces, from a whole mailbox (trailing padding up to the sync
    /// manager's size is ignored).
    pub fn split(bytes: &[u8]) -> Result<(MailboxHeader, &[u8]), FramingError> {
        let h = MailboxHeader::parse(bytes)?;
        let end = MAILBOX_HEADER_LEN + h.length as usize;
        let data = bytes
            .get(MAILBOX_HEADER_LEN..end)
            .ok_or(FramingError::Truncated {
                need: end,
                got: bytes.len(),
            })?;
        Ok((h, data))
    }

    /// A whole mailbox of `mailbox_type` to or from `address` with `counter`: the header (channel 0,
    /// priority 0) announcing `data`, then `data`.
    pub fn wrap(mailbox_type: MailboxType, address: u16, counter: u8, data: &[u8]) -> Vec<u8> {
        let header = MailboxHeader {
            length: data.len() as u16,
            address,
            channel: 0,
            priority: 0,
            mailbox_type,
            counter,
        };
        let mut out = Vec::with_capacity(MAILBOX_HEADER_LEN + data.len());
        out.extend_from_slice(&header.emit());
        out.extend_from_slice(data);
        out
    }

    /// The next counter after `counter`: 1, 2, … 7, 1 (0 is used only once, at start-up).
    pub const fn next_counter(counter: u8) -> u8 {
        if counter >= 7 {
            1
        } else {
            counter + 1
        }
    }
}

/// The CoE service in the CoE header.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CoeService {
    /// 1: emergency.
    Emergency,
    /// 2: SDO request.
    SdoRequest,
    /// 3: SDO response.
    SdoResponse,
    /// 4: TxPDO.
    TxPdo,
    /// 5: RxPDO.
    RxPdo,
    /// 6: TxPDO remote request.
    TxPdoRemote,
    /// 7: RxPDO remote request.
    RxPdoRemote,
    /// 8: SDO information.
    SdoInformation,
    /// Another value.
    Other(u8),
}

impl CoeService {
    /// The 4-bit code.
    pub const fn code(self) -> u8 {
        match self {
            CoeService::Emergency => 1,
            CoeService::SdoRequest => 2,
            CoeService::SdoResponse => 3,
            CoeService::TxPdo => 4,
            CoeService::RxPdo => 5,
            CoeService::TxPdoRemote => 6,
            CoeService::RxPdoRemote => 7,
            CoeService::SdoInformation => 8,
            CoeService::Other(c) => c & 0x0F,
        }
    }

    /// The service of a 4-bit code.
    pub const fn from_code(code: u8) -> CoeService {
        match code & 0x0F {
            1 => CoeService::Emergency,
            2 => CoeService::SdoRequest,
            3 => CoeService::SdoResponse,
            4 => CoeService::TxPdo,
            5 => CoeService::RxPdo,
            6 => CoeService::TxPdoRemote,
            7 => CoeService::RxPdoRemote,
            8 => CoeService::SdoInformation,
            c => CoeService::Other(c),
        }
    }
}

/// The CoE header: a PDO number (0 for SDO) and the service.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CoeHeader {
    /// PDO number, 0–511 (0 for SDO services).
    pub number: u16,
    /// The service.
    pub service: CoeService,
}

impl CoeHeader {
    /// An SDO request header.
    pub const REQUEST: CoeHeader = CoeHeader {
        number: 0,
        service: CoeService::SdoRequest,
    };
    /// An SDO response header.
    pub const RESPONSE: CoeHeader = CoeHeader {
        number: 0,
        service: CoeService::SdoResponse,
    };

    /// Parses the two header bytes.
    pub fn parse(bytes: &[u8]) -> Result<CoeHeader, FramingError> {
        let b = bytes.get(..2).ok_or(FramingError::Truncated {
            need: 2,
            got: bytes.len(),
        })?;
        let v = u16::from_le_bytes([b[0], b[1]]);
        Ok(CoeHeader {
            number: v & 0x01FF,
            service: CoeService::from_code((v >> 12) as u8),
        })
    }

    /// The two header bytes.
    pub fn emit(&self) -> [u8; 2] {
        ((self.number & 0x01FF) | ((self.service.code() as u16) << 12)).to_le_bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mailbox_header_golden_bytes() {
        // 10 bytes of CoE data to station 0x1001, priority 0, channel 0, counter 2.
        let h = MailboxHeader {
            length: 10,
            address: 0x1001,
            channel: 0,
            priority: 0,
            mailbox_type: MailboxType::Coe,
            counter: 2,
        };
        let bytes = [0x0A, 0x00, 0x01, 0x10, 0x00, 0x23];
        assert_eq!(h.emit(), bytes);
        assert_eq!(MailboxHeader::parse(&bytes), Ok(h));
        let h = MailboxHeader {
            priority: 3,
            channel: 5,
            counter: 7,
            ..h
        };
        assert_eq!(h.emit()[4..], [0xC5, 0x73]);
        assert_eq!(MailboxHeader::parse(&h.emit()), Ok(h));
    }

    #[test]
    fn split_takes_the_announced_length_and_ignores_padding() {
        let mut mbx = vec![0x02, 0x00, 0x00, 0x00, 0x00, 0x13, 0x00, 0x20];
        mbx.resize(128, 0);
        let (h, data) = MailboxHeader::split(&mbx).unwrap();
        assert_eq!(h.counter, 1);
        assert_eq!(data, &[0x00, 0x20]);
        assert_eq!(
            MailboxHeader::split(&[0x10, 0x00, 0, 0, 0, 0x13, 1, 2]),
            Err(FramingError::Truncated { need: 22, got: 8 })
        );
        assert_eq!(
            MailboxHeader::parse(&[1, 2]),
            Err(FramingError::Truncated { need: 6, got: 2 })
        );
    }

    #[test]
    fn coe_header_golden_bytes() {
        assert_eq!(CoeHeader::REQUEST.emit(), [0x00, 0x20]);
        assert_eq!(CoeHeader::RESPONSE.emit(), [0x00, 0x30]);
        assert_eq!(
            CoeHeader {
                number: 0,
                service: CoeService::SdoInformation
            }
            .emit(),
            [0x00, 0x80]
        );
        assert_eq!(CoeHeader::parse(&[0x00, 0x30]), Ok(CoeHeader::RESPONSE));
        assert_eq!(
            CoeHeader::parse(&[0x01, 0x10]),
            Ok(CoeHeader {
                number: 1,
                service: CoeService::Emergency
            })
        );
    }

    #[test]
    fn counters_cycle_one_to_seven() {
        assert_eq!(MailboxHeader::next_counter(0), 1);
        assert_eq!(MailboxHeader::next_counter(6), 7);
        assert_eq!(MailboxHeader::next_counter(7), 1);
    }
}
