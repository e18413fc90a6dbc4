//! The blur matrix of all directions (eq. 4.12) in the PSF view: `kernel_matrix_on` for one
//! channel (on the PSFs' backend) on a background thread with progress and Cancel, drawn as a log-scaled picture (rows = sensor
//! pixel, columns = direction), and "Save as CSV…" (a save dialog on a helper thread, the write
//! on another).

use crate::app::notice::Notice;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use egui::{TextureHandle, Ui};
use ndarray::Array2;

use super::{ChannelSet, PhaseAction, PhaseCtx, PhaseWorkspace, Quality};
use crate::app::dialogs::{FileSpec, ask};
use crate::app::history::Snapshot;
use crate::app::job::{Finished, Job, JobError, Keyed, Writes};
use crate::app::widgets::figure::{
    COLORBAR_WIDTH, ImageFrame, colour_bar_ui, image_panel_ui, panel_textures,
};
use crate::core::figure::Panel;
use crate::core::phase::figures::{KERNEL_DECADES, kernel_panel};
use crate::core::phase::{Chain, PhaseDesign, PhaseOptics, kernel_matrix_on};
use crate::io::IoError;

/// The channel names of the picker (the channel sets all have R, G, B in this order).
const CHANNEL_NAMES: [&str; 3] = ["R", "G", "B"];

/// A blur matrix on screen, with what it was computed for.
pub struct ShownKernels {
    /// The design it was computed for.
    pub design: PhaseDesign,
    /// Preview or thesis sampling.
    pub quality: Quality,
    /// The optical chain it was computed for.
    pub optics: PhaseOptics,
    /// The channel set its channel was taken from.
    pub channels: ChannelSet,
    /// Index of the channel (0 R, 1 G, 2 B).
    pub channel: usize,
    /// Name of the channel ("R", "G" or "B").
    pub channel_name: String,
    /// `k[[i, j]]`: energy on sensor pixel `i` from the direction imaged on pixel `j`.
    pub k: Arc<Array2<f64>>,
    /// How long the computation took, in seconds.
    pub elapsed_s: f64,
    /// K as a figure (`core::phase::figures::kernel_panel`) and its image's texture.
    pub panel: Arc<Panel>,
    textures: Vec<TextureHandle>,
}

/// A save dialog's answer: the chosen path, or `None` when cancelled.
type FileDialog = Job<Option<PathBuf>>;

/// What a blur matrix was started for.
struct KernelKey {
    design: PhaseDesign,
    quality: Quality,
    optics: PhaseOptics,
    channels: ChannelSet,
    channel: usize,
    channel_name: String,
}

pub(super) struct KernelState {
    native_dialogs: bool,
    channel: usize,
    job: Keyed<KernelKey, Array2<f64>>,
    shown: Option<ShownKernels>,
    /// The matrix being saved and the dialog asking where.
    dialog: Option<(Arc<Array2<f64>>, FileDialog)>,
    writes: Writes,
    message: Option<Notice>,
}

impl KernelState {
    pub fn new(native_dialogs: bool) -> Self {
        KernelState {
            native_dialogs,
            channel: 0,
            job: Keyed::idle(),
            shown: None,
            dialog: None,
            writes: Writes::default(),
            message: None,
        }
    }
}

/// Writes the blur matrix as CSV; the message says what was saved.
///
/// # Errors
/// The writer's error, naming the file.
pub fn write_kernels_csv(k: &Array2<f64>, path: &Path) -> Result<String, IoError> {
    crate::io::phase::export::write_kernels_csv(k, path)?;
    let (rows, cols) = k.dim();
    Ok(format!(
        "saved {}: {rows} rows (sensor pixels) × {cols} columns (directions)",
        path.display()
    ))
}

fn optics_label(o: PhaseOptics) -> &'static str {
    match o {
        PhaseOptics::SingleMask => "single mask",
        _ => "double MLA",
    }
}

impl PhaseWorkspace {
    /// The blur matrix on screen, if any.
    pub fn kernels(&self) -> Option<&ShownKernels> {
        self.kernels.shown.as_ref()
    }

    /// Whether the blur matrix is being computed.
    pub fn is_computing_kernels(&self) -> bool {
        self.kernels.job.is_running()
    }

    /// True while a blur-matrix CSV is being asked for or written.
    pub fn is_saving_kernels(&self) -> bool {
        self.kernels.dialog.is_some() || !self.kernels.writes.is_empty()
    }

    /// The latest message of the blur matrix or its CSV, and whether it is an error.
    pub fn kernels_message(&self) -> Option<&Notice> {
        self.kernels.message.as_ref()
    }

