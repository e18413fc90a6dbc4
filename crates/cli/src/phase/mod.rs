//! `udc-studio phase`: the phase-mask designer of thesis chapter 4 from the command line.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand};
use ndarray::Array2;
use serde_json::{Value, json};

use crate::drc::{Checked, report_lines, strict_error};
use udc_core::Progress;
use udc_core::design::Channel;
use udc_core::phase::allocate::{channel_invertibility, channel_matrix};
use udc_core::phase::geometry::{lambda0_per_lenslet, lenslet_count, uniform_counts};
use udc_core::phase::{
    AllocationSettings, GRID_LEN, HeightRounding, Incidence, Lambda0, PhaseDesign, PhaseOptics,
    PhaseSampling, Relay, SamplingConvention, Surface, kernel_matrix, optimize_lambda0, phase_psfs,
    v_matrix, wavelength_grid_nm,
};
use udc_io::design::spectral::{channels_from_response, load_response_csv, thesis_response};
use udc_io::numbers::json6 as r;
use udc_io::phase::design::{load_phase_design, save_phase_design};
use udc_io::phase::export::HeightFormat;

/// A subcommand of `udc-studio phase`.
#[derive(Debug, Subcommand)]
pub enum PhaseCommand {
    /// PSF per colour channel through the double MLA beside the bare T-OLED's: energy, peak,
    /// invertibility, LTR and FoV.
    Psf(PsfArgs),
    /// The 30 × 30 invertibility matrix V over λ0, λ = 401:10:691 nm (900 propagations).
    Invertibility(MaskArgs),
    /// Allocate folding wavelengths to lenslets (eqs. 4.9–4.11, Algorithm 1).
    Optimize(OptimizeArgs),
    /// Write the plate's height map for fabrication: CSV, 16-bit PNG, multi-level GDSII or STL.
    Export(ExportArgs),
    /// Capture a photo through the masks (or the bare T-OLED) and restore it (§4.5): PSNR and
    /// SSIM per light level on the field of view.
    Restore(RestoreArgs),
}

/// `--order`: the lenslets' λ0 left to right.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum OrderArg {
    /// The plan's own order: λ0 rising from left to right.
    Ascending,
    /// A seeded random permutation (`--seed`).
    Shuffled,
}

/// Arguments of `udc-studio phase restore`.
#[derive(Debug, Args)]
pub struct RestoreArgs {
    /// The mask and camera.
    #[command(flatten)]
    pub mask: MaskArgs,
    /// The photo (PNG, JPEG, TIFF, HDR or EXR), linear in [0, 1]; at most 1024 px wide (the
    /// sensor's directions); larger photos are scaled down. Default: the built-in astronaut.
    /// Repeat with `--compare` to average over several photos.
    #[arg(long)]
    pub photo: Vec<PathBuf>,
    /// Run the thesis's comparison instead of one setup: the bare T-OLED, T = 1 and 5 with fixed
    /// 530 nm, uniform and optimized λ0, shuffled orders, 0.2 µm steps and the pitches 56, 84
    /// and 168 µm (§4.5). Prints mean PSNR/SSIM per setup and light level; `--out` writes
    /// compare.csv with every row.
    #[arg(long, conflicts_with_all = ["bare", "quantize_um"])]
    pub compare: bool,
    /// Folding wavelengths: `fixed:NM`, `uniform` or `optimized`.
    #[arg(long, default_value = "fixed:530")]
    pub lambda0: String,
    /// The lenslets' λ0 order.
    #[arg(long, value_enum, default_value_t = OrderArg::Ascending)]
    pub order: OrderArg,
    /// Floor the plate's heights to this step in µm (Fig. 4.10b: 0.2).
    #[arg(long, allow_negative_numbers = true)]
    pub quantize_um: Option<f64>,
    /// The bare T-OLED of the same pitch instead of the masks.
    #[arg(long)]
    pub bare: bool,
    /// Light levels: photons on an open display aperture per pixel, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = udc_core::phase::imaging::THESIS_PHOTONS.to_vec(), allow_negative_numbers = true)]
    pub photons: Vec<f64>,
    /// Seed of the noise (and of a shuffled order).
    #[arg(long, default_value_t = 1)]
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
    pub denoise: crate::denoise_flags::DenoiseFlags,
}

