//! Writing a description back in the format it was read from without losing or adding anything the
//! model does not hold.
//!
//! The model holds what the project understands of a description; a file holds more: vendor
//! elements and keys, comments, the order and the spelling of its parts. A same-format rewrite
//! therefore does not write the model out afresh. It takes the original file and makes in it the
//! changes the model's edits make: the writer renders the model as read (the *base*) and as edited
//! (the *edited* text); every part where the two differ — a value, an attribute, a key, an element
//! or section added or removed — is changed at its place in the original, and nothing else is
//! touched. Parts are matched between the texts by their kind and identity among their siblings (an
//! object's index, a sub-index, a `uniqueID`, a language, a type name; else their order), so the
//! original's layout, comments and unknown parts stay as they were, and an unedited description
//! comes back byte for byte. What the writer would add that the original does not have (a default
//! it writes out) is not added unless an edit changes it.
//!
//! [`rewrite`] makes the changed file; [`unheld`] lists what of a file its model does not hold (the
//! parts `diff --all` compares).

mod ini;
mod tree;
mod xml;

use std::borrow::Cow;

use crate::device::DeviceDescription;
use crate::load::Format;
use tree::{align, Doc, Edits, Kind, Node};

/// Why a rewrite could not be made: a text is no well-formed file of its format, or the changes
/// could not be placed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct CarryError(String);

/// The original file's bytes with the changes that turn `base` into `edited` made in them; both are
/// texts the writer of `format`'s family made (an EDS and a DCF are one family). Returns the bytes
/// in the original's character encoding (and byte-order mark). Where a character an edit brings
/// has no place in that encoding, an XML file gets a character reference, an EDS is written as
/// UTF-8.
pub fn rewrite(
    original: &[u8],
    format: Format,
    base: &str,
    edited: &str,
) -> Result<Vec<u8>, CarryError> {
    if base == edited {
        return Ok(original.to_vec());
    }
    let source = Source::decode(original, format)?;
    let text = rewrite_text(&source.text, format, base, edited)?;
    Ok(source.encode(&text))
}

/// A description written in `target` format: the bytes, and why the original's parts could not be
/// kept when they were not.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Written {
    /// The file.
    pub bytes: Vec<u8>,
    /// `Err` with the reason when the file is the writer's rendering of the model alone.
    pub kept: Result<(), String>,
}

/// The writer's rendering of `devices` in `format` (an ESI holds them all; the other formats the
/// first).
pub fn render(format: Format, devices: &[DeviceDescription]) -> String {
    match (format, devices.first()) {
        (Format::Esi, _) => crate::esi::write_all(devices),
        (_, None) => String::new(),
        (Format::Xdd, Some(d)) => crate::xdd::write(d),
        (Format::Eds, Some(d)) => crate::eds::write_eds(d),
        (Format::Dcf, Some(d)) => crate::eds::write_dcf(d),
    }
}

/// Whether the writer of one format writes the other too (the EDS writer writes DCFs).
pub fn same_family(a: Format, b: Format) -> bool {
    let family = |f| match f {
        Format::Dcf => Format::Eds,
        other => other,
    };
    family(a) == family(b)
}

