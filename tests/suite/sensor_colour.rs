//! The colour sensor (`Cfa::Rggb`): the RGGB mosaic takes each site's channel, same-colour
//! binning never mixes colours and bins the documented sites, the Malvar-He-Cutler demosaic
//! returns flat fields exactly and ramps exactly inside, a grey scene reads as on the
//! monochrome sensor, and Table 5.4's ordering holds in colour on StillLife.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use crate::common::Reach;
use ndarray::Array2;
use udc_studio::core::Progress;
use udc_studio::core::sensor::cfa::{mosaic, read_regions, rggb_channel};
use udc_studio::core::sensor::demosaic::demosaic_rggb;
use udc_studio::core::sensor::noise::{Adc, Frame};
use udc_studio::core::sensor::{
    BinMode, Cfa, RoiGrid, Scene, SensorSettings, SensorSpec, Strategy, run,
};
use udc_studio::io::photo::hdr::load_hdr;

const STILL_LIFE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/hdr/StillLife_620x423.exr"
);

const MODES: [BinMode; 3] = [
    BinMode::AnalogAdditive,
    BinMode::AnalogAverage,
    BinMode::Digital,
];

/// Table 5.4's sensor with a 20-bit ADC: quantisation (≈ 1e-3 e⁻) is far below the checks.
fn fine_adc_sensor() -> SensorSpec {
    SensorSpec {
        adc_bits: 20,
        ..SensorSpec::table54()
    }
}

/// A noise-free frame: the charge is the expected electrons, no read noise.
fn noiseless(electrons: &Array2<f64>) -> Frame {
    Frame {
        charge_e: electrons.mapv(|v| v as f32),
        post_noise_e: Array2::zeros(electrons.dim()),
    }
}

/// Reads `frame` with one gain and one bin side for every ROI.
fn read(frame: &Frame, roi_px: usize, bin: usize, mode: BinMode, adc: &Adc) -> Array2<f64> {
    let grid = RoiGrid::new(frame.charge_e.dim(), roi_px);
    let dim = (grid.rows, grid.cols);
    read_regions(
        frame,
        &grid,
        &Array2::from_elem(dim, 1.0),
        &Array2::from_elem(dim, bin),
        mode,
        udc_studio::core::sensor::AdditiveGain::Scaled,
        adc,
    )
    .estimate_e
}

#[test]
fn the_rggb_mosaic_takes_each_sites_channel() {
    let planes: [Array2<f64>; 3] = std::array::from_fn(|c| {
        Array2::from_shape_fn((7, 9), |(y, x)| (100 * c + 10 * y + x) as f64)
    });
    let m = mosaic([&planes[0], &planes[1], &planes[2]]);
    for ((y, x), v) in m.indexed_iter() {
        let want = match (y % 2, x % 2) {
            (0, 0) => 0,
            (1, 1) => 2,
            _ => 1,
        };
        assert_eq!(rggb_channel(y, x), want);
        assert_eq!(*v, planes[want][[y, x]], "site ({y}, {x})");
    }
    // Through `run`: the exposed mosaic is each channel times the exposure's electrons per
    // radiance, which is set on the luminance as for the monochrome sensor.
    let scene = Scene {
        planes: std::array::from_fn::<_, 3, _>(|c| {
            Array2::from_shape_fn((40, 48), |(y, x)| {
                0.2 + 0.3 * c as f64 + 0.01 * (y + x) as f64
            })
        })
        .into(),
    };
    let settings = SensorSettings {
        roi_px: 16,
        cfa: Cfa::Rggb,
        ..SensorSettings::default()
    };
    let r = run(&scene, &settings, &Progress::new()).unwrap();
    let truth = r.colour_truth.as_ref().unwrap();
    let k = r.electrons_per_radiance;
    for ((y, x), v) in truth.mosaic_e().indexed_iter() {
        let want = scene.planes[rggb_channel(y, x)][[y, x]] * k;
        // Kept in f32: to half an f32 ulp (the exposure itself is drawn from the f64 value).
        assert!(
            (f64::from(*v) - want).abs() <= 6e-8 * want,
            "({y}, {x}): {v} vs {want}"
        );
    }
    let mono = run(
        &scene,
        &SensorSettings {
            cfa: Cfa::None,
            ..settings
        },
        &Progress::new(),
    );
    assert_eq!(mono.unwrap().electrons_per_radiance, k);
    assert!(
        (r.electrons.mean().unwrap() - 50.0).abs() < 1e-9,
        "luminance mean at 5 %"
    );
}

