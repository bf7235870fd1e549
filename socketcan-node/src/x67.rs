//! The X67BC4321-10 CANopen bus controller with one or more X67SM2436 modules in function model "Ramp".
//!
//! - The dictionary is the fixture's (`fixtures/x67/X67SM2436.xdd`, compiled in). Module 1 sits at the
//!   fixture's indices; module `m` (0-based) at the same objects shifted by `0x300 · m` (0x2000–0x22FF,
//!   0x2300–0x25FF, …), with its two RPDO/TPDO pairs at PDO numbers `2m+1` and `2m+2`. PDOs 1–4 take the
//!   CiA 301 pre-defined COB-IDs (module 2 therefore uses TPDOs 0x380/0x480 + node-ID and RPDOs
//!   0x400/0x500 + node-ID); PDOs 5 and up start invalid (COB-ID 0x80000000) for the master to assign.
//! - Every register of a module is its manufacturer object: what the master writes goes to the module
//!   (refusals with the module's abort codes), what it reads comes from the module at that moment.
//! - Simulation inputs, one record per module at `0x5F00 + m`: sub 1 the levels of DI1–DI6 (bits 0–5),
//!   sub 2 the supply voltage in 0.1 V, sub 3 the module temperature in °C. They are RPDO-mappable and
//!   not saved by 0x1010.
//! - Time: the X2X Link cycle (default 1 ms, at least 250 µs: X67-18.13-01) is the rate at which the bus
//!   controller refreshes the input image (X67-18.14-01); each module runs its ramp generator on its
//!   own cycle from GeneralConfig01 (25/10/5 ms), taking over the cyclic outputs at each cycle
//!   (X67-18.14-02).
//! - Errors: each axis's error code (0x3000, 0x4200, 0x2300, 0xFFxx) is an EMCY whose manufacturer
//!   bytes are the module number (1-based) and the axis (1, 2).

use std::collections::HashMap;
use std::time::{Duration, Instant};

use ds402::x67::module::Module;
use ds402::x67::registers::{Access, RegType, Register};
use od::abort::AbortCode;
use od::dict::{Address, Dictionary};
use od::hook::DeviceHook;
use od::object::{AccessType, DefaultValue, Object, ObjectKind, PdoMapping, SubObject};
use od::types::DataType;
use od::value::Value;

use crate::node::pdo::{MapEntry, COB_INVALID, MAP_OFFSET, RPDO_COMM, TPDO_COMM};
use crate::node::{Device, DeviceError, EmcyCode};

/// The fixture the node's dictionary comes from.
pub const FIXTURE_XDD: &str = include_str!("../../fixtures/x67/X67SM2436.xdd");
/// The bus controller modelled: the -10 variant, which monitors the software limits (X67-18.11.1.17-05).
pub const BUS_CONTROLLER: &str = "X67BC4321-10";
/// Index stride between modules.
pub const MODULE_STRIDE: u16 = 0x300;
/// First index of the simulation-input records.
pub const SIM_BASE: u16 = 0x5F00;
/// Most modules one node hosts.
pub const MAX_MODULES: usize = 16;
/// Shortest X2X Link cycle (X67-18.13-01).
pub const MIN_X2X_CYCLE: Duration = Duration::from_micros(250);
/// Default X2X Link cycle.
pub const DEFAULT_X2X_CYCLE: Duration = Duration::from_millis(1);

/// Why a bus controller could not be set up.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum X67Error {
    /// Module count outside 1–16.
    #[error("{0} modules: the node hosts 1 to {MAX_MODULES}")]
    Modules(usize),
    /// X2X cycle below 250 µs.
    #[error("X2X cycle of {0} µs is below the 250 µs the Ramp model allows (data sheet 18.13)")]
    Cycle(u128),
    /// The compiled-in fixture did not load.
    #[error("the X67SM2436 description does not load: {0}")]
    Fixture(#[source] od::ParseError),
}

