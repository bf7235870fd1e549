//! The indexer model bound to the SMD object dictionary of `fixtures/` (ARCHITECTURE principle 2: one
//! dictionary, data-driven), through the one device hook of the project ([`od::hook::DeviceHook`]).
//!
//! An [`SmdUnit`] is the dictionary of its device as the shipped ESI ([`FIXTURE_ESI`], the file CoE
//! access serves) describes it, with [`SmdModel`] (the [`Indexer`]) behind it:
//!
//! - the model **owns** the output image `0x7000:01–08` (CMD_word0 … Jerk: what the master last sent),
//!   the input image `0x6000:01–07` (STATUS_word0 … Jerk: computed by the indexer when read) and the
//!   configuration `0x8010:01–07` (the dictionary's values, told to the indexer when written); nothing
//!   is copied through the dictionary on a cycle;
//! - [`SmdUnit::sdo_write`] is an SDO download as the CoE server does it, through [`od::hook::Bound`]:
//!   the dictionary checks existence, access, length and value, the model its own rules, and a refusal
//!   is the SDO abort code ([`AbortCode`]; the dictionary's are [`OdError::abort_code`] of its
//!   error) and changes nothing; a confirmed download to `0x8010:01–07` also reaches the model through
//!   [`Indexer::write_config`], so it sets Position_Invalid (SMD-R2-012) and an invalid value shows as
//!   Configuration_Error (SMD-T2-005); [`SmdUnit::handle_mailbox`] serves a CoE mailbox on the same
//!   dictionary and model (complete access included);
//! - [`SmdUnit::receive_process_data`] and [`SmdUnit::send_process_data`] are a frame's process data,
//!   laid out as the PDO mapping of the description says ([`ProcessImage`]); [`SmdUnit::write_outputs`]
//!   is the same delivery of `0x7000:01–08` ([`od::hook::deliver`]) without the frame. The outputs are
//!   `ro` for SDO access, so [`SmdUnit::sdo_write`] to `0x7000` is refused with
//!   [`AbortCode::ReadOnly`];
//! - [`SmdUnit::cycle`] is one process-data exchange: [`Outputs`] → [`Indexer::cycle`] → [`Inputs`];
//!   an exchange with no output image written since the last is [`Indexer::cycle_held`], so the
//!   first image the master writes in Op is the indexer's edge reference (SMD-R6-073).
//!
//! Every address the model uses is one entry of [`TABLE`], with the name, data type, access and PDO
//! mapping the model expects. [`check`] proves them against a dictionary, [`SmdUnit::new`] refuses a
//! dictionary that does not match, and the tests run it on both devices of the fixture.
//!
//! ```
//! use ethercat_slave::smd::binding::{Device, SmdUnit, STATUS_WORD0};
//! use ds402::smd::config::EncoderKind;
//! use std::time::{Duration, Instant};
//!
//! let now = Instant::now();
//! let mut unit = SmdUnit::new(Device::Smd23kB, EncoderKind::Incremental).unwrap();
//! let inputs = unit.cycle(Duration::from_millis(1));
//! assert_eq!(inputs.status0, 0x4408);
//! assert_eq!(unit.sdo_read(STATUS_WORD0.index, STATUS_WORD0.sub).unwrap(), [0x08, 0x44]);
//! // Motor_Current 35 (3.5 A) is out of range: stored, and flagged as Configuration_Error.
//! unit.sdo_write(now, 0x8010, 7, &35u16.to_le_bytes()).unwrap();
//! assert_eq!(unit.cycle(Duration::from_millis(1)).status0, 0x6408);
//! ```

use std::fmt;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use od::abort::AbortCode;
use od::coe::server::CoeServer;
use od::dict::{Address, Dictionary, OdError};
use od::error::ParseError;
use od::esi::Select;
use od::hook::{self, DeviceHook, Objects, ProcessImage};
use od::object::{AccessType, PdoMapping};
use od::sdo::server::ServerEvent;
use od::sdo::store::ObjectStore;
use od::types::DataType;
use od::value::Value;

