//! The Measured PSF panel: a prototype's PSF set (as `psf import` writes it) beside the design
//! on screen. It compares them (the residual, the correlation, both MTFs and their AUC, with the
//! profile and MTF figures), fits the display to the measurement (pitch, open fraction, turn and
//! defocus, each with its uncertainty) and applies the fitted pitch and opening as one undoable
//! edit, and restores real captures with the set ([`super::measured_restore`]). Reading,
//! comparing, fitting and restoring run as jobs with progress and Cancel.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use egui::Ui;

use super::PanelCtx;
use super::measured_restore::CaptureRestore;
use crate::app::dialogs::{self, FileSpec};
use crate::app::job::{Job, JobError};
use crate::app::notice::Notice;
use crate::app::widgets::figure::{
    FigureCache, ImageFrame, PlotFrame, image_panel_ui, panel_ui_in,
};
use crate::core::Design;
use crate::core::figure::Panel;
use crate::core::measured::compare::{ComparedChannel, compare_set};
use crate::core::measured::figures::{
    FLOOR_DECADES, Side, mtf_panel, profile_panel, psf_panel, residual_panel,
};
use crate::core::measured::fit::{Estimate, FitOptions, FitResult, fit};
use crate::core::measured::{PsfSet, PsfSource};
use crate::io::measured::{SetDefaults, read_psf_set};
use udc_gpu::Route;

/// A loaded set and the file it came from.
pub struct Loaded {
    /// The set's file.
    pub path: PathBuf,
    /// The PSFs.
    pub set: Arc<PsfSet>,
}

/// What runs in the background: one job at a time.
enum Running {
    Dialog(Job<Option<PathBuf>>),
    Load(Job<Loaded>),
    Compare(Job<Vec<ComparedChannel>>),
    Fit(Job<FitResult>),
}

impl Running {
    fn fraction_and_label(&self) -> (f32, &'static str) {
        match self {
            Running::Dialog(_) => (0.0, "choosing a file…"),
            Running::Load(j) => (j.fraction(), "reading the set…"),
            Running::Compare(j) => (j.fraction(), "simulating the design at the set's pitch…"),
            Running::Fit(j) => (j.fraction(), "fitting the display…"),
        }
    }

    fn cancel(&self) {
        match self {
            Running::Dialog(_) => {}
            Running::Load(j) => j.cancel(),
            Running::Compare(j) => j.cancel(),
            Running::Fit(j) => j.cancel(),
        }
    }
}

/// The panel's state.
pub struct MeasuredPanel {
    running: Option<Running>,
    loaded: Option<Loaded>,
    /// The camera's pixel pitch for a set without its sidecar, µm.
    pub pixel_um: f64,
    compared: Option<Arc<Vec<ComparedChannel>>>,
    /// Each compared channel's MTF and profile figures, built once when the comparison arrives.
    figures: Vec<(Panel, Panel)>,
    fitted: Option<FitResult>,
    /// The channel whose figures are shown.
    channel: usize,
    /// The pictures of both PSFs and the residual, per comparison (its count) and channel.
    pictures: FigureCache<(usize, Picture), u64>,
    /// Comparisons arrived so far: the pictures' key.
    comparisons: u64,
    /// Restoring real captures with the loaded set.
    pub restore: CaptureRestore,
    message: Option<Notice>,
}

/// The pictures of a comparison, in the order they are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Picture {
    Psf(Side),
    Residual,
}

impl Default for MeasuredPanel {
    fn default() -> Self {
        MeasuredPanel {
            running: None,
            loaded: None,
            pixel_um: 2.0,
            compared: None,
            figures: Vec::new(),
            fitted: None,
            channel: 0,
            pictures: FigureCache::default(),
            comparisons: 0,
            restore: CaptureRestore::default(),
            message: None,
        }
    }
}

impl MeasuredPanel {
    /// The loaded set, if any.
    pub fn loaded(&self) -> Option<&Loaded> {
        self.loaded.as_ref()
    }

    /// The last comparison, if any.
    pub fn compared(&self) -> Option<&[ComparedChannel]> {
        self.compared.as_deref().map(Vec::as_slice)
    }

    /// The last fit, if any.
    pub fn fitted(&self) -> Option<&FitResult> {
        self.fitted.as_ref()
    }

    /// The last message (an error says what went wrong).
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    /// Whether a job runs (a restoration included).
    pub fn is_busy(&self) -> bool {
        self.running.is_some() || self.restore.is_busy()
    }

