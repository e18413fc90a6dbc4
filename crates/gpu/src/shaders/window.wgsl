// One stage of the optimizer's window transform: for each of a chunk's vectors (rows of the
// input), the chirp-z "zoom" X_q = Σ_{k<K} x_k ω^{(s+k)(t+q)}, q < Q, ω = exp(∓2πi/M), as
// pre-chirp → FFT → product with the kernel's spectrum (bluestein.wgsl's `convolve`) → FFT →
// post-chirp. The pre- and post-chirps and the kernel come from the CPU, in f64 (tables.rs,
// `zoom`); the sign of ω, the offsets s and t and 1/N are in them. The first stage of a
// transform writes its output transposed, so the second reads its summed index contiguously.

// The first four words are bluestein.wgsl's, so its `convolve` reads the same uniform.
struct Params {
    // DFT length M (in the tables; unused here).
    m: u32,
    // Convolution length N (a power of two).
    n: u32,
    // Vectors in this chunk.
    batch: u32,
    // Index of the chunk's first vector among all P.
    first: u32,
    // Input samples per vector, K.
    k_len: u32,
    // Outputs per vector, Q.
    q_len: u32,
    // Vectors in all, P.
    rows: u32,
    // 1: out[q][p]; 0: out[p][q].
    transpose: u32,
}

@group(0) @binding(0) var<uniform> p: Params;
// The pre-chirp (K values) or the post-chirp (Q values).
@group(0) @binding(1) var<storage, read> chirp: array<vec2<f32>>;
// The stage's input, P × K.
@group(0) @binding(2) var<storage, read> src: array<vec2<f32>>;
// The stage's output, P × Q (or Q × P).
@group(0) @binding(3) var<storage, read_write> dst: array<vec2<f32>>;
// The chunk's vectors, N each.
@group(0) @binding(5) var<storage, read_write> work: array<vec2<f32>>;

fn cmul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

// u_k = x_k · pre_k, zero-padded to N.
@compute @workgroup_size(256)
fn zoom_pre(@builtin(global_invocation_id) g: vec3<u32>) {
    let k = g.x;
    let b = g.y;
    if (k >= p.n || b >= p.batch) {
        return;
    }
    var u = vec2<f32>(0.0, 0.0);
    if (k < p.k_len) {
        u = cmul(src[(p.first + b) * p.k_len + k], chirp[k]);
    }
    work[b * p.n + k] = u;
}

// After `convolve` and the second FFT, work holds N · conj(u ⊛ v); X_q = post_q · conj(y_q)
// (post carries the 1/N).
@compute @workgroup_size(256)
fn zoom_post(@builtin(global_invocation_id) g: vec3<u32>) {
    let q = g.x;
    let b = g.y;
    if (q >= p.q_len || b >= p.batch) {
        return;
    }
    let y = work[b * p.n + q];
    let x = cmul(chirp[q], vec2<f32>(y.x, -y.y));
    let row = p.first + b;
    if (p.transpose == 1u) {
        dst[q * p.rows + row] = x;
    } else {
        dst[row * p.q_len + q] = x;
    }
}
