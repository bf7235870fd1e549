//! CiA 311 XML device descriptions (XDD) and device configuration files (XDC), v1.0 and v1.1 of the schema:
//! an ISO 15745-1 `ISO15745ProfileContainer` holding a device profile (`ProfileBody_Device_CANopen`) and a
//! communication network profile (`ProfileBody_CommunicationNetwork_CANopen`), in XML 1.0 or 1.1.
//!
//! This is the description-format layer: it knows XML elements, not SDOs. [`read`] turns the bytes of an
//! XDD/XDC into a [`DeviceDescription`](crate::device::DeviceDescription); [`write`](fn@write) turns a description into
//! a complete XDD (an XDC when the description has commissioning values).
//!
//! # What is read
//!
//! - `ProfileBody` attributes `fileName`, `fileCreator`, `fileCreationDate`, `fileCreationTime`,
//!   `fileModifiedBy`, `fileModificationDate`, `fileModificationTime`, `fileVersion` → [`FileInfo`], as
//!   written (the device profile's win over the network profile's).
//! - `DeviceIdentity`: `vendorName`, `vendorID`, `productName`, `productID`, `orderNumber` → [`Identity`];
//!   `productText/description` → [`FileInfo::description`]. `version` (`versionType` SW, FW or HW) is checked
//!   but has no place in the model. The revision number is the default of 0x1018:03; a missing or empty
//!   `vendorID`/`productID` falls back to the defaults of 0x1018:01/02.
//! - `ApplicationProcess/parameterList/parameter`: `uniqueID`, `access` (`const`, `read`, `write`,
//!   `readWrite`, `readWriteInput`, `readWriteOutput`; `noAccess` reads as `ro`), `label`/`description`
//!   (English preferred), the type as a child element (`<UINT/>`) or `dataTypeIDRef`, `defaultValue`,
//!   `actualValue`, `allowedValues/range/minValue|maxValue`, and CANopenNode's
//!   `property name="CO_stringLengthMin"` (the byte capacity of a VISIBLE_STRING or OCTET_STRING).
//!   `dataTypeList`: `array`, `struct`, `enum`, `derived` (name, element or base type). The types are
//!   checked, never expanded: an array's `subrange` (its elements are an ARRAY's sub-indices) and a
//!   struct's `varDeclaration`s (a RECORD's entries) must fit sub-indices 0x00–0xFE, and the
//!   `dataTypeIDRef`s between types must name a type and never lead back to the type they are in.
//!   An object's `subNumber` may not exceed the 256 sub-indices.
//! - `ApplicationLayers/CANopenObjectList`: `CANopenObject` and `CANopenSubObject` with `index`, `subIndex`,
//!   `name`, `objectType`, `dataType` (4 hex digits), `accessType`, `defaultValue` (also `$NODEID+0x180`,
//!   CiA 306 §4.6.2), `lowLimit`, `highLimit`, `actualValue`, `PDOmapping` (`no` → none, `RPDO`, `TPDO`,
//!   `default`/`optional` → both) and `uniqueIDRef`. What the object says wins over the same information in
//!   the referenced parameter, except that a parameter's `readWriteInput`/`readWriteOutput` refines an
//!   `accessType` of `rw` into `rwr`/`rww` (the schema's `accessType` has `ro`, `wo`, `rw`, `const` only;
//!   `rwr` and `rww` written there are accepted too). `objFlags` (hexBinary, CiA 306 §4.6.3 `ObjFlags`) of a
//!   `CANopenObject` → [`Object::flags`](crate::object::Object::flags), of a `CANopenSubObject` →
//!   [`SubObject::flags`](crate::object::SubObject::flags); one that is no hexadecimal number of 32 bits
//!   reads as none with a warning. `subNumber` and `denotation` are accepted and not kept.
//! - `dummyUsage/dummy entry="Dummy0005=1"`, `TransportLayers/PhysicalLayer/baudRate/supportedBaudRate`
//!   (`"250 Kbps"`), `NetworkManagement/CANopenGeneralFeatures` (`granularity`, `nrOfRxPDO`, `nrOfTxPDO`,
//!   `bootUpSlave`, `layerSettingServiceSlave`, `groupMessaging`, `dynamicChannels`; absent booleans are
//!   false, as the schema says) and `CANopenMasterFeatures@bootUpMaster` → [`CanInfo`], present whenever the
//!   file has a communication network profile; `deviceCommissioning` (`nodeID`, also CANopenEditor's
//!   `NodeID`, `nodeName`, `actualBaudRate`, `networkNumber`, `networkName`, `CANopenManager`) →
//!   [`Commissioning`]. `$NODEID` defaults are resolved with its node-ID (0 without one). A `nodeID` of
//!   0, 255 or an empty one is no node-ID: read as none (a node LSS configures), with a warning.
//! - A `defaultValue`, `lowLimit`, `highLimit` or `actualValue` (of an object or of its parameter) that
//!   is no value of the entry's type (`0x100000000` for an UNSIGNED32, `none`, a `$NODEID` default that
//!   does not fit for node-ID 127) is dropped with a warning at the value, as the EDS reader and
//!   python-canopen drop one; the entry and its other values stand.
//!
//! - A `dataType` that is no CiA 301 basic type is read with a warning: as DOMAIN (a complex or
//!   profile type, as EDS readers take them), or, in a POWERLINK file, the POWERLINK MAC_ADDRESS
//!   (0x0401) as a 6-octet OCTET_STRING, IP_ADDRESS (0x0402) as UNSIGNED32 and NETTIME (0x0403) as
//!   UNSIGNED64 (EPSG DS 301 §6.1.4).
//! - Other networks: a POWERLINK description (EPSG DS 311: `ProfileBody_Device_Powerlink`,
//!   `ProfileBody_CommunicationNetwork_Powerlink`) is the same XML with its object dictionary in
//!   `ObjectList/Object/SubObject`; it is read (as openCONFIGURATOR reads it) with a warning that says
//!   the file is POWERLINK, its network parts are not, and it has no [`CanInfo`]. A file whose only
//!   profile bodies are of another kind (`ProfileBody_Device_Modbus`, …) is refused, naming the kind.
//!
//! The two profile bodies may come in either order: the reader streams the file once, keeps small
//! per-object and per-parameter records, and resolves the references at the end. Element names are matched
//! without their namespace prefix (CANopenEditor writes `q1:parameter`). Unknown elements and attributes are
//! skipped; any other wrong value of a known one, a dangling `uniqueIDRef`, a type made of itself, an array or a
//! struct of more entries than there are sub-indices, and a duplicate index, sub-index or `uniqueID` are
//! errors naming the file, line and column.
//!
//! A parameter's `description` (else its `label` when that differs from the entry's name) is the description
//! of the object or sub-object that refers to it; an object whose value is inline (a VAR) gets it as the
//! description of the object and of sub-index 0. The `name` of the `array` or `struct` a structured object's
//! parameter refers to is its [`Object::type_name`](crate::object::Object::type_name). A parameter type
//! `BITSTRING` without a default reads as DOMAIN (that is how CANopenEditor writes domains), with one as
//! OCTET_STRING.
//!
//! # What is written
//!
//! Both profile bodies, `DeviceIdentity`, a `DeviceFunction` naming the product (the schema requires one), and
//! every entry with its attributes inline. A VAR, DOMAIN or DEFTYPE whose sub-index 0 has the object's name
//! and description and no `objFlags` of its own is one `CANopenObject`; any other object has
//! `CANopenSubObject`s. `objFlags` is written where the description has flags (4 hexadecimal digits, 8 for
//! flags beyond 16 bits), on the element they belong to, and nowhere else. A `parameterList` holds a
//! parameter, referenced by `uniqueIDRef` (`UID_OBJ_1018`, `UID_SUB_101801`), for each object or entry with a
//! description, a structure type name, a string capacity, or access `rwr`/`rww` (written as `rw` refined by the
//! parameter); a `dataTypeList` holds the named structure types. The output is byte-stable.
//!
//! What XDD cannot carry: [`FileInfo::file_revision`], [`FileInfo::format_version`], comments,
//! [`Commissioning::lss_serial_number`], the EtherCAT parts, ESI access restrictions, bit fields `BITn`
//! (written as BOOLEAN/UNSIGNED8), the capacity of UNICODE_STRING and DOMAIN entries, dummy types other than
//! 0x0001–0x0007, bit rates other than 10, 20, 50, 100, 125, 250, 500, 800 and 1000 kbit/s, explicitly set
//! values that are not `value_set`, and the revision number except as the default of 0x1018:03. Dates and
//! times must be XML Schema dates (`2024-05-31`) and times (`13:00:00`): EDS forms (`05-31-2024`, `1:00PM`)
//! are converted, anything else is left out, and a missing creation date is written as `1970-01-01` because
//! the schema requires one. The CAN parts of the communication network body (`dummyUsage`, `TransportLayers`,
//! `NetworkManagement`) are written only for a description with [`CanInfo`] (a POWERLINK or EtherCAT one has
//! none), and a file is read with `CanInfo` only when it has one of them; commissioning values of a
//! description without `CanInfo` come with the general features CiA 311 requires beside them, as
//! `CanInfo::default()`. Commissioning values without a node-ID of 1 to 127 (an unconfigured node) are left
//! out.
//!
//! [`FileInfo`]: crate::device::FileInfo
//! [`FileInfo::description`]: crate::device::FileInfo::description
//! [`FileInfo::file_revision`]: crate::device::FileInfo::file_revision
//! [`FileInfo::format_version`]: crate::device::FileInfo::format_version
//! [`Identity`]: crate::device::Identity
//! [`CanInfo`]: crate::device::CanInfo
//! [`Commissioning`]: crate::device::Commissioning
//! [`Commissioning::lss_serial_number`]: crate::device::Commissioning::lss_serial_number

