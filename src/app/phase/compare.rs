//! "Compare setups" in the Capture & restore view: the setups §4.5 compares (bare T-OLED; double
//! MLA at T = 1 and 5 with λ0 fixed at 530 nm, uniform and optimized; shuffled λ0 order;
//! 200 nm height steps; pitches 56 / 84 / 168 µm) on the view's photo over the thesis's light
//! levels, run by [`compare_setups`] (the CLI's `phase restore --compare`) on a background
//! thread. Rows arrive as they finish; the table, the PSNR-vs-photons plot (Fig. 4.6) and the
//! CSV (the CLI's `compare.csv`) are made from them.

use crate::app::notice::Notice;
use std::path::PathBuf;

use super::{ChannelSet, PhaseWorkspace, Quality};
use crate::app::dialogs::{FileSpec, ask};
use crate::app::job::{Job, JobError, Streaming, Writes};
use crate::core::phase::imaging::{
    CompareRow, Setup, THESIS_PHOTONS, compare_setups, thesis_setups,
};
use crate::io::display::restore_report::compare_csv;
use crate::io::safe_file::write_atomic;

pub use crate::core::phase::figures::CompareMetric;

/// What a comparison was run for.
#[derive(Debug, Clone)]
pub struct CompareRun {
    /// Name of the photo every setup captured.
    pub photo_name: String,
    /// Sampling of the setups' operators.
    pub quality: Quality,
    /// Colour channels of the capture.
    pub channels: ChannelSet,
    /// The ticked setups, in table order.
    pub setups: Vec<Setup>,
    /// The ticked light levels, in photons per white pixel.
    pub photons: Vec<f64>,
    /// The denoiser before the solver.
    pub denoise: crate::core::restore::Denoise,
}

/// The setup comparison (Fig. 4.6, Tables 4.1-4.2): which setups and light levels are ticked,
/// the run in flight or on screen with its rows, and its CSV export.
pub struct CompareState {
    native_dialogs: bool,
    /// The setups on offer (the thesis's) and which are ticked.
    setups: Vec<Setup>,
    selected: Vec<bool>,
    /// The thesis's light levels and which are ticked.
    levels: Vec<(f64, bool)>,
    pub(super) metric: CompareMetric,
    /// The comparison in flight, for its run; its rows stream in as they finish.
    job: Option<Streaming<CompareRun, CompareRow>>,
    /// What the rows on screen were run for (also while they stream in).
    run: Option<CompareRun>,
    rows: Vec<CompareRow>,
    elapsed_s: f64,
    dialog: Option<Job<Option<PathBuf>>>,
    writes: Writes,
    message: Option<Notice>,
}

impl CompareState {
    /// The thesis's setups and light levels, all ticked; no run yet.
    pub fn new(native_dialogs: bool) -> Self {
        let setups = thesis_setups();
        CompareState {
            native_dialogs,
            selected: vec![true; setups.len()],
            setups,
            levels: THESIS_PHOTONS.iter().map(|n| (*n, true)).collect(),
            metric: CompareMetric::PsnrDb,
            job: None,
            run: None,
            rows: Vec::new(),
            elapsed_s: 0.0,
            dialog: None,
            writes: Writes::default(),
            message: None,
        }
    }

    pub(super) fn setups_mut(&mut self) -> impl Iterator<Item = (&Setup, &mut bool)> {
        self.setups.iter().zip(self.selected.iter_mut())
    }

    pub(super) fn levels_mut(&mut self) -> &mut [(f64, bool)] {
        &mut self.levels
    }

    /// The rows so far (they stream in while the comparison runs).
    pub fn rows(&self) -> &[CompareRow] {
        &self.rows
    }

    /// What the rows on screen were run for.
    pub fn run(&self) -> Option<&CompareRun> {
        self.run.as_ref()
    }

    /// Whether a comparison is running.
    pub fn is_running(&self) -> bool {
        self.job.is_some()
    }

    /// The latest message of the comparison or its CSV export.
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    /// True while a comparison CSV is being asked for or written.
    pub fn is_saving(&self) -> bool {
        self.dialog.is_some() || !self.writes.is_empty()
    }

