//! Every workspace at the window sizes people use (a 1024×700 laptop, 1366×768, 1920×1080):
//! the side panels leave the centre at least 40 % of the width, nothing is cut off the window,
//! and a pixel snapshot of each state is kept in `tests/snapshots/layout-*.png` (regenerate with
//! `tests/snapshots/make.sh`, i.e. `UPDATE_SNAPSHOTS=1`). Skipped pictures only where no renderer
//! exists (CI installs lavapipe).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::Duration;

use crate::common::Reach;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use udc_studio::app::{StudioApp, WorkspaceId};

const SIZES: [(f32, f32); 3] = [(1024.0, 700.0), (1366.0, 768.0), (1920.0, 1080.0)];

fn harness(dir: &std::path::Path, size: (f32, f32)) -> Harness<'static, StudioApp> {
    let dirs = udc_studio::app::AppDirs::at(dir);
    Harness::builder()
        .with_size(egui::vec2(size.0, size.1))
        .with_max_steps(10_000)
        .wgpu()
        .build_eframe(move |cc| {
            StudioApp::new(
                &cc.egui_ctx,
                udc_studio::app::StudioOptions {
                    dirs,
                    design_path: None,
                    native_dialogs: false,
                    autosave_every: Duration::from_secs(3600),
                    gpu: None,
                },
            )
        })
}

fn up_to_date(app: &StudioApp, ws: WorkspaceId) -> bool {
    match ws {
        WorkspaceId::Display => app.display().is_up_to_date(),
        WorkspaceId::Phase => app.phase().is_up_to_date(),
        WorkspaceId::Sensor => app.sensor().is_up_to_date(),
        WorkspaceId::Sweep => app.sweep().is_idle(),
    }
}

/// The numbers' heading (or tab) and the centre's first tab, per workspace.
fn landmarks(ws: WorkspaceId) -> (&'static str, &'static str) {
    match ws {
        WorkspaceId::Display => ("Numbers", "PSF"),
        WorkspaceId::Phase => ("Numbers", "PSF and MTF"),
        WorkspaceId::Sensor => ("Numbers", "Scene and maps"),
        // No numbers panel: the table is the centre.
        WorkspaceId::Sweep => ("Sweep results", "Filter"),
    }
}

fn check(ws: WorkspaceId, name: &str) {
    for size in SIZES {
        let dir = tempfile::tempdir().unwrap();
        let mut h = harness(dir.path(), size);
        h.state_mut().set_workspace(ws);
        crate::common::step_until(&mut h, name, |app| up_to_date(app, ws));
        for _ in 0..4 {
            h.step();
        }
        let (right_heading, centre_widget) = landmarks(ws);
        let right = h.get_by_label(right_heading).rect();
        let centre = h.get_by_label(centre_widget).rect();
        // From the centre's first tab to the right panel's heading, or to the window's edge
        // when the numbers are a tab of the left panel (narrow windows).
        let right_edge = if right.left() > centre.left() {
            right.left()
        } else {
            size.0
        };
        let centre_width = right_edge - centre.left();
        assert!(
            centre_width >= 0.4 * size.0,
            "{name} at {}×{}: the centre is {centre_width:.0} px wide",
            size.0,
            size.1
        );
        assert!(
            right.right() <= size.0 && centre.left() >= 0.0,
            "{name} at {}×{}: a panel is cut off",
            size.0,
            size.1
        );
        let options = egui_kittest::SnapshotOptions::default()
            // Computed timings ("in 175 ms") differ from run to run; the layout may not.
            .max_failed_pixels(600);
        let snapshot = format!("layout-{name}-{}x{}", size.0, size.1);
        match h.try_snapshot_options(&snapshot, &options) {
            Ok(()) => {}
            Err(egui_kittest::SnapshotError::RenderError { err }) => {
                eprintln!("no renderer here ({err}); {snapshot} skipped")
            }
            Err(e) => panic!("{e}"),
        }
    }
}

#[test]
fn display_workspace_fits_every_window() {
    check(WorkspaceId::Display, "display");
}

#[test]
fn phase_workspace_fits_every_window() {
    check(WorkspaceId::Phase, "phase");
}

#[test]
fn sensor_workspace_fits_every_window() {
    check(WorkspaceId::Sensor, "sensor");
}
