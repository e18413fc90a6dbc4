//! `figure`: one of the display views saved as a figure file (SVG or PNG at a chosen size) with
//! its axes, units, colour bar, legend and a caption naming the design: the figure the studio's
//! Save figure writes, from a script.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use serde::{Deserialize, Serialize};
use serde_json::json;

use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with_route};
use udc_core::figure::{FIGURE_SIDE_PX, FigureFormat};
use udc_core::psf::route::Backend;
use udc_core::views::saved::{
    DisplayView, ViewSettings, check_floor_decades, compare_figure, display_figure,
};
use udc_core::{Design, Progress};

use super::DesignSelection;
use crate::Report;

/// The parameters of `figure`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub struct FigureJob {
    /// The design.
    #[command(flatten)]
    #[serde(flatten)]
    pub selection: DesignSelection,
    /// Which view.
    #[arg(long, value_parser = crate::choice::choice::<DisplayView>(), default_value_t = DisplayView::LogPsf)]
    #[serde(default)]
    pub view: DisplayView,
    /// The channel a one-channel view shows, by name (R, G, B); the first by default.
    #[arg(long, value_name = "NAME")]
    #[serde(default)]
    pub channel: Option<String>,
    /// Decades below the peak a log-PSF or RGB picture reaches.
    #[arg(long, value_name = "DECADES", default_value_t = ViewSettings::default().floor_decades)]
    #[serde(default = "default_floor")]
    pub floor_decades: f64,
    /// Decades below 1 the 2-D MTF reaches.
    #[arg(long, value_name = "DECADES", default_value_t = ViewSettings::default().mtf_floor_decades)]
    #[serde(default = "default_mtf_floor")]
    pub mtf_floor_decades: f64,
    /// The figure file: `.svg` (scalable) or `.png`.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Width of the figure, pixels (PNG) or user units (SVG).
    #[arg(long, value_name = "PX", default_value_t = 960)]
    #[serde(default = "default_width")]
    pub width_px: u32,
    /// Height of the figure, pixels (PNG) or user units (SVG).
    #[arg(long, value_name = "PX", default_value_t = 600)]
    #[serde(default = "default_height")]
    pub height_px: u32,
    /// The caption under the figure instead of the one naming the design.
    #[arg(long, value_name = "TEXT", conflicts_with = "no_caption")]
    #[serde(default)]
    pub caption: Option<String>,
    /// No caption.
    #[arg(long)]
    #[serde(default)]
    pub no_caption: bool,
    /// Interactive preview quality (as `analyze --preview`): faster, AUC within 3 %.
    #[arg(long)]
    #[serde(default)]
    pub preview: bool,
    /// Design A of a comparison (the studio's Compare tab), from a design file: `--view mtf`
    /// then draws its radially-minimum MTFs dashed under the design's.
    #[arg(long, value_name = "FILE", conflicts_with = "against_preset")]
    #[serde(default)]
    pub against_design: Option<PathBuf>,
    /// Design A of a comparison, as a built-in preset (see `--against-design`).
    #[arg(long, value_name = "NAME")]
    #[serde(default)]
    pub against_preset: Option<String>,
    /// Where the PSFs are computed: cpu, gpu or auto (as `analyze --backend`).
    #[arg(long, value_parser = crate::choice::choice::<Backend>(), default_value_t = Backend::Cpu)]
    #[serde(default)]
    pub backend: Backend,
}

impl Default for FigureJob {
    fn default() -> Self {
        FigureJob {
            selection: DesignSelection::default(),
            view: DisplayView::default(),
            channel: None,
            floor_decades: default_floor(),
            mtf_floor_decades: default_mtf_floor(),
            out: PathBuf::new(),
            width_px: default_width(),
            height_px: default_height(),
            caption: None,
            no_caption: false,
            preview: false,
            against_design: None,
            against_preset: None,
            backend: Backend::Cpu,
        }
    }
}

fn default_floor() -> f64 {
    ViewSettings::default().floor_decades
}
fn default_mtf_floor() -> f64 {
    ViewSettings::default().mtf_floor_decades
}
fn default_width() -> u32 {
    960
}
fn default_height() -> u32 {
    600
}

/// Runs `figure`.
///
/// # Errors
/// A file name that is neither `.svg` nor `.png`, a size outside the allowed sides, a floor
/// out of range, an unknown channel, a design that does not resolve or simulate, an
/// unwritable file.
pub fn figure(job: &FigureJob, progress: &Progress) -> Result<Report> {
    job.check()?;
    let design = job.selection.resolve()?;
    figure_of(&design, job, progress)
}

