//! The malformed-input campaign: every file in `tests/corpus` (written by `make_corpus.py`)
//! through every command that reads its kind, in a limited address space. Each must be refused
//! with exit code 1 or 2 and one line on stderr, leave no file behind and its input unchanged;
//! a run that has not finished after a minute is a hang.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Address space for one refusal (`ulimit -v`, KiB): a refusal must not allocate its way there.
const REFUSAL_ADDRESS_SPACE_KIB: u64 = 200 * 1024;
/// Not a timing goal (refusals take milliseconds): the point past which a run is a hang.
const HANG: Duration = Duration::from_secs(60);

fn corpus(kind: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/corpus")
        .join(kind);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("the corpus is committed")
        .map(|e| e.expect("entry").path())
        .collect();
    files.sort();
    assert!(files.len() >= 4, "{}: too few cases", dir.display());
    files
}

fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("list")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Runs `args` (with `{}` replaced by a private copy of `case` and `{out}` by a private output
/// directory) and checks the refusal contract. Returns the wall time.
fn refuse(case: &Path, args: &[&str]) -> Duration {
    let work = tempfile::tempdir().expect("temp dir");
    let input = work.path().join(case.file_name().expect("name"));
    std::fs::copy(case, &input).expect("copy the case");
    let before = std::fs::read(&input).expect("read");
    let out = work.path().join("out");
    std::fs::create_dir(&out).expect("out dir");
    let argv: Vec<String> = args
        .iter()
        .map(|a| {
            a.replace("{}", &input.to_string_lossy())
                .replace("{out}", &out.to_string_lossy())
        })
        .collect();
    let what = format!("{} {}", case.display(), args.join(" "));
    let t0 = Instant::now();
    let mut child = std::process::Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v {REFUSAL_ADDRESS_SPACE_KIB} && exec \"$0\" \"$@\""
        ))
        .arg(env!("CARGO_BIN_EXE_udc-studio"))
        .args(&argv)
        .current_dir(work.path())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("spawn");
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if t0.elapsed() > HANG {
            let _ = child.kill();
            panic!("{what}: still running after {HANG:?} (a hang)");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let took = t0.elapsed();
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().expect("stderr"), &mut stderr)
        .expect("stderr");
    assert!(
        matches!(status.code(), Some(1 | 2)),
        "{what}: exit {status:?} (a signal or panic, not a refusal): {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    assert!(stderr.starts_with("error: "), "{what}: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{what}: {stderr}");
    assert!(!stderr.contains(".part"), "{what}: a temp path in {stderr}");
    assert_eq!(
        std::fs::read(&input).expect("read"),
        before,
        "{what}: input changed"
    );
    let name = input
        .file_name()
        .expect("name")
        .to_string_lossy()
        .into_owned();
    let mut expected = vec!["out".to_string(), name];
    expected.sort();
    assert_eq!(listing(work.path()), expected, "{what}");
    assert!(listing(&out).is_empty(), "{what}: left {:?}", listing(&out));
    took
}

fn campaign(kind: &str, commands: &[&[&str]]) {
    let mut slowest = (Duration::ZERO, String::new());
    for case in corpus(kind) {
        for args in commands {
            let took = refuse(&case, args);
            if took > slowest.0 {
                slowest = (took, format!("{} {}", case.display(), args.join(" ")));
            }
        }
    }
    eprintln!("{kind}: slowest refusal {:?}: {}", slowest.0, slowest.1);
}

const PHOTO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/photos/astronaut_256.png"
);

#[test]
fn malformed_designs_are_refused_by_every_command() {
    campaign(
        "design",
        &[
            &["analyze", "{}", "--preview"],
            &[
                "export",
                "{}",
                "--format",
                "gds",
                "--region",
                "pixel",
                "--out",
                "{out}/m.gds",
            ],
            &[
                "restore",
                "{}",
                "--image",
                PHOTO,
                "--snr-db",
                "28",
                "--max-side-px",
                "32",
            ],
            &[
                "optimize",
                "{}",
                "--epochs",
                "1",
                "--preview",
                "--out",
                "{out}/o.json",
            ],
        ],
    );
}

