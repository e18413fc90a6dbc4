//! Native file dialogs, always on a helper thread: a modal dialog on the UI thread would freeze
//! rendering (and hang headless tests). The app polls for the answer each frame.

use super::job::{Job, JobError};
use std::path::PathBuf;

/// What the chosen path is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Purpose {
    /// A design file (`.json`) to open.
    Open,
    /// Where to save the design (`.json`).
    SaveAs,
    /// An image or GDSII/DXF mask to import as the opening.
    ImportPattern,
    /// A spectral response CSV (`wavelength_nm, r, g, b`) for the colour channels.
    Spectral,
    /// A photo for the Restore view (the view polls its own dialog).
    Photo,
    /// An HDR scene for the sensor previewer (it polls its own dialog).
    Hdr,
    /// Where to write this export of the current result.
    Export(ExportKind),
    /// Where to write the photolithography mask, in this file format.
    Mask(crate::io::mask::MaskFormat),
}

/// What the display workspace can export from the result on screen, each a save dialog of
/// its own (kept here, beside the dialog's purposes, so the dialogs need no workspace).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExportKind {
    /// The sensor PSF as a float OpenEXR image (RGB for three channels, else the first channel).
    PsfExr,
    /// The sensor PSF as a 16-bit PNG, one file per colour channel.
    PsfPng16,
    /// The log-scaled PSF as an 8-bit PNG, one file per colour channel.
    LogPsfPng,
    /// The MTF table as CSV: horizontal and vertical slices, radial min and mean per channel.
    MtfCsv,
    /// The analysis numbers as JSON, the same object `analyze --json` prints.
    NumbersJson,
}

impl ExportKind {
    /// Every export, in the order of the File > Export menu.
    pub const ALL: [ExportKind; 5] = [
        ExportKind::PsfExr,
        ExportKind::PsfPng16,
        ExportKind::LogPsfPng,
        ExportKind::MtfCsv,
        ExportKind::NumbersJson,
    ];

    /// Menu entry text, ending in an ellipsis because it opens a save dialog.
    pub fn label(self) -> &'static str {
        match self {
            ExportKind::PsfExr => "PSF (float EXR)…",
            ExportKind::PsfPng16 => "PSF (16-bit PNG)…",
            ExportKind::LogPsfPng => "log-PSF (PNG)…",
            ExportKind::MtfCsv => "MTF (CSV)…",
            ExportKind::NumbersJson => "Numbers (JSON)…",
        }
    }

    /// File extension (without the dot) the save dialog suggests.
    pub fn extension(self) -> &'static str {
        match self {
            ExportKind::PsfExr => "exr",
            ExportKind::PsfPng16 | ExportKind::LogPsfPng => "png",
            ExportKind::MtfCsv => "csv",
            ExportKind::NumbersJson => "json",
        }
    }
}

/// What a native file dialog asks for.
#[derive(Debug, Clone)]
pub struct FileSpec {
    /// Title bar text.
    pub title: &'static str,
    /// The filter's name and its extensions (without dots).
    pub filter: (&'static str, Vec<&'static str>),
    /// `Some(suggested file name)` for a save dialog, `None` to pick an existing file.
    pub save_as: Option<String>,
    /// The folder it opens in.
    pub start_dir: Option<PathBuf>,
}

impl FileSpec {
    /// A dialog that picks an existing file.
    pub fn open(title: &'static str, filter: (&'static str, &[&'static str])) -> Self {
        FileSpec {
            title,
            filter: (filter.0, filter.1.to_vec()),
            save_as: None,
            start_dir: None,
        }
    }

    /// A dialog that asks where to write a new file, suggesting `file_name`.
    pub fn save(
        title: &'static str,
        filter: (&'static str, &[&'static str]),
        file_name: impl Into<String>,
    ) -> Self {
        FileSpec {
            title,
            filter: (filter.0, filter.1.to_vec()),
            save_as: Some(file_name.into()),
            start_dir: None,
        }
    }
}

