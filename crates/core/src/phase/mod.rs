//! Phase masks (thesis chapter 4, conventions.md §7): two microlens arrays (MLAs) around a T-OLED,
//! folded into thin plates, with a folding wavelength λ0 per lenslet.
//!
//! Everything is 1-D along x (a T-OLED pixel is a slit, fully open along y). Conventions, stated
//! once here (conventions.md §7 is their source):
//! - x = 0 is the optical axis; display-plane samples sit on the lattice `x = m·δ` (δ = 15 nm).
//! - Where the optics and the sensor sit relative to the axis is a [`SamplingConvention`]:
//!   - [`SamplingConvention::Thesis`] (default, reproduces the thesis code's numbers): lenslets of
//!     `round(pitch/δ)` samples tile from the first sample inside the display aperture
//!     `D + 2 f_MLA tan 50°`, in ascending λ0 order; each lenslet's coordinate is
//!     `(q − patternN/2)·δ`; its slit is `round(open·pitch/δ)` samples starting at sample
//!     `round_half_even((patternN − slitN)/2)`; the grating is padded with ones outside the
//!     lenslets; the display-aperture and main-lens rects are the samples with `|x| ≤ W/2`. The
//!     sensor is `pixels` pixels of `fine` samples of the M-point FFT's bins `λf/(Mδ)`,
//!     `M = 2⌊λf/(2δ·δ3)⌋`, δ3 = 0.145 µm at 14 samples per pixel (an effective pixel of 2.03 µm
//!     for 2 µm pixels); sensor pixel `P/2` covers bins 0 … fine − 1, so the axis is its LEFT edge.
//!   - [`SamplingConvention::Centred`]: lenslet `l` of `L` is centred at `(l − (L−1)/2)·pitch`
//!     with its slit, the slits repeat beyond the array, rect edges are anti-aliased, and each
//!     pixel of exactly `pixel_um` integrates `fine` midpoint samples with the axis at the centre
//!     of pixel `P/2`.
//! - Direction `Incidence::Pixel(j)` is `sinθ = j · pixel_um / f` under both conventions.
//! - A PSF window is the whole sensor for every direction. A plain lens images the direction θ at
//!   `f·sinθ`; the double MLA, a 1:1 Keplerian telescope per lenslet pair, inverts the angle and
//!   sends it near `−f·sinθ`, split into the lenslet grating's orders `λf/pitch` apart.
//! - Energies are fractions of the light that falls on the main-lens opening (unit irradiance over
//!   its width D = f/F#); the polarisation-dependent plate's ×½ is applied only where a name says
//!   so (`*_with_polariser`).
//! - The plate's own frame ([`Lenslets`], exports, plots) centres the array on x = 0; the chain
//!   places it relative to the axis as the convention says.
//!
//! The chain ([`chain`]) is: plane wave `exp(i k sinθ x)` · display-aperture rect → MLA 1 → Fresnel
//! transfer-function propagation over z = f_MLA, `H(fx) = exp(−iπλz fx²)` → display slits →
//! Fresnel over z → MLA 2 → main-lens rect → Fraunhofer to the sensor (a chirp-z transform
//! evaluates exactly the sensor's samples, so every wavelength lands on its sensor grid) → box
//! binning. Lenslet heights are `mod(x²/(2(n−1)f_MLA), T λ0/(n−1))` and their transmission
//! `exp(−i k (n−1) h)`. Photos through a design: [`imaging`].

pub mod allocate;
pub mod chain;
pub mod czt;
pub mod drc;
pub mod figures;
pub mod geometry;
pub mod imaging;
pub mod invertibility;
pub mod plan;
pub mod plate;
pub mod psf;

use serde::{Deserialize, Serialize};

use crate::SimError;

pub use allocate::{
    Allocation, AllocationSettings, allocate, optimize_lambda0, optimize_lambda0_through,
};
pub use chain::{Chain, Incidence, MonoPsf, PhaseOptics, effective_pixel_um};
pub use geometry::{Lenslets, Surface};
pub use invertibility::{
    VMatrix, invertibility_score, optical_mtf, v_matrix, v_matrix_on, v_matrix_through,
};
pub use plan::Lambda0Plan;
pub use psf::{ChannelPsf, PhasePsfs, kernel_matrix, kernel_matrix_on, phase_psfs, phase_psfs_on};

