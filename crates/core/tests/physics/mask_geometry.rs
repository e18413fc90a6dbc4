//! Mask geometry (pure core): merged polygons reproduce the cells exactly, holes are keyholed,
//! the GDSII vertex limit holds, regions and tone areas add up.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use proptest::prelude::*;
use udc_core::design::{Design, Opening, TilingMode};
use udc_core::mask::{
    BinaryGrid, BorderPolicy, MAX_VERTICES, MaskError, MaskLayout, MaskRegion, MaskSpec, Ring,
    Tone, trace_polygons,
};

/// Scanline rasterisation of rings at cell centres, counting how many rings cover each cell.
fn coverage(rings: &[Ring], w: usize, h: usize) -> Vec<Vec<u32>> {
    let mut cov = vec![vec![0u32; w]; h];
    for ring in rings {
        let n = ring.points.len();
        for (r, row) in cov.iter_mut().enumerate() {
            // Half-cell lattice: row r's centre is at y = −2r − 1.
            let y = -2.0 * r as f64 - 1.0;
            let mut xs: Vec<f64> = (0..n)
                .filter_map(|i| {
                    let [x0, y0] = ring.points[i].map(|v| v as f64);
                    let [x1, y1] = ring.points[(i + 1) % n].map(|v| v as f64);
                    ((y0 <= y) != (y1 <= y)).then(|| x0 + (y - y0) * (x1 - x0) / (y1 - y0))
                })
                .collect();
            xs.sort_by(f64::total_cmp);
            for pair in xs.chunks_exact(2) {
                for (c, v) in row.iter_mut().enumerate() {
                    let x = 2.0 * c as f64 + 1.0;
                    if x > pair[0] && x < pair[1] {
                        *v += 1;
                    }
                }
            }
        }
    }
    cov
}

/// The rings cover exactly the open cells, once each, and are counter-clockwise.
fn assert_exact(grid: &BinaryGrid, rings: &[Ring], max_vertices: usize) {
    let cov = coverage(rings, grid.width(), grid.height());
    for (r, row) in cov.iter().enumerate() {
        for (c, &k) in row.iter().enumerate() {
            let want = u32::from(grid.get(c, r));
            assert_eq!(k, want, "cell ({c}, {r}) covered {k} times, open = {want}");
        }
    }
    let area: f64 = rings.iter().map(Ring::area_cells).sum();
    assert_eq!(area, grid.count_open() as f64);
    for ring in rings {
        assert!(
            ring.area_cells() > 0.0,
            "outer boundaries run counter-clockwise"
        );
        assert!(
            ring.points.len() <= max_vertices,
            "{} vertices > {max_vertices}",
            ring.points.len()
        );
        // Rectilinear: every edge is horizontal or vertical.
        let n = ring.points.len();
        for i in 0..n {
            let (a, b) = (ring.points[i], ring.points[(i + 1) % n]);
            assert!(a[0] == b[0] || a[1] == b[1], "diagonal edge {a:?} → {b:?}");
        }
    }
}

fn grid_of(w: usize, h: usize, open: impl Fn(usize, usize) -> bool) -> BinaryGrid {
    let mut g = BinaryGrid::new(w, h);
    for r in 0..h {
        for c in 0..w {
            g.set(c, r, open(c, r));
        }
    }
    g
}

#[test]
fn a_ring_becomes_one_keyholed_polygon_without_holes() {
    // An annulus: open between radii 10 and 20 cells.
    let g = grid_of(48, 48, |c, r| {
        let (x, y) = (c as f64 - 23.5, r as f64 - 23.5);
        (10.0..20.0).contains(&x.hypot(y))
    });
    let rings = trace_polygons(&g, MAX_VERTICES);
    assert_eq!(rings.len(), 1, "one region, its hole keyholed in");
    assert_exact(&g, &rings, MAX_VERTICES);
    // Nested rings: each ring is a region of its own, each keyholed.
    // Square bands at Chebyshev distances {0, 1}, {4, 5}, … {16, 17}, {20} from the centre.
    let nested = grid_of(41, 41, |c, r| {
        let d = (c as i64 - 20).abs().max((r as i64 - 20).abs());
        d % 4 < 2
    });
    let rings = trace_polygons(&nested, MAX_VERTICES);
    assert_eq!(rings.len(), 6);
    assert_exact(&nested, &rings, MAX_VERTICES);
}

#[test]
fn a_comb_of_ten_thousand_teeth_is_split_under_the_vertex_limit() {
    // Teeth one cell wide and two tall on every other column, on a one-cell spine.
    let g = grid_of(19_999, 3, |c, r| r == 2 || c % 2 == 0);
    let whole = trace_polygons(&g, usize::MAX);
    assert_eq!(whole.len(), 1);
    // Two spine corners, then four corners per tooth-and-gap.
    assert_eq!(whole[0].points.len(), 40_000);
    let rings = trace_polygons(&g, MAX_VERTICES);
    assert!(rings.len() >= 5, "{} pieces", rings.len());
    assert!(rings.len() <= 16, "{} pieces", rings.len());
    assert_exact(&g, &rings, MAX_VERTICES);
}

