//! The element walk of the ESI reader: the cursor's nodes onto the stack of known tags, the text of
//! the innermost element, its attributes, and the end of a device or module, which is resolved into a
//! description there.

use super::dictionary::build_device;
use super::{Parser, Tag};
use crate::device::{CatalogueModule, EsiRoot, Module};
use crate::error::ParseError;
use crate::xml::cursor::{Cursor, Element, Node};

impl<'a> Parser<'a> {
    pub(super) fn run(&mut self) -> Result<(), ParseError> {
        let mut cursor = Cursor::new(self.ctx.doc);
        let mut root_seen = false;
        // In an `EtherCATInfoList`: whether its end was seen.
        let mut list_closed = false;
        loop {
            match cursor.next()? {
                Node::Start(e) => {
                    if self.stack.is_empty() {
                        let list = self.check_root(&e, root_seen, list_closed)?;
                        root_seen = true;
                        if list {
                            // The list's element is not on the stack: each `EtherCATInfo` in it is
                            // read as a root of its own.
                            self.list_entry = Some(0);
                            continue;
                        }
                    }
                    self.start(&e)?;
                }
                Node::End { offset } => {
                    if self.stack.is_empty() {
                        list_closed = true;
                        continue;
                    }
                    self.end(offset)?;
                    if self.stack.is_empty() {
                        self.finish_info();
                    }
                }
                // White space before an element's text is layout: skip it without decoding.
                Node::Text(t, _) if self.text.is_blank() && t.is_blank() => {}
                node @ (Node::Text(..) | Node::CData(..) | Node::Ref(..)) => {
                    if self.collecting() {
                        self.text.take(self.ctx.doc, &node)?;
                    }
                }
                Node::Eof => break,
            }
        }
        let open = match self.stack.last() {
            Some(tag) => Some(tag.name()),
            None if self.list_entry.is_some() && !list_closed => Some("EtherCATInfoList"),
            None => None,
        };
        if let Some(open) = open {
            return Err(self.ctx.err(
                self.ctx.doc.text().len(),
                format!("unexpected end of file: <{open}> is not closed"),
            ));
        }
        if !root_seen {
            return Err(self
                .ctx
                .err(0, "expected an <EtherCATInfo> element, found no element"));
        }
        Ok(())
    }

    /// Checks an element at the top of the stack: the root (`EtherCATInfo`, `EtherCATModule` or
    /// `EtherCATInfoList`), or an `EtherCATInfo` in an open `EtherCATInfoList`. True for the list.
    fn check_root(&self, e: &Element, seen: bool, list_closed: bool) -> Result<bool, ParseError> {
        let tag = Tag::of(e.local_name());
        let in_list = self.list_entry.is_some() && !list_closed;
        match tag {
            Tag::EtherCATInfo | Tag::EtherCATModule if !seen => Ok(false),
            Tag::EtherCATInfoList if !seen => Ok(true),
            Tag::EtherCATInfo if in_list => Ok(false),
            _ if seen && !in_list => Err(self.ctx.err(
                e.offset(),
                format!(
                    "a second root element <{}>: a file has one",
                    String::from_utf8_lossy(e.name())
                ),
            )),
            _ => Err(self.ctx.err(
                e.offset(),
                format!(
                    "expected an <EtherCATInfo> {}, found <{}>",
                    if in_list {
                        "in the <EtherCATInfoList>"
                    } else {
                        "root element"
                    },
                    String::from_utf8_lossy(e.name())
                ),
            )),
        }
    }

    /// True when the innermost element is one whose text the reader may use.
    fn collecting(&self) -> bool {
        matches!(self.stack.last(), Some(t) if *t != Tag::Other)
    }

    /// Each attribute's local name, value, and the offset of its name in the source.
    pub(super) fn attrs(&self, e: &Element) -> Result<Vec<(Vec<u8>, String, usize)>, ParseError> {
        let mut out = Vec::new();
        for a in e.attributes() {
            let a = a.map_err(|err| {
                self.ctx
                    .err(e.offset(), format!("malformed attribute: {err}"))
            })?;
            let at = a.name_offset();
            let value = a
                .value()
                .map_err(|err| {
                    self.ctx
                        .err(at, format!("malformed attribute value: {err}"))
                })?
                .into_owned();
            out.push((a.key().to_vec(), value, at));
        }
        Ok(out)
    }

    fn start(&mut self, e: &Element) -> Result<(), ParseError> {
        let tag = Tag::of(e.local_name());
        self.stack.push(tag);
        self.text.clear();
        if tag == Tag::Other {
            return Ok(());
        }
        let stack = std::mem::take(&mut self.stack);
        let result = self.on_start(&stack, tag, e);
        self.stack = stack;
        result
    }

    fn end(&mut self, offset: usize) -> Result<(), ParseError> {
        let Some(&tag) = self.stack.last() else {
            return Ok(());
        };
        let result = if tag == Tag::Other {
            Ok(())
        } else {
            let stack = std::mem::take(&mut self.stack);
            let text = std::mem::take(&mut self.text);
            let at = text.offset().unwrap_or(offset);
            let r = self.on_end(&stack, tag, text.text().trim(), at);
            self.stack = stack;
            self.text = text;
            r
        };
        self.text.clear();
        self.stack.pop();
        if self.device_depth == Some(self.stack.len()) {
            self.device_depth = None;
            if let Some(mut raw) = self.device.take() {
                if raw.in_catalogue {
                    raw.ecat.root = EsiRoot::EtherCatModule(CatalogueModule {
                        ident: raw.module_ident,
                        class: raw.module_class.clone(),
                        pdo_group: raw.module_pdo_group,
                        profile_no: raw.profile_no,
                        add_info: raw.add_info,
                        dc_op_mode_name: raw.dc_op_mode_name.clone(),
                    });
                }
                let module = raw.is_module.then(|| {
                    (
                        raw.module_ident,
                        raw.module_class.clone(),
                        raw.module_pdo_group,
                        raw.dc_op_mode_name.clone(),
                        raw.profile_no,
                        raw.add_info,
                    )
                });
                let (desc, source) = build_device(self.ctx, raw)?;
                match module {
                    Some((ident, class, pdo_group, dc_op_mode_name, profile_no, add_info)) => {
                        let ecat = desc.ethercat.unwrap_or_default();
                        self.modules.push(Module {
                            ident,
                            class,
                            pdo_group,
                            type_name: desc.identity.order_code,
                            name: desc.identity.product_name,
                            rx_pdos: ecat.rx_pdos,
                            tx_pdos: ecat.tx_pdos,
                            mailbox: ecat.mailbox,
                            profile_no,
                            add_info,
                            dictionary: desc.dictionary,
                            dc_op_mode_name,
                        });
                    }
                    None => {
                        self.done.push(desc);
                        self.sources.push(source);
                    }
                }
            }
        }
        result
    }
}