/// Refractive index of the lenslets (no dispersion, as in the thesis).
pub const THESIS_REFRACTIVE_INDEX: f64 = 1.515;
/// The T-OLED's open ratio: a slit of pitch/4.2 per pixel (κ = 4.2 when f_MLA = pitch).
pub const THESIS_OPEN_RATIO: f64 = 1.0 / 4.2;
/// Half-angle that widens the display aperture beyond the main lens: `D + 2 z tan 50°`.
pub const DISPLAY_APERTURE_HALF_ANGLE_DEG: f64 = 50.0;
/// The polarisation-dependent implementation passes half of the unpolarised light (§4.3.4).
pub const POLARISER_TRANSMISSION: f64 = 0.5;
/// The wavelength grid of V and of the λ0 allocation: 401, 411, … 691 nm (30 values).
pub const GRID_FIRST_NM: f64 = 401.0;
/// Spacing of the wavelength grid, nm.
pub const GRID_STEP_NM: f64 = 10.0;
/// Wavelengths in the grid.
pub const GRID_LEN: usize = 30;

/// The 30 wavelengths of V and of the allocation, in nm.
pub fn wavelength_grid_nm() -> Vec<f64> {
    (0..GRID_LEN)
        .map(|j| GRID_FIRST_NM + GRID_STEP_NM * j as f64)
        .collect()
}

/// The camera behind the display. The thesis's: f = 4.67 mm, F/2, 1024 pixels of 2 µm.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhaseCamera {
    /// Main-lens focal length `f`, mm.
    pub focal_length_mm: f64,
    /// Main-lens F-number; the opening is `D = f / F#`.
    pub f_number: f64,
    /// Nominal sensor pixel pitch, µm (sets the incidence directions).
    pub pixel_um: f64,
    /// Sensor pixels along x (even): also the number of incidence directions of the kernel matrix.
    pub pixels: usize,
}

impl PhaseCamera {
    /// The thesis's camera: f = 4.67 mm, F/2, 1024 pixels of 2 µm.
    pub fn thesis() -> Self {
        PhaseCamera {
            focal_length_mm: 4.67,
            f_number: 2.0,
            pixel_um: 2.0,
            pixels: 1024,
        }
    }

    /// Focal length `f`, µm.
    pub fn focal_length_um(&self) -> f64 {
        self.focal_length_mm * 1000.0
    }

    /// Main-lens opening D = f / F#, in µm.
    pub fn aperture_um(&self) -> f64 {
        self.focal_length_um() / self.f_number
    }

    /// sinθ of the direction imaged on pixel `j` (relative to the axis pixel): `j·pixel / f`.
    pub fn sin_theta_of_pixel(&self, j: f64) -> f64 {
        j * self.pixel_um / self.focal_length_um()
    }
}

/// How finely the chain is sampled.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhaseSampling {
    /// δ1, the display-plane sample (conventions.md §7: 15 nm).
    pub display_sample_um: f64,
    /// Fine sensor samples per sensor pixel (conventions.md §7: 14).
    pub fine_per_pixel: usize,
    /// How the double MLA's relay is computed; files written before it existed read as
    /// [`Relay::WholeDisplay`].
    #[serde(default)]
    pub relay: Relay,
}

/// How the chain propagates through MLA 1, the display and MLA 2 (conventions.md §7).
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Relay {
    /// The thesis's: the whole display on one wrap-free Fresnel grid, so the edges of the
    /// lenslet array diffract as they do in the thesis code (its V reproduces to ~2e-5).
    #[default]
    WholeDisplay,
    /// The whole display on a grid of its own width, whose wrap-around stands in for the light
    /// the array's ends diffract beyond it (the display repeated, as the lenslet period repeats
    /// one lenslet), taken with the direction's Bloch phase: every plate, PSFs within 1e-5 of
    /// the whole display's peak where most light passes, a λ0 plan's spectral operator
    /// about 2× faster. Under the thesis convention and for the double MLA only (the other
    /// optics have no Fresnel step to wrap).
    WrappedDisplay,
    /// One lenslet period with the direction's Bloch phase, as if the array were infinite: the
    /// same fields where the display's edges do not reach (V within 1e-3 of
    /// the whole display), at a small fraction of the cost. Only for a plate whose lenslets
    /// are all alike under the thesis convention; a λ0 plan falls back to
    /// the wrapped display, the centred convention to the whole display.
    LensletPeriod,
}

