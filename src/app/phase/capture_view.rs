//! Drawing the Capture & restore view: its controls, the captured / restored / difference
//! pictures of this design and of the bare T-OLED, and the setup comparison's table and plot.

use egui::{Color32, Stroke, StrokeKind, TextureHandle, Ui, vec2};

use super::capture::CaptureRow;
use super::compare::{CompareMetric, CompareState, mean_score};
use super::{ChannelSet, PhaseAction, PhaseCtx, Quality};
use crate::app::widgets::denoise::denoise_ui;
use crate::app::widgets::figure::panel_ui;
use crate::app::widgets::message_ui;
use crate::core::phase::figures::compare_panel;
use crate::core::phase::imaging::THESIS_PHOTONS;
use crate::core::restore::Recipe;
use crate::io::photo::DIFFERENCE_GAIN;

/// Light levels the slider spans (the thesis's range, photons per pixel).
const SLIDER_PHOTONS: std::ops::RangeInclusive<f64> = 250.0..=10_000.0;

/// What the PSNR of the photo without its unpassed frequencies means, on every place it shows.
const UNPASSED_HELP: &str = "The PSNR of the photo with its content removed at the horizontal \
     frequencies this setup passes < 1 % of: the slits pass no light there (about 45 … 110 \
     sensor pixels per cycle at 600 DPI) and no capture carries the photo there. Over the \
     512-px test photos the T-OLED's PSNR at 10 000 photons follows this number (r = 0.90): \
     a photo with more content there restores worse, however much light there is. \"-\": \
     the setup passes every frequency.";

/// That PSNR in dB from the photo's mean square there; `None` when the setup passes everything.
fn unpassed_psnr_db(unpassed_mse: f64) -> Option<f64> {
    (unpassed_mse > 0.0).then(|| -10.0 * unpassed_mse.log10())
}

/// "12 s, about 30 s left" from a step's fraction done and its seconds so far.
fn time_left(fraction: f32, seconds: f64) -> String {
    let f = f64::from(fraction);
    if f < 0.02 || seconds < 1.0 {
        return format!("{seconds:.0} s");
    }
    format!(
        "{seconds:.0} s, about {:.0} s left",
        seconds * (1.0 - f) / f
    )
}

/// A picture scaled to fit `side` points, with the scored columns outlined.
fn picture(ui: &mut Ui, t: &TextureHandle, side: f32, valid: Option<(f32, f32)>, alt: &str) {
    let [w, h] = t.size();
    let s = side / w.max(h).max(1) as f32;
    let resp = ui.add(egui::Image::new((t.id(), vec2(w as f32 * s, h as f32 * s))).alt_text(alt));
    if let Some((a, b)) = valid {
        let r = resp.rect;
        let field = egui::Rect::from_x_y_ranges(
            r.left() + a * r.width()..=r.left() + b * r.width(),
            r.y_range(),
        );
        ui.painter().rect_stroke(
            field,
            0.0,
            Stroke::new(1.0, Color32::from_rgb(255, 200, 0)),
            StrokeKind::Inside,
        );
    }
}

