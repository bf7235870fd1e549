//! The configuration registers of one axis (seed 002, 18.11.1) and how the axis reads them: the stall and
//! mixed-decay fields, the referencing conditions, the limit-switch polarities and the software limits.

/// The referencing conditions of RefConfig0n (X67-18.11.1.11).
pub mod ref_config {
    /// Rising edge of DI4.
    pub const DI4_RISING: i8 = -121;
    /// Falling edge of DI4.
    pub const DI4_FALLING: i8 = -122;
    /// Rising edge of the axis's R input (DI3 / DI6); the default.
    pub const R_RISING: i8 = -125;
    /// Falling edge of the axis's R input.
    pub const R_FALLING: i8 = -126;
    /// Homing on stall.
    pub const STALL: i8 = -127;
    /// Immediate homing without motion.
    pub const IMMEDIATE: i8 = -128;
}
/// The configuration registers of one axis (seed 002, 18.11.1), with the bus-controller defaults.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AxisConfig {
    /// ConfigOutput03a/06a: holding current in % of 3 A, 0…167.
    pub holding_current: u8,
    /// ConfigOutput04a/07a: nominal current in %, 0…167.
    pub nominal_current: u8,
    /// ConfigOutput05a/08a: maximum current in %, 0…167.
    pub maximum_current: u8,
    /// StallDetectConfig0n: bits 0–3 mixed-decay threshold, 4–6 stall threshold, 7 motor load in the status
    /// word.
    pub stall_detect_config: u8,
    /// MaxSpeed0npos, microsteps/cycle.
    pub max_speed_pos: u16,
    /// MaxAcc0n, microsteps/cycle².
    pub max_acc: u16,
    /// MaxDec0n, microsteps/cycle².
    pub max_dec: u16,
    /// RevLoop0n, microsteps.
    pub rev_loop: i16,
    /// FixedPos0na, microsteps.
    pub fixed_pos_a: i32,
    /// FixedPos0nb, microsteps.
    pub fixed_pos_b: i32,
    /// RefSpeed0n, microsteps/cycle.
    pub ref_speed: u16,
    /// RefConfig0n: the referencing condition; default −125 (X67-18.11.1.11-06).
    pub ref_config: i8,
    /// FullStepThreshold0n, microsteps/cycle.
    pub full_step_threshold: u16,
    /// StallRecognitionDelay0n, cycles.
    pub stall_recognition_delay: u8,
    /// JoltTime0n, FIFO elements (values above 80 act as 80).
    pub jolt_time: u8,
    /// StallDetectMinSpeed0n, microsteps/cycle.
    pub stall_detect_min_speed: u16,
    /// LimitSwitchConfig0n: bits 0–1 negative switch, 2–3 positive switch, 7 direction monitoring.
    pub limit_switch_config: u8,
    /// PositionLimitMin0n, microsteps.
    pub position_limit_min: i32,
    /// PositionLimitMax0n, microsteps.
    pub position_limit_max: i32,
}

impl Default for AxisConfig {
    fn default() -> Self {
        AxisConfig {
            holding_current: 0,
            nominal_current: 0,
            maximum_current: 0,
            stall_detect_config: 0,
            max_speed_pos: 0,
            max_acc: 0,
            max_dec: 0,
            rev_loop: 0,
            fixed_pos_a: 0,
            fixed_pos_b: 0,
            ref_speed: 0,
            ref_config: ref_config::R_RISING,
            full_step_threshold: 0,
            stall_recognition_delay: 0,
            jolt_time: 0,
            stall_detect_min_speed: 0,
            limit_switch_config: 0,
            position_limit_min: 0,
            position_limit_max: 0,
        }
    }
}

impl AxisConfig {
    /// The stall threshold 0…7 (StallDetectConfig0n bits 4–6, X67-18.11.1.10-03); 0 = off.
    pub const fn stall_threshold(&self) -> u8 {
        (self.stall_detect_config >> 4) & 0x07
    }

    /// The mixed-decay threshold 0…15 (bits 0–3, X67-18.11.1.10-01).
    pub const fn mixed_decay_threshold(&self) -> u8 {
        self.stall_detect_config & 0x0F
    }

    /// Whether the motor load is shown in status-word bits 13–15 (bit 7, X67-18.11.1.10-04).
    pub const fn load_in_status(&self) -> bool {
        self.stall_detect_config & 0x80 != 0
    }

    /// Whether a RefConfig0n value is one of the listed referencing conditions. −120 is listed as "Set home
    /// position" but is no referencing condition; it is handled like the unlisted values (X67-18.11.1.11-04).
    pub const fn is_ref_condition(value: i8) -> bool {
        matches!(value, -121 | -122 | -125 | -126 | -127 | -128)
    }

    /// The software limits when they are on (at least one of Min/Max non-zero, X67-18.11.1.17-01).
    pub const fn software_limits(&self) -> Option<(i32, i32)> {
        if self.position_limit_min != 0 || self.position_limit_max != 0 {
            Some((self.position_limit_min, self.position_limit_max))
        } else {
            None
        }
    }
}

/// A limit switch's configuration: off, active low or active high (X67-18.11.1.16-01, X67-18.11.1.16-02).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SwitchPolarity {
    /// 00, and the reserved 10 (the catalogue's pick).
    Off,
    /// 01: active when the input is low.
    ActiveLow,
    /// 11: active when the input is high.
    ActiveHigh,
}

impl SwitchPolarity {
    /// Decodes a two-bit field.
    pub const fn from_bits(bits: u8) -> Self {
        match bits & 0b11 {
            0b01 => SwitchPolarity::ActiveLow,
            0b11 => SwitchPolarity::ActiveHigh,
            _ => SwitchPolarity::Off,
        }
    }

    /// Whether an input level counts as the switch being active.
    pub const fn active(self, level: bool) -> bool {
        match self {
            SwitchPolarity::Off => false,
            SwitchPolarity::ActiveLow => !level,
            SwitchPolarity::ActiveHigh => level,
        }
    }
}
