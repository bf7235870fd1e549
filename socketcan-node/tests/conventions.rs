//! What `canopen-node` and `x67-node` share with every command line of the workspace
//! (`cli-support`): the log on standard error plain text when it goes to a pipe or a file, coloured
//! (ANSI escape codes) on a terminal, plain there too with `NO_COLOR` set (no-color.org), the
//! terminal being util-linux `script`'s pseudo-terminal; and `--completions SHELL`, `--man DIR`.

use std::process::Command;
use std::time::Duration;
use testkit::free_port;

/// `bin` as a socketcand server on a free port with `args` for a second (coreutils `timeout` ends
/// it), its standard output and error read from a pipe or a terminal; `NO_COLOR` as given.
fn run(bin: &str, args: &[&str], terminal: bool, no_color: Option<&str>) -> String {
    let command = format!(
        "timeout 1 {bin} --bus socketcand-listen:127.0.0.1:{} {}",
        free_port(),
        args.join(" ")
    );
    let mut c = if terminal {
        let mut c = Command::new("script");
        c.args(["-qec", &command, "/dev/null"]);
        c
    } else {
        let mut c = Command::new("sh");
        c.args(["-c", &command]);
        c
    };
    c.env_remove("NO_COLOR").env_remove("RUST_LOG");
    if let Some(v) = no_color {
        c.env("NO_COLOR", v);
    }
    let done = testkit::run_for_at_most(&mut c, Duration::from_secs(20));
    assert!(done.status.is_some(), "{command} did not end");
    format!("{}{}", done.stdout, done.stderr)
}

#[test]
fn the_log_is_coloured_on_a_terminal_only() {
    let drive = testkit::root().join("examples/drive.eds");
    let drive = format!("--od {}@5", drive.display());
    for (bin, args) in [
        (env!("CARGO_BIN_EXE_canopen-node"), drive.as_str()),
        (env!("CARGO_BIN_EXE_x67-node"), ""),
    ] {
        let piped = run(bin, &[args], false, None);
        assert!(piped.contains(" INFO "), "{bin}: {piped}");
        assert!(!piped.contains('\x1b'), "{bin} piped: {piped}");
        let terminal = run(bin, &[args], true, None);
        assert!(
            terminal.contains("\x1b[32m INFO\x1b[0m"),
            "{bin}: {terminal}"
        );
        let plain = run(bin, &[args], true, Some("1"));
        assert!(plain.contains(" INFO "), "{bin}: {plain}");
        assert!(!plain.contains('\x1b'), "{bin} with NO_COLOR=1: {plain}");
        // An empty NO_COLOR does not count.
        let empty = run(bin, &[args], true, Some(""));
        assert!(empty.contains('\x1b'), "{bin} with NO_COLOR empty: {empty}");
    }
}

/// `--completions SHELL` and `--man DIR` of `canopen-node` and `x67-node` (canopen-node's `--od`
/// is not needed for them, `CANOPEN_BUS` is no obstacle); not both at once.
#[test]
fn completions_and_manual_pages_of_the_nodes() {
    let dir = tempfile::tempdir().unwrap();
    for (bin, name) in [
        (env!("CARGO_BIN_EXE_canopen-node"), "canopen-node"),
        (env!("CARGO_BIN_EXE_x67-node"), "x67-node"),
    ] {
        let out = Command::new(bin)
            .args(["--completions", "bash"])
            .output()
            .unwrap();
        assert!(out.status.success());
        let script = String::from_utf8_lossy(&out.stdout);
        let function = name.replace('-', "__");
        assert!(
            script.contains(&format!(
                "complete -F _{function} -o nosort -o bashdefault -o default {name}"
            )),
            "{script}"
        );
        assert!(script.contains("--bus"));
        let out = Command::new(bin)
            .arg("--man")
            .arg(dir.path())
            .output()
            .unwrap();
        assert!(out.status.success());
        let page = dir.path().join(format!("{name}.1"));
        assert_eq!(
            String::from_utf8_lossy(&out.stdout),
            format!("{}\n", page.display())
        );
        let text = std::fs::read_to_string(&page).unwrap();
        assert!(text.contains(&format!(".TH {name} 1")), "{text}");
        // The bus from the environment, as a user's shell may have it, is no obstacle; both at
        // once are refused.
        let out = Command::new(bin)
            .args(["--completions", "bash"])
            .env("CANOPEN_BUS", "vcan0")
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let out = Command::new(bin)
            .args(["--completions", "bash", "--man", "/tmp"])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2));
    }
}