/// A lit site, the ROI side, the bin side, and the rows and columns of the bin that holds it.
type BinCase = ((usize, usize), usize, usize, Vec<usize>, Vec<usize>);

#[test]
fn a_bin_of_side_n_takes_n_by_n_same_colour_sites_of_a_2n_super_block() {
    let adc = Adc::of(&fine_adc_sensor());
    // One lit site; its bin is `rows × cols`. ROIs of 15 px start the second ROI at (15, 15).
    let cases: [BinCase; 5] = [
        // Red at (4, 4) and (6, 6): the 2×2 red bin of the 4×4 super-block at (4, 4).
        ((4, 4), 16, 2, vec![4, 6], vec![4, 6]),
        ((6, 6), 16, 2, vec![4, 6], vec![4, 6]),
        // Blue: its phase starts at (1, 1), so its super-blocks start at odd rows and columns.
        ((5, 7), 16, 2, vec![5, 7], vec![5, 7]),
        // Red in the second ROI: its first red site is (16, 16).
        ((18, 16), 15, 2, vec![16, 18], vec![16, 18]),
        // Gb (odd row, even column) with 4×4 bins from (15, 16), the last one cut at row 30.
        ((27, 16), 15, 4, vec![23, 25, 27, 29], vec![16, 18, 20, 22]),
    ];
    for ((y, x), roi, n, rows, cols) in cases {
        let mut electrons = Array2::<f64>::zeros((30, 30));
        electrons[[y, x]] = 400.0;
        let share = 400.0 / (rows.len() * cols.len()) as f64;
        for mode in MODES {
            let est = read(&noiseless(&electrons), roi, n, mode, &adc);
            for ((yy, xx), v) in est.indexed_iter() {
                let expected = if rows.contains(&yy) && cols.contains(&xx) {
                    share
                } else {
                    0.0
                };
                assert!(
                    (v - expected).abs() < 0.01,
                    "{mode:?}, lit ({y}, {x}), ROI {roi}, bin {n}: ({yy}, {xx}) = {v}, want {expected}"
                );
            }
        }
    }
}

#[test]
fn same_colour_binning_never_mixes_colours() {
    let adc = Adc::of(&fine_adc_sensor());
    let (h, w) = (48, 64);
    // Red on the left (x < 40), blue on the right; no green.
    let red = Array2::from_shape_fn((h, w), |(_, x)| if x < 40 { 600.0 } else { 0.0 });
    let blue = Array2::from_shape_fn((h, w), |(_, x)| if x < 40 { 0.0 } else { 300.0 });
    let green = Array2::zeros((h, w));
    let frame = noiseless(&mosaic([&red, &green, &blue]));
    for roi in [16, 21, 32] {
        for n in [2, 4, 8] {
            for mode in MODES {
                let est = read(&frame, roi, n, mode, &adc);
                for ((y, x), v) in est.indexed_iter() {
                    let what = format!("{mode:?}, ROI {roi}, bin {n}, ({y}, {x}) = {v}");
                    match rggb_channel(y, x) {
                        1 => assert!(v.abs() < 0.01, "green got light: {what}"),
                        // A bin reaches at most 2n − 1 columns past its first site.
                        0 if x >= 40 + 2 * n => assert!(v.abs() < 0.01, "{what}"),
                        2 if x + 2 * n <= 40 => assert!(v.abs() < 0.01, "{what}"),
                        0 => assert!((-0.01..=600.01).contains(v), "{what}"),
                        _ => assert!((-0.01..=300.01).contains(v), "{what}"),
                    }
                }
            }
        }
    }
    // A flat field of three colours comes back per colour, whatever the bin and ROI phase.
    let flat: [Array2<f64>; 3] = [700.0, 250.0, 90.0].map(|v| Array2::from_elem((h, w), v));
    let frame = noiseless(&mosaic([&flat[0], &flat[1], &flat[2]]));
    for roi in [16, 17, 21] {
        for n in [1, 2, 4, 8] {
            for mode in MODES {
                let est = read(&frame, roi, n, mode, &adc);
                for ((y, x), v) in est.indexed_iter() {
                    let want = flat[rggb_channel(y, x)][[y, x]];
                    assert!(
                        (v - want).abs() < 0.01,
                        "{mode:?} ROI {roi} bin {n} ({y}, {x}) {v}"
                    );
                }
            }
        }
    }
}

