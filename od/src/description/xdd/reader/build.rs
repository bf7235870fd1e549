//! The end of the pass: `uniqueIDRef`s resolved, objects and entries built, values parsed, and the
//! description put together.

use super::{
    has_string_capacity, is_text_type, strip_node_id, Attr, DtKind, DtRec, EntryAttrs, ObjRec,
    ParamRec, Scan, TypeRef, XddType,
};
use crate::device::{DeviceDescription, FileInfo};
use crate::dict::Dictionary;
use crate::error::ParseError;
use crate::object::{AccessType, DefaultValue, Object, ObjectKind, SubObject};
use crate::report::Finding;
use crate::types::DataType;
use crate::value::Value;

impl<'a> Scan<'a> {
    /// Resolves the references and builds the description.
    pub(super) fn finish(mut self) -> Result<(DeviceDescription, Vec<Finding>), ParseError> {
        self.check_data_types()?;
        let node_id = self
            .commissioning
            .as_ref()
            .and_then(|c| c.node_id)
            .unwrap_or(0);
        let mut dictionary = Dictionary::new();
        let objects = std::mem::take(&mut self.objects);
        for o in &objects {
            let object = self.build_object(o, node_id)?;
            if dictionary.insert(object).is_some() {
                return Err(self.err(
                    o.offset,
                    format!("object 0x{:04X} is defined twice", o.index),
                ));
            }
        }

        let file = self
            .device_file
            .take()
            .or(self.network_file.take())
            .unwrap_or_default();
        let file_info = FileInfo {
            file_name: file.file_name.unwrap_or_default(),
            file_version: file.file_version.unwrap_or_default(),
            description: self.product_text.text.take().unwrap_or_default(),
            creation_time: file.creation_time.unwrap_or_default(),
            creation_date: file.creation_date.unwrap_or_default(),
            created_by: file.created_by.unwrap_or_default(),
            modification_time: file.modification_time.unwrap_or_default(),
            modification_date: file.modification_date.unwrap_or_default(),
            modified_by: file.modified_by.unwrap_or_default(),
            ..FileInfo::default()
        };

        let default_u32 = |sub: u8| -> Option<u32> {
            let d = dictionary.object(0x1018)?.sub(sub)?.default.as_ref()?;
            if d.plus_node_id {
                return None;
            }
            d.value.as_i128().and_then(|v| u32::try_from(v).ok())
        };
        let mut desc = DeviceDescription::default();
        desc.identity.vendor_name = self.vendor_name.take().unwrap_or_default();
        desc.identity.product_name = self.product_name.take().unwrap_or_default();
        desc.identity.order_code = self.order_number.take().unwrap_or_default();
        let [hardware, software, firmware] = std::mem::take(&mut self.versions);
        desc.identity.hardware_version = hardware.unwrap_or_default();
        desc.identity.software_version = software.unwrap_or_default();
        desc.identity.firmware_version = firmware.unwrap_or_default();
        desc.identity.vendor_id = self.vendor_id.or_else(|| default_u32(1)).unwrap_or(0);
        desc.identity.product_code = self.product_id.or_else(|| default_u32(2)).unwrap_or(0);
        desc.identity.revision = default_u32(3).unwrap_or(0);
        desc.file_info = file_info;
        if self.seen_network_body && self.seen_can {
            let mut can = std::mem::take(&mut self.can);
            can.baud_rates = std::mem::take(&mut self.baud_rates).into_iter().collect();
            can.dummy_usage = std::mem::take(&mut self.dummies)
                .into_iter()
                .filter_map(|(index, used)| used.then_some(index))
                .collect();
            desc.can = Some(can);
        }
        desc.commissioning = self.commissioning.take();
        desc.dictionary = dictionary;
        Ok((desc, self.doc.take_findings()))
    }

