//! `udc-studio reproduce`: every thesis result in one command. Each result is one or two sweep
//! specs in `presets/reproduce/` run by the sweep engine in-process (so a run resumes, and
//! `sweep slurm` runs the big ones on a cluster), then reduced to rows beside the thesis's
//! numbers, the claims of its text checked, and written as report.md, results.csv and plots.

pub use udc_core::reproduce as catalog;
pub mod outcome;
pub mod prepare;
mod reduce_display;
mod reduce_phase;
mod reduce_plate;
mod reduce_sensor;
pub mod report;
pub mod thesis;

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use udc_core::psf::route::Backend;

pub use catalog::ResultId;
use outcome::SweepTable;
pub use outcome::{Claim, Outcome, ReportRow, Value};
use report::RunInfo;

use udc_core::sweep::Shard;

/// Arguments of `udc-studio reproduce`.
#[derive(Debug, Args)]
pub struct ReproduceArgs {
    /// The result to reproduce (see `--list`).
    #[arg(value_parser = crate::choice::choice::<ResultId>(), required_unless_present = "list", value_name = "ID")]
    pub id: Option<ResultId>,
    /// List the results: ID, title, what each runs, the thesis numbers it checks, its cost.
    #[arg(long, conflicts_with_all = ["quick", "out"])]
    pub list: bool,
    /// Three photos of the test set at 256² and the phase model's preview sampling: about
    /// two minutes per result on 2 cores (the full run takes the whole test set).
    #[arg(long)]
    pub quick: bool,
    /// The results folder (default `reproduce/<id>`): report.md, results.csv, plots/ and the
    /// sweeps (a second run resumes them).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Worker threads (default: every core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print one JSON object (`{"id", "rows": [...], "claims": [...]}`) instead of the summary.
    #[arg(long)]
    pub json: bool,
    /// Table 4.1 and Fig. 4.14 only: the phase model's photos in the thesis's geometry (§4.4.1):
    /// scaled to the sensor's 1024 columns and restored with a 'full' boundary (twice as many
    /// columns, cropped back). A cluster-sized run: about 6 h on 2 cores for the whole test set;
    /// `udc-studio sweep slurm` runs its phase sweep as a job array.
    #[arg(long)]
    pub thesis_geometry: bool,
    /// Where the display and phase points compute their PSFs (`analyze`, `restore`, `phase
    /// psf`, `phase restore`; the others run on the CPU).
    #[command(flatten)]
    pub backend: udc_jobs::backend::BackendFlag,
}

/// Runs `udc-studio reproduce …`.
///
/// # Errors
/// A missing spec or photo, a sweep that cannot run, unwritable results.
pub fn reproduce_cmd(args: &ReproduceArgs) -> Result<()> {
    if args.list {
        print!("{}", listing());
        return Ok(());
    }
    let Some(id) = args.id else {
        anyhow::bail!(
            "give a result ID ({}) or --list",
            ResultId::ALL.map(ResultId::as_str).join(", ")
        );
    };
    let geometry = if args.thesis_geometry {
        catalog::Geometry::Thesis
    } else {
        catalog::Geometry::Ours
    };
    if !id.has_geometry(geometry) {
        anyhow::bail!(
            "--thesis-geometry: {} has no phase-model photos (it applies to table4.1 and fig4.14)",
            id.as_str()
        );
    }
    let out = args.out.clone().unwrap_or_else(|| {
        let d = id.default_out();
        if geometry == catalog::Geometry::Thesis {
            d.with_file_name(format!("{}-thesis-geometry", id.as_str()))
        } else {
            d
        }
    });
    // Resolved once: `gpu` without an adapter is one line before any point runs, and `auto`
    // says once why it computes on the CPU.
    let route = args.backend.route()?;
    if let Some(line) = args.backend.line(&route).filter(|_| !args.json) {
        eprintln!("{line}");
    }
    let options = ReproduceOptions {
        geometry,
        quick: args.quick,
        threads: args.threads,
        quiet: args.json,
        backend: args.backend.backend,
    };
    let run = reproduce(id, &out, &options, &udc_core::Progress::new())?;
    if args.json {
        crate::emit_json(&report::json_of(&run.info, &run.outcome, &run.report))?;
    } else {
        let passed = run.outcome.claims.iter().filter(|c| c.pass).count();
        println!("{} ({:.1} s)", id.title(), run.info.elapsed_s);
        for c in &run.outcome.claims {
            println!(
                "  {} {}: {}",
                if c.pass { "PASS" } else { "FAIL" },
                c.claim,
                c.measured
            );
        }
        println!(
            "{passed} of {} claims hold; wrote {}",
            run.outcome.claims.len(),
            run.report.display()
        );
    }
    Ok(())
}