impl Relay {
    /// The CLI's and the reports' spelling.
    pub fn name(self) -> &'static str {
        self.into()
    }
}

impl PhaseSampling {
    /// The studio's sampling by quality: the live preview's or the thesis's grid, both through
    /// the lenslet period where the plate has one (V within 1e-3 of the whole display, the same
    /// allocations; [`Relay`]).
    pub fn for_quality(quality: crate::Quality) -> Self {
        let grid = match quality {
            crate::Quality::Preview => PhaseSampling::preview(),
            crate::Quality::Full => PhaseSampling::thesis(),
        };
        grid.with_relay(Relay::LensletPeriod)
    }

    /// This sampling through `relay`.
    pub fn with_relay(self, relay: Relay) -> Self {
        PhaseSampling { relay, ..self }
    }

    /// The relay `design` actually goes through with this sampling: the lenslet period only
    /// where it applies (the bare T-OLED, or a plate with one λ0, under the thesis convention),
    /// the wrapped display only for the double MLA under the thesis convention.
    pub fn relay_for(&self, design: &PhaseDesign, optics: PhaseOptics) -> Relay {
        let thesis = design.sampling == SamplingConvention::Thesis;
        let periodic = match optics {
            PhaseOptics::Toled => thesis,
            PhaseOptics::DoubleMla | PhaseOptics::SingleMask => design.has_lenslet_period(),
        };
        let wraps = thesis && optics == PhaseOptics::DoubleMla;
        match self.relay {
            Relay::LensletPeriod if periodic => Relay::LensletPeriod,
            Relay::LensletPeriod | Relay::WrappedDisplay if wraps => Relay::WrappedDisplay,
            Relay::LensletPeriod | Relay::WrappedDisplay | Relay::WholeDisplay => {
                Relay::WholeDisplay
            }
        }
    }

    /// The thesis sampling: 15 nm at the display, 14 fine samples per pixel.
    pub fn thesis() -> Self {
        PhaseSampling {
            display_sample_um: 0.015,
            fine_per_pixel: 14,
            relay: Relay::WholeDisplay,
        }
    }

    /// A coarse preview for live dragging: 4× coarser display sampling and 7 samples per pixel.
    /// The lens phase still changes by < 0.4 rad per sample and the slits keep > 150 samples.
    pub fn preview() -> Self {
        PhaseSampling {
            display_sample_um: 0.06,
            fine_per_pixel: 7,
            relay: Relay::WholeDisplay,
        }
    }
}

/// Where the chain's samples sit relative to the optics (conventions.md §7). The thesis's numbers
/// (Tables 4.1–4.2, its V matrices and λ0 allocations) depend on it.
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SamplingConvention {
    /// The thesis code's: the sensor is 1024 pixels of 14 Fraunhofer samples of
    /// `λf/(M δ)` ≈ 0.145 µm (an effective pixel of 2.03 µm) with the optical axis on the LEFT
    /// edge of pixel 512; lenslets tile from the first display sample inside the display
    /// aperture, each `round(pitch/δ)` samples with its slit starting at sample
    /// `round_half_even((patternN − slitN)/2)`; rects are sets of whole samples.
    #[default]
    Thesis,
    /// Axis at the centre of the axis pixel, exact pixel pitch, lenslets and slits placed
    /// symmetrically about the axis, rect edges anti-aliased.
    Centred,
}

impl SamplingConvention {
    /// Both conventions, in the order the UI lists them.
    pub const ALL: [SamplingConvention; 2] =
        [SamplingConvention::Thesis, SamplingConvention::Centred];

    /// The CLI's and the design file's spelling.
    pub fn name(self) -> &'static str {
        self.into()
    }
}

/// How a fabrication step quantises the folded profile (conventions.md §7, "Phase plate
/// quantisation").
#[derive(strum::VariantArray, strum::IntoStaticStr, strum::EnumMessage, strum::Display)]
#[strum(serialize_all = "kebab-case")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum HeightRounding {
    /// `floor(h / step) · step`, as the authors' code: every height stays below the fold height.
    #[default]
    Floor,
    /// The nearest level of the unfolded sag, `round(sag/step) mod m` with `m = round(d0/step)`
    /// levels per fold: zero mean phase error, but the plate wraps every `m·step` of sag
    /// (1.2 µm for a 1.165 µm fold at 0.2 µm steps), not at the fold height.
    Nearest,
}

