//! Shared pieces of the XML readers and writers (ESI, XDD): decoding the file's character encoding,
//! numbers as ESI and XDD write them, an escaping writer with stable indentation, the `cursor` both
//! readers walk a document with, and the one way both collect an element's text (`text`: character
//! data, references and CDATA sections).

use std::borrow::Cow;

pub(crate) mod cursor;
pub(crate) mod text;

use crate::error::ParseError;

/// Decodes an XML file to text by its byte-order mark or its `encoding` declaration (UTF-8, UTF-16,
/// ISO-8859-1, Windows-1252 and the other encodings of the WHATWG list). CR LF line ends stay as they are;
/// the XML parser treats them as white space.
pub fn decode<'a>(bytes: &'a [u8], source_name: &str) -> Result<Cow<'a, str>, ParseError> {
    if let Some((encoding, bom_len)) = encoding_rs::Encoding::for_bom(bytes) {
        if encoding == encoding_rs::UTF_8 {
            return match std::str::from_utf8(&bytes[bom_len..]) {
                Ok(s) => Ok(Cow::Borrowed(s)),
                Err(e) => Err(ParseError::at_offset(
                    source_name,
                    bytes,
                    bom_len + e.valid_up_to(),
                    "invalid UTF-8 after a UTF-8 byte-order mark",
                )),
            };
        }
        let (text, had_errors) = encoding.decode_without_bom_handling(&bytes[bom_len..]);
        if had_errors {
            return Err(ParseError::new(
                source_name,
                Default::default(),
                format!("the file is not valid {}", encoding.name()),
            ));
        }
        return Ok(text);
    }
    let label = declared_encoding(bytes);
    let encoding = match label {
        Some(label) => encoding_rs::Encoding::for_label(label.as_bytes()).ok_or_else(|| {
            ParseError::at_offset(
                source_name,
                bytes,
                0,
                format!("unknown character encoding `{label}` in the XML declaration"),
            )
        })?,
        None => encoding_rs::UTF_8,
    };
    if encoding == encoding_rs::UTF_8 {
        return match std::str::from_utf8(bytes) {
            Ok(s) => Ok(Cow::Borrowed(s)),
            Err(e) => Err(ParseError::at_offset(
                source_name,
                bytes,
                e.valid_up_to(),
                "invalid UTF-8 (declare encoding=\"ISO-8859-1\" if the file is Latin-1)",
            )),
        };
    }
    let (text, _, had_errors) = encoding.decode(bytes);
    if had_errors {
        return Err(ParseError::new(
            source_name,
            Default::default(),
            format!("the file is not valid {}", encoding.name()),
        ));
    }
    Ok(text)
}

/// The `encoding` pseudo-attribute of the XML declaration, if any.
pub(crate) fn declared_encoding(bytes: &[u8]) -> Option<String> {
    let head = &bytes[..bytes.len().min(200)];
    let head = String::from_utf8_lossy(head);
    let decl = head.strip_prefix("<?xml")?;
    let end = decl.find("?>")?;
    let decl = &decl[..end];
    let pos = decl.find("encoding")?;
    let rest = decl[pos + "encoding".len()..]
        .trim_start()
        .strip_prefix('=')?
        .trim_start();
    let quote = rest.chars().next().filter(|c| *c == '"' || *c == '\'')?;
    let rest = &rest[1..];
    let close = rest.find(quote)?;
    Some(rest[..close].trim().to_string())
}

/// Parses a number as ESI and XDD write them: `#x1A00` (ETG hexadecimal), `0x1A00`, or decimal with an
/// optional sign. Answers `None` for anything else.
pub fn parse_number(text: &str) -> Option<i128> {
    let t = text.trim();
    let (neg, body) = match t.as_bytes().first()? {
        b'-' => (true, &t[1..]),
        b'+' => (false, &t[1..]),
        _ => (false, t),
    };
    let hex = body
        .strip_prefix("#x")
        .or_else(|| body.strip_prefix("#X"))
        .or_else(|| body.strip_prefix("0x"))
        .or_else(|| body.strip_prefix("0X"));
    let magnitude = match hex {
        Some(h) if !h.is_empty() && h.len() <= 32 && h.bytes().all(|b| b.is_ascii_hexdigit()) => {
            u128::from_str_radix(h, 16).ok()?
        }
        Some(_) => return None,
        None if !body.is_empty()
            && body.len() <= 39
            && body.bytes().all(|b| b.is_ascii_digit()) =>
        {
            body.parse::<u128>().ok()?
        }
        None => return None,
    };
    let magnitude = i128::try_from(magnitude).ok()?;
    Some(if neg { -magnitude } else { magnitude })
}

/// Parses an XML Schema boolean: `true`, `false`, `1`, `0` (case-insensitive, trimmed).
pub fn parse_bool(text: &str) -> Option<bool> {
    match text.trim().to_ascii_lowercase().as_str() {
        "true" | "1" => Some(true),
        "false" | "0" => Some(false),
        _ => None,
    }
}

