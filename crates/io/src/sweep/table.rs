//! The results table: one row per point, `point, hash, <axis parameters>, <metrics>,
//! design_hash, error, tool_version`. The CSV is the sweep's journal: rows are appended and
//! flushed as points finish, so an interrupted sweep keeps every finished point and a re-run
//! skips them by hash. Metrics are written with the shortest decimal that reads back exactly;
//! a missing metric (a failed point) is an empty cell.

use std::fs::{File, OpenOptions};
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use crate::error::{IoError, TableError};

/// The column type of an axis parameter, from its values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ColumnKind {
    /// Every value a whole number.
    Int,
    /// Every value a number.
    Float,
    /// Words (tilings, presets, paths) or switches.
    Text,
}

/// The columns of a results table.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TableSchema {
    /// The axis parameters and their column types, in the spec's order.
    pub params: Vec<(String, ColumnKind)>,
    /// The metric paths kept.
    pub metrics: Vec<String>,
}

/// The columns before the parameters.
pub const LEAD_COLUMNS: [&str; 2] = ["point", "hash"];
/// The columns after the metrics.
pub const TAIL_COLUMNS: [&str; 3] = ["design_hash", "error", "tool_version"];

impl TableSchema {
    /// Every column name, in order.
    pub fn header(&self) -> Vec<String> {
        LEAD_COLUMNS
            .iter()
            .map(|s| (*s).to_string())
            .chain(self.params.iter().map(|(n, _)| n.clone()))
            .chain(self.metrics.iter().cloned())
            .chain(TAIL_COLUMNS.iter().map(|s| (*s).to_string()))
            .collect()
    }
}

/// One point's row.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The point's index in the whole sweep.
    pub point: u64,
    /// The point's content hash (`core::sweep::hash::point_hash`).
    pub hash: String,
    /// The axis values as the command line spells them, in the schema's order.
    pub params: Vec<String>,
    /// The metrics in the schema's order; NaN where missing.
    pub metrics: Vec<f64>,
    /// Hash of the resolved design (or job inputs) the point computed.
    pub design_hash: String,
    /// Why the point failed; empty when it did not.
    pub error: String,
    /// The `udc-studio` version that computed it.
    pub tool_version: String,
}

impl Row {
    /// The row of a point that failed: its error, no metrics.
    pub fn failed(
        point: u64,
        hash: String,
        params: Vec<String>,
        metrics: usize,
        error: String,
    ) -> Row {
        Row {
            point,
            hash,
            params,
            metrics: vec![f64::NAN; metrics],
            design_hash: String::new(),
            error: error.replace(['\n', '\r'], " "),
            tool_version: crate::TOOL_VERSION.to_string(),
        }
    }

    fn record(&self) -> Vec<String> {
        let mut out = vec![self.point.to_string(), self.hash.clone()];
        out.extend(self.params.iter().cloned());
        out.extend(self.metrics.iter().map(|v| {
            if v.is_finite() {
                format!("{v}")
            } else {
                String::new()
            }
        }));
        out.push(self.design_hash.clone());
        out.push(self.error.clone());
        out.push(self.tool_version.clone());
        out
    }

    /// The row of a CSV record at `line` of the file.
    fn from_record(
        rec: &csv::StringRecord,
        schema: &TableSchema,
        line: usize,
    ) -> Result<Row, TableError> {
        let n = schema.params.len();
        let m = schema.metrics.len();
        let expected = 2 + n + m + 3;
        if rec.len() != expected {
            return Err(TableError::FieldCount {
                line,
                found: rec.len(),
                expected,
            });
        }
        let field = |i: usize| rec.get(i).unwrap_or_default();
        let point = field(0)
            .parse::<u64>()
            .map_err(|_| TableError::PointIndex {
                line,
                value: field(0).to_string(),
            })?;
        let metrics = (0..m)
            .map(|k| {
                let s = field(2 + n + k);
                if s.is_empty() {
                    Ok(f64::NAN)
                } else {
                    s.parse::<f64>().map_err(|_| TableError::Metric {
                        line,
                        value: s.to_string(),
                        metric: schema.metrics[k].clone(),
                    })
                }
            })
            .collect::<Result<Vec<f64>, TableError>>()?;
        Ok(Row {
            point,
            hash: field(1).to_string(),
            params: (0..n).map(|k| field(2 + k).to_string()).collect(),
            metrics,
            design_hash: field(2 + n + m).to_string(),
            error: field(3 + n + m).to_string(),
            tool_version: field(4 + n + m).to_string(),
        })
    }
}

/// Appends rows to a results CSV, flushing each one.
pub struct CsvAppender {
    path: PathBuf,
    writer: csv::Writer<File>,
}

