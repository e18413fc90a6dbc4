//! `udc_studio._native`: the compiled half of the Python package `udc_studio`.
//!
//! The functions here take and return plain values (design JSON text, numpy arrays, dicts); the
//! package's Python half (`python/udc_studio/`) wraps them in the documented API. Every
//! computation runs with the GIL released on a worker thread that Ctrl-C cancels
//! ([`cancel::run`]); every core or file error becomes a Python exception with the CLI's
//! one-line message ([`errors`]).

use pyo3::prelude::*;

mod analysis;
mod cancel;
mod design;
mod errors;
mod figures;
mod jobs;
mod measured;
mod restore;
mod theory;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // As the command line: jobs estimated to need more than half the memory are refused.
    udc_core::budget::set_max_memory_bytes(udc_io::system::default_max_memory_bytes());
    design::register(m)?;
    analysis::register(m)?;
    restore::register(m)?;
    theory::register(m)?;
    jobs::register(m)?;
    figures::register(m)?;
    measured::register(m)?;
    Ok(())
}
