//! The studio's panels. Each is a self-contained struct; it reads the document and the shown
//! result through [`PanelCtx`] and changes things only by queueing [`DisplayAction`]s.

pub mod advice;
pub mod editor;
pub mod editor_emitters;
pub mod editor_rules;
pub mod mask_export;
pub mod mask_preview;
pub mod measured;
pub mod measured_restore;
pub mod numbers;
pub mod one_axis_sweep;
pub mod optics;
pub mod optimize;
pub mod quality;
pub mod rules_check;
pub mod tiling;
pub mod views;
pub mod written_check;

use std::sync::Arc;

use super::action::{DisplayAction, Tool};
use crate::core::analysis::analyze::Quality;
use crate::core::{Analysis, Design};

/// A result on screen: the analysis and the design it was computed for.
#[derive(Clone)]
pub struct Shown {
    /// Worker generation of the design it was computed for (older than the newest: stale).
    pub generation: u64,
    /// Fast preview or full quality.
    pub quality: Quality,
    /// The PSFs, MTFs and numbers the views and the Numbers panel draw.
    pub analysis: Arc<Analysis>,
    /// The design the analysis belongs to (it may lag behind the document while computing).
    pub design: Arc<Design>,
    /// The route its PSFs were computed on (View ▸ Compute PSFs on): the studies of this
    /// design (field, depth, the measured comparison) compute theirs on it too.
    pub route: Arc<udc_gpu::Route>,
}

/// The rasterised display over the pupil, for the tiling preview.
#[derive(Clone)]
pub struct DisplayPreview {
    /// Worker generation of the design it shows.
    pub generation: u64,
    /// Samples per side; the optical axis is at `side / 2`.
    pub side: usize,
    /// Amplitude transmittance, row-major.
    pub values: Arc<Vec<f32>>,
    /// Spacing between samples, in µm.
    pub sample_um: f64,
    /// Diameter of the lens pupil drawn over the preview, in µm.
    pub pupil_diameter_um: f64,
}

/// A design pinned for comparison (A), with its full-quality result.
#[derive(Clone)]
pub struct Pinned {
    /// The design as it was when pinned.
    pub design: Arc<Design>,
    /// Its full-quality analysis.
    pub analysis: Arc<Analysis>,
    /// Local time of day of the pin, `HH:MM`: A and B often share a design name.
    pub pinned_at: String,
}

impl Pinned {
    /// `design` and its full-quality `analysis`, pinned at the present time.
    pub fn now(design: Arc<Design>, analysis: Arc<Analysis>) -> Self {
        Pinned {
            design,
            analysis,
            pinned_at: chrono::Local::now().format("%H:%M").to_string(),
        }
    }
}

/// What a panel may look at, and where it sends what it wants done.
pub struct PanelCtx<'a> {
    /// The document's current design (read-only; change it with [`PanelCtx::edit`]).
    pub design: &'a Design,
    /// The newest result on screen, if any has arrived yet.
    pub shown: Option<&'a Shown>,
    /// The newest display preview for the tiling view, if any.
    pub display: Option<&'a DisplayPreview>,
    /// The design pinned as A for Compare, if any.
    pub pinned: Option<&'a Pinned>,
    /// Teaching overlays and hints on.
    pub overlays: bool,
    /// The design-rule rings on the opening editor on (View menu).
    pub design_rules: bool,
    /// Native file dialogs may open (off in headless tests).
    pub native_dialogs: bool,
    /// The editor's current tool (also set by shortcuts).
    pub tool: Tool,
    /// Where the panel queues what it wants done; carried out after the frame's UI.
    pub actions: &'a mut Vec<DisplayAction>,
}

impl PanelCtx<'_> {
    /// The route the design on screen was computed on (View ▸ Compute PSFs on), the CPU
    /// before its first analysis: a comparison, fit or optimization then computes where the
    /// pictures beside it were.
    pub fn shown_route(&self) -> std::sync::Arc<udc_gpu::Route> {
        self.shown.map_or_else(
            || std::sync::Arc::new(udc_gpu::Route::cpu()),
            |s| s.route.clone(),
        )
    }

    /// Pushes a committed edit of the design.
    pub fn edit(&mut self, design: Design) {
        if &design != self.design {
            self.actions.push(DisplayAction::Edit(Box::new(design)));
        }
    }
}
