//! The text of an element as both XML readers collect it, whichever field it is: character data,
//! references and CDATA sections one after another, as one string (XML 1.0 §2.4 and §2.7: a CDATA
//! section is character data whose markup is not recognised, so `<![CDATA[Motor & Drive]]>` is the
//! text `Motor & Drive`, as `Motor &amp; Drive` is).
//!
//! Line ends are read as LF in text and in CDATA sections alike (XML 1.0 §2.11); references are
//! resolved (the five predefined entities and character references). What the text means, and whether
//! white space around it counts, stays with each reader.

use super::cursor::{normalize_line_ends, Document, Node};
use crate::error::ParseError;

/// The opening of a CDATA section, before its content.
const CDATA_OPEN: &str = "<![CDATA[";

/// The text of the element being read, and where its first character that is not white space is.
#[derive(Debug, Default)]
pub(crate) struct ElementText {
    text: String,
    offset: Option<usize>,
}

impl ElementText {
    /// Takes `node` into the text when it is a part of element text (text, a CDATA section, a
    /// reference) and answers true; answers false for any other node. A reference to an entity that
    /// is not predefined, or to no character, is an error at its `&`.
    pub(crate) fn take(&mut self, doc: &Document<'_>, node: &Node<'_>) -> Result<bool, ParseError> {
        match node {
            Node::Text(t, offset) => {
                if self.offset.is_none() && t.is_blank() {
                    // Layout before the text, kept as it is (a reader may keep leading white space).
                    self.text.push_str(&t.content());
                } else {
                    self.push(doc, &t.content(), *offset);
                }
            }
            Node::CData(t, offset) => {
                let content = normalize_line_ends(t.clone());
                self.push(doc, &content, offset + CDATA_OPEN.len());
            }
            Node::Ref(r, offset) => {
                let c = match r.resolve() {
                    Ok(Some(c)) => c,
                    Ok(None) => {
                        return Err(doc.error(
                            *offset,
                            format!(
                            "unknown entity `&{};` (expected &lt; &gt; &amp; &apos; &quot; or a \
                                 character reference)",
                            r.name()
                        ),
                        ))
                    }
                    Err(e) => {
                        return Err(doc.error(*offset, format!("bad character reference: {e}")))
                    }
                };
                if self.offset.is_none() && !c.is_whitespace() {
                    self.offset = Some(*offset);
                }
                self.text.push(c);
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// Appends a piece whose source starts at byte `offset` of the document.
    fn push(&mut self, doc: &Document<'_>, piece: &str, offset: usize) {
        if self.offset.is_none() && !piece.trim().is_empty() {
            // Where the first character that is not white space is in the source (a line end read
            // from CR LF is one byte shorter in the piece).
            let source = doc.text().get(offset..).unwrap_or_default();
            let lead = source.len() - source.trim_start().len();
            self.offset = Some(offset + lead);
        }
        self.text.push_str(piece);
    }

    /// The text so far, as written (white space included).
    pub(crate) fn text(&self) -> &str {
        &self.text
    }

    /// The byte offset of the first character that is not white space, if there is one.
    pub(crate) fn offset(&self) -> Option<usize> {
        self.offset
    }

    /// True when nothing but layout was taken so far.
    pub(crate) fn is_blank(&self) -> bool {
        self.offset.is_none()
    }

    /// The text, leaving none.
    pub(crate) fn take_text(&mut self) -> String {
        self.offset = None;
        std::mem::take(&mut self.text)
    }

    /// Forgets the text, keeping its buffer.
    pub(crate) fn clear(&mut self) {
        self.text.clear();
        self.offset = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Position;
    use crate::xml::cursor::Cursor;

    /// The text of the first element of `xml` and the position of its first character that is not
    /// white space.
    fn text_of(xml: &str) -> Result<(String, Option<Position>), ParseError> {
        let doc = Document::new(xml, "t.xml");
        let mut cursor = Cursor::new(&doc);
        let mut text = ElementText::default();
        let mut depth = 0;
        loop {
            let node = cursor.next()?;
            match node {
                Node::Start(_) => depth += 1,
                Node::End { .. } => {
                    depth -= 1;
                    if depth == 0 {
                        break;
                    }
                }
                Node::Eof => break,
                _ => {
                    assert!(text.take(&doc, &node)?);
                }
            }
        }
        Ok((
            text.text().to_string(),
            text.offset().map(|o| doc.position(o)),
        ))
    }

    #[test]
    fn a_cdata_section_is_its_content() {
        let (text, at) = text_of("<Name><![CDATA[Motor & Drive]]></Name>").unwrap();
        assert_eq!(text, "Motor & Drive");
        assert_eq!(
            at,
            Some(Position {
                line: 1,
                column: 16
            })
        );
        let (text, _) = text_of("<Name><![CDATA[<b>&amp;</b>]]></Name>").unwrap();
        assert_eq!(
            text, "<b>&amp;</b>",
            "markup and references in CDATA are text"
        );
    }

    #[test]
    fn text_references_and_cdata_pieces_make_one_text() {
        let (text, at) =
            text_of("<Name>\r\n  Motor &amp; <![CDATA[<Drive>\r\n]]>&#x20AC;&lt;1</Name>").unwrap();
        assert_eq!(text, "\n  Motor & <Drive>\n€<1");
        assert_eq!(at, Some(Position { line: 2, column: 3 }));
        let (text, at) = text_of("<Name>  <![CDATA[  x]]></Name>").unwrap();
        assert_eq!(text, "    x");
        assert_eq!(
            at,
            Some(Position {
                line: 1,
                column: 20
            })
        );
        let (text, at) = text_of("<Name>&#32;&amp;</Name>").unwrap();
        assert_eq!(text, " &");
        assert_eq!(
            at,
            Some(Position {
                line: 1,
                column: 12
            })
        );
        assert_eq!(
            text_of("<Name> <![CDATA[]]> </Name>").unwrap(),
            ("  ".into(), None)
        );
    }

    #[test]
    fn an_unknown_entity_is_an_error_at_its_ampersand() {
        let e = text_of("<Name>a&nbsp;</Name>").unwrap_err();
        assert_eq!(e.position, Position { line: 1, column: 8 });
        assert!(e.message.starts_with("unknown entity `&nbsp;`"), "{e}");
        let e = text_of("<Name>&#0;</Name>").unwrap_err();
        assert!(e.message.starts_with("bad character reference"), "{e}");
    }
}
