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
        // A job whose every step stays on the CPU (a phase plate under the lenslet period)
        // must not claim the device it was handed.
        (Some(adapter), None) if route.device_transforms() == 0 => outln!(
            out,
            "PSFs computed on the CPU: no step of this job runs on {adapter} (the book's GPU chapter lists what does)"
        ),
        (Some(adapter), None) => outln!(out, "PSFs computed on {adapter}"),
        (None, None) => outln!(out, "PSFs computed on the CPU"),
    }
}

/// `--backend` of the commands that print their own tables (`field`, `depth`, `saturation`,
/// `appearance`): the flag, its route, and where the PSFs ran, as a job's [`report`] says it.
#[derive(Debug, Clone, Copy, Default, clap::Args)]
pub struct BackendFlag {
    /// Where the design's PSFs are computed: cpu, gpu or auto (as `analyze --backend`).
    #[arg(long, value_parser = crate::choice::choice::<Backend>(), default_value_t = Backend::Cpu)]
    pub backend: Backend,
}

impl BackendFlag {
    /// The flag resolved on this process's shared headless device.
    ///
    /// # Errors
    /// As [`route`].
    pub fn route(&self) -> Result<Route> {
        route(self.backend)
    }

    /// Adds the `backend` object to `json` (unless the CPU was asked for) and gives the line
    /// to print after the table, as [`report`] does for a job.
    pub fn note(&self, route: &Route, json: &mut Value) -> Option<String> {
        let mut out = Report {
            json: std::mem::take(json),
            text: String::new(),
        };
        report(&mut out, self.backend, route);
        *json = out.json;
        let line = out.text.trim_end();
        (!line.is_empty()).then(|| line.to_owned())
    }

    /// The line [`BackendFlag::note`] gives, for a table printed without JSON.
    pub fn line(&self, route: &Route) -> Option<String> {
        self.note(route, &mut Value::Null)
    }
}
