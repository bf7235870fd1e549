//! CiA 306 electronic data sheets (EDS) and device configuration files (DCF): the INI-style description of a
//! CANopen device, read into and written from a [`DeviceDescription`].
//!
//! This is the description layer: no IO, no protocol. [`read`] takes the bytes of an EDS or a DCF,
//! [`write_eds`] and [`write_dcf`] give back the text of one.
//!
//! # What is read (CiA 306-1)
//!
//! - `[FileInfo]` → [`FileInfo`](crate::device::FileInfo); `[DeviceInfo]` → the
//!   [`Identity`](crate::device::Identity) and the [`CanInfo`]; `[DummyUsage]`
//!   → [`CanInfo::dummy_usage`](crate::device::CanInfo::dummy_usage); `[Comments]` →
//!   [`DeviceDescription::comments`] (CiA 306-1 §4, the general sections of an EDS).
//! - The object lists `[MandatoryObjects]`, `[OptionalObjects]`, `[ManufacturerObjects]`: every entry
//!   must be an object index; a listed object without its section is skipped (CiA 306 wants one, real
//!   files such as python-canopen's `e35.eds` forget it). Objects that have a section but are missing from the
//!   lists are read too (real files forget to list them), as python-canopen reads them. Where Lely, which
//!   reads the lists, would read otherwise, a warning says so: a `SupportedObjects=` that is not the number
//!   of entries, an object listed twice, a listed object without its section, and (one warning) the
//!   objects in no list.
//! - Object descriptions (§4.6.3): `[1018]` and `[1018sub1]` with `ParameterName`, `ObjectType` (VAR when
//!   absent), `DataType`, `AccessType`, `DefaultValue`, `PDOMapping`, `LowLimit`, `HighLimit`, `SubNumber`,
//!   `ObjFlags`, `CompactSubObj`, and `ParameterValue` (§5: in a DCF, and in EDS files such as
//!   python-canopen's `e35.eds`). `Denotation`, `UploadFile`,
//!   `DownloadFile` and unknown keys (`StorageLocation`, `Factor`…) are skipped.
//! - Compact storage (§4.6.3, `CompactSubObj`): `CompactSubObj=N` on an ARRAY describes sub-indices
//!   1..N with the object's own keys. `CompactSubObj=255` (python-canopen's `receiver.eds`) reaches
//!   sub-index 0xFF, which CiA 301 keeps for the object's structure: read as 255 entries, as Lely builds
//!   them, with a warning. Sub-index 0 is implied: `NrOfObjects`, UNSIGNED8, `ro`, default N. The names
//!   come from `[xxxxName]` (`NrOfEntries=`, `1=name`…), else they are the object's name followed by the
//!   sub-index in decimal (`Valve 1 % Open3`); current values come from `[xxxxValue]`. Explicit
//!   `[xxxxsubN]` sections, where a file has them as well, win.
//! - Values (§4.6.2) as [`Value::parse_text`](crate::value::Value::parse_text) reads them, plus
//!   `$NODEID` (case-insensitive) as `$NODEID`, `$NODEID+0x180` or `0x180+$NODEID` in integer
//!   `DefaultValue`s and `ParameterValue`s: the offset is kept with
//!   [`DefaultValue::plus_node_id`](crate::object::DefaultValue::plus_node_id) and
//!   [`SubObject::value_plus_node_id`](crate::object::SubObject::value_plus_node_id).
//! - Inline comments: a value ends before a `;` that follows white space (`DefaultValue=0x3ED ;
//!   prevent homing` is 1005, a tab before the `;` as well), for every key, as python-canopen's
//!   configparser reads them; a `;` right after the value (`1005;c`) is part of it, which is then no
//!   number and is dropped with a warning, as python-canopen drops it. `[Comments]` lines are free
//!   text and kept whole. The comment is not kept in the description; the writer never writes a text
//!   that a reader would cut (it drops the blanks before a `;` in one: `a ; b` is written `a; b`).
//! - `AccessType=R` and `AccessType=W` (no CiA 306 access types, but python-canopen reads them) are `ro`
//!   and `wo`, with a warning. A REAL32 or REAL64 value in hexadecimal is its IEEE 754 bits, as Lely
//!   writes them (`0x40490FDB` is π).
//! - `PDOMapping=1` becomes a direction from the access type: `ro`, `const`, `rwr` → TPDO; `wo`, `rww` →
//!   RPDO; `rw` → both.
//! - `ObjFlags` (§4.6.3: bit 0 refuse write on download, bit 1 refuse read on scan) of an object's section
//!   → [`Object::flags`](crate::object::Object::flags) (a VAR's too: its one section is the object's), of
//!   a sub-index section → [`SubObject::flags`](crate::object::SubObject::flags); an object's flags are not
//!   copied into its sub-indices (a tool takes both: [`Object::flags_of`](crate::object::Object::flags_of)).
//!   Absent, empty or no number (`ObjFlags=NV`, read with a warning): none.
//! - A DCF (§5) is an EDS with `[DeviceComissioning]` (`NodeID`, `NodeName`, `Baudrate`, `NetNumber`,
//!   `NetworkName`, `CANopenManager`, `LSS_SerialNumber`; the correctly spelled `[DeviceCommissioning]` is
//!   accepted too) and `ParameterValue`s: it sets
//!   [`DeviceDescription::commissioning`] and the current values.
//! - The node-ID: `NodeID=` 1 to 127. Lely's DCFs of a node that LSS is yet to configure say
//!   `NodeID=0xFF`, or have no `NodeID` (or no section) at all; Lely reads both as unconfigured, and so
//!   does the reader: [`Commissioning::node_id`](crate::device::Commissioning::node_id) is `None`, with a
//!   warning where a section says `NodeID=0xFF`, `NodeID=0`, another number that is no node-ID, or nothing.
//!   A `NodeID` that is no number at all is an error.
//!
//! After reading, every entry's current value (`SubObject::value`) is its default resolved with the
//! node-ID: the DCF's `NodeID`, or 0 in an EDS and for an unconfigured node (so `$NODEID+0x180` reads as
//! 0x180, to be resolved when a node with a node-ID resets its dictionary, or by [`set_node_id`]); zero
//! where there is no default. A `ParameterValue` sets the value and `value_set`. A `ParameterValue`
//! relative to the node-ID (`$NODEID+0x80000200`: ros_canopen's DCFs are templates for a node whose ID is
//! set at run time, and have no `[DeviceComissioning]`) is resolved the same way and keeps
//! [`SubObject::value_plus_node_id`](crate::object::SubObject::value_plus_node_id), so that it is written
//! relative again and follows [`set_node_id`]. A value relative to the node-ID, default or parameter,
//! must fit for node 127 when the file gives no node-ID, or a DCF written from it for node 127 could not
//! be read: one that does not is dropped with a warning.
//!
//! [`set_node_id`]: crate::device::DeviceDescription::set_node_id
//!
//! # Reading rules
//!
//! Section names and keys are case-insensitive; keys and values are trimmed of ASCII white space; blank lines
//! and lines starting with `;` (or `#`) are skipped; lines end in LF or CR LF; a UTF-8 byte-order mark is
//! skipped, and a file that is not UTF-8 is read as ISO-8859-1. Unknown sections and keys are skipped.
//! Findings name the line and column of the value (see [`crate::report`] for what is an error and what
//! a warning).
//!
//! A value of `DefaultValue`, `LowLimit`, `HighLimit`, `ParameterValue` or an `[xxxxValue]` entry that
//! is no value of the entry's type (`0xDEADBEEF` for an INTEGER16, `0` for an OCTET_STRING, `$NODEID` in
//! a limit or on a REAL32) is dropped with a warning, as python-canopen skips a value it cannot convert:
//! the entry loads without it. A C integer suffix (`0x1234567890ABCDEFLL`, `0x100u`: CANopenNode's
//! editor writes them) is dropped with a warning and the number read, as Lely's C lexer reads it.
//! `ObjectType` and `DataType` given by their CiA 301 names (`VAR`, `UNSIGNED32`: CANopenEditor's Python
//! port writes them) are read with a warning; neither python-canopen nor Lely reads a name, but a name
//! says which code or type as plainly as the number. TIME_OF_DAY and TIME_DIFFERENCE values are read as
//! `days:ms`, as Lely's `days ms`, or as a plain millisecond count.
//!
//! Errors: a line that is neither `[section]`, `key=value`, blank nor a comment; a key before the first
//! section; a section or a known key that appears twice; a sub-index section without its object's
//! section, or under a VAR; a structural value that no reading makes fit (an object code that does not
//! exist, a data type that is neither an index nor a name, an access type that is none of CiA 306's, a
//! number key such as `VendorNumber` or `NodeID` that is no number, `PDOMapping` other than 0 or 1).
//!
//! Choices where files and the standard disagree, so that the real files of the corpus read: an empty
//! value of a numeric key (`VendorNumber=`, `DefaultValue=` of an integer) counts as absent; a `DataType` of
//! the complex and profile range 0x0020–0x025F (a structure the model cannot describe), or one no standard
//! defines, is read as DOMAIN with a warning, as python-canopen and Lely take it; a DOMAIN `DefaultValue` or
//! `ParameterValue` that is not hexadecimal bytes is not kept (tools write domain contents in different
//! notations, and CiA 306 gives them through `UploadFile`/`DownloadFile`; a warning says so);
//! `LowLimit`/`HighLimit` are read for numeric types only.
//!
//! The parser is a small line scanner rather than the `rust-ini` crate: an error has to name the line and
//! column of the offending value (a bad `DataType=` found while building the dictionary), and `rust-ini`
//! keeps no positions. An EDS is the simplest INI there is (`[section]`, `key=value`, `;` comments, no
//! quoting, escapes or continuation lines), so the scanner is a few dozen lines: one pass that keeps the
//! sections and keys as slices of the text, without a copy per key; positions are worked out from a slice's
//! offset, through an index of the line starts made on the first request (the source map asks for one per
//! section). A release build reads the generated 1.3 MB EDS of `cargo bench -p od --bench readers` at
//! about 100 MiB/s.
//!
//! # What is written
//!
//! [`write_eds`] writes the description as it was read, in CiA 306 order: `[FileInfo]`, `[DeviceInfo]`,
//! `[DeviceComissioning]` when the description has commissioning values (an EDS may carry them:
//! python-canopen's `sample.eds` does, and its `$NODEID` values need the node-ID to read back the same),
//! `[DummyUsage]`, `[Comments]`, `[MandatoryObjects]` (0x1000, 0x1001, 0x1018 where present),
//! `[OptionalObjects]` (the other objects of 0x0000–0x1FFF and 0x6000–0xFFFF), `[ManufacturerObjects]`
//! (0x2000–0x5FFF), then the object sections in index order, every ARRAY and RECORD with one section per
//! sub-index (never compact: a compact array's `[xxxxName]` and `[xxxxValue]` entries become the names and
//! `ParameterValue`s of its sub-index sections; an object with all 256 sub-indices says `SubNumber=0xFF`,
//! the largest value the key holds). `ObjFlags=0x…` is written where the description has flags, an
//! explicit `0` too, and nowhere else, so a file without `ObjFlags` gains none; a VAR whose entry has
//! flags of its own (an XDD can say so) gets them in its one section with the object's. A `ParameterValue` is written for every entry whose current value was
//! set explicitly (`value_set`: python-canopen's `e35.eds` has them in an EDS) or differs from its
//! default for the node-ID; a value given relative to the node-ID is written `$NODEID+offset` again. Lines
//! end in CR LF, as CiA 306 files usually do and as Windows tools expect; keys come in a fixed order and
//! there are no timestamps, so the output is byte-stable. Numbers are hexadecimal (`0x0007`), defaults that
//! add the node-ID are written `$NODEID+0x180`, bit fields (ESI `BITn`) as BOOLEAN or UNSIGNED8, times as
//! `days ms` (the form Lely reads; CiA 306 gives none).
//!
//! [`write_dcf`] writes the same; `[DeviceComissioning]` is written when the description has commissioning
//! values (a DCF read without the section, as ros_canopen's, is written without it; `esi-gen dcf` always
//! gives one). The node-ID is the description's
//! [`Commissioning::node_id`](crate::device::Commissioning::node_id); a description without one (an EDS, an
//! unconfigured node) is written without `NodeID=` (Lely reads that as unconfigured, where a made-up
//! node-ID would change what every `$NODEID` value means), and without commissioning values the others
//! are empty or zero. `LSS_SerialNumber` is left out when it is 0: Lely writes it into 0x1018:04 and
//! refuses a file without that entry. An entry that still holds its `$NODEID` default as an EDS reads it
//! (resolved with node-ID 0) counts as the default, so a description read from an EDS and written for
//! another node (without [`DeviceDescription::set_node_id`](crate::device::DeviceDescription::set_node_id))
//! gets its COB-IDs resolved for that node when read back.
//!
//! A DCF that configures a device has a `ParameterValue` for every configurable entry, so that a
//! configuration tool applying it (`sdo-tool apply`) writes them all: `esi-gen dcf` marks them with
//! [`DeviceDescription::configure_writable`](crate::device::DeviceDescription::configure_writable) first
//! (writable entries, not DOMAINs nor the command entries 0x1003:00, 0x1010, 0x1011, 0x1F25, 0x1F51;
//! one still at its `$NODEID` default is written relative, `ParameterValue=$NODEID+0x180`). Read back, those
//! entries are `value_set`.
//!
//! # What EDS cannot carry
//!
//! Descriptions (`Object::description`, `SubObject::description`), structure type names
//! (`Object::type_name`), string and domain capacities (`SubObject::bit_size` reads back as the type's size,
//! `None` for strings and domains), bit-field types (`BITn`), EtherCAT state restrictions of access, the PDO
//! direction beyond what the access type implies, an object name that differs from the name of its VAR entry,
//! the EtherCAT parts, bit rates other than the eight of CiA 306, and strings with line breaks or leading or
//! trailing blanks. What a file left out is left out again: a description without
//! [`CanInfo`] (an EDS whose `[DeviceInfo]` has no CAN keys) is written without the
//! CAN keys of `[DeviceInfo]` and without `[DummyUsage]`, an empty `format_version` (a file without
//! `EDSVersion`, as Lely's) without `EDSVersion`; a new file gets both from [`complete_new_file`].