    /// The channel the blur matrix is computed for (0 R, 1 G, 2 B).
    pub fn kernel_channel(&self) -> usize {
        self.kernels.channel
    }

    /// Chooses the channel of the next blur matrix (0 R, 1 G, 2 B; larger values mean B).
    pub fn set_kernel_channel(&mut self, channel: usize) {
        self.kernels.channel = channel.min(CHANNEL_NAMES.len() - 1);
    }

    /// Whether the shown matrix is of another design, optics or channel set than the current.
    pub fn kernels_are_stale(&self) -> bool {
        self.kernels.shown.as_ref().is_some_and(|s| {
            !s.design.same(self.history.current())
                || s.optics != self.optics()
                || s.channels != self.channels
        })
    }

    /// Computes the blur matrix of the chosen channel for the current design, optics and
    /// quality, on a background thread.
    pub fn compute_kernels(&mut self, ctx: &egui::Context) {
        if self.kernels.job.is_running() {
            return;
        }
        if let Err(e) = self.history.current().validate() {
            self.kernels.message = Some(Notice::error(format!(
                "cannot compute the blur matrix: {e}"
            )));
            return;
        }
        let channels = match self.channel_list(self.channels) {
            Ok(c) => c,
            Err(e) => {
                self.kernels.message =
                    Some(Notice::error(format!("cannot make the channels: {e}")));
                return;
            }
        };
        let index = self.kernels.channel.min(channels.len().saturating_sub(1));
        let Some(channel) = channels.into_iter().nth(index) else {
            self.kernels.message = Some(Notice::error("the channel set is empty"));
            return;
        };
        let design = self.history.current().clone();
        let quality = self.quality;
        let optics = self.optics();
        let (d, wake) = (design.clone(), ctx.clone());
        let channel_name = channel.name.clone();
        // On the PSFs' backend (View ▸ Compute PSFs on): a λ0 plan's propagations on the GPU.
        let relay = self.relay();
        let job = Job::spawn(
            "blur-matrix job",
            move || wake.request_repaint(),
            move |p| {
                let sampling = crate::core::phase::PhaseSampling::for_quality(quality);
                let chain = Chain::new(&d, &sampling)?.with_relay_if(relay.as_ref());
                kernel_matrix_on(&chain, &channel, optics, p)
            },
        );
        self.kernels.message = None;
        let key = KernelKey {
            design,
            quality,
            optics,
            channels: self.channels,
            channel: index,
            channel_name,
        };
        self.kernels.job.start(key, job);
    }

    /// Stops the blur matrix; the last result stays.
    pub fn cancel_kernels(&mut self) {
        if self.kernels.job.is_running() {
            self.kernels.job.stop();
            self.kernels.message = Some(Notice::info("blur matrix cancelled"));
        }
    }

    /// Writes the shown blur matrix to `path` as CSV on a background thread (no dialog).
    pub fn save_kernels_to(&mut self, path: PathBuf, ctx: &egui::Context) {
        match &self.kernels.shown {
            Some(s) => {
                let k = s.k.clone();
                self.start_kernel_write(k, path, ctx);
            }
            None => self.kernels.message = Some(Notice::error("no blur matrix to save yet")),
        }
    }

    fn start_kernel_write(&mut self, k: Arc<Array2<f64>>, path: PathBuf, ctx: &egui::Context) {
        let wake = ctx.clone();
        self.kernels.message = Some(Notice::info(format!("writing {}…", path.display())));
        self.kernels.writes.spawn(
            move || wake.request_repaint(),
            move || write_kernels_csv(&k, &path),
        );
    }

    pub(super) fn ask_kernel_file(&mut self, ctx: &egui::Context) {
        if !self.kernels.native_dialogs {
            self.kernels.message = Some(Notice::error("file dialogs are disabled in this session"));
            return;
        }
        let Some(s) = &self.kernels.shown else {
            return;
        };
        if self.kernels.dialog.is_some() {
            return;
        }
        let name = format!("blur-matrix-{}.csv", s.channel_name);
        let wake = ctx.clone();
        let spec = FileSpec::save(
            "Save the blur matrix",
            ("Blur matrix (CSV)", &["csv"]),
            name,
        );
        let task = ask(spec, move || wake.request_repaint());
        self.kernels.dialog = Some((s.k.clone(), task));
    }