impl CsvAppender {
    /// Opens `path` for appending; writes the header when the file is new or empty. An
    /// existing file must have been read with [`read_csv`] first (which also cuts a row an
    /// interruption left half-written).
    ///
    /// # Errors
    /// [`IoError::File`] when it cannot be opened or written.
    pub fn open(path: &Path, schema: &TableSchema) -> Result<Self, IoError> {
        let file = OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .map_err(|e| IoError::file("open the results table", path, e))?;
        let empty = file
            .metadata()
            .map_err(|e| IoError::file("open the results table", path, e))?
            .len()
            == 0;
        let mut writer = csv::WriterBuilder::new()
            .has_headers(false)
            .from_writer(file);
        if empty {
            writer
                .write_record(schema.header())
                .and_then(|()| writer.flush().map_err(csv::Error::from))
                .map_err(|e| table_error(path, TableError::Csv(e)))?;
        }
        Ok(CsvAppender {
            path: path.to_path_buf(),
            writer,
        })
    }

    /// Appends one row and flushes it to the file.
    ///
    /// # Errors
    /// [`IoError::Table`] naming the file.
    pub fn append(&mut self, row: &Row) -> Result<(), IoError> {
        self.writer
            .write_record(row.record())
            .and_then(|()| self.writer.flush().map_err(csv::Error::from))
            .map_err(|e| table_error(&self.path, TableError::Csv(e)))
    }
}

fn table_error(path: &Path, error: TableError) -> IoError {
    IoError::Table {
        path: path.to_path_buf(),
        error,
    }
}

/// Reads a results CSV row by row, checking its header against `schema`. A last
/// line without its newline (a row an interruption cut) is dropped and, when `repair`, cut
/// from the file so appending continues cleanly.
///
/// # Errors
/// [`IoError::Table`] naming the file and the line: a different header, a malformed row.
pub fn read_csv(
    path: &Path,
    schema: &TableSchema,
    repair: bool,
    mut each: impl FnMut(Row) -> Result<(), IoError>,
) -> Result<(), IoError> {
    let (file, len, complete) = open_complete(path)?;
    if repair && complete < len {
        let f = OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(|e| IoError::file("repair the results table", path, e))?;
        f.set_len(complete)
            .map_err(|e| IoError::file("repair the results table", path, e))?;
    }
    if complete == 0 {
        return Ok(());
    }
    let mut csv = checked_reader(file, complete, path, schema)?;
    for (i, rec) in csv.records().enumerate() {
        let rec = rec.map_err(|e| table_error(path, TableError::Csv(e)))?;
        // Line 1 is the header.
        let row = Row::from_record(&rec, schema, i + 2).map_err(|e| table_error(path, e))?;
        each(row)?;
    }
    Ok(())
}

/// The file, its length and the length up to its last newline (what a cut last row leaves).
fn open_complete(path: &Path) -> Result<(File, u64, u64), IoError> {
    let file = File::open(path).map_err(|e| IoError::file("read the results table", path, e))?;
    let len = file
        .metadata()
        .map_err(|e| IoError::file("read the results table", path, e))?
        .len();
    let complete = complete_length(&file, len).map_err(|e| IoError::file("read", path, e))?;
    Ok((file, len, complete))
}

/// A reader of the first `complete` bytes of `file` whose header is `schema`'s.
fn checked_reader(
    file: File,
    complete: u64,
    path: &Path,
    schema: &TableSchema,
) -> Result<csv::Reader<std::io::Take<BufReader<File>>>, IoError> {
    let mut csv = csv::ReaderBuilder::new()
        .has_headers(true)
        .flexible(true)
        .from_reader(BufReader::new(file).take(complete));
    let header: Vec<String> = csv
        .headers()
        .map_err(|e| table_error(path, TableError::Csv(e)))?
        .iter()
        .map(str::to_string)
        .collect();
    let expected = schema.header();
    if expected != header {
        return Err(table_error(
            path,
            TableError::Columns {
                found: header,
                expected,
            },
        ));
    }
    Ok(csv)
}

/// Where one row of a results CSV starts: enough to read it again with [`CsvRows::row_at`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RowIndex {
    /// The row's point.
    pub point: u64,
    /// Its byte offset in the file.
    pub byte: u64,
    /// Its line number (the header is line 1).
    pub line: u64,
}

/// Reads a results CSV as [`read_csv`] does (a cut last line ignored, never repaired), but
/// hands each row with where it starts, so that a caller can keep the offsets instead of the
/// rows: `sweep merge` orders a million rows this way in a few tens of megabytes.
///
/// # Errors
/// As [`read_csv`].
pub fn index_csv(
    path: &Path,
    schema: &TableSchema,
    mut each: impl FnMut(RowIndex, Row) -> Result<(), IoError>,
) -> Result<(), IoError> {
    let (file, _, complete) = open_complete(path)?;
    if complete == 0 {
        return Ok(());
    }
    let mut csv = checked_reader(file, complete, path, schema)?;
    let mut rec = csv::StringRecord::new();
    for line in 2u64.. {
        let byte = csv.position().byte();
        let more = csv
            .read_record(&mut rec)
            .map_err(|e| table_error(path, TableError::Csv(e)))?;
        if !more {
            break;
        }
        let row =
            Row::from_record(&rec, schema, line as usize).map_err(|e| table_error(path, e))?;
        each(
            RowIndex {
                point: row.point,
                byte,
                line,
            },
            row,
        )?;
    }
    Ok(())
}

