//! A YAML document as a tree whose every node knows its line, built from `yaml-rust2`'s events, with
//! the scalar rules of YAML 1.1 as PyYAML's `safe_load` applies them (the reading dcfgen makes of a bus
//! description): `0x1A`, `0o17`, `017` (octal), `0b101` and `1_000` are integers; `yes`/`no`/`on`/`off`
//! and `true`/`false` are booleans; a quoted scalar is always a string.

use yaml_rust2::parser::{Event, MarkedEventReceiver, Parser};
use yaml_rust2::scanner::{Marker, TScalarStyle};

/// What a node holds.
#[derive(Debug, Clone, PartialEq)]
pub enum Kind {
    /// `null`, `~` or nothing.
    Null,
    /// A boolean.
    Bool(bool),
    /// An integer (wide enough for every CANopen value).
    Int(i128),
    /// A floating-point number.
    Float(f64),
    /// A string (every quoted scalar, and plain scalars that are nothing else).
    Str(String),
    /// A sequence.
    Seq(Vec<Node>),
    /// A mapping, in document order (a repeated key keeps its first place and its last value, as a
    /// Python dictionary does).
    Map(Vec<(Node, Node)>),
}

/// One node and the line (from 1) where it starts.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// The line of the node in its file, from 1.
    pub line: usize,
    /// The value.
    pub kind: Kind,
}

impl Node {
    /// The value of `key` in a mapping, with the node of the key.
    pub fn get(&self, key: &str) -> Option<(&Node, &Node)> {
        match &self.kind {
            Kind::Map(entries) => entries
                .iter()
                .find(|(k, _)| k.key_text().as_deref() == Some(key))
                .map(|(k, v)| (k, v)),
            _ => None,
        }
    }

    /// The text a mapping key stands for (`str()` of the key, as Python would give it).
    pub fn key_text(&self) -> Option<String> {
        match &self.kind {
            Kind::Str(s) => Some(s.clone()),
            Kind::Int(i) => Some(i.to_string()),
            Kind::Bool(true) => Some("True".into()),
            Kind::Bool(false) => Some("False".into()),
            Kind::Null => Some("None".into()),
            Kind::Float(f) => Some(f.to_string()),
            _ => None,
        }
    }

    /// The entries of a mapping (empty for anything else).
    pub fn entries(&self) -> &[(Node, Node)] {
        match &self.kind {
            Kind::Map(entries) => entries,
            _ => &[],
        }
    }
}

/// Parses `text`, a single YAML document. An empty document is `Null` at line 1. The error is the line
/// and what the parser found.
pub(crate) fn parse(text: &str) -> Result<Node, (usize, String)> {
    let mut builder = Builder::default();
    let mut parser = Parser::new_from_str(text);
    parser
        .load(&mut builder, false)
        .map_err(|e| (e.marker().line(), e.info().to_string()))?;
    if let Some(err) = builder.error {
        return Err(err);
    }
    Ok(builder.root.unwrap_or(Node {
        line: 1,
        kind: Kind::Null,
    }))
}

enum Open {
    Seq(usize, Vec<Node>),
    Map(usize, Vec<(Node, Node)>, Option<Node>),
}

#[derive(Default)]
struct Builder {
    stack: Vec<Open>,
    root: Option<Node>,
    anchors: Vec<(usize, Node)>,
    pending_anchor: Vec<usize>,
    error: Option<(usize, String)>,
}

impl Builder {
    fn push(&mut self, node: Node) {
        match self.stack.last_mut() {
            Some(Open::Seq(_, items)) => items.push(node),
            Some(Open::Map(_, entries, key)) => match key.take() {
                None => *key = Some(node),
                Some(k) => {
                    let name = k.key_text();
                    match entries
                        .iter_mut()
                        .find(|(old, _)| name.is_some() && old.key_text() == name)
                    {
                        Some(entry) => entry.1 = node,
                        None => entries.push((k, node)),
                    }
                }
            },
            None => {
                if self.root.is_none() {
                    self.root = Some(node);
                }
            }
        }
    }

    fn finish(&mut self, node: Node) {
        if let Some(id) = self.pending_anchor.pop() {
            if id > 0 {
                self.anchors.push((id, node.clone()));
            }
        }
        self.push(node);
    }
}

impl MarkedEventReceiver for Builder {
    fn on_event(&mut self, ev: Event, mark: Marker) {
        let line = mark.line();
        match ev {
            Event::Scalar(text, style, anchor, _) => {
                let kind = if style == TScalarStyle::Plain {
                    plain(&text)
                } else {
                    Kind::Str(text)
                };
                let node = Node { line, kind };
                if anchor > 0 {
                    self.anchors.push((anchor, node.clone()));
                }
                self.push(node);
            }
            Event::SequenceStart(anchor, _) => {
                self.pending_anchor.push(anchor);
                self.stack.push(Open::Seq(line, Vec::new()));
            }
            Event::MappingStart(anchor, _) => {
                self.pending_anchor.push(anchor);
                self.stack.push(Open::Map(line, Vec::new(), None));
            }
            Event::SequenceEnd | Event::MappingEnd => {
                let node = match self.stack.pop() {
                    Some(Open::Seq(line, items)) => Node {
                        line,
                        kind: Kind::Seq(items),
                    },
                    Some(Open::Map(line, entries, _)) => Node {
                        line,
                        kind: Kind::Map(merge(entries)),
                    },
                    None => return,
                };
                self.finish(node);
            }
            Event::Alias(id) => match self.anchors.iter().rev().find(|(a, _)| *a == id) {
                Some((_, node)) => {
                    let node = node.clone();
                    self.push(node);
                }
                None => {
                    self.error
                        .get_or_insert((line, "an alias to no anchor".to_string()));
                }
            },
            _ => {}
        }
    }
}

