//! Streaming XDD/XDC reader (CiA 311): one pass over quick-xml events that keeps small records of the
//! objects, parameters and data types it meets, then the resolution of `uniqueIDRef`s into a
//! [`DeviceDescription`].

use std::borrow::Cow;
use std::collections::{BTreeMap, BTreeSet, HashMap};

use super::{
    has_string_capacity, parse_access_type, parse_baud, parse_parameter_access, parse_pdo,
    parse_type_element, XddType, STRING_LENGTH_PROPERTY,
};
use crate::device::{CanInfo, Commissioning, DeviceDescription, FileInfo};
use crate::dict::Dictionary;
use crate::error::{ParseError, Position};
use crate::object::{AccessType, DefaultValue, Object, ObjectKind, PdoMapping, SubObject};
use crate::report::{Finding, Reading, SourceMap};
use crate::types::DataType;
use crate::value::Value;
use crate::xml;
use crate::xml::cursor::{Cursor, Document, Element, Node};

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
}

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
    text: String,
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
            text: String::new(),
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

    fn run(&mut self) -> Result<(), ParseError> {
        let mut cursor = Cursor::new(self.doc);
        loop {
            match cursor.next()? {
                Node::Start(e) => {
                    let ctx = self.open(&e, e.offset())?;
                    self.stack.push(ctx);
                }
                Node::End { offset } => {
                    let ctx = self.stack.pop().unwrap_or(Ctx::Document);
                    if ctx == Ctx::Document || self.stack.is_empty() {
                        return Err(self.err(offset, "closing tag without an open element"));
                    }
                    self.close(ctx, offset)?;
                }
                Node::Text(t, _) => {
                    if self.collecting() {
                        self.text.push_str(&t.content());
                    }
                }
                Node::CData(t, _) => {
                    if self.collecting() {
                        self.text.push_str(&t);
                    }
                }
                Node::Ref(r, before) => {
                    if self.collecting() {
                        let c = match r.resolve() {
                            Ok(Some(c)) => c,
                            Ok(None) => {
                                return Err(self.err(
                                    before,
                                    format!(
                                        "unknown entity `&{};` (expected &lt; &gt; &amp; &apos; &quot; or a character reference)",
                                        r.name()
                                    ),
                                ))
                            }
                            Err(e) => {
                                return Err(self.err(before, format!("bad character reference: {e}")))
                            }
                        };
                        self.text.push(c);
                    }
                }
                Node::Eof => break,
            }
        }
        if self.stack.len() > 1 {
            return Err(self.err(
                self.doc.text().len(),
                "unexpected end of file: an element is not closed",
            ));
        }
        if !self.seen_root {
            return Err(self.err(
                0,
                "expected an ISO15745ProfileContainer element, found no element",
            ));
        }
        Ok(())
    }

    fn collecting(&self) -> bool {
        matches!(
            self.stack.last(),
            Some(Ctx::IdentityField(_) | Ctx::ProductTextDescription | Ctx::ParameterText(_))
        )
    }

    /// Calls `f` with the local name and value of every attribute of `e`.
    fn attrs(
        &mut self,
        e: &Element<'a>,
        offset: usize,
        mut f: impl FnMut(&mut Self, &[u8], Attr<'a>) -> Result<(), ParseError>,
    ) -> Result<(), ParseError> {
        for a in e.attributes() {
            let a = match a {
                Ok(a) => a,
                Err(err) => {
                    return Err(self.err(
                        offset,
                        format!("malformed attribute in <{}>: {err}", show(e.name())),
                    ))
                }
            };
            // Literal tabs and line ends become spaces before references are resolved, so `&#10;` stays.
            let text = a
                .normalized_value()
                .map_err(|err| self.err(a.value_offset(), format!("bad attribute value: {err}")))?;
            f(
                self,
                local(a.name()),
                Attr {
                    text,
                    offset: a.value_offset(),
                },
            )?;
        }
        Ok(())
    }

    /// The value of the attribute `name` of `e`, which must be there.
    fn required_attr(
        &mut self,
        e: &Element<'a>,
        offset: usize,
        name: &[u8],
    ) -> Result<Attr<'a>, ParseError> {
        let mut value = None;
        self.attrs(e, offset, |_, key, v| {
            if key == name {
                value = Some(v);
            }
            Ok(())
        })?;
        value.ok_or_else(|| {
            self.err(
                offset,
                format!(
                    "expected a {} attribute in <{}>",
                    show(name),
                    show(local(e.name()))
                ),
            )
        })
    }

    /// Handles a start tag in the current context and answers the context of its content.
    fn open(&mut self, e: &Element<'a>, offset: usize) -> Result<Ctx, ParseError> {
        let parent = self.stack.last().copied().unwrap_or(Ctx::Skip);
        let name = local(e.name());
        let ctx = match (parent, name) {
            (Ctx::Document, b"ISO15745ProfileContainer") => {
                self.seen_root = true;
                Ctx::Container
            }
            (Ctx::Document, other) => {
                return Err(self.err(
                    offset,
                    format!(
                        "expected an ISO15745ProfileContainer element (a CiA 311 XDD), found <{}>",
                        show(other)
                    ),
                ))
            }
            (Ctx::Container, b"ISO15745Profile") => Ctx::Profile,
            (Ctx::Profile, b"ProfileBody") => self.open_body(e, offset)?,
            (Ctx::Body, b"DeviceIdentity") => Ctx::Identity,
            (Ctx::Body, b"ApplicationProcess") => Ctx::ApplicationProcess,
            (Ctx::Body, b"ApplicationLayers") => Ctx::ApplicationLayers,
            (Ctx::Body, b"TransportLayers") => {
                self.seen_can = true;
                Ctx::TransportLayers
            }
            (Ctx::Body, b"NetworkManagement") => Ctx::NetworkManagement,
            (Ctx::Identity, field) => match field {
                b"vendorName" => Ctx::IdentityField(IdField::VendorName),
                b"vendorID" => Ctx::IdentityField(IdField::VendorId),
                b"productName" => Ctx::IdentityField(IdField::ProductName),
                b"productID" => Ctx::IdentityField(IdField::ProductId),
                b"orderNumber" => Ctx::IdentityField(IdField::OrderNumber),
                b"productText" => Ctx::ProductText,
                b"version" => {
                    self.attrs(e, offset, |s, key, v| {
                        if key == b"versionType" && !matches!(v.text.trim(), "SW" | "FW" | "HW") {
                            return Err(s.err(
                                v.offset,
                                format!("expected versionType SW, FW or HW, found `{}`", v.text),
                            ));
                        }
                        Ok(())
                    })?;
                    Ctx::Skip
                }
                _ => Ctx::Skip,
            },
            (Ctx::ProductText, b"description") => {
                self.text_lang_en = self.english(e, offset)?;
                Ctx::ProductTextDescription
            }
            (Ctx::ApplicationProcess, b"dataTypeList") => Ctx::DataTypeList,
            (Ctx::ApplicationProcess, b"parameterList") => Ctx::ParameterList,
            (Ctx::DataTypeList, kind @ (b"array" | b"struct" | b"enum" | b"derived")) => {
                let kind = match kind {
                    b"array" => DtKind::Array,
                    b"struct" => DtKind::Struct,
                    _ => DtKind::Simple,
                };
                self.open_data_type(e, offset, kind)?;
                Ctx::DataTypeDef
            }
            (Ctx::DataTypeDef, type_name) => {
                if let (Some(t), Some((_, dt))) =
                    (parse_type_element(type_name), &mut self.data_type)
                {
                    if dt.base.is_none() && dt.kind != DtKind::Struct {
                        dt.base = Some(t);
                    }
                }
                Ctx::Skip
            }
            (Ctx::ParameterList, b"parameter") => {
                self.open_parameter(e, offset)?;
                Ctx::Parameter
            }
            (Ctx::Parameter, child) => self.open_parameter_child(e, offset, child)?,
            (Ctx::AllowedValues, b"range") => Ctx::Range,
            (Ctx::Range, bound @ (b"minValue" | b"maxValue")) => {
                let value = self.required_attr(e, offset, b"value")?;
                if let Some((_, p)) = &mut self.param {
                    let slot = if bound == b"minValue" {
                        &mut p.low
                    } else {
                        &mut p.high
                    };
                    if slot.is_none() {
                        *slot = Some(value);
                    }
                }
                Ctx::Skip
            }
            (Ctx::ApplicationLayers, b"CANopenObjectList") => Ctx::ObjectList,
            (Ctx::ApplicationLayers, b"ObjectList") if self.powerlink.is_some() => Ctx::ObjectList,
            (Ctx::ApplicationLayers, b"dummyUsage") => {
                self.seen_can = true;
                Ctx::DummyUsage
            }
            (Ctx::ObjectList, b"CANopenObject") => {
                self.open_object(e, offset)?;
                Ctx::Object
            }
            (Ctx::ObjectList, b"Object") if self.powerlink.is_some() => {
                self.open_object(e, offset)?;
                Ctx::Object
            }
            (Ctx::Object, b"SubObject") if self.powerlink.is_some() => {
                self.open_sub_object(e, offset)?;
                Ctx::Skip
            }
            (Ctx::Object, b"CANopenSubObject") => {
                self.open_sub_object(e, offset)?;
                Ctx::Skip
            }
            (Ctx::DummyUsage, b"dummy") => {
                self.read_dummy(e, offset)?;
                Ctx::Skip
            }
            (Ctx::TransportLayers, b"PhysicalLayer") => Ctx::PhysicalLayer,
            (Ctx::PhysicalLayer, b"baudRate") => Ctx::BaudRate,
            (Ctx::BaudRate, b"supportedBaudRate") => {
                self.attrs(e, offset, |s, key, v| {
                    if key == b"value" {
                        let kbps = parse_baud(&v.text).ok_or_else(|| {
                            s.err(
                                v.offset,
                                format!(
                                    "expected a bit rate like \"250 Kbps\" in supportedBaudRate, found `{}`",
                                    v.text
                                ),
                            )
                        })?;
                        if kbps != 0 {
                            s.baud_rates.insert(kbps);
                        }
                    }
                    Ok(())
                })?;
                Ctx::Skip
            }
            (Ctx::NetworkManagement, b"CANopenGeneralFeatures") => {
                self.seen_can = true;
                self.read_general_features(e, offset)?;
                Ctx::Skip
            }
            (Ctx::NetworkManagement, b"CANopenMasterFeatures") => {
                self.seen_can = true;
                self.attrs(e, offset, |s, key, v| {
                    if key == b"bootUpMaster" {
                        s.can.simple_boot_up_master = s.boolean(&v, "bootUpMaster")?;
                    }
                    Ok(())
                })?;
                Ctx::Skip
            }
            (Ctx::NetworkManagement, b"deviceCommissioning") => {
                self.read_commissioning(e, offset)?;
                Ctx::Skip
            }
            _ => Ctx::Skip,
        };
        if matches!(
            ctx,
            Ctx::IdentityField(_) | Ctx::ProductTextDescription | Ctx::ParameterText(_)
        ) {
            self.text.clear();
        }
        Ok(ctx)
    }

    /// Handles the end of an element whose content context was `ctx`.
    fn close(&mut self, ctx: Ctx, offset: usize) -> Result<(), ParseError> {
        match ctx {
            Ctx::IdentityField(field) => {
                let text = std::mem::take(&mut self.text);
                match field {
                    IdField::VendorName => self.vendor_name = Some(text),
                    IdField::ProductName => self.product_name = Some(text),
                    IdField::OrderNumber => {
                        if self.order_number.is_none() {
                            self.order_number = Some(text)
                        }
                    }
                    IdField::VendorId | IdField::ProductId => {
                        let what = if field == IdField::VendorId {
                            "vendorID"
                        } else {
                            "productID"
                        };
                        let value = if text.trim().is_empty() {
                            None
                        } else {
                            Some(
                                xml::parse_number(&text)
                                    .and_then(|v| u32::try_from(v).ok())
                                    .ok_or_else(|| {
                                        self.err(
                                            offset,
                                            format!(
                                                "expected a 32-bit number like 0x0000012E in <{what}>, found `{}`",
                                                text.trim()
                                            ),
                                        )
                                    })?,
                            )
                        };
                        if field == IdField::VendorId {
                            self.vendor_id = value;
                        } else {
                            self.product_id = value;
                        }
                    }
                }
            }
            Ctx::ProductTextDescription => {
                let text = std::mem::take(&mut self.text);
                self.product_text.offer(text, self.text_lang_en);
            }
            Ctx::ParameterText(kind) => {
                let text = std::mem::take(&mut self.text);
                let english = self.text_lang_en;
                if let Some((_, p)) = &mut self.param {
                    match kind {
                        TextKind::Label => p.label.offer(text, english),
                        TextKind::Description => p.description.offer(text, english),
                    }
                }
            }
            Ctx::DataTypeDef => {
                if let Some((id, dt)) = self.data_type.take() {
                    if self.data_types.contains_key(id.text.as_ref()) {
                        return Err(self.err(
                            id.offset,
                            format!(
                                "uniqueID `{}` is defined twice in the dataTypeList",
                                id.text
                            ),
                        ));
                    }
                    self.data_types.insert(id.text, dt);
                }
            }
            Ctx::Parameter => {
                if let Some((id, p)) = self.param.take() {
                    if self.params.contains_key(id.text.as_ref()) {
                        return Err(self.err(
                            id.offset,
                            format!("parameter uniqueID `{}` is defined twice", id.text),
                        ));
                    }
                    self.params.insert(id.text, p);
                }
            }
            Ctx::Object => {
                if let Some(o) = self.object.take() {
                    self.objects.push(o);
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// True when the element's `lang` attribute names English (or is absent on a single-language file).
    fn english(&mut self, e: &Element<'a>, offset: usize) -> Result<bool, ParseError> {
        let mut english = false;
        self.attrs(e, offset, |_, key, v| {
            if key == b"lang" {
                let l = v.text.trim();
                english = l.eq_ignore_ascii_case("en")
                    || l.get(..3).is_some_and(|p| p.eq_ignore_ascii_case("en-"));
            }
            Ok(())
        })?;
        Ok(english)
    }

    fn boolean(&self, v: &Attr<'_>, what: &str) -> Result<bool, ParseError> {
        xml::parse_bool(&v.text).ok_or_else(|| {
            self.err(
                v.offset,
                format!("expected true or false in {what}, found `{}`", v.text),
            )
        })
    }

    fn number<T: TryFrom<i128>>(
        &self,
        v: &Attr<'_>,
        what: &str,
        like: &str,
    ) -> Result<T, ParseError> {
        xml::parse_number(&v.text)
            .and_then(|n| T::try_from(n).ok())
            .ok_or_else(|| {
                self.err(
                    v.offset,
                    format!(
                        "expected a number like {like} in {what}, found `{}`",
                        v.text
                    ),
                )
            })
    }

    /// A number of at most `digits` hexadecimal digits, with or without `0x` (`noun`, `like` and `what`
    /// for the message).
    fn hex<T: TryFrom<u16>>(
        &self,
        v: &Attr<'_>,
        noun: &str,
        digits: usize,
        like: &str,
        what: &str,
    ) -> Result<T, ParseError> {
        let t = v.text.trim();
        let t = t
            .strip_prefix("0x")
            .or_else(|| t.strip_prefix("0X"))
            .unwrap_or(t);
        (!t.is_empty() && t.len() <= digits)
            .then(|| u16::from_str_radix(t, 16).ok())
            .flatten()
            .and_then(|n| T::try_from(n).ok())
            .ok_or_else(|| {
                self.err(
                    v.offset,
                    format!(
                        "expected {noun} of {digits} hex digits like {like} in {what}, found `{}`",
                        v.text
                    ),
                )
            })
    }

    fn open_body(&mut self, e: &Element<'a>, offset: usize) -> Result<Ctx, ParseError> {
        let mut kind: Option<Cow<'a, str>> = None;
        let mut file = FileAttrs::default();
        self.attrs(e, offset, |_, key, v| {
            let slot = match key {
                b"type" => {
                    kind = Some(v.text);
                    return Ok(());
                }
                b"fileName" => &mut file.file_name,
                b"fileVersion" => &mut file.file_version,
                b"fileCreator" => &mut file.created_by,
                b"fileCreationDate" => &mut file.creation_date,
                b"fileCreationTime" => &mut file.creation_time,
                b"fileModifiedBy" => &mut file.modified_by,
                b"fileModificationDate" => &mut file.modification_date,
                b"fileModificationTime" => &mut file.modification_time,
                _ => return Ok(()),
            };
            *slot = Some(v.text.into_owned());
            Ok(())
        })?;
        let kind = kind.as_deref().map(|k| k.rsplit(':').next().unwrap_or(k));
        match kind {
            Some("ProfileBody_Device_CANopen") => {
                if self.device_file.is_none() {
                    self.device_file = Some(file);
                }
                Ok(Ctx::Body)
            }
            Some("ProfileBody_CommunicationNetwork_CANopen") => {
                self.seen_network_body = true;
                if self.network_file.is_none() {
                    self.network_file = Some(file);
                }
                Ok(Ctx::Body)
            }
            // A body without a type is read for whatever CANopen content it has.
            None => Ok(Ctx::Body),
            // POWERLINK (EPSG DS 311) describes its object dictionary as CANopen does, in
            // `ObjectList/Object/SubObject`: read it, as openCONFIGURATOR does.
            Some(
                k @ ("ProfileBody_Device_Powerlink" | "ProfileBody_CommunicationNetwork_Powerlink"),
            ) => {
                if self.powerlink.is_none() {
                    self.powerlink = Some((offset, k.to_string()));
                }
                if self.device_file.is_none() {
                    self.device_file = Some(file);
                }
                Ok(Ctx::Body)
            }
            // Other technologies and other profile kinds.
            Some(k) => {
                self.other_bodies.push((offset, k.to_string()));
                Ok(Ctx::Skip)
            }
        }
    }

    fn open_data_type(
        &mut self,
        e: &Element<'a>,
        offset: usize,
        kind: DtKind,
    ) -> Result<(), ParseError> {
        let mut id = None;
        let mut name = String::new();
        self.attrs(e, offset, |_, key, v| {
            match key {
                b"uniqueID" => id = Some(v),
                b"name" => name = v.text.into_owned(),
                _ => {}
            }
            Ok(())
        })?;
        // A type without a uniqueID cannot be referred to; its content is not needed.
        self.data_type = id.map(|id| {
            (
                id,
                DtRec {
                    name,
                    kind,
                    base: None,
                },
            )
        });
        Ok(())
    }

    fn open_parameter(&mut self, e: &Element<'a>, offset: usize) -> Result<(), ParseError> {
        let mut id = None;
        let mut param = ParamRec::new();
        self.attrs(e, offset, |s, key, v| {
            match key {
                b"uniqueID" => id = Some(v),
                b"access" => {
                    param.access = Some(parse_parameter_access(&v.text).ok_or_else(|| {
                        s.err(
                            v.offset,
                            format!(
                                "expected access const, read, write, readWrite, readWriteInput, readWriteOutput or noAccess, found `{}`",
                                v.text
                            ),
                        )
                    })?)
                }
                _ => {}
            }
            Ok(())
        })?;
        let id =
            id.ok_or_else(|| self.err(offset, "expected a uniqueID attribute in <parameter>"))?;
        self.param = Some((id, param));
        Ok(())
    }

    fn open_parameter_child(
        &mut self,
        e: &Element<'a>,
        offset: usize,
        child: &[u8],
    ) -> Result<Ctx, ParseError> {
        match child {
            b"label" | b"description" => {
                self.text_lang_en = self.english(e, offset)?;
                Ok(Ctx::ParameterText(if child == b"label" {
                    TextKind::Label
                } else {
                    TextKind::Description
                }))
            }
            b"dataTypeIDRef" => {
                let r = self.required_attr(e, offset, b"uniqueIDRef")?;
                if let Some((_, p)) = &mut self.param {
                    p.ty = Some(TypeRef::Ref(r));
                }
                Ok(Ctx::Skip)
            }
            b"defaultValue" | b"actualValue" => {
                let value = self.required_attr(e, offset, b"value")?;
                if let Some((_, p)) = &mut self.param {
                    if child == b"defaultValue" {
                        p.default = Some(value);
                    } else {
                        p.actual = Some(value);
                    }
                }
                Ok(Ctx::Skip)
            }
            b"allowedValues" => Ok(Ctx::AllowedValues),
            b"property" => {
                let mut name = None;
                let mut value = None;
                self.attrs(e, offset, |_, key, v| {
                    match key {
                        b"name" => name = Some(v),
                        b"value" => value = Some(v),
                        _ => {}
                    }
                    Ok(())
                })?;
                if let (Some(name), Some(value)) = (name, value) {
                    if name.text == STRING_LENGTH_PROPERTY {
                        let n: u32 = self.number(&value, STRING_LENGTH_PROPERTY, "16")?;
                        if n > u32::MAX / 8 {
                            return Err(self.err(value.offset, "string length too large"));
                        }
                        if let Some((_, p)) = &mut self.param {
                            p.capacity = Some(n);
                        }
                    }
                }
                Ok(Ctx::Skip)
            }
            type_name => {
                if let (Some(t), Some((_, p))) = (parse_type_element(type_name), &mut self.param) {
                    if p.ty.is_none() {
                        p.ty = Some(TypeRef::Simple(t));
                    }
                }
                Ok(Ctx::Skip)
            }
        }
    }

    /// Reads the attributes an object and a sub-object share into `attrs`; answers the other ones.
    fn entry_attr(
        &self,
        attrs: &mut EntryAttrs<'a>,
        key: &[u8],
        v: Attr<'a>,
    ) -> Result<Option<Attr<'a>>, ParseError> {
        match key {
            b"dataType" => {
                let index = self.hex(&v, "a data type index", 4, "0007", "dataType")?;
                attrs.data_type = Some((index, v.offset));
            }
            b"accessType" => {
                attrs.access = Some(parse_access_type(&v.text).ok_or_else(|| {
                    self.err(
                        v.offset,
                        format!(
                            "expected accessType ro, wo, rw, rwr, rww or const, found `{}`",
                            v.text
                        ),
                    )
                })?)
            }
            b"PDOmapping" => {
                attrs.pdo = parse_pdo(&v.text).ok_or_else(|| {
                    self.err(
                        v.offset,
                        format!(
                            "expected PDOmapping no, default, optional, RPDO or TPDO, found `{}`",
                            v.text
                        ),
                    )
                })?
            }
            b"defaultValue" => attrs.default = Some(v),
            b"lowLimit" => attrs.low = Some(v),
            b"highLimit" => attrs.high = Some(v),
            b"actualValue" => attrs.actual = Some(v),
            b"uniqueIDRef" => attrs.unique_id_ref = Some(v),
            _ => return Ok(Some(v)),
        }
        Ok(None)
    }

    fn object_kind(&self, v: &Attr<'_>) -> Result<ObjectKind, ParseError> {
        xml::parse_number(&v.text)
            .and_then(|c| u8::try_from(c).ok())
            .and_then(ObjectKind::from_code)
            .ok_or_else(|| {
                self.err(
                    v.offset,
                    format!(
                        "expected objectType 0, 2, 5, 6, 7, 8 or 9 (NULL, DOMAIN, DEFTYPE, DEFSTRUCT, VAR, ARRAY, RECORD), found `{}`",
                        v.text
                    ),
                )
            })
    }

    fn open_object(&mut self, e: &Element<'a>, offset: usize) -> Result<(), ParseError> {
        let mut attrs = EntryAttrs::default();
        let mut index = None;
        let mut name: Cow<'a, str> = Cow::Borrowed("");
        let mut kind = None;
        self.attrs(e, offset, |s, key, v| {
            let Some(v) = s.entry_attr(&mut attrs, key, v)? else {
                return Ok(());
            };
            match key {
                b"index" => index = Some(s.hex(&v, "an index", 4, "1A00", "index")?),
                b"name" => name = v.text,
                b"objectType" => kind = Some(s.object_kind(&v)?),
                _ => {}
            }
            Ok(())
        })?;
        let index = index
            .ok_or_else(|| self.err(offset, "expected an index attribute in <CANopenObject>"))?;
        let kind = kind.ok_or_else(|| {
            self.err(
                offset,
                format!("expected an objectType attribute in <CANopenObject> 0x{index:04X}"),
            )
        })?;
        self.object = Some(ObjRec {
            offset,
            index,
            name,
            kind,
            attrs,
            subs: Vec::new(),
        });
        Ok(())
    }

    fn open_sub_object(&mut self, e: &Element<'a>, offset: usize) -> Result<(), ParseError> {
        let mut attrs = EntryAttrs::default();
        let mut sub = None;
        let mut name: Cow<'a, str> = Cow::Borrowed("");
        self.attrs(e, offset, |s, key, v| {
            let Some(v) = s.entry_attr(&mut attrs, key, v)? else {
                return Ok(());
            };
            match key {
                b"subIndex" => sub = Some(s.hex(&v, "a sub-index", 2, "01", "subIndex")?),
                b"name" => name = v.text,
                b"objectType" => {
                    s.object_kind(&v)?;
                }
                _ => {}
            }
            Ok(())
        })?;
        let sub = sub.ok_or_else(|| {
            self.err(
                offset,
                "expected a subIndex attribute in <CANopenSubObject>",
            )
        })?;
        if let Some(o) = &mut self.object {
            o.subs.push(SubRec {
                offset,
                sub,
                name,
                attrs,
            });
        }
        Ok(())
    }

    fn read_dummy(&mut self, e: &Element<'a>, offset: usize) -> Result<(), ParseError> {
        self.attrs(e, offset, |s, key, v| {
            if key != b"entry" {
                return Ok(());
            }
            let bad = || {
                s.err(
                    v.offset,
                    format!(
                        "expected a dummy entry like Dummy0005=1, found `{}`",
                        v.text
                    ),
                )
            };
            let t = v.text.trim();
            let (name, used) = t.split_once('=').ok_or_else(bad)?;
            let name = name.trim();
            let digits = name
                .get(..5)
                .filter(|p| p.eq_ignore_ascii_case("dummy"))
                .and_then(|_| name.get(5..))
                .filter(|d| d.len() == 4)
                .ok_or_else(bad)?;
            let index = u16::from_str_radix(digits, 16).map_err(|_| bad())?;
            let used = match used.trim() {
                "1" => true,
                "0" => false,
                _ => return Err(bad()),
            };
            s.dummies.insert(index, used);
            Ok(())
        })
    }

    fn read_general_features(&mut self, e: &Element<'a>, offset: usize) -> Result<(), ParseError> {
        self.attrs(e, offset, |s, key, v| {
            match key {
                b"granularity" => {
                    let g: u8 = s.number(&v, "granularity", "8")?;
                    if g > 64 {
                        return Err(s.err(
                            v.offset,
                            format!("expected a granularity of 0 to 64 bits, found `{}`", v.text),
                        ));
                    }
                    s.can.granularity = g;
                }
                b"nrOfRxPDO" => s.can.nr_of_rx_pdo = s.number(&v, "nrOfRxPDO", "4")?,
                b"nrOfTxPDO" => s.can.nr_of_tx_pdo = s.number(&v, "nrOfTxPDO", "4")?,
                b"dynamicChannels" => {
                    s.can.dynamic_channels = s.number(&v, "dynamicChannels", "0")?
                }
                b"bootUpSlave" => s.can.simple_boot_up_slave = s.boolean(&v, "bootUpSlave")?,
                b"groupMessaging" => s.can.group_messaging = s.boolean(&v, "groupMessaging")?,
                b"layerSettingServiceSlave" => {
                    s.can.lss_supported = s.boolean(&v, "layerSettingServiceSlave")?
                }
                _ => {}
            }
            Ok(())
        })
    }

    fn read_commissioning(&mut self, e: &Element<'a>, offset: usize) -> Result<(), ParseError> {
        let mut c = Commissioning::default();
        let mut has_node_id = false;
        self.attrs(e, offset, |s, key, v| {
            match key {
                // CANopenEditor writes `NodeID`.
                b"nodeID" | b"NodeID" => {
                    has_node_id = true;
                    let id: u8 = s.number(&v, "nodeID", "5")?;
                    if !(1..=127).contains(&id) {
                        return Err(s.err(
                            v.offset,
                            format!("expected a nodeID of 1 to 127, found `{}`", v.text),
                        ));
                    }
                    c.node_id = Some(id);
                }
                b"nodeName" => c.node_name = v.text.into_owned(),
                b"actualBaudRate" => {
                    c.baud_rate = parse_baud(&v.text).ok_or_else(|| {
                        s.err(
                            v.offset,
                            format!(
                            "expected a bit rate like \"250 Kbps\" in actualBaudRate, found `{}`",
                            v.text
                        ),
                        )
                    })?
                }
                b"networkNumber" => c.net_number = s.number(&v, "networkNumber", "1")?,
                b"networkName" => c.network_name = v.text.into_owned(),
                b"CANopenManager" => c.canopen_manager = s.boolean(&v, "CANopenManager")?,
                _ => {}
            }
            Ok(())
        })?;
        if !has_node_id {
            return Err(self.err(
                offset,
                "expected a nodeID attribute in <deviceCommissioning>",
            ));
        }
        self.commissioning = Some(c);
        Ok(())
    }

    /// Resolves the references and builds the description.
    fn finish(mut self) -> Result<(DeviceDescription, Vec<Finding>), ParseError> {
        let node_id = self
            .commissioning
            .as_ref()
            .and_then(|c| c.node_id)
            .unwrap_or(0);
        let mut dictionary = Dictionary::new();
        let objects = std::mem::take(&mut self.objects);
        for o in &objects {
            let object = self.build_object(o, node_id)?;
            if dictionary.insert(object).is_some() {
                return Err(self.err(
                    o.offset,
                    format!("object 0x{:04X} is defined twice", o.index),
                ));
            }
        }

        let file = self
            .device_file
            .take()
            .or(self.network_file.take())
            .unwrap_or_default();
        let file_info = FileInfo {
            file_name: file.file_name.unwrap_or_default(),
            file_version: file.file_version.unwrap_or_default(),
            description: self.product_text.text.take().unwrap_or_default(),
            creation_time: file.creation_time.unwrap_or_default(),
            creation_date: file.creation_date.unwrap_or_default(),
            created_by: file.created_by.unwrap_or_default(),
            modification_time: file.modification_time.unwrap_or_default(),
            modification_date: file.modification_date.unwrap_or_default(),
            modified_by: file.modified_by.unwrap_or_default(),
            ..FileInfo::default()
        };

        let default_u32 = |sub: u8| -> Option<u32> {
            let d = dictionary.object(0x1018)?.sub(sub)?.default.as_ref()?;
            if d.plus_node_id {
                return None;
            }
            d.value.as_i128().and_then(|v| u32::try_from(v).ok())
        };
        let mut desc = DeviceDescription::default();
        desc.identity.vendor_name = self.vendor_name.take().unwrap_or_default();
        desc.identity.product_name = self.product_name.take().unwrap_or_default();
        desc.identity.order_code = self.order_number.take().unwrap_or_default();
        desc.identity.vendor_id = self.vendor_id.or_else(|| default_u32(1)).unwrap_or(0);
        desc.identity.product_code = self.product_id.or_else(|| default_u32(2)).unwrap_or(0);
        desc.identity.revision = default_u32(3).unwrap_or(0);
        desc.file_info = file_info;
        if self.seen_network_body && self.seen_can {
            let mut can = std::mem::take(&mut self.can);
            can.baud_rates = std::mem::take(&mut self.baud_rates).into_iter().collect();
            can.dummy_usage = std::mem::take(&mut self.dummies)
                .into_iter()
                .filter_map(|(index, used)| used.then_some(index))
                .collect();
            desc.can = Some(can);
        }
        desc.commissioning = self.commissioning.take();
        desc.dictionary = dictionary;
        Ok((desc, self.doc.take_findings()))
    }

    /// How an entry whose `dataType` is no CiA 301 basic type is read: the POWERLINK types (EPSG DS
    /// 301 §6.1.4: MAC_ADDRESS, IP_ADDRESS, NETTIME) as the basic types of their size, anything else
    /// (a complex or profile type) as DOMAIN, as EDS readers take them.
    fn other_type(&self, index: u16) -> (DataType, Option<u32>, &'static str) {
        match (index, self.powerlink.is_some()) {
            (0x0401, true) => (
                DataType::OctetString,
                Some(48),
                "the POWERLINK MAC_ADDRESS (6 octets)",
            ),
            (0x0402, true) => (
                DataType::Unsigned32,
                None,
                "the POWERLINK IP_ADDRESS (4 octets)",
            ),
            (0x0403, true) => (
                DataType::Unsigned64,
                None,
                "the POWERLINK NETTIME (seconds and nanoseconds, 8 octets)",
            ),
            (0x0020..=0x025F, _) => (DataType::Domain, None, "a complex or profile data type"),
            _ => (DataType::Domain, None, "not a CiA 301 data type"),
        }
    }

    /// A warning at byte `offset`.
    fn warn(&self, offset: usize, message: String) {
        self.doc.warn(offset, message);
    }

    fn param(&self, r: &Option<Attr<'a>>) -> Result<Option<&ParamRec<'a>>, ParseError> {
        let Some(r) = r else { return Ok(None) };
        match self.params.get(r.text.as_ref()) {
            Some(p) => Ok(Some(p)),
            None => Err(self.err(
                r.offset,
                format!(
                    "uniqueIDRef `{}` names no parameter of the parameterList",
                    r.text
                ),
            )),
        }
    }

    fn data_type_def(&self, r: &Attr<'a>) -> Result<&DtRec, ParseError> {
        self.data_types.get(r.text.as_ref()).ok_or_else(|| {
            self.err(
                r.offset,
                format!(
                    "dataTypeIDRef `{}` names no type of the dataTypeList",
                    r.text
                ),
            )
        })
    }

    fn build_object(&self, o: &ObjRec<'a>, node_id: u8) -> Result<Object, ParseError> {
        let param = self.param(&o.attrs.unique_id_ref)?;
        let mut object = Object::structured(o.index, o.name.as_ref(), o.kind);
        object.description = param.and_then(|p| p.description(&o.name));
        // The element type that subs without a type of their own take (an array's element type).
        let mut element_type = None;
        if let Some(TypeRef::Ref(r)) = param.and_then(|p| p.ty.as_ref()) {
            let dt = self.data_type_def(r)?;
            if o.kind.has_subs() && dt.kind != DtKind::Simple {
                object.type_name = Some(dt.name.clone());
            }
            element_type = dt.base;
        } else if let Some(TypeRef::Simple(t)) = param.and_then(|p| p.ty.as_ref()) {
            if o.kind.has_subs() {
                element_type = Some(*t);
            }
        }

        if !o.subs.is_empty() {
            for s in &o.subs {
                let sub_param = self.param(&s.attrs.unique_id_ref)?;
                let fallback = if o.kind.has_subs() && s.sub == 0 {
                    Some(XddType::Basic(DataType::Unsigned8))
                } else {
                    element_type
                };
                let mut entry = self.build_entry(
                    o, s.sub, &s.name, &s.attrs, sub_param, fallback, s.offset, node_id,
                )?;
                entry.description = sub_param.and_then(|p| p.description(&s.name));
                if object.subs.insert(s.sub, entry).is_some() {
                    return Err(self.err(
                        s.offset,
                        format!(
                            "sub-index {:02X} of object 0x{:04X} is defined twice",
                            s.sub, o.index
                        ),
                    ));
                }
            }
        } else if !o.kind.has_subs() && o.kind != ObjectKind::Null {
            let mut entry =
                self.build_entry(o, 0, &o.name, &o.attrs, param, None, o.offset, node_id)?;
            entry.description = object.description.clone();
            object.subs.insert(0, entry);
        }
        Ok(object)
    }

    #[allow(clippy::too_many_arguments)]
    fn build_entry(
        &self,
        o: &ObjRec<'a>,
        sub: u8,
        name: &str,
        attrs: &EntryAttrs<'a>,
        param: Option<&ParamRec<'a>>,
        fallback: Option<XddType>,
        offset: usize,
        node_id: u8,
    ) -> Result<SubObject, ParseError> {
        let at = format!("0x{:04X}:{sub:02X}", o.index);
        let default = attrs
            .default
            .as_ref()
            .or(param.and_then(|p| p.default.as_ref()));

        // Data type: the dataType attribute, else the parameter's type, else the array's element type.
        let mut capacity = None;
        let data_type = if let Some((index, off)) = attrs.data_type {
            match DataType::from_index(index) {
                Some(t) => t,
                None => {
                    let (t, bits, what) = self.other_type(index);
                    capacity = bits;
                    self.warn(
                        off,
                        format!("dataType {index:04X} of {at} is {what}; the entry is read as {t}"),
                    );
                    t
                }
            }
        } else {
            let xt = match param.and_then(|p| p.ty.as_ref()) {
                Some(TypeRef::Simple(t)) => Some(*t),
                Some(TypeRef::Ref(r)) => {
                    let dt = self.data_type_def(r)?;
                    if dt.kind != DtKind::Simple {
                        return Err(self.err(
                            r.offset,
                            format!(
                                "{at} has the structured type `{}`; expected a basic type for a value",
                                r.text
                            ),
                        ));
                    }
                    dt.base
                }
                None => None,
            }
            .or(fallback);
            match xt {
                Some(XddType::Basic(t)) => t,
                Some(XddType::BitString) => {
                    let has_default = default.is_some_and(|d| !d.text.trim().is_empty());
                    if o.kind == ObjectKind::Domain || !has_default {
                        DataType::Domain
                    } else {
                        DataType::OctetString
                    }
                }
                None => {
                    return Err(self.err(
                        offset,
                        format!(
                            "no data type for {at}: expected a dataType attribute or a uniqueIDRef to a parameter with a type"
                        ),
                    ))
                }
            }
        };

        // The object's accessType wins, except that the parameter may refine `rw` into `rwr` or `rww`,
        // which the schema's accessType cannot say.
        let param_access = param.and_then(|p| p.access);
        let access = match (attrs.access, param_access) {
            (Some(AccessType::Rw), Some(refined @ (AccessType::Rwr | AccessType::Rww))) => refined,
            (Some(a), _) => a,
            (None, Some(a)) => a,
            (None, None) => AccessType::Ro,
        };
        let mut entry = SubObject::new(name, data_type, access);
        entry.pdo = attrs.pdo;

        if let Some(d) = default {
            entry.default = self.parse_default(data_type, d, &at)?;
        }
        let low = attrs.low.as_ref().or(param.and_then(|p| p.low.as_ref()));
        let high = attrs.high.as_ref().or(param.and_then(|p| p.high.as_ref()));
        if let Some(l) = low {
            entry.low = self.parse_value(data_type, l, "lowLimit", &at)?;
        }
        if let Some(h) = high {
            entry.high = self.parse_value(data_type, h, "highLimit", &at)?;
        }
        if has_string_capacity(data_type) {
            if let Some(cap) = param.and_then(|p| p.capacity) {
                let default_len = entry
                    .default
                    .as_ref()
                    .and_then(|d| d.value.encode(data_type).ok())
                    .map_or(0, |b| b.len());
                let bytes = (cap as usize).max(default_len);
                entry.bit_size = u32::try_from(bytes).ok().and_then(|b| b.checked_mul(8));
            }
        }
        if capacity.is_some() {
            entry.bit_size = capacity;
        }
        entry.reset(node_id);
        let actual = attrs
            .actual
            .as_ref()
            .or(param.and_then(|p| p.actual.as_ref()));
        if let Some(a) = actual {
            if let Some(v) = self.parse_value(data_type, a, "actualValue", &at)? {
                entry.value = v.encode(data_type).map_err(|e| {
                    self.err(a.offset, format!("actualValue of {at} does not fit: {e}"))
                })?;
                entry.value_set = true;
            }
        }
        Ok(entry)
    }

    fn parse_value(
        &self,
        t: DataType,
        v: &Attr<'_>,
        what: &str,
        at: &str,
    ) -> Result<Option<Value>, ParseError> {
        if !is_text_type(t) && v.text.trim().is_empty() {
            return Ok(None);
        }
        let value = Value::parse_text(t, &v.text).map_err(|e| {
            self.err(
                v.offset,
                format!(
                    "expected a {t} value in {what} of {at}, found `{}`: {e}",
                    v.text
                ),
            )
        })?;
        if matches!(value, Value::Real32(f) if !f.is_finite()) {
            return Err(self.err(
                v.offset,
                format!("{what} of {at} is beyond the range of REAL32: `{}`", v.text),
            ));
        }
        Ok(Some(value))
    }

    fn parse_default(
        &self,
        t: DataType,
        v: &Attr<'_>,
        at: &str,
    ) -> Result<Option<DefaultValue>, ParseError> {
        if !is_text_type(t) {
            if v.text.trim().is_empty() {
                return Ok(None);
            }
            if let Some(rest) = strip_node_id(&v.text) {
                let value = if rest.is_empty() {
                    Ok(Value::zero(t))
                } else {
                    Value::parse_text(t, rest)
                };
                let value = value.ok().filter(|_| t.is_signed() || t.is_unsigned());
                return match value {
                    // The default must fit for every node-ID, up to 127.
                    Some(value) => match (DefaultValue { value, plus_node_id: true }) {
                        d if d.resolve(127).encode(t).is_ok() => Ok(Some(d)),
                        _ => Err(self.err(
                            v.offset,
                            format!(
                                "defaultValue of {at} ({t}): `{}` does not fit with node-ID 127",
                                v.text
                            ),
                        )),
                    },
                    None => Err(self.err(
                        v.offset,
                        format!(
                            "expected an integer offset like $NODEID+0x180 in defaultValue of {at} ({t}), found `{}`",
                            v.text
                        ),
                    )),
                };
            }
        }
        Ok(self
            .parse_value(t, v, "defaultValue", at)?
            .map(DefaultValue::plain))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::ObjectKind;

    fn wrap(network: &str, device: &str) -> String {
        format!(
            r#"<?xml version="1.0" encoding="UTF-8"?>
<ISO15745ProfileContainer xmlns="http://www.canopen.org/xml/1.0" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
<ISO15745Profile>
<ProfileBody xsi:type="ProfileBody_Device_CANopen" fileName="t.xdd" fileCreator="me" fileCreationDate="2024-01-02" fileVersion="3">
{device}
</ProfileBody>
</ISO15745Profile>
<ISO15745Profile>
<ProfileBody xsi:type="ProfileBody_CommunicationNetwork_CANopen" fileName="t.xdd">
<ApplicationLayers>
<CANopenObjectList>
{network}
</CANopenObjectList>
</ApplicationLayers>
</ProfileBody>
</ISO15745Profile>
</ISO15745ProfileContainer>
"#
        )
    }

    fn err_of(text: &str) -> ParseError {
        read(text.as_bytes(), "t.xdd").unwrap_err()
    }

    #[test]
    fn node_id_defaults_must_fit_for_node_127() {
        let text = wrap(
            r#"<CANopenObject index="1014" name="COB-ID EMCY" objectType="7" dataType="0007" accessType="rw" defaultValue="$NODEID+0xFFFFFFFF" PDOmapping="no"/>"#,
            "",
        );
        let e = err_of(&text);
        assert!(e.message.contains("does not fit with node-ID 127"), "{e}");
    }

    #[test]
    fn inline_objects() {
        let text = wrap(
            r#"<CANopenObject index="1014" name="COB-ID EMCY" objectType="7" dataType="0007" accessType="rw" defaultValue="$NODEID+0x80" PDOmapping="no"/>
<CANopenObject index="2000" name="Speed" objectType="7" dataType="0003" accessType="rww" defaultValue="-5" lowLimit="-100" highLimit="0x64" PDOmapping="RPDO"/>
<CANopenObject index="1018" name="Identity" objectType="9" subNumber="2">
  <CANopenSubObject subIndex="00" name="Highest sub-index supported" objectType="7" dataType="0005" accessType="ro" defaultValue="1"/>
  <CANopenSubObject subIndex="01" name="Vendor-ID" objectType="7" dataType="0007" accessType="ro" defaultValue="0x12E" PDOmapping="optional"/>
</CANopenObject>"#,
            "<DeviceIdentity><vendorName>B&amp;R</vendorName><productName>P</productName><orderNumber>X-1</orderNumber></DeviceIdentity>",
        );
        let d = read(text.as_bytes(), "t.xdd").unwrap();
        assert_eq!(d.dictionary.len(), 3);
        let emcy = d.dictionary.entry(0x1014, 0).unwrap();
        assert_eq!(
            emcy.default,
            Some(DefaultValue {
                value: Value::Uint(0x80),
                plus_node_id: true
            })
        );
        assert_eq!(emcy.access.kind, AccessType::Rw);
        assert_eq!(emcy.value, vec![0x80, 0, 0, 0]);
        let speed = d.dictionary.entry(0x2000, 0).unwrap();
        assert_eq!(speed.data_type, DataType::Integer16);
        assert_eq!(speed.default, Some(DefaultValue::plain(Value::Int(-5))));
        assert_eq!(speed.low, Some(Value::Int(-100)));
        assert_eq!(speed.high, Some(Value::Int(100)));
        assert_eq!(speed.pdo, PdoMapping::Rpdo);
        assert_eq!(speed.access.kind, AccessType::Rww);
        assert_eq!(speed.value, (-5i16).to_le_bytes());
        let id = d.dictionary.object(0x1018).unwrap();
        assert_eq!(id.kind, ObjectKind::Record);
        assert_eq!(id.subs.len(), 2);
        assert_eq!(id.subs[&1].pdo, PdoMapping::Both);
        assert_eq!(d.identity.vendor_name, "B&R");
        assert_eq!(d.identity.vendor_id, 0x12E, "from 0x1018:01");
        assert_eq!(d.identity.order_code, "X-1");
        assert_eq!(d.file_info.file_name, "t.xdd");
        assert_eq!(d.file_info.created_by, "me");
        assert_eq!(d.file_info.creation_date, "2024-01-02");
        assert_eq!(d.file_info.file_version, "3");
        assert_eq!(d.can, None, "a network body without CAN parts");
    }

    #[test]
    fn parameters_by_unique_id_in_either_order_with_prefixes() {
        let network = r#"<ISO15745Profile>
<ProfileBody xmlns:q2="http://www.canopen.org/xml/1.1" xsi:type="q2:ProfileBody_CommunicationNetwork_CANopen">
<ApplicationLayers><q2:CANopenObjectList>
<CANopenObject index="2100" name="Errors" objectType="7" PDOmapping="no" uniqueIDRef="UID_OBJ_2100"/>
<CANopenObject index="2101" name="Mode" objectType="7" accessType="ro" defaultValue="3" uniqueIDRef="UID_OBJ_2101"/>
<CANopenObject index="6000" name="Inputs" objectType="8" uniqueIDRef="UID_OBJ_6000" subNumber="2">
  <CANopenSubObject subIndex="00" name="Highest sub-index supported" objectType="7" uniqueIDRef="UID_SUB_600000"/>
  <CANopenSubObject subIndex="01" name="Input" objectType="7" PDOmapping="TPDO" uniqueIDRef="UID_SUB_600001"/>
</CANopenObject>
<CANopenObject index="2122" name="Demo domain" objectType="7" uniqueIDRef="UID_OBJ_2122"/>
</q2:CANopenObjectList></ApplicationLayers>
</ProfileBody></ISO15745Profile>"#;
        let device = r#"<ISO15745Profile>
<ProfileBody xmlns:q1="http://www.canopen.org/xml/1.1" xsi:type="q1:ProfileBody_Device_CANopen" fileName="p.xdd">
<q1:DeviceIdentity><q1:vendorName>V</q1:vendorName><q1:vendorID>0x5</q1:vendorID><q1:productID>7</q1:productID>
<q1:productText><description lang="de">Gerät</description><description lang="en">Device</description></q1:productText>
<q1:version versionType="SW">1.0</q1:version></q1:DeviceIdentity>
<q1:ApplicationProcess>
<q1:dataTypeList>
  <q1:array name="Inputs type" uniqueID="UID_ARR_6000"><q1:subrange lowerLimit="0" upperLimit="1"/><USINT/></q1:array>
</q1:dataTypeList>
<q1:parameterList>
  <q1:parameter uniqueID="UID_OBJ_2100" access="readWrite"><description lang="en">Error bits
second line</description><BITSTRING/><q1:defaultValue value="00 01"/></q1:parameter>
  <q1:parameter uniqueID="UID_OBJ_2101" access="readWrite"><label lang="en">Mode</label><UINT/><q1:defaultValue value="9"/>
    <q1:allowedValues><q1:range><q1:minValue value="1"/><q1:maxValue value="5"/></q1:range></q1:allowedValues></q1:parameter>
  <q1:parameter uniqueID="UID_OBJ_6000"><description lang="en">Digital inputs.</description><q1:dataTypeIDRef uniqueIDRef="UID_ARR_6000"/></q1:parameter>
  <q1:parameter uniqueID="UID_SUB_600000"><label lang="en">Highest sub-index supported</label><USINT/><q1:defaultValue value="0x01"/></q1:parameter>
  <q1:parameter uniqueID="UID_SUB_600001"><label lang="en">Input 1 of 8</label><q1:defaultValue value="0"/></q1:parameter>
  <q1:parameter uniqueID="UID_OBJ_2122" access="readWrite"><label lang="en">Demo domain</label><BITSTRING/></q1:parameter>
</q1:parameterList>
</q1:ApplicationProcess>
</ProfileBody></ISO15745Profile>"#;
        for (first, second) in [(network, device), (device, network)] {
            let text = format!(
                "<?xml version=\"1.1\" encoding=\"utf-8\"?>\n<ISO15745ProfileContainer xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\">{first}{second}</ISO15745ProfileContainer>"
            );
            let d = read(text.as_bytes(), "p.xdd").unwrap();
            assert_eq!(d.identity.vendor_id, 5);
            assert_eq!(d.identity.product_code, 7);
            assert_eq!(d.file_info.description, "Device");
            assert_eq!(d.file_info.file_name, "p.xdd");
            let errors = d.dictionary.object(0x2100).unwrap();
            assert_eq!(
                errors.description.as_deref(),
                Some("Error bits\nsecond line")
            );
            assert_eq!(errors.subs[&0].description, errors.description);
            let e = &errors.subs[&0];
            assert_eq!(e.data_type, DataType::OctetString);
            assert_eq!(e.access.kind, AccessType::Rw);
            assert_eq!(e.value, vec![0, 1]);
            let mode = d.dictionary.entry(0x2101, 0).unwrap();
            assert_eq!(mode.data_type, DataType::Unsigned16);
            assert_eq!(mode.access.kind, AccessType::Ro, "inline accessType wins");
            assert_eq!(
                mode.default,
                Some(DefaultValue::plain(Value::Uint(3))),
                "inline default wins"
            );
            assert_eq!(mode.low, Some(Value::Uint(1)));
            assert_eq!(mode.high, Some(Value::Uint(5)));
            assert_eq!(
                mode.description, None,
                "a label equal to the name is no description"
            );
            let inputs = d.dictionary.object(0x6000).unwrap();
            assert_eq!(inputs.type_name.as_deref(), Some("Inputs type"));
            assert_eq!(inputs.description.as_deref(), Some("Digital inputs."));
            assert_eq!(
                inputs.subs[&1].data_type,
                DataType::Unsigned8,
                "element type of the array"
            );
            assert_eq!(inputs.subs[&1].pdo, PdoMapping::Tpdo);
            assert_eq!(inputs.subs[&1].description.as_deref(), Some("Input 1 of 8"));
            assert_eq!(
                inputs.subs[&0].default,
                Some(DefaultValue::plain(Value::Uint(1)))
            );
            assert_eq!(inputs.subs[&0].description, None);
            let domain = d.dictionary.entry(0x2122, 0).unwrap();
            assert_eq!(
                domain.data_type,
                DataType::Domain,
                "BITSTRING without default"
            );
        }
    }

    #[test]
    fn commissioning_features_and_actual_values() {
        let text = r#"<ISO15745ProfileContainer><ISO15745Profile>
<ProfileBody xsi:type="ProfileBody_CommunicationNetwork_CANopen" xmlns:xsi="x">
<ApplicationLayers>
<CANopenObjectList>
<CANopenObject index="1800" name="TPDO" objectType="9">
  <CANopenSubObject subIndex="01" name="COB-ID" objectType="7" dataType="0007" accessType="rw" defaultValue="$NODEID+0x180" actualValue="0x00000190"/>
  <CANopenSubObject subIndex="02" name="Type" objectType="7" dataType="0005" accessType="rw" defaultValue="0xFF"/>
</CANopenObject>
</CANopenObjectList>
<dummyUsage><dummy entry="Dummy0001=0"/><dummy entry="Dummy0007=1"/><dummy entry="Dummy0005=1"/></dummyUsage>
</ApplicationLayers>
<TransportLayers><PhysicalLayer><baudRate defaultValue="250 Kbps"><supportedBaudRate value="500 Kbps"/><supportedBaudRate value="125 Kbps"/><supportedBaudRate value="auto-baudRate"/></baudRate></PhysicalLayer></TransportLayers>
<NetworkManagement>
<CANopenGeneralFeatures granularity="0" nrOfRxPDO="2" nrOfTxPDO="3" bootUpSlave="true" groupMessaging="1" dynamicChannels="1" layerSettingServiceSlave="false" selfStartingDevice="true"/>
<CANopenMasterFeatures bootUpMaster="true"/>
<deviceCommissioning nodeID="5" nodeName="axis" actualBaudRate="500 Kbps" networkNumber="2" networkName="line" CANopenManager="false"/>
</NetworkManagement>
</ProfileBody></ISO15745Profile></ISO15745ProfileContainer>"#;
        let d = read(text.as_bytes(), "t.xdc").unwrap();
        let can = d.can.as_ref().unwrap();
        assert_eq!(can.baud_rates, vec![125, 500]);
        assert_eq!(can.dummy_usage, vec![5, 7]);
        assert_eq!(can.granularity, 0);
        assert_eq!((can.nr_of_rx_pdo, can.nr_of_tx_pdo), (2, 3));
        assert!(can.simple_boot_up_slave && can.group_messaging && can.simple_boot_up_master);
        assert!(!can.lss_supported);
        assert_eq!(can.dynamic_channels, 1);
        let c = d.commissioning.as_ref().unwrap();
        assert_eq!(c.node_id, Some(5));
        assert_eq!(c.node_name, "axis");
        assert_eq!(c.baud_rate, 500);
        assert_eq!(c.net_number, 2);
        assert_eq!(c.network_name, "line");
        let cob = d.dictionary.entry(0x1800, 1).unwrap();
        assert!(cob.value_set);
        assert_eq!(cob.value, 0x190u32.to_le_bytes());
        let tt = d.dictionary.entry(0x1800, 2).unwrap();
        assert!(!tt.value_set);
        assert_eq!(tt.value, vec![0xFF]);
    }

    #[test]
    fn a_parameter_refines_rw_into_rwr_or_rww_but_does_not_override_the_object() {
        let text = wrap(
            r#"<CANopenObject index="2000" name="Out" objectType="7" dataType="0006" accessType="rw" PDOmapping="RPDO" uniqueIDRef="A"/>
<CANopenObject index="2001" name="In" objectType="7" dataType="0006" accessType="rw" PDOmapping="TPDO" uniqueIDRef="B"/>
<CANopenObject index="2002" name="Plain" objectType="7" dataType="0006" accessType="rw" uniqueIDRef="C"/>
<CANopenObject index="2003" name="Ro" objectType="7" dataType="0006" accessType="ro" uniqueIDRef="A"/>
<CANopenObject index="2004" name="Hand-written" objectType="7" dataType="0006" accessType="rww"/>"#,
            r#"<ApplicationProcess><parameterList>
<parameter uniqueID="A" access="readWriteOutput"><label>x</label><UINT/></parameter>
<parameter uniqueID="B" access="readWriteInput"><label>x</label><UINT/></parameter>
<parameter uniqueID="C" access="read"><label>x</label><UINT/></parameter>
</parameterList></ApplicationProcess>"#,
        );
        let d = read(text.as_bytes(), "t.xdd").unwrap();
        let access = |i| d.dictionary.entry(i, 0).unwrap().access.kind;
        assert_eq!(access(0x2000), AccessType::Rww);
        assert_eq!(access(0x2001), AccessType::Rwr);
        assert_eq!(access(0x2002), AccessType::Rw);
        assert_eq!(access(0x2003), AccessType::Ro);
        assert_eq!(access(0x2004), AccessType::Rww);
    }

    #[test]
    fn canopen_editor_spells_node_id_with_a_capital() {
        let text = r#"<ISO15745ProfileContainer><ISO15745Profile><ProfileBody>
<NetworkManagement><deviceCommissioning NodeID="9" nodeName="n" actualBaudRate="125 Kbps" networkNumber="1" networkName="x" CANopenManager="true"/></NetworkManagement>
</ProfileBody></ISO15745Profile></ISO15745ProfileContainer>"#;
        let d = read(text.as_bytes(), "t.xdc").unwrap();
        let c = d.commissioning.unwrap();
        assert_eq!(
            (c.node_id, c.baud_rate, c.canopen_manager),
            (Some(9), 125, true)
        );
        let e = err_of(&text.replace("NodeID=\"9\" ", ""));
        assert_eq!(e.position.line, 2, "{e}");
        assert!(e.message.contains("nodeID"), "{e}");
        let e = err_of(&text.replace("NodeID=\"9\"", "nodeID=\"128\""));
        assert!(e.message.contains("1 to 127"), "{e}");
    }

    #[test]
    fn node_id_spellings() {
        assert_eq!(strip_node_id("$NODEID+0x180"), Some("0x180"));
        assert_eq!(strip_node_id(" $nodeid + 0x80 "), Some("0x80"));
        assert_eq!(strip_node_id("0x600+$NODEID"), Some("0x600"));
        assert_eq!(strip_node_id("$NODEID"), Some(""));
        assert_eq!(strip_node_id("0x180"), None);
        assert_eq!(strip_node_id("€"), None);
    }

    #[test]
    fn errors_name_line_and_column() {
        let text = wrap(
            r#"<CANopenObject index="1000" name="A" objectType="7" dataType="0007" defaultValue="zz"/>"#,
            "",
        );
        let e = err_of(&text);
        assert_eq!(e.source_name, "t.xdd");
        assert_eq!((e.position.line, e.position.column), (12, 83), "{e}");
        assert!(
            e.message.contains("UNSIGNED32") && e.message.contains("`zz`"),
            "{e}"
        );

        let e = err_of(&wrap(
            r#"<CANopenObject index="10G0" name="A" objectType="7"/>"#,
            "",
        ));
        assert_eq!((e.position.line, e.position.column), (12, 23), "{e}");
        assert!(e.message.contains("index"), "{e}");

        let e = err_of(&wrap(
            r#"<CANopenObject index="1000" name="A" objectType="7" dataType="0007" accessType="readonly"/>"#,
            "",
        ));
        assert_eq!((e.position.line, e.position.column), (12, 81), "{e}");

        let e = err_of(&wrap(
            r#"  <CANopenObject index="1000" name="A" objectType="7"/>"#,
            "",
        ));
        assert_eq!((e.position.line, e.position.column), (12, 3), "{e}");
        assert!(e.message.contains("no data type"), "{e}");

        let e = err_of(&wrap(
            r#"<CANopenObject index="1000" name="A" objectType="7" uniqueIDRef="nope"/>"#,
            "",
        ));
        assert_eq!((e.position.line, e.position.column), (12, 66), "{e}");
        assert!(e.message.contains("`nope`"), "{e}");

        let e = err_of(&wrap(
            r#"<CANopenObject index="1000" name="A" objectType="7" dataType="0007"/>
<CANopenObject index="1000" name="B" objectType="7" dataType="0007"/>"#,
            "",
        ));
        assert_eq!((e.position.line, e.position.column), (13, 1), "{e}");

        // A complex type is no error: a DOMAIN, with a warning at the attribute's value.
        let text = wrap(
            r#"<CANopenObject index="1000" name="A" objectType="7" dataType="0020"/>"#,
            "",
        );
        let r = read_file(text.as_bytes(), "t.xdd").unwrap();
        let w = &r.findings[0];
        assert_eq!(
            w.position,
            Some(Position {
                line: 12,
                column: 63
            })
        );
        assert_eq!(
            w.message,
            "dataType 0020 of 0x1000:00 is a complex or profile data type; the entry is read as DOMAIN"
        );
        assert_eq!(
            r.devices[0].dictionary.entry(0x1000, 0).unwrap().data_type,
            DataType::Domain
        );

        let e = err_of(&wrap(
            r#"<CANopenObject index="1000" name="A" objectType="7" dataType="0007" PDOmapping="yes"/>"#,
            "",
        ));
        assert_eq!((e.position.line, e.position.column), (12, 81), "{e}");

        let e = err_of(&wrap(
            "",
            r#"<DeviceIdentity><vendorID>12x</vendorID></DeviceIdentity>"#,
        ));
        assert_eq!(e.position.line, 5, "{e}");
        assert!(e.message.contains("vendorID"), "{e}");

        let e = err_of("<?xml version=\"1.0\"?>\n<EtherCATInfo/>");
        assert_eq!((e.position.line, e.position.column), (2, 1), "{e}");
        assert!(e.message.contains("ISO15745ProfileContainer"), "{e}");

        let e = err_of("<ISO15745ProfileContainer>\n  <a></b>\n</ISO15745ProfileContainer>");
        assert_eq!(e.position.line, 2, "{e}");

        let e = err_of("<ISO15745ProfileContainer>\n  <a>");
        assert!(e.message.contains("end of file"), "{e}");
        let e = err_of("");
        assert!(e.message.contains("ISO15745ProfileContainer"), "{e}");
    }

    #[test]
    fn line_ends_and_references_in_text_and_attributes() {
        let text = wrap(
            "<CANopenObject index=\"2000\" name=\"a&#10;b\tc\r\nd\" objectType=\"7\" dataType=\"0009\" defaultValue=\"x&#9;&lt;&#x20AC;\" uniqueIDRef=\"P\"/>",
            "<ApplicationProcess><parameterList><parameter uniqueID=\"P\"><description>one\r\ntwo\rthree&#13;&amp;<![CDATA[<four>]]></description></parameter></parameterList></ApplicationProcess>",
        );
        let d = read(text.as_bytes(), "t.xdd").unwrap();
        let o = d.dictionary.object(0x2000).unwrap();
        assert_eq!(o.name, "a\nb c d");
        assert_eq!(o.description.as_deref(), Some("one\ntwo\nthree\r&<four>"));
        assert_eq!(
            o.subs[&0].default,
            Some(DefaultValue::plain(Value::String("x\t<€".into())))
        );
    }

    #[test]
    fn unknown_elements_and_attributes_are_skipped() {
        let text = wrap(
            r#"<vendorThing index="zz"><CANopenObject index="zz"/></vendorThing>
<CANopenObject index="1000" name="A" objectType="7" dataType="0007" vendorAttr="?" objFlags="0001" denotation="x" subNumber="0"><extra/></CANopenObject>"#,
            "<DeviceIdentity><vendorFamily>x</vendorFamily></DeviceIdentity><foo><parameterList/></foo>",
        );
        let d = read(text.as_bytes(), "t.xdd").unwrap();
        assert_eq!(d.dictionary.len(), 1);
    }
}
