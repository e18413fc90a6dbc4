//! Files in and out (`io::safe_file`): special files and oversized files are refused before they
//! are read, a byte-order mark is accepted by every text reader, temp files are unique and never
//! left behind, not even after Ctrl-C in the middle of an export.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::time::{Duration, Instant};

use udc_studio::io::IoError;
use udc_studio::io::design::file::{load_design, to_json};
use udc_studio::io::design::pattern::load_pattern_png;
use udc_studio::io::design::presets::load_preset;
use udc_studio::io::design::spectral::load_response_csv;
use udc_studio::io::phase::design::load_phase_design;
use udc_studio::io::photo::hdr::load_hdr;
use udc_studio::io::photo::load_photo;
use udc_studio::io::safe_file::{
    TempFile, read_bounded, read_text_bounded, temp_files_in_flight, write_atomic,
};

/// Every reader of the studio, by name, on one path.
fn every_reader(path: &Path) -> Vec<(&'static str, Result<(), IoError>)> {
    vec![
        ("design", load_design(path).map(|_| ())),
        ("phase design", load_phase_design(path).map(|_| ())),
        ("spectral", load_response_csv(path).map(|_| ())),
        ("photo", load_photo::<f64>(path, Some(64)).map(|_| ())),
        ("pattern", load_pattern_png(path).map(|_| ())),
        ("hdr", load_hdr(path).map(|_| ())),
    ]
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn devices_fifos_and_directories_are_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.json");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    for path in [Path::new("/dev/zero"), &fifo, dir.path()] {
        for (reader, result) in every_reader(path) {
            let start = Instant::now();
            let e = result.expect_err(reader);
            assert!(
                start.elapsed() < Duration::from_secs(1),
                "{reader} took {:?} on {}",
                start.elapsed(),
                path.display()
            );
            assert!(
                matches!(e, IoError::NotAFile { .. }),
                "{reader} on {}: {e}",
                path.display()
            );
            let msg = e.to_string();
            assert!(msg.contains(&path.display().to_string()), "{msg}");
            assert!(msg.contains("give a regular file"), "{msg}");
        }
    }
}

