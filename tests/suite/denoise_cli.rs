//! The `denoise` command's contract: the output is the input's kind, channels and size; `--json`
//! fields; PSNR against a reference rises; every bad input is one line with nothing written. And
//! the test set it is scored on: at least ten 512×512 photos, each with a licence.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};

use image::{ColorType, GrayImage, ImageBuffer, Luma, Rgb, Rgb32FImage};
use ndarray::Array2;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use udc_studio::io::photo::hdr::{ExrPrecision, write_exr};
use udc_studio::io::photo::planes::{ImageKind, read_planes};

use crate::common::run_cli as run;

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// A smooth clean scene in [0.1, 0.9]: a gradient, a bright disc and a dark bar.
fn clean_plane(w: usize, h: usize, phase: f64) -> Array2<f64> {
    Array2::from_shape_fn((h, w), |(y, x)| {
        let (fx, fy) = (x as f64 / w as f64, y as f64 / h as f64);
        let disc = ((fx - 0.5).powi(2) + (fy - 0.5).powi(2)).sqrt() < 0.25;
        let bar = (fy - 0.2).abs() < 0.05;
        let base = 0.3 + 0.3 * (fx + phase).sin().abs();
        if bar {
            0.1
        } else if disc {
            0.9
        } else {
            base
        }
    })
}

/// `plane` plus white Gaussian noise of variance `sigma2` (seeded), unclipped.
fn noisy(plane: &Array2<f64>, sigma2: f64, seed: u64) -> Array2<f64> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let normal = Normal::new(0.0, sigma2.sqrt()).expect("normal");
    plane.mapv(|v| v + normal.sample(&mut rng))
}

fn to_u8(v: f64) -> u8 {
    (255.0 * v.clamp(0.0, 1.0)).round() as u8
}

fn to_u16(v: f64) -> u16 {
    (65535.0 * v.clamp(0.0, 1.0)).round() as u16
}

/// Runs `denoise` and returns the JSON object it printed.
fn denoise_json(input: &Path, out: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "denoise",
        "--image",
        s(input),
        "--sigma2",
        "0.01",
        "--out",
        s(out),
        "--json",
    ];
    args.extend_from_slice(extra);
    let (ok, stdout, stderr) = run(&args);
    assert!(ok, "{stderr}");
    serde_json::from_str(stdout.trim()).expect("one JSON object")
}

#[test]
fn denoise_cli_png8_grey_stays_a_grey_png() {
    let dir = tempfile::tempdir().expect("tempdir");
    let input = dir.path().join("noisy.png");
    let plane = noisy(&clean_plane(40, 24, 0.0), 0.01, 1);
    GrayImage::from_fn(40, 24, |x, y| {
        Luma([to_u8(plane[[y as usize, x as usize]])])
    })
    .save(&input)
    .expect("save");
    let out = dir.path().join("clean.png");
    denoise_json(&input, &out, &[]);
    let img = image::open(&out).expect("a PNG");
    assert_eq!(img.color(), ColorType::L16, "grey in, 16-bit grey out");
    assert_eq!((img.width(), img.height()), (40, 24));
}

#[test]
fn denoise_cli_png16_rgb_stays_an_rgb_png() {
    let dir = tempfile::tempdir().expect("tempdir");
    let input = dir.path().join("noisy.png");
    let planes: Vec<Array2<f64>> = (0..3)
        .map(|c| noisy(&clean_plane(24, 32, c as f64), 0.01, 2 + c))
        .collect();
    ImageBuffer::<Rgb<u16>, _>::from_fn(24, 32, |x, y| {
        let at = |c: usize| to_u16(planes[c][[y as usize, x as usize]]);
        Rgb([at(0), at(1), at(2)])
    })
    .save(&input)
    .expect("save");
    let out = dir.path().join("clean.png");
    let v = denoise_json(&input, &out, &[]);
    assert_eq!(v["channels"], 3);
    let img = image::open(&out).expect("a PNG");
    assert_eq!(img.color(), ColorType::Rgb16);
    assert_eq!((img.width(), img.height()), (24, 32));
}

