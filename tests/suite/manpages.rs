//! Man pages, shell completions and the version string, as the package installs them.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::process::Command;

use crate::common::{run_cli, run_cli_timed};

/// Whether `program` runs here (`program --version` starts); the shell and `man` checks skip
/// with a note where it does not.
fn have(program: &str) -> bool {
    Command::new(program)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// The `(commit …)` part of a version: 12 or more hex digits, `-dirty` after them when the tree
/// was dirty, or `unknown`.
fn commit_of(version: &str) -> &str {
    let rest = version
        .strip_prefix(concat!(env!("CARGO_PKG_VERSION"), " (commit "))
        .unwrap_or_else(|| {
            panic!(
                "{version:?}: not `{} (commit …)`",
                env!("CARGO_PKG_VERSION")
            )
        });
    let commit = rest
        .strip_suffix(')')
        .unwrap_or_else(|| panic!("{version:?}: no closing parenthesis"));
    let hash = commit.strip_suffix("-dirty").unwrap_or(commit);
    assert!(
        commit == "unknown"
            || (hash.len() >= 12 && hash.chars().all(|c| matches!(c, '0'..='9' | 'a'..='f'))),
        "{version:?}: the commit is neither a 12-digit hash (with -dirty) nor `unknown`"
    );
    commit
}

#[test]
fn the_version_names_the_commit_and_is_the_tool_version_outputs_carry() {
    let (ok, stdout, stderr) = run_cli(&["--version"]);
    assert!(ok, "{stderr}");
    let line = stdout.trim_end();
    assert_eq!(line.lines().count(), 1, "{stdout:?}");
    let version = line
        .strip_prefix("udc-studio ")
        .unwrap_or_else(|| panic!("{line:?} does not start with the program's name"));
    assert_eq!(version, udc_studio::cli::TOOL_VERSION);
    let commit = commit_of(version);

    // In a git checkout the hash is a commit of this repository (HEAD when the binary was
    // built), not `unknown`.
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    if repo.join(".git").exists() && have("git") {
        assert_ne!(
            commit, "unknown",
            "built in a git checkout with git installed"
        );
        let hash = commit.strip_suffix("-dirty").unwrap_or(commit);
        let exists = Command::new("git")
            .arg("-C")
            .arg(repo)
            .args(["cat-file", "-e", &format!("{hash}^{{commit}}")])
            .status()
            .expect("run git");
        assert!(
            exists.success(),
            "{hash} is not a commit of {}",
            repo.display()
        );
    } else {
        println!("note: no git checkout or no git: only the form of the commit was checked");
    }

    // A printed JSON object carries it too.
    let (ok, stdout, stderr) = run_cli(&["presets", "--json"]);
    assert!(ok, "{stderr}");
    let printed: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(printed["tool_version"], version);

    // A sweep's rows and manifest carry the same string.
    let dir = tempfile::tempdir().unwrap();
    let spec = dir.path().join("one.toml");
    std::fs::write(
        &spec,
        "job = \"analyze\"\nmetrics = [\"ltr\"]\n[base]\npreset = \"open-aperture\"\n\
         preview = true\n[[axis]]\nparam = \"seed\"\nrange = { start = 0, stop = 0 }\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let (ok, _, stderr) = run_cli(&[
        "sweep",
        spec.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
        "--no-plots",
    ]);
    assert!(ok, "{stderr}");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("sweep.json")).unwrap()).unwrap();
    assert_eq!(manifest["tool_version"], version);
    let mut rows = csv::Reader::from_path(out.join("results.csv")).unwrap();
    let column = rows
        .headers()
        .unwrap()
        .iter()
        .position(|h| h == "tool_version")
        .expect("a tool_version column");
    let rows: Vec<csv::StringRecord> = rows.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 1);
    assert_eq!(&rows[0][column], version);
}

/// `udc-studio completions SHELL` into a file.
fn completion_script(shell: &str, dir: &Path) -> (String, std::path::PathBuf) {
    let (ok, script, stderr) = run_cli(&["completions", shell]);
    assert!(ok, "completions {shell}: {stderr}");
    let path = dir.join(format!("udc-studio.{shell}"));
    std::fs::write(&path, &script).unwrap();
    (script, path)
}

#[test]
fn the_bash_script_registers_and_completes_subcommands_and_their_flags() {
    let dir = tempfile::tempdir().unwrap();
    let (script, path) = completion_script("bash", dir.path());
    assert!(script.contains("analyze"), "{script}");
    if !have("bash") {
        println!("note: bash is not installed: the bash script was not sourced");
        return;
    }
    let registered = Command::new("bash")
        .arg("-c")
        .arg("source \"$1\" && complete -p udc-studio")
        .arg("bash")
        .arg(&path)
        .output()
        .expect("run bash");
    let stdout = String::from_utf8_lossy(&registered.stdout);
    assert!(
        registered.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&registered.stderr)
    );
    assert!(
        stdout.starts_with("complete ") && stdout.trim_end().ends_with(" udc-studio"),
        "{stdout}"
    );
    // What Tab offers: the registered function called as bash calls it, one line per case.
    let cases = r#"
