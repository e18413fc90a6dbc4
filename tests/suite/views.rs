//! The result views panel, driven headless with egui_kittest: every tab draws, the tabs and the
//! pin button work, and nothing is re-uploaded while nothing changes.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::sync::Arc;

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use udc_studio::app::panels::numbers::NumbersPanel;
use udc_studio::app::panels::views::{ViewTab, ViewsPanel};
use udc_studio::app::panels::{PanelCtx, Pinned, Shown};
use udc_studio::app::{DisplayAction, Tool};
use udc_studio::core::analysis::analyze::{AnalyzeOptions, Quality, analyze, analyze_with};
use udc_studio::core::design::{Design, Optics, OpticsRecipe, TilingMode};
use udc_studio::core::{Analysis, Progress};
use udc_studio::io::design::presets::load_preset;

/// What the harness draws from: the panel plus the context the shell would hand it.
struct State {
    panel: ViewsPanel,
    design: Design,
    shown: Option<Shown>,
    pinned: Option<Pinned>,
    overlays: bool,
    actions: Vec<DisplayAction>,
}

/// The 150-DPI T-OLED opening on small, fast optics, randomly tiled (so the expected PSF exists).
fn small_result() -> (Design, Analysis) {
    let mut design = load_preset("toled-150dpi").expect("preset");
    // Small, fast optics: f/5 at 8-µm pupil samples (250 across), 2 fine samples a pixel.
    design.optics = Optics {
        recipe: OpticsRecipe::Custom,
        focal_length_mm: 10.0,
        f_number: 5.0,
        pupil_sample_um: 8.0,
        fine_sample_um: 1.0,
        sensor_pixel_um: 2.0,
        window_px: 64,
        axis_in_pixel_um: [0.5, 0.5],
    };
    design.tiling.mode = TilingMode::RandomD4;
    let analysis = analyze(&design, &Progress::new()).expect("analysis");
    (design, analysis)
}

fn shown(design: &Design, analysis: Analysis, generation: u64) -> Shown {
    Shown {
        generation,
        quality: Quality::Full,
        analysis: Arc::new(analysis),
        design: Arc::new(design.clone()),
        route: Arc::new(udc_gpu::Route::cpu()),
    }
}

fn harness(state: State) -> Harness<'static, State> {
    let mut builder = Harness::builder().with_size(egui::vec2(1200.0, 800.0));
    if shots_dir().is_some() {
        builder = builder.wgpu();
    }
    builder.build_ui_state(
        |ui, s: &mut State| {
            let mut ctx = PanelCtx {
                design: &s.design,
                shown: s.shown.as_ref(),
                display: None,
                pinned: s.pinned.as_ref(),
                overlays: s.overlays,
                design_rules: false,
                native_dialogs: false,
                tool: Tool::default(),
                actions: &mut s.actions,
            };
            s.panel.ui(ui, &mut ctx);
        },
        state,
    )
}

/// Where to save pictures of the views (`UDC_SCREENSHOTS_DIR`), if anywhere.
fn shots_dir() -> Option<std::path::PathBuf> {
    std::env::var_os("UDC_SCREENSHOTS_DIR").map(Into::into)
}

/// Saves a picture of the panel when `UDC_SCREENSHOTS_DIR` is set (and a renderer exists).
fn capture(h: &mut Harness<'_, State>, name: &str) {
    let Some(dir) = shots_dir() else { return };
    match h.render() {
        Ok(img) => {
            std::fs::create_dir_all(&dir).unwrap();
            img.save(dir.join(format!("views-{name}.png"))).unwrap();
        }
        Err(e) => eprintln!("{name}: no renderer here ({e})"),
    }
}

#[test]
fn without_a_result_the_panel_says_it_is_computing() {
    let (design, _) = small_result();
    let mut h = harness(State {
        panel: ViewsPanel::default(),
        design,
        shown: None,
        pinned: None,
        overlays: false,
        actions: Vec::new(),
    });
    h.step();
    assert!(h.query_by_label("computing…").is_some());
}

