//! `psf import`: a measured PSF from raw frames (one file, or a bracket of exposures with dark
//! frames) into a PSF set on disk (`.npy` and its `.json` sidecar), every step reported.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use serde::{Deserialize, Serialize};
use serde_json::json;

use udc_core::Progress;
use udc_core::measured::import::{Bracket, Centring, Exposure, ImportSteps, merge};
use udc_core::measured::{PsfChannel, PsfSet, PsfSource};
use udc_core::psf::route::Backend;
use udc_io::measured::read::{Encoding, FramePick, RawFrame, read_frame};

use crate::Report;

/// The parameters of `psf import`.
#[derive(Debug, Clone, Default, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", default, deny_unknown_fields)]
pub struct ImportJob {
    /// The frames: one file, or a bracket of exposures of the same point source (.npy, MATLAB
    /// v5 .mat, 16-bit PNG or TIFF, OpenEXR).
    #[arg(value_name = "FRAME", required_unless_present = "bracket")]
    pub frames: Vec<PathBuf>,
    /// The frames' exposure times in seconds, comma-separated, in the frames' order (one frame
    /// needs none).
    #[arg(long, value_name = "T1,T2,…", value_delimiter = ',')]
    #[serde(default, with = "crate::params::list")]
    pub exposures_s: Vec<f64>,
    /// A small TOML file naming the bracket instead: `[[exposure]]` tables with `file` and
    /// `exposure_s`, and `dark = ["d1.tif", …]`; paths relative to it.
    #[arg(long, value_name = "TOML", conflicts_with_all = ["frames", "exposures_s"])]
    pub bracket: Option<PathBuf>,
    /// A dark frame (the source covered, the same exposure); give it several times to average.
    #[arg(long, value_name = "FILE")]
    #[serde(default)]
    pub dark: Vec<PathBuf>,
    /// The page of a multi-page TIFF (a focus stack), from 1.
    #[arg(long)]
    pub page: Option<usize>,
    /// The variable of a MATLAB .mat file (for example `lin_hdr`).
    #[arg(long)]
    pub variable: Option<String>,
    /// The camera's pixel pitch, µm.
    #[arg(long, value_name = "UM")]
    pub pixel_um: f64,
    /// The wavelength the PSF was measured at (a grey frame), nm.
    #[arg(long, value_name = "NM")]
    pub wavelength_nm: Option<f64>,
    /// Keep the dark level (do not subtract the dark frames).
    #[arg(long)]
    pub no_dark: bool,
    /// Keep hot pixels.
    #[arg(long)]
    pub no_hot_pixels: bool,
    /// Merge saturated samples as if they were not.
    #[arg(long)]
    pub no_saturation: bool,
    /// Keep the background.
    #[arg(long)]
    pub no_background: bool,
    /// Where the PSF is centred.
    #[arg(long, value_parser = crate::choice::choice::<Centring>(), default_value_t = Centring::Centroid)]
    pub centre: Centring,
    /// The side of the square crop around the centre, pixels (default: the largest that fits,
    /// at most 1024).
    #[arg(long, value_name = "PX")]
    pub crop_px: Option<usize>,
    /// Keep the merged scale (counts per second) instead of unit sum.
    #[arg(long)]
    pub no_normalise: bool,
    /// The PSF set to write: a `.npy` array and its `.json` sidecar beside it.
    #[arg(long, value_name = "PSF.npy")]
    pub out: PathBuf,
}

/// The bracket file of `--bracket`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct BracketFile {
    exposure: Vec<BracketExposure>,
    #[serde(default)]
    dark: Vec<PathBuf>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct BracketExposure {
    file: PathBuf,
    exposure_s: f64,
}

/// The frames with their exposure times (s), and the dark frames.
type Listed = (Vec<(PathBuf, f64)>, Vec<PathBuf>);

