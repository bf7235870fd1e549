//! CiA 301 emergency error codes (§7.2.7.3.2) and the errors a device reports with them: what an
//! EMCY frame carries, whichever node sends it.

use std::fmt;

/// An EMCY error code (CiA 301 §7.2.7.3.2, Table 21 "Emergency error codes"): bytes 0–1 of an EMCY
/// frame, little-endian. The high byte names the class of the error.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct EmcyCode(pub u16);

impl EmcyCode {
    /// 0x0000 "error reset or no error".
    pub const NO_ERROR: EmcyCode = EmcyCode(0x0000);
    /// 0x2300 "current, CANopen device output side" (X67SM2436: overcurrent).
    pub const CURRENT_OUTPUT: EmcyCode = EmcyCode(0x2300);
    /// 0x3000 "voltage – generic error" (X67SM2436: supply voltage).
    pub const VOLTAGE: EmcyCode = EmcyCode(0x3000);
    /// 0x4200 "temperature, CANopen device" (X67SM2436: module temperature).
    pub const DEVICE_TEMPERATURE: EmcyCode = EmcyCode(0x4200);
    /// 0x8130 "life guard error or heartbeat error".
    pub const HEARTBEAT_ERROR: EmcyCode = EmcyCode(0x8130);
    /// 0x8210 "PDO not processed due to length error".
    pub const PDO_LENGTH_ERROR: EmcyCode = EmcyCode(0x8210);

    /// The 16-bit code.
    pub const fn get(self) -> u16 {
        self.0
    }

    /// The code as it travels in an EMCY frame.
    pub const fn to_le_bytes(self) -> [u8; 2] {
        self.0.to_le_bytes()
    }

    /// What the code means: the codes CiA 301 Table 21 names one by one (and those of the X67SM2436
    /// model), else the class of its high byte ([`EmcyCode::class`]).
    pub const fn meaning(self) -> &'static str {
        match self.0 {
            0x4200 => "temperature, device",
            0x8110 => "CAN overrun (objects lost)",
            0x8120 => "CAN in error passive mode",
            0x8130 => "life guard error or heartbeat error",
            0x8140 => "recovered from bus off",
            0x8150 => "CAN-ID collision",
            0x8210 => "PDO not processed due to length error",
            0x8220 => "PDO length exceeded",
            0x8240 => "unexpected SYNC data length",
            0x8250 => "RPDO timeout",
            _ => self.class(),
        }
    }

    /// The class of the code by its high byte (CiA 301 Table 21); a high byte the table does not list
    /// takes the generic class of its first digit.
    pub const fn class(self) -> &'static str {
        match self.0 >> 8 {
            0x00 => "error reset or no error",
            0x21 => "current, device input side",
            0x22 => "current inside the device",
            0x23 => "current, device output side",
            0x31 => "mains voltage",
            0x32 => "voltage inside the device",
            0x33 => "output voltage",
            0x41 => "ambient temperature",
            0x42 => "device temperature",
            0x61 => "internal software",
            0x62 => "user software",
            0x63 => "data set",
            0x81 => "communication",
            0x82 => "protocol error",
            0xFF => "device specific",
            _ => match self.0 >> 12 {
                0x1 => "generic error",
                0x2 => "current",
                0x3 => "voltage",
                0x4 => "temperature",
                0x5 => "device hardware",
                0x6 => "device software",
                0x7 => "additional modules",
                0x8 => "monitoring",
                0x9 => "external error",
                0xF => "additional functions",
                _ => "no class of CiA 301",
            },
        }
    }

    /// The error register bit the code sets (CiA 301 Table 48), besides bit 0 (generic).
    pub const fn register_bit(self) -> u8 {
        match self.0 >> 12 {
            0x2 => 1 << 1,
            0x3 => 1 << 2,
            0x4 => 1 << 3,
            // 0x81xx communication, 0x82xx protocol: the communication error bit; the other
            // monitoring codes (0x83xx–0x8Fxx: torque, speed, position, sync controllers) are the
            // device profile's (CiA 402: 0x8611 following error).
            0x8 if matches!((self.0 >> 8) & 0xF, 1 | 2) => 1 << 4,
            0x8 => 1 << 5,
            0x6 => 1 << 5,
            0xF => 1 << 7,
            _ => 0,
        }
    }
}

impl From<u16> for EmcyCode {
    fn from(code: u16) -> EmcyCode {
        EmcyCode(code)
    }
}

impl From<EmcyCode> for u16 {
    fn from(code: EmcyCode) -> u16 {
        code.0
    }
}

impl fmt::Display for EmcyCode {
    /// `0x8130 (life guard error or heartbeat error)`: the number and its [`EmcyCode::meaning`].
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "0x{:04X} ({})", self.0, self.meaning())
    }
}

/// EMCY error code "error reset or no error".
pub const NO_ERROR: EmcyCode = EmcyCode::NO_ERROR;
/// EMCY error code "life guard error or heartbeat error".
pub const HEARTBEAT_ERROR: EmcyCode = EmcyCode::HEARTBEAT_ERROR;
/// EMCY error code "PDO not processed due to length error".
pub const PDO_LENGTH_ERROR: EmcyCode = EmcyCode::PDO_LENGTH_ERROR;

/// An error a device reports: its EMCY code and the 5 manufacturer-specific bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DeviceError {
    /// CiA 301 / device error code.
    pub code: EmcyCode,
    /// Manufacturer-specific bytes 3–7 of the EMCY frame (which module and axis, for the X67 node).
    pub info: [u8; 5],
}

