//! The streaming ESI reader: quick-xml events over the decoded file, a stack of known element names, and
//! per-device raw records (data types, objects, EtherCAT parts) that are resolved into a
//! [`DeviceDescription`] when the device's element ends. Nothing but the current device is held.

use std::collections::{BTreeMap, HashMap};

use crate::device::{
    CoeFlags, DeviceDescription, Eeprom, EthercatInfo, InitCmd, Mailbox, Module, ModulePdoGroup,
    OpMode, Pdo, PdoEntry, PdoRef, Slot, SlotDepend, SlotModuleClass, SlotModuleIdent, Slots,
    SyncManager,
};
use crate::dict::{Address, Dictionary};
use crate::error::{ParseError, Position};
use crate::object::{
    Access, AccessType, DefaultValue, EcatStates, Object, ObjectKind, PdoMapping, SubObject,
};
use crate::report::{Reading, SourceMap};
use crate::types::DataType;
use crate::value::{parse_hex_bytes, Value};
use crate::xml;
use crate::xml::cursor::{normalize_line_ends, Cursor, Document, Element, Node};

/// Deepest type-alias chain followed (`DT… → BaseType → …`).
const MAX_TYPE_DEPTH: usize = 8;

macro_rules! tags {
    ($($name:ident),* $(,)?) => {
        /// The element names the reader acts on; everything else is `Other` and skipped.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        enum Tag { $($name,)* Other }

        impl Tag {
            fn of(name: &[u8]) -> Tag {
                $(if name == stringify!($name).as_bytes() { return Tag::$name; })*
                Tag::Other
            }

            fn name(self) -> &'static str {
                match self { $(Tag::$name => stringify!($name),)* Tag::Other => "?" }
            }
        }
    };
}

tags! {
    EtherCATInfo, EtherCATModule, Vendor, Id, Name, Descriptions, Devices, Device, Modules, Module, Type,
    GroupType, Profile, Dictionary, DataTypes, DataType, BaseType, BitSize, Comment, SubItem, SubIdx,
    BitOffs, Flags, Access, PdoMapping, ArrayInfo, LBound, Elements, EnumInfo, Objects, Object, Index,
    Info, DefaultData, DefaultValue, DefaultString, MinData, MaxData, MinValue, MaxValue, Fmmu, Sm, RxPdo,
    TxPdo, Exclude, Entry, SubIndex, BitLen, Mailbox, CoE, FoE, EoE, Dc, OpMode, Desc, AssignActivate,
    CycleTimeSync0, ShiftTimeSync0, CycleTimeSync1, ShiftTimeSync1, Eeprom, ByteSize, ConfigData,
    BootStrap, Slots, Slot, ModuleIdent, ModuleClass, Class, VendorId, ModulePdoGroup, InitCmd, Transition,
    Data, DcOpModeName, ProfileNo, AddInfo,
}

/// The document being read: error positions and the warnings found so far.
#[derive(Clone, Copy)]
struct Ctx<'a> {
    doc: &'a Document<'a>,
}

impl Ctx<'_> {
    fn pos(&self, offset: usize) -> Position {
        self.doc.position(offset)
    }

    fn err(&self, offset: usize, message: impl Into<String>) -> ParseError {
        self.doc.error(offset, message)
    }

    /// A warning at `offset`.
    fn warn(&self, offset: usize, message: impl Into<String>) {
        self.doc.warn(offset, message);
    }

    /// A warning at `offset` about the dictionary entry `address`.
    fn warn_about(&self, offset: usize, address: Address, message: impl Into<String>) {
        self.doc.warn_about(offset, address, message);
    }

    /// A number as [`xml::parse_number`] reads it; a hexadecimal number with both prefixes (`#x0x6041`,
    /// as some generators write) is read without the second, with a warning.
    fn parse_number(&self, text: &str, offset: usize, what: &str) -> Option<i128> {
        if let Some(v) = xml::parse_number(text) {
            return Some(v);
        }
        let t = text.trim();
        let (sign, body) = match t.strip_prefix('-') {
            Some(rest) => ("-", rest),
            None => ("", t.strip_prefix('+').unwrap_or(t)),
        };
        let digits = ["#x", "#X"]
            .iter()
            .find_map(|p| body.strip_prefix(p))
            .and_then(|r| ["0x", "0X"].iter().find_map(|p| r.strip_prefix(p)))?;
        let single = format!("{sign}#x{digits}");
        let v = xml::parse_number(&single)?;
        self.warn(
            offset,
            format!(
                "`{}` in {what} has two hexadecimal prefixes; read as {single}",
                clip(t)
            ),
        );
        Some(v)
    }

    /// A number of type `T` from element text.
    fn number<T: Bounded>(&self, text: &str, offset: usize, what: &str) -> Result<T, ParseError> {
        match self.parse_number(text, offset, what) {
            Some(v) => T::try_from(v).map_err(|_| {
                self.err(
                    offset,
                    format!(
                        "expected a number {}..{} in {what}, found `{}`",
                        T::LOW,
                        T::HIGH,
                        clip(text)
                    ),
                )
            }),
            None => Err(self.err(
                offset,
                format!(
                    "expected a number like #x1A00 or 6656 in {what}, found `{}`",
                    clip(text)
                ),
            )),
        }
    }

    /// hexBinary bytes. An odd number of digits is read with a leading 0 (`2` = `02`), as some vendors
    /// write one-digit values.
    fn hex(&self, text: &str, offset: usize, what: &str) -> Result<Vec<u8>, ParseError> {
        let digits = text.bytes().filter(|b| !b.is_ascii_whitespace()).count();
        let parsed = if digits % 2 == 1 && !text.trim().starts_with("0x") {
            parse_hex_bytes(&format!("0{}", text.trim()))
        } else {
            parse_hex_bytes(text)
        };
        parsed.ok_or_else(|| {
            self.err(
                offset,
                format!(
                    "expected hexadecimal bytes like 0A1B in {what}, found `{}`",
                    clip(text)
                ),
            )
        })
    }
}

/// The integer types numbers are read into, with their range for messages.
trait Bounded: TryFrom<i128> {
    const LOW: i128;
    const HIGH: i128;
}

macro_rules! bounded {
    ($($t:ty),*) => {$(
        impl Bounded for $t {
            const LOW: i128 = <$t>::MIN as i128;
            const HIGH: i128 = <$t>::MAX as i128;
        }
    )*};
}

bounded!(u8, u16, u32, i32);

/// At most 40 characters of `text`, for messages.
fn clip(text: &str) -> String {
    let t = text.trim();
    if t.chars().count() <= 40 {
        t.to_string()
    } else {
        let mut s: String = t.chars().take(40).collect();
        s.push('…');
        s
    }
}

/// A text given in several languages: `LcId` 1033 wins, else the first.
#[derive(Debug, Default, Clone)]
struct Localized {
    text: String,
    rank: u8,
}

impl Localized {
    fn offer(&mut self, lcid: Option<u32>, text: &str) {
        let rank = if lcid == Some(1033) { 2 } else { 1 };
        if rank > self.rank {
            self.text.clear();
            self.text.push_str(text);
            self.rank = rank;
        }
    }

    fn get(&self) -> Option<&str> {
        (self.rank > 0).then_some(self.text.as_str())
    }
}

/// A text and where it was.
#[derive(Debug, Default, Clone)]
struct At {
    text: String,
    offset: usize,
}

#[derive(Debug, Default, Clone, Copy)]
struct RawFlags {
    access: Option<Access>,
    pdo: Option<PdoMapping>,
}

#[derive(Debug, Default)]
struct RawInfo {
    default_data: Option<(Vec<u8>, usize)>,
    default_value: Option<At>,
    default_string: Option<At>,
    min_data: Option<(Vec<u8>, usize)>,
    max_data: Option<(Vec<u8>, usize)>,
    min_value: Option<At>,
    max_value: Option<At>,
}

#[derive(Debug, Default)]
struct RawSubItem {
    offset: usize,
    sub_idx: Option<u8>,
    name: String,
    type_name: At,
    bit_size: Option<u32>,
    comment: Localized,
    flags: Option<RawFlags>,
}

#[derive(Debug, Default)]
struct RawDataType {
    name: String,
    base_type: Option<At>,
    bit_size: Option<u32>,
    comment: Localized,
    arrays: Vec<(Option<u32>, Option<u32>)>,
    subitems: Vec<RawSubItem>,
}

#[derive(Debug, Default)]
struct RawObject {
    offset: usize,
    index: Option<u16>,
    name: Localized,
    comment: Localized,
    type_name: At,
    bit_size: Option<u32>,
    info: RawInfo,
    /// `Info/SubItem`s: name, values, and where the `SubItem` is.
    sub_infos: Vec<(String, RawInfo, usize)>,
    flags: Option<RawFlags>,
}

#[derive(Debug, Default)]
struct RawDevice {
    offset: usize,
    /// Where each PDO entry is.
    pdo_entry_offsets: Vec<EntryAt>,
    /// Inside an `RxPdo`/`TxPdo` that refers to a template (`Ref`), which is left out.
    in_ref_pdo: bool,
    product_code: u32,
    revision: u32,
    order_code: String,
    name: Localized,
    group_type: String,
    has_dictionary: bool,
    data_types: Vec<RawDataType>,
    objects: Vec<RawObject>,
    ecat: EthercatInfo,
    /// A `Descriptions/Modules/Module` (a module of the file's modular devices), not a device.
    is_module: bool,
    /// `Type@ModuleIdent`, `@ModuleClass`, `@ModulePdoGroup` of a module.
    module_ident: u32,
    module_class: String,
    module_pdo_group: Option<u32>,
    /// `DcOpModeName` of a module.
    dc_op_mode_name: String,
    /// `Profile/ProfileNo` and `Profile/AddInfo`.
    profile_no: Option<u32>,
    add_info: Option<u32>,
}

/// Where a PDO entry is: in a TxPdo or an RxPdo, the PDO's place in its list, the entry's place in the
/// PDO, and the offset of its `Entry` element.
#[derive(Debug, Clone, Copy)]
struct EntryAt {
    tx: bool,
    pdo: usize,
    n: usize,
    offset: usize,
}