    /// Reads the set at `path` in the background (the sidecar's pixel pitch, else the panel's).
    pub fn open(&mut self, path: &Path, ctx: &egui::Context) {
        let path = path.to_path_buf();
        let pixel_um = self.pixel_um;
        let wake = ctx.clone();
        self.running = Some(Running::Load(Job::spawn(
            "PSF set reader",
            move || wake.request_repaint(),
            move |_| {
                let set = read_psf_set(
                    &path,
                    &SetDefaults {
                        pixel_um: None,
                        wavelength_nm: None,
                    },
                )
                .or_else(|first| {
                    // Without a sidecar the pitch is the panel's; with one, its error stands.
                    if path.with_extension("json").exists() {
                        Err(first)
                    } else {
                        read_psf_set(
                            &path,
                            &SetDefaults {
                                pixel_um: Some(pixel_um),
                                wavelength_nm: None,
                            },
                        )
                    }
                })?;
                Ok::<_, JobError>(Loaded {
                    path,
                    set: Arc::new(set),
                })
            },
        )));
    }

    /// Compares the loaded set with `design` in the background, its PSFs computed on `route`.
    pub fn compare(&mut self, design: &Design, route: Arc<Route>, ctx: &egui::Context) {
        let Some(loaded) = &self.loaded else { return };
        let (design, set, wake) = (design.clone(), loaded.set.clone(), ctx.clone());
        self.running = Some(Running::Compare(Job::spawn(
            "PSF comparison",
            move || wake.request_repaint(),
            move |p| compare_set(&design, &set, route.as_ref(), p),
        )));
    }

    /// Fits the display to the loaded set, starting from `design`, in the background, its fine
    /// intensities transformed on `route`.
    pub fn fit(&mut self, design: &Design, route: Arc<Route>, ctx: &egui::Context) {
        let Some(loaded) = &self.loaded else { return };
        let (design, set, wake) = (design.clone(), loaded.set.clone(), ctx.clone());
        self.running = Some(Running::Fit(Job::spawn(
            "display fit",
            move || wake.request_repaint(),
            move |p| fit(&design, &set, &FitOptions::default(), route.as_ref(), p),
        )));
    }

    /// Cancels the running job.
    pub fn cancel(&mut self) {
        if let Some(r) = &self.running {
            r.cancel();
        }
    }

    /// Takes a finished job's result.
    pub fn poll(&mut self, ctx: &egui::Context) {
        self.restore.poll(self.loaded.as_ref().map(|l| &l.set), ctx);
        let Some(running) = &self.running else { return };
        match running {
            Running::Dialog(j) => match j.poll() {
                None => {}
                Some(answer) => {
                    self.running = None;
                    match answer {
                        Ok(Some(path)) => self.open(&path, ctx),
                        Ok(None) => {}
                        Err(e) => self.message = Some(Notice::error(e.to_string())),
                    }
                }
            },
            Running::Load(j) => {
                if let Some(r) = j.poll() {
                    self.running = None;
                    match r {
                        Ok(loaded) => {
                            self.message =
                                Some(Notice::info(format!("read {}", loaded.path.display())));
                            self.loaded = Some(loaded);
                            self.compared = None;
                            self.figures.clear();
                            self.fitted = None;
                            self.channel = 0;
                        }
                        Err(e) => self.message = Some(failed("cannot read the set", &e)),
                    }
                }
            }
            Running::Compare(j) => {
                if let Some(r) = j.poll() {
                    self.running = None;
                    match r {
                        Ok(c) => {
                            let pixel_um = self.loaded.as_ref().map_or(1.0, |l| l.set.pixel_um);
                            self.figures = c
                                .iter()
                                .map(|c| {
                                    (
                                        mtf_panel(&c.comparison, &c.name),
                                        profile_panel(&c.comparison, pixel_um, &c.name),
                                    )
                                })
                                .collect();
                            self.compared = Some(Arc::new(c));
                            self.comparisons += 1;
                            self.message = None;
                        }
                        Err(e) => self.message = Some(failed("cannot compare", &e)),
                    }
                }
            }
            Running::Fit(j) => {
                if let Some(r) = j.poll() {
                    self.running = None;
                    match r {
                        Ok(f) => {
                            self.message = Some(Notice::info(format!(
                                "fitted in {} evaluations ({})",
                                f.evaluations,
                                if f.converged {
                                    "converged"
                                } else {
                                    "not converged: read the uncertainties with care"
                                }
                            )));
                            self.fitted = Some(f);
                        }
                        Err(e) => self.message = Some(failed("cannot fit", &e)),
                    }
                }
            }
        }
    }

