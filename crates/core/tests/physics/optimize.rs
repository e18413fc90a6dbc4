//! The opening optimizer (thesis §3.4.2, conventions.md §6): its model agrees with `analyze`, its
//! gradients agree with finite differences, and a run does what the thesis says it does.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::ops::ControlFlow;

use ndarray::Array2;
use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_core::design::{Design, TilingMode};
use udc_core::display::aperture::{CellMap, Display, Extent, effective_cells};
use udc_core::optimize::{
    DataSet, LossWeights, Objective, OptimizeSettings, Relaxation, binarise, optimize,
};
use udc_core::psf::route::PsfRoute;
use udc_core::{Progress, SimError};
use udc_io::design::presets;

fn toled(tiling: TilingMode) -> Design {
    let mut d = presets::load_preset("toled-150dpi").unwrap();
    d.tiling.mode = tiling;
    d
}

fn small(mut d: Design) -> Design {
    d.optics = common::small_optics();
    d
}

/// A deterministic pseudo-random sequence in [0, 1).
fn uniform(seed: u64, n: usize) -> Vec<f64> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect()
}

#[test]
fn cell_map_reproduces_the_rasterised_display() {
    let d = toled(TilingMode::RandomD4);
    let cells = effective_cells(&d.opening);
    let display = Display::from_design(&d, &cells);
    let extent = Extent::Pupil {
        diameter_um: d.optics.pupil_diameter_um(),
    };
    let field = udc_core::display::aperture::rasterise(&display, extent, 8.0);
    let map = CellMap::new(&display, extent, 8.0);
    let flat: Vec<f64> = cells.iter().flatten().copied().collect();
    let values = map.apply(&flat);
    let dense = field.to_dense(600);
    let mut checked = 0;
    for ((y, x), v) in map.iy.iter().zip(&map.ix).zip(&values) {
        assert_eq!(dense[(y + 300) as usize][(x + 300) as usize], *v);
        checked += 1;
    }
    let nonzero: usize = field
        .rows
        .iter()
        .map(|r| r.values.iter().filter(|v| **v != 0.0).count())
        .sum();
    assert_eq!(values.iter().filter(|v| **v != 0.0).count(), nonzero);
    assert!(checked > 190_000, "the whole pupil is mapped ({checked})");
}

#[test]
fn model_loss_and_psfs_equal_the_analysis() {
    for tiling in [TilingMode::Repeat, TilingMode::RandomD4] {
        let d = toled(tiling);
        let a = analyze_with(
            &d,
            &AnalyzeOptions {
                quality: Quality::Full,
                expected_psf: false,
            },
            &Progress::new(),
        )
        .unwrap();
        let obj = Objective::new(
            &d,
            Quality::Full,
            LossWeights::default(),
            Relaxation::Sigmoid,
            None,
            &PsfRoute::Auto,
        )
        .unwrap();
        let flat: Vec<f64> = d.opening.cells.iter().flatten().copied().collect();
        let fwd = obj.model.forward(&flat).unwrap();
        assert!(
            (fwd.loss_inv - a.invertibility_loss).abs() < 1e-9,
            "{tiling:?}: {} vs {}",
            fwd.loss_inv,
            a.invertibility_loss
        );
        for (p, c) in fwd.psfs().iter().zip(&a.channels) {
            let diff = (p - &c.psf).mapv(f64::abs).sum();
            assert!(diff < 1e-9, "{tiling:?} {}: PSF differs by {diff}", c.name);
        }
    }
}

/// Central differences of the total loss against the analytic gradient, for a few logits.
fn gradient_check(design: &Design, weights: LossWeights, data: Option<&DataSet>) {
    let obj = Objective::new(
        design,
        Quality::Full,
        weights,
        Relaxation::Sigmoid,
        data,
        &PsfRoute::Auto,
    )
    .unwrap();
    let n2 = design.opening.n().pow(2);
    let logits: Vec<f64> = uniform(7, n2).iter().map(|u| 3.0 * u - 1.5).collect();
    let c = 0.4;
    let step = obj.step(&logits, c).unwrap();
    let h = 1e-5;
    let mut worst: f64 = 0.0;
    let scale = step.grad_logits.iter().fold(0.0f64, |m, g| m.max(g.abs()));
    assert!(scale > 0.0, "the gradient is not zero");
    for i in [0, 3, n2 / 2, n2 / 3, n2 - 1, 100 % n2] {
        let mut up = logits.clone();
        up[i] += h;
        let mut down = logits.clone();
        down[i] -= h;
        let fd = (obj.step(&up, c).unwrap().loss_total - obj.step(&down, c).unwrap().loss_total)
            / (2.0 * h);
        let err = (fd - step.grad_logits[i]).abs() / scale;
        worst = worst.max(err);
        assert!(
            err < 1e-4,
            "logit {i}: analytic {} vs finite difference {fd}",
            step.grad_logits[i]
        );
    }
    eprintln!("worst relative gradient error {worst:.2e}");
}