/// What the parser is collecting.
struct Parser<'a> {
    ctx: Ctx<'a>,
    stack: Vec<Tag>,
    /// Index in `stack` of the current `Device` (or module) element.
    device_depth: Option<usize>,
    text: String,
    text_offset: Option<usize>,
    lcid: Option<u32>,
    restrictions: (Option<EcatStates>, Option<EcatStates>),
    vendor_id: u32,
    vendor_name: Localized,
    file_version: String,
    device: Option<RawDevice>,
    done: Vec<DeviceDescription>,
    /// The file's `Descriptions/Modules/Module`s.
    modules: Vec<Module>,
    sources: Vec<SourceMap>,
}

pub(super) fn read_all(bytes: &[u8], source_name: &str) -> Result<Reading, ParseError> {
    let text = xml::decode(bytes, source_name).map_err(|mut e| {
        if e.position.line == 0 {
            e.position = decode_error_position(bytes);
        }
        e
    })?;
    let doc = Document::new(&text, source_name);
    let ctx = Ctx { doc: &doc };
    let mut parser = Parser {
        ctx,
        stack: Vec::new(),
        device_depth: None,
        text: String::new(),
        text_offset: None,
        lcid: None,
        restrictions: (None, None),
        vendor_id: 0,
        vendor_name: Localized::default(),
        file_version: String::new(),
        device: None,
        done: Vec::new(),
        modules: Vec::new(),
        sources: Vec::new(),
    };
    parser.run()?;
    let Parser {
        mut done,
        vendor_id,
        vendor_name,
        file_version,
        sources,
        modules,
        ..
    } = parser;
    // The file's modules belong to each of its devices.
    let modules: std::sync::Arc<[Module]> = modules.into();
    for d in &mut done {
        d.identity.vendor_id = vendor_id;
        d.identity.vendor_name = vendor_name.get().unwrap_or_default().to_string();
        d.file_info.file_version = file_version.clone();
        if let Some(ecat) = d.ethercat.as_mut() {
            ecat.modules = modules.clone();
        }
    }
    let mut findings = doc.take_findings();
    // In file order: a device's findings about its PDOs come when the device ends.
    findings.sort_by_key(|f| f.position.map(|p| (p.line, p.column)));
    Ok(Reading {
        devices: done,
        sources,
        findings,
    })
}

/// Where a file that [`xml::decode`] refused without a position goes wrong: the first invalid UTF-8 byte
/// after a UTF-8 byte-order mark, else the start of the file.
fn decode_error_position(bytes: &[u8]) -> Position {
    let start = Position { line: 1, column: 1 };
    let Some(body) = bytes.strip_prefix(b"\xEF\xBB\xBF") else {
        return start;
    };
    match std::str::from_utf8(body) {
        Ok(_) => start,
        Err(e) => Position::of_offset(body, e.valid_up_to()),
    }
}

impl<'a> Parser<'a> {
    fn run(&mut self) -> Result<(), ParseError> {
        let mut cursor = Cursor::new(self.ctx.doc);
        let mut root_seen = false;
        loop {
            match cursor.next()? {
                Node::Start(e) => {
                    if self.stack.is_empty() {
                        self.check_root(&e, root_seen)?;
                        root_seen = true;
                    }
                    self.start(&e)?;
                }
                Node::End { offset } => self.end(offset)?,
                // White space before an element's text is layout: skip it without decoding.
                Node::Text(t, _) if self.text_offset.is_none() && t.is_blank() => {}
                Node::Text(t, offset) if self.collecting() => self.push_text(&t.content(), offset),
                Node::CData(t, offset) if self.collecting() => {
                    self.push_text(&normalize_line_ends(t), offset)
                }
                Node::Ref(r, offset) if self.collecting() => match r.resolve() {
                    Ok(Some(c)) => {
                        let mut buf = [0u8; 4];
                        self.push_text(c.encode_utf8(&mut buf), offset);
                    }
                    Ok(None) | Err(_) => {
                        return Err(self
                            .ctx
                            .err(offset, format!("unknown entity `&{};`", r.name())))
                    }
                },
                Node::Eof => break,
                _ => {}
            }
        }
        if let Some(open) = self.stack.last() {
            return Err(self.ctx.err(
                self.ctx.doc.text().len(),
                format!("unexpected end of file: <{}> is not closed", open.name()),
            ));
        }
        if !root_seen {
            return Err(self
                .ctx
                .err(0, "expected an <EtherCATInfo> element, found no element"));
        }
        Ok(())
    }

    fn check_root(&self, e: &Element, seen: bool) -> Result<(), ParseError> {
        let tag = Tag::of(e.local_name());
        if seen || !matches!(tag, Tag::EtherCATInfo | Tag::EtherCATModule) {
            return Err(self.ctx.err(
                e.offset(),
                format!(
                    "expected an <EtherCATInfo> root element, found <{}>",
                    String::from_utf8_lossy(e.name())
                ),
            ));
        }
        Ok(())
    }

    /// True when the innermost element is one whose text the reader may use.
    fn collecting(&self) -> bool {
        matches!(self.stack.last(), Some(t) if *t != Tag::Other)
    }

    fn push_text(&mut self, s: &str, offset: usize) {
        if self.text_offset.is_none() {
            if s.trim().is_empty() {
                return;
            }
            let lead = s.len() - s.trim_start().len();
            self.text_offset = Some(offset + lead);
        }
        self.text.push_str(s);
    }

    /// Each attribute's local name, value, and the offset of its name in the source.
    fn attrs(&self, e: &Element) -> Result<Vec<(Vec<u8>, String, usize)>, ParseError> {
        let mut out = Vec::new();
        for a in e.attributes() {
            let a = a.map_err(|err| {
                self.ctx
                    .err(e.offset(), format!("malformed attribute: {err}"))
            })?;
            let at = a.name_offset();
            let value = a
                .value()
                .map_err(|err| {
                    self.ctx
                        .err(at, format!("malformed attribute value: {err}"))
                })?
                .into_owned();
            out.push((a.key().to_vec(), value, at));
        }
        Ok(out)
    }

    fn start(&mut self, e: &Element) -> Result<(), ParseError> {
        let tag = Tag::of(e.local_name());
        self.stack.push(tag);
        self.text.clear();
        self.text_offset = None;
        if tag == Tag::Other {
            return Ok(());
        }
        let stack = std::mem::take(&mut self.stack);
        let result = self.on_start(&stack, tag, e);
        self.stack = stack;
        result
    }

