//! The studio's own error: what a studio task holds when its causes meet from several places (a
//! file, the simulation, a typed value, a spectral table) or are the studio's own refusals. Like
//! the library errors it wraps, it stays typed until it is drawn, where `to_string` makes the
//! line the user reads.

use crate::core::sweep::SweepJob;
use crate::core::{SimError, ValueError};
use crate::io::IoError;
use crate::io::error::SpectralError;

/// Why a studio task gave no result.
#[derive(Debug, thiserror::Error)]
pub enum StudioError {
    /// A file could not be read or written.
    #[error(transparent)]
    Io(#[from] IoError),
    /// The simulation refused its input.
    #[error(transparent)]
    Sim(#[from] SimError),
    /// A value that cannot be used (a sweep row's parameters).
    #[error(transparent)]
    Value(#[from] ValueError),
    /// A job's refusal (the design of a sweep row that does not resolve), as one message.
    #[error(transparent)]
    Job(#[from] anyhow::Error),
    /// A spectral response that cannot give channels on the wavelength grid.
    #[error(transparent)]
    Spectral(#[from] SpectralError),
    /// The custom response a channel choice names is no longer the loaded one.
    #[error("the custom response is no longer loaded")]
    ResponseGone,
    /// A sweep whose rows have no design to open (analyze, restore and phase-psf sweeps
    /// open).
    #[error(
        "this is a `{}` sweep: Open design is for display and phase-mask designs (analyze, \
         restore and phase-psf sweeps)",
        .0.as_str()
    )]
    NotDisplaySweep(SweepJob),
    /// A row index past the table's end.
    #[error("no row {0} in the table")]
    NoRow(usize),
    /// A plot names a column the table does not have.
    #[error("the table has no column `{0}`")]
    NoColumn(String),
    /// The data loss's training photo and the design have different numbers of colour channels.
    #[error(
        "the data loss needs {photo} colour channels (the training photo's); this design has \
         {design}: untick the data loss"
    )]
    TrainingChannels {
        /// Channels of the training photo.
        photo: usize,
        /// Channels of the design.
        design: usize,
    },
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
            "this is a `sensor` sweep: Open design is for display and phase-mask designs \
             (analyze, restore and phase-psf sweeps)"
        );
    }
}
