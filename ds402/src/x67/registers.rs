//! The registers of the X67SM2436 in function model 254 "Bus controller" / 3 "Ramp" (seed 002, table 18.5):
//! names, register numbers, data types and access, and the errors of a refused write.
//!
//! [`Register`] names one register of one axis or of the module; [`Register::from_name`] parses the seed's
//! spelling (`MaxAcc01`, `ConfigOutput07a`, `InputStatus`), and [`Register::info`] gives the table row.
//! [`crate::x67::module::Module::read`] and [`crate::x67::module::Module::write`] access them.
//!
//! ```
//! use ds402::x67::registers::{Access, AxisReg, Register, RegType};
//!
//! let reg = Register::from_name("ConfigOutput07a").unwrap();
//! assert_eq!(reg, Register::Axis(1, AxisReg::NominalCurrent));
//! let info = reg.info();
//! assert_eq!((info.number, info.ty, info.access), (113, RegType::Usint, Access::Config));
//! assert_eq!(Register::Axis(0, AxisReg::Status).name(), "MpGenStatus01");
//! ```

use std::fmt;

/// The data type of a register (X67-18.5-04).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RegType {
    /// 32-bit signed (INTEGER32).
    Dint,
    /// 16-bit unsigned (UNSIGNED16).
    Uint,
    /// 16-bit signed (INTEGER16).
    Int,
    /// 8-bit signed (INTEGER8).
    Sint,
    /// 8-bit unsigned (UNSIGNED8).
    Usint,
}

impl RegType {
    /// The value range of the type.
    pub const fn range(self) -> (i64, i64) {
        match self {
            RegType::Dint => (i32::MIN as i64, i32::MAX as i64),
            RegType::Uint => (0, u16::MAX as i64),
            RegType::Int => (i16::MIN as i64, i16::MAX as i64),
            RegType::Sint => (i8::MIN as i64, i8::MAX as i64),
            RegType::Usint => (0, u8::MAX as i64),
        }
    }

    /// The size in bytes.
    pub const fn size(self) -> usize {
        match self {
            RegType::Dint => 4,
            RegType::Uint | RegType::Int => 2,
            RegType::Sint | RegType::Usint => 1,
        }
    }
}

/// How a register is accessed (X67-18.5-03).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Access {
    /// Configuration: written acyclically only.
    Config,
    /// Read acyclically only (read-backs and status).
    ReadAcyclic,
    /// Cyclic output, written by the master.
    CyclicOut,
    /// Cyclic input, written by the module.
    CyclicIn,
}

impl Access {
    /// Whether the master may write the register.
    pub const fn writable(self) -> bool {
        matches!(self, Access::Config | Access::CyclicOut)
    }
}

/// A register of one axis; the axis is given by [`Register::Axis`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[allow(missing_docs)]
pub enum AxisReg {
    AbsPos,
    Control,
    Mode,
    ActVal,
    Status,
    HoldingCurrent,
    NominalCurrent,
    MaximumCurrent,
    StallDetectConfig,
    MaxSpeedPos,
    MaxAcc,
    MaxDec,
    RevLoop,
    FixedPosA,
    FixedPosB,
    RefSpeed,
    RefConfig,
    FullStepThreshold,
    StallRecognitionDelay,
    JoltTime,
    StallDetectMinSpeed,
    LimitSwitchConfig,
    PositionLimitMin,
    PositionLimitMax,
    HoldingCurrentRead,
    NominalCurrentRead,
    MaximumCurrentRead,
    ControlReadback,
    ModeReadback,
    MotorIdentification,
    RefPosCyclicCounter,
    ActValAcyclic,
    RefPosAcyclicCounter,
    ErrorCode,
}

impl AxisReg {
    /// Every per-axis register, in the order of the 18.5 table.
    pub const ALL: [AxisReg; 34] = [
        AxisReg::AbsPos,
        AxisReg::Control,
        AxisReg::Mode,
        AxisReg::ActVal,
        AxisReg::Status,
        AxisReg::HoldingCurrent,
        AxisReg::NominalCurrent,
        AxisReg::MaximumCurrent,
        AxisReg::StallDetectConfig,
        AxisReg::MaxSpeedPos,
        AxisReg::MaxAcc,
        AxisReg::MaxDec,
        AxisReg::RevLoop,
        AxisReg::FixedPosA,
        AxisReg::FixedPosB,
        AxisReg::RefSpeed,
        AxisReg::RefConfig,
        AxisReg::FullStepThreshold,
        AxisReg::StallRecognitionDelay,
        AxisReg::JoltTime,
        AxisReg::StallDetectMinSpeed,
        AxisReg::LimitSwitchConfig,
        AxisReg::PositionLimitMin,
        AxisReg::PositionLimitMax,
        AxisReg::HoldingCurrentRead,
        AxisReg::NominalCurrentRead,
        AxisReg::MaximumCurrentRead,
        AxisReg::ControlReadback,
        AxisReg::ModeReadback,
        AxisReg::MotorIdentification,
        AxisReg::RefPosCyclicCounter,
        AxisReg::ActValAcyclic,
        AxisReg::RefPosAcyclicCounter,
        AxisReg::ErrorCode,
    ];

