//! Objects and sub-objects of an EDS/DCF: their sections' keys, object codes, data types and values.

use super::{
    c_suffix, dropped, shown, split_node_id, Builder, Entry, Fields, ObjectSections, Section,
    Typed, OBJECT_KEYS, OBJECT_KINDS, OBJ_ACCESS, OBJ_COMPACT, OBJ_DATA_TYPE, OBJ_DEFAULT,
    OBJ_FLAGS, OBJ_HIGH, OBJ_LOW, OBJ_NAME, OBJ_PDO, OBJ_SUB_NUMBER, OBJ_TYPE, OBJ_VALUE,
};
use crate::error::ParseError;
use crate::object::{AccessType, DefaultValue, Object, ObjectKind, PdoMapping, SubObject};
use crate::types::{DataType, STANDARD_TYPES};
use crate::value::{parse_integer, Value};

impl<'i, 'a> Builder<'i, 'a> {
    pub(super) fn object(
        &self,
        index: u16,
        main: &Section<'a>,
        sections: &ObjectSections,
        node_id: Option<u8>,
    ) -> Result<Object, ParseError> {
        let fields = self.fields(main, OBJECT_KEYS)?;
        let name = fields[OBJ_NAME]
            .ok_or_else(|| self.missing(main, "ParameterName", "the object's name"))?
            .value;
        let kind = match fields[OBJ_TYPE].filter(|e| !e.value.is_empty()) {
            None => ObjectKind::Var,
            Some(e) => self.object_kind(main, e)?,
        };
        self.number::<u8>(
            main,
            fields[OBJ_SUB_NUMBER],
            "a number of sub-indices, 0 to 255",
            0,
        )?;
        let mut object = Object::structured(index, name, kind);
        object.flags = self.object_flags(main, fields[OBJ_FLAGS]);
        if !kind.has_subs() {
            if let Some(sub) = sections.subs.values().next().and_then(|&i| self.section(i)) {
                return Err(self.ini.error(
                    sub.name,
                    format!(
                        "section [{}] describes a sub-index of a {kind} object; only ARRAY, RECORD and DEFSTRUCT objects have them",
                        sub.name
                    ),
                ));
            }
            if kind == ObjectKind::Null && fields[OBJ_DATA_TYPE].is_none() {
                return Ok(object);
            }
            let sub = self.sub_object(main, &fields, name.to_string(), node_id, None)?;
            object.subs.insert(0, sub);
            return Ok(object);
        }
        let compact: u8 = self.number(
            main,
            fields[OBJ_COMPACT],
            "a number of compact sub-indices, 0 to 254",
            0,
        )?;
        if compact == 255 {
            if let Some(e) = fields[OBJ_COMPACT] {
                // CiA 301 keeps sub-index 0xFF for the object's structure, so an ARRAY has at most 254
                // entries; python-canopen's receiver.eds has 255 all the same, and Lely builds them.
                self.warn(
                    e.value,
                    format!(
                        "CompactSubObj= in [{}]: 255 entries reach sub-index 0xFF, which CiA 301 keeps for the object's structure; read as 255 entries, as Lely does",
                        main.name
                    ),
                );
            }
        }
        if compact > 0 {
            let names = match sections.names.and_then(|i| self.section(i)) {
                Some(section) => Some((section, self.numbered(section, "")?)),
                None => None,
            };
            let values = match sections.values.and_then(|i| self.section(i)) {
                Some(section) => Some((section, self.numbered(section, "")?)),
                None => None,
            };
            for section in [&names, &values].into_iter().flatten() {
                let [count] = self.fields(section.0, ["NrOfEntries"])?;
                self.number::<u8>(section.0, count, "a number of entries, 0 to 254", 0)?;
            }
            object.subs.insert(
                0,
                SubObject::new("NrOfObjects", DataType::Unsigned8, AccessType::Ro)
                    .with_default(Value::Uint(u64::from(compact))),
            );
            for n in 1..=compact {
                let key = u32::from(n);
                let sub_name = names
                    .as_ref()
                    .and_then(|(_, map)| map.get(&key))
                    .map_or_else(|| format!("{name}{n}"), |e| e.value.to_string());
                let value = values
                    .as_ref()
                    .and_then(|(section, map)| map.get(&key).map(|e| (*section, *e)));
                let sub = self.sub_object(main, &fields, sub_name, node_id, value)?;
                object.subs.insert(n, sub);
            }
        }
        for (&sub_index, &i) in &sections.subs {
            let Some(section) = self.section(i) else {
                continue;
            };
            let sub_fields = self.fields(section, OBJECT_KEYS)?;
            let sub_name = sub_fields[OBJ_NAME]
                .ok_or_else(|| self.missing(section, "ParameterName", "the entry's name"))?
                .value;
            let mut sub =
                self.sub_object(section, &sub_fields, sub_name.to_string(), node_id, None)?;
            sub.flags = self.object_flags(section, sub_fields[OBJ_FLAGS]);
            object.subs.insert(sub_index, sub);
        }
        Ok(object)
    }

