//! The Measured PSF panel's restoration: a real capture (a photo, a 16-bit PNG or TIFF, an EXR
//! or a linear `.npy`) restored with the loaded PSF set by Wiener deconvolution, the capture and
//! the restoration side by side, and the restoration saved as PNG or EXR. The same steps as
//! `udc-studio restore --psf SET --image CAPTURE`, on a background job with progress and Cancel.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use egui::{TextureHandle, TextureOptions, Ui};
use ndarray::Array2;

use crate::app::dialogs::{self, FileSpec};
use crate::app::job::{Job, JobError, Writes};
use crate::app::notice::Notice;
use crate::app::widgets::photo::color_image;
use crate::core::measured::PsfSet;
use crate::core::restore::{Method, Padding, THESIS_NSR, restore_capture};
use crate::jobs::display::{load_capture, negative_note};

/// The longest side of the pictures on screen (the restoration itself is full size).
const PREVIEW_SIDE_PX: usize = 768;
/// A linear capture is shown scaled so that this share of its samples clips.
const CLIPPED_SHARE: f64 = 0.005;

/// A capture and its restoration.
pub struct Restored {
    /// The capture's file.
    pub capture: PathBuf,
    /// The capture's planes on its `[0, 1]` scale.
    pub captured: Vec<Array2<f64>>,
    /// The restoration, plane by plane.
    pub restored: Vec<Array2<f64>>,
    /// What the reader and the restoration noticed.
    pub notes: Vec<String>,
    /// How long the restoration took, ms.
    pub elapsed_ms: f64,
    /// Both, scaled down and encoded for the screen: `[captured, restored]`.
    preview: [Vec<Array2<f64>>; 2],
}

/// Which file a dialog asks for.
#[derive(Clone, Copy)]
enum Asked {
    Capture,
    SaveRestored,
}

/// The restoration part of the panel: its settings, the job and the result on screen.
pub struct CaptureRestore {
    dialog: Option<(Asked, Job<Option<PathBuf>>)>,
    job: Option<Job<Restored>>,
    writes: Writes,
    /// Wiener's noise-to-signal ratio.
    pub nsr: f64,
    restored: Option<Restored>,
    textures: Vec<TextureHandle>,
    message: Option<Notice>,
}

impl Default for CaptureRestore {
    fn default() -> Self {
        CaptureRestore {
            dialog: None,
            job: None,
            writes: Writes::default(),
            nsr: THESIS_NSR,
            restored: None,
            textures: Vec::new(),
            message: None,
        }
    }
}

impl CaptureRestore {
    /// The last restoration, if any.
    pub fn restored(&self) -> Option<&Restored> {
        self.restored.as_ref()
    }

    /// The last message (an error says what went wrong).
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    /// Whether a restoration, a dialog or a write is in flight.
    pub fn is_busy(&self) -> bool {
        self.job.is_some() || self.dialog.is_some() || !self.writes.is_empty()
    }

    /// Restores the capture at `path` with `set` in the background.
    pub fn restore(&mut self, path: &Path, set: Arc<PsfSet>, ctx: &egui::Context) {
        let (path, wake, nsr) = (path.to_path_buf(), ctx.clone(), self.nsr);
        self.message = None;
        self.job = Some(Job::spawn(
            "capture restoration",
            move || wake.request_repaint(),
            move |p| restore_file(&path, &set, nsr, p),
        ));
    }

    /// Writes the restoration to `path`: EXR (linear, full precision) or an 8-bit PNG.
    pub fn save(&mut self, path: &Path, ctx: &egui::Context) {
        let Some(r) = &self.restored else { return };
        let (path, planes, wake) = (path.to_path_buf(), r.restored.clone(), ctx.clone());
        self.writes.spawn(
            move || wake.request_repaint(),
            move || -> Result<String, JobError> {
                let refs: Vec<&Array2<f64>> = planes.iter().collect();
                let exr = path
                    .extension()
                    .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
                let written = if exr {
                    crate::io::photo::write_photo_exr(&path, &refs)
                } else {
                    crate::io::photo::write_photo_png(&path, &refs)
                };
                written.map_err(|e| JobError::Failed(e.to_string()))?;
                Ok(format!("saved {}", path.display()))
            },
        );
    }

