//! CBM3D's colour space: the opponent transform of Dabov et al. (ICIP 2007), each channel then
//! stretched to [0, 1] as the reference implementation does, so that its block-matching
//! thresholds (set for [0, 1] grey images) apply to the luminance unchanged. Noise that is white
//! with variance σ² in R, G and B is white in each opponent channel with variance
//! `σ² Σ_j a_cj² / range_c²`; the channels' noise correlation is ignored, as in the paper.

use ndarray::Array2;

use crate::Sample;

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

/// R, G, B → stretched opponent channels (as `f32` row-major planes; `f32` input planes are
/// converted in place), the stretch, and each channel's noise standard deviation for an RGB
/// noise variance `sigma2`.
pub fn to_opponent<T: Sample>(
    rgb: Vec<Array2<T>>,
    sigma2: f64,
) -> (Vec<Vec<f32>>, Stretch, [f64; 3]) {
    let mut planes: Vec<Vec<f32>> = rgb.into_iter().map(T::plane_into_f32).collect();
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    if let [r, g, b] = &mut planes[..] {
        for ((r, g), b) in r.iter_mut().zip(g.iter_mut()).zip(b.iter_mut()) {
            let v = [f64::from(*r), f64::from(*g), f64::from(*b)];
            let o = FORWARD.map(|a| a[0] * v[0] + a[1] * v[1] + a[2] * v[2]);
            for c in 0..3 {
                lo[c] = lo[c].min(o[c]);
                hi[c] = hi[c].max(o[c]);
            }
            (*r, *g, *b) = (o[0] as f32, o[1] as f32, o[2] as f32);
        }
    }
    let mut stretch = Stretch {
        min: [0.0; 3],
        range: [1.0; 3],
    };
    let mut sigma = [0.0; 3];
    for (c, plane) in planes.iter_mut().enumerate() {
        // A flat channel (a grey image's chrominance) keeps its scale.
        let range = if hi[c] > lo[c] { hi[c] - lo[c] } else { 1.0 };
        stretch.min[c] = lo[c];
        stretch.range[c] = range;
        let norm2: f64 = FORWARD[c].iter().map(|a| a * a).sum();
        sigma[c] = (sigma2 * norm2).sqrt() / range;
        for v in plane.iter_mut() {
            *v = ((f64::from(*v) - lo[c]) / range) as f32;
        }
    }
    (planes, stretch, sigma)
}

/// Stretched opponent channels → R, G, B planes of `dim` (in place for `f32`).
pub fn from_opponent<T: Sample>(
    mut opp: Vec<Vec<f32>>,
    stretch: &Stretch,
    dim: (usize, usize),
) -> Vec<Array2<T>> {
    if let [a, b, c] = &mut opp[..] {
        for ((a, b), c) in a.iter_mut().zip(b.iter_mut()).zip(c.iter_mut()) {
            let o = [*a, *b, *c];
            let v: [f64; 3] =
                std::array::from_fn(|k| f64::from(o[k]) * stretch.range[k] + stretch.min[k]);
            let rgb = INVERSE.map(|m| m[0] * v[0] + m[1] * v[1] + m[2] * v[2]);
            (*a, *b, *c) = (rgb[0] as f32, rgb[1] as f32, rgb[2] as f32);
        }
    }
    opp.into_iter()
        .map(|plane| {
            Array2::from_shape_vec(dim, T::vec_from_f32(plane))
                .unwrap_or_else(|_| Array2::default(dim))
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
        let (opp, stretch, _) = to_opponent(rgb.clone(), 0.01);
        let back: Vec<Array2<f64>> = from_opponent(opp, &stretch, dim);
        for (a, b) in rgb.iter().zip(&back) {
            for (x, y) in a.iter().zip(b) {
                assert!((x - y).abs() < 1e-5);
            }
        }
    }
}
