//! The XML walk the ESI and XDD readers share: a [`Document`] (the decoded text and its name, which turns
//! byte offsets into the line:column of errors and warnings and collects the warnings) and a [`Cursor`]
//! over it that answers the document's content one [`Node`] at a time.
//!
//! The cursor is a thin layer over quick-xml's `Reader` (with end-tag names checked). It adds what both
//! readers need and quick-xml leaves out:
//!
//! - byte offsets into the decoded text for every node, and for every attribute's name and value;
//! - an empty-element tag `<a/>` answered as a [`Node::Start`] followed by a [`Node::End`] at the same
//!   offset, so readers handle one kind of element;
//! - well-formedness errors as [`ParseError`]s (`malformed XML: …` at the place quick-xml names);
//! - text with its line ends normalised (XML 1.0 §2.11), attribute values unescaped, with or without
//!   attribute-value normalisation (XML 1.0 §3.3.3), and references to the five predefined entities and
//!   to characters resolved.
//!
//! What an element means, which text is kept and which messages name a wrong value stay with each reader.
//! The cursor keeps no stack of names and sets no limit on depth: memory follows the input's size.

use std::borrow::Cow;
use std::cell::RefCell;

use quick_xml::escape::EscapeError;
use quick_xml::events::attributes::AttrError;
use quick_xml::events::{BytesCData, BytesRef, BytesStart, BytesText, Event};
use quick_xml::Reader;

use crate::dict::Address;
use crate::error::{LineIndex, ParseError, Position};
use crate::report::Finding;

/// A decoded XML document and the name it is known by: where each byte offset is, and the reader's
/// warnings about it.
pub(crate) struct Document<'a> {
    text: &'a str,
    name: &'a str,
    lines: LineIndex,
    findings: RefCell<Vec<Finding>>,
}

impl<'a> Document<'a> {
    /// The document `text` (already decoded), named `name` in errors.
    pub(crate) fn new(text: &'a str, name: &'a str) -> Document<'a> {
        Document {
            text,
            name,
            lines: LineIndex::new(text.as_bytes()),
            findings: RefCell::new(Vec::new()),
        }
    }

    /// The whole text.
    pub(crate) fn text(&self) -> &'a str {
        self.text
    }

    /// The line and column of byte `offset` (a column counts characters).
    pub(crate) fn position(&self, offset: usize) -> Position {
        self.lines.position(self.text.as_bytes(), offset)
    }

    /// An error at byte `offset`.
    pub(crate) fn error(&self, offset: usize, message: impl Into<String>) -> ParseError {
        ParseError::new(self.name, self.position(offset), message)
    }

    /// Records a warning at byte `offset`.
    pub(crate) fn warn(&self, offset: usize, message: impl Into<String>) {
        let f = Finding::warning(self.position(offset), message);
        self.findings.borrow_mut().push(f);
    }

    /// Records a warning at byte `offset` about the dictionary entry `address`.
    pub(crate) fn warn_about(&self, offset: usize, address: Address, message: impl Into<String>) {
        let f = Finding::warning(self.position(offset), message).at(address);
        self.findings.borrow_mut().push(f);
    }

    /// The warnings recorded so far, in the order they were recorded.
    pub(crate) fn take_findings(&self) -> Vec<Finding> {
        self.findings.take()
    }

    /// The byte offset of `slice` in the text, when it is a part of it.
    fn offset_of(&self, slice: &[u8]) -> Option<usize> {
        let base = self.text.as_ptr() as usize;
        let p = slice.as_ptr() as usize;
        (p >= base && p + slice.len() <= base + self.text.len()).then(|| p - base)
    }

    /// The part of the text that `slice` is, with its offset; `slice` itself at `fallback` when it is
    /// no part of the text.
    fn borrow(&self, slice: &[u8], fallback: usize) -> (usize, Cow<'a, str>) {
        if let Some(o) = self.offset_of(slice) {
            if let Some(s) = self.text.get(o..o + slice.len()) {
                return (o, Cow::Borrowed(s));
            }
        }
        (
            fallback,
            Cow::Owned(String::from_utf8_lossy(slice).into_owned()),
        )
    }
}

