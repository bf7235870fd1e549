//! The EDS/DCF reader: a line scanner over the INI text (the INI structure of CiA 306-1 §4), then the
//! building of the description from the sections it found: `sections` reads the named sections,
//! `objects` the object and sub-object sections.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::ops::Range;

use crate::error::{LineIndex, ParseError, Position};
use crate::object::{ObjFlags, ObjectKind};
use crate::report::{Finding, Reading, SourceMap};
use crate::value::{parse_integer, Value};

mod objects;
mod sections;

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

/// The text after a key's `=` without its inline comment: from the first `;` that follows white
/// space (`DefaultValue=0x3ED ; prevent homing`, a tab before the `;` as well) to the end of the
/// line, as python-canopen reads EDS files (configparser with `inline_comment_prefixes=(';',)`:
/// such a prefix counts only after white space, Python's `str.isspace`). A `;` right after the
/// value (`1005;c`) or right after the `=` starts no comment: it is part of the value, which is
/// then no number (python-canopen drops it, and so does this reader, with a warning). Every key is
/// read so, as configparser reads them all: names and strings lose such a comment too; only the
/// lines of `[Comments]`, free text, are kept whole.
pub(crate) fn without_comment(value: &str) -> &str {
    let mut after_space = false;
    for (at, c) in value.char_indices() {
        if c == ';' && after_space {
            return &value[..at];
        }
        // Python's white space: Rust's, and the separators U+001C–U+001F.
        after_space = c.is_whitespace() || ('\u{1c}'..='\u{1f}').contains(&c);
    }
    value
}

/// `key=value`, both trimmed, as slices of the text.
struct Entry<'a> {
    key: &'a str,
    /// The value without its inline comment ([`without_comment`]).
    value: &'a str,
    /// The whole text after the `=`: a `[Comments]` line is free text, a `;` in it no comment.
    whole: &'a str,
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
            let whole = line[eq + 1..].trim_ascii();
            let value = without_comment(&line[eq + 1..]).trim_ascii();
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
            ini.entries.push(Entry { key, value, whole });
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

    /// `ObjFlags` (CiA 306 §4.6.3: bit 0 refuse write on download, bit 1 refuse read on scan): a
    /// 32-bit number. An empty value (`ObjFlags=`) or one that is no number (`ObjFlags=NV`, as some
    /// vendor tools write it) is read as no flags with a warning at the value, as python-canopen and
    /// CANopenEditor load such a file (and as the XDD reader reads an empty `objFlags`). `None` when
    /// the section gives none.
    fn object_flags(&self, section: &Section<'a>, entry: Option<&Entry<'a>>) -> Option<ObjFlags> {
        let e = entry?;
        match parse_integer(e.value).and_then(|v| u32::try_from(v).ok()) {
            Some(flags) => Some(ObjFlags::from_bits(flags)),
            None => {
                let what = if e.value.is_empty() {
                    " is empty".to_string()
                } else {
                    format!(": `{}` is no 32-bit number", shown(e.value))
                };
                self.warn(
                    e.value,
                    format!("ObjFlags= in [{}]{what}; read as no flags", section.name),
                );
                None
            }
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
    fn inline_comments_follow_white_space() {
        assert_eq!(without_comment("0x3ED ; prevent homing"), "0x3ED ");
        assert_eq!(without_comment("0x3ED\t; tab"), "0x3ED\t");
        assert_eq!(without_comment("$NODEID+0x180 ; c"), "$NODEID+0x180 ");
        assert_eq!(without_comment("1005;c"), "1005;c");
        assert_eq!(without_comment(";c"), ";c");
        assert_eq!(without_comment(" ; all comment"), " ");
        assert_eq!(without_comment("a;b ;c ; d"), "a;b ");
        assert_eq!(without_comment("µ\u{1f};x"), "µ\u{1f}");
        assert_eq!(without_comment("\u{a0};x"), "\u{a0}");
        let ini = Ini::scan("[A]\nk=0x10 ; c\nl=2;3\nm=\t;only\n", "t").unwrap();
        let values: Vec<&str> = ini.entries.iter().map(|e| e.value).collect();
        assert_eq!(values, ["0x10", "2;3", ""]);
        assert_eq!(
            ini.position(ini.entries[0].value),
            Position { line: 2, column: 3 }
        );
    }

    #[test]
    fn latin1_decodes_one_character_per_byte() {
        assert_eq!(decode(b"a\xB5b"), "a\u{B5}b");
        assert_eq!(decode(b"\xEF\xBB\xBFab"), "ab");
        assert_eq!(decode("µ".as_bytes()), "µ");
    }
}
