//! Configuration data of the SMD23K-B / SMD24K (seed 000, Reference 5 "Configuration Data Format"): the
//! seven values of CoE object `8010`, the bit fields of CFG_Word_0 and CFG_Word_1, the calculator of
//! table R5.3 and the five "Invalid Configurations" of the manual.
//!
//! This is pure logic without IO:
//!
//! - [`InputFunction`] is a function code of table R5.2 (`000` … `110`; `111` is no function);
//! - [`Cfg0`] and [`Cfg1`] are CFG_Word_0 (`8010:01`) and CFG_Word_1 (`8010:02`) as named settings.
//!   [`Cfg0::from_word`] / [`Cfg1::from_word`] decode *any* word without loss (bit 15, "Reserved – State
//!   ignored", is dropped), [`Cfg0::encode`] / [`Cfg1::encode`] build the word (the table R5.3
//!   calculator) and `violations()` lists what makes the word invalid;
//! - [`Configuration`] holds all seven `8010` values, and [`Configuration::violations`] lists every rule
//!   the configuration breaks, each as a [`Violation`] naming the manual's invalid-configuration item
//!   ([`InvalidItem`], 1 … 5), the detail and the rule ID of the catalogue (`rules/smd.md`, R5);
//! - [`decode_words`] decodes CFG_Word_0 and optionally CFG_Word_1 for display, with their violations.
//!
//! ```
//! use ds402::smd::config::{decode_words, Cfg0, InputFunction, InvalidItem};
//!
//! let cfg0 = Cfg0 {
//!     input1: Some(InputFunction::CwLimit),
//!     input2: Some(InputFunction::CcwLimit),
//!     use_encoder: true,
//!     enable_stall_detection: true,
//!     ..Cfg0::default()
//! };
//! assert_eq!(cfg0.encode(), 0x2411);
//!
//! let d = decode_words(0x1007, None);
//! assert_eq!(d.violations.len(), 2);
//! assert_eq!(d.violations[0].item(), InvalidItem::ReservedBit);
//! assert_eq!(d.violations[0].rule(), "SMD-R5-012");
//! assert_eq!(
//!     d.violations[0].to_string(),
//!     "invalid configuration 1 (reserved bit): CFG_Word_0 bit 12 is reserved and must be 0"
//! );
//! assert_eq!(d.violations[1].item(), InvalidItem::InputCode111);
//! ```
//!
//! Picks of the rule catalogue followed here:
//!
//! - bit 15 of both words is ignored, never an error (SMD-R5-009, SMD-R5-025): it is masked off before
//!   decoding and checking, so CFG_Word_1 = 0x8043 counts as 0x0043;
//! - Encoder_Resolution (`8010:05`) is checked only when CFG_Word_0 bit 10 Use_Encoder is 1, against
//!   1,024 / 2,048 / 4,096 for an incremental and 2,048 for an absolute encoder (SMD-R5-005).
//!
//! Choices where the manual is silent:
//!
//! - every reserved bit that is set is its own violation (CFG_Word_0 = 0x03C0 gives four);
//! - code `111` on both inputs is two item-5 violations and not also item 3: `111` is no function;
//! - CFG_Word_1's valid-value list (0–3, 64–67) is exactly "no reserved bit among 14–7 and 5–2 set", so
//!   an invalid CFG_Word_1 is reported as item 1 (reserved bit) under SMD-R5-025, never as item 2.

use std::fmt;
use std::str::FromStr;

/// CFG_Word_0 bits 2–0: Input 1 function.
pub const CFG0_INPUT1_MASK: u16 = 0x0007;
/// CFG_Word_0 bits 5–3: Input 2 function.
pub const CFG0_INPUT2_MASK: u16 = 0x0038;
/// CFG_Word_0 bit 10: Use_Encoder.
pub const CFG0_USE_ENCODER: u16 = 1 << 10;
/// CFG_Word_0 bit 11: Use_Backplane_Proximity.
pub const CFG0_USE_BACKPLANE_PROXIMITY: u16 = 1 << 11;
/// CFG_Word_0 bit 13: Enable_Stall_Detection.
pub const CFG0_ENABLE_STALL_DETECTION: u16 = 1 << 13;
/// CFG_Word_0 bit 14: Disable_Antiresonance.
pub const CFG0_DISABLE_ANTIRESONANCE: u16 = 1 << 14;
/// CFG_Word_0 reserved bits that must be 0: bit 12 and bits 9–6.
pub const CFG0_RESERVED_MASK: u16 = 0x13C0;
/// Bit 15 of either configuration word: "Reserved – State ignored".
pub const IGNORED_BIT_15: u16 = 0x8000;

/// CFG_Word_1 bit 0: IN1_Active_Level.
pub const CFG1_IN1_ACTIVE_LEVEL: u16 = 0x0001;
/// CFG_Word_1 bit 1: IN2_Active_Level.
pub const CFG1_IN2_ACTIVE_LEVEL: u16 = 0x0002;
/// CFG_Word_1 bit 6: DC_Sync.
pub const CFG1_DC_SYNC: u16 = 0x0040;
/// CFG_Word_1 reserved bits that must be 0: bits 14–7 and 5–2.
pub const CFG1_RESERVED_MASK: u16 = 0x7FBC;
/// The valid values of CFG_Word_1 (R5 "Range of Values for Configuration Word 1"), bit 15 masked off.
pub const CFG1_VALID_VALUES: [u16; 8] = [
    0x0000, 0x0001, 0x0002, 0x0003, 0x0040, 0x0041, 0x0042, 0x0043,
];

