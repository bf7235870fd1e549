//! Where "save all parameters" (0x1010) puts the parameters and where the node finds them at the next
//! reset; "restore default parameters" (0x1011) forgets them.
//!
//! The parameter set is a small text file: a first line naming the format, one `IIII:SS HEX` line per
//! entry, and a last line with the CRC-32 of everything before it. [`FileStorage`] writes it to a
//! temporary file beside the target, syncs it, renames it over the target and syncs the directory, so a
//! process killed at any moment leaves the old set or the new one, never a mix; a file that is not a
//! complete set (bad first line, bad line, wrong CRC) is refused as a whole when it is loaded.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// First line of a parameter file.
const MAGIC: &str = "x67-node parameters 1";

/// The largest parameter file [`FileStorage`] reads: far above any set a node writes (16 modules make
/// some 40 KiB), so that a file that is not one is refused before it is read.
pub const MAX_PARAMETER_FILE: u64 = 4 << 20;

/// What a node asks its edge to do with the stored parameter set ([`super::Node::poll_storage`]).
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum StorageRequest {
    /// Replace the stored set with this one (0x1010 "save").
    Save(Vec<u8>),
    /// Forget the stored set (0x1011 "load"): the defaults apply at the next reset.
    Clear,
    /// Keep the LSS configuration (CiA 305 store configuration): the node-ID (0xFF: none) and the
    /// bit-timing table index the node starts with next time.
    SaveLss {
        /// The node-ID.
        node_id: u8,
        /// The bit-timing table index.
        bit_timing: u8,
    },
}

/// An LSS configuration kept by the edge (CiA 305 store configuration).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LssStored {
    /// The node-ID (0xFF: none).
    pub node_id: u8,
    /// The bit-timing table index.
    pub bit_timing: u8,
}

impl StorageRequest {
    /// Carries the request out on `storage`.
    pub fn apply(&self, storage: &mut dyn ParameterStorage) -> io::Result<()> {
        match self {
            StorageRequest::Save(set) => storage.save(set),
            StorageRequest::Clear => storage.clear(),
            StorageRequest::SaveLss {
                node_id,
                bit_timing,
            } => storage.save_lss(LssStored {
                node_id: *node_id,
                bit_timing: *bit_timing,
            }),
        }
    }
}

/// A place to keep one parameter set.
pub trait ParameterStorage: Send {
    /// The stored set, or `None` when there is none.
    fn load(&mut self) -> io::Result<Option<Vec<u8>>>;
    /// Replaces the stored set with `data`, all or nothing.
    fn save(&mut self, data: &[u8]) -> io::Result<()>;
    /// Forgets the stored set (the defaults apply at the next reset).
    fn clear(&mut self) -> io::Result<()>;
    /// The stored LSS configuration, or `None` when there is none.
    fn load_lss(&mut self) -> io::Result<Option<LssStored>> {
        Ok(None)
    }
    /// Keeps an LSS configuration, all or nothing.
    fn save_lss(&mut self, lss: LssStored) -> io::Result<()> {
        let _ = lss;
        Err(io::Error::new(
            io::ErrorKind::Unsupported,
            "this storage keeps no LSS configuration",
        ))
    }
}

/// Parameters kept in memory only (the default without `--storage`, and for tests).
#[derive(Debug, Default, Clone)]
pub struct MemoryStorage {
    /// The stored set.
    pub data: Option<Vec<u8>>,
    /// The stored LSS configuration.
    pub lss: Option<LssStored>,
}

impl ParameterStorage for MemoryStorage {
    fn load(&mut self) -> io::Result<Option<Vec<u8>>> {
        Ok(self.data.clone())
    }

    fn save(&mut self, data: &[u8]) -> io::Result<()> {
        self.data = Some(data.to_vec());
        Ok(())
    }

    fn clear(&mut self) -> io::Result<()> {
        self.data = None;
        Ok(())
    }

    fn load_lss(&mut self) -> io::Result<Option<LssStored>> {
        Ok(self.lss)
    }

    fn save_lss(&mut self, lss: LssStored) -> io::Result<()> {
        self.lss = Some(lss);
        Ok(())
    }
}

/// Parameters in a file, replaced atomically.
#[derive(Debug, Clone)]
pub struct FileStorage {
    path: PathBuf,
}

