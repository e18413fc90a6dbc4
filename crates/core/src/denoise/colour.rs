//! CBM3D's colour space: the opponent transform of Dabov et al. (ICIP 2007), each channel then
//! stretched to [0, 1] as the reference implementation does, so that its block-matching
//! thresholds (set for [0, 1] grey images) apply to the luminance unchanged. Noise that is white
//! with variance σ² in R, G and B is white in each opponent channel with variance
//! `σ² Σ_j a_cj² / range_c²`; the channels' noise correlation is ignored, as in the paper.

use ndarray::Array2;

/// Rows: luminance (mean of R, G, B) and two chrominances.
const FORWARD: [[f64; 3]; 3] = [
    [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
    [0.5, 0.0, -0.5],
    [0.25, -0.5, 0.25],
];
/// The inverse of [`FORWARD`].
const INVERSE: [[f64; 3]; 3] = [
    [1.0, 1.0, 2.0 / 3.0],
    [1.0, 0.0, -4.0 / 3.0],
    [1.0, -1.0, 2.0 / 3.0],
];

/// How the opponent channels were stretched, to undo it.
#[derive(Debug, Clone, Copy)]
pub struct Stretch {
    min: [f64; 3],
    range: [f64; 3],
}

/// R, G, B → stretched opponent channels (as f32 row-major planes), the stretch, and each
/// channel's noise standard deviation for an RGB noise variance `sigma2`.
pub fn to_opponent(rgb: &[Array2<f64>], sigma2: f64) -> (Vec<Vec<f32>>, Stretch, [f64; 3]) {
    let opp: Vec<Vec<f64>> = FORWARD
        .iter()
        .map(|a| {
            rgb[0]
                .iter()
                .zip(rgb[1].iter())
                .zip(rgb[2].iter())
                .map(|((r, g), b)| a[0] * r + a[1] * g + a[2] * b)
                .collect()
        })
        .collect();
    let mut stretch = Stretch {
        min: [0.0; 3],
        range: [1.0; 3],
    };
    let mut sigma = [0.0; 3];
    let mut out = Vec::with_capacity(3);
    for c in 0..3 {
        let (lo, hi) = opp[c]
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        // A flat channel (a grey image's chrominance) keeps its scale.
        let range = if hi > lo { hi - lo } else { 1.0 };
        stretch.min[c] = lo;
        stretch.range[c] = range;
        let norm2: f64 = FORWARD[c].iter().map(|a| a * a).sum();
        sigma[c] = (sigma2 * norm2).sqrt() / range;
        out.push(opp[c].iter().map(|v| ((v - lo) / range) as f32).collect());
    }
    (out, stretch, sigma)
}

/// Stretched opponent channels → R, G, B planes of `dim`.
pub fn from_opponent(opp: &[Vec<f32>], stretch: &Stretch, dim: (usize, usize)) -> Vec<Array2<f64>> {
    (0..3)
        .map(|c| {
            let b = INVERSE[c];
            Array2::from_shape_fn(dim, |(y, x)| {
                let i = y * dim.1 + x;
                (0..3)
                    .map(|k| b[k] * (opp[k][i] as f64 * stretch.range[k] + stretch.min[k]))
                    .sum()
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_undoes_forward() {
        for (i, inv) in INVERSE.iter().enumerate() {
            for j in 0..3 {
                let v: f64 = inv.iter().zip(&FORWARD).map(|(a, row)| a * row[j]).sum();
                assert!((v - f64::from(u8::from(i == j))).abs() < 1e-12);
            }
        }
        let dim = (4, 5);
        let rgb: Vec<Array2<f64>> = (0..3)
            .map(|c| Array2::from_shape_fn(dim, |(y, x)| (y * 5 + x + c * 7) as f64 / 40.0))
            .collect();
        let (opp, stretch, _) = to_opponent(&rgb, 0.01);
        let back = from_opponent(&opp, &stretch, dim);
        for (a, b) in rgb.iter().zip(&back) {
            for (x, y) in a.iter().zip(b) {
                assert!((x - y).abs() < 1e-5);
            }
        }
    }
}
