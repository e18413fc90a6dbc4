//! The opening editor's drawing operations: shapes, symmetry, fills, resampling and text.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use udc_studio::core::design::MAX_CELLS;
use udc_studio::core::opening_ops::{
    Symmetry, clear, ellipse, flood_fill, from_text, invert, line, open_extent, open_fraction,
    paint, rect, resample, symmetric_cells, to_text,
};

fn closed(n: usize) -> Vec<Vec<f64>> {
    vec![vec![0.0; n]; n]
}

fn open_count(cells: &[Vec<f64>]) -> usize {
    cells.iter().flatten().filter(|&&v| v == 1.0).count()
}

fn flip_lr(cells: &[Vec<f64>]) -> Vec<Vec<f64>> {
    cells
        .iter()
        .map(|r| r.iter().rev().copied().collect())
        .collect()
}

fn flip_ud(cells: &[Vec<f64>]) -> Vec<Vec<f64>> {
    cells.iter().rev().cloned().collect()
}

#[test]
fn four_fold_paint_is_symmetric_under_both_flips() {
    for n in [20, 21] {
        let mut g = closed(n);
        paint(&mut g, 2, 5, 3, 1.0, Symmetry::FourFold);
        line(&mut g, (0, 0), (7, 3), 2, 1.0, Symmetry::FourFold);
        ellipse(&mut g, (1, 9), (6, 14), 1.0, Symmetry::FourFold);
        if n % 2 == 0 {
            assert_eq!(
                open_count(&g) % 4,
                0,
                "even grids have no cells on a mirror line"
            );
        }
        assert_eq!(flip_lr(&g), g, "n = {n}");
        assert_eq!(flip_ud(&g), g, "n = {n}");
        assert!(open_count(&g) > 4 * 9);
    }
}

#[test]
fn mirror_x_is_symmetric_left_right_only() {
    let mut g = closed(10);
    paint(&mut g, 1, 2, 1, 1.0, Symmetry::MirrorX);
    assert_eq!(flip_lr(&g), g);
    assert_ne!(flip_ud(&g), g);
    assert_eq!(open_count(&g), 2);
    let mut g = closed(10);
    paint(&mut g, 1, 2, 1, 1.0, Symmetry::MirrorY);
    assert_eq!(flip_ud(&g), g);
    assert_ne!(flip_lr(&g), g);
    assert_eq!(
        symmetric_cells(10, 1, 2, Symmetry::MirrorY),
        vec![(1, 2), (8, 2)]
    );
}

#[test]
fn flood_fill_stops_at_walls_and_ignores_diagonals() {
    let mut g = from_text(
        "
        .....
        .###.
        .#.#.
        .###.
        ....#
        ",
    )
    .unwrap();
    // The inner cell is walled off: filling it opens only it.
    flood_fill(&mut g, 2, 2, 1.0, Symmetry::None);
    assert_eq!(open_count(&g), 10);
    // Filling the outside opens every closed cell except the walled-in one.
    let mut g = from_text(".....\n.###.\n.#.#.\n.###.\n....#").unwrap();
    flood_fill(&mut g, 0, 0, 1.0, Symmetry::None);
    assert_eq!(to_text(&g), "#####\n#####\n##.##\n#####\n#####");
    // Closing it again from the corner closes every 4-connected open cell.
    flood_fill(&mut g, 0, 0, 0.0, Symmetry::None);
    assert_eq!(g, closed(5));
    // A region of open cells touching another only at a corner is not filled.
    let mut g = from_text("#..\n.#.\n...").unwrap();
    flood_fill(&mut g, 0, 0, 0.0, Symmetry::None);
    assert_eq!(to_text(&g), "...\n.#.\n...");
}

#[test]
fn rect_ellipse_and_line_cell_counts() {
    let mut g = closed(16);
    rect(&mut g, (10, 12), (3, 4), 1.0, Symmetry::None);
    assert_eq!(open_count(&g), 8 * 9);

    // A 5×5 box: the four corner cells' centres lie outside the inscribed circle.
    let mut g = closed(16);
    ellipse(&mut g, (0, 0), (4, 4), 1.0, Symmetry::None);
    assert_eq!(open_count(&g), 21);
    assert_eq!(open_extent(&g), Some((0, 0, 4, 4)));
    // A large disc covers about π r² cells.
    let mut g = closed(64);
    ellipse(&mut g, (2, 2), (61, 61), 1.0, Symmetry::None);
    let want = std::f64::consts::PI * 30.0 * 30.0;
    assert!((open_count(&g) as f64 / want - 1.0).abs() < 0.02);

    // Lines: one cell per step along the longer axis, the brush widening them.
    let mut g = closed(16);
    line(&mut g, (0, 0), (3, 9), 1, 1.0, Symmetry::None);
    assert_eq!(open_count(&g), 10);
    let mut g = closed(16);
    line(&mut g, (5, 0), (5, 15), 3, 1.0, Symmetry::None);
    assert_eq!(open_count(&g), 3 * 16);
}

#[test]
fn shapes_are_clipped_at_the_edges() {
    let mut g = closed(6);
    paint(&mut g, 0, 5, 5, 1.0, Symmetry::None);
    assert_eq!(open_count(&g), 3 * 3);
    rect(&mut g, (4, 4), (50, 50), 1.0, Symmetry::None);
    assert_eq!(g[5][5], 1.0);
    ellipse(&mut g, (3, 3), (9, 9), 1.0, Symmetry::None);
    assert!(g.iter().all(|r| r.len() == 6));
}