/// The function of a discrete input, CFG_Word_0 bits 2–0 (Input 1) or 5–3 (Input 2), table R5.2.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum InputFunction {
    /// `000` General Purpose Input: no function, its state is only reported.
    GeneralPurpose,
    /// `001` CW Limit.
    CwLimit,
    /// `010` CCW Limit.
    CcwLimit,
    /// `011` Start Indexed Move / Capture Encoder Value.
    StartIndexed,
    /// `100` Stop Jog or Registration Move (and Capture Encoder Value).
    StopJog,
    /// `101` Emergency Stop.
    EStop,
    /// `110` Home.
    Home,
}

impl InputFunction {
    /// All seven functions in code order (`000` … `110`).
    pub const ALL: [InputFunction; 7] = [
        InputFunction::GeneralPurpose,
        InputFunction::CwLimit,
        InputFunction::CcwLimit,
        InputFunction::StartIndexed,
        InputFunction::StopJog,
        InputFunction::EStop,
        InputFunction::Home,
    ];

    /// The 3-bit function code (0 … 6).
    pub const fn code(self) -> u8 {
        match self {
            InputFunction::GeneralPurpose => 0b000,
            InputFunction::CwLimit => 0b001,
            InputFunction::CcwLimit => 0b010,
            InputFunction::StartIndexed => 0b011,
            InputFunction::StopJog => 0b100,
            InputFunction::EStop => 0b101,
            InputFunction::Home => 0b110,
        }
    }

    /// The function of a code; `None` for `111` ("Invalid Combination") and for values above 7.
    pub const fn from_code(code: u8) -> Option<InputFunction> {
        match code {
            0b000 => Some(InputFunction::GeneralPurpose),
            0b001 => Some(InputFunction::CwLimit),
            0b010 => Some(InputFunction::CcwLimit),
            0b011 => Some(InputFunction::StartIndexed),
            0b100 => Some(InputFunction::StopJog),
            0b101 => Some(InputFunction::EStop),
            0b110 => Some(InputFunction::Home),
            _ => None,
        }
    }

    /// The command-line name: `general-purpose`, `cw-limit`, `ccw-limit`, `start-indexed`, `stop-jog`,
    /// `e-stop` or `home`. [`FromStr`] parses it back.
    pub const fn name(self) -> &'static str {
        match self {
            InputFunction::GeneralPurpose => "general-purpose",
            InputFunction::CwLimit => "cw-limit",
            InputFunction::CcwLimit => "ccw-limit",
            InputFunction::StartIndexed => "start-indexed",
            InputFunction::StopJog => "stop-jog",
            InputFunction::EStop => "e-stop",
            InputFunction::Home => "home",
        }
    }

    /// The manual's name (table R5.2, catalogue SMD-R5-016), which [`Display`](fmt::Display) prints.
    pub const fn manual_name(self) -> &'static str {
        match self {
            InputFunction::GeneralPurpose => "General Purpose",
            InputFunction::CwLimit => "CW Limit",
            InputFunction::CcwLimit => "CCW Limit",
            InputFunction::StartIndexed => "Start Indexed Move/Capture",
            InputFunction::StopJog => "Stop Jog or Registration/Capture",
            InputFunction::EStop => "Emergency Stop",
            InputFunction::Home => "Home",
        }
    }
}

impl fmt::Display for InputFunction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.manual_name())
    }
}

impl From<InputFunction> for u8 {
    fn from(function: InputFunction) -> u8 {
        function.code()
    }
}

impl TryFrom<u8> for InputFunction {
    type Error = InvalidInputCode;

    fn try_from(code: u8) -> Result<Self, Self::Error> {
        InputFunction::from_code(code).ok_or(InvalidInputCode(code))
    }
}

/// A number that is no input-function code (`111`, or above 7).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0:#05b} is not an input-function code (000 to 110)")]
pub struct InvalidInputCode(pub u8);

/// A string that is no input-function name.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown input function {0:?} (expected general-purpose, cw-limit, ccw-limit, start-indexed, \
     stop-jog, e-stop or home)"
)]
pub struct ParseInputFunctionError(pub String);

impl FromStr for InputFunction {
    type Err = ParseInputFunctionError;

    /// Parses the command-line name ([`InputFunction::name`]), ignoring ASCII case and surrounding
    /// white space.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let t = s.trim();
        InputFunction::ALL
            .into_iter()
            .find(|f| f.name().eq_ignore_ascii_case(t))
            .ok_or_else(|| ParseInputFunctionError(s.to_string()))
    }
}

/// Which encoder the unit has (R1 Incremental Encoder Option / Absolute Multi-turn Encoder); it decides
/// the valid Encoder_Resolution values (SMD-R5-005).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum EncoderKind {
    /// Incremental (quadrature) encoder: 1,024, 2,048 or 4,096 counts per turn.
    #[default]
    Incremental,
    /// Absolute multi-turn encoder: 2,048 counts per turn.
    Absolute,
}