/// The error register for a set of active codes: bit 0 when any error is active, plus each code's bit.
pub fn error_register<'a>(codes: impl IntoIterator<Item = &'a DeviceError>) -> u8 {
    let mut reg = 0u8;
    for e in codes {
        reg |= 1 | e.code.register_bit();
    }
    reg
}

/// An EMCY frame's 8 data bytes.
pub fn frame_data(code: EmcyCode, register: u8, info: [u8; 5]) -> [u8; 8] {
    let c = code.to_le_bytes();
    [
        c[0], c[1], register, info[0], info[1], info[2], info[3], info[4],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn register_bits_follow_the_code_classes() {
        let e = |code| DeviceError {
            code: EmcyCode(code),
            info: [0; 5],
        };
        assert_eq!(error_register(&[e(0x2300)]), 0x03);
        assert_eq!(error_register(&[e(0x3000)]), 0x05);
        assert_eq!(error_register(&[e(0x4200)]), 0x09);
        assert_eq!(error_register(&[e(0x8130)]), 0x11);
        assert_eq!(error_register(&[e(0x8210)]), 0x11);
        assert_eq!(error_register(&[e(0x8611)]), 0x21);
        assert_eq!(error_register(&[e(0x6100)]), 0x21);
        assert_eq!(error_register(&[e(0x5000)]), 0x01);
        assert_eq!(error_register(&[e(0x1000)]), 0x01);
        assert_eq!(error_register(&[e(0xFF20), e(0x3000)]), 0x85);
        assert_eq!(error_register(&[]), 0x00);
        assert_eq!(
            frame_data(EmcyCode(0x4200), 0x09, [1, 2, 0, 0, 0]),
            [0x00, 0x42, 0x09, 1, 2, 0, 0, 0]
        );
    }

    #[test]
    fn codes_show_their_number_and_class() {
        let shown = |code: u16| EmcyCode(code).to_string();
        // Codes the table names one by one.
        assert_eq!(shown(0x0000), "0x0000 (error reset or no error)");
        assert_eq!(shown(0x1000), "0x1000 (generic error)");
        assert_eq!(shown(0x2300), "0x2300 (current, device output side)");
        assert_eq!(shown(0x3000), "0x3000 (voltage)");
        assert_eq!(shown(0x4200), "0x4200 (temperature, device)");
        assert_eq!(
            shown(0x8130),
            "0x8130 (life guard error or heartbeat error)"
        );
        assert_eq!(
            shown(0x8210),
            "0x8210 (PDO not processed due to length error)"
        );
        for (code, meaning) in [
            (0x8110, "CAN overrun (objects lost)"),
            (0x8120, "CAN in error passive mode"),
            (0x8140, "recovered from bus off"),
            (0x8150, "CAN-ID collision"),
            (0x8220, "PDO length exceeded"),
            (0x8240, "unexpected SYNC data length"),
            (0x8250, "RPDO timeout"),
        ] {
            assert_eq!(EmcyCode(code).meaning(), meaning, "{code:#06x}");
        }
        // Others: the class of the high byte.
        assert_eq!(shown(0x4210), "0x4210 (device temperature)");
        assert_eq!(shown(0x5000), "0x5000 (device hardware)");
        assert_eq!(shown(0x6300), "0x6300 (data set)");
        assert_eq!(shown(0x8131), "0x8131 (communication)");
        assert_eq!(shown(0x8211), "0x8211 (protocol error)");
        assert_eq!(shown(0x9000), "0x9000 (external error)");
        assert_eq!(shown(0xF000), "0xF000 (additional functions)");
        assert_eq!(shown(0xFF07), "0xFF07 (device specific)");
        // A high byte the table does not list: the generic class of its first digit.
        assert_eq!(shown(0x2400), "0x2400 (current)");
        assert_eq!(shown(0xA000), "0xA000 (no class of CiA 301)");
    }

    /// Every class of CiA 301 Table 21, by the high byte where the table lists it, else by the first
    /// digit.
    #[test]
    fn every_class_of_the_table() {
        for (code, class) in [
            (0x0001, "error reset or no error"),
            (0x2110, "current, device input side"),
            (0x2220, "current inside the device"),
            (0x2330, "current, device output side"),
            (0x3110, "mains voltage"),
            (0x3220, "voltage inside the device"),
            (0x3330, "output voltage"),
            (0x4110, "ambient temperature"),
            (0x4220, "device temperature"),
            (0x6110, "internal software"),
            (0x6200, "user software"),
            (0x6320, "data set"),
            (0x8140, "communication"),
            (0x8230, "protocol error"),
            (0xFF00, "device specific"),
            (0x1001, "generic error"),
            (0x2500, "current"),
            (0x3400, "voltage"),
            (0x4300, "temperature"),
            (0x5530, "device hardware"),
            (0x6400, "device software"),
            (0x7100, "additional modules"),
            (0x8611, "monitoring"),
            (0x9009, "external error"),
            (0xF001, "additional functions"),
            (0xB000, "no class of CiA 301"),
        ] {
            assert_eq!(EmcyCode(code).class(), class, "{code:#06x}");
        }
    }

    #[test]
    fn named_codes_are_the_tables_numbers() {
        assert_eq!(NO_ERROR.get(), 0x0000);
        assert_eq!(HEARTBEAT_ERROR.get(), 0x8130);
        assert_eq!(PDO_LENGTH_ERROR.get(), 0x8210);
        assert_eq!(EmcyCode::CURRENT_OUTPUT, EmcyCode::from(0x2300));
        assert_eq!(u16::from(EmcyCode::VOLTAGE), 0x3000);
        assert_eq!(EmcyCode::DEVICE_TEMPERATURE.to_le_bytes(), [0x00, 0x42]);
    }
}
