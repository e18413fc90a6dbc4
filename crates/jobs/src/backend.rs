//! `--backend cpu|gpu|auto` (Python's `backend=`): where a job's PSFs are computed. The switch
//! resolves to a `udc_gpu::Route`; the job's report says where they ran, in one line, when that
//! was not the CPU by default.

use anyhow::Result;
use serde_json::{Value, json};
use udc_core::psf::route::Backend;
use udc_gpu::Route;

use crate::Report;

/// `backend` resolved on this process's shared headless device.
///
/// # Errors
/// `gpu` on a machine with no adapter: the message names what was found.
pub fn route(backend: Backend) -> Result<Route> {
    Ok(Route::resolve(backend)?)
}

/// Adds where the PSFs ran to `out`: a `backend` object in its JSON (`requested`, `adapter`,
/// `note`, `device_transforms`: the transforms the device completed) and a line of text, unless the CPU was asked for.
pub fn report(out: &mut Report, backend: Backend, route: &Route) {
    if backend == Backend::Cpu {
        return;
    }
    let adapter = route.adapter();
    let note = route.note();
    if let Value::Object(map) = &mut out.json {
        map.insert(
            "backend".into(),
            json!({
                "requested": <&str>::from(backend),
                "adapter": adapter,
                "note": note,
                "device_transforms": route.device_transforms(),
            }),
        );
    }
    match (&adapter, &note) {
        (_, Some(note)) => outln!(out, "{note}"),
        (Some(adapter), None) => outln!(out, "PSFs computed on {adapter}"),
        (None, None) => outln!(out, "PSFs computed on the CPU"),
    }
}
