// The passes of a Stockham (self-sorting) FFT over a batch of power-of-two vectors, one vector
// per row of the dispatch (E. Bainville's formulation): radix-4 passes with span = 1, 4, 16, …
// and, where log2 N is odd, one radix-2 pass last; the output is in natural order, with no bit
// reversal. The twiddles come from a table the CPU computed in
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

// exp(-2πi t / N) for t < N: the table holds t < N/2, and w^(t + N/2) = −w^t.
fn twiddle_at(t: u32) -> vec2<f32> {
    let half = pass_.n / 2u;
    if (t < half) {
        return twiddle[t];
    }
    return -twiddle[t - half];
}

// One radix-4 pass (span = 1, 4, 16, …): half the passes of radix 2 and a quarter fewer
// twiddle products; a final radix-2 pass (`fft_pass`) completes a length that is not a power
// of four.
@compute @workgroup_size(256)
fn fft_pass4(@builtin(global_invocation_id) g: vec3<u32>) {
    let quarter = pass_.n / 4u;
    let i = g.x;
    let b = g.y;
    if (i >= quarter) {
        return;
    }
    let span = pass_.span;
    let k = i & (span - 1u);
    let base = b * pass_.n;
    // exp(-2πi k / (4 span)) = exp(-2πi t / N) with t = k N / (4 span).
    let t = k * (quarter / span);
    let u0 = src[base + i];
    let u1 = cmul(src[base + i + quarter], twiddle_at(t));
    let u2 = cmul(src[base + i + 2u * quarter], twiddle_at(2u * t));
    let u3 = cmul(src[base + i + 3u * quarter], twiddle_at(3u * t));
    let v0 = u0 + u2;
    let v1 = u0 - u2;
    let v2 = u1 + u3;
    let d = u1 - u3;
    // −i·d.
    let v3 = vec2<f32>(d.y, -d.x);
    let j = 4u * i - 3u * k;
    dst[base + j] = v0 + v2;
    dst[base + j + span] = v1 + v3;
    dst[base + j + 2u * span] = v0 - v2;
    dst[base + j + 3u * span] = v1 - v3;
}
