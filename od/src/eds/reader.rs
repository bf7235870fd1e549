//! The EDS/DCF reader: a line scanner over the INI text (the INI structure of CiA 306-1 §4), then the
//! building of the description from the sections it found.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::ops::Range;

use crate::device::{CanInfo, Commissioning, DeviceDescription, FileInfo, Identity};
use crate::error::{LineIndex, ParseError, Position};
use crate::object::{AccessType, DefaultValue, Object, ObjectKind, PdoMapping, SubObject};
use crate::report::{Finding, Reading, SourceMap};
use crate::types::{DataType, STANDARD_TYPES};
use crate::value::{parse_integer, Value};

pub(super) fn read(bytes: &[u8], source_name: &str) -> Result<Reading, ParseError> {
    let text = decode(bytes);
    let ini = Ini::scan(&text, source_name)?;
    let builder = Builder::new(&ini)?;
    let desc = builder.build()?;
    let mut source = SourceMap::default();
    source.set_device(Position { line: 1, column: 1 });
    for (&index, sections) in &builder.objects {
        if let Some(main) = sections.main.and_then(|i| builder.section(i)) {
            source.set_object(index, ini.position(main.name));
        }
        for (&sub, &i) in &sections.subs {
            if let Some(section) = builder.section(i) {
                source.set_entry(index, sub, ini.position(section.name));
            }
        }
    }
    Ok(Reading::one(desc, source, builder.findings.into_inner()))
}

/// The text of the file: UTF-8 without its byte-order mark, or ISO-8859-1 when the bytes are not UTF-8
/// (one character per byte, so lines and columns stay those of the file).
fn decode(bytes: &[u8]) -> Cow<'_, str> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    match std::str::from_utf8(bytes) {
        Ok(text) => Cow::Borrowed(text),
        Err(_) => Cow::Owned(bytes.iter().map(|&b| char::from(b)).collect()),
    }
}

fn is_comment(line: &str) -> bool {
    line.starts_with(';') || line.starts_with('#')
}

/// `key=value`, both trimmed, as slices of the text.
struct Entry<'a> {
    key: &'a str,
    value: &'a str,
}

/// `[name]` and the range of its entries in [`Ini::entries`].
struct Section<'a> {
    name: &'a str,
    entries: Range<usize>,
}

/// The scanned file: sections and their entries in file order.
struct Ini<'a> {
    text: &'a str,
    lines: LineIndex,
    source: &'a str,
    sections: Vec<Section<'a>>,
    entries: Vec<Entry<'a>>,
}

impl<'a> Ini<'a> {
    fn scan(text: &'a str, source: &'a str) -> Result<Ini<'a>, ParseError> {
        let mut ini = Ini {
            text,
            lines: LineIndex::new(text.as_bytes()),
            source,
            sections: Vec::new(),
            entries: Vec::new(),
        };
        for raw in text.split('\n') {
            let line = raw.trim_ascii();
            if line.is_empty() || is_comment(line) {
                continue;
            }
            if let Some(rest) = line.strip_prefix('[') {
                let Some(close) = rest.bytes().position(|b| b == b']') else {
                    return Err(ini.error(line, "expected `]` closing the section name"));
                };
                let name = rest[..close].trim_ascii();
                let after = rest[close + 1..].trim_ascii_start();
                if !after.is_empty() && !is_comment(after) {
                    return Err(ini.error(
                        after,
                        format!(
                            "unexpected text `{}` after the section name [{name}]",
                            shown(after)
                        ),
                    ));
                }
                if name.is_empty() {
                    return Err(ini.error(line, "expected a section name between `[` and `]`"));
                }
                let start = ini.entries.len();
                ini.sections.push(Section {
                    name,
                    entries: start..start,
                });
                continue;
            }
            let Some(eq) = line.bytes().position(|b| b == b'=') else {
                return Err(ini.error(
                    line,
                    format!(
                        "expected `key=value`, a `[section]` header or a `;` comment, found `{}`",
                        shown(line)
                    ),
                ));
            };
            let key = line[..eq].trim_ascii();
            let value = line[eq + 1..].trim_ascii();
            if key.is_empty() {
                return Err(ini.error(line, "expected a key before `=`"));
            }
            let Some(section) = ini.sections.last_mut() else {
                return Err(ini.error(
                    line,
                    format!("`{}` comes before the first [section]", shown(key)),
                ));
            };
            section.entries.end += 1;
            ini.entries.push(Entry { key, value });
        }
        Ok(ini)
    }

    /// Where `slice` (a part of the text) starts, from the index of line starts made once.
    fn position(&self, slice: &str) -> Position {
        let offset = (slice.as_ptr() as usize).saturating_sub(self.text.as_ptr() as usize);
        self.lines.position(self.text.as_bytes(), offset)
    }

    /// An error at the start of `slice`.
    fn error(&self, slice: &str, message: impl Into<String>) -> ParseError {
        ParseError::new(self.source, self.position(slice), message)
    }

    fn entries(&self, section: &Section<'a>) -> &[Entry<'a>] {
        self.entries.get(section.entries.clone()).unwrap_or(&[])
    }
}

/// The first characters of `text`, for messages.
fn shown(text: &str) -> Cow<'_, str> {
    const MAX: usize = 60;
    match text.char_indices().nth(MAX) {
        Some((cut, _)) => Cow::Owned(format!("{}…", &text[..cut])),
        None => Cow::Borrowed(text),
    }
}

/// What a section is, by its name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    FileInfo,
    DeviceInfo,
    DummyUsage,
    Comments,
    MandatoryObjects,
    OptionalObjects,
    ManufacturerObjects,
    Commissioning,
    Object(u16),
    Sub(u16, u8),
    Names(u16),
    Values(u16),
    Other,
}

