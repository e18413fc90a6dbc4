//! The README and the book (`docs/`): every relative link and image resolves, every chapter is
//! in `SUMMARY.md` and every entry there exists, the README stays a front page, and the CLI
//! reference is the one the command tree generates (`UDC_BLESS_DOCS=1` rewrites it).

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

use pulldown_cmark::{Event, LinkType, Parser, Tag};

/// The README's budget: a front page, with the detail in the book.
const README_MAX_LINES: usize = 250;

/// The generated CLI reference, relative to the package root.
const CLI_REFERENCE: &str = "docs/src/cli-reference.md";

/// The package root, where README.md and docs/ live.
fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// `path` relative to the package root, for messages.
fn shown(path: &Path) -> String {
    let root = root();
    path.strip_prefix(&root)
        .unwrap_or(path)
        .display()
        .to_string()
}

/// Every Markdown file under `dir`, sorted.
fn markdown_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        let entries = std::fs::read_dir(&folder)
            .unwrap_or_else(|e| panic!("cannot list {}: {e}", folder.display()));
        for entry in entries {
            let path = entry
                .unwrap_or_else(|e| panic!("cannot list {}: {e}", folder.display()))
                .path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|x| x == "md") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// The destination of every link and image in `markdown`, as written.
fn destinations(markdown: &str) -> Vec<String> {
    Parser::new(markdown)
        .filter_map(|event| match event {
            Event::Start(
                Tag::Link {
                    link_type,
                    dest_url,
                    ..
                }
                | Tag::Image {
                    link_type,
                    dest_url,
                    ..
                },
            ) if link_type != LinkType::Email => Some(dest_url.to_string()),
            _ => None,
        })
        .collect()
}

/// Whether a destination names a file of the repository: not a web address, not a mail
/// address, not an anchor on the same page.
fn is_relative(destination: &str) -> bool {
    !(destination.starts_with('#')
        || ["http:", "https:", "mailto:"]
            .iter()
            .any(|scheme| destination.starts_with(scheme)))
}

/// The file part of a destination, without its `#fragment`.
fn without_fragment(destination: &str) -> &str {
    destination.split('#').next().unwrap_or(destination)
}

/// `path` with `.` and `..` folded away, so that two spellings of one file compare equal.
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// The files a Markdown file's relative links and images point to, resolved against its folder;
/// an empty destination resolves to nothing and is reported as such.
fn link_targets(file: &Path) -> Vec<(String, Option<PathBuf>)> {
    let folder = file.parent().unwrap_or(Path::new("."));
    destinations(&read(file))
        .into_iter()
        .filter(|d| is_relative(d))
        .map(|d| {
            let target = without_fragment(&d);
            let resolved = (!target.is_empty()).then(|| normalize(&folder.join(target)));
            (d, resolved)
        })
        .collect()
}

#[test]
fn every_relative_link_and_image_of_the_readme_and_the_book_resolves() {
    let root = root();
    let mut files = vec![root.join("README.md")];
    files.extend(markdown_files(&root.join("docs/src")));
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in &files {
        for (destination, resolved) in link_targets(file) {
            checked += 1;
            if !resolved.as_deref().is_some_and(Path::exists) {
                broken.push(format!("{}: {destination}", shown(file)));
            }
        }
    }
    assert!(
        broken.is_empty(),
        "{} broken link(s) (file: target):\n{}",
        broken.len(),
        broken.join("\n")
    );
    assert!(
        checked > 0,
        "no relative links found: is the parser reading the files?"
    );
}

#[test]
fn every_chapter_is_in_the_summary_and_every_entry_exists() {
    let src = root().join("docs/src");
    let summary = src.join("SUMMARY.md");
    let listed: BTreeSet<PathBuf> = link_targets(&summary)
        .into_iter()
        .filter_map(|(_, resolved)| resolved)
        .collect();
    let chapters: BTreeSet<PathBuf> = markdown_files(&src)
        .into_iter()
        .filter(|f| *f != summary)
        .map(|f| normalize(&f))
        .collect();
    let missing: Vec<String> = chapters.difference(&listed).map(|f| shown(f)).collect();
    let absent: Vec<String> = listed
        .iter()
        .filter(|f| !f.is_file())
        .map(|f| shown(f))
        .collect();
    assert!(
        missing.is_empty() && absent.is_empty(),
        "chapters not listed in docs/src/SUMMARY.md:\n{}\nSUMMARY.md entries that do not exist:\n{}",
        missing.join("\n"),
        absent.join("\n")
    );
}

