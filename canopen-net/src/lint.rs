//! The strict reading of a slave's EDS or DCF that dcfgen makes before it generates anything (Lely
//! dcf-tools' `lint`): every section and key known, the object lists complete and in their ranges,
//! every object's sub-objects there, every value and limit a number of its type within its range.
//! A description that fails is refused unless generation is not strict (`-S`).
//!
//! The file is read as Python's `configparser` reads it: section and key names in any case, `=` or
//! `:` between key and value, `;` and `#` comments (after white space, inside a line), a section or
//! a key given twice refused.

/// What the strict reading found: `ok` false when the description is refused.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Lint {
    /// True when the description passes.
    pub ok: bool,
    /// What was found, in file order, one line each.
    pub warnings: Vec<String>,
}

type Section = (String, Vec<(String, String)>);

/// An INI file as `configparser` reads it.
struct Ini {
    sections: Vec<Section>,
}

impl Ini {
    fn parse(text: &str) -> Result<Ini, String> {
        let mut sections: Vec<Section> = Vec::new();
        for (n, raw) in text.lines().enumerate() {
            let line = raw.trim();
            if line.is_empty() || line.starts_with(['#', ';']) {
                continue;
            }
            if let Some(name) = line
                .strip_prefix('[')
                .and_then(|l| l.find(']').map(|e| &l[..e]))
            {
                if sections.iter().any(|(s, _)| s.eq_ignore_ascii_case(name)) {
                    return Err(format!("section [{name}] given twice (line {})", n + 1));
                }
                sections.push((name.to_string(), Vec::new()));
                continue;
            }
            let Some(at) = line.find(['=', ':']) else {
                return Err(format!("line {} is no key = value", n + 1));
            };
            let Some((_, keys)) = sections.last_mut() else {
                return Err(format!("line {} comes before any section", n + 1));
            };
            let key = line[..at].trim().to_string();
            let mut value = line[at + 1..].trim();
            if let Some(c) = value.char_indices().find(|&(i, c)| {
                matches!(c, '#' | ';') && i > 0 && value[..i].ends_with(char::is_whitespace)
            }) {
                value = value[..c.0].trim_end();
            }
            if keys.iter().any(|(k, _)| k.eq_ignore_ascii_case(&key)) {
                return Err(format!("key {key} given twice (line {})", n + 1));
            }
            keys.push((key, value.to_string()));
        }
        Ok(Ini { sections })
    }

    fn section(&self, name: &str) -> Option<&[(String, String)]> {
        self.sections
            .iter()
            .find(|(s, _)| s.eq_ignore_ascii_case(name))
            .map(|(_, k)| k.as_slice())
    }
}

fn get<'a>(keys: &'a [(String, String)], key: &str) -> Option<&'a str> {
    keys.iter()
        .find(|(k, _)| k.eq_ignore_ascii_case(key))
        .map(|(_, v)| v.as_str())
}

/// A value that is there and not empty.
pub(crate) fn given<'a>(keys: &'a [(String, String)], key: &str) -> Option<&'a str> {
    get(keys, key).filter(|v| !v.is_empty())
}

/// Python's `int(text, base)`: sign, `_` between digits, and with base 0 the `0x`/`0o`/`0b`
/// prefixes (and no leading zero on a decimal).
pub(crate) fn py_int(text: &str, base: u32) -> Option<i128> {
    let t = text.trim();
    let (neg, body) = match t.strip_prefix('-') {
        Some(r) => (true, r),
        None => (false, t.strip_prefix('+').unwrap_or(t)),
    };
    let lower = body.to_ascii_lowercase();
    let (digits, radix) = if base == 0 {
        if let Some(d) = lower.strip_prefix("0x") {
            (d.to_string(), 16)
        } else if let Some(d) = lower.strip_prefix("0o") {
            (d.to_string(), 8)
        } else if let Some(d) = lower.strip_prefix("0b") {
            (d.to_string(), 2)
        } else {
            if lower.len() > 1
                && lower.starts_with('0')
                && lower.chars().any(|c| c != '0' && c != '_')
            {
                return None;
            }
            (lower.clone(), 10)
        }
    } else {
        (lower.clone(), base)
    };
    let digits = digits
        .strip_prefix('_')
        .filter(|_| radix != 10)
        .unwrap_or(&digits);
    if digits.is_empty()
        || digits.starts_with('_')
        || digits.ends_with('_')
        || digits.contains("__")
    {
        return None;
    }
    let clean: String = digits.chars().filter(|&c| c != '_').collect();
    let v = i128::from_str_radix(&clean, radix).ok()?;
    Some(if neg { -v } else { v })
}