    fn on_start(&mut self, stack: &[Tag], tag: Tag, e: &Element) -> Result<(), ParseError> {
        let offset = e.offset();
        if matches!(tag, Tag::Name | Tag::Comment) {
            self.lcid = None;
            for (k, v, at) in self.attrs(e)? {
                if k == b"LcId" {
                    self.lcid = Some(self.ctx.number(&v, at, "the LcId attribute")?);
                }
            }
        }
        let Some(depth) = self.device_depth else {
            match stack {
                [Tag::EtherCATInfo | Tag::EtherCATModule, Tag::Vendor] => {
                    for (k, v, _) in self.attrs(e)? {
                        if k == b"FileVersion" {
                            self.file_version = v.trim().to_string();
                        }
                    }
                }
                [Tag::EtherCATInfo, Tag::Descriptions, Tag::Devices, Tag::Device]
                | [Tag::EtherCATModule, Tag::Modules, Tag::Module] => {
                    self.device_depth = Some(stack.len() - 1);
                    self.device = Some(RawDevice {
                        offset,
                        ..RawDevice::default()
                    });
                }
                [Tag::EtherCATInfo, Tag::Descriptions, Tag::Modules, Tag::Module] => {
                    self.device_depth = Some(stack.len() - 1);
                    self.device = Some(RawDevice {
                        offset,
                        is_module: true,
                        ..RawDevice::default()
                    });
                }
                _ => {}
            }
            return Ok(());
        };
        let rel = stack.get(depth + 1..).unwrap_or_default();
        let ctx = self.ctx;
        let attrs = self.attrs(e)?;
        let Some(dev) = self.device.as_mut() else {
            return Ok(());
        };
        match rel {
            [Tag::Type] => {
                for (k, v, at) in &attrs {
                    match k.as_slice() {
                        b"ProductCode" => {
                            dev.product_code = ctx.number(v, *at, "the ProductCode attribute")?
                        }
                        b"RevisionNo" => {
                            dev.revision = ctx.number(v, *at, "the RevisionNo attribute")?
                        }
                        b"ModuleIdent" => {
                            dev.module_ident = ctx.number(v, *at, "the ModuleIdent attribute")?
                        }
                        b"ModuleClass" => dev.module_class = v.clone(),
                        b"ModulePdoGroup" => {
                            dev.module_pdo_group =
                                Some(ctx.number(v, *at, "the ModulePdoGroup attribute")?)
                        }
                        _ => {}
                    }
                }
            }
            [Tag::Slots] => {
                let mut slots = Slots::default();
                for (k, v, at) in &attrs {
                    let what = format!("the {} attribute of <Slots>", String::from_utf8_lossy(k));
                    let field = match k.as_slice() {
                        b"MaxSlotCount" => &mut slots.max_slot_count,
                        b"MaxSlotGroupCount" => &mut slots.max_slot_group_count,
                        b"SlotPdoIncrement" => &mut slots.slot_pdo_increment,
                        b"SlotGroupPdoIncrement" => &mut slots.slot_group_pdo_increment,
                        b"SlotIndexIncrement" => &mut slots.slot_index_increment,
                        b"SlotGroupIndexIncrement" => &mut slots.slot_group_index_increment,
                        b"DownloadModuleIdentList" => {
                            slots.download_module_ident_list = flag(ctx, v, *at, &what)?;
                            continue;
                        }
                        b"IdentifyModuleBy" => {
                            slots.identify_module_by = v.clone();
                            continue;
                        }
                        _ => continue,
                    };
                    *field = Some(ctx.number(v, *at, &what)?);
                }
                dev.ecat.slots = Some(slots);
            }
            [Tag::Slots, Tag::Slot] => {
                let mut slot = Slot::default();
                for (k, v, at) in &attrs {
                    let what = format!("the {} attribute of <Slot>", String::from_utf8_lossy(k));
                    let field = match k.as_slice() {
                        b"MinInstances" => {
                            slot.min_instances = ctx.number(v, *at, &what)?;
                            continue;
                        }
                        b"MaxInstances" => {
                            slot.max_instances = ctx.number(v, *at, &what)?;
                            continue;
                        }
                        b"TreeView" => {
                            slot.tree_view = v.clone();
                            continue;
                        }
                        b"SlotGroup" => &mut slot.slot_group,
                        b"SlotPdoIncrement" => &mut slot.slot_pdo_increment,
                        b"SlotGroupPdoIncrement" => &mut slot.slot_group_pdo_increment,
                        b"SlotIndexIncrement" => &mut slot.slot_index_increment,
                        b"SlotGroupIndexIncrement" => &mut slot.slot_group_index_increment,
                        _ => continue,
                    };
                    *field = Some(ctx.number(v, *at, &what)?);
                }
                if let Some(s) = dev.ecat.slots.as_mut() {
                    s.slots.push(slot);
                }
            }
            [Tag::Slots, Tag::Slot, Tag::ModuleIdent] => {
                let mut ident = SlotModuleIdent::default();
                for (k, v, at) in &attrs {
                    if k == b"Default" {
                        ident.default =
                            Some(ctx.number(v, *at, "the Default attribute of <ModuleIdent>")?);
                    }
                }
                if let Some(slot) = dev.ecat.slots.as_mut().and_then(|s| s.slots.last_mut()) {
                    slot.module_idents.push(ident);
                }
            }
            [Tag::Slots, Tag::Slot, Tag::ModuleClass] => {
                if let Some(slot) = dev.ecat.slots.as_mut().and_then(|s| s.slots.last_mut()) {
                    slot.module_classes.push(SlotModuleClass::default());
                }
            }
            [Tag::Slots, Tag::ModulePdoGroup] => {
                let mut group = ModulePdoGroup::default();
                for (k, v, at) in &attrs {
                    let what = format!(
                        "the {} attribute of <ModulePdoGroup>",
                        String::from_utf8_lossy(k)
                    );
                    match k.as_slice() {
                        b"Alignment" => group.alignment = Some(ctx.number(v, *at, &what)?),
                        b"RxPdo" => group.rx_pdo = Some(ctx.number(v, *at, &what)?),
                        b"TxPdo" => group.tx_pdo = Some(ctx.number(v, *at, &what)?),
                        _ => {}
                    }
                }
                if let Some(s) = dev.ecat.slots.as_mut() {
                    s.module_pdo_groups.push(group);
                }
            }
            [Tag::Profile, Tag::Dictionary] => dev.has_dictionary = true,
            [Tag::Profile, Tag::Dictionary, Tag::DataTypes, Tag::DataType] => {
                dev.data_types.push(RawDataType::default())
            }
            [Tag::Profile, Tag::Dictionary, Tag::DataTypes, Tag::DataType, Tag::SubItem] => {
                if let Some(dt) = dev.data_types.last_mut() {
                    dt.subitems.push(RawSubItem {
                        offset,
                        ..RawSubItem::default()
                    });
                }
            }
            [Tag::Profile, Tag::Dictionary, Tag::DataTypes, Tag::DataType, Tag::ArrayInfo] => {
                if let Some(dt) = dev.data_types.last_mut() {
                    dt.arrays.push((None, None));
                }
            }
            [Tag::Profile, Tag::Dictionary, Tag::DataTypes, Tag::DataType, Tag::SubItem, Tag::Flags] => {
                if let Some(si) = dev
                    .data_types
                    .last_mut()
                    .and_then(|d| d.subitems.last_mut())
                {
                    si.flags.get_or_insert_with(RawFlags::default);
                }
            }
            [Tag::Profile, Tag::Dictionary, Tag::Objects, Tag::Object] => {
                dev.objects.push(RawObject {
                    offset,
                    ..RawObject::default()
                })
            }
            [Tag::Profile, Tag::Dictionary, Tag::Objects, Tag::Object, Tag::Flags] => {
                if let Some(o) = dev.objects.last_mut() {
                    o.flags.get_or_insert_with(RawFlags::default);
                }
            }
            [Tag::Profile, Tag::Dictionary, Tag::Objects, Tag::Object, Tag::Info, Tag::SubItem] => {
                if let Some(o) = dev.objects.last_mut() {
                    o.sub_infos
                        .push((String::new(), RawInfo::default(), offset));
                }
            }
            [.., Tag::Flags, Tag::Access] => {
                let mut r = (None, None);
                for (k, v, at) in &attrs {
                    let which = match k.as_slice() {
                        b"ReadRestrictions" => &mut r.0,
                        b"WriteRestrictions" => &mut r.1,
                        _ => continue,
                    };
                    *which = Some(EcatStates::parse(v).ok_or_else(|| {
                        ctx.err(
                            *at,
                            format!(
                                "expected EtherCAT states like PreOp_SafeOp_Op in the {} attribute, found `{}`",
                                String::from_utf8_lossy(k),
                                clip(v)
                            ),
                        )
                    })?);
                }
                self.restrictions = r;
            }
            [Tag::Sm] => {
                let mut sm = SyncManager::default();
                for (k, v, at) in &attrs {
                    let what = format!("the {} attribute of <Sm>", String::from_utf8_lossy(k));
                    match k.as_slice() {
                        b"StartAddress" => sm.start_address = ctx.number(v, *at, &what)?,
                        b"DefaultSize" => sm.default_size = Some(ctx.number(v, *at, &what)?),
                        b"MinSize" => sm.min_size = Some(ctx.number(v, *at, &what)?),
                        b"MaxSize" => sm.max_size = Some(ctx.number(v, *at, &what)?),
                        b"ControlByte" => sm.control_byte = ctx.number(v, *at, &what)?,
                        b"Enable" => sm.enable = enable(ctx, v, *at, &what)?,
                        b"Virtual" => sm.is_virtual = flag(ctx, v, *at, &what)?,
                        b"OpOnly" => sm.op_only = flag(ctx, v, *at, &what)?,
                        b"Watchdog" => sm.watchdog = flag(ctx, v, *at, &what)?,
                        _ => {}
                    }
                }
                dev.ecat.sync_managers.push(sm);
            }
            [Tag::RxPdo | Tag::TxPdo] => {
                if let Some((_, name, _)) = attrs.iter().find(|(k, _, _)| k == b"Ref") {
                    // The obsolete Beckhoff form: a PDO of the file's `Descriptions/Pdos` templates.
                    ctx.warn(
                        offset,
                        format!(
                            "<{} Ref=\"{}\"> refers to a PDO template of the obsolete Descriptions/Pdos list, which is not read; the PDO is left out",
                            tag.name(),
                            clip(name)
                        ),
                    );
                    dev.in_ref_pdo = true;
                    return Ok(());
                }
                let mut pdo = Pdo::default();
                for (k, v, at) in &attrs {
                    let what = format!(
                        "the {} attribute of <{}>",
                        String::from_utf8_lossy(k),
                        tag.name()
                    );
                    match k.as_slice() {
                        b"Fixed" => pdo.fixed = flag(ctx, v, *at, &what)?,
                        b"Mandatory" => pdo.mandatory = flag(ctx, v, *at, &what)?,
                        b"Virtual" => pdo.is_virtual = flag(ctx, v, *at, &what)?,
                        b"Sm" => pdo.sm = Some(ctx.number(v, *at, &what)?),
                        b"Su" => pdo.su = Some(ctx.number(v, *at, &what)?),
                        b"OSFac" => pdo.os_factor = Some(ctx.number(v, *at, &what)?),
                        b"OSMin" => pdo.os_min = Some(ctx.number(v, *at, &what)?),
                        b"OSMax" => pdo.os_max = Some(ctx.number(v, *at, &what)?),
                        b"OSIndexInc" => pdo.os_index_inc = Some(ctx.number(v, *at, &what)?),
                        _ => {}
                    }
                }
                if tag == Tag::RxPdo {
                    dev.ecat.rx_pdos.push(pdo);
                } else {
                    dev.ecat.tx_pdos.push(pdo);
                }
            }
            [Tag::RxPdo | Tag::TxPdo, ..] if dev.in_ref_pdo => {}
            [pdo @ (Tag::RxPdo | Tag::TxPdo), Tag::Index] => {
                let depend = slot_depend(ctx, &attrs)?;
                if let Some(p) = pdo_of(dev, *pdo) {
                    p.index_depend = depend;
                }
            }
            [pdo @ (Tag::RxPdo | Tag::TxPdo), Tag::Exclude] => {
                let depend = slot_depend(ctx, &attrs)?;
                if let Some(p) = pdo_of(dev, *pdo) {
                    p.exclude.push(PdoRef { index: 0, depend });
                }
            }
            [pdo @ (Tag::RxPdo | Tag::TxPdo), Tag::Entry] => {
                let tx = *pdo == Tag::TxPdo;
                let ordinal = if tx {
                    dev.ecat.tx_pdos.len()
                } else {
                    dev.ecat.rx_pdos.len()
                };
                let mut entry = PdoEntry::default();
                for (k, v, at) in &attrs {
                    if k == b"Fixed" {
                        entry.fixed = flag(ctx, v, *at, "the Fixed attribute of <Entry>")?;
                    }
                }
                if let Some(p) = pdo_of(dev, *pdo) {
                    p.entries.push(entry);
                    let n = p.entries.len() - 1;
                    dev.pdo_entry_offsets.push(EntryAt {
                        tx,
                        pdo: ordinal.saturating_sub(1),
                        n,
                        offset,
                    });
                }
            }
            [pdo @ (Tag::RxPdo | Tag::TxPdo), Tag::Entry, Tag::Index] => {
                let depend = slot_depend(ctx, &attrs)?;
                if let Some(e) = pdo_of(dev, *pdo).and_then(|p| p.entries.last_mut()) {
                    e.index_depend = depend;
                }
            }
            [pdo @ (Tag::RxPdo | Tag::TxPdo), Tag::Entry, Tag::DataType] => {
                if let Some((_, v, _)) = attrs.iter().find(|(k, _, _)| k == b"DScale") {
                    if let Some(e) = pdo_of(dev, *pdo).and_then(|p| p.entries.last_mut()) {
                        e.data_scale = v.clone();
                    }
                }
            }
            [Tag::Mailbox] => {
                let mut mb = Mailbox::default();
                for (k, v, at) in &attrs {
                    if k == b"DataLinkLayer" {
                        mb.data_link_layer =
                            flag(ctx, v, *at, "the DataLinkLayer attribute of <Mailbox>")?;
                    }
                }
                dev.ecat.mailbox = Some(mb);
            }
            [Tag::Mailbox, Tag::CoE] => {
                let mut coe = CoeFlags {
                    segmented_sdo: true,
                    ..CoeFlags::default()
                };
                for (k, v, at) in &attrs {
                    let what = format!("the {} attribute of <CoE>", String::from_utf8_lossy(k));
                    let field = match k.as_slice() {
                        b"SdoInfo" => &mut coe.sdo_info,
                        b"PdoAssign" => &mut coe.pdo_assign,
                        b"PdoConfig" => &mut coe.pdo_config,
                        b"PdoUpload" => &mut coe.pdo_upload,
                        b"CompleteAccess" => &mut coe.complete_access,
                        b"SegmentedSdo" => &mut coe.segmented_sdo,
                        _ => continue,
                    };
                    *field = flag(ctx, v, *at, &what)?;
                }
                if let Some(mb) = dev.ecat.mailbox.as_mut() {
                    mb.coe = Some(coe);
                }
            }
            [Tag::Mailbox, Tag::CoE, Tag::InitCmd] => {
                let mut cmd = InitCmd::default();
                for (k, v, at) in &attrs {
                    let what = format!("the {} attribute of <InitCmd>", String::from_utf8_lossy(k));
                    let field = match k.as_slice() {
                        b"Fixed" => &mut cmd.fixed,
                        b"CompleteAccess" => &mut cmd.complete_access,
                        b"OverwrittenByModule" => &mut cmd.overwritten_by_module,
                        _ => continue,
                    };
                    *field = flag(ctx, v, *at, &what)?;
                }
                if let Some(mb) = dev.ecat.mailbox.as_mut() {
                    mb.init_cmds.push(cmd);
                }
            }
            [Tag::Mailbox, Tag::CoE, Tag::InitCmd, Tag::Index] => {
                let depend = slot_depend(ctx, &attrs)?;
                if let Some(cmd) = init_cmd_of(dev) {
                    cmd.index_depend = depend;
                }
            }
            [Tag::Mailbox, Tag::CoE, Tag::InitCmd, Tag::Data] => {
                let mut adapt = false;
                for (k, v, at) in &attrs {
                    if k == b"AdaptAutomatically" {
                        adapt = flag(ctx, v, *at, "the AdaptAutomatically attribute of <Data>")?;
                    }
                }
                if let Some(cmd) = init_cmd_of(dev) {
                    cmd.adapt_automatically = adapt;
                }
            }
            [Tag::Mailbox, Tag::FoE] => {
                if let Some(mb) = dev.ecat.mailbox.as_mut() {
                    mb.foe = true;
                }
            }
            [Tag::Mailbox, Tag::EoE] => {
                if let Some(mb) = dev.ecat.mailbox.as_mut() {
                    mb.eoe = true;
                }
            }
            [Tag::Dc, Tag::OpMode] => dev.ecat.op_modes.push(OpMode::default()),
            [Tag::Dc, Tag::OpMode, which @ (Tag::CycleTimeSync0 | Tag::CycleTimeSync1)] => {
                let mut factor = 1i32;
                for (k, v, at) in &attrs {
                    if k == b"Factor" {
                        factor = ctx.number(
                            v,
                            *at,
                            &format!("the Factor attribute of <{}>", which.name()),
                        )?;
                    }
                }
                if let Some(m) = dev.ecat.op_modes.last_mut() {
                    let slot = if *which == Tag::CycleTimeSync0 {
                        &mut m.cycle_time_sync0
                    } else {
                        &mut m.cycle_time_sync1
                    };
                    *slot = Some((0, factor));
                }
            }
            [Tag::Eeprom] => dev.ecat.eeprom = Some(Eeprom::default()),
            _ => {}
        }
        Ok(())
    }

