//! `analyze`: PSF, MTF, AUC, LTR and invertibility of a display design.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use serde::{Deserialize, Serialize};

use udc_core::analysis::advice::{AdviceScope, advise_in};
use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with_route};
use udc_core::psf::route::Backend;
use udc_core::{Analysis, Design, Progress};
use udc_io::display::{export, report};

use super::DesignSelection;
use crate::Report;

/// The parameters of `analyze`.
#[derive(Debug, Clone, Default, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub struct AnalyzeJob {
    /// The design to analyse.
    #[command(flatten)]
    #[serde(flatten)]
    pub selection: DesignSelection,
    /// Also write the PSFs (EXR, 16-bit PNG), log-PSFs (PNG) and mtf.csv into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Interactive preview quality: twice the fine PSF spacing where the f-number oversamples
    /// the PSF enough for the AUC to stay within 3 % (about 4× faster), full quality otherwise
    /// (the thesis recipe at f/2.5).
    #[arg(long)]
    pub preview: bool,
    /// Also look for a fix for each note (a documented property of the thesis recipe), not
    /// only for each warning; every fix is checked by a further analysis.
    #[arg(long)]
    pub advice: bool,
    /// Where the PSFs are computed: the CPU (f64, the reference), a GPU (f32, through
    /// Vulkan, Metal or DX12), or auto (a hardware GPU when there is one, else the CPU).
    #[arg(long, value_parser = crate::choice::choice::<Backend>(), default_value_t = Backend::Cpu)]
    #[serde(default)]
    pub backend: Backend,
}

/// Runs `analyze`.
///
/// # Errors
/// A design that does not resolve, a refused size, unwritable outputs, cancellation.
pub fn analyze(job: &AnalyzeJob, progress: &Progress) -> Result<Report> {
    let design = job.selection.resolve()?;
    let options = AnalyzeOptions {
        quality: if job.preview {
            Quality::Preview
        } else {
            Quality::Full
        },
        expected_psf: job.out.is_some(),
    };
    let route = crate::backend::route(job.backend)?;
    let mut analysis = analyze_with_route(&design, &options, &route, progress)?;
    // A fix is checked by a further analysis: paid for where the numbers are off (warnings),
    // and for the notes only when asked.
    let scope = if job.advice {
        AdviceScope::All
    } else {
        AdviceScope::Warnings
    };
    advise_in(&design, &mut analysis.warnings, scope, progress)?;
    if let Some(dir) = &job.out {
        export::write_analysis_outputs(dir, &analysis)?;
    }
    let mut out = Report {
        json: report::analysis_json(&analysis),
        text: String::new(),
    };
    table(&mut out, &design, &analysis);
    crate::backend::report(&mut out, job.backend, &route);
    Ok(out)
}

fn table(out: &mut Report, design: &Design, a: &Analysis) {
    outln!(
        out,
        "{}: {} cells of {:.2} µm, pitch {:.1} µm ({:.0} DPI), tiling {}",
        if design.name.is_empty() {
            "design"
        } else {
            &design.name
        },
        design.opening.n(),
        design.opening.cell_um(),
        design.opening.pitch_um,
        design.opening.dpi(),
        design.tiling.mode.as_str()
    );
    outln!(
        out,
        "open fraction {:.4}   LTR {:.4}   L_inv {:.4}   {:.1} ms",
        a.open_fraction,
        a.ltr,
        a.invertibility_loss,
        a.elapsed_ms
    );
    outln!(
        out,
        "channel  λ (nm)   FFT    AUC(min)  AUC/0.5   AUC(mean)  in window"
    );
    for c in &a.channels {
        outln!(
            out,
            "{:<8} {:>6.1}  {:>5}   {:.5}   {:.5}   {:.5}    {:.4}",
            c.name,
            c.wavelength_nm,
            c.fft_sizes.first().copied().unwrap_or(0),
            c.mtf.auc_radial_min,
            c.mtf.auc_normalised(),
            c.mtf.auc_radial_mean,
            c.energy_in_window
        );
    }
    for w in &a.warnings {
        outln!(out, "{}: {w}", w.severity.as_str());
        if let Some(fix) = &w.fix {
            outln!(
                out,
                "  advice: set {} ({})",
                fix.assignments(),
                fix.summary()
            );
        }
    }
}
