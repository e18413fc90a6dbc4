//! `udc-studio phase`: the phase-mask designer of thesis chapter 4 from the command line.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::{Args, Subcommand};
use serde_json::json;

use crate::drc::{Checked, report_lines, strict_error};
use crate::{JobArgs, run_job};
use udc_core::Progress;
use udc_core::phase::Surface;
use udc_io::phase::design::load_phase_design;
use udc_io::phase::export::HeightFormat;
use udc_jobs::JobSpec;
use udc_jobs::phase::{
    InvertibilityJob, Mask, OptimizeJob, PsfJob, RestoreJob, design_of, resolve_lambda0,
    sampling_of,
};

/// A subcommand of `udc-studio phase`.
#[derive(Debug, Subcommand)]
pub enum PhaseCommand {
    /// PSF per colour channel through the double MLA beside the bare T-OLED's: energy, peak,
    /// invertibility, LTR and FoV.
    Psf(JobArgs<PsfJob>),
    /// The 30 × 30 invertibility matrix V over λ0, λ = 401:10:691 nm (900 propagations).
    Invertibility(JobArgs<InvertibilityJob>),
    /// Allocate folding wavelengths to lenslets (eqs. 4.9–4.11, Algorithm 1).
    Optimize(JobArgs<OptimizeJob>),
    /// Write the plate's height map for fabrication: CSV, 16-bit PNG, multi-level GDSII or STL.
    Export(ExportArgs),
    /// Capture a photo through the masks (or the bare T-OLED) and restore it (§4.5): PSNR and
    /// SSIM per light level on the field of view.
    Restore(JobArgs<RestoreJob>),
}

/// Arguments of `udc-studio phase export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The mask, and the output file (`--out`); with `--design` only `--out` and `--json` apply.
    #[command(flatten)]
    pub mask: Mask,
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
    /// Print one JSON object instead of the pretty-printed report.
    #[arg(long)]
    pub json: bool,
}

/// Runs `udc-studio phase …`: a job, or the export of a plate.
///
/// # Errors
/// Invalid parameters, unreadable spectral tables, unwritable outputs.
pub fn phase_cmd(cmd: PhaseCommand, progress: &Progress) -> Result<()> {
    match cmd {
        PhaseCommand::Psf(a) => run_job(JobSpec::PhasePsf(a.job), a.json, progress),
        PhaseCommand::Invertibility(a) => {
            run_job(JobSpec::PhaseInvertibility(a.job), a.json, progress)
        }
        PhaseCommand::Optimize(a) => run_job(JobSpec::PhaseOptimize(a.job), a.json, progress),
        PhaseCommand::Restore(a) => run_job(JobSpec::PhaseRestore(a.job), a.json, progress),
        PhaseCommand::Export(a) => export_cmd(&a, progress),
    }
}

/// Runs `udc-studio phase export`.
///
/// # Errors
/// Bad values (naming the flag), a refused design rule with `--strict`, unwritable files.
pub fn export_cmd(a: &ExportArgs, progress: &Progress) -> Result<()> {
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
            d.lambda0 =
                resolve_lambda0(&a.lambda0, &d, &sampling_of(&a.mask), None, None, progress)?;
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
    let rules = a.rules.resolve()?;
    let drc = udc_core::phase::drc::check_plate(&design, &rules).map_err(flag_names)?;
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
        phase_min_feature_um: rules.phase_min_feature_um,
    };
    let written = udc_io::phase::export::write_height(a.format, &design, file, &params);
    let summary = written.map_err(flag_names)?;
    // The design-rule minimum a fab must write: the narrowest ring, at a lenslet's edge.
    let mut report = serde_json::to_value(&summary)?;
    let lenslets = udc_core::phase::geometry::Lenslets::new(&design)?;
    if let (Some(n), Some(obj)) = (
        udc_core::phase::plate::narrowest_feature(&design, &lenslets, rules.phase_min_feature_um)?,
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
    if a.json {
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
