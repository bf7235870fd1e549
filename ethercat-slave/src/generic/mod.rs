//! Any ESI's device as a unit of an emulated chain ([`crate::unit`]): its dictionary, CoE server,
//! SyncManagers, AL checks, SII, PDOs and modules from the ESI, and behind every axis whose 0x6040
//! and 0x6041 the dictionary has (CiA 402-2: axis *a* at 0x6000 + 0x800·*a*) a CiA 402 drive
//! ([`ds402::drive::Drive`], the same device the CANopen node runs:
//! [`ds402::generic::GenericApp`], with its simulation record at 0x5FF0 + axis). A device
//! without CiA 402 axes but with drive channels of ETG.5001 MDP 742 (the servo and stepper
//! terminals' "DRV" objects at 0x6010/0x7010 + 0x100·channel) has the same drive behind each
//! channel, reached through a mapping from the channel's objects to the drive's ([`mdp`]; channel
//! *n* is drive axis *n*, its simulation record at 0x5FF0 + *n*). A device without drive axes is
//! the dictionary alone: its process data writes and reads its entries.
//!
//! - [`Template`] is one ESI device made ready once ([`Template::new`]): the modules in its slots
//!   (ETG.2001 `Slots`/`Modules`, given or the slots' defaults) with their PDOs and objects moved by
//!   the slot's increments, the dictionary completed with the power-on PDO configuration
//!   ([`pdo`]), the AL checks of its `Sm` and `Dc` elements, its mailbox size and CoE abilities,
//!   and its SII image (in an EEPROM of `Eeprom/ByteSize`, or of the next power of two that holds
//!   the image where that is too small).
//! - Before its units, a template's dictionary gets what a real device of the ESI reports where the
//!   ESI gives no value ([`ds402::generic::complete`], as the CANopen node does): 0x1018:01–03
//!   the ESI's identity, as the SII has it (a value of the ESI's object that contradicts it gives
//!   way to it, since a master compares the two; said as an adjustment), the names 0x1008 and
//!   0x100A from its `Type` and revision, a drive's device type, supported modes and factory
//!   settings; each change one event ([`Template::events`]).
//! - [`GenericUnit`] is one unit of a template ([`Template::unit`]): its own dictionary (the
//!   serial number in 0x1018:04), drives and EtherCAT rules, and where the ESI offers FoE
//!   (`Mailbox/FoE`) an FoE server with a file store of its own ([`crate::foe`]; firmware in
//!   Bootstrap only where the ESI gives the bootstrap mailbox, `Eeprom/BootStrap`); [`chain`]
//!   puts units of several templates in one [`NodeChain`].
//!
//! What a unit adds to the dictionary's own checks of an SDO download (ETG.1000.6 §5.6.2, the rules
//! of a CoE slave; the codes are the CiA 301 abort codes):
//!
//! - an entry with ESI `WriteRestrictions` is written only in those states (0x08000022);
//! - the PDO configuration (0x1C12, 0x1C13, 0x1600+, 0x1A00+) as [`pdo`] says;
//! - a drive's own rules (`ds402::drive`).
//!
//! What the drives hear of the EtherCAT state machine:
//!
//! - their targets and control words through the process data in Op; a synchronisation event
//!   ([`Drive::sync`](ds402::drive::Drive::sync): the cyclic synchronous modes take their targets) at
//!   each SYNC0 event, or at each new output image without SYNC0 and before SYNC0's first pulse
//!   (its start time, which a master sets some way ahead: SOEM 100 ms); with SYNC0 the drives
//!   interpolate each target over the SYNC0 cycle (whatever 0x60C2 says: the set-points come at
//!   that cycle), which 0x1C32:02 and 0x1C33:02 then show;
//! - leaving Op (the master's request, the SyncManager watchdog, a lost link) is the end of the
//!   connection (CiA 402-2 0x6007 abort connection option code, taken from the dictionary, 2 where it
//!   has none): 0 nothing, 1 a fault with error code 0x8100 (communication), 2 disable voltage, 3
//!   quick stop.

pub mod mdp;
pub mod pdo;

use std::sync::Arc;
use std::time::{Duration, Instant};

