//! The simulation core stays pure: no GUI, no dialogs, no files (the layering in the crate docs, `src/lib.rs`).
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

/// `src/core/phase/chain.rs` → `core::phase::chain`; a `mod.rs` is its folder's module.
fn module_of(src: &std::path::Path, file: &std::path::Path) -> Vec<String> {
    let rel = file
        .strip_prefix(src)
        .expect("under src")
        .with_extension("");
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts
}

/// Every module path a file names through `crate::…` or `super::…` (brace lists expanded one
/// level), made absolute.
fn paths_named(module: &[String], text: &str) -> Vec<Vec<String>> {
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let mut out = Vec::new();
    for (start, _) in text
        .match_indices("crate::")
        .chain(text.match_indices("super::"))
    {
        let before = text[..start].chars().last();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        let mut base: Vec<String> = Vec::new();
        let mut rest = &text[start..];
        if rest.starts_with("crate::") {
            rest = &rest["crate::".len()..];
        } else {
            base = module.to_vec();
            while let Some(r) = rest.strip_prefix("super::") {
                base.pop();
                rest = r;
            }
        }
        loop {
            let name = ident(rest);
            if name.is_empty() {
                break;
            }
            rest = &rest[name.len()..];
            base.push(name);
            match rest.strip_prefix("::") {
                Some(r) => rest = r,
                None => break,
            }
        }
        if let Some(list) = rest.strip_prefix('{') {
            let body: String = list.chars().take_while(|c| *c != '}').collect();
            for item in body.split(',') {
                let name = ident(item.trim());
                if !name.is_empty() && name != "self" {
                    let mut p = base.clone();
                    p.push(name);
                    out.push(p);
                }
            }
        }
        out.push(base);
    }
    out
}

#[test]
fn sibling_modules_do_not_import_each_other_in_a_cycle() {
    use std::collections::{BTreeMap, BTreeSet};
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let modules: BTreeMap<Vec<String>, String> = files
        .iter()
        .map(|f| {
            (
                module_of(&src, f),
                std::fs::read_to_string(f).expect("read"),
            )
        })
        .filter(|(m, _)| !m.is_empty() && m != &["lib"] && m != &["main"])
        .collect();
    let known = |p: &[String]| modules.keys().any(|m| m.starts_with(p));
    // An edge from a module's ancestor to its sibling that the module names.
    let mut edges: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = BTreeMap::new();
    for (m, text) in &modules {
        for target in paths_named(m, text) {
            let k = m.iter().zip(&target).take_while(|(a, b)| a == b).count();
            if k < m.len() && k < target.len() && known(&target[..=k]) {
                edges
                    .entry(m[..=k].to_vec())
                    .or_default()
                    .insert(target[..=k].to_vec());
            }
        }
    }
    // Depth-first search for a back edge.
    fn visit(
        v: &Vec<String>,
        edges: &BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
        stack: &mut Vec<Vec<String>>,
        done: &mut BTreeSet<Vec<String>>,
    ) -> Option<Vec<String>> {
        if let Some(i) = stack.iter().position(|s| s == v) {
            return Some(stack[i..].iter().map(|m| m.join("::")).collect());
        }
        if done.contains(v) {
            return None;
        }
        stack.push(v.clone());
        for w in edges.get(v).into_iter().flatten() {
            if let Some(cycle) = visit(w, edges, stack, done) {
                return Some(cycle);
            }
        }
        stack.pop();
        done.insert(v.clone());
        None
    }
    assert!(
        edges.len() > 10,
        "the scan found too few imports: {edges:?}"
    );
    let mut done = BTreeSet::new();
    for v in edges.keys() {
        let cycle = visit(v, &edges, &mut Vec::new(), &mut done);
        assert!(cycle.is_none(), "import cycle between siblings: {cycle:?}");
    }
}