#[test]
fn the_demosaic_returns_a_flat_field_exactly_and_ramps_inside() {
    for (h, w) in [(11, 13), (16, 16), (24, 37)] {
        let flat = [0.7, 0.25, 0.1].map(|v| Array2::from_elem((h, w), v));
        let rgb = demosaic_rggb(&mosaic([&flat[0], &flat[1], &flat[2]]));
        for (c, plane) in rgb.iter().enumerate() {
            for ((y, x), v) in plane.indexed_iter() {
                let want = flat[c][[y, x]];
                assert!(
                    (v - want).abs() <= 1e-15,
                    "{h}×{w} channel {c} ({y}, {x}) {v}"
                );
            }
        }
    }
    // Linear ramps: the gradient correction vanishes, bilinear is exact two sites from the edge.
    let (h, w) = (32, 40);
    let ramp = |a: f64, by: f64, bx: f64| {
        Array2::from_shape_fn((h, w), |(y, x)| a + by * y as f64 + bx * x as f64)
    };
    let truth = [
        ramp(10.0, 0.5, 1.0),
        ramp(20.0, -0.2, 0.7),
        ramp(30.0, 0.3, -0.4),
    ];
    let rgb = demosaic_rggb(&mosaic([&truth[0], &truth[1], &truth[2]]));
    let mut edge_err = 0.0f64;
    for c in 0..3 {
        for ((y, x), v) in rgb[c].indexed_iter() {
            let err = (v - truth[c][[y, x]]).abs();
            if (2..h - 2).contains(&y) && (2..w - 2).contains(&x) {
                assert!(
                    err < 1e-12,
                    "channel {c} ({y}, {x}): {v} vs {}",
                    truth[c][[y, x]]
                );
            } else {
                edge_err = edge_err.max(err);
            }
        }
    }
    // At the edge the mirror bends the ramp (measured: 1.58 steps of the steepest slope, 1).
    assert!(edge_err > 0.0 && edge_err <= 2.0, "{edge_err}");
    // Smooth colour: a Gaussian blob per channel, each elsewhere and of its own width (σ 12 to
    // 20 px), so the channels do not move together. Measured worst errors: 1.0 % of the swing
    // two sites in from the edge, 2.5 % at the edge, where the mirror bends the slopes.
    let blob = |cx: f64, cy: f64, sigma: f64| {
        Array2::from_shape_fn((64, 64), |(y, x)| {
            let r2 = (x as f64 - cx).powi(2) + (y as f64 - cy).powi(2);
            0.1 + 0.8 * (-r2 / (2.0 * sigma * sigma)).exp()
        })
    };
    let truth = [
        blob(20.0, 30.0, 16.0),
        blob(40.0, 32.0, 20.0),
        blob(32.0, 44.0, 12.0),
    ];
    let rgb = demosaic_rggb(&mosaic([&truth[0], &truth[1], &truth[2]]));
    for c in 0..3 {
        let (mut inside, mut all) = (0.0f64, 0.0f64);
        for ((y, x), v) in rgb[c].indexed_iter() {
            let err = (v - truth[c][[y, x]]).abs();
            all = all.max(err);
            if (2..62).contains(&y) && (2..62).contains(&x) {
                inside = inside.max(err);
            }
        }
        assert!(
            inside < 0.015 * 0.8 && all < 0.03 * 0.8,
            "channel {c}: {inside}, {all}"
        );
    }
}

