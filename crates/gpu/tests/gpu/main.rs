//! The device backend against the CPU routes. The device tests run on whatever adapter the
//! machine has, a software one (lavapipe, which CI installs) included; where none exists they
//! say so and pass, because the CPU route is then the only one a user can reach.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod fraunhofer;
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
