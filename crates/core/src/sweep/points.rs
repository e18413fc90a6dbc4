//! The points of a sweep: the Cartesian product of its axes, enumerated lazily by index (last
//! axis fastest), so a sweep of millions of points never holds them all; and shards of it.

use super::spec::{ParamValue, SweepSpec, axis_values};
use crate::{SimError, ValueError};

/// The expanded axes of a spec; a point is one value per axis, found from its index.
#[derive(Debug, Clone)]
pub struct Points {
    names: Vec<String>,
    values: Vec<Vec<ParamValue>>,
    /// Per axis, the parameters that change with it and their values (`Axis::with`).
    linked: Vec<Vec<(String, Vec<ParamValue>)>>,
    /// Per axis, whether its values only name the points (`Axis::label`).
    labels: Vec<bool>,
    count: u64,
}

impl Points {
    /// Expands the spec's axes (validating them).
    ///
    /// # Errors
    /// As [`SweepSpec::validate`].
    pub fn new(spec: &SweepSpec) -> Result<Self, SimError> {
        spec.validate()?;
        let mut values = Vec::new();
        for (i, a) in spec.axes.iter().enumerate() {
            values.push(
                axis_values(a).map_err(|(f, message)| SimError::InvalidSetting {
                    path: format!("axis[{i}]{f}").into(),
                    message,
                })?,
            );
        }
        let count = values.iter().map(|v| v.len() as u64).product();
        Ok(Points {
            names: spec.axes.iter().map(|a| a.param.clone()).collect(),
            values,
            linked: spec
                .axes
                .iter()
                .map(|a| a.with.iter().map(|(k, v)| (k.clone(), v.clone())).collect())
                .collect(),
            labels: spec.axes.iter().map(|a| a.label).collect(),
            count,
        })
    }

    /// How many points the sweep has (1 when it has no axes).
    pub fn count(&self) -> u64 {
        self.count
    }

    /// The axis parameters, in the spec's order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Every value of axis `k`.
    pub fn axis(&self, k: usize) -> &[ParamValue] {
        self.values.get(k).map_or(&[], Vec::as_slice)
    }

    /// The value index of point `index` (`< count`) on each axis: a mixed-radix decoding of
    /// the index with the last axis as the lowest digit.
    pub fn digits(&self, index: u64) -> Vec<usize> {
        let mut rest = index;
        let mut out: Vec<usize> = Vec::with_capacity(self.values.len());
        for vals in self.values.iter().rev() {
            let n = (vals.len() as u64).max(1);
            out.push((rest % n) as usize);
            rest /= n;
        }
        out.reverse();
        out
    }

    /// The values of point `index` (`< count`), one per axis.
    pub fn point(&self, index: u64) -> Vec<&ParamValue> {
        self.at(&self.digits(index))
    }

    /// The axis values at these value indices (one per axis).
    pub fn at(&self, digits: &[usize]) -> Vec<&ParamValue> {
        self.values
            .iter()
            .zip(digits)
            .filter_map(|(vals, k)| vals.get(*k))
            .collect()
    }

    /// The parameters (name and value) that reach the command line at these value indices:
    /// every axis that is not a label, then the linked parameters, axis by axis.
    pub fn flags_at(&self, digits: &[usize]) -> Vec<(&str, &ParamValue)> {
        self.names
            .iter()
            .zip(self.at(digits))
            .zip(&self.labels)
            .filter(|(_, label)| !**label)
            .map(|((n, v), _)| (n.as_str(), v))
            .chain(self.linked_at(digits))
            .collect()
    }

    /// The linked parameters (`Axis::with`) at these value indices, axis by axis.
    pub fn linked_at(&self, digits: &[usize]) -> Vec<(&str, &ParamValue)> {
        self.linked
            .iter()
            .zip(digits)
            .flat_map(|(params, k)| {
                params
                    .iter()
                    .filter_map(move |(name, vals)| vals.get(*k).map(|v| (name.as_str(), v)))
            })
            .collect()
    }
}

/// One shard of a sweep, `index` of `count` (0-based): points `i` with `i % count == index`,
/// so slow and fast regions of the space spread over every shard.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard, `0..count`.
    pub index: u64,
    /// How many shards the sweep is cut into.
    pub count: u64,
}

impl Shard {
    /// The whole sweep as one shard.
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// Whether point `i` belongs to this shard.
    pub fn contains(self, i: u64) -> bool {
        i % self.count == self.index
    }

    /// How many of `points` points this shard holds.
    pub fn len(self, points: u64) -> u64 {
        points / self.count + u64::from(points % self.count > self.index)
    }

    /// Whether the shard holds no point of a sweep of `points`.
    pub fn is_empty(self, points: u64) -> bool {
        self.len(points) == 0
    }
}

/// Parses `I/N` with `0 ≤ I < N`.
///
/// # Errors
/// One line saying what is wrong.
pub fn parse_shard(s: &str) -> Result<Shard, ValueError> {
    let bad = |problem: String| ValueError::Unusable {
        value: s.to_string(),
        problem,
    };
    let (i, n) = s
        .split_once('/')
        .ok_or_else(|| bad("a shard is I/N, e.g. 0/4".into()))?;
    let index: u64 = i
        .trim()
        .parse()
        .map_err(|_| bad(format!("{i} is not a shard number")))?;
    let count: u64 = n
        .trim()
        .parse()
        .map_err(|_| bad(format!("{n} is not a shard count")))?;
    if count == 0 || index >= count {
        return Err(bad("needs 0 ≤ I < N".into()));
    }
    Ok(Shard { index, count })
}

impl std::str::FromStr for Shard {
    type Err = ValueError;
    fn from_str(s: &str) -> Result<Self, ValueError> {
        parse_shard(s)
    }
}
