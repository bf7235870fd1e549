//! XDD writer (CiA 311): both profile bodies, every entry with its attributes inline, and a parameter list
//! only for what the object list cannot say (descriptions, structure type names, string capacities).

use crate::device::{CanInfo, Commissioning, DeviceDescription, FileInfo};
use crate::object::{AccessType, ObjFlags, Object, ObjectKind, SubObject};
use crate::types::DataType;
use crate::value::Value;
use crate::xml::XmlWriter;

use super::{
    baud_name, has_string_capacity, parameter_access_name, pdo_name, type_element,
    STRING_LENGTH_PROPERTY,
};

/// The namespace of the CiA 311 schema the output follows.
const NAMESPACE: &str = "http://www.canopen.org/xml/1.0";
const XSI: &str = "http://www.w3.org/2001/XMLSchema-instance";
/// The bit rates the schema lists for `supportedBaudRate`, in kbit/s.
const BAUD_RATES: [u32; 9] = [10, 20, 50, 100, 125, 250, 500, 800, 1000];
/// The creation date written when the description has none (the schema requires one).
const NO_DATE: &str = "1970-01-01";

/// Writes `desc` as a complete XDD (UTF-8, byte-stable: the same description always gives the same text).
/// Writes an XDC's `deviceCommissioning` when the description has commissioning values with a node-ID of
/// 1 to 127, and `actualValue`s for the explicitly set values.
pub fn write(desc: &DeviceDescription) -> String {
    let mut w = XmlWriter::new();
    w.start(
        "ISO15745ProfileContainer",
        &[("xmlns", NAMESPACE), ("xmlns:xsi", XSI)],
    );
    let file_attrs = file_attributes(&desc.file_info);

    w.start("ISO15745Profile", &[]);
    header(&mut w, desc, "CANopen device profile", "Device");
    let mut body: Vec<(&str, &str)> = vec![("xsi:type", "ProfileBody_Device_CANopen")];
    body.extend(file_attrs.iter().map(|(k, v)| (*k, v.as_str())));
    w.start("ProfileBody", &body);
    device_identity(&mut w, desc);
    device_function(&mut w, desc);
    application_process(&mut w, desc);
    w.end();
    w.end();

    w.start("ISO15745Profile", &[]);
    header(
        &mut w,
        desc,
        "CANopen communication network profile",
        "CommunicationNetwork",
    );
    let mut body: Vec<(&str, &str)> =
        vec![("xsi:type", "ProfileBody_CommunicationNetwork_CANopen")];
    body.extend(file_attrs.iter().map(|(k, v)| (*k, v.as_str())));
    w.start("ProfileBody", &body);
    w.start("ApplicationLayers", &[]);
    w.start("CANopenObjectList", &[]);
    for object in desc.dictionary.objects() {
        write_object(&mut w, object);
    }
    w.end();
    // The CAN parts only for a description that has them (a POWERLINK one has not), or the defaults
    // the network management of a configured node needs (read back as CAN parts: the same text).
    let default_can = CanInfo::default();
    if let Some(can) = written_can(desc, &default_can) {
        w.start("dummyUsage", &[]);
        // The schema knows Dummy0001 to Dummy0007 only.
        for d in 1..=7u16 {
            let used = u8::from(can.dummy_usage.contains(&d));
            w.empty("dummy", &[("entry", &format!("Dummy{d:04X}={used}"))]);
        }
        w.end();
    }
    w.end();
    write_network(&mut w, desc);
    w.end();
    w.end();
    w.finish()
}

/// The commissioning values of a configured node (a node-ID of 1 to 127) and that node-ID.
fn configured(desc: &DeviceDescription) -> Option<(&Commissioning, u8)> {
    desc.commissioning.as_ref().and_then(|c| {
        c.node_id
            .filter(|id| (1..=127).contains(id))
            .map(|id| (c, id))
    })
}

/// The CAN parts written: the description's, or for a configured node without them the defaults
/// (CANopenGeneralFeatures is required in NetworkManagement, as an EDS writes them); none otherwise.
fn written_can<'a>(desc: &'a DeviceDescription, default: &'a CanInfo) -> Option<&'a CanInfo> {
    match (&desc.can, configured(desc)) {
        (Some(can), _) => Some(can),
        (None, Some(_)) => Some(default),
        (None, None) => None,
    }
}

