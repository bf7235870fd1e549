//! The rig the `drive_*` tests share: a dictionary with the objects a CiA 402 drive's EDS typically
//! has (the types and access of CiA 402-2), a [`Drive`] behind it reached through SDO uploads and
//! downloads ([`od::hook::Bound`]), and a simulated clock in whole milliseconds from the drive's
//! creation.
//!
//! The status-word values a test expects are spelled out in the tests; the constants here are the
//! control words of the standard's command table.
#![allow(dead_code)]

use std::time::{Duration, Instant};

use ds402::drive::{Drive, DriveConfig};
use od::hook::Bound;
use od::sdo::store::ObjectStore;
use od::{
    AbortCode, AccessType, Address, DataType, Dictionary, Object, ObjectKind, SubObject, Value,
};

/// Shutdown (0x06).
pub const SHUTDOWN: u16 = 0x0006;
/// Switch on (0x07); also Disable operation in Operation enabled.
pub const SWITCH_ON: u16 = 0x0007;
/// Enable operation (0x0F).
pub const ENABLE: u16 = 0x000F;
/// Disable voltage (0x00).
pub const DISABLE_VOLTAGE: u16 = 0x0000;
/// Quick stop as a master sends it from Operation enabled (0x0B: bit 2 cleared).
pub const QUICK_STOP: u16 = 0x000B;
/// Fault reset (bit 7).
pub const FAULT_RESET: u16 = 0x0080;

/// Controlword bit 4 (new set-point / start homing).
pub const NEW_SETPOINT: u16 = 0x0010;
/// Controlword bit 5 (change set immediately).
pub const IMMEDIATE: u16 = 0x0020;
/// Controlword bit 6 (relative).
pub const RELATIVE: u16 = 0x0040;
/// Controlword bit 8 (halt).
pub const HALT: u16 = 0x0100;

use AccessType::{Ro, Rw, Rww};
use DataType::{Integer16 as I16, Integer32 as I32, Integer8 as I8};
use DataType::{Unsigned16 as U16, Unsigned32 as U32, Unsigned8 as U8};

/// (index, sub, name, type, access, default) of the objects of one axis, standard indices.
const OBJECTS: &[(u16, u8, &str, DataType, AccessType, i64)] = &[
    (0x603F, 0, "Error code", U16, Ro, 0),
    (0x6040, 0, "Controlword", U16, Rww, 0),
    (0x6041, 0, "Statusword", U16, Ro, 0),
    (0x605A, 0, "Quick stop option code", I16, Rw, 2),
    (0x605B, 0, "Shutdown option code", I16, Rw, 0),
    (0x605C, 0, "Disable operation option code", I16, Rw, 1),
    (0x605D, 0, "Halt option code", I16, Rw, 1),
    (0x605E, 0, "Fault reaction option code", I16, Rw, 2),
    (0x6060, 0, "Modes of operation", I8, Rww, 0),
    (0x6061, 0, "Modes of operation display", I8, Ro, 0),
    (0x6062, 0, "Position demand value", I32, Ro, 0),
    (0x6063, 0, "Position actual internal value", I32, Ro, 0),
    (0x6064, 0, "Position actual value", I32, Ro, 0),
    (0x6065, 0, "Following error window", U32, Rw, 0xFFFF_FFFF),
    (0x6066, 0, "Following error time out", U16, Rw, 0),
    (0x6067, 0, "Position window", U32, Rw, 0xFFFF_FFFF),
    (0x6068, 0, "Position window time", U16, Rw, 0),
    (0x606B, 0, "Velocity demand value", I32, Ro, 0),
    (0x606C, 0, "Velocity actual value", I32, Ro, 0),
    (0x606D, 0, "Velocity window", U16, Rw, 10),
    (0x606E, 0, "Velocity window time", U16, Rw, 0),
    (0x606F, 0, "Velocity threshold", U16, Rw, 10),
    (0x6070, 0, "Velocity threshold time", U16, Rw, 0),
    (0x6071, 0, "Target torque", I16, Rww, 0),
    (0x6072, 0, "Max torque", U16, Rw, 3000),
    (0x6074, 0, "Torque demand", I16, Ro, 0),
    (0x6076, 0, "Motor rated torque", U32, Rw, 1000),
    (0x6077, 0, "Torque actual value", I16, Ro, 0),
    (0x607A, 0, "Target position", I32, Rww, 0),
    (0x607C, 0, "Home offset", I32, Rw, 0),
    (0x607D, 1, "Min position limit", I32, Rw, i32::MIN as i64),
    (0x607D, 2, "Max position limit", I32, Rw, i32::MAX as i64),
    (0x607F, 0, "Max profile velocity", U32, Rw, 1_000_000),
    (0x6080, 0, "Max motor speed", U32, Rw, 6000),
    (0x6081, 0, "Profile velocity", U32, Rww, 1000),
    (0x6083, 0, "Profile acceleration", U32, Rw, 10_000),
    (0x6084, 0, "Profile deceleration", U32, Rw, 10_000),
    (0x6085, 0, "Quick stop deceleration", U32, Rw, 100_000),
    (0x6086, 0, "Motion profile type", I16, Rw, 0),
    (0x608F, 1, "Encoder increments", U32, Rw, 10_000),
    (0x608F, 2, "Motor revolutions", U32, Rw, 1),
    (0x6098, 0, "Homing method", I8, Rw, 0),
    (0x6099, 1, "Speed during search for switch", U32, Rw, 2000),
    (0x6099, 2, "Speed during search for zero", U32, Rw, 500),
    (0x609A, 0, "Homing acceleration", U32, Rw, 20_000),
    (0x60B0, 0, "Position offset", I32, Rww, 0),
    (0x60B1, 0, "Velocity offset", I32, Rww, 0),
    (0x60B2, 0, "Torque offset", I16, Rww, 0),
    (0x60C2, 1, "Interpolation time period value", U8, Rw, 1),
    (0x60C2, 2, "Interpolation time index", I8, Rw, -3),
    (0x60F2, 0, "Positioning option code", U16, Rw, 0),
    (0x60F4, 0, "Following error actual value", I32, Ro, 0),
    (0x60FD, 0, "Digital inputs", U32, Ro, 0),
    (0x60FF, 0, "Target velocity", I32, Rww, 0),
    (0x6502, 0, "Supported drive modes", U32, Ro, 0x3A5),
];

