//! Save figure in the studio: the log-PSF view's button opens the window with the design's
//! caption, and the figure is written at the chosen size on a helper thread.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::Duration;

use egui_kittest::kittest::Queryable;

use crate::common::{self, Reach, step_until};
use udc_studio::app::DisplayAction;

#[test]
fn the_log_psf_view_saves_as_a_figure_with_the_designs_caption() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio(dir.path(), false, Duration::from_secs(600));
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    step_until(&mut h, "the T-OLED result", common::display_up_to_date);
    h.step();
    h.get_by_label("Save figure…").click();
    h.step();
    h.step();
    let window = h.state().save_figure();
    assert!(window.is_open(), "the button opens the window");
    let figure = window.figure().unwrap();
    assert!(
        figure.panels[0].title.contains("log-PSF"),
        "{}",
        figure.panels[0].title
    );
    let caption = figure.caption.unwrap();
    assert!(
        caption.contains("pitch 168.0 µm") && caption.contains("f/2.5"),
        "{caption}"
    );
    // Without native dialogs Save… says so instead of hanging.
    h.get_by_label("Save…").click();
    h.step();
    assert!(h.state().save_figure().message().unwrap().is_error());

    let path = dir.path().join("slide");
    let ctx = h.ctx.clone();
    let w = h.state_mut().save_figure_mut();
    w.format = udc_studio::core::figure::FigureFormat::Png;
    w.width_px = 640;
    w.height_px = 400;
    w.save_to(&path, &ctx);
    step_until(&mut h, "the write", |app| !app.save_figure().is_busy());
    h.step();
    let written = dir.path().join("slide.png");
    let img = image::open(&written).unwrap();
    assert_eq!((img.width(), img.height()), (640, 400));
    assert!(
        !h.state().save_figure().is_open(),
        "the window closes once the figure is written"
    );
}
