//! Names the build: `UDC_GIT_COMMIT` is the short hash of the repository's HEAD (12 digits),
//! with `-dirty` when tracked files differ from it, or `unknown` outside a git checkout (a
//! crates tarball, a source archive) or without `git`. `udc-studio --version` and every
//! `tool_version` the commands and exports write carry it (`udc_io::TOOL_VERSION`).
//!
//! Cheap on purpose: two `git` calls, and cargo reruns it only when HEAD, the branch it points
//! to or the index changes (a commit, a checkout, `git add`). An edit to a tracked file shows
//! as `-dirty` once the index is next touched (`git status`, `git add`, a commit).

use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let commit = match repository() {
        Some((root, git_dir)) => {
            watch(&git_dir);
            describe(&root).unwrap_or_else(|| "unknown".to_string())
        }
        None => "unknown".to_string(),
    };
    println!("cargo:rustc-env=UDC_GIT_COMMIT={commit}");
}

/// The workspace root and its git directory (`../../.git` from this crate), when there is one.
/// Only this repository counts: a tarball unpacked inside some other checkout is `unknown`.
fn repository() -> Option<(PathBuf, PathBuf)> {
    let manifest_dir = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR")?);
    let root = manifest_dir.parent()?.parent()?.to_path_buf();
    let dot_git = root.join(".git");
    if dot_git.is_dir() {
        return Some((root, dot_git));
    }
    // A linked worktree or a submodule: `.git` is a file `gitdir: PATH`.
    let text = std::fs::read_to_string(&dot_git).ok()?;
    let dir = Path::new(text.strip_prefix("gitdir:")?.trim());
    let git_dir = if dir.is_absolute() {
        dir.to_path_buf()
    } else {
        root.join(dir)
    };
    git_dir.is_dir().then_some((root, git_dir))
}

/// Reruns this script when HEAD moves: HEAD itself (a checkout), the branch it names (a
/// commit), the packed refs (a branch that only lives there), the index (staging, dirtiness).
/// Only files that exist: cargo treats a missing one as always changed.
fn watch(git_dir: &Path) {
    let head = git_dir.join("HEAD");
    let mut files = vec![head.clone(), git_dir.join("index")];
    if let Ok(text) = std::fs::read_to_string(&head)
        && let Some(name) = text.strip_prefix("ref:")
    {
        let name = name.trim();
        files.push(git_dir.join(name));
        // A linked worktree keeps its branches in the common directory.
        if let Ok(common) = std::fs::read_to_string(git_dir.join("commondir")) {
            let common = git_dir.join(common.trim());
            files.push(common.join(name));
            files.push(common.join("packed-refs"));
        }
    }
    files.push(git_dir.join("packed-refs"));
    for f in files.into_iter().filter(|f| f.is_file()) {
        println!("cargo:rerun-if-changed={}", f.display());
    }
}

/// `1a2b3c4d5e6f` or `1a2b3c4d5e6f-dirty`; `None` when `git` is missing or fails.
fn describe(root: &Path) -> Option<String> {
    let hash = git(root, &["rev-parse", "--short=12", "HEAD"])?;
    let hash = hash.trim();
    if hash.is_empty() || !hash.chars().all(|c| c.is_ascii_hexdigit()) {
        return None;
    }
    // `--no-optional-locks`: status does not rewrite the index it reads, which would change
    // the file this script watches and rerun it on every build.
    let status = git(
        root,
        &[
            "--no-optional-locks",
            "status",
            "--porcelain",
            "--untracked-files=no",
        ],
    )?;
    Some(if status.trim().is_empty() {
        hash.to_string()
    } else {
        format!("{hash}-dirty")
    })
}

/// The stdout of a successful `git -C root ARGS`.
fn git(root: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .arg("-C")
        .arg(root)
        .args(args)
        .output()
        .ok()?;
    if !out.status.success() {
        return None;
    }
    String::from_utf8(out.stdout).ok()
}
