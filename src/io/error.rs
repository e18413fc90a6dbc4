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
    #[error("cannot {action}: {source} ({})", path.display())]
    File {
        action: &'static str,
        path: PathBuf,
        #[source]
        source: std::io::Error,
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
}

impl IoError {
    pub fn file(action: &'static str, path: &Path, source: std::io::Error) -> Self {
        IoError::File {
            action,
            path: path.to_path_buf(),
            source,
        }
    }
}
