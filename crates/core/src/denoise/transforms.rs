//! The separable transforms of BM3D's collaborative filter: the orthonormal 8×8 DCT-II on each
//! block, the orthonormal Haar wavelet along the group, and the Kaiser window that weights the
//! aggregation. Blocks are `[f32; 64]`, row-major; all transforms are orthonormal, so a noise
//! variance σ² in pixels is σ² on every coefficient and the hard threshold is `λ σ` everywhere.

/// Side of a block, pixels (the paper's N1 = 8, as the reference implementation's default).
pub const BLOCK: usize = 8;
/// Pixels of a block.
pub const BLOCK_LEN: usize = BLOCK * BLOCK;

/// A block of pixels or coefficients, row-major.
pub type Block = [f32; BLOCK_LEN];

/// The orthonormal DCT-II matrix `C[k][n] = s_k cos(π (2n + 1) k / 16)`.
fn dct_matrix() -> [[f32; BLOCK]; BLOCK] {
    let mut c = [[0f32; BLOCK]; BLOCK];
    let n = BLOCK as f64;
    for (k, row) in c.iter_mut().enumerate() {
        let s = if k == 0 {
            (1.0 / n).sqrt()
        } else {
            (2.0 / n).sqrt()
        };
        for (i, v) in row.iter_mut().enumerate() {
            *v = (s * (std::f64::consts::PI * (2.0 * i as f64 + 1.0) * k as f64 / (2.0 * n)).cos())
                as f32;
        }
    }
    c
}

/// The DCT matrix, built once per denoise call.
#[derive(Debug, Clone)]
pub struct Dct8 {
    c: [[f32; BLOCK]; BLOCK],
}

impl Default for Dct8 {
    fn default() -> Self {
        Dct8 { c: dct_matrix() }
    }
}

type Row = [f32; BLOCK];

#[inline(always)]
fn row(x: &Block, i: usize) -> Row {
    let mut r = [0f32; BLOCK];
    r.copy_from_slice(&x[i * BLOCK..(i + 1) * BLOCK]);
    r
}

#[inline(always)]
fn add(a: &Row, b: &Row) -> Row {
    std::array::from_fn(|j| a[j] + b[j])
}

#[inline(always)]
fn sub(a: &Row, b: &Row) -> Row {
    std::array::from_fn(|j| a[j] - b[j])
}

#[inline(always)]
fn scale(a: &Row, s: f32) -> Row {
    std::array::from_fn(|j| a[j] * s)
}

#[inline(always)]
fn mul_add2(a: &Row, sa: f32, b: &Row, sb: f32) -> Row {
    std::array::from_fn(|j| a[j] * sa + b[j] * sb)
}

#[inline(always)]
fn mul_add4(x: [&Row; 4], s: [f32; 4]) -> Row {
    std::array::from_fn(|j| x[0][j] * s[0] + x[1][j] * s[1] + x[2][j] * s[2] + x[3][j] * s[3])
}

#[inline(always)]
fn transpose(x: &Block) -> Block {
    std::array::from_fn(|k| x[(k % BLOCK) * BLOCK + k / BLOCK])
}

impl Dct8 {
    /// `C · x` down the columns of `x`, all eight columns at once, by the even/odd split of
    /// the DCT-II (`C[k][7 − n] = ±C[k][n]`): 8 sums and differences, then the even half split
    /// once more and a 4×4 product for the odd half (about 2.5× fewer operations than `C · x`).
    #[inline(always)]
    fn columns_forward(&self, x: &Block) -> Block {
        let c = &self.c;
        let r: [Row; BLOCK] = std::array::from_fn(|i| row(x, i));
        let s: [Row; 4] = std::array::from_fn(|k| add(&r[k], &r[7 - k]));
        let d: [Row; 4] = std::array::from_fn(|k| sub(&r[k], &r[7 - k]));
        let (a0, a1) = (add(&s[0], &s[3]), add(&s[1], &s[2]));
        let (b0, b1) = (sub(&s[0], &s[3]), sub(&s[1], &s[2]));
        let mut out = [0f32; BLOCK_LEN];
        let mut put = |k: usize, v: Row| out[k * BLOCK..(k + 1) * BLOCK].copy_from_slice(&v);
        put(0, scale(&add(&a0, &a1), c[0][0]));
        put(4, scale(&sub(&a0, &a1), c[4][0]));
        put(2, mul_add2(&b0, c[2][0], &b1, c[2][1]));
        put(6, mul_add2(&b0, c[6][0], &b1, c[6][1]));
        for k in [1usize, 3, 5, 7] {
            put(
                k,
                mul_add4(
                    [&d[0], &d[1], &d[2], &d[3]],
                    [c[k][0], c[k][1], c[k][2], c[k][3]],
                ),
            );
        }
        out
    }

