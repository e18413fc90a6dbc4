//! The files of a reproduction: report.md (ours beside the thesis's, the claims, what each row
//! is), results.csv and the `--json` object.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Result;
use serde_json::{Value as Json, json};

use super::catalog::ResultId;
use super::outcome::{Outcome, ReportRow, fmt, fmt_signed};
use super::thesis::PHOTO_SET_NOTE;

/// What a run was, for the report's header.
#[derive(Debug, Clone)]
pub struct RunInfo {
    /// The result.
    pub id: ResultId,
    /// Whether `--quick` trimmed it.
    pub quick: bool,
    /// Where the display and phase points computed their PSFs (`--backend`).
    pub backend: udc_core::psf::route::Backend,
    /// The photos or scenes each part read.
    pub inputs: Vec<String>,
    /// The sweep folders, relative to the results folder.
    pub sweeps: Vec<PathBuf>,
    /// The plots copied into `plots/`, relative to the results folder.
    pub plots: Vec<PathBuf>,
    /// Points that failed, with their errors.
    pub failures: Vec<String>,
    /// Wall time of the run, s.
    pub elapsed_s: f64,
}

/// The report's file name.
pub const REPORT_FILE: &str = "report.md";
/// The table's file name.
pub const RESULTS_FILE: &str = "results.csv";

/// Writes report.md and results.csv into `dir`; returns their paths.
///
/// # Errors
/// A file that cannot be written.
pub fn write_report(dir: &Path, info: &RunInfo, outcome: &Outcome) -> Result<Vec<PathBuf>> {
    let md = dir.join(REPORT_FILE);
    udc_io::safe_file::write_atomic(&md, markdown(info, outcome).as_bytes())?;
    let csv_path = dir.join(RESULTS_FILE);
    udc_io::safe_file::write_atomic(&csv_path, csv_text(outcome)?.as_bytes())?;
    Ok(vec![md, csv_path])
}

/// report.md's text.
pub fn markdown(info: &RunInfo, o: &Outcome) -> String {
    let mut s = String::new();
    let id = info.id;
    let _ = writeln!(s, "# {}\n", id.title());
    let _ = writeln!(
        s,
        "`udc-studio reproduce {}{}{}`: {}.\n",
        id.as_str(),
        if info.quick { " --quick" } else { "" },
        match info.backend {
            udc_core::psf::route::Backend::Cpu => String::new(),
            other => format!(" --backend {other}"),
        },
        id.runs()
    );
    let _ = writeln!(
        s,
        "Mode: {}. Run time {:.1} s.\n",
        if info.quick {
            "quick (three photos of the test set at 256², fewer costly settings; see the notes)"
        } else {
            "full (the whole test set)"
        },
        info.elapsed_s
    );
    let _ = writeln!(s, "{PHOTO_SET_NOTE}\n");
    let passed = o.claims.iter().filter(|c| c.pass).count();
    let _ = writeln!(s, "## Claims: {passed} of {} hold\n", o.claims.len());
    let _ = writeln!(s, "| claim (thesis) | measured | result | why |");
    let _ = writeln!(s, "|---|---|---|---|");
    for c in &o.claims {
        let _ = writeln!(
            s,
            "| {} | {} | **{}** | {} |",
            cell(&c.claim),
            cell(&c.measured),
            if c.pass { "PASS" } else { "FAIL" },
            cell(&c.why)
        );
    }
    let _ = writeln!(s, "\n## Rows: ours beside the thesis\n");
    if let Some(first) = o.rows.first() {
        let mut head = String::from("| setup |");
        let mut rule = String::from("|---|");
        for v in &first.values {
            let _ = write!(head, " {0} ours | {0} thesis | Δ |", v.heading);
            rule.push_str("---|---|---|");
        }
        head.push_str(" note |");
        rule.push_str("---|");
        let _ = writeln!(s, "{head}\n{rule}");
        for r in &o.rows {
            let _ = writeln!(s, "{}", row_line(r));
        }
    }
    let _ = writeln!(s, "\n## What the rows are\n");
    for n in &o.notes {
        let _ = writeln!(s, "- {}", n.replace('\n', " "));
    }
    if info.quick {
        let _ = writeln!(
            s,
            "- Quick mode: three photos scaled to 256²; `phase restore` runs on its preview \
             sampling (60 nm at the display, 7 samples per pixel, the full spectral response: \
             6× faster, within 0.1 dB of the thesis sampling on Table 4.1's setups). Run \
             without `--quick` for the numbers of the whole test set."
        );
    }
    if !info.inputs.is_empty() {
        let _ = writeln!(s, "\nInputs: {}.", info.inputs.join(", "));
    }
    if !info.failures.is_empty() {
        let _ = writeln!(s, "\n## Failed points\n");
        for f in &info.failures {
            let _ = writeln!(s, "- {}", cell(f));
        }
    }
    let _ = writeln!(s, "\n## Files\n");
    let _ = writeln!(s, "- `{RESULTS_FILE}`: the rows above.");
    for p in &info.plots {
        let _ = writeln!(s, "- `{}`", p.display());
    }
    for p in &info.sweeps {
        let _ = writeln!(
            s,
            "- `{}/`: the sweep (results.csv per point, sweep.json; run the same command again \
             to resume)",
            p.display()
        );
    }
    s
}

