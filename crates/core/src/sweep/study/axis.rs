//! A study's axes: what each varies, its values as sweep parameters, and the designs its values
//! make (to check and cost them before anything runs).

use crate::SimError;
use crate::design::{Design, TilingMode};
use crate::phase::{Lambda0Plan, PhaseDesign};
use crate::restore::RestoreMethod;
use crate::sweep::ParamValue;
use crate::sweep::one_axis::SweepParameter;

/// One axis of a study.
#[derive(Debug, Clone, PartialEq)]
pub enum StudyAxis {
    /// Display pixel densities, DPI (each point's pitch is `25 400 µm / DPI`).
    Dpi(Vec<f64>),
    /// Tilings.
    Tiling(Vec<TilingMode>),
    /// This many seeds of the random tiling, from the design's own.
    Seeds(u64),
    /// One of the display design's numbers (the one-axis sweep's fields), at these values; for
    /// a phase-mask study only the pitch (µm), which is also the lenslets'.
    Number(SweepParameter, Vec<f64>),
    /// Light levels of the restored capture, as the SNR in dB of a white pixel behind the
    /// reference display (conventions §5).
    SnrDb(Vec<f64>),
    /// Restoration methods.
    Method(Vec<RestoreMethod>),
    /// The drawn opening grown (positive) or shrunk (negative) by these many cells
    /// ([`crate::display::opening_ops::grow`]): its variants, named by their open fraction.
    Opening(Vec<i32>),
    /// Open fractions of a phase-mask design's display pixel (its slit).
    OpenRatio(Vec<f64>),
    /// Fold thicknesses T of a phase-mask plate.
    Fold(Vec<f64>),
    /// Folding-wavelength plans of a phase-mask plate.
    Lambda0(Vec<Lambda0Plan>),
}

impl StudyAxis {
    /// The job parameter the axis sets (its column in the results).
    pub fn param(&self) -> &'static str {
        match self {
            StudyAxis::Dpi(_) => "dpi",
            StudyAxis::Tiling(_) => "tiling",
            StudyAxis::Seeds(_) => "seed",
            StudyAxis::Number(p, _) => p.param(),
            StudyAxis::SnrDb(_) => "snr-db",
            StudyAxis::Method(_) => "method",
            StudyAxis::Opening(_) => "open-fraction",
            StudyAxis::OpenRatio(_) => "open-ratio",
            StudyAxis::Fold(_) => "fold",
            StudyAxis::Lambda0(_) => "lambda0",
        }
    }

    /// How many values it takes.
    pub fn len(&self) -> usize {
        match self {
            StudyAxis::Dpi(v) | StudyAxis::Number(_, v) | StudyAxis::SnrDb(v) => v.len(),
            StudyAxis::Fold(v) | StudyAxis::OpenRatio(v) => v.len(),
            StudyAxis::Opening(k) => k.len(),
            StudyAxis::Tiling(t) => t.len(),
            StudyAxis::Method(m) => m.len(),
            StudyAxis::Lambda0(p) => p.len(),
            StudyAxis::Seeds(n) => usize::try_from(*n).unwrap_or(usize::MAX),
        }
    }

    /// Whether it takes no value.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether it makes the study restore a photo (a light level or a method).
    pub fn restores(&self) -> bool {
        matches!(self, StudyAxis::SnrDb(_) | StudyAxis::Method(_))
    }

    /// Whether it varies a phase-mask design alone (its fold, λ0 plan or open ratio).
    pub fn is_phase(&self) -> bool {
        matches!(
            self,
            StudyAxis::Fold(_) | StudyAxis::Lambda0(_) | StudyAxis::OpenRatio(_)
        )
    }

    /// Its values as sweep parameters; `first_seed` is the design's own seed. An opening
    /// axis's values are its steps here; the spec names its points by their open fractions.
    pub fn values(&self, first_seed: u64) -> Vec<ParamValue> {
        let floats = |v: &[f64]| v.iter().map(|x| ParamValue::Float(*x)).collect();
        match self {
            StudyAxis::Dpi(v) | StudyAxis::SnrDb(v) | StudyAxis::Fold(v) => floats(v),
            StudyAxis::OpenRatio(v) => floats(v),
            StudyAxis::Opening(k) => k.iter().map(|k| ParamValue::Int(i64::from(*k))).collect(),
            StudyAxis::Tiling(t) => t
                .iter()
                .map(|m| ParamValue::Text(m.as_str().into()))
                .collect(),
            StudyAxis::Seeds(n) => (0..*n)
                .map(|k| ParamValue::Int(first_seed.saturating_add(k) as i64))
                .collect(),
            StudyAxis::Number(p, v) => v.iter().map(|x| p.param_value(*x)).collect(),
            StudyAxis::Method(m) => m
                .iter()
                .map(|m| ParamValue::Text(m.name().into()))
                .collect(),
            StudyAxis::Lambda0(p) => p.iter().map(|p| ParamValue::Text(p.as_arg())).collect(),
        }
    }

    /// `design` at each of the axis's values that changes how much work a point is (the
    /// DPI and the lens numbers; a tiling, a seed, a light level or a method costs the same).
    pub(super) fn variants(&self, design: &Design) -> Vec<Result<Design, SimError>> {
        match self {
            StudyAxis::Dpi(v) => v.iter().map(|dpi| design.at_dpi(*dpi)).collect(),
            StudyAxis::Number(p, v) => v.iter().map(|x| p.apply(design, *x)).collect(),
            StudyAxis::Opening(k) => k.iter().map(|k| Ok(grown(design, *k))).collect(),
            _ => Vec::new(),
        }
    }

    /// `design` at each of the axis's values, for a phase-mask study: the pitch (the focal
    /// length follows it where it did, as the command's `--f-mla-um` default), the fold, the
    /// λ0 plan (`None` for the optimizer's, known only once it has run).
    pub(super) fn phase_variants(&self, design: &PhaseDesign) -> Vec<Option<PhaseDesign>> {
        match self {
            StudyAxis::Number(SweepParameter::PitchUm, v) => v
                .iter()
                .map(|p| {
                    let mut d = design.clone();
                    if d.f_mla_um == d.pitch_um {
                        d.f_mla_um = *p;
                    }
                    d.pitch_um = *p;
                    Some(d)
                })
                .collect(),
            StudyAxis::Fold(v) => v
                .iter()
                .map(|t| {
                    let mut d = design.clone();
                    d.fold = *t;
                    Some(d)
                })
                .collect(),
            StudyAxis::OpenRatio(v) => v
                .iter()
                .map(|o| {
                    let mut d = design.clone();
                    d.open_ratio = *o;
                    Some(d)
                })
                .collect(),
            StudyAxis::Lambda0(p) => p
                .iter()
                .map(|p| {
                    p.lambda0().map(|l| {
                        let mut d = design.clone();
                        d.lambda0 = l;
                        d
                    })
                })
                .collect(),
            _ => Vec::new(),
        }
    }
}

