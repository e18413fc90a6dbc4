//! `udc-studio drc`: the design-rule check of a display mask or a phase plate before it goes to
//! a fab, and the rules `export --strict` and `phase export --strict` check against.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;

use super::DesignSelection;
use udc_core::Progress;
use udc_core::mask::Tone;
use udc_core::mask::drc::{DrcReport, Rules, ViolationKind, check};
use udc_core::phase::drc::check_plate;
use udc_io::mask::{ChecksumCheck, MaskFormat, check_file};
use udc_io::phase::design::{is_phase_design_file, load_phase_design};

/// The rules to check against: a file, then flags over it.
#[derive(Debug, Args, Clone)]
pub struct RuleArgs {
    /// Rules file (JSON: `min_feature_um`, `min_gap_um`, `no_corner_contact`,
    /// `min_angle_deg`, and optionally `phase_min_feature_um`); flags override it. Without it:
    /// 2-µm features and gaps, no corner contacts, no acute angles, 0.5-µm phase-plate rings.
    #[arg(long)]
    pub rules: Option<PathBuf>,
    /// Smallest opening, µm (0: not checked).
    #[arg(long)]
    pub min_feature_um: Option<f64>,
    /// Smallest chrome gap between openings, µm (0: not checked).
    #[arg(long)]
    pub min_gap_um: Option<f64>,
    /// Accept openings that touch at a corner only.
    #[arg(long)]
    pub allow_corner_contact: bool,
    /// Smallest polygon angle, degrees (0: not checked).
    #[arg(long)]
    pub min_angle_deg: Option<f64>,
    /// Narrowest fold ring or height step of a phase plate, µm (0: not checked).
    #[arg(long)]
    pub phase_min_feature_um: Option<f64>,
}

/// Arguments of `udc-studio drc`.
#[derive(Debug, Args)]
pub struct DrcArgs {
    /// What to check: a display design (or preset), a phase design file (phase_design.json,
    /// as `phase optimize --out` writes), told apart by its content, or a mask file (.gds,
    /// .oas, .dxf): the polygons it holds on one layer.
    #[command(flatten)]
    pub selection: DesignSelection,
    /// Mask files: the layer checked.
    #[arg(long, default_value_t = 1)]
    pub layer: i16,
    /// Mask files: the datatype checked.
    #[arg(long, default_value_t = 0)]
    pub datatype: i16,
    /// Mask files: what the polygons are, `open` or `chrome` [default: the file's TONE note,
    /// else open].
    #[arg(long)]
    pub tone: Option<Tone>,
    /// Mask files: check even when the file's SHA-256 (the `.sha256` or manifest beside it)
    /// does not match.
    #[arg(long)]
    pub ignore_checksum: bool,
    /// The rules.
    #[command(flatten)]
    pub rules: RuleArgs,
    /// Exit with an error when any rule is broken.
    #[arg(long)]
    pub strict: bool,
    /// Print the report as one JSON object.
    #[arg(long)]
    pub json: bool,
}

impl RuleArgs {
    /// The rules: the file's, then the flags.
    ///
    /// # Errors
    /// An unreadable or invalid rules file, or a rule out of range.
    pub fn resolve(&self) -> Result<Rules> {
        let mut r = match &self.rules {
            Some(path) => {
                let text = udc_io::safe_file::read_text_bounded(path, 64 * 1024, "rules file")
                    .with_context(|| format!("rules file {}", path.display()))?;
                serde_json::from_str::<Rules>(&text)
                    .with_context(|| format!("rules file {}", path.display()))?
            }
            None => Rules::default(),
        };
        for (flag, rule) in [
            (self.min_feature_um, &mut r.min_feature_um),
            (self.min_gap_um, &mut r.min_gap_um),
            (self.min_angle_deg, &mut r.min_angle_deg),
            (self.phase_min_feature_um, &mut r.phase_min_feature_um),
        ] {
            if let Some(v) = flag {
                *rule = v;
            }
        }
        if self.allow_corner_contact {
            r.no_corner_contact = false;
        }
        for (name, v, max) in [
            ("min_feature_um", r.min_feature_um, 1e4),
            ("min_gap_um", r.min_gap_um, 1e4),
            ("min_angle_deg", r.min_angle_deg, 180.0),
            ("phase_min_feature_um", r.phase_min_feature_um, 1e4),
        ] {
            if !(v.is_finite() && (0.0..=max).contains(&v)) {
                bail!("{name}: must be 0 … {max} (got {v:?})");
            }
        }
        Ok(r)
    }
}

/// What was checked: the report's words and JSON `kind` differ.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Checked {
    /// A display mask.
    Display,
    /// A phase plate.
    Phase,
}

impl Checked {
    fn json_name(self) -> &'static str {
        match self {
            Checked::Display => "display",
            Checked::Phase => "phase",
        }
    }
}

