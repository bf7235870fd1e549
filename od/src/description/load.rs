//! Reading a description file of any supported format: the format is told from the contents (the XML
//! root element, or an INI file's sections), with the file name's extension as a tie-breaker between EDS
//! and DCF.

use std::fmt;
use std::io::Read as _;
use std::path::Path;

use crate::device::DeviceDescription;
use crate::error::{LoadError, ParseError};
use crate::report::Reading;
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
        let has = |needle: &[u8]| {
            bytes
                .windows(needle.len())
                .any(|w| w.eq_ignore_ascii_case(needle))
        };
        if has(b"[devicecomissioning]") || has(b"[devicecommissioning]") {
            return Some(Format::Dcf);
        }
        if lower.contains("[fileinfo]")
            || lower.contains("[deviceinfo]")
            || has(b"[mandatoryobjects]")
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
    read_reading(bytes, source_name, format).map(|r| r.devices)
}

/// Reads `bytes` in `format` as [`read_bytes`] does, with where each part was read and the reader's
/// warnings.
pub fn read_reading(
    bytes: &[u8],
    source_name: &str,
    format: Format,
) -> Result<Reading, ParseError> {
    match format {
        Format::Esi => esi::read_file(bytes, source_name),
        Format::Xdd => xdd::read_file(bytes, source_name),
        Format::Eds | Format::Dcf => eds::read_file(bytes, source_name),
    }
}

/// The largest description file [`load`] reads: 256 MiB, far above the largest real file (a few MB).
pub const MAX_FILE_BYTES: u64 = 256 << 20;

/// Reads the description file at `path`: its format and every device it describes.
pub fn load(path: &Path) -> Result<(Format, Vec<DeviceDescription>), LoadError> {
    load_reading(path).map(|(format, reading)| (format, reading.devices))
}

/// Reads the description file at `path` as [`load`] does, with where each part was read and the
/// reader's warnings.
pub fn load_reading(path: &Path) -> Result<(Format, Reading), LoadError> {
    let bytes = read_limited(path, MAX_FILE_BYTES)?;
    let format =
        Format::detect(path, &bytes).ok_or_else(|| LoadError::UnknownFormat(path.to_path_buf()))?;
    let name = path.display().to_string();
    let reading = read_reading(&bytes, &name, format)?;
    Ok((format, reading))
}

/// The environment variable that replaces every file size limit of the tools (descriptions, identity
/// files, scripts, parameter sets) with its value in bytes, for the rare file larger than its default.
pub const LIMIT_VARIABLE: &str = "CANOPEN_MAX_FILE_BYTES";

/// The size limit in force: `default`, or the value of [`LIMIT_VARIABLE`] when it is set (`None`
/// when unset; a value that is not a whole number of bytes is an error, never ignored).
pub fn limit_from(default: u64, set: Option<&std::ffi::OsStr>) -> Result<u64, LoadError> {
    match set {
        None => Ok(default),
        Some(v) => {
            let text = v.to_string_lossy();
            text.trim()
                .replace('_', "")
                .parse()
                .map_err(|_| LoadError::BadLimit(text.into_owned()))
        }
    }
}

