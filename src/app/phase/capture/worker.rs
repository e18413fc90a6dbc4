//! The capture job on its worker thread: each setup's operator (kept or built), then the
//! capture and restoration, sent row by row.

use super::*;
use std::sync::mpsc::Sender;

use crate::core::phase::Chain;
use crate::core::phase::chain::BlochRelay;
use crate::core::phase::imaging::phase_blur_on;

/// One setup for the worker: its row, its operator's key, the operator if kept.
pub(super) struct SetupJob {
    pub(super) row: usize,
    pub(super) key: OperatorKey,
    pub(super) blur: Option<Arc<PhaseBlur>>,
    pub(super) channels: Arc<Vec<Channel>>,
}

/// The capture's settings shared by every setup of a run.
pub(super) struct Light {
    pub(super) photons: f64,
    pub(super) seed: u64,
    pub(super) denoise: Denoise,
    /// Where the operators' Bloch relays run (the CPU when `None`).
    pub(super) relay: Option<Arc<dyn BlochRelay>>,
}

/// The worker: each setup's operator (kept or built), then the capture and restoration, sent
/// through `out` as each setup finishes.
pub(super) fn run_setups(
    jobs: &[SetupJob],
    truth: &[Array2<f64>],
    light: &Light,
    progress: &Progress,
    step: &Mutex<(String, Instant)>,
    out: &Sender<(usize, Finished)>,
) -> Result<(), SimError> {
    let say = |text: String| {
        if let Ok(mut s) = step.lock() {
            *s = (text, Instant::now());
        }
    };
    let n = jobs.len();
    for (i, job) in jobs.iter().enumerate() {
        let key = &job.key;
        let label = match key.channels {
            ChannelSet::Peaks => format!(
                "{} (peak wavelengths)",
                setup_label(key.optics, &key.design)
            ),
            _ => setup_label(key.optics, &key.design),
        };
        let (blur, built) = match &job.blur {
            Some(b) => (b.clone(), false),
            None => {
                let on = if light.relay.is_some() {
                    " on the GPU"
                } else {
                    ""
                };
                say(format!(
                    "step {} of {}: blur matrix of {label} ({} directions{on})",
                    2 * i + 1,
                    2 * n,
                    key.width
                ));
                progress.set(0.0);
                let sampling = crate::core::phase::PhaseSampling::for_quality(key.quality);
                let chain = Chain::new(&key.design, &sampling)?.with_relay_if(light.relay.as_ref());
                let b = phase_blur_on(&chain, &job.channels, key.optics, key.width, 0, progress)?;
                (Arc::new(b), true)
            }
        };
        let what = match light.denoise {
            Denoise::None => "capture and restore",
            Denoise::Bm3d { .. } => "capture, denoise (BM3D) and restore",
        };
        say(format!(
            "step {} of {}: {what} through {label}",
            2 * i + 2,
            2 * n
        ));
        progress.set(0.0);
        let run = capture_and_restore(
            &blur,
            truth,
            light.photons,
            light.seed,
            light.denoise,
            progress,
        )?;
        let images = run_images(&run, truth);
        let unpassed_mse = crate::core::phase::imaging::unpassed_mse(&blur, truth)?;
        let finished = Finished {
            label,
            key: key.clone(),
            blur,
            built,
            fov_deg: key.design.fov_deg(),
            unpassed_mse,
            run,
            images,
        };
        // A closed channel means the view went away: nothing to show it to.
        if out.send((job.row, finished)).is_err() {
            return Err(SimError::Cancelled);
        }
    }
    Ok(())
}
