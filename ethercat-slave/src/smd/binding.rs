//! The indexer model bound to the SMD object dictionary of `fixtures/` (ARCHITECTURE principle 2: one
//! dictionary, data-driven).
//!
//! An [`SmdUnit`] is an [`Indexer`] together with the dictionary of its device as the shipped ESI
//! ([`FIXTURE_ESI`], the file CoE access serves) describes it:
//!
//! - the unit **reads** its output image `0x7000:01–08` (CMD_word0 … Jerk) and its configuration
//!   `0x8010:01–07` from the dictionary, and **writes** its input image `0x6000:01–07` (STATUS_word0 …
//!   Jerk) into it;
//! - [`SmdUnit::sdo_write`] is an SDO download as the CoE server does it: the dictionary checks existence,
//!   access, length and value ([`Dictionary::write`]) and refuses with an [`OdError`] (whose
//!   [`OdError::abort_code`] is the SDO abort); a confirmed download to `0x8010:01–07` also reaches the
//!   model through [`Indexer::write_config`], so it sets Position_Invalid (SMD-R2-012) and an invalid value
//!   shows as Configuration_Error (SMD-T2-005);
//! - [`SmdUnit::write_outputs`] is what a process-data frame of the master does: it sets the eight output
//!   entries. In the fixture they are `ro` for SDO access, so [`SmdUnit::sdo_write`] to `0x7000` is
//!   refused with [`OdError::ReadOnly`];
//! - [`SmdUnit::cycle`] is one process-data exchange: `0x7000` → [`Outputs`] → [`Indexer::cycle`] →
//!   [`Inputs`] → `0x6000`.
//!
//! Every address the model uses is one entry of [`TABLE`], with the name, data type, access and PDO
//! mapping the model expects. [`check`] proves them against a dictionary, [`SmdUnit::new`] refuses a
//! dictionary that does not match, and the tests run it on both devices of the fixture.
//!
//! ```
//! use ethercat_slave::smd::binding::{Device, SmdUnit, STATUS_WORD0};
//! use ds402::smd::config::EncoderKind;
//! use std::time::Duration;
//!
//! let mut unit = SmdUnit::new(Device::Smd23kB, EncoderKind::Incremental).unwrap();
//! let inputs = unit.cycle(Duration::from_millis(1));
//! assert_eq!(inputs.status0, 0x4408);
//! assert_eq!(unit.dict().read(STATUS_WORD0.index, STATUS_WORD0.sub).unwrap(), &[0x08, 0x44]);
//! // Motor_Current 35 (3.5 A) is out of range: stored, and flagged as Configuration_Error.
//! unit.sdo_write(0x8010, 7, &35u16.to_le_bytes()).unwrap();
//! assert_eq!(unit.cycle(Duration::from_millis(1)).status0, 0x6408);
//! ```

use std::fmt;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use od::coe::server::CoeServer;
use od::dict::{Dictionary, OdError};
use od::error::ParseError;
use od::esi::Select;
use od::object::{AccessType, PdoMapping};
use od::sdo::server::ServerEvent;
use od::types::DataType;

use ds402::smd::config::{Configuration, EncoderKind};
use ds402::smd::indexer::{Indexer, Inputs, Outputs};

/// The ESI of both units as the generator writes it from `fixtures/src/smd.esi.xml` and
/// `fixtures/identity.toml` (`fixtures/smd/SMD23K-B_SMD24K.esi.xml`).
pub const FIXTURE_ESI: &str = include_str!("../../../fixtures/smd/SMD23K-B_SMD24K.esi.xml");

/// The file name [`FIXTURE_ESI`] goes by in errors.
pub const FIXTURE_NAME: &str = "SMD23K-B_SMD24K.esi.xml";

/// Which of the two units of the ESI (on a command line: `smd23k-b`, `smd24k`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Device {
    /// The SMD23K-B (size 23 motor).
    #[value(name = "smd23k-b")]
    Smd23kB,
    /// The SMD24K (size 24 motor).
    #[value(name = "smd24k")]
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