/// A mapping with its `<<` merge keys resolved as PyYAML does: the merged entries first, then the
/// mapping's own, which win.
fn merge(entries: Vec<(Node, Node)>) -> Vec<(Node, Node)> {
    let is_merge = |k: &Node| k.kind == Kind::Str("<<".into());
    if !entries.iter().any(|(k, _)| is_merge(k)) {
        return entries;
    }
    let mut out: Vec<(Node, Node)> = Vec::new();
    let put = |out: &mut Vec<(Node, Node)>, k: Node, v: Node| match out
        .iter_mut()
        .find(|(old, _)| old.key_text() == k.key_text())
    {
        Some(slot) => slot.1 = v,
        None => out.push((k, v)),
    };
    for (_, v) in entries.iter().filter(|(k, _)| is_merge(k)) {
        let sources: Vec<&Node> = match &v.kind {
            Kind::Seq(items) => items.iter().collect(),
            _ => vec![v],
        };
        for source in sources {
            for (k, v) in source.entries() {
                if !out.iter().any(|(old, _)| old.key_text() == k.key_text()) {
                    out.push((k.clone(), v.clone()));
                }
            }
        }
    }
    for (k, v) in entries.into_iter().filter(|(k, _)| !is_merge(k)) {
        put(&mut out, k, v);
    }
    out
}

/// The value of a plain scalar under YAML 1.1's core rules (PyYAML's resolver).
fn plain(text: &str) -> Kind {
    match text {
        "" | "~" | "null" | "Null" | "NULL" => return Kind::Null,
        "true" | "True" | "TRUE" | "yes" | "Yes" | "YES" | "on" | "On" | "ON" => {
            return Kind::Bool(true)
        }
        "false" | "False" | "FALSE" | "no" | "No" | "NO" | "off" | "Off" | "OFF" => {
            return Kind::Bool(false)
        }
        _ => {}
    }
    if let Some(i) = int(text) {
        return Kind::Int(i);
    }
    let looks_float = text
        .trim_start_matches(['-', '+'])
        .starts_with(|c: char| c.is_ascii_digit() || c == '.')
        && text.chars().any(|c| c.is_ascii_digit());
    if looks_float {
        if let Ok(f) = text.replace('_', "").parse::<f64>() {
            return Kind::Float(f);
        }
    }
    Kind::Str(text.to_string())
}

/// An integer as YAML 1.1 writes one: decimal, `0x` hex, `0o` or leading-zero octal, `0b` binary,
/// with an optional sign and `_` separators.
pub(crate) fn int(text: &str) -> Option<i128> {
    let (negative, body) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text.strip_prefix('+').unwrap_or(text)),
    };
    let body = body.replace('_', "");
    if body.is_empty() {
        return None;
    }
    let (digits, radix) = if let Some(h) = body.strip_prefix("0x") {
        (h, 16)
    } else if let Some(b) = body.strip_prefix("0b") {
        (b, 2)
    } else if let Some(o) = body.strip_prefix("0o") {
        (o, 8)
    } else if body.len() > 1 && body.starts_with('0') {
        (&body[1..], 8)
    } else {
        (body.as_str(), 10)
    };
    if digits.is_empty() || !digits.chars().all(|c| c.is_digit(radix)) {
        return None;
    }
    let value = i128::from_str_radix(digits, radix).ok()?;
    Some(if negative { -value } else { value })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nodes_carry_their_lines_and_yaml_1_1_scalars() {
        let doc = parse("a: 0x10\nb:\n  c: yes\n  d: '7'\ne: [1, 017]\n").unwrap();
        let (key, a) = doc.get("a").unwrap();
        assert_eq!((key.line, a.kind.clone()), (1, Kind::Int(16)));
        let (_, b) = doc.get("b").unwrap();
        assert_eq!(b.get("c").unwrap().1.kind, Kind::Bool(true));
        assert_eq!(b.get("d").unwrap().1.kind, Kind::Str("7".into()));
        assert_eq!(b.get("d").unwrap().0.line, 4);
        let (_, e) = doc.get("e").unwrap();
        let Kind::Seq(items) = &e.kind else { panic!() };
        assert_eq!(items[1].kind, Kind::Int(15));
    }

    #[test]
    fn a_syntax_error_names_its_line() {
        let (line, _) = parse("a: 1\nb: [1,\n").unwrap_err();
        assert!(line >= 2);
    }

    #[test]
    fn merge_keys_come_first_and_lose_to_own_keys() {
        let doc = parse("x: &v {a: 1, b: 2}\ny:\n  c: 3\n  <<: *v\n  a: 4\n").unwrap();
        let y = doc.get("y").unwrap().1;
        let keys: Vec<_> = y
            .entries()
            .iter()
            .map(|(k, v)| (k.key_text().unwrap(), v.kind.clone()))
            .collect();
        assert_eq!(
            keys,
            [
                ("a".into(), Kind::Int(4)),
                ("b".into(), Kind::Int(2)),
                ("c".into(), Kind::Int(3))
            ]
        );
    }

    #[test]
    fn aliases_repeat_their_anchor() {
        let doc = parse("x: &v {a: 1}\ny: *v\n").unwrap();
        assert_eq!(
            doc.get("y").unwrap().1.get("a").unwrap().1.kind,
            Kind::Int(1)
        );
    }
}
