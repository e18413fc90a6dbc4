//! A damaged mask is never read as a design: an OASIS file's END record signature (CRC-32, or
//! checksum-32) is checked, and so is the SHA-256 an export writes beside every mask. Every
//! byte of a small export is corrupted in turn; each file is either refused or imports the
//! identical opening.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};

use udc_studio::core::Progress;
use udc_studio::core::design::Design;
use udc_studio::core::mask::{MaskRegion, MaskSpec};
use udc_studio::io::design::presets::load_preset;
use udc_studio::io::mask::{ExportOptions, MaskFormat, export_mask, import_opening};

use crate::common::run_cli;

/// The l2inv-random opening (a random tiling: the import undoes the axis pixel's orientation)
/// exported as one pixel in `format`, with its `.sha256` and manifest beside it.
fn exported(dir: &Path, format: MaskFormat) -> (Design, PathBuf) {
    let d = load_preset("l2inv-random").unwrap();
    let path = dir.join(format!("mask.{}", format.extension()));
    let o = ExportOptions {
        format,
        spec: MaskSpec {
            region: MaskRegion::PIXEL,
            ..MaskSpec::default()
        },
        deterministic: true,
        ..ExportOptions::default()
    };
    export_mask(&d, &o, &path, &Progress::new()).unwrap();
    (d, path)
}

/// Corrupts each byte of `path` in turn with each of `flips` (xor), imports every result as
/// the studio does, and returns the positions of the corrupted files that were read (each
/// with the identical opening) and how many were tried; panics on one that imports a different
/// opening or panics.
fn corrupt_every_byte(d: &Design, path: &Path, flips: &[u8]) -> (Vec<usize>, usize) {
    let want = import_opening(path, d).unwrap();
    let good = std::fs::read(path).unwrap();
    let (mut read, mut tried) = (Vec::new(), 0);
    for i in 0..good.len() {
        for &flip in flips {
            let mut bad = good.clone();
            bad[i] ^= flip;
            std::fs::write(path, &bad).unwrap();
            tried += 1;
            match import_opening(path, d) {
                Err(e) => {
                    let message = e.to_string();
                    assert!(!message.contains('\n'), "byte {i}: {message}");
                }
                Ok(cells) => {
                    assert_eq!(
                        cells, want,
                        "byte {i} ^ {flip:#04x} imported a different opening"
                    );
                    read.push(i);
                }
            }
        }
    }
    std::fs::write(path, &good).unwrap();
    (read, tried)
}

fn remove_sidecars(path: &Path) {
    for suffix in [".sha256", ".manifest.json", ".layers.txt"] {
        let mut name = path.file_name().unwrap().to_os_string();
        name.push(suffix);
        let _ = std::fs::remove_file(path.with_file_name(name));
    }
}

/// Without any sidecar, the OASIS file's own CRC-32 catches every one-byte change before its
/// signature (a CRC-32 detects every error burst of up to 32 bits). Only the END record's own
/// tail can change without a refusal, where a change turns the validation off (scheme 1 → 0)
/// and leaves the design as it was.
#[test]
fn an_oasis_file_damaged_anywhere_is_refused_by_its_own_crc() {
    let dir = tempfile::tempdir().unwrap();
    let (d, path) = exported(dir.path(), MaskFormat::Oas);
    remove_sidecars(&path);
    let len = std::fs::metadata(&path).unwrap().len() as usize;
    let (read, tried) = corrupt_every_byte(&d, &path, &[0x01, 0xff]);
    assert_eq!(tried, 2 * len);
    assert!(
        read.iter().all(|&i| i >= len - 256) && read.len() <= 4,
        "read despite a change: bytes {read:?} of {len}"
    );
    let bad = {
        let mut b = std::fs::read(&path).unwrap();
        let mid = b.len() / 2;
        b[mid] ^= 0x10;
        b
    };
    std::fs::write(&path, bad).unwrap();
    let e = import_opening(&path, &d).unwrap_err().to_string();
    assert!(e.contains("damaged") && e.contains("CRC-32"), "{e}");
}

