//! The optimizer on the device: its window transform and adjoint against the CPU's, and one
//! step of the differentiable model (loss and gradient) against the CPU's, held to what `f32`
//! promises; a short run end to end through the route.

use std::ops::ControlFlow;

use rustfft::num_complex::Complex64;
use udc_core::Progress;
use udc_core::analysis::analyze::Quality;
use udc_core::design::{Design, OpticsRecipe, TilingMode};
use udc_core::optimize::{LossWeights, Objective, OptimizeSettings, Relaxation, optimize};
use udc_core::psf::route::{Fraunhofer, PsfRoute};
use udc_core::psf::spectra::{Pool, Span, WindowDft};
use udc_gpu::Route;
use udc_io::design::presets::load_preset;

use crate::device;

/// A deterministic sequence in [−0.5, 0.5).
fn noise(seed: u64, n: usize) -> Vec<f64> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect()
}

fn worst(a: &[Complex64], b: &[Complex64]) -> f64 {
    let peak = a.iter().map(|z| z.norm()).fold(0.0, f64::max);
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max)
        / peak
}

/// Forward and adjoint as the CPU's, within 1e-5 of their largest value, at a length with a
/// large prime factor (1324 = 4·331), boxes of odd sizes at negative offsets, frequency boxes
/// that wrap past `M/2`, sizes that are not multiples of the kernels' 16-wide tiles.
#[test]
fn the_device_window_transform_and_its_adjoint_are_the_cpus() {
    let Some(gpu) = device("the_device_window_transform_and_its_adjoint_are_the_cpus") else {
        return;
    };
    for dft in [
        WindowDft {
            m: 1324,
            rows: Span {
                start: -41,
                len: 83,
            },
            cols: Span {
                start: -37,
                len: 75,
            },
            freq_rows: Span {
                start: -150,
                len: 301,
            },
            freq_cols: Span {
                start: 500,
                len: 290,
            },
        },
        WindowDft {
            m: 12,
            rows: Span { start: -3, len: 5 },
            cols: Span { start: -2, len: 4 },
            freq_rows: Span { start: -4, len: 7 },
            freq_cols: Span { start: -6, len: 12 },
        },
    ] {
        let pool = Pool::default();
        let a = noise(1, dft.rows.len * dft.cols.len);
        let cpu = dft.forward(&a, &pool);
        let dev = gpu.window_spectrum(&dft, &a, &pool).unwrap();
        assert_eq!(cpu.len(), dev.len());
        let err = worst(&cpu, &dev);
        assert!(
            err < 1e-5,
            "M {}: forward off by {err:.2e} of its peak",
            dft.m
        );

        let n = dft.freq_rows.len * dft.freq_cols.len;
        let g: Vec<Complex64> = noise(2, n)
            .into_iter()
            .zip(noise(3, n))
            .map(|(re, im)| Complex64::new(re, im))
            .collect();
        let cpu = dft.adjoint(&g, &pool);
        let dev = gpu.window_spectrum_adjoint(&dft, &g, &pool).unwrap();
        let peak = cpu.iter().map(|v| v.abs()).fold(0.0, f64::max);
        let err = cpu
            .iter()
            .zip(&dev)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max)
            / peak;
        assert!(
            err < 1e-5,
            "M {}: adjoint off by {err:.2e} of its peak",
            dft.m
        );
    }
}

/// The T-OLED at 150 DPI behind a small lens (f/5, a 128-pixel window): a pupil box of 250
/// samples and FFTs of about 660, small enough for a software driver.
fn small_toled() -> Design {
    let mut d = load_preset("toled-150dpi").unwrap();
    d.tiling.mode = TilingMode::RandomD4;
    d.optics.recipe = OpticsRecipe::Custom;
    d.optics.f_number = 5.0;
    d.optics.fine_sample_um = 1.0;
    d.optics.window_px = 128;
    d
}

/// One step of the optimizer's model on the device: `L_inv` within 1e-4 of the CPU's and the
/// gradient within 1e-3 of its largest component, every window transform and adjoint counted
/// on the device. Then two epochs end to end through the route.
#[test]
fn the_optimizers_step_on_the_device_is_the_cpus() {
    let Some(gpu) = device("the_optimizers_step_on_the_device_is_the_cpus") else {
        return;
    };
    let d = small_toled();
    let route = Route::device(gpu);
    let weights = LossWeights::default();
    let on = |r: &dyn Fraunhofer| {
        let obj = Objective::new(&d, Quality::Full, weights, Relaxation::Sigmoid, None, r).unwrap();
        let logits: Vec<f64> = noise(7, d.opening.n().pow(2))
            .iter()
            .map(|u| 3.0 * u)
            .collect();
        obj.step(&logits, 0.4).unwrap()
    };
    let cpu = on(&PsfRoute::Auto);
    let dev = on(&route);
    let rel = (cpu.loss_inv - dev.loss_inv).abs() / cpu.loss_inv.abs();
    assert!(
        rel < 1e-4,
        "L_inv {} vs {} ({rel:.1e})",
        cpu.loss_inv,
        dev.loss_inv
    );
    let scale = cpu.grad_logits.iter().fold(0.0f64, |m, g| m.max(g.abs()));
    assert!(scale > 0.0);
    let off = cpu
        .grad_logits
        .iter()
        .zip(&dev.grad_logits)
        .map(|(c, g)| (c - g).abs())
        .fold(0.0, f64::max);
    assert!(
        off < 1e-3 * scale,
        "gradient off by {off:.2e} (largest {scale:.2e})"
    );
    // Three channels, one wavelength each: three transforms forward, three adjoints back.
    assert_eq!(route.device_transforms(), 6);

    let settings = OptimizeSettings {
        epochs: 2,
        ..OptimizeSettings::default()
    };
    let out = optimize(&d, &settings, None, &route, &Progress::new(), |_| {
        ControlFlow::Continue(())
    })
    .unwrap();
    assert_eq!(out.history.len(), 2);
    assert!(out.history.iter().all(|r| r.loss_inv.is_finite()));
    assert!(route.device_transforms() > 6, "the run used the device");
}