#[test]
fn the_demosaic_matches_an_independent_implementation_inside() {
    use demosaic::{Algorithm, CfaPattern};
    let (h, w) = (30, 44);
    let m = Array2::from_shape_fn((h, w), |(y, x)| {
        50.0 + 40.0 * ((x as f64 * 0.37).sin() + (y as f64 * 0.21).cos()) + (x * y % 7) as f64
    });
    let ours = demosaic_rggb(&m);
    let input: Vec<f32> = m.iter().map(|v| *v as f32).collect();
    let mut theirs = vec![0.0f32; 3 * h * w];
    demosaic::demosaic(
        &input,
        w,
        h,
        &CfaPattern::bayer_rggb(),
        Algorithm::Mhc,
        &mut theirs,
    )
    .unwrap();
    // Their edge sites repeat across colours; two sites in, both read the same taps.
    for c in 0..3 {
        for y in 2..h - 2 {
            for x in 2..w - 2 {
                let t = f64::from(theirs[c * h * w + y * w + x]);
                let o = ours[c][[y, x]];
                assert!(
                    (o - t).abs() < 1e-4 * o.abs().max(1.0),
                    "channel {c} ({y}, {x}): {o} vs {t}"
                );
            }
        }
    }
}

#[test]
fn a_grey_scene_reads_as_on_the_monochrome_sensor() {
    let plane = Array2::from_shape_fn((64, 96), |(y, x)| {
        10f64.powf(-3.0 + 4.0 * x as f64 / 96.0) * (1.0 + 0.3 * (y as f64 * 0.5).sin())
    });
    let scene = Scene {
        planes: vec![plane],
    };
    let mono = SensorSettings {
        roi_px: 32,
        strategies: Strategy::all(),
        ..SensorSettings::default()
    };
    let colour = SensorSettings {
        cfa: Cfa::Rggb,
        ..mono.clone()
    };
    let (m, c) = (
        run(&scene, &mono, &Progress::new()).unwrap(),
        run(&scene, &colour, &Progress::new()).unwrap(),
    );
    assert!(m.colour_truth.is_none() && m.strategies.iter().all(|s| s.colour.is_none()));
    assert_eq!(m.cfa, Cfa::None);
    assert_eq!(c.cfa, Cfa::Rggb);
    // Same light at every site, same frame: the unbinned, constant-gain readouts are equal
    // bit for bit, and the demosaic of a grey mosaic gives back its luminance.
    assert_eq!(c.electrons, m.electrons);
    let narrow = |a: &ndarray::Array2<f64>| a.mapv(|v| v as f32);
    assert_eq!(
        c.colour_truth.as_ref().unwrap().mosaic_e(),
        narrow(&m.electrons)
    );
    for name in ["const-gain/no-bin", "max-gain/no-bin"] {
        let by = |r: &udc_studio::core::sensor::SensorRun| {
            r.strategies
                .iter()
                .find(|s| s.name == name)
                .unwrap()
                .clone()
        };
        let (sm, sc) = (by(&m), by(&c));
        assert_eq!(
            sc.colour.as_ref().unwrap().mosaic_e(),
            narrow(&sm.capture),
            "{name}"
        );
    }
    for s in &c.strategies {
        let colour = s.colour.as_ref().unwrap();
        assert!(
            colour
                .display_rgb(&s.tone)
                .iter()
                .all(|p| p.iter().all(|v| (0.0..=1.0).contains(v)))
        );
        for ch in &colour.channels {
            assert!(
                ch.worst_roi_ssim <= ch.mean_ssim && ch.mean_ssim <= 1.0,
                "{}",
                s.name
            );
            assert!(ch.psnr_db.is_finite());
        }
    }
}