use ds402::smd::config::{Configuration, EncoderKind};
use ds402::smd::indexer::{Indexer, Inputs, Outputs};

/// The ESI of both units as the generator writes it from `fixtures/src/smd.esi.xml` and
/// `fixtures/identity.toml` (`fixtures/smd/SMD23K-B_SMD24K.esi.xml`).
pub const FIXTURE_ESI: &str = include_str!("../../../fixtures/smd/SMD23K-B_SMD24K.esi.xml");

/// The file name [`FIXTURE_ESI`] goes by in errors.
pub const FIXTURE_NAME: &str = "SMD23K-B_SMD24K.esi.xml";

/// Which of the two units of the ESI (on a command line: `smd23k-b`, `smd24k`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[non_exhaustive]
pub enum Device {
    /// The SMD23K-B (size 23 motor).
    #[cfg_attr(feature = "cli", value(name = "smd23k-b"))]
    Smd23kB,
    /// The SMD24K (size 24 motor).
    #[cfg_attr(feature = "cli", value(name = "smd24k"))]
    Smd24k,
}

impl Device {
    /// Both units, in the order of the ESI.
    pub const ALL: [Device; 2] = [Device::Smd23kB, Device::Smd24k];

    /// The order code, the ESI's `Type` text: `"SMD23K-B"` or `"SMD24K"`.
    pub const fn order_code(self) -> &'static str {
        match self {
            Device::Smd23kB => "SMD23K-B",
            Device::Smd24k => "SMD24K",
        }
    }
}

impl fmt::Display for Device {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.order_code())
    }
}

/// What an address is to the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Block {
    /// `0x7000`: output process data, written by the master, read by the unit.
    Output,
    /// `0x6000`: input process data, written by the unit, read by the master.
    Input,
    /// `0x8010`: configuration data, written by SDO, read by the unit.
    Configuration,
}

/// One address the model uses and what it expects to find there.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Entry {
    /// The block it belongs to.
    pub block: Block,
    /// Index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// The name in the ESI (and the manual).
    pub name: &'static str,
    /// The data type matching the model's Rust field.
    pub data_type: DataType,
    /// SDO access.
    pub access: AccessType,
    /// PDO mappability.
    pub pdo: PdoMapping,
}

impl fmt::Display for Entry {
    /// `CMD_word0 (0x7000:01)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} (0x{:04X}:{:02X})", self.name, self.index, self.sub)
    }
}

/// The output process data object.
pub const OUTPUTS_INDEX: u16 = 0x7000;
/// The input process data object.
pub const INPUTS_INDEX: u16 = 0x6000;
/// The configuration data object.
pub const CONFIGURATION_INDEX: u16 = 0x8010;

const fn output(sub: u8, name: &'static str, data_type: DataType) -> Entry {
    Entry {
        block: Block::Output,
        index: OUTPUTS_INDEX,
        sub,
        name,
        data_type,
        access: AccessType::Ro,
        pdo: PdoMapping::Rpdo,
    }
}

const fn input(sub: u8, name: &'static str, data_type: DataType) -> Entry {
    Entry {
        block: Block::Input,
        index: INPUTS_INDEX,
        sub,
        name,
        data_type,
        access: AccessType::Ro,
        pdo: PdoMapping::Tpdo,
    }
}

const fn configuration(sub: u8, name: &'static str, data_type: DataType) -> Entry {
    Entry {
        block: Block::Configuration,
        index: CONFIGURATION_INDEX,
        sub,
        name,
        data_type,
        access: AccessType::Rw,
        pdo: PdoMapping::None,
    }
}