impl ImportJob {
    /// The frames with their exposure times, and the dark frames.
    fn listed(&self) -> Result<Listed> {
        if let Some(file) = &self.bracket {
            let text = std::fs::read_to_string(file)
                .with_context(|| format!("cannot read the bracket file {}", file.display()))?;
            let b: BracketFile = toml::from_str(&text)
                .with_context(|| format!("not a bracket file: {}", file.display()))?;
            let base = file.parent().unwrap_or(Path::new("."));
            let frames = b
                .exposure
                .into_iter()
                .map(|e| (base.join(e.file), e.exposure_s))
                .collect();
            let darks = b
                .dark
                .iter()
                .chain(&self.dark)
                .map(|d| base.join(d))
                .collect();
            return Ok((frames, darks));
        }
        if self.frames.is_empty() {
            bail!("give the frames to import (or --bracket FILE)");
        }
        let times = match (self.frames.len(), self.exposures_s.len()) {
            (1, 0) => vec![1.0],
            (n, m) if n == m => self.exposures_s.clone(),
            (n, 0) => bail!("--exposures-s: {n} frames need {n} exposure times"),
            (n, m) => bail!("--exposures-s: {m} exposure times for {n} frames"),
        };
        Ok((
            self.frames.iter().cloned().zip(times).collect(),
            self.dark.clone(),
        ))
    }

    fn steps(&self) -> ImportSteps {
        ImportSteps {
            dark: !self.no_dark,
            hot_pixels: !self.no_hot_pixels,
            saturation: !self.no_saturation,
            background: !self.no_background,
            centring: self.centre,
            centre_px: None,
            crop_px: self.crop_px,
            normalise: !self.no_normalise,
        }
    }
}

/// Runs `psf import`.
///
/// # Errors
/// A bad pixel pitch or wavelength, frames that do not read or do not agree (size, channels,
/// encoding), a bracket the merge refuses, an unwritable output. Nothing is written then.
pub fn import(job: &ImportJob, progress: &Progress) -> Result<Report> {
    use udc_core::measured::{check_pixel_um, check_wavelength_nm, import::EXPOSURE_S_RANGE};
    check_pixel_um(job.pixel_um).map_err(|e| anyhow!("--pixel-um: {e}"))?;
    if let Some(w) = job.wavelength_nm {
        check_wavelength_nm(w).map_err(|e| anyhow!("--wavelength-nm: {e}"))?;
    }
    if let Some(t) = job
        .exposures_s
        .iter()
        .find(|t| !EXPOSURE_S_RANGE.contains(t))
    {
        bail!(
            "--exposures-s: an exposure time must be {} … {} s, got {t}",
            EXPOSURE_S_RANGE.start(),
            EXPOSURE_S_RANGE.end()
        );
    }
    if job.out.extension().and_then(|e| e.to_str()) != Some("npy") {
        bail!(
            "--out: a PSF set is written as .npy with a .json sidecar; got {}",
            job.out.display()
        );
    }
    let (listed, dark_paths) = job.listed()?;
    let pick = FramePick {
        page: job.page,
        variable: job.variable.clone(),
    };
    let mut notes = Vec::new();
    let mut read = |path: &Path| -> Result<RawFrame> {
        let f = read_frame(path, &pick)?;
        for n in &f.notes {
            let line = format!("{}: {n}", path.display());
            if !notes.contains(&line) {
                notes.push(line);
            }
        }
        Ok(f)
    };
    let frames: Vec<(RawFrame, f64)> = listed
        .iter()
        .map(|(p, t)| read(p).map(|f| (f, *t)))
        .collect::<Result<_>>()?;
    let darks: Vec<RawFrame> = dark_paths.iter().map(|p| read(p)).collect::<Result<_>>()?;
    let first = &frames[0].0;
    let channels = first.planes.len();
    for ((f, _), (path, _)) in frames.iter().zip(&listed) {
        if f.planes.len() != channels {
            bail!(
                "{}: {} channels, but {} has {channels}",
                path.display(),
                f.planes.len(),
                listed[0].0.display()
            );
        }
    }
    let gamma = frames.iter().any(|(f, _)| f.encoding == Encoding::Gamma8);
    let names: Vec<(String, Option<f64>)> = if channels == 3 {
        ["R", "G", "B"]
            .iter()
            .map(|n| ((*n).to_owned(), None))
            .collect()
    } else {
        vec![(
            job.wavelength_nm
                .map_or("measured".to_owned(), |w| format!("{w} nm")),
            job.wavelength_nm,
        )]
    };
    let bracket_of = |c: usize| Bracket {
        exposures: frames
            .iter()
            .map(|(f, t)| Exposure {
                frame: f.planes[c].clone(),
                exposure_s: *t,
            })
            .collect(),
        darks: darks
            .iter()
            .filter_map(|d| d.planes.get(c).cloned())
            .collect(),
        full_scale: first.full_scale,
    };
    let mut steps = job.steps();
    // The channels share one centre, found on their sum, so lateral colour is kept.
    if channels > 1 && steps.centre_px.is_none() && steps.centring != Centring::None {
        let mut sum = bracket_of(0);
        for c in 1..channels {
            let other = bracket_of(c);
            for (a, b) in sum.exposures.iter_mut().zip(other.exposures) {
                a.frame += &b.frame;
            }
            for (a, b) in sum.darks.iter_mut().zip(other.darks) {
                *a += &b;
            }
        }
        sum.full_scale = sum.full_scale.map(|f| f * channels as f64);
        let (_, r) = merge(&sum, &steps, progress)?;
        steps.centre_px = Some(r.centre_px);
        steps.crop_px = Some(r.side_px);
    }
    let mut set = PsfSet {
        channels: Vec::new(),
        pixel_um: job.pixel_um,
        source: PsfSource::Measured,
    };
    let mut reports = Vec::new();
    for (c, (name, wavelength_nm)) in names.into_iter().enumerate() {
        let (psf, report) =
            merge(&bracket_of(c), &steps, progress).with_context(|| format!("channel {name}"))?;
        set.channels.push(PsfChannel {
            name,
            wavelength_nm,
            psf,
        });
        reports.push(report);
    }
    let summary: Vec<String> = set
        .channels
        .iter()
        .zip(&reports)
        .map(|(c, r)| format!("{}: {}", c.name, r.summary()))
        .collect();
    let files = udc_io::measured::write_psf_set(&job.out, &set, Some(&summary.join(" | ")))?;
    let mut out = Report::default();
    for line in &summary {
        outln!(out, "{line}");
    }
    for r in &reports {
        for w in &r.warnings {
            let line = format!("warning: {w}");
            if !notes.contains(&line) {
                notes.push(line);
            }
        }
    }
    for n in &notes {
        outln!(out, "{n}");
    }
    for f in &files {
        outln!(out, "wrote {}", f.display());
    }
    out.json = json!({
        "pixel_um": set.pixel_um,
        "side_px": set.side_px(),
        "not_radiometric": gamma,
        "channels": set.channels.iter().zip(&reports).map(|(c, r)| json!({
            "name": c.name,
            "wavelength_nm": c.wavelength_nm,
            "import": r,
            "summary": r.summary(),
        })).collect::<Vec<_>>(),
        "notes": notes,
        "files": files,
    });
    Ok(out)
}