#[test]
fn table_5_4_ordering_holds_in_colour_on_still_life() {
    let scene = load_hdr(Path::new(STILL_LIFE)).unwrap();
    assert_eq!(scene.planes.len(), 3);
    let settings = SensorSettings {
        cfa: Cfa::Rggb,
        ..SensorSettings::default()
    };
    let r = run(&scene, &settings, &Progress::new()).unwrap();
    let worst: Vec<f64> = r.strategies.iter().map(|s| s.worst_roi_ssim).collect();
    let s = |i: usize| &r.strategies[i];
    // Table 5.4's claim in luminance of the demosaiced capture: the combination beats the
    // conventional sensor, each half helps on its own, and no column beats the combination
    // by more than seed noise (±0.005 on the worst ROI).
    assert!(worst[3] > worst[0] + 0.05, "{worst:?}");
    assert!(worst[1] > worst[0] && worst[2] > worst[0], "{worst:?}");
    assert!(worst.iter().all(|w| *w <= worst[3] + 0.005), "{worst:?}");
    assert!(s(3).mean_ssim > s(0).mean_ssim && s(3).psnr_db > s(0).psnr_db);
    // Per channel too, the combination beats the conventional sensor on the worst ROI.
    for c in 0..3 {
        let ch = |i: usize| s(i).colour.as_ref().unwrap().channels[c];
        assert!(ch(3).worst_roi_ssim > ch(0).worst_roi_ssim, "channel {c}");
    }
    // The exposure is the monochrome sensor's: the luminance mean at 5 % of the full well.
    assert!((r.electrons.mean().unwrap() - 50.0).abs() < 1e-6);
}

#[test]
fn the_previewer_shows_colour_captures_and_channel_scores() {
    use crate::common;
    use egui_kittest::kittest::Queryable;
    use udc_studio::app::WorkspaceId;
    use udc_studio::app::sensor::{CompareMode, SensorView};

    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, std::time::Duration::from_secs(600));
    h.state_mut().set_workspace(WorkspaceId::Sensor);
    h.step();
    assert!(h.query_by_label("Colour filter").is_some());
    let scene = load_hdr(Path::new(STILL_LIFE)).unwrap().downscaled(160);
    h.state_mut().sensor_mut().set_scene("small", scene);
    h.state_mut().sensor_mut().settings_mut().roi_px = 32;
    h.state_mut().sensor_mut().settings_mut().cfa = Cfa::Rggb;
    common::step_until(&mut h, "the colour run", |app| {
        app.sensor().is_up_to_date() && app.sensor().shown().is_some_and(|s| s.run.cfa == Cfa::Rggb)
    });
    let run = h.state().sensor().shown().unwrap().run.clone();
    assert!(run.colour_truth.is_some());
    assert!(h.query_by_label_contains("Per channel").is_some());
    // Each channel's worst-ROI SSIM is on screen.
    let first = run.strategies[0].colour.as_ref().unwrap().channels[0];
    let shown = format!("{:.4}, {:.1}", first.worst_roi_ssim, first.psnr_db);
    assert!(h.query_all_by_label(&shown).next().is_some(), "{shown}");
    // The split comparison draws in colour too.
    h.state_mut()
        .sensor_mut()
        .set_compare(0, 3, CompareMode::Split, 0.5);
    h.state_mut().sensor_mut().show(SensorView::Compare);
    h.step();
    h.step();
    assert!(h.query_by_label_contains("A: worst ROI SSIM").is_some());
}

