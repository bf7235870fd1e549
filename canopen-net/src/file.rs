//! A slave's description as generation takes it: the dictionary `od` read, and which identity keys
//! the file itself gives, since a key that is there, even as 0, takes the place of 0x1018's value.

use std::collections::BTreeMap;

use od::DeviceDescription;

use crate::lint::{lint, Lint};

/// The keys of a CiA 306 file (an EDS, a DCF, `master.dcf`) by section, each with the line and
/// value of every time it is given, read leniently: section and key names in any case, a key
/// given twice kept twice, no line refused (the strict reading is [`crate::lint`]'s).
pub(crate) struct IniKeys {
    /// (section in upper case, key in lower case) → (line from 1, value trimmed), in file order.
    keys: BTreeMap<(String, String), Vec<(usize, String)>>,
}

/// The keys of `text`.
pub(crate) fn ini_keys(text: &str) -> IniKeys {
    let mut keys: BTreeMap<(String, String), Vec<(usize, String)>> = BTreeMap::new();
    let mut section = String::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            section = name.trim().to_ascii_uppercase();
        } else if let Some((k, v)) = line.split_once('=') {
            let key = (section.clone(), k.trim().to_ascii_lowercase());
            keys.entry(key)
                .or_default()
                .push((n + 1, v.trim().to_string()));
        }
    }
    IniKeys { keys }
}

impl IniKeys {
    /// Every time `key` of `section` is given (names in any case), in file order.
    pub(crate) fn all<'a>(
        &'a self,
        section: &str,
        key: &str,
    ) -> impl Iterator<Item = (usize, &'a str)> + 'a {
        let k = (section.to_ascii_uppercase(), key.to_ascii_lowercase());
        self.keys
            .get(&k)
            .into_iter()
            .flatten()
            .map(|(line, v)| (*line, v.as_str()))
    }

    /// The last time `key` of `section` is given: its line and value.
    pub(crate) fn get(&self, section: &str, key: &str) -> Option<(usize, &str)> {
        self.all(section, key).last()
    }
}

/// Which identity keys a description file gives with a value: `[DeviceInfo]` `VendorNumber`,
/// `ProductNumber`, `RevisionNumber` and `[DeviceComissioning]` `LSS_SerialNumber`. Where one is
/// given, its value is the slave's (as dcfgen takes it), else 0x1018's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IdentityKeys {
    /// `VendorNumber`.
    pub vendor: bool,
    /// `ProductNumber`.
    pub product: bool,
    /// `RevisionNumber`.
    pub revision: bool,
    /// `LSS_SerialNumber`.
    pub serial: bool,
}

impl IdentityKeys {
    /// The keys `text` (an EDS or DCF) gives with a value; section and key names in any case.
    pub fn scan(text: &[u8]) -> IdentityKeys {
        let keys = ini_keys(&String::from_utf8_lossy(text));
        // Given with a value, a comment after `;` or `#` apart, any of the times it is given.
        let given = |section: &str, key: &str| {
            keys.all(section, key)
                .any(|(_, v)| !v.split([';', '#']).next().unwrap_or("").trim().is_empty())
        };
        IdentityKeys {
            vendor: given("DeviceInfo", "VendorNumber"),
            product: given("DeviceInfo", "ProductNumber"),
            revision: given("DeviceInfo", "RevisionNumber"),
            serial: given("DeviceComissioning", "LSS_SerialNumber"),
        }
    }
}

/// A slave's description: what `od` read, and the identity keys its file gives.
#[derive(Debug, Clone, PartialEq)]
pub struct SlaveFile {
    /// The description.
    pub description: DeviceDescription,
    /// The identity keys the file gives.
    pub keys: IdentityKeys,
    /// The strict reading of the file.
    pub lint: Lint,
}

impl SlaveFile {
    /// The description `od` read from `text`, with the identity keys `text` gives.
    pub fn new(description: DeviceDescription, text: &[u8]) -> SlaveFile {
        SlaveFile {
            description,
            keys: IdentityKeys::scan(text),
            lint: lint(text),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_with_values_count_in_any_case() {
        let text = b"[DeviceInfo]\nVendorNumber=0x5 ; vendor\nproductnumber=\nRevisionNumber=0\n\
                     [DeviceComissioning]\nLSS_SerialNumber=0\n[Other]\nVendorNumber=1\n";
        let keys = IdentityKeys::scan(text);
        assert_eq!(
            keys,
            IdentityKeys {
                vendor: true,
                product: false,
                revision: true,
                serial: true
            }
        );
        assert_eq!(
            IdentityKeys::scan(b"[Other]\nRevisionNumber=1\n"),
            IdentityKeys::default()
        );
    }
}
