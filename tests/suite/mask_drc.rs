//! The design-rule check on the thesis's layouts: the widths it reports are the layouts' own,
//! and the random L2-inverse tiling's corner contacts are found.

use udc_studio::core::mask::drc::{Rules, ViolationKind, check};
use udc_studio::io::presets::load_preset;

#[test]
fn the_toled_slit_is_40_um_wide_with_128_um_of_chrome_between() {
    let d = load_preset("toled-150dpi").unwrap();
    let r = check(&d, &Rules::default());
    // 5 open cells of 8 µm, 16 closed (two runs of 8 joined across the tile edge).
    assert_eq!(r.min_feature_um, Some(40.0));
    assert_eq!(r.min_gap_um, Some(128.0));
    assert_eq!(r.corner_contacts, 0);
    assert!(r.is_clean());
}

#[test]
fn the_random_l2inv_layout_has_corner_contacts_and_one_cell_features() {
    let d = load_preset("l2inv-random").unwrap();
    let r = check(&d, &Rules::default());
    assert!(r.corner_contacts > 0, "{r:?}");
    assert!(r.counts[ViolationKind::CornerContact as usize] > 0);
    // Its smallest features and gaps are single 8-µm cells: fine for a 2-µm process...
    assert_eq!(r.min_feature_um, Some(8.0));
    assert_eq!(r.min_gap_um, Some(8.0));
    // ...and flagged by a 10-µm one, with places in the tile frame.
    let coarse = Rules {
        min_feature_um: 10.0,
        min_gap_um: 10.0,
        ..Rules::default()
    };
    let r = check(&d, &coarse);
    let v = r
        .violations
        .iter()
        .find(|v| v.kind == ViolationKind::MinFeature)
        .unwrap();
    assert_eq!(v.value, 8.0);
    assert!((0.0..=2.0 * 168.0).contains(&v.at_um[0]) && (0.0..=2.0 * 168.0).contains(&v.at_um[1]));
    // The contacts are inside the optimized opening itself: an 8-µm wiring gap between the
    // tiles does not remove them (it only removes contacts across tile edges).
    let mut wired = d.clone();
    wired.tiling.wiring_gap_um = 8.0;
    let with_gap = check(&wired, &Rules::default()).corner_contacts;
    assert!(with_gap > 0 && with_gap <= check(&d, &Rules::default()).corner_contacts);
}