/// `edited` written in `target`, keeping what of `original` (a file in `input` whose model is
/// `as_read`) the model does not hold when both formats are of one family: [`rewrite`] with the
/// renderings of `as_read` (in `input`) and of `edited` (in `target`). That file is taken when it
/// reads back as `edited` at least as well as the writer's rendering does — every difference of the
/// one is a difference of the other —, else the rendering, with the reason.
pub fn write(
    original: &[u8],
    input: Format,
    as_read: &[DeviceDescription],
    target: Format,
    edited: &[DeviceDescription],
) -> Written {
    let plain = render(target, edited);
    let fallback = |why: String| Written {
        bytes: plain.as_bytes().to_vec(),
        kept: Err(why),
    };
    if !same_family(input, target) {
        return fallback(format!("{input} is no {target}"));
    }
    let base = render(input, as_read);
    let bytes = match rewrite(original, input, &base, &plain) {
        Ok(bytes) => bytes,
        Err(e) => return fallback(e.to_string()),
    };
    let differences = |text: &[u8]| -> Result<Vec<String>, String> {
        let back = crate::load::read_bytes(text, "written", target).map_err(|e| e.to_string())?;
        let mut out = Vec::new();
        for pairing in crate::diff::pair_devices(edited, &back) {
            match pairing {
                crate::diff::Pairing::Both(i, j) => out.extend(
                    crate::diff::diff_devices(&edited[i], &back[j])
                        .iter()
                        .map(|d| format!("{i}: {d}")),
                ),
                other => out.push(format!("{other:?}")),
            }
        }
        Ok(out)
    };
    match (differences(&bytes), differences(plain.as_bytes())) {
        (Ok(k), Ok(p)) if k.iter().all(|d| p.contains(d)) => Written {
            bytes,
            kept: Ok(()),
        },
        (Ok(k), _) => fallback(format!(
            "it would read back otherwise: {}",
            k.into_iter().next().unwrap_or_default()
        )),
        (Err(e), _) => fallback(format!("it would not read back: {e}")),
    }
}

/// [`rewrite`] on decoded text.
pub fn rewrite_text(
    original: &str,
    format: Format,
    base: &str,
    edited: &str,
) -> Result<String, CarryError> {
    if base == edited {
        return Ok(original.to_string());
    }
    let o = parse(original, format)?;
    let w0 = parse(base, format)?;
    let w1 = parse(edited, format)?;
    let mut m = Merge {
        o: &o,
        w0: &w0,
        w1: &w1,
        edits: Edits::default(),
        unit: indent_unit(&o),
        w1_unit: indent_unit(&w1),
        eol: o.eol(),
    };
    m.node(&o.root, &w0.root, &w1.root);
    m.edits.apply(original).map_err(CarryError)
}

/// One part of a file its model does not hold: a path of names from the root (`EtherCATInfo/
/// Descriptions/Devices/Device[1]/Info`, `[FileInfo] LastEDS`, `…/@Physics`) and its text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Unheld {
    /// Where it is.
    pub path: String,
    /// Its text: an attribute's value; a part's text as written.
    pub text: String,
}

/// What of `original` (a file in `format`) the writer's rendering of its model, `base`, does not
/// have: every element, comment, section or key with no partner there (with all it holds) and
/// every attribute of a partnered element that the rendering lacks, in file order.
pub fn unheld(original: &str, format: Format, base: &str) -> Result<Vec<Unheld>, CarryError> {
    let o = parse(original, format)?;
    let w = parse(base, format)?;
    let mut out = Vec::new();
    unheld_in(&o, &o.root, &w.root, "", &mut out);
    Ok(out)
}

/// What of the file `bytes` (in `format`, read as `devices`) its model does not hold: [`unheld`]
/// with the writer's rendering of `devices`.
pub fn unheld_in_file(
    bytes: &[u8],
    format: Format,
    devices: &[DeviceDescription],
) -> Result<Vec<Unheld>, CarryError> {
    let source = Source::decode(bytes, format)?;
    unheld(&source.text, format, &render(format, devices))
}

fn unheld_in(o: &Doc<'_>, on: &Node, wn: &Node, path: &str, out: &mut Vec<Unheld>) {
    if let (Some(oe), Some(we)) = (on.element(), wn.element()) {
        for a in &oe.attrs {
            if !we.attrs.iter().any(|b| b.name == a.name) {
                out.push(Unheld {
                    path: format!("{path}/@{}", a.name),
                    text: o.text[a.value.clone()].to_string(),
                });
            }
        }
    }
    let pairs = align(&on.children, &wn.children);
    let mut seen: std::collections::HashMap<(&str, &str), usize> = Default::default();
    for (c, pair) in on.children.iter().zip(pairs) {
        let n = seen.entry((c.name.as_str(), c.key.as_str())).or_default();
        *n += 1;
        let step = step(c, *n, o);
        let child_path = if path.is_empty() {
            step
        } else if matches!(on.kind, Kind::Section { .. }) {
            format!("{path} {step}")
        } else {
            format!("{path}/{step}")
        };
        match pair {
            Some(j) => unheld_in(o, c, &wn.children[j], &child_path, out),
            None => out.push(Unheld {
                path: child_path,
                text: match &c.kind {
                    Kind::Entry { value } => o.text[value.clone()].to_string(),
                    _ => o.raw(c).trim_end().to_string(),
                },
            }),
        }
    }
}

