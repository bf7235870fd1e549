//! Objects and sub-objects of the dictionary (CiA 301 §7.4.3 "object dictionary structure"): object codes,
//! access types, PDO mappability, defaults and limits.

use std::fmt;

use crate::types::DataType;
use crate::value::Value;

/// The object code (CiA 301 table 41; EDS `ObjectType=`, XDD `objectType=`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ObjectKind {
    /// NULL (0x0): an object with no data fields.
    Null,
    /// DOMAIN (0x2): a large amount of application data.
    Domain,
    /// DEFTYPE (0x5): a type definition.
    DefType,
    /// DEFSTRUCT (0x6): a record type definition.
    DefStruct,
    /// VAR (0x7): a single value at sub-index 0.
    Var,
    /// ARRAY (0x8): sub-index 0 counts the entries, all of one type.
    Array,
    /// RECORD (0x9): sub-index 0 counts the entries, each of its own type.
    Record,
}

impl ObjectKind {
    /// The object code as EDS and XDD write it.
    pub const fn code(self) -> u8 {
        match self {
            ObjectKind::Null => 0x0,
            ObjectKind::Domain => 0x2,
            ObjectKind::DefType => 0x5,
            ObjectKind::DefStruct => 0x6,
            ObjectKind::Var => 0x7,
            ObjectKind::Array => 0x8,
            ObjectKind::Record => 0x9,
        }
    }

    /// The kind with object code `code`.
    pub const fn from_code(code: u8) -> Option<ObjectKind> {
        Some(match code {
            0x0 => ObjectKind::Null,
            0x2 => ObjectKind::Domain,
            0x5 => ObjectKind::DefType,
            0x6 => ObjectKind::DefStruct,
            0x7 => ObjectKind::Var,
            0x8 => ObjectKind::Array,
            0x9 => ObjectKind::Record,
            _ => return None,
        })
    }

    /// True for the kinds whose sub-index 0 counts the entries (ARRAY, RECORD, DEFSTRUCT).
    pub const fn has_subs(self) -> bool {
        matches!(
            self,
            ObjectKind::Array | ObjectKind::Record | ObjectKind::DefStruct
        )
    }

    /// The CiA 301 name: `VAR`, `ARRAY`, `RECORD`…
    pub const fn name(self) -> &'static str {
        match self {
            ObjectKind::Null => "NULL",
            ObjectKind::Domain => "DOMAIN",
            ObjectKind::DefType => "DEFTYPE",
            ObjectKind::DefStruct => "DEFSTRUCT",
            ObjectKind::Var => "VAR",
            ObjectKind::Array => "ARRAY",
            ObjectKind::Record => "RECORD",
        }
    }
}

impl fmt::Display for ObjectKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The access type of a sub-object (CiA 301 table 43, CiA 306 `AccessType=`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AccessType {
    /// Read only.
    Ro,
    /// Write only.
    Wo,
    /// Read and write.
    Rw,
    /// Read and write, read-mappable in a TPDO (CiA 306 `rwr`).
    Rwr,
    /// Read and write, write-mappable in an RPDO (CiA 306 `rww`).
    Rww,
    /// Read only, the value never changes.
    Const,
}

impl AccessType {
    /// The CiA 306 spelling (`ro`, `rww`, `const`…).
    pub const fn as_str(self) -> &'static str {
        match self {
            AccessType::Ro => "ro",
            AccessType::Wo => "wo",
            AccessType::Rw => "rw",
            AccessType::Rwr => "rwr",
            AccessType::Rww => "rww",
            AccessType::Const => "const",
        }
    }

    /// Parses the CiA 306 / CiA 311 / ESI spelling, case-insensitively (`readOnly`, `readWrite`… of XDD
    /// parameter lists too).
    pub fn parse(text: &str) -> Option<AccessType> {
        Some(match text.trim().to_ascii_lowercase().as_str() {
            "ro" | "read" | "readonly" => AccessType::Ro,
            "wo" | "write" | "writeonly" => AccessType::Wo,
            "rw" | "readwrite" => AccessType::Rw,
            "rwr" | "readwriteinput" => AccessType::Rwr,
            "rww" | "readwriteoutput" => AccessType::Rww,
            "const" | "constant" => AccessType::Const,
            _ => return None,
        })
    }

    /// True when an SDO may read the value.
    pub const fn readable(self) -> bool {
        !matches!(self, AccessType::Wo)
    }

    /// True when an SDO may write the value.
    pub const fn writable(self) -> bool {
        matches!(
            self,
            AccessType::Wo | AccessType::Rw | AccessType::Rwr | AccessType::Rww
        )
    }
}