#[test]
fn every_tab_draws_and_textures_are_built_once() {
    let (design, analysis) = small_result();
    let mut h = harness(State {
        panel: ViewsPanel::default(),
        shown: Some(shown(&design, analysis, 1)),
        design,
        pinned: None,
        overlays: true,
        actions: Vec::new(),
    });
    h.step();
    for tab in ViewTab::ALL {
        h.get_by_label(tab.label()).click();
        h.step();
        h.step();
        assert_eq!(h.state().panel.tab(), tab);
        assert!(
            h.query_by_label("What am I seeing?").is_some(),
            "{tab:?} hint"
        );
        // These two start a background job on opening; their own tests (field_depth_view,
        // appearance_view) take the pictures once it has answered.
        if !matches!(tab, ViewTab::FieldDepth | ViewTab::Appearance) {
            capture(&mut h, &tab.label().replace(' ', "-"));
        }
    }
    // Hovering an image reads out the value under the pointer with its position.
    for (tab, unit) in [(ViewTab::LogPsf, "µm"), (ViewTab::Mtf2d, "cyc/px")] {
        h.get_by_label(tab.label()).click();
        h.step();
        h.hover_at(egui::pos2(500.0, 450.0));
        h.step();
        h.step();
        let readout = h.query_by_label_contains("x = ").map(|n| format!("{n:?}"));
        let readout = readout.expect("a hover readout");
        assert!(readout.contains(unit), "{readout}");
    }
    // Expected PSF of a random tiling: both images side by side.
    h.get_by_label("Expected PSF").click();
    h.step();
    // Its caption and the picture, which a screen reader names by the same title.
    assert_eq!(
        h.query_all_by_label("expected over all random tilings")
            .count(),
        2
    );
    // Frames without changes upload nothing.
    let builds = h.state().panel.texture_builds();
    assert!(
        builds >= 5,
        "PSF, log-PSF, RGB, MTF 2-D and the two expected images: {builds}"
    );
    for _ in 0..5 {
        h.step();
    }
    for tab in [ViewTab::Psf, ViewTab::LogPsf, ViewTab::Expected] {
        h.get_by_label(tab.label()).click();
        h.step();
    }
    assert_eq!(h.state().panel.texture_builds(), builds);
    // A new result rebuilds the image on screen, once.
    let (design, analysis) = small_result();
    h.state_mut().shown = Some(shown(&design, analysis, 2));
    for _ in 0..3 {
        h.step();
    }
    assert_eq!(h.state().panel.texture_builds(), builds + 2);
}

#[test]
fn compare_tab_pins_and_shows_a_and_b() {
    let (design, analysis) = small_result();
    let mut h = harness(State {
        panel: ViewsPanel::default(),
        shown: Some(shown(&design, analysis, 1)),
        design,
        pinned: None,
        overlays: false,
        actions: Vec::new(),
    });
    h.state_mut().panel.set_tab(ViewTab::Compare);
    h.step();
    assert!(h.query_by_label_contains("Nothing is pinned yet").is_some());
    h.get_by_label("Pin as A").click();
    h.step();
    assert!(matches!(
        h.state().actions.as_slice(),
        [DisplayAction::PinCompare]
    ));
    // The shell answers the command by pinning the result.
    let s = h.state_mut();
    let current = s.shown.clone().expect("shown");
    s.pinned = Some(Pinned::now(
        current.design.clone(),
        current.analysis.clone(),
    ));
    let at = s.pinned.as_ref().unwrap().pinned_at.clone();
    h.step();
    h.step();
    let name = &current.design.name;
    assert!(
        h.query_by_label(&format!("A: {name} (pinned {at})"))
            .is_some()
    );
    assert!(
        h.query_by_label(&format!("B: {name} (current, same as A)"))
            .is_some()
    );
    assert!(h.query_by_label("A (pinned)").is_some());
    assert!(h.query_by_label("B − A").is_some());
    assert!(h.query_by_label("R AUC").is_some());
    assert!(h.query_by_label("invertibility loss").is_some());
    capture(&mut h, "Compare-pinned");
}

/// The percentage in the Theory tab's agreement line.
fn theory_deviation_percent(h: &Harness<'_, State>) -> f64 {
    use egui_kittest::kittest::NodeT;
    let node = h.get_by_label_contains("differ by at most");
    let text = node.accesskit_node().value().unwrap_or_default();
    let after = text.split("at most ").nth(1).unwrap_or_default();
    after
        .split(' ')
        .next()
        .unwrap_or_default()
        .parse()
        .unwrap_or(f64::NAN)
}