/// The node's dictionary for `modules` modules.
pub fn dictionary(modules: usize) -> Result<Dictionary, X67Error> {
    if !(1..=MAX_MODULES).contains(&modules) {
        return Err(X67Error::Modules(modules));
    }
    let mut dict = fixture_dictionary()?;
    let base: Vec<Object> = dict
        .objects()
        .filter(|o| (0x2000..0x2000 + MODULE_STRIDE).contains(&o.index))
        .cloned()
        .collect();
    let pdo_objects: Vec<Object> = [RPDO_COMM, RPDO_COMM + 1, TPDO_COMM, TPDO_COMM + 1]
        .into_iter()
        .flat_map(|c| [c, c + MAP_OFFSET])
        .filter_map(|i| dict.object(i).cloned())
        .collect();
    for m in 0..modules {
        let shift = MODULE_STRIDE * m as u16;
        if m > 0 {
            // Module m's registers are named as module 1's with `_Mm` appended (`InputStatus_M2`),
            // so that a description of the whole node names each of them once.
            let suffix = format!("_M{}", m + 1);
            for o in &base {
                let mut o = o.clone();
                o.index += shift;
                o.name.push_str(&suffix);
                if !o.kind.has_subs() {
                    if let Some(s) = o.subs.get_mut(&0) {
                        s.name.push_str(&suffix);
                    }
                }
                dict.insert(o);
            }
            for o in &pdo_objects {
                let mut o = o.clone();
                let kind = o.index & 0xFE00;
                let n = o.index & 0x1FF;
                o.index = kind + 2 * m as u16 + n;
                let pdo_number = u32::from(o.index & 0x1FF) + 1;
                match kind {
                    0x1400 | 0x1800 => {
                        let base_id: u32 = if kind == 0x1400 { 0x200 } else { 0x180 };
                        if let Some(s) = o.subs.get_mut(&1) {
                            s.default = Some(if pdo_number <= 4 {
                                DefaultValue {
                                    value: Value::Uint(u64::from(
                                        base_id + 0x100 * (pdo_number - 1),
                                    )),
                                    plus_node_id: true,
                                }
                            } else {
                                DefaultValue::plain(Value::Uint(u64::from(COB_INVALID)))
                            });
                        }
                    }
                    _ => {
                        for (sub, s) in o.subs.iter_mut() {
                            if *sub == 0 {
                                continue;
                            }
                            if let Some(DefaultValue {
                                value: Value::Uint(raw),
                                ..
                            }) = &mut s.default
                            {
                                let e = MapEntry::from_raw(*raw as u32);
                                if !e.is_dummy() {
                                    *raw += u64::from(shift) << 16;
                                }
                            }
                        }
                    }
                }
                dict.insert(o);
            }
        }
        dict.insert(sim_object(m));
    }
    Ok(dict)
}

/// The fixture's dictionary, read once per process.
/// The description of the node with `modules` modules, as it runs: the module's description (its
/// identity, file information and CAN parts) with the dictionary of [`dictionary`], every module's
/// registers and PDOs and the simulation inputs at 0x5F00 + m−1 included. Written as an EDS or XDD,
/// it lets a master name module 2's objects as it names module 1's.
pub fn description(modules: usize) -> Result<od::DeviceDescription, X67Error> {
    let mut desc =
        od::xdd::read(FIXTURE_XDD.as_bytes(), "X67SM2436.xdd").map_err(X67Error::Fixture)?;
    desc.dictionary = dictionary(modules)?;
    Ok(desc)
}

fn fixture_dictionary() -> Result<Dictionary, X67Error> {
    static FIXTURE: std::sync::OnceLock<Result<Dictionary, od::ParseError>> =
        std::sync::OnceLock::new();
    FIXTURE
        .get_or_init(|| {
            od::xdd::read(FIXTURE_XDD.as_bytes(), "X67SM2436.xdd").map(|d| d.dictionary)
        })
        .clone()
        .map_err(X67Error::Fixture)
}