    /// Draws the panel.
    pub fn ui(&mut self, ui: &mut Ui, pctx: &mut PanelCtx) {
        ui.heading("Measured PSF");
        ui.label(
            "A prototype's PSF, imported with `udc-studio psf import` (a .npy set with its \
             .json sidecar), beside the design on screen.",
        );
        let idle = self.running.is_none();
        ui.horizontal(|ui| {
            if ui
                .add_enabled(idle, egui::Button::new("Open PSF set…"))
                .on_hover_text(
                    "A .npy PSF set; a file without its .json sidecar takes the pixel pitch below",
                )
                .clicked()
            {
                if !pctx.native_dialogs {
                    self.message = Some(Notice::error("file dialogs are disabled in this session"));
                    return;
                }
                let wake = ui.ctx().clone();
                self.running = Some(Running::Dialog(dialogs::ask(
                    FileSpec::open("Open a measured PSF set", ("PSF set", &["npy"])),
                    move || wake.request_repaint(),
                )));
            }
            ui.label("pixel");
            let range = crate::core::measured::PIXEL_UM_RANGE;
            let r = ui.add(
                egui::DragValue::new(&mut self.pixel_um)
                    .range(*range.start()..=*range.end())
                    .speed(0.01)
                    .suffix(" µm"),
            );
            r.on_hover_text("The camera's pixel pitch for a set without its sidecar");
        });
        if let Some(loaded) = &self.loaded {
            let set = &loaded.set;
            let names: Vec<String> = set
                .channels
                .iter()
                .map(|c| match c.wavelength_nm {
                    Some(w) => format!("{} ({w} nm)", c.name),
                    None => c.name.clone(),
                })
                .collect();
            ui.label(format!(
                "{}: {}, {} px at {} µm, {}",
                loaded.path.file_name().map_or_else(
                    || loaded.path.display().to_string(),
                    |n| n.to_string_lossy().into_owned()
                ),
                names.join(", "),
                set.side_px(),
                set.pixel_um,
                match set.source {
                    PsfSource::Measured => "measured",
                    PsfSource::Simulated => "simulated",
                }
            ));
            ui.horizontal(|ui| {
                if ui
                    .add_enabled(idle, egui::Button::new("Compare with the design"))
                    .on_hover_text("The design simulated at the set's pixel pitch, each channel aligned to a sub-pixel")
                    .clicked()
                {
                    self.compare(pctx.design, pctx.shown_route(), ui.ctx());
                }
                if ui
                    .add_enabled(idle, egui::Button::new("Fit the display"))
                    .on_hover_text(
                        "Pitch, open fraction, turn and defocus fitted by least squares, \
                         starting from the design on screen (10–25 s)",
                    )
                    .clicked()
                {
                    self.fit(pctx.design, pctx.shown_route(), ui.ctx());
                }
            });
        }
        if let Some(r) = &self.running {
            let (fraction, label) = r.fraction_and_label();
            ui.horizontal(|ui| {
                ui.add(
                    egui::ProgressBar::new(fraction)
                        .desired_width(160.0)
                        .text(label),
                );
                if ui.button("Cancel").clicked() {
                    r.cancel();
                }
            });
        }
        crate::app::widgets::message_ui(ui, self.message.as_ref());
        self.fit_ui(ui, pctx);
        self.compare_ui(ui);
        self.restore.ui(
            ui,
            self.loaded.as_ref().map(|l| &l.set),
            pctx.native_dialogs,
        );
    }

    fn fit_ui(&mut self, ui: &mut Ui, pctx: &mut PanelCtx) {
        let Some(f) = &self.fitted else { return };
        ui.separator();
        ui.strong("Fitted display");
        let pm = |e: Estimate, digits: usize, unit: &str| {
            format!("{:.*} ± {:.*}{unit}", digits, e.value, digits, e.sigma)
        };
        egui::Grid::new("fit table").striped(true).show(ui, |ui| {
            ui.label("");
            ui.label("fitted");
            ui.label("design");
            ui.end_row();
            ui.label("pitch");
            ui.label(pm(f.pitch_um, 2, " µm"));
            ui.label(format!("{:.2} µm", f.start_pitch_um));
            ui.end_row();
            ui.label("open fraction");
            ui.label(pm(f.open_fraction, 4, ""));
            ui.label(format!("{:.4}", f.start_open_fraction));
            ui.end_row();
            ui.label("edges moved");
            ui.label(pm(f.edge_bias_um, 3, " µm"));
            ui.label("0 µm");
            ui.end_row();
            ui.label("turn");
            ui.label(pm(f.rotation_deg, 3, "°"));
            ui.label("0°");
            ui.end_row();
            ui.label("defocus");
            ui.label(pm(f.defocus_um, 1, " µm"));
            ui.label("0 µm");
            ui.end_row();
            ui.label("residual");
            ui.label(format!("{:.2} %", 100.0 * f.residual));
            ui.label(format!("{:.2} %", 100.0 * f.residual_start));
            ui.end_row();
        });
        ui.label(
            "σ: one standard deviation from the fit's curvature; what the model lacks (stray \
             light, a second defect) makes the errors larger.",
        )
        .on_hover_text("Measuring a prototype, in the book, says how the fit works");
        if ui
            .button("Apply the fitted pitch and opening")
            .on_hover_text("Replaces the design's pitch and opening (one undoable edit); the turn and defocus belong to the setup, not the design")
            .clicked()
        {
            let mut d = pctx.design.clone();
            d.opening = f.design.opening.clone();
            d.tiling.origin_offset_cells = f.design.tiling.origin_offset_cells;
            d.subpixels = None;
            pctx.edit(d);
        }
    }