    /// Rows done and rows in all, the running step's fraction and the seconds so far.
    pub(super) fn progress(&self) -> Option<(usize, usize, f32, f64)> {
        self.job.as_ref().map(|j| {
            (
                self.rows.len(),
                j.key().setups.len() * j.key().photons.len(),
                j.job().fraction(),
                j.job().elapsed().as_secs_f64(),
            )
        })
    }

    /// Seconds the last comparison took.
    pub(super) fn elapsed_s(&self) -> f64 {
        self.elapsed_s
    }
}

/// The mean of `metric` over the `rows` that match `keep`, or `None` when none does.
pub fn mean_score(
    rows: &[CompareRow],
    metric: CompareMetric,
    keep: impl Fn(&CompareRow) -> bool,
) -> Option<f64> {
    let at: Vec<f64> = rows
        .iter()
        .filter(|r| keep(r))
        .map(|r| metric.of(r))
        .collect();
    (!at.is_empty()).then(|| at.iter().sum::<f64>() / at.len() as f64)
}

impl PhaseWorkspace {
    /// The setups on offer, in the order of the table.
    pub fn compare_setups(&self) -> &[Setup] {
        &self.compare.setups
    }

    /// Ticks exactly the setups at `indices` (into [`Self::compare_setups`]).
    pub fn select_compare_setups(&mut self, indices: &[usize]) {
        for (i, s) in self.compare.selected.iter_mut().enumerate() {
            *s = indices.contains(&i);
        }
    }

    /// Ticks exactly the thesis light levels in `photons`.
    pub fn select_compare_levels(&mut self, photons: &[f64]) {
        for (n, on) in &mut self.compare.levels {
            *on = photons.contains(n);
        }
    }

    /// The comparison: its selections, rows, run and messages.
    pub fn compare(&self) -> &CompareState {
        &self.compare
    }

    /// Runs the ticked setups over the ticked light levels on the view's photo, with the
    /// current design's camera, κ, sampling convention and rounding, at the chosen quality.
    pub fn run_compare(&mut self, ctx: &egui::Context) {
        if self.compare.job.is_some() {
            return;
        }
        let fail = |this: &mut Self, m: String| this.compare.message = Some(Notice::error(m));
        let Some(photo) = self.capture.photo_arc() else {
            return fail(self, "no photo yet".into());
        };
        if let Err(e) = self.history.current().validate() {
            return fail(self, format!("cannot compare: {e}"));
        }
        let setups: Vec<Setup> = self
            .compare
            .setups
            .iter()
            .zip(&self.compare.selected)
            .filter(|(_, on)| **on)
            .map(|(s, _)| s.clone())
            .collect();
        let photons: Vec<f64> = self
            .compare
            .levels
            .iter()
            .filter(|(_, on)| *on)
            .map(|(n, _)| *n)
            .collect();
        if setups.is_empty() || photons.is_empty() {
            return fail(self, "tick at least one setup and one light level".into());
        }
        let set = self.capture.channels;
        // Algorithm 1 needs channels on the 401:10:691 grid: a custom response is; the peaks
        // are not, so an optimized plan is made for the thesis's response (as the CLI does).
        let grid_set = match set {
            ChannelSet::Custom(_) => set,
            ChannelSet::Peaks | ChannelSet::Spectral => ChannelSet::Spectral,
        };
        let (channels, grid) = match (self.channel_list(set), self.channel_list(grid_set)) {
            (Ok(c), Ok(g)) => (c, g),
            (Err(e), _) | (_, Err(e)) => {
                return fail(self, format!("cannot make the channels: {e}"));
            }
        };
        let run = CompareRun {
            photo_name: photo.name.clone(),
            quality: self.quality,
            channels: set,
            setups: setups.clone(),
            photons: photons.clone(),
            denoise: self.capture.denoise,
        };
        let base = self.history.current().clone();
        let seed = self.capture.seed;
        let denoise = self.capture.denoise;
        let relay = self.relay();
        let wake = ctx.clone();
        let quality = self.quality;
        let job = Streaming::spawn(
            "comparison",
            run.clone(),
            move || wake.request_repaint(),
            move |p, tx| {
                let photos = [photo.planes.clone()];
                compare_setups(
                    &base,
                    &crate::core::phase::PhaseSampling::for_quality(quality),
                    &setups,
                    &grid,
                    &channels,
                    &photos,
                    &photons,
                    seed,
                    denoise,
                    relay.as_ref(),
                    p,
                    |row| {
                        let _ = tx.send(row);
                    },
                )
            },
        );
        self.compare.rows.clear();
        self.compare.run = Some(run);
        self.compare.message = None;
        self.compare.job = Some(job);
    }

