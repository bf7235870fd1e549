//! The file-level tree both formats are read into for carrying: nodes with their byte spans in the
//! text, a name and an identity among their siblings, and the edit list that patches a text.

use std::collections::{HashMap, VecDeque};
use std::ops::Range;

/// One part of a file: an INI section, key or comment line; an XML element or comment; or the
/// document itself.
#[derive(Debug)]
pub(crate) struct Node {
    /// What kind of part it is, as siblings are matched by it: a section's name (lower case, hex
    /// numbers in one form), a key (lower case), an element's local name, `#comment`.
    pub name: String,
    /// Which one of the siblings of that name it is, where the file says (an object's index, a
    /// sub-index, a `uniqueID`, a language, a type name; a comment's text); empty otherwise, and then
    /// siblings of one name pair in their order.
    pub key: String,
    /// The whole part: an INI line with its line end, a section from its header to the next one, an
    /// element from `<` to the end of its end tag.
    pub span: Range<usize>,
    pub kind: Kind,
    pub children: Vec<Node>,
}

#[derive(Debug)]
pub(crate) enum Kind {
    /// The whole file.
    Document,
    /// An INI section; `body` is where its first line after the header starts.
    Section { body: usize },
    /// `key=value`: the value without an inline comment.
    Entry { value: Range<usize> },
    /// An XML element.
    Element(Element),
    /// A part matched by its text alone (a comment).
    Opaque,
}

#[derive(Debug)]
pub(crate) struct Element {
    /// The name as written (`q1:parameter`).
    pub qname: String,
    /// `<` to `>` of the start tag (of the empty-element tag).
    pub start_tag: Range<usize>,
    /// Where an attribute added after the others goes: the end of the last attribute or of the name.
    pub attrs_end: usize,
    pub attrs: Vec<Attr>,
    /// Between the start and the end tag; `None` for an empty-element tag `<a/>`.
    pub content: Option<Range<usize>>,
}

#[derive(Debug)]
pub(crate) struct Attr {
    /// The local name.
    pub name: String,
    /// From the white space before the name to the closing quote.
    pub span: Range<usize>,
    /// Between the quotes.
    pub value: Range<usize>,
    pub quote: u8,
}

impl Node {
    /// The element part of an XML element.
    pub fn element(&self) -> Option<&Element> {
        match &self.kind {
            Kind::Element(e) => Some(e),
            _ => None,
        }
    }

    /// Whether an element holds no element: its content is text only.
    pub fn is_leaf(&self) -> bool {
        !self.children.iter().any(|c| c.element().is_some())
    }
}

/// Pairs each of `a` with the one of `b` of the same name and key, the n-th of `a` with the n-th of
/// `b` where several share both; `None` where `b` has no partner left.
pub(crate) fn align(a: &[Node], b: &[Node]) -> Vec<Option<usize>> {
    let mut free: HashMap<(&str, &str), VecDeque<usize>> = HashMap::new();
    for (j, n) in b.iter().enumerate() {
        free.entry((n.name.as_str(), n.key.as_str()))
            .or_default()
            .push_back(j);
    }
    a.iter()
        .map(|n| {
            free.get_mut(&(n.name.as_str(), n.key.as_str()))
                .and_then(VecDeque::pop_front)
        })
        .collect()
}

/// A text and its tree.
#[derive(Debug)]
pub(crate) struct Doc<'a> {
    pub text: &'a str,
    pub root: Node,
}

impl<'a> Doc<'a> {
    pub fn raw(&self, n: &Node) -> &'a str {
        &self.text[n.span.clone()]
    }

    /// The line end the text uses: CR LF when its first line ends so.
    pub fn eol(&self) -> &'static str {
        match self.text.find('\n') {
            Some(i) if i > 0 && self.text.as_bytes()[i - 1] == b'\r' => "\r\n",
            _ => "\n",
        }
    }

    /// The spaces and tabs before `at` when only they stand between a line start and `at`.
    pub fn indent_before(&self, at: usize) -> &'a str {
        let head = &self.text[..at];
        let start = head.trim_end_matches([' ', '\t']).len();
        let before = &head[..start];
        if before.is_empty() || before.ends_with('\n') {
            &head[start..]
        } else {
            ""
        }
    }
}

