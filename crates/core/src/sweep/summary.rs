//! What the plots show: a metric's mean, standard deviation and min–max over a spread axis, per x
//! and group, and the
//! Pareto front of two metrics. Fed one row at a time, so memory grows with the distinct x and
//! group values (and, for a front, the points), not with the metrics or the columns.

use std::collections::BTreeMap;

/// Mean, standard deviation, minimum and maximum of the values seen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    /// How many values.
    pub n: usize,
    /// Their sum.
    pub sum: f64,
    /// The sum of their squared deviations from the running mean (Welford's `M2`).
    pub m2: f64,
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
            m2: 0.0,
            min: v,
            max: v,
        }
    }

    fn add(&mut self, v: f64) {
        let before = self.mean();
        self.n += 1;
        self.sum += v;
        self.m2 += (v - before) * (v - self.mean());
        self.min = self.min.min(v);
        self.max = self.max.max(v);
    }

    /// The mean.
    pub fn mean(&self) -> f64 {
        self.sum / self.n as f64
    }

    /// The sample standard deviation (0 for one value).
    pub fn sd(&self) -> f64 {
        if self.n < 2 {
            0.0
        } else {
            (self.m2 / (self.n - 1) as f64).max(0.0).sqrt()
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spread_has_the_sample_standard_deviation() {
        let mut s = Spread::new(2.0);
        for v in [4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0] {
            s.add(v);
        }
        assert_eq!(s.mean(), 5.0);
        // Σ(v − 5)² = 32 over n − 1 = 7.
        assert!((s.sd() - (32.0f64 / 7.0).sqrt()).abs() < 1e-12);
        assert_eq!(Spread::new(3.0).sd(), 0.0);
        assert_eq!((s.min, s.max), (2.0, 9.0));
    }
}
