//! The elements of an XDD read from their attributes: profile bodies, data types, parameters, objects
//! and sub-objects, dummy usage, general features and commissioning, and the attribute values they
//! share.

use std::borrow::Cow;

use super::{
    parse_access_type, parse_baud, parse_parameter_access, parse_pdo, parse_type_element, Attr,
    Ctx, DtKind, DtRec, EntryAttrs, FileAttrs, ObjRec, ParamRec, Scan, SubRec, TextKind, TypeRef,
    MOST_SUB_INDICES, STRING_LENGTH_PROPERTY,
};
use crate::device::Commissioning;
use crate::error::ParseError;
use crate::object::{ObjFlags, ObjectKind};
use crate::xml;
use crate::xml::cursor::Element;

impl<'a> Scan<'a> {
    pub(super) fn boolean(&self, v: &Attr<'_>, what: &str) -> Result<bool, ParseError> {
        xml::parse_bool(&v.text).ok_or_else(|| {
            self.err(
                v.offset,
                format!("expected true or false in {what}, found `{}`", v.text),
            )
        })
    }

    fn number<T: TryFrom<i128>>(
        &self,
        v: &Attr<'_>,
        what: &str,
        like: &str,
    ) -> Result<T, ParseError> {
        xml::parse_number(&v.text)
            .and_then(|n| T::try_from(n).ok())
            .ok_or_else(|| {
                self.err(
                    v.offset,
                    format!(
                        "expected a number like {like} in {what}, found `{}`",
                        v.text
                    ),
                )
            })
    }

    /// A number of at most `digits` hexadecimal digits, with or without `0x` (`noun`, `like` and `what`
    /// for the message). More digits whose extra ones lead and are zeros (`subIndex="0000"`, as
    /// CANopenEditor wrote sub-indices) give the same number, with a warning at the value.
    fn hex<T: TryFrom<u16>>(
        &self,
        v: &Attr<'_>,
        noun: &str,
        digits: usize,
        like: &str,
        what: &str,
    ) -> Result<T, ParseError> {
        let t = v.text.trim();
        let t = t
            .strip_prefix("0x")
            .or_else(|| t.strip_prefix("0X"))
            .unwrap_or(t);
        let t = match t.len().checked_sub(digits) {
            Some(extra) if extra > 0 && t.as_bytes()[..extra].iter().all(|&b| b == b'0') => {
                self.warn(
                    v.offset,
                    format!(
                        "{what} `{}` has {} digits where CiA 311 gives {digits}; read as {}",
                        v.text,
                        t.len(),
                        &t[extra..]
                    ),
                );
                &t[extra..]
            }
            _ => t,
        };
        (!t.is_empty() && t.len() <= digits)
            .then(|| u16::from_str_radix(t, 16).ok())
            .flatten()
            .and_then(|n| T::try_from(n).ok())
            .ok_or_else(|| {
                self.err(
                    v.offset,
                    format!(
                        "expected {noun} of {digits} hex digits like {like} in {what}, found `{}`",
                        v.text
                    ),
                )
            })
    }

    pub(super) fn open_body(&mut self, e: &Element<'a>, offset: usize) -> Result<Ctx, ParseError> {
        let mut kind: Option<Cow<'a, str>> = None;
        let mut file = FileAttrs::default();
        self.attrs(e, offset, |_, key, v| {
            let slot = match key {
                b"type" => {
                    kind = Some(v.text);
                    return Ok(());
                }
                b"fileName" => &mut file.file_name,
                b"fileVersion" => &mut file.file_version,
                b"fileCreator" => &mut file.created_by,
                b"fileCreationDate" => &mut file.creation_date,
                b"fileCreationTime" => &mut file.creation_time,
                b"fileModifiedBy" => &mut file.modified_by,
                b"fileModificationDate" => &mut file.modification_date,
                b"fileModificationTime" => &mut file.modification_time,
                _ => return Ok(()),
            };
            *slot = Some(v.text.into_owned());
            Ok(())
        })?;
        let kind = kind.as_deref().map(|k| k.rsplit(':').next().unwrap_or(k));
        match kind {
            Some("ProfileBody_Device_CANopen") => {
                if self.device_file.is_none() {
                    self.device_file = Some(file);
                }
                Ok(Ctx::Body)
            }
            Some("ProfileBody_CommunicationNetwork_CANopen") => {
                self.seen_network_body = true;
                if self.network_file.is_none() {
                    self.network_file = Some(file);
                }
                Ok(Ctx::Body)
            }
            // A body without a type is read for whatever CANopen content it has.
            None => Ok(Ctx::Body),
            // POWERLINK (EPSG DS 311) describes its object dictionary as CANopen does, in
            // `ObjectList/Object/SubObject`: read it, as openCONFIGURATOR does.
            Some(
                k @ ("ProfileBody_Device_Powerlink" | "ProfileBody_CommunicationNetwork_Powerlink"),
            ) => {
                if self.powerlink.is_none() {
                    self.powerlink = Some((offset, k.to_string()));
                }
                if self.device_file.is_none() {
                    self.device_file = Some(file);
                }
                Ok(Ctx::Body)
            }
            // Other technologies and other profile kinds.
            Some(k) => {
                self.other_bodies.push((offset, k.to_string()));
                Ok(Ctx::Skip)
            }
        }
    }