use ds402::drive::DriveConfig;
use ds402::generic::{add_sim_records, complete, GenericApp};
use od::abort::AbortCode;
use od::coe::server::CoeServer;
use od::device::{DeviceDescription, EthercatInfo, Module};
use od::dict::{Address, Dictionary};
use od::event::Event;
use od::hook::{self, Device, DeviceHook, Objects, ProcessImage};
use od::object::{EcatStates, Object, ObjectKind};
use od::sdo::server::ServerConfig;
use od::types::DataType;

use crate::esc::al::{AlConfig, AlState, AlStatusCode};
use crate::esc::Esc;
use crate::foe::{FileStore, FoeConfig, FoeServer};
use crate::unit::{Model, Unit, UnitChain};

use mdp::Channels;
use pdo::Pdos;

/// The mailbox size taken where the ESI gives none.
const DEFAULT_MAILBOX: usize = 128;
/// The error code of the fault a drive raises when the connection ends with 0x6007 = 1 (CiA 301
/// emergency codes: 0x8100 communication).
pub const CONNECTION_FAULT: u16 = 0x8100;

/// A chain of units made from ESIs.
pub type NodeChain = UnitChain<GenericUnit>;

/// Why a device cannot be emulated as its ESI describes it.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TemplateError {
    /// The description has no EtherCAT part (not an ESI).
    #[error("{device}: no EtherCAT part (not an ESI device)")]
    NoEthercat {
        /// The device.
        device: String,
    },
    /// A module was asked for that the ESI does not describe.
    #[error("{device}: no module {wanted:?} in the ESI (it has: {available})")]
    NoSuchModule {
        /// The device.
        device: String,
        /// What was asked for.
        wanted: String,
        /// The modules of the ESI.
        available: String,
    },
    /// More modules than the device has slots, or modules for a device without slots.
    #[error("{device}: {given} module(s) given, but the device has {slots} slot(s)")]
    TooManyModules {
        /// The device.
        device: String,
        /// Modules given.
        given: usize,
        /// Slots the device has.
        slots: usize,
    },
    /// A module that its slot does not take.
    #[error("{device}: slot {slot} ({name}) does not take module {ident:#010x}; it takes {takes}")]
    ModuleNotInSlot {
        /// The device.
        device: String,
        /// The slot (1 for the first).
        slot: usize,
        /// The slot's name.
        name: String,
        /// The module.
        ident: u32,
        /// The modules the slot takes.
        takes: String,
    },
    /// The power-on PDO configuration gives no process image.
    #[error(
        "{device}: the power-on PDO assignment gives no process image (AL status code {code})"
    )]
    Pdos {
        /// The device.
        device: String,
        /// What Pre-Op → Safe-Op would answer.
        code: AlStatusCode,
    },
    /// The SII image could not be written.
    #[error("{device}: {source}")]
    Sii {
        /// The device.
        device: String,
        /// Why.
        source: od::sii::SiiError,
    },
}

/// The name a device goes by in messages: its type name, else its product name.
pub fn device_name(desc: &DeviceDescription) -> String {
    let name = desc.identity.order_code.trim();
    if name.is_empty() {
        desc.identity.product_name.trim().to_string()
    } else {
        name.to_string()
    }
}

/// One ESI device made ready to run as units. See the [module documentation](self).
#[derive(Debug, Clone)]
pub struct Template {
    desc: DeviceDescription,
    pdos: Arc<Pdos>,
    /// The dictionary at power-on, shared by the units for its structure and flags.
    meta: Arc<Dictionary>,
    al: AlConfig,
    mailbox_in: usize,
    segmented: bool,
    outputs_at: Option<u16>,
    inputs_at: Option<u16>,
    modules: Vec<(usize, u32)>,
    /// The MDP 742 drive channels, on a device without CiA 402 axes.
    channels: Option<Arc<Channels>>,
    events: Vec<Event>,
    /// FoE, where the ESI offers it (`Mailbox/FoE`).
    foe: Option<FoeConfig>,
}