/// `0x7000:01` CMD_word0 ([`Outputs::cmd0`]).
pub const CMD_WORD0: Entry = output(1, "CMD_word0", DataType::Unsigned16);
/// `0x7000:02` CMD_word1 ([`Outputs::cmd1`]).
pub const CMD_WORD1: Entry = output(2, "CMD_word1", DataType::Unsigned16);
/// `0x7000:03` Position ([`Outputs::position`]).
pub const POSITION: Entry = output(3, "Position", DataType::Integer32);
/// `0x7000:04` Velocity ([`Outputs::velocity`]).
pub const VELOCITY: Entry = output(4, "Velocity", DataType::Unsigned32);
/// `0x7000:05` Acceleration ([`Outputs::acceleration`]).
pub const ACCELERATION: Entry = output(5, "Acceleration", DataType::Unsigned16);
/// `0x7000:06` Deceleration ([`Outputs::deceleration`]).
pub const DECELERATION: Entry = output(6, "Deceleration", DataType::Unsigned16);
/// `0x7000:07` Motor_Current ([`Outputs::motor_current`]).
pub const OUT_MOTOR_CURRENT: Entry = output(7, "Motor_Current", DataType::Unsigned16);
/// `0x7000:08` Jerk ([`Outputs::jerk`]).
pub const OUT_JERK: Entry = output(8, "Jerk", DataType::Unsigned16);

/// `0x6000:01` STATUS_word0 ([`Inputs::status0`]).
pub const STATUS_WORD0: Entry = input(1, "STATUS_word0", DataType::Unsigned16);
/// `0x6000:02` STATUS_word1 ([`Inputs::status1`]).
pub const STATUS_WORD1: Entry = input(2, "STATUS_word1", DataType::Unsigned16);
/// `0x6000:03` Motor_Position ([`Inputs::motor_position`]).
pub const MOTOR_POSITION: Entry = input(3, "Motor_Position", DataType::Integer32);
/// `0x6000:04` Encoder_Position ([`Inputs::encoder_position`]).
pub const ENCODER_POSITION: Entry = input(4, "Encoder_Position", DataType::Integer32);
/// `0x6000:05` Trapped_Encoder_Position ([`Inputs::trapped_encoder_position`]).
pub const TRAPPED_ENCODER_POSITION: Entry =
    input(5, "Trapped_Encoder_Position", DataType::Integer32);
/// `0x6000:06` Motor_Current ([`Inputs::motor_current`]).
pub const IN_MOTOR_CURRENT: Entry = input(6, "Motor_Current", DataType::Unsigned16);
/// `0x6000:07` Jerk ([`Inputs::jerk`]).
pub const IN_JERK: Entry = input(7, "Jerk", DataType::Unsigned16);

/// `0x8010:01` CFG_Word_0 ([`Configuration::cfg0`]).
pub const CFG_WORD_0: Entry = configuration(1, "CFG_Word_0", DataType::Unsigned16);
/// `0x8010:02` CFG_Word_1 ([`Configuration::cfg1`]).
pub const CFG_WORD_1: Entry = configuration(2, "CFG_Word_1", DataType::Unsigned16);
/// `0x8010:03` Starting_Speed ([`Configuration::starting_speed`]).
pub const STARTING_SPEED: Entry = configuration(3, "Starting_Speed", DataType::Unsigned32);
/// `0x8010:04` Motor_Resolution ([`Configuration::motor_resolution`]).
pub const MOTOR_RESOLUTION: Entry = configuration(4, "Motor_Resolution", DataType::Unsigned16);
/// `0x8010:05` Encoder_Resolution ([`Configuration::encoder_resolution`]).
pub const ENCODER_RESOLUTION: Entry = configuration(5, "Encoder_Resolution", DataType::Unsigned16);
/// `0x8010:06` Idle_current_reduction ([`Configuration::idle_current_reduction`]).
pub const IDLE_CURRENT_REDUCTION: Entry =
    configuration(6, "Idle_current_reduction", DataType::Unsigned16);
/// `0x8010:07` Motor_Current ([`Configuration::motor_current`]).
pub const CFG_MOTOR_CURRENT: Entry = configuration(7, "Motor_Current", DataType::Unsigned16);

