//! What a package installs beside the binary: shell completions (`udc-studio completions`) and
//! man pages (`udc-studio manpages`, hidden), both from the command tree the command line is
//! parsed with, so they name every command and flag `--help` does.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};

/// The program's name in the scripts and pages.
const BIN: &str = "udc-studio";

/// A shell `completions` writes a script for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Shell {
    /// bash (with the bash-completion package).
    Bash,
    /// zsh (`compinit`).
    Zsh,
    /// fish.
    Fish,
}

impl Shell {
    fn generator(self) -> clap_complete::Shell {
        match self {
            Shell::Bash => clap_complete::Shell::Bash,
            Shell::Zsh => clap_complete::Shell::Zsh,
            Shell::Fish => clap_complete::Shell::Fish,
        }
    }
}

/// Arguments of `udc-studio completions`.
#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell to complete in.
    #[arg(value_enum)]
    pub shell: Shell,
}

/// Arguments of `udc-studio manpages`.
#[derive(Debug, Args)]
pub struct ManpagesArgs {
    /// The directory to write the pages into (created if needed; pages there are replaced).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

/// The script for `shell`, completing `udc-studio`.
pub fn completion_script(shell: Shell) -> Vec<u8> {
    let mut command = crate::parse::command();
    let mut script = Vec::new();
    if shell != Shell::Bash {
        clap_complete::generate(shell.generator(), &mut command, BIN, &mut script);
        return script;
    }
    // clap_complete's bash script spells a hyphenated program's states two ways, so nothing
    // past the first word completes (clap-rs/clap#6421): it is generated for `udc_studio`, whose
    // states agree, and registered for `udc-studio` (the function matches the command line's
    // first word whatever its name).
    let alias = BIN.replace('-', "_");
    clap_complete::generate(shell.generator(), &mut command, alias.as_str(), &mut script);
    let text = String::from_utf8_lossy(&script);
    let mut out = String::with_capacity(text.len());
    for line in text.split_inclusive('\n') {
        let body = line.trim_end_matches('\n');
        match body.strip_suffix(alias.as_str()) {
            Some(head) if body.trim_start().starts_with("complete ") => {
                out.push_str(head);
                out.push_str(BIN);
                out.push_str(&line[body.len()..]);
            }
            _ => out.push_str(line),
        }
    }
    out.into_bytes()
}

/// `udc-studio completions SHELL`: the script on stdout. A reader that stops early
/// (`| head`) is not an error.
///
/// # Errors
/// When stdout cannot be written.
pub fn completions_cmd(args: &CompletionsArgs) -> Result<()> {
    let script = completion_script(args.shell);
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(&script).and_then(|()| stdout.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(e).context("cannot write the completion script to stdout")
        }
        _ => Ok(()),
    }
}

/// The man pages as (file name, roff text): `udc-studio.1`, then one page per visible
/// subcommand, depth first, named by its path (`udc-studio-phase-psf.1`). Hidden commands and
/// `help` have none.
///
/// # Errors
/// When a page cannot be rendered.
pub fn man_pages() -> Result<Vec<(String, Vec<u8>)>> {
    fn no_help_subcommand(cmd: clap::Command) -> clap::Command {
        cmd.disable_help_subcommand(true)
            .mut_subcommands(no_help_subcommand)
    }
    fn collect(cmd: &clap::Command, out: &mut Vec<clap::Command>) {
        out.push(cmd.clone());
        for sub in cmd
            .get_subcommands()
            .filter(|s| !s.is_hide_set() && s.get_name() != "help")
        {
            collect(sub, out);
        }
    }
    let mut top = no_help_subcommand(crate::parse::command());
    // Gives every subcommand its hyphenated display name (`udc-studio-phase-psf`), the page's
    // NAME and file name, and its full usage (`udc-studio phase psf`).
    top.build();
    let mut commands = Vec::new();
    collect(&top, &mut commands);
    let source = format!("{BIN} {}", crate::TOOL_VERSION);
    commands
        .into_iter()
        .map(|cmd| {
            let name = cmd.get_display_name().unwrap_or(cmd.get_name()).to_string();
            let man = clap_mangen::Man::new(cmd)
                .title(name.to_uppercase())
                .section("1")
                // No date (the pages come out the same for the same build), as an explicit empty
                // argument: clap_mangen writes an empty one as nothing, and the source and
                // manual would shift into the date's and the source's places.
                .date("\"\"")
                .source(source.as_str())
                .manual("UDC Studio");
            let mut text = Vec::new();
            man.render(&mut text)
                .with_context(|| format!("cannot render the man page of {name}"))?;
            Ok((man.get_filename(), text))
        })
        .collect()
}

/// `udc-studio manpages --out DIR`: writes the pages and prints how many.
///
/// # Errors
/// A directory that cannot be created, a page that cannot be written.
pub fn manpages_cmd(args: &ManpagesArgs) -> Result<()> {
    let pages = man_pages()?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create the directory {}", args.out.display()))?;
    for (file, text) in &pages {
        udc_io::safe_file::write_atomic(&args.out.join(file), text)?;
    }
    println!(
        "wrote {} man pages into {}",
        pages.len(),
        args.out.display()
    );
    Ok(())
}