/// Arguments of `udc-studio phase export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The mask, and the output file (`--out`); with `--design` only `--out` and `--json` apply.
    #[command(flatten)]
    pub mask: MaskArgs,
    /// Folding wavelengths: `fixed:NM`, `uniform` or `optimized` (as for `psf`).
    #[arg(long, default_value = "fixed:530")]
    pub lambda0: String,
    /// A design written by `phase optimize --out` (phase_design.json) instead of the flags.
    #[arg(long, conflicts_with = "lambda0")]
    pub design: Option<PathBuf>,
    /// The unfolded thick lens instead of the folded plate.
    #[arg(long)]
    pub unfolded: bool,
    /// The file format; `--out FILE` names the file.
    #[arg(long, value_parser = crate::choice::choice::<HeightFormat>())]
    pub format: HeightFormat,
    /// Sample spacing along x in µm (CSV, PNG pixel size, STL chord length).
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    pub sample_um: f64,
    /// PNG rows (the plate is uniform along y).
    #[arg(long, default_value_t = 16)]
    pub rows: usize,
    /// Extent along y in µm (GDSII, STL).
    #[arg(long, default_value_t = 1000.0, allow_negative_numbers = true)]
    pub length_um: f64,
    /// STL base thickness under the plate in µm.
    #[arg(long, default_value_t = 5.0, allow_negative_numbers = true)]
    pub base_um: f64,
    /// Fixed GDSII timestamps (2000-01-01 00:00:00): identical exports are byte-identical.
    #[arg(long)]
    pub deterministic: bool,
    /// The design rules checked before writing (`--phase-min-feature-um` applies to a plate).
    #[command(flatten)]
    pub rules: crate::drc::RuleArgs,
    /// Refuse to write the plate when a ring or step breaks the rule (else they are warnings).
    #[arg(long)]
    pub strict: bool,
}