mod reader;
mod writer;

pub use reader::{read, read_file};
pub use writer::write;

use crate::object::{AccessType, PdoMapping};
use crate::types::DataType;

/// The CiA 311 spelling of a PDO mapping (`PDOmapping` attribute).
fn pdo_name(pdo: PdoMapping) -> &'static str {
    match pdo {
        PdoMapping::None => "no",
        PdoMapping::Rpdo => "RPDO",
        PdoMapping::Tpdo => "TPDO",
        PdoMapping::Both => "optional",
    }
}

/// Parses a `PDOmapping` attribute.
fn parse_pdo(text: &str) -> Option<PdoMapping> {
    Some(match text.trim() {
        "no" => PdoMapping::None,
        "default" | "optional" => PdoMapping::Both,
        "RPDO" => PdoMapping::Rpdo,
        "TPDO" => PdoMapping::Tpdo,
        _ => return None,
    })
}

/// The parameter `access` spelling of an access type (ISO 15745 / CiA 311 `parameter@access`).
fn parameter_access_name(access: AccessType) -> &'static str {
    match access {
        AccessType::Const => "const",
        AccessType::Ro => "read",
        AccessType::Wo => "write",
        AccessType::Rw => "readWrite",
        AccessType::Rwr => "readWriteInput",
        AccessType::Rww => "readWriteOutput",
    }
}

