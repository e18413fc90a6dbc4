//! Phase-plate height exports (thesis §4.6) read back with independent readers (the `png`,
//! `image`, `gds21` and `stl_io` crates) and compared with the fabricated plate,
//! `plate::profile_um`, sampled densely here; that plate is the model's own profile,
//! `geometry::profile_um`, but for the part-rings at its two outer edges.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::HashMap;
use std::path::Path;

use gds21::{GdsElement, GdsLibrary};
use udc_studio::core::phase::geometry::{self, Lenslets};
use udc_studio::core::phase::{HeightRounding, Lambda0, PhaseDesign, Surface, plate};
use udc_studio::io::phase::export::{
    HeightFormat, height_csv_text, write_height_csv, write_height_gds, write_height_png,
    write_height_stl,
};

/// 17 lenslets of 168 µm, T = 1, λ0 = 530 nm: small enough to sample at a few nm. With a 0.2 µm
/// step (floored) the 1.029 µm fold holds levels 0, 0.2, … 1.0 µm.
fn small(step: Option<f64>) -> PhaseDesign {
    let mut d = PhaseDesign::thesis(168.0, 1.0);
    d.height_step_um = step;
    d
}

/// The x positions the sampled exports promise: `N = ⌊W / s⌋` samples at `(i − (N−1)/2)·s`.
fn sample_xs(d: &PhaseDesign, sample_um: f64) -> Vec<f64> {
    let span = Lenslets::new(d).unwrap().span_um();
    let n = (span / sample_um + 1e-9).floor() as usize;
    (0..n)
        .map(|i| (i as f64 - (n as f64 - 1.0) / 2.0) * sample_um)
        .collect()
}

/// Midpoints of a dense grid over the array and the heights there.
fn dense(d: &PhaseDesign, dx: f64) -> (Vec<f64>, Vec<f64>) {
    let span = Lenslets::new(d).unwrap().span_um();
    let n = (span / dx).round() as usize;
    let xs: Vec<f64> = (0..n)
        .map(|i| -span / 2.0 + (i as f64 + 0.5) * dx)
        .collect();
    let hs = plate::profile_um(d, &xs, 0.0).unwrap();
    (xs, hs)
}

#[test]
fn phase_export_csv_round_trips_the_profile_and_lenslets() {
    let mut d = small(None);
    d.lambda0 = Lambda0::Uniform;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("profile.csv");
    let s = write_height_csv(&d, &path, 0.5, 0.0).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text, height_csv_text(&d, 0.5, 0.0).unwrap());
    let comments: Vec<&str> = text.lines().filter(|l| l.starts_with('#')).collect();
    let head = comments.join("\n");
    for word in ["micrometres", "pitch 168", "fold T 1", "height step: none"] {
        assert!(head.contains(word), "header lacks `{word}`:\n{head}");
    }
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    assert_eq!(lines.next(), Some("x_um,height_um,lenslet,lambda0_nm"));
    let lenslets = Lenslets::new(&d).unwrap();
    let distinct: std::collections::BTreeSet<u64> =
        lenslets.lambda0_nm.iter().map(|l| l.to_bits()).collect();
    assert!(distinct.len() > 5, "the λ0 column should vary");
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let xs = sample_xs(&d, 0.5);
    assert_eq!(rows.len(), xs.len());
    assert_eq!(s.samples, Some(xs.len()));
    assert_eq!(s.kind, HeightFormat::Csv);
    let parsed: Vec<f64> = rows.iter().map(|r| r[0].parse().unwrap()).collect();
    let expected = plate::profile_um(&d, &parsed, 0.0).unwrap();
    let mut seen = vec![false; lenslets.count()];
    for ((r, &x), (&want_x, &h)) in rows.iter().zip(&parsed).zip(xs.iter().zip(&expected)) {
        assert_eq!(r.len(), 4);
        assert!((x - want_x).abs() < 1e-9, "x {x} vs {want_x}");
        let h = udc_studio::io::numbers::snap_decimals(h, 9);
        assert_eq!(r[1].parse::<f64>().unwrap(), h, "height at x = {x}");
        let (l, _) = lenslets.locate(x).unwrap();
        assert_eq!(r[2].parse::<usize>().unwrap(), l, "lenslet at x = {x}");
        assert_eq!(r[3].parse::<f64>().unwrap(), lenslets.lambda0_nm[l]);
        seen[l] = true;
    }
    assert!(seen.iter().all(|&s| s), "every lenslet is sampled");
    assert!(
        (parsed[0] + parsed[parsed.len() - 1]).abs() < 1e-9,
        "centred on the axis"
    );
    let top = expected.iter().copied().fold(0.0, f64::max);
    assert_eq!(s.max_height_um, top);
}

#[test]
fn phase_export_csv_of_a_stepped_plate_has_only_levels() {
    let d = small(Some(0.2));
    let text = height_csv_text(&d, 0.25, 0.0).unwrap();
    assert!(text.contains("height step: 0.2 um"));
    let heights: Vec<f64> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('x'))
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    let levels: std::collections::BTreeSet<i64> =
        heights.iter().map(|h| (h / 0.2).round() as i64).collect();
    // Floored within the 1.029 µm fold: 0 … 1.0 µm, never 1.2.
    assert_eq!(
        levels.into_iter().collect::<Vec<_>>(),
        vec![0, 1, 2, 3, 4, 5]
    );
    for h in heights {
        assert!(
            (h / 0.2 - (h / 0.2).round()).abs() < 1e-9,
            "{h} is not a level"
        );
    }
}

/// Decodes a 16-bit grayscale PNG: (width, height, values, tEXt chunks).
fn read_png16(path: &Path) -> (usize, usize, Vec<u16>, HashMap<String, String>) {
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    let mut reader = png::Decoder::new(file).read_info().unwrap();
    let info = reader.info();
    assert_eq!(info.bit_depth, png::BitDepth::Sixteen);
    assert_eq!(info.color_type, png::ColorType::Grayscale);
    let (w, h) = (info.width as usize, info.height as usize);
    let texts: HashMap<String, String> = info
        .uncompressed_latin1_text
        .iter()
        .map(|t| (t.keyword.clone(), t.text.clone()))
        .collect();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut buf).unwrap();
    let values = buf
        .chunks(2)
        .map(|b| u16::from_be_bytes([b[0], b[1]]))
        .collect();
    (w, h, values, texts)
}