#[test]
fn a_solid_block_is_one_rectangle_and_a_checkerboard_is_squares() {
    let g = grid_of(300, 200, |_, _| true);
    let rings = trace_polygons(&g, MAX_VERTICES);
    assert_eq!(rings.len(), 1);
    assert_eq!(rings[0].points.len(), 4);
    let g = grid_of(9, 9, |c, r| (c + r) % 2 == 0);
    let rings = trace_polygons(&g, MAX_VERTICES);
    assert_eq!(rings.len(), 41, "cells touching at corners stay separate");
    assert_exact(&g, &rings, MAX_VERTICES);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, rng_seed: proptest::test_runner::RngSeed::Fixed(7), ..ProptestConfig::default() })]

    #[test]
    fn traced_polygons_reproduce_any_grid(
        w in 1usize..20,
        h in 1usize..20,
        density in 0.2f64..0.9,
        bits in proptest::collection::vec(0.0f64..1.0, 400),
        limit in prop_oneof![Just(4usize), Just(6), Just(12), Just(40), Just(MAX_VERTICES)],
    ) {
        let g = grid_of(w, h, |c, r| bits[r * 20 + c] < density);
        let rings = trace_polygons(&g, limit);
        assert_exact(&g, &rings, limit);
    }
}

fn design(cells: Vec<Vec<f64>>, pitch_um: f64, gap_um: f64) -> Design {
    let mut d = Design::default_toled();
    d.opening = Opening {
        pitch_um,
        cells,
        polygons: Vec::new(),
    };
    d.tiling.wiring_gap_um = gap_um;
    d.tiling.origin_offset_cells = [1.0, 2.0];
    d
}

#[test]
fn tones_split_each_period_square_exactly() {
    // 3 of 16 cells open (one grey cell at 0.5 counts as open, one at 0.49 does not).
    let mut cells = vec![vec![0.0; 4]; 4];
    cells[0][0] = 1.0;
    cells[1][2] = 0.5;
    cells[3][3] = 0.8;
    cells[2][2] = 0.49;
    let d = design(cells, 40.0, 6.0);
    for region in [MaskRegion::PIXEL, MaskRegion::Block { cols: 5, rows: 3 }] {
        let spec = |tone| MaskSpec {
            region,
            tone,
            border: BorderPolicy::Cut,
            ..MaskSpec::default()
        };
        let open = MaskLayout::new(&d, &spec(Tone::Open)).unwrap().stats();
        let chrome = MaskLayout::new(&d, &spec(Tone::Chrome)).unwrap().stats();
        let tiles = open.tiles as f64;
        assert_eq!(open.drawn_area_um2, tiles * 3.0 * 100.0);
        assert_eq!(open.region_area_um2, tiles * 46.0 * 46.0);
        assert_eq!(
            chrome.drawn_area_um2 + open.drawn_area_um2,
            open.region_area_um2
        );
        assert_eq!(chrome.open_area_um2, open.open_area_um2);
        assert_eq!(
            chrome.polygons_per_tile,
            1 + 1,
            "complement (one hole keyholed) + gap"
        );
    }
}

#[test]
fn the_pupil_region_covers_the_pupil_and_no_more() {
    let mut d = design(vec![vec![1.0; 2]; 2], 168.0, 0.0);
    d.tiling.mode = TilingMode::RandomD4;
    let spec = MaskSpec {
        region: MaskRegion::Pupil,
        border: BorderPolicy::Cut,
        ..MaskSpec::default()
    };
    let l = MaskLayout::new(&d, &spec).unwrap();
    let r_nm = d.optics.pupil_diameter_um() * 500.0;
    // Every tile overlaps the disc; the disc area is covered by the tiles.
    let q = l.period_nm as f64;
    for row in &l.rows {
        for tx in [row.tx0, row.tx0 + i64::from(row.count) - 1] {
            let [cx, cy] = l.tile_corner_nm(tx, row.ty).map(|v| v as f64);
            let dx = cx.max(-(cx + q)).max(0.0);
            let dy = (cy - q).max(-cy).max(0.0);
            assert!(dx.hypot(dy) < r_nm);
        }
    }
    let disc_um2 = std::f64::consts::PI * (r_nm * 1e-3).powi(2);
    let s = l.stats();
    assert!(s.region_area_um2 > disc_um2);
    assert!(s.region_area_um2 < disc_um2 * 1.4, "{}", s.region_area_um2);
    assert_eq!(l.orientations.len(), 8);
    let outline = l.pupil_outline.as_ref().unwrap();
    assert!(outline.points_nm.len() <= MAX_VERTICES);
    assert!((outline.area_um2() - disc_um2).abs() / disc_um2 < 1e-6);
}

#[test]
fn bad_layouts_are_refused_with_a_reason() {
    let empty = design(vec![vec![0.2; 3]; 3], 30.0, 0.0);
    assert_eq!(
        MaskLayout::new(&empty, &MaskSpec::default()).unwrap_err(),
        MaskError::EmptyPattern
    );
    let mut zero = design(vec![vec![1.0; 3]; 3], 30.0, 0.0);
    zero.opening.pitch_um = 0.0;
    let e = MaskLayout::new(&zero, &MaskSpec::default()).unwrap_err();
    assert!(e.to_string().contains("opening.pitch_um"), "{e}");
    let huge = MaskSpec {
        region: MaskRegion::Block {
            cols: 30_000,
            rows: 10,
        },
        border: BorderPolicy::Cut,
        ..MaskSpec::default()
    };
    let e = MaskLayout::new(&design(vec![vec![1.0; 3]; 3], 168.0, 0.0), &huge).unwrap_err();
    assert!(matches!(e, MaskError::TooLarge(_)), "{e}");
    assert!(e.to_string().contains("32-bit"), "{e}");
    let coarse = MaskSpec {
        grid_nm: 20_000,
        border: BorderPolicy::Cut,
        ..MaskSpec::default()
    };
    let e = MaskLayout::new(&design(vec![vec![1.0; 3]; 3], 30.0, 0.0), &coarse).unwrap_err();
    assert!(e.to_string().contains("finer grid"), "{e}");
}
