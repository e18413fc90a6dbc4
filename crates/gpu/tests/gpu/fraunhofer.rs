//! The device's Fraunhofer step against the CPU's full route: one field at lengths with large
//! prime factors, every preset and both tilings, and the whole analysis, held to the
//! tolerances an `f32` device promises (PSF within 1e-5 of its peak, AUC within 0.3 %, LTR
//! exact).

use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with, analyze_with_route};
use udc_core::design::TilingMode;
use udc_core::display::aperture::{Display, Extent, Field, SparseRow, effective_cells, rasterise};
use udc_core::psf::fft::{Binned, binned_intensity, binned_intensity_complex, full_intensity};
use udc_core::psf::route::{Fraunhofer, PsfRoute};
use udc_core::psf::sampling::Binning;
use udc_core::{Progress, SimError};
use udc_io::design::presets::{PRESETS, load_preset};

use crate::device;

/// An irregular real field: rows of different lengths and offsets, values in (0, 1].
fn field(rows: i64, half_width: i64) -> Field {
    Field {
        rows: (-rows..rows)
            .filter(|iy| iy % 5 != 2)
            .map(|iy| {
                let ix0 = -half_width + (iy * 7).rem_euclid(11);
                let len = (2 * half_width - (iy * 3).rem_euclid(13)) as usize;
                SparseRow {
                    iy,
                    ix0,
                    values: (0..len)
                        .map(|i| ((i as i64 * 37 + iy * 11).rem_euclid(17) + 1) as f64 / 17.0)
                        .collect(),
                }
            })
            .collect(),
    }
}

#[test]
fn the_device_bins_the_cpus_intensity_at_any_length() {
    let Some(gpu) = device("the_device_bins_the_cpus_intensity_at_any_length") else {
        return;
    };
    // 1324 = 4·331 and 998 = 2·499: lengths a power-of-two FFT cannot do without the chirp-z
    // step; windows that reach past the grid's edge (998) and phases on both axes. Convolution
    // lengths 4 096 (radix-4 passes only), 2 048 and 128 (a last radix-2 pass).
    for (m, rows, half, window, sp, phase) in [
        (1324usize, 300i64, 400i64, 48usize, 7usize, [3usize, 5usize]),
        (998, 60, 120, 64, 16, [0, 15]),
        (64, 8, 20, 16, 4, [1, 2]),
    ] {
        let f = field(rows, half);
        let binning = Binning {
            window_px: window,
            samples_per_px: sp,
            phase,
        };
        let cpu = binned_intensity(&f, m, &binning, &Progress::new()).unwrap();
        let dev = gpu.binned(&f, m, &binning, &Progress::new()).unwrap();
        agree(&cpu, &dev, 1e-12, &format!("M {m}"));
    }
}

/// The whole grid (the measured-PSF fit's fine intensities) as the CPU's, sample for sample:
/// within 1e-5 of its peak everywhere, the mirrored half included (the device computes half the
/// columns of a real field), and its light `M² Σa²`.
#[test]
fn the_device_gives_the_cpus_whole_intensity() {
    let Some(gpu) = device("the_device_gives_the_cpus_whole_intensity") else {
        return;
    };
    let p = Progress::new();
    for (m, rows, half) in [(998usize, 60i64, 120i64), (64, 8, 20)] {
        let f = field(rows, half);
        let cpu = full_intensity(&f, m, &p).unwrap();
        let dev = gpu.full(&f, m, &p).unwrap();
        assert_eq!(dev.dim(), (m, m), "M {m}");
        // The field has no mirror symmetry of its own, so a half computed and mirrored the
        // wrong way round would not match.
        let flipped = |y: usize, x: usize| cpu[[(m - y) % m, x]];
        let asymmetry = (0..m)
            .flat_map(|y| (0..m).map(move |x| (y, x)))
            .map(|(y, x)| (cpu[[y, x]] - flipped(y, x)).abs())
            .fold(0.0, f64::max);
        assert!(
            asymmetry > 1e-2 * cpu[[m / 2, m / 2]],
            "M {m}: the test field must not be symmetric"
        );
        let worst = worst_of_peak(&cpu, &dev);
        assert!(worst <= 1e-5, "M {m}: {worst:e} of the peak");
        let light = (m * m) as f64 * f.energy();
        assert!(rel(dev.sum(), light) <= 1e-5, "M {m}: light {}", dev.sum());
    }
}

