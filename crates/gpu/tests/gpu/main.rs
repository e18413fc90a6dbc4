//! The device backend against the CPU routes. The device tests run on whatever adapter the
//! machine has, a software one (lavapipe, which CI installs) included; where none exists they
//! say so and pass, because the CPU route is then the only one a user can reach.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod fraunhofer;
mod optimize;
mod phase;
mod tables;

use std::sync::Arc;

use udc_gpu::{AdapterKind, Gpu};

/// The shared device on any adapter, or `None` after printing why the test is skipped.
pub fn device(test: &str) -> Option<Arc<Gpu>> {
    match Gpu::shared(AdapterKind::Any) {
        Ok(gpu) => {
            eprintln!("{test}: on {}", gpu.adapter());
            Some(gpu)
        }
        Err(e) => {
            eprintln!("{test}: skipped, {e}");
            None
        }
    }
}

/// A device handed in (the studio's, on its window's adapter) becomes the process's shared one,
/// which every job resolving `--backend gpu` then uses; a software one is not taken for `auto`.
#[test]
fn a_device_handed_in_is_the_one_jobs_resolve() {
    let gpu = match Gpu::headless(AdapterKind::Any) {
        Ok(gpu) => Arc::new(gpu),
        Err(e) => {
            eprintln!("a_device_handed_in_is_the_one_jobs_resolve: skipped, {e}");
            return;
        }
    };
    // Each test runs in a process of its own under nextest; elsewhere another test may have
    // opened the shared device first, and then nothing can be said about this one.
    if !Gpu::share(&gpu) {
        eprintln!(
            "a_device_handed_in_is_the_one_jobs_resolve: skipped, a shared device was already open"
        );
        return;
    }
    let resolved = Gpu::shared(AdapterKind::Any).unwrap();
    assert!(
        Arc::ptr_eq(&resolved, &gpu),
        "gpu resolves on the device handed in"
    );
    let route = udc_gpu::Route::resolve(udc_core::psf::route::Backend::Gpu).unwrap();
    assert_eq!(route.adapter(), Some(gpu.adapter().to_string()));
    if gpu.adapter().software {
        let hardware = Gpu::shared(AdapterKind::Hardware);
        assert!(
            hardware.as_ref().map_or(true, |h| !Arc::ptr_eq(h, &gpu)),
            "a software device is not the hardware one"
        );
    }
    // Handed in once: a second device does not replace it.
    assert!(!Gpu::share(&Arc::new(
        Gpu::headless(AdapterKind::Any).unwrap()
    )));
    assert!(Arc::ptr_eq(&Gpu::shared(AdapterKind::Any).unwrap(), &gpu));
}