/// One step of the walk.
pub(crate) enum Node<'a> {
    /// A start tag, or an empty-element tag (then the next node is its [`Node::End`]).
    Start(Element<'a>),
    /// The end of the innermost open element, at the offset of its end tag (of the empty-element tag).
    End {
        /// Byte offset of `</` (of the `<` of an empty-element tag).
        offset: usize,
    },
    /// Character data between tags, with the offset of its first byte.
    Text(Text<'a>, usize),
    /// A CDATA section, its content as written, with the offset of `<![CDATA[`.
    CData(Cow<'a, str>, usize),
    /// A reference `&name;` or `&#…;` in text, with the offset of its `&`.
    Ref(Reference<'a>, usize),
    /// The end of the document. The cursor does not check that every element was closed: quick-xml
    /// stops at the end of the text, so readers say what is open.
    Eof,
}

/// A start tag.
pub(crate) struct Element<'a> {
    start: BytesStart<'a>,
    offset: usize,
    doc: &'a Document<'a>,
}

impl<'a> Element<'a> {
    /// Byte offset of the tag's `<`.
    pub(crate) fn offset(&self) -> usize {
        self.offset
    }

    /// The name as written, with its namespace prefix (`q1:parameter`).
    pub(crate) fn name(&self) -> &[u8] {
        self.start.name().into_inner()
    }

    /// The name without its namespace prefix (`q1:parameter` → `parameter`).
    pub(crate) fn local_name(&self) -> &[u8] {
        self.start.local_name().into_inner()
    }

    /// The attributes in the order written. A syntax error (a missing quote, a repeated name) ends the
    /// list with an `Err`.
    pub(crate) fn attributes(&self) -> impl Iterator<Item = Result<Attribute<'a>, AttrError>> + '_ {
        let doc = self.doc;
        let offset = self.offset;
        self.start.attributes().map(move |a| {
            let a = a?;
            let (_, key) = doc.borrow(a.key.local_name().into_inner(), offset);
            let (name_offset, name) = doc.borrow(a.key.as_ref(), offset);
            let (value_offset, raw) = doc.borrow(&a.value, offset);
            Ok(Attribute {
                key,
                name,
                name_offset,
                raw,
                value_offset,
            })
        })
    }
}

/// An attribute of a start tag.
pub(crate) struct Attribute<'a> {
    key: Cow<'a, str>,
    name: Cow<'a, str>,
    name_offset: usize,
    raw: Cow<'a, str>,
    value_offset: usize,
}

impl<'a> Attribute<'a> {
    /// The name without its namespace prefix (`xsi:type` → `type`).
    pub(crate) fn key(&self) -> &[u8] {
        self.key.as_bytes()
    }

    /// The name as written, with its namespace prefix.
    pub(crate) fn name(&self) -> &[u8] {
        self.name.as_bytes()
    }

    /// Byte offset of the attribute's name as written (its prefix, if any).
    pub(crate) fn name_offset(&self) -> usize {
        self.name_offset
    }

    /// Byte offset of the value's first character (after the quote).
    pub(crate) fn value_offset(&self) -> usize {
        self.value_offset
    }

    /// The value with its references resolved; tabs and line ends stay as written.
    pub(crate) fn value(&self) -> Result<Cow<'a, str>, EscapeError> {
        unescape(self.raw.clone())
    }

    /// The value as XML 1.0 §3.3.3 normalises it: literal tabs and line ends become spaces, then the
    /// references are resolved (so `&#10;` stays a line end).
    pub(crate) fn normalized_value(&self) -> Result<Cow<'a, str>, EscapeError> {
        let raw = self.raw.clone();
        if !raw.contains(['\t', '\n', '\r']) {
            return unescape(raw);
        }
        unescape(Cow::Owned(
            raw.replace("\r\n", " ").replace(['\t', '\n', '\r'], " "),
        ))
    }
}

fn unescape(raw: Cow<'_, str>) -> Result<Cow<'_, str>, EscapeError> {
    match raw {
        Cow::Borrowed(s) => quick_xml::escape::unescape(s),
        Cow::Owned(s) => quick_xml::escape::unescape(&s).map(|t| Cow::Owned(t.into_owned())),
    }
}

/// Character data between tags.
pub(crate) struct Text<'a>(BytesText<'a>);

impl<'a> Text<'a> {
    /// True when the text is white space only (layout between tags).
    pub(crate) fn is_blank(&self) -> bool {
        self.0.iter().all(u8::is_ascii_whitespace)
    }

    /// The text with CR LF and lone CR read as LF (XML 1.0 §2.11).
    pub(crate) fn content(&self) -> Cow<'a, str> {
        match self.0.xml10_content() {
            Ok(s) => s,
            // The reader runs over a `str`, so the text is UTF-8 and this is not reached.
            Err(_) => {
                Cow::Owned(normalize_line_ends(String::from_utf8_lossy(&self.0)).into_owned())
            }
        }
    }
}

