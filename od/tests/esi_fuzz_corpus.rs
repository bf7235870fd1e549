//! The ESI reader over the saved fuzz corpus (`fuzz/corpus/esi/`), every file also truncated at 64 evenly
//! spaced lengths and with bytes flipped: it must always return, never panic. What reads must also write
//! and read again, as the fuzz target does.

mod support;

use support::corpus::{changes, files, prefixes};

fn corpus() -> Vec<(String, Vec<u8>)> {
    files("esi", 8)
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
    for (name, data) in corpus() {
        let broken =
            name.starts_with("broken_") || name.starts_with("empty") || name.starts_with("bom_bad");
        assert_eq!(exercise(&data), !broken, "{name}");
    }
}

#[test]
fn truncations_and_byte_flips_never_panic() {
    for (_, data) in corpus() {
        for prefix in prefixes(&data) {
            exercise(prefix);
        }
        let n = data.len();
        if n == 0 {
            continue;
        }
        changes(
            &data,
            (0..64).map(|k| (n - 1) * k / 63),
            |b| [b ^ 0x01, b ^ 0x80, b'<', b'>', b'&', b'"', b'0', b'#', 0],
            |flipped| {
                exercise(flipped);
            },
        );
    }
}
