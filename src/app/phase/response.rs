//! A custom sensor response for the phase workspace: "Open response CSV…" asks for a file on a
//! helper thread, reads it on another, and makes the R, G, B channels on the 401:10:691 nm grid.
//! A bad file leaves the channels as they were and says which line and column is wrong.

use crate::app::notice::Notice;
use std::path::{Path, PathBuf};

use egui::Ui;

use super::{ChannelSet, PhaseAction, PhaseCtx, PhaseWorkspace};
use crate::app::dialogs::{FileSpec, ask};
use crate::app::error::StudioError;
use crate::app::job::Job;
use crate::core::design::Channel;
use crate::core::phase::wavelength_grid_nm;
use crate::io::IoError;
use crate::io::design::spectral;
use crate::io::error::TableError;

/// A loaded response: its file and the channels it makes.
pub struct CustomResponse {
    /// Which load this is: [`ChannelSet::Custom`] carries it, so a new file is a new choice.
    pub serial: u32,
    /// The CSV file it was read from.
    pub path: PathBuf,
    /// The R, G, B channels it makes on the phase workspace's wavelength grid.
    pub channels: Vec<Channel>,
}

impl CustomResponse {
    /// The file's name, for the channel choice.
    pub fn file_name(&self) -> String {
        self.path.file_name().map_or_else(
            || self.path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        )
    }
}

pub(super) struct ResponseState {
    native_dialogs: bool,
    dialog: Option<Job<Option<PathBuf>>>,
    /// A response file being read: its path and channels.
    load: Option<Job<(PathBuf, Vec<Channel>)>>,
    custom: Option<CustomResponse>,
    serial: u32,
    message: Option<Notice>,
}

/// Reads a response CSV and makes its channels on the phase wavelength grid.
///
/// # Errors
/// The table's error naming the file: unreadable, malformed, or giving no channels on the grid.
fn read_channels(path: &Path) -> Result<Vec<Channel>, IoError> {
    let resp = spectral::load_response_csv(path)?;
    spectral::channels_from_response(&resp, &wavelength_grid_nm()).map_err(|e| IoError::Table {
        path: path.to_path_buf(),
        error: TableError::Spectral(e),
    })
}

impl ResponseState {
    pub fn new(native_dialogs: bool) -> Self {
        ResponseState {
            native_dialogs,
            dialog: None,
            load: None,
            custom: None,
            serial: 0,
            message: None,
        }
    }

    /// The channels of load `serial`, if it is the loaded one.
    pub fn channels(&self, serial: u32) -> Result<Vec<Channel>, StudioError> {
        match &self.custom {
            Some(c) if c.serial == serial => Ok(c.channels.clone()),
            _ => Err(StudioError::ResponseGone),
        }
    }

    /// True while a response file is being asked for or read.
    pub fn is_loading(&self) -> bool {
        self.dialog.is_some() || self.load.is_some()
    }

    /// The label of a channel choice (a custom one names its file).
    pub fn label(&self, set: ChannelSet) -> String {
        match (set, &self.custom) {
            (ChannelSet::Custom(s), Some(c)) if c.serial == s => {
                format!("{} (custom response)", c.file_name())
            }
            _ => set.label().into(),
        }
    }
}

impl PhaseWorkspace {
    /// The loaded custom response, if any.
    pub fn custom_response(&self) -> Option<&CustomResponse> {
        self.response.custom.as_ref()
    }

    /// The latest message about a response CSV, and whether it is an error.
    pub fn response_message(&self) -> Option<&Notice> {
        self.response.message.as_ref()
    }

    /// True while a response file is being asked for or read.
    pub fn is_loading_response(&self) -> bool {
        self.response.is_loading()
    }

    /// Reads the response CSV at `path` on a background thread; on success its channels become
    /// the chosen ones, on failure the message names the problem and the channels stay.
    pub fn load_response_from(&mut self, path: PathBuf, ctx: &egui::Context) {
        let wake = ctx.clone();
        self.response.message = Some(Notice::info(format!("reading {}…", path.display())));
        self.response.load = Some(Job::spawn(
            "response reader",
            move || wake.request_repaint(),
            move |_| read_channels(&path).map(|c| (path, c)),
        ));
    }

    pub(super) fn ask_response(&mut self, ctx: &egui::Context) {
        if !self.response.native_dialogs {
            self.response.message =
                Some(Notice::error("file dialogs are disabled in this session"));
            return;
        }
        if self.response.dialog.is_some() {
            return;
        }
        let wake = ctx.clone();
        let spec = FileSpec::open(
            "Open a sensor response",
            ("Spectral response (CSV)", &["csv"]),
        );
        self.response.dialog = Some(ask(spec, move || wake.request_repaint()));
    }

    /// Takes an answered dialog and a finished read.
    pub(super) fn poll_response(&mut self, ctx: &egui::Context) {
        if let Some(answer) = self.response.dialog.as_ref().and_then(Job::poll) {
            self.response.dialog = None;
            match answer {
                Ok(Some(path)) => self.load_response_from(path, ctx),
                Ok(None) => {}
                Err(e) => self.response.message = Some(Notice::error(e.to_string())),
            }
        }
        let Some(done) = self.response.load.as_ref().and_then(Job::poll) else {
            return;
        };
        self.response.load = None;
        match done {
            Ok((path, channels)) => {
                self.response.serial += 1;
                let c = CustomResponse {
                    serial: self.response.serial,
                    path,
                    channels,
                };
                self.response.message = Some(Notice::info(format!(
                    "loaded {}: R, G, B on {} wavelengths",
                    c.file_name(),
                    wavelength_grid_nm().len()
                )));
                self.channels = ChannelSet::Custom(c.serial);
                self.response.custom = Some(c);
            }
            Err(e) => {
                self.response.message = Some(Notice::error(format!(
                    "cannot use the response: {e}; the channels stay"
                )));
            }
        }
    }
}

/// The channel choice: peaks, the thesis response, a loaded file, and "Open response CSV…".
pub(super) fn channel_choice_ui(ui: &mut Ui, channels: &mut ChannelSet, ctx: &mut PhaseCtx<'_>) {
    ui.vertical(|ui| {
        let mut sets = vec![ChannelSet::Peaks, ChannelSet::Spectral];
        if let Some(c) = &ctx.response.custom {
            sets.push(ChannelSet::Custom(c.serial));
        }
        for set in sets {
            let label = ctx.response.label(set);
            ui.selectable_value(channels, set, label);
        }
        if ui
            .add_enabled(
                !ctx.response.is_loading(),
                egui::Button::new("Open response CSV…"),
            )
            .on_hover_text("A sensor response table: wavelength_nm, r, g, b (covering 401-691 nm)")
            .clicked()
        {
            ctx.queue(PhaseAction::AskResponse);
        }
        crate::app::widgets::message_ui(ui, ctx.response.message.as_ref());
    });
}
