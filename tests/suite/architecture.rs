//! The layering: one crate per layer (fft → core → gpu, io → jobs → cli → studio), the compiler
//! refusing an arrow back up; these tests add what the compiler does not see: no window crate
//! below the studio, wgpu named only by the GPU crate and the studio, no file access in the core,
//! and no import cycle between sibling modules inside a crate.
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

fn repo() -> &'static std::path::Path {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The source folders of the workspace's crates, lowest layer first.
const CRATE_SOURCES: [&str; 8] = [
    "crates/fft/src",
    "crates/core/src",
    "crates/gpu/src",
    "crates/io/src",
    "crates/jobs/src",
    "crates/cli/src",
    "python/src",
    "src",
];

/// What a headless build must not link: the window and dialog stack. (wgpu is the compute
/// backend's too: the GPU crate opens a headless device; see `wgpu_is_named_by_the_gpu_crate_and_the_studio_only`.)
const GUI_CRATES: [&str; 6] = [
    "egui",
    "eframe",
    "egui_plot",
    "winit",
    "rfd",
    "egui_kittest",
];

/// Every package `root` depends on, directly or not, for any target and feature, as
/// `Cargo.lock` records it (a package's entries name its dependencies by name, or by
/// "name version" when several versions are locked).
fn locked_closure(root: &str) -> std::collections::BTreeSet<String> {
    let lock: toml::Table = std::fs::read_to_string(repo().join("Cargo.lock"))
        .expect("read Cargo.lock")
        .parse()
        .expect("parse Cargo.lock");
    let packages = lock["package"].as_array().expect("packages");
    let deps_of = |name: &str| -> Vec<String> {
        let (name, version) = name.split_once(' ').unwrap_or((name, ""));
        packages
            .iter()
            .filter(|p| p["name"].as_str() == Some(name))
            .filter(|p| version.is_empty() || p["version"].as_str() == Some(version))
            .flat_map(|p| p.get("dependencies").and_then(|d| d.as_array()).cloned())
            .flatten()
            .filter_map(|d| d.as_str().map(str::to_string))
            .collect()
    };
    let mut seen = std::collections::BTreeSet::new();
    let mut todo = vec![root.to_string()];
    while let Some(p) = todo.pop() {
        for d in deps_of(&p) {
            if seen.insert(d.clone()) {
                todo.push(d);
            }
        }
    }
    seen.into_iter()
        .map(|d| d.split(' ').next().unwrap_or_default().to_string())
        .collect()
}

#[test]
fn the_core_io_and_cli_crates_and_the_python_module_link_no_gui() {
    for krate in [
        "udc-core",
        "udc-gpu",
        "udc-io",
        "udc-jobs",
        "udc-cli",
        "udc-studio-python",
    ] {
        let closure = locked_closure(krate);
        assert!(
            closure.contains("ndarray"),
            "{krate}: the lock walk found {closure:?}"
        );
        for gui in GUI_CRATES {
            assert!(!closure.contains(gui), "{krate} depends on {gui}");
        }
    }
    // The studio crate itself takes each GUI crate only through its `gui` feature.
    assert!(locked_closure("udc-studio").contains("eframe"));
    let manifest: toml::Table = std::fs::read_to_string(repo().join("Cargo.toml"))
        .expect("read Cargo.toml")
        .parse()
        .expect("parse Cargo.toml");
    let deps = manifest["dependencies"].as_table().expect("dependencies");
    for (name, spec) in deps {
        if GUI_CRATES.contains(&name.as_str()) || name == "egui_commonmark" || name == "wgpu" {
            let optional = spec.get("optional").and_then(toml::Value::as_bool);
            assert_eq!(
                optional,
                Some(true),
                "{name} must be optional (feature `gui`)"
            );
        }
    }
}

/// The compute backend is one crate: the core and the file formats link no wgpu, and among the
/// rest only the GPU crate (which owns the device, the pipelines and the WGSL) and the studio
/// (which hands it eframe's device) name wgpu; the jobs, the CLI and Python reach it through
/// the GPU crate's `Route`.
#[test]
fn wgpu_is_named_by_the_gpu_crate_and_the_studio_only() {
    for krate in ["udc-core", "udc-io", "udc-fft"] {
        assert!(
            !locked_closure(krate).contains("wgpu"),
            "{krate} links wgpu"
        );
    }
    assert!(locked_closure("udc-gpu").contains("wgpu"));
    for manifest in [
        "crates/core",
        "crates/io",
        "crates/jobs",
        "crates/cli",
        "python",
    ] {
        let text = std::fs::read_to_string(repo().join(manifest).join("Cargo.toml")).unwrap();
        let table: toml::Table = text.parse().unwrap();
        for section in ["dependencies", "dev-dependencies"] {
            if let Some(deps) = table.get(section).and_then(toml::Value::as_table) {
                assert!(!deps.contains_key("wgpu"), "{manifest} names wgpu");
            }
        }
    }
    for src in [
        "crates/core/src",
        "crates/io/src",
        "crates/jobs/src",
        "crates/cli/src",
        "python/src",
    ] {
        let mut files = Vec::new();
        rust_files(&repo().join(src), &mut files);
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            assert!(!text.contains("wgpu::"), "{} uses wgpu", f.display());
        }
    }
}

