//! Presentation mode, driven like a user: Ctrl+Shift+P turns it on (black on white, everything
//! larger, the advanced tabs folded away, pictures in viridis), it survives a restart, and again
//! restores the dark studio as it was.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::Duration;

use egui::{Key, Modifiers};
use egui_kittest::kittest::Queryable;

use crate::common::{self, Reach, step_until};
use udc_studio::app::DisplayAction;
use udc_studio::app::presentation;

#[test]
fn ctrl_shift_p_presents_for_a_projector_keeps_f5_for_the_seed_and_survives_a_restart() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio_small(dir.path());
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    step_until(&mut h, "the T-OLED result", common::display_up_to_date);
    assert!(
        h.ctx.global_style().visuals.dark_mode,
        "the studio starts dark"
    );
    assert!(h.query_by_label("Optimize").is_some());
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::P);
    h.step();
    h.step();
    assert!(presentation::is_on(&h.ctx));
    assert!(!h.ctx.global_style().visuals.dark_mode, "a light theme");
    assert_eq!(
        h.ctx.global_style().visuals.override_text_color,
        Some(egui::Color32::BLACK)
    );
    assert!((h.ctx.zoom_factor() - presentation::ZOOM).abs() < 1e-6);
    assert!(
        h.query_by_label("Optimize").is_none() && h.query_by_label("Measured").is_none(),
        "the advanced tabs fold away"
    );
    assert!(h.query_by_label("Opening").is_some());
    // F5 stays the random tiling's reroll: the seed changes, the mode stays.
    let seed = h.state().display().design().tiling.seed;
    h.key_press(Key::F5);
    h.step();
    h.step();
    assert!(presentation::is_on(&h.ctx));
    assert_ne!(
        h.state().display().design().tiling.seed,
        seed,
        "F5 rerolled"
    );
    for _ in 0..3 {
        h.step();
    }
    crate::screenshots::capture(&mut h, "presentation-1024x700");
    drop(h);

    // The next session starts presenting.
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.step();
    assert!(presentation::is_on(&h.ctx), "the setting is kept");
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::P);
    h.step();
    h.step();
    assert!(!presentation::is_on(&h.ctx));
    assert!(
        h.ctx.global_style().visuals.dark_mode,
        "back to the dark theme"
    );
    assert!((h.ctx.zoom_factor() - 1.0).abs() < 1e-6);
    assert!(h.query_by_label("Optimize").is_some());
}