/// Checksum-32 (scheme 2, the byte sum) is read too: the same file re-signed with it imports
/// the same opening, and a wrong sum is refused.
#[test]
fn an_oasis_checksum_32_signature_is_checked() {
    let dir = tempfile::tempdir().unwrap();
    let (d, path) = exported(dir.path(), MaskFormat::Oas);
    remove_sidecars(&path);
    let want = import_opening(&path, &d).unwrap();
    let mut b = std::fs::read(&path).unwrap();
    // The END record is the last 256 bytes: ..., the scheme (1 byte), the signature (4 bytes).
    let n = b.len();
    assert_eq!(b[n - 5], 1, "our exports sign with CRC-32");
    b[n - 5] = 2;
    let sum = b[..n - 4]
        .iter()
        .fold(0u32, |s, &x| s.wrapping_add(u32::from(x)));
    b[n - 4..].copy_from_slice(&sum.to_le_bytes());
    std::fs::write(&path, &b).unwrap();
    assert_eq!(import_opening(&path, &d).unwrap(), want);
    b[n - 4] ^= 1;
    std::fs::write(&path, &b).unwrap();
    let e = import_opening(&path, &d).unwrap_err().to_string();
    assert!(e.contains("checksum-32"), "{e}");
}

/// A GDSII file has no checksum of its own: the `.sha256` its export wrote beside it catches
/// every change, and without it a change reads as whatever the bytes now say.
#[test]
fn a_gdsii_file_damaged_anywhere_is_refused_by_its_sha256() {
    let dir = tempfile::tempdir().unwrap();
    let (d, path) = exported(dir.path(), MaskFormat::Gds);
    let (read, tried) = corrupt_every_byte(&d, &path, &[0x01]);
    assert!(
        read.is_empty(),
        "read despite a change: bytes {read:?} of {tried}"
    );
    // The manifest alone is enough.
    let mut sha = path.file_name().unwrap().to_os_string();
    sha.push(".sha256");
    std::fs::remove_file(path.with_file_name(sha)).unwrap();
    let mut b = std::fs::read(&path).unwrap();
    let last = b.len() - 1;
    b[last] ^= 0x01;
    std::fs::write(&path, &b).unwrap();
    let e = import_opening(&path, &d).unwrap_err().to_string();
    assert!(
        e.contains("manifest.json") && e.contains("--ignore-checksum"),
        "{e}"
    );
}

/// The command line refuses a mismatch in one line that names the way out, and
/// `--ignore-checksum` reads the file anyway; a sidecar that states no hash is refused too.
#[test]
fn import_refuses_a_checksum_mismatch_unless_told_to_ignore_it() {
    let dir = tempfile::tempdir().unwrap();
    let (_, path) = exported(dir.path(), MaskFormat::Gds);
    let out = dir.path().join("back.json");
    let (ok, _, stderr) = run_cli(&[
        "import",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "the untouched export imports: {stderr}");
    // The library's modification year (BGNLIB, right after the 6-byte HEADER record) moved
    // by one: still a valid file of the same design, so only the checksum can tell.
    let mut b = std::fs::read(&path).unwrap();
    assert_eq!(&b[6..10], &[0x00, 0x1c, 0x01, 0x02], "BGNLIB after HEADER");
    b[11] ^= 0x01;
    std::fs::write(&path, &b).unwrap();
    let (ok, _, stderr) = run_cli(&[
        "import",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("does not match its checksum") && stderr.contains("--ignore-checksum"),
        "{stderr}"
    );
    let (ok, _, stderr) = run_cli(&[
        "import",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--ignore-checksum",
    ]);
    assert!(ok, "{stderr}");
    let mut sha = path.file_name().unwrap().to_os_string();
    sha.push(".sha256");
    std::fs::write(path.with_file_name(sha), "not a hash\n").unwrap();
    let (ok, _, stderr) = run_cli(&[
        "import",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok && stderr.contains("states no SHA-256"), "{stderr}");
}
