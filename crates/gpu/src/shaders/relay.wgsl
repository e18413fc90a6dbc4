// The phase model's Bloch relay for a batch of directions at one wavelength (the double MLA on
// the wrapped grid): the transfer function's Bloch shift times the plate's spectrum, the
// display's slits between two Fresnel steps (the FFTs are mixed.wgsl's), the opening's factors
// and the tilt, the chirp-z convolution's kernel product, the fine intensities and the light on
// the opening. Every table and ramp comes from the CPU, computed in f64; the kernels multiply.

struct Params {
    // Bins of the wrapped grid.
    len: u32,
    // Directions in this chunk.
    batch: u32,
    // The chain's samples (the slits); the grid is open beyond them.
    n_slits: u32,
    // The opening's first grid sample, and its samples.
    start: u32,
    n_in: u32,
    // The chirp-z convolution's FFT length, and the fine sensor samples kept.
    conv: u32,
    n_out: u32,
    // Anchors per direction of the shift (one per 256 bins) and of the tilt.
    shift_anchors: u32,
    tilt_anchors: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> spectrum: array<vec2<f32>>;
@group(0) @binding(2) var<storage, read> untilted: array<vec2<f32>>;
// Per direction: `shift_anchors` anchors, then 256 steps, in one buffer each.
@group(0) @binding(3) var<storage, read> anchors: array<vec2<f32>>;
@group(0) @binding(4) var<storage, read> steps: array<vec2<f32>>;
// Per direction: (first bin, bins, offset into `exact`, 0) of the bins given whole.
@group(0) @binding(5) var<storage, read> exact_at: array<vec4<u32>>;
@group(0) @binding(6) var<storage, read> exact: array<vec2<f32>>;
@group(0) @binding(7) var<storage, read_write> transfer: array<vec2<f32>>;
@group(0) @binding(8) var<storage, read_write> field: array<vec2<f32>>;
@group(0) @binding(9) var<storage, read> slits: array<f32>;
@group(0) @binding(10) var<storage, read> opening: array<vec2<f32>>;
@group(0) @binding(11) var<storage, read_write> conv: array<vec2<f32>>;
@group(0) @binding(12) var<storage, read> kernel: array<vec2<f32>>;
@group(0) @binding(13) var<storage, read_write> fine: array<f32>;
@group(0) @binding(14) var<storage, read_write> partials: array<f32>;

fn cmul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

// The shifted transfer function, and the plate's spectrum times it.
@compute @workgroup_size(256)
fn form_transfer(@builtin(global_invocation_id) g: vec3<u32>) {
    let n = g.x;
    let b = g.y;
    if (n >= p.len || b >= p.batch) {
        return;
    }
    let e = exact_at[b];
    var t: vec2<f32>;
    if (n >= e.x && n < e.x + e.y) {
        t = exact[e.z + n - e.x];
    } else {
        let ramp = cmul(anchors[b * p.shift_anchors + n / 256u], steps[b * 256u + n % 256u]);
        t = cmul(untilted[n], ramp);
    }
    let i = b * p.len + n;
    transfer[i] = t;
    field[i] = cmul(spectrum[n], t);
}

@compute @workgroup_size(256)
fn apply_slits(@builtin(global_invocation_id) g: vec3<u32>) {
    let n = g.x;
    let b = g.y;
    if (n >= p.n_slits || b >= p.batch) {
        return;
    }
    let i = b * p.len + n;
    field[i] = field[i] * slits[n];
}

@compute @workgroup_size(256)
fn apply_transfer(@builtin(global_invocation_id) g: vec3<u32>) {
    let n = g.x;
    let b = g.y;
    if (n >= p.len || b >= p.batch) {
        return;
    }
    let i = b * p.len + n;
    field[i] = cmul(field[i], transfer[i]);
}

// The chirp-z input: the field on the opening times MLA 2, the lens, the input chirp and the
// tilt (the tilt's ramp in `anchors`/`steps`, which this kernel reads as the tilt's), zero
// beyond.
@compute @workgroup_size(256)
fn opening_input(@builtin(global_invocation_id) g: vec3<u32>) {
    let j = g.x;
    let b = g.y;
    if (j >= p.conv || b >= p.batch) {
        return;
    }
    var v = vec2<f32>(0.0, 0.0);
    if (j < p.n_in) {
        let tilt = cmul(anchors[b * p.tilt_anchors + j / 256u], steps[b * 256u + j % 256u]);
        v = cmul(cmul(field[b * p.len + p.start + j], opening[j]), tilt);
    }
    conv[b * p.conv + j] = v;
}

// Σ|input|² per direction, one workgroup each: 256 compensated partial sums for the CPU to add.
@compute @workgroup_size(256)
fn energy(@builtin(local_invocation_id) l: vec3<u32>, @builtin(workgroup_id) w: vec3<u32>) {
    let b = w.y;
    var s = 0.0;
    var c = 0.0;
    for (var j = l.x; j < p.n_in; j = j + 256u) {
        let v = conv[b * p.conv + j];
        let y = dot(v, v) - c;
        let t = s + y;
        c = (t - s) - y;
        s = t;
    }
    partials[b * 256u + l.x] = s;
}

@compute @workgroup_size(256)
fn apply_kernel(@builtin(global_invocation_id) g: vec3<u32>) {
    let j = g.x;
    let b = g.y;
    if (j >= p.conv || b >= p.batch) {
        return;
    }
    let i = b * p.conv + j;
    conv[i] = cmul(conv[i], kernel[j]);
}

@compute @workgroup_size(256)
fn fine_intensity(@builtin(global_invocation_id) g: vec3<u32>) {
    let m = g.x;
    let b = g.y;
    if (m >= p.n_out || b >= p.batch) {
        return;
    }
    let v = conv[b * p.conv + m];
    fine[b * p.n_out + m] = dot(v, v);
}
