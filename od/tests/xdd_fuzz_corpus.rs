//! The XDD reader over the saved fuzz corpus (`fuzz/corpus/xdd`), every truncation at 64 evenly spaced
//! lengths and some byte flips of each file: it must always answer, never panic. The valid files must read
//! and the broken ones must be refused.

mod support;

use support::corpus::{changes, files, prefixes};

fn corpus() -> Vec<(String, Vec<u8>)> {
    files("xdd", 5)
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
        for prefix in prefixes(&bytes) {
            exercise(prefix);
        }
        let n = bytes.len();
        let step = (n / 97).max(1);
        changes(
            &bytes,
            (0..n).step_by(step),
            |b| [0x00u8, 0xFF, b'<', b'>', b'"', b'&', b'/', b'0', b ^ 0x20],
            exercise,
        );
    }
}
