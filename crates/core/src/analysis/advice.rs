//! Advice for sampling warnings: for each warning of an analysis, the least costly change of the
//! optics (δ1, δ2, the window) that resolves it without raising a kind of warning the analysis
//! did not have. Every candidate is checked by analysing the changed design, because how much
//! light a larger window or a finer grid holds depends on the opening: only a run knows.
//!
//! Candidates, cheapest first:
//! - light outside the window: the window enlarged to the FFT grid of the shortest wavelength;
//!   once it fills that grid, δ1 divided by 2, 4 or 8 with the window filling the grown grid
//!   (a larger window alone would reach past the grid, where nothing is computed);
//! - aliasing, and cells finer than δ1: δ1 smaller (at most the cell size) with the window grown
//!   in proportion up to the new grid, then with the window kept;
//! - a window beyond the grid: the window shrunk to the grid, then δ1 smaller;
//! - under-padding, and a pixel that is not a whole number of fine samples: δ2 = pixel / k.
//!
//! A candidate keeps every full-quality FFT within [`MAX_FFT_SIZE`] and its values within the
//! Optics panel's ranges. It is checked at preview quality (the energy shares agree with full
//! quality to about 0.1 %) with a margin (98.5 % of the light in the window, at most 1.5 % at
//! the grid edge), plus the full-quality sampling plan. When no candidate passes, the warning's
//! message says why and it has no fix.

use std::collections::BTreeSet;

use crate::analysis::analyze::{AnalyzeOptions, Limits, Quality, analyze_within};
use crate::design::{Design, MAX_FFT_SIZE, Optics};
use crate::psf::sampling::{fft_size, plan};
use crate::psf::warning::{Fix, SamplingWarning, Severity, WarningKind, short_number};
use crate::{Progress, SimError};

/// Largest window a fix proposes, and the Optics panel's (its field clamps anything larger).
pub const MAX_FIX_WINDOW_PX: usize = 2048;
/// Smallest δ1 a fix proposes, and the Optics panel's, µm.
pub const MIN_FIX_PUPIL_SAMPLE_UM: f64 = 0.25;
/// Smallest δ2 a fix proposes, and the Optics panel's, µm.
pub const MIN_FIX_FINE_SAMPLE_UM: f64 = 0.05;

/// A fix must pass these, stricter than what the analysis reports, so that the full-quality
/// analysis after Apply does not warn again at the threshold.
const CHECKED: Limits = Limits {
    min_energy_in_window: 0.985,
    max_edge_energy: 0.015,
};

/// How δ1 is refined: each step quadruples the FFT work.
const DELTA1_DIVISORS: [f64; 3] = [2.0, 4.0, 8.0];

/// How many δ2 = pixel / k values are tried.
const FINE_CANDIDATES: usize = 2;

/// Candidate optics of one kind, with the limits that ruled out the costlier ones.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Candidates {
    /// The optics to check, cheapest first.
    pub optics: Vec<Optics>,
    /// Why no costlier candidate was proposed ("δ1 2 → 1 µm needs FFTs of 12200² …").
    pub limits: Vec<String>,
}

fn with_optics(design: &Design, optics: &Optics) -> Design {
    Design {
        optics: optics.clone(),
        ..design.clone()
    }
}

/// The largest full-quality FFT of `design` with these δ1 and δ2, and its wavelength.
fn largest_fft(design: &Design, pupil_sample_um: f64, fine_sample_um: f64) -> (usize, f64) {
    let f = design.optics.focal_length_mm;
    design
        .channels
        .iter()
        .flat_map(|c| &c.wavelengths_nm)
        .map(|&l| (fft_size(l, f, pupil_sample_um, fine_sample_um), l))
        .fold((0, 0.0), |a, b| if b.0 > a.0 { b } else { a })
}

/// The window (sensor pixels) that fills the narrowest full-quality FFT grid of `design` with
/// `optics`, at most [`MAX_FIX_WINDOW_PX`]; `None` when the grid cannot be planned.
pub fn grid_window_px(design: &Design, optics: &Optics) -> Option<usize> {
    let mut ignored = Vec::new();
    let d = with_optics(design, optics);
    let p = plan(&d, optics.fine_sample_um, &mut ignored).ok()?;
    let px = p
        .iter()
        .flatten()
        .map(|s| s.fft_size as f64 / s.binning.samples_per_px as f64)
        .fold(f64::INFINITY, f64::min);
    // Half a pixel past the grid is within the analysis's tolerance of 2 fine samples a side:
    // so the thesis's 294 px fill its 293.5-px grid at 470 nm.
    px.is_finite()
        .then(|| (px.round() as usize).clamp(2, MAX_FIX_WINDOW_PX))
}

