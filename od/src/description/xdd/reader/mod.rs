//! Streaming XDD/XDC reader (CiA 311): one pass over the nodes of the XML cursor that keeps small
//! records of the objects, parameters and data types it meets, then the resolution of `uniqueIDRef`s
//! into a [`DeviceDescription`].
//!
//! The parts: `walk` (the cursor's nodes, the context stack, text and attributes), `elements` (what
//! the attributes of each element say) and `build` (references resolved, the description built).

use std::borrow::Cow;
use std::collections::{BTreeMap, BTreeSet, HashMap};

use super::{
    has_string_capacity, parse_access_type, parse_baud, parse_parameter_access, parse_pdo,
    parse_type_element, XddType, STRING_LENGTH_PROPERTY,
};
use crate::device::{CanInfo, Commissioning, DeviceDescription};
use crate::error::{ParseError, Position};
use crate::object::{AccessType, ObjFlags, ObjectKind, PdoMapping};
use crate::report::{Reading, SourceMap};
use crate::types::DataType;
use crate::xml;
use crate::xml::cursor::Document;
use crate::xml::text::ElementText;

mod build;
mod elements;
#[cfg(test)]
mod tests;
mod walk;

/// Reads an XDD or XDC file. `source_name` names the file in errors.
///
/// ```
/// let xdd = br#"<?xml version="1.1"?>
/// <ISO15745ProfileContainer><ISO15745Profile>
///   <ProfileBody xsi:type="ProfileBody_CommunicationNetwork_CANopen"
///       xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
///     <ApplicationLayers><CANopenObjectList>
///       <CANopenObject index="1000" name="Device type" objectType="7" dataType="0007"
///           accessType="ro" defaultValue="0x00020192"/>
///     </CANopenObjectList></ApplicationLayers>
///   </ProfileBody>
/// </ISO15745Profile></ISO15745ProfileContainer>"#;
/// let desc = od::xdd::read(xdd, "demo.xdd").unwrap();
/// assert_eq!(desc.dictionary.object(0x1000).unwrap().name, "Device type");
/// ```
pub fn read(bytes: &[u8], source_name: &str) -> Result<DeviceDescription, ParseError> {
    let mut reading = read_file(bytes, source_name)?;
    Ok(reading.devices.pop().unwrap_or_default())
}

/// Reads an XDD or XDC file as [`read`] does, with where each object was read and the reader's warnings.
pub fn read_file(bytes: &[u8], source_name: &str) -> Result<Reading, ParseError> {
    let text = xml::decode(bytes, source_name)?;
    let doc = Document::new(&text, source_name);
    let mut scan = Scan::new(&doc);
    scan.run()?;
    let mut source = SourceMap::default();
    source.set_device(Position { line: 1, column: 1 });
    let at = |offset: usize| doc.position(offset);
    for o in &scan.objects {
        source.set_object(o.index, at(o.offset));
        for sub in &o.subs {
            source.set_entry(o.index, sub.sub, at(sub.offset));
        }
    }
    if let Some((offset, kind)) = &scan.powerlink {
        scan.warn(
            *offset,
            format!(
                "a POWERLINK description ({kind}, EPSG DS 311), not a CANopen one: its object dictionary is read; its POWERLINK network parts are not"
            ),
        );
    } else if scan.device_file.is_none() && scan.network_file.is_none() {
        if let Some((offset, kind)) = scan.other_bodies.first() {
            return Err(scan.err(
                *offset,
                format!(
                    "a {kind} profile body: the file describes a device of another network, not a CANopen device (no ProfileBody_Device_CANopen or ProfileBody_CommunicationNetwork_CANopen)"
                ),
            ));
        }
    }
    let (desc, findings) = scan.finish()?;
    Ok(Reading::one(desc, source, findings))
}

/// An attribute value (unescaped) and the byte offset of its first character.
#[derive(Debug, Clone)]
struct Attr<'a> {
    text: Cow<'a, str>,
    offset: usize,
}

/// Where the reader is: the kind of the innermost open element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Ctx {
    Document,
    Container,
    Profile,
    Body,
    Identity,
    IdentityField(IdField),
    ProductText,
    ProductTextDescription,
    ApplicationProcess,
    DataTypeList,
    DataTypeDef,
    /// A `varDeclaration` of a `struct`: a member, whose type may be a `dataTypeIDRef`.
    MemberDecl,
    ParameterList,
    Parameter,
    ParameterText(TextKind),
    AllowedValues,
    Range,
    ApplicationLayers,
    ObjectList,
    Object,
    DummyUsage,
    TransportLayers,
    PhysicalLayer,
    BaudRate,
    NetworkManagement,
    /// An element whose content is not read (unknown, or fully read from its start tag).
    Skip,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum IdField {
    VendorName,
    VendorId,
    ProductName,
    ProductId,
    OrderNumber,
    /// `version` with its `versionType`.
    Version(VersionType),
}