/// Parses a parameter `access` attribute. `noAccess` has no CiA 301 equivalent and reads as read-only.
fn parse_parameter_access(text: &str) -> Option<AccessType> {
    match text.trim() {
        "const" => Some(AccessType::Const),
        "read" | "noAccess" => Some(AccessType::Ro),
        "write" => Some(AccessType::Wo),
        "readWrite" => Some(AccessType::Rw),
        "readWriteInput" => Some(AccessType::Rwr),
        "readWriteOutput" => Some(AccessType::Rww),
        _ => None,
    }
}

/// Parses an `accessType` attribute of a `CANopenObject` (CiA 306 spellings).
fn parse_access_type(text: &str) -> Option<AccessType> {
    Some(match text.trim() {
        "ro" => AccessType::Ro,
        "wo" => AccessType::Wo,
        "rw" => AccessType::Rw,
        "rwr" => AccessType::Rwr,
        "rww" => AccessType::Rww,
        "const" => AccessType::Const,
        _ => return None,
    })
}

/// A parameter data type element: a basic type, or `BITSTRING`, which is an OCTET_STRING or a DOMAIN
/// depending on the entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum XddType {
    Basic(DataType),
    BitString,
}

/// The data type named by a parameter type element (the IEC 61131 names of ISO 15745, plus the names
/// other tools write for the CiA 301 types that have none).
fn parse_type_element(name: &[u8]) -> Option<XddType> {
    Some(XddType::Basic(match name {
        b"BOOL" => DataType::Boolean,
        b"BITSTRING" => return Some(XddType::BitString),
        b"BYTE" | b"USINT" => DataType::Unsigned8,
        b"CHAR" | b"SINT" => DataType::Integer8,
        b"WORD" | b"UINT" => DataType::Unsigned16,
        b"DWORD" | b"UDINT" => DataType::Unsigned32,
        b"LWORD" | b"ULINT" => DataType::Unsigned64,
        b"INT" => DataType::Integer16,
        b"DINT" => DataType::Integer32,
        b"LINT" => DataType::Integer64,
        b"REAL" => DataType::Real32,
        b"LREAL" => DataType::Real64,
        b"STRING" => DataType::VisibleString,
        b"WSTRING" => DataType::UnicodeString,
        b"INT24" => DataType::Integer24,
        b"INT40" => DataType::Integer40,
        b"INT48" => DataType::Integer48,
        b"INT56" => DataType::Integer56,
        b"UINT24" => DataType::Unsigned24,
        b"UINT40" => DataType::Unsigned40,
        b"UINT48" => DataType::Unsigned48,
        b"UINT56" => DataType::Unsigned56,
        b"TIME_OF_DAY" => DataType::TimeOfDay,
        b"TIME" | b"TIME_DIFFERENCE" => DataType::TimeDifference,
        b"DOMAIN" => DataType::Domain,
        _ => return None,
    }))
}

