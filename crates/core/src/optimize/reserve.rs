//! The "reserve subpixels" constraint: an optimized opening must leave room for three equal
//! R, G, B emitters of at least a minimum footprint in its opaque area (thesis §3.7). A
//! binarised candidate without room is not kept: its least-wanted open cells (lowest relaxed
//! transmittance) are closed one at a time until the auto-placement succeeds.

use crate::SimError;
use crate::design::{Opening, Subpixels};
use crate::display::emitters::auto_place;

/// Closes the open cells of `cells` in order of increasing `relaxed` value until three emitters
/// of `min_area_um2` fit; returns the cells and the placement.
///
/// # Errors
/// [`SimError::InvalidSetting`] on `reserve_subpixels_um2` when even a fully closed pixel has no
/// room (the footprint is more than a third of the pixel).
pub fn reserve_subpixels(
    mut cells: Vec<Vec<f64>>,
    relaxed: &[f64],
    pitch_um: f64,
    min_area_um2: f64,
) -> Result<(Vec<Vec<f64>>, Subpixels), SimError> {
    let n = cells.len();
    let opening = |cells: &Vec<Vec<f64>>| Opening {
        pitch_um,
        cells: cells.clone(),
        polygons: Vec::new(),
    };
    if let Some(sp) = auto_place(&opening(&cells), min_area_um2) {
        return Ok((cells, sp));
    }
    let mut open: Vec<usize> = (0..n * n).filter(|&i| cells[i / n][i % n] > 0.0).collect();
    open.sort_by(|&a, &b| {
        let v = |i: usize| relaxed.get(i).copied().unwrap_or(0.0);
        v(a).total_cmp(&v(b)).then(a.cmp(&b))
    });
    for i in open {
        cells[i / n][i % n] = 0.0;
        if let Some(sp) = auto_place(&opening(&cells), min_area_um2) {
            return Ok((cells, sp));
        }
    }
    Err(SimError::invalid(
        "reserve_subpixels_um2",
        format!(
            "{min_area_um2} µm² per colour does not fit three times in a {pitch_um} µm pixel \
             of {n}×{n} cells"
        ),
    ))
}
