//! What several benches share: where their figures for benches/report.sh go.

use std::path::PathBuf;

/// Writes `text` to `<target>/udc-bench/<name>` (criterion's target dir convention). A read-only
/// target dir only prints a message: the figures are a convenience, the bench must not fail.
pub fn write_figures(name: &str, text: &str) {
    let target =
        std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| PathBuf::from("target"), PathBuf::from);
    let path = target.join("udc-bench").join(name);
    let written = path
        .parent()
        .map_or(Ok(()), std::fs::create_dir_all)
        .and_then(|()| std::fs::write(&path, text));
    if let Err(e) = written {
        eprintln!("could not write {}: {e}", path.display());
    }
}