#[test]
fn phase_export_png_levels_are_the_quantised_heights() {
    let d = small(Some(0.2));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plate.png");
    let s = write_height_png(&d, &path, 0.5, 3, 0.0).unwrap();
    let (w, h, values, texts) = read_png16(&path);
    let xs = sample_xs(&d, 0.5);
    assert_eq!((w, h), (xs.len(), 3));
    assert_eq!(texts["um_per_level"].parse::<f64>().unwrap(), 0.2);
    assert_eq!(texts["pixel_um"].parse::<f64>().unwrap(), 0.5);
    assert!(texts["description"].contains("um_per_level"));
    assert_eq!(s.um_per_level, Some(0.2));
    assert_eq!(s.pixel_um, Some(0.5));
    assert_eq!(s.levels, Some(6));
    let heights = plate::profile_um(&d, &xs, 0.0).unwrap();
    for row in values.chunks(w) {
        assert_eq!(row, &values[..w], "rows are identical");
    }
    for (&v, &hgt) in values.iter().zip(&heights) {
        assert_eq!(f64::from(v), (hgt / 0.2).round(), "level of {hgt}");
        assert!((f64::from(v) * 0.2 - hgt).abs() < 1e-9);
    }
    assert_eq!(values.iter().copied().max(), Some(5));
}

#[test]
fn phase_export_png_without_step_is_within_half_a_level() {
    let mut d = small(None);
    d.lambda0 = Lambda0::Uniform;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plate.png");
    let s = write_height_png(&d, &path, 0.25, 2, 0.0).unwrap();
    let (_, _, _, texts) = read_png16(&path);
    let upl: f64 = texts["um_per_level"].parse().unwrap();
    let tallest = Lenslets::new(&d).unwrap().max_height_um(&d);
    assert!((upl - tallest / 65535.0).abs() < 1e-15);
    assert_eq!(s.um_per_level, Some(upl));
    // A second, independent decoder for the pixels.
    let img = image::open(&path).unwrap();
    assert_eq!(img.color(), image::ColorType::L16);
    let img = img.into_luma16();
    let xs = sample_xs(&d, 0.25);
    assert_eq!(img.width() as usize, xs.len());
    let heights = plate::profile_um(&d, &xs, 0.0).unwrap();
    for y in 0..img.height() {
        for (i, &hgt) in heights.iter().enumerate() {
            let v = f64::from(img.get_pixel(i as u32, y).0[0]);
            assert!(
                (v * upl - hgt).abs() <= upl / 2.0 + 1e-12,
                "pixel {i}: {v} × {upl} vs {hgt}"
            );
        }
    }
}

#[test]
fn phase_export_png_refuses_oversized_images() {
    let d = PhaseDesign::thesis(42.0, 1.0);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.png");
    // 2436 µm at 10 nm: 243 600 columns.
    let e = write_height_png(&d, &path, 0.01, 1, 0.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("sample_um") && e.contains("65535"), "{e}");
    // 48 720 columns × 65 535 rows.
    let e = write_height_png(&d, &path, 0.05, 65_535, 0.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("rows") && e.contains("200000000"), "{e}");
    assert!(!path.exists());
}

#[derive(Debug)]
struct Rect {
    layer: i16,
    x0: i32,
    x1: i32,
    y0: i32,
    y1: i32,
}

fn read_gds_rects(path: &Path) -> (GdsLibrary, Vec<Rect>) {
    let lib = GdsLibrary::open(path).unwrap();
    let mut rects = Vec::new();
    for s in &lib.structs {
        for e in &s.elems {
            if let GdsElement::GdsBoundary(b) = e {
                assert_eq!(b.xy.len(), 5, "a closed rectangle");
                assert_eq!(b.xy[0], b.xy[4]);
                let xs: Vec<i32> = b.xy.iter().map(|p| p.x).collect();
                let ys: Vec<i32> = b.xy.iter().map(|p| p.y).collect();
                let (x0, x1) = (*xs.iter().min().unwrap(), *xs.iter().max().unwrap());
                let (y0, y1) = (*ys.iter().min().unwrap(), *ys.iter().max().unwrap());
                for p in &b.xy[..4] {
                    assert!((p.x == x0 || p.x == x1) && (p.y == y0 || p.y == y1));
                }
                assert!(x1 > x0 && y1 > y0);
                rects.push(Rect {
                    layer: b.layer,
                    x0,
                    x1,
                    y0,
                    y1,
                });
            }
        }
    }
    (lib, rects)
}

#[test]
fn phase_export_gds_has_one_layer_per_level_with_the_right_widths() {
    let d = small(Some(0.2));
    let fold = geometry::fold_height_um(&d, 530.0);
    // Floor keeps the unrounded fold; levels 0 … floor(1.029 / 0.2) = 5.
    assert!((fold - 0.53 / 0.515).abs() < 1e-12, "{fold}");
    let top = geometry::top_level(fold, 0.2) as i16;
    assert_eq!(top, 5);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plate.gds");
    let s = write_height_gds(&d, &path, 100.0, 0.0).unwrap();
    let (lib, rects) = read_gds_rects(&path);
    // 1 nm database unit, 1 µm user unit: integer coordinates are the 1 nm grid.
    // (gds21's `user_unit()` divides the wrong way round; read the record's two numbers.)
    let (db_in_user, db_m) = (lib.units.0, lib.units.1);
    assert!((db_m - 1e-9).abs() < 1e-21, "database unit {db_m} m");
    assert!(
        (db_m / db_in_user - 1e-6).abs() < 1e-18,
        "user unit {} m",
        db_m / db_in_user
    );
    let layers: std::collections::BTreeSet<i16> = rects.iter().map(|r| r.layer).collect();
    assert_eq!(
        layers.into_iter().collect::<Vec<_>>(),
        (1..=top).collect::<Vec<_>>()
    );
    assert_eq!(s.levels, Some(top as usize + 1));
    assert_eq!(s.rectangles, Some(rects.len()));
    assert_eq!(s.layers.len(), top as usize);
    let span_nm = (Lenslets::new(&d).unwrap().span_um() * 1000.0).round() as i32;
    for r in &rects {
        assert_eq!((r.y0, r.y1), (-50_000, 50_000), "100 µm along y, centred");
        assert!(r.x0 >= -span_nm / 2 && r.x1 <= span_nm / 2);
    }
    // Independent measure of {x : height = k·step} by dense sampling.
    let dx = 0.004;
    let (_, hs) = dense(&d, dx);
    let level: Vec<i16> = hs.iter().map(|h| (h / 0.2).round() as i16).collect();
    for k in 1..=top {
        let measure = level.iter().filter(|&&l| l == k).count() as f64 * dx;
        let edges = level
            .windows(2)
            .filter(|w| (w[0] == k) != (w[1] == k))
            .count() as f64;
        let mut mine: Vec<&Rect> = rects.iter().filter(|r| r.layer == k).collect();
        let width_um: f64 = mine.iter().map(|r| f64::from(r.x1 - r.x0)).sum::<f64>() * 1e-3;
        let area_um2: f64 = mine
            .iter()
            .map(|r| f64::from(r.x1 - r.x0) * f64::from(r.y1 - r.y0))
            .sum::<f64>()
            * 1e-6;
        assert!(
            (area_um2 - measure * 100.0).abs() <= (edges * (dx + 0.001) + 1e-6) * 100.0,
            "layer {k}: area {area_um2} µm² vs {} µm² ({edges} edges)",
            measure * 100.0
        );
        let summary = &s.layers[k as usize - 1];
        assert_eq!(summary.layer, k);
        assert!((summary.height_um - f64::from(k) * 0.2).abs() < 1e-12);
        assert_eq!(summary.rectangles, mine.len());
        assert!((summary.width_um - width_um).abs() < 1e-6);
        // Merged: rectangles of one layer neither overlap nor touch.
        mine.sort_by_key(|r| r.x0);
        for w in mine.windows(2) {
            assert!(
                w[1].x0 > w[0].x1,
                "layer {k}: {}..{} then {}..{}",
                w[0].x0,
                w[0].x1,
                w[1].x0,
                w[1].x1
            );
        }
    }
    // Layers never overlap one another either.
    let mut all: Vec<&Rect> = rects.iter().collect();
    all.sort_by_key(|r| r.x0);
    for w in all.windows(2) {
        assert!(w[1].x0 >= w[0].x1);
    }
}