impl Template {
    /// `desc` (an ESI device) with `modules` in its slots, one for each slot from the first: a
    /// module ident (`0x10b00100`, `#x10b00100` or decimal) or type name, or `none` for an empty
    /// slot; `None` puts each slot's default module in it (ETG.2001 `ModuleIdent@Default`). Its
    /// drives are servos ([`Template::for_drives`] for others).
    pub fn new(
        desc: DeviceDescription,
        modules: Option<&[String]>,
    ) -> Result<Template, TemplateError> {
        Template::for_drives(desc, modules, &DriveConfig::default())
    }

    /// [`Template::new`] for drives made as `config` says (its motor: the device type and the modes
    /// the device reports). The units should be made with the same motor ([`Template::unit`]).
    pub fn for_drives(
        mut desc: DeviceDescription,
        modules: Option<&[String]>,
        config: &DriveConfig,
    ) -> Result<Template, TemplateError> {
        let device = device_name(&desc);
        let ec = desc
            .ethercat
            .clone()
            .ok_or_else(|| TemplateError::NoEthercat {
                device: device.clone(),
            })?;
        let placed = place_modules(&device, &ec, modules)?;
        let list: Vec<(usize, &Module)> = placed.iter().map(|(s, m)| (*s, m)).collect();
        add_module_objects(&mut desc.dictionary, &ec, &list);
        let pdos = Pdos::new(&ec, &list);
        Pdos::standard_types(&mut desc.dictionary);
        pdos.complete(&mut desc.dictionary);
        set_module_lists(&mut desc.dictionary, &list);
        add_sm_types(&mut desc.dictionary, &ec);
        // What a real device of the ESI reports where the ESI gives no value (0x1018 the SII's
        // identity, the names, a drive's device type, modes and factory settings), for drives that
        // take SYNC0 as their SYNC, as the units' do.
        let drives = DriveConfig {
            sync_clock: true,
            ..config.clone()
        };
        let events = complete(&mut desc, &drives);
        add_sim_records(&mut desc.dictionary, &ds402::drive::SimConfig::default());
        let channels = Channels::of(&desc.dictionary);
        if let Some(c) = &channels {
            // The channels' drives have their simulation records too, where the index is free.
            let drives = channel_drives(c, &desc.dictionary);
            for &n in c.channels() {
                let index = ds402::generic::SIM_BASE + u16::from(n);
                if let (Some(o), None) = (drives.object(index), desc.dictionary.object(index)) {
                    desc.dictionary.insert(o.clone());
                }
            }
        }
        pdos.images(&desc.dictionary)
            .map_err(|code| TemplateError::Pdos {
                device: device.clone(),
                code,
            })?;
        // An SII image larger than the ESI's EEPROM (`Eeprom/ByteSize`; a PDO category per PDO of
        // a drive with many) gets an EEPROM of the next power of two that holds it.
        if let Err(od::sii::SiiError::TooLarge { need, .. }) = od::sii::write(&desc, 0) {
            let ec = desc.ethercat.get_or_insert_with(Default::default);
            ec.eeprom.get_or_insert_with(Default::default).byte_size =
                need.next_power_of_two().min(1 << 20) as u32;
        }
        // An image the SII cannot hold otherwise (more strings than an index byte names) is
        // refused here, before any unit.
        od::sii::write(&desc, 0).map_err(|source| TemplateError::Sii {
            device: device.clone(),
            source,
        })?;
        let mut al = AlConfig::from_description(&desc);
        // ETG.1000.6 §6.4.1.4: SYNC0 on a device whose ESI assigns it in no DC mode is refused.
        al.no_sync0 = !ec
            .op_modes
            .iter()
            .any(|m| (m.assign_activate >> 8) & 0x02 != 0);
        // 0x1C32:05, the minimum cycle time (ETG.1020), bounds the SYNC0 cycle from below.
        let min_cycle = desc
            .dictionary
            .read_value(0x1C32, 5)
            .ok()
            .and_then(|v| v.as_i128())
            .and_then(|v| u32::try_from(v).ok())
            .filter(|v| *v > 0);
        al.sync0_cycle = min_cycle.map(|m| (m, u32::MAX));
        let sm = |kind: &str| ec.sync_managers.iter().find(|s| s.kind == kind);
        let mailbox_in = sm("MBoxIn")
            .and_then(|s| s.default_size.or(s.max_size))
            .map_or(DEFAULT_MAILBOX, usize::from);
        let segmented = ec
            .mailbox
            .as_ref()
            .and_then(|m| m.coe)
            .is_none_or(|c| c.segmented_sdo);
        // FoE where the ESI offers it; firmware goes in Bootstrap where the device has it.
        let foe = ec.mailbox.as_ref().filter(|m| m.foe).map(|_| FoeConfig {
            boot: al.boot_mailbox.is_some(),
            ..FoeConfig::default()
        });
        Ok(Template {
            foe,
            meta: Arc::new(desc.dictionary.clone()),
            pdos: Arc::new(pdos),
            al,
            mailbox_in,
            segmented,
            outputs_at: sm("Outputs").map(|s| s.start_address),
            inputs_at: sm("Inputs").map(|s| s.start_address),
            modules: placed.iter().map(|(s, m)| (*s, m.ident)).collect(),
            channels: channels.map(Arc::new),
            desc,
            events,
        })
    }

