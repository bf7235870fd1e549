//! EtherCAT Slave Information (ESI) files: the `EtherCATInfo` XML of ETG.2000 ("EtherCAT Slave Information
//! Specification", schema `EtherCATInfo.xsd` with `EtherCATBase.xsd` and `EtherCATDict.xsd`), read into and
//! written from [`DeviceDescription`]s. This is the description-format layer: it knows XML elements, not SDOs.
//!
//! # What is read
//!
//! - `Vendor/Id` and `Vendor/Name` go into the identity of every device of the file; `Vendor@FileVersion`
//!   into [`FileInfo::file_version`](crate::device::FileInfo::file_version).
//! - `Descriptions/Devices/Device`: `Type` (`@ProductCode`, `@RevisionNo`, text = order code), `Name`
//!   (`LcId` 1033 preferred, else the first), `GroupType`, `Profile/Dictionary`, `Fmmu`, `Sm`, `RxPdo`/`TxPdo`,
//!   `Mailbox` (with the `InitCmd`s of `CoE`), `Dc/OpMode`, `Slots` and `Eeprom` (ETG.2000 `DeviceType`). An
//!   `EtherCATModule` file (ETG.2000 module description, a module catalogue) has no devices; each of its
//!   `Modules/Module` is read as a description of its own, with product code and revision 0 (a module has
//!   only a `ModuleIdent`), that knows it is a catalogue's module:
//!   [`EthercatInfo::root`](crate::device::EthercatInfo::root) is
//!   [`EsiRoot::EtherCatModule`](crate::device::EsiRoot::EtherCatModule) with what the module has beyond
//!   a device's parts (`Type@ModuleIdent`, `@ModuleClass`, `@ModulePdoGroup`, `Profile/ProfileNo`,
//!   `AddInfo`, `DcOpModeName`).
//! - Modular devices (ETG.2001): `Device/Slots` (`MaxSlotCount`, `MaxSlotGroupCount`, the PDO and index
//!   increments, `DownloadModuleIdentList`, `IdentifyModuleBy`; each `Slot` with `Name`, `SlotGroup`,
//!   `MinInstances`, `MaxInstances`, its own increments, `TreeView`, and the `ModuleIdent`s (with
//!   `Default`) or `ModuleClass`es (`Class`, `VendorId`, `Name`) it takes; the `ModulePdoGroup`s) into
//!   [`Slots`](crate::device::Slots); `Descriptions/Modules/Module` (`Type` with `ModuleIdent`,
//!   `ModuleClass`, `ModulePdoGroup`; `Name`, `RxPdo`/`TxPdo`, `Mailbox/CoE` with its `InitCmd`s,
//!   `Profile` with `ProfileNo`, `AddInfo` and `Dictionary`, `DcOpModeName`) into
//!   [`Module`](crate::device::Module)s. A module's PDOs speak about its dictionary as a device's do. The
//!   modules of a file belong to every device of it: each device's
//!   [`EthercatInfo::modules`](crate::device::EthercatInfo::modules) is the same shared list.
//! - The dictionary (ETG.2000 `DictionaryType`): `DataTypes/DataType` (`Name`, `BaseType`, `BitSize`,
//!   `SubItem` with `SubIdx`/`Name`/`Type`/`BitSize`/`BitOffs`/`Flags`/`Comment`, `ArrayInfo` with
//!   `LBound`/`Elements`, `EnumInfo` types resolve to their base type) and `Objects/Object` (`Index`, `Name`,
//!   `Comment`, `Type`, `BitSize`, `Info`, `Flags`).
//!
//! Object types (CiA 301 §7.4.3 object codes): an object whose `Type` is a basic type name (`UINT`,
//! `STRING(8)`, `ARRAY [0..3] OF BYTE`) is a VAR (DOMAIN for `DOMAIN`); a `DataType` with `SubItem`s is a
//! RECORD, or an ARRAY when it is the ETG layout "sub-index 0 plus one `SubItem` without `SubIdx` whose type
//! has `ArrayInfo`" (`DT1C00` / `DT1C00ARR`). An array element's sub-index is `LBound` + its position. A
//! `DataType` with `ArrayInfo` used directly as an object's type (`ARRAY [0..13] OF UINT` on a VAR) is one
//! value: an OCTET_STRING of the type's `BitSize`. The structure name is kept in
//! [`Object::type_name`](crate::object::Object::type_name). A RECORD or ARRAY whose type has no sub-index 0
//! gets the CoE one: `SubIndex 000`, USINT, ro, default = highest sub-index.
//!
//! `Object/Info/SubItem`s are matched to the structure's entries by position when they list every entry,
//! else by name and then by position; an array element takes its name from its `Info/SubItem`
//! (`SubIndex 001` when there is none).
//!
//! Values: `DefaultData`, `MinData` and `MaxData` are the value's little-endian bytes as hexBinary (ETG.2000
//! `ObjectInfoType`); `DefaultValue`, `MinValue`, `MaxValue` are numbers (`#x1A00` or decimal; `#xFFFF` is
//! -1 for an INT); `DefaultString` is text. Where both spellings are present the `…Data` one wins.
//! `MinData`/`MinValue` and `MaxData`/`MaxValue` become [`SubObject::low`](crate::object::SubObject::low)
//! and `high`. Real files give fixed-size values in fewer bytes than the type (`00` for a UINT), with zero
//! bytes beyond it, or with an odd number of digits (`2`); these read as the number they spell (missing
//! high bytes are zero). A limit that is no value of the type (vendors copy limits between objects,
//! `-4294967295` for a DINT) is dropped with a warning, and so is a default that is no value of its
//! type (`<DefaultValue>300</DefaultValue>` for a USINT, an empty `<DefaultData>` for a UDINT), as
//! the EDS and XDD readers drop theirs; a `DefaultData` longer than its type reads as its first bytes,
//! with a warning where the rest is not zeros. A string type shorter than its default (`STRING(0)` with a default, as SOES writes) takes the
//! default's size, with a warning. Numbers are HexDecValues (`#x1A00`, `0x1A00` or decimal); one with
//! both hexadecimal prefixes (`#x0x6041`) is read as the hexadecimal number, with a warning.
//!
//! Access (`Flags`): `Access` `ro`/`rw`/`wo` with `ReadRestrictions`/`WriteRestrictions` (`PreOp`,
//! `PreOp_SafeOp`, `PreOp_SafeOp_Op`, …), `PdoMapping` `R`, `T`, `RT`/`TR`. An entry of a structure takes
//! its `SubItem`'s flags; what they leave out comes from the object's `Flags` (not the PDO mapping of
//! sub-index 0); without either, `ro`. `Category` is ignored (the model has no field for it).
//!
//! `Sm`: `StartAddress`, the sizes, `ControlByte`, `Enable` as the number it is (the SII enable byte:
//! files write 0 or 1, some `9`; `true`/`false` read as 1/0), `Virtual`, `OpOnly` and `Watchdog`.
//!
//! `RxPdo`/`TxPdo`: `Index`, `Name`, `Exclude`s, the attributes `Fixed`, `Mandatory`, `Virtual`, `Sm`, `Su`,
//! `OSFac`, `OSMin`, `OSMax`, `OSIndexInc`, and each `Entry` (`Index`, `SubIndex`, `BitLen`, `Name`,
//! `Comment`, `DataType` with its `DScale`, the `Fixed` attribute); the `DependOnSlot`/`DependOnSlotGroup`
//! of every index. An entry with index 0 is a gap of its `BitLen`, and one at 0x0001–0x0007 a CiA 301
//! dummy entry, padding as well. A PDO that only names a template (`<RxPdo Ref="…"/>`, the obsolete
//! Beckhoff `Descriptions/Pdos` list of Version 1.2 files) is left out with a warning.
//!
//! `Dc/OpMode`: an absent `Factor` of `CycleTimeSync0`/`CycleTimeSync1` reads as 1.
//!
//! Descriptions: ESI carries meanings in `Object/Comment` (→
//! [`Object::description`](crate::object::Object::description), and for a VAR also the description of its
//! sub-index 0; when the object has none, its `DataType/Comment`) and `DataType/SubItem/Comment` (→ the
//! entry's description).
//!
//! The device's own PDOs speak about its dictionary too. An entry a PDO maps is mappable in the PDO's
//! direction: where its `PdoMapping` is missing or says otherwise (`R` for an entry a TxPdo maps), the
//! PDOs win, with a warning (the elements of an ARRAY share one `SubItem`, so all of them). An entry the
//! dictionary does not have (a device without `Profile/Dictionary` — couplers, Modules/Slots devices —
//! or a partial dictionary, with a warning) is made from the PDO entry that maps it: of its `DataType`
//! (ETG.2000 names, and the spellings `UINT8`…`UINT64`, `INT8`…`INT64`, `BITARR8/16/32`, `BYTE`, `WORD`,
//! `DWORD`, `BOOL`); a `DataType` that names no type, or none, gives an unsigned of the `BitLen`, a bit
//! field below 8 bits or an octet string of the bytes it covers, with a warning. The entry is
//! read-only, without default; a VAR for sub-index 0, else an entry of a RECORD (type name `DTxxxx`, as
//! the writer names it, or `DTxxxx_n` when the file uses that name) whose sub-index 0 counts up to the
//! highest entry, named after the first PDO that maps it. An entry that several PDOs map with
//! different lengths takes the first PDO's type (virtual PDOs map windows of ESC registers of any
//! length). Nothing else is made up: no mapping or assignment objects.
//!
//! # What is written
//!
//! Descriptions that are all devices of an `EtherCATInfoList` are written as one: an `EtherCATInfo` for
//! each run of descriptions of the same place in the list. Descriptions that are all modules of a
//! module catalogue are written as one: `EtherCATModule` with the
//! `Vendor` of the first and `Modules` with a `Module` per description, its elements in the order of
//! ETG.2001 `ModuleType` (`Type` with its attributes, `Name`, `RxPdo`s, `TxPdo`s, `Mailbox`, `Profile`
//! with `ProfileNo`, `AddInfo` and `Dictionary`, `DcOpModeName`) as for a module of an `EtherCATInfo`;
//! a device's parts such a description may carry (sync managers, slots, …) have no place there and are
//! left out. Any other set of descriptions, a catalogue's modules among devices too, is written as
//! a complete `EtherCATInfo` file: `Vendor`, one `Group` per distinct `GroupType`, one `Device` per
//! description, and `Modules` with each distinct module of the descriptions once (reading the file back
//! gives every device all of them: descriptions from different files, written together, share their
//! modules). `DataTypes` come from the dictionary: one `DataType` per basic type used, and per RECORD or
//! ARRAY one structure type named after `type_name` (else `DTxxxx`) with the standard CoE layout (sub-index 0
//! USINT at bit offset 0, sub-index 1 at offset 16 — after a wider sub-index 0, such as DS301's UNSIGNED32
//! in 0x1004, at the next 16-bit boundary —, the rest packed). An ARRAY whose entries are uniform
//! (same type, size, access, mapping, comment) and numbered 1…n is written with an `…ARR` type carrying
//! `ArrayInfo`; any other ARRAY is written entry by entry and reads back as a RECORD. Objects carry
//! `Info/DefaultData` (little-endian hex, strings too), `MinData`/`MaxData` where limits exist, `Flags` with
//! `Access`, restrictions and `PdoMapping`, and `Comment`s for descriptions. Sync managers, PDOs, CoE
//! `InitCmd`s and `Slots` are written with everything the model keeps of them; a module's `Profile`
//! always holds a `Dictionary` (the one its PDOs made when the file had none), so that it reads back the
//! same.
//!
//! When a description has no EtherCAT part (a CANopen device written as ESI) the writer derives a minimal
//! valid one and says so in an XML comment:
//! - `RxPdo`s from the mapping objects 0x1600–0x17FF and `TxPdo`s from 0x1A00–0x1BFF: index and name of the
//!   object, entries from the default mapping (sub-index 0 = count, each entry `index << 16 | sub << 8 |
//!   bits`; CiA 301 dummy mappings 0x0001–0x0007 become gaps); `Fixed` when the mapping is read-only; the PDO
//!   is assigned to SM2/SM3 (`Sm` attribute) unless its CANopen communication object (0x1400/0x1800 + n)
//!   marks it invalid (COB-ID bit 31);
//! - the standard four sync managers (MBoxOut 0x1000, MBoxIn 0x1080, both 128 bytes; Outputs 0x1100,
//!   Inputs 0x1400 sized by the assigned PDOs), FMMUs Outputs/Inputs/MBoxState;
//! - a CoE mailbox with SDO information; `PdoConfig` when a mapping object is writable;
//! - `GroupType` = the order code, else the product name.
//!
//! # What ESI cannot carry
//!
//! File information other than the file version, CANopen communication data
//! ([`CanInfo`](crate::device::CanInfo)), DCF commissioning values and current values, `[Comments]`, the
//! access types `const`, `rwr` and `rww` (written as `ro`, `rw`, `rw`), the DEFTYPE/DEFSTRUCT/NULL object
//! codes, `$NODEID` defaults (written resolved for the DCF's node-ID, or as the plain offset), unbounded
//! strings (written with the length of their default), a VAR whose entry has another name or description
//! than the object, an ARRAY whose entries are not uniform or not numbered 1…n (it reads back as a
//! RECORD).
//!
//! Read but not kept (the model has no place for them): group display names (a written group is named
//! after its type), `Device@Physics`, `Category`, `EnumInfo` texts, the `Factor` of `ShiftTimeSync0/1`,
//! `Info` (electrical data, timeouts), `HideType`, a device's `Profile/ProfileNo`, the `InitCmd`s of
//! `EoE`, `SoE` and `AoE`, `Fmmu` attributes, `Slots/SlotSelections`, a module's `SafetyParaMapping`s,
//! `SRA_ParameterSupported` and `VendorSpecific`, the templates of an obsolete `Descriptions/Pdos` list,
//! images (a same-format rewrite keeps them all: `crate::carry`).
//!
//! A file with the root `EtherCATInfoList` (ETG.2000's list of `EtherCATInfo`s, as IgH's `ethercat xml`
//! writes the slaves of a bus) is read as its `EtherCATInfo`s one after the other, each with its own
//! vendor, file version and modules; its devices know their place in the list
//! ([`crate::device::EsiRoot::EtherCatInfoList`]) and are written back as the list.