/// The Capture & restore view.
pub(super) fn capture_ui(ui: &mut Ui, ctx: &mut PhaseCtx<'_>) {
    ui.label(
        "A photo captured through this design and through the bare T-OLED of the same pitch \
             at the same light, then denoised and restored (thesis §4.5): the blur matrix of \
             every direction (eq. 4.12), Poisson and read noise, gain 1/LTR, 12-bit ADC, BM3D, \
             and conjugate gradients on the same operator. Scores are on the field of view \
             (eq. 4.13), outlined in yellow.",
    );
    capture_controls(ui, ctx);
    if let Some((step, f, seconds)) = ctx.capture.progress() {
        let mut cancel = false;
        ui.horizontal_wrapped(|ui| {
            cancel = ui.button("Cancel").clicked();
            ui.spinner();
            ui.label(format!("{step}… {}", time_left(f, seconds)));
        });
        ui.add(egui::ProgressBar::new(f).show_percentage());
        if cancel {
            ctx.queue(PhaseAction::CancelCapture);
        }
    }
    message_ui(ui, ctx.capture.message());
    if ctx.choices.quality == Quality::Preview {
        ui.colored_label(
            ui.visuals().warn_fg_color,
            "Preview sampling (Simulation panel): quick to look at, but it overstates the \
                 double MLA by 3-9 dB. Use full quality for numbers to quote.",
        );
    }
    // Four pictures and the spacing between them fit the width, whatever the window.
    let gap = ui.spacing().item_spacing.x;
    let side = ((ui.available_width() - 3.0 * gap - 4.0) / 4.0).clamp(48.0, 320.0);
    if let Some(t) = ctx.capture.photo_texture() {
        ui.horizontal(|ui| {
            ui.vertical(|ui| {
                ui.label("ground truth");
                picture(ui, t, side * 0.6, None, "ground truth photo");
            });
        });
    }
    let stale = !ctx.capture_current && !ctx.capture.rows().is_empty();
    if stale {
        ui.weak("Updating for the new settings; the pictures below are of the last run.");
    }
    for row in ctx.capture.rows() {
        ui.separator();
        capture_row_ui(ui, row, side);
    }
    ui.add_space(8.0);
    ui.separator();
    egui::CollapsingHeader::new(
        "Compare setups (Fig. 4.6, Tables 4.1-4.2, Fig. 4.10): PSNR vs photons",
    )
    .default_open(true)
    .show(ui, |ui| {
        // Its own ids: the pictures and progress above come and go, the buttons here stay.
        let stable = egui::UiBuilder::new().scope_id(egui::Id::unique("phase-compare"));
        ui.scope_builder(stable, |ui| compare_ui(ui, ctx));
    });
}

fn capture_controls(ui: &mut Ui, ctx: &mut PhaseCtx<'_>) {
    ui.horizontal_wrapped(|ui| {
        ui.label("Photo:");
        ui.strong(ctx.capture.photo_name().unwrap_or("(loading)"));
        if ui
            .button("Open photo…")
            .on_hover_text(format!(
                "A PNG or JPEG, scaled to at most {} px (the sensor's width)",
                ctx.design.camera.pixels
            ))
            .clicked()
        {
            ctx.queue(PhaseAction::AskCapturePhoto);
        }
        if ui.button("Built-in photo").clicked() {
            ctx.queue(PhaseAction::BuiltInCapturePhoto);
        }
    });
    let mut c = ctx.capture.choices();
    ui.horizontal_wrapped(|ui| {
        let photons = &mut c.photons;
        ui.add(
            egui::Slider::new(photons, SLIDER_PHOTONS)
                .logarithmic(true)
                .max_decimals(0)
                .text("photons per pixel"),
        )
        .on_hover_text(
            "Light level: photons an open display aperture would pass to a white pixel \
                 (§4.5). Every setup gets the same mean signal through its gain 1/LTR.",
        );
        for n in THESIS_PHOTONS {
            if ui
                .selectable_label(*photons == n, format!("{n:.0}"))
                .on_hover_text("A light level the thesis names")
                .clicked()
            {
                *photons = n;
            }
        }
    });
    ui.horizontal_wrapped(|ui| {
        ui.label("Channels:");
        let set = &mut c.channels;
        ui.selectable_value(set, ChannelSet::Spectral, "spectral (thesis)")
            .on_hover_text(
                "The sensor's response on the 401:10:691 nm grid, as the thesis and the CLI",
            );
        ui.selectable_value(set, ChannelSet::Peaks, "peaks (10× faster)")
            .on_hover_text("R 610, G 530, B 470 nm only: favours a plate folded at 530 nm");
        if let ChannelSet::Custom(serial) = ctx.choices.channels {
            ui.selectable_value(set, ChannelSet::Custom(serial), "custom response");
        }
        ui.separator();
        // The setup's LTR is known once its operator is built; the table's σ² needs none.
        let noise = crate::core::phase::imaging::capture_noise(c.photons, f64::NAN);
        let thesis = crate::core::restore::Sigma2::Thesis(Recipe::Iccv23).resolve(&noise);
        denoise_ui(ui, &mut c.denoise, Recipe::Iccv23, thesis, None);
    });
    ui.horizontal_wrapped(|ui| {
        ui.add(crate::app::widgets::number(&mut c.seed).prefix("noise seed "));
        ui.separator();
        ui.weak(format!("{} sampling", ctx.choices.quality.label()));
    });
    if c != ctx.capture.choices() {
        ctx.queue(PhaseAction::Capture(c));
    }
}

