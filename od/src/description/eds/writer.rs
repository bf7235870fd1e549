//! The EDS/DCF writer: sections in CiA 306 order, keys in a fixed order, CR LF line ends.

use std::borrow::Cow;
use std::fmt::Write as _;

use crate::device::{CanInfo, Commissioning, DeviceDescription};
use crate::object::{AccessType, DefaultValue, ObjFlags, Object, PdoMapping, SubObject};
use crate::types::DataType;
use crate::value::Value;

/// The bit rates of `[DeviceInfo]`, in kbit/s.
const BAUD_RATES: [u32; 8] = [10, 20, 50, 125, 250, 500, 800, 1000];

/// The objects CiA 306 lists in `[MandatoryObjects]`.
const MANDATORY: [u16; 3] = [0x1000, 0x1001, 0x1018];

pub(super) fn write(desc: &DeviceDescription) -> String {
    let mut w = IniWriter::default();
    file_info(&mut w, desc);
    device_info(&mut w, desc, desc.can.as_ref());
    // The commissioning section the description has (python-canopen's sample.eds has one, ros_canopen's
    // DCFs have none), so that its values keep the node-ID they were resolved with.
    if let Some(c) = &desc.commissioning {
        commissioning_section(&mut w, c);
    }
    // The node-ID the current values are resolved with: the description's, else 0 (an unconfigured node,
    // whose `$NODEID` values stay relative).
    let node_id = desc.node_id().unwrap_or(0);
    if let Some(can) = &desc.can {
        dummy_usage(&mut w, can);
    }
    comments(&mut w, &desc.comments);

    let objects: Vec<&Object> = desc.dictionary.objects().collect();
    let mandatory: Vec<u16> = objects
        .iter()
        .map(|o| o.index)
        .filter(|i| MANDATORY.contains(i))
        .collect();
    let manufacturer: Vec<u16> = objects
        .iter()
        .map(|o| o.index)
        .filter(|i| (0x2000..=0x5FFF).contains(i))
        .collect();
    let optional: Vec<u16> = objects
        .iter()
        .map(|o| o.index)
        .filter(|i| !MANDATORY.contains(i) && !(0x2000..=0x5FFF).contains(i))
        .collect();
    object_list(&mut w, "MandatoryObjects", &mandatory);
    object_list(&mut w, "OptionalObjects", &optional);
    object_list(&mut w, "ManufacturerObjects", &manufacturer);
    for object in objects {
        object_sections(&mut w, object, node_id);
    }
    w.out
}

/// Accumulates the text: a blank line between sections, CR LF after every line.
#[derive(Default)]
struct IniWriter {
    out: String,
}

impl IniWriter {
    fn section(&mut self, name: &str) {
        if !self.out.is_empty() {
            self.out.push_str("\r\n");
        }
        self.out.push('[');
        self.out.push_str(name);
        self.out.push_str("]\r\n");
    }

    fn key(&mut self, key: &str, value: &str) {
        self.out.push_str(key);
        self.out.push('=');
        self.out.push_str(&without_comment_start(one_line(value)));
        self.out.push_str("\r\n");
    }

    /// A `[Comments]` line: free text, written whole (readers keep its `;`).
    fn comment_line(&mut self, key: &str, value: &str) {
        self.out.push_str(key);
        self.out.push('=');
        self.out.push_str(&one_line(value));
        self.out.push_str("\r\n");
    }
}

/// `text` as an INI value can hold it: line breaks become spaces, and the blanks a reader trims go.
fn one_line(text: &str) -> Cow<'_, str> {
    let trimmed = text.trim_matches(|c: char| c.is_ascii_whitespace());
    if trimmed.contains(['\r', '\n']) {
        Cow::Owned(trimmed.replace(['\r', '\n'], " "))
    } else {
        Cow::Borrowed(trimmed)
    }
}

/// `text` without the blanks before a `;`, which would make the rest an inline comment for a reader
/// (this one, python-canopen's): `a ; b` is written `a; b`, never cut to `a`.
fn without_comment_start(mut out: Cow<'_, str>) -> Cow<'_, str> {
    while let Some(at) = comment_start(&out) {
        let kept = out[..at].trim_end_matches(is_blank).len();
        out.to_mut().replace_range(kept..at, "");
    }
    out
}

/// Where a `;` after white space is in `text` (where a reader's inline comment would start).
fn comment_start(text: &str) -> Option<usize> {
    let mut after_space = false;
    for (at, c) in text.char_indices() {
        if c == ';' && after_space {
            return Some(at);
        }
        after_space = is_blank(c);
    }
    None
}

/// White space as python-canopen's reader (Python's `str.isspace`) takes it.
fn is_blank(c: char) -> bool {
    c.is_whitespace() || ('\u{1c}'..='\u{1f}').contains(&c)
}

fn flag(b: bool) -> &'static str {
    if b {
        "1"
    } else {
        "0"
    }
}

