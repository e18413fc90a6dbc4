//! The plate as a binary STL solid.

use super::*;

use super::pieces::{Piece, Shape, pieces};

/// One vertex of the STL's top profile: x in grid units, z (base + height) in µm.
#[derive(Debug, Clone, Copy)]
struct TopPoint {
    x: i64,
    z_um: f64,
}

/// The x grid of the STL: 1 nm, coarsened by tens while single precision could not tell
/// neighbouring grid points apart (f32 spacing near v is at most v·2⁻²³; four per grid step).
fn stl_grid_um(extent_um: f64) -> f64 {
    let mut grid = DB_UNIT_UM;
    while 4.0 * extent_um * 2f64.powi(-23) > grid && grid < 1e6 {
        grid *= 10.0;
    }
    grid
}

/// The top of the plate's cross-section, left to right: both sides of every jump at the same
/// x (so walls are vertical), curved pieces as chords at most `sample_um` long, flat runs as
/// their two ends.
fn top_profile(
    design: &PhaseDesign,
    pieces: &[Piece],
    sample_um: f64,
    base_um: f64,
    grid_um: f64,
) -> Result<Vec<TopPoint>, IoError> {
    let snap = |x: f64| (x / grid_um).round() as i64;
    let divisions = |p: &Piece, cells: i64| match p.shape {
        Shape::Flat { .. } => 1,
        Shape::Curved { .. } => {
            ((cells as f64 * grid_um / sample_um).ceil() as i64).clamp(1, cells)
        }
    };
    let estimate: f64 = pieces
        .iter()
        .map(|p| divisions(p, (snap(p.x1_um) - snap(p.x0_um)).max(1)) as f64 + 1.0)
        .sum();
    // Each profile vertex costs about eight triangles (top, bottom, two caps).
    if !(8.0 * estimate <= MAX_STL_TRIANGLES as f64) {
        return Err(invalid(format!(
            "sample_um = {sample_um}: the plate would need about {:.0} triangles, more than \
             {MAX_STL_TRIANGLES}; use a coarser sample (or a height step)",
            8.0 * estimate
        )));
    }
    let mut pts: Vec<TopPoint> = Vec::with_capacity(estimate as usize);
    // Jumps smaller than half a grid step are not walls: single precision could not draw them.
    let push = |pts: &mut Vec<TopPoint>, p: TopPoint| match pts.last() {
        Some(last) if last.x == p.x && (last.z_um - p.z_um).abs() < grid_um / 2.0 => {}
        _ => pts.push(p),
    };
    for p in pieces {
        let (x0, x1) = (snap(p.x0_um), snap(p.x1_um));
        if x1 <= x0 {
            continue;
        }
        let n = divisions(p, x1 - x0);
        for i in 0..=n {
            let x = x0 + ((x1 - x0) as f64 * i as f64 / n as f64).round() as i64;
            let z_um = base_um + p.height_um(design, x as f64 * grid_um);
            push(&mut pts, TopPoint { x, z_um });
        }
    }
    // Flat runs keep only their ends.
    let flat = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(1.0);
    let mut out: Vec<TopPoint> = Vec::with_capacity(pts.len());
    for p in pts {
        if let [.., a, b] = out.as_slice()
            && a.x < b.x
            && b.x < p.x
            && flat(a.z_um, b.z_um)
            && flat(b.z_um, p.z_um)
        {
            out.pop();
        }
        out.push(p);
    }
    Ok(out)
}

/// Triangles in the x–z plane, counter-clockwise, filling the column between the vertical
/// chains `a` (at `xa`) and `b` (at `xb > xa`), each listed bottom to top. Every triangle has two
/// vertices on one chain and one on the other, so none is degenerate.
fn zipper(xa: f64, a: &[f64], xb: f64, b: &[f64], out: &mut Vec<[[f64; 2]; 3]>) {
    let (mut i, mut j) = (0, 0);
    while i + 1 < a.len() || j + 1 < b.len() {
        let advance_b = i + 1 >= a.len() || (j + 1 < b.len() && b[j + 1] <= a[i + 1]);
        if advance_b {
            out.push([[xa, a[i]], [xb, b[j]], [xb, b[j + 1]]]);
            j += 1;
        } else {
            out.push([[xa, a[i]], [xb, b[j]], [xa, a[i + 1]]]);
            i += 1;
        }
    }
}

fn triangle(p: [[f64; 3]; 3]) -> Triangle {
    let d1 = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
    let d2 = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
    let n = [
        d1[1] * d2[2] - d1[2] * d2[1],
        d1[2] * d2[0] - d1[0] * d2[2],
        d1[0] * d2[1] - d1[1] * d2[0],
    ];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let unit = |v: f64| if len > 0.0 { (v / len) as f32 } else { 0.0 };
    Triangle {
        normal: Normal::new([unit(n[0]), unit(n[1]), unit(n[2])]),
        vertices: p.map(|v| Vertex::new([v[0] as f32, v[1] as f32, v[2] as f32])),
    }
}