/// The device's window within 1e-5 of the CPU's peak, its total within `total_rel` and its
/// aliasing band within 1e-4.
fn agree(cpu: &Binned, dev: &Binned, total_rel: f64, what: &str) {
    let w = worst_of_peak(&cpu.sensor, &dev.sensor);
    assert!(w <= 1e-5, "{what}: worst {w:e} of the peak");
    assert!(
        (cpu.total - dev.total).abs() <= total_rel * cpu.total,
        "{what}: total {} vs {}",
        cpu.total,
        dev.total
    );
    assert!(
        (cpu.edge - dev.edge).abs() <= 1e-4 * cpu.edge.max(1e-6 * cpu.total),
        "{what}: band {} vs {}",
        cpu.edge,
        dev.edge
    );
}

/// A complex field (a pupil with a defocus and a tilt, so its intensity has no mirror symmetry)
/// on the whole grid: the window within 1e-5 of the CPU's peak, the total and the band as the
/// CPU's; with no phase at all, the device's whole-grid path bins as its half-grid one.
#[test]
fn the_device_bins_a_complex_fields_intensity_as_the_cpu() {
    let Some(gpu) = device("the_device_bins_a_complex_fields_intensity_as_the_cpu") else {
        return;
    };
    for (m, rows, half, window, sp, phase) in [
        (998usize, 60i64, 120i64, 64usize, 16usize, [0usize, 15usize]),
        (64, 8, 20, 16, 4, [1, 2]),
    ] {
        let real = field(rows, half);
        let f = real.with_phase(|ix, iy| 0.003 * (ix * ix + iy * iy) as f64 + 0.4 * ix as f64);
        let binning = Binning {
            window_px: window,
            samples_per_px: sp,
            phase,
        };
        let p = Progress::new();
        let cpu = binned_intensity_complex(&f, m, &binning, &p).unwrap();
        let dev = gpu.binned_complex(&f, m, &binning, &p).unwrap();
        // The tilt moves light to one side: a half-grid (mirrored) route could not give this.
        // Pixel j mirrors to W − j about the axis pixel W/2 (row and column 0 have no mirror).
        let peak = cpu.sensor.iter().copied().fold(0.0, f64::max);
        let w_px = cpu.sensor.nrows();
        let asymmetry = (1..w_px)
            .flat_map(|y| (1..w_px).map(move |x| (y, x)))
            .map(|(y, x)| (cpu.sensor[[y, x]] - cpu.sensor[[w_px - y, w_px - x]]).abs())
            .fold(0.0, f64::max);
        assert!(asymmetry > 1e-2 * peak, "M {m}: symmetric");
        agree(&cpu, &dev, 1e-10, &format!("M {m}, complex"));
        let flat = real.with_phase(|_, _| 0.0);
        let whole = gpu.binned_complex(&flat, m, &binning, &p).unwrap();
        let halved = gpu.binned(&real, m, &binning, &p).unwrap();
        let w = worst_of_peak(&halved.sensor, &whole.sensor);
        assert!(w <= 1e-6, "M {m}: whole vs half grid {w:e} of the peak");
        assert!((whole.edge - halved.edge).abs() <= 1e-5 * halved.edge.max(1e-6 * halved.total));
    }
}

#[test]
fn the_device_refuses_what_the_cpu_refuses() {
    let Some(gpu) = device("the_device_refuses_what_the_cpu_refuses") else {
        return;
    };
    let binning = Binning {
        window_px: 8,
        samples_per_px: 2,
        phase: [0, 0],
    };
    let f = field(20, 30);
    let p = Progress::new();
    for m in [41usize, 40] {
        let cpu = binned_intensity(&f, m, &binning, &p)
            .unwrap_err()
            .to_string();
        let dev = gpu.binned(&f, m, &binning, &p).unwrap_err().to_string();
        assert_eq!(cpu, dev, "M {m}");
    }
    let cancelled = Progress::new();
    cancelled.cancel();
    assert!(matches!(
        gpu.binned(&f, 128, &binning, &cancelled),
        Err(SimError::Cancelled)
    ));
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(f64::MIN_POSITIVE)
}