    /// One entry from the keys of `section`. `value` replaces the section's `ParameterValue` (the
    /// `[xxxxValue]` entry of a compact array).
    fn sub_object(
        &self,
        section: &Section<'a>,
        fields: &Fields<'i, 'a, 12>,
        name: String,
        node_id: Option<u8>,
        value: Option<(&Section<'a>, &Entry<'a>)>,
    ) -> Result<SubObject, ParseError> {
        let data_type = fields[OBJ_DATA_TYPE]
            .ok_or_else(|| {
                self.missing(section, "DataType", "a CiA 301 data type index like 0x0007")
            })
            .and_then(|e| self.data_type(section, e))?;
        let access = fields[OBJ_ACCESS]
            .ok_or_else(|| self.missing(section, "AccessType", "ro, wo, rw, rwr, rww or const"))?;
        let access = match AccessType::parse(access.value) {
            Some(a) => a,
            None => {
                // `R` and `W` alone (can2mqtt's files): python-canopen reads them as readable and
                // writable.
                let single = match access.value.trim() {
                    "r" | "R" => Some(AccessType::Ro),
                    "w" | "W" => Some(AccessType::Wo),
                    _ => None,
                };
                let Some(a) = single else {
                    return Err(self.bad(section, access, "ro, wo, rw, rwr, rww or const"));
                };
                self.warn(
                    access.value,
                    format!(
                        "AccessType={} in [{}] is no CiA 306 access type; read as {a}",
                        access.value.trim(),
                        section.name
                    ),
                );
                a
            }
        };
        let mappable = self.flag(section, fields[OBJ_PDO], false)?;
        let mut sub = SubObject::new(name, data_type, access);
        if mappable {
            sub.pdo = match access {
                AccessType::Ro | AccessType::Const | AccessType::Rwr => PdoMapping::Tpdo,
                AccessType::Wo | AccessType::Rww => PdoMapping::Rpdo,
                AccessType::Rw => PdoMapping::Both,
            };
        }
        if let Some(e) = fields[OBJ_DEFAULT] {
            if let Some((value, plus_node_id)) = self.typed(section, e, data_type, true) {
                let default = DefaultValue {
                    value,
                    plus_node_id,
                };
                if let Some(bytes) = self.resolved(section, e, &default, data_type, node_id) {
                    sub.value = bytes;
                    sub.default = Some(default);
                }
            }
        }
        if data_type.is_signed() || data_type.is_unsigned() || data_type.is_real() {
            for (slot, entry) in [
                (&mut sub.low, fields[OBJ_LOW]),
                (&mut sub.high, fields[OBJ_HIGH]),
            ] {
                if let Some(e) = entry {
                    *slot = self.typed(section, e, data_type, false).map(|(v, _)| v);
                }
            }
        }
        let value = value.or_else(|| fields[OBJ_VALUE].map(|e| (section, e)));
        if let Some((value_section, e)) = value {
            if let Some((value, plus_node_id)) = self.typed(value_section, e, data_type, true) {
                let current = DefaultValue {
                    value,
                    plus_node_id,
                };
                if let Some(bytes) = self.resolved(value_section, e, &current, data_type, node_id) {
                    sub.value = bytes;
                    sub.value_set = true;
                    sub.value_plus_node_id = plus_node_id;
                }
            }
        }
        Ok(sub)
    }

    /// The bytes of `value` (read from `entry`) for the node `node_id`, or `None` with a warning when
    /// they do not fit `data_type`. A value that adds the node-ID must fit for every node-ID when the file
    /// names none, or a DCF written from it for node 127 could not be read.
    fn resolved(
        &self,
        section: &Section<'a>,
        entry: &Entry<'a>,
        value: &DefaultValue,
        data_type: DataType,
        node_id: Option<u8>,
    ) -> Option<Vec<u8>> {
        let widest = (value.plus_node_id && node_id.is_none()).then_some(127);
        let mut bytes = Vec::new();
        for id in widest.into_iter().chain([node_id.unwrap_or(0)]) {
            match value.resolve(id).encode(data_type) {
                Ok(b) => bytes = b,
                Err(err) => {
                    let what = if value.plus_node_id {
                        format!("with node-ID {id} the value does not fit: {err}")
                    } else {
                        err.to_string()
                    };
                    self.warn(
                        entry.value,
                        format!(
                            "{}= in [{}]: {what}; {}",
                            entry.key,
                            section.name,
                            dropped(entry.key)
                        ),
                    );
                    return None;
                }
            }
        }
        Some(bytes)
    }