#[test]
fn phase_export_gds_without_a_step_says_to_set_one() {
    let d = small(None);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plate.gds");
    let e = write_height_gds(&d, &path, 100.0, 0.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("height_step_um") && e.contains("0.2"), "{e}");
    assert!(!path.exists());
}

/// Signed volume by the divergence theorem, in µm³ (positive for outward normals).
fn volume(mesh: &stl_io::IndexedMesh) -> f64 {
    let v = |i: usize| mesh.vertices[i].0.map(f64::from);
    mesh.faces
        .iter()
        .map(|f| {
            let (a, b, c) = (v(f.vertices[0]), v(f.vertices[1]), v(f.vertices[2]));
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        })
        .sum()
}

/// Reads an STL and checks it is closed and consistently oriented: every directed edge once,
/// and its reverse once. Also that every stored normal agrees with the winding.
fn read_watertight(path: &Path) -> stl_io::IndexedMesh {
    let bytes = std::fs::read(path).unwrap();
    assert!(
        String::from_utf8_lossy(&bytes[..80]).contains("micrometres"),
        "units in the header"
    );
    let mesh = stl_io::read_stl(&mut std::io::Cursor::new(bytes)).unwrap();
    let mut directed: HashMap<(usize, usize), usize> = HashMap::new();
    for f in &mesh.faces {
        let v = f.vertices;
        assert!(
            v[0] != v[1] && v[1] != v[2] && v[2] != v[0],
            "degenerate face"
        );
        for k in 0..3 {
            *directed.entry((v[k], v[(k + 1) % 3])).or_default() += 1;
        }
        let p = |i: usize| mesh.vertices[v[i]].0.map(f64::from);
        let (a, b, c) = (p(0), p(1), p(2));
        let (d1, d2) = (
            [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
            [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
        );
        let n = [
            d1[1] * d2[2] - d1[2] * d2[1],
            d1[2] * d2[0] - d1[0] * d2[2],
            d1[0] * d2[1] - d1[1] * d2[0],
        ];
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let stored = f.normal.0.map(f64::from);
        let dot = (n[0] * stored[0] + n[1] * stored[1] + n[2] * stored[2]) / len;
        assert!(dot > 0.99, "normal {stored:?} against winding {n:?}");
    }
    for (&(a, b), &count) in &directed {
        assert_eq!(count, 1, "edge {a}->{b} used {count} times");
        assert_eq!(directed.get(&(b, a)), Some(&1), "edge {a}->{b} has no twin");
    }
    mesh.validate().unwrap();
    mesh
}

fn bbox(mesh: &stl_io::IndexedMesh) -> [[f64; 2]; 3] {
    let mut b = [[f64::INFINITY, f64::NEG_INFINITY]; 3];
    for v in &mesh.vertices {
        for (range, &c) in b.iter_mut().zip(&v.0) {
            range[0] = range[0].min(f64::from(c));
            range[1] = range[1].max(f64::from(c));
        }
    }
    b
}

/// Writes the STL, checks it is closed, its volume and bounding box; returns the mesh.
fn check_stl(d: &PhaseDesign, sample_um: f64) -> (stl_io::IndexedMesh, f64) {
    let (length, base) = (50.0, 2.0);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plate.stl");
    let s = write_height_stl(d, &path, sample_um, length, base, 0.0).unwrap();
    let mesh = read_watertight(&path);
    assert_eq!(s.triangles, Some(mesh.faces.len()));
    let span = Lenslets::new(d).unwrap().span_um();
    let dx = 0.005;
    let (_, hs) = dense(d, dx);
    let integral: f64 = hs.iter().map(|h| (base + h) * dx).sum();
    let want = length * integral;
    let got = volume(&mesh);
    assert!(
        ((got - want) / want).abs() < 0.01,
        "volume {got} µm³ vs {want} µm³"
    );
    let top = hs.iter().copied().fold(0.0, f64::max);
    let b = bbox(&mesh);
    let close = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol;
    assert!(
        close(b[0][0], -span / 2.0, 1e-3) && close(b[0][1], span / 2.0, 1e-3),
        "{b:?}"
    );
    assert!(close(b[1][0], -length / 2.0, 1e-4) && close(b[1][1], length / 2.0, 1e-4));
    assert_eq!(b[2][0], 0.0);
    // The dense samples miss the true top by at most the steepest slope × half a sample.
    let slope = d.pitch_um / 2.0 / ((d.refractive_index - 1.0) * d.f_mla_um);
    let tol = 1e-3 + slope * dx / 2.0;
    assert!(
        close(b[2][1], base + top, tol),
        "top {} vs {}",
        b[2][1],
        base + top
    );
    assert!(close(s.max_height_um, top, tol));
    (mesh, got / want - 1.0)
}

#[test]
fn phase_export_stl_of_a_folded_plate_is_closed_with_the_right_volume() {
    let (mesh, err) = check_stl(&small(None), 0.5);
    assert!(err.abs() < 1e-3, "volume error {err}");
    assert!(mesh.faces.len() > 1000);
}

#[test]
fn phase_export_stl_of_an_unfolded_lens_is_closed() {
    let mut d = small(None);
    d.surface = Surface::Unfolded;
    check_stl(&d, 1.0);
}

#[test]
fn phase_export_stl_of_a_stepped_plate_has_flat_tops_and_vertical_walls() {
    let d = small(Some(0.2));
    let (mesh, err) = check_stl(&d, 0.5);
    assert!(
        err.abs() < 1e-4,
        "a stepped plate is exact: volume error {err}"
    );
    let mut up = 0;
    for f in &mesh.faces {
        let n = f.normal.0;
        let axes = n.iter().filter(|c| c.abs() > 1e-6).count();
        assert_eq!(axes, 1, "normal {n:?} is not axis-aligned");
        if n[2] > 0.5 {
            up += 1;
        }
    }
    // One strip (two triangles) per flat run of the profile.
    let (_, hs) = dense(&d, 0.004);
    let runs = 1 + hs
        .windows(2)
        .filter(|w| (w[0] / 0.2).round() != (w[1] / 0.2).round())
        .count();
    assert_eq!(up, 2 * runs);
}

#[test]
fn phase_export_stl_with_mixed_lambda0_has_walls_at_lenslet_edges() {
    let mut d = small(Some(0.1));
    d.lambda0 = Lambda0::Uniform;
    check_stl(&d, 0.5);
    d.height_step_um = None;
    check_stl(&d, 0.5);
}

#[test]
fn phase_export_rejects_bad_parameters_without_writing() {
    let d = small(Some(0.2));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out");
    let bad_sample = [f64::NAN, -1.0, 0.0, f64::INFINITY, 1e9];
    let bad_length = [f64::NAN, -5.0, 0.0, 1e12];
    let bad_base = [f64::NAN, -1.0, 0.0, 1e9];
    let expect = |e: udc_studio::io::IoError, name: &str| {
        let msg = e.to_string();
        assert!(msg.contains(name), "`{msg}` does not name {name}");
        assert!(!path.exists(), "{name}: a file was written");
    };
    for s in bad_sample {
        expect(
            write_height_csv(&d, &path, s, 0.0).unwrap_err(),
            "sample_um",
        );
        expect(height_csv_text(&d, s, 0.0).unwrap_err(), "sample_um");
        expect(
            write_height_png(&d, &path, s, 4, 0.0).unwrap_err(),
            "sample_um",
        );
        expect(
            write_height_stl(&d, &path, s, 10.0, 1.0, 0.0).unwrap_err(),
            "sample_um",
        );
    }
    for rows in [0, 1_000_000] {
        expect(
            write_height_png(&d, &path, 0.5, rows, 0.0).unwrap_err(),
            "rows",
        );
    }
    for l in bad_length {
        expect(
            write_height_gds(&d, &path, l, 0.0).unwrap_err(),
            "length_um",
        );
        expect(
            write_height_stl(&d, &path, 0.5, l, 1.0, 0.0).unwrap_err(),
            "length_um",
        );
    }
    for b in bad_base {
        expect(
            write_height_stl(&d, &path, 0.5, 10.0, b, 0.0).unwrap_err(),
            "base_um",
        );
    }
    // A design that does not validate names its field.
    let mut broken = d.clone();
    broken.pitch_um = f64::NAN;
    expect(
        write_height_gds(&broken, &path, 10.0, 0.0).unwrap_err(),
        "pitch_um",
    );
    // A step so fine under a wide lens that the plate would have billions of levels.
    let mut fine = PhaseDesign::thesis(2000.0, 100.0);
    fine.f_mla_um = 1.0;
    fine.refractive_index = 1.01;
    fine.height_step_um = Some(0.001);
    expect(
        write_height_gds(&fine, &path, 10.0, 0.0).unwrap_err(),
        "height_step_um",
    );
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

/// The thesis's 600-DPI plate (42 µm pitch, 58 lenslets, T = 1, 530 nm) with a 0.2 µm step: the
/// file sizes stay small and the numbers are the ones docs/src/phase/export.md quotes.
#[test]
fn phase_export_thesis_600dpi_plate_stays_small() {
    let mut d = PhaseDesign::thesis(42.0, 1.0);
    d.height_step_um = Some(0.2);
    let dir = tempfile::tempdir().unwrap();
    let gds = write_height_gds(&d, &dir.path().join("p.gds"), 1000.0, 0.0).unwrap();
    let stl = write_height_stl(&d, &dir.path().join("p.stl"), 0.5, 1000.0, 5.0, 0.0).unwrap();
    let png = write_height_png(&d, &dir.path().join("p.png"), 0.5, 16, 0.0).unwrap();
    let smooth = PhaseDesign::thesis(42.0, 1.0);
    let curved =
        write_height_stl(&smooth, &dir.path().join("c.stl"), 0.5, 1000.0, 5.0, 0.0).unwrap();
    println!(
        "{}",
        serde_json::to_string_pretty(&[&gds, &stl, &png, &curved]).unwrap()
    );
    assert!(curved.triangles.unwrap() < 200_000);
    read_watertight(&dir.path().join("c.stl"));
    // Floored within the 1.029 µm fold: 0, 0.2, … 1.0 µm.
    assert_eq!(gds.levels, Some(6));
    assert_eq!(gds.layers.len(), 5);
    assert!((gds.max_height_um - 1.0).abs() < 1e-12);
    assert!((gds.width_um - 58.0 * 42.0).abs() < 1e-9);
    assert!(gds.rectangles.unwrap() < 10_000);
    assert!(stl.triangles.unwrap() < 100_000);
    read_watertight(&dir.path().join("p.stl"));
}

// ---- Quantisation (issue 12): floor within the unrounded fold, level rings at the analytic
// crossings of the sag, in every format.

/// The issue's plate: T = 1, λ0 fixed at 600 nm (fold d0 = 0.6 / 0.515 = 1.165 µm), a 0.2 µm step.
fn issue_design(pitch_um: f64, rounding: HeightRounding) -> PhaseDesign {
    let mut d = PhaseDesign::thesis(pitch_um, 1.0);
    d.lambda0 = Lambda0::Fixed { nm: 600.0 };
    d.height_step_um = Some(0.2);
    d.height_rounding = rounding;
    d
}

const STEP: f64 = 0.2;
const D0: f64 = 0.6 / 0.515;

/// The plate written out from the formulas alone (not from `geometry`): runs `(x0, x1, level)`
/// left to right, equal neighbours merged. In each lenslet (centre c, `|u| = |x − c|`) the level
/// changes where the sag `u² / (2(n−1)f)` reaches
/// - floor: `w·d0 + j·s` (level j of wrap w, j = 0 … floor(d0/s)), i.e.
///   `|u| = sqrt(2(n−1)f (w·d0 + j·s))`;
/// - nearest: `(K − ½)·s` (level K mod m, the fold rounded to m = round(d0/s) steps).
fn analytic_runs(d: &PhaseDesign) -> Vec<(f64, f64, i64)> {
    let two_nf = 2.0 * (d.refractive_index - 1.0) * d.f_mla_um;
    let radius = |sag: f64| (two_nf * sag).sqrt();
    let p = d.pitch_um;
    let edge_sag = (p / 2.0).powi(2) / two_nf;
    // (sag where a level starts, level), from the centre out.
    let mut starts: Vec<(f64, i64)> = Vec::new();
    match d.height_rounding {
        HeightRounding::Floor => {
            let top = (D0 / STEP).floor() as i64;
            'out: for w in 0.. {
                for j in 0..=top {
                    let sag = w as f64 * D0 + j as f64 * STEP;
                    if sag >= edge_sag {
                        break 'out;
                    }
                    starts.push((sag, j));
                }
            }
        }
        HeightRounding::Nearest => {
            let m = (D0 / STEP).round() as i64;
            for k in 0.. {
                let sag = if k == 0 { 0.0 } else { (k as f64 - 0.5) * STEP };
                if sag >= edge_sag {
                    break;
                }
                starts.push((sag, k % m));
            }
        }
    }
    let lenslets = geometry::lenslet_count(d);
    let mut runs: Vec<(f64, f64, i64)> = Vec::new();
    // A ring of no width (a crossing exactly on a lenslet edge: at 168 µm the edge sag is exactly
    // 35 folds) is no ring; its neighbours of equal level join.
    let mut push = |x0: f64, x1: f64, level: i64| {
        if x1 - x0 < 1e-9 {
            return;
        }
        match runs.last_mut() {
            Some(last) if last.2 == level => last.1 = x1,
            _ => runs.push((x0, x1, level)),
        }
    };
    for l in 0..lenslets {
        let c = (l as f64 - (lenslets as f64 - 1.0) / 2.0) * p;
        let (left, right) = (c - p / 2.0, c + p / 2.0);
        let n = starts.len();
        let outer = |k: usize| {
            if k + 1 < n {
                radius(starts[k + 1].0)
            } else {
                p / 2.0
            }
        };
        for (k, &(sag, level)) in starts.iter().enumerate().skip(1).rev() {
            let x0 = if k + 1 == n { left } else { c - outer(k) };
            push(x0, c - radius(sag), level);
        }
        push(c - outer(0), c + outer(0), starts[0].1);
        for (k, &(sag, level)) in starts.iter().enumerate().skip(1) {
            let x1 = if k + 1 == n { right } else { c + outer(k) };
            push(c + radius(sag), x1, level);
        }
    }
    // The fabricated plate: a part-ring at either outer edge narrower than the run inside it
    // is that run, continued to the edge.
    let width = |r: &(f64, f64, i64)| r.1 - r.0;
    if runs.len() > 2 && width(&runs[0]) < width(&runs[1]) {
        let x0 = runs.remove(0).0;
        runs[0].0 = x0;
    }
    let n = runs.len();
    if n > 2 && width(&runs[n - 1]) < width(&runs[n - 2]) {
        let x1 = runs.pop().map_or(0.0, |r| r.1);
        runs[n - 2].1 = x1;
    }
    runs
}

/// The level of the fabricated plate at `x`: [`floor_level_at`], but in the runs at the two
/// outer edges, which may carry an edge part-ring continued from inside (`analytic_runs`).
fn plate_level_at(d: &PhaseDesign, runs: &[(f64, f64, i64)], x: f64) -> i64 {
    match (runs.first(), runs.last()) {
        (Some(first), _) if x < first.1 => first.2,
        (_, Some(last)) if x >= last.0 => last.2,
        _ => floor_level_at(d, x),
    }
}

/// The level the floor rule gives at `x`, straight from `floor(mod(sag, d0) / s)`.
fn floor_level_at(d: &PhaseDesign, x: f64) -> i64 {
    let lenslets = geometry::lenslet_count(d) as f64;
    let l = ((x / d.pitch_um) + lenslets / 2.0).floor();
    let u = x - (l - (lenslets - 1.0) / 2.0) * d.pitch_um;
    let sag = u * u / (2.0 * (d.refractive_index - 1.0) * d.f_mla_um);
    (sag.rem_euclid(D0) / STEP).floor() as i64
}

/// Runs of equal levels in a sampled export (samples at `xs`, `sample` apart): each run spans
/// from half a sample before its first sample to half a sample after its last.
fn sampled_runs(xs: &[f64], levels: &[i64], sample: f64) -> Vec<(f64, f64, i64)> {
    let mut runs: Vec<(f64, f64, i64)> = Vec::new();
    for (&x, &level) in xs.iter().zip(levels) {
        match runs.last_mut() {
            Some(last) if last.2 == level => last.1 = x + sample / 2.0,
            _ => runs.push((x - sample / 2.0, x + sample / 2.0, level)),
        }
    }
    runs
}

/// The same levels in the same order, every edge within `tol` µm of the analytic one (so every
/// ring's width within `2 tol`). Edges at the array's ends are within `end_tol`.
fn assert_runs_match(
    what: &str,
    got: &[(f64, f64, i64)],
    want: &[(f64, f64, i64)],
    tol: f64,
    end_tol: f64,
) {
    assert_eq!(
        got.len(),
        want.len(),
        "{what}: {} runs, the analytic plate has {}",
        got.len(),
        want.len()
    );
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert_eq!(g.2, w.2, "{what}: run {k} at x = {} has level {}", w.0, g.2);
        let t0 = if k == 0 { end_tol } else { tol };
        let t1 = if k + 1 == want.len() { end_tol } else { tol };
        assert!(
            (g.0 - w.0).abs() <= t0 && (g.1 - w.1).abs() <= t1,
            "{what}: level {} run {k} spans {}..{}, the crossings say {}..{} (tolerance {tol})",
            g.2,
            g.0,
            g.1,
            w.0,
            w.1
        );
        let (gw, ww) = (g.1 - g.0, w.1 - w.0);
        assert!(
            (gw - ww).abs() <= t0 + t1,
            "{what}: level {} run {k} is {gw} µm wide, the crossings say {ww}",
            g.2
        );
    }
}

fn levels_of(runs: &[(f64, f64, i64)]) -> std::collections::BTreeSet<i64> {
    runs.iter().map(|r| r.2).collect()
}

/// Issue 12: at 600 nm the fold is 1.165 µm; flooring to 0.2 µm gives exactly the levels
/// 0, 0.2, … 1.0 µm (floor(d0/s) + 1 = 6), none above the fold, and every format's rings sit at
/// the analytic crossings `|u| = sqrt(2(n−1)f (w·d0 + j·s))` within its resolution: the sample
/// for CSV and PNG, 1 nm for GDSII, the STL grid (1 nm) plus single precision.
#[test]
fn phase_export_floor_levels_stay_within_the_fold_at_the_analytic_crossings() {
    for pitch in [42.0, 168.0] {
        let d = issue_design(pitch, HeightRounding::Floor);
        assert_eq!(d.height_rounding, HeightRounding::default());
        let fold = geometry::fold_height_um(&d, 600.0);
        assert!(
            (fold - D0).abs() < 1e-12,
            "the wrap is the unrounded d0: {fold}"
        );
        let top = (D0 / STEP).floor() as i64;
        assert_eq!(top, 5);
        assert_eq!(geometry::top_level(fold, STEP), 5);
        let want = analytic_runs(&d);
        assert_eq!(levels_of(&want), (0..=top).collect());
        // The analytic rings are what the floor formula says inside them (a quarter in from each
        // end: a ring merged across a lenslet edge has the edge at its middle).
        for (k, r) in want.iter().enumerate() {
            // An edge run's outer quarter may be the part-ring it continues over.
            let ts: &[f64] = match k {
                0 => &[0.75],
                k if k + 1 == want.len() => &[0.25],
                _ => &[0.25, 0.75],
            };
            for t in ts {
                assert_eq!(floor_level_at(&d, r.0 + t * (r.1 - r.0)), r.2, "{r:?}");
            }
        }
        // Whole rings (not cut by a lenslet edge) are at least the top ring's 0.165 µm of sag over
        // the steepest slope, 0.97 at a lenslet edge: the slope's natural width, no slivers.
        let w = geometry::lenslet_count(&d) as f64 * pitch;
        let edges_in = |r: &&(f64, f64, i64)| {
            let (a, b) = ((r.0 + w / 2.0) / pitch, (r.1 + w / 2.0) / pitch);
            (a - 1e-9).ceil() <= (b + 1e-9).floor()
        };
        let whole = want.iter().filter(|r| !edges_in(r));
        let narrowest = whole.map(|r| r.1 - r.0).fold(f64::INFINITY, f64::min);
        let slope = (pitch / 2.0) / ((d.refractive_index - 1.0) * d.f_mla_um);
        let natural = (D0 - top as f64 * STEP) / slope;
        assert!(
            narrowest >= natural * (1.0 - 1e-9) && natural > 0.16,
            "pitch {pitch}: a whole ring is {narrowest} µm wide, under {natural}"
        );
        let dir = tempfile::tempdir().unwrap();

        // CSV and PNG at 40 or 50 nm (within the PNG's 65535 columns): every sample's level, and
        // the rings within half a sample; every ring, also those cut by the array's ends, holds a
        // sample.
        let sample = if pitch == 42.0 { 0.04 } else { 0.05 };
        let all_narrowest = want.iter().map(|r| r.1 - r.0).fold(f64::INFINITY, f64::min);
        assert!(all_narrowest > 1.5 * sample, "{all_narrowest}");
        let xs = sample_xs(&d, sample);
        let text = height_csv_text(&d, sample, 0.0).unwrap();
        assert!(
            text.contains("floor rounding"),
            "the header states the rule"
        );
        let heights: Vec<f64> = text
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with('x'))
            .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
            .collect();
        assert_eq!(heights.len(), xs.len());
        let csv_levels: Vec<i64> = heights.iter().map(|h| (h / STEP).round() as i64).collect();
        for ((&h, &k), &x) in heights.iter().zip(&csv_levels).zip(&xs) {
            // The CSV writes the level's height as its shortest decimal (0.6, not 0.6000000000000001).
            let level = udc_studio::io::numbers::snap_decimals(k as f64 * STEP, 9);
            assert_eq!(h, level, "x = {x}: {h} is not exactly a level");
            assert!(h < D0, "x = {x}: {h} µm is above the fold height {D0}");
            assert_eq!(k, plate_level_at(&d, &want, x), "x = {x}: level {k}");
        }
        let csv_runs = sampled_runs(&xs, &csv_levels, sample);
        assert_eq!(levels_of(&csv_runs), (0..=top).collect());
        assert_runs_match(
            &format!("CSV, pitch {pitch}"),
            &csv_runs,
            &want,
            sample / 2.0 + 1e-9,
            sample,
        );

        let png_path = dir.path().join("plate.png");
        let png = write_height_png(&d, &png_path, sample, 2, 0.0).unwrap();
        assert_eq!(png.levels, Some(top as usize + 1));
        assert!((png.max_height_um - 1.0).abs() < 1e-12);
        let (w, _, values, texts) = read_png16(&png_path);
        assert_eq!(texts["um_per_level"].parse::<f64>().unwrap(), STEP);
        let png_levels: Vec<i64> = values[..w].iter().map(|&v| i64::from(v)).collect();
        assert_eq!(png_levels, csv_levels, "PNG pixels are the CSV's levels");
        assert_runs_match(
            &format!("PNG, pitch {pitch}"),
            &sampled_runs(&xs, &png_levels, sample),
            &want,
            sample / 2.0 + 1e-9,
            sample,
        );

        // GDSII: one layer per level 1 … 5, rectangles at the crossings to the 1 nm unit.
        let gds_path = dir.path().join("plate.gds");
        let gds = write_height_gds(&d, &gds_path, 10.0, 0.0).unwrap();
        assert_eq!(gds.levels, Some(top as usize + 1));
        assert_eq!(gds.layers.len(), top as usize);
        assert!((gds.max_height_um - 1.0).abs() < 1e-12);
        for (k, layer) in gds.layers.iter().enumerate() {
            assert_eq!(layer.layer, k as i16 + 1);
            assert!((layer.height_um - (k + 1) as f64 * STEP).abs() < 1e-12);
            assert!(layer.height_um < D0);
        }
        let (_, mut rects) = read_gds_rects(&gds_path);
        rects.sort_by_key(|r| r.x0);
        let gds_runs: Vec<(f64, f64, i64)> = rects
            .iter()
            .map(|r| {
                (
                    f64::from(r.x0) * 1e-3,
                    f64::from(r.x1) * 1e-3,
                    i64::from(r.layer),
                )
            })
            .collect();
        let drawn: Vec<(f64, f64, i64)> = want.iter().copied().filter(|r| r.2 > 0).collect();
        assert_eq!(levels_of(&gds_runs), (1..=top).collect());
        assert_runs_match(
            &format!("GDSII, pitch {pitch}"),
            &gds_runs,
            &drawn,
            0.5e-3 + 1e-9,
            0.5e-3 + 1e-9,
        );
        for (layer, k) in gds.layers.iter().zip(1..) {
            let width: f64 = drawn.iter().filter(|r| r.2 == k).map(|r| r.1 - r.0).sum();
            let rings = drawn.iter().filter(|r| r.2 == k).count() as f64;
            assert!(
                (layer.width_um - width).abs() <= rings * 1e-3,
                "layer {k}: {} µm vs {width} µm",
                layer.width_um
            );
        }

        // STL: the up-facing strips are the flat levels, at base + level·s.
        let (base, length) = (2.0, 10.0);
        let stl_path = dir.path().join("plate.stl");
        let stl = write_height_stl(&d, &stl_path, 0.5, length, base, 0.0).unwrap();
        assert!((stl.max_height_um - 1.0).abs() < 1e-5);
        let grid = stl.grid_um.unwrap();
        let mesh = read_watertight(&stl_path);
        let mut strips: Vec<(f64, f64, i64)> = Vec::new();
        for f in &mesh.faces {
            if f.normal.0[2] < 0.5 {
                continue;
            }
            let v: Vec<[f64; 3]> = f
                .vertices
                .iter()
                .map(|&i| mesh.vertices[i].0.map(f64::from))
                .collect();
            let x0 = v.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min);
            let x1 = v.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max);
            let h = v[0][2] - base;
            let level = (h / STEP).round() as i64;
            assert!((h - level as f64 * STEP).abs() < 1e-5, "a top at {h} µm");
            assert!(h < D0, "a top at {h} µm is above the fold {D0}");
            strips.push((x0, x1, level));
        }
        strips.sort_by(|a, b| a.0.total_cmp(&b.0));
        strips.dedup_by(|a, b| a.0 == b.0 && a.1 == b.1);
        // Single precision near x = W/2 (≤ 1.5 mm) adds up to ~1e-4 µm to the grid's half step.
        let tol = grid / 2.0 + 2e-4;
        assert_runs_match(&format!("STL, pitch {pitch}"), &strips, &want, tol, tol);
    }
}

