//! The simulation core stays pure: no GUI, no dialogs, no files (STYLE.md, "The house").
#![allow(clippy::unwrap_used, clippy::expect_used)]

fn rust_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("read src") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn core_uses_neither_egui_nor_files() {
    let mut files = Vec::new();
    rust_files(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/core"),
        &mut files,
    );
    assert!(files.len() > 5);
    for f in files {
        let text = std::fs::read_to_string(&f).expect("read");
        for banned in [
            "egui",
            "eframe",
            "rfd",
            "std::fs",
            "crate::io",
            "crate::app",
        ] {
            assert!(!text.contains(banned), "{} mentions {banned}", f.display());
        }
    }
}