/// A node's step in a path: its name as written, its key or number where siblings share the name.
fn step(n: &Node, nth: usize, o: &Doc<'_>) -> String {
    let written = match &n.kind {
        Kind::Element(e) => e.qname.clone(),
        Kind::Section { body } => o.text[n.span.start..*body].trim().to_string(),
        Kind::Entry { .. } => {
            let line = o.raw(n);
            line.split('=').next().unwrap_or("").trim().to_string()
        }
        _ => n.name.clone(),
    };
    match (n.key.is_empty(), &n.kind) {
        (_, Kind::Opaque) => format!("#comment[{nth}]"),
        (true, _) if nth == 1 => written,
        (true, _) => format!("{written}[{nth}]"),
        (false, _) if nth == 1 => format!("{written}[{}]", n.key),
        (false, _) => format!("{written}[{}][{nth}]", n.key),
    }
}

fn parse(text: &str, format: Format) -> Result<Doc<'_>, CarryError> {
    match format {
        Format::Eds | Format::Dcf => Ok(ini::parse(text)),
        Format::Esi | Format::Xdd => xml::parse(text).map_err(CarryError),
    }
}

/// The unit of indentation of an XML file: what a child's indentation adds to its parent's at the
/// first place the file shows both; a tab when it shows none.
fn indent_unit(o: &Doc<'_>) -> String {
    fn find(o: &Doc<'_>, n: &Node) -> Option<String> {
        let parent = o.indent_before(n.span.start);
        for c in n.children.iter().filter(|c| c.element().is_some()) {
            let child = o.indent_before(c.span.start);
            if child.len() > parent.len()
                && child.starts_with(parent)
                && o.text[..n.span.start].ends_with(parent)
            {
                return Some(child[parent.len()..].to_string());
            }
            if let Some(u) = find(o, c) {
                return Some(u);
            }
        }
        None
    }
    o.root
        .children
        .iter()
        .find_map(|c| find(o, c))
        .unwrap_or_else(|| "\t".to_string())
}

struct Merge<'m, 'a> {
    o: &'m Doc<'a>,
    w0: &'m Doc<'a>,
    w1: &'m Doc<'a>,
    edits: Edits,
    /// The original's unit of indentation, and the edited text's.
    unit: String,
    w1_unit: String,
    eol: &'static str,
}

impl Merge<'_, '_> {
    /// Makes in `o` the changes from `b` (the base's part matching `o`) to `e` (the edited one).
    fn node(&mut self, o: &Node, b: &Node, e: &Node) {
        if self.w0.raw(b) == self.w1.raw(e) {
            return;
        }
        match (&o.kind, &b.kind, &e.kind) {
            (Kind::Entry { value: ov }, Kind::Entry { value: bv }, Kind::Entry { value: ev }) => {
                let (bt, et) = (&self.w0.text[bv.clone()], &self.w1.text[ev.clone()]);
                if bt != et {
                    self.edits.replace(ov.clone(), et);
                }
                return;
            }
            (Kind::Element(_), Kind::Element(_), Kind::Element(_)) if self.element(o, b, e) => {
                return;
            }
            _ => {}
        }
        self.children(o, b, e);
    }