    /// What the ESI was given that it does not say itself ([`complete`]), in index order.
    pub fn events(&self) -> &[Event] {
        &self.events
    }

    /// The description (its dictionary as the units start with it).
    pub fn description(&self) -> &DeviceDescription {
        &self.desc
    }

    /// The device's name.
    pub fn name(&self) -> String {
        device_name(&self.desc)
    }

    /// The modules in the slots: (slot from 0, module ident).
    pub fn modules(&self) -> &[(usize, u32)] {
        &self.modules
    }

    /// The process images at power-on (outputs, inputs).
    pub fn images(&self) -> (ProcessImage, ProcessImage) {
        self.pdos.images(&self.desc.dictionary).unwrap_or_default()
    }

    /// The drive axes of the device: its CiA 402 axes, or its MDP 742 channels.
    pub fn axes(&self) -> Vec<u8> {
        match &self.channels {
            Some(c) => c.channels().to_vec(),
            None => ds402::drive::Drive::axes(&self.desc.dictionary),
        }
    }

    /// The FoE configuration of the units, where the ESI offers FoE.
    pub fn foe(&self) -> Option<&FoeConfig> {
        self.foe.as_ref()
    }

    /// The units serve FoE as `config` says, where the ESI offers it ([`FoeConfig::boot`] stays
    /// what the ESI says: whether the device has a Bootstrap state).
    pub fn set_foe(&mut self, config: &FoeConfig) {
        if let Some(foe) = &mut self.foe {
            *foe = FoeConfig {
                boot: foe.boot,
                ..config.clone()
            };
        }
    }

    /// The MDP 742 drive channels, on a device that has them (and no CiA 402 axis).
    pub fn channels(&self) -> Option<&Channels> {
        self.channels.as_deref()
    }

    /// The PDOs of the device and of the modules in its slots, and what a master may change of them.
    pub fn pdos(&self) -> &Pdos {
        &self.pdos
    }

    /// A unit of this device with serial number `serial` (SII and 0x1018:04), its drives running
    /// as `config` says, powered on at `now`: its ESC and the unit behind it.
    pub fn unit(
        &self,
        serial: u32,
        config: &DriveConfig,
        now: Instant,
    ) -> Result<(Esc, Unit<GenericUnit>), TemplateError> {
        // The ESC has the FMMUs and SyncManagers of the ESI (ETG.2000 `Fmmu`, `Sm`).
        let mut esc = Esc::for_device(&self.desc);
        esc.sii = od::sii::write(&self.desc, serial).map_err(|source| TemplateError::Sii {
            device: self.name(),
            source,
        })?;
        esc.load_sii_configuration();
        esc.al = self.al.clone();
        let mut dict = self.desc.dictionary.clone();
        // 0x1018:04 is UNSIGNED32 where a dictionary has it; one without keeps what it has.
        let _ = dict.store(0x1018, 4, &serial.to_le_bytes());
        // EtherCAT's SYNC0 (or the output image's SyncManager event) is the drives' SYNC: their
        // cyclic modes need no 0x60C2.
        let config = DriveConfig {
            sync_clock: true,
            ..config.clone()
        };
        let app = match &self.channels {
            Some(c) => GenericApp::new(&channel_drives(c, &dict), &config, now),
            None => GenericApp::new(&dict, &config, now),
        };
        let model = GenericUnit {
            dict,
            hook: UnitHook {
                app,
                channels: self.channels.clone(),
                pdos: self.pdos.clone(),
                meta: self.meta.clone(),
                state: AlState::Init,
                span: tracing::info_span!("unit", serial),
            },
        };
        let coe = CoeServer::new(ServerConfig::default(), self.mailbox_in)
            .with_segmented_transfer(self.segmented);
        let mut unit = Unit::new(model, coe, self.outputs_at, self.inputs_at);
        if let Some(config) = &self.foe {
            let store = FileStore::new(config.max_file, config.max_store);
            unit = unit.with_foe(FoeServer::new(config.clone(), store));
        }
        Ok((esc, unit))
    }
}

