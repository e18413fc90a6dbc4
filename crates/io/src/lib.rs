#![warn(missing_docs)]
//! Every file format the studio reads or writes. Core types go in, files come out; nothing here
//! simulates.

use std::path::Path;

/// The repository this crate was built from (two folders above its manifest): where the
/// presets, the test set and the reproduce specs are when the studio runs from a checkout.
#[must_use]
pub fn source_tree() -> &'static Path {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest.ancestors().nth(2).unwrap_or(manifest)
}

/// The version that names this build: the package version and the commit it was built from,
/// `0.1.0 (commit 1a2b3c4d5e6f)`, with `-dirty` after the hash when tracked files differed
/// from it and `unknown` outside a git checkout (see crates/io/build.rs). `--version` prints it
/// and every `tool_version` the commands and exports write carries it.
pub const TOOL_VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (commit ",
    env!("UDC_GIT_COMMIT"),
    ")"
);

/// Where a package installs the data a binary reads from disk (the test set, the reproduce
/// specs): `<prefix>/share/udc-studio` beside `<prefix>/bin`, so `/usr/bin/udc-studio` looks in
/// `/usr/share/udc-studio`. `None` when the running binary's path is unknown.
#[must_use]
pub fn installed_data_dir() -> Option<std::path::PathBuf> {
    let exe = std::env::current_exe().ok()?;
    Some(exe.parent()?.parent()?.join("share").join("udc-studio"))
}

pub mod decode_budget;
pub mod design;
pub mod display;
pub mod error;
pub mod fab;
pub mod figure;
pub mod lesson;
pub mod mask;
pub mod measured;
pub mod numbers;
pub mod phase;
pub mod photo;
pub mod safe_file;
pub mod sensor;
pub mod sweep;
pub mod system;

pub use error::IoError;
