//! The PSFs of a design, computed once per process: a sweep's `restore` points that share a
//! display (every light level and photo of it) analyse it once. A 600-DPI design with 1 µm
//! cells takes seconds, its capture and restoration of a 256² photo under one; without the
//! cache `reproduce table4.1` spent most of its time recomputing the same four PSFs.

use std::sync::{Arc, Mutex, OnceLock};

use anyhow::{Result, anyhow};

use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with_route};
use udc_core::{Analysis, Design, Progress, SimError};
use udc_gpu::Route;

/// Designs kept: a sweep's points walk its axes in order, so a handful covers the displays in
/// flight on every worker (each analysis holds three PSFs and MTFs: a few MB).
const KEPT: usize = 8;

type Slot = Arc<OnceLock<Result<Arc<Analysis>, SimError>>>;

fn cache() -> &'static Mutex<Vec<(String, Slot)>> {
    static CACHE: OnceLock<Mutex<Vec<(String, Slot)>>> = OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(Vec::new()))
}

/// The analysis of `design` at `options` with its PSFs on `route`, shared with every earlier
/// call on the same design (by the hash of its file form), quality and device; concurrent
/// callers wait for the first.
///
/// # Errors
/// The analysis's own error (a cached failure repeats it).
pub fn analyze_shared(
    design: &Design,
    options: &AnalyzeOptions,
    route: &Route,
) -> Result<Arc<Analysis>> {
    let key = format!(
        "{}/{}/{}/{}",
        udc_io::design::hash::design_hash(design),
        matches!(options.quality, Quality::Full),
        options.expected_psf,
        route.adapter().unwrap_or_default()
    );
    let slot: Slot = {
        let mut kept = cache()
            .lock()
            .map_err(|_| anyhow!("the PSF cache is poisoned"))?;
        match kept.iter().position(|(k, _)| *k == key) {
            Some(i) => {
                // Most recently used last.
                let entry = kept.remove(i);
                let slot = entry.1.clone();
                kept.push(entry);
                slot
            }
            None => {
                let slot: Slot = Arc::default();
                kept.push((key, slot.clone()));
                if kept.len() > KEPT {
                    kept.remove(0);
                }
                slot
            }
        }
    };
    slot.get_or_init(|| analyze_with_route(design, options, route, &Progress::new()).map(Arc::new))
        .clone()
        .map_err(anyhow::Error::from)
}
