//! The EMCY producer's bookkeeping (CiA 301 §7.2.7): active errors, the error register 0x1001, the
//! pre-defined error field 0x1003 and the frames to send.

/// EMCY error code "error reset or no error".
pub const NO_ERROR: u16 = 0x0000;
/// EMCY error code "life guard error or heartbeat error".
pub const HEARTBEAT_ERROR: u16 = 0x8130;
/// EMCY error code "PDO not processed due to length error".
pub const PDO_LENGTH_ERROR: u16 = 0x8210;

/// An error the application reports: its EMCY code and the 5 manufacturer-specific bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct AppError {
    /// CiA 301 / device error code.
    pub code: u16,
    /// Manufacturer-specific bytes 3–7 of the EMCY frame (which module and axis, for the X67 node).
    pub info: [u8; 5],
}

/// The error register bit an error code sets (CiA 301 Table 48), besides bit 0 (generic).
pub const fn register_bit(code: u16) -> u8 {
    match code >> 12 {
        0x2 => 1 << 1,
        0x3 => 1 << 2,
        0x4 => 1 << 3,
        0x8 => 1 << 4,
        0x6 => 1 << 5,
        0xF => 1 << 7,
        _ => 0,
    }
}

/// The error register for a set of active codes: bit 0 when any error is active, plus each code's bit.
pub fn error_register<'a>(codes: impl IntoIterator<Item = &'a AppError>) -> u8 {
    let mut reg = 0u8;
    for e in codes {
        reg |= 1 | register_bit(e.code);
    }
    reg
}

/// An EMCY frame's 8 data bytes.
pub fn frame_data(code: u16, register: u8, info: [u8; 5]) -> [u8; 8] {
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
        let e = |code| AppError { code, info: [0; 5] };
        assert_eq!(error_register(&[e(0x2300)]), 0x03);
        assert_eq!(error_register(&[e(0x3000)]), 0x05);
        assert_eq!(error_register(&[e(0x4200)]), 0x09);
        assert_eq!(error_register(&[e(0x8130)]), 0x11);
        assert_eq!(error_register(&[e(0xFF20), e(0x3000)]), 0x85);
        assert_eq!(error_register(&[]), 0x00);
        assert_eq!(
            frame_data(0x4200, 0x09, [1, 2, 0, 0, 0]),
            [0x00, 0x42, 0x09, 1, 2, 0, 0, 0]
        );
    }
}