/// Rows of a results CSV read again at the offsets [`index_csv`] gave.
pub struct CsvRows {
    path: PathBuf,
    schema: TableSchema,
    reader: csv::Reader<BufReader<File>>,
    record: csv::StringRecord,
}

impl CsvRows {
    /// Opens `path`, whose rows follow `schema`.
    ///
    /// # Errors
    /// [`IoError::File`] when it cannot be opened.
    pub fn open(path: &Path, schema: &TableSchema) -> Result<Self, IoError> {
        let file =
            File::open(path).map_err(|e| IoError::file("read the results table", path, e))?;
        // Small buffers: each read seeks, and a seek drops what the buffer holds.
        let reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .from_reader(BufReader::with_capacity(1024, file));
        Ok(CsvRows {
            path: path.to_path_buf(),
            schema: schema.clone(),
            reader,
            record: csv::StringRecord::new(),
        })
    }

    /// The row at `index`.
    ///
    /// # Errors
    /// [`IoError::Table`] naming the file and line when it no longer reads as it did.
    pub fn row_at(&mut self, index: RowIndex) -> Result<Row, IoError> {
        let mut at = csv::Position::new();
        at.set_byte(index.byte).set_line(index.line);
        self.reader
            .seek(at)
            .map_err(|e| table_error(&self.path, TableError::Csv(e)))?;
        let more = self
            .reader
            .read_record(&mut self.record)
            .map_err(|e| table_error(&self.path, TableError::Csv(e)))?;
        if !more {
            return Err(table_error(
                &self.path,
                TableError::Csv(csv::Error::from(std::io::Error::new(
                    std::io::ErrorKind::UnexpectedEof,
                    format!("line {} is gone", index.line),
                ))),
            ));
        }
        Row::from_record(&self.record, &self.schema, index.line as usize)
            .map_err(|e| table_error(&self.path, e))
    }
}

/// Writes a results CSV row by row to a temp file beside `path`, renamed into place by
/// [`CsvWriter::finish`] (an error or interruption leaves the old file, if any).
pub struct CsvWriter {
    path: PathBuf,
    temp: crate::safe_file::TempFile,
    writer: csv::Writer<std::io::BufWriter<File>>,
}

impl CsvWriter {
    /// Starts `path` with `schema`'s header.
    ///
    /// # Errors
    /// [`IoError::File`] or [`IoError::Table`] naming `path`.
    pub fn create(path: &Path, schema: &TableSchema) -> Result<Self, IoError> {
        let temp = crate::safe_file::TempFile::beside(path)?;
        let file = crate::safe_file::open_reserved(temp.path())
            .map_err(|e| IoError::file("write", path, e))?;
        let mut writer = csv::WriterBuilder::new()
            .has_headers(false)
            .from_writer(std::io::BufWriter::new(file));
        writer
            .write_record(schema.header())
            .map_err(|e| table_error(path, TableError::Csv(e)))?;
        Ok(CsvWriter {
            path: path.to_path_buf(),
            temp,
            writer,
        })
    }

    /// Writes one row.
    ///
    /// # Errors
    /// [`IoError::Table`] naming the file.
    pub fn write(&mut self, row: &Row) -> Result<(), IoError> {
        self.writer
            .write_record(row.record())
            .map_err(|e| table_error(&self.path, TableError::Csv(e)))
    }

    /// Flushes the rows and renames the file into place.
    ///
    /// # Errors
    /// [`IoError::File`] naming the file.
    pub fn finish(mut self) -> Result<(), IoError> {
        self.writer
            .flush()
            .map_err(|e| IoError::file("write", &self.path, e))?;
        drop(self.writer);
        self.temp.persist()
    }
}

/// The length up to and including the last newline.
fn complete_length(file: &File, len: u64) -> std::io::Result<u64> {
    let mut f = file.try_clone()?;
    let mut pos = len;
    let mut buf = [0u8; 4096];
    while pos > 0 {
        let start = pos.saturating_sub(buf.len() as u64);
        let n = (pos - start) as usize;
        f.seek(SeekFrom::Start(start))?;
        let chunk = buf.get_mut(..n).unwrap_or_default();
        f.read_exact(chunk)?;
        if let Some(k) = chunk.iter().rposition(|b| *b == b'\n') {
            f.seek(SeekFrom::Start(0))?;
            return Ok(start + k as u64 + 1);
        }
        pos = start;
    }
    f.seek(SeekFrom::Start(0))?;
    Ok(0)
}

/// Writes a whole table (a merge) through a temp file and a rename.
///
/// # Errors
/// [`IoError::Table`] or [`IoError::File`] naming `path`.
pub fn write_csv(path: &Path, schema: &TableSchema, rows: &[Row]) -> Result<(), IoError> {
    let mut w = CsvWriter::create(path, schema)?;
    for r in rows {
        w.write(r)?;
    }
    w.finish()
}
