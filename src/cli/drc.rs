//! `udc-studio drc`: the design-rule check of a display mask before it goes to a fab.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;

use super::DesignSelection;
use crate::core::mask::drc::{Rules, ViolationKind, check};

/// Arguments of `udc-studio drc`.
#[derive(Debug, Args)]
pub struct DrcArgs {
    /// The design to check.
    #[command(flatten)]
    pub selection: DesignSelection,
    /// Rules file (JSON: `min_feature_um`, `min_gap_um`, `no_corner_contact`,
    /// `min_angle_deg`); flags override it. Without it: 2-µm features and gaps, no corner
    /// contacts, no acute angles.
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
    /// Exit with an error when any rule is broken.
    #[arg(long)]
    pub strict: bool,
    /// Print the report as one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// The rules of `args`: the file's, then the flags.
fn rules(args: &DrcArgs) -> Result<Rules> {
    let mut r = match &args.rules {
        Some(path) => {
            let text = crate::io::safe_file::read_text_bounded(path, 64 * 1024, "rules file")
                .with_context(|| format!("rules file {}", path.display()))?;
            serde_json::from_str::<Rules>(&text)
                .with_context(|| format!("rules file {}", path.display()))?
        }
        None => Rules::default(),
    };
    if let Some(v) = args.min_feature_um {
        r.min_feature_um = v;
    }
    if let Some(v) = args.min_gap_um {
        r.min_gap_um = v;
    }
    if let Some(v) = args.min_angle_deg {
        r.min_angle_deg = v;
    }
    if args.allow_corner_contact {
        r.no_corner_contact = false;
    }
    for (name, v, max) in [
        ("min_feature_um", r.min_feature_um, 1e4),
        ("min_gap_um", r.min_gap_um, 1e4),
        ("min_angle_deg", r.min_angle_deg, 180.0),
    ] {
        if !(v.is_finite() && (0.0..=max).contains(&v)) {
            bail!("{name}: must be 0 … {max} (got {v:?})");
        }
    }
    Ok(r)
}

/// Runs `udc-studio drc`.
///
/// # Errors
/// A bad design or rules file, bad rule values, or (with `--strict`) any violation.
pub fn drc_cmd(args: &DrcArgs) -> Result<()> {
    let design = args.selection.resolve()?;
    let rules = rules(args)?;
    let report = check(&design, &rules);
    let kinds = [
        (
            ViolationKind::MinFeature,
            "openings narrower than the minimum feature",
        ),
        (
            ViolationKind::MinGap,
            "chrome gaps narrower than the minimum gap",
        ),
        (ViolationKind::CornerContact, "corner contacts"),
        (ViolationKind::AcuteAngle, "acute polygon angles"),
    ];
    if args.json {
        let v = serde_json::json!({
            "design": design.name,
            "clean": report.is_clean(),
            "report": report,
        });
        println!("{v}");
    } else {
        let um = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:.3} µm"));
        println!("{}: design-rule check", design.name);
        println!(
            "smallest opening {}, smallest chrome gap {}, corner contacts {}",
            um(report.min_feature_um),
            um(report.min_gap_um),
            report.corner_contacts
        );
        for (kind, what) in kinds {
            let count = report.counts[kind as usize];
            if count > 0 {
                println!("{count} {what}:");
                for v in report.violations.iter().filter(|v| v.kind == kind).take(10) {
                    match kind {
                        ViolationKind::CornerContact => println!("  {}", v.place),
                        ViolationKind::AcuteAngle => println!("  {}: {:.1}°", v.place, v.value),
                        _ => println!("  {}: {:.3} µm", v.place, v.value),
                    }
                }
            }
        }
        if report.is_clean() {
            println!("no violation");
        }
    }
    if args.strict && !report.is_clean() {
        let total: usize = report.counts.iter().sum();
        bail!("{total} design-rule violations (--strict)");
    }
    Ok(())
}