    fn end(&mut self, offset: usize) -> Result<(), ParseError> {
        let Some(&tag) = self.stack.last() else {
            return Ok(());
        };
        let result = if tag == Tag::Other {
            Ok(())
        } else {
            let stack = std::mem::take(&mut self.stack);
            let text = std::mem::take(&mut self.text);
            let at = self.text_offset.unwrap_or(offset);
            let r = self.on_end(&stack, tag, text.trim(), at);
            self.stack = stack;
            self.text = text;
            self.text.clear();
            r
        };
        self.text_offset = None;
        self.stack.pop();
        if self.device_depth == Some(self.stack.len()) {
            self.device_depth = None;
            if let Some(raw) = self.device.take() {
                let module = raw.is_module.then(|| {
                    (
                        raw.module_ident,
                        raw.module_class.clone(),
                        raw.module_pdo_group,
                        raw.dc_op_mode_name.clone(),
                        raw.profile_no,
                        raw.add_info,
                    )
                });
                let (desc, source) = build_device(self.ctx, raw)?;
                match module {
                    Some((ident, class, pdo_group, dc_op_mode_name, profile_no, add_info)) => {
                        let ecat = desc.ethercat.unwrap_or_default();
                        self.modules.push(Module {
                            ident,
                            class,
                            pdo_group,
                            type_name: desc.identity.order_code,
                            name: desc.identity.product_name,
                            rx_pdos: ecat.rx_pdos,
                            tx_pdos: ecat.tx_pdos,
                            mailbox: ecat.mailbox,
                            profile_no,
                            add_info,
                            dictionary: desc.dictionary,
                            dc_op_mode_name,
                        });
                    }
                    None => {
                        self.done.push(desc);
                        self.sources.push(source);
                    }
                }
            }
        }
        result
    }