/// Module `m`'s (0-based) simulation inputs, at 0x5F00 + m, named after the module (1-based).
fn sim_object(m: usize) -> Object {
    let index = SIM_BASE + m as u16;
    let entry = |name: &str, t: DataType, v: Value| {
        SubObject::new(name, t, AccessType::Rw)
            .with_default(v)
            .with_pdo(PdoMapping::Rpdo)
    };
    Object::structured(
        index,
        format!("Simulation inputs module {}", m + 1),
        ObjectKind::Record,
    )
    .with_sub(
        0,
        SubObject::new(
            "Highest sub-index supported",
            DataType::Unsigned8,
            AccessType::Ro,
        )
        .with_default(Value::Uint(3)),
    )
    .with_sub(
        1,
        entry(
            "Digital inputs DI1-DI6",
            DataType::Unsigned8,
            Value::Uint(0),
        )
        .with_limits(None, Some(Value::Uint(0x3F))),
    )
    .with_sub(
        2,
        entry(
            "Supply voltage [0.1 V]",
            DataType::Unsigned16,
            Value::Uint(240),
        ),
    )
    .with_sub(
        3,
        entry(
            "Module temperature [degC]",
            DataType::Integer8,
            Value::Int(25),
        ),
    )
}

/// What an application object is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Slot {
    Register(usize, Register),
    Sim(usize),
}

/// The bus controller and its modules: the node's [`Device`].
#[derive(Clone)]
pub struct BusController {
    modules: Vec<Module>,
    slots: HashMap<u16, Slot>,
    x2x: Duration,
    x2x_next: Instant,
    inputs: Vec<u8>,
}

impl BusController {
    /// `modules` modules at power-on behind the objects of `dict` (from [`dictionary`]), the X2X cycle
    /// `x2x`, time starting at `now`.
    pub fn new(
        dict: &Dictionary,
        modules: usize,
        x2x: Duration,
        now: Instant,
    ) -> Result<BusController, X67Error> {
        if !(1..=MAX_MODULES).contains(&modules) {
            return Err(X67Error::Modules(modules));
        }
        if x2x < MIN_X2X_CYCLE {
            return Err(X67Error::Cycle(x2x.as_micros()));
        }
        let mut slots = HashMap::new();
        let end = 0x2000 + MODULE_STRIDE * modules as u16;
        for o in dict.objects().filter(|o| (0x2000..end).contains(&o.index)) {
            // Module m's objects are module 1's at m strides on (their names carry `_Mm`): the
            // register is the one module 1's object at that place names.
            let m = usize::from((o.index - 0x2000) / MODULE_STRIDE);
            let first = dict.object(o.index - MODULE_STRIDE * m as u16);
            if let Some(reg) = first.and_then(|f| Register::from_name(&f.name)) {
                slots.insert(o.index, Slot::Register(m, reg));
            }
        }
        for m in 0..modules {
            slots.insert(SIM_BASE + m as u16, Slot::Sim(m));
        }
        let mut bc = BusController {
            modules: Vec::new(),
            slots,
            x2x,
            x2x_next: now,
            inputs: vec![0; modules],
        };
        bc.power_on(modules, now);
        Ok(bc)
    }

    fn power_on(&mut self, modules: usize, now: Instant) {
        self.modules = (0..modules)
            .map(|_| {
                let mut m = Module::new();
                m.start(now);
                m
            })
            .collect();
        self.x2x_next = now + self.x2x;
        self.inputs = vec![0; modules];
    }

    /// The modules.
    pub fn modules(&self) -> &[Module] {
        &self.modules
    }

    /// A module, to act on it from outside (inputs, supply, temperature, motor faults).
    pub fn module_mut(&mut self, m: usize) -> Option<&mut Module> {
        self.modules.get_mut(m)
    }

    /// The X2X Link cycle.
    pub fn x2x_cycle(&self) -> Duration {
        self.x2x
    }

