//! The closed-form expected PSF of a random tiling against the mean over many realisations.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common::small_optics;
use ndarray::Array2;
use udc_core::Progress;
use udc_core::analysis::analyze::{AnalyzeOptions, analyze_with};
use udc_core::design::{Channel, Design, TilingMode};

fn l1(a: &Array2<f64>, b: &Array2<f64>) -> f64 {
    (a - b).iter().map(|v| v.abs()).sum::<f64>() / b.iter().map(|v| v.abs()).sum::<f64>()
}

fn design(mode: TilingMode, seed: u64) -> Design {
    let mut d = Design::default_toled();
    d.optics = small_optics();
    d.channels = vec![Channel::peak("G", 530.0)];
    d.tiling.mode = mode;
    d.tiling.seed = seed;
    d
}

fn psf(d: &Design, expected: bool) -> (Array2<f64>, Option<Array2<f64>>) {
    let opts = AnalyzeOptions {
        expected_psf: expected,
        ..Default::default()
    };
    let mut a = analyze_with(d, &opts, &Progress::new()).expect("analysis");
    let ch = a.channels.remove(0);
    (ch.psf, ch.expected_psf)
}

#[test]
fn mean_over_seeds_approaches_the_closed_form() {
    for mode in [TilingMode::RandomD4, TilingMode::Random4] {
        let (_, expected) = psf(&design(mode, 0), true);
        let expected = expected.expect("random tiling has an expected PSF");
        assert!((expected.sum() - 1.0).abs() < 1e-9);
        let seeds = 48;
        let mut mean = Array2::<f64>::zeros(expected.dim());
        let mut err_at_4 = 0.0;
        for s in 0..seeds {
            mean += &psf(&design(mode, 1000 + s), false).0;
            if s == 3 {
                err_at_4 = l1(&(&mean / 4.0), &expected);
            }
        }
        mean /= seeds as f64;
        let err = l1(&mean, &expected);
        let single = l1(&psf(&design(mode, 7), false).0, &expected);
        let periodic = l1(&psf(&design(TilingMode::Repeat, 0), false).0, &expected);
        // Averaging realisations converges on the closed form, and it is not the periodic PSF.
        assert!(
            err < 0.5 * err_at_4,
            "{mode:?}: 48 seeds {err}, 4 seeds {err_at_4}"
        );
        assert!(
            err < 0.4 * single,
            "{mode:?}: mean {err} vs one realisation {single}"
        );
        assert!(err < 0.15, "{mode:?}: relative L1 {err}");
        assert!(
            periodic > 3.0 * err,
            "{mode:?}: periodic {periodic} vs mean {err}"
        );
    }
}

#[test]
fn repeat_tiling_has_no_expected_psf_and_seeds_are_reproducible() {
    let (_, e) = psf(&design(TilingMode::Repeat, 0), true);
    assert!(e.is_none());
    // Bit for bit, run after run: the parallel sums merge in a fixed order.
    let (a, _) = psf(&design(TilingMode::RandomD4, 5), false);
    for _ in 0..4 {
        let (b, _) = psf(&design(TilingMode::RandomD4, 5), false);
        assert_eq!(a, b, "same seed, same PSF, bit for bit");
    }
    let (c, _) = psf(&design(TilingMode::RandomD4, 6), false);
    assert!(
        l1(&a, &c) > 1e-3,
        "another seed must give another realisation"
    );
}
