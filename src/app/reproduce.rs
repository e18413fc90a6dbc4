//! Help ▸ Reproduce thesis results: the results `udc-studio reproduce` regenerates, each with
//! what it runs, checks and costs; a quick run in the background and the report it writes,
//! shown in the window; any report on disk opened with a file dialog.
//!
//! A run is the library call behind `udc-studio reproduce ID --quick --out DIR`, made on a job
//! thread: the UI only polls, the bar shows the share of the points in the tables, and Cancel
//! stops the points in flight at their next check (a new run resumes the finished ones).

use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::app::dialogs::{self, FileSpec};
use crate::app::job::{Job, JobError, Keyed};
use crate::app::notice::Notice;
use crate::core::Progress;
use crate::core::psf::route::Backend;
use crate::core::reproduce::ResultId;

/// The largest report read (ours are a few kB).
const REPORT_LIMIT_BYTES: u64 = 4 << 20;

/// A report read from disk.
#[derive(Debug, Clone)]
struct Report {
    path: PathBuf,
    text: String,
}

/// The window's state.
pub struct ReproduceWindow {
    /// Whether the window is shown.
    pub open: bool,
    selected: ResultId,
    /// Where runs write: `<data dir>/reproduce/<id>`.
    out_root: Option<PathBuf>,
    native_dialogs: bool,
    run: Keyed<ResultId, PathBuf>,
    dialog: Option<Job<Option<PathBuf>>>,
    report: Option<Report>,
    message: Option<Notice>,
    /// The Markdown viewer's layout cache.
    markdown: egui_commonmark::CommonMarkCache,
    /// Where a run's PSFs are computed: View ▸ Compute PSFs on, as the window last drew.
    backend: Backend,
}

impl ReproduceWindow {
    /// A closed window whose runs write under `data_dir/reproduce` (none: no runs, reports
    /// can still be opened).
    pub fn new(data_dir: Option<&Path>, native_dialogs: bool) -> Self {
        ReproduceWindow {
            open: false,
            selected: ResultId::ALL[0],
            out_root: data_dir.map(|d| d.join("reproduce")),
            native_dialogs,
            run: Keyed::idle(),
            dialog: None,
            report: None,
            message: None,
            markdown: egui_commonmark::CommonMarkCache::default(),
            backend: Backend::Cpu,
        }
    }

    /// The result shown.
    pub fn selected(&self) -> ResultId {
        self.selected
    }

    /// Shows `id` (and its last report, when there is one).
    pub fn select(&mut self, id: ResultId) {
        self.selected = id;
        self.report = None;
        if let Some(path) = self.out_of(id).map(|d| d.join("report.md"))
            && path.is_file()
        {
            self.load_report(&path);
        }
    }

    /// Whether a run is going.
    pub fn is_running(&self) -> bool {
        self.run.is_running()
    }

    /// The report shown: its path and text.
    pub fn report(&self) -> Option<(&Path, &str)> {
        self.report
            .as_ref()
            .map(|r| (r.path.as_path(), r.text.as_str()))
    }

    /// The message line (a finished, failed or cancelled run).
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    fn out_of(&self, id: ResultId) -> Option<PathBuf> {
        self.out_root.as_ref().map(|r| r.join(id.as_str()))
    }

    /// Starts the quick run of the selected result.
    pub fn start_quick_run(&mut self, ctx: &egui::Context) {
        let id = self.selected;
        let Some(out) = self.out_of(id) else {
            self.message = Some(Notice::error(
                "no folder to write results in (this system gives no data directory); run \
                 `udc-studio reproduce` from a terminal instead",
            ));
            return;
        };
        let wake = {
            let ctx = ctx.clone();
            move || ctx.request_repaint()
        };
        self.message = None;
        let backend = self.backend;
        self.run.start(
            id,
            Job::spawn("reproduce", wake, move |p| quick_run(id, &out, backend, p)),
        );
    }

    /// Stops the run (a later run resumes the points it finished).
    pub fn cancel(&mut self) {
        if let Some(job) = self.run.job() {
            job.cancel();
        }
    }

    fn load_report(&mut self, path: &Path) {
        match crate::io::safe_file::read_text_bounded(path, REPORT_LIMIT_BYTES, "report") {
            Ok(text) => {
                self.report = Some(Report {
                    path: path.to_path_buf(),
                    text,
                });
            }
            Err(e) => self.message = Some(Notice::error(e.to_string())),
        }
    }

    /// Collects finished jobs.
    fn poll(&mut self) {
        let seconds = self.run.job().map_or(0.0, |j| j.elapsed().as_secs_f64());
        if let Some((id, done)) = self.run.poll() {
            match done {
                Ok(report) => {
                    self.message = Some(Notice::info(format!(
                        "{} reproduced (quick) in {seconds:.0} s",
                        id.as_str()
                    )));
                    self.selected = id;
                    self.load_report(&report);
                }
                Err(JobError::Cancelled) => {
                    self.message = Some(Notice::info(format!(
                        "{} cancelled; a new run resumes its finished points",
                        id.as_str()
                    )));
                }
                Err(e) => self.message = Some(Notice::error(e.to_string())),
            }
        }
        if let Some(job) = &self.dialog
            && let Some(done) = job.poll()
        {
            self.dialog = None;
            match done {
                Ok(Some(path)) => self.load_report(&path),
                Ok(None) | Err(JobError::Cancelled) => {}
                Err(e) => self.message = Some(Notice::error(e.to_string())),
            }
        }
    }