/// The parameters of `psf compare`.
#[derive(Debug, Clone, Default, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", default, deny_unknown_fields)]
pub struct CompareJob {
    /// The measured PSF set (`psf import`'s .npy, with its .json sidecar).
    #[arg(value_name = "PSF.npy")]
    pub psf: PathBuf,
    /// The design file (JSON) the prototype was built from.
    #[arg(long, conflicts_with = "preset")]
    pub design: Option<PathBuf>,
    /// Or a built-in preset (see `udc-studio presets`).
    #[arg(long)]
    pub preset: Option<String>,
    /// The camera's pixel pitch, µm (when the set has no sidecar; overrides it).
    #[arg(long, value_name = "UM")]
    pub pixel_um: Option<f64>,
    /// Write the figures (profile, MTF, residual and both PSFs per channel; PNG and SVG) into
    /// this folder.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Where the design's PSFs are computed: cpu, gpu or auto (as `analyze --backend`).
    #[arg(long, value_parser = crate::choice::choice::<Backend>(), default_value_t = Backend::Cpu)]
    #[serde(default)]
    pub backend: Backend,
}

/// The parameters of `psf fit`.
#[derive(Debug, Clone, Default, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", default, deny_unknown_fields)]
pub struct FitJob {
    /// The measured PSF set (`psf import`'s .npy, with its .json sidecar).
    #[arg(value_name = "PSF.npy")]
    pub psf: PathBuf,
    /// The design file (JSON) the prototype was built from: where the fit starts.
    #[arg(long, conflicts_with = "preset")]
    pub design: Option<PathBuf>,
    /// Or a built-in preset (see `udc-studio presets`).
    #[arg(long)]
    pub preset: Option<String>,
    /// The camera's pixel pitch, µm (when the set has no sidecar; overrides it).
    #[arg(long, value_name = "UM")]
    pub pixel_um: Option<f64>,
    /// Side of the central window fitted, pixels (8–512; the set's side when smaller).
    #[arg(long, value_name = "PX")]
    pub window_px: Option<usize>,
    /// Start the refinement from the design's pitch, without the coarse search (−20 … +25 %).
    #[arg(long)]
    #[serde(default)]
    pub no_search: bool,
    /// Write the fitted design (the start with the fitted pitch and edges) to this JSON file.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Where the display's fine intensities are computed: cpu, gpu or auto (as `analyze
    /// --backend`; the rest of the fit runs on the CPU).
    #[arg(long, value_parser = crate::choice::choice::<Backend>(), default_value_t = Backend::Cpu)]
    #[serde(default)]
    pub backend: Backend,
}