impl fmt::Display for AccessType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A set of EtherCAT states (ETG.2000 `ReadRestrictions` / `WriteRestrictions`: `PreOp`, `PreOp_SafeOp`,
/// `PreOp_SafeOp_Op`, `SafeOp`, `SafeOp_Op`, `Op`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct EcatStates(u8);

impl EcatStates {
    /// PRE-OPERATIONAL.
    pub const PREOP: EcatStates = EcatStates(1);
    /// SAFE-OPERATIONAL.
    pub const SAFEOP: EcatStates = EcatStates(2);
    /// OPERATIONAL.
    pub const OP: EcatStates = EcatStates(4);

    /// The union of two sets.
    pub const fn union(self, other: EcatStates) -> EcatStates {
        EcatStates(self.0 | other.0)
    }

    /// True when every state of `other` is in this set.
    pub const fn contains(self, other: EcatStates) -> bool {
        self.0 & other.0 == other.0
    }

    /// True for the empty set.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Parses the ESI spelling, case-insensitively: state names joined by `_`.
    pub fn parse(text: &str) -> Option<EcatStates> {
        let mut set = EcatStates::default();
        for part in text.trim().split('_') {
            set = set.union(match part.to_ascii_lowercase().as_str() {
                "preop" => EcatStates::PREOP,
                "safeop" => EcatStates::SAFEOP,
                "op" => EcatStates::OP,
                _ => return None,
            });
        }
        Some(set)
    }
}

impl fmt::Display for EcatStates {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = [
            (EcatStates::PREOP, "PreOp"),
            (EcatStates::SAFEOP, "SafeOp"),
            (EcatStates::OP, "Op"),
        ]
        .iter()
        .filter(|(s, _)| self.contains(*s))
        .map(|(_, n)| *n)
        .collect();
        f.write_str(&names.join("_"))
    }
}

/// Access of a sub-object: the CiA 301 access type plus, from ESI, the EtherCAT states in which reading
/// and writing are allowed (`None`: no restriction).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Access {
    /// The access type.
    pub kind: AccessType,
    /// ESI `ReadRestrictions`: the states in which an SDO may read.
    pub read_states: Option<EcatStates>,
    /// ESI `WriteRestrictions`: the states in which an SDO may write.
    pub write_states: Option<EcatStates>,
}

impl Access {
    /// Access of `kind` with no state restriction.
    pub const fn new(kind: AccessType) -> Access {
        Access {
            kind,
            read_states: None,
            write_states: None,
        }
    }
}

impl From<AccessType> for Access {
    fn from(kind: AccessType) -> Access {
        Access::new(kind)
    }
}

/// PDO mappability of a sub-object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum PdoMapping {
    /// Not mappable.
    #[default]
    None,
    /// Mappable into receive PDOs (outputs of the master, ESI `R`).
    Rpdo,
    /// Mappable into transmit PDOs (inputs of the master, ESI `T`).
    Tpdo,
    /// Mappable in both directions (ESI `RT`, XDD `optional`).
    Both,
}

impl PdoMapping {
    /// True when the entry may go into an RPDO.
    pub const fn rpdo(self) -> bool {
        matches!(self, PdoMapping::Rpdo | PdoMapping::Both)
    }

    /// True when the entry may go into a TPDO.
    pub const fn tpdo(self) -> bool {
        matches!(self, PdoMapping::Tpdo | PdoMapping::Both)
    }

    /// True when the entry is mappable at all.
    pub const fn any(self) -> bool {
        !matches!(self, PdoMapping::None)
    }
}

/// The flags of CiA 306 §4.6.3 `ObjFlags` (UNSIGNED32; CiA 311 `objFlags`, hexBinary): what a configuration
/// tool leaves out for an object or an entry. Bit 0 "refuse write on download": the tool does not write it
/// when it downloads a configuration; bit 1 "refuse read on scan": the tool does not read it when it scans
/// (dumps) a device. Bits 2–31 are reserved; they are kept as read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ObjFlags(u32);