const SECTIONS: [(&str, &[&str]); 3] = [
    (
        "FileInfo",
        &[
            "FileName",
            "FileVersion",
            "FileRevision",
            "EDSVersion",
            "Description",
            "CreationTime",
            "CreationDate",
            "CreatedBy",
            "ModificationTime",
            "ModificationDate",
            "ModifiedBy",
            "LastEDS",
        ],
    ),
    (
        "DeviceComissioning",
        &[
            "NodeID",
            "NodeName",
            "NodeRefd",
            "Baudrate",
            "NetNumber",
            "NetworkName",
            "NetRefd",
            "CANopenManager",
            "LSS_SerialNumber",
        ],
    ),
    (
        "DeviceInfo",
        &[
            "VendorName",
            "VendorNumber",
            "ProductName",
            "ProductNumber",
            "RevisionNumber",
            "OrderCode",
            "BaudRate_10",
            "BaudRate_20",
            "BaudRate_50",
            "BaudRate_125",
            "BaudRate_250",
            "BaudRate_500",
            "BaudRate_800",
            "BaudRate_1000",
            "SimpleBootUpMaster",
            "SimpleBootUpSlave",
            "Granularity",
            "DynamicChannelsSupported",
            "GroupMessaging",
            "NrOfRxPDO",
            "NrOfTxPDO",
            "LSS_Supported",
            "CompactPDO",
        ],
    ),
];

const OBJECT_KEYS: [&str; 16] = [
    "SubNumber",
    "ParameterName",
    "ObjectType",
    "DataType",
    "AccessType",
    "LowLimit",
    "HighLimit",
    "DefaultValue",
    "PDOMapping",
    "ObjFlags",
    "CompactSubObj",
    "ParameterValue",
    "UploadFile",
    "DownloadFile",
    "Denotation",
    "ParamRefd",
];

/// Reads `text` strictly, as dcfgen does before it takes a description.
pub fn lint(text: &[u8]) -> Lint {
    let text = String::from_utf8_lossy(text);
    let ini = match Ini::parse(&text) {
        Ok(ini) => ini,
        Err(e) => {
            return Lint {
                ok: false,
                warnings: vec![e],
            }
        }
    };
    let mut l = Linter {
        ini: &ini,
        warnings: Vec::new(),
    };
    let mut ok = true;
    for (section, keys) in &ini.sections {
        ok &= l.section(section, keys);
    }
    Lint {
        ok,
        warnings: l.warnings,
    }
}

pub(crate) struct Linter<'a> {
    ini: &'a Ini,
    pub(crate) warnings: Vec<String>,
}

/// The parts of an object section's name: the index and `Name`, `Value` or `subN`.
fn object_name(section: &str) -> Option<(u16, &str)> {
    let head = section.get(..4)?;
    if !head
        .chars()
        .all(|c| c.is_ascii_hexdigit() || c == 'x' || c == 'X')
    {
        return None;
    }
    let rest = &section[4..];
    let lower = rest.to_ascii_lowercase();
    let known = lower.is_empty()
        || lower == "name"
        || lower == "value"
        || lower
            .strip_prefix("sub")
            .is_some_and(|s| !s.is_empty() && s.chars().all(|c| c.is_ascii_hexdigit()));
    let index = u16::from_str_radix(head, 16).ok()?;
    known.then_some((index, rest))
}