/// A drive dictionary for axis 0 with `changes` applied to the defaults, leaving out the objects
/// `without` names (standard indices).
pub fn dictionary_with(changes: &[(u16, u8, i64)], without: &[u16]) -> Dictionary {
    let mut dict = Dictionary::new();
    add_axis(&mut dict, 0, changes, without);
    dict
}

/// A drive dictionary for axis 0 with `changes` applied to the defaults.
pub fn dictionary(changes: &[(u16, u8, i64)]) -> Dictionary {
    dictionary_with(changes, &[])
}

fn value_of(ty: DataType, v: i64) -> Value {
    if ty.is_signed() {
        Value::Int(v)
    } else {
        Value::Uint(v as u64)
    }
}

/// Adds the objects of `axis` (at 0x6000 + 0x800 · axis).
pub fn add_axis(dict: &mut Dictionary, axis: u8, changes: &[(u16, u8, i64)], without: &[u16]) {
    let base = 0x800 * u16::from(axis);
    for &(index, sub, name, ty, access, default) in OBJECTS {
        if without.contains(&index) {
            continue;
        }
        let value = changes
            .iter()
            .find(|(i, s, _)| *i == index && *s == sub)
            .map_or(default, |c| c.2);
        let mut entry = SubObject::new(name, ty, access).with_default(value_of(ty, default));
        entry.value = value_of(ty, value).encode(ty).expect("value fits its type");
        let at = index + base;
        if sub == 0 {
            dict.insert(Object::var(at, entry));
        } else {
            let object = dict.remove(at).unwrap_or_else(|| {
                Object::structured(at, name, ObjectKind::Array).with_sub(
                    0,
                    SubObject::new("Highest sub-index supported", U8, AccessType::Const)
                        .with_default(Value::Uint(0)),
                )
            });
            let mut object = object.with_sub(sub, entry);
            let n = object.max_sub();
            if let Some(s0) = object.subs.get_mut(&0) {
                s0.value = vec![n];
            }
            dict.insert(object);
        }
    }
}

/// A dictionary, its drive, and the simulated clock.
pub struct Rig {
    pub dict: Dictionary,
    pub drive: Drive,
    pub t0: Instant,
    pub now: Instant,
}

impl Rig {
    /// The drive of axis 0 of `dict`, made at t = 0.
    pub fn new(dict: Dictionary, config: DriveConfig) -> Rig {
        let t0 = Instant::now();
        let drive = Drive::from_dictionary(&dict, 0, config, t0).expect("axis 0 is a drive");
        Rig {
            dict,
            drive,
            t0,
            now: t0,
        }
    }

