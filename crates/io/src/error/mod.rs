//! Errors of file input/output: [`IoError`] (which file, what is wrong) and the errors of the
//! formats with failure modes of their own, which it carries beside the path. Messages say what
//! was wrong and where, the path last.

use std::path::{Path, PathBuf};

use thiserror::Error;

use udc_core::SimError;
use udc_core::mask::MaskError;

// The formats' own errors live here, not beside their readers: `IoError` wraps them, and a
// format module that defined its error while naming `IoError` would import `error` in a cycle.
mod design;
mod images;
mod mask;
mod sweep;
mod table;

pub use design::DesignFileError;
pub use images::{HdrError, PatternError, PlanesError};
pub use mask::{ExportOptionsError, LayerMapError, MaskImportError, OasisError};
pub use sweep::{PlotError, SpecError};
pub use table::{SpectralError, TableError};

/// Why a file could not be read or written; every variant that concerns a file names it.
///
/// A variant that wraps a format's typed error prints it before the path. The typed error is
/// a plain field, deliberately not a `#[source]`: the message already contains it, and a chain
/// printer (anyhow's `{:#}`) would repeat it.
#[derive(Debug, Error)]
pub enum IoError {
    /// A design file (display or phase) that is not valid JSON or not a valid design.
    #[error("{} (in {})", one_line(error), path.display())]
    Design {
        /// The design file.
        path: PathBuf,
        /// What is wrong, naming the field.
        error: DesignFileError,
    },
    /// An image that cannot be encoded, or a photo that cannot be decoded or used, in words
    /// composed where it happened (the image readers with a format of their own have their own
    /// variants: [`IoError::Pattern`], [`IoError::Planes`], [`IoError::Hdr`]).
    #[error("{} (in {})", one_line(message), path.display())]
    Image {
        /// The image file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// An image opening that cannot be decoded or is not a usable grid of cells.
    #[error("{} (in {})", one_line(error), path.display())]
    Pattern {
        /// The image file.
        path: PathBuf,
        /// What is wrong.
        error: PatternError,
    },
    /// An image read as its planes (PNG, TIFF, OpenEXR) that cannot be decoded or used.
    #[error("{} (in {})", one_line(error), path.display())]
    Planes {
        /// The image file.
        path: PathBuf,
        /// What is wrong.
        error: PlanesError,
    },
    /// An HDR scene (Radiance or OpenEXR) that cannot be read.
    #[error("{} (in {})", one_line(error), path.display())]
    Hdr {
        /// The HDR file (or the built-in sample's name).
        path: PathBuf,
        /// What is wrong.
        error: HdrError,
    },
    /// A sweep plot that cannot be drawn or encoded.
    #[error("{} (in {})", one_line(error), path.display())]
    Plot {
        /// The plot file.
        path: PathBuf,
        /// What went wrong.
        error: PlotError,
    },
    /// A sweep spec (TOML or JSON) or manifest that cannot be parsed or is not a valid sweep.
    #[error("{} (in {})", one_line(error), path.display())]
    Spec {
        /// The spec file.
        path: PathBuf,
        /// What is wrong, naming the field (and in TOML the line).
        error: SpecError,
    },
    /// A table that cannot be parsed (a spectral response, a sweep's results) or written
    /// (`mtf.csv`, a sweep's results).
    #[error("{} (in {})", one_line(error), path.display())]
    Table {
        /// The table file.
        path: PathBuf,
        /// What is wrong (in a parsed table, with its line and column).
        error: TableError,
    },
    // The cause is in the message and deliberately not a `#[source]`: a chain printer
    // (anyhow's `{:#}`) would repeat it.
    /// The operating system refused to open, read, write or rename a file.
    #[error("cannot {action}: {cause} ({})", path.display())]
    File {
        /// What was being done, completing "cannot …" (e.g. "read the design").
        action: &'static str,
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        cause: std::io::Error,
    },
    /// A simulation error met while preparing or writing a file (e.g. an out-of-range value).
    #[error(transparent)]
    Invalid(#[from] SimError),
    /// A mask file that cannot be read or written as a mask, in words composed where it
    /// happened (GDSII, DXF and PNG masks; OASIS and the import have their own variants).
    #[error("{} (in {})", one_line(message), path.display())]
    Mask {
        /// The mask file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// An OASIS mask that cannot be read.
    #[error("{} (in {})", one_line(error), path.display())]
    Oasis {
        /// The mask file.
        path: PathBuf,
        /// What is wrong.
        error: OasisError,
    },
    /// A mask that cannot be read back into cells (`udc-studio import`, the studio's import).
    #[error("{} (in {})", one_line(error), path.display())]
    MaskImport {
        /// The mask file.
        path: PathBuf,
        /// What is wrong.
        error: MaskImportError,
    },
    /// Export options whose layers cannot be written (met while writing the mask at `path`).
    #[error("{} (in {})", one_line(error), path.display())]
    MaskOptions {
        /// The mask file being written.
        path: PathBuf,
        /// The bad option.
        error: ExportOptionsError,
    },
    /// A design or options that cannot be laid out as a mask (or a cancelled export).
    #[error(transparent)]
    MaskLayout(#[from] MaskError),
    /// A strict export whose written geometry breaks a design rule.
    #[error(
        "{} design-rule violations in the geometry to be written (--strict): nothing written",
        report.total()
    )]
    RulesBroken {
        /// The findings, to list the violations.
        report: Box<udc_core::mask::drc::DrcReport>,
        /// What was checked, in words.
        scope: String,
    },
    /// A preset name that is not built in (the name as given).
    #[error("unknown preset `{0}` (run `udc-studio presets` for the list)")]
    UnknownPreset(String),
    /// A directory, device, FIFO or socket where a file was expected.
    #[error("{} is {kind}; give a regular file", path.display())]
    NotAFile {
        /// The path given.
        path: PathBuf,
        /// What it is instead, completing "… is" (e.g. "a directory").
        kind: &'static str,
    },
    /// A file past the byte cap of its kind (read no further than the cap).
    #[error("{} is larger than {} MB, the limit for this kind of file", path.display(), cap / 1_000_000)]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// The byte cap of its kind, in bytes.
        cap: u64,
    },
    /// An output path that names one of the command's own inputs.
    #[error("{} is also an input of this command; it is left as it is: write to another file", path.display())]
    OutputIsInput {
        /// The output path, which is also an input.
        path: PathBuf,
    },
    /// Bytes that are not UTF-8 text.
    #[error("{} is not UTF-8 text (an invalid byte at offset {offset})", path.display())]
    NotText {
        /// The file.
        path: PathBuf,
        /// Byte offset of the first invalid UTF-8 byte.
        offset: usize,
    },
    /// A lesson file that does not parse or breaks a rule, naming the step and the field.
    #[error("{message} (in {})", path.display())]
    Lesson {
        /// The lesson file.
        path: PathBuf,
        /// What is wrong, in one line.
        message: String,
    },
}

/// A message as one line, as the command line and the studio show it: the text trimmed, and a
/// line break inside it escaped (`\n`, `\r`). Such breaks come from the file itself, echoed by
/// a parser or decoder (a JSON key, a header, an image format name), or end a decoder's message.
fn one_line(text: impl std::fmt::Display) -> String {
    let text = text.to_string();
    let text = text.trim();
    if text.contains(['\n', '\r']) {
        text.replace('\r', "\\r").replace('\n', "\\n")
    } else {
        text.to_string()
    }
}

impl IoError {
    /// The same error naming `to` where it named `from`: a temp file's errors name the file
    /// the user asked for, never the temp file.
    pub fn naming(self, from: &Path, to: &Path) -> Self {
        let swap = |p: PathBuf| if p == from { to.to_path_buf() } else { p };
        match self {
            IoError::Design { path, error } => IoError::Design {
                path: swap(path),
                error,
            },
            IoError::Image { path, message } => IoError::Image {
                path: swap(path),
                message,
            },
            IoError::Pattern { path, error } => IoError::Pattern {
                path: swap(path),
                error,
            },
            IoError::Planes { path, error } => IoError::Planes {
                path: swap(path),
                error,
            },
            IoError::Hdr { path, error } => IoError::Hdr {
                path: swap(path),
                error,
            },
            IoError::Plot { path, error } => IoError::Plot {
                path: swap(path),
                error,
            },
            IoError::Table { path, error } => IoError::Table {
                path: swap(path),
                error,
            },
            IoError::Mask { path, message } => IoError::Mask {
                path: swap(path),
                message,
            },
            IoError::Oasis { path, error } => IoError::Oasis {
                path: swap(path),
                error,
            },
            IoError::MaskImport { path, error } => IoError::MaskImport {
                path: swap(path),
                error,
            },
            IoError::MaskOptions { path, error } => IoError::MaskOptions {
                path: swap(path),
                error,
            },
            IoError::File {
                action,
                path,
                cause,
            } => IoError::File {
                action,
                path: swap(path),
                cause,
            },
            other => other,
        }
    }

    /// An [`IoError::File`]: `action` completes "cannot …" (e.g. "write the mask").
    pub fn file(action: &'static str, path: &Path, cause: std::io::Error) -> Self {
        IoError::File {
            action,
            path: path.to_path_buf(),
            cause,
        }
    }
}