/// The `--list` text: one block per result.
pub fn listing() -> String {
    let mut s = String::new();
    for id in ResultId::ALL {
        let (quick, full) = id.cost();
        s.push_str(&format!(
            "{:<9} {}\n          runs:   {}\n          checks: {}\n          cost:   --quick {quick}, full {full} (2 cores)\n",
            id.as_str(),
            id.title(),
            id.runs(),
            id.checks()
        ));
    }
    s
}

/// A finished reproduction.
#[derive(Debug, Clone)]
pub struct Reproduction {
    /// What ran.
    pub info: RunInfo,
    /// What it found.
    pub outcome: Outcome,
    /// The report's path.
    pub report: PathBuf,
}

/// How [`reproduce`] runs a result.
#[derive(Debug, Clone, Copy)]
pub struct ReproduceOptions {
    /// Our geometry or the thesis's (`--thesis-geometry`).
    pub geometry: catalog::Geometry,
    /// `--quick`: three photos at 256² and fewer costly settings.
    pub quick: bool,
    /// Worker threads (`None`: every core).
    pub threads: Option<usize>,
    /// No progress bar or summary on the terminal.
    pub quiet: bool,
    /// Where the points that take a backend compute their PSFs.
    pub backend: Backend,
}

/// Runs (or resumes) result `id` into `out` and writes its report; the one entry point of the
/// CLI and the tests.
///
/// # Errors
/// A missing spec or photo, a sweep that cannot run, unwritable results.
pub fn reproduce(
    id: ResultId,
    out: &Path,
    options: &ReproduceOptions,
    progress: &udc_core::Progress,
) -> Result<Reproduction> {
    let ReproduceOptions {
        geometry,
        quick,
        threads,
        quiet,
        backend,
    } = *options;
    let started = Instant::now();
    let parts = id.parts_for(geometry);
    let first = parts.first().map_or("", |p| p.file);
    let root = prepare::repo_root(first)?;
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let sweeps_dir = if quick { "sweep-quick" } else { "sweep" };
    let quick_photos = out.join("quick-photos");
    let mut tables = Vec::new();
    let mut info = RunInfo {
        id,
        quick,
        backend,
        inputs: Vec::new(),
        sweeps: Vec::new(),
        plots: Vec::new(),
        failures: Vec::new(),
        elapsed_s: 0.0,
    };
    let plots_dir = out.join("plots");
    for (k, part) in parts.iter().enumerate() {
        let spec = prepare::prepared_spec(
            &root,
            id,
            part,
            quick.then_some(quick_photos.as_path()),
            backend,
        )?;
        for p in prepare::photos_of(&spec, part.inputs) {
            let name = Path::new(&p)
                .file_name()
                .map_or(p.clone(), |n| n.to_string_lossy().into_owned());
            if !info.inputs.contains(&name) {
                info.inputs.push(name);
            }
        }
        // One folder per spec: an edited spec starts afresh instead of being refused by the
        // folder of its previous version.
        let hash = udc_io::sweep::manifest::spec_hash(&spec);
        let rel =
            Path::new(sweeps_dir).join(format!("{}-{}", part.name, hash.get(..8).unwrap_or(&hash)));
        let dir = out.join(&rel);
        let options = crate::sweep::RunOptions {
            shard: Shard::WHOLE,
            threads,
            plots: part.plots,
            check_values: true,
            hold_after_points: None,
        };
        // Each part fills its share of the bar.
        let _span = progress.span(
            k as f32 / parts.len() as f32,
            (k + 1) as f32 / parts.len() as f32,
        );
        let summary = crate::progress_bar::with_bar(progress, !quiet, part.name, || {
            crate::sweep::run_sweep(&spec, &dir, &options, progress, &mut |_| {})
        })
        .with_context(|| format!("{} ({})", id.as_str(), part.file))?;
        if !quiet && std::io::stderr().is_terminal() {
            crate::sweep::print_summary(&summary, &dir);
        }
        std::fs::create_dir_all(&plots_dir)
            .with_context(|| format!("cannot create {}", plots_dir.display()))?;
        for p in &summary.plots {
            if let Some(name) = p.file_name() {
                let to =
                    Path::new("plots").join(format!("{}-{}", part.name, name.to_string_lossy()));
                std::fs::copy(p, out.join(&to)).with_context(|| {
                    format!("cannot copy {} into {}", p.display(), plots_dir.display())
                })?;
                info.plots.push(to);
            }
        }
        let table = SweepTable::read(&dir, part.name)?;
        info.failures.extend(table.failures());
        info.sweeps.push(rel);
        tables.push(table);
    }
    let mut outcome = reduce(id, &tables);
    if geometry == catalog::Geometry::Thesis {
        outcome.notes.insert(
            0,
            "The thesis's geometry (§4.4.1, `--thesis-geometry`): the phase model's photos scaled \
             to the sensor's 1024 columns (1024 directions), captured as they are and restored \
             with a 'full' boundary: the solver also estimates 512 columns beyond each edge \
             (2048 in all) and the result is cropped back to the capture's 1024, then scored on \
             the field of view. The 2-D rows are as in our geometry."
                .into(),
        );
    }
    std::fs::create_dir_all(&plots_dir)
        .with_context(|| format!("cannot create {}", plots_dir.display()))?;
    for c in &outcome.curves {
        for p in draw_curves(&plots_dir, c)? {
            if let Some(name) = p.file_name() {
                info.plots.push(Path::new("plots").join(name));
            }
        }
    }
    info.elapsed_s = started.elapsed().as_secs_f64();
    let written = report::write_report(out, &info, &outcome)?;
    let report = written
        .first()
        .cloned()
        .unwrap_or_else(|| out.join(report::REPORT_FILE));
    Ok(Reproduction {
        info,
        outcome,
        report,
    })
}