    /// The drive of [`dictionary`]`(changes)` with the default configuration.
    pub fn with(changes: &[(u16, u8, i64)]) -> Rig {
        Rig::new(dictionary(changes), DriveConfig::default())
    }

    /// Milliseconds since the drive was made.
    pub fn ms(&self) -> u64 {
        (self.now - self.t0).as_millis() as u64
    }

    /// Runs the drive to `ms` milliseconds after it was made, as a node does: at each instant
    /// `poll_timeout` names up to then, then at `ms` itself.
    pub fn at(&mut self, ms: u64) {
        self.at_us(1000 * ms);
    }

    /// Runs the drive to `us` microseconds after it was made (see [`Rig::at`]).
    pub fn at_us(&mut self, us: u64) {
        let until = self.t0 + Duration::from_micros(us);
        assert!(until >= self.now, "time runs forwards: {us} µs");
        while let Some(t) = self.drive.poll_timeout() {
            if t > until {
                break;
            }
            self.drive.handle_timeout(t);
        }
        self.drive.handle_timeout(until);
        self.now = until;
    }

    /// Runs `ms` milliseconds on.
    pub fn wait(&mut self, ms: u64) {
        let to = self.ms() + ms;
        self.at(to);
    }

    /// A SYNC at `ms`.
    pub fn sync_at(&mut self, ms: u64) {
        self.sync_at_us(1000 * ms);
    }

    /// A SYNC at `us` microseconds, between two ticks or on one.
    pub fn sync_at_us(&mut self, us: u64) {
        self.at_us(us);
        self.drive.sync(self.now);
    }

    /// An SDO download of `value` (in the entry's type) to standard `index:sub` of axis 0.
    pub fn write(&mut self, index: u16, sub: u8, value: i64) -> Result<(), AbortCode> {
        let ty = self.dict.entry(index, sub).expect("entry exists").data_type;
        let bytes = value_of(ty, value).encode(ty).expect("value fits its type");
        let mut bound = Bound::new(&mut self.dict, &mut self.drive, self.now);
        bound.download(Address::new(index, sub), &bytes)
    }

    /// An SDO download of raw `bytes`.
    pub fn write_bytes(&mut self, index: u16, sub: u8, bytes: &[u8]) -> Result<(), AbortCode> {
        let mut bound = Bound::new(&mut self.dict, &mut self.drive, self.now);
        bound.download(Address::new(index, sub), bytes)
    }

    /// Writes and expects success.
    #[track_caller]
    pub fn set(&mut self, index: u16, sub: u8, value: i64) {
        self.write(index, sub, value)
            .unwrap_or_else(|e| panic!("write 0x{index:04X}:{sub} = {value}: {e}"));
    }

    /// An SDO upload of standard `index:sub`, decoded.
    #[track_caller]
    pub fn read(&mut self, index: u16, sub: u8) -> i64 {
        let ty = self.dict.entry(index, sub).expect("entry exists").data_type;
        let mut bound = Bound::new(&mut self.dict, &mut self.drive, self.now);
        let bytes = bound.upload(Address::new(index, sub)).expect("upload");
        Value::decode(ty, &bytes)
            .expect("value of its type")
            .as_i128()
            .expect("integer") as i64
    }

    /// Writes the control word.
    #[track_caller]
    pub fn cw(&mut self, cw: u16) {
        self.set(0x6040, 0, i64::from(cw));
    }

    /// The status word as an SDO upload reads it.
    #[track_caller]
    pub fn sw(&mut self) -> u16 {
        self.read(0x6041, 0) as u16
    }

    /// 0x6064.
    pub fn pos(&mut self) -> i64 {
        self.read(0x6064, 0)
    }

    /// 0x6062.
    pub fn demand(&mut self) -> i64 {
        self.read(0x6062, 0)
    }

    /// From power-on to Operation enabled in `mode` at t = 1 ms (the first tick leaves Not ready
    /// to switch on): Shutdown, Switch on, Enable operation.
    #[track_caller]
    pub fn enable(&mut self, mode: i8) {
        self.at(1);
        self.set(0x6060, 0, i64::from(mode));
        self.cw(SHUTDOWN);
        self.cw(SWITCH_ON);
        self.cw(ENABLE);
        assert_eq!(self.sw() & 0x006F, 0x0027, "Operation enabled");
    }
}
