//! A unit's files: held by name, each up to a size limit and all of them together up to another,
//! with the names written since the edge last took them (to keep them in a folder,
//! [`super::dir`]). No I/O here.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;

/// The longest file name a store takes, in bytes (a name kept in a folder, escaped, stays within
/// the 255 bytes a Linux file name may have).
pub const MAX_NAME: usize = 80;
/// The most files a store holds.
pub const MAX_FILES: usize = 256;

/// Why a file is not taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum StoreError {
    /// The name is empty or longer than [`MAX_NAME`].
    #[error("a file name of {0} bytes (1 to {MAX_NAME})")]
    Name(usize),
    /// The file is over the limit of one file.
    #[error("{size} bytes, over the {limit}-byte limit of a file")]
    FileTooLarge {
        /// Its size.
        size: usize,
        /// The limit.
        limit: usize,
    },
    /// The file does not fit beside the others.
    #[error(
        "{size} bytes do not fit: {used} of the store's {limit} bytes are taken by other files"
    )]
    StoreFull {
        /// Its size.
        size: usize,
        /// What the other files take.
        used: usize,
        /// The limit.
        limit: usize,
    },
    /// Already [`MAX_FILES`] other files.
    #[error("the store holds {MAX_FILES} files already")]
    TooManyFiles,
}

/// A unit's files. See the [module documentation](self).
#[derive(Debug, Clone)]
pub struct FileStore {
    files: BTreeMap<Vec<u8>, Arc<[u8]>>,
    /// The bytes of all files.
    used: usize,
    max_file: usize,
    max_store: usize,
    /// The names written since [`FileStore::take_written`] last gave them.
    written: BTreeSet<Vec<u8>>,
}

impl FileStore {
    /// An empty store taking files of up to `max_file` bytes, `max_store` bytes in all.
    pub fn new(max_file: usize, max_store: usize) -> FileStore {
        FileStore {
            files: BTreeMap::new(),
            used: 0,
            max_file,
            max_store,
            written: BTreeSet::new(),
        }
    }

    /// The limit of one file.
    pub fn max_file(&self) -> usize {
        self.max_file
    }

    /// The limit of all files.
    pub fn max_store(&self) -> usize {
        self.max_store
    }

    /// The bytes all files take.
    pub fn used(&self) -> usize {
        self.used
    }

    /// The file `name`.
    pub fn get(&self, name: &[u8]) -> Option<&Arc<[u8]>> {
        self.files.get(name)
    }

    /// The names, in byte order.
    pub fn names(&self) -> impl Iterator<Item = &[u8]> {
        self.files.keys().map(Vec::as_slice)
    }

    /// Whether `name` is one a store takes: 1 to [`MAX_NAME`] bytes.
    pub fn check_name(name: &[u8]) -> Result<(), StoreError> {
        if name.is_empty() || name.len() > MAX_NAME {
            return Err(StoreError::Name(name.len()));
        }
        Ok(())
    }

    /// Whether a file `name` of `size` bytes would be taken, in place of the file of that name
    /// where there is one.
    pub fn check(&self, name: &[u8], size: usize) -> Result<(), StoreError> {
        FileStore::check_name(name)?;
        if size > self.max_file {
            return Err(StoreError::FileTooLarge {
                size,
                limit: self.max_file,
            });
        }
        let old = self.files.get(name);
        let used = self.used - old.map_or(0, |f| f.len());
        if size > self.max_store.saturating_sub(used) {
            return Err(StoreError::StoreFull {
                size,
                used,
                limit: self.max_store,
            });
        }
        if old.is_none() && self.files.len() >= MAX_FILES {
            return Err(StoreError::TooManyFiles);
        }
        Ok(())
    }

    /// Puts `data` as `name`, in place of the file of that name; a refused file changes nothing.
    pub fn put(&mut self, name: &[u8], data: Arc<[u8]>) -> Result<(), StoreError> {
        self.check(name, data.len())?;
        self.used += data.len();
        if let Some(old) = self.files.insert(name.to_vec(), data) {
            self.used -= old.len();
        }
        self.written.insert(name.to_vec());
        Ok(())
    }

