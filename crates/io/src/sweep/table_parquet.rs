//! The results table as Parquet, written in row groups as points finish (typed columns: the
//! point index, integer or float or text parameters, float metrics with nulls for failed
//! points). A Parquet file is only readable once its footer is written, so the file grows
//! under a temporary name and takes its place when the sweep stops; the CSV journal is what a
//! re-run resumes from, and it rewrites the Parquet from it.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_array::builder::{Float64Builder, Int64Builder, StringBuilder, UInt64Builder};
use arrow_array::{ArrayRef, RecordBatch};
use arrow_schema::{DataType, Field, Schema};
use parquet::arrow::ArrowWriter;
use parquet::basic::Compression;
use parquet::file::properties::WriterProperties;

use super::table::{ColumnKind, Row, TableSchema};
use crate::error::{IoError, TableError};
use crate::safe_file::TempFile;

/// Rows per record batch: a few hundred kB of columns in memory at most.
const BATCH_ROWS: usize = 1024;

/// Streams rows into `results.parquet`.
pub struct ParquetAppender {
    path: PathBuf,
    temp: Option<TempFile>,
    writer: Option<ArrowWriter<File>>,
    schema: TableSchema,
    arrow: Arc<Schema>,
    pending: Vec<Row>,
}

fn arrow_schema(schema: &TableSchema) -> Arc<Schema> {
    let mut fields = vec![
        Field::new("point", DataType::UInt64, false),
        Field::new("hash", DataType::Utf8, false),
    ];
    for (name, kind) in &schema.params {
        let t = match kind {
            ColumnKind::Int => DataType::Int64,
            ColumnKind::Float => DataType::Float64,
            ColumnKind::Text => DataType::Utf8,
        };
        fields.push(Field::new(name, t, true));
    }
    for m in &schema.metrics {
        fields.push(Field::new(m, DataType::Float64, true));
    }
    for name in super::table::TAIL_COLUMNS {
        fields.push(Field::new(name, DataType::Utf8, false));
    }
    Arc::new(Schema::new(fields))
}

impl ParquetAppender {
    /// Starts `path` (written beside it under a temporary name until [`finish`](Self::finish)).
    ///
    /// # Errors
    /// [`IoError::File`] or [`IoError::Table`] naming `path`.
    pub fn create(path: &Path, schema: &TableSchema) -> Result<Self, IoError> {
        let temp = TempFile::beside(path)?;
        let file = crate::safe_file::open_reserved(temp.path())
            .map_err(|e| IoError::file("write the results", path, e))?;
        let arrow = arrow_schema(schema);
        let props = WriterProperties::builder()
            .set_compression(Compression::SNAPPY)
            .build();
        let writer = ArrowWriter::try_new(file, arrow.clone(), Some(props))
            .map_err(|e| parquet_error(path, TableError::Parquet(e)))?;
        Ok(ParquetAppender {
            path: path.to_path_buf(),
            temp: Some(temp),
            writer: Some(writer),
            schema: schema.clone(),
            arrow,
            pending: Vec::with_capacity(BATCH_ROWS),
        })
    }

    /// Adds a row; every `BATCH_ROWS` rows become a record batch.
    ///
    /// # Errors
    /// [`IoError::Table`] naming the file.
    pub fn append(&mut self, row: Row) -> Result<(), IoError> {
        self.pending.push(row);
        if self.pending.len() >= BATCH_ROWS {
            self.write_pending()?;
        }
        Ok(())
    }

    fn write_pending(&mut self) -> Result<(), IoError> {
        if self.pending.is_empty() {
            return Ok(());
        }
        let batch = to_batch(&self.pending, &self.schema, self.arrow.clone())
            .map_err(|e| parquet_error(&self.path, e))?;
        if let Some(w) = self.writer.as_mut() {
            w.write(&batch)
                .map_err(|e| parquet_error(&self.path, TableError::Parquet(e)))?;
        }
        self.pending.clear();
        Ok(())
    }

    /// Writes the last rows and the footer, and moves the file into place.
    ///
    /// # Errors
    /// [`IoError::Table`] or [`IoError::File`] naming the file.
    pub fn finish(mut self) -> Result<(), IoError> {
        self.write_pending()?;
        if let Some(w) = self.writer.take() {
            w.close()
                .map_err(|e| parquet_error(&self.path, TableError::Parquet(e)))?;
        }
        match self.temp.take() {
            Some(t) => t.persist(),
            None => Ok(()),
        }
    }
}

fn parquet_error(path: &Path, error: TableError) -> IoError {
    IoError::Table {
        path: path.to_path_buf(),
        error,
    }
}

fn to_batch(
    rows: &[Row],
    schema: &TableSchema,
    arrow: Arc<Schema>,
) -> Result<RecordBatch, TableError> {
    let mut columns: Vec<ArrayRef> = Vec::new();
    let mut point = UInt64Builder::with_capacity(rows.len());
    let mut hash = StringBuilder::new();
    for r in rows {
        point.append_value(r.point);
        hash.append_value(&r.hash);
    }
    columns.push(Arc::new(point.finish()));
    columns.push(Arc::new(hash.finish()));
    for (k, (name, kind)) in schema.params.iter().enumerate() {
        let text = |r: &Row| r.params.get(k).cloned().unwrap_or_default();
        match kind {
            ColumnKind::Int => {
                let mut b = Int64Builder::with_capacity(rows.len());
                for r in rows {
                    let t = text(r);
                    let v = t.parse::<i64>().map_err(|_| TableError::NotWholeNumber {
                        column: name.clone(),
                        value: t.clone(),
                    })?;
                    b.append_value(v);
                }
                columns.push(Arc::new(b.finish()));
            }
            ColumnKind::Float => {
                let mut b = Float64Builder::with_capacity(rows.len());
                for r in rows {
                    let t = text(r);
                    let v = t.parse::<f64>().map_err(|_| TableError::NotNumber {
                        column: name.clone(),
                        value: t.clone(),
                    })?;
                    b.append_value(v);
                }
                columns.push(Arc::new(b.finish()));
            }
            ColumnKind::Text => {
                let mut b = StringBuilder::new();
                for r in rows {
                    b.append_value(text(r));
                }
                columns.push(Arc::new(b.finish()));
            }
        }
    }
    for k in 0..schema.metrics.len() {
        let mut b = Float64Builder::with_capacity(rows.len());
        for r in rows {
            match r.metrics.get(k) {
                Some(v) if v.is_finite() => b.append_value(*v),
                _ => b.append_null(),
            }
        }
        columns.push(Arc::new(b.finish()));
    }
    let tails: [fn(&Row) -> &str; 3] = [
        |r| r.design_hash.as_str(),
        |r| r.error.as_str(),
        |r| r.tool_version.as_str(),
    ];
    for f in tails {
        let mut b = StringBuilder::new();
        for r in rows {
            b.append_value(f(r));
        }
        columns.push(Arc::new(b.finish()));
    }
    RecordBatch::try_new(arrow, columns).map_err(TableError::Arrow)
}
