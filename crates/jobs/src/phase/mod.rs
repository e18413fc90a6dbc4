//! Phase-mask jobs (thesis chapter 4): `phase psf`, `phase invertibility`, `phase optimize`
//! and `phase restore`, and the mask and camera they share.

mod design_cache;
mod psf;
mod restore;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, Result, bail};
use clap::Args;
use ndarray::Array2;
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

use crate::Report;
use crate::denoise::DenoiseFlags;
use udc_core::Progress;
use udc_core::design::Channel;
use udc_core::phase::allocate::{channel_invertibility, channel_matrix};
use udc_core::phase::chain::{BlochRelay, Chain};
use udc_core::phase::geometry::{lambda0_per_lenslet, lenslet_count, uniform_counts};
use udc_core::phase::{
    AllocationSettings, GRID_LEN, HeightRounding, Incidence, Lambda0, Lambda0Plan, PhaseDesign,
    PhaseOptics, PhaseSampling, Relay, SamplingConvention, Surface, kernel_matrix_on,
    optimize_lambda0_through, phase_psfs_on, v_matrix_through, wavelength_grid_nm,
};
use udc_core::psf::route::Backend;
use udc_io::design::spectral::{channels_from_response, load_response_csv, thesis_response};
use udc_io::numbers::json6 as r;
use udc_io::phase::design::save_phase_design;

pub use psf::{psf, psf_design};
pub use restore::restore;

/// The folding wavelength plan unless given: every lenslet folded for 530 nm (thesis §4.5).
const FIXED_530: &str = "fixed:530";

/// `--order`: the lenslets' λ0 left to right.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum OrderArg {
    /// The plan's own order: λ0 rising from left to right.
    #[default]
    Ascending,
    /// A seeded random permutation (`--seed`).
    Shuffled,
}

/// The parameters of `phase restore`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub struct RestoreJob {
    /// The mask and camera.
    #[command(flatten)]
    #[serde(flatten)]
    pub mask: Mask,
    /// The photo (PNG, JPEG, TIFF, HDR or EXR), linear in [0, 1]; at most 1024 px wide (the
    /// sensor's directions); larger photos are scaled down. Default: the built-in astronaut.
    /// Repeat with `--compare` to average over several photos.
    #[arg(long)]
    #[serde(with = "crate::params::paths")]
    pub photo: Vec<PathBuf>,
    /// Run the thesis's comparison instead of one setup: the bare T-OLED, T = 1 and 5 with fixed
    /// 530 nm, uniform and optimized λ0, shuffled orders, 0.2 µm steps and the pitches 56, 84
    /// and 168 µm (§4.5). Prints mean PSNR/SSIM per setup and light level; `--out` writes
    /// compare.csv with every row.
    #[arg(long, conflicts_with_all = ["bare", "quantize_um"])]
    pub compare: bool,
    /// Folding wavelengths: `fixed:NM`, `uniform` or `optimized`.
    #[arg(long, default_value_t = RestoreJob::default().lambda0)]
    pub lambda0: String,
    /// The lenslets' λ0 order.
    #[arg(long, value_enum, default_value_t = RestoreJob::default().order)]
    pub order: OrderArg,
    /// Floor the plate's heights to this step in µm (Fig. 4.10b: 0.2).
    #[arg(long, allow_negative_numbers = true)]
    pub quantize_um: Option<f64>,
    /// The bare T-OLED of the same pitch instead of the masks.
    #[arg(long)]
    pub bare: bool,
    /// Light levels: photons on an open display aperture per pixel, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = RestoreJob::default().photons, allow_negative_numbers = true)]
    #[serde(with = "crate::params::list")]
    pub photons: Vec<f64>,
    /// Seed of the noise (and of a shuffled order).
    #[arg(long, default_value_t = RestoreJob::default().seed)]
    pub seed: u64,
    /// Colour channels at the peak wavelengths R 610, G 530, B 470 nm (10× faster) instead of
    /// the thesis's spectral response over 401:10:691 nm.
    #[arg(long)]
    pub peaks: bool,
    /// Scale every photo, up or down, to this many columns (aspect kept), at most the sensor's
    /// pixels: 1024 is thesis §4.4.1's scene, as wide as the sensor. Default: the photo as it
    /// is, scaled down to the sensor if wider.
    #[arg(long)]
    pub scene_px: Option<usize>,
    /// Restore with thesis §4.4.1's 'full' boundary: the solver also estimates half the scene's
    /// width of directions beyond each edge (whose light the capture would hold had the scene
    /// gone on), then crops them off. The capture itself sees the scene alone.
    #[arg(long)]
    pub full_boundary: bool,
    /// The denoiser before the solver: `--denoise bm3d` (default) is the thesis's chapter 4
    /// (σ² and λ per light level, 150 iterations); `--denoise none` keeps λ = 30/(N·LTR).
    #[command(flatten)]
    #[serde(flatten)]
    pub denoise: DenoiseFlags,
    /// Where the operator's propagations through the double MLA on the wrapped grid run (a λ0
    /// plan, the slowest step): the CPU, a GPU (through Vulkan, Metal or DX12), or auto (a
    /// hardware GPU when there is one, else the CPU).
    #[arg(long, value_parser = crate::choice::choice::<Backend>(), default_value_t = Backend::Cpu)]
    #[serde(default)]
    pub backend: Backend,
}

