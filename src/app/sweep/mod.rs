//! The Sweep workspace (issue 19): opens a results folder written by `udc-studio sweep`, shows
//! its table (sortable, filterable), its plots, and opens any row's design in the Display
//! workspace. Reading the folder, filtering, sorting, the plots' data and rebuilding a design
//! all run on jobs; the UI thread only draws. The previous table stays when a read fails.

mod action;
pub mod derive;
mod open;
mod plots_view;
pub mod study;
pub mod study_dialog;
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
pub use open::{OpenedDesign, RowDesign, results_dir};
use table::{Sort, SweepTable};

/// The user's own plot: two columns, as a line (mean ± SD over the rows at each x) or
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
    /// A row's design being rebuilt, and whether it is to be pinned as A rather than opened.
    opening: Option<(bool, Job<OpenedDesign>)>,
    message: Option<Notice>,
    /// What the panels and menus queued this frame, carried out after the UI.
    actions: Vec<SweepAction>,
    panels: Panels,
    /// New study….
    pub study_dialog: study_dialog::StudyDialog,
    /// The study running, if any.
    study: Option<study::StudyRun>,
    /// Hold a study's workers after this many new points until it is cancelled: a run that is
    /// certain to be interrupted midway (the interruption tests).
    pub hold_after_points: Option<u64>,
    /// How the last study ended, shown once its folder has been read again.
    study_end: Option<Notice>,
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
    /// The study running: its share done and seconds since it started.
    pub study: Option<(f32, f64)>,
    /// Whether the open table's study can be resumed here (it is not complete and its
    /// folder holds its spec).
    pub resumable: bool,
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
            study: self
                .study
                .as_ref()
                .map(|r| (r.fraction(), r.elapsed().as_secs_f64())),
            resumable: self.study.is_none()
                && self
                    .table
                    .as_ref()
                    .is_some_and(|t| !t.manifest.complete && t.dir.join(study::SPEC_FILE).exists()),
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
            SweepAction::OpenRow(index) => self.open_row(index, false, shell.waker()),
            SweepAction::PinRow(index) => self.open_row(index, true, shell.waker()),
            SweepAction::Filter(filter) => self.filter = filter,
            SweepAction::Sort(sort) => self.sort = sort,
            SweepAction::Custom(custom) => self.custom = custom,
            SweepAction::NewStudy => shell.send(WorkspaceId::Display, Request::StudyCurrentDesign),
            SweepAction::CancelStudy => {
                if let Some(r) = &self.study {
                    r.cancel();
                }
            }
            SweepAction::ResumeStudy => self.resume_study(shell),
            SweepAction::RunExample(name) => self.run_example(name, shell),
            SweepAction::OpenReproduce => shell.open_reproduce(),
        }
    }

    /// Carries out what the panels and menus queued this frame.
    pub fn apply_queued(&mut self, shell: &mut Shell) {
        for action in std::mem::take(&mut self.actions) {
            self.act(action, shell);
        }
    }

    /// Runs `study` of `design` in a new folder under the studio's data folder (or a scratch
    /// one when nothing is kept), and shows its rows as they land.
    pub fn start_study(&mut self, request: study_dialog::RunRequest, shell: &mut Shell) {
        if self.study.is_some() {
            self.message = Some(Notice::error(
                "a study is running: cancel it or wait for it before starting another",
            ));
            return;
        }
        let dir = self.new_study_dir(shell, "study");
        let backend = shell.compute.effective();
        match study::write_study(&dir, &request.study, request.photo.as_deref(), backend) {
            Ok(spec) if request.cluster => self.message = Some(study::write_cluster(&dir, &spec)),
            Ok(spec) => self.run_study(dir, spec, shell),
            Err(e) => self.message = Some(Notice::error(format!("cannot start the study: {e}"))),
        }
    }

    /// Runs the shipped example `name` in a new folder under the studio's data folder.
    fn run_example(&mut self, name: &str, shell: &mut Shell) {
        let Some((_, text)) = crate::io::sweep::EXAMPLES.iter().find(|(n, _)| *n == name) else {
            return;
        };
        let spec = match crate::io::sweep::parse_spec(text, true) {
            Ok(s) => s.computed_on(shell.compute.effective()),
            Err(e) => {
                self.message = Some(Notice::error(format!("{name}: {e}")));
                return;
            }
        };
        let dir = self.new_study_dir(shell, name.trim_end_matches(".toml"));
        if let Err(e) = std::fs::create_dir_all(&dir) {
            self.message = Some(Notice::error(format!(
                "cannot create {}: {e}",
                dir.display()
            )));
            return;
        }
        self.run_study(dir, spec, shell);
    }

    /// A new folder for a study's results under the studio's data folder (a scratch one when
    /// the session keeps nothing), named `stem` and the time.
    fn new_study_dir(&self, shell: &Shell, stem: &str) -> PathBuf {
        let stamp = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_millis());
        shell
            .dirs
            .data_dir
            .clone()
            .unwrap_or_else(std::env::temp_dir)
            .join("studies")
            .join(format!("{stem}-{stamp}"))
    }

    /// Runs `spec` into `dir` and opens the folder as its first rows land.
    fn run_study(&mut self, dir: PathBuf, spec: crate::core::sweep::SweepSpec, shell: &mut Shell) {
        let dir = std::fs::canonicalize(&dir).unwrap_or(dir);
        // Where its points' PSFs are computed, as its spec says (a resumed study keeps its own).
        let on = match spec.base.get("backend") {
            Some(crate::core::sweep::ParamValue::Text(b)) if b != "cpu" => format!(
                ", PSFs on {}",
                shell.compute.adapter_name().unwrap_or_else(|| b.clone())
            ),
            _ => String::new(),
        };
        self.message = Some(Notice::info(format!(
            "running {} points into {}{on}",
            crate::core::sweep::Points::new(&spec).map_or(0, |p| p.count()),
            dir.display()
        )));
        shell.settings.last_sweep = Some(dir.clone());
        shell.save_settings();
        self.study = Some(study::StudyRun::start(
            dir,
            spec,
            self.hold_after_points,
            shell.waker(),
        ));
    }

    /// Runs what is left of the open table's study (its folder's spec).
    fn resume_study(&mut self, shell: &mut Shell) {
        let Some(dir) = self.table.as_ref().map(|t| t.dir.clone()) else {
            return;
        };
        match study::saved_spec(&dir) {
            Ok(Some(spec)) => self.run_study(dir, spec, shell),
            Ok(None) => {
                self.message = Some(Notice::error(format!(
                    "{} holds no {}: resume it with udc-studio sweep",
                    dir.display(),
                    study::SPEC_FILE
                )));
            }
            Err(e) => self.message = Some(Notice::error(e.to_string())),
        }
    }

    /// Whether a study is running.
    pub fn is_studying(&self) -> bool {
        self.study.is_some()
    }

    /// Takes the running study's news: re-reads its folder as rows land, and its end.
    fn poll_study(&mut self, shell: &mut Shell) {
        let Some(run) = &mut self.study else {
            return;
        };
        let dir = run.dir.clone();
        // Rows that land while a read runs wait for the next one.
        let reread = !self.load.is_running() && run.take_new_rows();
        let end = run.poll();
        let landed = run.landed();
        let unread = landed > run.read_rows();
        if reread {
            self.open_folder(&dir, shell.waker());
        }
        let Some(end) = end else {
            // Rows that landed just after a read are read once the pause is over, even if no
            // other row lands to wake the UI.
            if unread {
                shell.ctx.request_repaint_after(study::REREAD_EVERY);
            }
            return;
        };
        self.study = None;
        self.study_end = Some(match end {
            Ok(s) if s.complete => Notice::info(format!(
                "the study is complete: {} points ({} failed) in {:.1} s",
                s.rows, s.failed_total, s.elapsed_s
            )),
            Ok(s) => Notice::info(format!(
                "{} of {} points: Resume runs the rest",
                s.rows, s.total
            )),
            Err(JobError::Cancelled) => Notice::info(format!(
                "the study was cancelled after {landed} new points; Resume runs the rest"
            )),
            Err(e) => Notice::error(format!("the study stopped: {e}")),
        });
        self.message.clone_from(&self.study_end);
        // The last rows, and the manifest's final word on completeness.
        self.open_folder(&dir, shell.waker());
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
    /// opens in the workspace that made it, or (`pin`) is pinned as A for Compare.
    pub fn open_row(&mut self, index: usize, pin: bool, wake: impl Fn() + Send + 'static) {
        let Some(table) = self.table.clone() else {
            return;
        };
        let job = Job::spawn("design builder", wake, move |p| {
            open::open_row(&table, index, p)
        });
        self.opening = Some((pin, job));
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
                    // A running study's own message (its progress) stays, and how one
                    // ended replaces the reader's.
                    if let Some(end) = self.study_end.take() {
                        self.message = Some(end);
                    } else if self.study.is_none() {
                        self.message = Some(Notice::info(format!(
                            "read {} rows ({} failed) of sweep `{}` from {}",
                            t.rows.len(),
                            t.manifest.failed,
                            t.manifest.spec.name,
                            t.dir.display()
                        )));
                    }
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
        self.poll_study(shell);
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
        let Some(done) = self.opening.as_ref().and_then(|(_, j)| j.poll()) else {
            return;
        };
        let pin = self.opening.take().is_some_and(|(pin, _)| pin);
        let o = match done {
            Ok(o) => o,
            Err(e) => {
                self.message = Some(Notice::error(format!("cannot open the design: {e}")));
                return;
            }
        };
        let name = self
            .table
            .as_ref()
            .map(|t| t.manifest.spec.name.clone())
            .unwrap_or_default();
        let what = format!("point {} of sweep `{name}`", o.point);
        if !o.hash_matches {
            shell.set_status(Notice::error(format!(
                "{what}: the design differs from the one the sweep computed (its preset or \
                 file changed since)"
            )));
        }
        let (request, target, verb) = match o.design {
            RowDesign::Display(design) if pin => (
                Request::PinDesign {
                    design: Box::new(design),
                    what: what.clone(),
                },
                WorkspaceId::Display,
                "pinning",
            ),
            RowDesign::Display(design) => (
                Request::OpenDesign {
                    design: Box::new(design),
                    what: what.clone(),
                },
                WorkspaceId::Display,
                "opened",
            ),
            RowDesign::Phase(design) => (
                Request::OpenPhaseDesign {
                    design: Box::new(design),
                    what: what.clone(),
                },
                WorkspaceId::Phase,
                "opened",
            ),
        };
        self.message = Some(if o.hash_matches {
            Notice::info(format!("{verb} {what}"))
        } else {
            Notice::error(format!(
                "{verb} {what}, but its design hash differs from the row's: the preset or a \
                 file changed since the sweep ran"
            ))
        });
        shell.send(target, request);
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
