//! The setups the thesis compares (§4.5, Table 4.2, Fig. 4.10): bare T-OLED, folds, λ0 plans,
//! orders, steps and pitches, designed once each and run over photos and light levels.

use super::*;

use std::sync::Arc;

use crate::phase::chain::BlochRelay;

/// Where a setup's folding wavelengths come from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Lambda0Plan {
    /// Every lenslet at one wavelength (the thesis: 530 nm).
    Fixed {
        /// The folding wavelength, nm.
        nm: f64,
    },
    /// The 30 grid wavelengths in equal counts.
    Uniform,
    /// Algorithm 1's allocation (needs V: 900 propagations).
    Optimized,
}

/// The left-to-right order of the lenslets' λ0 (Table 4.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum LensletOrder {
    /// Ascending λ0 from left to right, as the thesis assigns them.
    Ascending,
    /// A seeded random permutation of the ascending plan.
    Shuffled {
        /// Seed of the permutation.
        seed: u64,
    },
}

/// One of the setups §4.5 compares.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Setup {
    /// The T-OLED alone at this pitch.
    Bare {
        /// Display pixel pitch, µm.
        pitch_um: f64,
    },
    /// The double MLA.
    DoubleMla {
        /// Display pixel (and lenslet) pitch, µm.
        pitch_um: f64,
        /// Fold thickness T (1 = phase SLM, 5 thicker).
        fold: f64,
        /// Where the folding wavelengths come from.
        lambda0: Lambda0Plan,
        /// Left-to-right order of the lenslets' λ0.
        order: LensletOrder,
        /// Heights floored to this step in µm (Fig. 4.10b: 0.2).
        quantize_um: Option<f64>,
    },
}

impl Setup {
    /// The double MLA with an ascending plan and no quantisation.
    pub fn mla(pitch_um: f64, fold: f64, lambda0: Lambda0Plan) -> Self {
        Setup::DoubleMla {
            pitch_um,
            fold,
            lambda0,
            order: LensletOrder::Ascending,
            quantize_um: None,
        }
    }

    /// Display pixel pitch of the setup, µm.
    pub fn pitch_um(&self) -> f64 {
        match self {
            Setup::Bare { pitch_um } | Setup::DoubleMla { pitch_um, .. } => *pitch_um,
        }
    }

    /// A short label for tables and plots, e.g. `T=5 optimized` or `T-OLED`.
    pub fn label(&self) -> String {
        match self {
            Setup::Bare { pitch_um } => format!("T-OLED {pitch_um} µm"),
            Setup::DoubleMla {
                pitch_um,
                fold,
                lambda0,
                order,
                quantize_um,
            } => {
                let plan = match lambda0 {
                    Lambda0Plan::Fixed { nm } => format!("fixed {nm} nm"),
                    Lambda0Plan::Uniform => "uniform".into(),
                    Lambda0Plan::Optimized => "optimized".into(),
                };
                let order = match order {
                    LensletOrder::Ascending => "",
                    LensletOrder::Shuffled { .. } => ", shuffled",
                };
                let q = quantize_um.map_or(String::new(), |q| format!(", {q} µm steps"));
                format!("MLA {pitch_um} µm T={fold} {plan}{order}{q}")
            }
        }
    }

    /// The design and optics of this setup, from `base` (its camera, index, open ratio, κ,
    /// rounding and sampling convention; pitch, fold, plan and step are the setup's). An
    /// optimized plan runs Algorithm 1 for `grid_channels` (channels on the 401:10:691 grid),
    /// its V through `relay` where one is given ([`optimize_lambda0_through`]).
    ///
    /// # Errors
    /// An invalid parameter, [`SimError::Cancelled`], or the relay's refusals.
    pub fn resolve(
        &self,
        base: &PhaseDesign,
        sampling: &PhaseSampling,
        grid_channels: &[Channel],
        relay: Option<&Arc<dyn BlochRelay>>,
        progress: &Progress,
    ) -> Result<(PhaseDesign, PhaseOptics), SimError> {
        let at_pitch = |pitch_um: f64| {
            let mut d = base.clone();
            // The same κ = f_MLA / opening at every pitch (§4.5: f_MLA = pitch).
            d.f_mla_um = base.f_mla_um / base.pitch_um * pitch_um;
            d.pitch_um = pitch_um;
            d.lambda0 = Lambda0::Fixed { nm: 530.0 };
            d.height_step_um = None;
            d
        };
        match self {
            Setup::Bare { pitch_um } => {
                let mut d = at_pitch(*pitch_um);
                // No plate: one canonical fold, so equal T-OLEDs are equal designs.
                d.fold = 1.0;
                d.validate()?;
                Ok((d, PhaseOptics::Toled))
            }
            Setup::DoubleMla {
                pitch_um,
                fold,
                lambda0,
                order,
                quantize_um,
            } => {
                let mut d = at_pitch(*pitch_um);
                d.fold = *fold;
                d.height_step_um = *quantize_um;
                d.lambda0 = match lambda0 {
                    Lambda0Plan::Fixed { nm } => Lambda0::Fixed { nm: *nm },
                    Lambda0Plan::Uniform => Lambda0::Uniform,
                    Lambda0Plan::Optimized => {
                        let chain = Chain::new(&d, sampling)?.with_relay_if(relay);
                        let (_, alloc) = optimize_lambda0_through(
                            &chain,
                            grid_channels,
                            &AllocationSettings::default(),
                            progress,
                        )?;
                        Lambda0::Counts {
                            counts: alloc.counts,
                        }
                    }
                };
                if let LensletOrder::Shuffled { seed } = order {
                    let mut nm = lambda0_per_lenslet(&d)?;
                    nm.shuffle(&mut ChaCha8Rng::seed_from_u64(*seed));
                    d.lambda0 = Lambda0::PerLenslet { nm };
                }
                d.validate()?;
                Ok((d, PhaseOptics::DoubleMla))
            }
        }
    }
}

