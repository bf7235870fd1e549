//! An EDS or DCF as a file-level tree: the document holds the comment lines before the first section
//! and the sections; a section its keys and comment lines. Blank lines belong to no node. Names of
//! sections and keys match whatever their case, and a sub-object's section whatever its digit count
//! (`[1018sub1]`, `[1018SUB01]`).

use super::tree::{Doc, Kind, Node};

/// The tree of `text`. Lines that are neither a section, a key nor a comment (which the EDS reader
/// refuses) are left out.
pub(crate) fn parse(text: &str) -> Doc<'_> {
    let mut root = Node {
        name: String::new(),
        key: String::new(),
        span: 0..text.len(),
        kind: Kind::Document,
        children: Vec::new(),
    };
    let mut at = 0;
    for line in text.split_inclusive('\n') {
        let span = at..at + line.len();
        at = span.end;
        let trimmed = line.trim_ascii();
        if trimmed.is_empty() {
            continue;
        }
        if trimmed.starts_with(';') || trimmed.starts_with('#') {
            let node = Node {
                name: "#comment".into(),
                key: trimmed.to_string(),
                span,
                kind: Kind::Opaque,
                children: Vec::new(),
            };
            match root.children.last_mut() {
                Some(section) if matches!(section.kind, Kind::Section { .. }) => {
                    section.children.push(node)
                }
                _ => root.children.push(node),
            }
            continue;
        }
        if let Some(rest) = trimmed.strip_prefix('[') {
            let name = rest.split(']').next().unwrap_or("").trim_ascii();
            root.children.push(Node {
                name: section_name(name),
                key: String::new(),
                span: span.clone(),
                kind: Kind::Section { body: span.end },
                children: Vec::new(),
            });
            continue;
        }
        let Some(eq) = line.find('=') else { continue };
        let Some(section) = root
            .children
            .last_mut()
            .filter(|s| matches!(s.kind, Kind::Section { .. }))
        else {
            continue;
        };
        let key = line[..eq].trim_ascii().to_ascii_lowercase();
        let after = line[eq + 1..].trim_end_matches(['\r', '\n']);
        let value_text = crate::eds::without_comment(after);
        let value_start = span.start + eq + 1 + (after.len() - after.trim_ascii_start().len());
        let value_start = value_start.min(span.start + eq + 1 + value_text.len());
        let value_len = value_text.trim_ascii().len();
        section.children.push(Node {
            name: key,
            key: String::new(),
            span,
            kind: Kind::Entry {
                value: value_start..value_start + value_len,
            },
            children: Vec::new(),
        });
    }
    // A section runs to the next section's header (its blank and comment lines with it).
    let starts: Vec<usize> = root
        .children
        .iter()
        .map(|n| n.span.start)
        .skip(1)
        .chain(std::iter::once(text.len()))
        .collect();
    for (n, next) in root.children.iter_mut().zip(starts) {
        if matches!(n.kind, Kind::Section { .. }) {
            n.span.end = next;
        }
    }
    Doc { text, root }
}

/// A section's name in one form: lower case, a sub-object's section `XXXXsubN` with its numbers
/// read.
fn section_name(name: &str) -> String {
    let lower = name.to_ascii_lowercase();
    if let Some((index, sub)) = lower.split_once("sub") {
        if let (Ok(i), Ok(s)) = (u16::from_str_radix(index, 16), u8::from_str_radix(sub, 16)) {
            return format!("{i:04x}sub{s:x}");
        }
    }
    if let Ok(i) = u16::from_str_radix(&lower, 16) {
        if lower.len() == 4 {
            return format!("{i:04x}");
        }
    }
    lower
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sections_keys_comments_and_values() {
        let text =
            "; head\n[FileInfo]\nFileName = a.eds ; named\r\n\n[1018SUB01]\n;c\nDefaultValue=\n";
        let d = parse(text);
        let names: Vec<&str> = d.root.children.iter().map(|n| n.name.as_str()).collect();
        assert_eq!(names, ["#comment", "fileinfo", "1018sub1"]);
        let info = &d.root.children[1];
        assert_eq!(
            &text[info.span.clone()],
            "[FileInfo]\nFileName = a.eds ; named\r\n\n"
        );
        let Kind::Entry { value } = &info.children[0].kind else {
            panic!("an entry")
        };
        assert_eq!(&text[value.clone()], "a.eds");
        let sub = &d.root.children[2];
        assert_eq!(sub.children[0].key, ";c");
        let Kind::Entry { value } = &sub.children[1].kind else {
            panic!("an entry")
        };
        assert_eq!(value.clone(), text.len() - 1..text.len() - 1);
    }

    #[test]
    fn section_names_in_one_form() {
        assert_eq!(section_name("1A00sub0A"), "1a00suba");
        assert_eq!(section_name("1a00SUB00a"), "1a00suba");
        assert_eq!(section_name("2000"), "2000");
        assert_eq!(section_name("DeviceComissioning"), "devicecomissioning");
    }
}