/// What the user is told when no dialog could be shown.
pub const NO_DIALOG: &str = "no file dialog could open: this desktop has no \
    xdg-desktop-portal (on Debian or Ubuntu: sudo apt install xdg-desktop-portal-gtk). Until \
    then, drop the file onto the window";

/// A dialog that answers faster than this never appeared: nobody cancels that quickly.
const NOT_SHOWN: std::time::Duration = std::time::Duration::from_millis(250);

/// Shows the dialog on a helper thread: the answer arrives as `Ok(None)` when cancelled, and as
/// an error saying what to install when no dialog could appear (no portal on this desktop).
pub fn ask(spec: FileSpec, wake: impl Fn() + Send + 'static) -> Job<Option<PathBuf>> {
    Job::spawn("file dialog", wake, move |_| {
        let started = std::time::Instant::now();
        let mut d = rfd::FileDialog::new()
            .add_filter(spec.filter.0, &spec.filter.1)
            .set_title(spec.title);
        if let Some(dir) = spec.start_dir {
            d = d.set_directory(dir);
        }
        let answer = match spec.save_as {
            Some(name) => d.set_file_name(name).save_file(),
            None => d.pick_file(),
        };
        if answer.is_none() && started.elapsed() < NOT_SHOWN {
            return Err(JobError::Failed(NO_DIALOG.into()));
        }
        Ok(answer)
    })
}

impl Purpose {
    /// The dialog this purpose shows.
    fn spec(self, file_name: Option<String>) -> FileSpec {
        const IMAGES_AND_MASKS: &[&str] = &[
            "png", "bmp", "tif", "tiff", "jpg", "jpeg", "gds", "gds2", "oas", "dxf",
        ];
        match self {
            Purpose::Open => FileSpec::open("Open design", ("UDC design", &["json"])),
            Purpose::ImportPattern => FileSpec::open(
                "Import opening: an image, or the axis pixel of a mask",
                ("Openings (images, GDSII, OASIS, DXF)", IMAGES_AND_MASKS),
            ),
            Purpose::Spectral => FileSpec::open(
                "Load spectral response (wavelength_nm, r, g, b)",
                ("Spectral response CSV", &["csv"]),
            ),
            Purpose::Photo => FileSpec::open(
                "Open a photo to capture through the display",
                ("Photos", &["png", "jpg", "jpeg"]),
            ),
            Purpose::Hdr => FileSpec::open(
                "Open an HDR scene (Radiance .hdr or OpenEXR .exr)",
                ("HDR scenes", &["hdr", "exr"]),
            ),
            Purpose::SaveAs => FileSpec::save(
                "Save design as",
                ("UDC design", &["json"]),
                // `.udc.json`: the desktop's MIME database maps it to the studio by name (plain
                // `.json` designs open as well; assets/desktop/udc-studio.xml).
                file_name.unwrap_or_else(|| "design.udc.json".into()),
            ),
            Purpose::Export(kind) => FileSpec::save(
                "Export",
                (kind.label().trim_end_matches('…'), &[kind.extension()]),
                file_name.unwrap_or_else(|| format!("export.{}", kind.extension())),
            ),
            Purpose::Mask(format) => FileSpec::save(
                "Export mask",
                (format.label(), &[format.extension()]),
                file_name.unwrap_or_else(|| format!("mask.{}", format.extension())),
            ),
        }
    }
}

/// A dialog of the display workspace in flight, with what its answer is for.
pub struct PendingDialog {
    /// What the chosen path is for.
    pub purpose: Purpose,
    job: Job<Option<PathBuf>>,
}

impl PendingDialog {
    /// Opens a native dialog on a helper thread.
    pub fn spawn(purpose: Purpose, start_dir: Option<PathBuf>, file_name: Option<String>) -> Self {
        let mut spec = purpose.spec(file_name);
        spec.start_dir = start_dir;
        PendingDialog {
            purpose,
            job: ask(spec, || {}),
        }
    }

    /// `Some(answer)` once the user closed the dialog: the path, `None` when cancelled, or why
    /// no dialog could be shown.
    pub fn poll(&self) -> Option<Result<Option<PathBuf>, JobError>> {
        self.job.poll()
    }
}
