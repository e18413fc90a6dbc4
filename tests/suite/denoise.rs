//! BM3D and CBM3D against the reference implementation BM3D's authors distribute (the Python
//! package `bm3d`, run by `tests/bm3d_check.py` on the very noisy image this test makes), and
//! the denoiser's own properties. Needs python3 with `bm3d` (the test command installs it).

use std::io::Write;
use std::process::Command;

use ndarray::Array2;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use udc_studio::core::denoise::{BlockTransform, Bm3dProfile, bm3d, bm3d_with};
use udc_studio::core::restore::quality::psnr_db_planes;
use udc_studio::core::{Progress, SimError};
use udc_studio::io::photo::testset::{load_testset_photo, testset_dir};

/// PSNR over every channel, peak 1.
fn psnr(a: &[Array2<f64>], b: &[Array2<f64>]) -> f64 {
    psnr_db_planes(a, b, 1.0).expect("same sizes")
}

/// Side of the centred crop the comparison runs on: large enough that the image borders (where
/// the two implementations pad differently) weigh little, small enough for the reference's
/// seconds per call.
const CROP_PX: usize = 192;

fn crop(name: &str) -> Vec<Array2<f64>> {
    let planes = load_testset_photo(&testset_dir().join(name)).expect("test-set photo");
    let (h, w) = planes[0].dim();
    let (y, x) = ((h - CROP_PX) / 2, (w - CROP_PX) / 2);
    planes
        .iter()
        .map(|p| Array2::from_shape_fn((CROP_PX, CROP_PX), |(r, c)| p[[y + r, x + c]]))
        .collect()
}

fn add_noise(clean: &[Array2<f64>], sigma: f64, seed: u64) -> Vec<Array2<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let normal = Normal::new(0.0, sigma).expect("finite σ");
    clean
        .iter()
        .map(|p| p.mapv(|v| v + normal.sample(&mut rng)))
        .collect()
}

/// Raw little-endian f64, row-major, channels last (what the script reads).
fn write_raw(path: &std::path::Path, planes: &[Array2<f64>]) {
    let (h, w) = planes[0].dim();
    let mut bytes = Vec::with_capacity(h * w * planes.len() * 8);
    for y in 0..h {
        for x in 0..w {
            for p in planes {
                bytes.extend_from_slice(&p[[y, x]].to_le_bytes());
            }
        }
    }
    std::fs::File::create(path)
        .and_then(|mut f| f.write_all(&bytes))
        .expect("write the raw image");
}

/// The reference's PSNR on each `(noisy, σ²)`, in one Python process.
fn reference_psnr_db(clean: &[Array2<f64>], runs: &[(Vec<Array2<f64>>, f64)]) -> Vec<f64> {
    let dir = tempfile::tempdir().expect("temp dir");
    let c = dir.path().join("clean.f64");
    write_raw(&c, clean);
    let (h, w) = clean[0].dim();
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/bm3d_check.py");
    let mut cmd = Command::new("python3");
    cmd.arg(script)
        .arg(&c)
        .args([h, w, clean.len()].map(|v| v.to_string()));
    for (i, (noisy, sigma2)) in runs.iter().enumerate() {
        let n = dir.path().join(format!("noisy{i}.f64"));
        write_raw(&n, noisy);
        cmd.arg(n).arg(sigma2.to_string());
    }
    let out = cmd
        .output()
        .expect("python3 with the bm3d package is required (pip install bm3d)");
    assert!(
        out.status.success(),
        "the reference BM3D failed (pip install bm3d): {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<f64> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).expect("JSON from the script");
            v["psnr_db"].as_f64().expect("psnr_db")
        })
        .collect();
    assert_eq!(lines.len(), runs.len(), "one result per noisy image");
    lines
}

/// Ours within 0.3 dB of the reference at σ 0.02, 0.1 and 0.2, on one noisy input each.
fn matches_reference(photo: &str, seed: u64) {
    let clean = crop(photo);
    let runs: Vec<(Vec<Array2<f64>>, f64)> = [0.02f64, 0.1, 0.2]
        .into_iter()
        .enumerate()
        .map(|(i, sigma)| (add_noise(&clean, sigma, seed + i as u64), sigma * sigma))
        .collect();
    let reference = reference_psnr_db(&clean, &runs);
    for ((noisy, sigma2), ref_db) in runs.iter().zip(reference) {
        let sigma = sigma2.sqrt();
        let ours = bm3d(noisy, *sigma2, &Progress::new()).expect("denoise");
        let ours_db = psnr(&ours, &clean);
        let noisy_db = psnr(noisy, &clean);
        eprintln!(
            "{photo} σ = {sigma}: noisy {noisy_db:.2} dB, ours {ours_db:.2}, reference {ref_db:.2}"
        );
        assert!(ours_db > noisy_db + 3.0, "{photo} σ {sigma}: no denoising");
        assert!(
            (ours_db - ref_db).abs() <= 0.3,
            "{photo} σ = {sigma}: ours {ours_db:.3} dB, reference {ref_db:.3} dB"
        );
    }
}

