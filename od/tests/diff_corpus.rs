//! The diff on the real-world files of `shared/corpus` (see its SOURCES.md): each file compared with
//! itself is equal, and compared with its rewrite in its own format the diff is empty exactly when the
//! model read back is the same (compared through `Debug`, since some files hold NaN defaults). What the
//! rewrites lose is printed (`cargo test -p od --test diff_corpus -- --nocapture`): those are losses of
//! the readers and writers, not of the diff.
//!
//! The files of more than 900 KB take minutes to read in a debug build; they are compared by the
//! ignored test (`-- --ignored`).

use od::diff::{diff_devices, pair_devices, Change, Difference, Pairing};
use od::load::{read_bytes, Format};
use od::DeviceDescription;

/// Files larger than this are left to the ignored test.
const LARGE: usize = 900 << 10;

fn files(large: bool) -> Vec<(String, Vec<u8>)> {
    let root = format!("{}/../../shared/corpus", env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    for dir in ["esi", "eds", "xdd"] {
        let dir = format!("{root}/{dir}");
        let entries = std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{dir}: {e}"));
        for entry in entries {
            let path = entry.unwrap().path();
            let name = path.strip_prefix(&root).unwrap().display().to_string();
            out.push((name, std::fs::read(&path).unwrap()));
        }
    }
    out.sort();
    assert!(out.len() >= 80, "the corpus is there");
    out.retain(|(_, bytes)| (bytes.len() > LARGE) == large);
    out
}

fn rewrite(format: Format, devices: &[DeviceDescription]) -> String {
    match format {
        Format::Esi => od::esi::write_all(devices),
        Format::Xdd => od::xdd::write(&devices[0]),
        Format::Eds => od::eds::write_eds(&devices[0]),
        Format::Dcf => od::eds::write_dcf(&devices[0]),
    }
}

#[test]
fn every_file_equals_itself_and_its_rewrite_differs_only_where_the_model_does() {
    compare(files(false));
}

#[test]
fn every_large_file_equals_itself_and_its_rewrite_differs_only_where_the_model_does() {
    compare(files(true));
}

/// Checks each file against itself and against its rewrite; prints what the rewrites lose.
fn compare(files: Vec<(String, Vec<u8>)>) {
    let mut lossy = Vec::new();
    for (name, bytes) in files {
        let path = std::path::Path::new(&name);
        let Some(format) = Format::detect(path, &bytes) else {
            continue;
        };
        let Ok(devices) = read_bytes(&bytes, &name, format) else {
            continue;
        };
        // Equal to itself, each device with itself.
        let pairs = pair_devices(&devices, &devices);
        let itself: Vec<Pairing> = (0..devices.len()).map(|i| Pairing::Both(i, i)).collect();
        assert_eq!(pairs, itself, "{name}");
        for d in &devices {
            assert_eq!(diff_devices(d, d), vec![], "{name}");
        }
        // Against its rewrite.
        let text = rewrite(format, &devices);
        let back = read_bytes(text.as_bytes(), "rewritten", format)
            .unwrap_or_else(|e| panic!("{name}: the rewrite does not read: {e}"));
        assert_eq!(back.len(), devices.len(), "{name}");
        for (a, b) in devices.iter().zip(&back) {
            let found = diff_devices(a, b);
            assert_eq!(
                found.is_empty(),
                format!("{a:?}") == format!("{b:?}"),
                "{name}: the diff and the model disagree: {found:?}"
            );
            for x in &found {
                lossy.push(format!("{name} {}: {x}", a.identity.order_code));
            }
        }
    }
    for line in &lossy {
        println!("{line}");
    }
}

/// The difference `d` seen from the other side: what only `a` has only `b` has, and the other way.
fn mirrored(d: &Difference) -> Difference {
    let change = match &d.change {
        Change::OnlyInA(name) => Change::OnlyInB(name.clone()),
        Change::OnlyInB(name) => Change::OnlyInA(name.clone()),
        Change::Changed { field, a, b } => Change::Changed {
            field,
            a: b.clone(),
            b: a.clone(),
        },
    };
    Difference {
        path: d.path.clone(),
        change,
    }
}

fn sorted(mut lines: Vec<String>) -> Vec<String> {
    lines.sort();
    lines
}

/// Every description of the saved fuzz corpus and of the shared EDS corpus against every other: no
/// panic, the diff is empty exactly when the model is the same, and `b` against `a` finds the mirror of
/// what `a` against `b` finds.
#[test]
fn every_pair_of_fuzz_corpus_descriptions_compares_both_ways_alike() {
    let mut devices = Vec::new();
    let root = env!("CARGO_MANIFEST_DIR");
    for dir in [
        "../fuzz/corpus/esi",
        "../fuzz/corpus/eds",
        "../fuzz/corpus/xdd",
        "../../shared/corpus/eds",
    ] {
        let dir = format!("{root}/{dir}");
        for entry in std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{dir}: {e}")) {
            let path = entry.unwrap().path();
            let bytes = std::fs::read(&path).unwrap();
            let Some(format) = Format::detect(&path, &bytes) else {
                continue;
            };
            if let Ok(read) = read_bytes(&bytes, "fuzz", format) {
                devices.extend(read);
            }
        }
    }
    assert!(devices.len() >= 40, "{}", devices.len());
    for a in &devices {
        for b in &devices {
            let ab = diff_devices(a, b);
            assert_eq!(ab.is_empty(), format!("{a:?}") == format!("{b:?}"));
            let ba: Vec<String> = diff_devices(b, a).iter().map(|d| d.to_string()).collect();
            let back: Vec<String> = ab.iter().map(|d| mirrored(d).to_string()).collect();
            assert_eq!(sorted(ba), sorted(back));
        }
    }
    // The devices of all files as two files of several devices, one the other reversed.
    let mut reversed = devices.clone();
    reversed.reverse();
    for p in pair_devices(&devices, &reversed) {
        if let Pairing::Both(i, j) = p {
            let _ = diff_devices(&devices[i], &reversed[j]);
        }
    }
}