const NAMED: [(&str, Kind); 9] = [
    ("FileInfo", Kind::FileInfo),
    ("DeviceInfo", Kind::DeviceInfo),
    ("DummyUsage", Kind::DummyUsage),
    ("Comments", Kind::Comments),
    ("MandatoryObjects", Kind::MandatoryObjects),
    ("OptionalObjects", Kind::OptionalObjects),
    ("ManufacturerObjects", Kind::ManufacturerObjects),
    ("DeviceComissioning", Kind::Commissioning),
    ("DeviceCommissioning", Kind::Commissioning),
];

fn hex_u16(text: &str) -> Option<u16> {
    if text.is_empty() || text.len() > 4 || !text.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    u16::from_str_radix(text, 16).ok()
}

/// `key` without `prefix`, which it starts with in any case.
fn strip_prefix_ignore_case<'k>(key: &'k str, prefix: &str) -> Option<&'k str> {
    key.get(..prefix.len())
        .filter(|p| p.eq_ignore_ascii_case(prefix))
        .and_then(|_| key.get(prefix.len()..))
}

fn classify(name: &str) -> Kind {
    if let (Some(head), Some(rest)) = (name.get(..4), name.get(4..)) {
        if let Some(index) = hex_u16(head).filter(|_| head.len() == 4) {
            if rest.is_empty() {
                return Kind::Object(index);
            }
            if let (Some(sub), Some(digits)) = (rest.get(..3), rest.get(3..)) {
                if sub.eq_ignore_ascii_case("sub") && (1..=2).contains(&digits.len()) {
                    if let Some(s) = hex_u16(digits) {
                        return Kind::Sub(index, s as u8);
                    }
                }
            }
            if rest.eq_ignore_ascii_case("Name") {
                return Kind::Names(index);
            }
            if rest.eq_ignore_ascii_case("Value") {
                return Kind::Values(index);
            }
            return Kind::Other;
        }
    }
    NAMED
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name))
        .map_or(Kind::Other, |&(_, kind)| kind)
}

/// The sections that describe one object.
#[derive(Default)]
struct ObjectSections {
    main: Option<usize>,
    subs: BTreeMap<u8, usize>,
    names: Option<usize>,
    values: Option<usize>,
}

/// Keys of object and sub-object sections, in the order of the `OBJ_*` constants.
const OBJECT_KEYS: [&str; 12] = [
    "ParameterName",
    "ObjectType",
    "DataType",
    "AccessType",
    "DefaultValue",
    "PDOMapping",
    "LowLimit",
    "HighLimit",
    "SubNumber",
    "ObjFlags",
    "CompactSubObj",
    "ParameterValue",
];
const OBJ_NAME: usize = 0;
const OBJ_TYPE: usize = 1;
const OBJ_DATA_TYPE: usize = 2;
const OBJ_ACCESS: usize = 3;
const OBJ_DEFAULT: usize = 4;
const OBJ_PDO: usize = 5;
const OBJ_LOW: usize = 6;
const OBJ_HIGH: usize = 7;
const OBJ_SUB_NUMBER: usize = 8;
const OBJ_FLAGS: usize = 9;
const OBJ_COMPACT: usize = 10;
const OBJ_VALUE: usize = 11;

type Fields<'i, 'a, const N: usize> = [Option<&'i Entry<'a>>; N];

/// Turns the scanned sections into a description.
struct Builder<'i, 'a> {
    ini: &'i Ini<'a>,
    named: [Option<usize>; NAMED_KINDS.len()],
    objects: BTreeMap<u16, ObjectSections>,
    /// The warnings, in the order they were found.
    findings: std::cell::RefCell<Vec<Finding>>,
}

/// The named sections the reader uses, one slot each in [`Builder::named`].
const NAMED_KINDS: [Kind; 8] = [
    Kind::FileInfo,
    Kind::DeviceInfo,
    Kind::DummyUsage,
    Kind::Comments,
    Kind::MandatoryObjects,
    Kind::OptionalObjects,
    Kind::ManufacturerObjects,
    Kind::Commissioning,
];

/// The error for section `i`, which repeats section `first`.
fn repeated(ini: &Ini<'_>, i: usize, first: usize) -> ParseError {
    let (Some(again), Some(first)) = (ini.sections.get(i), ini.sections.get(first)) else {
        return ParseError::new(ini.source, Position::default(), "repeated section");
    };
    ini.error(
        again.name,
        format!(
            "section [{}] appears a second time (first at line {})",
            again.name,
            ini.position(first.name).line
        ),
    )
}

/// Every object code, for reading `ObjectType=` written as a name.
const OBJECT_KINDS: [ObjectKind; 7] = [
    ObjectKind::Null,
    ObjectKind::Domain,
    ObjectKind::DefType,
    ObjectKind::DefStruct,
    ObjectKind::Var,
    ObjectKind::Array,
    ObjectKind::Record,
];

/// A parsed value and whether the node-ID is added to it.
type Typed = (Value, bool);

impl<'i, 'a> Builder<'i, 'a> {
    fn new(ini: &'i Ini<'a>) -> Result<Builder<'i, 'a>, ParseError> {
        let mut named = [None; NAMED_KINDS.len()];
        let mut objects: BTreeMap<u16, ObjectSections> = BTreeMap::new();
        for (i, section) in ini.sections.iter().enumerate() {
            let slot = match classify(section.name) {
                Kind::Other => continue,
                Kind::Object(index) => &mut objects.entry(index).or_default().main,
                Kind::Sub(index, sub) => {
                    let subs = &mut objects.entry(index).or_default().subs;
                    if let Some(&first) = subs.get(&sub) {
                        return Err(repeated(ini, i, first));
                    }
                    subs.insert(sub, i);
                    continue;
                }
                Kind::Names(index) => &mut objects.entry(index).or_default().names,
                Kind::Values(index) => &mut objects.entry(index).or_default().values,
                kind => match NAMED_KINDS
                    .iter()
                    .position(|&k| k == kind)
                    .and_then(|n| named.get_mut(n))
                {
                    Some(slot) => slot,
                    None => continue,
                },
            };
            if let Some(first) = *slot {
                return Err(repeated(ini, i, first));
            }
            *slot = Some(i);
        }
        Ok(Builder {
            ini,
            named,
            objects,
            findings: std::cell::RefCell::new(Vec::new()),
        })
    }

