//! The error-code register of one X67SM2436 axis and the module's over-temperature cut-off (seed 002,
//! sections 15, 18.11.3.8 and 18.11.3.13).
//!
//! This is a sans-IO model. [`ErrorRegister`] keeps, for each code of the seed's error-code table, two flags:
//! whether its *condition* is present now and whether it is *latched* (reported). A condition that appears
//! latches its code; the code stays latched after the condition has gone, until it is acknowledged
//! (X67-18.6.3.1-05): a Warning reset (↑ control-word bit 12) acknowledges warnings, a Fault reset
//! (↑ control-word bit 7) acknowledges errors and warnings. A code whose condition is still present when it
//! is acknowledged is latched again at once. [`ErrorRegister::register`] is the value of ErrorCode0n: the
//! latched code with the highest priority, or 0.
//!
//! [`Temperature`] is the module-wide temperature: the Temperature register value and the 85 °C / 83 °C
//! hysteresis of the over-temperature condition 0x4200, which it enters on each axis's register.
//!
//! ```
//! use ds402::x67::errors::{ErrorCode, ErrorRegister, Temperature};
//!
//! let mut axis = ErrorRegister::new();
//! let mut temp = Temperature::new();
//! temp.update(86.0);
//! temp.apply_to(&mut axis);
//! assert_eq!((axis.register(), axis.has_error()), (0x4200, true));
//! temp.update(83.0); // condition gone, the code stays until a Fault reset
//! temp.apply_to(&mut axis);
//! assert_eq!((axis.register(), axis.has_error()), (0x4200, false));
//! axis.fault_reset();
//! assert_eq!(axis.register(), 0x0000);
//! ```
//!
//! Rule IDs (`X67-…`) refer to the rule catalogue of the X67SM2436 (`rules/x67.md`), sections 15, 18.11.3.8 and
//! 18.11.3.13.

/// Control word bit 12: Warning reset, acting on its rising edge (X67-18.11.3.2-06, X67-18.11.4.1-10).
pub const CW_WARNING_RESET: u16 = 1 << 12;
/// Control word bit 13: current-error detection on (X67-18.11.3.2-07).
pub const CW_CURRENT_ERROR_DETECTION: u16 = 1 << 13;
/// Control word bit 15: stall detection on (X67-18.11.3.2-09).
pub const CW_STALL_DETECTION: u16 = 1 << 15;

/// The type of an error code (seed 002, 18.11.3.13 table, column "Error type").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    /// Takes the axis to Fault through Fault reaction active; status-word bit 3.
    Error,
    /// Sets status-word bit 7 only, without a state change.
    Warning,
}

/// A code of the error-code table (seed 002, 18.11.3.13), declared in the table's order, which is the
/// priority order: the first variant has the highest priority (X67-18.11.3.13-10).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ErrorCode {
    /// 0x3000 "Voltage": Error, highest priority (X67-18.11.3.13-02). Every supply-voltage error is reported
    /// with this code, also the DC-bus overvoltage that 18.11.4.3 calls 0x3210 (the catalogue's pick).
    Voltage,
    /// 0x4200 "Overtemperature": Error, second (X67-18.11.3.13-03, X67-15-01).
    Overtemperature,
    /// 0xFF20 "Negative limit switch": Warning, third (X67-18.11.3.13-04).
    NegativeLimitSwitch,
    /// 0xFF21 "Positive limit switch": Warning, fourth (X67-18.11.3.13-05).
    PositiveLimitSwitch,
    /// 0x2300 "Overcurrent": Warning, fifth (X67-18.11.3.13-06).
    Overcurrent,
    /// 0xFF00 "Current error": Warning, sixth; detected only with control-word bit 13 = 1
    /// (X67-18.11.3.13-07).
    CurrentError,
    /// 0xFF01 "Stall": Warning, seventh; detected only with control-word bit 15 = 1 (X67-18.11.3.13-08).
    Stall,
    /// 0xFF11 "Open circuit": Warning, lowest priority; detected whatever bit 13 holds (X67-18.11.3.13-09).
    OpenCircuit,
}

impl ErrorCode {
    /// All codes in table order, highest priority first.
    pub const ALL: [ErrorCode; 8] = [
        ErrorCode::Voltage,
        ErrorCode::Overtemperature,
        ErrorCode::NegativeLimitSwitch,
        ErrorCode::PositiveLimitSwitch,
        ErrorCode::Overcurrent,
        ErrorCode::CurrentError,
        ErrorCode::Stall,
        ErrorCode::OpenCircuit,
    ];