    /// Sets the digital inputs of module `m` (bits 0–5 = DI1–DI6).
    pub fn set_inputs(&mut self, m: usize, bits: u8) {
        let Some(module) = self.modules.get_mut(m) else {
            return;
        };
        for k in 0..6 {
            module.set_input(k + 1, bits & (1 << k) != 0);
        }
        self.inputs[m] = bits & 0x3F;
    }
}

fn decode(ty: RegType, data: &[u8]) -> Option<i64> {
    Some(match (ty, data) {
        (RegType::Dint, [a, b, c, d]) => i64::from(i32::from_le_bytes([*a, *b, *c, *d])),
        (RegType::Uint, [a, b]) => i64::from(u16::from_le_bytes([*a, *b])),
        (RegType::Int, [a, b]) => i64::from(i16::from_le_bytes([*a, *b])),
        (RegType::Sint, [a]) => i64::from(*a as i8),
        (RegType::Usint, [a]) => i64::from(*a),
        _ => return None,
    })
}

impl DeviceHook for BusController {
    fn owns(&self, index: u16) -> bool {
        self.slots.contains_key(&index)
    }

    fn read(&self, at: Address, out: &mut [u8; 8]) -> Option<usize> {
        let (index, sub) = (at.index, at.sub);
        match *self.slots.get(&index)? {
            Slot::Register(m, reg) if sub == 0 => {
                let info = reg.info();
                if matches!(info.access, Access::Config | Access::CyclicOut) {
                    return None;
                }
                let v = self.modules[m].read(reg);
                let n = info.ty.size();
                out[..n].copy_from_slice(&v.to_le_bytes()[..n]);
                Some(n)
            }
            _ => None,
        }
    }

    /// The modules take a write at the X2X cycle the node has run them up to (`now` is past
    /// their last cycle and before the next).
    fn write(&mut self, at: Address, data: &[u8], _now: Instant) -> Result<(), AbortCode> {
        let (index, sub) = (at.index, at.sub);
        match self.slots.get(&index).copied() {
            Some(Slot::Register(m, reg)) if sub == 0 => {
                let v = decode(reg.info().ty, data).ok_or(AbortCode::LengthMismatch)?;
                self.modules[m]
                    .write(reg, v)
                    .map_err(|e| AbortCode::from(e.abort_code()))
            }
            Some(Slot::Sim(m)) => {
                let module = &mut self.modules[m];
                match (sub, data) {
                    (1, [bits]) => {
                        self.set_inputs(m, *bits);
                        Ok(())
                    }
                    (2, [a, b]) => {
                        module.set_supply(f64::from(u16::from_le_bytes([*a, *b])) / 10.0);
                        Ok(())
                    }
                    (3, [t]) => {
                        module.set_temperature(f64::from(*t as i8));
                        Ok(())
                    }
                    _ => Err(AbortCode::NoSubIndex),
                }
            }
            _ => Ok(()),
        }
    }
}

impl Device for BusController {
    fn handle_timeout(&mut self, now: Instant) {
        for module in &mut self.modules {
            module.handle_timeout(now);
            let _ = module.take_diagnostics();
        }
        while self.x2x_next <= now {
            self.x2x_next += self.x2x;
        }
    }

    fn poll_timeout(&self) -> Option<Instant> {
        Some(self.x2x_next)
    }

    fn errors(&self, out: &mut Vec<DeviceError>) {
        for (m, module) in self.modules.iter().enumerate() {
            for a in 0..2 {
                let code = EmcyCode(module.error_code(a));
                if code != EmcyCode::NO_ERROR {
                    out.push(DeviceError {
                        code,
                        info: [m as u8 + 1, a as u8 + 1, 0, 0, 0],
                    });
                }
            }
        }
    }

    fn reset(&mut self, now: Instant) {
        let n = self.modules.len();
        self.power_on(n, now);
    }
}