    fn compare_ui(&mut self, ui: &mut Ui) {
        let Some(compared) = self.compared.clone() else {
            return;
        };
        ui.separator();
        ui.strong("Measured against the design");
        egui::Grid::new("compare table")
            .striped(true)
            .show(ui, |ui| {
                // Four narrow columns: the table fits a 1024-point window's left panel.
                for (h, hover) in [
                    (
                        "channel",
                        "The measured channel (the design channel it was compared with)",
                    ),
                    (
                        "residual",
                        "The residual's energy as a share of the measured PSF's",
                    ),
                    ("corr.", "Pearson correlation of the two PSFs"),
                    (
                        "AUC meas. / design",
                        "Area under the radially-minimum MTF, measured / design",
                    ),
                ] {
                    ui.label(h).on_hover_text(hover);
                }
                ui.end_row();
                for c in compared.iter() {
                    let k = &c.comparison;
                    ui.label(format!("{} ({})", c.name, c.design_channel));
                    ui.label(format!("{:.2} %", 100.0 * k.residual_energy_share));
                    ui.label(format!("{:.4}", k.correlation));
                    ui.label(format!(
                        "{:.4} / {:.4}",
                        k.mtf_measured.auc_radial_min, k.mtf_simulated.auc_radial_min
                    ));
                    ui.end_row();
                }
            });
        if compared.len() > 1 {
            ui.horizontal(|ui| {
                for (i, c) in compared.iter().enumerate() {
                    ui.selectable_value(&mut self.channel, i, &c.name);
                }
            });
        }
        self.pictures_ui(ui, &compared);
        let Some((mtf, profile)) = self.figures.get(self.channel) else {
            return;
        };
        let frame = PlotFrame {
            width: None,
            height: 180.0,
            link_x: None,
            legend_above: false,
        };
        panel_ui_in(ui, "measured mtf", mtf, frame);
        panel_ui_in(ui, "measured profile", profile, frame);
    }
}

impl MeasuredPanel {
    /// The measured and design PSFs side by side on one log scale, and the residual map, of
    /// the chosen channel; built once per comparison.
    fn pictures_ui(&mut self, ui: &mut Ui, compared: &[ComparedChannel]) {
        let Some(c) = compared.get(self.channel) else {
            return;
        };
        let pixel_um = self.loaded.as_ref().map_or(1.0, |l| l.set.pixel_um);
        let gap = ui.spacing().item_spacing.x;
        let width = ui.available_width() - 8.0;
        // Three in a row where each gets 130 points or more (its axes take about 50), else
        // fewer to a row: a 1024-point window's left panel holds two.
        let per_row = (((width + gap) / (130.0 + gap)).floor() as usize).clamp(1, 3);
        let side = ((width - (per_row - 1) as f32 * gap) / per_row as f32).clamp(90.0, 260.0);
        let link = ui.make_persistent_id("measured pictures");
        let pictures = [
            (Picture::Psf(Side::Measured), "measured"),
            (Picture::Psf(Side::Design), "design"),
            (Picture::Residual, "|measured − design|"),
        ];
        for row in pictures.chunks(per_row) {
            ui.horizontal(|ui| {
                for &(picture, caption) in row {
                    let shown = self.pictures.get(
                        ui.ctx(),
                        (self.channel, picture),
                        self.comparisons,
                        || match picture {
                            Picture::Psf(s) => {
                                psf_panel(&c.comparison, s, pixel_um, &c.name, FLOOR_DECADES)
                            }
                            Picture::Residual => residual_panel(&c.comparison, pixel_um, &c.name),
                        },
                    );
                    ui.vertical(|ui| {
                        ui.set_width(side);
                        ui.small(caption).on_hover_text(&shown.panel.title);
                        image_panel_ui(
                            ui,
                            ("measured picture", picture),
                            &shown.panel,
                            &shown.textures,
                            ImageFrame {
                                size: egui::vec2(side, side),
                                link: Some(link),
                                view_half: shown.view_half,
                            },
                        );
                    });
                }
            });
        }
    }
}

/// The notice of a failed job (a cancel is no failure).
fn failed(what: &str, e: &JobError) -> Notice {
    match e {
        JobError::Cancelled => Notice::info("cancelled"),
        e => Notice::error(format!("{what}: {e}")),
    }
}