/// The CiA 402 dictionary of the drives behind `channels` of `dict`, with their simulation records.
fn channel_drives(channels: &Channels, dict: &Dictionary) -> Dictionary {
    let mut drives = channels.dictionary(dict);
    add_sim_records(&mut drives, &ds402::drive::SimConfig::default());
    drives
}

/// A chain of `units` (each a template and how many units of it, in chain order), serial numbers
/// 1… by position, drives as `config` says, all in Init at `now`, their process-data cycle every
/// `cycle`.
pub fn chain(
    units: &[(&Template, usize)],
    config: &DriveConfig,
    cycle: Duration,
    now: Instant,
) -> Result<NodeChain, TemplateError> {
    let mut list = Vec::new();
    for (template, n) in units {
        for _ in 0..*n {
            let serial = list.len() as u32 + 1;
            list.push(template.unit(serial, config, now)?);
        }
    }
    Ok(UnitChain::from_units(list, cycle, now))
}

/// The modules `asked` for (or the defaults) in the device's slots, numbered from 0.
fn place_modules(
    device: &str,
    ec: &EthercatInfo,
    asked: Option<&[String]>,
) -> Result<Vec<(usize, Module)>, TemplateError> {
    // One place per slot instance, in the ESI's order.
    let places: Vec<&od::device::Slot> = ec
        .slots
        .iter()
        .flat_map(|s| s.slots.iter())
        .flat_map(|slot| std::iter::repeat_n(slot, slot.max_instances.max(1) as usize))
        .collect();
    let find = |wanted: &str| -> Result<Option<Module>, TemplateError> {
        let w = wanted.trim();
        if w.eq_ignore_ascii_case("none") || w.is_empty() {
            return Ok(None);
        }
        let ident = parse_number(w);
        ec.modules
            .iter()
            .find(|m| Some(m.ident) == ident || m.type_name.trim().eq_ignore_ascii_case(w))
            .cloned()
            .map(Some)
            .ok_or_else(|| TemplateError::NoSuchModule {
                device: device.to_string(),
                wanted: wanted.to_string(),
                available: if ec.modules.is_empty() {
                    "none".into()
                } else {
                    ec.modules
                        .iter()
                        .map(|m| format!("{:#010x} {}", m.ident, m.type_name))
                        .collect::<Vec<_>>()
                        .join(", ")
                },
            })
    };
    let chosen: Vec<Option<Module>> = match asked {
        Some(list) => {
            if list.len() > places.len() {
                return Err(TemplateError::TooManyModules {
                    device: device.to_string(),
                    given: list.len(),
                    slots: places.len(),
                });
            }
            list.iter().map(|w| find(w)).collect::<Result<_, _>>()?
        }
        None => places
            .iter()
            .map(|slot| {
                let default = slot
                    .module_idents
                    .iter()
                    .find(|m| m.default.is_some_and(|d| d != 0))
                    .map(|m| m.ident);
                default.and_then(|i| ec.modules.iter().find(|m| m.ident == i).cloned())
            })
            .collect(),
    };
    let mut out = Vec::new();
    for (k, module) in chosen.into_iter().enumerate() {
        let Some(module) = module else { continue };
        let slot = places[k];
        let takes = &slot.module_idents;
        if !takes.is_empty() && !takes.iter().any(|m| m.ident == module.ident) {
            return Err(TemplateError::ModuleNotInSlot {
                device: device.to_string(),
                slot: k + 1,
                name: slot.name.clone(),
                ident: module.ident,
                takes: takes
                    .iter()
                    .map(|m| format!("{:#010x}", m.ident))
                    .collect::<Vec<_>>()
                    .join(", "),
            });
        }
        out.push((k, module));
    }
    Ok(out)
}