    /// Takes finished jobs' results.
    pub fn poll(&mut self, set: Option<&Arc<PsfSet>>, ctx: &egui::Context) {
        if let Some(n) = self.writes.poll() {
            self.message = Some(n);
        }
        if let Some((asked, j)) = &self.dialog
            && let Some(answer) = j.poll()
        {
            let asked = *asked;
            self.dialog = None;
            match (answer, asked, set) {
                (Ok(Some(path)), Asked::Capture, Some(set)) => {
                    self.restore(&path, set.clone(), ctx);
                }
                (Ok(Some(path)), Asked::SaveRestored, _) => self.save(&path, ctx),
                (Ok(_), ..) => {}
                (Err(e), ..) => self.message = Some(Notice::error(e.to_string())),
            }
        }
        let Some(j) = &self.job else { return };
        let Some(result) = j.poll() else { return };
        self.job = None;
        match result {
            Ok(r) => {
                self.textures = r
                    .preview
                    .iter()
                    .enumerate()
                    .map(|(i, planes)| {
                        let refs: Vec<&Array2<f64>> = planes.iter().collect();
                        ctx.load_texture(
                            format!("measured restore {i}"),
                            color_image(&refs, 1.0),
                            TextureOptions::LINEAR,
                        )
                    })
                    .collect();
                self.restored = Some(r);
            }
            Err(JobError::Cancelled) => self.message = Some(Notice::info("cancelled")),
            Err(e) => self.message = Some(Notice::error(format!("cannot restore: {e}"))),
        }
    }

    /// Draws the restoration controls and the result for `set` (none loaded: nothing).
    pub fn ui(&mut self, ui: &mut Ui, set: Option<&Arc<PsfSet>>, native_dialogs: bool) {
        let Some(set) = set else { return };
        ui.separator();
        ui.strong("Restore a real capture with this PSF");
        let idle = self.job.is_none() && self.dialog.is_none();
        ui.horizontal(|ui| {
            let open = ui
                .add_enabled(idle, egui::Button::new("Restore a capture…"))
                .on_hover_text(
                    "A photo taken through the prototype (16-bit PNG or TIFF, EXR, linear .npy or \
                     an 8-bit photo), deconvolved by Wiener with this set's PSFs",
                );
            if open.clicked() {
                self.ask(
                    ui.ctx(),
                    native_dialogs,
                    Asked::Capture,
                    FileSpec::open(
                        "Open a capture to restore",
                        (
                            "capture",
                            &["png", "tif", "tiff", "exr", "npy", "mat", "jpg", "jpeg"],
                        ),
                    ),
                );
            }
            ui.label("noise-to-signal");
            ui.add(
                egui::DragValue::new(&mut self.nsr)
                    .range(1e-6..=1.0)
                    .speed(1e-4)
                    .max_decimals(5),
            )
            .on_hover_text(
                "Wiener's noise-to-signal ratio: larger keeps the noise down and the detail soft \
                 (the thesis: 0.00371)",
            );
        });
        if let Some(j) = &self.job {
            ui.horizontal(|ui| {
                ui.add(
                    egui::ProgressBar::new(j.fraction())
                        .desired_width(160.0)
                        .text("restoring the capture…"),
                );
                if ui.button("Cancel").clicked() {
                    j.cancel();
                }
            });
        }
        crate::app::widgets::message_ui(ui, self.message.as_ref());
        let Some(r) = &self.restored else { return };
        let (rows, cols) = r.captured.first().map_or((0, 0), Array2::dim);
        ui.label(format!(
            "{} ({cols}×{rows} px) restored in {:.0} ms with the {} px PSF{}",
            r.capture.file_name().map_or_else(
                || r.capture.display().to_string(),
                |n| n.to_string_lossy().into_owned()
            ),
            r.elapsed_ms,
            set.side_px(),
            if set.channels.len() == 1 { "" } else { "s" },
        ));
        for n in &r.notes {
            ui.colored_label(ui.visuals().warn_fg_color, n);
        }
        let gap = ui.spacing().item_spacing.x;
        let side = ((ui.available_width() - gap - 8.0) / 2.0).clamp(96.0, 360.0);
        ui.horizontal(|ui| {
            for (t, caption) in self.textures.iter().zip(["captured", "restored"]) {
                let [w, h] = t.size();
                let s = side / w.max(h).max(1) as f32;
                ui.vertical(|ui| {
                    ui.label(caption);
                    ui.add(
                        egui::Image::new((t.id(), egui::vec2(w as f32 * s, h as f32 * s)))
                            .alt_text(format!("{caption} capture")),
                    );
                });
            }
        });
        ui.label(
            "Shown scaled to the capture's brightest samples and, for a linear capture, \
             display-encoded (γ 2.2); the restoration saved is linear.",
        );
        if ui
            .add_enabled(idle, egui::Button::new("Save the restoration…"))
            .on_hover_text("EXR keeps the linear values; PNG is 8-bit, clipped to [0, 1]")
            .clicked()
        {
            let stem = r
                .capture
                .file_stem()
                .map_or("capture".into(), |s| s.to_string_lossy().into_owned());
            self.ask(
                ui.ctx(),
                native_dialogs,
                Asked::SaveRestored,
                FileSpec::save(
                    "Save the restoration",
                    ("image", &["exr", "png"]),
                    format!("{stem}_restored.exr"),
                ),
            );
        }
    }

