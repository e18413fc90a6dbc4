// One pass of a mixed-radix Stockham FFT over a batch of vectors whose length N has no prime
// factor above 5 (the phase model's grids, whose length fixes the wrap-around period and so
// cannot be rounded up to a power of two): radix R ∈ {2, 3, 4, 5}, span = the product of the
// earlier passes' radices, the output in natural order. R is a pipeline constant, one pipeline
// per radix, so that the butterfly's loops have fixed bounds and unroll. Forward or inverse (unnormalised), by
// conjugating the twiddles. The twiddles, and the radix's own roots of unity, come from one
// table exp(−2πi t/N), t < N, computed in f64 on the CPU.

override RADIX: u32 = 2u;

struct Pass {
    n: u32,
    span: u32,
    // The pipeline's RADIX (kept for the layout).
    radix: u32,
    // 1 for the inverse transform.
    inverse: u32,
}

@group(0) @binding(0) var<uniform> ps: Pass;
@group(0) @binding(1) var<storage, read> table: array<vec2<f32>>;
@group(0) @binding(2) var<storage, read> src: array<vec2<f32>>;
@group(0) @binding(3) var<storage, read_write> dst: array<vec2<f32>>;

fn cmul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

// exp(∓2πi t/N), t < N.
fn w(t: u32) -> vec2<f32> {
    let v = table[t];
    if (ps.inverse != 0u) {
        return vec2<f32>(v.x, -v.y);
    }
    return v;
}

@compute @workgroup_size(256)
fn fft_radix(@builtin(global_invocation_id) g: vec3<u32>) {
    let r = RADIX;
    let stride = ps.n / r;
    let i = g.x;
    let b = g.y;
    if (i >= stride) {
        return;
    }
    let span = ps.span;
    let k = i % span;
    let base = b * ps.n;
    // The butterfly's inputs, twiddled by exp(−2πi q k / (span R)) = w(q k N / (span R)).
    let step = k * (stride / span);
    var v: array<vec2<f32>, 5>;
    for (var q = 0u; q < r; q = q + 1u) {
        v[q] = cmul(src[base + i + q * stride], w(q * step));
    }
    // The length-R DFT, its roots exp(−2πi m/R) = w(m N/R).
    let j = (i / span) * span * r + k;
    for (var q = 0u; q < r; q = q + 1u) {
        var acc = v[0];
        for (var s = 1u; s < r; s = s + 1u) {
            acc = acc + cmul(v[s], w(((q * s) % r) * stride));
        }
        dst[base + j + q * span] = acc;
    }
}