#[test]
fn invertibility_gradient_matches_finite_differences() {
    let weights = LossWeights {
        area: 0.0,
        inv: 1.0,
        data: 0.0,
    };
    gradient_check(&small(toled(TilingMode::RandomD4)), weights, None);
    gradient_check(&small(toled(TilingMode::Repeat)), weights, None);
}

#[test]
fn multi_wavelength_and_area_gradients_match_finite_differences() {
    let mut d = small(toled(TilingMode::Random4));
    d.channels[1].wavelengths_nm = vec![500.0, 530.0, 560.0];
    d.channels[1].weights = vec![0.25, 0.5, 0.25];
    gradient_check(&d, LossWeights::default(), None);
}

#[test]
fn data_loss_gradient_matches_finite_differences() {
    // Smooth synthetic "photos": a few blobs and edges per channel.
    let photo = |k: f64| -> Vec<Array2<f64>> {
        (0..3)
            .map(|c| {
                Array2::from_shape_fn((160, 160), |(y, x)| {
                    let (y, x) = (y as f64, x as f64);
                    let blob =
                        (-((x - 60.0 - 10.0 * k).powi(2) + (y - 80.0).powi(2)) / 300.0).exp();
                    let edge = if x + 0.5 * y > 120.0 + 5.0 * c as f64 {
                        0.4
                    } else {
                        0.1
                    };
                    blob * 0.5 + edge
                })
            })
            .collect()
    };
    let data = DataSet::new(&[photo(0.0), photo(1.0)], 3, 128).unwrap();
    let weights = LossWeights {
        area: 0.0,
        inv: 0.0,
        data: 1.0,
    };
    gradient_check(&small(toled(TilingMode::RandomD4)), weights, Some(&data));
}

#[test]
fn binarise_keeps_the_target_area_and_the_strongest_cells() {
    let relaxed = uniform(3, 441);
    let cells = binarise(&relaxed, 21, 0.2);
    let open: Vec<usize> = (0..441).filter(|&i| cells[i / 21][i % 21] == 1.0).collect();
    assert_eq!(open.len(), 88);
    let weakest_open = open
        .iter()
        .map(|&i| relaxed[i])
        .fold(f64::INFINITY, f64::min);
    let strongest_closed = (0..441)
        .filter(|i| !open.contains(i))
        .map(|i| relaxed[i])
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(weakest_open >= strongest_closed);
}

#[test]
fn settings_reject_nonsense() {
    let bad = [
        OptimizeSettings {
            epochs: 0,
            ..Default::default()
        },
        OptimizeSettings {
            target_open_fraction: f64::NAN,
            ..Default::default()
        },
        OptimizeSettings {
            learning_rate: -1.0,
            ..Default::default()
        },
        OptimizeSettings {
            beta1: 1.0,
            ..Default::default()
        },
    ];
    let d = small(toled(TilingMode::Repeat));
    for s in bad {
        let err = optimize(&d, &s, None, &PsfRoute::Auto, &Progress::new(), |_| {
            ControlFlow::Continue(())
        })
        .unwrap_err();
        assert!(matches!(err, SimError::InvalidSetting { .. }), "{err}");
    }
}

#[test]
fn area_schedule_follows_physics_md() {
    let s = OptimizeSettings::default();
    assert_eq!(s.area_target(0), 1.0);
    assert_eq!(s.area_target(4), 1.0);
    assert!((s.area_target(5) - 0.95).abs() < 1e-12);
    assert!((s.area_target(79) - 0.25).abs() < 1e-12);
    assert!((s.area_target(80) - 0.2).abs() < 1e-12);
    assert_eq!(s.area_target(149), 0.2);
}