mod derive;
mod reader;
mod writer;

use crate::device::DeviceDescription;
use crate::error::{ParseError, Position};
use crate::report::Reading;

/// Which device of a file [`read`] answers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Select {
    /// The device whose `Type` text (order code) or `Name` is this, compared case-insensitively.
    Name(String),
    /// The device with this `Type@ProductCode`.
    ProductCode(u32),
}

/// Reads every device of an ESI file (`EtherCATInfo`), or every module of an `EtherCATModule` file (a
/// module catalogue, which each module's description records).
///
/// `source_name` names the file in errors. The vendor's `Id` and `Name` go into each identity.
pub fn read_all(bytes: &[u8], source_name: &str) -> Result<Vec<DeviceDescription>, ParseError> {
    reader::read_all(bytes, source_name).map(|r| r.devices)
}

/// Reads every device of an ESI file as [`read_all`] does, with where each part was read and the
/// reader's warnings.
pub fn read_file(bytes: &[u8], source_name: &str) -> Result<Reading, ParseError> {
    reader::read_all(bytes, source_name)
}

/// Reads one device of an ESI file.
///
/// With `select` = `None` the file must describe exactly one device; with several, the error lists them
/// (type name and product code) and asks to choose one. When a selection matches several revisions of one
/// device, the highest revision is answered (as EtherCAT configuration tools do); a selection that matches
/// different devices is refused with the list of them.
pub fn read(
    bytes: &[u8],
    source_name: &str,
    select: Option<&Select>,
) -> Result<DeviceDescription, ParseError> {
    let devices = read_all(bytes, source_name)?;
    choose(devices, source_name, select)
}

