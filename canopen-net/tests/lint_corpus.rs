//! The strict reading against dcfgen's on every EDS and DCF of the corpus: a file dcfgen refuses as
//! an invalid DCF is refused, a file it takes is taken, and each of our warnings is one of dcfgen's.

use std::path::Path;
use std::process::{Command, Stdio};

#[test]
fn the_corpus_passes_and_fails_as_with_dcfgen() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpus/eds");
    let Ok(entries) = std::fs::read_dir(&corpus) else {
        panic!("the corpus is beside the repository: {}", corpus.display());
    };
    let mut files: Vec<_> = entries.map(|e| e.unwrap().path()).collect();
    files.sort();
    let dir = tempfile::tempdir().unwrap();
    // Every dcfgen at once, each with its own description: the machine's cores share them.
    let runs: Vec<_> = files
        .iter()
        .enumerate()
        .map(|(n, file)| {
            let out = dir.path().join(n.to_string());
            std::fs::create_dir(&out).unwrap();
            let yml = out.join("bus.yml");
            let text = format!(
                "master: {{node_id: 1}}\ns:\n  dcf: {}\n  node_id: 5\n",
                file.display()
            );
            std::fs::write(&yml, text).unwrap();
            Command::new("dcfgen")
                .args(["-d", out.to_str().unwrap(), yml.to_str().unwrap()])
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .expect("dcfgen runs (scripts/setup-test-deps installs it)")
        })
        .collect();
    let mut compared = 0;
    for (file, run) in files.iter().zip(runs) {
        let out = run.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        let refused = stderr.contains("ValueError: invalid DCF");
        if !out.status.success() && !refused && !stderr.contains("UserWarning") {
            continue; // dcfgen cannot read the file at all (its encoding, a key it fails on).
        }
        let lint = canopen_net::lint::lint(&std::fs::read(file).unwrap());
        let name = file.file_name().unwrap().to_string_lossy();
        if out.status.success() || refused {
            assert_eq!(lint.ok, !refused, "{name}: {:?}", lint.warnings);
            compared += 1;
        }
        for w in &lint.warnings {
            assert!(
                stderr.contains(&format!("UserWarning: {w}\n")),
                "{name}: {w} is not dcfgen's"
            );
        }
    }
    eprintln!("{compared} corpus files passed or failed as with dcfgen");
    assert!(compared > 30, "{compared} files compared");
}
