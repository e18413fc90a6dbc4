//! Setups designed once per process: a sweep's `phase restore` points that share a setup (its
//! photos, its seeds) run Algorithm 1, and the 900 propagations of V behind it, once. V takes
//! about 7 s on 2 cores at the thesis's sampling; `reproduce table4.1` ran it once per photo.

use std::sync::{Arc, Mutex, OnceLock};

use crate::core::design::Channel;
use crate::core::phase::imaging::Setup;
use crate::core::phase::{PhaseDesign, PhaseOptics, PhaseSampling};
use crate::core::{Progress, SimError};

/// Setups kept (each a design: a few kB).
const KEPT: usize = 32;

type Designed = Result<(PhaseDesign, PhaseOptics), SimError>;
type Slot = Arc<OnceLock<Designed>>;

fn cache() -> &'static Mutex<Vec<(String, Slot)>> {
    static CACHE: OnceLock<Mutex<Vec<(String, Slot)>>> = OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(Vec::new()))
}

/// [`Setup::resolve`], shared with every earlier call on the same setup, base design, sampling
/// and channels (their exact `Debug` text is the key: every f64 prints so that it reads back);
/// concurrent callers wait for the first. A cancelled design is not kept.
///
/// # Errors
/// As [`Setup::resolve`].
pub fn resolve_shared(
    setup: &Setup,
    base: &PhaseDesign,
    sampling: &PhaseSampling,
    grid_channels: &[Channel],
    progress: &Progress,
) -> Designed {
    let key = format!("{setup:?}|{base:?}|{sampling:?}|{grid_channels:?}");
    let slot: Slot = match cache().lock() {
        Ok(mut kept) => match kept.iter().position(|(k, _)| *k == key) {
            Some(i) => kept[i].1.clone(),
            None => {
                let slot: Slot = Arc::default();
                kept.push((key.clone(), slot.clone()));
                if kept.len() > KEPT {
                    kept.remove(0);
                }
                slot
            }
        },
        Err(_) => return setup.resolve(base, sampling, grid_channels, progress),
    };
    let out = slot
        .get_or_init(|| setup.resolve(base, sampling, grid_channels, progress))
        .clone();
    if matches!(out, Err(SimError::Cancelled))
        && let Ok(mut kept) = cache().lock()
    {
        kept.retain(|(k, _)| *k != key);
    }
    out
}
