//! The opening editor: its drawing operations (shapes, symmetry, fills, resampling, text) and the
//! editor panel driven by simulated pointer events (one committed edit per stroke).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use egui::{PointerButton, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use udc_studio::app::panels::PanelCtx;
use udc_studio::app::panels::editor::EditorPanel;
use udc_studio::app::{DisplayAction, Tool};
use udc_studio::core::design::{Design, MAX_CELLS};
use udc_studio::core::display::opening_ops::{
    GridTextError, Symmetry, clear, ellipse, flood_fill, from_text, invert, line, open_extent,
    open_fraction, paint, rect, resample, symmetric_cells, to_text,
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
    let e = from_text(&rows.join("\n")).unwrap_err();
    assert_eq!(
        e,
        GridTextError::RowLength {
            row: 3,
            cells: 20,
            expected: 21
        }
    );
    assert_eq!(e.to_string(), "row 3 has 20 cells, expected 21");
    let e = from_text("##\n#x").unwrap_err();
    assert_eq!(
        e,
        GridTextError::Character {
            row: 2,
            column: 2,
            found: 'x'
        }
    );
    assert!(
        e.to_string().contains("row 2, column 2") && e.to_string().contains("'x'"),
        "{e}"
    );
    let e = from_text("###\n###").unwrap_err();
    assert!(
        matches!(e, GridTextError::NotSquare { rows: 2, cols: 3 }),
        "{e}"
    );
    assert!(e.to_string().contains("square"), "{e}");
    assert_eq!(from_text("").unwrap_err(), GridTextError::NoRows);
    let big = vec![".".repeat(MAX_CELLS + 1); MAX_CELLS + 1].join("\n");
    assert!(
        from_text(&big)
            .unwrap_err()
            .to_string()
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

// ---- The editor panel ----

struct State {
    panel: EditorPanel,
    design: Design,
    tool: Tool,
    actions: Vec<DisplayAction>,
}

fn harness(tool: Tool, value: f64) -> Harness<'static, State> {
    let mut design = Design::default_toled();
    design.opening.cells = vec![vec![value; 21]; 21];
    let mut h = editor_harness(
        Harness::builder().with_size(egui::vec2(480.0, 720.0)),
        design,
        tool,
    );
    h.run();
    h
}

/// The editor panel alone, drawing `design`, in a harness from `builder`.
fn editor_harness(
    builder: egui_kittest::HarnessBuilder<State>,
    design: Design,
    tool: Tool,
) -> Harness<'static, State> {
    let state = State {
        panel: EditorPanel::default(),
        design,
        tool,
        actions: Vec::new(),
    };
    builder.build_ui_state(
        |ui, s: &mut State| {
            let mut ctx = PanelCtx {
                design: &s.design,
                shown: None,
                display: None,
                pinned: None,
                overlays: false,
                design_rules: false,
                native_dialogs: false,
                tool: s.tool,
                actions: &mut s.actions,
            };
            s.panel.ui(ui, &mut ctx);
        },
        state,
    )
}

fn at(h: &Harness<State>, r: usize, c: usize) -> Pos2 {
    h.state().panel.cell_center(r, c).expect("grid drawn")
}

/// The cells of the single edit pushed so far.
fn single_edit(h: &Harness<State>) -> Vec<Vec<f64>> {
    match h.state().actions.as_slice() {
        [DisplayAction::Edit(d)] => d.opening.cells.clone(),
        other => panic!("expected one edit, got {other:?}"),
    }
}

fn pointer(h: &Harness<State>, pos: Pos2, button: PointerButton, pressed: bool) {
    h.event(egui::Event::PointerButton {
        pos,
        button,
        pressed,
        modifiers: egui::Modifiers::NONE,
    });
}

#[test]
fn a_fast_drag_is_one_edit_without_gaps() {
    let mut h = harness(Tool::Paint, 0.0);
    let rect = h.state().panel.grid_rect().expect("grid drawn");
    assert!((rect.width() - rect.height()).abs() < 1e-3);
    h.drag_at(at(&h, 2, 2));
    h.run();
    h.hover_at(at(&h, 2, 15));
    h.run();
    assert!(h.state().panel.is_drawing());
    assert!(h.state().actions.is_empty(), "nothing is pushed mid-drag");
    h.drop_at(at(&h, 2, 15));
    h.run();
    let cells = single_edit(&h);
    assert_eq!(open_extent(&cells), Some((2, 2, 2, 15)));
    assert_eq!(open_fraction(&cells), 14.0 / 441.0);
}