#[test]
fn denoise_cli_tiff_grey_and_float_rgb_give_16_bit_tiffs() {
    let dir = tempfile::tempdir().expect("tempdir");
    let plane = noisy(&clean_plane(32, 16, 0.0), 0.01, 5);
    let grey = dir.path().join("grey.tif");
    ImageBuffer::<Luma<u16>, _>::from_fn(32, 16, |x, y| {
        Luma([to_u16(plane[[y as usize, x as usize]])])
    })
    .save(&grey)
    .expect("save");
    let out = dir.path().join("grey_out.tiff");
    denoise_json(&grey, &out, &[]);
    let img = image::open(&out).expect("a TIFF");
    assert_eq!(img.color(), ColorType::L16);
    assert_eq!((img.width(), img.height()), (32, 16));

    let rgb = dir.path().join("float.tiff");
    Rgb32FImage::from_fn(32, 16, |x, y| {
        let v = plane[[y as usize, x as usize]] as f32;
        Rgb([v, 0.5 * v, 1.0 - v])
    })
    .save(&rgb)
    .expect("save");
    let out = dir.path().join("float_out.tif");
    denoise_json(&rgb, &out, &[]);
    let img = image::open(&out).expect("a TIFF");
    assert_eq!(img.color(), ColorType::Rgb16);
    assert_eq!((img.width(), img.height()), (32, 16));
}

#[test]
fn denoise_cli_exr_stays_float_exr_with_its_channels() {
    let dir = tempfile::tempdir().expect("tempdir");
    for (name, count) in [("y.exr", 1), ("rgb.exr", 3)] {
        let planes: Vec<Array2<f64>> = (0..count)
            .map(|c| noisy(&clean_plane(20, 28, c as f64), 0.01, 9 + c as u64))
            .collect();
        let input = dir.path().join(name);
        let refs: Vec<&Array2<f64>> = planes.iter().collect();
        write_exr(&input, &refs, ExrPrecision::Float).expect("write EXR");
        let out = dir.path().join(format!("out_{name}"));
        let v = denoise_json(&input, &out, &[]);
        assert_eq!(v["channels"], count);
        let back = read_planes(&out).expect("an EXR");
        assert_eq!(back.kind, ImageKind::Exr);
        assert_eq!(back.planes.len(), count, "{name}: channels kept");
        assert_eq!(back.size(), (20, 28));
    }
}

#[test]
fn denoise_cli_json_fields_and_psnr_rise_against_the_reference() {
    let dir = tempfile::tempdir().expect("tempdir");
    let clean: Vec<Array2<f64>> = (0..3).map(|c| clean_plane(64, 64, c as f64)).collect();
    let sigma2 = 0.01;
    let dirty: Vec<Array2<f64>> = clean
        .iter()
        .enumerate()
        .map(|(c, p)| noisy(p, sigma2, 20 + c as u64))
        .collect();
    // Float EXR keeps the noise exactly as drawn (no clipping at 0 and 1).
    let (clean_path, noisy_path) = (dir.path().join("clean.exr"), dir.path().join("noisy.exr"));
    write_exr(
        &clean_path,
        &clean.iter().collect::<Vec<_>>(),
        ExrPrecision::Float,
    )
    .expect("EXR");
    write_exr(
        &noisy_path,
        &dirty.iter().collect::<Vec<_>>(),
        ExrPrecision::Float,
    )
    .expect("EXR");
    let out = dir.path().join("out.exr");

    let v = denoise_json(&noisy_path, &out, &[]);
    for key in [
        "sigma2",
        "elapsed_ms",
        "width",
        "height",
        "channels",
        "psnr_db",
        "noisy_psnr_db",
        "out",
    ] {
        assert!(v.get(key).is_some(), "missing {key}: {v}");
    }
    assert_eq!(v["sigma2"], 0.01);
    assert_eq!(
        (v["width"].as_u64(), v["height"].as_u64()),
        (Some(64), Some(64))
    );
    assert!(
        v["psnr_db"].is_null() && v["noisy_psnr_db"].is_null(),
        "{v}"
    );
    assert!(v["out"].as_str().expect("path").ends_with("out.exr"));
    assert!(v["elapsed_ms"].as_f64().expect("number") >= 0.0);

    let v = denoise_json(&noisy_path, &out, &["--reference", s(&clean_path)]);
    let noisy_db = v["noisy_psnr_db"].as_f64().expect("number");
    let denoised_db = v["psnr_db"].as_f64().expect("number");
    // σ = 0.1 on a peak of 1 is 20 dB of noise; BM3D on a piecewise-smooth scene gains far more
    // than 3 dB.
    assert!((noisy_db - 20.0).abs() < 0.5, "{noisy_db}");
    assert!(denoised_db > noisy_db + 3.0, "{denoised_db} vs {noisy_db}");
}