/// Replacements of spans of a text, applied at once.
#[derive(Default)]
pub(crate) struct Edits {
    list: Vec<(Range<usize>, String)>,
}

impl Edits {
    pub fn replace(&mut self, at: Range<usize>, text: impl Into<String>) {
        self.list.push((at, text.into()));
    }

    pub fn insert(&mut self, at: usize, text: impl Into<String>) {
        self.list.push((at..at, text.into()));
    }

    /// `text` with every edit made; insertions at one place in the order they were made. Two edits
    /// of overlapping spans are a failure of the merge, named.
    pub fn apply(mut self, text: &str) -> Result<String, String> {
        // A stable sort keeps insertions at one place in their order; an insertion at the start of
        // a replaced span goes before it.
        self.list
            .sort_by_key(|(r, _)| (r.start, usize::from(r.end > r.start)));
        let mut out = String::with_capacity(text.len());
        let mut at = 0;
        for (r, t) in &self.list {
            if r.start < at {
                return Err(format!("two changes at byte {} overlap", r.start));
            }
            out.push_str(&text[at..r.start]);
            out.push_str(t);
            at = r.end;
        }
        out.push_str(&text[at..]);
        Ok(out)
    }
}

/// A number as the files write it (`#x1A00`, `0x1A00`, `1A00h`, decimal) in one form, for keys;
/// other text as it is. `hex` reads bare digits as hexadecimal (XDD attributes).
pub(crate) fn number_key(text: &str, hex: bool) -> String {
    let t = text.trim();
    let lower = t.to_ascii_lowercase();
    let parsed = if let Some(h) = lower
        .strip_prefix("#x")
        .or_else(|| lower.strip_prefix("0x"))
    {
        u64::from_str_radix(h, 16).ok()
    } else if hex {
        u64::from_str_radix(&lower, 16).ok()
    } else {
        lower.parse::<u64>().ok()
    };
    match parsed {
        Some(n) => n.to_string(),
        None => t.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn leaf(name: &str, key: &str) -> Node {
        Node {
            name: name.into(),
            key: key.into(),
            span: 0..0,
            kind: Kind::Opaque,
            children: Vec::new(),
        }
    }

    #[test]
    fn align_pairs_by_name_and_key_then_order() {
        let a = [leaf("a", "1"), leaf("b", ""), leaf("b", ""), leaf("c", "")];
        let b = [leaf("b", ""), leaf("a", "2"), leaf("a", "1"), leaf("b", "")];
        assert_eq!(align(&a, &b), vec![Some(2), Some(0), Some(3), None]);
    }

    #[test]
    fn edits_apply_in_place_and_refuse_overlaps() {
        let mut e = Edits::default();
        e.replace(2..4, "XY");
        e.insert(2, "<");
        e.insert(6, ">");
        assert_eq!(e.apply("abcdefg").unwrap(), "ab<XYef>g");
        let mut e = Edits::default();
        e.replace(1..4, "");
        e.replace(3..5, "");
        assert_eq!(
            e.apply("abcdef").unwrap_err(),
            "two changes at byte 3 overlap"
        );
    }

    #[test]
    fn number_keys() {
        assert_eq!(number_key("#x1A00", false), "6656");
        assert_eq!(number_key(" 0x1a00 ", false), "6656");
        assert_eq!(number_key("6656", false), "6656");
        assert_eq!(number_key("1A00", true), "6656");
        assert_eq!(number_key("Name", false), "Name");
    }

    #[test]
    fn indent_is_white_space_from_a_line_start() {
        let d = Doc {
            text: "<a>\n\t <b/> <c/>",
            root: leaf("", ""),
        };
        assert_eq!(d.indent_before(6), "\t ");
        assert_eq!(d.indent_before(11), "");
        assert_eq!(d.eol(), "\n");
    }
}