/// The parameter type element written for a data type ([`DataType::xdd_name`]).
fn type_element(data_type: DataType) -> &'static str {
    data_type.xdd_name()
}

/// The name of CANopenNode's parameter property that gives the byte capacity of a string.
const STRING_LENGTH_PROPERTY: &str = "CO_stringLengthMin";

/// True for the types whose capacity [`STRING_LENGTH_PROPERTY`] carries.
fn has_string_capacity(data_type: DataType) -> bool {
    matches!(data_type, DataType::VisibleString | DataType::OctetString)
}

/// Parses a bit rate as CiA 311 writes it (`"250 Kbps"`); `auto-baudRate` answers 0.
fn parse_baud(text: &str) -> Option<u32> {
    let t = text.trim();
    if t.eq_ignore_ascii_case("auto-baudRate") {
        return Some(0);
    }
    let digits = t
        .strip_suffix("Kbps")
        .or_else(|| t.strip_suffix("kbps"))
        .or_else(|| t.strip_suffix("KBPS"))?
        .trim();
    if digits.is_empty() || digits.len() > 7 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// The CiA 311 spelling of a bit rate in kbit/s.
fn baud_name(kbps: u32) -> String {
    if kbps == 0 {
        "auto-baudRate".to_string()
    } else {
        format!("{kbps} Kbps")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spellings_round_trip() {
        for pdo in [
            PdoMapping::None,
            PdoMapping::Rpdo,
            PdoMapping::Tpdo,
            PdoMapping::Both,
        ] {
            assert_eq!(parse_pdo(pdo_name(pdo)), Some(pdo));
        }
        assert_eq!(parse_pdo("default"), Some(PdoMapping::Both));
        assert_eq!(parse_pdo("yes"), None);
        for a in [
            AccessType::Ro,
            AccessType::Wo,
            AccessType::Rw,
            AccessType::Rwr,
            AccessType::Rww,
            AccessType::Const,
        ] {
            assert_eq!(parse_parameter_access(parameter_access_name(a)), Some(a));
            assert_eq!(parse_access_type(a.as_str()), Some(a));
        }
        assert_eq!(parse_parameter_access("noAccess"), Some(AccessType::Ro));
        assert_eq!(parse_access_type("readWrite"), None);
        for &t in crate::types::STANDARD_TYPES {
            let back = parse_type_element(type_element(t).as_bytes()).unwrap();
            match back {
                XddType::Basic(b) => assert_eq!(b, t),
                XddType::BitString => assert_eq!(type_element(t), "BITSTRING"),
            }
        }
    }

    #[test]
    fn baud_rates() {
        assert_eq!(parse_baud("250 Kbps"), Some(250));
        assert_eq!(parse_baud("1000 Kbps"), Some(1000));
        assert_eq!(parse_baud("auto-baudRate"), Some(0));
        assert_eq!(parse_baud("fast"), None);
        assert_eq!(parse_baud(" Kbps"), None);
        assert_eq!(baud_name(125), "125 Kbps");
        assert_eq!(parse_baud(&baud_name(0)), Some(0));
    }
}