/// A reference in text.
pub(crate) struct Reference<'a>(BytesRef<'a>);

impl Reference<'_> {
    /// What is between `&` and `;`.
    pub(crate) fn name(&self) -> Cow<'_, str> {
        String::from_utf8_lossy(self.0.as_ref())
    }

    /// The character the reference stands for: a character reference, or one of the five predefined
    /// entities. `Ok(None)` for any other entity; `Err` for a character reference that names no
    /// character.
    pub(crate) fn resolve(&self) -> Result<Option<char>, quick_xml::errors::Error> {
        match self.0.resolve_char_ref() {
            Ok(Some(c)) => Ok(Some(c)),
            Ok(None) => Ok(super::predefined_entity(self.0.as_ref())),
            Err(e) => Err(e),
        }
    }
}

/// Line ends of a CDATA section read as text reads them (CR LF and lone CR as LF).
pub(crate) fn normalize_line_ends(text: Cow<'_, str>) -> Cow<'_, str> {
    if !text.contains('\r') {
        return text;
    }
    Cow::Owned(text.replace("\r\n", "\n").replace('\r', "\n"))
}

/// The walk over one [`Document`].
pub(crate) struct Cursor<'a> {
    doc: &'a Document<'a>,
    reader: Reader<&'a [u8]>,
    /// The offset of an empty-element tag whose [`Node::End`] comes next.
    pending_end: Option<usize>,
}

impl<'a> Cursor<'a> {
    /// A cursor at the start of `doc`.
    pub(crate) fn new(doc: &'a Document<'a>) -> Cursor<'a> {
        let mut reader = Reader::from_str(doc.text());
        reader.config_mut().check_end_names = true;
        Cursor {
            doc,
            reader,
            pending_end: None,
        }
    }

    /// The next node; declarations, processing instructions, comments and the DOCTYPE are skipped.
    /// Text that is not well-formed XML is an error `malformed XML: …` where quick-xml finds it.
    pub(crate) fn next(&mut self) -> Result<Node<'a>, ParseError> {
        if let Some(offset) = self.pending_end.take() {
            return Ok(Node::End { offset });
        }
        loop {
            let before = usize::try_from(self.reader.buffer_position()).unwrap_or(usize::MAX);
            let event = match self.reader.read_event() {
                Ok(e) => e,
                Err(e) => {
                    let at = usize::try_from(self.reader.error_position()).unwrap_or(before);
                    return Err(self.doc.error(at, format!("malformed XML: {e}")));
                }
            };
            return Ok(match event {
                Event::Start(e) => Node::Start(self.element(e, before)),
                Event::Empty(e) => {
                    let element = self.element(e, before);
                    self.pending_end = Some(element.offset);
                    Node::Start(element)
                }
                Event::End(_) => Node::End { offset: before },
                Event::Text(t) => Node::Text(Text(t), before),
                Event::CData(t) => Node::CData(cdata(t), before),
                Event::GeneralRef(r) => Node::Ref(Reference(r), before),
                Event::Eof => Node::Eof,
                Event::Decl(_) | Event::PI(_) | Event::Comment(_) | Event::DocType(_) => continue,
            });
        }
    }

    fn element(&self, start: BytesStart<'a>, before: usize) -> Element<'a> {
        let offset = self
            .doc
            .offset_of(start.name().as_ref())
            .map_or(before, |o| o.saturating_sub(1));
        Element {
            start,
            offset,
            doc: self.doc,
        }
    }
}

