//! A sweep's results in memory and the rows a view shows: which columns there are, the filter
//! the user typed and the sort order. No drawing here: a view is computed on a job (a table
//! may have 100 000 rows) and the table widget only draws the indices it gets.

use std::cmp::Ordering;
use std::path::PathBuf;

use crate::io::sweep::Row;
use crate::io::sweep::manifest::Manifest;

/// A results folder read into memory.
#[derive(Debug, Clone)]
pub struct SweepTable {
    /// The folder it was read from.
    pub dir: PathBuf,
    /// Its `sweep.json`.
    pub manifest: Manifest,
    /// Every row of `results.csv`, in file order.
    pub rows: Vec<Row>,
}

/// A column of the table widget (the hash and tool-version columns are left out: they are for
/// machines).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Column {
    /// The point's index in the sweep.
    Point,
    /// An axis parameter, by its index in the schema.
    Param(usize),
    /// A metric, by its index in the schema.
    Metric(usize),
    /// Why the point failed.
    Error,
}

/// A sort order: the column and its direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Sort {
    /// The column sorted by.
    pub column: Column,
    /// Largest first.
    pub descending: bool,
}

impl Default for Sort {
    fn default() -> Self {
        Sort {
            column: Column::Point,
            descending: false,
        }
    }
}

impl SweepTable {
    /// Every column the table widget shows, in order.
    pub fn columns(&self) -> Vec<Column> {
        let s = &self.manifest.schema;
        std::iter::once(Column::Point)
            .chain((0..s.params.len()).map(Column::Param))
            .chain((0..s.metrics.len()).map(Column::Metric))
            .chain(std::iter::once(Column::Error))
            .collect()
    }

    /// A column's header.
    pub fn name(&self, c: Column) -> &str {
        let s = &self.manifest.schema;
        match c {
            Column::Point => "point",
            Column::Param(k) => s.params.get(k).map_or("?", |(n, _)| n.as_str()),
            Column::Metric(k) => s.metrics.get(k).map_or("?", String::as_str),
            Column::Error => "error",
        }
    }

    /// The column with this header, if any.
    pub fn column(&self, name: &str) -> Option<Column> {
        self.columns().into_iter().find(|c| self.name(*c) == name)
    }

    /// A cell as a number (NaN for words and empty cells).
    pub fn number(&self, row: &Row, c: Column) -> f64 {
        match c {
            Column::Point => row.point as f64,
            Column::Param(k) => row
                .params
                .get(k)
                .and_then(|t| t.parse().ok())
                .unwrap_or(f64::NAN),
            Column::Metric(k) => row.metrics.get(k).copied().unwrap_or(f64::NAN),
            Column::Error => f64::NAN,
        }
    }

    /// A cell as the table shows it: metrics with 6 significant digits, words as they are.
    pub fn text(&self, row: &Row, c: Column) -> String {
        match c {
            Column::Point => row.point.to_string(),
            Column::Param(k) => row.params.get(k).cloned().unwrap_or_default(),
            Column::Metric(k) => format_number(row.metrics.get(k).copied().unwrap_or(f64::NAN)),
            Column::Error => row.error.clone(),
        }
    }

    /// The rows `filter` keeps, in `sort` order, as indices into [`SweepTable::rows`]. The sort
    /// is stable: equal cells keep file order.
    pub fn view(&self, filter: &Filter, sort: Sort) -> Vec<usize> {
        let mut idx: Vec<usize> = (0..self.rows.len())
            .filter(|&i| self.rows.get(i).is_some_and(|r| filter.keeps(self, r)))
            .collect();
        let numeric = match sort.column {
            Column::Point | Column::Metric(_) => true,
            Column::Param(k) => self.rows.iter().all(|r| {
                r.params
                    .get(k)
                    .is_some_and(|t| t.is_empty() || t.parse::<f64>().is_ok())
            }),
            Column::Error => false,
        };
        let key = |i: &usize| self.rows.get(*i);
        idx.sort_by(|a, b| {
            let (Some(ra), Some(rb)) = (key(a), key(b)) else {
                return Ordering::Equal;
            };
            let ord = if numeric {
                let (x, y) = (self.number(ra, sort.column), self.number(rb, sort.column));
                // Missing values last in both directions: they are not small, they are absent.
                match (x.is_nan(), y.is_nan()) {
                    (true, true) => return Ordering::Equal,
                    (true, false) => return Ordering::Greater,
                    (false, true) => return Ordering::Less,
                    _ => x.total_cmp(&y),
                }
            } else {
                self.text(ra, sort.column).cmp(&self.text(rb, sort.column))
            };
            if sort.descending { ord.reverse() } else { ord }
        });
        idx
    }
}

