//! The ESI reader over the saved fuzz corpus (`fuzz/corpus/esi/`), every file also truncated at 64 evenly
//! spaced lengths and with bytes flipped: it must always return, never panic. What reads must also write
//! and read again, as the fuzz target does.

use std::path::PathBuf;

fn corpus_files() -> Vec<PathBuf> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../fuzz/corpus/esi");
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{dir}: {e}"))
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(files.len() >= 8, "the saved corpus is there");
    files
}

/// What the fuzz target does.
fn exercise(data: &[u8]) -> bool {
    match od::esi::read_all(data, "fuzz") {
        Ok(devices) => {
            let text = od::esi::write_all(&devices);
            let again = od::esi::read_all(text.as_bytes(), "fuzz-written");
            assert!(again.is_ok(), "written output must read: {again:?}");
            true
        }
        Err(e) => {
            assert_eq!(e.source_name, "fuzz");
            assert!(e.position.line >= 1);
            false
        }
    }
}

#[test]
fn corpus_files_read_or_fail_as_named() {
    for path in corpus_files() {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let data = std::fs::read(&path).unwrap();
        let broken =
            name.starts_with("broken_") || name.starts_with("empty") || name.starts_with("bom_bad");
        assert_eq!(exercise(&data), !broken, "{name}");
    }
}

#[test]
fn truncations_and_byte_flips_never_panic() {
    for path in corpus_files() {
        let data = std::fs::read(&path).unwrap();
        let n = data.len();
        for k in 0..64 {
            let len = n * k / 63;
            exercise(&data[..len.min(n)]);
        }
        if n == 0 {
            continue;
        }
        for k in 0..64 {
            let at = (n - 1) * k / 63;
            for replace in [
                data[at] ^ 0x01,
                data[at] ^ 0x80,
                b'<',
                b'>',
                b'&',
                b'"',
                b'0',
                b'#',
                0,
            ] {
                let mut flipped = data.clone();
                flipped[at] = replace;
                exercise(&flipped);
            }
        }
    }
}
