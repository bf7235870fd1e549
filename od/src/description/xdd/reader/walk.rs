//! The element walk of the XDD reader: the cursor's nodes onto the stack of contexts, the text kept,
//! attributes, and what each start and end tag means in its context.

use super::{
    local, parse_baud, parse_type_element, show, Attr, Ctx, DtKind, IdField, Scan, TextKind,
    VersionType, MOST_SUB_INDICES,
};
use crate::error::ParseError;
use crate::xml;
use crate::xml::cursor::{Cursor, Element, Node};

impl<'a> Scan<'a> {
    pub(super) fn run(&mut self) -> Result<(), ParseError> {
        let mut cursor = Cursor::new(self.doc);
        loop {
            match cursor.next()? {
                Node::Start(e) => {
                    let ctx = self.open(&e, e.offset())?;
                    self.stack.push(ctx);
                }
                Node::End { offset } => {
                    let ctx = self.stack.pop().unwrap_or(Ctx::Document);
                    if ctx == Ctx::Document || self.stack.is_empty() {
                        return Err(self.err(offset, "closing tag without an open element"));
                    }
                    self.close(ctx, offset)?;
                }
                node @ (Node::Text(..) | Node::CData(..) | Node::Ref(..)) => {
                    if self.collecting() {
                        self.text.take(self.doc, &node)?;
                    }
                }
                Node::Eof => break,
            }
        }
        if self.stack.len() > 1 {
            return Err(self.err(
                self.doc.text().len(),
                "unexpected end of file: an element is not closed",
            ));
        }
        if !self.seen_root {
            return Err(self.err(
                0,
                "expected an ISO15745ProfileContainer element, found no element",
            ));
        }
        Ok(())
    }

    fn collecting(&self) -> bool {
        matches!(
            self.stack.last(),
            Some(Ctx::IdentityField(_) | Ctx::ProductTextDescription | Ctx::ParameterText(_))
        )
    }

    /// Calls `f` with the local name and value of every attribute of `e`.
    pub(super) fn attrs(
        &mut self,
        e: &Element<'a>,
        offset: usize,
        mut f: impl FnMut(&mut Self, &[u8], Attr<'a>) -> Result<(), ParseError>,
    ) -> Result<(), ParseError> {
        for a in e.attributes() {
            let a = match a {
                Ok(a) => a,
                Err(err) => {
                    return Err(self.err(
                        offset,
                        format!("malformed attribute in <{}>: {err}", show(e.name())),
                    ))
                }
            };
            // Literal tabs and line ends become spaces before references are resolved, so `&#10;` stays.
            let text = a
                .normalized_value()
                .map_err(|err| self.err(a.value_offset(), format!("bad attribute value: {err}")))?;
            f(
                self,
                local(a.name()),
                Attr {
                    text,
                    offset: a.value_offset(),
                },
            )?;
        }
        Ok(())
    }

    /// The value of the attribute `name` of `e`, which must be there.
    pub(super) fn required_attr(
        &mut self,
        e: &Element<'a>,
        offset: usize,
        name: &[u8],
    ) -> Result<Attr<'a>, ParseError> {
        let mut value = None;
        self.attrs(e, offset, |_, key, v| {
            if key == name {
                value = Some(v);
            }
            Ok(())
        })?;
        value.ok_or_else(|| {
            self.err(
                offset,
                format!(
                    "expected a {} attribute in <{}>",
                    show(name),
                    show(local(e.name()))
                ),
            )
        })
    }