/// The `versionType` of a `DeviceIdentity/version` (CiA 311).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum VersionType {
    Hardware,
    Software,
    Firmware,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum TextKind {
    Label,
    Description,
}

/// A text in one language; English texts are preferred over others.
#[derive(Debug, Clone, Default)]
struct LangText {
    text: Option<String>,
    english: bool,
}

impl LangText {
    fn offer(&mut self, text: String, english: bool) {
        if self.text.is_none() || (english && !self.english) {
            self.text = Some(text);
            self.english = english;
        }
    }
}

/// The type of a parameter: an element such as `<UINT/>`, or a reference to the `dataTypeList`.
#[derive(Debug, Clone)]
enum TypeRef<'a> {
    Simple(XddType),
    Ref(Attr<'a>),
}

/// What a `parameter` says about an entry.
#[derive(Debug, Clone)]
struct ParamRec<'a> {
    access: Option<AccessType>,
    ty: Option<TypeRef<'a>>,
    default: Option<Attr<'a>>,
    actual: Option<Attr<'a>>,
    low: Option<Attr<'a>>,
    high: Option<Attr<'a>>,
    label: LangText,
    description: LangText,
    capacity: Option<u32>,
}

impl ParamRec<'_> {
    fn new() -> Self {
        ParamRec {
            access: None,
            ty: None,
            default: None,
            actual: None,
            low: None,
            high: None,
            label: LangText::default(),
            description: LangText::default(),
            capacity: None,
        }
    }

    /// The description: the `description`, else a `label` that says more than the entry's name.
    fn description(&self, name: &str) -> Option<String> {
        if let Some(d) = &self.description.text {
            return Some(d.clone());
        }
        self.label.text.as_ref().filter(|l| *l != name).cloned()
    }
}

/// What kind of `dataTypeList` entry a type is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum DtKind {
    Array,
    Struct,
    /// `enum` or `derived`: a basic type under another name.
    Simple,
}

/// A `dataTypeList` entry.
#[derive(Debug, Clone)]
struct DtRec {
    name: String,
    kind: DtKind,
    /// The element type of an array, the base type of an enum or derived type.
    base: Option<XddType>,
    /// Where its `uniqueID` is: the place of its findings, and the order of the types.
    offset: usize,
    /// The types it is made of by `dataTypeIDRef` (an array's element type, a derived type's
    /// base, a struct's members' types): the `uniqueIDRef` and where it is.
    refs: Vec<(String, usize)>,
    /// A struct's members (`varDeclaration`s).
    members: usize,
}

impl DtRec {
    /// `array `UID_ARR_1003` (Errors)`: its kind, `uniqueID` and name.
    fn what(&self, id: &str) -> String {
        let kind = match self.kind {
            DtKind::Array => "array",
            DtKind::Struct => "struct",
            DtKind::Simple => "data type",
        };
        format!("{kind} {}", self.label(id))
    }

    /// `` `UID_ARR_1003` (Errors) ``: its `uniqueID` and name.
    fn label(&self, id: &str) -> String {
        if self.name.is_empty() {
            format!("`{id}`")
        } else {
            format!("`{id}` ({})", self.name)
        }
    }
}

/// The most sub-indices an ARRAY or RECORD holds: 0x00 to 0xFE (CiA 301 §7.4.3; 0xFF is
/// reserved).
const MOST_SUB_INDICES: i128 = 0xFF;

/// The value attributes of a `CANopenObject` or `CANopenSubObject`.
#[derive(Debug, Clone, Default)]
struct EntryAttrs<'a> {
    data_type: Option<(u16, usize)>,
    access: Option<AccessType>,
    pdo: PdoMapping,
    default: Option<Attr<'a>>,
    low: Option<Attr<'a>>,
    high: Option<Attr<'a>>,
    actual: Option<Attr<'a>>,
    unique_id_ref: Option<Attr<'a>>,
    flags: Option<ObjFlags>,
}

#[derive(Debug, Clone)]
struct SubRec<'a> {
    offset: usize,
    sub: u8,
    name: Cow<'a, str>,
    attrs: EntryAttrs<'a>,
}

#[derive(Debug, Clone)]
struct ObjRec<'a> {
    offset: usize,
    index: u16,
    name: Cow<'a, str>,
    kind: ObjectKind,
    attrs: EntryAttrs<'a>,
    subs: Vec<SubRec<'a>>,
}