impl FileStorage {
    /// Storage in `path` (the file need not exist yet; its directory must).
    pub fn new(path: impl Into<PathBuf>) -> FileStorage {
        FileStorage { path: path.into() }
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn dir(&self) -> PathBuf {
        match self.path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        }
    }

    fn sync_dir(&self) -> io::Result<()> {
        fs::File::open(self.dir())?.sync_all()
    }

    /// The file of the LSS configuration, beside the parameters: `PATH.lss`, in the same format
    /// (entry 0000:01 the node-ID, 0000:02 the bit-timing index).
    pub fn lss_path(&self) -> PathBuf {
        let mut p = self.path.clone().into_os_string();
        p.push(".lss");
        p.into()
    }

    /// Replaces `path` (in this file's directory) with `data`: a temporary copy beside it, synced,
    /// renamed over it, the directory synced.
    fn replace(&self, path: &Path, data: &[u8]) -> io::Result<()> {
        let mut tmp = tempfile::Builder::new()
            .prefix(&temp_prefix(path))
            .tempfile_in(self.dir())?;
        tmp.write_all(data)?;
        tmp.as_file().sync_all()?;
        tmp.persist(path).map_err(|e| e.error)?;
        self.sync_dir()
    }

    /// Removes the temporary copies a process killed during a save left beside the file.
    fn remove_stale_copies(&self) {
        let prefix = temp_prefix(&self.path);
        let Ok(entries) = fs::read_dir(self.dir()) else {
            return;
        };
        for entry in entries.flatten() {
            let stale = entry.file_name().to_string_lossy().starts_with(&prefix)
                && entry.file_type().is_ok_and(|t| t.is_file());
            if stale {
                let _ = fs::remove_file(entry.path());
            }
        }
    }
}

/// Reads `path` if it is a regular file of at most [`MAX_PARAMETER_FILE`] bytes (`None` when it does
/// not exist); anything else is refused before it is read or opened.
fn read_bounded(path: &Path) -> io::Result<Option<Vec<u8>>> {
    match od::load::read_limited(path, MAX_PARAMETER_FILE).map_err(io::Error::from) {
        Ok(bytes) => Ok(Some(bytes)),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e),
    }
}

impl ParameterStorage for FileStorage {
    /// The stored set (removing first what a save killed midway left beside it).
    fn load(&mut self) -> io::Result<Option<Vec<u8>>> {
        self.remove_stale_copies();
        read_bounded(&self.path)
    }

    fn save(&mut self, data: &[u8]) -> io::Result<()> {
        self.replace(&self.path, data)
    }

    fn clear(&mut self) -> io::Result<()> {
        match fs::remove_file(&self.path) {
            Ok(()) => self.sync_dir(),
            Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(()),
            Err(e) => Err(e),
        }
    }

    /// The LSS configuration of `PATH.lss`; a file that is not a complete one is refused.
    fn load_lss(&mut self) -> io::Result<Option<LssStored>> {
        let Some(bytes) = read_bounded(&self.lss_path())? else {
            return Ok(None);
        };
        let bad = |why: String| io::Error::new(io::ErrorKind::InvalidData, why);
        let entries = decode(&bytes).map_err(|e| bad(e.to_string()))?;
        let byte = |sub: u8| {
            entries
                .iter()
                .find(|(i, s, v)| (*i, *s) == (0, sub) && v.len() == 1)
                .map(|(_, _, v)| v[0])
        };
        match (byte(1), byte(2)) {
            (Some(node_id), Some(bit_timing)) => Ok(Some(LssStored {
                node_id,
                bit_timing,
            })),
            _ => Err(bad(
                "not an LSS configuration (0000:01 and 0000:02 missing)".into(),
            )),
        }
    }

    fn save_lss(&mut self, lss: LssStored) -> io::Result<()> {
        let set = encode(&[(0, 1, vec![lss.node_id]), (0, 2, vec![lss.bit_timing])]);
        self.replace(&self.lss_path(), &set)
    }
}

/// The name of a file's temporary copies, beside it: `.NAME.tmp-…`.
fn temp_prefix(path: &Path) -> String {
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    format!(".{name}.tmp-")
}

