//! The sensor previewer end to end (thesis §5.7, Table 5.4): on StillLife, varying gain and
//! binning beat the conventional sensor on worst-ROI SSIM; the maps and numbers are consistent;
//! a seed gives the same run on any thread count; bad settings name their field.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;

use ndarray::Array2;
use udc_core::sensor::gain::ratio_db;
use udc_core::sensor::{
    BinStrategy, GainStrategy, Held, PRESET_NAMES, PREVIEW_MAX_SIDE_PX, Scene, SensorSettings,
    SensorSpec, Strategy, peak_bytes, run, run_with,
};
use udc_core::{Progress, SimError};
use udc_io::photo::hdr::load_hdr;

const STILL_LIFE: &str = concat!(
    concat!(env!("CARGO_MANIFEST_DIR"), "/../.."),
    "/assets/hdr/StillLife_620x423.exr"
);

const TABLE54: [&str; 4] = [
    "const-gain/no-bin",
    "vary-gain/no-bin",
    "const-gain/vary-bin",
    "vary-gain/vary-bin",
];

/// A synthetic HDR scene: a smooth texture over six decades of brightness, left to right.
fn hdr_scene(h: usize, w: usize) -> Scene {
    let plane = Array2::from_shape_fn((h, w), |(y, x)| {
        let level = 10f64.powf(-4.0 + 6.0 * x as f64 / w as f64);
        level * (1.0 + 0.5 * ((x as f64 * 0.4).sin() * (y as f64 * 0.3).cos()))
    });
    Scene {
        planes: vec![plane],
    }
}

#[test]
fn still_life_varying_gain_and_binning_beat_the_conventional_sensor() {
    let scene = load_hdr(Path::new(STILL_LIFE)).unwrap();
    let settings = SensorSettings::default();
    let r = run(&scene, &settings, &Progress::new()).unwrap();
    let names: Vec<&str> = r.strategies.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, TABLE54);
    let s = |i: usize| &r.strategies[i];
    // Table 5.4's claim: the combination beats constant gain without binning (worst ROI).
    assert!(
        s(3).worst_roi_ssim > s(0).worst_roi_ssim + 0.05,
        "vary/vary {} vs const/no-bin {}",
        s(3).worst_roi_ssim,
        s(0).worst_roi_ssim
    );
    // And each half of it helps on its own, as in the table's average row.
    assert!(s(1).worst_roi_ssim > s(0).worst_roi_ssim);
    assert!(s(2).worst_roi_ssim > s(0).worst_roi_ssim);
    assert!(s(3).mean_ssim > s(0).mean_ssim && s(3).psnr_db > s(0).psnr_db);
    // The exposure: mean at 5 % of the 1000 e⁻ full well.
    assert!((r.electrons.mean().unwrap() - 50.0).abs() < 1e-6);
    assert_eq!((r.grid.rows, r.grid.cols), (4, 5));
    assert!(r.truth_display().iter().all(|v| (0.0..=1.0).contains(v)));
    for st in &r.strategies {
        assert_eq!(st.capture.dim(), (423, 620));
        assert_eq!(st.roi_ssim.dim(), (4, 5));
        let worst = st.roi_ssim.iter().copied().fold(f64::INFINITY, f64::min);
        assert_eq!(st.worst_roi_ssim, worst);
        assert!(st.mean_ssim >= st.worst_roi_ssim);
        assert!(st.display().iter().all(|v| (0.0..=1.0).contains(v)));
        assert!(st.bin_map.iter().all(|b| [1, 2, 4, 8].contains(b)));
        assert!(
            st.gain_map
                .iter()
                .all(|g| (1.0..=settings.sensor.max_gain).contains(&f64::from(*g)))
        );
        let saturated = st.saturated.iter().filter(|v| **v).count();
        assert_eq!(
            st.saturated_fraction,
            saturated as f64 / st.saturated.len() as f64
        );
        match st.strategy.gain {
            GainStrategy::Base => assert!(st.gain_map.iter().all(|g| *g == 1.0)),
            _ => assert!(st.gain_map.iter().any(|g| *g > 1.0)),
        }
        match st.strategy.bin {
            BinStrategy::None => assert!(st.bin_map.iter().all(|b| *b == 1)),
            _ => assert!(st.bin_map.iter().any(|b| *b > 1)),
        }
    }
    // Saturation stays rare: the lamps' flames, a fraction of a percent.
    assert!(s(0).saturated_fraction > 0.0 && s(3).saturated_fraction < 0.01);
}

#[test]
fn varying_gain_reaches_l_wc_over_sigma_pre_where_constant_gain_stays_at_sigma_post() {
    let scene = hdr_scene(128, 256);
    let settings = SensorSettings {
        roi_px: 32,
        ..SensorSettings::default()
    };
    let r = run(&scene, &settings, &Progress::new()).unwrap();
    let s = &settings.sensor;
    let (constant, varying) = (&r.strategies[0], &r.strategies[1]);
    let pre = ratio_db(s.full_well_e / s.sigma_pre_e);
    let post = ratio_db(s.full_well_e / s.sigma_post_e);
    assert!(
        (constant.dynamic_range_db - post).abs() < 0.2,
        "{}",
        constant.dynamic_range_db
    );
    assert!(
        (varying.dynamic_range_db - pre).abs() < 0.2,
        "{}",
        varying.dynamic_range_db
    );
    // Binning lowers the floor further.
    assert!(r.strategies[3].dynamic_range_db > varying.dynamic_range_db);
}