/// `height_rounding: nearest` keeps the old rule: round(sag / s)·s with the fold rounded to the
/// step (1.165 → 1.2 µm, six steps), so the rings start at (K − ½)·s and the plate wraps every
/// 1.2 µm of sag instead of every 1.165 µm. The files differ from the floored plate's.
#[test]
fn phase_export_nearest_rounding_is_still_available_and_differs() {
    for pitch in [42.0, 168.0] {
        let d = issue_design(pitch, HeightRounding::Nearest);
        let fold = geometry::fold_height_um(&d, 600.0);
        assert!(
            (fold - 1.2).abs() < 1e-12,
            "nearest rounds the fold: {fold}"
        );
        assert!(fold > D0);
        let want = analytic_runs(&d);
        let floor = analytic_runs(&issue_design(pitch, HeightRounding::Floor));
        assert_ne!(want.len(), floor.len());
        let sample = 0.05;
        let xs = sample_xs(&d, sample);
        let text = height_csv_text(&d, sample, 0.0).unwrap();
        assert!(text.contains("nearest rounding"));
        assert!(
            text.contains("max fold height 1.2"),
            "the rounded fold is stated"
        );
        let levels: Vec<i64> = text
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with('x'))
            .map(|l| {
                let h: f64 = l.split(',').nth(1).unwrap().parse().unwrap();
                let k = (h / STEP).round() as i64;
                let level = udc_studio::io::numbers::snap_decimals(k as f64 * STEP, 9);
                assert_eq!(h, level, "{h} is not exactly a level");
                k
            })
            .collect();
        assert_runs_match(
            &format!("nearest CSV, pitch {pitch}"),
            &sampled_runs(&xs, &levels, sample),
            &want,
            sample / 2.0 + 1e-9,
            sample,
        );
        let differ = xs
            .iter()
            .zip(&levels)
            .filter(|(x, k)| floor_level_at(&d, **x) != **k)
            .count();
        assert!(
            differ > xs.len() / 4,
            "pitch {pitch}: only {differ} of {} samples differ from the floored plate",
            xs.len()
        );
        let dir = tempfile::tempdir().unwrap();
        let gds_path = dir.path().join("nearest.gds");
        write_height_gds(&d, &gds_path, 10.0, 0.0).unwrap();
        let (_, mut rects) = read_gds_rects(&gds_path);
        rects.sort_by_key(|r| r.x0);
        let gds_runs: Vec<(f64, f64, i64)> = rects
            .iter()
            .map(|r| {
                (
                    f64::from(r.x0) * 1e-3,
                    f64::from(r.x1) * 1e-3,
                    i64::from(r.layer),
                )
            })
            .collect();
        let drawn: Vec<(f64, f64, i64)> = want.iter().copied().filter(|r| r.2 > 0).collect();
        assert_runs_match(
            &format!("nearest GDSII, pitch {pitch}"),
            &gds_runs,
            &drawn,
            0.5e-3 + 1e-9,
            0.5e-3 + 1e-9,
        );
    }
}