/// A press whose first move arrives in the same frame (a quick flick) paints from the pressed
/// cell, not from where the pointer already is; and the frame that ends the stroke still draws
/// it, since the document only takes the edit after that frame.
#[test]
fn a_press_that_moves_in_its_first_frame_keeps_the_pressed_cell() {
    let mut h = harness(Tool::Paint, 0.0);
    h.hover_at(at(&h, 2, 2));
    h.run();
    // Both events in one frame, as a windowing system batches them (`Harness::event` would
    // run a frame for each).
    let (a, b) = (at(&h, 2, 2), at(&h, 2, 6));
    h.input_mut().events.extend([
        egui::Event::PointerButton {
            pos: a,
            button: PointerButton::Primary,
            pressed: true,
            modifiers: egui::Modifiers::NONE,
        },
        egui::Event::PointerMoved(b),
    ]);
    h.step();
    h.event(egui::Event::PointerMoved(at(&h, 2, 9)));
    h.step();
    pointer(&h, at(&h, 2, 9), PointerButton::Primary, false);
    h.step();
    let cells = single_edit(&h);
    assert_eq!(
        open_extent(&cells),
        Some((2, 2, 2, 9)),
        "cells (2, 2)…(2, 9)"
    );
    assert_eq!(open_fraction(&cells), 8.0 / 441.0);
    assert_eq!(
        h.state().panel.shown_cells(),
        Some(cells.as_slice()),
        "the release frame draws the stroke, not the cells from before it"
    );
    // Once the document has the edit, the grid shows the document.
    h.state_mut().design.opening.cells = cells.clone();
    h.state_mut().actions.clear();
    h.run();
    assert_eq!(h.state().panel.shown_cells(), Some(cells.as_slice()));
    assert!(h.state().actions.is_empty(), "the stroke is committed once");
}

#[test]
fn secondary_drag_with_paint_erases() {
    let mut h = harness(Tool::Paint, 1.0);
    pointer(&h, at(&h, 5, 5), PointerButton::Secondary, true);
    h.run();
    h.hover_at(at(&h, 9, 5));
    h.run();
    pointer(&h, at(&h, 9, 5), PointerButton::Secondary, false);
    h.run();
    let cells = single_edit(&h);
    assert!((5..=9).all(|r| cells[r][5] == 0.0));
    assert_eq!(open_fraction(&cells), 436.0 / 441.0);
}

#[test]
fn rectangle_with_symmetry_and_a_click_fill() {
    let mut h = harness(Tool::Rect, 0.0);
    h.state_mut().panel.set_symmetry(Symmetry::MirrorX);
    h.drag_at(at(&h, 1, 1));
    h.run();
    h.hover_at(at(&h, 3, 4));
    h.run();
    h.drop_at(at(&h, 3, 4));
    h.run();
    let cells = single_edit(&h);
    assert_eq!(open_fraction(&cells), 24.0 / 441.0);
    assert_eq!(cells[2][18], 1.0);

    let mut h = harness(Tool::Fill, 0.0);
    h.get_by_label("Opening editor").click();
    h.run();
    assert_eq!(open_fraction(&single_edit(&h)), 1.0);
}

#[test]
fn tooltips_name_shortcuts_and_units() {
    let mut h = harness(Tool::Paint, 0.0);
    let checks = [
        ("Paint", "Paint (B)"),
        ("Invert", "transmittance"),
        ("Clear", "close every cell"),
        ("Import PNG…", "PNG image"),
        ("Opening editor", "cell (10, 10) · x = 84 µm, y = 84 µm"),
    ];
    for (label, tip) in checks {
        h.get_by_label(label).hover();
        h.run();
        assert!(h.query_by_label_contains(tip).is_some(), "{label}: {tip}");
    }
}

#[test]
fn buttons_push_commands() {
    let mut h = harness(Tool::Paint, 0.0);
    for label in ["Ellipse", "Invert", "Clear", "Import PNG…"] {
        h.get_by_label(label).click();
        h.run();
    }
    assert!(matches!(
        h.state().actions.as_slice(),
        [
            DisplayAction::SetTool(Tool::Ellipse),
            DisplayAction::Invert,
            DisplayAction::Clear,
            DisplayAction::ImportPattern
        ]
    ));
    h.state_mut().actions.clear();
    h.get_by_role_and_label(egui::Role::SpinButton, "grid")
        .set_value_accesskit(42.0);
    h.run();
    h.get_by_label("Apply").click();
    h.run();
    assert_eq!(single_edit(&h).len(), 42);
}

/// A pixel snapshot of the editor showing the thesis's optimized opening, compared with
/// `tests/snapshots/editor-l2inv-random.png` (regenerate with `UPDATE_SNAPSHOTS=1`). Skipped
/// only where no renderer exists (CI installs lavapipe, so it runs there).
#[test]
fn editor_snapshot_matches() {
    let design = udc_studio::io::design::presets::load_preset("l2inv-random").unwrap();
    let mut h = editor_harness(
        Harness::builder()
            .with_size(egui::vec2(420.0, 560.0))
            .wgpu(),
        design,
        Tool::Paint,
    );
    h.run();
    match h.try_snapshot("editor-l2inv-random") {
        Ok(()) => {}
        Err(egui_kittest::SnapshotError::RenderError { err }) => {
            eprintln!("no renderer here ({err}); snapshot skipped")
        }
        Err(e) => panic!("{e}"),
    }
}