/// Every address the model uses: the eight outputs (`0x7000:01–08`), the seven inputs (`0x6000:01–07`)
/// and the seven configuration values (`0x8010:01–07`), each block in sub-index order.
pub const TABLE: [Entry; 22] = [
    CMD_WORD0,
    CMD_WORD1,
    POSITION,
    VELOCITY,
    ACCELERATION,
    DECELERATION,
    OUT_MOTOR_CURRENT,
    OUT_JERK,
    STATUS_WORD0,
    STATUS_WORD1,
    MOTOR_POSITION,
    ENCODER_POSITION,
    TRAPPED_ENCODER_POSITION,
    IN_MOTOR_CURRENT,
    IN_JERK,
    CFG_WORD_0,
    CFG_WORD_1,
    STARTING_SPEED,
    MOTOR_RESOLUTION,
    ENCODER_RESOLUTION,
    IDLE_CURRENT_REDUCTION,
    CFG_MOTOR_CURRENT,
];

/// The entries of `block` in [`TABLE`], in sub-index order.
pub fn entries(block: Block) -> impl Iterator<Item = &'static Entry> {
    TABLE.iter().filter(move |e| e.block == block)
}

/// The entry of [`TABLE`] at `index:sub`.
pub fn entry_at(index: u16, sub: u8) -> Option<&'static Entry> {
    TABLE.iter().find(|e| e.index == index && e.sub == sub)
}

/// How a dictionary entry differs from what the model expects.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Mismatch {
    /// The entry is not there.
    #[error("missing: {0}")]
    Missing(OdError),
    /// Another name.
    #[error("named {found:?}")]
    Name {
        /// The name in the dictionary.
        found: String,
    },
    /// Another data type.
    #[error("of type {found}")]
    DataType {
        /// The type in the dictionary.
        found: DataType,
    },
    /// Another access.
    #[error("with access {found}")]
    Access {
        /// The access in the dictionary.
        found: AccessType,
    },
    /// Another PDO mappability.
    #[error("with PDO mapping {found:?}")]
    Pdo {
        /// The mapping in the dictionary.
        found: PdoMapping,
    },
    /// A process-data entry with a low or high limit: process data carries every value of its type.
    #[error("limited to a range")]
    Limited,
    /// The current value does not decode as the type.
    #[error("holding an undecodable value: {0}")]
    Value(OdError),
}

/// Why the model could not be bound to a dictionary.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BindingError {
    /// The fixture ESI does not load, or does not describe the device.
    #[error("the SMD fixture does not give the {device} dictionary: {source}")]
    Fixture {
        /// The device asked for.
        device: Device,
        /// The reader's error.
        source: ParseError,
    },
    /// An address of [`TABLE`] is not in the dictionary as the model expects it.
    #[error("{entry} is not as the model expects it: {mismatch}")]
    Entry {
        /// The entry of [`TABLE`].
        entry: Entry,
        /// What differs.
        mismatch: Mismatch,
    },
}

/// The dictionary of `device` from [`FIXTURE_ESI`], at its default values. The ESI is parsed once per
/// process and device; each call answers a fresh copy.
pub fn dictionary(device: Device) -> Result<Dictionary, BindingError> {
    static FIXTURE: [OnceLock<Result<Dictionary, ParseError>>; 2] =
        [OnceLock::new(), OnceLock::new()];
    let slot = match device {
        Device::Smd23kB => &FIXTURE[0],
        Device::Smd24k => &FIXTURE[1],
    };
    slot.get_or_init(|| {
        let select = Select::Name(device.order_code().to_string());
        od::esi::read(FIXTURE_ESI.as_bytes(), FIXTURE_NAME, Some(&select)).map(|d| d.dictionary)
    })
    .clone()
    .map_err(|source| BindingError::Fixture { device, source })
}

/// Checks every entry of [`TABLE`] against `dict`: it exists with the name, data type, access and PDO
/// mapping the model expects, holds a value of its type, and (process data) has no limits.
pub fn check(dict: &Dictionary) -> Result<(), BindingError> {
    TABLE.iter().try_for_each(|entry| {
        check_entry(dict, entry).map_err(|mismatch| BindingError::Entry {
            entry: *entry,
            mismatch,
        })
    })
}