    /// An element's own changes: its attributes, and its text when it holds no element. True when
    /// the renderings hold no element in it (its text is done; nothing is left to do inside).
    fn element(&mut self, o: &Node, b: &Node, e: &Node) -> bool {
        let (oe, be, ee) = (
            o.element().expect("an element"),
            b.element().expect("an element"),
            e.element().expect("an element"),
        );
        for a in &ee.attrs {
            let new = &self.w1.text[a.value.clone()];
            let old = be
                .attrs
                .iter()
                .find(|x| x.name == a.name)
                .map(|x| &self.w0.text[x.value.clone()]);
            if old == Some(new) {
                continue;
            }
            match oe.attrs.iter().find(|x| x.name == a.name) {
                Some(x) => {
                    let value = if x.quote == b'\'' {
                        Cow::Owned(new.replace('\'', "&apos;"))
                    } else {
                        Cow::Borrowed(new)
                    };
                    self.edits.replace(x.value.clone(), value);
                }
                None => self.edits.insert(
                    oe.attrs_end,
                    format!(" {}", &self.w1.text[a.span.clone()].trim_start()),
                ),
            }
        }
        for a in &be.attrs {
            if !ee.attrs.iter().any(|x| x.name == a.name) {
                if let Some(x) = oe.attrs.iter().find(|x| x.name == a.name) {
                    self.edits.replace(x.span.clone(), "");
                }
            }
        }
        if b.is_leaf() && e.is_leaf() {
            let text = |d: &Doc<'_>, n: &Node| {
                n.element()
                    .and_then(|x| x.content.clone())
                    .map(|r| d.text[r].to_string())
                    .unwrap_or_default()
            };
            let (bt, et) = (text(self.w0, b), text(self.w1, e));
            if bt != et {
                // The content goes whole, elements the original had in it (mixed content) too;
                // the start tag stays, with what the model does not hold in it.
                match &oe.content {
                    Some(r) => self.edits.replace(r.clone(), et),
                    None => {
                        let close = oe.start_tag.end - 2..oe.start_tag.end;
                        self.edits.replace(close, format!(">{et}</{}>", oe.qname));
                    }
                }
            }
            return true;
        }
        false
    }

    /// The children's changes: partnered ones changed in place, the base's without an edited
    /// partner removed, the edited ones without a base partner (or whose base partner the original
    /// lacks) added after the original's part that comes before them.
    fn children(&mut self, o: &Node, b: &Node, e: &Node) {
        let b_to_e = align(&b.children, &e.children);
        let b_to_o = align(&b.children, &o.children);
        let mut e_to_b = vec![None; e.children.len()];
        for (i, j) in b_to_e.iter().enumerate() {
            if let Some(j) = j {
                e_to_b[*j] = Some(i);
            }
        }
        for (i, j) in b_to_e.iter().enumerate() {
            if j.is_none() {
                if let Some(k) = b_to_o[i] {
                    self.remove(&o.children[k]);
                }
            }
        }
        // The original's parts the base has no partner for (which the model does not hold): an
        // edited part of the same name and key takes one's place instead of coming beside it.
        let mut o_has_b = vec![false; o.children.len()];
        for k in b_to_o.iter().flatten() {
            o_has_b[*k] = true;
        }
        let mut unheld = align(&e.children, &o.children);
        for k in unheld.iter_mut() {
            if k.is_some_and(|k| o_has_b[k]) {
                *k = None;
            }
        }
        let mut anchor: Option<&Node> = None;
        let mut added = String::new();
        let empty_tag = o.element().is_some_and(|x| x.content.is_none());
        for (j, ec) in e.children.iter().enumerate() {
            let partner = e_to_b[j].map(|i| (i, b_to_o[i]));
            match partner {
                Some((i, Some(k))) => {
                    self.node(&o.children[k], &b.children[i], ec);
                    anchor = Some(&o.children[k]);
                }
                Some((i, None)) if self.w0.raw(&b.children[i]) == self.w1.raw(ec) => {}
                _ if unheld[j].is_some() => {
                    let k = unheld[j].expect("an unheld part");
                    self.take_place(&o.children[k], ec);
                    anchor = Some(&o.children[k]);
                }
                _ => {
                    if empty_tag {
                        added.push_str(&self.addition(ec, o, None));
                    } else {
                        let (at, text) = self.placed(ec, o, anchor);
                        self.edits.insert(at, text);
                    }
                }
            }
        }
        if empty_tag && !added.is_empty() {
            let oe = o.element().expect("an element");
            let indent = self.o.indent_before(o.span.start);
            let close = oe.start_tag.end - 2..oe.start_tag.end;
            self.edits.replace(
                close,
                format!(">{added}{}{indent}</{}>", self.eol, oe.qname),
            );
        }
    }

    /// `ec` (an edited part) in the place of `on`, a part of the original the model does not hold: a
    /// key's value, an element whole.
    fn take_place(&mut self, on: &Node, ec: &Node) {
        match (&on.kind, &ec.kind) {
            (Kind::Entry { value }, Kind::Entry { value: ev }) => {
                let text = self.w1.text[ev.clone()].to_string();
                self.edits.replace(value.clone(), text);
            }
            _ => {
                let text = self.reindented(ec, on.span.start);
                self.edits.replace(on.span.clone(), text);
            }
        }
    }

    /// Where and as what text `ec` (an edited part) goes into `o`: after `anchor`, else at the start
    /// of `o`'s content.
    fn placed(&self, ec: &Node, o: &Node, anchor: Option<&Node>) -> (usize, String) {
        let at = match (anchor, &o.kind) {
            (Some(a), _) => a.span.end,
            (None, Kind::Section { body }) => *body,
            (None, Kind::Element(x)) => x.start_tag.end,
            (None, _) => o
                .children
                .iter()
                .find(|c| matches!(c.kind, Kind::Section { .. }))
                .map_or(self.o.text.len(), |c| c.span.start),
        };
        (at, self.addition(ec, o, Some(at)))
    }

    /// The text of `ec` as it goes into `o` at `at`: an INI part as written (on a line of its own),
    /// an element on a line of its own, indented as `o`'s children are.
    fn addition(&self, ec: &Node, o: &Node, at: Option<usize>) -> String {
        if ec.element().is_none() {
            let raw = self.w1.raw(ec);
            let mut text = String::new();
            if let Some(at) = at {
                if at > 0 && !self.o.text[..at].ends_with('\n') {
                    text.push_str(self.eol);
                }
            }
            text.push_str(&eol(raw, self.eol));
            if !text.ends_with('\n') {
                text.push_str(self.eol);
            }
            return text;
        }
        let indent = self.child_indent(o);
        format!("{}{indent}{}", self.eol, self.reindent_to(ec, &indent))
    }

    /// `o`'s children's indentation: its first element child's, else its own and one unit more.
    fn child_indent(&self, o: &Node) -> String {
        if let Some(c) = o.children.iter().find(|c| c.element().is_some()) {
            let i = self.o.indent_before(c.span.start);
            if !i.is_empty() {
                return i.to_string();
            }
        }
        format!("{}{}", self.o.indent_before(o.span.start), self.unit)
    }

    /// `e`'s text for the original's place `at`, its lines re-indented from the edited text's
    /// indentation to the original's there.
    fn reindented(&self, e: &Node, at: usize) -> String {
        let indent = self.o.indent_before(at).to_string();
        self.reindent_to(e, &indent)
    }

    fn reindent_to(&self, e: &Node, indent: &str) -> String {
        let from = self.w1.indent_before(e.span.start);
        let raw = self.w1.raw(e);
        let mut out = String::with_capacity(raw.len());
        for (n, line) in raw.split_inclusive('\n').enumerate() {
            if n > 0 {
                match line.strip_prefix(from) {
                    Some(mut rest) => {
                        out.push_str(indent);
                        // Each further level of the edited text's indentation is one of the
                        // original's.
                        while let Some(r) = rest
                            .strip_prefix(self.w1_unit.as_str())
                            .filter(|_| !self.w1_unit.is_empty())
                        {
                            out.push_str(&self.unit);
                            rest = r;
                        }
                        out.push_str(rest);
                    }
                    None => out.push_str(line),
                }
            } else {
                out.push_str(line);
            }
        }
        eol(&out, self.eol).into_owned()
    }

    /// Removes `n` from the original with the white space before it on its line (and that line's
    /// start, when it stood alone there).
    fn remove(&mut self, n: &Node) {
        let text = self.o.text;
        let mut start = n.span.start;
        let indent = self.o.indent_before(start);
        if !indent.is_empty() || (start > 0 && text.as_bytes()[start - 1] == b'\n') {
            start -= indent.len();
            if n.element().is_some() || matches!(n.kind, Kind::Opaque) {
                let head = &text[..start];
                if let Some(h) = head.strip_suffix('\n') {
                    start = h.strip_suffix('\r').unwrap_or(h).len();
                }
            }
        }
        self.edits.replace(start..n.span.end, "");
    }
}

