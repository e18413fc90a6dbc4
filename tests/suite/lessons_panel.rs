//! Help ▸ Lessons, driven like a student: the slit lesson loads its preset and view, a wrong
//! prediction is told wrong, the closed form's value is told right, Reveal explains with the
//! numbers filled in; a damaged lesson dropped on the window is refused in one line.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use egui_kittest::kittest::Queryable;

use crate::common::{self, step_until};
use udc_studio::app::ShellCommand;
use udc_studio::app::lessons::Verdict;

#[test]
fn a_student_walks_the_slit_lesson_and_is_checked_against_the_simulation() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio_small(dir.path());
    h.step();
    h.state_mut().command(ShellCommand::ToggleLessons);
    h.step();
    h.get_by_label("A single slit and sinc²").click();
    h.step();
    h.step();
    step_until(&mut h, "the slit", |app| {
        common::display_up_to_date(app) && app.lessons().current().is_some()
    });
    assert_eq!(
        crate::common::Reach::display(h.state()).design().name,
        "Fourier optics: single slit",
        "the step loaded its preset"
    );
    h.get_by_label("Next ▶").click();
    h.step();
    step_until(&mut h, "the step's view", common::display_up_to_date);
    assert!(h.query_by_label_contains("How far from the axis").is_some());
    // A wrong prediction, with its unit as a student types it.
    h.state_mut().lessons_mut().guess = "50 µm".into();
    h.step();
    h.get_by_label("Check").click();
    h.step();
    assert_eq!(h.state().lessons().verdict(), Some(&Verdict::Wrong));
    assert!(h.query_by_label_contains("Not quite").is_some());
    // λf / a for green light: 530 nm × 10 mm / 216 µm.
    let closed = 0.530 * 10_000.0 / 216.0;
    h.state_mut().lessons_mut().guess = format!("{closed:.1}");
    h.step();
    h.get_by_label("Check").click();
    h.step();
    assert_eq!(h.state().lessons().verdict(), Some(&Verdict::Right));
    h.get_by_label("Reveal").click();
    h.step();
    h.step();
    assert!(h.state().lessons().revealed().is_some());
    assert!(
        h.query_by_label_contains(&format!("that is {closed:.1} µm"))
            .is_some(),
        "the explanation carries the closed form's value"
    );
    crate::screenshots::capture(&mut h, "lesson-step-1024x700");

    // A damaged lesson dropped on the window: one line, naming the step and the field.
    let bad = dir.path().join("bad.toml");
    let text = udc_studio::io::lesson::SHIPPED[0]
        .1
        .replace("tolerance = 0.1", "tolerance = 3");
    std::fs::write(&bad, text).unwrap();
    crate::drop::drop_file(&mut h, bad);
    h.step();
    let m = h.state().lessons().message().unwrap();
    assert!(m.is_error());
    assert!(
        m.text.contains("step 2") && m.text.contains("question.tolerance"),
        "{}",
        m.text
    );
}

#[test]
fn a_mystery_aperture_is_scored_against_the_drawing_and_revealed() {
    use crate::common::Reach;
    use udc_studio::app::DisplayAction;
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio_small(dir.path());
    h.step();
    start_shipped(&mut h, "09-mystery.toml");
    step_until(&mut h, "the mystery and the canvas", |app| {
        app.lessons().mystery_ready() && common::display_up_to_date(app)
    });
    assert!(h.query_by_label("The mystery's log-PSF (green)").is_some());
    h.get_by_label("Score my drawing").click();
    h.step();
    let before = h.state().lessons().score().unwrap();
    assert!(before < 0.9, "the L is not the mystery: {before}");
    // The student draws the grating: the mystery's opening, as an edit of the design.
    let mut drawn = h.state().display().design().clone();
    drawn.opening = udc_studio::io::design::presets::load_preset("fourier-grating")
        .unwrap()
        .opening;
    h.state_mut().act(DisplayAction::Edit(Box::new(drawn)));
    step_until(&mut h, "the drawing's PSF", common::display_up_to_date);
    h.get_by_label("Score my drawing").click();
    h.step();
    let after = h.state().lessons().score().unwrap();
    assert!(after > 0.999, "the same opening matches: {after}");
    assert!(h.query_by_label_contains("Match: 100 %").is_some());
    h.get_by_label("Reveal the opening").click();
    h.step();
    h.step();
    assert!(h.state().lessons().unveiled());
    assert!(h.query_by_label("the mystery's opening").is_some());
    crate::screenshots::capture(&mut h, "mystery-revealed-1024x700");
}

/// The chapter-4 lesson sets up the Phase workspace (the thesis's design, then a refold at
/// 610 nm as one undo step) and checks predictions on its PSFs.
#[test]
fn the_microlens_lesson_sets_up_the_phase_workspace_and_checks_its_psfs() {
    use crate::common::Reach;
    use udc_studio::app::WorkspaceId;
    use udc_studio::core::lesson::measure::Guess;
    use udc_studio::core::phase::Lambda0;
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::studio_small(dir.path());
    h.step();
    start_shipped(&mut h, "11-microlens-arrays.toml");
    h.step();
    assert_eq!(h.state().workspace(), WorkspaceId::Phase);
    assert_eq!(h.state().phase().design().pitch_um, 42.0);
    step_until(&mut h, "the phase PSFs", |app| app.phase().is_up_to_date());
    // A bare T-OLED's answer (no gain) is wrong; P / a = 4.2 is right.
    assert_eq!(
        h.state_mut().check_lesson(Guess::Number(1.0)),
        Some(Verdict::Wrong)
    );
    assert_eq!(
        h.state_mut().check_lesson(Guess::Number(4.2)),
        Some(Verdict::Right)
    );
    h.state_mut().reveal_lesson();
    h.step();
    h.step();
    crate::screenshots::capture(&mut h, "lesson-microlens-1024x700");
    // Step 3 refolds the plate at 610 nm: one undo step on the Phase workspace.
    let ctx = h.ctx.clone();
    h.state_mut().lessons_mut().go_to(2, &ctx);
    h.step();
    assert_eq!(
        h.state().phase().design().lambda0,
        Lambda0::Fixed { nm: 610.0 }
    );
    step_until(&mut h, "the refolded PSFs", |app| {
        app.phase().is_up_to_date()
    });
    // R is the first option: the channel nearest 610 nm gains most.
    assert_eq!(
        h.state_mut().check_lesson(Guess::Choice(0)),
        Some(Verdict::Right)
    );
    assert!(h.state_mut().phase_mut().undo());
    assert_eq!(
        h.state().phase().design().lambda0,
        Lambda0::Fixed { nm: 530.0 }
    );
}

/// Starts the shipped lesson `file` in the studio, as picking it from the list does.
fn start_shipped(h: &mut egui_kittest::Harness<'_, udc_studio::app::StudioApp>, file: &str) {
    let (name, text) = udc_studio::io::lesson::SHIPPED
        .iter()
        .find(|(n, _)| *n == file)
        .unwrap();
    let lesson = udc_studio::io::lesson::parse_lesson(text).unwrap();
    let ctx = h.ctx.clone();
    h.state_mut()
        .lessons_mut()
        .start((*name).to_owned(), lesson, &ctx);
}
