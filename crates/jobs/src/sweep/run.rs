//! Running a sweep in-process: points in parallel on a rayon pool, rows streamed to the CSV
//! journal and the Parquet file by one writer thread, finished points skipped by hash, and a
//! first Ctrl-C (or a cancelled [`Progress`]) that stops after the points in flight. It prints
//! nothing: the caller shows `progress` and the [`RunSummary`].

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use rayon::prelude::*;

use super::points::{FileDigests, evaluate_point, hash_of, job_of, point_params};
use udc_core::Progress;
use udc_core::sweep::{ParamValue, Points, Shard, SweepSpec};
use udc_io::sweep::manifest::{
    CSV_FILE, FORMAT, MANIFEST_FILE, Manifest, PARQUET_FILE, read_manifest, spec_hash,
    write_manifest,
};
use udc_io::sweep::metrics::{flatten_metrics, select_columns};
use udc_io::sweep::table::{ColumnKind, CsvAppender, Row, TableSchema, read_csv};
use udc_io::sweep::table_parquet::ParquetAppender;

/// How to run.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Which points.
    pub shard: Shard,
    /// Worker threads; `None` for every core.
    pub threads: Option<usize>,
    /// Draw the plots when done (whole sweeps only).
    pub plots: bool,
    /// Check every axis value before running, so that a refused value stops the sweep before
    /// anything is written (the command line); off, a refused value is a failed point, a row
    /// with its message (the studio's "sweep this parameter", whose plot shows it as a gap).
    pub check_values: bool,
    /// Start this many new points, then no more, and keep the run open until it is stopped: a
    /// run that is certain to be interrupted midway, however fast the machine (the interruption
    /// tests; the command line sets it from `UDC_SWEEP_HOLD_AFTER_POINTS`).
    pub hold_after_points: Option<u64>,
}

/// The environment variable that sets [`RunOptions::hold_after_points`] for the command line.
pub const HOLD_AFTER_POINTS_ENV: &str = "UDC_SWEEP_HOLD_AFTER_POINTS";

/// How a run went.
#[derive(Debug, Clone)]
pub struct RunSummary {
    /// Points computed in this run.
    pub computed: u64,
    /// Points found finished and skipped.
    pub skipped: u64,
    /// Points that failed (in this run).
    pub failed: u64,
    /// Points of the shard in the table now (this run's and earlier runs').
    pub rows: u64,
    /// Points in the shard.
    pub total: u64,
    /// Points of the shard that failed (in any run).
    pub failed_total: u64,
    /// Seconds this run took.
    pub elapsed_s: f64,
    /// Points computed per second in this run.
    pub points_per_s: f64,
    /// Whether every point of the shard is in the table.
    pub complete: bool,
    /// The plots written.
    pub plots: Vec<PathBuf>,
}

/// The column type of each axis, from its values.
fn column_kinds(points: &Points) -> Vec<(String, ColumnKind)> {
    (0..points.names().len())
        .map(|k| {
            let vals = points.axis(k);
            let kind = if vals.iter().all(|v| matches!(v, ParamValue::Int(_))) {
                ColumnKind::Int
            } else if vals.iter().all(|v| v.as_f64().is_some()) {
                ColumnKind::Float
            } else {
                ColumnKind::Text
            };
            (points.names()[k].clone(), kind)
        })
        .collect()
}

/// One point, computed into a row (a failure is a row with its error, so it is not retried).
fn compute_row(
    spec: &SweepSpec,
    points: &Points,
    index: u64,
    hash: String,
    metrics: &[String],
    progress: &Progress,
) -> (Row, Option<serde_json::Value>) {
    let params = point_params(spec, points, index);
    let axis_text: Vec<String> = points.point(index).iter().map(|v| v.to_arg()).collect();
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        evaluate_point(&job_of(spec.job, &params)?, &hash, progress)
    }))
    .unwrap_or_else(|_| Err(anyhow!("internal error (a panic) computing this point")));
    let mut row = Row::failed(index, hash, axis_text, metrics.len(), String::new());
    match outcome {
        Ok(out) => {
            let flat = flatten_metrics(&out.value);
            for (slot, name) in row.metrics.iter_mut().zip(metrics) {
                if let Some((_, v)) = flat.iter().find(|(n, _)| n == name) {
                    *slot = *v;
                }
            }
            row.design_hash = out.design_hash;
            (row, Some(out.value))
        }
        Err(e) => {
            row.error = format!("{e:#}").replace(['\n', '\r'], " ");
            (row, None)
        }
    }
}