/// A fold that is a whole number of steps has no sliver level at the fold itself, and a fold
/// under one step floors the whole plate to 0.
#[test]
fn phase_export_floor_edge_cases_of_the_top_level() {
    assert_eq!(geometry::top_level(1.0, 0.2), 4);
    assert_eq!(geometry::top_level(1.0 + 1e-13, 0.2), 4);
    assert_eq!(geometry::top_level(1.01, 0.2), 5);
    assert_eq!(geometry::top_level(0.15, 0.2), 0);
    let mut d = small(Some(2.0));
    d.lambda0 = Lambda0::Fixed { nm: 530.0 };
    let text = height_csv_text(&d, 0.5, 0.0).unwrap();
    assert!(
        text.lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with('x'))
            .all(|l| l.split(',').nth(1) == Some("0")),
        "a 2 µm step floors a 1.03 µm fold to 0"
    );
    let dir = tempfile::tempdir().unwrap();
    let s = write_height_gds(&d, &dir.path().join("flat.gds"), 10.0, 0.0).unwrap();
    assert_eq!((s.levels, s.rectangles), (Some(1), Some(0)));
    // Unfolded, floored: floor(sag / s)·s, never above the sag (the model's profile; the
    // fabricated plate's outer edges are tested in `the_plate_edge_is_never_narrower_...`).
    let mut u = small(Some(0.2));
    u.surface = Surface::Unfolded;
    let (xs, _) = dense(&u, 0.01);
    let hs = geometry::profile_um(&u, &xs).unwrap();
    let lenslets = Lenslets::new(&u).unwrap();
    for (&x, &h) in xs.iter().zip(&hs) {
        let (_, du) = lenslets.locate(x).unwrap();
        let sag = geometry::sag_um(&u, du);
        assert_eq!(h, (sag / 0.2).floor() * 0.2, "x = {x}");
    }
}