impl Default for RestoreJob {
    fn default() -> Self {
        RestoreJob {
            mask: Mask::default(),
            photo: Vec::new(),
            compare: false,
            lambda0: FIXED_530.to_string(),
            order: OrderArg::Ascending,
            quantize_um: None,
            bare: false,
            photons: udc_core::phase::imaging::THESIS_PHOTONS.to_vec(),
            seed: 1,
            peaks: false,
            scene_px: None,
            full_boundary: false,
            denoise: DenoiseFlags::default(),
            backend: Backend::Cpu,
        }
    }
}

/// The mask and camera: the thesis's 600-DPI design unless overridden.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub struct Mask {
    /// Display (and lenslet) pitch in µm: 42 = 600 DPI, 168 = 150 DPI.
    #[arg(long, default_value_t = Mask::default().pitch_um, allow_negative_numbers = true)]
    pub pitch_um: f64,
    /// Fold thickness T: plate height T·λ0/(n − 1) (1 = phase SLM, 5 = thicker retarder).
    #[arg(long, default_value_t = Mask::default().fold, allow_negative_numbers = true)]
    pub fold: f64,
    /// Lenslet focal length in µm (default: the pitch, κ = 4.2).
    #[arg(long, allow_negative_numbers = true)]
    pub f_mla_um: Option<f64>,
    /// Refractive index of the lenslets.
    #[arg(long, default_value_t = Mask::default().n, allow_negative_numbers = true)]
    pub n: f64,
    /// Open fraction of a display pixel (T-OLED: 1/4.2 = 0.238).
    #[arg(long, allow_negative_numbers = true)]
    pub open_ratio: Option<f64>,
    /// Round fold heights and the profile to this fabrication step in µm (e.g. 0.2).
    #[arg(long, allow_negative_numbers = true)]
    pub height_step_um: Option<f64>,
    /// How `--height-step-um` quantises heights.
    #[arg(long, value_parser = crate::choice::choice::<HeightRounding>(), default_value_t = Mask::default().height_rounding)]
    pub height_rounding: HeightRounding,
    /// Sampling convention: `thesis` (the thesis code's, its numbers reproduce) or `centred`.
    #[arg(long, value_parser = crate::choice::choice::<SamplingConvention>(), default_value_t = Mask::default().sampling)]
    pub sampling: SamplingConvention,
    /// Coarse sampling (60 nm at the display, 7 samples per pixel) for quick looks.
    #[arg(long)]
    pub preview: bool,
    /// The relay through MLA 1, the display and MLA 2: `lenslet-period` (one lenslet with the
    /// direction's Bloch phase, for plates whose lenslets are all alike; V within 1e-3 of the
    /// whole display, many times faster; a λ0 plan takes `wrapped-display`), `wrapped-display`
    /// (the whole display on a grid of its own width, every plate, about 2× faster) or
    /// `whole-display` (the thesis code's, every plate).
    #[arg(long, value_parser = crate::choice::choice::<Relay>(), default_value_t = Mask::default().relay)]
    pub relay: Relay,
    /// Write CSV files into this directory (`phase psf`: also its PSF and MTF figures, SVG and
    /// PNG).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// The parameters of `phase psf`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub struct PsfJob {
    /// The mask and camera.
    #[command(flatten)]
    #[serde(flatten)]
    pub mask: Mask,
    /// Folding wavelengths: `fixed:NM` (all lenslets), `uniform` (400–700 nm evenly) or
    /// `optimized` (runs the allocation first).
    #[arg(long, default_value_t = PsfJob::default().lambda0)]
    pub lambda0: String,
    /// Incidence angle in degrees (off-axis PSF over the whole sensor).
    #[arg(long, default_value_t = PsfJob::default().angle_deg, allow_negative_numbers = true)]
    pub angle_deg: f64,
    /// Spectral channels from a response CSV (wavelength_nm,r,g,b) sampled at 401:10:691 nm,
    /// instead of the peak wavelengths R 610, G 530, B 470 nm.
    #[arg(long)]
    pub spectral: Option<PathBuf>,
    /// The unfolded thick lens instead of the folded plate (the reference).
    #[arg(long)]
    pub unfolded: bool,
    /// Lemma 1's comparison: one plate pressed against the display, no second array.
    #[arg(long)]
    pub single_mask: bool,
    /// Also write the blur matrix of all sensor directions per channel (eq. 4.12) into --out.
    #[arg(long, requires = "out")]
    pub all_angles: bool,
    /// Where the propagations through the double MLA on the wrapped grid run (a λ0 plan): the
    /// CPU, a GPU (through Vulkan, Metal or DX12), or auto (as `phase restore --backend`).
    #[arg(long, value_parser = crate::choice::choice::<Backend>(), default_value_t = Backend::Cpu)]
    #[serde(default)]
    pub backend: Backend,
}

