//! The Sweep workspace (issue 19): opens a results folder written by `udc-studio sweep`, shows
//! its table (sortable, filterable), its plots, and opens any row's design in the Display
//! workspace. Reading the folder, filtering, sorting, the plots' data and rebuilding a design
//! all run on jobs; the UI thread only draws. The previous table stays when a read fails.

mod action;
pub mod derive;
mod open;
mod plots_view;
pub mod table;
mod table_view;
mod workspace;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::app::error::StudioError;
use crate::app::job::{Job, JobError, Keyed};
use crate::app::notice::Notice;
use crate::app::workspace::{Request, Shell, WorkspaceId};
use crate::core::sweep::{PlotKind, PlotSpec};
use crate::io::sweep::plots::plots_for;
pub use action::SweepAction;
use derive::{View, ViewRequest};
pub use open::{OpenedDesign, results_dir};
use table::{Sort, SweepTable};

/// The user's own plot: two columns, as a line (mean and min–max over the rows at each x) or
/// as points with their Pareto front.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CustomPlot {
    /// The x column's name (empty: no custom plot yet).
    pub x: String,
    /// The y column's name.
    pub y: String,
    /// Points and their Pareto front instead of a line.
    pub pareto: bool,
}

/// The Sweep workspace's state.
#[derive(Default)]
pub struct SweepWorkspace {
    table: Option<Arc<SweepTable>>,
    load: Keyed<PathBuf, SweepTable>,
    dialog: Option<Job<Option<PathBuf>>>,
    view: Option<View>,
    view_job: Keyed<ViewRequest, View>,
    /// The filter box's text (see [`table::Filter`]).
    pub filter: String,
    /// The table's sort order.
    pub sort: Sort,
    /// The user's plot below the spec's.
    pub custom: CustomPlot,
    opening: Option<Job<OpenedDesign>>,
    message: Option<Notice>,
    /// What the panels and menus queued this frame, carried out after the UI.
    actions: Vec<SweepAction>,
    panels: Panels,
}

/// The workspace's panels: each draws from a [`SweepCtx`] and queues [`SweepAction`]s.
#[derive(Default)]
struct Panels {
    controls: table_view::ControlsPanel,
    table: table_view::TablePanel,
    plots: plots_view::PlotsPanel,
}

/// What a panel may look at, and where it sends what it wants done.
pub struct SweepCtx<'a> {
    /// The table on screen, if a folder was read.
    pub table: Option<&'a Arc<SweepTable>>,
    /// The filtered and sorted rows and the plots' data, once derived.
    pub view: Option<&'a View>,
    /// A newer view is being derived.
    pub deriving: bool,
    /// The folder being read and the share read.
    pub reading: Option<(&'a Path, f32)>,
    /// A folder dialog is open.
    pub asking: bool,
    /// The last results folder opened (Reopen last).
    pub last_sweep: Option<&'a PathBuf>,
    /// The message line.
    pub message: Option<&'a Notice>,
    /// The filter in force.
    pub filter: &'a str,
    /// The sort in force.
    pub sort: Sort,
    /// The user's plot in force.
    pub custom: &'a CustomPlot,
    /// Where the panel queues what it wants done; carried out after the frame's UI.
    pub actions: &'a mut Vec<SweepAction>,
}