#[test]
fn malformed_images_are_refused_as_photos_and_patterns() {
    campaign(
        "image",
        &[
            &["restore", "--image", "{}", "--snr-db", "28"],
            &[
                "phase",
                "restore",
                "--photo",
                "{}",
                "--photons",
                "250",
                "--peaks",
                "--preview",
            ],
            &["analyze", "--pattern", "{}", "--preview"],
            &[
                "denoise",
                "--image",
                "{}",
                "--sigma2",
                "0.01",
                "--out",
                "{out}/d.png",
            ],
        ],
    );
}

#[test]
fn malformed_hdr_scenes_are_refused() {
    campaign("hdr", &[&["sensor", "--hdr", "{}", "--out", "{out}"]]);
}

#[test]
fn malformed_spectral_responses_are_refused() {
    campaign("spectral", &[&["analyze", "--spectral", "{}", "--preview"]]);
}

#[test]
fn malformed_phase_designs_are_refused() {
    campaign(
        "phase",
        &[&[
            "phase",
            "export",
            "--design",
            "{}",
            "--format",
            "csv",
            "--out",
            "{out}/p.csv",
        ]],
    );
}

#[test]
fn malformed_masks_are_refused_by_the_importer() {
    use udc_studio::io::mask::{ImportOptions, import_mask};
    for case in corpus("mask") {
        let before = std::fs::read(&case).expect("read");
        let got = std::panic::catch_unwind(|| import_mask(&case, &ImportOptions::default()));
        let result = got.unwrap_or_else(|_| panic!("{}: the importer panicked", case.display()));
        let err = result
            .err()
            .unwrap_or_else(|| panic!("{}: accepted", case.display()));
        let text = err.to_string();
        assert_eq!(text.lines().count(), 1, "{}: {text}", case.display());
        assert!(text.contains(&*case.to_string_lossy()), "{text}");
        assert_eq!(std::fs::read(&case).expect("read"), before);
    }
}

/// Extreme flag values on every command: refused in one line, never run on.
#[test]
fn hostile_flag_values_are_refused_in_one_line() {
    use crate::common::run_cli_timed;
    let hdr = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/hdr/StillLife_620x423.exr"
    );
    let out = tempfile::tempdir().expect("temp dir");
    let design_out = out.path().join("o.json");
    let design_out = design_out.to_str().expect("utf-8");
    for v in ["1e-300", "1e308", "-1", "NaN", "inf"] {
        let exposure = format!("mean:{v}");
        let cases: Vec<Vec<&str>> = vec![
            vec!["analyze", "--pitch-um", v, "--preview"],
            vec!["phase", "psf", "--pitch-um", v],
            vec!["phase", "psf", "--fold", v],
            vec!["phase", "psf", "--n", v],
            vec!["phase", "psf", "--open-ratio", v],
            vec!["phase", "invertibility", "--f-mla-um", v],
            vec!["phase", "restore", "--photons", v, "--peaks", "--preview"],
            vec!["sensor", "--hdr", hdr, "--snr-t", v],
            vec!["sensor", "--hdr", hdr, "--exposure", &exposure],
            vec!["restore", "--image", PHOTO, "--light", v],
            vec![
                "optimize",
                "--area",
                v,
                "--epochs",
                "1",
                "--preview",
                "--out",
                design_out,
            ],
        ];
        let mut cases = cases;
        if v != "1e-300" {
            // η = 0 is a valid margin and 0 a valid loss weight, so tiny ones are too.
            cases.push(vec!["sensor", "--hdr", hdr, "--eta", v]);
            cases.push(vec![
                "optimize",
                "--weight-inv",
                v,
                "--epochs",
                "1",
                "--out",
                design_out,
            ]);
        }
        for args in cases {
            let (code, stdout, stderr, _) = run_cli_timed(&args);
            assert_eq!(code, Some(1), "{args:?}: {stdout}{stderr}");
            assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: {stderr}");
            // Numbers are shown compactly, never as hundreds of digits.
            assert!(stderr.len() < 400, "{args:?}: {stderr}");
        }
        assert!(
            !out.path().join("o.json").exists(),
            "an optimize run saved a design"
        );
    }
}