/// The parameters of `phase invertibility`.
#[derive(Debug, Clone, Default, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub struct InvertibilityJob {
    /// The mask and camera whose V matrix is computed.
    #[command(flatten)]
    #[serde(flatten)]
    pub mask: Mask,
    /// Where V's 900 propagations run under `--relay wrapped-display` (the whole display on
    /// its wrapped grid): the CPU, a GPU (through Vulkan, Metal or DX12), or auto (as
    /// `phase restore --backend`). The lenslet period (one lenslet's samples) and the whole
    /// display stay on the CPU, as the report says.
    #[arg(long, value_parser = crate::choice::choice::<Backend>(), default_value_t = Backend::Cpu)]
    #[serde(default)]
    pub backend: Backend,
}

/// The parameters of `phase optimize`.
#[derive(Debug, Clone, Default, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub struct OptimizeJob {
    /// The mask and camera whose folding wavelengths are allocated.
    #[command(flatten)]
    #[serde(flatten)]
    pub mask: Mask,
    /// Sensor response CSV (wavelength_nm,r,g,b); default: the thesis's built-in response.
    #[arg(long)]
    pub spectral: Option<PathBuf>,
    /// Where V's propagations run (as `phase invertibility --backend`).
    #[arg(long, value_parser = crate::choice::choice::<Backend>(), default_value_t = Backend::Cpu)]
    #[serde(default)]
    pub backend: Backend,
}

impl Default for Mask {
    fn default() -> Self {
        Mask {
            pitch_um: 42.0,
            fold: 1.0,
            f_mla_um: None,
            n: 1.515,
            open_ratio: None,
            height_step_um: None,
            height_rounding: HeightRounding::Floor,
            sampling: SamplingConvention::Thesis,
            preview: false,
            relay: Relay::LensletPeriod,
            out: None,
        }
    }
}

impl Default for PsfJob {
    fn default() -> Self {
        PsfJob {
            mask: Mask::default(),
            lambda0: FIXED_530.to_string(),
            angle_deg: 0.0,
            spectral: None,
            unfolded: false,
            single_mask: false,
            all_angles: false,
            backend: Backend::Cpu,
        }
    }
}

/// A phase job's backend: the route (for its report) and the Bloch relay its chains get
/// (`None` on the CPU, whose relay a chain has of its own).
pub(crate) type RelayOf = (Arc<udc_gpu::Route>, Option<Arc<dyn BlochRelay>>);

/// `backend` resolved to a phase job's [`RelayOf`].
///
/// # Errors
/// `gpu` on a machine with no adapter.
pub(crate) fn relay_of(backend: Backend) -> Result<RelayOf> {
    let route = Arc::new(crate::backend::route(backend)?);
    let relay = (backend != Backend::Cpu).then(|| route.clone() as Arc<dyn BlochRelay>);
    Ok((route, relay))
}

