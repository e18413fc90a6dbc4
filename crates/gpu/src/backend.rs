//! The user's switch ([`Backend`]) resolved to a Fraunhofer step and a phase relay
//! ([`BlochRelay`]): the CPU routes, a device, or
//! (for `auto`) a hardware device that hands a transform it cannot hold back to the CPU. What
//! was decided, and why, is one line a front end prints ([`Route::note`]).

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use ndarray::Array2;
use rustfft::num_complex::Complex64;

use udc_core::SimError;
use udc_core::display::aperture::Field;
use udc_core::phase::chain::{
    BlochDirection, BlochIntensity, BlochRelay, BlochWavelength, CpuBloch,
};
use udc_core::progress::Progress;
use udc_core::psf::fft::Binned;
use udc_core::psf::route::{Backend, Fraunhofer, PsfRoute};
use udc_core::psf::sampling::Binning;
use udc_core::psf::spectra::{Pool, WindowDft};

use crate::device::{AdapterKind, Gpu, GpuError};

/// A resolved backend: it computes every PSF of a job and says where it ran.
#[derive(Debug)]
pub struct Route {
    device: Option<Arc<Gpu>>,
    /// `auto`: a transform the device refuses (too large, lost) runs on the CPU instead.
    falls_back: bool,
    /// Transforms (Fraunhofer steps, relay directions) the device completed: what the report
    /// gives as proof the device, not the CPU, computed them.
    on_device: AtomicUsize,
    note: Mutex<Option<String>>,
}

impl Route {
    /// The CPU routes.
    pub fn cpu() -> Route {
        Route {
            device: None,
            falls_back: false,
            note: Mutex::new(None),
            on_device: AtomicUsize::new(0),
        }
    }

    /// The kernels on `gpu` (the studio's device); errors are the job's.
    pub fn device(gpu: Arc<Gpu>) -> Route {
        Route {
            device: Some(gpu),
            falls_back: false,
            note: Mutex::new(None),
            on_device: AtomicUsize::new(0),
        }
    }

    /// The kernels on `gpu`, handing a transform the device refuses (a buffer larger than it
    /// binds, a lost device) to the CPU, with [`Route::note`] saying so: the studio's, whose
    /// device is the window's, opened with default limits.
    pub fn device_or_cpu(gpu: Arc<Gpu>) -> Route {
        Route {
            device: Some(gpu),
            falls_back: true,
            note: Mutex::new(None),
            on_device: AtomicUsize::new(0),
        }
    }

    /// `backend` on this process's shared headless device.
    ///
    /// # Errors
    /// [`Backend::Gpu`] on a machine with no adapter at all ([`GpuError`]); `auto` never fails.
    pub fn resolve(backend: Backend) -> Result<Route, GpuError> {
        Ok(match backend {
            Backend::Cpu => Route::cpu(),
            Backend::Gpu => Route::device(Gpu::shared(AdapterKind::Any)?),
            Backend::Auto => match Gpu::shared(AdapterKind::Hardware) {
                Ok(gpu) => Route::device_or_cpu(gpu),
                Err(e) => Route {
                    note: Mutex::new(Some(format!("backend auto: {e}; computing on the CPU"))),
                    ..Route::cpu()
                },
            },
        })
    }

    /// The adapter the transforms run on, or `None` on the CPU.
    pub fn adapter(&self) -> Option<String> {
        self.device.as_ref().map(|g| g.adapter().to_string())
    }

    /// Records why `auto` computed on the CPU (the first reason only).
    fn fell_back(&self, e: &SimError) {
        if let Ok(mut note) = self.note.lock() {
            note.get_or_insert_with(|| format!("backend auto: {e}; computing on the CPU"));
        }
    }

    /// How many transforms the device completed so far (0 on the CPU, or after a fallback).
    pub fn device_transforms(&self) -> usize {
        self.on_device.load(Ordering::Relaxed)
    }

    /// The one line a front end shows when `auto` did not use the device it hoped for (no
    /// hardware adapter, or a transform the device refused), else `None`.
    pub fn note(&self) -> Option<String> {
        self.note.lock().map(|n| n.clone()).unwrap_or_default()
    }
}

impl Route {
    /// `device` on the route's device, its `count` transforms counted; `cpu` where there is
    /// none, or, for `auto`, where the device refuses (too large, lost), the note saying why.
    fn compute<T>(
        &self,
        device: impl FnOnce(&Gpu) -> Result<T, SimError>,
        cpu: impl FnOnce() -> Result<T, SimError>,
        count: impl FnOnce(&T) -> usize,
    ) -> Result<T, SimError> {
        let Some(gpu) = &self.device else {
            return cpu();
        };
        match device(gpu) {
            Ok(out) => {
                self.on_device.fetch_add(count(&out), Ordering::Relaxed);
                Ok(out)
            }
            Err(e @ (SimError::TooLarge(_) | SimError::Device(_))) if self.falls_back => {
                self.fell_back(&e);
                cpu()
            }
            other => other,
        }
    }
}

impl Fraunhofer for Route {
    fn binned(
        &self,
        field: &Field,
        m: usize,
        binning: &Binning,
        progress: &Progress,
    ) -> Result<Binned, SimError> {
        self.compute(
            |gpu| gpu.binned(field, m, binning, progress),
            || PsfRoute::Auto.binned(field, m, binning, progress),
            |_| 1,
        )
    }

    fn binned_complex(
        &self,
        field: &Field<Complex64>,
        m: usize,
        binning: &Binning,
        progress: &Progress,
    ) -> Result<Binned, SimError> {
        self.compute(
            |gpu| gpu.binned_complex(field, m, binning, progress),
            || PsfRoute::Auto.binned_complex(field, m, binning, progress),
            |_| 1,
        )
    }

    fn full(&self, field: &Field, m: usize, progress: &Progress) -> Result<Array2<f64>, SimError> {
        self.compute(
            |gpu| gpu.full(field, m, progress),
            || PsfRoute::Auto.full(field, m, progress),
            |_| 1,
        )
    }

    fn window_spectrum(
        &self,
        dft: &WindowDft,
        field: &[f64],
        pool: &Pool,
    ) -> Result<Vec<Complex64>, SimError> {
        self.compute(
            |gpu| gpu.window_spectrum(dft, field, pool),
            || PsfRoute::Auto.window_spectrum(dft, field, pool),
            |_| 1,
        )
    }

    fn window_spectrum_adjoint(
        &self,
        dft: &WindowDft,
        g: &[Complex64],
        pool: &Pool,
    ) -> Result<Vec<f64>, SimError> {
        self.compute(
            |gpu| gpu.window_spectrum_adjoint(dft, g, pool),
            || PsfRoute::Auto.window_spectrum_adjoint(dft, g, pool),
            |_| 1,
        )
    }
}

impl BlochRelay for Route {
    fn directions(
        &self,
        wavelength: &BlochWavelength<'_>,
        count: usize,
        direction: &(dyn Fn(usize) -> BlochDirection + Sync),
        progress: &Progress,
    ) -> Result<Vec<BlochIntensity>, SimError> {
        self.compute(
            |gpu| gpu.directions(wavelength, count, direction, progress),
            || CpuBloch.directions(wavelength, count, direction, progress),
            Vec::len,
        )
    }
}
