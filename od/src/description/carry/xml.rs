//! An ESI or XDD as a file-level tree: elements with their attributes and the byte spans of each
//! part, and comments. Text is no node: an element that holds no element has its content compared
//! and replaced whole.

use quick_xml::events::Event;
use quick_xml::Reader;

use super::tree::{number_key, Attr, Doc, Element, Kind, Node};

/// The deepest nesting of elements carried (real descriptions nest about 15 deep); the tree's walks
/// recurse, so a deeper file is written from the model instead.
const MAX_DEPTH: usize = 256;

/// The tree of `text`, or why it is no well-formed XML or nests deeper than [`MAX_DEPTH`].
pub(crate) fn parse(text: &str) -> Result<Doc<'_>, String> {
    let mut reader = Reader::from_str(text);
    reader.config_mut().check_end_names = true;
    let mut stack = vec![Node {
        name: String::new(),
        key: String::new(),
        span: 0..text.len(),
        kind: Kind::Document,
        children: Vec::new(),
    }];
    loop {
        let before = position(&reader);
        let event = reader
            .read_event()
            .map_err(|e| format!("malformed XML at byte {}: {e}", position(&reader)))?;
        let after = position(&reader);
        match event {
            Event::Start(_) | Event::Empty(_) => {
                let empty = matches!(event, Event::Empty(_));
                let mut node = element(text, before..after);
                if empty {
                    finish(&mut node, text);
                    push(&mut stack, node);
                } else {
                    if stack.len() > MAX_DEPTH {
                        return Err(format!(
                            "elements nested deeper than {MAX_DEPTH} at byte {before}"
                        ));
                    }
                    if let Kind::Element(e) = &mut node.kind {
                        e.content = Some(after..after);
                    }
                    stack.push(node);
                }
            }
            Event::End(_) => {
                if stack.len() < 2 {
                    return Err(format!("an end tag at byte {before} closes nothing"));
                }
                let mut node = stack.pop().expect("an open element");
                if let Kind::Element(e) = &mut node.kind {
                    if let Some(c) = &mut e.content {
                        c.end = before;
                    }
                }
                node.span.end = after;
                finish(&mut node, text);
                push(&mut stack, node);
            }
            Event::Comment(_) => push(
                &mut stack,
                Node {
                    name: "#comment".into(),
                    key: text[before..after].to_string(),
                    span: before..after,
                    kind: Kind::Opaque,
                    children: Vec::new(),
                },
            ),
            Event::Eof => break,
            _ => {}
        }
    }
    if stack.len() != 1 {
        return Err("the document ends inside an element".into());
    }
    let mut root = stack.pop().expect("the document");
    // The document element is the one whatever it holds.
    for c in &mut root.children {
        if c.element().is_some() {
            c.key.clear();
        }
    }
    Ok(Doc { text, root })
}

fn position(reader: &Reader<&[u8]>) -> usize {
    usize::try_from(reader.buffer_position()).unwrap_or(usize::MAX)
}

fn push(stack: &mut [Node], node: Node) {
    if let Some(parent) = stack.last_mut() {
        parent.children.push(node);
    }
}

/// An element from its start tag `text[tag]`, its attributes read from the tag.
fn element(text: &str, tag: std::ops::Range<usize>) -> Node {
    let bytes = text.as_bytes();
    let mut i = tag.start + 1;
    while i < tag.end && !is_space(bytes[i]) && bytes[i] != b'>' && bytes[i] != b'/' {
        i += 1;
    }
    let qname = text[tag.start + 1..i].to_string();
    let mut attrs_end = i;
    let mut attrs = Vec::new();
    loop {
        let ws = i;
        while i < tag.end && is_space(bytes[i]) {
            i += 1;
        }
        let name_start = i;
        while i < tag.end && !is_space(bytes[i]) && !matches!(bytes[i], b'=' | b'>' | b'/') {
            i += 1;
        }
        if i == name_start {
            break;
        }
        let name = &text[name_start..i];
        while i < tag.end && (is_space(bytes[i]) || bytes[i] == b'=') {
            i += 1;
        }
        if i >= tag.end || !matches!(bytes[i], b'"' | b'\'') {
            break;
        }
        let quote = bytes[i];
        let value_start = i + 1;
        let Some(len) = text[value_start..tag.end].find(char::from(quote)) else {
            break;
        };
        i = value_start + len + 1;
        attrs_end = i;
        attrs.push(Attr {
            name: local(name).to_string(),
            span: ws..i,
            value: value_start..value_start + len,
            quote,
        });
    }
    Node {
        name: matched_name(local(&qname)).to_string(),
        key: String::new(),
        span: tag.clone(),
        kind: Kind::Element(Element {
            qname,
            start_tag: tag,
            attrs_end,
            attrs,
            content: None,
        }),
        children: Vec::new(),
    }
}

fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n')
}

/// The name an element is matched by: a CiA 311 name without its `CANopen` (a POWERLINK XDD's
/// `ObjectList`, `Object`, `SubObject` are its `CANopenObjectList`, `CANopenObject`,
/// `CANopenSubObject`, as the reader takes them).
fn matched_name(local: &str) -> &str {
    local
        .strip_prefix("CANopen")
        .filter(|r| !r.is_empty())
        .unwrap_or(local)
}

