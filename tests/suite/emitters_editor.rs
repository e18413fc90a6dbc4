//! The editor's Emitters layer: painting R, G, B on closed cells is an undoable edit; painting
//! on an open cell is refused with a status message.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use egui_kittest::Harness;
use udc_studio::app::panels::PanelCtx;
use udc_studio::app::panels::editor::EditorPanel;
use udc_studio::app::panels::editor_emitters::EmitterBrush;
use udc_studio::app::{DisplayAction, Tool};
use udc_studio::core::design::{Design, Subpixel};

struct State {
    panel: EditorPanel,
    design: Design,
    actions: Vec<DisplayAction>,
}

fn harness() -> Harness<'static, State> {
    let mut panel = EditorPanel::default();
    panel.emitters.shown = true;
    panel.emitters.brush = Some(EmitterBrush::Paint(Subpixel::Red));
    let state = State {
        panel,
        design: Design::default_toled(),
        actions: Vec::new(),
    };
    let mut h = Harness::builder()
        .with_size(egui::vec2(480.0, 760.0))
        .build_ui_state(
            |ui, s: &mut State| {
                let mut ctx = PanelCtx {
                    design: &s.design,
                    shown: None,
                    display: None,
                    pinned: None,
                    overlays: false,
                    design_rules: false,
                    native_dialogs: false,
                    tool: Tool::Paint,
                    actions: &mut s.actions,
                };
                s.panel.ui(ui, &mut ctx);
            },
            state,
        );
    h.run();
    h
}

fn click(h: &mut Harness<'static, State>, r: usize, c: usize) {
    let p = h.state().panel.cell_center(r, c).expect("grid drawn");
    h.drag_at(p);
    h.run();
    h.drop_at(p);
    h.run();
}

#[test]
fn painting_an_emitter_on_a_closed_cell_is_an_edit() {
    let mut h = harness();
    // Column 2 is closed (the T-OLED slit is columns 8 to 12).
    click(&mut h, 3, 2);
    let edits: Vec<&Design> = h
        .state()
        .actions
        .iter()
        .filter_map(|c| match c {
            DisplayAction::Edit(d) => Some(d.as_ref()),
            _ => None,
        })
        .collect();
    assert_eq!(edits.len(), 1, "one edit per painted cell");
    let sp = edits[0].subpixels.as_ref().expect("an emitter layer");
    assert_eq!(sp.cells[3][2], Some(Subpixel::Red));
    assert_eq!(sp.counts(), [1, 0, 0]);
    // The editor leaves the opening alone.
    assert_eq!(edits[0].opening, h.state().design.opening);
}

#[test]
fn painting_on_an_open_cell_is_refused_with_a_message() {
    let mut h = harness();
    click(&mut h, 3, 10);
    assert!(
        !h.state()
            .actions
            .iter()
            .any(|c| matches!(c, DisplayAction::Edit(_))),
        "no edit"
    );
    let status = h.state().panel.emitters.status.clone().expect("a status");
    assert!(status.contains("open"), "{status}");
}