impl EncoderKind {
    /// The valid Encoder_Resolution values for this kind.
    pub const fn resolutions(self) -> &'static [u32] {
        match self {
            EncoderKind::Incremental => &[1024, 2048, 4096],
            EncoderKind::Absolute => &[2048],
        }
    }

    /// The command-line name: `incremental` or `absolute`. [`FromStr`] parses it back.
    pub const fn name(self) -> &'static str {
        match self {
            EncoderKind::Incremental => "incremental",
            EncoderKind::Absolute => "absolute",
        }
    }
}

impl fmt::Display for EncoderKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A string that is no encoder-kind name.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown encoder kind {0:?} (expected incremental or absolute)")]
pub struct ParseEncoderKindError(pub String);

impl FromStr for EncoderKind {
    type Err = ParseEncoderKindError;

    /// Parses `incremental` or `absolute`, ignoring ASCII case and surrounding white space.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let t = s.trim();
        [EncoderKind::Incremental, EncoderKind::Absolute]
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(t))
            .ok_or_else(|| ParseEncoderKindError(s.to_string()))
    }
}

/// One of the two bit-field configuration words.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Word {
    /// CFG_Word_0, `8010:01`.
    Cfg0,
    /// CFG_Word_1, `8010:02`.
    Cfg1,
}

impl Word {
    /// The manual's name, `CFG_Word_0` or `CFG_Word_1`.
    pub const fn name(self) -> &'static str {
        match self {
            Word::Cfg0 => "CFG_Word_0",
            Word::Cfg1 => "CFG_Word_1",
        }
    }

    /// The sub-index in object `8010`.
    pub const fn sub_index(self) -> u8 {
        match self {
            Word::Cfg0 => 1,
            Word::Cfg1 => 2,
        }
    }
}

impl fmt::Display for Word {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One of the five numeric configuration parameters (`8010:03` … `8010:07`, table R5.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Parameter {
    /// Starting_Speed, `8010:03`, 1 … 1,999,999 steps/s (SMD-R5-003).
    StartingSpeed,
    /// Motor_Resolution, `8010:04`, 200 … 32,767 steps per turn (SMD-R5-004).
    MotorResolution,
    /// Encoder_Resolution, `8010:05`, depends on the [`EncoderKind`] (SMD-R5-005).
    EncoderResolution,
    /// Idle_current_reduction, `8010:06`, 0 … 100 % (SMD-R5-006).
    IdleCurrentReduction,
    /// Motor_Current, `8010:07`, 1 … 34 (×0.1 Arms) (SMD-R5-007).
    MotorCurrent,
}

impl Parameter {
    /// The five parameters in sub-index order.
    pub const ALL: [Parameter; 5] = [
        Parameter::StartingSpeed,
        Parameter::MotorResolution,
        Parameter::EncoderResolution,
        Parameter::IdleCurrentReduction,
        Parameter::MotorCurrent,
    ];

    /// The manual's name (table R5.1).
    pub const fn name(self) -> &'static str {
        match self {
            Parameter::StartingSpeed => "Starting_Speed",
            Parameter::MotorResolution => "Motor_Resolution",
            Parameter::EncoderResolution => "Encoder_Resolution",
            Parameter::IdleCurrentReduction => "Idle_current_reduction",
            Parameter::MotorCurrent => "Motor_Current",
        }
    }

    /// The sub-index in object `8010`.
    pub const fn sub_index(self) -> u8 {
        match self {
            Parameter::StartingSpeed => 3,
            Parameter::MotorResolution => 4,
            Parameter::EncoderResolution => 5,
            Parameter::IdleCurrentReduction => 6,
            Parameter::MotorCurrent => 7,
        }
    }

    /// The valid values on a unit with the given encoder (only Encoder_Resolution depends on it).
    pub const fn range(self, kind: EncoderKind) -> ValidRange {
        match self {
            Parameter::StartingSpeed => ValidRange::Between {
                min: 1,
                max: 1_999_999,
            },
            Parameter::MotorResolution => ValidRange::Between {
                min: 200,
                max: 32_767,
            },
            Parameter::EncoderResolution => ValidRange::Encoder(kind),
            Parameter::IdleCurrentReduction => ValidRange::Between { min: 0, max: 100 },
            Parameter::MotorCurrent => ValidRange::Between { min: 1, max: 34 },
        }
    }

    /// The catalogue rule of the parameter's range.
    pub const fn rule(self) -> &'static str {
        match self {
            Parameter::StartingSpeed => "SMD-R5-003",
            Parameter::MotorResolution => "SMD-R5-004",
            Parameter::EncoderResolution => "SMD-R5-005",
            Parameter::IdleCurrentReduction => "SMD-R5-006",
            Parameter::MotorCurrent => "SMD-R5-007",
        }
    }

    /// The unit of the value as shown in messages ("" for a plain count).
    const fn unit(self) -> &'static str {
        match self {
            Parameter::StartingSpeed => " steps/s",
            Parameter::MotorResolution => " steps per turn",
            Parameter::EncoderResolution => " counts per turn",
            Parameter::IdleCurrentReduction => " %",
            Parameter::MotorCurrent => " (×0.1 Arms)",
        }
    }
}