/// Runs a sweep (or one shard of it) into `out`, resuming what is there. `progress` shows the
/// share of the shard's points in the table and stops the run when cancelled: no new point
/// starts, the points in flight stop at their next check and are left for a resume. Every row
/// written (a computed or failed point) is handed to `on_row` as it lands.
///
/// # Errors
/// An invalid spec or axis value, a folder holding another sweep, unwritable files, a run
/// stopped by Ctrl-C or `progress` (after saving every finished point).
pub fn run_sweep(
    spec: &SweepSpec,
    out: &Path,
    opts: &RunOptions,
    progress: &Progress,
    on_row: &mut (dyn FnMut(&Row) + Send),
) -> Result<RunSummary> {
    let started = Instant::now();
    let points = Points::new(spec)?;
    let count = points.count();
    let shard = opts.shard;
    if let Some(t) = opts.threads
        && !(1..=1024).contains(&t)
    {
        bail!("--threads {t}: between 1 and 1024");
    }
    if opts.check_values {
        super::check_points(spec)?;
    }
    let files = FileDigests::default();
    let hash_at = |i: u64| hash_of(spec.job, &point_params(spec, &points, i), &files);

    // The columns: from the folder's manifest when it holds this sweep, else from the first
    // point that computes.
    let this_hash = spec_hash(spec);
    let existing = if out.join(MANIFEST_FILE).exists() {
        Some(read_manifest(out)?)
    } else {
        None
    };
    let mut first_row: Option<Row> = None;
    let schema = match &existing {
        Some(m) if m.spec_hash == this_hash && m.shard == [shard.index, shard.count] => {
            m.schema.clone()
        }
        Some(m) if m.spec_hash != this_hash && out.join(CSV_FILE).exists() => bail!(
            "{} holds results of another sweep (spec {}, this one {}); give a new --out",
            out.display(),
            m.spec_hash,
            this_hash
        ),
        Some(m) if out.join(CSV_FILE).exists() => bail!(
            "{} holds shard {}/{} of this sweep, not {}/{}; give a new --out",
            out.display(),
            m.shard[0],
            m.shard[1],
            shard.index,
            shard.count
        ),
        _ => {
            let mut found = None;
            let mut tried = Vec::new();
            for i in (0..count).filter(|i| shard.contains(*i)).take(8) {
                let probe = vec!["*".to_string()];
                let (row, value) = compute_row(spec, &points, i, hash_at(i)?, &probe, progress);
                match value {
                    Some(v) => {
                        let flat = flatten_metrics(&v);
                        let metrics = select_columns(&spec.metric_patterns(), &flat)
                            .map_err(|e| anyhow!("{e}"))?;
                        found = Some(TableSchema {
                            params: column_kinds(&points),
                            metrics: metrics.clone(),
                        });
                        let mut row = row;
                        row.metrics = metrics
                            .iter()
                            .map(|m| {
                                flat.iter()
                                    .find(|(n, _)| n == m)
                                    .map_or(f64::NAN, |(_, v)| *v)
                            })
                            .collect();
                        first_row = Some(row);
                        break;
                    }
                    None => tried.push(format!("point {i}: {}", row.error)),
                }
            }
            match found {
                Some(s) => s,
                None if tried.is_empty() => TableSchema {
                    params: column_kinds(&points),
                    metrics: Vec::new(),
                },
                None => bail!("the first points all failed: {}", tried.join("; ")),
            }
        }
    };

    // The folder is made (and locked) only once the points are known to compute: a refused
    // sweep leaves nothing behind.
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    // One writer per folder: a second sweep into it would interleave rows.
    let lock_path = out.join(".sweep.lock");
    let lock = std::fs::File::create(&lock_path)
        .with_context(|| format!("cannot create {}", lock_path.display()))?;
    if lock.try_lock().is_err() {
        bail!(
            "another sweep is writing to {}; wait for it or give another --out",
            out.display()
        );
    }
    // Resume: what the journal holds, rewritten into a fresh Parquet file.
    let csv_path = out.join(CSV_FILE);
    let mut parquet = ParquetAppender::create(&out.join(PARQUET_FILE), &schema)?;
    let mut done: HashSet<String> = HashSet::new();
    let mut failed_before = 0u64;
    if csv_path.exists() {
        read_csv(&csv_path, &schema, true, |row| {
            if done.insert(row.hash.clone()) {
                failed_before += u64::from(!row.error.is_empty());
                parquet.append(row)?;
            }
            Ok(())
        })?;
    }
    let mut csv = CsvAppender::open(&csv_path, &schema)?;
    let total = shard.len(count);
    let mut manifest = Manifest {
        format: FORMAT.into(),
        version: 1,
        spec: spec.clone(),
        spec_hash: this_hash,
        points: count,
        shard: [shard.index, shard.count],
        schema: schema.clone(),
        tool_version: udc_io::TOOL_VERSION.into(),
        rows: done.len() as u64,
        failed: failed_before,
        complete: false,
        elapsed_s: 0.0,
        points_per_s: 0.0,
        threads: opts.threads.unwrap_or_else(rayon::current_num_threads),
    };
    write_manifest(out, &manifest)?;

    let skipped = AtomicU64::new(0);
    let started_points = AtomicU64::new(0);
    let held = AtomicBool::new(false);
    // Ctrl-C drains: the points in flight finish and are saved (a second one quits).
    let drain = Arc::new(AtomicBool::new(false));
    let _deferred = udc_io::safe_file::defer_signal_to(drain.clone());
    let stop = || drain.load(Ordering::SeqCst) || progress.is_cancelled();
    // What the points in flight check: cancelled by the writer thread when `progress` is.
    let in_flight = Arc::new(Progress::new());
    let (tx, rx) = std::sync::mpsc::sync_channel::<Row>(256);

    // The first point computed for the columns is written like any other.
    let mut computed = 0u64;
    let mut failed = 0u64;
    let first_hash = first_row.as_ref().map(|r| r.hash.clone());
    if let Some(row) = first_row.take()
        && !done.contains(&row.hash)
    {
        done.insert(row.hash.clone());
        failed += u64::from(!row.error.is_empty());
        computed += 1;
        csv.append(&row)?;
        on_row(&row);
        parquet.append(row)?;
    }
    let share = |rows: usize| rows.min(total as usize) as f32 / total.max(1) as f32;
    progress.set(share(done.len()));

    let pool = {
        let mut b = rayon::ThreadPoolBuilder::new();
        if let Some(t) = opts.threads {
            b = b.num_threads(t.max(1));
        }
        b.build().context("cannot start the worker threads")?
    };
    let metrics = schema.metrics.clone();
    let done_ref = &done;
    let (n, f, parquet) = std::thread::scope(|scope| -> Result<(u64, u64, ParquetAppender)> {
        let in_flight_w = in_flight.clone();
        let rows_before = done_ref.len();
        let handle = scope.spawn(move || -> Result<(u64, u64, ParquetAppender)> {
            let (mut n, mut f) = (0u64, 0u64);
            loop {
                if progress.is_cancelled() {
                    in_flight_w.cancel();
                }
                let row = match rx.recv_timeout(std::time::Duration::from_millis(50)) {
                    Ok(row) => row,
                    Err(std::sync::mpsc::RecvTimeoutError::Timeout) => continue,
                    Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => break,
                };
                f += u64::from(!row.error.is_empty());
                n += 1;
                csv.append(&row)?;
                on_row(&row);
                parquet.append(row)?;
                progress.set(share(rows_before + n as usize));
            }
            Ok((n, f, parquet))
        });
        // Stopping (Ctrl-C) or a closed writer ends the iteration early; either is reported
        // below, so the iteration's own result carries nothing more.
        let _: Result<(), ()> = pool.install(|| {
            (0..count)
                .into_par_iter()
                .filter(|i| shard.contains(*i))
                .try_for_each_with(tx, |tx, i| {
                    if stop() {
                        return Err(());
                    }
                    let row = match hash_at(i) {
                        Ok(hash) if done_ref.contains(&hash) => {
                            if first_hash.as_ref() != Some(&hash) {
                                skipped.fetch_add(1, Ordering::Relaxed);
                            }
                            return Ok(());
                        }
                        Ok(hash) => {
                            if let Some(hold) = opts.hold_after_points
                                && started_points.fetch_add(1, Ordering::SeqCst) >= hold
                            {
                                // Not waited for here: a worker waiting inside a point's own
                                // parallel steps may run this job on top of that point, which
                                // would then never finish. The run waits below, off the pool.
                                held.store(true, Ordering::SeqCst);
                                return Err(());
                            }
                            let row = compute_row(spec, &points, i, hash, &metrics, &in_flight).0;
                            // A point cut short by the cancel is not a result: a resume
                            // computes it.
                            if in_flight.is_cancelled() && !row.error.is_empty() {
                                return Err(());
                            }
                            row
                        }
                        // An unreadable input file: a failed point with its message.
                        Err(e) => Row::failed(
                            i,
                            format!("unreadable-{i}"),
                            points.point(i).iter().map(|v| v.to_arg()).collect(),
                            metrics.len(),
                            format!("{e:#}"),
                        ),
                    };
                    tx.send(row).map_err(|_| ())
                })
        });
        let written = handle
            .join()
            .map_err(|_| anyhow!("the results writer stopped"))?;
        // Held (a test's pause, `hold_after_points`): the points started are written; the run
        // stays open until it is cancelled.
        if held.load(Ordering::SeqCst) {
            while !stop() {
                std::thread::sleep(std::time::Duration::from_millis(10));
            }
        }
        written
    })?;
    computed += n;
    failed += f;
    parquet.finish()?;
    let elapsed = started.elapsed().as_secs_f64();
    let rows = manifest.rows + computed;
    manifest.rows = rows;
    manifest.failed = failed_before + failed;
    manifest.complete = rows >= total;
    manifest.elapsed_s = elapsed;
    manifest.points_per_s = computed as f64 / elapsed.max(1e-9);
    write_manifest(out, &manifest)?;
    let skipped = skipped.load(Ordering::Relaxed);
    let interrupted = stop() && !manifest.complete;
    let mut plots = Vec::new();
    if manifest.complete && opts.plots && shard.count == 1 {
        plots = udc_io::sweep::plots::write_plots(out, &manifest)?;
    }
    if interrupted {
        bail!(
            "interrupted: {} of {total} points are saved in {}; run the same command again to resume",
            rows.min(total),
            out.display()
        );
    }
    Ok(RunSummary {
        computed,
        skipped,
        failed,
        rows: rows.min(total),
        total,
        failed_total: manifest.failed,
        elapsed_s: elapsed,
        points_per_s: manifest.points_per_s,
        complete: manifest.complete,
        plots,
    })
}