/// `text` with its line ends made `eol`.
fn eol<'t>(text: &'t str, eol: &str) -> Cow<'t, str> {
    if eol == "\r\n" {
        if text.contains('\n') && !text.contains("\r\n") {
            return Cow::Owned(text.replace('\n', "\r\n"));
        }
    } else if text.contains("\r\n") {
        return Cow::Owned(text.replace("\r\n", "\n"));
    }
    Cow::Borrowed(text)
}

/// A file's decoded text and how to encode it back.
struct Source {
    text: String,
    encoding: Encoding,
}

enum Encoding {
    Utf8 {
        bom: bool,
    },
    Utf16 {
        big_endian: bool,
    },
    /// ISO-8859-1 read one character per byte (an EDS that is no UTF-8).
    Latin1,
    Other(&'static encoding_rs::Encoding),
}

impl Source {
    fn decode(bytes: &[u8], format: Format) -> Result<Source, CarryError> {
        let bom = bytes.starts_with(b"\xEF\xBB\xBF");
        match format {
            Format::Eds | Format::Dcf => {
                let body = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
                Ok(match std::str::from_utf8(body) {
                    Ok(t) => Source {
                        text: t.to_string(),
                        encoding: Encoding::Utf8 { bom },
                    },
                    Err(_) => Source {
                        text: body.iter().map(|&b| char::from(b)).collect(),
                        encoding: Encoding::Latin1,
                    },
                })
            }
            Format::Esi | Format::Xdd => {
                let text = crate::xml::decode(bytes, "original")
                    .map_err(|e| CarryError(e.to_string()))?
                    .into_owned();
                let encoding = match encoding_rs::Encoding::for_bom(bytes) {
                    Some((e, _)) if e == encoding_rs::UTF_16BE => {
                        Encoding::Utf16 { big_endian: true }
                    }
                    Some((e, _)) if e == encoding_rs::UTF_16LE => {
                        Encoding::Utf16 { big_endian: false }
                    }
                    Some(_) => Encoding::Utf8 { bom: true },
                    None => match crate::xml::declared_encoding(bytes)
                        .and_then(|l| encoding_rs::Encoding::for_label(l.as_bytes()))
                    {
                        Some(e) if e != encoding_rs::UTF_8 => Encoding::Other(e),
                        _ => Encoding::Utf8 { bom: false },
                    },
                };
                Ok(Source { text, encoding })
            }
        }
    }

    fn encode(&self, text: &str) -> Vec<u8> {
        match &self.encoding {
            Encoding::Utf8 { bom } => {
                let mut out = Vec::with_capacity(text.len() + 3);
                if *bom {
                    out.extend_from_slice(b"\xEF\xBB\xBF");
                }
                out.extend_from_slice(text.as_bytes());
                out
            }
            Encoding::Utf16 { big_endian } => {
                let mut out = if *big_endian {
                    vec![0xFE, 0xFF]
                } else {
                    vec![0xFF, 0xFE]
                };
                for u in text.encode_utf16() {
                    let b = if *big_endian {
                        u.to_be_bytes()
                    } else {
                        u.to_le_bytes()
                    };
                    out.extend_from_slice(&b);
                }
                out
            }
            Encoding::Latin1 => match text
                .chars()
                .map(|c| u8::try_from(u32::from(c)).ok())
                .collect::<Option<Vec<u8>>>()
            {
                Some(bytes) => bytes,
                None => text.as_bytes().to_vec(),
            },
            Encoding::Other(e) => e.encode(text).0.into_owned(),
        }
    }
}

#[cfg(test)]
mod tests;
