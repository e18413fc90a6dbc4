//! Work shared by the `phase restore` points of one process: a sweep's points that share a
//! setup (its photos, its light levels' seeds) run Algorithm 1, and the 900 propagations of V
//! behind it, once, and build the blur matrix of a design once per scene width. V takes about
//! 7 s on 2 cores at the thesis's sampling and the blur matrix 6 s; `reproduce table4.1` ran
//! both once per photo.

use std::sync::{Arc, Mutex, OnceLock};

use udc_core::design::Channel;
use udc_core::phase::chain::{BlochRelay, Chain};
use udc_core::phase::imaging::{PhaseBlur, Setup, phase_blur_full, phase_blur_on};
use udc_core::phase::{PhaseDesign, PhaseOptics, PhaseSampling};
use udc_core::{Progress, SimError};

/// Designs kept (each a few kB).
const DESIGNS_KEPT: usize = 32;
/// Blur matrices kept (each `3 × width²` numbers: 6 MB at 512 columns).
const BLURS_KEPT: usize = 4;

type Slot<T> = Arc<OnceLock<Result<T, SimError>>>;

/// The last `kept` results by key; concurrent callers of one key wait for the first, and a
/// cancelled computation is not kept.
struct Shared<T> {
    kept: usize,
    slots: Mutex<Vec<(String, Slot<T>)>>,
}

impl<T: Clone> Shared<T> {
    const fn new(kept: usize) -> Self {
        Shared {
            kept,
            slots: Mutex::new(Vec::new()),
        }
    }

    fn get(
        &self,
        key: String,
        compute: impl FnOnce() -> Result<T, SimError>,
    ) -> Result<T, SimError> {
        let slot: Slot<T> = match self.slots.lock() {
            Ok(mut slots) => match slots.iter().position(|(k, _)| *k == key) {
                Some(i) => slots[i].1.clone(),
                None => {
                    let slot: Slot<T> = Arc::default();
                    slots.push((key.clone(), slot.clone()));
                    if slots.len() > self.kept {
                        slots.remove(0);
                    }
                    slot
                }
            },
            Err(_) => return compute(),
        };
        let out = slot.get_or_init(compute).clone();
        if matches!(out, Err(SimError::Cancelled))
            && let Ok(mut slots) = self.slots.lock()
        {
            slots.retain(|(k, _)| *k != key);
        }
        out
    }
}

static DESIGNS: Shared<(PhaseDesign, PhaseOptics)> = Shared::new(DESIGNS_KEPT);
static BLURS: Shared<PhaseBlur> = Shared::new(BLURS_KEPT);

/// [`Setup::resolve`], shared with every earlier call on the same setup, base design, sampling,
/// channels and relay (their exact `Debug` text is the key: every f64 prints so that it reads
/// back); an optimized plan's V runs through `relay`, the CPU when `None`.
///
/// # Errors
/// As [`Setup::resolve`].
pub fn resolve_shared(
    setup: &Setup,
    base: &PhaseDesign,
    sampling: &PhaseSampling,
    grid_channels: &[Channel],
    relay: Option<&Arc<dyn BlochRelay>>,
    progress: &Progress,
) -> Result<(PhaseDesign, PhaseOptics), SimError> {
    let on = if relay.is_some() { "device" } else { "cpu" };
    let key = format!("{setup:?}|{base:?}|{sampling:?}|{grid_channels:?}|{on}");
    DESIGNS.get(key, || {
        setup.resolve(base, sampling, grid_channels, relay, progress)
    })
}

/// [`phase_blur_full`], shared with every earlier call on the same design, sampling, channels,
/// optics, width, margin and relay (keyed as [`resolve_shared`]); `relay` runs the Bloch
/// relays ([`Chain::with_relay`]), the CPU when `None`.
///
/// # Errors
/// As [`phase_blur_full`].
#[allow(clippy::too_many_arguments)]
pub fn blur_shared(
    design: &PhaseDesign,
    sampling: &PhaseSampling,
    channels: &[Channel],
    optics: PhaseOptics,
    width: usize,
    margin: usize,
    relay: Option<Arc<dyn BlochRelay>>,
    progress: &Progress,
) -> Result<PhaseBlur, SimError> {
    let on = if relay.is_some() { "device" } else { "cpu" };
    let key = format!("{design:?}|{sampling:?}|{channels:?}|{optics:?}|{width}|{margin}|{on}");
    BLURS.get(key, || match relay {
        Some(relay) => {
            let chain = Chain::new(design, sampling)?.with_relay(relay);
            phase_blur_on(&chain, channels, optics, width, margin, progress)
        }
        None => phase_blur_full(design, sampling, channels, optics, width, margin, progress),
    })
}
