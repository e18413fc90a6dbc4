//! Shared helpers for the integration tests.
#![allow(dead_code)]

mod reach;
pub use reach::{Reach, display_up_to_date};

/// The real studio in a headless harness, persisting into `dir`, with native dialogs off.
pub fn studio(
    dir: &std::path::Path,
    wgpu: bool,
    autosave_every: std::time::Duration,
) -> egui_kittest::Harness<'static, udc_studio::app::StudioApp> {
    studio_sized(dir, wgpu, autosave_every, egui::vec2(1440.0, 900.0))
}

/// [`studio`] rendered in the smallest window the studio supports, 1024×700 points (the
/// screenshots of the teaching features are taken there).
pub fn studio_small(
    dir: &std::path::Path,
) -> egui_kittest::Harness<'static, udc_studio::app::StudioApp> {
    studio_sized(
        dir,
        true,
        std::time::Duration::from_secs(600),
        egui::vec2(1024.0, 700.0),
    )
}

/// [`studio`] in a window of `size` points.
pub fn studio_sized(
    dir: &std::path::Path,
    wgpu: bool,
    autosave_every: std::time::Duration,
    size: egui::Vec2,
) -> egui_kittest::Harness<'static, udc_studio::app::StudioApp> {
    let dirs = udc_studio::app::AppDirs::at(dir);
    let mut b = egui_kittest::Harness::builder()
        .with_size(size)
        .with_max_steps(10_000);
    if wgpu {
        b = b.wgpu();
    }
    b.build_eframe(move |cc| {
        udc_studio::app::StudioApp::new(
            &cc.egui_ctx,
            udc_studio::app::StudioOptions {
                dirs,
                design_path: None,
                native_dialogs: false,
                autosave_every,
                gpu: None,
            },
        )
    })
}

/// Steps the UI until `done` holds (the worker runs on its own thread); fails after 300 s (a hang guard, not a timing check: CI shares 2 cores between tests).
///
/// The pause between frames grows from 2 to 100 ms: a quick job is seen at once, and while a
/// long one runs the test's frames (a large UI laid out at 100 frames a second took a tenth of
/// the CPU of the phase comparison's test) leave the cores to the workers.
pub fn step_until(
    h: &mut egui_kittest::Harness<'_, udc_studio::app::StudioApp>,
    what: &str,
    done: impl Fn(&udc_studio::app::StudioApp) -> bool,
) {
    let start = std::time::Instant::now();
    let mut pause = std::time::Duration::from_millis(2);
    loop {
        h.step();
        if done(h.state()) {
            h.step();
            return;
        }
        assert!(
            start.elapsed() < std::time::Duration::from_secs(300),
            "timed out waiting for {what}"
        );
        std::thread::sleep(pause);
        pause = (pause * 2).min(std::time::Duration::from_millis(100));
    }
}

/// Presses the primary button at `a` and moves to `b` in `steps` frames, without releasing.
pub fn press_and_move<S>(
    h: &mut egui_kittest::Harness<'_, S>,
    a: egui::Pos2,
    b: egui::Pos2,
    steps: usize,
) {
    h.hover_at(a);
    h.step();
    h.event(egui::Event::PointerButton {
        pos: a,
        button: egui::PointerButton::Primary,
        pressed: true,
        modifiers: Default::default(),
    });
    h.step();
    for k in 1..=steps {
        h.event(egui::Event::PointerMoved(
            a + (b - a) * (k as f32 / steps as f32),
        ));
        h.step();
    }
}

/// Runs the `udc-studio` binary: (success, stdout, stderr).
pub fn run_cli(args: &[&str]) -> (bool, String, String) {
    let (code, stdout, stderr, _) = run_cli_timed(args);
    (code == Some(0), stdout, stderr)
}

/// Runs the `udc-studio` binary: (exit code, stdout, stderr, wall time).
pub fn run_cli_timed(args: &[&str]) -> (Option<i32>, String, String, std::time::Duration) {
    let t0 = std::time::Instant::now();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_udc-studio"))
        .args(args)
        .output()
        .expect("run the binary");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        t0.elapsed(),
    )
}

/// Runs `python3 -c code` in `dir`; `needs` names the modules it imports, for the message
/// when python3 or they are missing (the test command installs them).
pub fn python(dir: &std::path::Path, code: &str, needs: &str) {
    let out = std::process::Command::new("python3")
        .arg("-c")
        .arg(code)
        .current_dir(dir)
        .output()
        .unwrap_or_else(|e| panic!("python3 with {needs} is required: {e}"));
    assert!(
        out.status.success(),
        "python failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The 150-DPI T-OLED preset at `pitch_um`, its green PSF simulated on `window_px` pixels
/// with the axis on a pixel's centre (as an import centres it), written as a measured PSF set
/// to `path`.
pub fn toled_green_set(path: &std::path::Path, pitch_um: f64, window_px: usize) {
    use udc_studio::core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
    use udc_studio::core::measured::{PsfSet, PsfSource};
    let mut truth = udc_studio::io::design::presets::load_preset("toled-150dpi").expect("preset");
    truth.opening.pitch_um = pitch_um;
    truth.optics.axis_in_pixel_um = [1.0, 1.0];
    truth.optics.window_px = window_px;
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    let analysis =
        analyze_with(&truth, &options, &udc_studio::core::Progress::new()).expect("analysis");
    let mut set = PsfSet::from_analysis(&analysis);
    set.channels.retain(|c| c.name == "G");
    set.source = PsfSource::Measured;
    udc_studio::io::measured::write_psf_set(path, &set, None).expect("written");
}

/// Runs `udc-studio sweep tests/sweep/tiny.toml --out DIR/tiny-results` (8 points at preview
/// quality) and returns the results folder.
pub fn tiny_sweep(dir: &std::path::Path) -> std::path::PathBuf {
    let out = dir.join("tiny-results");
    let spec = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/sweep/tiny.toml");
    let (ok, _, stderr) = run_cli(&[
        "sweep",
        spec.to_str().expect("utf-8 path"),
        "--out",
        out.to_str().expect("utf-8 path"),
    ]);
    assert!(ok, "the sweep ran: {stderr}");
    out
}

/// Help ▸ Reproduce thesis results, opened from the menu as a user does.
pub fn open_reproduce_window(h: &mut egui_kittest::Harness<'_, udc_studio::app::StudioApp>) {
    use egui_kittest::kittest::Queryable;
    h.get_by_label("Help").click();
    h.step();
    h.step();
    h.get_by_label("Reproduce thesis results…").click();
    // A new window is laid out invisibly on its first frame.
    h.step();
    h.step();
}

/// Changes the phase capture view's choices as its controls do (one queued action).
pub fn choose_capture(
    phase: &mut udc_studio::app::phase::PhaseWorkspace,
    change: impl FnOnce(&mut udc_studio::app::phase::CaptureChoices),
) {
    let mut c = phase.capture_choices();
    change(&mut c);
    phase.act(udc_studio::app::phase::PhaseAction::Capture(c));
}

/// Right-clicks at `at` with the pointer (hover, press, release), then lets the context menu
/// open.
pub fn right_click(h: &mut egui_kittest::Harness<'_, udc_studio::app::StudioApp>, at: egui::Pos2) {
    h.hover_at(at);
    h.step();
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Secondary,
            pressed,
            modifiers: Default::default(),
        });
        h.step();
    }
    h.run_steps(2);
}