fn file_info(w: &mut IniWriter, desc: &DeviceDescription) {
    let f = &desc.file_info;
    w.section("FileInfo");
    w.key("FileName", &f.file_name);
    w.key("FileVersion", &f.file_version);
    w.key("FileRevision", &f.file_revision);
    if !f.format_version.trim().is_empty() {
        w.key("EDSVersion", &f.format_version);
    }
    w.key("Description", &f.description);
    w.key("CreationTime", &f.creation_time);
    w.key("CreationDate", &f.creation_date);
    w.key("CreatedBy", &f.created_by);
    w.key("ModificationTime", &f.modification_time);
    w.key("ModificationDate", &f.modification_date);
    w.key("ModifiedBy", &f.modified_by);
}

/// `[DeviceInfo]`: the identity, and the CAN capabilities where the description has them.
fn device_info(w: &mut IniWriter, desc: &DeviceDescription, can: Option<&CanInfo>) {
    let id = &desc.identity;
    w.section("DeviceInfo");
    w.key("VendorName", &id.vendor_name);
    w.key("VendorNumber", &format!("0x{:08X}", id.vendor_id));
    w.key("ProductName", &id.product_name);
    w.key("ProductNumber", &format!("0x{:08X}", id.product_code));
    w.key("RevisionNumber", &format!("0x{:08X}", id.revision));
    w.key("OrderCode", &id.order_code);
    let Some(can) = can else {
        return;
    };
    for rate in BAUD_RATES {
        w.key(
            &format!("BaudRate_{rate}"),
            flag(can.baud_rates.contains(&rate)),
        );
    }
    w.key("SimpleBootUpMaster", flag(can.simple_boot_up_master));
    w.key("SimpleBootUpSlave", flag(can.simple_boot_up_slave));
    w.key("Granularity", &can.granularity.to_string());
    w.key(
        "DynamicChannelsSupported",
        &can.dynamic_channels.to_string(),
    );
    w.key("GroupMessaging", flag(can.group_messaging));
    w.key("NrOfRXPDO", &can.nr_of_rx_pdo.to_string());
    w.key("NrOfTXPDO", &can.nr_of_tx_pdo.to_string());
    w.key("LSS_Supported", flag(can.lss_supported));
}

fn commissioning_section(w: &mut IniWriter, c: &Commissioning) {
    w.section("DeviceComissioning");
    // No `NodeID=` for an unconfigured node: Lely reads its absence as unconfigured, where a made-up
    // node-ID would change what every `$NODEID` value means.
    if let Some(id) = c.node_id {
        w.key("NodeID", &id.to_string());
    }
    w.key("NodeName", &c.node_name);
    w.key("Baudrate", &c.baud_rate.to_string());
    w.key("NetNumber", &c.net_number.to_string());
    w.key("NetworkName", &c.network_name);
    w.key("CANopenManager", flag(c.canopen_manager));
    // Lely writes `LSS_SerialNumber` into 0x1018:04, and refuses the file where there is none: 0 (no
    // serial number given) is left out.
    if c.lss_serial_number != 0 {
        w.key(
            "LSS_SerialNumber",
            &format!("0x{:08X}", c.lss_serial_number),
        );
    }
}

fn dummy_usage(w: &mut IniWriter, can: &CanInfo) {
    w.section("DummyUsage");
    let mut indices: Vec<u16> = (1..=7).chain(can.dummy_usage.iter().copied()).collect();
    indices.sort_unstable();
    indices.dedup();
    for index in indices {
        w.key(
            &format!("Dummy{index:04X}"),
            flag(can.dummy_usage.contains(&index)),
        );
    }
}

fn comments(w: &mut IniWriter, lines: &[String]) {
    w.section("Comments");
    w.key("Lines", &lines.len().to_string());
    for (n, line) in lines.iter().enumerate() {
        w.comment_line(&format!("Line{}", n + 1), line);
    }
}

fn object_list(w: &mut IniWriter, name: &str, indices: &[u16]) {
    w.section(name);
    w.key("SupportedObjects", &indices.len().to_string());
    for (n, index) in indices.iter().enumerate() {
        w.key(&(n + 1).to_string(), &format!("0x{index:04X}"));
    }
}

