// One radix-2 pass of a Stockham (self-sorting) FFT over a batch of power-of-two vectors
// (E. Bainville's formulation): after log2 N passes with span = 1, 2, 4, …, N/2 the output is
// in natural order, with no bit reversal. The twiddles come from a table the CPU computed in
// f64 (WGSL's sin/cos are promised to only about 5e-4).

struct Pass {
    // Vector length N (a power of two).
    n: u32,
    // Butterfly span of this pass: 1, 2, 4, …, N/2.
    span: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> pass_: Pass;
// exp(-2πi t / N) for t < N/2.
@group(0) @binding(1) var<storage, read> twiddle: array<vec2<f32>>;
@group(0) @binding(2) var<storage, read> src: array<vec2<f32>>;
@group(0) @binding(3) var<storage, read_write> dst: array<vec2<f32>>;

fn cmul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

@compute @workgroup_size(256)
fn fft_pass(@builtin(global_invocation_id) g: vec3<u32>) {
    let half = pass_.n / 2u;
    let i = g.x;
    let b = g.y;
    if (i >= half) {
        return;
    }
    let span = pass_.span;
    let k = i & (span - 1u);
    let base = b * pass_.n;
    let u0 = src[base + i];
    // exp(-πi k / span) = exp(-2πi t / N) with t = k N / (2 span).
    let u1 = cmul(src[base + i + half], twiddle[k * (half / span)]);
    let j = 2u * i - k;
    dst[base + j] = u0 + u1;
    dst[base + j + span] = u0 - u1;
}
