//! Errors of file input/output. Messages say what was wrong and where, the path last.

use std::path::{Path, PathBuf};

use thiserror::Error;

use udc_core::SimError;
use udc_core::mask::MaskError;

/// Why a file could not be read or written; every variant that concerns a file names it.
#[derive(Debug, Error)]
pub enum IoError {
    /// A design file (display or phase) that is not valid JSON or not a valid design.
    #[error("{message} (in {})", path.display())]
    Design {
        /// The design file.
        path: PathBuf,
        /// What is wrong, naming the field.
        message: String,
    },
    /// An image that cannot be decoded, encoded or used (wrong size, empty, non-finite values).
    #[error("{message} (in {})", path.display())]
    Image {
        /// The image file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A sweep spec (TOML or JSON) that cannot be parsed or is not a valid sweep.
    #[error("{message} (in {})", path.display())]
    Spec {
        /// The spec file.
        path: PathBuf,
        /// What is wrong, naming the field (and in TOML the line).
        message: String,
    },
    /// A CSV table that cannot be parsed (a spectral response) or written (`mtf.csv`).
    #[error("{message} (in {})", path.display())]
    Table {
        /// The table file.
        path: PathBuf,
        /// What is wrong (in a parsed table, with its line and column).
        message: String,
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
    /// A mask file that cannot be read as a mask.
    #[error("{message} (in {})", path.display())]
    Mask {
        /// The mask file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A design or options that cannot be laid out as a mask (or a cancelled export).
    #[error(transparent)]
    MaskLayout(#[from] MaskError),
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
}

impl IoError {
    /// The same error naming `to` where it named `from`: a temp file's errors name the file
    /// the user asked for, never the temp file.
    pub fn naming(self, from: &Path, to: &Path) -> Self {
        let swap = |p: PathBuf| if p == from { to.to_path_buf() } else { p };
        match self {
            IoError::Design { path, message } => IoError::Design {
                path: swap(path),
                message,
            },
            IoError::Image { path, message } => IoError::Image {
                path: swap(path),
                message,
            },
            IoError::Table { path, message } => IoError::Table {
                path: swap(path),
                message,
            },
            IoError::Mask { path, message } => IoError::Mask {
                path: swap(path),
                message,
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