/// The character that one of the five predefined entities stands for (`lt` for `&lt;`, …).
pub(crate) fn predefined_entity(name: &[u8]) -> Option<char> {
    match name {
        b"lt" => Some('<'),
        b"gt" => Some('>'),
        b"amp" => Some('&'),
        b"apos" => Some('\''),
        b"quot" => Some('"'),
        _ => None,
    }
}

/// Escapes text for an XML attribute or element.
pub fn escape(text: &str) -> Cow<'_, str> {
    if !text.contains(['&', '<', '>', '"', '\'', '\r', '\n', '\t']) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\r' => out.push_str("&#13;"),
            '\n' => out.push_str("&#10;"),
            '\t' => out.push_str("&#9;"),
            c => out.push(c),
        }
    }
    Cow::Owned(out)
}

/// A small XML writer with two-space indentation and LF line ends, so output is byte-stable.
#[derive(Debug, Default)]
pub struct XmlWriter {
    out: String,
    stack: Vec<String>,
}

impl XmlWriter {
    /// A writer that starts with the XML declaration (UTF-8).
    pub fn new() -> XmlWriter {
        XmlWriter {
            out: "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n".to_string(),
            stack: Vec::new(),
        }
    }

    fn indent(&mut self) {
        for _ in 0..self.stack.len() {
            self.out.push_str("  ");
        }
    }

    fn open_tag(&mut self, name: &str, attrs: &[(&str, &str)]) {
        self.indent();
        self.out.push('<');
        self.out.push_str(name);
        for (k, v) in attrs {
            self.out.push(' ');
            self.out.push_str(k);
            self.out.push_str("=\"");
            self.out.push_str(&escape(v));
            self.out.push('"');
        }
    }

    /// Opens an element with attributes; its children follow on their own lines.
    pub fn start(&mut self, name: &str, attrs: &[(&str, &str)]) -> &mut Self {
        self.open_tag(name, attrs);
        self.out.push_str(">\n");
        self.stack.push(name.to_string());
        self
    }

    /// Closes the innermost open element.
    pub fn end(&mut self) -> &mut Self {
        if let Some(name) = self.stack.pop() {
            self.indent();
            self.out.push_str("</");
            self.out.push_str(&name);
            self.out.push_str(">\n");
        }
        self
    }

    /// An element with text content on one line: `<Name a="b">text</Name>`.
    pub fn text(&mut self, name: &str, attrs: &[(&str, &str)], text: &str) -> &mut Self {
        self.open_tag(name, attrs);
        self.out.push('>');
        self.out.push_str(&escape(text));
        self.out.push_str("</");
        self.out.push_str(name);
        self.out.push_str(">\n");
        self
    }

    /// An empty element: `<Name a="b"/>`.
    pub fn empty(&mut self, name: &str, attrs: &[(&str, &str)]) -> &mut Self {
        self.open_tag(name, attrs);
        self.out.push_str("/>\n");
        self
    }

    /// A comment on its own line.
    pub fn comment(&mut self, text: &str) -> &mut Self {
        self.indent();
        self.out.push_str("<!-- ");
        self.out.push_str(&text.replace("--", "- -"));
        self.out.push_str(" -->\n");
        self
    }

    /// Closes every open element and answers the document.
    pub fn finish(mut self) -> String {
        while !self.stack.is_empty() {
            self.end();
        }
        self.out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_in_esi_and_xdd_spellings() {
        assert_eq!(parse_number("#x1A00"), Some(0x1A00));
        assert_eq!(parse_number("0x1a00"), Some(0x1A00));
        assert_eq!(parse_number(" 6656 "), Some(6656));
        assert_eq!(parse_number("-5"), Some(-5));
        assert_eq!(parse_number("#x"), None);
        assert_eq!(parse_number("12a"), None);
        assert_eq!(parse_number(""), None);
    }

    #[test]
    fn latin1_and_utf8_files_decode() {
        let latin1 = b"<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?><a>\xB5s</a>";
        assert_eq!(
            decode(latin1, "t.xml").unwrap(),
            "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?><a>\u{b5}s</a>"
        );
        let utf8 = "<?xml version=\"1.0\"?><a>µs</a>".as_bytes();
        assert_eq!(
            decode(utf8, "t.xml").unwrap(),
            "<?xml version=\"1.0\"?><a>µs</a>"
        );
        let bad = b"<?xml version=\"1.0\"?>\n<a>\xB5</a>";
        let e = decode(bad, "t.xml").unwrap_err();
        assert_eq!(e.position.line, 2);
        assert_eq!(e.position.column, 4);
        let bom = b"\xEF\xBB\xBF<a>\n\xFF</a>";
        let e = decode(bom, "t.xml").unwrap_err();
        assert_eq!((e.position.line, e.position.column), (2, 1));
    }

    #[test]
    fn writer_escapes_and_indents() {
        let mut w = XmlWriter::new();
        w.start("A", &[("x", "1<2")])
            .text("B", &[], "B&R")
            .empty("C", &[]);
        assert_eq!(
            w.finish(),
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<A x=\"1&lt;2\">\n  <B>B&amp;R</B>\n  <C/>\n</A>\n"
        );
    }
}