    /// `Cᵀ · y` down the columns, the inverse of [`Dct8::columns_forward`].
    #[inline(always)]
    fn columns_inverse(&self, y: &Block) -> Block {
        let c = &self.c;
        let r: [Row; BLOCK] = std::array::from_fn(|i| row(y, i));
        let p = scale(&r[0], c[0][0]);
        let q = scale(&r[4], c[4][0]);
        let (a0, a1) = (add(&p, &q), sub(&p, &q));
        let b0 = mul_add2(&r[2], c[2][0], &r[6], c[6][0]);
        let b1 = mul_add2(&r[2], c[2][1], &r[6], c[6][1]);
        let e = [add(&a0, &b0), add(&a1, &b1), sub(&a1, &b1), sub(&a0, &b0)];
        let o: [Row; 4] = std::array::from_fn(|n| {
            mul_add4(
                [&r[1], &r[3], &r[5], &r[7]],
                [c[1][n], c[3][n], c[5][n], c[7][n]],
            )
        });
        let mut out = [0f32; BLOCK_LEN];
        for n in 0..4 {
            out[n * BLOCK..(n + 1) * BLOCK].copy_from_slice(&add(&e[n], &o[n]));
            out[(7 - n) * BLOCK..(8 - n) * BLOCK].copy_from_slice(&sub(&e[n], &o[n]));
        }
        out
    }

    /// 2-D forward DCT. The coefficients come out transposed (`(C X Cᵀ)ᵀ`): every use is
    /// coefficient by coefficient (thresholds, Wiener gains, the Haar transform along the group),
    /// so the order does not matter as long as [`Dct8::inverse`] takes the same order.
    #[inline]
    pub fn forward(&self, x: &Block) -> Block {
        self.columns_forward(&transpose(&self.columns_forward(x)))
    }

    /// 2-D inverse DCT of [`Dct8::forward`]'s coefficients.
    #[inline]
    pub fn inverse(&self, y: &Block) -> Block {
        self.columns_inverse(&transpose(&self.columns_inverse(y)))
    }
}

/// The 2-D block transform of a stage: a closed set, as the paper offers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BlockTransform {
    /// The orthonormal DCT-II (fast even/odd route).
    #[default]
    Dct,
    /// The biorthogonal 1.5 wavelet, full decomposition, each basis row of unit norm (the
    /// reference implementation's matrix; its hard-threshold stage uses it).
    Bior15,
}

/// The reference implementation's 8-point bior1.5 forward matrix (rows: basis elements of unit
/// l2 norm), as its package hard-codes it.
const BIOR15: [[f64; BLOCK]; BLOCK] = [
    [0.343550200747110; BLOCK],
    [
        -0.225454819240296,
        -0.461645582253923,
        -0.461645582253923,
        -0.225454819240296,
        0.225454819240296,
        0.461645582253923,
        0.461645582253923,
        0.225454819240296,
    ],
    [
        0.569359398342840,
        0.402347308162280,
        -0.402347308162280,
        -0.569359398342840,
        -0.083506045090280,
        0.083506045090280,
        -0.083506045090280,
        0.083506045090280,
    ],
    [
        -0.083506045090280,
        0.083506045090280,
        -0.083506045090280,
        0.083506045090280,
        0.569359398342840,
        0.402347308162280,
        -0.402347308162280,
        -0.569359398342840,
    ],
    [
        0.707106781186550,
        -0.707106781186550,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.0,
        0.0,
        0.707106781186550,
        -0.707106781186550,
        0.0,
        0.0,
        0.0,
        0.0,
    ],
    [
        0.0,
        0.0,
        0.0,
        0.0,
        0.707106781186550,
        -0.707106781186550,
        0.0,
        0.0,
    ],
    [
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.707106781186550,
        -0.707106781186550,
    ],
];

