//! Every command line of the README and of the book under `docs/` works when pasted from the
//! repository root. The README comes first, then the book's pages in the order of
//! `docs/src/SUMMARY.md` (a page may use what an earlier one made).
//!
//! - Each ```` ```sh ```` block runs as one bash session from the repository root, the project's
//!   binaries first on `PATH` (the README has the user put `target/release` there), against the
//!   processes the README starts: its main job (`x67-node` with no arguments, node 1, the socketcand
//!   server on 127.0.0.1:29536), and whatever a block starts itself (the EtherCAT block its veth pair
//!   and emulator). Every command must end with exit 0, or with the code its trailing `# exit N` says.
//! - Each ```` ```python ```` block runs with python3, as a user runs it with the main job up.
//! - In ```` ```text ```` blocks, a line `$ COMMAND` is a command too (its output follows it).
//! - A command named inline in the prose (`` `bash scripts/…` ``, `` `cargo bench -p P --bench B` ``)
//!   must name a script or benchmark that exists; the two set-up commands (the indented ones, which
//!   run the main job and the whole suite) are not run here, but their scripts must exist.
//!
//! Needs root for the EtherCAT block (a network namespace and a veth pair), as the suite does.

use std::path::{Path, PathBuf};
use std::process::{Child, Command};

fn root() -> &'static Path {
    testkit::root()
}

/// One command of a block: its first line in the README and its text (several lines for a heredoc
/// or a continued line), and the exit code it must end with.
#[derive(Debug)]
struct Cmd {
    line: usize,
    text: String,
    exit: i32,
}

/// A fenced block: its kind and the line of its opening fence.
#[derive(Debug)]
struct Block {
    kind: String,
    line: usize,
    body: Vec<(usize, String)>,
}

/// A document: its path from the repository root and its text.
struct Doc {
    name: String,
    text: String,
}

/// The pages `docs/src/SUMMARY.md` links to, in its order.
fn book_pages() -> Vec<String> {
    let summary = std::fs::read_to_string(root().join("docs/src/SUMMARY.md")).unwrap();
    summary
        .lines()
        .filter_map(|l| {
            let at = l.find("](")?;
            let rest = &l[at + 2..];
            Some(rest[..rest.find(')')?].to_string())
        })
        .collect()
}

/// The README, then the book's pages.
fn documents() -> Vec<Doc> {
    let mut docs = vec![Doc {
        name: "README.md".into(),
        text: std::fs::read_to_string(root().join("README.md")).unwrap(),
    }];
    for page in book_pages() {
        let name = format!("docs/src/{page}");
        let text = std::fs::read_to_string(root().join(&name))
            .unwrap_or_else(|e| panic!("{name}, in docs/src/SUMMARY.md: {e}"));
        docs.push(Doc { name, text });
    }
    docs
}

fn blocks(doc: &Doc) -> Vec<Block> {
    let readme = &doc.text;
    let mut out = Vec::new();
    let mut open: Option<Block> = None;
    for (k, l) in readme.lines().enumerate() {
        let n = k + 1;
        if let Some(fence) = l.strip_prefix("```") {
            match open.take() {
                Some(b) => out.push(b),
                None => {
                    open = Some(Block {
                        kind: fence.trim().to_string(),
                        line: n,
                        body: Vec::new(),
                    })
                }
            }
            continue;
        }
        if let Some(b) = open.as_mut() {
            b.body.push((n, l.to_string()));
        }
    }
    assert!(open.is_none(), "{}: a fence is not closed", doc.name);
    out
}

/// The commands of an `sh` block: comments and blank lines dropped, heredocs and `\` continuations
/// joined to their command.
fn commands(block: &Block) -> Vec<Cmd> {
    let mut out = Vec::new();
    let mut lines = block.body.iter().peekable();
    while let Some((n, l)) = lines.next() {
        let t = l.trim();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        let mut text = l.clone();
        let mut last = l.clone();
        while last.trim_end().ends_with('\\') {
            let Some((_, next)) = lines.next() else { break };
            text.push('\n');
            text.push_str(next);
            last = next.clone();
        }
        if let Some(at) = l.find("<<'") {
            let tag: String = l[at + 3..].chars().take_while(|c| *c != '\'').collect();
            for (_, next) in lines.by_ref() {
                text.push('\n');
                text.push_str(next);
                if next.trim() == tag {
                    break;
                }
            }
        }
        let exit = l
            .rsplit_once("# exit ")
            .and_then(|(_, c)| {
                let digits: String = c.chars().take_while(char::is_ascii_digit).collect();
                digits.parse().ok()
            })
            .unwrap_or(0);
        out.push(Cmd {
            line: *n,
            text,
            exit,
        });
    }
    out
}