fn local(name: &str) -> &str {
    name.rsplit(':').next().unwrap_or(name)
}

/// Gives a closed element its key: which of its siblings of one name it is, as the file tells.
fn finish(node: &mut Node, text: &str) {
    let Kind::Element(e) = &node.kind else { return };
    let attr = |name: &str| {
        e.attrs
            .iter()
            .find(|a| a.name == name)
            .map(|a| &text[a.value.clone()])
    };
    let child = |name: &str| {
        node.children
            .iter()
            .find(|c| c.name == name && c.element().is_some() && c.is_leaf())
            .and_then(|c| c.element()?.content.clone())
            .map(|r| text[r].trim())
    };
    let key = if let Some(index) = child("Index") {
        let sub = child("SubIndex").or_else(|| child("SubIdx"));
        match sub {
            Some(s) => format!("{}/{}", number_key(index, false), number_key(s, false)),
            None => number_key(index, false),
        }
    } else if let Some(sub) = child("SubIdx") {
        number_key(sub, false)
    } else if let Some(index) = attr("index") {
        match attr("subIndex") {
            Some(s) => format!("{}/{}", number_key(index, true), number_key(s, true)),
            None => number_key(index, true),
        }
    } else if let Some(sub) = attr("subIndex") {
        number_key(sub, true)
    } else if let Some(id) = attr("uniqueID")
        .or_else(|| attr("LcId"))
        .or_else(|| attr("lang"))
    {
        id.to_string()
    } else if node.name == "Name" {
        // An ESI name without a language is in English (ETG.2000's default LcId).
        "1033".to_string()
    } else if let Some(t) = child("Type") {
        t.to_string()
    } else if let Some(n) =
        child("Name").filter(|_| matches!(node.name.as_str(), "SubItem" | "DataType"))
    {
        // An ESI data type is known by its name, the sub-items of an object's Info by theirs.
        n.to_string()
    } else {
        String::new()
    };
    node.key = key;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elements_attributes_spans_and_keys() {
        let text = "<?xml version=\"1.0\"?>\n<R a = 'x' b=\"y\"><!-- c --><Object><Index>#x1000</Index><Name>N</Name></Object><e/></R>";
        let d = parse(text).unwrap();
        let r = &d.root.children[0];
        assert_eq!(r.name, "R");
        let e = r.element().unwrap();
        assert_eq!(e.attrs.len(), 2);
        assert_eq!(&text[e.attrs[0].span.clone()], " a = 'x'");
        assert_eq!(&text[e.attrs[1].value.clone()], "y");
        assert_eq!(&text[e.attrs_end..e.start_tag.end], ">");
        assert_eq!(r.children[0].name, "#comment");
        let o = &r.children[1];
        assert_eq!((o.name.as_str(), o.key.as_str()), ("Object", "4096"));
        assert_eq!(
            d.raw(o),
            "<Object><Index>#x1000</Index><Name>N</Name></Object>"
        );
        let empty = &r.children[2];
        assert_eq!(d.raw(empty), "<e/>");
        assert!(empty.element().unwrap().content.is_none());
        assert_eq!(d.raw(r).len(), text.len() - 22);
    }

    #[test]
    fn xdd_keys_from_attributes() {
        let text = "<q:CANopenObjectList xmlns:q='u'><q:CANopenObject index=\"1A00\"><CANopenSubObject subIndex=\"01\"/></q:CANopenObject></q:CANopenObjectList>";
        let d = parse(text).unwrap();
        let o = &d.root.children[0].children[0];
        assert_eq!((o.name.as_str(), o.key.as_str()), ("Object", "6656"));
        assert_eq!(o.children[0].key, "1");
    }

    #[test]
    fn esi_names_data_types_and_sub_items_by_their_names() {
        let text = "<D><Name>N</Name><Name LcId=\"1031\">M</Name><DataType><Name>DT1018</Name><SubItem><SubIdx>1</SubIdx><Name>a</Name></SubItem></DataType><SubItem><Name>b</Name></SubItem><Sm/></D>";
        let d = parse(text).unwrap();
        let keys: Vec<(&str, &str)> = d.root.children[0]
            .children
            .iter()
            .map(|c| (c.name.as_str(), c.key.as_str()))
            .collect();
        assert_eq!(
            keys,
            [
                ("Name", "1033"),
                ("Name", "1031"),
                ("DataType", "DT1018"),
                ("SubItem", "b"),
                ("Sm", "")
            ]
        );
        assert_eq!(d.root.children[0].children[2].children[1].key, "1");
    }

    #[test]
    fn nesting_is_bounded() {
        let deep = |n: usize| format!("{}{}", "<a>".repeat(n), "</a>".repeat(n));
        assert!(parse(&deep(256)).is_ok());
        assert_eq!(
            parse(&deep(257)).unwrap_err(),
            "elements nested deeper than 256 at byte 768"
        );
        assert!(parse(&deep(100_000)).is_err());
    }

    #[test]
    fn malformed_is_an_error() {
        assert!(parse("<a><b></a>").is_err());
        assert!(parse("<a>").is_err());
    }
}
