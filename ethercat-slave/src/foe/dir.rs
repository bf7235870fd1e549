//! A folder that keeps the units' files across runs (`ethercat-node --foe-dir DIR`): unit *n*'s
//! files (1 for the first in the chain) in `DIR/unit<n>/`, one file each, its contents the file's.
//!
//! A name is kept as it is where it is made of `A–Z a–z 0–9 _ - .` and does not start with `.`;
//! any other byte is written `%XX` (two upper-case hexadecimal digits), so every FoE name is a
//! file name and none is a path. Read back, `%XX` is the byte and everything else itself: a file a
//! user puts in the folder keeps its name. A write goes to a hidden temporary file renamed over
//! the old one; files whose names start with `.`, and folders, are not a unit's files.
//!
//! This is the edge: the server ([`super::FoeServer`]) never touches a file.

use std::ffi::OsStr;
use std::os::unix::ffi::OsStrExt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::store::{FileStore, StoreError};

/// Why a folder could not be read or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DirError {
    /// The operating system's error on a path.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A file the unit's store does not take.
    #[error("{}: {source}", path.display())]
    Store {
        /// The file.
        path: PathBuf,
        /// Why.
        source: StoreError,
    },
}

/// The folder of the unit at `position` (1 for the first) under `root`.
pub fn unit_dir(root: &Path, position: usize) -> PathBuf {
    root.join(format!("unit{position}"))
}

/// `name` as a file name: see the [module documentation](self).
pub fn encode(name: &[u8]) -> String {
    let mut out = String::with_capacity(name.len());
    for (k, &b) in name.iter().enumerate() {
        let plain = b.is_ascii_alphanumeric() || b == b'_' || b == b'-' || (b == b'.' && k > 0);
        if plain {
            out.push(char::from(b));
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

/// The FoE name of the file `file_name`: see the [module documentation](self).
pub fn decode(file_name: &OsStr) -> Vec<u8> {
    let b = file_name.as_bytes();
    let hex = |c: u8| char::from(c).to_digit(16);
    let mut out = Vec::with_capacity(b.len());
    let mut k = 0;
    while k < b.len() {
        let escaped = (b[k] == b'%')
            .then(|| Some((hex(*b.get(k + 1)?)?, hex(*b.get(k + 2)?)?)))
            .flatten();
        match escaped {
            Some((hi, lo)) => {
                out.push((hi * 16 + lo) as u8);
                k += 3;
            }
            None => {
                out.push(b[k]);
                k += 1;
            }
        }
    }
    out
}

/// Puts the files of the unit at `position` under `root` into `store` (none when its folder is
/// not there): how many. A file over the store's limits, or one whose name it does not take, is
/// an error naming it (and it is not read).
pub fn load(root: &Path, position: usize, store: &mut FileStore) -> Result<usize, DirError> {
    let dir = unit_dir(root, position);
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| DirError::Io { path, source }
    };
    let entries = match std::fs::read_dir(&dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(0),
        Err(e) => return Err(io(&dir)(e)),
    };
    let mut paths: Vec<PathBuf> = Vec::new();
    for entry in entries {
        let entry = entry.map_err(io(&dir))?;
        let hidden = entry.file_name().as_bytes().first() == Some(&b'.');
        if !hidden && entry.file_type().map_err(io(&entry.path()))?.is_file() {
            paths.push(entry.path());
        }
    }
    paths.sort();
    for path in &paths {
        let name = decode(path.file_name().unwrap_or_default());
        let size = std::fs::metadata(path).map_err(io(path))?.len();
        let size = usize::try_from(size).unwrap_or(usize::MAX);
        let refused = |source| DirError::Store {
            path: path.clone(),
            source,
        };
        store.check(&name, size).map_err(refused)?;
        let data = std::fs::read(path).map_err(io(path))?;
        store.load(&name, Arc::from(data)).map_err(refused)?;
    }
    Ok(paths.len())
}

/// Keeps `data` as the file `name` of the unit at `position` under `root` (its folder made where
/// needed): written to a temporary file, then renamed over the old one.
pub fn save(root: &Path, position: usize, name: &[u8], data: &[u8]) -> Result<PathBuf, DirError> {
    let dir = unit_dir(root, position);
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| DirError::Io { path, source }
    };
    std::fs::create_dir_all(&dir).map_err(io(&dir))?;
    let file = encode(name);
    let path = dir.join(&file);
    let temporary = dir.join(format!(".{file}.part"));
    std::fs::write(&temporary, data).map_err(io(&temporary))?;
    std::fs::rename(&temporary, &path).map_err(io(&path))?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Plain names stay; a leading dot, `/`, a space, `%`, NUL and non-ASCII bytes are escaped;
    /// each decodes back to its bytes.
    #[test]
    fn names_are_file_names_and_come_back() {
        for (name, file) in [
            (&b"app.efw"[..], "app.efw"),
            (b"A_b-9", "A_b-9"),
            (b".hidden", "%2Ehidden"),
            (b"..", "%2E."),
            (b"a/b", "a%2Fb"),
            (b"x y%", "x%20y%25"),
            (b"\0\xff", "%00%FF"),
        ] {
            assert_eq!(encode(name), file);
            assert_eq!(decode(OsStr::new(file)), name);
        }
        // A user's file keeps its name, a stray % included.
        assert_eq!(decode(OsStr::new("my file%zz%4")), b"my file%zz%4");
    }

    /// Saved files load into a fresh store with their names and contents; hidden files and
    /// folders are not loaded; a missing folder is no file; a file over the limit is refused,
    /// naming it.
    #[test]
    fn saved_files_load_again() {
        let root = std::env::temp_dir().join(format!("foe-dir-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let path = save(&root, 2, b"fw 1.efw", &[1, 2, 3]).unwrap();
        assert_eq!(path, root.join("unit2/fw%201.efw"));
        save(&root, 2, b"empty", &[]).unwrap();
        save(&root, 2, b"fw 1.efw", &[4, 5]).unwrap();
        std::fs::create_dir(root.join("unit2/sub")).unwrap();
        std::fs::write(root.join("unit2/.junk"), b"x").unwrap();
        let mut store = FileStore::new(10, 100);
        assert_eq!(load(&root, 2, &mut store).unwrap(), 2);
        assert_eq!(store.get(b"fw 1.efw").map(|f| f.to_vec()), Some(vec![4, 5]));
        assert_eq!(store.get(b"empty").map(|f| f.len()), Some(0));
        assert_eq!(store.take_written(), None);
        assert_eq!(load(&root, 3, &mut store).unwrap(), 0);
        let mut small = FileStore::new(1, 100);
        let e = load(&root, 2, &mut small).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "{}: 2 bytes, over the 1-byte limit of a file",
                root.join("unit2/fw%201.efw").display()
            )
        );
        // A unit's folder that is a file: no folder to read, said with its path (not "no files").
        std::fs::write(root.join("unit4"), b"not a folder").unwrap();
        let e = load(&root, 4, &mut store).unwrap_err();
        assert!(
            matches!(&e, DirError::Io { path, source }
                if *path == root.join("unit4") && source.kind() == std::io::ErrorKind::NotADirectory),
            "{e:?}"
        );
        std::fs::remove_dir_all(&root).unwrap();
    }
}