fn check_entry(dict: &Dictionary, e: &Entry) -> Result<(), Mismatch> {
    let found = dict.entry(e.index, e.sub).map_err(Mismatch::Missing)?;
    if found.name != e.name {
        return Err(Mismatch::Name {
            found: found.name.clone(),
        });
    }
    if found.data_type != e.data_type {
        return Err(Mismatch::DataType {
            found: found.data_type,
        });
    }
    if found.access.kind != e.access {
        return Err(Mismatch::Access {
            found: found.access.kind,
        });
    }
    if found.pdo != e.pdo {
        return Err(Mismatch::Pdo { found: found.pdo });
    }
    if e.block != Block::Configuration && (found.low.is_some() || found.high.is_some()) {
        return Err(Mismatch::Limited);
    }
    dict.read_value(e.index, e.sub).map_err(Mismatch::Value)?;
    Ok(())
}

/// The indexer as the model behind its dictionary ([`DeviceHook`]): it owns the output image
/// `0x7000` (what the master last sent, by process data), the input image `0x6000` (computed by the
/// indexer when read) and the configuration `0x8010` (kept in the dictionary, told to the indexer
/// when written: Position_Invalid, SMD-R2-012; Configuration_Error for an invalid value, SMD-T2-005).
#[derive(Debug, Clone)]
pub struct SmdModel {
    indexer: Indexer,
    outputs: Outputs,
    /// `outputs` were written (by process data) since the last exchange: new output data for the
    /// indexer (the first in Op is its edge reference, SMD-R6-073).
    fresh: bool,
}

/// A little-endian value of up to 8 bytes.
fn le(data: &[u8]) -> u64 {
    let mut b = [0u8; 8];
    let n = data.len().min(8);
    b[..n].copy_from_slice(&data[..n]);
    u64::from_le_bytes(b)
}

impl DeviceHook for SmdModel {
    fn owns(&self, index: u16) -> bool {
        matches!(index, OUTPUTS_INDEX | INPUTS_INDEX | CONFIGURATION_INDEX)
    }

    fn read(&self, at: Address, out: &mut [u8; 8]) -> Option<usize> {
        // The size is the table's data type; the configuration is the dictionary's.
        let entry = entry_at(at.index, at.sub).filter(|e| e.block != Block::Configuration)?;
        let v: u64 = if entry.block == Block::Output {
            let o = &self.outputs;
            match at.sub {
                1 => o.cmd0.into(),
                2 => o.cmd1.into(),
                3 => u64::from(o.position as u32),
                4 => o.velocity.into(),
                5 => o.acceleration.into(),
                6 => o.deceleration.into(),
                7 => o.motor_current.into(),
                _ => o.jerk.into(),
            }
        } else {
            let i = self.indexer.inputs();
            match at.sub {
                1 => i.status0.into(),
                2 => i.status1.into(),
                3 => u64::from(i.motor_position as u32),
                4 => u64::from(i.encoder_position as u32),
                5 => u64::from(i.trapped_encoder_position as u32),
                6 => i.motor_current.into(),
                _ => i.jerk.into(),
            }
        };
        let n = entry.data_type.byte_size()?;
        out[..n].copy_from_slice(&v.to_le_bytes()[..n]);
        Some(n)
    }

    /// The model takes what it binds: an output (`0x7000:01–08`) or a configuration value
    /// (`0x8010:01–07`). It refuses the inputs (`0x6000:01–07`, the indexer's answer:
    /// [`AbortCode::ReadOnly`]) and any other entry of its objects a dictionary may hold
    /// ([`AbortCode::UnsupportedAccess`]), whatever the dictionary's access says.
    fn check(&self, at: Address, _data: &[u8]) -> Result<(), AbortCode> {
        match entry_at(at.index, at.sub).map(|e| e.block) {
            Some(Block::Output | Block::Configuration) => Ok(()),
            Some(Block::Input) => Err(AbortCode::ReadOnly),
            None => Err(AbortCode::UnsupportedAccess),
        }
    }

    fn write(&mut self, at: Address, data: &[u8], now: Instant) -> Result<(), AbortCode> {
        self.check(at, data)?;
        self.take(at, data, now);
        Ok(())
    }
}