fn describe(d: &DeviceDescription) -> String {
    format!(
        "`{}` (product code #x{:08X}, revision #x{:08X})",
        if d.identity.order_code.is_empty() {
            &d.identity.product_name
        } else {
            &d.identity.order_code
        },
        d.identity.product_code,
        d.identity.revision
    )
}

fn choose(
    devices: Vec<DeviceDescription>,
    source_name: &str,
    select: Option<&Select>,
) -> Result<DeviceDescription, ParseError> {
    let at = Position { line: 1, column: 1 };
    let list = |ds: &[&DeviceDescription]| {
        ds.iter()
            .map(|d| describe(d))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let Some(select) = select else {
        let count = devices.len();
        return match count {
            0 => Err(ParseError::new(
                source_name,
                at,
                "the file describes no device",
            )),
            1 => Ok(devices.into_iter().next().unwrap_or_default()),
            _ => {
                let all: Vec<&DeviceDescription> = devices.iter().collect();
                Err(ParseError::new(
                    source_name,
                    at,
                    format!(
                        "the file describes {count} devices: {}; choose one by type name or product code",
                        list(&all)
                    ),
                ))
            }
        };
    };
    let matches = |d: &DeviceDescription| match select {
        Select::Name(name) => {
            let name = name.trim();
            d.identity.order_code.trim().eq_ignore_ascii_case(name)
                || d.identity.product_name.trim().eq_ignore_ascii_case(name)
        }
        Select::ProductCode(code) => d.identity.product_code == *code,
    };
    let hits: Vec<usize> = (0..devices.len())
        .filter(|&i| matches(&devices[i]))
        .collect();
    let Some(&first) = hits.first() else {
        let all: Vec<&DeviceDescription> = devices.iter().collect();
        let wanted = match select {
            Select::Name(n) => format!("named `{n}`"),
            Select::ProductCode(c) => format!("with product code #x{c:08X}"),
        };
        return Err(ParseError::new(
            source_name,
            at,
            format!(
                "the file describes no device {wanted}; it describes {}",
                if all.is_empty() {
                    "none".to_string()
                } else {
                    list(&all)
                }
            ),
        ));
    };
    let same_device = hits.iter().all(|&i| {
        devices[i].identity.product_code == devices[first].identity.product_code
            && devices[i]
                .identity
                .order_code
                .eq_ignore_ascii_case(&devices[first].identity.order_code)
    });
    if !same_device {
        let found: Vec<&DeviceDescription> = hits.iter().map(|&i| &devices[i]).collect();
        return Err(ParseError::new(
            source_name,
            at,
            format!(
                "the selection matches {} devices: {}; choose one by {}",
                found.len(),
                list(&found),
                match select {
                    Select::Name(_) => "product code",
                    Select::ProductCode(_) => "type name",
                }
            ),
        ));
    }
    // Several revisions of one device: the newest, the first of equals.
    let mut best = first;
    for &i in &hits {
        if devices[i].identity.revision > devices[best].identity.revision {
            best = i;
        }
    }
    Ok(devices.into_iter().nth(best).unwrap_or_default())
}

/// Writes one description as a complete ESI file (UTF-8, byte-stable).
pub fn write(desc: &DeviceDescription) -> String {
    writer::write_all(std::slice::from_ref(desc))
}

/// Writes several descriptions as one ESI file with one `Device` each, or, when they are all modules of
/// a module catalogue, as an `EtherCATModule` file with one `Module` each; the vendor (and file
/// version) is taken from the first.
pub fn write_all(descs: &[DeviceDescription]) -> String {
    writer::write_all(descs)
}
