// Sensor binning and the aliasing band of a centred M × M intensity stored [kx][ky]: a real
// field's as its kept half (columns kx ≤ M/2; a sample in the other half is its mirror image,
// I(ky, kx) = I(−ky, −kx)), a complex field's whole (`full`). Conventions: the sensor's axis pixel is
// W/2, a fine sample at signed offset s lands in pixel W/2 + floor((s + phase) / samples).

struct Params {
    m: u32,
    // Window side W, pixels.
    w: u32,
    // Fine samples per sensor pixel.
    sp: u32,
    // Band: |signed offset| ≥ edge on either axis.
    edge: u32,
    // Fine phase of the axis sample inside its pixel, x then y.
    phase_x: u32,
    phase_y: u32,
    // 1 when the intensity holds all M columns (a complex field).
    full: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> intensity: array<f32>;
@group(0) @binding(2) var<storage, read_write> sensor: array<f32>;
@group(0) @binding(3) var<storage, read_write> band: array<f32>;

// The intensity at signed offsets (t, s) = (row, column), each in [−M/2, M/2).
fn sample(t: i32, s: i32) -> f32 {
    let m = i32(p.m);
    let kx = (s + m) % m;
    let ky = (t + m) % m;
    if (kx <= m / 2 || p.full == 1u) {
        return intensity[u32(kx * m + ky)];
    }
    return intensity[u32((m - kx) * m + (m - ky) % m)];
}

@compute @workgroup_size(8, 8)
fn bin_window(@builtin(global_invocation_id) g: vec3<u32>) {
    let jx = g.x;
    let jy = g.y;
    if (jx >= p.w || jy >= p.w) {
        return;
    }
    let half = i32(p.m / 2u);
    let sp = i32(p.sp);
    let s0 = (i32(jx) - i32(p.w / 2u)) * sp - i32(p.phase_x);
    let t0 = (i32(jy) - i32(p.w / 2u)) * sp - i32(p.phase_y);
    var acc = 0.0;
    for (var dx = 0; dx < sp; dx++) {
        let s = s0 + dx;
        if (s < -half || s >= half) {
            continue;
        }
        for (var dy = 0; dy < sp; dy++) {
            let t = t0 + dy;
            if (t >= -half && t < half) {
                acc += sample(t, s);
            }
        }
    }
    sensor[jy * p.w + jx] = acc;
}

// Σ over kept column kx of the samples in the band (all of them when the column is in it).
@compute @workgroup_size(256)
fn band_columns(@builtin(global_invocation_id) g: vec3<u32>) {
    let kx = g.x;
    var cols = p.m / 2u + 1u;
    if (p.full == 1u) {
        cols = p.m;
    }
    if (kx >= cols) {
        return;
    }
    let m = i32(p.m);
    let e = i32(p.edge);
    // The column's signed offset: kx ≥ M/2 lies at kx − M (M/2 at −M/2).
    var s = i32(kx);
    if (kx >= p.m / 2u) {
        s = s - m;
    }
    let whole = abs(s) >= e;
    var acc = 0.0;
    for (var ky = 0; ky < m; ky++) {
        var t = ky;
        if (ky >= m / 2) {
            t = ky - m;
        }
        if (whole || abs(t) >= e) {
            acc += intensity[u32(i32(kx) * m + ky)];
        }
    }
    band[kx] = acc;
}