/// From all-open with `L_inv` only, the run (at the studio's default preview sampling) lands on
/// the target open fraction and beats the T-OLED pixel of the same open fraction on AUC and, at
/// full quality, on `L_inv`, under the same random tiling: the end is never worse.
#[test]
fn optimized_opening_beats_toled_at_the_same_open_fraction() {
    let toled_d = small(toled(TilingMode::RandomD4));
    let target = 5.0 / 21.0; // the T-OLED slit's open fraction
    let settings = OptimizeSettings {
        epochs: 80,
        target_open_fraction: target,
        area_every_epochs: 3,
        quality: Quality::Preview,
        ..Default::default()
    };
    let mut epochs_seen = 0;
    let out = optimize(
        &toled_d,
        &settings,
        None,
        &PsfRoute::Auto,
        &Progress::new(),
        |r| {
            epochs_seen = r.epoch + 1;
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    assert_eq!(epochs_seen, 80);
    assert_eq!(out.history.len(), 80);
    let last = out.history.last().unwrap();
    assert!(
        (last.open_fraction - target).abs() < 0.03,
        "relaxed open fraction {} vs target {target}",
        last.open_fraction
    );
    let open = out
        .design
        .opening
        .cells
        .iter()
        .flatten()
        .filter(|v| **v == 1.0)
        .count();
    assert_eq!(open, (target * 441.0).round() as usize);
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    let before = analyze_with(&toled_d, &options, &Progress::new()).unwrap();
    let after = analyze_with(&out.design, &options, &Progress::new()).unwrap();
    for (b, a) in before.channels.iter().zip(&after.channels) {
        assert!(
            a.mtf.auc_radial_min > b.mtf.auc_radial_min,
            "{}: optimized AUC {} vs T-OLED {}",
            b.name,
            a.mtf.auc_radial_min,
            b.mtf.auc_radial_min
        );
    }
    assert!(after.invertibility_loss < before.invertibility_loss);
    assert!((out.at_full_quality.result.loss_inv - after.invertibility_loss).abs() < 1e-9);
    // Straight-through: the loss the run reports is that of a buildable (binary) pattern.
    assert!(
        (last.loss_inv - after.invertibility_loss).abs() < 0.02,
        "reported {} vs the saved design's {}",
        last.loss_inv,
        after.invertibility_loss
    );
}

/// A run's summary scores are what `analyze` reports for its start and its result, at full
/// quality and at the run's own (preview) sampling. The last epoch is not the result: its loss
/// is of the mask before the last step, thresholded at that epoch's area target, and a run
/// stopped early thresholds the result at the final open fraction instead.
#[test]
fn a_runs_scores_are_the_analysis_of_its_start_and_its_result() {
    let d = small(toled(TilingMode::RandomD4));
    let settings = OptimizeSettings {
        epochs: 40,
        target_open_fraction: 0.3,
        area_every_epochs: 1,
        area_step: 0.05,
        quality: Quality::Preview,
        ..Default::default()
    };
    // Stopped after 4 epochs, while the area target is still 0.85.
    let out = optimize(
        &d,
        &settings,
        None,
        &PsfRoute::Auto,
        &Progress::new(),
        |r| {
            if r.epoch == 3 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        },
    )
    .unwrap();
    assert!(out.stopped_early);
    let analysis = |design: &Design, quality| {
        let options = AnalyzeOptions {
            quality,
            expected_psf: false,
        };
        analyze_with(design, &options, &Progress::new()).unwrap()
    };
    for (scores, quality) in [
        (&out.at_full_quality, Quality::Full),
        (&out.at_run_quality, Quality::Preview),
    ] {
        assert_eq!(scores.quality, quality);
        let (start, result) = (analysis(&d, quality), analysis(&out.design, quality));
        let s = scores.start.expect("the T-OLED lets light through");
        assert!(
            (s.loss_inv - start.invertibility_loss).abs() < 1e-9,
            "{quality:?} start: {} vs {}",
            s.loss_inv,
            start.invertibility_loss
        );
        assert!(
            (scores.result.loss_inv - result.invertibility_loss).abs() < 1e-9,
            "{quality:?} result: {} vs {}",
            scores.result.loss_inv,
            result.invertibility_loss
        );
        assert!((scores.result.open_fraction - result.open_fraction).abs() < 1e-12);
        assert!((s.open_fraction - start.open_fraction).abs() < 1e-12);
    }
    // The two samplings agree (crates/core/tests/physics/preview.rs; at this f/5 they are one sampling).
    let (full, run) = (
        out.at_full_quality.result.loss_inv,
        out.at_run_quality.result.loss_inv,
    );
    assert!(
        (full - run).abs() <= 0.1 * full.abs() + 5e-4,
        "{full} vs {run}"
    );
    // The last epoch's loss is of another pattern than the result's.
    let last = out.history.last().unwrap();
    assert!((last.area_target - 0.85).abs() < 1e-12);
    assert!((last.loss_inv - out.at_run_quality.result.loss_inv).abs() > 1e-6);
}

#[test]
fn stopping_early_returns_the_run_so_far_and_cancel_aborts() {
    let d = small(toled(TilingMode::Repeat));
    let settings = OptimizeSettings {
        epochs: 50,
        ..Default::default()
    };
    let out = optimize(
        &d,
        &settings,
        None,
        &PsfRoute::Auto,
        &Progress::new(),
        |r| {
            if r.epoch == 2 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        },
    )
    .unwrap();
    assert!(out.stopped_early);
    assert_eq!(out.history.len(), 3);
    assert_eq!(out.design.opening.n(), 21);
    let progress = Progress::new();
    progress.cancel();
    let err = optimize(&d, &settings, None, &PsfRoute::Auto, &progress, |_| {
        ControlFlow::Continue(())
    })
    .unwrap_err();
    assert_eq!(err, SimError::Cancelled);
}