impl fmt::Display for Parameter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The valid values of a parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ValidRange {
    /// `min` to `max`, both included.
    Between {
        /// Lowest valid value.
        min: u32,
        /// Highest valid value.
        max: u32,
    },
    /// The Encoder_Resolution values of this encoder kind ([`EncoderKind::resolutions`]).
    Encoder(EncoderKind),
}

impl ValidRange {
    /// Whether `value` is valid.
    pub fn contains(self, value: u32) -> bool {
        match self {
            ValidRange::Between { min, max } => (min..=max).contains(&value),
            ValidRange::Encoder(kind) => kind.resolutions().contains(&value),
        }
    }
}

impl fmt::Display for ValidRange {
    /// "range 1 to 1,999,999", "values for an incremental encoder 1,024, 2,048 or 4,096", "value for an
    /// absolute encoder 2,048".
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            ValidRange::Between { min, max } => {
                write!(f, "range {} to {}", grouped(min), grouped(max))
            }
            ValidRange::Encoder(kind) => {
                let values = kind.resolutions();
                if values.len() == 1 {
                    write!(f, "value for an {kind} encoder {}", grouped(values[0]))
                } else {
                    write!(f, "values for an {kind} encoder ")?;
                    for (i, v) in values.iter().enumerate() {
                        if i + 1 == values.len() {
                            f.write_str(" or ")?;
                        } else if i > 0 {
                            f.write_str(", ")?;
                        }
                        f.write_str(&grouped(*v))?;
                    }
                    Ok(())
                }
            }
        }
    }
}

/// `value` with thousands separators, as the manual writes numbers ("1,999,999").
fn grouped(value: u32) -> String {
    let digits = value.to_string();
    let head = match digits.len() % 3 {
        0 => 3,
        n => n,
    };
    let mut out = digits[..head].to_string();
    let mut rest = &digits[head..];
    while !rest.is_empty() {
        out.push(',');
        out.push_str(&rest[..3]);
        rest = &rest[3..];
    }
    out
}

/// The five items of the manual's "Invalid Configurations" list (R5, p.64).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum InvalidItem {
    /// 1) Setting any of the reserved bits in the configuration words.
    ReservedBit,
    /// 2) Setting any parameter to a value outside of its valid range.
    OutOfRange,
    /// 3) Configuring the two inputs to have the same function (except both General Purpose).
    SameFunction,
    /// 4) Setting the Stall Detection Enable bit without using the built-in encoder.
    StallWithoutEncoder,
    /// 5) Setting the input configuration bits of an input to `111`.
    InputCode111,
}

impl InvalidItem {
    /// The item's number in the manual's list, 1 … 5.
    pub const fn number(self) -> u8 {
        match self {
            InvalidItem::ReservedBit => 1,
            InvalidItem::OutOfRange => 2,
            InvalidItem::SameFunction => 3,
            InvalidItem::StallWithoutEncoder => 4,
            InvalidItem::InputCode111 => 5,
        }
    }

    /// A short title: "reserved bit", "parameter out of range", "same function on both inputs",
    /// "stall detection without encoder" or "input code 111".
    pub const fn title(self) -> &'static str {
        match self {
            InvalidItem::ReservedBit => "reserved bit",
            InvalidItem::OutOfRange => "parameter out of range",
            InvalidItem::SameFunction => "same function on both inputs",
            InvalidItem::StallWithoutEncoder => "stall detection without encoder",
            InvalidItem::InputCode111 => "input code 111",
        }
    }
}

impl fmt::Display for InvalidItem {
    /// "invalid configuration 1 (reserved bit)".
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "invalid configuration {} ({})",
            self.number(),
            self.title()
        )
    }
}

/// One broken validity rule of the configuration. [`Violation::item`] is the manual's item,
/// [`Violation::rule`] the catalogue rule, and [`Display`](fmt::Display) one sentence such as
/// "invalid configuration 1 (reserved bit): CFG_Word_0 bit 12 is reserved and must be 0".
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Violation {
    /// Item 1: a reserved bit that must be 0 is set (CFG_Word_0 bit 12: SMD-R5-012; CFG_Word_0 bits
    /// 9–6: SMD-R5-013; CFG_Word_1 bits 14–7 and 5–2: SMD-R5-025).
    ReservedBit {
        /// The word.
        word: Word,
        /// The bit number, 0 … 14.
        bit: u8,
    },
    /// Item 2: a parameter outside its valid values (SMD-R5-003, SMD-R5-004, SMD-R5-005,
    /// SMD-R5-006, SMD-R5-007).
    OutOfRange {
        /// The parameter.
        parameter: Parameter,
        /// Its value.
        value: u32,
        /// What would be valid.
        valid: ValidRange,
    },
    /// Item 3: both inputs have the same function other than General Purpose (SMD-R5-018).
    SameFunction {
        /// The shared function.
        function: InputFunction,
    },
    /// Item 4: CFG_Word_0 bit 13 Enable_Stall_Detection without bit 10 Use_Encoder (SMD-R5-011).
    StallWithoutEncoder,
    /// Item 5: an input's function code is `111` (SMD-R5-017).
    InputCode111 {
        /// The input, 1 or 2.
        input: u8,
    },
}