    /// Puts a file the unit had before it started (read back from a folder): as [`put`](FileStore::put),
    /// but not counted as written.
    pub fn load(&mut self, name: &[u8], data: Arc<[u8]>) -> Result<(), StoreError> {
        self.put(name, data)?;
        self.written.remove(name);
        Ok(())
    }

    /// A file written since the last call (the edge keeps it), with its contents as they are now.
    pub fn take_written(&mut self) -> Option<(Vec<u8>, Arc<[u8]>)> {
        let name = self.written.pop_first()?;
        let data = self.files.get(&name)?.clone();
        Some((name, data))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bytes(n: usize) -> Arc<[u8]> {
        vec![7u8; n].into()
    }

    /// A file up to the file limit is taken; one byte more is refused with the limit named; in all
    /// the files take at most the store limit, a file replacing one of its name counting without
    /// the old one; a refusal leaves the store as it was.
    #[test]
    fn limits_of_a_file_and_of_the_store() {
        let mut s = FileStore::new(10, 25);
        s.put(b"a", bytes(10)).unwrap();
        assert_eq!(
            s.put(b"b", bytes(11)),
            Err(StoreError::FileTooLarge {
                size: 11,
                limit: 10
            })
        );
        s.put(b"b", bytes(10)).unwrap();
        assert_eq!(
            s.put(b"c", bytes(6)),
            Err(StoreError::StoreFull {
                size: 6,
                used: 20,
                limit: 25
            })
        );
        assert_eq!(s.used(), 20);
        assert!(s.get(b"c").is_none());
        s.put(b"c", bytes(5)).unwrap();
        assert_eq!(s.used(), 25);
        // Replacing "a" (10 bytes): the others take 15, so 10 fit again and 11 do not.
        s.put(b"a", bytes(10)).unwrap();
        assert_eq!(
            s.check(b"a", 11),
            Err(StoreError::FileTooLarge {
                size: 11,
                limit: 10
            })
        );
        s.put(b"a", bytes(2)).unwrap();
        assert_eq!(s.used(), 17);
        assert_eq!(s.names().collect::<Vec<_>>(), [b"a", b"b", b"c"]);
        let msg = StoreError::StoreFull {
            size: 6,
            used: 20,
            limit: 25,
        }
        .to_string();
        assert_eq!(
            msg,
            "6 bytes do not fit: 20 of the store's 25 bytes are taken by other files"
        );
    }

    /// Names of 1 to 80 bytes; at most 256 files, a file replacing one still taken then.
    #[test]
    fn names_and_the_number_of_files() {
        assert_eq!(FileStore::check_name(b""), Err(StoreError::Name(0)));
        assert_eq!(
            FileStore::check_name(&[b'x'; 81]),
            Err(StoreError::Name(81))
        );
        assert_eq!(FileStore::check_name(&[b'x'; 80]), Ok(()));
        let mut s = FileStore::new(10, 10);
        for k in 0..256u32 {
            s.put(format!("{k}").as_bytes(), bytes(0)).unwrap();
        }
        assert_eq!(s.put(b"new", bytes(0)), Err(StoreError::TooManyFiles));
        s.put(b"7", bytes(1)).unwrap();
    }

    /// What was written is given once each, with its latest contents; what was loaded is not.
    #[test]
    fn written_files_are_given_once() {
        let mut s = FileStore::new(10, 100);
        s.load(b"old", bytes(3)).unwrap();
        s.put(b"b", bytes(1)).unwrap();
        s.put(b"a", bytes(1)).unwrap();
        s.put(b"b", bytes(2)).unwrap();
        assert_eq!(s.take_written(), Some((b"a".to_vec(), bytes(1))));
        assert_eq!(s.take_written(), Some((b"b".to_vec(), bytes(2))));
        assert_eq!(s.take_written(), None);
        assert_eq!(s.get(b"old").map(|f| f.len()), Some(3));
    }
}