    fn ask(&mut self, ctx: &egui::Context, native_dialogs: bool, asked: Asked, spec: FileSpec) {
        if !native_dialogs {
            self.message = Some(Notice::error("file dialogs are disabled in this session"));
            return;
        }
        let wake = ctx.clone();
        self.dialog = Some((asked, dialogs::ask(spec, move || wake.request_repaint())));
    }
}

/// Reads the capture at `path` and restores it with `set` (Wiener at `nsr`, the 2× padding):
/// `restore --psf` without the denoiser, whose σ² a real capture does not tell.
fn restore_file(
    path: &Path,
    set: &PsfSet,
    nsr: f64,
    progress: &crate::core::Progress,
) -> Result<Restored, JobError> {
    let mut notes = Vec::new();
    let capture = load_capture(path, &mut notes).map_err(|e| JobError::Failed(format!("{e:#}")))?;
    let (kernels, negative) = set.restoration_kernels(capture.planes.len())?;
    notes.extend(negative_note(negative));
    let started = Instant::now();
    let psfs: Vec<&Array2<f64>> = kernels.iter().collect();
    let restored = restore_capture(
        capture.planes.clone(),
        &psfs,
        Method::Wiener { nsr },
        Padding::Double,
        None,
        progress,
    )?;
    let elapsed_ms = started.elapsed().as_secs_f64() * 1e3;
    let preview = [&capture.planes, &restored]
        .map(|planes| screen_planes(planes, &capture.planes, capture.display_encoded));
    Ok(Restored {
        capture: path.to_path_buf(),
        captured: capture.planes,
        restored,
        notes,
        elapsed_ms,
        preview,
    })
}

/// `planes` scaled down for the screen, divided by the level below which all but
/// [`CLIPPED_SHARE`] of `reference`'s samples lie and, unless already `display_encoded`,
/// raised to 1/2.2.
fn screen_planes(
    planes: &[Array2<f64>],
    reference: &[Array2<f64>],
    display_encoded: bool,
) -> Vec<Array2<f64>> {
    let mut all: Vec<f64> = reference.iter().flat_map(|p| p.iter().copied()).collect();
    let k = ((1.0 - CLIPPED_SHARE) * all.len() as f64) as usize;
    let top = if all.is_empty() {
        1.0
    } else {
        let k = k.min(all.len() - 1);
        *all.select_nth_unstable_by(k, f64::total_cmp).1
    };
    let white = if top > 0.0 { top } else { 1.0 };
    let small = crate::io::photo::fit_max_side(planes.to_vec(), PREVIEW_SIDE_PX);
    small
        .into_iter()
        .map(|p| {
            p.mapv(|v| {
                let v = (v / white).clamp(0.0, 1.0);
                if display_encoded {
                    v
                } else {
                    v.powf(1.0 / 2.2)
                }
            })
        })
        .collect()
}