    fn on_end(&mut self, stack: &[Tag], tag: Tag, text: &str, at: usize) -> Result<(), ParseError> {
        let lcid = if matches!(tag, Tag::Name | Tag::Comment) {
            self.lcid.take()
        } else {
            None
        };
        let ctx = self.ctx;
        let what = || format!("<{}>", tag.name());
        let Some(depth) = self.device_depth else {
            match stack {
                [Tag::EtherCATInfo | Tag::EtherCATModule, Tag::Vendor, Tag::Id] => {
                    self.vendor_id = ctx.number(text, at, "<Vendor>/<Id>")?;
                }
                [Tag::EtherCATInfo | Tag::EtherCATModule, Tag::Vendor, Tag::Name] => {
                    self.vendor_name.offer(lcid, text)
                }
                _ => {}
            }
            return Ok(());
        };
        let rel = stack.get(depth + 1..).unwrap_or_default();
        let restrictions = self.restrictions;
        let Some(dev) = self.device.as_mut() else {
            return Ok(());
        };
        match rel {
            [Tag::Type] => dev.order_code = text.to_string(),
            [Tag::Name] => dev.name.offer(lcid, text),
            [Tag::GroupType] => dev.group_type = text.to_string(),
            [Tag::DcOpModeName] => dev.dc_op_mode_name = text.to_string(),
            // Kept for modules; a device's profile number is not kept.
            [Tag::Profile, f @ (Tag::ProfileNo | Tag::AddInfo)] if dev.is_module => {
                let what = format!("<Profile>/<{}>", f.name());
                let n = match ctx.number(text, at, &what) {
                    Ok(n) => Some(n),
                    Err(e) => {
                        ctx.warn(at, format!("{}; it is left out", e.message));
                        None
                    }
                };
                if *f == Tag::ProfileNo {
                    dev.profile_no = n;
                } else {
                    dev.add_info = n;
                }
            }
            [Tag::Slots, Tag::Slot, rest @ ..] => {
                let Some(slot) = dev.ecat.slots.as_mut().and_then(|s| s.slots.last_mut()) else {
                    return Ok(());
                };
                match rest {
                    // Localized: 1033 wins over the first.
                    [Tag::Name] if slot.name.is_empty() || lcid == Some(1033) => {
                        slot.name = text.to_string()
                    }
                    [Tag::ModuleIdent] => {
                        let ident = ctx.number(text, at, "<Slot>/<ModuleIdent>")?;
                        if let Some(m) = slot.module_idents.last_mut() {
                            m.ident = ident;
                        }
                    }
                    [Tag::ModuleClass, f] => {
                        if let Some(c) = slot.module_classes.last_mut() {
                            match f {
                                Tag::Class => c.class = text.to_string(),
                                Tag::VendorId => {
                                    c.vendor_id =
                                        Some(ctx.number(text, at, "<ModuleClass>/<VendorId>")?)
                                }
                                Tag::Name if c.name.is_empty() || lcid == Some(1033) => {
                                    c.name = text.to_string()
                                }
                                _ => {}
                            }
                        }
                    }
                    _ => {}
                }
            }
            [Tag::Slots, Tag::ModulePdoGroup] => {
                if let Some(g) = dev
                    .ecat
                    .slots
                    .as_mut()
                    .and_then(|s| s.module_pdo_groups.last_mut())
                {
                    g.name = text.to_string();
                }
            }
            [Tag::Mailbox, Tag::CoE, Tag::InitCmd, f] => {
                if let Some(cmd) = init_cmd_of(dev) {
                    match f {
                        Tag::Transition => cmd.transitions.push(text.to_string()),
                        Tag::Index => cmd.index = ctx.number(text, at, "<InitCmd>/<Index>")?,
                        Tag::SubIndex => cmd.sub = ctx.number(text, at, "<InitCmd>/<SubIndex>")?,
                        Tag::Data => cmd.data = ctx.hex(text, at, "<InitCmd>/<Data>")?,
                        Tag::Comment => cmd.comment = text.to_string(),
                        _ => {}
                    }
                }
            }
            [Tag::Profile, Tag::Dictionary, Tag::DataTypes, Tag::DataType, rest @ ..] => {
                let Some(dt) = dev.data_types.last_mut() else {
                    return Ok(());
                };
                match rest {
                    [Tag::Name] => dt.name = text.to_string(),
                    [Tag::BaseType] => {
                        dt.base_type = Some(At {
                            text: text.to_string(),
                            offset: at,
                        })
                    }
                    [Tag::BitSize] => {
                        dt.bit_size = Some(ctx.number(text, at, "<DataType>/<BitSize>")?)
                    }
                    [Tag::Comment] => dt.comment.offer(lcid, text),
                    [Tag::ArrayInfo, Tag::LBound] => {
                        if let Some(a) = dt.arrays.last_mut() {
                            a.0 = Some(ctx.number(text, at, "<ArrayInfo>/<LBound>")?);
                        }
                    }
                    [Tag::ArrayInfo, Tag::Elements] => {
                        if let Some(a) = dt.arrays.last_mut() {
                            a.1 = Some(ctx.number(text, at, "<ArrayInfo>/<Elements>")?);
                        }
                    }
                    [Tag::SubItem, rest @ ..] => {
                        let Some(si) = dt.subitems.last_mut() else {
                            return Ok(());
                        };
                        match rest {
                            [Tag::SubIdx] => {
                                si.sub_idx = Some(ctx.number(text, at, "<SubItem>/<SubIdx>")?)
                            }
                            [Tag::Name] => si.name = text.to_string(),
                            [Tag::Type] => {
                                si.type_name = At {
                                    text: text.to_string(),
                                    offset: at,
                                }
                            }
                            [Tag::BitSize] => {
                                si.bit_size = Some(ctx.number(text, at, "<SubItem>/<BitSize>")?)
                            }
                            [Tag::BitOffs] => {
                                let _: u32 = ctx.number(text, at, "<SubItem>/<BitOffs>")?;
                            }
                            [Tag::Comment] => si.comment.offer(lcid, text),
                            [Tag::Flags, f] => {
                                let flags = si.flags.get_or_insert_with(RawFlags::default);
                                read_flag(ctx, flags, *f, text, at, restrictions)?;
                            }
                            _ => {}
                        }
                    }
                    _ => {}
                }
            }
            [Tag::Profile, Tag::Dictionary, Tag::Objects, Tag::Object, rest @ ..] => {
                let Some(o) = dev.objects.last_mut() else {
                    return Ok(());
                };
                match rest {
                    [Tag::Index] => o.index = Some(ctx.number(text, at, "<Object>/<Index>")?),
                    [Tag::Name] => o.name.offer(lcid, text),
                    [Tag::Comment] => o.comment.offer(lcid, text),
                    [Tag::Type] => {
                        o.type_name = At {
                            text: text.to_string(),
                            offset: at,
                        }
                    }
                    [Tag::BitSize] => {
                        o.bit_size = Some(ctx.number(text, at, "<Object>/<BitSize>")?)
                    }
                    [Tag::Info, Tag::SubItem, Tag::Name] => {
                        if let Some(si) = o.sub_infos.last_mut() {
                            si.0 = text.to_string();
                        }
                    }
                    [Tag::Info, Tag::SubItem, Tag::Info, f] => {
                        if let Some(si) = o.sub_infos.last_mut() {
                            read_info(ctx, &mut si.1, *f, text, at)?;
                        }
                    }
                    [Tag::Info, f] => read_info(ctx, &mut o.info, *f, text, at)?,
                    [Tag::Flags, f] => {
                        let flags = o.flags.get_or_insert_with(RawFlags::default);
                        read_flag(ctx, flags, *f, text, at, restrictions)?;
                    }
                    _ => {}
                }
            }
            [Tag::Fmmu] => dev.ecat.fmmus.push(text.to_string()),
            [Tag::Sm] => {
                if let Some(sm) = dev.ecat.sync_managers.last_mut() {
                    sm.kind = text.to_string();
                }
            }
            [Tag::RxPdo | Tag::TxPdo] if dev.in_ref_pdo => dev.in_ref_pdo = false,
            [Tag::RxPdo | Tag::TxPdo, ..] if dev.in_ref_pdo => {}
            [pdo @ (Tag::RxPdo | Tag::TxPdo), rest @ ..] => {
                let kind = *pdo;
                let Some(p) = pdo_of(dev, kind) else {
                    return Ok(());
                };
                match rest {
                    [Tag::Index] => {
                        p.index = ctx.number(text, at, &format!("<{}>/<Index>", kind.name()))?
                    }
                    // Localized: 1033 wins over the first.
                    [Tag::Name] if p.name.is_empty() || lcid == Some(1033) => {
                        p.name = text.to_string()
                    }
                    [Tag::Exclude] => {
                        let index = ctx.number(text, at, "<Exclude>")?;
                        if let Some(x) = p.exclude.last_mut() {
                            x.index = index;
                        }
                    }
                    [Tag::Entry, f] => {
                        if let Some(en) = p.entries.last_mut() {
                            match f {
                                Tag::Index => en.index = ctx.number(text, at, "<Entry>/<Index>")?,
                                Tag::SubIndex => {
                                    en.sub = ctx.number(text, at, "<Entry>/<SubIndex>")?
                                }
                                Tag::BitLen => {
                                    en.bit_len = ctx.number(text, at, "<Entry>/<BitLen>")?
                                }
                                Tag::Name if en.name.is_empty() || lcid == Some(1033) => {
                                    en.name = text.to_string()
                                }
                                Tag::DataType => en.data_type = text.to_string(),
                                Tag::Comment => en.comment = text.to_string(),
                                _ => {}
                            }
                        }
                    }
                    _ => {}
                }
            }
            [Tag::Dc, Tag::OpMode, f] => {
                if let Some(m) = dev.ecat.op_modes.last_mut() {
                    match f {
                        Tag::Name => m.name = text.to_string(),
                        Tag::Desc => m.desc = text.to_string(),
                        Tag::AssignActivate => {
                            m.assign_activate = ctx.number(text, at, "<AssignActivate>")?
                        }
                        Tag::CycleTimeSync0 | Tag::CycleTimeSync1 => {
                            let v: u32 = ctx.number(text, at, &what())?;
                            let slot = if *f == Tag::CycleTimeSync0 {
                                &mut m.cycle_time_sync0
                            } else {
                                &mut m.cycle_time_sync1
                            };
                            let factor = slot.map_or(1, |s| s.1);
                            *slot = Some((v, factor));
                        }
                        Tag::ShiftTimeSync0 => {
                            m.shift_time_sync0 = Some(ctx.number(text, at, &what())?)
                        }
                        Tag::ShiftTimeSync1 => {
                            m.shift_time_sync1 = Some(ctx.number(text, at, &what())?)
                        }
                        _ => {}
                    }
                }
            }
            [Tag::Eeprom, f] => {
                if let Some(ee) = dev.ecat.eeprom.as_mut() {
                    match f {
                        Tag::ByteSize => {
                            ee.byte_size = ctx.number(text, at, "<Eeprom>/<ByteSize>")?
                        }
                        Tag::ConfigData => ee.config_data = ctx.hex(text, at, "<ConfigData>")?,
                        Tag::BootStrap => ee.boot_strap = ctx.hex(text, at, "<BootStrap>")?,
                        _ => {}
                    }
                }
            }
            _ => {}
        }
        Ok(())
    }
}

fn init_cmd_of(dev: &mut RawDevice) -> Option<&mut InitCmd> {
    dev.ecat
        .mailbox
        .as_mut()
        .and_then(|m| m.init_cmds.last_mut())
}

fn pdo_of(dev: &mut RawDevice, tag: Tag) -> Option<&mut Pdo> {
    if tag == Tag::RxPdo {
        dev.ecat.rx_pdos.last_mut()
    } else {
        dev.ecat.tx_pdos.last_mut()
    }
}

/// The `DependOnSlot` and `DependOnSlotGroup` attributes of an element.
fn slot_depend(ctx: Ctx, attrs: &[(Vec<u8>, String, usize)]) -> Result<SlotDepend, ParseError> {
    let mut d = SlotDepend::default();
    for (k, v, at) in attrs {
        let which = match k.as_slice() {
            b"DependOnSlot" => &mut d.slot,
            b"DependOnSlotGroup" => &mut d.slot_group,
            _ => continue,
        };
        *which = flag(
            ctx,
            v,
            *at,
            &format!("the {} attribute", String::from_utf8_lossy(k)),
        )?;
    }
    Ok(d)
}

/// The `Enable` attribute of `Sm`: a number 0..255 (the SII enable byte), or `true`/`false`.
fn enable(ctx: Ctx, text: &str, at: usize, what: &str) -> Result<u8, ParseError> {
    match ctx.number::<u8>(text, at, what) {
        Ok(n) => Ok(n),
        Err(e) => xml::parse_bool(text).map(u8::from).ok_or(e),
    }
}

/// A boolean attribute (`1`, `0`, `true`, `false`).
fn flag(ctx: Ctx, text: &str, at: usize, what: &str) -> Result<bool, ParseError> {
    xml::parse_bool(text).ok_or_else(|| {
        ctx.err(
            at,
            format!(
                "expected 1, 0, true or false in {what}, found `{}`",
                clip(text)
            ),
        )
    })
}