    /// Handles a start tag in the current context and answers the context of its content.
    fn open(&mut self, e: &Element<'a>, offset: usize) -> Result<Ctx, ParseError> {
        let parent = self.stack.last().copied().unwrap_or(Ctx::Skip);
        let name = local(e.name());
        let ctx = match (parent, name) {
            (Ctx::Document, b"ISO15745ProfileContainer") => {
                self.seen_root = true;
                Ctx::Container
            }
            (Ctx::Document, other) => {
                return Err(self.err(
                    offset,
                    format!(
                        "expected an ISO15745ProfileContainer element (a CiA 311 XDD), found <{}>",
                        show(other)
                    ),
                ))
            }
            (Ctx::Container, b"ISO15745Profile") => Ctx::Profile,
            (Ctx::Profile, b"ProfileBody") => self.open_body(e, offset)?,
            (Ctx::Body, b"DeviceIdentity") => Ctx::Identity,
            (Ctx::Body, b"ApplicationProcess") => Ctx::ApplicationProcess,
            (Ctx::Body, b"ApplicationLayers") => Ctx::ApplicationLayers,
            (Ctx::Body, b"TransportLayers") => {
                self.seen_can = true;
                Ctx::TransportLayers
            }
            (Ctx::Body, b"NetworkManagement") => Ctx::NetworkManagement,
            (Ctx::Identity, field) => self.open_identity_field(e, offset, field)?,
            (Ctx::ProductText, b"description") => {
                self.text_lang_en = self.english(e, offset)?;
                Ctx::ProductTextDescription
            }
            (Ctx::ApplicationProcess, b"dataTypeList") => Ctx::DataTypeList,
            (Ctx::ApplicationProcess, b"parameterList") => Ctx::ParameterList,
            (Ctx::DataTypeList, kind @ (b"array" | b"struct" | b"enum" | b"derived")) => {
                let kind = match kind {
                    b"array" => DtKind::Array,
                    b"struct" => DtKind::Struct,
                    _ => DtKind::Simple,
                };
                self.open_data_type(e, offset, kind)?;
                Ctx::DataTypeDef
            }
            (Ctx::DataTypeDef, b"subrange") => {
                self.read_subrange(e, offset)?;
                Ctx::Skip
            }
            (Ctx::DataTypeDef | Ctx::MemberDecl, b"dataTypeIDRef") => {
                let r = self.required_attr(e, offset, b"uniqueIDRef")?;
                if let Some((_, dt)) = &mut self.data_type {
                    dt.refs.push((r.text.into_owned(), r.offset));
                }
                Ctx::Skip
            }
            (Ctx::DataTypeDef, b"varDeclaration") => {
                if let Some((_, dt)) = &mut self.data_type {
                    dt.members += 1;
                }
                Ctx::MemberDecl
            }
            (Ctx::DataTypeDef, type_name) => {
                self.data_type_base(type_name);
                Ctx::Skip
            }
            (Ctx::ParameterList, b"parameter") => {
                self.open_parameter(e, offset)?;
                Ctx::Parameter
            }
            (Ctx::Parameter, child) => self.open_parameter_child(e, offset, child)?,
            (Ctx::AllowedValues, b"range") => Ctx::Range,
            (Ctx::Range, bound @ (b"minValue" | b"maxValue")) => {
                self.read_range_bound(e, offset, bound)?;
                Ctx::Skip
            }
            (Ctx::ApplicationLayers, b"CANopenObjectList") => Ctx::ObjectList,
            (Ctx::ApplicationLayers, b"ObjectList") if self.powerlink.is_some() => Ctx::ObjectList,
            (Ctx::ApplicationLayers, b"dummyUsage") => {
                self.seen_can = true;
                Ctx::DummyUsage
            }
            (Ctx::ObjectList, b"CANopenObject") => {
                self.open_object(e, offset)?;
                Ctx::Object
            }
            (Ctx::ObjectList, b"Object") if self.powerlink.is_some() => {
                self.open_object(e, offset)?;
                Ctx::Object
            }
            (Ctx::Object, b"SubObject") if self.powerlink.is_some() => {
                self.open_sub_object(e, offset)?;
                Ctx::Skip
            }
            (Ctx::Object, b"CANopenSubObject") => {
                self.open_sub_object(e, offset)?;
                Ctx::Skip
            }
            (Ctx::DummyUsage, b"dummy") => {
                self.read_dummy(e, offset)?;
                Ctx::Skip
            }
            (Ctx::TransportLayers, b"PhysicalLayer") => Ctx::PhysicalLayer,
            (Ctx::PhysicalLayer, b"baudRate") => Ctx::BaudRate,
            (Ctx::BaudRate, b"supportedBaudRate") => {
                self.read_supported_baud_rate(e, offset)?;
                Ctx::Skip
            }
            (Ctx::NetworkManagement, b"CANopenGeneralFeatures") => {
                self.seen_can = true;
                self.read_general_features(e, offset)?;
                Ctx::Skip
            }
            (Ctx::NetworkManagement, b"CANopenMasterFeatures") => {
                self.seen_can = true;
                self.read_master_features(e, offset)?;
                Ctx::Skip
            }
            (Ctx::NetworkManagement, b"deviceCommissioning") => {
                self.read_commissioning(e, offset)?;
                Ctx::Skip
            }
            _ => Ctx::Skip,
        };
        if matches!(
            ctx,
            Ctx::IdentityField(_) | Ctx::ProductTextDescription | Ctx::ParameterText(_)
        ) {
            self.text.clear();
        }
        Ok(ctx)
    }

