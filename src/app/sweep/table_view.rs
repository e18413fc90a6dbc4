//! The Sweep workspace's controls (the folder, the filter, the message line) and its table, as
//! panels: each reads the workspace through [`SweepCtx`] and changes it only by queueing
//! [`SweepAction`]s.
//!
//! The table is rows of fixed-width cells inside a `ScrollArea::show_rows`, so only the rows
//! on screen are laid out (100 000 rows scroll as fast as 10). Widths are fixed per column,
//! from the header and the widest cell the view's job measured, because a `Grid` sizes its
//! columns from the rows it has drawn and would shift the columns under the header as it
//! scrolls.

use egui::{Align, Layout, RichText, Sense, vec2};

use super::table::{Column, Sort};
use super::{SweepAction, SweepCtx};

/// Room for the Open button at the start of each row.
const OPEN_COLUMN_PX: f32 = 52.0;
/// Room for the Open and Pin A buttons (a display sweep's rows).
const OPEN_PIN_COLUMN_PX: f32 = 104.0;
/// The widest a column gets (longer errors are cut; hover shows them whole).
const MAX_COLUMN_PX: f32 = 360.0;

/// The left panel: what is open, the filter and the message line.
#[derive(Default)]
pub struct ControlsPanel;

/// The centre: a header row of sort buttons and the shown rows, each with its Open button.
#[derive(Default)]
pub struct TablePanel;

impl ControlsPanel {
    /// Draws the panel.
    pub fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut SweepCtx<'_>) {
        ui.heading("Sweep results");
        ui.horizontal_wrapped(|ui| {
            if ui
                .add_enabled(!ctx.asking, egui::Button::new("Open…"))
                .on_hover_text("File > Open sweep results…: a folder written by udc-studio sweep")
                .clicked()
            {
                ctx.actions.push(SweepAction::AskFolder);
            }
            if let Some(last) = ctx.last_sweep.cloned()
                && ctx.table.is_none_or(|t| t.dir != last)
                && ui
                    .add_enabled(ctx.reading.is_none(), egui::Button::new("Reopen last"))
                    .on_hover_text(last.display().to_string())
                    .clicked()
            {
                ctx.actions.push(SweepAction::OpenFolder(last));
            }
        });
        if let Some((dir, fraction)) = ctx.reading {
            let mut cancel = false;
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label(format!(
                    "reading {} … {:.0} %",
                    dir.display(),
                    100.0 * fraction
                ));
                cancel = ui.button("Cancel").clicked();
            });
            if cancel {
                ctx.actions.push(SweepAction::CancelLoad);
            }
        }
        study_ui(ui, ctx);
        crate::app::widgets::message_ui(ui, ctx.message);
        let Some(t) = ctx.table else {
            empty_ui(ui, ctx);
            return;
        };
        let m = &t.manifest;
        ui.separator();
        egui::Grid::new("sweep_summary")
            .num_columns(2)
            .show(ui, |ui| {
                let mut row = |k: &str, v: String| {
                    ui.label(k);
                    ui.label(v);
                    ui.end_row();
                };
                row("name", m.spec.name.clone());
                row("job", m.spec.job.as_str().to_string());
                // Counted from the rows read, which a running study adds to before it writes
                // its manifest again.
                let failed = t.rows.iter().filter(|r| !r.error.is_empty()).count();
                row(
                    "rows",
                    format!("{} of {} points ({failed} failed)", t.rows.len(), m.points),
                );
                row(
                    "complete",
                    if m.complete { "yes" } else { "no: resume it" }.into(),
                );
                row("run time", format!("{:.1} s", m.elapsed_s));
                row("tool", m.tool_version.clone());
            });
        ui.label(RichText::new(t.dir.display().to_string()).weak().small());
        ui.separator();
        ui.label("Filter");
        let mut filter = ctx.filter.to_string();
        ui.add(
            egui::TextEdit::singleline(&mut filter)
                .hint_text("random-4  ltr>0.5  seed<3")
                .desired_width(f32::INFINITY),
        )
        .on_hover_text(
            "Words separated by spaces, all of which must hold: text found in a parameter \
             or the error (random-4), or a column compared with a number (ltr>0.5, seed<3) \
             or equal to a word (tiling=repeat)",
        );
        if filter != ctx.filter {
            ctx.actions.push(SweepAction::Filter(filter));
        }
    }
}