#[test]
fn every_strategy_runs_on_the_bayer_sensor() {
    // Six decades of grey light from left to right; a deep red ROI where the grey gets high gain.
    let (h, w) = (96, 192);
    let level = |x: usize| 10f64.powf(-4.0 + 6.0 * x as f64 / w as f64);
    let red_patch = |y: usize, x: usize| y < 32 && (96..128).contains(&x);
    let plane = |c: usize| {
        Array2::from_shape_fn((h, w), |(y, x)| {
            let tex = 1.0 + 0.5 * ((x as f64 * 0.4).sin() * (y as f64 * 0.3).cos());
            match (red_patch(y, x), c) {
                (true, 0) => 4.0 * level(x),
                (true, _) => 0.02 * level(x),
                _ => level(x) * tex,
            }
        })
    };
    let scene = Scene {
        planes: vec![plane(0), plane(1), plane(2)],
    };
    let settings = SensorSettings {
        roi_px: 32,
        strategies: Strategy::all(),
        cfa: Cfa::Rggb,
        ..SensorSettings::default()
    };
    let r = run(&scene, &settings, &Progress::new()).unwrap();
    let by = |name: &str| r.strategies.iter().find(|s| s.name == name).unwrap();
    let max_gain = settings.sensor.max_gain;
    // Alternating gains in row pairs, so each colour has rows at both gains.
    let alt = by("alt-gain/no-bin");
    let gains: Vec<f64> = (0..6).map(|y| f64::from(alt.gain_map[[y, 5]])).collect();
    assert_eq!(gains, [1.0, 1.0, max_gain, max_gain, 1.0, 1.0]);
    // Per pixel: the first site of each colour in a row is read at base gain.
    let pp = by("pixel-gain/no-bin");
    assert!((0..h).all(|y| pp.gain_map[[y, 0]] == 1.0 && pp.gain_map[[y, 1]] == 1.0));
    assert!(pp.gain_map.iter().any(|g| *g > 30.0));
    assert!(pp.saturated_fraction < 0.05, "{}", pp.saturated_fraction);
    // The ROI gain comes from the brightest colour: the red patch's red sites clip no more
    // than eq. 5.3's η = 2 allows (≈ 2.2 % at the ROI's brightest block, less elsewhere); a
    // luminance snapshot would see a fifth of the red and give it the grey's gain.
    let vary = by("vary-gain/no-bin");
    let (mut red_sites, mut red_clipped) = (0usize, 0usize);
    for y in (0..32).step_by(2) {
        for x in (96..128).step_by(2) {
            red_sites += 1;
            red_clipped += usize::from(vary.saturated[[y, x]]);
        }
    }
    let clipped = red_clipped as f64 / red_sites as f64;
    assert!(
        clipped < 0.06,
        "{red_clipped} of {red_sites} red sites clipped"
    );
    assert!(
        vary.gain_map[[0, 110]] < 0.6 * vary.gain_map[[40, 110]],
        "the red ROI's gain {} vs the grey's {}",
        vary.gain_map[[0, 110]],
        vary.gain_map[[40, 110]]
    );
    assert!(by("max-gain/no-bin").saturated_fraction > 0.2);
    assert!(by("const-gain/bin-2").bin_map.iter().all(|b| *b == 2));
    for s in &r.strategies {
        let c = s.colour.as_ref().unwrap();
        assert_eq!(c.mosaic_e().dim(), (h, w));
        assert!(s.worst_roi_ssim <= s.mean_ssim, "{}", s.name);
    }
}

#[test]
fn a_colour_run_is_the_same_on_any_thread_count() {
    let scene = Scene {
        planes: (0..3)
            .map(|c| {
                Array2::from_shape_fn((70, 90), |(y, x)| {
                    10f64.powf(-3.0 + 4.0 * x as f64 / 90.0) * (1.0 + 0.2 * c as f64)
                        + 0.01 * ((y * 7 + x * 3) % 11) as f64
                })
            })
            .collect(),
    };
    let settings = SensorSettings {
        roi_px: 24,
        strategies: Strategy::all(),
        cfa: Cfa::Rggb,
        seed: 5,
        ..SensorSettings::default()
    };
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run(&scene, &settings, &Progress::new()).unwrap())
    };
    let (a, b) = (on(1), on(3));
    for (x, y) in a.strategies.iter().zip(&b.strategies) {
        let (cx, cy) = (x.colour.as_ref().unwrap(), y.colour.as_ref().unwrap());
        assert_eq!(cx.mosaic_e(), cy.mosaic_e(), "{}", x.name);
        assert_eq!(cx.rgb_e, cy.rgb_e, "{}", x.name);
        assert_eq!(x.gain_map, y.gain_map, "{}", x.name);
        assert_eq!(x.roi_ssim, y.roi_ssim, "{}", x.name);
    }
}