/// The transport layers and network management of a CANopen network body: the CAN capabilities, when
/// the description has them, and the commissioning values of a configured node.
fn write_network(w: &mut XmlWriter, desc: &DeviceDescription) {
    let configured = configured(desc);
    let default_can = CanInfo::default();
    let Some(can) = written_can(desc, &default_can) else {
        return;
    };
    w.start("TransportLayers", &[]);
    w.start("PhysicalLayer", &[]);
    w.start("baudRate", &[]);
    let mut rates = can.baud_rates.clone();
    rates.sort_unstable();
    rates.dedup();
    for rate in rates.into_iter().filter(|r| BAUD_RATES.contains(r)) {
        w.empty("supportedBaudRate", &[("value", &baud_name(rate))]);
    }
    w.end();
    w.end();
    w.end();

    w.start("NetworkManagement", &[]);
    let flag = |b: bool| if b { "true" } else { "false" };
    w.empty(
        "CANopenGeneralFeatures",
        &[
            ("granularity", &can.granularity.to_string()),
            ("nrOfRxPDO", &can.nr_of_rx_pdo.to_string()),
            ("nrOfTxPDO", &can.nr_of_tx_pdo.to_string()),
            ("bootUpSlave", flag(can.simple_boot_up_slave)),
            ("groupMessaging", flag(can.group_messaging)),
            ("dynamicChannels", &can.dynamic_channels.to_string()),
            ("layerSettingServiceSlave", flag(can.lss_supported)),
        ],
    );
    if can.simple_boot_up_master {
        w.empty("CANopenMasterFeatures", &[("bootUpMaster", "true")]);
    }
    // `nodeID` is required, and a node-ID outside 1..127 is no node-ID: the commissioning values of an
    // unconfigured node are left out.
    if let Some((c, node_id)) = configured {
        w.empty(
            "deviceCommissioning",
            &[
                ("nodeID", &node_id.to_string()),
                ("nodeName", &c.node_name),
                ("actualBaudRate", &baud_name(c.baud_rate)),
                ("networkNumber", &c.net_number.to_string()),
                ("networkName", &c.network_name),
                ("CANopenManager", flag(c.canopen_manager)),
            ],
        );
    }
    w.end();
}

fn header(w: &mut XmlWriter, desc: &DeviceDescription, identification: &str, class: &str) {
    w.start("ProfileHeader", &[]);
    w.text("ProfileIdentification", &[], identification);
    w.text("ProfileRevision", &[], "1");
    w.text("ProfileName", &[], &desc.identity.product_name);
    w.text("ProfileSource", &[], "");
    w.text("ProfileClassID", &[], class);
    w.start("ISO15745Reference", &[]);
    w.text("ISO15745Part", &[], "1");
    w.text("ISO15745Edition", &[], "1");
    w.text("ProfileTechnology", &[], "CANopen");
    w.end();
    w.end();
}

/// The `ProfileBody` attributes both bodies carry.
fn file_attributes(f: &FileInfo) -> Vec<(&'static str, String)> {
    let mut attrs = vec![
        ("formatName", "CANopen".to_string()),
        ("formatVersion", "1.0".to_string()),
        ("fileName", f.file_name.clone()),
        ("fileCreator", f.created_by.clone()),
        (
            "fileCreationDate",
            xs_date(&f.creation_date).unwrap_or_else(|| NO_DATE.to_string()),
        ),
    ];
    if let Some(t) = xs_time(&f.creation_time) {
        attrs.push(("fileCreationTime", t));
    }
    if !f.modified_by.is_empty() {
        attrs.push(("fileModifiedBy", f.modified_by.clone()));
    }
    if let Some(d) = xs_date(&f.modification_date) {
        attrs.push(("fileModificationDate", d));
    }
    if let Some(t) = xs_time(&f.modification_time) {
        attrs.push(("fileModificationTime", t));
    }
    attrs.push(("fileVersion", f.file_version.clone()));
    attrs.push(("supportedLanguages", "en".to_string()));
    attrs
}

fn digits(s: &[u8], n: usize) -> bool {
    s.len() == n && s.iter().all(u8::is_ascii_digit)
}