/// The indexer's lifecycle: a timeout is one process-data exchange (the output image to
/// [`Indexer::exchange`] when it was written since the last exchange, else
/// [`Indexer::exchange_held`]: after entering Op the first image written is the edge reference,
/// SMD-R6-073), due one exchange period after the last ([`Indexer::poll_timeout`]); a
/// synchronisation is the SYNC0 event at its instant (DC_Sync starts 520 µs after it, SMD-R1-022);
/// a reset is a power cycle.
impl od::hook::Device for SmdModel {
    fn handle_timeout(&mut self, now: Instant) {
        self.exchange(now);
    }

    fn poll_timeout(&self) -> Option<Instant> {
        self.indexer.poll_timeout()
    }

    fn reset(&mut self, _now: Instant) {
        self.indexer.power_cycle();
    }

    fn sync(&mut self, now: Instant) {
        self.indexer.sync0_event(now);
    }
}

impl SmdModel {
    /// The indexer.
    pub fn indexer(&self) -> &Indexer {
        &self.indexer
    }

    /// What a write of `data` to `at` does (every value the dictionary and
    /// [`DeviceHook::check`] accept is taken).
    fn take(&mut self, at: Address, data: &[u8], now: Instant) {
        let v = le(data);
        match at.index {
            OUTPUTS_INDEX => {
                self.fresh = true;
                let o = &mut self.outputs;
                match at.sub {
                    1 => o.cmd0 = v as u16,
                    2 => o.cmd1 = v as u16,
                    3 => o.position = v as u32 as i32,
                    4 => o.velocity = v as u32,
                    5 => o.acceleration = v as u16,
                    6 => o.deceleration = v as u16,
                    7 => o.motor_current = v as u16,
                    8 => o.jerk = v as u16,
                    _ => {}
                }
            }
            CONFIGURATION_INDEX => {
                self.indexer.write_config(now, at.sub, v as u32);
            }
            _ => {}
        }
    }

    /// One process-data exchange at `now` (see the [`od::hook::Device`] implementation); the inputs it
    /// answers.
    fn exchange(&mut self, now: Instant) -> Inputs {
        if std::mem::take(&mut self.fresh) {
            self.indexer.exchange(now, self.outputs)
        } else {
            self.indexer.exchange_held(now)
        }
    }
}

/// A unit: the indexer model ([`SmdModel`]) behind its device's dictionary.
#[derive(Debug, Clone)]
pub struct SmdUnit {
    device: Device,
    dict: Dictionary,
    model: SmdModel,
}

impl Objects for SmdUnit {
    fn split(&mut self) -> (&mut Dictionary, &mut dyn DeviceHook) {
        (&mut self.dict, &mut self.model)
    }
}

impl SmdUnit {
    /// A unit at power-up: the fixture dictionary of `device` at its defaults, the configuration in memory
    /// taken from its `0x8010:01–07` defaults, and the power-up inputs (Position_Invalid, Stopped,
    /// Module_OK).
    pub fn new(device: Device, kind: EncoderKind) -> Result<SmdUnit, BindingError> {
        SmdUnit::with_dictionary(device, dictionary(device)?, kind)
    }

    /// A unit on `dict` (e.g. a dictionary with start-up values already applied), checked with [`check`].
    pub fn with_dictionary(
        device: Device,
        dict: Dictionary,
        kind: EncoderKind,
    ) -> Result<SmdUnit, BindingError> {
        check(&dict)?;
        let config = Configuration {
            cfg0: value_of(&dict, &CFG_WORD_0),
            cfg1: value_of(&dict, &CFG_WORD_1),
            starting_speed: value_of(&dict, &STARTING_SPEED),
            motor_resolution: value_of(&dict, &MOTOR_RESOLUTION),
            encoder_resolution: value_of(&dict, &ENCODER_RESOLUTION),
            idle_current_reduction: value_of(&dict, &IDLE_CURRENT_REDUCTION),
            motor_current: value_of(&dict, &CFG_MOTOR_CURRENT),
        };
        let outputs = Outputs {
            cmd0: value_of(&dict, &CMD_WORD0),
            cmd1: value_of(&dict, &CMD_WORD1),
            position: value_of(&dict, &POSITION),
            velocity: value_of(&dict, &VELOCITY),
            acceleration: value_of(&dict, &ACCELERATION),
            deceleration: value_of(&dict, &DECELERATION),
            motor_current: value_of(&dict, &OUT_MOTOR_CURRENT),
            jerk: value_of(&dict, &OUT_JERK),
        };
        Ok(SmdUnit {
            device,
            dict,
            model: SmdModel {
                indexer: Indexer::new(kind, config),
                outputs,
                // The master has sent nothing yet.
                fresh: false,
            },
        })
    }