/// The largest difference between two binned windows, as a fraction of the first's peak.
fn worst_of_peak(cpu: &ndarray::Array2<f64>, dev: &ndarray::Array2<f64>) -> f64 {
    let peak = cpu.iter().copied().fold(0.0, f64::max);
    cpu.iter()
        .zip(dev.iter())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / peak
}

/// Every preset in both tilings, through the seam on its smallest grid (the device's cost on a
/// software driver grows as M², and every grid runs the same kernels): the binned window
/// within 1e-5 of the CPU's peak, the grid's light and its aliasing band with it.
#[test]
fn every_preset_and_both_tilings_bin_as_the_cpu_does() {
    let Some(gpu) = device("every_preset_and_both_tilings_bin_as_the_cpu_does") else {
        return;
    };
    let p = Progress::new();
    for preset in PRESETS {
        for tiling in [TilingMode::Repeat, TilingMode::RandomD4] {
            let mut design = load_preset(preset.name).unwrap();
            design.tiling.mode = tiling;
            let label = format!("{} {}", preset.name, tiling.as_str());
            let samplings = Quality::Preview.plan(&design, &mut Vec::new()).unwrap();
            let s = samplings
                .iter()
                .flatten()
                .min_by_key(|s| s.fft_size)
                .unwrap();
            let cells = effective_cells(&design.opening);
            let op = &design.optics;
            let field = rasterise(
                &Display::from_design(&design, &cells),
                Extent::Pupil {
                    diameter_um: op.pupil_diameter_um(),
                },
                op.pupil_sample_um,
            );
            let cpu = PsfRoute::Full
                .binned(&field, s.fft_size, &s.binning, &p)
                .unwrap();
            let dev = gpu.binned(&field, s.fft_size, &s.binning, &p).unwrap();
            let worst = worst_of_peak(&cpu.sensor, &dev.sensor);
            assert!(
                worst <= 1e-5,
                "{label}, M {}: {worst:e} of the peak",
                s.fft_size
            );
            assert!(rel(cpu.total, dev.total) <= 1e-12, "{label}: total");
            assert!(
                (cpu.edge - dev.edge).abs() <= 1e-4 * cpu.edge + 1e-9 * cpu.total,
                "{label}: band {} vs {}",
                cpu.edge,
                dev.edge
            );
        }
    }
}

/// The whole analysis with every PSF from the device: the numbers a user reads (PSF, AUC, LTR)
/// within an `f32` device's tolerances of the CPU's, in both tilings, and the random tiling's
/// expected PSF (its pupil-sized transforms on the device) within 1e-5 of its peak.
#[test]
fn the_analysis_on_the_device_reads_as_on_the_cpu() {
    let Some(gpu) = device("the_analysis_on_the_device_reads_as_on_the_cpu") else {
        return;
    };
    let options = AnalyzeOptions {
        quality: Quality::Preview,
        expected_psf: true,
    };
    let p = Progress::new();
    for tiling in [TilingMode::Repeat, TilingMode::RandomD4] {
        let mut design = load_preset("toled-150dpi").unwrap();
        design.tiling.mode = tiling;
        let cpu = analyze_with(&design, &options, &p).unwrap();
        let dev = analyze_with_route(&design, &options, gpu.as_ref(), &p).unwrap();
        assert_eq!(cpu.ltr, dev.ltr, "{tiling:?}: LTR");
        for (c, d) in cpu.channels.iter().zip(&dev.channels) {
            let worst = worst_of_peak(&c.psf, &d.psf);
            assert!(worst <= 1e-5, "{tiling:?} {}: PSF {worst:e}", c.name);
            let auc = rel(c.mtf.auc_radial_min, d.mtf.auc_radial_min);
            assert!(auc <= 3e-3, "{tiling:?} {}: AUC {auc:e}", c.name);
            assert!((c.energy_in_window - d.energy_in_window).abs() <= 1e-5);
            match (&c.expected_psf, &d.expected_psf) {
                (Some(ce), Some(de)) => {
                    let worst = worst_of_peak(ce, de);
                    assert!(
                        worst <= 1e-5,
                        "{tiling:?} {}: expected PSF {worst:e}",
                        c.name
                    );
                }
                (None, None) => assert_eq!(tiling, TilingMode::Repeat, "a random tiling has one"),
                _ => panic!("{tiling:?}: the expected PSF on one backend only"),
            }
        }
    }
}