/// Inverts an 8×8 matrix by Gauss-Jordan elimination with partial pivoting (`None` if singular).
fn invert(m: &[[f64; BLOCK]; BLOCK]) -> Option<[[f64; BLOCK]; BLOCK]> {
    let mut a = *m;
    let mut inv = [[0f64; BLOCK]; BLOCK];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for col in 0..BLOCK {
        let pivot = (col..BLOCK).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[pivot][col].abs() < 1e-12 {
            return None;
        }
        a.swap(col, pivot);
        inv.swap(col, pivot);
        let p = a[col][col];
        for j in 0..BLOCK {
            a[col][j] /= p;
            inv[col][j] /= p;
        }
        for r in 0..BLOCK {
            if r != col {
                let f = a[r][col];
                for j in 0..BLOCK {
                    a[r][j] -= f * a[col][j];
                    inv[r][j] -= f * inv[col][j];
                }
            }
        }
    }
    Some(inv)
}

/// `out = a · x` for 8×8 row-major matrices, one row of `x` scaled and added at a time (each
/// row stays in vector registers).
#[inline(always)]
fn left_mul(a: &[[f32; BLOCK]; BLOCK], x: &Block) -> Block {
    let mut out = [0f32; BLOCK_LEN];
    for i in 0..BLOCK {
        let mut r = [0f32; BLOCK];
        for (k, &aik) in a[i].iter().enumerate() {
            let xr = &x[k * BLOCK..(k + 1) * BLOCK];
            for j in 0..BLOCK {
                r[j] += aik * xr[j];
            }
        }
        out[i * BLOCK..(i + 1) * BLOCK].copy_from_slice(&r);
    }
    out
}

/// A stage's 2-D block transform, ready to apply: the DCT by its fast route, any other by
/// its forward and inverse matrices.
#[derive(Debug, Clone)]
pub struct Transform2d {
    dct: Option<Dct8>,
    forward: [[f32; BLOCK]; BLOCK],
    inverse: [[f32; BLOCK]; BLOCK],
}

impl Transform2d {
    /// The transform of `kind`.
    pub fn new(kind: BlockTransform) -> Self {
        let to_f32 = |m: &[[f64; BLOCK]; BLOCK]| {
            std::array::from_fn(|i| std::array::from_fn(|j| m[i][j] as f32))
        };
        let dct = || {
            let d = Dct8::default();
            let forward = d.c;
            let inverse = std::array::from_fn(|i| std::array::from_fn(|j| d.c[j][i]));
            Transform2d {
                dct: Some(d),
                forward,
                inverse,
            }
        };
        match kind {
            BlockTransform::Dct => dct(),
            // The hard-coded matrix is a wavelet basis, so invertible; the DCT would stand in
            // should that ever fail.
            BlockTransform::Bior15 => match invert(&BIOR15) {
                Some(inv) => Transform2d {
                    dct: None,
                    forward: to_f32(&BIOR15),
                    inverse: to_f32(&inv),
                },
                None => dct(),
            },
        }
    }

    /// Standard deviation of each coefficient for white noise of unit variance (the forward
    /// transform's basis norms `‖t_k‖ ‖t_l‖`; 1 for the orthonormal DCT), in the coefficient
    /// order of [`Transform2d::forward`].
    pub fn noise_scale(&self) -> Block {
        let norm: [f32; BLOCK] =
            std::array::from_fn(|k| self.forward[k].iter().map(|v| v * v).sum::<f32>().sqrt());
        std::array::from_fn(|i| norm[i / BLOCK] * norm[i % BLOCK])
    }