impl ObjFlags {
    /// No flag.
    pub const NONE: ObjFlags = ObjFlags(0);
    /// Bit 0: a tool does not write the entry when it downloads a configuration.
    pub const REFUSE_WRITE_ON_DOWNLOAD: ObjFlags = ObjFlags(1);
    /// Bit 1: a tool does not read the entry when it scans a device.
    pub const REFUSE_READ_ON_SCAN: ObjFlags = ObjFlags(2);

    /// The flags of the number a file gives.
    pub const fn from_bits(bits: u32) -> ObjFlags {
        ObjFlags(bits)
    }

    /// The number a file gives.
    pub const fn bits(self) -> u32 {
        self.0
    }

    /// The union of two sets.
    pub const fn union(self, other: ObjFlags) -> ObjFlags {
        ObjFlags(self.0 | other.0)
    }

    /// True when every flag of `other` is set.
    pub const fn contains(self, other: ObjFlags) -> bool {
        self.0 & other.0 == other.0
    }

    /// True when no flag is set.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }
}

impl fmt::Display for ObjFlags {
    /// `0x3 (refuse write on download, refuse read on scan)`; `0x0` for none.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "0x{:X}", self.0)?;
        let names: Vec<&str> = [
            (
                ObjFlags::REFUSE_WRITE_ON_DOWNLOAD,
                "refuse write on download",
            ),
            (ObjFlags::REFUSE_READ_ON_SCAN, "refuse read on scan"),
        ]
        .iter()
        .filter(|(flag, _)| self.contains(*flag))
        .map(|(_, name)| *name)
        .collect();
        if !names.is_empty() {
            write!(f, " ({})", names.join(", "))?;
        }
        Ok(())
    }
}

/// A default value as description files write it: a value, or a value plus the node-ID (CiA 306 §4.6.2
/// `$NODEID+0x180`).
#[derive(Debug, Clone, PartialEq)]
pub struct DefaultValue {
    /// The value, or the offset added to the node-ID.
    pub value: Value,
    /// True when the node-ID is added to `value` to get the default.
    pub plus_node_id: bool,
}

impl DefaultValue {
    /// A plain default.
    pub fn plain(value: Value) -> DefaultValue {
        DefaultValue {
            value,
            plus_node_id: false,
        }
    }

    /// The default for a node with `node_id` (plain defaults ignore it).
    pub fn resolve(&self, node_id: u8) -> Value {
        if !self.plus_node_id {
            return self.value.clone();
        }
        match self.value {
            Value::Uint(v) => Value::Uint(v.wrapping_add(node_id as u64)),
            Value::Int(v) => Value::Int(v.wrapping_add(node_id as i64)),
            ref other => other.clone(),
        }
    }
}

/// One sub-object: the addressable value of a dictionary entry.
#[derive(Debug, Clone, PartialEq)]
pub struct SubObject {
    /// Name (ESI `Name`, EDS `ParameterName`).
    pub name: String,
    /// What the entry means: units, ranges, bit meanings (ESI `Comment`, XDD `description`).
    pub description: Option<String>,
    /// Data type.
    pub data_type: DataType,
    /// Size in bits of the value. Fixed-size types take their type's size; for strings and DOMAIN it is the
    /// capacity a write may fill (`None`: unbounded).
    pub bit_size: Option<u32>,
    /// Access.
    pub access: Access,
    /// PDO mappability.
    pub pdo: PdoMapping,
    /// Default value.
    pub default: Option<DefaultValue>,
    /// The unit of the value, ETG.1004 / CiA 303-2 encoded (ESI `Info/Unit`): the prefix's power of
    /// ten (signed) in bits 31–24, the unit in 23–16, a unit it is divided by in 15–8; see
    /// [`crate::units::unit_text`].
    pub unit: Option<u32>,
    /// Lowest value a write may set.
    pub low: Option<Value>,
    /// Highest value a write may set.
    pub high: Option<Value>,
    /// Current value, encoded little-endian. DCF `ParameterValue` and everything an SDO wrote.
    pub value: Vec<u8>,
    /// True when the current value was set explicitly (a DCF `ParameterValue`); a writer of configuration
    /// files writes only these and values that differ from the default.
    pub value_set: bool,
    /// True when the current value was given relative to the node-ID (`ParameterValue=$NODEID+0x200`, as
    /// ros_canopen's DCFs for a node whose ID is set at run time give it): `value` holds it resolved with
    /// the description's node-ID (0 when it has none), and writers write it relative again. Storing a
    /// value clears it.
    pub value_plus_node_id: bool,
    /// `ObjFlags` of the entry's own sub-index section (EDS `[xxxxsubN]`, XDD `CANopenSubObject`);
    /// `None` when it gives none. The entry takes nothing from its object here: the flags of the
    /// object's section stay on the [`Object`] (for a VAR or DOMAIN, whose one section is the
    /// object's, there), and what a tool honours is [`Object::flags_of`], both together.
    pub flags: Option<ObjFlags>,
}