    /// The device.
    pub fn device(&self) -> Device {
        self.device
    }

    /// The dictionary: descriptions, access, limits and the parameters. The values of `0x6000` and
    /// `0x7000` are the model's ([`SmdUnit::value`], [`SmdUnit::sdo_read`]).
    pub fn dict(&self) -> &Dictionary {
        &self.dict
    }

    /// The model behind the dictionary.
    pub fn model(&self) -> &SmdModel {
        &self.model
    }

    /// The model, to run it ([`od::hook::Device`]).
    pub fn model_mut(&mut self) -> &mut SmdModel {
        &mut self.model
    }

    /// The indexer.
    pub fn indexer(&self) -> &Indexer {
        &self.model.indexer
    }

    /// The indexer, for what the unit senses (inputs, shaft, temperature) and the network events (SYNC0,
    /// the SyncManager watchdog).
    pub fn indexer_mut(&mut self) -> &mut Indexer {
        &mut self.model.indexer
    }

    /// Sets the unit's serial number, `0x1018:04` (the SII holds the same).
    pub fn set_serial_number(&mut self, serial: u32) {
        // 0x1018:04 is UNSIGNED32 in the fixture; a dictionary without it keeps what it has.
        let _ = self.dict.store(0x1018, 4, &serial.to_le_bytes());
    }

    /// The EtherCAT state the unit is in from `now` (see [`Indexer::set_network_state`]).
    pub fn set_network_state(&mut self, now: Instant, state: ds402::smd::indexer::NetworkState) {
        self.model.indexer.set_network_state(now, state);
    }

    /// The current value of `index:sub`, the model's for what it owns, decoded as the entry's type.
    pub fn value(&self, index: u16, sub: u8) -> Result<Value, OdError> {
        let data_type = self.dict.entry(index, sub)?.data_type;
        let mut buf = [0u8; 8];
        let bytes = hook::value(&self.dict, &self.model, Address::new(index, sub), &mut buf);
        Value::decode(data_type, bytes).map_err(|e| OdError::InvalidValue {
            index,
            sub,
            reason: e.to_string(),
        })
    }

    /// An SDO upload of `index:sub` as the CoE server does it: refused as the dictionary refuses it
    /// ([`Dictionary::read`]), else the current value.
    pub fn sdo_read(&self, index: u16, sub: u8) -> Result<Vec<u8>, OdError> {
        self.dict.read(index, sub)?;
        let mut buf = [0u8; 8];
        Ok(hook::value(&self.dict, &self.model, Address::new(index, sub), &mut buf).to_vec())
    }

    /// An SDO download of `bytes` to `index:sub` made at `now`, as the CoE server does it, through
    /// [`od::hook::Bound`]: the dictionary checks the entry, its access, the length and the value,
    /// then the model its own rules ([`od::hook::check_download`], [`SmdModel`]'s
    /// [`DeviceHook::check`]); the model takes the value, then the dictionary
    /// ([`od::hook::store_download`]). A confirmed download to `0x8010:01–07` reaches the indexer
    /// ([`Indexer::write_config`]).
    ///
    /// A refusal is the SDO abort code the CoE server answers with (for the dictionary's refusals,
    /// [`OdError::abort_code`] of its error), and changes nothing, neither the dictionary nor the
    /// model. The device is not run up to `now` here: [`od::hook::Device::handle_timeout`] is the
    /// caller's, as the unit runs it.
    pub fn sdo_write(
        &mut self,
        now: Instant,
        index: u16,
        sub: u8,
        bytes: &[u8],
    ) -> Result<(), AbortCode> {
        let mut bound = hook::Bound::new(&mut self.dict, &mut self.model, now);
        bound.download(Address::new(index, sub), bytes)
    }