/// The measured set (`--pixel-um` checked, and used where the set has no sidecar) and the
/// design (`--design` or `--preset`) that `psf compare` and `psf fit` read.
///
/// # Errors
/// A bad pixel pitch, a set or design that does not load.
fn set_and_design(
    psf: &std::path::Path,
    pixel_um: Option<f64>,
    design: &Option<PathBuf>,
    preset: &Option<String>,
) -> Result<(PsfSet, udc_core::Design)> {
    use udc_io::measured::{SetDefaults, read_psf_set};
    if let Some(p) = pixel_um {
        udc_core::measured::check_pixel_um(p).map_err(|e| anyhow!("--pixel-um: {e}"))?;
    }
    let set = read_psf_set(
        psf,
        &SetDefaults {
            pixel_um,
            wavelength_nm: None,
        },
    )?;
    let selection = crate::display::DesignSelection {
        design: design.clone(),
        preset: preset.clone(),
        ..crate::display::DesignSelection::default()
    };
    Ok((set, selection.resolve()?))
}

/// Runs `psf fit`: the display's pitch, open fraction, turn and defocus fitted to a measured
/// set, starting from a design, each with its uncertainty.
///
/// # Errors
/// A set or design that does not load, a bad pixel pitch or window, an unwritable design.
pub fn fit(job: &FitJob, progress: &Progress) -> Result<Report> {
    use udc_core::measured::fit::{FitOptions, fit as fit_display};

    let defaults = FitOptions::default();
    let window_px = job.window_px.unwrap_or(defaults.window_px);
    if !(8..=512).contains(&window_px) {
        bail!("--window-px: the fitted window must be 8 … 512 pixels, got {window_px}");
    }
    let (set, design) = set_and_design(&job.psf, job.pixel_um, &job.design, &job.preset)?;
    let options = FitOptions {
        window_px,
        search_pitch: !job.no_search,
        ..defaults
    };
    let route = crate::backend::route(job.backend)?;
    let r = fit_display(&design, &set, &options, &route, progress).context("the fit")?;
    let mut out = Report::default();
    outln!(
        out,
        "{} fitted from {} over the central {} px",
        job.psf.display(),
        if design.name.is_empty() {
            "the design"
        } else {
            &design.name
        },
        options.window_px.min(set.side_px())
    );
    outln!(
        out,
        "pitch          {:10.3} ± {:.3} µm   (design {:.3} µm, coarse search {:.3} µm)",
        r.pitch_um.value,
        r.pitch_um.sigma,
        r.start_pitch_um,
        r.searched_pitch_um
    );
    outln!(
        out,
        "open fraction  {:10.4} ± {:.4}      (design {:.4}; edges moved {:+.3} ± {:.3} µm)",
        r.open_fraction.value,
        r.open_fraction.sigma,
        r.start_open_fraction,
        r.edge_bias_um.value,
        r.edge_bias_um.sigma
    );
    outln!(
        out,
        "rotation       {:10.3} ± {:.3} °    (counter-clockwise)",
        r.rotation_deg.value,
        r.rotation_deg.sigma
    );
    outln!(
        out,
        "defocus        {:10.1} ± {:.1} µm   (blur circle {:.2} ± {:.2} µm; side not known)",
        r.defocus_um.value,
        r.defocus_um.sigma,
        r.blur_um.value,
        r.blur_um.sigma
    );
    outln!(
        out,
        "residual       {:10.4} of the measured energy (the design as drawn: {:.4}); {} evaluations, {}",
        r.residual,
        r.residual_start,
        r.evaluations,
        if r.converged {
            "converged"
        } else {
            "not converged"
        }
    );
    if let Some(path) = &job.out {
        udc_io::design::file::save_design(path, &r.design)
            .with_context(|| format!("cannot write {}", path.display()))?;
        outln!(out, "wrote {}", path.display());
    }
    let estimate =
        |e: udc_core::measured::fit::Estimate| json!({"value": e.value, "sigma": e.sigma});
    out.json = json!({
        "psf": job.psf,
        "design": design.name,
        "pitch_um": estimate(r.pitch_um),
        "open_fraction": estimate(r.open_fraction),
        "edge_bias_um": estimate(r.edge_bias_um),
        "rotation_deg": estimate(r.rotation_deg),
        "defocus_um": estimate(r.defocus_um),
        "blur_um": estimate(r.blur_um),
        "start": {
            "pitch_um": r.start_pitch_um,
            "open_fraction": r.start_open_fraction,
            "searched_pitch_um": r.searched_pitch_um,
        },
        "residual": r.residual,
        "residual_start": r.residual_start,
        "evaluations": r.evaluations,
        "converged": r.converged,
        "stopped": r.stopped,
        "shifts_px": r.shifts_px,
        "axes_px": r.axes_px,
        "out": job.out,
    });
    crate::backend::report(&mut out, job.backend, &route);
    Ok(out)
}