mod reader;

pub(crate) use reader::without_comment;
mod writer;

use crate::device::{CanInfo, DeviceDescription};
use crate::error::ParseError;
use crate::report::Reading;

/// Reads an EDS or a DCF. `source_name` names the file in errors.
///
/// A DCF (a file with `[DeviceComissioning]`) sets [`DeviceDescription::commissioning`], and its
/// `ParameterValue`s set the current values.
pub fn read(bytes: &[u8], source_name: &str) -> Result<DeviceDescription, ParseError> {
    let mut reading = reader::read(bytes, source_name)?;
    Ok(reading.devices.pop().unwrap_or_default())
}

/// Reads an EDS or a DCF as [`read`] does, with where each object was read and the reader's warnings.
pub fn read_file(bytes: &[u8], source_name: &str) -> Result<Reading, ParseError> {
    reader::read(bytes, source_name)
}

/// The `EDSVersion` of the files this crate writes: CiA 306 v1.3's file format 4.0.
pub const EDS_VERSION: &str = "4.0";

/// Gives a description that is to become a new EDS or DCF what CiA 306 asks of one and it lacks (a
/// description read from ESI or XDD, or from a file that left them out): the file format version
/// [`EDS_VERSION`], and the CAN capabilities of `[DeviceInfo]` (`CanInfo::default()`).
pub fn complete_new_file(desc: &mut DeviceDescription) {
    if desc.file_info.format_version.trim().is_empty() {
        desc.file_info.format_version = EDS_VERSION.to_string();
    }
    desc.can.get_or_insert_with(CanInfo::default);
}

/// Writes an EDS (CR LF line ends, byte-stable): file and device information, the commissioning values
/// the description has, object lists and object sections with the current values that were set or differ
/// from their defaults.
pub fn write_eds(desc: &DeviceDescription) -> String {
    writer::write(desc)
}

/// Writes a DCF: the EDS of [`write_eds`], with the `[DeviceComissioning]` of
/// [`DeviceDescription::commissioning`] (a DCF without one, as ros_canopen's, stays without one; a new DCF
/// gets one by [`DeviceDescription::set_node_id`]); without a node-ID there, there is no `NodeID=`. For a DCF that configures every
/// writable entry, mark them first with [`DeviceDescription::configure_writable`].
pub fn write_dcf(desc: &DeviceDescription) -> String {
    writer::write(desc)
}
