//! The ROI grid: square regions of `roi_px` unit pixels from the top-left corner; the last row
//! and column of ROIs hold what is left over.

use std::ops::Range;

/// Square ROIs over an image of `dim` pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RoiGrid {
    /// Image size `(rows, cols)`.
    pub dim: (usize, usize),
    /// Side of a full ROI, pixels.
    pub roi_px: usize,
    /// Number of ROIs down and across.
    pub rows: usize,
    /// Number of ROIs across (the last column may be narrower).
    pub cols: usize,
}

impl RoiGrid {
    /// The grid of `roi_px` ROIs (at least 1 px) over `dim`.
    pub fn new(dim: (usize, usize), roi_px: usize) -> RoiGrid {
        let roi_px = roi_px.max(1);
        RoiGrid {
            dim,
            roi_px,
            rows: dim.0.div_ceil(roi_px),
            cols: dim.1.div_ceil(roi_px),
        }
    }

    /// Image rows of ROI row `r`.
    pub fn row_range(&self, r: usize) -> Range<usize> {
        (r * self.roi_px).min(self.dim.0)..((r + 1) * self.roi_px).min(self.dim.0)
    }

    /// Image columns of ROI column `c`.
    pub fn col_range(&self, c: usize) -> Range<usize> {
        (c * self.roi_px).min(self.dim.1)..((c + 1) * self.roi_px).min(self.dim.1)
    }

    /// The ROI `(row, col)` holding pixel `(y, x)`.
    pub fn roi_of(&self, y: usize, x: usize) -> (usize, usize) {
        (y / self.roi_px, x / self.roi_px)
    }

    /// The fraction of ROIs, each counted once whatever its size, in which `map` (of `dim`) has
    /// any `true` pixel; 0 for an empty grid.
    ///
    /// # Panics
    /// If `map` is not `dim`.
    pub fn fraction_with_any(&self, map: &ndarray::Array2<bool>) -> f64 {
        assert_eq!(map.dim(), self.dim, "a map of the grid's size");
        let count = self.rows * self.cols;
        let hit = (0..count)
            .filter(|k| {
                let (r, c) = (k / self.cols, k % self.cols);
                self.row_range(r).any(|y| {
                    let row = map.row(y);
                    self.col_range(c).any(|x| row[x])
                })
            })
            .count();
        if count == 0 {
            0.0
        } else {
            hit as f64 / count as f64
        }
    }

    /// A range of at least `min_len` inside `0..len` that contains `range` (extended backwards,
    /// then forwards): where an edge ROI is thinner than the SSIM window, its score is taken over
    /// the window-sized strip at the image edge.
    pub fn widened(range: Range<usize>, min_len: usize, len: usize) -> Range<usize> {
        if range.len() >= min_len || len < min_len {
            return range;
        }
        let start = range.end.saturating_sub(min_len);
        start..(start + min_len).min(len)
    }
}