/// `design` sampled by `sampling`, its Bloch relay on `relay` where one is given.
///
/// # Errors
/// As `Chain::new`.
pub(crate) fn chain_on(
    design: &PhaseDesign,
    sampling: &PhaseSampling,
    relay: Option<&Arc<dyn BlochRelay>>,
) -> Result<Chain> {
    Ok(Chain::new(design, sampling)?.with_relay_if(relay))
}

/// The phase design of a mask's parameters, checked (refusals name the flags).
///
/// # Errors
/// A value out of range.
pub fn design_of(m: &Mask) -> Result<PhaseDesign> {
    let mut d = PhaseDesign::thesis(m.pitch_um, m.fold);
    d.f_mla_um = m.f_mla_um.unwrap_or(m.pitch_um);
    d.refractive_index = m.n;
    if let Some(o) = m.open_ratio {
        d.open_ratio = o;
    }
    d.height_step_um = m.height_step_um;
    d.height_rounding = m.height_rounding;
    d.sampling = m.sampling;
    // Flag names, not field names, in the messages a CLI user sees.
    d.validate().map_err(|e| {
        anyhow::anyhow!(
            "{}",
            e.to_string()
                .replace("`pitch_um`", "--pitch-um")
                .replace("`fold`", "--fold")
                .replace("`f_mla_um`", "--f-mla-um")
                .replace("`refractive_index`", "--n")
                .replace("`open_ratio`", "--open-ratio")
                .replace("`height_step_um`", "--height-step-um")
        )
    })?;
    Ok(d)
}

/// The sampling of a mask's parameters (`--preview`, `--relay`).
pub fn sampling_of(m: &Mask) -> PhaseSampling {
    let grid = if m.preview {
        PhaseSampling::preview()
    } else {
        PhaseSampling::thesis()
    };
    grid.with_relay(m.relay)
}

fn grid_channels(spectral: Option<&Path>) -> Result<Vec<Channel>> {
    let response = match spectral {
        Some(p) => load_response_csv(p)?,
        None => thesis_response(),
    };
    channels_from_response(&response, &wavelength_grid_nm())
        .map_err(|e| anyhow::anyhow!("--spectral: {e}"))
}

fn parse_lambda0(s: &str) -> Result<Option<Lambda0>> {
    Lambda0Plan::parse(s)
        .map(Lambda0Plan::lambda0)
        .map_err(|why| anyhow::anyhow!("--lambda0 `{s}`: {why}"))
}

/// The λ0 plan of `--lambda0`; `optimized` runs the allocation for `design` first.
///
/// # Errors
/// A plan that does not parse; a cancelled allocation.
pub fn resolve_lambda0(
    text: &str,
    design: &PhaseDesign,
    sampling: &PhaseSampling,
    spectral: Option<&Path>,
    relay: Option<&Arc<dyn BlochRelay>>,
    progress: &Progress,
) -> Result<Lambda0> {
    if let Some(plan) = parse_lambda0(text)? {
        return Ok(plan);
    }
    let channels = grid_channels(spectral)?;
    let chain = chain_on(design, sampling, relay)?;
    let (_, alloc) =
        optimize_lambda0_through(&chain, &channels, &AllocationSettings::default(), progress)?;
    Ok(Lambda0::Counts {
        counts: alloc.counts,
    })
}