/// A directory of links named as the binaries, to put first on `PATH`.
fn binaries() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("readme-bin-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for (package, bin, features) in [
        ("socketcan-node", "x67-node", &[][..]),
        ("socketcan-node", "canopen-node", &[]),
        ("sdo-tool", "sdo-tool", &[]),
        ("esi-gen", "esi-gen", &[]),
        ("ethercat-slave", "smd-ethercat", &[]),
        ("ethercat-slave", "ethercat-node", &[]),
        ("ds402", "smd", &["cli"]),
    ] {
        let path = testkit::cargo_binary(package, bin, features);
        std::os::unix::fs::symlink(&path, dir.join(bin)).unwrap();
    }
    dir
}

/// The main job as the README starts it (`bash scripts/main`: `x67-node` without arguments), once
/// it says it listens; killed when dropped.
struct MainJob(Child);

impl MainJob {
    fn start(bin: &Path) -> MainJob {
        let (child, line) = testkit::start_until_first_line(
            Command::new(bin.join("x67-node"))
                .current_dir(root())
                .env_remove("CANOPEN_BUS"),
        );
        assert!(
            line.starts_with("x67-node: node 1 ") && line.contains("127.0.0.1:29536"),
            "the main job: {line}"
        );
        MainJob(child)
    }
}