#[test]
fn the_theory_tab_agrees_on_a_slit_then_parts_when_it_is_broken() {
    let design = load_preset("fourier-slit").unwrap();
    let analysis = analyze(&design, &Progress::new()).unwrap();
    let mut h = harness(State {
        panel: ViewsPanel::default(),
        shown: Some(shown(&design, analysis, 1)),
        design: design.clone(),
        pinned: None,
        overlays: false,
        actions: Vec::new(),
    });
    h.step();
    h.get_by_label("Theory").click();
    h.step();
    h.step();
    assert!(h.query_by_label("Theory: single slit").is_some());
    assert!(
        h.query_by_label_contains("I(x) = I(0)·sinc²(a·x / λf), a = 216 µm")
            .is_some()
    );
    let agree = theory_deviation_percent(&h);
    assert!(agree < 0.5, "{agree} %");
    capture(&mut h, "theory-slit");
    // Open a second slit beside the first: the formula stays, the simulation follows.
    let mut broken = design.clone();
    let n = broken.opening.n();
    for row in broken
        .opening
        .cells
        .iter_mut()
        .take(n / 2 + 40)
        .skip(n / 2 - 40)
    {
        row[n / 2 + 12] = 1.0;
    }
    let analysis = analyze(&broken, &Progress::new()).unwrap();
    h.state_mut().shown = Some(shown(&broken, analysis, 2));
    h.step();
    h.step();
    let parted = theory_deviation_percent(&h);
    assert!(parted > 10.0, "{parted} %");
    // A design without a named aperture is compared with its own orders.
    let (design, analysis) = small_result();
    h.state_mut().shown = Some(shown(&design, analysis, 3));
    h.step();
    h.step();
    assert!(h.query_by_label("Theory: grating orders").is_some());
}

/// The Numbers panel alone, showing `shown`.
struct NumbersState {
    panel: NumbersPanel,
    design: Design,
    shown: Shown,
    actions: Vec<DisplayAction>,
}

/// The numbers say which result they are: a preview estimate, with "≈" on what the sampling
/// changes, until the full-quality result replaces it; the Compare tab says it of B too.
#[test]
fn the_quality_label_follows_the_shown_result() {
    let (mut design, _) = small_result();
    // Fine enough for the preview to double δ2 (at δ2 = 1 µm it is full quality's sampling).
    design.optics.fine_sample_um = 0.25;
    assert!(Quality::Preview.doubles_spacing(&design));
    for quality in [Quality::Preview, Quality::Full] {
        let options = AnalyzeOptions {
            quality,
            expected_psf: false,
        };
        let analysis = analyze_with(&design, &options, &Progress::new()).expect("analysis");
        let loss = format!("{:.4}", analysis.invertibility_loss);
        let mut s = shown(&design, analysis, 1);
        s.quality = quality;
        let preview = quality == Quality::Preview;
        let mut h = Harness::builder()
            .with_size(egui::vec2(400.0, 600.0))
            .build_ui_state(
                |ui, st: &mut NumbersState| {
                    let mut ctx = PanelCtx {
                        design: &st.design,
                        shown: Some(&st.shown),
                        display: None,
                        pinned: None,
                        overlays: false,
                        design_rules: false,
                        native_dialogs: false,
                        tool: Tool::default(),
                        actions: &mut st.actions,
                    };
                    st.panel.ui(ui, &mut ctx, None);
                },
                NumbersState {
                    panel: NumbersPanel,
                    design: design.clone(),
                    shown: s.clone(),
                    actions: Vec::new(),
                },
            );
        h.run();
        let said =
            |h: &Harness<'_, NumbersState>, text: &str| h.query_by_label_contains(text).is_some();
        // The spacing is the result's own: 0.5 µm in a preview, 0.25 µm at full quality.
        let spacing = if preview {
            "(δ2 = 0.5 µm)"
        } else {
            "(δ2 = 0.25 µm)"
        };
        assert_eq!(
            said(&h, &format!("Preview estimate {spacing}")),
            preview,
            "{quality:?}"
        );
        assert_eq!(
            said(&h, &format!("Full quality {spacing}")),
            !preview,
            "{quality:?}"
        );
        assert_eq!(h.query_by_label(&format!("≈ {loss}")).is_some(), preview);
        assert_eq!(h.query_by_label(&loss).is_some(), !preview);
        assert_eq!(h.query_by_label("≈ AUC").is_some(), preview);

        let mut v = harness(State {
            panel: ViewsPanel::default(),
            shown: Some(s.clone()),
            design: design.clone(),
            pinned: Some(Pinned::now(s.design.clone(), s.analysis.clone())),
            overlays: false,
            actions: Vec::new(),
        });
        v.state_mut().panel.set_tab(ViewTab::Compare);
        v.step();
        v.step();
        assert_eq!(
            v.query_by_label_contains("Preview estimate").is_some(),
            preview
        );
        assert_eq!(
            v.query_by_label_contains("Full quality").is_some(),
            !preview
        );
    }
}