    /// Takes a finished blur matrix, an answered dialog and finished writes.
    pub(super) fn poll_kernels(&mut self, ctx: &egui::Context) {
        if let Some(answer) = self.kernels.dialog.as_ref().and_then(|d| d.1.poll())
            && let Some((k, _)) = self.kernels.dialog.take()
        {
            match answer {
                Ok(Some(path)) => self.start_kernel_write(k, path, ctx),
                Ok(None) => {}
                Err(e) => self.kernels.message = Some(Notice::error(e.to_string())),
            }
        }
        if let Some(report) = self.kernels.writes.poll() {
            self.kernels.message = Some(report);
        }
        let Some(Finished {
            key,
            result,
            elapsed,
        }) = self.kernels.job.finished()
        else {
            return;
        };
        match result {
            Ok(k) => {
                let elapsed_s = elapsed.as_secs_f64();
                let k = Arc::new(k);
                let panel = Arc::new(kernel_panel(k.clone(), &key.channel_name));
                let textures = panel_textures(ctx, "phase-kernels", &panel);
                self.kernels.message = Some(Notice::info(format!(
                    "blur matrix computed in {elapsed_s:.1} s"
                )));
                self.kernels.shown = Some(ShownKernels {
                    design: key.design,
                    quality: key.quality,
                    optics: key.optics,
                    channels: key.channels,
                    channel: key.channel,
                    channel_name: key.channel_name,
                    k,
                    elapsed_s,
                    panel,
                    textures,
                });
            }
            Err(JobError::Cancelled) => {}
            Err(e) => self.kernels.message = Some(Notice::error(e.to_string())),
        }
    }
}

/// The blur-matrix section of the PSF view.
pub(super) fn kernels_ui(ui: &mut Ui, ctx: &mut PhaseCtx<'_>) {
    ui.add_space(8.0);
    ui.separator();
    let p = ctx.design.camera.pixels;
    let valid = ctx.design.validate().is_ok();
    let running = ctx.kernels.job.is_running();
    ui.horizontal_wrapped(|ui| {
        ui.strong("Blur matrix K (eq. 4.12)");
        ui.label("channel");
        let mut channel = ctx.kernels.channel;
        for (i, name) in CHANNEL_NAMES.iter().enumerate() {
            ui.add_enabled_ui(!running, |ui| {
                ui.selectable_value(&mut channel, i, *name);
            });
        }
        if channel != ctx.kernels.channel {
            ctx.queue(PhaseAction::KernelChannel(channel));
        }
        if ui
            .add_enabled(
                valid && !running,
                egui::Button::new(format!("Blur matrix (all {p} directions)…")),
            )
            .on_hover_text(
                "One propagation per direction and wavelength at the chosen quality: \
                     about 10 s per peak channel at preview sampling, more at full quality",
            )
            .on_disabled_hover_text("Fix the design first, or wait for the running matrix")
            .clicked()
        {
            ctx.queue(PhaseAction::ComputeKernels);
        }
        let can_save = ctx.kernels.shown.is_some() && ctx.kernels.dialog.is_none();
        if ui
            .add_enabled(can_save, egui::Button::new("Save as CSV…"))
            .on_hover_text("One line per sensor pixel, one column per direction")
            .clicked()
        {
            ctx.queue(PhaseAction::AskKernelFile);
        }
    });
    let mut cancel = false;
    if let Some((key, job)) = ctx.kernels.job.current() {
        ui.horizontal(|ui| {
            ui.spinner();
            ui.label(format!(
                "blur matrix of {} over {} directions…",
                key.channel_name, key.design.camera.pixels
            ));
            cancel = ui.button("Cancel").clicked();
        });
        ui.add(egui::ProgressBar::new(job.fraction()).show_percentage());
    }
    if cancel {
        ctx.queue(PhaseAction::CancelKernels);
    }
    crate::app::widgets::message_ui(ui, ctx.kernels.message.as_ref());
    let stale = ctx.kernels_stale;
    let Some(s) = &ctx.kernels.shown else {
        return;
    };
    if stale {
        ui.colored_label(
            ui.visuals().warn_fg_color,
            "Stale: the design, optics or channels changed since this matrix was computed.",
        );
    }
    let (rows, cols) = s.k.dim();
    ui.label(format!(
        "{} channel, {}, {}: {rows} × {cols}, computed in {:.1} s. Log scale over {} \
             decades below the largest entry.",
        s.channel_name,
        s.quality.label(),
        optics_label(s.optics),
        s.elapsed_s,
        KERNEL_DECADES
    ));
    let side = (ui.available_width() - COLORBAR_WIDTH - 70.0).clamp(160.0, 560.0);
    let textures: Vec<egui::TextureId> = s.textures.iter().map(TextureHandle::id).collect();
    ui.horizontal(|ui| {
        let frame = ImageFrame {
            size: egui::vec2(side, side),
            link: None,
            view_half: None,
        };
        image_panel_ui(ui, "phase-kernels", &s.panel, &textures, frame);
        if let Some(img) = s.panel.images.first() {
            colour_bar_ui(ui, side, img);
        }
    });
}
