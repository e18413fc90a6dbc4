//! The simulation worker: a named thread that takes the newest job, computes a fast preview
//! (where the design's sampling allows a cheaper one that agrees, see `Quality`) and then full
//! quality (with the advice for its sampling warnings), and wakes the UI. A newer job
//! cancels the running one (generation numbers tell stale results apart). The UI thread never
//! calls the simulation.

use std::sync::mpsc::{Receiver, Sender, channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use crate::core::analysis::advice::advise;
use crate::core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with_route};
use crate::core::{Analysis, Design, Progress, SimError};
use udc_gpu::Route;

/// What a job produces, in order: the display preview, then the preview (where one agrees with
/// full quality) and the full analyses.
pub enum Payload {
    /// The rasterised display around the pupil, for the tiling preview (sent first, only for a
    /// valid design).
    Display {
        /// Samples per side of the square image; the optical axis is at `side / 2`.
        side: usize,
        /// Amplitude transmittance in [0, 1], row-major.
        values: Vec<f32>,
        /// Spacing between samples, in µm.
        sample_um: f64,
        /// Diameter of the lens pupil, in µm.
        pupil_diameter_um: f64,
    },
    /// One analysis of the design: the fast preview, then the full quality, then the full
    /// quality again with the advice for its warnings (each advice is a further analysis, so
    /// the numbers come first).
    Analysis {
        /// Whether this is the fast preview or the full-quality result.
        quality: Quality,
        /// Whether the warnings carry their advice (the last payload of a job).
        advised: bool,
        /// The analysis, or why it failed (a failed preview ends the job).
        result: Result<Analysis, SimError>,
        /// The route its PSFs were computed on.
        route: Arc<Route>,
    },
}

/// A finished (or failed) piece of the job of one generation.
pub struct JobResult {
    /// Generation of the design it was computed for; stale when older than the worker's newest.
    pub generation: u64,
    /// What was computed.
    pub payload: Payload,
}

/// Largest side of the display preview image, in samples.
const DISPLAY_PREVIEW_SIDE: usize = 640;

struct Shared {
    pending: Option<(u64, Design)>,
    running: Option<(u64, Arc<Progress>)>,
    shutdown: bool,
}

/// Handle owned by the UI.
pub struct Worker {
    shared: Arc<(Mutex<Shared>, std::sync::Condvar)>,
    results: Receiver<JobResult>,
    generation: u64,
    thread: Option<JoinHandle<()>>,
}

impl Worker {
    /// Starts the worker; `wake` is called whenever a result is ready (e.g. `request_repaint`);
    /// each job computes its PSFs by the route `route` holds when the job starts.
    pub fn spawn(wake: impl Fn() + Send + 'static, route: Arc<Mutex<Arc<Route>>>) -> Self {
        let shared = Arc::new((
            Mutex::new(Shared {
                pending: None,
                running: None,
                shutdown: false,
            }),
            std::sync::Condvar::new(),
        ));
        let (tx, rx) = channel();
        let thread_shared = shared.clone();
        let thread = std::thread::Builder::new()
            .name("udc-simulation".into())
            .spawn(move || worker_loop(&thread_shared, &tx, &wake, &route))
            .ok();
        Worker {
            shared,
            results: rx,
            generation: 0,
            thread,
        }
    }

    /// Queues a design; any older pending or running job is superseded. Returns its generation.
    pub fn submit(&mut self, design: Design) -> u64 {
        self.generation += 1;
        let (lock, cvar) = &*self.shared;
        let mut s = lock.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, p)) = &s.running {
            p.cancel();
        }
        s.pending = Some((self.generation, design));
        cvar.notify_one();
        self.generation
    }

    /// The newest generation submitted.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Progress of the running job, if any.
    pub fn progress(&self) -> Option<f32> {
        let s = self.shared.0.lock().unwrap_or_else(|e| e.into_inner());
        s.running.as_ref().map(|(_, p)| p.fraction())
    }

    /// Drains finished results without blocking.
    pub fn poll(&self) -> Vec<JobResult> {
        self.results.try_iter().collect()
    }

    /// Blocks until a result arrives or the timeout passes (for tests and headless use).
    pub fn wait(&self, timeout: std::time::Duration) -> Option<JobResult> {
        self.results.recv_timeout(timeout).ok()
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        {
            let (lock, cvar) = &*self.shared;
            let mut s = lock.lock().unwrap_or_else(|e| e.into_inner());
            s.shutdown = true;
            if let Some((_, p)) = &s.running {
                p.cancel();
            }
            cvar.notify_one();
        }
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn worker_loop(
    shared: &Arc<(Mutex<Shared>, std::sync::Condvar)>,
    tx: &Sender<JobResult>,
    wake: &dyn Fn(),
    route: &Mutex<Arc<Route>>,
) {
    let (lock, cvar) = &**shared;
    loop {
        let (generation, design, progress) = {
            let mut s = lock.lock().unwrap_or_else(|e| e.into_inner());
            while s.pending.is_none() && !s.shutdown {
                s = cvar.wait(s).unwrap_or_else(|e| e.into_inner());
            }
            if s.shutdown {
                return;
            }
            let Some((generation, design)) = s.pending.take() else {
                continue;
            };
            let progress = Arc::new(Progress::new());
            s.running = Some((generation, progress.clone()));
            (generation, design, progress)
        };
        let route = route
            .lock()
            .map(|r| r.clone())
            .unwrap_or_else(|_| Arc::new(Route::cpu()));
        // Delivers one piece of the job and wakes the UI; false once the UI has gone.
        let send = |payload: Payload| {
            let ok = tx
                .send(JobResult {
                    generation,
                    payload,
                })
                .is_ok();
            wake();
            ok
        };
        if design.validate().is_ok() {
            let (side, values, sample_um) =
                crate::core::display::aperture::display_preview(&design, DISPLAY_PREVIEW_SIDE);
            let payload = Payload::Display {
                side,
                values,
                sample_um,
                pupil_diameter_um: design.optics.pupil_diameter_um(),
            };
            if !send(payload) {
                return;
            }
        }
        // A preview that keeps the design's sampling is the full-quality computation: run it once.
        let qualities: &[Quality] = if Quality::Preview.doubles_spacing(&design) {
            &[Quality::Preview, Quality::Full]
        } else {
            &[Quality::Full]
        };
        for &quality in qualities {
            let options = AnalyzeOptions {
                quality,
                expected_psf: true,
            };
            let mut result = analyze_with_route(&design, &options, route.as_ref(), &progress);
            // Advice analyses candidates of its own: only for the result that stays on screen,
            // and after its numbers are on screen.
            let advise_after =
                quality == Quality::Full && result.as_ref().is_ok_and(|a| !a.warnings.is_empty());
            if advise_after
                && !send(Payload::Analysis {
                    quality,
                    advised: false,
                    result: result.clone(),
                    route: route.clone(),
                })
            {
                return;
            }
            if advise_after
                && let Ok(a) = &mut result
                && let Err(e) = advise(&design, &mut a.warnings, &progress)
            {
                result = Err(e);
            }
            let cancelled = matches!(result, Err(SimError::Cancelled));
            if !cancelled {
                let failed = result.is_err();
                let advised = quality == Quality::Full;
                if !send(Payload::Analysis {
                    quality,
                    advised,
                    result,
                    route: route.clone(),
                }) {
                    return;
                }
                if failed {
                    break;
                }
            } else {
                break;
            }
        }
        let mut s = lock.lock().unwrap_or_else(|e| e.into_inner());
        if s.running.as_ref().is_some_and(|(g, _)| *g == generation) {
            s.running = None;
        }
    }
}