/// Runs `psf compare`: the design simulated at the set's pixel pitch and side, each measured
/// channel aligned with its design channel, the residual and both MTFs.
///
/// # Errors
/// A set or design that does not load, a bad pixel pitch, a PSF larger than a design window
/// may be, unwritable figures.
pub fn compare(job: &CompareJob, progress: &Progress) -> Result<Report> {
    use udc_core::measured::figures::{self, FLOOR_DECADES, Side};

    let (set, design) = set_and_design(&job.psf, job.pixel_um, &job.design, &job.preset)?;
    let route = crate::backend::route(job.backend)?;
    let compared = udc_core::measured::compare::compare_set(&design, &set, &route, progress)
        .context("the design at the measurement's pixel pitch")?;
    let mut out = Report::default();
    let mut rows = Vec::new();
    let mut files = Vec::new();
    outln!(
        out,
        "{} ({} px at {} µm) against {} simulated at that pitch",
        job.psf.display(),
        set.side_px(),
        set.pixel_um,
        if design.name.is_empty() {
            "the design"
        } else {
            &design.name
        }
    );
    outln!(
        out,
        "channel      design  shift (px)      residual  correlation  AUC measured  AUC design"
    );
    for compared in &compared {
        let (channel, c) = (compared, &compared.comparison);
        outln!(
            out,
            "{:<12} {:<6}  {:+6.2} {:+6.2}   {:7.2} %  {:11.4}  {:12.4}  {:10.4}",
            channel.name,
            channel.design_channel,
            c.shift_px[0],
            c.shift_px[1],
            100.0 * c.residual_energy_share,
            c.correlation,
            c.mtf_measured.auc_radial_min,
            c.mtf_simulated.auc_radial_min
        );
        if let Some(dir) = &job.out {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("cannot create {}", dir.display()))?;
            let stem = channel
                .name
                .replace(|ch: char| !ch.is_ascii_alphanumeric(), "-");
            for (kind, panel) in [
                (
                    "profile",
                    figures::profile_panel(c, set.pixel_um, &channel.name),
                ),
                ("mtf", figures::mtf_panel(c, &channel.name)),
                (
                    "residual",
                    figures::residual_panel(c, set.pixel_um, &channel.name),
                ),
                (
                    "psf-measured",
                    figures::psf_panel(
                        c,
                        Side::Measured,
                        set.pixel_um,
                        &channel.name,
                        FLOOR_DECADES,
                    ),
                ),
                (
                    "psf-design",
                    figures::psf_panel(c, Side::Design, set.pixel_um, &channel.name, FLOOR_DECADES),
                ),
            ] {
                files.extend(udc_io::figure::write_panel(
                    dir,
                    &format!("{stem}-{kind}"),
                    &panel,
                )?);
            }
        }
        rows.push(json!({
            "channel": channel.name,
            "design_channel": channel.design_channel,
            "shift_px": c.shift_px,
            "residual_energy_share": c.residual_energy_share,
            "correlation": c.correlation,
            "auc_measured": c.mtf_measured.auc_radial_min,
            "auc_design": c.mtf_simulated.auc_radial_min,
            "mtf_radial_min_measured": c.mtf_measured.radial_min,
            "mtf_radial_min_design": c.mtf_simulated.radial_min,
            "frequencies_cyc_per_px": c.mtf_measured.freqs_cyc_per_px(),
        }));
    }
    for f in &files {
        outln!(out, "wrote {}", f.display());
    }
    out.json = json!({
        "psf": job.psf,
        "pixel_um": set.pixel_um,
        "design": design.name,
        "channels": rows,
        "files": files,
    });
    crate::backend::report(&mut out, job.backend, &route);
    Ok(out)
}
