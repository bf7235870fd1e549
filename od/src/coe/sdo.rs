//! CoE SDO frames (ETG.1000.6 §5.6.2.1–5.6.2.7): the eight bytes of a CiA 301 SDO frame, with the
//! complete-access bit (bit 4 of an initiate command, reserved on CAN) and any number of bytes after the
//! eighth, which a mailbox carries where CAN cannot:
//!
//! - a normal (non-expedited) download request and upload response hold the complete size in bytes 4–7
//!   and the first part of the data from byte 8 on;
//! - a segment holds its data from byte 1 on; when that is fewer than seven bytes the frame is padded to
//!   eight and the command's size bits tell the unused bytes, as on CAN.
//!
//! The first eight bytes are parsed by [`ClientFrame`] / [`ServerFrame`] of [`crate::sdo::frame`], so
//! the CAN and CoE SDO servers share one codec.

use crate::abort::AbortCode;
use crate::coe::mailbox::{CoeHeader, CoeService, FramingError, MailboxHeader, MailboxType};
use crate::sdo::frame::{ClientFrame, Frame, ServerFrame, FRAME_LEN};

/// The command of a CoE SDO frame: a request from the master or a response from the slave.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoeSdoCommand {
    /// CoE service 2: an SDO request.
    Request(ClientFrame),
    /// CoE service 3: an SDO response.
    Response(ServerFrame),
}

/// One CoE SDO frame: the command, the complete-access bit, and the bytes after the eighth.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CoeSdo<'a> {
    /// The first eight bytes, typed.
    pub command: CoeSdoCommand,
    /// Complete access (bit 4 of an initiate download/upload command): the whole object from sub-index
    /// 0 or 1.
    pub complete_access: bool,
    /// The bytes after the eighth (data of a normal transfer or of a long segment).
    pub extra: &'a [u8],
}

/// Why a mailbox is not a CoE SDO frame, or which abort answers it.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum CoeSdoError {
    /// The mailbox or CoE framing is wrong.
    #[error(transparent)]
    Framing(#[from] FramingError),
    /// The SDO command is not valid: the abort code that answers it.
    #[error("SDO command refused: {0}")]
    Abort(AbortCode),
}

/// True when bit 4 of `command` is the complete-access bit: on the initiate commands, which are ccs 1
/// (download) and 2 (upload) in a request and scs 3 (download) and 2 (upload) in a response. On a
/// segment (request ccs 0 and 3, response scs 0 and 1) bit 4 is the toggle bit.
fn is_initiate(service: CoeService, command: u8) -> bool {
    match service {
        CoeService::SdoRequest => matches!(command >> 5, 1 | 2),
        CoeService::SdoResponse => matches!(command >> 5, 2 | 3),
        _ => false,
    }
}