/// An XML Schema date: `2024-05-31` as it is (with an optional time zone), an EDS date `05-31-2024`
/// converted; `None` for anything else.
fn xs_date(text: &str) -> Option<String> {
    let t = text.trim();
    let b = t.as_bytes();
    if b.len() < 10 {
        return None;
    }
    let (date, zone) = b.split_at(10);
    let zone_ok = zone.is_empty()
        || zone == b"Z"
        || (zone.len() == 6
            && matches!(zone[0], b'+' | b'-')
            && digits(&zone[1..3], 2)
            && zone[3] == b':'
            && digits(&zone[4..], 2));
    if digits(&date[..4], 4)
        && date[4] == b'-'
        && digits(&date[5..7], 2)
        && date[7] == b'-'
        && digits(&date[8..], 2)
        && zone_ok
    {
        return Some(t.to_string());
    }
    if digits(&date[..2], 2)
        && date[2] == b'-'
        && digits(&date[3..5], 2)
        && date[5] == b'-'
        && digits(&date[6..], 4)
        && zone.is_empty()
    {
        // All ASCII digits and dashes: the slices below are on character boundaries.
        return Some(format!("{}-{}-{}", &t[6..10], &t[..2], &t[3..5]));
    }
    None
}

/// An XML Schema time: `13:05:00` (with optional fraction and time zone) as it is, an EDS time `1:05PM`
/// converted; `None` for anything else.
fn xs_time(text: &str) -> Option<String> {
    let t = text.trim();
    let b = t.as_bytes();
    if b.len() >= 8
        && digits(&b[..2], 2)
        && b[2] == b':'
        && digits(&b[3..5], 2)
        && b[5] == b':'
        && digits(&b[6..8], 2)
        && b[8..]
            .iter()
            .all(|c| c.is_ascii_digit() || matches!(c, b'.' | b'+' | b'-' | b':' | b'Z'))
    {
        return Some(t.to_string());
    }
    let upper = t.to_ascii_uppercase();
    let (clock, pm) = if let Some(c) = upper.strip_suffix("PM") {
        (c.trim(), true)
    } else if let Some(c) = upper.strip_suffix("AM") {
        (c.trim(), false)
    } else {
        return None;
    };
    let (h, m) = clock.split_once(':')?;
    if h.is_empty()
        || h.len() > 2
        || !digits(m.as_bytes(), 2)
        || !h.bytes().all(|b| b.is_ascii_digit())
    {
        return None;
    }
    let h: u32 = h.parse().ok()?;
    let m: u32 = m.parse().ok()?;
    if !(1..=12).contains(&h) || m > 59 {
        return None;
    }
    let h24 = match (h, pm) {
        (12, false) => 0,
        (12, true) => 12,
        (h, false) => h,
        (h, true) => h + 12,
    };
    Some(format!("{h24:02}:{m:02}:00"))
}

fn device_identity(w: &mut XmlWriter, desc: &DeviceDescription) {
    let id = &desc.identity;
    w.start("DeviceIdentity", &[]);
    w.text("vendorName", &[], &id.vendor_name);
    w.text("vendorID", &[], &format!("0x{:08X}", id.vendor_id));
    w.text("productName", &[], &id.product_name);
    w.text("productID", &[], &format!("0x{:08X}", id.product_code));
    if !desc.file_info.description.is_empty() {
        w.start("productText", &[]);
        w.text(
            "description",
            &[("lang", "en")],
            &desc.file_info.description,
        );
        w.end();
    }
    if !id.order_code.is_empty() {
        w.text("orderNumber", &[], &id.order_code);
    }
    // CiA 311: the versions follow the order number.
    for (kind, text) in [
        ("HW", &id.hardware_version),
        ("SW", &id.software_version),
        ("FW", &id.firmware_version),
    ] {
        if !text.is_empty() {
            w.text("version", &[("versionType", kind)], text);
        }
    }
    w.end();
}

/// The `DeviceFunction` the schema requires: one characteristic, the product name.
fn device_function(w: &mut XmlWriter, desc: &DeviceDescription) {
    w.start("DeviceFunction", &[]);
    w.start("capabilities", &[]);
    w.start("characteristicsList", &[]);
    w.start("characteristic", &[]);
    w.start("characteristicName", &[]);
    w.text("label", &[("lang", "en")], "Product name");
    w.end();
    w.start("characteristicContent", &[]);
    w.text("label", &[("lang", "en")], &desc.identity.product_name);
    w.end();
    w.end();
    w.end();
    w.end();
    w.end();
}

/// True when the object's own attributes carry its value (sub-index 0 inline on `CANopenObject`): a VAR,
/// DOMAIN or DEFTYPE whose only entry, sub-index 0, has the object's name and description. Any other object
/// is written with `CANopenSubObject`s.
fn inline_value(object: &Object) -> bool {
    !object.kind.has_subs()
        && object.kind != ObjectKind::Null
        && object.subs.len() == 1
        && object.subs.get(&0).is_some_and(|s| {
            s.name == object.name && s.description == object.description && s.flags.is_none()
        })
}

