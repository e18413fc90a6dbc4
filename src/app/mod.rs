//! The studio (egui/eframe). The only module that touches egui.

mod worker;

use std::path::PathBuf;

use anyhow::Result;
use egui::{ColorImage, TextureHandle, TextureOptions};

pub use worker::{JobResult, Worker};

use crate::core::analyze::Quality;
use crate::core::{Analysis, Design};
use crate::io::{design_file, presets};

/// Opens the studio window with `design` (or the default preset).
///
/// # Errors
/// When no window can be created (no display) or the design file cannot be read.
pub fn run_studio(design: Option<PathBuf>) -> Result<()> {
    let design = match design {
        Some(path) => design_file::load_design(&path)?,
        None => presets::load_preset(presets::DEFAULT_PRESET)?,
    };
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("UDC Studio")
            .with_inner_size([1280.0, 800.0]),
        ..Default::default()
    };
    eframe::run_native(
        "UDC Studio",
        options,
        Box::new(move |cc| Ok(Box::new(StudioApp::new(&cc.egui_ctx, design)))),
    )
    .map_err(|e| anyhow::anyhow!("cannot open the studio window: {e}"))
}

/// The studio.
pub struct StudioApp {
    design: Design,
    worker: Worker,
    shown: Option<(Quality, Analysis)>,
    error: Option<String>,
    psf_texture: Option<TextureHandle>,
}

impl StudioApp {
    pub fn new(ctx: &egui::Context, design: Design) -> Self {
        let wake_ctx = ctx.clone();
        let mut worker = Worker::spawn(move || wake_ctx.request_repaint());
        worker.submit(design.clone());
        StudioApp {
            design,
            worker,
            shown: None,
            error: None,
            psf_texture: None,
        }
    }

    /// The design being edited.
    pub fn design(&self) -> &Design {
        &self.design
    }

    /// The result on screen, if any.
    pub fn analysis(&self) -> Option<&Analysis> {
        self.shown.as_ref().map(|(_, a)| a)
    }

    fn take_results(&mut self, ctx: &egui::Context) {
        for r in self.worker.poll() {
            if r.generation != self.worker.generation() {
                continue;
            }
            match r.result {
                Ok(a) => {
                    self.psf_texture = Some(psf_texture(ctx, &a));
                    self.shown = Some((r.quality, a));
                    self.error = None;
                }
                Err(e) => self.error = Some(e.to_string()),
            }
        }
    }
}

/// An RGB composite of the channels' PSFs on a log scale (6 decades), for display.
fn psf_texture(ctx: &egui::Context, a: &Analysis) -> TextureHandle {
    let n = a.window_px;
    let mut rgb = vec![0u8; n * n * 3];
    for (k, ch) in a.channels.iter().take(3).enumerate() {
        let peak = ch
            .psf
            .iter()
            .copied()
            .fold(0.0f64, f64::max)
            .max(f64::MIN_POSITIVE);
        for (i, v) in ch.psf.iter().enumerate() {
            let l = ((v / peak).max(1e-6).log10() + 6.0) / 6.0;
            rgb[i * 3 + k] = (l.clamp(0.0, 1.0) * 255.0).round() as u8;
        }
    }
    let image = ColorImage::from_rgb([n, n], &rgb);
    ctx.load_texture("psf", image, TextureOptions::NEAREST)
}

impl eframe::App for StudioApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        self.take_results(&ctx);
        egui::Panel::left("numbers").resizable(true).show(ui, |ui| {
            ui.heading(&self.design.name);
            ui.label(&self.design.description);
            ui.separator();
            if let Some(p) = self.worker.progress() {
                ui.add(egui::ProgressBar::new(p).text("computing…"));
            }
            if let Some(err) = &self.error {
                ui.colored_label(ui.visuals().error_fg_color, err);
            }
            if let Some((q, a)) = &self.shown {
                ui.label(format!("quality: {q:?}, {:.0} ms", a.elapsed_ms));
                ui.label(format!(
                    "LTR {:.4}   open fraction {:.4}",
                    a.ltr, a.open_fraction
                ));
                ui.label(format!("invertibility loss {:.4}", a.invertibility_loss));
                for c in &a.channels {
                    ui.label(format!(
                        "{} ({:.0} nm): AUC {:.4} (normalised {:.3})",
                        c.name,
                        c.wavelength_nm,
                        c.mtf.auc_radial_min,
                        c.mtf.auc_normalised()
                    ));
                }
                for w in &a.warnings {
                    ui.small(format!("⚠ {w}"));
                }
            }
        });
        egui::CentralPanel::default().show(ui, |ui| {
            if let Some(tex) = &self.psf_texture {
                let side = ui.available_width().min(ui.available_height());
                ui.add(egui::Image::new(tex).fit_to_exact_size(egui::vec2(side, side)));
            } else {
                ui.spinner();
            }
        });
    }
}