#[test]
fn grey_bm3d_matches_the_reference() {
    matches_reference("camera.png", 10);
}

#[test]
fn colour_cbm3d_matches_the_reference() {
    matches_reference("astronaut.png", 20);
}

#[test]
fn cbm3d_beats_denoising_each_channel_alone() {
    // Grouping on the luminance finds better groups than each noisy channel does alone.
    let clean = crop("coffee.png");
    let noisy = add_noise(&clean, 0.1, 3);
    let colour = bm3d(&noisy, 0.01, &Progress::new()).unwrap();
    let alone: Vec<Array2<f64>> = noisy
        .iter()
        .flat_map(|p| bm3d(std::slice::from_ref(p), 0.01, &Progress::new()).unwrap())
        .collect();
    let (c, a) = (psnr(&colour, &clean), psnr(&alone, &clean));
    assert!(c > a + 0.3, "CBM3D {c:.2} dB, per channel {a:.2} dB");
}

#[test]
fn the_reference_profile_beats_weaker_choices() {
    let clean = crop("camera.png");
    let noisy = add_noise(&clean, 0.1, 4);
    let full = psnr(&bm3d(&noisy, 0.01, &Progress::new()).unwrap(), &clean);
    let profile = Bm3dProfile {
        transform_ht: BlockTransform::Dct,
        ..Bm3dProfile::default()
    };
    let dct = psnr(
        &bm3d_with(&noisy, 0.01, &profile, &Progress::new()).unwrap(),
        &clean,
    );
    assert!(
        full > dct,
        "bior1.5 {full:.2} dB vs DCT {dct:.2} dB in the first stage"
    );
    let weaker = Bm3dProfile {
        lambda_ht: 1.0,
        ..Bm3dProfile::default()
    };
    let w = psnr(
        &bm3d_with(&noisy, 0.01, &weaker, &Progress::new()).unwrap(),
        &clean,
    );
    assert!(full > w, "λ = 3 {full:.2} dB should beat λ = 1 {w:.2} dB");
}

#[test]
fn the_result_does_not_depend_on_the_thread_count() {
    let clean = crop("camera.png");
    let noisy = add_noise(&clean, 0.05, 5);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| bm3d(&noisy, 0.0025, &Progress::new()).unwrap());
    let three = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap()
        .install(|| bm3d(&noisy, 0.0025, &Progress::new()).unwrap());
    assert_eq!(one, three);
}

#[test]
fn bad_input_is_refused_with_the_field_named() {
    let p = Progress::new();
    let img = Array2::from_elem((16, 16), 0.5);
    let field = |e: SimError| match e {
        SimError::InvalidSetting { path: field, .. } => field,
        other => panic!("expected an invalid field, got {other}"),
    };
    for s2 in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(
            field(bm3d(std::slice::from_ref(&img), s2, &p).unwrap_err()),
            "sigma2"
        );
    }
    assert_eq!(field(bm3d::<f64>(&[], 0.01, &p).unwrap_err()), "planes");
    let small = Array2::from_elem((7, 30), 0.5);
    assert_eq!(field(bm3d(&[small], 0.01, &p).unwrap_err()), "planes[0]");
    let mut nan = img.clone();
    nan[[3, 3]] = f64::NAN;
    assert_eq!(
        field(bm3d(&[img.clone(), nan], 0.01, &p).unwrap_err()),
        "planes[1]"
    );
    let other = Array2::from_elem((16, 17), 0.5);
    assert_eq!(
        field(bm3d(&[img.clone(), other], 0.01, &p).unwrap_err()),
        "planes[1]"
    );
    let bad = Bm3dProfile {
        max_group_ht: 12,
        ..Bm3dProfile::default()
    };
    assert_eq!(
        field(bm3d_with(&[img], 0.01, &bad, &p).unwrap_err()),
        "bm3d.max_group_ht"
    );
}

#[test]
fn cancelling_stops_the_denoiser() {
    let p = Progress::new();
    p.cancel();
    let img = Array2::from_elem((64, 64), 0.5);
    assert!(matches!(bm3d(&[img], 0.01, &p), Err(SimError::Cancelled)));
}