impl SubObject {
    /// A sub-object of `data_type` with `access`, its value zero, no default and no limits.
    pub fn new(
        name: impl Into<String>,
        data_type: DataType,
        access: impl Into<Access>,
    ) -> SubObject {
        let value = Value::zero(data_type).encode(data_type).unwrap_or_default();
        SubObject {
            name: name.into(),
            description: None,
            data_type,
            bit_size: data_type.bit_size(),
            access: access.into(),
            pdo: PdoMapping::None,
            default: None,
            unit: None,
            low: None,
            high: None,
            value,
            value_set: false,
            value_plus_node_id: false,
            flags: None,
        }
    }

    /// Sets the default and the current value to `value` (builder style).
    pub fn with_default(mut self, value: Value) -> SubObject {
        if let Ok(bytes) = value.encode(self.data_type) {
            self.value = bytes;
        }
        self.default = Some(DefaultValue::plain(value));
        self
    }

    /// Sets the limits (builder style).
    pub fn with_limits(mut self, low: Option<Value>, high: Option<Value>) -> SubObject {
        self.low = low;
        self.high = high;
        self
    }

    /// Sets the PDO mappability (builder style).
    pub fn with_pdo(mut self, pdo: PdoMapping) -> SubObject {
        self.pdo = pdo;
        self
    }

    /// Sets the description (builder style).
    pub fn with_description(mut self, text: impl Into<String>) -> SubObject {
        self.description = Some(text.into());
        self
    }

    /// Sets the bit size (builder style): the capacity of a string or domain.
    pub fn with_bit_size(mut self, bits: u32) -> SubObject {
        self.bit_size = Some(bits);
        self
    }

    /// The capacity in bytes of a variable-length value, if bounded.
    pub fn capacity(&self) -> Option<usize> {
        if self.data_type.is_variable() {
            self.bit_size.map(|b| (b as usize).div_ceil(8))
        } else {
            self.data_type.byte_size()
        }
    }

    /// Whether the description gives the entry a value: a default, or a current value set
    /// explicitly (a DCF `ParameterValue`). An entry without one holds zero (or an empty string) only
    /// for want of a value.
    pub fn has_value(&self) -> bool {
        self.default.is_some() || self.value_set
    }

    /// Makes `value` the entry's default and its current value, so that a reset (NMT reset node,
    /// restore defaults) keeps it; the value is no longer one set explicitly. Refused (`false`, nothing changed) when it is no value of the
    /// entry's type, is longer than the entry holds or lies outside its limits.
    pub fn set_default(&mut self, value: Value) -> bool {
        let Ok(bytes) = value.encode(self.data_type) else {
            return false;
        };
        if self.capacity().is_some_and(|cap| bytes.len() > cap) {
            return false;
        }
        let outside = |limit: &Option<Value>, wrong: std::cmp::Ordering| {
            limit
                .as_ref()
                .is_some_and(|l| crate::dict::compare(&value, l) == Some(wrong))
        };
        if outside(&self.low, std::cmp::Ordering::Less)
            || outside(&self.high, std::cmp::Ordering::Greater)
        {
            return false;
        }
        self.value = bytes;
        self.default = Some(DefaultValue::plain(value));
        self.value_set = false;
        self.value_plus_node_id = false;
        true
    }

    /// The current value, decoded.
    pub fn current(&self) -> Option<Value> {
        Value::decode(self.data_type, &self.value).ok()
    }

