//! The studio's panels. Each is a self-contained struct; it reads the document and the shown
//! result through [`PanelCtx`] and changes things only by pushing [`Command`]s.

pub mod editor;
pub mod mask_export;
pub mod numbers;
pub mod optics;
pub mod optimize;
pub mod tiling;
pub mod views;

use std::sync::Arc;

use crate::app::commands::{Command, Tool};
use crate::core::analyze::Quality;
use crate::core::{Analysis, Design};

/// A result on screen: the analysis and the design it was computed for.
#[derive(Clone)]
pub struct Shown {
    pub generation: u64,
    pub quality: Quality,
    pub analysis: Arc<Analysis>,
    pub design: Arc<Design>,
}

/// The rasterised display over the pupil, for the tiling preview.
#[derive(Clone)]
pub struct DisplayPreview {
    pub generation: u64,
    /// Samples per side; the optical axis is at `side / 2`.
    pub side: usize,
    /// Amplitude transmittance, row-major.
    pub values: Arc<Vec<f32>>,
    pub sample_um: f64,
    pub pupil_diameter_um: f64,
}

/// A design pinned for comparison (A), with its full-quality result.
#[derive(Clone)]
pub struct Pinned {
    pub design: Arc<Design>,
    pub analysis: Arc<Analysis>,
}

/// What a panel may look at, and where it sends what it wants done.
pub struct PanelCtx<'a> {
    pub design: &'a Design,
    pub shown: Option<&'a Shown>,
    pub display: Option<&'a DisplayPreview>,
    pub pinned: Option<&'a Pinned>,
    /// Teaching overlays and hints on.
    pub overlays: bool,
    /// The editor's current tool (also set by shortcuts).
    pub tool: Tool,
    pub commands: &'a mut Vec<Command>,
}

impl PanelCtx<'_> {
    /// Pushes a committed edit of the design.
    pub fn edit(&mut self, design: Design) {
        if &design != self.design {
            self.commands.push(Command::Edit(Box::new(design)));
        }
    }
}
