//! The Save figure window: a plot or picture asked to be saved (its context menu, or a view's
//! Save figure button) is drawn to a file as the command line's `figure` draws it, SVG or PNG
//! at a chosen size, with a caption naming the document (editable). Writing runs on a helper
//! thread; the window stays until the file is written or the user closes it.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::app::dialogs::{self, FileSpec};
use crate::app::job::{Job, JobError, Writes};
use crate::app::notice::Notice;
use crate::core::figure::{FIGURE_SIDE_PX, Figure, FigureFormat, Panel};

/// The window's state: the figure asked for and how to write it.
pub struct SaveFigureWindow {
    panel: Option<Arc<Panel>>,
    /// The line under the figure (empty: none).
    pub caption: String,
    /// SVG or PNG.
    pub format: FigureFormat,
    /// Width, pixels (PNG) or user units (SVG).
    pub width_px: u32,
    /// Height, pixels or user units.
    pub height_px: u32,
    dialog: Option<Job<Option<PathBuf>>>,
    writes: Writes,
    message: Option<Notice>,
}

impl Default for SaveFigureWindow {
    fn default() -> Self {
        SaveFigureWindow {
            panel: None,
            caption: String::new(),
            format: FigureFormat::Svg,
            width_px: 960,
            height_px: 600,
            dialog: None,
            writes: Writes::default(),
            message: None,
        }
    }
}

impl SaveFigureWindow {
    /// Opens the window for `panel`, its caption `caption` (the document's).
    pub fn open(&mut self, panel: Arc<Panel>, caption: String) {
        self.panel = Some(panel);
        self.caption = caption;
        self.message = None;
    }

    /// Whether the window is open.
    pub fn is_open(&self) -> bool {
        self.panel.is_some()
    }

    /// The figure it would write now.
    pub fn figure(&self) -> Option<Figure> {
        let panel = self.panel.as_ref()?;
        let caption = self.caption.trim();
        Some(Figure {
            panels: vec![(**panel).clone()],
            caption: (!caption.is_empty()).then(|| caption.to_owned()),
        })
    }

    /// The last message (a write's report or error).
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    /// Whether a dialog or a write is in flight.
    pub fn is_busy(&self) -> bool {
        self.dialog.is_some() || !self.writes.is_empty()
    }

    /// Writes the figure to `path` on a helper thread, in the format its extension names (the
    /// chosen format's extension is added to a name without one).
    pub fn save_to(&mut self, path: &Path, ctx: &egui::Context) {
        let Some(figure) = self.figure() else { return };
        let (path, format) = match FigureFormat::of_path(path) {
            Some(f) => (path.to_path_buf(), f),
            None if path.extension().is_none() => {
                (path.with_extension(extension(self.format)), self.format)
            }
            None => {
                self.message = Some(Notice::error(format!(
                    "{}: name a .svg or .png file",
                    path.display()
                )));
                return;
            }
        };
        let size = (self.width_px, self.height_px);
        let wake = ctx.clone();
        self.writes.spawn(
            move || wake.request_repaint(),
            move || -> Result<String, JobError> {
                crate::io::figure::write_figure(&path, &figure, format, size)?;
                Ok(format!("saved the figure {}", path.display()))
            },
        );
    }

    /// Takes finished dialogs and writes.
    fn poll(&mut self, ctx: &egui::Context) {
        if let Some(n) = self.writes.poll() {
            let saved = !n.is_error();
            self.message = Some(n);
            if saved {
                self.panel = None;
            }
        }
        if let Some(j) = &self.dialog
            && let Some(answer) = j.poll()
        {
            self.dialog = None;
            match answer {
                Ok(Some(path)) => self.save_to(&path, ctx),
                Ok(None) => {}
                Err(e) => self.message = Some(Notice::error(e.to_string())),
            }
        }
    }

    /// Draws the window while a figure waits to be saved; returns the report of a finished
    /// write for the status bar.
    pub fn ui(&mut self, ctx: &egui::Context, native_dialogs: bool) -> Option<Notice> {
        let before = self.message.clone();
        self.poll(ctx);
        let finished = (self.message != before)
            .then(|| self.message.clone())
            .flatten();
        let Some(panel) = self.panel.clone() else {
            return finished;
        };
        let mut open = true;
        egui::Window::new("Save figure")
            .id(egui::Id::unique("save figure window"))
            .open(&mut open)
            .collapsible(false)
            .resizable(false)
            .show(ctx, |ui| {
                ui.label(format!("“{}”", panel.title));
                ui.horizontal(|ui| {
                    ui.label("format");
                    ui.selectable_value(&mut self.format, FigureFormat::Svg, "SVG")
                        .on_hover_text("Scalable: sharp in a paper or on a slide at any size");
                    ui.selectable_value(&mut self.format, FigureFormat::Png, "PNG")
                        .on_hover_text("Pixels at the size below");
                });
                let range = *FIGURE_SIDE_PX.start()..=*FIGURE_SIDE_PX.end();
                ui.horizontal(|ui| {
                    ui.label("size");
                    ui.add(
                        egui::DragValue::new(&mut self.width_px)
                            .range(range.clone())
                            .suffix(" px"),
                    )
                    .on_hover_text("Width: pixels (PNG) or user units (SVG)");
                    ui.label("×");
                    ui.add(
                        egui::DragValue::new(&mut self.height_px)
                            .range(range)
                            .suffix(" px"),
                    )
                    .on_hover_text("Height: pixels (PNG) or user units (SVG)");
                });
                ui.label("caption (empty: none)");
                ui.add(
                    egui::TextEdit::multiline(&mut self.caption)
                        .desired_rows(2)
                        .desired_width(360.0),
                );
                let idle = !self.is_busy();
                ui.horizontal(|ui| {
                    if ui
                        .add_enabled(idle, egui::Button::new("Save…"))
                        .on_hover_text("Choose the file; its extension picks the format")
                        .clicked()
                    {
                        self.ask(ctx, native_dialogs, &panel.title);
                    }
                    if !idle {
                        ui.spinner();
                    }
                });
                crate::app::widgets::message_ui(ui, self.message.as_ref());
            });
        if !open {
            self.panel = None;
        }
        finished
    }

    fn ask(&mut self, ctx: &egui::Context, native_dialogs: bool, title: &str) {
        if !native_dialogs {
            self.message = Some(Notice::error("file dialogs are disabled in this session"));
            return;
        }
        let name = format!("{}.{}", slug(title), extension(self.format));
        let wake = ctx.clone();
        self.dialog = Some(dialogs::ask(
            FileSpec::save("Save figure", ("figure", &["svg", "png"]), name),
            move || wake.request_repaint(),
        ));
    }
}

fn extension(format: FigureFormat) -> &'static str {
    match format {
        FigureFormat::Svg => "svg",
        FigureFormat::Png => "png",
    }
}

/// A file name from a figure's title: letters and digits, the rest as single dashes.
fn slug(title: &str) -> String {
    let mut out = String::new();
    for c in title.chars() {
        if c.is_alphanumeric() {
            out.extend(c.to_lowercase());
        } else if !out.ends_with('-') && !out.is_empty() {
            out.push('-');
        }
    }
    let out = out.trim_end_matches('-');
    if out.is_empty() {
        "figure".into()
    } else {
        out.into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_title_becomes_a_file_name() {
        assert_eq!(slug("G log-PSF (530 nm)"), "g-log-psf-530-nm");
        assert_eq!(slug("  "), "figure");
    }
}