impl TablePanel {
    /// Draws the panel.
    pub fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut SweepCtx<'_>) {
        let Some(t) = ctx.table else {
            ui.centered_and_justified(|ui| {
                ui.weak("File > Open sweep results… to see a sweep's table and plots.");
            });
            return;
        };
        let Some(view) = ctx.view else {
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label("sorting and filtering…");
            });
            return;
        };
        ui.horizontal(|ui| {
            ui.label(format!("{} shown / {} rows", view.rows.len(), t.rows.len()));
            if ctx.deriving {
                ui.spinner();
            }
        });
        let columns = t.columns();
        let widths: Vec<f32> = columns
            .iter()
            .map(|c| {
                let header = ui.fonts_mut(|f| {
                    f.layout_no_wrap(
                        t.name(*c).to_string(),
                        egui::TextStyle::Button.resolve(ui.style()),
                        egui::Color32::WHITE,
                    )
                    .size()
                    .x
                });
                let chars = view.widest.get(c).copied().unwrap_or(6) as f32;
                (header + 30.0).max(chars * 7.5 + 12.0).min(MAX_COLUMN_PX)
            })
            .collect();
        let row_h = ui.spacing().interact_size.y;
        let mut sort = ctx.sort;
        let mut open = None;
        let pinnable = matches!(
            t.manifest.spec.job,
            crate::core::sweep::SweepJob::Analyze | crate::core::sweep::SweepJob::Restore
        );
        let open_px = if pinnable {
            OPEN_PIN_COLUMN_PX
        } else {
            OPEN_COLUMN_PX
        };
        egui::ScrollArea::horizontal()
            .id_salt("sweep_table_x")
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    ui.add_space(open_px);
                    for (c, w) in columns.iter().zip(&widths) {
                        header_ui(ui, t.name(*c), *c, *w, &mut sort);
                    }
                });
                ui.separator();
                egui::ScrollArea::vertical()
                    .id_salt("sweep_table_y")
                    .auto_shrink([false, false])
                    .show_rows(ui, row_h, view.rows.len(), |ui, range| {
                        for k in range {
                            let Some(&i) = view.rows.get(k) else { continue };
                            let Some(row) = t.rows.get(i) else { continue };
                            ui.horizontal(|ui| {
                                ui.allocate_ui_with_layout(
                                    vec2(open_px, row_h),
                                    Layout::left_to_right(Align::Center),
                                    |ui| {
                                        // The column keeps its width under the headers.
                                        ui.set_min_width(open_px);
                                        if ui
                                            .small_button("Open")
                                            .on_hover_text(
                                                "Open this point's design where it was made \
                                                 (Display layouts or Phase masks): the current \
                                                 design, B in Compare",
                                            )
                                            .clicked()
                                        {
                                            open = Some(SweepAction::OpenRow(i));
                                        }
                                        if pinnable
                                            && ui
                                                .small_button("Pin A")
                                                .on_hover_text(
                                                    "Pin this point's design as A for Display \
                                                     layouts' Compare (analysed at full \
                                                     quality); the current design stays B",
                                                )
                                                .clicked()
                                        {
                                            open = Some(SweepAction::PinRow(i));
                                        }
                                    },
                                );
                                for (c, w) in columns.iter().zip(&widths) {
                                    cell_ui(ui, &t.text(row, *c), *c, *w, row_h);
                                }
                            });
                        }
                    });
            });
        if sort != ctx.sort {
            ctx.actions.push(SweepAction::Sort(sort));
        }
        if let Some(a) = open {
            ctx.actions.push(a);
        }
    }
}

/// A column's header: click to sort by it, again to reverse; a painted triangle shows the
/// order (the studio's fonts have no arrow glyphs).
fn header_ui(ui: &mut egui::Ui, name: &str, c: Column, width: f32, sort: &mut Sort) {
    let r = ui.add_sized(
        vec2(width, ui.spacing().interact_size.y),
        egui::Button::new(RichText::new(name).strong()).frame(false),
    );
    if sort.column == c {
        let color = ui.visuals().strong_text_color();
        let centre = egui::pos2(r.rect.right() - 5.0, r.rect.center().y);
        let (tip, base) = if sort.descending {
            (4.0, -4.0)
        } else {
            (-4.0, 4.0)
        };
        ui.painter().add(egui::Shape::convex_polygon(
            vec![
                centre + vec2(0.0, tip),
                centre + vec2(-4.0, base),
                centre + vec2(4.0, base),
            ],
            color,
            egui::Stroke::NONE,
        ));
    }
    let order = match (sort.column == c, sort.descending) {
        (true, false) => " (now smallest first)",
        (true, true) => " (now largest first)",
        _ => "",
    };
    if r.on_hover_text(format!("Sort by {name}{order}; click again to reverse"))
        .clicked()
    {
        *sort = Sort {
            column: c,
            descending: sort.column == c && !sort.descending,
        };
    }
}