/// A number as ESI and command lines write it: `0x…`, `#x…` or decimal.
pub fn parse_number(text: &str) -> Option<u32> {
    let t = text.trim();
    let hex = t
        .strip_prefix("0x")
        .or_else(|| t.strip_prefix("0X"))
        .or_else(|| t.strip_prefix("#x"))
        .or_else(|| t.strip_prefix("#X"));
    match hex {
        Some(h) => u32::from_str_radix(h, 16).ok(),
        None => t.parse().ok(),
    }
}

/// The objects of each module's dictionary the device's lacks, moved by the slot's index increment
/// when they are in the profile area 0x6000–0xAFFF (ETG.5001: a slot's objects follow its
/// `SlotIndexIncrement`).
fn add_module_objects(dict: &mut Dictionary, ec: &EthercatInfo, modules: &[(usize, &Module)]) {
    let slots = ec.slots.as_ref();
    for &(slot, module) in modules {
        let inc = slots
            .and_then(|s| s.slots.get(slot))
            .and_then(|s| s.slot_index_increment)
            .or(slots.and_then(|s| s.slot_index_increment))
            .unwrap_or(0);
        for object in module.dictionary.objects() {
            let mut object = object.clone();
            if (0x6000..0xB000).contains(&object.index) {
                object.index = (u32::from(object.index) + inc * slot as u32) as u16;
            }
            if dict.object(object.index).is_none() {
                dict.insert(object);
            }
        }
    }
}

/// The SyncManager communication types (ETG.1000.6 §5.6.7.4, 0x1C00: 1 mailbox out, 2 mailbox in,
/// 3 process data outputs, 4 process data inputs, 0 unused) of a dictionary with a PDO assignment:
/// added (read-only) where it lacks them, set where the ESI gives them no values. Masters read them
/// before the assignment (SOEM's `ecx_readPDOmap`).
fn add_sm_types(dict: &mut Dictionary, ec: &EthercatInfo) {
    if dict.object(pdo::RX_ASSIGN).is_none() && dict.object(pdo::TX_ASSIGN).is_none() {
        return;
    }
    let types: Vec<u32> = ec
        .sync_managers
        .iter()
        .take(32)
        .map(|s| match s.kind.as_str() {
            "MBoxOut" => 1,
            "MBoxIn" => 2,
            "Outputs" => 3,
            "Inputs" => 4,
            _ => 0,
        })
        .collect();
    let empty = match dict.object(0x1C00) {
        None => {
            dict.insert(Object::structured(
                0x1C00,
                "Sync manager type",
                ObjectKind::Array,
            ));
            true
        }
        Some(o) => o.sub(0).is_none_or(pdo::no_default),
    };
    if empty {
        pdo::set_values(dict, 0x1C00, DataType::Unsigned8, &types);
    }
}

/// The configured and detected module lists (ETG.5001: 0xF030, 0xF050) where the dictionary has
/// them: the module idents slot by slot.
fn set_module_lists(dict: &mut Dictionary, modules: &[(usize, &Module)]) {
    if modules.is_empty() {
        return;
    }
    let count = modules.iter().map(|(s, _)| s + 1).max().unwrap_or(0);
    for index in [0xF030, 0xF050] {
        if dict.object(index).is_none() {
            continue;
        }
        for &(slot, m) in modules {
            let _ = dict.store(index, slot as u8 + 1, &m.ident.to_le_bytes());
        }
        let _ = dict.store(index, 0, &[count.min(255) as u8]);
    }
}

/// The device hook of a unit: its drives, and the EtherCAT rules of its dictionary.
#[derive(Clone)]
struct UnitHook {
    app: GenericApp,
    /// The MDP 742 channels the drives are behind (the drives' own objects are then in a
    /// dictionary of their own).
    channels: Option<Arc<Channels>>,
    pdos: Arc<Pdos>,
    meta: Arc<Dictionary>,
    state: AlState,
    /// What the unit's drives log is said of it (`unit{serial=3}: axis 0: …`).
    span: tracing::Span,
}

