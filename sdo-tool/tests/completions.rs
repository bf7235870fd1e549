//! `sdo-tool completions SHELL` and `sdo-tool man DIR`: a completion script for each shell clap
//! knows, and a manual page for the tool and each of its commands, nested ones too.

mod common;

/// The script of each shell names the tool and its commands; bash's completes them with the
/// function it installs.
#[test]
fn a_completion_script_for_each_shell() {
    let bash = common::sdo_tool_ok(&[], &["completions", "bash"]);
    assert!(bash.starts_with("_sdo__tool() {\n"), "{}", &bash[..40]);
    assert!(bash.contains("complete -F _sdo__tool -o nosort -o bashdefault -o default sdo-tool"));
    for command in [
        "read",
        "write",
        "dump",
        "apply",
        "watch",
        "decode",
        "drive",
        "completions",
    ] {
        assert!(bash.contains(&format!("sdo__tool,{command})")), "{command}");
    }
    assert!(common::sdo_tool_ok(&[], &["completions", "zsh"]).starts_with("#compdef sdo-tool\n"));
    let fish = common::sdo_tool_ok(&[], &["completions", "fish"]);
    assert!(
        fish.contains("complete -c sdo-tool -n \"__fish_sdo_tool_needs_command\" -f -a \"read\"")
    );
    assert!(common::sdo_tool_ok(&[], &["completions", "elvish"])
        .contains("edit:completion:arg-completer[sdo-tool]"));
    assert!(common::sdo_tool_ok(&[], &["completions", "powershell"])
        .contains("Register-ArgumentCompleter -Native -CommandName 'sdo-tool'"));
    let o = common::sdo_tool(&[], &["completions", "tcsh"]);
    assert_eq!(o.status.code(), Some(2));
}

/// `man DIR`: sdo-tool.1, a page per command and per command of `net`, `lss` and `drive`, each
/// named on standard output; a page is roff with the command's name, version and words.
#[test]
fn a_manual_page_for_the_tool_and_each_command() {
    let dir = tempfile::tempdir().unwrap();
    let out = common::sdo_tool_ok(&[], &["man", dir.path().to_str().unwrap()]);
    let pages: Vec<String> = out
        .lines()
        .map(|l| {
            std::path::Path::new(l)
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    for page in [
        "sdo-tool.1",
        "sdo-tool-read.1",
        "sdo-tool-net-gen.1",
        "sdo-tool-lss-assign.1",
        "sdo-tool-drive-move.1",
        "sdo-tool-completions.1",
        "sdo-tool-man.1",
    ] {
        assert!(pages.contains(&page.to_string()), "{page} in {pages:?}");
        assert!(dir.path().join(page).is_file(), "{page}");
    }
    assert_eq!(pages[0], "sdo-tool.1");
    assert!(!pages.iter().any(|p| p.contains("help")));
    let read = std::fs::read_to_string(dir.path().join("sdo-tool-read.1")).unwrap();
    let version = env!("CARGO_PKG_VERSION");
    assert!(read.contains(&format!(".TH sdo-tool-read 1  \"sdo-tool-read {version}\"")));
    assert!(read.contains("sdo\\-tool\\-read \\- Read an object"));
    assert!(read.contains("\\-\\-full"));
}