    /// A CoE mailbox the master wrote (sync manager 0), served by `server` on the unit's dictionary and
    /// model; its answers are left in `server` for the master to read. Returns the server's events.
    pub fn handle_mailbox(
        &mut self,
        server: &mut CoeServer,
        now: Instant,
        mailbox: &[u8],
    ) -> Vec<ServerEvent> {
        server.handle_mailbox(now, mailbox, self);
        std::iter::from_fn(|| server.poll_event()).collect()
    }

    /// What a process-data frame of the master received at `now` does to the output image: each of
    /// `0x7000:01–08` delivered ([`od::hook::deliver`]) as [`ProcessImage::unpack`] delivers it, so
    /// the next exchange takes it as new output data.
    pub fn write_outputs(&mut self, now: Instant, outputs: &Outputs) {
        for (entry, bytes) in entries(Block::Output).zip(output_bytes(outputs)) {
            let at = Address::new(entry.index, entry.sub);
            hook::deliver(&mut self.dict, &mut self.model, at, &bytes, now);
        }
    }

    /// The output image `0x7000:01–08` as the unit reads it.
    pub fn outputs(&self) -> Outputs {
        self.model.outputs
    }

    /// The input image `0x6000:01–07`.
    pub fn inputs(&self) -> Inputs {
        self.model.indexer.inputs()
    }

    /// The output process data of a frame received at `now`, laid out as `image` (from the RxPDO
    /// assignment): each mapped entry delivered to the model or the dictionary
    /// ([`ProcessImage::unpack`]).
    pub fn receive_process_data(&mut self, now: Instant, image: &ProcessImage, data: &[u8]) {
        image.unpack(data, &mut self.dict, &mut self.model, now);
    }

    /// The input process data laid out as `image` (from the TxPDO assignment), from the model and the
    /// dictionary ([`ProcessImage::pack`]).
    pub fn send_process_data(&self, image: &ProcessImage, out: &mut [u8]) {
        image.pack(&self.dict, &self.model, out);
    }

    /// One process-data exchange at `now`: the output image to [`Indexer::exchange`] when it was
    /// written since the last exchange, else [`Indexer::exchange_held`] (no new output data: after
    /// entering Op the first image written is the edge reference, SMD-R6-073); the inputs it answers.
    pub fn exchange(&mut self, now: Instant) -> Inputs {
        self.model.exchange(now)
    }

    /// One process-data exchange of `dt`, without a clock: as [`SmdUnit::exchange`], with
    /// [`Indexer::cycle`] or [`Indexer::cycle_held`]; the inputs it answers.
    pub fn cycle(&mut self, dt: Duration) -> Inputs {
        if std::mem::take(&mut self.model.fresh) {
            self.model.indexer.cycle(self.model.outputs, dt)
        } else {
            self.model.indexer.cycle_held(dt)
        }
    }
}

/// The output words little-endian, in the order of `0x7000:01–08`, each in its entry's size.
fn output_bytes(o: &Outputs) -> [Vec<u8>; 8] {
    [
        o.cmd0.to_le_bytes().to_vec(),
        o.cmd1.to_le_bytes().to_vec(),
        o.position.to_le_bytes().to_vec(),
        o.velocity.to_le_bytes().to_vec(),
        o.acceleration.to_le_bytes().to_vec(),
        o.deceleration.to_le_bytes().to_vec(),
        o.motor_current.to_le_bytes().to_vec(),
        o.jerk.to_le_bytes().to_vec(),
    ]
}

/// The current value of an entry [`check`] has proven (0 if it could not be read, which the check
/// rules out).
fn value_of<T: TryFrom<i128> + Default>(dict: &Dictionary, e: &Entry) -> T {
    dict.read_value(e.index, e.sub)
        .ok()
        .and_then(|v| v.as_i128())
        .and_then(|v| T::try_from(v).ok())
        .unwrap_or_default()
}