/// One cell, cut to its column; numbers right-aligned so their digits line up.
fn cell_ui(ui: &mut egui::Ui, text: &str, c: Column, width: f32, height: f32) {
    let layout = match c {
        Column::Metric(_) | Column::Point => Layout::right_to_left(Align::Center),
        _ => Layout::left_to_right(Align::Center),
    };
    ui.allocate_ui_with_layout(vec2(width, height), layout, |ui| {
        ui.set_min_width(width);
        let label = egui::Label::new(text).truncate().sense(Sense::hover());
        let r = ui.add(label);
        if matches!(c, Column::Error) && !text.is_empty() {
            r.on_hover_text(text);
        }
    });
}

/// A running study's progress bar with its ETA and Cancel, or Resume for an open study that
/// is not complete.
fn study_ui(ui: &mut egui::Ui, ctx: &mut SweepCtx<'_>) {
    // An id of their own: the reading line above comes and goes as rows land, which would move
    // the buttons' automatic ids between two frames, so a click (or an accessibility action)
    // aimed at Cancel study could miss it.
    let scope = egui::UiBuilder::new().scope_id(egui::Id::unique("sweep-study-controls"));
    ui.scope_builder(scope, |ui| study_controls(ui, ctx));
}

fn study_controls(ui: &mut egui::Ui, ctx: &mut SweepCtx<'_>) {
    if let Some((fraction, elapsed_s)) = ctx.study {
        let eta = if fraction > 0.0 && fraction < 1.0 {
            let left = elapsed_s * f64::from(1.0 - fraction) / f64::from(fraction);
            format!(", about {} left", super::study_dialog::duration_text(left))
        } else {
            String::new()
        };
        ui.add(
            egui::ProgressBar::new(fraction).text(format!("study {:.0} %{eta}", 100.0 * fraction)),
        );
        if ui
            .button("Cancel study")
            .on_hover_text("Stops after the points in flight; Resume runs the rest")
            .clicked()
        {
            ctx.actions.push(SweepAction::CancelStudy);
        }
    } else if ctx.resumable
        && ui
            .button("Resume study")
            .on_hover_text("Runs the points the folder does not hold yet")
            .clicked()
    {
        ctx.actions.push(SweepAction::ResumeStudy);
    }
}

/// The empty state: how to get results.
fn empty_ui(ui: &mut egui::Ui, ctx: &mut SweepCtx<'_>) {
    ui.separator();
    ui.label("No results open yet. Start one:");
    if ui
        .add_enabled(
            ctx.study.is_none(),
            egui::Button::new("New study from the current design…"),
        )
        .on_hover_text(
            "Vary the Display workspace's design over DPI, tiling, seeds or any of its numbers",
        )
        .clicked()
    {
        ctx.actions.push(SweepAction::NewStudy);
    }
    for (name, text) in crate::io::sweep::EXAMPLES {
        let title = text
            .lines()
            .find_map(|l| l.strip_prefix("name = "))
            .map_or(*name, |t| t.trim_matches('"'));
        if ui
            .add_enabled(
                ctx.study.is_none(),
                egui::Button::new(format!("Run the example: {title}")),
            )
            .on_hover_text(format!(
                "presets/sweeps/{name}, run in a new results folder"
            ))
            .clicked()
        {
            ctx.actions.push(SweepAction::RunExample(name));
        }
    }
    if ui
        .button("Reproduce a thesis result…")
        .on_hover_text(
            "The thesis's figures and tables as sweeps (their specs are in presets/reproduce/), \
             beside the thesis's own numbers: Help > Reproduce thesis results",
        )
        .clicked()
    {
        ctx.actions.push(SweepAction::OpenReproduce);
    }
    ui.label(
        RichText::new(
            "A folder written by udc-studio sweep: Open… above, or drop it on the window.",
        )
        .weak(),
    );
}