/// The closed surface of the extruded cross-section. The cross-section's boundary (top left to
/// right, down the right end, back along the bottom through every column edge, up the left end)
/// runs clockwise in x–z, so extruding each boundary edge `p → q` as `(p0, q0, q1), (p0, q1, p1)`
/// points every side face outward; the end caps are counter-clockwise column strips at y = −L/2
/// (normal −y) and reversed at +L/2. Every edge is then shared by exactly two triangles, once
/// in each direction.
fn plate_triangles(
    top: &[TopPoint],
    grid_um: f64,
    length_um: f64,
) -> Result<Vec<Triangle>, IoError> {
    // Each distinct x with the heights just left and right of it (equal without a jump).
    let mut columns: Vec<(f64, f64, f64)> = Vec::new();
    for p in top {
        let x = p.x as f64 * grid_um;
        match columns.last_mut() {
            Some(c) if c.0 == x => c.2 = p.z_um,
            _ => columns.push((x, p.z_um, p.z_um)),
        }
    }
    if columns.len() < 2 {
        return Err(invalid(
            "the plate has no width to triangulate; check the design".into(),
        ));
    }
    let mut boundary: Vec<[f64; 2]> = top.iter().map(|p| [p.x as f64 * grid_um, p.z_um]).collect();
    boundary.extend(columns.iter().rev().map(|c| [c.0, 0.0]));
    let mut cap = Vec::new();
    for w in columns.windows(2) {
        let (xa, la, ra) = w[0];
        let (xb, lb, rb) = w[1];
        // A jump at an edge splits that side where the lower of its two heights meets it.
        let a: Vec<f64> = if la < ra {
            vec![0.0, la, ra]
        } else {
            vec![0.0, ra]
        };
        let b: Vec<f64> = if rb < lb {
            vec![0.0, rb, lb]
        } else {
            vec![0.0, lb]
        };
        zipper(xa, &a, xb, &b, &mut cap);
    }
    let total = 2 * boundary.len() + 2 * cap.len();
    if total > MAX_STL_TRIANGLES {
        return Err(invalid(format!(
            "the plate needs {total} triangles, more than {MAX_STL_TRIANGLES}; \
             use a coarser sample_um"
        )));
    }
    let (y0, y1) = (-length_um / 2.0, length_um / 2.0);
    let at = |p: [f64; 2], y: f64| [p[0], y, p[1]];
    let mut tris = Vec::with_capacity(total);
    for (k, &p) in boundary.iter().enumerate() {
        let q = boundary[(k + 1) % boundary.len()];
        tris.push(triangle([at(p, y0), at(q, y0), at(q, y1)]));
        tris.push(triangle([at(p, y0), at(q, y1), at(p, y1)]));
    }
    for t in &cap {
        tris.push(triangle([at(t[0], y0), at(t[1], y0), at(t[2], y0)]));
        tris.push(triangle([at(t[0], y1), at(t[2], y1), at(t[1], y1)]));
    }
    Ok(tris)
}

/// Binary STL header text: units first, since STL itself has none. Must not begin with
/// `solid`, which readers take for ASCII STL.
const STL_HEADER: &str = "UDC Studio phase plate; units: micrometres (um); x lenslets, z up";

/// Writes a closed, watertight binary STL of the plate for two-photon printing: the
/// cross-section `{0 ≤ z ≤ base + h(x)}` over the array extruded along y over `length_um`,
/// centred on the origin, in µm. Steps and fold wraps are vertical walls; flat runs are single
/// strips; curved parts are chords at most `sample_um` long (a quantised plate is exact and
/// `sample_um` then does not matter). x is snapped to a 1 nm grid (coarser only when the plate
/// is too wide for single precision to keep 1 nm apart; the summary states it).
///
/// # Errors
/// Names `sample_um`, `length_um` or `base_um` when out of range or the mesh would be too
/// large; [`IoError::File`] when the file cannot be written.
pub fn write_height_stl(
    design: &PhaseDesign,
    path: &Path,
    sample_um: f64,
    length_um: f64,
    base_um: f64,
    min_feature_um: f64,
) -> Result<ExportSummary, IoError> {
    let lenslets = lenslets_of(design)?;
    check_sample(design, sample_um)?;
    check_length(length_um)?;
    check_um("base_um", base_um, MIN_BASE_UM, MAX_BASE_UM, "")?;
    let pieces = pieces(design, &lenslets, min_feature_um)?;
    let tallest = lenslets.max_height_um(design);
    let grid_um = stl_grid_um((lenslets.span_um() / 2.0).max(base_um + tallest));
    let top = top_profile(design, &pieces, sample_um, base_um, grid_um)?;
    let tris = plate_triangles(&top, grid_um, length_um)?;
    write_stl_file(path, &tris)?;
    let max_z = max_of(top.iter().map(|p| p.z_um));
    let mut summary = ExportSummary::new(
        path,
        HeightFormat::Stl,
        lenslets.span_um(),
        (max_z - base_um).max(0.0),
    );
    summary.samples = Some(top.len());
    summary.sample_um = Some(sample_um);
    summary.triangles = Some(tris.len());
    summary.length_um = Some(length_um);
    summary.base_um = Some(base_um);
    summary.grid_um = Some(grid_um);
    Ok(summary)
}

/// Writes beside the target and renames, so a failed export leaves no half file behind.
fn write_stl_file(path: &Path, tris: &[Triangle]) -> Result<(), IoError> {
    let temp = TempFile::beside(path)?;
    let io = |e| IoError::file("write", path, e);
    let mut file = crate::safe_file::open_reserved(temp.path()).map_err(io)?;
    stl_io::write_stl(&mut file, tris.iter()).map_err(io)?;
    // stl_io writes a blank header; the units go in it afterwards.
    let mut header = [0u8; 80];
    let text = STL_HEADER.as_bytes();
    let n = text.len().min(header.len());
    header[..n].copy_from_slice(&text[..n]);
    file.seek(SeekFrom::Start(0)).map_err(io)?;
    file.write_all(&header).map_err(io)?;
    file.flush().map_err(io)?;
    drop(file);
    temp.persist()
}
