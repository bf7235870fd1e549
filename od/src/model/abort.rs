//! SDO abort codes (CiA 301 §7.2.4.3.17, table 22) and the EtherCAT additions of ETG.1000.6 §5.6.2.7.2.
//!
//! One table gives the constants, the `Display` text and the `From<u32>` conversion; a code that is in no
//! table converts to [`AbortCode::Unknown`] and back to the same number.

use std::fmt;

macro_rules! abort_codes {
    ($( $(#[$doc:meta])* $name:ident = $code:literal, $text:literal; )*) => {
        /// An SDO abort code.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[non_exhaustive]
        pub enum AbortCode {
            $( $(#[$doc])* $name, )*
            /// A code that none of the standards this crate follows defines.
            Unknown(u32),
        }

        impl AbortCode {
            /// Every defined code, in the order of the standards' tables.
            pub const ALL: &'static [AbortCode] = &[$(AbortCode::$name,)*];

            /// The 32-bit code as it travels on the wire.
            pub const fn code(self) -> u32 {
                match self {
                    $(AbortCode::$name => $code,)*
                    AbortCode::Unknown(code) => code,
                }
            }

            /// The standard's description of the code.
            pub const fn description(self) -> &'static str {
                match self {
                    $(AbortCode::$name => $text,)*
                    AbortCode::Unknown(_) => "unknown abort code",
                }
            }
        }

        impl From<u32> for AbortCode {
            fn from(code: u32) -> Self {
                match code {
                    $($code => AbortCode::$name,)*
                    other => AbortCode::Unknown(other),
                }
            }
        }
    };
}

abort_codes! {
    /// 0x05030000: toggle bit not alternated.
    ToggleBit = 0x0503_0000, "Toggle bit not alternated";
    /// 0x05040000: SDO protocol timed out.
    Timeout = 0x0504_0000, "SDO protocol timed out";
    /// 0x05040001: client/server command specifier not valid or unknown.
    InvalidCommand = 0x0504_0001, "Client/server command specifier not valid or unknown";
    /// 0x05040002: invalid block size (block mode only).
    InvalidBlockSize = 0x0504_0002, "Invalid block size (block mode only)";
    /// 0x05040003: invalid sequence number (block mode only).
    InvalidSequence = 0x0504_0003, "Invalid sequence number (block mode only)";
    /// 0x05040004: CRC error (block mode only).
    CrcError = 0x0504_0004, "CRC error (block mode only)";
    /// 0x05040005: out of memory.
    OutOfMemory = 0x0504_0005, "Out of memory";
    /// 0x06010000: unsupported access to an object.
    UnsupportedAccess = 0x0601_0000, "Unsupported access to an object";
    /// 0x06010001: attempt to read a write-only object.
    WriteOnly = 0x0601_0001, "Attempt to read a write only object";
    /// 0x06010002: attempt to write a read-only object.
    ReadOnly = 0x0601_0002, "Attempt to write a read only object";
    /// 0x06010003: sub-index cannot be written, sub-index 0 must be 0 for write access (ETG.1000.6).
    SubIndex0MustBeZero = 0x0601_0003, "Subindex cannot be written, SI0 must be 0 for write access";
    /// 0x06010004: complete access not supported for variable-length objects (ETG.1000.6).
    CompleteAccessUnsupported = 0x0601_0004, "SDO Complete access not supported for objects of variable length";
    /// 0x06010005: object length exceeds mailbox size (ETG.1000.6).
    ExceedsMailbox = 0x0601_0005, "Object length exceeds mailbox size";
    /// 0x06010006: object mapped to RxPDO, SDO download blocked (ETG.1000.6).
    MappedToRxPdo = 0x0601_0006, "Object mapped to RxPDO, SDO Download blocked";
    /// 0x06020000: object does not exist in the object dictionary.
    NoObject = 0x0602_0000, "Object does not exist in the object dictionary";
    /// 0x06040041: object cannot be mapped to the PDO.
    NotMappable = 0x0604_0041, "Object cannot be mapped to the PDO";
    /// 0x06040042: the number and length of the objects to be mapped would exceed the PDO length.
    PdoTooLong = 0x0604_0042, "The number and length of the objects to be mapped would exceed PDO length";
    /// 0x06040043: general parameter incompatibility reason.
    ParameterIncompatible = 0x0604_0043, "General parameter incompatibility reason";
    /// 0x06040047: general internal incompatibility in the device.
    InternalIncompatible = 0x0604_0047, "General internal incompatibility in the device";
    /// 0x06060000: access failed due to a hardware error.
    HardwareError = 0x0606_0000, "Access failed due to a hardware error";
    /// 0x06070010: data type does not match, length of service parameter does not match.
    LengthMismatch = 0x0607_0010, "Data type does not match, length of service parameter does not match";
    /// 0x06070012: data type does not match, length of service parameter too high.
    LengthTooHigh = 0x0607_0012, "Data type does not match, length of service parameter too high";
    /// 0x06070013: data type does not match, length of service parameter too low.
    LengthTooLow = 0x0607_0013, "Data type does not match, length of service parameter too low";
    /// 0x06090011: sub-index does not exist.
    NoSubIndex = 0x0609_0011, "Sub-index does not exist";
    /// 0x06090030: invalid value for parameter (download only).
    InvalidValue = 0x0609_0030, "Invalid value for parameter (download only)";
    /// 0x06090031: value of parameter written too high (download only).
    ValueTooHigh = 0x0609_0031, "Value of parameter written too high (download only)";
    /// 0x06090032: value of parameter written too low (download only).
    ValueTooLow = 0x0609_0032, "Value of parameter written too low (download only)";
    /// 0x06090036: maximum value is less than minimum value.
    MaxLessThanMin = 0x0609_0036, "Maximum value is less than minimum value";
    /// 0x060A0023: resource not available: SDO connection.
    ResourceUnavailable = 0x060A_0023, "Resource not available: SDO connection";
    /// 0x08000000: general error.
    General = 0x0800_0000, "General error";
    /// 0x08000020: data cannot be transferred or stored to the application.
    CannotStore = 0x0800_0020, "Data cannot be transferred or stored to the application";
    /// 0x08000021: data cannot be transferred or stored because of local control.
    LocalControl = 0x0800_0021, "Data cannot be transferred or stored to the application because of local control";
    /// 0x08000022: data cannot be transferred or stored because of the present device state.
    DeviceState = 0x0800_0022, "Data cannot be transferred or stored to the application because of the present device state";
    /// 0x08000023: object dictionary dynamic generation failed or no object dictionary is present.
    NoDictionary = 0x0800_0023, "Object dictionary dynamic generation fails or no object dictionary is present";
    /// 0x08000024: no data available.
    NoData = 0x0800_0024, "No data available";
}

impl From<AbortCode> for u32 {
    fn from(code: AbortCode) -> u32 {
        code.code()
    }
}

impl fmt::Display for AbortCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "0x{:08X} ({})", self.code(), self.description())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_round_trips_through_u32() {
        for &code in AbortCode::ALL {
            assert_eq!(AbortCode::from(code.code()), code);
        }
        assert_eq!(
            AbortCode::from(0x1234_5678),
            AbortCode::Unknown(0x1234_5678)
        );
        assert_eq!(AbortCode::Unknown(0x1234_5678).code(), 0x1234_5678);
    }

    #[test]
    fn codes_are_distinct() {
        let mut seen: Vec<u32> = AbortCode::ALL.iter().map(|c| c.code()).collect();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), AbortCode::ALL.len());
    }

    #[test]
    fn display_names_the_code_and_its_meaning() {
        assert_eq!(
            AbortCode::ReadOnly.to_string(),
            "0x06010002 (Attempt to write a read only object)"
        );
    }
}