    /// Names and register numbers of axis 1 and of axis 2, type and access.
    const fn row(self) -> Row {
        ROWS[self as usize]
    }
}

/// One row of the 18.5 table: the names and register numbers of axis 1 and of axis 2, type and access.
type Row = (&'static str, &'static str, u16, u16, RegType, Access);

/// The rows of the per-axis registers, in the order of [`AxisReg`]'s variants (and of [`AxisReg::ALL`]).
const ROWS: [Row; 34] = {
    use Access::*;
    use RegType::*;
    [
        // AbsPos
        ("AbsPos01", "AbsPos02", 0, 8, Dint, CyclicOut),
        // Control
        ("MpGenControl01", "MpGenControl02", 4, 12, Uint, CyclicOut),
        // Mode
        ("MpGenMode01", "MpGenMode02", 6, 14, Sint, CyclicOut),
        // ActVal
        ("AbsPos01ActVal", "AbsPos02ActVal", 0, 8, Dint, CyclicIn),
        // Status
        ("MpGenStatus01", "MpGenStatus02", 4, 12, Uint, CyclicIn),
        // HoldingCurrent
        ("ConfigOutput03a", "ConfigOutput06a", 48, 112, Usint, Config),
        // NominalCurrent
        ("ConfigOutput04a", "ConfigOutput07a", 49, 113, Usint, Config),
        // MaximumCurrent
        ("ConfigOutput05a", "ConfigOutput08a", 50, 114, Usint, Config),
        // StallDetectConfig
        (
            "StallDetectConfig01",
            "StallDetectConfig02",
            51,
            115,
            Usint,
            Config,
        ),
        // MaxSpeedPos
        ("MaxSpeed01pos", "MaxSpeed02pos", 52, 116, Uint, Config),
        // MaxAcc
        ("MaxAcc01", "MaxAcc02", 54, 118, Uint, Config),
        // MaxDec
        ("MaxDec01", "MaxDec02", 56, 120, Uint, Config),
        // RevLoop
        ("RevLoop01", "RevLoop02", 58, 122, Int, Config),
        // FixedPosA
        ("FixedPos01a", "FixedPos02a", 60, 124, Dint, Config),
        // FixedPosB
        ("FixedPos01b", "FixedPos02b", 64, 128, Dint, Config),
        // RefSpeed
        ("RefSpeed01", "RefSpeed02", 68, 132, Uint, Config),
        // RefConfig
        ("RefConfig01", "RefConfig02", 70, 134, Sint, Config),
        // FullStepThreshold
        (
            "FullStepThreshold01",
            "FullStepThreshold02",
            72,
            136,
            Uint,
            Config,
        ),
        // StallRecognitionDelay
        (
            "StallRecognitionDelay01",
            "StallRecognitionDelay02",
            74,
            138,
            Usint,
            Config,
        ),
        // JoltTime
        ("JoltTime01", "JoltTime02", 75, 139, Usint, Config),
        // StallDetectMinSpeed
        (
            "StallDetectMinSpeed01",
            "StallDetectMinSpeed02",
            78,
            142,
            Uint,
            Config,
        ),
        // LimitSwitchConfig
        (
            "LimitSwitchConfig01",
            "LimitSwitchConfig02",
            306,
            308,
            Usint,
            Config,
        ),
        // PositionLimitMin
        (
            "PositionLimitMin01",
            "PositionLimitMin02",
            380,
            388,
            Dint,
            Config,
        ),
        // PositionLimitMax
        (
            "PositionLimitMax01",
            "PositionLimitMax02",
            384,
            392,
            Dint,
            Config,
        ),
        // HoldingCurrentRead
        (
            "ConfigOutput03aRead",
            "ConfigOutput06aRead",
            48,
            112,
            Usint,
            ReadAcyclic,
        ),
        // NominalCurrentRead
        (
            "ConfigOutput04aRead",
            "ConfigOutput07aRead",
            49,
            113,
            Usint,
            ReadAcyclic,
        ),
        // MaximumCurrentRead
        (
            "ConfigOutput05aRead",
            "ConfigOutput08aRead",
            50,
            114,
            Usint,
            ReadAcyclic,
        ),
        // ControlReadback
        (
            "ControlReadback01",
            "ControlReadback02",
            80,
            144,
            Uint,
            ReadAcyclic,
        ),
        // ModeReadback
        (
            "ModeReadback01",
            "ModeReadback02",
            82,
            146,
            Sint,
            ReadAcyclic,
        ),
        // MotorIdentification
        (
            "Motoridentification01",
            "Motoridentification02",
            84,
            148,
            Uint,
            ReadAcyclic,
        ),
        // RefPosCyclicCounter
        (
            "RefPos01CyclicCounter",
            "RefPos02CyclicCounter",
            86,
            150,
            Dint,
            ReadAcyclic,
        ),
        // ActValAcyclic
        (
            "AbsPos01ActValAcyclic",
            "AbsPos02ActValAcyclic",
            90,
            154,
            Dint,
            ReadAcyclic,
        ),
        // RefPosAcyclicCounter
        (
            "RefPos01AcyclicCounter",
            "RefPos02AcyclicCounter",
            94,
            158,
            Dint,
            ReadAcyclic,
        ),
        // ErrorCode
        ("ErrorCode01", "ErrorCode02", 98, 162, Uint, ReadAcyclic),
    ]
};

