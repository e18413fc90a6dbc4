//! HDR scenes: the committed StillLife, EXR (half, float, luminance) and Radiance round trips,
//! repaired samples, clear errors naming the path; downscaling and exposure.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};

use ndarray::Array2;
use udc_core::sensor::scene::percentile_of;
use udc_core::sensor::{Exposure, Scene, SensorSpec};
use udc_io::photo::hdr::{ExrPrecision, load_hdr, load_hdr_with_report, write_exr};

const STILL_LIFE: &str = concat!(
    concat!(env!("CARGO_MANIFEST_DIR"), "/../.."),
    "/assets/hdr/StillLife_620x423.exr"
);

fn ramp(h: usize, w: usize, k: f64) -> Array2<f64> {
    Array2::from_shape_fn((h, w), |(y, x)| {
        k * (1.0 + y as f64 * 3.0 + x as f64).powf(1.7)
    })
}

fn err_text(path: &Path) -> String {
    match load_hdr(path) {
        Ok(_) => panic!("{} loaded", path.display()),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_committed_still_life_is_a_half_float_hdr_scene() {
    let (scene, report) = load_hdr_with_report(Path::new(STILL_LIFE)).unwrap();
    assert_eq!(scene.dim(), (423, 620));
    assert_eq!(scene.planes.len(), 3);
    assert_eq!(report.format, "OpenEXR");
    assert_eq!(report.channels, ["R", "G", "B"]);
    assert!(report.notes().is_empty(), "{:?}", report.notes());
    let y = scene.luminance();
    assert!(y.iter().all(|v| v.is_finite() && *v >= 0.0));
    // High dynamic range: thousands between the bright and the dark end.
    let ratio = percentile_of(&y, 99.9) / percentile_of(&y, 1.0);
    assert!(ratio > 1e3, "p99.9 / p1 = {ratio}");
}

#[test]
fn exr_round_trips_in_half_and_float_rgb_and_luminance() {
    let dir = tempfile::tempdir().unwrap();
    let planes = [ramp(21, 34, 1e-3), ramp(21, 34, 2e-3), ramp(21, 34, 5e-4)];
    let refs: Vec<&Array2<f64>> = planes.iter().collect();
    for (precision, tol) in [(ExrPrecision::Float, 1e-7), (ExrPrecision::Half, 1e-3)] {
        let p = dir.path().join(format!("rgb-{precision:?}.exr"));
        write_exr(&p, &refs, precision).unwrap();
        let s = load_hdr(&p).unwrap();
        assert_eq!(s.planes.len(), 3);
        for (a, b) in s.planes.iter().zip(&planes) {
            for (x, y) in a.iter().zip(b) {
                assert!((x - y).abs() <= tol * y.abs(), "{precision:?}: {x} vs {y}");
            }
        }
        let p = dir.path().join(format!("y-{precision:?}.EXR"));
        write_exr(&p, &[&planes[0]], precision).unwrap();
        let (s, report) = load_hdr_with_report(&p).unwrap();
        assert_eq!(report.channels, ["Y"]);
        assert_eq!(s.planes.len(), 1);
        assert_eq!(s.luminance(), s.planes[0]);
    }
}

#[test]
fn radiance_hdr_round_trips_within_rgbe_precision() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("scene.hdr");
    let img = image::Rgb32FImage::from_fn(40, 30, |x, y| {
        let v = 0.01 * (1.0 + x as f32) * (1.0 + y as f32 * y as f32);
        image::Rgb([v, 0.5 * v, 2.0 * v])
    });
    image::DynamicImage::ImageRgb32F(img.clone())
        .save(&p)
        .unwrap();
    let (s, report) = load_hdr_with_report(&p).unwrap();
    assert_eq!(report.format, "Radiance");
    assert_eq!(s.dim(), (30, 40));
    // RGBE: 8-bit mantissas under one exponent per pixel, so each channel is good to 1/128 of
    // the pixel's brightest channel.
    for (y, x) in [(0, 0), (29, 39), (10, 20)] {
        let px = img.get_pixel(x as u32, y as u32).0;
        let brightest = f64::from(px.iter().copied().fold(0.0f32, f32::max));
        for (c, want) in px.iter().enumerate() {
            let want = f64::from(*want);
            let got = s.planes[c][[y, x]];
            assert!((got - want).abs() <= brightest / 128.0, "{got} vs {want}");
        }
    }
}

#[test]
fn negative_nan_and_infinite_samples_are_repaired_and_counted() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("odd.exr");
    let mut y = ramp(16, 16, 1.0);
    y[[0, 0]] = -2.0;
    y[[0, 1]] = -0.5;
    y[[1, 0]] = f64::NAN;
    y[[2, 2]] = f64::INFINITY;
    let largest = y
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    write_exr(&p, &[&y], ExrPrecision::Float).unwrap();
    let (s, report) = load_hdr_with_report(&p).unwrap();
    assert_eq!(
        (
            report.negative_samples,
            report.nan_samples,
            report.infinite_samples
        ),
        (2, 1, 1)
    );
    assert_eq!(report.notes().len(), 3);
    let s = &s.planes[0];
    assert_eq!((s[[0, 0]], s[[0, 1]], s[[1, 0]]), (0.0, 0.0, 0.0));
    assert!((s[[2, 2]] - largest).abs() < 1e-3 * largest);
    assert!(s.iter().all(|v| v.is_finite() && *v >= 0.0));
}

