//! A question's right answer, measured on the design on screen, beside the closed form its
//! explanation names. Measurements read the simulated PSF as a student would read the plot:
//! the first minimum of a profile, the spacing of its peaks, the light in an order.

use ndarray::{Array2, Axis};

use super::{ChoiceRule, Quantity, Question};
use crate::SimError;
use crate::analysis::analyze::{Analysis, ChannelAnalysis};
use crate::design::{Design, Theory};

/// A question's answer on the design on screen.
#[derive(Debug, Clone, PartialEq)]
pub enum Answer {
    /// A number in `unit`, and the closed form's value where there is one.
    Number {
        /// Measured on the simulation.
        value: f64,
        /// The closed form's value.
        closed: Option<f64>,
        /// Its unit.
        unit: &'static str,
    },
    /// A drawing: the share of the zero order's light left in the orders the goal removes,
    /// simulated and by the closed form, and whether the goal is met.
    Drawing {
        /// Simulated share.
        share: f64,
        /// The closed form's share.
        closed: f64,
        /// Whether the simulated share is under [`super::NO_ORDERS_SHARE`].
        met: bool,
    },
    /// The right option among `options`, and the one the closed form picks where there is one.
    Choice {
        /// The options offered.
        options: Vec<String>,
        /// The index of the right one, from the simulation.
        right: usize,
        /// The index the closed form picks.
        closed: Option<usize>,
    },
}

/// What a student answered.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Guess {
    /// A number.
    Number(f64),
    /// "My drawing is done": graded by the simulation of the design on screen.
    Drawn,
    /// An option's index.
    Choice(usize),
}

impl Answer {
    /// Whether `guess` is right: a number within `tolerance` (relative) of the measured value,
    /// or the right option.
    pub fn grade(&self, guess: Guess, tolerance: f64) -> bool {
        match (self, guess) {
            (Answer::Number { value, .. }, Guess::Number(g)) => {
                g.is_finite() && (g - value).abs() <= tolerance * value.abs()
            }
            (Answer::Choice { right, .. }, Guess::Choice(i)) => i == *right,
            (Answer::Drawing { met, .. }, Guess::Drawn) => *met,
            _ => false,
        }
    }

    /// The answer as the explanation writes it ("24.4 µm", "R").
    pub fn text(&self) -> String {
        match self {
            Answer::Number { value, unit, .. } => with_unit(*value, unit),
            Answer::Choice { options, right, .. } => {
                options.get(*right).cloned().unwrap_or_default()
            }
            Answer::Drawing { share, .. } => {
                format!("{:.2} % of the zero order's light", 100.0 * share)
            }
        }
    }

    /// The closed form's value as the explanation writes it, if there is one.
    pub fn closed_text(&self) -> Option<String> {
        match self {
            Answer::Number { closed, unit, .. } => closed.map(|c| with_unit(c, unit)),
            Answer::Drawing { closed, .. } => {
                Some(format!("{:.2} % of the zero order's light", 100.0 * closed))
            }
            Answer::Choice {
                options, closed, ..
            } => closed.and_then(|c| options.get(c).cloned()),
        }
    }

    /// `template` with `{answer}` and `{closed}` filled in.
    pub fn explain(&self, template: &str) -> String {
        template.replace("{answer}", &self.text()).replace(
            "{closed}",
            &self.closed_text().unwrap_or_else(|| "—".into()),
        )
    }
}

fn with_unit(v: f64, unit: &str) -> String {
    let digits = if v.abs() >= 100.0 {
        0
    } else if v.abs() >= 10.0 {
        1
    } else if v.abs() >= 0.1 {
        2
    } else {
        4
    };
    if unit.is_empty() {
        format!("{v:.digits$}")
    } else {
        format!("{v:.digits$} {unit}")
    }
}