    /// The register value of the code.
    pub const fn code(self) -> u16 {
        match self {
            ErrorCode::Voltage => 0x3000,
            ErrorCode::Overtemperature => 0x4200,
            ErrorCode::NegativeLimitSwitch => 0xFF20,
            ErrorCode::PositiveLimitSwitch => 0xFF21,
            ErrorCode::Overcurrent => 0x2300,
            ErrorCode::CurrentError => 0xFF00,
            ErrorCode::Stall => 0xFF01,
            ErrorCode::OpenCircuit => 0xFF11,
        }
    }

    /// The code with register value `value`; `None` for 0 ("No error") and for values not in the table.
    pub fn from_code(value: u16) -> Option<ErrorCode> {
        ErrorCode::ALL.into_iter().find(|c| c.code() == value)
    }

    /// The type of the code: 0x3000 and 0x4200 are Errors, all others Warnings.
    pub const fn kind(self) -> Kind {
        match self {
            ErrorCode::Voltage | ErrorCode::Overtemperature => Kind::Error,
            _ => Kind::Warning,
        }
    }

    /// The rank in the priority order: 0 for the highest priority (0x3000), 7 for the lowest (0xFF11).
    pub const fn priority(self) -> usize {
        self as usize
    }

    /// The control-word bit that must be 1 for the code to be detected, if any (table footnotes 1 and 2).
    pub const fn detection_bit(self) -> Option<u16> {
        match self {
            ErrorCode::CurrentError => Some(CW_CURRENT_ERROR_DETECTION),
            ErrorCode::Stall => Some(CW_STALL_DETECTION),
            _ => None,
        }
    }

    fn bit(self) -> u8 {
        1 << self.priority()
    }
}

const ERROR_MASK: u8 = (1 << ErrorCode::Voltage as u8) | (1 << ErrorCode::Overtemperature as u8);
const WARNING_MASK: u8 = !ERROR_MASK;

/// The error-code register of one axis (ErrorCode01 or ErrorCode02) with its pending list.
///
/// Each axis has its own (X67-18.11.3.13-12); a module-wide condition (supply voltage, module temperature) is
/// raised on both.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ErrorRegister {
    /// Codes whose condition is present now, one bit per code in priority order.
    present: u8,
    /// Codes reported and not yet acknowledged.
    latched: u8,
    /// The last control word given to [`ErrorRegister::control_word`].
    control: u16,
}

impl ErrorRegister {
    /// A register with nothing pending, as after power-up (X67-18.11.3.13-01), and with current-error and
    /// stall detection off (the control word's default 0).
    pub const fn new() -> ErrorRegister {
        ErrorRegister {
            present: 0,
            latched: 0,
            control: 0,
        }
    }

    /// Takes the control word of this cycle: bits 13 and 15 switch the detection of 0xFF00 and 0xFF01, and a
    /// rising edge on bit 12 is a [`warning_reset`](ErrorRegister::warning_reset). Bit 7 (Fault reset) is left
    /// to the state machine, whose `ClearErrors` action calls [`fault_reset`](ErrorRegister::fault_reset).
    ///
    /// Switching a detection off drops that condition (it can no longer be detected) but not its latched code,
    /// which waits for an acknowledgement like any other.
    pub fn control_word(&mut self, cw: u16) {
        let rising = cw & !self.control;
        self.control = cw;
        for code in [ErrorCode::CurrentError, ErrorCode::Stall] {
            if !self.detection_enabled(code) {
                self.present &= !code.bit();
            }
        }
        if rising & CW_WARNING_RESET != 0 {
            self.warning_reset();
        }
    }

    /// Whether `code` can be detected with the current control word: 0xFF00 needs bit 13, 0xFF01 bit 15; all
    /// other codes always.
    pub fn detection_enabled(&self, code: ErrorCode) -> bool {
        match code.detection_bit() {
            Some(bit) => self.control & bit != 0,
            None => true,
        }
    }

    /// The condition of `code` is present: the code is latched and stays so while the condition lasts.
    /// Returns `false`, changing nothing, when the detection of `code` is off (0xFF00 without control-word
    /// bit 13, 0xFF01 without bit 15).
    pub fn raise(&mut self, code: ErrorCode) -> bool {
        if !self.detection_enabled(code) {
            return false;
        }
        self.present |= code.bit();
        self.latched |= code.bit();
        true
    }