/// The hand-over sees every strategy in order, with the capture and maps `run` keeps; the run
/// keeps what the hand-over returns; a scene the run takes over gives the same numbers as one
/// it borrows; an error from the hand-over ends the run.
#[test]
fn run_with_hands_each_strategy_over_as_it_is_scored() {
    let rgb = hdr_scene(96, 140).planes.remove(0);
    let scene = Scene {
        planes: vec![rgb.clone(), rgb.mapv(|v| 0.5 * v), rgb.mapv(|v| 2.0 * v)],
    };
    let settings = SensorSettings {
        roi_px: 32,
        strategies: Strategy::all(),
        seed: 5,
        ..SensorSettings::default()
    };
    let kept = run(&scene, &settings, &Progress::new()).unwrap();
    let mut seen = Vec::new();
    let luminance = Scene {
        planes: vec![scene.luminance()],
    };
    let handed = run_with(
        luminance,
        &settings,
        &Progress::new(),
        Held::HandedOver,
        |s| {
            let k = &kept.strategies[seen.len()];
            assert_eq!(s.name, k.name);
            assert_eq!(s.capture, k.capture, "{}", s.name);
            assert_eq!(s.gain_map, k.gain_map, "{}", s.name);
            assert_eq!(s.bin_map, k.bin_map, "{}", s.name);
            assert_eq!(s.saturated, k.saturated, "{}", s.name);
            seen.push(s.name.clone());
            Ok::<_, SimError>((s.worst_roi_ssim, s.psnr_db))
        },
    )
    .unwrap();
    assert_eq!(seen.len(), settings.strategies.len());
    assert_eq!(handed.electrons, kept.electrons);
    for (h, k) in handed.strategies.iter().zip(&kept.strategies) {
        assert_eq!(*h, (k.worst_roi_ssim, k.psnr_db), "{}", k.name);
    }
    // The first hand-over's error ends the run: no second strategy is read.
    let mut calls = 0;
    let stopped = run_with(&scene, &settings, &Progress::new(), Held::Kept, |_| {
        calls += 1;
        Err::<(), _>(SimError::invalid("disk", "full"))
    });
    assert!(matches!(stopped, Err(SimError::InvalidSetting { .. })));
    assert_eq!(calls, 1);
    // One strategy held costs less than all of them, by the strategies' maps.
    let dim = (4096, 4096);
    let all = peak_bytes(dim, 3, &settings, Held::Kept);
    let one = peak_bytes(dim, 0, &settings, Held::HandedOver);
    assert!(one < 1 << 30 && all > 2 * one, "{one} vs {all}");
}

#[test]
fn a_seed_gives_the_same_run_on_any_thread_count() {
    let scene = hdr_scene(96, 140);
    let settings = SensorSettings {
        roi_px: 32,
        strategies: Strategy::all(),
        seed: 77,
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
        assert_eq!(x.capture, y.capture, "{}", x.name);
        assert_eq!(x.gain_map, y.gain_map, "{}", x.name);
        assert_eq!(x.roi_ssim, y.roi_ssim, "{}", x.name);
    }
    let other = run(
        &scene,
        &SensorSettings {
            seed: 78,
            ..settings.clone()
        },
        &Progress::new(),
    )
    .unwrap();
    assert_ne!(other.strategies[0].capture, a.strategies[0].capture);
}

#[test]
fn every_strategy_runs_and_the_baselines_behave() {
    let scene = hdr_scene(96, 192);
    let settings = SensorSettings {
        roi_px: 32,
        strategies: Strategy::all(),
        ..SensorSettings::default()
    };
    let r = run(&scene, &settings, &Progress::new()).unwrap();
    let by = |name: &str| r.strategies.iter().find(|s| s.name == name).unwrap();
    assert_eq!(r.strategies.len(), 8);
    // Maximum gain everywhere clips the bright side.
    assert!(by("max-gain/no-bin").saturated_fraction > 0.2);
    // Alternating rows: gains 1 and max on alternate rows.
    let alt = by("alt-gain/no-bin");
    assert_eq!(alt.gain_map[[0, 5]], 1.0);
    assert_eq!(f64::from(alt.gain_map[[1, 5]]), settings.sensor.max_gain);
    // Per pixel with η = 4: few saturations, gains spanning the range.
    let pp = by("pixel-gain/no-bin");
    assert!(pp.saturated_fraction < 0.05, "{}", pp.saturated_fraction);
    assert!(pp.gain_map.iter().any(|g| *g > 30.0));
    assert!(by("const-gain/bin-2").bin_map.iter().all(|b| *b == 2));
}