    /// Resets the current value to the default for a node with `node_id` (zero where there is none).
    pub fn reset(&mut self, node_id: u8) {
        let v = self
            .default
            .as_ref()
            .map(|d| d.resolve(node_id))
            .unwrap_or_else(|| Value::zero(self.data_type));
        if let Ok(bytes) = v.encode(self.data_type) {
            self.value = bytes;
        }
        self.value_set = false;
        self.value_plus_node_id = false;
    }

    /// The current value as a configuration file gives it: `$NODEID+offset` when it was given relative to
    /// the node-ID (resolved with `node_id`, the description's), else the value itself. `None` when the
    /// bytes are no value of the type.
    pub fn parameter(&self, node_id: u8) -> Option<DefaultValue> {
        let value = self.current()?;
        if !self.value_plus_node_id {
            return Some(DefaultValue::plain(value));
        }
        let offset = match value {
            Value::Uint(v) => v.checked_sub(u64::from(node_id)).map(Value::Uint),
            Value::Int(v) => v.checked_sub(i64::from(node_id)).map(Value::Int),
            _ => None,
        };
        Some(match offset {
            Some(offset) => DefaultValue {
                value: offset,
                plus_node_id: true,
            },
            None => DefaultValue::plain(value),
        })
    }
}

/// One entry of the dictionary, at a 16-bit index.
#[derive(Debug, Clone, PartialEq)]
pub struct Object {
    /// Index.
    pub index: u16,
    /// Name.
    pub name: String,
    /// What the object is for (ESI `Comment`, XDD `description`).
    pub description: Option<String>,
    /// Object code.
    pub kind: ObjectKind,
    /// For ARRAY and RECORD objects read from ESI or XDD: the name of the structure type (`DT1018`).
    pub type_name: Option<String>,
    /// Sub-objects by sub-index. A VAR or DOMAIN object has its value at sub-index 0.
    pub subs: std::collections::BTreeMap<u8, SubObject>,
    /// `ObjFlags` of the object's section (EDS `[xxxx]`, XDD `CANopenObject`), for a VAR or DOMAIN
    /// the flags of its one entry; `None` when the file gives none (CiA 306: no flags), kept apart
    /// from an explicit 0 so that a writer writes back only the flags a file had.
    pub flags: Option<ObjFlags>,
}

impl Object {
    /// A VAR object holding `sub` at sub-index 0; its name is the sub-object's.
    pub fn var(index: u16, sub: SubObject) -> Object {
        let kind = if sub.data_type == DataType::Domain {
            ObjectKind::Domain
        } else {
            ObjectKind::Var
        };
        let mut subs = std::collections::BTreeMap::new();
        let name = sub.name.clone();
        subs.insert(0, sub);
        Object {
            index,
            name,
            description: None,
            kind,
            type_name: None,
            subs,
            flags: None,
        }
    }

    /// An ARRAY or RECORD object with no sub-objects yet.
    pub fn structured(index: u16, name: impl Into<String>, kind: ObjectKind) -> Object {
        Object {
            index,
            name: name.into(),
            description: None,
            kind,
            type_name: None,
            subs: std::collections::BTreeMap::new(),
            flags: None,
        }
    }

    /// Adds or replaces a sub-object (builder style).
    pub fn with_sub(mut self, sub_index: u8, sub: SubObject) -> Object {
        self.subs.insert(sub_index, sub);
        self
    }

    /// The sub-object at `sub`.
    pub fn sub(&self, sub: u8) -> Option<&SubObject> {
        self.subs.get(&sub)
    }

    /// The `ObjFlags` a tool honours for the entry at `sub`: the object's and the entry's own
    /// together. CiA 306 §4.6.3 gives `ObjFlags` to an object's section and to a sub-index's and does
    /// not say whether the object's reach its sub-indices; vendor files flag a whole RECORD in the
    /// object's section alone (a drive's calibration data, `ObjFlags=0x3`, its sub-indices without
    /// any), and a tool that leaves an object out leaves out its parts, so they do.
    pub fn flags_of(&self, sub: u8) -> ObjFlags {
        let own = self.subs.get(&sub).and_then(|s| s.flags);
        self.flags
            .unwrap_or_default()
            .union(own.unwrap_or_default())
    }

    /// The highest sub-index present.
    pub fn max_sub(&self) -> u8 {
        self.subs.keys().next_back().copied().unwrap_or(0)
    }
}
