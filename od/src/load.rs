//! Reading a description file of any supported format: the format is told from the contents (the XML
//! root element, or an INI file's sections), with the file name's extension as a tie-breaker between EDS
//! and DCF.

use std::fmt;
use std::path::Path;

use crate::device::DeviceDescription;
use crate::error::{LoadError, ParseError};
use crate::{eds, esi, xdd};

/// A description format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    /// EtherCAT Slave Information (ETG.2000).
    Esi,
    /// CANopen device description, XML (CiA 311 XDD; XDC for a configured device).
    Xdd,
    /// Electronic data sheet (CiA 306 EDS).
    Eds,
    /// Device configuration file (CiA 306 DCF).
    Dcf,
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Esi => "ESI",
            Format::Xdd => "XDD",
            Format::Eds => "EDS",
            Format::Dcf => "DCF",
        })
    }
}

impl Format {
    /// Tells the format of `bytes`, using `path`'s extension only to tell a DCF from an EDS when the
    /// contents do not (a DCF has a `[DeviceComissioning]` section).
    pub fn detect(path: &Path, bytes: &[u8]) -> Option<Format> {
        let head = &bytes[..bytes.len().min(4096)];
        let text = String::from_utf8_lossy(head);
        let lower = text.to_ascii_lowercase();
        if lower.contains("<ethercatinfo") {
            return Some(Format::Esi);
        }
        if lower.contains("<iso15745profilecontainer")
            || lower.contains(":iso15745profilecontainer")
        {
            return Some(Format::Xdd);
        }
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase());
        let whole = String::from_utf8_lossy(bytes).to_ascii_lowercase();
        if whole.contains("[devicecomissioning]") || whole.contains("[devicecommissioning]") {
            return Some(Format::Dcf);
        }
        if lower.contains("[fileinfo]")
            || lower.contains("[deviceinfo]")
            || whole.contains("[mandatoryobjects]")
        {
            return Some(if ext.as_deref() == Some("dcf") {
                Format::Dcf
            } else {
                Format::Eds
            });
        }
        match ext.as_deref() {
            Some("xml") | Some("esi") => Some(Format::Esi),
            Some("xdd") | Some("xdc") | Some("xpd") => Some(Format::Xdd),
            Some("eds") => Some(Format::Eds),
            Some("dcf") => Some(Format::Dcf),
            _ => None,
        }
    }
}

/// Reads every device of `bytes` in `format` (an ESI may hold several; the other formats hold one).
pub fn read_bytes(
    bytes: &[u8],
    source_name: &str,
    format: Format,
) -> Result<Vec<DeviceDescription>, ParseError> {
    match format {
        Format::Esi => esi::read_all(bytes, source_name),
        Format::Xdd => xdd::read(bytes, source_name).map(|d| vec![d]),
        Format::Eds | Format::Dcf => eds::read(bytes, source_name).map(|d| vec![d]),
    }
}

/// Reads the description file at `path`: its format and every device it describes.
pub fn load(path: &Path) -> Result<(Format, Vec<DeviceDescription>), LoadError> {
    let bytes = std::fs::read(path).map_err(|source| LoadError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let format =
        Format::detect(path, &bytes).ok_or_else(|| LoadError::UnknownFormat(path.to_path_buf()))?;
    let name = path.display().to_string();
    let devices = read_bytes(&bytes, &name, format)?;
    Ok((format, devices))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_are_told_by_content_then_extension() {
        let p = Path::new("x.bin");
        assert_eq!(
            Format::detect(p, b"<?xml version=\"1.0\"?>\n<EtherCATInfo>"),
            Some(Format::Esi)
        );
        assert_eq!(
            Format::detect(
                p,
                b"<?xml version=\"1.1\"?><ISO15745ProfileContainer xmlns=\"x\">"
            ),
            Some(Format::Xdd)
        );
        assert_eq!(
            Format::detect(p, b"[FileInfo]\nFileName=a.eds\n"),
            Some(Format::Eds)
        );
        assert_eq!(
            Format::detect(Path::new("a.dcf"), b"[FileInfo]\n"),
            Some(Format::Dcf)
        );
        assert_eq!(
            Format::detect(p, b"[FileInfo]\n[DeviceComissioning]\nNodeID=2\n"),
            Some(Format::Dcf)
        );
        assert_eq!(Format::detect(p, b"hello"), None);
    }
}