/// The `objFlags` attribute (hexBinary: 4 digits, 8 for flags beyond 16 bits), where there are flags.
fn obj_flags(attrs: &mut Vec<(&'static str, String)>, flags: Option<ObjFlags>) {
    if let Some(flags) = flags.map(ObjFlags::bits) {
        let text = if flags > 0xFFFF {
            format!("{flags:08X}")
        } else {
            format!("{flags:04X}")
        };
        attrs.push(("objFlags", text));
    }
}

fn object_id(index: u16) -> String {
    format!("UID_OBJ_{index:04X}")
}

fn sub_id(index: u16, sub: u8) -> String {
    format!("UID_SUB_{index:04X}{sub:02X}")
}

fn type_id(index: u16) -> String {
    format!("UID_DT_{index:04X}")
}

/// The capacity property to write for an entry, in bytes.
fn capacity(sub: &SubObject) -> Option<u32> {
    if !has_string_capacity(sub.data_type) {
        return None;
    }
    sub.bit_size.filter(|b| b % 8 == 0).map(|b| b / 8)
}

/// True when the object needs a parameter of its own.
fn object_has_parameter(object: &Object) -> bool {
    if inline_value(object) {
        object.description.is_some()
            || object
                .subs
                .get(&0)
                .is_some_and(|s| capacity(s).is_some() || refined_access(s))
    } else {
        object.description.is_some() || (object.kind.has_subs() && object.type_name.is_some())
    }
}

/// True when a sub-object written as `CANopenSubObject` needs a parameter of its own.
fn sub_has_parameter(sub: &SubObject) -> bool {
    sub.description.is_some() || capacity(sub).is_some() || refined_access(sub)
}

/// True for `rwr` and `rww`, which the schema's `accessType` (`ro`, `wo`, `rw`, `const`) cannot say: they are
/// written as `rw` and refined by the parameter's `readWriteInput` or `readWriteOutput`.
fn refined_access(sub: &SubObject) -> bool {
    matches!(sub.access.kind, AccessType::Rwr | AccessType::Rww)
}

/// The `accessType` attribute of an entry.
fn access_type_name(sub: &SubObject) -> &'static str {
    if refined_access(sub) {
        "rw"
    } else {
        sub.access.kind.as_str()
    }
}

fn application_process(w: &mut XmlWriter, desc: &DeviceDescription) {
    let objects: Vec<&Object> = desc.dictionary.objects().collect();
    let any_parameter = objects.iter().any(|o| {
        object_has_parameter(o) || (!inline_value(o) && o.subs.values().any(sub_has_parameter))
    });
    if !any_parameter {
        return;
    }
    w.start("ApplicationProcess", &[]);
    let typed: Vec<&&Object> = objects
        .iter()
        .filter(|o| o.kind.has_subs() && o.type_name.is_some())
        .collect();
    if !typed.is_empty() {
        w.start("dataTypeList", &[]);
        for o in typed {
            write_type(w, o);
        }
        w.end();
    }
    w.start("parameterList", &[]);
    for o in &objects {
        if object_has_parameter(o) {
            if inline_value(o) {
                if let Some(sub) = o.subs.get(&0) {
                    write_parameter(
                        w,
                        &object_id(o.index),
                        &o.name,
                        o.description.as_deref(),
                        sub,
                    );
                }
            } else {
                write_structure_parameter(w, o);
            }
        }
        if !inline_value(o) {
            for (&s, sub) in &o.subs {
                if sub_has_parameter(sub) {
                    write_parameter(
                        w,
                        &sub_id(o.index, s),
                        &sub.name,
                        sub.description.as_deref(),
                        sub,
                    );
                }
            }
        }
    }
    w.end();
    w.end();
}

/// The element type of a structured object: its first entry's type (UNSIGNED8 when it has none).
fn element_type(o: &Object) -> DataType {
    o.subs
        .iter()
        .find(|(&s, _)| s != 0)
        .or_else(|| o.subs.iter().next())
        .map_or(DataType::Unsigned8, |(_, sub)| sub.data_type)
}

