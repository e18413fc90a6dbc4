//! What the plots show: a metric's mean and min–max over a spread axis, per x and group, and the
//! Pareto front of two metrics. Fed one row at a time, so memory grows with the distinct x and
//! group values (and, for a front, the points), not with the metrics or the columns.

use std::collections::BTreeMap;

/// Mean, minimum and maximum of the values seen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    /// How many values.
    pub n: usize,
    /// Their sum.
    pub sum: f64,
    /// The smallest.
    pub min: f64,
    /// The largest.
    pub max: f64,
}

impl Spread {
    fn new(v: f64) -> Self {
        Spread {
            n: 1,
            sum: v,
            min: v,
            max: v,
        }
    }

    fn add(&mut self, v: f64) {
        self.n += 1;
        self.sum += v;
        self.min = self.min.min(v);
        self.max = self.max.max(v);
    }

    /// The mean.
    pub fn mean(&self) -> f64 {
        self.sum / self.n as f64
    }
}

/// A metric against an axis: per group (a line), per x position, the spread of the metric.
/// Non-numeric x values (a tiling, a preset) sit at their index along the axis.
#[derive(Debug, Clone, Default)]
pub struct SeriesSummary {
    /// Group label → x position (as bits, so it orders and compares exactly) → spread.
    pub lines: BTreeMap<String, BTreeMap<OrderedX, Spread>>,
}

/// An x position that orders totally (no NaN reaches it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrderedX(pub f64);

impl PartialOrd for OrderedX {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Eq for OrderedX {}

impl Ord for OrderedX {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

impl SeriesSummary {
    /// Adds one point; a non-finite metric (a failed point) is left out.
    pub fn add(&mut self, group: &str, x: f64, y: f64) {
        if !(x.is_finite() && y.is_finite()) {
            return;
        }
        self.lines
            .entry(group.to_string())
            .or_default()
            .entry(OrderedX(x))
            .and_modify(|s| s.add(y))
            .or_insert_with(|| Spread::new(y));
    }
}

/// One labelled point of two metrics.
#[derive(Debug, Clone, PartialEq)]
pub struct ParetoPoint {
    /// First metric.
    pub x: f64,
    /// Second metric.
    pub y: f64,
    /// The point's index in the sweep.
    pub point: u64,
}

/// The points no other point beats in both metrics (larger is better for `y`, and for `x`
/// unless `x_smaller_is_better`), sorted by `x`. Ties keep the lower point index.
pub fn pareto_front(points: &[ParetoPoint], x_smaller_is_better: bool) -> Vec<ParetoPoint> {
    let sign = if x_smaller_is_better { -1.0 } else { 1.0 };
    let mut sorted: Vec<&ParetoPoint> = points
        .iter()
        .filter(|p| p.x.is_finite() && p.y.is_finite())
        .collect();
    // Best x first; among equal x, best y first, then the lower index.
    sorted.sort_by(|a, b| {
        (sign * b.x)
            .total_cmp(&(sign * a.x))
            .then(b.y.total_cmp(&a.y))
            .then(a.point.cmp(&b.point))
    });
    let mut front: Vec<ParetoPoint> = Vec::new();
    let mut best_y = f64::NEG_INFINITY;
    for p in sorted {
        if p.y > best_y {
            best_y = p.y;
            front.push(p.clone());
        }
    }
    front.sort_by(|a, b| a.x.total_cmp(&b.x));
    front
}