    fn section(&self, i: usize) -> Option<&'i Section<'a>> {
        self.ini.sections.get(i)
    }

    fn named(&self, kind: Kind) -> Option<&'i Section<'a>> {
        let n = NAMED_KINDS.iter().position(|&k| k == kind)?;
        self.named
            .get(n)
            .copied()
            .flatten()
            .and_then(|i| self.section(i))
    }

    /// Picks the entries named `names` out of `section`, case-insensitively; a key given twice is an
    /// error.
    fn fields<const N: usize>(
        &self,
        section: &Section<'a>,
        names: [&str; N],
    ) -> Result<Fields<'i, 'a, N>, ParseError> {
        let mut found: Fields<'i, 'a, N> = [None; N];
        let entries: &'i [Entry<'a>] = self.ini.entries(section);
        for entry in entries {
            let Some(i) = names.iter().position(|n| n.eq_ignore_ascii_case(entry.key)) else {
                continue;
            };
            let Some(slot) = found.get_mut(i) else {
                continue;
            };
            if let Some(first) = slot {
                return Err(self.repeated_key(section, entry, first));
            }
            *slot = Some(entry);
        }
        Ok(found)
    }

    /// The entries of `section` whose keys are `prefix` (in any case) and a decimal number, by number; a
    /// number given twice is an error. Other keys are skipped.
    fn numbered(
        &self,
        section: &Section<'a>,
        prefix: &str,
    ) -> Result<BTreeMap<u32, &'i Entry<'a>>, ParseError> {
        let mut found = BTreeMap::new();
        let entries: &'i [Entry<'a>] = self.ini.entries(section);
        for entry in entries {
            let Some(digits) = strip_prefix_ignore_case(entry.key, prefix) else {
                continue;
            };
            if !digits.bytes().all(|b| b.is_ascii_digit()) {
                continue;
            }
            let Ok(n) = digits.parse::<u32>() else {
                continue;
            };
            if let Some(first) = found.insert(n, entry) {
                return Err(self.repeated_key(section, entry, first));
            }
        }
        Ok(found)
    }

    /// The error for `entry`, whose key `first` already gave in `section`.
    fn repeated_key(
        &self,
        section: &Section<'a>,
        entry: &Entry<'a>,
        first: &Entry<'a>,
    ) -> ParseError {
        self.ini.error(
            entry.key,
            format!(
                "{}= appears a second time in [{}] (first at line {})",
                entry.key,
                section.name,
                self.ini.position(first.key).line
            ),
        )
    }

    /// A warning at the start of `slice` (a part of the text).
    fn warn(&self, slice: &str, message: impl Into<String>) {
        self.findings
            .borrow_mut()
            .push(Finding::warning(self.ini.position(slice), message));
    }

    /// An error about the value of `entry`: what was expected and what was found.
    fn bad(&self, section: &Section<'a>, entry: &Entry<'a>, expected: &str) -> ParseError {
        self.ini.error(
            entry.value,
            format!(
                "{}= in [{}]: expected {expected}, found `{}`",
                entry.key,
                section.name,
                shown(entry.value)
            ),
        )
    }

    /// An error about a key missing from `section`.
    fn missing(&self, section: &Section<'a>, key: &str, expected: &str) -> ParseError {
        self.ini.error(
            section.name,
            format!("[{}] has no {key}= ({expected})", section.name),
        )
    }

    /// An integer that fits `T`; `default` when absent or empty.
    fn number<T: TryFrom<i128>>(
        &self,
        section: &Section<'a>,
        entry: Option<&Entry<'a>>,
        expected: &str,
        default: T,
    ) -> Result<T, ParseError> {
        match entry {
            None => Ok(default),
            Some(e) if e.value.is_empty() => Ok(default),
            Some(e) => parse_integer(e.value)
                .and_then(|v| T::try_from(v).ok())
                .ok_or_else(|| self.bad(section, e, expected)),
        }
    }

    /// `0`/`1` (or `false`/`true`); `default` when absent or empty.
    fn flag(
        &self,
        section: &Section<'a>,
        entry: Option<&Entry<'a>>,
        default: bool,
    ) -> Result<bool, ParseError> {
        let Some(e) = entry.filter(|e| !e.value.is_empty()) else {
            return Ok(default);
        };
        if e.value.eq_ignore_ascii_case("true") {
            return Ok(true);
        }
        if e.value.eq_ignore_ascii_case("false") {
            return Ok(false);
        }
        match parse_integer(e.value) {
            Some(0) => Ok(false),
            Some(1) => Ok(true),
            _ => Err(self.bad(section, e, "0 or 1")),
        }
    }

    fn build(&self) -> Result<DeviceDescription, ParseError> {
        let mut desc = DeviceDescription::default();
        if let Some(section) = self.named(Kind::FileInfo) {
            desc.file_info = self.file_info(section)?;
        }
        let mut can = None;
        if let Some(section) = self.named(Kind::DeviceInfo) {
            let (identity, info) = self.device_info(section)?;
            desc.identity = identity;
            can = info;
        }
        if let Some(section) = self.named(Kind::DummyUsage) {
            can.get_or_insert_with(CanInfo::default).dummy_usage = self.dummy_usage(section)?;
        }
        desc.can = can;
        if let Some(section) = self.named(Kind::Comments) {
            desc.comments = self.comments(section)?;
        }
        if let Some(section) = self.named(Kind::Commissioning) {
            desc.commissioning = Some(self.commissioning(section)?);
        }
        let mut listed: BTreeMap<u16, &str> = BTreeMap::new();
        let mut lists = 0;
        for kind in [
            Kind::MandatoryObjects,
            Kind::OptionalObjects,
            Kind::ManufacturerObjects,
        ] {
            if let Some(section) = self.named(kind) {
                lists += 1;
                self.check_list(section, &mut listed)?;
            }
        }
        if lists > 0 {
            // Lely reads the objects its lists name and no others: one warning, at the first of them.
            let unlisted: Vec<&str> = self
                .objects
                .iter()
                .filter(|(index, _)| !listed.contains_key(index))
                .filter_map(|(_, sections)| sections.main.and_then(|i| self.section(i)))
                .map(|main| main.name)
                .collect();
            if let Some(first) = unlisted.first() {
                let mut names: Vec<String> =
                    unlisted.iter().take(8).map(|n| format!("[{n}]")).collect();
                if unlisted.len() > 8 {
                    names.push("…".into());
                }
                self.warn(
                    first,
                    format!(
                        "{} object(s) in none of the object lists, which Lely leaves out: {}",
                        unlisted.len(),
                        names.join(", ")
                    ),
                );
            }
        }
        let node_id = desc.node_id();
        for (&index, sections) in &self.objects {
            let Some(main) = sections.main.and_then(|i| self.section(i)) else {
                if let Some(sub) = sections.subs.values().next().and_then(|&i| self.section(i)) {
                    return Err(self.ini.error(
                        sub.name,
                        format!(
                            "section [{}] has no object section [{index:04X}] before or after it",
                            sub.name
                        ),
                    ));
                }
                // `[xxxxName]` / `[xxxxValue]` of an object the file does not describe: nothing to apply
                // them to.
                continue;
            };
            desc.dictionary
                .insert(self.object(index, main, sections, node_id)?);
        }
        Ok(desc)
    }

    fn file_info(&self, section: &Section<'a>) -> Result<FileInfo, ParseError> {
        let f = self.fields(
            section,
            [
                "FileName",
                "FileVersion",
                "FileRevision",
                "EDSVersion",
                "Description",
                "CreationTime",
                "CreationDate",
                "CreatedBy",
                "ModificationTime",
                "ModificationDate",
                "ModifiedBy",
            ],
        )?;
        let text = |i: usize| f[i].map_or_else(String::new, |e| e.value.to_string());
        Ok(FileInfo {
            file_name: text(0),
            file_version: text(1),
            file_revision: text(2),
            format_version: text(3),
            description: text(4),
            creation_time: text(5),
            creation_date: text(6),
            created_by: text(7),
            modification_time: text(8),
            modification_date: text(9),
            modified_by: text(10),
        })
    }

    /// The identity of `[DeviceInfo]`, and its CAN capabilities where it gives any of their keys.
    fn device_info(
        &self,
        section: &Section<'a>,
    ) -> Result<(Identity, Option<CanInfo>), ParseError> {
        const U32: &str = "a 32-bit number like 0x0000012A";
        let [vendor_name, vendor_number, product_name, product_number, revision, order_code] = self
            .fields(
                section,
                [
                    "VendorName",
                    "VendorNumber",
                    "ProductName",
                    "ProductNumber",
                    "RevisionNumber",
                    "OrderCode",
                ],
            )?;
        let text = |e: Option<&Entry<'a>>| e.map_or_else(String::new, |e| e.value.to_string());
        let identity = Identity {
            vendor_id: self.number(section, vendor_number, U32, 0)?,
            vendor_name: text(vendor_name),
            product_code: self.number(section, product_number, U32, 0)?,
            revision: self.number(section, revision, U32, 0)?,
            product_name: text(product_name),
            order_code: text(order_code),
        };

        const RATES: [u32; 8] = [10, 20, 50, 125, 250, 500, 800, 1000];
        let rate_keys = self.fields(
            section,
            [
                "BaudRate_10",
                "BaudRate_20",
                "BaudRate_50",
                "BaudRate_125",
                "BaudRate_250",
                "BaudRate_500",
                "BaudRate_800",
                "BaudRate_1000",
            ],
        )?;
        let any_rate = rate_keys.iter().any(Option::is_some);
        let mut baud_rates = Vec::new();
        for (rate, entry) in RATES.into_iter().zip(rate_keys) {
            if self.flag(section, entry, false)? {
                baud_rates.push(rate);
            }
        }

        let [master, slave, granularity, dynamic, group, rx, tx, lss] = self.fields(
            section,
            [
                "SimpleBootUpMaster",
                "SimpleBootUpSlave",
                "Granularity",
                "DynamicChannelsSupported",
                "GroupMessaging",
                "NrOfRXPDO",
                "NrOfTXPDO",
                "LSS_Supported",
            ],
        )?;
        let given = any_rate
            || [master, slave, granularity, dynamic, group, rx, tx, lss]
                .iter()
                .any(Option::is_some);
        let defaults = CanInfo::default();
        let info = CanInfo {
            baud_rates,
            simple_boot_up_master: self.flag(section, master, defaults.simple_boot_up_master)?,
            simple_boot_up_slave: self.flag(section, slave, defaults.simple_boot_up_slave)?,
            granularity: self.number(
                section,
                granularity,
                "a granularity in bits, 0 to 64",
                defaults.granularity,
            )?,
            dynamic_channels: self.number(
                section,
                dynamic,
                "a number of dynamic channels, 0 to 255",
                defaults.dynamic_channels,
            )?,
            group_messaging: self.flag(section, group, defaults.group_messaging)?,
            nr_of_rx_pdo: self.number(
                section,
                rx,
                "a number of RPDOs, 0 to 512",
                defaults.nr_of_rx_pdo,
            )?,
            nr_of_tx_pdo: self.number(
                section,
                tx,
                "a number of TPDOs, 0 to 512",
                defaults.nr_of_tx_pdo,
            )?,
            lss_supported: self.flag(section, lss, defaults.lss_supported)?,
            dummy_usage: Vec::new(),
        };
        Ok((identity, given.then_some(info)))
    }

    /// `DummyXXXX=1`: the data types (by index) that may be mapped as dummies.
    fn dummy_usage(&self, section: &Section<'a>) -> Result<Vec<u16>, ParseError> {
        let mut usable = Vec::new();
        for entry in self.ini.entries(section) {
            let Some(index) = strip_prefix_ignore_case(entry.key, "Dummy").and_then(hex_u16) else {
                continue;
            };
            if self.flag(section, Some(entry), false)? {
                usable.push(index);
            }
        }
        usable.sort_unstable();
        usable.dedup();
        Ok(usable)
    }

    fn comments(&self, section: &Section<'a>) -> Result<Vec<String>, ParseError> {
        let [lines] = self.fields(section, ["Lines"])?;
        let count: u32 = self.number(section, lines, "a number of comment lines", 0)?;
        let numbered = self.numbered(section, "Line")?;
        (1..=count)
            .map(|n| {
                numbered
                    .get(&n)
                    .map(|e| e.value.to_string())
                    .ok_or_else(|| {
                        self.missing(
                            section,
                            &format!("Line{n}"),
                            &format!("Lines={count} announces it"),
                        )
                    })
            })
            .collect()
    }

    fn commissioning(&self, section: &Section<'a>) -> Result<Commissioning, ParseError> {
        let [node_id, node_name, baud_rate, net_number, network_name, manager, serial] = self
            .fields(
                section,
                [
                    "NodeID",
                    "NodeName",
                    "Baudrate",
                    "NetNumber",
                    "NetworkName",
                    "CANopenManager",
                    "LSS_SerialNumber",
                ],
            )?;
        // Lely's DCFs of a node that LSS is yet to configure say `NodeID=0xFF`, or give none; Lely reads
        // both as unconfigured, and python-canopen takes whatever number is there. A number that is no
        // node-ID leaves the node unconfigured, with a warning.
        let node_id = match node_id.filter(|e| !e.value.is_empty()) {
            Some(e) => {
                let id = parse_integer(e.value)
                    .ok_or_else(|| self.bad(section, e, "a node-ID, 1 to 127"))?;
                match u8::try_from(id).ok().filter(|id| (1..=127).contains(id)) {
                    Some(id) => Some(id),
                    None => {
                        let what = if id == 0xFF {
                            "marks a node that LSS has yet to configure"
                        } else {
                            "is no node-ID (1 to 127)"
                        };
                        self.warn(
                            e.value,
                            format!(
                                "NodeID= in [{}]: `{}` {what}; the node is unconfigured, and `$NODEID` values stay relative to the node-ID",
                                section.name, e.value
                            ),
                        );
                        None
                    }
                }
            }
            None => {
                self.warn(
                    section.name,
                    format!(
                        "[{}] has no NodeID=; the node is unconfigured, and `$NODEID` values stay relative to the node-ID",
                        section.name
                    ),
                );
                None
            }
        };
        let text = |e: Option<&Entry<'a>>| e.map_or_else(String::new, |e| e.value.to_string());
        Ok(Commissioning {
            node_id,
            node_name: text(node_name),
            baud_rate: self.number(section, baud_rate, "a bit rate in kbit/s", 0)?,
            net_number: self.number(section, net_number, "a 32-bit network number", 0)?,
            network_name: text(network_name),
            canopen_manager: self.flag(section, manager, false)?,
            lss_serial_number: self.number(section, serial, "a 32-bit serial number", 0)?,
        })
    }

    /// Checks an object list: `SupportedObjects=` is a number and every entry is an object index, and
    /// adds the objects it lists to `listed` (index → the list naming it). A count that is not the number of
    /// entries, an object listed twice and a listed object without its section are warnings: python-canopen
    /// reads the sections whatever the lists say, Lely reads the lists' first `SupportedObjects` entries and
    /// refuses an object without its section.
    fn check_list(
        &self,
        section: &Section<'a>,
        listed: &mut BTreeMap<u16, &'a str>,
    ) -> Result<(), ParseError> {
        let [supported] = self.fields(section, ["SupportedObjects"])?;
        let count = self.number::<u32>(section, supported, "a number of objects", 0)?;
        let entries = self.numbered(section, "")?;
        if let Some(s) = supported {
            if usize::try_from(count).ok() != Some(entries.len()) {
                self.warn(
                    s.value,
                    format!(
                        "SupportedObjects={} in [{}], but it lists {} object(s)",
                        s.value.trim(),
                        section.name,
                        entries.len()
                    ),
                );
            }
        }
        for entry in entries.values() {
            const INDEX: &str = "an object index like 0x1000";
            if entry.value.is_empty() {
                return Err(self.bad(section, entry, INDEX));
            }
            // A listed object without its section is skipped: CiA 306 wants one, but real files
            // (python-canopen's e35.eds) list objects they do not describe, and every other tool reads them.
            let index = self.number::<u16>(section, Some(entry), INDEX, 0)?;
            if let Some(first) = listed.insert(index, section.name) {
                self.warn(
                    entry.value,
                    format!(
                        "[{}] lists 0x{index:04X} again (first in [{first}])",
                        section.name
                    ),
                );
            } else if !self.objects.get(&index).is_some_and(|s| s.main.is_some()) {
                self.warn(
                    entry.value,
                    format!(
                        "[{}] lists 0x{index:04X}, which has no section [{index:04X}] (Lely refuses that)",
                        section.name
                    ),
                );
            }
        }
        Ok(())
    }

    fn object(
        &self,
        index: u16,
        main: &Section<'a>,
        sections: &ObjectSections,
        node_id: Option<u8>,
    ) -> Result<Object, ParseError> {
        let fields = self.fields(main, OBJECT_KEYS)?;
        let name = fields[OBJ_NAME]
            .ok_or_else(|| self.missing(main, "ParameterName", "the object's name"))?
            .value;
        let kind = match fields[OBJ_TYPE].filter(|e| !e.value.is_empty()) {
            None => ObjectKind::Var,
            Some(e) => self.object_kind(main, e)?,
        };
        self.number::<u8>(
            main,
            fields[OBJ_SUB_NUMBER],
            "a number of sub-indices, 0 to 255",
            0,
        )?;
        self.number::<u32>(main, fields[OBJ_FLAGS], "object flags, a 32-bit number", 0)?;
        let mut object = Object::structured(index, name, kind);
        if !kind.has_subs() {
            if let Some(sub) = sections.subs.values().next().and_then(|&i| self.section(i)) {
                return Err(self.ini.error(
                    sub.name,
                    format!(
                        "section [{}] describes a sub-index of a {kind} object; only ARRAY, RECORD and DEFSTRUCT objects have them",
                        sub.name
                    ),
                ));
            }
            if kind == ObjectKind::Null && fields[OBJ_DATA_TYPE].is_none() {
                return Ok(object);
            }
            let sub = self.sub_object(main, &fields, name.to_string(), node_id, None)?;
            object.subs.insert(0, sub);
            return Ok(object);
        }
        let compact: u8 = self.number(
            main,
            fields[OBJ_COMPACT],
            "a number of compact sub-indices, 0 to 254",
            0,
        )?;
        if compact == 255 {
            if let Some(e) = fields[OBJ_COMPACT] {
                // CiA 301 keeps sub-index 0xFF for the object's structure, so an ARRAY has at most 254
                // entries; python-canopen's receiver.eds has 255 all the same, and Lely builds them.
                self.warn(
                    e.value,
                    format!(
                        "CompactSubObj= in [{}]: 255 entries reach sub-index 0xFF, which CiA 301 keeps for the object's structure; read as 255 entries, as Lely does",
                        main.name
                    ),
                );
            }
        }
        if compact > 0 {
            let names = match sections.names.and_then(|i| self.section(i)) {
                Some(section) => Some((section, self.numbered(section, "")?)),
                None => None,
            };
            let values = match sections.values.and_then(|i| self.section(i)) {
                Some(section) => Some((section, self.numbered(section, "")?)),
                None => None,
            };
            for section in [&names, &values].into_iter().flatten() {
                let [count] = self.fields(section.0, ["NrOfEntries"])?;
                self.number::<u8>(section.0, count, "a number of entries, 0 to 254", 0)?;
            }
            object.subs.insert(
                0,
                SubObject::new("NrOfObjects", DataType::Unsigned8, AccessType::Ro)
                    .with_default(Value::Uint(u64::from(compact))),
            );
            for n in 1..=compact {
                let key = u32::from(n);
                let sub_name = names
                    .as_ref()
                    .and_then(|(_, map)| map.get(&key))
                    .map_or_else(|| format!("{name}{n}"), |e| e.value.to_string());
                let value = values
                    .as_ref()
                    .and_then(|(section, map)| map.get(&key).map(|e| (*section, *e)));
                let sub = self.sub_object(main, &fields, sub_name, node_id, value)?;
                object.subs.insert(n, sub);
            }
        }
        for (&sub_index, &i) in &sections.subs {
            let Some(section) = self.section(i) else {
                continue;
            };
            let sub_fields = self.fields(section, OBJECT_KEYS)?;
            let sub_name = sub_fields[OBJ_NAME]
                .ok_or_else(|| self.missing(section, "ParameterName", "the entry's name"))?
                .value;
            let sub = self.sub_object(section, &sub_fields, sub_name.to_string(), node_id, None)?;
            object.subs.insert(sub_index, sub);
        }
        Ok(object)
    }

    /// One entry from the keys of `section`. `value` replaces the section's `ParameterValue` (the
    /// `[xxxxValue]` entry of a compact array).
    fn sub_object(
        &self,
        section: &Section<'a>,
        fields: &Fields<'i, 'a, 12>,
        name: String,
        node_id: Option<u8>,
        value: Option<(&Section<'a>, &Entry<'a>)>,
    ) -> Result<SubObject, ParseError> {
        let data_type = fields[OBJ_DATA_TYPE]
            .ok_or_else(|| {
                self.missing(section, "DataType", "a CiA 301 data type index like 0x0007")
            })
            .and_then(|e| self.data_type(section, e))?;
        let access = fields[OBJ_ACCESS]
            .ok_or_else(|| self.missing(section, "AccessType", "ro, wo, rw, rwr, rww or const"))?;
        let access = match AccessType::parse(access.value) {
            Some(a) => a,
            None => {
                // `R` and `W` alone (can2mqtt's files): python-canopen reads them as readable and
                // writable.
                let single = match access.value.trim() {
                    "r" | "R" => Some(AccessType::Ro),
                    "w" | "W" => Some(AccessType::Wo),
                    _ => None,
                };
                let Some(a) = single else {
                    return Err(self.bad(section, access, "ro, wo, rw, rwr, rww or const"));
                };
                self.warn(
                    access.value,
                    format!(
                        "AccessType={} in [{}] is no CiA 306 access type; read as {a}",
                        access.value.trim(),
                        section.name
                    ),
                );
                a
            }
        };
        let mappable = self.flag(section, fields[OBJ_PDO], false)?;
        let mut sub = SubObject::new(name, data_type, access);
        if mappable {
            sub.pdo = match access {
                AccessType::Ro | AccessType::Const | AccessType::Rwr => PdoMapping::Tpdo,
                AccessType::Wo | AccessType::Rww => PdoMapping::Rpdo,
                AccessType::Rw => PdoMapping::Both,
            };
        }
        if let Some(e) = fields[OBJ_DEFAULT] {
            if let Some((value, plus_node_id)) = self.typed(section, e, data_type, true) {
                let default = DefaultValue {
                    value,
                    plus_node_id,
                };
                if let Some(bytes) = self.resolved(section, e, &default, data_type, node_id) {
                    sub.value = bytes;
                    sub.default = Some(default);
                }
            }
        }
        if data_type.is_signed() || data_type.is_unsigned() || data_type.is_real() {
            for (slot, entry) in [
                (&mut sub.low, fields[OBJ_LOW]),
                (&mut sub.high, fields[OBJ_HIGH]),
            ] {
                if let Some(e) = entry {
                    *slot = self.typed(section, e, data_type, false).map(|(v, _)| v);
                }
            }
        }
        let value = value.or_else(|| fields[OBJ_VALUE].map(|e| (section, e)));
        if let Some((value_section, e)) = value {
            if let Some((value, plus_node_id)) = self.typed(value_section, e, data_type, true) {
                let current = DefaultValue {
                    value,
                    plus_node_id,
                };
                if let Some(bytes) = self.resolved(value_section, e, &current, data_type, node_id) {
                    sub.value = bytes;
                    sub.value_set = true;
                    sub.value_plus_node_id = plus_node_id;
                }
            }
        }
        Ok(sub)
    }

    /// The bytes of `value` (read from `entry`) for the node `node_id`, or `None` with a warning when
    /// they do not fit `data_type`. A value that adds the node-ID must fit for every node-ID when the file
    /// names none, or a DCF written from it for node 127 could not be read.
    fn resolved(
        &self,
        section: &Section<'a>,
        entry: &Entry<'a>,
        value: &DefaultValue,
        data_type: DataType,
        node_id: Option<u8>,
    ) -> Option<Vec<u8>> {
        let widest = (value.plus_node_id && node_id.is_none()).then_some(127);
        let mut bytes = Vec::new();
        for id in widest.into_iter().chain([node_id.unwrap_or(0)]) {
            match value.resolve(id).encode(data_type) {
                Ok(b) => bytes = b,
                Err(err) => {
                    let what = if value.plus_node_id {
                        format!("with node-ID {id} the value does not fit: {err}")
                    } else {
                        err.to_string()
                    };
                    self.warn(
                        entry.value,
                        format!(
                            "{}= in [{}]: {what}; {}",
                            entry.key,
                            section.name,
                            dropped(entry.key)
                        ),
                    );
                    return None;
                }
            }
        }
        Some(bytes)
    }

    /// The object code of `ObjectType=`: a number, or (CANopenEditor's Python port writes them) the
    /// name of one, read with a warning.
    fn object_kind(
        &self,
        section: &Section<'a>,
        entry: &Entry<'a>,
    ) -> Result<ObjectKind, ParseError> {
        if let Some(kind) = parse_integer(entry.value)
            .and_then(|v| u8::try_from(v).ok())
            .and_then(ObjectKind::from_code)
        {
            return Ok(kind);
        }
        let named = OBJECT_KINDS
            .iter()
            .copied()
            .find(|k| k.name().eq_ignore_ascii_case(entry.value));
        let Some(kind) = named else {
            return Err(self.bad(
                section,
                entry,
                "an object code: 0x7 (VAR), 0x8 (ARRAY), 0x9 (RECORD), 0x2 (DOMAIN), 0x5 (DEFTYPE), 0x6 (DEFSTRUCT) or 0x0 (NULL)",
            ));
        };
        self.warn(
            entry.value,
            format!(
                "ObjectType= in [{}]: `{}` is the name of an object code, not a code; read as 0x{:X} ({kind})",
                section.name,
                entry.value,
                kind.code()
            ),
        );
        Ok(kind)
    }

    fn data_type(&self, section: &Section<'a>, entry: &Entry<'a>) -> Result<DataType, ParseError> {
        let Some(index) = parse_integer(entry.value).and_then(|v| u16::try_from(v).ok()) else {
            // CANopenEditor's Python port writes the CiA 301 name (`UNSIGNED32`) instead of the index;
            // a name says which type as plainly, so it is read with a warning.
            let named = STANDARD_TYPES
                .iter()
                .copied()
                .find(|t| t.cia_name().eq_ignore_ascii_case(entry.value));
            let Some(t) = named else {
                return Err(self.bad(section, entry, "a CiA 301 data type index like 0x0007"));
            };
            self.warn(
                entry.value,
                format!(
                    "DataType= in [{}]: `{}` is the name of data type 0x{:04X}, not its index; read as {t}",
                    section.name,
                    entry.value,
                    t.index()
                ),
            );
            return Ok(t);
        };
        if let Some(t) = DataType::from_index(index) {
            return Ok(t);
        }
        // An index that is no basic type: a complex or profile type (PDO parameter, identity, a
        // manufacturer structure; 0x0020-0x025F) or one no standard defines. The model has no structured
        // type for a single entry, so its bytes are a domain, as python-canopen and Lely take it too.
        let what = if (0x0020..=0x025F).contains(&index) {
            "a complex or profile data type"
        } else {
            "not a CiA 301 data type"
        };
        self.warn(
            entry.value,
            format!(
                "DataType= in [{}]: 0x{index:04X} is {what}; the entry is read as DOMAIN",
                section.name
            ),
        );
        Ok(DataType::Domain)
    }

    /// The value of `entry` as `data_type`, and whether it adds the node-ID (`$NODEID+…`, allowed when
    /// `node_id_allowed`). Empty text of a type whose values are not text is no value. Text that is no
    /// value of the type is no value either, with a warning: python-canopen skips such a default, limit or
    /// parameter value, and the entry is usable without it. A C integer suffix (`LL`, `U`: CANopenNode
    /// writes them) is dropped with a warning.
    fn typed(
        &self,
        section: &Section<'a>,
        entry: &Entry<'a>,
        data_type: DataType,
        node_id_allowed: bool,
    ) -> Option<Typed> {
        let text = entry.value;
        let textual = matches!(
            data_type,
            DataType::VisibleString
                | DataType::UnicodeString
                | DataType::OctetString
                | DataType::Domain
        );
        if text.is_empty() && !textual {
            return None;
        }
        let drop = |why: &str| {
            self.warn(
                text,
                format!(
                    "{}= in [{}]: {why}; {}",
                    entry.key,
                    section.name,
                    dropped(entry.key)
                ),
            );
            None
        };
        let integer =
            data_type.is_signed() || (data_type.is_unsigned() && data_type != DataType::Boolean);
        let (body, plus_node_id) = if textual {
            (text, false)
        } else {
            match split_node_id(text) {
                Some(split) => split,
                None => {
                    return drop(&format!(
                        "`{}` is not `$NODEID`, `$NODEID+offset` or `offset+$NODEID`",
                        shown(text)
                    ))
                }
            }
        };
        if plus_node_id {
            if !node_id_allowed {
                return drop(&format!(
                    "`{}` adds the node-ID, which a limit cannot",
                    shown(text)
                ));
            }
            if !integer {
                return drop(&format!(
                    "`{}` adds the node-ID to a {data_type}, and $NODEID is added to integers only",
                    shown(text)
                ));
            }
        }
        let body = match c_suffix(body).filter(|_| integer) {
            Some((number, suffix)) => {
                self.warn(
                    text,
                    format!(
                        "{}= in [{}]: the C suffix `{suffix}` of `{}` is dropped",
                        entry.key,
                        section.name,
                        shown(text)
                    ),
                );
                number
            }
            None => body,
        };
        match Value::parse_text(data_type, body) {
            Ok(value) => Some((value, plus_node_id)),
            Err(err) => drop(&err.to_string()),
        }
    }
}