/// Where each lenslet's folding wavelength λ0 comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Lambda0 {
    /// Every lenslet folded at one wavelength (the thesis's fixed 530 nm).
    Fixed {
        /// The folding wavelength, nm.
        nm: f64,
    },
    /// Wavelengths spread evenly over 400–700 nm: the 30-value grid in equal counts, ascending.
    Uniform,
    /// Counts per grid wavelength (30 values summing to the lenslet count), assigned in
    /// ascending order: what the optimizer returns.
    Counts {
        /// Lenslets folded at each grid wavelength (401, 411, … 691 nm).
        counts: Vec<usize>,
    },
    /// One λ0 per lenslet, left to right, as the user edited them.
    PerLenslet {
        /// λ0 of each lenslet, nm, left to right.
        nm: Vec<f64>,
    },
}

/// One double-MLA phase-mask design.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhaseDesign {
    /// Display pixel pitch in µm (also the lenslet pitch). 42 µm = 600 DPI.
    pub pitch_um: f64,
    /// Lenslet focal length f_MLA in µm (= the MLA–display gap z); conventions.md: f_MLA = pitch.
    pub f_mla_um: f64,
    /// Refractive index `n` of the lenslets (the thesis: 1.515).
    pub refractive_index: f64,
    /// Fold thickness T: the plate's maximum height is `T λ0 / (n − 1)` (1 = phase SLM, 5 thicker).
    pub fold: f64,
    /// Open fraction of each display pixel (a slit of `open_ratio · pitch`).
    pub open_ratio: f64,
    /// Folding wavelength λ0 of each lenslet.
    pub lambda0: Lambda0,
    /// Optional fabrication step in µm (e.g. 0.2): fold heights and the profile are rounded to it.
    #[serde(default)]
    pub height_step_um: Option<f64>,
    /// How `height_step_um` quantises heights (floor by default).
    #[serde(default)]
    pub height_rounding: HeightRounding,
    /// Folded plate, or the unfolded thick lens it comes from (the reference).
    #[serde(default)]
    pub surface: Surface,
    /// Where the samples sit (the thesis's convention unless a file says otherwise).
    #[serde(default)]
    pub sampling: SamplingConvention,
    /// The camera behind the display.
    pub camera: PhaseCamera,
}

impl PhaseDesign {
    /// The thesis's 600-DPI design: pitch 42 µm, f_MLA = pitch, n = 1.515, T = 1, fixed 530 nm.
    pub fn thesis(pitch_um: f64, fold: f64) -> Self {
        PhaseDesign {
            pitch_um,
            f_mla_um: pitch_um,
            refractive_index: THESIS_REFRACTIVE_INDEX,
            fold,
            open_ratio: THESIS_OPEN_RATIO,
            lambda0: Lambda0::Fixed { nm: 530.0 },
            height_step_um: None,
            height_rounding: HeightRounding::Floor,
            surface: Surface::Folded,
            sampling: SamplingConvention::Thesis,
            camera: PhaseCamera::thesis(),
        }
    }

    /// κ = f_MLA / opening (eq. 4.13's design choice; 4.2 in the thesis).
    pub fn kappa(&self) -> f64 {
        self.f_mla_um / (self.pitch_um * self.open_ratio)
    }

    /// Whether the plate repeats from lenslet to lenslet, so that a sampling with
    /// [`Relay::LensletPeriod`] takes the fast route: one λ0 for every lenslet (a fixed λ0, or
    /// a plan that names one) under the thesis convention (the centred one does not place
    /// lenslets on whole samples).
    pub fn has_lenslet_period(&self) -> bool {
        let one_lambda0 = match &self.lambda0 {
            Lambda0::Fixed { .. } => true,
            Lambda0::Uniform => false,
            Lambda0::Counts { counts } => counts.iter().filter(|&&c| c > 0).count() <= 1,
            Lambda0::PerLenslet { nm } => nm.windows(2).all(|w| w[0] == w[1]),
        };
        one_lambda0 && self.sampling == SamplingConvention::Thesis
    }

    /// Full field of view, eq. 4.13: `2 atan(1 / (2κ))`, in degrees.
    pub fn fov_deg(&self) -> f64 {
        (2.0 * (0.5 / self.kappa()).atan()).to_degrees()
    }