    pub(super) fn open_data_type(
        &mut self,
        e: &Element<'a>,
        offset: usize,
        kind: DtKind,
    ) -> Result<(), ParseError> {
        let mut id = None;
        let mut name = String::new();
        self.attrs(e, offset, |_, key, v| {
            match key {
                b"uniqueID" => id = Some(v),
                b"name" => name = v.text.into_owned(),
                _ => {}
            }
            Ok(())
        })?;
        // A type without a uniqueID cannot be referred to; its content is not needed.
        self.data_type = id.map(|id| {
            let offset = id.offset;
            (
                id,
                DtRec {
                    name,
                    kind,
                    base: None,
                    offset,
                    refs: Vec::new(),
                    members: 0,
                },
            )
        });
        Ok(())
    }

    /// An array's `subrange`: its elements are an ARRAY's sub-indices, `lowerLimit` to
    /// `upperLimit` (CANopenEditor counts sub-index 0 among them, CiA 311's examples start at 1);
    /// beyond 0x00–0xFE no device holds them.
    pub(super) fn read_subrange(
        &mut self,
        e: &Element<'a>,
        offset: usize,
    ) -> Result<(), ParseError> {
        let mut low = None;
        let mut high = None;
        self.attrs(e, offset, |s, key, v| {
            match key {
                b"lowerLimit" => low = Some((s.number::<i128>(&v, "lowerLimit", "1")?, v.offset)),
                b"upperLimit" => high = Some((s.number::<i128>(&v, "upperLimit", "8")?, v.offset)),
                _ => {}
            }
            Ok(())
        })?;
        let (Some((id, dt)), Some((low, low_at)), Some((high, high_at))) =
            (&self.data_type, low, high)
        else {
            return Ok(());
        };
        if low <= high && (low < 0 || high >= MOST_SUB_INDICES) {
            return Err(self.err(
                if low < 0 { low_at } else { high_at },
                format!(
                    "{} has elements {low} to {high} (subrange): no ARRAY holds them, CiA 301 \
                     sub-indices go to 0xFE",
                    dt.what(&id.text)
                ),
            ));
        }
        Ok(())
    }

    pub(super) fn open_parameter(
        &mut self,
        e: &Element<'a>,
        offset: usize,
    ) -> Result<(), ParseError> {
        let mut id = None;
        let mut param = ParamRec::new();
        self.attrs(e, offset, |s, key, v| {
            match key {
                b"uniqueID" => id = Some(v),
                b"access" => {
                    param.access = Some(parse_parameter_access(&v.text).ok_or_else(|| {
                        s.err(
                            v.offset,
                            format!(
                                "expected access const, read, write, readWrite, readWriteInput, readWriteOutput or noAccess, found `{}`",
                                v.text
                            ),
                        )
                    })?)
                }
                _ => {}
            }
            Ok(())
        })?;
        let id =
            id.ok_or_else(|| self.err(offset, "expected a uniqueID attribute in <parameter>"))?;
        self.param = Some((id, param));
        Ok(())
    }