/// What is left out when the value of `key` cannot be read: a default, a limit, or a current value
/// (`ParameterValue`, or the entry of an `[xxxxValue]` section).
fn dropped(key: &str) -> &'static str {
    if key.eq_ignore_ascii_case("DefaultValue") {
        "the default is dropped"
    } else if key.eq_ignore_ascii_case("LowLimit") || key.eq_ignore_ascii_case("HighLimit") {
        "the limit is dropped"
    } else {
        "the value is dropped"
    }
}

/// An integer with a C suffix (`U`, `L`, `LL`, `UL`, `ULL`, `LU`, `LLU` in any case), split into the
/// number and the suffix; `None` when `text` is no integer with such a suffix.
fn c_suffix(text: &str) -> Option<(&str, &str)> {
    const SUFFIXES: [&str; 7] = ["u", "l", "ll", "ul", "ull", "lu", "llu"];
    let body = text.trim_end_matches(['u', 'U', 'l', 'L']);
    let suffix = text.get(body.len()..)?;
    let valid = SUFFIXES.iter().any(|s| s.eq_ignore_ascii_case(suffix));
    (valid && parse_integer(body).is_some()).then_some((body, suffix))
}

/// Splits `$NODEID`, `$NODEID+offset` and `offset+$NODEID` (case-insensitive, blanks allowed) into the
/// offset and `true`; other text comes back unchanged with `false`. `None`: `$NODEID` in another form.
fn split_node_id(text: &str) -> Option<(&str, bool)> {
    const TOKEN: &[u8] = b"$NODEID";
    let Some(at) = text
        .as_bytes()
        .windows(TOKEN.len())
        .position(|w| w.eq_ignore_ascii_case(TOKEN))
    else {
        return Some((text, false));
    };
    let before = text.get(..at)?.trim_ascii();
    let after = text.get(at + TOKEN.len()..)?.trim_ascii();
    let offset = match (before.is_empty(), after.is_empty()) {
        (true, true) => "0",
        (true, false) => after.strip_prefix('+')?.trim_ascii(),
        (false, true) => before.strip_suffix('+')?.trim_ascii(),
        (false, false) => return None,
    };
    if offset.is_empty() {
        return None;
    }
    Some((offset, true))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_id_forms() {
        assert_eq!(split_node_id("$NODEID+0x180"), Some(("0x180", true)));
        assert_eq!(split_node_id("0x180+$NODEID"), Some(("0x180", true)));
        assert_eq!(split_node_id("$nodeid + 0x180"), Some(("0x180", true)));
        assert_eq!(split_node_id("$NodeId"), Some(("0", true)));
        assert_eq!(split_node_id("0x180"), Some(("0x180", false)));
        assert_eq!(split_node_id("$NODEID-1"), None);
        assert_eq!(split_node_id("1+$NODEID+2"), None);
        assert_eq!(split_node_id("$NODEID+"), None);
    }

    #[test]
    fn section_names() {
        assert_eq!(classify("1018"), Kind::Object(0x1018));
        assert_eq!(classify("1a00"), Kind::Object(0x1A00));
        assert_eq!(classify("1018sub1"), Kind::Sub(0x1018, 1));
        assert_eq!(classify("1018SUB1f"), Kind::Sub(0x1018, 0x1F));
        assert_eq!(classify("3010Sub0"), Kind::Sub(0x3010, 0));
        assert_eq!(classify("1018sub100"), Kind::Other);
        assert_eq!(classify("3004Name"), Kind::Names(0x3004));
        assert_eq!(classify("3004value"), Kind::Values(0x3004));
        assert_eq!(classify("3004ObjectLinks"), Kind::Other);
        assert_eq!(classify("fileinfo"), Kind::FileInfo);
        assert_eq!(classify("DeviceCommissioning"), Kind::Commissioning);
        assert_eq!(classify("A0"), Kind::Other);
        assert_eq!(classify("BEEF"), Kind::Object(0xBEEF));
        assert_eq!(classify("Tools"), Kind::Other);
        assert_eq!(classify("µµµµ"), Kind::Other);
    }

    #[test]
    fn positions_from_the_line_index_are_those_of_a_scan() {
        let text = "[A]\r\nkey=µ value\n\n  [B] ; x\nlast=€€\nend=";
        let ini = Ini::scan(text, "t").unwrap();
        for (offset, _) in text.char_indices().chain([(text.len(), ' ')]) {
            assert_eq!(
                ini.position(&text[offset..]),
                Position::of_offset(text.as_bytes(), offset),
                "{offset}"
            );
        }
        assert_eq!(ini.position(&text[12..]), Position { line: 2, column: 7 });
    }

    #[test]
    fn latin1_decodes_one_character_per_byte() {
        assert_eq!(decode(b"a\xB5b"), "a\u{B5}b");
        assert_eq!(decode(b"\xEF\xBB\xBFab"), "ab");
        assert_eq!(decode("µ".as_bytes()), "µ");
    }
}