impl FigureJob {
    /// Checks what the user typed, before anything is simulated.
    ///
    /// # Errors
    /// The first bad value, naming its flag.
    pub fn check(&self) -> Result<()> {
        if FigureFormat::of_path(&self.out).is_none() {
            bail!("--out {}: name a .svg or .png file", self.out.display());
        }
        for (flag, v) in [
            ("--width-px", self.width_px),
            ("--height-px", self.height_px),
        ] {
            if !FIGURE_SIDE_PX.contains(&v) {
                bail!(
                    "{flag} {v}: give {} to {} px",
                    FIGURE_SIDE_PX.start(),
                    FIGURE_SIDE_PX.end()
                );
            }
        }
        for (flag, v) in [
            ("--floor-decades", self.floor_decades),
            ("--mtf-floor-decades", self.mtf_floor_decades),
        ] {
            check_floor_decades(v).map_err(|e| anyhow::anyhow!("{flag} {e}"))?;
        }
        if self.against_design.is_some() && self.against_preset.is_some() {
            bail!("--against-design and --against-preset: give one design A");
        }
        if self.against().is_some() && self.view != DisplayView::Mtf {
            bail!(
                "--view {}: only the mtf view compares two designs (--against-design, \
                 --against-preset)",
                self.view
            );
        }
        Ok(())
    }

    /// Design A of a comparison, as the flags name it.
    fn against(&self) -> Option<DesignSelection> {
        match (&self.against_design, &self.against_preset) {
            (Some(d), _) => Some(DesignSelection {
                design: Some(d.clone()),
                ..DesignSelection::default()
            }),
            (None, Some(p)) => Some(DesignSelection {
                preset: Some(p.clone()),
                ..DesignSelection::default()
            }),
            (None, None) => None,
        }
    }
}

/// `figure` of a design already in hand (the Python package's `Design`), the job's selection
/// aside.
///
/// # Errors
/// As [`figure`].
pub fn figure_of(design: &Design, job: &FigureJob, progress: &Progress) -> Result<Report> {
    job.check()?;
    let Some(format) = FigureFormat::of_path(&job.out) else {
        bail!("--out {}: name a .svg or .png file", job.out.display());
    };
    let options = AnalyzeOptions {
        quality: if job.preview {
            Quality::Preview
        } else {
            Quality::Full
        },
        expected_psf: false,
    };
    let route = crate::backend::route(job.backend)?;
    let against = match job.against() {
        Some(sel) => {
            let a = sel.resolve().context("design A (--against-…)")?;
            let analysis =
                analyze_with_route(&a, &options, &route, progress).context("design A")?;
            Some((a, analysis))
        }
        None => None,
    };
    let analysis = analyze_with_route(design, &options, &route, progress)?;
    let channel = match &job.channel {
        None => 0,
        Some(name) => analysis
            .channels
            .iter()
            .position(|c| c.name.eq_ignore_ascii_case(name))
            .with_context(|| {
                let names: Vec<&str> = analysis.channels.iter().map(|c| c.name.as_str()).collect();
                format!(
                    "--channel {name}: the design's channels are {}",
                    names.join(", ")
                )
            })?,
    };
    let settings = ViewSettings {
        channel,
        floor_decades: job.floor_decades,
        mtf_floor_decades: job.mtf_floor_decades,
        ..ViewSettings::default()
    };
    let mut figure = match &against {
        Some((a, a_analysis)) => compare_figure((a, a_analysis), (design, &analysis)),
        None => display_figure(design, &analysis, job.view, &settings)?,
    };
    if job.no_caption {
        figure.caption = None;
    } else if let Some(c) = &job.caption {
        figure.caption = Some(c.clone());
    }
    if let Some(dir) = job.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    udc_io::figure::write_figure(&job.out, &figure, format, (job.width_px, job.height_px))?;
    let mut out = Report::default();
    let title = figure.panels.first().map_or("", |p| p.title.as_str());
    outln!(
        out,
        "wrote {} ({}, {}×{}): {title}",
        job.out.display(),
        match format {
            FigureFormat::Svg => "SVG",
            FigureFormat::Png => "PNG",
        },
        job.width_px,
        job.height_px
    );
    if let Some(c) = &figure.caption {
        outln!(out, "caption: {c}");
    }
    out.json = json!({
        "file": job.out,
        "format": format,
        "view": job.view,
        "title": title,
        "caption": figure.caption,
        "against": against.as_ref().map(|(a, _)| a.name.clone()),
        "width_px": job.width_px,
        "height_px": job.height_px,
    });
    crate::backend::report(&mut out, job.backend, &route);
    Ok(out)
}