fn row_line(r: &ReportRow) -> String {
    let mut line = format!("| {} |", cell(&r.setup));
    for (i, v) in r.values.iter().enumerate() {
        let thesis = match (&v.thesis, &r.thesis_claim) {
            (Some(t), _) => format!("{t:.0$}", v.decimals),
            (None, Some(claim)) if i == 0 => cell(claim),
            _ => "—".into(),
        };
        let _ = write!(
            line,
            " {} | {} | {} |",
            fmt(v.ours, v.decimals),
            thesis,
            fmt_signed(v.difference(), v.decimals)
        );
    }
    let _ = write!(line, " {} |", cell(&r.note));
    line
}

/// Text safe inside a Markdown table cell.
fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// results.csv: `setup`, then per value `<name>, thesis_<name>, diff_<name>`, then `thesis_claim`
/// and `note`.
fn csv_text(o: &Outcome) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let names: Vec<&str> = o
        .rows
        .first()
        .map(|r| r.values.iter().map(|v| v.name).collect())
        .unwrap_or_default();
    let mut header = vec!["setup".to_string()];
    for n in &names {
        header.extend([n.to_string(), format!("thesis_{n}"), format!("diff_{n}")]);
    }
    header.extend(["thesis_claim".into(), "note".into()]);
    w.write_record(&header)?;
    let num = |v: Option<f64>| v.map_or_else(String::new, |v| format!("{v}"));
    for r in &o.rows {
        let mut rec = vec![r.setup.clone()];
        for n in &names {
            let v = r.values.iter().find(|v| v.name == *n);
            rec.push(num(v.and_then(|v| v.ours)));
            rec.push(num(v.and_then(|v| v.thesis)));
            rec.push(num(v.and_then(|v| v.difference())));
        }
        rec.push(r.thesis_claim.clone().unwrap_or_default());
        rec.push(r.note.clone());
        w.write_record(&rec)?;
    }
    let bytes = w.into_inner().map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(String::from_utf8(bytes)?)
}

/// The `--json` object: `{"id", "quick", "rows": [{"setup", <name>, "thesis_<name>", …,
/// "note"}], "claims": [{"claim", "measured", "pass", "why"}], "report"}`; a missing number is
/// `null`.
pub fn json_of(info: &RunInfo, o: &Outcome, report: &Path) -> Json {
    let rows: Vec<Json> = o
        .rows
        .iter()
        .map(|r| {
            let mut m = serde_json::Map::new();
            m.insert("setup".into(), json!(r.setup));
            for v in &r.values {
                m.insert(v.name.into(), json!(v.ours));
                m.insert(format!("thesis_{}", v.name), json!(v.thesis));
            }
            m.insert("thesis_claim".into(), json!(r.thesis_claim));
            m.insert("note".into(), json!(r.note));
            Json::Object(m)
        })
        .collect();
    json!({
        "id": info.id.as_str(),
        "title": info.id.title(),
        "quick": info.quick,
        "backend": <&str>::from(info.backend),
        "rows": rows,
        "claims": o.claims.iter().map(|c| json!({
            "claim": c.claim, "measured": c.measured, "pass": c.pass, "why": c.why,
        })).collect::<Vec<_>>(),
        "failures": info.failures,
        "elapsed_s": info.elapsed_s,
        "report": report.display().to_string(),
    })
}