#[test]
fn the_preview_path_is_smaller_and_tells_the_same_story() {
    let scene = load_hdr(Path::new(STILL_LIFE)).unwrap();
    let small = scene.downscaled(PREVIEW_MAX_SIDE_PX / 2);
    assert_eq!(small.dim().1, PREVIEW_MAX_SIDE_PX / 2);
    let settings = SensorSettings::default().for_preview(scene.dim(), small.dim());
    assert_eq!(settings.roi_px, 66);
    let r = run(&small, &settings, &Progress::new()).unwrap();
    assert!(r.strategies[3].worst_roi_ssim > r.strategies[0].worst_roi_ssim);
}

#[test]
fn presets_carry_the_thesis_numbers() {
    let presets = SensorSpec::presets();
    let names: Vec<&str> = presets.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, PRESET_NAMES);
    for p in &presets {
        p.validate().unwrap();
    }
    let t = SensorSpec::named("table54").unwrap();
    assert_eq!(
        (
            t.unit_pixel_um,
            t.full_well_e,
            t.sigma_pre_e,
            t.sigma_post_e
        ),
        (0.5, 1000.0, 0.33, 3.31)
    );
    assert_eq!((t.adc_bits, t.black_level_fraction), (12, 0.05));
    let z5 = SensorSpec::named("NIKON-Z5").unwrap();
    assert_eq!(
        (z5.sigma_pre_e, z5.sigma_post_e, z5.max_gain),
        (0.11, 3.53, 512.0)
    );
    let n6p = SensorSpec::named("nexus-6p").unwrap();
    assert!((n6p.max_gain - 127.6).abs() < 1e-9);
    let bfs = SensorSpec::named("bfs-u3-200s6c").unwrap();
    assert!((bfs.max_gain - 22.387).abs() < 1e-3, "27 dB");
    let mono = SensorSpec::named("bfs-u3-16s2m").unwrap();
    assert!((mono.max_gain - 251.19).abs() < 1e-2, "48 dB");
    assert!(SensorSpec::named("nope").is_none());
    // Every preset simulates.
    let scene = hdr_scene(64, 96);
    for p in presets {
        let settings = SensorSettings {
            sensor: p,
            roi_px: 32,
            ..SensorSettings::default()
        };
        run(&scene, &settings, &Progress::new()).unwrap();
    }
}

fn field_of(settings: &SensorSettings, scene: &Scene) -> String {
    match run(scene, settings, &Progress::new()) {
        Err(SimError::InvalidSetting { path: field, .. }) => field.to_string(),
        other => panic!("expected a field error, got {:?}", other.map(|_| ())),
    }
}

#[test]
fn bad_settings_and_scenes_name_their_field() {
    let scene = hdr_scene(64, 64);
    let d = SensorSettings::default();
    let cases: Vec<(SensorSettings, &str)> = vec![
        (
            SensorSettings {
                roi_px: 4,
                ..d.clone()
            },
            "roi_px",
        ),
        (
            SensorSettings {
                eta: f64::NAN,
                ..d.clone()
            },
            "eta",
        ),
        (
            SensorSettings {
                snr_t: 0.0,
                ..d.clone()
            },
            "snr_t",
        ),
        (
            SensorSettings {
                gamma: 2.0,
                ..d.clone()
            },
            "gamma",
        ),
        (
            SensorSettings {
                sensor: SensorSpec {
                    full_well_e: -1.0,
                    ..SensorSpec::table54()
                },
                ..d.clone()
            },
            "sensor.full_well_e",
        ),
        (
            SensorSettings {
                sensor: SensorSpec {
                    max_gain: 0.5,
                    ..SensorSpec::table54()
                },
                ..d.clone()
            },
            "sensor.max_gain",
        ),
        (
            SensorSettings {
                exposure: udc_core::sensor::Exposure::PercentileFill {
                    percentile: 99.9,
                    fill: 0.0,
                },
                ..d.clone()
            },
            "exposure.fill",
        ),
        (
            SensorSettings {
                strategies: vec![Strategy {
                    gain: GainStrategy::PerPixel,
                    bin: BinStrategy::Uniform(2),
                }],
                ..d.clone()
            },
            "strategies[0].bin",
        ),
        (
            SensorSettings {
                strategies: vec![],
                ..d.clone()
            },
            "strategies",
        ),
    ];
    for (settings, field) in cases {
        assert_eq!(field_of(&settings, &scene), field);
    }
    let mut negative = scene.clone();
    negative.planes[0][[3, 3]] = -1.0;
    assert_eq!(field_of(&d, &negative), "scene.planes[0]");
    assert_eq!(field_of(&d, &Scene::default()), "scene");
    assert_eq!(field_of(&d, &hdr_scene(8, 64)), "scene");
    let black = Scene {
        planes: vec![Array2::zeros((32, 32))],
    };
    assert_eq!(field_of(&d, &black), "scene");
}

#[test]
fn a_cancelled_run_stops() {
    let progress = Progress::new();
    progress.cancel();
    let r = run(&hdr_scene(64, 64), &SensorSettings::default(), &progress);
    assert!(matches!(r, Err(SimError::Cancelled)));
}