fn read_flag(
    ctx: Ctx,
    flags: &mut RawFlags,
    tag: Tag,
    text: &str,
    at: usize,
    restrictions: (Option<EcatStates>, Option<EcatStates>),
) -> Result<(), ParseError> {
    match tag {
        Tag::Access => {
            let kind = AccessType::parse(text).ok_or_else(|| {
                ctx.err(
                    at,
                    format!("expected ro, rw or wo in <Access>, found `{}`", clip(text)),
                )
            })?;
            flags.access = Some(Access {
                kind,
                read_states: restrictions.0,
                write_states: restrictions.1,
            });
        }
        Tag::PdoMapping => {
            let pdo = match text.to_ascii_uppercase().as_str() {
                "R" => PdoMapping::Rpdo,
                "T" => PdoMapping::Tpdo,
                "RT" | "TR" => PdoMapping::Both,
                "" => PdoMapping::None,
                _ => {
                    return Err(ctx.err(
                        at,
                        format!(
                            "expected R, T, RT or TR in <PdoMapping>, found `{}`",
                            clip(text)
                        ),
                    ))
                }
            };
            flags.pdo = Some(pdo);
        }
        _ => {}
    }
    Ok(())
}

fn read_info(
    ctx: Ctx,
    info: &mut RawInfo,
    tag: Tag,
    text: &str,
    at: usize,
) -> Result<(), ParseError> {
    let keep = || At {
        text: text.to_string(),
        offset: at,
    };
    match tag {
        Tag::DefaultData => info.default_data = Some((ctx.hex(text, at, "<DefaultData>")?, at)),
        Tag::MinData | Tag::MaxData => {
            let what = if tag == Tag::MinData {
                "<MinData>"
            } else {
                "<MaxData>"
            };
            let bytes = match ctx.hex(text, at, what) {
                Ok(b) => Some((b, at)),
                Err(e) => {
                    ctx.warn(at, format!("{}; the limit is dropped", e.message));
                    None
                }
            };
            if tag == Tag::MinData {
                info.min_data = bytes;
            } else {
                info.max_data = bytes;
            }
        }
        Tag::DefaultValue => info.default_value = Some(keep()),
        Tag::MinValue => info.min_value = Some(keep()),
        Tag::MaxValue => info.max_value = Some(keep()),
        Tag::DefaultString => info.default_string = Some(keep()),
        _ => {}
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------------------
// Resolution of one device's raw records.

/// What a type name stands for.
enum Resolved<'t> {
    /// A basic type, with the bit size its name gives (strings).
    Basic(DataType, Option<u32>),
    /// A structure (`DataType` with `SubItem`s).
    Struct(&'t RawDataType),
    /// A `DataType` with `ArrayInfo`: element type, first sub-index, element count, total bits.
    Array {
        element: DataType,
        element_bits: Option<u32>,
        lbound: u32,
        elements: u32,
        bit_size: Option<u32>,
    },
}

struct Types<'t> {
    by_name: HashMap<&'t str, &'t RawDataType>,
}

impl<'t> Types<'t> {
    fn new(list: &'t [RawDataType]) -> Types<'t> {
        let mut by_name = HashMap::with_capacity(list.len());
        for dt in list {
            by_name.entry(dt.name.as_str()).or_insert(dt);
        }
        Types { by_name }
    }

    fn resolve(&self, name: &str, depth: usize) -> Option<Resolved<'t>> {
        let name = name.trim();
        if let Some((t, bits)) = DataType::from_esi_name(name) {
            return Some(Resolved::Basic(t, bits));
        }
        if depth > MAX_TYPE_DEPTH {
            return None;
        }
        let dt = *self.by_name.get(name)?;
        if !dt.subitems.is_empty() {
            return Some(Resolved::Struct(dt));
        }
        let base = dt.base_type.as_ref()?;
        let base = match self.resolve(&base.text, depth + 1)? {
            Resolved::Basic(t, bits) => (t, bits),
            _ => return None,
        };
        if dt.arrays.is_empty() {
            // An alias or enumeration of a basic type.
            let bits = if base.0.is_variable() {
                dt.bit_size.or(base.1)
            } else {
                None
            };
            return Some(Resolved::Basic(base.0, bits));
        }
        let mut elements: u32 = 1;
        let mut lbound = None;
        for (lb, n) in &dt.arrays {
            elements = elements.checked_mul(n.unwrap_or(0))?;
            lbound.get_or_insert(lb.unwrap_or(0));
        }
        let element_bits = match base.0.bit_size() {
            Some(b) => Some(b),
            None => base.1.or_else(|| dt.bit_size.map(|b| b / elements.max(1))),
        };
        Some(Resolved::Array {
            element: base.0,
            element_bits,
            lbound: lbound.unwrap_or(0),
            elements,
            bit_size: dt.bit_size,
        })
    }
}

/// One entry of a flattened structure.
struct Flat<'t> {
    sub: u8,
    name: String,
    data_type: DataType,
    bit_size: Option<u32>,
    flags: Option<RawFlags>,
    comment: Option<&'t str>,
    /// An array element: its name comes from the object's `Info/SubItem`.
    element: bool,
    /// Where its `SubItem` is.
    offset: usize,
}

fn build_device(ctx: Ctx, raw: RawDevice) -> Result<(DeviceDescription, SourceMap), ParseError> {
    let pos = |offset: usize| ctx.pos(offset);
    let mut source = SourceMap::default();
    source.set_device(pos(raw.offset));
    let mut desc = DeviceDescription::default();
    desc.identity.product_code = raw.product_code;
    desc.identity.revision = raw.revision;
    desc.identity.order_code = raw.order_code.clone();
    desc.identity.product_name = raw.name.get().unwrap_or_default().to_string();
    let types = Types::new(&raw.data_types);
    let mut dict = Dictionary::new();
    let mut first_at: BTreeMap<u16, usize> = BTreeMap::new();
    for o in &raw.objects {
        let Some(index) = o.index else {
            return Err(ctx.err(o.offset, "expected an <Index> in <Object>"));
        };
        if let Some(&prev) = first_at.get(&index) {
            let p = ctx.pos(prev);
            return Err(ctx.err(
                o.offset,
                format!(
                    "object #x{index:04X} is defined twice (first at line {})",
                    p.line
                ),
            ));
        }
        first_at.insert(index, o.offset);
        source.set_object(index, pos(o.offset));
        dict.insert(build_object(ctx, &types, o, index, &mut source)?);
    }
    for e in &raw.pdo_entry_offsets {
        let pdos = if e.tx {
            &raw.ecat.tx_pdos
        } else {
            &raw.ecat.rx_pdos
        };
        if let Some(pdo) = pdos.get(e.pdo) {
            source.set_pdo_entry(pdo.index, e.n, pos(e.offset));
        }
    }
    apply_pdos(ctx, &mut dict, &raw, &mut source);
    desc.dictionary = dict;
    let mut ecat = raw.ecat;
    ecat.group_type = raw.group_type;
    desc.ethercat = Some(ecat);
    Ok((desc, source))
}

fn build_object(
    ctx: Ctx,
    types: &Types,
    o: &RawObject,
    index: u16,
    source: &mut SourceMap,
) -> Result<Object, ParseError> {
    let name = o.name.get().unwrap_or_default().to_string();
    let comment = o.comment.get().map(str::to_string);
    let type_at = if o.type_name.text.is_empty() {
        o.offset
    } else {
        o.type_name.offset
    };
    let resolved = types.resolve(&o.type_name.text, 0).ok_or_else(|| {
        ctx.err(
            type_at,
            format!(
                "object #x{index:04X}: expected a basic type name or the name of a <DataType> in <Type>, found `{}`",
                clip(&o.type_name.text)
            ),
        )
    })?;
    let object_access = o.flags.and_then(|f| f.access);
    let var = |data_type: DataType, bit_size: Option<u32>| -> Result<Object, ParseError> {
        let mut sub = SubObject::new(
            name.clone(),
            data_type,
            object_access.unwrap_or(Access::new(AccessType::Ro)),
        );
        sub.bit_size = bit_size;
        sub.pdo = o.flags.and_then(|f| f.pdo).unwrap_or_default();
        sub.description = comment.clone();
        apply_info(ctx, &mut sub, &o.info, index)?;
        let mut object = Object::var(index, sub);
        object.description = comment.clone();
        Ok(object)
    };
    match resolved {
        Resolved::Basic(t, bits) => {
            let bit_size = if t.is_variable() {
                bits.or(o.bit_size)
            } else {
                t.bit_size()
            };
            var(t, bit_size)
        }
        Resolved::Array {
            element,
            element_bits,
            elements,
            bit_size,
            ..
        } => {
            // An array used as the type of one value: its bytes.
            let bits = bit_size
                .or(o.bit_size)
                .or_else(|| element_bits.and_then(|b| b.checked_mul(elements)));
            let _ = element;
            var(DataType::OctetString, bits)
        }
        Resolved::Struct(dt) => {
            let (flat, is_array) = flatten(ctx, types, dt, index)?;
            let kind = if is_array {
                ObjectKind::Array
            } else {
                ObjectKind::Record
            };
            let mut object = Object::structured(index, name.clone(), kind);
            object.type_name = Some(dt.name.clone());
            object.description = comment
                .clone()
                .or_else(|| dt.comment.get().map(str::to_string));
            // Match Info/SubItems to entries: by position when the Info lists every entry, else by name
            // and then by position.
            let mut assigned: Vec<Option<usize>> = vec![None; flat.len()];
            let complete = o.sub_infos.len() == flat.len();
            for (i, (info_name, _, _)) in o.sub_infos.iter().enumerate() {
                if complete {
                    assigned[i] = Some(i);
                    continue;
                }
                let pick =
                    if flat.get(i).is_some_and(|f| &f.name == info_name) && assigned[i].is_none() {
                        Some(i)
                    } else if let Some(j) = (0..flat.len())
                        .find(|&j| assigned[j].is_none() && &flat[j].name == info_name)
                    {
                        Some(j)
                    } else if i < flat.len() && assigned[i].is_none() {
                        Some(i)
                    } else {
                        None
                    };
                if let Some(j) = pick {
                    assigned[j] = Some(i);
                }
            }
            for (j, f) in flat.iter().enumerate() {
                let flags = f.flags.unwrap_or_default();
                let access = flags
                    .access
                    .or(object_access)
                    .unwrap_or(Access::new(AccessType::Ro));
                let pdo = flags
                    .pdo
                    .or(if f.sub == 0 {
                        None
                    } else {
                        o.flags.and_then(|g| g.pdo)
                    })
                    .unwrap_or_default();
                let info = assigned[j].and_then(|i| o.sub_infos.get(i));
                let name = match (f.element, info) {
                    (true, Some((n, _, _))) => n.clone(),
                    _ => f.name.clone(),
                };
                let mut sub = SubObject::new(name, f.data_type, access);
                sub.bit_size = f.bit_size;
                sub.pdo = pdo;
                sub.description = f.comment.map(str::to_string);
                if let Some((_, info, at)) = info {
                    apply_info(ctx, &mut sub, info, index)?;
                    source.set_entry(index, f.sub, ctx.pos(*at));
                }
                object.subs.insert(f.sub, sub);
            }
            if !object.subs.contains_key(&0) {
                let count = object.max_sub();
                let sub = SubObject::new("SubIndex 000", DataType::Unsigned8, AccessType::Ro)
                    .with_default(Value::Uint(count as u64));
                object.subs.insert(0, sub);
            }
            Ok(object)
        }
    }
}