    /// Stops the comparison; the rows so far stay.
    pub fn cancel_compare(&mut self) {
        if let Some(j) = self.compare.job.take() {
            let (run, rest) = j.stop();
            self.compare.rows.extend(rest);
            self.compare.message = Some(Notice::info(format!(
                "cancelled after {} of {}",
                self.compare.rows.len(),
                crate::app::widgets::counted(
                    (run.setups.len() * run.photons.len()) as f64,
                    "run",
                    "runs"
                )
            )));
        }
    }

    /// Writes the rows on screen as CSV to `path` on a background thread (no dialog).
    pub fn save_compare_csv_to(&mut self, path: PathBuf, ctx: &egui::Context) {
        let Some(run) = &self.compare.run else {
            self.compare.message = Some(Notice::error("no comparison to save yet"));
            return;
        };
        let text = compare_csv(&self.compare.rows, std::slice::from_ref(&run.photo_name));
        let wake = ctx.clone();
        self.compare.message = Some(Notice::info(format!("writing {}…", path.display())));
        self.compare.writes.spawn(
            move || wake.request_repaint(),
            move || {
                write_atomic(&path, text.as_bytes())?;
                Ok::<_, JobError>(format!("saved {}", path.display()))
            },
        );
    }

    pub(super) fn ask_compare_file(&mut self, ctx: &egui::Context) {
        if !self.compare.native_dialogs {
            self.compare.message = Some(Notice::error("file dialogs are disabled in this session"));
            return;
        }
        if self.compare.dialog.is_some() || self.compare.run.is_none() {
            return;
        }
        let wake = ctx.clone();
        let spec = FileSpec::save(
            "Save the setup comparison",
            ("Setup comparison (CSV)", &["csv"]),
            "compare.csv",
        );
        self.compare.dialog = Some(ask(spec, move || wake.request_repaint()));
    }

    /// Takes streamed rows, the finished run, an answered dialog and finished writes.
    pub(super) fn poll_compare(&mut self, ctx: &egui::Context) {
        if let Some(answer) = self.compare.dialog.as_ref().and_then(Job::poll) {
            self.compare.dialog = None;
            match answer {
                Ok(Some(path)) => self.save_compare_csv_to(path, ctx),
                Ok(None) => {}
                Err(e) => self.compare.message = Some(Notice::error(e.to_string())),
            }
        }
        if let Some(report) = self.compare.writes.poll() {
            self.compare.message = Some(report);
        }
        let Some(job) = &self.compare.job else {
            return;
        };
        self.compare.rows.extend(job.arrived());
        ctx.request_repaint_after(std::time::Duration::from_millis(500));
        let Some(done) = job.ended() else {
            return;
        };
        let Some(job) = self.compare.job.take() else {
            return;
        };
        self.compare.rows.extend(job.arrived());
        match done {
            Ok(()) => {
                self.compare.elapsed_s = job.job().elapsed().as_secs_f64();
                self.compare.message = Some(Notice::info(format!(
                    "{} in {:.0} s",
                    crate::app::widgets::counted(self.compare.rows.len() as f64, "run", "runs"),
                    self.compare.elapsed_s
                )));
            }
            Err(JobError::Cancelled) => {}
            Err(e) => self.compare.message = Some(Notice::error(e.to_string())),
        }
    }
}
