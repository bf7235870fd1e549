//! Cross-crate integration tests: the fixtures against the device documents' rules, and shared helpers.
#![deny(missing_docs)]

use std::path::{Path, PathBuf};

use od::device::DeviceDescription;

/// `ARCHITECTURE.md`: its examples run as this crate's doc tests.
#[doc = include_str!("../ARCHITECTURE.md")]
pub mod architecture {}

/// The workspace root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A path under `fixtures/`.
pub fn fixture(rel: &str) -> PathBuf {
    root().join("fixtures").join(rel)
}

/// Every device of a description file; panics with the reader's message when it cannot be read.
pub fn load_all(path: &Path) -> Vec<DeviceDescription> {
    match od::load::load(path) {
        Ok((_, devices)) => devices,
        Err(e) => panic!("{e}"),
    }
}

/// The single device of a description file.
pub fn load_one(path: &Path) -> DeviceDescription {
    let mut all = load_all(path);
    assert_eq!(
        all.len(),
        1,
        "{} should describe one device",
        path.display()
    );
    all.remove(0)
}