    pub(super) fn open_parameter_child(
        &mut self,
        e: &Element<'a>,
        offset: usize,
        child: &[u8],
    ) -> Result<Ctx, ParseError> {
        match child {
            b"label" | b"description" => {
                self.text_lang_en = self.english(e, offset)?;
                Ok(Ctx::ParameterText(if child == b"label" {
                    TextKind::Label
                } else {
                    TextKind::Description
                }))
            }
            b"dataTypeIDRef" => {
                let r = self.required_attr(e, offset, b"uniqueIDRef")?;
                if let Some((_, p)) = &mut self.param {
                    p.ty = Some(TypeRef::Ref(r));
                }
                Ok(Ctx::Skip)
            }
            b"defaultValue" | b"actualValue" => {
                let value = self.required_attr(e, offset, b"value")?;
                if let Some((_, p)) = &mut self.param {
                    if child == b"defaultValue" {
                        p.default = Some(value);
                    } else {
                        p.actual = Some(value);
                    }
                }
                Ok(Ctx::Skip)
            }
            b"allowedValues" => Ok(Ctx::AllowedValues),
            b"property" => {
                let mut name = None;
                let mut value = None;
                self.attrs(e, offset, |_, key, v| {
                    match key {
                        b"name" => name = Some(v),
                        b"value" => value = Some(v),
                        _ => {}
                    }
                    Ok(())
                })?;
                if let (Some(name), Some(value)) = (name, value) {
                    if name.text == STRING_LENGTH_PROPERTY {
                        let n: u32 = self.number(&value, STRING_LENGTH_PROPERTY, "16")?;
                        if n > u32::MAX / 8 {
                            return Err(self.err(value.offset, "string length too large"));
                        }
                        if let Some((_, p)) = &mut self.param {
                            p.capacity = Some(n);
                        }
                    }
                }
                Ok(Ctx::Skip)
            }
            type_name => {
                if let (Some(t), Some((_, p))) = (parse_type_element(type_name), &mut self.param) {
                    if p.ty.is_none() {
                        p.ty = Some(TypeRef::Simple(t));
                    }
                }
                Ok(Ctx::Skip)
            }
        }
    }