impl Violation {
    /// The manual's "Invalid Configurations" item this violation falls under.
    pub const fn item(&self) -> InvalidItem {
        match self {
            Violation::ReservedBit { .. } => InvalidItem::ReservedBit,
            Violation::OutOfRange { .. } => InvalidItem::OutOfRange,
            Violation::SameFunction { .. } => InvalidItem::SameFunction,
            Violation::StallWithoutEncoder => InvalidItem::StallWithoutEncoder,
            Violation::InputCode111 { .. } => InvalidItem::InputCode111,
        }
    }

    /// The catalogue rule ID, e.g. `"SMD-R5-012"`.
    pub const fn rule(&self) -> &'static str {
        match self {
            Violation::ReservedBit {
                word: Word::Cfg0,
                bit: 12,
            } => "SMD-R5-012",
            Violation::ReservedBit {
                word: Word::Cfg0, ..
            } => "SMD-R5-013",
            Violation::ReservedBit {
                word: Word::Cfg1, ..
            } => "SMD-R5-025",
            Violation::OutOfRange { parameter, .. } => parameter.rule(),
            Violation::SameFunction { .. } => "SMD-R5-018",
            Violation::StallWithoutEncoder => "SMD-R5-011",
            Violation::InputCode111 { .. } => "SMD-R5-017",
        }
    }
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: ", self.item())?;
        match *self {
            Violation::ReservedBit { word, bit } => {
                write!(f, "{word} bit {bit} is reserved and must be 0")
            }
            Violation::OutOfRange {
                parameter,
                value,
                valid,
            } => write!(
                f,
                "{parameter} (8010:{:02}) is {}{}, valid {valid}",
                parameter.sub_index(),
                grouped(value),
                parameter.unit(),
            ),
            Violation::SameFunction { function } => write!(
                f,
                "Input 1 and Input 2 are both {function}; only General Purpose may be given to both"
            ),
            Violation::StallWithoutEncoder => f.write_str(
                "CFG_Word_0 bit 13 Enable_Stall_Detection is 1 but bit 10 Use_Encoder is 0",
            ),
            Violation::InputCode111 { input } => {
                let bits = if input == 1 { "2–0" } else { "5–3" };
                write!(
                    f,
                    "Input {input} function (CFG_Word_0 bits {bits}) is 111, a reserved combination"
                )
            }
        }
    }
}

impl std::error::Error for Violation {}

/// One violation per set bit of `bits`, lowest bit first.
fn reserved_bits(word: Word, bits: u16, out: &mut Vec<Violation>) {
    out.extend(
        (0..16u8)
            .filter(|b| bits & (1 << b) != 0)
            .map(|bit| Violation::ReservedBit { word, bit }),
    );
}

/// CFG_Word_0 (`8010:01`) as named settings. [`Cfg0::from_word`] keeps every bit except the ignored bit
/// 15, so `Cfg0::from_word(w).encode() == w & 0x7FFF` for every `w`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Cfg0 {
    /// Bits 2–0: Input 1 function; `None` is code `111` (invalid).
    pub input1: Option<InputFunction>,
    /// Bits 5–3: Input 2 function; `None` is code `111` (invalid).
    pub input2: Option<InputFunction>,
    /// Bit 10 Use_Encoder: the built-in encoder is used.
    pub use_encoder: bool,
    /// Bit 11 Use_Backplane_Proximity: the Backplane_Proximity_Bit is used when homing.
    pub use_backplane_proximity: bool,
    /// Bit 13 Enable_Stall_Detection (needs [`Cfg0::use_encoder`]).
    pub enable_stall_detection: bool,
    /// Bit 14 Disable_Antiresonance: `true` turns the anti-resonance feature off.
    pub disable_antiresonance: bool,
    /// The reserved bits that are set among bit 12 and bits 9–6 (a mask of [`CFG0_RESERVED_MASK`]);
    /// 0 in a valid word.
    pub reserved: u16,
}

impl Default for Cfg0 {
    /// CFG_Word_0 = 0: both inputs General Purpose, everything off.
    fn default() -> Self {
        Cfg0::from_word(0)
    }
}

impl Cfg0 {
    /// The settings with the two input functions and everything else off.
    pub fn with_inputs(input1: InputFunction, input2: InputFunction) -> Cfg0 {
        Cfg0 {
            input1: Some(input1),
            input2: Some(input2),
            ..Cfg0::default()
        }
    }

    /// Decodes any word; bit 15 is ignored. Never fails: see [`Cfg0::violations`] for validity.
    pub fn from_word(word: u16) -> Cfg0 {
        Cfg0 {
            input1: InputFunction::from_code((word & CFG0_INPUT1_MASK) as u8),
            input2: InputFunction::from_code(((word & CFG0_INPUT2_MASK) >> 3) as u8),
            use_encoder: word & CFG0_USE_ENCODER != 0,
            use_backplane_proximity: word & CFG0_USE_BACKPLANE_PROXIMITY != 0,
            enable_stall_detection: word & CFG0_ENABLE_STALL_DETECTION != 0,
            disable_antiresonance: word & CFG0_DISABLE_ANTIRESONANCE != 0,
            reserved: word & CFG0_RESERVED_MASK,
        }
    }