/// The entries of a structure type, in order, with array members expanded; and whether it is the ETG
/// array layout.
fn flatten<'t>(
    ctx: Ctx,
    types: &Types<'t>,
    dt: &'t RawDataType,
    index: u16,
) -> Result<(Vec<Flat<'t>>, bool), ParseError> {
    let mut out: Vec<Flat<'t>> = Vec::with_capacity(dt.subitems.len());
    let mut next: u32 = 0;
    let mut arrays = 0usize;
    let mut others = 0usize;
    for si in &dt.subitems {
        let at = if si.type_name.text.is_empty() {
            si.offset
        } else {
            si.type_name.offset
        };
        let resolved = types.resolve(&si.type_name.text, 0).ok_or_else(|| {
            ctx.err(
                at,
                format!(
                    "<DataType> {}: expected a basic type name or the name of an array <DataType> in <SubItem>/<Type>, found `{}`",
                    dt.name,
                    clip(&si.type_name.text)
                ),
            )
        })?;
        let comment = si.comment.get();
        match resolved {
            Resolved::Basic(t, bits) => {
                let sub = si.sub_idx.map_or(next, u32::from);
                let sub = u8::try_from(sub).map_err(|_| {
                    ctx.err(si.offset, format!("<DataType> {}: more than 256 entries", dt.name))
                })?;
                let bit_size = if t.is_variable() {
                    bits.or(si.bit_size)
                } else {
                    t.bit_size()
                };
                if sub != 0 {
                    others += 1;
                }
                out.push(Flat {
                    sub,
                    name: si.name.clone(),
                    data_type: t,
                    bit_size,
                    flags: si.flags,
                    comment,
                    element: false,
                    offset: si.offset,
                });
                next = u32::from(sub) + 1;
            }
            Resolved::Array {
                element,
                element_bits,
                lbound,
                elements,
                bit_size,
            } => {
                if let Some(sub) = si.sub_idx {
                    // An entry whose value is a whole array: its bytes.
                    out.push(Flat {
                        sub,
                        name: si.name.clone(),
                        data_type: DataType::OctetString,
                        bit_size: si.bit_size.or(bit_size),
                        flags: si.flags,
                        comment,
                        element: false,
                        offset: si.offset,
                    });
                    others += 1;
                    next = u32::from(sub) + 1;
                    continue;
                }
                let first = lbound.max(next);
                let last = first
                    .checked_add(elements)
                    .and_then(|e| e.checked_sub(1))
                    .filter(|&l| l <= 255 || elements == 0);
                let Some(last) = last else {
                    return Err(ctx.err(
                        at,
                        format!(
                            "object #x{index:04X}: the array type `{}` has {elements} elements from sub-index {first}; sub-indices end at 255",
                            clip(&si.type_name.text)
                        ),
                    ));
                };
                let element_bits = if element.is_variable() {
                    element_bits
                } else {
                    element.bit_size()
                };
                for s in first..first + elements {
                    let sub = u8::try_from(s).unwrap_or(u8::MAX);
                    out.push(Flat {
                        sub,
                        name: format!("SubIndex {sub:03}"),
                        data_type: element,
                        bit_size: element_bits,
                        flags: si.flags,
                        comment,
                        element: true,
                        offset: si.offset,
                    });
                }
                arrays += 1;
                next = last + 1;
            }
            Resolved::Struct(_) => {
                return Err(ctx.err(
                    at,
                    format!(
                        "<DataType> {}: the entry `{}` has the structure type `{}`; CoE entries are basic types or arrays of them",
                        dt.name,
                        si.name,
                        clip(&si.type_name.text)
                    ),
                ))
            }
        }
    }
    // Duplicate sub-indices: the later entry would silently replace the earlier.
    let mut seen = [false; 256];
    for f in &out {
        let s = usize::from(f.sub);
        if seen[s] {
            return Err(ctx.err(
                f.offset,
                format!(
                    "<DataType> {}: sub-index {} is defined twice",
                    dt.name, f.sub
                ),
            ));
        }
        seen[s] = true;
    }
    Ok((out, arrays == 1 && others == 0))
}

/// Sets default, limits and current value of `sub` from an `Info` element.
fn apply_info(ctx: Ctx, sub: &mut SubObject, info: &RawInfo, index: u16) -> Result<(), ParseError> {
    let t = sub.data_type;
    let default = if let Some((bytes, at)) = &info.default_data {
        Some(decode_data(ctx, t, bytes, *at, index, "DefaultData")?)
    } else if let Some(v) = &info.default_value {
        Some(value_text(ctx, t, v, index, "DefaultValue")?)
    } else if let Some(s) = &info.default_string {
        Some(match t {
            DataType::VisibleString => Value::String(s.text.clone()),
            DataType::UnicodeString => Value::Unicode(s.text.encode_utf16().collect()),
            DataType::OctetString | DataType::Domain => Value::Bytes(s.text.as_bytes().to_vec()),
            _ => value_text(ctx, t, s, index, "DefaultString")?,
        })
    } else {
        None
    };
    // A limit that is no value of the type (vendors copy limits between objects of different types)
    // limits nothing a master could write: it is dropped.
    let limit = |data: &Option<(Vec<u8>, usize)>, value: &Option<At>, what: [&str; 2]| {
        let read = match (data, value) {
            (Some((bytes, at)), _) => decode_data(ctx, t, bytes, *at, index, what[0]),
            (None, Some(v)) => value_text(ctx, t, v, index, what[1]),
            (None, None) => return None,
        };
        match read {
            Ok(v) => Some(v),
            Err(e) => {
                let at = data
                    .as_ref()
                    .map_or_else(|| value.as_ref().map_or(0, |v| v.offset), |d| d.1);
                ctx.warn(at, format!("{}; the limit is dropped", e.message));
                None
            }
        }
    };
    sub.low = limit(&info.min_data, &info.min_value, ["MinData", "MinValue"]);
    sub.high = limit(&info.max_data, &info.max_value, ["MaxData", "MaxValue"]);
    if let Some(v) = &default {
        // A string whose type is shorter than its default (`STRING(0)` with a default): the default
        // shows the size.
        if let (Some(bits), Ok(bytes)) = (sub.bit_size, v.encode(t)) {
            let unit = if t == DataType::UnicodeString { 16 } else { 8 };
            let needed = u32::try_from(bytes.len())
                .unwrap_or(u32::MAX / 8)
                .saturating_mul(8)
                .div_ceil(unit)
                * unit;
            if t.is_variable() && needed > bits {
                let at = info
                    .default_data
                    .as_ref()
                    .map(|d| d.1)
                    .or(info.default_value.as_ref().map(|v| v.offset))
                    .or(info.default_string.as_ref().map(|v| v.offset))
                    .unwrap_or(0);
                ctx.warn(
                    at,
                    format!(
                        "object #x{index:04X}: the default takes {needed} bits but the type gives {bits}; the size is the default's"
                    ),
                );
                sub.bit_size = Some(needed);
            }
        }
    }
    if let Some(v) = default {
        if let Ok(bytes) = v.encode(t) {
            sub.value = bytes;
        }
        sub.default = Some(DefaultValue::plain(v));
    }
    Ok(())
}

/// A value from little-endian hexBinary bytes. Real files give fixed-size values in fewer bytes (`00` for
/// a UINT) or with zero bytes beyond the type's size; both are read as the number they spell (the missing
/// high bytes are zero). Nonzero bytes beyond the type are an error.
fn decode_data(
    ctx: Ctx,
    t: DataType,
    bytes: &[u8],
    at: usize,
    index: u16,
    what: &str,
) -> Result<Value, ParseError> {
    let mut fitted;
    let mut bytes = bytes;
    if let Some(size) = t.byte_size() {
        if bytes.len() < size && !bytes.is_empty() {
            fitted = bytes.to_vec();
            fitted.resize(size, 0);
            bytes = &fitted;
        } else if bytes.len() > size && bytes.iter().skip(size).all(|&b| b == 0) {
            fitted = bytes.to_vec();
            fitted.truncate(size);
            bytes = &fitted;
        }
    }
    Value::decode(t, bytes).map_err(|e| {
        ctx.err(
            at,
            format!(
                "object #x{index:04X}: <{what}> is not a {}: {e}",
                t.esi_base_name()
            ),
        )
    })
}

