//! The saved fuzz corpus of a format (`fuzz/corpus/<format>`) and the cut and changed copies of its files
//! that the no-panic tests feed to the readers.

/// The files of `fuzz/corpus/<format>` as (file name, contents), sorted by name; there must be at least
/// `at_least` of them.
pub fn files(format: &str, at_least: usize) -> Vec<(String, Vec<u8>)> {
    let dir = format!("{}/../fuzz/corpus/{format}", env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{dir}: {e}"))
        .map(|entry| {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&path).unwrap())
        })
        .collect();
    files.sort();
    assert!(files.len() >= at_least, "the saved corpus is there");
    files
}

/// `bytes` cut at 64 evenly spaced lengths, from nothing to all of it.
pub fn prefixes(bytes: &[u8]) -> impl Iterator<Item = &[u8]> {
    (0..64).map(move |k| &bytes[..bytes.len() * k / 63])
}

/// Calls `f` with a copy of `bytes` in which the byte at one of `positions` is replaced by one of
/// `replacements(original byte)`, for every position and replacement.
pub fn changes<R: IntoIterator<Item = u8>>(
    bytes: &[u8],
    positions: impl IntoIterator<Item = usize>,
    replacements: impl Fn(u8) -> R,
    mut f: impl FnMut(&[u8]),
) {
    let mut changed = bytes.to_vec();
    for at in positions {
        for replacement in replacements(bytes[at]) {
            changed[at] = replacement;
            f(&changed);
        }
        changed[at] = bytes[at];
    }
}