/// Why a stored parameter set was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ParamFileError {
    /// The first line is not the format's.
    #[error("not a parameter set (first line is not {MAGIC:?})")]
    Magic,
    /// A line is not `IIII:SS HEX`.
    #[error("line {line}: expected `IIII:SS HEX`, found {text:?}")]
    Line {
        /// 1-based line number.
        line: usize,
        /// The line.
        text: String,
    },
    /// The CRC line is missing or does not match: the set is incomplete or damaged.
    #[error("the set is incomplete or damaged (CRC line missing or wrong)")]
    Crc,
}

/// Writes `entries` (index, sub, value bytes) as a parameter set.
pub fn encode(entries: &[(u16, u8, Vec<u8>)]) -> Vec<u8> {
    let mut text = String::with_capacity(32 + entries.len() * 24);
    text.push_str(MAGIC);
    text.push('\n');
    for (index, sub, value) in entries {
        text.push_str(&format!("{index:04X}:{sub:02X} "));
        for b in value {
            text.push_str(&format!("{b:02X}"));
        }
        text.push('\n');
    }
    let crc = crc32(text.as_bytes());
    text.push_str(&format!("crc32 {crc:08X}\n"));
    text.into_bytes()
}

/// Reads a parameter set written by [`encode`].
pub fn decode(bytes: &[u8]) -> Result<Vec<(u16, u8, Vec<u8>)>, ParamFileError> {
    let text = std::str::from_utf8(bytes).map_err(|_| ParamFileError::Magic)?;
    let body_end = text.rfind("crc32 ").ok_or(ParamFileError::Crc)?;
    let (body, crc_line) = text.split_at(body_end);
    let want = crc_line
        .trim_end()
        .strip_prefix("crc32 ")
        .and_then(|h| u32::from_str_radix(h, 16).ok())
        .ok_or(ParamFileError::Crc)?;
    if crc32(body.as_bytes()) != want || !crc_line.ends_with('\n') {
        return Err(ParamFileError::Crc);
    }
    let mut lines = body.lines();
    if lines.next() != Some(MAGIC) {
        return Err(ParamFileError::Magic);
    }
    let mut out = Vec::new();
    for (n, line) in lines.enumerate() {
        let bad = || ParamFileError::Line {
            line: n + 2,
            text: line.chars().take(80).collect(),
        };
        let (mux, hex) = line.split_once(' ').ok_or_else(bad)?;
        let (i, s) = mux.split_once(':').ok_or_else(bad)?;
        let index = u16::from_str_radix(i, 16).map_err(|_| bad())?;
        let sub = u8::from_str_radix(s, 16).map_err(|_| bad())?;
        if hex.len() % 2 != 0 || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
            return Err(bad());
        }
        let value = (0..hex.len())
            .step_by(2)
            .map(|k| u8::from_str_radix(&hex[k..k + 2], 16).map_err(|_| bad()))
            .collect::<Result<Vec<u8>, _>>()?;
        out.push((index, sub, value));
    }
    Ok(out)
}

