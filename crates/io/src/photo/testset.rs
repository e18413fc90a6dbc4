//! The denoising test set, `assets/testset/`: 512×512 open-licence photographs (see the book's reproducing chapter
//! there), listed and loaded.
//!
//! Unlike the built-in photo it is not compiled into the binary (3 MB of PNGs that only tests,
//! benches and studies read), so it is looked for on disk: next to the running binary (and up to
//! three folders above it, which covers `target/{debug,release}[/deps]` in a checkout), then
//! where a package installs it (`/usr/share/udc-studio` for `/usr/bin/udc-studio`), then under
//! the working directory, then in the source tree the binary was built from.

use std::path::{Path, PathBuf};

use ndarray::Array2;

use crate::IoError;
use crate::photo::planes::read_planes;

/// The test set's folder relative to the repository (or an installed binary's folder).
pub const TESTSET_SUBDIR: &str = "assets/testset";

/// Where the test set was when this binary was built.
fn built_in_dir() -> PathBuf {
    crate::source_tree().join(TESTSET_SUBDIR)
}

/// The folders looked in, in order (see the module docs).
fn candidate_dirs() -> Vec<PathBuf> {
    let mut dirs = Vec::new();
    if let Ok(exe) = std::env::current_exe() {
        dirs.extend(
            exe.ancestors()
                .skip(1)
                .take(4)
                .map(|d| d.join(TESTSET_SUBDIR)),
        );
    }
    if let Some(share) = crate::installed_data_dir() {
        dirs.push(share.join(TESTSET_SUBDIR));
    }
    if let Ok(cwd) = std::env::current_dir() {
        dirs.push(cwd.join(TESTSET_SUBDIR));
    }
    dirs.push(built_in_dir());
    dirs
}

/// The test set's folder: the first of the places in the module docs that exists, or the
/// source tree's (which then names the missing folder in [`testset_photos`]'s error).
pub fn testset_dir() -> PathBuf {
    candidate_dirs()
        .into_iter()
        .find(|d| d.is_dir())
        .unwrap_or_else(built_in_dir)
}

/// The test set's PNG files, sorted by name.
///
/// # Errors
/// [`IoError::File`] when the folder (see [`testset_dir`]) cannot be listed.
pub fn testset_photos() -> Result<Vec<PathBuf>, IoError> {
    let dir = testset_dir();
    let list = |e| IoError::file("list the test set", &dir, e);
    let mut photos = Vec::new();
    for entry in std::fs::read_dir(&dir).map_err(list)? {
        let path = entry.map_err(list)?.path();
        let is_png = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if is_png && path.is_file() {
            photos.push(path);
        }
    }
    photos.sort();
    Ok(photos)
}

/// A test-set photo as its planes in `[0, 1]`: one for a grey photo, three (R, G, B) for a
/// colour one. Callers that need colour repeat the grey plane.
///
/// # Errors
/// As [`read_planes`].
pub fn load_testset_photo(path: &Path) -> Result<Vec<Array2<f64>>, IoError> {
    read_planes(path).map(|image| image.planes)
}