fn compare_ui(ui: &mut Ui, ctx: &mut PhaseCtx<'_>) {
    let running = ctx.compare.is_running();
    ui.add_enabled_ui(!running, |ui| {
        egui::CollapsingHeader::new("Setups and light levels")
            .default_open(false)
            .show(ui, |ui| {
                egui::Grid::new("phase-compare-setups")
                    .num_columns(2)
                    .show(ui, |ui| {
                        for (i, (setup, on)) in ctx.compare.setups_mut().enumerate() {
                            ui.checkbox(on, setup.label());
                            if i % 2 == 1 {
                                ui.end_row();
                            }
                        }
                    });
                ui.horizontal_wrapped(|ui| {
                    ui.label("photons per pixel:");
                    for (n, on) in ctx.compare.levels_mut() {
                        ui.checkbox(on, format!("{n:.0}"));
                    }
                });
            });
    });
    ui.horizontal_wrapped(|ui| {
        if ui
            .add_enabled(!running, egui::Button::new("Run comparison"))
            .on_hover_text(
                "Each setup designed once (optimized plans run Algorithm 1), its operator \
                     built for the photo, then every light level: about a minute at full \
                     quality for the built-in photo",
            )
            .clicked()
        {
            ctx.queue(PhaseAction::RunCompare);
        }
        let can_save = !running && ctx.compare.run().is_some() && !ctx.compare.is_saving();
        if ui
            .add_enabled(can_save, egui::Button::new("Save CSV…"))
            .on_hover_text("setup, LTR, photo, photons, PSNR (dB), SSIM: one line per run")
            .clicked()
        {
            ctx.queue(PhaseAction::AskCompareFile);
        }
    });
    if let Some((done, total, f, seconds)) = ctx.compare.progress() {
        let mut cancel = false;
        ui.horizontal_wrapped(|ui| {
            cancel = ui.button("Cancel").clicked();
            ui.spinner();
            let total = crate::app::widgets::counted(total as f64, "run", "runs");
            ui.label(format!("{done} of {total}, {seconds:.0} s"));
        });
        let overall = (done as f32 + f.min(0.99)) / total.max(1) as f32;
        ui.add(egui::ProgressBar::new(overall).show_percentage());
        if cancel {
            ctx.queue(PhaseAction::CancelCompare);
        }
    }
    message_ui(ui, ctx.compare.message());
    ui.horizontal(|ui| {
        ui.label("Show:");
        for m in [CompareMetric::PsnrDb, CompareMetric::Ssim] {
            ui.selectable_value(&mut ctx.compare.metric, m, m.label());
        }
    });
    compare_table(ui, ctx.compare);
    compare_plot(ui, ctx.compare);
}

