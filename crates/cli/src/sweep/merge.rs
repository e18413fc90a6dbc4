//! `sweep merge`: shard folders into one results folder, every point exactly once.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;

use udc_io::sweep::manifest::{CSV_FILE, Manifest, PARQUET_FILE, read_manifest, write_manifest};
use udc_io::sweep::table::{CsvRows, CsvWriter, RowIndex, index_csv};
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

/// One row of a shard: where it is (32 bytes a row).
struct Entry {
    at: RowIndex,
    shard: u32,
    failed: bool,
}

/// Runs `sweep merge`.
///
/// # Errors
/// Folders of different sweeps, a point with two different results, missing points (without
/// `--allow-incomplete`), unwritable output.
pub fn merge_cmd(a: &MergeArgs) -> Result<()> {
    let mut first: Option<Manifest> = None;
    // Where each row is, not the rows: a million rows take 32 MB this way (the rows
    // themselves took about 0.5 GB).
    let mut index: Vec<Entry> = Vec::new();
    for (shard, dir) in a.dirs.iter().enumerate() {
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
        index_csv(&dir.join(CSV_FILE), &m.schema, |at, row| {
            index.push(Entry {
                at,
                shard: shard as u32,
                failed: !row.error.is_empty(),
            });
            Ok(())
        })?;
        if first.is_none() {
            first = Some(m);
        }
    }
    let Some(mut manifest) = first else {
        bail!("no folders to merge");
    };
    let mut readers = a
        .dirs
        .iter()
        .map(|d| CsvRows::open(&d.join(CSV_FILE), &manifest.schema))
        .collect::<Result<Vec<_>, _>>()?;
    index.sort_unstable_by_key(|e| (e.at.point, e.shard));
    // Each point once, compacted in place; a point in two shards (a shard given twice, a
    // resubmitted task) must be the same result.
    let mut kept = 0;
    for i in 0..index.len() {
        if kept > 0 && index[kept - 1].at.point == index[i].at.point {
            let (a, b) = (&index[kept - 1], &index[i]);
            let first = readers[a.shard as usize].row_at(a.at)?;
            let second = readers[b.shard as usize].row_at(b.at)?;
            if first.hash != second.hash {
                bail!(
                    "point {} has two different results (hashes {} and {})",
                    b.at.point,
                    first.hash,
                    second.hash
                );
            }
        } else {
            index.swap(kept, i);
            kept += 1;
        }
    }
    index.truncate(kept);
    let merged = index;
    let missing = manifest.points - merged.len() as u64;
    if missing > 0 && !a.allow_incomplete {
        let mut have = merged.iter().map(|e| e.at.point).peekable();
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
    // One pass in point order: each row read once, written to both tables.
    let mut csv = CsvWriter::create(&a.out.join(CSV_FILE), &manifest.schema)?;
    let mut parquet = ParquetAppender::create(&a.out.join(PARQUET_FILE), &manifest.schema)?;
    for e in &merged {
        let row = readers[e.shard as usize].row_at(e.at)?;
        csv.write(&row)?;
        parquet.append(row)?;
    }
    csv.finish()?;
    parquet.finish()?;
    manifest.failed = merged.iter().filter(|e| e.failed).count() as u64;
    manifest.rows = merged.len() as u64;
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
