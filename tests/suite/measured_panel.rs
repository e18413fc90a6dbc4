//! The Measured PSF panel, driven like a user: a prototype's PSF set dropped on the window
//! opens beside the design on screen, compared, the display fitted to it (with Cancel), and the fit applied as one
//! undoable edit.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::Duration;

use egui_kittest::kittest::Queryable;

use crate::common::{self, Reach, step_until};
use udc_studio::app::{DisplayAction, LeftTab, ShellCommand};

#[test]
fn a_measured_set_compares_fits_and_applies_as_one_undoable_edit() {
    let dir = tempfile::tempdir().unwrap();
    // The 150-DPI T-OLED built 10 % coarser than drawn (184.8 µm), green, on 96 pixels.
    let set = dir.path().join("prototype.npy");
    common::toled_green_set(&set, 184.8, 96);
    // Rendered (lavapipe) so that the screenshot script can take the panel's picture.
    let mut h = common::studio(dir.path(), true, Duration::from_secs(600));
    h.state_mut()
        .act(DisplayAction::LoadPreset("toled-150dpi".into()));
    step_until(&mut h, "the T-OLED result", common::display_up_to_date);
    let before = h.state().display().design().clone();
    h.state_mut().display_mut().show_left_tab(LeftTab::Measured);
    h.step();
    // Without native dialogs the button says so instead of hanging.
    h.get_by_label("Open PSF set…").click();
    h.step();
    h.step();
    assert!(
        h.state().display().measured().message().unwrap().is_error(),
        "the disabled dialog is reported"
    );
    // Dropped on the window, as the dialog's message says.
    crate::drop::drop_file(&mut h, set.clone());
    step_until(&mut h, "the set", |app| {
        app.display().measured().loaded().is_some()
    });
    assert!(
        h.query_by_label_contains("96 px at 2 µm, measured")
            .is_some(),
        "the set's line names its size, pitch and source"
    );

    h.get_by_label("Compare with the design").click();
    step_until(&mut h, "the comparison", |app| {
        app.display().measured().compared().is_some()
    });
    let compared = h.state().display().measured().compared().unwrap()[0].clone();
    assert_eq!(compared.design_channel, "G");
    // A display 10 % off is not the design: most of the PSF's energy is in the residual.
    assert!(compared.comparison.residual_energy_share > 0.1);
    assert!(h.query_by_label("Measured against the design").is_some());

    // A fit cancelled midway leaves nothing fitted and says so.
    h.get_by_label("Fit the display").click();
    h.step();
    assert!(h.state().display().measured().is_busy());
    h.get_by_label("Cancel").click();
    step_until(&mut h, "the cancel", |app| {
        !app.display().measured().is_busy()
    });
    assert!(h.state().display().measured().fitted().is_none());
    assert_eq!(
        h.state().display().measured().message().unwrap().text,
        "cancelled"
    );

    h.get_by_label("Fit the display").click();
    step_until(&mut h, "the fit", |app| {
        app.display().measured().fitted().is_some()
    });
    let fitted = h.state().display().measured().fitted().unwrap();
    let pitch = fitted.pitch_um.value;
    assert!((pitch / 184.8 - 1.0).abs() < 0.01, "{pitch}");
    assert!(h.query_by_label("Fitted display").is_some());
    assert!(
        h.query_by_label_contains(&format!("{pitch:.2} ±"))
            .is_some(),
        "the table shows the fitted pitch with its uncertainty"
    );
    assert_eq!(
        h.state().display().design(),
        &before,
        "nothing changes before Apply"
    );
    crate::screenshots::capture(&mut h, "measured-psf-fit");

    h.get_by_label("Apply the fitted pitch and opening").click();
    h.step();
    h.step();
    let after = h.state().display().design().clone();
    assert!((after.opening.pitch_um - pitch).abs() < 1e-9);
    assert_eq!(after.optics, before.optics, "the optics stay");
    h.state_mut().command(ShellCommand::Undo);
    h.step();
    assert_eq!(
        h.state().display().design(),
        &before,
        "one undo restores the design"
    );
}
