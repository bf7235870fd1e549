//! A slave's description as generation takes it: the dictionary `od` read, and which identity keys
//! the file itself gives, since a key that is there, even as 0, takes the place of 0x1018's value.

use od::DeviceDescription;

use crate::lint::{lint, Lint};

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
        let text = String::from_utf8_lossy(text);
        let mut keys = IdentityKeys::default();
        let mut section = String::new();
        for line in text.lines().map(str::trim) {
            if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
                section = name.trim().to_ascii_lowercase();
                continue;
            }
            let Some((key, value)) = line.split_once('=') else {
                continue;
            };
            let value = value.split([';', '#']).next().unwrap_or("").trim();
            if value.is_empty() {
                continue;
            }
            match (section.as_str(), key.trim().to_ascii_lowercase().as_str()) {
                ("deviceinfo", "vendornumber") => keys.vendor = true,
                ("deviceinfo", "productnumber") => keys.product = true,
                ("deviceinfo", "revisionnumber") => keys.revision = true,
                ("devicecomissioning", "lss_serialnumber") => keys.serial = true,
                _ => {}
            }
        }
        keys
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