    /// The object code of `ObjectType=`: a number, or (CANopenEditor's Python port writes them) the
    /// name of one, read with a warning.
    fn object_kind(
        &self,
        section: &Section<'a>,
        entry: &Entry<'a>,
    ) -> Result<ObjectKind, ParseError> {
        if let Some(kind) = parse_integer(entry.value)
            .and_then(|v| u8::try_from(v).ok())
            .and_then(ObjectKind::from_code)
        {
            return Ok(kind);
        }
        let named = OBJECT_KINDS
            .iter()
            .copied()
            .find(|k| k.name().eq_ignore_ascii_case(entry.value));
        let Some(kind) = named else {
            return Err(self.bad(
                section,
                entry,
                "an object code: 0x7 (VAR), 0x8 (ARRAY), 0x9 (RECORD), 0x2 (DOMAIN), 0x5 (DEFTYPE), 0x6 (DEFSTRUCT) or 0x0 (NULL)",
            ));
        };
        self.warn(
            entry.value,
            format!(
                "ObjectType= in [{}]: `{}` is the name of an object code, not a code; read as 0x{:X} ({kind})",
                section.name,
                entry.value,
                kind.code()
            ),
        );
        Ok(kind)
    }

    fn data_type(&self, section: &Section<'a>, entry: &Entry<'a>) -> Result<DataType, ParseError> {
        let Some(index) = parse_integer(entry.value).and_then(|v| u16::try_from(v).ok()) else {
            // CANopenEditor's Python port writes the CiA 301 name (`UNSIGNED32`) instead of the index;
            // a name says which type as plainly, so it is read with a warning.
            let named = STANDARD_TYPES
                .iter()
                .copied()
                .find(|t| t.cia_name().eq_ignore_ascii_case(entry.value));
            let Some(t) = named else {
                return Err(self.bad(section, entry, "a CiA 301 data type index like 0x0007"));
            };
            self.warn(
                entry.value,
                format!(
                    "DataType= in [{}]: `{}` is the name of data type 0x{:04X}, not its index; read as {t}",
                    section.name,
                    entry.value,
                    t.index()
                ),
            );
            return Ok(t);
        };
        if let Some(t) = DataType::from_index(index) {
            return Ok(t);
        }
        // An index that is no basic type: a complex or profile type (PDO parameter, identity, a
        // manufacturer structure; 0x0020-0x025F) or one no standard defines. The model has no structured
        // type for a single entry, so its bytes are a domain, as python-canopen and Lely take it too.
        let what = if (0x0020..=0x025F).contains(&index) {
            "a complex or profile data type"
        } else {
            "not a CiA 301 data type"
        };
        self.warn(
            entry.value,
            format!(
                "DataType= in [{}]: 0x{index:04X} is {what}; the entry is read as DOMAIN",
                section.name
            ),
        );
        Ok(DataType::Domain)
    }

    /// The value of `entry` as `data_type`, and whether it adds the node-ID (`$NODEID+…`, allowed when
    /// `node_id_allowed`). Empty text of a type whose values are not text is no value. Text that is no
    /// value of the type is no value either, with a warning: python-canopen skips such a default, limit or
    /// parameter value, and the entry is usable without it. A C integer suffix (`LL`, `U`: CANopenNode
    /// writes them) is dropped with a warning.
    fn typed(
        &self,
        section: &Section<'a>,
        entry: &Entry<'a>,
        data_type: DataType,
        node_id_allowed: bool,
    ) -> Option<Typed> {
        let text = entry.value;
        let textual = matches!(
            data_type,
            DataType::VisibleString
                | DataType::UnicodeString
                | DataType::OctetString
                | DataType::Domain
        );
        if text.is_empty() && !textual {
            return None;
        }
        let drop = |why: &str| {
            // `1005;c`: a `;` starts a comment only after white space (as python-canopen reads it).
            let hint = if text.contains(';') {
                " (a `;` starts a comment only after a blank)"
            } else {
                ""
            };
            self.warn(
                text,
                format!(
                    "{}= in [{}]: {why}{hint}; {}",
                    entry.key,
                    section.name,
                    dropped(entry.key)
                ),
            );
            None
        };
        let integer =
            data_type.is_signed() || (data_type.is_unsigned() && data_type != DataType::Boolean);
        let (body, plus_node_id) = if textual {
            (text, false)
        } else {
            match split_node_id(text) {
                Some(split) => split,
                None => {
                    return drop(&format!(
                        "`{}` is not `$NODEID`, `$NODEID+offset` or `offset+$NODEID`",
                        shown(text)
                    ))
                }
            }
        };
        if plus_node_id {
            if !node_id_allowed {
                return drop(&format!(
                    "`{}` adds the node-ID, which a limit cannot",
                    shown(text)
                ));
            }
            if !integer {
                return drop(&format!(
                    "`{}` adds the node-ID to a {data_type}, and $NODEID is added to integers only",
                    shown(text)
                ));
            }
        }
        let body = match c_suffix(body).filter(|_| integer) {
            Some((number, suffix)) => {
                self.warn(
                    text,
                    format!(
                        "{}= in [{}]: the C suffix `{suffix}` of `{}` is dropped",
                        entry.key,
                        section.name,
                        shown(text)
                    ),
                );
                number
            }
            None => body,
        };
        match Value::parse_text(data_type, body) {
            Ok(value) => Some((value, plus_node_id)),
            Err(err) => drop(&err.to_string()),
        }
    }
}