/// `design` with its drawn opening grown (or shrunk) by `steps` cells, as one edit: its
/// polygons dropped (the cells are the opening now) and its sub-pixels refitted.
pub fn grown(design: &Design, steps: i32) -> Design {
    let mut d = design.clone();
    d.opening.cells = crate::display::opening_ops::grow(&design.opening.cells, steps);
    if steps != 0 {
        d.opening.polygons.clear();
        d.reconcile_subpixels();
    }
    d
}

/// Whole numbers as a designer types them (`-1, 0, 1, 2`), each within ±`limit`.
///
/// # Errors
/// Text that is not a list of whole numbers, or none, or one beyond the limit.
pub fn parse_steps(text: &str, limit: i32) -> Result<Vec<i32>, String> {
    let v: Vec<i32> = text
        .split([',', ' ', ';'])
        .filter(|s| !s.trim().is_empty())
        .map(|s| {
            s.trim()
                .parse::<i32>()
                .ok()
                .filter(|k| k.abs() <= limit)
                .ok_or_else(|| {
                    format!(
                        "{:?} is not a whole number of cells within ±{limit}",
                        s.trim()
                    )
                })
        })
        .collect::<Result<_, _>>()?;
    if v.is_empty() {
        Err("no value: list the cells to grow (1, 2) or shrink (-1)".into())
    } else {
        Ok(v)
    }
}

/// Values as a designer types them: a list (`80, 150, 300, 600`) or `from:to:count`
/// (`80:600:5`, both ends included).
///
/// # Errors
/// Text that is neither, a count below 1 or above [`crate::sweep::spec::MAX_AXIS_VALUES`], a
/// value that is not a finite number.
pub fn parse_values(text: &str) -> Result<Vec<f64>, String> {
    let number = |s: &str| -> Result<f64, String> {
        let s = s.trim();
        s.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("{s:?} is not a number"))
    };
    let parts: Vec<&str> = text.split(':').collect();
    match parts.as_slice() {
        [from, to, count] => {
            let (from, to) = (number(from)?, number(to)?);
            let n: usize = count
                .trim()
                .parse()
                .map_err(|_| format!("{:?} is not a count of values", count.trim()))?;
            if !(1..=crate::sweep::spec::MAX_AXIS_VALUES).contains(&n) {
                return Err(format!(
                    "{n} values: give 1 to {}",
                    crate::sweep::spec::MAX_AXIS_VALUES
                ));
            }
            Ok(crate::sweep::one_axis::values(from, to, n, false))
        }
        [_] => {
            let v: Vec<f64> = text
                .split([',', ' ', ';'])
                .filter(|s| !s.trim().is_empty())
                .map(number)
                .collect::<Result<_, _>>()?;
            if v.is_empty() {
                Err("no value: list them (80, 150, 300) or give from:to:count".into())
            } else {
                Ok(v)
            }
        }
        _ => Err(format!(
            "{text:?}: list values (80, 150, 300) or give from:to:count (80:600:5)"
        )),
    }
}

/// λ0 plans as a designer types them: `fixed:530, uniform, optimized` (commas or spaces).
///
/// # Errors
/// A plan that does not read, or none.
pub fn parse_plans(text: &str) -> Result<Vec<Lambda0Plan>, String> {
    let v: Vec<Lambda0Plan> = text
        .split([',', ' ', ';'])
        .filter(|s| !s.trim().is_empty())
        .map(|s| Lambda0Plan::parse(s).map_err(|why| format!("{:?}: {why}", s.trim())))
        .collect::<Result<_, _>>()?;
    if v.is_empty() {
        Err("no plan: list them (fixed:530, uniform, optimized)".into())
    } else {
        Ok(v)
    }
}