/// Draws a result's own figure with the sweep engine's plotters code.
fn draw_curves(plots_dir: &Path, c: &outcome::Curves) -> Result<Vec<PathBuf>> {
    use udc_core::sweep::summary::SeriesSummary;
    use udc_core::sweep::{PlotKind, PlotSpec};
    use udc_io::sweep::plots::{PlotData, write_plot};
    let mut summary = SeriesSummary::default();
    for (group, x, y) in &c.points {
        summary.add(group, *x, *y);
    }
    let spec = PlotSpec {
        kind: PlotKind::MetricVsAxis,
        x: c.x.to_string(),
        y: c.y.to_string(),
        group: Some("display".into()),
        spread: None,
        x_smaller_is_better: false,
    };
    let data = PlotData::Series {
        summary,
        x_labels: None,
    };
    Ok(write_plot(plots_dir, c.stem, &spec, &data, &c.title)?)
}

/// The rows and claims of `id` from its parts' tables (in the catalog's order); a part that
/// is missing leaves the outcome empty but for a note.
pub fn reduce(id: ResultId, tables: &[SweepTable]) -> Outcome {
    let part = |name: &str| tables.iter().find(|t| t.part == name);
    let missing = || Outcome {
        notes: vec!["a part of this result has no table".into()],
        ..Outcome::default()
    };
    match id {
        ResultId::Fig3_8 => part("display").map_or_else(missing, reduce_display::fig3_8),
        ResultId::Fig3_9 => part("display").map_or_else(missing, reduce_display::fig3_9),
        ResultId::Table4_1 => match (part("phase"), part("display")) {
            (Some(p), Some(d)) => reduce_phase::table4_1(p, d, part("display-table")),
            _ => missing(),
        },
        ResultId::Fig4_14 => match (part("phase"), part("display")) {
            (Some(p), Some(d)) => reduce_phase::fig4_14(p, d),
            _ => missing(),
        },
        ResultId::Table4_2 => part("phase").map_or_else(missing, reduce_plate::table4_2),
        ResultId::Fig4_10 => part("phase").map_or_else(missing, reduce_plate::fig4_10),
        ResultId::Table5_1 => part("sensor").map_or_else(missing, reduce_sensor::table5_1),
        ResultId::Table5_4 => part("sensor").map_or_else(missing, reduce_sensor::table5_4),
    }
}

/// Reads a finished report (the studio's Reproduce window).
///
/// # Errors
/// A folder without report.md, or one that cannot be read.
pub fn read_report(dir: &Path) -> Result<String> {
    let path = dir.join(report::REPORT_FILE);
    udc_io::safe_file::read_text_bounded(&path, 4_000_000, "report")
        .with_context(|| format!("no finished report in {}", dir.display()))
}