fn cdata(t: BytesCData<'_>) -> Cow<'_, str> {
    match t.into_inner() {
        Cow::Borrowed(b) => String::from_utf8_lossy(b),
        Cow::Owned(b) => Cow::Owned(String::from_utf8_lossy(&b).into_owned()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every node of `text` in a short notation, with its offset.
    fn walk(text: &str) -> Result<Vec<String>, ParseError> {
        let doc = Document::new(text, "t.xml");
        let mut cursor = Cursor::new(&doc);
        let mut out = Vec::new();
        loop {
            out.push(match cursor.next()? {
                Node::Start(e) => format!(
                    "<{}>@{} local={}",
                    String::from_utf8_lossy(e.name()),
                    e.offset(),
                    String::from_utf8_lossy(e.local_name())
                ),
                Node::End { offset } => format!("</>@{offset}"),
                Node::Text(t, at) if t.is_blank() => format!("blank@{at}"),
                Node::Text(t, at) => format!("text {:?}@{at}", t.content()),
                Node::CData(t, at) => format!("cdata {t:?}@{at}"),
                Node::Ref(r, at) => format!("ref {} {:?}@{at}", r.name(), r.resolve().ok()),
                Node::Eof => return Ok(out),
            });
        }
    }

    #[test]
    fn nodes_come_with_their_offsets_and_an_empty_tag_ends_where_it_starts() {
        let nodes =
            walk("<?xml version=\"1.0\"?>\n<q:a>x&amp;&#x20AC;&bogus;<b/><![CDATA[c\r\nd]]></q:a>")
                .unwrap();
        assert_eq!(
            nodes,
            [
                "blank@21",
                "<q:a>@22 local=a",
                "text \"x\"@27",
                "ref amp Some(Some('&'))@28",
                "ref #x20AC Some(Some('€'))@33",
                "ref bogus Some(None)@41",
                "<b>@48 local=b",
                "</>@48",
                "cdata \"c\\r\\nd\"@52",
                "</>@68",
            ]
        );
    }

    #[test]
    fn text_reads_line_ends_as_lf() {
        let nodes = walk("<a>one\r\ntwo\rthree</a>").unwrap();
        assert_eq!(nodes[1], "text \"one\\ntwo\\nthree\"@3");
        assert_eq!(normalize_line_ends(Cow::Borrowed("a\r\nb\rc")), "a\nb\nc");
    }

    #[test]
    fn attributes_have_the_offsets_of_their_name_and_value() {
        let text = "<a\n  x:k=\"1&#10;2\t3\"  b='&lt;'/>";
        let doc = Document::new(text, "t.xml");
        let mut cursor = Cursor::new(&doc);
        let Node::Start(e) = cursor.next().unwrap() else {
            panic!("expected a start tag");
        };
        let attrs: Vec<_> = e.attributes().map(Result::unwrap).collect();
        assert_eq!(attrs[0].key(), b"k");
        assert_eq!(attrs[0].name(), b"x:k");
        assert_eq!(
            doc.position(attrs[0].name_offset()),
            Position { line: 2, column: 3 }
        );
        assert_eq!(
            doc.position(attrs[0].value_offset()),
            Position { line: 2, column: 8 }
        );
        assert_eq!(attrs[0].value().unwrap(), "1\n2\t3");
        assert_eq!(attrs[0].normalized_value().unwrap(), "1\n2 3");
        assert_eq!(attrs[1].key(), b"b");
        assert_eq!(attrs[1].value().unwrap(), "<");
        assert!(matches!(cursor.next().unwrap(), Node::End { offset: 0 }));
        assert!(matches!(cursor.next().unwrap(), Node::Eof));
    }

    #[test]
    fn a_repeated_attribute_and_a_bad_reference_in_a_value_are_errors() {
        let doc = Document::new("<a k=\"1\" k=\"2\" v=\"&nope;\"/>", "t.xml");
        let mut cursor = Cursor::new(&doc);
        let Node::Start(e) = cursor.next().unwrap() else {
            panic!("expected a start tag");
        };
        let mut attrs = e.attributes();
        assert!(attrs.next().unwrap().is_ok());
        assert!(attrs.next().unwrap().is_err());
        let doc = Document::new("<a v=\"&nope;\"/>", "t.xml");
        let mut cursor = Cursor::new(&doc);
        let Node::Start(e) = cursor.next().unwrap() else {
            panic!("expected a start tag");
        };
        let a = e.attributes().next().unwrap().unwrap();
        assert!(a.value().is_err());
        assert!(a.normalized_value().is_err());
    }

    #[test]
    fn malformed_xml_is_an_error_where_quick_xml_finds_it() {
        let e = walk("<a>\n  <b></c>\n</a>").unwrap_err();
        assert_eq!(e.source_name, "t.xml");
        assert_eq!(e.position.line, 2);
        assert!(e.message.starts_with("malformed XML: "), "{e}");
    }

    #[test]
    fn warnings_are_kept_in_the_order_given() {
        let doc = Document::new("<a>\n<b/></a>", "t.xml");
        doc.warn(4, "second line");
        doc.warn(0, "first line");
        let findings = doc.take_findings();
        assert_eq!(findings.len(), 2);
        assert_eq!(findings[0].position, Some(Position { line: 2, column: 1 }));
        assert_eq!(findings[1].message, "first line");
        assert!(doc.take_findings().is_empty());
        assert_eq!(doc.error(4, "x").position, Position { line: 2, column: 1 });
    }
}