/// δ1 refined by 2, 4, 8 (or, with `cell_um`, down to the cell size first), within the limits.
fn finer_delta1(design: &Design, cell_um: Option<f64>, limits: &mut Vec<String>) -> Vec<f64> {
    let op = &design.optics;
    let steps: Vec<f64> = match cell_um {
        Some(cell) => DELTA1_DIVISORS
            .iter()
            .map(|k| cell * 2.0 / k)
            .filter(|d| *d < op.pupil_sample_um)
            .collect(),
        None => DELTA1_DIVISORS
            .iter()
            .map(|k| op.pupil_sample_um / k)
            .collect(),
    };
    let mut out = Vec::new();
    for d1 in steps {
        let (m, l) = largest_fft(design, d1, op.fine_sample_um);
        let step = format!(
            "δ1 {} → {} µm",
            short_number(op.pupil_sample_um),
            short_number(d1)
        );
        if d1 < MIN_FIX_PUPIL_SAMPLE_UM {
            limits.push(format!(
                "{step} is below the {MIN_FIX_PUPIL_SAMPLE_UM} µm limit"
            ));
            break;
        }
        if m > MAX_FFT_SIZE {
            limits.push(format!(
                "{step} needs FFTs of {m}² samples at {l} nm, above the {MAX_FFT_SIZE}² limit"
            ));
            break;
        }
        out.push(d1);
    }
    out
}

/// δ2 = pixel / k, smaller than now (or, for `whole`, any k near the current ratio), that pads
/// the pupil at least 2× at every wavelength within the FFT limit.
fn whole_fine_samples(design: &Design, whole: bool, limits: &mut Vec<String>) -> Vec<f64> {
    let op = &design.optics;
    let ratio = op.sensor_pixel_um / op.fine_sample_um;
    let first = if whole {
        ratio.floor().max(1.0)
    } else {
        ratio.floor() + 1.0
    } as usize;
    let pupil_samples = op.pupil_diameter_um() / op.pupil_sample_um;
    let f = op.focal_length_mm;
    let mut out = Vec::new();
    for k in first..first + 64 {
        let d2 = op.sensor_pixel_um / k as f64;
        let (m, l) = largest_fft(design, op.pupil_sample_um, d2);
        let step = format!(
            "δ2 {} → {} µm",
            short_number(op.fine_sample_um),
            short_number(d2)
        );
        if d2 < MIN_FIX_FINE_SAMPLE_UM {
            limits.push(format!(
                "{step} is below the {MIN_FIX_FINE_SAMPLE_UM} µm limit"
            ));
            break;
        }
        if m > MAX_FFT_SIZE {
            limits.push(format!(
                "{step} needs FFTs of {m}² samples at {l} nm, above the {MAX_FFT_SIZE}² limit"
            ));
            break;
        }
        let padded = design
            .channels
            .iter()
            .flat_map(|c| &c.wavelengths_nm)
            .all(|&l| fft_size(l, f, op.pupil_sample_um, d2) as f64 >= 2.0 * pupil_samples);
        if padded {
            out.push(d2);
            if out.len() == FINE_CANDIDATES {
                break;
            }
        }
    }
    out
}