/// CRC-32 (IEEE 802.3, reflected, as zip and PNG use it).
fn crc32(data: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in data {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_of_the_check_string() {
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
    }

    #[test]
    fn round_trip_and_refusals() {
        let set = vec![(0x1017, 0, vec![0xE8, 0x03]), (0x2114, 0, vec![0x10, 0x27])];
        let bytes = encode(&set);
        assert_eq!(
            String::from_utf8(bytes.clone()).unwrap(),
            "x67-node parameters 1\n1017:00 E803\n2114:00 1027\ncrc32 ".to_string()
                + &format!(
                    "{:08X}\n",
                    crc32(b"x67-node parameters 1\n1017:00 E803\n2114:00 1027\n")
                )
        );
        assert_eq!(decode(&bytes).unwrap(), set);
        // Every strict prefix (a torn write) is refused as a whole.
        for n in 0..bytes.len() {
            assert!(decode(&bytes[..n]).is_err(), "prefix of {n} bytes accepted");
        }
        let mut flipped = bytes.clone();
        flipped[30] ^= 1;
        assert_eq!(decode(&flipped), Err(ParamFileError::Crc));
    }

    /// `body` with its CRC line, as a complete set.
    fn signed(body: &str) -> Vec<u8> {
        format!("{body}crc32 {:08X}\n", crc32(body.as_bytes())).into_bytes()
    }

    /// A set whose CRC is right but with a line that is not `IIII:SS HEX` is refused by that line's
    /// number (the format line is line 1): an odd number of digits, a digit that is not hexadecimal,
    /// a sign.
    #[test]
    fn a_bad_line_is_named_by_its_number() {
        let bad = |line: usize, text: &str| ParamFileError::Line {
            line,
            text: text.into(),
        };
        assert_eq!(
            decode(&signed("x67-node parameters 1\n1017:00 E80\n")),
            Err(bad(2, "1017:00 E80"))
        );
        assert_eq!(
            decode(&signed(
                "x67-node parameters 1\n1017:00 E803\n2114:00 10Z7\n"
            )),
            Err(bad(3, "2114:00 10Z7"))
        );
        assert_eq!(
            decode(&signed("x67-node parameters 1\n1017:00 E803\n1016:01 +1\n")),
            Err(bad(3, "1016:01 +1"))
        );
        assert_eq!(
            decode(&signed("x67-node parameters 1\n1017:00 E803\n")),
            Ok(vec![(0x1017, 0, vec![0xE8, 0x03])])
        );
    }

    /// A file named without a folder lives in the working directory: that is the folder its
    /// temporary copies go to and the one synced.
    #[test]
    fn the_folder_of_a_bare_file_name_is_the_working_directory() {
        assert_eq!(FileStorage::new("node5.params").dir(), PathBuf::from("."));
        assert_eq!(
            FileStorage::new("/var/lib/node/node5.params").dir(),
            PathBuf::from("/var/lib/node")
        );
    }

    #[test]
    fn file_storage_replaces_and_clears() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = FileStorage::new(dir.path().join("p.txt"));
        assert_eq!(s.load().unwrap(), None);
        s.save(b"one").unwrap();
        s.save(b"two").unwrap();
        assert_eq!(s.load().unwrap().as_deref(), Some(&b"two"[..]));
        // No temporary file is left behind.
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
        s.clear().unwrap();
        assert_eq!(s.load().unwrap(), None);
        s.clear().unwrap();
    }

    /// What is not a parameter file is refused before it is read: a FIFO (opening one would wait for
    /// a writer forever), a directory, a file over the limit (no more read than the limit).
    #[test]
    fn file_storage_reads_only_bounded_regular_files() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("fifo");
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(made.success());
        let e = FileStorage::new(&fifo).load().unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
        assert_eq!(e.to_string(), "not a regular file");
        // A folder as the file (inside the test's own folder, so that the clean-up of stale copies
        // looks there and nowhere else).
        let folder = dir.path().join("folder");
        fs::create_dir(&folder).unwrap();
        let e = FileStorage::new(&folder).load().unwrap_err();
        assert_eq!(e.to_string(), "not a regular file");
        let big = dir.path().join("big");
        let f = fs::File::create(&big).unwrap();
        f.set_len(MAX_PARAMETER_FILE + 1).unwrap();
        let e = FileStorage::new(&big).load().unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "{} bytes, more than the 4194304 such a file may have (CANOPEN_MAX_FILE_BYTES=BYTES raises the limit)",
                4 * 1024 * 1024 + 1
            )
        );
        // At the limit: read (and refused as a set by `decode`, not by its size).
        f.set_len(MAX_PARAMETER_FILE).unwrap();
        assert_eq!(
            FileStorage::new(&big).load().unwrap().map(|b| b.len()),
            Some(4 << 20)
        );
    }

    /// A save killed midway leaves its temporary copy beside the file; the next load removes it (and
    /// only this file's copies).
    #[test]
    fn stale_copies_of_a_killed_save_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("node5.params");
        fs::write(dir.path().join(".node5.params.tmp-a1b2c3"), b"half").unwrap();
        fs::write(dir.path().join(".node6.params.tmp-a1b2c3"), b"other").unwrap();
        let mut s = FileStorage::new(&path);
        s.save(b"set").unwrap();
        assert_eq!(s.load().unwrap().as_deref(), Some(&b"set"[..]));
        let mut names: Vec<String> = fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, [".node6.params.tmp-a1b2c3", "node5.params"]);
    }
}
