// The Bluestein (chirp-z) steps around the power-of-two FFT that make a DFT of any length M:
// X_k = conj(c_k) · Σ_n [x_n conj(c_n)] c_{k−n}, c_j = exp(iπ j² / M), the sum a circular
// convolution of length N ≥ M + L − 1 done as FFT → product with the chirp's spectrum (from the
// CPU, in f64) → FFT of the conjugate (an inverse FFT up to a conjugate and 1/N).
//
// The 2-D transform of a sparse field: each nonzero row's DFT along x (rows), written
// transposed into one column per kept frequency, then each column's DFT along y, whose |·|² is
// the intensity. A real field keeps kx ≤ M/2 (the other half is the mirror image); a complex
// one (a pupil with a phase) has no such symmetry and keeps all M.

struct Params {
    // DFT length M.
    m: u32,
    // Convolution length N (a power of two).
    n: u32,
    // Vectors in this chunk.
    batch: u32,
    // Index of the chunk's first vector: a field row, or a column kx.
    first: u32,
    // Input samples per column (the field's rows, Ly).
    ly: u32,
    // Columns kept: M/2 + 1, or M for a complex field.
    cols: u32,
    // 1 / N.
    inv_n: f32,
    // 1 when `values` holds (re, im) pairs: a complex field.
    complex: u32,
}

@group(0) @binding(0) var<uniform> p: Params;
// c_j for j < M.
@group(0) @binding(1) var<storage, read> chirp: array<vec2<f32>>;
// Per field row: (y, x0, samples, offset into `values` in samples), rows and columns counted
// from the field's corner.
@group(0) @binding(2) var<storage, read> rows: array<vec4<u32>>;
@group(0) @binding(3) var<storage, read> values: array<f32>;
// FFT of the convolution kernel v (length N).
@group(0) @binding(4) var<storage, read> kernel: array<vec2<f32>>;
// The chunk's vectors, N each.
@group(0) @binding(5) var<storage, read_write> work: array<vec2<f32>>;
// Row spectra transposed: [kx][y], `cols` × Ly.
@group(0) @binding(6) var<storage, read_write> columns: array<vec2<f32>>;
// |X|² per kept column: [kx][ky], `cols` × M.
@group(0) @binding(7) var<storage, read_write> intensity: array<f32>;

fn cmul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

fn conj(a: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(a.x, -a.y);
}

// u_n = a_n conj(c_n) for one field row, zero beyond it.
@compute @workgroup_size(256)
fn prechirp_rows(@builtin(global_invocation_id) g: vec3<u32>) {
    let n = g.x;
    let b = g.y;
    if (n >= p.n || b >= p.batch) {
        return;
    }
    let h = rows[p.first + b];
    var u = vec2<f32>(0.0, 0.0);
    if (n >= h.y && n < h.y + h.z) {
        let i = h.w + n - h.y;
        if (p.complex == 1u) {
            u = cmul(vec2<f32>(values[2u * i], values[2u * i + 1u]), conj(chirp[n]));
        } else {
            u = values[i] * conj(chirp[n]);
        }
    }
    work[b * p.n + n] = u;
}

// conj(U · V): the next forward FFT then gives N · conj(u ⊛ v).
@compute @workgroup_size(256)
fn convolve(@builtin(global_invocation_id) g: vec3<u32>) {
    let n = g.x;
    let b = g.y;
    if (n >= p.n || b >= p.batch) {
        return;
    }
    let i = b * p.n + n;
    work[i] = conj(cmul(work[i], kernel[n]));
}

// X_kx = conj(c_kx) (u ⊛ v)_kx = conj(c_kx · y_kx) / N for the kept kx, stored in column kx
// at the row's y.
@compute @workgroup_size(256)
fn postchirp_rows(@builtin(global_invocation_id) g: vec3<u32>) {
    let kx = g.x;
    let b = g.y;
    if (kx >= p.cols || b >= p.batch) {
        return;
    }
    let y = rows[p.first + b].x;
    columns[kx * p.ly + y] = p.inv_n * conj(cmul(chirp[kx], work[b * p.n + kx]));
}

// u_n = X_n(kx) conj(c_n) down one column, zero beyond the field.
@compute @workgroup_size(256)
fn prechirp_columns(@builtin(global_invocation_id) g: vec3<u32>) {
    let n = g.x;
    let b = g.y;
    if (n >= p.n || b >= p.batch) {
        return;
    }
    var u = vec2<f32>(0.0, 0.0);
    if (n < p.ly) {
        u = cmul(columns[(p.first + b) * p.ly + n], conj(chirp[n]));
    }
    work[b * p.n + n] = u;
}

// |X_ky|² = |y_ky|² / N²: the chirp in front has modulus one.
@compute @workgroup_size(256)
fn intensity_columns(@builtin(global_invocation_id) g: vec3<u32>) {
    let k = g.x;
    let b = g.y;
    if (k >= p.m || b >= p.batch) {
        return;
    }
    let y = p.inv_n * work[b * p.n + k];
    intensity[(p.first + b) * p.m + k] = dot(y, y);
}