/// A number with 6 significant digits, without trailing zeros; empty for a missing value.
pub fn format_number(v: f64) -> String {
    if !v.is_finite() {
        return String::new();
    }
    if v == 0.0 {
        return "0".into();
    }
    let magnitude = v.abs().log10().floor() as i32;
    if !(-4..6).contains(&magnitude) {
        return format!("{v:.5e}");
    }
    let decimals = (5 - magnitude).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// One term of a filter.
#[derive(Debug, Clone, PartialEq)]
enum Term {
    /// Case-insensitive substring of a parameter or the error.
    Text(String),
    /// `column<value`, `column>value` or `column=value` on a named column.
    Compare {
        column: String,
        op: Op,
        value: String,
    },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Op {
    Less,
    Greater,
    Equal,
}

/// What the filter box holds, parsed: terms separated by spaces, all of which must hold.
/// `random-4` keeps rows with that text in a parameter or the error; `ltr>0.5` and `seed<3`
/// compare a column with a number; `tiling=repeat` wants a parameter equal to a word.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Filter {
    terms: Vec<Term>,
}

impl Filter {
    /// Parses the filter box's text (never fails: anything that is not a comparison is text).
    pub fn parse(text: &str) -> Self {
        let terms = text
            .split_whitespace()
            .map(|word| {
                for (ch, op) in [('<', Op::Less), ('>', Op::Greater), ('=', Op::Equal)] {
                    if let Some((c, v)) = word.split_once(ch)
                        && !c.is_empty()
                        && !v.is_empty()
                    {
                        return Term::Compare {
                            column: c.to_string(),
                            op,
                            value: v.to_string(),
                        };
                    }
                }
                Term::Text(word.to_lowercase())
            })
            .collect();
        Filter { terms }
    }

    /// Whether `row` passes every term. A comparison on a column the table lacks keeps
    /// nothing, so a typo shows an empty table rather than everything.
    pub fn keeps(&self, table: &SweepTable, row: &Row) -> bool {
        self.terms.iter().all(|t| match t {
            Term::Text(s) => {
                row.params.iter().any(|p| p.to_lowercase().contains(s))
                    || row.error.to_lowercase().contains(s)
            }
            Term::Compare { column, op, value } => {
                let Some(c) = table.column(column) else {
                    return false;
                };
                let number = table.number(row, c);
                match (op, value.parse::<f64>()) {
                    (Op::Less, Ok(v)) => number < v,
                    (Op::Greater, Ok(v)) => number > v,
                    (Op::Equal, Ok(v)) if !number.is_nan() => number == v,
                    (Op::Equal, _) => table.text(row, c) == *value,
                    _ => false,
                }
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn six_significant_digits() {
        assert_eq!(format_number(0.123456789), "0.123457");
        assert_eq!(format_number(123.456789), "123.457");
        assert_eq!(format_number(2.0), "2");
        assert_eq!(format_number(1.5e-7), "1.50000e-7");
        assert_eq!(format_number(f64::NAN), "");
    }

    #[test]
    fn filter_terms() {
        let f = Filter::parse("random-4 ltr>0.5 tiling=repeat");
        assert_eq!(f.terms.len(), 3);
        assert_eq!(f.terms[0], Term::Text("random-4".into()));
        assert!(matches!(
            &f.terms[1],
            Term::Compare {
                op: Op::Greater,
                ..
            }
        ));
    }
}