fn write_type(w: &mut XmlWriter, o: &Object) {
    let name = o.type_name.as_deref().unwrap_or_default();
    let id = type_id(o.index);
    if o.kind == ObjectKind::Array {
        w.start("array", &[("name", name), ("uniqueID", &id)]);
        // The elements are the sub-indices up to 0xFE: an entry at 0xFF describes the object's
        // structure and is none.
        let upper = o
            .subs
            .keys()
            .copied()
            .filter(|&s| s < 0xFF)
            .max()
            .unwrap_or(0)
            .max(1)
            .to_string();
        w.empty("subrange", &[("lowerLimit", "1"), ("upperLimit", &upper)]);
        w.empty(type_element(element_type(o)), &[]);
        w.end();
    } else {
        w.start("struct", &[("name", name), ("uniqueID", &id)]);
        // The members are the entries up to 0xFE, as for an array.
        for (&s, sub) in o.subs.range(..0xFF) {
            w.start(
                "varDeclaration",
                &[("name", &sub.name), ("uniqueID", &format!("{id}_{s:02X}"))],
            );
            w.empty(type_element(sub.data_type), &[]);
            w.end();
        }
        w.end();
    }
}

/// The parameter of an ARRAY or RECORD: its description and its type.
fn write_structure_parameter(w: &mut XmlWriter, o: &Object) {
    w.start("parameter", &[("uniqueID", &object_id(o.index))]);
    w.text("label", &[("lang", "en")], &o.name);
    if let Some(d) = &o.description {
        w.text("description", &[("lang", "en")], d);
    }
    if o.kind.has_subs() && o.type_name.is_some() {
        w.empty("dataTypeIDRef", &[("uniqueIDRef", &type_id(o.index))]);
    } else {
        w.empty(type_element(element_type(o)), &[]);
    }
    w.end();
}

/// The parameter of one value: label, description, access, type and string capacity. Defaults and limits
/// stay on the object, where they win.
fn write_parameter(
    w: &mut XmlWriter,
    id: &str,
    name: &str,
    description: Option<&str>,
    sub: &SubObject,
) {
    w.start(
        "parameter",
        &[
            ("uniqueID", id),
            ("access", parameter_access_name(sub.access.kind)),
        ],
    );
    w.text("label", &[("lang", "en")], name);
    if let Some(d) = description {
        w.text("description", &[("lang", "en")], d);
    }
    w.empty(type_element(sub.data_type), &[]);
    if let Some(cap) = capacity(sub) {
        w.empty(
            "property",
            &[
                ("name", STRING_LENGTH_PROPERTY),
                ("value", &cap.to_string()),
            ],
        );
    }
    w.end();
}

fn default_text(sub: &SubObject) -> Option<String> {
    let d = sub.default.as_ref()?;
    let text = d.value.to_text(sub.data_type);
    Some(if d.plus_node_id {
        format!("$NODEID+{text}")
    } else {
        text
    })
}

fn actual_text(sub: &SubObject) -> Option<String> {
    if !sub.value_set {
        return None;
    }
    Value::decode(sub.data_type, &sub.value)
        .ok()
        .map(|v| v.to_text(sub.data_type))
}

/// The value attributes of an entry, in the order CiA 311 lists them.
fn value_attributes(sub: &SubObject) -> Vec<(&'static str, String)> {
    let mut attrs = vec![("dataType", format!("{:04X}", sub.data_type.index()))];
    if let Some(low) = &sub.low {
        attrs.push(("lowLimit", low.to_text(sub.data_type)));
    }
    if let Some(high) = &sub.high {
        attrs.push(("highLimit", high.to_text(sub.data_type)));
    }
    attrs.push(("accessType", access_type_name(sub).to_string()));
    if let Some(d) = default_text(sub) {
        attrs.push(("defaultValue", d));
    }
    if let Some(a) = actual_text(sub) {
        attrs.push(("actualValue", a));
    }
    attrs.push(("PDOmapping", pdo_name(sub.pdo).to_string()));
    attrs
}