impl UnitHook {
    /// Whether `index` is the simulation record of a drive behind an MDP 742 channel (the same
    /// index in both dictionaries).
    fn channel_sim(&self, index: u16) -> bool {
        let base = ds402::generic::SIM_BASE;
        (base..base + u16::from(mdp::MAX_CHANNELS)).contains(&index) && self.app.owns(index)
    }

    fn ecat_state(&self) -> Option<EcatStates> {
        match self.state {
            AlState::PreOp => Some(EcatStates::PREOP),
            AlState::SafeOp => Some(EcatStates::SAFEOP),
            AlState::Op => Some(EcatStates::OP),
            _ => None,
        }
    }
}

impl DeviceHook for UnitHook {
    fn owns(&self, _: u16) -> bool {
        // Every download passes the EtherCAT rules; reads are the drives' where they own the object.
        true
    }

    fn read(&self, at: Address, out: &mut [u8; 8]) -> Option<usize> {
        if let Some(c) = &self.channels {
            if let Some(drive) = c.drive_address(at) {
                let mut buf = [0u8; 8];
                let n = self.app.read(drive, &mut buf)?;
                let value = c.from_drive(at, &buf[..n])?;
                let n = value.len().min(8);
                out[..n].copy_from_slice(&value[..n]);
                return Some(n);
            }
            return if self.channel_sim(at.index) {
                self.app.read(at, out)
            } else {
                None
            };
        }
        if self.app.owns(at.index) {
            self.app.read(at, out)
        } else {
            None
        }
    }

    fn check(&self, at: Address, data: &[u8]) -> Result<(), AbortCode> {
        // ETG.2000 `WriteRestrictions`: the states in which an SDO may write the entry.
        if let Ok(entry) = self.meta.entry(at.index, at.sub) {
            if let Some(states) = entry.access.write_states {
                if !self.ecat_state().is_some_and(|s| states.contains(s)) {
                    return Err(AbortCode::DeviceState);
                }
            }
        }
        self.pdos
            .check(&self.meta, at, data, self.state == AlState::PreOp)?;
        if let Some(c) = &self.channels {
            return match c.to_drive(at, data) {
                Some((drive, value)) => self.app.check(drive, &value),
                None if self.channel_sim(at.index) => self.app.check(at, data),
                None => Ok(()),
            };
        }
        if self.app.owns(at.index) {
            self.app.check(at, data)
        } else {
            Ok(())
        }
    }

    fn write(&mut self, at: Address, data: &[u8], now: Instant) -> Result<(), AbortCode> {
        let _unit = self.span.clone().entered();
        if let Some(c) = &self.channels {
            return match c.to_drive(at, data) {
                Some((drive, value)) => self.app.write(drive, &value, now),
                None if self.channel_sim(at.index) => self.app.write(at, data, now),
                None => Ok(()),
            };
        }
        if self.app.owns(at.index) {
            self.app.write(at, data, now)
        } else {
            Ok(())
        }
    }
}

/// The drives of the unit ([`GenericApp`]), each call in the unit's span.
impl Device for UnitHook {
    fn handle_timeout(&mut self, now: Instant) {
        let _unit = self.span.clone().entered();
        self.app.handle_timeout(now);
    }

    fn poll_timeout(&self) -> Option<Instant> {
        self.app.poll_timeout()
    }

    fn errors(&self, out: &mut Vec<od::emcy::DeviceError>) {
        self.app.errors(out);
    }

    fn reset(&mut self, now: Instant) {
        let _unit = self.span.clone().entered();
        self.app.reset(now);
    }

    fn sync(&mut self, now: Instant) {
        let _unit = self.span.clone().entered();
        self.app.sync(now);
    }
}

/// One unit of an ESI device: its dictionary with the drives and the EtherCAT rules behind it.
#[derive(Clone)]
pub struct GenericUnit {
    dict: Dictionary,
    hook: UnitHook,
}

impl Objects for GenericUnit {
    fn split(&mut self) -> (&mut Dictionary, &mut dyn DeviceHook) {
        (&mut self.dict, &mut self.hook)
    }
}

