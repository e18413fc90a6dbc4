//! Errors of the simulation core.

use thiserror::Error;

use crate::setting::SettingPath;

/// Everything that can go wrong in a simulation. Messages name what was wrong and where.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SimError {
    /// A parameter is out of range; `path` is where it is in the design file (or the setting's
    /// name). The message calls it a "field" of the file, as a user reads one.
    #[error("field `{path}`: {message}")]
    InvalidSetting {
        /// The offending setting, or a path inside one.
        path: SettingPath,
        /// What is wrong with it.
        message: String,
    },
    /// The sampling cannot represent the design (e.g. the pupil does not fit the FFT grid).
    #[error("sampling: {0}")]
    Sampling(String),
    /// The job would need more memory than the studio allows.
    #[error("too large: {0}")]
    TooLarge(String),
    /// A result that is not a finite number (an overflow somewhere upstream): never reported
    /// as a value.
    #[error("{what} is not a finite number ({value:?}); {hint}")]
    NonFinite {
        /// What was computed (e.g. "the loss at epoch 3").
        what: String,
        /// The offending value (NaN or ±∞).
        value: f64,
        /// What the user can change to avoid it.
        hint: &'static str,
    },
    /// The compute device failed (a lost device, a kernel the driver refused, its memory
    /// exhausted); the CPU route computes the same numbers.
    #[error("compute device: {0}")]
    Device(String),
    /// The caller cancelled the job through its [`crate::Progress`].
    #[error("cancelled")]
    Cancelled,
}

impl SimError {
    /// An [`SimError::InvalidSetting`] for `path` with `message`.
    pub fn invalid(path: impl Into<SettingPath>, message: impl Into<String>) -> Self {
        SimError::InvalidSetting {
            path: path.into(),
            message: message.into(),
        }
    }
}

/// A value typed on the command line, in a dialog or in a file that the studio cannot use (a
/// size, a shard, a name from a closed set). The message names the value as given and says what
/// would be accepted.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum ValueError {
    /// A name outside a closed set (a tiling, a tone, a region).
    #[error("unknown {what} `{value}` (expected {expected})")]
    UnknownName {
        /// What the name names ("tiling").
        what: &'static str,
        /// The name as given.
        value: String,
        /// The accepted names.
        expected: &'static str,
    },
    /// Text that does not have the form of the value.
    #[error("`{value}` is not {expected}")]
    Malformed {
        /// The text as given.
        value: String,
        /// What it should be, with an example ("a size (e.g. 2G)").
        expected: &'static str,
    },
    /// A well-formed value that cannot be used.
    #[error("`{value}`: {problem}")]
    Unusable {
        /// The value as given.
        value: String,
        /// Why it cannot be used.
        problem: String,
    },
}