/// The mask and camera: the thesis's 600-DPI design unless overridden.
#[derive(Debug, Args, Clone)]
pub struct MaskArgs {
    /// Display (and lenslet) pitch in µm: 42 = 600 DPI, 168 = 150 DPI.
    #[arg(long, default_value_t = 42.0, allow_negative_numbers = true)]
    pub pitch_um: f64,
    /// Fold thickness T: plate height T·λ0/(n − 1) (1 = phase SLM, 5 = thicker retarder).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub fold: f64,
    /// Lenslet focal length in µm (default: the pitch, κ = 4.2).
    #[arg(long, allow_negative_numbers = true)]
    pub f_mla_um: Option<f64>,
    /// Refractive index of the lenslets.
    #[arg(long, default_value_t = 1.515, allow_negative_numbers = true)]
    pub n: f64,
    /// Open fraction of a display pixel (T-OLED: 1/4.2 = 0.238).
    #[arg(long, allow_negative_numbers = true)]
    pub open_ratio: Option<f64>,
    /// Round fold heights and the profile to this fabrication step in µm (e.g. 0.2).
    #[arg(long, allow_negative_numbers = true)]
    pub height_step_um: Option<f64>,
    /// How `--height-step-um` quantises heights.
    #[arg(long, value_parser = crate::choice::choice::<HeightRounding>(), default_value_t = HeightRounding::Floor)]
    pub height_rounding: HeightRounding,
    /// Sampling convention: `thesis` (the thesis code's, its numbers reproduce) or `centred`.
    #[arg(long, value_parser = crate::choice::choice::<SamplingConvention>(), default_value_t = SamplingConvention::Thesis)]
    pub sampling: SamplingConvention,
    /// Coarse sampling (60 nm at the display, 7 samples per pixel) for quick looks.
    #[arg(long)]
    pub preview: bool,
    /// The relay through MLA 1, the display and MLA 2: `lenslet-period` (one lenslet with the
    /// direction's Bloch phase, for plates whose lenslets are all alike; V within 1e-3 of the
    /// whole display, many times faster; a λ0 plan takes `wrapped-display`), `wrapped-display`
    /// (the whole display on a grid of its own width, every plate, about 2× faster) or
    /// `whole-display` (the thesis code's, every plate).
    #[arg(long, value_parser = crate::choice::choice::<Relay>(), default_value_t = Relay::LensletPeriod)]
    pub relay: Relay,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Write CSV files into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Arguments of `udc-studio phase psf`.
#[derive(Debug, Args)]
pub struct PsfArgs {
    /// The mask and camera.
    #[command(flatten)]
    pub mask: MaskArgs,
    /// Folding wavelengths: `fixed:NM` (all lenslets), `uniform` (400–700 nm evenly) or
    /// `optimized` (runs the allocation first).
    #[arg(long, default_value = "fixed:530")]
    pub lambda0: String,
    /// Incidence angle in degrees (off-axis PSF over the whole sensor).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
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
}

/// Arguments of `udc-studio phase optimize`.
#[derive(Debug, Args)]
pub struct OptimizeArgs {
    /// The mask and camera whose folding wavelengths are allocated.
    #[command(flatten)]
    pub mask: MaskArgs,
    /// Sensor response CSV (wavelength_nm,r,g,b); default: the thesis's built-in response.
    #[arg(long)]
    pub spectral: Option<PathBuf>,
}

fn design_of(m: &MaskArgs) -> Result<PhaseDesign> {
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

fn sampling_of(m: &MaskArgs) -> PhaseSampling {
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

/// Runs `job` with `progress` while a thread reports it on stderr (only on a terminal).
fn with_progress<T>(progress: &Progress, label: &str, job: impl FnOnce(&Progress) -> T) -> T {
    let show = std::io::stderr().is_terminal() && !crate::in_sweep();
    if !show {
        return job(progress);
    }
    let (done_tx, done_rx) = std::sync::mpsc::channel::<()>();
    std::thread::scope(|scope| {
        let reporter = scope.spawn(move || {
            while done_rx.recv_timeout(Duration::from_secs(1)).is_err() {
                eprint!("\r{label}: {:3.0} %", 100.0 * progress.fraction());
            }
            eprintln!("\r{label}: done   ");
        });
        let out = job(progress);
        drop(done_tx);
        let _ = reporter.join();
        out
    })
}

/// Runs `udc-studio phase …`.
///
/// # Errors
/// Invalid parameters, unreadable spectral tables, unwritable outputs.
pub fn phase_cmd(cmd: &PhaseCommand, progress: &Progress) -> Result<()> {
    match cmd {
        PhaseCommand::Psf(a) => psf_cmd(a, progress),
        PhaseCommand::Invertibility(m) => invertibility_cmd(m, progress),
        PhaseCommand::Optimize(a) => optimize_cmd(a, progress),
        PhaseCommand::Export(a) => export_cmd(a, progress),
        PhaseCommand::Restore(a) => restore_cmd(a, progress),
    }
}

fn parse_lambda0(s: &str) -> Result<Option<Lambda0>> {
    let t = s.trim().to_ascii_lowercase();
    if t == "uniform" {
        return Ok(Some(Lambda0::Uniform));
    }
    if t == "optimized" {
        return Ok(None);
    }
    if let Some(v) = t.strip_prefix("fixed:") {
        let nm: f64 = v
            .trim()
            .parse()
            .map_err(|_| anyhow::anyhow!("--lambda0 `{s}`: `{v}` is not a wavelength in nm"))?;
        return Ok(Some(Lambda0::Fixed { nm }));
    }
    bail!("--lambda0 `{s}`: expected fixed:NM (e.g. fixed:530), uniform or optimized")
}

/// The λ0 plan of `--lambda0`; `optimized` runs the allocation for `design` first.
fn resolve_lambda0(
    text: &str,
    design: &PhaseDesign,
    sampling: &PhaseSampling,
    spectral: Option<&Path>,
    progress: &Progress,
) -> Result<Lambda0> {
    if let Some(plan) = parse_lambda0(text)? {
        return Ok(plan);
    }
    let channels = grid_channels(spectral)?;
    let (_, alloc) = with_progress(progress, "optimizing λ0", |p| {
        optimize_lambda0(
            design,
            sampling,
            &channels,
            &AllocationSettings::default(),
            p,
        )
    })?;
    Ok(Lambda0::Counts {
        counts: alloc.counts,
    })
}

fn invertibility_cmd(m: &MaskArgs, progress: &Progress) -> Result<()> {
    let design = design_of(m)?;
    let sampling = sampling_of(m);
    let v = with_progress(progress, "V (900 propagations)", |p| {
        v_matrix(&design, &sampling, p)
    })?;
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
        if !m.json {
            println!("wrote {}", path.display());
        }
    }
    if m.json {
        let rows: Vec<Vec<Value>> =
            v.v.iter()
                .map(|row| row.iter().map(|&x| r(x)).collect())
                .collect();
        crate::emit_json(
            &json!({ "lambda_nm": v.lambda_nm, "lambda0_nm": v.lambda0_nm, "v": rows }),
        )?;
    } else {
        println!("V: invertibility (sum of the one-sided MTF) per λ0 (rows) and λ (columns), nm");
        print!("λ0\\λ ");
        for l in v.lambda_nm.iter().step_by(3) {
            print!("{l:>6.0}");
        }
        println!("   (every third column)");
        for (l0, row) in v.lambda0_nm.iter().zip(&v.v) {
            print!("{l0:>5.0}");
            for x in row.iter().step_by(3) {
                print!("{x:>6.1}");
            }
            println!();
        }
    }
    Ok(())
}

fn optimize_cmd(a: &OptimizeArgs, progress: &Progress) -> Result<()> {
    let design = design_of(&a.mask)?;
    let sampling = sampling_of(&a.mask);
    let channels = grid_channels(a.spectral.as_deref())?;
    let settings = AllocationSettings::default();
    let (v, alloc) = with_progress(progress, "optimizing λ0", |p| {
        optimize_lambda0(&design, &sampling, &channels, &settings, p)
    })?;
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
        if !a.mask.json {
            println!("wrote {}", path.display());
        }
    }
    let three = |v: [f64; 3]| v.iter().map(|&x| r(x)).collect::<Vec<_>>();
    if a.mask.json {
        crate::emit_json(&json!({
            "lenslets": lenslets,
            "counts": alloc.counts,
            "lambda0_nm": alloc.lambda0_nm,
            "channel_invertibility": three(alloc.channel_invertibility),
            "fixed_530_invertibility": three(fixed_inv),
            "uniform_invertibility": three(uniform_inv),
            "x": alloc.x.iter().map(|&x| r(x)).collect::<Vec<_>>(),
            "final_t": alloc.final_t,
            "steps_per_stage": alloc.steps_per_stage,
        }))?;
    } else {
        println!(
            "{lenslets} lenslets, pitch {} µm, T = {}; counts per λ0 (nm):",
            design.pitch_um, design.fold
        );
        for (l, c) in wavelength_grid_nm().iter().zip(&alloc.counts) {
            if *c > 0 {
                println!("  {l:>4.0}  {c:>3}  {}", "#".repeat(*c));
            }
        }
        let show = |v: [f64; 3]| format!("R {:.3}  G {:.3}  B {:.3}", v[0], v[1], v[2]);
        println!("invertibility (A·x, 1 = best single fold)");
        println!("  optimized   {}", show(alloc.channel_invertibility));
        println!("  fixed 531   {}", show(fixed_inv));
        println!("  uniform     {}", show(uniform_inv));
    }
    Ok(())
}

fn export_cmd(a: &ExportArgs, progress: &Progress) -> Result<()> {
    let Some(file) = &a.mask.out else {
        bail!("phase export needs --out FILE (e.g. --out plate.gds)");
    };
    let inputs: Vec<&std::path::Path> = a.design.iter().map(PathBuf::as_path).collect();
    udc_io::safe_file::check_not_an_input(file, &inputs)?;
    let mut design = match &a.design {
        Some(path) => {
            let loaded = load_phase_design(path)?;
            for note in &loaded.notes {
                eprintln!("note: {}: {note}", path.display());
            }
            loaded.design
        }
        None => {
            let mut d = design_of(&a.mask)?;
            d.lambda0 = resolve_lambda0(&a.lambda0, &d, &sampling_of(&a.mask), None, progress)?;
            d.validate().map_err(|e| {
                anyhow::anyhow!("{}", e.to_string().replace("`lambda0.nm`", "--lambda0"))
            })?;
            d
        }
    };
    if a.unfolded {
        design.surface = Surface::Unfolded;
    }
    // Checked first: a strict export that fails leaves nothing behind.
    let drc =
        udc_core::phase::drc::check_plate(&design, &a.rules.resolve()?).map_err(flag_names)?;
    if a.strict && !drc.is_clean() {
        for line in report_lines(&drc, Checked::Phase) {
            eprintln!("{line}");
        }
        return Err(strict_error(&drc));
    }
    let params = udc_io::phase::export::HeightParams {
        sample_um: a.sample_um,
        rows: a.rows,
        length_um: a.length_um,
        base_um: a.base_um,
        deterministic: a.deterministic,
    };
    let written = udc_io::phase::export::write_height(a.format, &design, file, &params);
    let summary = written.map_err(flag_names)?;
    // The design-rule minimum a fab must write: the narrowest ring, at a lenslet's edge.
    let mut report = serde_json::to_value(&summary)?;
    let lenslets = udc_core::phase::geometry::Lenslets::new(&design)?;
    if let (Some(n), Some(obj)) = (
        udc_core::phase::plate::narrowest_feature(&design, &lenslets)?,
        report.as_object_mut(),
    ) {
        obj.insert(
            "narrowest_feature_um".into(),
            serde_json::json!(udc_io::numbers::round_sig(n.width_um(), 6)),
        );
        obj.insert(
            "narrowest_feature_at_um".into(),
            serde_json::json!(udc_io::numbers::round_sig(n.x0_um, 6)),
        );
    }
    if let Some(obj) = report.as_object_mut() {
        obj.insert(
            "drc".into(),
            json!({ "clean": drc.is_clean(), "report": drc }),
        );
    }
    if !drc.is_clean() {
        eprintln!(
            "warning: {} design-rule violations (--strict refuses them):",
            drc.total()
        );
        for line in report_lines(&drc, Checked::Phase) {
            eprintln!("warning: {line}");
        }
    }
    if a.mask.json {
        crate::emit_json(&report)?;
    } else {
        println!("{}", serde_json::to_string_pretty(&report)?);
    }
    Ok(())
}

/// A writer's or checker's message with the design fields it names as the flags a CLI user
/// knows; without the error's source chain, which repeats the same message.
fn flag_names(e: impl std::fmt::Display) -> anyhow::Error {
    let mut text = e.to_string();
    for (field, flag) in [
        ("height_step_um", "--height-step-um"),
        ("sample_um", "--sample-um"),
        ("length_um", "--length-um"),
        ("base_um", "--base-um"),
        ("rows", "--rows"),
    ] {
        text = text.replace(field, flag);
    }
    anyhow::anyhow!("{text}")
}

mod design_cache;
mod psf;
mod restore;

use psf::psf_cmd;
use restore::restore_cmd;
