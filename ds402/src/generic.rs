//! Any CANopen description as a live node: the dictionary of an EDS, DCF, XDD or XDC with its defaults,
//! limits, access and PDO configuration, and a CiA 402 drive ([`crate::drive::Drive`]) behind each axis
//! whose objects the description has (CiA 402-2: 0x6040 and 0x6041 at 0x6000 + 0x800·axis).
//!
//! - A DCF's (or XDC's) `ParameterValue`s are the node's power-on values: they become the defaults the
//!   node resets to ([`power_on_values`]).
//! - Each drive gets a simulation record at `0x5FF0 + axis` when the description leaves that index
//!   free ([`SIM_BASE`]): the digital inputs a test forces (0x60FD bits) and the simulated switch
//!   positions, settable by SDO or RPDO like the X67 node's simulation inputs and not saved by 0x1010.
//! - A drive's fault is an EMCY with its 0x603F error code; the manufacturer bytes carry the axis
//!   (1-based).
//! - Before any of this, [`complete`] gives the description what a real device of it reports
//!   where the description gives no value (the identity and names of CiA 301, [`od::fill`]; the
//!   device type, supported modes and factory settings of a drive, [`crate::drive::fill`]) and says
//!   what it gave, one [`Event`] per entry. The CANopen node and the EtherCAT unit both start from
//!   it.
//!
//! [`GenericApp`] is the drives as one [`Device`]: the CANopen node (`canopen-node`) and the
//! EtherCAT unit (`ethercat-node`) run it alike.

use std::time::Instant;

use crate::drive::{Drive, DriveConfig, SimConfig};
use od::abort::AbortCode;
use od::device::DeviceDescription;
use od::dict::{Address, Dictionary};
use od::emcy::{DeviceError, EmcyCode};
use od::event::Event;
use od::hook::{Device, DeviceHook};
use od::object::{AccessType, Object, ObjectKind, PdoMapping, SubObject};
use od::types::DataType;
use od::value::Value;

/// First index of the drives' simulation records: axis `a` at `SIM_BASE + a`.
pub const SIM_BASE: u16 = 0x5FF0;

/// The entries of a simulation record (sub-index, name, type).
const SIM_ENTRIES: [(u8, &str, DataType); 5] = [
    (1, "Forced digital inputs", DataType::Unsigned32),
    (2, "Forced input levels", DataType::Unsigned32),
    (3, "Negative limit switch position", DataType::Integer32),
    (4, "Positive limit switch position", DataType::Integer32),
    (5, "Home switch position", DataType::Integer32),
];

/// The application of a generic node: its drives, if the description has any.
#[derive(Clone)]
pub struct GenericApp {
    drives: Vec<Drive>,
    /// The simulation record of each drive (its index), when the dictionary has room for it.
    sims: Vec<Option<u16>>,
    /// The forced 0x60FD bits and their levels, per drive (sub-indices 1 and 2).
    forced: Vec<(u32, u32)>,
    /// The simulated machine each drive was made with, which reset node returns to.
    power_on_sim: Vec<SimConfig>,
}

impl GenericApp {
    /// The drives of `dict` (see [`Drive::axes`]) with `config`, started at `now`. `dict` should
    /// already hold the simulation records ([`add_sim_records`]).
    pub fn new(dict: &Dictionary, config: &DriveConfig, now: Instant) -> GenericApp {
        let drives: Vec<Drive> = Drive::axes(dict)
            .into_iter()
            .filter_map(|axis| Drive::from_dictionary(dict, axis, config.clone(), now))
            .collect();
        let sims = drives
            .iter()
            .map(|d| {
                let index = SIM_BASE + u16::from(d.axis());
                dict.object(index)
                    .is_some_and(is_sim_record)
                    .then_some(index)
            })
            .collect();
        let forced = vec![(0, 0); drives.len()];
        let power_on_sim = drives.iter().map(|d| d.config().sim.clone()).collect();
        GenericApp {
            drives,
            sims,
            forced,
            power_on_sim,
        }
    }

    /// The drives, axis by axis.
    pub fn drives(&self) -> &[Drive] {
        &self.drives
    }

    /// The drives, to act on them from outside.
    pub fn drives_mut(&mut self) -> &mut [Drive] {
        &mut self.drives
    }

    /// The drive and simulation record owning `index`: (drive, true for the simulation record).
    fn owner(&self, index: u16) -> Option<(usize, bool)> {
        if let Some(k) = self.sims.iter().position(|s| *s == Some(index)) {
            return Some((k, true));
        }
        self.drives
            .iter()
            .position(|d| d.owns(index))
            .map(|k| (k, false))
    }

    /// Applies a simulation record's entry to its drive.
    fn sim_write(&mut self, k: usize, sub: u8, data: &[u8], now: Instant) -> Result<(), AbortCode> {
        let value = {
            let mut b = [0u8; 4];
            let n = data.len().min(4);
            b[..n].copy_from_slice(&data[..n]);
            u32::from_le_bytes(b)
        };
        let drive = &mut self.drives[k];
        match sub {
            1 | 2 => {
                let (mut mask, mut levels) = self.forced[k];
                if sub == 1 {
                    mask = value;
                } else {
                    levels = value;
                }
                self.forced[k] = (mask, levels);
                for bit in 0..32u8 {
                    let forced = mask & (1 << bit) != 0;
                    drive.set_input(now, bit, forced.then_some(levels & (1 << bit) != 0));
                }
            }
            3 => drive.sim_mut().negative_limit = Some(i64::from(value as i32)),
            4 => drive.sim_mut().positive_limit = Some(i64::from(value as i32)),
            5 => drive.sim_mut().home_switch = Some(i64::from(value as i32)),
            _ => return Err(AbortCode::NoSubIndex),
        }
        Ok(())
    }
}

