// One stage of a windowed DFT as a matrix product: for every row p of the input,
// out[p][q] = Σ_k in[p][k] · w((k_start + k)(q_start + q) mod M), w(t) = exp(∓2πi t/M) read from a
// table computed in f64 on the CPU. The optimizer's window transform is two such stages (x, then
// y), its adjoint two more with the conjugate kernel; the first stage of each writes its result
// transposed, so the second reads its summed index contiguously.
//
// 16×16 tiles: each workgroup stages 16 input values per row and the 16×16 kernel values of its
// outputs in workgroup memory, one tile of k at a time. The kernel's index is formed in integers
// (k_start + k and q_start + q reduced mod M first, so the product stays below M² < 2³²).

struct Params {
    m: u32,
    rows: u32,      // P: input rows (and output rows)
    summed: u32,    // K: the summed index's length
    outputs: u32,   // Q: outputs per row
    k_start: u32,   // the summed offsets' start, reduced mod M
    q_start: u32,   // the output offsets' start, reduced mod M
    conjugate: u32, // 1: exp(+2πi t/M) (the adjoint)
    transpose: u32, // 1: out[q][p]; 0: out[p][q]
}

@group(0) @binding(0) var<uniform> prm: Params;
@group(0) @binding(1) var<storage, read> roots: array<vec2<f32>>;
@group(0) @binding(2) var<storage, read> src: array<vec2<f32>>;
@group(0) @binding(3) var<storage, read_write> dst: array<vec2<f32>>;

const TILE: u32 = 16u;

var<workgroup> a_tile: array<array<vec2<f32>, 16>, 16>; // [p][k]
var<workgroup> w_tile: array<array<vec2<f32>, 16>, 16>; // [k][q]

@compute @workgroup_size(16, 16)
fn window_stage(
    @builtin(local_invocation_id) lid: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
) {
    let q = wid.x * TILE + lid.x;
    let p = wid.y * TILE + lid.y;
    let v = (prm.q_start + q) % prm.m;
    var acc = vec2<f32>(0.0, 0.0);
    let tiles = (prm.summed + TILE - 1u) / TILE;
    for (var t = 0u; t < tiles; t++) {
        let k0 = t * TILE;
        let ka = k0 + lid.x;
        var a = vec2<f32>(0.0, 0.0);
        if (p < prm.rows && ka < prm.summed) {
            a = src[p * prm.summed + ka];
        }
        a_tile[lid.y][lid.x] = a;
        let kw = k0 + lid.y;
        var w = vec2<f32>(0.0, 0.0);
        if (q < prm.outputs && kw < prm.summed) {
            let u = (prm.k_start + kw) % prm.m;
            w = roots[(u * v) % prm.m];
            if (prm.conjugate == 1u) {
                w.y = -w.y;
            }
        }
        w_tile[lid.y][lid.x] = w;
        workgroupBarrier();
        for (var kk = 0u; kk < TILE; kk++) {
            let x = a_tile[lid.y][kk];
            let y = w_tile[kk][lid.x];
            acc += vec2<f32>(x.x * y.x - x.y * y.y, x.x * y.y + x.y * y.x);
        }
        workgroupBarrier();
    }
    if (p < prm.rows && q < prm.outputs) {
        if (prm.transpose == 1u) {
            dst[q * prm.rows + p] = acc;
        } else {
            dst[p * prm.outputs + q] = acc;
        }
    }
}