impl Linter<'_> {
    pub(crate) fn warn(&mut self, text: String) -> bool {
        self.warnings.push(text);
        false
    }

    fn section(&mut self, section: &str, keys: &[(String, String)]) -> bool {
        if section == "DEFAULT" || section.eq_ignore_ascii_case("Comments") {
            return true;
        }
        if let Some((_, known)) = SECTIONS
            .iter()
            .find(|(s, _)| s.eq_ignore_ascii_case(section))
        {
            let mut ok = true;
            for (k, _) in keys {
                if !known.iter().any(|n| n.eq_ignore_ascii_case(k)) {
                    ok = self.warn(format!("invalid entry in [{section}]: {k}"));
                }
            }
            return ok;
        }
        if section.eq_ignore_ascii_case("DummyUsage") {
            let mut ok = true;
            for (k, v) in keys {
                let name = k.len() == 9
                    && k[..5].eq_ignore_ascii_case("Dummy")
                    && k[5..].chars().all(|c| c.is_ascii_hexdigit());
                if !name {
                    ok = self.warn(format!("invalid entry in [{section}]: {k}"));
                } else if py_int(v, 2).is_none() {
                    ok = self.warn(format!("invalid value for {k} in [{section}]: {v}"));
                }
            }
            return ok;
        }
        if ["MandatoryObjects", "OptionalObjects", "ManufacturerObjects"]
            .iter()
            .any(|s| s.eq_ignore_ascii_case(section))
        {
            return self.objects(section, keys);
        }
        match object_name(section) {
            Some((index, "")) => self.object(section, keys, index),
            Some((index, rest)) if rest.len() > 3 && rest[..3].eq_ignore_ascii_case("sub") => {
                let sub = u32::from_str_radix(&rest[3..], 16).unwrap_or(u32::MAX);
                self.sub_object(section, keys, index, sub)
            }
            Some((index, _)) => self.compact(section, keys, index),
            None => self.warn(format!("unknown section in DCF: {section}")),
        }
    }

    fn objects(&mut self, section: &str, keys: &[(String, String)]) -> bool {
        let mut ok = true;
        let mut supported = None;
        for (k, v) in keys {
            if k.eq_ignore_ascii_case("SupportedObjects") {
                match py_int(v, 10) {
                    Some(n) => supported = Some(n),
                    None => {
                        ok = self.warn(format!(
                            "invalid value for SupportedObjects in [{section}]: {k}"
                        ))
                    }
                }
            } else if py_int(k, 10).is_none() {
                ok = self.warn(format!("invalid entry in [{section}]: {k}"));
            }
        }
        let Some(supported) = supported else {
            return self.warn(format!("SupportedObjects entry missing in [{section}]"));
        };
        if supported < keys.len() as i128 - 1 {
            ok = self.warn(format!("too many entries in [{section}]"));
        }
        for i in 1..=supported.clamp(0, 0xFFFF) {
            let Some(text) = get(keys, &i.to_string()) else {
                ok = self.warn(format!("entry {i} missing in [{section}]"));
                continue;
            };
            let Some(index) = py_int(text, 0) else {
                ok = self.warn(format!(
                    "invalid object index for entry {i} in [{section}]: {text}"
                ));
                continue;
            };
            if self.ini.section(&format!("{index:04X}")).is_none() {
                ok = self.warn(format!("object 0x{index:04X} not found"));
            }
            let is = |s: &str| section.eq_ignore_ascii_case(s);
            let problem = if index < 0x1000 {
                Some(format!(
                    "data type objects are not supported: 0x{index:04X}"
                ))
            } else if is("MandatoryObjects") && ![0x1000, 0x1001, 0x1018].contains(&index) {
                Some(format!("object 0x{index:04X} is not mandatory"))
            } else if is("OptionalObjects") && (0x2000..0x6000).contains(&index) {
                Some(format!("object 0x{index:04X} is manufacturer-specific"))
            } else if is("ManufacturerObjects") && !(0x2000..0x6000).contains(&index) {
                Some(format!("object 0x{index:04X} is not manufacturer-specific"))
            } else {
                None
            };
            if let Some(p) = problem {
                ok = self.warn(p);
            }
        }
        ok
    }

    fn keys_known(&mut self, section: &str, keys: &[(String, String)]) -> bool {
        let mut ok = true;
        for (k, v) in keys {
            if !OBJECT_KEYS.iter().any(|n| n.eq_ignore_ascii_case(k)) {
                ok = self.warn(format!("invalid entry in [{section}]: {k}"));
            } else if k.eq_ignore_ascii_case("AccessType")
                && !["ro", "wo", "rw", "rwr", "rww", "const"]
                    .contains(&v.to_ascii_lowercase().as_str())
            {
                ok = self.warn(format!("invalid value for {k} in [{section}]: {v}"));
            }
        }
        if get(keys, "ParameterName").is_none() {
            ok = self.warn(format!("ParameterName not specified in [{section}]"));
        }
        ok
    }

    fn object(&mut self, section: &str, keys: &[(String, String)], index: u16) -> bool {
        let mut ok = self.keys_known(section, keys);
        let num = |k: &str, default: i128| given(keys, k).map_or(Some(default), |v| py_int(v, 0));
        let (Some(object_type), Some(sub_number), Some(compact)) = (
            num("ObjectType", 7),
            num("SubNumber", 0),
            num("CompactSubObj", 0),
        ) else {
            return self.warn(format!("invalid number in [{section}]"));
        };
        if matches!(object_type, 5 | 7) && given(keys, "DataType").is_none() {
            ok = self.warn(format!("DataType not specified in [{section}]"));
        }
        if given(keys, "AccessType").is_some() {
            if matches!(object_type, 6 | 8 | 9) && compact == 0 {
                ok = self.warn(format!("AccessType not supported in [{section}]"));
            }
        } else if object_type != 2 && compact != 0 {
            ok = self.warn(format!("AccessType not specified in [{section}]"));
        }
        let structured = matches!(object_type, 8 | 9);
        let not_structured =
            format!("ObjectType should be 0x08 (ARRAY) or 0x09 (RECORD) in [{section}]");
        if sub_number != 0 && compact != 0 {
            ok = self.warn(format!(
                "SubNumber and CompactSubObj specified in [{section}]"
            ));
        } else if sub_number != 0 {
            if !structured {
                ok = self.warn(not_structured);
            }
            let mut n = 0;
            for sub in 0..255 {
                let name = format!("{index:04X}sub{sub:X}");
                let Some(sk) = self.ini.section(&name) else {
                    continue;
                };
                n += 1;
                if sub == 0 && given(sk, "DataType").map_or(Some(0), |v| py_int(v, 0)) != Some(5) {
                    ok = self.warn(format!("DataType should be UNSIGNED8 in [{name}]"));
                }
            }
            if n < sub_number {
                ok = self.warn(format!(
                    "{} missing sub-object(s) for object 0x{index:04X}",
                    sub_number - n
                ));
            } else if n > sub_number {
                ok = self.warn(format!(
                    "{} extra sub-object(s) for object 0x{index:04X}",
                    n - sub_number
                ));
            }
        } else if compact != 0 && !structured {
            ok = self.warn(not_structured);
        }
        if sub_number == 0 {
            ok &= self.values(section, keys);
        }
        ok
    }

    /// The data type with its limits, then the default and parameter values.
    fn values(&mut self, section: &str, keys: &[(String, String)]) -> bool {
        if !self.data_type(section, keys) {
            return false;
        }
        let mut ok = true;
        for k in ["DefaultValue", "ParameterValue"] {
            if let Some(v) = given(keys, k) {
                ok &= self.value(keys, section, k, v);
            }
        }
        ok
    }

    fn sub_object(
        &mut self,
        section: &str,
        keys: &[(String, String)],
        index: u16,
        sub: u32,
    ) -> bool {
        let mut ok = true;
        let name = format!("{index:04X}");
        if self.ini.section(&name).is_none() {
            ok = self.warn(format!("object 0x{name} not defined: {section}"));
        }
        if sub > 254 {
            return self.warn(format!("invalid sub-index: {section}"));
        }
        ok &= self.keys_known(section, keys);
        ok &= self.values(section, keys);
        if given(keys, "AccessType").is_none() {
            ok = self.warn(format!("AccessType not specified in [{section}]"));
        }
        ok
    }

    fn compact(&mut self, section: &str, keys: &[(String, String)], index: u16) -> bool {
        let mut ok = true;
        let name = format!("{index:04X}");
        let object = self.ini.section(&name);
        let mut compact = 0;
        match object {
            Some(o) => {
                match given(o, "CompactSubObj").and_then(|v| py_int(v, 0)) {
                    Some(c) => compact = c,
                    None => {
                        ok = self.warn(format!("object 0x{name} does not support compact storage"))
                    }
                }
                ok &= self.data_type(&name, o);
            }
            None => ok = self.warn(format!("object 0x{name} not defined: {section}")),
        }
        let mut entries = None;
        for (k, v) in keys {
            if k.eq_ignore_ascii_case("NrOfEntries") {
                match py_int(v, 10) {
                    Some(n) => entries = Some(n),
                    None => {
                        ok = self.warn(format!("invalid value for NrOfEntries in [{section}]: {k}"))
                    }
                }
            } else {
                match py_int(k, 10) {
                    Some(i) if i > compact => {
                        ok = self.warn(format!("invalid sub-index in [{section}]: {i}"))
                    }
                    Some(_) => {}
                    None => ok = self.warn(format!("invalid entry in [{section}]: {k}")),
                }
            }
        }
        let Some(entries) = entries else {
            return self.warn(format!("NrOfEntries entry missing in [{section}]"));
        };
        let listed = keys.len() as i128 - 1;
        if entries < listed {
            ok = self.warn(format!("too many entries in [{section}]"));
        } else if entries > listed {
            ok = self.warn(format!("too few entries in [{section}]"));
        }
        if ok && section.to_ascii_lowercase().ends_with("value") {
            let object = object.unwrap_or(&[]);
            for (k, v) in keys
                .iter()
                .filter(|(k, _)| !k.eq_ignore_ascii_case("NrOfEntries"))
            {
                ok &= self.value(object, section, &format!("entry {k}"), v);
            }
        }
        ok
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn python_int_rules() {
        assert_eq!(py_int("0x1F", 0), Some(31));
        assert_eq!(py_int("010", 0), None);
        assert_eq!(py_int("010", 10), Some(10));
        assert_eq!(py_int("-5", 0), Some(-5));
        assert_eq!(py_int("1_000", 0), Some(1000));
        assert_eq!(py_int("12.5", 0), None);
        assert_eq!(py_int("0", 0), Some(0));
        assert_eq!(py_int("00", 0), Some(0));
    }

    #[test]
    fn a_clean_file_passes_and_a_wrong_one_says_why() {
        let good = b"[DeviceInfo]\nVendorNumber=0x1\n[MandatoryObjects]\nSupportedObjects=1\n1=0x1000\n\
                     [1000]\nParameterName=Device type\nDataType=0x0007\nAccessType=ro\nDefaultValue=0\n";
        assert_eq!(
            lint(good),
            Lint {
                ok: true,
                warnings: vec![]
            }
        );
        let bad = b"[DeviceInfo]\nNG_Slave=1\n[MandatoryObjects]\nSupportedObjects=1\n1=0x1000\n\
                    [1000]\nParameterName=Device type\nDataType=0x0007\nAccessType=ro\nDefaultValue=12.5\n";
        let l = lint(bad);
        assert!(!l.ok);
        assert_eq!(
            l.warnings,
            [
                "invalid entry in [DeviceInfo]: NG_Slave",
                "invalid DefaultValue in [1000]: 12.5"
            ]
        );
    }

    #[test]
    fn limits_and_node_id_values() {
        let text = |v: &str| {
            format!("[MandatoryObjects]\nSupportedObjects=1\n1=0x1000\n[1000]\nParameterName=D\nDataType=0x0005\nAccessType=rw\n{v}\n")
        };
        assert!(lint(text("DefaultValue=$NODEID+0x10").as_bytes()).ok);
        assert_eq!(
            lint(text("DefaultValue=$NODEID+0x90").as_bytes()).warnings,
            ["DefaultValue overflow in [1000]"]
        );
        assert_eq!(
            lint(text("DefaultValue=0x80+$NODEID").as_bytes()).warnings,
            ["invalid DefaultValue in [1000]: 0x80+$NODEID"]
        );
        assert_eq!(
            lint(text("HighLimit=5\nDefaultValue=6").as_bytes()).warnings,
            ["DefaultValue overflow in [1000]"]
        );
    }
}