    /// Decodes a word into its settings and the violations of the word alone (reserved bits, input
    /// codes, same function, stall without encoder), as [`Cfg0::violations`].
    pub fn decode(word: u16) -> (Cfg0, Vec<Violation>) {
        let cfg = Cfg0::from_word(word);
        let violations = cfg.violations();
        (cfg, violations)
    }

    /// The word (the calculator of table R5.3). An input of `None` gives code `111`; bit 15 is 0.
    pub fn encode(&self) -> u16 {
        let code = |f: Option<InputFunction>| f.map_or(0b111, InputFunction::code) as u16;
        let flag = |on: bool, bit: u16| if on { bit } else { 0 };
        code(self.input1)
            | code(self.input2) << 3
            | flag(self.use_encoder, CFG0_USE_ENCODER)
            | flag(self.use_backplane_proximity, CFG0_USE_BACKPLANE_PROXIMITY)
            | flag(self.enable_stall_detection, CFG0_ENABLE_STALL_DETECTION)
            | flag(self.disable_antiresonance, CFG0_DISABLE_ANTIRESONANCE)
            | (self.reserved & CFG0_RESERVED_MASK)
    }

    /// Every rule the word breaks, in item order: reserved bits (item 1, lowest bit first), same
    /// function (item 3), stall detection without encoder (item 4), code `111` (item 5, Input 1 first).
    pub fn violations(&self) -> Vec<Violation> {
        let mut out = Vec::new();
        reserved_bits(Word::Cfg0, self.reserved & CFG0_RESERVED_MASK, &mut out);
        if let (Some(a), Some(b)) = (self.input1, self.input2) {
            if a == b && a != InputFunction::GeneralPurpose {
                out.push(Violation::SameFunction { function: a });
            }
        }
        if self.enable_stall_detection && !self.use_encoder {
            out.push(Violation::StallWithoutEncoder);
        }
        if self.input1.is_none() {
            out.push(Violation::InputCode111 { input: 1 });
        }
        if self.input2.is_none() {
            out.push(Violation::InputCode111 { input: 2 });
        }
        out
    }

    /// Whether the word breaks no rule.
    pub fn is_valid(&self) -> bool {
        self.violations().is_empty()
    }
}

/// "yes" or "no".
fn yes_no(on: bool) -> &'static str {
    if on {
        "yes"
    } else {
        "no"
    }
}

/// The set bits of `mask` as "12, 9" (highest first), or "none".
fn bit_list(mask: u16) -> String {
    let bits: Vec<String> = (0..16u8)
        .rev()
        .filter(|b| mask & (1 << b) != 0)
        .map(|b| b.to_string())
        .collect();
    if bits.is_empty() {
        "none".to_string()
    } else {
        bits.join(", ")
    }
}

impl fmt::Display for Cfg0 {
    /// One setting per line, e.g. for 0x2411:
    ///
    /// ```text
    /// Input 1: CW Limit
    /// Input 2: CCW Limit
    /// Use_Encoder: yes
    /// Use_Backplane_Proximity: no
    /// Enable_Stall_Detection: yes
    /// Disable_Antiresonance: no
    /// Reserved bits set: none
    /// ```
    ///
    /// An input with code `111` shows as "Invalid Combination (111)".
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (n, input) in [(1, self.input1), (2, self.input2)] {
            match input {
                Some(function) => writeln!(f, "Input {n}: {function}")?,
                None => writeln!(f, "Input {n}: Invalid Combination (111)")?,
            }
        }
        writeln!(f, "Use_Encoder: {}", yes_no(self.use_encoder))?;
        writeln!(
            f,
            "Use_Backplane_Proximity: {}",
            yes_no(self.use_backplane_proximity)
        )?;
        writeln!(
            f,
            "Enable_Stall_Detection: {}",
            yes_no(self.enable_stall_detection)
        )?;
        writeln!(
            f,
            "Disable_Antiresonance: {}",
            yes_no(self.disable_antiresonance)
        )?;
        write!(f, "Reserved bits set: {}", bit_list(self.reserved))
    }
}

/// CFG_Word_1 (`8010:02`) as named settings. [`Cfg1::from_word`] keeps every bit except the ignored bit
/// 15, so `Cfg1::from_word(w).encode() == w & 0x7FFF` for every `w`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Cfg1 {
    /// Bit 0 IN1_Active_Level: `true` (1) = Input 1 is active when current flows (normally-open
    /// contacts), `false` (0) = active when no current flows (normally closed).
    pub in1_active_level: bool,
    /// Bit 1 IN2_Active_Level, as [`Cfg1::in1_active_level`] for Input 2.
    pub in2_active_level: bool,
    /// Bit 6 DC_Sync: `true` = moves start on SYNC0 of the Distributed Clock, `false` = as soon as the
    /// data is read from the ESC.
    pub dc_sync: bool,
    /// The reserved bits that are set among bits 14–7 and 5–2 (a mask of [`CFG1_RESERVED_MASK`]); 0 in a
    /// valid word.
    pub reserved: u16,
}

impl Default for Cfg1 {
    /// CFG_Word_1 = 3, the fixture's default: both active levels 1, DC_Sync off.
    fn default() -> Self {
        Cfg1::from_word(0x0003)
    }
}