/// The command line is a front end: the core and the file formats name their closed sets
/// (strum) and the CLI offers them to clap, so a library user builds no argument parser.
#[test]
fn the_core_and_io_link_no_argument_parser() {
    for krate in ["udc-core", "udc-io"] {
        let closure = locked_closure(krate);
        assert!(closure.contains("strum"), "{krate}: {closure:?}");
        for parser in ["clap", "clap_builder", "clap_derive"] {
            assert!(!closure.contains(parser), "{krate} depends on {parser}");
        }
    }
    assert!(locked_closure("udc-cli").contains("clap"));
    // The jobs carry clap's derive beside serde's: each parameter's flag, help and default once.
    assert!(locked_closure("udc-jobs").contains("clap"));
}

/// Internal calls are typed: the job layer (and the sweep runner in it) and the Python module
/// build jobs from their structs and parameters, never a command line to parse, and link no
/// command-line crate; nothing starts the project's own binary.
#[test]
fn internal_calls_build_no_command_line() {
    for krate in ["udc-jobs", "udc-studio-python"] {
        assert!(
            !locked_closure(krate).contains("udc-cli"),
            "{krate} depends on udc-cli"
        );
    }
    let mut files = Vec::new();
    for dir in ["crates/jobs/src", "python/src", "python/udc_studio", "src"] {
        let root = repo().join(dir);
        rust_files(&root, &mut files);
        for entry in std::fs::read_dir(&root).expect("read dir").flatten() {
            if entry.path().extension().is_some_and(|e| e == "py") {
                files.push(entry.path());
            }
        }
    }
    assert!(files.iter().any(|f| f.ends_with("_jobs.py")), "{files:?}");
    for f in files {
        let text = std::fs::read_to_string(&f).expect("read source");
        for word in [
            "parse_from",
            "get_matches_from",
            "Command::new",
            "current_exe",
            "\"--json\"",
            "subprocess",
        ] {
            assert!(!text.contains(word), "{} uses {word}", f.display());
        }
    }
}

/// One module-file style: a module that grew into a folder keeps its own file as the folder's
/// `mod.rs`, never as a `name.rs` beside a `name/` folder.
#[test]
fn a_folder_module_is_its_mod_rs() {
    let mut beside = Vec::new();
    for src in CRATE_SOURCES {
        let mut files = Vec::new();
        rust_files(&repo().join(src), &mut files);
        for f in files {
            if f.with_extension("").is_dir() {
                beside.push(f);
            }
        }
    }
    assert!(beside.is_empty(), "move to name/mod.rs: {beside:?}");
}

/// The studio runs its jobs through the library calls, never by starting a program (its own
/// binary included): a run shares the studio's `Progress` and cancel, and its errors are typed.
#[test]
fn the_studio_starts_no_process() {
    let mut files = Vec::new();
    rust_files(&repo().join("src"), &mut files);
    for f in files {
        let text = std::fs::read_to_string(&f).expect("read source");
        for word in ["Command::new", "current_exe"] {
            assert!(!text.contains(word), "{} uses {word}", f.display());
        }
    }
}

#[test]
fn core_reads_no_files() {
    // The core and the FFT plans below it.
    let mut files = Vec::new();
    for src in &CRATE_SOURCES[..2] {
        rust_files(&repo().join(src), &mut files);
    }
    assert!(files.len() > 5);
    for f in files {
        let text = std::fs::read_to_string(&f).expect("read");
        for banned in ["std::fs", "File::open", "File::create"] {
            assert!(!text.contains(banned), "{} mentions {banned}", f.display());
        }
    }
}

/// `crates/core/src/phase/chain/propagate.rs` → `phase::chain::propagate`; a `mod.rs` is its
/// folder's module.
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
    // The FFT crate is one file: it has no sibling modules.
    for crate_src in &CRATE_SOURCES[1..] {
        no_sibling_cycle(&repo().join(crate_src));
    }
}

fn no_sibling_cycle(src: &std::path::Path) {
    use std::collections::{BTreeMap, BTreeSet};
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let modules: BTreeMap<Vec<String>, String> = files
        .iter()
        .map(|f| (module_of(src, f), std::fs::read_to_string(f).expect("read")))
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
        edges.len() > 3,
        "the scan of {} found too few imports: {edges:?}",
        src.display()
    );
    let mut done = BTreeSet::new();
    for v in edges.keys() {
        let cycle = visit(v, &edges, &mut Vec::new(), &mut done);
        assert!(cycle.is_none(), "import cycle between siblings: {cycle:?}");
    }
}

/// Only `udc-fft` plans transforms: rustfft's planners are generic, so a planner in another
/// crate compiles every FFT algorithm again there (docs/src/budgets.md).
#[test]
fn fft_plans_are_made_only_in_the_fft_crate() {
    let mut files = Vec::new();
    for src in &CRATE_SOURCES[1..] {
        rust_files(&repo().join(src), &mut files);
    }
    rust_files(&repo().join("tests"), &mut files);
    rust_files(&repo().join("benches"), &mut files);
    assert!(files.len() > 50);
    // Spelled in pieces, so this file does not name what it looks for.
    let banned = ["Fft", "Planner"].concat();
    for f in files {
        let text = std::fs::read_to_string(&f).expect("read");
        assert!(
            !text.contains(&banned),
            "{} makes its own FFT planner; use udc_fft's plans",
            f.display()
        );
    }
}