impl GenericUnit {
    /// The dictionary (the drives' process values are theirs: [`GenericUnit::value`]).
    pub fn dict(&self) -> &Dictionary {
        &self.dict
    }

    /// The drives, axis by axis.
    pub fn drives(&self) -> &[ds402::drive::Drive] {
        self.hook.app.drives()
    }

    /// The drives, to act on them from outside (a simulated fault, a switch).
    pub fn drives_mut(&mut self) -> &mut [ds402::drive::Drive] {
        self.hook.app.drives_mut()
    }

    /// The current value of `at` as the process data carries it (the drive's for what it owns).
    pub fn value(&self, at: Address) -> Vec<u8> {
        let mut buf = [0u8; 8];
        hook::value(&self.dict, &self.hook, at, &mut buf).to_vec()
    }

    /// What the device senses at `now`: `bytes` as the value of `at`, set from the device's side (an
    /// input of an I/O device; the drives own their process values and take what they own as a
    /// write). Refused as the dictionary refuses a value it cannot hold.
    pub fn set(
        &mut self,
        now: Instant,
        at: Address,
        bytes: &[u8],
    ) -> Result<(), od::dict::OdError> {
        self.dict.check(at.index, at.sub, bytes)?;
        hook::deliver(&mut self.dict, &mut self.hook, at, bytes, now);
        Ok(())
    }

    /// The CiA 402-2 abort connection reaction of every drive at `now` (see the module
    /// documentation).
    fn connection_ended(&mut self, now: Instant) {
        let axes: Vec<u8> = self.hook.app.drives().iter().map(|d| d.axis()).collect();
        for (k, axis) in axes.into_iter().enumerate() {
            let base = 0x6000 + 0x800 * u16::from(axis);
            // An entry without a default (and not written since) holds 0 only for want of a value.
            let option = self
                .dict
                .entry(base + 0x0007, 0)
                .ok()
                .and_then(|e| e.current().and_then(|v| v.as_i128()).zip(Some(e)))
                .filter(|(v, e)| e.default.is_some() || *v != 0)
                .map_or(2, |(v, _)| v);
            if let Some(d) = self.hook.app.drives_mut().get_mut(k) {
                d.handle_timeout(now);
            }
            let control: Option<u16> = match option {
                0 => None,
                1 => {
                    if let Some(d) = self.hook.app.drives_mut().get_mut(k) {
                        d.raise_fault(now, CONNECTION_FAULT);
                    }
                    None
                }
                3 => Some(0x0002),
                _ => Some(0x0000),
            };
            if let Some(cw) = control {
                // A channel's controlword is the channel's entry (the dictionary keeps it too).
                let at = match self.hook.channels {
                    Some(_) => Channels::controlword(axis),
                    None => Address::new(base + 0x0040, 0),
                };
                hook::deliver(&mut self.dict, &mut self.hook, at, &cw.to_le_bytes(), now);
            }
        }
    }
}

impl Model for GenericUnit {
    fn process_images(&self) -> Result<(ProcessImage, ProcessImage), AlStatusCode> {
        self.hook.pdos.images(&self.dict)
    }

    fn set_al_state(&mut self, from: AlState, to: AlState, now: Instant) {
        self.hook.state = to;
        if from == AlState::Op && to != AlState::Op {
            self.connection_ended(now);
        }
    }

    fn outputs_lost(&mut self, _now: Instant) {
        // Leaving Op follows (set_al_state): the connection has ended.
    }

    fn device(&mut self) -> &mut dyn Device {
        &mut self.hook
    }

    fn set_sync0_cycle(&mut self, cycle: Option<Duration>) {
        // The set-points come at the SYNC0 cycle: the drives interpolate over it, whatever 0x60C2
        // says (it may say 1 s). The SyncManager parameters show it (ETG.1020: 0x1C32:02 and
        // 0x1C33:02, cycle time in ns), where the dictionary has them.
        for d in self.hook.app.drives_mut() {
            d.set_sync_cycle(cycle);
        }
        if let Some(c) = cycle {
            let ns = u32::try_from(c.as_nanos()).unwrap_or(u32::MAX);
            for index in [0x1C32, 0x1C33] {
                let _ = self.dict.store(index, 2, &ns.to_le_bytes());
            }
        }
    }
}