#[test]
fn bad_files_give_errors_naming_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let at = |name: &str| -> PathBuf { dir.path().join(name) };
    // Missing.
    let missing = at("missing.exr");
    let e = err_text(&missing);
    assert!(e.contains("missing.exr") && e.contains("cannot"), "{e}");
    // Unsupported extension.
    std::fs::write(at("photo.png"), b"not read").unwrap();
    let e = err_text(&at("photo.png"));
    assert!(e.contains("photo.png") && e.contains("unsupported"), "{e}");
    // Bytes that are not the format the extension says.
    std::fs::write(at("fake.exr"), b"#?RADIANCE\n").unwrap();
    let e = err_text(&at("fake.exr"));
    assert!(
        e.contains("fake.exr") && e.contains("not an OpenEXR"),
        "{e}"
    );
    std::fs::write(at("fake.hdr"), b"\x76\x2f\x31\x01garbage").unwrap();
    let e = err_text(&at("fake.hdr"));
    assert!(
        e.contains("fake.hdr") && e.contains("not a Radiance"),
        "{e}"
    );
    // A truncated EXR and a truncated Radiance file.
    let bytes = std::fs::read(STILL_LIFE).unwrap();
    std::fs::write(at("cut.exr"), &bytes[..bytes.len() / 3]).unwrap();
    let e = err_text(&at("cut.exr"));
    assert!(e.contains("cut.exr") && e.contains("OpenEXR"), "{e}");
    std::fs::write(at("head.exr"), &bytes[..40]).unwrap();
    let e = err_text(&at("head.exr"));
    assert!(e.contains("head.exr"), "{e}");
    std::fs::write(
        at("cut.hdr"),
        b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 40 +X 40\n\x02\x02",
    )
    .unwrap();
    let e = err_text(&at("cut.hdr"));
    assert!(e.contains("cut.hdr") && e.contains("Radiance"), "{e}");
    // An EXR without colour or luminance channels.
    let z = exr::prelude::AnyChannel::new("Z", exr::prelude::FlatSamples::F32(vec![1.0; 64]));
    let layer = exr::prelude::Layer::new(
        (8, 8),
        exr::prelude::LayerAttributes::default(),
        exr::prelude::Encoding::UNCOMPRESSED,
        exr::prelude::AnyChannels::sort(smallvec_of(z)),
    );
    use exr::prelude::WritableImage;
    exr::prelude::Image::from_layer(layer)
        .write()
        .to_file(at("depth.exr"))
        .unwrap();
    let e = err_text(&at("depth.exr"));
    assert!(
        e.contains("depth.exr") && e.contains("no R, G, B or Y"),
        "{e}"
    );
}

fn smallvec_of(
    c: exr::prelude::AnyChannel<exr::prelude::FlatSamples>,
) -> exr::prelude::SmallVec<[exr::prelude::AnyChannel<exr::prelude::FlatSamples>; 4]> {
    let mut v = exr::prelude::SmallVec::new();
    v.push(c);
    v
}

#[test]
fn downscaling_averages_areas_and_keeps_the_mean() {
    let plane = ramp(46, 64, 0.01);
    let scene = Scene {
        planes: vec![plane.clone()],
    };
    let half = scene.downscaled(32);
    assert_eq!(half.dim(), (23, 32));
    // Factor 2 exactly: each output pixel is a 2×2 mean.
    let want = (plane[[4, 6]] + plane[[4, 7]] + plane[[5, 6]] + plane[[5, 7]]) / 4.0;
    assert!((half.planes[0][[2, 3]] - want).abs() < 1e-12);
    // Any factor keeps the mean radiance.
    let odd = scene.downscaled(27);
    assert_eq!(odd.dim().1, 27);
    let (m0, m1) = (plane.mean().unwrap(), odd.planes[0].mean().unwrap());
    assert!((m1 / m0 - 1.0).abs() < 0.02, "{m0} vs {m1}");
    // A scene that fits is returned as it is.
    assert_eq!(scene.downscaled(100), scene);
}

#[test]
fn exposures_map_radiance_to_electrons() {
    let s = SensorSpec::table54();
    let y = ramp(30, 30, 1e-3);
    let k = Exposure::MeanFraction(0.05)
        .electrons_per_radiance(&y, &s)
        .unwrap();
    assert!(
        (k * y.mean().unwrap() - 50.0).abs() < 1e-9,
        "mean at 5 % of 1000 e⁻"
    );
    let k = Exposure::PercentileFill {
        percentile: 99.0,
        fill: 0.8,
    }
    .electrons_per_radiance(&y, &s)
    .unwrap();
    assert!((k * percentile_of(&y, 99.0) - 800.0).abs() < 1e-9);
    let k = Exposure::ElectronsPerUm2(200.0)
        .electrons_per_radiance(&y, &s)
        .unwrap();
    assert!((k - 50.0).abs() < 1e-12, "200 e⁻/µm² on a 0.25 µm² pixel");
    let bad = Exposure::PercentileFill {
        percentile: 120.0,
        fill: 0.8,
    }
    .validate()
    .unwrap_err()
    .to_string();
    assert!(bad.contains("exposure.percentile"), "{bad}");
    let black = Array2::zeros((20, 20));
    let e = Exposure::MeanFraction(0.05)
        .electrons_per_radiance(&black, &s)
        .unwrap_err()
        .to_string();
    assert!(e.contains("scene") && e.contains("black"), "{e}");
}