/// The optics worth checking for a warning of `kind` in `design`, cheapest first.
pub fn candidates(kind: WarningKind, design: &Design) -> Candidates {
    let op = &design.optics;
    let mut limits = Vec::new();
    let mut optics = Vec::new();
    let at = |d1: f64, window_px: usize| Optics {
        pupil_sample_um: d1,
        window_px,
        ..op.clone()
    };
    let fill = |o: &Optics| grid_window_px(design, o);
    match kind {
        WarningKind::LightOutsideWindow => {
            if let Some(w) = fill(op).filter(|w| *w > op.window_px) {
                optics.push(at(op.pupil_sample_um, w));
            }
            for d1 in finer_delta1(design, None, &mut limits) {
                if let Some(w) = fill(&at(d1, op.window_px)) {
                    optics.push(at(d1, w));
                }
            }
        }
        WarningKind::Aliasing | WarningKind::CellsFinerThanSampling => {
            let cell =
                (kind == WarningKind::CellsFinerThanSampling).then(|| design.opening.cell_um());
            for d1 in finer_delta1(design, cell, &mut limits) {
                let Some(w) = fill(&at(d1, op.window_px)) else {
                    continue;
                };
                let grown = (op.window_px as f64 * op.pupil_sample_um / d1).round() as usize;
                optics.push(at(d1, grown.min(w)));
                if op.window_px <= w {
                    optics.push(at(d1, op.window_px));
                }
            }
        }
        WarningKind::WindowBeyondGrid => {
            if let Some(w) = fill(op).filter(|w| *w < op.window_px) {
                optics.push(at(op.pupil_sample_um, w));
            }
            for d1 in finer_delta1(design, None, &mut limits) {
                optics.push(at(d1, op.window_px));
            }
        }
        WarningKind::UnderPadded | WarningKind::PixelNotWhole => {
            let whole = kind == WarningKind::PixelNotWhole;
            for d2 in whole_fine_samples(design, whole, &mut limits) {
                optics.push(Optics {
                    fine_sample_um: d2,
                    ..op.clone()
                });
            }
        }
    }
    optics.retain(|o| o != op);
    optics.dedup();
    Candidates { optics, limits }
}

/// What a candidate's check found.
#[derive(Debug, Clone, PartialEq)]
struct Checked {
    /// Kinds raised at the reported limits: the full-quality plan's and a preview analysis's.
    reported: BTreeSet<WarningKind>,
    /// The energy kinds raised at the stricter [`CHECKED`] limits.
    strict: BTreeSet<WarningKind>,
}

/// Checks `design` with `optics`; `Err` says why it cannot be analysed.
fn check(
    design: &Design,
    optics: &Optics,
    progress: &Progress,
) -> Result<Result<Checked, SimError>, SimError> {
    let d = with_optics(design, optics);
    let mut planned = Vec::new();
    if let Err(e) = plan(&d, optics.fine_sample_um, &mut planned) {
        return Ok(Err(e));
    }
    let options = AnalyzeOptions {
        quality: Quality::Preview,
        expected_psf: false,
    };
    match analyze_within(&d, &options, progress, &CHECKED) {
        Err(SimError::Cancelled) => Err(SimError::Cancelled),
        Err(e) => Ok(Err(e)),
        Ok((a, strict)) => Ok(Ok(Checked {
            // The plan's kinds come from full quality only: the preview's grids differ.
            reported: planned
                .iter()
                .map(|w| w.kind)
                .chain(
                    a.warnings
                        .iter()
                        .map(|w| w.kind)
                        .filter(|k| !k.is_planned()),
                )
                .collect(),
            strict: strict.into_iter().collect(),
        })),
    }
}

/// Which warnings [`advise_in`] looks for fixes for: each fix is checked by a further
/// analysis, which can cost more than the analysis that raised the warning.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AdviceScope {
    /// Only [`Severity::Warning`]s, the sampling that misrepresents the design (the CLI's
    /// default: a note is a documented property of the recipe, shown as it is).
    Warnings,
    /// Notes too (the studio, which offers an Apply button on each; the CLI's `--advice`).
    All,
}

impl AdviceScope {
    fn covers(self, severity: Severity) -> bool {
        self == AdviceScope::All || severity == Severity::Warning
    }
}

/// Finds a [`Fix`] for every warning and note of `design`'s analysis: [`advise_in`] with
/// [`AdviceScope::All`].
///
/// # Errors
/// As [`advise_in`].
pub fn advise(
    design: &Design,
    warnings: &mut [SamplingWarning],
    progress: &Progress,
) -> Result<(), SimError> {
    advise_in(design, warnings, AdviceScope::All, progress)
}

