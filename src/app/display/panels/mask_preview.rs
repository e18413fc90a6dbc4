//! The Export-mask dialog's preview (one pixel's drawing and the statistics of the file to be
//! written), laid out on a background job: for a display-sized block the layout, its border
//! edit and the file estimate take a tenth of a second or more, which the UI thread must not
//! spend on every option it changes. The dialog keeps drawing the last preview until the new one
//! arrives.

use crate::app::job::{Job, JobError, Keyed};
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

/// What the preview was computed for.
#[derive(Debug, Clone, PartialEq)]
struct Key {
    design: Design,
    options: ExportOptions,
}

/// A layout the options cannot make is an answer the dialog shows, not a failed job.
type Answer = Result<PreviewData, MaskError>;

/// The dialog's preview and the job computing the next one.
#[derive(Default)]
pub struct MaskPreview {
    running: Keyed<Key, Answer>,
    done: Option<(Key, Result<Answer, JobError>)>,
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
        let mut arrived = false;
        if let Some((key, result)) = self.running.poll() {
            // A cancelled preview (replaced by a newer one) keeps the last one on screen.
            if !matches!(result, Err(JobError::Cancelled)) {
                self.done = Some((key, result));
                arrived = true;
            }
        }
        let is_now = |k: &Key| &k.design == design && &k.options == options;
        let answered = self.done.as_ref().is_some_and(|(k, _)| is_now(k));
        if !answered && !self.running.is_running_for(is_now) {
            let key = Key {
                design: design.clone(),
                options: options.clone(),
            };
            let (d, o) = (key.design.clone(), key.options.clone());
            let wake = {
                let ctx = ctx.clone();
                move || ctx.request_repaint()
            };
            let job = Job::spawn("mask preview", wake, move |p| {
                p.check()?;
                Ok::<_, JobError>(compute(&d, &o))
            });
            self.running.start(key, job);
        }
        match &self.done {
            Some((_, Ok(Ok(data)))) if arrived => Some(&data.drawn),
            _ => None,
        }
    }

    /// The last preview (of the current options, or of earlier ones while the new one is laid
    /// out), `None` before the first arrives.
    pub fn latest(&self) -> Option<&Result<Answer, JobError>> {
        self.done.as_ref().map(|(_, r)| r)
    }

    /// Whether the shown preview is for `design` under `options`.
    pub fn is_current(&self, design: &Design, options: &ExportOptions) -> bool {
        self.done
            .as_ref()
            .is_some_and(|(k, _)| &k.design == design && &k.options == options)
    }

    /// Whether a preview is being laid out.
    pub fn is_computing(&self) -> bool {
        self.running.is_running()
    }
}
