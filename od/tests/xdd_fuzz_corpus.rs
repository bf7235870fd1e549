//! The XDD reader over the saved fuzz corpus (`fuzz/corpus/xdd`), every truncation at 64 evenly spaced
//! lengths and some byte flips of each file: it must always answer, never panic. The valid files must read
//! and the broken ones must be refused.

use std::path::PathBuf;

fn corpus() -> Vec<(String, Vec<u8>)> {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../fuzz/corpus/xdd"));
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&path).unwrap())
        })
        .collect();
    files.sort();
    assert!(files.len() >= 5, "the corpus has its files");
    files
}

/// Reads, and writes what was read (the writer must not panic on anything the reader accepts).
fn exercise(bytes: &[u8]) {
    if let Ok(desc) = od::xdd::read(bytes, "fuzz") {
        let text = od::xdd::write(&desc);
        let _ = od::xdd::read(text.as_bytes(), "fuzz-rewritten");
    }
}

#[test]
fn valid_files_read_and_broken_ones_are_refused() {
    for (name, bytes) in corpus() {
        let result = od::xdd::read(&bytes, &name);
        if name.starts_with("broken") || name.starts_with("not-") {
            let e = result.expect_err(&name);
            assert_eq!(e.source_name, name);
            assert!(e.position.line >= 1, "{e}");
        } else {
            let desc = result.unwrap_or_else(|e| panic!("{e}"));
            assert!(!desc.dictionary.is_empty(), "{name}");
        }
    }
}

#[test]
fn truncations_and_byte_flips_never_panic() {
    for (_, bytes) in corpus() {
        exercise(&bytes);
        let n = bytes.len();
        for i in 0..64 {
            exercise(&bytes[..n * i / 64]);
        }
        let step = (n / 97).max(1);
        for pos in (0..n).step_by(step) {
            for flip in [0x00u8, 0xFF, b'<', b'>', b'"', b'&', b'/', b'0'] {
                let mut b = bytes.clone();
                b[pos] = flip;
                exercise(&b);
            }
            let mut b = bytes.clone();
            b[pos] ^= 0x20;
            exercise(&b);
        }
    }
}