    /// A child of `DeviceIdentity`: the context of its content.
    fn open_identity_field(
        &mut self,
        e: &Element<'a>,
        offset: usize,
        field: &[u8],
    ) -> Result<Ctx, ParseError> {
        Ok(match field {
            b"vendorName" => Ctx::IdentityField(IdField::VendorName),
            b"vendorID" => Ctx::IdentityField(IdField::VendorId),
            b"productName" => Ctx::IdentityField(IdField::ProductName),
            b"productID" => Ctx::IdentityField(IdField::ProductId),
            b"orderNumber" => Ctx::IdentityField(IdField::OrderNumber),
            b"productText" => Ctx::ProductText,
            b"version" => {
                let mut kind = None;
                self.attrs(e, offset, |s, key, v| {
                    if key == b"versionType" {
                        kind = Some(match v.text.trim() {
                            "HW" => VersionType::Hardware,
                            "SW" => VersionType::Software,
                            "FW" => VersionType::Firmware,
                            _ => {
                                return Err(s.err(
                                    v.offset,
                                    format!(
                                        "expected versionType SW, FW or HW, found `{}`",
                                        v.text
                                    ),
                                ))
                            }
                        });
                    }
                    Ok(())
                })?;
                // CiA 311 requires the type; a version without one says nothing usable.
                kind.map_or(Ctx::Skip, |k| Ctx::IdentityField(IdField::Version(k)))
            }
            _ => Ctx::Skip,
        })
    }

    /// A type element (`UINT`, `BOOL`, ...) in a data type's definition: its base type, unless it has one
    /// or is a struct.
    fn data_type_base(&mut self, type_name: &[u8]) {
        if let (Some(t), Some((_, dt))) = (parse_type_element(type_name), &mut self.data_type) {
            if dt.base.is_none() && dt.kind != DtKind::Struct {
                dt.base = Some(t);
            }
        }
    }

    /// `minValue` or `maxValue` (`bound`) of a parameter's range: the first of each is kept.
    fn read_range_bound(
        &mut self,
        e: &Element<'a>,
        offset: usize,
        bound: &[u8],
    ) -> Result<(), ParseError> {
        let value = self.required_attr(e, offset, b"value")?;
        if let Some((_, p)) = &mut self.param {
            let slot = if bound == b"minValue" {
                &mut p.low
            } else {
                &mut p.high
            };
            if slot.is_none() {
                *slot = Some(value);
            }
        }
        Ok(())
    }

    /// `supportedBaudRate`: a bit rate the device supports.
    fn read_supported_baud_rate(
        &mut self,
        e: &Element<'a>,
        offset: usize,
    ) -> Result<(), ParseError> {
        self.attrs(e, offset, |s, key, v| {
            if key == b"value" {
                let kbps = parse_baud(&v.text).ok_or_else(|| {
                    s.err(
                        v.offset,
                        format!(
                            "expected a bit rate like \"250 Kbps\" in supportedBaudRate, found `{}`",
                            v.text
                        ),
                    )
                })?;
                if kbps != 0 {
                    s.baud_rates.insert(kbps);
                }
            }
            Ok(())
        })
    }

