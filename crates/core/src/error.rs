//! Errors of the simulation core.

use thiserror::Error;

/// Everything that can go wrong in a simulation. Messages name what was wrong and where.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SimError {
    /// A parameter is out of range; `field` is its path in the design file (or the setting's name).
    #[error("field `{field}`: {message}")]
    InvalidField {
        /// Path of the offending parameter.
        field: String,
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
    /// The caller cancelled the job through its [`crate::Progress`].
    #[error("cancelled")]
    Cancelled,
}

impl SimError {
    /// An [`SimError::InvalidField`] for `field` with `message`.
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        SimError::InvalidField {
            field: field.into(),
            message: message.into(),
        }
    }
}
