//! The EDS reader over the saved fuzz corpus (`fuzz/corpus/eds`), every file also cut at 64 evenly
//! spaced lengths and with bytes changed: it must always answer, never panic. The valid files must read,
//! the broken ones must be refused, and what reads must survive the writers.

mod support;

use support::corpus::{changes, files, prefixes};

fn corpus() -> Vec<(String, Vec<u8>)> {
    files("eds", 10)
}

/// What the fuzz target does: read, and when that works, write both ways and read again.
fn exercise(bytes: &[u8]) -> bool {
    match od::eds::read(bytes, "fuzz") {
        Ok(desc) => {
            let eds = od::eds::write_eds(&desc);
            let again = od::eds::read(eds.as_bytes(), "fuzz-eds");
            assert!(again.is_ok(), "written EDS does not read: {again:?}\n{eds}");
            let dcf = od::eds::write_dcf(&desc);
            let _ = od::eds::read(dcf.as_bytes(), "fuzz-dcf");
            true
        }
        Err(err) => {
            assert!(err.position.line >= 1 && err.position.column >= 1, "{err}");
            false
        }
    }
}

#[test]
fn saved_files_read_or_are_refused_as_expected() {
    for (name, bytes) in corpus() {
        let valid = !["bad_", "orphan_", "not_", "comments_", "repeated"]
            .iter()
            .any(|p| name.starts_with(p));
        assert_eq!(exercise(&bytes), valid, "{name}");
    }
}

#[test]
fn truncations_and_byte_changes_never_panic() {
    const REPLACEMENTS: [u8; 9] = [b'=', b'[', b']', b'\n', b'$', b'0', b';', 0xFF, 0xB5];
    for (_, bytes) in corpus() {
        for prefix in prefixes(&bytes) {
            exercise(prefix);
        }
        let stride = (bytes.len() / 40).max(1);
        changes(
            &bytes,
            (0..bytes.len()).step_by(stride),
            |b| REPLACEMENTS.into_iter().chain([b ^ 0x20]),
            |changed| {
                exercise(changed);
            },
        );
    }
}