/// A register of the module that is not per axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ModuleReg {
    /// InputStatus (6, cyclic input): DI1–DI6 in bits 0–5 (X67-18.11.3.6-01).
    InputStatus,
    /// GeneralConfig01 (304, configuration): bit 0 extended control word, bits 1–2 cycle (X67-18.11.1.15).
    GeneralConfig,
    /// Temperature (46, read acyclic): module temperature in °C (X67-18.11.3.8-01).
    Temperature,
}

/// A register of the module: one of an axis (0 = axis 1 with the `…01` registers, 1 = axis 2) or a
/// module-wide one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Register {
    /// A per-axis register; the axis index is 0 or 1.
    Axis(usize, AxisReg),
    /// A module-wide register.
    Module(ModuleReg),
}

/// One row of the 18.5 table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RegisterInfo {
    /// The seed's register name (`MaxAcc01`).
    pub name: &'static str,
    /// The seed's register number (not unique: a read and a write register may share it).
    pub number: u16,
    /// The data type.
    pub ty: RegType,
    /// The access.
    pub access: Access,
}

impl Register {
    /// Every register: the module-wide ones, then axis 1, then axis 2 (71 in all).
    pub fn all() -> impl Iterator<Item = Register> {
        [
            ModuleReg::InputStatus,
            ModuleReg::GeneralConfig,
            ModuleReg::Temperature,
        ]
        .into_iter()
        .map(Register::Module)
        .chain((0..2).flat_map(|a| AxisReg::ALL.into_iter().map(move |r| Register::Axis(a, r))))
    }

    /// The row of the 18.5 table. An axis index other than 0 is taken as axis 2.
    pub fn info(self) -> RegisterInfo {
        match self {
            Register::Module(m) => {
                let (name, number, ty, access) = match m {
                    ModuleReg::InputStatus => ("InputStatus", 6, RegType::Usint, Access::CyclicIn),
                    ModuleReg::GeneralConfig => {
                        ("GeneralConfig01", 304, RegType::Usint, Access::Config)
                    }
                    ModuleReg::Temperature => {
                        ("Temperature", 46, RegType::Sint, Access::ReadAcyclic)
                    }
                };
                RegisterInfo {
                    name,
                    number,
                    ty,
                    access,
                }
            }
            Register::Axis(axis, r) => {
                let (name1, name2, n1, n2, ty, access) = r.row();
                RegisterInfo {
                    name: if axis == 0 { name1 } else { name2 },
                    number: if axis == 0 { n1 } else { n2 },
                    ty,
                    access,
                }
            }
        }
    }

    /// The seed's name of the register.
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// The register with this name, exactly as the seed spells it (case-insensitive).
    pub fn from_name(name: &str) -> Option<Register> {
        Register::all().find(|r| r.name().eq_ignore_ascii_case(name))
    }
}

impl fmt::Display for Register {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Why a register write was refused; the register keeps its value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RegisterError {
    /// The register is read-only for the master (CiA 301 abort 0x06010002).
    #[error("{0} is read-only")]
    ReadOnly(Register),
    /// The value lies above the register's range (CiA 301 abort 0x06090031).
    #[error("{value} is above the range of {register} (at most {max})")]
    TooHigh {
        /// The register.
        register: Register,
        /// The value written.
        value: i64,
        /// The largest value accepted.
        max: i64,
    },
    /// The value lies below the register's range (CiA 301 abort 0x06090032).
    #[error("{value} is below the range of {register} (at least {min})")]
    TooLow {
        /// The register.
        register: Register,
        /// The value written.
        value: i64,
        /// The smallest value accepted.
        min: i64,
    },
}

impl RegisterError {
    /// The CiA 301 SDO abort code of the refusal.
    pub const fn abort_code(&self) -> u32 {
        match self {
            RegisterError::ReadOnly(_) => 0x0601_0002,
            RegisterError::TooHigh { .. } => 0x0609_0031,
            RegisterError::TooLow { .. } => 0x0609_0032,
        }
    }
}
