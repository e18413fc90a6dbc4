//! The studio's own error: what a studio task holds when its causes meet from several places (a
//! file, the simulation, a typed value, a spectral table) or are the studio's own refusals. Like
//! the library errors it wraps, it stays typed until it is drawn, where `to_string` makes the
//! line the user reads.

use std::fmt;

use crate::core::sweep::SweepJob;
use crate::core::{SimError, ValueError};
use crate::io::IoError;
use crate::io::error::SpectralError;

/// Why a studio task gave no result.
#[derive(Debug)]
pub enum StudioError {
    /// A file could not be read or written.
    Io(IoError),
    /// The simulation refused its input.
    Sim(SimError),
    /// A value that cannot be used (a sweep row's parameters).
    Value(ValueError),
    /// A spectral response that cannot give channels on the wavelength grid.
    Spectral(SpectralError),
    /// The custom response a channel choice names is no longer the loaded one.
    ResponseGone,
    /// A sweep whose rows are not display designs (only analyze and restore sweeps open).
    NotDisplaySweep(SweepJob),
    /// A row index past the table's end.
    NoRow(usize),
    /// A plot names a column the table does not have.
    NoColumn(String),
    /// The data loss's training photo and the design have different numbers of colour channels.
    TrainingChannels {
        /// Channels of the training photo.
        photo: usize,
        /// Channels of the design.
        design: usize,
    },
}

impl fmt::Display for StudioError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StudioError::Io(e) => e.fmt(f),
            StudioError::Sim(e) => e.fmt(f),
            StudioError::Value(e) => e.fmt(f),
            StudioError::Spectral(e) => e.fmt(f),
            StudioError::ResponseGone => f.write_str("the custom response is no longer loaded"),
            StudioError::NotDisplaySweep(job) => write!(
                f,
                "this is a `{}` sweep: Open design is for display designs (analyze and restore \
                 sweeps)",
                job.as_str()
            ),
            StudioError::NoRow(index) => write!(f, "no row {index} in the table"),
            StudioError::NoColumn(name) => write!(f, "the table has no column `{name}`"),
            StudioError::TrainingChannels { photo, design } => write!(
                f,
                "the data loss needs {photo} colour channels (the training photo's); this \
                 design has {design}: untick the data loss"
            ),
        }
    }
}

impl std::error::Error for StudioError {}

impl From<IoError> for StudioError {
    fn from(e: IoError) -> Self {
        StudioError::Io(e)
    }
}

impl From<SimError> for StudioError {
    fn from(e: SimError) -> Self {
        StudioError::Sim(e)
    }
}

impl From<ValueError> for StudioError {
    fn from(e: ValueError) -> Self {
        StudioError::Value(e)
    }
}

impl From<SpectralError> for StudioError {
    fn from(e: SpectralError) -> Self {
        StudioError::Spectral(e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The studio's own refusals read as they did when they were strings.
    #[test]
    fn the_studios_own_refusals_read_as_before() {
        assert_eq!(
            StudioError::NoColumn("auc".into()).to_string(),
            "the table has no column `auc`"
        );
        assert_eq!(
            StudioError::TrainingChannels {
                photo: 3,
                design: 1
            }
            .to_string(),
            "the data loss needs 3 colour channels (the training photo's); this design has 1: \
             untick the data loss"
        );
        assert_eq!(
            StudioError::NotDisplaySweep(SweepJob::Sensor).to_string(),
            "this is a `sensor` sweep: Open design is for display designs (analyze and restore \
             sweeps)"
        );
    }
}