impl Cfg1 {
    /// Decodes any word; bit 15 is ignored. Never fails: see [`Cfg1::violations`] for validity.
    pub fn from_word(word: u16) -> Cfg1 {
        Cfg1 {
            in1_active_level: word & CFG1_IN1_ACTIVE_LEVEL != 0,
            in2_active_level: word & CFG1_IN2_ACTIVE_LEVEL != 0,
            dc_sync: word & CFG1_DC_SYNC != 0,
            reserved: word & CFG1_RESERVED_MASK,
        }
    }

    /// Decodes a word into its settings and its violations, as [`Cfg1::violations`].
    pub fn decode(word: u16) -> (Cfg1, Vec<Violation>) {
        let cfg = Cfg1::from_word(word);
        let violations = cfg.violations();
        (cfg, violations)
    }

    /// The word; bit 15 is 0.
    pub fn encode(&self) -> u16 {
        let flag = |on: bool, bit: u16| if on { bit } else { 0 };
        flag(self.in1_active_level, CFG1_IN1_ACTIVE_LEVEL)
            | flag(self.in2_active_level, CFG1_IN2_ACTIVE_LEVEL)
            | flag(self.dc_sync, CFG1_DC_SYNC)
            | (self.reserved & CFG1_RESERVED_MASK)
    }

    /// One item-1 violation (SMD-R5-025) per reserved bit set, lowest bit first. Empty exactly when the
    /// word (bit 15 masked off) is one of [`CFG1_VALID_VALUES`].
    pub fn violations(&self) -> Vec<Violation> {
        let mut out = Vec::new();
        reserved_bits(Word::Cfg1, self.reserved & CFG1_RESERVED_MASK, &mut out);
        out
    }

    /// Whether the word breaks no rule.
    pub fn is_valid(&self) -> bool {
        self.violations().is_empty()
    }
}

impl fmt::Display for Cfg1 {
    /// One setting per line, e.g. for 0x0041:
    ///
    /// ```text
    /// IN1_Active_Level: 1 (active when current flows, normally open)
    /// IN2_Active_Level: 0 (active when no current flows, normally closed)
    /// DC_Sync: yes (moves start on SYNC0)
    /// Reserved bits set: none
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let level = |on: bool| {
            if on {
                "1 (active when current flows, normally open)"
            } else {
                "0 (active when no current flows, normally closed)"
            }
        };
        writeln!(f, "IN1_Active_Level: {}", level(self.in1_active_level))?;
        writeln!(f, "IN2_Active_Level: {}", level(self.in2_active_level))?;
        if self.dc_sync {
            writeln!(f, "DC_Sync: yes (moves start on SYNC0)")?;
        } else {
            writeln!(
                f,
                "DC_Sync: no (moves start when data is read from the ESC)"
            )?;
        }
        write!(f, "Reserved bits set: {}", bit_list(self.reserved))
    }
}

/// The seven values of object `8010` (table R5.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Configuration {
    /// `8010:01` CFG_Word_0.
    pub cfg0: u16,
    /// `8010:02` CFG_Word_1.
    pub cfg1: u16,
    /// `8010:03` Starting_Speed, steps/s.
    pub starting_speed: u32,
    /// `8010:04` Motor_Resolution, steps per turn.
    pub motor_resolution: u16,
    /// `8010:05` Encoder_Resolution, counts per turn.
    pub encoder_resolution: u16,
    /// `8010:06` Idle_current_reduction, % of the motor current.
    pub idle_current_reduction: u16,
    /// `8010:07` Motor_Current, in 0.1 Arms.
    pub motor_current: u16,
}

impl Default for Configuration {
    /// The fixture's defaults: CFG_Word_0 = 0, CFG_Word_1 = 3, Starting_Speed 141, Motor_Resolution 2000,
    /// Encoder_Resolution 2048, Idle_current_reduction 50 %, Motor_Current 10 (1.0 Arms). Valid for both
    /// encoder kinds.
    fn default() -> Self {
        Configuration {
            cfg0: 0x0000,
            cfg1: 0x0003,
            starting_speed: 141,
            motor_resolution: 2000,
            encoder_resolution: 2048,
            idle_current_reduction: 50,
            motor_current: 10,
        }
    }
}

impl Configuration {
    /// Stores `value` at `8010:sub` (1–7), as an SDO download does: narrowed to the entry's width,
    /// unchecked (an invalid value shows in the violations). `false` for another sub-index.
    pub fn set(&mut self, sub: u8, value: u32) -> bool {
        match sub {
            1 => self.cfg0 = value as u16,
            2 => self.cfg1 = value as u16,
            3 => self.starting_speed = value,
            4 => self.motor_resolution = value as u16,
            5 => self.encoder_resolution = value as u16,
            6 => self.idle_current_reduction = value as u16,
            7 => self.motor_current = value as u16,
            _ => return false,
        }
        true
    }

    /// CFG_Word_0 decoded.
    pub fn cfg0_settings(&self) -> Cfg0 {
        Cfg0::from_word(self.cfg0)
    }

    /// CFG_Word_1 decoded.
    pub fn cfg1_settings(&self) -> Cfg1 {
        Cfg1::from_word(self.cfg1)
    }