impl SweepWorkspace {
    /// Draws its three panels (controls left, plots below, the table in the centre) from one
    /// context.
    pub(super) fn panels_ui(&mut self, ui: &mut egui::Ui, shell: &Shell) {
        let mut ctx = SweepCtx {
            table: self.table.as_ref(),
            view: self.view.as_ref(),
            deriving: self.view_job.is_running(),
            reading: self
                .load
                .current()
                .map(|(dir, job)| (dir.as_path(), job.fraction())),
            asking: self.dialog.is_some(),
            last_sweep: shell.settings.last_sweep.as_ref(),
            message: self.message.as_ref(),
            filter: &self.filter,
            sort: self.sort,
            custom: &self.custom,
            actions: &mut self.actions,
        };
        let panels = &mut self.panels;
        let total = ui.available_width();
        crate::app::workspace::side_panel(
            egui::Panel::left("sweep_controls"),
            total,
            0.26,
            260.0,
            380.0,
        )
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| panels.controls.ui(ui, &mut ctx));
        });
        let height = ui.available_height();
        // Half the height for the plots: the table scrolls, a squeezed plot shows nothing.
        egui::Panel::bottom("sweep_plots")
            .exact_size((height * 0.5).clamp(220.0, 640.0))
            .show(ui, |ui| panels.plots.ui(ui, &mut ctx));
        egui::CentralPanel::default().show(ui, |ui| panels.table.ui(ui, &mut ctx));
    }

    /// Carries out one action now, as the queue does after the frame's UI.
    pub fn act(&mut self, action: SweepAction, shell: &mut Shell) {
        match action {
            SweepAction::AskFolder => self.ask_folder(shell),
            SweepAction::OpenFolder(path) => self.open_folder(&path, shell.waker()),
            SweepAction::CancelLoad => self.cancel_load(),
            SweepAction::OpenRow(index) => self.open_row(index, shell.waker()),
            SweepAction::Filter(filter) => self.filter = filter,
            SweepAction::Sort(sort) => self.sort = sort,
            SweepAction::Custom(custom) => self.custom = custom,
        }
    }

    /// Carries out what the panels and menus queued this frame.
    pub fn apply_queued(&mut self, shell: &mut Shell) {
        for action in std::mem::take(&mut self.actions) {
            self.act(action, shell);
        }
    }

    /// The table on screen, if a folder was read.
    pub fn table(&self) -> Option<&Arc<SweepTable>> {
        self.table.as_ref()
    }

    /// The rows shown, in order (indices into the table's rows), once computed.
    pub fn shown_rows(&self) -> Option<&[usize]> {
        self.view.as_ref().map(|v| v.rows.as_slice())
    }

    /// The plots shown, with their data or why they cannot be drawn.
    pub fn plots(
        &self,
    ) -> Option<
        &[(
            PlotSpec,
            Result<crate::io::sweep::plots::PlotData, StudioError>,
        )],
    > {
        self.view.as_ref().map(|v| v.plots.as_slice())
    }

    /// The workspace's message line.
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    /// Whether nothing is being read or computed and the view matches the controls.
    pub fn is_idle(&self) -> bool {
        !self.load.is_running()
            && self.opening.is_none()
            && !self.view_job.is_running()
            && (self.table.is_none()
                || self
                    .view
                    .as_ref()
                    .is_some_and(|v| v.request == self.request()))
    }

    /// Reads a results folder (or the folder of a `sweep.json` / `results.csv`) on a job; the
    /// table on screen stays until it has been read.
    pub fn open_folder(&mut self, path: &Path, wake: impl Fn() + Send + 'static) {
        let Some(dir) = results_dir(path) else {
            self.message = Some(Notice::error(format!(
                "not a sweep's results: choose its folder, sweep.json or results.csv ({})",
                path.display()
            )));
            return;
        };
        let d = dir.clone();
        let job = Job::spawn("sweep reader", wake, move |p| open::read_folder(&d, p));
        self.load.start(dir, job);
    }

    /// Rebuilds the design of row `index` (into the table's rows) on a job; once built, it
    /// opens in the Display workspace.
    pub fn open_row(&mut self, index: usize, wake: impl Fn() + Send + 'static) {
        let Some(table) = self.table.clone() else {
            return;
        };
        self.opening = Some(Job::spawn("design builder", wake, move |_| {
            open::open_row(&table, index)
        }));
    }

    /// The plots the controls ask for: the spec's (or the defaults), then the user's.
    fn request(&self) -> ViewRequest {
        let mut plots = self
            .table
            .as_ref()
            .map(|t| plots_for(&t.manifest))
            .unwrap_or_default();
        if !self.custom.x.is_empty() && !self.custom.y.is_empty() {
            plots.push(PlotSpec {
                kind: if self.custom.pareto {
                    PlotKind::Pareto
                } else {
                    PlotKind::MetricVsAxis
                },
                x: self.custom.x.clone(),
                y: self.custom.y.clone(),
                group: None,
                spread: None,
                x_smaller_is_better: false,
            });
        }
        ViewRequest {
            filter: self.filter.clone(),
            sort: self.sort,
            plots,
        }
    }

    /// Takes finished jobs and starts the view's job when the controls changed.
    fn poll(&mut self, shell: &mut Shell) {
        if let Some(answer) = self.dialog.as_ref().and_then(Job::poll) {
            self.dialog = None;
            match answer {
                Ok(Some(path)) => self.open_folder(&path, shell.waker()),
                Ok(None) => {}
                Err(e) => self.message = Some(Notice::error(e.to_string())),
            }
        }
        if let Some((dir, done)) = self.load.poll() {
            match done {
                Ok(t) => {
                    self.message = Some(Notice::info(format!(
                        "read {} rows ({} failed) of sweep `{}` from {}",
                        t.rows.len(),
                        t.manifest.failed,
                        t.manifest.spec.name,
                        t.dir.display()
                    )));
                    self.default_custom_plot(&t);
                    self.table = Some(Arc::new(t));
                    self.view = None;
                    self.view_job.stop();
                    shell.settings.last_sweep = Some(dir);
                    shell.save_settings();
                }
                Err(JobError::Cancelled) => {
                    self.message = Some(Notice::info("reading the results was cancelled"));
                }
                Err(e) => {
                    self.message = Some(Notice::error(format!(
                        "cannot open the sweep results in {}: {e}",
                        dir.display()
                    )));
                }
            }
        }
        if let Some((_, done)) = self.view_job.poll() {
            match done {
                Ok(v) => self.view = Some(v),
                Err(JobError::Cancelled) => {}
                Err(e) => self.message = Some(Notice::error(e.to_string())),
            }
        }
        self.poll_opening(shell);
        self.refresh_view(shell);
    }

    /// A newer request replaces a running one (dropping a job cancels it).
    fn refresh_view(&mut self, shell: &Shell) {
        let Some(table) = self.table.clone() else {
            return;
        };
        let request = self.request();
        let current = self.view.as_ref().is_some_and(|v| v.request == request);
        let running = self.view_job.is_running_for(|r| *r == request);
        if current || running {
            return;
        }
        let r = request.clone();
        let job = Job::spawn("sweep view", shell.waker(), move |p| {
            derive::derive(&table, r, p)
        });
        self.view_job.start(request, job);
    }

    fn poll_opening(&mut self, shell: &mut Shell) {
        let Some(done) = self.opening.as_ref().and_then(Job::poll) else {
            return;
        };
        self.opening = None;
        match done {
            Ok(o) => {
                let name = self
                    .table
                    .as_ref()
                    .map(|t| t.manifest.spec.name.clone())
                    .unwrap_or_default();
                let what = format!("point {} of sweep `{name}`", o.point);
                self.message = Some(if o.hash_matches {
                    Notice::info(format!("opened {what} in Display layouts"))
                } else {
                    Notice::error(format!(
                        "opened {what}, but its design hash differs from the row's: the \
                         preset or a file changed since the sweep ran"
                    ))
                });
                if !o.hash_matches {
                    shell.set_status(Notice::error(format!(
                        "{what}: the design differs from the one the sweep computed (its \
                         preset or file changed since)"
                    )));
                }
                shell.send(
                    WorkspaceId::Display,
                    Request::OpenDesign {
                        design: Box::new(o.design),
                        what,
                    },
                );
            }
            Err(e) => {
                self.message = Some(Notice::error(format!("cannot open the design: {e}")));
            }
        }
    }

    /// Starts the user's plot where the spec's default plot is not: the second metric
    /// against the last axis (often the seed), so it shows something new.
    fn default_custom_plot(&mut self, t: &SweepTable) {
        let s = &t.manifest.schema;
        let x_ok = t.column(&self.custom.x).is_some();
        let y_ok = t.column(&self.custom.y).is_some();
        if !(x_ok && y_ok) {
            self.custom.x = s.params.last().map(|(n, _)| n.clone()).unwrap_or_default();
            self.custom.y = s
                .metrics
                .get(1)
                .or(s.metrics.first())
                .cloned()
                .unwrap_or_default();
        }
    }

    /// Asks for a results folder with the desktop's folder dialog, on a helper thread.
    fn ask_folder(&mut self, shell: &Shell) {
        if !shell.native_dialogs {
            self.message = Some(Notice::error("file dialogs are disabled in this session"));
            return;
        }
        if self.dialog.is_some() {
            return;
        }
        let start = self.table.as_ref().map(|t| t.dir.clone());
        self.dialog = Some(Job::spawn("folder dialog", shell.waker(), move |_| {
            let started = std::time::Instant::now();
            let mut d = rfd::FileDialog::new().set_title("Open sweep results (a folder)");
            if let Some(dir) = start {
                d = d.set_directory(dir);
            }
            let answer = d.pick_folder();
            // A dialog that answers this fast never appeared: nobody cancels that quickly.
            if answer.is_none() && started.elapsed() < std::time::Duration::from_millis(250) {
                return Err(JobError::Failed(crate::app::dialogs::NO_DIALOG.into()));
            }
            Ok(answer)
        }));
    }

    /// Cancels reading a folder; the table on screen stays.
    fn cancel_load(&mut self) {
        if let Some(job) = self.load.job() {
            job.cancel();
        }
    }
}