impl<'a> CoeSdo<'a> {
    /// Parses the SDO part of a CoE frame (after the CoE header) of `service`.
    pub fn parse(service: CoeService, sdo: &'a [u8]) -> Result<CoeSdo<'a>, CoeSdoError> {
        let first: &Frame = sdo.get(..FRAME_LEN).and_then(|s| s.try_into().ok()).ok_or(
            FramingError::Truncated {
                need: FRAME_LEN,
                got: sdo.len(),
            },
        )?;
        let command = match service {
            CoeService::SdoRequest => {
                CoeSdoCommand::Request(ClientFrame::parse(first).map_err(CoeSdoError::Abort)?)
            }
            CoeService::SdoResponse => {
                CoeSdoCommand::Response(ServerFrame::parse(first).map_err(CoeSdoError::Abort)?)
            }
            other => return Err(FramingError::NotSdo(other.code()).into()),
        };
        let complete_access = is_initiate(service, first[0]) && first[0] & 0x10 != 0;
        Ok(CoeSdo {
            command,
            complete_access,
            extra: &sdo[FRAME_LEN..],
        })
    }

    /// The CoE service of this frame.
    pub fn service(&self) -> CoeService {
        match self.command {
            CoeSdoCommand::Request(_) => CoeService::SdoRequest,
            CoeSdoCommand::Response(_) => CoeService::SdoResponse,
        }
    }

    /// Appends the SDO bytes (eight, then `extra`) to `out`.
    pub fn emit_sdo(&self, out: &mut Vec<u8>) {
        let mut first = match self.command {
            CoeSdoCommand::Request(c) => c.emit(),
            CoeSdoCommand::Response(s) => s.emit(),
        };
        if self.complete_access && is_initiate(self.service(), first[0]) {
            first[0] |= 0x10;
        }
        out.extend_from_slice(&first);
        out.extend_from_slice(self.extra);
    }

    /// A whole mailbox: mailbox header (CoE, `address`, `counter`), CoE header and the SDO bytes.
    pub fn to_mailbox(&self, address: u16, counter: u8) -> Vec<u8> {
        let mut body = Vec::with_capacity(2 + FRAME_LEN + self.extra.len());
        body.extend_from_slice(
            &CoeHeader {
                number: 0,
                service: self.service(),
            }
            .emit(),
        );
        self.emit_sdo(&mut body);
        MailboxHeader::wrap(MailboxType::Coe, address, counter, &body)
    }

    /// Parses a whole mailbox holding a CoE SDO request or response.
    pub fn from_mailbox(mailbox: &'a [u8]) -> Result<(MailboxHeader, CoeSdo<'a>), CoeSdoError> {
        let (header, data) = MailboxHeader::split(mailbox)?;
        if header.mailbox_type != MailboxType::Coe {
            return Err(FramingError::NotCoe(header.mailbox_type.code()).into());
        }
        let coe = CoeHeader::parse(data)?;
        Ok((header, CoeSdo::parse(coe.service, &data[2..])?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sdo::frame::{Address, ExpeditedData, SegmentData};

    #[test]
    fn expedited_download_request_in_a_mailbox() {
        // ETG.1000.6 §5.6.2.1: write UINT 0x03E8 to 0x8010:04; counter 1, master address 0.
        let frame = CoeSdo {
            command: CoeSdoCommand::Request(ClientFrame::InitiateDownloadExpedited {
                mux: Address::new(0x8010, 4),
                data: ExpeditedData::new(&[0xE8, 0x03]),
            }),
            complete_access: false,
            extra: &[],
        };
        let bytes = frame.to_mailbox(0, 1);
        assert_eq!(
            bytes,
            [
                0x0A, 0x00, 0x00, 0x00, 0x00, 0x13, 0x00, 0x20, 0x2B, 0x10, 0x80, 0x04, 0xE8, 0x03,
                0x00, 0x00
            ]
        );
        let (h, back) = CoeSdo::from_mailbox(&bytes).unwrap();
        assert_eq!((h.length, h.counter), (10, 1));
        assert_eq!(back, frame);
    }

    #[test]
    fn normal_upload_response_carries_size_and_data() {
        // ETG.1000.6 §5.6.2.5: 0x41 = scs 2, s 1, e 0; complete size 9, data from byte 8 on.
        let data = b"SMD23K-B\0";
        let frame = CoeSdo {
            command: CoeSdoCommand::Response(ServerFrame::InitiateUploadSegmented {
                mux: Address::new(0x1008, 0),
                size: Some(9),
            }),
            complete_access: false,
            extra: data,
        };
        let mut sdo = Vec::new();
        frame.emit_sdo(&mut sdo);
        assert_eq!(&sdo[..8], &[0x41, 0x08, 0x10, 0x00, 0x09, 0x00, 0x00, 0x00]);
        assert_eq!(&sdo[8..], data);
        assert_eq!(CoeSdo::parse(CoeService::SdoResponse, &sdo).unwrap(), frame);
    }

    #[test]
    fn complete_access_bit_on_initiate_commands_only() {
        // Complete-access upload of 0x1C12 from sub-index 0: command 0x50.
        let req = CoeSdo {
            command: CoeSdoCommand::Request(ClientFrame::InitiateUpload {
                mux: Address::new(0x1C12, 0),
            }),
            complete_access: true,
            extra: &[],
        };
        let mut sdo = Vec::new();
        req.emit_sdo(&mut sdo);
        assert_eq!(sdo, [0x50, 0x12, 0x1C, 0x00, 0, 0, 0, 0]);
        assert_eq!(CoeSdo::parse(CoeService::SdoRequest, &sdo).unwrap(), req);
        // On a segment, bit 4 is the toggle bit, not complete access.
        let seg = [0x10, 1, 2, 3, 4, 5, 6, 7, 8, 9];
        let parsed = CoeSdo::parse(CoeService::SdoRequest, &seg).unwrap();
        assert!(!parsed.complete_access);
        assert_eq!(
            parsed.command,
            CoeSdoCommand::Request(ClientFrame::DownloadSegment {
                toggle: true,
                data: SegmentData::new(&[1, 2, 3, 4, 5, 6, 7]),
                last: false
            })
        );
        assert_eq!(parsed.extra, &[8, 9]);
    }

    #[test]
    fn complete_access_bit_in_responses() {
        // A complete-access download response: scs 3 with bit 4 set, 0x70.
        let resp = CoeSdo {
            command: CoeSdoCommand::Response(ServerFrame::InitiateDownload {
                mux: Address::new(0x1C12, 0),
            }),
            complete_access: true,
            extra: &[],
        };
        let mut sdo = Vec::new();
        resp.emit_sdo(&mut sdo);
        assert_eq!(sdo, [0x70, 0x12, 0x1C, 0x00, 0, 0, 0, 0]);
        assert_eq!(CoeSdo::parse(CoeService::SdoResponse, &sdo).unwrap(), resp);
        // A download segment response with toggle 1 (0x30) is not complete access, and a
        // complete-access flag on it does not touch its toggle bit.
        let seg = CoeSdo {
            command: CoeSdoCommand::Response(ServerFrame::DownloadSegment { toggle: false }),
            complete_access: true,
            extra: &[],
        };
        let mut sdo = Vec::new();
        seg.emit_sdo(&mut sdo);
        assert_eq!(sdo, [0x20, 0, 0, 0, 0, 0, 0, 0]);
        let parsed = CoeSdo::parse(CoeService::SdoResponse, &[0x30, 0, 0, 0, 0, 0, 0, 0]).unwrap();
        assert!(!parsed.complete_access);
        assert_eq!(
            parsed.command,
            CoeSdoCommand::Response(ServerFrame::DownloadSegment { toggle: true })
        );
        // A normal upload response of a complete access: 0x51.
        let up = CoeSdo::parse(
            CoeService::SdoResponse,
            &[0x51, 0x12, 0x1C, 0x00, 6, 0, 0, 0],
        )
        .unwrap();
        assert!(up.complete_access);
    }

    #[test]
    fn framing_errors_name_what_is_wrong() {
        assert_eq!(
            CoeSdo::parse(CoeService::SdoRequest, &[0x40, 0, 0]),
            Err(CoeSdoError::Framing(FramingError::Truncated {
                need: 8,
                got: 3
            }))
        );
        assert_eq!(
            CoeSdo::parse(CoeService::SdoRequest, &[0xE0, 0, 0, 0, 0, 0, 0, 0]),
            Err(CoeSdoError::Abort(AbortCode::InvalidCommand))
        );
        assert_eq!(
            CoeSdo::parse(CoeService::Emergency, &[0; 8]),
            Err(CoeSdoError::Framing(FramingError::NotSdo(1)))
        );
        let eoe = [0x02, 0x00, 0x00, 0x00, 0x00, 0x12, 0x00, 0x20];
        assert_eq!(
            CoeSdo::from_mailbox(&eoe),
            Err(CoeSdoError::Framing(FramingError::NotCoe(2)))
        );
    }

    #[test]
    fn ethercat_abort_codes() {
        assert_eq!(AbortCode::SubIndex0MustBeZero.code(), 0x0601_0003);
        assert_eq!(AbortCode::CompleteAccessUnsupported.code(), 0x0601_0004);
        assert_eq!(AbortCode::ExceedsMailbox.code(), 0x0601_0005);
        assert_eq!(AbortCode::MappedToRxPdo.code(), 0x0601_0006);
        let abort = CoeSdo {
            command: CoeSdoCommand::Response(ServerFrame::Abort {
                mux: Address::new(0x7000, 1),
                code: AbortCode::MappedToRxPdo,
            }),
            complete_access: false,
            extra: &[],
        };
        let mut sdo = Vec::new();
        abort.emit_sdo(&mut sdo);
        assert_eq!(sdo, [0x80, 0x00, 0x70, 0x01, 0x06, 0x00, 0x01, 0x06]);
    }
}