    /// The value of a numeric parameter.
    pub fn value(&self, parameter: Parameter) -> u32 {
        match parameter {
            Parameter::StartingSpeed => self.starting_speed,
            Parameter::MotorResolution => u32::from(self.motor_resolution),
            Parameter::EncoderResolution => u32::from(self.encoder_resolution),
            Parameter::IdleCurrentReduction => u32::from(self.idle_current_reduction),
            Parameter::MotorCurrent => u32::from(self.motor_current),
        }
    }

    /// Every rule the configuration breaks on a unit with the given encoder, in sub-index order:
    /// CFG_Word_0 ([`Cfg0::violations`]), CFG_Word_1 ([`Cfg1::violations`]), then the parameters
    /// `8010:03` … `8010:07` out of range (item 2). Encoder_Resolution is checked only when CFG_Word_0
    /// bit 10 Use_Encoder is 1 (SMD-R5-005 pick). Empty when the configuration is valid
    /// (Configuration_Error = 0, SMD-R5-026).
    pub fn violations(&self, kind: EncoderKind) -> Vec<Violation> {
        let cfg0 = self.cfg0_settings();
        let mut out = cfg0.violations();
        out.extend(self.cfg1_settings().violations());
        for parameter in Parameter::ALL {
            if parameter == Parameter::EncoderResolution && !cfg0.use_encoder {
                continue;
            }
            let value = self.value(parameter);
            let valid = parameter.range(kind);
            if !valid.contains(value) {
                out.push(Violation::OutOfRange {
                    parameter,
                    value,
                    valid,
                });
            }
        }
        out
    }

    /// Whether the configuration breaks no rule on a unit with the given encoder.
    pub fn is_valid(&self, kind: EncoderKind) -> bool {
        self.violations(kind).is_empty()
    }
}

impl fmt::Display for Configuration {
    /// The seven values, one per line ("8010:01 CFG_Word_0 = 0x0000", …, "8010:07 Motor_Current = 10
    /// (1.0 Arms)").
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "8010:01 CFG_Word_0 = {:#06X}", self.cfg0)?;
        writeln!(f, "8010:02 CFG_Word_1 = {:#06X}", self.cfg1)?;
        writeln!(
            f,
            "8010:03 Starting_Speed = {} steps/s",
            self.starting_speed
        )?;
        writeln!(
            f,
            "8010:04 Motor_Resolution = {} steps per turn",
            self.motor_resolution
        )?;
        writeln!(
            f,
            "8010:05 Encoder_Resolution = {} counts per turn",
            self.encoder_resolution
        )?;
        writeln!(
            f,
            "8010:06 Idle_current_reduction = {} %",
            self.idle_current_reduction
        )?;
        write!(
            f,
            "8010:07 Motor_Current = {} ({}.{} Arms)",
            self.motor_current,
            self.motor_current / 10,
            self.motor_current % 10
        )
    }
}

/// CFG_Word_0 and optionally CFG_Word_1 decoded, with their violations; what [`decode_words`] returns.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Decoded {
    /// The CFG_Word_0 value as given (bit 15 included).
    pub word0: u16,
    /// The CFG_Word_1 value as given, if any.
    pub word1: Option<u16>,
    /// CFG_Word_0's settings.
    pub cfg0: Cfg0,
    /// CFG_Word_1's settings, if the word was given.
    pub cfg1: Option<Cfg1>,
    /// The violations of CFG_Word_0, then those of CFG_Word_1 (the parameters `8010:03` … `8010:07` are
    /// not part of this check).
    pub violations: Vec<Violation>,
}

impl Decoded {
    /// Whether the given words break no rule.
    pub fn is_valid(&self) -> bool {
        self.violations.is_empty()
    }
}

/// Decodes CFG_Word_0 and, if given, CFG_Word_1, and checks them (the rules that need only the words).
pub fn decode_words(cfg0: u16, cfg1: Option<u16>) -> Decoded {
    let (settings0, mut violations) = Cfg0::decode(cfg0);
    let settings1 = cfg1.map(|w| {
        let (s, v) = Cfg1::decode(w);
        violations.extend(v);
        s
    });
    Decoded {
        word0: cfg0,
        word1: cfg1,
        cfg0: settings0,
        cfg1: settings1,
        violations,
    }
}

impl fmt::Display for Decoded {
    /// The words and their settings one per line, then "Valid: yes" or "Valid: no" followed by one line
    /// per violation, e.g.:
    ///
    /// ```text
    /// CFG_Word_0 = 0x2411
    /// Input 1: CW Limit
    /// …
    /// Reserved bits set: none
    /// Valid: yes
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "CFG_Word_0 = {:#06X}", self.word0)?;
        writeln!(f, "{}", self.cfg0)?;
        if let (Some(word), Some(cfg1)) = (self.word1, self.cfg1) {
            writeln!(f, "CFG_Word_1 = {word:#06X}")?;
            writeln!(f, "{cfg1}")?;
        }
        write!(f, "Valid: {}", yes_no(self.is_valid()))?;
        for v in &self.violations {
            write!(f, "\n  {v} [{}]", v.rule())?;
        }
        Ok(())
    }
}
