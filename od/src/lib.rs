//! The object dictionary and device descriptions, in four groups: [`model`], [`description`], [`sdo`]
//! and [`coe`] (each module of the first two is also reachable from the crate root, `od::dict`, `od::esi`, …).
//!
//! **The model.**
//! - [`types`] and [`value`]: the CiA 301 basic data types and their little-endian encoding.
//! - [`object`] and [`dict`]: objects, sub-objects and the [`Dictionary`], with access, type, length and
//!   range checks whose refusals map onto SDO [`AbortCode`]s ([`abort`]).
//! - [`hook`]: the one way a device model sits behind its dictionary ([`hook::DeviceHook`]), and the
//!   process image of a PDO or SyncManager decoded from its mapping objects.
//! - [`event`]: what a device says about its own entries (a value filled in at start, …), as a line
//!   of text or a JSON object.
//!
//! **The descriptions.**
//! - [`device`]: a [`DeviceDescription`] (identity, dictionary, format-specific parts).
//! - [`esi`], [`xdd`], [`eds`]: readers and writers of EtherCAT ESI, CiA 311 XDD and CiA 306 EDS/DCF; the
//!   two XML readers walk the file with one cursor ([`xml`]); [`load`] reads a file of any of them,
//!   [`error`] and [`report`] say what was wrong or lost and where.
//! - [`sii`] (the EtherCAT SII image), [`doc`] (a Markdown reference), [`diff`] (two descriptions
//!   compared), [`validate`] (a description's own consistency), [`fill`] (the CiA 301 identity and
//!   names a device reports where its description gives none).
//!
//! **SDO.** [`sdo`]: the CiA 301 SDO frames, server and client (sans-IO), and a blocking session.
//!
//! **CoE.** [`coe`]: the EtherCAT mailbox, SDO over CoE, complete access and the CoE server, on the same
//! dictionary and model.
//!
//! **FoE.** [`foe`]: File access over EtherCAT, its frames and error codes, and the master's side of
//! a transfer (sans-IO).
#![deny(missing_docs)]

pub mod model {
    //! The model: data types, values, objects, the dictionary, abort codes and the device hook.
    pub mod abort;
    pub mod bits;
    pub mod dict;
    pub mod emcy;
    pub mod event;
    pub mod hook;
    pub mod object;
    pub mod types;
    pub mod units;
    pub mod value;
}

pub mod description {
    //! The descriptions: the formats' readers and writers and what is built on them.
    pub mod carry;
    pub mod device;
    pub mod diff;
    pub mod doc;
    pub mod eds;
    pub mod error;
    pub mod esi;
    pub mod fill;
    pub mod load;
    pub mod report;
    pub mod sii;
    pub mod validate;
    pub mod xdd;
    pub mod xml;
}

pub mod coe;
pub mod foe;
pub mod pdo;
pub mod sdo;

pub use description::{
    carry, device, diff, doc, eds, error, esi, fill, load, report, sii, validate, xdd, xml,
};
pub use model::{abort, bits, dict, emcy, event, hook, object, types, units, value};

pub use abort::AbortCode;
pub use device::DeviceDescription;
pub use dict::{Address, Dictionary, LookupError, OdError};
pub use error::{LoadError, ParseError, Position};
pub use object::{
    Access, AccessType, DefaultValue, EcatStates, Object, ObjectKind, PdoMapping, SubObject,
};
pub use report::{Finding, Reading, Severity, SourceMap};
pub use types::DataType;
pub use value::{TimeValue, Value, ValueError};
