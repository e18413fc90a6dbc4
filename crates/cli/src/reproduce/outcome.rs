//! What a reproduction found: rows (ours beside the thesis's), the claims checked, and the sweep
//! tables they were read from.

use std::path::Path;

use anyhow::Result;

use udc_io::sweep::manifest::{CSV_FILE, read_manifest};
use udc_io::sweep::table::{Row, read_csv};

/// One number of a row: ours and, where the thesis prints one, the thesis's.
#[derive(Debug, Clone, PartialEq)]
pub struct Value {
    /// The JSON and CSV name (`psnr_db`); the thesis's is `thesis_<name>`.
    pub name: &'static str,
    /// The column heading in report.md.
    pub heading: &'static str,
    /// Ours; `None` when no point computed it.
    pub ours: Option<f64>,
    /// The thesis's; `None` where it prints no number.
    pub thesis: Option<f64>,
    /// Decimals shown in report.md.
    pub decimals: usize,
}

impl Value {
    /// A value the thesis prints no number for.
    pub fn ours(
        name: &'static str,
        heading: &'static str,
        ours: Option<f64>,
        decimals: usize,
    ) -> Self {
        Value {
            name,
            heading,
            ours,
            thesis: None,
            decimals,
        }
    }

    /// Ours beside the thesis's.
    pub fn both(
        name: &'static str,
        heading: &'static str,
        ours: Option<f64>,
        thesis: Option<f64>,
        decimals: usize,
    ) -> Self {
        Value {
            name,
            heading,
            ours,
            thesis,
            decimals,
        }
    }

    /// PSNR in dB (two decimals).
    pub fn psnr(ours: Option<f64>, thesis: Option<f64>) -> Self {
        Value::both("psnr_db", "PSNR (dB)", ours, thesis, 2)
    }

    /// SSIM (three decimals).
    pub fn ssim(ours: Option<f64>, thesis: Option<f64>) -> Self {
        Value::both("ssim", "SSIM", ours, thesis, 3)
    }

    /// Ours minus the thesis's, where both exist.
    pub fn difference(&self) -> Option<f64> {
        Some(self.ours? - self.thesis?)
    }
}

/// One row of a result.
#[derive(Debug, Clone, PartialEq)]
pub struct ReportRow {
    /// What was run, as the thesis names it (`T-OLED, periodic, SNR 24 dB`).
    pub setup: String,
    /// Its numbers; every row of a result has the same names in the same order.
    pub values: Vec<Value>,
    /// Where the thesis only plots this row: the claim its text makes about it.
    pub thesis_claim: Option<String>,
    /// One sentence on the difference from the thesis (or on what the row is).
    pub note: String,
}

/// A claim of the thesis, checked.
#[derive(Debug, Clone, PartialEq)]
pub struct Claim {
    /// The claim, as the thesis (or the bound on it) states it.
    pub claim: String,
    /// What we measured.
    pub measured: String,
    /// Whether it holds.
    pub pass: bool,
    /// Why it differs from the thesis, when it does (or how close it came).
    pub why: String,
}

/// A figure of the thesis redrawn from our rows (when no single sweep holds its lines): one
/// line per group, the mean over the photos.
#[derive(Debug, Clone, PartialEq)]
pub struct Curves {
    /// The file name, without extension.
    pub stem: &'static str,
    /// The plot's title.
    pub title: String,
    /// The horizontal axis's label.
    pub x: &'static str,
    /// The vertical axis's label.
    pub y: &'static str,
    /// `(line, x, y)` points.
    pub points: Vec<(String, f64, f64)>,
}

/// Everything a reproduction reports.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Outcome {
    /// The rows, ours beside the thesis's.
    pub rows: Vec<ReportRow>,
    /// The claims checked.
    pub claims: Vec<Claim>,
    /// What the rows are and how they were computed, one paragraph each.
    pub notes: Vec<String>,
    /// Figures drawn from the rows, beside the sweeps' own plots.
    pub curves: Vec<Curves>,
}

/// A finished sweep's table, read back for the reduction.
#[derive(Debug, Clone)]
pub struct SweepTable {
    /// The part of the result it is (`phase`, `display`).
    pub part: &'static str,
    /// Axis columns, in order.
    pub params: Vec<String>,
    /// Metric columns, in order.
    pub metrics: Vec<String>,
    /// Every row, by point.
    pub rows: Vec<Row>,
}

impl SweepTable {
    /// Reads `dir/results.csv` with the columns its manifest names.
    ///
    /// # Errors
    /// A missing or malformed manifest or table.
    pub fn read(dir: &Path, part: &'static str) -> Result<Self> {
        let manifest = read_manifest(dir)?;
        let mut rows = Vec::new();
        read_csv(&dir.join(CSV_FILE), &manifest.schema, false, |row| {
            rows.push(row);
            Ok(())
        })?;
        rows.sort_by_key(|r| r.point);
        Ok(SweepTable {
            part,
            params: manifest
                .schema
                .params
                .iter()
                .map(|(n, _)| n.clone())
                .collect(),
            metrics: manifest.schema.metrics,
            rows,
        })
    }

    /// The row's value of axis `name`.
    pub fn param<'a>(&self, row: &'a Row, name: &str) -> Option<&'a str> {
        let k = self.params.iter().position(|p| p == name)?;
        row.params.get(k).map(String::as_str)
    }

    /// The row's metric `name`, when finite.
    pub fn metric(&self, row: &Row, name: &str) -> Option<f64> {
        let k = self.metrics.iter().position(|m| m == name)?;
        row.metrics.get(k).copied().filter(|v| v.is_finite())
    }

    /// The rows whose axes have these values.
    pub fn matching<'a>(
        &'a self,
        filter: &'a [(&str, &str)],
    ) -> impl Iterator<Item = &'a Row> + 'a {
        self.rows
            .iter()
            .filter(move |r| filter.iter().all(|(p, v)| self.param(r, p) == Some(*v)))
    }

    /// The mean of metric `name` over the rows matching `filter` (e.g. over photos), and how
    /// many rows it averaged; `None` when no matching row has it.
    pub fn mean(&self, name: &str, filter: &[(&str, &str)]) -> Option<f64> {
        let vals: Vec<f64> = self
            .matching(filter)
            .filter_map(|r| self.metric(r, name))
            .collect();
        (!vals.is_empty()).then(|| vals.iter().sum::<f64>() / vals.len() as f64)
    }

    /// The distinct values of axis `name`, in point order.
    pub fn values_of(&self, name: &str) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for r in &self.rows {
            if let Some(v) = self.param(r, name)
                && !out.iter().any(|o| o == v)
            {
                out.push(v.to_string());
            }
        }
        out
    }

    /// The errors of the points that failed, each with its axis values.
    pub fn failures(&self) -> Vec<String> {
        self.rows
            .iter()
            .filter(|r| !r.error.is_empty())
            .map(|r| {
                let at: Vec<String> = self
                    .params
                    .iter()
                    .zip(&r.params)
                    .map(|(p, v)| format!("{p}={v}"))
                    .collect();
                format!("{} ({}): {}", self.part, at.join(", "), r.error)
            })
            .collect()
    }
}

/// `a` with `decimals` decimals, or `—` when missing.
pub fn fmt(v: Option<f64>, decimals: usize) -> String {
    v.map_or_else(|| "—".to_string(), |v| format!("{v:.decimals$}"))
}

/// `a` with its sign and `decimals` decimals, or `—`.
pub fn fmt_signed(v: Option<f64>, decimals: usize) -> String {
    v.map_or_else(|| "—".to_string(), |v| format!("{v:+.decimals$}"))
}