/// Finds a [`Fix`] for every warning of `design`'s analysis within `scope` (see the module
/// docs); a warning without one gets the reason appended to its message, one outside the scope
/// is left as it is. Several warnings often share a candidate, which is then analysed once.
///
/// # Errors
/// [`SimError::Cancelled`] when `progress` was cancelled; nothing else (a candidate that cannot
/// be analysed is a reason, not an error).
pub fn advise_in(
    design: &Design,
    warnings: &mut [SamplingWarning],
    scope: AdviceScope,
    progress: &Progress,
) -> Result<(), SimError> {
    let present: BTreeSet<WarningKind> = warnings.iter().map(|w| w.kind).collect();
    let mut checked: Vec<(Optics, Result<Checked, SimError>)> = Vec::new();
    for w in warnings.iter_mut().filter(|w| scope.covers(w.severity)) {
        let cands = candidates(w.kind, design);
        let mut reasons = Vec::new();
        for o in cands.optics {
            progress.check()?;
            let outcome = match checked.iter().find(|(c, _)| *c == o) {
                Some((_, r)) => r.clone(),
                None => {
                    let r = check(design, &o, progress)?;
                    checked.push((o.clone(), r.clone()));
                    r
                }
            };
            let fix = Fix::between(&design.optics, o);
            let outcome = match outcome {
                Ok(c) => c,
                Err(e) => {
                    reasons.push(format!("{}: {e}", fix.summary()));
                    continue;
                }
            };
            // Resolved with a margin; new only if it would be reported.
            if outcome.reported.contains(&w.kind) || outcome.strict.contains(&w.kind) {
                reasons.push(format!(
                    "{} still leaves {}",
                    fix.summary(),
                    w.kind.describe()
                ));
            } else if let Some(k) = outcome.reported.difference(&present).next() {
                reasons.push(format!("{} would add {}", fix.summary(), k.describe()));
            } else {
                w.fix = Some(fix);
                break;
            }
        }
        if w.fix.is_none() {
            reasons.extend(cands.limits);
            if reasons.is_empty() {
                reasons.push("nothing to change".into());
            }
            w.message.push_str(&format!(
                "; no change of optics.pupil_sample_um, optics.fine_sample_um or \
                 optics.window_px within the limits resolves it ({})",
                reasons.join("; ")
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::analyze::analyze_with;
    use crate::design::{Channel, Opening};

    fn thesis_slit() -> Design {
        Design::default_toled()
    }

    #[test]
    fn the_thesis_window_fills_its_grid_and_doubles_with_a_halved_delta1() {
        let d = thesis_slit();
        assert_eq!(grid_window_px(&d, &d.optics), Some(294));
        let finer = Optics {
            pupil_sample_um: 4.0,
            ..d.optics.clone()
        };
        assert_eq!(grid_window_px(&d, &finer), Some(588));
    }

    #[test]
    fn light_outside_a_full_window_asks_for_a_finer_grid_and_a_wider_window_together() {
        let d = thesis_slit();
        let c = candidates(WarningKind::LightOutsideWindow, &d);
        // The 294-px window already fills the 470-nm grid: enlarging it alone is no candidate.
        let first = &c.optics[0];
        assert_eq!((first.pupil_sample_um, first.window_px), (4.0, 588));
        assert_eq!(
            (c.optics[1].pupil_sample_um, c.optics[1].window_px),
            (2.0, 1175)
        );
        // δ1 = 1 µm needs 12200-point FFTs at 610 nm, within the limit.
        assert_eq!(
            (c.optics[2].pupil_sample_um, c.optics[2].window_px),
            (1.0, 2048)
        );
        assert_eq!(c.optics.len(), 3, "{c:?}");
        assert!(
            c.limits.iter().all(|l| !l.contains("12200²")),
            "{:?}",
            c.limits
        );
        // A smaller window is first enlarged up to the grid, δ1 untouched.
        let mut small = d.clone();
        small.optics.window_px = 200;
        let c = candidates(WarningKind::LightOutsideWindow, &small);
        assert_eq!(
            (c.optics[0].pupil_sample_um, c.optics[0].window_px),
            (8.0, 294)
        );
    }

    #[test]
    fn aliasing_grows_the_window_with_the_grid_then_keeps_it() {
        let c = candidates(WarningKind::Aliasing, &thesis_slit());
        let got: Vec<(f64, usize)> = c
            .optics
            .iter()
            .map(|o| (o.pupil_sample_um, o.window_px))
            .collect();
        assert_eq!(got[..2], [(4.0, 588), (4.0, 294)]);
    }

    #[test]
    fn cells_finer_than_delta1_get_delta1_at_most_the_cell_size() {
        let mut d = thesis_slit();
        d.opening.pitch_um = 84.0; // 4-µm cells under δ1 = 8 µm
        let c = candidates(WarningKind::CellsFinerThanSampling, &d);
        assert!(c.optics.iter().all(|o| o.pupil_sample_um <= 4.0));
        assert_eq!(c.optics[0].pupil_sample_um, 4.0);
    }

    #[test]
    fn under_padding_and_odd_pixels_get_a_whole_fraction_of_the_pixel() {
        let mut d = thesis_slit();
        d.optics.fine_sample_um = 0.6; // 1.96× padding at 470 nm, 3.33 samples per pixel
        let pad = candidates(WarningKind::UnderPadded, &d);
        assert_eq!(pad.optics[0].fine_sample_um, 0.5);
        let whole = candidates(WarningKind::PixelNotWhole, &d);
        assert_eq!(whole.optics[0].fine_sample_um, 0.5);
        // f/1: 2× padding at 470 nm needs δ2 ≤ 0.235 µm: 2 µm / 9.
        d.optics.f_number = 1.0;
        let pad = candidates(WarningKind::UnderPadded, &d);
        assert!((pad.optics[0].fine_sample_um - 2.0 / 9.0).abs() < 1e-12);
    }

    #[test]
    fn a_window_beyond_the_grid_is_first_shrunk_to_it() {
        let mut d = thesis_slit();
        d.optics.window_px = 400;
        let c = candidates(WarningKind::WindowBeyondGrid, &d);
        assert_eq!(
            (c.optics[0].pupil_sample_um, c.optics[0].window_px),
            (8.0, 294)
        );
        assert_eq!(
            (c.optics[1].pupil_sample_um, c.optics[1].window_px),
            (4.0, 400)
        );
    }

    /// A fast design: a 2-cell slit in 8 µm cells behind an f/5 lens, one wavelength.
    fn small_slit(window_px: usize) -> Design {
        Design {
            opening: Opening::slit(8, 2, 64.0),
            optics: Optics {
                recipe: crate::design::OpticsRecipe::Custom,
                f_number: 5.0,
                fine_sample_um: 1.0,
                window_px,
                ..Optics::iccp21()
            },
            channels: vec![Channel::peak("G", 530.0)],
            ..Design::default_toled()
        }
    }

    fn preview(d: &Design) -> Vec<SamplingWarning> {
        let options = AnalyzeOptions {
            quality: Quality::Preview,
            expected_psf: false,
        };
        analyze_with(d, &options, &Progress::new())
            .expect("analysis")
            .warnings
    }

    #[test]
    fn an_advised_window_holds_the_light_and_raises_nothing_new() {
        let d = small_slit(64);
        let mut warnings = preview(&d);
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert_eq!(warnings[0].kind, WarningKind::LightOutsideWindow);
        assert_eq!(warnings[0].severity, crate::psf::warning::Severity::Warning);
        advise(&d, &mut warnings, &Progress::new()).expect("advice");
        let fix = warnings[0].fix.clone().expect("a fix");
        assert!(fix.optics.window_px > 64, "{}", fix.summary());
        let after = preview(&Design {
            optics: fix.optics,
            ..d
        });
        assert!(after.is_empty(), "{after:?}");
    }

    #[test]
    fn without_a_fix_the_message_says_why() {
        // A 1-µm slit behind a 0.5-mm lens at the finest δ1 the studio proposes: the window
        // fills the 400-nm grid, and 1000 nm spreads past it.
        let mut d = small_slit(400);
        d.opening = Opening::slit(8, 1, 8.0);
        d.optics.focal_length_mm = 0.5;
        d.optics.f_number = 10.0;
        d.optics.pupil_sample_um = 0.25;
        d.channels = vec![Channel::peak("R", 1000.0), Channel::peak("B", 400.0)];
        let mut warnings = preview(&d);
        assert_eq!(
            warnings.iter().map(|w| w.kind).collect::<Vec<_>>(),
            [WarningKind::LightOutsideWindow]
        );
        advise(&d, &mut warnings, &Progress::new()).expect("advice");
        assert!(warnings[0].fix.is_none());
        assert!(
            warnings[0]
                .message
                .ends_with("(δ1 0.25 → 0.125 µm is below the 0.25 µm limit)"),
            "{}",
            warnings[0].message
        );
    }

    #[test]
    fn a_cancelled_advice_stops() {
        let d = small_slit(64);
        let mut warnings = preview(&d);
        let p = Progress::new();
        p.cancel();
        assert_eq!(advise(&d, &mut warnings, &p), Err(SimError::Cancelled));
        assert!(warnings[0].fix.is_none());
    }
}