/// The answer to `question` on `design`'s `analysis`; `other` is the analysis of the preset a
/// comparison names ([`ChoiceRule::AucAgainst`]), `None` for the other questions.
///
/// # Errors
/// A channel the analysis does not have, a profile with no minimum or peak where the
/// quantity needs one (the design on screen is not the kind the question is about), a
/// comparison without its other analysis.
pub fn answer(
    question: &Question,
    design: &Design,
    analysis: &Analysis,
    other: Option<&Analysis>,
) -> Result<Answer, SimError> {
    match question {
        Question::Number { quantity, .. } if quantity.is_phase() => Err(SimError::invalid(
            "question",
            "is about the phase-mask design (the Phase workspace's PSFs)",
        )),
        Question::Choice {
            rule: ChoiceRule::MostLightChannel,
            ..
        } => Err(SimError::invalid(
            "question",
            "is about the phase-mask design (the Phase workspace's PSFs)",
        )),
        Question::Number {
            quantity, channel, ..
        } => {
            let ch = channel_of(analysis, channel.as_deref())?;
            let (value, closed) = number(*quantity, design, analysis, ch)?;
            Ok(Answer::Number {
                value,
                closed,
                unit: quantity.unit(),
            })
        }
        Question::Drawing { goal, .. } => match goal {
            super::DrawingGoal::NoHorizontalOrders => {
                let i = green_or_first(analysis);
                let c = crate::theory::compare(design, Theory::Grating, analysis, i)?;
                let share = |v: &[f64]| -> Option<f64> {
                    let k = c.x_um.iter().position(|x| x.abs() < 1e-9)?;
                    let zero = v[k];
                    (zero > 0.0).then(|| {
                        v.iter()
                            .enumerate()
                            .filter(|(j, _)| *j != k)
                            .map(|(_, e)| e)
                            .sum::<f64>()
                            / zero
                    })
                };
                let missing = || {
                    SimError::invalid(
                        "question",
                        "no zero order in the simulation: is the display tiled periodically?",
                    )
                };
                let simulated = share(&c.simulated).ok_or_else(missing)?;
                let closed = share(&c.predicted).ok_or_else(missing)?;
                Ok(Answer::Drawing {
                    share: simulated,
                    closed,
                    met: simulated < super::NO_ORDERS_SHARE,
                })
            }
        },
        Question::Choice { rule, than, .. } => {
            let names: Vec<String> = analysis.channels.iter().map(|c| c.name.clone()).collect();
            let options = rule.options(&names);
            match rule {
                ChoiceRule::MostLightChannel => Err(SimError::invalid(
                    "question",
                    "is about the phase-mask design (the Phase workspace's PSFs)",
                )),
                ChoiceRule::WidestChannel => {
                    let mut widths = Vec::new();
                    for i in 0..analysis.channels.len() {
                        widths.push(number(Quantity::FirstDarkUm, design, analysis, i)?.0);
                    }
                    let right = arg_max(&widths);
                    let waves: Vec<f64> =
                        analysis.channels.iter().map(|c| c.wavelength_nm).collect();
                    Ok(Answer::Choice {
                        options,
                        right,
                        closed: Some(arg_max(&waves)),
                    })
                }
                ChoiceRule::AucAgainst => {
                    let other = other.ok_or_else(|| {
                        SimError::invalid(
                            "question",
                            format!("needs the analysis of {}", than.as_deref().unwrap_or("?")),
                        )
                    })?;
                    let auc = |a: &Analysis| -> Result<f64, SimError> {
                        let i = green_or_first(a);
                        Ok(a.channels
                            .get(i)
                            .ok_or_else(|| SimError::invalid("channels", "none"))?
                            .mtf
                            .auc_radial_min)
                    };
                    let right = usize::from(auc(analysis)? <= auc(other)?);
                    Ok(Answer::Choice {
                        options,
                        right,
                        closed: None,
                    })
                }
            }
        }
    }
}