/// The comparisons of §4.5 at the thesis's 600 DPI (Fig. 4.6, Table 4.2, Fig. 4.10b) and the
/// pitches of Fig. 4.10a, in that order.
pub fn thesis_setups() -> Vec<Setup> {
    let mut v = vec![Setup::Bare { pitch_um: 42.0 }];
    for fold in [1.0, 5.0] {
        for plan in [
            Lambda0Plan::Fixed { nm: 530.0 },
            Lambda0Plan::Uniform,
            Lambda0Plan::Optimized,
        ] {
            v.push(Setup::mla(42.0, fold, plan));
        }
    }
    for plan in [Lambda0Plan::Uniform, Lambda0Plan::Optimized] {
        v.push(Setup::DoubleMla {
            pitch_um: 42.0,
            fold: 1.0,
            lambda0: plan,
            order: LensletOrder::Shuffled { seed: 1 },
            quantize_um: None,
        });
    }
    v.push(Setup::DoubleMla {
        pitch_um: 42.0,
        fold: 5.0,
        lambda0: Lambda0Plan::Optimized,
        order: LensletOrder::Ascending,
        quantize_um: Some(0.2),
    });
    for pitch in [56.0, 84.0, 168.0] {
        v.push(Setup::Bare { pitch_um: pitch });
        v.push(Setup::mla(pitch, 5.0, Lambda0Plan::Optimized));
    }
    v
}

/// One row of a setup comparison: a setup, a photo, a light level.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CompareRow {
    /// The setup run.
    pub setup: Setup,
    /// Its label for tables and plots (`Setup::label`).
    pub label: String,
    /// Its light transmittance ratio, as `PhaseBlur::ltr`.
    pub ltr: f64,
    /// Index into the photos compared.
    pub photo: usize,
    /// Light level: photons on an open display aperture per pixel.
    pub photons: f64,
    /// PSNR of the restoration on the field of view, dB.
    pub psnr_db: f64,
    /// Mean SSIM of the restoration over channels, on the field of view.
    pub ssim: f64,
    /// PSNR of the denoised capture on the field of view; `None` without a denoiser.
    pub denoised_psnr_db: Option<f64>,
    /// The photo's mean squared content at the frequencies this setup passes < 1 % of
    /// ([`super::unpassed_mse`]): the same at every light level.
    pub unpassed_mse: f64,
}

/// Runs every setup on every photo at every light level (Fig. 4.6, Tables 4.1–4.2, Fig. 4.10):
/// each setup is designed once (an optimized plan runs Algorithm 1 once) and its operator is
/// built once per photo width over `channels` (the thesis: the sensor's spectral response on
/// the 401:10:691 grid, as `grid_channels`); every capture is denoised as `denoise` says before
/// the solver ([`thesis_denoise`] is the thesis's); `relay` runs the operators' Bloch relays
/// ([`Chain::with_relay`]; the CPU when `None`). Rows arrive through `on_row` as they finish; `progress` follows
/// the step under way (designing, the operator, a run) and cancels any of them.
///
/// # Errors
/// As [`Setup::resolve`], [`phase_blur`] and [`capture_and_restore`].
#[allow(clippy::too_many_arguments)]
pub fn compare_setups(
    base: &PhaseDesign,
    sampling: &PhaseSampling,
    setups: &[Setup],
    grid_channels: &[Channel],
    channels: &[Channel],
    photos: &[Vec<Array2<f64>>],
    photons: &[f64],
    seed: u64,
    denoise: Denoise,
    relay: Option<&Arc<dyn BlochRelay>>,
    progress: &Progress,
    mut on_row: impl FnMut(CompareRow),
) -> Result<(), SimError> {
    for setup in setups {
        let (design, optics) = setup.resolve(base, sampling, grid_channels, relay, progress)?;
        progress.check()?;
        let mut blurs: Vec<(usize, PhaseBlur)> = Vec::new();
        for (p, photo) in photos.iter().enumerate() {
            let width = photo.first().map_or(0, Array2::ncols);
            if !blurs.iter().any(|(w, _)| *w == width) {
                let chain = Chain::new(&design, sampling)?.with_relay_if(relay);
                let blur = phase_blur_on(&chain, channels, optics, width, 0, progress)?;
                blurs.push((width, blur));
            }
            let Some((_, blur)) = blurs.iter().find(|(w, _)| *w == width) else {
                continue;
            };
            let unpassed_mse = super::unpassed_mse(blur, photo)?;
            for &n in photons {
                progress.check()?;
                let run = capture_and_restore(blur, photo, n, seed, denoise, progress)?;
                on_row(CompareRow {
                    setup: setup.clone(),
                    label: setup.label(),
                    ltr: blur.ltr,
                    photo: p,
                    photons: n,
                    psnr_db: run.psnr_db,
                    ssim: run.ssim,
                    denoised_psnr_db: run.denoised_psnr_db,
                    unpassed_mse,
                });
            }
        }
    }
    Ok(())
}