#[test]
fn the_readme_is_a_front_page() {
    let lines = read(&root().join("README.md")).lines().count();
    assert!(
        lines <= README_MAX_LINES,
        "README.md has {lines} lines, at most {README_MAX_LINES}: move the detail into the book \
         (docs/src) and link it"
    );
}

/// Appends one command's section, then its subcommands', depth first in their order.
fn write_command(out: &mut String, command: &clap::Command) {
    let name = command.get_bin_name().unwrap_or(command.get_name());
    let about = command
        .get_about()
        .map(ToString::to_string)
        .unwrap_or_default();
    let help = command.clone().render_long_help().to_string();
    let lines: Vec<&str> = help.trim_end().lines().map(str::trim_end).collect();
    writeln!(out, "\n## {name}\n").expect("writing to a String");
    if !about.trim().is_empty() {
        writeln!(out, "{}\n", about.trim()).expect("writing to a String");
    }
    writeln!(out, "```text\n{}\n```", lines.join("\n")).expect("writing to a String");
    for sub in command
        .get_subcommands()
        .filter(|sub| sub.get_name() != "help" && !sub.is_hide_set())
    {
        write_command(out, sub);
    }
}

/// The CLI reference as Markdown: a section per command with its about text and its full
/// `--help`, at a fixed width and without colour so the text is the same on every machine.
fn cli_reference() -> String {
    use clap::CommandFactory;
    let mut command = udc_studio::cli::Cli::command()
        .term_width(100)
        .disable_colored_help(true);
    // Builds every subcommand and gives each its full name (`udc-studio phase restore`).
    command.build();
    let mut out = String::from(
        "# CLI reference\n\n<!-- Generated from the clap command tree by \
         tests/suite/docs_book.rs; do not edit.\n     Regenerate: UDC_BLESS_DOCS=1 cargo test \
         --test suite docs_book -->\n",
    );
    write_command(&mut out, &command);
    out
}

#[test]
fn the_cli_reference_is_generated_from_the_command_tree() {
    let path = root().join(CLI_REFERENCE);
    let generated = cli_reference();
    if std::env::var("UDC_BLESS_DOCS").is_ok_and(|v| v == "1") {
        if let Err(e) = std::fs::write(&path, generated.as_bytes()) {
            panic!("cannot write {}: {e}", path.display());
        }
        return;
    }
    let on_disk = std::fs::read_to_string(&path).unwrap_or_default();
    if on_disk == generated {
        return;
    }
    let first_difference = on_disk
        .lines()
        .zip(generated.lines())
        .position(|(a, b)| a != b)
        .unwrap_or_else(|| on_disk.lines().count().min(generated.lines().count()));
    panic!(
        "{CLI_REFERENCE} is stale (first difference at line {}: {:?} on disk, {:?} generated); \
         regenerate it with `UDC_BLESS_DOCS=1 cargo test --test suite docs_book` and commit it",
        first_difference + 1,
        on_disk
            .lines()
            .nth(first_difference)
            .unwrap_or("<end of file>"),
        generated
            .lines()
            .nth(first_difference)
            .unwrap_or("<end of file>"),
    );
}

/// Help texts read on a terminal: no rustdoc link brackets leak from a doc comment into
/// `--help` (the reference is every command's help, generated).
#[test]
fn the_cli_help_has_no_rustdoc_links() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let reference =
        std::fs::read_to_string(root.join("docs/src/cli-reference.md")).expect("the reference");
    assert!(
        reference.contains("`AdditiveGain` chooses"),
        "the bin-mode help"
    );
    for (n, line) in reference.lines().enumerate() {
        assert!(
            !line.contains("[`") && !line.contains("`]"),
            "line {}: {line}",
            n + 1
        );
    }
}