/// The report as text lines: the smallest widths, then up to ten violations of each kind.
pub fn report_lines(report: &DrcReport, checked: Checked) -> Vec<String> {
    let um = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:.3} µm"));
    let mut out = vec![match checked {
        Checked::Display => format!(
            "smallest opening {}, smallest chrome gap {}, corner contacts {}",
            um(report.min_feature_um),
            um(report.min_gap_um),
            report.corner_contacts
        ),
        Checked::Phase => format!(
            "narrowest ring or height step {} (rule {:.3} µm)",
            um(report.min_feature_um),
            report.rules.phase_min_feature_um
        ),
    }];
    let feature = match checked {
        Checked::Display => "openings narrower than the minimum feature",
        Checked::Phase => "rings or steps narrower than the phase-plate minimum",
    };
    let kinds = [
        (ViolationKind::MinFeature, feature),
        (
            ViolationKind::MinGap,
            "chrome gaps narrower than the minimum gap",
        ),
        (ViolationKind::CornerContact, "corner contacts"),
        (ViolationKind::AcuteAngle, "acute polygon angles"),
    ];
    for (kind, what) in kinds {
        let count = report.counts[kind as usize];
        if count > 0 {
            out.push(format!("{count} {what}:"));
            for v in report.violations.iter().filter(|v| v.kind == kind).take(10) {
                out.push(match kind {
                    ViolationKind::CornerContact => format!("  {}", v.place),
                    ViolationKind::AcuteAngle => format!("  {}: {:.1}°", v.place, v.value),
                    _ => format!("  {}: {:.3} µm", v.place, v.value),
                });
            }
        }
    }
    if report.is_clean() {
        out.push("no violation".into());
    }
    out
}

/// The error `--strict` ends with.
pub fn strict_error(report: &DrcReport) -> anyhow::Error {
    anyhow::anyhow!(
        "{} design-rule violations (--strict): nothing written",
        report.total()
    )
}

/// Runs `udc-studio drc`.
///
/// # Errors
/// A bad design, mask or rules file, bad rule values, or (with `--strict`) any violation.
pub fn drc_cmd(args: &DrcArgs) -> Result<()> {
    let rules = args.rules.resolve()?;
    let mask_flags =
        args.tone.is_some() || args.ignore_checksum || args.layer != 1 || args.datatype != 0;
    if let Some(path) = mask_file(&args.selection)? {
        return mask_file_cmd(args, path, &rules);
    }
    if mask_flags {
        bail!("--layer, --datatype, --tone and --ignore-checksum apply to mask files only");
    }
    let (name, report, checked) = match phase_file(&args.selection)? {
        Some(path) => {
            let loaded = load_phase_design(path)?;
            let name = path.file_stem().map_or_else(
                || "phase design".into(),
                |s| s.to_string_lossy().into_owned(),
            );
            (name, check_plate(&loaded.design, &rules)?, Checked::Phase)
        }
        None => {
            let design = args.selection.resolve()?;
            let report = check(&design, &rules);
            (design.name, report, Checked::Display)
        }
    };
    if args.json {
        let v = serde_json::json!({
            "design": name,
            "kind": checked.json_name(),
            "clean": report.is_clean(),
            "report": report,
        });
        crate::emit_json(&v)?;
    } else {
        match checked {
            Checked::Display => println!("{name}: design-rule check"),
            Checked::Phase => println!("{name}: design-rule check of the phase plate"),
        }
        for line in report_lines(&report, checked) {
            println!("{line}");
        }
    }
    if args.strict && !report.is_clean() {
        bail!("{} design-rule violations (--strict)", report.total());
    }
    Ok(())
}

/// The selection's file when it is a mask file (by extension); display-only options are
/// refused with it.
fn mask_file(selection: &DesignSelection) -> Result<Option<&Path>> {
    let Some(path) = selection.design.as_deref() else {
        return Ok(None);
    };
    if !matches!(
        MaskFormat::of_path(path),
        Some(MaskFormat::Gds | MaskFormat::Oas | MaskFormat::Dxf)
    ) {
        return Ok(None);
    }
    if selection.pattern.is_some()
        || selection.pitch_um.is_some()
        || selection.tiling.is_some()
        || selection.seed.is_some()
        || selection.optics.is_some()
        || selection.spectral.is_some()
    {
        bail!(
            "{} is a mask file: --pattern, --pitch-um, --tiling, --seed, --optics and \
             --spectral apply to designs only",
            path.display()
        );
    }
    Ok(Some(path))
}

/// `udc-studio drc FILE.gds|.oas|.dxf`: the check of the polygons the file holds.
fn mask_file_cmd(args: &DrcArgs, path: &Path, rules: &Rules) -> Result<()> {
    let checksum = if args.ignore_checksum {
        ChecksumCheck::Ignore
    } else {
        ChecksumCheck::Verify
    };
    let (report, tone) = check_file(
        path,
        (args.layer, args.datatype),
        args.tone,
        rules,
        checksum,
        &Progress::new(),
    )?;
    let name = path.display().to_string();
    if args.json {
        let v = serde_json::json!({
            "file": name,
            "kind": "mask-file",
            "layer": args.layer,
            "datatype": args.datatype,
            "tone": tone.as_str(),
            "clean": report.is_clean(),
            "report": report,
        });
        crate::emit_json(&v)?;
    } else {
        println!(
            "{name}: design-rule check of layer {}/{} ({})",
            args.layer,
            args.datatype,
            tone.meaning()
        );
        for line in report_lines(&report, Checked::Display) {
            println!("{line}");
        }
    }
    if args.strict && !report.is_clean() {
        bail!("{} design-rule violations (--strict)", report.total());
    }
    Ok(())
}

/// The selection's file when it is a phase design; display-only options are refused with it.
fn phase_file(selection: &DesignSelection) -> Result<Option<&Path>> {
    let Some(path) = selection.design.as_deref() else {
        return Ok(None);
    };
    if !is_phase_design_file(path) {
        return Ok(None);
    }
    let display_only = selection.pattern.is_some()
        || selection.pitch_um.is_some()
        || selection.tiling.is_some()
        || selection.seed.is_some()
        || selection.optics.is_some()
        || selection.spectral.is_some();
    if display_only {
        bail!(
            "{} is a phase design: --pattern, --pitch-um, --tiling, --seed, --optics and \
             --spectral apply to display designs only",
            path.display()
        );
    }
    Ok(Some(path))
}
