//! Core and file errors as Python exceptions, with the message the CLI prints.
//!
//! A bad parameter or design value is a `ValueError`; a file that cannot be read or written is
//! an `OSError`; a cancelled job is the `KeyboardInterrupt` that cancelled it (raised by
//! [`crate::cancel::run`], not here).

use pyo3::PyErr;
use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyValueError};
use udc_core::SimError;
use udc_io::IoError;

/// A core error: bad values are the caller's parameters.
pub fn sim(e: &SimError) -> PyErr {
    match e {
        SimError::Cancelled => PyKeyboardInterrupt::new_err("cancelled"),
        other => PyValueError::new_err(other.to_string()),
    }
}

/// A file error; an invalid value read from a file or an unknown preset name is a `ValueError`.
pub fn io(e: &IoError) -> PyErr {
    match e {
        IoError::Invalid(s) => sim(s),
        IoError::UnknownPreset(_) => PyValueError::new_err(e.to_string()),
        other => PyOSError::new_err(other.to_string()),
    }
}

/// A value the caller passed that no core type checks (a name outside a closed set, an array
/// of the wrong shape).
pub fn value(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}