fn compare_table(ui: &mut Ui, compare: &CompareState) {
    let Some(run) = compare.run() else {
        ui.weak("No comparison yet.");
        return;
    };
    let rows = compare.rows();
    let metric = compare.metric;
    ui.label(format!(
        "{} photo, {} sampling, {} channels, {}{}. Scores on the field of view; the \
             thesis (BM3D-denoised, its photos): T-OLED 22.4 dB, T = 5 optimized 28.0 dB on \
             average over 250-10 000 photons.",
        run.photo_name,
        run.quality.label(),
        match run.channels {
            ChannelSet::Peaks => "peak",
            ChannelSet::Spectral => "spectral",
            ChannelSet::Custom(_) => "custom",
        },
        match run.denoise {
            crate::core::restore::Denoise::None => "no denoiser",
            crate::core::restore::Denoise::Bm3d { .. } => "BM3D",
        },
        if compare.elapsed_s() > 0.0 && !compare.is_running() {
            format!(", {:.0} s", compare.elapsed_s())
        } else {
            String::new()
        }
    ));
    egui::ScrollArea::horizontal()
        .id_salt("phase-compare-table")
        .show(ui, |ui| {
            egui::Grid::new("phase-compare")
                .striped(true)
                .num_columns(run.photons.len() + 4)
                .show(ui, |ui| {
                    ui.strong("setup");
                    ui.strong("LTR");
                    for n in &run.photons {
                        ui.strong(format!("{n:.0} ph")).on_hover_text(format!(
                            "{} at {n:.0} photons per pixel",
                            metric.label()
                        ));
                    }
                    ui.strong("mean");
                    ui.strong("unpassed (dB)").on_hover_text(UNPASSED_HELP);
                    ui.end_row();
                    for setup in &run.setups {
                        let mine: Vec<_> =
                            rows.iter().filter(|r| &r.setup == setup).cloned().collect();
                        ui.label(setup.label());
                        ui.monospace(
                            mine.first()
                                .map_or_else(|| "-".into(), |r| format!("{:.3}", r.ltr)),
                        );
                        let cell =
                            |v: Option<f64>| v.map_or_else(|| "-".into(), |v| metric.format(v));
                        for n in &run.photons {
                            ui.monospace(cell(mean_score(&mine, metric, |r| r.photons == *n)));
                        }
                        let complete = mine.len() == run.photons.len();
                        ui.monospace(if complete {
                            cell(mean_score(&mine, metric, |_| true))
                        } else {
                            "-".into()
                        });
                        ui.monospace(
                            mine.first()
                                .and_then(|r| unpassed_psnr_db(r.unpassed_mse))
                                .map_or_else(|| "-".into(), |v| format!("{v:.2}")),
                        );
                        ui.end_row();
                    }
                });
        });
}

fn compare_plot(ui: &mut Ui, compare: &CompareState) {
    let (Some(run), rows) = (compare.run(), compare.rows()) else {
        return;
    };
    if rows.is_empty() {
        return;
    }
    let panel = compare_panel(rows, &run.setups, &run.photons, compare.metric);
    let height = (ui.available_width() * 0.45).clamp(200.0, 360.0);
    panel_ui(ui, "phase-compare-plot", &panel, height);
}

fn capture_row_ui(ui: &mut Ui, row: &CaptureRow, side: f32) {
    let r = &row.run;
    let denoised = match (r.denoised_psnr_db, r.denoise.sigma2) {
        (Some(p), Some(s)) => format!("denoised {p:.2} dB with σ² {s:.2e}, "),
        _ => "no denoiser, ".to_string(),
    };
    ui.horizontal_wrapped(|ui| {
        ui.strong(&row.label);
        ui.label(format!(
            "LTR {:.3}, FoV {:.1}°: restored PSNR {:.2} dB, SSIM {:.3} (captured {:.2} dB, \
             {denoised}CG λ {:.3}) at {:.0} photons per pixel",
            row.ltr, row.fov_deg, r.psnr_db, r.ssim, r.captured_psnr_db, r.cg.lambda, r.photons
        ));
    });
    if let Some(db) = unpassed_psnr_db(row.unpassed_mse) {
        ui.label(format!(
            "The photo without the frequencies this setup passes < 1 % of: {db:.2} dB"
        ))
        .on_hover_text(UNPASSED_HELP);
    }
    let width = r.captured.first().map_or(1, ndarray::Array2::ncols).max(1) as f32;
    let valid = Some((row.valid.start as f32 / width, row.valid.end as f32 / width));
    let t = row.textures();
    let mut pictures = vec![(&t.captured, "captured".to_string())];
    if let Some(d) = &t.denoised {
        pictures.push((d, "denoised (BM3D)".to_string()));
    }
    pictures.push((&t.restored, "restored".to_string()));
    pictures.push((
        &t.difference,
        format!("|restored - truth| × {DIFFERENCE_GAIN:.0}"),
    ));
    ui.horizontal(|ui| {
        for (t, caption) in pictures {
            ui.vertical(|ui| {
                ui.label(&caption);
                picture(ui, t, side, valid, &format!("{} {caption}", row.label));
            });
        }
    });
}