    /// The condition of `code` has gone. Its code stays latched until it is acknowledged (X67-18.6.3.1-05).
    pub fn clear_condition(&mut self, code: ErrorCode) {
        self.present &= !code.bit();
    }

    /// [`raise`](ErrorRegister::raise) when `present`, else [`clear_condition`](ErrorRegister::clear_condition);
    /// for conditions the axis model samples every cycle. Returns whether the condition is now present.
    pub fn set_condition(&mut self, code: ErrorCode, present: bool) -> bool {
        if present {
            self.raise(code)
        } else {
            self.clear_condition(code);
            false
        }
    }

    /// Warning reset (↑ control-word bit 12): acknowledges the latched warnings; errors stay
    /// (X67-18.11.4.1-10). A warning whose condition is still present is latched again (X67-18.11.3.2-06).
    pub fn warning_reset(&mut self) {
        self.latched = (self.latched & ERROR_MASK) | (self.present & WARNING_MASK);
    }

    /// Fault reset (↑ control-word bit 7, the state machine's `ClearErrors`): acknowledges all latched errors
    /// and warnings; a code whose condition is still present is latched again (X67-18.11.4.1-11,
    /// X67-18.11.4.3-20).
    pub fn fault_reset(&mut self) {
        self.latched = self.present;
    }

    /// An Error-type condition (0x3000, 0x4200) is present: the state machine's `error_pending`. While it is,
    /// the axis goes to Fault and a Fault reset cannot leave Fault (X67-15-02). A latched Error whose
    /// condition has gone does not count: it waits in the register for the Fault reset.
    pub fn has_error(&self) -> bool {
        self.present & ERROR_MASK != 0
    }

    /// A warning is latched: status-word bit 7 (X67-18.11.3.13-11, X67-18.11.4.2-10).
    pub fn has_warning(&self) -> bool {
        self.latched & WARNING_MASK != 0
    }

    /// An Error-type code is latched, i.e. the register shows 0x3000 or 0x4200.
    pub fn error_latched(&self) -> bool {
        self.latched & ERROR_MASK != 0
    }

    /// Whether `code` is latched (reported and not yet acknowledged).
    pub fn is_latched(&self, code: ErrorCode) -> bool {
        self.latched & code.bit() != 0
    }

    /// Whether the condition of `code` is present now.
    pub fn is_present(&self, code: ErrorCode) -> bool {
        self.present & code.bit() != 0
    }

    /// The latched codes, highest priority first.
    pub fn pending(&self) -> impl Iterator<Item = ErrorCode> + '_ {
        ErrorCode::ALL.into_iter().filter(|c| self.is_latched(*c))
    }

    /// The latched code with the highest priority, if any.
    pub fn highest(&self) -> Option<ErrorCode> {
        self.pending().next()
    }

    /// The value of ErrorCode0n: the latched code with the highest priority, or 0x0000 when nothing is
    /// pending (X67-18.11.3.13-01, X67-18.11.3.13-10).
    pub fn register(&self) -> u16 {
        self.highest().map_or(0, ErrorCode::code)
    }
}

/// The lowest valid supply voltage in V: 24 V − 25 % (X67-3-11).
pub const SUPPLY_MIN_VOLTS: f64 = 18.0;
/// The highest valid supply voltage in V: 38.5 V + 25 % (X67-3-11).
pub const SUPPLY_MAX_VOLTS: f64 = 48.125;

/// Whether a supply voltage lies in the valid band 18.0 V … 48.125 V, both ends included, with no hysteresis
/// (X67-3-11 and its pick). Outside it (or NaN) the voltage condition 0x3000 is present on both axes; enter it
/// with [`ErrorRegister::set_condition`]`(`[`ErrorCode::Voltage`]`, !supply_in_range(v))`.
pub fn supply_in_range(volts: f64) -> bool {
    (SUPPLY_MIN_VOLTS..=SUPPLY_MAX_VOLTS).contains(&volts)
}

