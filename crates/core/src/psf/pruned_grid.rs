//! The grid geometry of one pruned PSF transform (the pruned route): which rows and columns of
//! the `M×M` grid the field occupies, which the sensor window reads, and the aliasing band.

use crate::display::aperture::Field;
use crate::psf::sampling::Binning;

/// The grid geometry of one pruned transform.
pub(crate) struct Geometry {
    pub(crate) m: usize,
    /// `M/2`.
    pub(crate) h: i64,
    /// First band offset, `⌈0.45 M⌉`.
    pub(crate) e: i64,
    /// Grid rows of the field: `iy0 … iy0 + n_rows − 1`.
    pub(crate) iy0: i64,
    pub(crate) n_rows: usize,
    /// Grid columns of the field: `ix0 … ix0 + n_cols − 1`.
    pub(crate) ix0: i64,
    pub(crate) n_cols: usize,
    /// Window offsets along x and y, clipped to the grid `[−M/2, M/2)`.
    pub(crate) x_range: (i64, i64),
    pub(crate) y_range: (i64, i64),
    /// Largest half-spectrum column the window reads.
    pub(crate) kw: usize,
    /// Signed rows each window column's zoom returns.
    pub(crate) r_lo: i64,
    pub(crate) r_hi: i64,
    /// Kept half-spectrum columns, ascending.
    pub(crate) kept: Vec<usize>,
}

impl Geometry {
    pub(crate) fn new(field: &Field, m: usize, b: &Binning) -> Geometry {
        let h = (m / 2) as i64;
        let e = (0.45 * m as f64).ceil() as i64;
        let window = |axis: usize| {
            let (w, sp) = (b.window_px as i64, b.samples_per_px as i64);
            let lo = -(w / 2) * sp - b.phase[axis] as i64;
            let hi = (w - w / 2) * sp - b.phase[axis] as i64 - 1;
            (lo.max(-h), hi.min(h - 1))
        };
        let (x_range, y_range) = (window(0), window(1));
        let kw = x_range.0.abs().max(x_range.1.abs()).min(h) as usize;
        let r_lo = y_range.0.min(-y_range.1);
        let r_hi = y_range.1.max(-y_range.0).min(h - 1);
        let mut kept: Vec<usize> = (0..=kw).chain(e.max(0) as usize..=h as usize).collect();
        kept.sort_unstable();
        kept.dedup();
        let (iy0, iy1) = field
            .rows
            .iter()
            .fold((i64::MAX, i64::MIN), |(a, b), r| (a.min(r.iy), b.max(r.iy)));
        let (ix0, ix1) = field.rows.iter().fold((i64::MAX, i64::MIN), |(a, b), r| {
            (a.min(r.ix0), b.max(r.ix0 + r.values.len() as i64 - 1))
        });
        let span = |lo: i64, hi: i64| if hi >= lo { (hi - lo + 1) as usize } else { 0 };
        Geometry {
            m,
            h,
            e,
            iy0,
            n_rows: span(iy0, iy1),
            ix0,
            n_cols: span(ix0, ix1),
            x_range,
            y_range,
            kw,
            r_lo,
            r_hi,
            kept,
        }
    }

    pub(crate) fn window_zoom_len(&self) -> usize {
        (self.r_hi - self.r_lo + 1).max(0) as usize
    }

    pub(crate) fn band_len(&self) -> usize {
        (self.m as i64 - 2 * self.e + 1).max(0) as usize
    }

    /// Signed offset folded into `[−M/2, M/2)`.
    pub(crate) fn wrap(&self, v: i64) -> i64 {
        (v + self.h).rem_euclid(self.m as i64) - self.h
    }
}