/// The answer to a phase-mask `question` (a [`Quantity::is_phase`] number or
/// [`ChoiceRule::MostLightChannel`]) on `design`'s PSFs as the Phase workspace shows them.
///
/// # Errors
/// A question about the display layout, a channel the PSFs do not have.
pub fn phase_answer(
    question: &Question,
    design: &crate::phase::PhaseDesign,
    psfs: &crate::phase::psf::PhasePsfs,
) -> Result<Answer, SimError> {
    use crate::theory::landmarks::mla_light_gain;
    let names: Vec<String> = psfs.channels.iter().map(|c| c.name.clone()).collect();
    match question {
        Question::Number {
            quantity: q @ Quantity::MlaLightGain,
            channel,
            ..
        } => {
            let i = match channel {
                None => 0,
                Some(n) => names
                    .iter()
                    .position(|c| c.eq_ignore_ascii_case(n))
                    .ok_or_else(|| {
                        SimError::invalid(
                            "question.channel",
                            format!("the PSFs have no channel {n}"),
                        )
                    })?,
            };
            let c = &psfs.channels[i];
            Ok(Answer::Number {
                value: c.energy_vs_toled_before_polariser,
                closed: Some(mla_light_gain(design.open_ratio)),
                unit: q.unit(),
            })
        }
        Question::Choice {
            rule: rule @ ChoiceRule::MostLightChannel,
            ..
        } => {
            let gains: Vec<f64> = psfs
                .channels
                .iter()
                .map(|c| c.energy_vs_toled_before_polariser)
                .collect();
            // The plate is the unfolded lens only at λ0: the channel nearest it.
            let nearest: Vec<f64> = match &design.lambda0 {
                crate::phase::Lambda0::Fixed { nm } => psfs
                    .channels
                    .iter()
                    .map(|c| -(c.wavelength_nm - nm).abs())
                    .collect(),
                _ => Vec::new(),
            };
            Ok(Answer::Choice {
                options: rule.options(&names),
                right: arg_max(&gains),
                closed: (!nearest.is_empty()).then(|| arg_max(&nearest)),
            })
        }
        _ => Err(SimError::invalid(
            "question",
            "is about the display layout, not the phase-mask design",
        )),
    }
}

fn arg_max(v: &[f64]) -> usize {
    v.iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |(i, _)| i)
}

fn green_or_first(a: &Analysis) -> usize {
    a.channels
        .iter()
        .position(|c| c.name.eq_ignore_ascii_case("g"))
        .unwrap_or(0)
}

fn channel_of(analysis: &Analysis, name: Option<&str>) -> Result<usize, SimError> {
    match name {
        None => Ok(0),
        Some(n) => analysis
            .channels
            .iter()
            .position(|c| c.name.eq_ignore_ascii_case(n))
            .ok_or_else(|| {
                SimError::invalid("question.channel", format!("the design has no channel {n}"))
            }),
    }
}

/// `λ f` in µm² for a channel (its centre wavelength): λ in nm times f in mm is λ·f in µm².
fn lf_um2(design: &Design, ch: &ChannelAnalysis) -> f64 {
    ch.wavelength_nm * design.optics.focal_length_mm
}

