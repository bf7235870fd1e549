//! The streaming ESI reader: the XML cursor's nodes over the decoded file, a stack of known element
//! names, and per-device raw records (data types, objects, EtherCAT parts) that are resolved into a
//! [`DeviceDescription`] when the device's element ends. Nothing but the current device is held.
//!
//! The parts: `walk` (the cursor's nodes, the tag stack, text and attributes), `elements` (what each
//! known element means), `fields` (values several elements share), `dictionary` (data types and objects
//! into a dictionary) and `pdo` (what the device's PDOs say about its dictionary).

use crate::device::{DeviceDescription, EsiRoot, EthercatInfo, Module};
use crate::dict::Address;
use crate::error::{ParseError, Position};
use crate::object::{Access, EcatStates, PdoMapping};
use crate::report::{Reading, SourceMap};
use crate::value::parse_hex_bytes;
use crate::xml;
use crate::xml::cursor::Document;
use crate::xml::text::ElementText;

mod dictionary;
mod elements;
mod fields;
mod pdo;
mod walk;

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
    EtherCATInfo, EtherCATModule, EtherCATInfoList, Vendor, Id, Name, Descriptions, Devices, Device, Modules, Module, Type,
    GroupType, Profile, Dictionary, DataTypes, DataType, BaseType, BitSize, Comment, SubItem, SubIdx,
    BitOffs, Flags, Access, PdoMapping, ArrayInfo, LBound, Elements, EnumInfo, Objects, Object, Index,
    Info, DefaultData, DefaultValue, DefaultString, MinData, MaxData, MinValue, MaxValue, Fmmu, Sm, RxPdo,
    TxPdo, Exclude, Entry, SubIndex, BitLen, Mailbox, CoE, FoE, EoE, Dc, OpMode, Desc, AssignActivate,
    CycleTimeSync0, ShiftTimeSync0, CycleTimeSync1, ShiftTimeSync1, Eeprom, ByteSize, ConfigData,
    BootStrap, Slots, Slot, ModuleIdent, ModuleClass, Class, VendorId, ModulePdoGroup, InitCmd, Transition,
    Data, DcOpModeName, ProfileNo, AddInfo, Unit,
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

    /// A number as [`xml::parse_number`] reads it; a hexadecimal number with both prefixes
    /// (`#x0x6041`) or its x doubled (`#xx00DEFED`), as some generators write, is read without the
    /// second, with a warning.
    fn parse_number(&self, text: &str, offset: usize, what: &str) -> Option<i128> {
        if let Some(v) = xml::parse_number(text) {
            return Some(v);
        }
        let t = text.trim();
        let (sign, body) = match t.strip_prefix('-') {
            Some(rest) => ("-", rest),
            None => ("", t.strip_prefix('+').unwrap_or(t)),
        };
        let after = ["#x", "#X"].iter().find_map(|p| body.strip_prefix(p))?;
        // `#x0x6041` (two prefixes) or `#xx00DEFED` (the x doubled).
        let (digits, how) = match ["0x", "0X"].iter().find_map(|p| after.strip_prefix(p)) {
            Some(d) => (d, "has two hexadecimal prefixes"),
            None => (
                after
                    .strip_prefix('x')
                    .or_else(|| after.strip_prefix('X'))?,
                "has its hexadecimal prefix's x doubled",
            ),
        };
        let single = format!("{sign}#x{digits}");
        let v = xml::parse_number(&single)?;
        self.warn(
            offset,
            format!("`{}` in {what} {how}; read as {single}", clip(t)),
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
    unit: Option<u32>,
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
    /// A `Modules/Module` of a module catalogue (root `EtherCATModule`): a description of its own.
    in_catalogue: bool,
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
    /// The text of the innermost element.
    text: ElementText,
    lcid: Option<u32>,
    restrictions: (Option<EcatStates>, Option<EcatStates>),
    vendor_id: u32,
    vendor_name: Localized,
    file_version: String,
    device: Option<RawDevice>,
    done: Vec<DeviceDescription>,
    /// The file's `Descriptions/Modules/Module`s (of the current `EtherCATInfo` of a list).
    modules: Vec<Module>,
    sources: Vec<SourceMap>,
    /// In an `EtherCATInfoList`: the place of the current `EtherCATInfo` in it.
    list_entry: Option<usize>,
    /// The devices of `done` the vendor, file version and modules are given to.
    finished: usize,
}

impl Parser<'_> {
    /// The end of an `EtherCATInfo` (or `EtherCATModule`): its vendor, file version and modules
    /// belong to each of its devices; in a list, the devices are the list's entry's, and the next
    /// entry starts afresh.
    fn finish_info(&mut self) {
        let modules: std::sync::Arc<[Module]> = std::mem::take(&mut self.modules).into();
        let vendor_name = std::mem::take(&mut self.vendor_name);
        for d in &mut self.done[self.finished..] {
            d.identity.vendor_id = self.vendor_id;
            d.identity.vendor_name = vendor_name.get().unwrap_or_default().to_string();
            d.file_info.file_version = self.file_version.clone();
            if let Some(ecat) = d.ethercat.as_mut() {
                ecat.modules = modules.clone();
                if let Some(entry) = self.list_entry {
                    ecat.root = EsiRoot::EtherCatInfoList(entry);
                }
            }
        }
        self.finished = self.done.len();
        self.vendor_id = 0;
        self.file_version.clear();
        if let Some(entry) = self.list_entry.as_mut() {
            *entry += 1;
        }
    }
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
        text: ElementText::default(),
        lcid: None,
        restrictions: (None, None),
        vendor_id: 0,
        vendor_name: Localized::default(),
        file_version: String::new(),
        device: None,
        done: Vec::new(),
        modules: Vec::new(),
        sources: Vec::new(),
        list_entry: None,
        finished: 0,
    };
    parser.run()?;
    let Parser { done, sources, .. } = parser;
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