    /// LTR at the edge of the FoV, eq. 4.14 `1 − 1/κ`, before the polariser's ½.
    pub fn ltr_min(&self) -> f64 {
        1.0 - 1.0 / self.kappa()
    }

    /// Checks every parameter; the message names the field.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] for a NaN, negative or out-of-range value.
    pub fn validate(&self) -> Result<(), SimError> {
        let in_range = |field: &str, v: f64, lo: f64, hi: f64, unit: &str| {
            if v.is_finite() && v >= lo && v <= hi {
                Ok(())
            } else {
                Err(SimError::invalid(
                    field,
                    format!("{v:?} is outside {lo}–{hi} {unit}"),
                ))
            }
        };
        in_range("pitch_um", self.pitch_um, 1.0, 2000.0, "µm")?;
        in_range("f_mla_um", self.f_mla_um, 1.0, 10_000.0, "µm")?;
        in_range("refractive_index", self.refractive_index, 1.01, 4.0, "")?;
        in_range("fold", self.fold, 0.05, 100.0, "(T)")?;
        in_range("open_ratio", self.open_ratio, 0.01, 1.0, "")?;
        if let Some(step) = self.height_step_um {
            in_range("height_step_um", step, 0.001, 10.0, "µm")?;
        }
        match &self.lambda0 {
            Lambda0::Fixed { nm } => in_range("lambda0.nm", *nm, 300.0, 1100.0, "nm")?,
            Lambda0::Uniform => {}
            Lambda0::Counts { counts } => {
                if counts.len() != GRID_LEN {
                    return Err(SimError::invalid(
                        "lambda0.counts",
                        format!(
                            "has {} entries; one per grid wavelength ({GRID_LEN})",
                            counts.len()
                        ),
                    ));
                }
            }
            Lambda0::PerLenslet { nm } => {
                for (i, v) in nm.iter().enumerate() {
                    in_range(&format!("lambda0.nm[{i}]"), *v, 300.0, 1100.0, "nm")?;
                }
            }
        }
        let c = &self.camera;
        in_range(
            "camera.focal_length_mm",
            c.focal_length_mm,
            0.1,
            1000.0,
            "mm",
        )?;
        in_range("camera.f_number", c.f_number, 0.5, 64.0, "")?;
        in_range("camera.pixel_um", c.pixel_um, 0.1, 100.0, "µm")?;
        if c.pixels < 8 || c.pixels > 8192 || !c.pixels.is_multiple_of(2) {
            return Err(SimError::invalid(
                "camera.pixels",
                format!("{} must be even and within 8–8192", c.pixels),
            ));
        }
        // The lenslet count must be known before counts and per-lenslet lists can be checked.
        let lenslets = geometry::lenslet_count(self);
        match &self.lambda0 {
            Lambda0::Counts { counts } => {
                // A count from a file can be near usize::MAX: add up without overflowing.
                match counts.iter().try_fold(0usize, |sum, c| sum.checked_add(*c)) {
                    Some(total) if total == lenslets => Ok(()),
                    Some(total) => Err(SimError::invalid(
                        "lambda0.counts",
                        format!("sum to {total}, but this design has {lenslets} lenslets"),
                    )),
                    None => Err(SimError::invalid(
                        "lambda0.counts",
                        format!(
                            "sum to more than {}, but this design has {lenslets} lenslets",
                            usize::MAX
                        ),
                    )),
                }
            }
            Lambda0::PerLenslet { nm } if nm.len() != lenslets => Err(SimError::invalid(
                "lambda0.nm",
                format!(
                    "has {} entries, but this design has {lenslets} lenslets",
                    nm.len()
                ),
            )),
            _ => Ok(()),
        }
    }
}

impl PhaseSampling {
    /// Checks both sampling parameters.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] for a sample outside 5 nm – 1 µm or 1–64 fine samples.
    pub fn validate(&self) -> Result<(), SimError> {
        if !(self.display_sample_um >= 0.005 && self.display_sample_um <= 1.0) {
            return Err(SimError::invalid(
                "sampling.display_sample_um",
                format!("{:?} is outside 0.005–1 µm", self.display_sample_um),
            ));
        }
        if self.fine_per_pixel == 0 || self.fine_per_pixel > 64 {
            return Err(SimError::invalid(
                "sampling.fine_per_pixel",
                format!("{} is outside 1–64", self.fine_per_pixel),
            ));
        }
        Ok(())
    }
}