/// The bytes of the regular file at `path`, refused when it is something else (a FIFO, a device such
/// as `/dev/zero`, a folder) or larger than `limit` bytes (or what [`LIMIT_VARIABLE`] says), so that
/// no input makes the reader wait or take memory out of proportion.
pub fn read_limited(path: &Path, limit: u64) -> Result<Vec<u8>, LoadError> {
    let limit = limit_from(limit, std::env::var_os(LIMIT_VARIABLE).as_deref())?;
    let io = |source| LoadError::Io {
        path: path.to_path_buf(),
        source,
    };
    // Looked at before opening: opening a FIFO for reading waits for a writer.
    if !std::fs::metadata(path).map_err(io)?.is_file() {
        return Err(LoadError::NotAFile(path.to_path_buf()));
    }
    let file = std::fs::File::open(path).map_err(io)?;
    let meta = file.metadata().map_err(io)?;
    if !meta.is_file() {
        return Err(LoadError::NotAFile(path.to_path_buf()));
    }
    if meta.len() > limit {
        return Err(LoadError::TooLarge {
            path: path.to_path_buf(),
            size: meta.len(),
            limit,
        });
    }
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    // The file may grow while it is read: never more than the limit.
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(LoadError::TooLarge {
            path: path.to_path_buf(),
            size: bytes.len() as u64,
            limit,
        });
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    /// The variable replaces the default; unset keeps it; `1_000` is 1,000; anything else is refused
    /// with the value named.
    #[test]
    fn the_limit_variable_replaces_the_default_or_is_refused() {
        use std::ffi::OsStr;
        assert_eq!(limit_from(256, None).unwrap(), 256);
        assert_eq!(limit_from(256, Some(OsStr::new("1000"))).unwrap(), 1000);
        assert_eq!(limit_from(256, Some(OsStr::new("1_000"))).unwrap(), 1000);
        assert_eq!(limit_from(256, Some(OsStr::new(" 7 "))).unwrap(), 7);
        for bad in ["", "1 MiB", "-1", "0x100", "lots"] {
            assert_eq!(
                limit_from(256, Some(OsStr::new(bad)))
                    .unwrap_err()
                    .to_string(),
                format!("CANOPEN_MAX_FILE_BYTES={bad:?} is not a number of bytes")
            );
        }
    }

    /// A refusal becomes an I/O error that leaves the path to its caller; the system's error is kept.
    #[test]
    fn load_errors_as_io_errors() {
        use std::io::ErrorKind;
        let e = std::io::Error::from(LoadError::NotAFile("/dev/zero".into()));
        assert_eq!(
            (e.kind(), e.to_string()),
            (ErrorKind::InvalidInput, "not a regular file".into())
        );
        let e = std::io::Error::from(LoadError::TooLarge {
            path: "big".into(),
            size: 10,
            limit: 9,
        });
        assert_eq!(
            e.to_string(),
            "10 bytes, more than the 9 such a file may have (CANOPEN_MAX_FILE_BYTES=BYTES raises the limit)"
        );
        let gone = std::io::Error::new(ErrorKind::NotFound, "gone");
        let e = std::io::Error::from(LoadError::Io {
            path: "x".into(),
            source: gone,
        });
        assert_eq!(
            (e.kind(), e.to_string()),
            (ErrorKind::NotFound, "gone".into())
        );
        let e = std::io::Error::from(LoadError::UnknownFormat("f.txt".into()));
        assert_eq!(e.kind(), ErrorKind::InvalidData);
        assert!(e.to_string().starts_with("f.txt: not an ESI"), "{e}");
    }

    use super::*;

    #[test]
    fn only_regular_files_up_to_the_limit_are_read() {
        let dir = std::env::temp_dir().join(format!("od-load-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("ten.eds");
        std::fs::write(&file, b"0123456789").unwrap();
        assert_eq!(read_limited(&file, 10).unwrap(), b"0123456789");
        match read_limited(&file, 9) {
            Err(LoadError::TooLarge { size, limit, .. }) => assert_eq!((size, limit), (10, 9)),
            other => panic!("{other:?}"),
        }
        let e = read_limited(&file, 9).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "{}: 10 bytes, more than the 9 such a file may have (CANOPEN_MAX_FILE_BYTES=BYTES raises the limit)",
                file.display()
            )
        );
        assert!(matches!(
            read_limited(&dir, 100),
            Err(LoadError::NotAFile(p)) if p == dir
        ));
        assert!(matches!(
            read_limited(Path::new("/dev/zero"), 100),
            Err(LoadError::NotAFile(_))
        ));
        assert!(matches!(
            read_limited(&dir.join("none.eds"), 100),
            Err(LoadError::Io { .. })
        ));
        assert_eq!(MAX_FILE_BYTES, 268_435_456);
        std::fs::remove_dir_all(&dir).unwrap();
    }

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
        assert_eq!(
            Format::detect(p, b"[FileInfo]\n[DeviceCommissioning]\nNodeID=2\n"),
            Some(Format::Dcf),
            "the correct spelling too"
        );
        let mut late = b"[FileInfo]\n".to_vec();
        late.extend(std::iter::repeat_n(b';', 5000));
        late.extend(b"\n[devicecomissioning]\n");
        assert_eq!(
            Format::detect(p, &late),
            Some(Format::Dcf),
            "beyond the first 4096 bytes"
        );
        assert_eq!(Format::detect(p, b"hello"), None);
        // Any one of the general sections tells an EDS.
        for text in [
            &b"[DeviceInfo]\nVendorName=V\n"[..],
            b"; a comment\n[FileInfo]\n",
            b"[MandatoryObjects]\nSupportedObjects=0\n",
        ] {
            assert_eq!(Format::detect(p, text), Some(Format::Eds), "{text:?}");
        }
    }

    #[test]
    fn read_bytes_gives_the_devices_of_the_text() {
        let devices = read_bytes(
            b"[DeviceInfo]\nProductName=Probe\n",
            "probe.eds",
            Format::Eds,
        )
        .unwrap();
        assert_eq!(devices.len(), 1);
        assert_eq!(devices[0].identity.product_name, "Probe");
    }

    /// A file that holds more than its metadata says (a file growing while it is read; /proc files say
    /// 0 bytes) is read up to the limit and one byte more, and refused.
    #[test]
    fn a_file_longer_than_its_metadata_is_still_held_to_the_limit() {
        let status = Path::new("/proc/self/status");
        assert_eq!(std::fs::metadata(status).unwrap().len(), 0);
        match read_limited(status, 10) {
            Err(LoadError::TooLarge { size, limit, .. }) => assert_eq!((size, limit), (11, 10)),
            other => panic!("{other:?}"),
        }
    }
}