#[test]
fn a_file_past_the_cap_is_refused_whatever_its_metadata() {
    let dir = tempfile::tempdir().unwrap();
    // A sparse file one byte past the design cap: refused from its length, nothing read.
    let big = dir.path().join("big.json");
    let f = std::fs::File::create(&big).unwrap();
    f.set_len(udc_studio::io::design::file::MAX_FILE_BYTES + 1)
        .unwrap();
    let e = load_design(&big).unwrap_err();
    assert!(matches!(e, IoError::TooLarge { .. }), "{e}");
    // A file that grows past the cap while it is read: the read stops one byte past it.
    let small = dir.path().join("small.txt");
    std::fs::write(&small, vec![b'x'; 100]).unwrap();
    assert_eq!(read_bounded(&small, 100, "read").unwrap().len(), 100);
    assert!(matches!(
        read_bounded(&small, 99, "read"),
        Err(IoError::TooLarge { cap: 99, .. })
    ));
    // Not UTF-8: the offset of the first bad byte.
    let bad = dir.path().join("latin1.csv");
    std::fs::write(&bad, b"wavelength_nm,r,g,b\n500,0.1,0.2,\xe90.3\n").unwrap();
    match read_text_bounded(&bad, 1000, "read") {
        Err(IoError::NotText { offset, .. }) => assert_eq!(offset, 32),
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_byte_order_mark_is_accepted_by_every_text_reader() {
    let dir = tempfile::tempdir().unwrap();
    let design = load_preset("toled-150dpi").unwrap();
    let path = dir.path().join("bom.json");
    std::fs::write(&path, format!("\u{feff}{}", to_json(&design))).unwrap();
    assert_eq!(load_design(&path).unwrap(), design);
    let csv = dir.path().join("bom.csv");
    std::fs::write(
        &csv,
        "\u{feff}wavelength_nm,r,g,b\n400,0.1,0.2,0.3\n700,0.3,0.2,0.1\n",
    )
    .unwrap();
    let r = load_response_csv(&csv).unwrap();
    assert_eq!(r.wavelengths_nm, vec![400.0, 700.0]);
    let phase = dir.path().join("phase.json");
    let d = udc_studio::core::phase::PhaseDesign::thesis(42.0, 5.0);
    udc_studio::io::phase::design::save_phase_design(&phase, &d).unwrap();
    let text = std::fs::read_to_string(&phase).unwrap();
    std::fs::write(&phase, format!("\u{feff}{text}")).unwrap();
    assert_eq!(load_phase_design(&phase).unwrap().design, d);
}

#[test]
fn temp_files_are_unique_and_never_left_behind() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("out.gds");
    let before = temp_files_in_flight();
    let a = TempFile::beside(&target).unwrap();
    let b = TempFile::beside(&target).unwrap();
    assert_ne!(a.path(), b.path(), "two writers to one target");
    assert_eq!(a.path().parent(), Some(dir.path()), "beside the target");
    assert!(temp_files_in_flight() >= before + 2);
    std::fs::write(a.path(), b"first").unwrap();
    std::fs::write(b.path(), b"second").unwrap();
    drop(a);
    b.persist().unwrap();
    assert_eq!(std::fs::read(&target).unwrap(), b"second");
    assert_eq!(names_in(dir.path()), vec!["out.gds".to_string()]);
    // Writers racing to one target: one complete content wins, nothing else stays.
    let threads: Vec<_> = (0..8u8)
        .map(|i| {
            let t = target.clone();
            std::thread::spawn(move || write_atomic(&t, &vec![i; 1 << 16]).unwrap())
        })
        .collect();
    for t in threads {
        t.join().unwrap();
    }
    let got = std::fs::read(&target).unwrap();
    assert_eq!(got.len(), 1 << 16);
    assert!(got.iter().all(|b| *b == got[0]), "a mixed file");
    assert_eq!(names_in(dir.path()), vec!["out.gds".to_string()]);
    // A failed persist (the target is a directory) names the target and leaves nothing.
    let blocked = dir.path().join("blocked");
    std::fs::create_dir(&blocked).unwrap();
    let e = write_atomic(&blocked, b"x").unwrap_err().to_string();
    assert!(e.contains("blocked") && !e.contains(".part"), "{e}");
    assert_eq!(
        names_in(dir.path()),
        vec!["blocked".to_string(), "out.gds".to_string()]
    );
}

/// Ctrl-C in the middle of a large export: the CLI exits with 130 and the `.part` file it was
/// writing is gone.
#[test]
fn ctrl_c_during_an_export_leaves_no_part_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("display.svg");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_udc-studio"))
        .args([
            "export",
            "--preset",
            "toled-150dpi",
            "--tiling",
            "random-d4",
            "--format",
            "svg",
            "--region",
            "1080x2400",
            "--out",
        ])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let part = loop {
        if let Some(p) = names_in(dir.path())
            .into_iter()
            .find(|n| n.ends_with(".part"))
        {
            break p;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the export ended before its .part file was seen"
        );
        assert!(start.elapsed() < Duration::from_secs(60), "no .part file");
        std::thread::sleep(Duration::from_millis(5));
    };
    // Some bytes in it, then the signal.
    std::thread::sleep(Duration::from_millis(100));
    let killed = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{status:?}");
    let left = names_in(dir.path());
    assert!(!left.contains(&part), "{part} left behind: {left:?}");
    assert!(left.is_empty(), "{left:?}");
}

#[cfg(unix)]
#[test]
fn saved_files_get_the_same_mode_as_any_new_file() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let (ours, plain) = (dir.path().join("a.json"), dir.path().join("b.json"));
    udc_studio::io::safe_file::write_atomic(&ours, b"{}").unwrap();
    std::fs::write(&plain, b"{}").unwrap();
    let mode = |p: &std::path::Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    // Both are 0666 less the umask: not tempfile's private 0600.
    assert_eq!(mode(&ours), mode(&plain));
}
