//! `sweep merge`: shard folders into one results folder, every point exactly once.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;

use udc_io::sweep::manifest::{CSV_FILE, Manifest, PARQUET_FILE, read_manifest, write_manifest};
use udc_io::sweep::table::{Row, read_csv, write_csv};
use udc_io::sweep::table_parquet::ParquetAppender;

/// Arguments of `udc-studio sweep merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The shards' results folders (each written by `sweep SPEC --shard I/N`).
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// The merged results folder.
    #[arg(long)]
    pub out: PathBuf,
    /// Write what there is even when points are missing (the manifest says incomplete).
    #[arg(long)]
    pub allow_incomplete: bool,
    /// No summary.
    #[arg(long)]
    pub quiet: bool,
    /// Do not draw the plots.
    #[arg(long)]
    pub no_plots: bool,
}

/// Runs `sweep merge`.
///
/// # Errors
/// Folders of different sweeps, a point with two different results, missing points (without
/// `--allow-incomplete`), unwritable output.
pub fn merge_cmd(a: &MergeArgs) -> Result<()> {
    let mut first: Option<Manifest> = None;
    let mut rows: Vec<Row> = Vec::new();
    for dir in &a.dirs {
        let m = read_manifest(dir)?;
        if let Some(f) = &first
            && (f.spec_hash != m.spec_hash || f.schema != m.schema || f.points != m.points)
        {
            bail!(
                "{} holds another sweep (spec {}) than {} (spec {})",
                dir.display(),
                m.spec_hash,
                a.dirs[0].display(),
                f.spec_hash
            );
        }
        read_csv(&dir.join(CSV_FILE), &m.schema, false, |row| {
            rows.push(row);
            Ok(())
        })?;
        if first.is_none() {
            first = Some(m);
        }
    }
    let Some(mut manifest) = first else {
        bail!("no folders to merge");
    };
    rows.sort_by_key(|r| r.point);
    let mut merged: Vec<Row> = Vec::with_capacity(rows.len());
    for row in rows {
        match merged.last() {
            Some(last) if last.point == row.point => {
                if last.hash != row.hash {
                    bail!(
                        "point {} has two different results (hashes {} and {})",
                        row.point,
                        last.hash,
                        row.hash
                    );
                }
            }
            _ => merged.push(row),
        }
    }
    let missing = manifest.points - merged.len() as u64;
    if missing > 0 && !a.allow_incomplete {
        let mut have = merged.iter().map(|r| r.point).peekable();
        let mut examples = Vec::new();
        for i in 0..manifest.points {
            if have.peek() == Some(&i) {
                have.next();
            } else {
                examples.push(i.to_string());
                if examples.len() == 10 {
                    break;
                }
            }
        }
        bail!(
            "incomplete: {missing} of {} points are missing (points {}{}); run their shards again, or pass --allow-incomplete",
            manifest.points,
            examples.join(", "),
            if missing > 10 { ", …" } else { "" }
        );
    }
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    write_csv(&a.out.join(CSV_FILE), &manifest.schema, &merged)?;
    let mut parquet = ParquetAppender::create(&a.out.join(PARQUET_FILE), &manifest.schema)?;
    manifest.failed = merged.iter().filter(|r| !r.error.is_empty()).count() as u64;
    manifest.rows = merged.len() as u64;
    for row in merged {
        parquet.append(row)?;
    }
    parquet.finish()?;
    manifest.shard = [0, 1];
    manifest.complete = missing == 0;
    write_manifest(&a.out, &manifest)?;
    let plots = if manifest.complete && !a.no_plots {
        udc_io::sweep::plots::write_plots(&a.out, &manifest)?
    } else {
        Vec::new()
    };
    if !a.quiet {
        println!(
            "merged {} folders: {} of {} points ({} failed) into {}",
            a.dirs.len(),
            manifest.rows,
            manifest.points,
            manifest.failed,
            a.out.display()
        );
        for p in plots {
            println!("wrote {}", p.display());
        }
    }
    Ok(())
}