    /// Reads the attributes an object and a sub-object share into `attrs`; answers the other ones.
    fn entry_attr(
        &self,
        attrs: &mut EntryAttrs<'a>,
        key: &[u8],
        v: Attr<'a>,
    ) -> Result<Option<Attr<'a>>, ParseError> {
        match key {
            b"dataType" => {
                let index = self.hex(&v, "a data type index", 4, "0007", "dataType")?;
                attrs.data_type = Some((index, v.offset));
            }
            b"accessType" => {
                attrs.access = Some(parse_access_type(&v.text).ok_or_else(|| {
                    self.err(
                        v.offset,
                        format!(
                            "expected accessType ro, wo, rw, rwr, rww or const, found `{}`",
                            v.text
                        ),
                    )
                })?)
            }
            b"PDOmapping" => {
                attrs.pdo = parse_pdo(&v.text).ok_or_else(|| {
                    self.err(
                        v.offset,
                        format!(
                            "expected PDOmapping no, default, optional, RPDO or TPDO, found `{}`",
                            v.text
                        ),
                    )
                })?
            }
            b"defaultValue" => attrs.default = Some(v),
            b"lowLimit" => attrs.low = Some(v),
            b"highLimit" => attrs.high = Some(v),
            b"actualValue" => attrs.actual = Some(v),
            b"uniqueIDRef" => attrs.unique_id_ref = Some(v),
            b"objFlags" => attrs.flags = self.obj_flags(&v),
            _ => return Ok(Some(v)),
        }
        Ok(None)
    }

    /// `objFlags` (CiA 311, hexBinary: CiA 306 §4.6.3 `ObjFlags`, bit 0 refuse write on download, bit 1
    /// refuse read on scan): up to 8 hexadecimal digits (a `0x` before them is taken too). Other text
    /// is read as no flags with a warning at the value, as the EDS reader reads `ObjFlags=NV`.
    fn obj_flags(&self, v: &Attr<'_>) -> Option<ObjFlags> {
        let t = v.text.trim();
        let digits = t
            .strip_prefix("0x")
            .or_else(|| t.strip_prefix("0X"))
            .unwrap_or(t);
        let bits = (digits.len() <= 8 && digits.bytes().all(|b| b.is_ascii_hexdigit()))
            .then(|| u32::from_str_radix(digits, 16).ok())
            .flatten();
        if bits.is_none() {
            self.warn(
                v.offset,
                format!(
                    "objFlags `{}` is no hexBinary number of 32 bits; read as no flags",
                    v.text
                ),
            );
        }
        bits.map(ObjFlags::from_bits)
    }

    fn object_kind(&self, v: &Attr<'_>) -> Result<ObjectKind, ParseError> {
        xml::parse_number(&v.text)
            .and_then(|c| u8::try_from(c).ok())
            .and_then(ObjectKind::from_code)
            .ok_or_else(|| {
                self.err(
                    v.offset,
                    format!(
                        "expected objectType 0, 2, 5, 6, 7, 8 or 9 (NULL, DOMAIN, DEFTYPE, DEFSTRUCT, VAR, ARRAY, RECORD), found `{}`",
                        v.text
                    ),
                )
            })
    }

    pub(super) fn open_object(&mut self, e: &Element<'a>, offset: usize) -> Result<(), ParseError> {
        let mut attrs = EntryAttrs::default();
        let mut index = None;
        let mut name: Cow<'a, str> = Cow::Borrowed("");
        let mut kind = None;
        let mut sub_number = None;
        self.attrs(e, offset, |s, key, v| {
            let Some(v) = s.entry_attr(&mut attrs, key, v)? else {
                return Ok(());
            };
            match key {
                b"index" => index = Some(s.hex(&v, "an index", 4, "1A00", "index")?),
                b"name" => name = v.text,
                b"objectType" => kind = Some(s.object_kind(&v)?),
                b"subNumber" => sub_number = xml::parse_number(&v.text).map(|n| (n, v.offset)),
                _ => {}
            }
            Ok(())
        })?;
        let index = index
            .ok_or_else(|| self.err(offset, "expected an index attribute in <CANopenObject>"))?;
        let kind = kind.ok_or_else(|| {
            self.err(
                offset,
                format!("expected an objectType attribute in <CANopenObject> 0x{index:04X}"),
            )
        })?;
        // The number of sub-objects: at most one for each sub-index, 0x00 to 0xFF (the entry at
        // 0xFF, which describes the object's structure, included). A subNumber that is no number
        // is not read.
        if let Some((n, at)) = sub_number.filter(|(n, _)| !(0..=0x100).contains(n)) {
            return Err(self.err(
                at,
                format!(
                    "object 0x{index:04X} declares {n} sub-objects (subNumber): no object holds \
                     them, sub-indices go to 0xFF"
                ),
            ));
        }
        self.object = Some(ObjRec {
            offset,
            index,
            name,
            kind,
            attrs,
            subs: Vec::new(),
        });
        Ok(())
    }

    pub(super) fn open_sub_object(
        &mut self,
        e: &Element<'a>,
        offset: usize,
    ) -> Result<(), ParseError> {
        let mut attrs = EntryAttrs::default();
        let mut sub = None;
        let mut name: Cow<'a, str> = Cow::Borrowed("");
        self.attrs(e, offset, |s, key, v| {
            let Some(v) = s.entry_attr(&mut attrs, key, v)? else {
                return Ok(());
            };
            match key {
                b"subIndex" => sub = Some(s.hex(&v, "a sub-index", 2, "01", "subIndex")?),
                b"name" => name = v.text,
                b"objectType" => {
                    s.object_kind(&v)?;
                }
                _ => {}
            }
            Ok(())
        })?;
        let sub = sub.ok_or_else(|| {
            self.err(
                offset,
                "expected a subIndex attribute in <CANopenSubObject>",
            )
        })?;
        if let Some(o) = &mut self.object {
            o.subs.push(SubRec {
                offset,
                sub,
                name,
                attrs,
            });
        }
        Ok(())
    }

    pub(super) fn read_dummy(&mut self, e: &Element<'a>, offset: usize) -> Result<(), ParseError> {
        self.attrs(e, offset, |s, key, v| {
            if key != b"entry" {
                return Ok(());
            }
            let bad = || {
                s.err(
                    v.offset,
                    format!(
                        "expected a dummy entry like Dummy0005=1, found `{}`",
                        v.text
                    ),
                )
            };
            let t = v.text.trim();
            let (name, used) = t.split_once('=').ok_or_else(bad)?;
            let name = name.trim();
            let digits = name
                .get(..5)
                .filter(|p| p.eq_ignore_ascii_case("dummy"))
                .and_then(|_| name.get(5..))
                .filter(|d| d.len() == 4)
                .ok_or_else(bad)?;
            let index = u16::from_str_radix(digits, 16).map_err(|_| bad())?;
            let used = match used.trim() {
                "1" => true,
                "0" => false,
                _ => return Err(bad()),
            };
            s.dummies.insert(index, used);
            Ok(())
        })
    }

    pub(super) fn read_general_features(
        &mut self,
        e: &Element<'a>,
        offset: usize,
    ) -> Result<(), ParseError> {
        self.attrs(e, offset, |s, key, v| {
            match key {
                b"granularity" => {
                    let g: u8 = s.number(&v, "granularity", "8")?;
                    if g > 64 {
                        return Err(s.err(
                            v.offset,
                            format!("expected a granularity of 0 to 64 bits, found `{}`", v.text),
                        ));
                    }
                    s.can.granularity = g;
                }
                b"nrOfRxPDO" => s.can.nr_of_rx_pdo = s.number(&v, "nrOfRxPDO", "4")?,
                b"nrOfTxPDO" => s.can.nr_of_tx_pdo = s.number(&v, "nrOfTxPDO", "4")?,
                b"dynamicChannels" => {
                    s.can.dynamic_channels = s.number(&v, "dynamicChannels", "0")?
                }
                b"bootUpSlave" => s.can.simple_boot_up_slave = s.boolean(&v, "bootUpSlave")?,
                b"groupMessaging" => s.can.group_messaging = s.boolean(&v, "groupMessaging")?,
                b"layerSettingServiceSlave" => {
                    s.can.lss_supported = s.boolean(&v, "layerSettingServiceSlave")?
                }
                _ => {}
            }
            Ok(())
        })
    }

    pub(super) fn read_commissioning(
        &mut self,
        e: &Element<'a>,
        offset: usize,
    ) -> Result<(), ParseError> {
        let mut c = Commissioning::default();
        let mut has_node_id = false;
        self.attrs(e, offset, |s, key, v| {
            match key {
                // CANopenEditor writes `NodeID`.
                b"nodeID" | b"NodeID" => {
                    has_node_id = true;
                    // 0 (as tools write a node not yet configured), 255 (CiA 305's "not
                    // configured") and an empty value (python-canopen reads it as none) give the
                    // node no node-ID: one LSS configures.
                    let id: Option<u8> = if v.text.trim().is_empty() {
                        None
                    } else {
                        Some(s.number(&v, "nodeID", "5")?)
                    };
                    let Some(id) = id.filter(|id| *id != 0 && *id != 255) else {
                        let given = if id.is_none() {
                            "nodeID is empty, which".to_string()
                        } else {
                            format!("nodeID `{}`", v.text)
                        };
                        s.warn(
                            v.offset,
                            format!(
                                "{given} is no node-ID (1 to 127); read as none, a node LSS \
                                 configures"
                            ),
                        );
                        return Ok(());
                    };
                    if !(1..=127).contains(&id) {
                        return Err(s.err(
                            v.offset,
                            format!("expected a nodeID of 1 to 127, found `{}`", v.text),
                        ));
                    }
                    c.node_id = Some(id);
                }
                b"nodeName" => c.node_name = v.text.into_owned(),
                b"actualBaudRate" => {
                    c.baud_rate = parse_baud(&v.text).ok_or_else(|| {
                        s.err(
                            v.offset,
                            format!(
                            "expected a bit rate like \"250 Kbps\" in actualBaudRate, found `{}`",
                            v.text
                        ),
                        )
                    })?
                }
                b"networkNumber" => c.net_number = s.number(&v, "networkNumber", "1")?,
                b"networkName" => c.network_name = v.text.into_owned(),
                b"CANopenManager" => c.canopen_manager = s.boolean(&v, "CANopenManager")?,
                _ => {}
            }
            Ok(())
        })?;
        if !has_node_id {
            return Err(self.err(
                offset,
                "expected a nodeID attribute in <deviceCommissioning>",
            ));
        }
        self.commissioning = Some(c);
        Ok(())
    }
}