/// The `ProfileBody` file attributes.
#[derive(Debug, Clone, Default)]
struct FileAttrs {
    file_name: Option<String>,
    file_version: Option<String>,
    created_by: Option<String>,
    creation_date: Option<String>,
    creation_time: Option<String>,
    modified_by: Option<String>,
    modification_date: Option<String>,
    modification_time: Option<String>,
}

/// The state of one pass over the file.
struct Scan<'a> {
    /// The file: error positions and warnings.
    doc: &'a Document<'a>,
    stack: Vec<Ctx>,
    seen_root: bool,
    /// The text of the element being read, where it is kept.
    text: ElementText,
    text_lang_en: bool,
    /// File attributes of the device profile body and of the communication network body.
    device_file: Option<FileAttrs>,
    network_file: Option<FileAttrs>,
    seen_network_body: bool,
    /// A CAN part of the network body was read (dummy usage, physical layer, general or master
    /// features): the description has [`CanInfo`].
    seen_can: bool,
    /// The first POWERLINK profile body (EPSG DS 311), and where it is.
    powerlink: Option<(usize, String)>,
    /// Profile bodies of other technologies, skipped.
    other_bodies: Vec<(usize, String)>,
    vendor_name: Option<String>,
    vendor_id: Option<u32>,
    product_name: Option<String>,
    product_id: Option<u32>,
    order_number: Option<String>,
    /// The `version` elements: hardware, software, firmware (the first of each type).
    versions: [Option<String>; 3],
    product_text: LangText,
    params: HashMap<Cow<'a, str>, ParamRec<'a>>,
    param: Option<(Attr<'a>, ParamRec<'a>)>,
    data_types: HashMap<Cow<'a, str>, DtRec>,
    data_type: Option<(Attr<'a>, DtRec)>,
    objects: Vec<ObjRec<'a>>,
    object: Option<ObjRec<'a>>,
    can: CanInfo,
    baud_rates: BTreeSet<u32>,
    /// Dummy entries by data type index: used or not (the last entry for a type wins).
    dummies: BTreeMap<u16, bool>,
    commissioning: Option<Commissioning>,
}

/// The local part of a qualified name (`q1:parameter` → `parameter`).
fn local(name: &[u8]) -> &[u8] {
    match name.iter().rposition(|&b| b == b':') {
        Some(p) => &name[p + 1..],
        None => name,
    }
}

fn show(name: &[u8]) -> Cow<'_, str> {
    String::from_utf8_lossy(name)
}

/// True for the types whose text value is read literally (no trimming, empty is a value).
fn is_text_type(t: DataType) -> bool {
    matches!(
        t,
        DataType::VisibleString
            | DataType::UnicodeString
            | DataType::OctetString
            | DataType::Domain
    )
}

/// Splits `$NODEID+0x180` (or `0x180+$NODEID`) into the offset text; `None` when there is no `$NODEID`.
fn strip_node_id(text: &str) -> Option<&str> {
    let t = text.trim();
    const KEY: &str = "$NODEID";
    if t.len() >= KEY.len()
        && t.is_char_boundary(KEY.len())
        && t[..KEY.len()].eq_ignore_ascii_case(KEY)
    {
        let rest = t[KEY.len()..].trim_start();
        return Some(rest.strip_prefix('+').unwrap_or(rest).trim());
    }
    let cut = t.len().checked_sub(KEY.len())?;
    if t.is_char_boundary(cut) && t[cut..].eq_ignore_ascii_case(KEY) {
        let rest = t[..cut].trim_end();
        return Some(rest.strip_suffix('+').unwrap_or(rest).trim());
    }
    None
}

impl<'a> Scan<'a> {
    fn new(doc: &'a Document<'a>) -> Self {
        Scan {
            doc,
            stack: vec![Ctx::Document],
            seen_root: false,
            text: ElementText::default(),
            text_lang_en: false,
            device_file: None,
            network_file: None,
            seen_network_body: false,
            seen_can: false,
            powerlink: None,
            other_bodies: Vec::new(),
            vendor_name: None,
            vendor_id: None,
            product_name: None,
            product_id: None,
            order_number: None,
            versions: [None, None, None],
            product_text: LangText::default(),
            params: HashMap::new(),
            param: None,
            data_types: HashMap::new(),
            data_type: None,
            objects: Vec::new(),
            object: None,
            can: CanInfo {
                simple_boot_up_slave: false,
                ..CanInfo::default()
            },
            baud_rates: BTreeSet::new(),
            dummies: BTreeMap::new(),
            commissioning: None,
        }
    }

    fn err(&self, offset: usize, message: impl Into<String>) -> ParseError {
        self.doc.error(offset, message)
    }
}