/// The capacitance of the module's DC bus in F (seed 002, section 3: "DC bus capacitance 200 µF").
pub const DC_BUS_FARADS: f64 = 200e-6;
/// The time constant in s with which the DC bus falls back to the supply voltage after regeneration: the
/// bus capacitance discharging through the module's own consumption, 2 W at 48 V (section 3, "Internal I/O
/// at 48 VDC max. 2 W"): R = 48² / 2 = 1152 Ω, τ = R·C = 0.2304 s.
pub const DC_BUS_DISCHARGE_SECONDS: f64 = 1152.0 * DC_BUS_FARADS;

/// The module's DC bus, which both motor bridges share and the supply feeds.
///
/// Switching the voltage off on a turning motor sends its energy back into the bus capacitance
/// (18.11.4.3: "regeneration on a motor running at no load can cause an overvoltage error on the DC bus"),
/// which raises the bus to `√(V² + 2E/C)`; the supply cannot take current back, so the rise then falls
/// away through the module's consumption with [`DC_BUS_DISCHARGE_SECONDS`]. A bus above
/// [`SUPPLY_MAX_VOLTS`] is the overvoltage of the catalogue's pick, reported as 0x3000 on both axes
/// (X67-18.11.4.3-12, X67-18.11.3.13-02).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DcBus {
    /// How far the bus lies above the supply voltage, in V (0 or more).
    rise: f64,
}

impl DcBus {
    /// The bus voltage in V with the supply at `supply_volts`.
    pub fn volts(&self, supply_volts: f64) -> f64 {
        supply_volts + self.rise
    }

    /// Takes `joules` (0 or more) of regenerated energy into the bus capacitance, with the supply at
    /// `supply_volts` (finite).
    pub fn regenerate(&mut self, supply_volts: f64, joules: f64) {
        let v = self.volts(supply_volts);
        self.rise = (v * v + 2.0 * joules / DC_BUS_FARADS).sqrt() - supply_volts;
    }

    /// Lets `seconds` pass: the rise falls by `e^(−t/τ)`. A bus at the supply voltage (the usual
    /// case, every cycle) costs no exponential.
    pub fn discharge(&mut self, seconds: f64) {
        if self.rise != 0.0 {
            self.rise *= (-seconds / DC_BUS_DISCHARGE_SECONDS).exp();
        }
    }
}

/// The module temperature at which the over-temperature condition appears, in °C (X67-15-01).
pub const CUTOFF_CELSIUS: f64 = 85.0;
/// The module temperature at or below which the over-temperature condition goes, in °C (X67-15-02).
pub const RECOVERY_CELSIUS: f64 = 83.0;

/// The module temperature and its over-temperature cut-off (seed 002, sections 15 and 18.11.3.8).
///
/// There is one module temperature; its condition 0x4200 is entered on both axes (X67-15-01 pick) through
/// [`Temperature::apply_to`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Temperature {
    celsius: f64,
    over: bool,
}

impl Temperature {
    /// 0 °C, no over-temperature.
    pub const fn new() -> Temperature {
        Temperature {
            celsius: 0.0,
            over: false,
        }
    }

    /// Takes a new module temperature in °C and returns whether the over-temperature condition is present:
    /// it appears at 85 °C or more (X67-15-01) and goes at 83 °C or less; between the two it keeps its
    /// previous state (X67-15-02). A NaN reading is ignored.
    pub fn update(&mut self, celsius: f64) -> bool {
        if celsius.is_nan() {
            return self.over;
        }
        self.celsius = celsius;
        if celsius >= CUTOFF_CELSIUS {
            self.over = true;
        } else if celsius <= RECOVERY_CELSIUS {
            self.over = false;
        }
        self.over
    }

    /// The last module temperature in °C.
    pub fn celsius(&self) -> f64 {
        self.celsius
    }

    /// Whether the over-temperature condition is present (the PWM outputs are off while it is).
    pub fn over_temperature(&self) -> bool {
        self.over
    }

    /// The Temperature register: the module temperature in whole °C as a SINT, truncated toward zero and
    /// clamped to −128…127 (X67-18.11.3.8-01 and its pick).
    pub fn register(&self) -> i8 {
        // `as` truncates toward zero and saturates at the bounds of i8.
        self.celsius as i8
    }

    /// Enters the over-temperature condition on one axis's register: raises 0x4200 while it is present,
    /// clears the condition (not the latched code) otherwise.
    pub fn apply_to(&self, axis: &mut ErrorRegister) {
        axis.set_condition(ErrorCode::Overtemperature, self.over);
    }
}