    /// Forward 2-D transform (coefficients transposed, see [`Dct8::forward`]).
    #[inline]
    pub fn forward(&self, x: &Block) -> Block {
        match &self.dct {
            Some(d) => d.forward(x),
            None => left_mul(&self.forward, &transpose(&left_mul(&self.forward, x))),
        }
    }

    /// Inverse of [`Transform2d::forward`].
    #[inline]
    pub fn inverse(&self, y: &Block) -> Block {
        match &self.dct {
            Some(d) => d.inverse(y),
            None => left_mul(&self.inverse, &transpose(&left_mul(&self.inverse, y))),
        }
    }
}

/// Orthonormal Haar transform along the group (full decomposition), in place.
/// `group.len()` must be a power of two; `scratch` at least as long.
pub fn haar_forward(group: &mut [Block], scratch: &mut [Block]) {
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let mut len = group.len();
    while len > 1 {
        let half = len / 2;
        for i in 0..half {
            let (a, b) = (&group[2 * i], &group[2 * i + 1]);
            let (lo, hi) = (&mut [0f32; BLOCK_LEN], &mut [0f32; BLOCK_LEN]);
            for k in 0..BLOCK_LEN {
                lo[k] = (a[k] + b[k]) * s;
                hi[k] = (a[k] - b[k]) * s;
            }
            scratch[i] = *lo;
            scratch[half + i] = *hi;
        }
        group[..len].copy_from_slice(&scratch[..len]);
        len = half;
    }
}

/// Inverse of [`haar_forward`], in place.
pub fn haar_inverse(group: &mut [Block], scratch: &mut [Block]) {
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let n = group.len();
    let mut len = 2;
    while len <= n {
        let half = len / 2;
        for i in 0..half {
            let (lo, hi) = (&group[i], &group[half + i]);
            let (a, b) = (&mut [0f32; BLOCK_LEN], &mut [0f32; BLOCK_LEN]);
            for k in 0..BLOCK_LEN {
                a[k] = (lo[k] + hi[k]) * s;
                b[k] = (lo[k] - hi[k]) * s;
            }
            scratch[2 * i] = *a;
            scratch[2 * i + 1] = *b;
        }
        group[..len].copy_from_slice(&scratch[..len]);
        len *= 2;
    }
}

/// The zeroth-order modified Bessel function of the first kind, by its power series (enough
/// terms for the small arguments of a Kaiser window).
fn bessel_i0(x: f64) -> f64 {
    let mut sum = 1.0;
    let mut term = 1.0;
    let q = x * x / 4.0;
    for k in 1..40 {
        term *= q / (k as f64 * k as f64);
        sum += term;
    }
    sum
}