    fn open_dialog(&mut self, ctx: &egui::Context) {
        if !self.native_dialogs {
            return;
        }
        let mut spec = FileSpec::open("Open a reproduction report", ("Report", &["md"]));
        spec.start_dir = self.out_of(self.selected).filter(|d| d.is_dir());
        let ctx = ctx.clone();
        self.dialog = Some(dialogs::ask(spec, move || ctx.request_repaint()));
    }

    /// Draws the window when it is open; a run started from it computes its PSFs on `backend`
    /// (the studio's choice, on the window's GPU).
    pub fn ui(&mut self, ctx: &egui::Context, backend: Backend) {
        self.backend = backend;
        self.poll();
        if !self.open {
            return;
        }
        let mut open = self.open;
        let area = ctx.content_rect();
        egui::Window::new("Reproduce thesis results")
            .open(&mut open)
            // Below the menu bar, centred: the window must not hide the menus that opened it.
            .default_pos(egui::pos2(
                (area.center().x - 380.0).max(area.left()),
                area.top() + 40.0,
            ))
            .default_size([760.0, 520.0])
            .max_height(area.height() - 110.0)
            .show(ctx, |ui| self.contents(ui));
        self.open = open;
    }

    fn contents(&mut self, ui: &mut egui::Ui) {
        ui.label(
            "Every result below is regenerated by the studio from the thesis's recipe and \
             reported beside the thesis's own numbers. A quick run uses 3 photos of the test \
             set at 256²; the full run (the command line below without --quick) uses all of \
             them.",
        );
        ui.horizontal_wrapped(|ui| {
            for id in ResultId::ALL {
                if ui
                    .selectable_label(self.selected == id, id.as_str())
                    .on_hover_text(id.title())
                    .clicked()
                    && self.selected != id
                {
                    self.select(id);
                }
            }
        });
        ui.separator();
        let id = self.selected;
        let (quick, full) = id.cost();
        ui.strong(id.title());
        egui::Grid::new("reproduce-facts")
            .num_columns(2)
            .show(ui, |ui| {
                for (what, text) in [
                    ("runs", id.runs().to_string()),
                    ("checks", id.checks().to_string()),
                    ("cost", format!("quick {quick}, full {full} (2 cores)")),
                ] {
                    ui.label(what);
                    ui.add(egui::Label::new(text).wrap());
                    ui.end_row();
                }
                ui.label("command");
                ui.horizontal(|ui| {
                    // The backend a run here uses, so that the copied line computes alike.
                    let on = match self.backend {
                        Backend::Cpu => String::new(),
                        b => format!(" --backend {b}"),
                    };
                    let cmd = format!("udc-studio reproduce {} --out DIR{on}", id.as_str());
                    ui.monospace(&cmd);
                    if ui.small_button("Copy").clicked() {
                        ui.ctx().copy_text(cmd);
                    }
                });
                ui.end_row();
            });
        ui.horizontal(|ui| {
            if let Some((running, job)) = self.run.current() {
                // The share of the run's points in its tables (each part fills its share).
                ui.add(
                    egui::ProgressBar::new(job.fraction())
                        .desired_width(140.0)
                        .show_percentage(),
                );
                ui.label(format!(
                    "{} running (quick), {:.0} s",
                    running.as_str(),
                    job.elapsed().as_secs_f64()
                ));
                if ui.button("Cancel").clicked() {
                    self.cancel();
                }
                ui.ctx().request_repaint_after(Duration::from_millis(500));
            } else if ui
                .button(format!("Run quick ({quick})"))
                .on_hover_text("Runs in the background; the report opens here when it is done")
                .clicked()
            {
                self.start_quick_run(ui.ctx());
            }
            if ui
                .add_enabled(
                    self.native_dialogs && self.dialog.is_none(),
                    egui::Button::new("Open report…"),
                )
                .on_hover_text("A report.md written by `udc-studio reproduce`")
                .clicked()
            {
                self.open_dialog(ui.ctx());
            }
        });
        crate::app::widgets::message_ui(ui, self.message.as_ref());
        if let Some(r) = &self.report {
            ui.separator();
            ui.label(format!("{}", r.path.display()));
            let markdown = &mut self.markdown;
            egui::ScrollArea::vertical()
                .auto_shrink([false, true])
                .show(ui, |ui| {
                    egui_commonmark::CommonMarkViewer::new().show(ui, markdown, &r.text);
                });
        }
    }
}

/// Runs `reproduce ID --quick --out DIR --backend B` on this (the job's) thread: the library
/// call the command line makes, reporting to and cancelled by the job's progress. The
/// report's path. A GPU backend resolves on the process's shared device, which the studio
/// made its window's (`app::window_gpu`).
fn quick_run(
    id: ResultId,
    out: &Path,
    backend: Backend,
    p: &Progress,
) -> Result<PathBuf, JobError> {
    let options = crate::cli::reproduce::ReproduceOptions {
        geometry: crate::core::reproduce::Geometry::Ours,
        quick: true,
        threads: None,
        quiet: true,
        backend,
    };
    match crate::cli::reproduce::reproduce(id, out, &options, p) {
        Ok(run) => Ok(run.report),
        // A cancelled run stops between or inside its points; a new run resumes the rest.
        Err(_) if p.is_cancelled() => Err(JobError::Cancelled),
        Err(e) => Err(JobError::Failed(format!(
            "reproduce {} failed: {e:#}",
            id.as_str()
        ))),
    }
}