/// The measured value of `quantity` on channel `i` and its closed form.
fn number(
    quantity: Quantity,
    design: &Design,
    analysis: &Analysis,
    i: usize,
) -> Result<(f64, Option<f64>), SimError> {
    let ch = analysis
        .channels
        .get(i)
        .ok_or_else(|| SimError::invalid("channel", format!("{i} does not exist")))?;
    let pixel_um = analysis.sensor_pixel_um;
    let lf = lf_um2(design, ch);
    let not_found = |what: &str| {
        SimError::invalid(
            "question",
            format!(
                "{what} not found in channel {}'s PSF: is this the design the question is about?",
                ch.name
            ),
        )
    };
    match quantity {
        Quantity::FirstDarkUm => {
            let (profile, closed) = match design.theory {
                Some(Theory::Circle { diameter_um }) => {
                    (axis_row(&ch.psf), Some(1.22 * lf / diameter_um))
                }
                Some(Theory::Slit { width_um } | Theory::DoubleSlit { width_um, .. }) => {
                    (column_sums(&ch.psf), Some(lf / width_um))
                }
                Some(Theory::Rectangle { width_um, .. }) => {
                    (column_sums(&ch.psf), Some(lf / width_um))
                }
                // A grating's or a display's first dark is no closed form's.
                Some(Theory::Grating) | None => (axis_row(&ch.psf), None),
            };
            let d = first_minimum(&profile).ok_or_else(|| not_found("a dark fringe"))?;
            Ok((d * pixel_um, closed))
        }
        Quantity::FringeSpacingUm => {
            let profile = column_sums(&ch.psf);
            let closed = match design.theory {
                Some(Theory::DoubleSlit { separation_um, .. }) => Some(lf / separation_um),
                _ => None,
            };
            // The fringes inside the single slit's envelope (its first dark), where they are
            // bright enough to read.
            let reach = match design.theory {
                Some(Theory::DoubleSlit { width_um, .. }) => lf / width_um / pixel_um,
                _ => profile.len() as f64 / 4.0,
            };
            let peaks = peaks_within(&profile, reach);
            if peaks.len() < 3 {
                return Err(not_found("three fringes"));
            }
            let (first, last) = (peaks[0], peaks[peaks.len() - 1]);
            Ok(((last - first) / (peaks.len() - 1) as f64 * pixel_um, closed))
        }
        Quantity::OrderSpacingUm => {
            let profile = axis_row(&ch.psf);
            let closed = Some(crate::theory::landmarks::order_spacing_um(
                ch.wavelength_nm,
                design.optics.focal_length_mm,
                design.opening.pitch_um + design.tiling.wiring_gap_um,
            ));
            let d = first_side_peak(&profile).ok_or_else(|| not_found("a first order"))?;
            Ok((d * pixel_um, closed))
        }
        Quantity::ZeroOrderShare => {
            let c = crate::theory::compare(design, Theory::Grating, analysis, i)?;
            let k = c
                .x_um
                .iter()
                .position(|x| x.abs() < 1e-9)
                .ok_or_else(|| not_found("the zero order"))?;
            Ok((c.simulated[k], Some(c.predicted[k])))
        }
        Quantity::MlaLightGain => Err(SimError::invalid(
            "question",
            "is about the phase-mask design (the Phase workspace's PSFs)",
        )),
        Quantity::NyquistCycPerMm => {
            let top = ch
                .mtf
                .freqs_cyc_per_px()
                .last()
                .copied()
                .ok_or_else(|| not_found("an MTF"))?;
            Ok((top / pixel_um * 1000.0, Some(1000.0 / (2.0 * pixel_um))))
        }
    }
}

/// How well the design on screen's PSF matches a mystery's, from 0 to 1: the correlation of
/// the two log-PSFs (each from its peak down to [`MATCH_FLOOR_DECADES`] below it, so the faint
/// orders and halo count as much as the bright centre) in channel `channel`, on the window
/// both hold about the axis. Negative correlations count as 0.
///
/// # Errors
/// A channel either analysis lacks, or analyses on different sensor pixels.
pub fn psf_match(drawn: &Analysis, mystery: &Analysis, channel: &str) -> Result<f64, SimError> {
    let pick = |a: &Analysis| -> Result<Array2<f64>, SimError> {
        a.channels
            .iter()
            .find(|c| c.name.eq_ignore_ascii_case(channel))
            .map(|c| c.psf.clone())
            .ok_or_else(|| SimError::invalid("channel", format!("no channel {channel}")))
    };
    if (drawn.sensor_pixel_um - mystery.sensor_pixel_um).abs() > 1e-9 {
        return Err(SimError::invalid(
            "optics",
            "the drawing and the mystery are seen with different sensor pixels",
        ));
    }
    let (a, b) = (pick(drawn)?, pick(mystery)?);
    let side = a.nrows().min(b.nrows());
    let log = |p: &Array2<f64>| -> Vec<f64> {
        let p = crate::measured::compare::centred_to(p, side);
        let peak = p.iter().fold(0.0f64, |m, v| m.max(*v));
        let floor = peak * 10f64.powf(-MATCH_FLOOR_DECADES);
        p.iter().map(|v| v.max(floor).log10()).collect()
    };
    let (x, y) = (log(&a), log(&b));
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (u, v) in x.iter().zip(&y) {
        sxy += (u - mx) * (v - my);
        sxx += (u - mx) * (u - mx);
        syy += (v - my) * (v - my);
    }
    if sxx <= 0.0 || syy <= 0.0 {
        return Ok(0.0);
    }
    Ok((sxy / (sxx * syy).sqrt()).max(0.0))
}

/// How far below the peak the mystery's match reads the PSFs, decades.
pub const MATCH_FLOOR_DECADES: f64 = 5.0;

/// The light per column (summed over rows), centre at index `n / 2`.
fn column_sums(psf: &Array2<f64>) -> Vec<f64> {
    psf.sum_axis(Axis(0)).to_vec()
}