/// The 2-D Kaiser window `w(i) w(j)` of shape parameter `beta` over a block (the paper's
/// aggregation window; β = 2).
pub fn kaiser_block(beta: f64) -> Block {
    let n = BLOCK as f64;
    let w: Vec<f64> = (0..BLOCK)
        .map(|i| {
            let r = 2.0 * i as f64 / (n - 1.0) - 1.0;
            bessel_i0(beta * (1.0 - r * r).max(0.0).sqrt()) / bessel_i0(beta)
        })
        .collect();
    let mut out = [0f32; BLOCK_LEN];
    for i in 0..BLOCK {
        for j in 0..BLOCK {
            out[i * BLOCK + j] = (w[i] * w[j]) as f32;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn block(seed: u32) -> Block {
        let mut b = [0f32; BLOCK_LEN];
        let mut s = seed;
        for v in b.iter_mut() {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            *v = (s >> 8) as f32 / (1u32 << 24) as f32 - 0.5;
        }
        b
    }

    #[test]
    fn dct_is_orthonormal_and_inverts() {
        let d = Dct8::default();
        let x = block(7);
        let y = d.forward(&x);
        let e_x: f32 = x.iter().map(|v| v * v).sum();
        let e_y: f32 = y.iter().map(|v| v * v).sum();
        assert!((e_x - e_y).abs() < 1e-5 * e_x, "Parseval {e_x} {e_y}");
        let back = d.inverse(&y);
        for (a, b) in x.iter().zip(&back) {
            assert!((a - b).abs() < 1e-6);
        }
        // The fast route equals the matrix product C X Cᵀ (transposed).
        let c = dct_matrix();
        for k in 0..BLOCK {
            for l in 0..BLOCK {
                let mut v = 0f64;
                for i in 0..BLOCK {
                    for j in 0..BLOCK {
                        v += f64::from(c[k][i]) * f64::from(x[i * BLOCK + j]) * f64::from(c[l][j]);
                    }
                }
                assert!((v as f32 - y[l * BLOCK + k]).abs() < 1e-5, "({k}, {l})");
            }
        }
        // A constant block has only a DC coefficient, 8 × its value.
        let c = d.forward(&[0.25; BLOCK_LEN]);
        assert!((c[0] - 2.0).abs() < 1e-6);
        assert!(c[1..].iter().all(|v| v.abs() < 1e-6));
    }

    #[test]
    fn bior15_inverts_and_keeps_white_noise_white_in_variance() {
        let t = Transform2d::new(BlockTransform::Bior15);
        assert!(t.dct.is_none());
        let x = block(11);
        let back = t.inverse(&t.forward(&x));
        for (a, b) in x.iter().zip(&back) {
            assert!((a - b).abs() < 1e-5);
        }
        // White noise of unit variance has variance ‖t_k‖² ‖t_l‖² on coefficient (k, l): the
        // noise scale says so (the DCT's is 1 everywhere).
        let scale = t.noise_scale();
        let noise = |seed: u32| {
            let b = block(seed);
            t.forward(&b)
        };
        let mut var = [0f64; BLOCK_LEN];
        let trials = 20_000;
        for s in 0..trials {
            let c = noise(1000 + s);
            for k in 0..BLOCK_LEN {
                var[k] += f64::from(c[k]).powi(2) / trials as f64;
            }
        }
        // The test blocks are uniform on [-0.5, 0.5): variance 1/12.
        for k in 0..BLOCK_LEN {
            let want = f64::from(scale[k]).powi(2) / 12.0;
            assert!(
                (var[k] - want).abs() < 0.06 * want,
                "{k}: {} vs {want}",
                var[k]
            );
        }
        let dct = Transform2d::new(BlockTransform::Dct).noise_scale();
        assert!(dct.iter().all(|&s| (s - 1.0).abs() < 1e-6));
    }

    #[test]
    fn haar_is_orthonormal_and_inverts() {
        for n in [1usize, 2, 4, 8, 16, 32] {
            let orig: Vec<Block> = (0..n as u32).map(block).collect();
            let mut g = orig.clone();
            let mut scratch = vec![[0f32; BLOCK_LEN]; n];
            haar_forward(&mut g, &mut scratch);
            let e0: f32 = orig.iter().flatten().map(|v| v * v).sum();
            let e1: f32 = g.iter().flatten().map(|v| v * v).sum();
            assert!((e0 - e1).abs() < 1e-4 * e0.max(1e-6), "n = {n}");
            // The first coefficient is the group mean × √n.
            let mean0 = orig.iter().map(|b| b[0]).sum::<f32>() / n as f32;
            assert!((g[0][0] - mean0 * (n as f32).sqrt()).abs() < 1e-5);
            haar_inverse(&mut g, &mut scratch);
            for (a, b) in orig.iter().flatten().zip(g.iter().flatten()) {
                assert!((a - b).abs() < 1e-5);
            }
        }
    }

    #[test]
    fn kaiser_is_symmetric_and_peaks_inside() {
        let k = kaiser_block(2.0);
        for i in 0..BLOCK {
            for j in 0..BLOCK {
                assert_eq!(
                    k[i * BLOCK + j],
                    k[(BLOCK - 1 - i) * BLOCK + (BLOCK - 1 - j)]
                );
            }
        }
        assert!(k[3 * BLOCK + 3] > k[0]);
        assert!((k[0] as f64 - (1.0 / bessel_i0(2.0)).powi(2)).abs() < 1e-6);
    }
}