    /// The `dataTypeIDRef`s between the types of the `dataTypeList`: each names a type, and none
    /// leads back to the type it is in (a type made of itself has no size). A depth-first walk
    /// without recursion, in file order, each type and reference looked at once.
    fn check_data_types(&self) -> Result<(), ParseError> {
        let mut types: Vec<(&str, &DtRec)> = self
            .data_types
            .iter()
            .map(|(id, dt)| (id.as_ref(), dt))
            .collect();
        types.sort_by_key(|(_, dt)| dt.offset);
        let number: std::collections::HashMap<&str, usize> = types
            .iter()
            .enumerate()
            .map(|(k, (id, _))| (*id, k))
            .collect();
        let mut edges: Vec<Vec<(usize, usize)>> = Vec::with_capacity(types.len());
        for (_, dt) in &types {
            let mut to = Vec::with_capacity(dt.refs.len());
            for (r, at) in &dt.refs {
                let Some(&k) = number.get(r.as_str()) else {
                    return Err(self.err(
                        *at,
                        format!("dataTypeIDRef `{r}` names no type of the dataTypeList"),
                    ));
                };
                to.push((k, *at));
            }
            edges.push(to);
        }
        #[derive(Clone, Copy, PartialEq)]
        enum Seen {
            Not,
            OnPath,
            Done,
        }
        let mut seen = vec![Seen::Not; types.len()];
        // The path walked: each type with the number of its references looked at; the last one
        // looked at is the way to the next type on the path.
        let mut path: Vec<(usize, usize)> = Vec::new();
        for root in 0..types.len() {
            if seen[root] != Seen::Not {
                continue;
            }
            seen[root] = Seen::OnPath;
            path.push((root, 0));
            while let Some(top) = path.last_mut() {
                let (v, next) = *top;
                let Some(&(w, _)) = edges[v].get(next) else {
                    seen[v] = Seen::Done;
                    path.pop();
                    continue;
                };
                top.1 += 1;
                match seen[w] {
                    Seen::Not => {
                        seen[w] = Seen::OnPath;
                        path.push((w, 0));
                    }
                    Seen::Done => {}
                    Seen::OnPath => {
                        let from = path.iter().position(|(t, _)| *t == w).expect("on the path");
                        let (start, taken) = path[from];
                        let at = edges[start][taken - 1].1;
                        // A long way round is named by its first four types and its last.
                        let way = &path[from + 1..];
                        let name = |(t, _): &(usize, usize)| format!("`{}`", types[*t].0);
                        let mut through: Vec<String> = way.iter().take(4).map(name).collect();
                        if way.len() > 5 {
                            through.push(format!("… ({} more)", way.len() - 5));
                        }
                        through.extend(
                            way.iter()
                                .skip(4.max(way.len().saturating_sub(1)))
                                .map(name),
                        );
                        let what = format!("data type {}", types[w].1.label(types[w].0));
                        return Err(self.err(
                            at,
                            if through.is_empty() {
                                format!("{what} refers to itself")
                            } else {
                                format!("{what} refers to itself through {}", through.join(" → "))
                            },
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// How an entry whose `dataType` is no CiA 301 basic type is read: the POWERLINK types (EPSG DS
    /// 301 §6.1.4: MAC_ADDRESS, IP_ADDRESS, NETTIME) as the basic types of their size, anything else
    /// (a complex or profile type) as DOMAIN, as EDS readers take them.
    fn other_type(&self, index: u16) -> (DataType, Option<u32>, &'static str) {
        match (index, self.powerlink.is_some()) {
            (0x0401, true) => (
                DataType::OctetString,
                Some(48),
                "the POWERLINK MAC_ADDRESS (6 octets)",
            ),
            (0x0402, true) => (
                DataType::Unsigned32,
                None,
                "the POWERLINK IP_ADDRESS (4 octets)",
            ),
            (0x0403, true) => (
                DataType::Unsigned64,
                None,
                "the POWERLINK NETTIME (seconds and nanoseconds, 8 octets)",
            ),
            (0x0020..=0x025F, _) => (DataType::Domain, None, "a complex or profile data type"),
            _ => (DataType::Domain, None, "not a CiA 301 data type"),
        }
    }

    /// A warning at byte `offset`.
    pub(super) fn warn(&self, offset: usize, message: String) {
        self.doc.warn(offset, message);
    }

    fn param(&self, r: &Option<Attr<'a>>) -> Result<Option<&ParamRec<'a>>, ParseError> {
        let Some(r) = r else { return Ok(None) };
        match self.params.get(r.text.as_ref()) {
            Some(p) => Ok(Some(p)),
            None => Err(self.err(
                r.offset,
                format!(
                    "uniqueIDRef `{}` names no parameter of the parameterList",
                    r.text
                ),
            )),
        }
    }

    fn data_type_def(&self, r: &Attr<'a>) -> Result<&DtRec, ParseError> {
        self.data_types.get(r.text.as_ref()).ok_or_else(|| {
            self.err(
                r.offset,
                format!(
                    "dataTypeIDRef `{}` names no type of the dataTypeList",
                    r.text
                ),
            )
        })
    }

    fn build_object(&self, o: &ObjRec<'a>, node_id: u8) -> Result<Object, ParseError> {
        let param = self.param(&o.attrs.unique_id_ref)?;
        let mut object = Object::structured(o.index, o.name.as_ref(), o.kind);
        object.description = param.and_then(|p| p.description(&o.name));
        object.flags = o.attrs.flags;
        // The element type that subs without a type of their own take (an array's element type).
        let mut element_type = None;
        if let Some(TypeRef::Ref(r)) = param.and_then(|p| p.ty.as_ref()) {
            let dt = self.data_type_def(r)?;
            if o.kind.has_subs() && dt.kind != DtKind::Simple {
                object.type_name = Some(dt.name.clone());
            }
            element_type = dt.base;
        } else if let Some(TypeRef::Simple(t)) = param.and_then(|p| p.ty.as_ref()) {
            if o.kind.has_subs() {
                element_type = Some(*t);
            }
        }

        if !o.subs.is_empty() {
            for s in &o.subs {
                let sub_param = self.param(&s.attrs.unique_id_ref)?;
                let fallback = if o.kind.has_subs() && s.sub == 0 {
                    Some(XddType::Basic(DataType::Unsigned8))
                } else {
                    element_type
                };
                let mut entry = self.build_entry(
                    o, s.sub, &s.name, &s.attrs, sub_param, fallback, s.offset, node_id,
                )?;
                entry.description = sub_param.and_then(|p| p.description(&s.name));
                entry.flags = s.attrs.flags;
                if object.subs.insert(s.sub, entry).is_some() {
                    return Err(self.err(
                        s.offset,
                        format!(
                            "sub-index {:02X} of object 0x{:04X} is defined twice",
                            s.sub, o.index
                        ),
                    ));
                }
            }
        } else if !o.kind.has_subs() && o.kind != ObjectKind::Null {
            let mut entry =
                self.build_entry(o, 0, &o.name, &o.attrs, param, None, o.offset, node_id)?;
            entry.description = object.description.clone();
            object.subs.insert(0, entry);
        }
        Ok(object)
    }

    #[allow(clippy::too_many_arguments)]
    fn build_entry(
        &self,
        o: &ObjRec<'a>,
        sub: u8,
        name: &str,
        attrs: &EntryAttrs<'a>,
        param: Option<&ParamRec<'a>>,
        fallback: Option<XddType>,
        offset: usize,
        node_id: u8,
    ) -> Result<SubObject, ParseError> {
        let at = format!("0x{:04X}:{sub:02X}", o.index);
        let default = attrs
            .default
            .as_ref()
            .or(param.and_then(|p| p.default.as_ref()));

        // Data type: the dataType attribute, else the parameter's type, else the array's element type.
        let mut capacity = None;
        let data_type = if let Some((index, off)) = attrs.data_type {
            match DataType::from_index(index) {
                Some(t) => t,
                None => {
                    let (t, bits, what) = self.other_type(index);
                    capacity = bits;
                    self.warn(
                        off,
                        format!("dataType {index:04X} of {at} is {what}; the entry is read as {t}"),
                    );
                    t
                }
            }
        } else {
            let xt = match param.and_then(|p| p.ty.as_ref()) {
                Some(TypeRef::Simple(t)) => Some(*t),
                Some(TypeRef::Ref(r)) => {
                    let dt = self.data_type_def(r)?;
                    if dt.kind != DtKind::Simple {
                        return Err(self.err(
                            r.offset,
                            format!(
                                "{at} has the structured type `{}`; expected a basic type for a value",
                                r.text
                            ),
                        ));
                    }
                    dt.base
                }
                None => None,
            }
            .or(fallback);
            match xt {
                Some(XddType::Basic(t)) => t,
                Some(XddType::BitString) => {
                    let has_default = default.is_some_and(|d| !d.text.trim().is_empty());
                    if o.kind == ObjectKind::Domain || !has_default {
                        DataType::Domain
                    } else {
                        DataType::OctetString
                    }
                }
                None => {
                    return Err(self.err(
                        offset,
                        format!(
                            "no data type for {at}: expected a dataType attribute or a uniqueIDRef to a parameter with a type"
                        ),
                    ))
                }
            }
        };

        // The object's accessType wins, except that the parameter may refine `rw` into `rwr` or `rww`,
        // which the schema's accessType cannot say.
        let param_access = param.and_then(|p| p.access);
        let access = match (attrs.access, param_access) {
            (Some(AccessType::Rw), Some(refined @ (AccessType::Rwr | AccessType::Rww))) => refined,
            (Some(a), _) => a,
            (None, Some(a)) => a,
            (None, None) => AccessType::Ro,
        };
        let mut entry = SubObject::new(name, data_type, access);
        entry.pdo = attrs.pdo;

        if let Some(d) = default {
            let read = self.parse_default(data_type, d, &at);
            entry.default = self.or_dropped(d, read, "the default is dropped");
        }
        let low = attrs.low.as_ref().or(param.and_then(|p| p.low.as_ref()));
        let high = attrs.high.as_ref().or(param.and_then(|p| p.high.as_ref()));
        if let Some(l) = low {
            let read = self.parse_value(data_type, l, "lowLimit", &at);
            entry.low = self.or_dropped(l, read, "the limit is dropped");
        }
        if let Some(h) = high {
            let read = self.parse_value(data_type, h, "highLimit", &at);
            entry.high = self.or_dropped(h, read, "the limit is dropped");
        }
        if has_string_capacity(data_type) {
            if let Some(cap) = param.and_then(|p| p.capacity) {
                let default_len = entry
                    .default
                    .as_ref()
                    .and_then(|d| d.value.encode(data_type).ok())
                    .map_or(0, |b| b.len());
                let bytes = (cap as usize).max(default_len);
                entry.bit_size = u32::try_from(bytes).ok().and_then(|b| b.checked_mul(8));
            }
        }
        if capacity.is_some() {
            entry.bit_size = capacity;
        }
        entry.reset(node_id);
        let actual = attrs
            .actual
            .as_ref()
            .or(param.and_then(|p| p.actual.as_ref()));
        if let Some(a) = actual {
            let read = self
                .parse_value(data_type, a, "actualValue", &at)
                .and_then(|v| {
                    v.map(|v| {
                        v.encode(data_type).map_err(|e| {
                            self.err(a.offset, format!("actualValue of {at} does not fit: {e}"))
                        })
                    })
                    .transpose()
                });
            if let Some(bytes) = self.or_dropped(a, read, "the value is dropped") {
                entry.value = bytes;
                entry.value_set = true;
            }
        }
        Ok(entry)
    }

    /// The value `read` from `v`, or none where `v` is no value of the entry's type: the file is
    /// still usable without it, so it is left out (`dropped` says what) with a warning at the
    /// value, as the EDS reader and python-canopen leave out theirs.
    fn or_dropped<T>(
        &self,
        v: &Attr<'_>,
        read: Result<Option<T>, ParseError>,
        dropped: &str,
    ) -> Option<T> {
        match read {
            Ok(value) => value,
            Err(e) => {
                self.warn(v.offset, format!("{}; {dropped}", e.message));
                None
            }
        }
    }

    fn parse_value(
        &self,
        t: DataType,
        v: &Attr<'_>,
        what: &str,
        at: &str,
    ) -> Result<Option<Value>, ParseError> {
        if !is_text_type(t) && v.text.trim().is_empty() {
            return Ok(None);
        }
        let value = Value::parse_text(t, &v.text).map_err(|e| {
            self.err(
                v.offset,
                format!(
                    "expected a {t} value in {what} of {at}, found `{}`: {e}",
                    v.text
                ),
            )
        })?;
        if matches!(value, Value::Real32(f) if !f.is_finite()) {
            return Err(self.err(
                v.offset,
                format!("{what} of {at} is beyond the range of REAL32: `{}`", v.text),
            ));
        }
        Ok(Some(value))
    }

    fn parse_default(
        &self,
        t: DataType,
        v: &Attr<'_>,
        at: &str,
    ) -> Result<Option<DefaultValue>, ParseError> {
        if !is_text_type(t) {
            if v.text.trim().is_empty() {
                return Ok(None);
            }
            if let Some(rest) = strip_node_id(&v.text) {
                let value = if rest.is_empty() {
                    Ok(Value::zero(t))
                } else {
                    Value::parse_text(t, rest)
                };
                let value = value.ok().filter(|_| t.is_signed() || t.is_unsigned());
                return match value {
                    // The default must fit for every node-ID, up to 127.
                    Some(value) => match (DefaultValue { value, plus_node_id: true }) {
                        d if d.resolve(127).encode(t).is_ok() => Ok(Some(d)),
                        _ => Err(self.err(
                            v.offset,
                            format!(
                                "defaultValue of {at} ({t}): `{}` does not fit with node-ID 127",
                                v.text
                            ),
                        )),
                    },
                    None => Err(self.err(
                        v.offset,
                        format!(
                            "expected an integer offset like $NODEID+0x180 in defaultValue of {at} ({t}), found `{}`",
                            v.text
                        ),
                    )),
                };
            }
        }
        Ok(self
            .parse_value(t, v, "defaultValue", at)?
            .map(DefaultValue::plain))
    }
}
