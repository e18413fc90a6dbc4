//! The emitter layer: subpixels in the design file, their validation and auto-placement
//! (thesis §3.7, Fig. 3.26).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use udc_core::Progress;
use udc_core::design::TilingMode;
use udc_core::design::{Opening, Subpixel, SubpixelChecks, Subpixels};
use udc_core::display::emitters::{auto_place, auto_place_cells, closed_cells};
use udc_core::optimize::{OptimizeSettings, optimize};
use udc_core::psf::route::PsfRoute;
use udc_io::design::file::{parse_design, to_json};
use udc_io::design::presets::load_preset;

/// The presets that carry an emitter layer: T-OLED, P-OLED and the two proposed layouts.
const WITH_SUBPIXELS: [&str; 5] = [
    "toled-150dpi",
    "poled-336um",
    "l2inv-repeat",
    "l2inv-random",
    "l2inv-random-wiring8",
];

#[test]
fn presets_carry_equal_area_emitters_in_the_opaque_area() {
    for name in WITH_SUBPIXELS {
        let d = load_preset(name).expect("preset");
        let sp = d.subpixels.as_ref().expect("an emitter layer");
        let closed = closed_cells(&d.opening);
        for (r, row) in sp.cells.iter().enumerate() {
            for (c, s) in row.iter().enumerate() {
                assert!(
                    s.is_none() || closed[r][c],
                    "{name}: emitter on open cell {r},{c}"
                );
            }
        }
        let checks = SubpixelChecks::of(sp, d.opening.cell_um());
        assert!(checks.area_um2.iter().all(|a| *a > 0.0), "{name}");
        assert!(checks.equal_area_deviation_pct < 1e-9, "{name}: {checks:?}");
    }
}

#[test]
fn subpixels_round_trip_through_the_design_file() {
    let d = load_preset("toled-150dpi").expect("preset");
    let text = to_json(&d);
    assert!(text.contains("\"subpixels\""));
    assert_eq!(parse_design(&text).expect("parses"), d);
    // Old files without the field still load.
    let mut old = d.clone();
    old.subpixels = None;
    let old_text = to_json(&old);
    assert!(!old_text.contains("\"subpixels\""));
    assert_eq!(parse_design(&old_text).expect("parses").subpixels, None);
}

#[test]
fn an_emitter_on_an_open_cell_is_an_error_naming_the_cell() {
    let mut d = load_preset("toled-150dpi").expect("preset");
    // Column 10 is inside the T-OLED slit.
    d.subpixels.as_mut().expect("layer").cells[3][10] = Some(Subpixel::Green);
    let err = parse_design(&to_json(&d)).expect_err("refused").to_string();
    assert!(err.contains("subpixels.cells[3][10]"), "{err}");
    assert!(err.contains("green") && err.contains("open cell"), "{err}");
}

#[test]
fn a_wrong_letter_or_size_is_refused() {
    let d = load_preset("toled-150dpi").expect("preset");
    let text = to_json(&d).replacen("RRRRRRRR.....GGGGGGGG", "RRRRRRRX.....GGGGGGGG", 1);
    let err = parse_design(&text).expect_err("refused").to_string();
    assert!(err.contains("subpixels") && err.contains("'X'"), "{err}");
    let mut small = d.clone();
    small.subpixels = Some(Subpixels::empty(5));
    let err = parse_design(&to_json(&small))
        .expect_err("refused")
        .to_string();
    assert!(
        err.contains("subpixels.cells") && err.contains("21×21"),
        "{err}"
    );
}

#[test]
fn auto_placement_fills_three_equal_rectangles_or_refuses() {
    // T-OLED: two 8-column opaque strips beside the slit.
    let toled = Opening::slit(21, 5, 168.0);
    let sp = auto_place(&toled, 0.0).expect("fits");
    let counts = sp.counts();
    assert_eq!(counts[0], counts[1]);
    assert_eq!(counts[1], counts[2]);
    assert!(counts[0] >= 80, "{counts:?}");
    // A minimum footprint larger than a third of the opaque area cannot be met.
    let cell = toled.cell_um();
    assert!(auto_place(&toled, 113.0 * cell * cell).is_none());
    // A fully open pixel has no room at all.
    assert!(auto_place(&Opening::open(21, 168.0), 0.0).is_none());
    // Disjoint rectangles only on free cells.
    let free = vec![vec![true; 6]; 6];
    let sp = auto_place_cells(&free, 1).expect("fits");
    assert_eq!(sp.counts(), [12, 12, 12]);
}

#[test]
fn editing_the_opening_drops_emitters_on_opened_cells() {
    let mut d = load_preset("toled-150dpi").expect("preset");
    d.opening.cells[0][0] = 1.0;
    d.reconcile_subpixels();
    assert_eq!(d.subpixels.as_ref().expect("kept").cells[0][0], None);
    d.validate().expect("consistent again");
    d.opening = Opening::open(7, 168.0);
    d.reconcile_subpixels();
    assert!(d.subpixels.is_none());
}

#[test]
fn an_optimized_opening_under_the_reserve_constraint_admits_a_placement() {
    let mut d = load_preset("toled-150dpi").unwrap();
    d.optics = crate::common::small_optics();
    d.tiling.mode = TilingMode::RandomD4;
    // 60 % open leaves 176 closed cells; 50 cells of 64 µm² per colour need more than the
    // binarised candidate is likely to leave in three rectangles.
    let min_um2 = 50.0 * 64.0;
    let settings = OptimizeSettings {
        epochs: 6,
        target_open_fraction: 0.6,
        reserve_subpixels_um2: min_um2,
        ..OptimizeSettings::default()
    };
    let r = optimize(
        &d,
        &settings,
        None,
        &PsfRoute::Auto,
        &Progress::new(),
        |_| std::ops::ControlFlow::Continue(()),
    )
    .unwrap();
    let out = &r.design;
    out.validate().expect("emitters on closed cells");
    let sp = out.subpixels.as_ref().expect("a placement");
    let checks = SubpixelChecks::of(sp, out.opening.cell_um());
    assert!(checks.area_um2.iter().all(|a| *a >= min_um2), "{checks:?}");
    assert!(checks.equal_area_deviation_pct < 1e-9);
    // Without the constraint the old placement is dropped, not carried over.
    let free = OptimizeSettings {
        reserve_subpixels_um2: 0.0,
        ..settings
    };
    let r = optimize(&d, &free, None, &PsfRoute::Auto, &Progress::new(), |_| {
        std::ops::ControlFlow::Continue(())
    })
    .unwrap();
    assert!(r.design.subpixels.is_none());
    // A footprint larger than a third of the pixel is refused by name.
    let huge = OptimizeSettings {
        reserve_subpixels_um2: 168.0 * 168.0 / 2.0,
        ..free
    };
    let err = optimize(&d, &huge, None, &PsfRoute::Auto, &Progress::new(), |_| {
        std::ops::ControlFlow::Continue(())
    })
    .unwrap_err();
    assert!(err.to_string().contains("reserve_subpixels_um2"), "{err}");
}