impl DeviceHook for GenericApp {
    fn owns(&self, index: u16) -> bool {
        self.owner(index).is_some()
    }

    fn read(&self, at: Address, out: &mut [u8; 8]) -> Option<usize> {
        match self.owner(at.index)? {
            (k, false) => self.drives[k].read(at, out),
            // The dictionary holds what was written to a simulation record.
            (_, true) => None,
        }
    }

    fn check(&self, at: Address, data: &[u8]) -> Result<(), AbortCode> {
        match self.owner(at.index) {
            Some((k, false)) => self.drives[k].check(at, data),
            _ => Ok(()),
        }
    }

    fn write(&mut self, at: Address, data: &[u8], now: Instant) -> Result<(), AbortCode> {
        match self.owner(at.index) {
            Some((k, false)) => self.drives[k].write(at, data, now),
            Some((k, true)) => self.sim_write(k, at.sub, data, now),
            None => Ok(()),
        }
    }
}

impl Device for GenericApp {
    fn handle_timeout(&mut self, now: Instant) {
        for d in &mut self.drives {
            if d.poll_timeout().is_some_and(|t| t <= now) {
                d.handle_timeout(now);
            }
        }
    }

    fn poll_timeout(&self) -> Option<Instant> {
        self.drives.iter().filter_map(Drive::poll_timeout).min()
    }

    fn errors(&self, out: &mut Vec<DeviceError>) {
        for d in &self.drives {
            let code = d.error_code();
            if code != 0 {
                out.push(DeviceError {
                    code: EmcyCode(code),
                    info: [d.axis() + 1, 0, 0, 0, 0],
                });
            }
        }
    }

    /// The drives at power-on; the simulation records are back to their defaults, so no input stays
    /// forced and the switches are where the drives were made with them.
    fn reset(&mut self, now: Instant) {
        let power_on = self.power_on_sim.iter();
        for ((d, f), sim) in self.drives.iter_mut().zip(&mut self.forced).zip(power_on) {
            d.release_inputs();
            *f = (0, 0);
            *d.sim_mut() = sim.clone();
            d.reset(now);
        }
    }

    fn sync(&mut self, now: Instant) {
        for d in &mut self.drives {
            d.sync(now);
        }
    }
}

/// Whether `o` is a simulation record as [`add_sim_records`] makes it.
fn is_sim_record(o: &Object) -> bool {
    SIM_ENTRIES.iter().all(|(sub, name, t)| {
        o.subs
            .get(sub)
            .is_some_and(|s| s.name == *name && s.data_type == *t)
    })
}

/// Adds a simulation record at `0x5FF0 + axis` for every drive axis of `dict` whose index is free:
/// sub 1 the 0x60FD bits forced, sub 2 their levels, subs 3–5 the positions of the negative and
/// positive limit switches and the home switch (counts). Returns the indices added.
pub fn add_sim_records(dict: &mut Dictionary, sim: &SimConfig) -> Vec<u16> {
    let mut added = Vec::new();
    for axis in Drive::axes(dict) {
        let index = SIM_BASE + u16::from(axis);
        if dict.object(index).is_some() {
            continue;
        }
        let count = SubObject::new(
            "Highest sub-index supported",
            DataType::Unsigned8,
            AccessType::Ro,
        )
        .with_default(Value::Uint(SIM_ENTRIES.len() as u64));
        let mut object = Object::structured(
            index,
            format!("Drive simulation axis {}", axis + 1),
            ObjectKind::Record,
        )
        .with_sub(0, count);
        // Subs 3–5 start at the switch positions the drives are given (0 where there is none).
        let position = |sub: u8| match sub {
            3 => sim.negative_limit,
            4 => sim.positive_limit,
            5 => sim.home_switch,
            _ => None,
        };
        for (sub, name, data_type) in SIM_ENTRIES {
            let default = position(sub).map_or(Value::zero(data_type), |x| {
                Value::Int(x.clamp(i64::from(i32::MIN), i64::from(i32::MAX)))
            });
            let entry = SubObject::new(name, data_type, AccessType::Rw)
                .with_default(default)
                .with_pdo(PdoMapping::Rpdo);
            object = object.with_sub(sub, entry);
        }
        dict.insert(object);
        added.push(index);
    }
    added
}

/// Gives `desc` the values a real device of it reports where the description gives none, and the
/// factory settings its drives (made with `config`) run with where its values would stop them (see
/// [`od::fill::identity_and_names`], [`od::fill::pdo_cob_ids`], [`od::fill::pdo_mappings`] and
/// [`crate::drive::fill`]): each becomes the entry's default.
/// What changed, one event per entry, in index order.
pub fn complete(desc: &mut DeviceDescription, config: &DriveConfig) -> Vec<Event> {
    let mut events = od::fill::identity_and_names(desc);
    events.extend(od::fill::pdo_cob_ids(desc));
    events.extend(od::fill::pdo_mappings(desc));
    events.extend(crate::drive::fill(&mut desc.dictionary, config));
    events.sort_by_key(|e| e.address);
    events
}

/// Makes the current values of a DCF (its `ParameterValue`s, which the reader keeps as the entries'
/// values) the node's defaults, so that they are its power-on values and what a reset returns to. An
/// EDS has none: nothing changes.
pub fn power_on_values(desc: &mut DeviceDescription) {
    let node_id = desc.node_id().unwrap_or(0);
    for object in desc.dictionary.objects_mut() {
        for sub in object.subs.values_mut() {
            if sub.value_set {
                // `$NODEID+offset` stays relative to the node-ID.
                sub.default = sub.parameter(node_id).or(sub.default.take());
            }
        }
    }
}
