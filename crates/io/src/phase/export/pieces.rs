//! Level tables and runs of the plate's pieces (`core::phase::plate`), for the vector formats.

use super::*;
pub(super) use udc_core::phase::plate::{Piece, Shape, pieces};

/// Height of level `k` for tables: `k·step` without the binary noise (0.6, not
/// 0.6000000000000001), which would otherwise read as a different height in a layer map.
pub(super) fn level_height_um(k: u64, step_um: f64) -> f64 {
    (k as f64 * step_um * 1e9).round() / 1e9
}

/// Runs of one quantised level `[x0_nm, x1_nm, level]`, merged across pieces and lenslets and
/// snapped to the 1 nm grid. The level is each piece's integer index.
pub(super) fn level_runs(pieces: &[Piece]) -> Vec<(i64, i64, u64)> {
    let mut runs: Vec<(i64, i64, u64)> = Vec::new();
    for p in pieces {
        let Shape::Flat { level, .. } = p.shape else {
            continue;
        };
        let x0 = (p.x0_um / DB_UNIT_UM).round() as i64;
        let x1 = (p.x1_um / DB_UNIT_UM).round() as i64;
        if x1 <= x0 {
            continue;
        }
        match runs.last_mut() {
            Some(last) if last.2 == level && last.1 == x0 => last.1 = x1,
            _ => runs.push((x0, x1, level)),
        }
    }
    runs
}