/// A unit: the indexer model on its device's dictionary.
#[derive(Debug, Clone)]
pub struct SmdUnit {
    device: Device,
    indexer: Indexer,
    dict: Dictionary,
}

impl SmdUnit {
    /// A unit at power-up: the fixture dictionary of `device` at its defaults, the configuration in memory
    /// taken from its `0x8010:01–07` defaults, and the power-up inputs (Position_Invalid, Stopped,
    /// Module_OK) already in `0x6000`.
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
        let mut unit = SmdUnit {
            device,
            indexer: Indexer::new(kind, config),
            dict,
        };
        let inputs = unit.indexer.inputs();
        unit.store_inputs(&inputs);
        Ok(unit)
    }

    /// The device.
    pub fn device(&self) -> Device {
        self.device
    }

    /// The dictionary: what an SDO upload reads, with the present input and output images.
    pub fn dict(&self) -> &Dictionary {
        &self.dict
    }

    /// The model.
    pub fn indexer(&self) -> &Indexer {
        &self.indexer
    }

    /// The model, for what the unit senses (inputs, shaft, temperature) and the network events (SYNC0,
    /// the SyncManager watchdog).
    pub fn indexer_mut(&mut self) -> &mut Indexer {
        &mut self.indexer
    }

    /// Sets the unit's serial number, `0x1018:04` (the SII holds the same).
    pub fn set_serial_number(&mut self, serial: u32) {
        // 0x1018:04 is UNSIGNED32 in the fixture; a dictionary without it keeps what it has.
        let _ = self.dict.store(0x1018, 4, &serial.to_le_bytes());
    }

    /// The EtherCAT state the unit is in (see [`Indexer::set_network_state`]).
    pub fn set_network_state(&mut self, state: ds402::smd::indexer::NetworkState) {
        self.indexer.set_network_state(state);
    }

    /// An SDO upload of `index:sub` as the CoE server does it ([`Dictionary::read`]).
    pub fn sdo_read(&self, index: u16, sub: u8) -> Result<&[u8], OdError> {
        self.dict.read(index, sub)
    }

    /// An SDO download of `bytes` to `index:sub` as the CoE server does it: the dictionary checks the
    /// entry, its access, the length and the value ([`Dictionary::write`]); a refusal changes nothing.
    /// A confirmed download to `0x8010:01–07` is passed to [`Indexer::write_config`] (Position_Invalid,
    /// SMD-R2-012; Configuration_Error for an invalid value, SMD-T2-005).
    pub fn sdo_write(&mut self, index: u16, sub: u8, bytes: &[u8]) -> Result<(), OdError> {
        self.dict.write(index, sub, bytes)?;
        if let Some(e) = entry_at(index, sub).filter(|e| e.block == Block::Configuration) {
            let value = self.get::<u32>(e);
            self.indexer.write_config(sub, value);
        }
        Ok(())
    }

    /// A CoE mailbox the master wrote (sync manager 0), served by `server` on the unit's dictionary; its
    /// answers are left in `server` for the master to read. A confirmed download to `0x8010` reaches
    /// the model as [`sdo_write`](SmdUnit::sdo_write)'s does: the entry written, and for a Complete
    /// Access every sub-index whose value it changed. Returns the server's events.
    pub fn handle_mailbox(
        &mut self,
        server: &mut CoeServer,
        now: Instant,
        mailbox: &[u8],
    ) -> Vec<ServerEvent> {
        let before = self.configuration_values();
        server.handle_mailbox(now, mailbox, &mut self.dict);
        let events: Vec<ServerEvent> = std::iter::from_fn(|| server.poll_event()).collect();
        let after = self.configuration_values();
        for event in &events {
            let ServerEvent::Downloaded { mux } = event else {
                continue;
            };
            if mux.index != CONFIGURATION_INDEX {
                continue;
            }
            for (k, value) in after.iter().enumerate() {
                let sub = k as u8 + 1;
                if sub == mux.sub || before[k] != *value {
                    self.indexer.write_config(sub, *value);
                }
            }
        }
        events
    }

    /// `0x8010:01–07` as the dictionary holds them.
    fn configuration_values(&self) -> [u32; 7] {
        let mut values = [0u32; 7];
        for (k, v) in values.iter_mut().enumerate() {
            if let Some(e) = entry_at(CONFIGURATION_INDEX, k as u8 + 1) {
                *v = self.get::<u32>(e);
            }
        }
        values
    }

    /// What a process-data frame of the master does: sets `0x7000:01–08` to `outputs`.
    pub fn write_outputs(&mut self, outputs: &Outputs) {
        self.put(&CMD_WORD0, &outputs.cmd0.to_le_bytes());
        self.put(&CMD_WORD1, &outputs.cmd1.to_le_bytes());
        self.put(&POSITION, &outputs.position.to_le_bytes());
        self.put(&VELOCITY, &outputs.velocity.to_le_bytes());
        self.put(&ACCELERATION, &outputs.acceleration.to_le_bytes());
        self.put(&DECELERATION, &outputs.deceleration.to_le_bytes());
        self.put(&OUT_MOTOR_CURRENT, &outputs.motor_current.to_le_bytes());
        self.put(&OUT_JERK, &outputs.jerk.to_le_bytes());
    }

    /// The output image `0x7000:01–08` as the unit reads it.
    pub fn outputs(&self) -> Outputs {
        Outputs {
            cmd0: self.get(&CMD_WORD0),
            cmd1: self.get(&CMD_WORD1),
            position: self.get(&POSITION),
            velocity: self.get(&VELOCITY),
            acceleration: self.get(&ACCELERATION),
            deceleration: self.get(&DECELERATION),
            motor_current: self.get(&OUT_MOTOR_CURRENT),
            jerk: self.get(&OUT_JERK),
        }
    }

    /// The input image `0x6000:01–07` as the dictionary holds it.
    pub fn inputs(&self) -> Inputs {
        Inputs {
            status0: self.get(&STATUS_WORD0),
            status1: self.get(&STATUS_WORD1),
            motor_position: self.get(&MOTOR_POSITION),
            encoder_position: self.get(&ENCODER_POSITION),
            trapped_encoder_position: self.get(&TRAPPED_ENCODER_POSITION),
            motor_current: self.get(&IN_MOTOR_CURRENT),
            jerk: self.get(&IN_JERK),
        }
    }

    /// One process-data exchange of `dt`: reads the outputs from `0x7000`, runs [`Indexer::cycle`], writes
    /// the inputs into `0x6000` and answers them.
    pub fn cycle(&mut self, dt: Duration) -> Inputs {
        let outputs = self.outputs();
        let inputs = self.indexer.cycle(outputs, dt);
        self.store_inputs(&inputs);
        inputs
    }

    fn store_inputs(&mut self, inputs: &Inputs) {
        self.put(&STATUS_WORD0, &inputs.status0.to_le_bytes());
        self.put(&STATUS_WORD1, &inputs.status1.to_le_bytes());
        self.put(&MOTOR_POSITION, &inputs.motor_position.to_le_bytes());
        self.put(&ENCODER_POSITION, &inputs.encoder_position.to_le_bytes());
        self.put(
            &TRAPPED_ENCODER_POSITION,
            &inputs.trapped_encoder_position.to_le_bytes(),
        );
        self.put(&IN_MOTOR_CURRENT, &inputs.motor_current.to_le_bytes());
        self.put(&IN_JERK, &inputs.jerk.to_le_bytes());
    }

    /// Sets a process-data entry from the device's side. [`check`] has proven the entry exists with the
    /// type whose encoding `bytes` is and has no limits, so the store cannot be refused.
    fn put(&mut self, e: &Entry, bytes: &[u8]) {
        // Cannot fail after `check`; a refusal would leave the old value, never panic.
        let _ = self.dict.store(e.index, e.sub, bytes);
    }

    /// The current value of a checked entry (0 if it could not be read, which [`check`] rules out).
    fn get<T: TryFrom<i128> + Default>(&self, e: &Entry) -> T {
        value_of(&self.dict, e)
    }
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
