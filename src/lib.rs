#![warn(missing_docs)]
//! # UDC Studio
//!
//! A design studio for under-display cameras (UDC): draw a display pixel's opening, tile it, and
//! see what the camera behind the display sees. The workspace has one crate per layer, and this
//! one is the top:
//!
//! - [`core`] (`udc-core`): the pure simulation, with the conventions every number follows.
//! - [`io`] (`udc-io`): every file format (design files, images, reports, photolithography masks).
//! - [`jobs`] (`udc-jobs`): the typed jobs (`JobSpec`, `evaluate`) and the one sweep runner,
//!   shared by every front end.
//! - [`cli`] (`udc-cli`): the headless commands, built only on `core`, `io` and `jobs`.
//! - `app` (this crate, feature `gui`, on by default): the egui studio; the only code that
//!   touches egui.
//!
//! The lower crates are re-exported under their layer's name, so `udc_studio::core::analysis::analyze` and
//! `udc_core::analysis::analyze` are the same item.

#[cfg(feature = "gui")]
pub mod app;
pub use udc_cli as cli;
pub use udc_core as core;
pub use udc_io as io;
pub use udc_jobs as jobs;
