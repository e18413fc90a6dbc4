//! The Export-mask dialog's preview (one pixel's drawing and the statistics of the file to be
//! written), laid out on a background job: for a display-sized block the layout, its border
//! edit and the file estimate take a tenth of a second or more, which the UI thread must not
//! spend on every option it changes. The dialog keeps drawing the last preview until the new one
//! arrives.

use crate::app::job::{Answered, Job, JobError};
use crate::core::Progress;
use crate::core::design::Design;
use crate::core::mask::{BinaryGrid, MaskError, MaskStats};
use crate::io::mask::{ExportOptions, FileCounts, estimate, plan};

/// What the preview shows of one design under one set of options.
pub struct PreviewData {
    /// The region's pixels, orientations, areas and flattened polygons.
    pub stats: MaskStats,
    /// What the file would hold: polygons, vertices, references and its size.
    pub counts: FileCounts,
    /// One pixel's drawn cells (identity orientation).
    pub drawn: BinaryGrid,
    /// Its polygons in tile units (x right, y down, `[0, 1]²`).
    pub outlines: Vec<Vec<[f32; 2]>>,
    /// The tile's pitch, µm, to place the violations on the preview.
    pub pitch_um: f64,
}

/// What the dialog's background parts (the preview, the written-file check) read: the design
/// and the export's options.
#[derive(Debug, Clone, PartialEq)]
pub struct ExportKey {
    design: Design,
    options: ExportOptions,
}

impl ExportKey {
    /// Whether this is `design` under `options`.
    pub fn is_of(&self, design: &Design, options: &ExportOptions) -> bool {
        &self.design == design && &self.options == options
    }
}

/// Asks `answered` for `design` under `options`: unless its answer or its job in flight is for
/// them, a job named `name` runs `work` on copies (replacing, and so cancelling, the one in
/// flight) and wakes `ctx` when done. Returns whether an answer arrived.
pub fn ask<T: Send + 'static>(
    answered: &mut Answered<ExportKey, T>,
    ctx: &egui::Context,
    (design, options): (&Design, &ExportOptions),
    name: &'static str,
    work: impl FnOnce(&Design, &ExportOptions, &Progress) -> Result<T, JobError> + Send + 'static,
) -> bool {
    answered.update(
        |k| k.is_of(design, options),
        || ExportKey {
            design: design.clone(),
            options: options.clone(),
        },
        |key| {
            let (d, o) = (key.design.clone(), key.options.clone());
            let ctx = ctx.clone();
            Job::spawn(
                name,
                move || ctx.request_repaint(),
                move |p| work(&d, &o, p),
            )
        },
    )
}

/// A layout the options cannot make is an answer the dialog shows, not a failed job.
type Answer = Result<PreviewData, MaskError>;

/// The dialog's preview and the job computing the next one.
#[derive(Default)]
pub struct MaskPreview {
    /// The layout in flight, and the newest preview with what it is of.
    previews: Answered<ExportKey, Answer>,
}

/// Lays out `design` as `options` say and gathers what the preview draws.
pub fn compute(design: &Design, options: &ExportOptions) -> Result<PreviewData, MaskError> {
    let layout = plan(design, options)?;
    let unit = layout.pitch_nm as f32;
    let outlines = layout
        .base_polygons
        .iter()
        .map(|p| {
            p.points_nm
                .iter()
                .map(|q| [q[0] as f32 / unit, -q[1] as f32 / unit])
                .collect()
        })
        .collect();
    // Resolved: the derived top cell name's length is part of the size.
    let resolved = options.resolved(design).unwrap_or(options.clone());
    Ok(PreviewData {
        stats: layout.stats(),
        counts: estimate(&layout, &resolved),
        drawn: layout.drawn.clone(),
        outlines,
        pitch_um: design.opening.pitch_um,
    })
}

impl MaskPreview {
    /// Collects a finished preview and starts one when the design or the options changed.
    /// Returns the newly arrived preview's drawing, once, for the dialog's texture.
    pub fn update(
        &mut self,
        ctx: &egui::Context,
        design: &Design,
        options: &ExportOptions,
    ) -> Option<&BinaryGrid> {
        let arrived = ask(
            &mut self.previews,
            ctx,
            (design, options),
            "mask preview",
            |d, o, p| {
                p.check()?;
                Ok(compute(d, o))
            },
        );
        match self.previews.answer() {
            Some((_, Ok(Ok(data)))) if arrived => Some(&data.drawn),
            _ => None,
        }
    }

    /// The last preview (of the current options, or of earlier ones while the new one is laid
    /// out), `None` before the first arrives.
    pub fn latest(&self) -> Option<&Result<Answer, JobError>> {
        self.previews.answer().map(|(_, r)| r)
    }

    /// Whether the shown preview is for `design` under `options`.
    pub fn is_current(&self, design: &Design, options: &ExportOptions) -> bool {
        self.previews
            .answer_for(|k| k.is_of(design, options))
            .is_some()
    }

    /// Whether a preview is being laid out.
    pub fn is_computing(&self) -> bool {
        self.previews.is_running()
    }
}