/// Runs `phase invertibility`.
///
/// # Errors
/// Bad values (naming the flag), unwritable outputs, cancellation.
pub fn invertibility(a: &InvertibilityJob, progress: &Progress) -> Result<Report> {
    let mut out = Report::default();
    let m = &a.mask;
    let design = design_of(m)?;
    let sampling = sampling_of(m);
    let (route, relay) = relay_of(a.backend)?;
    let chain = chain_on(&design, &sampling, relay.as_ref())?;
    let grid = wavelength_grid_nm();
    let v = v_matrix_through(&chain, &grid, &grid, progress)?;
    if let Some(dir) = &m.out {
        std::fs::create_dir_all(dir).with_context(|| format!("create {}", dir.display()))?;
        let path = dir.join("v.csv");
        let mut text = String::from("lambda0_nm\\lambda_nm");
        for l in &v.lambda_nm {
            text.push_str(&format!(",{l}"));
        }
        text.push('\n');
        for (l0, row) in v.lambda0_nm.iter().zip(&v.v) {
            text.push_str(&l0.to_string());
            for x in row {
                text.push_str(&format!(",{x}"));
            }
            text.push('\n');
        }
        udc_io::safe_file::write_atomic(&path, text.as_bytes())?;
        outln!(out, "wrote {}", path.display());
    }
    {
        let rows: Vec<Vec<Value>> =
            v.v.iter()
                .map(|row| row.iter().map(|&x| r(x)).collect())
                .collect();
        out.json = json!({ "lambda_nm": v.lambda_nm, "lambda0_nm": v.lambda0_nm, "v": rows });
    }
    {
        outln!(
            out,
            "V: invertibility (sum of the one-sided MTF) per λ0 (rows) and λ (columns), nm"
        );
        out!(out, "λ0\\λ ");
        for l in v.lambda_nm.iter().step_by(3) {
            out!(out, "{l:>6.0}");
        }
        outln!(out, "   (every third column)");
        for (l0, row) in v.lambda0_nm.iter().zip(&v.v) {
            out!(out, "{l0:>5.0}");
            for x in row.iter().step_by(3) {
                out!(out, "{x:>6.1}");
            }
            outln!(out);
        }
    }
    crate::backend::report(&mut out, a.backend, &route);
    Ok(out)
}

/// Runs `phase optimize`.
///
/// # Errors
/// Bad values (naming the flag), an unreadable response, unwritable outputs, cancellation.
pub fn optimize(a: &OptimizeJob, progress: &Progress) -> Result<Report> {
    let mut out = Report::default();
    let design = design_of(&a.mask)?;
    let sampling = sampling_of(&a.mask);
    let channels = grid_channels(a.spectral.as_deref())?;
    let settings = AllocationSettings::default();
    let (route, relay) = relay_of(a.backend)?;
    let chain = chain_on(&design, &sampling, relay.as_ref())?;
    let (v, alloc) = optimize_lambda0_through(&chain, &channels, &settings, progress)?;
    let lenslets = lenslet_count(&design);
    let matrix = channel_matrix(&v, &channels)?;
    let mut fixed = vec![0; GRID_LEN];
    // 530 nm is not on the 401:10:691 grid; its nearest grid wavelength is 531 nm.
    fixed[13] = lenslets;
    let fixed_inv = channel_invertibility(&matrix, &fixed);
    let uniform_inv = channel_invertibility(&matrix, &uniform_counts(lenslets));
    let mut optimized = design.clone();
    optimized.lambda0 = Lambda0::Counts {
        counts: alloc.counts.clone(),
    };
    if let Some(dir) = &a.mask.out {
        std::fs::create_dir_all(dir).with_context(|| format!("create {}", dir.display()))?;
        let path = dir.join("phase_design.json");
        save_phase_design(&path, &optimized)?;
        outln!(out, "wrote {}", path.display());
    }
    let three = |v: [f64; 3]| v.iter().map(|&x| r(x)).collect::<Vec<_>>();
    {
        out.json = json!({
            "lenslets": lenslets,
            "counts": alloc.counts,
            "lambda0_nm": alloc.lambda0_nm,
            "channel_invertibility": three(alloc.channel_invertibility),
            "fixed_530_invertibility": three(fixed_inv),
            "uniform_invertibility": three(uniform_inv),
            "x": alloc.x.iter().map(|&x| r(x)).collect::<Vec<_>>(),
            "final_t": alloc.final_t,
            "steps_per_stage": alloc.steps_per_stage,
        });
    }
    {
        outln!(
            out,
            "{lenslets} lenslets, pitch {} µm, T = {}; counts per λ0 (nm):",
            design.pitch_um,
            design.fold
        );
        for (l, c) in wavelength_grid_nm().iter().zip(&alloc.counts) {
            if *c > 0 {
                outln!(out, "  {l:>4.0}  {c:>3}  {}", "#".repeat(*c));
            }
        }
        let show = |v: [f64; 3]| format!("R {:.3}  G {:.3}  B {:.3}", v[0], v[1], v[2]);
        outln!(out, "invertibility (A·x, 1 = best single fold)");
        outln!(out, "  optimized   {}", show(alloc.channel_invertibility));
        outln!(out, "  fixed 531   {}", show(fixed_inv));
        outln!(out, "  uniform     {}", show(uniform_inv));
    }
    crate::backend::report(&mut out, a.backend, &route);
    Ok(out)
}