/// The row through the axis.
fn axis_row(psf: &Array2<f64>) -> Vec<f64> {
    psf.row(psf.nrows() / 2).to_vec()
}

/// The vertex offset of the parabola through three samples, in `[-0.5, 0.5]`.
fn vertex(a: f64, b: f64, c: f64) -> f64 {
    let den = a - 2.0 * b + c;
    if den.abs() < f64::MIN_POSITIVE {
        0.0
    } else {
        (0.5 * (a - c) / den).clamp(-0.5, 0.5)
    }
}

/// The mean distance (samples) of the first local minimum from the centre, walking right and
/// left, each refined by a parabola.
fn first_minimum(p: &[f64]) -> Option<f64> {
    let c = p.len() / 2;
    let right = (c + 1..p.len() - 1)
        .find(|&i| p[i] <= p[i - 1] && p[i] < p[i + 1])
        .map(|i| i as f64 - c as f64 + vertex(p[i - 1], p[i], p[i + 1]))?;
    let left = (1..c)
        .rev()
        .find(|&i| p[i] <= p[i + 1] && p[i] < p[i - 1])
        .map(|i| c as f64 - i as f64 - vertex(p[i - 1], p[i], p[i + 1]))?;
    Some(0.5 * (right + left))
}

/// The mean distance (samples) from the centre of the first order, right and left: the
/// nearest peak past the central lobe holding at least a tenth of the brightest such peak (the
/// lens pupil's faint rings between the orders are not orders).
fn first_side_peak(p: &[f64]) -> Option<f64> {
    let c = p.len() / 2;
    let side = |dir: isize| -> Option<f64> {
        let at = |k: usize| -> f64 { p[(c as isize + dir * k as isize) as usize] };
        let n = c.min(p.len() - 1 - c);
        let first_min = (1..n - 1).find(|&k| at(k) <= at(k - 1) && at(k) < at(k + 1))?;
        let peaks: Vec<usize> = (first_min + 1..n - 1)
            .filter(|&k| at(k) >= at(k - 1) && at(k) > at(k + 1))
            .collect();
        let top = peaks.iter().map(|&k| at(k)).fold(0.0, f64::max);
        let k = *peaks.iter().find(|&&k| at(k) >= 0.1 * top)?;
        Some(k as f64 + vertex(at(k - 1), at(k), at(k + 1)))
    };
    Some(0.5 * (side(1)? + side(-1)?))
}

/// The local maxima (refined positions in samples from the centre, ascending) within `reach`
/// samples of the centre.
fn peaks_within(p: &[f64], reach: f64) -> Vec<f64> {
    let c = p.len() / 2;
    (1..p.len() - 1)
        .filter(|&i| p[i] >= p[i - 1] && p[i] > p[i + 1])
        .map(|i| i as f64 - c as f64 + vertex(p[i - 1], p[i], p[i + 1]))
        .filter(|x| x.abs() < reach)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sampled_sinc_squared_has_its_first_zero_where_the_formula_puts_it() {
        // sinc²(x / 7.3): zeros at ±7.3 samples.
        let p: Vec<f64> = (0..64)
            .map(|i| {
                let x = (i as f64 - 32.0) / 7.3;
                if x == 0.0 {
                    1.0
                } else {
                    let s = (std::f64::consts::PI * x).sin() / (std::f64::consts::PI * x);
                    s * s
                }
            })
            .collect();
        let d = first_minimum(&p).unwrap();
        assert!((d - 7.3).abs() < 0.25, "{d}");
        let peaks = peaks_within(&p, 20.0);
        assert_eq!(peaks.len(), 5, "{peaks:?}");
    }

    #[test]
    fn a_number_is_right_within_its_tolerance_only() {
        let a = Answer::Number {
            value: 24.0,
            closed: Some(24.5),
            unit: "µm",
        };
        assert!(a.grade(Guess::Number(25.0), 0.05));
        assert!(!a.grade(Guess::Number(26.0), 0.05));
        assert!(!a.grade(Guess::Number(f64::NAN), 0.05));
        assert!(!a.grade(Guess::Choice(0), 0.05));
        assert_eq!(
            a.explain("{answer} against {closed}"),
            "24.0 µm against 24.5 µm"
        );
    }
}