impl Drop for MainJob {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Runs `script` with `program` from the repository root, `bin` first on PATH; its output.
fn run(program: &str, script: &str, bin: &Path) -> std::process::Output {
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    Command::new(program)
        .arg("-c")
        .arg(script)
        .current_dir(root())
        .env("PATH", path)
        .env_remove("CANOPEN_BUS")
        .output()
        .unwrap()
}

/// The bash script of one block of `name`: each command, then a check of its exit code that names
/// its line.
fn script(name: &str, cmds: &[Cmd]) -> String {
    let mut s = String::new();
    for c in cmds {
        s.push_str(&c.text);
        s.push('\n');
        if c.text.trim_end().ends_with('&') {
            continue;
        }
        s.push_str(&format!(
            "rc=$?; if [ $rc -ne {} ]; then echo \"{name}:{}: exit $rc, not {}\" >&2; \
             kill $(jobs -p) 2>/dev/null; exit 1; fi\n",
            c.exit, c.line, c.exit
        ));
    }
    s.push_str("kill $(jobs -p) 2>/dev/null; wait 2>/dev/null; exit 0\n");
    s
}

#[test]
fn every_command_line_of_the_readme_and_the_book_works_when_pasted() {
    let docs = documents();
    let bin = binaries();
    // What an interrupted earlier run of a block may have left: every namespace and link the
    // blocks add, by the names they give.
    for line in docs.iter().flat_map(|d| d.text.lines()) {
        let words: Vec<&str> = line.split_whitespace().collect();
        if let ["ip", kind @ ("netns" | "link"), "add", name, ..] = words[..] {
            let _ = Command::new("ip").args([kind, "del", name]).output();
        }
    }
    let _main = MainJob::start(&bin);
    let mut ran = 0;
    let mut failures = Vec::new();
    for doc in &docs {
        for b in blocks(doc) {
            let (program, text, count) = match b.kind.as_str() {
                "sh" => {
                    let cmds = commands(&b);
                    (String::from("bash"), script(&doc.name, &cmds), cmds.len())
                }
                "python" => {
                    let body: Vec<&str> = b.body.iter().map(|(_, l)| l.as_str()).collect();
                    (String::from("python3"), body.join("\n"), 1)
                }
                "text" => {
                    let cmds: Vec<Cmd> = b
                        .body
                        .iter()
                        .filter_map(|(n, l)| {
                            l.strip_prefix("$ ").map(|c| Cmd {
                                line: *n,
                                text: c.to_string(),
                                exit: 0,
                            })
                        })
                        .collect();
                    if cmds.is_empty() {
                        continue;
                    }
                    let n = cmds.len();
                    (String::from("bash"), script(&doc.name, &cmds), n)
                }
                "" => panic!(
                    "{}:{}: a block without a kind: sh (commands), python or text",
                    doc.name, b.line
                ),
                _ => continue,
            };
            let out = run(&program, &text, &bin);
            ran += count;
            if !out.status.success() {
                failures.push(format!(
                    "{}:{} ({}): {}\n{}{}",
                    doc.name,
                    b.line,
                    b.kind,
                    out.status,
                    String::from_utf8_lossy(&out.stdout),
                    String::from_utf8_lossy(&out.stderr)
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n---\n"));
    assert!(
        ran >= 30,
        "only {ran} commands found in the README and the book"
    );
    println!("{ran} commands of the README and the book ran");
}

/// The scripts and benchmarks the prose and the indented set-up commands name exist.
#[test]
fn every_script_and_benchmark_the_readme_and_the_book_name_exists() {
    let mut checked = 0;
    for doc in documents() {
        checked += scripts_and_benchmarks(&doc);
    }
    assert!(checked >= 5, "only {checked} scripts and benchmarks named");
}

/// Checks the scripts and benchmarks `doc` names; how many.
fn scripts_and_benchmarks(doc: &Doc) -> usize {
    let name = &doc.name;
    let mut checked = 0;
    for (k, line) in doc.text.lines().enumerate() {
        let mut rest = line;
        while let Some(at) = rest.find("bash ") {
            let path: String = rest[at + 5..]
                .chars()
                .take_while(|c| !c.is_whitespace() && *c != '`')
                .collect();
            if path.starts_with("scripts/") || path.starts_with("tests/") {
                assert!(
                    root().join(&path).is_file(),
                    "{name}:{}: {path} does not exist",
                    k + 1
                );
                checked += 1;
            }
            rest = &rest[at + 5..];
        }
        let mut rest = line;
        while let Some(at) = rest.find("cargo bench -p ") {
            let words: Vec<&str> = rest[at..]
                .split(|c: char| c.is_whitespace() || c == '`')
                .filter(|w| !w.is_empty())
                .collect();
            let (package, bench) = (words[3], words[5]);
            assert_eq!(words[4], "--bench", "{name}:{}", k + 1);
            let dir = match package {
                "od" | "ds402" | "sdo-tool" | "esi-gen" | "socketcan-node" | "ethercat-slave" => {
                    package
                }
                other => panic!("{name}:{}: no package {other}", k + 1),
            };
            assert!(
                root()
                    .join(dir)
                    .join("benches")
                    .join(format!("{bench}.rs"))
                    .is_file(),
                "{name}:{}: no benchmark {bench} in {package}",
                k + 1
            );
            checked += 1;
            rest = &rest[at + 15..];
        }
    }
    checked
}

/// The book is whole: `docs/book.toml` names `src`, `SUMMARY.md` lists every page of `docs/src` once
/// and only pages that exist, and every relative link of the README and the book leads to a file
/// that exists.
#[test]
fn the_book_lists_every_page_and_every_link_leads_somewhere() {
    let book = std::fs::read_to_string(root().join("docs/book.toml")).unwrap();
    assert!(book.contains("[book]"), "docs/book.toml: {book}");
    let listed = book_pages();
    let mut on_disk: Vec<String> = std::fs::read_dir(root().join("docs/src"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md") && n != "SUMMARY.md")
        .collect();
    on_disk.sort();
    let mut sorted = listed.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(
        sorted.len(),
        listed.len(),
        "a page listed twice: {listed:?}"
    );
    assert_eq!(
        sorted, on_disk,
        "docs/src/SUMMARY.md and the pages of docs/src"
    );
    for doc in documents() {
        let dir = root().join(&doc.name);
        let dir = dir.parent().unwrap();
        for (k, line) in doc.text.lines().enumerate() {
            let mut rest = line;
            while let Some(at) = rest.find("](") {
                rest = &rest[at + 2..];
                let Some(end) = rest.find(')') else { break };
                let target = rest[..end].split('#').next().unwrap();
                if !target.is_empty() && !target.contains("://") {
                    assert!(
                        dir.join(target).exists(),
                        "{}:{}: {target} does not exist",
                        doc.name,
                        k + 1
                    );
                }
            }
        }
    }
}