/// Runs `denoise` expecting a refusal: one line naming `needle`, exit 1, no output, no temp file.
fn refused(dir: &Path, args: &[&str], out: &Path, needle: &str) {
    let before = listing(dir);
    let (code, _, stderr, _) = crate::common::run_cli_timed(args);
    assert_eq!(code, Some(1), "{args:?}: {stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{args:?}: {stderr}");
    assert!(
        stderr.contains(needle),
        "{args:?}: wanted {needle:?} in {stderr}"
    );
    assert!(
        !out.exists() || before.contains(&out.to_path_buf()),
        "{args:?} wrote {out:?}"
    );
    assert_eq!(listing(dir), before, "{args:?} left a file behind");
}

fn listing(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("list")
        .map(|e| e.expect("entry").path())
        .collect();
    v.sort();
    v
}

/// A PNG whose header says 0×0 pixels (no encoder writes one).
fn zero_by_zero_png() -> Vec<u8> {
    let mut ihdr = b"IHDR".to_vec();
    ihdr.extend_from_slice(&0u32.to_be_bytes());
    ihdr.extend_from_slice(&0u32.to_be_bytes());
    ihdr.extend_from_slice(&[8, 0, 0, 0, 0]);
    let mut bytes = b"\x89PNG\r\n\x1a\n".to_vec();
    bytes.extend_from_slice(&13u32.to_be_bytes());
    bytes.extend_from_slice(&ihdr);
    bytes.extend_from_slice(&crc32fast::hash(&ihdr).to_be_bytes());
    bytes
}

/// `denoise --image IMAGE --sigma2 SIGMA2 --out OUT`.
fn cmd<'a>(image: &'a str, sigma2: &'a str, out: &'a str) -> Vec<&'a str> {
    vec![
        "denoise", "--image", image, "--sigma2", sigma2, "--out", out,
    ]
}