fn object_sections(w: &mut IniWriter, object: &Object, node_id: u8) {
    w.section(&format!("{:04X}", object.index));
    w.key("ParameterName", &object.name);
    w.key("ObjectType", &format!("0x{:X}", object.kind.code()));
    if object.kind.has_subs() {
        // SubNumber is an UNSIGNED8: an object with all 256 sub-indices (CompactSubObj=255, as Lely reads
        // it) says 0xFF, and readers take the sections that are there.
        let sub_number = object.subs.len().min(0xFF);
        w.key("SubNumber", &format!("0x{sub_number:X}"));
        obj_flags(w, object.flags);
        for (&sub_index, sub) in &object.subs {
            w.section(&format!("{:04X}sub{sub_index:X}", object.index));
            w.key("ParameterName", &sub.name);
            w.key("ObjectType", "0x7");
            entry_keys(w, sub, sub.flags, node_id);
        }
    } else if let Some(sub) = object.subs.get(&0) {
        // One section for the object and its entry: the flags of both.
        let flags = match (object.flags, sub.flags) {
            (None, None) => None,
            (a, b) => Some(a.unwrap_or_default().union(b.unwrap_or_default())),
        };
        entry_keys(w, sub, flags, node_id);
    } else {
        obj_flags(w, object.flags);
    }
}

/// `ObjFlags=` where the description has flags (CiA 306 §4.6.3), and only there.
fn obj_flags(w: &mut IniWriter, flags: Option<ObjFlags>) {
    if let Some(flags) = flags {
        w.key("ObjFlags", &format!("0x{:X}", flags.bits()));
    }
}

/// The type an EDS writes for `data_type`: bit fields become BOOLEAN or UNSIGNED8.
fn eds_type(data_type: DataType) -> DataType {
    match data_type {
        DataType::Bit(1) => DataType::Boolean,
        DataType::Bit(_) => DataType::Unsigned8,
        t => t,
    }
}

/// `value` as text of the EDS type `data_type`. Times are written `days ms`, the form Lely reads (CiA 306
/// gives none, and python-canopen reads no time at all).
fn value_text(value: &Value, data_type: DataType) -> String {
    match (value, data_type) {
        (Value::Uint(v), DataType::Boolean) => Value::Bool(*v != 0).to_text(data_type),
        (Value::Time(t), _) => format!("{} {}", t.days, t.ms),
        _ => value.to_text(data_type),
    }
}

fn default_text(default: &DefaultValue, data_type: DataType) -> String {
    if !default.plus_node_id {
        return value_text(&default.value, data_type);
    }
    let mut text = String::from("$NODEID+");
    match default.value {
        Value::Uint(v) => {
            let _ = write!(text, "0x{v:X}");
        }
        ref other => text.push_str(&value_text(other, data_type)),
    }
    text
}

/// The access type an EDS carries for `sub`. EDS has only `PDOMapping=0/1` and tells the direction by the
/// access type (CiA 306 §4.6.3.2), so an entry mappable into RPDOs only is written `rww` and one mappable into
/// TPDOs only and writable is written `rwr`; an ESI output object (`ro` with `PdoMapping R`) becomes `rww`, as
/// the CANopen view of a process output is.
fn eds_access(sub: &SubObject) -> AccessType {
    match (sub.access.kind, sub.pdo) {
        (AccessType::Ro | AccessType::Rw, PdoMapping::Rpdo) => AccessType::Rww,
        (AccessType::Rw, PdoMapping::Tpdo) => AccessType::Rwr,
        (kind, _) => kind,
    }
}

fn entry_keys(w: &mut IniWriter, sub: &SubObject, flags: Option<ObjFlags>, node_id: u8) {
    let data_type = eds_type(sub.data_type);
    w.key("DataType", &format!("0x{:04X}", data_type.index()));
    w.key("AccessType", eds_access(sub).as_str());
    if let Some(default) = &sub.default {
        w.key("DefaultValue", &default_text(default, data_type));
    }
    w.key("PDOMapping", flag(sub.pdo.any()));
    if let Some(low) = &sub.low {
        w.key("LowLimit", &value_text(low, data_type));
    }
    if let Some(high) = &sub.high {
        w.key("HighLimit", &value_text(high, data_type));
    }
    obj_flags(w, flags);
    if let Some(current) = parameter_value(sub, node_id) {
        w.key("ParameterValue", &default_text(&current, data_type));
    }
}

/// The current value written for `sub` (`ParameterValue`): one that was set explicitly, or differs from
/// the default for the node `node_id` (the description's, 0 without one). A `$NODEID` default resolved
/// with node-ID 0, as an EDS reads it, counts as the default too, so a description read from an EDS gets
/// no `ParameterValue`s it did not ask for. A value given relative to the node-ID is written relative
/// again. `None` also when the bytes are no value of the type (nothing a reader could take back).
fn parameter_value(sub: &SubObject, node_id: u8) -> Option<DefaultValue> {
    let is = |value: Value| {
        value
            .encode(sub.data_type)
            .is_ok_and(|bytes| bytes == sub.value)
    };
    let at_default = match &sub.default {
        None => is(Value::zero(sub.data_type)),
        Some(default) => {
            is(default.resolve(node_id)) || (default.plus_node_id && is(default.resolve(0)))
        }
    };
    if at_default && !sub.value_set {
        return None;
    }
    sub.parameter(node_id)
}