#[test]
fn resample_round_trips_and_keeps_the_shape() {
    let mut g = closed(21);
    rect(&mut g, (0, 8), (20, 12), 1.0, Symmetry::None);
    ellipse(&mut g, (3, 2), (9, 6), 1.0, Symmetry::None);
    let double = resample(&g, 42);
    assert_eq!(double.len(), 42);
    assert_eq!(open_count(&double), 4 * open_count(&g));
    assert_eq!(resample(&double, 21), g);
    assert_eq!(resample(&g, 63).len(), 63);
    assert_eq!(resample(&resample(&g, 63), 21), g);
    // Same open fraction at any integer multiple.
    assert!((open_fraction(&resample(&g, 84)) - open_fraction(&g)).abs() < 1e-12);
}

#[test]
fn text_round_trip() {
    let mut g = closed(9);
    ellipse(&mut g, (1, 1), (7, 5), 1.0, Symmetry::MirrorX);
    let text = to_text(&g);
    assert_eq!(text.lines().count(), 9);
    assert!(!text.ends_with('\n'));
    assert_eq!(from_text(&text).unwrap(), g);
    // '1' / '0', surrounding whitespace, CRLF and blank lines are accepted.
    let alt = format!(
        "\n\n  {}  \r\n\n",
        text.replace('#', "1")
            .replace('.', "0")
            .replace('\n', "\r\n")
    );
    assert_eq!(from_text(&alt).unwrap(), g);
}

#[test]
fn text_errors_say_what_is_wrong() {
    let mut rows = vec!["#".repeat(21); 21];
    rows[2] = "#".repeat(20);
    assert_eq!(
        from_text(&rows.join("\n")).unwrap_err(),
        "row 3 has 20 cells, expected 21"
    );
    let e = from_text("##\n#x").unwrap_err();
    assert!(e.contains("row 2, column 2") && e.contains("'x'"), "{e}");
    let e = from_text("###\n###").unwrap_err();
    assert!(e.contains("square"), "{e}");
    assert!(from_text("").unwrap_err().contains("no rows"));
    let big = vec![".".repeat(MAX_CELLS + 1); MAX_CELLS + 1].join("\n");
    assert!(
        from_text(&big)
            .unwrap_err()
            .contains(&MAX_CELLS.to_string())
    );
    assert_eq!(
        from_text(&vec![".".repeat(MAX_CELLS); MAX_CELLS].join("\n"))
            .unwrap()
            .len(),
        MAX_CELLS
    );
}

#[test]
fn invert_clear_fraction_and_extent() {
    let mut g = closed(4);
    assert_eq!(open_extent(&g), None);
    invert(&mut g);
    assert_eq!(open_fraction(&g), 1.0);
    assert_eq!(open_extent(&g), Some((0, 0, 3, 3)));
    clear(&mut g);
    assert_eq!(g, closed(4));
    g[1][2] = 1.0;
    g[3][1] = 1.0;
    assert_eq!(open_extent(&g), Some((1, 1, 3, 2)));
    assert!((open_fraction(&g) - 2.0 / 16.0).abs() < 1e-12);
}

fn grid_strategy() -> impl Strategy<Value = Vec<Vec<f64>>> {
    (1usize..24).prop_flat_map(|n| {
        prop::collection::vec(
            prop::collection::vec(prop::sample::select(vec![0.0, 0.25, 0.5, 1.0]), n),
            n,
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 128,
        rng_seed: RngSeed::Fixed(0x0DC5_7D10),
        ..ProptestConfig::default()
    })]

    #[test]
    fn invert_twice_is_identity(g in grid_strategy()) {
        let mut h = g.clone();
        invert(&mut h);
        invert(&mut h);
        prop_assert_eq!(h, g);
    }

    #[test]
    fn paint_only_touches_the_brush_footprint(
        g in grid_strategy(),
        r in 0usize..30,
        c in 0usize..30,
        brush in 1usize..8,
        value in prop::sample::select(vec![0.0, 1.0]),
    ) {
        let n = g.len();
        let (r, c) = (r % n, c % n);
        let mut h = g.clone();
        paint(&mut h, r, c, brush, value, Symmetry::None);
        // An odd brush is centred; an even one reaches one cell further down and right.
        let before = (brush - 1) / 2;
        let span = |x: usize| x.saturating_sub(before)..x + brush - before;
        for (i, (row_h, row_g)) in h.iter().zip(&g).enumerate() {
            for (j, (&a, &b)) in row_h.iter().zip(row_g).enumerate() {
                let inside = span(r).contains(&i) && span(c).contains(&j);
                if inside {
                    prop_assert_eq!(a, value, "cell ({}, {}) inside the brush", i, j);
                } else {
                    prop_assert_eq!(a, b, "cell ({}, {}) outside the brush changed", i, j);
                }
            }
        }
    }

    #[test]
    fn symmetric_paint_stays_symmetric(
        r in 0usize..30, c in 0usize..30, brush in 1usize..8, n in 1usize..24,
    ) {
        let (r, c) = (r % n, c % n);
        let mut g = closed(n);
        paint(&mut g, r, c, brush, 1.0, Symmetry::FourFold);
        prop_assert_eq!(&flip_lr(&g), &g);
        prop_assert_eq!(&flip_ud(&g), &g);
    }

    #[test]
    fn text_round_trips_binary_grids(g in grid_strategy()) {
        let binary: Vec<Vec<f64>> = g
            .iter()
            .map(|row| row.iter().map(|&v| if v >= 0.5 { 1.0 } else { 0.0 }).collect())
            .collect();
        prop_assert_eq!(from_text(&to_text(&g)).unwrap(), binary);
    }

    #[test]
    fn resample_by_an_integer_factor_round_trips(g in grid_strategy(), k in 1usize..4) {
        let n = g.len();
        prop_assert_eq!(resample(&resample(&g, n * k), n), g);
    }
}
