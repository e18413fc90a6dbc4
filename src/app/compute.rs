//! Where the display workspace's PSFs are computed (View ▸ Compute PSFs on): the CPU, or the
//! GPU the window draws with (a device of its own on eframe's adapter, see `app::window_gpu`).
//! The simulation worker reads the current route at the start of each job.

use std::sync::{Arc, Mutex};

use crate::core::psf::route::Backend;
use udc_gpu::{Gpu, Route};

/// The window's GPU (if it draws with wgpu) and the route the worker uses.
pub struct Compute {
    gpu: Option<Arc<Gpu>>,
    route: Arc<Mutex<Arc<Route>>>,
    backend: Backend,
}

impl Compute {
    /// The route for `backend` on `gpu` (a device on the window's adapter, `None` where the window does not
    /// draw with wgpu or in tests without one).
    pub fn new(gpu: Option<Arc<Gpu>>, backend: Backend) -> Self {
        let mut compute = Compute {
            gpu,
            route: Arc::new(Mutex::new(Arc::new(Route::cpu()))),
            backend: Backend::Cpu,
        };
        compute.set(backend);
        compute
    }

    /// Switches the route: `gpu` and `auto` take the window's GPU when there is one (a
    /// software one only for `gpu`), the CPU otherwise.
    pub fn set(&mut self, backend: Backend) {
        self.backend = backend;
        let route = match (backend, &self.gpu) {
            (Backend::Gpu, Some(gpu)) => Route::device_or_cpu(gpu.clone()),
            (Backend::Auto, Some(gpu)) if !gpu.adapter().software => {
                Route::device_or_cpu(gpu.clone())
            }
            _ => Route::cpu(),
        };
        if let Ok(mut r) = self.route.lock() {
            *r = Arc::new(route);
        }
    }

    /// The backend asked for.
    pub fn backend(&self) -> Backend {
        self.backend
    }

    /// The backend the route resolved to: the one asked for where the window's GPU serves it,
    /// the CPU otherwise (`gpu` kept from a session whose window had one; `auto` on a software
    /// driver). What the jobs the studio runs by their `backend` parameter (a study, a quick
    /// reproduction) are given: they resolve it on the window's device (`app::window_gpu`).
    pub fn effective(&self) -> Backend {
        if self.current().adapter().is_some() {
            self.backend
        } else {
            Backend::Cpu
        }
    }

    /// The window's GPU, named with its API and driver, or `None` where the window does not
    /// draw with wgpu.
    pub fn adapter(&self) -> Option<String> {
        self.gpu.as_ref().map(|g| g.adapter().to_string())
    }

    /// The window's GPU's name alone (the menu's label; [`Compute::adapter`] is its hover).
    pub fn adapter_name(&self) -> Option<String> {
        self.gpu.as_ref().map(|g| g.adapter().name.clone())
    }

    /// The route in use now.
    pub fn current(&self) -> Arc<Route> {
        self.route
            .lock()
            .map(|r| r.clone())
            .unwrap_or_else(|_| Arc::new(Route::cpu()))
    }

    /// What the worker holds to read the route each job.
    pub fn shared(&self) -> Arc<Mutex<Arc<Route>>> {
        self.route.clone()
    }
}