    /// `CANopenMasterFeatures`: whether the device is a simple boot-up master.
    fn read_master_features(&mut self, e: &Element<'a>, offset: usize) -> Result<(), ParseError> {
        self.attrs(e, offset, |s, key, v| {
            if key == b"bootUpMaster" {
                s.can.simple_boot_up_master = s.boolean(&v, "bootUpMaster")?;
            }
            Ok(())
        })
    }

    /// Handles the end of an element whose content context was `ctx`.
    fn close(&mut self, ctx: Ctx, offset: usize) -> Result<(), ParseError> {
        match ctx {
            Ctx::IdentityField(field) => {
                let text = self.text.take_text();
                match field {
                    IdField::VendorName => self.vendor_name = Some(text),
                    IdField::Version(kind) => {
                        let slot = &mut self.versions[kind as usize];
                        if slot.is_none() {
                            *slot = Some(text.trim().to_string());
                        }
                    }
                    IdField::ProductName => self.product_name = Some(text),
                    IdField::OrderNumber => {
                        if self.order_number.is_none() {
                            self.order_number = Some(text)
                        }
                    }
                    IdField::VendorId | IdField::ProductId => {
                        let what = if field == IdField::VendorId {
                            "vendorID"
                        } else {
                            "productID"
                        };
                        let value = if text.trim().is_empty() {
                            None
                        } else {
                            Some(
                                xml::parse_number(&text)
                                    .and_then(|v| u32::try_from(v).ok())
                                    .ok_or_else(|| {
                                        self.err(
                                            offset,
                                            format!(
                                                "expected a 32-bit number like 0x0000012E in <{what}>, found `{}`",
                                                text.trim()
                                            ),
                                        )
                                    })?,
                            )
                        };
                        if field == IdField::VendorId {
                            self.vendor_id = value;
                        } else {
                            self.product_id = value;
                        }
                    }
                }
            }
            Ctx::ProductTextDescription => {
                let text = self.text.take_text();
                self.product_text.offer(text, self.text_lang_en);
            }
            Ctx::ParameterText(kind) => {
                let text = self.text.take_text();
                let english = self.text_lang_en;
                if let Some((_, p)) = &mut self.param {
                    match kind {
                        TextKind::Label => p.label.offer(text, english),
                        TextKind::Description => p.description.offer(text, english),
                    }
                }
            }
            Ctx::DataTypeDef => {
                if let Some((id, dt)) = self.data_type.take() {
                    if dt.kind == DtKind::Struct && dt.members as i128 > MOST_SUB_INDICES {
                        return Err(self.err(
                            id.offset,
                            format!(
                                "{} has {} members: no RECORD holds them, CiA 301 sub-indices go \
                                 to 0xFE",
                                dt.what(&id.text),
                                dt.members
                            ),
                        ));
                    }
                    if self.data_types.contains_key(id.text.as_ref()) {
                        return Err(self.err(
                            id.offset,
                            format!(
                                "uniqueID `{}` is defined twice in the dataTypeList",
                                id.text
                            ),
                        ));
                    }
                    self.data_types.insert(id.text, dt);
                }
            }
            Ctx::Parameter => {
                if let Some((id, p)) = self.param.take() {
                    if self.params.contains_key(id.text.as_ref()) {
                        return Err(self.err(
                            id.offset,
                            format!("parameter uniqueID `{}` is defined twice", id.text),
                        ));
                    }
                    self.params.insert(id.text, p);
                }
            }
            Ctx::Object => {
                if let Some(o) = self.object.take() {
                    self.objects.push(o);
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// True when the element's `lang` attribute names English (or is absent on a single-language file).
    pub(super) fn english(&mut self, e: &Element<'a>, offset: usize) -> Result<bool, ParseError> {
        let mut english = false;
        self.attrs(e, offset, |_, key, v| {
            if key == b"lang" {
                let l = v.text.trim();
                english = l.eq_ignore_ascii_case("en")
                    || l.get(..3).is_some_and(|p| p.eq_ignore_ascii_case("en-"));
            }
            Ok(())
        })?;
        Ok(english)
    }
}