fn write_object(w: &mut XmlWriter, o: &Object) {
    let index = format!("{:04X}", o.index);
    let code = o.kind.code().to_string();
    let mut attrs: Vec<(&str, String)> = vec![
        ("index", index),
        ("name", o.name.clone()),
        ("objectType", code),
    ];
    let inline = inline_value(o);
    if inline {
        if let Some(sub) = o.subs.get(&0) {
            attrs.extend(value_attributes(sub));
        }
    } else if !o.subs.is_empty() && o.subs.len() <= 255 {
        attrs.push(("subNumber", o.subs.len().to_string()));
    }
    obj_flags(&mut attrs, o.flags);
    if object_has_parameter(o) {
        attrs.push(("uniqueIDRef", object_id(o.index)));
    }
    let refs: Vec<(&str, &str)> = attrs.iter().map(|(k, v)| (*k, v.as_str())).collect();
    if inline || o.subs.is_empty() {
        w.empty("CANopenObject", &refs);
        return;
    }
    w.start("CANopenObject", &refs);
    for (&s, sub) in &o.subs {
        let mut attrs: Vec<(&str, String)> = vec![
            ("subIndex", format!("{s:02X}")),
            ("name", sub.name.clone()),
            ("objectType", "7".to_string()),
        ];
        attrs.extend(value_attributes(sub));
        obj_flags(&mut attrs, sub.flags);
        if sub_has_parameter(sub) {
            attrs.push(("uniqueIDRef", sub_id(o.index, s)));
        }
        let refs: Vec<(&str, &str)> = attrs.iter().map(|(k, v)| (*k, v.as_str())).collect();
        w.empty("CANopenSubObject", &refs);
    }
    w.end();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::{Commissioning, DeviceDescription};
    use crate::object::{AccessType, DefaultValue, ObjectKind, PdoMapping};

    #[test]
    fn dates_and_times() {
        assert_eq!(xs_date("2024-05-31").as_deref(), Some("2024-05-31"));
        assert_eq!(
            xs_date("2024-05-31+02:00").as_deref(),
            Some("2024-05-31+02:00")
        );
        assert_eq!(xs_date("05-31-2024").as_deref(), Some("2024-05-31"));
        assert_eq!(xs_date("31.05.2024"), None);
        assert_eq!(xs_date(""), None);
        assert_eq!(xs_date("2024-05-3€"), None);
        assert_eq!(
            xs_time("13:00:00.0000000+02:00").as_deref(),
            Some("13:00:00.0000000+02:00")
        );
        assert_eq!(xs_time("1:05PM").as_deref(), Some("13:05:00"));
        assert_eq!(xs_time("12:30AM").as_deref(), Some("00:30:00"));
        assert_eq!(xs_time("09:15am").as_deref(), Some("09:15:00"));
        assert_eq!(xs_time("noon"), None);
        assert_eq!(xs_time("13:5€PM"), None);
    }

    fn small() -> DeviceDescription {
        let mut d = DeviceDescription::default();
        d.identity.vendor_name = "B&R".into();
        d.identity.vendor_id = 0x12E;
        d.identity.product_name = "Box".into();
        d.identity.product_code = 7;
        d.file_info.file_name = "box.xdd".into();
        d.file_info.file_version = "2".into();
        d.file_info.created_by = "me".into();
        d.file_info.creation_date = "05-31-2024".into();
        d.file_info.creation_time = "1:05PM".into();
        d.dictionary.insert(Object::var(
            0x1014,
            SubObject::new("COB-ID EMCY", DataType::Unsigned32, AccessType::Rw)
                .with_default(Value::Uint(0x80)),
        ));
        if let Some(s) = d
            .dictionary
            .object_mut(0x1014)
            .and_then(|o| o.subs.get_mut(&0))
        {
            s.default = Some(DefaultValue {
                value: Value::Uint(0x80),
                plus_node_id: true,
            });
        }
        let mut o = Object::var(
            0x2000,
            SubObject::new("Name", DataType::VisibleString, AccessType::Ro)
                .with_default(Value::String("a<b".into()))
                .with_bit_size(64)
                .with_description("Two\nlines"),
        );
        o.description = Some("Two\nlines".into());
        d.dictionary.insert(o);
        let mut rec = Object::structured(0x6000, "Inputs", ObjectKind::Array)
            .with_sub(
                0,
                SubObject::new("Count", DataType::Unsigned8, AccessType::Ro)
                    .with_default(Value::Uint(1)),
            )
            .with_sub(
                1,
                SubObject::new("In", DataType::Unsigned8, AccessType::Rwr)
                    .with_pdo(PdoMapping::Tpdo)
                    .with_limits(Some(Value::Uint(0)), Some(Value::Uint(9)))
                    .with_description("bits"),
            );
        rec.type_name = Some("ARR".into());
        d.dictionary.insert(rec);
        d.can = Some(CanInfo {
            baud_rates: vec![125, 250],
            dummy_usage: vec![5],
            ..CanInfo::default()
        });
        d.commissioning = Some(Commissioning {
            node_id: Some(3),
            node_name: "n".into(),
            baud_rate: 250,
            net_number: 1,
            network_name: "net".into(),
            canopen_manager: false,
            lss_serial_number: 0,
        });
        d
    }

    #[test]
    fn golden_output() {
        let expected = r#"<?xml version="1.0" encoding="UTF-8"?>
<ISO15745ProfileContainer xmlns="http://www.canopen.org/xml/1.0" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
  <ISO15745Profile>
    <ProfileHeader>
      <ProfileIdentification>CANopen device profile</ProfileIdentification>
      <ProfileRevision>1</ProfileRevision>
      <ProfileName>Box</ProfileName>
      <ProfileSource></ProfileSource>
      <ProfileClassID>Device</ProfileClassID>
      <ISO15745Reference>
        <ISO15745Part>1</ISO15745Part>
        <ISO15745Edition>1</ISO15745Edition>
        <ProfileTechnology>CANopen</ProfileTechnology>
      </ISO15745Reference>
    </ProfileHeader>
    <ProfileBody xsi:type="ProfileBody_Device_CANopen" formatName="CANopen" formatVersion="1.0" fileName="box.xdd" fileCreator="me" fileCreationDate="2024-05-31" fileCreationTime="13:05:00" fileVersion="2" supportedLanguages="en">
      <DeviceIdentity>
        <vendorName>B&amp;R</vendorName>
        <vendorID>0x0000012E</vendorID>
        <productName>Box</productName>
        <productID>0x00000007</productID>
      </DeviceIdentity>
      <DeviceFunction>
        <capabilities>
          <characteristicsList>
            <characteristic>
              <characteristicName>
                <label lang="en">Product name</label>
              </characteristicName>
              <characteristicContent>
                <label lang="en">Box</label>
              </characteristicContent>
            </characteristic>
          </characteristicsList>
        </capabilities>
      </DeviceFunction>
      <ApplicationProcess>
        <dataTypeList>
          <array name="ARR" uniqueID="UID_DT_6000">
            <subrange lowerLimit="1" upperLimit="1"/>
            <USINT/>
          </array>
        </dataTypeList>
        <parameterList>
          <parameter uniqueID="UID_OBJ_2000" access="read">
            <label lang="en">Name</label>
            <description lang="en">Two&#10;lines</description>
            <STRING/>
            <property name="CO_stringLengthMin" value="8"/>
          </parameter>
          <parameter uniqueID="UID_OBJ_6000">
            <label lang="en">Inputs</label>
            <dataTypeIDRef uniqueIDRef="UID_DT_6000"/>
          </parameter>
          <parameter uniqueID="UID_SUB_600001" access="readWriteInput">
            <label lang="en">In</label>
            <description lang="en">bits</description>
            <USINT/>
          </parameter>
        </parameterList>
      </ApplicationProcess>
    </ProfileBody>
  </ISO15745Profile>
  <ISO15745Profile>
    <ProfileHeader>
      <ProfileIdentification>CANopen communication network profile</ProfileIdentification>
      <ProfileRevision>1</ProfileRevision>
      <ProfileName>Box</ProfileName>
      <ProfileSource></ProfileSource>
      <ProfileClassID>CommunicationNetwork</ProfileClassID>
      <ISO15745Reference>
        <ISO15745Part>1</ISO15745Part>
        <ISO15745Edition>1</ISO15745Edition>
        <ProfileTechnology>CANopen</ProfileTechnology>
      </ISO15745Reference>
    </ProfileHeader>
    <ProfileBody xsi:type="ProfileBody_CommunicationNetwork_CANopen" formatName="CANopen" formatVersion="1.0" fileName="box.xdd" fileCreator="me" fileCreationDate="2024-05-31" fileCreationTime="13:05:00" fileVersion="2" supportedLanguages="en">
      <ApplicationLayers>
        <CANopenObjectList>
          <CANopenObject index="1014" name="COB-ID EMCY" objectType="7" dataType="0007" accessType="rw" defaultValue="$NODEID+0x00000080" PDOmapping="no"/>
          <CANopenObject index="2000" name="Name" objectType="7" dataType="0009" accessType="ro" defaultValue="a&lt;b" PDOmapping="no" uniqueIDRef="UID_OBJ_2000"/>
          <CANopenObject index="6000" name="Inputs" objectType="8" subNumber="2" uniqueIDRef="UID_OBJ_6000">
            <CANopenSubObject subIndex="00" name="Count" objectType="7" dataType="0005" accessType="ro" defaultValue="0x01" PDOmapping="no"/>
            <CANopenSubObject subIndex="01" name="In" objectType="7" dataType="0005" lowLimit="0x00" highLimit="0x09" accessType="rw" PDOmapping="TPDO" uniqueIDRef="UID_SUB_600001"/>
          </CANopenObject>
        </CANopenObjectList>
        <dummyUsage>
          <dummy entry="Dummy0001=0"/>
          <dummy entry="Dummy0002=0"/>
          <dummy entry="Dummy0003=0"/>
          <dummy entry="Dummy0004=0"/>
          <dummy entry="Dummy0005=1"/>
          <dummy entry="Dummy0006=0"/>
          <dummy entry="Dummy0007=0"/>
        </dummyUsage>
      </ApplicationLayers>
      <TransportLayers>
        <PhysicalLayer>
          <baudRate>
            <supportedBaudRate value="125 Kbps"/>
            <supportedBaudRate value="250 Kbps"/>
          </baudRate>
        </PhysicalLayer>
      </TransportLayers>
      <NetworkManagement>
        <CANopenGeneralFeatures granularity="8" nrOfRxPDO="0" nrOfTxPDO="0" bootUpSlave="true" groupMessaging="false" dynamicChannels="0" layerSettingServiceSlave="false"/>
        <deviceCommissioning nodeID="3" nodeName="n" actualBaudRate="250 Kbps" networkNumber="1" networkName="net" CANopenManager="false"/>
      </NetworkManagement>
    </ProfileBody>
  </ISO15745Profile>
</ISO15745ProfileContainer>
"#;
        let d = small();
        let out = write(&d);
        assert_eq!(out, expected);
        assert_eq!(write(&d), out, "byte-stable");
    }

    #[test]
    fn a_var_whose_entry_differs_from_the_object_is_written_with_a_sub_object() {
        let mut d = DeviceDescription::default();
        let mut o = Object::var(
            0x2001,
            SubObject::new("Value", DataType::Unsigned16, AccessType::Rw)
                .with_description("the value"),
        );
        o.name = "Object".into();
        o.description = Some("the object".into());
        d.dictionary.insert(o);
        let text = write(&d);
        assert!(text.contains(
            "<CANopenObject index=\"2001\" name=\"Object\" objectType=\"7\" subNumber=\"1\" uniqueIDRef=\"UID_OBJ_2001\">"
        ), "{text}");
        assert!(
            text.contains("<CANopenSubObject subIndex=\"00\" name=\"Value\""),
            "{text}"
        );
        let mut back = super::super::read(text.as_bytes(), "t.xdd").unwrap();
        back.file_info = d.file_info.clone();
        back.can = None;
        assert_eq!(back, d);
    }

    /// An ARRAY and a RECORD with every sub-index, 0xFF's structure entry too: the array's
    /// elements go to 0xFE (`upperLimit="254"`), the struct has the 255 members up to 0xFE; the
    /// file reads back as it was, with the 256 sub-objects of each.
    #[test]
    fn objects_with_every_sub_index_are_written_as_a_reader_takes_them() {
        let mut d = DeviceDescription::default();
        for (index, kind, name) in [
            (0x2000, ObjectKind::Array, "ALL"),
            (0x2001, ObjectKind::Record, "REC"),
        ] {
            let mut o = Object::structured(index, "All", kind);
            for s in 0..=0xFFu8 {
                o.subs.insert(
                    s,
                    SubObject::new(format!("e{s}"), DataType::Unsigned8, AccessType::Ro),
                );
            }
            o.type_name = Some(name.into());
            d.dictionary.insert(o);
        }
        let text = write(&d);
        assert!(
            text.contains("<subrange lowerLimit=\"1\" upperLimit=\"254\"/>"),
            "{text}"
        );
        assert!(text.contains("uniqueID=\"UID_DT_2001_FE\""), "{text}");
        assert!(!text.contains("uniqueID=\"UID_DT_2001_FF\""), "{text}");
        let mut back = super::super::read(text.as_bytes(), "t.xdd").unwrap();
        back.file_info = d.file_info.clone();
        back.can = None;
        assert_eq!(back, d);
    }

    #[test]
    fn commissioning_without_a_valid_node_id_is_left_out() {
        let mut d = small();
        if let Some(c) = &mut d.commissioning {
            c.node_id = None;
        }
        let text = write(&d);
        assert!(!text.contains("deviceCommissioning"));
        assert!(super::super::read(text.as_bytes(), "t.xdd").is_ok());
    }

    #[test]
    fn round_trip_of_a_small_description() {
        let mut d = small();
        // What the reader gives back: converted dates and the default resolved for node 3.
        d.file_info.creation_date = "2024-05-31".into();
        d.file_info.creation_time = "13:05:00".into();
        d.dictionary.reset(3);
        let back = super::super::read(write(&d).as_bytes(), "box.xdd").unwrap();
        assert_eq!(back, d);
        assert_eq!(
            back.dictionary.entry(0x1014, 0).unwrap().value,
            0x83u32.to_le_bytes()
        );
    }
}