source "$1" || exit 3
f=$(complete -p udc-studio | sed -n 's/.* -F \([^ ]*\) .*/\1/p')
comp() {
    COMP_WORDS=("$@"); COMP_CWORD=$(( $# - 1 )); COMP_LINE="$*"; COMP_POINT=${#COMP_LINE}
    COMPREPLY=()
    "$f" udc-studio "${COMP_WORDS[COMP_CWORD]}" "${COMP_WORDS[COMP_CWORD-1]}"
    echo "${COMPREPLY[*]}"
}
comp udc-studio ph
comp udc-studio phase ''
comp udc-studio analyze --pre
comp udc-studio completions ''
comp udc-studio sweep m
"#;
    let out = Command::new("bash")
        .arg("-c")
        .arg(cases)
        .arg("bash")
        .arg(&path)
        .output()
        .expect("run bash");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<Vec<&str>> = stdout
        .lines()
        .map(|l| l.split_whitespace().collect())
        .collect();
    assert_eq!(lines.len(), 5, "{stdout}");
    assert_eq!(lines[0], ["phase"], "udc-studio ph<Tab>");
    for sub in ["psf", "invertibility", "optimize", "export", "restore"] {
        assert!(
            lines[1].contains(&sub),
            "udc-studio phase <Tab>: {:?}",
            lines[1]
        );
    }
    let mut flags = lines[2].clone();
    flags.sort_unstable();
    assert_eq!(
        flags,
        ["--preset", "--preview"],
        "udc-studio analyze --pre<Tab>"
    );
    for shell in ["bash", "zsh", "fish"] {
        assert!(
            lines[3].contains(&shell),
            "completions <Tab>: {:?}",
            lines[3]
        );
    }
    assert_eq!(lines[4], ["merge"], "udc-studio sweep m<Tab>");
}

#[test]
fn the_zsh_and_fish_scripts_name_the_commands() {
    let dir = tempfile::tempdir().unwrap();
    for (shell, checker, first) in [
        ("zsh", ["zsh", "-n"], "#compdef udc-studio"),
        ("fish", ["fish", "--no-execute"], ""),
    ] {
        let (script, path) = completion_script(shell, dir.path());
        assert!(
            script.starts_with(first),
            "{shell}: {:?}",
            script.lines().next()
        );
        assert!(script.lines().count() > 50, "{shell}: {script}");
        for name in [
            "udc-studio",
            "analyze",
            "phase",
            "sweep",
            "psf",
            "merge",
            "preset",
        ] {
            assert!(
                script.contains(name),
                "the {shell} script does not name {name}"
            );
        }
        if have(checker[0]) {
            let out = Command::new(checker[0])
                .arg(checker[1])
                .arg(&path)
                .output()
                .expect("run the shell");
            assert!(
                out.status.success(),
                "{shell} -n: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        } else {
            println!("note: {shell} is not installed: its script was not parsed");
        }
    }
}

#[test]
fn a_bad_shell_is_a_one_line_usage_error() {
    for (args, names) in [
        (vec!["completions", "powershell"], "bash, zsh, fish"),
        (vec!["completions", "Bash "], "bash, zsh, fish"),
        (vec!["completions"], "<SHELL>"),
    ] {
        let (code, stdout, stderr, _) = run_cli_timed(&args);
        assert_eq!(code, Some(2), "{args:?}: {stderr}");
        assert!(stdout.is_empty(), "{args:?}: {stdout}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.starts_with("error: "), "{args:?}: {stderr}");
        assert!(stderr.contains(names), "{args:?}: {stderr}");
    }
}

/// The pages the command tree calls for, each with its command line: `udc-studio`, then
/// `udc-studio-SUB` (`udc-studio SUB`) and `udc-studio-SUB-SUBSUB` for every subcommand that
/// is not hidden, `help` excepted.
fn expected_pages() -> std::collections::BTreeMap<String, String> {
    use clap::CommandFactory;
    fn walk(
        cmd: &clap::Command,
        page: &str,
        line: &str,
        out: &mut std::collections::BTreeMap<String, String>,
    ) {
        out.insert(page.to_string(), line.to_string());
        for sub in cmd.get_subcommands() {
            if !sub.is_hide_set() && sub.get_name() != "help" {
                let name = sub.get_name();
                walk(
                    sub,
                    &format!("{page}-{name}"),
                    &format!("{line} {name}"),
                    out,
                );
            }
        }
    }
    let mut out = std::collections::BTreeMap::new();
    walk(
        &udc_studio::cli::Cli::command(),
        "udc-studio",
        "udc-studio",
        &mut out,
    );
    out
}

#[test]
fn manpages_writes_a_page_per_visible_command() {
    // The packaging command stays out of --help; completions is in it.
    let (ok, help, stderr) = run_cli(&["--help"]);
    assert!(ok, "{stderr}");
    assert!(!help.contains("manpages"), "{help}");
    assert!(help.contains("completions"), "{help}");

    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("share/man/man1");
    let (ok, stdout, stderr) = run_cli(&["manpages", "--out", out.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let expected = expected_pages();
    assert!(expected.len() > 20, "{expected:?}");
    for page in [
        "udc-studio-phase-psf",
        "udc-studio-sweep-merge",
        "udc-studio-sensor-flat-patch",
        "udc-studio-completions",
    ] {
        assert!(expected.contains_key(page), "{expected:?}");
    }
    assert!(
        !expected
            .keys()
            .any(|p| p.contains("manpages") || p.ends_with("-help"))
    );
    assert!(
        stdout.contains(&format!("wrote {} man pages", expected.len())),
        "{stdout}"
    );
    let written: std::collections::BTreeSet<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let wanted: std::collections::BTreeSet<String> =
        expected.keys().map(|p| format!("{p}.1")).collect();
    assert_eq!(written, wanted);

    for (name, command_line) in &expected {
        let text = std::fs::read_to_string(out.join(format!("{name}.1"))).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        // The page opens with its title (after clap_mangen's apostrophe string definitions).
        let th = lines
            .iter()
            .find(|l| !l.starts_with(".ie ") && !l.starts_with(".el "))
            .expect("a first line");
        let words: Vec<&str> = th.split_whitespace().collect();
        assert_eq!(
            words[..3],
            [".TH", &name.to_uppercase(), "1"],
            "{name}: {th}"
        );
        assert!(
            th.contains(udc_studio::cli::TOOL_VERSION),
            "{name}: the title does not name the build: {th}"
        );
        let at = lines
            .iter()
            .position(|l| *l == ".SH NAME")
            .unwrap_or_else(|| panic!("{name}: no NAME section"));
        let entry = lines[at + 1].replace("\\-", "-");
        assert!(
            entry.starts_with(&format!("{name} - ")),
            "{name}: NAME is {entry:?}"
        );
        let synopsis = lines
            .iter()
            .position(|l| *l == ".SH SYNOPSIS")
            .unwrap_or_else(|| panic!("{name}: no SYNOPSIS section"));
        let usage = lines[synopsis + 1].replace("\\-", "-");
        assert!(
            usage.starts_with(&format!("\\fB{command_line}\\fR")),
            "{name}: SYNOPSIS is {usage:?}"
        );
    }
    let top = std::fs::read_to_string(out.join("udc-studio.1"))
        .unwrap()
        .replace("\\-", "-");
    for sub in [
        "udc-studio-analyze(1)",
        "udc-studio-phase(1)",
        "udc-studio-completions(1)",
    ] {
        assert!(top.contains(sub), "the top page does not list {sub}");
    }
    assert!(!top.contains("manpages") && !top.contains("udc-studio-help"));

    if have("man") {
        for page in ["udc-studio.1", "udc-studio-phase-psf.1"] {
            let rendered = Command::new("man")
                .args(["-l", "--warnings", "-E", "UTF-8"])
                .arg(out.join(page))
                .env("MANWIDTH", "80")
                .output()
                .expect("run man");
            let text = String::from_utf8_lossy(&rendered.stdout);
            let warnings = String::from_utf8_lossy(&rendered.stderr);
            assert!(rendered.status.success(), "man {page}: {warnings}");
            assert!(warnings.trim().is_empty(), "man {page}: {warnings}");
            let title = page.trim_end_matches(".1").to_uppercase();
            let header = text.lines().next().unwrap_or_default();
            // Header: TITLE(1), the manual, TITLE(1); footer: the source (the build), then
            // the date (none), then TITLE(1).
            assert!(
                header.starts_with(&format!("{title}(1)")) && header.contains("UDC Studio"),
                "man {page}: header {header:?}"
            );
            let footer = text.lines().rev().find(|l| !l.trim().is_empty());
            let footer = footer.unwrap_or_default().trim_start();
            assert!(
                footer.starts_with(&format!("udc-studio {}", udc_studio::cli::TOOL_VERSION))
                    && footer.trim_end().ends_with(&format!("{title}(1)")),
                "man {page}: footer {footer:?}"
            );
            assert!(
                text.contains("SYNOPSIS") && text.contains("OPTIONS"),
                "{text}"
            );
        }
    } else {
        println!("note: man is not installed: the pages were not rendered");
    }

    // A directory that cannot be created: one line, exit 1.
    let file = dir.path().join("a-file");
    std::fs::write(&file, "").unwrap();
    let (code, _, stderr, _) =
        run_cli_timed(&["manpages", "--out", file.join("man1").to_str().unwrap()]);
    assert_eq!(code, Some(1), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("a-file"), "{stderr}");
}