/// Pitches of 600, 300 and 150 DPI, folds T = 1, 2 and 5, three folding-wavelength plans and
/// three ways of stepping the height.
fn edge_setups() -> Vec<PhaseDesign> {
    let mut out = Vec::new();
    for pitch in [42.0, 84.0, 168.0] {
        for fold in [1.0, 2.0, 5.0] {
            for lambda0 in [
                Lambda0::Fixed { nm: 530.0 },
                Lambda0::Fixed { nm: 600.0 },
                Lambda0::Uniform,
            ] {
                for (step, rounding) in [
                    (None, HeightRounding::Floor),
                    (Some(0.2), HeightRounding::Floor),
                    (Some(0.2), HeightRounding::Nearest),
                ] {
                    let mut d = PhaseDesign::thesis(pitch, fold);
                    d.lambda0 = lambda0.clone();
                    d.height_step_um = step;
                    d.height_rounding = rounding;
                    out.push(d);
                }
            }
        }
    }
    out
}

/// The plate's outer edges never make a feature narrower than the plate makes inside: with the
/// rule set to the narrowest feature away from the two edges, the plate passes its own design-
/// rule check, for every pitch × fold × λ0 plan × step. The model's profile would not: for a
/// 600-DPI plate at 0.2-µm steps and λ0 = 600 nm its edge part-rings are 76 nm wide against
/// 152 nm inside.
#[test]
fn the_plate_edge_is_never_narrower_than_the_plate_inside() {
    use udc_studio::core::mask::drc::Rules;
    use udc_studio::core::phase::drc::check_plate;
    let mut merged = 0;
    for d in edge_setups() {
        let lenslets = Lenslets::new(&d).unwrap();
        let pieces = plate::pieces(&d, &lenslets, 0.0).unwrap();
        let width = |p: &plate::Piece| p.x1_um - p.x0_um;
        let inside = pieces[1..pieces.len() - 1]
            .iter()
            .map(width)
            .fold(f64::INFINITY, f64::min);
        let rules = Rules {
            phase_min_feature_um: inside,
            ..Rules::default()
        };
        let report = check_plate(&d, &rules).unwrap();
        let what = format!(
            "pitch {} µm, T = {}, {:?}, step {:?} {:?}",
            d.pitch_um, d.fold, d.lambda0, d.height_step_um, d.height_rounding
        );
        assert!(report.is_clean(), "{what}: {:?}", report.violations.first());
        // Where the model's part-ring was a sliver, the plate differs from the model over it
        // and only there: within the outermost piece at each edge.
        let span = lenslets.span_um();
        let xs: Vec<f64> = (0..40_000)
            .map(|i| -span / 2.0 + (i as f64 + 0.5) * span / 40_000.0)
            .collect();
        let model = geometry::profile_um(&d, &xs).unwrap();
        let fabricated = plate::profile_um(&d, &xs, 0.0).unwrap();
        let (first, last) = (&pieces[0], &pieces[pieces.len() - 1]);
        let mut differs = false;
        for ((&x, m), f) in xs.iter().zip(&model).zip(&fabricated) {
            if (m - f).abs() > 1e-9 {
                differs = true;
                assert!(
                    x < first.x1_um || x >= last.x0_um,
                    "{what}: the plate leaves the model at x = {x} µm, inside the array"
                );
            }
        }
        merged += usize::from(differs);
    }
    assert!(
        merged > 0,
        "no setup had an edge sliver: the test would not see one"
    );
}

/// The issue's example: `phase export --format gds --fold 1 --height-step-um 0.2 --lambda0
/// fixed:600` drew 76-nm slivers at the plate's two outer edges; the GDSII now has none.
#[test]
fn the_600_dpi_plate_at_600_nm_has_no_edge_sliver_in_its_gds() {
    let mut d = PhaseDesign::thesis(42.0, 1.0);
    d.lambda0 = Lambda0::Fixed { nm: 600.0 };
    d.height_step_um = Some(0.2);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plate.gds");
    write_height_gds(&d, &path, 1000.0, 0.0).unwrap();
    let (_, rects) = read_gds_rects(&path);
    let half_span_nm = Lenslets::new(&d).unwrap().span_um() * 500.0;
    let at_edge: Vec<&Rect> = rects
        .iter()
        .filter(|r| {
            (r.x0 as f64 + half_span_nm).abs() < 1.0 || (r.x1 as f64 - half_span_nm).abs() < 1.0
        })
        .collect();
    assert!(
        !at_edge.is_empty(),
        "the outermost rectangles reach the edges"
    );
    for r in at_edge {
        assert!(
            r.x1 - r.x0 > 152,
            "{r:?} at the edge is narrower than the rings inside"
        );
    }
}
