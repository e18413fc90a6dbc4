//! Errors of file input/output. Messages say what was wrong and where, the path last.

use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::core::SimError;
use crate::core::mask::MaskError;

#[derive(Debug, Error)]
pub enum IoError {
    #[error("{message} (in {})", path.display())]
    Design { path: PathBuf, message: String },
    #[error("{message} (in {})", path.display())]
    Image { path: PathBuf, message: String },
    #[error("{message} (in {})", path.display())]
    Table { path: PathBuf, message: String },
    // The cause is in the message and deliberately not a `#[source]`: a chain printer
    // (anyhow's `{:#}`) would repeat it.
    #[error("cannot {action}: {cause} ({})", path.display())]
    File {
        action: &'static str,
        path: PathBuf,
        cause: std::io::Error,
    },
    #[error("{0}")]
    Invalid(#[from] SimError),
    /// A mask file that cannot be read as a mask.
    #[error("{message} (in {})", path.display())]
    Mask { path: PathBuf, message: String },
    /// A design or options that cannot be laid out as a mask (or a cancelled export).
    #[error("{0}")]
    MaskLayout(#[from] MaskError),
    #[error("unknown preset `{0}` (run `udc-studio presets` for the list)")]
    UnknownPreset(String),
    /// A directory, device, FIFO or socket where a file was expected.
    #[error("{} is {kind}; give a regular file", path.display())]
    NotAFile { path: PathBuf, kind: &'static str },
    /// A file past the byte cap of its kind (read no further than the cap).
    #[error("{} is larger than {} MB, the limit for this kind of file", path.display(), cap / 1_000_000)]
    TooLarge { path: PathBuf, cap: u64 },
    /// An output path that names one of the command's own inputs.
    #[error("{} is also an input of this command; it is left as it is: write to another file", path.display())]
    OutputIsInput { path: PathBuf },
    /// Bytes that are not UTF-8 text.
    #[error("{} is not UTF-8 text (an invalid byte at offset {offset})", path.display())]
    NotText { path: PathBuf, offset: usize },
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

    pub fn file(action: &'static str, path: &Path, cause: std::io::Error) -> Self {
        IoError::File {
            action,
            path: path.to_path_buf(),
            cause,
        }
    }
}