/// A value from a number (`#x…` or decimal) or, for strings, text.
fn value_text(ctx: Ctx, t: DataType, v: &At, index: u16, what: &str) -> Result<Value, ParseError> {
    let text = v.text.trim();
    let bad = |reason: &str| {
        ctx.err(
            v.offset,
            format!(
                "object #x{index:04X}: expected {reason} in <{what}>, found `{}`",
                clip(text)
            ),
        )
    };
    match t {
        DataType::VisibleString => Ok(Value::String(v.text.clone())),
        DataType::UnicodeString => Ok(Value::Unicode(v.text.encode_utf16().collect())),
        DataType::OctetString | DataType::Domain => parse_hex_bytes(text)
            .map(Value::Bytes)
            .ok_or_else(|| bad("hexadecimal bytes")),
        DataType::Real32 | DataType::Real64 => {
            if let Some(bits) = text.strip_prefix("#x").or_else(|| text.strip_prefix("#X")) {
                let n = u64::from_str_radix(bits, 16).map_err(|_| bad("a number"))?;
                return Ok(if t == DataType::Real32 {
                    Value::Real32(f32::from_bits(
                        u32::try_from(n).map_err(|_| bad("a 32-bit pattern"))?,
                    ))
                } else {
                    Value::Real64(f64::from_bits(n))
                });
            }
            Value::parse_text(t, text).map_err(|_| bad("a decimal number"))
        }
        DataType::TimeOfDay | DataType::TimeDifference => {
            let n = ctx
                .parse_number(text, v.offset, &format!("<{what}>"))
                .ok_or_else(|| bad("a number"))?;
            let bytes = u64::try_from(n)
                .ok()
                .filter(|&n| n < (1u64 << 48))
                .ok_or_else(|| bad("a 48-bit number"))?
                .to_le_bytes();
            Value::decode(t, &bytes[..6]).map_err(|_| bad("a time"))
        }
        DataType::Boolean => match text.to_ascii_lowercase().as_str() {
            "true" => Ok(Value::Bool(true)),
            "false" => Ok(Value::Bool(false)),
            _ => match ctx.parse_number(text, v.offset, &format!("<{what}>")) {
                Some(0) => Ok(Value::Bool(false)),
                Some(1) => Ok(Value::Bool(true)),
                _ => Err(bad("0, 1, true or false")),
            },
        },
        _ => {
            let n = ctx
                .parse_number(text, v.offset, &format!("<{what}>"))
                .ok_or_else(|| bad("a number like #x1A00 or 6656"))?;
            let (lo, hi) = t.integer_range().ok_or_else(|| bad("a number"))?;
            let hex = text.starts_with("#x") || text.starts_with("#X") || text.starts_with("0x");
            // Hexadecimal for a signed type may spell the two's complement (`#xFFFF` = -1 for INT).
            let n = if t.is_signed() && hex && n > hi && n <= 2 * hi + 1 {
                n - 2 * (hi + 1)
            } else {
                n
            };
            if n < lo || n > hi {
                return Err(bad(&format!("a {} value {lo}..{hi}", t.esi_base_name())));
            }
            Ok(if t.is_signed() {
                Value::Int(n as i64)
            } else {
                Value::Uint(n as u64)
            })
        }
    }
}

/// A type for an entry that only a PDO describes and whose `DataType` names none: an unsigned of its
/// `BitLen`, a bit field below 8 bits, else an octet string of the bytes it covers.
fn type_of_size(bits: u16) -> Option<(DataType, Option<u32>)> {
    let t = match bits {
        0 => return None,
        1..=7 => DataType::Bit(bits as u8),
        8 => DataType::Unsigned8,
        16 => DataType::Unsigned16,
        24 => DataType::Unsigned24,
        32 => DataType::Unsigned32,
        40 => DataType::Unsigned40,
        48 => DataType::Unsigned48,
        56 => DataType::Unsigned56,
        64 => DataType::Unsigned64,
        _ => return Some((DataType::OctetString, Some(u32::from(bits).div_ceil(8) * 8))),
    };
    Some((t, None))
}

/// `p` with the direction `dir` added.
fn with_direction(p: PdoMapping, dir: PdoMapping) -> PdoMapping {
    match (p, dir) {
        (PdoMapping::None, d) => d,
        (PdoMapping::Rpdo, PdoMapping::Tpdo) | (PdoMapping::Tpdo, PdoMapping::Rpdo) => {
            PdoMapping::Both
        }
        (p, _) => p,
    }
}

fn direction_text(p: PdoMapping) -> &'static str {
    match p {
        PdoMapping::None => "nothing",
        PdoMapping::Rpdo => "R",
        PdoMapping::Tpdo => "T",
        PdoMapping::Both => "RT",
    }
}

/// What the device's own PDOs say about its dictionary. An entry a PDO maps is mappable in the PDO's
/// direction: where the dictionary's `PdoMapping` is missing or says otherwise, the PDOs win (with a
/// warning). An entry the dictionary does not have (a device without a dictionary, or a partial one) is
/// made from the PDO entry that maps it: of the `DataType`'s type (else one of its `BitLen`), read-only,
/// mappable in the PDO's direction, without default; a VAR for sub-index 0, else an entry of a RECORD
/// (type name `DTxxxx`, as the writer names it) whose sub-index 0 counts up to the highest entry. The
/// object is named after the first PDO that maps it. Nothing else is made up.
fn apply_pdos(ctx: Ctx, dict: &mut Dictionary, raw: &RawDevice, source: &mut SourceMap) {
    let partial = raw.has_dictionary;
    // Entries and objects made here (a second PDO that maps them only adds its direction).
    let mut made: std::collections::HashSet<(u16, u8)> = std::collections::HashSet::new();
    let mut made_objects: std::collections::HashSet<u16> = std::collections::HashSet::new();
    // The structure type names in use, once a RECORD is made.
    let mut type_names: Option<std::collections::HashSet<String>> = None;
    for at in &raw.pdo_entry_offsets {
        let (pdos, dir, kind) = if at.tx {
            (&raw.ecat.tx_pdos, PdoMapping::Tpdo, "TxPdo")
        } else {
            (&raw.ecat.rx_pdos, PdoMapping::Rpdo, "RxPdo")
        };
        let Some(pdo) = pdos.get(at.pdo) else {
            continue;
        };
        let Some(e) = pdo.entries.get(at.n) else {
            continue;
        };
        // Index 0 is a gap (ETG.1000.6); 0x0001–0x0007 are CiA 301 dummy entries (KickCAT's examples map
        // 0x0006:01): padding of a data type's size, no entry of the dictionary.
        if e.index <= 0x0007 {
            continue;
        }
        let address = Address::new(e.index, e.sub);
        let which = || format!("{kind} #x{:04X}", pdo.index);
        if let Some(object) = dict
            .object_mut(e.index)
            .filter(|o| o.subs.contains_key(&e.sub))
        {
            // The elements of an ARRAY share one `SubItem`, and so one `PdoMapping`.
            let array = object.kind == ObjectKind::Array && e.sub != 0;
            let was = object.subs.get(&e.sub).map_or(PdoMapping::None, |s| s.pdo);
            let now = with_direction(was, dir);
            for (&s, sub) in object.subs.iter_mut() {
                if s == e.sub || (array && s != 0) {
                    sub.pdo = with_direction(sub.pdo, dir);
                }
            }
            if now != was && !made.contains(&(e.index, e.sub)) {
                let flag = if was == PdoMapping::None {
                    "is missing".to_string()
                } else {
                    format!("says {}", direction_text(was))
                };
                ctx.warn_about(
                    at.offset,
                    address,
                    format!(
                        "{} maps it, but its <PdoMapping> {flag}: read as {}",
                        which(),
                        direction_text(now)
                    ),
                );
            }
            continue;
        }
        let exists = dict.object(e.index).map(|o| o.kind.has_subs());
        if exists == Some(false) {
            // A VAR mapped with a sub-index it does not have: validate says so.
            continue;
        }
        let (t, bits) = match DataType::from_esi_name(&e.data_type) {
            Some(found) => found,
            None => {
                let named = if e.data_type.trim().is_empty() {
                    "no <DataType>".to_string()
                } else {
                    format!(
                        "the <DataType> `{}`, which names no type",
                        clip(&e.data_type)
                    )
                };
                let Some((t, bits)) = type_of_size(e.bit_len) else {
                    ctx.warn_about(
                        at.offset,
                        address,
                        format!(
                            "{} gives it {named} and BitLen 0: no entry is made",
                            which()
                        ),
                    );
                    continue;
                };
                let size = bits.or(t.bit_size()).unwrap_or(0);
                ctx.warn_about(
                    at.offset,
                    address,
                    format!(
                        "{} gives it {named}: made {} from its BitLen {}",
                        which(),
                        t.esi_name(size),
                        e.bit_len
                    ),
                );
                (t, bits)
            }
        };
        let bit_size = if t.is_variable() {
            bits.or(Some(u32::from(e.bit_len)))
        } else {
            t.bit_size()
        };
        let mut sub = SubObject::new(e.name.clone(), t, AccessType::Ro).with_pdo(dir);
        sub.bit_size = bit_size;
        let exists = exists.is_some();
        if e.sub == 0 && !exists {
            dict.insert(Object::var(e.index, sub));
        } else {
            if !exists {
                let mut object = Object::structured(e.index, pdo.name.clone(), ObjectKind::Record);
                // The name the writer gives the structure type (unless the file uses it), so the
                // dictionary reads back the same.
                let used = type_names.get_or_insert_with(|| {
                    raw.data_types
                        .iter()
                        .map(|t| t.name.clone())
                        .chain(dict.objects().filter_map(|o| o.type_name.clone()))
                        .collect()
                });
                let base = format!("DT{:04X}", e.index);
                let name = std::iter::once(base.clone())
                    .chain((1..=256).map(|n| format!("{base}_{n}")))
                    .find(|n| !used.contains(n))
                    .unwrap_or(base);
                used.insert(name.clone());
                object.type_name = Some(name);
                dict.insert(object);
                made_objects.insert(e.index);
            }
            let Some(object) = dict.object_mut(e.index) else {
                continue;
            };
            object.subs.insert(e.sub, sub);
            if made_objects.contains(&e.index) {
                let count = object.max_sub();
                let zero = SubObject::new("SubIndex 000", DataType::Unsigned8, AccessType::Ro)
                    .with_default(Value::Uint(u64::from(count)));
                object.subs.insert(0, zero);
            }
        }
        made.insert((e.index, e.sub));
        source.set_entry(e.index, e.sub, ctx.pos(at.offset));
        if partial {
            ctx.warn_about(
                at.offset,
                address,
                format!(
                    "{} maps it, but the dictionary does not have it: made from the PDO ({}, ro, mappable {})",
                    which(),
                    t.esi_name(bit_size.unwrap_or(0)),
                    direction_text(dir)
                ),
            );
        }
    }
}