#[test]
fn denoise_cli_bad_inputs_are_one_line_errors_and_write_nothing() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let good = d.join("good.png");
    GrayImage::from_fn(16, 16, |x, y| Luma([(x * 13 + y * 7) as u8]))
        .save(&good)
        .expect("save");
    let other_size = d.join("other.png");
    GrayImage::from_fn(16, 12, |x, _| Luma([x as u8]))
        .save(&other_size)
        .expect("save");
    let tiny = d.join("tiny.png");
    GrayImage::from_fn(4, 100, |_, y| Luma([y as u8]))
        .save(&tiny)
        .expect("save");
    let text = d.join("notes.png");
    std::fs::write(&text, "not an image\n").expect("write");
    let empty = d.join("empty.png");
    std::fs::write(&empty, zero_by_zero_png()).expect("write");
    let out = d.join("out.png");
    let (g, o) = (s(&good), s(&out));

    refused(d, &cmd(s(&text), "0.01", o), &out, "notes.png");
    refused(d, &cmd(s(&text), "0.01", o), &out, "not an image");
    refused(d, &cmd(s(&empty), "0.01", o), &out, "empty.png");
    refused(d, &cmd(s(&tiny), "0.01", o), &out, "at least 8×8");
    refused(
        d,
        &cmd(s(&d.join("missing.png")), "0.01", o),
        &out,
        "missing.png",
    );
    for bad in ["0", "-0.01", "nan", "inf", "1.5", "1e308", "1e-300"] {
        refused(d, &cmd(g, bad, o), &out, "--sigma2");
    }
    // `-inf` is not a number to clap, so it goes in the flag's own word.
    let minus_inf = ["denoise", "--image", g, "--sigma2=-inf", "--out", o];
    refused(d, &minus_inf, &out, "--sigma2");
    let mut with_ref = cmd(g, "0.01", o);
    with_ref.extend(["--reference", s(&other_size)]);
    refused(d, &with_ref, &out, "--reference");
    refused(
        d,
        &cmd(g, "0.01", s(&d.join("out.jpg"))),
        &d.join("out.jpg"),
        "unknown image kind",
    );
    refused(
        d,
        &cmd(g, "0.01", s(&d.join("out"))),
        &d.join("out"),
        "no extension",
    );
    let exr = d.join("out.exr");
    refused(
        d,
        &cmd(g, "0.01", s(&exr)),
        &exr,
        "the input is a PNG image",
    );
    let nowhere = d.join("no-such-folder").join("out.png");
    refused(d, &cmd(g, "0.01", s(&nowhere)), &nowhere, "no-such-folder");
    refused(d, &cmd(g, "0.01", g), &good, "also an input");
    let folder = d.join("folder.png");
    std::fs::create_dir(&folder).expect("mkdir");
    refused(d, &cmd(g, "0.01", s(&folder)), &folder, "is a directory");
}

#[test]
fn denoise_cli_help_names_the_kinds_and_the_scale() {
    let (ok, stdout, stderr) = run(&["denoise", "--help"]);
    assert!(ok, "{stderr}");
    for needle in ["--sigma2", "--reference", "[0, 1]", "EXR", "TIFF"] {
        assert!(stdout.contains(needle), "{needle} missing from {stdout}");
    }
}

#[test]
fn denoise_cli_testset_has_ten_licensed_512_photos() {
    use udc_studio::io::photo::testset::{load_testset_photo, testset_dir, testset_photos};
    let photos = testset_photos().expect("the test set is listed");
    assert!(
        photos.len() >= 10,
        "{} photos in {:?}",
        photos.len(),
        testset_dir()
    );
    let readme = std::fs::read_to_string(testset_dir().join("README.md")).expect("README");
    for p in &photos {
        let name = p.file_name().and_then(|n| n.to_str()).expect("name");
        assert_eq!(
            image::image_dimensions(p).expect("a PNG"),
            (512, 512),
            "{name}"
        );
        let row = readme
            .lines()
            .find(|l| l.starts_with(&format!("| `{name}` |")))
            .unwrap_or_else(|| panic!("{name} has no row in the README"));
        let licence = row.trim_end_matches('|').rsplit('|').next().unwrap_or("");
        assert!(
            ["CC0", "public domain", "No known copyright restrictions"]
                .iter()
                .any(|l| licence.contains(l)),
            "{name}: no licence in {row}"
        );
    }
    let grey = photos
        .iter()
        .find(|p| p.ends_with("camera.png"))
        .expect("camera");
    assert_eq!(
        load_testset_photo(grey).expect("load").len(),
        1,
        "grey stays one plane"
    );
    let colour = photos
        .iter()
        .find(|p| p.ends_with("astronaut.png"))
        .expect("astronaut");
    let planes = load_testset_photo(colour).expect("load");
    assert_eq!(planes.len(), 3);
    assert!(planes.iter().all(|p| p.dim() == (512, 512)));
    assert!(
        planes
            .iter()
            .flat_map(|p| p.iter())
            .all(|v| (0.0..=1.0).contains(v))
    );
}
